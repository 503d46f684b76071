//! The rasterizer: from world-space polygons to an 8-bit sRGB image.
//!
//! The pipeline is the classic one, split one idea per module:
//!
//! 1. [`crate::view::clip`]: each polygon is transformed to homogeneous clip
//!    coordinates and clipped there, *before* the perspective divide, so
//!    nothing behind the eye is ever drawn mirrored and no division by zero
//!    happens (near = 0 works).
//! 2. [`project`](try_project): the divide and the viewport map give screen
//!    coordinates in pixels, y up, (0,0) the lower-left corner of the image.
//!    Each polygon gets an affine *nearness* function over the screen (bigger is
//!    nearer): `1/w` for perspective views, `-z_clip` for parallel ones. Both are
//!    exactly affine in screen space for a planar polygon, and both are kept in
//!    f64, so depth precision does not depend on the near plane. Its colour
//!    comes from one [`Shader`].
//! 3. One of three resolvers turns the screen polygons into linear-light pixels:
//!    [`scan`] (point sampling, `--aa none` and `--aa ss<N>`, watertight on exact
//!    integer edge functions), [`coverage`] (`--aa exact`: the exact area of every
//!    visible polygon in every pixel; its tile's geometry in [`gather`], the
//!    visibility within a pixel in `visible`), [`reference`](mod@reference) (`--reference`: the
//!    reference (docs/rendering.md) by an independent method, with its own error estimate).
//! 4. Linear light is encoded to sRGB once, rounding: each tile as soon as
//!    it is rendered ([`render_encoded`]; over a transparent background from
//!    the tile's two passes, over black and over white,
//!    [`render_encoded_with_alpha`]), or a whole [`Frame`] kept in linear
//!    light ([`Frame::to_image`]) where it is needed, for `--reference`. A
//!    tile that no polygon reaches, over a plain background, is one colour,
//!    encoded once. ([`Background`] is what lies behind every polygon.)
//!
//! Work is split into fixed square tiles of [`TILE`] pixels; every tile is
//! computed from the same inputs in the same order whatever the number of
//! threads, so the output is byte-identical for any `--threads`.
//!
//! Visibility ties (coplanar overlapping polygons, z-fighting) go to the polygon
//! that comes later in the stream (painter's order), in all three
//! resolvers alike (see [`DEPTH_TIE_REL`]). [`compare`] measures one image
//! against another.

// Per-channel loops `for ch in 0..3` over several arrays at once read better
// than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod compare;
pub mod coverage;
mod crowd;
mod frame;
pub mod gather;
mod outline;
mod project;
pub mod reference;
pub mod scan;
mod visible;

use crate::color::{linear_to_srgb, linear_to_srgb16, Rgb8};
use crate::io::{AnyImage, Encoding, Image, Image16, LinearImage};
use crate::progress::{Progress, Silent};
use crate::view::View;
pub use frame::{Background, Frame};
use frame::{Block, RowOrder};
#[cfg(test)]
pub(crate) use project::project;
pub use project::{try_project, Cull, Dropped, ScreenPoly, ShadeField, Shader, Tally};

/// Side of the square tiles work is split into. 32 keeps a tile's sample
/// buffers in cache for up to 16x16 supersampling while leaving a 1024x768
/// image 768 tiles to share among threads. `--aa exact` keeps a state per
/// pixel (uncovered part, showers, colour) read at random as the tile's
/// polygons come in, and at 32 it stays in cache too. Measured on a million
/// random triangles at 1024x768 (interleaved runs, two threads): 64 → 1.25x
/// the time of 32, 128 → 1.8x; 16, 24 and 48 within 5% of 32.
pub const TILE: u32 = 32;

/// Relative depth tolerance under which two polygons count as equally near at a
/// point (coplanar overlap): the later polygon in the stream then wins, as
/// in painter's order (the IRIS drawing 2D shapes one over the other, or OpenGL
/// with `GL_LEQUAL`). 1e-9 is
/// far above f64 rounding of the plane fit (~1e-15) and far below any real depth
/// separation in a scene that f64 can tell apart.
pub const DEPTH_TIE_REL: f64 = 1e-9;

/// The absolute part of the tie tolerance for polygons projected through
/// `view`: [`DEPTH_TIE_REL`] times its [`View::nearness_scale`]. One number
/// a frame, given to the resolvers with the view (kept in every polygon it
/// was 8 bytes of each, bench/memory.sh).
pub fn tie_floor(view: &View) -> f64 {
    DEPTH_TIE_REL * view.nearness_scale()
}

/// The tie tolerance between two nearness values at a point: relative to
/// the larger, plus the view's part ([`tie_floor`]).
#[inline]
pub fn tie_tolerance(qa: f64, qb: f64, floor: f64) -> f64 {
    DEPTH_TIE_REL * qa.abs().max(qb.abs()) + floor
}

/// Curves (`circle`, `arc`) are flattened to polygons whose chords stray at most
/// this many pixels from the true curve: far below what 8 bits can show.
pub const CURVE_TOLERANCE_PX: f64 = 1.0 / 256.0;

/// How pixels are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aa {
    /// One sample at each pixel centre.
    None,
    /// `k x k` samples per pixel on a regular grid (`--aa ss<k²>`).
    Ss(u32),
    /// Exact area coverage, box filter.
    Exact,
}

/// Most samples per side of a pixel for `--aa ss<N>`: 16 (256 samples) keeps the
/// fixed-point edge functions of [`scan`] within i64 for a 65535-pixel image.
pub const MAX_SS_SIDE: u32 = 16;

impl std::str::FromStr for Aa {
    type Err = String;
    fn from_str(s: &str) -> Result<Aa, String> {
        match s {
            "none" => return Ok(Aa::None),
            "exact" => return Ok(Aa::Exact),
            _ => {}
        }
        let bad = || {
            format!(
                "invalid anti-aliasing `{s}`: expected none, exact or ss<N> with N a square \
                 from 1 to {} (ss4, ss16, ...)",
                MAX_SS_SIDE * MAX_SS_SIDE
            )
        };
        let n: u32 = s
            .strip_prefix("ss")
            .and_then(|n| n.parse().ok())
            .ok_or_else(bad)?;
        let k = (n as f64).sqrt().round() as u32;
        if k == 0 || k * k != n || k > MAX_SS_SIDE {
            return Err(bad());
        }
        Ok(if k == 1 { Aa::None } else { Aa::Ss(k) })
    }
}

/// The tiles of a `width x height` frame: `[x0, y0, x1, y1]`, row-major from the
/// bottom.
pub fn tiles(width: u32, height: u32) -> Vec<[u32; 4]> {
    let mut out = Vec::new();
    for y in (0..height).step_by(TILE as usize) {
        for x in (0..width).step_by(TILE as usize) {
            out.push([x, y, (x + TILE).min(width), (y + TILE).min(height)]);
        }
    }
    out
}

/// For every tile of [`tiles`], the indices of the polygons whose bounding
/// box meets it, in stream order: tile `i`'s are `bins[i]`.
///
/// One list for all tiles, each tile's a range of it, sized by a first pass
/// that counts: a list per tile, grown as it filled, held up to twice its
/// entries (4 bytes each) in blocks scattered over the heap: 2.2 MB more at
/// the peak of a million triangles (bench/memory.sh's input, `/usr/bin/time`,
/// one run each; runs of one build spread by about 1 MB).
pub struct Bins {
    /// Where each tile's range starts in `entries`, and where the last ends.
    starts: Vec<usize>,
    entries: Vec<u32>,
}

impl std::ops::Index<usize> for Bins {
    type Output = [u32];

    fn index(&self, tile: usize) -> &[u32] {
        &self.entries[self.starts[tile]..self.starts[tile + 1]]
    }
}

impl Bins {
    /// How many tiles.
    pub fn len(&self) -> usize {
        self.starts.len() - 1
    }

    /// Whether there are no tiles (a frame with no pixels).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The polygons of `bin` (a tile's, [`Bins`]) each with its pixel box
/// ([`ScreenPoly::bbox`]), worked out once for a tile that reads them more
/// than once.
pub fn boxed<'a>(
    polys: &'a [ScreenPoly],
    bin: &'a [u32],
) -> impl Iterator<Item = (u32, [u32; 4])> + 'a {
    bin.iter().map(|&pi| (pi, polys[pi as usize].bbox()))
}

/// Bins the polygons into the tiles of a `width x height` frame ([`Bins`]).
pub fn bin(polys: &[ScreenPoly], width: u32, height: u32) -> Bins {
    let tx = width.div_ceil(TILE) as usize;
    let ty = height.div_ceil(TILE) as usize;
    // The tiles a polygon's box meets, cut to the frame.
    let tiles_of = |p: &ScreenPoly| {
        let [x0, y0, x1, y1] = p.bbox();
        let (x0, x1) = (x0.min(width), x1.min(width));
        let (y0, y1) = (y0.min(height), y1.min(height));
        let (cols, rows) = if x1 <= x0 || y1 <= y0 {
            (0..0, 0..0)
        } else {
            (
                (x0 / TILE) as usize..((x1 - 1) / TILE) as usize + 1,
                (y0 / TILE) as usize..((y1 - 1) / TILE) as usize + 1,
            )
        };
        rows.flat_map(move |r| cols.clone().map(move |c| r * tx + c))
    };
    let mut starts = vec![0usize; tx * ty + 1];
    for p in polys {
        for t in tiles_of(p) {
            starts[t + 1] += 1;
        }
    }
    for t in 0..tx * ty {
        starts[t + 1] += starts[t];
    }
    let mut next = starts.clone();
    let mut entries = vec![0u32; starts[tx * ty]];
    for (i, p) in polys.iter().enumerate() {
        for t in tiles_of(p) {
            entries[next[t]] = i as u32;
            next[t] += 1;
        }
    }
    Bins { starts, entries }
}

/// Renders polygons projected through `view` ([`try_project`]) with the
/// chosen anti-aliasing, in a frame of the view's size. Runs on the current
/// rayon pool; the result does not depend on its size.
pub fn render(polys: &[ScreenPoly], bg: &Background, view: &View, aa: Aa) -> Frame {
    render_with(polys, bg, view, aa, &Silent)
}

/// [`render`], reporting each tile done to `progress` (phase "render").
pub fn render_with(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
) -> Frame {
    let (pixels, estimated) =
        render_pixels(polys, bg, view, aa, progress, RowOrder::BottomFirst, |p| p);
    Frame {
        width: view.width,
        height: view.height,
        pixels,
        estimated,
    }
}

/// [`render_with`] in `encoding`, each tile encoded as soon as it is
/// rendered: the same image as [`Frame::encode`] of the frame, without the
/// frame (12 bytes a pixel). Also gives [`Frame::estimated`].
pub fn render_encoded(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
    encoding: Encoding,
) -> (AnyImage, u64) {
    let (width, height) = (view.width, view.height);
    match encoding {
        Encoding::Srgb8 => {
            let (data, n) = render_channels(polys, bg, view, aa, progress, linear_to_srgb);
            let image = Image {
                width,
                height,
                channels: 3,
                data,
            };
            (AnyImage::Srgb8(image), n)
        }
        Encoding::Srgb16 => {
            let (data, n) = render_channels(polys, bg, view, aa, progress, linear_to_srgb16);
            let image = Image16 {
                width,
                height,
                channels: 3,
                data,
            };
            (AnyImage::Srgb16(image), n)
        }
        Encoding::LinearF32 => {
            let (data, n) = render_channels(polys, bg, view, aa, progress, |x| x);
            let image = LinearImage {
                width,
                height,
                data,
            };
            (AnyImage::Linear(image), n)
        }
    }
}

/// Renders the pixels and puts every channel through `encode`, rows from
/// the top; also gives the count of estimated fragments.
fn render_channels<T: Copy + Default + Send>(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
    encode: fn(f32) -> T,
) -> (Vec<T>, u64) {
    let (pixels, n) = render_pixels(polys, bg, view, aa, progress, RowOrder::TopFirst, |p| {
        p.map(encode)
    });
    (pixels.into_flattened(), n)
}

/// The resolver's pixels, rows in `order`, each stored as `encode` gives it
/// ([`frame::render_bands`]), and the count of estimated fragments
/// ([`Frame::estimated`]).
fn render_pixels<P: Copy + Default + Send>(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
    order: RowOrder,
    encode: impl Fn([f32; 3]) -> P + Sync,
) -> (Vec<P>, u64) {
    let r = Resolver::new(polys, view, aa);
    let pixels = r.bands(progress, order, |i| r.tile(i, bg, true), encode);
    (pixels, r.estimated.into_inner())
}

/// [`render_encoded`] over a transparent background
/// ([`Background::transparent`]), with alpha: each tile drawn over black
/// and over white in turn, and encoded from the two as soon as it is done
/// ([`Frame::encode_with_alpha`]'s pixels, without its two frames of 12
/// bytes a pixel). Linear float has no alpha: it is the frame over black,
/// drawn once.
pub fn render_encoded_with_alpha(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
    encoding: Encoding,
) -> (AnyImage, u64) {
    let black = bg.opaque(Rgb8::BLACK);
    if encoding == Encoding::LinearF32 {
        return render_encoded(polys, &black, view, aa, progress, encoding);
    }
    let white = bg.opaque(Rgb8::WHITE);
    let r = Resolver::new(polys, view, aa);
    let both = |i: usize| {
        let [x0, y0, x1, y1] = r.tiles[i];
        let n = ((x1 - x0) * (y1 - y0)) as usize;
        r.tile(i, &black, true).zip(r.tile(i, &white, false), n)
    };
    let (width, height, top) = (view.width, view.height, RowOrder::TopFirst);
    // 8 or 16 bits: linear float returned above.
    let image = if encoding == Encoding::Srgb8 {
        let data = r.bands(progress, top, both, frame::rgba8).into_flattened();
        AnyImage::Srgb8(Image {
            width,
            height,
            channels: 4,
            data,
        })
    } else {
        let data = r.bands(progress, top, both, frame::rgba16).into_flattened();
        AnyImage::Srgb16(Image16 {
            width,
            height,
            channels: 4,
            data,
        })
    };
    (image, r.estimated.into_inner())
}

/// One frame's tiles, their polygons ([`Bins`]) and the resolver `aa`
/// chosen for them: what [`Resolver::tile`] needs to render any tile over
/// any background.
struct Resolver<'a> {
    polys: &'a [ScreenPoly],
    size: (u32, u32),
    tiles: Vec<[u32; 4]>,
    bins: Bins,
    floor: f64,
    aa: Aa,
    /// Fragments estimated so far ([`Frame::estimated`]).
    estimated: std::sync::atomic::AtomicU64,
}

impl<'a> Resolver<'a> {
    fn new(polys: &'a [ScreenPoly], view: &View, aa: Aa) -> Resolver<'a> {
        let size = (view.width, view.height);
        Resolver {
            polys,
            size,
            tiles: tiles(size.0, size.1),
            bins: bin(polys, size.0, size.1),
            floor: tie_floor(view),
            aa,
            estimated: Default::default(),
        }
    }

    /// Every tile through `tile`, each reported to `progress` (phase
    /// "render") and encoded into the frame's rows in `order` as soon as it
    /// is done ([`frame::render_bands`]).
    fn bands<T: Copy, P: Copy + Default + Send>(
        &self,
        progress: &dyn Progress,
        order: RowOrder,
        tile: impl Fn(usize) -> Block<T> + Sync,
        encode: impl Fn(T) -> P + Sync,
    ) -> Vec<P> {
        progress.phase("render", self.tiles.len() as u64);
        let render = |i: usize| {
            let block = tile(i);
            progress.advance(1);
            block
        };
        frame::render_bands(self.size, &self.tiles, order, render, encode)
    }

    /// Tile `i` over `bg`, its estimated fragments counted if `count`.
    ///
    /// A tile that no polygon reaches, over a plain background, is one
    /// colour: the resolver's own for a pixel of background only, worked out
    /// at the tile's corner (it is the same at every pixel).
    fn tile(&self, i: usize, bg: &Background, count: bool) -> Block {
        let (bin, tile) = (&self.bins[i], self.tiles[i]);
        let [x, y, _, _] = tile;
        let empty = bin.is_empty() && bg.plain().is_some();
        match self.aa {
            Aa::Exact if empty => Block::Flat(coverage::background_pixel(bg, x, y)),
            Aa::Exact => {
                let (block, n) =
                    coverage::render_bin_counted(self.polys, bin, bg, tile, self.floor);
                if count {
                    self.estimated
                        .fetch_add(n, std::sync::atomic::Ordering::Relaxed);
                }
                Block::Pixels(block)
            }
            Aa::None | Aa::Ss(_) => {
                let k = if let Aa::Ss(k) = self.aa { k } else { 1 };
                if empty {
                    Block::Flat(scan::background_pixel(bg, k, x, y))
                } else {
                    Block::Pixels(scan::render_tile(self.polys, bin, bg, tile, k, self.floor))
                }
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::view::View;
    use glam::DVec3;

    pub fn poly2(view: &View, pts: &[[f64; 2]], color: Rgb8, order: u32) -> Option<ScreenPoly> {
        let w: Vec<DVec3> = pts.iter().map(|p| DVec3::new(p[0], p[1], 0.0)).collect();
        project(view, &w, color, order, Cull::None).ok()
    }

    /// The largest difference, in 8-bit codes, between `--aa exact`'s image
    /// of `polys` and the reference's (6 strips a pixel): the tests' check
    /// of the exact resolver against a method that shares none of its code.
    pub fn exact_off_reference(polys: &[ScreenPoly], bg: &Background, view: &View) -> u8 {
        let exact = render(polys, bg, view, Aa::Exact).to_image();
        let want = reference::render(polys, bg, view, 6).frame.to_image();
        let diffs = exact
            .data
            .iter()
            .zip(&want.data)
            .map(|(a, b)| a.abs_diff(*b));
        diffs.max().unwrap_or(0)
    }

    #[test]
    fn aa_names_parse() {
        assert_eq!("none".parse::<Aa>().unwrap(), Aa::None);
        assert_eq!("exact".parse::<Aa>().unwrap(), Aa::Exact);
        assert_eq!("ss16".parse::<Aa>().unwrap(), Aa::Ss(4));
        assert_eq!("ss1".parse::<Aa>().unwrap(), Aa::None);
        for bad in ["ss3", "ss0", "ss", "ss512", "ssx", "fxaa"] {
            assert!(bad.parse::<Aa>().unwrap_err().contains(bad));
        }
    }

    /// Each tile's bin holds, in stream order, the polygons whose pixel
    /// box meets the tile, as asking every polygon of every tile says: on
    /// frames whose sides are and are not whole tiles, with polygons inside,
    /// across and partly off the frame.
    #[test]
    fn bins_hold_each_tiles_polygons_in_stream_order() {
        let mut rng = scan::tests::Rng(3);
        for (w, h) in [(100, 70), (64, 32), (1, 1), (33, 97)] {
            let v = View::ortho2(0.0, w as f64, 0.0, h as f64, w, h);
            let polys: Vec<ScreenPoly> = (0..300)
                .filter_map(|i| {
                    let (cx, cy) = (rng.next() * 1.4 - 0.2, rng.next() * 1.4 - 0.2);
                    let r = rng.next() * 40.0;
                    let pts = [[0.0, 0.0], [1.0, 0.1], [0.3, 1.0]]
                        .map(|[x, y]| [cx * w as f64 + r * x, cy * h as f64 + r * y]);
                    poly2(&v, &pts, Rgb8::WHITE, i)
                })
                .collect();
            let bins = bin(&polys, w, h);
            let tiles = tiles(w, h);
            assert_eq!(bins.len(), tiles.len());
            for (t, tile) in tiles.iter().enumerate() {
                let want: Vec<u32> = (0..polys.len() as u32)
                    .filter(|&i| {
                        let b = polys[i as usize].bbox();
                        b[0] < tile[2] && tile[0] < b[2] && b[1] < tile[3] && tile[1] < b[3]
                    })
                    .collect();
                assert_eq!(&bins[t], &want[..], "{w}x{h}, tile {tile:?}");
            }
        }
    }
}

#[cfg(test)]
mod determinism {
    use super::scan::tests::Rng;
    use super::*;
    use crate::color::Rgb8;
    use crate::view::tests::perspective;
    use glam::DVec3;

    /// `n` random triangles through `v`, from `rng`: centres at
    /// `(r·spread[0] - 5, r·spread[1] - 4, -3 - 20r)`, corners at the
    /// centre plus `(r·size[0], r·size[1], r·size[2])`, each `r` uniform in
    /// [0, 1); triangle `i` coloured `colour(i)`.
    fn triangles(
        v: &View,
        rng: &mut Rng,
        n: u32,
        spread: [f64; 2],
        size: [f64; 3],
        colour: impl Fn(u32) -> Rgb8,
    ) -> Vec<ScreenPoly> {
        (0..n)
            .filter_map(|i| {
                let c = DVec3::new(
                    rng.next() * spread[0] - 5.0,
                    rng.next() * spread[1] - 4.0,
                    -3.0 - rng.next() * 20.0,
                );
                let tri: Vec<DVec3> = (0..3)
                    .map(|_| {
                        c + DVec3::new(
                            rng.next() * size[0],
                            rng.next() * size[1],
                            rng.next() * size[2],
                        )
                    })
                    .collect();
                project(v, &tri, colour(i), i, Cull::None).ok()
            })
            .collect()
    }

    #[test]
    fn output_is_identical_for_any_thread_count() {
        let v = perspective(60.0, 100, 70, 0.0, 100.0);
        let mut rng = Rng(7);
        let polys = triangles(&v, &mut rng, 300, [10.0, 8.0], [3.0; 3], |i| {
            Rgb8([i as u8, 255 - i as u8, 77])
        });
        let bg = Background::color(Rgb8([3, 4, 5]));
        for aa in [Aa::None, Aa::Ss(3), Aa::Exact] {
            let run = |n: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .unwrap()
                    .install(|| render(&polys, &bg, &v, aa).to_image())
            };
            let one = run(1);
            assert_eq!(one, run(3), "{aa:?}");
        }
        let run_ref = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| reference::render(&polys, &bg, &v, 6).frame.to_image())
        };
        assert_eq!(run_ref(1), run_ref(2));
    }

    /// A tile that no polygon reaches, filled with the resolver's colour for
    /// a pixel of background only, is what the resolver gives it: the same
    /// frame over a plain colour as over a pattern of that one colour (which
    /// every tile is resolved over, pixel by pixel), in each resolver, and
    /// the same 8-bit image encoded as the tiles come.
    #[test]
    fn empty_tiles_filled_at_once_are_the_resolvers_own_pixels() {
        use crate::pat::Pattern;
        use crate::texture::Texels;
        let mut rng = Rng(5);
        let (w, h) = (200, 150);
        let v = View::ortho2(0.0, w as f64, 0.0, h as f64, w, h);
        // Small triangles near the lower left and one across the top right
        // corner, off the frame in part: most tiles are empty.
        let mut polys: Vec<ScreenPoly> = (0..40)
            .filter_map(|i| {
                let (cx, cy) = (rng.next() * 60.0, rng.next() * 50.0);
                let pts = [[0.0, 0.0], [7.3, 1.1], [2.2, 6.9]].map(|[x, y]| [cx + x, cy + y]);
                tests::poly2(&v, &pts, Rgb8([i as u8 * 6, 90, 200]), i)
            })
            .collect();
        let corner = [[190.5, 140.25], [230.0, 141.0], [195.0, 180.0]];
        polys.extend(tests::poly2(&v, &corner, Rgb8([250, 250, 0]), 40));
        let bins = bin(&polys, w, h);
        let empty = (0..bins.len()).filter(|&i| bins[i].is_empty()).count();
        assert!(
            empty > bins.len() / 2,
            "{empty} of {} tiles empty",
            bins.len()
        );
        let colour = Rgb8([37, 141, 203]);
        let plain = Background::color(colour);
        let one_colour = Pattern::new(16, vec![colour], vec![0; 256]).unwrap();
        let patterned = Background::new(colour, Some(Texels::new(&one_colour)));
        for aa in [Aa::None, Aa::Ss(2), Aa::Ss(3), Aa::Exact] {
            let frame = render(&polys, &plain, &v, aa);
            let bits = |f: &Frame| {
                f.pixels
                    .iter()
                    .flatten()
                    .map(|c| c.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(
                bits(&frame),
                bits(&render(&polys, &patterned, &v, aa)),
                "{aa:?}"
            );
            let (image, _) = render_encoded(&polys, &plain, &v, aa, &Silent, Encoding::Srgb8);
            assert!(image == frame.encode(Encoding::Srgb8), "{aa:?}");
        }
    }

    /// Over a transparent background, tiles drawn over black and over white
    /// in turn and encoded as they come give what the two whole frames
    /// give ([`Frame::encode_with_alpha`]), in each encoding and resolver,
    /// with and without a background pattern (partly transparent: a
    /// checker), with empty tiles, partial tiles, and one thread or two.
    #[test]
    fn alpha_encoded_as_tiles_come_equals_alpha_from_two_frames() {
        use crate::pat::{Pattern, TRANSPARENT};
        use crate::texture::Texels;
        let mut rng = Rng(19);
        let checker: Vec<u16> = (0..256)
            .map(|i| {
                if (i / 16 + i) % 2 == 0 {
                    0
                } else {
                    TRANSPARENT
                }
            })
            .collect();
        let pattern = Texels::new(&Pattern::new(16, vec![Rgb8([200, 10, 90])], checker).unwrap());
        for (w, h) in [(100, 70), (33, 65), (1, 1)] {
            let v = perspective(60.0, w, h, 0.0, 100.0);
            let polys = triangles(&v, &mut rng, 40, [3.0, 3.0], [2.0, 2.0, 1.0], |i| {
                Rgb8([i as u8 * 6, 200, 9])
            });
            for bg in [
                Background::transparent(None),
                Background::transparent(Some(pattern.clone())),
            ] {
                for aa in [Aa::None, Aa::Ss(2), Aa::Exact] {
                    let black = render(&polys, &bg.opaque(Rgb8::BLACK), &v, aa);
                    let white = render(&polys, &bg.opaque(Rgb8::WHITE), &v, aa);
                    for encoding in [Encoding::Srgb8, Encoding::Srgb16, Encoding::LinearF32] {
                        let want = Frame::encode_with_alpha(&black, &white, encoding);
                        for threads in [1, 2] {
                            let (image, estimated) = rayon::ThreadPoolBuilder::new()
                                .num_threads(threads)
                                .build()
                                .unwrap()
                                .install(|| {
                                    render_encoded_with_alpha(
                                        &polys, &bg, &v, aa, &Silent, encoding,
                                    )
                                });
                            assert!(
                                image == want,
                                "{w}x{h} {aa:?} {encoding:?}, {threads} threads"
                            );
                            assert_eq!(estimated, black.estimated);
                        }
                    }
                }
            }
        }
    }

    /// Tiles encoded as they are rendered give the image that encoding the
    /// whole frame gives, in every encoding and resolver, at sizes that
    /// leave partial tiles at the top and the right, and at whole tiles; and
    /// the same with one thread and two.
    #[test]
    fn encoding_tiles_as_they_come_equals_encoding_the_frame() {
        let mut rng = Rng(11);
        for (w, h) in [(100, 70), (33, 65), (1, 1), (64, 32), (40, 64)] {
            let v = perspective(60.0, w, h, 0.0, 100.0);
            let polys = triangles(&v, &mut rng, 60, [10.0, 8.0], [4.0, 4.0, 1.0], |i| {
                Rgb8([i as u8 * 4, 200, 9])
            });
            let bg = Background::color(Rgb8([30, 4, 5]));
            for aa in [Aa::None, Aa::Ss(2), Aa::Exact] {
                let frame = render(&polys, &bg, &v, aa);
                for encoding in [Encoding::Srgb8, Encoding::Srgb16, Encoding::LinearF32] {
                    let run = |threads: usize| {
                        rayon::ThreadPoolBuilder::new()
                            .num_threads(threads)
                            .build()
                            .unwrap()
                            .install(|| render_encoded(&polys, &bg, &v, aa, &Silent, encoding))
                    };
                    let (image, estimated) = run(1);
                    assert!(
                        image == frame.encode(encoding),
                        "{w}x{h} {aa:?} {encoding:?}"
                    );
                    assert_eq!(estimated, frame.estimated);
                    assert!(
                        run(2).0 == image,
                        "{w}x{h} {aa:?} {encoding:?}, two threads"
                    );
                }
            }
        }
    }
}
