//! The camera's JSON form (module docs of [`camera`](super), `docs/camera.md`):
//! [`Camera::from_json`] and [`Camera::load`] read it into a [`CameraSpec`] and
//! hand that to [`Camera::from_spec`].
//!
//! This reader finds what only JSON can get wrong: a value of the wrong type, an
//! unknown key (a typo such as "fov" for "fovy"), a required number missing from
//! `lookat` or a projection, both models at once. Everything else is the spec's
//! business. One subtlety keeps the first error of every input what it has always
//! been: the spec's checks read their inputs in the textbook's order (see
//! `spec.rs`), and a geometric error in an early input (a zero VPN)
//! is reported before a type error in a later one (a `"window"` that is not an
//! array). So the reader runs each early stage of the spec's checks as soon as
//! that stage's inputs are read, in the same order as `from_spec`, which then
//! runs them again on the finished spec (they are cheap and give the same
//! verdict).

use glam::DVec3;
use serde_json::{Map, Value};

use super::spec::{
    checked_back, checked_front, checked_view_up, checked_vpn, checked_window, models_combined,
    one_iris_projection, one_view_projection,
};
use super::{
    Aspect, Camera, CameraError, CameraSpec, IrisProjection, IrisSpec, LookAt, ObliqueKind, Ortho,
    Ortho2, Perspective, ViewProjection, ViewSpec, Window,
};

type Result<T> = std::result::Result<T, CameraError>;

impl Camera {
    /// Reads a camera from its JSON form (see the module docs). Errors name
    /// `source` (the file) and the field.
    pub fn from_json(value: &Value, source: &str) -> Result<Camera> {
        spec_from_json(value)
            .and_then(|spec| Camera::from_spec(&spec))
            .map_err(|e| e.with_origin(source))
    }

    /// Reads a camera JSON file (`-` is standard input). Errors name the file.
    pub fn load(path: &str) -> Result<Camera> {
        let read = |error| CameraError::Read {
            path: path.to_string(),
            error,
        };
        // Bounded, and refused at once where it is not text (`/dev/zero`).
        let bytes = crate::io::read_input(path, crate::io::InputKind::Camera).map_err(|e| {
            read(match e {
                crate::io::IoError::Read { error, .. } => error,
                other => std::io::Error::other(other.to_string()),
            })
        })?;
        let text = String::from_utf8(bytes).map_err(|_| {
            read(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "stream did not contain valid UTF-8",
            ))
        })?;
        let name = if path == "-" { "<stdin>" } else { path };
        let value =
            crate::stream::value_with_unique_keys(&text).map_err(|error| CameraError::Json {
                origin: name.to_string(),
                error,
            })?;
        Camera::from_json(&value, name)
    }
}

/// The specification a camera JSON value gives. Fails on wrong types and keys,
/// and (to keep the first error the same as it has always been, module docs) on
/// the spec checks that come before the last value is read.
fn spec_from_json(value: &Value) -> Result<CameraSpec> {
    let root = Obj::new("", value)?;
    root.check_keys(&["lookat", "perspective", "ortho", "ortho2", "view"])?;
    let iris = ["lookat", "perspective", "ortho", "ortho2"]
        .into_iter()
        .find(|k| root.has(k));
    match (root.map.get("view"), iris) {
        (Some(_), Some(k)) => Err(models_combined(k)),
        (Some(view), None) => view_spec(&Obj::new("view", view)?).map(CameraSpec::View),
        (None, _) => iris_spec(&root).map(CameraSpec::Iris),
    }
}

/// The IRIS GL / GLU model: optional `lookat`, exactly one projection.
fn iris_spec(root: &Obj) -> Result<IrisSpec> {
    let lookat = match root.map.get("lookat") {
        Some(v) => {
            let o = Obj::new("lookat", v)?;
            o.check_keys(&["eye", "center", "up", "twist"])?;
            let lookat = LookAt {
                eye: o.req_vec3("eye")?,
                center: o.req_vec3("center")?,
                up: o.vec3("up")?,
                twist: o.num("twist")?,
            };
            // A degenerate line of sight comes before anything wrong in the
            // projection.
            lookat.view()?;
            Some(lookat)
        }
        None => None,
    };
    let given: Vec<&str> = ["perspective", "ortho", "ortho2"]
        .into_iter()
        .filter(|k| root.has(k))
        .collect();
    one_iris_projection(&given)?;
    let projection = match given[0] {
        "perspective" => {
            let p = Obj::new("perspective", &root.map["perspective"])?;
            p.check_keys(&["fovy", "aspect", "near", "far"])?;
            IrisProjection::Perspective(Perspective {
                fovy: p.req_num("fovy")?,
                aspect: p.aspect()?,
                near: p.req_num("near")?,
                far: p.req_num("far")?,
            })
        }
        "ortho" => {
            let o = Obj::new("ortho", &root.map["ortho"])?;
            o.check_keys(&["left", "right", "bottom", "top", "near", "far"])?;
            IrisProjection::Ortho(Ortho {
                left: o.req_num("left")?,
                right: o.req_num("right")?,
                bottom: o.req_num("bottom")?,
                top: o.req_num("top")?,
                near: o.req_num("near")?,
                far: o.req_num("far")?,
            })
        }
        _ => {
            let [left, right, bottom, top] = root.req_array::<4>("ortho2")?;
            IrisProjection::Ortho2(Ortho2 {
                left,
                right,
                bottom,
                top,
            })
        }
    };
    Ok(IrisSpec {
        lookat,
        projection: vec![projection],
    })
}

/// The textbook's view system; each stage of the spec's checks runs as soon as
/// its inputs are read (module docs).
fn view_spec(o: &Obj) -> Result<ViewSpec> {
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
    one_view_projection(&given)?;
    let isometric = o.has("isometric");
    if isometric && o.map["isometric"] != Value::Bool(true) {
        return Err(o.err(
            "isometric",
            format!("expected true, found {}", kind(&o.map["isometric"])),
        ));
    }
    let vrp = o.vec3("vrp")?;
    let vpn = o.vec3("vpn")?;
    let checked = checked_vpn(vpn, isometric)?;
    let view_up = o.vec3("view_up")?;
    checked_view_up(view_up, checked)?;
    let view_distance = o.num("view_distance")?;
    let window = o.array::<4>("window")?.map(Window::from_array);
    checked_window(window)?;
    let front = o.num("front")?;
    let checked = checked_front(front)?;
    let back = o.num("back")?;
    checked_back(checked, back)?;
    let projection = match given[0] {
        "cop" => ViewProjection::Cop(o.req_vec3("cop")?),
        "dop" => ViewProjection::Dop(o.req_vec3("dop")?),
        "oblique" => {
            let ob = Obj::new("view.oblique", &o.map["oblique"])?;
            ob.check_keys(&["kind", "angle"])?;
            let kind = match ob.map.get("kind") {
                Some(Value::String(k)) if k == "cavalier" => ObliqueKind::Cavalier,
                Some(Value::String(k)) if k == "cabinet" => ObliqueKind::Cabinet,
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
            ViewProjection::Oblique {
                kind,
                angle: ob.num("angle")?,
            }
        }
        _ => ViewProjection::Isometric,
    };
    Ok(ViewSpec {
        vrp,
        vpn,
        view_up,
        view_distance,
        window,
        projection: vec![projection],
        front,
        back,
    })
}

/// A JSON object being read: checks keys and types, naming the field on error.
struct Obj<'a> {
    path: String,
    map: &'a Map<String, Value>,
}

impl<'a> Obj<'a> {
    fn new(path: &str, value: &'a Value) -> Result<Obj<'a>> {
        let shown = if path.is_empty() { "camera" } else { path };
        match value {
            Value::Object(map) => Ok(Obj {
                path: path.to_string(),
                map,
            }),
            other => Err(CameraError::invalid(
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

    fn err(&self, key: &str, msg: impl std::fmt::Display) -> CameraError {
        CameraError::invalid(self.field(key), msg)
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

    /// `"aspect"`: a number, or `"auto"` for the image's own ratio.
    fn aspect(&self) -> Result<Aspect> {
        match self.map.get("aspect") {
            Some(Value::String(s)) if s == "auto" => Ok(Aspect::Auto),
            Some(Value::String(s)) => {
                Err(self.err("aspect", format!("{s:?} is neither a number nor \"auto\"")))
            }
            _ => self.req_num("aspect").map(Aspect::Ratio),
        }
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

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::*;
    use serde_json::json;

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
        // 1e200 away, on the viewer's side: its distance squared overflowed
        // and made it "on" the plane; what is wrong is the depth range, which
        // f64 cannot tell from zero that far out.
        assert_err(
            view(json!({"cop": [0, 0, 1e200], "front": 0, "back": 10})),
            &["empty view volume: near 1000", "is not below far 1000"],
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

    /// The example cameras of the docs, the fuzz seeds and the tests, each with
    /// the spec written by hand: the reader fills every field where it belongs,
    /// and the JSON route gives the same bits as the spec route.
    #[test]
    fn json_and_hand_built_specs_give_the_same_bits() {
        let v = DVec3::new;
        let iris = |lookat, p| {
            CameraSpec::Iris(IrisSpec {
                lookat,
                projection: vec![p],
            })
        };
        let look = |eye, center, up, twist| {
            Some(LookAt {
                eye,
                center,
                up,
                twist,
            })
        };
        let demo2_perspective = IrisProjection::Perspective(Perspective {
            fovy: 55.0,
            aspect: Aspect::Ratio(1.0),
            near: 0.0,
            far: 1000.0,
        });
        let unit_window = Some(Window::from_array([-1.0, 1.0, -1.0, 1.0]));
        let (w, h) = (48.0, 36.0);
        let t = crate::math::tan(27.5f64.to_radians());
        let dir = DVec3::new(1.0, 0.0, -1.0).normalize();
        let pos = DVec3::new(10.0, 50.0, -20.0);
        let far_away = DVec3::new(1e7, -1e7, 1e7);
        let cases = [
            // The module docs and docs/camera.md; the tools' tests (the thesis's demo 2).
            (
                demo2(),
                iris(
                    look(v(0.0, 100.0, -5.0), v(0.0, 0.0, -900.0), None, Some(0.0)),
                    demo2_perspective,
                ),
            ),
            (
                json!({"ortho": {"left": -1, "right": 1, "bottom": -1, "top": 1, "near": -1, "far": 1}}),
                iris(
                    None,
                    IrisProjection::Ortho(Ortho {
                        left: -1.0,
                        right: 1.0,
                        bottom: -1.0,
                        top: 1.0,
                        near: -1.0,
                        far: 1.0,
                    }),
                ),
            ),
            (
                json!({"ortho2": [0, 1023, 0, 767]}),
                iris(
                    None,
                    IrisProjection::Ortho2(Ortho2 {
                        left: 0.0,
                        right: 1023.0,
                        bottom: 0.0,
                        top: 767.0,
                    }),
                ),
            ),
            (
                json!({"view": {"vrp": [0,0,0], "vpn": [0,0,-1], "view_up": [0,1,0], "view_distance": 0,
                      "window": [-1, 1, -1, 1], "cop": [0, 0, 2], "front": 0, "back": 10}}),
                CameraSpec::View(ViewSpec {
                    vrp: Some(DVec3::ZERO),
                    vpn: Some(DVec3::NEG_Z),
                    view_up: Some(DVec3::Y),
                    view_distance: Some(0.0),
                    window: unit_window,
                    projection: vec![ViewProjection::Cop(v(0.0, 0.0, 2.0))],
                    front: Some(0.0),
                    back: Some(10.0),
                }),
            ),
            // fuzz/seeds/camera_parse/textbook.json
            (
                json!({"view":{"vrp":[0,0,0],"vpn":[0,0,-1],"view_up":[0,1,0],"view_distance":1,
                      "window":[-1,1,-1,1],"dop":[0,0,-1],"front":-10,"back":10}}),
                CameraSpec::View(ViewSpec {
                    vrp: Some(DVec3::ZERO),
                    vpn: Some(DVec3::NEG_Z),
                    view_up: Some(DVec3::Y),
                    view_distance: Some(1.0),
                    window: unit_window,
                    projection: vec![ViewProjection::Dop(DVec3::NEG_Z)],
                    front: Some(-10.0),
                    back: Some(10.0),
                }),
            ),
            // tests/stress/camera.rs: a scene 1e7 from the origin.
            (
                json!({"lookat": {"eye": far_away.to_array(), "center": (far_away - DVec3::Z).to_array()},
                       "perspective": {"fovy": 60, "aspect": w / h, "near": 0.5, "far": 100}}),
                iris(
                    look(far_away, far_away - DVec3::Z, None, None),
                    IrisProjection::Perspective(Perspective {
                        fovy: 60.0,
                        aspect: Aspect::Ratio(w / h),
                        near: 0.5,
                        far: 100.0,
                    }),
                ),
            ),
            // The unit tests: up and twist, the textbook's demo 2, the flight
            // simulator, oblique and isometric views.
            (
                json!({"lookat": {"eye": [0, 10, 0], "center": [0, 0, 0], "up": [1, 0, 0], "twist": 30},
                       "ortho2": [-1, 1, -1, 1]}),
                iris(
                    look(v(0.0, 10.0, 0.0), DVec3::ZERO, Some(DVec3::X), Some(30.0)),
                    IrisProjection::Ortho2(Ortho2 {
                        left: -1.0,
                        right: 1.0,
                        bottom: -1.0,
                        top: 1.0,
                    }),
                ),
            ),
            (
                json!({"view": {"vrp": [0, 100, -5], "vpn": [0, -100, -895],
                      "view_up": [0, 1, 0], "view_distance": 1, "window": [-t, t, -t, t],
                      "cop": [0, 100, -5], "front": 0, "back": 1000}}),
                CameraSpec::View(ViewSpec {
                    vrp: Some(v(0.0, 100.0, -5.0)),
                    vpn: Some(v(0.0, -100.0, -895.0)),
                    view_up: Some(DVec3::Y),
                    view_distance: Some(1.0),
                    window: Some(Window::from_array([-t, t, -t, t])),
                    projection: vec![ViewProjection::Cop(v(0.0, 100.0, -5.0))],
                    front: Some(0.0),
                    back: Some(1000.0),
                }),
            ),
            (
                json!({"view": {"vrp": pos.to_array(), "vpn": dir.to_array(),
                      "view_distance": 0, "window": [-0.5, 0.5, -0.5, 0.5],
                      "cop": (pos - 0.5 * dir).to_array(), "front": 0, "back": 1000}}),
                CameraSpec::View(ViewSpec {
                    vrp: Some(pos),
                    vpn: Some(dir),
                    view_distance: Some(0.0),
                    window: Some(Window::from_array([-0.5, 0.5, -0.5, 0.5])),
                    projection: vec![ViewProjection::Cop(pos - 0.5 * dir)],
                    front: Some(0.0),
                    back: Some(1000.0),
                    ..ViewSpec::default()
                }),
            ),
            (
                view(json!({"oblique": {"kind": "cabinet", "angle": 30}})),
                CameraSpec::View(ViewSpec {
                    window: unit_window,
                    projection: vec![ViewProjection::Oblique {
                        kind: ObliqueKind::Cabinet,
                        angle: Some(30.0),
                    }],
                    front: Some(-10.0),
                    back: Some(10.0),
                    ..ViewSpec::default()
                }),
            ),
            (
                view(json!({"oblique": {"kind": "cavalier"}, "view_up": [0.2, 1, 0.1]})),
                CameraSpec::View(ViewSpec {
                    view_up: Some(v(0.2, 1.0, 0.1)),
                    window: unit_window,
                    projection: vec![ViewProjection::Oblique {
                        kind: ObliqueKind::Cavalier,
                        angle: None,
                    }],
                    front: Some(-10.0),
                    back: Some(10.0),
                    ..ViewSpec::default()
                }),
            ),
            (
                json!({"view": {"vrp": [2, 2, 2], "isometric": true,
                      "window": [-1, 1, -1, 1], "front": 0, "back": 9}}),
                CameraSpec::View(ViewSpec {
                    vrp: Some(v(2.0, 2.0, 2.0)),
                    window: unit_window,
                    projection: vec![ViewProjection::Isometric],
                    front: Some(0.0),
                    back: Some(9.0),
                    ..ViewSpec::default()
                }),
            ),
        ];
        for (value, spec) in cases {
            assert_eq!(spec_from_json(&value).unwrap(), spec, "{value}");
            let by_json = cam(value.clone());
            let by_spec = Camera::from_spec(&spec).unwrap();
            assert!(same_bits(&by_json, &by_spec), "{value}");
        }
    }

    #[test]
    fn errors_name_origin_field_and_io_cause() {
        let e = Camera::from_json(&json!({"ortho2": [0, 0, 0, 1]}), "cam.json").unwrap_err();
        assert_eq!(
            e.to_string(),
            "cam.json: ortho2: left 0 equals right 0: zero-width"
        );
        let spec = spec_from_json(&json!({"ortho2": [0, 0, 0, 1]})).unwrap();
        let e = Camera::from_spec(&spec).unwrap_err();
        assert_eq!(e.to_string(), "ortho2: left 0 equals right 0: zero-width");
        assert_eq!(
            e.with_origin("here").to_string(),
            "here: ortho2: left 0 equals right 0: zero-width"
        );
        // As the tools print it: the I/O cause after the context.
        let e = Camera::load("/nonexistent/cam.json").unwrap_err();
        let io = std::fs::read_to_string("/nonexistent/cam.json").unwrap_err();
        assert_eq!(
            crate::test_util::chain(&e),
            format!("/nonexistent/cam.json: cannot read camera: {io}")
        );
        assert_eq!(format!("{e}"), "/nonexistent/cam.json: cannot read camera");
    }

    #[test]
    fn non_finite_specs_are_rejected_by_field() {
        let spec = CameraSpec::View(ViewSpec {
            window: Some(Window::from_array([-1.0, 1.0, -1.0, 1.0])),
            projection: vec![ViewProjection::Cop(DVec3::new(0.0, f64::NAN, 1.0))],
            front: Some(0.0),
            back: Some(1.0),
            ..ViewSpec::default()
        });
        let e = Camera::from_spec(&spec).unwrap_err();
        assert_eq!(e.to_string(), "view.cop: NaN is not a finite number");
        let e = Camera::try_ortho2(0.0, f64::INFINITY, 0.0, 1.0).unwrap_err();
        assert_eq!(e.to_string(), "ortho2: ortho2: inf is not a finite number");
    }
}
