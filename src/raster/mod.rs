//! The rasterizer: from world-space polygons to an 8-bit sRGB image.
//!
//! The pipeline is the classic one, split one idea per module:
//!
//! 1. [`clip`]: each polygon is transformed to homogeneous clip coordinates and
//!    clipped there, *before* the perspective divide, so nothing behind the eye
//!    is ever drawn mirrored and no division by zero happens (near = 0 works).
//! 2. [`project`] (this file): the divide and the viewport map give screen
//!    coordinates in pixels, y up, (0,0) the lower-left corner of the image.
//!    Each polygon gets an affine *nearness* function over the screen (bigger is
//!    nearer): `1/w` for perspective views, `-z_clip` for parallel ones. Both are
//!    exactly affine in screen space for a planar polygon, and both are kept in
//!    f64, so depth precision does not depend on the near plane.
//! 3. One of three resolvers turns the screen polygons into linear-light pixels:
//!    [`scan`] (point sampling, `--aa none` and `--aa ss<N>`, watertight on exact
//!    integer edge functions), [`coverage`] (`--aa exact`: the exact area of every
//!    visible polygon in every pixel; its tile's geometry in [`gather`], the
//!    visibility within a pixel in `visible`), [`reference`] (`--reference`: the SPEC §4
//!    reference by an independent method, with its own error estimate).
//! 4. [`Frame::to_image`] encodes linear light to sRGB once, rounding.
//!
//! Work is split into fixed square tiles of [`TILE`] pixels; every tile is
//! computed from the same inputs in the same order whatever the number of
//! threads, so the output is byte-identical for any `--threads`.
//!
//! Visibility ties (coplanar overlapping polygons, z-fighting) go to the polygon
//! that comes later in the stream (painter's order), in all three
//! resolvers alike (see [`DEPTH_TIE_REL`]).

// Per-channel loops `for ch in 0..3` over several arrays at once read better
// than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod budget;
pub mod compare;
pub mod coverage;
pub mod gather;
pub mod reference;
pub mod scan;
mod visible;

use crate::color::{linear_to_srgb, srgb_to_linear_f64, Rgb8};
use crate::geom::polygon::{area2, ear_clip, is_convex, newell_plane, GRID_SNAP_PX};
use crate::io::Image;
use crate::pat::Pattern;
use crate::stripe::StripeTexture;
use crate::texture::{PolyTexture, Texels};
use crate::view::{clip, View};
use glam::{DVec2, DVec3, DVec4};
use std::sync::Arc;

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

/// The tie tolerance between two nearness values at a point: relative to
/// them, floored by the view's scale (stored in each polygon as `tie_floor`).
#[inline]
pub fn tie_tolerance(qa: f64, qb: f64, floor: f64) -> f64 {
    DEPTH_TIE_REL * qa.abs().max(qb.abs()) + floor
}

/// Curves (`circle`, `arc`) are flattened to polygons whose chords stray at most
/// this many pixels from the true curve: far below what 8 bits can show.
pub const CURVE_TOLERANCE_PX: f64 = 1.0 / 256.0;

/// Which faces to drop (SPEC §2: vertices counter-clockwise seen from the front).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Cull {
    /// Draw both faces.
    #[default]
    None,
    /// Drop polygons seen from behind (clockwise on screen).
    Back,
    /// Drop polygons seen from the front (counter-clockwise on screen).
    Front,
}

/// The per-pixel colour source of a [`ScreenPoly`]: the projected form of the
/// scene's texture source (`crate::scene::TextureSource`).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Shader {
    /// `color` everywhere.
    #[default]
    Flat,
    /// A screen-mode pattern (SPEC §2, the IRIS `setpattern`) that replaces
    /// `color`: pixel (x, y) from the lower-left shows texel (x mod SIZE,
    /// y mod SIZE), and the polygon is absent where that texel is transparent.
    Screen(Arc<Texels>),
    /// A pattern in "object" or "uv" placement (SPEC §2), sampled per pixel
    /// through its screen → texel map (`crate::texture`). Each resolver
    /// integrates it exactly over texel cells; transparent texels leave the
    /// polygon absent there.
    Texture(Arc<PolyTexture>),
    /// A stripe texture (seed 001, `crate::stripe`): its colour replaces
    /// `color` (which then holds the face colour). Point samplers evaluate it
    /// at each sample, `--aa exact` at each fragment's centroid, the
    /// reference integrates its crisp function. Always opaque.
    Stripe(Arc<StripeTexture>),
}

/// A polygon ready for a resolver: clipped, projected, counter-clockwise on
/// screen (back faces are reversed when not culled).
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenPoly {
    /// Screen positions in pixels, y up, counter-clockwise, no repeated neighbours.
    pub verts: Vec<DVec2>,
    /// Nearness `q = a*x + b*y + c` over the screen (bigger is nearer).
    pub plane: [f64; 3],
    /// Linear-light colour.
    pub color: [f64; 3],
    /// What colours the polygon instead of `color`, if anything: one
    /// source per polygon, so no precedence between sources is needed.
    pub shader: Shader,
    /// Position in the stream: draw order, for visibility ties.
    pub order: u32,
    /// Convex pieces that tile the polygon exactly: none when it is convex
    /// (it is its own piece, see [`ScreenPoly::piece`]), else an
    /// ear-clipping triangulation. (A copy of a convex polygon's vertices
    /// cost a million allocations on a million triangles, and the exact
    /// resolver a cache miss more per polygon and tile to reach them.)
    pub pieces: Vec<Vec<DVec2>>,
    /// Absolute part of the tie tolerance: [`DEPTH_TIE_REL`] times the view's
    /// [`View::nearness_scale`].
    pub tie_floor: f64,
    /// Pixel bounding box, inclusive-exclusive: `x0..x1`, `y0..y1` (y up).
    pub bbox: [u32; 4],
}

impl ScreenPoly {
    /// How many convex pieces tile the polygon.
    pub fn piece_count(&self) -> usize {
        self.pieces.len().max(1)
    }

    /// Convex piece `k` of the polygon (`k < piece_count()`).
    pub fn piece(&self, k: usize) -> &[DVec2] {
        if self.pieces.is_empty() {
            &self.verts
        } else {
            &self.pieces[k]
        }
    }

    /// The screen-mode pattern, if that is the shader.
    #[inline]
    pub fn screen(&self) -> Option<&Arc<Texels>> {
        match &self.shader {
            Shader::Screen(t) => Some(t),
            _ => None,
        }
    }

    /// The placed texture, if that is the shader.
    #[inline]
    pub fn texture(&self) -> Option<&Arc<PolyTexture>> {
        match &self.shader {
            Shader::Texture(t) => Some(t),
            _ => None,
        }
    }

    /// The stripe texture, if that is the shader.
    #[inline]
    pub fn stripe(&self) -> Option<&Arc<StripeTexture>> {
        match &self.shader {
            Shader::Stripe(t) => Some(t),
            _ => None,
        }
    }

    /// The polygon's linear colour at pixel (x, y); `None` where a screen-mode
    /// pattern is transparent.
    #[inline]
    pub fn color_at(&self, x: u32, y: u32) -> Option<[f64; 3]> {
        match self.screen() {
            None => Some(self.color),
            Some(p) => p.at(x, y),
        }
    }

    /// The polygon's linear colour at the screen point (sx, sy) of pixel
    /// (x, y): the texel there for an "object" or "uv" pattern (point
    /// sampling, `None` where transparent), the stripe colour there (LOD
    /// filtered), else [`ScreenPoly::color_at`].
    #[inline]
    pub fn color_at_point(&self, x: u32, y: u32, sx: f64, sy: f64) -> Option<[f64; 3]> {
        if let Some(s) = self.stripe() {
            return Some(s.linear_at(sx, sy).map(f64::from));
        }
        match self.texture() {
            None => self.color_at(x, y),
            Some(t) => {
                let uv = t.map.uv(sx, sy);
                t.texel(uv.x.floor() as i64, uv.y.floor() as i64)
            }
        }
    }

    /// The colour the point-sampling resolver shows at the sample (sx, sy)
    /// of pixel (x, y): [`ScreenPoly::color_at_point`] under the exact box
    /// filter (a sample's share of the pixel's integral), else the texture's
    /// filter evaluated there with a pixel's footprint.
    #[inline]
    pub fn sample_color(&self, x: u32, y: u32, sx: f64, sy: f64) -> Option<[f64; 3]> {
        use crate::texture::filter::Eval;
        match self.texture() {
            Some(t) => match t.eval(sx, sy) {
                Eval::Box => self.color_at_point(x, y, sx, sy),
                Eval::Color(c) => c,
            },
            // Stripes and flat colours.
            None => self.color_at_point(x, y, sx, sy),
        }
    }

    /// Whether the colour can be absent somewhere (a screen-mode pattern, or
    /// a texture whose transparent texels can show): only then must a
    /// resolver look at the colour to decide visibility. `--no-skip hidden`
    /// (benchmarks) says yes for every texture, so each covered sample is
    /// textured before its depth test, hidden or not.
    #[inline]
    pub fn may_be_transparent(&self) -> bool {
        self.screen().is_some()
            || self
                .texture()
                .is_some_and(|t| !t.always_opaque() || !t.skips.hidden)
    }

    /// Nearness at a screen point.
    #[inline]
    pub fn q(&self, x: f64, y: f64) -> f64 {
        self.plane[0] * x + self.plane[1] * y + self.plane[2]
    }
}

fn snap_grid(v: f64) -> f64 {
    let r = (v * 2.0).round() * 0.5;
    if (v - r).abs() <= GRID_SNAP_PX {
        r
    } else {
        v
    }
}

/// The most vertices a concave screen polygon may have. Concave polygons are
/// split into triangles by [`ear_clip`], whose time grows with the square of
/// the vertex count (10,000 vertices: about 5 s in a debug build, well under
/// 1 s optimised); a 1,000,000-vertex concave outline would run for hours.
/// Convex outlines are drawn whole, in linear time, whatever their size.
pub const MAX_CONCAVE_VERTICES: usize = 10_000;

/// Why a polygon cannot be drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProjectError {
    /// The visible outline is concave with more than [`MAX_CONCAVE_VERTICES`].
    TooManyConcaveVertices(usize),
}

impl std::fmt::Display for ProjectError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            ProjectError::TooManyConcaveVertices(n) => write!(
                f,
                "the polygon is concave on screen with {n} vertices, more than the \
                 {MAX_CONCAVE_VERTICES} its triangulation takes (ear clipping, quadratic \
                 time): split it into smaller polygons"
            ),
        }
    }
}

impl std::error::Error for ProjectError {}

/// [`try_project`] for polygons known to be small (tests).
#[cfg(test)]
pub(crate) fn project(
    view: &View,
    world: &[DVec3],
    color: Rgb8,
    order: u32,
    cull: Cull,
) -> Option<ScreenPoly> {
    try_project(view, world, color, order, cull).expect("a test polygon too complex to draw")
}

/// Clips, projects and orients one world polygon. `Ok(None)` when nothing of
/// it is visible, it is culled, or it is edge-on (zero area on screen); an
/// error when it is too complex to triangulate ([`MAX_CONCAVE_VERTICES`]).
pub fn try_project(
    view: &View,
    world: &[DVec3],
    color: Rgb8,
    order: u32,
    cull: Cull,
) -> Result<Option<ScreenPoly>, ProjectError> {
    let clip_space: Vec<DVec4> = world.iter().map(|&p| view.to_clip(p)).collect();
    if clip_space.iter().any(|c| !c.is_finite()) {
        return Ok(None);
    }
    let clipped = clip::clip_polygon(&clip_space, view);
    if clipped.len() < 3 {
        return Ok(None);
    }
    let mut verts: Vec<DVec2> = Vec::with_capacity(clipped.len());
    let mut qs: Vec<f64> = Vec::with_capacity(clipped.len());
    for &c in &clipped {
        let s = view.to_screen(c).map(snap_grid);
        if verts.last() == Some(&s) {
            continue;
        }
        verts.push(s);
        qs.push(view.nearness(c));
    }
    while verts.len() > 1 && verts.first() == verts.last() {
        verts.pop();
        qs.pop();
    }
    if verts.len() < 3 {
        return Ok(None);
    }
    let a2 = area2(&verts);
    if a2 == 0.0 || !a2.is_finite() {
        return Ok(None);
    }
    match cull {
        Cull::Back if a2 < 0.0 => return Ok(None),
        Cull::Front if a2 > 0.0 => return Ok(None),
        _ => {}
    }
    if a2 < 0.0 {
        verts.reverse();
        qs.reverse();
    }
    let Some(plane) = newell_plane(&verts, &qs) else {
        return Ok(None);
    };
    let pieces = if is_convex(&verts) {
        Vec::new()
    } else if verts.len() > MAX_CONCAVE_VERTICES {
        return Err(ProjectError::TooManyConcaveVertices(verts.len()));
    } else {
        ear_clip(&verts)
    };
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for v in &verts {
        x0 = x0.min(v.x);
        y0 = y0.min(v.y);
        x1 = x1.max(v.x);
        y1 = y1.max(v.y);
    }
    let (w, h) = (view.width, view.height);
    let bbox = [
        (x0.floor().max(0.0) as u32).min(w),
        (y0.floor().max(0.0) as u32).min(h),
        (x1.ceil().max(0.0) as u32).min(w),
        (y1.ceil().max(0.0) as u32).min(h),
    ];
    let c = color.0.map(|ch| srgb_to_linear_f64(ch as f64 / 255.0));
    Ok(Some(ScreenPoly {
        verts,
        plane,
        color: c,
        shader: Shader::Flat,
        order,
        pieces,
        tie_floor: DEPTH_TIE_REL * view.nearness_scale(),
        bbox,
    }))
}

/// What lies behind every polygon: a colour, or the thesis's `colorclear`
/// pattern tiled in screen mode (pixel (x, y) from the lower-left takes texel
/// (x mod SIZE, y mod SIZE); transparent texels show the colour).
#[derive(Clone, Debug)]
pub struct Background {
    /// Linear light of the colour, decoded once (it is read for every pixel
    /// not fully covered).
    color: [f64; 3],
    pattern: Option<Texels>,
}

impl Background {
    pub fn color(color: Rgb8) -> Background {
        Background::new(color, None)
    }

    /// A colour, with a pattern tiled over it in screen mode.
    pub fn new(color: Rgb8, pattern: Option<&Pattern>) -> Background {
        Background {
            color: color.0.map(|ch| srgb_to_linear_f64(ch as f64 / 255.0)),
            pattern: pattern.map(Texels::new),
        }
    }

    /// Linear-light colour of pixel (x, y), y counted from the bottom.
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> [f64; 3] {
        match &self.pattern {
            Some(p) => p.at(x, y).unwrap_or(self.color),
            None => self.color,
        }
    }
}

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

/// A frame of linear-light pixels, rows from the bottom (y up).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear RGB, `(y * width + x)`, y from the bottom.
    pub pixels: Vec<[f32; 3]>,
}

impl Frame {
    /// Assembles a frame from per-tile results (each a row-major block of the
    /// tile's pixels, in [`tiles`] order).
    pub(crate) fn from_tiles(
        width: u32,
        height: u32,
        tiles: &[[u32; 4]],
        blocks: Vec<Vec<[f32; 3]>>,
    ) -> Frame {
        let mut pixels = vec![[0.0f32; 3]; width as usize * height as usize];
        for (t, block) in tiles.iter().zip(blocks) {
            let tw = (t[2] - t[0]) as usize;
            for (r, row) in block.chunks_exact(tw).enumerate() {
                let y = t[1] as usize + r;
                let start = y * width as usize + t[0] as usize;
                pixels[start..start + tw].copy_from_slice(row);
            }
        }
        Frame {
            width,
            height,
            pixels,
        }
    }

    /// Encodes to 8-bit sRGB, rounding once; row 0 of the image is the top.
    ///
    /// Rows are encoded in parallel (on the current rayon pool): a serial
    /// pass over a 1024x768 frame costs as much as rendering a light scene.
    pub fn to_image(&self) -> Image {
        use rayon::prelude::*;
        let (w, h) = (self.width as usize, self.height as usize);
        let mut data = vec![0u8; w * h * 3];
        if w > 0 {
            data.par_chunks_mut(w * 3).enumerate().for_each(|(r, out)| {
                let y = h - 1 - r;
                for (o, p) in out
                    .chunks_exact_mut(3)
                    .zip(&self.pixels[y * w..(y + 1) * w])
                {
                    o.copy_from_slice(&p.map(linear_to_srgb));
                }
            });
        }
        Image {
            width: self.width,
            height: self.height,
            channels: 3,
            data,
        }
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

/// For every tile, the indices of the polygons whose bounding box meets it, in
/// stream order.
pub fn bin(polys: &[ScreenPoly], width: u32, height: u32) -> Vec<Vec<u32>> {
    let tx = width.div_ceil(TILE) as usize;
    let ty = height.div_ceil(TILE) as usize;
    let mut bins = vec![Vec::new(); tx * ty];
    for (i, p) in polys.iter().enumerate() {
        let [x0, y0, x1, y1] = p.bbox;
        if x1 <= x0 || y1 <= y0 {
            continue;
        }
        for ty_i in (y0 / TILE) as usize..=((y1 - 1) / TILE) as usize {
            for tx_i in (x0 / TILE) as usize..=((x1 - 1) / TILE) as usize {
                bins[ty_i * tx + tx_i].push(i as u32);
            }
        }
    }
    bins
}

/// Renders projected polygons with the chosen anti-aliasing. Runs on the
/// current rayon pool; the result does not depend on its size.
pub fn render(polys: &[ScreenPoly], bg: &Background, width: u32, height: u32, aa: Aa) -> Frame {
    use rayon::prelude::*;
    let tiles = tiles(width, height);
    let bins = bin(polys, width, height);
    let blocks: Vec<Vec<[f32; 3]>> = match aa {
        Aa::Exact => tiles
            .par_iter()
            .zip(&bins)
            .map(|(t, b)| coverage::render_bin(polys, b, bg, *t))
            .collect(),
        Aa::None | Aa::Ss(_) => {
            let k = if let Aa::Ss(k) = aa { k } else { 1 };
            let snapped: Vec<scan::FixedPoly> = polys
                .par_iter()
                .map(|p| scan::FixedPoly::new(p, k))
                .collect();
            tiles
                .par_iter()
                .zip(&bins)
                .map(|(t, b)| scan::render_tile(polys, &snapped, b, bg, *t, k))
                .collect()
        }
    };
    Frame::from_tiles(width, height, &tiles, blocks)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::view::tests::perspective;

    pub fn poly2(view: &View, pts: &[[f64; 2]], color: Rgb8, order: u32) -> Option<ScreenPoly> {
        let w: Vec<DVec3> = pts.iter().map(|p| DVec3::new(p[0], p[1], 0.0)).collect();
        project(view, &w, color, order, Cull::None)
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

    #[test]
    fn ortho2_maps_world_units_to_pixels() {
        let v = View::ortho2(0.0, 100.0, 0.0, 50.0, 100, 50);
        let p = poly2(
            &v,
            &[[10.0, 5.0], [20.0, 5.0], [20.0, 15.0]],
            Rgb8::WHITE,
            0,
        )
        .unwrap();
        assert_eq!(p.verts[0], DVec2::new(10.0, 5.0));
        assert_eq!(p.bbox, [10, 5, 20, 15]);
    }

    #[test]
    fn culling_follows_the_ccw_front_rule_and_back_faces_are_reoriented() {
        let v = View::ortho2(0.0, 10.0, 0.0, 10.0, 10, 10);
        let ccw: Vec<DVec3> = [[1.0, 1.0], [5.0, 1.0], [1.0, 5.0]]
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.0))
            .collect();
        let cw: Vec<DVec3> = ccw.iter().rev().copied().collect();
        assert!(project(&v, &ccw, Rgb8::WHITE, 0, Cull::Back).is_some());
        assert!(project(&v, &cw, Rgb8::WHITE, 0, Cull::Back).is_none());
        assert!(project(&v, &ccw, Rgb8::WHITE, 0, Cull::Front).is_none());
        let p = project(&v, &cw, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert!(area2(&p.verts) > 0.0);
    }

    #[test]
    fn snap_sized_kinks_keep_a_fine_circle_convex_but_real_dents_do_not() {
        let n = 1_000_000;
        let mut circle: Vec<DVec2> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                DVec2::new(8.0 + 7.0 * a.cos(), 8.0 + 7.0 * a.sin())
            })
            .collect();
        // Every third vertex pushed inwards by a grid snap's worth.
        for (i, v) in circle.iter_mut().enumerate().step_by(3) {
            let inward = (DVec2::new(8.0, 8.0) - *v).normalize();
            *v += inward * GRID_SNAP_PX * 0.9 * (i % 2) as f64;
        }
        assert!(is_convex(&circle));
        // A dent of 1e-6 px is geometry, not rounding.
        let inward = (DVec2::new(8.0, 8.0) - circle[10]).normalize();
        circle[10] += inward * 1e-6;
        assert!(!is_convex(&circle));
    }

    #[test]
    fn concave_polygons_are_triangulated_exactly() {
        // An L shape with a repeated and a collinear vertex.
        let l = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 3.0),
            DVec2::new(0.0, 3.0),
        ];
        assert!(!is_convex(&l));
        let tris = ear_clip(&l);
        let sum: f64 = tris.iter().map(|t| area2(t)).sum();
        assert!((sum - area2(&l)).abs() < 1e-12, "{sum}");
        assert!(tris.iter().all(|t| area2(t) > 0.0));
    }

    #[test]
    fn nearness_is_affine_and_bigger_nearer_in_both_projections() {
        let v = perspective(60.0, 64, 64, 0.0, 100.0);
        let tri: Vec<DVec3> = vec![
            DVec3::new(-1.0, -1.0, -2.0),
            DVec3::new(1.0, -1.0, -4.0),
            DVec3::new(0.0, 1.0, -3.0),
        ];
        let p = project(&v, &tri, Rgb8::WHITE, 0, Cull::None).unwrap();
        for (s, w) in p.verts.iter().zip([2.0, 4.0, 3.0]) {
            assert!((p.q(s.x, s.y) - 1.0 / w).abs() < 1e-12);
        }
        let o = View::ortho2(0.0, 10.0, 0.0, 10.0, 10, 10);
        let near = project(
            &o,
            &[
                DVec3::new(1.0, 1.0, 0.5),
                DVec3::new(5.0, 1.0, 0.5),
                DVec3::new(1.0, 5.0, 0.5),
            ],
            Rgb8::WHITE,
            0,
            Cull::None,
        )
        .unwrap();
        let far = project(
            &o,
            &[
                DVec3::new(1.0, 1.0, -0.5),
                DVec3::new(5.0, 1.0, -0.5),
                DVec3::new(1.0, 5.0, -0.5),
            ],
            Rgb8::WHITE,
            0,
            Cull::None,
        )
        .unwrap();
        assert!(near.q(2.0, 2.0) > far.q(2.0, 2.0));
    }
}

#[cfg(test)]
mod determinism {
    use super::scan::tests::Rng;
    use super::*;
    use crate::view::tests::perspective;

    #[test]
    fn output_is_identical_for_any_thread_count() {
        let v = perspective(60.0, 100, 70, 0.0, 100.0);
        let mut rng = Rng(7);
        let polys: Vec<ScreenPoly> = (0..300)
            .filter_map(|i| {
                let c = DVec3::new(
                    rng.next() * 10.0 - 5.0,
                    rng.next() * 8.0 - 4.0,
                    -3.0 - rng.next() * 20.0,
                );
                let tri: Vec<DVec3> = (0..3)
                    .map(|_| c + DVec3::new(rng.next() * 3.0, rng.next() * 3.0, rng.next() * 3.0))
                    .collect();
                project(&v, &tri, Rgb8([i as u8, 255 - i as u8, 77]), i, Cull::None)
            })
            .collect();
        let bg = Background::color(Rgb8([3, 4, 5]));
        for aa in [Aa::None, Aa::Ss(3), Aa::Exact] {
            let run = |n: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .unwrap()
                    .install(|| render(&polys, &bg, 100, 70, aa).to_image())
            };
            let one = run(1);
            assert_eq!(one, run(3), "{aa:?}");
        }
        let run_ref = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| reference::render(&polys, &bg, 100, 70, 6).frame.to_image())
        };
        assert_eq!(run_ref(1), run_ref(2));
    }
}

#[cfg(test)]
mod clip_tests {
    use super::{project, Cull};
    use crate::color::Rgb8;
    use crate::view::clip::clip_polygon;
    use crate::view::tests::perspective;
    use crate::view::W_EPSILON_REL;
    use glam::DVec3;

    #[test]
    fn nothing_behind_the_eye_is_drawn() {
        let v = perspective(90.0, 100, 100, 0.0, 1000.0);
        // Entirely behind the eye (z_eye > 0): a naive divide would mirror it
        // into the view.
        let behind = [
            DVec3::new(-1.0, -1.0, 5.0),
            DVec3::new(1.0, -1.0, 5.0),
            DVec3::new(0.0, 1.0, 5.0),
        ];
        assert!(project(&v, &behind, Rgb8::WHITE, 0, Cull::None).is_none());
        // Straddling the eye plane: only the part in front survives, and it
        // lies on the correct side of the screen.
        let straddle = [
            DVec3::new(-1.0, -1.0, -5.0),
            DVec3::new(1.0, -1.0, -5.0),
            DVec3::new(1.0, -1.0, 5.0),
            DVec3::new(-1.0, -1.0, 5.0),
        ];
        let p = project(&v, &straddle, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert!(p.verts.iter().all(|s| s.y <= 50.0 && s.x.is_finite()));
    }

    #[test]
    fn near_zero_clips_at_a_tiny_positive_w_without_division_by_zero() {
        let v = perspective(90.0, 100, 100, 0.0, 1000.0);
        // A floor through the eye's position: vertex at z_eye = 0 exactly.
        let floor = [
            DVec3::new(-10.0, -1.0, 0.0),
            DVec3::new(10.0, -1.0, 0.0),
            DVec3::new(10.0, -1.0, -100.0),
            DVec3::new(-10.0, -1.0, -100.0),
        ];
        let clipped = clip_polygon(&floor.iter().map(|&p| v.to_clip(p)).collect::<Vec<_>>(), &v);
        assert!(!clipped.is_empty());
        assert!(clipped
            .iter()
            .all(|c| c.w >= W_EPSILON_REL * 1000.0 * (1.0 - 1e-12)));
        let p = project(&v, &floor, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert!(p.plane.iter().all(|c| c.is_finite()));
        // The floor reaches the bottom edge of the screen.
        assert!(p.verts.iter().any(|s| s.y == 0.0));
    }

    #[test]
    fn shared_edges_get_identical_crossings() {
        let v = perspective(60.0, 64, 64, 0.5, 50.0);
        let a = DVec3::new(-3.0, 0.2, -20.0);
        let b = DVec3::new(2.0, -0.1, 3.0);
        let t1 = [a, b, DVec3::new(3.0, 2.0, -10.0)];
        let t2 = [b, a, DVec3::new(-3.0, -2.0, -10.0)];
        let c1 = clip_polygon(&t1.map(|p| v.to_clip(p)), &v);
        let c2 = clip_polygon(&t2.map(|p| v.to_clip(p)), &v);
        let shared: Vec<_> = c1.iter().filter(|p| c2.contains(p)).collect();
        assert!(shared.len() >= 2, "{c1:?} {c2:?}");
    }
}
