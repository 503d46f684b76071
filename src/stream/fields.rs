//! A record's JSON object as the tools keep it ([`Fields`]): the fields they
//! read are parsed ([`Field::Value`]), every other field is kept as the text
//! it was written in ([`Field::Raw`], serde_json's `RawValue`), so that a tool
//! forwarding records passes unknown fields through unchanged (docs/stream-format.md) — an
//! `"id"` of `123456789012345678901234567890` stays that, where a parsed
//! number would come out as `1.2345678901234568e+29`.
//!
//! What "unchanged" means, exactly (docs/polyfill3.md says it for users):
//!
//! - An unknown top-level field of a record, an object definition or an
//!   instance comes out byte for byte as written — number spelling (`1e2`,
//!   `-0`, `1.50`, integers of any size), string escapes (`"\u00e9"`, `"\/"`)
//!   and key order included — except JSON's insignificant whitespace (space,
//!   tab, newline, carriage return outside strings), which is removed, since
//!   the output is one record per line.
//! - Its value may be any JSON value: numbers out of the range of a double
//!   (`1e400`), nesting of any depth. Only the syntax is checked.
//! - The known fields ([`is_value_key`]: the geometry, `"color"`,
//!   `"pattern"`, `"uv"`, `"stripe"`, `"transform"`, `"object"`,
//!   `"instance"`, `"texel"`, `"cells"`) are parsed, checked and written
//!   again as serde_json writes them: numbers in their shortest round-trip
//!   form (`1e2` becomes `100.0`), strings with the minimal escapes. Keys
//!   inside them, unknown ones too (`"pattern": {"note": 1e2}`), are part of
//!   the known field and are written the same way; their numbers must be
//!   doubles or 64-bit integers.
//! - `"records"` (an object definition's) is a list of records: each keeps
//!   its unknown fields as written by these rules.
//!
//! The reader parses the stream into these [`Element`]s in one pass
//! ([`Element`]'s `Deserialize`), so JSON errors keep their positions in the
//! whole input.

use super::MAX_VERTICES;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::value::RawValue;
use serde_json::{Map, Value};
use std::fmt;
use std::sync::OnceLock;

/// Whether the tools read field `key` as a JSON value: the known fields a
/// [`Field::Value`] holds. Every other key but `"records"` is kept as text.
pub fn is_value_key(key: &str) -> bool {
    matches!(
        key,
        "vertices"
            | "rect"
            | "circle"
            | "arc"
            | "sphere"
            | "cylinder"
            | "cone"
            | "disk"
            | "color"
            | "pattern"
            | "uv"
            | "stripe"
            | "transform"
            | "object"
            | "instance"
            | "light"
            | "mesh"
            | "normals"
            | "shade"
            | "texel"
            | "cells"
    )
}

/// The value of one field of a record.
#[derive(Clone, Debug)]
pub enum Field {
    /// A known field ([`is_value_key`]), parsed.
    Value(Value),
    /// Any other field: its JSON text as written, insignificant whitespace
    /// removed.
    Raw(Box<RawValue>),
}

impl Field {
    /// The parsed value of a known field; `None` for one kept as text.
    pub fn as_value(&self) -> Option<&Value> {
        match self {
            Field::Value(v) => Some(v),
            Field::Raw(_) => None,
        }
    }

    /// The text of a field kept as written; `None` for a parsed one.
    pub fn as_raw(&self) -> Option<&RawValue> {
        match self {
            Field::Value(_) => None,
            Field::Raw(r) => Some(r),
        }
    }

    /// A field holding `value` as the reader would keep it under `key`:
    /// parsed for a known key, else as the text serde_json writes for it.
    pub fn for_key(key: &str, value: Value) -> Field {
        if is_value_key(key) {
            Field::Value(value)
        } else {
            Field::Raw(text_of(&value))
        }
    }
}

impl From<Value> for Field {
    fn from(v: Value) -> Field {
        Field::Value(v)
    }
}

/// The field's JSON text, as it is written out.
impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Field::Value(v) => fmt::Display::fmt(v, f),
            Field::Raw(r) => f.write_str(r.get()),
        }
    }
}

impl PartialEq for Field {
    fn eq(&self, other: &Field) -> bool {
        match (self, other) {
            (Field::Value(a), Field::Value(b)) => a == b,
            (Field::Raw(a), Field::Raw(b)) => a.get() == b.get(),
            _ => false,
        }
    }
}

impl Serialize for Field {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Field::Value(v) => v.serialize(s),
            // serde_json writes a RawValue's text as it is.
            Field::Raw(r) => r.serialize(s),
        }
    }
}

/// A record's whole JSON object (or an object definition's, an instance's):
/// its fields in the order written, known ones parsed, the others kept as
/// text (see the module's documentation for what comes out unchanged).
///
/// The general reader builds the fields as it reads; the fast path for plain
/// NDJSON polygons (`stream::plain`) keeps the record's line instead and
/// parses it on first use, so a tool that never looks never pays for them;
/// looking for a key a line of only "vertices" and "color" lacks (what
/// scene-render asks of every record) does not count as looking.
#[derive(Clone)]
pub struct Fields {
    /// The record's JSON text, when the fields are still to be made from it
    /// (a line the fast path kept: see [`Fields::field`]).
    line: Option<Box<[u8]>>,
    list: OnceLock<Vec<(String, Field)>>,
}

impl Default for Fields {
    fn default() -> Fields {
        Fields::new()
    }
}

impl Fields {
    /// No fields.
    pub fn new() -> Fields {
        Fields::from_list(Vec::new())
    }

    fn from_list(list: Vec<(String, Field)>) -> Fields {
        Fields {
            line: None,
            list: OnceLock::from(list),
        }
    }

    /// Fields to be parsed from `line` when first asked for. The line must be
    /// one JSON object that the reader's general path would read (the fast
    /// path checks that: it parses every known field it does not read as
    /// `Value` and every other as `RawValue`, as [`Element`] does), without
    /// `"records"`.
    pub(super) fn from_line(line: &[u8]) -> Fields {
        Fields {
            line: Some(line.into()),
            list: OnceLock::new(),
        }
    }

    fn list(&self) -> &Vec<(String, Field)> {
        self.list.get_or_init(|| {
            let line = self.line.as_deref().unwrap_or_default();
            match serde_json::from_slice::<Element>(line) {
                Ok(Element::Object(o)) => o.into_list(),
                _ => unreachable!("the fast path accepts only lines that parse as a JSON object"),
            }
        })
    }

    fn list_mut(&mut self) -> &mut Vec<(String, Field)> {
        self.list();
        self.line = None;
        self.list.get_mut().expect("parsed above")
    }

    /// How many fields.
    pub fn len(&self) -> usize {
        self.list().len()
    }

    /// Whether there are no fields.
    pub fn is_empty(&self) -> bool {
        self.list().is_empty()
    }

    /// The fields in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (&str, &Field)> + '_ {
        self.list().iter().map(|(k, f)| (k.as_str(), f))
    }

    /// The keys in order.
    pub fn keys(&self) -> impl ExactSizeIterator<Item = &str> + '_ {
        self.list().iter().map(|(k, _)| k.as_str())
    }

    /// Field `key`, parsed or kept as text.
    ///
    /// A line the fast path kept holds none of the keys it declines
    /// (`plain::declines`), so asking for one parses nothing:
    /// scene-render asks every record for its "pattern" and "stripe" (to
    /// check their keys), which parsed each line a second time, serially.
    pub fn field(&self, key: &str) -> Option<&Field> {
        if self.line.is_some() && self.list.get().is_none() && super::plain::declines(key) {
            return None;
        }
        self.list().iter().find(|(k, _)| k == key).map(|(_, f)| f)
    }

    /// The parsed value of field `key`: a known field. A field kept as text
    /// (an unknown one) gives `None`: see [`Fields::field`].
    pub fn get(&self, key: &str) -> Option<&Value> {
        self.field(key).and_then(Field::as_value)
    }

    /// Whether field `key` is there, parsed or kept as text.
    pub fn contains_key(&self, key: &str) -> bool {
        self.field(key).is_some()
    }

    /// The parsed value of field `key`, to change it.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Value> {
        self.list_mut()
            .iter_mut()
            .find(|(k, _)| k == key)
            .and_then(|(_, f)| match f {
                Field::Value(v) => Some(v),
                Field::Raw(_) => None,
            })
    }

    /// Sets field `key`: in its place if it is there, else last. Returns
    /// the field it replaces.
    pub fn insert(&mut self, key: impl Into<String>, field: impl Into<Field>) -> Option<Field> {
        let (key, field) = (key.into(), field.into());
        let list = self.list_mut();
        match list.iter_mut().find(|(k, _)| *k == key) {
            Some((_, f)) => Some(std::mem::replace(f, field)),
            None => {
                list.push((key, field));
                None
            }
        }
    }

    /// Removes field `key`, keeping the order of the others.
    pub fn remove(&mut self, key: &str) -> Option<Field> {
        let list = self.list_mut();
        let i = list.iter().position(|(k, _)| k == key)?;
        Some(list.remove(i).1)
    }

    /// Keeps only the fields `keep` says yes to, in their order.
    pub fn retain(&mut self, mut keep: impl FnMut(&str, &Field) -> bool) {
        self.list_mut().retain(|(k, f)| keep(k, f));
    }
}

/// Fields from a JSON object: known keys parsed, the others kept as the text
/// serde_json writes for them ([`Field::for_key`]).
impl From<Map<String, Value>> for Fields {
    fn from(map: Map<String, Value>) -> Fields {
        Fields::from_list(
            map.into_iter()
                .map(|(k, v)| {
                    let f = if k == "records" {
                        Field::Raw(text_of(&v))
                    } else {
                        Field::for_key(&k, v)
                    };
                    (k, f)
                })
                .collect(),
        )
    }
}

/// The parsed value of known field `key`. Panics when there is no such field
/// or it is kept as text (use [`Fields::field`]), as `Map`'s index does for
/// a missing key.
impl std::ops::Index<&str> for Fields {
    type Output = Value;
    fn index(&self, key: &str) -> &Value {
        match self.field(key) {
            Some(Field::Value(v)) => v,
            Some(Field::Raw(_)) => panic!("field `{key}` is kept as text: see Fields::field"),
            None => panic!("no field `{key}`"),
        }
    }
}

impl<'a> IntoIterator for &'a Fields {
    type Item = (&'a String, &'a Field);
    type IntoIter = std::iter::Map<
        std::slice::Iter<'a, (String, Field)>,
        fn(&'a (String, Field)) -> (&'a String, &'a Field),
    >;
    fn into_iter(self) -> Self::IntoIter {
        self.list().iter().map(|(k, f)| (k, f))
    }
}

impl fmt::Debug for Fields {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

impl PartialEq for Fields {
    fn eq(&self, other: &Fields) -> bool {
        self.list() == other.list()
    }
}

/// The JSON object, unknown fields as written.
impl Serialize for Fields {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let list = self.list();
        let mut m = s.serialize_map(Some(list.len()))?;
        for (k, f) in list {
            m.serialize_entry(k, f)?;
        }
        m.end()
    }
}

/// One element of the stream (or of an object's `"records"`) as read: an
/// object, or any other JSON value, which the caller refuses in words of its
/// own.
#[derive(Debug)]
pub(super) enum Element {
    Object(Object),
    Other(Value),
}

/// An object as read. An object definition's `"records"` are elements too,
/// kept apart until the caller knows whether the object is a definition;
/// their place among the fields holds a stand-in till then.
#[derive(Debug)]
pub(super) struct Object {
    list: Vec<(String, Field)>,
    records: Option<Vec<Element>>,
}

impl Object {
    /// Whether the object has field `key`.
    pub(super) fn contains_key(&self, key: &str) -> bool {
        self.list.iter().any(|(k, _)| k == key)
    }

    /// The `"records"` of the object, when they are an array: each element
    /// kept as read. Their field becomes their text (unknown fields as
    /// written, known ones as serde_json writes them).
    pub(super) fn take_records(&mut self) -> Option<Vec<Element>> {
        let records = self.records.take()?;
        let text = serde_json::value::to_raw_value(&records).expect("elements serialize");
        if let Some((_, f)) = self.list.iter_mut().find(|(k, _)| k == "records") {
            *f = Field::Raw(text);
        }
        Some(records)
    }

    /// The object's fields, `"records"` as text.
    pub(super) fn into_fields(self) -> Fields {
        Fields::from_list(self.into_list())
    }

    fn into_list(mut self) -> Vec<(String, Field)> {
        self.take_records();
        self.list
    }
}

impl From<Value> for Element {
    fn from(v: Value) -> Element {
        let Value::Object(map) = v else {
            return Element::Other(v);
        };
        let mut records = None;
        let list = map
            .into_iter()
            .map(|(k, v)| {
                let f = match v {
                    Value::Array(elements) if k == "records" => {
                        records = Some(elements.into_iter().map(Element::from).collect());
                        Field::Value(Value::Null)
                    }
                    v if k == "records" => Field::Raw(text_of(&v)),
                    v => Field::for_key(&k, v),
                };
                (k, f)
            })
            .collect();
        Element::Object(Object { list, records })
    }
}

impl Serialize for Element {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Element::Other(v) => v.serialize(s),
            Element::Object(o) => {
                let mut m = s.serialize_map(Some(o.list.len()))?;
                for (k, f) in &o.list {
                    match &o.records {
                        Some(r) if k == "records" => m.serialize_entry(k, r)?,
                        _ => m.serialize_entry(k, f)?,
                    }
                }
                m.end()
            }
        }
    }
}

impl<'de> de::Deserialize<'de> for Element {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Element, D::Error> {
        d.deserialize_any(ElementVisitor)
    }
}

/// A JSON value as an [`Element`]: objects field by field, anything else as
/// a `Value`.
struct ElementVisitor;

/// Implements a visitor's methods for the values other than objects (and,
/// with `seq`, arrays) as `Value`s wrapped by `$wrap`.
macro_rules! other_values {
    ($out:ty, $wrap:expr) => {
        fn visit_i64<E: de::Error>(self, n: i64) -> Result<$out, E> {
            Ok($wrap(Value::from(n)))
        }
        fn visit_u64<E: de::Error>(self, n: u64) -> Result<$out, E> {
            Ok($wrap(Value::from(n)))
        }
        fn visit_f64<E: de::Error>(self, x: f64) -> Result<$out, E> {
            Ok($wrap(Value::from(x)))
        }
        non_numbers!($out, $wrap);
    };
}

/// [`other_values`] but for numbers: booleans, strings and null.
macro_rules! non_numbers {
    ($out:ty, $wrap:expr) => {
        fn visit_bool<E: de::Error>(self, b: bool) -> Result<$out, E> {
            Ok($wrap(Value::Bool(b)))
        }
        fn visit_str<E: de::Error>(self, s: &str) -> Result<$out, E> {
            Ok($wrap(Value::String(s.to_string())))
        }
        fn visit_string<E: de::Error>(self, s: String) -> Result<$out, E> {
            Ok($wrap(Value::String(s)))
        }
        fn visit_unit<E: de::Error>(self) -> Result<$out, E> {
            Ok($wrap(Value::Null))
        }
    };
}

impl<'de> Visitor<'de> for ElementVisitor {
    type Value = Element;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    other_values!(Element, Element::Other);
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Element, A::Error> {
        Value::deserialize(SeqAccessDeserializer::new(seq)).map(Element::Other)
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Element, A::Error> {
        let mut list: Vec<(String, Field)> = Vec::new();
        let mut records = None;
        // Where each key is, once there are too many to search. A repeated
        // key is refused: `Value` keeps the last value, which dropped the
        // first without a word (`"id": 1, "id": 2` came out as `"id": 2`).
        let mut index: Option<std::collections::HashMap<String, usize>> = None;
        while let Some(key) = map.next_key::<String>()? {
            let field = if key == "records" {
                match map.next_value_seed(RecordsSeed)? {
                    Ok(elements) => {
                        records = Some(elements);
                        Field::Value(Value::Null)
                    }
                    Err(other) => {
                        records = None;
                        Field::Raw(text_of(&other))
                    }
                }
            } else if let Some(per_vertex) = PerVertex::of(&key) {
                Field::Value(map.next_value_seed(per_vertex)?)
            } else if is_value_key(&key) {
                Field::Value(map.next_value_seed(UniqueKeys)?)
            } else {
                Field::Raw(without_whitespace(map.next_value()?))
            };
            let at = match &mut index {
                Some(ix) => ix.get(&key).copied(),
                None => list.iter().position(|(k, _)| *k == key),
            };
            match at {
                Some(_) => return Err(repeated_key(&key)),
                None => {
                    if let Some(ix) = &mut index {
                        ix.insert(key.clone(), list.len());
                    }
                    list.push((key, field));
                    if index.is_none() && list.len() > 16 {
                        index = Some(
                            list.iter()
                                .enumerate()
                                .map(|(i, (k, _))| (k.clone(), i))
                                .collect(),
                        );
                    }
                }
            }
        }
        Ok(Element::Object(Object { list, records }))
    }
}

/// Parses `text` as one JSON value, as `serde_json::from_str::<Value>`
/// does, but refuses a key repeated in any of its objects:
/// for files read whole, such as a camera.
pub fn value_with_unique_keys(text: &str) -> Result<Value, serde_json::Error> {
    let mut d = serde_json::Deserializer::from_str(text);
    let value = UniqueKeys.deserialize(&mut d)?;
    d.end()?;
    Ok(value)
}

/// A JSON value, as `Value` deserializes it, except that a key repeated in
/// one of its objects is an error: `Value` keeps the last value and drops
/// the first without a word (`{"ortho2": [0,1,0,1], "ortho2": [0,64,0,64]}`
/// was the second camera, a hostile-input review found).
struct UniqueKeys;

impl<'de> DeserializeSeed<'de> for UniqueKeys {
    type Value = Value;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(UniqueVisitor)
    }
}

/// [`UniqueKeys`]' visitor.
struct UniqueVisitor;

impl<'de> Visitor<'de> for UniqueVisitor {
    type Value = Value;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    other_values!(Value, std::convert::identity);
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element_seed(UniqueKeys)? {
            out.push(v);
        }
        Ok(Value::Array(out))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            let value = map.next_value_seed(UniqueKeys)?;
            match out.entry(key) {
                serde_json::map::Entry::Occupied(o) => {
                    return Err(repeated_key(o.key()));
                }
                serde_json::map::Entry::Vacant(v) => {
                    v.insert(value);
                }
            }
        }
        Ok(Value::Object(out))
    }
}

/// The error of a key repeated in one JSON object.
fn repeated_key<E: de::Error>(key: &str) -> E {
    E::custom(format_args!(
        "the key \"{key}\" appears twice in one object: which one is meant?"
    ))
}

/// The keys of a record whose arrays hold one element per vertex.
const PER_VERTEX_KEYS: [&str; 3] = ["vertices", "uv", "normals"];

/// The value of a record's field that holds one element per vertex
/// ([`PER_VERTEX_KEYS`]), read as [`UniqueKeys`] reads it, but an array is
/// counted as it is read: at its element [`MAX_VERTICES`] + 1 the record is
/// refused ([`per_vertex_limit`]), whatever follows. Counted only once the
/// whole array was a `Value` tree (about 380 bytes a vertex), a record one
/// vertex over the limit needed 6.6 GB and ran out of memory instead of
/// naming the limit, and an endless array grew until it did. Its elements
/// past the first [`READ_AS_VALUES`] are kept [`Packed`] (32 bytes a
/// point) until the array ends, then made the `Value` the field holds,
/// each point's array no larger than it needs.
#[derive(Clone, Copy)]
struct PerVertex(&'static str);

/// How many elements of a per-vertex array are read straight into `Value`s
/// (about 300 KB of them), as before: packing and unpacking them cost 3% of
/// the instructions of reading 200,000 triangles in a JSON array
/// (callgrind), and few polygons have more vertices.
const READ_AS_VALUES: usize = 1024;

impl PerVertex {
    /// The reader of `key`'s value, if it holds one element per vertex.
    fn of(key: &str) -> Option<PerVertex> {
        PER_VERTEX_KEYS
            .into_iter()
            .find(|k| *k == key)
            .map(PerVertex)
    }
}

/// The error of a `key` array ([`PER_VERTEX_KEYS`]) with more elements
/// than a polygon may have vertices, as `record::parse_vertices` words it
/// for a `Value`, but "at least": reading stops at the first element past
/// the limit.
pub(super) fn per_vertex_limit(key: &str) -> String {
    let n = MAX_VERTICES + 1;
    match key {
        "vertices" => {
            format!("vertices: at least {n} vertices is more than the limit of {MAX_VERTICES}")
        }
        "uv" => format!(
            "uv: at least {n} pairs is more than the limit of {MAX_VERTICES} vertices \
             (one pair per vertex)"
        ),
        _ => format!(
            "normals: at least {n} is more than the limit of {MAX_VERTICES} vertices \
             (one per vertex)"
        ),
    }
}

/// The message of `e` if it is a [`per_vertex_limit`] error, without the
/// position serde_json adds: the record's error, not a JSON syntax error.
pub(super) fn per_vertex_limit_in(e: &serde_json::Error) -> Option<String> {
    if !e.is_data() {
        return None;
    }
    let text = e.to_string();
    let position = format!(" at line {} column {}", e.line(), e.column());
    let message = text.strip_suffix(&position).unwrap_or(&text);
    PER_VERTEX_KEYS
        .into_iter()
        .map(per_vertex_limit)
        .find(|m| m == message)
}

impl<'de> DeserializeSeed<'de> for PerVertex {
    type Value = Value;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for PerVertex {
    type Value = Value;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    other_values!(Value, std::convert::identity);
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        // The first elements as they are read, as any known field's: most
        // arrays end before these do, at no more cost than before.
        let mut values = Vec::new();
        while values.len() < READ_AS_VALUES {
            match seq.next_element_seed(UniqueKeys)? {
                Some(v) => values.push(v),
                None => return Ok(Value::Array(values)),
            }
        }
        // The rest packed, counted.
        let (mut packed, mut others) = (Vec::new(), Vec::new());
        while let Some(element) = seq.next_element_seed(Packed::READ)? {
            if values.len() + packed.len() == MAX_VERTICES {
                return Err(de::Error::custom(per_vertex_limit(self.0)));
            }
            packed.push(element.unwrap_or_else(|other| {
                others.push(other);
                Packed::OTHER
            }));
        }
        let mut others = others.into_iter();
        values.reserve_exact(packed.len());
        values.extend(packed.iter().map(|p| p.value(&mut others)));
        Ok(Value::Array(values))
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Value, A::Error> {
        UniqueVisitor.visit_map(map)
    }
}

/// A JSON number as serde_json hands it on.
#[derive(Clone, Copy)]
enum Num {
    U(u64),
    I(i64),
    F(f64),
}

impl Num {
    /// The number as [`UniqueKeys`] makes it a `Value`.
    fn value(self) -> Value {
        match self {
            Num::U(n) => Value::from(n),
            Num::I(n) => Value::from(n),
            Num::F(x) => Value::from(x),
        }
    }
}

/// One element of a per-vertex array as read ([`PerVertex`]), in 32
/// bytes: an array of up to three numbers, a number, `null` or a boolean;
/// or any other value ([`Packed::OTHER`]), kept apart, in order.
#[derive(Clone, Copy)]
struct Packed {
    /// The numbers, each a `u64`, an `i64` or an `f64` as `kinds` says.
    bits: [u64; 3],
    /// How many numbers an array holds (0 to 3), or one of the other
    /// forms ([`Packed::NUMBER`], ...).
    form: u8,
    /// Two bits a number: 0 for a `u64`, 1 an `i64`, 2 an `f64`.
    kinds: u8,
}

impl Packed {
    const NUMBER: u8 = 4;
    const NULL: u8 = 5;
    const FALSE: u8 = 6;
    const TRUE: u8 = 7;
    /// An element kept apart as a `Value`.
    const OTHER: Packed = Packed::form(8);
    /// The reader of one element: `Err` for one kept as a `Value`.
    const READ: PackedSeed = PackedSeed;

    const fn form(form: u8) -> Packed {
        Packed {
            bits: [0; 3],
            form,
            kinds: 0,
        }
    }

    /// The numbers `nums` (at most three), as an array or, with `form`
    /// [`Packed::NUMBER`], one number alone.
    fn numbers(nums: &[Num], form: u8) -> Packed {
        let mut p = Packed::form(form);
        for (i, n) in nums.iter().enumerate() {
            let (bits, kind) = match *n {
                Num::U(n) => (n, 0),
                Num::I(n) => (n as u64, 1),
                Num::F(x) => (x.to_bits(), 2),
            };
            p.bits[i] = bits;
            p.kinds |= kind << (2 * i);
        }
        p
    }

    /// Number `i`.
    fn num(&self, i: usize) -> Num {
        let bits = self.bits[i];
        match (self.kinds >> (2 * i)) & 3 {
            0 => Num::U(bits),
            1 => Num::I(bits as i64),
            _ => Num::F(f64::from_bits(bits)),
        }
    }

    /// The element as [`UniqueKeys`] would have read it, `others` giving
    /// the ones kept apart.
    fn value(&self, others: &mut impl Iterator<Item = Value>) -> Value {
        match self.form {
            n @ 0..=3 => Value::Array((0..usize::from(n)).map(|i| self.num(i).value()).collect()),
            Packed::NUMBER => self.num(0).value(),
            Packed::NULL => Value::Null,
            Packed::FALSE => Value::Bool(false),
            Packed::TRUE => Value::Bool(true),
            _ => others.next().expect("a value kept for every other element"),
        }
    }
}

/// Reads one element of a per-vertex array ([`Packed::READ`]).
#[derive(Clone, Copy)]
struct PackedSeed;

impl<'de> DeserializeSeed<'de> for PackedSeed {
    type Value = Result<Packed, Value>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for PackedSeed {
    type Value = Result<Packed, Value>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_u64<E: de::Error>(self, n: u64) -> Result<Self::Value, E> {
        Ok(Ok(Packed::numbers(&[Num::U(n)], Packed::NUMBER)))
    }
    fn visit_i64<E: de::Error>(self, n: i64) -> Result<Self::Value, E> {
        Ok(Ok(Packed::numbers(&[Num::I(n)], Packed::NUMBER)))
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Self::Value, E> {
        Ok(Ok(Packed::numbers(&[Num::F(x)], Packed::NUMBER)))
    }
    fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(Ok(Packed::form(Packed::NULL)))
    }
    fn visit_bool<E: de::Error>(self, b: bool) -> Result<Self::Value, E> {
        Ok(Ok(Packed::form(if b {
            Packed::TRUE
        } else {
            Packed::FALSE
        })))
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<Self::Value, E> {
        Ok(Err(Value::String(s.to_string())))
    }
    fn visit_string<E: de::Error>(self, s: String) -> Result<Self::Value, E> {
        Ok(Err(Value::String(s)))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut nums = [Num::U(0); 3];
        let mut n = 0;
        while let Some(x) = seq.next_element_seed(NumSeed)? {
            match x {
                Ok(x) if n < 3 => {
                    nums[n] = x;
                    n += 1;
                }
                // A fourth number, or something else: the element is
                // kept as a `Value`.
                x => {
                    let mut out: Vec<Value> = nums[..n].iter().map(|x| x.value()).collect();
                    out.push(x.map_or_else(|v| v, Num::value));
                    while let Some(v) = seq.next_element_seed(UniqueKeys)? {
                        out.push(v);
                    }
                    return Ok(Err(Value::Array(out)));
                }
            }
        }
        Ok(Ok(Packed::numbers(&nums[..n], n as u8)))
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
        UniqueVisitor.visit_map(map).map(Err)
    }
}

/// Reads a number, or (`Err`) any other value as [`UniqueKeys`] does.
struct NumSeed;

impl<'de> DeserializeSeed<'de> for NumSeed {
    type Value = Result<Num, Value>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for NumSeed {
    type Value = Result<Num, Value>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_u64<E: de::Error>(self, n: u64) -> Result<Self::Value, E> {
        Ok(Ok(Num::U(n)))
    }
    fn visit_i64<E: de::Error>(self, n: i64) -> Result<Self::Value, E> {
        Ok(Ok(Num::I(n)))
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Self::Value, E> {
        Ok(Ok(Num::F(x)))
    }
    non_numbers!(Result<Num, Value>, Err);
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
        UniqueVisitor.visit_seq(seq).map(Err)
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
        UniqueVisitor.visit_map(map).map(Err)
    }
}

/// `"records"`: an array of elements, or (`Err`) any other value, which
/// only an object definition refuses.
struct RecordsSeed;

impl<'de> DeserializeSeed<'de> for RecordsSeed {
    type Value = Result<Vec<Element>, Value>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        struct RecordsVisitor;
        impl<'de> Visitor<'de> for RecordsVisitor {
            type Value = Result<Vec<Element>, Value>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a JSON value")
            }
            other_values!(Result<Vec<Element>, Value>, Err);
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut out = Vec::new();
                while let Some(e) = seq.next_element::<Element>()? {
                    out.push(e);
                }
                Ok(Ok(out))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                Value::deserialize(MapAccessDeserializer::new(map)).map(Err)
            }
        }
        d.deserialize_any(RecordsVisitor)
    }
}

use serde::Deserialize as _;

/// `v`'s JSON text as serde_json writes it.
fn text_of(v: &Value) -> Box<RawValue> {
    serde_json::value::to_raw_value(v).expect("a Value always serializes")
}

/// JSON's insignificant whitespace (RFC 8259 §2).
fn is_json_whitespace(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r')
}

/// `raw` without the whitespace between its tokens (strings keep theirs).
/// Most values have none and are returned as they are, without copying.
pub(super) fn without_whitespace(raw: Box<RawValue>) -> Box<RawValue> {
    let text = raw.get().as_bytes();
    if !text.iter().copied().any(is_json_whitespace) {
        return raw;
    }
    let mut out: Option<Vec<u8>> = None;
    let (mut in_string, mut escaped) = (false, false);
    for (i, &b) in text.iter().enumerate() {
        if in_string {
            if escaped {
                escaped = false;
            } else if b == b'\\' {
                escaped = true;
            } else if b == b'"' {
                in_string = false;
            }
        } else if b == b'"' {
            in_string = true;
        } else if is_json_whitespace(b) {
            out.get_or_insert_with(|| text[..i].to_vec());
            continue;
        }
        if let Some(o) = &mut out {
            o.push(b);
        }
    }
    match out {
        None => raw,
        Some(o) => {
            let s = String::from_utf8(o).expect("only ASCII whitespace was removed");
            RawValue::from_string(s).expect("JSON without its insignificant whitespace")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kept_line_answers_for_keys_the_fast_path_declines_without_parsing() {
        let line = br#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"id":7}"#;
        let f = Fields::from_line(line);
        assert!(f.get("pattern").is_none() && !f.contains_key("stripe"));
        assert!(f.field("transform").is_none());
        assert!(f.list.get().is_none(), "looked up without parsing");
        assert_eq!(f.get("color"), Some(&serde_json::json!([1, 2, 3])));
        assert_eq!(f.field("id").map(|f| f.to_string()).as_deref(), Some("7"));
        assert_eq!(f.len(), 3);
    }

    fn element(text: &str) -> Element {
        serde_json::from_str(text).unwrap()
    }

    #[test]
    fn unknown_fields_keep_their_text_known_ones_are_parsed() {
        let Element::Object(o) = element(
            r#"{"id": 123456789012345678901234567890, "vertices": [[0, 1e2]], "s": "\u00e9 \/",
                "n": [ 1e400 , -0, 1.50, {"a" : "b c"} ], "pattern": {"note": 1e2}}"#,
        ) else {
            panic!()
        };
        let f = o.into_fields();
        assert_eq!(
            f.keys().collect::<Vec<_>>(),
            ["id", "vertices", "s", "n", "pattern"]
        );
        assert_eq!(
            f.field("id").unwrap().as_raw().unwrap().get(),
            "123456789012345678901234567890"
        );
        assert_eq!(f.field("s").unwrap().to_string(), r#""\u00e9 \/""#);
        assert_eq!(
            f.field("n").unwrap().to_string(),
            r#"[1e400,-0,1.50,{"a":"b c"}]"#
        );
        assert_eq!(f["vertices"][0][1], 100.0);
        assert_eq!(f.get("id"), None);
        assert_eq!(
            serde_json::to_string(&f).unwrap(),
            r#"{"id":123456789012345678901234567890,"vertices":[[0,100.0]],"s":"\u00e9 \/","n":[1e400,-0,1.50,{"a":"b c"}],"pattern":{"note":100.0}}"#
        );
    }

    #[test]
    fn a_repeated_key_is_refused_at_any_depth() {
        // Before, the last value was kept and the first dropped without a
        // word, as `Value` does (a hostile-input review: `"id": 1, "id": 2`
        // came out of polyfill3 as `"id": 2`). Before and after the list
        // of keys gets its index (16 keys).
        for n in [3, 40] {
            let mut keys = String::new();
            for i in 0..n {
                keys += &format!(",\"k{i}\":{i}");
            }
            for (dup, key) in [
                (",\"a\":2", "a"),
                (",\"color\":[4,5,6]", "color"),
                (",\"pattern\":{\"file\":\"a\",\"file\":\"b\"}", "file"),
            ] {
                let text = format!("{{\"a\":1,\"color\":[1,2,3]{keys}{dup}}}");
                let e = serde_json::from_str::<Element>(&text).unwrap_err();
                assert!(
                    e.to_string()
                        .contains(&format!("the key \"{key}\" appears twice in one object")),
                    "{n} {key}: {e}"
                );
                let e = value_with_unique_keys(&text).unwrap_err().to_string();
                assert!(e.contains("appears twice"), "{e}");
            }
        }
        let text = r#"{"a": [1, {"b": {"c": 2}}], "d": {"c": 3}}"#;
        assert_eq!(
            value_with_unique_keys(text).unwrap(),
            serde_json::from_str::<Value>(text).unwrap()
        );
        assert!(value_with_unique_keys(r#"{"a": [{"b": 1, "b": 1}]}"#).is_err());
        assert!(value_with_unique_keys("{} x").is_err());
    }

    #[test]
    fn whitespace_is_removed_outside_strings_only() {
        let raw = |s: &str| without_whitespace(RawValue::from_string(s.into()).unwrap());
        assert_eq!(raw("[1, 2]").get(), "[1,2]");
        assert_eq!(
            raw("{ \"a b\" :\t\"c \\\" d\"\r\n}").get(),
            "{\"a b\":\"c \\\" d\"}"
        );
        assert_eq!(raw("\"\\\\\" ").get(), "\"\\\\\"");
        assert_eq!(raw("7").get(), "7");
    }

    #[test]
    fn records_are_elements_and_their_field_their_text() {
        let Element::Object(mut o) = element(
            r#"{"object": "o", "records": [{"rect": [0, 0, 1, 1], "id": 1e2}, 5], "x": 1}"#,
        ) else {
            panic!()
        };
        let records = o.take_records().unwrap();
        assert_eq!(records.len(), 2);
        assert!(matches!(&records[1], Element::Other(v) if *v == 5));
        let f = o.into_fields();
        assert_eq!(
            f.field("records").unwrap().to_string(),
            r#"[{"rect":[0,0,1,1],"id":1e2},5]"#
        );
        assert_eq!(f.keys().collect::<Vec<_>>(), ["object", "records", "x"]);
    }

    /// A per-vertex field is read (counted, its elements packed) into the
    /// very `Value` the other known fields are read into, whatever its
    /// elements; other fields are as they were.
    #[test]
    fn per_vertex_fields_are_the_values_any_known_field_would_be() {
        // Past the elements read as values, the packed ones.
        let first = "[0.5,1],".repeat(READ_AS_VALUES - 1);
        let long = format!(
            r#"[{first}[0,0],[1,-2,3.5],[],[7],[1,2,3,4],[1,2,3,"x"],[1,"x",2],5,-0,1e2,
            -9223372036854775808,18446744073709551615,[1.5e300,-0.0,4.9e-324],null,true,
            false,"s",{{"a":[1,{{"b":2}}]}},[[1]],[null],[1,[2]],[{{"c":3}}]]"#
        );
        let elements = r#"[[0,0],[1,-2,3.5],[],[7],[1,2,3,4],[1,2,3,"x"],[1,"x",2],5,-0,1e2,
            -9223372036854775808,18446744073709551615,[1.5e300,-0.0,4.9e-324],null,true,
            false,"s",{"a":[1,{"b":2}]},[[1]],[null],[1,[2]],[{"c":3}]]"#;
        for text in [&long, elements, "[]", "7", "\"v\"", "{\"a\":[1,2]}", "null"] {
            let want = value_with_unique_keys(text).unwrap();
            for key in PER_VERTEX_KEYS {
                let record = format!("{{\"{key}\":{text},\"color\":[1,2,3]}}");
                let Element::Object(o) = element(&record) else {
                    panic!("{record}")
                };
                let f = o.into_fields();
                assert_eq!(f.get(key), Some(&want), "{record}");
                assert_eq!(
                    serde_json::to_string(&f).unwrap(),
                    serde_json::to_string(&serde_json::json!({key: want, "color": [1, 2, 3]}))
                        .unwrap()
                );
            }
        }
        // Repeated keys are refused inside them too.
        for first in ["", &first] {
            let text = format!(r#"{{"uv":[{first}[0,0],{{"a":1,"a":2}}]}}"#);
            let e = serde_json::from_str::<Element>(&text).unwrap_err();
            assert!(e.to_string().contains("the key \"a\" appears twice"), "{e}");
        }
    }

    /// The error of a per-vertex array past the limit is told from other
    /// data errors by its whole message, with or without a position.
    #[test]
    fn the_per_vertex_limit_is_told_by_its_message() {
        use serde::de::Error as _;
        for key in PER_VERTEX_KEYS {
            let m = per_vertex_limit(key);
            assert!(m.starts_with(&format!("{key}: at least 16777217 ")), "{m}");
            assert!(m.contains("more than the limit of 16777216"), "{m}");
            let e = serde_json::Error::custom(&m);
            assert_eq!(per_vertex_limit_in(&e).as_deref(), Some(&m[..]));
        }
        let e = serde_json::from_str::<Element>(&format!(
            r#"{{"a":1,"a":"{}"}}"#,
            per_vertex_limit("uv")
        ));
        assert_eq!(per_vertex_limit_in(&e.unwrap_err()), None);
        let e = serde_json::Error::custom(format!("x{}", per_vertex_limit("vertices")));
        assert_eq!(per_vertex_limit_in(&e), None);
    }
}
