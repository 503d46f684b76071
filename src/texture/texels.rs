//! The texel store: a pattern or an image decoded for sampling.
//!
//! Texels are kept as the file's sRGB codes (8 or 16 bits a channel, with
//! alpha) and decoded through a lookup table built with
//! [`srgb_to_linear_f64`], the same expression that decoded every texel to
//! f64 up front before: the linear values (and so the output bytes) are the
//! same, at 4 or 8 bytes a texel instead of 32, so a 4096 x 4096 photograph
//! costs 64 MB (docs/rendering.md, "Image textures").

use super::mip::{Extend, MipBuild, MipKey};
use crate::color::srgb_to_linear_f64;
use crate::io::RgbaPixels;
use crate::pat::Pattern;
use std::path::Path;
use std::sync::OnceLock;

/// Alpha below this (of 1) is a transparent texel, like a `.pat`'s
/// transparent texel; at or above it the texel is shown, composed over the
/// polygon's colour by its alpha ([`Texels::texel_over`]). One half, as
/// the filters' alpha test ([`super::filter::ALPHA_TEST`]).
pub const ALPHA_CUTOFF: f64 = 0.5;

/// The most texels an image texture may have: as many as the largest
/// `.pat` (4096 x 4096, [`crate::pat::MAX_SIZE`]), in any aspect ratio. It
/// bounds the store (64 MB at 8 bits, 128 MB at 16) and its MIP pyramids.
pub const MAX_TEXELS: u64 = (crate::pat::MAX_SIZE as u64) * (crate::pat::MAX_SIZE as u64);

/// The texels' sRGB codes, straight (not premultiplied) RGBA, row-major,
/// row 0 at the bottom. A texel whose alpha is below [`ALPHA_CUTOFF`] is
/// stored as all zeros.
#[derive(Clone, Debug, PartialEq)]
enum Codes {
    /// 8 bits a channel: `.pat` colours and 8-bit images.
    Srgb8(Vec<u8>),
    /// 16 bits a channel: 16-bit images.
    Srgb16(Vec<u16>),
}

/// The linear value of each 8-bit sRGB code.
fn lut8() -> &'static [f64; 256] {
    crate::color::decode_table_f64()
}

/// The linear value of each 16-bit sRGB code (built only when a 16-bit image
/// is loaded: 512 KB).
fn lut16() -> &'static [f64] {
    static LUT: OnceLock<Vec<f64>> = OnceLock::new();
    LUT.get_or_init(|| {
        (0..=u16::MAX as u32)
            .map(|c| srgb_to_linear_f64(c as f64 / 65535.0))
            .collect()
    })
}

/// A texel shown over `under` by its alpha `a` (XGL's intrinsic colour,
/// OpenGL's `GL_DECAL`: `C = Cp (1 - A) + Ct A`), in linear light.
#[inline]
fn over(t: [f64; 3], a: f64, under: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| under[i] * (1.0 - a) + t[i] * a)
}

/// A pattern's or image's texels, decoded to linear light on access, with
/// what every filter shares: the opaque runs of its rows and its MIP
/// pyramids. One store serves every placement (screen, object, uv) and
/// every polygon that uses the file, so each file is decoded once per run.
#[derive(Debug)]
pub struct Texels {
    width: u32,
    height: u32,
    codes: Codes,
    /// Whether any texel is transparent, found once (resolvers ask per
    /// fragment).
    transparent: bool,
    /// Whether any shown texel has alpha below 1 (only images): its
    /// pyramids then carry the coverage channel ([`super::mip::Level`]).
    partial: bool,
    /// The opaque runs of each texel row, found once for the box filter's
    /// transparent-run skip ([`crate::texture::skip`]).
    runs: super::skip::OpaqueRuns,
    /// Its MIP pyramids, built on first use, one per [`MipKey`] (18 keys:
    /// 2 builds x 3 x 3 edge extensions), shared by every polygon that
    /// holds this pattern.
    pyramids: [OnceLock<super::mip::Pyramid>; MIP_KEYS],
}

impl PartialEq for Texels {
    /// The same texels (pyramids are derived from them).
    fn eq(&self, o: &Texels) -> bool {
        (self.width, self.height) == (o.width, o.height) && self.codes == o.codes
    }
}

impl Clone for Texels {
    fn clone(&self) -> Texels {
        Texels::with_codes(self.width, self.height, self.codes.clone())
    }
}

/// The number of distinct [`MipKey`]s.
const MIP_KEYS: usize = 18;

fn mip_key_index(k: MipKey) -> usize {
    let e = |x: Extend| match x {
        Extend::Repeat => 0,
        Extend::Mirror => 1,
        Extend::Edge => 2,
    };
    (k.build == MipBuild::Mitchell) as usize * 9 + e(k.u) * 3 + e(k.v)
}

/// Why a texture file cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// Not an image, and not a valid `.pat` (or unreadable).
    #[error(transparent)]
    Pattern(#[from] crate::text::ParseError),
    /// An image that cannot be decoded, or is too large
    /// ([`MAX_TEXELS`]).
    #[error(transparent)]
    Image(#[from] crate::io::IoError),
}

/// An opened texture: an image, read whole by `read_whole` (which gives the
/// read's errors) and decoded; or else a `.pat`, read as a stream (it may be
/// larger than a file read whole may be). An image never starts with
/// whitespace, and the stream's errors are those of [`Pattern::parse`];
/// reading whole what did not start as a pattern in its first 4096 bytes
/// took 256 MiB before refusing `yes ' ' | scene-render
/// --background-pattern - ...`.
fn from_opened(
    opened: crate::io::Opened,
    name: &str,
    read_whole: impl FnOnce(crate::io::Opened) -> Result<Vec<u8>, LoadError>,
) -> Result<Texels, LoadError> {
    if crate::io::is_image(&opened.start) {
        return Texels::parse(&read_whole(opened)?, name);
    }
    Ok(Texels::new(&Pattern::read_from(
        &mut opened.into_reader(),
        name,
    )?))
}

impl Texels {
    /// The texels of `p` (docs/pat-format.md: row 0 at the bottom), each an sRGB
    /// colour or transparent.
    pub fn new(p: &Pattern) -> Texels {
        let size = p.size();
        let mut codes = Vec::with_capacity(4 * (size * size) as usize);
        for row in 0..size {
            for col in 0..size {
                codes.extend_from_slice(&match p.color_at(col, row) {
                    Some(c) => [c.0[0], c.0[1], c.0[2], 255],
                    None => [0; 4],
                });
            }
        }
        Texels::with_codes(size, size, Codes::Srgb8(codes))
    }

    /// Reads a texture file: an image (any format the `image` crate reads,
    /// told by its content, not its name) or else a `.pat` (docs/pat-format.md).
    /// Errors name the file; an image of more than [`MAX_TEXELS`] pixels is
    /// refused before it is decoded.
    pub fn read_file(path: &Path) -> Result<Texels, LoadError> {
        let name = path.display().to_string();
        let io_error = |e| crate::text::ParseError::io(&name, e);
        let opened = crate::io::open_path(path).map_err(io_error)?;
        from_opened(opened, &name, |o| Ok(o.read_all().map_err(io_error)?))
    }

    /// [`Texels::read_file`] of an input named on the command line (`-`
    /// for standard input), with [`crate::io::read_input`]'s errors.
    pub fn read_input(file: &str) -> Result<Texels, LoadError> {
        let name = crate::io::display_name(file);
        let opened = crate::io::open_input(file, crate::io::InputKind::TextOrImage)?;
        from_opened(opened, name, |o| Ok(o.read_input()?))
    }

    /// [`Texels::read_file`] of bytes already read; `name` is used in
    /// errors.
    pub fn parse(bytes: &[u8], name: &str) -> Result<Texels, LoadError> {
        if crate::io::is_image(bytes) {
            let (w, h, px) = crate::io::decode_texture(bytes, name, MAX_TEXELS)?;
            Ok(Texels::from_image(w, h, px))
        } else {
            Ok(Texels::new(&Pattern::parse(bytes, name)?))
        }
    }

    /// The texels of a `width` x `height` image whose row 0 is the top (as
    /// image files store it): the image's BOTTOM row becomes texel row 0, so
    /// the picture stands upright where a `.pat` drawn from it would
    /// (`pat-tile` writes a pattern's row 0 as the image's bottom row).
    /// Alpha below [`ALPHA_CUTOFF`] is a transparent texel.
    ///
    /// # Panics
    /// If `pixels` does not hold `4 * width * height` channels.
    pub fn from_image(width: u32, height: u32, pixels: RgbaPixels) -> Texels {
        let row = 4 * width as usize;
        let n = row * height as usize;
        fn flip<T: Copy>(v: &mut [T], row: usize) {
            let rows = v.len() / row.max(1);
            for r in 0..rows / 2 {
                let (top, bottom) = v.split_at_mut((rows - 1 - r) * row);
                top[r * row..(r + 1) * row].swap_with_slice(&mut bottom[..row]);
            }
        }
        fn cut<T: Copy + Default + Into<f64>>(v: &mut [T], max: f64) {
            for px in v.chunks_exact_mut(4) {
                if px[3].into() < ALPHA_CUTOFF * max {
                    px.fill(T::default());
                }
            }
        }
        let codes = match pixels {
            RgbaPixels::Rgba8(mut v) => {
                assert_eq!(v.len(), n, "RGBA8 pixels of a {width}x{height} image");
                flip(&mut v, row);
                cut(&mut v, 255.0);
                Codes::Srgb8(v)
            }
            RgbaPixels::Rgba16(mut v) => {
                assert_eq!(v.len(), n, "RGBA16 pixels of a {width}x{height} image");
                flip(&mut v, row);
                cut(&mut v, 65535.0);
                Codes::Srgb16(v)
            }
        };
        Texels::with_codes(width, height, codes)
    }

    fn with_codes(width: u32, height: u32, codes: Codes) -> Texels {
        let (transparent, partial) = match &codes {
            Codes::Srgb8(v) => (
                v.chunks_exact(4).any(|p| p[3] == 0),
                v.chunks_exact(4).any(|p| p[3] != 0 && p[3] != u8::MAX),
            ),
            Codes::Srgb16(v) => (
                v.chunks_exact(4).any(|p| p[3] == 0),
                v.chunks_exact(4).any(|p| p[3] != 0 && p[3] != u16::MAX),
            ),
        };
        let mut t = Texels {
            width,
            height,
            codes,
            transparent,
            partial,
            runs: super::skip::OpaqueRuns::default(),
            pyramids: std::array::from_fn(|_| OnceLock::new()),
        };
        t.runs = super::skip::OpaqueRuns::new(width, height, |c, r| t.alpha(t.index(c, r)) > 0.0);
        t
    }

    #[inline]
    fn index(&self, c: u32, r: u32) -> usize {
        r as usize * self.width as usize + c as usize
    }

    /// The alpha of texel `i`, 0 for a transparent one.
    #[inline]
    fn alpha(&self, i: usize) -> f64 {
        match &self.codes {
            Codes::Srgb8(v) => match v[4 * i + 3] {
                u8::MAX => 1.0,
                a => a as f64 / 255.0,
            },
            Codes::Srgb16(v) => match v[4 * i + 3] {
                u16::MAX => 1.0,
                a => a as f64 / 65535.0,
            },
        }
    }

    /// The linear colour (straight) and alpha of texel `i`; alpha 0 is
    /// transparent.
    #[inline]
    fn linear(&self, i: usize) -> ([f64; 3], f64) {
        match &self.codes {
            Codes::Srgb8(v) => {
                let (p, lut) = (&v[4 * i..4 * i + 4], lut8());
                let a = match p[3] {
                    u8::MAX => 1.0,
                    a => a as f64 / 255.0,
                };
                (
                    [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]],
                    a,
                )
            }
            Codes::Srgb16(v) => {
                let (p, lut) = (&v[4 * i..4 * i + 4], lut16());
                let a = match p[3] {
                    u16::MAX => 1.0,
                    a => a as f64 / 65535.0,
                };
                (
                    [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]],
                    a,
                )
            }
        }
    }

    /// Linear colour of texel (c, r), `c < width`, `r < height`, shown over
    /// the colour `under` (the polygon's own, linear) by its alpha; `None`
    /// where it is transparent. Opaque texels (every shown `.pat` texel)
    /// are their own colour.
    #[inline]
    pub fn texel_over(&self, c: u32, r: u32, under: [f64; 3]) -> Option<[f64; 3]> {
        let (t, a) = self.linear(self.index(c, r));
        if a == 1.0 {
            Some(t)
        } else if a == 0.0 {
            None
        } else {
            Some(over(t, a, under))
        }
    }

    /// [`Texels::texel_over`] as premultiplied linear RGBA (a shown texel is
    /// opaque).
    #[inline]
    pub fn premultiplied(&self, c: u32, r: u32, under: [f64; 3]) -> [f64; 4] {
        match self.texel_over(c, r, under) {
            Some(t) => [t[0], t[1], t[2], 1.0],
            None => [0.0; 4],
        }
    }

    /// The MIP pyramid built with `key`: built by the first caller (others
    /// wait for it), then shared.
    pub fn pyramid(&self, key: MipKey) -> &super::mip::Pyramid {
        self.pyramids[mip_key_index(key)].get_or_init(|| {
            let (w, h) = (self.width, self.height);
            if self.partial {
                // Premultiplied colour and alpha, and the coverage (1 where
                // shown): filtered, coverage minus alpha is the weight of
                // the polygon's colour under the texel.
                super::mip::build::<5>(
                    |c, r| {
                        let (t, a) = self.linear(self.index(c, r));
                        let v = if a > 0.0 { 1.0 } else { 0.0 };
                        [t[0] * a, t[1] * a, t[2] * a, a, v]
                    },
                    w,
                    h,
                    key,
                )
            } else {
                super::mip::build::<4>(|c, r| self.premultiplied(c, r, [0.0; 3]), w, h, key)
            }
        })
    }

    /// Linear colour of pixel (x, y) counted from the lower-left in screen
    /// mode (column `x mod width`, row `y mod height`, docs/stream-format.md), shown over
    /// `under`; `None` where transparent.
    #[inline]
    pub fn at_over(&self, x: u32, y: u32, under: [f64; 3]) -> Option<[f64; 3]> {
        self.texel_over(x % self.width, y % self.height, under)
    }

    /// Linear colour of texel cell (k, j) of the infinite tiling: column
    /// `k mod width`, row `j mod height` (docs/stream-format.md), over `under`; `None` is
    /// transparent.
    #[inline]
    pub fn texel(&self, k: i64, j: i64, under: [f64; 3]) -> Option<[f64; 3]> {
        self.texel_over(
            k.rem_euclid(self.width as i64) as u32,
            j.rem_euclid(self.height as i64) as u32,
            under,
        )
    }

    /// Width of the store in texels (columns; a `.pat`'s side).
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height of the store in texels (rows; a `.pat`'s side).
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Whether any texel is transparent (the pattern has an alpha channel).
    pub fn has_transparency(&self) -> bool {
        self.transparent
    }

    /// Whether any texel has alpha: transparent, or shown with alpha below
    /// 1 (XGL's "four-channel map", what the decal compositions need).
    pub fn has_alpha(&self) -> bool {
        self.transparent || self.partial
    }

    /// The opaque runs of each texel row.
    pub fn runs(&self) -> &super::skip::OpaqueRuns {
        &self.runs
    }

    /// Bytes held by the texel codes (not counting pyramids).
    pub fn code_bytes(&self) -> usize {
        match &self.codes {
            Codes::Srgb8(v) => v.len(),
            Codes::Srgb16(v) => 2 * v.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_rows_are_flipped_and_low_alpha_is_transparent() {
        // 2x2, top row: red opaque, green alpha 100 (transparent); bottom
        // row: blue opaque, white alpha 200.
        let px = vec![
            255, 0, 0, 255, 0, 255, 0, 100, //
            0, 0, 255, 255, 255, 255, 255, 200,
        ];
        let t = Texels::from_image(2, 2, RgbaPixels::Rgba8(px));
        let under = [0.0; 3];
        assert_eq!(t.texel_over(0, 0, under), Some([0.0, 0.0, 1.0]));
        assert_eq!(t.texel_over(0, 1, under), Some([1.0, 0.0, 0.0]));
        assert_eq!(t.texel_over(1, 1, under), None);
        let w = t.texel_over(1, 0, [0.0, 0.0, 0.0]).unwrap();
        assert!((w[0] - 200.0 / 255.0).abs() < 1e-15, "{w:?}");
        assert!(t.has_transparency() && t.has_alpha());
    }

    #[test]
    fn the_lookup_tables_decode_like_the_formula() {
        for c in 0..=255u32 {
            assert_eq!(lut8()[c as usize], srgb_to_linear_f64(c as f64 / 255.0));
        }
        for c in (0..=65535u32).step_by(257) {
            assert_eq!(lut16()[c as usize], lut8()[(c / 257) as usize]);
        }
    }

    #[test]
    fn a_16_bit_image_keeps_its_precision() {
        let t = Texels::from_image(1, 1, RgbaPixels::Rgba16(vec![1, 2, 3, 65535]));
        let c = t.texel_over(0, 0, [0.0; 3]).unwrap();
        assert_eq!(c[0], srgb_to_linear_f64(1.0 / 65535.0));
        assert!(c[0] > 0.0 && c[0] < lut8()[1]);
        assert_eq!(t.code_bytes(), 8);
    }

    #[test]
    fn partial_alpha_lies_over_the_polygon_at_every_mip_level() {
        // 4x4 blue at alpha 191: every level shows blue over the polygon's
        // green by that alpha, opaque.
        let t = Texels::from_image(4, 4, RgbaPixels::Rgba8([0, 0, 255, 191].repeat(16)));
        let a = 191.0 / 255.0;
        let green = [0.0, 1.0, 0.0];
        let key = MipKey {
            build: MipBuild::Mitchell,
            u: Extend::Repeat,
            v: Extend::Repeat,
        };
        assert_eq!(t.premultiplied(0, 0, green), [0.0, 1.0 - a, a, 1.0]);
        for l in &t.pyramid(key).levels {
            let p = l.at_over(0, 0, green);
            for (got, want) in p.iter().zip([0.0, 1.0 - a, a, 1.0]) {
                assert!((got - want).abs() < 1e-6, "{}x{}: {p:?}", l.width, l.height);
            }
        }
    }
}
