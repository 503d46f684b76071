//! The clustering space, shared by palette choice and remapping: colours as
//! their 8-bit sRGB codes (as floats), compared by squared Euclidean distance.
//!
//! That distance is the 8-bit sRGB error by which docs/rendering.md measures every image,
//! so minimising it is minimising the metric (the module doc of
//! [`crate::quantize`] says why neither linear light nor OKLab is used).
//! [`Nearest`] answers "which palette colour is nearest" for every k-means
//! assignment and every remapped pixel, skipping the centres that the triangle
//! inequality rules out.

/// A colour in the clustering space (8-bit sRGB codes as floats).
pub(super) type Point = [f32; 3];

pub(super) fn point(c: [u8; 3]) -> Point {
    c.map(|v| v as f32)
}

#[inline]
pub(super) fn dist2(a: Point, b: Point) -> f32 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Nearest-centre search that skips centres the triangle inequality rules out:
/// if d(c, j) >= 2 d(p, c) for the best centre c so far, j cannot be nearer.
pub(super) struct Nearest {
    centres: Vec<Point>,
    /// Squared distances between centres, divided by 4.
    quarter: Vec<f32>,
}

impl Nearest {
    pub(super) fn new(centres: &[Point]) -> Nearest {
        let k = centres.len();
        let mut quarter = vec![0f32; k * k];
        for i in 0..k {
            for j in 0..k {
                quarter[i * k + j] = dist2(centres[i], centres[j]) / 4.0;
            }
        }
        Nearest {
            centres: centres.to_vec(),
            quarter,
        }
    }

    /// The nearest centre to `p` and its squared distance; `hint` is a good
    /// first guess (the previous answer for this or a neighbouring point).
    /// Ties go to the lower index, so the answer does not depend on the hint.
    #[inline]
    pub(super) fn find(&self, p: Point, hint: usize) -> (usize, f32) {
        let k = self.centres.len();
        let mut best = hint.min(k - 1);
        let mut bd = dist2(p, self.centres[best]);
        for j in 0..k {
            if j == best || self.quarter[best * k + j] > bd {
                continue;
            }
            let d = dist2(p, self.centres[j]);
            if d < bd || (d == bd && j < best) {
                best = j;
                bd = d;
            }
        }
        (best, bd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::test_data::lcg;

    #[test]
    fn nearest_search_agrees_with_brute_force() {
        let mut seed = 7;
        let centres: Vec<Point> = (0..40)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed) as f32))
            .collect();
        let nearest = Nearest::new(&centres);
        for i in 0..2000 {
            let p = [0; 3].map(|_: u8| lcg(&mut seed) as f32);
            let want = (0..centres.len())
                .min_by(|&a, &b| dist2(p, centres[a]).total_cmp(&dist2(p, centres[b])))
                .unwrap();
            let got = nearest.find(p, i % centres.len());
            assert_eq!(got.1, dist2(p, centres[want]));
        }
    }
}
