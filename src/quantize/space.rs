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

/// Lanes of [`Channels`]' searches: eight f32, two SSE registers.
const LANES: usize = 8;

/// The centres as three channel arrays, padded to whole [`LANES`], for a
/// brute-force search in SIMD: k-means' full searches need the two nearest
/// (for Hamerly's bounds), which the triangle-inequality skipping of
/// [`Nearest`] cannot give; the rounded-palette Lloyd steps and the
/// undithered remap use it too. Every distance is computed, and each lane
/// keeps its least distance, that centre's index and its second least, with
/// no branch that depends on the data.
pub(super) struct Channels {
    c: [Vec<f32>; 3],
}

/// What each lane of a [`Channels`] scan kept.
#[derive(Debug, PartialEq)]
struct Lanes {
    least: [f32; LANES],
    /// The index of `least` (the first, on ties), as f32: exact far beyond
    /// 256 centres, and kept by the same masked select as the value.
    at: [f32; LANES],
    /// The least of the lane's other distances.
    second: [f32; LANES],
}

impl Channels {
    pub(super) fn new(centres: &[Point]) -> Channels {
        let padded = centres.len().div_ceil(LANES) * LANES;
        // Padding centres lie infinitely far away, so they are never nearest.
        let channel = |ch: usize| {
            let mut v: Vec<f32> = centres.iter().map(|p| p[ch]).collect();
            v.resize(padded, f32::INFINITY);
            v
        };
        Channels {
            c: [channel(0), channel(1), channel(2)],
        }
    }

    /// The nearest centre to `p` and its squared distance. Ties go to the
    /// lower index, as in [`Nearest::find`].
    #[inline]
    pub(super) fn nearest(&self, p: Point) -> (usize, f32) {
        let lanes = self.scan(p);
        let (_, at, best) = best_lane(&lanes);
        (at, best)
    }

    /// The nearest centre to `p`, its squared distance and the squared
    /// distance to the nearest other centre (infinite for one centre). Ties go
    /// to the lower index, as in [`Nearest::find`].
    #[inline]
    pub(super) fn two_nearest(&self, p: Point) -> (usize, f32, f32) {
        let lanes = self.scan(p);
        let (lane, at, best) = best_lane(&lanes);
        let second = (0..LANES).fold(lanes.second[lane], |m, l| {
            let v = if l == lane {
                f32::INFINITY
            } else {
                lanes.least[l]
            };
            if v < m {
                v
            } else {
                m
            }
        });
        (at, best, second)
    }

    #[cfg(target_arch = "x86_64")]
    #[inline]
    fn scan(&self, p: Point) -> Lanes {
        // SAFETY: SSE2 is part of the x86-64 baseline: every CPU this target
        // runs on has it.
        unsafe { scan_sse2(&self.c, p) }
    }

    #[cfg(not(target_arch = "x86_64"))]
    #[inline]
    fn scan(&self, p: Point) -> Lanes {
        self.scan_portable(p)
    }

    /// The portable form of `scan_sse2`, lane for lane (the test
    /// `the_simd_scan_is_the_portable_one_lane_for_lane` holds them equal).
    #[cfg(any(test, not(target_arch = "x86_64")))]
    fn scan_portable(&self, p: Point) -> Lanes {
        let [xs, ys, zs] = &self.c;
        let mut out = Lanes {
            least: [f32::INFINITY; LANES],
            at: [0.0; LANES],
            second: [f32::INFINITY; LANES],
        };
        for j in 0..xs.len() {
            let l = j % LANES;
            let (dx, dy, dz) = (p[0] - xs[j], p[1] - ys[j], p[2] - zs[j]);
            let d = dx * dx + dy * dy + dz * dz;
            let high = if d < out.least[l] { out.least[l] } else { d };
            out.second[l] = if high < out.second[l] {
                high
            } else {
                out.second[l]
            };
            if d < out.least[l] {
                out.least[l] = d;
                out.at[l] = j as f32;
            }
        }
        out
    }
}

/// Written with SSE2 intrinsics: the compiler's own vectorisation of the
/// portable loop packed its compare masks to bytes and back; this took the
/// 1024x1024 Earth photo at K = 256 from 0.43 to 0.33 s whole process. The
/// distance is summed in the order of [`dist2`], so it is the same number to
/// the bit.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
fn scan_sse2(c: &[Vec<f32>; 3], p: Point) -> Lanes {
    use std::arch::x86_64::*;
    let [xs, ys, zs] = c;
    let n = xs.len();
    assert!(n % LANES == 0 && ys.len() == n && zs.len() == n);
    // SAFETY: `j + 4 <= n` for every `j` below (`n` is a multiple of LANES).
    let load = |v: &[f32], j: usize| unsafe { _mm_loadu_ps(v.as_ptr().add(j)) };
    let (px, py, pz) = (_mm_set1_ps(p[0]), _mm_set1_ps(p[1]), _mm_set1_ps(p[2]));
    let mut least = [_mm_set1_ps(f32::INFINITY); 2];
    let mut second = least;
    let mut at = [_mm_setzero_ps(); 2];
    let mut index = [
        _mm_setr_ps(0.0, 1.0, 2.0, 3.0),
        _mm_setr_ps(4.0, 5.0, 6.0, 7.0),
    ];
    let step = _mm_set1_ps(LANES as f32);
    for j in (0..n).step_by(LANES) {
        for h in 0..2 {
            let dx = _mm_sub_ps(px, load(xs, j + 4 * h));
            let dy = _mm_sub_ps(py, load(ys, j + 4 * h));
            let dz = _mm_sub_ps(pz, load(zs, j + 4 * h));
            let d = _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)),
                _mm_mul_ps(dz, dz),
            );
            // Strictly less: each lane keeps its first least index.
            let less = _mm_cmplt_ps(d, least[h]);
            second[h] = _mm_min_ps(second[h], _mm_max_ps(d, least[h]));
            least[h] = _mm_min_ps(d, least[h]);
            at[h] = _mm_or_ps(_mm_and_ps(less, index[h]), _mm_andnot_ps(less, at[h]));
            index[h] = _mm_add_ps(index[h], step);
        }
    }
    let lanes = |v: [__m128; 2]| -> [f32; LANES] {
        let mut out = [0.0; LANES];
        for h in 0..2 {
            out[4 * h] = _mm_cvtss_f32(v[h]);
            out[4 * h + 1] = _mm_cvtss_f32(_mm_shuffle_ps::<0b01>(v[h], v[h]));
            out[4 * h + 2] = _mm_cvtss_f32(_mm_shuffle_ps::<0b10>(v[h], v[h]));
            out[4 * h + 3] = _mm_cvtss_f32(_mm_shuffle_ps::<0b11>(v[h], v[h]));
        }
        out
    };
    Lanes {
        least: lanes(least),
        at: lanes(at),
        second: lanes(second),
    }
}

/// The lane holding the least distance (ties to the lower index), that
/// index and the distance.
#[inline]
fn best_lane(lanes: &Lanes) -> (usize, usize, f32) {
    (0..LANES).fold((0, usize::MAX, f32::INFINITY), |(bl, ba, bm), l| {
        let (v, a) = (lanes.least[l], lanes.at[l] as usize);
        if v < bm || (v == bm && a < ba) {
            (l, a, v)
        } else {
            (bl, ba, bm)
        }
    })
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

    #[test]
    fn the_simd_scan_is_the_portable_one_lane_for_lane() {
        let mut seed = 21;
        let centres: Vec<Point> = (0..29)
            .map(|_| [0; 3].map(|_: u8| (lcg(&mut seed) / 4) as f32))
            .collect();
        let channels = Channels::new(&centres);
        for _ in 0..500 {
            let p = [0; 3].map(|_: u8| lcg(&mut seed) as f32 + 0.25);
            assert_eq!(channels.scan(p), channels.scan_portable(p));
        }
    }

    #[test]
    fn the_two_nearest_agree_with_a_sort() {
        let mut seed = 9;
        // Repeated centres make ties, which must go to the lower index.
        let mut centres: Vec<Point> = (0..37)
            .map(|_| [0; 3].map(|_: u8| (lcg(&mut seed) / 8) as f32))
            .collect();
        centres.extend_from_within(..5);
        let channels = Channels::new(&centres);
        for _ in 0..2000 {
            let p = [0; 3].map(|_: u8| (lcg(&mut seed) / 8) as f32);
            let mut by: Vec<(f32, usize)> = centres.iter().map(|&c| dist2(p, c)).zip(0..).collect();
            by.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            assert_eq!(channels.two_nearest(p), (by[0].1, by[0].0, by[1].0));
        }
        assert_eq!(
            Channels::new(&[[1.0, 2.0, 3.0]]).two_nearest([0.0; 3]),
            (0, 14.0, f32::INFINITY)
        );
    }
}
