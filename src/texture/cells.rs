//! The exact box filter for crisp patterns: a textured fragment cut into its
//! texel cells.
//!
//! A pattern is piecewise constant over texel squares in the polygon's plane
//! (docs/stream-format.md; the thesis's texture point polygons). The box-filtered pixel is
//! therefore the sum, over the cells the pixel's visible part overlaps, of
//! the cell's colour times the exact area of (fragment ∩ cell) on the screen:
//! what `polyfill3 | scene-render --aa exact` draws, without writing one
//! polygon per texel. Under the projective map of [`super::map`] a cell is a
//! convex quadrilateral on the screen bounded by the lines `u = k`, `u = k+1`,
//! `v = j`, `v = j+1`: a convex fragment's texel rows are its slices
//! between the lines `v = j`, and a row's cells the slices of the row's
//! strip between the lines `u = k` (`crate::geom::slice`). Each piece then
//! takes part in the exact visibility of `raster::coverage` as a fragment
//! of its own with the texel's colour, and a transparent texel's piece is
//! simply absent, leaving its area to whatever lies behind.
//!
//! Minification: the cut stays exact up to [`MAX_EXACT_CELLS`] cells met by
//! the fragment (estimated from its image in texel space, not its box;
//! [`MAX_SWEPT_CELLS`] where its pieces are kept for the visibility sweep).
//! Beyond that (a pixel over millions of texels, at the far edge of a
//! plane running to its horizon) the cost would grow without bound, so
//! the fragment takes one colour: the EWA filter (`super::ewa`, on the MIP
//! pyramid) at its centroid with the pixel's footprint there. That is an
//! estimate, not the box integral, and it is counted
//! ([`Scratch::estimated`]) so the tools report it, with a bound. Beyond
//! the plane's horizon, where the map has no footprint, the fragment is
//! cut into [`FALLBACK_SIDE`]² sub-squares of the pixel instead, each
//! taking the texel at its centre (also counted).
//!
//! A fragment of an always-opaque texture that meets more than one cell is
//! not cut before its visibility is known: `raster::visible` sweeps it
//! whole, and [`integrate`] cuts only the part of it that shows, summing
//! its pieces ([`Sink::Sum`]) as they are cut. A piece needs no visibility
//! work of its own, since the part it was cut from is the part that shows.

use super::PolyTexture;
use crate::geom::polygon::area2;
use crate::geom::polygon::clip_axis;
use crate::geom::polygon::AREA_EPS;
use crate::geom::slice::Slicer;
use glam::DVec2;

/// Most texel cells a fragment may meet and still be cut exactly (its area
/// in texel space plus twice its extents, `CellBox::cells_met`). The work
/// is one slice per texel row the fragment spans plus one per cell a row's
/// strip meets (`crate::geom::slice`), each summed as it is cut
/// ([`integrate`]).
///
/// Why 65,536: on the photographed plane of `bench/texture.sh` (640x480,
/// texels of 0.05 units, the far edge 400 units off) the fragments of the
/// two rows over the far edge meet 16,397 to 34,125 cells. At 16,384 (until
/// 2026-11-27) those 1,056 fragments took the EWA estimate, and 10 pixels
/// the reference is certain of were up to 22 codes off it; at 65,536 none
/// is estimated and the default equals the reference wherever the
/// reference is certain (test `a_pattern_minified_150_times_is_integrated_exactly`
/// covers the range), for about 0.8 s more on one core (paired runs of
/// that scene on one thread: 1.28-1.46 s before, 2.09-2.16 s after;
/// `bench/RESULTS-texture.md`). The one-texel checker
/// ground of `scene::horizon_tests` still estimates the row over its far
/// edge, about two million cells a pixel.
pub const MAX_EXACT_CELLS: i64 = 65536;

/// [`MAX_EXACT_CELLS`] for a fragment whose pieces are kept for the
/// visibility sweep ([`Sink::Pieces`]): a pattern with transparent texels,
/// whose pieces each hide or let through what lies behind, so each is
/// stored (about 100 bytes) until its pixel is swept. A plane of
/// `fixtures/patterns/bkgrnd.pat` (9% transparent) at 0.05 units a texel,
/// minified to a far edge 400 units off at 640x480, took 471 MB and 2.6 s
/// at 16,384 and 935 MB and 5.6 s at 65,536; it keeps 16,384.
pub const MAX_SWEPT_CELLS: i64 = 16384;

/// Sub-squares per pixel side in the minification fallback (16 per pixel).
pub const FALLBACK_SIDE: u32 = 4;

/// How a fragment splits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Split {
    /// The fragment lies in one texel cell: its colour, or `None` when the
    /// texel is transparent (the fragment is absent).
    Whole(Option<[f64; 3]>),
    /// The fragment was cut; the opaque pieces were appended to the outputs.
    Pieces,
    /// The fragment was not cut ([`split_or_defer`]): it can meet several
    /// cells, and the visibility sweep cuts only the part of it that shows
    /// ([`integrate`]).
    Deferred,
}

/// One opaque piece: `len` vertices from `start` in the vertex arena.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Index of its first vertex in the `verts` arena of [`split`].
    pub start: u32,
    /// Number of vertices: a convex counter-clockwise polygon in screen
    /// pixels, y up.
    pub len: u32,
    /// Linear-light colour of the texel cell it lies in (boundary conditions
    /// and composition applied).
    pub color: [f64; 3],
}

/// A factor per piece, per channel, that its colour is multiplied by:
/// smooth lighting's ([`Sink::SumLit`]).
pub type PieceFactor<'a> = &'a dyn Fn(&[DVec2]) -> [f64; 3];

/// Where [`split`] puts what it cuts.
pub enum Sink<'a> {
    /// Each opaque piece, for the exact visibility of `raster::coverage`:
    /// vertices into the arena, pieces into the list.
    Pieces(&'a mut Vec<DVec2>, &'a mut Vec<Piece>),
    /// Only the area-weighted sum of the pieces' colours ([`integrate`]):
    /// for a visible part of a fragment, whose pieces need no visibility
    /// work of their own.
    Sum(&'a mut Summed),
    /// [`Sink::Sum`] with each piece's colour times a factor for that
    /// piece: smooth lighting's, at the piece's area centroid.
    SumLit(&'a mut Summed, PieceFactor<'a>),
}

/// The pieces of a fragment summed ([`Sink::Sum`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summed {
    /// Twice the area of each piece times its colour, summed.
    pub weighted: [f64; 3],
    /// Twice the pieces' total area.
    pub area2: f64,
}

impl Summed {
    /// The pieces' mean colour, or `None` when they have no area.
    pub fn mean(&self) -> Option<[f64; 3]> {
        (self.area2 > 0.0).then(|| self.weighted.map(|w| w / self.area2))
    }
}

impl Sink<'_> {
    /// Takes one opaque piece `cell`, of twice the area `area2`.
    fn take(&mut self, cell: &[DVec2], area2: f64, color: [f64; 3]) {
        match self {
            Sink::Pieces(verts, pieces) => push_piece(cell, color, verts, pieces),
            Sink::Sum(sum) => {
                for (w, c) in sum.weighted.iter_mut().zip(color) {
                    *w += area2 * c;
                }
                sum.area2 += area2;
            }
            Sink::SumLit(sum, factor) => {
                let k = factor(cell);
                for ch in 0..3 {
                    sum.weighted[ch] += area2 * (color[ch] * k[ch]);
                }
                sum.area2 += area2;
            }
        }
    }
}

/// Reusable buffers, and the count of estimated fragments.
#[derive(Default)]
pub struct Scratch {
    /// Fragments [`split`] did not integrate exactly: beyond
    /// [`MAX_EXACT_CELLS`] (the EWA mean) or beyond the plane's horizon
    /// (sub-square samples). Counted so the tools can say so rather than
    /// be silent (issue 15).
    pub estimated: u64,
    rows: Slicer,
    cols: Slicer,
    a: Vec<DVec2>,
    strip: Vec<DVec2>,
    b: Vec<DVec2>,
    cell: Vec<DVec2>,
}

/// Least number of texel cells a fragment must be able to meet
/// (`CellBox::cells_met`) for [`split_or_defer`] to leave it to the
/// visibility sweep: two, so every fragment the texture cuts at all.
///
/// Why defer: cut first, the pieces of two polygons in one pixel cost each
/// other a convex subtraction per pair in the sweep, so a pixel over k
/// cells of each costs O(k²): the two photographed globes at 100x75 took
/// 111 s, demo 2 at 8x8 34 s (`bench/RESULTS-thumbnails.md` has them
/// deferred). Deferred, a fragment costs one visibility check and one cut,
/// and its cells are cut once, from the part of it that shows. The two
/// routes add the same areas in another order; on the unlit scenes of that
/// benchmark the images are bit for bit the same but for one f32 value.
///
/// Why not one cell: such a fragment keeps its texel's colour as given;
/// its mean over its visible part, `(a·c)/a`, could differ from `c` in the
/// last bit.
pub const DEFER_MIN_CELLS: f64 = 2.0;

/// Cuts the convex counter-clockwise fragment `frag` of pixel `(px, py)` of a
/// polygon textured by `tex`, its pieces into `out`.
pub fn split(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    out: &mut Sink,
    s: &mut Scratch,
) -> Split {
    split_with(frag, px, py, tex, out, s, false)
}

/// [`split`], but a fragment of an always-opaque texture that can meet
/// [`DEFER_MIN_CELLS`] cells or more is not cut: [`Split::Deferred`]. Its
/// cell box serves both decisions, computed once.
pub fn split_or_defer(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    out: &mut Sink,
    s: &mut Scratch,
) -> Split {
    split_with(frag, px, py, tex, out, s, tex.always_opaque())
}

fn split_with(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    out: &mut Sink,
    s: &mut Scratch,
    defer: bool,
) -> Split {
    let Some(b) = cell_box(frag, tex) else {
        return Split::Whole(None);
    };
    // The magnification fast path: inside one cell the fragment is the
    // piece (`--no-skip magnify` cuts it anyway, for the benchmark).
    if b.k0 == b.k1 && b.j0 == b.j1 && !b.far && tex.skips.magnify {
        return Split::Whole(tex.texel(b.k0, b.j0));
    }
    if defer && b.cells_met() >= DEFER_MIN_CELLS {
        return Split::Deferred;
    }
    let most = match out {
        Sink::Pieces(..) => MAX_SWEPT_CELLS,
        Sink::Sum(_) | Sink::SumLit(..) => MAX_EXACT_CELLS,
    };
    if b.cells_met() > most as f64 {
        s.estimated += 1;
        let c = crate::geom::polygon::vertex_mean(frag);
        if let Some(fp) = tex.map.footprint(c.x, c.y) {
            let rgba = tex.sample(super::filter::Filter::Ewa, &fp);
            return Split::Whole(super::filter::unpremultiply(rgba));
        }
        sub_squares(frag, px, py, tex, out, s);
    } else if !cut(frag, b, tex, out, s) {
        s.estimated += 1;
        sub_squares(frag, px, py, tex, out, s);
    }
    Split::Pieces
}

/// The box-filtered colour of the union of the disjoint convex `pieces` of
/// pixel `(px, py)`: each piece [`split`] into its cells and summed, a piece
/// in one cell taking that cell's texel whole (a lone such piece, its colour
/// as given). `None` where they hold no
/// opaque area. `tex` must be always opaque: a transparent texel's area
/// would show what lies behind it, which one colour cannot say.
///
/// This is the integral the visibility sweep takes over the visible part of
/// a fragment swept whole (`raster::visible`); each piece's own cut is
/// exact up to [`MAX_EXACT_CELLS`], like any fragment's. With `factor`
/// (smooth lighting), each cell's piece is weighted by it
/// ([`Sink::SumLit`]): the exact integral of texel times factor wherever
/// the factor is affine on the screen.
pub fn integrate<'a>(
    pieces: impl IntoIterator<Item = &'a [DVec2]>,
    px: u32,
    py: u32,
    tex: &PolyTexture,
    factor: Option<PieceFactor>,
    s: &mut Scratch,
) -> Option<[f64; 3]> {
    let (mut sum, mut count, mut whole) = (Summed::default(), 0, None);
    for piece in pieces {
        count += 1;
        let mut sink = match factor {
            Some(f) => Sink::SumLit(&mut sum, f),
            None => Sink::Sum(&mut sum),
        };
        whole = match split(piece, px, py, tex, &mut sink, s) {
            Split::Whole(Some(c)) => {
                sink.take(piece, area2(piece), c);
                Some((c, piece))
            }
            _ => None,
        };
    }
    // One piece that `split` gives one colour (one cell, or estimated)
    // takes that colour as given: its mean, `(a·c)/a`, could differ from
    // `c` in the last bit.
    match (count, whole, factor) {
        (1, Some((c, _)), None) => Some(c),
        (1, Some((c, piece)), Some(f)) => {
            let k = f(piece);
            Some([c[0] * k[0], c[1] * k[1], c[2] * k[2]])
        }
        _ => sum.mean(),
    }
}

/// The texel cells `k0..=k1` x `j0..=j1` a convex fragment can overlap.
#[derive(Clone, Copy)]
struct CellBox {
    k0: i64,
    k1: i64,
    j0: i64,
    j1: i64,
    /// Area of the fragment's image in texel space (texel squares).
    area: f64,
    /// Whether the image reaches beyond [`super::filter::FAR_TEXELS`]
    /// texels: its cell indices (saturated casts) and their differences
    /// mean nothing there, and it is not cut.
    far: bool,
}

impl CellBox {
    /// How many cells the fragment can meet: its image in texel space is
    /// convex (the map is projective with `D > 0`), and a convex set of
    /// area `A` spanning `du` x `dv` meets at most about `A + du + dv + 1`
    /// unit squares (a row's strip meets its own width plus the cells its
    /// two sides cross). Not the box: a thin diagonal footprint towards the
    /// horizon meets 6 to 160 times fewer cells than its box holds (issue
    /// 15), and [`cut`] visits only the cells each strip meets.
    ///
    /// Infinite for a [`CellBox::far`] image, which therefore takes the
    /// EWA estimate: counted in `i64`, `k1 - k0` of an image reaching 1e20
    /// wrapped to a small count and the cut ran through its 1e20 columns.
    fn cells_met(&self) -> f64 {
        if self.far {
            return f64::INFINITY;
        }
        let (du, dv) = (
            (self.k1 - self.k0 + 1) as f64,
            (self.j1 - self.j0 + 1) as f64,
        );
        (self.area + 2.0 * (du + dv) + 1.0).min(du * dv)
    }
}

/// The box of cells under a convex fragment: the (u, v) of its vertices
/// bound it, since the map is projective with `D > 0` (lines stay lines).
fn cell_box(frag: &[DVec2], tex: &PolyTexture) -> Option<CellBox> {
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    // The shoelace sum over the images of the vertices, each mapped once.
    let (mut twice_area, mut ends) = (0.0, None::<(DVec2, DVec2)>);
    for p in frag {
        let t = tex.map.uv(p.x, p.y);
        lo = lo.min(t);
        hi = hi.max(t);
        ends = match ends {
            Some((first, prev)) => {
                twice_area += prev.perp_dot(t);
                Some((first, t))
            }
            None => Some((t, t)),
        };
    }
    if let Some((first, last)) = ends {
        twice_area += last.perp_dot(first);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let (k0, j0) = (lo.x.floor() as i64, lo.y.floor() as i64);
    // The casts saturate far out (a far box's indices mean nothing), so
    // `- 1` must too: at i64::MIN it overflowed, a panic where overflow is
    // checked (the test profile).
    Some(CellBox {
        k0,
        k1: (hi.x.ceil() as i64).saturating_sub(1).max(k0),
        j0,
        j1: (hi.y.ceil() as i64).saturating_sub(1).max(j0),
        area: 0.5 * twice_area.abs(),
        far: lo.min(-hi).min_element() < -super::filter::FAR_TEXELS,
    })
}

/// The texel cell `(k, j)` holding the whole screen rectangle of pixels
/// `xa..xb` of row `py`, if there is one: by the rule of `cell_box` on
/// the rectangle's corners (the magnification fast path of a run of full
/// pixels, `raster::coverage`).
pub fn single_cell(tex: &PolyTexture, xa: u32, xb: u32, py: u32) -> Option<(i64, i64)> {
    let (x0, x1, y0, y1) = (xa as f64, xb as f64, py as f64, py as f64 + 1.0);
    let corners = [
        DVec2::new(x0, y0),
        DVec2::new(x1, y0),
        DVec2::new(x1, y1),
        DVec2::new(x0, y1),
    ];
    let b = cell_box(&corners, tex)?;
    (b.k0 == b.k1 && b.j0 == b.j1 && !b.far).then_some((b.k0, b.j0))
}

/// Whether the transparent-run skip applies to `tex`: a transparent texel
/// must give an absent piece (not the decal compositions, which fill it) and
/// every cell must be a pattern texel at column `k mod W`, row
/// `j mod H` (repeat on both axes, the default; the other boundary
/// conditions map cells otherwise and are cut without the skip).
fn runs_apply(tex: &PolyTexture) -> bool {
    use super::boundary::Boundary;
    tex.skips.transparent
        && tex.texels.has_transparency()
        && !tex.compose.fills_transparent()
        && tex.bounds.u == Boundary::Repeat
        && tex.bounds.v == Boundary::Repeat
}

/// The exact cut of a fragment into the cells of its box: its texel rows
/// are its slices along the lines `v = j`, and a row's cells the slices of
/// the row's strip along `u = k` ([`crate::geom::slice`]), each chord
/// computed once. `false` when the fragment cannot be sliced (the map's
/// denominator not positive at a vertex: beyond the horizon).
///
/// With a transparent pattern ([`runs_apply`]) the texel rows' opaque runs
/// ([`super::skip::OpaqueRuns`]) skip work that gives no piece: a row with
/// no opaque texel in the box's columns is not sliced at all, and within a
/// strip only the opaque runs of its columns are visited. The cells skipped
/// are exactly those whose texel lookup gives `None`, and a slice does not
/// depend on which slices came before it, so the pieces (and their order)
/// are the same as without the skip.
fn cut(frag: &[DVec2], b: CellBox, tex: &PolyTexture, out: &mut Sink, s: &mut Scratch) -> bool {
    let m = &tex.map;
    let CellBox { k0, k1, j0, j1, .. } = b;
    let runs = runs_apply(tex).then(|| tex.texels.runs());
    let height = tex.texels.height() as i64;
    if s.rows.load(frag, m.v, m.d).is_none() {
        return false;
    }
    let rows = (j0..=j1).filter(|&j| match runs {
        Some(runs) => runs.any(j.rem_euclid(height) as u32, k0, k1),
        None => true,
    });
    let cols = &mut s.cols;
    s.rows.slices(rows, |j, strip| {
        // The strip's own columns: a thin diagonal footprint has a box of
        // cells far larger than the cells it meets.
        let Some((ulo, uhi)) = cols.load(strip, m.u, m.d) else {
            return;
        };
        let sk0 = (ulo.floor() as i64).clamp(k0, k1);
        let sk1 = (uhi.ceil() as i64 - 1).clamp(sk0, k1);
        let mut take = |k: i64, cell: &[DVec2]| {
            let Some(color) = tex.texel(k, j) else {
                return;
            };
            let a2 = area2(cell);
            if a2 > 2.0 * AREA_EPS {
                out.take(cell, a2, color);
            }
        };
        match runs {
            Some(runs) => {
                let row = j.rem_euclid(height) as u32;
                cols.slices(
                    runs.spans(row, sk0, sk1).flat_map(|(a, b)| a..=b),
                    &mut take,
                );
            }
            None => cols.slices(sk0..=sk1, &mut take),
        }
    });
    true
}

/// Appends one opaque piece, its vertices into the arena.
fn push_piece(cell: &[DVec2], color: [f64; 3], verts: &mut Vec<DVec2>, pieces: &mut Vec<Piece>) {
    pieces.push(Piece {
        start: verts.len() as u32,
        len: cell.len() as u32,
        color,
    });
    verts.extend_from_slice(cell);
}

/// Beyond the horizon: [`FALLBACK_SIDE`]² sub-squares of the pixel (clipped
/// to the fragment, exact area), each given the texel at its vertex
/// centroid, which lies inside the fragment.
fn sub_squares(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    out: &mut Sink,
    s: &mut Scratch,
) {
    let n = FALLBACK_SIDE;
    let step = 1.0 / n as f64;
    for sy in 0..n {
        let (y0, y1) = (
            py as f64 + sy as f64 * step,
            py as f64 + (sy + 1) as f64 * step,
        );
        s.a.clear();
        clip_axis(frag, 1, y0, true, &mut s.a);
        s.strip.clear();
        clip_axis(&s.a, 1, y1, false, &mut s.strip);
        if s.strip.len() < 3 {
            continue;
        }
        for sx in 0..n {
            let (x0, x1) = (
                px as f64 + sx as f64 * step,
                px as f64 + (sx + 1) as f64 * step,
            );
            s.b.clear();
            clip_axis(&s.strip, 0, x0, true, &mut s.b);
            s.cell.clear();
            clip_axis(&s.b, 0, x1, false, &mut s.cell);
            if s.cell.len() < 3 {
                continue;
            }
            let a2 = area2(&s.cell);
            if a2 <= 2.0 * AREA_EPS {
                continue;
            }
            let c = crate::geom::polygon::vertex_mean(&s.cell);
            let t = tex.map.uv(c.x, c.y);
            let (u, v) = tex.near_period(0, t.x, t.y, 1.0);
            let Some(color) = tex.texel(u.floor() as i64, v.floor() as i64) else {
                continue;
            };
            out.take(&s.cell, a2, color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::{srgb_to_linear_f64, Rgb8};
    use crate::geom::polygon::{clip_line, pixel_square};
    use crate::pat::TRANSPARENT;
    use crate::texture::filter::tests::{pattern, placed};
    use crate::texture::filter::Filter;
    use proptest::prelude::*;

    /// `split` of pixel (px, py) of `tex`, with its pieces' vertices.
    fn pieces_of(tex: &PolyTexture, px: u32, py: u32) -> (Split, Vec<Piece>, Vec<DVec2>) {
        let (mut verts, mut pieces) = (Vec::new(), Vec::new());
        let sq = pixel_square(px, py);
        let mut sink = Sink::Pieces(&mut verts, &mut pieces);
        let split = split(&sq, px, py, tex, &mut sink, &mut Scratch::default());
        (split, pieces, verts)
    }

    proptest! {
        /// The transparent-run skip gives the very same pieces, in the same
        /// order, as visiting every cell: on sparse patterns, rotated and
        /// perspective maps, magnified and minified.
        #[test]
        fn the_transparent_run_skip_gives_the_same_pieces(
            sixteens in 1u32..3,
            seed in any::<u64>(),
            density in 0u32..4,
            scale in 0.3f64..40.0,
            angle in 0.0f64..std::f64::consts::TAU,
            persp in 0.0f64..0.05,
            px in 0u32..16,
            py in 0u32..16,
        ) {
            // A dot pattern: texel opaque with probability density/8.
            let texels = pattern(16 * sixteens, &[Rgb8([200, 10, 10]), Rgb8([10, 200, 10])], |c, r| {
                let h = (seed ^ ((c as u64) << 32 | r as u64)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                if (h >> 61) < density as u64 { ((c + r) % 2) as u16 } else { TRANSPARENT }
            });
            let mut tex = placed(texels, scale, Filter::Box, 0.0);
            let (sn, cs) = crate::math::sin_cos(angle);
            tex.map.u = [scale * cs, -scale * sn, 0.37];
            tex.map.v = [scale * sn, scale * cs, -1.21];
            tex.map.d = [persp, persp * 0.5, 1.0];
            let with = pieces_of(&tex, px, py);
            tex.skips.transparent = false;
            let without = pieces_of(&tex, px, py);
            prop_assert_eq!(with, without);
        }
    }

    /// A one-texel checker `scale` texels a pixel, turned `angle`, under
    /// a perspective of strength `persp`.
    fn checker(scale: f64, angle: f64, persp: f64) -> PolyTexture {
        let (a, b) = (Rgb8([230, 230, 230]), Rgb8([20, 20, 120]));
        let texels = pattern(16, &[a, b], |c, r| ((c + r) % 2) as u16);
        let mut tex = placed(texels, scale, Filter::Box, 0.0);
        let (sn, cs) = crate::math::sin_cos(angle);
        tex.map.u = [scale * cs, -scale * sn, 0.37];
        tex.map.v = [scale * sn, scale * cs, -1.21];
        tex.map.d = [persp, persp * 0.5, 1.0];
        tex
    }

    proptest! {
        /// The summing sink is the pieces' area-weighted colours, to the
        /// bit (the same sums in the same order), and the pieces tile the
        /// pixel: their areas add up to its area.
        #[test]
        fn the_summed_pieces_are_the_pieces(
            scale in 0.3f64..60.0,
            angle in 0.0f64..std::f64::consts::TAU,
            persp in 0.0f64..0.05,
            px in 0u32..16,
            py in 0u32..16,
        ) {
            let tex = checker(scale, angle, persp);
            let (split_p, pieces, verts) = pieces_of(&tex, px, py);
            let mut sum = Summed::default();
            let sq = pixel_square(px, py);
            let split_s = split(&sq, px, py, &tex, &mut Sink::Sum(&mut sum), &mut Scratch::default());
            prop_assert_eq!(split_p, split_s);
            let mut expect = Summed::default();
            for piece in &pieces {
                let a2 = area2(&verts[piece.start as usize..(piece.start + piece.len) as usize]);
                for ch in 0..3 {
                    expect.weighted[ch] += a2 * piece.color[ch];
                }
                expect.area2 += a2;
            }
            prop_assert_eq!(sum, expect);
            if split_s == Split::Pieces {
                prop_assert!((sum.area2 - 2.0).abs() < 1e-9, "{}", sum.area2);
            }
        }
    }

    proptest! {
        /// The box integral over a pixel cut in two by a line is the
        /// integral over the whole pixel, in colour and in the area behind
        /// it, to rounding: `integrate` over the visible pieces a sweep
        /// finds gives what one fragment of their union gives, however the
        /// union is cut.
        #[test]
        fn integrating_two_halves_is_integrating_the_whole(
            scale in 0.3f64..60.0,
            angle in 0.0f64..std::f64::consts::TAU,
            persp in 0.0f64..0.05,
            px in 0u32..16,
            py in 0u32..16,
            cut in proptest::array::uniform3(-1.0f64..1.0),
        ) {
            let tex = checker(scale, angle, persp);
            let sq = pixel_square(px, py);
            // A line through the pixel: a*(x - cx) + b*(y - cy) + c/2 = 0.
            let (cx, cy) = (px as f64 + 0.5, py as f64 + 0.5);
            let line = [cut[0], cut[1], 0.5 * cut[2] - cut[0] * cx - cut[1] * cy];
            let neg = line.map(|v| -v);
            let (mut left, mut right) = (Vec::new(), Vec::new());
            clip_line(&sq, line, &mut left);
            clip_line(&sq, neg, &mut right);
            let halves: Vec<&[DVec2]> = [&left[..], &right[..]]
                .into_iter()
                .filter(|h| h.len() >= 3 && area2(h) > 2.0 * AREA_EPS)
                .collect();
            let whole = integrate([&sq[..]], px, py, &tex, None, &mut Scratch::default()).unwrap();
            let parts = integrate(halves, px, py, &tex, None, &mut Scratch::default()).unwrap();
            for ch in 0..3 {
                prop_assert!((whole[ch] - parts[ch]).abs() < 1e-9, "{:?} vs {:?}", whole, parts);
            }
            // And the whole pixel's integral is the pieces route's sum.
            let (split, pieces, verts) = pieces_of(&tex, px, py);
            let expect = match split {
                Split::Whole(c) => c.unwrap(),
                Split::Pieces => {
                    let mut sum = Summed::default();
                    for piece in &pieces {
                        let v = &verts[piece.start as usize..(piece.start + piece.len) as usize];
                        Sink::Sum(&mut sum).take(v, area2(v), piece.color);
                    }
                    sum.mean().unwrap()
                }
                Split::Deferred => unreachable!("split never defers"),
            };
            prop_assert_eq!(whole, expect);
        }
    }

    /// A pixel over 150x150 texels (about 23,000 cells): summed exactly,
    /// but estimated where its pieces would be kept for the sweep
    /// ([`MAX_SWEPT_CELLS`]).
    #[test]
    fn kept_pieces_have_the_lower_bound() {
        let (a, b) = (Rgb8([230, 230, 230]), Rgb8([20, 20, 120]));
        let texels = pattern(16, &[a, b], |c, r| match (c + r) % 3 {
            2 => TRANSPARENT,
            i => i as u16,
        });
        let tex = placed(texels, 150.0, Filter::Box, 0.0);
        let square = pixel_square(3, 4);
        let mut s = Scratch::default();
        let mut sum = Summed::default();
        let split_sum = split(&square, 3, 4, &tex, &mut Sink::Sum(&mut sum), &mut s);
        assert_eq!((split_sum, s.estimated), (Split::Pieces, 0));
        // A third of the cells are transparent: two thirds of the area.
        assert!((sum.area2 / 2.0 - 2.0 / 3.0).abs() < 0.01, "{}", sum.area2);
        let (mut verts, mut pieces) = (Vec::new(), Vec::new());
        let split_kept = split(
            &square,
            3,
            4,
            &tex,
            &mut Sink::Pieces(&mut verts, &mut pieces),
            &mut s,
        );
        assert!(matches!(split_kept, Split::Whole(Some(_))) && pieces.is_empty());
        assert_eq!(s.estimated, 1);
    }

    /// A pixel whose image reaches u = -1e20 (one vertex's uv of `-1e20`):
    /// its cell count, taken in `i64` from saturated indices, wrapped to a
    /// negative number, so the fragment was cut, through 1e20 columns, and
    /// never finished. It is past [`MAX_EXACT_CELLS`] and takes the EWA
    /// estimate.
    #[test]
    fn a_fragment_reaching_past_far_texels_is_estimated_not_cut() {
        let (a, b) = (Rgb8([230, 230, 230]), Rgb8([20, 20, 120]));
        let texels = pattern(16, &[a, b], |c, r| ((c + r) % 2) as u16);
        let mut tex = placed(texels, 1.0, Filter::Box, 0.0);
        tex.map.u = [-1e20, 0.0, 8.0];
        let square = pixel_square(0, 0);
        let b = cell_box(&square, &tex).unwrap();
        assert!(b.cells_met() > MAX_EXACT_CELLS as f64, "{}", b.cells_met());
        let mut s = Scratch::default();
        let mut sum = Summed::default();
        let got = split(&square, 0, 0, &tex, &mut Sink::Sum(&mut sum), &mut s);
        assert!(matches!(got, Split::Whole(Some(_))), "{got:?}");
        assert_eq!(s.estimated, 1);
        // Magnified but far out (u about 1e30): not one cell of saturated
        // indices, the estimate too.
        tex.map.u = [1.0, 0.0, 1e30];
        assert!(cell_box(&square, &tex).unwrap().cells_met().is_infinite());
        assert_eq!(single_cell(&tex, 0, 4, 0), None);
    }

    #[test]
    fn a_magnified_fragment_is_whole_unless_the_skip_is_off() {
        let texels = pattern(16, &[Rgb8([200, 10, 10])], |_, _| 0);
        let mut tex = placed(texels, 0.1, Filter::Box, 0.0);
        let (split, pieces, _) = pieces_of(&tex, 3, 3);
        assert!(matches!(split, Split::Whole(Some(_))) && pieces.is_empty());
        tex.skips.magnify = false;
        let (split, pieces, verts) = pieces_of(&tex, 3, 3);
        assert_eq!(split, Split::Pieces);
        assert_eq!(pieces.len(), 1);
        assert_eq!(area2(&verts), 2.0);
    }

    /// A pixel over 300x300 texels of a one-texel checker (90,000 cells, past
    /// [`MAX_EXACT_CELLS`]) takes the checker's linear mean: the EWA on the
    /// pyramid, within 1% (the box integral over a 300x300 block is the
    /// mean exactly).
    #[test]
    fn heavy_minification_takes_the_local_mean_in_one_piece() {
        let (a, b) = (Rgb8([230, 230, 230]), Rgb8([20, 20, 120]));
        let checker = pattern(16, &[a, b], |c, r| ((c + r) % 2) as u16);
        let tex = placed(checker, 300.0, Filter::Box, 0.0);
        let square = crate::geom::polygon::pixel_square(3, 4);
        let (mut verts, mut pieces, mut s) = (Vec::new(), Vec::new(), Scratch::default());
        let Split::Whole(Some(c)) = split(
            &square,
            3,
            4,
            &tex,
            &mut Sink::Pieces(&mut verts, &mut pieces),
            &mut s,
        ) else {
            panic!("expected one opaque piece");
        };
        for ch in 0..3 {
            let mean = 0.5
                * (srgb_to_linear_f64(a.0[ch] as f64 / 255.0)
                    + srgb_to_linear_f64(b.0[ch] as f64 / 255.0));
            assert!((c[ch] - mean).abs() <= 0.01 * mean, "{c:?} vs mean {mean}");
        }
        // Under the bound the cut is exact: 50x50 cells, 2500 pieces.
        let tex = placed(tex.texels.clone(), 50.0, Filter::Box, 0.0);
        assert_eq!(
            split(
                &square,
                3,
                4,
                &tex,
                &mut Sink::Pieces(&mut verts, &mut pieces),
                &mut s
            ),
            Split::Pieces
        );
        assert_eq!(pieces.len(), 2500);
    }
}
