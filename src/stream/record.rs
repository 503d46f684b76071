//! One record of the stream (docs/stream-format.md): its typed view ([`Record`]) and the
//! parsers of its fields (geometry, colour, pattern, texture coordinates,
//! quadric parameters). Kept apart from the reader so that the rules of what
//! a record may hold, and the wording of every field error, live in one place
//! whichever form (array, NDJSON, object definition) the record came in.

use super::fields::Fields;
use super::{ReadOptions, StreamError, MAX_VERTICES};
use crate::color::Rgb8;
use crate::geom::transform::Transform;
use crate::geom::Shape;
use crate::light::Shade;
use glam::DVec3;
use serde_json::Value;

/// How a pattern is fixed to a polygon (docs/stream-format.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum PatternMode {
    /// Fixed to the polygon: the thesis's `polcolorf3`.
    #[default]
    Object,
    /// Fixed to the screen: the IRIS hardware pattern.
    Screen,
    /// Placed by per-vertex texture coordinates.
    Uv,
}

/// The keys of a `"pattern"` object that place it (read here); its texture
/// state keys are [`crate::texture::state::KEYS`], read by the scene.
pub const PATTERN_KEYS: [&str; 6] = ["file", "mode", "incr", "rotate", "horz", "vert"];

/// A record's `"pattern"` object. Fields left out are `None`; the tool's
/// command-line defaults fill them in.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct PatternRef {
    /// Path of the `.pat`, as written in the record.
    pub file: Option<String>,
    /// How the pattern is fixed. Left to the tool when absent: `uv` for a
    /// record with `"uv"` and for quadrics, `object` otherwise.
    pub mode: Option<PatternMode>,
    /// Side of one texel in world units. Must be finite and > 0.
    pub incr: Option<f64>,
    /// Degrees, counter-clockwise, of +x from the edge vertex0→vertex1.
    pub rotate: Option<f64>,
    /// Shift of the pattern right, in texels.
    pub horz: Option<f64>,
    /// Shift of the pattern up, in texels.
    pub vert: Option<f64>,
}

/// One record: its typed view and the whole JSON object it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// 0-based position in the stream, for error messages.
    pub index: usize,
    /// The geometry: exactly one of `"vertices"`, `"rect"`, `"circle"`,
    /// `"arc"` or a quadric key ([`QUADRIC_KEYS`]), so a record is never
    /// ambiguous.
    pub shape: Shape,
    /// `"color"`: the flat colour, and with a pattern the intrinsic colour
    /// that scene-render's `--compose` combines with the texels. A record
    /// needs a colour, a pattern or a stripe.
    pub color: Option<Rgb8>,
    /// `"pattern"`: the texture pattern and its placement.
    pub pattern: Option<PatternRef>,
    /// Per-vertex texture coordinates in texels, one pair per vertex.
    pub uv: Option<Vec<[f64; 2]>>,
    /// `"normals"`: per-vertex surface normals (non-zero, any length), one
    /// per vertex of a polygon, for smooth lighting ([`crate::light`]).
    pub normals: Option<Vec<DVec3>>,
    /// `"shade"`: how a lit scene shades the record. Default value:
    /// [`Shade::Auto`].
    pub shade: Shade,
    /// The record's whole JSON object (including the fields above), unknown
    /// fields kept as written ([`Fields`]).
    pub fields: Fields,
}

impl Record {
    /// Builds the typed view of one JSON record. Its unknown fields are kept
    /// as serde_json writes them (a `Value` holds no text): the reader keeps
    /// them as written.
    pub fn from_value(index: usize, value: Value) -> Result<Record, StreamError> {
        match value {
            Value::Object(map) => Record::from_fields(index, map.into()),
            other => Err(not_an_object(index, &other)),
        }
    }

    /// Builds the typed view of a record's JSON object.
    pub fn from_fields(index: usize, fields: Fields) -> Result<Record, StreamError> {
        Record::from_fields_with(index, fields, &ReadOptions::default())
    }

    /// [`Record::from_fields`] as `options` ask: with
    /// [`ReadOptions::bare_records`], a polygon record needs no colour.
    pub fn from_fields_with(
        index: usize,
        fields: Fields,
        options: &ReadOptions,
    ) -> Result<Record, StreamError> {
        let e = |m: String| field_err(index, m);
        let present: Vec<&str> = GEOMETRY_KEYS
            .iter()
            .copied()
            .filter(|k| fields.contains_key(k))
            .collect();
        let shape = match present.as_slice() {
            ["vertices"] => Shape::Polygon(parse_vertices(&fields["vertices"]).map_err(e)?.into()),
            ["rect"] => Shape::Rect(number_array::<4>(&fields["rect"], "rect").map_err(e)?),
            ["circle"] => {
                let c = &fields["circle"];
                let center =
                    number_array::<2>(c.get("center").unwrap_or(&Value::Null), "circle.center")
                        .map_err(e)?;
                let radius = as_finite(c.get("radius").unwrap_or(&Value::Null), "circle.radius")
                    .map_err(e)?;
                if radius <= 0.0 {
                    return Err(field_err(
                        index,
                        format!("circle.radius: {radius} is not positive"),
                    ));
                }
                Shape::Circle { center, radius }
            }
            ["arc"] => {
                let a = &fields["arc"];
                let get = |k: &str| a.get(k).unwrap_or(&Value::Null);
                let center = number_array::<2>(get("center"), "arc.center").map_err(e)?;
                let radius = as_finite(get("radius"), "arc.radius").map_err(e)?;
                if radius <= 0.0 {
                    return Err(field_err(
                        index,
                        format!("arc.radius: {radius} is not positive"),
                    ));
                }
                Shape::Arc {
                    center,
                    radius,
                    start: as_finite(get("start"), "arc.start").map_err(e)?,
                    end: as_finite(get("end"), "arc.end").map_err(e)?,
                }
            }
            [k] if QUADRIC_KEYS.contains(k) => {
                let kind = QUADRIC_KEYS.into_iter().find(|q| q == k).expect("checked");
                Shape::Quadric(Box::new(
                    parse_quadric(kind, &fields[kind], fields.get("transform")).map_err(e)?,
                ))
            }
            [] => {
                return Err(field_err(
                    index,
                    "no geometry: expected one of \"vertices\", \"rect\", \"circle\", \"arc\", \"sphere\", \"cylinder\", \"cone\", \"disk\"",
                ))
            }
            many => {
                return Err(field_err(
                    index,
                    format!(
                        "several geometries ({}): expected exactly one",
                        many.join(", ")
                    ),
                ))
            }
        };
        let color = fields
            .get("color")
            .map(parse_color)
            .transpose()
            .map_err(e)?;
        let pattern = fields
            .get("pattern")
            .map(parse_pattern)
            .transpose()
            .map_err(e)?;
        let uv = match fields.get("uv") {
            None => None,
            Some(v) => {
                let Shape::Polygon(verts) = &shape else {
                    return Err(field_err(
                        index,
                        "uv: only polygons carry texture coordinates",
                    ));
                };
                let arr = v.as_array().ok_or_else(|| {
                    field_err(index, format!("uv: expected an array, found {}", short(v)))
                })?;
                if arr.len() != verts.len() {
                    return Err(field_err(
                        index,
                        format!(
                            "uv: {} pairs for {} vertices: expected one pair per vertex",
                            arr.len(),
                            verts.len()
                        ),
                    ));
                }
                let pair = |(i, p): (usize, &Value)| {
                    let uv = number_array::<2>(p, &format!("uv[{i}]"))?;
                    if uv[0].abs().max(uv[1].abs()) > MAX_UV {
                        return Err(format!(
                            "uv[{i}] {}: expected texture coordinates within ±{MAX_UV:e} texels \
                             (the texture map's arithmetic would overflow)",
                            short(p)
                        ));
                    }
                    Ok(uv)
                };
                Some(
                    arr.iter()
                        .enumerate()
                        .map(pair)
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(e)?,
                )
            }
        };
        let normals = match fields.get("normals") {
            None => None,
            Some(v) => {
                let Shape::Polygon(verts) = &shape else {
                    return Err(field_err(
                        index,
                        "normals: only polygons carry per-vertex normals (quadrics make their own)",
                    ));
                };
                Some(parse_normals(v, verts.len()).map_err(e)?)
            }
        };
        let shade = fields
            .get("shade")
            .map(Shade::from_json)
            .transpose()
            .map_err(e)?
            .unwrap_or_default();
        if let (Shape::Quadric(q), Some(p)) = (&shape, &pattern) {
            if p.mode == Some(PatternMode::Object) {
                return Err(field_err(
                    index,
                    format!(
                        "{}: pattern.mode \"object\": a quadric's pattern is placed by its texture coordinates: expected \"uv\" (the default for quadrics) or \"screen\"",
                        q.kind
                    ),
                ));
            }
        }
        // A stripe texture (crate::stripe::record) may carry its own colour
        // code, so it counts as colouring the record. A bare polygon is
        // coloured by the caller where it asked for one (`polyfill3
        // --pattern`); a quadric never is.
        let caller_colours = options.bare_records && !matches!(shape, Shape::Quadric(_));
        if color.is_none() && pattern.is_none() && !fields.contains_key("stripe") && !caller_colours
        {
            return Err(field_err(
                index,
                "no \"color\" and no \"pattern\": expected at least one",
            ));
        }
        Record {
            index,
            shape,
            color,
            pattern,
            uv,
            normals,
            shade,
            fields,
        }
        .with_own_transform()
    }

    /// Applies a polygon, rect, circle or arc record's own `"transform"`
    /// (docs/objects.md, Transforms) as an instance's transform moves it
    /// ([`super::transform_record`]): the record becomes a polygon in the
    /// space the transform leads to and the key is dropped, so that every
    /// tool (and `polyfill3`'s output) sees it already moved. A transform
    /// whose numbers vary per frame is kept, with the record in its own
    /// coordinates: only the renderer knows the frame. Quadrics keep theirs
    /// ([`parse_quadric`]).
    fn with_own_transform(self) -> Result<Record, StreamError> {
        let Some(json) = self.fields.get("transform") else {
            return Ok(self);
        };
        if matches!(self.shape, Shape::Quadric(_)) {
            return Ok(self);
        }
        let e = |m: String| field_err(self.index, m);
        // Frame 0 is checked for an animated one, so that a bad step is
        // reported when read, as for quadrics and instances.
        let transform = Transform::from_json(json).map_err(|t| e(t.to_string()))?;
        if Transform::is_animated(json) {
            return Ok(self);
        }
        let mut moved = super::objects::move_record(&self, &transform, self.index, "transform")
            .map_err(|m| e(format!("transform: {m}")))?;
        moved.fields.remove("transform");
        Ok(moved)
    }
}

/// The error of an element that is not a JSON object.
pub(super) fn not_an_object(index: usize, v: &Value) -> StreamError {
    field_err(index, format!("expected a JSON object, found {}", short(v)))
}

/// Parses `[r,g,b]` with integers 0..=255.
pub fn parse_color(v: &Value) -> Result<Rgb8, String> {
    let arr = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| format!("color: expected [r,g,b], found {}", short(v)))?;
    let mut c = [0u8; 3];
    for (o, x) in c.iter_mut().zip(arr) {
        *o = x
            .as_u64()
            .filter(|&n| n <= 255)
            .ok_or_else(|| format!("color: expected integers 0..=255, found {}", short(v)))?
            as u8;
    }
    Ok(Rgb8(c))
}

/// Parses `"normals"`: `count` vectors `[x, y, z]` of finite numbers, none
/// of length 0 (it could not be made unit).
fn parse_normals(v: &Value, count: usize) -> Result<Vec<DVec3>, String> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("normals: expected an array, found {}", short(v)))?;
    if arr.len() != count {
        return Err(format!(
            "normals: {} for {count} vertices: expected one per vertex",
            arr.len()
        ));
    }
    arr.iter()
        .enumerate()
        .map(|(i, n)| {
            let [x, y, z] = number_array::<3>(n, &format!("normals[{i}]"))?;
            let n = DVec3::new(x, y, z);
            if n.length() > 0.0 && n.length().is_finite() {
                Ok(n)
            } else {
                Err(format!("normals[{i}]: [{x}, {y}, {z}] has no direction"))
            }
        })
        .collect()
}

/// Parses `"vertices"`: 3 to [`MAX_VERTICES`] points of 2 or 3 finite
/// numbers (z = 0 for `[x,y]`), making a simple polygon
/// ([`crate::geom::simple`]: every tool refuses one that crosses or touches
/// itself, here, before any of them draws or cuts it).
fn parse_vertices(v: &Value) -> Result<Vec<DVec3>, String> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("vertices: expected an array, found {}", short(v)))?;
    if arr.len() < 3 {
        return Err(format!(
            "vertices: a polygon needs at least 3 vertices, found {}",
            arr.len()
        ));
    }
    if arr.len() > MAX_VERTICES {
        return Err(format!(
            "vertices: {} vertices is more than the limit of {MAX_VERTICES}",
            arr.len()
        ));
    }
    let verts = arr
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let xs = p
                .as_array()
                .filter(|a| a.len() == 2 || a.len() == 3)
                .ok_or_else(|| {
                    format!(
                        "vertices[{i}]: expected [x,y] or [x,y,z], found {}",
                        short(p)
                    )
                })?;
            let c = |k: usize| finite(&xs[k], || format!("vertices[{i}][{k}]"));
            Ok(DVec3::new(
                c(0)?,
                c(1)?,
                if xs.len() == 3 { c(2)? } else { 0.0 },
            ))
        })
        .collect::<Result<Vec<_>, String>>()?;
    crate::geom::simple::check(&verts).map_err(|c| format!("vertices: {c}"))?;
    Ok(verts)
}

/// Parses a `"pattern"` object; its fields are all optional.
fn parse_pattern(v: &Value) -> Result<PatternRef, String> {
    let obj = v
        .as_object()
        .ok_or_else(|| format!("pattern: expected an object, found {}", short(v)))?;
    let num = |k: &str| -> Result<Option<f64>, String> {
        obj.get(k)
            .map(|x| as_finite(x, &format!("pattern.{k}")))
            .transpose()
    };
    let mode = match obj.get("mode") {
        None => None,
        Some(Value::String(s)) => Some(match s.as_str() {
            "object" => PatternMode::Object,
            "screen" => PatternMode::Screen,
            "uv" => PatternMode::Uv,
            other => {
                return Err(format!(
                    "pattern.mode: `{other}` is not a mode: expected object, screen or uv"
                ))
            }
        }),
        Some(x) => {
            return Err(format!(
                "pattern.mode: expected a string, found {}",
                short(x)
            ))
        }
    };
    let file = match obj.get("file") {
        None => None,
        Some(Value::String(s)) => Some(s.clone()),
        Some(x) => {
            return Err(format!(
                "pattern.file: expected a path string, found {}",
                short(x)
            ))
        }
    };
    let incr = num("incr")?;
    if let Some(i) = incr {
        if i <= 0.0 {
            return Err(format!("pattern.incr: {i} is not positive"));
        }
    }
    Ok(PatternRef {
        file,
        mode,
        incr,
        rotate: num("rotate")?,
        horz: num("horz")?,
        vert: num("vert")?,
    })
}

/// The keys that give a record its geometry; exactly one must be present.
pub const GEOMETRY_KEYS: [&str; 8] = [
    "vertices", "rect", "circle", "arc", "sphere", "cylinder", "cone", "disk",
];

/// The record keys of the quadrics, GLU's names (`cone` is a cylinder with
/// top radius 0).
pub const QUADRIC_KEYS: [&str; 4] = ["sphere", "cylinder", "cone", "disk"];

/// Parses a quadric record's geometry: `kind` is its key, `v` its object,
/// `transform` the record's `"transform"` (frame 0 of an animated one).
/// GLU's parameter names: sphere `radius, slices, stacks`; cylinder `base,
/// top, height, slices, stacks`; cone `base, height, slices, stacks`; disk
/// `inner, outer, slices, loops`; any of them may add `"repeat": [ns, nt]`.
fn parse_quadric(
    kind: &'static str,
    v: &Value,
    transform: Option<&Value>,
) -> Result<crate::geom::quadric::QuadricShape, String> {
    use crate::geom::quadric::{
        Quadric, QuadricShape, MAX_REPEAT, MAX_SEGMENTS, MIN_SLICES, MIN_SPHERE_STACKS,
    };
    let obj = v
        .as_object()
        .ok_or_else(|| format!("{kind}: expected an object, found {}", short(v)))?;
    let (params, stack_key, min_stacks): (&[&str], &str, u32) = match kind {
        "sphere" => (&["radius"], "stacks", MIN_SPHERE_STACKS),
        "cylinder" => (&["base", "top", "height"], "stacks", 1),
        "cone" => (&["base", "height"], "stacks", 1),
        _ => (&["inner", "outer"], "loops", 1),
    };
    for k in obj.keys() {
        let known =
            params.contains(&k.as_str()) || ["slices", stack_key, "repeat"].contains(&k.as_str());
        if !known {
            return Err(format!(
                "{kind}.{k}: not a {kind} parameter: expected {}, slices, {stack_key}, repeat",
                params.join(", ")
            ));
        }
    }
    let num = |k: &str| -> Result<f64, String> {
        let x = obj.get(k).ok_or_else(|| format!("{kind}.{k} is missing"))?;
        as_finite(x, &format!("{kind}.{k}"))
    };
    let count = |k: &str, min: u32| -> Result<Option<u32>, String> {
        let Some(x) = obj.get(k) else { return Ok(None) };
        match x.as_u64() {
            Some(n) if (min as u64..=MAX_SEGMENTS as u64).contains(&n) => Ok(Some(n as u32)),
            _ => Err(format!(
                "{kind}.{k} {}: expected a whole number from {min} to {MAX_SEGMENTS}",
                short(x)
            )),
        }
    };
    let quadric = match kind {
        "sphere" => Quadric::Sphere {
            radius: num("radius")?,
        },
        "cylinder" => Quadric::Cylinder {
            base: num("base")?,
            top: num("top")?,
            height: num("height")?,
        },
        "cone" => Quadric::Cylinder {
            base: num("base")?,
            top: 0.0,
            height: num("height")?,
        },
        _ => Quadric::Disk {
            inner: obj.get("inner").map_or(Ok(0.0), |_| num("inner"))?,
            outer: num("outer")?,
        },
    };
    quadric.check().map_err(|e| e.for_kind(kind).to_string())?;
    let repeat = match obj.get("repeat") {
        None => [1.0, 1.0],
        Some(r) => {
            let [a, b] = number_array::<2>(r, &format!("{kind}.repeat"))?;
            if !(a > 0.0 && b > 0.0) {
                return Err(format!(
                    "{kind}.repeat [{a}, {b}]: expected two positive numbers"
                ));
            }
            if a.max(b) > MAX_REPEAT {
                return Err(format!(
                    "{kind}.repeat {}: expected at most {MAX_REPEAT:e} copies of the pattern \
                     (texture coordinates would overflow)",
                    short(r)
                ));
            }
            [a, b]
        }
    };
    let transform = transform
        .map(Transform::from_json)
        .transpose()
        .map_err(|e| e.to_string())?
        .unwrap_or_default();
    Ok(QuadricShape {
        quadric,
        kind,
        slices: count("slices", MIN_SLICES)?,
        stacks: count(stack_key, min_stacks)?,
        repeat,
        transform,
    })
}

/// A record error as [`Record::from_value`] returns it: the record's index
/// and the message; the reader names the input.
pub(super) fn field_err(index: usize, msg: impl Into<String>) -> StreamError {
    StreamError::in_record(index, msg)
}

/// A finite number, naming the field `what` on error.
fn as_finite(v: &Value, what: &str) -> Result<f64, String> {
    finite(v, || what.to_string())
}

/// A finite number, naming the field only on error: the label is built lazily
/// because this runs for every coordinate of every record.
fn finite(v: &Value, what: impl FnOnce() -> String) -> Result<f64, String> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        Some(_) => Err(format!("{} is not finite", what())),
        None => Err(format!("{}: expected a number, found {}", what(), short(v))),
    }
}

/// A JSON value shortened for an error message.
pub(super) fn short(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 40 {
        format!(
            "{}...",
            &s[..s.char_indices().nth(37).map_or(s.len(), |(i, _)| i)]
        )
    } else {
        s
    }
}

/// An array of exactly `N` finite numbers, `what` naming the field on error.
fn number_array<const N: usize>(v: &Value, what: &str) -> Result<[f64; N], String> {
    let arr = v.as_array().ok_or_else(|| {
        format!(
            "{what}: expected an array of {N} numbers, found {}",
            short(v)
        )
    })?;
    if arr.len() != N {
        return Err(format!("{what}: expected {N} numbers, found {}", arr.len()));
    }
    let mut out = [0.0; N];
    for (i, (o, x)) in out.iter_mut().zip(arr).enumerate() {
        *o = finite(x, || format!("{what}[{i}]"))?;
    }
    Ok(out)
}

/// The largest texture coordinate a record's `"uv"` may give, in texels:
/// [`MAX_REPEAT`](crate::geom::quadric::MAX_REPEAT)'s bound, for the same reason. Coordinates of 1e307 made
/// the screen fit of the texture map infinite, and scene-render dropped
/// the polygon as if it were edge-on, without an error.
pub const MAX_UV: f64 = crate::geom::quadric::MAX_REPEAT;

#[cfg(test)]
mod tests {
    use super::super::testing::{err, read_all};
    use super::*;

    #[test]
    fn a_quadric_repeat_whose_texture_coordinates_would_overflow_is_refused() {
        assert_eq!(
            err(
                r#"{"vertices":[[0,0],[10,0],[10,10]],"color":[1,2,3],"uv":[[0,0],[1e307,0],[0,1]]}"#
            ),
            "s.json: record 0: uv[1] [1e+307,0]: expected texture coordinates within ±1e100 \
             texels (the texture map's arithmetic would overflow)"
        );
        assert!(read_all(
            r#"{"vertices":[[0,0],[10,0],[10,10]],"color":[1,2,3],"uv":[[0,0],[-1e100,0],[0,1e100]]}"#
        )
        .is_ok());
        assert_eq!(
            err(r#"{"sphere": {"radius": 10, "repeat": [1e308, 1e308]}, "color": [0,0,0]}"#),
            "s.json: record 0: sphere.repeat [1e+308,1e+308]: expected at most 1e100 copies \
             of the pattern (texture coordinates would overflow)"
        );
        assert!(
            err(r#"{"disk": {"outer": 1, "repeat": [1, 2e100]}, "color": [0,0,0]}"#)
                .contains("disk.repeat [1,2e+100]: expected at most 1e100")
        );
        let ok =
            read_all(r#"{"sphere": {"radius": 1, "repeat": [1e100, 1e30]}, "color": [0,0,0]}"#);
        assert!(ok.is_ok(), "{ok:?}");
    }

    #[test]
    fn a_stripe_texture_colours_a_record_by_itself() {
        let recs = read_all(r#"{"vertices":[[0,0],[1,0],[0,1]],"stripe":{"code":3}}"#).unwrap();
        assert_eq!(recs[0].color, None);
        assert!(recs[0].fields.contains_key("stripe"));
    }

    #[test]
    fn bare_records_are_read_only_where_the_caller_colours_them() {
        let fields = |text: &str| {
            Fields::from(serde_json::from_str::<serde_json::Map<String, Value>>(text).unwrap())
        };
        let bare = ReadOptions { bare_records: true };
        let polygon = r#"{"vertices":[[0,0],[1,0],[0,1]]}"#;
        let rec = Record::from_fields_with(0, fields(polygon), &bare).unwrap();
        assert_eq!((rec.color, rec.pattern), (None, None));
        assert!(Record::from_fields_with(0, fields(r#"{"rect":[0,0,1,1]}"#), &bare).is_ok());
        let refused = |r: Result<Record, StreamError>| r.unwrap_err().message;
        let sphere = r#"{"sphere":{"radius":1}}"#;
        assert_eq!(
            refused(Record::from_fields_with(0, fields(sphere), &bare)),
            "no \"color\" and no \"pattern\": expected at least one"
        );
        assert_eq!(
            refused(Record::from_fields(0, fields(polygon))),
            "no \"color\" and no \"pattern\": expected at least one"
        );
    }

    #[test]
    fn bad_records_name_the_record_and_the_field() {
        assert_eq!(
            err(r#"{"vertices":[[0,0],[1,0]],"color":[0,0,0]}"#),
            "s.json: record 0: vertices: a polygon needs at least 3 vertices, found 2"
        );
        assert!(err(r#"{"vertices":[[0,0],[1,0],[0,"a"]],"color":[0,0,0]}"#)
            .contains("record 0: vertices[2][1]: expected a number"));
        assert!(err(r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[0,0,256]}"#)
            .contains("color: expected integers 0..=255"));
        assert!(
            err(r#"{"vertices":[[0,0],[1,0],[0,1]]}"#).contains("no \"color\" and no \"pattern\"")
        );
        assert!(
            err(r#"{"rect":[0,0,1,1],"circle":{},"color":[0,0,0]}"#).contains("several geometries")
        );
        assert!(
            err(r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"incr":0}}"#)
                .contains("pattern.incr: 0 is not positive")
        );
        assert!(
            err(r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"mode":"sky"}}"#)
                .contains("`sky` is not a mode")
        );
        assert!(
            err(r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{},"uv":[[0,0]]}"#)
                .contains("uv: 1 pairs for 3 vertices")
        );
        assert!(
            err(r#"{"circle":{"center":[0,0],"radius":-1},"color":[0,0,0]}"#)
                .contains("circle.radius: -1 is not positive")
        );
        assert!(err("[1]").contains("record 0: expected a JSON object, found 1"));
        // A bow-tie, 2D or 3D, on the fast path (colour only) or not.
        for rec in [
            r#"{"vertices":[[0,0],[1,1],[1,0],[0,1]],"color":[0,0,0]}"#,
            r#"{"vertices":[[0,0,5],[1,1,5],[1,0,5],[0,1,5]],"pattern":{"file":"a.pat"}}"#,
        ] {
            assert_eq!(
                err(rec),
                "s.json: record 0: vertices: the polygon crosses itself: \
                 edge 0 (vertex 0 to 1) crosses edge 2 (vertex 2 to 3)"
            );
        }
    }

    #[test]
    fn quadric_records_parse_with_glu_names_and_defaults() {
        use crate::geom::quadric::Quadric;
        let recs = read_all(
            r#"{"sphere": {"radius": 2, "slices": 8}, "color": [1,2,3], "transform": {"translate": [1, 0, 0]}}
               {"cone": {"base": 3, "height": 4}, "pattern": {"file": "p.pat"}}
               {"disk": {"outer": 5, "loops": 2, "repeat": [2, 1]}, "color": [0,0,0]}"#,
        )
        .unwrap();
        let q = |r: &Record| match &r.shape {
            Shape::Quadric(q) => (**q).clone(),
            other => panic!("{other:?}"),
        };
        let sphere = q(&recs[0]);
        assert_eq!(sphere.quadric, Quadric::Sphere { radius: 2.0 });
        assert_eq!((sphere.slices, sphere.stacks), (Some(8), None));
        assert_eq!(sphere.transform.apply(DVec3::ZERO), DVec3::X);
        let cone = q(&recs[1]);
        assert_eq!(
            cone.quadric,
            Quadric::Cylinder {
                base: 3.0,
                top: 0.0,
                height: 4.0
            }
        );
        assert_eq!(cone.kind, "cone");
        let disk = q(&recs[2]);
        assert_eq!(
            disk.quadric,
            Quadric::Disk {
                inner: 0.0,
                outer: 5.0
            }
        );
        assert_eq!((disk.stacks, disk.repeat), (Some(2), [2.0, 1.0]));
        assert!(
            err(r#"{"sphere": {"radius": 1}, "color": [0,0,0], "uv": [[0,0]]}"#)
                .contains("uv: only polygons carry texture coordinates")
        );
        assert!(
            err(r#"{"sphere": {"radius": 1}, "rect": [0,0,1,1], "color": [0,0,0]}"#)
                .contains("several geometries (rect, sphere)")
        );
        assert!(err(r#"{"sphere": {}, "color": [0,0,0]}"#).contains("sphere.radius is missing"));
        assert!(
            err(r#"{"sphere": {"radius": 1, "repeat": [0, 1]}, "color": [0,0,0]}"#)
                .contains("sphere.repeat [0, 1]: expected two positive numbers")
        );
        assert!(
            err(r#"{"sphere": {"radius": 1, "slices": 4.5}, "color": [0,0,0]}"#)
                .contains("sphere.slices 4.5: expected a whole number")
        );
    }
}
