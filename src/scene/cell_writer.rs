//! The output side of `polyfill3`'s partition ([`super::polyfill`]): texel
//! cells turned into NDJSON records, formatted in parallel batches and
//! written in the order the partition gave them.

use crate::error::OptionError;
use crate::geom::merge::{BlockMerger, Merge, RunMerger};
use crate::geom::CellSink;
use crate::pat::Pattern;
use crate::stream::{self, Record};
use crate::view::ViewVolume;
use glam::DVec3;
use std::io::Write;
use std::ops::Range;
use std::rc::Rc;

/// Fields an output record does not carry over: the geometry, the colour and
/// the pattern are replaced by the cell's; per-vertex normals belong to the
/// record's vertices, not the cell's (a cell is flat: in a lit scene it is
/// lit flat, by its plane).
const REPLACED: [&str; 9] = [
    "vertices", "rect", "circle", "arc", "color", "pattern", "uv", "texel", "normals",
];

/// Bytes of output gathered before they are handed to the output stream.
const FLUSH_BYTES: usize = 1 << 16;

/// Cells held before they are formatted: about 2 MB of text at demo 2's
/// 236 bytes a cell...
const BATCH_CELLS: usize = 8192;
/// ... or fewer, once their text would pass about this many bytes: a
/// record's other fields come out in each of its cells, and a long one
/// (an animated transform's keyframes, a long string) would otherwise make
/// the batch's text 8,192 times its length. Over one record's text, the
/// batch's memory stays within this bound whatever the input.
const BATCH_BYTES: usize = 4 << 20;

/// Cells one formatting job takes: formatting is nearly all of
/// `polyfill3`'s time (the float text alone more than half), and jobs this
/// size keep both cores busy with a few dozen jobs per batch.
const JOB_CELLS: usize = 512;

/// One output record waiting to be formatted.
struct PendingCell {
    /// Texel column and row.
    texel: [u32; 2],
    color: [u8; 3],
    /// Cells merged into this polygon (`"cells"` is written above 1).
    cells: usize,
    /// Its vertices in [`Pending::verts`].
    verts: Range<usize>,
    /// Its input record's other fields in [`Pending::fields_text`].
    fields: Range<usize>,
}

/// The cells of a batch, in output order.
#[derive(Default)]
struct Pending {
    cells: Vec<PendingCell>,
    verts: Vec<DVec3>,
    /// `,"key":value` for every field carried over, one run per input record
    /// with cells in the batch, and the current record's last.
    fields_text: Vec<u8>,
    /// The current input record's run in `fields_text`.
    current_fields: Range<usize>,
    /// About how many bytes the batch's text will take (see
    /// [`BATCH_BYTES`]).
    text_bytes: usize,
}

impl Pending {
    fn clear(&mut self) {
        self.cells.clear();
        self.verts.clear();
        self.fields_text.clear();
        self.current_fields = 0..0;
        self.text_bytes = 0;
    }
}

/// What one formatting job keeps from record to record.
struct Formatter {
    floats: RecentFloats,
    staging: Staging,
}

/// Texts of recently written floats, direct-mapped by their bits.
/// Neighbouring cells share their corners, and a grid's cells their rows'
/// and columns' coordinates, so the same floats come again and again; their
/// formatting (`zmij`) had been half of polyfill3's time. With this cache,
/// the staging block and the parallel batches, demo 2's faces at incr 0.25
/// are written in 0.11 s instead of 0.38 (bench/RESULTS-stream.md).
struct RecentFloats {
    zmij: zmij::Buffer,
    slots: Vec<FloatText>,
}

/// A float's shortest round-trip text, as `zmij` writes it.
#[derive(Clone, Copy)]
struct FloatText {
    bits: u64,
    len: u8,
    text: [u8; MAX_PIECE],
}

/// Slots of [`RecentFloats`]: 2 to this power.
const RECENT_BITS: u32 = 8;
const RECENT_FLOATS: usize = 1 << RECENT_BITS;

/// The slot of a float's bits: Fibonacci hashing (the top bits of the
/// product mix all of `bits`).
fn slot(bits: u64) -> usize {
    (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - RECENT_BITS)) as usize
}

impl RecentFloats {
    fn new() -> RecentFloats {
        RecentFloats {
            zmij: zmij::Buffer::new(),
            slots: vec![
                FloatText {
                    // No finite float has these bits: a NaN's.
                    bits: u64::MAX,
                    len: 0,
                    text: [0; MAX_PIECE],
                };
                RECENT_FLOATS
            ],
        }
    }

    /// The text of finite `x`: remembered, or written now.
    #[inline]
    fn text(&mut self, x: f64) -> &FloatText {
        let bits = x.to_bits();
        let e = &mut self.slots[slot(bits)];
        if e.bits != bits {
            let s = self.zmij.format_finite(x).as_bytes();
            e.bits = bits;
            e.len = s.len() as u8;
            e.text[..s.len()].copy_from_slice(s);
        }
        e
    }
}

impl Formatter {
    fn new() -> Formatter {
        Formatter {
            floats: RecentFloats::new(),
            staging: Staging::new(),
        }
    }

    /// Formats one record:
    /// `{"vertices":[...],"color":[r,g,b],"texel":[c,r]` (`,"cells":n` for a
    /// merged run), the input's other fields, `}` and a newline.
    ///
    /// Floats are written by `zmij`, the formatter serde_json itself uses, so
    /// the text is the one serde_json would write. A record of at most
    /// [`STAGED_VERTICES`] vertices is put together in the staging block and
    /// joins `b` in one copy.
    fn cell(&mut self, b: &mut Vec<u8>, cell: &PendingCell, pending: &Pending) {
        let verts = &pending.verts[cell.verts.clone()];
        if verts.len() <= STAGED_VERTICES {
            self.staging.len = 0;
            head(&mut self.floats, &mut self.staging, cell, verts);
            b.extend_from_slice(self.staging.text());
        } else {
            head(&mut self.floats, b, cell, verts);
        }
        b.extend_from_slice(&pending.fields_text[cell.fields.clone()]);
        b.extend_from_slice(b"}\n");
    }
}

/// A record's own fields, up to its input record's other fields.
fn head<T: Text>(floats: &mut RecentFloats, b: &mut T, cell: &PendingCell, verts: &[DVec3]) {
    b.put(b"{\"vertices\":[");
    for (i, p) in verts.iter().enumerate() {
        if i > 0 {
            b.put_byte(b',');
        }
        b.put_byte(b'[');
        for (n, x) in [p.x, p.y, p.z].into_iter().enumerate() {
            if n > 0 {
                b.put_byte(b',');
            }
            // -0.0 is written as 0.0: the same point, and stabler text.
            b.put_float(floats.text(x + 0.0));
        }
        b.put_byte(b']');
    }
    let [r, g, bl] = cell.color;
    b.put(b"],\"color\":[");
    put_uint(b, r as u64);
    b.put_byte(b',');
    put_uint(b, g as u64);
    b.put_byte(b',');
    put_uint(b, bl as u64);
    b.put(b"],\"texel\":[");
    put_uint(b, cell.texel[0] as u64);
    b.put_byte(b',');
    put_uint(b, cell.texel[1] as u64);
    b.put_byte(b']');
    if cell.cells > 1 {
        b.put(b",\"cells\":");
        put_uint(b, cell.cells as u64);
    }
}

/// Appends an unsigned integer in decimal (`write!` costs more than the rest
/// of a record's integers together).
fn put_uint<T: Text>(b: &mut T, mut n: u64) {
    let mut d = [0u8; 20];
    let mut i = d.len();
    loop {
        i -= 1;
        d[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    b.put(&d[i..]);
}

/// Where [`head`] writes: the output's `Vec`, or a [`Staging`]
/// block.
trait Text {
    /// Appends at most [`MAX_PIECE`] bytes.
    fn put(&mut self, s: &[u8]);
    fn put_byte(&mut self, c: u8);
    fn put_float(&mut self, f: &FloatText) {
        self.put(&f.text[..f.len as usize]);
    }
}

impl Text for Vec<u8> {
    #[inline]
    fn put(&mut self, s: &[u8]) {
        self.extend_from_slice(s);
    }
    #[inline]
    fn put_byte(&mut self, c: u8) {
        self.push(c);
    }
}

/// Longest piece [`Text::put`] takes: a float's shortest text is at most 24
/// bytes (`-1.2345678901234567e-308`), an integer's 20.
const MAX_PIECE: usize = 32;

/// Most vertices of a record put together in a [`Staging`] block: 3 floats
/// of at most 25 bytes with their commas and brackets, 8 times, is 616
/// bytes; the colour, texel and cells fields at most 100 more.
const STAGED_VERTICES: usize = 8;

/// Room in a [`Staging`] block: a staged record's text, and a piece's
/// worth of slack after it.
const STAGING_BYTES: usize = 768 + MAX_PIECE;

/// A record's text put together with fixed-size copies. The floats' and
/// integers' texts are 1 to 24 bytes long; appending them to a `Vec` calls
/// `memcpy` for each, and those calls were 30% of `polyfill3`'s time. Here
/// a float is one copy of [`MAX_PIECE`] bytes (the slack after the text
/// takes what lies past its end), and another piece of n bytes two
/// overlapping copies of 16 (8, 4) bytes, its first and its last; the
/// compiler turns both into plain loads and stores.
struct Staging {
    bytes: [u8; STAGING_BYTES],
    len: usize,
}

impl Staging {
    fn new() -> Staging {
        Staging {
            bytes: [0; STAGING_BYTES],
            len: 0,
        }
    }

    fn text(&self) -> &[u8] {
        &self.bytes[..self.len]
    }
}

/// Copies `s` (`N <= s.len() <= 2N`) into `d` as its first N and its last N
/// bytes.
#[inline(always)]
fn copy_ends<const N: usize>(d: &mut [u8], s: &[u8]) {
    let n = s.len();
    let head: [u8; N] = s[..N].try_into().expect("N bytes");
    let tail: [u8; N] = s[n - N..].try_into().expect("N bytes");
    d[..N].copy_from_slice(&head);
    d[n - N..n].copy_from_slice(&tail);
}

impl Text for Staging {
    #[inline]
    fn put(&mut self, s: &[u8]) {
        let n = s.len();
        assert!(n <= MAX_PIECE, "a piece of at most {MAX_PIECE} bytes");
        let d = &mut self.bytes[self.len..self.len + MAX_PIECE];
        match n {
            16.. => copy_ends::<16>(d, s),
            8..=15 => copy_ends::<8>(d, s),
            4..=7 => copy_ends::<4>(d, s),
            _ => d.iter_mut().zip(s).for_each(|(d, s)| *d = *s),
        }
        self.len += n;
    }
    #[inline]
    fn put_byte(&mut self, c: u8) {
        self.bytes[self.len] = c;
        self.len += 1;
    }
    #[inline]
    fn put_float(&mut self, f: &FloatText) {
        self.bytes[self.len..self.len + MAX_PIECE].copy_from_slice(&f.text);
        self.len += f.len as usize;
    }
}

/// The output side of a partition: turns cells into NDJSON records.
///
/// Cells are gathered into batches (`BATCH_CELLS`, `BATCH_BYTES`), and a
/// batch is formatted in parallel, `JOB_CELLS` to a job, on the current
/// rayon pool; the jobs' texts are written in order, so the output is
/// the same byte for byte whatever the number of threads. Each record is
/// `{"vertices":[...],"color":[r,g,b],"texel":[c,r]` followed by the input's
/// other fields, serialized once per input polygon.
pub struct CellWriter<W: Write> {
    out: W,
    /// With culling: cells wholly outside this volume are not written.
    pub volume: Option<ViewVolume>,
    pattern: Option<Rc<Pattern>>,
    /// Text on its way to `out` (or kept, while capturing).
    buf: Vec<u8>,
    pending: Pending,
    /// One text per formatting job, kept from batch to batch: allocated
    /// afresh on the workers and freed here, they cost more in page faults
    /// than the formatting gained.
    texts: Vec<Vec<u8>>,
    /// The formatter of a batch too small to share out, kept from batch to
    /// batch (its recent floats are 10 KiB to set up).
    formatter: Formatter,
    merger: Option<RunMerger>,
    /// With `--merge=blocks`: the runs joined into blocks.
    blocks: Option<BlockMerger>,
    /// Polygons written for the current input polygon.
    pub(super) written: u64,
    /// Most polygons this input polygon may still write.
    budget: u64,
    error: Option<std::io::Error>,
    /// While set, output stays in `buf` (an object's records, gathered to be
    /// written inside its definition).
    capturing: bool,
}

impl<W: Write> CellWriter<W> {
    /// A writer of NDJSON records to `out`, buffered in blocks of 64 KiB.
    pub fn new(out: W) -> Self {
        CellWriter {
            out,
            volume: None,
            pattern: None,
            buf: Vec::with_capacity(2 * FLUSH_BYTES),
            pending: Pending::default(),
            texts: Vec::new(),
            formatter: Formatter::new(),
            merger: None,
            blocks: None,
            written: 0,
            budget: 0,
            error: None,
            capturing: false,
        }
    }

    /// Writes a record unchanged: its unknown fields as written, less the
    /// whitespace between their tokens ([`stream::Fields`]).
    pub fn pass(&mut self, fields: &stream::Fields) -> std::io::Result<()> {
        self.format_pending()?;
        stream::write_ndjson(&mut self.buf, fields)?;
        self.drain_full()
    }

    /// Writes already serialized NDJSON (one or more whole lines).
    pub fn pass_raw(&mut self, line: &[u8]) -> std::io::Result<()> {
        self.format_pending()?;
        self.buf.extend_from_slice(line);
        self.drain_full()
    }

    /// From now on keeps every record written in memory instead of sending it
    /// to the output, until [`CellWriter::end_capture`].
    pub fn capture(&mut self) -> std::io::Result<()> {
        self.format_pending()?;
        self.drain()?;
        self.capturing = true;
        Ok(())
    }

    /// The NDJSON lines written since [`CellWriter::capture`].
    pub fn end_capture(&mut self) -> std::io::Result<Vec<u8>> {
        self.format_pending()?;
        self.capturing = false;
        Ok(std::mem::replace(
            &mut self.buf,
            Vec::with_capacity(2 * FLUSH_BYTES),
        ))
    }

    /// Writes what is buffered and returns the output.
    pub fn into_inner(mut self) -> std::io::Result<W> {
        self.format_pending()?;
        self.drain()?;
        Ok(self.out)
    }

    /// Prepares for the cells of one input record.
    pub fn begin(&mut self, rec: &Record, pattern: Rc<Pattern>, merge: Option<Merge>, budget: u64) {
        let p = &mut self.pending;
        // The last record's fields go unless a cell of it waits in the batch
        // (a record with no cells must not leave them behind).
        let start = p.cells.last().map_or(0, |c| c.fields.end);
        p.fields_text.truncate(start);
        let text = &mut p.fields_text;
        for (k, v) in rec.fields.iter() {
            if REPLACED.contains(&k) {
                continue;
            }
            text.push(b',');
            serde_json::to_writer(&mut *text, k).expect("writing to a Vec cannot fail");
            text.push(b':');
            serde_json::to_writer(&mut *text, v).expect("writing to a Vec cannot fail");
        }
        p.current_fields = start..text.len();
        self.pattern = Some(pattern);
        // Both mergers are kept from record to record (`finish` leaves them
        // empty), with the lists they have grown.
        self.merger = merge.map(|_| self.merger.take().unwrap_or_default());
        self.blocks =
            (merge == Some(Merge::Blocks)).then(|| self.blocks.take().unwrap_or_default());
        self.written = 0;
        self.budget = budget;
        self.error = None;
    }

    pub(super) fn pattern_size(&self) -> i64 {
        self.pattern.as_ref().map_or(16, |p| p.size() as i64)
    }

    fn texel(&self, k: i64, j: i64) -> (u32, u32, Option<u16>) {
        let p = self.pattern.as_ref().expect("begin() sets the pattern");
        let s = p.size() as i64;
        let (c, r) = (k.rem_euclid(s) as u32, j.rem_euclid(s) as u32);
        (c, r, p.index_at(c, r))
    }

    /// Adds a record to the batch (formatted when the batch is full).
    fn write_record(&mut self, col: u32, row: u32, index: u16, world: &[DVec3], cells: usize) {
        if self.written >= self.budget {
            self.error.get_or_insert_with(|| {
                std::io::Error::other(OptionError::new(
                    "the output would exceed ",
                    "max_polygons",
                    "",
                ))
            });
            return;
        }
        let color = self
            .pattern
            .as_ref()
            .expect("begin() sets the pattern")
            .palette()[index as usize];
        let p = &mut self.pending;
        let start = p.verts.len();
        p.verts.extend_from_slice(world);
        p.cells.push(PendingCell {
            texel: [col, row],
            color: color.0,
            cells,
            verts: start..p.verts.len(),
            fields: p.current_fields.clone(),
        });
        // At most 77 bytes a vertex and 100 for the rest of the cell's own
        // fields (see `STAGED_VERTICES`).
        p.text_bytes += 100 + 77 * world.len() + p.current_fields.len();
        self.written += 1;
        if p.cells.len() >= BATCH_CELLS || p.text_bytes >= BATCH_BYTES {
            if let Err(e) = self.format_pending() {
                self.error.get_or_insert(e);
            }
        }
    }

    /// Formats the batch, in parallel if it has more than one job's cells,
    /// and hands the text on in order. The current record's fields stay, for
    /// its cells still to come.
    fn format_pending(&mut self) -> std::io::Result<()> {
        use rayon::prelude::*;
        let p = &self.pending;
        if p.cells.is_empty() {
            return Ok(());
        }
        if p.cells.len() <= JOB_CELLS {
            for cell in &p.cells {
                self.formatter.cell(&mut self.buf, cell, p);
            }
        } else {
            let jobs = p.cells.len().div_ceil(JOB_CELLS);
            if self.texts.len() < jobs {
                self.texts.resize_with(jobs, Vec::new);
            }
            let texts = &mut self.texts[..jobs];
            p.cells
                .par_chunks(JOB_CELLS)
                .zip(texts.par_iter_mut())
                .for_each(|(cells, text)| {
                    text.clear();
                    let mut formatter = Formatter::new();
                    for cell in cells {
                        formatter.cell(text, cell, p);
                    }
                });
            if self.capturing {
                for text in texts.iter() {
                    self.buf.extend_from_slice(text);
                }
            } else {
                self.out.write_all(&self.buf)?;
                self.buf.clear();
                for text in texts.iter() {
                    self.out.write_all(text)?;
                }
            }
        }
        // Keep the current record's fields, at the start.
        let p = &mut self.pending;
        let current = p.current_fields.clone();
        p.fields_text.copy_within(current.clone(), 0);
        p.fields_text.truncate(current.len());
        p.current_fields = 0..current.len();
        p.cells.clear();
        p.verts.clear();
        p.text_bytes = 0;
        self.drain_full()
    }

    /// Ends the current run: written, or, with blocks, handed to the block
    /// merger, and the blocks that closes written.
    fn flush_run(&mut self) {
        let Some(mut m) = self.merger.take() else {
            return;
        };
        if let Some(run) = m.take() {
            match self.blocks.as_mut() {
                Some(blocks) => blocks.add(&run),
                None => self.write_merged(run.first, run.row, run.key, run.cells, run.vertices),
            }
        }
        self.merger = Some(m);
        self.write_closed_blocks();
    }

    /// Writes the blocks the block merger has closed.
    fn write_closed_blocks(&mut self) {
        let Some(mut blocks) = self.blocks.take() else {
            return;
        };
        while let Some(b) = blocks.take_closed() {
            self.write_merged(b.first, b.row, b.key, b.cells, b.vertices);
        }
        self.blocks = Some(blocks);
    }

    /// Writes a run or a block of `cells` cells of colour `key`: the texel of
    /// its first cell (column `first`, row `row`), the cell count.
    fn write_merged(&mut self, first: i64, row: i64, key: u32, cells: usize, verts: &[DVec3]) {
        let (c, r, _) = self.texel(first, row);
        self.write_record(c, r, key as u16, verts, cells);
    }

    /// Hands the buffer to the output once it holds [`FLUSH_BYTES`].
    fn drain_full(&mut self) -> std::io::Result<()> {
        if self.buf.len() >= FLUSH_BYTES {
            self.drain()?;
        }
        Ok(())
    }

    fn drain(&mut self) -> std::io::Result<()> {
        if self.capturing {
            return Ok(());
        }
        self.out.write_all(&self.buf)?;
        self.buf.clear();
        Ok(())
    }

    /// Ends the current record: its error if it had one, else its records
    /// are handed on as the batch fills. An error drops whatever has not
    /// been handed to the output yet, this record's cells and those of
    /// earlier records still in the batch (a batch formatted before the
    /// error has been written): every caller stops at the error, and a run
    /// that fails early writes nothing (`polyfill3`'s
    /// `bad_input_names_the_record_and_writes_nothing`); one that fails
    /// later leaves what was written before, cut at a batch, as it was cut
    /// at 64 KiB before the batches.
    pub fn finish(&mut self) -> std::io::Result<()> {
        self.flush_run();
        if let Some(blocks) = self.blocks.as_mut() {
            blocks.close_all();
        }
        self.write_closed_blocks();
        if let Some(e) = self.error.take() {
            self.buf.clear();
            self.pending.clear();
            return Err(e);
        }
        Ok(())
    }
}

impl<W: Write> CellSink for CellWriter<W> {
    fn wants(&mut self, k: i64, j: i64) -> bool {
        self.error.is_none() && self.texel(k, j).2.is_some()
    }

    fn cell(&mut self, k: i64, j: i64, world: &[DVec3], _plane: &[glam::DVec2], full: bool) {
        let (c, r, idx) = self.texel(k, j);
        let Some(idx) = idx else { return };
        if self.volume.is_some_and(|v| v.outside(world)) {
            return;
        }
        if let Some(m) = self.merger.as_mut() {
            if full {
                if !m.continues(k, j, idx as u32) {
                    self.flush_run();
                }
                let m = self.merger.as_mut().expect("merging");
                m.push(k, j, idx as u32, world);
                return;
            }
            self.flush_run();
        }
        self.write_record(c, r, idx, world, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::stream::Fields;
    use proptest::prelude::*;

    /// A record's text as serde_json writes it (the independent oracle):
    /// the vertices through `serde_json::to_string`, -0.0 as 0.0.
    fn oracle(cell: &PendingCell, verts: &[DVec3], rest: &str) -> String {
        let v: Vec<[f64; 3]> = verts
            .iter()
            .map(|p| [p.x + 0.0, p.y + 0.0, p.z + 0.0])
            .collect();
        let cells = if cell.cells > 1 {
            format!(",\"cells\":{}", cell.cells)
        } else {
            String::new()
        };
        format!(
            "{{\"vertices\":{},\"color\":{},\"texel\":{}{cells}{rest}}}\n",
            serde_json::to_string(&v).unwrap(),
            serde_json::to_string(&cell.color).unwrap(),
            serde_json::to_string(&cell.texel).unwrap(),
        )
    }

    fn finite() -> impl Strategy<Value = f64> {
        prop_oneof![
            any::<u64>()
                .prop_map(f64::from_bits)
                .prop_filter("finite", |x| x.is_finite()),
            (-1000i32..1000).prop_map(|i| i as f64 / 4.0),
            Just(-0.0),
            Just(f64::MIN_POSITIVE),
            Just(-f64::MAX),
            Just(5e-324),
            Just(-1.2345678901234567e-308),
        ]
    }

    proptest! {
        /// Staged or not, from the recent floats or written afresh, every
        /// record is the text serde_json gives for it.
        #[test]
        fn records_read_as_serde_json_writes_them(
            verts in prop::collection::vec((finite(), finite(), finite()), 1..12),
            repeat in 1usize..4,
            color in any::<[u8; 3]>(),
            texel in any::<[u32; 2]>(),
            cells in prop_oneof![Just(1usize), any::<usize>()],
        ) {
            let verts: Vec<DVec3> = verts.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect();
            let rest = ",\"id\":\"a\\u00e9\"";
            let mut pending = Pending::default();
            pending.verts.extend_from_slice(&verts);
            pending.fields_text.extend_from_slice(rest.as_bytes());
            let cell = PendingCell {
                texel,
                color,
                cells,
                verts: 0..verts.len(),
                fields: 0..rest.len(),
            };
            let mut formatter = Formatter::new();
            let mut text = Vec::new();
            // Again and again: the later times read the recent floats.
            for _ in 0..repeat {
                formatter.cell(&mut text, &cell, &pending);
            }
            let one = oracle(&cell, &verts, rest);
            prop_assert_eq!(String::from_utf8(text).unwrap(), one.repeat(repeat));
        }
    }

    /// Two floats whose bits fall in one slot of the recent floats each get
    /// their own text.
    #[test]
    fn a_slot_taken_by_another_float_is_written_again() {
        let mut floats = RecentFloats::new();
        let slot = |x: f64| slot(x.to_bits());
        let a = 1.5f64;
        let b = (1..1_000_000)
            .map(|i| a + i as f64)
            .find(|&b| slot(b) == slot(a))
            .expect("a float sharing the slot");
        for x in [a, b, a, b] {
            let t = floats.text(x);
            assert_eq!(
                &t.text[..t.len as usize],
                serde_json::to_string(&x).unwrap().as_bytes()
            );
        }
    }

    /// The checker pattern of the writer tests.
    fn checker() -> Rc<Pattern> {
        Rc::new(
            Pattern::new(
                16,
                vec![Rgb8([1, 2, 3]), Rgb8([250, 0, 9])],
                (0..256).map(|i| (i + i / 16) % 2).collect(),
            )
            .unwrap(),
        )
    }

    /// A triangle record with `"id": id`.
    fn record(i: usize, id: &serde_json::Value) -> Record {
        let json = serde_json::json!({
            "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
            "color": [0, 0, 0],
            "id": id,
        });
        Record::from_fields(i, Fields::from(json.as_object().unwrap().clone())).unwrap()
    }

    /// Cell k of a record: its corners.
    fn corners(k: i64) -> [DVec3; 3] {
        let x = k as f64 * 0.1;
        [
            DVec3::new(x, -0.0, 1e-300),
            DVec3::new(x + 0.1, 0.0, 2.0),
            DVec3::new(x, 0.5, 1.0 / 3.0),
        ]
    }

    /// Records of 7,000, 0, 1, 13,000 cells and 100 cells with a 100 KB
    /// field (so batches fill by count and by bytes, mid-record, and are
    /// formatted in parallel jobs), and a line passed through between them,
    /// written by one thread and by two, and captured: the same text, each
    /// line serde_json's own text for its cell, in order.
    #[test]
    fn batches_and_threads_leave_the_text_unchanged() {
        let long = serde_json::Value::String("é".repeat(50_000));
        let records: Vec<(serde_json::Value, i64)> = vec![
            (0.into(), 7_000),
            (1.into(), 0),
            (2.into(), 1),
            (3.into(), 13_000),
            (long, 100),
        ];
        let passed = "{\"light\":{\"ambient\":[1,1,1]}}\n";
        let write = |threads: usize, capture: bool| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let pattern = checker();
                let mut w = CellWriter::new(Vec::new());
                if capture {
                    w.capture().unwrap();
                }
                for (i, (id, n)) in records.iter().enumerate() {
                    if i == 3 {
                        w.pass_raw(passed.as_bytes()).unwrap();
                    }
                    w.begin(&record(i, id), pattern.clone(), None, u64::MAX);
                    for k in 0..*n {
                        w.cell(k, i as i64, &corners(k), &[], true);
                    }
                    w.finish().unwrap();
                }
                if capture {
                    w.end_capture().unwrap()
                } else {
                    w.into_inner().unwrap()
                }
            })
        };
        let pattern = checker();
        let mut expected = String::new();
        for (i, (id, n)) in records.iter().enumerate() {
            if i == 3 {
                expected.push_str(passed);
            }
            let fields = format!(",\"id\":{}", serde_json::to_string(id).unwrap());
            for k in 0..*n {
                let (c, r) = (k as u32 % 16, i as u32 % 16);
                let color = pattern.palette()[pattern.index_at(c, r).unwrap() as usize].0;
                let cell = PendingCell {
                    texel: [c, r],
                    color,
                    cells: 1,
                    verts: 0..0,
                    fields: 0..0,
                };
                expected.push_str(&oracle(&cell, &corners(k), &fields));
            }
        }
        let one = write(1, false);
        assert!(one == expected.as_bytes(), "one thread");
        assert!(one == write(2, false), "two threads");
        assert!(one == write(2, true), "captured");
    }

    /// Records that give no cell leave nothing behind: the fields kept for
    /// the batch stay one record's, however many such records come.
    #[test]
    fn records_without_cells_keep_no_fields() {
        let pattern = checker();
        let mut w = CellWriter::new(Vec::new());
        let id = serde_json::Value::String("x".repeat(1000));
        for i in 0..1000 {
            w.begin(&record(i, &id), pattern.clone(), None, u64::MAX);
            w.finish().unwrap();
        }
        assert!(w.pending.fields_text.len() <= 1100);
        assert!(w.into_inner().unwrap().is_empty());
    }

    /// A record that passes its budget in the middle of a batch is an error,
    /// and what the batch held is not written.
    #[test]
    fn a_budget_passed_mid_batch_is_an_error() {
        let pattern = checker();
        let mut w = CellWriter::new(Vec::new());
        w.begin(&record(0, &0.into()), pattern.clone(), None, u64::MAX);
        for k in 0..100 {
            w.cell(k, 0, &corners(k), &[], true);
        }
        w.finish().unwrap();
        w.begin(&record(1, &1.into()), pattern.clone(), None, 10);
        for k in 0..100 {
            w.cell(k, 1, &corners(k), &[], true);
        }
        let err = w.finish().unwrap_err();
        assert!(err.to_string().contains("max_polygons"), "{err}");
        assert!(w.into_inner().unwrap().is_empty());
    }
}
