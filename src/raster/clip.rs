//! Clipping in homogeneous coordinates, before the perspective divide.
//!
//! A polygon is clipped (Sutherland–Hodgman) against the planes of the clip
//! volume of [`View`]: `-w <= x <= w`, `-w <= y <= w`, `near <= z_clip <= far`,
//! and for perspective views also `w >= W_EPSILON_REL * far`. Every plane is an
//! affine function of the clip-space point, and clip space is a linear image of
//! world space, so the crossing of an edge is found by linear interpolation
//! exactly as in world space: a point behind the eye (`w < 0`) never reaches the
//! divide, so nothing is drawn mirrored.
//!
//! Watertightness across clipping: a crossing is always computed from the
//! *inside* endpoint towards the outside one, so two polygons that share an
//! edge (traversed in opposite directions) get bit-identical new vertices.

use super::{View, W_EPSILON_REL};
use glam::{DVec2, DVec4};

/// The clip planes of a view, each as `f(p) >= 0` on the visible side.
fn planes(view: &View) -> Vec<Box<dyn Fn(DVec4) -> f64 + '_>> {
    let mut p: Vec<Box<dyn Fn(DVec4) -> f64 + '_>> = Vec::with_capacity(7);
    if view.perspective {
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

/// One Sutherland–Hodgman pass: keeps the part where `d(p) >= 0`. `lerp(inside,
/// outside, t)` makes the crossing, always from the inside endpoint.
pub fn clip_against<T: Copy>(
    poly: &[T],
    d: impl Fn(T) -> f64,
    out: &mut Vec<T>,
    lerp: impl Fn(T, T, f64) -> T,
) {
    let n = poly.len();
    if n == 0 {
        return;
    }
    let mut db = d(poly[0]);
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b, da) = (poly[i], poly[j], db);
        db = d(b);
        if da >= 0.0 {
            out.push(a);
            if db < 0.0 && da > 0.0 {
                out.push(lerp(a, b, da / (da - db)));
            }
        } else if db > 0.0 {
            out.push(lerp(b, a, db / (db - da)));
        }
    }
}

/// Clips a 2D polygon to `coord(p) >= value` (`keep_above`) or `<= value`,
/// where `coord` is x (`axis = 0`) or y (`axis = 1`). New vertices get exactly
/// `value` on that axis, so the pieces of a pixel grid meet without gaps.
pub fn clip_axis(poly: &[DVec2], axis: usize, value: f64, keep_above: bool, out: &mut Vec<DVec2>) {
    let d = |p: DVec2| {
        let c = if axis == 0 { p.x } else { p.y };
        if keep_above {
            c - value
        } else {
            value - c
        }
    };
    clip_against(poly, d, out, |a, b, t| {
        let mut p = a + (b - a) * t;
        if axis == 0 {
            p.x = value;
        } else {
            p.y = value;
        }
        p
    });
}

/// Clips a 2D polygon to the half-plane `a*x + b*y + c >= 0`.
pub fn clip_line(poly: &[DVec2], abc: [f64; 3], out: &mut Vec<DVec2>) {
    let d = |p: DVec2| abc[0] * p.x + abc[1] * p.y + abc[2];
    clip_against(poly, d, out, |a, b, t| a + (b - a) * t);
}

#[cfg(test)]
mod tests {
    use super::super::tests::perspective;
    use super::super::{project, Cull};
    use super::*;
    use crate::color::Rgb8;
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
