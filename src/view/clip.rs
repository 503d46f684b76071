//! Clipping to the view volume in homogeneous coordinates, before the
//! perspective divide.
//!
//! A polygon is clipped (Sutherland–Hodgman) against the planes of the clip
//! volume of [`View`]: `-w <= x <= w`, `-w <= y <= w`, `near <= z_clip <= far`,
//! and for perspective views with `near = 0` also `w >= W_EPSILON_REL * far`. Every plane is an
//! affine function of the clip-space point, and clip space is a linear image of
//! world space, so the crossing of an edge is found by linear interpolation
//! exactly as in world space: a point behind the eye (`w < 0`) never reaches the
//! divide, so nothing is drawn mirrored.
//!
//! Watertightness across clipping: a crossing is always computed from the
//! *inside* endpoint towards the outside one, so two polygons that share an
//! edge (traversed in opposite directions) get bit-identical new vertices.
//!
//! Precision: each plane's value is a sum of two coordinates, taken exactly
//! ([`crate::math::DoubleDouble::sum`]; its rounded part decides inside and outside, as
//! a plain `f64` sum would), and the crossing `t = d_a / (d_a - d_b)` and
//! the new vertex `a + (b - a) t` are computed in double-double, then
//! rounded once. In plain `f64` an edge from -3e16 to 3e16 crossed the
//! plane x = -1 at 0 (t rounded to 0.5), so a square at ±1e18 covered a
//! quarter of the frame (issue 17, item 6). Double-double carries 106 bits,
//! and its crossing errs by its last bit times the edge's length: an edge
//! more than about 2^100 times the view (a polygon of radius 1e34 around a
//! 4-pixel view) was placed off by more than the view, and drew a third of
//! it or nothing. So an edge more than `DD_CROSSING_SPAN` (2^40) times `|w|` at
//! its crossing takes the weighted mean `(a d_b' + b d_a) / (d_a + d_b')`
//! from its exact numerator instead ([`Dd::weighted_mean`], `d_b' = -d_b`),
//! within an ulp of the true crossing (and 2^-1070 of the larger end) for
//! any finite clip-space coordinates: n-gons of radius up to 1e300 cover
//! the view, a triangle scaled by 2^1000 draws what it draws unscaled, and
//! planes at z = ±1e-160 under ends of 1e300 are placed right (test
//! `edges_of_any_length_are_clipped_at_the_right_place`). A plane value
//! that overflows to infinity has no such mean: that edge keeps the
//! double-double crossing.
//! The clip-space coordinates themselves are the projection's `f64`
//! products: their rounding is relative to their own size.

use super::{View, W_EPSILON_REL};
use crate::geom::polygon::{clip_against, SignedDistance};
use crate::math::DoubleDouble as Dd;
use glam::{DVec2, DVec4};

/// A clip plane of a view: [`Plane::value`] `>= 0` on the visible side,
/// exactly.
#[derive(Clone, Copy, Debug)]
enum Plane {
    /// `w >= eps`: the floor of a perspective view with near = 0.
    WFloor(f64),
    /// `z_clip >= near`.
    Near(f64),
    /// `z_clip <= far`.
    Far(f64),
    /// `x >= -w`, `x <= w`, `y >= -w`, `y <= w`.
    Left,
    Right,
    Bottom,
    Top,
}

impl Plane {
    /// The plane's signed value at `c`, a sum of two coordinates taken
    /// exactly.
    #[inline]
    fn value(self, c: DVec4) -> Dd {
        match self {
            Plane::WFloor(eps) => Dd::sum(c.w, -eps),
            Plane::Near(near) => Dd::sum(c.z, -near),
            Plane::Far(far) => Dd::sum(far, -c.z),
            Plane::Left => Dd::sum(c.w, c.x),
            Plane::Right => Dd::sum(c.w, -c.x),
            Plane::Bottom => Dd::sum(c.w, c.y),
            Plane::Top => Dd::sum(c.w, -c.y),
        }
    }
}

/// The clip planes of a view, in the order they are clipped against. (Made
/// for every polygon, so without a heap block: with a boxed closure each,
/// clipping 100,000 of polyfill3's cells took 178 M instructions, against
/// 83 M without, callgrind.)
fn planes(view: &View) -> impl Iterator<Item = Plane> {
    w_floor(view).map(Plane::WFloor).into_iter().chain([
        Plane::Near(view.near),
        Plane::Far(view.far),
        Plane::Left,
        Plane::Right,
        Plane::Bottom,
        Plane::Top,
    ])
}

/// The `w` floor of a perspective view with near = 0 ([`Plane::WFloor`]).
fn w_floor(view: &View) -> Option<f64> {
    // With near > 0 the near plane already keeps w >= near > 0 (z_clip = w
    // in perspective), and |x|, |y| <= w keeps the divide finite: a floor at
    // a fraction of far would only hide near geometry when far is huge
    // (near 0.1, far 5.1e9: a quad 5 units away vanished).
    (view.perspective && view.near <= 0.0)
        .then(|| W_EPSILON_REL * view.far.abs().max(f64::MIN_POSITIVE))
}

/// What the first plane that has a vertex outside does to a polygon.
enum Cut {
    /// No plane has: the polygon is inside the volume.
    None,
    /// It has every vertex outside: nothing is left.
    Whole,
    /// It has some: [`clip_by_planes`] clips.
    Some,
}

/// [`clip_by_planes`]'s answer for the polygons it leaves unchanged or
/// empty, most of a big stream's, from one pass over the vertices: each
/// vertex's plane values, rounded, as a bit per plane it lies outside (in
/// the order of [`planes`]), and the first plane with a bit set in any of
/// them. The same rounded values and the same order as the plane loop, so
/// the same answer, without a loop over planes around a loop over
/// vertices (a `match` on the plane for each): dropping a triangle wholly
/// outside a 16x12 view took 434 instructions in [`clip_polygon`], 205
/// with this pass (callgrind, 100,000 random triangles).
fn first_cut(vertices: impl Iterator<Item = DVec4>, view: &View) -> Cut {
    let floor = w_floor(view);
    // Outside is "not >= 0", as `clip_by_planes` tests it: NaN is outside.
    let out = |value: f64, bit: u32| u32::from(value.is_nan() || value < 0.0) << bit;
    let (mut any, mut all) = (0u32, u32::MAX);
    for c in vertices {
        let mask = floor.map_or(0, |eps| out(Plane::WFloor(eps).value(c).hi, 0))
            | out(Plane::Near(view.near).value(c).hi, 1)
            | out(Plane::Far(view.far).value(c).hi, 2)
            | out(Plane::Left.value(c).hi, 3)
            | out(Plane::Right.value(c).hi, 4)
            | out(Plane::Bottom.value(c).hi, 5)
            | out(Plane::Top.value(c).hi, 6);
        any |= mask;
        all &= mask;
    }
    if any == 0 {
        return Cut::None;
    }
    let first = 1 << any.trailing_zeros();
    if all & first != 0 {
        Cut::Whole
    } else {
        Cut::Some
    }
}

/// A plane's value at a vertex, for [`clip_against`]: its crossings carry
/// both endpoints' values, which the exact crossing needs ([`Lerp`]).
#[derive(Clone, Copy)]
struct Distance(Dd);

/// The plane's values at an edge's inside and outside endpoints.
#[derive(Clone, Copy)]
struct Ends {
    inside: Dd,
    outside: Dd,
}

impl SignedDistance for Distance {
    type Param = Ends;
    fn rounded(self) -> f64 {
        self.0.hi
    }
    fn crossing(inside: Self, outside: Self) -> Ends {
        Ends {
            inside: inside.0,
            outside: outside.0,
        }
    }
}

/// How long an edge may be, relative to `|w|` at its crossing, for
/// `a + (b - a) t` in double-double: that errs by about `|b - a| * 2^-102`,
/// so up to 2^40 times `|w|` the crossing is within 2^-62 of `w`, far below
/// a rounding of the divided coordinates (2^-53). Longer edges (a polygon of
/// radius 1e34 around a 4-pixel view drew a third of it) take
/// [`Dd::weighted_mean`], within an ulp of the true crossing. Ordinary
/// scenes have no such edge and draw as they did, bit for bit (the 19
/// scenes of `bench/RESULTS-same-images.md`).
const DD_CROSSING_SPAN: f64 = (1u64 << 40) as f64;

/// How a crossing's coordinates are interpolated between the inside
/// endpoint `a` and the outside one `b`: every coordinate (and a carried
/// attribute) the same way, so the crossing is one point.
#[derive(Clone, Copy)]
enum Lerp {
    /// `a + (b - a) t` in double-double, rounded once.
    Fraction(Dd),
    /// The mean of `a` and `b` weighted by the plane's values, from the
    /// exact numerator (`Dd::weighted_mean`).
    Weighted(Ends),
}

impl Lerp {
    /// The interpolation for the edge from `a` to `b` crossing the plane
    /// where its values are `ends`, and the crossing.
    fn choose(a: DVec4, b: DVec4, ends: Ends) -> (Lerp, DVec4) {
        let fraction = Lerp::Fraction(ends.inside / (ends.inside - ends.outside));
        let p = fraction.at4(a, b);
        // Not `>`: a NaN or infinite span takes the exact route too.
        if (b - a).abs().max_element() <= DD_CROSSING_SPAN * p.w.abs() {
            return (fraction, p);
        }
        // An infinite plane value (an overflowed sum of two coordinates)
        // has no weighted mean: such an edge keeps what it had before.
        let weighted = Lerp::Weighted(ends);
        let q = weighted.at4(a, b);
        match q.is_finite() {
            true => (weighted, q),
            false => (fraction, p),
        }
    }

    fn at(self, a: f64, b: f64) -> f64 {
        match self {
            Lerp::Fraction(t) => (Dd::sum(b, -a) * t + Dd::from(a)).hi,
            Lerp::Weighted(Ends { inside, outside }) => Dd::weighted_mean(a, inside, b, -outside),
        }
    }

    fn at4(self, a: DVec4, b: DVec4) -> DVec4 {
        DVec4::new(
            self.at(a.x, b.x),
            self.at(a.y, b.y),
            self.at(a.z, b.z),
            self.at(a.w, b.w),
        )
    }
}

/// Clips a clip-space polygon to the view volume. The result may be empty.
pub fn clip_polygon(poly: &[DVec4], view: &View) -> Vec<DVec4> {
    clip_by_planes(poly, view, |c| c, |a, b, ends| Lerp::choose(a, b, ends).1)
}

/// Clips a clip-space polygon carrying a 2D attribute per vertex (texture
/// coordinates), by the same planes and the same interpolation as
/// [`clip_polygon`]: the clip-space part of the result is bit for bit what
/// [`clip_polygon`] returns, so the attribute lands on the same vertices.
pub fn clip_carrying(poly: &[(DVec4, DVec2)], view: &View) -> Vec<(DVec4, DVec2)> {
    clip_by_planes(
        poly,
        view,
        |(c, _)| c,
        |a, b, ends| {
            let (lerp, p) = Lerp::choose(a.0, b.0, ends);
            (p, DVec2::new(lerp.at(a.1.x, b.1.x), lerp.at(a.1.y, b.1.y)))
        },
    )
}

/// Sutherland–Hodgman through [`planes`]: vertices `T` at clip-space
/// positions `at(T)`, new ones made by `lerp`. A plane with every vertex
/// inside is passed over, and one with every vertex outside ends it: both
/// are what clipping against it gives (nothing kept, no crossing), without
/// copying the polygon. Most of a big stream's polygons lie outside a
/// plane or inside all of them.
fn clip_by_planes<T: Copy>(
    poly: &[T],
    view: &View,
    at: impl Fn(T) -> DVec4,
    lerp: impl Fn(T, T, Ends) -> T,
) -> Vec<T> {
    match first_cut(poly.iter().map(|&v| at(v)), view) {
        Cut::None => return poly.to_vec(),
        Cut::Whole => return Vec::new(),
        Cut::Some => {}
    }
    // `None` while no plane has cut `poly`.
    let (mut cur, mut spare): (Option<Vec<T>>, Vec<T>) = (None, Vec::new());
    for f in planes(view) {
        let now = cur.as_deref().unwrap_or(poly);
        // Inside and outside as `clip_against` decides them.
        let (mut inside, mut outside) = (false, false);
        for &v in now {
            if f.value(at(v)).hi >= 0.0 {
                inside = true;
            } else {
                outside = true;
            }
        }
        if !outside {
            continue;
        }
        if !inside {
            return Vec::new();
        }
        let mut next = std::mem::take(&mut spare);
        next.clear();
        next.reserve(now.len() + 8);
        clip_against(now, |v| Distance(f.value(at(v))), &mut next, &lerp);
        spare = cur.replace(next).unwrap_or_default();
    }
    cur.unwrap_or_else(|| poly.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::tests::perspective;
    use proptest::prelude::*;

    /// [`first_cut`] as its definition reads: the planes in order, the
    /// first with a vertex outside, whether it has them all.
    fn first_cut_plane_by_plane(poly: &[DVec4], view: &View) -> Cut {
        for f in planes(view) {
            let inside = poly.iter().filter(|&&c| f.value(c).hi >= 0.0).count();
            let outside = poly.len() - inside;
            if outside == poly.len() && outside > 0 {
                return Cut::Whole;
            }
            if outside > 0 {
                return Cut::Some;
            }
        }
        Cut::None
    }

    fn name(c: Cut) -> &'static str {
        match c {
            Cut::None => "none",
            Cut::Whole => "whole",
            Cut::Some => "some",
        }
    }

    /// A coordinate near the planes of the views below, or not finite.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            6 => -3.0..3.0f64,
            2 => prop::sample::select(vec![-1.0, 0.0, 1.0, -0.0, 1e-300, 2.0, 1000.0, 1001.0]),
            1 => prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
        ]
    }

    proptest! {
        #[test]
        fn first_cut_is_the_first_plane_with_a_vertex_outside(
            poly in prop::collection::vec(
                (coordinate(), coordinate(), coordinate(), coordinate())
                    .prop_map(|(x, y, z, w)| DVec4::new(x, y, z, w)),
                0..6,
            ),
            kind in 0..3usize,
        ) {
            let mut view = perspective(90.0, 16, 12, [0.0, 0.5, 0.0][kind], 1000.0);
            view.perspective = kind != 2;
            let fast = name(first_cut(poly.iter().copied(), &view));
            prop_assert_eq!(fast, name(first_cut_plane_by_plane(&poly, &view)));
        }
    }
}
