//! Netpbm samples against their header's maxval, checked before the `image`
//! crate decodes them: it scales each sample by `255 / maxval` (or `65535 /
//! maxval`) and saturates, so a sample over maxval (`P5 1 1 100` with a byte
//! of 200) read as white instead of being refused, where netpbm's own
//! programs refuse it (a hostile-input review). Formats with a maxval are
//! checked: plain and raw grey and colour (P2, P3, P5, P6) and PAM (P7);
//! bitmaps (P1, P4) have none.

/// The first sample over its maxval, and where it is.
#[derive(Debug, PartialEq, Eq)]
pub(super) struct OverMaxval {
    /// As written (a plain sample past `u32` was said as 4294967295).
    pub(super) value: u64,
    pub(super) maxval: u32,
    /// Its pixel (0-based, row 0 at the top).
    pub(super) x: u64,
    pub(super) y: u64,
}

/// The picture's shape: where sample `i` lies.
#[derive(Clone, Copy)]
struct Shape {
    width: u64,
    /// Samples a pixel.
    depth: u64,
}

impl Shape {
    /// A header's numbers as the shape and count of its samples and its
    /// maxval; `None` for a maxval outside 1..=65535 (the decoder refuses
    /// it) or more samples than a `u64` counts.
    fn of(width: u64, height: u64, depth: u64, maxval: u64) -> Option<(Shape, u64, u32)> {
        let maxval = u32::try_from(maxval)
            .ok()
            .filter(|&m| (1..=65535).contains(&m))?;
        let samples = width.checked_mul(height)?.checked_mul(depth)?;
        let shape = Shape {
            width: width.max(1),
            depth: depth.max(1),
        };
        Some((shape, samples, maxval))
    }

    fn over(self, value: u64, maxval: u32, i: u64) -> OverMaxval {
        let pixel = i / self.depth;
        OverMaxval {
            value,
            maxval,
            x: pixel % self.width,
            y: pixel / self.width,
        }
    }
}

/// The first sample of a netpbm picture over its header's maxval, if there
/// is one; `None` too for anything this does not read as a header with a
/// maxval (the decoder then refuses it or reads it as it does).
pub(super) fn first_over_maxval(bytes: &[u8]) -> Option<OverMaxval> {
    let magic = bytes.get(..2)?;
    let (fields, raw) = match magic {
        b"P2" | b"P5" => (1u64, magic == b"P5"),
        b"P3" | b"P6" => (3, magic == b"P6"),
        b"P7" => return pam_over_maxval(bytes),
        _ => return None,
    };
    let mut at = 2;
    let mut header = [0u64; 3];
    for value in &mut header {
        *value = number(bytes, &mut at)?;
    }
    let [width, height, maxval] = header;
    let (shape, samples, maxval) = Shape::of(width, height, fields, maxval)?;
    if raw {
        // One whitespace character ends the header; a comment there is
        // read differently by netpbm and by the decoder, so such a file is
        // left to the decoder.
        if bytes.get(at) == Some(&b'#') {
            return None;
        }
        raw_over_maxval(bytes.get(at + 1..)?, samples, maxval, shape)
    } else {
        // Up to the first thing that is not a number: the decoder refuses
        // it, or the data has ended.
        for i in 0..samples {
            let v = number(bytes, &mut at)?;
            if v > u64::from(maxval) {
                return Some(shape.over(v, maxval, i));
            }
        }
        None
    }
}

/// The first of `samples` raw samples (one byte each below 256, two
/// big-endian above) over `maxval`.
fn raw_over_maxval(data: &[u8], samples: u64, maxval: u32, shape: Shape) -> Option<OverMaxval> {
    let wide = maxval > 255;
    if maxval == 255 || maxval == 65535 {
        return None; // Every sample fits.
    }
    let width = if wide { 2 } else { 1 };
    let len = usize::try_from(samples.checked_mul(width)?)
        .ok()?
        .min(data.len());
    data[..len]
        .chunks_exact(width as usize)
        .enumerate()
        .find_map(|(i, s)| {
            let v = if wide {
                u32::from(u16::from_be_bytes([s[0], s[1]]))
            } else {
                u32::from(s[0])
            };
            (v > maxval).then(|| shape.over(u64::from(v), maxval, i as u64))
        })
}

/// A PAM's header (`WIDTH`, `HEIGHT`, `DEPTH`, `MAXVAL` lines up to the
/// line `ENDHDR`, `#` lines being comments), then its raw samples.
fn pam_over_maxval(bytes: &[u8]) -> Option<OverMaxval> {
    let (mut width, mut height, mut depth, mut maxval) = (None, None, None, None);
    let mut at = 0;
    loop {
        let len = memchr::memchr(b'\n', bytes.get(at..)?)?;
        let line = std::str::from_utf8(&bytes[at..at + len]).ok()?;
        at += len + 1;
        if line.starts_with('#') {
            continue;
        }
        let mut words = line.split_ascii_whitespace();
        let key = words.next();
        let value = words.next().and_then(|w| w.parse::<u64>().ok());
        match key {
            Some("WIDTH") => width = value,
            Some("HEIGHT") => height = value,
            Some("DEPTH") => depth = value,
            Some("MAXVAL") => maxval = value,
            Some("ENDHDR") => break,
            _ => {}
        }
    }
    let (shape, samples, maxval) = Shape::of(width?, height?, depth?, maxval?)?;
    raw_over_maxval(&bytes[at..], samples, maxval, shape)
}

/// The next decimal number from `at`, past whitespace (the decoder's: space,
/// tab, CR, LF, VT, FF) and `#` comments (to the end of their line), as a
/// netpbm header and a plain raster write them.
fn number(bytes: &[u8], at: &mut usize) -> Option<u64> {
    loop {
        match bytes.get(*at)? {
            b'#' => {
                while bytes.get(*at).is_some_and(|&c| c != b'\n' && c != b'\r') {
                    *at += 1;
                }
            }
            b' ' | b'\t' | b'\r' | b'\n' | b'\x0b' | b'\x0c' => *at += 1,
            _ => break,
        }
    }
    let start = *at;
    let mut v: u64 = 0;
    while let Some(&c) = bytes.get(*at).filter(|c| c.is_ascii_digit()) {
        v = v.checked_mul(10)?.checked_add(u64::from(c - b'0'))?;
        *at += 1;
    }
    (*at > start).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::{first_over_maxval, OverMaxval};

    #[test]
    fn samples_over_maxval_are_found_in_every_format_with_one() {
        let at = |value, maxval, x, y| {
            Some(OverMaxval {
                value,
                maxval,
                x,
                y,
            })
        };
        // Raw grey, maxval 100: the second sample, 200, is over it.
        assert_eq!(
            first_over_maxval(b"P5 2 1 100\n\x32\xc8"),
            at(200, 100, 1, 0)
        );
        assert_eq!(first_over_maxval(b"P5 2 1 100\n\x32\x64"), None);
        // Raw colour with a comment in the header; 16-bit samples; the
        // second row.
        assert_eq!(
            first_over_maxval(
                b"P6\n# made by hand\n1 2\n1000\n\0\x01\0\x02\0\x03\0\x04\x03\xe9\0\0"
            ),
            at(1001, 1000, 0, 1)
        );
        // Plain grey and colour.
        assert_eq!(first_over_maxval(b"P2\n2 1\n15\n3 16\n"), at(16, 15, 1, 0));
        assert_eq!(first_over_maxval(b"P3 1 1 255 255 0 7\n"), None);
        assert_eq!(first_over_maxval(b"P3 1 1 7 0 8 7\n"), at(8, 7, 0, 0));
        // A plain sample past u32 is said as written, not as 4294967295.
        assert_eq!(
            first_over_maxval(b"P2 2 2 255 1 2 3 4294967296\n"),
            at(4294967296, 255, 1, 1)
        );
        // PAM.
        let pam =
            b"P7\nWIDTH 1\nHEIGHT 1\nDEPTH 2\nMAXVAL 3\nTUPLTYPE GRAYSCALE_ALPHA\nENDHDR\n\x03\x04";
        assert_eq!(first_over_maxval(pam), at(4, 3, 0, 0));
        // Full-range samples cannot be over; bitmaps have no maxval.
        assert_eq!(first_over_maxval(b"P5 1 1 255\n\xff"), None);
        assert_eq!(first_over_maxval(b"P4 8 1\n\xff"), None);
        // Found by a review: a plain header promising 4e9 x 4e9 samples over
        // no data is not scanned for them (it hung); a vertical tab
        // separates samples as it does for the decoder.
        assert_eq!(first_over_maxval(b"P2 4000000000 4000000000 100\n"), None);
        assert_eq!(first_over_maxval(b"P2 2 1 15\n1\x0b99\n"), at(99, 15, 1, 0));
        // A PAM comment naming ENDHDR is a comment; a comment right after
        // a raw header's maxval is left to the decoder.
        let pam = b"P7\nWIDTH 2\nHEIGHT 1\nDEPTH 1\nMAXVAL 15\n# ENDHDR\nTUPLTYPE GRAYSCALE\nENDHDR\n\x03\x0c";
        assert_eq!(first_over_maxval(pam), None);
        assert_eq!(first_over_maxval(b"P5 2 1 15#c\n \x03\x04"), None);
        // Not a header: left to the decoder.
        assert_eq!(first_over_maxval(b"P5 x"), None);
        assert_eq!(first_over_maxval(b"\x89PNG"), None);
    }
}
