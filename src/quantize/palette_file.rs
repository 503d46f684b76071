//! Forced palettes (`--palette`): the palette of a `.pat` file, or a text list
//! of colours. A list's `#` is both the comment sign and the `#rrggbb` prefix;
//! a hex digit after it decides, so a mistyped colour is an error rather than
//! a silently ignored comment.

use super::MAX_QUANT_COLORS;
use crate::color::ColorParseError;
use crate::color::Rgb8;
use crate::pat::Pattern;
use crate::text::{ParseError, BOM, BOM_NAMED};

/// Why a forced palette file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum PaletteError {
    /// A line of a colour list is not a colour.
    #[error("{file}:{line}")]
    Line {
        /// The file's name.
        file: String,
        /// The line, from 1.
        line: usize,
        /// What is wrong with it.
        #[source]
        error: LineError,
    },
    /// The file looks like a pattern and is not a valid one.
    #[error(transparent)]
    Pattern(#[from] ParseError),
    /// The file is text that is neither a `.pat` nor a colour list, and
    /// says why it looks like neither (a colour list with spaces, a GIMP
    /// palette, a byte-order mark, a byte that is not UTF-8).
    #[error("{file}:{line}: not a palette: {why}")]
    Unlike {
        /// The file's name.
        file: String,
        /// The line, from 1.
        line: usize,
        /// What it looks like, and what to write instead.
        why: String,
    },
    /// The file holds no colour.
    #[error("{0}: the palette has no colours")]
    Empty(String),
    /// The file holds more colours than a quantized pattern may have.
    #[error("{file}: the palette has {colours} colours, at most {MAX_QUANT_COLORS} are allowed")]
    TooMany {
        /// The file's name.
        file: String,
        /// How many it holds.
        colours: usize,
    },
}

/// What is wrong with one line of a colour list.
#[derive(Debug, thiserror::Error)]
pub enum LineError {
    /// Text after a `#rrggbb` colour that is not a comment.
    #[error("unexpected `{0}` after the colour")]
    Trailing(String),
    /// Not a colour.
    #[error(transparent)]
    Colour(#[from] ColorParseError),
}

/// A forced palette: the palette of a `.pat` file, or a text list with one
/// colour per line as `r,g,b` or `#rrggbb`, blank lines and `#` comments allowed.
/// A file whose first meaningful line holds a comma or starts with `#` is a list.
pub fn parse_palette_file(bytes: &[u8], name: &str) -> Result<Vec<Rgb8>, PaletteError> {
    let unlike = |line: usize, why: String| PaletteError::Unlike {
        file: name.to_string(),
        line,
        why,
    };
    let text = match std::str::from_utf8(bytes) {
        Ok(text) => text,
        // A .pat with a stray byte is the .pat reader's to name.
        Err(_) if palette_is_pattern(bytes) => {
            return checked(Pattern::parse(bytes, name)?.palette().to_vec(), name)
        }
        Err(e) => {
            let at = e.valid_up_to();
            let line = 1 + crate::text::line_ends(&bytes[..at], false);
            return Err(unlike(
                line,
                format!(
                    "byte 0x{:02x} is not UTF-8 text (a palette is text)",
                    bytes[at]
                ),
            ));
        }
    };
    if text.starts_with(BOM) {
        return Err(unlike(
            1,
            format!("it starts with {BOM_NAMED}: save it without one"),
        ));
    }
    let first = crate::text::lines(text)
        .map(str::trim)
        .find(|l| !l.is_empty());
    let Some(first) = first else {
        // Nothing but blanks: no colours, as a list of comments has none
        // (it said `.pat`'s "empty file: expected `SIZE NCOLORS`...").
        return Err(PaletteError::Empty(name.to_string()));
    };
    let is_list = first.contains(',') || first.starts_with('#');
    let palette = if is_list {
        let mut out = Vec::new();
        for (i, line) in crate::text::lines(text).enumerate() {
            let colour = parse_list_line(line).map_err(|error| PaletteError::Line {
                file: name.to_string(),
                line: i + 1,
                error,
            })?;
            if let Some(c) = colour {
                out.push(c);
            }
        }
        out
    } else {
        let pattern = Pattern::parse(bytes, name);
        // Colours written `R G B`, or a GIMP palette: say what to write.
        let (line, first) = crate::text::lines(text)
            .enumerate()
            .find(|(_, l)| !l.trim().is_empty())
            .unwrap_or((0, ""));
        let words: Vec<&str> = first.split_whitespace().collect();
        let rgb = words.len() >= 3 && words[..3].iter().all(|w| w.parse::<u8>().is_ok());
        if pattern.is_err() && (rgb || first.starts_with("GIMP Palette")) {
            return Err(unlike(
                line + 1,
                "neither a .pat file nor a list of colours: write one colour a line as \
                 `r,g,b` (with commas) or `#rrggbb`"
                    .into(),
            ));
        }
        pattern?.palette().to_vec()
    };
    checked(palette, name)
}

/// Whether a palette file that starts with `start` is a `.pat` to read as a
/// stream ([`Pattern::read_from`]: a pattern may be larger than a file read
/// whole may be): it starts as a pattern, and its first line, whole within
/// `start`, holds no comma (`16,0,0` starts a list).
pub fn palette_is_pattern(start: &[u8]) -> bool {
    let from = start.iter().position(|b| !b.is_ascii_whitespace());
    let first_line = from.and_then(|i| {
        let line = &start[i..];
        line.iter()
            .position(|&b| b == b'\n')
            .map(|end| &line[..end])
    });
    crate::pat::starts_as_pattern(start) && first_line.is_some_and(|l| !l.contains(&b','))
}

/// The palette of a pattern read as a stream, checked as
/// [`parse_palette_file`] checks one.
pub fn pattern_palette(pattern: &Pattern, name: &str) -> Result<Vec<Rgb8>, PaletteError> {
    checked(pattern.palette().to_vec(), name)
}

/// `palette`, unless it is empty or too long for a quantized pattern.
fn checked(palette: Vec<Rgb8>, name: &str) -> Result<Vec<Rgb8>, PaletteError> {
    if palette.is_empty() {
        return Err(PaletteError::Empty(name.to_string()));
    }
    if palette.len() > MAX_QUANT_COLORS {
        return Err(PaletteError::TooMany {
            file: name.to_string(),
            colours: palette.len(),
        });
    }
    Ok(palette)
}

/// One line of a colour list: a colour, or `None` for a blank or comment line.
/// A `#` followed by a hex digit begins a colour (`#rrggbb`, so a mistyped `#fff`
/// is an error, not a comment); any other `#` begins a comment.
fn parse_list_line(line: &str) -> Result<Option<Rgb8>, LineError> {
    let t = line.trim();
    let colour = if t.starts_with('#') && t[1..].starts_with(|c: char| c.is_ascii_hexdigit()) {
        let (colour, rest) = t.split_once(char::is_whitespace).unwrap_or((t, ""));
        let rest = rest.trim();
        if !rest.is_empty() && !rest.starts_with('#') {
            return Err(LineError::Trailing(rest.to_string()));
        }
        colour
    } else {
        t.split('#').next().unwrap_or("").trim()
    };
    if colour.is_empty() {
        return Ok(None);
    }
    Ok(Some(colour.parse::<Rgb8>()?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::chain;

    #[test]
    fn only_a_file_starting_as_a_pattern_is_read_as_one_streamed() {
        for (start, pattern) in [
            (&b"16 1\n1 2 3\n"[..], true),
            (b"\n\n  32 0\r\n", true),
            (b"255,0,0\n0,0,255\n", false),
            (b"16, 0, 0\n", false),
            (b"# a list\n1,2,3\n", false),
            (b"#ff0000\n", false),
            // A first line not yet whole: read whole, decided as before.
            (b"16 1", false),
            (b"", false),
        ] {
            assert_eq!(palette_is_pattern(start), pattern, "{start:?}");
        }
    }

    #[test]
    fn palette_files_parse_as_lists_or_patterns() {
        let list =
            b"# my palette\n\n#ff0000  # red\n 0, 255 ,0\n#00f # not a colour: a comment? no\n";
        let e = chain(&parse_palette_file(list, "p.txt").unwrap_err());
        assert!(e.contains("p.txt:5"), "{e}");
        let list = b"# my palette\n\n#ff0000  # red\n 0, 255 ,0 # green\n#0000FF\n";
        assert_eq!(
            parse_palette_file(list, "p.txt").unwrap(),
            vec![Rgb8([255, 0, 0]), Rgb8([0, 255, 0]), Rgb8([0, 0, 255])]
        );
        let pat = Pattern::new(16, vec![Rgb8([1, 2, 3]), Rgb8([4, 5, 6])], vec![0; 256]).unwrap();
        assert_eq!(
            parse_palette_file(pat.to_canonical().as_bytes(), "p.pat").unwrap(),
            pat.palette()
        );
        for bad in [&b""[..], b"# nothing\n", b"16 1\n", b"\xff\xfe", b"1,2\n"] {
            let e = chain(&parse_palette_file(bad, "bad.pal").unwrap_err());
            assert!(e.contains("bad.pal"), "{e}");
        }
        // Nothing but blanks has no colours, as comments alone have none
        // (it said the .pat reader's "empty file: expected `SIZE NCOLORS`").
        for blank in [&b""[..], b" \n\t\n", b"# nothing\n"] {
            let e = chain(&parse_palette_file(blank, "b.pal").unwrap_err());
            assert_eq!(e, "b.pal: the palette has no colours", "{blank:?}");
        }
        let e = chain(&parse_palette_file(b"#ff0000 junk\n", "j").unwrap_err());
        assert!(e.contains("j:1") && e.contains("junk"), "{e}");
        // Lines ended by a bare CR (classic Mac OS): a comment ends at one,
        // and a line number counts them. It read "no colours" (a
        // hostile-input review).
        let cr = b"# my colours\r255,0,0\r\n0,255,0\r";
        assert_eq!(
            parse_palette_file(cr, "cr").unwrap(),
            vec![Rgb8([255, 0, 0]), Rgb8([0, 255, 0])]
        );
        let e = chain(&parse_palette_file(b"1,2,3\r\r1,2\r", "cr").unwrap_err());
        assert!(e.contains("cr:3"), "{e}");
    }

    #[test]
    fn text_that_is_neither_says_what_it_looks_like() {
        // They got the .pat reader's words ("pattern size 255 is not a
        // multiple of 16"), or no place at all (a hostile-input review).
        let err = |bytes: &[u8]| chain(&parse_palette_file(bytes, "p.txt").unwrap_err());
        for (bytes, want) in [
            (&b"255 0 0\n0 255 0\n"[..], "p.txt:1: not a palette: neither a .pat file nor a list of colours: write one colour a line as `r,g,b` (with commas) or `#rrggbb`"),
            (b"GIMP Palette\n255 0 0 red\n", "p.txt:1: not a palette: neither a .pat file"),
            (b"\xef\xbb\xbf255,0,0\n", "p.txt:1: not a palette: it starts with a UTF-8 byte-order mark"),
            (b"255,0,0\n0,0,255 # caf\xe9\n", "p.txt:2: not a palette: byte 0xe9 is not UTF-8 text"),
        ] {
            let e = err(bytes);
            assert!(e.contains(want), "{e}");
        }
        // A .pat keeps the .pat reader's words.
        assert!(err(b"16 1\n1 2 3\n\xff\n").contains("p.txt:3"));
    }
}
