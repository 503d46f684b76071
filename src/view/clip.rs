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

use super::{View, W_EPSILON_REL};
use crate::geom::polygon::clip_against;
use glam::{DVec2, DVec4};

/// The clip planes of a view, each as `f(p) >= 0` on the visible side.
fn planes(view: &View) -> Vec<Box<dyn Fn(DVec4) -> f64 + '_>> {
    let mut p: Vec<Box<dyn Fn(DVec4) -> f64 + '_>> = Vec::with_capacity(7);
    // With near > 0 the near plane already keeps w >= near > 0 (z_clip = w
    // in perspective), and |x|, |y| <= w keeps the divide finite: a floor at
    // a fraction of far would only hide near geometry when far is huge
    // (near 0.1, far 5.1e9: a quad 5 units away vanished).
    if view.perspective && view.near <= 0.0 {
        let eps = W_EPSILON_REL * view.far.abs().max(f64::MIN_POSITIVE);
        p.push(Box::new(move |c: DVec4| c.w - eps));
    }
    p.push(Box::new(|c: DVec4| c.z - view.near));
    p.push(Box::new(|c: DVec4| view.far - c.z));
    p.push(Box::new(|c: DVec4| c.w + c.x));
    p.push(Box::new(|c: DVec4| c.w - c.x));
    p.push(Box::new(|c: DVec4| c.w + c.y));
    p.push(Box::new(|c: DVec4| c.w - c.y));
    p
}

/// Clips a clip-space polygon to the view volume. The result may be empty.
pub fn clip_polygon(poly: &[DVec4], view: &View) -> Vec<DVec4> {
    let mut cur = poly.to_vec();
    let mut next = Vec::with_capacity(poly.len() + 8);
    for f in planes(view) {
        if cur.is_empty() {
            break;
        }
        if cur.iter().all(|&c| f(c) >= 0.0) {
            continue;
        }
        next.clear();
        clip_against(&cur, &f, &mut next, |a, b, t| a + (b - a) * t);
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
        if cur.iter().all(|&(c, _)| f(c) >= 0.0) {
            continue;
        }
        next.clear();
        clip_against(
            &cur,
            |(c, _)| f(c),
            &mut next,
            |a, b, t| (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t),
        );
        std::mem::swap(&mut cur, &mut next);
    }
    cur
}
