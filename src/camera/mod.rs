//! The camera (docs/camera.md): world → eye → clip matrices from either of the seeds'
//! two viewing models, with every degenerate specification rejected by name.
//!
//! # Why one `Camera` for two models
//!
//! `scene-render` accepts the IRIS GL / GLU camera of the thesis (`lookat` plus
//! `perspective`, `ortho` or `ortho2`) and the textbook's view system (Harrington,
//! *Computer Graphics: A Programming Approach*, ch. 8, "Viewing parameters" to
//! "The 3D viewing transformation": view reference point, view plane normal, view
//! distance, view-up, window, centre or direction of projection, front and back
//! planes). Both are reduced to the same pair of matrices, so the renderer has one
//! code path and the same view described both ways gives the same `world_to_clip`
//! (tested to 1e-12 below).
//!
//! # Coordinates
//!
//! * World: right-handed, y up (docs/camera.md).
//! * Eye ([`Camera::view`]): right-handed, x right and y up on the image, looking
//!   down −z; the origin is the centre of projection for perspective views and
//!   the view reference point (or the GL eye) for parallel views.
//! * Clip ([`Camera::projection`]): `clip = projection * eye` (column vectors).
//!   Visible is `-w <= x <= w`, `-w <= y <= w` (the window fills the image,
//!   its lower-left at the image's bottom-left) and `near <= z <= far`, where
//!   `z_clip = -z_eye` (the distance along the view direction) for every camera;
//!   `w = -z_eye` for perspective, `w = 1` for parallel. Unlike OpenGL, depth is
//!   not squashed into [−1, 1], which is why `near = 0` (the thesis's
//!   `perspective(550, 1.0, 0.0, 1000.0)`) works.
//!
//! # The textbook's conventions, as decided here
//!
//! The OCR'd chapter garbles the formulas; they were rebuilt from the algorithms,
//! which are consistent with each other:
//!
//! * The chapter itself "adopt\[s\] the right-handed system". Its view plane
//!   coordinates (Alg. 8.20, eqs. 8.59–8.66) are built from proper rotations only
//!   (R_x, R_y, R_z all have determinant +1): R_x R_y take the view plane normal to
//!   **−z** and R_z takes the projected view-up to **+y**. So the view plane
//!   system is right-handed with x right, y up and z towards the viewer — the GL eye
//!   system translated to the view plane. No handedness flip is needed; world
//!   coordinates map to it unchanged.
//! * The VPN points the way the camera looks ("the camera is pointed in the
//!   direction of the view plane normal"): the default view (Alg. 8.41) has
//!   VPN = (0, 0, −1), the isometric example looks along VPN = (−1, −1, −1) at the
//!   upper-right-front corner, and the flight simulator sets the VPN to the
//!   direction of flight. Depth therefore grows along the VPN, and front/back
//!   distances (Alg. 8.23) are measured from the VRP along the VPN: visible is
//!   `front <= s <= back` (eqs. 8.71–8.72 with FRONT-Z = VIEW-DISTANCE − FRONT).
//! * The view plane lies VIEW-DISTANCE from the VRP along the VPN (eq. 8.60); the
//!   window `[umin, umax, vmin, vmax]` is in view plane coordinates, centred
//!   where the VPN line through the VRP meets the view plane (Fig. 8-44).
//! * The centre of projection (SET-PERSPECTIVE, Alg. 8.19) and the direction of
//!   projection (SET-PARALLEL, Alg. 8.18) are given in **world** coordinates:
//!   Alg. 8.21/8.22 convert them with the view plane transformation, and the
//!   flight simulator passes the pilot's world position. The COP must lie on the
//!   viewer's side of the view plane (Alg. 8.21, ZC > 0 in view plane
//!   coordinates); a COP off the VPN line gives an off-axis (sheared) frustum.
//! * Perspective projection is eq. 8.45 (x₂ = (x_c z₁ − x₁ z_c)/(z₁ − z_c)),
//!   parallel projection eq. 8.37 (x₂ = x₁ − z₁ x_p/z_p). The oblique forms of the
//!   "Special projections" section are expressed in view plane coordinates:
//!   cavalier is the DOP (cos A, sin A, 1), cabinet (cos A, sin A, 2), so a point
//!   one unit behind the view plane shifts 1 (cavalier) or 1/2 (cabinet) up and
//!   to the right at angle A (default 45°). Isometric is the parallel projection
//!   along a VPN whose three components have equal magnitude (default VPN
//!   (−1, −1, −1), as in the book's example).
//! * The book's clipping is off by default; a renderer needs a bounded volume, so
//!   `front` and `back` are required here.
//!
//! # The IRIS GL / GLU model
//!
//! `lookat` is gluLookAt (eye, center, up; up defaults to +y). IRIS GL's
//! `lookat(vx,vy,vz, px,py,pz, twist)` has no up vector but a twist that "measures
//! right-hand rotation about the line of sight" (IRIS man page), given in tenths of
//! degrees in C; the JSON takes degrees. The world as seen turns right-handedly by
//! twist about the line of sight eye→center (the −z eye axis), i.e. by −twist about
//! +z eye: `view = R_z(−twist) · lookAt(eye, center, up)`, the `rot(-twist, 'z')`
//! applied last in eye space as IRIS-compatible libraries build `lookat` and
//! `polarview`. A twist of 0 keeps world +y up on the image. `up` and `twist` may
//! be combined. No `lookat` means the identity view, as in GL.
//! `perspective` is gluPerspective (fovy in degrees, aspect = width/height),
//! `ortho` is glOrtho, `ortho2` is gluOrtho2D with near = −1, far = 1.
//!
//! # JSON
//!
//! ```json
//! {"lookat": {"eye": [0,100,-5], "center": [0,0,-900], "twist": 0},
//!  "perspective": {"fovy": 55, "aspect": 1.0, "near": 0, "far": 1000}}
//! {"ortho": {"left": -1, "right": 1, "bottom": -1, "top": 1, "near": -1, "far": 1}}
//! {"ortho2": [0, 1023, 0, 767]}
//! {"view": {"vrp": [0,0,0], "vpn": [0,0,-1], "view_up": [0,1,0], "view_distance": 0,
//!           "window": [-1, 1, -1, 1], "cop": [0, 0, 2], "front": 0, "back": 10}}
//! ```
//!
//! In `"view"` exactly one of `"cop": [x,y,z]`, `"dop": [x,y,z]`,
//! `"oblique": {"kind": "cavalier"|"cabinet", "angle": deg}` or `"isometric": true`
//! gives the projection; `vrp` defaults to the origin, `vpn` to (0,0,−1) ((−1,−1,−1)
//! for isometric), `view_up` to +y and `view_distance` to 0 (Alg. 8.41);
//! `window`, `front` and `back` are required. Unknown keys are errors (typos).
//! See also `docs/camera.md`.
//!
//! # One specification, three ways in
//!
//! A camera is first a [`CameraSpec`]: the values of one of the two models, typed
//! but not yet checked (`spec.rs`). [`Camera::from_spec`] holds every geometric
//! check and builds the matrices. The JSON form above is read into a `CameraSpec`
//! by [`Camera::from_json`] and [`Camera::load`] (`json.rs`), which only adds the
//! checks of types and keys (and runs some of the spec's checks early, the same
//! functions, so that the first error reported is the one the book's order
//! meets first); the tools' camera flags build a `CameraSpec` directly, and
//! [`Camera::try_ortho2`] does the same. So a view given as a file, as flags or in
//! code is checked by the same code, reported with the same words and gives the
//! same matrices, bit for bit.
//!
//! Errors are [`CameraError`]s: `{origin}: {field}: {message}`, where the field is
//! named by its JSON path (`lookat.center`, `view.cop`, `perspective.fovy`, or
//! `camera` for the whole), whatever the camera was written in.

use std::fmt;

use glam::{DMat3, DMat4, DVec3};

mod json;
mod spec;

pub use spec::{
    Aspect, CameraSpec, IrisProjection, IrisSpec, LookAt, ObliqueKind, Ortho, Ortho2, Perspective,
    ViewProjection, ViewSpec, Window, DEFAULT_OBLIQUE_ANGLE,
};

/// The camera: world → eye (`view`) and eye → clip (`projection`).
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// world → eye: right-handed, eye at the origin (for parallel views: the view
    /// reference point), looking down −z, y up on the image.
    pub view: DMat4,
    /// eye → clip (column-vector convention, clip = projection * eye). The visible
    /// volume is −w ≤ x_clip ≤ w, −w ≤ y_clip ≤ w (the window maps to the whole
    /// image), and near ≤ z_clip ≤ far, where z_clip = −z_eye (the distance along
    /// the view direction) for EVERY camera, and w_clip = −z_eye for perspective
    /// (COP at the eye origin), w_clip = 1 for parallel. Oblique projections and
    /// off-axis windows are shears/offsets in the x and y rows only.
    pub projection: DMat4,
    /// Distances along the view direction bounding the view volume (near may be 0
    /// for perspective; may be negative for parallel views, e.g. a front plane
    /// behind the VRP). near < far always.
    pub near: f64,
    /// See `near`.
    pub far: f64,
    /// Whether `projection` is a perspective one (w_clip = −z_eye) rather than
    /// parallel (w_clip = 1).
    pub perspective: bool,
    /// Whether the window's width / height is the image's ([`Aspect::Auto`]):
    /// `projection` is then built for a square window until
    /// [`Camera::for_image`] fits it.
    pub aspect_from_image: bool,
}

/// Why a camera could not be made. `Display` gives the whole line the tools print
/// after `TOOL: error: `; `std::error::Error::source` gives the I/O cause of
/// [`CameraError::Read`] (so a front end printing the chain, as the tools do
/// with `anyhow`'s `{:#}`, prints `context: cause`).
#[derive(Debug)]
pub enum CameraError {
    /// The specification is wrong: a JSON value of the wrong type, a missing or
    /// unknown key, no projection or several, both models at once, or a
    /// degenerate view (coincident points, zero vectors, an empty view volume...).
    Invalid {
        /// Where the specification came from (a file name, `<stdin>`, `camera
        /// flags`, `ortho2`); None for [`Camera::from_spec`], which does not know.
        /// (Not called `source`, which `std::error::Error` uses for the cause.)
        origin: Option<String>,
        /// The offending field as a JSON path: `lookat.center`, `view.oblique.kind`,
        /// `ortho2`; `camera` for the whole specification.
        field: String,
        /// What is wrong with it, and where the textbook names the error, its name.
        message: String,
    },
    /// A camera file (or standard input, path `-`) could not be read.
    Read {
        /// The path as given; `-` is standard input.
        path: String,
        /// The cause.
        error: std::io::Error,
    },
    /// A camera file is not JSON.
    Json {
        /// The file name (`<stdin>` for standard input).
        origin: String,
        /// The parser's complaint, with its line and column.
        error: serde_json::Error,
    },
}

impl CameraError {
    /// An invalid field, origin not yet known.
    pub(crate) fn invalid(field: impl Into<String>, message: impl fmt::Display) -> CameraError {
        CameraError::Invalid {
            origin: None,
            field: field.into(),
            message: message.to_string(),
        }
    }

    /// Names where the specification came from (a file name, `camera flags`), for
    /// an [`CameraError::Invalid`] that does not name it yet; other errors already
    /// name their file and are returned unchanged.
    pub fn with_origin(self, origin: &str) -> CameraError {
        match self {
            CameraError::Invalid {
                origin: None,
                field,
                message,
            } => CameraError::Invalid {
                origin: Some(origin.to_string()),
                field,
                message,
            },
            other => other,
        }
    }
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CameraError::Invalid {
                origin: Some(origin),
                field,
                message,
            } => write!(f, "{origin}: {field}: {message}"),
            CameraError::Invalid {
                origin: None,
                field,
                message,
            } => write!(f, "{field}: {message}"),
            CameraError::Read { path, .. } if path == "-" => {
                f.write_str("reading the camera from standard input")
            }
            CameraError::Read { path, .. } if path.is_empty() => {
                f.write_str("an empty camera file name")
            }
            CameraError::Read { path, .. } => write!(f, "{path}: cannot read camera"),
            CameraError::Json { origin, error } => {
                write!(f, "{origin}: not valid camera JSON: {error}")
            }
        }
    }
}

impl std::error::Error for CameraError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CameraError::Read { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// The rotation from world axes to eye axes for a camera looking along `forward`
/// with `up` projected to +y: rows x = forward × up, y = x × forward, z = −forward.
/// (Equivalent to the textbook's R_x R_y R_z of eqs. 8.61–8.64, and to gluLookAt.)
/// The caller has checked that forward and up are non-zero and not parallel.
/// Normalized by [`crate::vector::normalized`], so that a VPN or view-up of
/// `[1e300, 1e300, 1e300]` (whose squared length overflows) is a direction
/// and not NaN; ordinary vectors give the bits of `normalize()`.
fn eye_rotation(forward: DVec3, up: DVec3) -> DMat3 {
    let unit = |v: DVec3| crate::vector::normalized(v).unwrap_or(DVec3::NAN);
    let f = unit(forward);
    let s = unit(f.cross(up));
    let u = s.cross(f);
    DMat3::from_cols(s, u, -f).transpose()
}

/// world → eye for an eye at `origin` with the rotation `r` (world → eye axes).
fn view_matrix(r: DMat3, origin: DVec3) -> DMat4 {
    let t = -(r * origin);
    DMat4::from_cols(
        r.x_axis.extend(0.0),
        r.y_axis.extend(0.0),
        r.z_axis.extend(0.0),
        t.extend(1.0),
    )
}

/// A matrix from its rows (the textbook and GL documents write matrices by rows).
fn from_rows(rows: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&rows).transpose()
}

/// z_clip = −z_eye, the distance along the view direction (every camera).
const DEPTH_ROW: [f64; 4] = [0.0, 0.0, -1.0, 0.0];
/// w_clip = −z_eye: perspective with the COP at the eye origin.
const PERSPECTIVE_W_ROW: [f64; 4] = [0.0, 0.0, -1.0, 0.0];
/// w_clip = 1: parallel projection.
const PARALLEL_W_ROW: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// An orthographic projection of the eye-space box [l, r] × [b, t] (glOrtho's x
/// and y rows; depth is z_clip = −z_eye as for every camera).
fn ortho_matrix(l: f64, r: f64, b: f64, t: f64) -> DMat4 {
    from_rows([
        [2.0 / (r - l), 0.0, 0.0, -(r + l) / (r - l)],
        [0.0, 2.0 / (t - b), 0.0, -(t + b) / (t - b)],
        DEPTH_ROW,
        PARALLEL_W_ROW,
    ])
}

impl Camera {
    /// IRIS GL `ortho2(left, right, bottom, top)` (gluOrtho2D): identity view,
    /// parallel projection, near = −1, far = 1 as in GL.
    ///
    /// # Panics
    /// If an edge pair coincides or a value is not finite; use [`Camera::try_ortho2`]
    /// for user input.
    pub fn ortho2(left: f64, right: f64, bottom: f64, top: f64) -> Camera {
        match Camera::try_ortho2(left, right, bottom, top) {
            Ok(camera) => camera,
            Err(e) => panic!("Camera::ortho2: {e}"),
        }
    }

    /// [`Camera::ortho2`] with the degenerate cases as errors (origin `ortho2`,
    /// field `ortho2`, as the JSON `{"ortho2": [...]}` would report them).
    pub fn try_ortho2(left: f64, right: f64, bottom: f64, top: f64) -> Result<Camera, CameraError> {
        let spec = CameraSpec::Iris(IrisSpec {
            lookat: None,
            projection: vec![IrisProjection::Ortho2(Ortho2 {
                left,
                right,
                bottom,
                top,
            })],
        });
        Camera::from_spec(&spec).map_err(|e| e.with_origin("ortho2"))
    }

    /// This camera on a `width` x `height` image: an [`Aspect::Auto`]
    /// perspective takes the image's ratio, with the same arithmetic as the
    /// ratio given as a number (`f / aspect`), so `auto` and `4/3` at 1024x768
    /// give the same bits.
    pub fn for_image(&self, width: u32, height: u32) -> Camera {
        let mut c = self.clone();
        if c.aspect_from_image {
            // Built with aspect 1: the x scale is f / 1.0 = f exactly.
            let f = c.projection.x_axis.x;
            c.projection.x_axis.x = f / (width as f64 / height as f64);
            c.aspect_from_image = false;
        }
        c
    }

    /// world → clip: `projection * view`.
    pub fn world_to_clip(&self) -> DMat4 {
        self.projection * self.view
    }

    /// The world-space centre of projection for perspective views; None for parallel.
    pub fn eye_position(&self) -> Option<DVec3> {
        self.perspective
            .then(|| self.view.inverse().transform_point3(DVec3::ZERO))
    }

    /// The world-space unit vector the camera looks along: the −z eye axis for
    /// perspective; for parallel views the direction of projection (which may be
    /// oblique), pointing into the scene.
    pub fn view_direction(&self) -> DVec3 {
        let eye_dir = if self.perspective {
            DVec3::NEG_Z
        } else {
            // The direction d (with d.z = −1) along which x_clip and y_clip do not
            // change: the x and y rows of the projection annihilate it.
            let r0 = self.projection.row(0);
            let r1 = self.projection.row(1);
            let det = r0.x * r1.y - r0.y * r1.x;
            let dx = (r0.z * r1.y - r0.y * r1.z) / det;
            let dy = (r0.x * r1.z - r0.z * r1.x) / det;
            DVec3::new(dx, dy, -1.0)
        };
        self.view.inverse().transform_vector3(eye_dir).normalize()
    }
}

/// Helpers shared by the camera tests, here and in the tools' flag tests.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;
    use serde_json::{json, Value};

    /// Agreement demanded of two descriptions of the same view.
    pub(crate) const SAME_VIEW: f64 = 1e-12;
    /// Tolerance for projected coordinates computed through a few matrix products.
    pub(crate) const CLOSE: f64 = 1e-9;

    pub(crate) fn cam(v: Value) -> Camera {
        Camera::from_json(&v, "test.json").unwrap_or_else(|e| panic!("{e:#}"))
    }

    /// The error message for a camera that must be rejected.
    pub(crate) fn err(v: Value) -> String {
        match Camera::from_json(&v, "test.json") {
            Ok(c) => panic!("accepted: {c:?}"),
            Err(e) => format!("{e:#}"),
        }
    }

    pub(crate) fn assert_err(v: Value, parts: &[&str]) {
        let msg = err(v);
        assert!(msg.starts_with("test.json: "), "{msg}");
        for part in parts {
            assert!(msg.contains(part), "{msg:?} lacks {part:?}");
        }
    }

    /// Normalised device coordinates of a world point.
    pub(crate) fn ndc(c: &Camera, p: DVec3) -> DVec3 {
        let clip = c.world_to_clip() * p.extend(1.0);
        clip.truncate() / clip.w
    }

    pub(crate) fn demo2() -> Value {
        json!({"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900], "twist": 0},
               "perspective": {"fovy": 55, "aspect": 1.0, "near": 0, "far": 1000}})
    }

    pub(crate) fn max_diff(a: DMat4, b: DMat4) -> f64 {
        (a - b)
            .to_cols_array()
            .iter()
            .fold(0.0, |m, x| m.max(x.abs()))
    }

    /// A view system camera on the default (GL-like) orientation.
    pub(crate) fn view(extra: Value) -> Value {
        let mut v = json!({"window": [-1, 1, -1, 1], "front": -10, "back": 10});
        for (k, x) in extra.as_object().unwrap() {
            v[k] = x.clone();
        }
        json!({ "view": v })
    }

    /// Whether two cameras are the same to the bit (`PartialEq` on f64 would let
    /// 0 equal −0).
    pub(crate) fn same_bits(a: &Camera, b: &Camera) -> bool {
        let bits = |c: &Camera| {
            let mut v: Vec<u64> = c.view.to_cols_array().iter().map(|x| x.to_bits()).collect();
            v.extend(c.projection.to_cols_array().iter().map(|x| x.to_bits()));
            v.extend([c.near.to_bits(), c.far.to_bits(), u64::from(c.perspective)]);
            v
        };
        bits(a) == bits(b)
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use serde_json::json;

    #[test]
    fn auto_aspect_is_the_images_ratio_to_the_bit() {
        let with = |aspect: serde_json::Value| {
            cam(
                json!({"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900]},
                       "perspective": {"fovy": 55, "aspect": aspect, "near": 0, "far": 1000}}),
            )
        };
        let auto = with(json!("auto"));
        assert!(auto.aspect_from_image);
        for (w, h) in [(1024u32, 768u32), (640, 480), (1000, 333), (7, 1000)] {
            let fitted = auto.for_image(w, h);
            let given = with(json!(w as f64 / h as f64));
            assert_eq!(fitted, given, "{w}x{h}");
            // A camera given a ratio keeps it, whatever the image.
            assert_eq!(given.for_image(h, w), given);
        }
        let bad = Camera::from_json(
            &json!({"perspective": {"fovy": 55, "aspect": "wide", "near": 0, "far": 1}}),
            "cam.json",
        )
        .unwrap_err()
        .to_string();
        assert!(
            bad.contains("perspective.aspect") && bad.contains("\"wide\""),
            "{bad}"
        );
    }

    #[test]
    fn demo2_maps_straight_ahead_to_the_centre() {
        let c = cam(demo2());
        assert!(c.perspective);
        assert_eq!((c.near, c.far), (0.0, 1000.0));
        let eye = DVec3::new(0.0, 100.0, -5.0);
        let ahead = DVec3::new(0.0, 0.0, -900.0);
        let p = ndc(&c, ahead);
        assert!(p.x.abs() < CLOSE && p.y.abs() < CLOSE, "{p}");
        let clip = c.world_to_clip() * ahead.extend(1.0);
        assert!(
            (clip.z - (ahead - eye).length()).abs() < CLOSE,
            "z_clip is the distance"
        );
        assert!((clip.w - clip.z).abs() < CLOSE);
        assert!((c.eye_position().unwrap() - eye).length() < CLOSE);
        assert!((c.view_direction() - (ahead - eye).normalize()).length() < CLOSE);
        // The floor (y = 0) below the line of sight is in the lower half of the image.
        assert!(ndc(&c, DVec3::new(0.0, 0.0, -300.0)).y < 0.0);
        // +x world is to the right: the camera looks down -z with y up.
        assert!(ndc(&c, DVec3::new(50.0, 0.0, -900.0)).x > 0.0);
    }

    #[test]
    fn ortho2_maps_the_screen_corners() {
        let c = Camera::ortho2(0.0, 1023.0, 0.0, 767.0);
        assert!(!c.perspective);
        assert_eq!((c.near, c.far), (-1.0, 1.0));
        let a = ndc(&c, DVec3::new(0.0, 0.0, 0.0));
        let b = ndc(&c, DVec3::new(1023.0, 767.0, 0.0));
        assert!((a - DVec3::new(-1.0, -1.0, 0.0)).length() < CLOSE, "{a}");
        assert!((b - DVec3::new(1.0, 1.0, 0.0)).length() < CLOSE, "{b}");
        assert_eq!(c.eye_position(), None);
        assert!((c.view_direction() - DVec3::NEG_Z).length() < CLOSE);
        assert_eq!(c, cam(json!({"ortho2": [0, 1023, 0, 767]})));
    }

    #[test]
    fn ortho2_is_ortho_with_gl_depth() {
        let a = Camera::ortho2(-3.0, 5.0, 2.0, 7.0);
        let b = cam(
            json!({"ortho": {"left": -3, "right": 5, "bottom": 2, "top": 7,
                                      "near": -1, "far": 1}}),
        );
        assert!(max_diff(a.world_to_clip(), b.world_to_clip()) <= SAME_VIEW);
        assert_eq!((a.near, a.far), (b.near, b.far));
    }
}
