//! The polygon stream (SPEC §2): one JSON array of records, or NDJSON.
//!
//! Records are read one at a time whichever form the input takes, so memory does
//! not grow with the number of records. Every record keeps its full JSON object
//! ([`Record::fields`]) so tools that forward records pass unknown fields through
//! unchanged; the typed view ([`Record::shape`], [`Record::pattern`], ...) is
//! what the geometry and the renderer use.

use crate::color::Rgb8;
use crate::geom::transform::Transform;
use crate::geom::Shape;
use glam::DVec3;
use serde::de::{Deserializer as _, SeqAccess, Visitor};
use serde_json::{Map, Value};
use std::fmt;
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod plain;

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
        Quadric, QuadricShape, MAX_SEGMENTS, MIN_SLICES, MIN_SPHERE_STACKS,
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
    quadric.check().map_err(|e| {
        // The check names a cone's radii as the cylinder's it is.
        if kind == "cone" {
            e.replace("cylinder", "cone")
        } else {
            e
        }
    })?;
    let repeat = match obj.get("repeat") {
        None => [1.0, 1.0],
        Some(r) => {
            let [a, b] = number_array::<2>(r, &format!("{kind}.repeat"))?;
            if !(a > 0.0 && b > 0.0) {
                return Err(format!(
                    "{kind}.repeat [{a}, {b}]: expected two positive numbers"
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

/// How a pattern is fixed to a polygon (SPEC §2).
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

/// A record's `"pattern"` object. Fields left out are `None`; the tool's
/// command-line defaults fill them in.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct PatternRef {
    /// Path of the `.pat`, as written in the record.
    pub file: Option<String>,
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
    pub shape: Shape,
    pub color: Option<Rgb8>,
    pub pattern: Option<PatternRef>,
    /// Per-vertex texture coordinates in texels, one pair per vertex.
    pub uv: Option<Vec<[f64; 2]>>,
    /// The record exactly as read (including the fields above).
    pub fields: Fields,
}

/// A record's whole JSON object, as a map (`Deref`). The general reader
/// builds the map as it reads; the fast path for plain NDJSON polygons
/// ([`plain`]) keeps the record's line instead and parses it on first use,
/// so a tool that never looks (scene-render) never pays for the map.
#[derive(Clone)]
pub struct Fields {
    /// The record's JSON text, when the map is still to be made from it.
    line: Option<Box<[u8]>>,
    map: OnceLock<Map<String, Value>>,
}

impl Fields {
    /// Fields to be parsed from `line` when first asked for. The line must be
    /// one JSON object that parses as `Value` (the fast path checks that:
    /// it parses every field it does not read as `Value`, and its numbers
    /// parse as `Value` numbers by the same code).
    fn from_line(line: &[u8]) -> Fields {
        Fields {
            line: Some(line.into()),
            map: OnceLock::new(),
        }
    }
}

impl From<Map<String, Value>> for Fields {
    fn from(map: Map<String, Value>) -> Fields {
        Fields {
            line: None,
            map: OnceLock::from(map),
        }
    }
}

impl std::ops::Deref for Fields {
    type Target = Map<String, Value>;
    fn deref(&self) -> &Map<String, Value> {
        self.map.get_or_init(|| {
            let line = self.line.as_deref().unwrap_or_default();
            serde_json::from_slice(line)
                .expect("the fast path accepts only lines that parse as a JSON object")
        })
    }
}

impl<'a> IntoIterator for &'a Fields {
    type Item = (&'a String, &'a Value);
    type IntoIter = serde_json::map::Iter<'a>;
    fn into_iter(self) -> Self::IntoIter {
        (**self).iter()
    }
}

impl fmt::Debug for Fields {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        (**self).fmt(f)
    }
}

impl PartialEq for Fields {
    fn eq(&self, other: &Fields) -> bool {
        **self == **other
    }
}

/// A stream error, naming the input and the record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StreamError {
    pub source: String,
    /// 0-based record index, when the error belongs to one record.
    pub record: Option<usize>,
    pub message: String,
}

impl fmt::Display for StreamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.record {
            Some(i) => write!(f, "{}: record {i}: {}", self.source, self.message),
            None => write!(f, "{}: {}", self.source, self.message),
        }
    }
}

impl std::error::Error for StreamError {}

/// The most vertices one polygon may have: 2^24 (16.7 million). Past that a
/// record is certainly a mistake, and the limit keeps memory bounded.
pub const MAX_VERTICES: usize = 1 << 24;

fn field_err(index: usize, msg: impl Into<String>) -> (usize, String) {
    (index, msg.into())
}

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
fn short(v: &Value) -> String {
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
    arr.iter()
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
        .collect()
}

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

impl Record {
    /// Builds the typed view of one JSON record.
    pub fn from_value(index: usize, value: Value) -> Result<Record, (usize, String)> {
        let Value::Object(fields) = value else {
            return Err(field_err(
                index,
                format!("expected a JSON object, found {}", short(&value)),
            ));
        };
        let e = |m: String| field_err(index, m);
        let keys = [
            "vertices", "rect", "circle", "arc", "sphere", "cylinder", "cone", "disk",
        ];
        let present: Vec<&str> = keys
            .iter()
            .copied()
            .filter(|k| fields.contains_key(*k))
            .collect();
        let shape = match present.as_slice() {
            ["vertices"] => Shape::Polygon(parse_vertices(&fields["vertices"]).map_err(e)?),
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
                Some(
                    arr.iter()
                        .enumerate()
                        .map(|(i, p)| number_array::<2>(p, &format!("uv[{i}]")))
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(e)?,
                )
            }
        };
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
        // code, so it counts as colouring the record.
        if color.is_none() && pattern.is_none() && !fields.contains_key("stripe") {
            return Err(field_err(
                index,
                "no \"color\" and no \"pattern\": expected at least one",
            ));
        }
        Ok(Record {
            index,
            shape,
            color,
            pattern,
            uv,
            fields: fields.into(),
        })
    }
}

/// One element of the stream: a drawable record, a named object definition, or
/// an instance of an object (the thesis's `makeobj`/`callobj`, Fig. 5.1).
///
/// ```json
/// {"object": "face", "records": [{"vertices": [...], "pattern": {...}}]}
/// {"instance": "face", "transform": [{"rotate": 90, "axis": "y"}]}
/// ```
///
/// An object must be defined before it is placed, once; its records may place
/// instances of objects defined earlier, so instances nest but never form a
/// cycle. Unknown fields are kept on all three.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    Record(Record),
    Object(ObjectDef),
    Instance(Instance),
}

/// A named group of items, drawn only through instances.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDef {
    pub index: usize,
    pub name: String,
    pub items: Vec<Item>,
    /// The definition's JSON object, including `"records"`.
    pub fields: Map<String, Value>,
}

/// An object placed with a transform.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    pub index: usize,
    pub object: String,
    /// Applied to the object's coordinates (identity when absent).
    pub transform: Transform,
    pub fields: Map<String, Value>,
}

impl ObjectDef {
    /// What [`Objects::define`] needs to check a definition (its name, index
    /// and the instances inside it), without its records: for tools that
    /// keep the records in their own form.
    pub fn skeleton(&self) -> ObjectDef {
        ObjectDef {
            index: self.index,
            name: self.name.clone(),
            items: self
                .items
                .iter()
                .filter(|it| !matches!(it, Item::Record(_)))
                .cloned()
                .collect(),
            fields: Map::new(),
        }
    }
}

impl Item {
    /// Builds the typed view of one JSON stream element.
    pub fn from_value(index: usize, value: Value) -> Result<Item, (usize, String)> {
        match &value {
            Value::Object(m) if m.contains_key("object") => {
                let Value::Object(fields) = value else {
                    unreachable!()
                };
                let name = match &fields["object"] {
                    Value::String(s) if !s.is_empty() => s.clone(),
                    other => {
                        return Err(field_err(
                            index,
                            format!("object: expected a non-empty name, found {}", short(other)),
                        ))
                    }
                };
                let records = fields
                    .get("records")
                    .and_then(Value::as_array)
                    .ok_or_else(|| {
                        field_err(
                            index,
                            format!("object `{name}`: expected \"records\": [...]"),
                        )
                    })?;
                let items = records
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        Item::from_value(index, v.clone()).map_err(|(_, m)| {
                            field_err(index, format!("object `{name}` records[{i}]: {m}"))
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Item::Object(ObjectDef {
                    index,
                    name,
                    items,
                    fields,
                }))
            }
            Value::Object(m) if m.contains_key("instance") => {
                let Value::Object(fields) = value else {
                    unreachable!()
                };
                let object = match &fields["instance"] {
                    Value::String(s) if !s.is_empty() => s.clone(),
                    other => {
                        return Err(field_err(
                            index,
                            format!("instance: expected an object name, found {}", short(other)),
                        ))
                    }
                };
                let transform = fields
                    .get("transform")
                    .map(Transform::from_json)
                    .transpose()
                    .map_err(|e| field_err(index, format!("instance of `{object}`: {e}")))?
                    .unwrap_or_default();
                Ok(Item::Instance(Instance {
                    index,
                    object,
                    transform,
                    fields,
                }))
            }
            _ => Record::from_value(index, value).map(Item::Record),
        }
    }
}

/// Tolerance, relative to the radius, of the polygon that replaces a circle or
/// arc moved by an instance transform: 1e-4 keeps the chord error below a
/// hundredth of a pixel for any circle under 100 pixels across.
pub const INSTANCE_CURVE_TOLERANCE: f64 = 1e-4;

/// The object definitions seen so far, and the expansion of instances.
#[derive(Default)]
pub struct Objects {
    defs: std::collections::HashMap<String, std::rc::Rc<ObjectDef>>,
}

impl Objects {
    /// Records a definition after checking its name is new and every instance
    /// inside it names an object defined before it.
    pub fn define(&mut self, def: ObjectDef) -> Result<(), StreamError> {
        let err = |m: String| StreamError {
            source: String::new(),
            record: Some(def.index),
            message: m,
        };
        if self.defs.contains_key(&def.name) {
            return Err(err(format!("object `{}` is defined twice", def.name)));
        }
        fn check(objs: &Objects, name: &str, items: &[Item]) -> Result<(), String> {
            for it in items {
                match it {
                    Item::Instance(i) if i.object == name => {
                        return Err(format!(
                            "object `{name}` places an instance of itself: a cycle"
                        ))
                    }
                    Item::Instance(i) if !objs.defs.contains_key(&i.object) => {
                        return Err(format!(
                            "object `{name}` places unknown object `{}` (define it first)",
                            i.object
                        ))
                    }
                    Item::Object(o) => {
                        return Err(format!(
                            "object `{name}` defines object `{}` inside it: definitions are top-level only",
                            o.name
                        ))
                    }
                    _ => {}
                }
            }
            Ok(())
        }
        check(self, &def.name, &def.items).map_err(err)?;
        self.defs.insert(def.name.clone(), std::rc::Rc::new(def));
        Ok(())
    }

    /// Checks that a top-level instance names an object defined before it.
    pub fn check_instance(&self, inst: &Instance) -> Result<(), StreamError> {
        if self.defs.contains_key(&inst.object) {
            return Ok(());
        }
        Err(StreamError {
            source: String::new(),
            record: Some(inst.index),
            message: format!(
                "instance of unknown object `{}` (define it first)",
                inst.object
            ),
        })
    }

    pub fn get(&self, name: &str) -> Option<&ObjectDef> {
        self.defs.get(name).map(|d| &**d)
    }

    /// Feeds one stream item through: records go to `each`, definitions are
    /// stored, instances are expanded into moved records.
    pub fn expand(
        &mut self,
        item: Item,
        each: &mut dyn FnMut(Record) -> anyhow::Result<()>,
    ) -> anyhow::Result<()> {
        match item {
            Item::Record(r) => each(r),
            Item::Object(def) => Ok(self.define(def)?),
            Item::Instance(inst) => {
                self.check_instance(&inst)?;
                let def = self.defs[&inst.object].clone();
                self.place(&def, inst.transform, inst.index, each)
            }
        }
    }

    fn place(
        &self,
        def: &ObjectDef,
        transform: Transform,
        index: usize,
        each: &mut dyn FnMut(Record) -> anyhow::Result<()>,
    ) -> anyhow::Result<()> {
        for item in &def.items {
            match item {
                Item::Record(r) => {
                    let moved =
                        transform_record(r, &transform, index).map_err(|m| StreamError {
                            source: String::new(),
                            record: Some(index),
                            message: format!("object `{}`: {m}", def.name),
                        })?;
                    each(moved)?;
                }
                Item::Instance(inner) => {
                    let inner_def = &self.defs[&inner.object];
                    // The inner placement applies first, then this one.
                    self.place(inner_def, inner.transform.then(transform), index, each)?;
                }
                Item::Object(_) => unreachable!("rejected by define"),
            }
        }
        Ok(())
    }
}

/// A record moved by `t`: vertices transformed (2D records become polygons),
/// an object-mode pattern's `incr` scaled with the transform, which must then
/// be a similarity. Windings are kept as listed, so a mirroring transform turns
/// the record's front face away (as in GL).
pub fn transform_record(r: &Record, t: &Transform, index: usize) -> Result<Record, String> {
    if let Shape::Quadric(q) = &r.shape {
        // A quadric stays a quadric: its own placement is followed by `t`,
        // and its JSON "transform" becomes the combined matrix.
        let mut moved = (**q).clone();
        moved.transform = q.transform.then(*t);
        let mut fields: Map<String, Value> = (*r.fields).clone();
        fields.insert(
            "transform".into(),
            serde_json::json!({"matrix": moved.transform.row_matrix()}),
        );
        return Ok(Record {
            index,
            shape: Shape::Quadric(Box::new(moved)),
            fields: fields.into(),
            ..r.clone()
        });
    }
    let tol = match r.shape {
        Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => {
            radius * INSTANCE_CURVE_TOLERANCE
        }
        _ => 0.0,
    };
    let verts: Vec<DVec3> = crate::geom::outline(&r.shape, tol)
        .into_iter()
        .map(|p| t.apply(p))
        .collect();
    if !verts.iter().all(|p| p.is_finite()) {
        return Err("the transform moves a vertex out of the finite numbers".into());
    }
    let mut fields = Map::clone(&r.fields);
    for k in ["rect", "circle", "arc"] {
        fields.remove(k);
    }
    fields.insert(
        "vertices".into(),
        Value::Array(
            verts
                .iter()
                .map(|p| serde_json::json!([p.x, p.y, p.z]))
                .collect(),
        ),
    );
    let mut pattern = r.pattern.clone();
    if let Some(p) = pattern.as_mut() {
        let object_mode = r.uv.is_none() && p.mode.unwrap_or_default() == PatternMode::Object;
        if object_mode {
            let s = t.similarity_scale().ok_or_else(|| {
                "the instance transform stretches unevenly, which an object-mode pattern cannot follow: partition the object with polyfill3 first".to_string()
            })?;
            if (s - 1.0).abs() > crate::geom::transform::SIMILARITY_TOLERANCE {
                let incr = p.incr.ok_or_else(|| {
                    format!("the instance transform scales by {s}: give the pattern an explicit \"incr\" so it can scale too")
                })?;
                p.incr = Some(incr * s);
                if let Some(Value::Object(pf)) = fields.get_mut("pattern") {
                    pf.insert("incr".into(), serde_json::json!(incr * s));
                }
            }
        }
    }
    Ok(Record {
        index,
        shape: Shape::Polygon(verts),
        color: r.color,
        pattern,
        uv: r.uv.clone(),
        fields: fields.into(),
    })
}

/// A quadric record as plain triangle records, for tools that forward
/// polygons (`polyfill3`): each triangle keeps the record's other fields,
/// gets `"vertices"` (the record's transform applied) and, when the record
/// has a pattern, `"uv"` in texels of a `pattern_size` pattern with the
/// pattern's mode set to `"uv"` (see [`crate::geom::quadric::QuadricShape::texel_triangles`]).
/// `tolerance` is the chord tolerance in the record's space, for the slices
/// and stacks it leaves out. Not a quadric: `None`.
pub fn quadric_triangles(
    r: &Record,
    tolerance: f64,
    pattern_size: Option<u32>,
) -> Option<Result<Vec<Map<String, Value>>, String>> {
    let Shape::Quadric(q) = &r.shape else {
        return None;
    };
    // Chords in the quadric's own units: the transform stretches them by at
    // most its largest column length (an upper bound on its largest
    // singular value within sqrt(3)).
    let m = q.transform.matrix();
    let stretch = [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|c| c.truncate().length())
        .fold(0.0, f64::max);
    let tris = match q.texel_triangles(tolerance / stretch, pattern_size.unwrap_or(1)) {
        Ok(t) => t,
        Err(e) => return Some(Err(e)),
    };
    let mut base: Map<String, Value> = (*r.fields).clone();
    base.remove(q.kind);
    base.remove("transform");
    let screen = matches!(
        r.pattern.as_ref().and_then(|p| p.mode),
        Some(PatternMode::Screen)
    );
    let uv = pattern_size.is_some() && !screen;
    if let (true, Some(Value::Object(p))) = (uv, base.get_mut("pattern")) {
        p.insert("mode".into(), Value::from("uv"));
    }
    Some(Ok(tris
        .iter()
        .map(|t| {
            let mut f = base.clone();
            f.insert(
                "vertices".into(),
                Value::Array(
                    t.v.iter()
                        .map(|p| serde_json::json!([p.x, p.y, p.z]))
                        .collect(),
                ),
            );
            if uv {
                f.insert(
                    "uv".into(),
                    Value::Array(t.uv.iter().map(|c| serde_json::json!(c)).collect()),
                );
            }
            f
        })
        .collect()))
}

/// Where relative pattern paths resolve (SPEC §2): the stream file's directory,
/// or the current directory for standard input.
pub fn base_dir(input_name: &str) -> PathBuf {
    if input_name == crate::io::STDIO {
        PathBuf::from(".")
    } else {
        Path::new(input_name)
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
    }
}

/// Resolves a pattern path against a stream's base directory.
pub fn resolve(base: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

/// Reads records one at a time from a JSON array or an NDJSON stream, calling
/// `each` for every drawable record in order. Object definitions are kept and
/// their instances expanded here, each record moved by its instance's
/// transform (see [`Objects`]); a tool that must keep objects intact uses
/// [`for_each_item`] instead. Stops at the first error, which names the input
/// and the record. Memory stays bounded by the largest single record plus the
/// object definitions.
pub fn for_each_record<R: BufRead>(
    reader: R,
    source: &str,
    mut each: impl FnMut(Record) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let mut objects = Objects::default();
    for_each_item(reader, source, |item| {
        objects
            .expand(item, &mut each)
            .map_err(|e| match e.downcast::<StreamError>() {
                Ok(mut se) => {
                    se.source = source.to_string();
                    anyhow::Error::new(se)
                }
                Err(other) => other,
            })
    })
}

/// Like [`for_each_record`], but hands over object definitions and instances
/// as they are, for tools that forward them.
pub fn for_each_item<R: BufRead>(
    mut reader: R,
    source: &str,
    mut each: impl FnMut(Item) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let stream_err = |record: Option<usize>, message: String| StreamError {
        source: source.to_string(),
        record,
        message,
    };
    // Peek at the first non-blank byte to tell an array from NDJSON.
    let first = loop {
        let buf = reader
            .fill_buf()
            .map_err(|e| stream_err(None, e.to_string()))?;
        if buf.is_empty() {
            break None;
        }
        match buf.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(i) => {
                let b = buf[i];
                reader.consume(i);
                break Some(b);
            }
            None => {
                let n = buf.len();
                reader.consume(n);
            }
        }
    };
    let mut index = 0usize;
    let mut handle = |value: Parsed, index: &mut usize| -> anyhow::Result<()> {
        let item = match value {
            Parsed::Value(value) => {
                Item::from_value(*index, value).map_err(|(i, m)| stream_err(Some(i), m))?
            }
            Parsed::Item(item) => item,
        };
        *index += 1;
        each(item)
    };
    match first {
        None => Ok(()),
        Some(b'[') => {
            let mut de = serde_json::Deserializer::from_reader(reader);
            let mut failure: Option<anyhow::Error> = None;
            let visitor = ArrayVisitor {
                each: &mut |v: Value| -> bool {
                    match handle(Parsed::Value(v), &mut index) {
                        Ok(()) => true,
                        Err(e) => {
                            failure = Some(e);
                            false
                        }
                    }
                },
            };
            let res = (&mut de).deserialize_seq(visitor);
            if let Some(f) = failure {
                return Err(f);
            }
            res.map_err(|e| stream_err(Some(index), json_message(&e)))?;
            de.end()
                .map_err(|e| stream_err(None, format!("after the array: {}", json_message(&e))))?;
            Ok(())
        }
        Some(_) => {
            // NDJSON is read a line at a time and each line parsed from
            // memory: serde_json reading an `io::Read` goes byte by byte, and
            // a plain polygon on a line of its own skips the `Value` tree too
            // (`plain`). A line that is not one whole JSON value (a value
            // spread over lines, two on one line, a syntax error) hands the
            // rest of the input, from the start of that line, to serde_json's
            // own stream reader, behind as many newlines as were read before
            // it so that its error positions are those of the whole input.
            let mut line = Vec::new();
            let mut newlines = 0u64;
            loop {
                line.clear();
                if let Err(e) = reader.read_until(b'\n', &mut line) {
                    // serde_json words a read error as the error itself.
                    return Err(stream_err(Some(index), format!("invalid JSON: {e}")).into());
                }
                if line.is_empty() {
                    return Ok(());
                }
                let body = trim_json_whitespace(&line);
                if !body.is_empty() {
                    if let Some(rec) = plain::record(body, index) {
                        handle(Parsed::Item(Item::Record(rec)), &mut index)?;
                    } else if let Ok(v) = serde_json::from_slice::<Value>(body) {
                        handle(Parsed::Value(v), &mut index)?;
                    } else {
                        use std::io::Read as _;
                        let rest = std::io::repeat(b'\n')
                            .take(newlines)
                            .chain(&line[..])
                            .chain(reader);
                        let de = serde_json::Deserializer::from_reader(rest).into_iter::<Value>();
                        for v in de {
                            let v = v.map_err(|e| stream_err(Some(index), json_message(&e)))?;
                            handle(Parsed::Value(v), &mut index)?;
                        }
                        return Ok(());
                    }
                }
                if line.last() == Some(&b'\n') {
                    newlines += 1;
                }
            }
        }
    }
}

/// A stream element as the readers hand it on: parsed JSON, or an item the
/// NDJSON fast path has already typed. Moved once per record straight into
/// the handler, so its size costs nothing, where boxing the item would cost
/// an allocation per record.
#[allow(clippy::large_enum_variant)]
enum Parsed {
    Value(Value),
    Item(Item),
}

/// `s` without JSON's whitespace (space, tab, newline, carriage return; RFC
/// 8259 §2) at either end.
fn trim_json_whitespace(s: &[u8]) -> &[u8] {
    let ws = |b: &u8| matches!(b, b' ' | b'\t' | b'\n' | b'\r');
    let start = s.iter().position(|b| !ws(b)).unwrap_or(s.len());
    let end = s.iter().rposition(|b| !ws(b)).map_or(start, |i| i + 1);
    &s[start..end]
}

/// serde_json's message with its position, phrased for a user.
fn json_message(e: &serde_json::Error) -> String {
    format!("invalid JSON: {e}")
}

/// Streams the elements of a JSON array to a callback without collecting them.
struct ArrayVisitor<'a> {
    each: &'a mut dyn FnMut(Value) -> bool,
}

impl<'de> Visitor<'de> for ArrayVisitor<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of records")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while let Some(v) = seq.next_element::<Value>()? {
            if !(self.each)(v) {
                // Stop early: the caller reports its own error.
                return Ok(());
            }
        }
        Ok(())
    }
}

/// Writes one record as a line of NDJSON (the default output form).
pub fn write_ndjson<W: Write>(w: &mut W, fields: &Map<String, Value>) -> std::io::Result<()> {
    serde_json::to_writer(&mut *w, fields)?;
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(text: &str) -> anyhow::Result<Vec<Record>> {
        let mut out = Vec::new();
        for_each_record(text.as_bytes(), "s.json", |r| {
            out.push(r);
            Ok(())
        })?;
        Ok(out)
    }

    fn err(text: &str) -> String {
        format!("{:#}", read_all(text).unwrap_err())
    }

    #[test]
    fn array_and_ndjson_give_the_same_records() {
        let a = r#"[{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"id":"a"},
                    {"rect":[0,0,2,2],"color":[0,0,0]}]"#;
        let n = "{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3],\"id\":\"a\"}\n{\"rect\":[0,0,2,2],\"color\":[0,0,0]}\n";
        assert_eq!(read_all(a).unwrap(), read_all(n).unwrap());
        let r = read_all(a).unwrap();
        assert_eq!(r[0].fields["id"], "a");
        assert_eq!(r[1].index, 1);
        assert!(matches!(r[0].shape, Shape::Polygon(ref v) if v[2] == DVec3::new(0.0, 1.0, 0.0)));
    }

    #[test]
    fn ndjson_syntax_errors_keep_the_positions_of_the_whole_input() {
        // Plain lines, a blank line, a value spread over lines, then an error
        // on line 6: the line reader hands over to serde_json's own stream
        // reader, whose message must name the same line and column as when
        // it read the whole input itself.
        let text = "  {\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n\n\
                    {\"rect\":[0,0,1,1],\n \"color\":[1,2,3]}\n\
                    {\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n\
                    {\"vertices\": [[0,0]] x\n";
        let mut seen = 0;
        let whole = serde_json::Deserializer::from_str(text.trim_start())
            .into_iter::<Value>()
            .find_map(|v| match v {
                Ok(_) => {
                    seen += 1;
                    None
                }
                Err(e) => Some(e),
            })
            .unwrap();
        assert_eq!(seen, 3);
        assert_eq!(whole.line(), 6);
        assert_eq!(
            err(text),
            format!("s.json: record 3: {}", json_message(&whole))
        );
    }

    #[test]
    fn empty_input_is_an_empty_stream() {
        assert!(read_all("").unwrap().is_empty());
        assert!(read_all(" \n ").unwrap().is_empty());
        assert!(read_all("[]").unwrap().is_empty());
    }

    #[test]
    fn a_stripe_texture_colours_a_record_by_itself() {
        let recs = read_all(r#"{"vertices":[[0,0],[1,0],[0,1]],"stripe":{"code":3}}"#).unwrap();
        assert_eq!(recs[0].color, None);
        assert!(recs[0].fields.contains_key("stripe"));
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
    }

    #[test]
    fn nan_huge_numbers_truncation_and_deep_nesting_are_errors_not_panics() {
        assert!(
            err(r#"{"vertices":[[NaN,0],[1,0],[0,1]],"color":[0,0,0]}"#).contains("invalid JSON")
        );
        assert!(
            err(r#"{"vertices":[[1e999,0],[1,0],[0,1]],"color":[0,0,0]}"#).contains("record 0")
        );
        assert!(err(r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[0,0,0]"#).contains("invalid JSON"));
        assert!(err(r#"[{"vertices":[[0,0],[1,0],[0,1]],"color":[0,0,0]}"#)
            .contains("record 1: invalid JSON"));
        let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
        assert!(err(&deep).contains("invalid JSON"));
        let deep_obj = format!("{{\"x\":{}1{}}}", "[".repeat(100_000), "]".repeat(100_000));
        assert!(err(&deep_obj).contains("record 0: invalid JSON"));
    }

    #[test]
    fn an_error_in_the_callback_stops_the_array_stream() {
        let text = r#"[{"rect":[0,0,1,1],"color":[0,0,0]},{"rect":[0,0,1,1],"color":[0,0,0]}]"#;
        let mut seen = 0;
        let r = for_each_record(text.as_bytes(), "s", |_| {
            seen += 1;
            anyhow::bail!("stop")
        });
        assert_eq!(seen, 1);
        assert_eq!(r.unwrap_err().to_string(), "stop");
    }

    #[test]
    fn instances_expand_moved_and_nested_in_order() {
        let text = r#"
            {"object": "tri", "records": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "color": [1,2,3], "id": "t"}]}
            {"object": "pair", "records": [
                {"instance": "tri"},
                {"instance": "tri", "transform": {"translate": [10, 0, 0]}}]}
            {"instance": "pair", "transform": [{"rotate": 90, "axis": "z"}], "id": "p"}
            {"rect": [0,0,1,1], "color": [0,0,0]}"#;
        let recs = read_all(text).unwrap();
        assert_eq!(recs.len(), 3);
        let v = |r: &Record| match &r.shape {
            Shape::Polygon(v) => v.clone(),
            _ => panic!(),
        };
        // The second copy moved to x = 10, then the whole pair turned 90° about z.
        let second = v(&recs[1]);
        assert!((second[0] - DVec3::new(0.0, 10.0, 0.0)).length() < 1e-12);
        assert_eq!(recs[0].index, 2);
        assert_eq!(recs[0].fields["id"], "t");
        assert_eq!(recs[0].fields["vertices"].as_array().unwrap().len(), 3);
        assert_eq!(recs[2].index, 3);
    }

    #[test]
    fn object_errors_name_the_record() {
        assert!(err(r#"{"instance": "ghost"}"#)
            .contains("record 0: instance of unknown object `ghost`"));
        assert!(err(r#"{"object": "a", "records": [{"instance": "a"}]}"#)
            .contains("record 0: object `a` places an instance of itself: a cycle"));
        assert!(
            err("{\"object\": \"a\", \"records\": []}\n{\"object\": \"a\", \"records\": []}")
                .contains("record 1: object `a` is defined twice")
        );
        assert!(err(r#"{"object": "a", "records": [{"rect": [0,0,1,1]}]}"#)
            .contains("object `a` records[0]: no \"color\""));
        assert!(err(
            r#"{"object": "a", "records": []} {"instance": "a", "transform": {"scale": 0}}"#
        )
        .contains("record 1: instance of `a`: transform step 0: scale: singular"));
        assert!(err(r#"{"object": "a"}"#).contains("expected \"records\""));
    }

    #[test]
    fn object_mode_patterns_scale_with_similarities_and_refuse_stretching() {
        let def = r#"{"object": "a", "records": [{"vertices": [[0,0],[1,0],[0,1]], "pattern": {"file": "p.pat", "incr": 2}}]}"#;
        let recs = read_all(&format!(
            "{def}\n{{\"instance\": \"a\", \"transform\": {{\"scale\": 3}}}}"
        ))
        .unwrap();
        assert_eq!(recs[0].pattern.as_ref().unwrap().incr, Some(6.0));
        assert_eq!(recs[0].fields["pattern"]["incr"], 6.0);
        let e = err(&format!(
            "{def}\n{{\"instance\": \"a\", \"transform\": {{\"scale\": [1, 2, 1]}}}}"
        ));
        assert!(
            e.contains("record 1: object `a`: the instance transform stretches unevenly"),
            "{e}"
        );
    }

    #[test]
    fn relative_pattern_paths_resolve_against_the_stream_directory() {
        assert_eq!(
            resolve(&base_dir("scenes/a.json"), "p.pat"),
            PathBuf::from("scenes/p.pat")
        );
        assert_eq!(
            resolve(&base_dir("a.json"), "p.pat"),
            PathBuf::from("./p.pat")
        );
        assert_eq!(
            resolve(&base_dir("-"), "/x/p.pat"),
            PathBuf::from("/x/p.pat")
        );
    }

    #[test]
    fn ndjson_output_keeps_unknown_fields_in_order() {
        let r = read_all(r#"{"z":1,"rect":[0,0,1,1],"color":[0,0,0],"a":{"b":[1]}}"#).unwrap();
        let mut out = Vec::new();
        write_ndjson(&mut out, &r[0].fields).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "{\"z\":1,\"rect\":[0,0,1,1],\"color\":[0,0,0],\"a\":{\"b\":[1]}}\n"
        );
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

    #[test]
    fn an_instance_moves_a_quadric_by_composing_transforms() {
        let recs = read_all(
            r#"{"object": "o", "records": [{"sphere": {"radius": 1}, "transform": {"scale": 2}, "color": [0,0,0], "id": "s"}]}
               {"instance": "o", "transform": {"translate": [5, 0, 0]}}"#,
        )
        .unwrap();
        let Shape::Quadric(q) = &recs[0].shape else {
            panic!("{:?}", recs[0].shape)
        };
        // Scale first, then the instance's translation.
        assert_eq!(q.transform.apply(DVec3::X), DVec3::new(7.0, 0.0, 0.0));
        assert_eq!(recs[0].fields["id"], "s");
        assert!(recs[0].fields["transform"].get("matrix").is_some());
        // The written matrix reads back as the same transform.
        let again = Record::from_value(0, Value::Object((*recs[0].fields).clone())).unwrap();
        assert_eq!(again.shape, recs[0].shape);
    }

    #[test]
    fn quadric_triangles_become_uv_records_keeping_other_fields() {
        let recs = read_all(
            r#"{"sphere": {"radius": 1, "slices": 4, "stacks": 2}, "pattern": {"file": "p.pat"}, "id": 7, "transform": {"translate": [0, 0, 3]}}
               {"rect": [0,0,1,1], "color": [0,0,0]}"#,
        )
        .unwrap();
        let tris = quadric_triangles(&recs[0], 0.1, Some(16)).unwrap().unwrap();
        assert_eq!(tris.len(), 8);
        for t in &tris {
            assert_eq!(t["id"], 7);
            assert_eq!(t["pattern"]["mode"], "uv");
            assert!(t.get("sphere").is_none() && t.get("transform").is_none());
            let back = Record::from_value(0, Value::Object(t.clone())).unwrap();
            let Shape::Polygon(v) = &back.shape else {
                panic!()
            };
            assert!(v
                .iter()
                .all(|p| ((*p - DVec3::new(0.0, 0.0, 3.0)).length() - 1.0).abs() < 1e-12));
            assert!(back
                .uv
                .unwrap()
                .iter()
                .all(|c| (0.0..=16.0).contains(&c[0])));
        }
        assert!(quadric_triangles(&recs[1], 0.1, None).is_none());
    }
}
