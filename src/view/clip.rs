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
//! quarter of the frame (issue 17, item 6); now the crossing is within an
//! `f64` rounding of the true one while the edge is shorter than about
//! 2^100 times that rounding: double-double carries 106 bits, and the
//! crossing's error is its last bit times the edge's length. A polygon of
//! radius 1e30 around a 4-pixel view covers it; of radius 1e50 it drew
//! nothing or half the frame (a stress run, 2026-11-28; a known limit, not
//! yet refused, README's *Limits*). The clip-space coordinates themselves are
//! the projection's `f64` products: their rounding is relative to their own
//! size.

use super::{View, W_EPSILON_REL};
use crate::geom::polygon::clip_against;
use crate::math::DoubleDouble as Dd;
use glam::{DVec2, DVec4};

/// A clip plane of a view: `f(p) >= 0` on the visible side, exactly.
type Plane<'a> = Box<dyn Fn(DVec4) -> Dd + 'a>;

/// The clip planes of a view, each as `f(p) >= 0` on the visible side.
fn planes(view: &View) -> Vec<Plane<'_>> {
    let mut p: Vec<Plane<'_>> = Vec::with_capacity(7);
    // With near > 0 the near plane already keeps w >= near > 0 (z_clip = w
    // in perspective), and |x|, |y| <= w keeps the divide finite: a floor at
    // a fraction of far would only hide near geometry when far is huge
    // (near 0.1, far 5.1e9: a quad 5 units away vanished).
    if view.perspective && view.near <= 0.0 {
        let eps = W_EPSILON_REL * view.far.abs().max(f64::MIN_POSITIVE);
        p.push(Box::new(move |c: DVec4| Dd::sum(c.w, -eps)));
    }
    p.push(Box::new(|c: DVec4| Dd::sum(c.z, -view.near)));
    p.push(Box::new(|c: DVec4| Dd::sum(view.far, -c.z)));
    p.push(Box::new(|c: DVec4| Dd::sum(c.w, c.x)));
    p.push(Box::new(|c: DVec4| Dd::sum(c.w, -c.x)));
    p.push(Box::new(|c: DVec4| Dd::sum(c.w, c.y)));
    p.push(Box::new(|c: DVec4| Dd::sum(c.w, -c.y)));
    p
}

/// `a + (b - a) t` in double-double, rounded once.
fn lerp1(a: f64, b: f64, t: Dd) -> f64 {
    (Dd::sum(b, -a) * t + Dd::from(a)).hi
}

fn lerp4(a: DVec4, b: DVec4, t: Dd) -> DVec4 {
    DVec4::new(
        lerp1(a.x, b.x, t),
        lerp1(a.y, b.y, t),
        lerp1(a.z, b.z, t),
        lerp1(a.w, b.w, t),
    )
}

/// Clips a clip-space polygon to the view volume. The result may be empty.
pub fn clip_polygon(poly: &[DVec4], view: &View) -> Vec<DVec4> {
    let mut cur = poly.to_vec();
    let mut next = Vec::with_capacity(poly.len() + 8);
    for f in planes(view) {
        if cur.is_empty() {
            break;
        }
        if cur.iter().all(|&c| f(c).hi >= 0.0) {
            continue;
        }
        next.clear();
        clip_against(&cur, &f, &mut next, lerp4);
        std::mem::swap(&mut cur, &mut next);
    }
    cur
}

/// Clips a clip-space polygon carrying a 2D attribute per vertex (texture
/// coordinates), by the same planes and the same interpolation as
/// [`clip_polygon`]: the clip-space part of the result is bit for bit what
/// [`clip_polygon`] returns, so the attribute lands on the same vertices.
pub fn clip_carrying(poly: &[(DVec4, DVec2)], view: &View) -> Vec<(DVec4, DVec2)> {
    let mut cur = poly.to_vec();
    let mut next = Vec::with_capacity(poly.len() + 8);
    for f in planes(view) {
        if cur.is_empty() {
            break;
        }
        if cur.iter().all(|&(c, _)| f(c).hi >= 0.0) {
            continue;
        }
        next.clear();
        clip_against(
            &cur,
            |(c, _)| f(c),
            &mut next,
            |a, b, t| {
                (
                    lerp4(a.0, b.0, t),
                    DVec2::new(lerp1(a.1.x, b.1.x, t), lerp1(a.1.y, b.1.y, t)),
                )
            },
        );
        std::mem::swap(&mut cur, &mut next);
    }
    cur
}
