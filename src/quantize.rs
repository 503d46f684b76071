//! Colour quantization and dithering: an image becomes a `.pat` (SPEC §1).
//!
//! The steps, each a function here:
//!
//! 1. [`resample_square`] (or [`crop_square`]) brings the image to SIZE x SIZE.
//!    Filtering is done in linear light with premultiplied alpha (SPEC §4): a box
//!    filter (exact area average) when shrinking, a separable Mitchell–Netravali
//!    filter when enlarging. The result is rounded once to 8-bit sRGB: this
//!    "resampled image" is what the pattern is measured against.
//! 2. [`choose_palette`] picks K colours: median cut in Wu's greedy form (each
//!    box cut where the squared error falls most), then weighted k-means (Lloyd,
//!    with Hamerly's bounds so it can run to convergence cheaply), then a few
//!    split/remove moves that let k-means leave a poor local optimum, then Lloyd
//!    steps on the rounded 8-bit palette and, for small problems, a search of
//!    its one-code neighbours. All of it runs on the distinct colours
//!    weighted by their pixel counts, and nothing is random (the parallel sums
//!    use fixed chunks), so the same image always gives the same palette.
//! 3. [`remap`] assigns each pixel a palette index, with no dithering,
//!    Floyd–Steinberg error diffusion (serpentine, in linear light) or an 8x8
//!    Bayer ordered dither.
//!
//! **The clustering space is sRGB-encoded 8-bit values, not linear light.**
//! Averaging *pixels* must happen in linear light (resampling, error diffusion),
//! but choosing *representatives* is a different problem: it minimises an error,
//! and the error that matters is the visible one. The sRGB encoding is close to
//! perceptually uniform (its curve approximates lightness), linear light is not:
//! k-means in linear light spends most palette entries on highlights and crushes
//! the shadows into one or two colours. OKLab would be more uniform still, but its
//! nearest colour is not the nearest in the 8-bit sRGB error that SPEC §4 uses to
//! measure every image (RMSE/PSNR over sRGB codes); clustering in that space makes
//! the k-means objective *be* the metric, so every Lloyd step provably lowers it.
//! Exactly representable palette entries and exact round trips come with it.

use crate::color::{decode_table, linear_to_srgb, Rgb8};
use crate::pat::{Pattern, TRANSPARENT};
use anyhow::{bail, Context, Result};

/// The default palette size (the classic 16-colour `.pat` of the thesis).
pub const DEFAULT_COLORS: usize = 16;
/// The most colours `pat-from-image` will choose: beyond 256 a quantizer buys
/// little and the nearest-colour search grows linearly.
pub const MAX_QUANT_COLORS: usize = 256;
/// Pixels whose alpha is below this become transparent texels by default
/// (the midpoint of 8-bit alpha: "more transparent than opaque").
pub const DEFAULT_ALPHA_THRESHOLD: u8 = 128;

/// At most this many Lloyd iterations. On 256x256 photos k-means still gains
/// about 0.1% of its error every ten iterations after 60; with Hamerly's bounds
/// those late iterations are cheap, and 300 bounds pathological inputs.
const KMEANS_MAX_ITERATIONS: usize = 300;
/// ... and at most this many (distinct colours x iterations), so that large
/// patterns of photos (a 1024x1024 upscale has ~10^6 colours) stay within
/// seconds; every image of up to 256x256 pixels still gets all 300.
const KMEANS_WORK: usize = 1 << 25;
/// The fewest iterations the work budget may leave: past the first few dozen,
/// gains are fractions of a percent of the error.
const KMEANS_MIN_ITERATIONS: usize = 24;

/// Mitchell–Netravali parameters B = C = 1/3: the pair its authors recommend,
/// balancing blur against ringing.
const MITCHELL_B: f64 = 1.0 / 3.0;
const MITCHELL_C: f64 = 1.0 / 3.0;
/// The Mitchell filter is zero outside |x| < 2.
const MITCHELL_SUPPORT: f64 = 2.0;

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

/// Peak value of an 8-bit channel, for PSNR.
const PEAK: f64 = 255.0;

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

/// A SIZE x SIZE image in 8-bit sRGB with straight alpha, row 0 at the TOP.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SquareImage {
    pub size: u32,
    pub pixels: Vec<[u8; 4]>,
}

/// Everything [`quantize`] needs besides the image.
#[derive(Clone, Debug)]
pub struct Options {
    /// Palette size to choose (ignored when `palette` is given).
    pub colors: usize,
    pub dither: Dither,
    /// A forced palette: pixels are mapped to these colours, in this order.
    pub palette: Option<Vec<Rgb8>>,
    /// Pixels with alpha below this are transparent.
    pub alpha_threshold: u8,
    /// Opaque pixels of exactly this colour are transparent too.
    pub transparent: Option<Rgb8>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            colors: DEFAULT_COLORS,
            dither: Dither::None,
            palette: None,
            alpha_threshold: DEFAULT_ALPHA_THRESHOLD,
            transparent: None,
        }
    }
}

// ---------------------------------------------------------------- resampling

/// The centred largest square of `img`, resampled to `size` x `size` in linear
/// light with premultiplied alpha (box filter down, Mitchell up).
pub fn resample_square(img: &image::RgbaImage, size: u32) -> SquareImage {
    let (w, h) = img.dimensions();
    let side = w.min(h);
    let (x0, y0) = ((w - side) / 2, (h - side) / 2);
    let lut = decode_table();
    let src_n = side as usize;
    let dst_n = size as usize;
    // Premultiplied linear RGBA of the source square.
    let mut src = Vec::with_capacity(src_n * src_n);
    for y in 0..side {
        for x in 0..side {
            let p = img.get_pixel(x0 + x, y0 + y).0;
            let a = p[3] as f32 / 255.0;
            src.push([
                lut[p[0] as usize] * a,
                lut[p[1] as usize] * a,
                lut[p[2] as usize] * a,
                a,
            ]);
        }
    }
    let weights = filter_weights(src_n, dst_n);
    // Horizontal pass: src_n rows of dst_n.
    let mut tmp = vec![[0f32; 4]; src_n * dst_n];
    for y in 0..src_n {
        let row = &src[y * src_n..(y + 1) * src_n];
        for (x, (start, ws)) in weights.iter().enumerate() {
            tmp[y * dst_n + x] =
                weighted_sum(ws.iter().enumerate().map(|(k, &wt)| (row[start + k], wt)));
        }
    }
    // Vertical pass.
    let mut pixels = Vec::with_capacity(dst_n * dst_n);
    for (start, ws) in &weights {
        for x in 0..dst_n {
            let acc = weighted_sum(
                ws.iter()
                    .enumerate()
                    .map(|(k, &wt)| (tmp[(start + k) * dst_n + x], wt)),
            );
            pixels.push(encode_premultiplied(acc));
        }
    }
    SquareImage { size, pixels }
}

fn weighted_sum(items: impl Iterator<Item = ([f32; 4], f32)>) -> [f32; 4] {
    let mut acc = [0f32; 4];
    for (p, w) in items {
        for c in 0..4 {
            acc[c] += p[c] * w;
        }
    }
    acc
}

/// Premultiplied linear RGBA to straight 8-bit sRGB, clamping the overshoot of
/// the Mitchell filter's negative lobes.
fn encode_premultiplied(p: [f32; 4]) -> [u8; 4] {
    let a = p[3].clamp(0.0, 1.0);
    let a8 = (a * 255.0).round() as u8;
    if a8 == 0 {
        return [0, 0, 0, 0];
    }
    let un = |c: f32| linear_to_srgb((c / a).clamp(0.0, 1.0));
    [un(p[0]), un(p[1]), un(p[2]), a8]
}

/// For each of `dst` output samples, the first source index and the weights
/// (summing to 1) of the source samples it averages.
fn filter_weights(src: usize, dst: usize) -> Vec<(usize, Vec<f32>)> {
    let scale = src as f64 / dst as f64;
    (0..dst)
        .map(|i| {
            if dst <= src {
                // Box: output i covers [i*scale, (i+1)*scale) of the source exactly.
                let lo = i as f64 * scale;
                let hi = (i + 1) as f64 * scale;
                let first = lo.floor() as usize;
                let last = (hi.ceil() as usize).min(src);
                let ws = (first..last)
                    .map(|j| ((hi.min(j as f64 + 1.0) - lo.max(j as f64)) / scale) as f32)
                    .collect();
                (first, ws)
            } else {
                // Mitchell, centred on the output sample's position in source
                // pixel units; taps beyond the edges repeat the edge pixel.
                let centre = (i as f64 + 0.5) * scale - 0.5;
                let first = (centre - MITCHELL_SUPPORT).ceil() as i64;
                let last = (centre + MITCHELL_SUPPORT).floor() as i64;
                let lo = first.clamp(0, src as i64 - 1) as usize;
                let hi = last.clamp(0, src as i64 - 1) as usize;
                let mut ws = vec![0f64; hi - lo + 1];
                for j in first..=last {
                    let k = j.clamp(0, src as i64 - 1) as usize;
                    ws[k - lo] += mitchell(centre - j as f64);
                }
                let total: f64 = ws.iter().sum();
                (lo, ws.iter().map(|w| (w / total) as f32).collect())
            }
        })
        .collect()
}

/// The Mitchell–Netravali cubic.
fn mitchell(x: f64) -> f64 {
    let (b, c) = (MITCHELL_B, MITCHELL_C);
    let x = x.abs();
    let v = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x.powi(3)
            + (-18.0 + 12.0 * b + 6.0 * c) * x * x
            + (6.0 - 2.0 * b)
    } else if x < MITCHELL_SUPPORT {
        (-b - 6.0 * c) * x.powi(3)
            + (6.0 * b + 30.0 * c) * x * x
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    v / 6.0
}

/// The central `size` x `size` region of `img`, pixel for pixel.
pub fn crop_square(img: &image::RgbaImage, size: u32, name: &str) -> Result<SquareImage> {
    let (w, h) = img.dimensions();
    if w < size || h < size {
        bail!("{name}: the image is {w}x{h}, smaller than the {size}x{size} that --crop needs");
    }
    let (x0, y0) = ((w - size) / 2, (h - size) / 2);
    let mut pixels = Vec::with_capacity((size as usize).pow(2));
    for y in 0..size {
        for x in 0..size {
            pixels.push(img.get_pixel(x0 + x, y0 + y).0);
        }
    }
    Ok(SquareImage { size, pixels })
}

// ------------------------------------------------------------ the whole job

/// Quantizes a square image to a pattern. The pattern's row 0 is the image's
/// bottom row (SPEC §1).
pub fn quantize(img: &SquareImage, opts: &Options) -> Result<Pattern> {
    let opaque = opaque_mask(img, opts);
    let colors: Vec<[u8; 3]> = img.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let palette = match &opts.palette {
        Some(p) => dedup_keep_order(p),
        None => {
            let hist = histogram(
                colors
                    .iter()
                    .zip(&opaque)
                    .filter(|(_, &o)| o)
                    .map(|(c, _)| *c),
            );
            choose_palette(&hist, opts.colors)
        }
    };
    let top_down = remap(&colors, &opaque, img.size, &palette, opts.dither);
    let mut texels = Vec::with_capacity(top_down.len());
    for row in top_down.chunks_exact(img.size as usize).rev() {
        texels.extend_from_slice(row);
    }
    let (palette, texels) = if opts.palette.is_some() {
        (palette, texels)
    } else {
        drop_unused(palette, texels)
    };
    Pattern::new(img.size, palette, texels).context("building the pattern")
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

/// Distinct colours and their pixel counts, sorted by colour (deterministic).
pub fn histogram(colors: impl Iterator<Item = [u8; 3]>) -> Vec<([u8; 3], u64)> {
    let mut packed: Vec<u32> = colors
        .map(|[r, g, b]| (r as u32) << 16 | (g as u32) << 8 | b as u32)
        .collect();
    packed.sort_unstable();
    let mut out: Vec<([u8; 3], u64)> = Vec::new();
    for p in packed {
        let c = [(p >> 16) as u8, (p >> 8) as u8, p as u8];
        match out.last_mut() {
            Some((last, n)) if *last == c => *n += 1,
            _ => out.push((c, 1)),
        }
    }
    out
}

// ------------------------------------------------------- palette selection

/// A colour in the clustering space (8-bit sRGB codes as floats).
type Point = [f32; 3];

fn point(c: [u8; 3]) -> Point {
    c.map(|v| v as f32)
}

#[inline]
fn dist2(a: Point, b: Point) -> f32 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Chooses at most `k` colours for the weighted colour histogram `hist`. With
/// `k` or fewer distinct colours the palette is exactly those colours.
pub fn choose_palette(hist: &[([u8; 3], u64)], k: usize) -> Vec<Rgb8> {
    let k = k.max(1);
    if hist.len() <= k {
        return hist.iter().map(|(c, _)| Rgb8(*c)).collect();
    }
    let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
    let centres = median_cut(&points, k);
    let clustering = split_merge(&points, kmeans(&points, centres));
    let mut palette: Vec<Rgb8> = neighbour_search(&points, integer_lloyd(&points, clustering))
        .iter()
        .map(|c| Rgb8(c.map(|v| v as u8)))
        .collect();
    palette.sort();
    palette.dedup();
    palette
}

/// Running weighted sums of a set of points.
#[derive(Clone, Copy, Default)]
struct Moments {
    w: f64,
    s: [f64; 3],
    ss: f64,
}

impl Moments {
    fn add(&mut self, p: Point, w: f64) {
        self.w += w;
        for (s, &v) in self.s.iter_mut().zip(&p) {
            *s += v as f64 * w;
            self.ss += (v as f64).powi(2) * w;
        }
    }
    fn add_moments(&mut self, o: &Moments) {
        self.w += o.w;
        self.ss += o.ss;
        for c in 0..3 {
            self.s[c] += o.s[c];
        }
    }
    fn sub(&self, o: &Moments) -> Moments {
        Moments {
            w: self.w - o.w,
            s: [self.s[0] - o.s[0], self.s[1] - o.s[1], self.s[2] - o.s[2]],
            ss: self.ss - o.ss,
        }
    }
    /// Weighted sum of squared distances to the mean.
    fn sse(&self) -> f64 {
        if self.w <= 0.0 {
            return 0.0;
        }
        (self.ss - self.s.iter().map(|s| s * s).sum::<f64>() / self.w).max(0.0)
    }
    fn mean(&self) -> Point {
        self.s.map(|s| (s / self.w) as f32)
    }
}

fn moments_of(s: &[(Point, f64)]) -> Moments {
    let mut m = Moments::default();
    for &(p, w) in s {
        m.add(p, w);
    }
    m
}

/// Levels of an 8-bit channel: the clustering space is integer-valued, so a
/// cut is found from per-level sums (counting sort) instead of a sort.
const LEVELS: usize = 256;

/// The cut of `points` (whose moments are `total`) that lowers the squared
/// error most: `(gain, axis, threshold)`, the left part being the points with
/// `p[axis] < threshold`. `None` if every point has the same colour.
fn best_cut(points: &[(Point, f64)], total: &Moments) -> Option<(f64, usize, f32)> {
    let mut best: Option<(f64, usize, f32)> = None;
    let mut bins = vec![Moments::default(); LEVELS];
    for axis in 0..3 {
        bins.iter_mut().for_each(|b| *b = Moments::default());
        for &(p, w) in points {
            bins[p[axis] as usize].add(p, w);
        }
        let mut left = Moments::default();
        let mut seen_any = false;
        for (level, bin) in bins.iter().enumerate() {
            if bin.w == 0.0 {
                continue;
            }
            // A cut just below this level, if anything lies below it.
            if seen_any {
                let gain = total.sse() - left.sse() - total.sub(&left).sse();
                if best.map_or(true, |b| gain > b.0) {
                    best = Some((gain, axis, level as f32));
                }
            }
            left.add_moments(bin);
            seen_any = true;
        }
    }
    best
}

/// Splits `points` in place at a cut from [`best_cut`]: the left part first,
/// each part keeping its order. Returns the size of the left part.
fn apply_cut(points: &mut [(Point, f64)], axis: usize, threshold: f32) -> usize {
    let (left, right): (Vec<_>, Vec<_>) = points.iter().partition(|(p, _)| p[axis] < threshold);
    let n = left.len();
    points[..n].copy_from_slice(&left);
    points[n..].copy_from_slice(&right);
    n
}

/// A box of median cut: a range of the point array, its moments, its best cut.
struct CutBox {
    lo: usize,
    hi: usize,
    cut: Option<(f64, usize, f32)>,
    moments: Moments,
}

impl CutBox {
    fn new(pts: &mut [(Point, f64)], lo: usize, hi: usize) -> CutBox {
        let moments = moments_of(&pts[lo..hi]);
        let cut = best_cut(&pts[lo..hi], &moments);
        CutBox {
            lo,
            hi,
            cut,
            moments,
        }
    }
}

/// Median cut in Wu's greedy form: every box knows the cut (axis and place,
/// not necessarily the median) that lowers its squared error most, and the
/// box split next is the one whose cut gains most.
fn median_cut(points: &[(Point, f64)], k: usize) -> Vec<Point> {
    let mut pts = points.to_vec();
    let n = pts.len();
    let mut boxes = vec![CutBox::new(&mut pts, 0, n)];
    while boxes.len() < k {
        let Some(bi) = (0..boxes.len())
            .filter(|&i| boxes[i].cut.is_some())
            .max_by(|&a, &b| {
                let g = |i: usize| boxes[i].cut.map_or(0.0, |c| c.0);
                g(a).total_cmp(&g(b)).then(b.cmp(&a))
            })
        else {
            break;
        };
        let (lo, hi) = (boxes[bi].lo, boxes[bi].hi);
        let (_, axis, threshold) = boxes[bi].cut.expect("filtered on Some");
        let cut = apply_cut(&mut pts[lo..hi], axis, threshold);
        boxes[bi] = CutBox::new(&mut pts, lo, lo + cut);
        boxes.push(CutBox::new(&mut pts, lo + cut, hi));
    }
    boxes.iter().map(|b| b.moments.mean()).collect()
}

/// Nearest-centre search that skips centres the triangle inequality rules out:
/// if d(c, j) >= 2 d(p, c) for the best centre c so far, j cannot be nearer.
struct Nearest {
    centres: Vec<Point>,
    /// Squared distances between centres, divided by 4.
    quarter: Vec<f32>,
}

impl Nearest {
    fn new(centres: &[Point]) -> Nearest {
        let k = centres.len();
        let mut quarter = vec![0f32; k * k];
        for i in 0..k {
            for j in 0..k {
                quarter[i * k + j] = dist2(centres[i], centres[j]) / 4.0;
            }
        }
        Nearest {
            centres: centres.to_vec(),
            quarter,
        }
    }

    /// The nearest centre to `p` and its squared distance; `hint` is a good
    /// first guess (the previous answer for this or a neighbouring point).
    /// Ties go to the lower index, so the answer does not depend on the hint.
    #[inline]
    fn find(&self, p: Point, hint: usize) -> (usize, f32) {
        let k = self.centres.len();
        let mut best = hint.min(k - 1);
        let mut bd = dist2(p, self.centres[best]);
        for j in 0..k {
            if j == best || self.quarter[best * k + j] > bd {
                continue;
            }
            let d = dist2(p, self.centres[j]);
            if d < bd || (d == bd && j < best) {
                best = j;
                bd = d;
            }
        }
        (best, bd)
    }
}

/// Points per parallel work unit of a Lloyd step. Fixed, so the chunking (and
/// with it every floating-point sum) is the same whatever the thread count.
const KMEANS_CHUNK: usize = 4096;

/// The result of k-means: centres, each point's cluster, the weighted squared error.
struct Clustering {
    centres: Vec<Point>,
    assign: Vec<usize>,
    err: f64,
}

/// One Lloyd assignment: each point to its nearest centre (starting from its
/// current one), with per-cluster moments, the total error and the point that
/// contributes most error.
fn assign_step(
    points: &[(Point, f64)],
    centres: &[Point],
    assign: &mut [usize],
) -> (Vec<Moments>, f64, (f64, usize)) {
    use rayon::prelude::*;
    let nearest = Nearest::new(centres);
    let parts: Vec<(Vec<Moments>, f64, (f64, usize))> = points
        .par_chunks(KMEANS_CHUNK)
        .zip(assign.par_chunks_mut(KMEANS_CHUNK))
        .enumerate()
        .map(|(ci, (pts, asg))| {
            let mut sums = vec![Moments::default(); centres.len()];
            let mut err = 0.0;
            let mut worst = (-1.0f64, 0usize);
            for (i, (&(p, w), a)) in pts.iter().zip(asg.iter_mut()).enumerate() {
                let (c, d) = nearest.find(p, *a);
                *a = c;
                sums[c].add(p, w);
                let e = d as f64 * w;
                err += e;
                if e > worst.0 {
                    worst = (e, ci * KMEANS_CHUNK + i);
                }
            }
            (sums, err, worst)
        })
        .collect();
    let mut sums = vec![Moments::default(); centres.len()];
    let mut err = 0.0;
    let mut worst = (-1.0f64, 0usize);
    for (s, e, w) in parts {
        for (acc, m) in sums.iter_mut().zip(&s) {
            acc.w += m.w;
            acc.ss += m.ss;
            for c in 0..3 {
                acc.s[c] += m.s[c];
            }
        }
        err += e;
        if w.0 > worst.0 {
            worst = w;
        }
    }
    (sums, err, worst)
}

/// Hamerly's bounds for one point: its cluster, an upper bound on the
/// distance to that centre and a lower bound on the distance to any other.
#[derive(Clone, Copy)]
struct Bounds {
    cluster: usize,
    upper: f32,
    lower: f32,
}

/// Weighted Lloyd iterations from `centres` until no point changes cluster (or
/// the iteration budget, [`KMEANS_MAX_ITERATIONS`] and [`KMEANS_WORK`], runs out). Hamerly's bounds skip the nearest-centre search
/// for points that provably keep their centre, so the long tail of small
/// moves that k-means needs to converge costs little. An emptied cluster is
/// moved to the point with the largest weighted error bound.
fn kmeans(points: &[(Point, f64)], mut centres: Vec<Point>) -> Clustering {
    use rayon::prelude::*;
    let k = centres.len();
    let mut bounds = vec![
        Bounds {
            cluster: 0,
            upper: f32::INFINITY,
            lower: 0.0,
        };
        points.len()
    ];
    let iterations =
        (KMEANS_WORK / points.len().max(1)).clamp(KMEANS_MIN_ITERATIONS, KMEANS_MAX_ITERATIONS);
    for _ in 0..iterations {
        // Half the distance from each centre to its nearest other centre.
        let half_gap: Vec<f32> = (0..k)
            .map(|i| {
                (0..k)
                    .filter(|&j| j != i)
                    .map(|j| dist2(centres[i], centres[j]))
                    .fold(f32::INFINITY, f32::min)
                    .sqrt()
                    / 2.0
            })
            .collect();
        let centres_ref = &centres;
        let parts: Vec<(Vec<Moments>, usize, (f64, usize))> = points
            .par_chunks(KMEANS_CHUNK)
            .zip(bounds.par_chunks_mut(KMEANS_CHUNK))
            .enumerate()
            .map(|(ci, (pts, bs))| {
                let mut sums = vec![Moments::default(); k];
                let mut changed = 0;
                let mut worst = (-1.0f64, 0usize);
                for (i, (&(p, w), b)) in pts.iter().zip(bs.iter_mut()).enumerate() {
                    let limit = half_gap[b.cluster].max(b.lower);
                    if b.upper > limit {
                        b.upper = dist2(p, centres_ref[b.cluster]).sqrt();
                        if b.upper > limit {
                            let (mut best, mut second) = ((f32::INFINITY, 0usize), f32::INFINITY);
                            for (j, &c) in centres_ref.iter().enumerate() {
                                let d = dist2(p, c);
                                if d < best.0 {
                                    second = best.0;
                                    best = (d, j);
                                } else if d < second {
                                    second = d;
                                }
                            }
                            if best.1 != b.cluster {
                                changed += 1;
                            }
                            *b = Bounds {
                                cluster: best.1,
                                upper: best.0.sqrt(),
                                lower: second.sqrt(),
                            };
                        }
                    }
                    sums[b.cluster].add(p, w);
                    let e = (b.upper as f64).powi(2) * w;
                    if e > worst.0 {
                        worst = (e, ci * KMEANS_CHUNK + i);
                    }
                }
                (sums, changed, worst)
            })
            .collect();
        let mut sums = vec![Moments::default(); k];
        let mut changed = 0;
        let mut worst = (-1.0f64, 0usize);
        for (s, c, w) in parts {
            for (acc, m) in sums.iter_mut().zip(&s) {
                acc.add_moments(m);
            }
            changed += c;
            if w.0 > worst.0 {
                worst = w;
            }
        }
        let mut moved = vec![0f32; k];
        let mut reseeded = false;
        for (j, m) in sums.iter().enumerate() {
            let new = if m.w > 0.0 {
                m.mean()
            } else if !reseeded {
                reseeded = true;
                points[worst.1].0
            } else {
                centres[j]
            };
            moved[j] = dist2(new, centres[j]).sqrt();
            centres[j] = new;
        }
        if changed == 0 && moved.iter().all(|&m| m == 0.0) {
            break;
        }
        // Widen the bounds by how far the centres moved.
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&a, &b| moved[b].total_cmp(&moved[a]));
        let (max1, max2) = (moved[order[0]], order.get(1).map_or(0.0, |&j| moved[j]));
        let first = order[0];
        bounds.par_iter_mut().for_each(|b| {
            b.upper += moved[b.cluster];
            b.lower -= if b.cluster == first { max2 } else { max1 };
        });
    }
    let mut assign: Vec<usize> = bounds.iter().map(|b| b.cluster).collect();
    let (_, err, _) = assign_step(points, &centres, &mut assign);
    Clustering {
        centres,
        assign,
        err,
    }
}

/// At most this many split-and-merge trials after k-means, in all; each is a
/// full k-means run, kept only if it lowers the error.
const SPLIT_MERGE_TRIALS: usize = 16;
/// ... and at most this many (distinct colours x trials): a 64x64 image gets
/// every trial, a 256x256 photo (~60 000 colours) about four, which keeps the
/// search within a few times the cost of the first k-means run; images with
/// more than this many colours get none.
const SPLIT_MERGE_WORK: usize = 1 << 18;
/// Each round considers the best this-many splits and merges, paired.
const SPLIT_MERGE_CANDIDATES: usize = 3;

/// Escapes k-means' local optima (common on nearly one-dimensional colour sets
/// such as ramps and grey textures): remove a centre whose removal costs little
/// (its colours going to their second-nearest centre), split a cluster whose
/// best cut gains much, rerun k-means, and keep the result if the error fell.
/// Moves are tried by falling (gain - cost) even when the cost exceeds the
/// gain, since k-means' re-convergence is what finds the better optimum.
/// Deterministic, like everything here.
fn split_merge(points: &[(Point, f64)], mut best: Clustering) -> Clustering {
    let k = best.centres.len();
    if k < 3 {
        return best;
    }
    let budget = (SPLIT_MERGE_WORK / points.len().max(1)).min(SPLIT_MERGE_TRIALS);
    let mut trials = 0;
    'rounds: while trials < budget {
        let mut members: Vec<Vec<(Point, f64)>> = vec![Vec::new(); k];
        for (&(p, w), &a) in points.iter().zip(&best.assign) {
            members[a].push((p, w));
        }
        let moments: Vec<Moments> = members.iter().map(|m| moments_of(m)).collect();
        // The splits that gain most. A cut gains at most the cluster's whole
        // error, so clusters are tried by falling error until none can enter.
        let mut by_err: Vec<usize> = (0..k).collect();
        by_err.sort_by(|&a, &b| {
            moments[b]
                .sse()
                .total_cmp(&moments[a].sse())
                .then(a.cmp(&b))
        });
        let mut splits: Vec<(f64, usize, Point, Point)> = Vec::new();
        for c in by_err {
            if splits.len() == SPLIT_MERGE_CANDIDATES
                && splits[SPLIT_MERGE_CANDIDATES - 1].0 >= moments[c].sse()
            {
                break;
            }
            let m = &mut members[c];
            if let Some((gain, axis, threshold)) = best_cut(m, &moments[c]) {
                let cut = apply_cut(m, axis, threshold);
                let (l, r) = (moments_of(&m[..cut]), moments_of(&m[cut..]));
                splits.push((gain, c, l.mean(), r.mean()));
                splits.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                splits.truncate(SPLIT_MERGE_CANDIDATES);
            }
        }
        // The removals that cost least: a centre's points would move to their
        // second-nearest centre, at a cost of the difference in squared error.
        let mut removal = vec![0f64; k];
        for (&(p, w), &a) in points.iter().zip(&best.assign) {
            let second = best
                .centres
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != a)
                .map(|(_, &c)| dist2(p, c))
                .fold(f32::INFINITY, f32::min);
            removal[a] += w * (second - dist2(p, best.centres[a])) as f64;
        }
        let mut removals: Vec<(f64, usize)> = (0..k).map(|r| (removal[r], r)).collect();
        removals.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (si, s) in splits.iter().enumerate() {
            for r in removals
                .iter()
                .filter(|r| r.1 != s.1)
                .take(SPLIT_MERGE_CANDIDATES)
            {
                pairs.push((s.0 - r.0, si, r.1));
            }
        }
        pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        for (_, si, removed) in pairs {
            if trials == budget {
                break 'rounds;
            }
            trials += 1;
            let (_, sc, left, right) = splits[si];
            let mut centres = best.centres.clone();
            centres[sc] = left;
            centres[removed] = right;
            let trial = kmeans(points, centres);
            if trial.err < best.err {
                best = trial;
                continue 'rounds;
            }
        }
        break;
    }
    best
}

/// At most this many Lloyd steps on 8-bit palette entries.
const INTEGER_LLOYD_ITERATIONS: usize = 16;

fn round_point(p: Point) -> Point {
    p.map(|v| v.round().clamp(0.0, 255.0))
}

/// Lloyd steps with the centres rounded to 8-bit codes after each mean: the
/// palette is stored in 8 bits, and rounding a converged float palette moves
/// some pixels' nearest colour; re-assigning and re-rounding wins that back.
/// Stops when the palette is stable or the error stops falling.
fn integer_lloyd(points: &[(Point, f64)], c: Clustering) -> Vec<Point> {
    let mut best: Vec<Point> = c.centres.iter().map(|&p| round_point(p)).collect();
    let mut assign = c.assign;
    let (mut sums, mut best_err, _) = assign_step(points, &best, &mut assign);
    for _ in 0..INTEGER_LLOYD_ITERATIONS {
        let next: Vec<Point> = best
            .iter()
            .zip(&sums)
            .map(|(&old, m)| {
                if m.w > 0.0 {
                    round_point(m.mean())
                } else {
                    old
                }
            })
            .collect();
        if next == best {
            break;
        }
        let mut trial_assign = assign.clone();
        let (trial_sums, err, _) = assign_step(points, &next, &mut trial_assign);
        if err >= best_err {
            break;
        }
        (best, assign, sums, best_err) = (next, trial_assign, trial_sums, err);
    }
    best
}

/// The 26 unit steps of the 8-bit colour lattice (every +-1/0 combination but none).
const LATTICE_STEPS: usize = 26;
/// The neighbour search runs only while one pass costs at most this many
/// distance evaluations (points x K x K x 26): all small palettes of small
/// images (a few milliseconds), never a large photo.
const NEIGHBOUR_SEARCH_WORK: usize = 1 << 23;
/// At most this many passes over the palette.
const NEIGHBOUR_SEARCH_PASSES: usize = 3;

/// Last polish of an 8-bit palette: move single entries by one code in any
/// combination of channels while that lowers the total error (each point
/// taking its nearest entry). Lloyd's rounded means cannot find these moves,
/// since the best 8-bit palette is not the rounded best real-valued one.
fn neighbour_search(points: &[(Point, f64)], mut palette: Vec<Point>) -> Vec<Point> {
    let k = palette.len();
    if points.len() * k * k * LATTICE_STEPS > NEIGHBOUR_SEARCH_WORK {
        return palette;
    }
    let error = |pal: &[Point]| -> f64 {
        points
            .iter()
            .map(|&(p, w)| {
                w * pal
                    .iter()
                    .map(|&c| dist2(p, c))
                    .fold(f32::INFINITY, f32::min) as f64
            })
            .sum()
    };
    let mut best = error(&palette);
    for _ in 0..NEIGHBOUR_SEARCH_PASSES {
        let mut improved = false;
        for j in 0..k {
            for step in 0..27 {
                let d = [step / 9, step / 3 % 3, step % 3].map(|v| v as f32 - 1.0);
                if d == [0.0; 3] {
                    continue;
                }
                let moved = [0, 1, 2].map(|c| palette[j][c] + d[c]);
                if moved.iter().any(|v| !(0.0..=255.0).contains(v)) {
                    continue;
                }
                let mut trial = palette.clone();
                trial[j] = moved;
                let e = error(&trial);
                if e < best {
                    (best, palette, improved) = (e, trial, true);
                }
            }
        }
        if !improved {
            break;
        }
    }
    palette
}

// ----------------------------------------------------------------- remapping

/// Palette indices for each pixel (row 0 at the top, like `colors`);
/// [`TRANSPARENT`] where `opaque` is false or the palette is empty.
pub fn remap(
    colors: &[[u8; 3]],
    opaque: &[bool],
    size: u32,
    palette: &[Rgb8],
    dither: Dither,
) -> Vec<u16> {
    let n = size as usize;
    let mut out = vec![TRANSPARENT; colors.len()];
    if palette.is_empty() {
        return out;
    }
    let centres: Vec<Point> = palette.iter().map(|c| point(c.0)).collect();
    let nearest = Nearest::new(&centres);
    match dither {
        Dither::None => {
            let mut hint = 0;
            for i in 0..colors.len() {
                if opaque[i] {
                    hint = nearest.find(point(colors[i]), hint).0;
                    out[i] = hint as u16;
                }
            }
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
            }
        }
    }
    out
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

// ------------------------------------------------------------------ measures

/// PSNR in dB of the pattern against the square image it came from, over the
/// RGB of texels that are coloured in the pattern (SPEC §4: 8-bit sRGB).
/// `None` if no texel is coloured; infinite for an exact match.
pub fn psnr(pattern: &Pattern, img: &SquareImage) -> Option<f64> {
    let n = img.size;
    let mut sum = 0f64;
    let mut count = 0u64;
    for row in 0..n {
        for col in 0..n {
            if let Some(c) = pattern.color_at(col, n - 1 - row) {
                let p = img.pixels[(row * n + col) as usize];
                for (&a, &b) in c.0.iter().zip(&p) {
                    sum += (a as f64 - b as f64).powi(2);
                }
                count += 3;
            }
        }
    }
    (count > 0).then(|| {
        let mse = sum / count as f64;
        10.0 * (PEAK * PEAK / mse).log10()
    })
}

// ------------------------------------------------------------ palette files

/// A forced palette: the palette of a `.pat` file, or a text list with one
/// colour per line as `r,g,b` or `#rrggbb`, blank lines and `#` comments allowed.
/// A file whose first meaningful line holds a comma or starts with `#` is a list.
pub fn parse_palette_file(bytes: &[u8], name: &str) -> Result<Vec<Rgb8>> {
    let text = std::str::from_utf8(bytes).map_err(|_| {
        anyhow::anyhow!("{name}: not a palette: neither a .pat file nor a text list of colours")
    })?;
    let first = text.lines().map(str::trim).find(|l| !l.is_empty());
    let is_list = first.is_some_and(|l| l.contains(',') || l.starts_with('#'));
    let palette = if is_list {
        let mut out = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if let Some(c) = parse_list_line(line).with_context(|| format!("{name}:{}", i + 1))? {
                out.push(c);
            }
        }
        out
    } else {
        Pattern::parse(bytes, name)?.palette().to_vec()
    };
    if palette.is_empty() {
        bail!("{name}: the palette has no colours");
    }
    if palette.len() > MAX_QUANT_COLORS {
        bail!(
            "{name}: the palette has {} colours, at most {MAX_QUANT_COLORS} are allowed",
            palette.len()
        );
    }
    Ok(palette)
}

/// One line of a colour list: a colour, or `None` for a blank or comment line.
/// A `#` followed by a hex digit begins a colour (`#rrggbb`, so a mistyped `#fff`
/// is an error, not a comment); any other `#` begins a comment.
fn parse_list_line(line: &str) -> Result<Option<Rgb8>> {
    let t = line.trim();
    let colour = if t.starts_with('#') && t[1..].starts_with(|c: char| c.is_ascii_hexdigit()) {
        let (colour, rest) = t.split_once(char::is_whitespace).unwrap_or((t, ""));
        let rest = rest.trim();
        if !rest.is_empty() && !rest.starts_with('#') {
            bail!("unexpected `{rest}` after the colour");
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

    /// A deterministic pseudo-random sequence for test data (64-bit LCG, Knuth's MMIX constants).
    fn lcg(seed: &mut u64) -> u8 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 56) as u8
    }

    fn rgba(w: u32, h: u32, mut f: impl FnMut(u32, u32) -> [u8; 4]) -> image::RgbaImage {
        image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)))
    }

    #[test]
    fn filter_weights_sum_to_one_and_are_identity_at_scale_one() {
        for (src, dst) in [(7, 7), (100, 64), (64, 16), (3, 64), (16, 48)] {
            for (_, ws) in filter_weights(src, dst) {
                let s: f32 = ws.iter().sum();
                assert!((s - 1.0).abs() < 1e-5, "{src}->{dst}: {s}");
            }
        }
        for (i, (start, ws)) in filter_weights(9, 9).into_iter().enumerate() {
            assert_eq!((start, ws), (i, vec![1.0]));
        }
    }

    #[test]
    fn resampling_at_the_same_size_is_exact_even_with_partial_alpha() {
        let mut seed = 1;
        let img = rgba(16, 16, |_, _| {
            let a = lcg(&mut seed).max(1);
            [lcg(&mut seed), lcg(&mut seed), lcg(&mut seed), a]
        });
        let out = resample_square(&img, 16);
        for (p, q) in img.pixels().zip(&out.pixels) {
            assert_eq!(p.0, *q);
        }
    }

    #[test]
    fn shrinking_averages_in_linear_light_and_ignores_transparent_colour() {
        // Black/white checker: the linear average 0.5 encodes to 188, not 128.
        let img = rgba(32, 32, |x, y| {
            let v = if (x + y) % 2 == 0 { 255 } else { 0 };
            [v, v, v, 255]
        });
        let out = resample_square(&img, 16);
        assert!(out.pixels.iter().all(|p| *p == [188, 188, 188, 255]));
        // Red next to a fully transparent (green) pixel stays red, at half alpha.
        let img = rgba(32, 32, |x, _| {
            if x % 2 == 0 {
                [255, 0, 0, 255]
            } else {
                [0, 255, 0, 0]
            }
        });
        let out = resample_square(&img, 16);
        assert!(
            out.pixels.iter().all(|p| *p == [255, 0, 0, 128]),
            "{:?}",
            out.pixels[0]
        );
    }

    #[test]
    fn non_square_images_use_the_centred_square_and_crop_refuses_small_images() {
        // A 48x16 image: only the middle third is blue.
        let img = rgba(48, 16, |x, _| {
            if (16..32).contains(&x) {
                [0, 0, 255, 255]
            } else {
                [255, 0, 0, 255]
            }
        });
        assert!(resample_square(&img, 16)
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        assert!(resample_square(&img, 32)
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        assert!(crop_square(&img, 16, "x")
            .unwrap()
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        let e = crop_square(&img, 32, "pic.png").unwrap_err().to_string();
        assert!(
            e.contains("pic.png") && e.contains("48x16") && e.contains("32x32"),
            "{e}"
        );
    }

    #[test]
    fn enlarging_a_flat_image_keeps_it_flat() {
        let img = rgba(5, 5, |_, _| [10, 200, 30, 255]);
        let out = resample_square(&img, 64);
        assert!(out.pixels.iter().all(|p| *p == [10, 200, 30, 255]));
    }

    #[test]
    fn few_colours_give_exactly_those_colours() {
        let hist = histogram([[1, 2, 3], [9, 9, 9], [1, 2, 3]].into_iter());
        assert_eq!(hist, vec![([1, 2, 3], 2), ([9, 9, 9], 1)]);
        let pal = choose_palette(&hist, 2);
        assert_eq!(pal, vec![Rgb8([1, 2, 3]), Rgb8([9, 9, 9])]);
    }

    #[test]
    fn nearest_search_agrees_with_brute_force() {
        let mut seed = 7;
        let centres: Vec<Point> = (0..40)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed) as f32))
            .collect();
        let nearest = Nearest::new(&centres);
        for i in 0..2000 {
            let p = [0; 3].map(|_: u8| lcg(&mut seed) as f32);
            let want = (0..centres.len())
                .min_by(|&a, &b| dist2(p, centres[a]).total_cmp(&dist2(p, centres[b])))
                .unwrap();
            let got = nearest.find(p, i % centres.len());
            assert_eq!(got.1, dist2(p, centres[want]));
        }
    }

    fn weighted_error(points: &[(Point, f64)], centres: &[Point]) -> f64 {
        points
            .iter()
            .map(|&(p, w)| {
                w * centres
                    .iter()
                    .map(|&c| dist2(p, c) as f64)
                    .fold(f64::INFINITY, f64::min)
            })
            .sum()
    }

    #[test]
    fn kmeans_never_worsens_median_cut_and_the_palette_is_deterministic() {
        let mut seed = 3;
        let colours: Vec<[u8; 3]> = (0..5000)
            .map(|_| {
                let base = lcg(&mut seed) / 64 * 64;
                [base, base / 2 + lcg(&mut seed) / 8, lcg(&mut seed)]
            })
            .collect();
        let hist = histogram(colours.iter().copied());
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        for k in [2, 4, 8, 16, 32] {
            let mc = median_cut(&points, k);
            let km = split_merge(&points, kmeans(&points, mc.clone())).centres;
            assert_eq!(mc.len(), k);
            assert!(weighted_error(&points, &km) <= weighted_error(&points, &mc) + 1e-6);
            assert_eq!(choose_palette(&hist, k), choose_palette(&hist, k));
            assert!(choose_palette(&hist, k).len() <= k);
        }
    }

    #[test]
    fn the_palette_does_not_depend_on_the_thread_count() {
        let mut seed = 11;
        let colours: Vec<[u8; 3]> = (0..20_000)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed)))
            .collect();
        let hist = histogram(colours.into_iter());
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        assert_eq!(
            one.install(|| choose_palette(&hist, 16)),
            three.install(|| choose_palette(&hist, 16))
        );
    }

    #[test]
    fn the_lattice_search_never_raises_the_error() {
        let mut seed = 5;
        let hist = histogram((0..600).map(|_| {
            let g = 160 + lcg(&mut seed) / 16;
            [g, g, g + 3]
        }));
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        let start = vec![
            [150.0, 150.0, 150.0],
            [170.0, 171.0, 172.0],
            [180.0, 180.0, 180.0],
        ];
        let polished = neighbour_search(&points, start.clone());
        assert!(weighted_error(&points, &polished) < weighted_error(&points, &start));
        assert!(polished.iter().flatten().all(|v| v.fract() == 0.0));
    }

    #[test]
    fn two_clusters_are_found() {
        let hist = vec![
            ([0, 0, 0], 10),
            ([2, 0, 0], 10),
            ([250, 250, 250], 5),
            ([254, 254, 254], 5),
        ];
        assert_eq!(
            choose_palette(&hist, 2),
            vec![Rgb8([1, 0, 0]), Rgb8([252, 252, 252])]
        );
    }

    fn square(size: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> SquareImage {
        let mut pixels = Vec::new();
        for y in 0..size {
            for x in 0..size {
                pixels.push(f(x, y));
            }
        }
        SquareImage { size, pixels }
    }

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

    #[test]
    fn palette_files_parse_as_lists_or_patterns() {
        let list =
            b"# my palette\n\n#ff0000  # red\n 0, 255 ,0\n#00f # not a colour: a comment? no\n";
        let e = parse_palette_file(list, "p.txt").unwrap_err();
        assert!(format!("{e:#}").contains("p.txt:5"), "{e:#}");
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
            let e = format!("{:#}", parse_palette_file(bad, "bad.pal").unwrap_err());
            assert!(e.contains("bad.pal"), "{e}");
        }
        let e = format!(
            "{:#}",
            parse_palette_file(b"#ff0000 junk\n", "j").unwrap_err()
        );
        assert!(e.contains("j:1") && e.contains("junk"), "{e}");
    }
}
