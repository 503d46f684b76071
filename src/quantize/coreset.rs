//! A smaller stand-in for a large colour histogram, so that the palette search
//! of a big photo costs about what a 256x256 one does.
//!
//! A 1024x1024 photo has 10^5 to 10^6 distinct colours; median cut, k-means
//! and its split/merge trials on all of them took 1.8-2.9 s at K = 256,
//! 3.6-5.9x pngquant. The colours are grouped into boxes of the 8-bit lattice, each
//! replaced by its weighted mean with the box's whole weight. The squared
//! error of any palette splits exactly into the error of those means plus each
//! box's own spread, which no palette changes; so k-means on the means
//! minimises the same objective wherever a box lies wholly in one palette
//! colour's cell, and only boxes that straddle a cell boundary are
//! misassigned. The final remap assigns every pixel its own nearest colour.
//!
//! Histograms of at most [`CORESET_POINTS`] colours are searched whole, as
//! before.

use super::median_cut::Moments;
use super::space::{point, Point};

/// Histograms with more distinct colours than this are grouped into boxes.
/// At twice this, the 1024x1024 rose and wizard of
/// `bench/pat_from_image_large.sh` took 0.33 and 0.24 s at K = 256
/// (pngquant: 0.31 and 0.24 s); at this, 0.24 and 0.21 s, 0.1 dB lower and
/// still 0.24 and 0.32 dB above pngquant.
pub(super) const CORESET_POINTS: usize = 1 << 15;

/// Lloyd steps on a coreset, where a whole histogram gets up to 300 (and
/// split/merge trials, skipped here). On the 1024x1024 rose and plasma of
/// `bench/pat_from_image_large.sh` at K = 256 (measured with a coreset of up
/// to 65,536 colours, twice [`CORESET_POINTS`]), 50 steps landed within
/// 0.007 dB of 300. Histograms large for their palette size get as many
/// (`LIGHT_SEARCH_WORK` in palette.rs).
pub(super) const CORESET_KMEANS_ITERATIONS: usize = 50;

/// `points` (8-bit colours and weights) grouped into boxes of the 8-bit
/// lattice, the smallest that leave at most [`CORESET_POINTS`] of them; each
/// box becomes its points' weighted mean and total weight. Boxes start at
/// 2x2x2 codes and double along one channel at a time (red, green, blue, red,
/// ...), so each step about halves their number and the result lands between
/// half the limit and the limit. Deterministic: the boxes come in the order
/// of their packed corner.
pub(super) fn coreset(points: &[(Point, f64)]) -> Vec<(Point, f64)> {
    coarsen(group(points, FIRST_SHIFTS))
}

/// The first level's boxes: 2x2x2 codes.
const FIRST_SHIFTS: [u32; 3] = [1, 1, 1];

/// Histograms of at least this many colours have their first level of boxes
/// summed in place, in a table of every 2x2x2 box (2^21 of them, 40 bytes
/// each: 84 MB), rather than from a float copy of every colour and a sort
/// of their keys (24 and 16 bytes a colour): a 4096x4096 picture of 16.7
/// million distinct colours peaked at 1.03 GB that way. Smaller ones, all
/// of the 1024x1024 benchmark's (at most 688,717 colours), keep the sort,
/// cheaper than clearing and scanning the table.
const IN_PLACE_COLOURS: usize = 1 << 21;

/// [`coreset`] of a histogram (8-bit colours and their pixel counts), the
/// same boxes to the bit: the first level in place when the histogram has
/// [`IN_PLACE_COLOURS`] or more. A box's points are summed in the
/// histogram's order either way (the sort in [`group`] keeps it within a
/// box), so the sums, and the means, are the same.
pub(super) fn coreset_of_histogram(hist: &[([u8; 3], u64)]) -> Vec<(Point, f64)> {
    if hist.len() < IN_PLACE_COLOURS {
        let points: Vec<(Point, f64)> = hist.iter().map(|&(c, n)| (point(c), n as f64)).collect();
        return coreset(&points);
    }
    let side = 256 >> FIRST_SHIFTS[0];
    let mut boxes = vec![Moments::default(); side * side * side];
    for &(c, n) in hist {
        let [r, g, b] = c.map(|v| (v >> FIRST_SHIFTS[0]) as usize);
        boxes[(r * side + g) * side + b].add(point(c), n as f64);
    }
    coarsen(
        boxes
            .iter()
            .filter(|m| m.w > 0.0)
            .map(|m| (m.mean(), m.w))
            .collect(),
    )
}

/// The first level's boxes grouped into larger ones, a channel at a time,
/// until at most [`CORESET_POINTS`] are left.
fn coarsen(mut boxes: Vec<(Point, f64)>) -> Vec<(Point, f64)> {
    let mut shifts = FIRST_SHIFTS;
    // A box twice as long along one channel is the union of two of the last
    // level's, and the weighted mean of their means is the mean of its
    // points: each level groups the last one's (fewer) boxes, keyed by their
    // means, which lie inside them.
    for step in 0.. {
        if boxes.len() <= CORESET_POINTS || shifts == [8, 8, 8] {
            break;
        }
        shifts[step % 3] += 1;
        boxes = group(&boxes, shifts);
    }
    boxes
}

/// The points grouped into boxes of `2^shifts[c]` codes along channel `c`.
fn group(points: &[(Point, f64)], shifts: [u32; 3]) -> Vec<(Point, f64)> {
    let key = |p: &Point| {
        let c = [0, 1, 2].map(|ch| (p[ch] as u32) >> shifts[ch]);
        c[0] << 16 | c[1] << 8 | c[2]
    };
    let mut keyed: Vec<(u32, usize)> = points
        .iter()
        .enumerate()
        .map(|(i, (p, _))| (key(p), i))
        .collect();
    keyed.sort_unstable();
    let mut out = Vec::new();
    let mut i = 0;
    while i < keyed.len() {
        let mut m = Moments::default();
        let mut j = i;
        while j < keyed.len() && keyed[j].0 == keyed[i].0 {
            let (p, w) = points[keyed[j].1];
            m.add(p, w);
            j += 1;
        }
        out.push((m.mean(), m.w));
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The in-place first level gives the sorted one's boxes to the bit.
    #[test]
    fn a_histogram_summed_in_place_gives_the_same_coreset() {
        let mut seed = 5;
        let mut hist: Vec<([u8; 3], u64)> = (0..IN_PLACE_COLOURS as u32 + 1000)
            .map(|i| {
                let c = i.wrapping_mul(2_654_435_761) >> 8;
                let n = 1 + crate::quantize::test_data::lcg(&mut seed) as u64 % 5;
                ([(c >> 16) as u8, (c >> 8) as u8, c as u8], n)
            })
            .collect();
        hist.sort_unstable();
        hist.dedup_by_key(|(c, _)| *c);
        assert!(hist.len() >= IN_PLACE_COLOURS, "{}", hist.len());
        let points: Vec<(Point, f64)> = hist.iter().map(|&(c, n)| (point(c), n as f64)).collect();
        let (sorted, in_place) = (coreset(&points), coreset_of_histogram(&hist));
        assert!(in_place.len() <= CORESET_POINTS);
        assert!(sorted == in_place, "{} {}", sorted.len(), in_place.len());
    }

    #[test]
    fn cubes_keep_the_weight_and_the_mean() {
        // Every colour of a 64-level ramp in each channel: 262,144 points,
        // grouped into 2x2x2 cubes (32,768 of them).
        let mut points = Vec::new();
        for r in 0..64u8 {
            for g in 0..64u8 {
                for b in 0..64u8 {
                    points.push((point([r * 4, g * 4, b * 4]), 1.0 + (r % 3) as f64));
                }
            }
        }
        let core = coreset(&points);
        assert!(core.len() <= CORESET_POINTS, "{}", core.len());
        let total = |s: &[(Point, f64)]| {
            let mut m = Moments::default();
            s.iter().for_each(|&(p, w)| m.add(p, w));
            m
        };
        let (a, b) = (total(&points), total(&core));
        assert_eq!(a.w, b.w);
        for c in 0..3 {
            assert!((a.s[c] - b.s[c]).abs() < 1e-6 * a.s[c], "{c}");
        }
        // A small histogram is kept as it is, in order.
        let few: Vec<(Point, f64)> = (0..10u8).map(|i| (point([i, 0, 0]), 1.0)).collect();
        assert_eq!(group(&few, [0, 0, 0]), few);
    }
}
