//! The exact box filter for crisp patterns: a textured fragment cut into its
//! texel cells.
//!
//! A pattern is piecewise constant over texel squares in the polygon's plane
//! (SPEC §2; the thesis's texture point polygons). The box-filtered pixel is
//! therefore the sum, over the cells the pixel's visible part overlaps, of
//! the cell's colour times the exact area of (fragment ∩ cell) on the screen:
//! what `polyfill3 | scene-render --aa exact` draws, without writing one
//! polygon per texel. Under the projective map of [`super::map`] a cell is a
//! convex quadrilateral on the screen bounded by the lines `u = k`, `u = k+1`,
//! `v = j`, `v = j+1`, so a convex fragment is cut by four half-planes per
//! cell. Each piece then takes part in the exact visibility of
//! `raster::coverage` as a fragment of its own with the texel's colour, and a
//! transparent texel's piece is simply absent, leaving its area to whatever
//! lies behind.
//!
//! Minification: when a fragment spans more than [`MAX_EXACT_CELLS`] cells
//! (the texels are far smaller than the pixel), cutting it exactly costs more
//! than it is worth. The fragment is then cut into [`FALLBACK_SIDE`]²
//! sub-squares of the pixel instead, each taking the texel at its centre: an
//! area-weighted supersampling of the texture, documented as an approximation
//! (its error shows in `bench/RESULTS-texture.md` against `--reference`).

use super::PolyTexture;
use crate::raster::area2;
use crate::raster::clip::{clip_axis, clip_line};
use crate::raster::coverage::AREA_EPS;
use glam::DVec2;

/// Most texel cells (of the fragment's bounding box in texel space) cut
/// exactly. 64 = an 8x8 block of texels per pixel: the exact cut of every
/// cell stays cheaper than the 16 sub-squares of the fallback up to about
/// there, and a pixel over more texels than that is minified well past the
/// point where individual texel edges can be seen.
pub const MAX_EXACT_CELLS: i64 = 64;

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
}

/// One opaque piece: `len` vertices from `start` in the vertex arena.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub start: u32,
    pub len: u32,
    pub color: [f64; 3],
}

/// Reusable buffers.
#[derive(Default)]
pub struct Scratch {
    a: Vec<DVec2>,
    strip: Vec<DVec2>,
    b: Vec<DVec2>,
    cell: Vec<DVec2>,
}

/// Cuts the convex counter-clockwise fragment `frag` of pixel `(px, py)` of a
/// polygon textured by `tex`.
pub fn split(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    verts: &mut Vec<DVec2>,
    pieces: &mut Vec<Piece>,
    s: &mut Scratch,
) -> Split {
    let m = &tex.map;
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    for p in frag {
        let t = m.uv(p.x, p.y);
        lo = lo.min(t);
        hi = hi.max(t);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Split::Whole(None);
    }
    let (k0, j0) = (lo.x.floor() as i64, lo.y.floor() as i64);
    let k1 = (hi.x.ceil() as i64 - 1).max(k0);
    let j1 = (hi.y.ceil() as i64 - 1).max(j0);
    if k0 == k1 && j0 == j1 {
        return Split::Whole(tex.texel(k0, j0));
    }
    let cells = (k1 - k0 + 1).saturating_mul(j1 - j0 + 1);
    if cells > MAX_EXACT_CELLS {
        fallback(frag, px, py, tex, verts, pieces, s);
        return Split::Pieces;
    }
    for j in j0..=j1 {
        s.a.clear();
        clip_line(frag, m.v_side(j as f64, true), &mut s.a);
        s.strip.clear();
        clip_line(&s.a, m.v_side((j + 1) as f64, false), &mut s.strip);
        if s.strip.len() < 3 {
            continue;
        }
        for k in k0..=k1 {
            let Some(color) = tex.texel(k, j) else {
                continue;
            };
            s.b.clear();
            clip_line(&s.strip, m.u_side(k as f64, true), &mut s.b);
            s.cell.clear();
            clip_line(&s.b, m.u_side((k + 1) as f64, false), &mut s.cell);
            if s.cell.len() < 3 || area2(&s.cell) <= 2.0 * AREA_EPS {
                continue;
            }
            pieces.push(Piece {
                start: verts.len() as u32,
                len: s.cell.len() as u32,
                color,
            });
            verts.extend_from_slice(&s.cell);
        }
    }
    Split::Pieces
}

/// The minification fallback: [`FALLBACK_SIDE`]² sub-squares of the pixel,
/// each (clipped to the fragment, exact area) with the texel at its
/// vertex centroid, which lies inside the fragment.
fn fallback(
    frag: &[DVec2],
    px: u32,
    py: u32,
    tex: &PolyTexture,
    verts: &mut Vec<DVec2>,
    pieces: &mut Vec<Piece>,
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
            if s.cell.len() < 3 || area2(&s.cell) <= 2.0 * AREA_EPS {
                continue;
            }
            let c = s.cell.iter().fold(DVec2::ZERO, |a, &p| a + p) / s.cell.len() as f64;
            let t = tex.map.uv(c.x, c.y);
            let Some(color) = tex.texel(t.x.floor() as i64, t.y.floor() as i64) else {
                continue;
            };
            pieces.push(Piece {
                start: verts.len() as u32,
                len: s.cell.len() as u32,
                color,
            });
            verts.extend_from_slice(&s.cell);
        }
    }
}
