//! Exact-area anti-aliasing (`--aa exact`): each pixel is the box-filtered
//! (area-weighted) linear-light mean of what is visible in its square.
//!
//! 1. **Fragments.** Each convex piece of a polygon (the polygon itself, or its
//!    ear-clipping triangles when concave) is cut into pixel rows and then into
//!    pixels by axis clipping; new vertices take the grid coordinate exactly, and
//!    crossings of an edge are computed from its inside endpoint, so the
//!    fragments of polygons that share an edge meet exactly. Pixels whose four
//!    corners lie in the piece are marked *full* without any clipping.
//! 2. **Visibility.** Nearness is affine over the screen, so the part of
//!    fragment G in front of fragment F is G cut by one line (where
//!    `q_G - q_F > 0`): a convex polygon. The visible part of F is F minus the
//!    union of those pieces over every other G, by convex subtraction (the
//!    remainder stays a list of convex polygons): exact for interpenetrating
//!    polygons too ([`subtract_pairwise`]).
//! 3. **Tile sweep.** The same areas, found front to back: the tile's
//!    polygons come nearest first, and each fragment is cut out of its
//!    pixel's uncovered part as it is made, its visible area being what it
//!    removed ([`PixelStates`]). That holds where no fragment is in front of
//!    one that showed before it, which is checked; a pixel where the check
//!    fails is resolved again pairwise. A covered pixel drops what comes
//!    behind everything that showed in it before it is clipped, and a pixel
//!    row wholly behind is never cut from its piece.
//! 4. **Blend.** The pixel is `sum(area_F * colour_F) + (1 - sum(area_F)) * bg`
//!    in linear light, accumulated in f64.
//!
//! Two same-coloured polygons sharing an edge give areas that sum to the area of
//! their union up to ~1e-16; [`AREA_EPS`] absorbs that so no seam of background
//! shows through, and the pixel is bit for bit that of one polygon.

use super::clip::{clip_axis, clip_line};
use super::gather::{Local, TileGeom, GATHER_MAX_VERTS};
use super::{area2, tie_tolerance, Background, ScreenPoly};
use glam::DVec2;

/// Areas (in pixels) below this are rounding noise, not geometry: f64 shoelace
/// areas of unit-scale fragments are exact to ~1e-15, while the smallest area
/// that can change an 8-bit sRGB value is ~1e-6 (1/255 of the darkest step).
pub const AREA_EPS: f64 = 1e-12;

/// Edges shorter than this (pixels) are clipping debris: a crossing computed a
/// hair from an existing vertex. Their direction is rounding noise, so they
/// must not serve as a separating axis or as a cutting line (a zero-length
/// edge would "separate" everything and cut nothing). Skipping them moves
/// the result by at most this length times the pixel, far below 8 bits.
pub const EDGE_EPS: f64 = 1e-9;

/// Two fragments that share an edge meet along it only up to rounding (their
/// vertices there come from separate clips): a vertex within this distance
/// (pixels) of a separating line counts as on it. Treating an overlap this thin
/// as none changes an area by at most 1e-9 pixel, and it spares the convex
/// subtraction for every pair of neighbours, the common case on textured faces.
pub const SEPARATION_EPS: f64 = 1e-9;

/// One polygon's part of one pixel.
#[derive(Clone, Copy, Debug)]
struct Frag {
    /// Pixel index within the tile.
    pixel: u32,
    /// Polygon index.
    poly: u32,
    /// Vertices in the arena, or `len == 0` for the full pixel square.
    start: u32,
    len: u32,
    /// Index of this fragment's own colour (a texel's) in the tile's colour
    /// list, or [`POLY_COLOR`] for the polygon's colour.
    color: u32,
}

/// [`Frag::color`] of a fragment coloured by its polygon.
const POLY_COLOR: u32 = u32::MAX;

/// [`Frag::color`] of an opaque textured fragment whose filtered colour (at
/// the pixel centre) is computed only once it is known to be visible.
const FILTER_LATER: u32 = u32::MAX - 1;

/// The filtered colour at the centre of pixel `(px, py)` of a
/// [`FILTER_LATER`] fragment of `l`, computed once it is known to show.
fn deferred_filter(polys: &[ScreenPoly], l: &Local, px: u32, py: u32) -> [f64; 3] {
    let tex = polys[l.global as usize]
        .texture
        .as_ref()
        .expect("FILTER_LATER fragments are textured");
    match tex.eval(px as f64 + 0.5, py as f64 + 0.5) {
        crate::texture::filter::Eval::Color(Some(c)) => c,
        // Unreachable for a texture that is always opaque and was given a
        // filter at this centre when the fragment was made.
        other => unreachable!("a deferred filter gave {other:?}"),
    }
}

/// Per-tile buffers for fragments of textured polygons.
#[derive(Default)]
struct TexScratch {
    colors: Vec<[f64; 3]>,
    pieces: Vec<crate::texture::cells::Piece>,
    verts: Vec<DVec2>,
    cells: crate::texture::cells::Scratch,
}

/// Pushes one fragment of polygon `pi` in `pixel` (`verts` empty = the full
/// pixel square): as is, or, for a textured polygon, cut into its texel cells
/// (`crate::texture::cells`), each piece with its texel's colour; for a
/// stripe-textured polygon, whole, with the stripe colour at its centroid.
#[allow(clippy::too_many_arguments)]
fn push_frag(
    p: &ScreenPoly,
    pi: u32,
    pixel: u32,
    (px, py): (u32, u32),
    verts: &[DVec2],
    frags: &mut Vec<Frag>,
    arena: &mut Vec<DVec2>,
    t: &mut TexScratch,
) {
    use crate::texture::cells::{split, Split};
    if let Some(stripe) = &p.stripe {
        t.colors
            .push(stripe.fragment_linear(px, py, verts).map(f64::from));
        push_piece(frags, arena, pixel, pi, verts, (t.colors.len() - 1) as u32);
        return;
    }
    let Some(tex) = &p.texture else {
        push_piece(frags, arena, pixel, pi, verts, POLY_COLOR);
        return;
    };
    let (x, y) = (px as f64, py as f64);
    // A filter other than the box: the fragment is flat, coloured by the
    // filter at the pixel centre (its coverage stays exact). When no texel
    // can be transparent the colour does not decide visibility, and it is
    // left to [`PixelStates::sweep`], which computes it only if the
    // fragment shows (hidden pixels are never filtered; `--no-skip hidden`
    // filters them all, for the benchmark).
    if let Some((f, fp)) = tex.filter_at(x + 0.5, y + 0.5) {
        if tex.always_opaque() && tex.skips.hidden {
            push_piece(frags, arena, pixel, pi, verts, FILTER_LATER);
        } else if let Some(c) = crate::texture::filter::unpremultiply(tex.sample(f, &fp)) {
            t.colors.push(c);
            push_piece(frags, arena, pixel, pi, verts, (t.colors.len() - 1) as u32);
        }
        return;
    }
    // The centre of a pixel straddling the plane's horizon can lie beyond
    // it, where the map has no footprint; the fragment's own vertex centroid
    // lies inside the polygon. (Falling back to the box filter there would
    // cut a near-horizon fragment into up to MAX_EXACT_CELLS pieces.)
    if !tex.filters.is_box() && !verts.is_empty() {
        let c = super::vertex_mean(verts);
        if let Some((f, fp)) = tex.filter_at(c.x, c.y) {
            if let Some(c) = crate::texture::filter::unpremultiply(tex.sample(f, &fp)) {
                t.colors.push(c);
                push_piece(frags, arena, pixel, pi, verts, (t.colors.len() - 1) as u32);
            }
            return;
        }
    }
    let square = super::pixel_square(px, py);
    let shape: &[DVec2] = if verts.is_empty() { &square } else { verts };
    t.pieces.clear();
    t.verts.clear();
    match split(
        shape,
        px,
        py,
        tex,
        &mut t.verts,
        &mut t.pieces,
        &mut t.cells,
    ) {
        Split::Whole(None) => {}
        Split::Whole(Some(c)) => {
            t.colors.push(c);
            let color = (t.colors.len() - 1) as u32;
            push_piece(frags, arena, pixel, pi, verts, color);
        }
        Split::Pieces => {
            for piece in &t.pieces {
                t.colors.push(piece.color);
                let verts = &t.verts[piece.start as usize..(piece.start + piece.len) as usize];
                push_piece(frags, arena, pixel, pi, verts, (t.colors.len() - 1) as u32);
            }
        }
    }
}

/// Whether [`push_full_run`] applies to `p`: a pattern under the exact box
/// filter (no stripe), with the magnification fast path on.
fn box_magnified(p: &ScreenPoly) -> bool {
    p.stripe.is_none()
        && p.texture
            .as_ref()
            .is_some_and(|t| t.filters.is_box() && t.skips.magnify)
}

/// Where a run of full pixels lies in a tile: row `py`, tile origin and width.
#[derive(Clone, Copy)]
struct Row {
    py: u32,
    ty0: u32,
    tx0: u32,
    tw: usize,
}

/// The magnification fast path over a run `xa..xb` of full pixels of one
/// row of a box-filtered textured polygon. Where the run's rectangle lies in
/// one texel cell, every pixel of it is that texel, whole: what
/// `cells::split` finds pixel by pixel (the map is projective with `D > 0`
/// on the polygon, so the rectangle's image is the convex hull of its
/// corners' images, and the cell box of the corners bounds every pixel's).
/// Otherwise the run is halved, down to single pixels, which go through
/// [`push_frag`]. A close-up wall of 40-pixel texels costs a few map
/// evaluations per cell edge instead of four per pixel.
#[allow(clippy::too_many_arguments)]
fn push_full_run(
    p: &ScreenPoly,
    pi: u32,
    row: Row,
    xa: u32,
    xb: u32,
    frags: &mut Vec<Frag>,
    arena: &mut Vec<DVec2>,
    t: &mut TexScratch,
) {
    let pixel = |x: u32| ((row.py - row.ty0) as usize * row.tw + (x - row.tx0) as usize) as u32;
    let tex = p.texture.as_ref().expect("box_magnified");
    if xb - xa == 1 {
        push_frag(p, pi, pixel(xa), (xa, row.py), &[], frags, arena, t);
        return;
    }
    if let Some((k, j)) = crate::texture::cells::single_cell(tex, xa, xb, row.py) {
        if let Some(c) = tex.texel(k, j) {
            t.colors.push(c);
            let color = (t.colors.len() - 1) as u32;
            for x in xa..xb {
                push_piece(frags, arena, pixel(x), pi, &[], color);
            }
        }
        return;
    }
    let mid = xa + (xb - xa) / 2;
    push_full_run(p, pi, row, xa, mid, frags, arena, t);
    push_full_run(p, pi, row, mid, xb, frags, arena, t);
}

/// Stores one fragment: its vertices copied into the tile's arena (none for
/// the full pixel square, which `verts` being empty stands for).
fn push_piece(
    frags: &mut Vec<Frag>,
    arena: &mut Vec<DVec2>,
    pixel: u32,
    poly: u32,
    verts: &[DVec2],
    color: u32,
) {
    let start = if verts.is_empty() {
        0
    } else {
        arena.len() as u32
    };
    arena.extend_from_slice(verts);
    frags.push(Frag {
        pixel,
        poly,
        start,
        len: verts.len() as u32,
        color,
    });
}

/// One row of a convex piece inside a tile: its band (the piece clipped to
/// the row), the pixel columns `cx0..cx1` it touches, and its full pixels
/// `[x, x + 1] ⊂ [full_lo, full_hi]`.
struct RowSpan {
    cx0: u32,
    cx1: u32,
    full_lo: f64,
    full_hi: f64,
}

/// The pixel rows `y0..y1` and columns `x0..x1` of the tile that a box
/// `[x0, y0, x1, y1]` meets.
fn pixel_range(bb: &[f64; 4], [tx0, ty0, tx1, ty1]: [u32; 4]) -> [u32; 4] {
    [
        (bb[0].floor() as u32).max(tx0),
        (bb[1].floor() as u32).max(ty0),
        (bb[2].ceil() as u32).min(tx1),
        (bb[3].ceil() as u32).min(ty1),
    ]
}

/// The band of the convex `piece` in pixel row `py` (into `band`, `tmp`
/// scratch) and where it lies in the row, or `None` where the piece meets
/// the row with no area.
fn row_band(
    piece: &[DVec2],
    py: u32,
    (tx0, tx1): (u32, u32),
    tmp: &mut Vec<DVec2>,
    band: &mut Vec<DVec2>,
) -> Option<RowSpan> {
    let (yb, yt) = (py as f64, py as f64 + 1.0);
    tmp.clear();
    clip_axis(piece, 1, yb, true, tmp);
    band.clear();
    clip_axis(tmp, 1, yt, false, band);
    if band.len() < 3 {
        return None;
    }
    let (mut bx0, mut bx1) = (f64::MAX, f64::MIN);
    // Spans of the band on its bottom and top lines: the pixel
    // [x, x+1] is full iff it lies within both (convexity).
    let (mut lb, mut rb, mut lt, mut rt) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for v in band.iter() {
        bx0 = fmin(bx0, v.x);
        bx1 = fmax(bx1, v.x);
        if v.y == yb {
            lb = fmin(lb, v.x);
            rb = fmax(rb, v.x);
        }
        if v.y == yt {
            lt = fmin(lt, v.x);
            rt = fmax(rt, v.x);
        }
    }
    Some(RowSpan {
        cx0: (bx0.floor() as u32).max(tx0),
        cx1: (bx1.ceil() as u32).min(tx1),
        full_lo: lb.max(lt).ceil(),
        full_hi: rb.min(rt).floor(),
    })
}

/// The part of pixel `x` of a row's `band` (into `cell`, `tmp` scratch):
/// `Some(&[])` for the full pixel square (no clipping), `None` where the
/// piece has no area in the pixel.
fn pixel_cell<'a>(
    band: &[DVec2],
    r: &RowSpan,
    x: u32,
    tmp: &mut Vec<DVec2>,
    cell: &'a mut Vec<DVec2>,
) -> Option<&'a [DVec2]> {
    let (xl, xr) = (x as f64, x as f64 + 1.0);
    if xl >= r.full_lo && xr <= r.full_hi {
        return Some(&[]);
    }
    tmp.clear();
    clip_axis(band, 0, xl, true, tmp);
    cell.clear();
    clip_axis(tmp, 0, xr, false, cell);
    if cell.len() < 3 || area2(cell) <= 2.0 * AREA_EPS {
        return None;
    }
    Some(cell)
}

/// Buffers of [`render_tile`], kept from tile to tile by each thread: a
/// deep tile holds tens of thousands of fragments, and fresh vectors per
/// tile cost page faults and regrowth copies.
#[derive(Default)]
pub struct TileScratch {
    frags: Vec<Frag>,
    arena: Vec<DVec2>,
    pixels: PixelStates,
    band: Vec<DVec2>,
    tmp: Vec<DVec2>,
    cell: Vec<DVec2>,
    tmp2: Vec<DVec2>,
    /// A large piece clipped to the tile.
    large: Vec<DVec2>,
    tex: TexScratch,
    resolve: Scratch,
}

thread_local! {
    /// Each thread's [`TileScratch`] and tile geometry, kept for the
    /// process's life: rayon's `map_init` makes a fresh one per work split,
    /// and a fresh large vector is fresh pages for the kernel to zero.
    static SCRATCH: std::cell::RefCell<(TileScratch, TileGeom)> = Default::default();
}

/// Runs `f` with this thread's tile buffers, or fresh ones if they are in
/// use (a tile's work waiting in rayon could let this thread start another).
pub fn with_tile_scratch<R>(f: impl FnOnce(&mut TileScratch, &mut TileGeom) -> R) -> R {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut held) => {
            let (s, g) = &mut *held;
            f(s, g)
        }
        Err(_) => f(&mut TileScratch::default(), &mut TileGeom::default()),
    })
}

/// Renders one tile with exact coverage.
///
/// The tile's pieces are swept nearest first (by their greatest nearness
/// in the tile), and each fragment is cut out of its pixel's uncovered part
/// as it is made ([`PixelStates`]): once a pixel is covered, what comes
/// later and lies behind everything that showed in it is dropped before it
/// is clipped, and a pixel row wholly behind is never cut from its piece.
/// At depth (ten layers of small triangles) most fragments die there.
/// Pixels where that order does not hold (polygons crossing inside the
/// pixel, or met out of order) are resolved again by pairwise subtraction.
pub fn render_tile(
    polys: &[ScreenPoly],
    geom: &TileGeom,
    bg: &Background,
    tile: [u32; 4],
    s: &mut TileScratch,
) -> Vec<[f32; 3]> {
    let [tx0, ty0, tx1, _] = tile;
    let tw = (tx1 - tx0) as usize;
    let th = (tile[3] - ty0) as usize;
    let TileScratch {
        frags,
        arena,
        pixels,
        band,
        tmp,
        cell,
        tmp2,
        large,
        tex,
        resolve,
    } = s;
    frags.clear();
    arena.clear();
    tex.colors.clear();
    pixels.reset(tw * th, &mut resolve.pool);
    let locals = &geom.locals[..];
    let tile_box = [tx0 as f64, ty0 as f64, tx1 as f64, tile[3] as f64];
    let pixel_of = |x: u32, py: u32| ((py - ty0) as usize * tw + (x - tx0) as usize) as u32;
    for r in &geom.pieces {
        // Fragments name their polygon by its index in the tile ([`Local`]).
        let pi = r.local;
        let l = &locals[pi as usize];
        let p = (!l.plain).then(|| &polys[l.global as usize]);
        let mut piece = geom.piece(polys, r);
        if piece.len() > GATHER_MAX_VERTS {
            // A large polygon, read in place: clipped to the tile once,
            // not whole for each of its rows.
            clip_to_box(piece, &tile_box, tmp, large);
            piece = large;
        }
        let [rx0, ry0, rx1, ry1] = pixel_range(&r.bb, tile);
        for py in ry0..ry1 {
            let cy = py as f64 + 0.5;
            let hidden = |pixels: &PixelStates, x: u32| {
                l.cullable && pixels.hides(pixel_of(x, py), l, x as f64 + 0.5, cy)
            };
            if (rx0..rx1).all(|x| hidden(pixels, x)) {
                continue; // Behind every pixel the row could touch.
            }
            let Some(r) = row_band(piece, py, (tx0, tx1), tmp, band) else {
                continue;
            };
            // The full pixels of the row, for the run fast path.
            let (fx0, fx1) = if r.full_hi >= r.full_lo + 1.0 {
                (
                    (r.full_lo.max(r.cx0 as f64) as u32).min(r.cx1),
                    (r.full_hi.min(r.cx1 as f64) as u32).max(r.cx0),
                )
            } else {
                (r.cx1, r.cx1)
            };
            let run_path = fx1 > fx0 && p.is_some_and(box_magnified);
            // Where the band is in the arena, and its box, once an open
            // pixel needs it.
            let mut band_at: Option<(u32, u32, [f64; 4])> = None;
            let mut px = r.cx0;
            while px < r.cx1 {
                frags.clear();
                // The box of the fragment, where already known.
                let mut known_bb = None;
                if let (true, Some(p)) = (run_path && px == fx0, p) {
                    let row = Row { py, ty0, tx0, tw };
                    push_full_run(p, pi, row, fx0, fx1, frags, arena, tex);
                    px = fx1;
                } else {
                    let x = px;
                    px += 1;
                    let pixel = pixel_of(x, py);
                    if hidden(pixels, x) {
                        continue;
                    }
                    let full = x as f64 >= r.full_lo && x as f64 + 1.0 <= r.full_hi;
                    if p.is_none() && !full && pixels.is_open(pixel) {
                        // Only cut out of the open part: the row's band
                        // stands for the fragment (the open part lies in
                        // the pixel), saving its clip to the pixel.
                        let (start, len, bb) = *band_at.get_or_insert_with(|| {
                            arena.extend_from_slice(band);
                            let start = (arena.len() - band.len()) as u32;
                            (start, band.len() as u32, bounds(band))
                        });
                        known_bb = Some(bb);
                        frags.push(Frag {
                            pixel,
                            poly: pi,
                            start,
                            len,
                            color: POLY_COLOR,
                        });
                    } else {
                        let Some(verts) = pixel_cell(band, &r, x, tmp2, cell) else {
                            continue;
                        };
                        match p {
                            None => push_piece(frags, arena, pixel, pi, verts, POLY_COLOR),
                            Some(p) => push_frag(p, pi, pixel, (x, py), verts, frags, arena, tex),
                        }
                    }
                }
                for f in frags.iter() {
                    let at = (tx0 + f.pixel % tw as u32, ty0 + f.pixel / tw as u32);
                    let shown = Shown {
                        polys,
                        locals,
                        arena,
                        colors: &tex.colors,
                    };
                    pixels.sweep(f, at, known_bb, &shown, resolve);
                }
            }
        }
    }
    (0..(tw * th) as u32)
        .map(|idx| {
            let (px, py) = (tx0 + idx % tw as u32, ty0 + idx / tw as u32);
            pixels.colour(idx, bg, px, py)
        })
        .collect()
}

/// Where a pixel stands in the tile-order sweep of [`render_tile`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Status {
    /// What has shown (if anything) is pairwise disjoint, so the uncovered
    /// part is the square minus their areas, and it is never built: a pixel
    /// cut into texel cells or split between neighbours that only touch
    /// costs no subtraction at all.
    Disjoint,
    /// Partly covered, with overlaps: the uncovered part is the pixel's
    /// convex pieces.
    Open,
    /// Wholly covered.
    Closed,
}

/// A fragment that showed in a pixel, kept to check what comes later
/// against it (and to resolve the pixel again if that check fails).
#[derive(Clone, Copy)]
struct Shower {
    poly: u32,
    /// Vertices in the arena, or `len == 0` for the full pixel square.
    start: u32,
    len: u32,
    /// Nearness at the pixel centre, and least over the pixel.
    qc: f64,
    q_lo: f64,
    bb: [f64; 4],
    color: [f64; 3],
}

/// What [`PixelStates::sweep`] reads of the tile to place and colour a
/// fragment.
struct Shown<'a> {
    polys: &'a [ScreenPoly],
    locals: &'a [Local],
    arena: &'a [DVec2],
    colors: &'a [[f64; 3]],
}

/// The tile-order sweep's state of each pixel of a tile: what is still
/// uncovered, the colour and area of what has shown, and the fragments
/// that showed (the *showers*).
///
/// Fragments arrive in the tile's sweep order, nearest first by a bound,
/// not in each pixel's own order. Each is checked against every shower of
/// its pixel: it must be nowhere in front of it where they overlap
/// ([`front_of`] `<= 0` at the vertices of either, which bound their
/// overlap since it is affine, or no common interior). Then it hides
/// nothing that has shown, and what it shows is exactly its part of the
/// uncovered region: it is cut out of it, and its visible area is what it
/// removed. Fragments that showed nothing need no check: they lie under
/// showers, which are in front of them there.
///
/// Where the check fails (polygons crossing inside the pixel, or met out
/// of order) the pixel is resolved again among its showers and the
/// newcomer by pairwise subtraction ([`subtract_pairwise`]), exact for any
/// arrangement. The showers are enough: every other fragment lies, at each
/// of its points, behind a shower. The sweep then goes on from there.
#[derive(Default)]
struct PixelStates {
    status: Vec<Status>,
    /// Area-weighted linear-light colour of what has shown, and its area.
    acc: Vec<[f64; 4]>,
    /// Over the showers: the least nearness over the pixel, and the largest
    /// |nearness| at the centre (for the tie tolerance).
    floor: Vec<[f64; 2]>,
    /// The uncovered part of an [`Status::Open`] pixel, as convex pieces.
    open: Vec<Vec<Vec<DVec2>>>,
    showers: Vec<Vec<Shower>>,
    /// How many times a pixel was resolved again (a count for the tests).
    resolved_again: u32,
}

/// A fragment on its way into [`PixelStates::sweep`].
struct Newcomer<'a> {
    f: &'a Frag,
    l: &'a Local,
    verts: &'a [DVec2],
    bb: [f64; 4],
    qc: f64,
    /// Its colour, `None` for a [`FILTER_LATER`] one not yet filtered.
    color: Option<[f64; 3]>,
}

impl PixelStates {
    /// Every pixel uncovered, for a tile of `n` pixels; the last tile's
    /// pieces go back to `pool`.
    fn reset(&mut self, n: usize, pool: &mut Vec<Vec<DVec2>>) {
        for open in &mut self.open {
            pool.append(open);
        }
        for s in &mut self.showers {
            s.clear();
        }
        if self.open.len() < n {
            self.open.resize_with(n, Vec::new);
            self.showers.resize_with(n, Vec::new);
        }
        self.status.clear();
        self.status.resize(n, Status::Disjoint);
        self.acc.clear();
        self.acc.resize(n, [0.0; 4]);
        self.floor.clear();
        self.floor.resize(n, [f64::INFINITY, 0.0]);
    }

    /// Whether `l` can show nothing in the pixel centred at `(cx, cy)`: the
    /// pixel is covered, and `l` is behind every shower over the whole
    /// pixel by more than the tie tolerance (so the check of
    /// [`PixelStates::sweep`] passes for it without its fragment).
    #[inline]
    fn is_open(&self, pixel: u32) -> bool {
        self.status[pixel as usize] == Status::Open
    }

    #[inline]
    fn hides(&self, pixel: u32, l: &Local, cx: f64, cy: f64) -> bool {
        let p = pixel as usize;
        if self.status[p] != Status::Closed {
            return false;
        }
        let [q_lo, abs] = self.floor[p];
        let qc = l.q(cx, cy);
        qc + l.half_spread() + tie_tolerance(qc, abs, l.tie_floor) <= q_lo
    }

    /// Sweeps fragment `f` of pixel `(px, py)` (see [`PixelStates`]).
    fn sweep(
        &mut self,
        f: &Frag,
        (px, py): (u32, u32),
        bb: Option<[f64; 4]>,
        t: &Shown,
        work: &mut Scratch,
    ) {
        let p = f.pixel as usize;
        let l = &t.locals[f.poly as usize];
        // A screen pattern's transparent texel: no fragment at all.
        let color = match f.color {
            POLY_COLOR => match l
                .color
                .or_else(|| t.polys[l.global as usize].color_at(px, py))
            {
                Some(c) => Some(c),
                None => return,
            },
            FILTER_LATER => None,
            i => Some(t.colors[i as usize]),
        };
        let square = super::pixel_square(px, py);
        let verts = frag_verts(f, t.arena, &square);
        let first_full =
            f.len == 0 && self.showers[p].is_empty() && self.status[p] == Status::Disjoint;
        let n = Newcomer {
            f,
            l,
            verts,
            bb: match bb {
                Some(bb) => bb,
                None if f.len == 0 => box_of(&square),
                None => bounds(verts),
            },
            qc: l.q(px as f64 + 0.5, py as f64 + 0.5),
            color,
        };
        let status = self.status[p];
        if first_full {
            // The first fragment, and full: it is all the pixel shows so far
            // (the common case inside polygons; nothing to check or cut).
            let c = n
                .color
                .unwrap_or_else(|| deferred_filter(t.polys, l, px, py));
            self.show(p, &n, 1.0, c);
            self.status[p] = Status::Closed;
            return;
        }
        let (in_order, overlaps) = self.check(p, &n, &square, t);
        if !in_order {
            self.resolve_again(p, &n, (px, py), &square, t, work);
            return;
        }
        let seen2 = match status {
            Status::Closed => return, // Hidden: behind what covers the pixel.
            Status::Disjoint if !overlaps => {
                if f.len == 0 {
                    2.0
                } else {
                    area2(verts)
                }
            }
            Status::Disjoint | Status::Open => {
                if status == Status::Disjoint {
                    self.build_open(p, &square, t.arena, work);
                }
                self.cut(p, &n, &square, work)
            }
        };
        let area = 0.5 * seen2;
        if area > AREA_EPS {
            let c = n
                .color
                .unwrap_or_else(|| deferred_filter(t.polys, l, px, py));
            self.show(p, &n, area, c);
        }
        if self.status[p] == Status::Disjoint && self.acc[p][3] >= 1.0 - AREA_EPS {
            self.status[p] = Status::Closed;
        }
    }

    /// Whether `n` is nowhere in front of a shower of pixel `p` where they
    /// overlap; and, for a [`Status::Disjoint`] pixel, whether it overlaps
    /// any shower.
    fn check(&self, p: usize, n: &Newcomer, square: &[DVec2; 4], t: &Shown) -> (bool, bool) {
        let track = self.status[p] == Status::Disjoint;
        let (l, qc) = (n.l, n.qc);
        let q_hi = qc + l.half_spread();
        let [floor, abs] = self.floor[p];
        let behind_all = q_hi + tie_tolerance(qc, abs, l.tie_floor) <= floor;
        if behind_all && !track {
            return (true, false);
        }
        let mut overlaps = false;
        for c in &self.showers[p] {
            if c.poly == n.f.poly {
                continue; // One polygon's pieces never overlap.
            }
            let cv = if c.len == 0 {
                &square[..]
            } else {
                &t.arena[c.start as usize..(c.start + c.len) as usize]
            };
            let apart = || boxes_apart(&n.bb, &c.bb) || disjoint(cv, n.verts);
            let behind = behind_all || q_hi + tie_tolerance(qc, c.qc, l.tie_floor) <= c.q_lo || {
                let d = front_of(l, &t.locals[c.poly as usize], qc, c.qc);
                let val = |v: &DVec2| d[0] * v.x + d[1] * v.y + d[2];
                n.verts.iter().all(|v| val(v) <= 0.0) || cv.iter().all(|v| val(v) <= 0.0)
            };
            if behind {
                overlaps = overlaps || (track && !apart());
                continue;
            }
            if apart() {
                continue;
            }
            return (false, true);
        }
        (true, overlaps)
    }

    /// Builds the uncovered part of a [`Status::Disjoint`] pixel: the
    /// square minus each shower.
    fn build_open(&mut self, p: usize, square: &[DVec2; 4], arena: &[DVec2], work: &mut Scratch) {
        let open = &mut self.open[p];
        let mut whole = work.pool.pop().unwrap_or_default();
        whole.clear();
        whole.extend_from_slice(square);
        open.push(whole);
        for c in &self.showers[p] {
            let cv = if c.len == 0 {
                &square[..]
            } else {
                &arena[c.start as usize..(c.start + c.len) as usize]
            };
            cut_out(open, cv, &c.bb, square, work);
        }
        self.status[p] = if open.is_empty() {
            Status::Closed
        } else {
            Status::Open
        };
    }

    /// Cuts `n` out of the uncovered part of an [`Status::Open`] pixel;
    /// twice the area it removed.
    fn cut(&mut self, p: usize, n: &Newcomer, square: &[DVec2; 4], work: &mut Scratch) -> f64 {
        let open = &mut self.open[p];
        let seen2 = cut_out(open, n.verts, &n.bb, square, work);
        if open.is_empty() {
            self.status[p] = Status::Closed;
        }
        seen2
    }

    /// Adds a shower to pixel `p`.
    fn show(&mut self, p: usize, n: &Newcomer, area: f64, c: [f64; 3]) {
        let acc = &mut self.acc[p];
        for ch in 0..3 {
            acc[ch] += area * c[ch];
        }
        acc[3] += area;
        let q_lo = n.qc - n.l.half_spread();
        self.showers[p].push(Shower {
            poly: n.f.poly,
            start: n.f.start,
            len: n.f.len,
            qc: n.qc,
            q_lo,
            bb: n.bb,
            color: c,
        });
        let fl = &mut self.floor[p];
        *fl = [fmin(fl[0], q_lo), fmax(fl[1], n.qc.abs())];
    }

    /// Resolves pixel `p` again among its showers and `n`, which is in front
    /// of one of them somewhere, by pairwise subtraction; then cuts `n` out
    /// of the uncovered part.
    #[allow(clippy::too_many_arguments)]
    fn resolve_again(
        &mut self,
        p: usize,
        n: &Newcomer,
        (px, py): (u32, u32),
        square: &[DVec2; 4],
        t: &Shown,
        work: &mut Scratch,
    ) {
        self.resolved_again += 1;
        let showers = &mut self.showers[p];
        // Each one's part of the pixel (a row's band stands for the
        // fragments of open pixels), copied into an arena of their own.
        let mut cells = std::mem::take(&mut work.cells);
        cells.clear();
        let batch = &mut work.batch;
        batch.clear();
        work.alive.clear();
        let members = showers
            .iter()
            .map(|c| (c.poly, c.start, c.len, c.bb))
            .chain([(n.f.poly, n.f.start, n.f.len, n.bb)]);
        let pixel = box_of(square);
        for (poly, start, len, bb) in members {
            let at = cells.len() as u32;
            // `len == 0`: the full square. A band that meets the pixel in no
            // area is absent (and its empty vertex list is never read).
            let present = len == 0 || {
                let v = &t.arena[start as usize..(start + len) as usize];
                if within(&bb, &pixel) {
                    cells.extend_from_slice(v);
                } else {
                    clip_to_box(v, &pixel, &mut work.a, &mut work.b);
                    if work.b.len() >= 3 {
                        cells.extend_from_slice(&work.b);
                    }
                }
                cells.len() as u32 > at
            };
            work.alive.push(present);
            batch.push(Frag {
                pixel: p as u32,
                poly,
                start: at,
                len: cells.len() as u32 - at,
                color: POLY_COLOR,
            });
        }
        work.qc.clear();
        work.qc.extend(showers.iter().map(|c| c.qc));
        work.qc.push(n.qc);
        let batch = std::mem::take(&mut work.batch);
        subtract_pairwise(t.locals, &batch, &cells, square, work);
        work.batch = batch;
        work.cells = cells;
        // The new showers, with their new areas.
        let mut acc = [0.0; 4];
        let mut kept = std::mem::take(&mut work.showers);
        kept.clear();
        for &(i, area) in &work.seen {
            let c = match showers.get(i as usize) {
                Some(s) => *s,
                None => {
                    let color = n
                        .color
                        .unwrap_or_else(|| deferred_filter(t.polys, n.l, px, py));
                    Shower {
                        poly: n.f.poly,
                        start: n.f.start,
                        len: n.f.len,
                        qc: n.qc,
                        q_lo: n.qc - n.l.half_spread(),
                        bb: n.bb,
                        color,
                    }
                }
            };
            for ch in 0..3 {
                acc[ch] += area * c.color[ch];
            }
            acc[3] += area;
            kept.push(c);
        }
        std::mem::swap(showers, &mut kept);
        work.showers = kept;
        self.acc[p] = acc;
        self.floor[p] = showers.iter().fold([f64::INFINITY, 0.0], |[lo, abs], c| {
            [fmin(lo, c.q_lo), fmax(abs, c.qc.abs())]
        });
        match self.status[p] {
            Status::Closed => {}
            Status::Disjoint => self.build_open(p, square, t.arena, work),
            Status::Open => {
                self.cut(p, n, square, work);
            }
        }
    }

    /// The pixel's colour.
    fn colour(&self, pixel: u32, bg: &Background, px: u32, py: u32) -> [f32; 3] {
        let [r, g, b, covered] = self.acc[pixel as usize];
        blend_background([r, g, b], covered, bg, px, py)
    }
}

/// Cuts the convex `v` (bounding box `bb`) out of the convex pieces `open`
/// of the pixel `square`; twice the area it removed.
fn cut_out(
    open: &mut Vec<Vec<DVec2>>,
    v: &[DVec2],
    bb: &[f64; 4],
    square: &[DVec2; 4],
    work: &mut Scratch,
) -> f64 {
    if v == square {
        // The whole pixel: all that was open is seen.
        let seen2 = open.iter().map(|piece| area2(piece)).sum();
        work.pool.append(open);
        return seen2;
    }
    let pixel = box_of(square);
    let mut seen2 = 0.0;
    let next = &mut work.next;
    next.clear();
    for piece in open.drain(..) {
        if boxes_apart(&bounds(&piece), bb) {
            next.push(piece);
            continue;
        }
        match subtract(
            &piece,
            v,
            pixel,
            next,
            &mut work.a,
            &mut work.b,
            &mut work.pool,
        ) {
            None => next.push(piece),
            Some(s2) => {
                seen2 += s2;
                work.pool.push(piece);
            }
        }
    }
    std::mem::swap(open, next);
    seen2
}

/// Per-tile buffers of the per-pixel visibility, reused from pixel to pixel.
#[derive(Default)]
struct Scratch {
    pieces: Vec<Vec<DVec2>>,
    next: Vec<Vec<DVec2>>,
    /// Vertex lists no longer in use, kept for their allocations: the convex
    /// subtraction makes and drops several small pieces per fragment pair, and
    /// recycling them keeps the allocator out of the inner loop.
    pool: Vec<Vec<DVec2>>,
    occ: Vec<DVec2>,
    a: Vec<DVec2>,
    b: Vec<DVec2>,
    /// The fragments [`subtract_pairwise`] resolves, and which of them are
    /// present.
    batch: Vec<Frag>,
    alive: Vec<bool>,
    /// Runs `[start, end)` of consecutive fragments of one polygon.
    runs: Vec<(u32, u32)>,
    /// Each fragment's nearness at the pixel centre (the point the tie rule
    /// is evaluated at), computed once per pixel instead of once per pair.
    qc: Vec<f64>,
    /// Visible area of each fragment that shows, found by
    /// [`subtract_pairwise`].
    seen: Vec<(u32, f64)>,
    /// A spare list of showers, and the vertices of the fragments it
    /// resolves, for [`PixelStates::resolve_again`].
    showers: Vec<Shower>,
    cells: Vec<DVec2>,
}

fn frag_verts<'a>(f: &Frag, arena: &'a [DVec2], square: &'a [DVec2; 4]) -> &'a [DVec2] {
    if f.len == 0 {
        square
    } else {
        &arena[f.start as usize..(f.start + f.len) as usize]
    }
}

/// `q_G - q_F` as an affine function, shifted by the tie rule: positive where G
/// is in front of F. The later polygon wins within [`tie_tolerance`] (painter's order).
/// `qg` and `qf` are `g.q(at)` and `f.q(at)` at the point the tie is decided
/// (the pixel centre), passed in because they are the same for every pair.
fn front_of(g: &Local, f: &Local, qg: f64, qf: f64) -> [f64; 3] {
    let d = [
        g.plane[0] - f.plane[0],
        g.plane[1] - f.plane[1],
        g.plane[2] - f.plane[2],
    ];
    let bias = tie_tolerance(qg, qf, g.tie_floor);
    let c = if g.order > f.order {
        d[2] + bias
    } else {
        d[2] - bias
    };
    [d[0], d[1], c]
}

/// The visible area of each live fragment, in `s.seen` in stream order: F
/// minus the part of every other fragment G in front of it (G cut by the
/// line where their nearness is equal, so a convex polygon), by convex
/// subtraction. Exact for any arrangement, interpenetration included;
/// quadratic in the fragments, but it cuts nothing for neighbours that
/// only touch, the common case on a textured or finely split face.
fn subtract_pairwise(
    locals: &[Local],
    frags: &[Frag],
    arena: &[DVec2],
    square: &[DVec2; 4],
    s: &mut Scratch,
) {
    let pixel = box_of(square);
    let Scratch {
        pieces,
        next,
        pool,
        occ,
        a,
        b,
        qc,
        alive,
        runs,
        seen,
        ..
    } = s;
    runs.clear();
    let mut start = 0;
    for k in 1..=frags.len() {
        if k == frags.len() || frags[k].poly != frags[start].poly {
            runs.push((start as u32, k as u32));
            start = k;
        }
    }
    seen.clear();
    // Stream order, even after a sweep that gave up had sorted `live`.
    for i in (0..frags.len()).filter(|&i| alive[i]) {
        let f = &frags[i];
        let fp = &locals[f.poly as usize];
        pool.append(pieces);
        let mut whole = pool.pop().unwrap_or_default();
        whole.clear();
        whole.extend_from_slice(frag_verts(f, arena, square));
        pieces.push(whole);
        // Pieces of one polygon (ear-clipping triangles, texel cells) never
        // hide each other: `front_of` is then the constant `-tie` < 0. They
        // come in runs (fragments are made polygon by polygon), and F's own
        // runs are skipped whole, so a pixel over n texel cells of one
        // polygon costs O(n), not O(n²) tests or even O(n²) skips.
        for &(r0, r1) in runs.iter() {
            if frags[r0 as usize].poly == f.poly {
                continue;
            }
            for j in r0 as usize..r1 as usize {
                if !alive[j] || pieces.is_empty() {
                    continue;
                }
                let g = &frags[j];
                let gv = frag_verts(g, arena, square);
                let gp = &locals[g.poly as usize];
                let d = front_of(gp, fp, qc[j], qc[i]);
                let val = |v: &DVec2| d[0] * v.x + d[1] * v.y + d[2];
                // The two tests that let G pass are independent of each
                // other; the cheap depth test goes first (it passes about
                // half the pairs at depth), the separating-axis test second.
                if gv.iter().all(|v| val(v) <= 0.0) {
                    continue; // G is behind F wherever G is.
                }
                if pieces.len() == 1 && disjoint(&pieces[0], gv) {
                    continue; // Neighbours that only share an edge.
                }
                occ.clear();
                if gv.iter().all(|v| val(v) >= 0.0) {
                    occ.extend_from_slice(gv);
                } else {
                    clip_line(gv, d, occ);
                }
                if occ.len() < 3 || area2(occ) <= 2.0 * AREA_EPS {
                    continue;
                }
                next.clear();
                for piece in pieces.drain(..) {
                    match subtract(&piece, occ, pixel, next, a, b, pool) {
                        None => next.push(piece),
                        Some(_) => pool.push(piece),
                    }
                }
                std::mem::swap(pieces, next);
            }
        }
        let area: f64 = pieces.iter().map(|p| area2(p)).sum::<f64>() * 0.5;
        if area > AREA_EPS {
            seen.push((i as u32, area));
        }
    }
}

/// Adds the background over the part of the pixel no fragment covers.
fn blend_background(
    mut acc: [f64; 3],
    covered: f64,
    bg: &Background,
    px: u32,
    py: u32,
) -> [f32; 3] {
    let rest = 1.0 - covered;
    if rest > AREA_EPS {
        let b = bg.at(px, py);
        for ch in 0..3 {
            acc[ch] += rest * b[ch];
        }
    }
    acc.map(|c| c as f32)
}

/// `a.min(b)` for numbers that are not NaN (screen geometry is finite by
/// construction: the stream rejects NaN and the clipper keeps `w > 0`). One
/// instruction, where `f64::min` and `f64::max` with their NaN handling took
/// 13% of `render_tile`'s samples in a profile of a deep scene.
#[inline(always)]
fn fmin(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// `a.max(b)` for numbers that are not NaN; see [`fmin`].
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// Bounding box `[x0, y0, x1, y1]` of a vertex list.
pub(super) fn bounds(v: &[DVec2]) -> [f64; 4] {
    v.iter().fold(
        [f64::MAX, f64::MAX, f64::MIN, f64::MIN],
        |[x0, y0, x1, y1], p| [fmin(x0, p.x), fmin(y0, p.y), fmax(x1, p.x), fmax(y1, p.y)],
    )
}

/// Whether box `a` lies within box `b`.
fn within(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] >= b[0] && a[1] >= b[1] && a[2] <= b[2] && a[3] <= b[3]
}

/// The part of the convex `v` in the box `[x0, y0, x1, y1]`, into `out`
/// (`tmp` scratch), clipped as the fragments are made: rows first, then
/// columns, each crossing made from its inside endpoint.
fn clip_to_box(
    v: &[DVec2],
    [x0, y0, x1, y1]: &[f64; 4],
    tmp: &mut Vec<DVec2>,
    out: &mut Vec<DVec2>,
) {
    tmp.clear();
    clip_axis(v, 1, *y0, true, tmp);
    out.clear();
    clip_axis(tmp, 1, *y1, false, out);
    tmp.clear();
    clip_axis(out, 0, *x0, true, tmp);
    out.clear();
    clip_axis(tmp, 0, *x1, false, out);
}

/// The box `[x0, y0, x1, y1]` of a pixel square.
fn box_of(square: &[DVec2; 4]) -> [f64; 4] {
    [square[0].x, square[0].y, square[2].x, square[2].y]
}

/// Whether two boxes share no interior (touching counts as apart).
fn boxes_apart(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1]
}

/// Whether two convex counter-clockwise polygons have no interior in common:
/// some edge of one has the whole other on its outer side (separating axis;
/// touching along an edge, within [`SEPARATION_EPS`], counts as disjoint).
fn disjoint(a: &[DVec2], b: &[DVec2]) -> bool {
    let separated = |p: &[DVec2], q: &[DVec2]| {
        let n = p.len();
        (0..n).any(|i| {
            let (s, e) = (p[i], p[if i + 1 == n { 0 } else { i + 1 }]);
            let dir = e - s;
            let len = dir.length();
            len > EDGE_EPS
                && q.iter()
                    .all(|&v| dir.perp_dot(v - s) <= SEPARATION_EPS * len)
        })
    };
    separated(a, b) || separated(b, a)
}

/// Longest piece [`subtract`] splits in one pass (its sides on the stack);
/// longer ones, which a pixel's pieces never are in practice, are clipped
/// twice instead, with the same result.
const SPLIT_MAX: usize = 32;

/// Splits the convex `poly` by a line whose value at each vertex is
/// `sides`: the part where it is `>= 0` into `inside`, the part where it is
/// `<= 0` into `outside`. Bit for bit what `clip_line` gives with the line
/// and with its negation (negating a line negates its values exactly, and
/// each crossing is made from the same endpoint as there).
fn split(poly: &[DVec2], sides: &[f64], inside: &mut Vec<DVec2>, outside: &mut Vec<DVec2>) {
    let n = poly.len();
    for i in 0..n {
        let j = if i + 1 == n { 0 } else { i + 1 };
        let (a, b) = (poly[i], poly[j]);
        let (da, db) = (sides[i], sides[j]);
        clip_step(a, b, da, db, inside);
        clip_step(a, b, -da, -db, outside);
    }
}

/// One edge `a -> b` of a Sutherland–Hodgman pass keeping `d >= 0` (`da`,
/// `db` at its ends), pushing what `clip_line` pushes for it.
#[inline(always)]
fn clip_step(a: DVec2, b: DVec2, da: f64, db: f64, out: &mut Vec<DVec2>) {
    if da >= 0.0 {
        out.push(a);
        if db < 0.0 && da > 0.0 {
            out.push(a + (b - a) * (da / (da - db)));
        }
    } else if db > 0.0 {
        out.push(b + (a - b) * (db / (db - da)));
    }
}

/// Appends the convex pieces of `p \ o` (both convex, counter-clockwise) to
/// `out`: for each edge of `o`, the part of `p` to its right is outside `o` and
/// kept; the rest goes on to the next edge, and what is left at the end lies in
/// `o` and is dropped. New pieces take their vertex lists from `pool`.
/// Returns twice the area of what was dropped, `p ∩ o`; or `None`, with
/// nothing appended, where `p` lies wholly outside `o` (or `o` has no
/// interior): `p \ o` is then `p` itself, which the caller keeps without a
/// copy.
///
/// An `o` with fewer than three edges longer than [`EDGE_EPS`] has no
/// interior and removes nothing (without this check, all of `p` would be
/// "left at the end" and dropped).
///
/// `p` lies in the pixel `[x0, y0, x1, y1]`: an edge of `o` along a side of
/// it (exactly, as the axis clipping makes them) has all of `p` inside and
/// is skipped. A fragment's pixel-border edges are half of its edges.
///
/// Where `cur` lies strictly on one side of an edge's line, the two clips
/// would return `cur` unchanged and nothing (or nothing and `cur`): that case
/// is decided from the signs alone and the clips are skipped. The signs are
/// the very values `clip_line` computes (negating a line negates them
/// exactly in IEEE arithmetic), so the pieces are bit for bit the same.
fn subtract(
    p: &[DVec2],
    o: &[DVec2],
    [x0, y0, x1, y1]: [f64; 4],
    out: &mut Vec<Vec<DVec2>>,
    cur: &mut Vec<DVec2>,
    tmp: &mut Vec<DVec2>,
    pool: &mut Vec<Vec<DVec2>>,
) -> Option<f64> {
    let keep = |piece: &[DVec2], out: &mut Vec<Vec<DVec2>>, pool: &mut Vec<Vec<DVec2>>| {
        let mut v = pool.pop().unwrap_or_default();
        v.clear();
        v.extend_from_slice(piece);
        out.push(v);
    };
    let n = o.len();
    let edges = (0..n)
        .filter(|&i| {
            (o[if i + 1 == n { 0 } else { i + 1 }] - o[i]).length_squared() > EDGE_EPS * EDGE_EPS
        })
        .count();
    if edges < 3 {
        return None;
    }
    cur.clear();
    cur.extend_from_slice(p);
    // Whether `cur` is no longer `p`.
    let mut cut = false;
    for i in 0..n {
        if cur.len() < 3 {
            return Some(0.0);
        }
        let (a, b) = (o[i], o[if i + 1 == n { 0 } else { i + 1 }]);
        // Left of a->b: (b - a) x (p - a) >= 0, as a*x + b*y + c.
        let e = b - a;
        if e.length_squared() <= EDGE_EPS * EDGE_EPS
            || (e.x == 0.0 && (a.x == x0 || a.x == x1))
            || (e.y == 0.0 && (a.y == y0 || a.y == y1))
        {
            continue;
        }
        let line = [-e.y, e.x, e.y * a.x - e.x * a.y];
        let side = |v: &DVec2| line[0] * v.x + line[1] * v.y + line[2];
        let m = cur.len();
        if m > SPLIT_MAX {
            if cur.iter().all(|v| side(v) > 0.0) {
                continue; // Wholly inside this edge: nothing outside it.
            }
            if cur.iter().all(|v| side(v) < 0.0) {
                // Wholly outside this edge, so outside `o`: kept whole.
                if !cut {
                    return None;
                }
                if area2(cur) > 2.0 * AREA_EPS {
                    keep(cur, out, pool);
                }
                return Some(0.0);
            }
            cut = true;
            tmp.clear();
            clip_line(cur, [-line[0], -line[1], -line[2]], tmp);
            if tmp.len() >= 3 && area2(tmp) > 2.0 * AREA_EPS {
                keep(tmp, out, pool);
            }
            tmp.clear();
            clip_line(cur, line, tmp);
            std::mem::swap(cur, tmp);
            continue;
        }
        // The same two clips in one pass, each vertex's side computed once.
        let mut sides = [0.0f64; SPLIT_MAX];
        let (mut inside, mut outside) = (true, true);
        for (d, v) in sides.iter_mut().zip(cur.iter()) {
            *d = side(v);
            inside &= *d > 0.0;
            outside &= *d < 0.0;
        }
        if inside {
            continue; // Wholly inside this edge: nothing outside it.
        }
        if outside {
            // Wholly outside this edge, so outside `o`: kept whole.
            if !cut {
                return None;
            }
            if area2(cur) > 2.0 * AREA_EPS {
                keep(cur, out, pool);
            }
            return Some(0.0);
        }
        cut = true;
        let mut part = pool.pop().unwrap_or_default();
        part.clear();
        tmp.clear();
        split(cur, &sides[..m], tmp, &mut part);
        if part.len() >= 3 && area2(&part) > 2.0 * AREA_EPS {
            out.push(part);
        } else {
            pool.push(part);
        }
        std::mem::swap(cur, tmp);
    }
    Some(if cur.len() < 3 { 0.0 } else { area2(cur) })
}

#[cfg(test)]
mod tests {
    use super::super::tests::{perspective, poly2};
    use super::super::{project, render, Aa, Cull, View};
    use super::*;
    use crate::color::Rgb8;
    use glam::DVec3;

    fn render_exact(polys: &[ScreenPoly], w: u32, h: u32) -> crate::io::Image {
        render(polys, &Background::color(Rgb8::BLACK), w, h, Aa::Exact).to_image()
    }

    /// Regression: the occluder of `tests/cli/texture.rs`'s
    /// `a_sliver_of_a_near_textured_polygon_hides_nothing_behind_it`, a
    /// clipping sliver with 1e-12-pixel edges far from the origin: it has no
    /// area and subtracting it leaves the piece whole.
    #[test]
    fn a_sliver_occluder_far_from_the_origin_hides_nothing() {
        let sliver = [
            DVec2::new(423.8080517040671, 256.9861491440843),
            DVec2::new(423.80805170407166, 256.98614914408506),
            DVec2::new(423.80805170407154, 256.9861491440851),
        ];
        assert!(area2(&sliver).abs() <= 2.0 * AREA_EPS);
        let piece = vec![
            DVec2::new(424.0, 256.73198427959096),
            DVec2::new(424.0, 257.0),
            DVec2::new(423.0, 257.0),
            DVec2::new(423.0, 256.6012019151243),
            DVec2::new(423.2278482750052, 256.4861575572889),
        ];
        let (mut out, mut a, mut b, mut pool) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let pixel = [423.0, 256.0, 424.0, 257.0];
        let left: f64 = match subtract(&piece, &sliver, pixel, &mut out, &mut a, &mut b, &mut pool)
        {
            None => area2(&piece), // Untouched.
            Some(_) => out.iter().map(|p| area2(p)).sum(),
        };
        assert!(
            (left - area2(&piece)).abs() < 1e-12,
            "{left} of {}",
            area2(&piece)
        );
    }

    #[test]
    fn a_half_covered_pixel_is_the_linear_light_half() {
        let v = View::ortho2(0.0, 2.0, 0.0, 1.0, 2, 1);
        // Covers pixel 0 fully and half of pixel 1 (diagonal).
        let p = poly2(
            &v,
            &[[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            Rgb8::WHITE,
            0,
        )
        .unwrap();
        let img = render_exact(&[p], 2, 1);
        assert_eq!(img.data, vec![255, 255, 255, 188, 188, 188]);
    }

    #[test]
    fn two_triangles_sharing_an_edge_render_exactly_like_one_quad() {
        let v = View::ortho2(0.0, 16.0, 0.0, 16.0, 16, 16);
        let (a, b, c, d) = ([1.3, 0.7], [14.9, 2.2], [13.1, 15.4], [0.2, 12.8]);
        let c1 = Rgb8([200, 120, 30]);
        let quad = poly2(&v, &[a, b, c, d], c1, 0).unwrap();
        let t1 = poly2(&v, &[a, b, c], c1, 0).unwrap();
        let t2 = poly2(&v, &[a, c, d], c1, 1).unwrap();
        assert_eq!(
            render_exact(&[quad], 16, 16),
            render_exact(&[t1, t2], 16, 16)
        );
    }

    #[test]
    fn interpenetrating_polygons_split_a_pixel_along_their_intersection() {
        // Two squares crossing at x = 0.5 inside one pixel: left half red in
        // front, right half blue in front; the result is the linear mean.
        let v = View::ortho2(0.0, 1.0, 0.0, 1.0, 1, 1);
        let sq = |z0: f64, z1: f64, c: Rgb8, o: u32| {
            project(
                &v,
                &[
                    DVec3::new(0.0, 0.0, z0),
                    DVec3::new(1.0, 0.0, z1),
                    DVec3::new(1.0, 1.0, z1),
                    DVec3::new(0.0, 1.0, z0),
                ],
                c,
                o,
                Cull::None,
            )
            .unwrap()
        };
        let red = sq(0.5, -0.5, Rgb8([255, 0, 0]), 0);
        let blue = sq(-0.5, 0.5, Rgb8([0, 0, 255]), 1);
        let img = render_exact(&[red, blue], 1, 1);
        assert_eq!(img.data, vec![188, 0, 188]);
    }

    #[test]
    fn perspective_ground_plane_with_near_zero_renders_finite_pixels() {
        let v = perspective(60.0, 32, 24, 0.0, 1000.0);
        let ground = [
            DVec3::new(-500.0, -1.0, 0.0),
            DVec3::new(500.0, -1.0, 0.0),
            DVec3::new(500.0, -1.0, -800.0),
            DVec3::new(-500.0, -1.0, -800.0),
        ];
        let p = project(&v, &ground, Rgb8::WHITE, 0, Cull::None).unwrap();
        let img = render_exact(&[p], 32, 24);
        // Bottom row white, top row black: the horizon lies in between.
        assert!(img.data[(23 * 32) * 3..].iter().all(|&c| c == 255));
        assert!(img.data[..32 * 3].iter().all(|&c| c == 0));
    }
}

#[cfg(test)]
mod ties {
    use super::super::tests::poly2;
    use super::super::{render, Aa, View};
    use super::*;
    use crate::color::Rgb8;

    #[test]
    fn coplanar_overlap_goes_to_the_later_polygon_without_double_counting() {
        let v = View::ortho2(0.0, 4.0, 0.0, 4.0, 4, 4);
        let red = poly2(
            &v,
            &[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]],
            Rgb8([255, 0, 0]),
            0,
        )
        .unwrap();
        let blue = poly2(
            &v,
            &[[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]],
            Rgb8([0, 0, 255]),
            1,
        )
        .unwrap();
        let bg = Background::color(Rgb8::BLACK);
        let want = |i: usize| {
            let (x, y) = (i % 4, i / 4);
            if (1..3).contains(&x) && (1..3).contains(&y) {
                [0, 0, 255]
            } else {
                [255, 0, 0]
            }
        };
        for aa in [Aa::Exact, Aa::None, Aa::Ss(4)] {
            let img = render(&[red.clone(), blue.clone()], &bg, 4, 4, aa).to_image();
            for (i, p) in img.data.chunks(3).enumerate() {
                assert_eq!(p, want(i), "{aa:?} pixel {i}");
            }
        }
        let r = super::super::reference::render(&[red, blue], &bg, 4, 4, 6);
        for (i, p) in r.frame.to_image().data.chunks(3).enumerate() {
            assert_eq!(p, want(i), "reference pixel {i}");
        }
    }
}

#[cfg(test)]
mod debris {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn near_duplicate_vertices_neither_separate_nor_cut() {
        // Clipping leaves a crossing a hair from a vertex: a tiny edge whose
        // direction is noise. It must not make overlapping polygons "disjoint"
        // nor keep the whole polygon as "outside" the occluder.
        let tri = [v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0)];
        let with_debris = [
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 0.0),
            v(1.0 - 1e-14, 1e-14),
            v(0.0, 1.0),
        ];
        let small = [v(0.1, 0.1), v(0.3, 0.1), v(0.1, 0.3)];
        assert!(!disjoint(&with_debris, &small));
        assert!(!disjoint(&small, &with_debris));
        let (mut out, mut a, mut b, mut pool) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        // A box wider than the shapes: no edge of theirs lies on its sides.
        let wide = [-1.0, -1.0, 2.0, 2.0];
        let cut = subtract(
            &small,
            &with_debris,
            wide,
            &mut out,
            &mut a,
            &mut b,
            &mut pool,
        );
        assert!(cut.is_some(), "the debris hides the small triangle");
        let left: f64 = out.iter().map(|p| area2(p)).sum();
        assert!(left.abs() < 1e-12, "{out:?}");
        out.clear();
        let cut = subtract(&tri, &tri, wide, &mut out, &mut a, &mut b, &mut pool);
        assert!(cut.is_some());
        assert!(out.iter().map(|p| area2(p)).sum::<f64>().abs() < 1e-12);
    }
}

/// The tile sweep and the pairwise subtraction against each other and
/// against the independent reference.
#[cfg(test)]
mod sweep {
    use super::super::{project, reference, render, Aa, Cull, View};
    use super::*;
    use crate::color::Rgb8;
    use glam::DVec3;
    use proptest::prelude::*;

    /// A small deterministic generator (no dependence on a crate's stream).
    struct Lcg(u64);
    impl Lcg {
        fn unit(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// `n` random triangles of a few pixels in a `w x h` frame, at random
    /// depths: flat ones (layers), or tilted ones that cross each other.
    fn scene(seed: u64, n: usize, tilted: bool, w: u32, h: u32) -> Vec<ScreenPoly> {
        let v = View::ortho2(0.0, w as f64, 0.0, h as f64, w, h);
        let mut r = Lcg(seed);
        (0..n)
            .filter_map(|i| {
                let (cx, cy) = (r.unit() * w as f64, r.unit() * h as f64);
                let z = r.unit() * 1.6 - 0.8;
                let pts: Vec<DVec3> = (0..3)
                    .map(|_| {
                        let dz = if tilted { r.unit() * 0.4 - 0.2 } else { 0.0 };
                        DVec3::new(cx + r.unit() * 6.0 - 3.0, cy + r.unit() * 6.0 - 3.0, z + dz)
                    })
                    .collect();
                let c = Rgb8([(r.unit() * 255.0) as u8, (r.unit() * 255.0) as u8, 90]);
                project(&v, &pts, c, i as u32, Cull::None)
            })
            .collect()
    }

    /// Ten layers of small triangles, flat and crossing: `--aa exact`
    /// (the tile sweep, its drops, and pairwise subtraction where its order
    /// fails) against the reference, which shares none of that code.
    #[test]
    fn deep_random_scenes_match_the_reference() {
        let bg = Background::color(Rgb8([20, 40, 60]));
        for (seed, tilted) in [(1, false), (2, false), (3, true), (4, true)] {
            let polys = scene(seed, 400, tilted, 32, 24);
            let exact = render(&polys, &bg, 32, 24, Aa::Exact).to_image();
            let r = reference::render(&polys, &bg, 32, 24, 6);
            let want = r.frame.to_image();
            let worst = exact
                .data
                .iter()
                .zip(&want.data)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            assert!(worst <= 1, "seed {seed} tilted {tilted}: off by {worst}");
        }
    }

    /// One pixel's fragments: random triangles clipped to the square, flat
    /// or tilted planes, each its own polygon.
    fn pixel_frags(tris: &[([f64; 6], [f64; 3])]) -> (Vec<Local>, Vec<Frag>, Vec<DVec2>) {
        let (mut locals, mut frags, mut arena) = (vec![], vec![], vec![]);
        for (k, (t, plane)) in tris.iter().enumerate() {
            let mut tri = vec![
                DVec2::new(t[0], t[1]),
                DVec2::new(t[2], t[3]),
                DVec2::new(t[4], t[5]),
            ];
            if area2(&tri) < 0.0 {
                tri.reverse();
            }
            let mut a = Vec::new();
            let mut cell = tri;
            for (axis, value, above) in [
                (0, 0.0, true),
                (0, 1.0, false),
                (1, 0.0, true),
                (1, 1.0, false),
            ] {
                a.clear();
                clip_axis(&cell, axis, value, above, &mut a);
                std::mem::swap(&mut cell, &mut a);
            }
            if cell.len() < 3 || area2(&cell) <= 2.0 * AREA_EPS {
                continue;
            }
            locals.push(Local {
                plane: *plane,
                tie_floor: 1e-12,
                order: k as u32,
                global: k as u32,
                color: Some([0.5; 3]),
                plain: true,
                occludes: true,
                cullable: true,
            });
            push_piece(
                &mut frags,
                &mut arena,
                0,
                (locals.len() - 1) as u32,
                &cell,
                POLY_COLOR,
            );
        }
        (locals, frags, arena)
    }

    fn triangle() -> impl Strategy<Value = [f64; 6]> {
        proptest::array::uniform6(-0.5f64..1.5)
    }

    /// Sweeps `frags` into one pixel in the order `order`, fragment `k`
    /// coloured `colors[k]`: the pixel's colour (linear, before the
    /// background) and covered area, and how often it was resolved again.
    fn swept(
        locals: &[Local],
        frags: &[Frag],
        arena: &[DVec2],
        colors: &[[f64; 3]],
        order: &[usize],
    ) -> ([f64; 4], u32) {
        let mut pixels = PixelStates::default();
        let mut work = Scratch::default();
        pixels.reset(1, &mut work.pool);
        let shown = Shown {
            polys: &[],
            locals,
            arena,
            colors,
        };
        for &k in order {
            pixels.sweep(&frags[k], (0, 0), None, &shown, &mut work);
        }
        (pixels.acc[0], pixels.resolved_again)
    }

    proptest! {
        /// The tile sweep gives each pixel the colour and covered area that
        /// pairwise subtraction gives, whatever order its fragments come
        /// in; nearest first over flat layers, it never resolves again.
        #[test]
        fn the_tile_sweep_agrees_with_pairwise_subtraction_in_any_order(
            tris in proptest::collection::vec(
                (triangle(), (-0.3f64..0.3, -0.3f64..0.3, -1.0f64..1.0), any::<bool>(), 0.0f64..1.0),
                1..12,
            ),
            shuffle in proptest::collection::vec(any::<u32>(), 12),
        ) {
            let planes: Vec<([f64; 6], [f64; 3])> = tris
                .iter()
                .map(|(t, (a, b, c), flat, _)| (*t, if *flat { [0.0, 0.0, *c] } else { [*a, *b, *c] }))
                .collect();
            let all_flat = planes.iter().all(|(_, p)| p[0] == 0.0 && p[1] == 0.0);
            let (locals, mut frags, arena) = pixel_frags(&planes);
            // Fragment k in its own colour.
            let colors: Vec<[f64; 3]> = frags
                .iter()
                .map(|f| {
                    let g = tris[locals[f.poly as usize].order as usize].3;
                    [g, 1.0 - g, g * g]
                })
                .collect();
            for (k, f) in frags.iter_mut().enumerate() {
                f.color = k as u32;
            }
            let square = super::super::pixel_square(0, 0);
            let mut s = Scratch::default();
            s.qc.extend(frags.iter().map(|f| locals[f.poly as usize].q(0.5, 0.5)));
            s.alive.resize(frags.len(), true);
            subtract_pairwise(&locals, &frags, &arena, &square, &mut s);
            let mut want = [0.0; 4];
            for &(i, area) in &s.seen {
                for ch in 0..3 {
                    want[ch] += area * colors[i as usize][ch];
                }
                want[3] += area;
            }
            let mut order: Vec<usize> = (0..frags.len()).collect();
            order.sort_by_key(|&k| shuffle[k]);
            let (got, _) = swept(&locals, &frags, &arena, &colors, &order);
            for ch in 0..4 {
                prop_assert!((got[ch] - want[ch]).abs() <= 1e-9, "shuffled: {got:?} against {want:?}");
            }
            // Nearest first, as the tile sweep orders flat polygons.
            order.sort_by(|&i, &j| {
                let q = |k: usize| locals[frags[k].poly as usize].q(0.5, 0.5);
                q(j).total_cmp(&q(i))
            });
            let (got, again) = swept(&locals, &frags, &arena, &colors, &order);
            for ch in 0..4 {
                prop_assert!((got[ch] - want[ch]).abs() <= 1e-9, "nearest first: {got:?} against {want:?}");
            }
            prop_assert!(again == 0 || !all_flat, "flat layers resolved again {again} times");
        }
    }
}
