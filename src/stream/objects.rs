//! Objects and instances (the thesis's `makeobj`/`callobj`, Fig. 5.1): the
//! stream's two elements beside drawable records, kept as definitions and
//! expanded into moved records. Apart from the record parsers because an
//! instance changes records after they are read (their vertices, their
//! pattern's scale) and checks the order of definitions across the stream.

use super::fields::{Element, Fields};
use super::record::{field_err, not_an_object, short, PatternMode, Record, GEOMETRY_KEYS};
use super::{ReadOptions, StreamError};
use crate::geom::transform::Transform;
use crate::geom::Shape;
use crate::light::LightRecord;
use glam::DVec3;
use serde_json::Value;

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
    /// A drawable record.
    Record(Record),
    /// `{"object": name, "records": [...]}`: a definition, drawn only
    /// through instances.
    Object(ObjectDef),
    /// `{"instance": name, "transform": ...}`: a placed copy of an object.
    Instance(Instance),
    /// `{"light": {...}}`: a light of the scene ([`crate::light`]), top
    /// level only.
    Light(LightDef),
}

/// A light element of the stream.
#[derive(Clone, Debug, PartialEq)]
pub struct LightDef {
    /// 0-based position in the stream.
    pub index: usize,
    /// What it adds to the scene's lights.
    pub light: LightRecord,
    /// The element's JSON object, kept whole for tools that forward it.
    pub fields: Fields,
}

/// A named group of items, drawn only through instances.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDef {
    /// 0-based position of the definition in the stream, which its records'
    /// parse errors name too (the records it expands into take the index of
    /// the instance that places them).
    pub index: usize,
    /// The object's name (`"object"`), never empty.
    pub name: String,
    /// Its `"records"`, typed: records and instances of objects defined
    /// earlier (definitions inside definitions are rejected by
    /// [`Objects::define`]).
    pub items: Vec<Item>,
    /// The definition's JSON object, including `"records"` (kept as text:
    /// its records' unknown fields as written, known ones as serde_json
    /// writes them; [`ObjectDef::items`] is their typed view).
    pub fields: Fields,
    /// The files read to make its items (the OBJ and MTL files of its
    /// meshes), resolved, once each: files a tool must not replace and a
    /// make rule depends on.
    pub files: Vec<std::path::PathBuf>,
}

/// An object placed with a transform.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// 0-based position of the instance in the stream, which the records it
    /// expands into take as their own.
    pub index: usize,
    /// The name of the object placed (`"instance"`), never empty.
    pub object: String,
    /// Applied to the object's coordinates (identity when absent).
    pub transform: Transform,
    /// The instance's JSON object, kept whole so that tools forwarding
    /// instances pass unknown fields through.
    pub fields: Fields,
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
            fields: Fields::new(),
            files: Vec::new(),
        }
    }
}

impl Item {
    /// The element's 0-based position in the stream.
    pub fn index(&self) -> usize {
        match self {
            Item::Record(r) => r.index,
            Item::Object(d) => d.index,
            Item::Instance(i) => i.index,
            Item::Light(l) => l.index,
        }
    }

    /// Builds the typed view of one JSON stream element. Unknown fields are
    /// kept as serde_json writes them (a `Value` holds no text): the reader
    /// keeps them as written.
    /// A mesh record's OBJ file resolves against the current directory.
    pub fn from_value(index: usize, value: Value) -> Result<Item, StreamError> {
        Item::from_element(
            index,
            Element::from(value),
            std::path::Path::new("."),
            &ReadOptions::default(),
        )
    }

    /// Builds the typed view of one stream element as read; files that mesh
    /// records inside an object name resolve against `base`. (A top-level
    /// mesh is two items, read by [`super::mesh::top_level`].)
    pub(super) fn from_element(
        index: usize,
        element: Element,
        base: &std::path::Path,
        options: &ReadOptions,
    ) -> Result<Item, StreamError> {
        let object = match element {
            Element::Object(o) => o,
            Element::Other(v) => return Err(not_an_object(index, &v)),
        };
        if object.contains_key("object") {
            let mut object = object;
            let records = object.take_records();
            let fields = object.into_fields();
            let name = object_name(&fields, "object", index, "a non-empty name")?;
            let what = format!("object `{name}`: a definition");
            no_geometry(&fields, index, &what)?;
            none_of(
                &fields,
                index,
                &what,
                &["transform"],
                "to its records or its instances",
            )?;
            none_of(&fields, index, &what, DRAWING_KEYS, "to its records")?;
            none_of(
                &fields,
                index,
                &what,
                &["instance", "light"],
                "its own element",
            )?;
            let records = records.ok_or_else(|| {
                field_err(
                    index,
                    format!("object `{name}`: expected \"records\": [...]"),
                )
            })?;
            let mut items = Vec::with_capacity(records.len());
            let mut files = Vec::new();
            for (i, e) in records.into_iter().enumerate() {
                let inner = |e: StreamError| {
                    let m = e.message;
                    field_err(index, format!("object `{name}` records[{i}]: {m}"))
                };
                match e {
                    // A mesh inside an object: its faces are the object's
                    // records; it is placed by the object's instances.
                    Element::Object(o) if o.contains_key("mesh") => {
                        let fields = o.into_fields();
                        if fields.contains_key("transform") {
                            return Err(inner(field_err(
                                index,
                                "mesh: a mesh inside an object takes no \"transform\": it \
                                 would be dropped (give it to the object's instances)",
                            )));
                        }
                        items.extend(
                            super::mesh::faces(index, &fields, base, &mut files).map_err(inner)?,
                        )
                    }
                    e => items.push(Item::from_element(index, e, base, options).map_err(inner)?),
                }
            }
            return Ok(Item::Object(ObjectDef {
                index,
                name,
                items,
                fields,
                files,
            }));
        }
        if object.contains_key("instance") {
            let fields = object.into_fields();
            let object = object_name(&fields, "instance", index, "an object name")?;
            let what = format!("instance of `{object}`: an instance");
            no_geometry(&fields, index, &what)?;
            none_of(
                &fields,
                index,
                &what,
                DRAWING_KEYS,
                "to the object's records",
            )?;
            none_of(&fields, index, &what, &["light"], "its own element")?;
            let transform = fields
                .get("transform")
                .map(Transform::from_json)
                .transpose()
                .map_err(|e| field_err(index, format!("instance of `{object}`: {e}")))?
                .unwrap_or_default();
            return Ok(Item::Instance(Instance {
                index,
                object,
                transform,
                fields,
            }));
        }
        if object.contains_key("light") {
            let fields = object.into_fields();
            no_geometry(&fields, index, "light: a light")?;
            // A light's "transform" was kept as an unknown field and did
            // nothing (an animated light stood still), as did a "pattern"
            // naming a missing file: a hostile-input review.
            let world = "its position and direction in world coordinates, where it shines";
            none_of(&fields, index, "a light", &["transform"], world)?;
            none_of(
                &fields,
                index,
                "a light",
                DRAWING_KEYS,
                "to the records it lights",
            )?;
            let light =
                LightRecord::from_json(&fields["light"]).map_err(|m| field_err(index, m))?;
            return Ok(Item::Light(LightDef {
                index,
                light,
                fields,
            }));
        }
        Record::from_fields_with(index, object.into_fields(), options).map(Item::Record)
    }
}

/// An error unless the fields of element `index` have no geometry key: an
/// instance, a definition and a light draw nothing of their own, and a
/// `"rect"` beside `"instance"` was dropped without a word (a
/// hostile-input review). `what` begins the message.
fn no_geometry(fields: &Fields, index: usize, what: &str) -> Result<(), StreamError> {
    match GEOMETRY_KEYS.iter().find(|k| fields.contains_key(k)) {
        Some(k) => Err(field_err(
            index,
            format!("{what} has no geometry of its own, found \"{k}\" beside it"),
        )),
        None => Ok(()),
    }
}

/// The keys that say how a record is drawn, which an instance and a
/// definition do not take: they draw their records as those are.
const DRAWING_KEYS: &[&str] = &["color", "pattern", "stripe", "shade", "uv", "normals"];

/// An error unless the fields of element `index` have none of `keys`: such
/// a key was kept as an unknown field and did nothing (an instance's
/// `"color"`, a definition's `"transform"`; a stripe map named there was
/// never opened), found by a hostile-input review. `what` begins the
/// message; `give` says where the key belongs.
fn none_of(
    fields: &Fields,
    index: usize,
    what: &str,
    keys: &[&str],
    give: &str,
) -> Result<(), StreamError> {
    match keys.iter().find(|k| fields.contains_key(k)) {
        Some(k) => Err(field_err(
            index,
            format!("{what} takes no \"{k}\": it would be dropped (give it {give})"),
        )),
        None => Ok(()),
    }
}

/// The object name in field `key` of element `index`, a non-empty string,
/// else an error saying it `expected` one: a definition's `"object"` and an
/// instance's `"instance"` are checked alike.
fn object_name(
    fields: &Fields,
    key: &str,
    index: usize,
    expected: &str,
) -> Result<String, StreamError> {
    match fields.get(key) {
        Some(Value::String(s)) if !s.is_empty() => Ok(s.clone()),
        other => Err(field_err(
            index,
            format!(
                "{key}: expected {expected}, found {}",
                short(other.unwrap_or(&Value::Null))
            ),
        )),
    }
}

/// Tolerance, relative to the radius, of the polygon that replaces a circle or
/// arc moved by an instance transform: 1e-4 keeps the chord error below a
/// hundredth of a pixel for any circle under 100 pixels across.
pub const INSTANCE_CURVE_TOLERANCE: f64 = 1e-4;

/// The deepest an object may nest instances: an object of records alone is
/// 1 deep, one placing it 2, and so on. Every tool walks a placement by
/// recursion (`scene-render` projects an instance's parts inside the
/// projection of its parent, on a rayon worker thread of rayon's default 2
/// MiB stack; the readers expand nested instances the same way), so a chain
/// of definitions each placing the one before overflowed the stack, an
/// abort: `scene-render` at about 1,080 levels (measured 2026-11-29 on a
/// release build, about 1.9 KB of stack a level), `pat-info --record` at
/// about 20,000 on the main thread. 64 levels take about 125 KB of a worker's
/// 2 MiB there: room for a debug build's larger frames and for what runs
/// below the deepest level (clipping, drawing); far beyond the few levels a
/// model's hierarchy needs. Checked by [`Objects::define`], which every tool
/// uses, so each refuses the same stream with the same words.
pub const MAX_OBJECT_DEPTH: usize = 64;

/// The object definitions seen so far, and the expansion of instances.
#[derive(Default)]
pub struct Objects {
    defs: std::collections::HashMap<String, std::rc::Rc<ObjectDef>>,
    /// Each object's nesting depth ([`MAX_OBJECT_DEPTH`]).
    depths: std::collections::HashMap<String, usize>,
    /// Each object's [`Objects::walk`].
    walks: std::collections::HashMap<String, u64>,
}

impl Objects {
    /// Records a definition after checking its name is new, every instance
    /// inside it names an object defined before it, and it nests instances
    /// at most [`MAX_OBJECT_DEPTH`] deep.
    pub fn define(&mut self, def: ObjectDef) -> Result<(), StreamError> {
        let err = |m: String| StreamError::in_record(def.index, m);
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
                    Item::Light(_) => {
                        return Err(format!(
                            "object `{name}` holds a light: lights are top-level only, in world coordinates"
                        ))
                    }
                    _ => {}
                }
            }
            Ok(())
        }
        check(self, &def.name, &def.items).map_err(err)?;
        let depth = 1 + def
            .items
            .iter()
            .filter_map(|it| match it {
                Item::Instance(i) => self.depths.get(&i.object).copied(),
                _ => None,
            })
            .max()
            .unwrap_or(0);
        if depth > MAX_OBJECT_DEPTH {
            return Err(err(format!(
                "object `{}` nests instances {depth} deep, over the limit of {MAX_OBJECT_DEPTH}",
                def.name
            )));
        }
        self.depths.insert(def.name.clone(), depth);
        let walk = def.items.iter().fold(0u64, |n, it| {
            let inner = match it {
                Item::Instance(i) => self.walk(&i.object),
                _ => 0,
            };
            n.saturating_add(1).saturating_add(inner)
        });
        self.walks.insert(def.name.clone(), walk);
        self.defs.insert(def.name.clone(), std::rc::Rc::new(def));
        Ok(())
    }

    /// How many records and instances placing object `name` once visits,
    /// nested instances expanded (saturating; 0 for an unknown name): the
    /// work of expanding it, which what it draws does not bound, since an
    /// object may be empty. Twelve objects each placing the one before ten
    /// times, the first empty, visit 10^12 placements to draw nothing (a
    /// hostile-input review: `pat-info --record` ran for hours).
    pub fn walk(&self, name: &str) -> u64 {
        self.walks.get(name).copied().unwrap_or(0)
    }

    /// Checks that a top-level instance names an object defined before it.
    pub fn check_instance(&self, inst: &Instance) -> Result<(), StreamError> {
        if self.defs.contains_key(&inst.object) {
            return Ok(());
        }
        Err(StreamError::in_record(
            inst.index,
            format!(
                "instance of unknown object `{}` (define it first)",
                inst.object
            ),
        ))
    }

    /// The definition of object `name`, if one was defined.
    pub fn get(&self, name: &str) -> Option<&ObjectDef> {
        self.defs.get(name).map(|d| &**d)
    }

    /// Feeds one stream item through: records go to `each`, definitions are
    /// stored, instances are expanded into moved records. `source` names the
    /// input in the errors raised here; `each`'s own errors pass unchanged.
    pub fn expand<E: From<StreamError>>(
        &mut self,
        item: Item,
        source: &str,
        each: &mut dyn FnMut(Record) -> Result<(), E>,
    ) -> Result<(), E> {
        match item {
            Item::Record(r) => each(r),
            // Records only: a light draws nothing.
            Item::Light(_) => Ok(()),
            Item::Object(def) => Ok(self.define(def).map_err(|e| e.named(source))?),
            Item::Instance(inst) => {
                self.check_instance(&inst).map_err(|e| e.named(source))?;
                let def = self.defs[&inst.object].clone();
                self.place(&def, inst.transform, inst.index, source, each)
            }
        }
    }

    fn place<E: From<StreamError>>(
        &self,
        def: &ObjectDef,
        transform: Transform,
        index: usize,
        source: &str,
        each: &mut dyn FnMut(Record) -> Result<(), E>,
    ) -> Result<(), E> {
        for item in &def.items {
            match item {
                Item::Record(r) => {
                    let moved = transform_record(r, &transform, index).map_err(|m| {
                        StreamError::in_record(index, format!("object `{}`: {m}", def.name))
                            .named(source)
                    })?;
                    each(moved)?;
                }
                Item::Instance(inner) => {
                    let inner_def = &self.defs[&inner.object];
                    // The inner placement applies first, then this one.
                    let placed = inner.transform.then_checked(transform).map_err(|e| {
                        StreamError::in_record(
                            index,
                            format!(
                                "object `{}`: instance of `{}`: its transform with those of the instances placing it: {e}",
                                def.name, inner.object
                            ),
                        )
                        .named(source)
                    })?;
                    self.place(inner_def, placed, index, source, each)?;
                }
                Item::Object(_) | Item::Light(_) => unreachable!("rejected by define"),
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
    move_record(r, t, index, "instance transform")
}

/// [`transform_record`], with `what` naming the transform in its errors
/// (an instance's, or the record's own).
pub(super) fn move_record(
    r: &Record,
    t: &Transform,
    index: usize,
    what: &str,
) -> Result<Record, String> {
    if let Shape::Quadric(q) = &r.shape {
        // A quadric stays a quadric: its own placement is followed by `t`,
        // and its JSON "transform" becomes the combined matrix.
        let mut moved = (**q).clone();
        moved.transform = q.transform.then(*t);
        let mut fields = r.fields.clone();
        fields.insert(
            "transform",
            serde_json::json!({"matrix": moved.transform.row_matrix()}),
        );
        return Ok(Record {
            index,
            shape: Shape::Quadric(Box::new(moved)),
            fields,
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
    let mut fields = r.fields.clone();
    for k in ["rect", "circle", "arc"] {
        fields.remove(k);
    }
    fields.insert(
        "vertices",
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
                {
                let hint = if what == "instance transform" {
                    "partition the object with polyfill3 first"
                } else {
                    "define the record as an object and place an instance of it (scene-render stretches the pattern with the object)"
                };
                format!("the {what} stretches unevenly, which an object-mode pattern cannot follow: {hint}")
            }
            })?;
            if (s - 1.0).abs() > crate::geom::transform::SIMILARITY_TOLERANCE {
                let incr = p.incr.ok_or_else(|| {
                    format!("the {what} scales by {s}: give the pattern an explicit \"incr\" so it can scale too")
                })?;
                p.incr = Some(incr * s);
                if let Some(Value::Object(pf)) = fields.get_mut("pattern") {
                    pf.insert("incr".into(), serde_json::json!(incr * s));
                }
            }
        }
    }
    let normals = r
        .normals
        .as_ref()
        .map(|ns| ns.iter().map(|&n| t.apply_normal(n)).collect::<Vec<_>>());
    if let Some(ns) = &normals {
        fields.insert(
            "normals",
            Value::Array(
                ns.iter()
                    .map(|n| serde_json::json!([n.x, n.y, n.z]))
                    .collect(),
            ),
        );
    }
    Ok(Record {
        index,
        shape: Shape::Polygon(verts.into()),
        color: r.color,
        pattern,
        uv: r.uv.clone(),
        normals,
        shade: r.shade,
        fields,
    })
}

#[cfg(test)]
mod tests {
    use super::super::testing::{err, read_all};
    use super::*;

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
        assert_eq!(recs[0].fields.field("id").unwrap().to_string(), r#""t""#);
        assert_eq!(recs[0].fields["vertices"].as_array().unwrap().len(), 3);
        assert_eq!(recs[2].index, 3);
    }

    #[test]
    fn object_errors_name_the_record() {
        assert!(err(r#"{"instance": "ghost"}"#)
            .contains("record 0: instance of unknown object `ghost`"));
        // Geometry beside "instance" or "object" was dropped without a word.
        assert!(err(
            "{\"object\": \"a\", \"records\": []}\n\
             {\"instance\": \"a\", \"rect\": [0,0,64,64], \"color\": [255,0,0]}"
        )
        .contains(
            "record 1: instance of `a`: an instance has no geometry of its own, found \"rect\" beside it"
        ));
        assert!(
            err(r#"{"object": "a", "vertices": [[0,0],[1,0],[0,1]], "records": []}"#).contains(
                "record 0: object `a`: a definition has no geometry of its own, found \"vertices\""
            )
        );
        // And so were the keys that say how a record is drawn, and a
        // definition's transform (a hostile-input review).
        for (stream, message) in [
            (
                r#"{"object": "a", "records": []} {"instance": "a", "color": [0,255,0]}"#,
                "record 1: instance of `a`: an instance takes no \"color\": it would be dropped (give it to the object's records)",
            ),
            (
                r#"{"object": "a", "records": []} {"instance": "a", "stripe": {"map": "missing.map"}}"#,
                "an instance takes no \"stripe\"",
            ),
            (
                r#"{"object": "a", "records": [], "transform": {"translate": [5,5,0]}}"#,
                "record 0: object `a`: a definition takes no \"transform\": it would be dropped (give it to its records or its instances)",
            ),
            (
                r#"{"object": "a", "records": [], "pattern": {"file": "p.pat"}}"#,
                "a definition takes no \"pattern\"",
            ),
            (
                r#"{"object": "a", "records": []} {"instance": "a", "light": {"ambient": 0.1}}"#,
                "an instance takes no \"light\": it would be dropped (give it its own element)",
            ),
            (
                r#"{"object": "a", "records": [], "instance": "b"}"#,
                "a definition takes no \"instance\"",
            ),
            (
                r#"{"light": {"position": [0,0,1]}, "transform": {"translate": [4,4,0]}}"#,
                "record 0: a light takes no \"transform\": it would be dropped (give it its position and direction in world coordinates, where it shines)",
            ),
            (
                r#"{"light": {"ambient": 0.1}, "pattern": {"file": "missing.pat"}}"#,
                "a light takes no \"pattern\": it would be dropped (give it to the records it lights)",
            ),
            (
                r#"{"light": {"ambient": 0.1}, "shade": "bogus"}"#,
                "a light takes no \"shade\"",
            ),
        ] {
            let e = err(stream);
            assert!(e.contains(message), "{stream}: {e}");
        }
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
    fn nesting_deeper_than_the_limit_is_refused_naming_the_object() {
        // A chain of definitions, each placing the one before: `o{k}` is
        // k + 1 deep.
        let chain = |n: usize| {
            let mut s = String::from(
                "{\"object\": \"o0\", \"records\": [{\"vertices\": [[0,0],[1,0],[0,1]], \"color\": [1,2,3]}]}\n",
            );
            for k in 1..n {
                s += &format!("{{\"object\": \"o{k}\", \"records\": [{{\"rect\": [0,0,1,1], \"color\": [1,2,3]}}, {{\"instance\": \"o{}\"}}]}}\n", k - 1);
            }
            s + &format!("{{\"instance\": \"o{}\"}}\n", n - 1)
        };
        let recs = read_all(&chain(MAX_OBJECT_DEPTH)).unwrap();
        assert_eq!(recs.len(), MAX_OBJECT_DEPTH);
        let e = err(&chain(MAX_OBJECT_DEPTH + 1));
        assert!(
            e.contains(&format!(
                "record {MAX_OBJECT_DEPTH}: object `o{MAX_OBJECT_DEPTH}` nests instances {} deep, over the limit of {MAX_OBJECT_DEPTH}",
                MAX_OBJECT_DEPTH + 1
            )),
            "{e}"
        );
        // The depth is that of the deepest instance, not the first.
        let mut s = chain(MAX_OBJECT_DEPTH);
        s += &format!("{{\"object\": \"w\", \"records\": [{{\"instance\": \"o0\"}}, {{\"instance\": \"o{}\"}}]}}\n", MAX_OBJECT_DEPTH - 1);
        assert!(
            err(&s).contains(&format!(
                "object `w` nests instances {} deep",
                MAX_OBJECT_DEPTH + 1
            )),
            "{}",
            err(&s)
        );
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
        assert_eq!(recs[0].fields.field("id").unwrap().to_string(), r#""s""#);
        assert!(recs[0].fields["transform"].get("matrix").is_some());
        // The written matrix reads back as the same transform.
        let again = Record::from_fields(0, recs[0].fields.clone()).unwrap();
        assert_eq!(again.shape, recs[0].shape);
    }

    #[test]
    fn a_value_gives_the_item_the_reader_gives_for_its_text() {
        // `Item::from_value` keeps unknown fields as serde_json writes them,
        // which for text serde_json wrote is the text itself.
        let text = r#"{"object":"o","records":[{"rect":[0,0,1,1],"color":[1,2,3],"id":"a","n":[1.5,{"k":null}]},{"instance":"p","tag":7}],"note":"x"}"#;
        let mut read = Vec::new();
        super::super::for_each_item(text.as_bytes(), "s.json", |item| {
            read.push(item);
            Ok::<(), StreamError>(())
        })
        .unwrap();
        let from_value = Item::from_value(0, serde_json::from_str(text).unwrap()).unwrap();
        assert_eq!(read, vec![from_value]);
        let Item::Object(def) = &read[0] else {
            panic!("{:?}", read[0])
        };
        assert_eq!(serde_json::to_string(&def.fields).unwrap(), text);
        assert_eq!(def.items.len(), 2);
    }
}
