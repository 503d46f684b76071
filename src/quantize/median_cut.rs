//! The first palette: median cut in Wu's greedy form. Every box knows the cut
//! (axis and place, not necessarily the median) that lowers its squared error
//! most, and the box split next is the one whose cut gains most.
//!
//! A box's error comes from its [`Moments`] (weight, sums, sums of squares), so
//! the error on either side of every candidate cut is a subtraction; and since
//! the clustering space is integer-valued, the candidates along an axis are
//! found from per-level sums (a counting sort) instead of a sort. Ties are
//! broken by index: the same histogram always gives the same boxes. The
//! moments and the cut also serve k-means' split moves.

use super::space::Point;

/// Running weighted sums of a set of points.
#[derive(Clone, Copy, Default)]
pub(super) struct Moments {
    pub(super) w: f64,
    pub(super) s: [f64; 3],
    pub(super) ss: f64,
}

impl Moments {
    pub(super) fn add(&mut self, p: Point, w: f64) {
        self.w += w;
        for (s, &v) in self.s.iter_mut().zip(&p) {
            *s += v as f64 * w;
            self.ss += (v as f64).powi(2) * w;
        }
    }
    pub(super) fn add_moments(&mut self, o: &Moments) {
        self.w += o.w;
        self.ss += o.ss;
        for c in 0..3 {
            self.s[c] += o.s[c];
        }
    }
    fn sub(&self, o: &Moments) -> Moments {
        Moments {
            w: self.w - o.w,
            s: [self.s[0] - o.s[0], self.s[1] - o.s[1], self.s[2] - o.s[2]],
            ss: self.ss - o.ss,
        }
    }
    /// Weighted sum of squared distances to the mean.
    pub(super) fn sse(&self) -> f64 {
        if self.w <= 0.0 {
            return 0.0;
        }
        (self.ss - self.s.iter().map(|s| s * s).sum::<f64>() / self.w).max(0.0)
    }
    pub(super) fn mean(&self) -> Point {
        self.s.map(|s| (s / self.w) as f32)
    }
}

pub(super) fn moments_of(s: &[(Point, f64)]) -> Moments {
    let mut m = Moments::default();
    for &(p, w) in s {
        m.add(p, w);
    }
    m
}

/// Levels of an 8-bit channel: the clustering space is integer-valued, so a
/// cut is found from per-level sums (counting sort) instead of a sort.
const LEVELS: usize = 256;

/// The cut of `points` (whose moments are `total`) that lowers the squared
/// error most: `(gain, axis, threshold)`, the left part being the points with
/// `p[axis] < threshold`. `None` if every point has the same colour.
pub(super) fn best_cut(points: &[(Point, f64)], total: &Moments) -> Option<(f64, usize, f32)> {
    let mut best: Option<(f64, usize, f32)> = None;
    let mut bins = vec![Moments::default(); LEVELS];
    for axis in 0..3 {
        bins.iter_mut().for_each(|b| *b = Moments::default());
        for &(p, w) in points {
            bins[p[axis] as usize].add(p, w);
        }
        let mut left = Moments::default();
        let mut seen_any = false;
        for (level, bin) in bins.iter().enumerate() {
            if bin.w == 0.0 {
                continue;
            }
            // A cut just below this level, if anything lies below it.
            if seen_any {
                let gain = total.sse() - left.sse() - total.sub(&left).sse();
                if best.is_none_or(|b| gain > b.0) {
                    best = Some((gain, axis, level as f32));
                }
            }
            left.add_moments(bin);
            seen_any = true;
        }
    }
    best
}

/// Splits `points` in place at a cut from [`best_cut`]: the left part first,
/// each part keeping its order. Returns the size of the left part.
pub(super) fn apply_cut(points: &mut [(Point, f64)], axis: usize, threshold: f32) -> usize {
    let (left, right): (Vec<_>, Vec<_>) = points.iter().partition(|(p, _)| p[axis] < threshold);
    let n = left.len();
    points[..n].copy_from_slice(&left);
    points[n..].copy_from_slice(&right);
    n
}

/// A box of median cut: a range of the point array, its moments, its best cut.
struct CutBox {
    lo: usize,
    hi: usize,
    cut: Option<(f64, usize, f32)>,
    moments: Moments,
}

impl CutBox {
    fn new(pts: &mut [(Point, f64)], lo: usize, hi: usize) -> CutBox {
        let moments = moments_of(&pts[lo..hi]);
        let cut = best_cut(&pts[lo..hi], &moments);
        CutBox {
            lo,
            hi,
            cut,
            moments,
        }
    }
}

/// Median cut in Wu's greedy form: every box knows the cut (axis and place,
/// not necessarily the median) that lowers its squared error most, and the
/// box split next is the one whose cut gains most.
pub(super) fn median_cut(points: &[(Point, f64)], k: usize) -> Vec<Point> {
    let mut pts = points.to_vec();
    let n = pts.len();
    let mut boxes = vec![CutBox::new(&mut pts, 0, n)];
    while boxes.len() < k {
        let Some(bi) = (0..boxes.len())
            .filter(|&i| boxes[i].cut.is_some())
            .max_by(|&a, &b| {
                let g = |i: usize| boxes[i].cut.map_or(0.0, |c| c.0);
                g(a).total_cmp(&g(b)).then(b.cmp(&a))
            })
        else {
            break;
        };
        let (lo, hi) = (boxes[bi].lo, boxes[bi].hi);
        let (_, axis, threshold) = boxes[bi].cut.expect("filtered on Some");
        let cut = apply_cut(&mut pts[lo..hi], axis, threshold);
        boxes[bi] = CutBox::new(&mut pts, lo, lo + cut);
        boxes.push(CutBox::new(&mut pts, lo + cut, hi));
    }
    boxes.iter().map(|b| b.moments.mean()).collect()
}
