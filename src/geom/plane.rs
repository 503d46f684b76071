//! The plane of a 3D polygon and the 2D frame the pattern is laid in (docs/stream-format.md,
//! "object" mode; the thesis's `map_to_xy_plane`, ch. IV.B).
//!
//! The thesis rotates the polygon into the x-y plane with Euler angles about y
//! and x. That construction divides by the length of the normal's projection,
//! which vanishes when the normal lies along an axis. Here the normal is
//! Newell's (a sum over all edges, exact for any planar polygon and stable for
//! concave or nearly degenerate ones) and the frame is built directly:
//! +x along the first edge from vertex 0 that has length in the plane, rotated
//! by `rotate` degrees counter-clockwise about the normal, +y = n × x. There is
//! no special direction, so no singularity.
//!
//! Plane coordinates are measured from the vertices' centroid, not from the
//! world origin: a polygon 1e7 away from the origin keeps its full precision in
//! the plane. Only translation-invariant quantities (xmin, ymin, the grid)
//! depend on plane coordinates, so the choice of origin does not move the
//! pattern (docs/stream-format.md puts it at vertex 0; the offset cancels in `x - xmin`).

use super::polygon::area2;
use crate::math;
use crate::text::readable;
use glam::{DVec2, DVec3};
use smallvec::SmallVec;
use std::fmt;

/// A polygon whose area is at most this fraction of the square of its size
/// (bounding-box diagonal) is rejected as having no area: below it the normal's
/// direction is dominated by rounding and no frame is meaningful.
pub const ZERO_AREA_REL: f64 = 1e-12;

/// Default `--planarity-tol`: the largest distance of a vertex from the
/// polygon's best-fit plane, relative to the polygon's size. 1e-6 accepts
/// everything written out at single precision and rejects real mistakes.
pub const DEFAULT_PLANARITY_TOL: f64 = 1e-6;

/// An orthonormal frame in the polygon's plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Point of the plane that plane coordinates (0, 0) map to.
    pub origin: DVec3,
    /// Unit +x in the plane.
    pub ex: DVec3,
    /// Unit +y in the plane: `normal × ex`, 90° counter-clockwise from +x seen
    /// from the front.
    pub ey: DVec3,
    /// Unit normal, towards the front (the side the vertices are counter-clockwise from).
    pub normal: DVec3,
}

impl Frame {
    /// Plane coordinates of a world point (projected onto the plane).
    #[inline]
    pub fn to_plane(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.ex), d.dot(self.ey))
    }

    /// The world point of plane coordinates, evaluated as
    /// `(origin + ey*y) + ex*x` and never otherwise: a grid corner then has the
    /// same bits whichever cell computes it, and the partition can cache
    /// `origin + ey*y` per row and `ex*x` per column (see `partition`).
    #[inline]
    pub fn to_world(&self, p: DVec2) -> DVec3 {
        self.row_base(p.y) + self.ex * p.x
    }

    /// `origin + ey*y`: the world point of plane point (0, y).
    #[inline]
    pub fn row_base(&self, y: f64) -> DVec3 {
        self.origin + self.ey * y
    }
}

/// A polygon mapped to its plane.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanePolygon {
    /// The plane's frame: origin at the vertices' centroid, +x along the first
    /// edge with length (turned by `rotate`), the normal towards the front.
    pub frame: Frame,
    /// The vertices in plane coordinates, counter-clockwise (positive area).
    pub points: Vec<DVec2>,
    /// Bounding-box diagonal in world units: the scale every tolerance is relative to.
    pub size: f64,
    /// Area (world units², positive).
    pub area: f64,
}

/// Why a polygon has no plane frame.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneError {
    /// Fewer than 3 vertices (the number found).
    TooFewVertices(usize),
    /// A vertex coordinate is NaN or infinite.
    NotFinite,
    /// The vertices are collinear or repeated: the area is at most
    /// [`ZERO_AREA_REL`] × size², or no edge from vertex 0 has length in the plane.
    ZeroArea {
        /// The polygon's area from Newell's normal, in world units².
        area: f64,
        /// Bounding-box diagonal, in world units.
        size: f64,
    },
    /// The polygon's size or area overflows a float (sides beyond about
    /// 1e154): nothing can be measured on its plane, though every coordinate
    /// is finite.
    TooLarge {
        /// Bounding-box diagonal, in world units (perhaps infinite).
        size: f64,
        /// The area, as far as it could be computed.
        area: f64,
    },
    /// A vertex lies farther from the plane than `tolerance` × `size`.
    NonPlanar {
        /// Distance of the farthest vertex from the plane through the
        /// centroid, in world units.
        deviation: f64,
        /// Bounding-box diagonal, in world units.
        size: f64,
        /// Index of the farthest vertex.
        vertex: usize,
        /// The planarity tolerance applied, relative to `size` (`--planarity-tol`).
        tolerance: f64,
    },
}

impl fmt::Display for PlaneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            PlaneError::TooFewVertices(n) => {
                write!(f, "a polygon needs at least 3 vertices, found {n}")
            }
            PlaneError::NotFinite => f.write_str("a vertex coordinate is not finite"),
            PlaneError::ZeroArea { area, size } => write!(
                f,
                "the polygon has no area (area {} for size {}): its vertices are collinear \
                 or repeated, or its outline crosses itself so that its parts cancel (a bow-tie)",
                readable(area),
                readable(size)
            ),
            PlaneError::TooLarge { size, area } => write!(
                f,
                "the polygon is too large to lay a pattern on (size {}, area {}: a 64-bit \
                 float overflows; sides up to about 1e154 can be)",
                readable(size),
                readable(area)
            ),
            PlaneError::NonPlanar {
                deviation,
                size,
                vertex,
                tolerance,
            } => write!(
                f,
                "the polygon is not planar: vertex {vertex} is {} from its plane, \
                 {} of its size {} (--planarity-tol {})",
                readable(deviation),
                readable(deviation / size),
                readable(size),
                readable(tolerance)
            ),
        }
    }
}

impl std::error::Error for PlaneError {}

/// Newell's normal of a closed polygon, with vertices taken relative to `c`
/// for precision. Its length is twice the polygon's area; it points to the
/// side the vertices are counter-clockwise from.
pub fn newell_normal(v: &[DVec3], c: DVec3) -> DVec3 {
    let n = v.len();
    let mut s = DVec3::ZERO;
    for i in 0..n {
        let a = v[i] - c;
        let b = v[(i + 1) % n] - c;
        s.x += (a.y - b.y) * (a.z + b.z);
        s.y += (a.z - b.z) * (a.x + b.x);
        s.z += (a.x - b.x) * (a.y + b.y);
    }
    s
}

/// Maps a polygon to its plane: Newell normal, planarity check against
/// `planarity_tol` (relative to the size), frame with +x along the first edge
/// from vertex 0 rotated `rotate_deg` counter-clockwise.
pub fn map_to_plane(
    v: &[DVec3],
    rotate_deg: f64,
    planarity_tol: f64,
) -> Result<PlanePolygon, PlaneError> {
    if v.len() < 3 {
        return Err(PlaneError::TooFewVertices(v.len()));
    }
    if v.iter().any(|p| !p.is_finite()) || !rotate_deg.is_finite() {
        return Err(PlaneError::NotFinite);
    }
    let (lo, hi) = v
        .iter()
        .fold((v[0], v[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let size = (hi - lo).length();
    let centroid = v.iter().fold(DVec3::ZERO, |s, &p| s + (p - v[0])) / v.len() as f64 + v[0];
    let nn = newell_normal(v, centroid);
    // Newell's normal grows as the size², its squared length as the size⁴:
    // that overflowed to infinity for sides beyond about 1e77, giving a
    // zero normal and a frame with no +y, and the polygon was partitioned
    // into nothing, silently. Then the normal is scaled by its largest
    // component first, and the length overflows only with the area itself
    // (sides beyond about 1e154, where the size overflows too and the
    // polygon is refused). Below, the length is taken as it always was, so
    // that every other polygon keeps its frame to the bit.
    let length = nn.length();
    let (area, normal) = if length.is_finite() {
        (length / 2.0, nn / length)
    } else {
        let largest = nn.abs().max_element();
        let scaled = nn / largest;
        (largest * (scaled.length() / 2.0), scaled.normalize())
    };
    if !size.is_finite() || area.is_infinite() {
        return Err(PlaneError::TooLarge { size, area });
    }
    if area.is_nan() || area <= ZERO_AREA_REL * size * size {
        return Err(PlaneError::ZeroArea { area, size });
    }
    // Planarity: the distance of every vertex from the plane through the centroid.
    let (vertex, deviation) = v
        .iter()
        .map(|&p| (p - centroid).dot(normal).abs())
        .enumerate()
        .fold(
            (0, 0.0f64),
            |best, (i, d)| if d > best.1 { (i, d) } else { best },
        );
    if deviation > planarity_tol * size {
        return Err(PlaneError::NonPlanar {
            deviation,
            size,
            vertex,
            tolerance: planarity_tol,
        });
    }
    // +x: the first edge from vertex 0 with length in the plane. One exists,
    // since the area is positive.
    let ex0 = v[1..]
        .iter()
        .map(|&p| {
            let d = p - v[0];
            d - normal * d.dot(normal)
        })
        .find(|d| d.length() > ZERO_AREA_REL.sqrt() * size)
        .map(|d| d.normalize())
        .ok_or(PlaneError::ZeroArea { area, size })?;
    let (s, c) = math::sin_cos_degrees(rotate_deg);
    // No turn (0, or a whole number of turns: the same bits either way).
    let ex = if (s, c) == (0.0, 1.0) {
        ex0
    } else {
        (ex0 * c + normal.cross(ex0) * s).normalize()
    };
    let ey = normal.cross(ex);
    let frame = Frame {
        origin: centroid,
        ex,
        ey,
        normal,
    };
    let points = v.iter().map(|&p| frame.to_plane(p)).collect();
    Ok(PlanePolygon {
        frame,
        points,
        size,
        area,
    })
}

/// A polygon seen flat ([`flat_view`]): a polygon of up to 8 vertices (a
/// mesh's triangles and quads, polyfill3's cells) without a heap block,
/// since every polygon read is seen flat once to check it is simple.
pub type FlatView = SmallVec<[DVec2; 8]>;

/// The polygon seen along the coordinate axis its plane faces most: for each
/// vertex the two other coordinates, copied without arithmetic, so that exact
/// predicates on them are exact about the polygon as given. The axes stay in
/// cyclic order ((x, y) without z, (y, z) without x, (z, x) without y), so
/// the result is counter-clockwise exactly when the polygon is
/// counter-clockwise seen from that axis's positive side.
///
/// The plane's normal is Newell's, or when that is lost in rounding (its
/// length at most [`ZERO_AREA_REL`] of the size², as for a bow-tie whose two
/// loops cancel) the cross product of the vertices farthest apart, so a
/// self-intersecting polygon is still seen flat. `None` when that too is
/// within [`ZERO_AREA_REL`] of the size² (the vertices are collinear or
/// repeated, which [`map_to_plane`] words as no area) or a vertex is not finite.
pub fn flat_view(v: &[DVec3]) -> Option<FlatView> {
    flat_view_along(v).map(|(flat, _)| flat)
}

/// [`flat_view`], and the index (0, 1, 2 for x, y, z) of the coordinate
/// axis it drops.
pub(crate) fn flat_view_along(v: &[DVec3]) -> Option<(FlatView, usize)> {
    let &first = v.first()?;
    if v.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let (lo, hi) = v
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let size = (hi - lo).length();
    // False for NaN too.
    let has_area = |n: DVec3| n.length() > ZERO_AREA_REL * size * size;
    // A polygon in a plane z = constant (every 2D record) faces z: its
    // normal is the shoelace of its (x, y), and those are its flat view.
    let level =
        (lo.z == hi.z).then(|| v.iter().map(|p| DVec2::new(p.x, p.y)).collect::<FlatView>());
    let mut normal = match &level {
        Some(flat) => DVec3::new(0.0, 0.0, area2(flat)),
        None => newell_normal(v, first),
    };
    if !has_area(normal) {
        // The vertex farthest from the first, then the one farthest from
        // the line through both.
        let far = v.iter().copied().max_by(|a, b| {
            (*a - first)
                .length_squared()
                .total_cmp(&(*b - first).length_squared())
        })?;
        let d = far - first;
        normal = v
            .iter()
            .map(|&p| d.cross(p - first))
            .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))?;
    }
    if !has_area(normal) {
        return None;
    }
    if let Some(flat) = level {
        return Some((flat, 2));
    }
    let a = normal.abs();
    let (pick, axis): (fn(&DVec3) -> DVec2, usize) = if a.z >= a.x && a.z >= a.y {
        (|p| DVec2::new(p.x, p.y), 2)
    } else if a.x >= a.y {
        (|p| DVec2::new(p.y, p.z), 0)
    } else {
        (|p| DVec2::new(p.z, p.x), 1)
    };
    Some((v.iter().map(pick).collect(), axis))
}

/// Signed area of a 2D polygon (positive when counter-clockwise): half the
/// kernel's [`area2`], taken about the first vertex for precision.
pub fn signed_area(p: &[DVec2]) -> f64 {
    area2(p) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_in(frame: DVec3, u: DVec3, w: DVec3) -> Vec<DVec3> {
        vec![frame, frame + u, frame + u + w, frame + w]
    }

    #[test]
    fn normals_along_each_axis_have_a_frame() {
        let o = DVec3::new(3.0, -2.0, 7.0);
        for (u, w, n) in [
            (DVec3::X, DVec3::Y, DVec3::Z),
            (DVec3::Y, DVec3::X, -DVec3::Z),
            (DVec3::Y, DVec3::Z, DVec3::X),
            (DVec3::Z, DVec3::X, DVec3::Y),
            (DVec3::X, DVec3::Z, -DVec3::Y),
        ] {
            let p = map_to_plane(&square_in(o, u * 2.0, w * 2.0), 0.0, 1e-9).unwrap();
            assert!(
                (p.frame.normal - n).length() < 1e-15,
                "{:?}",
                p.frame.normal
            );
            assert!((p.frame.ex - u).length() < 1e-15);
            assert!((p.area - 4.0).abs() < 1e-12);
            assert!(signed_area(&p.points) > 0.0);
            for (q, &w3) in p.points.iter().zip(&square_in(o, u * 2.0, w * 2.0)) {
                assert!((p.frame.to_world(*q) - w3).length() < 1e-14);
            }
        }
    }

    #[test]
    fn rotate_turns_x_counter_clockwise_about_the_normal() {
        let v = square_in(DVec3::ZERO, DVec3::X, DVec3::Y);
        let p = map_to_plane(&v, 90.0, 1e-9).unwrap();
        assert!((p.frame.ex - DVec3::Y).length() < 1e-15);
        assert!((p.frame.ey + DVec3::X).length() < 1e-15);
    }

    #[test]
    fn a_polygon_of_huge_sides_keeps_its_area_and_frame() {
        // Sides of 1e78 to 1e153 made the normal's squared length overflow:
        // a zero normal and +y, and no cells.
        for side in [1e77, 1e78, 1e100, 1e150] {
            let v = [
                DVec3::ZERO,
                DVec3::new(side, 0.0, 0.0),
                DVec3::new(0.0, side, 0.0),
            ];
            let p = map_to_plane(&v, 0.0, DEFAULT_PLANARITY_TOL).unwrap();
            let f = p.frame;
            let near = |a: DVec3, b: DVec3| (a - b).length() < 1e-15;
            assert!(near(f.normal, DVec3::Z), "{side}: {f:?}");
            assert!(near(f.ex, DVec3::X), "{side}: {f:?}");
            assert!(near(f.ey, DVec3::Y), "{side}: {f:?}");
            assert!((p.area / (side * side / 2.0) - 1.0).abs() < 1e-12, "{side}");
            assert!(
                (signed_area(&p.points) / p.area - 1.0).abs() < 1e-12,
                "{side}"
            );
        }
        // Beyond about 1e154 the area overflows (and then the size): refused
        // as too large, where it was called collinear (a hostile-input
        // review; polyfill3 and scene-render said "no area (area NaN for
        // size inf)").
        for side in [1e155, 1e160, 1e200, 1e300] {
            let v = [
                DVec3::new(side, 0.0, 0.0),
                DVec3::new(-side, 0.0, 0.0),
                DVec3::new(0.0, side, 0.0),
            ];
            let e = map_to_plane(&v, 0.0, DEFAULT_PLANARITY_TOL).unwrap_err();
            assert!(matches!(e, PlaneError::TooLarge { .. }), "{side}: {e:?}");
            assert!(e.to_string().contains("too large"), "{e}");
        }
    }

    #[test]
    fn degenerate_and_non_planar_polygons_are_refused() {
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X];
        assert!(matches!(
            map_to_plane(&line, 0.0, 1e-6),
            Err(PlaneError::ZeroArea { .. })
        ));
        let warped = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.1), DVec3::Y];
        let e = map_to_plane(&warped, 0.0, 1e-6).unwrap_err();
        assert!(matches!(e, PlaneError::NonPlanar { .. }));
        assert!(e.to_string().contains("not planar"), "{e}");
        assert!(map_to_plane(&warped, 0.0, 0.1).is_ok());
    }

    #[test]
    fn repeated_first_vertex_takes_the_next_edge() {
        let v = [
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        ];
        let p = map_to_plane(&v, 0.0, 1e-9).unwrap();
        assert!((p.frame.ex - DVec3::Y).length() < 1e-15);
    }
}
