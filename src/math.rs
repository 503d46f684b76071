//! Transcendental functions that give the same bits on every host.
//!
//! `f64::sin`, `powf`, `exp` and the rest call the platform's C library
//! (glibc, musl, macOS's libm), whose results differ in the last bit from
//! one to another and from one version to the next; a frame rendered on two
//! hosts of a render farm could then differ. These are the `libm` crate's
//! (a Rust port of musl's libm): the same code, so the same bits, on every
//! host. Every value that reaches a pixel or an output number goes through
//! them; `clippy.toml` forbids the `f64` methods, and the test
//! `binaries_import_no_maths_from_the_c_library` (`tests/cli/host.rs`) checks
//! that the tools import none of them.
//!
//! `sqrt`, `mul_add`, `floor` and the like are left to `f64`: IEEE 754
//! specifies them exactly, so every host agrees.

/// Sine of `x` radians.
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// Cosine of `x` radians.
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// Sine and cosine of `x` radians, computed together.
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// Tangent of `x` radians.
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// Arc sine, in radians.
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// Arc cosine, in radians.
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// The angle of the point (`x`, `y`), in radians: `y.atan2(x)`.
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `sqrt(x² + y²)` without undue overflow or underflow.
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// `x` to the power `y`.
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// `e^x`.
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// `2^x`.
pub fn exp2(x: f64) -> f64 {
    libm::exp2(x)
}

/// Base-2 logarithm.
pub fn log2(x: f64) -> f64 {
    libm::log2(x)
}

/// Base-10 logarithm.
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

/// Cube root.
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// Neumaier's compensated sum: the rounding error of every addition is
/// carried and added back, so the result is within about one rounding of the
/// true sum however many terms there are (while n·ε ≪ 1), where a plain sum
/// of a million terms drifts by a thousand roundings. Not exact: the tests
/// and benchmarks that compare areas with it allow 1e-12.
pub fn sum_compensated(terms: impl IntoIterator<Item = f64>) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0f64);
    for x in terms {
        let t = s + x;
        c += if s.abs() >= x.abs() {
            (s - t) + x
        } else {
            (x - t) + s
        };
        s = t;
    }
    s + c
}

/// A double-double number `hi + lo` (`hi` the nearest `f64` to the sum):
/// about 106 bits, for the few computations whose inputs are exact `f64`s
/// but whose result cancels most of them. The view clipper's crossings are
/// one: an edge from -3e16 to 3e16 crosses the plane x = -1 at
/// t = 0.5 - 1.6e-17, which rounds to 0.5 in `f64` and puts the crossing at
/// 0, half a frame away (issue 17, item 6). Algorithms of Dekker (1971)
/// and Knuth (TAOCP 4.2.2), as in Hida, Li and Bailey's QD library; the
/// products use a fused multiply-add (`libm::fma`, correctly rounded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleDouble {
    /// The sum rounded to `f64`.
    pub hi: f64,
    /// What `hi` leaves out: `|lo| <= ulp(hi) / 2`.
    pub lo: f64,
}

impl DoubleDouble {
    /// `a + b` exactly (Knuth's two-sum; any magnitudes).
    pub fn sum(a: f64, b: f64) -> Self {
        let s = a + b;
        let bb = s - a;
        let lo = (a - (s - bb)) + (b - bb);
        DoubleDouble { hi: s, lo }
    }

    /// `a * b` exactly (while it neither overflows nor underflows).
    pub fn product(a: f64, b: f64) -> Self {
        let p = a * b;
        DoubleDouble {
            hi: p,
            lo: libm::fma(a, b, -p),
        }
    }

    /// `hi + lo` normalised, for `|hi| >= |lo|` (Dekker's fast two-sum).
    fn fast(hi: f64, lo: f64) -> Self {
        let s = hi + lo;
        DoubleDouble {
            hi: s,
            lo: lo - (s - hi),
        }
    }
}

impl std::ops::Add for DoubleDouble {
    type Output = Self;
    /// The sum, to about 106 bits.
    fn add(self, o: Self) -> Self {
        let s = Self::sum(self.hi, o.hi);
        let t = Self::sum(self.lo, o.lo);
        let s = Self::fast(s.hi, s.lo + t.hi);
        Self::fast(s.hi, s.lo + t.lo)
    }
}

impl std::ops::Neg for DoubleDouble {
    type Output = Self;
    fn neg(self) -> Self {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl std::ops::Sub for DoubleDouble {
    type Output = Self;
    /// The difference, to about 106 bits.
    fn sub(self, o: Self) -> Self {
        self + -o
    }
}

impl std::ops::Mul for DoubleDouble {
    type Output = Self;
    /// The product, to about 104 bits.
    fn mul(self, o: Self) -> Self {
        let p = Self::product(self.hi, o.hi);
        Self::fast(p.hi, p.lo + (self.hi * o.lo + self.lo * o.hi))
    }
}

impl std::ops::Div for DoubleDouble {
    type Output = Self;
    /// The quotient, to about 104 bits (two correction steps).
    fn div(self, o: Self) -> Self {
        let q1 = self.hi / o.hi;
        let r = self - o * DoubleDouble::from(q1);
        let q2 = r.hi / o.hi;
        let r = r - o * DoubleDouble::from(q2);
        let q3 = r.hi / o.hi;
        Self::fast(q1, q2) + DoubleDouble::from(q3)
    }
}

impl From<f64> for DoubleDouble {
    fn from(x: f64) -> Self {
        DoubleDouble { hi: x, lo: 0.0 }
    }
}

#[cfg(test)]
#[allow(clippy::disallowed_methods)] // compared with the platform's functions
mod tests {
    use super::*;

    #[test]
    fn double_double_keeps_what_f64_cancels() {
        type Dd = DoubleDouble;
        // Exact sums and products, by their definition.
        let s = Dd::sum(1e16, 1.0);
        assert_eq!((s.hi, s.lo), (1e16, 1.0));
        let p = Dd::product(1.0 + f64::EPSILON, 1.0 + f64::EPSILON);
        assert_eq!(
            (p.hi, p.lo),
            (1.0 + 2.0 * f64::EPSILON, f64::EPSILON * f64::EPSILON)
        );
        // (3e16 + 1) / 6e16 carried through: 6e16 * t - 3e16 = 1, where f64
        // gives t = 0.5 and 0.
        let t = Dd::sum(3e16, 1.0) / Dd::from(6e16);
        let back = Dd::from(6e16) * t - Dd::from(3e16);
        assert!((back.hi - 1.0).abs() < 1e-12, "{back:?}");
        // Against exact rationals: 1/3 to about 1e-32.
        let third = Dd::from(1.0) / Dd::from(3.0);
        let err = third * Dd::from(3.0) - Dd::from(1.0);
        assert!(err.hi.abs() < 1e-31, "{err:?}");
    }

    #[test]
    fn the_functions_are_the_usual_ones() {
        // Within an ulp or two of the platform's: the same functions, only
        // the last bit may differ (which is the point).
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0);
        for x in [-3.0, -0.5, 0.0, 0.25, 1.0, 2.5, 100.0] {
            assert!(close(sin(x), x.sin()) && close(cos(x), x.cos()), "{x}");
            assert_eq!(sin_cos(x), (sin(x), cos(x)));
            assert!(close(atan2(x, 1.5), x.atan2(1.5)), "{x}");
            assert!(
                close(exp2(x), x.exp2()) && close(exp(x / 10.0), (x / 10.0).exp()),
                "{x}"
            );
            assert!(close(hypot(x, 3.0), x.hypot(3.0)), "{x}");
            assert!(close(cbrt(x), x.cbrt()), "{x}");
        }
        for x in [0.01, 0.5, 1.0, 7.0, 1e6] {
            assert!(
                close(powf(x, 2.4), x.powf(2.4)) && close(log2(x), x.log2()),
                "{x}"
            );
            assert!(close(log10(x), x.log10()), "{x}");
        }
        assert!(close(acos(0.3), 0.3f64.acos()) && close(asin(0.3), 0.3f64.asin()));
        assert!(close(tan(0.7), 0.7f64.tan()));
    }
}
