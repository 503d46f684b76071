//! The polygon stream (docs/stream-format.md): one JSON array of records, or NDJSON.
//!
//! Records are read one at a time whichever form the input takes, so memory does
//! not grow with the number of records. Every record keeps its full JSON object
//! ([`Record::fields`]), unknown fields as the text they were written in, so
//! tools that forward records pass them through unchanged (see [`Fields`] for
//! exactly what that means); the typed view ([`Record::shape`],
//! [`Record::pattern`], ...) is what the geometry and the renderer use.
//!
//! One file per idea; every public name is re-exported here, so callers write
//! `stream::Record`, `stream::for_each_record`, ...:
//!
//! - `fields.rs`: a record's JSON object ([`Fields`], [`Field`]): known fields
//!   parsed, unknown ones kept as written, parsed lazily on the fast path.
//! - `record.rs`: one record, its typed view ([`Record`], [`PatternRef`],
//!   [`PatternMode`]) and the field parsers (vertices, colour, pattern, uv,
//!   quadric parameters).
//! - `objects.rs`: object definitions and instances ([`Item`], [`Objects`]),
//!   and moving a record by an instance's transform ([`transform_record`]).
//! - `triangles.rs`: a quadric record as triangle records, for tools that
//!   forward polygons ([`for_each_quadric_triangle`]).
//! - `read.rs`: the streaming reader of both forms ([`for_each_record`],
//!   [`for_each_item`]) and its JSON error messages.
//! - `plain.rs`: the reader's fast path for plain NDJSON polygon lines.
//! - `write.rs`: writing records as NDJSON ([`write_ndjson`]).
//! - `paths.rs`: resolving the file names records hold ([`base_dir`],
//!   [`resolve`]).
//!
//! This file keeps what they all share: [`StreamError`], [`ReadOptions`] and
//! [`MAX_VERTICES`].

use std::fmt;

mod fields;
pub mod mesh;
pub mod obj;
mod objects;
mod paths;
mod plain;
mod read;
mod record;
mod triangles;
mod write;

pub use fields::{is_value_key, value_with_unique_keys, Field, Fields};
pub use objects::{
    transform_record, Instance, Item, LightDef, ObjectDef, Objects, INSTANCE_CURVE_TOLERANCE,
    MAX_OBJECT_DEPTH,
};
pub use paths::{base_dir, forward_file_refs, names_files, resolve, FileIds, RefTarget};
pub use read::{
    for_each_item, for_each_item_in, for_each_item_with, for_each_record, nth_item, MAX_NTH_RECORDS,
};
pub use record::{parse_color, PatternMode, PatternRef, Record, PATTERN_KEYS, QUADRIC_KEYS};
pub use triangles::{for_each_quadric_triangle, quadric_triangle_bound};
pub use write::write_ndjson;

/// A stream error, naming the input and the record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StreamError {
    /// The input's name as the user gave it (`-` for standard input). Empty
    /// when [`Objects`] raises the error: the reader fills it in.
    pub source: String,
    /// 0-based record index, when the error belongs to one record.
    pub record: Option<usize>,
    /// What is wrong, without the input and record, which `Display` adds.
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

impl StreamError {
    /// An error of record `index`, its input not yet named: the reader, which
    /// knows the input, names it ([`StreamError::named`]).
    pub fn in_record(index: usize, message: impl Into<String>) -> StreamError {
        StreamError {
            source: String::new(),
            record: Some(index),
            message: message.into(),
        }
    }

    /// The error with its input named `source`, unless it names one already.
    pub fn named(mut self, source: &str) -> StreamError {
        if self.source.is_empty() {
            self.source = source.to_string();
        }
        self
    }
}

/// What a reader accepts beyond the stream format's own rules
/// ([`for_each_item_with`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Whether a polygon record (vertices, rect, circle or arc) may come
    /// with no `"color"`, `"pattern"` or `"stripe"`: a *bare* record, which
    /// the caller colours itself, as `polyfill3 --pattern` gives it the
    /// pattern. Quadrics still need one.
    ///
    /// Default value: `false` (a bare record is an error naming it).
    pub bare_records: bool,
}

/// The most vertices one polygon may have: 2^24 (16.7 million). Past that a
/// record is certainly a mistake, and the limit keeps memory bounded.
pub const MAX_VERTICES: usize = 1 << 24;

/// Reading a whole stream from text, for the tests of every file.
#[cfg(test)]
mod testing {
    use super::*;

    pub(super) fn read_all(text: &str) -> Result<Vec<Record>, StreamError> {
        let mut out = Vec::new();
        for_each_record(text.as_bytes(), "s.json", |r| {
            out.push(r);
            Ok::<(), StreamError>(())
        })?;
        Ok(out)
    }

    pub(super) fn err(text: &str) -> String {
        read_all(text).unwrap_err().to_string()
    }
}
