//! Refining the median-cut palette: weighted k-means, split/merge moves,
//! Lloyd steps on the rounded 8-bit palette and a one-code neighbour search,
//! each bounded in work so that large photos stay within seconds.
//!
//! - [`kmeans`] runs Lloyd's iterations to convergence: on 256x256 photos they
//!   still gain about 0.1% of the error every ten iterations after 60, and
//!   Hamerly's bounds make those late iterations cheap.
//! - [`split_merge`] lets k-means leave a poor local optimum (common on nearly
//!   one-dimensional colour sets such as ramps and grey textures).
//! - [`integer_lloyd`] wins back what rounding a converged float palette to
//!   8-bit codes loses, and [`neighbour_search`] finds the moves that rounded
//!   means cannot: the best 8-bit palette is not the rounded best real one.
//!
//! The parallel sums use fixed chunks ([`KMEANS_CHUNK`]) and every tie is
//! broken by index, so the result does not depend on the thread count.

use super::median_cut::{apply_cut, best_cut, moments_of, Moments};
use super::space::{dist2, Channels, Point};
use crate::progress::Progress;

/// At most this many Lloyd iterations. On 256x256 photos k-means still gains
/// about 0.1% of its error every ten iterations after 60; with Hamerly's bounds
/// those late iterations are cheap, and 300 bounds pathological inputs.
const KMEANS_MAX_ITERATIONS: usize = 300;
/// ... and at most this many (distinct colours x iterations), so that large
/// patterns of photos (a 1024x1024 upscale has ~10^6 colours) stay within
/// seconds; every image of up to 256x256 pixels still gets all 300.
const KMEANS_WORK: usize = 1 << 25;
/// ... and at most this many (distinct colours x centres x iterations): the
/// same budget for palettes of up to 32 colours, fewer iterations for larger
/// ones, whose every step costs K distances a point. The 1024x1024 logo of
/// `bench/pat_from_image_large.sh` (28,252 colours) at K = 256 took 0.39 s
/// with the per-point budget alone (300 iterations, 9 split/merge trials)
/// and 0.20 s with this one; pngquant 0.13 s.
const KMEANS_WORK_WITH_K: usize = KMEANS_WORK * 32;
/// The fewest iterations the work budget may leave: past the first few dozen,
/// gains are fractions of a percent of the error.
const KMEANS_MIN_ITERATIONS: usize = 24;

/// Points per parallel work unit of a Lloyd step. Fixed, so the chunking (and
/// with it every floating-point sum) is the same whatever the thread count.
const KMEANS_CHUNK: usize = 4096;

/// The result of k-means: centres, each point's cluster, the weighted squared error.
pub(super) struct Clustering {
    centres: Vec<Point>,
    assign: Vec<usize>,
    err: f64,
}

/// One Lloyd assignment: each point to its nearest centre (starting from its
/// current one), with per-cluster moments, the total error and the point that
/// contributes most error.
fn assign_step(
    points: &[(Point, f64)],
    centres: &[Point],
    assign: &mut [usize],
) -> (Vec<Moments>, f64, (f64, usize)) {
    use rayon::prelude::*;
    let channels = Channels::new(centres);
    let parts: Vec<(Vec<Moments>, f64, (f64, usize))> = points
        .par_chunks(KMEANS_CHUNK)
        .zip(assign.par_chunks_mut(KMEANS_CHUNK))
        .enumerate()
        .map(|(ci, (pts, asg))| {
            let mut sums = vec![Moments::default(); centres.len()];
            let mut err = 0.0;
            let mut worst = (-1.0f64, 0usize);
            for (i, (&(p, w), a)) in pts.iter().zip(asg.iter_mut()).enumerate() {
                let (c, d) = channels.nearest(p);
                *a = c;
                sums[c].add(p, w);
                let e = d as f64 * w;
                err += e;
                if e > worst.0 {
                    worst = (e, ci * KMEANS_CHUNK + i);
                }
            }
            (sums, err, worst)
        })
        .collect();
    let mut sums = vec![Moments::default(); centres.len()];
    let mut err = 0.0;
    let mut worst = (-1.0f64, 0usize);
    for (s, e, w) in parts {
        for (acc, m) in sums.iter_mut().zip(&s) {
            acc.w += m.w;
            acc.ss += m.ss;
            for c in 0..3 {
                acc.s[c] += m.s[c];
            }
        }
        err += e;
        if w.0 > worst.0 {
            worst = w;
        }
    }
    (sums, err, worst)
}

/// Hamerly's bounds for one point: its cluster, an upper bound on the
/// distance to that centre and a lower bound on the distance to any other.
#[derive(Clone, Copy)]
struct Bounds {
    cluster: usize,
    upper: f32,
    lower: f32,
}

/// Weighted Lloyd iterations from `centres` until no point changes cluster (or
/// the iteration budget, [`KMEANS_MAX_ITERATIONS`] and [`KMEANS_WORK`], runs out). Hamerly's bounds skip the nearest-centre search
/// for points that provably keep their centre, so the long tail of small
/// moves that k-means needs to converge costs little. An emptied cluster is
/// moved to the point with the largest weighted error bound.
pub(super) fn kmeans(points: &[(Point, f64)], centres: Vec<Point>) -> Clustering {
    let n = points.len().max(1);
    let iterations = (KMEANS_WORK / n)
        .min(KMEANS_WORK_WITH_K / (n * centres.len().max(1)))
        .clamp(KMEANS_MIN_ITERATIONS, KMEANS_MAX_ITERATIONS);
    kmeans_at_most(points, centres, iterations)
}

/// [`kmeans`] with at most `iterations` Lloyd steps.
pub(super) fn kmeans_at_most(
    points: &[(Point, f64)],
    mut centres: Vec<Point>,
    iterations: usize,
) -> Clustering {
    use rayon::prelude::*;
    let k = centres.len();
    let mut bounds = vec![
        Bounds {
            cluster: 0,
            upper: f32::INFINITY,
            lower: 0.0,
        };
        points.len()
    ];
    for _ in 0..iterations {
        // Half the distance from each centre to its nearest other centre.
        let half_gap: Vec<f32> = (0..k)
            .map(|i| {
                (0..k)
                    .filter(|&j| j != i)
                    .map(|j| dist2(centres[i], centres[j]))
                    .fold(f32::INFINITY, f32::min)
                    .sqrt()
                    / 2.0
            })
            .collect();
        let centres_ref = &centres;
        let channels = Channels::new(centres_ref);
        let parts: Vec<(Vec<Moments>, usize, (f64, usize))> = points
            .par_chunks(KMEANS_CHUNK)
            .zip(bounds.par_chunks_mut(KMEANS_CHUNK))
            .enumerate()
            .map(|(ci, (pts, bs))| {
                let mut sums = vec![Moments::default(); k];
                let mut changed = 0;
                let mut worst = (-1.0f64, 0usize);
                for (i, (&(p, w), b)) in pts.iter().zip(bs.iter_mut()).enumerate() {
                    let limit = half_gap[b.cluster].max(b.lower);
                    if b.upper > limit {
                        b.upper = dist2(p, centres_ref[b.cluster]).sqrt();
                        if b.upper > limit {
                            let (at, best, second) = channels.two_nearest(p);
                            if at != b.cluster {
                                changed += 1;
                            }
                            *b = Bounds {
                                cluster: at,
                                upper: best.sqrt(),
                                lower: second.sqrt(),
                            };
                        }
                    }
                    sums[b.cluster].add(p, w);
                    let e = (b.upper as f64).powi(2) * w;
                    if e > worst.0 {
                        worst = (e, ci * KMEANS_CHUNK + i);
                    }
                }
                (sums, changed, worst)
            })
            .collect();
        let mut sums = vec![Moments::default(); k];
        let mut changed = 0;
        let mut worst = (-1.0f64, 0usize);
        for (s, c, w) in parts {
            for (acc, m) in sums.iter_mut().zip(&s) {
                acc.add_moments(m);
            }
            changed += c;
            if w.0 > worst.0 {
                worst = w;
            }
        }
        let mut moved = vec![0f32; k];
        let mut reseeded = false;
        for (j, m) in sums.iter().enumerate() {
            let new = if m.w > 0.0 {
                m.mean()
            } else if !reseeded {
                reseeded = true;
                points[worst.1].0
            } else {
                centres[j]
            };
            moved[j] = dist2(new, centres[j]).sqrt();
            centres[j] = new;
        }
        if changed == 0 && moved.iter().all(|&m| m == 0.0) {
            break;
        }
        // Widen the bounds by how far the centres moved.
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&a, &b| moved[b].total_cmp(&moved[a]));
        let (max1, max2) = (moved[order[0]], order.get(1).map_or(0.0, |&j| moved[j]));
        let first = order[0];
        bounds.par_iter_mut().for_each(|b| {
            b.upper += moved[b.cluster];
            b.lower -= if b.cluster == first { max2 } else { max1 };
        });
    }
    let mut assign: Vec<usize> = bounds.iter().map(|b| b.cluster).collect();
    let (_, err, _) = assign_step(points, &centres, &mut assign);
    Clustering {
        centres,
        assign,
        err,
    }
}

/// At most this many split-and-merge trials after k-means, in all; each is a
/// full k-means run, kept only if it lowers the error.
const SPLIT_MERGE_TRIALS: usize = 16;
/// ... and at most this many (distinct colours x trials): a 64x64 image gets
/// every trial, a 256x256 photo (~60 000 colours) about four, which keeps the
/// search within a few times the cost of the first k-means run; images with
/// more than this many colours get none.
const SPLIT_MERGE_WORK: usize = 1 << 18;
/// ... and at most this many (distinct colours x centres x trials), as
/// [`KMEANS_WORK_WITH_K`] for k-means.
const SPLIT_MERGE_WORK_WITH_K: usize = SPLIT_MERGE_WORK * 32;
/// Each round considers the best this-many splits and merges, paired.
const SPLIT_MERGE_CANDIDATES: usize = 3;

/// Escapes k-means' local optima (common on nearly one-dimensional colour sets
/// such as ramps and grey textures): remove a centre whose removal costs little
/// (its colours going to their second-nearest centre), split a cluster whose
/// best cut gains much, rerun k-means, and keep the result if the error fell.
/// Moves are tried by falling (gain - cost) even when the cost exceeds the
/// gain, since k-means' re-convergence is what finds the better optimum.
/// Deterministic, like everything here.
/// Each trial is reported to `progress` (phase "split/merge", at most the
/// trial budget).
pub(super) fn split_merge(
    points: &[(Point, f64)],
    mut best: Clustering,
    progress: &dyn Progress,
) -> Clustering {
    let k = best.centres.len();
    if k < 3 {
        return best;
    }
    let n = points.len().max(1);
    let budget = (SPLIT_MERGE_WORK / n)
        .min(SPLIT_MERGE_WORK_WITH_K / (n * k))
        .min(SPLIT_MERGE_TRIALS);
    progress.phase("split/merge", budget as u64);
    let mut trials = 0;
    'rounds: while trials < budget {
        let mut members: Vec<Vec<(Point, f64)>> = vec![Vec::new(); k];
        for (&(p, w), &a) in points.iter().zip(&best.assign) {
            members[a].push((p, w));
        }
        let moments: Vec<Moments> = members.iter().map(|m| moments_of(m)).collect();
        // The splits that gain most. A cut gains at most the cluster's whole
        // error, so clusters are tried by falling error until none can enter.
        let mut by_err: Vec<usize> = (0..k).collect();
        by_err.sort_by(|&a, &b| {
            moments[b]
                .sse()
                .total_cmp(&moments[a].sse())
                .then(a.cmp(&b))
        });
        let mut splits: Vec<(f64, usize, Point, Point)> = Vec::new();
        for c in by_err {
            if splits.len() == SPLIT_MERGE_CANDIDATES
                && splits[SPLIT_MERGE_CANDIDATES - 1].0 >= moments[c].sse()
            {
                break;
            }
            let m = &mut members[c];
            if let Some((gain, axis, threshold)) = best_cut(m, &moments[c]) {
                let cut = apply_cut(m, axis, threshold);
                let (l, r) = (moments_of(&m[..cut]), moments_of(&m[cut..]));
                splits.push((gain, c, l.mean(), r.mean()));
                splits.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                splits.truncate(SPLIT_MERGE_CANDIDATES);
            }
        }
        // The removals that cost least: a centre's points would move to their
        // second-nearest centre, at a cost of the difference in squared error.
        let mut removal = vec![0f64; k];
        for (&(p, w), &a) in points.iter().zip(&best.assign) {
            let second = best
                .centres
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != a)
                .map(|(_, &c)| dist2(p, c))
                .fold(f32::INFINITY, f32::min);
            removal[a] += w * (second - dist2(p, best.centres[a])) as f64;
        }
        let mut removals: Vec<(f64, usize)> = (0..k).map(|r| (removal[r], r)).collect();
        removals.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (si, s) in splits.iter().enumerate() {
            for r in removals
                .iter()
                .filter(|r| r.1 != s.1)
                .take(SPLIT_MERGE_CANDIDATES)
            {
                pairs.push((s.0 - r.0, si, r.1));
            }
        }
        pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        for (_, si, removed) in pairs {
            if trials == budget {
                break 'rounds;
            }
            trials += 1;
            progress.advance(1);
            let (_, sc, left, right) = splits[si];
            let mut centres = best.centres.clone();
            centres[sc] = left;
            centres[removed] = right;
            let trial = kmeans(points, centres);
            if trial.err < best.err {
                best = trial;
                continue 'rounds;
            }
        }
        break;
    }
    best
}

/// At most this many Lloyd steps on 8-bit palette entries.
const INTEGER_LLOYD_ITERATIONS: usize = 16;

fn round_point(p: Point) -> Point {
    p.map(|v| v.round().clamp(0.0, 255.0))
}

/// Lloyd steps with the centres rounded to 8-bit codes after each mean: the
/// palette is stored in 8 bits, and rounding a converged float palette moves
/// some pixels' nearest colour; re-assigning and re-rounding wins that back.
/// Stops when the palette is stable or the error stops falling.
pub(super) fn integer_lloyd(points: &[(Point, f64)], c: Clustering) -> Vec<Point> {
    let mut best: Vec<Point> = c.centres.iter().map(|&p| round_point(p)).collect();
    let mut assign = c.assign;
    let (mut sums, mut best_err, _) = assign_step(points, &best, &mut assign);
    for _ in 0..INTEGER_LLOYD_ITERATIONS {
        let next: Vec<Point> = best
            .iter()
            .zip(&sums)
            .map(|(&old, m)| {
                if m.w > 0.0 {
                    round_point(m.mean())
                } else {
                    old
                }
            })
            .collect();
        if next == best {
            break;
        }
        let mut trial_assign = assign.clone();
        let (trial_sums, err, _) = assign_step(points, &next, &mut trial_assign);
        if err >= best_err {
            break;
        }
        (best, assign, sums, best_err) = (next, trial_assign, trial_sums, err);
    }
    best
}

/// The 26 unit steps of the 8-bit colour lattice (every +-1/0 combination but none).
const LATTICE_STEPS: usize = 26;
/// The neighbour search runs only while one pass costs at most this many
/// distance evaluations (points x K x K x 26): all small palettes of small
/// images (a few milliseconds), never a large photo.
const NEIGHBOUR_SEARCH_WORK: usize = 1 << 23;
/// At most this many passes over the palette.
const NEIGHBOUR_SEARCH_PASSES: usize = 3;

/// Last polish of an 8-bit palette: move single entries by one code in any
/// combination of channels while that lowers the total error (each point
/// taking its nearest entry). Lloyd's rounded means cannot find these moves,
/// since the best 8-bit palette is not the rounded best real-valued one.
pub(super) fn neighbour_search(points: &[(Point, f64)], mut palette: Vec<Point>) -> Vec<Point> {
    let k = palette.len();
    if points.len() * k * k * LATTICE_STEPS > NEIGHBOUR_SEARCH_WORK {
        return palette;
    }
    let error = |pal: &[Point]| -> f64 {
        points
            .iter()
            .map(|&(p, w)| {
                w * pal
                    .iter()
                    .map(|&c| dist2(p, c))
                    .fold(f32::INFINITY, f32::min) as f64
            })
            .sum()
    };
    let mut best = error(&palette);
    for _ in 0..NEIGHBOUR_SEARCH_PASSES {
        let mut improved = false;
        for j in 0..k {
            for step in 0..27 {
                let d = [step / 9, step / 3 % 3, step % 3].map(|v| v as f32 - 1.0);
                if d == [0.0; 3] {
                    continue;
                }
                let moved = [0, 1, 2].map(|c| palette[j][c] + d[c]);
                if moved.iter().any(|v| !(0.0..=255.0).contains(v)) {
                    continue;
                }
                let mut trial = palette.clone();
                trial[j] = moved;
                let e = error(&trial);
                if e < best {
                    (best, palette, improved) = (e, trial, true);
                }
            }
        }
        if !improved {
            break;
        }
    }
    palette
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::median_cut::median_cut;
    use crate::quantize::palette::{choose_palette, histogram};
    use crate::quantize::space::point;
    use crate::quantize::test_data::{lcg, weighted_error};

    #[test]
    fn kmeans_never_worsens_median_cut_and_the_palette_is_deterministic() {
        let mut seed = 3;
        let colours: Vec<[u8; 3]> = (0..5000)
            .map(|_| {
                let base = lcg(&mut seed) / 64 * 64;
                [base, base / 2 + lcg(&mut seed) / 8, lcg(&mut seed)]
            })
            .collect();
        let hist = histogram(colours.iter().copied());
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        for k in [2, 4, 8, 16, 32] {
            let mc = median_cut(&points, k);
            let km = split_merge(
                &points,
                kmeans(&points, mc.clone()),
                &crate::progress::Silent,
            )
            .centres;
            assert_eq!(mc.len(), k);
            assert!(weighted_error(&points, &km) <= weighted_error(&points, &mc) + 1e-6);
            assert_eq!(choose_palette(&hist, k), choose_palette(&hist, k));
            assert!(choose_palette(&hist, k).len() <= k);
        }
    }

    #[test]
    fn the_lattice_search_never_raises_the_error() {
        let mut seed = 5;
        let hist = histogram((0..600).map(|_| {
            let g = 160 + lcg(&mut seed) / 16;
            [g, g, g + 3]
        }));
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        let start = vec![
            [150.0, 150.0, 150.0],
            [170.0, 171.0, 172.0],
            [180.0, 180.0, 180.0],
        ];
        let polished = neighbour_search(&points, start.clone());
        assert!(weighted_error(&points, &polished) < weighted_error(&points, &start));
        assert!(polished.iter().flatten().all(|v| v.fract() == 0.0));
    }
}
