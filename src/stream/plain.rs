//! The fast path of the NDJSON reader: a *plain* polygon record (one line
//! holding `"vertices"` and `"color"`, any other fields being ones the typed
//! view ignores) is deserialized straight into its typed form, without first
//! building a `serde_json::Value` for every coordinate. That tree was most of
//! the time of reading a large stream (issue 4: 1M triangles read in 2.4 s of
//! a 2.9 s run).
//!
//! The fast path only ever *accepts* a record that [`Record::from_value`]
//! would accept with the very same typed view; anything else (another
//! geometry, a pattern, uv, a stripe, an object or instance, a missing colour,
//! too few vertices, a polygon that is not simple, a duplicate key, a number
//! of the wrong kind) makes it
//! decline, and the caller runs the general path on the same line, so every
//! error message stays what it was. Fields other than the two it reads are
//! still checked as the general path checks them (known fields parsed as
//! `Value`, unknown ones as `RawValue`, then dropped), so a line the general
//! path would reject for them (a number out of range in a known field, say)
//! is declined too. The record's JSON object ([`Record::fields`]) is parsed
//! from the kept line only when a tool asks for it.
//!
//! Two routes lead there: a hand-written scanner (`scan`) that reads the
//! vertices and colour without serde's visitors, and, for whatever it does
//! not know, serde with the visitors below. Both accept the same lines with
//! the same numbers, which their tests check bit for bit.

use super::{is_value_key, Fields, Record, MAX_VERTICES};
use crate::color::Rgb8;
use crate::geom::Shape;
use glam::DVec3;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::value::RawValue;
use serde_json::Value;
use std::fmt;

mod scan;

use scan::Scanned;

/// The typed view of `line` (one JSON value, surrounding whitespace trimmed)
/// as record `index`, if it is a plain polygon record; `None` sends the line
/// to the general path. (The reader uses [`parse`] and [`PlainView::record`]
/// on different threads.)
#[cfg(test)]
pub(super) fn record(line: &[u8], index: usize) -> Option<Record> {
    let mut verts = Vec::new();
    let view = parse(line, &mut verts)?;
    Some(view.record(&verts, line, index))
}

/// A plain line parsed ([`parse`]): its vertices in the list it was given,
/// and its colour.
pub(super) struct PlainView {
    start: usize,
    len: usize,
    color: [u8; 3],
}

/// Parses `line` as a plain polygon record, its vertices appended to
/// `verts`; `None` (with `verts` as it was) sends the line to the general
/// path. The parsing threads share one list per run of lines, and the
/// record's own vertex list and fields are made by [`PlainView::record`]
/// on the thread that hands the records on: allocated by a parsing thread
/// and freed by the other, each record's blocks had that thread's `malloc`
/// search its arena, a third of its time.
pub(super) fn parse(line: &[u8], verts: &mut Vec<DVec3>) -> Option<PlainView> {
    let start = verts.len();
    let color = match scan::vertices_and_color(line, verts) {
        Scanned::Plain(c) => c,
        Scanned::TooMany => {
            // Up to MAX_VERTICES points were read into the run's list:
            // not kept while the general path reads the line again.
            verts.shrink_to_fit();
            return None;
        }
        Scanned::Other => {
            let plain: Plain = serde_json::from_slice(line).ok()?;
            let (Some(v), Some(c)) = (plain.vertices, plain.color) else {
                return None;
            };
            verts.extend(v);
            c
        }
    };
    let v = &verts[start..];
    if v.len() < 3
        || v.len() > MAX_VERTICES
        || !v.iter().all(|p| p.is_finite())
        || crate::geom::simple::check(v).is_err()
    {
        verts.truncate(start);
        return None;
    }
    Some(PlainView {
        start,
        len: v.len(),
        color,
    })
}

impl PlainView {
    /// Record `index` of `line`, whose vertices [`parse`] put in `verts`.
    pub(super) fn record(&self, verts: &[DVec3], line: &[u8], index: usize) -> Record {
        Record {
            index,
            shape: Shape::Polygon(verts[self.start..self.start + self.len].into()),
            color: Some(Rgb8(self.color)),
            pattern: None,
            uv: None,
            normals: None,
            shade: Default::default(),
            fields: Fields::from_line(line),
        }
    }
}

/// What the fast path reads of a record.
struct Plain {
    vertices: Option<Vec<DVec3>>,
    color: Option<[u8; 3]>,
}

/// Whether a line holding key `k` is left to the general path: every known
/// field ([`is_value_key`]) but the two the fast path reads and the two
/// polyfill3 writes on each cell ("texel", "cells", which the typed view
/// does not read), so the other geometries (quadrics too: with "vertices" they make
/// the record ambiguous, which the general path words), the fields
/// `Record::from_value` reads, a "transform" (it moves the record) and the
/// keys that make an item an object or an instance (`Item::from_value`);
/// and "records", read as records. A known key added later is declined
/// until the fast path learns it. So a line the fast path kept never holds
/// one of these, which [`Fields::field`] answers without parsing the line.
pub(super) fn declines(k: &str) -> bool {
    (is_value_key(k) && !matches!(k, "vertices" | "color" | "texel" | "cells")) || k == "records"
}

/// A record's key, as the fast path sorts them.
enum Key {
    Vertices,
    Color,
    /// A key that changes the typed view beyond a plain polygon: decline.
    Decline,
    /// Another known field ([`is_value_key`]): parsed as `Value`, as
    /// [`Record::fields`] will parse it.
    Value(String),
    /// Any other key: its text is kept in [`Record::fields`], so only its
    /// syntax is checked (as `RawValue`, as the fields will read it).
    Raw(String),
}

impl<'de> de::Deserialize<'de> for Key {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Key, D::Error> {
        struct KeyVisitor;
        impl Visitor<'_> for KeyVisitor {
            type Value = Key;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a field name")
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<Key, E> {
                Ok(match s {
                    "vertices" => Key::Vertices,
                    "color" => Key::Color,
                    k if declines(k) => Key::Decline,
                    k if is_value_key(k) => Key::Value(k.to_string()),
                    k => Key::Raw(k.to_string()),
                })
            }
        }
        d.deserialize_identifier(KeyVisitor)
    }
}

impl<'de> de::Deserialize<'de> for Plain {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Plain, D::Error> {
        struct PlainVisitor;
        impl<'de> Visitor<'de> for PlainVisitor {
            type Value = Plain;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a plain polygon record")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Plain, A::Error> {
                let mut p = Plain {
                    vertices: None,
                    color: None,
                };
                // The other keys, to decline a repeated one, which the
                // general path refuses with its position.
                let mut others: Vec<String> = Vec::new();
                let mut repeated = |k: &String| {
                    let again = others.contains(k);
                    others.push(k.clone());
                    again
                };
                while let Some(key) = map.next_key::<Key>()? {
                    match key {
                        // A repeated key: the general path keeps the last
                        // value; declining is simpler than matching that.
                        Key::Vertices if p.vertices.is_some() => {
                            return Err(de::Error::custom("repeated vertices"))
                        }
                        Key::Color if p.color.is_some() => {
                            return Err(de::Error::custom("repeated color"))
                        }
                        Key::Vertices => p.vertices = Some(map.next_value_seed(Vertices)?),
                        Key::Color => p.color = Some(map.next_value::<[u8; 3]>()?),
                        Key::Decline => return Err(de::Error::custom("not a plain record")),
                        Key::Value(k) | Key::Raw(k) if repeated(&k) => {
                            return Err(de::Error::custom("repeated key"))
                        }
                        Key::Value(_) => {
                            map.next_value::<Value>()?;
                        }
                        Key::Raw(_) => {
                            map.next_value::<&RawValue>()?;
                        }
                    }
                }
                Ok(p)
            }
        }
        d.deserialize_map(PlainVisitor)
    }
}

/// `[[x,y] or [x,y,z], ...]`, parsed into points (z = 0 for `[x,y]`, as
/// `parse_vertices` does).
struct Vertices;

impl<'de> DeserializeSeed<'de> for Vertices {
    type Value = Vec<DVec3>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<DVec3>, D::Error> {
        struct SeqVisitor;
        impl<'de> Visitor<'de> for SeqVisitor {
            type Value = Vec<DVec3>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of points")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<DVec3>, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(4).min(64));
                while let Some(Point(p)) = seq.next_element::<Point>()? {
                    if out.len() == MAX_VERTICES {
                        return Err(de::Error::custom("too many vertices"));
                    }
                    out.push(p);
                }
                Ok(out)
            }
        }
        d.deserialize_seq(SeqVisitor)
    }
}

/// One vertex: two or three numbers.
struct Point(DVec3);

impl<'de> de::Deserialize<'de> for Point {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Point, D::Error> {
        struct PointVisitor;
        impl<'de> Visitor<'de> for PointVisitor {
            type Value = Point;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("[x,y] or [x,y,z]")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Point, A::Error> {
                let mut c = [0.0f64; 3];
                let mut n = 0;
                while let Some(x) = seq.next_element::<f64>()? {
                    if n == 3 {
                        return Err(de::Error::custom("more than 3 coordinates"));
                    }
                    c[n] = x;
                    n += 1;
                }
                if n < 2 {
                    return Err(de::Error::custom("fewer than 2 coordinates"));
                }
                Ok(Point(DVec3::new(c[0], c[1], c[2])))
            }
        }
        d.deserialize_seq(PointVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The general path's record for the same line.
    fn general(line: &str) -> Result<Record, super::super::StreamError> {
        from_element(7, serde_json::from_str(line).unwrap())
    }

    /// The general path's record for one element.
    fn from_element(
        index: usize,
        e: super::super::fields::Element,
    ) -> Result<Record, super::super::StreamError> {
        let options = super::super::ReadOptions::default();
        match super::super::Item::from_element(index, e, std::path::Path::new("."), &options)? {
            super::super::Item::Record(r) => Ok(r),
            other => panic!("not a record: {other:?}"),
        }
    }

    #[test]
    fn a_plain_record_is_read_exactly_as_the_general_path_reads_it() {
        for line in [
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"name":"x","vertices":[[-0.5,1e3,2],[1,-0,0.25],[0.1,1,-7]],"color":[255,0,9],"texel":[1,2]}"#,
            r#"{"color":[0,0,0],"vertices":[[1.7976931348623157e308,0],[5e-324,0],[0,12345678901234567890]]}"#,
            // Unknown fields are kept as text: any number, any spelling.
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"id":123456789012345678901234567890,"x":[1e400,-0,1.50],"s":"\u00e9\/"}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":{"records":[1e2]}}"#,
        ] {
            let fast = record(line.as_bytes(), 7).expect("plain");
            let slow = general(line).unwrap();
            assert_eq!(fast, slow, "{line}");
            assert_eq!(fast.fields, slow.fields, "{line}");
            assert_eq!(
                serde_json::to_string(&fast.fields).unwrap(),
                serde_json::to_string(&slow.fields).unwrap()
            );
        }
    }

    #[test]
    fn anything_else_is_left_to_the_general_path() {
        for line in [
            // Other geometries and typed fields.
            r#"{"rect":[0,0,1,1],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"sphere":{"radius":1}}"#,
            r#"{"disk":{"outer":1},"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"a.pat"}}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"uv":[[0,0],[1,0],[0,1]]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"stripe":{"code":3},"color":[1,2,3]}"#,
            r#"{"object":"o","records":[]}"#,
            // Errors the general path words itself.
            r#"{"vertices":[[0,0],[1,0]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,1],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1,2,3]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,"1"]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,256]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3.0]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"transform":1e400}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"transform":{"translate":[1,2,3]}}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"texel":[1e400,0]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":[1,]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"records":[]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"[1,2,3]"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]} {}"#,
        ] {
            assert!(record(line.as_bytes(), 0).is_none(), "{line}");
        }
    }

    #[test]
    fn a_polygon_line_with_a_quadric_key_is_ambiguous_as_in_the_general_path() {
        // The fast path once took "sphere" for a field it may ignore.
        let line = r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"sphere":{"radius":1}}"#;
        assert_eq!(
            super::super::testing::err(line),
            "s.json: record 0: several geometries (vertices, sphere): expected exactly one"
        );
    }

    /// A JSON number or something in its place: integers, decimals,
    /// exponents, negative zero, and a few tokens the general path rejects.
    fn token() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        prop_oneof![
            (-300i64..300).prop_map(|i| i.to_string()),
            any::<f64>()
                .prop_filter("finite", |x| x.is_finite())
                .prop_map(|x| format!("{x:?}")),
            (-1e6f64..1e6).prop_map(|x| format!("{x:e}")),
            Just("-0".to_string()),
            Just("1e400".to_string()),
            Just("\"7\"".to_string()),
            Just("null".to_string()),
        ]
    }

    proptest::proptest! {
        /// Whatever line it is given, the fast path either declines or
        /// yields exactly the general path's record (typed view and fields),
        /// and the reader as a whole gives the general path's answer.
        #[test]
        fn the_fast_path_never_disagrees_with_the_general_path(
            points in proptest::collection::vec(proptest::collection::vec(token(), 1..5), 1..6),
            color in proptest::collection::vec(token(), 2..5),
            extra in proptest::option::of(token()),
            color_first in proptest::bool::ANY,
        ) {
            let verts = format!(
                "\"vertices\":[{}]",
                points.iter().map(|p| format!("[{}]", p.join(","))).collect::<Vec<_>>().join(",")
            );
            let col = format!("\"color\":[{}]", color.join(","));
            let mut parts = if color_first { vec![col, verts] } else { vec![verts, col] };
            if let Some(x) = extra {
                parts.push(format!("\"extra\":{x}"));
            }
            let line = format!("{{{}}}", parts.join(","));
            let general = serde_json::from_str::<super::super::fields::Element>(&line)
                .map_err(|e| e.to_string())
                .and_then(|v| from_element(0, v).map_err(|e| e.message));
            if let Some(fast) = record(line.as_bytes(), 0) {
                let slow = general.clone().expect("the general path accepts what the fast path does");
                proptest::prop_assert_eq!(&fast, &slow);
                proptest::prop_assert_eq!(&fast.fields, &slow.fields);
            }
            let mut read = Vec::new();
            let whole = super::super::for_each_record(line.as_bytes(), "p.json", |r| {
                read.push(r);
                Ok::<(), super::super::StreamError>(())
            });
            match (whole, general) {
                (Ok(()), Ok(g)) => proptest::prop_assert_eq!(read, vec![g]),
                (Err(e), Err(m)) => {
                    let e = e.to_string();
                    proptest::prop_assert!(e.contains(&*m) || e.contains("invalid JSON"), "{} vs {}", e, m);
                }
                (w, g) => proptest::prop_assert!(false, "reader {:?} vs general {:?}", w.map_err(|e| e.to_string()), g),
            }
        }
    }
}
