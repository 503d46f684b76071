//! Benchmark helper: the error of a quantized image against its reference.
//!
//! `cargo run --release --example psnr -- REFERENCE CANDIDATE` prints one line,
//! `PSNR_SRGB LINEAR_PSNR OKLAB_DE`:
//! - PSNR in dB over RGB in 8-bit sRGB (docs/rendering.md, the benchmark's main score);
//! - PSNR in dB of linear-light values (peak 1), which weighs highlights more;
//! - mean OKLab distance x 100, a perceptual error (about 1 is just noticeable).
//!
//! CANDIDATE may be any image or a `.pat` (rendered with row 0 at the bottom).
//! Both must have the same size; transparent pattern texels are skipped.

use anyhow::{bail, Context, Result};
use patkit::color::decode_table;
use patkit::math;
use patkit::Pattern;

/// OKLab distances are around 0.01 for a just-noticeable difference: scale to ~1.
const OKLAB_DE_SCALE: f64 = 100.0;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [reference, candidate] = &args[..] else {
        bail!("usage: psnr REFERENCE CANDIDATE");
    };
    let r = image::open(reference)
        .with_context(|| reference.clone())?
        .into_rgba8();
    let c = read_candidate(candidate)?;
    let (w, h) = r.dimensions();
    if c.len() != (w * h) as usize {
        bail!("{candidate}: not the size of {reference} ({w}x{h})");
    }
    let lut = decode_table();
    let (mut se, mut se_lin, mut de, mut n) = (0f64, 0f64, 0f64, 0u64);
    for (i, p) in r.pixels().enumerate() {
        let Some(q) = c[i] else { continue };
        for ch in 0..3 {
            se += (p.0[ch] as f64 - q[ch] as f64).powi(2);
            se_lin += (lut[p.0[ch] as usize] as f64 - lut[q[ch] as usize] as f64).powi(2);
        }
        let (a, b) = (oklab(p.0[..3].try_into()?), oklab(q));
        de += ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        n += 1;
    }
    if n == 0 {
        bail!("no pixels to compare");
    }
    let psnr = |mse: f64, peak: f64| 10.0 * math::log10(peak * peak / mse);
    println!(
        "{:.3} {:.3} {:.4}",
        psnr(se / (3 * n) as f64, 255.0).min(99.0),
        psnr(se_lin / (3 * n) as f64, 1.0).min(99.0),
        de / n as f64 * OKLAB_DE_SCALE
    );
    Ok(())
}

/// Pixels of the candidate, row 0 at the top; `None` where transparent.
fn read_candidate(name: &str) -> Result<Vec<Option<[u8; 3]>>> {
    if name.ends_with(".pat") {
        let p = Pattern::read_file(name.as_ref())?;
        let n = p.size();
        let mut out = Vec::new();
        for y in 0..n {
            for x in 0..n {
                out.push(p.color_at(x, n - 1 - y).map(|c| c.0));
            }
        }
        return Ok(out);
    }
    let img = image::open(name)
        .with_context(|| name.to_string())?
        .into_rgba8();
    Ok(img
        .pixels()
        .map(|p| (p.0[3] > 0).then_some([p.0[0], p.0[1], p.0[2]]))
        .collect())
}

/// sRGB code to OKLab (Björn Ottosson's matrices).
fn oklab(c: [u8; 3]) -> [f64; 3] {
    let lut = decode_table();
    let [r, g, b] = c.map(|v| lut[v as usize] as f64);
    let l = math::cbrt(0.4122214708 * r + 0.5363325363 * g + 0.0514459929 * b);
    let m = math::cbrt(0.2119034982 * r + 0.6806995451 * g + 0.1073969566 * b);
    let s = math::cbrt(0.0883024619 * r + 0.2817188376 * g + 0.6299787005 * b);
    [
        0.2104542553 * l + 0.7936177850 * m - 0.0040720468 * s,
        1.9779984951 * l - 2.4285922050 * m + 0.4505937099 * s,
        0.0259040371 * l + 0.7827717662 * m - 0.8086757660 * s,
    ]
}
