//! The texture mapping function (seed 001, "Texture Mapping Function", Fig. 6):
//! the texture coordinate `P` of the face point seen at a screen position, as a
//! ratio of two linear functions of that position, so that a scan-line
//! renderer evaluates it with a handful of multiply-adds and one division per
//! pixel.
//!
//! # Screen coordinates
//!
//! `(x, y)` are continuous pixel coordinates with the origin at the image's
//! lower-left corner and y up, the renderer's screen space: pixel `(px, py)`
//! (`py` counted from the bottom row) is the square `[px, px+1] × [py, py+1]`
//! and its centre is `(px + 0.5, py + 0.5)`. A world point with clip
//! coordinates `c = world_to_clip · (X, 1)` is at
//! `x = (c_x / c_w + 1) W / 2`, `y = (c_y / c_w + 1) H / 2`.
//!
//! # Derivation
//!
//! Write the three rows `s0 = W/2 (m0 + m3)`, `s1 = H/2 (m1 + m3)`, `s2 = m3`
//! of the screen matrix (`m_i` the rows of `world_to_clip`), so that the point
//! `X̃ = (X, 1)` is seen at `x = s0·X̃ / s2·X̃`, `y = s1·X̃ / s2·X̃`. The face's
//! plane is `π·X̃ = 0` with `π = (N_f, −N_f·Q)`, `Q` a point of the face. The
//! face point seen at `(x, y)` is the intersection of the pixel's ray with the
//! plane: the three linear conditions
//!
//! `(s0 − x s2)·X̃ = 0`, `(s1 − y s2)·X̃ = 0`, `π·X̃ = 0`
//!
//! fix the homogeneous `X̃` up to scale as the generalised cross product
//! `X̃ = ×(s0 − x s2, s1 − y s2, π)`. The product is linear in each argument and
//! alternating, so the `x y ×(s2, s2, π)` term vanishes and
//!
//! `X̃(x, y) = K0 + x Kx + y Ky`, `K0 = ×(s0, s1, π)`, `Kx = −×(s2, s1, π)`,
//! `Ky = −×(s0, s2, π)`.
//!
//! `P = P0 + K_p N_p · X = u·X̃ / X̃_w` with `u = (K_p N_p, P0)`, hence
//!
//! **`P(x, y) = (C1 x + C2 y + C3) / (C4 x + C5 y + C6)`** with
//! `C1 = u·Kx, C2 = u·Ky, C3 = u·K0, C4 = Kx_w, C5 = Ky_w, C6 = K0_w`.
//!
//! This holds for every camera of docs/camera.md (off-axis and oblique too); for a
//! parallel projection `C4 = C5 = 0` and `P` is affine in the screen position.
//! The computation is done with the origin moved to `Q`, so large world
//! coordinates do not cancel.
//!
//! # What the seed's Fig. 6 formula gets wrong
//!
//! For a perspective view the same result follows from the eye ray
//! `X = V + t D(I, J)`, `D` linear in the screen offsets `(I − I0, J − J0)`:
//! `t = N_f·(Q − V) / N_f·D`, so
//! `P = P0 + K_p N_p·V + (K_p N_p·D) d / (N_f·D)` with `d = N_f·(Q − V)`, the
//! eye's distance to the face plane. In the seed's eye axes (`u` along the line
//! of sight, `w` across, `v` down the screen; `C_w`, `C_v` the screen constants
//! per element and per line):
//!
//! `P = P0' + (C1 + C2(I−I0) + C3(J−J0)) / (C4 + C5(I−I0) + C6(J−J0))`,
//! `C1 = K_p N_pu`, `C2 = K_p N_pw C_w`, `C3 = K_p N_pv C_v`,
//! `C4 = N_fu / d`, `C5 = N_fw C_w / d`, `C6 = N_fv C_v / d`.
//!
//! The printed formula has two misprints, corrected here:
//!
//! 1. `C1` stands outside the fraction (`P0' + C1 + (...)/(...)`). It is the
//!    numerator's constant term — the pattern vector's component along the line
//!    of sight — and belongs inside: `(C1 + C2(I−I0) + C3(J−J0))`. With `C1`
//!    outside, `P` would not even be constant along a stripe.
//! 2. `C6 = dot(N_f, V_r)` repeats the line for `d`. By the pattern of `C4` and
//!    `C5` (the face normal's `u` and `w` components over `d`), and because the
//!    denominator must be `N_f·D / d`, it is `C6 = N_fv C_v / d`.
//!
//! Besides, `P0' = P0 − dot(K_p N_p, V_r)` and `d = dot(N_f, V_r)` agree with
//! the ray derivation only if `V_r` is the vector from the viewpoint to the
//! pattern origin and the face plane passes through that origin; in general
//! `P0' = P0 + K_p N_p·V` (`V` the viewpoint) and `d = N_f·(Q − V)`. The
//! tests check the rational form against direct evaluation (unproject the
//! pixel's ray, intersect the plane, dot with `K_p N_p`) to 1e-9 relative.

use crate::camera::Camera;
use glam::{DMat3, DMat4, DVec3, DVec4};
use std::fmt;

/// A face whose plane contains the centre of projection (or, for parallel
/// views, the direction of projection) is seen edge-on and has no mapping: the
/// sine of the angle under which the plane is seen is then below this. 1e-12 is
/// far above f64 round-off of the cross products (about 1e-16 relative) and far
/// below any face that covers a pixel.
const EDGE_ON_RELATIVE: f64 = 1e-12;

/// The face is seen edge-on: it covers no pixels, and `P` is undefined.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeOn;

impl fmt::Display for EdgeOn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("the face is seen edge-on: its stripe texture has no screen mapping")
    }
}
impl std::error::Error for EdgeOn {}

/// `P(x, y) = (c[0] x + c[1] y + c[2]) / (c[3] x + c[4] y + c[5])` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenMapping {
    /// `C1..C6` of the module docs, screen pixels with y up, scaled so that
    /// the largest of the denominator's `c[3..6]` has magnitude 1.
    pub c: [f64; 6],
}

/// The generalised cross product of three 4-vectors: the vector orthogonal to
/// all three whose components are the signed 3x3 minors.
fn cross4(a: DVec4, b: DVec4, c: DVec4) -> DVec4 {
    let m = |i: usize| {
        // The 3x3 determinant of a, b, c with component i removed.
        let pick = |v: DVec4| -> DVec3 {
            let a = v.to_array();
            let mut o = [0.0; 3];
            let mut k = 0;
            for (j, x) in a.iter().enumerate() {
                if j != i {
                    o[k] = *x;
                    k += 1;
                }
            }
            DVec3::from_array(o)
        };
        DMat3::from_cols(pick(a), pick(b), pick(c)).determinant()
    };
    DVec4::new(m(0), -m(1), m(2), -m(3))
}

/// The rows `s0, s1, s2` of the world → screen matrix (module docs).
pub fn screen_rows(camera: &Camera, width: u32, height: u32) -> [DVec4; 3] {
    screen_rows_of(camera.world_to_clip(), width, height)
}

/// [`screen_rows`] of a world → clip matrix (a camera's, or a camera's times
/// an instance's object → world transform).
pub fn screen_rows_of(m: DMat4, width: u32, height: u32) -> [DVec4; 3] {
    let (w, h) = (width as f64 * 0.5, height as f64 * 0.5);
    [
        (m.row(0) + m.row(3)) * w,
        (m.row(1) + m.row(3)) * h,
        m.row(3),
    ]
}

impl ScreenMapping {
    /// The mapping of `P = p0 + gradient · X` over the plane through `point`
    /// with normal `normal`, for `camera` and an image of `width` x `height`.
    pub fn new(
        camera: &Camera,
        width: u32,
        height: u32,
        normal: DVec3,
        point: DVec3,
        gradient: DVec3,
        p0: f64,
    ) -> Result<ScreenMapping, EdgeOn> {
        ScreenMapping::from_matrix(
            camera.world_to_clip(),
            width,
            height,
            normal,
            point,
            gradient,
            p0,
        )
    }

    /// [`ScreenMapping::new`] for a world → clip matrix: `scene-render` passes
    /// the view's matrix times an instance's transform, so that the plane,
    /// point and pattern vector are in the object's own coordinates and the
    /// stripes stay fixed to the object as it moves.
    pub fn from_matrix(
        world_to_clip: DMat4,
        width: u32,
        height: u32,
        normal: DVec3,
        point: DVec3,
        gradient: DVec3,
        p0: f64,
    ) -> Result<ScreenMapping, EdgeOn> {
        // Move the origin to `point`: a row r acting on (X, 1) acts on (Y, 1),
        // Y = X − point, as (r.xyz, r · (point, 1)).
        let shift = |r: DVec4| r.truncate().extend(r.dot(point.extend(1.0)));
        let [s0, s1, s2] = screen_rows_of(world_to_clip, width, height).map(shift);
        let plane = normal.extend(0.0);
        // The centre of projection (a direction, w = 0, for parallel views) is
        // the null vector of the screen rows; a plane through it is edge-on.
        let centre = cross4(s0, s1, s2);
        let seen = plane.dot(centre).abs();
        let limit = EDGE_ON_RELATIVE * normal.length() * centre.truncate().length();
        if seen.is_nan() || seen <= limit {
            return Err(EdgeOn);
        }
        let k0 = cross4(s0, s1, plane);
        let kx = -cross4(s2, s1, plane);
        let ky = -cross4(s0, s2, plane);
        let u = gradient.extend(p0 + gradient.dot(point));
        let mut c = [u.dot(kx), u.dot(ky), u.dot(k0), kx.w, ky.w, k0.w];
        let scale = [k0, kx, ky]
            .iter()
            .map(|k| k.abs().max_element())
            .fold(0.0, f64::max);
        let denom = c[3].abs().max(c[4].abs()).max(c[5].abs());
        if denom <= EDGE_ON_RELATIVE * scale || !c.iter().all(|v| v.is_finite()) {
            // Not reached for a plane that passes the test above; kept so that
            // no division by zero can ever leave this function.
            return Err(EdgeOn);
        }
        for v in &mut c {
            *v /= denom;
        }
        Ok(ScreenMapping { c })
    }

    /// The denominator at `(x, y)`: proportional to `X̃_w`; its sign is constant
    /// over the face's image and it is zero on the plane's vanishing line.
    #[inline]
    pub fn denominator(&self, x: f64, y: f64) -> f64 {
        self.c[3] * x + self.c[4] * y + self.c[5]
    }

    /// The numerator at `(x, y)`: `P` times [`ScreenMapping::denominator`].
    #[inline]
    pub fn numerator(&self, x: f64, y: f64) -> f64 {
        self.c[0] * x + self.c[1] * y + self.c[2]
    }

    /// `P` at the screen position `(x, y)`.
    #[inline]
    pub fn p(&self, x: f64, y: f64) -> f64 {
        self.numerator(x, y) / self.denominator(x, y)
    }

    /// `P` and its screen-space derivatives `(∂P/∂x, ∂P/∂y)`, analytically:
    /// `∂P/∂x = (C1 − C4 P) / D`, `∂P/∂y = (C2 − C5 P) / D`.
    #[inline]
    pub fn p_and_gradient(&self, x: f64, y: f64) -> (f64, f64, f64) {
        let d = self.denominator(x, y);
        let inv = 1.0 / d;
        let p = self.numerator(x, y) * inv;
        (
            p,
            (self.c[0] - self.c[3] * p) * inv,
            (self.c[1] - self.c[4] * p) * inv,
        )
    }

    /// The line `a x + b y + c = 0` on which `P = value` (all such lines meet
    /// at the vanishing point of the stripes).
    pub fn iso_line(&self, value: f64) -> [f64; 3] {
        [
            self.c[0] - value * self.c[3],
            self.c[1] - value * self.c[4],
            self.c[2] - value * self.c[5],
        ]
    }
}

/// Direct evaluation, the independent check of [`ScreenMapping`]: unproject
/// the screen position to two points of its ray (depths 1 and 2 along the
/// view direction), intersect the ray with the plane, and return the world
/// point. None if the ray is parallel to the plane.
pub fn unproject_to_plane(
    camera: &Camera,
    width: u32,
    height: u32,
    x: f64,
    y: f64,
    normal: DVec3,
    point: DVec3,
) -> Option<DVec3> {
    let [s0, s1, s2] = screen_rows(camera, width, height);
    let depth = camera.world_to_clip().row(2);
    let at_depth = |z: f64| -> Option<DVec3> {
        let a = s0 - s2 * x;
        let b = s1 - s2 * y;
        let c = depth - DVec4::new(0.0, 0.0, 0.0, z);
        let m = DMat3::from_cols(a.truncate(), b.truncate(), c.truncate()).transpose();
        let rhs = -DVec3::new(a.w, b.w, c.w);
        (m.determinant().abs() > 0.0).then(|| m.inverse() * rhs)
    };
    let (p1, p2) = (at_depth(1.0)?, at_depth(2.0)?);
    let dir = p2 - p1;
    let denom = normal.dot(dir);
    (denom != 0.0).then(|| p1 + dir * (normal.dot(point - p1) / denom))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// The rational form agrees with direct evaluation to this relative error
    /// (of `P − P0`, over the range of P at hand): the brief's 1e-9.
    const AGREE_RELATIVE: f64 = 1e-9;
    /// Analytic derivatives against Richardson-extrapolated differences with
    /// steps of 1/100 pixel: truncation (step/distance to the horizon)^4
    /// stays well below this.
    const DERIVATIVE_RELATIVE: f64 = 1e-4;
    /// The differences' own round-off, absolute: about 1e-16 |P| per
    /// evaluation over a step of 5e-3 px, with a wide margin. Without it a
    /// constant P (zero gradient) failed on 1.5e-14 of noise.
    const DIFFERENCE_ROUNDOFF: f64 = 1e-12;
    /// Points closer than this (pixels) to the plane's horizon are not
    /// compared: there P grows like 1/distance, and both the rational form
    /// and the direct unprojection lose digits in proportion (a point a
    /// fraction of a pixel from the horizon, 3.4e6 units away, differed by a
    /// relative 3e-9).
    const HORIZON_MARGIN_PX: f64 = 1.0;

    fn camera(v: serde_json::Value) -> Camera {
        Camera::from_json(&v, "test").unwrap()
    }

    fn check(
        cam: &Camera,
        w: u32,
        h: u32,
        normal: DVec3,
        point: DVec3,
        grad: DVec3,
        p0: f64,
    ) -> usize {
        let map = ScreenMapping::new(cam, w, h, normal, point, grad, p0).unwrap();
        let mut checked = 0;
        for j in 0..=16 {
            for i in 0..=16 {
                let (x, y) = (w as f64 * i as f64 / 16.0, h as f64 * j as f64 / 16.0);
                let Some(xw) = unproject_to_plane(cam, w, h, x, y, normal, point) else {
                    continue;
                };
                // Only points in front of the camera are seen.
                let clip = cam.world_to_clip() * xw.extend(1.0);
                if clip.w <= 0.0 {
                    continue;
                }
                let horizon = map.denominator(x, y).abs() / crate::math::hypot(map.c[3], map.c[4]);
                if horizon < HORIZON_MARGIN_PX {
                    continue;
                }
                let direct = p0 + grad.dot(xw);
                let rational = map.p(x, y);
                let scale = (direct - p0)
                    .abs()
                    .max(grad.length() * (xw - point).length())
                    .max(1e-300);
                assert!(
                    (direct - rational).abs() <= AGREE_RELATIVE * scale.max(direct.abs()),
                    "({x},{y}): direct {direct} rational {rational}"
                );
                // The analytic derivatives agree with central differences.
                // Richardson-extrapolated central differences: O(e^4) error.
                let (_, px, py) = map.p_and_gradient(x, y);
                let diff = |f: &dyn Fn(f64) -> f64, e: f64| (f(e) - f(-e)) / (2.0 * e);
                let rich = |f: &dyn Fn(f64) -> f64| (4.0 * diff(f, 5e-3) - diff(f, 1e-2)) / 3.0;
                let fx = rich(&|e| map.p(x + e, y));
                let fy = rich(&|e| map.p(x, y + e));
                let tol = DERIVATIVE_RELATIVE * crate::math::hypot(px, py)
                    + DIFFERENCE_ROUNDOFF * rational.abs().max(1.0);
                assert!(
                    (px - fx).abs() <= tol && (py - fy).abs() <= tol,
                    "{px} {fx} {py} {fy}"
                );
                checked += 1;
            }
        }
        checked
    }

    proptest::proptest! {
        #[test]
        fn random_views_and_planes_match_direct_evaluation(
            eye in proptest::array::uniform3(-50.0f64..50.0),
            look in proptest::array::uniform3(-1.0f64..1.0),
            fovy in 10.0f64..120.0,
            normal in proptest::array::uniform3(-1.0f64..1.0),
            offset in -20.0f64..20.0,
            grad in proptest::array::uniform3(-0.01f64..0.01),
            p0 in -2.0f64..2.0,
            ortho in proptest::bool::ANY,
        ) {
            let (eye, look, normal) = (DVec3::from(eye), DVec3::from(look), DVec3::from(normal));
            proptest::prop_assume!(look.length() > 0.1 && normal.length() > 0.1);
            // Keep "up" away from the line of sight.
            let up = if look.normalize().y.abs() > 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
            let centre = eye + look;
            let projection = if ortho {
                json!({"ortho": {"left": -10, "right": 10, "bottom": -8, "top": 8, "near": 0.1, "far": 1e4}})
            } else {
                json!({"perspective": {"fovy": fovy, "aspect": 1.25, "near": 0.1, "far": 1e4}})
            };
            let mut v = json!({"lookat": {"eye": eye.to_array(), "center": centre.to_array(), "up": up}});
            v.as_object_mut().unwrap().extend(projection.as_object().unwrap().clone());
            let cam = camera(v);
            let normal = normal.normalize();
            let point = eye + normal * offset;
            // Planes seen (nearly) edge-on are refused, which is right.
            if ScreenMapping::new(&cam, 320, 256, normal, point, DVec3::from(grad), p0).is_ok() {
                check(&cam, 320, 256, normal, point, DVec3::from(grad), p0);
            }
        }
    }

    #[test]
    fn ground_plane_and_wall_match_direct_evaluation() {
        let cam = camera(json!({
            "lookat": {"eye": [3, 2, 10], "center": [0, 0, -20], "up": [0, 1, 0]},
            "perspective": {"fovy": 60, "aspect": 4.0/3.0, "near": 0.1, "far": 1000}
        }));
        let grad = DVec3::new(0.3, 0.0, -0.7) / 1024.0;
        let ground = check(&cam, 1024, 768, DVec3::Y, DVec3::ZERO, grad, 0.25);
        assert!(ground > 100, "{ground}");
        let wall = check(
            &cam,
            1024,
            768,
            DVec3::Z,
            DVec3::new(0.0, 0.0, -30.0),
            DVec3::X / 512.0,
            0.0,
        );
        assert!(wall > 200, "{wall}");
    }

    #[test]
    fn grazing_angles_and_far_coordinates_match_direct_evaluation() {
        // The eye 1e-3 above a ground plane far from the origin: rays meet the
        // plane at angles down to ~1e-5 rad near the horizon.
        let cam = camera(json!({
            "lookat": {"eye": [5000, 0.001, 7000], "center": [5000, 0.0, 6000], "up": [0, 1, 0]},
            "perspective": {"fovy": 40, "aspect": 1.0, "near": 0.0, "far": 1e6}
        }));
        let grad = DVec3::new(0.6, 0.0, 0.8) / (1024.0 * 0.25);
        let n = check(
            &cam,
            256,
            256,
            DVec3::Y,
            DVec3::new(5000.0, 0.0, 6000.0),
            grad,
            0.5,
        );
        assert!(n > 50, "{n}");
        // A tilted plane nearly containing the line of sight.
        let tilt = DVec3::new(0.0, 1.0, 1e-3).normalize();
        let cam2 = camera(json!({
            "lookat": {"eye": [0, 1, 0], "center": [0, 1, -1], "up": [0, 1, 0]},
            "perspective": {"fovy": 50, "aspect": 1.0, "near": 0.01, "far": 1e6}
        }));
        let n2 = check(&cam2, 200, 200, tilt, DVec3::ZERO, DVec3::Z / 1024.0, 0.0);
        assert!(n2 > 20, "{n2}");
    }

    #[test]
    fn parallel_and_oblique_views_are_affine_and_match() {
        let cam = camera(json!({
            "lookat": {"eye": [0, 5, 5], "center": [0, 0, 0], "up": [0, 1, 0]},
            "ortho": {"left": -4, "right": 4, "bottom": -3, "top": 3, "near": 0.1, "far": 100}
        }));
        let grad = DVec3::new(1.0, 0.0, 1.0) / 64.0;
        let map = ScreenMapping::new(&cam, 400, 300, DVec3::Y, DVec3::ZERO, grad, 0.1).unwrap();
        assert!(
            map.c[3].abs() < 1e-15 && map.c[4].abs() < 1e-15,
            "{:?}",
            map.c
        );
        assert!(check(&cam, 400, 300, DVec3::Y, DVec3::ZERO, grad, 0.1) > 250);
    }

    #[test]
    fn a_face_seen_edge_on_has_no_mapping() {
        let cam = camera(json!({
            "lookat": {"eye": [0, 0, 5], "center": [0, 0, 0], "up": [0, 1, 0]},
            "perspective": {"fovy": 60, "aspect": 1.0, "near": 0.1, "far": 100}
        }));
        // The plane y = 0 contains the eye.
        assert_eq!(
            ScreenMapping::new(&cam, 64, 64, DVec3::Y, DVec3::ZERO, DVec3::X, 0.0),
            Err(EdgeOn)
        );
    }

    #[test]
    fn iso_lines_carry_constant_p() {
        let cam = camera(json!({
            "lookat": {"eye": [0, 2, 5], "center": [0, 0, -5], "up": [0, 1, 0]},
            "perspective": {"fovy": 60, "aspect": 1.0, "near": 0.1, "far": 100}
        }));
        let map = ScreenMapping::new(
            &cam,
            100,
            100,
            DVec3::Y,
            DVec3::ZERO,
            DVec3::new(0.2, 0.0, 0.1),
            0.0,
        )
        .unwrap();
        let [a, b, c] = map.iso_line(0.3);
        for x in [10.0, 50.0, 90.0] {
            let y = -(a * x + c) / b;
            assert!((map.p(x, y) - 0.3).abs() < 1e-12);
        }
    }
}
