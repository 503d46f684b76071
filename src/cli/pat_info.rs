//! `pat-info`: examine and validate `.pat` patterns and stripe modulation
//! maps (told apart by content: a map starts with `STRIPE`), and print a
//! polygon record's stripe texture in the seed's terms (seed 001's PVA/TRA
//! examine commands).

use super::{AlreadyReported, IntPair};
use crate::cli::usage_bail;
use crate::io::{display_name, read_input};
use crate::pat::{Pattern, Seam};
use crate::stream::{Item, Record};
use crate::stripe::map::ModulationMap;
use crate::stripe::record::{LoadedStripe, StripeSpec, TranslationSpec};
use crate::stripe::vector::Orientation;
use anyhow::{Context, Result};
use clap::Parser;
use serde_json::{json, Value};
use std::io::Write;

const EXAMPLES: &str = "\
Examples:
  pat-info fixtures/patterns/brick.pat
  pat-info --preview fixtures/patterns/*.pat
  pat-info --check *.pat && echo all valid
  pat-info --at 3,5 --json brick.pat | jq '.files[0].texel'
  pat-tile --pat --size 256x256 brick.pat | pat-info -
  pat-info fixtures/stripes/furrow.map
      A modulation map: its length and, per level of detail, min/max/mean.
  pat-info --record 0 field.json
      Record 0's stripe texture: spacing, start point, yaw, pitch, ...";

/// Examine multi-colour texture patterns (size, colours and their coverage,
/// transparency, whether the pattern tiles without a seam, single texels, a
/// true-colour terminal preview), stripe modulation maps (length, levels of
/// detail and their range), and a polygon record's stripe texture.
#[derive(Parser, Debug)]
#[command(name = "pat-info", version, after_help = EXAMPLES)]
pub struct Args {
    /// Pattern (.pat) or modulation map files, or with --record one polygon
    /// stream; `-` reads standard input.
    #[arg(default_value = "-")]
    pub files: Vec<String>,

    /// Print record N of the polygon stream FILE: its stripe texture in the
    /// seed's terms (spacing, start point, yaw, pitch, translation, colour
    /// select and colour code). Records are numbered from 0 in the order of
    /// the stream, every element counting (object definitions and instances
    /// too): the numbers error messages give. For an object definition
    /// (drawn untransformed) or an instance, every polygon it draws that has
    /// a stripe is shown, as `record N, polygon K` (K from 0 in drawing
    /// order), each an element of --json's "records".
    #[arg(long, value_name = "N", conflicts_with_all = ["check", "at", "preview"])]
    pub record: Option<usize>,

    /// Validate only: print nothing on success, one error per invalid file, and
    /// exit 1 if any file is invalid.
    #[arg(long)]
    pub check: bool,

    /// Print one JSON object instead of text: {"version": 1, "tool":
    /// "pat-info", "files": [...]} with an object per file, or with --record
    /// "records": [...] (docs/json.md).
    #[arg(long, conflicts_with = "check")]
    pub json: bool,

    /// Also show the texel at column COL, row ROW (row 0 is the bottom row).
    #[arg(long, value_name = "COL,ROW")]
    pub at: Option<IntPair>,

    /// Draw the pattern in the terminal with 24-bit colour, two texels per
    /// character cell; transparent texels show as a grey checker. Without
    /// colour (--color), one character per texel names its colour as the
    /// table numbers them (1-9, A-Z, a-z; `?` beyond 61, `.` transparent),
    /// with a legend.
    #[arg(long, conflicts_with_all = ["check", "json"])]
    pub preview: bool,

    /// When the preview uses colour: `auto` when standard output is a
    /// terminal and NO_COLOR is unset or empty (<https://no-color.org>),
    /// `always` (even into a pipe, whatever NO_COLOR says), or `never`.
    #[arg(long, value_name = "WHEN", default_value = "auto")]
    pub color: super::ColorWhen,

    /// Widest preview in texels; larger patterns are shown subsampled.
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub preview_size: u32,
}

/// Standard output whose failed writes say so: without it a full disk
/// said only "No space left on device". The error keeps its kind, so a
/// closed pipe still ends the run quietly (`super::report`).
struct Stdout(std::io::StdoutLock<'static>);

impl Stdout {
    fn lock() -> Stdout {
        Stdout(std::io::stdout().lock())
    }
}

/// A failed write of a report, named.
fn writing_stdout(e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("writing standard output: {e}"))
}

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.write(buf).map_err(writing_stdout)
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        self.0.write_all(buf).map_err(writing_stdout)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush().map_err(writing_stdout)
    }
}

/// Runs `pat-info`.
pub fn run(args: Args) -> Result<()> {
    let places: Vec<String> = (1..=args.files.len())
        .map(|k| format!("file {k}"))
        .collect();
    let named: Vec<(&str, Option<&str>)> = places
        .iter()
        .zip(&args.files)
        .map(|(place, f)| (place.as_str(), Some(f.as_str())))
        .collect();
    // A usage error first (status 2), then the standard output's.
    super::check_inputs(&named)?;
    // --check writes nothing there: `pat-info --check *.pat >&-` failed.
    if !args.check {
        super::check_stdout("redirect it to a file, or give --check to validate only")?;
    }
    if let Some(n) = args.record {
        if args.files.len() != 1 {
            usage_bail!("--record takes exactly one polygon stream file");
        }
        return record_report(&args.files[0], n, args.json);
    }
    let colour = args.color.stdout_wants_colour();
    let mut stdout = Stdout::lock();
    let mut failures = 0usize;
    let mut reports = Vec::new();
    for file in &args.files {
        let name = display_name(file);
        // What may be a modulation map is read whole, as a map or for its
        // error; anything else is a pattern, read as a stream (it may be
        // larger than a file read whole may be: `read_pattern`). Reading
        // whole what did not start as a pattern took 256 MiB before
        // refusing `yes | pat-info -`, and `yes ' ' | pat-info -` before
        // the whitespace was read past.
        let opened = crate::io::open_input(file, crate::io::InputKind::Text)
            .and_then(crate::io::Opened::past_blank_start);
        let result = match opened {
            Ok(opened) if ModulationMap::may_start(&opened.start) => match opened.read_input() {
                Ok(b) if ModulationMap::sniff(&b) => {
                    let map = ModulationMap::parse(&b, name).map_err(anyhow::Error::new);
                    match map.and_then(|m| map_report(&m, name, &args, colour)) {
                        Err(e) => {
                            super::print_error("pat-info", &e);
                            failures += 1;
                        }
                        Ok(Report::Json(j)) => reports.push(j),
                        Ok(Report::Text(t)) => write!(stdout, "{t}")?,
                    }
                    continue;
                }
                bytes => bytes
                    .map_err(anyhow::Error::new)
                    .and_then(|b| Pattern::parse(&b, name).map_err(anyhow::Error::new)),
            },
            opened => opened
                .map_err(anyhow::Error::new)
                .and_then(|o| super::read_pattern(o, name)),
        }
        // Which file the texel is outside of: with several files of
        // several sizes the message alone did not say.
        .and_then(|p| {
            texel(&p, args.at)
                .with_context(|| name.to_string())
                .map(|t| (p, t))
        });
        let (pattern, at) = match result {
            Ok(ok) => ok,
            Err(e) => {
                super::print_error("pat-info", &e);
                failures += 1;
                continue;
            }
        };
        if args.check {
            continue;
        }
        if args.json {
            reports.push(json_report(name, &pattern, at));
        } else {
            write!(stdout, "{}", text_report(name, &pattern, at))?;
            if args.preview && colour {
                write_preview(&pattern, args.preview_size, &mut stdout)?;
            } else if args.preview {
                write!(stdout, "{}", plain_preview(&pattern, args.preview_size))?;
            }
        }
    }
    if args.json {
        serde_json::to_writer_pretty(
            &mut stdout,
            &super::json_document("pat-info", "files", reports),
        )?;
        writeln!(stdout)?;
    }
    stdout.flush()?;
    if failures > 0 {
        return Err(AlreadyReported.into());
    }
    Ok(())
}

/// The texel asked for with `--at`, checked against the pattern's size.
fn texel(p: &Pattern, at: Option<IntPair>) -> Result<Option<(u32, u32, Option<u16>)>> {
    let Some(IntPair(c, r)) = at else {
        return Ok(None);
    };
    let s = p.size() as i64;
    if !(0..s).contains(&c) || !(0..s).contains(&r) {
        anyhow::bail!(
            "texel ({c},{r}) is outside the {s}x{s} pattern: columns and rows run 0..{}",
            s - 1
        );
    }
    Ok(Some((c as u32, r as u32, p.index_at(c as u32, r as u32))))
}

fn percent(n: u64, total: u64) -> f64 {
    100.0 * n as f64 / total as f64
}

fn seam_word(s: &Seam) -> &'static str {
    if s.seamless {
        "seamless"
    } else {
        "visible seam"
    }
}

fn text_report(name: &str, p: &Pattern, at: Option<(u32, u32, Option<u16>)>) -> String {
    use std::fmt::Write;
    let (counts, transparent) = p.histogram();
    let total = (p.size() as u64).pow(2);
    let (h, v) = p.seams();
    let mut s = String::new();
    let n = p.palette().len();
    let _ = writeln!(
        s,
        "{name}: {size}x{size}, {n} colour{plural}, {t:.2}% transparent",
        size = p.size(),
        plural = if n == 1 { "" } else { "s" },
        t = percent(transparent, total)
    );
    let _ = writeln!(s, "  colour  rgb          hex       texels  coverage");
    for (i, (c, count)) in p.palette().iter().zip(&counts).enumerate() {
        let _ = writeln!(
            s,
            "  {:>6}  {:<11}  {}  {:>7}  {:>7.2}%",
            i + 1,
            c.to_string(),
            c.hex(),
            count,
            percent(*count, total)
        );
    }
    let _ = writeln!(
        s,
        "  transparent                  {:>7}  {:>7.2}%",
        transparent,
        percent(transparent, total)
    );
    let _ = writeln!(
        s,
        "  tiling: left/right {} (seam {:.3}, strongest edge inside {:.3}, mean {:.3}); bottom/top {} (seam {:.3}, strongest edge inside {:.3}, mean {:.3})",
        seam_word(&h),
        h.seam,
        h.strongest,
        h.interior,
        seam_word(&v),
        v.seam,
        v.strongest,
        v.interior
    );
    if let Some((c, r, idx)) = at {
        match idx {
            Some(i) => {
                let col = p.palette()[i as usize];
                let _ = writeln!(
                    s,
                    "  texel ({c},{r}): colour {} {} {}",
                    i + 1,
                    col,
                    col.hex()
                );
            }
            None => {
                let _ = writeln!(s, "  texel ({c},{r}): transparent");
            }
        }
    }
    s
}

fn seam_json(s: &Seam) -> Value {
    json!({"seamless": s.seamless, "seam": s.seam, "interior": s.interior, "strongest": s.strongest})
}

fn json_report(name: &str, p: &Pattern, at: Option<(u32, u32, Option<u16>)>) -> Value {
    let (counts, transparent) = p.histogram();
    let total = (p.size() as u64).pow(2);
    let (h, v) = p.seams();
    let colors: Vec<Value> = p
        .palette()
        .iter()
        .zip(&counts)
        .enumerate()
        .map(|(i, (c, &n))| {
            json!({"index": i + 1, "rgb": c.0, "hex": c.hex(), "texels": n, "coverage": n as f64 / total as f64})
        })
        .collect();
    let mut obj = json!({
        "file": name,
        "kind": "pattern",
        "size": p.size(),
        "colors": colors,
        "transparent": {"texels": transparent, "share": transparent as f64 / total as f64},
        "tiling": {"left_right": seam_json(&h), "bottom_top": seam_json(&v)},
    });
    if let Some((c, r, idx)) = at {
        obj["texel"] = match idx {
            Some(i) => {
                let col = p.palette()[i as usize];
                json!({"column": c, "row": r, "index": i + 1, "rgb": col.0, "hex": col.hex()})
            }
            None => json!({"column": c, "row": r, "transparent": true}),
        };
    }
    obj
}

/// What pat-info says of one file: a JSON value for the list `--json`
/// prints at the end, or text to print now (empty with `--check`).
enum Report {
    Json(Value),
    Text(String),
}

/// The report of modulation map `m`, as `args` ask (`--at` names a texel
/// of a pattern, so it is an error here).
fn map_report(m: &ModulationMap, name: &str, args: &Args, colour: bool) -> Result<Report> {
    if args.at.is_some() {
        anyhow::bail!("{name}: --at names a texel of a pattern, but this is a modulation map");
    }
    Ok(if args.check {
        Report::Text(String::new())
    } else if args.json {
        Report::Json(map_json(name, m))
    } else if args.preview {
        Report::Text(map_text(name, m) + &map_preview(m, args.preview_size, colour))
    } else {
        Report::Text(map_text(name, m))
    })
}

fn map_text(name: &str, m: &ModulationMap) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{name}: modulation map, {} entries, {} levels, fade {}",
        m.len(),
        m.levels(),
        m.fade().word()
    );
    let _ = writeln!(s, "  level  entries     min     max    mean");
    for l in m.level_stats() {
        let _ = writeln!(
            s,
            "  {:>5}  {:>7}  {:>6.2}  {:>6.2}  {:>6.2}",
            l.level, l.entries, l.min, l.max, l.mean
        );
    }
    s
}

fn map_json(name: &str, m: &ModulationMap) -> Value {
    let levels: Vec<Value> = m
        .level_stats()
        .iter()
        .map(|l| {
            json!({"level": l.level, "entries": l.entries, "min": round4(l.min), "max": round4(l.max), "mean": round4(l.mean)})
        })
        .collect();
    json!({
        "file": name,
        "kind": "modulation map",
        "length": m.len(),
        "fade": m.fade().word(),
        "levels": levels,
    })
}

/// Four decimals: the level statistics are sRGB codes, and f64 noise past
/// that (61.00000000000001) only distracts.
fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// Characters from dark to light for a modulation map without colour.
const GREY_RAMP: &[u8] = b" .:-=+*#%@";

/// One line of grey cells per level, finest first, at most `max` cells wide;
/// without colour, one character of [`GREY_RAMP`] per cell.
fn map_preview(m: &ModulationMap, max: u32, colour: bool) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for level in m.pyramid() {
        let step = level.len().div_ceil(max as usize).max(1);
        for v in level.iter().step_by(step) {
            let g = crate::color::linear_to_srgb(*v as f32);
            if colour {
                let _ = write!(s, "\x1b[48;2;{g};{g};{g}m ");
            } else {
                let k = g as usize * GREY_RAMP.len() / 256;
                s.push(GREY_RAMP[k] as char);
            }
        }
        s.push_str(if colour { "\x1b[0m\n" } else { "\n" });
    }
    s
}

/// `--record N`: the stripe texture of stream element N in the seed's terms:
/// a record's own, or for an object definition or an instance, that of every
/// polygon it draws that has one, as `record N, polygon K`.
fn record_report(file: &str, n: usize, as_json: bool) -> Result<()> {
    let name = display_name(file);
    let bytes = read_input(file, crate::io::InputKind::Stream)?;
    let (item, drawn) = match crate::stream::nth_item(bytes.as_slice(), name, n)? {
        Ok(found) => found,
        Err(count) => anyhow::bail!(
            "{name}: record {n} does not exist: the stream has {count} record{} (numbered from 0)",
            if count == 1 { "" } else { "s" }
        ),
    };
    let base = crate::stream::base_dir(file);
    let unknown = std::cell::RefCell::new(crate::scene::keys::UnknownKeys::default());
    let load = |record: &Record, label: &str| -> Result<Option<LoadedStripe>> {
        unknown
            .borrow_mut()
            .check(record.index, &record.fields, |w| super::warn("pat-info", w));
        let Some(spec) =
            StripeSpec::from_fields(&record.fields).map_err(|m| anyhow::anyhow!("{label}: {m}"))?
        else {
            return Ok(None);
        };
        let loaded = spec
            .load(&base)
            .map_err(|e| anyhow::Error::new(e).context(label.to_string()))?;
        Ok(Some(loaded))
    };
    let (what, key, object) = match &item {
        Item::Record(record) => {
            let label = format!("{name}: record {n}");
            let loaded = load(record, &label)?
                .ok_or_else(|| anyhow::anyhow!("{label} has no \"stripe\" texture"))?;
            let mut stdout = Stdout::lock();
            if as_json {
                let o = record_json(name, n, &loaded, record.color);
                let doc = super::json_document("pat-info", "records", vec![o]);
                serde_json::to_writer_pretty(&mut stdout, &doc)?;
                writeln!(stdout)?;
            } else {
                let title = format!("{label}: stripe texture");
                write!(stdout, "{}", record_text(&title, &loaded, record.color))?;
            }
            stdout.flush()?;
            return Ok(());
        }
        Item::Light(_) => {
            anyhow::bail!("{name}: record {n} is a light, which has no \"stripe\" texture")
        }
        Item::Object(def) => (format!("object `{}`", def.name), "object", &def.name),
        Item::Instance(inst) => (
            format!("instance of `{}`", inst.object),
            "instance_of",
            &inst.object,
        ),
    };
    // Every polygon is loaded before anything is printed, so that an error
    // leaves standard output empty.
    let mut shown = Vec::new();
    for (k, record) in drawn.iter().enumerate() {
        let label = format!("{name}: record {n}, polygon {k}");
        if let Some(loaded) = load(record, &label)? {
            shown.push((k, label, loaded, record.color));
        }
    }
    if shown.is_empty() {
        anyhow::bail!("{name}: record {n} ({what}) draws no polygon with a \"stripe\" texture");
    }
    let mut stdout = Stdout::lock();
    if as_json {
        let list: Vec<Value> = shown
            .iter()
            .map(|(k, _, loaded, colour)| {
                let Value::Object(o) = record_json(name, n, loaded, *colour) else {
                    unreachable!("record_json makes an object")
                };
                // "polygon" and the object after "record", the rest as for a record.
                let mut m = serde_json::Map::new();
                for (field, v) in o {
                    let after_record = field == "record";
                    m.insert(field, v);
                    if after_record {
                        m.insert("polygon".into(), json!(k));
                        m.insert(key.into(), json!(object));
                    }
                }
                Value::Object(m)
            })
            .collect();
        let doc = super::json_document("pat-info", "records", list);
        serde_json::to_writer_pretty(&mut stdout, &doc)?;
        writeln!(stdout)?;
    } else {
        for (_, label, loaded, colour) in &shown {
            let title = format!("{label}: stripe texture ({what})");
            write!(stdout, "{}", record_text(&title, loaded, *colour))?;
        }
    }
    stdout.flush()?;
    Ok(())
}

fn translation_words(t: &TranslationSpec) -> String {
    match t {
        TranslationSpec::Identity => "identity (the null translator, slope one)".into(),
        TranslationSpec::Brightness(b) => format!("brightness {b}"),
        TranslationSpec::Contrast(c) => format!("contrast {c}"),
        TranslationSpec::File(f) => format!("file {f}"),
    }
}

/// The stripe texture `l` under the heading `title`, one line per term.
fn record_text(title: &str, l: &LoadedStripe, colour: Option<crate::color::Rgb8>) -> String {
    use std::fmt::Write;
    let v = &l.spec.vector;
    let len = l.map.len();
    let (yaw, pitch) = v.orientation.yaw_pitch();
    let np = v.orientation.normal();
    let mut s = String::new();
    let _ = writeln!(s, "{title}");
    let _ = writeln!(
        s,
        "  map           {} ({len} entries, {} levels, fade {})",
        l.spec.map,
        l.map.levels(),
        l.map.fade().word()
    );
    let _ = writeln!(
        s,
        "  spacing       {} (w, world units per sample; repeats every {}; K_p = 1/({len} w) = {})",
        v.spacing,
        v.period(len),
        v.k_p(len)
    );
    let _ = writeln!(
        s,
        "  start point   {} (sample; P0 = {})",
        v.phase,
        v.p0(len)
    );
    let _ = writeln!(
        s,
        "  yaw           {yaw} (degrees from East, positive North)"
    );
    let _ = writeln!(s, "  pitch         {pitch} (degrees above horizontal)");
    if let Orientation::Plane { plane, theta } = v.orientation {
        let _ = writeln!(
            s,
            "  plane         {} ({}), theta {theta}",
            plane.name(),
            plane.seed_name()
        );
    }
    let _ = writeln!(s, "  N_p           {} {} {}", np.x, np.y, np.z);
    let _ = writeln!(
        s,
        "  translation   {}",
        translation_words(&l.spec.translation)
    );
    let _ = writeln!(s, "  select        {}", l.spec.select.name());
    match l.spec.code {
        Some(c) => {
            let rgb = l.colours.get(c);
            let _ = writeln!(s, "  colour code   {c} ({rgb} {})", rgb.hex());
        }
        None => {
            let _ = match colour {
                Some(rgb) => writeln!(
                    s,
                    "  colour        {rgb} {} (the record's \"color\")",
                    rgb.hex()
                ),
                None => writeln!(s, "  colour        none (no code, no \"color\")"),
            };
        }
    }
    if let Some(b) = l.blend() {
        let _ = writeln!(
            s,
            "  blend         to {} {} ({}), select {} ({})",
            b.next,
            b.next.hex(),
            match l.spec.blend.map(|b| b.next) {
                Some(crate::stripe::record::NextColour::Code(c)) => format!("next colour code {c}"),
                _ => "\"next_color\"".to_string(),
            },
            b.select.number(),
            b.select.words()
        );
    }
    s
}

fn record_json(
    name: &str,
    n: usize,
    l: &LoadedStripe,
    colour: Option<crate::color::Rgb8>,
) -> Value {
    let v = &l.spec.vector;
    let len = l.map.len();
    let (yaw, pitch) = v.orientation.yaw_pitch();
    let np = v.orientation.normal();
    let mut o = json!({
        "file": name,
        "record": n,
        "map": l.spec.map,
        "length": len,
        "levels": l.map.levels(),
        "fade": l.map.fade().word(),
        "spacing": v.spacing,
        "start_point": v.phase,
        "k_p": v.k_p(len),
        "p0": v.p0(len),
        "yaw": yaw,
        "pitch": pitch,
        "n_p": [np.x, np.y, np.z],
        "translation": translation_words(&l.spec.translation),
        "select": l.spec.select.name(),
    });
    if let Orientation::Plane { plane, theta } = v.orientation {
        o["plane"] = json!(plane.name());
        o["theta"] = json!(theta);
    }
    let face = match l.spec.code {
        Some(c) => {
            o["code"] = json!(c);
            Some(l.colours.get(c))
        }
        None => colour,
    };
    if let Some(rgb) = face {
        o["color"] = json!({"rgb": rgb.0, "hex": rgb.hex()});
    }
    if let Some(b) = l.blend() {
        o["blend"] = json!({
            "next": {"rgb": b.next.0, "hex": b.next.hex()},
            "select": b.select.number(),
        });
    }
    o
}

/// Light and dark greys of the checker that stands for transparency.
const CHECKER: [[u8; 3]; 2] = [[153, 153, 153], [102, 102, 102]];

/// Half-block preview: each character cell shows two texels, the upper one in
/// the foreground (`▀`) and the lower in the background. Top of the output is
/// the top row of the pattern (row SIZE-1).
#[cfg(test)]
fn preview(p: &Pattern, max: u32) -> String {
    let mut out = Vec::new();
    write_preview(p, max, &mut out).expect("writing to a Vec cannot fail");
    String::from_utf8(out).expect("the preview is UTF-8")
}

/// [`preview`] written to `out` a line at a time: a 4096x4096 pattern's
/// preview at `--preview-size 4096` is 243 MB of escapes, which were held
/// whole before the first byte was written (274 MB peak, for a pattern
/// read in 37 MB).
fn write_preview(p: &Pattern, max: u32, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    use std::fmt::Write;
    let size = p.size();
    let step = size.div_ceil(max).max(1);
    let cells = size.div_ceil(step);
    let rgb = |c: u32, r: u32| -> [u8; 3] {
        match p.color_at(c, r) {
            Some(col) => col.0,
            None => CHECKER[((c / step + r / step) % 2) as usize],
        }
    };
    let mut s = String::new();
    let mut y = cells as i64 - 1;
    while y >= 0 {
        s.clear();
        for x in 0..cells {
            let top = rgb(x * step, y as u32 * step);
            let bottom = if y >= 1 {
                rgb(x * step, (y as u32 - 1) * step)
            } else {
                [0, 0, 0]
            };
            if y >= 1 {
                let _ = write!(
                    s,
                    "\x1b[38;2;{};{};{}m\x1b[48;2;{};{};{}m▀",
                    top[0], top[1], top[2], bottom[0], bottom[1], bottom[2]
                );
            } else {
                let _ = write!(s, "\x1b[38;2;{};{};{}m\x1b[49m▀", top[0], top[1], top[2]);
            }
        }
        s.push_str("\x1b[0m\n");
        out.write_all(s.as_bytes())?;
        y -= 2;
    }
    Ok(())
}

/// Characters naming palette indices 0, 1, ... in a preview without colour.
/// The characters of colours 1 to 61 in a preview without colour: the
/// numbers the colour table, `--at` and `--json` give (it drew index 0 as
/// `0`, so the table's colour 3 was the preview's `2`: a hostile-input
/// review).
const COLOUR_CHARS: &[u8] = b"123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";

/// Preview without colour: one character per texel, its colour's number
/// ([`COLOUR_CHARS`]; `.` transparent, `?` beyond them), top row first,
/// then a legend of the characters, `?` included. Subsampled like
/// [`preview`].
fn plain_preview(p: &Pattern, max: u32) -> String {
    use std::fmt::Write;
    let size = p.size();
    let step = size.div_ceil(max).max(1);
    let cells = size.div_ceil(step);
    let mut s = String::new();
    for y in (0..cells).rev() {
        for x in 0..cells {
            s.push(match p.index_at(x * step, y * step) {
                None => '.',
                Some(i) => COLOUR_CHARS.get(i as usize).map_or('?', |&c| c as char),
            });
        }
        s.push('\n');
    }
    let palette = p.palette();
    for (i, c) in palette.iter().enumerate().take(COLOUR_CHARS.len()) {
        let _ = writeln!(s, "  {} {}", COLOUR_CHARS[i] as char, c.hex());
    }
    if palette.len() > COLOUR_CHARS.len() {
        let _ = writeln!(
            s,
            "  ? colours {} to {} (see the table)",
            COLOUR_CHARS.len() + 1,
            palette.len()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::pat::TRANSPARENT;

    #[test]
    fn a_preview_is_written_a_line_at_a_time() {
        // A hostile-input review found a 4096x4096 preview (243 MB of
        // escapes) built whole before it was written: 274 MB peak.
        struct Lines(Vec<Vec<u8>>);
        impl std::io::Write for Lines {
            fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
                self.0.push(b.to_vec());
                Ok(b.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let texels: Vec<u16> = (0..64 * 64).map(|i| (i % 3 % 2) as u16).collect();
        let palette = vec![Rgb8([1, 2, 3]), Rgb8([4, 5, 6])];
        let p = Pattern::new(64, palette, texels).unwrap();
        // What the preview shows is checked through `preview` by the tests
        // below; here, that it is written one line per write: a line of
        // `cells` half blocks for each two texel rows.
        for (max, cells) in [(64, 64), (7, 7)] {
            let mut lines = Lines(Vec::new());
            write_preview(&p, max, &mut lines).unwrap();
            assert_eq!(lines.0.len(), cells / 2 + cells % 2, "max {max}");
            for line in &lines.0 {
                assert!(line.ends_with(b"\x1b[0m\n"), "max {max}");
                assert_eq!(line.iter().filter(|&&b| b == b'\n').count(), 1);
                let blocks = String::from_utf8_lossy(line).matches('▀').count();
                assert_eq!(blocks, cells, "max {max}");
            }
        }
    }

    #[test]
    fn preview_has_one_line_per_two_rows_and_resets_colour() {
        let p = Pattern::new(16, vec![Rgb8([1, 2, 3])], vec![0; 256]).unwrap();
        let out = preview(&p, 64);
        assert_eq!(out.lines().count(), 8);
        assert!(out.lines().all(|l| l.ends_with("\x1b[0m")));
        assert_eq!(out.matches('▀').count(), 16 * 8);
        assert!(out.contains("38;2;1;2;3m"));
        // Subsampled to 8 texels wide: 4 lines of 8 cells.
        let small = preview(&p, 8);
        assert_eq!(small.lines().count(), 4);
        assert_eq!(small.matches('▀').count(), 32);
    }

    #[test]
    fn the_plain_preview_numbers_colours_as_the_table_does() {
        // Texel (0, 0) of colour index 2 is the table's colour 3, and so
        // the preview's `3`; beyond 61 colours, `?`, explained.
        let palette: Vec<Rgb8> = (0..70).map(|i| Rgb8([i as u8, 0, 0])).collect();
        let mut texels = vec![TRANSPARENT; 256];
        texels[0] = 2;
        texels[1] = 69;
        let p = Pattern::new(16, palette, texels).unwrap();
        let out = plain_preview(&p, 16);
        let bottom = out.lines().nth(15).unwrap();
        assert!(bottom.starts_with("3?."), "{bottom}");
        assert!(out.contains("\n  3 #020000\n"), "{out}");
        assert!(out.contains("\n  z #3c0000\n"), "{out}");
        assert!(
            out.ends_with("  ? colours 62 to 70 (see the table)\n"),
            "{out}"
        );
    }

    #[test]
    fn texel_outside_the_pattern_is_an_error_naming_it() {
        let p = Pattern::new(16, vec![], vec![TRANSPARENT; 256]).unwrap();
        let e = texel(&p, Some(IntPair(16, 0))).unwrap_err().to_string();
        assert!(
            e.contains("texel (16,0) is outside the 16x16 pattern"),
            "{e}"
        );
        assert_eq!(
            texel(&p, Some(IntPair(15, 15))).unwrap(),
            Some((15, 15, None))
        );
    }
}
