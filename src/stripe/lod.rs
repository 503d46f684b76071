//! Level of detail (seed 001, "Texture Blending" and Fig. 7): which levels of
//! the modulation map's pyramid a pixel reads, and how much of each.
//!
//! The seed takes `ΔP_max`, the larger of the screen-space changes of `P` per
//! pixel, as a floating-point number `2^e × 1.xxxx...` and reads off
//! `LOD = 10 + e` (Fig. 7: 2^0 → LOD 10, 2^−10 → LOD 0, for 1024-entry maps)
//! and the four bits after the leading one as the blend factor `a` in sixteenths:
//! `m = a M_L + (1 − a) M`, `M` the modulation at LOD and `M_L` at the next,
//! coarser, LOD. The seed's LOD number is this module's level `k` (level `k` has
//! `N / 2^k` entries), and its 10 is `log2 N`.
//!
//! Modes:
//!
//! * [`LodMode::Blend`] (default): the continuous version. The rate `ρ` is the
//!   number of level-0 samples per pixel, `N |∇P|` (the gradient's length: a
//!   box of that width has the same second moment as the trapezoid that a
//!   pixel square projects to in `P`, so it is the box that best stands for the
//!   pixel); `λ = log2 ρ +` [`LOD_BIAS`], `k = floor λ`, `a = λ − k` with no
//!   rounding.
//! * [`LodMode::Nearest`]: one level, `k = round(λ)` (same `λ`): the baseline.
//! * [`LodMode::Cig`] (`--cig-compat`): the seed's rule exactly: `ΔP_max =
//!   max(|∂P/∂x|, |∂P/∂y|)`, integer exponent, 4-bit `a`. Since
//!   `log2(1 + f) ≈ f`, its `e + a` is a piecewise-linear log2, coarser than
//!   `λ` by up to 0.086 levels.
//!
//! Below level 0 (magnification) the finest level is used alone, crisp;
//! beyond the last level (one entry) the last level is used alone.
//!
//! Within a level, the blend and nearest modes interpolate linearly between
//! the two entries whose centres bracket `P` (the 1-D "bilinear" of a
//! mip-map), so the filter is centred on the pixel instead of on the aligned
//! block of `2^k` samples that happens to contain `P`; on a receding ground
//! plane of random stripes (the test in `stripe/tests.rs`, before
//! [`LOD_BIAS`]) it cut the RMSE against the box-filtered reference from 10.8
//! to 7.5 (nearest level) and from 9.6 to 6.8 (blended levels); with the bias
//! they are 7.3 and 6.4, and the seed's rule 9.9. The cig mode keeps the seed's single table
//! reference per level ("requiring only one memory reference per sample
//! point").

use crate::math;

/// How a pixel's levels are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum LodMode {
    /// The nearest level only.
    Nearest,
    /// Continuous LOD, blended linearly between the two nearest levels.
    #[default]
    Blend,
    /// The Compuscene III rule: ΔP_max, integer exponent, 4-bit blend factor.
    #[cfg_attr(feature = "cli", value(name = "cig"))]
    Cig,
}

/// The levels a pixel reads: `m = (1 − a) level[k] + a level[k + 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lod {
    /// The finer level read, `k` (level `k` has `N / 2^k` entries; 0 is the
    /// full map).
    pub level: usize,
    /// Weight of level `level + 1`, in `[0, 1)`; 0 when only `level` is read.
    pub a: f32,
    /// Interpolate linearly between the two entries nearest to `P` within a
    /// level (minified pixels in the blend and nearest modes), rather than
    /// reading the one entry that covers `P` (the seed's single memory
    /// reference, and magnified pixels, where the crisp map is exact).
    pub linear: bool,
}

impl Lod {
    const CRISP: Lod = Lod {
        level: 0,
        a: 0.0,
        linear: false,
    };
}

/// Added to `λ` in the blend and nearest modes. With linear interpolation
/// within a level, level `k` acts as a filter of standard deviation `2^k / 2`
/// (box of `2^k` samples convolved with a tent of half-width `2^k`), against
/// `ρ / √12` for the pixel's own footprint; matching the two would give a bias
/// of `−log2 √3 = −0.79`, but that blurs the bars of `runway.map` visibly.
/// Measured RMSE against the box reference (`examples/stripe_shade.rs`,
/// ground and wall at 1024x768, runway.map; and the random-strip ground plane
/// of `stripe/tests.rs`) is lowest near −0.25 on both scenes and both faces
/// (runway, all pixels: bias 0 → 6.31, −0.25 → 4.88, −0.5 → 5.75, −0.79 → 7.48).
pub const LOD_BIAS: f64 = -0.25;

/// The seed's blend factor resolution: 4 bits.
pub const CIG_BLEND_STEPS: f64 = 16.0;

impl LodMode {
    /// The LOD for screen-space derivatives `(px, py)` of `P` (map periods per
    /// pixel) on a map of `n` entries with `levels = log2 n + 1` levels.
    #[inline]
    pub fn select(self, px: f64, py: f64, n: usize, levels: usize) -> Lod {
        let last = levels - 1;
        let n = n as f64;
        match self {
            LodMode::Blend | LodMode::Nearest => {
                // log2 of the rate ρ = N |∇P|, as half the log2 of ρ² (no hypot:
                // its overflow care costs more than the whole lookup).
                let lambda = 0.5 * math::log2(n * n * (px * px + py * py)) + LOD_BIAS;
                if lambda.is_nan() || lambda <= 0.0 {
                    // Magnified, exactly one sample per pixel, or no gradient.
                    return Lod::CRISP;
                }
                let single = |level: usize| Lod {
                    level,
                    a: 0.0,
                    linear: true,
                };
                if self == LodMode::Nearest {
                    return single((lambda.round() as usize).min(last));
                }
                if lambda >= last as f64 {
                    return single(last);
                }
                let k = super::floor_i64(lambda) as f64;
                Lod {
                    level: k as usize,
                    a: (lambda - k) as f32,
                    linear: true,
                }
            }
            LodMode::Cig => {
                let single = |level: usize| Lod {
                    level,
                    a: 0.0,
                    linear: false,
                };
                let dp = px.abs().max(py.abs()) * n;
                if dp.is_nan() || dp < 1.0 {
                    return single(0);
                }
                if !dp.is_finite() {
                    return single(last);
                }
                // dp = 2^e × (1 + f): the exponent and the top four fraction bits.
                let bits = dp.to_bits();
                let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
                let xxxx = (bits >> 48) & 0xf;
                if e >= last as i64 {
                    return single(last);
                }
                Lod {
                    level: e as usize,
                    a: (xxxx as f64 / CIG_BLEND_STEPS) as f32,
                    linear: false,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = 1024;
    const LEVELS: usize = 11;

    /// `λ` of a rate, as the blend mode computes it.
    fn lambda(rate: f64) -> f64 {
        math::log2(rate) + LOD_BIAS
    }

    fn level_and_a(l: Lod) -> f64 {
        l.level as f64 + l.a as f64
    }

    #[test]
    fn blend_is_log2_of_samples_per_pixel() {
        let s = 1.0 / N as f64;
        assert_eq!(LodMode::Blend.select(0.5 * s, 0.0, N, LEVELS), Lod::CRISP);
        // Rate 2^(2 - LOD_BIAS): exactly level 2.
        let l = LodMode::Blend.select(math::powf(2f64, 2.0 - LOD_BIAS) * s, 0.0, N, LEVELS);
        assert!(l.linear && (level_and_a(l) - 2.0).abs() < 1e-6, "{l:?}");
        let l = LodMode::Blend.select(0.0, 6.0 * s, N, LEVELS);
        assert!((level_and_a(l) - lambda(6.0)).abs() < 1e-6, "{l:?}");
        // The gradient's length: 3-4-5.
        let l = LodMode::Blend.select(3.0 * s, 4.0 * s, N, LEVELS);
        assert!((level_and_a(l) - lambda(5.0)).abs() < 1e-6, "{l:?}");
        assert_eq!(
            LodMode::Blend.select(3.0, 0.0, N, LEVELS),
            Lod {
                level: 10,
                a: 0.0,
                linear: true
            }
        );
        assert_eq!(LodMode::Blend.select(f64::NAN, 0.0, N, LEVELS).level, 0);
    }

    #[test]
    fn nearest_rounds_the_level() {
        let s = 1.0 / N as f64;
        assert_eq!(
            LodMode::Nearest.select(5.0 * s, 0.0, N, LEVELS).level,
            lambda(5.0).round() as usize
        );
        assert_eq!(LodMode::Nearest.select(7.0 * s, 0.0, N, LEVELS).level, 3);
        assert_eq!(LodMode::Nearest.select(1e9, 0.0, N, LEVELS).level, 10);
    }

    #[test]
    fn cig_follows_figure_7() {
        // ΔP_max = 2^0 → LOD 10; 2^-10 → LOD 0; 2^-3 × 1.1010b → LOD 7, a = 10/16.
        assert_eq!(
            LodMode::Cig.select(1.0, 0.5, N, LEVELS),
            Lod {
                level: 10,
                a: 0.0,
                linear: false
            }
        );
        assert_eq!(
            LodMode::Cig.select(1.0 / 1024.0, 0.0, N, LEVELS),
            Lod {
                level: 0,
                a: 0.0,
                linear: false
            }
        );
        let dp = (1.0 + 10.0 / 16.0 + 1.0 / 64.0) / 8.0;
        assert_eq!(
            LodMode::Cig.select(0.0, -dp, N, LEVELS),
            Lod {
                level: 7,
                a: 10.0 / 16.0,
                linear: false,
            }
        );
        // ΔP_max is the larger component, not the gradient's length.
        assert_eq!(
            LodMode::Cig
                .select(3.0 / 1024.0, 3.0 / 1024.0, N, LEVELS)
                .level,
            1
        );
        assert_eq!(LodMode::Cig.select(f64::INFINITY, 0.0, N, LEVELS).level, 10);
    }

    #[test]
    fn cig_is_within_a_tenth_of_a_level_of_blend() {
        // Along one axis both measure the same rate; the piecewise-linear log2
        // stays within 0.0861 of the true one (max of log2(1+f) − f), plus the
        // 4-bit truncation of 1/16.
        let mut r = 1.2; // above 2^-LOD_BIAS, where blend starts minifying
        while r < 1024.0 {
            let b = LodMode::Blend.select(r / 1024.0, 0.0, N, LEVELS);
            let c = LodMode::Cig.select(r / 1024.0, 0.0, N, LEVELS);
            let lb = b.level as f64 + b.a as f64 - LOD_BIAS;
            let lc = c.level as f64 + c.a as f64;
            assert!(
                (lb - lc) >= -1e-6 && lb - lc <= 0.0861 + 1.0 / 16.0,
                "{r}: {lb} {lc}"
            );
            r *= 1.037;
        }
    }
}
