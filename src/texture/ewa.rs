//! The elliptical weighted average (Heckbert, "Fundamentals of Texture
//! Mapping and Image Warping", 1989, §3.5.8; Greene & Heckbert 1986): an
//! anisotropic filter whose footprint is the pixel's ellipse in texel space.
//!
//! The pixel filter is a Gaussian of standard deviation [`PIXEL_SIGMA`]
//! pixels; mapped through the Jacobian `J` it has covariance
//! `PIXEL_SIGMA² J Jᵀ` in texels. Heckbert adds the reconstruction filter
//! (here a Gaussian of [`TEXEL_SIGMA`] texels), which keeps the ellipse at
//! least one texel wide under magnification and along a thin footprint's
//! minor axis. Texels whose centres lie within [`CUTOFF`] standard
//! deviations (Mahalanobis distance) are weighted by the Gaussian and the sum
//! normalized.
//!
//! Bounded cost: the ellipse is made no more elongated than
//! [`MAX_ANISOTROPY`], and when its major radius would cover more than
//! [`MAX_RADIUS`] texels the average is taken on the first MIP level where it
//! covers no more, so at most about `(2 MAX_RADIUS + 3)²` texels are read.

use super::map::Footprint;
use super::PolyTexture;
use crate::math;

/// The pixel's Gaussian, in pixels. 0.5 makes the weight fall to e^-2 at one
/// pixel from the centre: roughly the span of the box filter's unit square,
/// slightly softer (the box's own standard deviation is 0.29).
pub const PIXEL_SIGMA: f64 = 0.5;

/// The reconstruction Gaussian, in texels of the level sampled.
pub const TEXEL_SIGMA: f64 = 0.5;

/// Texels beyond this many standard deviations are left out: the Gaussian
/// there is e^-4.5 = 1.1% of its peak.
pub const CUTOFF: f64 = 3.0;

/// The most elongated ellipse averaged: ratio of the major to the minor axis
/// (16, as GPUs' 16x anisotropic filtering). Beyond it the minor axis is
/// widened, blurring along it rather than reading ever more texels.
pub const MAX_ANISOTROPY: f64 = 16.0;

/// The largest major radius (at [`CUTOFF`]) averaged on one level, in texels
/// of that level; beyond it a coarser MIP level is used.
pub const MAX_RADIUS: f64 = 8.0;

/// The EWA's premultiplied RGBA at the footprint.
pub fn sample(t: &PolyTexture, fp: &Footprint) -> [f64; 4] {
    // Covariance of the pixel's Gaussian in base texels, s2 J Jᵀ, with the
    // LOD bias scaling the footprint by 2^bias per axis (like a change of
    // level): s2 = (PIXEL_SIGMA 2^bias)².
    let s2 = (PIXEL_SIGMA * math::exp2(t.filters.lod_bias)).powi(2);
    let (dx, dy) = tamed(fp.dx, fp.dy);
    let (mut a, b, mut c) = (
        s2 * (dx.x * dx.x + dy.x * dy.x),
        s2 * (dx.x * dx.y + dy.x * dy.y),
        s2 * (dx.y * dx.y + dy.y * dy.y),
    );
    // Eigenvalues; widen the minor axis to the anisotropy limit by adding
    // d I, which raises both so that (l1 + d) / (l2 + d) = MAX_ANISOTROPY².
    let half_tr = 0.5 * (a + c);
    let disc = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (mut l1, l2) = (half_tr + disc, (half_tr - disc).max(0.0));
    let m2 = MAX_ANISOTROPY * MAX_ANISOTROPY;
    if l1 > m2 * l2 {
        let d = (l1 - m2 * l2) / (m2 - 1.0);
        a += d;
        c += d;
        l1 += d;
    }
    // The level: the first whose texels keep the major radius within bounds.
    // log2 of the side, rounded down: the number of levels below the base.
    // (Of the longer side, for an image: each axis has its own scale, and
    // the smaller one bounds the radius in texels of the level.)
    let levels = (u32::BITS - 1 - t.base_side().leading_zeros()) as usize;
    let major = CUTOFF * l1.sqrt();
    let min_scale = |k| {
        let (sx, sy) = t.level_scale(k);
        sx.min(sy)
    };
    let mut k = 0;
    while k < levels && major / min_scale(k) > MAX_RADIUS {
        k += 1;
    }
    let (sx, sy) = t.level_scale(k);
    let sc = sx.min(sy);
    // Past the coarsest level (a pixel over more than the whole pattern
    // many times, towards a horizon) the ellipse is shrunk to MAX_RADIUS
    // texels of that level, bounding the work; it then already spans the
    // whole level several times over.
    // The covariance in texels of the level: u scaled by 1 / sx, v by 1 / sy.
    let (mut fa, mut fb, mut fc) = (1.0 / (sx * sx), 1.0 / (sx * sy), 1.0 / (sy * sy));
    let r = major / sc;
    if r > MAX_RADIUS {
        let g = (MAX_RADIUS / r) * (MAX_RADIUS / r);
        fa *= g;
        fb *= g;
        fc *= g;
    }
    let tt = TEXEL_SIGMA * TEXEL_SIGMA;
    let (a, b, c) = (a * fa + tt, b * fb, c * fc + tt);
    let det = a * c - b * b;
    // Inverse covariance for the Mahalanobis distance.
    let (ia, ib, ic) = (c / det, -b / det, a / det);
    let (ru, rv) = (CUTOFF * a.sqrt(), CUTOFF * c.sqrt());
    // Far out (a coordinate of 1e30), moved by whole periods so that the
    // texel indices below are exact.
    let (u, v) = t.near_period(k, fp.uv.x / sx, fp.uv.y / sy, ru.max(rv) + 1.0);
    let mut acc = [0.0f64; 4];
    let mut wsum = 0.0;
    for j in (v - rv - 0.5).floor() as i64..=(v + rv - 0.5).ceil() as i64 {
        let dv = j as f64 + 0.5 - v;
        for i in (u - ru - 0.5).floor() as i64..=(u + ru - 0.5).ceil() as i64 {
            let du = i as f64 + 0.5 - u;
            let q = ia * du * du + 2.0 * ib * du * dv + ic * dv * dv;
            if q > CUTOFF * CUTOFF {
                continue;
            }
            let w = math::exp(-0.5 * q);
            let p = t.fetch(k, i, j);
            for ch in 0..4 {
                acc[ch] += w * p[ch];
            }
            wsum += w;
        }
    }
    // The centre texel always lies within the cutoff (q <= 0.5 / TEXEL_SIGMA² = 2 < 9 at
    // half a texel), so wsum > 0. Should rounding ever leave no weight, the
    // texel under the centre stands in: a defined colour, never 0 / 0.
    if wsum > 0.0 && wsum.is_finite() {
        acc.map(|x| x / wsum)
    } else {
        t.fetch(k, u.floor() as i64, v.floor() as i64)
    }
}

/// Jacobian columns above this magnitude (2^300) are scaled down by a power
/// of two before their squares are taken, which would otherwise overflow to
/// infinity (a quadric's `"repeat"` of 1e308).
const TAME_ABOVE: f64 = f64::from_bits((1023 + 300) << 52);

/// `(dx, dy)` scaled by one power of two so that their largest component is
/// at most [`TAME_ABOVE`], or as given. Such a footprint is far past the
/// coarsest level, where [`sample`] shrinks the ellipse to [`MAX_RADIUS`]:
/// only its shape counts, which an exact power-of-two scale keeps.
fn tamed(dx: glam::DVec2, dy: glam::DVec2) -> (glam::DVec2, glam::DVec2) {
    let m = dx.abs().max_element().max(dy.abs().max_element());
    if m <= TAME_ABOVE || !m.is_finite() {
        return (dx, dy);
    }
    let e = (math::log2(m / TAME_ABOVE)).ceil() as i32 + 1;
    // 2^-e, exactly.
    let f = f64::from_bits(((1023 - e) as u64) << 52);
    (dx * f, dy * f)
}

#[cfg(test)]
mod tests {
    use super::super::boundary::{Boundary, Bounds};
    use super::super::filter::tests::{pattern, placed};
    use super::super::filter::{Eval, Filter};
    use super::*;
    use crate::color::Rgb8;

    /// The exact box filter of a head-on, axis-aligned pixel covering
    /// `n x n` whole texels: the mean of their linear colours.
    fn box_mean(t: &PolyTexture, x: u32, y: u32, n: u32) -> f64 {
        let mut s = 0.0;
        for j in y * n..(y + 1) * n {
            for i in x * n..(x + 1) * n {
                s += t.texels.texel(i as i64, j as i64, [0.0; 3]).unwrap()[0];
            }
        }
        s / (n * n) as f64
    }

    /// EWA against the box on an axis-aligned footprint: a Gaussian is not a
    /// box, so they agree only on slowly varying content. A sine of period 32
    /// texels seen at 4 texels per pixel is attenuated by 0.97 by the box and
    /// ~0.92 by the Gaussian: with amplitude 0.5 that is a difference of 0.03
    /// at most; [`EWA_BOX_TOL`] allows it with margin.
    const EWA_BOX_TOL: f64 = 0.05;

    #[test]
    fn ewa_on_an_axis_aligned_footprint_approximates_the_box() {
        // A grey ramp in 16 levels following a sine along u, period 32... on
        // a 32 pattern (sizes are multiples of 16).
        let greys: Vec<Rgb8> = (0..16).map(|i| Rgb8([(i * 17) as u8; 3])).collect();
        let p = pattern(32, &greys, |c, _| {
            let s = math::sin(std::f64::consts::TAU * (c as f64 + 0.5) / 32.0);
            ((s * 0.5 + 0.5) * 15.0).round() as u16
        });
        let t = placed(p, 4.0, Filter::Ewa, 0.0);
        for x in 0..8 {
            let Eval::Color(Some(c)) = t.eval(x as f64 + 0.5, 3.5) else {
                panic!()
            };
            let b = box_mean(&t, x, 3, 4);
            assert!(
                (c[0] - b).abs() < EWA_BOX_TOL,
                "pixel {x}: ewa {} box {b}",
                c[0]
            );
        }
    }

    #[test]
    fn ewa_is_anisotropic_along_a_thin_footprint() {
        // Stripes along u (bands of 4 rows, black and white). A footprint
        // long in u (8 texels) and short in v (1 texel) resolves the
        // stripes; an isotropic filter of the same rho (level 3, whose
        // texels span 8 rows) averages them to grey.
        let p = pattern(16, &[Rgb8::BLACK, Rgb8::WHITE], |_, r| (r / 4 % 2) as u16);
        let mut t = placed(p, 1.0, Filter::Ewa, 0.0);
        t.map.u = [8.0, 0.0, 0.0];
        t.map.v = [0.0, 1.0, 0.0];
        let Eval::Color(Some(white)) = t.eval(0.5, 6.0) else {
            panic!()
        };
        // v = 6: row 6 is in the white band 4..8 (centre).
        assert!(white[0] > 0.9, "{white:?}");
        t.filters.min = Filter::Trilinear;
        let Eval::Color(Some(grey)) = t.eval(0.5, 6.0) else {
            panic!()
        };
        assert!((grey[0] - 0.5).abs() < 0.1, "{grey:?}");
    }

    /// Texture coordinates of 1e30 (a triangle's uv, a quadric's
    /// `"repeat"`): the EWA used to read one saturated texel index, outside
    /// its own ellipse, and divide by a zero weight, and the renderers
    /// panicked on the transparent colour. A position whole periods away
    /// from another gives the very same colour, under every condition that
    /// wraps, and the conditions that leave the pattern still do.
    #[test]
    fn ewa_far_from_the_origin_is_the_colour_a_whole_period_away() {
        use crate::texture::map::Footprint;
        use glam::DVec2;
        let p = pattern(16, &[Rgb8::BLACK, Rgb8::WHITE], |c, r| {
            ((c * 7 + r * 3) % 5 < 2) as u16
        });
        let mut t = placed(p, 1.0, Filter::Ewa, 0.0);
        let fp = |x: f64, y: f64, scale: f64| Footprint {
            uv: DVec2::new(x, y),
            dx: DVec2::new(scale, 0.3 * scale),
            dy: DVec2::new(-0.2 * scale, scale),
        };
        for bounds in [Boundary::Repeat, Boundary::Mirror] {
            t.bounds = Bounds::both(bounds);
            for scale in [0.7, 3.0, 40.0] {
                let near = sample(&t, &fp(0.0, 5.0, scale));
                // Multiples of 32: whole periods of both conditions.
                for far in [2f64.powi(62), 2f64.powi(70), 1e30, -1e30, 1e300] {
                    let got = sample(&t, &fp(far, 5.0, scale));
                    assert_eq!(got, near, "{bounds:?} at {far} scale {scale}");
                }
            }
        }
        // Far out under clamp: the constant colour.
        t.bounds = Bounds::both(Boundary::Clamp);
        t.constant = [1.0, 0.0, 0.0];
        let c = sample(&t, &fp(1e30, 5.0, 2.0));
        assert!(
            (c[0] - 1.0).abs() < 1e-12 && c[1] == 0.0 && c[3] == 1.0,
            "{c:?}"
        );
        // A Jacobian whose squares overflow (1e300 texels a pixel): the
        // pattern's mean, a defined colour.
        t.bounds = Bounds::both(Boundary::Repeat);
        let c = sample(&t, &fp(1e30, 1e30, 1e300));
        assert!(c.iter().all(|x| x.is_finite()) && c[3] == 1.0, "{c:?}");
        let mean = sample(&t, &fp(0.5, 0.5, 1e12));
        assert!((c[0] - mean[0]).abs() < 1e-6, "{c:?} vs {mean:?}");
    }

    #[test]
    fn a_footprint_far_larger_than_the_pattern_is_bounded() {
        // 1e12 texels per pixel (a horizon): the coarsest level, a bounded
        // ellipse; under clamp the constant dominates, under repeat the
        // pattern's mean.
        let p = pattern(16, &[Rgb8::BLACK, Rgb8::WHITE], |c, r| ((c + r) % 2) as u16);
        let mut t = placed(p, 1e12, Filter::Ewa, 0.0);
        let Eval::Color(Some(c)) = t.eval(0.5, 0.5) else {
            panic!()
        };
        assert!((c[0] - 0.5).abs() < 1e-6, "{c:?}");
        t.bounds = Bounds::both(Boundary::Clamp);
        t.constant = [1.0, 0.0, 0.0];
        let Eval::Color(Some(c)) = t.eval(0.5, 0.5) else {
            panic!()
        };
        assert!(c[0] > 0.9 && c[1] < 0.1, "{c:?}");
    }
}
