//! Colour quantization and dithering: an image becomes a `.pat` (docs/pat-format.md).
//!
//! The pipeline is resample → histogram → palette → remap, one file per idea:
//!
//! 1. `resample.rs`: [`resample_square`] (or [`crop_square`]) brings the image
//!    to SIZE x SIZE. Filtering is done in linear light with premultiplied
//!    alpha (docs/rendering.md): a box filter (exact area average) when shrinking, a
//!    separable Mitchell–Netravali filter when enlarging. The result is rounded
//!    once to 8-bit sRGB: this "resampled image" ([`SquareImage`]) is what the
//!    pattern is measured against.
//! 2. `palette.rs`: [`histogram`] reduces the opaque pixels ([`opaque_mask`]) to
//!    their distinct colours weighted by pixel counts, and [`choose_palette`]
//!    picks K colours from it: median cut in Wu's greedy form (`median_cut.rs`:
//!    each box cut where the squared error falls most), then weighted k-means
//!    (`kmeans.rs`: Lloyd, with Hamerly's bounds so it can run to convergence
//!    cheaply), then a few split/remove moves that let k-means leave a poor
//!    local optimum, then Lloyd steps on the rounded 8-bit palette and, for
//!    small problems, a search of its one-code neighbours. A histogram of
//!    more than 32,768 colours is searched through its coreset
//!    (`coreset.rs`: colours grouped into small boxes of the lattice, each
//!    its weighted mean); one of fewer colours but more than 2^20 colours x K
//!    gets the coreset's shorter search. Nothing is random (the parallel sums use fixed
//!    chunks), so the same image always gives the same palette.
//! 3. `remap.rs`: [`remap()`] assigns each pixel a palette index, with no
//!    dithering, Floyd–Steinberg error diffusion (serpentine, in linear light)
//!    or an 8x8 Bayer ordered dither ([`Dither`]). Undithered, a chosen
//!    palette is found for each distinct colour of the histogram once, and
//!    each pixel looks its colour up.
//!
//! [`quantize`] (this file) runs the steps for given [`Options`], flips the
//! rows and orders the palette by use. `space.rs` is the clustering space that
//! steps 2 and 3 share (points, distance, nearest-centre searches, one in
//! SIMD); `psnr.rs` measures the result ([`psnr()`]); `palette_file.rs` reads
//! forced palettes ([`parse_palette_file`]).
//!
//! **The clustering space is sRGB-encoded 8-bit values, not linear light.**
//! Averaging *pixels* must happen in linear light (resampling, error diffusion),
//! but choosing *representatives* is a different problem: it minimises an error,
//! and the error that matters is the visible one. The sRGB encoding is close to
//! perceptually uniform (its curve approximates lightness), linear light is not:
//! k-means in linear light spends most palette entries on highlights and crushes
//! the shadows into one or two colours. OKLab would be more uniform still, but its
//! nearest colour is not the nearest in the 8-bit sRGB error that docs/rendering.md uses to
//! measure every image (RMSE/PSNR over sRGB codes); clustering in that space makes
//! the k-means objective *be* the metric, so every Lloyd step provably lowers it.
//! Exactly representable palette entries and exact round trips come with it.

mod coreset;
mod kmeans;
mod median_cut;
mod packed;
mod palette;
mod palette_file;
mod psnr;
mod remap;
mod resample;
mod space;
#[cfg(test)]
mod test_data;

pub use self::palette::{choose_palette, choose_palette_with, histogram};
pub use self::palette_file::{palette_is_pattern, parse_palette_file, pattern_palette};
pub use self::psnr::psnr;
pub use self::remap::{remap, remap_with, Dither};
use self::remap::{remap_by_table, NearestTable};
pub use self::resample::{crop_square, resample_square, SquareImage};

use crate::color::Rgb8;
use crate::pat::{InvalidPattern, Pattern, TRANSPARENT};
use crate::progress::{Progress, Silent};

/// The default palette size (the classic 16-colour `.pat` of the thesis).
pub const DEFAULT_COLORS: usize = 16;
/// The most colours `pat-from-image` will choose: beyond 256 a quantizer buys
/// little and the nearest-colour search grows linearly.
pub const MAX_QUANT_COLORS: usize = 256;
/// Pixels whose alpha is below this become transparent texels by default
/// (the midpoint of 8-bit alpha: "more transparent than opaque").
pub const DEFAULT_ALPHA_THRESHOLD: u8 = 128;

/// Everything [`quantize`] needs besides the image.
#[derive(Clone, Debug)]
pub struct Options {
    /// Palette size to choose (ignored when `palette` is given).
    ///
    /// Default value: [`DEFAULT_COLORS`] (16).
    pub colors: usize,
    /// How pixels are assigned palette colours.
    ///
    /// Default value: [`Dither::None`].
    pub dither: Dither,
    /// A forced palette: pixels are mapped to these colours, in this order
    /// (repeated colours are dropped, unused ones kept).
    ///
    /// Default value: `None` (the palette is chosen for the image).
    pub palette: Option<Vec<Rgb8>>,
    /// Pixels with alpha below this are transparent.
    ///
    /// Default value: [`DEFAULT_ALPHA_THRESHOLD`] (128).
    pub alpha_threshold: u8,
    /// Opaque pixels of exactly this colour are transparent too.
    ///
    /// Default value: `None`.
    pub transparent: Option<Rgb8>,
}

impl Options {
    /// Every field at its default value (see each field).
    pub const DEFAULT: Options = Options {
        colors: DEFAULT_COLORS,
        dither: Dither::None,
        palette: None,
        alpha_threshold: DEFAULT_ALPHA_THRESHOLD,
        transparent: None,
    };
}

impl Default for Options {
    fn default() -> Self {
        Options::DEFAULT
    }
}

/// Quantizes a square image to a pattern. The pattern's row 0 is the image's
/// bottom row (docs/pat-format.md).
///
/// Fails only if the options break the `.pat` limits: a forced palette of
/// more colours than a pattern holds.
pub fn quantize(img: &SquareImage, opts: &Options) -> Result<Pattern, InvalidPattern> {
    quantize_with(img, opts, &Silent)
}

/// [`quantize`], telling `progress` its steps: the palette search
/// ([`choose_palette_with`]'s phases) and the remapping, row by row.
pub fn quantize_with(
    img: &SquareImage,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<Pattern, InvalidPattern> {
    let opaque = opaque_mask(img, opts);
    let rgb = |p: &[u8; 4]| [p[0], p[1], p[2]];
    let (palette, table) = match &opts.palette {
        Some(p) => (dedup_keep_order(p), None),
        None => {
            let hist = histogram(
                img.pixels
                    .iter()
                    .zip(&opaque)
                    .filter(|(_, &o)| o)
                    .map(|(p, _)| rgb(p)),
            );
            let palette = choose_palette_with(&hist, opts.colors, progress);
            // An undithered remap of a chosen palette goes through the table
            // unless the table would be both large and nearly one entry a
            // pixel: on all ten 1024x1024 images of
            // `bench/pat_from_image_large.sh` (370 to 688,717 colours, K =
            // 256) it took less CPU than scanning the palette for each pixel
            // (granite 134 ms against 250 for the whole process, plasma 354
            // against 425; perf stat, 5 runs), and the 4096x4096 plasma (2.6
            // million colours) peaked at the same 232 MiB, the histogram's
            // step being the larger. See [`use_nearest_table`] for where it
            // does not pay.
            let table = (opts.dither == Dither::None
                && use_nearest_table(hist.len(), img.pixels.len()))
            .then(|| NearestTable::new(&hist, &palette));
            (palette, table)
        }
    };
    let mut texels = match &table {
        // The table reads the pixels as they are: no copy of their colours.
        Some(table) => remap_by_table(&img.pixels, &opaque, img.size, table, progress),
        None => {
            // Made only now, so that it never lives beside the histogram's
            // buffers (a 4096x4096 image has 50 MB of colours).
            let colors: Vec<[u8; 3]> = img.pixels.iter().map(rgb).collect();
            remap_with(&colors, &opaque, img.size, &palette, opts.dither, progress)
        }
    };
    drop(table);
    // Row 0 of the pattern is the image's bottom row.
    let n = img.size as usize;
    for y in 0..n / 2 {
        let (top, bottom) = texels.split_at_mut((n - 1 - y) * n);
        top[y * n..(y + 1) * n].swap_with_slice(&mut bottom[..n]);
    }
    let (palette, texels) = if opts.palette.is_some() {
        (palette, texels)
    } else {
        drop_unused(palette, texels)
    };
    Pattern::new(img.size, palette, texels)
}

/// Histograms of at most this many colours always go through the
/// [`NearestTable`] (at most 2^21 slots of 6 bytes, 12 MiB).
const NEAREST_TABLE_COLOURS: usize = 1 << 20;

/// Whether an undithered remap of `pixels` pixels of `colours` distinct
/// colours is done through a [`NearestTable`] rather than a palette scan a
/// pixel: when the table is small ([`NEAREST_TABLE_COLOURS`]) or holds at
/// most one colour for every two pixels. A 4096x4096 picture of 16.7
/// million distinct colours took 6.60 s through the table (2^25 slots, each
/// lookup a cache miss) against 5.17 by the scan; the 4096x4096 plasma of
/// `bench/pat_from_image_large.sh` (2.6 million) 3.43 against 3.62; a
/// 1024x1024 picture of 2^20 distinct colours 0.433 against 0.437 (paired
/// runs, `bench/timing.py`'s `measure_in_turns`, K = 256).
fn use_nearest_table(colours: usize, pixels: usize) -> bool {
    colours <= NEAREST_TABLE_COLOURS || 2 * colours <= pixels
}

/// Which pixels become coloured texels: alpha at or above the threshold and not
/// the `--transparent` colour.
pub fn opaque_mask(img: &SquareImage, opts: &Options) -> Vec<bool> {
    img.pixels
        .iter()
        .map(|p| p[3] >= opts.alpha_threshold && opts.transparent != Some(Rgb8([p[0], p[1], p[2]])))
        .collect()
}

fn dedup_keep_order(p: &[Rgb8]) -> Vec<Rgb8> {
    let mut seen = std::collections::HashSet::new();
    p.iter().copied().filter(|c| seen.insert(*c)).collect()
}

/// Sorts the palette by use (most used first, ties by colour) and drops unused
/// entries, renumbering the texels.
fn drop_unused(palette: Vec<Rgb8>, texels: Vec<u16>) -> (Vec<Rgb8>, Vec<u16>) {
    let mut counts = vec![0u64; palette.len()];
    for &t in &texels {
        if t != TRANSPARENT {
            counts[t as usize] += 1;
        }
    }
    let mut order: Vec<usize> = (0..palette.len()).filter(|&i| counts[i] > 0).collect();
    order.sort_by(|&a, &b| counts[b].cmp(&counts[a]).then(palette[a].cmp(&palette[b])));
    let mut new_index = vec![TRANSPARENT; palette.len()];
    for (new, &old) in order.iter().enumerate() {
        new_index[old] = new as u16;
    }
    let texels = texels
        .into_iter()
        .map(|t| {
            if t == TRANSPARENT {
                t
            } else {
                new_index[t as usize]
            }
        })
        .collect();
    (order.iter().map(|&i| palette[i]).collect(), texels)
}

#[cfg(test)]
mod tests {
    use super::test_data::square;
    use super::*;

    #[test]
    fn quantize_flips_rows_and_honours_alpha_and_the_transparent_colour() {
        let img = square(16, |x, y| match (x, y) {
            (0, 0) => [255, 0, 0, 255], // top-left: red
            (1, 0) => [0, 255, 0, 127], // below the alpha threshold
            (2, 0) => [0, 0, 255, 255], // the --transparent colour
            (3, 0) => [0, 255, 0, 128], // just at the threshold: kept
            _ => [9, 9, 9, 255],
        });
        let opts = Options {
            transparent: Some(Rgb8([0, 0, 255])),
            ..Options::default()
        };
        let pat = quantize(&img, &opts).unwrap();
        assert_eq!(pat.color_at(0, 15), Some(Rgb8([255, 0, 0])));
        assert_eq!(pat.color_at(1, 15), None);
        assert_eq!(pat.color_at(2, 15), None);
        assert_eq!(pat.color_at(3, 15), Some(Rgb8([0, 255, 0])));
        assert_eq!(pat.color_at(0, 0), Some(Rgb8([9, 9, 9])));
        // Most used colour first.
        assert_eq!(pat.palette()[0], Rgb8([9, 9, 9]));
        assert_eq!(psnr(&pat, &img), Some(f64::INFINITY));
    }

    #[test]
    fn a_forced_palette_is_kept_whole_and_in_order() {
        let img = square(16, |x, _| {
            if x < 8 {
                [10, 10, 10, 255]
            } else {
                [240, 240, 240, 255]
            }
        });
        let forced = vec![Rgb8([255, 255, 255]), Rgb8([255, 0, 0]), Rgb8([0, 0, 0])];
        let opts = Options {
            palette: Some(forced.clone()),
            ..Options::default()
        };
        let pat = quantize(&img, &opts).unwrap();
        assert_eq!(pat.palette(), &forced[..]);
        assert_eq!(pat.index_at(0, 0), Some(2));
        assert_eq!(pat.index_at(15, 0), Some(0));
    }
}
