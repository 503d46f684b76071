//! Directions and lengths of 3D vectors whatever their magnitude: the
//! plain `v / |v|` squares the components, which overflows past about
//! 1e154 and underflows below about 1e-154, so that a rotation axis, light
//! direction or view-plane normal of `[1e200, 0, 0]` had "no direction" (a
//! hostile-input review). Ordinary vectors keep the plain formulas' bits.
//! Below every stage that takes a direction from its input (`geom`,
//! `light`, `camera`).

use glam::DVec3;

/// Whether `v`'s squared length is a normal finite number, so that
/// `v.length()` and `v / v.length()` lose nothing: false for components
/// near 1e155 and above (the square overflows to infinity) or near 1e-154
/// and below (it underflows to zero or loses digits).
pub fn plain_length_is_exact(v: DVec3) -> bool {
    let sq = v.length_squared();
    sq.is_finite() && sq >= f64::MIN_POSITIVE
}

/// `v` divided by its largest |component| when its squared length would
/// overflow or underflow (see [`direction`]), else `v` itself: the same
/// direction, with lengths that square safely. Zero and non-finite vectors
/// are returned as they are.
pub fn tame(v: DVec3) -> DVec3 {
    if plain_length_is_exact(v) || !v.is_finite() {
        return v;
    }
    let m = v.abs().max_element();
    if m > 0.0 {
        v / m
    } else {
        v
    }
}

/// `|v|` without overflow or underflow in the square: `v.length()` when that
/// is exact, bit for bit, else the largest |component| times the length of
/// `v` divided by it (`[1e200, 0, 0]` is 1e200 long, not infinitely;
/// `[1e-200, 0, 0]` 1e-200, not 0). Infinite only when |v| is past
/// `f64::MAX`; NaN for a NaN component.
pub fn length(v: DVec3) -> f64 {
    if plain_length_is_exact(v) || !v.is_finite() {
        return v.length();
    }
    let m = v.abs().max_element();
    if m > 0.0 {
        m * (v / m).length()
    } else {
        0.0
    }
}

/// `v` scaled to length 1, or None for the zero vector and non-finite ones:
/// `v / v.length()`, bit for bit, when the squared length is a normal
/// finite number. Otherwise `v` is first divided by its largest |component|:
/// the square of `[1e200, 0, 0]` overflows (its length was infinite, so it
/// had "no direction") and that of `[1e-200, 0, 0]` underflows to 0.
pub fn direction(v: DVec3) -> Option<DVec3> {
    to_unit(v, |w| w / w.length())
}

/// [`direction`] by glam's `normalize()` (`v` times the reciprocal of its
/// length, which rounds differently from dividing by it): for the code that
/// normalized that way, whose ordinary vectors must keep their bits (the
/// camera's axes: dividing moved a PFM of `bench/same_images.sh` by 7e-15).
pub fn normalized(v: DVec3) -> Option<DVec3> {
    to_unit(v, DVec3::normalize)
}

/// `unit(v)`, or `unit` of `v` [`tame`]d when its squared length would
/// overflow or underflow; None for the zero vector and non-finite ones.
fn to_unit(v: DVec3, unit: impl Fn(DVec3) -> DVec3) -> Option<DVec3> {
    if !v.is_finite() {
        return None;
    }
    if plain_length_is_exact(v) {
        return Some(unit(v));
    }
    let w = tame(v);
    (w != DVec3::ZERO).then(|| unit(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_and_length_survive_huge_and_tiny_components() {
        // Ordinary vectors: the plain formulas, bit for bit.
        for v in [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-0.3, 1e-5, 7e10),
            DVec3::new(1e150, -1e150, 3.0),
            DVec3::new(1e-150, 0.0, 0.0),
        ] {
            assert_eq!(
                direction(v).unwrap().to_array(),
                (v / v.length()).to_array()
            );
            assert_eq!(length(v).to_bits(), v.length().to_bits());
            assert_eq!(tame(v), v);
            // glam's normalize() multiplies by the reciprocal, kept by
            // `normalized`.
            assert_eq!(normalized(v).unwrap().to_array(), v.normalize().to_array());
        }
        // ... which rounds otherwise than dividing, for some vectors.
        assert!((1..100).any(|i| {
            let v = DVec3::new(i as f64, 0.7, 0.1);
            direction(v) != normalized(v)
        }));
        let huge = normalized(DVec3::splat(1e300)).unwrap();
        assert!((huge - DVec3::splat(1.0 / 3f64.sqrt())).length() < 1e-15);
        let s = 1.0 / 3f64.sqrt();
        for (v, unit, len) in [
            (DVec3::new(1e200, 0.0, 0.0), DVec3::X, 1e200),
            (DVec3::new(0.0, -1e300, 0.0), DVec3::NEG_Y, 1e300),
            (DVec3::splat(1e300), DVec3::splat(s), 1e300 * 3f64.sqrt()),
            (DVec3::new(0.0, 0.0, 1e-200), DVec3::Z, 1e-200),
            (
                DVec3::splat(-1e-200),
                DVec3::splat(-s),
                1e-200 * 3f64.sqrt(),
            ),
            (DVec3::new(f64::MAX, 0.0, 0.0), DVec3::X, f64::MAX),
            (DVec3::new(5e-324, 0.0, 0.0), DVec3::X, 5e-324),
        ] {
            let d = direction(v).unwrap();
            assert!((d - unit).length() < 1e-15, "{v}: {d}");
            assert!((length(v) / len - 1.0).abs() < 1e-15, "{v}: {}", length(v));
        }
        assert_eq!(length(DVec3::splat(f64::MAX)), f64::INFINITY);
        for v in [
            DVec3::ZERO,
            DVec3::new(f64::NAN, 1.0, 0.0),
            DVec3::new(f64::INFINITY, 0.0, 0.0),
        ] {
            assert_eq!(direction(v), None, "{v}");
        }
    }
}
