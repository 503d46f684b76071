//! Step 3: each pixel takes a palette index, with no dithering, Floyd–Steinberg
//! error diffusion or an 8x8 Bayer ordered dither. Without dithering, a
//! palette chosen from the image's histogram is applied through a table of
//! each distinct colour's nearest entry ([`NearestTable`]), looked up per
//! pixel.
//!
//! Nearest colours are found in the clustering space (8-bit sRGB codes, the
//! metric's space), but the error that Floyd–Steinberg diffuses is light, so it
//! is computed and spread in linear light, along a serpentine scan, and never
//! into transparent pixels. The ordered dither offsets each pixel by a Bayer
//! threshold scaled to the palette's typical step ([`ordered_spread`]); its
//! regular texture tiles cleanly.

use super::packed::{pack, slot, EMPTY};
use super::space::{dist2, point, Channels, Nearest, Point};
use crate::color::{decode_table, linear_to_srgb, Rgb8};
use crate::pat::TRANSPARENT;
use crate::progress::{Progress, Silent};

/// The classic 8x8 Bayer threshold matrix (values 0..64).
const BAYER8: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];
/// Cells of the Bayer matrix.
const BAYER_LEVELS: f32 = 64.0;

/// Floyd–Steinberg weights (sixteenths): ahead, behind-below, below, ahead-below.
const FS_AHEAD: f32 = 7.0 / 16.0;
const FS_BEHIND_BELOW: f32 = 3.0 / 16.0;
const FS_BELOW: f32 = 5.0 / 16.0;
const FS_AHEAD_BELOW: f32 = 1.0 / 16.0;

/// How pixels are assigned palette colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Dither {
    /// Each pixel takes its nearest palette colour: crisp texels, best PSNR.
    #[default]
    None,
    /// Error diffusion in linear light, serpentine scan.
    FloydSteinberg,
    /// 8x8 Bayer threshold matrix: a regular texture that tiles cleanly.
    Ordered,
}

/// Palette indices for each pixel (row 0 at the top, like `colors`);
/// [`TRANSPARENT`] where `opaque` is false or the palette is empty.
pub fn remap(
    colors: &[[u8; 3]],
    opaque: &[bool],
    size: u32,
    palette: &[Rgb8],
    dither: Dither,
) -> Vec<u16> {
    remap_with(colors, opaque, size, palette, dither, &Silent)
}

/// Rows per parallel work unit of the undithered remap.
const REMAP_BAND_ROWS: usize = 16;

/// [`remap`], reporting each row done to `progress` (phase "remap").
pub fn remap_with(
    colors: &[[u8; 3]],
    opaque: &[bool],
    size: u32,
    palette: &[Rgb8],
    dither: Dither,
    progress: &dyn Progress,
) -> Vec<u16> {
    let n = size as usize;
    progress.phase("remap", n as u64);
    let mut out = vec![TRANSPARENT; colors.len()];
    if palette.is_empty() {
        return out;
    }
    let centres: Vec<Point> = palette.iter().map(|c| point(c.0)).collect();
    let nearest = Nearest::new(&centres);
    match dither {
        Dither::None => {
            let channels = Channels::new(&centres);
            let rgb = |c: &[u8; 3]| *c;
            let nearest = |c| channels.nearest(point(c)).0 as u16;
            remap_bands(&mut out, colors, opaque, n, rgb, nearest, progress);
        }
        Dither::Ordered => {
            let spread = ordered_spread(&centres);
            let mut hint = 0;
            for y in 0..n {
                for x in 0..n {
                    let i = y * n + x;
                    if !opaque[i] {
                        continue;
                    }
                    let t = (BAYER8[y % 8][x % 8] as f32 + 0.5) / BAYER_LEVELS - 0.5;
                    let p = point(colors[i]).map(|v| v + t * spread);
                    hint = nearest.find(p, hint).0;
                    out[i] = hint as u16;
                }
                progress.advance(1);
            }
        }
        Dither::FloydSteinberg => {
            let lut = decode_table();
            let pal_lin: Vec<[f32; 3]> = palette.iter().map(|c| c.to_linear()).collect();
            let mut cur = vec![[0f32; 3]; n + 2];
            let mut next = vec![[0f32; 3]; n + 2];
            let mut hint = 0;
            for y in 0..n {
                let rtl = y % 2 == 1;
                for step in 0..n {
                    let x = if rtl { n - 1 - step } else { step };
                    let i = y * n + x;
                    if !opaque[i] {
                        continue;
                    }
                    // Buffers are offset by one so x-1 and x+1 always exist.
                    let e = cur[x + 1];
                    let want =
                        [0, 1, 2].map(|c| (lut[colors[i][c] as usize] + e[c]).clamp(0.0, 1.0));
                    let code = want.map(|v| linear_to_srgb(v) as f32);
                    hint = nearest.find(code, hint).0;
                    out[i] = hint as u16;
                    let err = [0, 1, 2].map(|c| want[c] - pal_lin[hint][c]);
                    let (ahead, behind) = if rtl { (x, x + 2) } else { (x + 2, x) };
                    let spread = |buf: &mut [[f32; 3]], at: usize, f: f32| {
                        for c in 0..3 {
                            buf[at][c] += err[c] * f;
                        }
                    };
                    if (rtl && x > 0) || (!rtl && x + 1 < n) {
                        spread(&mut cur, ahead, FS_AHEAD);
                    }
                    if y + 1 < n {
                        let below_ok = |xx: usize| opaque[(y + 1) * n + xx - 1];
                        if (1..=n).contains(&behind) && below_ok(behind) {
                            spread(&mut next, behind, FS_BEHIND_BELOW);
                        }
                        if below_ok(x + 1) {
                            spread(&mut next, x + 1, FS_BELOW);
                        }
                        if (1..=n).contains(&ahead) && below_ok(ahead) {
                            spread(&mut next, ahead, FS_AHEAD_BELOW);
                        }
                    }
                }
                std::mem::swap(&mut cur, &mut next);
                next.iter_mut().for_each(|e| *e = [0.0; 3]);
                progress.advance(1);
            }
        }
    }
    out
}

/// Each distinct colour of an image and the index of its nearest palette
/// colour, in an open-addressing hash table: the undithered remap of an
/// image of few colours looks each pixel up instead of scanning the palette.
/// Built from the histogram, whose colours are those of the opaque pixels.
pub(super) struct NearestTable {
    /// Packed colours ([`pack`]), [`EMPTY`] in free slots; a power of two
    /// long.
    keys: Vec<u32>,
    index: Vec<u16>,
}

impl NearestTable {
    /// The table of `colours` (a [`super::histogram`]'s: distinct, their
    /// counts unused) and their nearest `palette` colour
    /// (ties to the lower index, as the scan gives). At most half full, so
    /// that a probe rarely goes past its first slot.
    pub(super) fn new(colours: &[([u8; 3], u64)], palette: &[Rgb8]) -> NearestTable {
        use rayon::prelude::*;
        let centres: Vec<Point> = palette.iter().map(|c| point(c.0)).collect();
        let channels = Channels::new(&centres);
        let nearest: Vec<u16> = colours
            .par_iter()
            .map(|&(c, _)| channels.nearest(point(c)).0 as u16)
            .collect();
        let len = (2 * colours.len()).next_power_of_two().max(2);
        let mut table = NearestTable {
            keys: vec![EMPTY; len],
            index: vec![0; len],
        };
        for (&(c, _), &i) in colours.iter().zip(&nearest) {
            let s = slot(&table.keys, pack(c));
            table.keys[s] = pack(c);
            table.index[s] = i;
        }
        table
    }

    /// The nearest palette index of `c`, one of the table's colours.
    #[inline]
    fn get(&self, c: [u8; 3]) -> u16 {
        let s = slot(&self.keys, pack(c));
        debug_assert_eq!(self.keys[s], pack(c), "a colour not in the histogram");
        self.index[s]
    }
}

/// The undithered [`remap`] of RGBA `pixels` through a [`NearestTable`] of
/// every opaque pixel's colour: the same indices, in parallel bands,
/// reporting each row to `progress` (phase "remap").
pub(super) fn remap_by_table(
    pixels: &[[u8; 4]],
    opaque: &[bool],
    size: u32,
    table: &NearestTable,
    progress: &dyn Progress,
) -> Vec<u16> {
    let n = size as usize;
    progress.phase("remap", n as u64);
    let mut out = vec![TRANSPARENT; pixels.len()];
    let rgb = |&[r, g, b, _]: &[u8; 4]| [r, g, b];
    remap_bands(&mut out, pixels, opaque, n, rgb, |c| table.get(c), progress);
    out
}

/// The undithered remap's loop: `out[i]` becomes `nearest` of the colour
/// (`rgb`) of each opaque pixel, in parallel bands of rows (each pixel on its
/// own, so the answer does not depend on the order), reporting each band's
/// rows to `progress`. Neighbouring pixels often repeat a colour, and
/// comparing it is cheaper than a palette scan or a hash (the 1024x1024
/// gradient's rows are one colour each): the last answer is kept while the
/// colour repeats.
fn remap_bands<P: Sync>(
    out: &mut [u16],
    pixels: &[P],
    opaque: &[bool],
    n: usize,
    rgb: impl Fn(&P) -> [u8; 3] + Sync,
    nearest: impl Fn([u8; 3]) -> u16 + Sync,
    progress: &dyn Progress,
) {
    use rayon::prelude::*;
    let band = REMAP_BAND_ROWS * n.max(1);
    out.par_chunks_mut(band)
        .zip(pixels.par_chunks(band).zip(opaque.par_chunks(band)))
        .for_each(|(out, (pixels, opaque))| {
            let mut last: Option<([u8; 3], u16)> = None;
            for ((o, p), &op) in out.iter_mut().zip(pixels).zip(opaque) {
                if op {
                    let c = rgb(p);
                    let index = match last {
                        Some((lc, index)) if lc == c => index,
                        _ => nearest(c),
                    };
                    last = Some((c, index));
                    *o = index;
                }
            }
            progress.advance((out.len() / n.max(1)) as u64);
        });
}

/// The amplitude of the ordered dither: the mean distance from each palette
/// colour to its nearest neighbour, the step between adjacent levels.
fn ordered_spread(centres: &[Point]) -> f32 {
    if centres.len() < 2 {
        return 0.0;
    }
    let total: f32 = centres
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            centres
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &d)| dist2(c, d))
                .fold(f32::INFINITY, f32::min)
                .sqrt()
        })
        .sum();
    total / centres.len() as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::resample::SquareImage;
    use crate::quantize::test_data::square;
    use crate::quantize::{psnr, quantize, Options};

    fn white_share(img: &SquareImage, dither: Dither) -> f64 {
        let opts = Options {
            palette: Some(vec![Rgb8::BLACK, Rgb8::WHITE]),
            dither,
            ..Options::default()
        };
        let pat = quantize(img, &opts).unwrap();
        let (counts, _) = pat.histogram();
        counts[1] as f64 / (img.size * img.size) as f64
    }

    #[test]
    fn the_table_remap_is_the_scan_remap() {
        use crate::quantize::palette::{choose_palette, histogram};
        use crate::quantize::test_data::lcg;
        let mut seed = 17;
        // Few colours, repeated in noise, with a transparent hole.
        let colours: Vec<[u8; 3]> = (0..64 * 64)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed) / 32 * 32))
            .collect();
        let opaque: Vec<bool> = (0..64 * 64).map(|i| i % 97 != 0).collect();
        let hist = histogram(
            colours
                .iter()
                .zip(&opaque)
                .filter(|(_, &o)| o)
                .map(|(c, _)| *c),
        );
        for k in [1, 5, 16, 200] {
            let palette = choose_palette(&hist, k);
            let table = NearestTable::new(&hist, &palette);
            let rgba: Vec<[u8; 4]> = colours.iter().map(|&[r, g, b]| [r, g, b, 9]).collect();
            assert_eq!(
                remap_by_table(&rgba, &opaque, 64, &table, &Silent),
                remap(&colours, &opaque, 64, &palette, Dither::None),
                "{k}"
            );
        }
    }

    #[test]
    fn dithering_preserves_average_light() {
        // sRGB 188 is 50% linear light: Floyd–Steinberg (linear light) gives half
        // white; no dithering gives all white.
        let img = square(64, |_, _| [188, 188, 188, 255]);
        assert!((white_share(&img, Dither::FloydSteinberg) - 0.5).abs() < 0.02);
        assert_eq!(white_share(&img, Dither::None), 1.0);
        // Ordered dithering of mid-code grey mixes both, roughly evenly.
        let img = square(64, |_, _| [128, 128, 128, 255]);
        let share = white_share(&img, Dither::Ordered);
        assert!((0.4..=0.6).contains(&share), "{share}");
    }

    #[test]
    fn dithering_skips_transparent_pixels_and_everything_transparent_is_empty() {
        let img = square(16, |x, _| {
            if x % 2 == 0 {
                [100, 50, 20, 255]
            } else {
                [0, 0, 0, 0]
            }
        });
        for d in [Dither::None, Dither::FloydSteinberg, Dither::Ordered] {
            let pat = quantize(
                &img,
                &Options {
                    dither: d,
                    ..Options::default()
                },
            )
            .unwrap();
            assert_eq!(pat.palette(), &[Rgb8([100, 50, 20])]);
            assert_eq!(pat.histogram(), (vec![128], 128));
        }
        let img = square(16, |_, _| [1, 2, 3, 0]);
        let pat = quantize(&img, &Options::default()).unwrap();
        assert!(pat.palette().is_empty());
        assert_eq!(psnr(&pat, &img), None);
    }
}
