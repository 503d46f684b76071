//! The small tables of a texture code (seed 001, "Translation Maps", "Color
//! Code", and the texture record's "Modulation Color Select").
//!
//! * A **translation map** is "an intensity transform function. The input and
//!   output ranges are from 0 to 255. The null translator map is a ramp with a
//!   slope of one" (Fig. 5: brightness shifts the ramp, contrast tilts it). It
//!   takes a modulation value to the intensity that modulates the face.
//!   Brightness `b`: `T(i) = i + b`; contrast `c`: `T(i) = 127.5 + c (i − 127.5)`;
//!   both rounded to nearest and clamped to 0..=255. A file holds exactly 256
//!   entries: `TRANSLATE` then 256 decimal values 0..=255 (`#` comments).
//! * The **colour-code table** gives each code 0..=255 a red/green/blue mixture
//!   (the seed has twelve such tables of 256 codes; one is enough here). The
//!   default table, so that codes mean something without a file: codes 0..=215
//!   are the 6x6x6 cube `r g b` in steps of 51 (code = 36 r' + 6 g' + b',
//!   `r = 51 r'`, the "web-safe" cube), codes 216..=255 a grey ramp
//!   `round(255 (code − 215) / 41)`. A table file is `COLOURS` followed by
//!   entries `code r g b` that replace those codes of the default table.
//! * The **modulation colour select** is the seed's "three-bit field that
//!   indicates ... which of the three color components to modulate": here a
//!   string of the letters `r`, `g`, `b` (`"rgb"`, `"g"`, `"rb"`, ...).

use crate::color::Rgb8;
use crate::pat::ParseError;
use crate::text::Words;
use std::fmt;

/// Entries of a translation map and of a colour-code table.
pub const TABLE_LEN: usize = 256;
/// The header of a translation map file.
pub const TRANSLATE_MAGIC: &str = "TRANSLATE";
/// The header of a colour-code table file.
pub const COLOURS_MAGIC: &str = "COLOURS";
/// The contrast pivot: the middle of 0..=255.
const PIVOT: f64 = 127.5;

/// A 256-entry intensity transfer table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Translation(pub [u8; TABLE_LEN]);

fn ramp(f: impl Fn(f64) -> f64) -> Translation {
    let mut t = [0u8; TABLE_LEN];
    for (i, v) in t.iter_mut().enumerate() {
        *v = f(i as f64).round().clamp(0.0, 255.0) as u8;
    }
    Translation(t)
}

/// A bad table value (not a file error).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableError(pub String);

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for TableError {}

impl Translation {
    /// The null translator: a ramp with a slope of one.
    pub fn identity() -> Translation {
        ramp(|i| i)
    }

    /// Shift every intensity by `b` (−255..=255).
    pub fn brightness(b: f64) -> Result<Translation, TableError> {
        if !b.is_finite() || !(-255.0..=255.0).contains(&b) {
            return Err(TableError(format!(
                "brightness: {b} is out of range: expected -255 to 255"
            )));
        }
        Ok(ramp(|i| i + b))
    }

    /// Scale intensities about the middle by `c` (0..=255; 1 is the identity).
    pub fn contrast(c: f64) -> Result<Translation, TableError> {
        if !c.is_finite() || !(0.0..=255.0).contains(&c) {
            return Err(TableError(format!(
                "contrast: {c} is out of range: expected 0 to 255 (1 leaves the map unchanged)"
            )));
        }
        Ok(ramp(|i| PIVOT + c * (i - PIVOT)))
    }

    /// Parses a translation map file: `TRANSLATE` and exactly 256 values.
    pub fn parse(bytes: &[u8], name: &str) -> Result<Translation, ParseError> {
        let mut w = Words::new(
            bytes,
            name,
            "a translation map: `TRANSLATE` and 256 values 0..=255",
        );
        let magic = w.expect("`TRANSLATE`")?;
        if magic.text != TRANSLATE_MAGIC {
            return Err(w.error_at(
                &magic,
                "expected `TRANSLATE`, the header of a translation map".into(),
            ));
        }
        let mut t = [0u8; TABLE_LEN];
        for (i, v) in t.iter_mut().enumerate() {
            *v = w.decimal(&format!("entry {} of {TABLE_LEN}, 0..=255", i + 1), 255)? as u8;
        }
        w.end("its 256 entries: a translation map has exactly 256")?;
        Ok(Translation(t))
    }

    /// The canonical text: header, then 16 entries per line.
    pub fn to_canonical(&self) -> String {
        let mut s = format!("{TRANSLATE_MAGIC}\n");
        for chunk in self.0.chunks(16) {
            let line: Vec<String> = chunk.iter().map(u8::to_string).collect();
            s.push_str(&line.join(" "));
            s.push('\n');
        }
        s
    }

    #[cfg(test)]
    pub(crate) fn is_identity(&self) -> bool {
        *self == Translation::identity()
    }
}

/// Code → RGB mixture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColourTable(pub [Rgb8; TABLE_LEN]);

impl Default for ColourTable {
    /// The documented default table (module docs).
    fn default() -> Self {
        let mut t = [Rgb8::BLACK; TABLE_LEN];
        for (code, c) in t.iter_mut().enumerate() {
            *c = if code < 216 {
                let step = |v: usize| (v * 51) as u8;
                Rgb8([step(code / 36), step(code / 6 % 6), step(code % 6)])
            } else {
                let g = (255.0 * (code - 215) as f64 / 41.0).round() as u8;
                Rgb8([g, g, g])
            };
        }
        ColourTable(t)
    }
}

impl ColourTable {
    /// The sRGB colour of colour code `code`.
    pub fn get(&self, code: u8) -> Rgb8 {
        self.0[code as usize]
    }

    /// Parses a table file: `COLOURS`, then entries `code r g b` replacing the
    /// default table's. A code given twice is an error.
    pub fn parse(bytes: &[u8], name: &str) -> Result<ColourTable, ParseError> {
        let mut w = Words::new(
            bytes,
            name,
            "a colour-code table: `COLOURS` and entries `code r g b`",
        );
        let magic = w.expect("`COLOURS`")?;
        if magic.text != COLOURS_MAGIC {
            return Err(w.error_at(
                &magic,
                "expected `COLOURS`, the header of a colour-code table".into(),
            ));
        }
        let mut table = ColourTable::default();
        let mut seen = [false; TABLE_LEN];
        while let Some(code_word) = w.next()? {
            let code = w.decimal_of(&code_word, "a colour code 0..=255", 255)? as usize;
            if seen[code] {
                return Err(w.error_at(&code_word, format!("colour code {code} is given twice")));
            }
            seen[code] = true;
            let mut rgb = [0u8; 3];
            for (c, chan) in rgb.iter_mut().zip(["red", "green", "blue"]) {
                *c = w.decimal(&format!("the {chan} of colour code {code}, 0..=255"), 255)? as u8;
            }
            table.0[code] = Rgb8(rgb);
        }
        Ok(table)
    }
}

/// Which of R, G, B the texture modulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Select(pub [bool; 3]);

impl Default for Select {
    fn default() -> Self {
        Select([true; 3])
    }
}

impl Select {
    /// `"rgb"`, `"r"`, `"gb"`, ...: each letter at most once, at least one.
    pub fn parse(s: &str) -> Result<Select, TableError> {
        let mut sel = [false; 3];
        if s.is_empty() {
            return Err(TableError(
                "select: empty: expected some of the letters r, g, b, e.g. \"rgb\" or \"g\"".into(),
            ));
        }
        for ch in s.chars() {
            let i = match ch.to_ascii_lowercase() {
                'r' => 0,
                'g' => 1,
                'b' => 2,
                _ => {
                    return Err(TableError(format!(
                    "select: `{s}`: `{ch}` is not a colour: expected some of the letters r, g, b"
                )))
                }
            };
            if sel[i] {
                return Err(TableError(format!("select: `{s}` names `{ch}` twice")));
            }
            sel[i] = true;
        }
        Ok(Select(sel))
    }

    /// The canonical spelling, letters in r, g, b order.
    pub fn name(self) -> String {
        "rgb"
            .chars()
            .zip(self.0)
            .filter_map(|(c, on)| on.then_some(c))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramps_follow_figure_5() {
        let id = Translation::identity();
        assert!(id.is_identity());
        assert_eq!(id.0[200], 200);
        let b = Translation::brightness(40.0).unwrap();
        assert_eq!((b.0[0], b.0[100], b.0[250]), (40, 140, 255));
        let d = Translation::brightness(-40.0).unwrap();
        assert_eq!((d.0[0], d.0[100]), (0, 60));
        let c = Translation::contrast(2.0).unwrap();
        assert_eq!(
            (c.0[0], c.0[100], c.0[127], c.0[128], c.0[255]),
            (0, 73, 127, 129, 255)
        );
        let flat = Translation::contrast(0.0).unwrap();
        assert!(flat.0.iter().all(|&v| v == 128));
        assert!(Translation::brightness(300.0)
            .unwrap_err()
            .to_string()
            .contains("brightness: 300 is out of range"));
        assert!(Translation::contrast(-1.0)
            .unwrap_err()
            .to_string()
            .contains("contrast: -1 is out of range"));
    }

    #[test]
    fn translation_files_have_exactly_256_entries() {
        let t = Translation::contrast(1.5).unwrap();
        let text = t.to_canonical();
        assert_eq!(Translation::parse(text.as_bytes(), "t.tm").unwrap(), t);
        let short: String = format!("TRANSLATE\n{}\n", vec!["7"; 255].join(" "));
        assert_eq!(
            Translation::parse(short.as_bytes(), "t.tm")
                .unwrap_err()
                .to_string(),
            "t.tm:2: unexpected end of file: expected entry 256 of 256, 0..=255"
        );
        let long: String = format!("TRANSLATE\n{}\n", vec!["7"; 257].join(" "));
        assert_eq!(
            Translation::parse(long.as_bytes(), "t.tm").unwrap_err().to_string(),
            "t.tm:2: word 258 `7`: trailing data: the file ends after its 256 entries: a translation map has exactly 256"
        );
        assert!(Translation::parse(b"STRIPE 2 1 2", "t.tm")
            .unwrap_err()
            .to_string()
            .contains("expected `TRANSLATE`"));
    }

    #[test]
    fn default_colour_table_is_the_cube_and_greys() {
        let t = ColourTable::default();
        assert_eq!(t.get(0), Rgb8::BLACK);
        assert_eq!(t.get(215), Rgb8::WHITE);
        assert_eq!(t.get(36 * 5), Rgb8([255, 0, 0]));
        assert_eq!(t.get(6 * 3 + 1), Rgb8([0, 153, 51]));
        assert_eq!(t.get(216), Rgb8([6, 6, 6]));
        assert_eq!(t.get(255), Rgb8([249, 249, 249]));
    }

    #[test]
    fn colour_table_files_replace_codes() {
        let t = ColourTable::parse(b"COLOURS\n# runway\n7 10 20 30\n255 1 2 3\n", "c.ct").unwrap();
        assert_eq!(t.get(7), Rgb8([10, 20, 30]));
        assert_eq!(t.get(255), Rgb8([1, 2, 3]));
        assert_eq!(t.get(0), Rgb8::BLACK);
        let e = |s: &str| {
            ColourTable::parse(s.as_bytes(), "c.ct")
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            e("COLOURS\n256 0 0 0\n"),
            "c.ct:2: word 2 `256`: out of range: expected a colour code 0..=255"
        );
        assert_eq!(
            e("COLOURS\n1 0 0 0\n1 2 2 2\n"),
            "c.ct:3: word 6 `1`: colour code 1 is given twice"
        );
        assert_eq!(
            e("COLOURS\n1 0 0\n"),
            "c.ct:2: unexpected end of file: expected the blue of colour code 1, 0..=255"
        );
    }

    #[test]
    fn select_reads_letters() {
        assert_eq!(Select::parse("rgb").unwrap(), Select([true; 3]));
        assert_eq!(Select::parse("B").unwrap(), Select([false, false, true]));
        assert_eq!(Select::parse("gr").unwrap().name(), "rg");
        assert!(Select::parse("").unwrap_err().to_string().contains("empty"));
        assert!(Select::parse("rx")
            .unwrap_err()
            .to_string()
            .contains("`x` is not a colour"));
        assert!(Select::parse("rr")
            .unwrap_err()
            .to_string()
            .contains("names `r` twice"));
    }
}
