//! Sampling patterns.
//!
//! - Screen mode (this file): the IRIS hardware pattern (`defpattern`/
//!   `setpattern`, and `colorclear`): pixel (px, py), counted from the
//!   LOWER-left of the image, takes texel (px mod SIZE, py mod SIZE) (docs/stream-format.md).
//! - [`map`]: where a pattern lies on a projected polygon in "object" and
//!   "uv" placement (the screen → texel projective map).
//! - [`cells`]: the exact box filter, a fragment cut into its texel cells.
//! - [`boundary`]: XGL's boundary conditions outside the pattern's bounds.
//! - [`compose`]: XGL's composition of texel and polygon colour.
//! - [`place`]: a record's pattern placed on its projected polygon.
//! - [`state`]: a record's own filters, boundary and composition (its
//!   `"pattern"` keys), over the tool's flags.
//! - [`filter`]: the other filters (point, bilinear, the MIP filters, EWA in
//!   [`ewa`]) and the choice between minification and magnification; their
//!   pyramids in [`mip`].

pub mod boundary;
pub mod cells;
pub mod compose;
pub mod ewa;
pub mod filter;
pub mod map;
pub mod mip;
pub mod place;
pub mod skip;
pub mod state;
pub mod texels;

pub use texels::Texels;

use crate::color::Rgb8;
use crate::io::Image;
use crate::pat::Pattern;
use std::sync::Arc;

/// A pattern placed on one projected polygon ("object" or "uv" mode): its
/// texels (linear light, shared between polygons) and the screen → texel map.
#[derive(Clone, Debug, PartialEq)]
pub struct PolyTexture {
    /// The pattern decoded to linear light, shared by every polygon that
    /// uses it.
    pub texels: Arc<Texels>,
    /// Screen (pixels, y up) → texel coordinates of this polygon.
    pub map: map::TexMap,
    /// What lies outside the pattern's bounds (default: repeat, docs/stream-format.md).
    pub bounds: boundary::Bounds,
    /// The polygon's own colour, linear (XGL's intrinsic colour): shown
    /// outside the bounds under [`boundary::Boundary::Transparent`].
    pub intrinsic: [f64; 3],
    /// The constant colour of [`boundary::Boundary::Clamp`], linear.
    pub constant: [f64; 3],
    /// How texels combine with `intrinsic` (default: replace).
    pub compose: compose::Compose,
    /// The composition's constant colours (XGL's `op` colours), linear.
    pub compose_colors: [[f64; 3]; 2],
    /// The filters (default: the exact box filter everywhere).
    pub filters: filter::Filters,
    /// Which work-saving skips are on (all but for benchmarks).
    pub skips: skip::Skips,
}

impl PolyTexture {
    /// The least and greatest linear value of each channel over the colours
    /// this texture can show (composition applied, transparent texels left
    /// out; the intrinsic and constant colours too unless both axes
    /// repeat), or `None` when it shows none. Any box average of it lies
    /// within. O(texels): for bounds and reports, not for rendering.
    pub fn colour_range(&self) -> Option<([f64; 3], [f64; 3])> {
        use boundary::Boundary;
        let (w, h) = (self.texels.width() as i64, self.texels.height() as i64);
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        let repeats = self.bounds.u == Boundary::Repeat && self.bounds.v == Boundary::Repeat;
        let edges = (!repeats).then_some([Some(self.intrinsic), Some(self.constant)]);
        let texels = (0..h).flat_map(|j| (0..w).map(move |k| (k, j)));
        let shown = texels
            .map(|(k, j)| self.texel(k, j))
            .chain(edges.into_iter().flatten());
        for c in shown.flatten() {
            for ch in 0..3 {
                lo[ch] = lo[ch].min(c[ch]);
                hi[ch] = hi[ch].max(c[ch]);
            }
        }
        (lo[0] <= hi[0]).then_some((lo, hi))
    }

    /// The largest channel difference between two colours of
    /// [`PolyTexture::colour_range`], linear: how far any estimate of a box
    /// average within that range can be from the exact one.
    pub fn contrast_linear(&self) -> f64 {
        self.colour_range().map_or(0.0, |(lo, hi)| {
            (0..3).map(|ch| hi[ch] - lo[ch]).fold(0.0, f64::max)
        })
    }

    /// [`PolyTexture::contrast_linear`] in 8-bit sRGB codes: the bound
    /// `scene-render` reports for fragments over more than
    /// [`cells::MAX_EXACT_CELLS`] cells, which take the EWA estimate.
    pub fn contrast_codes(&self) -> u32 {
        let encode = |c: [f64; 3]| Rgb8::from_linear(c.map(|l| l as f32));
        self.colour_range()
            .map_or(0, |(lo, hi)| encode(lo).code_distance(encode(hi)))
    }

    /// What decides the colours this texture shows, all but its map:
    /// polygons that share it share [`PolyTexture::colour_range`].
    pub fn appearance(&self) -> Appearance {
        let bits = |c: [f64; 3]| c.map(f64::to_bits);
        Appearance {
            texels: Arc::as_ptr(&self.texels) as usize,
            intrinsic: bits(self.intrinsic),
            constant: bits(self.constant),
            compose_colors: self.compose_colors.map(bits),
            compose: self.compose,
            bounds: self.bounds,
        }
    }

    /// Linear colour of texel cell (k, j) of the placement, after the
    /// boundary conditions; `None` where the pattern's texel is transparent.
    /// A texel with partial alpha is shown over the polygon's colour, then
    /// composed ([`Texels::texel_over`]).
    #[inline]
    pub fn texel(&self, k: i64, j: i64) -> Option<[f64; 3]> {
        let (w, h) = (self.texels.width(), self.texels.height());
        match self.bounds.lookup(k, j, w, h) {
            boundary::Lookup::Texel(c, r) => self.compose.apply(
                self.texels.texel_over(c, r, self.intrinsic),
                self.intrinsic,
                self.compose_colors[0],
                self.compose_colors[1],
            ),
            boundary::Lookup::Intrinsic => Some(self.intrinsic),
            boundary::Lookup::Constant => Some(self.constant),
        }
    }
}

/// A texture's colours without its map ([`PolyTexture::appearance`]): a key
/// to compute [`PolyTexture::colour_range`] once per scene, not per polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Appearance {
    texels: usize,
    intrinsic: [u64; 3],
    constant: [u64; 3],
    compose_colors: [[u64; 3]; 2],
    compose: compose::Compose,
    bounds: boundary::Bounds,
}

/// How a pattern is laid over the screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScreenTiling {
    /// Each texel covers `scale` x `scale` pixels. Default value: 1.
    pub scale: u32,
    /// The texel shown at the image's lower-left pixel. Default value: (0, 0).
    pub offset: (i64, i64),
}

impl ScreenTiling {
    /// One pixel per texel, texel (0, 0) at the lower-left pixel: the IRIS
    /// hardware pattern.
    pub const DEFAULT: ScreenTiling = ScreenTiling {
        scale: 1,
        offset: (0, 0),
    };

    /// Texel index (column or row) of pixel coordinate `p` counted from the
    /// left or bottom edge.
    ///
    /// The offset is reduced modulo the pattern size before it is added:
    /// an offset near `i64::MAX` plus the texel count overflowed (wrapping
    /// in a release build, to the wrong texels). Any offset now shows the
    /// texels of its residue, and the others the same texels as before.
    #[inline]
    fn texel(&self, p: u32, offset: i64, size: u32) -> u32 {
        let size = size as i64;
        ((p / self.scale.max(1)) as i64 + offset.rem_euclid(size)).rem_euclid(size) as u32
    }
}

impl Default for ScreenTiling {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Fills a `width` x `height` image with the repeated pattern: the rows of
/// [`TileRows`], held together.
///
/// Transparent texels take `background`; with no background the image gets an
/// alpha channel (only if the pattern has transparent texels) and they stay
/// transparent.
pub fn tile_image(
    pattern: &Pattern,
    width: u32,
    height: u32,
    tiling: ScreenTiling,
    background: Option<Rgb8>,
) -> Image {
    use crate::io::RowSource;
    let mut rows = TileRows::new(pattern, width, height, tiling, background);
    let channels = rows.shape().2;
    let mut data = Vec::with_capacity(width as usize * height as usize * channels as usize);
    for y in 0..height {
        data.extend_from_slice(rows.row(y));
    }
    Image {
        width,
        height,
        channels,
        data,
    }
}

/// The rows of a `width` x `height` image filled with the repeated pattern,
/// made one at a time ([`crate::io::RowSource`]), so that `pat-tile` writes
/// any size in the memory of one row: 16384x16384 of a pattern with
/// transparent texels peaked at 1.06 GB held whole (`bench/memory.sh`).
///
/// Each row costs one pass over its bytes: a texel row is built as a full
/// image row once (one period, then doubled by copying), and the image rows
/// that show the same texel row, one after another, reuse it.
pub struct TileRows<'a> {
    pattern: &'a Pattern,
    tiling: ScreenTiling,
    /// The colour of each texel index, and of [`crate::pat::TRANSPARENT`]
    /// (last): `background`, or no colour and no coverage.
    colours: Vec<[u8; 4]>,
    channels: u8,
    width: u32,
    height: u32,
    /// The image row last built and the texel row it shows.
    row: Vec<u8>,
    texel_row: Option<u32>,
}

impl<'a> TileRows<'a> {
    /// The rows of the image [`tile_image`] makes with these arguments.
    pub fn new(
        pattern: &'a Pattern,
        width: u32,
        height: u32,
        tiling: ScreenTiling,
        background: Option<Rgb8>,
    ) -> TileRows<'a> {
        let has_transparency = pattern.histogram().1 > 0;
        let channels = if has_transparency && background.is_none() {
            4
        } else {
            3
        };
        let clear = match background {
            Some(b) => [b.0[0], b.0[1], b.0[2], 255],
            None => [0, 0, 0, 0],
        };
        let colours = pattern
            .palette()
            .iter()
            .map(|c| [c.0[0], c.0[1], c.0[2], 255])
            .chain([clear])
            .collect();
        TileRows {
            pattern,
            tiling,
            colours,
            channels,
            width,
            height,
            row: vec![0; width as usize * channels as usize],
            texel_row: None,
        }
    }
}

impl crate::io::RowSource for TileRows<'_> {
    fn shape(&self) -> (u32, u32, u8) {
        (self.width, self.height, self.channels)
    }

    fn row(&mut self, y: u32) -> &[u8] {
        let size = self.pattern.size();
        let from_bottom = self.height - 1 - y;
        let trow = self.tiling.texel(from_bottom, self.tiling.offset.1, size);
        if self.texel_row == Some(trow) {
            return &self.row;
        }
        let texels = &self.pattern.texels()[(trow * size) as usize..((trow + 1) * size) as usize];
        let channels = self.channels as usize;
        let transparent = self.colours.len() - 1;
        // One period: SIZE * scale pixels (or the whole row if shorter).
        let period = (size as usize * self.tiling.scale.max(1) as usize).min(self.width as usize);
        for (x, px) in self.row[..period * channels]
            .chunks_exact_mut(channels)
            .enumerate()
        {
            let t = texels[self.tiling.texel(x as u32, self.tiling.offset.0, size) as usize];
            let colour = self
                .colours
                .get(t as usize)
                .unwrap_or(&self.colours[transparent]);
            px.copy_from_slice(&colour[..channels]);
        }
        // Double the filled prefix until the row is full.
        let row_bytes = self.row.len();
        let mut filled = period * channels;
        while filled < row_bytes {
            let n = filled.min(row_bytes - filled);
            self.row.copy_within(0..n, filled);
            filled += n;
        }
        self.texel_row = Some(trow);
        &self.row
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pat::TRANSPARENT;

    /// 16x16: texel (c, r) has colour index (c + 16 r) % 3, except (1,0) transparent.
    fn pattern() -> Pattern {
        let mut t: Vec<u16> = (0..256).map(|i| (i % 3) as u16).collect();
        t[1] = TRANSPARENT;
        Pattern::new(
            16,
            vec![Rgb8([255, 0, 0]), Rgb8([0, 255, 0]), Rgb8([0, 0, 255])],
            t,
        )
        .unwrap()
    }

    /// The direct formula, pixel by pixel: the slow route the fast one must match.
    fn direct(p: &Pattern, w: u32, h: u32, t: ScreenTiling, bg: Rgb8) -> Vec<u8> {
        let mut out = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let py = h - 1 - y;
                let c = p
                    .color_wrapped(
                        (x / t.scale) as i64 + t.offset.0,
                        (py / t.scale) as i64 + t.offset.1,
                    )
                    .unwrap_or(bg);
                out.extend_from_slice(&c.0);
            }
        }
        out
    }

    #[test]
    fn fast_tiling_matches_the_direct_formula() {
        let p = pattern();
        for (w, h, scale, off) in [
            (1, 1, 1, (0, 0)),
            (37, 29, 1, (0, 0)),
            (100, 70, 3, (5, -7)),
            (16, 16, 1, (-1, 100)),
            (5, 300, 20, (0, 0)),
        ] {
            let t = ScreenTiling { scale, offset: off };
            let bg = Rgb8([9, 9, 9]);
            let img = tile_image(&p, w, h, t, Some(bg));
            assert_eq!(img.channels, 3);
            assert_eq!(
                img.data,
                direct(&p, w, h, t, bg),
                "{w}x{h} scale {scale} {off:?}"
            );
        }
    }

    /// An offset near `i64::MAX` or `i64::MIN` shows the texels of its
    /// residue modulo the size: adding it to the texel count overflowed
    /// (wrong texels in a release build, a panic in a debug one).
    #[test]
    fn extreme_offsets_show_the_texels_of_their_residue() {
        // 48 texels, not a power of two (whose residues a wrap keeps), and
        // colours of period 5 along both axes.
        let palette = (0..5).map(|i| Rgb8([i * 50, 0, 0])).collect();
        let texels = (0..48 * 48).map(|i| ((i % 48 + 2 * (i / 48)) % 5) as u16);
        let p = Pattern::new(48, palette, texels.collect()).unwrap();
        for off in [
            (i64::MAX, i64::MIN),
            (i64::MIN, i64::MAX),
            (i64::MAX - 3, 1),
        ] {
            let residue = (off.0.rem_euclid(48), off.1.rem_euclid(48));
            for scale in [1, 3] {
                let t = |offset| ScreenTiling { scale, offset };
                assert_eq!(
                    tile_image(&p, 100, 70, t(off), None).data,
                    tile_image(&p, 100, 70, t(residue), None).data,
                    "{off:?} scale {scale}"
                );
            }
        }
    }

    #[test]
    fn row_0_of_the_pattern_is_the_bottom_of_the_image() {
        let p = pattern();
        let img = tile_image(&p, 16, 16, ScreenTiling::DEFAULT, None);
        assert_eq!(img.channels, 4);
        let px = |x: usize, y: usize| &img.data[(y * 16 + x) * 4..(y * 16 + x) * 4 + 4];
        // Bottom-left pixel (image row 15) is texel (0,0): index 0, red.
        assert_eq!(px(0, 15), &[255, 0, 0, 255]);
        // Texel (1,0) is transparent.
        assert_eq!(px(1, 15), &[0, 0, 0, 0]);
        // Top-left pixel is texel (0,15): index 240 % 3 = 0.
        assert_eq!(px(0, 0), &[255, 0, 0, 255]);
        // Texel (2,1): (2 + 16) % 3 = 0, red; texel (3,1): 19 % 3 = 1, green.
        assert_eq!(px(2, 14), &[255, 0, 0, 255]);
        assert_eq!(px(3, 14), &[0, 255, 0, 255]);
    }
}
