//! The camera (SPEC §3): world → eye → clip matrices from either of the seeds'
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
//! * World: right-handed, y up (SPEC §3).
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
//! * The chapter itself "adopt[s] the right-handed system". Its view plane
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

use std::io::Read;

use anyhow::{anyhow, Context, Result};
use glam::{DMat3, DMat4, DVec3};
use serde_json::{Map, Value};

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
    pub far: f64,
    pub perspective: bool,
}

/// Where an error is reported: the source (file name or "command line") and
/// whether field names should be shown with their flag spelling.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    source: &'a str,
    flags: bool,
}

impl Ctx<'_> {
    /// An error naming the source and the field.
    fn err(&self, field: &str, msg: impl std::fmt::Display) -> anyhow::Error {
        match (self.flags, flag_of(field)) {
            (true, Some(flag)) => anyhow!("{}: {flag}: {msg}", self.source),
            _ => anyhow!("{}: {field}: {msg}", self.source),
        }
    }
}

/// The command-line flag that sets a JSON field (for error messages).
fn flag_of(field: &str) -> Option<&'static str> {
    let top = field.split('.').take(2).collect::<Vec<_>>();
    Some(match top.as_slice() {
        ["lookat", "eye" | "center"] | ["lookat"] => "--lookat",
        ["lookat", "up"] => "--up",
        ["lookat", "twist"] => "--twist",
        ["perspective", ..] => "--perspective",
        ["ortho", ..] => "--ortho",
        ["ortho2", ..] => "--ortho2",
        ["view", "vrp"] => "--vrp",
        ["view", "vpn"] => "--vpn",
        ["view", "view_up"] => "--view-up",
        ["view", "view_distance"] => "--view-distance",
        ["view", "window"] => "--window",
        ["view", "cop"] => "--cop",
        ["view", "dop"] => "--dop",
        ["view", "oblique" | "isometric"] => "--oblique",
        ["view", "front"] => "--front",
        ["view", "back"] => "--back",
        _ => return None,
    })
}

/// A JSON object being read: checks keys and types, naming the field on error.
struct Obj<'a> {
    ctx: Ctx<'a>,
    path: String,
    map: &'a Map<String, Value>,
}

impl<'a> Obj<'a> {
    fn new(ctx: Ctx<'a>, path: &str, value: &'a Value) -> Result<Obj<'a>> {
        let shown = if path.is_empty() { "camera" } else { path };
        match value {
            Value::Object(map) => Ok(Obj {
                ctx,
                path: path.to_string(),
                map,
            }),
            other => Err(ctx.err(
                shown,
                format!("expected a JSON object, found {}", kind(other)),
            )),
        }
    }

    fn field(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    fn err(&self, key: &str, msg: impl std::fmt::Display) -> anyhow::Error {
        self.ctx.err(&self.field(key), msg)
    }

    /// Rejects keys outside `allowed` (catches typos such as "fov" for "fovy").
    fn check_keys(&self, allowed: &[&str]) -> Result<()> {
        for key in self.map.keys() {
            if !allowed.contains(&key.as_str()) {
                return Err(self.err(
                    key,
                    format!("unknown key (expected one of: {})", allowed.join(", ")),
                ));
            }
        }
        Ok(())
    }

    fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    fn num(&self, key: &str) -> Result<Option<f64>> {
        self.map.get(key).map(|v| number(self, key, v)).transpose()
    }

    fn req_num(&self, key: &str) -> Result<f64> {
        self.num(key)?
            .ok_or_else(|| self.err(key, "missing (a number is required)"))
    }

    fn array<const N: usize>(&self, key: &str) -> Result<Option<[f64; N]>> {
        let Some(v) = self.map.get(key) else {
            return Ok(None);
        };
        let items = match v {
            Value::Array(items) if items.len() == N => items,
            other => {
                return Err(self.err(
                    key,
                    format!("expected an array of {N} numbers, found {}", kind(other)),
                ))
            }
        };
        let mut out = [0.0; N];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = number(self, key, item)?;
        }
        Ok(Some(out))
    }

    fn req_array<const N: usize>(&self, key: &str) -> Result<[f64; N]> {
        self.array::<N>(key)?.ok_or_else(|| {
            self.err(
                key,
                format!("missing (an array of {N} numbers is required)"),
            )
        })
    }

    fn vec3(&self, key: &str) -> Result<Option<DVec3>> {
        Ok(self.array::<3>(key)?.map(DVec3::from_array))
    }

    fn req_vec3(&self, key: &str) -> Result<DVec3> {
        Ok(DVec3::from_array(self.req_array::<3>(key)?))
    }
}

fn number(obj: &Obj, key: &str, v: &Value) -> Result<f64> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        Some(x) => Err(obj.err(key, format!("{x} is not a finite number"))),
        None => Err(obj.err(key, format!("expected a number, found {}", kind(v)))),
    }
}

/// A short description of a JSON value for error messages.
fn kind(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("the string {s:?}"),
        Value::Array(a) => format!("an array of {} items", a.len()),
        Value::Object(_) => "an object".into(),
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

/// Whether two non-zero directions are parallel (or antiparallel).
fn parallel(a: DVec3, b: DVec3) -> bool {
    a.cross(b).length() <= PARALLEL_SINE * a.length() * b.length()
}

/// The rotation from world axes to eye axes for a camera looking along `forward`
/// with `up` projected to +y: rows x = forward × up, y = x × forward, z = −forward.
/// (Equivalent to the textbook's R_x R_y R_z of eqs. 8.61–8.64, and to gluLookAt.)
/// The caller has checked that forward and up are non-zero and not parallel.
fn eye_rotation(forward: DVec3, up: DVec3) -> DMat3 {
    let f = forward.normalize();
    let s = f.cross(up).normalize();
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
    /// Reads a camera from its JSON form (see the module docs). Errors name
    /// `source` (the file) and the field.
    pub fn from_json(value: &Value, source: &str) -> Result<Camera> {
        from_json_ctx(
            value,
            Ctx {
                source,
                flags: false,
            },
        )
    }

    /// Reads a camera JSON file (`-` is standard input). Errors name the file.
    pub fn load(path: &str) -> Result<Camera> {
        let text = if path == "-" {
            let mut s = String::new();
            std::io::stdin()
                .read_to_string(&mut s)
                .context("reading the camera from standard input")?;
            s
        } else {
            std::fs::read_to_string(path).with_context(|| format!("{path}: cannot read camera"))?
        };
        let name = if path == "-" { "<stdin>" } else { path };
        let value: Value = serde_json::from_str(&text)
            .map_err(|e| anyhow!("{name}: not valid camera JSON: {e}"))?;
        Camera::from_json(&value, name)
    }

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

    /// [`Camera::ortho2`] with the degenerate cases as errors.
    pub fn try_ortho2(left: f64, right: f64, bottom: f64, top: f64) -> Result<Camera> {
        let value = serde_json::json!({ "ortho2": [left, right, bottom, top] });
        from_json_ctx(
            &value,
            Ctx {
                source: "ortho2",
                flags: false,
            },
        )
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

    /// Whether the front of a polygon (the side its normal points to; seen from
    /// there its vertices run counter-clockwise, SPEC §2) faces the camera: the
    /// centre of projection, or for parallel views the incoming projection rays,
    /// lie strictly on the normal's side of the polygon's plane. Edge-on polygons
    /// are not front-facing.
    pub fn is_front_facing(&self, world_normal: DVec3, point_on_plane: DVec3) -> bool {
        match self.eye_position() {
            Some(eye) => world_normal.dot(eye - point_on_plane) > 0.0,
            None => world_normal.dot(-self.view_direction()) > 0.0,
        }
    }

    /// The last line of defence: every entry finite, near < far.
    fn checked(self, ctx: Ctx) -> Result<Camera> {
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
            return Err(ctx.err(
                "camera",
                "the specification overflows f64 (a matrix entry is not finite): \
                 check for extreme or nearly degenerate values",
            ));
        }
        if !self.near.is_finite() || !self.far.is_finite() || self.near >= self.far {
            return Err(ctx.err(
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

fn from_json_ctx(value: &Value, ctx: Ctx) -> Result<Camera> {
    let root = Obj::new(ctx, "", value)?;
    root.check_keys(&["lookat", "perspective", "ortho", "ortho2", "view"])?;
    let iris = ["lookat", "perspective", "ortho", "ortho2"]
        .into_iter()
        .find(|k| root.has(k));
    let camera = match (root.map.get("view"), iris) {
        (Some(_), Some(k)) => {
            return Err(ctx.err(
                k,
                "cannot be combined with \"view\": give either the IRIS/GLU camera \
                 (lookat + perspective/ortho/ortho2) or the textbook view system",
            ))
        }
        (Some(view), None) => textbook(&Obj::new(ctx, "view", view)?)?,
        (None, _) => iris_camera(&root)?,
    };
    camera.checked(ctx)
}

/// The IRIS GL / GLU model: optional `lookat`, exactly one projection.
fn iris_camera(root: &Obj) -> Result<Camera> {
    let ctx = root.ctx;
    let view = match root.map.get("lookat") {
        Some(v) => lookat(&Obj::new(ctx, "lookat", v)?)?,
        None => DMat4::IDENTITY,
    };
    let given: Vec<&str> = ["perspective", "ortho", "ortho2"]
        .into_iter()
        .filter(|k| root.has(k))
        .collect();
    match given.as_slice() {
        [] => Err(ctx.err(
            "camera",
            "no projection: give one of \"perspective\", \"ortho\", \"ortho2\" (or a \"view\")",
        )),
        [_, second, ..] => Err(ctx.err(
            second,
            format!(
                "more than one projection given ({}): give exactly one",
                given.join(", ")
            ),
        )),
        ["perspective"] => {
            let p = Obj::new(ctx, "perspective", &root.map["perspective"])?;
            p.check_keys(&["fovy", "aspect", "near", "far"])?;
            let fovy = p.req_num("fovy")?;
            let aspect = p.req_num("aspect")?;
            let near = p.req_num("near")?;
            let far = p.req_num("far")?;
            if !(fovy > 0.0 && fovy < 180.0) {
                return Err(p.err("fovy", format!("{fovy} is outside (0, 180) degrees")));
            }
            if aspect <= 0.0 {
                return Err(p.err("aspect", format!("{aspect} is not positive (width/height)")));
            }
            if near < 0.0 {
                return Err(p.err(
                    "near",
                    format!("{near} is negative: a perspective view cannot see behind the eye"),
                ));
            }
            if far <= near {
                return Err(p.err("far", format!("{far} is not beyond near {near}")));
            }
            // gluPerspective: f = cot(fovy/2).
            let f = 1.0 / (fovy.to_radians() / 2.0).tan();
            let projection = from_rows([
                [f / aspect, 0.0, 0.0, 0.0],
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
            })
        }
        ["ortho"] => {
            let o = Obj::new(ctx, "ortho", &root.map["ortho"])?;
            o.check_keys(&["left", "right", "bottom", "top", "near", "far"])?;
            let [l, r, b, t, n, f] =
                ["left", "right", "bottom", "top", "near", "far"].map(|k| o.req_num(k));
            let (l, r, b, t, near, far) = (l?, r?, b?, t?, n?, f?);
            check_extent(&o, "right", l, r, "left")?;
            check_extent(&o, "top", b, t, "bottom")?;
            if far <= near {
                return Err(o.err("far", format!("{far} is not beyond near {near}")));
            }
            Ok(Camera {
                view,
                projection: ortho_matrix(l, r, b, t),
                near,
                far,
                perspective: false,
            })
        }
        _ => {
            let [l, r, b, t] = root.req_array::<4>("ortho2")?;
            if coincide(l, r) {
                return Err(root.err("ortho2", format!("left {l} equals right {r}: zero-width")));
            }
            if coincide(b, t) {
                return Err(root.err("ortho2", format!("bottom {b} equals top {t}: zero-height")));
            }
            Ok(Camera {
                view,
                projection: ortho_matrix(l, r, b, t),
                near: -1.0,
                far: 1.0,
                perspective: false,
            })
        }
    }
}

/// A non-empty extent `lo..hi` (reversed is allowed: it mirrors, as in GL).
fn check_extent(o: &Obj, key: &str, lo: f64, hi: f64, lo_key: &str) -> Result<()> {
    if coincide(lo, hi) {
        return Err(o.err(key, format!("{hi} equals {lo_key} {lo}: zero-size")));
    }
    Ok(())
}

/// `lookat`: gluLookAt with IRIS GL's twist (module docs).
fn lookat(o: &Obj) -> Result<DMat4> {
    o.check_keys(&["eye", "center", "up", "twist"])?;
    let eye = o.req_vec3("eye")?;
    let center = o.req_vec3("center")?;
    let up = o.vec3("up")?.unwrap_or(DVec3::Y);
    let twist = o.num("twist")?.unwrap_or(0.0);
    let sight = center - eye;
    let scale = eye.length().max(center.length()).max(1.0);
    if sight.length() <= COINCIDENT_RELATIVE * scale {
        return Err(o.err(
            "center",
            format!(
                "{} equals eye {}: the line of sight has no direction",
                show(center),
                show(eye)
            ),
        ));
    }
    if up.length() <= ROUNDOFF {
        return Err(o.err(
            "up",
            format!("{} is the zero vector: no up direction", show(up)),
        ));
    }
    if parallel(sight, up) {
        let which = if o.has("up") { "up" } else { "center" };
        return Err(o.err(
            which,
            format!(
                "up {} is parallel to the line of sight eye→center {}: the image's up is undefined{}",
                show(up),
                show(sight),
                if o.has("up") { "" } else { " (give \"up\")" }
            ),
        ));
    }
    let look = view_matrix(eye_rotation(sight, up), eye);
    Ok(DMat4::from_rotation_z(-twist.to_radians()) * look)
}

/// The textbook's view system (Harrington ch. 8; conventions in the module docs).
fn textbook(o: &Obj) -> Result<Camera> {
    o.check_keys(&[
        "vrp",
        "vpn",
        "view_up",
        "view_distance",
        "window",
        "cop",
        "dop",
        "oblique",
        "isometric",
        "front",
        "back",
    ])?;
    let given: Vec<&str> = ["cop", "dop", "oblique", "isometric"]
        .into_iter()
        .filter(|k| o.has(k))
        .collect();
    match given.as_slice() {
        [] => {
            return Err(o.ctx.err(
                "view",
                "no projection: give one of \"cop\" (perspective), \"dop\", \"oblique\" or \
                 \"isometric\" (parallel)",
            ))
        }
        [_] => {}
        [_, second, ..] => {
            return Err(o.err(
                second,
                format!(
                    "more than one projection given ({}): give exactly one",
                    given.join(", ")
                ),
            ))
        }
    }
    let isometric = o.has("isometric");
    if isometric && o.map["isometric"] != Value::Bool(true) {
        return Err(o.err(
            "isometric",
            format!("expected true, found {}", kind(&o.map["isometric"])),
        ));
    }

    // SET-VIEW-REFERENCE-POINT, SET-VIEW-PLANE-NORMAL, SET-VIEW-UP, SET-VIEW-DISTANCE
    // (Alg. 8.14–8.17) with the defaults of INITIALIZE-8 (Alg. 8.41).
    let vrp = o.vec3("vrp")?.unwrap_or(DVec3::ZERO);
    let default_vpn = if isometric {
        DVec3::splat(-1.0)
    } else {
        DVec3::NEG_Z
    };
    let vpn = o.vec3("vpn")?.unwrap_or(default_vpn);
    if vpn.length() <= ROUNDOFF {
        return Err(o.err(
            "vpn",
            format!(
                "{} is the zero vector: the view plane needs a normal (INVALID VIEW PLANE NORMAL)",
                show(vpn)
            ),
        ));
    }
    if isometric && !parallel(vpn.abs(), DVec3::ONE) {
        return Err(o.err(
            "vpn",
            format!(
                "{} is not an isometric direction: its three components must have equal magnitude, e.g. [-1, -1, -1]",
                show(vpn)
            ),
        ));
    }
    let up = o.vec3("view_up")?.unwrap_or(DVec3::Y);
    if up.length() <= ROUNDOFF {
        return Err(o.err(
            "view_up",
            format!(
                "{} is the zero vector: no up direction (NO SET-VIEW-UP DIRECTION)",
                show(up)
            ),
        ));
    }
    if parallel(vpn, up) {
        return Err(o.err(
            "view_up",
            format!(
                "{} is parallel to the view plane normal {}: the image's up is undefined \
                 (SET-VIEW-UP ALONG VIEW PLANE NORMAL)",
                show(up),
                show(vpn)
            ),
        ));
    }
    let distance = o.num("view_distance")?.unwrap_or(0.0);

    let [umin, umax, vmin, vmax] = o.req_array::<4>("window")?;
    if coincide(umin, umax) {
        return Err(o.err(
            "window",
            format!("zero width: umin {umin} equals umax {umax}"),
        ));
    }
    if coincide(vmin, vmax) {
        return Err(o.err(
            "window",
            format!("zero height: vmin {vmin} equals vmax {vmax}"),
        ));
    }
    let (wu, wv) = (umax - umin, vmax - vmin);

    // SET-VIEW-DEPTH (Alg. 8.23): distances from the VRP along the VPN.
    let front = o.req_num("front")?;
    let back = o.req_num("back")?;
    if front > back {
        return Err(o.err(
            "front",
            format!("{front} is beyond back {back} (FRONT PLANE BEHIND BACK PLANE)"),
        ));
    }
    if front == back {
        return Err(o.err(
            "back",
            format!("{back} equals front: the view volume is empty"),
        ));
    }

    // MAKE-VIEW-PLANE-TRANSFORMATION (Alg. 8.20): the view plane coordinate axes.
    let r = eye_rotation(vpn, up);
    let n = vpn.normalize();
    let plane_centre = vrp + distance * n;

    if let Some(cop) = o.vec3("cop")? {
        // MAKE-PERSPECTIVE-TRANSFORMATION (Alg. 8.21): the COP in view plane
        // coordinates must have ZC > 0.
        let c = r * (cop - plane_centre);
        let tolerance = COINCIDENT_RELATIVE * (cop - plane_centre).length().max(1.0);
        if c.z <= tolerance {
            let (where_, book) = if c.z < -tolerance {
                ("behind", " (CENTER OF PROJECTION BEHIND VIEW PLANE)")
            } else {
                ("on", "")
            };
            return Err(o.err(
                "cop",
                format!(
                    "{} is {where_} the view plane{book}: the centre of projection must lie on the \
                     viewer's side, before the view plane along the VPN (its distance to the plane is {})",
                    show(cop),
                    -c.z
                ),
            ));
        }
        // Eye coordinates: the view plane axes moved to the COP. The front and back
        // distances become distances from the COP.
        let cop_depth = (cop - vrp).dot(n);
        let (near, far) = (front - cop_depth, back - cop_depth);
        if near < 0.0 {
            return Err(o.err(
                "front",
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
        });
    }

    // The direction of projection in view plane coordinates (Alg. 8.22).
    let p = if let Some(dop) = o.vec3("dop")? {
        if dop.length() <= ROUNDOFF {
            return Err(o.err(
                "dop",
                format!(
                    "{} is the zero vector (NO DIRECTION OF PROJECTION)",
                    show(dop)
                ),
            ));
        }
        let p = r * dop;
        if p.z.abs() <= PARALLEL_SINE * p.length() {
            return Err(o.err(
                "dop",
                format!(
                    "{} is parallel to the view plane (PROJECTION PARALLEL VIEW PLANE): \
                     the projection lines never meet it",
                    show(dop)
                ),
            ));
        }
        p
    } else if let Some(value) = o.map.get("oblique") {
        let ob = Obj::new(o.ctx, "view.oblique", value)?;
        ob.check_keys(&["kind", "angle"])?;
        // "Special projections": SET-PARALLEL(cos A, sin A, 1) is cavalier,
        // (cos A, sin A, 2) cabinet.
        let receding = match ob.map.get("kind") {
            Some(Value::String(k)) if k == "cavalier" => 1.0,
            Some(Value::String(k)) if k == "cabinet" => 2.0,
            Some(other) => {
                return Err(ob.err(
                    "kind",
                    format!(
                        "expected \"cavalier\" or \"cabinet\", found {}",
                        kind(other)
                    ),
                ))
            }
            None => return Err(ob.err("kind", "missing (\"cavalier\" or \"cabinet\")")),
        };
        let angle = ob
            .num("angle")?
            .unwrap_or(DEFAULT_OBLIQUE_ANGLE)
            .to_radians();
        DVec3::new(angle.cos(), angle.sin(), receding)
    } else {
        // Isometric: projection along the view plane normal.
        DVec3::Z
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
    })
}

/// The angle of the receding axis of cavalier and cabinet projections when none
/// is given, in degrees (the usual drafting choice; the textbook leaves A free).
pub const DEFAULT_OBLIQUE_ANGLE: f64 = 45.0;

/// Parses `N` comma-separated finite numbers (`"0,100,-5"`).
fn parse_list<const N: usize>(text: &str) -> std::result::Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers, found {}",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(&parts) {
        let x: f64 = part
            .parse()
            .map_err(|_| format!("{part:?} is not a number"))?;
        if !x.is_finite() {
            return Err(format!("{part} is not a finite number"));
        }
        *slot = x;
    }
    Ok(out)
}

/// Parses one finite number.
fn parse_finite(text: &str) -> std::result::Result<f64, String> {
    parse_list::<1>(text).map(|[x]| x)
}

/// The camera flags shared by the tools (`#[command(flatten)]`): a camera file, or
/// either model spelled as flags. See the module docs for the meaning of each value.
#[derive(clap::Args, Clone, Debug, Default, PartialEq)]
pub struct CameraArgs {
    /// Camera JSON file (`-` = standard input); excludes every other camera flag.
    /// Default: none (the tool's default view).
    #[arg(long, value_name = "FILE", help_heading = "Camera")]
    pub camera: Option<String>,

    /// IRIS/GLU lookat: eye and center points. Default: none (identity view, eye at
    /// the origin looking down -z).
    #[arg(long, value_name = "EX,EY,EZ,CX,CY,CZ", value_parser = parse_list::<6>, allow_hyphen_values = true, help_heading = "Camera")]
    pub lookat: Option<[f64; 6]>,

    /// Up direction for --lookat. Default: 0,1,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera")]
    pub up: Option<[f64; 3]>,

    /// IRIS lookat twist in degrees (right-hand rotation of the camera about its line
    /// of sight). Default: 0.
    #[arg(long, value_name = "DEG", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera")]
    pub twist: Option<f64>,

    /// gluPerspective: vertical field of view in degrees, aspect (width/height),
    /// near and far distances (near may be 0). Default: none.
    #[arg(long, value_name = "FOVY,ASPECT,NEAR,FAR", value_parser = parse_list::<4>, allow_hyphen_values = true, help_heading = "Camera")]
    pub perspective: Option<[f64; 4]>,

    /// glOrtho: left, right, bottom, top, near, far in eye coordinates. Default: none.
    #[arg(long, value_name = "L,R,B,T,N,F", value_parser = parse_list::<6>, allow_hyphen_values = true, help_heading = "Camera")]
    pub ortho: Option<[f64; 6]>,

    /// IRIS ortho2 (gluOrtho2D): left, right, bottom, top; near -1, far 1. Default: none.
    #[arg(long, value_name = "L,R,B,T", value_parser = parse_list::<4>, allow_hyphen_values = true, help_heading = "Camera")]
    pub ortho2: Option<[f64; 4]>,

    /// Textbook view reference point (world). Default: 0,0,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub vrp: Option<[f64; 3]>,

    /// View plane normal: the direction the camera looks. Default: 0,0,-1
    /// (-1,-1,-1 with --oblique isometric).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub vpn: Option<[f64; 3]>,

    /// View-up direction (world), shown vertical on the image. Default: 0,1,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub view_up: Option<[f64; 3]>,

    /// Distance from the VRP to the view plane along the VPN. Default: 0.
    #[arg(long, value_name = "D", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub view_distance: Option<f64>,

    /// Window on the view plane (view plane coordinates, centred on the VPN line
    /// through the VRP); it fills the image. Default: none (required).
    #[arg(long, value_name = "UMIN,UMAX,VMIN,VMAX", value_parser = parse_list::<4>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub window: Option<[f64; 4]>,

    /// Perspective: centre of projection (world coordinates, on the viewer's side of
    /// the view plane). Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub cop: Option<[f64; 3]>,

    /// Parallel: direction of projection (world; oblique when not along the VPN).
    /// Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub dop: Option<[f64; 3]>,

    /// Parallel: cavalier or cabinet oblique projection with the receding axis at
    /// ANGLE degrees (default 45), or isometric (no angle). Default: none.
    #[arg(long, value_name = "cavalier|cabinet|isometric[,ANGLE]", value_parser = parse_oblique, help_heading = "Camera (textbook view system)")]
    pub oblique: Option<Oblique>,

    /// Front clipping plane: distance from the VRP along the VPN. Default: none
    /// (required).
    #[arg(long, value_name = "F", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub front: Option<f64>,

    /// Back clipping plane: distance from the VRP along the VPN. Default: none
    /// (required).
    #[arg(long, value_name = "B", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub back: Option<f64>,
}

/// `--oblique`: one of the textbook's special parallel projections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Oblique {
    /// Receding axis at the angle (degrees), full length.
    Cavalier(Option<f64>),
    /// Receding axis at the angle (degrees), half length.
    Cabinet(Option<f64>),
    /// Projection along a VPN with equal-magnitude components.
    Isometric,
}

fn parse_oblique(text: &str) -> std::result::Result<Oblique, String> {
    let (kind, angle) = match text.split_once(',') {
        Some((k, a)) => (k.trim(), Some(parse_finite(a)?)),
        None => (text.trim(), None),
    };
    match (kind, angle) {
        ("cavalier", a) => Ok(Oblique::Cavalier(a)),
        ("cabinet", a) => Ok(Oblique::Cabinet(a)),
        ("isometric", None) => Ok(Oblique::Isometric),
        ("isometric", Some(_)) => Err("isometric takes no angle".into()),
        (other, _) => Err(format!(
            "{other:?}: expected cavalier, cabinet or isometric"
        )),
    }
}

fn oblique_json(kind: &str, angle: Option<f64>) -> Value {
    match angle {
        Some(a) => serde_json::json!({"kind": kind, "angle": a}),
        None => serde_json::json!({ "kind": kind }),
    }
}

impl CameraArgs {
    /// The camera the flags describe; None when no camera flag was given (the
    /// caller picks its default). Contradictory or degenerate flags are usage
    /// errors (exit status 2) naming the flag; a bad --camera file is a failure.
    pub fn resolve(&self) -> Result<Option<Camera>> {
        if let Some(path) = &self.camera {
            if self.json().is_some() {
                crate::cli::usage_bail!("--camera cannot be combined with other camera flags");
            }
            return Camera::load(path).map(Some);
        }
        if self.lookat.is_none() && (self.up.is_some() || self.twist.is_some()) {
            crate::cli::usage_bail!("--up and --twist need --lookat EX,EY,EZ,CX,CY,CZ");
        }
        let Some(value) = self.json() else {
            return Ok(None);
        };
        from_json_ctx(
            &value,
            Ctx {
                source: "camera flags",
                flags: true,
            },
        )
        .map(Some)
        .map_err(|e| anyhow::Error::new(crate::cli::UsageError(format!("{e:#}"))))
    }

    /// The JSON form of the flags (None when no camera flag was given).
    fn json(&self) -> Option<Value> {
        use serde_json::json;
        let mut root = Map::new();
        if self.lookat.is_some() || self.up.is_some() || self.twist.is_some() {
            let mut lookat = Map::new();
            if let Some(l) = self.lookat {
                lookat.insert("eye".into(), json!(l[..3]));
                lookat.insert("center".into(), json!(l[3..]));
            }
            if let Some(up) = self.up {
                lookat.insert("up".into(), json!(up));
            }
            if let Some(twist) = self.twist {
                lookat.insert("twist".into(), json!(twist));
            }
            root.insert("lookat".into(), Value::Object(lookat));
        }
        if let Some([fovy, aspect, near, far]) = self.perspective {
            root.insert(
                "perspective".into(),
                json!({"fovy": fovy, "aspect": aspect, "near": near, "far": far}),
            );
        }
        if let Some([l, r, b, t, n, f]) = self.ortho {
            root.insert(
                "ortho".into(),
                json!({"left": l, "right": r, "bottom": b, "top": t, "near": n, "far": f}),
            );
        }
        if let Some(o2) = self.ortho2 {
            root.insert("ortho2".into(), json!(o2));
        }
        let mut view = Map::new();
        let vectors = [
            ("vrp", self.vrp),
            ("vpn", self.vpn),
            ("view_up", self.view_up),
            ("cop", self.cop),
            ("dop", self.dop),
        ];
        for (key, v) in vectors {
            if let Some(v) = v {
                view.insert(key.into(), json!(v));
            }
        }
        let numbers = [
            ("view_distance", self.view_distance),
            ("front", self.front),
            ("back", self.back),
        ];
        for (key, x) in numbers {
            if let Some(x) = x {
                view.insert(key.into(), json!(x));
            }
        }
        if let Some(w) = self.window {
            view.insert("window".into(), json!(w));
        }
        match self.oblique {
            Some(Oblique::Cavalier(a)) => {
                view.insert("oblique".into(), oblique_json("cavalier", a));
            }
            Some(Oblique::Cabinet(a)) => {
                view.insert("oblique".into(), oblique_json("cabinet", a));
            }
            Some(Oblique::Isometric) => {
                view.insert("isometric".into(), Value::Bool(true));
            }
            None => {}
        }
        if !view.is_empty() {
            root.insert("view".into(), Value::Object(view));
        }
        (!root.is_empty()).then_some(Value::Object(root))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;
    use proptest::prelude::*;
    use serde_json::json;

    /// Agreement demanded of two descriptions of the same view.
    const SAME_VIEW: f64 = 1e-12;
    /// Tolerance for projected coordinates computed through a few matrix products.
    const CLOSE: f64 = 1e-9;

    fn cam(v: Value) -> Camera {
        Camera::from_json(&v, "test.json").unwrap_or_else(|e| panic!("{e:#}"))
    }

    /// The error message for a camera that must be rejected.
    fn err(v: Value) -> String {
        match Camera::from_json(&v, "test.json") {
            Ok(c) => panic!("accepted: {c:?}"),
            Err(e) => format!("{e:#}"),
        }
    }

    fn assert_err(v: Value, parts: &[&str]) {
        let msg = err(v);
        assert!(msg.starts_with("test.json: "), "{msg}");
        for part in parts {
            assert!(msg.contains(part), "{msg:?} lacks {part:?}");
        }
    }

    /// Normalised device coordinates of a world point.
    fn ndc(c: &Camera, p: DVec3) -> DVec3 {
        let clip = c.world_to_clip() * p.extend(1.0);
        clip.truncate() / clip.w
    }

    fn demo2() -> Value {
        json!({"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900], "twist": 0},
               "perspective": {"fovy": 55, "aspect": 1.0, "near": 0, "far": 1000}})
    }

    fn max_diff(a: DMat4, b: DMat4) -> f64 {
        (a - b)
            .to_cols_array()
            .iter()
            .fold(0.0, |m, x| m.max(x.abs()))
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
    fn front_facing() {
        let c = cam(demo2());
        // The floor's normal +y faces the camera above it; -y does not.
        let p = DVec3::new(0.0, 0.0, -400.0);
        assert!(c.is_front_facing(DVec3::Y, p));
        assert!(!c.is_front_facing(DVec3::NEG_Y, p));
        let o = Camera::ortho2(0.0, 10.0, 0.0, 10.0);
        assert!(o.is_front_facing(DVec3::Z, DVec3::ZERO));
        assert!(!o.is_front_facing(DVec3::NEG_Z, DVec3::ZERO));
        assert!(!o.is_front_facing(DVec3::X, DVec3::ZERO), "edge-on");
    }

    #[test]
    fn iris_errors() {
        let p = |fovy: f64, aspect: f64, near: f64, far: f64| json!({"perspective": {"fovy": fovy, "aspect": aspect, "near": near, "far": far}});
        assert_err(
            p(0.0, 1.0, 0.0, 1.0),
            &["perspective.fovy", "0", "(0, 180)"],
        );
        assert_err(p(180.0, 1.0, 0.0, 1.0), &["perspective.fovy", "180"]);
        assert_err(p(-5.0, 1.0, 0.0, 1.0), &["perspective.fovy", "-5"]);
        assert_err(p(60.0, 0.0, 0.0, 1.0), &["perspective.aspect", "0"]);
        assert_err(p(60.0, -1.0, 0.0, 1.0), &["perspective.aspect", "-1"]);
        assert_err(
            p(60.0, 1.0, -1.0, 1.0),
            &["perspective.near", "-1", "negative"],
        );
        assert_err(p(60.0, 1.0, 2.0, 2.0), &["perspective.far", "2"]);
        assert_err(
            p(60.0, 1.0, 2.0, 1.0),
            &["perspective.far", "not beyond near 2"],
        );
        assert_err(
            json!({"ortho": {"left": 1, "right": 1, "bottom": 0, "top": 1, "near": 0, "far": 1}}),
            &["ortho.right", "zero-size"],
        );
        assert_err(
            json!({"ortho": {"left": 0, "right": 1, "bottom": 0, "top": 1, "near": 1, "far": 0}}),
            &["ortho.far", "near 1"],
        );
        assert_err(json!({"ortho2": [0, 0, 0, 1]}), &["ortho2", "zero-width"]);
        assert_err(json!({"ortho2": [0, 1, 3, 3]}), &["ortho2", "zero-height"]);
        assert_err(json!({"ortho2": [0, 1, 3]}), &["ortho2", "array of 4"]);
        assert_err(
            json!({"ortho2": [0, 1, 3, "x"]}),
            &["ortho2", "expected a number"],
        );
        let look = |l: Value| json!({"lookat": l, "ortho2": [0, 1, 0, 1]});
        assert_err(
            look(json!({"eye": [1, 2, 3], "center": [1, 2, 3]})),
            &["lookat.center", "equals eye [1, 2, 3]"],
        );
        assert_err(
            look(json!({"eye": [0, 5, 0], "center": [0, 0, 0]})),
            &[
                "lookat.center",
                "parallel to the line of sight",
                "give \"up\"",
            ],
        );
        assert_err(
            look(json!({"eye": [0, 0, 0], "center": [0, 0, -1], "up": [0, 0, 2]})),
            &["lookat.up", "parallel"],
        );
        assert_err(
            look(json!({"eye": [0, 0, 0], "center": [0, 0, -1], "up": [0, 0, 0]})),
            &["lookat.up", "zero vector"],
        );
        assert_err(
            look(json!({"eye": [0, 0, 0]})),
            &["lookat.center", "missing"],
        );
        assert_err(
            look(json!({"eye": [0, 0, 0], "centre": [0, 0, 1]})),
            &["lookat.centre", "unknown key"],
        );
        assert_err(json!({"perspectiv": {}}), &["perspectiv", "unknown key"]);
        assert_err(
            json!({"perspective": {"fov": 60, "aspect": 1, "near": 0, "far": 1}}),
            &["perspective.fov", "unknown key"],
        );
        assert_err(
            json!({"lookat": {"eye": [0, 0, 0], "center": [0, 0, -1]}}),
            &["no projection"],
        );
        assert_err(
            json!({"ortho2": [0, 1, 0, 1], "perspective": {"fovy": 60, "aspect": 1, "near": 0, "far": 1}}),
            &["more than one projection"],
        );
        assert_err(json!([1, 2]), &["expected a JSON object"]);
        // Finite inputs whose matrices overflow are caught by the final check.
        assert_err(
            json!({"ortho2": [0, 1e-310, 0, 1]}),
            &["ortho2", "zero-width"],
        );
        assert_err(
            json!({"perspective": {"fovy": 1e-320, "aspect": 1, "near": 0, "far": 1}}),
            &["not finite"],
        );
    }

    #[test]
    fn flags_resolve_like_json() {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            camera: CameraArgs,
        }
        let parse = |args: &[&str]| {
            Cli::try_parse_from(std::iter::once("t").chain(args.iter().copied())).map(|c| c.camera)
        };
        <Cli as clap::CommandFactory>::command().debug_assert();
        assert_eq!(parse(&[]).unwrap().resolve().unwrap(), None);
        let e = parse(&["--up", "0,0,1", "--ortho2", "0,1,0,1"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(format!("{e}").contains("need --lookat"), "{e}");
        let flags = parse(&[
            "--lookat",
            "0,100,-5,0,0,-900",
            "--twist",
            "0",
            "--perspective",
            "55,1,0,1000",
        ])
        .unwrap();
        assert_eq!(flags.resolve().unwrap(), Some(cam(demo2())));
        let e = parse(&["--perspective", "55,1,-1,1000"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(e.downcast_ref::<crate::cli::UsageError>().is_some());
        let msg = format!("{e:#}");
        assert!(
            msg.contains("--perspective") && msg.contains("negative"),
            "{msg}"
        );
        assert!(parse(&["--perspective", "NaN,1,0,1"]).is_err());
        assert!(parse(&["--perspective", "inf,1,0,1"]).is_err());
        assert!(parse(&["--ortho2", "0,1,0"]).is_err());
        let e = parse(&["--camera", "x.json", "--ortho2", "0,1,0,1"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(e.downcast_ref::<crate::cli::UsageError>().is_some());
    }

    #[test]
    fn load_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cam.json");
        std::fs::write(&path, r#"{"ortho2": [0, 1, 0, 1], "extra": 1}"#).unwrap();
        let p = path.to_str().unwrap();
        let msg = format!("{:#}", Camera::load(p).unwrap_err());
        assert!(msg.starts_with(p) && msg.contains("extra"), "{msg}");
        std::fs::write(&path, "{").unwrap();
        let msg = format!("{:#}", Camera::load(p).unwrap_err());
        assert!(msg.starts_with(p) && msg.contains("line 1"), "{msg}");
        let msg = format!("{:#}", Camera::load("/nonexistent/cam.json").unwrap_err());
        assert!(msg.contains("/nonexistent/cam.json"), "{msg}");
        std::fs::write(&path, r#"{"ortho2": [0, 1, 0, 1]}"#).unwrap();
        assert_eq!(Camera::load(p).unwrap(), Camera::ortho2(0.0, 1.0, 0.0, 1.0));
    }

    /// A view system camera on the default (GL-like) orientation.
    fn view(extra: Value) -> Value {
        let mut v = json!({"window": [-1, 1, -1, 1], "front": -10, "back": 10});
        for (k, x) in extra.as_object().unwrap() {
            v[k] = x.clone();
        }
        json!({ "view": v })
    }

    #[test]
    fn textbook_perspective_equals_lookat_perspective() {
        let (eye, center, up) = ([1.0, 2.0, 3.0], [4.0, -1.0, -5.0], [0.2, 1.0, 0.1]);
        let iris = cam(json!({"lookat": {"eye": eye, "center": center, "up": up},
                              "perspective": {"fovy": 50, "aspect": 1.5, "near": 0.5, "far": 40}}));
        let t = 25f64.to_radians().tan();
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
        let t = 27.5f64.to_radians().tan();
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
            let want = glam::DVec2::new(a.cos(), a.sin()) * length;
            assert!((p.truncate() - want).length() < CLOSE, "{kind}: {p}");
            // Depth still measures along the VPN; the front face is not distorted.
            assert!((p.z - 1.0).abs() < CLOSE);
            let q = ndc(&c, DVec3::new(0.25, -0.5, 0.0));
            assert!((q.truncate() - glam::DVec2::new(0.25, -0.5)).length() < CLOSE);
            // The textbook's SET-PARALLEL(cos A, sin A, 1 or 2) is the same camera.
            let dop = [a.cos(), a.sin(), 1.0 / length];
            let d = cam(view(json!({ "dop": dop })));
            assert!(max_diff(c.world_to_clip(), d.world_to_clip()) <= SAME_VIEW);
            // The camera looks along the (oblique) projection direction.
            let v = c.view_direction();
            assert!(
                (v - -DVec3::from_array(dop).normalize()).length() < CLOSE,
                "{v}"
            );
            assert!(c.is_front_facing(DVec3::Z, DVec3::ZERO));
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

    #[test]
    fn textbook_errors() {
        assert_err(
            view(json!({"vpn": [0, 0, 0], "dop": [0, 0, 1]})),
            &["view.vpn", "zero vector", "INVALID VIEW PLANE NORMAL"],
        );
        assert_err(
            view(json!({"view_up": [0, 0, 0], "dop": [0, 0, 1]})),
            &["view.view_up", "zero vector", "NO SET-VIEW-UP DIRECTION"],
        );
        assert_err(
            view(json!({"view_up": [0, 0, 3], "dop": [0, 0, 1]})),
            &[
                "view.view_up",
                "[0, 0, 3]",
                "parallel",
                "SET-VIEW-UP ALONG VIEW PLANE NORMAL",
            ],
        );
        assert_err(
            view(json!({"dop": [0, 0, 0]})),
            &["view.dop", "NO DIRECTION OF PROJECTION"],
        );
        assert_err(
            view(json!({"dop": [1, 1, 0]})),
            &["view.dop", "[1, 1, 0]", "PROJECTION PARALLEL VIEW PLANE"],
        );
        assert_err(
            view(json!({"cop": [0, 0, -3]})),
            &[
                "view.cop",
                "[0, 0, -3]",
                "behind the view plane",
                "CENTER OF PROJECTION BEHIND",
            ],
        );
        assert_err(
            view(json!({"cop": [1, 1, 0]})),
            &["view.cop", "is on the view plane"],
        );
        assert_err(
            view(json!({"cop": [0, 0, 1], "front": -2})),
            &["view.front", "behind the centre of projection"],
        );
        assert_err(
            view(json!({"dop": [0, 0, 1], "front": 3, "back": 2})),
            &["view.front", "FRONT PLANE BEHIND BACK PLANE"],
        );
        assert_err(
            view(json!({"dop": [0, 0, 1], "front": 2, "back": 2})),
            &["view.back", "empty"],
        );
        assert_err(
            view(json!({"dop": [0, 0, 1], "window": [1, 1, 0, 1]})),
            &["view.window", "zero width"],
        );
        assert_err(
            view(json!({"dop": [0, 0, 1], "window": [0, 1, 2, 2]})),
            &["view.window", "zero height"],
        );
        assert_err(view(json!({})), &["view", "no projection"]);
        assert_err(
            view(json!({"cop": [0, 0, 1], "dop": [0, 0, 1]})),
            &["view.dop", "more than one projection"],
        );
        assert_err(
            view(json!({"isometric": false})),
            &["view.isometric", "expected true"],
        );
        assert_err(
            view(json!({"isometric": true, "vpn": [-1, -2, -1]})),
            &["view.vpn", "not an isometric direction"],
        );
        assert_err(
            view(json!({"oblique": {"kind": "cavalir"}})),
            &["view.oblique.kind", "cavalir"],
        );
        assert_err(
            view(json!({"oblique": {"kind": "cabinet", "angel": 30}})),
            &["view.oblique.angel", "unknown key"],
        );
        assert_err(
            view(json!({"dop": [0, 0, 1], "vup": [0, 1, 0]})),
            &["view.vup", "unknown key"],
        );
        assert_err(
            json!({"view": {"dop": [0, 0, 1], "front": 0, "back": 1}}),
            &["view.window", "missing"],
        );
        assert_err(
            json!({"view": {"dop": [0, 0, 1], "window": [0, 1, 0, 1], "back": 1}}),
            &["view.front", "missing"],
        );
        let mut both = view(json!({"dop": [0, 0, 1]}));
        both["ortho2"] = json!([0, 1, 0, 1]);
        assert_err(both, &["ortho2", "cannot be combined"]);
        // Overflow is caught by the final check, never a NaN matrix.
        assert_err(
            view(json!({"dop": [1, 0, 1e-300], "vpn": [0, 0, -1]})),
            &["view.dop"],
        );
        assert_err(
            view(json!({"vrp": [1.5e308, 1.5e308, 1.5e308], "isometric": true})),
            &["not finite"],
        );
    }

    #[test]
    fn textbook_flags() {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            camera: CameraArgs,
        }
        let parse = |args: &[&str]| {
            Cli::try_parse_from(std::iter::once("t").chain(args.iter().copied())).map(|c| c.camera)
        };
        let flags = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--oblique",
            "cabinet,30",
        ])
        .unwrap();
        let json = cam(view(json!({"oblique": {"kind": "cabinet", "angle": 30}})));
        assert_eq!(flags.resolve().unwrap(), Some(json));
        let flags = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--oblique",
            "isometric",
            "--vrp",
            "1,1,1",
        ])
        .unwrap();
        assert!(flags.resolve().unwrap().is_some());
        assert!(parse(&["--oblique", "isometric,30"]).is_err());
        assert!(parse(&["--oblique", "cabinett"]).is_err());
        let e = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--vpn",
            "0,0,0",
            "--dop",
            "0,0,1",
        ])
        .unwrap()
        .resolve()
        .unwrap_err();
        let msg = format!("{e:#}");
        assert!(
            msg.contains("--vpn") && msg.contains("INVALID VIEW PLANE NORMAL"),
            "{msg}"
        );
        let e = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--dop",
            "0,0,1",
            "--ortho2",
            "0,1,0,1",
        ])
        .unwrap()
        .resolve()
        .unwrap_err();
        assert!(format!("{e:#}").contains("--ortho2"), "{e:#}");
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
