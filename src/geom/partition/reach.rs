//! Which edges of a ring reach each band of grid cells: what the row strips
//! and a concave strip's column slabs of [`super::Partitioner::run`] are cut
//! from, so that slicing a polygon of V vertices into R rows costs what the
//! strips hold, not V per row (and a strip of S vertices into its runs of
//! columns, not S per run).
//!
//! A strip is the polygon clipped to `ylo <= y <= yhi` by two
//! Sutherland–Hodgman passes ([`super::clip_band`]): `y >= ylo`, then
//! `y <= yhi`; a slab, the strip clipped to `x0 <= x <= x1` alike. What
//! follows says it of strips; it holds of slabs and cells alike.
//!
//! Why the ring may lose vertices first, bit for bit and tag for tag. A
//! pass ([`crate::geom::clip::clip_tagged`]) walks the edges from the one
//! that ends at vertex 0, pushes for each edge what its two ends' sides
//! say (a crossing made from the input's own edge, named by the vertex that
//! starts it; the end vertex), merges a pushed point equal to the one before
//! it, and at the end pops a last point equal to the first. So a vertex
//! that lies, with both its neighbours, strictly outside a pass's line
//! (and is not the first or the last) can be dropped from that pass's
//! input: its two edges pushed nothing, the edge that now joins its
//! neighbours pushes nothing either, and every other edge, the first one
//! included, pushes what it pushed. Below `ylo` this holds for the first
//! pass, so the strip is the same. Above `yhi` it holds for the second
//! pass, whose input is the first pass's output; dropping the vertex
//! before the first pass instead removes it from that output (it lay
//! inside `y >= ylo`, as did its neighbours), where two equal points it
//! separated may then merge: the merged point lies above `yhi` too and
//! carries the later one's tag, so the second pass pushes the same around
//! it. The one place a merge or a drop can reach further is the pop at the
//! end, which decides the second pass's first edge: with the ring closed by
//! repeats of vertex 0, the first pass's output ends in them, merged and
//! popped, and then in the last vertex whose point is not vertex 0's, which
//! must still be there to be the second pass's first point (dropped, an
//! earlier repeat of vertex 0 merged with the closing one and went too).
//! So the first and last vertices and that one always stay.
//! `kept_rings_cut_the_same_strips_and_slabs_as_whole_ones` checks all
//! this against the whole ring on random rings with vertices on and beside
//! the lines, repeats and rings closed by a repeat of their first vertex.
//!
//! The vertices kept are the ends of the edges whose range meets the band,
//! found from an active-edge table: each edge is listed from the cell
//! before its lowest point to the cell of its highest, and the exact test is
//! made per band. Before this, a sliver 100,000 texels tall with 50,000
//! vertices a side took 26.2 s, all of it clipping whole rings, and a comb
//! of 16,000 teeth in one row 6.5 s (`bench/RESULTS-polyfill3-vertices.md`).

use crate::geom::clip::{Axis, TVertex};

/// Below this many vertices a band clips the whole ring, as before: a
/// handful of comparisons per vertex. The threshold is a choice, not a
/// measured optimum: the polygons the table is for have thousands.
pub(super) const REACH_FROM_VERTICES: usize = 16;

/// The active-edge table of one ring over the grid lines of one axis.
#[derive(Default)]
pub(super) struct Reach {
    /// Edge `i` (vertex `i` to `i + 1`) may reach the cells between lines
    /// `lines[i].0` and `lines[i].1 + 1`.
    lines: Vec<(i64, i64)>,
    /// Edges in the order of their first line.
    order: Vec<u32>,
    /// How many of `order` have been taken into `active`.
    taken: usize,
    /// Edges that may reach the current band.
    active: Vec<u32>,
    /// Indices of the vertices kept for the current band.
    kept: Vec<u32>,
    /// The last vertex whose point is not vertex 0's, which always stays
    /// (see the module's comment).
    last_apart: u32,
}

/// A point's coordinate along `axis`.
fn along(v: &TVertex, axis: Axis) -> f64 {
    match axis {
        Axis::X => v.p.x,
        Axis::Y => v.p.y,
    }
}

impl Reach {
    /// Lists the edges of `ring` by the cells along `axis` they may reach,
    /// `cell_of(t)` being the cell `k` with `line(k) <= t < line(k + 1)`
    /// ([`super::Grid::row_of`], [`super::Grid::col_of`]). Bands are then
    /// asked in increasing order with [`Reach::ring`].
    pub(super) fn start(&mut self, ring: &[TVertex], axis: Axis, cell_of: impl Fn(f64) -> i64) {
        let n = ring.len();
        self.lines.clear();
        self.lines.extend((0..n).map(|i| {
            let (a, b) = (along(&ring[i], axis), along(&ring[(i + 1) % n], axis));
            // An edge whose lowest point is exactly on a cell's first line
            // also reaches the cell before it (bands are closed), hence the
            // one cell more.
            (cell_of(a.min(b)) - 1, cell_of(a.max(b)))
        }));
        self.order.clear();
        self.order.extend(0..n as u32);
        let lines = &self.lines;
        self.order.sort_unstable_by_key(|&i| lines[i as usize].0);
        self.taken = 0;
        self.active.clear();
        self.last_apart = ring.iter().rposition(|v| v.p != ring[0].p).unwrap_or(0) as u32;
    }

    /// The ring to clip to the band of cells `first..=last`, `lo <= t <=
    /// hi` along `axis`: `ring` (as given to [`Reach::start`]) less the
    /// vertices that add nothing to the band's piece, into `out`. Bands must
    /// come in increasing order and not overlap.
    pub(super) fn ring(
        &mut self,
        (first, last): (i64, i64),
        (lo, hi): (f64, f64),
        ring: &[TVertex],
        axis: Axis,
        out: &mut Vec<TVertex>,
    ) {
        while self.taken < self.order.len() && self.lines[self.order[self.taken] as usize].0 <= last
        {
            self.active.push(self.order[self.taken]);
            self.taken += 1;
        }
        let lines = &self.lines;
        self.active.retain(|&i| lines[i as usize].1 >= first);
        let n = ring.len();
        self.kept.clear();
        for &i in &self.active {
            let next = (i as usize + 1) % n;
            let (a, b) = (along(&ring[i as usize], axis), along(&ring[next], axis));
            // The exact test: the edge's range meets the closed band.
            if a.max(b) >= lo && a.min(b) <= hi {
                self.kept.extend([i, next as u32]);
            }
        }
        // The first and last vertices, and the last one apart from the
        // first, stay whatever they reach: the passes start from the edge
        // that ends at vertex 0, and the second pass from the point the
        // first one's closing pop leaves last (see the module's comment).
        self.kept.extend([0, self.last_apart, n as u32 - 1]);
        self.kept.sort_unstable();
        self.kept.dedup();
        out.clear();
        out.extend(self.kept.iter().map(|&i| ring[i as usize]));
    }
}

#[cfg(test)]
mod tests {
    use super::super::{clip_band, Grid, Placement};
    use super::*;
    use crate::geom::clip::tagged;
    use glam::DVec2;
    use proptest::prelude::*;

    /// Every row's strip from the whole ring and from the kept ring; then,
    /// in each strip, the slab of every run of `run` columns (and of the
    /// single columns) from the whole strip and from its kept ring, and each
    /// slab's cells from the whole slab and from its kept ring. Returns the
    /// most vertices a row kept.
    fn pieces_agree(
        orig: &[DVec2],
        incr: f64,
        vert: f64,
        run: i64,
    ) -> Result<usize, TestCaseError> {
        let place = Placement {
            incr,
            horz: 0.25,
            vert,
        };
        let Ok(grid) = Grid::new(orig, place) else {
            return Ok(0);
        };
        let base: Vec<TVertex> = tagged(orig).collect();
        let (mut rows, mut cols) = (Reach::default(), Reach::default());
        rows.start(&base, Axis::Y, |y| grid.row_of(y));
        let (mut tmp, mut whole, mut ring, mut strip) = (vec![], vec![], vec![], vec![]);
        let mut most = 0;
        for j in grid.j0..=grid.j1 {
            let band = (grid.gy(j), grid.gy(j + 1));
            clip_band(&base, orig, Axis::Y, band, band, &mut tmp, &mut strip);
            rows.ring((j, j), band, &base, Axis::Y, &mut ring);
            most = most.max(ring.len());
            clip_band(&ring, orig, Axis::Y, band, band, &mut tmp, &mut whole);
            prop_assert_eq!(&whole, &strip, "row {} of {:?}", j, orig);
            if strip.len() < 3 {
                continue;
            }
            for width in [1, run] {
                cols.start(&strip, Axis::X, |x| grid.col_of(x));
                let mut k = grid.k0;
                while k <= grid.k1 {
                    let last = (k + width - 1).min(grid.k1);
                    let slab = (grid.gx(k), grid.gx(last + 1));
                    clip_band(&strip, orig, Axis::X, slab, band, &mut tmp, &mut whole);
                    cols.ring((k, last), slab, &strip, Axis::X, &mut ring);
                    let mut cut = vec![];
                    clip_band(&ring, orig, Axis::X, slab, band, &mut tmp, &mut cut);
                    prop_assert_eq!(
                        &cut,
                        &whole,
                        "row {} columns {}..={} of {:?}",
                        j,
                        k,
                        last,
                        orig
                    );
                    // The slab's cells, from the whole slab and its kept ring.
                    let slab_ring = whole.clone();
                    if slab_ring.len() >= 3 {
                        let mut cells = Reach::default();
                        cells.start(&slab_ring, Axis::X, |x| grid.col_of(x));
                        for c in k..=last {
                            let cell = (grid.gx(c), grid.gx(c + 1));
                            clip_band(&slab_ring, orig, Axis::X, cell, band, &mut tmp, &mut whole);
                            cells.ring((c, c), cell, &slab_ring, Axis::X, &mut ring);
                            clip_band(&ring, orig, Axis::X, cell, band, &mut tmp, &mut cut);
                            prop_assert_eq!(
                                &cut,
                                &whole,
                                "row {} cell {} of {:?}",
                                j,
                                c,
                                slab_ring
                            );
                        }
                    }
                    k = last + 1;
                }
            }
        }
        Ok(most)
    }

    /// A ring of `n` points, each a random step from the last, with some
    /// landing exactly on grid lines and some repeated: concave, often
    /// self-touching, and not always simple (the pieces are compared as the
    /// clip makes them, whatever the ring).
    fn ring_strategy() -> impl Strategy<Value = Vec<DVec2>> {
        prop::collection::vec((-8i32..=8, -8i32..=8, 0u8..6), 3..60).prop_map(|steps| {
            let mut at = DVec2::ZERO;
            let mut first = None;
            steps
                .into_iter()
                .map(|(dx, dy, kind)| {
                    match kind {
                        // On a line of the grid (incr 1 or 0.5; shifts 0.25 and 0.5).
                        0 => at += DVec2::new(dx as f64 * 0.25, dy as f64 * 0.25),
                        // A step of a third: beside the lines.
                        1 => at += DVec2::new(dx as f64 / 3.0, dy as f64 / 3.0),
                        // A repeated vertex.
                        2 => {}
                        // Straight up or down, or across: an edge along an axis.
                        3 => at.y += dy as f64 * 0.5,
                        4 => at.x += dx as f64 * 0.5,
                        // Back to the first vertex (a ring closed, or
                        // touching itself, by a repeat of it).
                        _ => at = first.unwrap_or(at),
                    }
                    first.get_or_insert(at);
                    at
                })
                .collect()
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(super::super::props::cases_or(512)))]

        #[test]
        fn kept_rings_cut_the_same_strips_and_slabs_as_whole_ones(
            orig in ring_strategy(),
            incr in prop::sample::select(vec![0.5, 1.0, 0.7, 3.0]),
            vert in prop::sample::select(vec![0.0, 0.5, 0.25]),
            run in 2i64..6,
        ) {
            pieces_agree(&orig, incr, vert, run)?;
        }
    }

    /// Shrunk by proptest from a version that let the ring start at its
    /// first kept vertex: six repeats of one point above the band, then the
    /// edges through it. Both rings gave the same cycle of points but began
    /// it at different ones, since the first pass merges a closing point
    /// equal to the opening one.
    #[test]
    fn a_ring_whose_start_reaches_no_row_begins_its_strips_where_the_whole_ring_does() {
        let mut orig = vec![DVec2::ZERO; 6];
        orig.extend([(0.0, -0.5), (-2.0, -4.5), (0.0, -2.5), (0.0, -0.5)].map(DVec2::from));
        pieces_agree(&orig, 0.5, 0.0, 2).unwrap();
    }

    /// Found by a review: a ring closed by a repeat of its first vertex,
    /// with fourteen points above the band before the repeat. Dropping them
    /// let the repeat merge with an earlier copy of the first vertex, so the
    /// first pass's closing pop took both, and the second pass began at
    /// another point: the same cycle, started elsewhere. Kept since: the
    /// last vertex apart from the first.
    #[test]
    fn a_ring_closed_by_a_repeat_of_its_first_vertex_begins_its_strips_where_the_whole_ring_does() {
        let mut orig: Vec<DVec2> = [(0.0, 5.0), (4.0, 5.0), (4.0, 0.0), (1.0, 0.0), (0.0, 5.0)]
            .map(DVec2::from)
            .to_vec();
        orig.extend((0..14).map(|i| DVec2::new(-1.0 - i as f64 * 0.1, 6.0 + i as f64)));
        orig.push(DVec2::new(0.0, 5.0));
        pieces_agree(&orig, 1.0, 0.0, 2).unwrap();
    }

    #[test]
    fn a_tall_sliver_keeps_a_few_vertices_a_row() {
        // 400 vertices a side over 200 rows: each row's ring holds the
        // vertices near it, not the 800.
        let v = 400;
        let side = |x0: f64, k: f64| {
            (0..v)
                .map(move |i| DVec2::new(x0 + 0.1 * crate::math::sin(i as f64 * k), i as f64 * 0.5))
        };
        let mut orig: Vec<DVec2> = side(0.8, 0.9).collect();
        orig.extend(side(0.2, 0.7).collect::<Vec<_>>().into_iter().rev());
        let most = pieces_agree(&orig, 1.0, 0.0, 1).unwrap();
        // A closed band one row tall meets the edges between y = j - 0.5
        // and j + 1.5: 5 vertices a side, and vertex 0 and the last one,
        // which always stay (the last is also the last apart from vertex 0).
        assert!(most <= 12, "a row kept {most} of {} vertices", orig.len());
    }
}
