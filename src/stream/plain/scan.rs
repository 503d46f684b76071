//! The plain line read by hand, as the tools and most generators write it:
//! `"vertices"` and `"color"` read straight into numbers, any other field
//! stepped over by serde (by hand when it is an integer or an array of
//! integers, [`Scanner::integers`]). serde's route spent
//! its time in visitor calls and number parsing; this one walks the bytes
//! once: the read phase of a million random triangles took 0.58 s against
//! 0.65-0.67 through serde's route (paired runs, `bench/RESULTS-stream.md`).
//!
//! For polyfill3's cells (17-digit coordinates, a `"texel"` and the
//! input's own fields) the line is checked as UTF-8 once, digits are read
//! eight at a time and integer fields stepped over by hand: reading and
//! drawing 100,000 of them took 1.68 G instructions against 1.88 before
//! (callgrind, one thread, `bench/RESULTS-stream.md`).
//!
//! It only ever *accepts* what serde's route accepts, with the same numbers
//! to the bit; anything it does not know (a key with an escape, a repeated
//! vertices or colour, a key the fast path declines, a number that is not a
//! plain JSON number, a colour that is not a decimal from 0 to 255, a
//! syntax error) gives `None`, and serde's route reads the line as before.
//! The tests hold it to that route bit for bit.

use super::super::is_value_key;
use glam::DVec3;
use serde_json::value::RawValue;
use serde_json::Value;

/// What [`vertices_and_color`] found.
pub(super) enum Scanned {
    /// A line the fast path keeps: its colour.
    Plain([u8; 3]),
    /// Anything else: serde's route reads the line.
    Other,
    /// More vertices than a polygon may have: the general path words it,
    /// and serde's route need not read them all again.
    TooMany,
}

/// The colour of `line` (one JSON value, trimmed), its vertices appended
/// to `verts`, if it is an object with both that the fast path keeps;
/// otherwise (with `verts` as it was) what to do with it.
pub(super) fn vertices_and_color(line: &[u8], verts: &mut Vec<DVec3>) -> Scanned {
    // One UTF-8 check of the whole line, so that keys and the texts of
    // numbers are cut from it as `str` without one each (about ten a line
    // of polyfill3's cells; `from_utf8` was 4.6% of the instructions of
    // reading and drawing them, callgrind). A line that is not UTF-8 is
    // serde's route's to refuse, as before.
    let Ok(text) = std::str::from_utf8(line) else {
        return Scanned::Other;
    };
    let start = verts.len();
    let mut s = Scanner::new(text);
    match scan_object(&mut s, verts) {
        Some(color) => Scanned::Plain(color),
        None => {
            verts.truncate(start);
            match s.too_many {
                true => Scanned::TooMany,
                false => Scanned::Other,
            }
        }
    }
}

/// [`vertices_and_color`], leaving what it appended on failure.
fn scan_object(s: &mut Scanner, verts: &mut Vec<DVec3>) -> Option<[u8; 3]> {
    s.byte(b'{')?;
    let (mut vertices, mut color) = (false, None);
    // The other keys so far, to decline a repeated one (the general path
    // refuses it); a line of more declines too.
    let mut others: [&str; MOST_OTHER_KEYS] = [""; MOST_OTHER_KEYS];
    let mut n_others = 0;
    loop {
        s.byte(b'"')?;
        let key = s.key()?;
        s.byte(b':')?;
        if !matches!(key, "vertices" | "color") {
            if n_others == MOST_OTHER_KEYS || others[..n_others].contains(&key) {
                return None;
            }
            others[n_others] = key;
            n_others += 1;
        }
        match key {
            "vertices" if !vertices => {
                s.points(verts)?;
                vertices = true;
            }
            "color" if color.is_none() => color = Some(s.color()?),
            // Repeated (serde's route declines them too) or declined.
            "vertices" | "color" => return None,
            k if super::declines(k) => return None,
            // Checked as serde's route checks them (`super::Key`): a known
            // field must parse as a `Value`, any other as JSON text.
            k if is_value_key(k) => s.skip_field::<Value>()?,
            _ => s.skip_field::<&RawValue>()?,
        }
        match s.next()? {
            b',' => continue,
            b'}' => break,
            _ => return None,
        }
    }
    s.skip_ws();
    (vertices && s.i == s.b.len()).then_some(color?)
}

/// The most keys besides `"vertices"` and `"color"` a line the scanner
/// reads may have (polyfill3's cells have two or three, a generator's own
/// ids and tags a few more); a line of more goes by serde's route.
const MOST_OTHER_KEYS: usize = 16;

/// A cursor over the line.
struct Scanner<'a> {
    /// The line, and its bytes.
    s: &'a str,
    b: &'a [u8],
    i: usize,
    /// Whether the scan stopped at a vertex past [`super::MAX_VERTICES`].
    too_many: bool,
}

/// What [`Scanner::short_decimal`] read.
enum Short {
    /// The number, read whole.
    Value(f64),
    /// The integer digits and eight fraction digits, as one integer: more
    /// may follow.
    LongFraction(u64),
    /// Nothing read: another form, or one to refuse.
    Other,
}

/// `10^k` for the exactly representable `k <= 22` (Clinger's fast path).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

impl<'a> Scanner<'a> {
    fn new(s: &'a str) -> Scanner<'a> {
        Scanner {
            s,
            b: s.as_bytes(),
            i: 0,
            too_many: false,
        }
    }

    /// Skips JSON whitespace (RFC 8259 §2: space, tab, newline, return).
    #[inline]
    fn skip_ws(&mut self) {
        while let Some(b' ' | b'\t' | b'\n' | b'\r') = self.b.get(self.i) {
            self.i += 1;
        }
    }

    /// The next byte after whitespace, consumed.
    #[inline]
    fn next(&mut self) -> Option<u8> {
        self.skip_ws();
        let c = *self.b.get(self.i)?;
        self.i += 1;
        Some(c)
    }

    /// Consumes `want` after whitespace, or fails.
    #[inline]
    fn byte(&mut self, want: u8) -> Option<()> {
        (self.next()? == want).then_some(())
    }

    /// A key after its opening quote, through its closing one: `None` for
    /// one with an escape or a control character (serde's route reads
    /// those) or that is not UTF-8.
    fn key(&mut self) -> Option<&'a str> {
        let start = self.i;
        loop {
            match *self.b.get(self.i)? {
                b'"' => break,
                b'\\' | 0..=0x1f => return None,
                _ => self.i += 1,
            }
        }
        self.i += 1;
        // Cut between ASCII quotes, so on character boundaries.
        self.s.get(start..self.i - 1)
    }

    /// Steps over the field's value: by hand when it is an integer or an
    /// array of them ([`Scanner::integers`]), else by serde as `T`.
    fn skip_field<T: serde::Deserialize<'a>>(&mut self) -> Option<()> {
        let at = self.i;
        if self.integers().is_some() {
            return Some(());
        }
        self.i = at;
        self.skip_value::<T>()
    }

    /// Steps over an integer of at most 18 digits, or a flat array of
    /// them, if that is what starts here: polyfill3's `"texel"` (`[column,
    /// row]`) and most generators' ids. Such a value is a `Value` (a `u64`
    /// or an `i64`) and a `RawValue` alike, so serde's route takes it too,
    /// and stepping over it by hand spares a serde deserializer made for
    /// the field and, for `"texel"`, a `Value` built and freed. `None` (the
    /// cursor anywhere) for anything else.
    fn integers(&mut self) -> Option<()> {
        self.skip_ws();
        if self.b.get(self.i) != Some(&b'[') {
            return self.integer();
        }
        self.i += 1;
        self.skip_ws();
        if self.b.get(self.i) == Some(&b']') {
            self.i += 1;
            return Some(());
        }
        loop {
            self.integer()?;
            match self.next()? {
                b',' => continue,
                b']' => return Some(()),
                _ => return None,
            }
        }
    }

    /// An integer of at most 18 digits, not followed by a fraction or an
    /// exponent (those are left to serde).
    fn integer(&mut self) -> Option<()> {
        self.skip_ws();
        self.i += usize::from(self.b.get(self.i) == Some(&b'-'));
        let start = self.i;
        while let Some(b'0'..=b'9') = self.b.get(self.i) {
            self.i += 1;
        }
        let len = self.i - start;
        let leading_zero = len > 1 && self.b[start] == b'0';
        let more = matches!(self.b.get(self.i), Some(b'.' | b'e' | b'E'));
        ((1..=18).contains(&len) && !leading_zero && !more).then_some(())
    }

    /// Steps over the JSON value that starts here if it deserializes as
    /// `T`: serde_json's own parser reads it and says where it ended.
    fn skip_value<T: serde::Deserialize<'a>>(&mut self) -> Option<()> {
        let mut values = serde_json::Deserializer::from_slice(&self.b[self.i..]).into_iter::<T>();
        values.next()?.ok()?;
        self.i += values.byte_offset();
        Some(())
    }

    /// `[[x, y] or [x, y, z], ...]` appended to `out`: z = 0 for `[x, y]`,
    /// as serde's route.
    fn points(&mut self, out: &mut Vec<DVec3>) -> Option<()> {
        self.byte(b'[')?;
        let start = out.len();
        self.skip_ws();
        if self.b.get(self.i) == Some(&b']') {
            self.i += 1;
            return Some(());
        }
        loop {
            self.byte(b'[')?;
            let x = self.number()?;
            self.byte(b',')?;
            let y = self.number()?;
            let z = match self.next()? {
                b',' => {
                    let z = self.number()?;
                    self.byte(b']')?;
                    z
                }
                b']' => 0.0,
                _ => return None,
            };
            if out.len() - start == super::MAX_VERTICES {
                self.too_many = true;
                return None;
            }
            out.push(DVec3::new(x, y, z));
            match self.next()? {
                b',' => continue,
                b']' => return Some(()),
                _ => return None,
            }
        }
    }

    /// `[r, g, b]`, each a decimal integer from 0 to 255 (serde reads a
    /// `u8` from no other JSON number).
    fn color(&mut self) -> Option<[u8; 3]> {
        self.byte(b'[')?;
        let mut c = [0u8; 3];
        for (k, slot) in c.iter_mut().enumerate() {
            if k > 0 {
                self.byte(b',')?;
            }
            self.skip_ws();
            let start = self.i;
            let mut v = 0u32;
            while let Some(d @ b'0'..=b'9') = self.b.get(self.i) {
                v = v * 10 + u32::from(d - b'0');
                self.i += 1;
                if self.i - start > 3 {
                    return None;
                }
            }
            let digits = self.i - start;
            let leading_zero = digits > 1 && self.b[start] == b'0';
            if digits == 0 || leading_zero || v > 255 {
                return None;
            }
            *slot = v as u8;
        }
        self.byte(b']')?;
        Some(c)
    }

    /// A JSON number (RFC 8259 §6), correctly rounded to the nearest `f64`
    /// as serde_json's `float_roundtrip` parser gives it. While its digits'
    /// integer stays below 2^53 and the decimal exponent within ±22, both
    /// the integer and the power of ten are exact `f64`s, so one IEEE
    /// multiplication or division is the correctly rounded value (Clinger's
    /// fast path); anything else goes to the standard library's correctly
    /// rounded parser. An overflow to infinity, or non-zero digits that
    /// underflow to zero, are left to serde's route, which words them.
    ///
    /// Inlined into its callers for its commonest forms
    /// ([`Scanner::short_decimal`]); the rest is [`Scanner::more_digits`]
    /// and [`Scanner::any_number`].
    #[inline(always)]
    fn number(&mut self) -> Option<f64> {
        self.skip_ws();
        let start = self.i;
        let negative = self.b.get(self.i) == Some(&b'-');
        self.i += usize::from(negative);
        match self.short_decimal(negative) {
            Short::Value(x) => Some(x),
            Short::LongFraction(m) => self.more_digits(start, negative, m),
            Short::Other => self.any_number(start, negative),
        }
    }

    /// The digits of a number after its sign in the forms most streams
    /// write: at most seven integer digits (no leading zero) and, after a
    /// point, fraction digits, no exponent, with eight bytes to read after
    /// each part's start. Each part's first eight bytes are one
    /// [`leading_digits`], with no loop around it nor a call: reading and
    /// projecting 100,000 random triangles (`-0.0091`, `139.297`) took
    /// 564 M instructions against 619 M through [`Scanner::digits`]
    /// (callgrind, one thread). Seven fraction digits or fewer are read
    /// whole ([`Short::Value`]); eight or more (polyfill3's 17 significant
    /// digits) are handed on after the first eight. The cursor moves only
    /// past what it returns.
    #[inline(always)]
    fn short_decimal(&mut self, negative: bool) -> Short {
        let Some(rest) = self.b.get(self.i..) else {
            return Short::Other;
        };
        let Some(&int_bytes) = rest.first_chunk::<8>() else {
            return Short::Other;
        };
        let (int_len, int) = leading_digits(int_bytes);
        if !(1..8).contains(&int_len) || (int_len > 1 && rest[0] == b'0') {
            return Short::Other;
        }
        let (m, frac_len) = if rest.get(int_len) == Some(&b'.') {
            let Some(&frac_bytes) = rest.get(int_len + 1..).and_then(|r| r.first_chunk::<8>())
            else {
                return Short::Other;
            };
            let (frac_len, frac) = leading_digits(frac_bytes);
            let m = int * POW10_U64[frac_len] + frac;
            match frac_len {
                0 => return Short::Other,
                8 => {
                    self.i += int_len + 1 + 8;
                    return Short::LongFraction(m);
                }
                _ => (m, frac_len),
            }
        } else {
            (int, 0)
        };
        let end = if frac_len == 0 {
            int_len
        } else {
            int_len + 1 + frac_len
        };
        if let Some(b'e' | b'E') = rest.get(end) {
            return Short::Other;
        }
        self.i += end;
        // Below 2^53 with at most seven fraction digits: the quotient of
        // exact operands, finite, zero only for zero digits.
        let m = if negative { -(m as f64) } else { m as f64 };
        Short::Value(m / POW10[frac_len])
    }

    /// The rest of a number [`Scanner::short_decimal`] began: `m` holds
    /// its integer digits and the first eight of its fraction, the cursor
    /// is after them.
    #[inline(never)]
    fn more_digits(&mut self, start: usize, negative: bool, mut m: u64) -> Option<f64> {
        let frac_start = self.i - 8;
        let mut inexact = false;
        self.digits(&mut m, &mut inexact);
        let exp10 = -((self.i - frac_start) as i64);
        self.exponent_and_value(start, negative, m, inexact, exp10)
    }

    /// A number read from the start, the cursor after its sign.
    #[inline(never)]
    fn any_number(&mut self, start: usize, negative: bool) -> Option<f64> {
        let int_start = self.i;
        let mut m = 0u64;
        // Whether a digit was dropped from `m` to keep it in range.
        let mut inexact = false;
        self.digits(&mut m, &mut inexact);
        let int_len = self.i - int_start;
        if int_len == 0 || (int_len > 1 && self.b[int_start] == b'0') {
            return None;
        }
        let mut exp10 = 0i64;
        if self.b.get(self.i) == Some(&b'.') {
            self.i += 1;
            let frac_start = self.i;
            self.digits(&mut m, &mut inexact);
            if self.i == frac_start {
                return None;
            }
            exp10 = -((self.i - frac_start) as i64);
        }
        self.exponent_and_value(start, negative, m, inexact, exp10)
    }

    /// A number's exponent, if it has one, and its value: its digits'
    /// integer `m` (`inexact` if digits were dropped from it) times
    /// 10^`exp10`, its text starting at `start`.
    fn exponent_and_value(
        &mut self,
        start: usize,
        negative: bool,
        m: u64,
        inexact: bool,
        mut exp10: i64,
    ) -> Option<f64> {
        if let Some(b'e' | b'E') = self.b.get(self.i) {
            self.i += 1;
            let sign = if self.b.get(self.i) == Some(&b'-') {
                -1
            } else {
                1
            };
            if let Some(b'-' | b'+') = self.b.get(self.i) {
                self.i += 1;
            }
            let exp_start = self.i;
            let mut e = 0i64;
            while let Some(&d @ b'0'..=b'9') = self.b.get(self.i) {
                e = (e * 10 + i64::from(d - b'0')).min(1 << 40);
                self.i += 1;
            }
            if self.i == exp_start {
                return None;
            }
            exp10 += sign * e;
        }
        let magnitude = if !inexact && m < 1 << 53 && (-22..=22).contains(&exp10) {
            let m = m as f64;
            if exp10 >= 0 {
                m * POW10[exp10 as usize]
            } else {
                m / POW10[(-exp10) as usize]
            }
        } else if let Some(x) = u32::try_from(-exp10)
            .ok()
            .filter(|_| !inexact)
            .and_then(|k| divide_by_pow10(m, k))
        {
            x
        } else {
            // Cut between ASCII bytes, so on character boundaries.
            self.s.get(start..self.i)?.parse::<f64>().ok()?.abs()
        };
        if !magnitude.is_finite() || (magnitude == 0.0 && (m != 0 || inexact)) {
            return None;
        }
        Some(if negative { -magnitude } else { magnitude })
    }

    /// Consumes a run of decimal digits into `m`; past 10^18 `m` takes no
    /// more and `inexact` is set (the standard parser then reads the text).
    ///
    /// Up to eight digits are taken at once ([`leading_digits`]) while
    /// `m < 10^10`: the digit-by-digit loop would take them all too (`m`
    /// stays below 10^17 before each), so `m` and `inexact` come out the
    /// same. A digit at a time was half of reading a number (callgrind);
    /// polyfill3 writes 16 and 17 significant digits.
    #[inline]
    fn digits(&mut self, m: &mut u64, inexact: &mut bool) {
        while *m < 10_000_000_000 {
            let Some(&eight) = self.b.get(self.i..).and_then(|r| r.first_chunk::<8>()) else {
                break;
            };
            let (n, v) = leading_digits(eight);
            *m = *m * POW10_U64[n] + v;
            self.i += n;
            if n < 8 {
                return; // The next byte is not a digit.
            }
        }
        while let Some(&d @ b'0'..=b'9') = self.b.get(self.i) {
            if *m < 1_000_000_000_000_000_000 {
                *m = *m * 10 + u64::from(d - b'0');
            } else {
                *inexact = true;
            }
            self.i += 1;
        }
    }
}

/// `m / 10^k`, correctly rounded (to nearest, ties to even), by integer
/// division, for `m` from 2^53 (below it the caller's Clinger fast path
/// serves), `k` up to 19 (`10^k` below 2^64) and a quotient below 2^55;
/// `None` for anything else.
/// polyfill3 writes 17 significant digits, a third of its numbers above
/// 2^53; the standard parser read their text a second time.
///
/// With `s = 54 + bits(10^k) - bits(m)`, `q = floor(m * 2^s / 10^k)` has
/// 54 or 55 bits (`m / 10^k` lies within a factor 2 either side of
/// `2^(bits(m) - bits(10^k))`), and `m * 2^s` fits 128 bits. `q` is taken
/// down to 54 bits, the last of them the round bit, with everything below
/// it (the division's remainder, a bit shifted out) as the sticky bit.
fn divide_by_pow10(m: u64, k: u32) -> Option<f64> {
    if m < 1 << 53 || k > 19 {
        return None;
    }
    if k == 0 {
        return Some(m as f64); // `as` rounds to nearest, ties to even.
    }
    let d = 10u64.pow(k);
    // Negative when the quotient has more than 55 bits (19 digits over a
    // small power of ten): left to the standard parser.
    let s = u32::try_from(54 + m.leading_zeros() as i32 - d.leading_zeros() as i32).ok()?;
    let num = u128::from(m) << s;
    let mut q = num / u128::from(d);
    let mut sticky = num % u128::from(d) != 0;
    // x = q * 2^e, and then some below q's last bit.
    let mut e = -(s as i32);
    if q >= 1 << 54 {
        sticky |= q & 1 != 0;
        q >>= 1;
        e += 1;
    }
    let round = q & 1 != 0;
    let mut mantissa = (q >> 1) as u64; // 53 bits
    e += 1;
    if round && (sticky || mantissa & 1 != 0) {
        mantissa += 1; // At most 2^53: still exact.
    }
    // 2^e is a normal f64 (e from -63 to 2 here), so the product is exact.
    Some(mantissa as f64 * f64::from_bits(((1023 + e) as u64) << 52))
}

/// `10^n` for the digit counts of [`leading_digits`].
const POW10_U64: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// How many of eight bytes, from the first, are ASCII decimal digits, and
/// the value of those digits, by word arithmetic (SWAR): the bytes are read
/// as a little-endian word, so the first is its lowest byte.
#[inline(always)]
fn leading_digits(bytes: [u8; 8]) -> (usize, u64) {
    const LOW: u64 = 0x0101_0101_0101_0101;
    let w = u64::from_le_bytes(bytes);
    // A digit byte is 0x30..=0x39: its high nibble is 3, and adding 6 to it
    // leaves the high nibble 3 (0x39 + 6 = 0x3f; 0x3a + 6 = 0x40). Adding 6
    // to a byte of 0xfa or more carries into the next one, spoiling the
    // test of the bytes after it only: it is not a digit itself, and only
    // the bytes before the first that is not are used.
    let high = (w & (0xf0 * LOW)) ^ (0x30 * LOW);
    let carried = (w.wrapping_add(0x06 * LOW) & (0xf0 * LOW)) ^ (0x30 * LOW);
    // A non-zero byte here marks a byte that is not a digit.
    let n = ((high | carried).trailing_zeros() / 8) as usize;
    if n == 0 {
        return (0, 0);
    }
    // The n digits as the last of eight, behind leading '0's.
    let padded = if n == 8 {
        w
    } else {
        (w << (8 * (8 - n))) | ((0x30 * LOW) >> (8 * n))
    };
    let d = padded - 0x30 * LOW;
    // Pairs: byte 2k becomes 10 * digit 2k + digit 2k+1 (the junk in the
    // odd bytes is masked off below).
    let pairs = d.wrapping_mul(10).wrapping_add(d >> 8);
    // Quads from pairs, and the two quads into eight digits, in 32-bit
    // lanes: (p0 * 100 + p1) * 10^4 + p2 * 100 + p3.
    let lanes = 0x0000_00ff_0000_00ff;
    let lo = (pairs & lanes).wrapping_mul(100 + (1_000_000 << 32));
    let hi = ((pairs >> 16) & lanes).wrapping_mul(1 + (10_000 << 32));
    (n, lo.wrapping_add(hi) >> 32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// serde's route for the same line: `Plain` through serde_json.
    fn serde_route(line: &str) -> Option<(Vec<DVec3>, [u8; 3])> {
        let p: super::super::Plain = serde_json::from_str(line).ok()?;
        Some((p.vertices?, p.color?))
    }

    /// The scanner's vertices (after some already in the list) and colour;
    /// a declined line must leave the list as it was.
    fn scanned(line: &str) -> Option<(Vec<DVec3>, [u8; 3])> {
        let mut verts = vec![DVec3::splat(7.0)];
        let c = match vertices_and_color(line.as_bytes(), &mut verts) {
            Scanned::Plain(c) => Some(c),
            Scanned::Other | Scanned::TooMany => None,
        };
        assert_eq!(verts[0], DVec3::splat(7.0));
        if c.is_none() {
            assert_eq!(
                verts.len(),
                1,
                "a declined line leaves the list as it was: {line}"
            );
        }
        Some((verts.split_off(1), c?))
    }

    /// Bit for bit, signs of zero included (`DVec3`'s `==` calls -0 and 0
    /// equal).
    fn bits(v: &[DVec3]) -> Vec<[u64; 3]> {
        v.iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect()
    }

    fn agree(line: &str) -> Result<(), TestCaseError> {
        if let Some((v, c)) = scanned(line) {
            let (sv, sc) = serde_route(line).expect("serde's route accepts what the scanner does");
            prop_assert_eq!(bits(&v), bits(&sv), "{}", line);
            prop_assert_eq!(c, sc, "{}", line);
        }
        Ok(())
    }

    #[test]
    fn the_common_lines_are_scanned() {
        for line in [
            r#"{"vertices":[[139.297,649.243,-0.0091],[137.262,651.811,0.5774],[134.959,647.775,0.6715]],"color":[221,1,228]}"#,
            r#"{ "color" : [ 0 , 10 , 255 ] , "vertices" : [ [ 0 , 0 ] , [ 1 , 0 ] , [ 0 , 1 ] ] }"#,
            "{\"vertices\":[[0,0],[1e2,0],[0,1E-2]],\r\n\t\"color\":[1,2,3]}",
            r#"{"vertices":[[-0,-0.0,0.1],[12345678901234567890,1.7976931348623157e308,5e-324],[0.30000000000000004,-1,2]],"color":[0,0,0]}"#,
            // polyfill3's cells, and fields serde's route keeps as text.
            r#"{"vertices":[[99.71238155194987,0.40899343312727865,99.5],[100.0,0.0,100.0],[100.0,0.0,99.5]],"color":[180,144,86],"texel":[5,0],"face":1}"#,
            r#"{"id":1,"vertices":[[0,0],[1,0],[0,1]],"s":"a\"]}\\","color":[1,2,3],"x":[1e400,{"records":[]}],"n":null,"id2":true}"#,
            // Each side of `short_decimal`'s seven digits, and numbers with
            // fewer than eight bytes after them, which it leaves.
            r#"{"vertices":[[1234567.1234567,-9999999.9999999,12345678.5],[0.12345678,-1.123456789,7],[1234567,-0,5.0e1]],"color":[1,2,3]}"#,
            r#"{"color":[1,2,3],"vertices":[[1.5,2.25],[3.125,-4],[5,6.0625]]}"#,
        ] {
            assert!(scanned(line).is_some(), "{line}");
            agree(line).unwrap();
        }
    }

    #[test]
    fn anything_else_is_left_to_serde() {
        for line in [
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"texel":[1e400,0]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"records":[]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"transform":{"translate":[1,2,3]}}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":[1,]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":"\q"}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":tru}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":[}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x":}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"x\"":1}"#,
            r#"{"verti\u0063es":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            // A repeated key of the record's own (serde's route refuses it).
            r#"{"id":1,"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"id":2}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"k0":0,"k1":1,"k2":2,"k3":3,"k4":4,"k5":5,"k6":6,"k7":7,"k8":8,"k9":9,"k10":10,"k11":11,"k12":12,"k13":13,"k14":14,"k15":15,"k16":16}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3.0]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,03]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,256]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3,4]}"#,
            r#"{"vertices":[[00,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[.5,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[1.,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[+1,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[1e,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[1e400,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[1e-400,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0,0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0],[1,0],[0,1]],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1],],"color":[1,2,3]}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]} {}"#,
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],}"#,
            r#"{"vertices":[[NaN,0],[1,0],[0,1]],"color":[1,2,3]}"#,
        ] {
            assert!(scanned(line).is_none(), "{line}");
        }
    }

    proptest! {
        /// Integer division rounds as the standard parser does.
        #[test]
        fn division_by_a_power_of_ten_is_correctly_rounded(
            m in prop_oneof![(1u64 << 53)..100_000_000_000_000_000, (1u64 << 53)..=u64::MAX],
            k in 0u32..=19,
        ) {
            let text = format!("{m}e-{k}");
            let want = text.parse::<f64>().unwrap();
            match divide_by_pow10(m, k) {
                Some(x) => prop_assert_eq!(x.to_bits(), want.to_bits(), "{}", text),
                // Only a quotient of more than 54 bits is declined.
                None => prop_assert!(want >= (1u64 << 54) as f64, "{}", text),
            }
        }

        /// Eight bytes read at once give what a digit at a time gives.
        #[test]
        fn leading_digits_are_read_as_one_at_a_time(
            bytes in prop::array::uniform8(prop_oneof![
                3 => b'0'..=b'9',
                1 => any::<u8>(),
                1 => prop::sample::select(vec![b'.', b'e', b',', b']', b'/', b':', 0xfa, 0xff]),
            ]),
        ) {
            let n = bytes.iter().take_while(|b| b.is_ascii_digit()).count();
            let v = bytes[..n].iter().fold(0u64, |m, &d| m * 10 + u64::from(d - b'0'));
            prop_assert_eq!(leading_digits(bytes), (n, v), "{:?}", bytes);
        }
    }

    /// Halfway cases, which random numbers seldom meet: `m / 10^k` a
    /// 54-bit odd integer times a power of two, exactly between two f64s.
    #[test]
    fn division_by_a_power_of_ten_rounds_ties_to_even() {
        let mut checked = 0;
        for n in [
            (1u64 << 53) + 1,
            (1 << 53) + 3,
            (1 << 54) - 1,
            (1 << 53) + 12_345_677,
        ] {
            for k in 1..=4u32 {
                for j in 0..=8 {
                    let Some(m) = n
                        .checked_mul(5u64.pow(k))
                        .and_then(|m| m.checked_mul(1 << j))
                    else {
                        continue;
                    };
                    let text = format!("{m}e-{k}");
                    if let Some(x) = divide_by_pow10(m, k) {
                        assert_eq!(
                            x.to_bits(),
                            text.parse::<f64>().unwrap().to_bits(),
                            "{text}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 16, "{checked}");
    }

    /// Shrunk from `division_by_a_power_of_ten_is_correctly_rounded`: 2^58
    /// over 10 has 55 bits and a shift below zero; it is declined, and the
    /// scanner reads it through the standard parser, to the bit.
    #[test]
    fn a_quotient_of_more_than_54_bits_is_left_to_the_standard_parser() {
        assert_eq!(divide_by_pow10(1 << 58, 1), None);
        let line = r#"{"vertices":[[28823037615171174.4,0],[1,0],[0,1]],"color":[1,2,3]}"#;
        agree(line).unwrap();
        assert!(scanned(line).is_some());
    }

    #[test]
    fn integers_and_arrays_of_them_are_stepped_over_by_hand() {
        for (text, by_hand) in [
            ("[5,0]", true),
            (" [ -12 , 0 ] ", true),
            ("[]", true),
            ("123456789012345678", true),
            ("1234567890123456789", false),
            ("[1.5]", false),
            ("1e2", false),
            ("[01]", false),
            ("-", false),
            ("[1,]", false),
            ("[[1]]", false),
        ] {
            let mut s = Scanner::new(text);
            assert_eq!(s.integers().is_some(), by_hand, "{text}");
        }
    }

    /// A number as JSON writes it, or near misses.
    fn number_text() -> impl Strategy<Value = String> {
        prop_oneof![
            any::<i64>().prop_map(|i| i.to_string()),
            any::<u64>().prop_map(|i| i.to_string()),
            any::<f64>()
                .prop_filter("finite", |x| x.is_finite())
                .prop_map(|x| format!("{x:?}")),
            any::<f64>()
                .prop_filter("finite", |x| x.is_finite())
                .prop_map(|x| format!("{x:e}")),
            (-1e4f64..1e4).prop_map(|x| format!("{x:.3}")),
            // Digits and exponents around the fast path's edges.
            ("-?[0-9]{1,25}(\\.[0-9]{1,25})?([eE][-+]?[0-9]{1,3})?").prop_map(|s| s),
            // ... and around `short_decimal`'s seven digits either side.
            ("-?[0-9]{1,9}(\\.[0-9]{0,10})?([eE][0-9])?").prop_map(|s| s),
            Just("-0".to_string()),
            Just("1e400".to_string()),
        ]
    }

    /// Whether the number `t` is a finite `f64` that is zero only if its
    /// digits are (no underflow): those the scanner must accept.
    fn representable(t: &str) -> bool {
        let digits = t.split(['e', 'E']).next().unwrap_or_default();
        t.parse::<f64>().is_ok_and(|x| {
            x.is_finite() && (x != 0.0 || !digits.bytes().any(|b| matches!(b, b'1'..=b'9')))
        })
    }

    proptest! {
        /// Whatever the numbers and the spacing, the scanner declines or
        /// gives serde's numbers to the bit.
        #[test]
        fn the_scanner_agrees_with_serde_to_the_bit(
            points in prop::collection::vec(prop::collection::vec(number_text(), 2..4), 0..5),
            color in prop::collection::vec(0u32..300, 3),
            space in prop::sample::select(vec!["", " ", "\t", "\r\n"]),
            color_first in any::<bool>(),
            extra in prop::option::of((
                prop::sample::select(vec!["texel", "face", "id", "records", "transform", "uv", "x"]),
                prop_oneof![
                    number_text(),
                    prop::collection::vec(number_text(), 0..4).prop_map(|v| format!("[{}]", v.join(","))),
                    Just(r#""a\"]}\\""#.to_string()),
                    Just(r#"[1,[2,{"a":"]"}],null]"#.to_string()),
                    Just(r#"{"b":[1e400]}"#.to_string()),
                    Just("[1,]".to_string()),
                    Just(r#""\q""#.to_string()),
                    Just("tru".to_string()),
                ],
            )),
        ) {
            let sep = |items: Vec<String>| items.join(&format!("{space},{space}"));
            let verts = format!(
                "\"vertices\"{space}:{space}[{}]",
                sep(points.iter().map(|p| format!("[{space}{}{space}]", sep(p.clone()))).collect())
            );
            let col = format!("\"color\":[{}]", sep(color.iter().map(|c| c.to_string()).collect()));
            let mut parts = if color_first { vec![col, verts] } else { vec![verts, col] };
            if let Some((k, v)) = extra {
                parts.insert(1, format!("\"{k}\"{space}:{space}{v}"));
            }
            let line = format!("{{{space}{}{space}}}", sep(parts));
            agree(&line)?;
            // What the scanner declines, only serde's route may accept:
            // a line of valid numbers and colours must be accepted.
            let valid = serde_route(&line).is_some();
            if valid && points.iter().flatten().all(|t| representable(t)) {
                prop_assert!(scanned(&line).is_some(), "{}", line);
            }
        }
    }
}
