//! Geometry in world and plane coordinates, below every stage that draws.
//!
//! This file holds the record shapes ([`Shape`]) and turns the thesis's 2D
//! records (`rect`, `circle`, `arc`) into polygons. [`polygon`] is the 2D
//! polygon kernel (area, exact orientation, half-plane clipping, convexity
//! and their named tolerances), [`mod@slice`] cuts a convex polygon between the
//! lines of a pencil (texel rows and cells on the screen), [`simple`] tells whether a polygon crosses or
//! touches itself, [`triangulate`] cuts a simple polygon into triangles,
//! [`transform`] the affine transforms of records and instances, [`plane`]
//! maps a 3D polygon to its plane, [`clip`] holds
//! the tagged clipping of the partition, [`partition`] cuts a polygon into
//! texture point polygons (`polyfill3`), [`merge`] joins runs of equal cells,
//! and [`quadric`] tessellates GLU's quadrics with texture coordinates.
//!
//! A 3 x 2 rectangle partitioned at one texel per unit gives six cells whose
//! areas add up to the rectangle's:
//!
//! ```
//! use glam::{DVec2, DVec3};
//! use patkit::geom::plane::DEFAULT_PLANARITY_TOL;
//! use patkit::geom::polygon::area2;
//! use patkit::geom::{map_to_plane, CellSink, Grid, Partitioner, Placement};
//!
//! struct Tally { cells: usize, area: f64 }
//! impl CellSink for Tally {
//!     fn wants(&mut self, _k: i64, _j: i64) -> bool { true }
//!     fn cell(&mut self, _k: i64, _j: i64, _world: &[DVec3], plane: &[DVec2], _full: bool) {
//!         self.cells += 1;
//!         self.area += area2(plane) / 2.0;
//!     }
//! }
//! let rect = [(0.0, 0.0), (3.0, 0.0), (3.0, 2.0), (0.0, 2.0)].map(|(x, y)| DVec3::new(x, y, 0.0));
//! let polygon = map_to_plane(&rect, 0.0, DEFAULT_PLANARITY_TOL)?;
//! let grid = Grid::new(&polygon.points, Placement { incr: 1.0, horz: 0.0, vert: 0.0 })?;
//! let mut tally = Tally { cells: 0, area: 0.0 };
//! Partitioner::new().run(&polygon, &grid, &mut tally);
//! assert_eq!(tally.cells, 6);
//! assert!((tally.area - 6.0).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod clip;
pub mod merge;
pub mod partition;
pub mod plane;
pub mod polygon;
pub mod quadric;
pub mod simple;
pub mod slice;
mod sweep;
pub mod transform;
pub mod triangulate;
mod vertices;

pub use partition::{CellSink, Grid, GridError, Partitioner, Placement};
pub use plane::{map_to_plane, Frame, PlaneError, PlanePolygon};
pub use vertices::Vertices;

use crate::math;
use glam::DVec3;
use std::f64::consts::PI;

/// The geometry of a stream record (docs/stream-format.md), in its own coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A planar polygon, counter-clockwise seen from its front. `[x,y]` means z = 0.
    Polygon(Vertices),
    /// `{"rect": [x1,y1,x2,y2]}` in the z = 0 plane.
    Rect([f64; 4]),
    /// `{"circle": {"center": [x,y], "radius": r}}` in the z = 0 plane.
    Circle {
        /// Centre `[x, y]` in record coordinates.
        center: [f64; 2],
        /// Radius in record units.
        radius: f64,
    },
    /// `{"arc": {...}}`: a filled sector drawn counter-clockwise from `start` to `end` degrees.
    Arc {
        /// Centre `[x, y]` in record coordinates; the sector's apex.
        center: [f64; 2],
        /// Radius in record units.
        radius: f64,
        /// First angle of the sector, in degrees counter-clockwise from +x.
        start: f64,
        /// Last angle of the sector, in degrees counter-clockwise from +x.
        end: f64,
    },
    /// `{"sphere": {...}}`, `"cylinder"`, `"cone"` or `"disk"` with an
    /// optional record `"transform"` (docs/objects.md, Quadrics): drawn as
    /// triangles with GLU texture coordinates (`crate::geom::quadric`).
    Quadric(Box<quadric::QuadricShape>),
}

impl Shape {
    /// The stream key the shape is written with (docs/stream-format.md), for messages.
    pub fn key(&self) -> &'static str {
        match self {
            Shape::Polygon(_) => "vertices",
            Shape::Rect(_) => "rect",
            Shape::Circle { .. } => "circle",
            Shape::Arc { .. } => "arc",
            Shape::Quadric(q) => q.kind,
        }
    }
}

/// Fewest segments a full circle is ever drawn with, however coarse the tolerance.
pub const MIN_CIRCLE_SEGMENTS: usize = 8;
/// Most segments a full circle is drawn with: the chord error is then at most
/// r(1 - cos(π/65,536)) ≈ 1.15e-9 r, within 1/256 pixel up to a radius of about
/// 3.4 million pixels (further beyond), and more segments only cost time.
pub const MAX_CIRCLE_SEGMENTS: usize = 1 << 16;

/// Segments for a full circle of `radius` so that no chord strays more than
/// `tolerance` from the true circle: the sagitta r(1 - cos(π/n)) <= tolerance.
pub fn circle_segments(radius: f64, tolerance: f64) -> usize {
    if tolerance.is_nan() || tolerance <= 0.0 || tolerance >= radius {
        return MIN_CIRCLE_SEGMENTS;
    }
    let n = (PI / math::acos(1.0 - tolerance / radius)).ceil();
    (n as usize).clamp(MIN_CIRCLE_SEGMENTS, MAX_CIRCLE_SEGMENTS)
}

/// The polygon of a record's shape, counter-clockwise seen from +z for the 2D
/// records. Curves are approximated within `tolerance` (world units).
///
/// An arc is the sector from `start` to `end` degrees counter-clockwise (IRIS
/// `arcf`): the sweep is `(end - start) mod 360`, and a sweep of 0 with
/// `end != start` (e.g. 0 to 360) is the full disc.
///
/// A quadric is no single polygon: its outline is empty, and its consumers
/// tessellate it instead ([`quadric::QuadricShape::texel_triangles`]).
pub fn outline(shape: &Shape, tolerance: f64) -> Vec<DVec3> {
    match *shape {
        Shape::Quadric(_) => Vec::new(),
        Shape::Polygon(ref v) => v.to_vec(),
        Shape::Rect([x1, y1, x2, y2]) => {
            let (x0, x1) = (x1.min(x2), x1.max(x2));
            let (y0, y1) = (y1.min(y2), y1.max(y2));
            vec![
                DVec3::new(x0, y0, 0.0),
                DVec3::new(x1, y0, 0.0),
                DVec3::new(x1, y1, 0.0),
                DVec3::new(x0, y1, 0.0),
            ]
        }
        Shape::Circle { center, radius } => {
            let n = circle_segments(radius, tolerance);
            (0..n)
                .map(|i| {
                    let a = 2.0 * PI * i as f64 / n as f64;
                    DVec3::new(
                        center[0] + radius * math::cos(a),
                        center[1] + radius * math::sin(a),
                        0.0,
                    )
                })
                .collect()
        }
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => {
            // Start and end reduced exactly first (math::reduce_degrees), so
            // that a turn more or less draws the same arc to the bit; and
            // the ends taken as given, not as start plus sweep, so that an
            // end on an axis (an arc from 29.86 to 90) lies on it exactly.
            let (from, to) = (math::reduce_degrees(start), math::reduce_degrees(end));
            let mut sweep = (to - from).rem_euclid(360.0);
            if sweep == 0.0 && end != start {
                sweep = 360.0;
            }
            let full = circle_segments(radius, tolerance);
            let n = ((full as f64 * sweep / 360.0).ceil() as usize).max(1);
            let mut v = Vec::with_capacity(n + 2);
            v.push(DVec3::new(center[0], center[1], 0.0));
            for i in 0..=n {
                let at = match i {
                    0 => from,
                    _ if i == n && sweep < 360.0 => to,
                    _ if i == n => from,
                    _ => from + sweep * i as f64 / n as f64,
                };
                let (sin, cos) = math::sin_cos_degrees(at);
                v.push(DVec3::new(
                    center[0] + radius * cos,
                    center[1] + radius * sin,
                    0.0,
                ));
            }
            v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_area_xy(v: &[DVec3]) -> f64 {
        let n = v.len();
        (0..n)
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                a.x * b.y - b.x * a.y
            })
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn rect_is_ccw_whatever_corner_order() {
        let v = outline(&Shape::Rect([425.0, 700.0, 75.0, 500.0]), 0.1);
        assert_eq!(signed_area_xy(&v), 350.0 * 200.0);
    }

    #[test]
    fn circle_chords_stay_within_tolerance() {
        for (r, tol) in [(100.0, 0.01), (1.0, 0.5), (1e6, 1e-3)] {
            let v = outline(
                &Shape::Circle {
                    center: [1.0, 2.0],
                    radius: r,
                },
                tol,
            );
            let n = v.len() as f64;
            assert!(
                r * (1.0 - math::cos(PI / n)) <= tol * (1.0 + 1e-12)
                    || v.len() == MAX_CIRCLE_SEGMENTS
            );
            assert!(signed_area_xy(&v) > 0.0);
        }
    }

    #[test]
    fn arc_is_the_ccw_sector_and_wraps_past_360() {
        // The thesis's demo: 30 to 90 degrees, a sixth of the disc.
        let v = outline(
            &Shape::Arc {
                center: [0.0, 0.0],
                radius: 1.0,
                start: 30.0,
                end: 90.0,
            },
            1e-4,
        );
        let a = signed_area_xy(&v);
        assert!((a - PI / 6.0).abs() < 1e-3, "{a}");
        let w = outline(
            &Shape::Arc {
                center: [0.0, 0.0],
                radius: 1.0,
                start: 300.0,
                end: 60.0,
            },
            1e-4,
        );
        assert!((signed_area_xy(&w) - PI / 3.0).abs() < 1e-3);
        let full = outline(
            &Shape::Arc {
                center: [0.0, 0.0],
                radius: 1.0,
                start: 0.0,
                end: 360.0,
            },
            1e-4,
        );
        assert!((signed_area_xy(&full) - PI).abs() < 1e-3);
    }

    #[test]
    fn an_arc_a_turn_further_is_the_same_and_its_ends_on_axes_lie_on_them() {
        let arc = |start: f64, end: f64| {
            outline(
                &Shape::Arc {
                    center: [0.0, 0.0],
                    radius: 10.0,
                    start,
                    end,
                },
                1e-3,
            )
        };
        // Turns further, exactly: angles whose sum with 360 is exact
        // (71.09 + 360 is not: 431.09 is a hair more than a turn past
        // 71.09, in binary).
        let (a, b) = (71.125, 128.8125);
        assert_eq!((a + 360.0 - 360.0, b + 360.0 - 360.0), (a, b));
        assert_eq!(arc(a, b), arc(a + 360.0, b + 360.0));
        assert_eq!(arc(a, b), arc(a - 720.0, b + 1080.0));
        assert_eq!(arc(-10.0, 20.0), arc(350.0, 380.0));
        assert_eq!(arc(-180.0, 90.0), arc(180.0, 450.0));
        // An end on an axis, reached from a start that start + sweep would
        // not have brought back to it: (-1.608e-15, 10) before.
        let v = arc(29.86, 90.0);
        assert_eq!(v.last().unwrap().truncate(), glam::DVec2::new(0.0, 10.0));
        let v = arc(-33.3, 180.0);
        assert_eq!(v.last().unwrap().truncate(), glam::DVec2::new(-10.0, 0.0));
        // A whole turn closes on its first point.
        let v = arc(12.5, 372.5);
        assert_eq!(v[1], *v.last().unwrap());
    }
}
