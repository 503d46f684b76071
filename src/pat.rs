//! The `.pat` multi-colour texture pattern (docs/pat-format.md; thesis Fig. 3.3, 3.4, 4.6).
//!
//! In memory a pattern is a square grid of palette indices with one reserved
//! [`TRANSPARENT`] value. The per-colour bit masks of the file exist only at the
//! file boundary, in [`Pattern::parse`] and [`Pattern::write_canonical`].
//!
//! Orientation: row 0 is the BOTTOM row (IRIS GL, y up), exactly as in the file.
//!
//! A pattern written in the canonical form and read back:
//!
//! ```
//! use patkit::{Pattern, Rgb8};
//!
//! // A 16x16 checker of two colours; texel (col, row) is at index row * 16 + col.
//! let texels: Vec<u16> = (0..256).map(|i| ((i % 16 + i / 16) % 2) as u16).collect();
//! let red_white = vec![Rgb8([200, 40, 40]), Rgb8([240, 240, 240])];
//! let pattern = Pattern::new(16, red_white, texels)?;
//! let text = pattern.to_canonical();
//! let back = Pattern::parse(text.as_bytes(), "checker.pat")?;
//! assert_eq!(back, pattern);
//! assert_eq!(back.color_at(1, 0), Some(Rgb8([240, 240, 240])));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::color::Rgb8;
pub use crate::text::ParseError;
use crate::text::{Failed, ReadWords, Span};
use std::fmt;
use std::io::{self, Read, Write};
use std::path::Path;

/// Pattern sides are multiples of this many texels: one 16-bit word per run.
pub const WORD_BITS: u32 = 16;
/// The largest side accepted: the thesis asks for larger than its 64, and 4096
/// keeps a 16-colour canonical file under 100 MiB.
pub const MAX_SIZE: u32 = 4096;
/// Palette indices are `u16`; the last value is reserved for transparency.
pub const TRANSPARENT: u16 = u16::MAX;
/// The most colours a pattern may have (every index but [`TRANSPARENT`]).
pub const MAX_COLORS: usize = TRANSPARENT as usize;

/// The most bytes of canonical text a tool writes as a `.pat`: 16 GiB.
///
/// The format allows 65,535 colours of 4096x4096, 344 GB of text (one
/// 2.1 MB bit plane per colour of that side): `pat-tile --pat --size
/// 4096x4096` of a 16x16 pattern of 65,535 colours (6 MB) set out to write
/// all of it, until the disk was full. 16 GiB is twelve times the 1.3 GB
/// of the largest pattern `pat-from-image` makes (4096x4096 in 256
/// colours) and the text of 3,276 colours at 4096x4096, while no run
/// fills a disk by surprise. [`Pattern::check_canonical_len`] refuses a
/// longer text before a byte of it is written.
pub const MAX_CANONICAL_BYTES: u64 = 16 << 30;

/// The length of canonical text from which [`Pattern::write_canonical`]
/// formats on a second thread: 1 MiB, a 256x256 pattern of 64 colours.
/// Below it the thread's start (tens of microseconds) would cost more than
/// the overlap saves.
const FORMAT_AHEAD_BYTES: usize = 1 << 20;

/// A validated multi-colour texture pattern.
///
/// Guarantees: `size` is a multiple of 16 in 16..=4096; `texels.len() == size²`;
/// every texel is [`TRANSPARENT`] or an index into `palette`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    size: u32,
    palette: Vec<Rgb8>,
    texels: Vec<u16>,
}

/// Why a pattern could not be built from parts (not a file error).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidPattern(pub String);

impl fmt::Display for InvalidPattern {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for InvalidPattern {}

/// Checks a pattern side against docs/pat-format.md.
pub fn check_size(size: u64) -> Result<u32, InvalidPattern> {
    if size == 0 || size > MAX_SIZE as u64 || !size.is_multiple_of(WORD_BITS as u64) {
        Err(InvalidPattern(format!(
            "pattern size {size} is not a multiple of 16 from 16 to {MAX_SIZE}"
        )))
    } else {
        Ok(size as u32)
    }
}

impl Pattern {
    /// Builds a pattern from its parts, checking every guarantee of the type.
    pub fn new(size: u32, palette: Vec<Rgb8>, texels: Vec<u16>) -> Result<Self, InvalidPattern> {
        let size = check_size(size as u64)?;
        if palette.len() > MAX_COLORS {
            return Err(InvalidPattern(format!(
                "{} colours: at most {MAX_COLORS} are allowed",
                palette.len()
            )));
        }
        let n = (size as usize) * (size as usize);
        if texels.len() != n {
            return Err(InvalidPattern(format!(
                "{} texels for a {size}x{size} pattern, which needs {n}",
                texels.len()
            )));
        }
        if let Some(bad) = texels
            .iter()
            .find(|&&t| t != TRANSPARENT && t as usize >= palette.len())
        {
            return Err(InvalidPattern(format!(
                "texel index {bad} but only {} colours",
                palette.len()
            )));
        }
        Ok(Pattern {
            size,
            palette,
            texels,
        })
    }

    /// Side in texels.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// The colours in file order; an opaque texel's value indexes this slice.
    pub fn palette(&self) -> &[Rgb8] {
        &self.palette
    }

    /// Row-major texel indices, row 0 at the bottom.
    pub fn texels(&self) -> &[u16] {
        &self.texels
    }

    /// Palette index at (col, row), or `None` where transparent. Panics outside the grid.
    #[inline]
    pub fn index_at(&self, col: u32, row: u32) -> Option<u16> {
        let t = self.texels[(row * self.size + col) as usize];
        (t != TRANSPARENT).then_some(t)
    }

    /// Colour at (col, row), or `None` where transparent. Panics outside the grid.
    #[inline]
    pub fn color_at(&self, col: u32, row: u32) -> Option<Rgb8> {
        self.index_at(col, row).map(|i| self.palette[i as usize])
    }

    /// Colour at any integer texel coordinate, the pattern repeating in both
    /// directions (docs/stream-format.md: `floor(u) mod SIZE`): the plain formula the tests
    /// check the fast paths against.
    #[cfg(test)]
    pub(crate) fn color_wrapped(&self, col: i64, row: i64) -> Option<Rgb8> {
        let s = self.size as i64;
        self.color_at(col.rem_euclid(s) as u32, row.rem_euclid(s) as u32)
    }

    /// Reads a `.pat` file as a stream ([`Pattern::read_from`]); errors
    /// name the file, line and word.
    pub fn read_file(path: &Path) -> Result<Pattern, ParseError> {
        let name = path.display().to_string();
        let opened = crate::io::open_path(path).map_err(|e| ParseError::io(&name, e))?;
        Pattern::read_from(&mut opened.into_reader(), &name)
    }

    /// Parses the texted format (docs/pat-format.md) from bytes; `name` is used in errors.
    pub fn parse(mut bytes: &[u8], name: &str) -> Result<Pattern, ParseError> {
        // In memory already: no bound on what is read.
        Parser::new(&mut bytes, name, false)
            .pattern()
            .map_err(|e| *e)
    }

    /// Parses a pattern read from `reader` a chunk at a time, in memory of
    /// its texels and a buffer of a few hundred KiB: a pattern's text may be
    /// a gigabyte (4096x4096 in 256 colours) where its texels are 32 MiB.
    /// The same parser and errors as [`Pattern::parse`]; what is read is
    /// bounded by [`read_limit`] of the header (before it by
    /// [`crate::io::MAX_NAMED_FILE_BYTES`]), so an endless input ends.
    pub fn read_from(reader: &mut dyn Read, name: &str) -> Result<Pattern, ParseError> {
        Parser::new(reader, name, true).pattern().map_err(|e| *e)
    }

    /// The canonical text (docs/pat-format.md), as one string.
    pub fn to_canonical(&self) -> String {
        let mut out = Vec::with_capacity(self.canonical_len());
        self.write_canonical(&mut out)
            .expect("writing to a Vec cannot fail");
        String::from_utf8(out).expect("canonical form is ASCII")
    }

    /// Exact byte length of the canonical form ([`Pattern::write_canonical`]).
    pub fn canonical_len(&self) -> usize {
        let words_per_row = (self.size / WORD_BITS) as usize;
        let row = words_per_row * 5; // "xxxx" plus a space or the newline
        let header = format!("{} {}\n", self.size, self.palette.len()).len();
        header
            + self
                .palette
                .iter()
                .map(|c| format!("{} {} {}\n", c.0[0], c.0[1], c.0[2]).len())
                .sum::<usize>()
            + self.palette.len() * self.size as usize * row
    }

    /// An error unless the canonical text is at most
    /// [`MAX_CANONICAL_BYTES`]: a tool calls it before it writes a `.pat`.
    /// The message gives the length, the colours and the size, and ends
    /// with `smaller`, the tool's way to a shorter text (fewer colours, a
    /// smaller size).
    pub fn check_canonical_len(&self, smaller: &str) -> Result<(), InvalidPattern> {
        let len = self.canonical_len() as u64;
        if len <= MAX_CANONICAL_BYTES {
            return Ok(());
        }
        let (size, n) = (self.size, self.palette.len());
        Err(InvalidPattern(format!(
            "the .pat would be {len} bytes of text ({n} colours of {size}x{size}), more than \
             the {MAX_CANONICAL_BYTES} bytes (16 GiB) a tool writes: {smaller}"
        )))
    }

    /// Writes the canonical form: `SIZE NCOLORS`, then per colour one `R G B` line
    /// and one line per row of lowercase 4-digit words, final newline.
    ///
    /// The texels are first sorted by colour (a counting sort keeps them in
    /// row order), so each colour's plane visits only its own texels: a
    /// 1024x1024 pattern of 256 colours no longer compares every texel with
    /// every colour (268 million tests).
    ///
    /// A text of `FORMAT_AHEAD_BYTES` or more, in a rayon pool of more than
    /// one thread, is formatted a colour block ahead on a second thread while
    /// this one writes: the 84 MB of a 1024x1024 pattern of 256 colours spend
    /// as long in the kernel's copy as in the formatting. The bytes are the
    /// same either way (test `formatting_ahead_writes_the_same_bytes`).
    pub fn write_canonical<W: Write>(&self, w: &mut W) -> io::Result<()> {
        writeln!(w, "{} {}", self.size, self.palette.len())?;
        let planes = Planes::of(self);
        let colours = 0..self.palette.len();
        if self.canonical_len() < FORMAT_AHEAD_BYTES || rayon::current_num_threads() < 2 {
            let mut block = Vec::new();
            for k in colours {
                block.clear();
                planes.format(k, &mut block);
                w.write_all(&block)?;
            }
            return Ok(());
        }
        std::thread::scope(|s| {
            // Two blocks in the channel, one being formatted, one being
            // written: about 1.3 MB at 1024x1024, whatever the colour count.
            let (full, formatted) = std::sync::mpsc::sync_channel::<Vec<u8>>(2);
            let (empty, spare) = std::sync::mpsc::channel::<Vec<u8>>();
            let planes = &planes;
            s.spawn(move || {
                for k in colours {
                    let mut block = spare.try_recv().unwrap_or_default();
                    block.clear();
                    planes.format(k, &mut block);
                    if full.send(block).is_err() {
                        break; // The writer failed and stopped reading.
                    }
                }
            });
            for block in formatted {
                w.write_all(&block)?;
                // The formatter may have finished: a spare nobody takes is dropped.
                let _ = empty.send(block);
            }
            Ok(())
        })
    }

    /// The same pattern with every transparent texel painted `color` (an existing
    /// palette entry of that colour is reused, else one is added).
    pub fn with_background(mut self, color: Rgb8) -> Result<Pattern, InvalidPattern> {
        if !self.texels.contains(&TRANSPARENT) {
            return Ok(self);
        }
        let index = match self.palette.iter().position(|&c| c == color) {
            Some(i) => i,
            None => {
                if self.palette.len() == MAX_COLORS {
                    return Err(InvalidPattern(format!(
                        "cannot add a background colour to a pattern that already has {MAX_COLORS} colours"
                    )));
                }
                self.palette.push(color);
                self.palette.len() - 1
            }
        } as u16;
        for t in &mut self.texels {
            if *t == TRANSPARENT {
                *t = index;
            }
        }
        Ok(self)
    }

    /// Number of texels of each palette entry, and of transparent texels last.
    pub fn histogram(&self) -> (Vec<u64>, u64) {
        let mut counts = vec![0u64; self.palette.len()];
        let mut transparent = 0;
        for &t in &self.texels {
            match counts.get_mut(t as usize) {
                Some(c) => *c += 1,
                None => transparent += 1,
            }
        }
        (counts, transparent)
    }

    /// A `new_size` pattern that repeats this one; each source texel covers
    /// `scale` x `scale` texels of the result, and texel (0, 0) of the result
    /// shows source texel `offset` (the same convention as screen tiling).
    pub fn tiled(
        &self,
        new_size: u32,
        scale: u32,
        offset: (i64, i64),
    ) -> Result<Pattern, InvalidPattern> {
        let new_size = check_size(new_size as u64)?;
        let scale = scale.max(1) as i64;
        let size = self.size as i64;
        // Reduced first: an offset near `i64::MAX` plus the row or column
        // overflowed (wrapping in a release build, to the wrong texels).
        let offset = (offset.0.rem_euclid(size), offset.1.rem_euclid(size));
        let mut texels = Vec::with_capacity((new_size as usize).pow(2));
        for row in 0..new_size as i64 {
            let src_row = (row.div_euclid(scale) + offset.1).rem_euclid(size);
            for col in 0..new_size as i64 {
                let src_col = (col.div_euclid(scale) + offset.0).rem_euclid(size);
                texels.push(self.texels[(src_row as u32 * self.size + src_col as u32) as usize]);
            }
        }
        Pattern::new(new_size, self.palette.clone(), texels)
    }
}

/// Each byte as two lowercase hex digits.
const HEX_BYTE: [[u8; 2]; 256] = {
    const HEX: &[u8; 16] = b"0123456789abcdef";
    let mut table = [[0; 2]; 256];
    let mut b = 0;
    while b < 256 {
        table[b] = [HEX[b >> 4], HEX[b & 0xf]];
        b += 1;
    }
    table
};

/// A pattern's texels sorted by colour, for writing its bit planes: colour
/// `k`'s texel indices, in row order, are `at[start[k]..start[k + 1]]`.
struct Planes<'a> {
    pattern: &'a Pattern,
    start: Vec<usize>,
    at: Vec<u32>,
}

impl<'a> Planes<'a> {
    /// The counting sort of `pattern`'s texels by colour.
    fn of(pattern: &'a Pattern) -> Planes<'a> {
        let colours = pattern.palette.len();
        let mut start = vec![0usize; colours + 1];
        for &t in &pattern.texels {
            if t != TRANSPARENT {
                start[t as usize + 1] += 1;
            }
        }
        for k in 0..colours {
            start[k + 1] += start[k];
        }
        let mut next = start.clone();
        let mut at = vec![0u32; start[colours]];
        for (i, &t) in pattern.texels.iter().enumerate() {
            if t != TRANSPARENT {
                at[next[t as usize]] = i as u32;
                next[t as usize] += 1;
            }
        }
        Planes { pattern, start, at }
    }

    /// Appends colour `k`'s block of the canonical text to `out`: its
    /// `R G B` line and one line of words per row.
    ///
    /// Each row starts as a copy of an all-zero line and only the words
    /// holding one of the colour's texels are written over: of a 1024x1024
    /// pattern of 256 colours' 16.8 million words, at most one in 16 is not
    /// `0000` (a texel has one colour). Formatting every word took 30% of
    /// the samples of the 1024x1024 gradient of
    /// `bench/pat_from_image_large.sh` (K = 256).
    fn format(&self, k: usize, out: &mut Vec<u8>) {
        let size = self.pattern.size as usize;
        let words_per_row = size / WORD_BITS as usize;
        let [r, g, b] = self.pattern.palette[k].0;
        // Writing to a Vec cannot fail.
        let _ = writeln!(out, "{r} {g} {b}");
        // "0000 " per word; the last space is the newline.
        let mut zero_line = b"0000 ".repeat(words_per_row);
        *zero_line.last_mut().expect("a row has at least one word") = b'\n';
        out.reserve(size * zero_line.len());
        let mut mine = self.at[self.start[k]..self.start[k + 1]].iter().peekable();
        for row in 0..size {
            let line_at = out.len();
            out.extend_from_slice(&zero_line);
            let line = &mut out[line_at..];
            let end = ((row + 1) * size) as u32;
            // The word being gathered: its place in the row and its bits.
            let mut word: Option<(usize, u16)> = None;
            let put = |line: &mut [u8], (at, bits): (usize, u16)| {
                let [hi, lo] = bits.to_be_bytes();
                line[at * 5..at * 5 + 2].copy_from_slice(&HEX_BYTE[hi as usize]);
                line[at * 5 + 2..at * 5 + 4].copy_from_slice(&HEX_BYTE[lo as usize]);
            };
            while let Some(&&i) = mine.peek() {
                if i >= end {
                    break;
                }
                let x = i as usize - row * size;
                let at = x / WORD_BITS as usize;
                // The first texel of a word is its most significant bit.
                let bit = 0x8000 >> (x % WORD_BITS as usize);
                word = match word {
                    Some((w, bits)) if w == at => Some((w, bits | bit)),
                    Some(done) => {
                        put(line, done);
                        Some((at, bit))
                    }
                    None => Some((at, bit)),
                };
                mine.next();
            }
            if let Some(done) = word {
                put(line, done);
            }
        }
    }
}

/// A seam looks like the pattern's own texture when its mean jump is no more
/// than this many times the strongest edge inside: the largest mean jump
/// across one interior column (or row) boundary. A pattern that tiles
/// perfectly (a checker, bricks whose mortar falls on the wrap) has its seam
/// equal to the edges it repeats, where a mean over every interior boundary
/// would be diluted by the flat runs between them; 1.5 lets a seam vary like
/// those edges do. A seam that is a new, systematic edge (a gradient
/// restarting, a course shifted against the rest) exceeds it. The one blind
/// spot: a seam weaker than the pattern's strongest edge passes.
pub const SEAM_RATIO: f64 = 1.5;
/// Absolute slack on the seam test, so that near-uniform patterns (interior
/// jumps close to 0) are not called seamed by a single odd texel pair.
pub const SEAM_SLACK: f64 = 0.01;

/// How abrupt the wrap-around boundary of a tiled pattern is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seam {
    /// Mean jump across the wrap boundary (last column to first, or top row to bottom).
    pub seam: f64,
    /// Mean jump between neighbouring interior columns (or rows).
    pub interior: f64,
    /// The largest mean jump across one interior boundary: the pattern's
    /// strongest edge.
    pub strongest: f64,
    /// `seam <= SEAM_RATIO * strongest + SEAM_SLACK`.
    pub seamless: bool,
}

impl Pattern {
    /// Seams when tiled: left/right edges (horizontal repetition), then
    /// bottom/top edges (vertical repetition). A jump between two texels is 0 for
    /// the same palette entry, 1 between a transparent and an opaque texel, else
    /// the linear-light RGB distance scaled to 0..=1.
    pub fn seams(&self) -> (Seam, Seam) {
        let lin: Vec<[f32; 3]> = self.palette.iter().map(|c| c.to_linear()).collect();
        let jump = |a: u16, b: u16| -> f64 {
            if a == b {
                return 0.0;
            }
            match (lin.get(a as usize), lin.get(b as usize)) {
                (Some(x), Some(y)) => {
                    let d2: f32 = (0..3).map(|i| (x[i] - y[i]).powi(2)).sum();
                    (d2 as f64 / 3.0).sqrt()
                }
                _ => 1.0,
            }
        };
        let s = self.size as usize;
        let t = |c: usize, r: usize| self.texels[r * s + c];
        let seam_of = |across: &dyn Fn(usize, usize) -> (u16, u16)| -> Seam {
            // across(k, i): the texel pair at boundary k (k = s-1 is the wrap) on line i.
            let boundary = |k: usize| {
                (0..s)
                    .map(|i| {
                        let (a, b) = across(k, i);
                        jump(a, b)
                    })
                    .sum::<f64>()
                    / s as f64
            };
            let inside: Vec<f64> = (0..s - 1).map(boundary).collect();
            let interior = inside.iter().sum::<f64>() / inside.len().max(1) as f64;
            let strongest = inside.iter().copied().fold(0.0, f64::max);
            let seam = boundary(s - 1);
            Seam {
                seam,
                interior,
                strongest,
                seamless: seam <= SEAM_RATIO * strongest + SEAM_SLACK,
            }
        };
        let horizontal = seam_of(&|k, i| (t(k, i), t((k + 1) % s, i)));
        let vertical = seam_of(&|k, i| (t(i, k), t(i, (k + 1) % s)));
        (horizontal, vertical)
    }
}

/// What a `.pat` file holds, for the "empty file" and "not text" messages.
const PAT_CONTENTS: &str = "`SIZE NCOLORS` and colour blocks of hex words";

/// The `.pat` grammar (docs/pat-format.md) over the shared word tokenizer. The format has
/// no comments: a `#` is a word, and so trailing garbage or a bad number.
struct Parser<'a> {
    words: ReadWords<'a>,
    /// Whether to bound the bytes read by the header (`Pattern::read_from`).
    bounded: bool,
}

impl<'a> Parser<'a> {
    /// A `bounded` parser bounds what it reads by the header, and by
    /// [`crate::io::MAX_NAMED_FILE_BYTES`] (the old bound of any `.pat`)
    /// until the header is read.
    fn new(reader: &'a mut dyn Read, name: &'a str, bounded: bool) -> Self {
        let mut words = ReadWords::new(reader, name, PAT_CONTENTS);
        if bounded {
            words.set_limit(
                crate::io::MAX_NAMED_FILE_BYTES,
                "an input may have before a pattern's `SIZE NCOLORS`".to_string(),
            );
        }
        Parser { words, bounded }
    }

    /// Bounds what a stream may read to the header and `blocks` colour
    /// blocks ([`read_limit`]), raised block by block: a header that
    /// promises 65,535 colours of 4096x4096 (687 GB) and then sends
    /// whitespace without end is refused after 256 MiB, not 1.4 TB.
    /// `ncolors` is the header's count, named when `blocks` is fewer ("13
    /// colour blocks" of a header of 16 read as a miscount: a
    /// hostile-input review).
    fn bound(&mut self, size: u32, blocks: usize, ncolors: usize) {
        if self.bounded {
            let what = match blocks {
                0 => "the header".to_string(),
                _ if blocks == ncolors => format!(
                    "the header and {blocks} colour block{}",
                    if blocks == 1 { "" } else { "s" }
                ),
                _ => format!("the header and the first {blocks} of its {ncolors} colour blocks"),
            };
            self.words.set_limit(
                read_limit(size, blocks),
                format!(
                    "{what} of a {size}x{size} pattern may take (twice their canonical length \
                     and 1 MiB, or the {} bytes of any .pat read whole, whichever is more)",
                    crate::io::MAX_NAMED_FILE_BYTES
                ),
            );
        }
    }

    /// A 16-bit word: 1..4 hex digits of any case, optional `0x`. `what` is
    /// only formatted on an error: this runs once per word of the file.
    fn hex_word(&mut self, what: &dyn Fn() -> String) -> Result<(u16, Span), Failed> {
        let Some(w) = self.words.next()? else {
            return Err(self
                .words
                .expect(&what())
                .expect_err("the end of the words stays the end"));
        };
        let text = self.words.text(&w);
        let digits = text
            .strip_prefix("0x")
            .or_else(|| text.strip_prefix("0X"))
            .unwrap_or(text);
        if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_hexdigit()) {
            return Err(self.words.error_at(&w, format!("expected {}", what())));
        }
        if digits.len() > 4 {
            return Err(self.words.error_at(
                &w,
                format!(
                    "more than 4 hex digits (a word is 16 bits): expected {}",
                    what()
                ),
            ));
        }
        Ok((u16::from_str_radix(digits, 16).expect("checked hex"), w))
    }

    fn pattern(mut self) -> Result<Pattern, Failed> {
        let what = "the pattern size, a multiple of 16 from 16 to 4096";
        let w = self.words.expect(what)?;
        let size = self.words.decimal_of(&w, what, u64::MAX)?;
        let size = check_size(size).map_err(|e| {
            self.words
                .error_at(&w, format!("{e}: expected the pattern size"))
        })?;
        let ncolors = self.words.decimal(
            &format!("the number of colours, 0 to {MAX_COLORS}"),
            MAX_COLORS as u64,
        )? as usize;
        self.bound(size, 0, ncolors);

        let s = size as usize;
        let words_per_row = s / WORD_BITS as usize;
        let mut texels = vec![TRANSPARENT; s * s];
        let mut palette = Vec::with_capacity(ncolors.min(256));
        for k in 0..ncolors {
            let n = k + 1;
            self.bound(size, n, ncolors);
            let mut rgb = [0u8; 3];
            for (ch, name) in rgb.iter_mut().zip(["red", "green", "blue"]) {
                *ch = self
                    .words
                    .decimal(&format!("the {name} value of colour {n}, 0 to 255"), 255)?
                    as u8;
            }
            palette.push(Rgb8(rgb));
            for row in 0..s {
                for j in 0..words_per_row {
                    let what = || {
                        format!(
                            "hex word {} of row {row} of colour {n} ({words_per_row} {} per \
                             row, {s} rows)",
                            j + 1,
                            if words_per_row == 1 { "word" } else { "words" }
                        )
                    };
                    let (word, w) = self.hex_word(&what)?;
                    let base = row * s + j * WORD_BITS as usize;
                    for m in 0..WORD_BITS as usize {
                        if word & (0x8000 >> m) == 0 {
                            continue;
                        }
                        let t = &mut texels[base + m];
                        if *t != TRANSPARENT {
                            return Err(self.words.error_at(
                                &w,
                                format!(
                                    "pixel (column {}, row {row}) is set by colour {} and again by colour {n}: each pixel may be set by one colour only",
                                    j * WORD_BITS as usize + m,
                                    *t + 1
                                ),
                            ));
                        }
                        *t = k as u16;
                    }
                }
            }
        }
        if let Some(w) = self.words.next()? {
            return Err(self.words.error_at(
                &w,
                format!(
                    "trailing garbage: expected end of file after {ncolors} colour block{}",
                    if ncolors == 1 { "" } else { "s" }
                ),
            ));
        }
        Ok(Pattern {
            size,
            palette,
            texels,
        })
    }
}

/// The most bytes [`Pattern::read_from`] reads of a pattern whose header
/// says `size`, up to the end of its first `ncolors` colour blocks: twice
/// the canonical length with the longest `R G B` lines, and 1 MiB, and
/// never less than [`crate::io::MAX_NAMED_FILE_BYTES`]. Room for any
/// layout a person or script writes (`0x0000`, CRLF, a space more), and an
/// end to an endless input. The floor keeps every layout the format allows
/// ("any layout is read", docs/pat-format.md) that a .pat read whole could
/// have: without it a 4096x4096 pattern of one indented `0xffff` a CRLF
/// line (12.6 MB) and a 64x64 one followed by 2 MiB of blank space were
/// refused, where reading them whole had read them.
pub fn read_limit(size: u32, ncolors: usize) -> u64 {
    let row = (size / WORD_BITS) as u64 * 5;
    let block = "255 255 255\n".len() as u64 + size as u64 * row;
    let canonical = format!("{size} {ncolors}\n").len() as u64 + ncolors as u64 * block;
    (2 * canonical + (1 << 20)).max(crate::io::MAX_NAMED_FILE_BYTES)
}

/// Whether an input that starts with `start` may be a `.pat`: its first
/// word starts with a digit, as a pattern's size does. For a caller that
/// must tell a pattern from another text format by its first bytes (a
/// `--palette` file, which may be a list of colours); the readers of
/// nothing but patterns and images stream all but an image.
pub fn starts_as_pattern(start: &[u8]) -> bool {
    start
        .iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(u8::is_ascii_digit)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16x16 two-colour checker with a transparent bottom-left texel, built in memory.
    fn sample() -> Pattern {
        let mut texels = vec![0u16; 256];
        for row in 0..16 {
            for col in 0..16 {
                texels[row * 16 + col] = ((row + col) % 2) as u16;
            }
        }
        texels[0] = TRANSPARENT;
        Pattern::new(16, vec![Rgb8([255, 0, 0]), Rgb8([0, 0, 255])], texels).unwrap()
    }

    fn parse(s: &str) -> Result<Pattern, ParseError> {
        Pattern::parse(s.as_bytes(), "t.pat")
    }

    fn err(s: &str) -> String {
        parse(s).unwrap_err().to_string()
    }

    /// A canonical 16x16 header plus `n` words of `w` for one colour.
    fn one_colour(words: &str) -> String {
        format!("16 1\n1 2 3\n{words}")
    }

    #[test]
    fn canonical_round_trip_is_byte_identical() {
        let text = sample().to_canonical();
        let back = parse(&text).unwrap();
        assert_eq!(back, sample());
        assert_eq!(back.to_canonical(), text);
        assert_eq!(text.len(), sample().canonical_len());
        assert!(text.ends_with('\n'));
        assert!(text.starts_with("16 2\n255 0 0\n"));
    }

    /// A 512x512 pattern of 64 colours, a few transparent texels, scrambled:
    /// its canonical text (1.6 MB) is long enough to be formatted ahead.
    fn large() -> Pattern {
        let size = 512u32;
        let palette: Vec<Rgb8> = (0..64u8).map(|k| Rgb8([k, 255 - k, k / 2])).collect();
        let mut state = 12345u64;
        let texels = (0..size * size)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                match (state >> 33) % 67 {
                    k if k < 64 => k as u16,
                    _ => TRANSPARENT,
                }
            })
            .collect();
        Pattern::new(size, palette, texels).unwrap()
    }

    /// The canonical text by the definition (docs/pat-format.md), texel by
    /// texel: the oracle of the writer's sorted, blocked route.
    fn canonical_by_definition(p: &Pattern) -> String {
        let size = p.size as usize;
        let mut text = format!("{} {}\n", size, p.palette.len());
        for (k, c) in p.palette.iter().enumerate() {
            text += &format!("{} {} {}\n", c.0[0], c.0[1], c.0[2]);
            for row in 0..size {
                let words: Vec<String> = (0..size / 16)
                    .map(|w| {
                        let bits = (0..16).fold(0u16, |bits, b| {
                            let mine = p.texels[row * size + w * 16 + b] == k as u16;
                            bits | (u16::from(mine) << (15 - b))
                        });
                        format!("{bits:04x}")
                    })
                    .collect();
                text += &words.join(" ");
                text.push('\n');
            }
        }
        text
    }

    #[test]
    fn formatting_ahead_writes_the_same_bytes() {
        let p = large();
        assert!(p.canonical_len() >= FORMAT_AHEAD_BYTES);
        let written_in = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| p.to_canonical())
        };
        let expected = canonical_by_definition(&p);
        assert_eq!(written_in(1), expected, "one thread: formatted in line");
        assert_eq!(written_in(2), expected, "two threads: formatted ahead");
        assert_eq!(sample().to_canonical(), canonical_by_definition(&sample()));
    }

    /// A writer that fails once it has taken `left` bytes.
    struct FailsAfter {
        left: usize,
    }

    impl Write for FailsAfter {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.left == 0 {
                return Err(io::Error::other("disk full"));
            }
            let n = buf.len().min(self.left);
            self.left -= n;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_write_error_while_formatting_ahead_stops_both_threads() {
        let p = large();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for left in [0, 10, 300_000, 1_000_000] {
            let mut w = FailsAfter { left };
            let err = pool.install(|| p.write_canonical(&mut w)).unwrap_err();
            assert_eq!(err.to_string(), "disk full", "after {left} bytes");
        }
    }

    #[test]
    fn bit_0x8000_is_the_leftmost_pixel_and_row_0_is_first() {
        let mut words = vec!["0"; 16];
        words[0] = "8000";
        words[1] = "0001";
        let p = parse(&one_colour(&words.join(" "))).unwrap();
        assert_eq!(p.index_at(0, 0), Some(0));
        assert_eq!(p.index_at(1, 0), None);
        assert_eq!(p.index_at(15, 1), Some(0));
        assert_eq!(p.histogram(), (vec![2], 254));
    }

    #[test]
    fn accepts_any_layout_case_digit_count_and_0x() {
        // The thesis's own files write `0` and `8888`, all on one line.
        let mut words = vec!["0"; 16];
        words[3] = "0XaBc";
        words[4] = "0x1";
        words[5] = "FFFF";
        let text = format!("  016\t1 \r\n 0001 2 3 {}", words.join("\n\n"));
        let p = parse(&text).unwrap();
        assert_eq!(p.palette(), &[Rgb8([1, 2, 3])]);
        assert_eq!(p.index_at(15, 5), Some(0));
        assert!(p.to_canonical().contains("0abc"));
    }

    #[test]
    fn zero_colours_is_a_fully_transparent_pattern() {
        let p = parse("32 0\n").unwrap();
        assert_eq!(p.histogram(), (vec![], 1024));
        assert_eq!(p.to_canonical(), "32 0\n");
    }

    #[test]
    fn empty_file_is_rejected() {
        assert_eq!(
            err(""),
            "t.pat: empty file: expected `SIZE NCOLORS` and colour blocks of hex words"
        );
        assert!(err(" \n\t\n").contains("empty file"));
    }

    #[test]
    fn non_numeric_size_is_rejected_with_line_and_word() {
        // A file that does not start as a pattern has its word kept to
        // itself (it could be any file: issue 17, item 4).
        assert_eq!(
            err("\nsixteen 1"),
            "t.pat:2: word 1: expected the pattern size, a multiple of 16 from 16 to 4096"
        );
        // A word written as a number is echoed: the user must see it to
        // mend it (a hostile-input review).
        for (first, echoed) in [("-16", true), ("+16", true), ("nan", true), ("-Inf", true)]
            .into_iter()
            .chain([("1.5e-3", true), (".5", true), ("7.", true)])
            .chain([("1e3x", false), ("e", false), ("-", false), ("0x10", false)])
            .chain([
                ("078-05-1120", false),
                ("192.168.1.10", false),
                ("2024-01-01", false),
            ])
            .chain([("1+2", false), ("...5", false), (".", false), ("1e", false)])
        {
            let e = err(&format!("{first} 1"));
            let said = if echoed {
                format!("t.pat:1: word 1 `{first}`: expected the pattern size")
            } else {
                "t.pat:1: word 1: expected the pattern size".to_string()
            };
            assert!(e.starts_with(&said), "{first}: {e}");
        }
        assert!(!err("root:x:0:0:root:/root 1").contains("root"));
    }

    #[test]
    fn size_not_a_multiple_of_16_zero_or_too_large_is_rejected() {
        for bad in ["15", "17", "0", "4112", "8192"] {
            let e = err(&format!("{bad} 0"));
            assert!(e.contains("not a multiple of 16 from 16 to 4096"), "{e}");
            assert!(e.contains("word 1"), "{e}");
        }
        // Past u64::MAX, echoed as written: it was shown saturated, as
        // `pattern size 18446744073709551615`.
        assert_eq!(
            err("99999999999999999999999 0"),
            "t.pat:1: word 1 `99999999999999999999999`: out of range: expected the pattern \
             size, a multiple of 16 from 16 to 4096"
        );
        assert!(parse("4096 0").is_ok());
    }

    #[test]
    fn negative_or_absurd_ncolors_is_rejected() {
        assert!(err("16 -1").contains("word 2 `-1`: expected the number of colours"));
        assert!(err("16 65536").contains("word 2 `65536`: out of range"));
        assert!(err("16 1e9").contains("word 2 `1e9`"));
    }

    #[test]
    fn rgb_out_of_range_is_rejected() {
        let e = err("16 1\n1 256 3\n");
        assert_eq!(
            e,
            "t.pat:2: word 4 `256`: out of range: expected the green value of colour 1, 0 to 255"
        );
        assert!(err("16 1\n1 2 -3\n").contains("word 5 `-3`: expected the blue value"));
    }

    #[test]
    fn too_few_words_names_what_was_missing() {
        let e = err(&one_colour(&vec!["0"; 15].join(" ")));
        assert_eq!(
            e,
            "t.pat:3: unexpected end of file: expected hex word 1 of row 15 of colour 1 (1 word per row, 16 rows)"
        );
    }

    #[test]
    fn too_many_words_is_trailing_garbage() {
        let e = err(&one_colour(&vec!["0"; 17].join(" ")));
        assert!(
            e.contains("word 22 `0`: trailing garbage: expected end of file after 1 colour block"),
            "{e}"
        );
        let e = err(&format!(
            "{}\n# comment",
            one_colour(&vec!["0"; 16].join(" "))
        ));
        assert!(e.contains("t.pat:4: word 22 `#`: trailing garbage"), "{e}");
    }

    #[test]
    fn words_above_0xffff_or_not_hex_are_rejected() {
        let mut words = vec!["0"; 16];
        words[2] = "10000";
        let e = err(&one_colour(&words.join(" ")));
        assert!(e.contains("word 8 `10000`: more than 4 hex digits"), "{e}");
        words[2] = "0xg1";
        assert!(err(&one_colour(&words.join(" ")))
            .contains("word 8 `0xg1`: expected hex word 1 of row 2"));
        words[2] = "0x";
        assert!(err(&one_colour(&words.join(" "))).contains("word 8 `0x`"));
    }

    #[test]
    fn pixel_set_by_two_colours_is_rejected() {
        let zeros = vec!["0"; 15].join(" ");
        let text = format!("16 2\n1 1 1\n0100 {zeros}\n2 2 2\n0300 {zeros}");
        let e = err(&text);
        assert!(
            e.contains("pixel (column 7, row 0) is set by colour 1 and again by colour 2"),
            "{e}"
        );
        assert!(e.contains("t.pat:5: word 25 `0300`"), "{e}");
    }

    #[test]
    fn binary_junk_is_rejected_not_decoded() {
        let mut bytes = b"16 1\n1 2 3\n".to_vec();
        bytes.extend_from_slice(&[0x89, b'P', b'N', b'G', 0, 1]);
        let e = Pattern::parse(&bytes, "x.pat").unwrap_err().to_string();
        assert_eq!(
            e,
            "x.pat:3: byte 0x89 is not text: expected `SIZE NCOLORS` and colour blocks of hex words"
        );
        let e = Pattern::parse(b"\x00\x01", "x.pat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("byte 0x00 is not text"), "{e}");
        // A byte-order mark at the start is named as one; 0xef later is not.
        let e = Pattern::parse(b"\xef\xbb\xbf16 1\n", "bom.pat")
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("(a UTF-8 byte-order mark starts so: save the file without one)"),
            "{e}"
        );
        let e = Pattern::parse(b"16 1\n\xef\xbb\xbf", "x.pat")
            .unwrap_err()
            .to_string();
        assert!(!e.contains("byte-order mark"), "{e}");
    }

    #[test]
    fn directory_and_missing_file_are_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let e = Pattern::read_file(dir.path()).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        let missing = dir.path().join("nope.pat");
        let e = Pattern::read_file(&missing).unwrap_err().to_string();
        assert!(e.starts_with(&missing.display().to_string()), "{e}");
        assert!(e.contains("No such file"), "{e}");
    }

    /// A reader that hands out 1 to 7 bytes a call, in turn: every word,
    /// line end and error falls across a refill somewhere.
    struct Trickle<'a> {
        bytes: &'a [u8],
        next: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            self.next = self.next % 7 + 1;
            let n = self.next.min(buf.len()).min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    fn streamed(bytes: &[u8], name: &str) -> Result<Pattern, ParseError> {
        Pattern::read_from(&mut Trickle { bytes, next: 0 }, name)
    }

    #[test]
    fn a_stream_read_a_few_bytes_at_a_time_parses_as_the_bytes_do() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/patterns");
        let mut seen = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "pat") {
                continue;
            }
            let bytes = std::fs::read(&path).unwrap();
            let whole = Pattern::parse(&bytes, "f.pat").unwrap();
            assert_eq!(streamed(&bytes, "f.pat").unwrap(), whole, "{path:?}");
            seen += 1;
        }
        assert!(seen >= 9, "{seen} fixtures");
        let text = large().to_canonical();
        assert_eq!(streamed(text.as_bytes(), "l.pat").unwrap(), large());
    }

    #[test]
    fn a_stream_gives_the_errors_the_bytes_give() {
        let zeros = vec!["0"; 15].join(" ");
        let mut words = vec!["0"; 16];
        words[2] = "10000";
        let too_many_digits = one_colour(&words.join(" "));
        words[2] = "0xg1";
        let not_hex = one_colour(&words.join(" "));
        let mut junk = b"16 1\n1 2 3\n".to_vec();
        junk.extend_from_slice(&[0x89, b'P', b'N', b'G', 0, 1]);
        let mut cases: Vec<Vec<u8>> = [
            String::new(),
            " \n\t\n".into(),
            "\nsixteen 1".into(),
            "-16 1".into(),
            "root:x:0:0:root:/root 1".into(),
            "17 0".into(),
            "99999999999999999999999 0".into(),
            "16 -1".into(),
            "16 65536".into(),
            "16 1e9".into(),
            "16".into(),
            "16 1\n1 256 3\n".into(),
            "16 1\n1 2 -3\n".into(),
            one_colour(&vec!["0"; 15].join(" ")),
            one_colour(&vec!["0"; 17].join(" ")),
            format!("{}\n# comment", one_colour(&vec!["0"; 16].join(" "))),
            too_many_digits,
            not_hex,
            format!("16 2\n1 1 1\n0100 {zeros}\n2 2 2\n0300 {zeros}"),
            format!("16 1\n1 2 3\n{}x", "f".repeat(40)),
        ]
        .into_iter()
        .map(String::into_bytes)
        .collect();
        cases.push(junk);
        cases.push(b"\x00\x01".to_vec());
        cases.push(b"16 0\r\n\x7f".to_vec());
        for bytes in &cases {
            let whole = Pattern::parse(bytes, "x.pat").unwrap_err();
            assert_eq!(
                streamed(bytes, "x.pat").unwrap_err().to_string(),
                whole.to_string(),
                "{:?}",
                String::from_utf8_lossy(bytes)
            );
        }
    }

    #[test]
    fn a_word_longer_than_a_stream_keeps_is_an_error_naming_its_line() {
        let mut text = b"16 1\n\n".to_vec();
        text.extend(std::iter::repeat_n(b'7', crate::text::MAX_STREAM_WORD + 10));
        let e = Pattern::read_from(&mut &text[..], "w.pat")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "w.pat:3: word 3 `777777777777777777777777...`: a word of more than {} bytes: \
                 expected `SIZE NCOLORS` and colour blocks of hex words",
                crate::text::MAX_STREAM_WORD
            )
        );
    }

    /// `bytes` read in two parts, the first ending at `cut`.
    struct CutAt<'a> {
        bytes: &'a [u8],
        cut: usize,
    }

    impl Read for CutAt<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = match self.cut {
                0 => self.bytes.len(),
                cut => cut,
            }
            .min(buf.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            self.cut = self.cut.saturating_sub(n);
            Ok(n)
        }
    }

    #[test]
    fn a_long_word_is_refused_whatever_the_reads_of_its_stream() {
        // The red value of colour 1 is a decimal of `len` digits, 000...01.
        // A hostile-input review found a word of exactly MAX_STREAM_WORD
        // bytes refused as "more than" that when a pipe's read ended right
        // after it, and one byte longer accepted when it was read whole:
        // the same bytes, two answers, decided by how the reads fell.
        let max = crate::text::MAX_STREAM_WORD;
        for len in [max - 1, max, max + 1] {
            let head = "16 1\n";
            let mut text = head.as_bytes().to_vec();
            text.extend(std::iter::repeat_n(b'0', len - 1));
            text.extend_from_slice(b"1 2 3\n");
            text.extend_from_slice(vec!["ffff"; 16].join("\n").as_bytes());
            let word_end = head.len() + len;
            let reads = [
                Pattern::read_from(&mut &text[..], "w.pat"),
                streamed(&text, "w.pat"),
                Pattern::read_from(
                    &mut CutAt {
                        bytes: &text,
                        cut: word_end,
                    },
                    "w.pat",
                ),
                Pattern::read_from(
                    &mut CutAt {
                        bytes: &text,
                        cut: 4096,
                    },
                    "w.pat",
                ),
                Pattern::parse(&text, "w.pat"),
            ];
            for (i, read) in reads.into_iter().enumerate() {
                if len <= max {
                    let p = read.unwrap_or_else(|e| panic!("{len} bytes, read {i}: {e}"));
                    assert_eq!(p.palette(), [Rgb8([1, 2, 3])]);
                } else {
                    let e = read.expect_err("too long").to_string();
                    assert!(
                        e.starts_with(
                            "w.pat:2: word 3 `000000000000000000000000...`: a word of more than"
                        ),
                        "{len} bytes, read {i}: {e}"
                    );
                }
            }
        }
    }

    /// Whitespace without end after `head`.
    struct Endless {
        head: &'static [u8],
    }

    impl Read for Endless {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.head.len().min(buf.len());
            buf[..n].copy_from_slice(&self.head[..n]);
            self.head = &self.head[n..];
            buf[n..].fill(b' ');
            Ok(buf.len())
        }
    }

    #[test]
    fn an_endless_stream_ends_at_the_bound_its_header_sets() {
        let e = Pattern::read_from(&mut Endless { head: b"16 1\n" }, "-")
            .unwrap_err()
            .to_string();
        let bound = read_limit(16, 1);
        assert!(bound > 2 * sample().canonical_len() as u64);
        assert_eq!(
            e,
            format!(
                "-: is longer than the {bound} bytes the header and 1 colour block of a 16x16 \
                 pattern may take (twice their canonical length and 1 MiB, or the 268435456 \
                 bytes of any .pat read whole, whichever is more)"
            )
        );
        // A header promising more than it sends is bounded by what came.
        let head = b"4096 65535\n1 2 3\n";
        let e = Pattern::read_from(&mut Endless { head }, "-")
            .unwrap_err()
            .to_string();
        let bound = read_limit(4096, 1);
        assert_eq!(bound, crate::io::MAX_NAMED_FILE_BYTES);
        assert!(
            e.starts_with(&format!(
                "-: is longer than the {bound} bytes the header and the first 1 of its 65535 \
                 colour blocks of a 4096x4096 pattern may take"
            )),
            "{e}"
        );
        // The largest pattern pat-from-image writes is well within its bound.
        let biggest = 4096u64 * (4096 / 16 * 5) * 256;
        assert!(read_limit(4096, 256) > 2 * biggest);
    }

    #[test]
    fn a_stream_reads_any_layout_a_file_read_whole_could_have() {
        // A hostile-input review found the stream's bound (twice the
        // canonical length, and 1 MiB) refusing layouts the format allows
        // and reading whole had read: one indented `0xffff` a CRLF line
        // (12 bytes a word, 2.4 times the canonical 5), and a pattern
        // followed by 2 MiB of blank space.
        let mut indented = b"4096 1\r\n    1 2 3\r\n".to_vec();
        for _ in 0..4096 * 256 {
            indented.extend_from_slice(b"    0xffff\r\n");
        }
        let trailing = format!("{}{}", sample().to_canonical(), " ".repeat(2 << 20));
        for text in [&indented[..], trailing.as_bytes()] {
            let whole = Pattern::parse(text, "l.pat").unwrap();
            assert_eq!(Pattern::read_from(&mut &text[..], "l.pat").unwrap(), whole);
        }
    }

    #[test]
    fn new_checks_its_guarantees() {
        assert!(Pattern::new(16, vec![], vec![TRANSPARENT; 255]).is_err());
        assert!(Pattern::new(16, vec![], vec![0; 256]).is_err());
        assert!(Pattern::new(24, vec![], vec![TRANSPARENT; 576]).is_err());
    }

    #[test]
    fn tiled_repeats_scales_and_shifts() {
        let p = sample();
        let t = p.tiled(64, 1, (0, 0)).unwrap();
        for (row, col) in [(0, 0), (17, 33), (63, 63)] {
            assert_eq!(t.index_at(col, row), p.index_at(col % 16, row % 16));
        }
        let t = p.tiled(32, 2, (1, 0)).unwrap();
        // Texel (2,0) of the result is source column 2/2 + 1 = 2.
        assert_eq!(t.index_at(2, 0), p.index_at(2, 0));
        assert_eq!(t.index_at(3, 1), p.index_at(2, 0));
        assert_eq!(t.index_at(0, 0), p.index_at(1, 0));
    }

    /// The canonical text is bounded by MAX_CANONICAL_BYTES: 3,276 colours
    /// at 4096x4096 pass it, 3,277 do not, and the largest pattern
    /// pat-from-image makes (256 colours) is far below it.
    #[test]
    fn canonical_text_longer_than_the_bound_is_refused() {
        let with_colours = |n: usize| {
            let palette = vec![Rgb8([255, 255, 255]); n];
            Pattern::new(4096, palette, vec![0; 4096 * 4096]).unwrap()
        };
        let largest_made = with_colours(256);
        assert!(largest_made.check_canonical_len("").is_ok());
        assert!(largest_made.canonical_len() as u64 * 12 < MAX_CANONICAL_BYTES);
        assert!(with_colours(3276).check_canonical_len("").is_ok());
        let e = with_colours(3277)
            .check_canonical_len("give fewer colours")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "the .pat would be 17180957094 bytes of text (3277 colours of 4096x4096), more \
             than the 17179869184 bytes (16 GiB) a tool writes: give fewer colours"
        );
    }

    /// An offset near `i64::MAX` or `i64::MIN` tiles as its residue modulo
    /// the size: added to the row or column it overflowed (wrong texels in
    /// a release build, a panic in a debug one).
    #[test]
    fn tiled_takes_extreme_offsets_as_their_residue() {
        // 48 texels, not a power of two (whose residues a wrap keeps), and
        // colours of period 5 along both axes.
        let palette = (0..5).map(|i| Rgb8([i * 50, 0, 0])).collect();
        let texels = (0..48 * 48).map(|i| ((i % 48 + 2 * (i / 48)) % 5) as u16);
        let p = Pattern::new(48, palette, texels.collect()).unwrap();
        for off in [(i64::MAX, 0), (0, i64::MAX), (i64::MIN, i64::MAX - 5)] {
            let residue = (off.0.rem_euclid(48), off.1.rem_euclid(48));
            for scale in [1, 3] {
                assert_eq!(
                    p.tiled(48, scale, off).unwrap(),
                    p.tiled(48, scale, residue).unwrap(),
                    "{off:?} scale {scale}"
                );
            }
        }
    }

    #[test]
    fn seams_tell_a_continuing_checker_from_a_cut_gradient() {
        // A 1-texel checker continues across the wrap: seamless both ways.
        let (h, v) = sample().seams();
        assert!(h.seamless && v.seamless, "{h:?} {v:?}");
        // A horizontal ramp of 16 greys: interior steps are small, the wrap
        // jumps from the brightest back to the darkest.
        let palette: Vec<Rgb8> = (0..16).map(|i| Rgb8([i * 17, i * 17, i * 17])).collect();
        let texels: Vec<u16> = (0..256).map(|i| (i % 16) as u16).collect();
        let ramp = Pattern::new(16, palette, texels).unwrap();
        let (h, v) = ramp.seams();
        assert!(!h.seamless && h.seam > 10.0 * h.interior, "{h:?}");
        assert!(v.seamless && v.seam == 0.0, "{v:?}");
    }

    #[test]
    fn a_checker_of_wide_squares_tiles_without_a_seam() {
        // Issue 22, item 9: an 8x8 board of 8-texel squares tiles perfectly,
        // its wrap an edge like its seven inner ones; the mean over every
        // inner boundary (1/9 here) called it a "visible seam".
        let texels: Vec<u16> = (0..64 * 64)
            .map(|i| (((i % 64) / 8 + (i / 64) / 8) % 2) as u16)
            .collect();
        let board = Pattern::new(64, vec![Rgb8::BLACK, Rgb8::WHITE], texels).unwrap();
        for s in [board.seams().0, board.seams().1] {
            assert!(s.seamless && s.seam == 1.0 && s.strongest == 1.0, "{s:?}");
            assert!(s.interior < 0.12, "the diluted mean: {s:?}");
        }
    }

    #[test]
    fn color_wrapped_repeats_in_both_directions() {
        let p = sample();
        assert_eq!(p.color_wrapped(-1, -16), p.color_at(15, 0));
        assert_eq!(p.color_wrapped(16 * 1_000_000 + 3, 5), p.color_at(3, 5));
    }
}
