//! Partition of a planar polygon into texture point polygons (the thesis's
//! `polcolorf3`, Fig. 4.7, with docs/stream-format.md "object" placement).
//!
//! The thesis clips the whole polygon against the four lines of every cell of
//! the bounding box (Fig. 4.5): O(V) per cell, convex polygons only, and its
//! inclusive loop emits degenerate polygons along the far edges. Here:
//!
//! 1. The polygon is sliced into horizontal strips, one per grid row: two
//!    clips per row line, of the vertices whose edges reach the row
//!    (`reach`: the same strip as from the whole ring, at the cost of what
//!    the strip holds, where clipping the whole ring took O(V) per row).
//! 2. In each strip the columns touched by a polygon edge are found from the
//!    edges' x-extents; only those *boundary* cells are clipped, against the
//!    strip's polygon (a handful of vertices, whatever V is). The runs of
//!    columns between them are wholly inside or wholly outside; one
//!    point-in-polygon test per run decides, and inside cells are emitted as
//!    exact squares of grid coordinates. The cost per cell does not depend on V.
//! 3. Every crossing of a grid line is computed from the input's own edge in a
//!    canonical order (`clip::cross_x`/`cross_y`), and every world point as
//!    `(origin + ey*y) + ex*x` (`Frame::to_world`), so cells on either side of
//!    a grid line share their vertices bit for bit: no cracks. (The rare
//!    piece whose rounding made it touch itself loses a vertex: `tidy`.)
//! 4. Cells are kept only when their piece has positive area: no degenerate
//!    output. For a concave polygon, a boundary cell's piece is rebuilt from
//!    its chains of input edges joined along the cell's border
//!    (`clip::split_on_border`): Sutherland–Hodgman alone would join parts by
//!    zero-width bridges whose ends lie outside the polygon. A piece that
//!    falls apart gives one polygon per part, all with the cell's texel; so
//!    the number of distinct cells written is exactly the number of cells with
//!    area, and the number of polygons can exceed it by the extra parts.
//!
//! Concave polygons and repeated or collinear vertices need nothing special:
//! clipping handles them, and the inside test of a run is even-odd.
//! Self-intersecting polygons are outside the contract (docs/stream-format.md asks for
//! planar polygons; the result is then the clip of the signed regions).

mod reach;
mod tidy;

use super::clip::{clip_closed, clip_tagged, split_on_border, tagged, Axis, TVertex, Tag};
use super::plane::{newell_normal, signed_area, PlanePolygon};
use glam::{DVec2, DVec3};
use reach::{Reach, REACH_FROM_VERTICES};
use tidy::{drop_spikes, simple_in_world, Part, WorldPiece};
pub use tidy::{simple_on_plane, OnPlane};

/// Pattern placement in a polygon's plane (docs/stream-format.md): texel side and shifts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Side of one texel in world units, > 0.
    pub incr: f64,
    /// Shift of the pattern right, in texels.
    pub horz: f64,
    /// Shift of the pattern up, in texels.
    pub vert: f64,
}

/// The grid of texel cells laid over a polygon. Cell (k, j) spans
/// `[gx(k), gx(k+1)] x [gy(j), gy(j+1)]`, where docs/stream-format.md's u = k..k+1 and
/// v = j..j+1; its texel is `(k mod SIZE, j mod SIZE)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// The polygon's bounding box in plane coordinates (the origin of the
    /// placement: docs/stream-format.md counts u from `xmin`, v from `ymin`).
    pub xmin: f64,
    /// See [`Grid::xmin`].
    pub ymin: f64,
    /// The far corner of the bounding box.
    pub xmax: f64,
    /// See [`Grid::xmax`].
    pub ymax: f64,
    /// The placement the cells follow.
    pub place: Placement,
    /// First column that can overlap the polygon.
    pub k0: i64,
    /// Last column that can overlap the polygon (inclusive).
    pub k1: i64,
    /// First row that can overlap the polygon.
    pub j0: i64,
    /// Last row that can overlap the polygon (inclusive).
    pub j1: i64,
}

/// The finest texel side, relative to the largest plane coordinate of the
/// polygon (bounding-box corner): 2^-36, about 1.5e-11. A grid line is
/// `xmin + (k + horz)*incr`; when `incr` approaches the spacing of f64 near
/// the coordinates (2^-52 of them), consecutive lines round to the same
/// value, [`Grid::col_of`] walks ~2^52 steps (a hang) and the index
/// `floor(extent/incr)` overflows i64 (a panic). At 2^-36 every cell still
/// spans 2^16 ulps of its coordinates and an axis has at most 2^37 cells.
/// The stress suite asks for incr down to 1e-6 of a polygon's size, 5 orders
/// of magnitude above this floor (`--max-polygons` refuses such jobs anyway).
pub const MIN_INCR_REL: f64 = 1.0 / (1u64 << 36) as f64;

/// The largest pattern shift `horz`/`vert`, in texels: 2^31. Lines are
/// `(k + horz)*incr`, so a shift must leave `k + horz` exact to a small
/// fraction of a texel (2^-21 here); at 1e17 texels whole columns merged and
/// at 1e19 the column index overflowed i64. Shifts that matter are below the
/// pattern's size (at most 4096): the placement repeats every SIZE texels.
pub const MAX_SHIFT_TEXELS: f64 = (1u64 << 31) as f64;

/// The smallest area of a written piece, relative to `min(incr, E) * E`
/// where E is the largest plane coordinate of the polygon: 1e-13.
///
/// A piece of a cell is cut from the polygon by crossings computed in f64:
/// each of its points is off by a few ulps of E (about E * 2.2e-16 each), so
/// a piece whose true area is zero (the polygon touching a cell at a corner,
/// an edge running along a grid line a rounding error away from it) comes out
/// as a polygon at most `min(incr, E) * sqrt(2)` or so across with an area of
/// rounding noise, up to about `1.2e-15 * min(incr, E) * E`, of either sign;
/// written to world coordinates, such a piece can even come out reversed.
/// "Only pieces with positive area" has to mean "with more area than the
/// noise": 1e-13 is about 100 times above it, and what it can drop is
/// negligible: at most `1e-13 * incr * E` per boundary cell, and over the
/// about E/incr boundary cells of a polygon about 1e-13 of E², far below the
/// 1e-9 the tests ask of the areas' sum (a polygon needs an area above 1e-12
/// of its size² to have a plane at all: `plane::ZERO_AREA_REL`). The test
/// applies both to the piece in the plane and to the world polygon written
/// (its area along the polygon's normal), so that what is written has the
/// input's winding.
pub const MIN_PIECE_AREA_REL: f64 = 1e-13;

/// The floor of [`MIN_PIECE_AREA_REL`] never exceeds this fraction of the
/// polygon's own area: a sliver (area 1e-10 of its size², say) has real
/// pieces below the noise floor at its thin end, and dropping them would
/// break the areas' sum (1e-9 of the polygon's, `tests/stress/geometry.rs`).
/// At 1e-12 of the area per piece, the pieces dropped cost the sum at most
/// 1e-12 per boundary cell; pieces of noise above this lower floor can then
/// be written for such slivers, but never with the wrong winding.
pub const MIN_PIECE_AREA_OF_POLYGON: f64 = 1e-12;

/// A placement that cannot be laid over a polygon as a grid of cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridError {
    /// `incr` is below [`MIN_INCR_REL`] of the polygon's coordinates.
    TooFine {
        /// The texel side asked for, world units.
        incr: f64,
        /// The polygon's largest plane coordinate.
        extent: f64,
    },
    /// `horz` or `vert` exceeds [`MAX_SHIFT_TEXELS`] in magnitude.
    ShiftTooLarge {
        /// Which shift: `horz` or `vert`.
        name: &'static str,
        /// Its value, texels.
        shift: f64,
    },
}

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            GridError::TooFine { incr, extent } => write!(
                f,
                "pattern incr {incr:e} is too fine for a polygon with plane coordinates \
                 up to {extent:e}: it must be at least {:e} ({MIN_INCR_REL:e} of them)",
                MIN_INCR_REL * extent
            ),
            GridError::ShiftTooLarge { name, shift } => write!(
                f,
                "pattern {name} {shift:e} is too large: shifts are limited to \
                 {MAX_SHIFT_TEXELS} texels (the pattern repeats every SIZE texels; \
                 reduce it modulo the pattern's size)"
            ),
        }
    }
}

impl std::error::Error for GridError {}

impl Grid {
    /// The grid over plane points `p` (bounding box = the thesis's texture
    /// pattern limits). Fails, instead of hanging or overflowing, when the
    /// placement is finer or shifted further than f64 can index (see
    /// [`MIN_INCR_REL`] and [`MAX_SHIFT_TEXELS`]).
    pub fn new(p: &[DVec2], place: Placement) -> Result<Grid, GridError> {
        let (mut lo, mut hi) = (p[0], p[0]);
        for &q in p {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        for (name, shift) in [("horz", place.horz), ("vert", place.vert)] {
            if shift.is_nan() || shift.abs() > MAX_SHIFT_TEXELS {
                return Err(GridError::ShiftTooLarge { name, shift });
            }
        }
        let extent = lo.abs().max(hi.abs()).max_element();
        // Written so that a NaN incr fails both comparisons and is refused.
        let indexable = place.incr > 0.0 && place.incr >= MIN_INCR_REL * extent;
        if !indexable {
            return Err(GridError::TooFine {
                incr: place.incr,
                extent,
            });
        }
        let mut g = Grid {
            xmin: lo.x,
            ymin: lo.y,
            xmax: hi.x,
            ymax: hi.y,
            place,
            k0: 0,
            k1: 0,
            j0: 0,
            j1: 0,
        };
        g.k0 = g.col_of(g.xmin);
        g.k1 = g.col_of(g.xmax);
        if g.gx(g.k1) >= g.xmax && g.k1 > g.k0 {
            g.k1 -= 1;
        }
        g.j0 = g.row_of(g.ymin);
        g.j1 = g.row_of(g.ymax);
        if g.gy(g.j1) >= g.ymax && g.j1 > g.j0 {
            g.j1 -= 1;
        }
        Ok(g)
    }

    /// x of column line k: where docs/stream-format.md's u equals k. Computed from the
    /// integer index every time, never accumulated.
    #[inline]
    pub fn gx(&self, k: i64) -> f64 {
        self.xmin + ((k as f64) + self.place.horz) * self.place.incr
    }

    /// y of row line j: where v equals j.
    #[inline]
    pub fn gy(&self, j: i64) -> f64 {
        self.ymin + ((j as f64) + self.place.vert) * self.place.incr
    }

    /// The column k with `gx(k) <= x < gx(k+1)`.
    pub fn col_of(&self, x: f64) -> i64 {
        Self::line_at(
            x,
            (x - self.xmin) / self.place.incr - self.place.horz,
            |k| self.gx(k),
        )
    }

    /// The row j with `gy(j) <= y < gy(j+1)`.
    pub fn row_of(&self, y: f64) -> i64 {
        Self::line_at(
            y,
            (y - self.ymin) / self.place.incr - self.place.vert,
            |j| self.gy(j),
        )
    }

    /// The index k with `line(k) <= t < line(k+1)`: the floor of the estimate
    /// `guess`, corrected by the grid lines themselves, so that a coordinate
    /// lying exactly on a line (as computed by `line`) is always in the cell
    /// above it, whatever the division rounded to.
    fn line_at(t: f64, guess: f64, line: impl Fn(i64) -> f64) -> i64 {
        let mut k = guess.floor() as i64;
        while line(k) > t {
            k -= 1;
        }
        while line(k + 1) <= t {
            k += 1;
        }
        k
    }

    /// Number of cells of the bounding box.
    pub fn cells(&self) -> u64 {
        ((self.k1 - self.k0 + 1) as u64).saturating_mul((self.j1 - self.j0 + 1) as u64)
    }
}

/// The number of cells of the bounding box of a polygon of plane extent
/// `w x h` at `incr`, without building anything: what `--max-polygons` checks
/// before a polygon's cells are written.
pub fn estimate_cells(w: f64, h: f64, incr: f64) -> f64 {
    ((w / incr).floor() + 2.0) * ((h / incr).floor() + 2.0)
}

/// Receives the cells of a partition, row by row, columns ascending.
pub trait CellSink {
    /// Whether cell (k, j) is wanted at all (its texel is not transparent).
    /// Asked before any work is done for the cell.
    fn wants(&mut self, k: i64, j: i64) -> bool;
    /// One texture point polygon in world coordinates, counter-clockwise in
    /// the plane like the input. `full` when it is the whole cell square
    /// `[c(k,j), c(k+1,j), c(k+1,j+1), c(k,j+1)]`.
    /// `plane` holds the same vertices in plane coordinates.
    fn cell(&mut self, k: i64, j: i64, world: &[DVec3], plane: &[DVec2], full: bool);
}

/// Working space for partitions, reused from polygon to polygon so that a
/// stream of polygons allocates nothing per polygon once warmed up.
#[derive(Default)]
pub struct Partitioner {
    base: Vec<TVertex>,
    tmp: Vec<TVertex>,
    strip: Vec<TVertex>,
    cell_a: Vec<TVertex>,
    cell_b: Vec<TVertex>,
    pts: Vec<DVec2>,
    world: Vec<DVec3>,
    ranges: Vec<(i64, i64)>,
    segs: Vec<(DVec2, DVec2)>,
    rings: Vec<Vec<DVec2>>,
    run: Vec<TVertex>,
    /// Parts split off a piece that touched itself (`tidy`).
    parts: Vec<Part>,
    /// The edges that reach each row, and the ring a row is cut from
    /// (`reach`): for polygons of [`REACH_FROM_VERTICES`] or more.
    rows: Reach,
    row_ring: Vec<TVertex>,
    /// The same for the columns of a long strip, and of a long slab (a
    /// concave strip's run of boundary columns); the ring a slab or a cell
    /// is cut from.
    cols_reach: Reach,
    slab_reach: Reach,
    cell_ring: Vec<TVertex>,
}

impl Partitioner {
    /// A partitioner with empty scratch buffers (they grow to the largest
    /// polygon it sees and are reused).
    pub fn new() -> Self {
        Self::default()
    }

    /// Partitions `poly` by `grid`, handing every non-transparent cell with
    /// positive area to `sink`. `poly`'s ring should be simple: an input
    /// off its plane that its projection made cross itself is mended by
    /// [`simple_on_plane`] first, as polyfill3 does.
    pub fn run(&mut self, poly: &PlanePolygon, grid: &Grid, sink: &mut impl CellSink) {
        let frame = &poly.frame;
        let orig = &poly.points;
        self.base.clear();
        self.base.extend(tagged(orig));
        // Column line k's x, gx(k), and ex * gx(k): a corner is
        // row_base + ex * gx(k), the same bits as Frame::to_world gives.
        // Computed where used: a table of them for every column line took
        // 32 bytes a column, 1.5 GB for a strip 49 million texels long (a
        // hostile-input review).
        let column = |k: i64| {
            let x = grid.gx(k);
            (frame.ex * x, x)
        };
        // A convex polygon's strips and cells are single pieces without
        // bridges: the rebuild of `split_on_border` can be skipped.
        let convex = is_convex(orig);
        let extent = [grid.xmin, grid.xmax, grid.ymin, grid.ymax]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let incr = grid.place.incr;
        let min_area = (MIN_PIECE_AREA_REL * incr.min(extent) * extent)
            .min(MIN_PIECE_AREA_OF_POLYGON * signed_area(orig));
        let by_reach = orig.len() >= REACH_FROM_VERTICES;
        if by_reach {
            self.rows.start(&self.base, Axis::Y, |y| grid.row_of(y));
        }
        for j in grid.j0..=grid.j1 {
            let (ylo, yhi) = (grid.gy(j), grid.gy(j + 1));
            // The same strip from the vertices that reach the row.
            let ring = if by_reach {
                let band = ((j, j), (ylo, yhi));
                self.rows
                    .ring(band.0, band.1, &self.base, Axis::Y, &mut self.row_ring);
                &self.row_ring
            } else {
                &self.base
            };
            clip_band(
                ring,
                orig,
                Axis::Y,
                (ylo, yhi),
                (ylo, yhi),
                &mut self.tmp,
                &mut self.strip,
            );
            let n = self.strip.len();
            if n < 3 {
                continue;
            }
            // Boundary columns: those an input edge passes through.
            self.ranges.clear();
            self.segs.clear();
            let (mut sx0, mut sx1) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..n {
                let (s, e) = (self.strip[i], self.strip[(i + 1) % n]);
                sx0 = sx0.min(s.p.x);
                sx1 = sx1.max(s.p.x);
                if let Tag::Edge(_) = s.tag {
                    let (xa, xb) = (s.p.x.min(e.p.x), s.p.x.max(e.p.x));
                    let mut lo = grid.col_of(xa);
                    if grid.gx(lo) == xa {
                        lo -= 1;
                    }
                    let hi = grid.col_of(xb);
                    self.ranges.push((lo.max(grid.k0), hi.min(grid.k1)));
                    if s.p.y != e.p.y {
                        self.segs.push((s.p, e.p));
                    }
                }
            }
            self.ranges.sort_unstable();
            // A long strip's slabs and cells are cut from the vertices that
            // reach their columns.
            let strip_by_reach = n >= REACH_FROM_VERTICES;
            if strip_by_reach {
                self.cols_reach
                    .start(&self.strip, Axis::X, |x| grid.col_of(x));
            }
            let kstart = grid.col_of(sx0).max(grid.k0);
            let kend = grid.col_of(sx1).min(grid.k1);
            let rb_lo = frame.row_base(ylo);
            let rb_hi = frame.row_base(yhi);
            let ym = 0.5 * (ylo + yhi);
            let mut cursor = kstart;
            let mut r = 0;
            while cursor <= kend {
                // Next boundary range at or after the cursor, merged with overlaps.
                while r < self.ranges.len() && self.ranges[r].1 < cursor {
                    r += 1;
                }
                let (blo, mut bhi) = if r < self.ranges.len() {
                    self.ranges[r]
                } else {
                    (kend + 1, kend)
                };
                let blo = blo.max(cursor);
                // The run of whole cells before the boundary range.
                if blo > cursor {
                    let gap_end = blo.min(kend + 1);
                    let px = 0.5 * (grid.gx(cursor) + grid.gx(cursor + 1));
                    if inside_even_odd(&self.segs, DVec2::new(px, ym)) {
                        // Corners are shared along the run: each cell computes
                        // only its right-hand pair.
                        let (c0, xl) = column(cursor);
                        let (mut bl, mut tl, mut xl) = (rb_lo + c0, rb_hi + c0, xl);
                        for k in cursor..gap_end {
                            let (c1, xr) = column(k + 1);
                            let (br, tr) = (rb_lo + c1, rb_hi + c1);
                            if sink.wants(k, j) {
                                let pl = [
                                    DVec2::new(xl, ylo),
                                    DVec2::new(xr, ylo),
                                    DVec2::new(xr, yhi),
                                    DVec2::new(xl, yhi),
                                ];
                                sink.cell(k, j, &[bl, br, tr, tl], &pl, true);
                            }
                            (bl, tl, xl) = (br, tr, xr);
                        }
                    }
                    cursor = gap_end;
                    if cursor > kend {
                        break;
                    }
                }
                // Merge overlapping ranges into one boundary run.
                while r + 1 < self.ranges.len() && self.ranges[r + 1].0 <= bhi + 1 {
                    r += 1;
                    bhi = bhi.max(self.ranges[r].1);
                }
                r += 1;
                let bhi = bhi.min(kend);
                // For a concave polygon the strip can be long (many edges
                // cross it): cut out this run's slab first, so that each cell
                // clips only the few vertices of its own run. The slab's
                // bridges are undone by `split_on_border` below.
                let slab = !(convex || bhi == cursor);
                if slab {
                    let (x0, x1) = (grid.gx(cursor), grid.gx(bhi + 1));
                    let ring = if strip_by_reach {
                        self.cols_reach.ring(
                            (cursor, bhi),
                            (x0, x1),
                            &self.strip,
                            Axis::X,
                            &mut self.cell_ring,
                        );
                        &self.cell_ring
                    } else {
                        &self.strip
                    };
                    clip_band(
                        ring,
                        orig,
                        Axis::X,
                        (x0, x1),
                        (ylo, yhi),
                        &mut self.tmp,
                        &mut self.run,
                    );
                }
                let source = if slab { &self.run } else { &self.strip };
                // Cells of a long source, one by one: those of the strip from
                // its table (a slab took no band of it), those of a long slab
                // (a comb's teeth in one run) from a table of their own.
                let mut cell_reach = if !slab {
                    strip_by_reach.then_some(&mut self.cols_reach)
                } else if source.len() >= REACH_FROM_VERTICES {
                    self.slab_reach.start(source, Axis::X, |x| grid.col_of(x));
                    Some(&mut self.slab_reach)
                } else {
                    None
                };
                for k in cursor..=bhi {
                    if !sink.wants(k, j) {
                        continue;
                    }
                    let (xl, xr) = (grid.gx(k), grid.gx(k + 1));
                    let ring = match cell_reach.as_deref_mut() {
                        Some(reach) => {
                            reach.ring((k, k), (xl, xr), source, Axis::X, &mut self.cell_ring);
                            &self.cell_ring
                        }
                        None => source,
                    };
                    clip_band(
                        ring,
                        orig,
                        Axis::X,
                        (xl, xr),
                        (ylo, yhi),
                        &mut self.cell_a,
                        &mut self.cell_b,
                    );
                    if self.cell_b.len() < 3 {
                        continue;
                    }
                    // Rebuild the piece from its chains of input edges: no
                    // bridges, and a concave polygon's piece that falls apart
                    // gives one polygon per part.
                    self.pts.clear();
                    if !convex
                        && split_on_border(&self.cell_b, (xl, ylo, xr, yhi), &mut self.rings)
                        && rebuild_kept_the_area(&self.cell_b, &self.rings, min_area)
                    {
                        if self.rings.len() > 1 {
                            for ring in &mut self.rings {
                                drop_spikes(ring);
                                if ring.len() < 3 {
                                    continue;
                                }
                                self.world.clear();
                                self.world.extend(ring.iter().map(|&p| frame.to_world(p)));
                                let piece = (&mut self.world, &mut *ring);
                                if tidied_has_area(
                                    piece,
                                    &mut self.parts,
                                    (k, j),
                                    frame.normal,
                                    min_area,
                                    sink,
                                ) {
                                    sink.cell(k, j, &self.world, ring, false);
                                }
                            }
                            continue;
                        }
                        self.pts.extend_from_slice(&self.rings[0]);
                    } else {
                        self.pts.extend(self.cell_b.iter().map(|v| v.p));
                    }
                    drop_spikes(&mut self.pts);
                    if self.pts.len() < 3 {
                        continue;
                    }
                    // A clipped cell that is the whole square (an input edge
                    // along a grid line) is written as the canonical square.
                    let corners = [
                        DVec2::new(xl, ylo),
                        DVec2::new(xr, ylo),
                        DVec2::new(xr, yhi),
                        DVec2::new(xl, yhi),
                    ];
                    let full = self.pts.len() == 4
                        && (0..4).any(|r| (0..4).all(|i| self.pts[(i + r) % 4] == corners[i]));
                    self.world.clear();
                    if full {
                        let (c0, c1) = (column(k).0, column(k + 1).0);
                        self.world
                            .extend([rb_lo + c0, rb_lo + c1, rb_hi + c1, rb_hi + c0]);
                    } else {
                        self.world
                            .extend(self.pts.iter().map(|&p| frame.to_world(p)));
                        let piece = (&mut self.world, &mut self.pts);
                        if !tidied_has_area(
                            piece,
                            &mut self.parts,
                            (k, j),
                            frame.normal,
                            min_area,
                            sink,
                        ) {
                            continue;
                        }
                    }
                    if full {
                        self.pts.clear();
                        self.pts.extend(corners);
                    }
                    sink.cell(k, j, &self.world, &self.pts, full);
                }
                cursor = bhi + 1;
            }
        }
    }
}

/// The part of `input` between the lines `lo` and `hi` of `axis`, into
/// `out` (`tmp` takes the cut at `lo`): the two [`clip_tagged`] cuts that
/// a row's strip, a concave run's slab and a cell each take, in one place
/// so that all three cut alike.
fn clip_band(
    input: &[TVertex],
    orig: &[DVec2],
    axis: Axis,
    (lo, hi): (f64, f64),
    clamp: (f64, f64),
    tmp: &mut Vec<TVertex>,
    out: &mut Vec<TVertex>,
) {
    clip_tagged(input, orig, axis, lo, true, clamp, tmp);
    clip_tagged(tmp, orig, axis, hi, false, clamp, out);
}

/// Whether the parts `split_on_border` rebuilt (`rings`) cover the
/// area of the clipped piece they were rebuilt from (`q`).
///
/// Sutherland–Hodgman's ring has the piece's area whatever its bridges
/// and spikes (they have none); the rebuild only decides how the ring
/// falls apart, by the order of its chains' entries and exits along the
/// cell's border. Each of those points is a crossing rounded on its own,
/// so when a polygon vertex lies within rounding of the border (a notch's
/// apex 2e-16 inside a cell, as integer input rotated by 90° or 270°
/// gives), the two crossings of its edges can coincide or come out in the
/// wrong order. The chain is then a spike of no area, and whether the
/// walk from its exit to its entry is nothing or the whole border cannot
/// be told from the points: the rebuild took nothing and lost the whole
/// cell. A rebuild that does not keep the area (beyond `min_area`, the
/// rounding noise of [`MIN_PIECE_AREA_REL`]) is refused, and the piece is
/// written as the clipped ring itself, spike included, which has the
/// right area and winding.
fn rebuild_kept_the_area(q: &[TVertex], rings: &[Vec<DVec2>], min_area: f64) -> bool {
    let o = q[0].p;
    let whole = 0.5
        * q.windows(2)
            .skip(1)
            .map(|w| (w[0].p - o).perp_dot(w[1].p - o))
            .sum::<f64>();
    let parts: f64 = rings.iter().map(|r| signed_area(r)).sum();
    (whole - parts).abs() <= min_area
}

/// Whether a counter-clockwise polygon turns left (or goes straight) at
/// every vertex. Repeated vertices are skipped.
fn is_convex(p: &[DVec2]) -> bool {
    let n = p.len();
    let mut prev: Option<DVec2> = None;
    let mut first: Option<DVec2> = None;
    // Walk the edges twice around so the last turns, back to the first edge, count too.
    for i in 0..=n {
        let d = p[(i + 1) % n] - p[i % n];
        if d == DVec2::ZERO {
            continue;
        }
        if let Some(q) = prev {
            if q.perp_dot(d) < 0.0 {
                return false;
            }
        }
        first.get_or_insert(d);
        prev = Some(d);
    }
    match (prev, first) {
        (Some(a), Some(b)) => a.perp_dot(b) >= 0.0,
        _ => true,
    }
}

/// Makes a partly covered piece of cell `kj` simple as readers judge it
/// ([`simple_in_world`]), hands on to `sink` the parts split off it that
/// have area ([`has_area`]), and says whether the piece itself is to be
/// written: not noise, and with area. A piece left tangled is written as it
/// is: dropped, its area would be lost without a word, where the reader
/// names the record it refuses.
fn tidied_has_area(
    (world, plane): (&mut Vec<DVec3>, &mut Vec<DVec2>),
    parts: &mut Vec<Part>,
    (k, j): (i64, i64),
    normal: DVec3,
    min_area: f64,
    sink: &mut impl CellSink,
) -> bool {
    let made = simple_in_world(world, plane, parts);
    for (world, plane) in parts.drain(..) {
        if has_area(&plane, &world, normal, min_area) {
            sink.cell(k, j, &world, &plane, false);
        }
    }
    made != WorldPiece::Noise && has_area(plane, world, normal, min_area)
}

/// Whether a piece has more area than rounding noise ([`MIN_PIECE_AREA_REL`],
/// `min_area` is its absolute value for this grid): in the plane, and as the
/// world polygon written, along the polygon's `normal` (so that it keeps the
/// input's winding).
fn has_area(plane: &[DVec2], world: &[DVec3], normal: DVec3, min_area: f64) -> bool {
    plane.len() >= 3
        && signed_area(plane) > min_area
        && newell_normal(world, world[0]).dot(normal) > 2.0 * min_area
}

/// Even-odd test of `p` against the non-horizontal segments of a polygon.
fn inside_even_odd(segs: &[(DVec2, DVec2)], p: DVec2) -> bool {
    let mut inside = false;
    for &(a, b) in segs {
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > p.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// `--compat thesis`: the thesis's own loop (Fig. 4.7, App. E), for checking
/// Table 5.1. Grid lines are accumulated (`xincr += incr`) from the lower-left
/// of the bounding box with vertex 0 at the origin, the loops run while
/// `xmin + xincr <= xmax` (inclusive, so a column and a row beyond the far
/// edges are visited), texel indices start at `(SIZE - horz) % SIZE` with
/// C's remainder (taken modulo SIZE here where C would index out of bounds),
/// and every cell the closed polygon reaches is emitted, degenerate ones
/// included. `k`, `j` given to the sink are the texel column and row.
pub fn thesis_partition(
    poly: &PlanePolygon,
    incr: f64,
    horz: i64,
    vert: i64,
    pattern_size: i64,
    sink: &mut impl CellSink,
) {
    let o = poly.points[0];
    let p: Vec<DVec2> = poly.points.iter().map(|&q| q - o).collect();
    let (mut lo, mut hi) = (p[0], p[0]);
    for &q in &p {
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let s = pattern_size;
    let i_begin = ((s - vert) % s).rem_euclid(s);
    let j_begin = ((s - horz) % s).rem_euclid(s);
    let (mut out, mut scratch, mut world, mut plane) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut i = i_begin;
    let mut yincr = 0.0;
    while lo.y + yincr <= hi.y {
        let mut xincr = 0.0;
        let mut jj = j_begin;
        while lo.x + xincr <= hi.x {
            if sink.wants(jj, i) {
                let bx = (
                    lo.x + xincr,
                    lo.y + yincr,
                    lo.x + xincr + incr,
                    lo.y + yincr + incr,
                );
                clip_closed(&p, bx, &mut out, &mut scratch);
                if !out.is_empty() {
                    world.clear();
                    plane.clear();
                    plane.extend(out.iter().map(|&q| q + o));
                    while plane.len() < 3 {
                        plane.push(*plane.last().expect("non-empty"));
                    }
                    world.extend(plane.iter().map(|&q| poly.frame.to_world(q)));
                    sink.cell(jj, i, &world, &plane, false);
                }
            }
            jj += 1;
            xincr += incr;
            if jj == s {
                jj = 0;
            }
        }
        i += 1;
        if i == s {
            i = 0;
        }
        yincr += incr;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::plane::map_to_plane;

    /// Collects every cell.
    #[derive(Default)]
    struct Collect {
        cells: Vec<(i64, i64, Vec<DVec3>, bool)>,
    }
    impl CellSink for Collect {
        fn wants(&mut self, _: i64, _: i64) -> bool {
            true
        }
        fn cell(&mut self, k: i64, j: i64, w: &[DVec3], _: &[DVec2], full: bool) {
            self.cells.push((k, j, w.to_vec(), full));
        }
    }

    fn run(v: &[DVec3], place: Placement) -> (PlanePolygon, Grid, Collect) {
        let poly = map_to_plane(v, 0.0, 1e-9).unwrap();
        let grid = Grid::new(&poly.points, place).unwrap();
        let mut c = Collect::default();
        Partitioner::new().run(&poly, &grid, &mut c);
        (poly, grid, c)
    }

    fn area3(w: &[DVec3]) -> f64 {
        crate::geom::plane::newell_normal(w, w[0]).length() / 2.0
    }

    fn p3(v: &[[f64; 3]]) -> Vec<DVec3> {
        v.iter().map(|a| DVec3::from_array(*a)).collect()
    }

    #[test]
    fn the_thesis_plain_gives_1280_squares() {
        let plain = p3(&[
            [-500.0, 0.0, 0.0],
            [500.0, 0.0, 0.0],
            [500.0, 0.0, -800.0],
            [-500.0, 0.0, -800.0],
        ]);
        let place = Placement {
            incr: 25.0,
            horz: 0.0,
            vert: 0.0,
        };
        let (_, grid, c) = run(&plain, place);
        assert_eq!(c.cells.len(), 1280);
        assert_eq!(grid.cells(), 1280);
        assert!(c.cells.iter().all(|x| x.3 && x.2.len() == 4));
        // Texel (0, 0) is at the lower-left corner of the plane's bounding box.
        assert_eq!((c.cells[0].0, c.cells[0].1), (0, 0));
    }

    #[test]
    fn the_thesis_loop_gives_1353_on_the_plain() {
        let plain = p3(&[
            [-500.0, 0.0, 0.0],
            [500.0, 0.0, 0.0],
            [500.0, 0.0, -800.0],
            [-500.0, 0.0, -800.0],
        ]);
        let poly = map_to_plane(&plain, 0.0, 1e-9).unwrap();
        let mut c = Collect::default();
        thesis_partition(&poly, 25.0, 0, 0, 16, &mut c);
        assert_eq!(c.cells.len(), 1353);
        let with_area = c.cells.iter().filter(|x| area3(&x.2) > 0.0).count();
        assert_eq!(with_area, 1280);
    }

    #[test]
    fn concave_polygon_areas_sum_and_cells_share_corners() {
        // A U shape whose arms cross the same strips.
        let u = p3(&[
            [0.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [3.0, 3.0, 0.0],
            [2.3, 3.0, 0.0],
            [2.3, 0.7, 0.0],
            [0.6, 0.7, 0.0],
            [0.6, 3.0, 0.0],
            [0.0, 3.0, 0.0],
        ]);
        let place = Placement {
            incr: 0.4,
            horz: 0.25,
            vert: -0.5,
        };
        let (poly, _, c) = run(&u, place);
        let total: f64 = c.cells.iter().map(|x| area3(&x.2)).sum();
        assert!(
            (total - poly.area).abs() < 1e-12 * poly.area,
            "{total} {}",
            poly.area
        );
        // Every vertex of every cell that lies strictly inside the polygon's
        // box is also a vertex of a neighbouring cell, bit for bit.
        use std::collections::HashMap;
        let mut seen: HashMap<[u64; 3], usize> = HashMap::new();
        for (_, _, w, _) in &c.cells {
            for p in w {
                *seen.entry(p.to_array().map(f64::to_bits)).or_default() += 1;
            }
        }
        let shared = seen.values().filter(|&&n| n >= 2).count();
        assert!(shared * 2 > seen.len(), "{shared} of {}", seen.len());
    }
}
#[cfg(test)]
mod table51 {
    //! Table 5.1 of the thesis, through `--compat thesis`: the four faces of
    //! App. C's pyramid at incr 1..10 with a fully opaque pattern.
    use super::*;
    use crate::geom::plane::map_to_plane;

    struct Count(usize);
    impl CellSink for Count {
        fn wants(&mut self, _: i64, _: i64) -> bool {
            true
        }
        fn cell(&mut self, _: i64, _: i64, _: &[DVec3], _: &[DVec2], _: bool) {
            self.0 += 1;
        }
    }

    /// The four faces of the thesis's App. C pyramid (demo2.c), counter-
    /// clockwise seen from outside: the geometry of Table 5.1, read from the
    /// fixture the command-line tests and the benchmark use too.
    fn app_c_pyramid() -> Vec<[[f64; 3]; 3]> {
        include_str!("../../fixtures/scenes/demo2-faces.json")
            .lines()
            .map(|line| {
                let record: serde_json::Value = serde_json::from_str(line).unwrap();
                serde_json::from_value(record["vertices"].clone()).unwrap()
            })
            .collect()
    }
    const THESIS: [usize; 10] = [70632, 17936, 8092, 4616, 3008, 2116, 1572, 1224, 984, 808];
    /// What the thesis loop gives here in double precision (see the bench notes:
    /// one cell per face that only touches the triangle at a point comes and
    /// goes with the rounding of the mapping).
    const COMPAT: [usize; 10] = [70628, 17932, 8088, 4620, 3004, 2112, 1568, 1220, 984, 804];
    /// Cells with area (no degenerate ones).
    const EXACT: [usize; 10] = [70624, 17928, 8088, 4616, 3000, 2112, 1568, 1216, 984, 800];

    #[test]
    fn table_5_1_within_one_touching_cell_per_face() {
        for incr in 1..=10usize {
            let (mut t, mut f) = (Count(0), Count(0));
            for face in &app_c_pyramid() {
                let v: Vec<DVec3> = face.iter().map(|a| DVec3::from_array(*a)).collect();
                let poly = map_to_plane(&v, 0.0, 1e-9).unwrap();
                thesis_partition(&poly, incr as f64, -5, 0, 64, &mut t);
                let place = Placement {
                    incr: incr as f64,
                    horz: -5.0,
                    vert: 0.0,
                };
                Partitioner::new().run(&poly, &Grid::new(&poly.points, place).unwrap(), &mut f);
            }
            assert_eq!(t.0, COMPAT[incr - 1], "incr {incr}");
            assert_eq!(f.0, EXACT[incr - 1], "incr {incr}");
            assert!(t.0.abs_diff(THESIS[incr - 1]) <= 4, "incr {incr}");
        }
    }
}

#[cfg(test)]
mod props;

#[cfg(test)]
mod differential;
