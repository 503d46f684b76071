//! Stage 2 of the pipeline: a world-space polygon through the [`View`] to a
//! [`ScreenPoly`]. Clipping happens in clip space first
//! ([`crate::view::clip`]); then the divide and the viewport map give screen
//! positions in pixels (y up, (0,0) the image's lower-left corner), snapped
//! to the pixel grid within [`GRID_SNAP_PX`], with an affine nearness over
//! the screen fitted through every vertex (Newell), and concave outlines are
//! cut into triangles (`geom::triangulate`, in the world polygon's plane).

use super::outline::Outline;
use crate::color::Rgb8;
use crate::geom::plane::flat_view;
use crate::geom::polygon::{area2, is_convex, newell_plane, GRID_SNAP_PX};
use crate::geom::triangulate::triangulate;
use crate::stripe::StripeTexture;
use crate::texture::{PolyTexture, Texels};
use crate::view::{clip, View};
use glam::{DVec2, DVec3, DVec4};
use smallvec::SmallVec;
use std::sync::Arc;

/// Which faces to drop (docs/stream-format.md: vertices counter-clockwise seen from the front).
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
    /// A screen-mode pattern (docs/stream-format.md, the IRIS `setpattern`) that replaces
    /// `color`: pixel (x, y) from the lower-left shows texel (x mod SIZE,
    /// y mod SIZE), and the polygon is absent where that texel is transparent.
    Screen(Arc<Texels>),
    /// A pattern in "object" or "uv" placement (docs/stream-format.md), sampled per pixel
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

/// Smooth (Gouraud) lighting's factor over a polygon: per channel, the lit
/// colour over the unlit one, given at the vertices and interpolated
/// perspective-correctly (affine in the polygon's plane, as texture
/// coordinates are), so a screen point's factor is `F(x, y) = N(x, y) /
/// D(x, y)` with `N`, `D` affine over the screen. Fitted by
/// [`crate::texture::map::TexMap::fit`], the texture coordinates' own fit:
/// exact at the vertices of a triangle; for a polygon of more vertices a
/// plane fitted through them (Newell), exact where the vertex values are
/// affine over the polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadeField {
    /// Red and green as the map's `u` and `v`.
    pub rg: crate::texture::map::TexMap,
    /// Blue as its `u`.
    pub b: crate::texture::map::TexMap,
}

impl ShadeField {
    /// The factor at the screen point `(x, y)`, per channel.
    #[inline]
    pub fn at(&self, x: f64, y: f64) -> [f64; 3] {
        let rg = self.rg.uv(x, y);
        [rg.x, rg.y, self.b.uv(x, y).x]
    }

    /// `c` times the factor at `(x, y)`.
    #[inline]
    pub fn apply(&self, c: [f64; 3], x: f64, y: f64) -> [f64; 3] {
        let f = self.at(x, y);
        [c[0] * f[0], c[1] * f[1], c[2] * f[2]]
    }

    /// The mean of the factor along the horizontal segment `a..b` at height
    /// `y`, by 4-point Gauss–Legendre quadrature: the factor is a ratio of
    /// affine functions whose denominator stays far from 0 over a pixel, so
    /// the rule's error (of the order of the 8th derivative) is at rounding
    /// level there; the reference's two-grid residual estimate covers what
    /// is left.
    pub fn mean_along(&self, a: f64, b: f64, y: f64) -> [f64; 3] {
        /// Nodes on [-1, 1] and weights, summing to 2.
        const GL4: [(f64, f64); 4] = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        ];
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let mut m = [0.0; 3];
        for (t, w) in GL4 {
            let f = self.at(mid + half * t, y);
            for ch in 0..3 {
                m[ch] += 0.5 * w * f[ch];
            }
        }
        m
    }
}

/// A polygon ready for a resolver: clipped, projected, counter-clockwise on
/// screen (back faces are reversed when not culled).
///
/// What most polygons lack (a shader, smooth lighting, concave pieces) is
/// held out of line, and what the frame or the vertices decide (the tie
/// floor, [`super::tie_floor`]; the pixel box, [`ScreenPoly::bbox`]) is not
/// kept: a flat triangle is 112 bytes with no heap block (it was 152 and a
/// block of 64; `raster::project::tests::a_flat_triangle_is_112_bytes`).
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenPoly {
    /// The vertices ([`ScreenPoly::verts`]) and the stream position
    /// ([`ScreenPoly::order`]), packed together ([`Outline`]).
    outline: Outline,
    /// Nearness `q = a*x + b*y + c` over the screen (bigger is nearer).
    pub plane: [f64; 3],
    /// Linear-light colour.
    pub color: [f64; 3],
    /// The shader, the smooth lighting and the concave pieces, when any of
    /// them is not the default.
    rare: Option<Box<Rare>>,
}

/// The parts of a [`ScreenPoly`] that few polygons have.
#[derive(Clone, Debug, PartialEq, Default)]
struct Rare {
    shader: Shader,
    shade: Option<Arc<ShadeField>>,
    pieces: Vec<Vec<DVec2>>,
}

/// What a [`ScreenPoly`] without [`Rare`] parts is coloured by.
static FLAT: Shader = Shader::Flat;

impl ScreenPoly {
    /// A flat, convex polygon (the shader [`Shader::Flat`], no smooth
    /// lighting); the setters below add the rest.
    pub fn new(verts: &[DVec2], plane: [f64; 3], color: [f64; 3], order: u32) -> ScreenPoly {
        ScreenPoly {
            outline: Outline::new(verts, order),
            plane,
            color,
            rare: None,
        }
    }

    /// Screen positions in pixels, y up, counter-clockwise, no repeated
    /// neighbours.
    #[inline]
    pub fn verts(&self) -> &[DVec2] {
        self.outline.verts()
    }

    /// Position in the stream: draw order, for visibility ties.
    #[inline]
    pub fn order(&self) -> u32 {
        self.outline.order()
    }

    /// The pixels the polygon can touch, inclusive-exclusive: `x0..x1`,
    /// `y0..y1` (y up), from its vertices' floors and ceilings, not below 0.
    /// Not cut to the frame: a resolver cuts it to the tile it draws
    /// ([`super::bin`] to the frame).
    ///
    /// Worked out where it is needed rather than kept: four numbers a
    /// polygon were 16 of its bytes, and a frame holds every polygon at once
    /// (bench/memory.sh); a triangle's box is a few compares.
    pub fn bbox(&self) -> [u32; 4] {
        let [x0, y0, x1, y1] = super::visible::bounds(self.verts());
        // `as` saturates: a vertex beyond u32 pixels is cut by the tile.
        [x0.floor(), y0.floor(), x1.ceil(), y1.ceil()].map(|c| c.max(0.0) as u32)
    }

    /// Changes the out-of-line parts, dropping the block when they are all
    /// the defaults again: two polygons that differ only in having had a
    /// shader set and reset compare equal.
    /// (A default is changed on the stack first: a flat polygon makes no
    /// block to drop.)
    fn change_rare(&mut self, change: impl FnOnce(&mut Rare)) {
        let mut rare = self.rare.take().map_or_else(Rare::default, |b| *b);
        change(&mut rare);
        if rare != Rare::default() {
            self.rare = Some(Box::new(rare));
        }
    }

    /// What colours the polygon instead of `color`, if anything: one
    /// source per polygon, so no precedence between sources is needed.
    #[inline]
    pub fn shader(&self) -> &Shader {
        self.rare.as_ref().map_or(&FLAT, |r| &r.shader)
    }

    /// Sets [`ScreenPoly::shader`].
    pub fn set_shader(&mut self, shader: Shader) {
        self.change_rare(|r| r.shader = shader);
    }

    /// Smooth lighting: a per-channel factor that multiplies the colour the
    /// shader gives, varying over the polygon ([`ShadeField`]); `None` for
    /// unlit and flat-lit polygons (flat lighting is already in `color` or
    /// the texture's intrinsic colour).
    #[inline]
    pub fn shade(&self) -> Option<&Arc<ShadeField>> {
        self.rare.as_ref().and_then(|r| r.shade.as_ref())
    }

    /// Sets [`ScreenPoly::shade`].
    pub fn set_shade(&mut self, shade: Option<Arc<ShadeField>>) {
        self.change_rare(|r| r.shade = shade);
    }

    /// Convex pieces that tile the polygon exactly: none when it is convex
    /// (it is its own piece, see [`ScreenPoly::piece`]), else its
    /// triangles, clipped and projected (`concave_pieces`). (A copy of a
    /// convex polygon's vertices cost a million allocations on a million
    /// triangles, and the exact resolver a cache miss more per polygon and
    /// tile to reach them.)
    pub fn pieces(&self) -> &[Vec<DVec2>] {
        self.rare.as_ref().map_or(&[], |r| &r.pieces)
    }

    /// Sets [`ScreenPoly::pieces`] (none: the polygon is convex).
    pub fn set_pieces(&mut self, pieces: Vec<Vec<DVec2>>) {
        self.change_rare(|r| r.pieces = pieces);
    }

    /// How many convex pieces tile the polygon.
    pub fn piece_count(&self) -> usize {
        self.pieces().len().max(1)
    }

    /// Convex piece `k` of the polygon (`k < piece_count()`).
    pub fn piece(&self, k: usize) -> &[DVec2] {
        let pieces = self.pieces();
        if pieces.is_empty() {
            self.verts()
        } else {
            &pieces[k]
        }
    }

    /// The screen-mode pattern, if that is the shader.
    #[inline]
    pub fn screen(&self) -> Option<&Arc<Texels>> {
        match self.shader() {
            Shader::Screen(t) => Some(t),
            _ => None,
        }
    }

    /// The placed texture, if that is the shader.
    #[inline]
    pub fn texture(&self) -> Option<&Arc<PolyTexture>> {
        match self.shader() {
            Shader::Texture(t) => Some(t),
            _ => None,
        }
    }

    /// The stripe texture, if that is the shader.
    #[inline]
    pub fn stripe(&self) -> Option<&Arc<StripeTexture>> {
        match self.shader() {
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
            Some(p) => p.at_over(x, y, self.color),
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
        let c = match self.texture() {
            Some(t) => match t.eval(sx, sy) {
                Eval::Box => self.color_at_point(x, y, sx, sy),
                Eval::Color(c) => c,
            },
            // Stripes and flat colours.
            None => self.color_at_point(x, y, sx, sy),
        };
        match self.shade() {
            Some(s) => c.map(|c| s.apply(c, sx, sy)),
            None => c,
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

/// [`try_project`], under the name the tests use.
#[cfg(test)]
pub(crate) use try_project as project;

/// Why a polygon did not reach the screen ([`try_project`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dropped {
    /// A vertex is infinite or NaN once transformed (an overflowing
    /// transform or camera).
    NotFinite,
    /// Nothing of it lies inside the view volume.
    Outside,
    /// Dropped by `cull` (`--cull`).
    Culled,
    /// Edge-on, or smaller than the pixel grid's snap: no area on screen.
    NoArea,
}

/// How many polygons of a frame reached the screen, and why the others did
/// not: what `scene-render` reports when a frame draws nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Polygons drawn.
    pub drawn: u64,
    /// Their summed area on screen, in pixels (overlaps counted twice).
    pub drawn_area: f64,
    /// Polygons with a vertex that is not finite in clip space.
    pub not_finite: u64,
    /// Polygons wholly outside the view volume.
    pub outside: u64,
    /// Polygons culled as back (or front) faces.
    pub culled: u64,
    /// Polygons with no area on screen.
    pub no_area: u64,
}

impl Tally {
    /// Counts one polygon's fate.
    pub fn count(&mut self, fate: Result<&ScreenPoly, Dropped>) {
        match fate {
            Ok(p) => {
                self.drawn += 1;
                self.drawn_area += area2(p.verts()).abs() / 2.0;
            }
            Err(Dropped::NotFinite) => self.not_finite += 1,
            Err(Dropped::Outside) => self.outside += 1,
            Err(Dropped::Culled) => self.culled += 1,
            Err(Dropped::NoArea) => self.no_area += 1,
        }
    }

    /// Adds the counts of `other` (polygons counted apart, in parallel).
    pub fn add(&mut self, other: &Tally) {
        self.drawn += other.drawn;
        self.drawn_area += other.drawn_area;
        self.not_finite += other.not_finite;
        self.outside += other.outside;
        self.culled += other.culled;
        self.no_area += other.no_area;
    }

    /// Every polygon counted.
    pub fn total(&self) -> u64 {
        self.drawn + self.not_finite + self.outside + self.culled + self.no_area
    }
}

/// Clips, projects and orients one world polygon, or says why nothing of it
/// reaches the screen.
///
/// A concave outline is also cut into triangles ([`ScreenPoly::pieces`]) in
/// O(n log n) time, however many vertices it has (`concave_pieces`).
pub fn try_project(
    view: &View,
    world: &[DVec3],
    color: Rgb8,
    order: u32,
    cull: Cull,
) -> Result<ScreenPoly, Dropped> {
    // On the stack for a quad or less: a heap block for each was a fifth of
    // projecting a polygon that is then dropped (callgrind).
    let clip_space: SmallVec<[DVec4; 4]> = world.iter().map(|&p| view.to_clip(p)).collect();
    if clip_space.iter().any(|c| !c.is_finite()) {
        return Err(Dropped::NotFinite);
    }
    let clipped = clip::clip_polygon(&clip_space, view);
    if clipped.len() < 3 {
        return Err(Dropped::Outside);
    }
    // On the stack up to an octagon (a clipped quad has at most eight
    // vertices); the polygon keeps its own copy (`Outline`).
    let mut verts: SmallVec<[DVec2; 8]> = SmallVec::with_capacity(clipped.len());
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
        return Err(Dropped::NoArea);
    }
    let a2 = area2(&verts);
    if a2 == 0.0 || !a2.is_finite() {
        return Err(Dropped::NoArea);
    }
    match cull {
        Cull::Back if a2 < 0.0 => return Err(Dropped::Culled),
        Cull::Front if a2 > 0.0 => return Err(Dropped::Culled),
        _ => {}
    }
    if a2 < 0.0 {
        verts.reverse();
        qs.reverse();
    }
    let plane = newell_plane(&verts, &qs).ok_or(Dropped::NoArea)?;
    let pieces = if is_convex(&verts) {
        Vec::new()
    } else {
        let whole = clipped[..] == clip_space[..];
        concave_pieces(view, world, &clip_space, whole, a2 < 0.0).ok_or(Dropped::NoArea)?
    };
    let c = color.to_linear_f64();
    let mut p = ScreenPoly::new(&verts, plane, c, order);
    if !pieces.is_empty() {
        // A convex polygon, most of them, is its own piece: nothing to set.
        p.set_pieces(pieces);
    }
    Ok(p)
}

/// The convex pieces of a concave polygon on screen: its triangles, found in
/// the world polygon's own plane ([`triangulate`] on its [`flat_view`], O(n
/// log n) time, exact: they tile it) and each clipped and projected as the
/// outline is, counter-clockwise on screen (`reversed` when the outline was
/// turned round). `whole` says the view volume clips nothing, so each
/// triangle's corners are outline vertices, taken as projected once.
///
/// Triangulating before clipping keeps the input a simple polygon, as the
/// stream's records are checked to be ([`crate::geom::simple`]): clipping a
/// concave outline joins its visible parts by zero-width bridges along the
/// faces of the view volume. A clipped triangle's new corners are computed
/// from the same edges, from the same inside endpoint, as the outline's
/// ([`clip::clip_polygon`]), so the pieces tile the clipped outline up to that
/// rounding. `None` when the polygon has no area in its plane: nothing to draw.
fn concave_pieces(
    view: &View,
    world: &[DVec3],
    clip_space: &[DVec4],
    whole: bool,
    reversed: bool,
) -> Option<Vec<Vec<DVec2>>> {
    let triangles = triangulate(&flat_view(world)?);
    if triangles.is_empty() {
        return None;
    }
    let screen = |c: DVec4| view.to_screen(c).map(snap_grid);
    let at: Vec<DVec2> = if whole {
        clip_space.iter().map(|&c| screen(c)).collect()
    } else {
        Vec::new()
    };
    let mut pieces = Vec::with_capacity(triangles.len());
    for t in triangles {
        let mut piece: Vec<DVec2> = if whole {
            t.iter().map(|&i| at[i as usize]).collect()
        } else {
            let corners = t.map(|i| clip_space[i as usize]);
            clip::clip_polygon(&corners, view)
                .into_iter()
                .map(screen)
                .collect()
        };
        piece.dedup();
        while piece.len() > 1 && piece.first() == piece.last() {
            piece.pop();
        }
        if reversed {
            piece.reverse();
        }
        if piece.len() >= 3 && area2(&piece) > 0.0 {
            pieces.push(piece);
        }
    }
    (!pieces.is_empty()).then_some(pieces)
}

#[cfg(test)]
mod tests {
    use super::super::tests::poly2;
    use super::*;
    use crate::math::sum_compensated;
    use crate::view::tests::perspective;

    /// A right triangle 10 pixels a side, corner at (10, 5), in a 100x50 frame.
    fn right_triangle() -> ScreenPoly {
        let v = View::ortho2(0.0, 100.0, 0.0, 50.0, 100, 50);
        poly2(
            &v,
            &[[10.0, 5.0], [20.0, 5.0], [20.0, 15.0]],
            Rgb8::WHITE,
            0,
        )
        .unwrap()
    }

    /// A million triangles keep a million screen polygons until the frame
    /// is drawn: a flat triangle's must need no heap block of its own.
    #[test]
    fn a_flat_triangle_is_112_bytes() {
        assert!(std::mem::size_of::<ScreenPoly>() <= 112);
        let p = right_triangle();
        assert!(p.outline.is_inline());
        assert!(p.rare.is_none());
        assert_eq!(p.shader(), &Shader::Flat);
        assert_eq!(p.piece_count(), 1);
        // Set and reset, it is the polygon it was, block and all.
        let mut q = p.clone();
        q.set_pieces(vec![p.verts().to_vec()]);
        q.set_shader(Shader::Flat);
        assert!(q.rare.is_some() && q != p);
        q.set_pieces(Vec::new());
        assert!(q.rare.is_none());
        assert_eq!(q, p);
    }

    #[test]
    fn ortho2_maps_world_units_to_pixels() {
        let p = right_triangle();
        assert_eq!(p.verts()[0], DVec2::new(10.0, 5.0));
        assert_eq!(p.bbox(), [10, 5, 20, 15]);
    }

    #[test]
    fn culling_follows_the_ccw_front_rule_and_back_faces_are_reoriented() {
        let v = View::ortho2(0.0, 10.0, 0.0, 10.0, 10, 10);
        let ccw: Vec<DVec3> = [[1.0, 1.0], [5.0, 1.0], [1.0, 5.0]]
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.0))
            .collect();
        let cw: Vec<DVec3> = ccw.iter().rev().copied().collect();
        assert!(project(&v, &ccw, Rgb8::WHITE, 0, Cull::Back).is_ok());
        assert_eq!(
            project(&v, &cw, Rgb8::WHITE, 0, Cull::Back).err(),
            Some(Dropped::Culled)
        );
        assert_eq!(
            project(&v, &ccw, Rgb8::WHITE, 0, Cull::Front).err(),
            Some(Dropped::Culled)
        );
        let p = project(&v, &cw, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert!(area2(p.verts()) > 0.0);
    }

    #[test]
    fn snap_sized_kinks_keep_a_fine_circle_convex_but_real_dents_do_not() {
        let n = 1_000_000;
        let mut circle: Vec<DVec2> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                DVec2::new(
                    8.0 + 7.0 * crate::math::cos(a),
                    8.0 + 7.0 * crate::math::sin(a),
                )
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

    /// The pieces of a concave polygon: counter-clockwise, with positive
    /// area, adding up to the outline's area within 1e-12.
    fn assert_tiled(p: &ScreenPoly) {
        assert!(!p.pieces().is_empty());
        assert!(p.pieces().iter().all(|t| area2(t) > 0.0));
        let sum = sum_compensated(p.pieces().iter().map(|t| area2(t)));
        let (o, n) = (p.verts()[0], p.verts().len());
        let a = sum_compensated(
            (0..n).map(|i| (p.verts()[i] - o).perp_dot(p.verts()[(i + 1) % n] - o)),
        );
        assert!((sum - a).abs() <= 1e-12 * a, "{sum} vs {a}");
    }

    fn world(v: &[[f64; 2]]) -> Vec<DVec3> {
        v.iter().map(|&[x, y]| DVec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn concave_pieces_tile_the_outline_whole_clipped_and_turned_round() {
        // An arch (concave), with a repeated and a collinear vertex.
        let arch = world(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 2.0],
            [1.0, 2.0],
            [2.0, 2.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [1.5, 3.0],
            [0.0, 3.0],
        ]);
        let whole = View::ortho2(-1.0, 4.0, -1.0, 4.0, 50, 50);
        let p = project(&whole, &arch, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert_tiled(&p);
        assert!((area2(p.verts()) - 2.0 * 7.0 * 100.0).abs() < 1e-9);
        // Cut below the arch's top: two legs, which the clipped outline joins
        // by a zero-width bridge along the image's top edge.
        let legs = View::ortho2(-1.0, 4.0, -1.0, 1.5, 50, 25);
        let p = project(&legs, &arch, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert_tiled(&p);
        assert!((area2(p.verts()) - 2.0 * 3.0 * 100.0).abs() < 1e-9);
        assert!(p.pieces().iter().flatten().all(|v| v.y <= 25.0));
        // Seen from behind, and through a perspective camera that clips it
        // at the near plane.
        let back: Vec<DVec3> = arch.iter().rev().copied().collect();
        let p = project(&whole, &back, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert_tiled(&p);
        let v = perspective(60.0, 64, 64, 0.5, 100.0);
        let floor: Vec<DVec3> = arch
            .iter()
            .map(|w| DVec3::new(w.x * 4.0 - 6.0, -1.0, 2.0 - w.y * 8.0))
            .collect();
        let p = project(&v, &floor, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert_tiled(&p);
    }

    #[test]
    fn a_concave_star_of_200000_vertices_is_cut_into_triangles() {
        let n = 200_000;
        let star: Vec<DVec3> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                let r = if i % 2 == 0 { 7.0 } else { 5.0 };
                DVec3::new(
                    8.0 + r * crate::math::cos(a),
                    8.0 + r * crate::math::sin(a),
                    0.0,
                )
            })
            .collect();
        let v = View::ortho2(0.0, 16.0, 0.0, 16.0, 16, 16);
        let p = project(&v, &star, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert_eq!(p.pieces().len(), n - 2);
        assert_tiled(&p);
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
        for (s, w) in p.verts().iter().zip([2.0, 4.0, 3.0]) {
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
        assert_eq!(
            project(&v, &behind, Rgb8::WHITE, 0, Cull::None).err(),
            Some(super::Dropped::Outside)
        );
        // Straddling the eye plane: only the part in front survives, and it
        // lies on the correct side of the screen.
        let straddle = [
            DVec3::new(-1.0, -1.0, -5.0),
            DVec3::new(1.0, -1.0, -5.0),
            DVec3::new(1.0, -1.0, 5.0),
            DVec3::new(-1.0, -1.0, 5.0),
        ];
        let p = project(&v, &straddle, Rgb8::WHITE, 0, Cull::None).unwrap();
        assert!(p.verts().iter().all(|s| s.y <= 50.0 && s.x.is_finite()));
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
        assert!(p.verts().iter().any(|s| s.y == 0.0));
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
