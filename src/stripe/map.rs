//! The modulation map (seed 001, "Modulation Maps", Fig. 3 and 4): a 1-D table
//! of intensities 0 (darkest) ..= 255 (brightest), and its level-of-detail
//! pyramid.
//!
//! # File format
//!
//! ```text
//! STRIPE N [linear|none]      # header: length, then the fade rule (default linear)
//! v0 v1 v2 ... v(N-1)         # N decimal values 0..=255, any layout
//! ```
//!
//! `#` starts a comment to the end of the line. `N` is a power of two from 1 to
//! [`MAX_LEN`] (the seed's maps have 1024 entries). The canonical form, which
//! [`ModulationMap::write_canonical`] emits and which reads back byte for byte,
//! is the header on line 1 (the fade word only when it is `none`), then 16
//! values per line separated by single spaces, and a final newline.
//!
//! # Levels of detail
//!
//! "Modulation maps consist of a set of tables, one for each LOD ... The number
//! of entries at each LOD is one-half of the adjacent LOD ... until the final
//! LOD is reached whereby there is only one entry." Level `k` therefore has
//! `N / 2^k` entries, `L = log2 N` is the last level, and entry `i` of level `k`
//! covers level-0 samples `i 2^k .. (i+1) 2^k`: it is their box average, taken
//! in linear light (docs/rendering.md), as the average of two entries of level `k - 1`.
//!
//! "Similarly, the amplitude range of the waveform decreases with LOD. The
//! purpose is to reduce the noticeable contrast as range increases." The seed
//! gives no numbers, only its two ends: level 0 is the map as modelled (full
//! contrast) and level `L` is one entry, which can only be the mean (no
//! contrast). The rule used here, `linear`, decreases the amplitude linearly in
//! LOD between those two ends: level `k` is
//!
//! `mean + (1 - k/L) (box_k - mean)`,
//!
//! i.e. each level keeps `(L - k) / (L - k + 1)` of the contrast the previous
//! level had after box averaging (for `N = 1024`: 9/10, 8/9, ..., 1/2, 0). The
//! fade `none` keeps the plain box averages, which is what the box-filtered
//! reference (docs/rendering.md) implies; the fade is a deliberate departure from it, so
//! benchmarks report both.

use crate::color::{linear_to_srgb_f64, srgb8_to_linear_f64};
use crate::pat::ParseError;
use crate::text::{without_bom, Words};
use std::fmt;
use std::io::{self, Write};
use std::path::Path;

/// The seed's map length.
pub const DEFAULT_LEN: usize = 1024;
/// The longest map accepted: 2^16 entries, 64 times the seed's, is far beyond
/// any stripe a modeller draws and keeps a pyramid under 1 MiB of f32.
pub const MAX_LEN: usize = 1 << 16;
/// Values per line in the canonical form.
const PER_LINE: usize = 16;
/// The header keyword that tells a map file from a `.pat` (which starts with a number).
pub const MAGIC: &str = "STRIPE";

/// How the contrast of the coarser levels decreases (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Fade {
    /// Amplitude `1 - k/L` at level `k`: the seed's "amplitude range ...
    /// decreases with LOD".
    #[default]
    Linear,
    /// Plain box averages.
    None,
}

impl Fade {
    /// The fade's word in a map file's header (`linear` or `none`).
    pub fn word(self) -> &'static str {
        match self {
            Fade::Linear => "linear",
            Fade::None => "none",
        }
    }

    /// The amplitude kept at level `k` of `levels` (relative to the box average).
    pub fn amplitude(self, k: usize, levels: usize) -> f64 {
        let last = levels.saturating_sub(1);
        match self {
            Fade::None => 1.0,
            Fade::Linear if last == 0 => 1.0,
            Fade::Linear => 1.0 - k as f64 / last as f64,
        }
    }
}

/// Why a map could not be built from parts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidMap(pub String);

impl fmt::Display for InvalidMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for InvalidMap {}

/// Checks a map length: a power of two from 1 to [`MAX_LEN`].
pub fn check_len(n: u64) -> Result<usize, InvalidMap> {
    if n == 0 || n > MAX_LEN as u64 || !n.is_power_of_two() {
        Err(InvalidMap(format!(
            "map length {n} is not a power of two from 1 to {MAX_LEN}"
        )))
    } else {
        Ok(n as usize)
    }
}

/// A validated modulation map: a power-of-two number of 8-bit intensities.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModulationMap {
    values: Vec<u8>,
    fade: Fade,
}

impl ModulationMap {
    /// A map of `values` (sRGB-coded intensities, 0 darkest) and its fade;
    /// refused unless the length is a power of two from 1 to [`MAX_LEN`].
    pub fn new(values: Vec<u8>, fade: Fade) -> Result<Self, InvalidMap> {
        check_len(values.len() as u64)?;
        Ok(ModulationMap { values, fade })
    }

    /// The level-0 entries as modelled, sRGB-coded 0..=255, in map order.
    pub fn values(&self) -> &[u8] {
        &self.values
    }

    /// Number of level-0 entries, `N` (a power of two).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Never true: a map has at least one entry. (For clippy's `len` rule.)
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// How the contrast of the coarser levels decreases.
    pub fn fade(&self) -> Fade {
        self.fade
    }

    /// Number of levels, `log2 N + 1`.
    pub fn levels(&self) -> usize {
        self.values.len().trailing_zeros() as usize + 1
    }

    /// Whether bytes look like a map file: their first word (after blank
    /// lines and `#` comments) is [`MAGIC`], in any case, after a
    /// byte-order mark if there is one. Such a map that is not a valid one
    /// is then refused in the map's words (`expected `STRIPE``, the mark
    /// named), where the `.pat` reader's words were (a hostile-input
    /// review).
    pub fn sniff(bytes: &[u8]) -> bool {
        let mut w = Words::new(without_bom(bytes), "", "");
        matches!(w.next(), Ok(Some(word)) if word.text.eq_ignore_ascii_case(MAGIC))
    }

    /// Whether a file whose first bytes are `start` may be a map, for a
    /// caller that reads anything else as a stream (a `.pat`): its first
    /// byte that is not whitespace starts a comment or [`MAGIC`], or
    /// `start` is all whitespace (a map may have any number of blank
    /// lines and comments before [`MAGIC`]).
    pub fn may_start(start: &[u8]) -> bool {
        let start = without_bom(start);
        match start.iter().position(|b| !b.is_ascii_whitespace()) {
            None => true,
            Some(i) => {
                let word = &start[i..];
                word[0] == b'#'
                    || word[0] == MAGIC.as_bytes()[0]
                    || word
                        .get(..MAGIC.len())
                        .is_some_and(|w| w.eq_ignore_ascii_case(MAGIC.as_bytes()))
            }
        }
    }

    /// Reads a map file; errors name the file, line and word.
    pub fn read_file(path: &Path) -> Result<ModulationMap, ParseError> {
        let name = path.display().to_string();
        let bytes = crate::io::read_path(path).map_err(|e| ParseError {
            file: name.clone(),
            line: None,
            word: None,
            message: e.to_string(),
        })?;
        ModulationMap::parse(&bytes, &name)
    }

    /// Parses the text format (module docs); `name` is used in errors.
    pub fn parse(bytes: &[u8], name: &str) -> Result<ModulationMap, ParseError> {
        let mut w = Words::new(
            bytes,
            name,
            "a modulation map: `STRIPE N` and N values 0..=255",
        );
        let magic = w.expect("`STRIPE`")?;
        if magic.text != MAGIC {
            return Err(w.error_at(
                &magic,
                "expected `STRIPE`, the header of a modulation map".into(),
            ));
        }
        let len_word = w.expect("the map length")?;
        let what = format!("the map length, a power of two from 1 to {MAX_LEN}");
        let n = w.decimal_of(&len_word, &what, u64::MAX)?;
        let n = check_len(n).map_err(|e| w.error_at(&len_word, e.to_string()))?;
        let mut values = Vec::with_capacity(n);
        let mut fade = Fade::Linear;
        let first = w.expect(&format!("{n} values 0..=255"))?;
        let first_value = match first.text {
            "linear" => None,
            "none" => {
                fade = Fade::None;
                None
            }
            _ if first.text.bytes().all(|c| c.is_ascii_digit()) => {
                Some(w.decimal_of(&first, "a value 0..=255", 255)? as u8)
            }
            _ => {
                return Err(w.error_at(
                    &first,
                    "expected the fade rule `linear` or `none`, or the first value 0..=255".into(),
                ))
            }
        };
        values.extend(first_value);
        while values.len() < n {
            let what = format!("value {} of {n}, 0..=255", values.len() + 1);
            values.push(w.decimal(&what, 255)? as u8);
        }
        w.end(&format!("its {n} values"))?;
        Ok(ModulationMap { values, fade })
    }

    /// The canonical text as a string.
    pub fn to_canonical(&self) -> String {
        let mut out = Vec::new();
        self.write_canonical(&mut out)
            .expect("writing to a Vec cannot fail");
        String::from_utf8(out).expect("ASCII")
    }

    /// Writes the canonical form (module docs).
    pub fn write_canonical<W: Write>(&self, w: &mut W) -> io::Result<()> {
        write!(w, "{MAGIC} {}", self.values.len())?;
        if self.fade != Fade::Linear {
            write!(w, " {}", self.fade.word())?;
        }
        writeln!(w)?;
        for chunk in self.values.chunks(PER_LINE) {
            let line: Vec<String> = chunk.iter().map(u8::to_string).collect();
            writeln!(w, "{}", line.join(" "))?;
        }
        Ok(())
    }

    /// The level-0 samples in linear light.
    pub fn linear(&self) -> Vec<f64> {
        self.values
            .iter()
            .map(|&v| srgb8_to_linear_f64(v))
            .collect()
    }

    /// The pyramid of this map's own intensities (identity translation), in
    /// linear light.
    pub fn pyramid(&self) -> Vec<Vec<f64>> {
        pyramid(&self.linear(), self.fade)
    }

    /// Per level: entries, and min/max/mean as sRGB codes (fractional, 0..=255).
    pub fn level_stats(&self) -> Vec<LevelStats> {
        self.pyramid()
            .iter()
            .enumerate()
            .map(|(k, level)| {
                let enc = |l: f64| 255.0 * linear_to_srgb_f64(l.clamp(0.0, 1.0));
                let min = level.iter().copied().fold(f64::INFINITY, f64::min);
                let max = level.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let mean = level.iter().sum::<f64>() / level.len() as f64;
                LevelStats {
                    level: k,
                    entries: level.len(),
                    min: enc(min),
                    max: enc(max),
                    mean: enc(mean),
                }
            })
            .collect()
    }
}

/// One level's summary, in 8-bit sRGB units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelStats {
    /// The level `k` (0 is the map as modelled).
    pub level: usize,
    /// Its number of entries, `N / 2^k`.
    pub entries: usize,
    /// Darkest entry, encoded back to sRGB (unrounded, 0..=255).
    pub min: f64,
    /// Brightest entry, encoded back to sRGB (unrounded, 0..=255).
    pub max: f64,
    /// Mean taken in linear light, then encoded to sRGB (unrounded, 0..=255).
    pub mean: f64,
}

/// Builds the LOD pyramid of linear-light samples (length a power of two):
/// box averages of pairs, then the fade toward the mean (module docs).
pub fn pyramid(level0: &[f64], fade: Fade) -> Vec<Vec<f64>> {
    debug_assert!(level0.len().is_power_of_two());
    let levels = level0.len().trailing_zeros() as usize + 1;
    let mean = level0.iter().sum::<f64>() / level0.len() as f64;
    let mut boxes = vec![level0.to_vec()];
    while boxes.last().expect("non-empty").len() > 1 {
        let prev = boxes.last().expect("non-empty");
        let next: Vec<f64> = prev.chunks(2).map(|p| 0.5 * (p[0] + p[1])).collect();
        boxes.push(next);
    }
    boxes
        .into_iter()
        .enumerate()
        .map(|(k, level)| {
            let amp = fade.amplitude(k, levels);
            level.into_iter().map(|v| mean + amp * (v - mean)).collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn err(text: &str) -> String {
        ModulationMap::parse(text.as_bytes(), "m.map")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn canonical_text_round_trips_byte_for_byte() {
        let values: Vec<u8> = (0..32).map(|i| (i * 8) as u8).collect();
        let m = ModulationMap::new(values.clone(), Fade::Linear).unwrap();
        let text = m.to_canonical();
        assert!(text.starts_with("STRIPE 32\n0 8 16 "), "{text}");
        assert_eq!(text.lines().count(), 3);
        let back = ModulationMap::parse(text.as_bytes(), "m").unwrap();
        assert_eq!(back, m);
        assert_eq!(back.to_canonical(), text);
        let none = ModulationMap::new(values, Fade::None).unwrap();
        assert!(none.to_canonical().starts_with("STRIPE 32 none\n"));
        assert_eq!(
            ModulationMap::parse(none.to_canonical().as_bytes(), "m").unwrap(),
            none
        );
    }

    #[test]
    fn any_layout_and_comments_are_read() {
        let m =
            ModulationMap::parse(b"# furrows\nSTRIPE 4 linear\n1 2\n3 # three\n 4\n", "m").unwrap();
        assert_eq!(m.values(), &[1, 2, 3, 4]);
        assert_eq!(m.levels(), 3);
    }

    #[test]
    fn bad_maps_are_rejected_naming_file_line_and_word() {
        assert_eq!(
            err("STRIPE 1000\n"),
            "m.map:1: word 2 `1000`: map length 1000 is not a power of two from 1 to 65536"
        );
        assert!(err("STRIPE 131072\n").contains("not a power of two from 1 to 65536"));
        assert!(err("STRIPE 0\n").contains("map length 0"));
        assert_eq!(
            err("STRIPE 2\n1 256\n"),
            "m.map:2: word 4 `256`: out of range: expected value 2 of 2, 0..=255"
        );
        assert_eq!(
            err("STRIPE 4\n1 2 3\n"),
            "m.map:2: unexpected end of file: expected value 4 of 4, 0..=255"
        );
        assert_eq!(
            err("STRIPE 2\n1 2 3\n"),
            "m.map:2: word 5 `3`: trailing data: the file ends after its 2 values"
        );
        assert!(err("").contains("empty file"));
        assert!(err("16 1\n").contains("expected `STRIPE`"));
        assert!(err("STRIPE 2 wobbly 1 2").contains("fade rule"));
        assert!(err("STRIPE 2\n1 -2\n").contains("expected value 2 of 2"));
        assert!(err("STRIPE 2\n1\x002\n").contains("byte 0x00 is not text"));
    }

    #[test]
    fn sniff_tells_maps_from_patterns() {
        assert!(ModulationMap::sniff(b"\n STRIPE 4\n1 2 3 4"));
        assert!(ModulationMap::sniff(
            b"# made by a script\nSTRIPE 4\n1 2 3 4"
        ));
        assert!(!ModulationMap::sniff(b"16 1\n"));
        assert!(!ModulationMap::sniff(b"STRIPED"));
        assert!(!ModulationMap::sniff(b""));
        // A mark or a lowercase header is a map, refused in its words.
        for bytes in [&b"\xef\xbb\xbfSTRIPE 1\n1\n"[..], b"stripe 1\n1\n"] {
            assert!(ModulationMap::sniff(bytes) && ModulationMap::may_start(bytes));
        }
        let e = ModulationMap::parse(b"\xef\xbb\xbfSTRIPE 1\n1\n", "b.map")
            .unwrap_err()
            .to_string();
        assert!(e.contains("byte-order mark"), "{e}");
        let e = ModulationMap::parse(b"stripe 1\n1\n", "l.map")
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected `STRIPE`"), "{e}");
        assert!(!ModulationMap::may_start(b"sss"));
    }

    #[test]
    fn pyramid_halves_down_to_one_entry_and_fades_linearly() {
        let m = ModulationMap::new(vec![0, 255, 0, 255, 255, 255, 0, 0], Fade::None).unwrap();
        let p = m.pyramid();
        assert_eq!(p.iter().map(Vec::len).collect::<Vec<_>>(), [8, 4, 2, 1]);
        // Box averages in linear light: a 0/255 pair is exactly 0.5.
        assert_eq!(p[1], [0.5, 0.5, 1.0, 0.0]);
        assert_eq!(p[3], [0.5]);
        let lin = ModulationMap::new(m.values().to_vec(), Fade::Linear).unwrap();
        let q = lin.pyramid();
        // L = 3: amplitudes 1, 2/3, 1/3, 0 around the mean 0.5.
        assert_eq!(q[0], p[0]);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert!(close(q[1][2], 0.5 + 2.0 / 3.0 * 0.5));
        assert!(close(q[2][1], 0.5 + 1.0 / 3.0 * (0.5 - 0.5)));
        assert!(close(q[3][0], 0.5));
    }

    #[test]
    fn level_stats_report_srgb_units() {
        let m = ModulationMap::new(vec![0, 255], Fade::None).unwrap();
        let s = m.level_stats();
        assert_eq!(s.len(), 2);
        assert!(
            s[0].min == 0.0 && (s[0].max - 255.0).abs() < 1e-9,
            "{:?}",
            s[0]
        );
        // Half of linear light is sRGB code 187.5 or so, not 127.5.
        assert!((s[1].mean - 187.5).abs() < 0.5, "{}", s[1].mean);
    }

    proptest! {
        #[test]
        fn every_level_has_the_same_mean_and_narrower_range(
            values in proptest::collection::vec(any::<u8>(), 64),
            linear in any::<bool>(),
        ) {
            let fade = if linear { Fade::Linear } else { Fade::None };
            let m = ModulationMap::new(values, fade).unwrap();
            let p = m.pyramid();
            let mean0 = p[0].iter().sum::<f64>() / 64.0;
            for (k, level) in p.iter().enumerate() {
                prop_assert_eq!(level.len(), 64 >> k);
                let mean = level.iter().sum::<f64>() / level.len() as f64;
                prop_assert!((mean - mean0).abs() < 1e-12);
                if k > 0 {
                    let span = |l: &Vec<f64>| l.iter().copied().fold(f64::MIN, f64::max)
                        - l.iter().copied().fold(f64::MAX, f64::min);
                    prop_assert!(span(level) <= span(&p[k - 1]) + 1e-12);
                }
            }
            let text = m.to_canonical();
            prop_assert_eq!(ModulationMap::parse(text.as_bytes(), "p").unwrap(), m);
        }
    }
}
