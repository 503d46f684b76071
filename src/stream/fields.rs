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
        fn visit_bool<E: de::Error>(self, b: bool) -> Result<$out, E> {
            Ok($wrap(Value::Bool(b)))
        }
        fn visit_i64<E: de::Error>(self, n: i64) -> Result<$out, E> {
            Ok($wrap(Value::from(n)))
        }
        fn visit_u64<E: de::Error>(self, n: u64) -> Result<$out, E> {
            Ok($wrap(Value::from(n)))
        }
        fn visit_f64<E: de::Error>(self, x: f64) -> Result<$out, E> {
            Ok($wrap(Value::from(x)))
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
        d.deserialize_any(UniqueVisitor)
    }
}

/// The error of a key repeated in one JSON object.
fn repeated_key<E: de::Error>(key: &str) -> E {
    E::custom(format_args!(
        "the key \"{key}\" appears twice in one object: which one is meant?"
    ))
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
}
