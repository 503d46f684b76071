//! Exact-area anti-aliasing (`--aa exact`): each pixel is the box-filtered
//! (area-weighted) linear-light mean of what is visible in its square.
//!
//! 1. **Fragments.** Each convex piece of a polygon (the polygon itself, or its
//!    ear-clipping triangles when concave) is cut into pixel rows and then into
//!    pixels by axis clipping; new vertices take the grid coordinate exactly, and
//!    crossings of an edge are computed from its inside endpoint, so the
//!    fragments of polygons that share an edge meet exactly. Pixels whose four
//!    corners lie in the piece are marked *full* without any clipping.
//! 2. **Occlusion cull.** A first pass over the tile records, per pixel, the
//!    nearest opaque polygon full in it; a fragment behind that one over the
//!    whole pixel (tie tolerance included) is never cut or stored.
//! 3. **Visibility.** Nearness is affine over the screen, so the part of
//!    fragment G in front of fragment F is G cut by one line (where
//!    `q_G - q_F > 0`): a convex polygon. The visible part of F is F minus the
//!    union of those pieces over every other G, computed by convex subtraction
//!    (the remainder stays a list of convex polygons). This is exact for
//!    interpenetrating polygons too, with no depth sorting
//!    ([`subtract_pairwise`]). Where the fragments of a pixel have one
//!    front-to-back order over all their overlaps, which is checked, a sweep
//!    in that order cuts each out of what is still uncovered and stops when
//!    nothing is ([`sweep_front_to_back`]): the same areas, in linear time.
//! 4. **Blend.** The pixel is `sum(area_F * colour_F) + (1 - sum(area_F)) * bg`
//!    in linear light, accumulated in f64 in a fixed order.
//!
//! Fast path: a full fragment that is nearer than every other fragment at all
//! four corners of the pixel (differences of affine functions are extreme at
//! corners) hides them entirely, and the pixel is its colour.
//!
//! Two same-coloured polygons sharing an edge give areas that sum to the area of
//! their union up to ~1e-16; [`AREA_EPS`] absorbs that so no seam of background
//! shows through, and the pixel is bit for bit that of one polygon.

use super::clip::{clip_axis, clip_line};
use super::gather::{Local, TileGeom};
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

/// Pixels with at least this many live fragments are resolved by
/// [`sweep_front_to_back`], the others by pairwise subtraction. With two or
/// three, the pairs are mostly neighbours that touch along an edge, which
/// the pairwise test passes without cutting anything, while the sweep cuts
/// every fragment out of the uncovered part. Measured (resolve time, one
/// thread) on demo 2 at incr 1 with back faces culled, about three per
/// pixel: 40 ms all pairwise, 53 ms all swept, 43 ms with this threshold.
/// On a million random triangles, about nine per pixel, the sweep took the
/// whole render from 4.2 s to 2.0 s.
const SWEEP_MIN_LIVE: usize = 4;

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

/// The colour of a fragment, filtering a [`FILTER_LATER`] texture now.
#[inline]
fn frag_color(
    polys: &[ScreenPoly],
    locals: &[Local],
    f: &Frag,
    cols: &[[f64; 3]],
    i: usize,
    px: u32,
    py: u32,
) -> [f64; 3] {
    if f.color != FILTER_LATER {
        return cols[i];
    }
    let tex = polys[locals[f.poly as usize].global as usize]
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
    // left to [`resolve_pixel`], which computes it only if the fragment
    // shows (hidden pixels are never filtered; `--no-skip hidden` filters
    // them all, for the benchmark).
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
    py: u32,
    cx0: u32,
    cx1: u32,
    full_lo: f64,
    full_hi: f64,
}

/// Calls `row` for each pixel row of the tile that the convex `piece` meets
/// with some area, with the band of the piece in that row.
fn for_each_row(
    piece: &[DVec2],
    [tx0, ty0, tx1, ty1]: [u32; 4],
    tmp: &mut Vec<DVec2>,
    band: &mut Vec<DVec2>,
    mut row: impl FnMut(RowSpan, &[DVec2]),
) {
    let [_, y0, _, y1] = bounds(piece);
    let ry0 = (y0.floor() as u32).max(ty0);
    let ry1 = (y1.ceil() as u32).min(ty1);
    for py in ry0..ry1 {
        let (yb, yt) = (py as f64, py as f64 + 1.0);
        tmp.clear();
        clip_axis(piece, 1, yb, true, tmp);
        band.clear();
        clip_axis(tmp, 1, yt, false, band);
        if band.len() < 3 {
            continue;
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
        let span = RowSpan {
            py,
            cx0: (bx0.floor() as u32).max(tx0),
            cx1: (bx1.ceil() as u32).min(tx1),
            full_lo: lb.max(lt).ceil(),
            full_hi: rb.min(rt).floor(),
        };
        row(span, band);
    }
}

/// The nearest polygon known to cover a whole pixel, as a bound: its
/// nearness at the pixel centre and its least nearness over the pixel.
#[derive(Clone, Copy)]
struct Cover {
    q_centre: f64,
    q_min: f64,
}

impl Cover {
    const NONE: Cover = Cover {
        q_centre: f64::NEG_INFINITY,
        q_min: f64::NEG_INFINITY,
    };
}

/// Whether `p` is behind `cover` over the whole pixel centred at `(cx, cy)`
/// by more than the tie tolerance (so that [`front_of`] from `p` to the
/// covering polygon is `<= 0` at every corner): then the pixel never shows
/// `p`, as [`resolve_pixel`]'s fast path finds for fragments behind a full
/// one. The bound uses the cover's least nearness over the pixel and `p`'s
/// greatest, so it holds at every point, not only at the corners.
fn hidden_by(p: &Local, cover: Cover, cx: f64, cy: f64) -> bool {
    let qc = p.q(cx, cy);
    qc + p.half_spread() + tie_tolerance(qc, cover.q_centre, p.tie_floor) <= cover.q_min
}

/// Buffers of [`render_tile`], kept from tile to tile by each thread: a
/// deep tile holds tens of thousands of fragments, and fresh vectors per
/// tile cost page faults and regrowth copies.
#[derive(Default)]
pub struct TileScratch {
    frags: Vec<Frag>,
    grouped: Vec<Frag>,
    arena: Vec<DVec2>,
    first: Vec<u32>,
    next: Vec<u32>,
    covers: Vec<Cover>,
    band: Vec<DVec2>,
    tmp: Vec<DVec2>,
    cell: Vec<DVec2>,
    tmp2: Vec<DVec2>,
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
/// A first pass finds, per pixel, the nearest opaque polygon that covers it
/// whole; fragments behind it by more than the tie tolerance over the whole
/// pixel are then never clipped or stored. At depth (ten layers of small
/// triangles) most fragments die there, before the per-pixel work.
pub fn render_tile(
    polys: &[ScreenPoly],
    geom: &TileGeom,
    bg: &Background,
    tile: [u32; 4],
    s: &mut TileScratch,
) -> Vec<[f32; 3]> {
    let [tx0, ty0, tx1, ty1] = tile;
    let tw = (tx1 - tx0) as usize;
    let th = (ty1 - ty0) as usize;
    let TileScratch {
        frags,
        grouped,
        arena,
        first,
        next,
        covers,
        band,
        tmp,
        cell,
        tmp2,
        tex,
        resolve,
    } = s;
    frags.clear();
    arena.clear();
    tex.colors.clear();
    covers.clear();
    covers.resize(tw * th, Cover::NONE);
    let locals = &geom.locals[..];
    let pixel_of = |x: u32, py: u32| ((py - ty0) as usize * tw + (x - tx0) as usize) as u32;
    for r in &geom.pieces {
        let l = &locals[r.local as usize];
        if !l.occludes {
            continue;
        }
        let piece = geom.piece(polys, r);
        let [x0, y0, x1, y1] = bounds(piece);
        if x1 - x0 < 1.0 || y1 - y0 < 1.0 {
            continue; // No room for a full pixel.
        }
        for_each_row(piece, tile, tmp, band, |r, _| {
            let lo = (r.full_lo.max(r.cx0 as f64) as u32).min(r.cx1);
            let hi = (r.full_hi.min(r.cx1 as f64).max(lo as f64)) as u32;
            let cy = r.py as f64 + 0.5;
            for x in lo..hi {
                let q_centre = l.q(x as f64 + 0.5, cy);
                let c = &mut covers[pixel_of(x, r.py) as usize];
                let q_min = q_centre - l.half_spread();
                if q_min > c.q_min {
                    *c = Cover { q_centre, q_min };
                }
            }
        });
    }
    for r in &geom.pieces {
        // Fragments name their polygon by its index in the tile ([`Local`]).
        let pi = r.local;
        let l = &locals[pi as usize];
        let p = (!l.plain).then(|| &polys[l.global as usize]);
        for_each_row(geom.piece(polys, r), tile, tmp, band, |r, band| {
            let py = r.py;
            let cy = py as f64 + 0.5;
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
            let mut px = r.cx0;
            while px < r.cx1 {
                if let (true, Some(p)) = (run_path && px == fx0, p) {
                    let row = Row { py, ty0, tx0, tw };
                    push_full_run(p, pi, row, fx0, fx1, frags, arena, tex);
                    px = fx1;
                    continue;
                }
                let x = px;
                px += 1;
                let pixel = pixel_of(x, py);
                if l.cullable && hidden_by(l, covers[pixel as usize], x as f64 + 0.5, cy) {
                    continue;
                }
                let (xl, xr) = (x as f64, x as f64 + 1.0);
                let verts: &[DVec2] = if xl >= r.full_lo && xr <= r.full_hi {
                    &[]
                } else {
                    tmp2.clear();
                    clip_axis(band, 0, xl, true, tmp2);
                    cell.clear();
                    clip_axis(tmp2, 0, xr, false, cell);
                    if cell.len() < 3 || area2(cell) <= 2.0 * AREA_EPS {
                        continue;
                    }
                    cell
                };
                match p {
                    None => push_piece(frags, arena, pixel, pi, verts, POLY_COLOR),
                    Some(p) => push_frag(p, pi, pixel, (x, py), verts, frags, arena, tex),
                }
            }
        });
    }
    // Group by pixel, keeping stream order within a pixel: a counting sort
    // (stable, like the comparison sort it replaces, and linear in the number
    // of fragments, which runs to tens of thousands per tile at depth).
    first.clear();
    first.resize(tw * th + 1, 0);
    for f in frags.iter() {
        first[f.pixel as usize + 1] += 1;
    }
    for k in 0..tw * th {
        first[k + 1] += first[k];
    }
    grouped.clear();
    if let Some(&f0) = frags.first() {
        grouped.resize(frags.len(), f0);
        next.clear();
        next.extend_from_slice(first);
        for f in frags.iter() {
            let slot = &mut next[f.pixel as usize];
            grouped[*slot as usize] = *f;
            *slot += 1;
        }
    }
    let mut out = Vec::with_capacity(tw * th);
    for idx in 0..(tw * th) as u32 {
        let (start, end) = (
            first[idx as usize] as usize,
            first[idx as usize + 1] as usize,
        );
        let (px, py) = (tx0 + idx % tw as u32, ty0 + idx / tw as u32);
        out.push(resolve_pixel(
            polys,
            locals,
            &grouped[start..end],
            arena,
            &tex.colors,
            bg,
            px,
            py,
            resolve,
        ));
    }
    out
}

/// Per-tile buffers of [`resolve_pixel`], reused from pixel to pixel.
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
    alive: Vec<bool>,
    cols: Vec<[f64; 3]>,
    /// Runs `[start, end)` of consecutive fragments of one polygon.
    runs: Vec<(u32, u32)>,
    /// Each fragment's nearness at the pixel centre (the point the tie rule
    /// is evaluated at), computed once per pixel instead of once per pair.
    qc: Vec<f64>,
    /// The fragments still alive after the fast path, in stream order, or
    /// nearest first once [`sweep_front_to_back`] has run.
    live: Vec<u32>,
    /// Bounding box of each of `live`, in its order.
    bb: Vec<[f64; 4]>,
    /// Visible area of each fragment that shows, found by
    /// [`sweep_front_to_back`].
    seen: Vec<(u32, f64)>,
    /// Least and most nearness over the pixel of each of `live`.
    span: Vec<[f64; 2]>,
    /// Over `live[k..]`: the most nearness, the largest |q| at the centre,
    /// the largest tie floor.
    tail: Vec<[f64; 3]>,
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

#[allow(clippy::too_many_arguments)]
fn resolve_pixel(
    polys: &[ScreenPoly],
    locals: &[Local],
    frags: &[Frag],
    arena: &[DVec2],
    colors: &[[f64; 3]],
    bg: &Background,
    px: u32,
    py: u32,
    s: &mut Scratch,
) -> [f32; 3] {
    let (x, y) = (px as f64, py as f64);
    let square = super::pixel_square(px, py);
    let corners = [(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)];
    let centre = (x + 0.5, y + 0.5);
    if frags.is_empty() {
        return bg.at(px, py).map(|c| c as f32);
    }
    // Colours here; a screen-mode pattern's transparent texel removes the
    // fragment from this pixel altogether.
    s.cols.clear();
    s.alive.clear();
    s.qc.clear();
    for f in frags {
        let l = &locals[f.poly as usize];
        s.qc.push(l.q(centre.0, centre.1));
        let c = match f.color {
            POLY_COLOR => l
                .color
                .or_else(|| polys[l.global as usize].color_at(px, py)),
            // Opaque; computed below only if it shows.
            FILTER_LATER => Some([0.0; 3]),
            i => Some(colors[i as usize]),
        };
        s.alive.push(c.is_some());
        s.cols.push(c.unwrap_or_default());
    }
    // Fast path: the nearest full fragment at the centre, if it is in front of
    // every other fragment over the whole pixel.
    let mut best: Option<usize> = None;
    for (i, f) in frags.iter().enumerate() {
        if f.len == 0 && s.alive[i] && best.map_or(true, |b| s.qc[i] > s.qc[b]) {
            best = Some(i);
        }
    }
    if let Some(b) = best {
        let fb = &locals[frags[b].poly as usize];
        let mut all_hidden = true;
        for (i, g) in frags.iter().enumerate() {
            if i == b || !s.alive[i] {
                continue;
            }
            let gp = &locals[g.poly as usize];
            let d = front_of(gp, fb, s.qc[i], s.qc[b]);
            // G never in front of the full fragment B anywhere in the pixel.
            if corners
                .iter()
                .all(|&(cx, cy)| d[0] * cx + d[1] * cy + d[2] <= 0.0)
            {
                s.alive[i] = false;
            } else {
                all_hidden = false;
            }
        }
        if all_hidden {
            return frag_color(polys, locals, &frags[b], &s.cols, b, px, py).map(|c| c as f32);
        }
    }
    s.live.clear();
    s.live
        .extend((0..frags.len() as u32).filter(|&i| s.alive[i as usize]));
    if s.live.len() < SWEEP_MIN_LIVE || !sweep_front_to_back(locals, frags, arena, &square, s) {
        subtract_pairwise(locals, frags, arena, &square, s);
    }
    let mut acc = [0.0f64; 3];
    let mut covered = 0.0f64;
    for &(i, area) in &s.seen {
        let i = i as usize;
        covered += area;
        let c = frag_color(polys, locals, &frags[i], &s.cols, i, px, py);
        for ch in 0..3 {
            acc[ch] += area * c[ch];
        }
    }
    blend_background(acc, covered, bg, px, py)
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
                    subtract(&piece, occ, next, a, b, pool);
                    pool.push(piece);
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
fn bounds(v: &[DVec2]) -> [f64; 4] {
    v.iter().fold(
        [f64::MAX, f64::MAX, f64::MIN, f64::MIN],
        |[x0, y0, x1, y1], p| [fmin(x0, p.x), fmin(y0, p.y), fmax(x1, p.x), fmax(y1, p.y)],
    )
}

/// Whether two boxes share no interior (touching counts as apart).
fn boxes_apart(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1]
}

/// The visible area of each live fragment by a front-to-back sweep, in
/// `s.seen`; `false` (and `s.seen` meaningless) where the sweep's order
/// does not hold and [`resolve_pixel`] must subtract pairwise.
///
/// `s.live` is sorted nearest first at the pixel centre (on equal nearness
/// the later polygon first, as the tie rule decides). The pixel's uncovered
/// part starts as the square; each fragment in turn sees its overlap with
/// it and is then cut out of it. That equals the pairwise subtraction (up
/// to rounding) when no fragment is in front of an earlier one anywhere
/// they overlap: then what an earlier G hides of F is all of their
/// overlap, and no later G hides any of F. Each fragment is checked against
/// every later one as it is swept ([`front_of`] <= 0 at the vertices of
/// either, which bound their overlap since it is affine, or no common
/// interior; pieces of one polygon never overlap). The check fails only
/// where two fragments interpenetrate inside the pixel, or meet at an angle
/// within the tie tolerance.
///
/// The sweep stops when nothing is left uncovered: the fragments after that
/// are hidden, and they need no check among themselves. A pixel under ten
/// layers of small triangles is settled by its first few fragments: linear
/// work where the pairwise subtraction is quadratic.
fn sweep_front_to_back(
    locals: &[Local],
    frags: &[Frag],
    arena: &[DVec2],
    square: &[DVec2; 4],
    s: &mut Scratch,
) -> bool {
    let Scratch {
        pieces: open,
        next,
        pool,
        a,
        b,
        live,
        qc,
        bb,
        seen,
        span,
        tail,
        ..
    } = s;
    live.sort_by(|&i, &j| {
        let (i, j) = (i as usize, j as usize);
        qc[j].total_cmp(&qc[i]).then_with(|| {
            let (pi, pj) = (
                &locals[frags[i].poly as usize],
                &locals[frags[j].poly as usize],
            );
            pj.order.cmp(&pi.order).then(i.cmp(&j))
        })
    });
    bb.clear();
    bb.extend(
        live.iter()
            .map(|&i| bounds(frag_verts(&frags[i as usize], arena, square))),
    );
    // Nearness bounds over the pixel, `[least, most]`, per fragment in
    // sweep order; and over each suffix of it, the most nearness, the
    // largest |q| at the centre and the largest tie floor: the tie
    // tolerance of any pair in the suffix is at most what those give.
    span.clear();
    span.extend(live.iter().map(|&i| {
        let l = &locals[frags[i as usize].poly as usize];
        let q = qc[i as usize];
        [q - l.half_spread(), q + l.half_spread()]
    }));
    tail.clear();
    tail.resize(live.len() + 1, [f64::NEG_INFINITY, 0.0, 0.0]);
    for k in (0..live.len()).rev() {
        let i = live[k] as usize;
        let [most, abs, floor] = tail[k + 1];
        tail[k] = [
            fmax(most, span[k][1]),
            fmax(abs, qc[i].abs()),
            fmax(floor, locals[frags[i].poly as usize].tie_floor),
        ];
    }
    seen.clear();
    pool.append(open);
    let mut whole = pool.pop().unwrap_or_default();
    whole.clear();
    whole.extend_from_slice(square);
    open.push(whole);
    for (k, &e) in live.iter().enumerate() {
        if open.is_empty() {
            break;
        }
        let e = e as usize;
        let fe = &frags[e];
        let ep = &locals[fe.poly as usize];
        let ev = frag_verts(fe, arena, square);
        // Every later fragment is behind E over the whole pixel, tie
        // tolerance included: its pairs need no look (one test per
        // fragment, in a scene of layers at distinct depths).
        let [most, abs, floor] = tail[k + 1];
        let all_behind = most + tie_tolerance(abs, qc[e], floor) <= span[k][0];
        for (m, &l) in live.iter().enumerate().skip(k + 1) {
            if all_behind {
                break;
            }
            let l = l as usize;
            let fl = &frags[l];
            if fl.poly == fe.poly {
                continue;
            }
            let lp = &locals[fl.poly as usize];
            if span[m][1] + tie_tolerance(qc[l], qc[e], lp.tie_floor) <= span[k][0] {
                continue; // L behind E over the whole pixel.
            }
            let lv = frag_verts(fl, arena, square);
            let d = front_of(lp, ep, qc[l], qc[e]);
            let val = |v: &DVec2| d[0] * v.x + d[1] * v.y + d[2];
            if lv.iter().all(|v| val(v) <= 0.0)
                || ev.iter().all(|v| val(v) <= 0.0)
                || boxes_apart(&bb[k], &bb[m])
                || disjoint(ev, lv)
            {
                continue;
            }
            return false;
        }
        let mut seen2 = 0.0;
        next.clear();
        for piece in open.drain(..) {
            if boxes_apart(&bounds(&piece), &bb[k]) {
                next.push(piece);
                continue;
            }
            seen2 += subtract(&piece, ev, next, a, b, pool);
            pool.push(piece);
        }
        std::mem::swap(open, next);
        let area = 0.5 * seen2;
        if area > AREA_EPS {
            seen.push((e as u32, area));
        }
    }
    true
}

/// Whether two convex counter-clockwise polygons have no interior in common:
/// some edge of one has the whole other on its outer side (separating axis;
/// touching along an edge, within [`SEPARATION_EPS`], counts as disjoint).
fn disjoint(a: &[DVec2], b: &[DVec2]) -> bool {
    let separated = |p: &[DVec2], q: &[DVec2]| {
        let n = p.len();
        (0..n).any(|i| {
            let (s, e) = (p[i], p[(i + 1) % n]);
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
/// Returns twice the area of what was dropped, `p ∩ o`.
///
/// An `o` with fewer than three edges longer than [`EDGE_EPS`] has no
/// interior and removes nothing (without this check, all of `p` would be
/// "left at the end" and dropped).
///
/// Where `cur` lies strictly on one side of an edge's line, the two clips
/// would return `cur` unchanged and nothing (or nothing and `cur`): that case
/// is decided from the signs alone and the clips are skipped. The signs are
/// the very values `clip_line` computes (negating a line negates them
/// exactly in IEEE arithmetic), so the pieces are bit for bit the same.
fn subtract(
    p: &[DVec2],
    o: &[DVec2],
    out: &mut Vec<Vec<DVec2>>,
    cur: &mut Vec<DVec2>,
    tmp: &mut Vec<DVec2>,
    pool: &mut Vec<Vec<DVec2>>,
) -> f64 {
    let keep = |piece: &[DVec2], out: &mut Vec<Vec<DVec2>>, pool: &mut Vec<Vec<DVec2>>| {
        let mut v = pool.pop().unwrap_or_default();
        v.clear();
        v.extend_from_slice(piece);
        out.push(v);
    };
    let n = o.len();
    let edges = (0..n)
        .filter(|&i| (o[(i + 1) % n] - o[i]).length_squared() > EDGE_EPS * EDGE_EPS)
        .count();
    if edges < 3 {
        keep(p, out, pool);
        return 0.0;
    }
    cur.clear();
    cur.extend_from_slice(p);
    for i in 0..n {
        if cur.len() < 3 {
            return 0.0;
        }
        let (a, b) = (o[i], o[(i + 1) % n]);
        // Left of a->b: (b - a) x (p - a) >= 0, as a*x + b*y + c.
        let e = b - a;
        if e.length_squared() <= EDGE_EPS * EDGE_EPS {
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
                if area2(cur) > 2.0 * AREA_EPS {
                    keep(cur, out, pool);
                }
                return 0.0;
            }
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
            if area2(cur) > 2.0 * AREA_EPS {
                keep(cur, out, pool);
            }
            return 0.0;
        }
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
    if cur.len() < 3 {
        0.0
    } else {
        area2(cur)
    }
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
        subtract(&piece, &sliver, &mut out, &mut a, &mut b, &mut pool);
        let left: f64 = out.iter().map(|p| area2(p)).sum();
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
        subtract(&small, &with_debris, &mut out, &mut a, &mut b, &mut pool);
        let left: f64 = out.iter().map(|p| area2(p)).sum();
        assert!(left.abs() < 1e-12, "{out:?}");
        out.clear();
        subtract(&tri, &tri, &mut out, &mut a, &mut b, &mut pool);
        assert!(out.iter().map(|p| area2(p)).sum::<f64>().abs() < 1e-12);
    }
}

/// The sweep, the pairwise subtraction and the occlusion cull against each
/// other and against the independent reference.
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
    /// (occlusion cull, sweep, and pairwise where the sweep's order fails)
    /// against the reference, which shares none of that code.
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

    fn areas(seen: &[(u32, f64)], n: usize) -> Vec<f64> {
        let mut out = vec![0.0; n];
        for &(i, a) in seen {
            out[i as usize] += a;
        }
        out
    }

    fn triangle() -> impl Strategy<Value = [f64; 6]> {
        proptest::array::uniform6(-0.5f64..1.5)
    }

    proptest! {
        /// Where the sweep accepts its order, it finds the areas the
        /// pairwise subtraction finds; with flat planes at distinct depths
        /// it always accepts.
        #[test]
        fn the_sweep_agrees_with_pairwise_subtraction(
            tris in proptest::collection::vec(
                (triangle(), (-0.3f64..0.3, -0.3f64..0.3, -1.0f64..1.0), any::<bool>()),
                4..12,
            )
        ) {
            let tris: Vec<([f64; 6], [f64; 3])> = tris
                .iter()
                .map(|(t, (a, b, c), flat)| (*t, if *flat { [0.0, 0.0, *c] } else { [*a, *b, *c] }))
                .collect();
            let all_flat = tris.iter().all(|(_, p)| p[0] == 0.0 && p[1] == 0.0);
            let (locals, frags, arena) = pixel_frags(&tris);
            let square = super::super::pixel_square(0, 0);
            let mut s = Scratch::default();
            s.qc.extend(frags.iter().map(|f| locals[f.poly as usize].q(0.5, 0.5)));
            s.alive.resize(frags.len(), true);
            s.live.extend(0..frags.len() as u32);
            subtract_pairwise(&locals, &frags, &arena, &square, &mut s);
            let pairwise = areas(&s.seen, frags.len());
            let accepted = sweep_front_to_back(&locals, &frags, &arena, &square, &mut s);
            prop_assert!(accepted || !all_flat, "flat layers must sweep");
            if accepted {
                let swept = areas(&s.seen, frags.len());
                for (i, (p, w)) in pairwise.iter().zip(&swept).enumerate() {
                    prop_assert!((p - w).abs() <= 1e-9, "fragment {i}: pairwise {p}, sweep {w}");
                }
            }
        }
    }
}
