//! Test data shared by the unit tests of the quantizer's files.

use super::resample::SquareImage;

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
