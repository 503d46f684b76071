//! Texture filters: how a textured polygon's colour at a pixel is computed
//! from its pattern, with separate choices for minification and
//! magnification (XGL Programmer's Guide, texture chapter, "Texture Sampling
//! Method", Table 18-5, `filter1`/`filter2`; OpenGL's
//! `GL_TEXTURE_MIN_FILTER`/`GL_TEXTURE_MAG_FILTER`, seed 002 §7.4).
//!
//! - `box` (the default): the exact area integral of the piecewise-constant
//!   pattern over the pixel ([`super::cells`]), what a user of texel-sized
//!   polygons expects to see.
//! - `point`, `bilinear`: one texel, or the four nearest texel centres
//!   weighted linearly, from the base level (XGL `POINT`, `BILINEAR`; GL
//!   `NEAREST`, `LINEAR`).
//! - `mip-point`, `mip-bilinear`: the same on the nearest MIP level (XGL
//!   `MIPMAP_POINT`, `MIPMAP_BILINEAR`; GL `NEAREST_MIPMAP_NEAREST`,
//!   `LINEAR_MIPMAP_NEAREST`).
//! - `mip-point-linear`, `trilinear`: point or bilinear samples on the two
//!   levels around the footprint, mixed by where it lies between them (XGL
//!   `MIPMAP_PT_LINEAR`, `MIPMAP_TRILINEAR`; GL `NEAREST_MIPMAP_LINEAR`,
//!   `LINEAR_MIPMAP_LINEAR`). XGL's text says "average"; GL's weighting by
//!   the fractional level is used, so the result is continuous in depth.
//! - `ewa`: Heckbert's elliptical weighted average ([`super::ewa`]), an
//!   anisotropic Gaussian over the footprint's ellipse.
//!
//! Conventions (GL 1.x spec, 3.8.8): texel centres at `k + 0.5`; the scale
//! factor rho is the longer of the two mapped pixel steps (texels per pixel,
//! [`super::map::Footprint::rho`]); the level of detail is
//! `lambda = log2(rho) + lod_bias` (XGL's `depth_interp_factor`: +1 one level
//! blurrier); `lambda > 0` is minification and uses the min filter, else the
//! mag filter. Neighbour texels outside the pattern follow the boundary
//! conditions ([`super::boundary`]) at every level.
//!
//! Filtering is done on premultiplied linear RGBA, after composing each
//! texel ([`super::compose::Compose::apply_premultiplied`]). A filtered
//! alpha is then turned into presence by an alpha test at [`ALPHA_TEST`]
//! (the resolvers' visibility is all-or-nothing per fragment): the pixel
//! shows the un-premultiplied colour where alpha is at least one half, and
//! what lies behind elsewhere.

use super::mip::{Extend, MipBuild, MipKey};
use super::PolyTexture;
use crate::math;
use glam::DVec2;

/// A filter method (the module docs describe each).
///
/// - [`Filter::Box`]: the exact area integral over texel cells.
/// - [`Filter::Point`], [`Filter::Bilinear`]: the nearest texel, or the four
///   nearest texel centres weighted linearly, on the base level.
/// - [`Filter::MipPoint`], [`Filter::MipBilinear`]: the same on the nearest
///   MIP level.
/// - [`Filter::MipPointLinear`], [`Filter::Trilinear`]: point or bilinear on
///   the two levels around the footprint, mixed by the fractional level.
/// - [`Filter::Ewa`]: Heckbert's elliptical weighted average.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
// The variants are documented above, not one by one: clap's `ValueEnum`
// turns a variant's doc comment into its `--filter` help text and man page.
#[allow(missing_docs)]
pub enum Filter {
    /// The exact area integral over texel cells.
    #[default]
    Box,
    Point,
    Bilinear,
    MipPoint,
    MipBilinear,
    MipPointLinear,
    Trilinear,
    Ewa,
}

impl Filter {
    /// Every method, in the order of `--filter`'s help.
    pub const ALL: [Filter; 8] = [
        Filter::Box,
        Filter::Point,
        Filter::Bilinear,
        Filter::MipPoint,
        Filter::MipBilinear,
        Filter::MipPointLinear,
        Filter::Trilinear,
        Filter::Ewa,
    ];

    /// The filters allowed for magnification: those of the base level (as
    /// GL's `GL_TEXTURE_MAG_FILTER` accepts only `NEAREST` and `LINEAR`).
    pub fn magnifies(self) -> bool {
        matches!(self, Filter::Box | Filter::Point | Filter::Bilinear)
    }

    /// The magnification filter that goes with `--filter self`: the base
    /// level's counterpart of a MIP filter (point for the point-sampled ones,
    /// bilinear for the others and EWA).
    pub fn mag_counterpart(self) -> Filter {
        match self {
            Filter::Box => Filter::Box,
            Filter::Point | Filter::MipPoint | Filter::MipPointLinear => Filter::Point,
            Filter::Bilinear | Filter::MipBilinear | Filter::Trilinear | Filter::Ewa => {
                Filter::Bilinear
            }
        }
    }

    /// The name on the command line and in a record's `"pattern"`: the one
    /// table of spellings (a test in `cli::scene_texture` checks that clap's
    /// agree).
    pub fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Point => "point",
            Filter::Bilinear => "bilinear",
            Filter::MipPoint => "mip-point",
            Filter::MipBilinear => "mip-bilinear",
            Filter::MipPointLinear => "mip-point-linear",
            Filter::Trilinear => "trilinear",
            Filter::Ewa => "ewa",
        }
    }
}

/// Largest LOD bias magnitude (`--lod-bias`, a record's `"lod_bias"`): 16
/// levels is beyond the 13 of the largest pattern (4096), so any larger value
/// means the same and is likely a typo.
pub const MAX_LOD_BIAS: f64 = 16.0;

/// The filtering of one placement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filters {
    /// For minification (`lambda > 0`). Default value: box.
    pub min: Filter,
    /// For magnification; one of box, point, bilinear. Default value: box.
    pub mag: Filter,
    /// Added to the level of detail (XGL's `depth_interp_factor`). Default
    /// value: 0.
    pub lod_bias: f64,
    /// How MIP levels are built. Default value: Mitchell (XGL).
    pub build: MipBuild,
}

impl Filters {
    /// The exact box filter for both minification and magnification, no LOD
    /// bias, Mitchell MIP build (unused by the box filter): every default.
    pub const BOX: Filters = Filters {
        min: Filter::Box,
        mag: Filter::Box,
        lod_bias: 0.0,
        build: MipBuild::Mitchell,
    };

    /// Whether every pixel uses the exact box filter.
    pub fn is_box(&self) -> bool {
        self.min == Filter::Box && self.mag == Filter::Box
    }
}

impl Default for Filters {
    fn default() -> Self {
        Filters::BOX
    }
}

/// Filtered alpha at or above this shows the texture, below it what is
/// behind (OpenGL's alpha test with `GL_GEQUAL 0.5`): a half-covered filter
/// footprint goes to whichever side covers more.
pub const ALPHA_TEST: f64 = 0.5;

/// The result of evaluating a filter at a screen point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Eval {
    /// The exact box filter applies here: the caller integrates over cells.
    Box,
    /// The filtered colour, linear; `None` where it is transparent.
    Color(Option<[f64; 3]>),
}

/// Where a footprint of `rho` base texels per pixel lies in the pyramid of a
/// `s0` pattern ([`super::mip::level_sizes`]): level `k` and the fraction `t` towards level `k + 1`. Level
/// `k` has scale `s0 / s_k` base texels per texel; the position is linear in
/// `log2` between neighbouring scales (exactly `lambda` for powers of two).
/// For a `W x H` image `s0` is the longer side, whose halvings number the
/// levels.
pub fn level_position(rho: f64, s0: u32) -> (usize, f64) {
    if rho.is_nan() || rho <= 1.0 {
        return (0, 0.0);
    }
    // The sides of [`level_sizes`], walked without allocating (this runs
    // per sample).
    let (mut prev, mut s, mut k) = (1.0f64, s0, 0);
    while s > 1 {
        s /= 2;
        let scale = s0 as f64 / s as f64;
        if rho < scale {
            return (k, math::log2(rho / prev) / math::log2(scale / prev));
        }
        prev = scale;
        k += 1;
    }
    (k, 0.0)
}

impl PolyTexture {
    /// The key of this placement's pyramid.
    pub fn mip_key(&self) -> MipKey {
        MipKey {
            build: self.filters.build,
            u: Extend::of(self.bounds.u),
            v: Extend::of(self.bounds.v),
        }
    }

    /// Whether this texture shows a colour everywhere (no transparent texel
    /// can show through): a fragment's visibility then needs no texel.
    pub fn always_opaque(&self) -> bool {
        self.compose.fills_transparent() || !self.texels.has_transparency()
    }

    /// The sides (width, height) of level `k` ([`super::mip::level_dims`]).
    fn level_dims(&self, k: usize) -> (u32, u32) {
        (
            (self.texels.width() >> k).max(1),
            (self.texels.height() >> k).max(1),
        )
    }

    /// Premultiplied, composed RGBA of texel (i, j) of level `k`, after the
    /// boundary conditions (applied with that level's sides). A texel
    /// shown with partial alpha lies over the polygon's colour.
    #[inline]
    pub(crate) fn fetch(&self, k: usize, i: i64, j: i64) -> [f64; 4] {
        use super::boundary::Lookup;
        let (w, h) = self.level_dims(k);
        match self.bounds.lookup(i, j, w, h) {
            Lookup::Texel(c, r) => {
                let raw = if k == 0 {
                    self.texels.premultiplied(c, r, self.intrinsic)
                } else {
                    self.texels.pyramid(self.mip_key()).levels[k - 1].at_over(c, r, self.intrinsic)
                };
                self.compose.apply_premultiplied(
                    raw,
                    self.intrinsic,
                    self.compose_colors[0],
                    self.compose_colors[1],
                )
            }
            Lookup::Intrinsic => {
                let c = self.intrinsic;
                [c[0], c[1], c[2], 1.0]
            }
            Lookup::Constant => {
                let c = self.constant;
                [c[0], c[1], c[2], 1.0]
            }
        }
    }

    /// Base texels per texel of level `k`, along u and along v (equal for a
    /// square store).
    pub(crate) fn level_scale(&self, k: usize) -> (f64, f64) {
        let (w, h) = self.level_dims(k);
        (
            self.texels.width() as f64 / w as f64,
            self.texels.height() as f64 / h as f64,
        )
    }

    /// A position `(u, v)` in texels of level `k`, moved by whole periods
    /// of the boundary conditions where it lies so far out that its texel
    /// indices would not fit an `i64` or its half-texel offsets a float
    /// (beyond [`FAR_TEXELS`]): what a neighbourhood of `reach` texels
    /// around it fetches is unchanged. Each coordinate keeps its residue
    /// modulo twice the level's side (so modulo the side too: repeat and
    /// mirror fetch the same texels) and stays beyond the same edge by more
    /// than `reach` (so the conditions that leave the pattern, edge's
    /// clamping and XGL's precedence, all see it out on that side). Nearer
    /// positions are returned as given.
    pub(crate) fn near_period(&self, k: usize, u: f64, v: f64, reach: f64) -> (f64, f64) {
        // Every sample of every filter passes here: the common case costs
        // two compares, not the level's dimensions.
        if u.abs() <= FAR_TEXELS && v.abs() <= FAR_TEXELS {
            return (u, v);
        }
        let (w, h) = self.level_dims(k);
        (near(u, w, reach), near(v, h, reach))
    }

    /// The longer side of the base level: the side whose halvings number the
    /// levels ([`level_position`]).
    pub(crate) fn base_side(&self) -> u32 {
        self.texels.width().max(self.texels.height())
    }

    /// The texel of level `k` whose cell holds `uv` (base texel units).
    fn point(&self, k: usize, uv: DVec2) -> [f64; 4] {
        let (sx, sy) = self.level_scale(k);
        let (u, v) = self.near_period(k, uv.x / sx, uv.y / sy, 1.0);
        self.fetch(k, u.floor() as i64, v.floor() as i64)
    }

    /// The four texel centres of level `k` around `uv`, weighted linearly.
    fn bilinear(&self, k: usize, uv: DVec2) -> [f64; 4] {
        let (sx, sy) = self.level_scale(k);
        let (u, v) = self.near_period(k, uv.x / sx, uv.y / sy, 2.0);
        let (a, b) = (u - 0.5, v - 0.5);
        let (i, j) = (a.floor(), b.floor());
        let (fx, fy) = (a - i, b - j);
        let (i, j) = (i as i64, j as i64);
        let mut out = [0.0; 4];
        for (di, dj, w) in [
            (0, 0, (1.0 - fx) * (1.0 - fy)),
            (1, 0, fx * (1.0 - fy)),
            (0, 1, (1.0 - fx) * fy),
            (1, 1, fx * fy),
        ] {
            if w == 0.0 {
                continue;
            }
            let t = self.fetch(k, i + di, j + dj);
            for ch in 0..4 {
                out[ch] += w * t[ch];
            }
        }
        out
    }

    /// The premultiplied RGBA of `filter` at the footprint `fp` (not box).
    pub fn sample(&self, filter: Filter, fp: &super::map::Footprint) -> [f64; 4] {
        let rho = fp.rho() * math::exp2(self.filters.lod_bias);
        let (k, t) = level_position(rho, self.base_side());
        let mix =
            |a: [f64; 4], b: [f64; 4]| std::array::from_fn(|ch| a[ch] * (1.0 - t) + b[ch] * t);
        let nearest = if t < 0.5 { k } else { k + 1 };
        match filter {
            Filter::Box | Filter::Point => self.point(0, fp.uv),
            Filter::Bilinear => self.bilinear(0, fp.uv),
            Filter::MipPoint => self.point(nearest, fp.uv),
            Filter::MipBilinear => self.bilinear(nearest, fp.uv),
            Filter::MipPointLinear if t > 0.0 => {
                mix(self.point(k, fp.uv), self.point(k + 1, fp.uv))
            }
            Filter::MipPointLinear => self.point(k, fp.uv),
            Filter::Trilinear if t > 0.0 => {
                mix(self.bilinear(k, fp.uv), self.bilinear(k + 1, fp.uv))
            }
            Filter::Trilinear => self.bilinear(k, fp.uv),
            Filter::Ewa => super::ewa::sample(self, fp),
        }
    }

    /// The filter that applies at the screen point (x, y) and the footprint
    /// of a pixel there; `None` where it is the exact box filter (or the map
    /// has no footprint there, beyond the plane's horizon: the box filter,
    /// which needs none, takes over).
    #[inline]
    pub fn filter_at(&self, x: f64, y: f64) -> Option<(Filter, super::map::Footprint)> {
        if self.filters.is_box() {
            return None;
        }
        let fp = self.map.footprint(x, y)?;
        let lambda = math::log2(fp.rho()) + self.filters.lod_bias;
        let f = if lambda > 0.0 {
            self.filters.min
        } else {
            self.filters.mag
        };
        (f != Filter::Box).then_some((f, fp))
    }

    /// The filters' colour at the screen point (x, y), with the footprint of
    /// a pixel there.
    #[inline]
    pub fn eval(&self, x: f64, y: f64) -> Eval {
        match self.filter_at(x, y) {
            None => Eval::Box,
            Some((f, fp)) => Eval::Color(unpremultiply(self.sample(f, &fp))),
        }
    }
}

/// Texel coordinates beyond this magnitude (2^50) are moved by whole
/// periods before sampling (`PolyTexture::near_period`): past it a float
/// no longer resolves a texel's centre to better than a quarter texel, and
/// past 2^63 its index no longer fits an `i64` (a coordinate of 1e30 made
/// the EWA read one saturated index, outside its ellipse, and divide by a
/// zero weight).
pub const FAR_TEXELS: f64 = (1u64 << 50) as f64;

/// One coordinate of [`PolyTexture::near_period`] on an axis of `n` texels.
fn near(x: f64, n: u32, reach: f64) -> f64 {
    if x.abs() <= FAR_TEXELS || !x.is_finite() {
        return x;
    }
    let p = 2.0 * n as f64;
    // Exact: the remainder of a float is representable, and so is its sum
    // with a small multiple of the period.
    let r = x.rem_euclid(p);
    let m = ((n as f64 + reach.max(0.0) + 2.0) / p).ceil() + 1.0;
    if x > 0.0 {
        r + p * m
    } else {
        r - p * m
    }
}

/// The alpha test and the colour behind the premultiplication.
#[inline]
pub fn unpremultiply(p: [f64; 4]) -> Option<[f64; 3]> {
    (p[3] >= ALPHA_TEST).then(|| [p[0] / p[3], p[1] / p[3], p[2] / p[3]])
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::pat::{Pattern, TRANSPARENT};
    use crate::texture::boundary::{Boundary, Bounds};
    use crate::texture::compose::Compose;
    use crate::texture::map::TexMap;
    use crate::texture::Texels;
    use std::sync::Arc;

    pub const ALL: [Filter; 8] = Filter::ALL;

    /// A pattern of side `s` from a texel → palette index function.
    pub fn pattern(s: u32, colors: &[Rgb8], mut f: impl FnMut(u32, u32) -> u16) -> Arc<Texels> {
        let t = (0..s * s).map(|i| f(i % s, i / s)).collect();
        Arc::new(Texels::new(&Pattern::new(s, colors.to_vec(), t).unwrap()))
    }

    /// The pattern seen head-on at `scale` texels per pixel (u = scale x,
    /// v = scale y), with filter `min` (mag: its counterpart).
    pub fn placed(texels: Arc<Texels>, scale: f64, min: Filter, bias: f64) -> PolyTexture {
        PolyTexture {
            texels,
            map: TexMap {
                u: [scale, 0.0, 0.0],
                v: [0.0, scale, 0.0],
                d: [0.0, 0.0, 1.0],
            },
            bounds: Bounds::both(Boundary::Repeat),
            intrinsic: [0.1, 0.2, 0.3],
            constant: [0.0; 3],
            compose: Compose::Replace,
            compose_colors: [[0.0; 3], [1.0; 3]],
            filters: Filters {
                min,
                mag: min.mag_counterpart(),
                lod_bias: bias,
                build: MipBuild::Box,
            },
            skips: crate::texture::skip::Skips::ALL,
        }
    }

    fn color(t: &PolyTexture, x: f64, y: f64) -> [f64; 3] {
        match t.eval(x, y) {
            Eval::Color(Some(c)) => c,
            other => panic!("{other:?}"),
        }
    }

    const BW: [Rgb8; 2] = [Rgb8([0, 0, 0]), Rgb8([255, 255, 255])];

    /// Rounding of sums of a few f64 (and the f32 levels): far below 8 bits.
    const TOL: f64 = 1e-6;

    proptest::proptest! {
        /// Every filter weighs texels with non-negative weights summing to
        /// one (the Mitchell build's overshoot is clamped to [0, alpha]), so
        /// on a black-and-white pattern every channel stays within [0, 1] and
        /// the three channels stay equal, under any placement, perspective,
        /// bias, build and boundary.
        #[test]
        fn filtered_colours_stay_within_the_texels_range(
            seed in 0u64..1000,
            (a, b, c, dd) in (-20.0f64..20.0, -20.0f64..20.0, -20.0f64..20.0, -20.0f64..20.0),
            persp in (-0.01f64..0.01, -0.01f64..0.01),
            (x, y) in (0.0f64..64.0, 0.0f64..64.0),
            fi in 1usize..8,
            bias in -3.0f64..3.0,
            mitchell in proptest::bool::ANY,
            bi in 0usize..5,
        ) {
            let mut r = crate::test_util::Rng(seed.wrapping_mul(2654435761) + 1);
            let p = pattern(16, &BW, |_, _| (r.next() < 0.5) as u16);
            let mut t = placed(p, 1.0, ALL[fi], bias);
            t.map = TexMap { u: [a, b, 3.0], v: [c, dd, -7.0], d: [persp.0, persp.1, 1.0] };
            t.filters.build = if mitchell { MipBuild::Mitchell } else { MipBuild::Box };
            t.bounds = Bounds::both([Boundary::Repeat, Boundary::Mirror, Boundary::Edge,
                Boundary::Clamp, Boundary::Transparent][bi]);
            t.intrinsic = [1.0; 3];
            if let Eval::Color(Some(col)) = t.eval(x, y) {
                // Rounding of the normalized sums and of the f32 levels.
                for ch in 0..3 {
                    proptest::prop_assert!((-TOL..=1.0 + TOL).contains(&col[ch]), "{col:?}");
                    proptest::prop_assert!((col[ch] - col[0]).abs() < TOL, "{col:?}");
                }
            }
        }
    }

    #[test]
    fn a_constant_texture_gives_its_colour_under_every_filter_and_scale() {
        let p = pattern(16, &[Rgb8([200, 100, 50])], |_, _| 0);
        let want = [200.0f64, 100.0, 50.0].map(|c| crate::color::srgb_to_linear_f64(c / 255.0));
        for f in ALL.into_iter().filter(|&f| f != Filter::Box) {
            for scale in [0.1, 0.7, 1.0, 3.3, 40.0, 1000.0] {
                let t = placed(p.clone(), scale, f, 0.0);
                let c = color(&t, 5.3, 7.9);
                for ch in 0..3 {
                    assert!((c[ch] - want[ch]).abs() < TOL, "{f:?} x{scale}: {c:?}");
                }
            }
        }
    }

    #[test]
    fn bilinear_at_texel_centres_returns_the_texel() {
        let p = pattern(
            16,
            &[Rgb8([255, 0, 0]), Rgb8([0, 0, 255]), Rgb8([0, 200, 0])],
            |c, r| ((c + 2 * r) % 3) as u16,
        );
        // Magnified x1/4: texel centre (k + 0.5, j + 0.5) at pixel (4k + 2, 4j + 2).
        let t = placed(p.clone(), 0.25, Filter::Bilinear, 0.0);
        for (k, j) in [(0u32, 0u32), (3, 5), (15, 15)] {
            let c = color(&t, 4.0 * k as f64 + 2.0, 4.0 * j as f64 + 2.0);
            let want = p.texel(k as i64, j as i64, [0.0; 3]).unwrap();
            for ch in 0..3 {
                assert!((c[ch] - want[ch]).abs() < 1e-12, "({k}, {j})");
            }
        }
        // Half-way between two texel centres: their mean.
        let c = color(&t, 4.0, 2.0);
        let (a, b) = (
            p.texel(0, 0, [0.0; 3]).unwrap(),
            p.texel(1, 0, [0.0; 3]).unwrap(),
        );
        for ch in 0..3 {
            assert!((c[ch] - 0.5 * (a[ch] + b[ch])).abs() < 1e-12);
        }
    }

    #[test]
    fn a_checker_minifies_to_linear_mid_grey_under_mip_filters() {
        let p = pattern(16, &BW, |c, r| ((c + r) % 2) as u16);
        for f in [
            Filter::MipPoint,
            Filter::MipBilinear,
            Filter::MipPointLinear,
            Filter::Trilinear,
            Filter::Ewa,
        ] {
            for scale in [2.0, 3.0, 5.5, 16.0, 100.0] {
                let t = placed(p.clone(), scale, f, 0.0);
                let c = color(&t, 3.3, 2.1);
                assert!((c[0] - 0.5).abs() < 0.02, "{f:?} x{scale}: {c:?}");
            }
        }
    }

    #[test]
    fn level_positions_follow_log2_of_rho() {
        assert_eq!(level_position(0.5, 16), (0, 0.0));
        assert_eq!(level_position(1.0, 16), (0, 0.0));
        assert_eq!(level_position(2.0, 16), (1, 0.0));
        let (k, t) = level_position(math::powf(2f64, 1.25), 16);
        assert_eq!(k, 1);
        assert!((t - 0.25).abs() < 1e-12);
        assert_eq!(level_position(1e9, 16), (4, 0.0));
        // 48 -> 3 -> 1: scale 16 then 48; rho = sqrt(16 * 48) is half-way.
        let (k, t) = level_position((16.0f64 * 48.0).sqrt(), 48);
        assert_eq!(k, 4);
        assert!((t - 0.5).abs() < 1e-12);
    }

    /// A pattern whose columns are one colour per 8-texel band: level 0
    /// black/white bands of 8, level 3 (2x2, 8 base texels each) the same
    /// bands, level 4 mid grey. Trilinear at a footprint between levels 3
    /// and 4 mixes them in proportion.
    #[test]
    fn trilinear_mixes_the_two_levels_around_the_footprint() {
        let p = pattern(16, &BW, |c, _| (c / 8) as u16);
        let at = |scale: f64| {
            color(
                &placed(p.clone(), scale, Filter::Trilinear, 0.0),
                4.0 / scale,
                0.3,
            )[0]
        };
        // At u = 4 (centre of the black band), level 3 is black, level 4 grey.
        let (k, t) = level_position(math::powf(2f64, 3.25), 16);
        assert!(k == 3 && (t - 0.25).abs() < 1e-12, "{k} {t}");
        let c = at(math::powf(2f64, 3.25));
        assert!((c - 0.25 * 0.5).abs() < TOL, "{c}");
        let c = at(math::powf(2f64, 3.75));
        assert!((c - 0.75 * 0.5).abs() < TOL, "{c}");
    }

    #[test]
    fn lod_bias_shifts_the_level() {
        let p = pattern(16, &BW, |c, _| (c / 8) as u16);
        let c = |scale: f64, bias: f64| {
            color(
                &placed(p.clone(), scale, Filter::MipPoint, bias),
                4.0 / scale,
                0.3,
            )[0]
        };
        // rho = 8: level 3, black at u = 4. Bias +1: level 4, grey.
        assert!(c(8.0, 0.0).abs() < TOL);
        assert!((c(8.0, 1.0) - 0.5).abs() < TOL);
        // rho = 16 (level 4, grey); bias -1: level 3, black.
        assert!((c(16.0, 0.0) - 0.5).abs() < TOL);
        assert!(c(16.0, -1.0).abs() < TOL);
        // A negative bias can turn minification into magnification.
        let t = placed(p.clone(), 1.5, Filter::Box, -1.0);
        assert_eq!(t.eval(1.0, 1.0), Eval::Box);
    }

    #[test]
    fn transparent_texels_pass_the_alpha_test_by_majority() {
        // Columns 0..8 white, 8..16 transparent.
        let p = pattern(16, &BW[1..], |c, _| if c < 8 { 0 } else { TRANSPARENT });
        let t = placed(p, 1.0 / 16.0, Filter::Bilinear, 0.0);
        // u = 7.5 + 0.25: 3/4 white → white; u = 8.5 - ... 1/4 white → absent.
        assert_eq!(t.eval(7.75 * 16.0, 8.0), Eval::Color(Some([1.0; 3])));
        assert_eq!(t.eval(8.25 * 16.0, 8.0), Eval::Color(None));
    }

    #[test]
    fn boundary_modes_apply_to_bilinear_neighbours() {
        let p = pattern(16, &BW, |c, _| (c / 8) as u16);
        let mut t = placed(p, 1.0 / 16.0, Filter::Bilinear, 0.0);
        // u = 0.25: between texel -1 and texel 0 (weight 3/4 on texel 0).
        let at = |t: &PolyTexture| color(t, 0.25 * 16.0, 8.0 * 16.0)[0];
        assert!((at(&t) - 0.25).abs() < TOL, "repeat: texel 15 is white");
        t.bounds = Bounds::both(Boundary::Edge);
        assert!(at(&t).abs() < TOL, "edge: texel 0 again");
        t.bounds = Bounds::both(Boundary::Transparent);
        assert!((at(&t) - 0.25 * 0.1).abs() < TOL, "the polygon's colour");
    }
}
