//! The 2D polygon kernel: signed area, exact orientation, half-plane
//! clipping, convexity and plane fitting on screen or plane coordinates, with
//! the named tolerances they share (triangulation is [`super::triangulate`]).
//! Every stage that cuts polygons (the exact resolver, the texel cells, the
//! stripe integrals, the partition) uses these, so a rounding rule is decided
//! once.

use glam::DVec2;

/// Areas (in pixels) below this are rounding noise, not geometry: f64 shoelace
/// areas of unit-scale fragments are exact to ~1e-15, while the smallest area
/// that can change an 8-bit sRGB value is ~1e-6 (1/255 of the darkest step).
pub const AREA_EPS: f64 = 1e-12;

/// Screen coordinates within this many pixels of a whole or half pixel are
/// moved onto it: the viewport map's rounding (1e-15 px) would otherwise make
/// a pixel-aligned 2D rectangle cover its border pixels by 1 - 1e-15. Any
/// geometry this close to the grid is on it for every purpose of 8-bit output.
pub const GRID_SNAP_PX: f64 = 1e-9;

/// The square of pixel `(px, py)` (y up), counter-clockwise from its
/// lower-left corner: the box filter's footprint.
pub fn pixel_square(px: u32, py: u32) -> [DVec2; 4] {
    let (x, y) = (px as f64, py as f64);
    [
        DVec2::new(x, y),
        DVec2::new(x + 1.0, y),
        DVec2::new(x + 1.0, y + 1.0),
        DVec2::new(x, y + 1.0),
    ]
}

/// The mean of a convex polygon's vertices: a point inside it (where the
/// texture filters are evaluated for a fragment whose pixel centre may lie
/// outside it, beyond a plane's horizon).
pub fn vertex_mean(v: &[DVec2]) -> DVec2 {
    v.iter().fold(DVec2::ZERO, |a, &p| a + p) / v.len() as f64
}

/// Twice the signed area of the triangle `a, b, c`, with the exact sign:
/// positive when they turn counter-clockwise (y up), negative clockwise, and
/// zero only when they are exactly collinear. Shewchuk's adaptive predicate
/// (the `robust` crate): the plain cross product, exact in most cases, is
/// extended to exact arithmetic only when its rounding could flip the sign.
/// Every combinatorial decision of the simplicity test ([`super::simple`]) and
/// the triangulation ([`super::triangulate`]) goes through this, so they never
/// disagree with each other or with themselves about which side a point lies on.
#[inline]
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let p = |v: DVec2| robust::Coord { x: v.x, y: v.y };
    robust::orient2d(p(a), p(b), p(c))
}

/// Twice the signed area (shoelace), positive counter-clockwise with y up.
///
/// Taken about the first vertex, so the rounding error follows the polygon's
/// own size, not its distance from the origin: the plain shoelace on screen
/// coordinates near (1000, 1000) rounds with an absolute error of ~1e-10
/// (|x|·|y|·ε per term), which made a clipping sliver with 1e-12-pixel edges
/// count as an area above [`AREA_EPS`] and, as an occluder, erase a
/// whole texel piece behind it (regression test
/// `raster::coverage::tests::a_sliver_occluder_far_from_the_origin_hides_nothing`).
///
/// Inlined: the exact sweep calls it for each piece a subtraction keeps.
#[inline]
pub fn area2(v: &[DVec2]) -> f64 {
    let Some(&o) = v.first() else {
        return 0.0;
    };
    let mut s = 0.0;
    for w in v.windows(2).skip(1) {
        s += (w[0] - o).perp_dot(w[1] - o);
    }
    s
}

/// A signed distance to a clip plane, positive on the kept side: a plain
/// `f64`, or the view clipper's exact double-double value (`view::clip`'s
/// `Distance`), whose crossings keep both ends' values for the exact one.
pub trait SignedDistance: Copy {
    /// What says where along an edge the crossing is.
    type Param;
    /// The distance rounded to `f64`, whose sign decides inside and outside.
    fn rounded(self) -> f64;
    /// Where the edge from the inside point to the outside one crosses the
    /// plane (for `f64`, `inside / (inside - outside)`).
    fn crossing(inside: Self, outside: Self) -> Self::Param;
}

impl SignedDistance for f64 {
    type Param = f64;
    fn rounded(self) -> f64 {
        self
    }
    fn crossing(inside: f64, outside: f64) -> f64 {
        inside / (inside - outside)
    }
}

/// One Sutherland–Hodgman pass: keeps the part where `d(p) >= 0`. `lerp(inside,
/// outside, t)` makes the crossing, always from the inside endpoint.
pub fn clip_against<T: Copy, D: SignedDistance>(
    poly: &[T],
    d: impl Fn(T) -> D,
    out: &mut Vec<T>,
    lerp: impl Fn(T, T, D::Param) -> T,
) {
    let n = poly.len();
    if n == 0 {
        return;
    }
    let mut db = d(poly[0]);
    for i in 0..n {
        // Not `(i + 1) % n`: a division per edge, on the render's hottest
        // path (fragments are cut into rows and pixels by this).
        let j = if i + 1 == n { 0 } else { i + 1 };
        let (a, b, da) = (poly[i], poly[j], db);
        db = d(b);
        let (ra, rb) = (da.rounded(), db.rounded());
        if ra >= 0.0 {
            out.push(a);
            if rb < 0.0 && ra > 0.0 {
                out.push(lerp(a, b, D::crossing(da, db)));
            }
        } else if rb > 0.0 {
            out.push(lerp(b, a, D::crossing(db, da)));
        }
    }
}

/// Clips a 2D polygon to `coord(p) >= value` (`keep_above`) or `<= value`,
/// where `coord` is x (`axis = 0`) or y (`axis = 1`). New vertices get exactly
/// `value` on that axis, so the pieces of a pixel grid meet without gaps.
///
/// Inlined so that callers' constant `axis` and `keep_above` pick one of
/// four copies with the choice made at compile time (`clip_axis_as`):
/// the exact sweep cuts every fragment into a row and a pixel this way.
#[inline]
pub fn clip_axis(poly: &[DVec2], axis: usize, value: f64, keep_above: bool, out: &mut Vec<DVec2>) {
    match (axis == 0, keep_above) {
        (true, true) => clip_axis_as::<0, true>(poly, value, out),
        (true, false) => clip_axis_as::<0, false>(poly, value, out),
        (false, true) => clip_axis_as::<1, true>(poly, value, out),
        (false, false) => clip_axis_as::<1, false>(poly, value, out),
    }
}

/// [`clip_axis`] for one axis and side.
fn clip_axis_as<const AXIS: usize, const KEEP_ABOVE: bool>(
    poly: &[DVec2],
    value: f64,
    out: &mut Vec<DVec2>,
) {
    let d = |p: DVec2| {
        let c = if AXIS == 0 { p.x } else { p.y };
        if KEEP_ABOVE {
            c - value
        } else {
            value - c
        }
    };
    clip_against(poly, d, out, |a, b, t| {
        let mut p = a + (b - a) * t;
        if AXIS == 0 {
            p.x = value;
        } else {
            p.y = value;
        }
        p
    });
}

/// Clips a 2D polygon to the half-plane `a*x + b*y + c >= 0`.
pub fn clip_line(poly: &[DVec2], abc: [f64; 3], out: &mut Vec<DVec2>) {
    let d = |p: DVec2| abc[0] * p.x + abc[1] * p.y + abc[2];
    clip_against(poly, d, out, |a, b, t| a + (b - a) * t);
}

/// The affine nearness `q(x, y)` through a planar polygon's screen vertices, by
/// Newell's method on the points `(x, y, q)`: it uses every vertex, so it stays
/// well conditioned for slivers where any three vertices would not.
pub fn newell_plane(v: &[DVec2], q: &[f64]) -> Option<[f64; 3]> {
    let n = v.len();
    let (mut nx, mut ny, mut nz) = (0.0, 0.0, 0.0);
    let (mut cx, mut cy, mut cq) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let j = (i + 1) % n;
        nx += (v[i].y - v[j].y) * (q[i] + q[j]);
        ny += (q[i] - q[j]) * (v[i].x + v[j].x);
        nz += (v[i].x - v[j].x) * (v[i].y + v[j].y);
        cx += v[i].x;
        cy += v[i].y;
        cq += q[i];
    }
    let k = n as f64;
    let (cx, cy, cq) = (cx / k, cy / k, cq / k);
    if nz == 0.0 {
        return None;
    }
    let a = -nx / nz;
    let b = -ny / nz;
    let plane = [a, b, cq - a * cx - b * cy];
    plane.iter().all(|c| c.is_finite()).then_some(plane)
}

/// The area centroid of a polygon; `None` for fewer than three vertices or
/// no area (a sliver whose centroid is not defined: the caller uses the pixel
/// centre, which a fragment of no area cannot make visibly wrong).
pub fn area_centroid(poly: &[DVec2]) -> Option<DVec2> {
    if poly.len() < 3 {
        return None;
    }
    // Relative to the first vertex: pixel coordinates near 1000 would
    // otherwise cancel in the cross products.
    let o = poly[0];
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..poly.len() {
        let (p, q) = (poly[i] - o, poly[(i + 1) % poly.len()] - o);
        let cross = p.x * q.y - q.x * p.y;
        a2 += cross;
        cx += (p.x + q.x) * cross;
        cy += (p.y + q.y) * cross;
    }
    let (x, y) = (o.x + cx / (3.0 * a2), o.y + cy / (3.0 * a2));
    (a2 != 0.0 && x.is_finite() && y.is_finite()).then_some(DVec2::new(x, y))
}

/// Relative tolerance of the convexity test: a turn against the polygon's
/// orientation smaller than this share of the product of the two edge lengths
/// counts as straight (clipping and projection leave such rounding-level kinks).
const CONVEX_REL: f64 = 1e-12;

/// Absolute tolerance of the convexity test, in pixels: a vertex at most this
/// far inside the chord of its neighbours still counts as convex. It is the
/// [`GRID_SNAP_PX`] by which projection may move a vertex, so the snap alone
/// never makes a convex outline concave: a 10-million-vertex circle of radius
/// 7 px has 4e-6 px edges, which a 1e-9 px move turns by 2e-4 rad, far above
/// [`CONVEX_REL`]. Drawing such a polygon whole misplaces at most ~1e-9 px²
/// per kink, far below 8 bits.
const CONVEX_ABS_PX: f64 = GRID_SNAP_PX;

/// Whether a counter-clockwise polygon is convex (collinear and repeated
/// vertices allowed).
pub fn is_convex(v: &[DVec2]) -> bool {
    let mut v: Vec<DVec2> = v.to_vec();
    v.dedup();
    while v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    let n = v.len();
    (0..n).all(|i| {
        let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
        let (e, f) = (b - a, c - b);
        // perp_dot / |c - a| is b's distance from the chord a-c.
        e.perp_dot(f)
            >= -(CONVEX_REL * e.length() * f.length()).max(CONVEX_ABS_PX * (c - a).length())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_centroid_is_exact_far_from_the_origin() {
        // A right triangle: centroid at the mean of its vertices, even far
        // from the origin (the computation is relative to the first vertex).
        let tri = [
            DVec2::new(1000.0, 700.0),
            DVec2::new(1001.0, 700.0),
            DVec2::new(1000.0, 701.0),
        ];
        let c = area_centroid(&tri).unwrap();
        assert!(
            (c.x - 1000.0 - 1.0 / 3.0).abs() < 1e-12 && (c.y - 700.0 - 1.0 / 3.0).abs() < 1e-12
        );
        assert_eq!(area_centroid(&tri[..2]), None);
        assert_eq!(area_centroid(&[tri[0], tri[0], tri[0]]), None);
    }
}
