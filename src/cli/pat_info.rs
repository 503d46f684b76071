//! `pat-info`: examine and validate `.pat` patterns.

use super::{AlreadyReported, IntPair};
use crate::io::{display_name, read_input};
use crate::pat::{Pattern, Seam};
use anyhow::Result;
use clap::Parser;
use serde_json::{json, Value};
use std::io::Write;

const EXAMPLES: &str = "\
Examples:
  pat-info fixtures/patterns/brick.pat
  pat-info --preview fixtures/patterns/*.pat
  pat-info --check *.pat && echo all valid
  pat-info --at 3,5 --json brick.pat | jq '.[0].texel'
  pat-tile --pat --size 256x256 brick.pat | pat-info -";

/// Examine multi-colour texture patterns: size, colours and their coverage,
/// transparency, whether the pattern tiles without a seam, single texels, and a
/// true-colour terminal preview.
#[derive(Parser, Debug)]
#[command(name = "pat-info", version, after_help = EXAMPLES)]
pub struct Args {
    /// Pattern files; `-` reads standard input.
    #[arg(default_value = "-")]
    pub files: Vec<String>,

    /// Validate only: print nothing on success, one error per invalid file, and
    /// exit 1 if any file is invalid.
    #[arg(long)]
    pub check: bool,

    /// Print one JSON array with an object per file instead of text.
    #[arg(long, conflicts_with = "check")]
    pub json: bool,

    /// Also show the texel at column COL, row ROW (row 0 is the bottom row).
    #[arg(long, value_name = "COL,ROW")]
    pub at: Option<IntPair>,

    /// Draw the pattern in the terminal with 24-bit colour, two texels per
    /// character cell; transparent texels show as a grey checker.
    #[arg(long, conflicts_with_all = ["check", "json"])]
    pub preview: bool,

    /// Widest preview in texels; larger patterns are shown subsampled.
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub preview_size: u32,
}

/// Runs `pat-info`.
pub fn run(args: Args) -> Result<()> {
    let mut stdout = std::io::stdout().lock();
    let mut failures = 0usize;
    let mut reports = Vec::new();
    for file in &args.files {
        let name = display_name(file);
        let result = read_input(file)
            .and_then(|bytes| Pattern::parse(&bytes, name).map_err(anyhow::Error::new))
            .and_then(|p| texel(&p, args.at).map(|t| (p, t)));
        let (pattern, at) = match result {
            Ok(ok) => ok,
            Err(e) => {
                eprintln!("pat-info: error: {e:#}");
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
            if args.preview {
                write!(stdout, "{}", preview(&pattern, args.preview_size))?;
            }
        }
    }
    if args.json {
        serde_json::to_writer_pretty(&mut stdout, &Value::Array(reports))?;
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
        "  tiling: left/right {} (seam {:.3}, interior {:.3}); bottom/top {} (seam {:.3}, interior {:.3})",
        seam_word(&h),
        h.seam,
        h.interior,
        seam_word(&v),
        v.seam,
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
    json!({"seamless": s.seamless, "seam": s.seam, "interior": s.interior})
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
            json!({"colour": i + 1, "rgb": c.0, "hex": c.hex(), "texels": n, "coverage": n as f64 / total as f64})
        })
        .collect();
    let mut obj = json!({
        "file": name,
        "size": p.size(),
        "colours": colors,
        "transparent": {"texels": transparent, "share": transparent as f64 / total as f64},
        "tiling": {"left_right": seam_json(&h), "bottom_top": seam_json(&v)},
    });
    if let Some((c, r, idx)) = at {
        obj["texel"] = match idx {
            Some(i) => {
                let col = p.palette()[i as usize];
                json!({"column": c, "row": r, "colour": i + 1, "rgb": col.0, "hex": col.hex()})
            }
            None => json!({"column": c, "row": r, "transparent": true}),
        };
    }
    obj
}

/// Light and dark greys of the checker that stands for transparency.
const CHECKER: [[u8; 3]; 2] = [[153, 153, 153], [102, 102, 102]];

/// Half-block preview: each character cell shows two texels, the upper one in
/// the foreground (`▀`) and the lower in the background. Top of the output is
/// the top row of the pattern (row SIZE-1).
fn preview(p: &Pattern, max: u32) -> String {
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
        y -= 2;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::pat::TRANSPARENT;

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
