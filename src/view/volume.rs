//! Culling against a camera (`polyfill3 --camera FILE --cull`): polygons
//! facing the dropped way and cells wholly outside the view volume are
//! dropped before they are written, so the renderer never sees them.
//!
//! Written against the two matrices of a camera (world→eye looking down -z,
//! eye→clip) and its near/far distances, so it does not depend on how the
//! camera was specified (docs/camera.md has two models). Unlike [`super::View`] it
//! needs no image: it decides in world space.

use crate::camera::Camera;
use glam::{DMat4, DVec3, DVec4};

/// How far from edge-on a polygon must turn (the sine of the angle between
/// its plane and the line of sight) for its face to drop it. The renderer
/// decides a face by the sign of the polygon's area on screen, which the
/// rounding of its projection can give either sign for a polygon seen edge
/// on: a plain seen exactly edge-on through a horizontal parallel view was
/// dropped here as back-facing while `scene-render --cull back --aa none`
/// drew slivers of 463 of its cells (review, 2026-11-28). Within 2^-20 of
/// edge-on, the polygon is kept whatever its face, and the renderer
/// decides; such a polygon covers about a millionth of its own area on
/// screen, so keeping it costs nothing.
pub const EDGE_ON_SINE: f64 = 1.0 / (1u64 << 20) as f64;

/// How near the eye, relative to the larger of the eye's and the point's
/// distance from the origin, a point of a polygon lies for the line of
/// sight to it to have no direction. The eye is the camera's view matrix
/// inverted ([`Camera::eye_position`]), a few ulps off, so the sight line to
/// a point within rounding of it points anywhere and its facing was a
/// coin toss; such a polygon passes through the eye, edge-on, and is kept.
const AT_THE_EYE: f64 = 1.0 / (1u64 << 30) as f64;

/// A camera's view volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewVolume {
    view: DMat4,
    projection: DMat4,
    near: f64,
    far: f64,
    /// The eye in world coordinates for a perspective view; `None` for a parallel one.
    eye: Option<DVec3>,
    /// The direction of view in world coordinates (unit).
    direction: DVec3,
}

impl ViewVolume {
    /// The volume a camera sees: a point is visible iff -w <= x, y <= w and
    /// near <= -z_eye <= far (the camera contract). Rays come from the
    /// camera's eye, or for parallel views along its direction of projection
    /// (slanted for an oblique view: cavalier, cabinet).
    pub fn new(camera: &Camera) -> ViewVolume {
        ViewVolume {
            view: camera.view,
            projection: camera.projection,
            near: camera.near,
            far: camera.far,
            eye: camera.eye_position(),
            direction: camera.view_direction(),
        }
    }

    /// Whether a polygon with front `normal` through `point` turns its back
    /// to the camera by more than [`EDGE_ON_SINE`]: conservative, as
    /// [`Self::outside`] is, so that a polygon the renderer may draw is kept.
    pub fn back_facing(&self, normal: DVec3, point: DVec3) -> bool {
        self.facing(normal, point) > EDGE_ON_SINE
    }

    /// Whether a polygon with front `normal` through `point` turns its front
    /// to the camera by more than [`EDGE_ON_SINE`]: the mirror of
    /// [`Self::back_facing`]. A polygon within that of edge-on is neither.
    pub fn front_facing(&self, normal: DVec3, point: DVec3) -> bool {
        self.facing(normal, point) < -EDGE_ON_SINE
    }

    /// The sine of the angle between the line of sight to `point` (for a
    /// parallel view, the direction of projection) and the polygon's plane,
    /// positive when the polygon turns its back to the camera; 0 (edge-on)
    /// for a point at the eye ([`AT_THE_EYE`]), and NaN or 0 where the
    /// normal's length overflows, which keep the polygon too.
    fn facing(&self, normal: DVec3, point: DVec3) -> f64 {
        let to = match self.eye {
            Some(e) => {
                let to = point - e;
                if to.length() <= AT_THE_EYE * e.length().max(point.length()) {
                    return 0.0;
                }
                to
            }
            None => self.direction,
        };
        normal.dot(to) / (normal.length() * to.length())
    }

    /// Whether every point lies beyond one and the same plane of the view
    /// volume (then the convex hull, and the polygon, is invisible). A polygon
    /// straddling a corner may be kept although invisible: the test is
    /// conservative, never wrong the other way.
    pub fn outside(&self, points: &[DVec3]) -> bool {
        let mut all = 0b11_1111u8;
        for &p in points {
            let e = self.view.transform_point3(p);
            let c = self.projection * DVec4::new(e.x, e.y, e.z, 1.0);
            let d = -e.z;
            let mut m = 0u8;
            m |= (c.x > c.w) as u8;
            m |= ((c.x < -c.w) as u8) << 1;
            m |= ((c.y > c.w) as u8) << 2;
            m |= ((c.y < -c.w) as u8) << 3;
            m |= ((d < self.near) as u8) << 4;
            m |= ((d > self.far) as u8) << 5;
            all &= m;
            if all == 0 {
                return false;
            }
        }
        all != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(perspective: bool) -> ViewVolume {
        // The thesis's demo2: eye (0,100,-5) looking at (0,0,-900).
        let view = DMat4::look_at_rh(
            DVec3::new(0.0, 100.0, -5.0),
            DVec3::new(0.0, 0.0, -900.0),
            DVec3::Y,
        );
        let proj = if perspective {
            DMat4::perspective_rh_gl(55f64.to_radians(), 1024.0 / 768.0, 1.0, 1000.0)
        } else {
            DMat4::orthographic_rh_gl(-500.0, 500.0, -400.0, 400.0, 1.0, 1000.0)
        };
        ViewVolume::new(&Camera {
            view,
            projection: proj,
            near: 1.0,
            far: 1000.0,
            perspective,
            aspect_from_image: false,
        })
    }

    #[test]
    fn the_plain_faces_the_camera_and_its_underside_does_not() {
        for persp in [true, false] {
            let v = camera(persp);
            assert!(!v.back_facing(DVec3::Y, DVec3::new(0.0, 0.0, -400.0)));
            assert!(v.back_facing(-DVec3::Y, DVec3::new(0.0, 0.0, -400.0)));
        }
    }

    #[test]
    fn oblique_parallel_views_cull_along_the_direction_of_projection() {
        // Cavalier-like shear: x_clip = x + z (rays along (1, 0, -1) in the eye frame).
        let mut proj = DMat4::IDENTITY;
        proj.z_axis.x = 1.0;
        let v = ViewVolume::new(&Camera {
            view: DMat4::IDENTITY,
            projection: proj,
            near: -10.0,
            far: 10.0,
            perspective: false,
            aspect_from_image: false,
        });
        // A plane facing +x is seen by rays travelling -x... here rays travel +x: back.
        assert!(v.back_facing(DVec3::X, DVec3::ZERO));
        assert!(!v.back_facing(-DVec3::X + DVec3::Z * 0.1, DVec3::ZERO));
    }

    #[test]
    fn cells_behind_the_eye_or_beyond_far_are_outside() {
        let v = camera(true);
        let cell = |z: f64| {
            vec![
                DVec3::new(0.0, 0.0, z),
                DVec3::new(1.0, 0.0, z),
                DVec3::new(1.0, 0.0, z - 1.0),
            ]
        };
        assert!(!v.outside(&cell(-400.0)));
        assert!(v.outside(&cell(100.0)));
        assert!(v.outside(&cell(-2000.0)));
        assert!(v.outside(&[
            DVec3::new(5000.0, 0.0, -400.0),
            DVec3::new(5001.0, 0.0, -400.0),
            DVec3::new(5001.0, 0.0, -401.0)
        ]));
    }

    #[test]
    fn faces_turned_away_are_dropped_and_edge_on_ones_kept() {
        let c = Camera::from_json(
            &serde_json::json!({"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900]},
                                "perspective": {"fovy": 55, "aspect": 1, "near": 0, "far": 1000}}),
            "t",
        )
        .unwrap();
        let v = ViewVolume::new(&c);
        // The floor's normal +y faces the camera above it; -y does not.
        let p = DVec3::new(0.0, 0.0, -400.0);
        assert!(!v.back_facing(DVec3::Y, p));
        assert!(v.back_facing(DVec3::NEG_Y, p));
        let o = ViewVolume::new(&Camera::ortho2(0.0, 10.0, 0.0, 10.0));
        assert!(!o.back_facing(DVec3::Z, DVec3::ZERO));
        assert!(o.back_facing(DVec3::NEG_Z, DVec3::ZERO));
        for n in [DVec3::Y, DVec3::NEG_Y] {
            assert_ne!(v.back_facing(n, p), v.front_facing(n, p), "{n}");
        }
        assert!(o.front_facing(DVec3::Z, DVec3::ZERO));
        assert!(!o.front_facing(DVec3::NEG_Z, DVec3::ZERO));
        // Edge-on, and within EDGE_ON_SINE of it: kept, whichever face.
        let tilt = EDGE_ON_SINE / 2.0;
        for n in [
            DVec3::X,
            DVec3::new(1.0, 0.0, tilt),
            DVec3::new(1.0, 0.0, -tilt),
        ] {
            assert!(
                !o.back_facing(n, DVec3::ZERO) && !o.front_facing(n, DVec3::ZERO),
                "{n}"
            );
        }
        let tilt = EDGE_ON_SINE * 2.0;
        assert!(o.front_facing(DVec3::new(1.0, 0.0, tilt), DVec3::ZERO));
        assert!(o.back_facing(DVec3::new(1.0, 0.0, -tilt), DVec3::ZERO));
        // A polygon through the eye (the eye given as the camera gave it,
        // not as the inverted view matrix finds it), and one whose normal is
        // too long for its length to be finite: kept, and the renderer
        // decides.
        let eye = DVec3::new(0.0, 100.0, -5.0);
        let huge = DVec3::new(0.0, 1e300, -1e300);
        for (n, at) in [(DVec3::Y, eye), (DVec3::NEG_Y, eye), (huge, p), (-huge, p)] {
            assert!(
                !v.back_facing(n, at) && !v.front_facing(n, at),
                "{n} at {at}"
            );
        }
    }
}
