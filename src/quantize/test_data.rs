//! Test data shared by the unit tests of the quantizer's files.

use super::resample::SquareImage;
use super::space::{dist2, Point};

/// A deterministic pseudo-random sequence for test data (64-bit LCG, Knuth's MMIX constants).
pub(super) fn lcg(seed: &mut u64) -> u8 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 56) as u8
}

/// A `size` x `size` image whose pixel (x, y), row 0 at the top, is `f(x, y)`.
pub(super) fn square(size: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> SquareImage {
    let mut pixels = Vec::new();
    for y in 0..size {
        for x in 0..size {
            pixels.push(f(x, y));
        }
    }
    SquareImage { size, pixels }
}

/// The weighted squared error of `points` each at its nearest of `centres`
/// (computed in f64, independently of the searches under test).
pub(super) fn weighted_error(points: &[(Point, f64)], centres: &[Point]) -> f64 {
    points
        .iter()
        .map(|&(p, w)| {
            w * centres
                .iter()
                .map(|&c| dist2(p, c) as f64)
                .fold(f64::INFINITY, f64::min)
        })
        .sum()
}
