//! Point-sampled scan conversion (`--aa none`, `--aa ss<N>`), watertight.
//!
//! Vertices are snapped to a fixed-point grid of 1/[`SUBPIXEL`] pixel and every
//! inside test is done in exact integer arithmetic, so the result is a pure
//! function of the snapped geometry and no rounding can open a gap or make two
//! polygons claim one sample.
//!
//! **Fill rule** (nonzero winding, with half-open conventions that play the part
//! of the usual top-left rule): a sample at `(X, Y)` counts an edge from `a` to
//! `b` when `min(ay, by) <= Y < max(ay, by)` (half-open in y) and `X < x_edge(Y)`
//! strictly (the edge lies to the sample's right); the edge adds +1 going up and
//! -1 going down, and the sample is inside when the sum is not 0. A sample on an
//! edge shared by two polygons is therefore inside exactly one of them (the one
//! to its right), a sample on a shared vertex in exactly one of the polygons
//! around it, and concave polygons need no triangulation.
//!
//! Samples: `k x k` per pixel on a regular grid at `((i + 1/2)/k, (j + 1/2)/k)`;
//! with `k = 1`, the pixel centre. To keep sample positions on the integer grid,
//! coordinates are scaled by `2k * SUBPIXEL`.

use super::{tie_tolerance, Background, ScreenPoly};
use smallvec::SmallVec;

/// Sub-pixel precision of snapped vertices: 1/256 pixel, as in common GPU
/// rasterizers. Moving a vertex by at most 1/512 pixel is far below what a
/// point-sampled image can show, and it keeps all products within i64 (see
/// [`super::MAX_SS_SIDE`]).
pub const SUBPIXEL: i64 = 256;

/// One edge on the integer sample lattice, lower endpoint first (so both
/// polygons sharing an edge compute the same crossings).
#[derive(Clone, Copy, Debug)]
struct LatticeEdge {
    /// The lower endpoint.
    ax: i64,
    ay: i64,
    /// The upper endpoint: `by > ay` (horizontal edges are dropped).
    bx: i64,
    by: i64,
    /// The winding it adds: +1 when the polygon runs up along it, -1 down.
    dir: i8,
}

/// One polygon on the integer sample lattice: its non-horizontal edges (a
/// triangle's or a quad's without a heap block). Made where a tile meets the
/// polygon, again in each tile it meets: made once per polygon and kept,
/// a million triangles' took 150 MB beside their screen polygons.
#[derive(Clone, Debug)]
pub struct FixedPoly {
    edges: SmallVec<[LatticeEdge; 4]>,
    /// Lowest and highest y (lattice units).
    ymin: i64,
    ymax: i64,
}

impl FixedPoly {
    /// Snaps a screen polygon for `k x k` sampling.
    pub fn new(p: &ScreenPoly, k: u32) -> FixedPoly {
        let scale = 2 * k as i64;
        let snap = |v: f64| (v * SUBPIXEL as f64).round() as i64 * scale;
        let pts: SmallVec<[(i64, i64); 4]> =
            p.verts().iter().map(|v| (snap(v.x), snap(v.y))).collect();
        let n = pts.len();
        let mut edges = SmallVec::with_capacity(n);
        let (mut ymin, mut ymax) = (i64::MAX, i64::MIN);
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            ymin = ymin.min(a.1);
            ymax = ymax.max(a.1);
            match a.1.cmp(&b.1) {
                std::cmp::Ordering::Less => edges.push(LatticeEdge {
                    ax: a.0,
                    ay: a.1,
                    bx: b.0,
                    by: b.1,
                    dir: 1,
                }),
                std::cmp::Ordering::Greater => edges.push(LatticeEdge {
                    ax: b.0,
                    ay: b.1,
                    bx: a.0,
                    by: a.1,
                    dir: -1,
                }),
                std::cmp::Ordering::Equal => {}
            }
        }
        FixedPoly { edges, ymin, ymax }
    }

    /// Calls `span(m0, m1)` for every maximal run of inside samples on the
    /// sample row at lattice height `y`, where sample `m` sits at lattice x
    /// `x0 + m * step` for `m` in `0..count`.
    pub fn spans(&self, y: i64, x0: i64, step: i64, count: i64, mut span: impl FnMut(i64, i64)) {
        if y < self.ymin || y >= self.ymax {
            return;
        }
        // Each active edge: the first sample index no longer left of it.
        let mut events: [(i64, i8); 8] = [(0, 0); 8];
        let mut heap: Vec<(i64, i8)> = Vec::new();
        let mut n_ev = 0;
        for &LatticeEdge {
            ax,
            ay,
            bx,
            by,
            dir,
        } in &self.edges
        {
            if y < ay || y >= by {
                continue;
            }
            // x_edge(y) = (ax*dy + (bx-ax)*(y-ay)) / dy exactly; samples with
            // X < ceil(x_edge) are left of the edge.
            let dy = by - ay;
            let num = ax * dy + (bx - ax) * (y - ay);
            let t = ceil_div(num, dy);
            // First m with x0 + m*step >= t.
            let m = ceil_div(t - x0, step).clamp(0, count);
            if n_ev < events.len() {
                events[n_ev] = (m, dir);
                n_ev += 1;
            } else {
                if heap.is_empty() {
                    heap.extend_from_slice(&events);
                }
                heap.push((m, dir));
            }
        }
        let evs: &mut [(i64, i8)] = if heap.is_empty() {
            &mut events[..n_ev]
        } else {
            &mut heap
        };
        evs.sort_unstable();
        // Left of every event the winding is the sum of all directions (0 for
        // a closed polygon); passing an event removes its edge.
        let mut wind: i32 = evs.iter().map(|e| e.1 as i32).sum();
        let mut prev = 0i64;
        for &(m, dir) in evs.iter() {
            if wind != 0 && m > prev {
                span(prev, m);
            }
            wind -= dir as i32;
            prev = prev.max(m);
        }
        if wind != 0 && count > prev {
            span(prev, count);
        }
    }
}

/// `ceil(a / b)` for `b > 0`.
#[inline]
fn ceil_div(a: i64, b: i64) -> i64 {
    -((-a).div_euclid(b))
}

/// Renders one tile by point sampling: per sample the nearest polygon wins
/// (ties to the later one, painter's order, within
/// [`super::tie_tolerance`] floored by `tie_floor`); a pixel is the
/// linear-light mean of its samples.
pub fn render_tile(
    polys: &[ScreenPoly],
    bin: &[u32],
    bg: &Background,
    tile: [u32; 4],
    k: u32,
    tie_floor: f64,
) -> Vec<[f32; 3]> {
    let [tx0, ty0, tx1, ty1] = tile;
    let (tw, th) = ((tx1 - tx0) as usize, (ty1 - ty0) as usize);
    let ki = k as usize;
    // Sample buffers, row-major over the tile's sample grid.
    let sw = tw * ki;
    let sh = th * ki;
    let mut depth = vec![f64::NEG_INFINITY; sw * sh];
    let mut owner = vec![u32::MAX; sw * sh];
    let scale = 2 * k as i64 * SUBPIXEL;
    let step = 2 * SUBPIXEL; // lattice distance between samples
    let kf = k as f64;
    for &pi in bin {
        let p = &polys[pi as usize];
        let [bx0, by0, bx1, by1] = p.bbox();
        let (x0, x1) = (bx0.max(tx0), bx1.min(tx1));
        let (y0, y1) = (by0.max(ty0), by1.min(ty1));
        if x0 >= x1 || y0 >= y1 {
            continue;
        }
        let f = FixedPoly::new(p, k);
        let col0 = (x0 - tx0) as usize * ki;
        let count = ((x1 - x0) as usize * ki) as i64;
        // Lattice x of the first sample column in range.
        let lx0 = x0 as i64 * scale + SUBPIXEL;
        let dq = p.plane[0] / kf;
        for py in y0..y1 {
            for j in 0..ki {
                let ly = py as i64 * scale + (2 * j as i64 + 1) * SUBPIXEL;
                let sy = py as f64 + (j as f64 + 0.5) / kf;
                let row = ((py - ty0) as usize * ki + j) * sw;
                f.spans(ly, lx0, step, count, |m0, m1| {
                    let sx0 = x0 as f64 + (m0 as f64 + 0.5) / kf;
                    let mut q = p.q(sx0, sy);
                    for m in m0..m1 {
                        let idx = row + col0 + m as usize;
                        let old = depth[idx];
                        // A screen-mode pattern's transparent texel leaves
                        // the sample to whatever is behind.
                        let opaque = !p.may_be_transparent()
                            || p.sample_color(
                                x0 + (m as u32) / k,
                                py,
                                x0 as f64 + (m as f64 + 0.5) / kf,
                                sy,
                            )
                            .is_some();
                        // A later polygon wins unless it is farther by more
                        // than the tie tolerance.
                        if opaque
                            && (old == f64::NEG_INFINITY
                                || q - old >= -tie_tolerance(q, old, tie_floor))
                        {
                            depth[idx] = q;
                            owner[idx] = pi;
                        }
                        q += dq;
                    }
                });
            }
        }
    }
    let inv = 1.0 / (k * k) as f64;
    let mut out = Vec::with_capacity(tw * th);
    for ty in 0..th {
        for tx in 0..tw {
            let mut acc = [0.0f64; 3];
            let mut n_bg = 0u32;
            for j in 0..ki {
                for i in 0..ki {
                    let o = owner[(ty * ki + j) * sw + tx * ki + i];
                    if o == u32::MAX {
                        n_bg += 1;
                    } else {
                        let (px, py) = (tx0 + tx as u32, ty0 + ty as u32);
                        let c = polys[o as usize]
                            .sample_color(
                                px,
                                py,
                                px as f64 + (i as f64 + 0.5) / kf,
                                py as f64 + (j as f64 + 0.5) / kf,
                            )
                            .expect("transparent texels own no sample");
                        for ch in 0..3 {
                            acc[ch] += c[ch];
                        }
                    }
                }
            }
            out.push(mean_of_samples(
                acc,
                n_bg,
                bg,
                (tx0 + tx as u32, ty0 + ty as u32),
                inv,
            ));
        }
    }
    out
}

/// A pixel's linear light: the mean, by `inv = 1/k²`, of its samples, `acc`
/// summing those of polygons and `n_bg` more of the background.
#[inline]
fn mean_of_samples(
    mut acc: [f64; 3],
    n_bg: u32,
    bg: &Background,
    (px, py): (u32, u32),
    inv: f64,
) -> [f32; 3] {
    if n_bg > 0 {
        let b = bg.at(px, py);
        for ch in 0..3 {
            acc[ch] += b[ch] * n_bg as f64;
        }
    }
    acc.map(|a| (a * inv) as f32)
}

/// What [`render_tile`] gives pixel `(px, py)` with `k x k` samples when no
/// polygon covers any of them: the same arithmetic, so a tile that no
/// polygon reaches can be filled with it without being sampled.
pub fn background_pixel(bg: &Background, k: u32, px: u32, py: u32) -> [f32; 3] {
    mean_of_samples([0.0; 3], k * k, bg, (px, py), 1.0 / (k * k) as f64)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::tests::poly2;
    use super::super::{render, Aa};
    use super::*;
    use crate::color::Rgb8;
    use crate::view::View;

    pub use crate::test_util::Rng;

    /// Counts, per sample, how many polygons cover it.
    fn count_hits(polys: &[ScreenPoly], w: u32, h: u32, k: u32) -> Vec<u32> {
        let ki = k as usize;
        let sw = w as usize * ki;
        let mut hits = vec![0u32; sw * h as usize * ki];
        let scale = 2 * k as i64 * SUBPIXEL;
        for p in polys {
            let f = FixedPoly::new(p, k);
            for sy in 0..h as usize * ki {
                let ly = (sy / ki) as i64 * scale + (2 * (sy % ki) as i64 + 1) * SUBPIXEL;
                f.spans(ly, SUBPIXEL, 2 * SUBPIXEL, sw as i64, |m0, m1| {
                    for m in m0..m1 {
                        hits[sy * sw + m as usize] += 1;
                    }
                });
            }
        }
        hits
    }

    #[test]
    fn random_triangles_tiling_a_square_cover_every_sample_exactly_once() {
        // A jittered 40x40 grid of points over [3, 61]^2, each cell cut along a
        // random diagonal: 3200 triangles sharing every inner edge. Points are
        // also placed exactly on sample positions and pixel corners to hit the
        // tie cases of the fill rule.
        let (w, h, k) = (64u32, 64u32, 4u32);
        let view = View::ortho2(0.0, w as f64, 0.0, h as f64, w, h);
        let n = 40usize;
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (lo, hi) = (3.0, 61.0);
        let cell = (hi - lo) / n as f64;
        let mut pts = vec![[0.0f64; 2]; (n + 1) * (n + 1)];
        for j in 0..=n {
            for i in 0..=n {
                let mut x = lo + i as f64 * cell;
                let mut y = lo + j as f64 * cell;
                if i > 0 && i < n {
                    x += (rng.next() - 0.5) * cell * 0.5;
                }
                if j > 0 && j < n {
                    y += (rng.next() - 0.5) * cell * 0.5;
                }
                match (i + j) % 5 {
                    0 => {
                        x = (x * 8.0).round() / 8.0 + 1.0 / 16.0;
                        y = (y * 8.0).round() / 8.0 + 1.0 / 16.0;
                    }
                    1 => {
                        x = (x * 4.0).round() / 4.0;
                        y = (y * 4.0).round() / 4.0;
                    }
                    _ => {}
                }
                if i == 0 || i == n {
                    x = if i == 0 { lo } else { hi };
                }
                if j == 0 || j == n {
                    y = if j == 0 { lo } else { hi };
                }
                pts[j * (n + 1) + i] = [x, y];
            }
        }
        let mut polys = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = pts[j * (n + 1) + i];
                let b = pts[j * (n + 1) + i + 1];
                let c = pts[(j + 1) * (n + 1) + i + 1];
                let d = pts[(j + 1) * (n + 1) + i];
                let tris = if rng.next() < 0.5 {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for t in tris {
                    polys.extend(poly2(&view, &t, Rgb8::WHITE, polys.len() as u32));
                }
            }
        }
        assert_eq!(polys.len(), 2 * n * n);
        let hits = count_hits(&polys, w, h, k);
        let sw = (w * k) as usize;
        for (idx, &c) in hits.iter().enumerate() {
            let sx = (idx % sw) as f64 / k as f64 + 0.5 / k as f64;
            let sy = (idx / sw) as f64 / k as f64 + 0.5 / k as f64;
            let inside = sx > lo && sx < hi && sy > lo && sy < hi;
            if inside {
                assert_eq!(c, 1, "sample ({sx}, {sy}) hit {c} times");
            } else if !(sx >= lo && sx <= hi && sy >= lo && sy <= hi) {
                assert_eq!(c, 0, "sample ({sx}, {sy}) outside hit");
            }
        }
    }

    #[test]
    fn concave_polygons_fill_by_nonzero_winding() {
        let view = View::ortho2(0.0, 8.0, 0.0, 8.0, 8, 8);
        let l = poly2(
            &view,
            &[
                [0.0, 0.0],
                [4.0, 0.0],
                [4.0, 1.0],
                [1.0, 1.0],
                [1.0, 4.0],
                [0.0, 4.0],
            ],
            Rgb8::WHITE,
            0,
        )
        .unwrap();
        let hits = count_hits(&[l], 8, 8, 1);
        assert_eq!(hits.iter().sum::<u32>(), 7);
        assert_eq!(hits[8 + 1], 0);
    }

    #[test]
    fn nearer_polygons_hide_farther_ones_and_ties_go_to_the_later() {
        let view = View::ortho2(0.0, 4.0, 0.0, 4.0, 4, 4);
        let sq = |z: f64, c: Rgb8, o: u32| {
            super::super::project(
                &view,
                &[
                    glam::DVec3::new(0.0, 0.0, z),
                    glam::DVec3::new(4.0, 0.0, z),
                    glam::DVec3::new(4.0, 4.0, z),
                    glam::DVec3::new(0.0, 4.0, z),
                ],
                c,
                o,
                super::super::Cull::None,
            )
            .unwrap()
        };
        let red = Rgb8([255, 0, 0]);
        let blue = Rgb8([0, 0, 255]);
        let bg = Background::color(Rgb8::BLACK);
        // Blue nearer (z = 0.5 is toward the viewer) though drawn first.
        let img = render(&[sq(0.5, blue, 0), sq(0.0, red, 1)], &bg, &view, Aa::None).to_image();
        assert_eq!(&img.data[..3], &[0, 0, 255]);
        let img = render(&[sq(0.0, red, 0), sq(0.0, blue, 1)], &bg, &view, Aa::Ss(2)).to_image();
        assert_eq!(&img.data[..3], &[0, 0, 255]);
    }
}
