//! The whitespace tokenizer shared by the project's text formats: `.pat`
//! patterns and the stripe formats (modulation maps, translation maps,
//! colour-code tables). Errors are [`ParseError`]s naming file,
//! line, word number and word; a byte that is not printable ASCII is refused
//! as binary data rather than decoded.
//!
//! One word grammar (`Cursor`) serves two tokenizers: `Words`, over bytes
//! already in memory (the stripe formats, small inputs), and `ReadWords`,
//! over a stream read a chunk at a time (a `.pat`, which may be a gigabyte
//! of text for 32 MiB of texels), with the same lines, word numbers and
//! errors for the same bytes.

use std::fmt;

/// The first byte of a UTF-8 byte-order mark (EF BB BF), which some
/// editors put at the start of a text file: none of the formats has one.
pub(crate) const BOM_FIRST: u8 = 0xEF;

/// The UTF-8 byte-order mark itself, as text.
pub(crate) const BOM: char = '\u{feff}';

/// How an error names a byte-order mark, so that every format says it alike.
pub(crate) const BOM_NAMED: &str = "a UTF-8 byte-order mark (bytes EF BB BF)";

/// `bytes` past a UTF-8 byte-order mark, if they start with one: for a
/// reader that sniffs a format past the mark, to refuse it then in that
/// format's words.
pub(crate) fn without_bom(bytes: &[u8]) -> &[u8] {
    let mut mark = [0; 3];
    BOM.encode_utf8(&mut mark);
    bytes.strip_prefix(mark.as_slice()).unwrap_or(bytes)
}

/// Said after an error at a file's first byte when it is [`BOM_FIRST`]:
/// "byte 0xef is not text" alone left the user to guess (a hostile-input
/// review).
pub(crate) const BOM_HINT: &str = " (a UTF-8 byte-order mark starts so: save the file without one)";

/// The lines of `text` without their ends, as [`str::lines`] gives them,
/// but a line may also end in a bare CR (classic Mac OS text): there
/// `str::lines` saw one line, so every error said line 1 and a `#`
/// comment hid the rest of the file (a hostile-input review). CR LF is
/// one end, as there.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = text;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let line = &rest[..end];
        let after = &rest[end..];
        rest = after
            .strip_prefix("\r\n")
            .or_else(|| after.get(1..))
            .unwrap_or_default();
        Some(line)
    })
}

/// How many lines end in `bytes` (in LF, CR LF or a bare CR, as
/// [`lines`] has it), the byte before them being a CR when `after_cr`.
pub(crate) fn line_ends(bytes: &[u8], after_cr: bool) -> usize {
    let mut cr = after_cr;
    let mut ends = 0;
    for &b in bytes {
        ends += usize::from(b == b'\r' || (b == b'\n' && !cr));
        cr = b == b'\r';
    }
    ends
}

/// Longest word echoed back in an error message (as in `pat.rs`).
const MAX_ECHO: usize = 24;

/// An error at a file's first word means the file did not start as the
/// format does, and then its word is not echoed: a scene may name
/// `/etc/shadow` as a pattern, and its first word is nobody's business.
/// Once a word has been accepted the file is of the format, and the
/// offending word helps the user find the mistake.
const FIRST_WORD: usize = 1;

/// What went wrong reading a text file (a `.pat`, a stripe map or table), and
/// where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    /// The file as the user named it (`-` or `<stdin>` for standard input).
    pub file: String,
    /// 1-based line, when the error has a position.
    pub line: Option<usize>,
    /// 1-based index of the offending word in the file, and the word itself
    /// (empty when the file did not start as the format does: it is not
    /// echoed).
    pub word: Option<(usize, String)>,
    /// What was wrong, or what was expected there.
    pub message: String,
}

impl ParseError {
    pub(crate) fn io(file: &str, e: std::io::Error) -> ParseError {
        ParseError {
            file: file.to_string(),
            line: None,
            word: None,
            message: e.to_string(),
        }
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        match &self.word {
            Some((n, w)) if w.is_empty() => write!(f, ": word {n}")?,
            Some((n, w)) => write!(f, ": word {n} `{w}`")?,
            None => {}
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for ParseError {}

/// One word of a file with its position.
#[derive(Debug)]
pub(crate) struct Word<'a> {
    pub text: &'a str,
    pub line: usize,
    pub index: usize,
}

/// The error at word `index` (`text`, on `line`) of `file`. The first word
/// is not echoed (`FIRST_WORD`) unless it is written as a number (a sign,
/// digits, a point, an exponent, or NaN or infinity: `-16`, `1.5`, `nan`),
/// which is nobody's secret and which the user must see to mend (`-16 1`
/// and `nan 1` both said only "word 1: expected the pattern size", a
/// hostile-input review); a long one is cut at `MAX_ECHO`.
fn word_error(file: &str, text: &str, line: usize, index: usize, message: String) -> ParseError {
    let mut error = number_error(file, text, line, index, message);
    if index == FIRST_WORD && !written_as_number(text) {
        error.word = Some((index, String::new()));
    }
    error
}

/// Whether `text` is a number as languages write one: an optional sign,
/// digits with at most one point among them, and an optional exponent
/// (`e`, an optional sign, digits), or NaN or infinity (`-16`, `+1.5e3`,
/// `.5`, `nan`, `-Infinity`): the grammar of Rust's `f64::from_str`. Not a
/// date, an address or an identity number (`2024-01-01`, `192.168.1.10`,
/// `078-05-1120`): those stay unechoed (a review).
fn written_as_number(text: &str) -> bool {
    text.parse::<f64>().is_ok()
}

/// [`word_error`] for a word of digits that is out of range, echoed even
/// as the first word: digits are a number, nobody's secret, and the
/// message must show the number as written (a saturated 23-digit size was
/// shown as `pattern size 18446744073709551615`).
fn number_error(file: &str, text: &str, line: usize, index: usize, message: String) -> ParseError {
    let mut echo: String = text.chars().take(MAX_ECHO).collect();
    if text.len() > MAX_ECHO {
        echo.push_str("...");
    }
    ParseError {
        file: file.to_string(),
        line: Some(line),
        word: Some((index, echo)),
        message,
    }
}

/// The error of a file that ended where `what` was expected: "empty file"
/// when it had no word at all (`what_file` says what it should contain).
fn end_error(file: &str, cursor: &Cursor, what: &str, what_file: &str) -> ParseError {
    if cursor.count == 0 {
        return ParseError {
            file: file.to_string(),
            line: None,
            word: None,
            message: format!("empty file: expected {what_file}"),
        };
    }
    ParseError {
        file: file.to_string(),
        line: Some(cursor.last_line),
        word: None,
        message: format!("unexpected end of file: expected {what}"),
    }
}

/// Why a word is not an unsigned decimal in range ([`decimal_value`]),
/// with the error's message.
enum BadDecimal {
    /// Not a decimal: the word is echoed as any other ([`word_error`]).
    NotDigits(String),
    /// Digits past `max` or past `u64::MAX`: the word is echoed as written
    /// ([`number_error`]).
    OutOfRange(String),
}

/// `text` as an unsigned decimal of at most `max`. A value past `u64::MAX`
/// is out of range whatever `max` is: it saturated, and a caller that
/// checks the value itself (a pattern's size, a map's length, `max`
/// `u64::MAX`) said `18446744073709551615`, a number nobody wrote.
fn decimal_value(text: &str, what: &str, max: u64) -> Result<u64, BadDecimal> {
    if !text.bytes().all(|c| c.is_ascii_digit()) {
        return Err(BadDecimal::NotDigits(format!("expected {what}")));
    }
    let v = text.bytes().try_fold(0u64, |acc, c| {
        acc.checked_mul(10)?.checked_add((c - b'0') as u64)
    });
    match v {
        Some(v) if v <= max => Ok(v),
        _ => Err(BadDecimal::OutOfRange(format!(
            "out of range: expected {what}"
        ))),
    }
}

/// What [`Cursor::scan`] found.
enum Scan {
    /// A word at `start..end` of the bytes.
    Word(usize, usize),
    /// No more words.
    End,
    /// The bytes ended inside a word, or before one, and more may follow.
    More,
}

/// Where the tokenizer is: kept across a stream's refills, so that lines
/// and word numbers count from the file's start whatever its chunks.
#[derive(Clone, Copy, Debug)]
struct Cursor {
    /// Whether `#` starts a comment.
    comments: bool,
    /// Offset of the next byte to look at.
    pos: usize,
    line: usize,
    count: usize,
    last_line: usize,
    /// Inside a comment that the bytes so far did not end.
    in_comment: bool,
    /// The last byte looked at was a CR, so an LF now ends no new line: a
    /// line ends in LF, CR LF or a bare CR, as [`lines`] has it.
    after_cr: bool,
}

impl Cursor {
    fn new(comments: bool) -> Cursor {
        Cursor {
            comments,
            pos: 0,
            line: 1,
            count: 0,
            last_line: 1,
            in_comment: false,
            after_cr: false,
        }
    }

    /// The grammar of words, the one both tokenizers use: the next word of
    /// `b` from `pos`, whitespace and comments skipped. Unless `at_eof`, a
    /// word reaching the end of `b` may go on in the next chunk: that is
    /// `More`, with `pos` left at the word's start. A byte that is neither
    /// whitespace nor printable ASCII is `Err(byte)` on `line`.
    fn scan(&mut self, b: &[u8], at_eof: bool) -> Result<Scan, u8> {
        loop {
            if self.in_comment {
                match memchr::memchr2(b'\n', b'\r', &b[self.pos..]) {
                    Some(n) => {
                        self.pos += n;
                        self.in_comment = false;
                    }
                    None => {
                        self.pos = b.len();
                        return Ok(if at_eof { Scan::End } else { Scan::More });
                    }
                }
            }
            while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
                let c = b[self.pos];
                if c == b'\r' || (c == b'\n' && !self.after_cr) {
                    self.line += 1;
                }
                self.after_cr = c == b'\r';
                self.pos += 1;
            }
            if self.comments && self.pos < b.len() && b[self.pos] == b'#' {
                self.in_comment = true;
                self.after_cr = false;
                continue;
            }
            break;
        }
        if self.pos == b.len() {
            return Ok(if at_eof { Scan::End } else { Scan::More });
        }
        let start = self.pos;
        let mut end = start;
        while end < b.len() && !b[end].is_ascii_whitespace() {
            let c = b[end];
            if !c.is_ascii_graphic() {
                return Err(c);
            }
            end += 1;
        }
        if end == b.len() && !at_eof {
            return Ok(Scan::More);
        }
        self.pos = end;
        self.after_cr = false;
        self.count += 1;
        self.last_line = self.line;
        Ok(Scan::Word(start, end))
    }

    /// The error for byte `c`, which is not text.
    fn not_text(&self, file: &str, c: u8, what_file: &str) -> ParseError {
        ParseError {
            file: file.to_string(),
            line: Some(self.line),
            word: None,
            message: format!(
                "byte 0x{c:02x} is not text: expected {what_file}{}",
                if c == BOM_FIRST && self.line == 1 && self.count == 0 {
                    BOM_HINT
                } else {
                    ""
                }
            ),
        }
    }
}

/// Words of a text file with their lines. In the stripe formats `#` starts a
/// comment to the end of the line (the maps are generated by scripts that like
/// to say how); the `.pat` format has no comments.
pub(crate) struct Words<'a> {
    bytes: &'a [u8],
    cursor: Cursor,
    pub name: &'a str,
    /// What the file should contain, for the "empty file" message.
    what: &'static str,
}

impl<'a> Words<'a> {
    /// A tokenizer where `#` starts a comment.
    pub fn new(bytes: &'a [u8], name: &'a str, what: &'static str) -> Self {
        Words {
            cursor: Cursor::new(true),
            ..Words::without_comments(bytes, name, what)
        }
    }

    /// A tokenizer with no comments: `#` is a word like any other.
    pub fn without_comments(bytes: &'a [u8], name: &'a str, what: &'static str) -> Self {
        Words {
            bytes,
            cursor: Cursor::new(false),
            name,
            what,
        }
    }

    pub fn error_at(&self, w: &Word, message: String) -> ParseError {
        word_error(self.name, w.text, w.line, w.index, message)
    }

    /// Next word, `Ok(None)` at the end, or an error on a byte that is not text.
    pub fn next(&mut self) -> Result<Option<Word<'a>>, ParseError> {
        match self.cursor.scan(self.bytes, true) {
            Ok(Scan::Word(start, end)) => Ok(Some(Word {
                text: std::str::from_utf8(&self.bytes[start..end]).expect("checked ASCII"),
                line: self.cursor.line,
                index: self.cursor.count,
            })),
            Ok(Scan::End | Scan::More) => Ok(None),
            Err(c) => Err(self.cursor.not_text(self.name, c, self.what)),
        }
    }

    /// The next word, or an error naming what was expected.
    pub fn expect(&mut self, what: &str) -> Result<Word<'a>, ParseError> {
        match self.next()? {
            Some(w) => Ok(w),
            None => Err(end_error(self.name, &self.cursor, what, self.what)),
        }
    }

    /// An unsigned decimal of at most `max` ([`decimal_value`]).
    pub fn decimal(&mut self, what: &str, max: u64) -> Result<u64, ParseError> {
        let w = self.expect(what)?;
        self.decimal_of(&w, what, max)
    }

    pub fn decimal_of(&self, w: &Word, what: &str, max: u64) -> Result<u64, ParseError> {
        decimal_value(w.text, what, max).map_err(|e| match e {
            BadDecimal::NotDigits(m) => self.error_at(w, m),
            BadDecimal::OutOfRange(m) => number_error(self.name, w.text, w.line, w.index, m),
        })
    }

    /// Fails if anything but comments and whitespace remains.
    pub fn end(&mut self, expected_count: &str) -> Result<(), ParseError> {
        match self.next()? {
            None => Ok(()),
            Some(w) => Err(self.error_at(
                &w,
                format!("trailing data: the file ends after {expected_count}"),
            )),
        }
    }
}

/// A [`ReadWords`] error, boxed: its `Result`s are returned once a word,
/// and a `Result` holding a whole `ParseError` (over 100 bytes) was moved
/// about so often that the moves were half of reading a `.pat` (`perf` of
/// `pat-info --check` on an 84 MB pattern).
pub(crate) type Failed = Box<ParseError>;

/// The longest word a stream's words may have: 64 KiB, thousands of times
/// any word of the formats, and a bound on the buffer of a stream that is
/// one endless word.
pub(crate) const MAX_STREAM_WORD: usize = 1 << 16;

/// Bytes read from a stream at a time.
const STREAM_CHUNK: usize = 1 << 18;

/// Where a word of [`ReadWords`] is: its text is
/// [`ReadWords::text`] until the next word is read.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Span {
    start: usize,
    end: usize,
    pub line: usize,
    pub index: usize,
}

/// The words of a text read from a stream a chunk at a time, in a buffer of
/// at most `STREAM_CHUNK` plus `MAX_STREAM_WORD` bytes however long the
/// text: a `.pat` of 4096x4096 texels in 256 colours is 1.3 GB. Lines,
/// word numbers and every error are those [`Words`] gives for the same
/// bytes; a word longer than [`MAX_STREAM_WORD`] is an error. No comments
/// (the `.pat` format has none).
pub(crate) struct ReadWords<'a> {
    reader: &'a mut dyn std::io::Read,
    /// The unread part of the text: `buf[cursor.pos..]`.
    buf: Vec<u8>,
    cursor: Cursor,
    eof: bool,
    /// Bytes read so far, and the most that may be read, with why.
    read: u64,
    limit: u64,
    limit_reason: String,
    pub name: &'a str,
    what: &'static str,
}

impl<'a> ReadWords<'a> {
    /// The words of `reader`, all of them unless [`ReadWords::set_limit`]
    /// says otherwise.
    pub fn new(reader: &'a mut dyn std::io::Read, name: &'a str, what: &'static str) -> Self {
        ReadWords {
            reader,
            buf: Vec::new(),
            cursor: Cursor::new(false),
            eof: false,
            read: 0,
            limit: u64::MAX,
            limit_reason: String::new(),
            name,
            what,
        }
    }

    /// Reading more than `limit` bytes in all is an error saying so, and
    /// `reason` (what the bound is): an endless input must end.
    pub fn set_limit(&mut self, limit: u64, reason: String) {
        self.limit = limit;
        self.limit_reason = reason;
    }

    /// Drops what was scanned and reads the next chunk after the rest.
    fn refill(&mut self) -> Result<(), Failed> {
        let pos = self.cursor.pos;
        self.buf.drain(..pos);
        self.cursor.pos = 0;
        // What is left is the start of a word that the bytes so far did
        // not end: already too long, it is refused before more is read.
        if self.buf.len() > MAX_STREAM_WORD {
            return Err(self.too_long(0, self.cursor.line, self.cursor.count + 1));
        }
        let kept = self.buf.len();
        self.buf.resize(kept + STREAM_CHUNK, 0);
        let n = loop {
            match self.reader.read(&mut self.buf[kept..]) {
                Ok(n) => break n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(ParseError::io(self.name, e).into()),
            }
        };
        self.buf.truncate(kept + n);
        self.eof = n == 0;
        self.read += n as u64;
        if self.read > self.limit {
            return Err(ParseError {
                file: self.name.to_string(),
                line: None,
                word: None,
                message: format!(
                    "is longer than the {} bytes {}",
                    self.limit, self.limit_reason
                ),
            }
            .into());
        }
        Ok(())
    }

    /// The error of the word at `start` of the buffer (word `index`, on
    /// `line`), longer than [`MAX_STREAM_WORD`].
    fn too_long(&self, start: usize, line: usize, index: usize) -> Failed {
        let echo = &self.buf[start..start + MAX_ECHO + 1];
        let text = std::str::from_utf8(echo).expect("checked ASCII");
        word_error(
            self.name,
            text,
            line,
            index,
            format!(
                "a word of more than {MAX_STREAM_WORD} bytes: expected {}",
                self.what
            ),
        )
        .into()
    }

    /// Next word, `Ok(None)` at the end, or an error on a byte that is not
    /// text, a word too long, a failed read or the limit passed.
    pub fn next(&mut self) -> Result<Option<Span>, Failed> {
        loop {
            match self.cursor.scan(&self.buf, self.eof) {
                Ok(Scan::Word(start, end)) => {
                    // Whether a long word is refused must not depend on
                    // where the reads of the input happened to end: a word
                    // whole in one chunk is held to the same bound as one
                    // that spans refills.
                    if end - start > MAX_STREAM_WORD {
                        return Err(self.too_long(start, self.cursor.line, self.cursor.count));
                    }
                    return Ok(Some(Span {
                        start,
                        end,
                        line: self.cursor.line,
                        index: self.cursor.count,
                    }));
                }
                Ok(Scan::End) => return Ok(None),
                Ok(Scan::More) => self.refill()?,
                Err(c) => return Err(self.cursor.not_text(self.name, c, self.what).into()),
            }
        }
    }

    /// The text of the word last read.
    pub fn text(&self, w: &Span) -> &str {
        std::str::from_utf8(&self.buf[w.start..w.end]).expect("checked ASCII")
    }

    pub fn error_at(&self, w: &Span, message: String) -> Failed {
        word_error(self.name, self.text(w), w.line, w.index, message).into()
    }

    /// The next word, or an error naming what was expected.
    pub fn expect(&mut self, what: &str) -> Result<Span, Failed> {
        match self.next()? {
            Some(w) => Ok(w),
            None => Err(end_error(self.name, &self.cursor, what, self.what).into()),
        }
    }

    /// An unsigned decimal of at most `max` ([`decimal_value`]).
    pub fn decimal(&mut self, what: &str, max: u64) -> Result<u64, Failed> {
        let w = self.expect(what)?;
        self.decimal_of(&w, what, max)
    }

    pub fn decimal_of(&self, w: &Span, what: &str, max: u64) -> Result<u64, Failed> {
        let text = self.text(w);
        decimal_value(text, what, max).map_err(|e| match e {
            BadDecimal::NotDigits(m) => self.error_at(w, m),
            BadDecimal::OutOfRange(m) => number_error(self.name, text, w.line, w.index, m).into(),
        })
    }
}

/// A number as a person writes it in a message: four significant digits at
/// most, no trailing zeros, an exponent only outside 1e-4 ..< 1e9 (`0.25`,
/// `1.414`, `1200`, `3e-300`; not `1.4142135623730951e1`).
pub fn readable(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    // Rounded to 4 significant digits first, so the exponent is the rounded one's.
    let sci = format!("{x:.3e}");
    let (mantissa, exp) = sci.split_once('e').expect("{:e} has an exponent");
    let exp: i32 = exp.parse().expect("{:e}'s exponent is an integer");
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if (-4..9).contains(&exp) {
        let decimals = (3 - exp).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    } else {
        format!("{}e{exp}", trim(mantissa))
    }
}

/// Longest run of digits (with its sign and point) that a message keeps as
/// written: `u64::MAX` has 20 digits; Rust prints an `f64` without an
/// exponent, so 1e-300 is a 302-character decimal and 1e300 a 301-digit one.
const LONGEST_PLAIN_NUMBER: usize = 21;

/// `message` with every number longer than `LONGEST_PLAIN_NUMBER` (21)
/// characters written with an exponent, the same value to the last bit (its
/// shortest round-trip form): `right 0.000…0001` (302 characters) becomes
/// `right 1e-300`. For messages that echo numbers as Rust displays them.
pub fn shorten_long_numbers(message: &str) -> std::borrow::Cow<'_, str> {
    let bytes = message.as_bytes();
    let is_num = |b: u8| b.is_ascii_digit() || b == b'.';
    let mut out = String::new();
    let (mut copied, mut i) = (0, 0);
    while i < bytes.len() {
        if !bytes[i].is_ascii_digit() {
            i += 1;
            continue;
        }
        let start = if i > 0 && bytes[i - 1] == b'-' {
            i - 1
        } else {
            i
        };
        let mut end = i;
        while end < bytes.len() && is_num(bytes[end]) {
            end += 1;
        }
        // A sentence's full stop is not part of the number.
        let mut num_end = end;
        while num_end > i && bytes[num_end - 1] == b'.' {
            num_end -= 1;
        }
        let token = &message[start..num_end];
        // Digits inside a word (a file name such as `f%0099...9d.png` or
        // `frame000...0.png`) are the user's text, echoed as given; so are
        // digits quoted in backticks, the way messages echo a user's word
        // (a .pat's `999...` of 26 digits, cut to 24, was shown `1e24...`).
        let in_word = |b: u8| b.is_ascii_alphanumeric() || b"_%/\\`".contains(&b);
        let inside =
            (start > 0 && in_word(bytes[start - 1])) || (end < bytes.len() && in_word(bytes[end]));
        if token.len() > LONGEST_PLAIN_NUMBER && !inside {
            if let Ok(x) = token.parse::<f64>() {
                out.push_str(&message[copied..start]);
                out.push_str(&format!("{x:e}"));
                copied = num_end;
            }
        }
        i = end;
    }
    if copied == 0 {
        return std::borrow::Cow::Borrowed(message);
    }
    out.push_str(&message[copied..]);
    std::borrow::Cow::Owned(out)
}

/// `message` on one line, its control characters written as Rust escapes
/// (`\n`, `\t`, `\u{1b}`): an error or a warning echoes the user's file
/// names, and a name holding a newline split the message over two lines
/// (a script reading one line a message lost the rest), one holding an
/// escape sequence could rewrite the terminal. The Unicode line and
/// paragraph separators and the bidirectional embeddings, overrides and
/// isolates, which are not control characters but break a line or reorder
/// what a terminal shows, are written as `\u{...}` too.
pub fn one_line(message: &str) -> std::borrow::Cow<'_, str> {
    if !message.chars().any(breaks_a_line) {
        return std::borrow::Cow::Borrowed(message);
    }
    let mut out = String::with_capacity(message.len() + 8);
    for c in message.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else if breaks_a_line(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// Whether [`one_line`] writes `c` as an escape.
fn breaks_a_line(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{2028}' | '\u{2029}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

#[cfg(test)]
mod tests {
    use super::{line_ends, lines, one_line, readable, shorten_long_numbers, ReadWords, Words};

    /// A reader that gives one byte a read, so that every CR LF is split
    /// between two chunks.
    struct ByteAtATime<'a>(&'a [u8]);

    impl std::io::Read for ByteAtATime<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let Some((first, rest)) = self.0.split_first() else {
                return Ok(0);
            };
            buf[0] = *first;
            self.0 = rest;
            Ok(1)
        }
    }

    /// LF, CR LF and a bare CR each end one line, in the line splitter, the
    /// line counter and both tokenizers, however the bytes are read; a `#`
    /// comment ends at a bare CR. The lines are counted by hand here.
    #[test]
    fn a_bare_cr_ends_a_line_and_cr_lf_is_one_end() {
        let text = "a\rb\r\nc\n\r\rd # x\re\r";
        assert_eq!(
            lines(text).collect::<Vec<_>>(),
            ["a", "b", "c", "", "", "d # x", "e"]
        );
        assert_eq!(lines("a\r\n").collect::<Vec<_>>(), ["a"]);
        assert_eq!(lines("").count(), 0);
        assert_eq!(line_ends(text.as_bytes(), false), 7);
        // A CR before the bytes makes their first LF no new end.
        assert_eq!(line_ends(b"\nx\n", true), 1);
        let want = [("a", 1), ("b", 2), ("c", 3), ("d", 6), ("e", 7)];
        let mut w = Words::new(text.as_bytes(), "t", "");
        let mut got = Vec::new();
        while let Some(word) = w.next().unwrap() {
            got.push((word.text, word.line));
        }
        assert_eq!(got, want);
        // Without comments, as a `.pat` is read, a chunk at a time.
        for chunked in [false, true] {
            let mut whole = text.as_bytes();
            let mut bytes = ByteAtATime(text.as_bytes());
            let reader: &mut dyn std::io::Read = if chunked { &mut bytes } else { &mut whole };
            let mut r = ReadWords::new(reader, "t", "");
            let mut got = Vec::new();
            while let Some(span) = r.next().ok().flatten() {
                got.push((r.text(&span).to_string(), span.line));
            }
            let at = |w: &str, line| (w.to_string(), line);
            let want = [
                at("a", 1),
                at("b", 2),
                at("c", 3),
                at("d", 6),
                at("#", 6),
                at("x", 6),
                at("e", 7),
            ];
            assert_eq!(got, want, "chunked {chunked}");
        }
    }

    #[test]
    fn long_numbers_in_messages_get_an_exponent() {
        let tiny = format!("left 0 equals right {}: zero-width", 1e-300);
        assert!(tiny.len() > 300);
        assert_eq!(
            shorten_long_numbers(&tiny),
            "left 0 equals right 1e-300: zero-width"
        );
        let huge = format!("x {} and -{}.", 1e300, 2.5e-30);
        assert_eq!(shorten_long_numbers(&huge), "x 1e300 and -2.5e-30.");
        // Numbers a person writes stay as they are, and so do u64 counts.
        for keep in [
            "record 12: 0.25 of 1.4142135623730951",
            "549755813888 polygons, 18446744073709551615 at most",
            "version 1.2.3",
        ] {
            assert_eq!(shorten_long_numbers(keep), keep);
        }
        // Digits that are part of a word, as in a file name, stay as given.
        let zeros = "0".repeat(255);
        for keep in [
            "-o f%0099999999999999999999999d.png: too wide".to_string(),
            format!("renaming the output to f{zeros}.png: File name too long"),
            format!("{zeros}.png and dir/{zeros}/x and {zeros}_1"),
            // A word quoted as the user wrote it (cut to 24 characters).
            "t.pat:1: word 2 `999999999999999999999999...`: out of range".to_string(),
            format!("invalid size `{zeros}`: expected N"),
        ] {
            assert_eq!(shorten_long_numbers(&keep), keep);
        }
        // The exponent form is the same value.
        let x = 1.2345678901234567e-25;
        let s = shorten_long_numbers(&format!("{x}")).into_owned();
        assert_eq!(s.parse::<f64>().unwrap(), x);
    }

    #[test]
    fn readable_numbers() {
        for (x, want) in [
            (0.25, "0.25"),
            (std::f64::consts::SQRT_2, "1.414"),
            (14.142135623730951, "14.14"),
            (1200.0, "1200"),
            (123456.7, "123457"),
            (1e-300, "1e-300"),
            (-2.5e12, "-2.5e12"),
            (0.00012346, "0.0001235"),
            (0.0, "0"),
            (9.99996, "10"),
        ] {
            assert_eq!(readable(x), want, "{x}");
        }
    }

    #[test]
    fn one_line_escapes_control_characters_and_keeps_the_rest() {
        assert_eq!(one_line("a.png: not found"), "a.png: not found");
        assert_eq!(one_line("a\nb.png: é"), "a\\nb.png: é");
        assert_eq!(one_line("x\u{1b}[2J\ty\r"), "x\\u{1b}[2J\\ty\\r");
        assert!(matches!(one_line("plain"), std::borrow::Cow::Borrowed(_)));
        // A right-to-left override and a line separator: not control
        // characters, but they reorder or break what is shown.
        assert_eq!(
            one_line("a\u{202e}gnp.exe\u{2028}"),
            "a\\u{202e}gnp.exe\\u{2028}"
        );
    }
}
