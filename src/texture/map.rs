//! Where a pattern lies on a projected polygon: the map from screen pixels to
//! texel coordinates (u, v), for the "object" and "uv" placements of docs/stream-format.md.
//!
//! Texture coordinates are affine over a planar polygon in world space, and a
//! perspective projection makes `u/w`, `v/w` and `1/w` affine over the screen
//! (the perspective-correct interpolation of OpenGL's chapter 7 and of XGL's
//! `PERSP_CORRECT`). So `u = U(x, y) / D(x, y)` with `U`, `V`, `D` affine in
//! screen coordinates: `D = 1/w` for perspective views and `D = 1` for parallel
//! ones. The map is exact for planar polygons; it is fitted once per polygon,
//! from its clipped vertices, by the same Newell fit as the nearness.
//!
//! Because `D > 0` on the visible polygon, the cell boundary `u = k` is the
//! straight screen line `U - k D = 0`: a texel cell seen on the screen is a
//! convex quadrilateral, and a fragment can be cut along it exactly.

use crate::geom::{map_to_plane, Grid, GridError, Placement, PlaneError};
use crate::view::{clip, View};
use glam::{DVec2, DVec3, DVec4};

/// A projective map from the screen (pixels, y up) to texel space.
#[derive(Clone, Debug, PartialEq)]
pub struct TexMap {
    /// `u * D`, affine: `[a, b, c]` for `a*x + b*y + c`.
    pub u: [f64; 3],
    /// `v * D`, affine.
    pub v: [f64; 3],
    /// The common denominator, affine and positive over the polygon.
    pub d: [f64; 3],
}

#[inline]
fn eval(p: [f64; 3], x: f64, y: f64) -> f64 {
    p[0] * x + p[1] * y + p[2]
}

impl TexMap {
    /// Texel coordinates of a screen point.
    #[inline]
    pub fn uv(&self, x: f64, y: f64) -> DVec2 {
        let d = eval(self.d, x, y);
        DVec2::new(eval(self.u, x, y) / d, eval(self.v, x, y) / d)
    }

    /// Texel coordinates of a screen point and the map's Jacobian there:
    /// `d(u, v)/dx` and `d(u, v)/dy`, in texels per pixel. With `u = U / D`,
    /// `du/dx = (U_x - u D_x) / D` (the quotient rule on affine `U`, `D`).
    /// `None` where `D <= 0` (beyond the polygon's horizon, where the map
    /// means nothing) or the result is not finite.
    #[inline]
    pub fn footprint(&self, x: f64, y: f64) -> Option<Footprint> {
        let d = eval(self.d, x, y);
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let uv = DVec2::new(eval(self.u, x, y) / d, eval(self.v, x, y) / d);
        let dx = DVec2::new(
            (self.u[0] - uv.x * self.d[0]) / d,
            (self.v[0] - uv.y * self.d[0]) / d,
        );
        let dy = DVec2::new(
            (self.u[1] - uv.x * self.d[1]) / d,
            (self.v[1] - uv.y * self.d[1]) / d,
        );
        (uv.is_finite() && dx.is_finite() && dy.is_finite()).then_some(Footprint { uv, dx, dy })
    }

    /// The screen half-plane `u >= k` (`keep_above`) or `u <= k`, as
    /// `[a, b, c]` with `a*x + b*y + c >= 0` inside (valid where `D > 0`).
    #[inline]
    pub fn u_side(&self, k: f64, keep_above: bool) -> [f64; 3] {
        side(self.u, self.d, k, keep_above)
    }

    /// The screen half-plane `v >= j` or `v <= j`.
    #[inline]
    pub fn v_side(&self, j: f64, keep_above: bool) -> [f64; 3] {
        side(self.v, self.d, j, keep_above)
    }

    /// Fits the map of a world polygon with texture coordinates `uv` at its
    /// vertices: the polygon is clipped to the view volume exactly as the
    /// rasterizer clips it ([`crate::view::clip::clip_carrying`]), carrying (u, v), and `U`, `V`, `D` are fitted through the
    /// clipped vertices. `None` when nothing is visible or the fit degenerates.
    ///
    /// `perspective_correct = false` interpolates (u, v) linearly over the
    /// screen instead (`D = 1`): XGL's `PERSP_NONE`, exact only for parallel
    /// views, kept to reproduce images made that way.
    pub fn fit(
        view: &View,
        world: &[DVec3],
        uv: &[DVec2],
        perspective_correct: bool,
    ) -> Option<TexMap> {
        let projective = view.perspective && perspective_correct;
        let pairs: Vec<(DVec4, DVec2)> = world
            .iter()
            .zip(uv)
            .map(|(&p, &t)| (view.to_clip(p), t))
            .collect();
        if pairs.iter().any(|(c, t)| !c.is_finite() || !t.is_finite()) {
            return None;
        }
        let clipped = clip::clip_carrying(&pairs, view);
        if clipped.len() < 3 {
            return None;
        }
        let mut pts = Vec::with_capacity(clipped.len());
        let (mut us, mut vs, mut ds) = (Vec::new(), Vec::new(), Vec::new());
        for (c, t) in &clipped {
            let s = view.to_screen(*c);
            let d = if projective { 1.0 / c.w } else { 1.0 };
            if pts.last() == Some(&s) {
                continue;
            }
            pts.push(s);
            us.push(t.x * d);
            vs.push(t.y * d);
            ds.push(d);
        }
        while pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
            us.pop();
            vs.pop();
            ds.pop();
        }
        if pts.len() < 3 {
            return None;
        }
        let u = crate::geom::polygon::newell_plane(&pts, &us)?;
        let v = crate::geom::polygon::newell_plane(&pts, &vs)?;
        let d = if projective {
            crate::geom::polygon::newell_plane(&pts, &ds)?
        } else {
            [0.0, 0.0, 1.0]
        };
        Some(TexMap { u, v, d })
    }
}

/// A pixel's footprint in texel space to first order: the point and the
/// images of the pixel's x and y steps (the Jacobian's columns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Texel coordinates `(u, v)` of the screen point.
    pub uv: DVec2,
    /// `d(u, v)/dx`: the image of one pixel step right, in texels.
    pub dx: DVec2,
    /// `d(u, v)/dy`: the image of one pixel step up, in texels.
    pub dy: DVec2,
}

impl Footprint {
    /// OpenGL's scale factor rho: texels per pixel along the longer of the
    /// two mapped pixel steps (GL 1.x spec, 3.8.8, `max(|dx|, |dy|)`).
    #[inline]
    pub fn rho(&self) -> f64 {
        self.dx.length().max(self.dy.length())
    }
}

fn side(n: [f64; 3], d: [f64; 3], k: f64, keep_above: bool) -> [f64; 3] {
    let l = [n[0] - k * d[0], n[1] - k * d[1], n[2] - k * d[2]];
    if keep_above {
        l
    } else {
        l.map(|c| -c)
    }
}

/// Why [`object_uv`] cannot place a pattern on a polygon: the polygon has no
/// plane, or the placement no grid.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectUvError {
    /// The polygon has no plane frame (too few vertices, no area, not planar).
    Plane(PlaneError),
    /// The placement gives no texel grid on the polygon's plane.
    Grid(GridError),
}

impl std::fmt::Display for ObjectUvError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ObjectUvError::Plane(e) => e.fmt(f),
            ObjectUvError::Grid(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ObjectUvError {}

/// docs/stream-format.md object placement, computed by `polyfill3`'s own functions: the
/// plane frame of [`map_to_plane`] and the grid of [`Grid::new`], so that
/// `u = (x - xmin)/incr - horz`, `v = (y - ymin)/incr - vert` at each vertex.
/// The texel cell (k, j) then spans exactly `polyfill3`'s cell (k, j), from
/// `Grid::gx(k)` to `Grid::gx(k+1)`.
pub fn object_uv(
    world: &[DVec3],
    place: Placement,
    rotate_deg: f64,
    planarity_tol: f64,
) -> Result<Vec<DVec2>, ObjectUvError> {
    let poly = map_to_plane(world, rotate_deg, planarity_tol).map_err(ObjectUvError::Plane)?;
    let grid = Grid::new(&poly.points, place).map_err(ObjectUvError::Grid)?;
    Ok(poly
        .points
        .iter()
        .map(|p| {
            DVec2::new(
                (p.x - grid.xmin) / place.incr - place.horz,
                (p.y - grid.ymin) / place.incr - place.vert,
            )
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jacobian_matches_finite_differences() {
        let view = crate::view::tests::perspective(70.0, 64, 64, 0.1, 100.0);
        let world = [
            DVec3::new(-1.0, -1.0, -1.5),
            DVec3::new(1.0, -1.0, -1.5),
            DVec3::new(1.0, -1.0, -6.0),
        ];
        let uv = [DVec2::ZERO, DVec2::new(8.0, 0.0), DVec2::new(8.0, 16.0)];
        let m = TexMap::fit(&view, &world, &uv, true).unwrap();
        let (x, y) = (36.3, 12.7);
        let f = m.footprint(x, y).unwrap();
        // Central differences of step h: error O(h²) times the second
        // derivative, ~1e-8 here; 1e-6 leaves room.
        let h = 1e-4;
        let ddx = (m.uv(x + h, y) - m.uv(x - h, y)) / (2.0 * h);
        let ddy = (m.uv(x, y + h) - m.uv(x, y - h)) / (2.0 * h);
        assert!((f.dx - ddx).length() < 1e-6, "{} {}", f.dx, ddx);
        assert!((f.dy - ddy).length() < 1e-6, "{} {}", f.dy, ddy);
        assert_eq!(f.uv, m.uv(x, y));
        assert!(f.rho() >= f.dx.length());
    }

    #[test]
    fn a_parallel_view_maps_texels_affinely() {
        let view = View::ortho2(0.0, 10.0, 0.0, 10.0, 10, 10);
        let world = [
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(9.0, 1.0, 0.0),
            DVec3::new(9.0, 5.0, 0.0),
        ];
        let uv = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(4.0, 2.0)];
        let m = TexMap::fit(&view, &world, &uv, true).unwrap();
        let at = m.uv(5.0, 3.0);
        assert!((at - DVec2::new(2.0, 1.0)).length() < 1e-12, "{at}");
    }

    #[test]
    fn a_perspective_view_interpolates_perspective_correctly() {
        let view = crate::view::tests::perspective(90.0, 100, 100, 0.1, 100.0);
        // A floor square from z = -1 to z = -3, u across, v along depth.
        let world = [
            DVec3::new(-1.0, -1.0, -1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(1.0, -1.0, -3.0),
            DVec3::new(-1.0, -1.0, -3.0),
        ];
        let uv = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let m = TexMap::fit(&view, &world, &uv, true).unwrap();
        // World point (0, -1, -2) is uv (1, 1); it projects to x = 50,
        // y = 50 - 50/2 = 25 (f = 1, w = 2).
        let at = m.uv(50.0, 25.0);
        assert!((at - DVec2::new(1.0, 1.0)).length() < 1e-9, "{at}");
        // Affine interpolation would put v = 1 at the screen midpoint of the
        // near (y = 0) and far (y = 100/3) edges instead.
        let mid = m.uv(50.0, 50.0 / 3.0);
        assert!((mid.y - 1.0).abs() > 0.1, "{mid}");
        // ... which is what PERSP_NONE does.
        let none = TexMap::fit(&view, &world, &uv, false).unwrap();
        let mid = none.uv(50.0, 50.0 / 3.0);
        assert!((mid.y - 1.0).abs() < 1e-9, "{mid}");
    }

    #[test]
    fn object_placement_is_polyfill3s_grid() {
        let world = [
            DVec3::new(0.5, 0.25, 0.0),
            DVec3::new(4.5, 0.25, 0.0),
            DVec3::new(4.5, 3.25, 0.0),
            DVec3::new(0.5, 3.25, 0.0),
        ];
        let place = Placement {
            incr: 0.5,
            horz: 0.5,
            vert: -1.0,
        };
        let uv = object_uv(&world, place, 0.0, 1e-6).unwrap();
        // Vertex 0 is the lower-left: u = -horz, v = -vert.
        assert!((uv[0] - DVec2::new(-0.5, 1.0)).length() < 1e-12);
        // Vertex 2: 4 units right, 3 up, in 0.5-unit texels.
        assert!((uv[2] - DVec2::new(7.5, 7.0)).length() < 1e-12);
    }
}
