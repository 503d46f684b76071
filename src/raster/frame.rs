//! The two ends of a resolver: what lies behind every polygon
//! ([`Background`]) and the pixels it fills, tile by tile
//! ([`render_bands`]): kept as linear light in a [`Frame`] and encoded to
//! 8-bit sRGB once, rounding, by [`Frame::to_image`] (16-bit sRGB by
//! [`Frame::to_image16`], kept linear by [`Frame::to_linear_image`]), or
//! encoded the same way as each tile is done (`super::render_encoded`).

use crate::color::{linear_to_srgb, linear_to_srgb16, Rgb8};
use crate::io::{AnyImage, Encoding, Image, Image16, LinearImage};
use crate::texture::Texels;

/// What lies behind every polygon: a colour, or the thesis's `colorclear`
/// pattern tiled in screen mode (pixel (x, y) from the lower-left takes texel
/// (x mod SIZE, y mod SIZE); transparent texels show the colour).
#[derive(Clone, Debug)]
pub struct Background {
    /// Linear light of the colour, decoded once (it is read for every pixel
    /// not fully covered).
    color: [f64; 3],
    pattern: Option<Texels>,
    /// No colour: where polygons leave a pixel uncovered it is transparent
    /// ([`Background::transparent`]).
    transparent: bool,
}

impl Background {
    /// A plain colour (8-bit sRGB) behind every pixel, no pattern.
    pub fn color(color: Rgb8) -> Background {
        Background::new(color, None)
    }

    /// A colour, with a pattern (or image, [`Texels::read_file`]) tiled over
    /// it in screen mode.
    pub fn new(color: Rgb8, pattern: Option<Texels>) -> Background {
        Background {
            color: color.to_linear_f64(),
            pattern,
            transparent: false,
        }
    }

    /// Nothing behind the polygons but the pattern's opaque texels, if a
    /// pattern is given: uncovered parts of a pixel are transparent, and the
    /// image carries alpha (`scene-render --background none`).
    ///
    /// A resolver draws the frame twice, over black and over white
    /// ([`Background::opaque`]), and [`Frame::to_image_with_alpha`] reads the
    /// coverage from the difference: exact for every resolver, since both
    /// passes cut and sample the same geometry, at the cost of a second pass
    /// (1.6x the whole process's time on 10,000 random triangles in one run,
    /// bench/RESULTS-same-images.md).
    pub fn transparent(pattern: Option<Texels>) -> Background {
        Background {
            transparent: true,
            ..Background::new(Rgb8::BLACK, pattern)
        }
    }

    /// Whether uncovered pixels are transparent.
    pub fn is_transparent(&self) -> bool {
        self.transparent
    }

    /// This background with `color` behind the pattern and nothing
    /// transparent: one pass of a transparent frame.
    pub fn opaque(&self, color: Rgb8) -> Background {
        Background {
            color: color.to_linear_f64(),
            pattern: self.pattern.clone(),
            transparent: false,
        }
    }

    /// The linear-light colour behind every pixel, if no pattern varies it:
    /// what a tile no polygon reaches shows in each of its pixels.
    pub(crate) fn plain(&self) -> Option<[f64; 3]> {
        self.pattern.is_none().then_some(self.color)
    }

    /// Linear-light colour of pixel (x, y), y counted from the bottom.
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> [f64; 3] {
        match &self.pattern {
            Some(p) => p.at_over(x, y, self.color).unwrap_or(self.color),
            None => self.color,
        }
    }
}

/// A frame of linear-light pixels, rows from the bottom (y up).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB, `(y * width + x)`, y from the bottom.
    pub pixels: Vec<[f32; 3]>,
    /// Textured fragments (a polygon's part of a pixel) whose colour `--aa
    /// exact` estimated instead of integrating: more than
    /// `texture::cells::MAX_EXACT_CELLS` texel cells under them, or beyond a
    /// plane's horizon. 0 for the other resolvers, which estimate
    /// everywhere.
    pub estimated: u64,
}

/// Copies tile `t`'s row-major `block` into `band`, the frame's rows
/// (`w` pixels wide, starting at the tile's first row).
fn copy_block(band: &mut [[f32; 3]], w: usize, t: [u32; 4], block: &[[f32; 3]]) {
    let tw = (t[2] - t[0]) as usize;
    for (r, row) in block.chunks_exact(tw).enumerate() {
        let start = r * w + t[0] as usize;
        band[start..start + tw].copy_from_slice(row);
    }
}

/// A tile's pixels as a resolver gives them to [`render_bands`]: linear
/// light, or (over a transparent background) the pair of a pixel's linear
/// light over black and over white.
pub(crate) enum Block<T = [f32; 3]> {
    /// Row-major, a value a pixel.
    Pixels(Vec<T>),
    /// The same linear light in every pixel: a tile that no polygon
    /// reaches, over a plain background. Encoded once and copied: resolving
    /// and encoding such tiles pixel by pixel was most of the render phase
    /// of a large frame with little drawn in it (`bench/large_frame.sh`:
    /// 10,000 triangles in the corner of a 16384x16384 frame, render phase
    /// 3.03 s before, 0.43 after). The tile's colour is the resolver's own
    /// for a pixel of background only (test
    /// `empty_tiles_filled_at_once_are_the_resolvers_own_pixels`).
    Flat(T),
}

impl<T: Copy> Block<T> {
    /// The pixels of two passes over a tile of `n` pixels, paired.
    pub(crate) fn zip<U: Copy>(self, other: Block<U>, n: usize) -> Block<(T, U)> {
        let pixels = |b: Block<T>| match b {
            Block::Pixels(v) => v,
            Block::Flat(p) => vec![p; n],
        };
        match (self, other) {
            (Block::Flat(a), Block::Flat(b)) => Block::Flat((a, b)),
            (a, Block::Pixels(b)) => Block::Pixels(pixels(a).into_iter().zip(b).collect()),
            (a, Block::Flat(b)) => Block::Pixels(pixels(a).into_iter().map(|a| (a, b)).collect()),
        }
    }
}

/// The order of the rows of pixels in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowOrder {
    /// From the bottom, y up: a [`Frame`]'s order.
    BottomFirst,
    /// From the top: an image's order.
    TopFirst,
}

/// Renders a frame tile by tile in parallel, each pixel stored as
/// `encode` gives it: `render(i)` gives tile `i` of `tiles` (as
/// [`super::tiles`] lists them) as a [`Block`] of linear-light pixels,
/// which is encoded into its band of the output at once and dropped, so the
/// next tile's block reuses its memory. Rows are stored in `order`.
///
/// Encoding as the tiles come, rather than after a whole [`Frame`] of
/// linear f32 is held, keeps a render at the output's own size: 3 bytes a
/// pixel for 8-bit sRGB instead of 12 more for the frame. (Holding every
/// block until the end, then copying them, faulted in a second frame's
/// worth of fresh pages: the part of a 2048x2048 textured render that did
/// not scale with threads.) Each band is locked only while a block is
/// encoded into it.
pub(crate) fn render_bands<T: Copy, P: Copy + Default + Send>(
    (width, height): (u32, u32),
    tiles: &[[u32; 4]],
    order: RowOrder,
    render: impl Fn(usize) -> Block<T> + Sync,
    encode: impl Fn(T) -> P + Sync,
) -> Vec<P> {
    use rayon::prelude::*;
    use std::sync::Mutex;
    let (w, h, tile) = (width as usize, height as usize, super::TILE as usize);
    let mut pixels = vec![P::default(); w * h];
    if w == 0 || h == 0 {
        return pixels;
    }
    // Band k holds the rows y of tile row k, kT <= y < min((k + 1)T, h).
    let top_first = order == RowOrder::TopFirst;
    let bands: Vec<Mutex<&mut [P]>> = if top_first {
        // From the top: the last band, partial, then the full ones down.
        let last = (h - 1) / tile;
        let (top, rest) = pixels.split_at_mut((h - last * tile) * w);
        let mut bands: Vec<_> = std::iter::once(top)
            .chain(rest.chunks_mut(tile * w))
            .map(Mutex::new)
            .collect();
        bands.reverse();
        bands
    } else {
        pixels.chunks_mut(tile * w).map(Mutex::new).collect()
    };
    // One tile per job: rayon otherwise splits the range into a few
    // chunks per thread up front and steals only whole chunks, and a
    // scene's work is bunched where its polygons are (demo 2 at 2048x2048
    // with the background pattern: one thread sat idle for 90 of 140 ms).
    // 4,096 jobs at that size cost nothing measurable.
    (0..tiles.len())
        .into_par_iter()
        .with_max_len(1)
        .for_each(|i| {
            let block = render(i);
            let t = tiles[i];
            let k = t[1] as usize / tile;
            let rows = (t[3] - t[1]) as usize;
            let mut band = bands[k].lock().unwrap_or_else(|e| e.into_inner());
            let tw = (t[2] - t[0]) as usize;
            // Row r of the block is y = t[1] + r; in a top-first band
            // (rows y1 - 1 down to kT) it is row rows - 1 - r.
            let band_row = |r: usize| {
                let start = (if top_first { rows - 1 - r } else { r }) * w + t[0] as usize;
                start..start + tw
            };
            match block {
                Block::Pixels(block) => {
                    for (r, row) in block.chunks_exact(tw).enumerate() {
                        for (o, p) in band[band_row(r)].iter_mut().zip(row) {
                            *o = encode(*p);
                        }
                    }
                }
                Block::Flat(p) => {
                    let o = encode(p);
                    for r in 0..rows {
                        band[band_row(r)].fill(o);
                    }
                }
            }
        });
    pixels
}

/// A pixel's linear light over black and over white: the two passes of a
/// transparent background ([`Background::transparent`]).
pub(crate) type OverBlackAndWhite = ([f32; 3], [f32; 3]);

/// One pixel over a transparent background, from its linear light over
/// black (`b`: its colour premultiplied by its coverage `a`) and over
/// white (`wh = b + (1 - a)`): `a = 1 - (wh - b)`, averaged over the
/// channels, and the colour `b / a`, each encoded once, rounding (straight,
/// not premultiplied, alpha, as PNG and PAM store it); `steps` is the code
/// of alpha 1, and a pixel is transparent, all zeros, below half a step.
#[inline]
fn with_alpha<T: Copy + Default>(
    b: [f32; 3],
    wh: [f32; 3],
    steps: f32,
    encode: fn(f32) -> T,
    code: fn(f32) -> T,
) -> [T; 4] {
    let uncovered: f32 = (0..3).map(|c| wh[c] - b[c]).sum::<f32>() / 3.0;
    let alpha = (1.0 - uncovered).clamp(0.0, 1.0);
    if alpha < 0.5 / steps {
        return [T::default(); 4];
    }
    let [r, g, bl] = b.map(|c| encode((c / alpha).clamp(0.0, 1.0)));
    [r, g, bl, code(alpha * steps)]
}

/// [`with_alpha`] in 8-bit sRGB.
pub(crate) fn rgba8((b, wh): OverBlackAndWhite) -> [u8; 4] {
    with_alpha(b, wh, 255.0, linear_to_srgb, |a| a.round() as u8)
}

/// [`with_alpha`] in 16-bit sRGB.
pub(crate) fn rgba16((b, wh): OverBlackAndWhite) -> [u16; 4] {
    with_alpha(b, wh, 65535.0, linear_to_srgb16, |a| a.round() as u16)
}

impl Frame {
    /// Assembles a frame from per-tile results (each a row-major block of the
    /// tile's pixels, in [`super::tiles`] order).
    pub(crate) fn from_tiles(
        width: u32,
        height: u32,
        tiles: &[[u32; 4]],
        blocks: Vec<Vec<[f32; 3]>>,
    ) -> Frame {
        use rayon::prelude::*;
        let w = width as usize;
        let mut pixels = vec![[0.0f32; 3]; w * height as usize];
        // Band by band (the tiles of one band of rows are consecutive, as
        // `super::tiles` lists them), in parallel: a serial copy of a
        // 2048x2048 frame, with the page faults of its first touch, was the
        // part of a textured render that did not scale with threads.
        let per_band = width.div_ceil(super::TILE).max(1) as usize;
        if w > 0 {
            pixels
                .par_chunks_mut(super::TILE as usize * w)
                .zip(tiles.par_chunks(per_band).zip(blocks.par_chunks(per_band)))
                .for_each(|(band, (tiles, blocks))| {
                    let y0 = tiles[0][1] as usize;
                    for (t, block) in tiles.iter().zip(blocks) {
                        debug_assert_eq!(t[1] as usize, y0, "tiles in row-major bands");
                        copy_block(band, w, *t, block);
                    }
                });
        }
        Frame {
            width,
            height,
            pixels,
            estimated: 0,
        }
    }

    /// The RGBA image of a frame over a transparent background, from the
    /// frame drawn over black (`over_black`: colours premultiplied by their
    /// coverage `a`) and over white (`over_white = over_black + (1 - a)`):
    /// `a = 1 - (over_white - over_black)`, averaged over the channels, and
    /// the colour `over_black / a`, each encoded once, rounding (straight,
    /// not premultiplied, alpha, as PNG and PAM store it); a pixel below
    /// half an 8-bit step of alpha is transparent, all zeros.
    pub fn to_image_with_alpha(over_black: &Frame, over_white: &Frame) -> Image {
        Image {
            width: over_black.width,
            height: over_black.height,
            channels: 4,
            data: Frame::pairs_top_first(over_black, over_white, rgba8),
        }
    }

    /// The pixels of two passes of one frame through `encode`, a pixel
    /// from each, rows top first.
    fn pairs_top_first<T: Copy>(
        over_black: &Frame,
        over_white: &Frame,
        encode: fn(OverBlackAndWhite) -> [T; 4],
    ) -> Vec<T> {
        assert_eq!(
            (over_black.width, over_black.height),
            (over_white.width, over_white.height),
            "two passes of one frame"
        );
        let w = (over_black.width as usize).max(1);
        let (black, white) = (&over_black.pixels, &over_white.pixels);
        black
            .chunks_exact(w)
            .rev()
            .zip(white.chunks_exact(w).rev())
            .flat_map(|(b, wh)| b.iter().zip(wh).map(|(b, wh)| encode((*b, *wh))))
            .flatten()
            .collect()
    }

    /// The image in `encoding`: [`Frame::to_image`], [`Frame::to_image16`]
    /// or [`Frame::to_linear_image`].
    pub fn encode(&self, encoding: Encoding) -> AnyImage {
        match encoding {
            Encoding::Srgb8 => AnyImage::Srgb8(self.to_image()),
            Encoding::Srgb16 => AnyImage::Srgb16(self.to_image16()),
            Encoding::LinearF32 => AnyImage::Linear(self.to_linear_image()),
        }
    }

    /// [`Frame::to_image_with_alpha`] in `encoding`. Linear float has no
    /// alpha (PFM stores none): it is the colour over black, as
    /// `over_black` holds it (colours premultiplied by their coverage).
    pub fn encode_with_alpha(
        over_black: &Frame,
        over_white: &Frame,
        encoding: Encoding,
    ) -> AnyImage {
        match encoding {
            Encoding::Srgb8 => AnyImage::Srgb8(Frame::to_image_with_alpha(over_black, over_white)),
            Encoding::Srgb16 => {
                AnyImage::Srgb16(Frame::to_image16_with_alpha(over_black, over_white))
            }
            Encoding::LinearF32 => AnyImage::Linear(over_black.to_linear_image()),
        }
    }

    /// [`Frame::to_image_with_alpha`] in 16 bits: the colour and the alpha
    /// each the nearest 16-bit code, a pixel transparent below half a
    /// 16-bit step of alpha.
    pub fn to_image16_with_alpha(over_black: &Frame, over_white: &Frame) -> Image16 {
        Image16 {
            width: over_black.width,
            height: over_black.height,
            channels: 4,
            data: Frame::pairs_top_first(over_black, over_white, rgba16),
        }
    }

    /// Encodes to 16-bit sRGB, each code the nearest to the exact sRGB value
    /// of the stored linear value ([`linear_to_srgb16`], whose doc gives
    /// the precision argument); row 0 of the image is the top. Rows in
    /// parallel, as [`Frame::to_image`].
    pub fn to_image16(&self) -> Image16 {
        Image16 {
            width: self.width,
            height: self.height,
            channels: 3,
            data: self.encode_rows(linear_to_srgb16),
        }
    }

    /// Every channel through `encode`, rows top first, in parallel on the
    /// current rayon pool: a serial pass over a 1024x768 frame costs as
    /// much as rendering a light scene.
    fn encode_rows<T: Copy + Default + Send>(&self, encode: fn(f32) -> T) -> Vec<T> {
        use rayon::prelude::*;
        let (w, h) = (self.width as usize, self.height as usize);
        let mut data = vec![T::default(); w * h * 3];
        if w > 0 {
            data.par_chunks_mut(w * 3).enumerate().for_each(|(r, out)| {
                let y = h - 1 - r;
                for (o, p) in out
                    .chunks_exact_mut(3)
                    .zip(&self.pixels[y * w..(y + 1) * w])
                {
                    o.copy_from_slice(&p.map(encode));
                }
            });
        }
        data
    }

    /// The frame's linear values as they are stored, unrounded, row 0 at
    /// the top (what PFM writes).
    pub fn to_linear_image(&self) -> LinearImage {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut data = Vec::with_capacity(w * h * 3);
        for r in 0..h {
            let y = h - 1 - r;
            data.extend(self.pixels[y * w..(y + 1) * w].iter().flatten());
        }
        LinearImage {
            width: self.width,
            height: self.height,
            data,
        }
    }

    /// Encodes to 8-bit sRGB, rounding once; row 0 of the image is the top
    /// (rows in parallel on the current rayon pool).
    pub fn to_image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            channels: 3,
            data: self.encode_rows(linear_to_srgb),
        }
    }
}
