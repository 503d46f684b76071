//! The typed camera specification and [`Camera::from_spec`], which checks it and
//! builds the matrices of either model (conventions and citations in the docs of
//! [`camera`](super)).
//!
//! A [`CameraSpec`] holds what was given, typed but unchecked: it can still say
//! "no window", "no projection" or "two projections", because the JSON file and
//! the flags can, and those must be reported as the same errors, in the same
//! order, whatever the camera was written in. Everything that can be wrong with
//! values of the right type is found here; the readers only find what their
//! syntax can get wrong (a JSON value of the wrong type, an unknown key, a number
//! missing from `lookat` or a projection, both models at once).
//!
//! The checks run in the order the textbook's algorithms read their inputs (the
//! viewing parameters of Alg. 8.14–8.17, the window, the view depth of Alg. 8.23,
//! then the projection of Alg. 8.21/8.22), so the first error is the one the book
//! would meet first. The JSON reader interleaves its own type checks with the
//! stage functions below (`checked_vpn` ... `checked_back`) in the same order.

use glam::{DMat4, DVec3, DVec4};

use super::{
    eye_rotation, from_rows, ortho_matrix, view_matrix, Camera, CameraError, DEPTH_ROW,
    PARALLEL_W_ROW, PERSPECTIVE_W_ROW,
};
use crate::math;

/// Below this length a direction vector counts as zero: the textbook's ROUNDOFF,
/// "some small number greater than any round-off error" (Alg. 8.15, 8.17, 8.18).
const ROUNDOFF: f64 = 1e-12;

/// Two directions whose angle has a sine below this count as parallel (view-up
/// along the VPN, up along the line of sight, a DOP in the view plane). 1e-9 rad
/// is far below any intended view and far above f64 round-off of the cross product.
const PARALLEL_SINE: f64 = 1e-9;

/// Two points or window edges closer than this, relative to their magnitude (at
/// least 1), coincide: the matrices would divide by (nearly) zero.
const COINCIDENT_RELATIVE: f64 = 1e-12;

/// The angle of the receding axis of cavalier and cabinet projections when none
/// is given, in degrees (the usual drafting choice; the textbook leaves A free).
pub const DEFAULT_OBLIQUE_ANGLE: f64 = 45.0;

/// A camera as specified, in one of the two viewing models. Build one by hand, or
/// let [`Camera::from_json`] or the tools' flags build it; [`Camera::from_spec`]
/// checks it and makes the matrices.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraSpec {
    /// The IRIS GL / GLU camera of the thesis: `lookat` and one projection.
    Iris(IrisSpec),
    /// The textbook's view system (Harrington ch. 8).
    View(ViewSpec),
}

/// The IRIS GL / GLU camera: an optional `lookat` and exactly one projection.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IrisSpec {
    /// Where the eye is and what it looks at.
    ///
    /// Default value: `None`, the identity view (eye at the origin looking down
    /// −z, y up), as in GL.
    pub lookat: Option<LookAt>,
    /// The projection. Exactly one is required; a list, because a reader may be
    /// given none or several, which [`Camera::from_spec`] reports ("no
    /// projection", or "more than one projection" naming the second).
    ///
    /// Default value: empty (an error).
    pub projection: Vec<IrisProjection>,
}

/// gluLookAt with IRIS GL's twist: `view = R_z(−twist) · lookAt(eye, center, up)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookAt {
    /// The eye, in world coordinates (the centre of projection for perspective).
    ///
    /// Default value: none (required).
    pub eye: DVec3,
    /// The point looked at, in world coordinates; it must differ from `eye`.
    ///
    /// Default value: none (required).
    pub center: DVec3,
    /// The world direction shown vertical on the image; must not lie along the
    /// line of sight.
    ///
    /// Default value: `None`, +y.
    pub up: Option<DVec3>,
    /// IRIS twist in degrees: the world turns right-handedly by this about the
    /// line of sight eye→center (IRIS GL takes tenths of degrees; this takes
    /// degrees).
    ///
    /// Default value: `None`, 0.
    pub twist: Option<f64>,
}

/// The projections of the IRIS GL / GLU model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IrisProjection {
    /// gluPerspective.
    Perspective(Perspective),
    /// glOrtho.
    Ortho(Ortho),
    /// IRIS `ortho2` / gluOrtho2D: glOrtho with near −1, far 1.
    Ortho2(Ortho2),
}

/// The width / height ratio of a perspective window (gluPerspective's
/// `aspect`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aspect {
    /// This ratio; positive. A ratio other than the image's stretches the
    /// picture, as the thesis's demo 2 does (aspect 1 at 1024x768).
    Ratio(f64),
    /// The image's own width / height, taken when the camera meets an image
    /// ([`Camera::for_image`]): no stretch. `"auto"` in JSON and flags.
    Auto,
}

/// gluPerspective: a symmetric frustum around −z from the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perspective {
    /// Vertical field of view in degrees, in (0, 180) (IRIS GL: tenths of degrees).
    ///
    /// Default value: none (required).
    pub fovy: f64,
    /// Width / height of the window.
    ///
    /// Default value: none (required).
    pub aspect: Aspect,
    /// Distance of the near plane from the eye; 0 is allowed (depth is not
    /// squashed into [−1, 1], see the module docs), negative is not.
    ///
    /// Default value: none (required).
    pub near: f64,
    /// Distance of the far plane from the eye; beyond `near`.
    ///
    /// Default value: none (required).
    pub far: f64,
}

/// glOrtho: the eye-space box [left, right] × [bottom, top] × [near, far].
/// A reversed pair mirrors the image, as in GL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ortho {
    /// Eye x shown at the left image edge.
    ///
    /// Default value: none (required).
    pub left: f64,
    /// Eye x shown at the right image edge; must differ from `left`.
    ///
    /// Default value: none (required).
    pub right: f64,
    /// Eye y shown at the bottom image edge.
    ///
    /// Default value: none (required).
    pub bottom: f64,
    /// Eye y shown at the top image edge; must differ from `bottom`.
    ///
    /// Default value: none (required).
    pub top: f64,
    /// Nearest visible distance along the view direction (may be negative).
    ///
    /// Default value: none (required).
    pub near: f64,
    /// Farthest visible distance along the view direction; beyond `near`.
    ///
    /// Default value: none (required).
    pub far: f64,
}

/// IRIS `ortho2(left, right, bottom, top)` (gluOrtho2D): [`Ortho`] with near −1
/// and far 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ortho2 {
    /// Eye x shown at the left image edge.
    ///
    /// Default value: none (required).
    pub left: f64,
    /// Eye x shown at the right image edge; must differ from `left`.
    ///
    /// Default value: none (required).
    pub right: f64,
    /// Eye y shown at the bottom image edge.
    ///
    /// Default value: none (required).
    pub bottom: f64,
    /// Eye y shown at the top image edge; must differ from `bottom`.
    ///
    /// Default value: none (required).
    pub top: f64,
}

/// The textbook's view system (Harrington ch. 8, "Viewing parameters" to "The 3D
/// viewing transformation"). The defaults are those of INITIALIZE-8 (Alg. 8.41).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewSpec {
    /// View reference point, world coordinates (SET-VIEW-REFERENCE-POINT,
    /// Alg. 8.14). Depths are measured from it; for parallel views it is the eye
    /// origin.
    ///
    /// Default value: `None`, the origin.
    pub vrp: Option<DVec3>,
    /// View plane normal: the direction the camera looks (SET-VIEW-PLANE-NORMAL,
    /// Alg. 8.15); not zero. For [`ViewProjection::Isometric`] its three
    /// components must have equal magnitude.
    ///
    /// Default value: `None`, (0, 0, −1); (−1, −1, −1) for isometric, as in the
    /// book's example.
    pub vpn: Option<DVec3>,
    /// View-up, world coordinates, shown vertical on the image (SET-VIEW-UP,
    /// Alg. 8.16); neither zero nor along the VPN.
    ///
    /// Default value: `None`, +y.
    pub view_up: Option<DVec3>,
    /// Distance from the VRP to the view plane along the VPN (SET-VIEW-DISTANCE,
    /// Alg. 8.17, eq. 8.60).
    ///
    /// Default value: `None`, 0.
    pub view_distance: Option<f64>,
    /// The window on the view plane (SET-WINDOW); it fills the image. Required:
    /// `None` is reported as missing.
    ///
    /// Default value: `None` (an error).
    pub window: Option<Window>,
    /// The projection: exactly one is required. A list, because a reader may be
    /// given none or several, which [`Camera::from_spec`] reports ("no
    /// projection", or "more than one projection" naming the second).
    ///
    /// Default value: empty (an error).
    pub projection: Vec<ViewProjection>,
    /// Front clipping plane: distance from the VRP along the VPN (SET-VIEW-DEPTH,
    /// Alg. 8.23). The book's clipping is off by default; a renderer needs a
    /// bounded volume, so it is required: `None` is reported as missing.
    ///
    /// Default value: `None` (an error).
    pub front: Option<f64>,
    /// Back clipping plane: distance from the VRP along the VPN, beyond `front`.
    /// Required like `front`.
    ///
    /// Default value: `None` (an error).
    pub back: Option<f64>,
}

/// The window `[umin, umax, vmin, vmax]` in view plane coordinates, centred where
/// the VPN line through the VRP meets the view plane (Fig. 8-44). A reversed pair
/// mirrors the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// Left edge (u).
    ///
    /// Default value: none (required).
    pub umin: f64,
    /// Right edge (u); must differ from `umin`.
    ///
    /// Default value: none (required).
    pub umax: f64,
    /// Bottom edge (v).
    ///
    /// Default value: none (required).
    pub vmin: f64,
    /// Top edge (v); must differ from `vmin`.
    ///
    /// Default value: none (required).
    pub vmax: f64,
}

impl Window {
    /// `[umin, umax, vmin, vmax]`, the order of the JSON array and of `--window`.
    pub fn from_array([umin, umax, vmin, vmax]: [f64; 4]) -> Window {
        Window {
            umin,
            umax,
            vmin,
            vmax,
        }
    }
}

/// The projections of the textbook's view system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViewProjection {
    /// Perspective from this centre of projection, world coordinates
    /// (SET-PERSPECTIVE, Alg. 8.19); on the viewer's side of the view plane.
    Cop(DVec3),
    /// Parallel along this direction of projection, world coordinates
    /// (SET-PARALLEL, Alg. 8.18); oblique when not along the VPN, never parallel
    /// to the view plane.
    Dop(DVec3),
    /// The "Special projections" cavalier and cabinet: the DOP (cos A, sin A, 1)
    /// or (cos A, sin A, 2) in view plane coordinates.
    Oblique {
        /// Cavalier (receding axis full length) or cabinet (half length).
        ///
        /// Default value: none (required).
        kind: ObliqueKind,
        /// A, the angle of the receding axis on the image, in degrees.
        ///
        /// Default value: `None`, [`DEFAULT_OBLIQUE_ANGLE`] (45°).
        angle: Option<f64>,
    },
    /// Parallel along a VPN whose three components have equal magnitude.
    Isometric,
}

/// Which oblique projection (the textbook's "Special projections").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObliqueKind {
    /// SET-PARALLEL(cos A, sin A, 1): a unit behind the view plane shifts 1.
    Cavalier,
    /// SET-PARALLEL(cos A, sin A, 2): a unit behind the view plane shifts 1/2.
    Cabinet,
}

impl CameraSpec {
    /// The spec of a reader that may have been given parts of both models (as the
    /// tools' flags may): `None` when both parts are empty (their defaults),
    /// the one given otherwise, and an error naming the first IRIS field given
    /// (`lookat`, else the first projection) when both are given, as a JSON
    /// file with both would be reported.
    pub fn from_parts(iris: IrisSpec, view: ViewSpec) -> Result<Option<CameraSpec>, CameraError> {
        let iris_field = if iris.lookat.is_some() {
            Some("lookat")
        } else {
            iris.projection.first().map(IrisProjection::name)
        };
        let view_given = view != ViewSpec::default();
        match (iris_field, view_given) {
            (Some(field), true) => Err(models_combined(field)),
            (None, true) => Ok(Some(CameraSpec::View(view))),
            (Some(_), false) => Ok(Some(CameraSpec::Iris(iris))),
            (None, false) => Ok(None),
        }
    }
}

impl IrisProjection {
    /// The JSON key (and error field) of this projection.
    pub fn name(&self) -> &'static str {
        match self {
            IrisProjection::Perspective(_) => "perspective",
            IrisProjection::Ortho(_) => "ortho",
            IrisProjection::Ortho2(_) => "ortho2",
        }
    }
}

impl ViewProjection {
    /// The JSON key under `view` (and error field) of this projection.
    pub fn name(&self) -> &'static str {
        match self {
            ViewProjection::Cop(_) => "cop",
            ViewProjection::Dop(_) => "dop",
            ViewProjection::Oblique { .. } => "oblique",
            ViewProjection::Isometric => "isometric",
        }
    }
}

/// `[x, y, z]` for error messages.
fn show(v: DVec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Whether `a` and `b` coincide relative to their magnitude (at least 1).
fn coincide(a: f64, b: f64) -> bool {
    (a - b).abs() <= COINCIDENT_RELATIVE * a.abs().max(b.abs()).max(1.0)
}

/// Whether two non-zero directions are parallel (or antiparallel). Each is
/// first [`crate::vector::tame`]d: a vector whose squared length would
/// overflow or underflow is divided by its largest |component| (with
/// `[1e300, 1e300, 1e300]` the lengths were infinite and every up
/// "parallel"); ordinary vectors are compared as they are. If their cross
/// product's square still overflows or underflows, both are brought to a
/// largest component of 1, where it cannot overflow, and underflows only
/// for a sine far below [`PARALLEL_SINE`].
fn parallel(a: DVec3, b: DVec3) -> bool {
    let (a, b) = (crate::vector::tame(a), crate::vector::tame(b));
    let cross = a.cross(b);
    let (a, b) = if cross == DVec3::ZERO || crate::vector::plain_length_is_exact(cross) {
        (a, b)
    } else {
        (a / a.abs().max_element(), b / b.abs().max_element())
    };
    a.cross(b).length() <= PARALLEL_SINE * a.length() * b.length()
}

/// A specification that gives both models (any IRIS key, `iris_field` being the
/// first of `lookat`, `perspective`, `ortho`, `ortho2`, together with a `view`):
/// a [`CameraSpec`] cannot hold it, so the readers report it with this.
pub(super) fn models_combined(iris_field: &str) -> CameraError {
    CameraError::invalid(
        iris_field,
        "cannot be combined with \"view\": give either the IRIS/GLU camera \
         (lookat + perspective/ortho/ortho2) or the textbook view system",
    )
}

/// Exactly one IRIS projection among those `given` (named in the order
/// perspective, ortho, ortho2).
pub(super) fn one_iris_projection(given: &[&str]) -> Result<(), CameraError> {
    match given {
        [] => Err(CameraError::invalid(
            "camera",
            "no projection: give one of \"perspective\", \"ortho\", \"ortho2\" (or a \"view\")",
        )),
        [_] => Ok(()),
        [_, second, ..] => Err(CameraError::invalid(
            *second,
            format!(
                "more than one projection given ({}): give exactly one",
                given.join(", ")
            ),
        )),
    }
}

/// Exactly one textbook projection among those `given` (named in the order cop,
/// dop, oblique, isometric).
pub(super) fn one_view_projection(given: &[&str]) -> Result<(), CameraError> {
    match given {
        [] => Err(CameraError::invalid(
            "view",
            "no projection: give one of \"cop\" (perspective), \"dop\", \"oblique\" or \
             \"isometric\" (parallel)",
        )),
        [_] => Ok(()),
        [_, second, ..] => Err(CameraError::invalid(
            format!("view.{second}"),
            format!(
                "more than one projection given ({}): give exactly one",
                given.join(", ")
            ),
        )),
    }
}

impl LookAt {
    /// world → eye: gluLookAt, then the IRIS twist applied last in eye space
    /// (`rot(-twist, 'z')`, module docs). Rejects a line of sight without
    /// direction and an up that is zero or along the line of sight.
    pub(super) fn view(&self) -> Result<DMat4, CameraError> {
        let (eye, center) = (self.eye, self.center);
        let up = self.up.unwrap_or(DVec3::Y);
        let twist = self.twist.unwrap_or(0.0);
        let sight = center - eye;
        let scale = eye.length().max(center.length()).max(1.0);
        if !sight.length().is_finite() || !scale.is_finite() {
            return Err(CameraError::invalid(
                "lookat.center",
                format!(
                    "{} is too far from eye {}: the line of sight overflows a 64-bit float",
                    show(center),
                    show(eye)
                ),
            ));
        }
        if sight.length() <= COINCIDENT_RELATIVE * scale {
            return Err(CameraError::invalid(
                "lookat.center",
                format!(
                    "{} equals eye {}: the line of sight has no direction",
                    show(center),
                    show(eye)
                ),
            ));
        }
        if up.length() <= ROUNDOFF {
            return Err(CameraError::invalid(
                "lookat.up",
                format!("{} is the zero vector: no up direction", show(up)),
            ));
        }
        if parallel(sight, up) {
            // With the default up, the fix is to give one: blame the center.
            let given = self.up.is_some();
            return Err(CameraError::invalid(
                if given { "lookat.up" } else { "lookat.center" },
                format!(
                    "up {} is parallel to the line of sight eye→center {}: the image's up is undefined{}",
                    show(up),
                    show(sight),
                    if given { "" } else { " (give \"up\")" }
                ),
            ));
        }
        let look = view_matrix(eye_rotation(sight, up), eye);
        // glam's from_rotation_z, with the sine and cosine of degrees.
        let (sin, cos) = math::sin_cos_degrees(-twist);
        let roll = DMat4::from_cols(
            DVec4::new(cos, sin, 0.0, 0.0),
            DVec4::new(-sin, cos, 0.0, 0.0),
            DVec4::Z,
            DVec4::W,
        );
        Ok(roll * look)
    }
}

/// SET-VIEW-PLANE-NORMAL (Alg. 8.15): the VPN with its default, not zero
/// (INVALID VIEW PLANE NORMAL); for isometric, equal-magnitude components.
pub(super) fn checked_vpn(vpn: Option<DVec3>, isometric: bool) -> Result<DVec3, CameraError> {
    let default_vpn = if isometric {
        DVec3::splat(-1.0)
    } else {
        DVec3::NEG_Z
    };
    let vpn = vpn.unwrap_or(default_vpn);
    if vpn.length() <= ROUNDOFF {
        return Err(CameraError::invalid(
            "view.vpn",
            format!(
                "{} is the zero vector: the view plane needs a normal (INVALID VIEW PLANE NORMAL)",
                show(vpn)
            ),
        ));
    }
    if isometric && !parallel(vpn.abs(), DVec3::ONE) {
        return Err(CameraError::invalid(
            "view.vpn",
            format!(
                "{} is not an isometric direction: its three components must have equal magnitude, e.g. [-1, -1, -1]",
                show(vpn)
            ),
        ));
    }
    Ok(vpn)
}

/// SET-VIEW-UP (Alg. 8.16): view-up with its default, neither zero (NO
/// SET-VIEW-UP DIRECTION) nor along the checked `vpn`.
pub(super) fn checked_view_up(up: Option<DVec3>, vpn: DVec3) -> Result<DVec3, CameraError> {
    let up = up.unwrap_or(DVec3::Y);
    if up.length() <= ROUNDOFF {
        return Err(CameraError::invalid(
            "view.view_up",
            format!(
                "{} is the zero vector: no up direction (NO SET-VIEW-UP DIRECTION)",
                show(up)
            ),
        ));
    }
    if parallel(vpn, up) {
        return Err(CameraError::invalid(
            "view.view_up",
            format!(
                "{} is parallel to the view plane normal {}: the image's up is undefined \
                 (SET-VIEW-UP ALONG VIEW PLANE NORMAL)",
                show(up),
                show(vpn)
            ),
        ));
    }
    Ok(up)
}

/// The window: given, with non-zero width and height.
pub(super) fn checked_window(window: Option<Window>) -> Result<Window, CameraError> {
    let Some(w) = window else {
        return Err(CameraError::invalid(
            "view.window",
            "missing (an array of 4 numbers is required)",
        ));
    };
    let Window {
        umin,
        umax,
        vmin,
        vmax,
    } = w;
    if coincide(umin, umax) {
        return Err(CameraError::invalid(
            "view.window",
            format!("zero width: umin {umin} equals umax {umax}"),
        ));
    }
    if coincide(vmin, vmax) {
        return Err(CameraError::invalid(
            "view.window",
            format!("zero height: vmin {vmin} equals vmax {vmax}"),
        ));
    }
    checked_span("view.window", umin, umax, "umin")?;
    checked_span("view.window", vmin, vmax, "vmin")?;
    Ok(w)
}

/// SET-VIEW-DEPTH (Alg. 8.23), first half: the front plane is required.
pub(super) fn checked_front(front: Option<f64>) -> Result<f64, CameraError> {
    front.ok_or_else(|| CameraError::invalid("view.front", "missing (a number is required)"))
}

/// SET-VIEW-DEPTH (Alg. 8.23), second half: the back plane is required and lies
/// beyond the front one (FRONT PLANE BEHIND BACK PLANE; equal is an empty volume).
pub(super) fn checked_back(front: f64, back: Option<f64>) -> Result<f64, CameraError> {
    let back =
        back.ok_or_else(|| CameraError::invalid("view.back", "missing (a number is required)"))?;
    if front > back {
        return Err(CameraError::invalid(
            "view.front",
            format!("{front} is beyond back {back} (FRONT PLANE BEHIND BACK PLANE)"),
        ));
    }
    if front == back {
        return Err(CameraError::invalid(
            "view.back",
            format!("{back} equals front: the view volume is empty"),
        ));
    }
    checked_span("view.back", front, back, "front")?;
    Ok(back)
}

/// A non-empty extent `lo..hi` (reversed is allowed: it mirrors, as in GL)
/// whose size is a finite f64 ([`checked_span`]).
fn checked_extent(field: &str, lo: f64, hi: f64, lo_key: &str) -> Result<(), CameraError> {
    if coincide(lo, hi) {
        return Err(CameraError::invalid(
            field,
            format!("{hi} equals {lo_key} {lo}: zero-size"),
        ));
    }
    checked_span(field, lo, hi, lo_key)
}

/// An extent `lo..hi` whose size `hi - lo` is a finite f64. Past f64's
/// largest (`--ortho2 -9e307,9e307,...`) the scale `2/(hi - lo)` of the
/// window's map was 0, every matrix entry still finite: the frame came out
/// blank, with a warning that each polygon was edge-on (a hostile-input
/// review).
fn checked_span(field: &str, lo: f64, hi: f64, lo_key: &str) -> Result<(), CameraError> {
    if !(hi - lo).is_finite() {
        return Err(CameraError::invalid(
            field,
            format!("{hi} is too far from {lo_key} {lo}: the size overflows a 64-bit float"),
        ));
    }
    Ok(())
}

impl CameraSpec {
    /// The first non-finite number, named by its field. The readers cannot
    /// produce one (JSON has no NaN, the flags refuse them), but a spec built in
    /// code can, and a NaN must not slip past the comparisons below.
    fn check_finite(&self) -> Result<(), CameraError> {
        let mut numbers: Vec<(String, f64)> = Vec::new();
        let mut add = |field: &str, xs: &[f64]| {
            numbers.extend(xs.iter().map(|&x| (field.to_string(), x)));
        };
        match self {
            CameraSpec::Iris(s) => {
                if let Some(l) = &s.lookat {
                    add("lookat.eye", &l.eye.to_array());
                    add("lookat.center", &l.center.to_array());
                    if let Some(up) = l.up {
                        add("lookat.up", &up.to_array());
                    }
                    if let Some(t) = l.twist {
                        add("lookat.twist", &[t]);
                    }
                }
                for p in &s.projection {
                    match *p {
                        IrisProjection::Perspective(p) => {
                            add("perspective.fovy", &[p.fovy]);
                            if let Aspect::Ratio(r) = p.aspect {
                                add("perspective.aspect", &[r]);
                            }
                            add("perspective.near", &[p.near]);
                            add("perspective.far", &[p.far]);
                        }
                        IrisProjection::Ortho(o) => {
                            add("ortho.left", &[o.left]);
                            add("ortho.right", &[o.right]);
                            add("ortho.bottom", &[o.bottom]);
                            add("ortho.top", &[o.top]);
                            add("ortho.near", &[o.near]);
                            add("ortho.far", &[o.far]);
                        }
                        IrisProjection::Ortho2(o) => {
                            add("ortho2", &[o.left, o.right, o.bottom, o.top]);
                        }
                    }
                }
            }
            CameraSpec::View(v) => {
                for (field, vector) in [
                    ("view.vrp", v.vrp),
                    ("view.vpn", v.vpn),
                    ("view.view_up", v.view_up),
                ] {
                    if let Some(vector) = vector {
                        add(field, &vector.to_array());
                    }
                }
                if let Some(d) = v.view_distance {
                    add("view.view_distance", &[d]);
                }
                if let Some(w) = v.window {
                    add("view.window", &[w.umin, w.umax, w.vmin, w.vmax]);
                }
                for p in &v.projection {
                    match *p {
                        ViewProjection::Cop(c) => add("view.cop", &c.to_array()),
                        ViewProjection::Dop(d) => add("view.dop", &d.to_array()),
                        ViewProjection::Oblique { angle: Some(a), .. } => {
                            add("view.oblique.angle", &[a])
                        }
                        ViewProjection::Oblique { angle: None, .. } | ViewProjection::Isometric => {
                        }
                    }
                }
                if let Some(front) = v.front {
                    add("view.front", &[front]);
                }
                if let Some(back) = v.back {
                    add("view.back", &[back]);
                }
            }
        }
        match numbers.into_iter().find(|(_, x)| !x.is_finite()) {
            Some((field, x)) => Err(CameraError::invalid(
                field,
                format!("{x} is not a finite number"),
            )),
            None => Ok(()),
        }
    }
}

impl Camera {
    /// Checks a specification and builds its camera: every degenerate view is an
    /// error naming the field (as a JSON path; [`CameraError::with_origin`] adds
    /// where the spec came from). The matrices are exact functions of the spec:
    /// the same spec gives the same bits however it was written.
    pub fn from_spec(spec: &CameraSpec) -> Result<Camera, CameraError> {
        spec.check_finite()?;
        let camera = match spec {
            CameraSpec::Iris(s) => iris(s)?,
            CameraSpec::View(v) => textbook(v)?,
        };
        camera.checked()
    }

    /// The last line of defence: every entry finite, near < far.
    fn checked(self) -> Result<Camera, CameraError> {
        let finite = self.view.to_cols_array().iter().all(|x| x.is_finite())
            && self
                .projection
                .to_cols_array()
                .iter()
                .all(|x| x.is_finite())
            && self
                .world_to_clip()
                .to_cols_array()
                .iter()
                .all(|x| x.is_finite());
        if !finite {
            return Err(CameraError::invalid(
                "camera",
                "the specification overflows f64 (a matrix entry is not finite): \
                 check for extreme or nearly degenerate values",
            ));
        }
        if !self.near.is_finite() || !self.far.is_finite() || self.near >= self.far {
            return Err(CameraError::invalid(
                "camera",
                format!(
                    "empty view volume: near {} is not below far {}",
                    self.near, self.far
                ),
            ));
        }
        Ok(self)
    }
}

/// The IRIS GL / GLU model: optional `lookat`, exactly one projection.
fn iris(s: &IrisSpec) -> Result<Camera, CameraError> {
    let view = match &s.lookat {
        Some(l) => l.view()?,
        None => DMat4::IDENTITY,
    };
    let given: Vec<&str> = s.projection.iter().map(IrisProjection::name).collect();
    one_iris_projection(&given)?;
    match s.projection[0] {
        IrisProjection::Perspective(Perspective {
            fovy,
            aspect,
            near,
            far,
        }) => {
            if !(fovy > 0.0 && fovy < 180.0) {
                return Err(CameraError::invalid(
                    "perspective.fovy",
                    format!("{fovy} is outside (0, 180) degrees"),
                ));
            }
            // Auto: built for a square window, made the image's by
            // `Camera::for_image`.
            let ratio = match aspect {
                Aspect::Ratio(r) if r <= 0.0 => {
                    return Err(CameraError::invalid(
                        "perspective.aspect",
                        format!("{r} is not positive (width/height)"),
                    ))
                }
                Aspect::Ratio(r) => r,
                Aspect::Auto => 1.0,
            };
            if near < 0.0 {
                return Err(CameraError::invalid(
                    "perspective.near",
                    format!("{near} is negative: a perspective view cannot see behind the eye"),
                ));
            }
            if far <= near {
                return Err(CameraError::invalid(
                    "perspective.far",
                    format!("{far} is not beyond near {near}"),
                ));
            }
            // gluPerspective: f = cot(fovy/2).
            let f = 1.0 / math::tan_degrees(fovy / 2.0);
            let projection = from_rows([
                [f / ratio, 0.0, 0.0, 0.0],
                [0.0, f, 0.0, 0.0],
                DEPTH_ROW,
                PERSPECTIVE_W_ROW,
            ]);
            Ok(Camera {
                view,
                projection,
                near,
                far,
                perspective: true,
                aspect_from_image: aspect == Aspect::Auto,
            })
        }
        IrisProjection::Ortho(Ortho {
            left: l,
            right: r,
            bottom: b,
            top: t,
            near,
            far,
        }) => {
            checked_extent("ortho.right", l, r, "left")?;
            checked_extent("ortho.top", b, t, "bottom")?;
            if far <= near {
                return Err(CameraError::invalid(
                    "ortho.far",
                    format!("{far} is not beyond near {near}"),
                ));
            }
            checked_span("ortho.far", near, far, "near")?;
            Ok(Camera {
                view,
                projection: ortho_matrix(l, r, b, t),
                near,
                far,
                perspective: false,
                aspect_from_image: false,
            })
        }
        IrisProjection::Ortho2(Ortho2 {
            left: l,
            right: r,
            bottom: b,
            top: t,
        }) => {
            if coincide(l, r) {
                return Err(CameraError::invalid(
                    "ortho2",
                    format!("left {l} equals right {r}: zero-width"),
                ));
            }
            if coincide(b, t) {
                return Err(CameraError::invalid(
                    "ortho2",
                    format!("bottom {b} equals top {t}: zero-height"),
                ));
            }
            checked_span("ortho2", l, r, "left")?;
            checked_span("ortho2", b, t, "bottom")?;
            Ok(Camera {
                view,
                projection: ortho_matrix(l, r, b, t),
                near: -1.0,
                far: 1.0,
                perspective: false,
                aspect_from_image: false,
            })
        }
    }
}

/// The textbook's view system (Harrington ch. 8; conventions in the module docs).
fn textbook(v: &ViewSpec) -> Result<Camera, CameraError> {
    let given: Vec<&str> = v.projection.iter().map(ViewProjection::name).collect();
    one_view_projection(&given)?;
    let projection = v.projection[0];
    let isometric = projection == ViewProjection::Isometric;

    // SET-VIEW-REFERENCE-POINT, SET-VIEW-PLANE-NORMAL, SET-VIEW-UP, SET-VIEW-DISTANCE
    // (Alg. 8.14–8.17) with the defaults of INITIALIZE-8 (Alg. 8.41).
    let vrp = v.vrp.unwrap_or(DVec3::ZERO);
    let vpn = checked_vpn(v.vpn, isometric)?;
    let up = checked_view_up(v.view_up, vpn)?;
    let distance = v.view_distance.unwrap_or(0.0);

    let Window {
        umin,
        umax,
        vmin,
        vmax,
    } = checked_window(v.window)?;
    let (wu, wv) = (umax - umin, vmax - vmin);

    // SET-VIEW-DEPTH (Alg. 8.23): distances from the VRP along the VPN.
    let front = checked_front(v.front)?;
    let back = checked_back(front, v.back)?;

    // MAKE-VIEW-PLANE-TRANSFORMATION (Alg. 8.20): the view plane coordinate axes.
    let r = eye_rotation(vpn, up);
    let n = crate::vector::normalized(vpn).expect("a checked VPN is non-zero and finite");
    let plane_centre = vrp + distance * n;

    let p = match projection {
        ViewProjection::Cop(cop) => {
            // MAKE-PERSPECTIVE-TRANSFORMATION (Alg. 8.21): the COP in view plane
            // coordinates must have ZC > 0.
            let c = r * (cop - plane_centre);
            // vector::length: a COP 1e200 away squared its distance to
            // infinity, and every point was then "on" the view plane.
            let tolerance =
                COINCIDENT_RELATIVE * crate::vector::length(cop - plane_centre).max(1.0);
            if c.z <= tolerance {
                let (where_, book) = if c.z < -tolerance {
                    ("behind", " (CENTER OF PROJECTION BEHIND VIEW PLANE)")
                } else {
                    ("on", "")
                };
                return Err(CameraError::invalid(
                    "view.cop",
                    format!(
                        "{} is {where_} the view plane{book}: the centre of projection must lie on the \
                         viewer's side, before the view plane along the VPN (its distance to the plane is {})",
                        show(cop),
                        -c.z
                    ),
                ));
            }
            // Eye coordinates: the view plane axes moved to the COP. The front and
            // back distances become distances from the COP.
            let cop_depth = (cop - vrp).dot(n);
            let (near, far) = (front - cop_depth, back - cop_depth);
            if near < 0.0 {
                return Err(CameraError::invalid(
                    "view.front",
                    format!(
                        "{front} puts the front plane {} behind the centre of projection (which lies {cop_depth} \
                         from the VRP along the VPN): a perspective view cannot see behind its eye",
                        -near
                    ),
                ));
            }
            // Eq. 8.45 on the window, as x_clip/w = (2u − (umax+umin))/(umax−umin).
            let projection = from_rows([
                [2.0 * c.z / wu, 0.0, (umax + umin - 2.0 * c.x) / wu, 0.0],
                [0.0, 2.0 * c.z / wv, (vmax + vmin - 2.0 * c.y) / wv, 0.0],
                DEPTH_ROW,
                PERSPECTIVE_W_ROW,
            ]);
            return Ok(Camera {
                view: view_matrix(r, cop),
                projection,
                near,
                far,
                perspective: true,
                aspect_from_image: false,
            });
        }
        // The direction of projection in view plane coordinates (Alg. 8.22).
        ViewProjection::Dop(dop) => {
            if dop.length() <= ROUNDOFF {
                return Err(CameraError::invalid(
                    "view.dop",
                    format!(
                        "{} is the zero vector (NO DIRECTION OF PROJECTION)",
                        show(dop)
                    ),
                ));
            }
            let p = r * dop;
            // vector::length: p.length() of a DOP of 1e300 was infinite, and
            // every such DOP "parallel to the view plane".
            if p.z.abs() <= PARALLEL_SINE * crate::vector::length(p) {
                return Err(CameraError::invalid(
                    "view.dop",
                    format!(
                        "{} is parallel to the view plane (PROJECTION PARALLEL VIEW PLANE): \
                         the projection lines never meet it",
                        show(dop)
                    ),
                ));
            }
            p
        }
        ViewProjection::Oblique { kind, angle } => {
            // "Special projections": SET-PARALLEL(cos A, sin A, 1) is cavalier,
            // (cos A, sin A, 2) cabinet.
            let receding = match kind {
                ObliqueKind::Cavalier => 1.0,
                ObliqueKind::Cabinet => 2.0,
            };
            let (sin, cos) = math::sin_cos_degrees(angle.unwrap_or(DEFAULT_OBLIQUE_ANGLE));
            DVec3::new(cos, sin, receding)
        }
        // Isometric: projection along the view plane normal.
        ViewProjection::Isometric => DVec3::Z,
    };
    // Eq. 8.37 on the view plane (z_eye = −distance), eye origin at the VRP:
    // u = x − z·sx − distance·sx.
    let (sx, sy) = (p.x / p.z, p.y / p.z);
    let projection = from_rows([
        [
            2.0 / wu,
            0.0,
            -2.0 * sx / wu,
            (-2.0 * distance * sx - (umax + umin)) / wu,
        ],
        [
            0.0,
            2.0 / wv,
            -2.0 * sy / wv,
            (-2.0 * distance * sy - (vmax + vmin)) / wv,
        ],
        DEPTH_ROW,
        PARALLEL_W_ROW,
    ]);
    Ok(Camera {
        view: view_matrix(r, vrp),
        projection,
        near: front,
        far: back,
        perspective: false,
        aspect_from_image: false,
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::*;
    use glam::DMat3;
    use proptest::prelude::*;
    use serde_json::json;

    #[test]
    fn perspective_edges_of_the_field_of_view() {
        let c = cam(json!({"perspective": {"fovy": 90, "aspect": 2.0, "near": 0.5, "far": 10}}));
        // fovy 90: at distance 3 the top edge is at y = 3, the right edge at x = 6.
        let p = ndc(&c, DVec3::new(6.0, 3.0, -3.0));
        assert!(
            (p.x - 1.0).abs() < CLOSE && (p.y - 1.0).abs() < CLOSE,
            "{p}"
        );
        assert_eq!(c.view, DMat4::IDENTITY);
    }

    #[test]
    fn ortho_box() {
        let c = cam(
            json!({"ortho": {"left": -2, "right": 2, "bottom": -1, "top": 3,
                                      "near": -5, "far": 5}}),
        );
        let p = ndc(&c, DVec3::new(2.0, 3.0, 4.0));
        assert!((p - DVec3::new(1.0, 1.0, -4.0)).length() < CLOSE, "{p}");
    }

    #[test]
    fn extents_whose_size_overflows_are_refused() {
        // 9e307 - (-9e307) is past f64's largest: the window's scale
        // 2/(r - l) was 0, every entry finite, and the frame came out blank.
        let view = |window: [f64; 4], front: f64, back: f64| {
            json!({"view": {"vrp": [0, 0, 0], "vpn": [0, 0, 1], "view_up": [0, 1, 0],
                            "window": window, "dop": [0, 0, 1], "front": front, "back": back}})
        };
        let said = "the size overflows a 64-bit float";
        for (spec, field, values) in [
            (
                json!({"ortho2": [-9e307, 9e307, -1, 1]}),
                "ortho2",
                "9e307 is too far from left -9e307",
            ),
            (
                json!({"ortho2": [-1, 1, 9e307, -9e307]}),
                "ortho2",
                "-9e307 is too far from bottom 9e307",
            ),
            (
                json!({"ortho": {"left": -1.7e308, "right": 1.7e308, "bottom": -1, "top": 1,
                                 "near": -1, "far": 1}}),
                "ortho.right",
                "1.7e308 is too far from left -1.7e308",
            ),
            (
                json!({"ortho": {"left": -1, "right": 1, "bottom": -1, "top": 1,
                                 "near": -1e308, "far": 1e308}}),
                "ortho.far",
                "1e308 is too far from near -1e308",
            ),
            (
                view([-1e308, 1e308, -1.0, 1.0], 0.0, 1.0),
                "view.window",
                "1e308 is too far from umin -1e308",
            ),
            (
                view([-1.0, 1.0, -1e308, 1e308], 0.0, 1.0),
                "view.window",
                "1e308 is too far from vmin -1e308",
            ),
            (
                view([-1.0, 1.0, -1.0, 1.0], -1e308, 1e308),
                "view.back",
                "1e308 is too far from front -1e308",
            ),
        ] {
            // As the tools print it (`cli::print_error`).
            let e = crate::text::shorten_long_numbers(&err(spec.clone())).into_owned();
            assert!(
                e.contains(&format!("{field}: {values}: {said}")),
                "{spec}: {e}"
            );
        }
        // Just inside f64's range the same windows are cameras.
        cam(json!({"ortho2": [-8e307, 8e307, -1, 1]}));
        cam(view([-8e307, 8e307, -1.0, 1.0], -8e307, 8e307));
    }

    #[test]
    fn twist_turns_the_camera_right_handed() {
        // Twist 90°: the world turns right-handedly about the line of sight (−z eye),
        // i.e. clockwise on the image, so the world's +x appears pointing down.
        let c = cam(
            json!({"lookat": {"eye": [0, 0, 0], "center": [0, 0, -1], "twist": 90},
                           "ortho2": [-1, 1, -1, 1]}),
        );
        let p = ndc(&c, DVec3::new(0.5, 0.0, 0.0));
        assert!((p - DVec3::new(0.0, -0.5, 0.0)).length() < CLOSE, "{p}");
    }

    #[test]
    fn lookat_with_up() {
        // Looking down from above with +x as up: world -z is to the right... check
        // with the frame: right = forward × up = (0,-1,0) × (1,0,0) = (0,0,1).
        let c = cam(
            json!({"lookat": {"eye": [0, 10, 0], "center": [0, 0, 0], "up": [1, 0, 0]},
                           "ortho2": [-1, 1, -1, 1]}),
        );
        let right = ndc(&c, DVec3::new(0.0, 0.0, 0.5));
        let up = ndc(&c, DVec3::new(0.5, 0.0, 0.0));
        assert!((right.truncate() - glam::DVec2::new(0.5, 0.0)).length() < CLOSE);
        assert!((up.truncate() - glam::DVec2::new(0.0, 0.5)).length() < CLOSE);
    }

    #[test]
    fn textbook_perspective_equals_lookat_perspective() {
        let (eye, center, up) = ([1.0, 2.0, 3.0], [4.0, -1.0, -5.0], [0.2, 1.0, 0.1]);
        let iris = cam(json!({"lookat": {"eye": eye, "center": center, "up": up},
                              "perspective": {"fovy": 50, "aspect": 1.5, "near": 0.5, "far": 40}}));
        let t = math::tan(25f64.to_radians());
        let e = DVec3::from_array(eye);
        let c = DVec3::from_array(center);
        let sight = c - e;
        // VRP at the eye, view plane 1 ahead, COP at the eye.
        let a = cam(
            json!({"view": {"vrp": eye, "vpn": sight.to_array(), "view_up": up,
            "view_distance": 1, "window": [-1.5 * t, 1.5 * t, -t, t], "cop": eye,
            "front": 0.5, "back": 40}}),
        );
        // VRP at the center, view plane 2 ahead of the eye (window twice as large):
        // the front and back distances are then measured from the center.
        let l = sight.length();
        let b = cam(
            json!({"view": {"vrp": center, "vpn": (sight * 3.0).to_array(),
            "view_up": up, "view_distance": 2.0 - l, "window": [-3.0 * t, 3.0 * t, -2.0 * t, 2.0 * t],
            "cop": eye, "front": 0.5 - l, "back": 40.0 - l}}),
        );
        for tb in [&a, &b] {
            let d = max_diff(iris.world_to_clip(), tb.world_to_clip());
            assert!(d <= SAME_VIEW, "differs by {d}");
            assert!(tb.perspective);
            assert!((tb.near - 0.5).abs() <= SAME_VIEW && (tb.far - 40.0).abs() <= SAME_VIEW);
        }
    }

    #[test]
    fn very_long_and_short_view_plane_normals_and_ups() {
        // A VPN of [1e300, 1e300, 1e300] was "parallel to view_up" (its
        // length overflowed to infinity); a view-up of 1e300 made NaN.
        let view = |vpn: [f64; 3], up: [f64; 3]| {
            cam(json!({"view": {"vrp": [2, 2, 2], "vpn": vpn, "view_up": up,
                "window": [-1, 1, -1, 1], "dop": vpn, "front": 0, "back": 9}}))
        };
        let reference = view([1.0, 1.0, 1.0], [0.0, 1.0, 0.0]);
        for (vpn, up) in [
            ([1e300, 1e300, 1e300], [0.0, 1.0, 0.0]),
            ([1e200, 1e200, 1e200], [0.0, 1e300, 0.0]),
            ([1e-10, 1e-10, 1e-10], [0.0, 1e300, 0.0]),
        ] {
            let c = view(vpn, up);
            let d = max_diff(reference.world_to_clip(), c.world_to_clip());
            assert!(d <= SAME_VIEW, "{vpn:?} {up:?}: differs by {d}");
        }
        // Isometric directions: a huge one still has equal components.
        assert!(checked_vpn(Some(DVec3::splat(-1e300)), true).is_ok());
        assert!(checked_vpn(Some(DVec3::new(-1e300, -2e300, -1e300)), true).is_err());
        // Tiny vectors are zero by ROUNDOFF, as before: named so.
        let e = checked_vpn(Some(DVec3::splat(1e-200)), false).unwrap_err();
        assert!(e.to_string().contains("zero vector"), "{e}");
        // parallel() itself, with huge, tiny and mixed magnitudes.
        for (a, b, want) in [
            (DVec3::splat(1e300), DVec3::Y, false),
            (DVec3::splat(1e300), DVec3::splat(1e-200), true),
            (
                DVec3::new(1e-200, 0.0, 0.0),
                DVec3::new(0.0, 1e-200, 0.0),
                false,
            ),
            (
                DVec3::new(1e-100, 0.0, 0.0),
                DVec3::new(0.0, 1e-100, 0.0),
                false,
            ),
            (
                DVec3::new(1e150, 0.0, 0.0),
                DVec3::new(0.0, 1e150, 0.0),
                false,
            ),
            (
                DVec3::new(1e150, 0.0, 0.0),
                DVec3::new(-1e150, 0.0, 0.0),
                true,
            ),
            (DVec3::new(1e300, 1.0, 0.0), DVec3::X, true),
        ] {
            assert_eq!(parallel(a, b), want, "{a} {b}");
        }
    }

    #[test]
    fn textbook_parallel_equals_lookat_ortho() {
        let (eye, center, up) = ([5.0, 4.0, 3.0], [0.0, 1.0, -2.0], [0.0, 1.0, 0.0]);
        let iris = cam(json!({"lookat": {"eye": eye, "center": center, "up": up},
            "ortho": {"left": -3, "right": 2, "bottom": -1, "top": 4, "near": -2, "far": 30}}));
        let sight = DVec3::from_array(center) - DVec3::from_array(eye);
        // The DOP's sign and length do not matter; the view distance does not change
        // an orthographic image.
        let tb = cam(
            json!({"view": {"vrp": eye, "vpn": sight.to_array(), "view_up": up,
            "view_distance": 3.5, "window": [-3, 2, -1, 4], "dop": (sight * -2.0).to_array(),
            "front": -2, "back": 30}}),
        );
        let d = max_diff(iris.world_to_clip(), tb.world_to_clip());
        assert!(d <= SAME_VIEW, "differs by {d}");
        assert_eq!((tb.near, tb.far, tb.perspective), (-2.0, 30.0, false));
        // Isometric is the same along a diagonal.
        let iris = cam(json!({"lookat": {"eye": [2, 2, 2], "center": [0, 0, 0]},
            "ortho": {"left": -1, "right": 1, "bottom": -1, "top": 1, "near": 0, "far": 9}}));
        let iso = cam(json!({"view": {"vrp": [2, 2, 2], "isometric": true,
            "window": [-1, 1, -1, 1], "front": 0, "back": 9}}));
        let d = max_diff(iris.world_to_clip(), iso.world_to_clip());
        assert!(d <= SAME_VIEW, "differs by {d}");
    }

    #[test]
    fn demo2_both_ways() {
        let iris = cam(demo2());
        let t = math::tan(27.5f64.to_radians());
        let tb = cam(json!({"view": {"vrp": [0, 100, -5], "vpn": [0, -100, -895],
            "view_up": [0, 1, 0], "view_distance": 1, "window": [-t, t, -t, t],
            "cop": [0, 100, -5], "front": 0, "back": 1000}}));
        let d = max_diff(iris.world_to_clip(), tb.world_to_clip());
        assert!(d <= SAME_VIEW, "differs by {d}");
        assert_eq!((tb.near, tb.far), (0.0, 1000.0));
        let p = ndc(&tb, DVec3::new(0.0, 0.0, -900.0));
        assert!(p.x.abs() < CLOSE && p.y.abs() < CLOSE, "{p}");
    }

    #[test]
    fn cavalier_and_cabinet_foreshortening() {
        for (kind, length) in [("cavalier", 1.0), ("cabinet", 0.5)] {
            let c = cam(view(json!({"oblique": {"kind": kind, "angle": 30}})));
            // One unit behind the view plane (along the VPN, -z): shifted up-right at 30°.
            let p = ndc(&c, DVec3::new(0.0, 0.0, -1.0));
            let a = 30f64.to_radians();
            let want = glam::DVec2::new(math::cos(a), math::sin(a)) * length;
            assert!((p.truncate() - want).length() < CLOSE, "{kind}: {p}");
            // Depth still measures along the VPN; the front face is not distorted.
            assert!((p.z - 1.0).abs() < CLOSE);
            let q = ndc(&c, DVec3::new(0.25, -0.5, 0.0));
            assert!((q.truncate() - glam::DVec2::new(0.25, -0.5)).length() < CLOSE);
            // The textbook's SET-PARALLEL(cos A, sin A, 1 or 2) is the same camera.
            let dop = [math::cos(a), math::sin(a), 1.0 / length];
            let d = cam(view(json!({ "dop": dop })));
            assert!(max_diff(c.world_to_clip(), d.world_to_clip()) <= SAME_VIEW);
            // The camera looks along the (oblique) projection direction.
            let v = c.view_direction();
            assert!(
                (v - -DVec3::from_array(dop).normalize()).length() < CLOSE,
                "{v}"
            );
            // A face towards the viewer (+z, the VPN is -z) meets the rays head on.
            assert!(DVec3::Z.dot(v) < 0.0);
        }
        let c = cam(view(json!({"oblique": {"kind": "cavalier"}})));
        let p = ndc(&c, DVec3::new(0.0, 0.0, -1.0));
        assert!((p.x - p.y).abs() < CLOSE && (p.truncate().length() - 1.0).abs() < CLOSE);
    }

    #[test]
    fn isometric_shortens_all_axes_equally() {
        let c = cam(json!({"view": {"isometric": true, "window": [-2, 2, -2, 2],
                                    "front": -5, "back": 5}}));
        let lengths = [DVec3::X, DVec3::Y, DVec3::Z]
            .map(|axis| (ndc(&c, axis) - ndc(&c, DVec3::ZERO)).truncate().length());
        assert!((lengths[0] - lengths[1]).abs() < CLOSE && (lengths[1] - lengths[2]).abs() < CLOSE);
        // View-up +y stays vertical on the image.
        let y = ndc(&c, DVec3::Y);
        assert!(y.x.abs() < CLOSE && y.y > 0.0);
    }

    #[test]
    fn flight_simulator() {
        // The textbook's application: VRP on the windshield, view distance 0, the
        // pilot 0.5 behind it, front clipping at the windshield.
        let pos = DVec3::new(10.0, 50.0, -20.0);
        let dir = DVec3::new(1.0, 0.0, -1.0).normalize();
        let c = cam(
            json!({"view": {"vrp": pos.to_array(), "vpn": dir.to_array(),
            "view_distance": 0, "window": [-0.5, 0.5, -0.5, 0.5],
            "cop": (pos - 0.5 * dir).to_array(), "front": 0, "back": 1000}}),
        );
        assert!((c.near - 0.5).abs() < CLOSE && (c.far - 1000.5).abs() < CLOSE);
        assert!((c.eye_position().unwrap() - (pos - 0.5 * dir)).length() < CLOSE);
        let ahead = ndc(&c, pos + 100.0 * dir);
        assert!(ahead.x.abs() < CLOSE && ahead.y.abs() < CLOSE);
        // A point on the windshield projects to its own window position: its corner.
        let right = dir.cross(DVec3::Y).normalize();
        let corner = ndc(&c, pos + 0.5 * right + 0.5 * DVec3::Y);
        assert!(
            (corner.truncate() - glam::DVec2::ONE).length() < CLOSE,
            "{corner}"
        );
    }

    #[test]
    fn view_plane_points_project_to_themselves() {
        // Whatever the COP or DOP, a point on the view plane lands at its own (u, v).
        let base = json!({"vrp": [1, 2, 3], "vpn": [0, 0, -1], "view_distance": 2,
                          "window": [-1, 3, -2, 2], "front": -2, "back": 50});
        let point = DVec3::new(1.0 + 0.5, 2.0 - 1.0, 3.0 - 2.0); // u = 0.5, v = -1
        let want = glam::DVec2::new((2.0 * 0.5 - 2.0) / 4.0, -0.5);
        for proj in [
            json!({"cop": [1.7, 2.3, 5]}),
            json!({"dop": [0.3, -0.2, 1]}),
            json!({"oblique": {"kind": "cabinet", "angle": 60}}),
        ] {
            let mut v = base.clone();
            for (k, x) in proj.as_object().unwrap() {
                v[k] = x.clone();
            }
            let c = cam(json!({ "view": v }));
            let p = ndc(&c, point);
            assert!((p.truncate() - want).length() < CLOSE, "{proj}: {p}");
        }
    }

    fn coord() -> impl Strategy<Value = f64> {
        -100.0..100.0f64
    }

    fn point() -> impl Strategy<Value = DVec3> {
        (coord(), coord(), coord()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #[test]
        fn lookat_is_orthonormal_and_sees_ahead(
            eye in point(), center in point(), up in point(), twist in -360.0..360.0f64,
            probe in point(),
        ) {
            let v = json!({"lookat": {"eye": eye.to_array(), "center": center.to_array(),
                                      "up": up.to_array(), "twist": twist},
                           "perspective": {"fovy": 60, "aspect": 1.5, "near": 0, "far": 100}});
            let Ok(c) = Camera::from_json(&v, "prop") else { return Ok(()) };
            let r = DMat3::from_mat4(c.view);
            let rrt = r * r.transpose();
            prop_assert!((rrt - DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-12));
            prop_assert!((r.determinant() - 1.0).abs() < 1e-12);
            prop_assert!(c.view.row(3) == DVec4::new(0.0, 0.0, 0.0, 1.0));
            prop_assert!((c.view.transform_point3(eye)).length() < 1e-9);
            let forward = (center - eye).normalize();
            let depth = (probe - eye).dot(forward);
            let clip = c.world_to_clip() * probe.extend(1.0);
            prop_assert!((clip.z - depth).abs() < 1e-9);
            if depth > 1e-6 {
                prop_assert!(clip.w > 0.0);
            }
        }
    }
}
