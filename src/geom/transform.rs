//! 3D transformations (Harrington ch. 8, Alg. 8.7-8.11 and "Rotation about an
//! arbitrary axis"): translation, scaling, rotation about x, y, z and about any
//! axis through any point, and 4x4 matrices.
//!
//! The textbook multiplies ROW vectors, `[x y z 1] · T1 · T2 ...`, so a list of
//! steps is applied in the order it is written: the first step moves the
//! points first. In JSON a transform is that list:
//!
//! ```json
//! "transform": [{"rotate": 90, "axis": "y"}, {"translate": [0, 0, -500]}]
//! ```
//!
//! rotates by 90° about y, then translates: IRIS's `translate(0,0,-500);
//! rotate(900,'Y'); callobj(...)` (IRIS post-multiplies column-style, so its
//! calls read in the reverse order). Rotations are right-handed (x: y into z,
//! y: z into x, z: x into y), angles in degrees. `{"matrix": [[..4..] x4]}` is
//! in the textbook's row-vector layout: the translation is the last row, and the
//! last column must be `0 0 0 1` (affine).
//!
//! Internally a transform is a glam column-vector matrix (`M_col = M_rowᵀ`).
//!
//! For animation (`scene-render --frames`), any number of a step may be
//! `{"start": a, "step": s}`: at frame k it is `a + s*k`. The thesis's demo 2
//! turns its pyramid this way, `rot` growing 10 degrees a frame (App. C):
//! `{"rotate": {"start": 0, "step": 10}, "axis": "y"}`. Read without a frame,
//! such a transform is its frame 0.

use crate::math;
use glam::{DMat3, DMat4, DVec3, DVec4};
use serde_json::Value;
use std::fmt;

/// A transform whose 3x3 part has |det| below this, relative to the cube of its
/// largest entry, squashes space onto a plane or line: it cannot be undone and
/// makes polygons degenerate, so it is rejected as singular.
pub const SINGULAR_RELATIVE_DET: f64 = 1e-12;
/// An arbitrary rotation axis shorter than this is no direction.
pub const MIN_AXIS_LENGTH: f64 = 1e-300;
/// How far a matrix may be from a similarity (rotation times uniform scale),
/// relative, and still count as one: object-mode patterns survive only those.
pub const SIMILARITY_TOLERANCE: f64 = 1e-9;

/// An invertible affine 3D transform.
///
/// Guarantees: every entry is finite; the last row (column-vector form) is
/// `0 0 0 1`; the linear part is not singular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform(DMat4);

/// Why a transform was refused, naming the step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TransformError(pub String);

impl fmt::Display for TransformError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for TransformError {}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    /// The transform that moves nothing: a record's or instance's default.
    pub const IDENTITY: Transform = Transform(DMat4::IDENTITY);

    /// Alg. 8.8 TRANSLATE-3.
    pub fn translate(t: DVec3) -> Transform {
        Transform(DMat4::from_translation(t))
    }

    /// Scaling about the origin; zero factors are singular and refused.
    pub fn scale(s: DVec3) -> Result<Transform, TransformError> {
        Transform::checked(DMat4::from_scale(s))
    }

    /// Alg. 8.9-8.11: right-handed rotation by `degrees` about a unit axis.
    /// The axis is normalized by [`crate::vector::direction`], which scales a very
    /// long or short axis first (`[1e200, 0, 0]` squared to infinity and had
    /// "no direction"); an ordinary axis gives the same bits as `axis / len`.
    pub fn rotate_axis(axis: DVec3, degrees: f64) -> Result<Transform, TransformError> {
        let unit = crate::vector::direction(axis)
            .filter(|_| crate::vector::length(axis) > MIN_AXIS_LENGTH);
        let Some(unit) = unit else {
            return Err(TransformError(format!(
                "rotation axis [{}, {}, {}] has no direction",
                axis.x, axis.y, axis.z
            )));
        };
        Ok(Transform(axis_angle(unit, degrees)))
    }

    /// Rotation about the line through `point` along `axis`: translate the
    /// axis to the origin, rotate, translate back (the textbook's steps (b)-(h),
    /// with the two alignment rotations folded into one axis-angle rotation).
    pub fn rotate_about(
        point: DVec3,
        axis: DVec3,
        degrees: f64,
    ) -> Result<Transform, TransformError> {
        let r = Transform::rotate_axis(axis, degrees)?;
        Ok(Transform::translate(-point)
            .then(r)
            .then(Transform::translate(point)))
    }

    /// From a matrix in the textbook's row-vector layout (`[x y z 1] · M`).
    pub fn from_row_matrix(rows: [[f64; 4]; 4]) -> Result<Transform, TransformError> {
        if rows[0][3] != 0.0 || rows[1][3] != 0.0 || rows[2][3] != 0.0 || rows[3][3] != 1.0 {
            return Err(TransformError(format!(
                "matrix: the last column is [{}, {}, {}, {}], expected [0, 0, 0, 1] (an affine transform)",
                rows[0][3], rows[1][3], rows[2][3], rows[3][3]
            )));
        }
        // Row-vector M is the transpose of the column-vector matrix; glam's
        // from_cols_array_2d takes columns, which are exactly the rows of M.
        Transform::checked(DMat4::from_cols_array_2d(&rows))
    }

    fn checked(m: DMat4) -> Result<Transform, TransformError> {
        if !m.to_cols_array().iter().all(|x| x.is_finite()) {
            return Err(TransformError("a matrix entry is not finite".into()));
        }
        let lin = DMat3::from_mat4(m);
        let scale = lin
            .to_cols_array()
            .iter()
            .fold(0.0f64, |a, &x| a.max(x.abs()));
        let det = lin.determinant();
        let cube = scale.powi(3);
        if !det.is_finite() || !cube.is_finite() {
            return Err(TransformError(format!(
                "overflows: entries up to {} make its determinant beyond the range of \
                 numbers (about 1e308), so no point it moves could be drawn",
                crate::text::readable(scale)
            )));
        }
        if scale == 0.0 || det.abs() <= SINGULAR_RELATIVE_DET * cube {
            // Where the bound itself has left the normal numbers, a
            // determinant at or under it may only have underflowed: a
            // uniform scale of 1e-110 is no more singular than 1, and was
            // called "determinant 0" (a hostile-input review).
            if scale > 0.0
                && SINGULAR_RELATIVE_DET * cube < f64::MIN_POSITIVE
                && !flat_when_scaled(&lin, scale)
            {
                return Err(TransformError(format!(
                    "underflows: entries no larger than {} put its determinant ({}) below \
                     the range of numbers (about 1e-308), where whether it squashes space \
                     flat cannot be told",
                    crate::text::readable(scale),
                    crate::text::readable(det)
                )));
            }
            // The largest entry is said: a determinant of 1e100 is flat
            // beside entries of 1e100 (a stretch of 1e100 along one axis).
            return Err(TransformError(format!(
                "singular: determinant {} squashes space flat (at most 1e-12 of the cube of \
                 its largest entry, {}), so polygons would vanish",
                crate::text::readable(det),
                crate::text::readable(scale)
            )));
        }
        Ok(Transform(m))
    }

    /// This transform followed by `next` (row-vector order: `self · next`).
    pub fn then(self, next: Transform) -> Transform {
        Transform(next.0 * self.0)
    }

    /// [`Transform::then`], refused as a single step is when the product
    /// overflows or is singular: each of two nested instances' translations
    /// by 1e308 is finite, but not their sum, and the instance's polygons
    /// were dropped without a word (a hostile-input review).
    pub fn then_checked(self, next: Transform) -> Result<Transform, TransformError> {
        Transform::checked(next.0 * self.0)
    }

    /// The column-vector matrix.
    pub fn matrix(&self) -> DMat4 {
        self.0
    }

    /// The point `p` moved by the transform (an affine map: w = 1, no divide).
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.0.transform_point3(p)
    }

    /// A surface normal moved with the transform, unit length: by the
    /// inverse transpose of the linear part, which keeps it perpendicular to
    /// the moved surface under any non-singular transform (a plain
    /// transform of the vector would not under uneven scaling). A mirroring
    /// transform keeps the normal on the side the surface's own normal
    /// gave, as it keeps the listed winding.
    pub fn apply_normal(&self, n: DVec3) -> DVec3 {
        let lin = DMat3::from_mat4(self.0);
        (lin.inverse().transpose() * n).normalize_or_zero()
    }

    /// The matrix in the textbook's row-vector layout.
    pub fn row_matrix(&self) -> [[f64; 4]; 4] {
        self.0.to_cols_array_2d()
    }

    /// The uniform scale factor when the linear part is a similarity (a
    /// rotation or reflection times one scale), else `None`.
    pub fn similarity_scale(&self) -> Option<f64> {
        let lin = DMat3::from_mat4(self.0);
        let s = math::cbrt(lin.determinant().abs());
        let gram = lin.transpose() * lin / (s * s);
        let off = (gram - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |a, &x| a.max(x.abs()));
        (off <= SIMILARITY_TOLERANCE).then_some(s)
    }

    /// True when the transform mirrors space (negative determinant): windings
    /// seen from the front reverse.
    pub fn mirrors(&self) -> bool {
        DMat3::from_mat4(self.0).determinant() < 0.0
    }

    /// Parses a JSON transform: a list of steps applied in order (or one step).
    pub fn from_json(v: &Value) -> Result<Transform, TransformError> {
        Transform::from_json_at(v, 0)
    }

    /// Whether a JSON transform has numbers that vary per frame.
    pub fn is_animated(v: &Value) -> bool {
        match v {
            Value::Object(m) => {
                (m.contains_key("start") && m.contains_key("step"))
                    || m.values().any(Transform::is_animated)
            }
            Value::Array(a) => a.iter().any(Transform::is_animated),
            _ => false,
        }
    }

    /// Parses a JSON transform at animation frame `frame`.
    pub fn from_json_at(v: &Value, frame: u64) -> Result<Transform, TransformError> {
        let steps: Vec<&Value> = match v {
            Value::Array(a) => a.iter().collect(),
            Value::Object(_) => vec![v],
            other => {
                return Err(TransformError(format!(
                    "transform: expected a list of steps, found {other}"
                )))
            }
        };
        let mut t = Transform::IDENTITY;
        for (i, step) in steps.iter().enumerate() {
            let s = parse_step(step, frame)
                .map_err(|e| TransformError(format!("transform step {i}: {e}")))?;
            t = t.then(s);
        }
        if steps.len() > 1 {
            // Steps each fine may be singular together: scaling y by 1e-7,
            // a turn, then scaling y by 1e-7 again squashes space flat.
            t = Transform::checked(t.0)
                .map_err(|e| TransformError(format!("transform steps together: {e}")))?;
        }
        Ok(t)
    }
}

fn vec3(v: &Value, what: &str, frame: u64) -> Result<DVec3, String> {
    let a = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| format!("{what}: expected [x, y, z], found {v}"))?;
    let mut out = [0.0; 3];
    for (o, x) in out.iter_mut().zip(a) {
        *o = number(x, what, frame)
            .map_err(|_| format!("{what}: expected finite numbers, found {v}"))?;
    }
    Ok(DVec3::from_array(out))
}

/// A number, or `{"start": a, "step": s}` evaluated at `frame` as `a + s*frame`.
fn number(v: &Value, what: &str, frame: u64) -> Result<f64, String> {
    let bad =
        || format!("{what}: expected a finite number or {{\"start\": a, \"step\": s}}, found {v}");
    let x = match v {
        Value::Object(m) => {
            if m.len() != 2 {
                return Err(bad());
            }
            let (a, s) = (
                m.get("start").and_then(Value::as_f64),
                m.get("step").and_then(Value::as_f64),
            );
            let (Some(a), Some(s)) = (a, s) else {
                return Err(bad());
            };
            a + s * frame as f64
        }
        _ => v.as_f64().ok_or_else(bad)?,
    };
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("{what}: {x} at frame {frame} is not finite"))
    }
}

fn parse_step(v: &Value, frame: u64) -> Result<Transform, String> {
    let obj = v.as_object().ok_or_else(|| {
        format!("expected an object such as {{\"translate\": [x,y,z]}}, found {v}")
    })?;
    let allowed: &[&str] = if obj.contains_key("translate") {
        &["translate"]
    } else if obj.contains_key("scale") {
        &["scale", "about"]
    } else if obj.contains_key("rotate") {
        &["rotate", "axis", "point"]
    } else if obj.contains_key("matrix") {
        &["matrix"]
    } else {
        return Err(format!(
            "expected one of \"translate\", \"scale\", \"rotate\", \"matrix\", found {v}"
        ));
    };
    if let Some(k) = obj.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(format!("unexpected key \"{k}\" beside \"{}\"", allowed[0]));
    }
    if let Some(t) = obj.get("translate") {
        return Ok(Transform::translate(vec3(t, "translate", frame)?));
    }
    if let Some(s) = obj.get("scale") {
        let factors = match s {
            Value::Array(_) => vec3(s, "scale", frame)?,
            _ => DVec3::splat(number(s, "scale", frame)?),
        };
        let scale = Transform::scale(factors).map_err(|e| format!("scale: {e}"))?;
        return Ok(match obj.get("about") {
            Some(p) => {
                let p = vec3(p, "about", frame)?;
                Transform::translate(-p)
                    .then(scale)
                    .then(Transform::translate(p))
            }
            None => scale,
        });
    }
    if let Some(r) = obj.get("rotate") {
        let degrees = number(r, "rotate", frame)?;
        let axis = match obj.get("axis") {
            None => return Err("rotate: needs \"axis\": \"x\", \"y\", \"z\" or [x, y, z]".into()),
            Some(Value::String(s)) => match s.to_ascii_lowercase().as_str() {
                "x" => DVec3::X,
                "y" => DVec3::Y,
                "z" => DVec3::Z,
                other => return Err(format!("axis: `{other}` is not x, y, z or [x, y, z]")),
            },
            Some(a) => vec3(a, "axis", frame)?,
        };
        let point = obj
            .get("point")
            .map(|p| vec3(p, "point", frame))
            .transpose()?;
        let r = match point {
            Some(p) => Transform::rotate_about(p, axis, degrees),
            None => Transform::rotate_axis(axis, degrees),
        };
        return r.map_err(|e| format!("rotate: {e}"));
    }
    let m = &obj["matrix"];
    let rows = m
        .as_array()
        .filter(|r| r.len() == 4)
        .ok_or_else(|| format!("matrix: expected 4 rows of 4 numbers, found {m}"))?;
    let mut out = [[0.0; 4]; 4];
    for (i, row) in rows.iter().enumerate() {
        let r = row
            .as_array()
            .filter(|r| r.len() == 4)
            .ok_or_else(|| format!("matrix row {i}: expected 4 numbers, found {row}"))?;
        for (j, x) in r.iter().enumerate() {
            out[i][j] = number(x, &format!("matrix[{i}][{j}]"), frame)?;
        }
    }
    Transform::from_row_matrix(out).map_err(|e| e.to_string())
}

/// Whether the linear part `lin` (largest entry `scale`) squashes space
/// flat by the relative rule, measured on `lin` scaled by the power of two
/// at or below `scale` (exact), where its determinant neither underflows
/// nor overflows: [`Transform::checked`] tells a genuinely flat tiny
/// transform (`scale [1e-99, 1e-99, 0]`) from one whose determinant only
/// underflowed (`scale 1e-110`). Entries that the scaling makes subnormal
/// are below 2^-1022 of the largest, too small to matter to the rule.
fn flat_when_scaled(lin: &DMat3, scale: f64) -> bool {
    if scale < f64::MIN_POSITIVE {
        return false; // Subnormal entries alone: nothing can be told.
    }
    let pow2 = f64::from_bits(scale.to_bits() & 0x7FF0_0000_0000_0000);
    let scaled = *lin * (1.0 / pow2);
    scaled.determinant().abs() <= SINGULAR_RELATIVE_DET * (scale / pow2).powi(3)
}

/// The rotation by `degrees` about the unit `axis`: glam's
/// `DMat4::from_axis_angle` (Rodrigues' formula, the same operations in the
/// same order), with the sine and cosine of [`math::sin_cos_degrees`], so
/// that a quarter turn about a coordinate axis only swaps coordinates and
/// their signs (a point turned onto an axis lands on it, not 6.1e-17 of its
/// distance off) and a turn more or less changes nothing.
fn axis_angle(axis: DVec3, degrees: f64) -> DMat4 {
    let (sin, cos) = math::sin_cos_degrees(degrees);
    let axis_sin = axis * sin;
    let axis_sq = axis * axis;
    let omc = 1.0 - cos;
    let xyomc = axis.x * axis.y * omc;
    let xzomc = axis.x * axis.z * omc;
    let yzomc = axis.y * axis.z * omc;
    DMat4::from_cols(
        DVec4::new(
            axis_sq.x * omc + cos,
            xyomc + axis_sin.z,
            xzomc - axis_sin.y,
            0.0,
        ),
        DVec4::new(
            xyomc - axis_sin.z,
            axis_sq.y * omc + cos,
            yzomc + axis_sin.x,
            0.0,
        ),
        DVec4::new(
            xzomc + axis_sin.y,
            yzomc - axis_sin.x,
            axis_sq.z * omc + cos,
            0.0,
        ),
        DVec4::W,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9 * (1.0 + b.length())
    }

    #[test]
    fn very_long_and_short_rotation_axes_have_a_direction() {
        // [1e200, 0, 0]'s squared length overflowed: "has no direction".
        let r = |axis: [f64; 3]| {
            Transform::from_json(&json!({"rotate": 90, "axis": axis})).map(|t| t.apply(DVec3::Y))
        };
        for axis in [[1e200, 0.0, 0.0], [1e300, 0.0, 0.0], [1e-200, 0.0, 0.0]] {
            assert!(close(r(axis).unwrap(), DVec3::Z), "{axis:?}");
        }
        let x = |axis: [f64; 3]| {
            Transform::from_json(&json!({"rotate": 120, "axis": axis}))
                .unwrap()
                .apply(DVec3::X)
        };
        // 120 degrees about the diagonal takes x to y, however long the axis.
        for k in [1e300, 1e200, 1e-200] {
            assert!(close(x([k, k, k]), DVec3::Y), "{k}");
        }
        // An ordinary axis: the same matrix as before, bit for bit.
        let axis = DVec3::new(0.3, -2.0, 5.0);
        assert_eq!(
            Transform::rotate_axis(axis, 37.0).unwrap().0,
            DMat4::from_axis_angle(axis / axis.length(), 37f64.to_radians())
        );
        assert!(r([0.0, 0.0, 0.0]).is_err());
        assert!(r([1e-310, 0.0, 0.0]).is_err(), "below MIN_AXIS_LENGTH");
    }

    #[test]
    fn quarter_turns_are_exact_and_a_turn_more_changes_nothing() {
        let m = |degrees: f64, axis: &str| {
            Transform::from_json(&json!({"rotate": degrees, "axis": axis}))
                .unwrap()
                .0
        };
        // About y, 90 degrees: z to x, x to -z, to the bit.
        let p = DVec3::new(100.0, 0.0, 100.0);
        assert_eq!(
            Transform(m(90.0, "y")).apply(p),
            DVec3::new(100.0, 0.0, -100.0)
        );
        for axis in ["x", "y", "z"] {
            for d in [90.0, 180.0, -90.0, 270.0] {
                assert!(
                    m(d, axis).to_cols_array().iter().all(|v| v.fract() == 0.0),
                    "{d} about {axis}"
                );
            }
            assert_eq!(m(450.0, axis), m(90.0, axis));
            assert_eq!(m(-270.0, axis), m(90.0, axis));
            assert_eq!(m(37.0 + 720.0, axis), m(37.0, axis));
        }
    }

    #[test]
    fn rotations_are_right_handed_like_alg_8_9_to_8_11() {
        let r = |axis: &str, p: DVec3| {
            Transform::from_json(&json!({"rotate": 90, "axis": axis}))
                .unwrap()
                .apply(p)
        };
        // x: y into z; y: z into x; z: x into y.
        assert!(close(r("x", DVec3::Y), DVec3::Z));
        assert!(close(r("y", DVec3::Z), DVec3::X));
        assert!(close(r("z", DVec3::X), DVec3::Y));
    }

    #[test]
    fn steps_apply_in_the_order_written_like_row_vectors() {
        let t = Transform::from_json(&json!([
            {"rotate": 90, "axis": "y"},
            {"translate": [0, 0, -500]}
        ]))
        .unwrap();
        // (100,0,0) rotates to (0,0,-100), then moves to (0,0,-600).
        assert!(close(
            t.apply(DVec3::new(100.0, 0.0, 0.0)),
            DVec3::new(0.0, 0.0, -600.0)
        ));
        // The row-vector matrix has the translation in its last row.
        let m = Transform::from_json(&json!({"translate": [1, 2, 3]}))
            .unwrap()
            .row_matrix();
        assert_eq!(m[3], [1.0, 2.0, 3.0, 1.0]);
    }

    #[test]
    fn matrix_step_uses_the_textbook_layout() {
        let t =
            Transform::from_json(&json!({"matrix": [[0,1,0,0],[-1,0,0,0],[0,0,1,0],[5,6,7,1]]}))
                .unwrap();
        // [1 0 0 1] · M = [0 1 0 0] + [5 6 7 1]: rotate x into y, then translate.
        assert!(close(t.apply(DVec3::X), DVec3::new(5.0, 7.0, 7.0)));
    }

    #[test]
    fn rotation_about_an_arbitrary_axis_through_a_point_fixes_the_axis() {
        let p = DVec3::new(3.0, -2.0, 7.0);
        let axis = DVec3::new(1.0, 2.0, 2.0);
        let t = Transform::rotate_about(p, axis, 37.0).unwrap();
        assert!(close(t.apply(p), p));
        assert!(close(t.apply(p + axis * 4.0), p + axis * 4.0));
        // A full turn is the identity; three 120° turns about (1,1,1) cycle the axes.
        let full = Transform::rotate_about(p, axis, 360.0).unwrap();
        assert!(close(full.apply(DVec3::ONE), DVec3::ONE));
        let third = Transform::rotate_axis(DVec3::ONE, 120.0).unwrap();
        assert!(close(third.apply(DVec3::X), DVec3::Y));
    }

    #[test]
    fn scale_about_a_point_and_similarity() {
        let t = Transform::from_json(&json!({"scale": 2, "about": [1, 1, 1]})).unwrap();
        assert!(close(
            t.apply(DVec3::new(2.0, 1.0, 1.0)),
            DVec3::new(3.0, 1.0, 1.0)
        ));
        assert!((t.similarity_scale().unwrap() - 2.0).abs() < 1e-12);
        let r = Transform::rotate_axis(DVec3::new(1.0, 2.0, 3.0), 33.0).unwrap();
        assert!((r.similarity_scale().unwrap() - 1.0).abs() < 1e-12);
        let squash = Transform::from_json(&json!({"scale": [1, 2, 1]})).unwrap();
        assert_eq!(squash.similarity_scale(), None);
        let mirror = Transform::from_json(&json!({"scale": [-1, 1, 1]})).unwrap();
        assert!(mirror.mirrors());
    }

    #[test]
    fn numbers_may_grow_by_a_step_per_frame() {
        let v =
            json!([{"rotate": {"start": 0, "step": 10}, "axis": "y"}, {"translate": [0, 0, -500]}]);
        assert!(Transform::is_animated(&v));
        assert!(!Transform::is_animated(&json!({"rotate": 10, "axis": "y"})));
        // Frame 9 turns 90 degrees: (100,0,0) to (0,0,-100), then to z = -600.
        let t = Transform::from_json_at(&v, 9).unwrap();
        assert!(close(
            t.apply(DVec3::new(100.0, 0.0, 0.0)),
            DVec3::new(0.0, 0.0, -600.0)
        ));
        assert_eq!(
            Transform::from_json(&v).unwrap(),
            Transform::from_json_at(&v, 0).unwrap()
        );
        // A scale that passes through zero is singular at that frame only.
        let s = json!({"scale": {"start": 2, "step": -1}});
        assert!(Transform::from_json_at(&s, 1).is_ok());
        assert!(Transform::from_json_at(&s, 2)
            .unwrap_err()
            .to_string()
            .contains("singular"));
        let e = Transform::from_json(&json!({"rotate": {"start": 0}, "axis": "y"}));
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("expected a finite number or"));
    }

    #[test]
    fn singular_and_non_finite_transforms_are_errors_naming_the_step() {
        let e = |v: Value| Transform::from_json(&v).unwrap_err().to_string();
        assert!(e(json!([{"translate": [1, 2, 3]}, {"scale": [1, 0, 1]}]))
            .starts_with("transform step 1: scale: singular"));
        assert!(
            e(json!({"matrix": [[1,0,0,0],[0,1,0,0],[1,1,0,0],[0,0,0,1]]})).contains("singular")
        );
        assert!(
            e(json!({"matrix": [[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})).contains("last column")
        );
        assert!(e(json!({"rotate": 10, "axis": [0, 0, 0]})).contains("has no direction"));
        assert!(e(json!({"rotate": 10})).contains("needs \"axis\""));
        assert!(e(json!({"rotate": 10, "axis": "w"})).contains("`w` is not x, y, z"));
        assert!(e(json!({"translate": [1, 2]})).contains("expected [x, y, z]"));
        assert!(e(json!({"spin": 3})).contains("expected one of"));
        assert!(e(json!({"translate": [1, 2, 3], "scale": 2})).contains("unexpected key"));
        // Underflow is named as such, not as singular; a stretch says the
        // entry its determinant is measured against.
        let tiny = e(json!({"scale": 1e-110}));
        assert!(
            tiny.contains("underflows: entries no larger than 1e-110"),
            "{tiny}"
        );
        assert!(e(json!({"scale": 1e-200})).contains("underflows"));
        // Tiny and flat is flat (a review): a zero axis.
        let flat = e(json!({"scale": [1e-99, 1e-99, 0]}));
        assert!(
            flat.contains("singular: determinant 0 squashes space flat"),
            "{flat}"
        );
        let stretch = e(json!({"scale": [1e100, 1, 1]}));
        assert!(
            stretch.contains(
                "singular: determinant 1e100 squashes space flat (at most 1e-12 of the cube of its largest entry, 1e100)"
            ),
            "{stretch}"
        );
        // A uniform scale whose bound is still a normal number is taken.
        assert!(Transform::from_json(&json!({"scale": 1e-100})).is_ok());
        // An overflowing scale is named as such, not as singular.
        let big = e(json!({"scale": 1e200}));
        assert!(big.contains("overflows: entries up to 1e200"), "{big}");
        assert!(e(json!("x")).starts_with("transform: expected a list"));
    }
}
