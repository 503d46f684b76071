//! The view a frame is rendered from: a camera's world → clip matrix on an
//! image of a given size, and clipping to its view volume ([`clip`]). The
//! texture maps, the stripe mappings and the rasterizer all project through a
//! [`View`], so it stands between the camera and them.

pub mod clip;
pub mod volume;

pub use volume::{ViewVolume, EDGE_ON_SINE};

use crate::camera::Camera;
use glam::{DMat4, DVec2, DVec3, DVec4};

/// For a perspective view with `near = 0` the clipper keeps
/// `w >= W_EPSILON_REL * far` (in eye units: distance in front of the eye).
/// This is what makes `near = 0` work (with near > 0 the near plane alone
/// keeps w positive): the
/// near plane `z >= 0` alone would let vertices reach `w = 0` and divide by zero.
/// At 1e-9 of the far distance the lost sliver is invisible at any image size
/// this tool makes (it would need a polygon lying within a billionth of the
/// scene depth of the eye).
pub const W_EPSILON_REL: f64 = 1e-9;

/// The view a frame is rendered from: world → clip matrix and the clip volume
/// contract of [`crate::camera`] (visible iff `-w<=x<=w`, `-w<=y<=w`,
/// `near <= z_clip <= far`; `z_clip = -z_eye`; `w = -z_eye` in perspective and 1
/// in parallel views).
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// World → clip, column vectors: the camera's `projection * view`, or
    /// that times an instance's transform for the instance's own coordinates.
    pub world_to_clip: DMat4,
    /// Distance along the view direction of the volume's near bound:
    /// visible iff `z_clip >= near`.
    pub near: f64,
    /// Distance along the view direction of the volume's far bound:
    /// visible iff `z_clip <= far`.
    pub far: f64,
    /// Whether `w = -z_eye` (perspective) rather than 1 (parallel).
    pub perspective: bool,
    /// Width of the image in pixels; the window fills it.
    pub width: u32,
    /// Height of the image in pixels.
    pub height: u32,
}

impl View {
    /// IRIS `ortho2(left, right, bottom, top)`: a parallel view of the z = 0
    /// plane with near = -1 and far = 1, as in IRIS GL.
    pub fn ortho2(l: f64, r: f64, b: f64, t: f64, width: u32, height: u32) -> View {
        let m = DMat4::from_cols(
            DVec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
            DVec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
            // z_clip = -z_eye, and the eye space of ortho2 is world space.
            DVec4::new(0.0, 0.0, -1.0, 0.0),
            DVec4::new(-(r + l) / (r - l), -(t + b) / (t - b), 0.0, 1.0),
        );
        View {
            world_to_clip: m,
            near: -1.0,
            far: 1.0,
            perspective: false,
            width,
            height,
        }
    }

    /// Clip coordinates of a world point.
    pub fn to_clip(&self, p: DVec3) -> DVec4 {
        self.world_to_clip * p.extend(1.0)
    }

    /// Screen position (pixels, y up) of a clip-space point with `w > 0`.
    pub fn to_screen(&self, c: DVec4) -> DVec2 {
        let (w, h) = (self.width as f64, self.height as f64);
        let x = ((c.x / c.w) * 0.5 + 0.5) * w;
        let y = ((c.y / c.w) * 0.5 + 0.5) * h;
        // Clipping keeps |x/w| <= 1 up to rounding; clamp that rounding away so
        // every later stage may assume the polygon lies within the image.
        DVec2::new(x.clamp(0.0, w), y.clamp(0.0, h))
    }

    /// Nearness at a clip-space point, bigger nearer: `1/w` in perspective
    /// views, `-z_clip` in parallel ones; both are affine over the screen for a
    /// planar polygon, so the rasterizer interpolates them exactly.
    pub fn nearness(&self, c: DVec4) -> f64 {
        if self.perspective {
            1.0 / c.w
        } else {
            -c.z
        }
    }

    /// The view of `camera` on a `width` x `height` image: its matrices and
    /// depth range, unchanged.
    pub fn new(camera: &Camera, width: u32, height: u32) -> View {
        let camera = camera.for_image(width, height);
        View {
            world_to_clip: camera.world_to_clip(),
            near: camera.near,
            far: camera.far,
            perspective: camera.perspective,
            width,
            height,
        }
    }

    /// The nearness scale of the view, the floor of the tie tolerance: without
    /// it, polygons at exactly nearness 0 (2D records at z = 0 under ortho2)
    /// would tie with a zero tolerance and each hide neither. Parallel views:
    /// the depth range; perspective: `1/far`, the smallest nearness visible.
    pub fn nearness_scale(&self) -> f64 {
        if self.perspective {
            1.0 / self.far.abs().max(f64::MIN_POSITIVE)
        } else {
            self.near.abs().max(self.far.abs()).max(f64::MIN_POSITIVE)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A perspective view for tests: eye at the origin looking down -z, vertical
    /// field `fovy` degrees, with the camera contract's z_clip = w = -z_eye.
    pub fn perspective(fovy: f64, width: u32, height: u32, near: f64, far: f64) -> View {
        let f = 1.0 / crate::math::tan(fovy.to_radians() / 2.0);
        let aspect = width as f64 / height as f64;
        let m = DMat4::from_cols(
            DVec4::new(f / aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, f, 0.0, 0.0),
            DVec4::new(0.0, 0.0, -1.0, -1.0),
            DVec4::new(0.0, 0.0, 0.0, 0.0),
        );
        View {
            world_to_clip: m,
            near,
            far,
            perspective: true,
            width,
            height,
        }
    }
}
