//! Stripe textures: the Compuscene III model of seed 001 (Wah 1986, "Interactive
//! Texturing for a Computer Graphics Display System", chapters I and II).
//!
//! A stripe texture sweeps a 1-D **modulation map** ([`map`]) across a face
//! along a **pattern vector** ([`vector`]): the face point `X` takes map sample
//! `floor(P N) mod N` with `P = P0 + K_p N_p · X`. On the screen, `P` is a ratio
//! of two linear functions of the pixel position ([`mapping`], Fig. 6), so
//! evaluating it per pixel costs a few multiply-adds and one division. Distant
//! faces read coarser levels of the map's pyramid, blended by the screen-space
//! rate of change of `P` ([`lod`], Fig. 7). The value read goes through a
//! **translation map** and modulates the **selected** components of the face's
//! colour, which comes from a **colour-code table** ([`tables`]). Records carry
//! all of this in a `"stripe"` object ([`record`]; schema in `docs/stripe.md`).
//!
//! # Colour (docs/rendering.md)
//!
//! Map values, translated values and face colours are 8-bit sRGB. The
//! modulation is a multiplication in linear light: a modulated channel is
//! `face_lin × lin(T(m))`, where `lin` decodes sRGB (for a pure power law this
//! is exactly the 8-bit product `face × T(m) / 255`). Because that is linear in
//! the modulation, averaging the result over a pixel is averaging `lin(T(m))`,
//! so the translation is applied to each map sample *before* the pyramid is
//! built ([`Modulation`]): every level holds box averages of the very values
//! the reference averages. (The seed translates after blending; the two agree
//! for the identity translation, and only this order is right for averaging.)
//!
//! # The reference
//!
//! [`StripeTexture::reference_shade`] is the exact box filter of the crisp
//! stripe function (level 0, no fade) over a pixel: the set of screen points
//! with `P < c` is a half-plane (the iso-`P` lines are straight), so the pixel's
//! average is a sum over the map samples it crosses of sample value times the
//! area between consecutive iso-lines, each area an exact convex clip.

pub mod from_image;
pub mod lod;
pub mod map;
pub mod mapping;
pub mod record;
pub mod tables;
pub mod vector;

pub use lod::{Lod, LodMode};
pub use map::{Fade, ModulationMap};
pub use mapping::ScreenMapping;
pub use tables::{ColourTable, Select, Translation};
pub use vector::{Orientation, PatternVector, RefPlane};

use crate::color::{srgb8_to_linear_f64, Rgb8};
use glam::DVec2;
use std::fmt;
use std::sync::Arc;

/// The pyramid a shader reads: per map sample the linear-light modulation
/// factor `lin(T(m))`, its levels concatenated (level `k` at `offsets[k]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Modulation {
    n: usize,
    data: Vec<f32>,
    offsets: Vec<usize>,
    /// Level 0 in f64, for the reference.
    level0: Vec<f64>,
}

impl Modulation {
    /// Translates every sample of `map`, decodes it to linear light and builds
    /// the pyramid with the map's fade rule.
    pub fn new(map: &ModulationMap, translation: &Translation) -> Modulation {
        let level0: Vec<f64> = map
            .values()
            .iter()
            .map(|&v| srgb8_to_linear_f64(translation.0[v as usize]))
            .collect();
        let levels = map::pyramid(&level0, map.fade());
        let mut data = Vec::with_capacity(2 * map.len());
        let mut offsets = Vec::with_capacity(levels.len());
        for level in &levels {
            offsets.push(data.len());
            data.extend(level.iter().map(|&v| v as f32));
        }
        Modulation {
            n: map.len(),
            data,
            offsets,
            level0,
        }
    }

    /// Number of level-0 samples, `N` (a power of two).
    pub fn len(&self) -> usize {
        self.n
    }

    /// Never true: a map has at least one sample. (For clippy's `len` rule.)
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Number of levels, `log2 N + 1` (the last has one sample).
    pub fn levels(&self) -> usize {
        self.offsets.len()
    }

    /// The entry of level `k` that covers `P` (the map repeating).
    #[inline]
    pub fn sample(&self, k: usize, p: f64) -> f32 {
        let nk = self.n >> k;
        let i = (floor_i64(p * nk as f64) & (nk as i64 - 1)) as usize;
        self.data[self.offsets[k] + i]
    }

    /// Level `k` at `P`, interpolated linearly between the two entries whose
    /// centres bracket `P` (the map repeating).
    #[inline]
    pub fn sample_linear(&self, k: usize, p: f64) -> f32 {
        let nk = self.n >> k;
        let u = p * nk as f64 - 0.5;
        let i = floor_i64(u);
        let f = (u - i as f64) as f32;
        let mask = nk as i64 - 1;
        let level = &self.data[self.offsets[k]..self.offsets[k] + nk];
        let a = level[(i & mask) as usize];
        let b = level[((i + 1) & mask) as usize];
        a + f * (b - a)
    }

    /// `m = (1 − a) M + a M_L` (the seed's `m = a M_L + (1 − a) M`).
    #[inline]
    pub fn lookup(&self, p: f64, lod: Lod) -> f32 {
        let read = |k: usize| {
            if lod.linear {
                self.sample_linear(k, p)
            } else {
                self.sample(k, p)
            }
        };
        let m = read(lod.level);
        if lod.a > 0.0 {
            m + lod.a * (read(lod.level + 1) - m)
        } else {
            m
        }
    }

    /// The crisp stripe function: level 0 at `P`, in f64.
    pub fn crisp(&self, p: f64) -> f64 {
        let i = (floor_i64(p * self.n as f64) & (self.n as i64 - 1)) as usize;
        self.level0[i]
    }
}

/// `x.floor() as i64` without the call: on x86-64 without SSE4.1 `floor` is
/// a libm call, which profiling showed at 6% of a point-sampled stripe frame.
/// Equal to it for every `|x| < 2^63`; beyond (a texture coordinate that
/// large has no meaningful sample anyway) both saturate, and NaN gives 0 as
/// the cast of NaN does.
#[inline]
pub fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x {
        i.saturating_sub(1)
    } else {
        i
    }
}

/// Why the reference cannot average a pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ReferenceError {
    /// The plane's vanishing line (horizon) crosses the region: part of it
    /// sees no point of the face's plane in front of the camera.
    Horizon,
    /// More map samples cross the region than [`MAX_REFERENCE_CROSSINGS`].
    TooManyStripes(u64),
    /// The region has no area.
    Empty,
}

impl fmt::Display for ReferenceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReferenceError::Horizon => f.write_str("the face plane's horizon crosses the pixel"),
            ReferenceError::TooManyStripes(n) => write!(
                f,
                "{n} map samples cross the pixel, more than the reference's limit of {MAX_REFERENCE_CROSSINGS}"
            ),
            ReferenceError::Empty => f.write_str("the region has no area"),
        }
    }
}
impl std::error::Error for ReferenceError {}

/// The most map-sample boundaries the exact reference integrates over in one
/// region. Each costs one 4-to-5-gon clip; 2^20 keeps one pixel under ~50 ms
/// and is far beyond any pixel of a face that is not at the horizon.
pub const MAX_REFERENCE_CROSSINGS: u64 = 1 << 20;

/// The blend of a face to its next face colour (seed 001's Face Color Data:
/// Next Face Color `nc`, Blend Flag `bf`, Blend Select `bs`). The seed names
/// the fields, not the arithmetic. The reading here: the seed's modulation
/// takes a selected channel from black (modulation 0) to the face colour
/// (modulation 1); with the blend flag the next face colour takes black's
/// place, so the stripes run between two colours, in linear light like the
/// modulation itself ([`StripeTexture::ends`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Blend {
    /// The next face colour, 8-bit sRGB.
    pub next: Rgb8,
    /// Which end of the modulation takes it.
    pub select: BlendSelect,
}

/// Blend Select: which end of the modulation takes the next face colour.
/// Seed 001 gives it two bits (0..3); 2 and 3 have no reading here and are
/// refused when read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BlendSelect {
    /// 0: where the modulation is 0 (the dark stripes), the next face
    /// colour; where it is 1, the face colour.
    #[default]
    DarkToNext,
    /// 1: the reverse: the bright stripes take the next face colour.
    BrightToNext,
}

impl BlendSelect {
    /// The seed's 2-bit value.
    pub fn number(self) -> u8 {
        match self {
            BlendSelect::DarkToNext => 0,
            BlendSelect::BrightToNext => 1,
        }
    }

    /// What it does, for reports.
    pub fn words(self) -> &'static str {
        match self {
            BlendSelect::DarkToNext => "dark stripes take the next colour",
            BlendSelect::BrightToNext => "bright stripes take the next colour",
        }
    }
}

/// A stripe-textured face as the renderer sees it: the shared pyramid, the
/// face's screen mapping, the colour select and the face colour.
#[derive(Clone, Debug, PartialEq)]
pub struct StripeTexture {
    /// The translated map's linear-light pyramid, shared by every face
    /// that uses the same map and translation.
    pub modulation: Arc<Modulation>,
    /// `P` as a function of the screen position (pixels, y up).
    pub mapping: ScreenMapping,
    /// Which of R, G, B the modulation multiplies; the others keep the
    /// face colour.
    pub select: Select,
    /// The face colour in linear light.
    pub face: [f32; 3],
    /// The colours of the selected channels where the modulation is 0 and
    /// where it is 1, linear light: black and the face colour (the seed's
    /// modulation, a product), or, with the blend flag, the next face
    /// colour and the face colour ([`Blend`]). A selected channel is
    /// `ends[0] + (ends[1] − ends[0])·m`: linear in `m`, so every box filter
    /// of `m` is the box filter of the colour, and with `ends[0]` = 0 it is
    /// `face·m` to the bit.
    pub ends: [[f32; 3]; 2],
    /// How each evaluation's levels of detail are chosen.
    pub mode: LodMode,
    /// The width, in pixels, of the screen area one evaluation stands for:
    /// the screen-space derivatives of `P` are scaled by it before the LOD is
    /// chosen. Default value: 1 (one evaluation per pixel). A `k x k`
    /// supersampler sets `1/k`: its samples are averaged over the pixel
    /// afterwards, and filtering each one over the whole pixel as well would
    /// blur twice.
    pub footprint: f64,
}

impl StripeTexture {
    /// A face's texture with the face colour `face` (8-bit sRGB, decoded to
    /// linear light here) and a footprint of one pixel.
    pub fn new(
        modulation: Arc<Modulation>,
        mapping: ScreenMapping,
        select: Select,
        face: Rgb8,
        mode: LodMode,
    ) -> StripeTexture {
        StripeTexture {
            modulation,
            mapping,
            select,
            face: face.to_linear(),
            ends: [[0.0; 3], face.to_linear()],
            mode,
            footprint: 1.0,
        }
    }

    /// The same texture blending to the next face colour (the seed's Blend
    /// Flag set): [`StripeTexture::ends`] as `blend` puts them.
    pub fn with_blend(self, blend: &Blend) -> StripeTexture {
        let next = blend.next.to_linear();
        let ends = match blend.select {
            BlendSelect::DarkToNext => [next, self.face],
            BlendSelect::BrightToNext => [self.face, next],
        };
        StripeTexture { ends, ..self }
    }

    /// The same texture with [`StripeTexture::footprint`] `f` (pixels).
    pub fn with_footprint(self, f: f64) -> StripeTexture {
        StripeTexture {
            footprint: f,
            ..self
        }
    }

    /// The same texture on a face receiving light `e` per channel (flat
    /// lighting, `crate::light`): the face colour and both ends of the
    /// modulation lit as GL lights a colour, `min(1, c e)`, before the
    /// modulation, so a lit stripe is the lit face colour modulated.
    pub fn lit(self, e: [f64; 3]) -> StripeTexture {
        let light = |c: [f32; 3]| [0, 1, 2].map(|ch| ((c[ch] as f64) * e[ch]).min(1.0) as f32);
        StripeTexture {
            face: light(self.face),
            ends: self.ends.map(light),
            ..self
        }
    }

    /// The modulated colour, linear light, for modulation factor `m`
    /// ([`StripeTexture::ends`]).
    #[inline]
    fn colour(&self, m: f32) -> [f32; 3] {
        let mut c = self.face;
        for (i, on) in self.select.0.into_iter().enumerate() {
            if on {
                let [lo, hi] = [self.ends[0][i], self.ends[1][i]];
                c[i] = lo + (hi - lo) * m;
            }
        }
        c
    }

    /// [`StripeTexture::colour`] in f64, for the reference's exact averages.
    #[inline]
    fn colour_f64(&self, m: f64) -> [f64; 3] {
        let mut c = self.face.map(|v| v as f64);
        for (i, on) in self.select.0.into_iter().enumerate() {
            if on {
                let [lo, hi] = [self.ends[0][i] as f64, self.ends[1][i] as f64];
                c[i] = lo + (hi - lo) * m;
            }
        }
        c
    }

    /// The modulation factor at the screen position `(x, y)` (y up, module
    /// [`mapping`]), filtered by the LOD mode.
    #[inline]
    pub fn modulation_at(&self, x: f64, y: f64) -> f32 {
        let (p, px, py) = self.mapping.p_and_gradient(x, y);
        let m = &self.modulation;
        let f = self.footprint;
        let lod = self.mode.select(px * f, py * f, m.len(), m.levels());
        m.lookup(p, lod)
    }

    /// The colour of pixel `(px, py)` — `py` counted from the BOTTOM row, as in
    /// the renderer's screen space — in linear light, sampled at its centre.
    #[inline]
    pub fn shade_linear(&self, px: u32, py: u32) -> [f32; 3] {
        self.colour(self.modulation_at(px as f64 + 0.5, py as f64 + 0.5))
    }

    /// The colour at the screen point `(x, y)` (y up), linear light: the
    /// LOD-filtered modulation there. `scene-render --aa none` and `ssN` call
    /// this at each sample point.
    #[inline]
    pub fn linear_at(&self, x: f64, y: f64) -> [f32; 3] {
        self.colour(self.modulation_at(x, y))
    }

    /// The colour of a fragment of pixel `(px, py)` (`py` from the bottom),
    /// linear light, for `scene-render --aa exact`; `verts` is the fragment
    /// (convex, any orientation), or empty for the whole pixel square.
    ///
    /// Where at most [`StripeTexture::exact_crossings`] map-sample
    /// boundaries cross the fragment (65,536; 2 under `--cig-compat`, which
    /// emulates the seed's filter), the exact box average of the crisp
    /// stripe function over it (as the reference computes it, independently:
    /// on fixed buffers here, by lines there). Elsewhere (a fragment reaching
    /// the plane's horizon, or crossing more samples), the LOD-filtered modulation
    /// at the fragment's centroid (the pixel centre for a whole pixel): the
    /// LOD filter stands for the box over the pixel's footprint, and the
    /// centroid centres it on the part of the pixel the face covers, so an
    /// edge pixel takes the stripes under its covered part rather than the
    /// ones under its (possibly uncovered) centre.
    ///
    /// Also says whether the colour is an estimate of the box integral to
    /// be reported (issue 15: never silent): the LOD filter where the
    /// integral was not taken, except under `--cig-compat`, whose filter is
    /// what was asked for.
    pub fn fragment_linear(&self, px: u32, py: u32, verts: &[DVec2]) -> ([f32; 3], bool) {
        let (x, y) = (px as f64, py as f64);
        let square = crate::geom::polygon::pixel_square(px, py);
        let shape: &[DVec2] = if verts.is_empty() { &square } else { verts };
        if let Some(m) = self.box_modulation_few(shape) {
            return (self.colour(m as f32), false);
        }
        let (cx, cy) =
            crate::geom::polygon::area_centroid(verts).map_or((x + 0.5, y + 0.5), |c| (c.x, c.y));
        (self.linear_at(cx, cy), self.mode != LodMode::Cig)
    }

    /// [`StripeTexture::fragment_linear`] over the disjoint convex `pieces`
    /// of pixel `(px, py)`, the part of a fragment that shows: their
    /// area-weighted mean modulation (the colour is affine in it), each
    /// piece's the exact box average where [`StripeTexture::fragment_linear`]
    /// takes it and the LOD filter at its centroid elsewhere. One piece is
    /// exactly [`StripeTexture::fragment_linear`] (the whole pixel square
    /// standing for the whole pixel). `None` where the pieces have no area.
    pub fn visible_linear<'a>(
        &self,
        px: u32,
        py: u32,
        pieces: impl IntoIterator<Item = &'a [DVec2]>,
    ) -> Option<([f32; 3], bool)> {
        let square = crate::geom::polygon::pixel_square(px, py);
        let mut iter = pieces.into_iter();
        let first = iter.next()?;
        let Some(second) = iter.next() else {
            let whole = if first == &square[..] { &[][..] } else { first };
            return Some(self.fragment_linear(px, py, whole));
        };
        let (mut sum, mut area, mut estimated) = (0.0, 0.0, false);
        for piece in [first, second].into_iter().chain(iter) {
            let a = polygon_area(piece);
            let m = match self.box_modulation_few(piece) {
                Some(m) => m,
                None => {
                    estimated |= self.mode != LodMode::Cig;
                    let c = crate::geom::polygon::area_centroid(piece)
                        .unwrap_or_else(|| crate::geom::polygon::vertex_mean(piece));
                    self.modulation_at(c.x, c.y) as f64
                }
            };
            sum += a * m;
            area += a;
        }
        (area > 0.0).then(|| (self.colour((sum / area) as f32), estimated))
    }

    /// Most map-sample boundaries a fragment may cross for `--aa exact` to
    /// integrate it exactly: [`MAX_EXACT_CROSSINGS`], or [`FEW_CROSSINGS`]
    /// under the seed's own rule (`LodMode::Cig`), whose point is its filter.
    pub fn exact_crossings(&self) -> u32 {
        match self.mode {
            LodMode::Cig => FEW_CROSSINGS,
            LodMode::Blend | LodMode::Nearest => MAX_EXACT_CROSSINGS,
        }
    }

    /// The exact box average of the crisp stripe function over a small convex
    /// fragment crossed by at most [`StripeTexture::exact_crossings`]
    /// map-sample boundaries;
    /// `None` otherwise, and for fragments of more than [`FEW_VERTS`] vertices,
    /// of no area, or reaching the plane's horizon. The same computation as
    /// [`StripeTexture::reference_modulation`] on fixed-size buffers, so it
    /// allocates nothing; where it answers, `--aa exact` has only f32
    /// rounding left against the reference.
    fn box_modulation_few(&self, poly: &[DVec2]) -> Option<f64> {
        if poly.len() < 3 || poly.len() > FEW_VERTS {
            return None;
        }
        let map = &self.mapping;
        let n = self.modulation.len() as f64;
        let (mut pmin, mut pmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut sign = 0.0;
        for v in poly {
            let d = map.denominator(v.x, v.y);
            let s = d.signum();
            if d == 0.0 || (sign != 0.0 && s != sign) {
                return None;
            }
            sign = s;
            let p = map.numerator(v.x, v.y) / d;
            pmin = pmin.min(p);
            pmax = pmax.max(p);
        }
        let (jmin, jmax) = ((pmin * n).floor(), (pmax * n).floor());
        // NaN (a vertex at infinity) fails both tests: no exact answer.
        let crossings = jmax - jmin;
        if crossings.is_nan() || crossings > self.exact_crossings() as f64 {
            return None;
        }
        let area = polygon_area(poly);
        if area.is_nan() || area <= 0.0 {
            return None;
        }
        let total = self.integrate((jmin as i64, jmax as i64), area, |[a, b, c]| {
            clipped_area_few(poly, sign * a, sign * b, sign * c)
        });
        Some(total / area)
    }

    /// The integral of the crisp stripe function over a polygon of area
    /// `area` whose stripe samples run from `jmin` to `jmax`: each sample's
    /// value times the polygon's area within it, found as differences of
    /// `area_where_less(line)`, the polygon's area on the negative side of
    /// `line` (the iso-line `P = (j + 1)/n`, as [`ScreenMapping::iso_line`]
    /// gives it). The one loop of the reference and of `--aa exact`.
    fn integrate(
        &self,
        (jmin, jmax): (i64, i64),
        area: f64,
        area_where_less: impl Fn([f64; 3]) -> f64,
    ) -> f64 {
        let n = self.modulation.len() as f64;
        let mut total = 0.0;
        let mut below = 0.0;
        for j in jmin..=jmax {
            let upto = if j == jmax {
                area
            } else {
                // Area where P < (j + 1)/n: sign·(N − c D) < 0.
                area_where_less(self.mapping.iso_line((j + 1) as f64 / n))
            };
            total += self.modulation.crisp((j as f64 + 0.5) / n) * (upto - below);
            below = upto;
        }
        total
    }

    /// The largest difference of one channel between two colours the
    /// stripes can show, linear: every colour is `ends[0] + (ends[1] −
    /// ends[0])·m` with `m` in 0..=1, so no box average of them is further
    /// than this from another (the reference's error where it cannot place
    /// every stripe boundary).
    pub fn contrast_linear(&self) -> f64 {
        (0..3)
            .map(|ch| (self.ends[1][ch] as f64 - self.ends[0][ch] as f64).abs())
            .fold(0.0, f64::max)
    }

    /// [`StripeTexture::contrast_linear`] in 8-bit sRGB codes: the bound
    /// `scene-render` reports for the fragments whose colour is the LOD
    /// filter's estimate ([`StripeTexture::fragment_linear`]).
    pub fn contrast_codes(&self) -> u32 {
        let encode = crate::color::Rgb8::from_linear;
        encode(self.ends[0]).code_distance(encode(self.ends[1]))
    }

    /// The crisp stripe colour at the screen point `(x, y)` (level 0, no LOD),
    /// linear light, f64: the function the reference integrates.
    #[inline]
    pub fn crisp_linear(&self, x: f64, y: f64) -> [f64; 3] {
        self.colour_f64(self.modulation.crisp(self.mapping.p(x, y)))
    }

    /// [`StripeTexture::shade_linear`] encoded to 8-bit sRGB.
    #[inline]
    pub fn shade(&self, px: u32, py: u32) -> Rgb8 {
        Rgb8::from_linear(self.shade_linear(px, py))
    }

    /// The exact average of the crisp stripe function over a convex screen
    /// polygon (vertices in order, either orientation) lying within the face.
    pub fn reference_modulation(&self, poly: &[DVec2]) -> Result<f64, ReferenceError> {
        let area = polygon_area(poly);
        if area.is_nan() || area <= 0.0 {
            return Err(ReferenceError::Empty);
        }
        let map = &self.mapping;
        let d: Vec<f64> = poly.iter().map(|v| map.denominator(v.x, v.y)).collect();
        let sign = if d.iter().all(|&v| v > 0.0) {
            1.0
        } else if d.iter().all(|&v| v < 0.0) {
            -1.0
        } else {
            return Err(ReferenceError::Horizon);
        };
        let n = self.modulation.len() as f64;
        let ps = poly.iter().map(|v| map.p(v.x, v.y));
        let (pmin, pmax) = ps.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p), b.max(p))
        });
        let (jmin, jmax) = ((pmin * n).floor(), (pmax * n).floor());
        let crossings = jmax - jmin;
        if crossings.is_nan() || crossings > MAX_REFERENCE_CROSSINGS as f64 {
            return Err(ReferenceError::TooManyStripes(if crossings.is_finite() {
                crossings as u64
            } else {
                u64::MAX
            }));
        }
        let total = self.integrate((jmin as i64, jmax as i64), area, |[a, b, c]| {
            clipped_area(poly, sign * a, sign * b, sign * c)
        });
        Ok(total / area)
    }

    /// The reference colour of pixel `(px, py)` (`py` from the bottom), linear
    /// light, f64: the exact box filter of the crisp stripe function over the
    /// pixel square, assuming the face covers the whole square. Exact up to f64
    /// rounding: the error is below 1e-12 per 10^3 crossed samples (each sample
    /// adds one rounded area difference of relative size 1e-16).
    pub fn reference_linear(&self, px: u32, py: u32) -> Result<[f64; 3], ReferenceError> {
        let square = crate::geom::polygon::pixel_square(px, py);
        Ok(self.colour_f64(self.reference_modulation(&square)?))
    }

    /// [`StripeTexture::reference_linear`] encoded to 8-bit sRGB.
    pub fn reference_shade(&self, px: u32, py: u32) -> Result<Rgb8, ReferenceError> {
        let c = self.reference_linear(px, py)?;
        Ok(Rgb8::from_linear(c.map(|v| v as f32)))
    }
}

/// Most map-sample boundaries across a fragment for `--aa exact` to integrate
/// the crisp stripe function exactly instead of reading the LOD pyramid: the
/// magnified and mildly minified pixels, where the pyramid's filter is least
/// like the box (one sample boundary in a pixel is a hard edge that no
/// level reproduces). Each boundary costs one small clip. Measured on a
/// ground-and-wall scene at 1024x768 (the geometry of `bench/stripe.sh`, with
/// `furrow.map` on the wall; RMSE against `--reference`, 8-bit): 0 → 3.98 (constant pixels only), 1 → 2.86, 2 → 2.74, 4 → 2.61,
/// 8 → 2.54, the render time growing by roughly 5% per step; 2 takes most
/// of the gain.
pub const FEW_CROSSINGS: u32 = 2;

/// Most map-sample boundaries across a fragment that `--aa exact` integrates
/// exactly (issue 15, item 3), each one small clip of a fragment of at most
/// [`FEW_VERTS`] vertices: the box filter of the crisp stripes, as the
/// reference has it, for every fragment short of a plane's horizon. Measured
/// on `bench/stripe.sh`'s ground and wall at 1024x768: RMSE against the
/// reference 2.71 → 0.08 (8-bit), render phase 0.065 → 0.19 s on one thread.
/// The LOD modes remain the point samplers' filter (`--aa none`, `ssN`) and
/// `--cig-compat`'s, which keeps [`FEW_CROSSINGS`] under `--aa exact` too.
pub const MAX_EXACT_CROSSINGS: u32 = 1 << 16;

/// Most vertices of a fragment for the exact path: a pixel square clipped by
/// a convex piece of up to 8 vertices, on a fixed-size buffer.
pub const FEW_VERTS: usize = 12;

/// [`clipped_area`] on a stack buffer, for polygons of at most [`FEW_VERTS`]
/// vertices (a convex polygon cut by a line gains at most one vertex).
fn clipped_area_few(poly: &[DVec2], a: f64, b: f64, c: f64) -> f64 {
    let f = |v: DVec2| a * v.x + b * v.y + c;
    let mut out = [DVec2::ZERO; FEW_VERTS + 1];
    let mut len = 0;
    let n = poly.len();
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 && len < out.len() {
            out[len] = p;
            len += 1;
        }
        if ((fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0)) && len < out.len() {
            let t = fp / (fp - fq);
            out[len] = p + (q - p) * t;
            len += 1;
        }
    }
    if len < 3 {
        0.0
    } else {
        polygon_area(&out[..len])
    }
}

/// Unsigned area of a simple polygon (shoelace).
///
/// This is the plain shoelace on screen coordinates, not the kernel's
/// anchored [`crate::geom::polygon::area2`]: the two differ in the last bits
/// far from the origin, and switching would move stripe pixels that sit on a
/// rounding boundary. It stays until the stripe path is verified against an
/// exact reference (the "exact means exact, stripes included" issue), so that
/// the layering change moved no output byte.
fn polygon_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a.x * b.y - a.y * b.x
        })
        .sum();
    0.5 * twice.abs()
}

/// Area of the part of a convex polygon where `a x + b y + c <= 0`.
fn clipped_area(poly: &[DVec2], a: f64, b: f64, c: f64) -> f64 {
    let f = |v: DVec2| a * v.x + b * v.y + c;
    let mut out: Vec<DVec2> = Vec::with_capacity(poly.len() + 1);
    let n = poly.len();
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            let t = fp / (fp - fq);
            out.push(p + (q - p) * t);
        }
    }
    if out.len() < 3 {
        0.0
    } else {
        polygon_area(&out)
    }
}

#[cfg(test)]
mod tests;
