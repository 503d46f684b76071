//! How good a pattern is: PSNR over 8-bit sRGB codes (docs/rendering.md), against the
//! resampled image and over the coloured texels only. This is the error that
//! the palette choice minimises (see the clustering space in
//! [`crate::quantize`]).

use super::resample::SquareImage;
use crate::math;
use crate::pat::Pattern;

/// Peak value of an 8-bit channel, for PSNR.
const PEAK: f64 = 255.0;

/// PSNR in dB of the pattern against the square image it came from, over the
/// RGB of texels that are coloured in the pattern (docs/rendering.md: 8-bit sRGB).
/// `None` if no texel is coloured; infinite for an exact match.
pub fn psnr(pattern: &Pattern, img: &SquareImage) -> Option<f64> {
    let n = img.size;
    let mut sum = 0f64;
    let mut count = 0u64;
    for row in 0..n {
        for col in 0..n {
            if let Some(c) = pattern.color_at(col, n - 1 - row) {
                let p = img.pixels[(row * n + col) as usize];
                for (&a, &b) in c.0.iter().zip(&p) {
                    sum += (a as f64 - b as f64).powi(2);
                }
                count += 3;
            }
        }
    }
    (count > 0).then(|| {
        let mse = sum / count as f64;
        10.0 * math::log10(PEAK * PEAK / mse)
    })
}
