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

/// Sine and cosine of `degrees`, for the angles users give in degrees
/// (placement `rotate`, transforms, camera twist, stripe directions, arcs).
///
/// The angle is reduced exactly, as `sind` and `cosd` do in Julia and
/// MATLAB: first to [-180, 180] (Rust's `%`, C's `fmod`, is exact, and
/// adding or taking 360 from a remainder beyond ±180 is exact by Sterbenz's
/// lemma), then to `a` in [-45, 45] about the nearest multiple of 90
/// (`r - 90q`, exact the same way), and the sine and cosine of `a`'s radians
/// are swapped and negated into place. So:
/// - a turn more or less gives the same bits (`rotate` 450 is `rotate` 90;
///   1e20° was the sine of a radian count whose every digit was rounding);
/// - at the multiples of 90° the values are exactly 0 and ±1 (the cosine of
///   π/2 rounded is 6.1e-17, which left a point turned onto an axis that
///   fraction of its distance off it: polyfill3 printed
///   `2.220446049250313e-16` where `0.0` belonged);
/// - near them the small value keeps its relative accuracy (the sine of
///   179.99999° from its radians was 5 million ulps off, the rounding of
///   π/180 magnified): against mpmath's 50-digit values, 365,688 angles
///   (uniform in ±720, and from 1 down to 10^-13 beside each multiple of
///   90 in ±720) were all within 1.54 ulps; the test
///   `degrees_are_exact_at_quarter_turns_and_periodic_to_the_bit` keeps
///   nine of those values.
///
/// Zeros are +0. Within ±45° the bits are [`sin_cos`] of the radians, as
/// before. NaN and infinities give NaN.
pub fn sin_cos_degrees(degrees: f64) -> (f64, f64) {
    let r = reduce_degrees(degrees);
    // Quadrant q in -2..=2 (ties at ±45 and ±135 go away from zero).
    let q = (r / 90.0).round();
    let (s, c) = sin_cos((r - 90.0 * q).to_radians());
    // `+ 0.0` turns a -0 into +0 and changes nothing else.
    let (s, c) = match q as i32 {
        0 => (s, c),
        1 => (c, -s),
        -1 => (-c, s),
        _ => (-s, -c),
    };
    (s + 0.0, c + 0.0)
}

/// The angle in (-180, 180] a whole number of turns from `degrees`,
/// exactly (see [`sin_cos_degrees`]): the same bits for every angle a
/// representable number of turns apart. NaN for NaN and infinities.
pub fn reduce_degrees(degrees: f64) -> f64 {
    let r = degrees % 360.0;
    if r > 180.0 {
        r - 360.0
    } else if r <= -180.0 {
        r + 360.0
    } else {
        r
    }
}

/// Tangent of `degrees` within (-90, 90), as for a field of view's half
/// angle (`fovy` is checked to lie in (0, 180), so nothing is reduced):
/// exact (0, ±1) at 0 and ±45° (`fovy` 90 made `tan(π/4 rounded)` =
/// 0.9999999999999999 and cot 1.0000000000000002, a frustum an ulp narrower
/// than asked); [`tan`] of the radians elsewhere.
pub fn tan_degrees(degrees: f64) -> f64 {
    match degrees {
        0.0 => 0.0,
        45.0 => 1.0,
        -45.0 => -1.0,
        _ => tan(degrees.to_radians()),
    }
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

    /// `(a * v + b * u) / (u + v)` for weights `u, v > 0`, to within an
    /// ulp of the result however much the numerator cancels: the point at
    /// distance `u` from `a` and `v` from `b` on a line, as the view
    /// clipper's crossings need it when the edge is more than 2^40 times
    /// longer than the view is wide (`view::clip`), where `a + (b - a) t` in
    /// double-double errs by about the edge's length times 2^-102.
    ///
    /// The ends are scaled by one power of two and the weights by another,
    /// exactly, so that the larger of each is in [1/2, 1) (the mean is
    /// unchanged by scaling both weights, and scales with the ends). Then
    /// the numerator's four products are exact (two `f64`s each), their sum
    /// exact (Shewchuk's grow-expansion, 1997), rounded to a double-double
    /// and divided by `u + v`: about 2^-100 relative, so the `f64` returned
    /// is the nearest or next to nearest. What the scaling can lose is a
    /// part of a product below the normal range: at most about 2^-1070 of
    /// the larger end. Tested against exact rationals with every operand
    /// anywhere from 2^-1000 to 2^1000 (`any_weights_and_ends`) and on ends
    /// built to cancel (`cancelling_ends`). NaN if an operand is not finite.
    pub fn weighted_mean(a: f64, u: Self, b: f64, v: Self) -> f64 {
        let operands = [a, b, u.hi, u.lo, v.hi, v.lo];
        if !operands.iter().all(|x| x.is_finite()) {
            return f64::NAN;
        }
        let ends = a.abs().max(b.abs());
        if ends == 0.0 {
            return 0.0;
        }
        let (_, ke) = libm::frexp(ends);
        let (_, kw) = libm::frexp(u.hi.abs().max(v.hi.abs()));
        let weight = |d: Self| DoubleDouble {
            hi: libm::scalbn(d.hi, -kw),
            lo: libm::scalbn(d.lo, -kw),
        };
        let mean = Self::mean_of_scaled(
            libm::scalbn(a, -ke),
            weight(u),
            libm::scalbn(b, -ke),
            weight(v),
        );
        libm::scalbn(mean, ke)
    }

    /// [`Self::weighted_mean`] of ends and weights of at most 1 in size.
    fn mean_of_scaled(a: f64, u: Self, b: f64, v: Self) -> f64 {
        // The exact numerator as a nonoverlapping expansion, smallest first.
        let mut expansion = [0.0f64; 8];
        let mut len = 0;
        for (x, w) in [(a, v.hi), (a, v.lo), (b, u.hi), (b, u.lo)] {
            let p = Self::product(x, w);
            for term in [p.lo, p.hi] {
                let mut q = term;
                let mut kept = 0;
                for i in 0..len {
                    let s = Self::sum(q, expansion[i]);
                    q = s.hi;
                    if s.lo != 0.0 {
                        expansion[kept] = s.lo;
                        kept += 1;
                    }
                }
                if q != 0.0 {
                    expansion[kept] = q;
                    kept += 1;
                }
                len = kept;
            }
        }
        let numerator = expansion[..len]
            .iter()
            .fold(Self::from(0.0), |s, &c| s + Self::from(c));
        (numerator / (u + v)).hi
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

    /// `Dd::weighted_mean` against exact rationals: within one ulp of the
    /// true mean, on numerators that cancel up to the whole f64 range.
    mod weighted_mean {
        use super::super::DoubleDouble as Dd;
        use num_bigint::BigInt;
        use num_rational::BigRational;
        use proptest::prelude::*;

        fn exact(x: f64) -> BigRational {
            BigRational::from_float(x).unwrap()
        }

        /// Whether `got` is within one ulp of `(a v + b u) / (u + v)`, and
        /// 2^-1060 of the larger end (what the scaling may lose below the
        /// normal range).
        fn within_an_ulp(a: f64, u: Dd, b: f64, v: Dd, got: f64) -> Result<(), String> {
            let (u_, v_) = (exact(u.hi) + exact(u.lo), exact(v.hi) + exact(v.lo));
            let want = (exact(a) * &v_ + exact(b) * &u_) / (&u_ + &v_);
            let ulp = exact(got.abs().max(f64::MIN_POSITIVE))
                / BigRational::from_integer(BigInt::from(1u64 << 52))
                + exact(a.abs().max(b.abs())) * exact(libm::scalbn(1.0, -1060));
            let err = exact(got) - &want;
            let err = if err < BigRational::from_integer(BigInt::from(0)) {
                -err
            } else {
                err
            };
            match err <= ulp {
                true => Ok(()),
                false => Err(format!("{a} {u:?} {b} {v:?}: got {got}, want {want}")),
            }
        }

        fn weight(hi: f64, lo_fraction: f64) -> Dd {
            Dd::sum(hi, hi * lo_fraction * f64::EPSILON / 2.0)
        }

        #[test]
        fn an_edge_of_1e34_crosses_the_plane_on_it() {
            // An edge as long as those that drew a third of a 4-pixel view
            // (README, Limits) crossing the plane x <= 1: its values there
            // are u = 1 - xa > 0 inside, 1 - xb < 0 outside (v = xb - 1).
            let (xa, xb) = (-7.071067811865476e33, 9.192388155425118e33);
            let (u, v) = (Dd::sum(1.0, -xa), Dd::sum(xb, -1.0));
            assert_eq!(Dd::weighted_mean(xa, u, xb, v), 1.0);
            let (ya, yb) = (7.071067811865476e33, -3.0e33);
            within_an_ulp(ya, u, yb, v, Dd::weighted_mean(ya, u, yb, v)).unwrap();
        }

        /// Found by review (2026-11-28) in a first version, which scaled
        /// ends and weights together by 2^-600 when one passed 2^500: a
        /// weight below 2^-474 vanished (NaN, or the crossing on an end),
        /// and an infinite operand recursed until the stack overflowed.
        #[test]
        fn weights_far_smaller_than_the_ends_and_infinities() {
            let d = Dd::from;
            assert_eq!(Dd::weighted_mean(1e200, d(1e-160), -1e200, d(1e-160)), 0.0);
            assert_eq!(Dd::weighted_mean(1e-300, d(1.0), 1e-300, d(1e301)), 1e-300);
            let (a, u, b, v) = (1e300, d(1e-300), -1e300, d(2e-300));
            within_an_ulp(a, u, b, v, Dd::weighted_mean(a, u, b, v)).unwrap();
            assert!(Dd::weighted_mean(1.0, d(f64::INFINITY), 2.0, d(1.0)).is_nan());
            assert!(Dd::weighted_mean(f64::INFINITY, d(1.0), 2.0, d(1.0)).is_nan());
            assert!(Dd::weighted_mean(f64::NAN, d(1.0), 2.0, d(1.0)).is_nan());
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(20_000))]
            #[test]
            fn any_weights_and_ends(
                (am, bm) in (-2.0f64..2.0, -2.0f64..2.0),
                (ae, be, ue, ve) in (-1000i32..1000, -1000i32..1000, -1000i32..1000, -1000i32..1000),
                (um, vm, ul, vl) in (1.0f64..2.0, 1.0f64..2.0, -1.0f64..1.0, -1.0f64..1.0),
            ) {
                let (a, b) = (am * 2f64.powi(ae), bm * 2f64.powi(be));
                let u = weight(um * 2f64.powi(ue), ul);
                let v = weight(vm * 2f64.powi(ve), vl);
                within_an_ulp(a, u, b, v, Dd::weighted_mean(a, u, b, v))
                    .map_err(TestCaseError::fail)?;
            }

            /// The mean near `p` from ends up to 2^1000 times farther
            /// away: `b` made from `a` so that the numerator cancels.
            #[test]
            fn cancelling_ends(
                p in -4.0f64..4.0, far in 1.0f64..1000.0, sign in prop::bool::ANY,
                (um, vm, ul, vl) in (1.0f64..2.0, 1.0f64..2.0, -1.0f64..1.0, -1.0f64..1.0),
                (ue, ve) in (-20i32..3, -20i32..3),
            ) {
                let a = if sign { 2f64.powf(far) } else { -(2f64.powf(far)) } * um;
                let u = weight(vm * 2f64.powi(ue) * a.abs(), ul);
                let v = weight(um * 2f64.powi(ve) * a.abs(), vl);
                // b with a v + b u = p (u + v), rounded.
                let ratio = v.hi / u.hi;
                let b = p * (1.0 + ratio) - a * ratio;
                prop_assume!(b.is_finite() && u.hi.is_finite() && v.hi.is_finite());
                within_an_ulp(a, u, b, v, Dd::weighted_mean(a, u, b, v))
                    .map_err(TestCaseError::fail)?;
            }
        }
    }

    #[test]
    fn degrees_are_exact_at_quarter_turns_and_periodic_to_the_bit() {
        for k in -12i32..=12 {
            let d = 90.0 * k as f64;
            let want = [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][k.rem_euclid(4) as usize];
            let got = sin_cos_degrees(d);
            assert_eq!(got, want, "{d}");
            assert!(got.0.is_sign_positive() || got.0 != 0.0, "{d}: +0");
            assert!(got.1.is_sign_positive() || got.1 != 0.0, "{d}: +0");
        }
        // 2^60 = 360·3202559735019019 + 136.
        assert_eq!(sin_cos_degrees(2f64.powi(60)), sin_cos_degrees(136.0));
        assert_eq!(sin_cos_degrees(1e20), sin_cos_degrees(280.0));
        assert!(sin_cos_degrees(f64::INFINITY).0.is_nan());
        assert!(sin_cos_degrees(f64::NAN).1.is_nan());
        // The true values, correctly rounded (mpmath, 50 digits): the
        // computed ones are within 1.6 ulps of them (the largest error of
        // 365,688 angles measured so, 1.54 ulps, at 615.5226944566381°),
        // also near the zeros, where the sine of 179.99999° from its
        // radians was 5 million ulps off.
        let ulps = |got: f64, want: f64| ((got - want) / (want.abs() * f64::EPSILON)).abs();
        for (x, s, c) in [
            (179.99999, 1.745329252548312e-07, -0.9999999999999848),
            (179.9999999999991, 1.5873677075381507e-14, -1.0),
            (90.0000001, 1.0, -1.7453291483773152e-09),
            (89.9999999999, 1.0, 1.7453603996790573e-12),
            (30.0, 0.5, 0.8660254037844386),
            (60.0, 0.8660254037844386, 0.5),
            (
                -150.38316114462992,
                -0.49419738412949415,
                -0.8693497256683096,
            ),
            (615.5226944566381, -0.9682467381938535, -0.2499965079295372),
            (1e20, -0.984807753012208, 0.17364817766693036),
        ] {
            let (gs, gc) = sin_cos_degrees(x);
            assert!(ulps(gs, s) <= 1.6 && ulps(gc, c) <= 1.6, "{x}: {gs} {gc}");
        }
        // The reduction is exact: what it takes off comes back to the bit;
        // a turn more or less gives the same bits; the sine is odd and the
        // cosine even; within ±45° the bits are sin_cos of the radians.
        let mut x = 0.123_f64;
        while x < 720.0 {
            let mut r = x % 360.0;
            if r > 180.0 {
                assert_eq!(DoubleDouble::sum(r, -360.0).lo, 0.0, "{x}");
                r -= 360.0;
            }
            let q = (r / 90.0).round();
            assert_eq!(DoubleDouble::sum(r, -90.0 * q).lo, 0.0, "{x}");
            let (s, c) = sin_cos_degrees(x);
            assert_eq!(sin_cos_degrees(-x), (-s, c), "{x}");
            for turns in [-3.0, -1.0, 1.0, 2.0, 1000.0] {
                let y = x + 360.0 * turns;
                if y - 360.0 * turns == x {
                    assert_eq!(sin_cos_degrees(y), (s, c), "{x} + {turns} turns");
                }
            }
            if x <= 45.0 {
                assert_eq!((s, c), sin_cos(x.to_radians()), "{x}");
            }
            x += 0.731;
        }
        assert_eq!(tan_degrees(45.0), 1.0);
        assert_eq!(tan_degrees(-45.0), -1.0);
        assert_eq!(tan_degrees(0.0), 0.0);
        assert_eq!(tan_degrees(30.0), tan(30f64.to_radians()));
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
