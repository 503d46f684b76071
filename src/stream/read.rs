//! The streaming reader: a JSON array or NDJSON, one element at a time, so
//! memory does not grow with the number of records. It tells the two forms
//! apart, words JSON syntax errors with their positions in the whole input,
//! and hands each element to the record and object parsers; plain polygon
//! lines take the fast path ([`super::plain`]), a batch of lines at a time
//! in parallel, the next batch read and parsed while one is handed on.

use super::fields::{per_vertex_limit_in, Element};
use super::objects::{Instance, Item, Objects};
use super::record::Record;
use super::{plain, ReadOptions, StreamError, MAX_VERTICES};
use crate::geom::transform::Transform;
use crate::text::{BOM_FIRST, BOM_HINT};
use serde::de::{Deserializer as _, SeqAccess, Visitor};
use std::fmt;
use std::io::BufRead;

/// Reads records one at a time from a JSON array or an NDJSON stream, calling
/// `each` for every drawable record in order. Object definitions are kept and
/// their instances expanded here, each record moved by its instance's
/// transform (see [`Objects`]); a tool that must keep objects intact uses
/// [`for_each_item`] instead. Stops at the first error, which names the input
/// and the record. Memory stays bounded by the largest single record plus the
/// object definitions (and, for NDJSON, two batches of lines, each ending at
/// the line that takes it past 2 MiB, or at 8,192 lines).
///
/// `each` may fail with an error of its own type `E`, which ends the reading
/// and comes back unchanged; the stream's own errors come back as `E` too.
pub fn for_each_record<R: BufRead + Send, E: From<StreamError>>(
    reader: R,
    source: &str,
    mut each: impl FnMut(Record) -> Result<(), E>,
) -> Result<(), E> {
    let mut objects = Objects::default();
    for_each_item(reader, source, |item| {
        objects.expand(item, source, &mut each)
    })
}

/// The most records and instances [`nth_item`] expands one element into
/// (so the most records it draws): each record is whole, with its JSON
/// (measured 1.7 KB), so about 170 MB.
pub const MAX_NTH_RECORDS: u64 = 100_000;

/// Element `n` of a stream, read no further than that element, with the
/// records it draws. Elements are numbered from 0 in the order of the
/// stream, every one counting (object definitions and instances as well as
/// records): the number error messages give. A record draws itself; an
/// instance, its object's records moved by its transform (nested instances
/// expanded, as [`for_each_record`] expands them, all numbered `n`); an
/// object definition, its records as if placed untransformed; an error
/// when that expansion visits more than [`MAX_NTH_RECORDS`] records and
/// instances ([`Objects::walk`]), before it starts. The elements before it are
/// read and their names checked, not expanded. `Err(count)`
/// when the stream has only `count` elements.
pub fn nth_item<R: BufRead + Send>(
    reader: R,
    source: &str,
    n: usize,
) -> Result<Result<(Item, Vec<Record>), usize>, StreamError> {
    /// How the scan ended early: element `n` was found, or the stream failed.
    enum Stop {
        Found,
        Failed(StreamError),
    }
    impl From<StreamError> for Stop {
        fn from(e: StreamError) -> Stop {
            Stop::Failed(e)
        }
    }

    let mut objects = Objects::default();
    let mut found = None;
    let mut count = 0usize;
    let scan = for_each_item(reader, source, |item| {
        // By the element's own number: a mesh element is two items (its
        // object and its instance), both numbered as the element.
        count = item.index() + 1;
        if item.index() < n {
            // Read and checked (definitions kept, instances' objects known),
            // not expanded: nested instances multiply, and what they draw
            // before element n is not asked for.
            return match item {
                Item::Object(def) => Ok(objects.define(def).map_err(|e| e.named(source))?),
                Item::Instance(inst) => {
                    Ok(objects.check_instance(&inst).map_err(|e| e.named(source))?)
                }
                Item::Record(_) | Item::Light(_) => Ok(()),
            };
        }
        let mut drawn = Vec::new();
        // Nested instances multiply: what the expansion visits (records and
        // instances, at least what it draws) is refused past the budget
        // before it starts. It once counted only what is drawn, and an
        // empty object placed 10^12 times drew nothing for hours.
        let affordable = |walk: u64| {
            if walk <= MAX_NTH_RECORDS {
                return Ok(());
            }
            Err(Stop::Failed(
                StreamError::in_record(
                    n,
                    format!(
                        "expands to {walk} records and instances (nested instances multiply), more than the {MAX_NTH_RECORDS} that can be listed"
                    ),
                )
                .named(source),
            ))
        };
        match &item {
            Item::Record(r) => drawn.push(r.clone()),
            Item::Light(_) => {}
            Item::Object(def) => {
                let as_placed = Instance {
                    index: n,
                    object: def.name.clone(),
                    transform: Transform::default(),
                    fields: Default::default(),
                };
                objects.define(def.clone()).map_err(|e| e.named(source))?;
                affordable(objects.walk(&def.name))?;
                objects.expand(Item::Instance(as_placed), source, &mut |r| {
                    drawn.push(r);
                    Ok::<(), Stop>(())
                })?;
            }
            Item::Instance(inst) => {
                affordable(objects.walk(&inst.object))?;
                // Within the budget: every record drawn is kept.
                objects.expand(item.clone(), source, &mut |r| {
                    drawn.push(r);
                    Ok::<(), Stop>(())
                })?
            }
        }
        found = Some((item, drawn));
        Err(Stop::Found)
    });
    match scan {
        Err(Stop::Failed(e)) => Err(e),
        Err(Stop::Found) | Ok(()) => Ok(found.ok_or(count)),
    }
}

/// Like [`for_each_record`], but hands over object definitions and instances
/// as they are, for tools that forward them.
///
/// The reader is `Send` because an NDJSON stream's next lines are read on
/// another thread while the lines before them are handed on (standard
/// input as `std::io::stdin()`, whose lock is taken per read, not
/// `stdin().lock()`); `each` runs on the calling thread, in stream order.
pub fn for_each_item<R: BufRead + Send, E: From<StreamError>>(
    reader: R,
    source: &str,
    each: impl FnMut(Item) -> Result<(), E>,
) -> Result<(), E> {
    for_each_item_in(reader, source, &super::base_dir(source), each)
}

/// [`for_each_item`] with the files records name (meshes, patterns)
/// resolved against `base`, not against `source`'s folder: for a stream
/// read from elsewhere than the file `source` names (a library caller's
/// buffer, say, given its own folder).
pub fn for_each_item_in<R: BufRead + Send, E: From<StreamError>>(
    reader: R,
    source: &str,
    base: &std::path::Path,
    each: impl FnMut(Item) -> Result<(), E>,
) -> Result<(), E> {
    for_each_item_with(reader, source, base, &ReadOptions::default(), each)
}

/// [`for_each_item_in`], accepting what `options` allow beyond the format's
/// own rules (bare records for a caller that colours them).
pub fn for_each_item_with<R: BufRead + Send, E: From<StreamError>>(
    mut reader: R,
    source: &str,
    base: &std::path::Path,
    options: &ReadOptions,
    mut each: impl FnMut(Item) -> Result<(), E>,
) -> Result<(), E> {
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
    let mut handle = |value: Parsed, index: &mut usize| -> Result<(), E> {
        let item = match value {
            // A mesh: the object of its faces, then the instance placing it.
            Parsed::Element(Element::Object(o)) if o.contains_key("mesh") => {
                let [def, inst] = super::mesh::top_level(*index, o.into_fields(), base)
                    .map_err(|e| e.named(source))?;
                each(def)?;
                inst
            }
            Parsed::Element(e) => {
                Item::from_element(*index, e, base, options).map_err(|e| e.named(source))?
            }
            Parsed::Item(item) => item,
        };
        *index += 1;
        each(item)
    };
    match first {
        None => Ok(()),
        // A stream is an array or objects, one a line: anything else is
        // refused at its first byte, before a line of it is read (`/dev/zero`
        // has no newline to end one; issue 17, item 4).
        Some(b) if b != b'[' && b != b'{' => Err(stream_err(
            Some(0),
            format!(
                "invalid JSON: the stream starts with {}, not `[` (an array) or `{{` (a record){}",
                if b.is_ascii_graphic() {
                    format!("`{}`", b as char)
                } else {
                    format!("byte 0x{b:02x}")
                },
                if b == BOM_FIRST { BOM_HINT } else { "" }
            ),
        )
        .into()),
        Some(b'[') => {
            let last = std::cell::Cell::new([0; 3]);
            let mut de = serde_json::Deserializer::from_reader(Tail::new(reader, &last));
            let mut failure: Option<E> = None;
            let visitor = ArrayVisitor {
                each: &mut |e: Element| -> bool {
                    match handle(Parsed::Element(e), &mut index) {
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
            res.map_err(|e| stream_err(Some(index), json_message(&e, last.get())))?;
            de.end().map_err(|e| {
                stream_err(
                    None,
                    format!("after the array: {}", json_message(&e, last.get())),
                )
            })?;
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
            //
            // Lines come in batches, whose plain records are parsed in
            // parallel (`parse_plain_batch`) and then handed on in order, one
            // by one, as a line at a time would: each line is parsed on its
            // own, so the records, their numbers and every error are the
            // same, only the parsing is spread over the threads. The next
            // batch is read and parsed while this one is handed on: handing
            // on is one thread's work, and parsing beside it rather than
            // before it hides most of the parse. (A million triangles read
            // in 0.62 s on one thread and 0.48 on two, so about 0.34 s of
            // hand-over and 0.28 of parsing; read ahead, 0.35-0.43 s.)
            // Reading, too, is done beside the handing on, by the job that
            // parses the batch (hence `R: Send`): the read calls' copy out
            // of the kernel and the copy into the batch were a fifth of the
            // handing thread's time on polyfill3's blocks. Median of 7 read
            // phases taking turns: a million triangles 0.261 s against
            // 0.290, the blocks of demo 2 at incr 0.25 0.118 against 0.123,
            // its cells 0.434 against 0.463.
            let mut batch = Batch::default();
            let mut failed = batch.fill(&mut reader);
            let mut typed = parse_plain_batch(&batch);
            let mut next = Batch::default();
            let mut newlines = 0u64;
            loop {
                if batch.lines.is_empty() {
                    return match failed {
                        // serde_json words a read error as the error itself.
                        Some(e) => {
                            Err(stream_err(Some(index), format!("invalid JSON: {e}")).into())
                        }
                        None => Ok(()),
                    };
                }
                let mut next_typed = Vec::new();
                let mut next_failed = None;
                let handed = rayon::in_place_scope(|scope| {
                    let (next, next_typed, next_failed) =
                        (&mut next, &mut next_typed, &mut next_failed);
                    // Nor past a line cut short: serde's stream reader
                    // reads on from there.
                    let (reader, read_on) = (&mut reader, failed.is_none() && !batch.cut);
                    scope.spawn(move |_| {
                        // Nothing is read past a read error: it ends the stream.
                        match read_on {
                            true => *next_failed = next.fill(reader),
                            false => next.clear(),
                        }
                        *next_typed = parse_plain_batch(next);
                    });
                    hand_on_batch(&batch, &typed, &mut newlines, &mut index, &mut handle)
                });
                match handed? {
                    Handed::All => {}
                    Handed::Refused(m) => return Err(stream_err(Some(index), m).into()),
                    Handed::NotOneValueAt(start) => {
                        // The rest of the input from that line: the batch's
                        // bytes from there, the next batch's, then the read
                        // error either met (one at most: nothing is read
                        // after one), then the reader, unless there was one:
                        // serde_json reads on after an error inside an array
                        // (`end_seq`), and the reader must not be asked again.
                        use std::io::Read as _;
                        let failure = failed.or(next_failed);
                        let unread = if failure.is_some() { 0 } else { u64::MAX };
                        let rest = std::io::repeat(b'\n')
                            .take(newlines)
                            .chain(&batch.buf[start..])
                            .chain(&next.buf[..])
                            .chain(FailedRead(failure))
                            .chain(reader.take(unread));
                        let last = std::cell::Cell::new([0; 3]);
                        let rest = Tail::new(rest, &last);
                        let de = serde_json::Deserializer::from_reader(rest).into_iter::<Element>();
                        for e in de {
                            let e = e.map_err(|e| {
                                stream_err(Some(index), json_message(&e, last.get()))
                            })?;
                            handle(Parsed::Element(e), &mut index)?;
                        }
                        return Ok(());
                    }
                }
                if let Some(e) = failed {
                    return Err(stream_err(Some(index), format!("invalid JSON: {e}")).into());
                }
                std::mem::swap(&mut batch, &mut next);
                typed = next_typed;
                failed = next_failed;
            }
        }
    }
}

/// How far [`hand_on_batch`] got.
enum Handed {
    /// Every line of the batch.
    All,
    /// Up to the line that starts at this byte of the batch, which is not
    /// one whole JSON value: the rest of the input goes to serde_json's
    /// stream reader from there.
    NotOneValueAt(usize),
    /// Up to a line that is one record with more vertices than a polygon
    /// may have: the error's message (`fields::per_vertex_limit`), for the
    /// record being read, as serde_json's stream reader would give it.
    Refused(String),
}

/// Hands on each line of `batch` in order: its typed view from `typed`
/// ([`parse_plain_batch`]) if it is a plain polygon record, else the JSON
/// value the line holds. `newlines` counts the lines handed on.
fn hand_on_batch<E>(
    batch: &Batch,
    typed: &[PlainRun],
    newlines: &mut u64,
    index: &mut usize,
    handle: &mut impl FnMut(Parsed, &mut usize) -> Result<(), E>,
) -> Result<Handed, E> {
    let views = typed.iter().flat_map(|run| {
        run.views
            .iter()
            .map(|v| v.as_ref().map(|v| (v, &run.verts)))
    });
    for (k, pre) in views.enumerate() {
        let (start, end) = batch.lines[k];
        let line = &batch.buf[start..end];
        let body = trim_json_whitespace(line);
        if !body.is_empty() {
            if let Some((view, verts)) = pre {
                let rec = view.record(verts, body, *index);
                handle(Parsed::Item(Item::Record(rec)), index)?;
            } else {
                match serde_json::from_slice::<Element>(body) {
                    Ok(e) => handle(Parsed::Element(e), index)?,
                    // Read as far as the element past the limit: not again.
                    Err(e) => match per_vertex_limit_in(&e) {
                        Some(m) => return Ok(Handed::Refused(m)),
                        None => return Ok(Handed::NotOneValueAt(start)),
                    },
                }
            }
        }
        if line.last() == Some(&b'\n') {
            *newlines += 1;
        }
    }
    if batch.cut {
        // Read as far as its array past the limit: the error serde_json's
        // stream reader would give (it reads the same bytes first), found
        // faster from memory. Anything else is left to that reader.
        let (start, end) = batch.lines[batch.lines.len() - 1];
        let body = trim_json_whitespace(&batch.buf[start..end]);
        if let Some(m) = serde_json::from_slice::<Element>(body)
            .err()
            .and_then(|e| per_vertex_limit_in(&e))
        {
            return Ok(Handed::Refused(m));
        }
        return Ok(Handed::NotOneValueAt(start));
    }
    Ok(Handed::All)
}

/// A reader that fails with the read error it holds (once), or is empty:
/// the read error the next batch met, in its place in the input.
struct FailedRead(Option<std::io::Error>);

impl std::io::Read for FailedRead {
    fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
        match self.0.take() {
            Some(e) => Err(e),
            None => Ok(0),
        }
    }
}

/// At most this many bytes of lines are read before a batch is parsed (a
/// longer line is read whole, alone)...
const BATCH_BYTES: usize = 1 << 21;
/// ... and at most this many lines: enough for each thread to parse a few
/// thousand records between two hand-overs.
const BATCH_LINES: usize = 8192;

/// NDJSON lines read together, each with its newline.
#[derive(Default)]
struct Batch {
    buf: Vec<u8>,
    /// Each line's range in `buf`.
    lines: Vec<(usize, usize)>,
    /// Whether the last line was cut short where [`LongLine`] found more
    /// elements in one of its per-vertex arrays than a polygon may have: it
    /// is left to serde's stream reader, from its start, and nothing more
    /// is read into batches.
    cut: bool,
}

impl Batch {
    /// Empties the batch.
    fn clear(&mut self) {
        self.buf.clear();
        self.lines.clear();
        self.cut = false;
    }

    /// The lines read whole: all but one [cut short](Batch::cut).
    fn whole_lines(&self) -> &[(usize, usize)] {
        &self.lines[..self.lines.len() - usize::from(self.cut)]
    }

    /// Reads the next batch; a read error ends it early and is returned
    /// after the lines read before it. The bytes of the line it cut short
    /// stay in `buf`, after the last line: a value spread over lines before
    /// it reads them, as serde's stream reader would have, before the error
    /// (with its position; dropped, a whole last record went missing too).
    ///
    /// The reader's buffer is searched for newlines with `memchr` (vector
    /// instructions) and copied a buffer at a time, not a line at a time as
    /// `read_until` does with a call per line and a search a word at a
    /// time: reading and projecting 100,000 random triangles took 544 M
    /// instructions against 564 M (callgrind). The batch ends as it would
    /// line by line: at the line that takes it to [`BATCH_BYTES`], or at
    /// [`BATCH_LINES`] lines.
    ///
    /// A line longer than [`LONG_LINE`] is counted as it is read
    /// ([`LongLine`]), and cut short ([`Batch::cut`]) once it has too many
    /// vertices for a polygon.
    fn fill(&mut self, reader: &mut impl BufRead) -> Option<std::io::Error> {
        self.clear();
        // Where the line being read starts in `buf`.
        let mut line_start = 0;
        // The count of a long line, once it is long.
        let mut long: Option<LongLine> = None;
        loop {
            let available = match reader.fill_buf() {
                Ok(a) => a,
                // As `read_until`: an interrupted read is tried again.
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Some(e),
            };
            if available.is_empty() {
                if line_start < self.buf.len() {
                    self.lines.push((line_start, self.buf.len()));
                }
                return None;
            }
            let (mut used, mut full) = (available.len(), false);
            for newline in memchr::memchr_iter(b'\n', available) {
                let end = self.buf.len() + newline + 1;
                self.lines.push((line_start, end));
                line_start = end;
                if end >= BATCH_BYTES || self.lines.len() >= BATCH_LINES {
                    (used, full) = (newline + 1, true);
                    break;
                }
            }
            self.buf.extend_from_slice(&available[..used]);
            reader.consume(used);
            if full {
                return None;
            }
            if self.buf.len() - line_start > LONG_LINE {
                let count = match &mut long {
                    Some(l) if l.start == line_start => l,
                    stale => stale.insert(LongLine::new(line_start)),
                };
                if count.too_many(&self.buf) {
                    self.lines.push((line_start, self.buf.len()));
                    self.cut = true;
                    return None;
                }
            }
        }
    }
}

/// A line longer than this is counted as it is read ([`LongLine`]): few
/// are (a polygon of some 100,000 vertices), so the count costs nothing on
/// the lines streams hold.
const LONG_LINE: usize = BATCH_BYTES;

/// The count of a line too long to take on trust ([`LONG_LINE`]): the
/// elements of every array under a key that holds one per vertex
/// (`"vertices"`, `"uv"`, `"normals"`, or a key with an escape, which may
/// spell one), at any depth, so that [`Batch::fill`] stops reading the line
/// once one of them has more than [`MAX_VERTICES`] elements. The line is
/// then read by serde's stream reader (`fields::PerVertex`), which stops at
/// the element past the limit and words the error: read whole first, an
/// endless `"vertices"` line grew by 4 GB in 5 s until memory ran out.
///
/// It counts right for any valid JSON, and only ever sends a line to
/// serde's stream reader, which reads it as the line would have been read
/// (the same records, the same errors): a miscount on a line that is not
/// JSON costs time, not a different answer.
struct LongLine {
    /// Where the line starts in the batch, and how far it has been counted.
    start: usize,
    counted: usize,
    in_string: bool,
    escaped: bool,
    /// The string being read, as far as a per-vertex key goes (a longer
    /// one has `key_len` 9), and whether it has an escape.
    key: [u8; 8],
    key_len: usize,
    key_escaped: bool,
    /// 1 after a string that may be a per-vertex key, 2 after its colon.
    after_key: u8,
    /// How many arrays and objects are open.
    depth: usize,
    /// The per-vertex arrays open, innermost last: their depth (inside
    /// them) and their commas so far.
    arrays: Vec<(usize, usize)>,
    /// The most elements one may have: [`MAX_VERTICES`] (less in tests).
    limit: usize,
}

impl LongLine {
    fn new(start: usize) -> LongLine {
        LongLine {
            start,
            counted: start,
            in_string: false,
            escaped: false,
            key: [0; 8],
            key_len: 0,
            key_escaped: false,
            after_key: 0,
            depth: 0,
            arrays: Vec::new(),
            limit: MAX_VERTICES,
        }
    }

    /// Counts the line's bytes in `buf` not yet counted: whether a
    /// per-vertex array now has more than [`MAX_VERTICES`] elements (as
    /// many commas as that: the element after the last one is on its way).
    /// Stops there, at the comma.
    fn too_many(&mut self, buf: &[u8]) -> bool {
        for &b in &buf[self.counted..] {
            self.counted += 1;
            if self.in_string {
                if self.escaped {
                    self.escaped = false;
                } else if b == b'\\' {
                    (self.escaped, self.key_escaped) = (true, true);
                } else if b == b'"' {
                    self.in_string = false;
                    let key = self.key.get(..self.key_len).unwrap_or_default();
                    let per_vertex = matches!(key, b"vertices" | b"uv" | b"normals");
                    self.after_key = u8::from(per_vertex || self.key_escaped);
                } else if self.key_len < 9 {
                    if let Some(k) = self.key.get_mut(self.key_len) {
                        *k = b;
                    }
                    self.key_len += 1;
                }
                continue;
            }
            match b {
                b' ' | b'\t' | b'\n' | b'\r' => continue,
                b'"' => {
                    (self.in_string, self.key_len, self.key_escaped) = (true, 0, false);
                }
                b':' if self.after_key == 1 => {
                    self.after_key = 2;
                    continue;
                }
                b'[' | b'{' => {
                    self.depth += 1;
                    if b == b'[' && self.after_key == 2 {
                        self.arrays.push((self.depth, 0));
                    }
                }
                b']' | b'}' => {
                    if self.arrays.last().is_some_and(|a| a.0 == self.depth) {
                        self.arrays.pop();
                    }
                    self.depth = self.depth.saturating_sub(1);
                }
                b',' => {
                    if let Some(a) = self.arrays.last_mut().filter(|a| a.0 == self.depth) {
                        a.1 += 1;
                        if a.1 >= self.limit {
                            return true;
                        }
                    }
                }
                _ => {}
            }
            self.after_key = 0;
        }
        false
    }
}

/// Lines parsed together by one thread ([`parse_plain_batch`]): each one's
/// typed view if it is a plain polygon record, their vertices in one list.
struct PlainRun {
    views: Vec<Option<plain::PlainView>>,
    verts: Vec<glam::DVec3>,
}

/// How many lines a parsing job takes at once: enough that its vertex list
/// and views are a few allocations among hundreds of records.
const RUN_LINES: usize = 512;

/// The typed view of each line of `batch` that is a plain polygon record
/// ([`plain::parse`]), in parallel, in runs of [`RUN_LINES`] lines, in order.
fn parse_plain_batch(batch: &Batch) -> Vec<PlainRun> {
    use rayon::prelude::*;
    batch
        .whole_lines()
        .par_chunks(RUN_LINES)
        .map(|lines| {
            let mut run = PlainRun {
                views: Vec::with_capacity(lines.len()),
                verts: Vec::with_capacity(3 * lines.len()),
            };
            for &(start, end) in lines {
                let body = trim_json_whitespace(&batch.buf[start..end]);
                let view = (!body.is_empty())
                    .then(|| plain::parse(body, &mut run.verts))
                    .flatten();
                run.views.push(view);
            }
            run
        })
        .collect()
}

/// A stream element as the readers hand it on: parsed JSON (unknown fields
/// kept as text), or an item the NDJSON fast path has already typed. Moved once per record straight into
/// the handler, so its size costs nothing, where boxing the item would cost
/// an allocation per record.
#[allow(clippy::large_enum_variant)]
enum Parsed {
    Element(Element),
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

/// serde_json's message with its position, phrased for a user, `last`
/// being the last three bytes serde_json read ([`Tail`]): a lone UTF-16
/// surrogate (`"\ud800"`) is said to be one, where serde_json speaks of a
/// hex escape that ended early, and a `NaN` or `Infinity` (which
/// JavaScript and Python's `json.dumps` write) is named, where serde_json
/// says only that it expected a value.
fn json_message(e: &serde_json::Error, last: [u8; 3]) -> String {
    // Not a syntax error: a record with too many vertices, found as it was
    // read (`fields::PerVertex`), worded as the record's own errors are.
    if let Some(m) = per_vertex_limit_in(e) {
        return m;
    }
    let text = e.to_string();
    let surrogate = ["unexpected end of hex escape", "lone leading surrogate"]
        .iter()
        .any(|m| text.contains(m));
    // Where a value starts, serde_json stops at the first byte of `NaN`,
    // `Infinity` or `inf`, one byte after the `I` of `-Infinity` or `-inf`,
    // and at the third byte of `nan` (as read on 2026-12-01, serde_json 1).
    let not_finite = e.is_syntax()
        && matches!(
            last,
            [_, _, b'N' | b'I' | b'i'] | [b'-', b'I' | b'i', b'n'] | [b'n', b'a', b'n']
        );
    if surrogate {
        format!(
            "invalid JSON: {text} (a \\uD800-\\uDFFF escape must be one half of a \
             surrogate pair: a string is Unicode text)"
        )
    } else if not_finite {
        format!("invalid JSON: {text} (JSON has no NaN or Infinity: every number must be finite)")
    } else {
        format!("invalid JSON: {text}")
    }
}

/// A reader that keeps the last three bytes read from it, for
/// [`json_message`]: serde_json reads a stream one byte a call, and stops
/// at the byte it cannot take. It buffers what it reads (serde_json's one
/// byte a call through it cost the array reader 17-35% of its time
/// unbuffered, `BufReader`'s own fast path for single bytes being lost
/// behind it).
struct Tail<'a, R> {
    inner: R,
    buf: Vec<u8>,
    at: usize,
    last: &'a std::cell::Cell<[u8; 3]>,
}

impl<'a, R> Tail<'a, R> {
    fn new(inner: R, last: &'a std::cell::Cell<[u8; 3]>) -> Self {
        Tail {
            inner,
            buf: Vec::new(),
            at: 0,
            last,
        }
    }
}

impl<R: std::io::Read> std::io::Read for Tail<'_, R> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        const CHUNK: usize = 1 << 16;
        if let (Some(&b), [slot]) = (self.buf.get(self.at), &mut *out) {
            // serde_json's call: one byte.
            *slot = b;
            self.at += 1;
            let [_, x, y] = self.last.get();
            self.last.set([x, y, b]);
            return Ok(1);
        }
        if self.at == self.buf.len() {
            self.buf.resize(CHUNK, 0);
            self.at = 0;
            let n = self
                .inner
                .read(&mut self.buf)
                .inspect_err(|_| self.buf.clear())?;
            self.buf.truncate(n);
        }
        let n = out.len().min(self.buf.len() - self.at);
        out[..n].copy_from_slice(&self.buf[self.at..self.at + n]);
        self.at += n;
        let mut last = self.last.get();
        for &b in &out[n.saturating_sub(3)..n] {
            last = [last[1], last[2], b];
        }
        self.last.set(last);
        Ok(n)
    }
}

/// Streams the elements of a JSON array to a callback without collecting them.
struct ArrayVisitor<'a> {
    each: &'a mut dyn FnMut(Element) -> bool,
}

impl<'de> Visitor<'de> for ArrayVisitor<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of records")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while let Some(v) = seq.next_element::<Element>()? {
            if !(self.each)(v) {
                // Stop early: the caller reports its own error.
                return Ok(());
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{err, read_all};
    use super::*;
    use crate::geom::Shape;
    use glam::DVec3;

    /// `NaN` and `Infinity` (as JavaScript and Python's `json.dumps` write
    /// them) got serde_json's "expected value", naming neither (a
    /// hostile-input review): now they are named, in a line of NDJSON or in
    /// an array, and other mistakes are left as serde_json words them.
    #[test]
    fn nan_and_infinity_are_said_to_be_not_json() {
        let hint = "(JSON has no NaN or Infinity: every number must be finite)";
        for (literal, hinted) in [
            ("NaN", true),
            ("Infinity", true),
            ("-Infinity", true),
            ("nan", true),
            ("inf", true),
            ("-inf", true),
            ("none", false),
            ("tru", false),
            ("1e999", false),
            ("1.2.3", false),
        ] {
            let record = format!(r#"{{"vertices":[[0,0],[{literal},0],[0,1]],"color":[1,2,3]}}"#);
            for text in [format!("{record}\n"), format!("[{record}]")] {
                let e = err(&text);
                assert!(e.contains("invalid JSON: "), "{text}: {e}");
                assert_eq!(e.contains(hint), hinted, "{text}: {e}");
            }
        }
    }

    /// A hostile-input review: a lone UTF-16 surrogate in a key or a
    /// string that is read got serde_json's "unexpected end of hex escape",
    /// which is not what is wrong.
    #[test]
    fn a_lone_surrogate_is_said_to_be_one() {
        let tri = r#""vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]"#;
        for text in [
            format!(r#"{{"\ud800":1,{tri}}}"#),
            format!(r#"{{{tri},"pattern":{{"file":"\ud800.pat"}}}}"#),
            format!(r#"[{{{tri},"pattern":{{"file":"\udc00\u0041.pat"}}}}]"#),
        ] {
            let e = err(&text);
            assert!(e.contains("invalid JSON: "), "{text}: {e}");
            assert!(e.contains("one half of a surrogate pair"), "{text}: {e}");
        }
        // A pair is a character, and other escapes are as serde_json says.
        let pair = format!(r#"{{{tri},"name":"\ud83d\ude00"}}"#);
        assert!(read_all(&pair).is_ok());
        let e = err(&format!(r#"{{{tri},"pattern":{{"file":"\u00zz"}}}}"#));
        assert!(!e.contains("surrogate"), "{e}");
    }

    #[test]
    fn nth_item_stops_at_the_element_or_counts_them() {
        // Record 1 is found although the stream breaks after it.
        let text = "{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n{\"rect\":[0,0,1,1],\"color\":[1,2,3],\"id\":7}\n{broken";
        let (item, drawn) = nth_item(text.as_bytes(), "t", 1).unwrap().unwrap();
        assert!(
            matches!(item, Item::Record(ref r) if r.fields.field("id").unwrap().to_string() == "7")
        );
        assert_eq!(drawn.len(), 1);
        assert_eq!(drawn[0].fields.field("id").unwrap().to_string(), "7");
        let good = "{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n";
        assert_eq!(nth_item(good.as_bytes(), "t", 5).unwrap().unwrap_err(), 1);
        assert!(nth_item(text.as_bytes(), "t", 2).is_err());
    }

    #[test]
    fn nth_item_numbers_definitions_and_instances_as_errors_do() {
        // Element 0 defines `tri`, 1 defines `pair` (two `tri`s), 2 places
        // `pair`, 3 is an instance of an unknown object.
        let text = r#"{"object": "tri", "records": [{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3]}]}
            {"object": "pair", "records": [{"instance": "tri"}, {"instance": "tri", "transform": {"translate": [5, 0, 0]}}]}
            {"instance": "pair", "transform": {"translate": [0, 7, 0]}}
            {"instance": "ghost"}"#;
        let nth = |n| nth_item(text.as_bytes(), "t", n);
        let (item, drawn) = nth(0).unwrap().unwrap();
        assert!(matches!(item, Item::Object(ref d) if d.name == "tri"));
        assert_eq!(drawn.len(), 1);
        let (item, drawn) = nth(1).unwrap().unwrap();
        assert!(matches!(item, Item::Object(ref d) if d.name == "pair"));
        assert_eq!(drawn.len(), 2);
        let (item, drawn) = nth(2).unwrap().unwrap();
        assert!(matches!(item, Item::Instance(ref i) if i.object == "pair"));
        assert!(drawn.iter().all(|r| r.index == 2));
        let Shape::Polygon(v) = &drawn[1].shape else {
            panic!("{:?}", drawn[1].shape)
        };
        assert_eq!(v[0], DVec3::new(5.0, 7.0, 0.0));
        let e = format!("{:#}", nth(3).unwrap_err());
        assert_eq!(
            e,
            "t: record 3: instance of unknown object `ghost` (define it first)"
        );
        assert_eq!(nth(4).unwrap_err().to_string(), e);
        let ok = &text[..text.rfind('\n').unwrap()];
        assert_eq!(nth_item(ok.as_bytes(), "t", 3).unwrap().unwrap_err(), 3);
    }

    #[test]
    fn array_and_ndjson_give_the_same_records() {
        let a = r#"[{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"id":"a"},
                    {"rect":[0,0,2,2],"color":[0,0,0]}]"#;
        let n = "{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3],\"id\":\"a\"}\n{\"rect\":[0,0,2,2],\"color\":[0,0,0]}\n";
        assert_eq!(read_all(a).unwrap(), read_all(n).unwrap());
        let r = read_all(a).unwrap();
        assert_eq!(r[0].fields.field("id").unwrap().to_string(), r#""a""#);
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
            .into_iter::<serde_json::Value>()
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
            format!("s.json: record 3: {}", json_message(&whole, [0; 3]))
        );
    }

    #[test]
    fn batches_number_records_and_place_errors_as_one_line_at_a_time_would() {
        // More lines than one batch holds: plain records (parsed in
        // parallel), rects (the general path) and blank lines (no record)
        // interleaved, then a value spread over two lines in the second
        // batch, more records, and a syntax error.
        let mut text = String::new();
        let mut elements = 0;
        for k in 0..BATCH_LINES + 300 {
            if k % 11 == 5 {
                text.push('\n');
                continue;
            }
            if k % 7 == 3 {
                text += &format!("{{\"rect\":[0,0,1,1],\"color\":[1,2,3],\"n\":{elements}}}\n");
            } else {
                text += &plain_line(elements + 1);
            }
            elements += 1;
        }
        text += "{\"rect\":[0,0,1,1],\n \"color\":[4,5,6]}\n";
        text += "{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n";
        let records = read_all(&text).unwrap();
        assert_eq!(records.len(), elements + 2);
        for (i, r) in records.iter().enumerate() {
            assert_eq!(r.index, i);
            match &r.shape {
                Shape::Polygon(v) if i < elements && v.len() == 3 => {
                    assert_eq!(v[2].y, (i + 1) as f64, "record {i}")
                }
                _ => {}
            }
        }
        assert_eq!(records[elements].color, Some(crate::color::Rgb8([4, 5, 6])));
        let broken = format!("{text}{{\"vertices\": [[0,0]] x\n");
        let whole = serde_json::Deserializer::from_str(&broken)
            .into_iter::<serde_json::Value>()
            .find_map(Result::err)
            .unwrap();
        assert_eq!(
            err(&broken),
            format!(
                "s.json: record {}: {}",
                elements + 2,
                json_message(&whole, [0; 3])
            )
        );
    }

    /// A value spread over lines in the first batch, while the second is
    /// already read and parsed: the rest of the input (the first batch from
    /// that line, the second, the reader) goes to the stream reader whole,
    /// and every record comes as a line at a time would give it.
    #[test]
    fn a_spread_value_early_hands_on_the_batch_read_ahead_too() {
        let mut text: String = (1..=100).map(plain_line).collect();
        text += "{\"rect\":[0,0,1,1],\n \"color\":[4,5,6]}\n";
        text.extend((101..=2 * BATCH_LINES + 50).map(plain_line));
        let records = read_all(&text).unwrap();
        assert_eq!(records.len(), 2 * BATCH_LINES + 51);
        assert_eq!(records[100].color, Some(crate::color::Rgb8([4, 5, 6])));
        for (i, r) in records.iter().enumerate() {
            assert_eq!(r.index, i);
            if let Shape::Polygon(v) = &r.shape {
                let k = if i < 100 { i + 1 } else { i };
                assert_eq!(v[2].y, k as f64, "record {i}");
            }
        }
    }

    /// A plain polygon line, its third vertex at height `k`.
    fn plain_line(k: usize) -> String {
        format!("{{\"vertices\":[[0,0],[1,0],[0,{k}]],\"color\":[1,2,3]}}\n")
    }

    /// A reader of `bytes`, then one error, then the end: an error read
    /// again would hide one that was dropped.
    struct FailsAfter<'a>(&'a [u8], bool);

    impl std::io::Read for FailsAfter<'_> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            if self.0.is_empty() {
                return match std::mem::replace(&mut self.1, true) {
                    false => Err(std::io::Error::other("the disk is gone")),
                    true => Ok(0),
                };
            }
            let n = out.len().min(self.0.len()).min(4096);
            out[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// A reader that must not be read again once it has failed: the stream
    /// ends at a read error (serde_json's own stream reader asks again).
    struct NotAfterError<R>(R, bool);

    impl<R: std::io::Read> std::io::Read for NotAfterError<R> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            assert!(!self.1, "read again after its error");
            let r = self.0.read(out);
            self.1 = r.is_err();
            r
        }
    }

    /// How many records the reader hands on from `bytes` read through
    /// [`FailsAfter`], and the error it ends with; nothing is read after
    /// the error.
    fn records_then_error(bytes: &[u8]) -> (usize, String) {
        let mut n = 0;
        let reader = std::io::BufReader::new(NotAfterError(FailsAfter(bytes, false), false));
        let e = for_each_record(reader, "s.json", |_| {
            n += 1;
            Ok::<(), StreamError>(())
        })
        .unwrap_err();
        (n, e.to_string())
    }

    /// The lines of `text` as batches cut them, read through a buffer of
    /// `capacity` bytes, each batch's count of lines after it.
    fn batched(text: &[u8], capacity: usize) -> (Vec<&[u8]>, Vec<usize>) {
        let mut reader = std::io::BufReader::with_capacity(capacity, text);
        let (mut lines, mut counts, mut batch) = (Vec::new(), Vec::new(), Batch::default());
        // Where the batch's first line starts in `text`.
        let mut offset = 0;
        loop {
            assert!(batch.fill(&mut reader).is_none());
            if batch.lines.is_empty() {
                return (lines, counts);
            }
            counts.push(batch.lines.len());
            // The batch's bytes are its lines, in order, each whole.
            let mut at = 0;
            for &(start, end) in &batch.lines {
                assert_eq!(start, at);
                lines.push(&text[offset + start..offset + end]);
                assert_eq!(&batch.buf[start..end], *lines.last().unwrap());
                at = end;
            }
            assert_eq!(at, batch.buf.len());
            offset += at;
        }
    }

    #[test]
    fn batches_cut_lines_as_read_until_would_whatever_the_buffer() {
        // Lines of every length up to 40, blank ones, `\r\n`, no newline
        // at the end.
        let text: Vec<u8> = (0..200usize)
            .flat_map(|k| {
                let mut l = vec![b'x'; k % 41];
                l.extend_from_slice(if k % 7 == 0 { b"\r\n" } else { b"\n" });
                l
            })
            .chain(*b"last")
            .collect();
        let want: Vec<&[u8]> = text.split_inclusive(|&b| b == b'\n').collect();
        for capacity in [1, 2, 3, 7, 40, 41, 64, 1 << 16] {
            assert_eq!(batched(&text, capacity), (want.clone(), vec![want.len()]));
        }
        // An interrupted read is tried again, as `read_until` does.
        struct Interrupted<'a>(&'a [u8], usize);
        impl std::io::Read for Interrupted<'_> {
            fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
                self.1 += 1;
                if self.1 % 2 == 1 {
                    return Err(std::io::ErrorKind::Interrupted.into());
                }
                self.0.read(out)
            }
        }
        let mut reader = std::io::BufReader::with_capacity(16, Interrupted(&text, 0));
        let mut batch = Batch::default();
        assert!(batch.fill(&mut reader).is_none());
        assert_eq!(batch.buf, text);
        // A batch ends at BATCH_LINES lines...
        let text = b"{}\n".repeat(2 * BATCH_LINES + 5);
        assert_eq!(batched(&text, 1000).1, [BATCH_LINES, BATCH_LINES, 5]);
        // ... or at the line that takes it to BATCH_BYTES: lines of 1 KiB
        // reach it exactly at a line's end.
        let line = [vec![b' '; 1023], vec![b'\n']].concat();
        let text = line.repeat(3000);
        let first = BATCH_BYTES / 1024;
        assert_eq!(batched(&text, 4096).1, [first, 3000 - first]);
    }

    /// A reader that fails after its text: the error comes after every
    /// record before it, numbered as the next record, whether the failing
    /// batch was read ahead of lines still handed on one by one or of a
    /// value spread over lines.
    #[test]
    fn a_read_error_in_the_batch_read_ahead_comes_after_the_records_before_it() {
        let lines: String = (1..=BATCH_LINES + 300).map(plain_line).collect();
        let spread = format!(
            "{}{{\"rect\":[0,0,1,1],\n \"color\":[4,5,6]}}\n{}",
            plain_line(1),
            lines
        );
        for text in [lines.clone(), spread] {
            let records = text.matches("\"color\"").count();
            assert_eq!(
                records_then_error(text.as_bytes()),
                (
                    records,
                    format!("s.json: record {records}: invalid JSON: the disk is gone")
                )
            );
        }
    }

    /// A read error in the middle of a line, after a value spread over
    /// lines (so the rest of the input goes to serde's stream reader): in
    /// the batch read ahead and in the spread value's own batch, the bytes
    /// before the error are read, and the error comes where serde's stream
    /// reader over the whole input puts it, record number and position. A
    /// review found the batch read ahead dropping the cut line (the
    /// position went, or a record), and the spread value's own batch
    /// ending the stream without the error, exit status 0.
    #[test]
    fn a_read_error_mid_line_after_a_spread_value_comes_where_serde_puts_it() {
        let mut text: String = (1..=3).map(plain_line).collect();
        text += "{\"rect\":[0,0,1,1],\n \"color\":[4,5,6]}\n";
        text.extend((4..=BATCH_LINES + 300).map(plain_line));
        let line_start = |k: usize| text.match_indices('\n').nth(k - 1).unwrap().0 + 1;
        // In the spread value's batch, then in the next: inside a line,
        // and with all of a line but its newline.
        for (cut, mid_value) in [
            (line_start(100) + 10, true),
            (line_start(BATCH_LINES + 50) + 10, true),
            (line_start(BATCH_LINES + 51) - 1, false),
        ] {
            let bytes = &text.as_bytes()[..cut];
            let mut values = serde_json::Deserializer::from_reader(FailsAfter(bytes, false))
                .into_iter::<serde_json::Value>();
            let mut ok = 0;
            let want = loop {
                match values.next().expect("the reader fails") {
                    Ok(_) => ok += 1,
                    Err(e) => break e,
                }
            };
            let (n, e) = records_then_error(bytes);
            assert_eq!(n, ok, "cut at {cut}");
            assert_eq!(
                e,
                format!("s.json: record {ok}: {}", json_message(&want, [0; 3])),
                "cut at {cut}"
            );
            // Inside a value serde says where; between values it cannot.
            assert_eq!(e.contains(" at line "), mid_value, "{e}");
        }
    }

    #[test]
    fn empty_input_is_an_empty_stream() {
        assert!(read_all("").unwrap().is_empty());
        assert!(read_all(" \n ").unwrap().is_empty());
        assert!(read_all("[]").unwrap().is_empty());
    }

    #[test]
    fn a_byte_order_mark_is_named() {
        let e = err("\u{feff}{\"rect\": [0,0,1,1], \"color\": [0,0,0]}");
        assert!(
            e.contains("starts with byte 0xef, not `[` (an array) or `{` (a record) (a UTF-8 byte-order mark starts so: save the file without one)"),
            "{e}"
        );
        assert!(!err("x").contains("byte-order"));
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
        // In a known field, in either form; an unknown field is kept as
        // text, which has no depth limit (`unknown_fields_are_any_json`).
        let deep_known = format!(
            "{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"pattern\":{}1{}}}",
            "[".repeat(100_000),
            "]".repeat(100_000)
        );
        assert!(err(&deep_known).contains("record 0: invalid JSON"));
        assert!(err(&format!("[{deep_known}]")).contains("record 0: invalid JSON"));
        let deep_record = format!(
            "{{\"object\":\"o\",\"records\":{}1{}}}",
            "[".repeat(100_000),
            "]".repeat(100_000)
        );
        assert!(err(&deep_record).contains("record 0: invalid JSON"));
    }

    #[test]
    fn unknown_fields_are_any_json_known_ones_must_parse() {
        // Kept as text, an unknown field's numbers have no range and its
        // nesting no depth limit; only its syntax is checked.
        let deep = format!("{}1{}", "[".repeat(100_000), "]".repeat(100_000));
        for (x, form) in [
            ("1e999", "ndjson"),
            ("-1e400", "array"),
            (&deep[..], "ndjson"),
        ] {
            let rec = format!("{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"x\":{x}}}");
            let text = if form == "array" {
                format!("[{rec}]")
            } else {
                rec
            };
            let r = read_all(&text).unwrap();
            assert_eq!(r[0].fields.field("x").unwrap().to_string(), x);
        }
        for bad in ["[1,]", "01", "1e", "\"\\x\"", "[1 2]", "nul"] {
            for text in [
                format!("{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"x\":{bad}}}"),
                format!("[{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"x\":{bad}}}]"),
            ] {
                assert!(err(&text).contains("record 0: invalid JSON"), "{text}");
            }
        }
        // Invalid UTF-8 in an unknown string, as in a known one.
        let mut bytes = br#"{"rect":[0,0,1,1],"color":[0,0,0],"x":"a"#.to_vec();
        bytes.extend_from_slice(b"\xff\"}");
        let e = for_each_record(&bytes[..], "s.json", |_| Ok::<(), StreamError>(()));
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("record 0: invalid JSON"));
    }

    #[test]
    fn an_error_in_the_callback_stops_the_array_stream() {
        let text = r#"[{"rect":[0,0,1,1],"color":[0,0,0]},{"rect":[0,0,1,1],"color":[0,0,0]}]"#;
        let mut seen = 0;
        let r = for_each_record(text.as_bytes(), "s", |_| {
            seen += 1;
            Err(StreamError::in_record(7, "stop"))
        });
        assert_eq!(seen, 1);
        assert_eq!(r.unwrap_err().to_string(), ": record 7: stop");
    }

    /// A reader of `head`, then `unit` over and over, without end,
    /// counting the bytes read from it in `read`.
    struct Endless<'a> {
        head: &'a [u8],
        unit: &'a [u8],
        at: usize,
        read: &'a std::sync::atomic::AtomicU64,
    }

    impl std::io::Read for Endless<'_> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            let mut n = 0;
            while n < out.len() {
                let piece = match self.head.get(self.at..) {
                    Some(head) if !head.is_empty() => head,
                    _ => &self.unit[(self.at - self.head.len()) % self.unit.len()..],
                };
                let k = piece.len().min(out.len() - n);
                out[n..n + k].copy_from_slice(&piece[..k]);
                (n, self.at) = (n + k, self.at + k);
            }
            self.read
                .fetch_add(n as u64, std::sync::atomic::Ordering::Relaxed);
            Ok(n)
        }
    }

    /// A record one vertex over the limit once needed 6.6 GB, a `Value`
    /// tree of its vertices, and ran out of memory instead of naming the
    /// limit: now each per-vertex array is counted as it is read. Here a
    /// whole line in memory (as `pat-info --record` reads a file).
    #[test]
    fn a_record_one_vertex_over_the_limit_is_refused_naming_the_limit() {
        let mut text = String::with_capacity(6 * MAX_VERTICES + 64);
        text += "{\"vertices\":[";
        for _ in 0..MAX_VERTICES {
            text += "[0,0],";
        }
        text += "[1,1]],\"color\":[1,2,3]}\n";
        assert_eq!(
            err(&text),
            format!(
                "s.json: record 0: vertices: at least {} vertices is more than the limit of \
                 {MAX_VERTICES}",
                MAX_VERTICES + 1
            )
        );
    }

    /// An endless per-vertex array, on a line or in an array: reading
    /// stops within a buffer of the element past the limit, with the
    /// limit's error. Read whole first, an endless `"vertices"` line grew
    /// by 4 GB in 5 s until memory ran out.
    #[test]
    fn an_endless_vertex_array_is_refused_once_it_passes_the_limit() {
        let over = MAX_VERTICES + 1;
        let tri = "\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]";
        // The stream's start, what repeats, the error, and its record: a
        // line after another (cut short by the batch reader), an array
        // (serde_json's stream reader), whose elements, counted whatever
        // they are, are numbers (as many elements in a third of the bytes:
        // that reader is slow).
        for (head, unit, message, index) in [
            (
                format!("{}{{\"vertices\":[", plain_line(1)),
                "[0,0],",
                format!(
                    "vertices: at least {over} vertices is more than the limit of {MAX_VERTICES}"
                ),
                1,
            ),
            (
                format!("[{{{tri}}},\n{{{tri},\"normals\":["),
                "0,",
                format!(
                    "normals: at least {over} is more than the limit of {MAX_VERTICES} \
                     vertices (one per vertex)"
                ),
                1,
            ),
        ] {
            let read = std::sync::atomic::AtomicU64::new(0);
            let reader = std::io::BufReader::with_capacity(
                1 << 16,
                Endless {
                    head: head.as_bytes(),
                    unit: unit.as_bytes(),
                    at: 0,
                    read: &read,
                },
            );
            let mut records = 0;
            let e = for_each_record(reader, "s.json", |_| {
                records += 1;
                Ok::<(), StreamError>(())
            })
            .unwrap_err();
            assert_eq!(records, index, "{head}");
            assert_eq!(e.to_string(), format!("s.json: record {index}: {message}"));
            let read = read.into_inner();
            let limit_worth = (head.len() + unit.len() * over) as u64;
            assert!(
                (limit_worth - (1 << 20)..=limit_worth + (1 << 20)).contains(&read),
                "{head}: {read} bytes read for {limit_worth}"
            );
        }
    }

    /// The count of a long line: elements of arrays under a per-vertex key,
    /// at any depth, whatever the strings hold, fed in pieces.
    #[test]
    fn a_long_line_counts_the_elements_of_per_vertex_arrays() {
        // Whether `line`, fed a byte at a time and at once, has an array
        // of more than 3 elements under a per-vertex key.
        let too_many = |line: &str| {
            let whole = {
                let mut l = LongLine::new(0);
                l.limit = 3;
                l.too_many(line.as_bytes())
            };
            let mut l = LongLine::new(0);
            l.limit = 3;
            let bytewise = (1..=line.len()).any(|n| l.too_many(&line.as_bytes()[..n]));
            assert_eq!(whole, bytewise, "{line}");
            whole
        };
        for line in [
            r#"{"vertices":[[0,0],[1,0],[0,1],[1,1]]"#,
            r#"{"vertices" : [ 1 , 2 , 3 , 4 ]}"#,
            r#"{"uv":[[0,0],[1,0],[0,1],[1,1]]}"#,
            r#"{"normals":[[0,0,1],[0,0,1],[0,0,1],[0,0,1]"#,
            r#"{"object":"o","records":[{"vertices":[{},{},"a",[[]],"#,
            r#"{"x":{"vertices":[1,2,3,4]}}"#,
            r#"{"vert\u0069ces":[1,2,3,4]}"#,
            r#"{"vertices":[["a,b,c,d"],2,3,4]}"#,
            r#"{"vertices":[{"vertices":[1,2]},2,3,4]}"#,
        ] {
            assert!(too_many(line), "{line}");
        }
        for line in [
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3,4,5]}"#,
            r#"{"vertices":[[0,0,0,0,0,0]],"uv":[[1,2,3,4,5]]}"#,
            r#"{"verticesx":[1,2,3,4],"xuv":[1,2,3,4],"v":[1,2,3,4]}"#,
            r#"{"name":"vertices","x":[1,2,3,4]}"#,
            r#"{"vertices":"[1,2,3,4]","uv":{"a":1,"b":2,"c":3,"d":4}}"#,
            r#"{"s":"\"vertices\":[1,2,3,4]"}"#,
            r#"{"vertices":[1,2,3]} {"vertices":[1,2,3]}"#,
        ] {
            assert!(!too_many(line), "{line}");
        }
    }

    /// A line too long for a batch is counted (it may be cut short), and
    /// read as before when it is not: a polygon of 200,000 vertices, and
    /// an unknown field of a few MB, through a small buffer.
    #[test]
    fn long_lines_read_as_before() {
        let n = 200_000;
        let ring: Vec<String> = (0..n)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                format!("[{},{}]", crate::math::cos(a), crate::math::sin(a))
            })
            .collect();
        let polygon = format!(
            "{{\"vertices\":[{}],\"color\":[1,2,3],\"id\":7}}\n",
            ring.join(",")
        );
        let note = format!(
            "{{\"rect\":[0,0,1,1],\"color\":[1,2,3],\"note\":{{\"vertices\":[{}]}}}}\n",
            ring.join(" , ")
        );
        let text = format!(
            "{}{polygon}{}{note}{}",
            plain_line(1),
            plain_line(2),
            plain_line(3)
        );
        assert!(polygon.len().min(note.len()) > LONG_LINE);
        let whole = read_all(&text).unwrap();
        assert_eq!(whole.len(), 5);
        let mut batched = Vec::new();
        let reader = std::io::BufReader::with_capacity(4096, text.as_bytes());
        for_each_record(reader, "s.json", |r| {
            batched.push(r);
            Ok::<(), StreamError>(())
        })
        .unwrap();
        assert_eq!(batched, whole);
        assert!(matches!(&whole[1].shape, Shape::Polygon(v) if v.len() == n));
    }
}
