//! The exact resolver's input per tile: a dense copy of what it reads of
//! each polygon of the tile's bin.
//!
//! `--aa exact` reads each polygon of a tile row by row and looks up the
//! plane of each pixel's earlier fragments many times. Read through
//! `ScreenPoly` (a struct, then its piece list, then each piece's vertices,
//! all on the heap), a tile of small triangles from a million-polygon scene
//! misses the cache at every step; gathered once, by the thread that
//! renders the tile, the tile's geometry is a few contiguous arrays. (Gathering every tile in
//! one pass over the polygons first measured the same and held every tile's
//! copy at once: 0.9 GB instead of 0.74 GB peak on a million triangles.)
//!
//! The copy is laid out in the order the resolver sweeps the tile, nearest
//! polygon first, so that it reads the arrays front to back: read in stream
//! order through a sorted index, the load of each polygon's flags missed
//! the cache and took 16% of the tile's time.

use super::visible::bounds;
use super::{ScreenPoly, Shader};
use glam::DVec2;

/// What visibility needs of a polygon. Fragments name it by its index in
/// [`TileGeom::locals`].
#[derive(Clone, Copy, Debug)]
pub struct Local {
    /// Nearness `q = a*x + b*y + c`, as [`ScreenPoly::plane`].
    pub plane: [f64; 3],
    /// Absolute part of the tie tolerance: the frame's [`super::tie_floor`].
    pub tie_floor: f64,
    /// Position in the stream, as [`ScreenPoly::order`]: on a depth tie the
    /// later polygon wins.
    pub order: u32,
    /// Index in the frame's polygon list, for its texture or screen pattern.
    pub global: u32,
    /// The flat colour, or `None` when a screen-mode pattern decides it.
    pub color: Option<[f64; 3]>,
    /// Neither textured nor striped: every fragment has the polygon's colour,
    /// and the fragment maker needs nothing else of it.
    pub plain: bool,
    /// Its fragments may be dropped unseen: all but textures under
    /// `--no-skip hidden`, which the benchmark filters hidden or not.
    pub cullable: bool,
}

impl Local {
    /// The copy of `p`, which is polygon `global` of the frame's list,
    /// projected with the tie floor `tie_floor`.
    pub fn new(p: &ScreenPoly, global: u32, tie_floor: f64) -> Local {
        Local {
            plane: p.plane,
            tie_floor,
            order: p.order(),
            global,
            color: p.screen().is_none().then_some(p.color),
            plain: matches!(p.shader(), Shader::Flat | Shader::Screen(_)) && p.shade().is_none(),
            cullable: p.texture().is_none_or(|t| t.skips.hidden),
        }
    }

    /// Nearness at a screen point, as [`ScreenPoly::q`].
    #[inline]
    pub fn q(&self, x: f64, y: f64) -> f64 {
        self.plane[0] * x + self.plane[1] * y + self.plane[2]
    }

    /// How far the nearness can move from a pixel's centre within the
    /// pixel: half a step in x and in y.
    #[inline]
    pub fn half_spread(&self) -> f64 {
        0.5 * (self.plane[0].abs() + self.plane[1].abs())
    }
}

/// Pieces with more vertices than this are not copied into each tile they
/// meet but read where they are: a polygon of a million vertices spanning a
/// 1024x768 frame's 768 tiles would otherwise be copied 768 times (12 GB). Small
/// pieces, the many that make a scene deep, are the ones worth copying.
pub const GATHER_MAX_VERTS: usize = 64;

/// One convex piece of a polygon in a tile: `len` vertices from `start` in
/// [`TileGeom::verts`], or, when `len` is `IN_PLACE` (`u32::MAX`), piece `start` of
/// the polygon itself (a large one, see [`GATHER_MAX_VERTS`]).
#[derive(Clone, Copy, Debug)]
pub struct PieceRef {
    /// The piece's polygon: its index in [`TileGeom::locals`].
    pub local: u32,
    /// First vertex in [`TileGeom::verts`]; for a piece read in place, the
    /// piece's index in its polygon (see [`ScreenPoly::piece`]).
    pub start: u32,
    /// Number of vertices, or `IN_PLACE` (`u32::MAX`) for a piece read in place.
    pub len: u32,
    /// Bounding box `[x0, y0, x1, y1]` of the piece.
    pub bb: [f64; 4],
}

/// [`PieceRef::len`] of a piece read in place.
const IN_PLACE: u32 = u32::MAX;

/// The polygons whose bounding box meets one tile, nearest first (see
/// [`TileGeom::gather`]).
#[derive(Default, Debug)]
pub struct TileGeom {
    /// The bin's polygons, nearest first (the sweep order).
    pub locals: Vec<Local>,
    /// Their convex pieces, polygon by polygon in the order of `locals`.
    pub pieces: Vec<PieceRef>,
    /// The copied vertices of the small pieces, screen pixels, y up.
    pub verts: Vec<DVec2>,
    /// The bin in sweep order: nearness bound, stream order, polygon.
    keyed: Vec<(f64, u32, u32)>,
}

/// The least nearness of `plane` over the pixel box `bbox` clipped to
/// `tile`: how near the polygon is at its farthest there, the key of the
/// sweep order.
///
/// Any order gives the same areas (a fragment met out of order overtakes
/// what it is in front of, `visible::PixelStates`); the order decides how
/// often that happens and how many fragments are dropped as hidden. The
/// greatest nearness, a bound of the polygon's nearness anywhere it can
/// show, was the key before: it brings a steep polygon early for its near
/// tip, and its far part then lies under what comes after. By the least,
/// a polygon comes once all of it is nearer than what is still to come.
/// Render phase of `bench/aa_scaling.sh`'s triangles (one run each), by
/// the greatest and by the least: 100,000 `auto` 0.94 and 0.73 s, 200,000
/// `auto` 1.61 and 1.20, 100,000 20-pixel 1.32 and 0.87, 200,000 20-pixel
/// 2.67 and 1.50. Flat polygons (most 2D scenes) have one nearness
/// over the box, and come in the same order either way.
fn farthest_in(plane: &[f64; 3], bbox: [u32; 4], tile: [u32; 4]) -> f64 {
    nearness_range(plane, bbox, tile).0
}

/// The least and greatest nearness of `plane` over the pixel box `bbox`
/// clipped to `tile`: an affine function's extremes over a box are at its
/// corners, taken axis by axis. The sweep order's key ([`farthest_in`]) and
/// the layered test of a deep square (`coverage::layered`) read it.
#[inline]
pub(super) fn nearness_range(plane: &[f64; 3], bbox: [u32; 4], tile: [u32; 4]) -> (f64, f64) {
    let x = [bbox[0].max(tile[0]) as f64, bbox[2].min(tile[2]) as f64];
    let y = [bbox[1].max(tile[1]) as f64, bbox[3].min(tile[3]) as f64];
    let [a, b, c] = *plane;
    let ((ax0, ax1), (by0, by1)) = ((a * x[0], a * x[1]), (b * y[0], b * y[1]));
    (
        c + ax0.min(ax1) + by0.min(by1),
        c + ax0.max(ax1) + by0.max(by1),
    )
}

impl TileGeom {
    /// Appends polygon `pi` of `polys`.
    fn push(&mut self, polys: &[ScreenPoly], pi: u32, tie_floor: f64) {
        let p = &polys[pi as usize];
        let local = self.locals.len() as u32;
        self.locals.push(Local::new(p, pi, tie_floor));
        for k in 0..p.piece_count() {
            let piece = p.piece(k);
            let bb = bounds(piece);
            if piece.len() > GATHER_MAX_VERTS {
                self.pieces.push(PieceRef {
                    local,
                    start: k as u32,
                    len: IN_PLACE,
                    bb,
                });
                continue;
            }
            self.pieces.push(PieceRef {
                local,
                start: self.verts.len() as u32,
                len: piece.len() as u32,
                bb,
            });
            self.verts.extend_from_slice(piece);
        }
    }

    /// The vertices of a piece (`polys`: the frame's polygons, for a piece
    /// read in place).
    #[inline]
    pub fn piece<'a>(&'a self, polys: &'a [ScreenPoly], r: &PieceRef) -> &'a [DVec2] {
        if r.len == IN_PLACE {
            let global = self.locals[r.local as usize].global;
            polys[global as usize].piece(r.start as usize)
        } else {
            &self.verts[r.start as usize..(r.start + r.len) as usize]
        }
    }

    /// Replaces the contents with the geometry of one tile's bin (see
    /// [`super::bin`]), in the order `coverage::render_tile`
    /// sweeps it: nearest first by the least nearness of the polygon's
    /// box in the tile (`farthest_in`); on a tie the later polygon first, as the tie rule
    /// decides; then the stream, so that the order is total. (Gathering in
    /// stream order and sorting the copy measured 1.07x slower.) `boxed`
    /// is the bin with each polygon's [`ScreenPoly::bbox`]
    /// ([`super::boxed`]); the
    /// polygons were projected with the tie floor `tie_floor`
    /// ([`super::tie_floor`]).
    pub fn gather(
        &mut self,
        polys: &[ScreenPoly],
        boxed: &[(u32, [u32; 4])],
        tile: [u32; 4],
        tie_floor: f64,
    ) {
        self.locals.clear();
        self.pieces.clear();
        self.verts.clear();
        let mut keyed = std::mem::take(&mut self.keyed);
        keyed.clear();
        keyed.extend(boxed.iter().map(|&(pi, bbox)| {
            let p = &polys[pi as usize];
            (farthest_in(&p.plane, bbox, tile), p.order(), pi)
        }));
        keyed.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)).then(a.2.cmp(&b.2)));
        for &(_, _, pi) in &keyed {
            self.push(polys, pi, tie_floor);
        }
        self.keyed = keyed;
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{exact_off_reference, poly2};
    use super::super::Background;
    use super::*;
    use crate::color::Rgb8;
    use crate::view::View;

    /// A regular `n`-gon of radius `r` about `(c, c)`.
    fn ngon(n: usize, c: f64, r: f64) -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                let a = k as f64 / n as f64 * std::f64::consts::TAU;
                [c + r * crate::math::cos(a), c + r * crate::math::sin(a)]
            })
            .collect()
    }

    /// Every tile sees each of its polygons' pieces exactly: small ones from
    /// its copy, large ones in place.
    #[test]
    fn tiles_see_small_pieces_copied_and_large_ones_in_place() {
        let v = View::ortho2(0.0, 200.0, 0.0, 200.0, 200, 200);
        let polys = vec![
            poly2(
                &v,
                &ngon(GATHER_MAX_VERTS + 36, 100.0, 90.0),
                Rgb8::WHITE,
                0,
            )
            .unwrap(),
            poly2(
                &v,
                &[[10.0, 10.0], [150.0, 20.0], [60.0, 170.0]],
                Rgb8::BLACK,
                1,
            )
            .unwrap(),
        ];
        let floor = super::super::tie_floor(&v);
        let mut g = TileGeom::default();
        let boxed: Vec<_> = super::super::boxed(&polys, &[0, 1]).collect();
        g.gather(&polys, &boxed, [0, 0, 200, 200], floor);
        assert_eq!(g.verts.len(), 3, "only the triangle is copied");
        for r in &g.pieces {
            let whole = polys[g.locals[r.local as usize].global as usize].piece(0);
            assert_eq!(g.piece(&polys, r), whole);
        }
        let bins = super::super::bin(&polys, 200, 200);
        let tiles = super::super::tiles(200, 200);
        for (t, tile) in tiles.iter().enumerate() {
            let boxed: Vec<_> = super::super::boxed(&polys, &bins[t]).collect();
            g.gather(&polys, &boxed, *tile, floor);
            for r in &g.pieces {
                let whole = polys[g.locals[r.local as usize].global as usize].piece(0);
                assert_eq!(g.piece(&polys, r), whole, "tile {t}");
            }
        }
    }

    /// A polygon read in place renders as the reference says, across tiles.
    #[test]
    fn a_large_polygon_across_tiles_matches_the_reference() {
        let v = View::ortho2(0.0, 150.0, 0.0, 150.0, 150, 150);
        let polys = vec![
            poly2(&v, &ngon(500, 75.0, 70.3), Rgb8([200, 100, 50]), 0).unwrap(),
            poly2(
                &v,
                &[[5.5, 5.5], [140.0, 30.2], [40.7, 120.1]],
                Rgb8([20, 90, 200]),
                1,
            )
            .unwrap(),
        ];
        let bg = Background::color(Rgb8::BLACK);
        let worst = exact_off_reference(&polys, &bg, &v);
        assert!(worst <= 1, "off by {worst}");
    }
}
