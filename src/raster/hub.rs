//! The showers of a crowded pixel indexed by their angle at a vertex their
//! polygons share, for `--aa exact`'s check in [`super::visible`].
//!
//! A fan of triangles around one vertex (a sphere's pole seen down its axis,
//! an OBJ face of many corners, a triangle fan) puts every triangle in the
//! pixels around that vertex, the *hub*. Each fragment arriving there is
//! checked against every fragment that showed before it, which made such a
//! pixel quadratic in its fragments: a fan of 40,000 triangles took 17.6 s.
//!
//! A convex polygon lies in its *cone* at each of its vertices: the angle
//! between its two edges there. Two convex polygons with a vertex at the
//! same point whose cones share no interior share no interior either, so
//! neither do their fragments in any pixel, and the check's separating-axis
//! test (`visible::disjoint`) finds them apart (for convex polygons it is
//! complete, and it allows [`super::coverage::SEPARATION_EPS`] more). Such a
//! pair needs no test at all: only the showers whose cones meet the
//! newcomer's ([`HubIndex::candidates`]), and those not indexed, are
//! tested, in O(log n) plus what they return.
//!
//! Angles are compared as pseudo-angles ([`pseudo_angle`]), which rounding
//! moves by a few ulps; every query is widened by [`CONE_PAD`], far more
//! than that, so a shower is left out only where the two cones are apart by
//! more than the pad. Leaving out more would change no result anyway (it
//! only spares tests that find a pair apart), but leaving out one that
//! overlaps could.

use glam::DVec2;
use std::collections::BTreeMap;

/// A pixel is indexed once this many showers have shown in it...
pub(super) const HUB_MIN_SHOWERS: usize = 32;

/// ... and again at four times as many, if no vertex was shared by most of
/// them before (the attempts cost O(n) each, so O(n) in all).
pub(super) const HUB_RETRY_FACTOR: usize = 4;

/// Polygons with more vertices are not looked up for the hub (each
/// fragment would scan its polygon's vertices): their showers are tested
/// one by one, as before.
pub(super) const HUB_MAX_VERTICES: usize = 16;

/// How far (pseudo-angle units, 4 to the turn) a query is widened on each
/// side. Rounding moves a pseudo-angle by about 1e-16 of it; at a hub 10^6
/// pixels away the pad still spans under 1e-3 pixel, and a wider query only
/// tests more showers.
pub(super) const CONE_PAD: f64 = 1e-9;

/// A direction's angle from +x counter-clockwise, as a number in `[0, 4)`
/// that increases with it (exactly in exact arithmetic; within a few ulps
/// in f64): the "diamond angle", one division and no `atan2`.
pub(super) fn pseudo_angle(d: DVec2) -> f64 {
    let p = d.x / (d.x.abs() + d.y.abs());
    if d.y >= 0.0 {
        1.0 - p
    } else {
        3.0 + p
    }
}

/// The cone of the convex counter-clockwise polygon `verts` at its vertex
/// equal to `hub`, as pseudo-angles `(from, to)`, counter-clockwise from the
/// next vertex's direction to the previous one's (`to < from` when it
/// crosses +x); `None` if `hub` is not one of its vertices or the cone is
/// degenerate.
pub(super) fn cone_at(verts: &[DVec2], hub: DVec2) -> Option<(f64, f64)> {
    let n = verts.len();
    if !(3..=HUB_MAX_VERTICES).contains(&n) {
        return None;
    }
    let i = verts.iter().position(|&v| v == hub)?;
    let next = verts[(i + 1) % n] - hub;
    let prev = verts[(i + n - 1) % n] - hub;
    // Turning left from `next` to `prev`: the cone is under half a turn.
    // Anything else (a clockwise outline, a straight angle) is not indexed.
    if next.perp_dot(prev) <= 0.0 {
        return None;
    }
    let (from, to) = (pseudo_angle(next), pseudo_angle(prev));
    (from.is_finite() && to.is_finite() && from != to).then_some((from, to))
}

/// The cones of the showers of one pixel at its hub, pairwise apart, and
/// the showers that are not among them.
pub(super) struct HubIndex {
    /// The shared vertex.
    pub(super) at: DVec2,
    /// Each cone (a piece of one, where it crosses +x) keyed by the bits of
    /// its start (non-negative f64s order as their bits do): its end and
    /// the shower's index in the pixel's list. No two share an interior.
    cones: BTreeMap<u64, (f64, u32)>,
    /// Showers whose polygon has no cone at the hub, or whose cone meets
    /// one indexed before: tested one by one.
    pub(super) others: Vec<u32>,
}

impl HubIndex {
    /// An empty index about `at`.
    pub(super) fn new(at: DVec2) -> HubIndex {
        HubIndex {
            at,
            cones: BTreeMap::new(),
            others: Vec::new(),
        }
    }

    /// Adds shower `shower`, whose polygon has the cone `cone` at the hub (or
    /// none).
    pub(super) fn insert(&mut self, shower: u32, cone: Option<(f64, f64)>) {
        match cone {
            Some(c) if pieces(c, 0.0).all(|(lo, hi)| self.free(lo, hi)) => {
                for (lo, hi) in pieces(c, 0.0) {
                    self.cones.insert(lo.to_bits(), (hi, shower));
                }
            }
            _ => self.others.push(shower),
        }
    }

    /// Whether no indexed cone meets the open interval `(lo, hi)`.
    fn free(&self, lo: f64, hi: f64) -> bool {
        let before = self.cones.range(..lo.to_bits()).next_back();
        before.is_none_or(|(_, &(end, _))| end <= lo)
            && self
                .cones
                .range(lo.to_bits()..hi.to_bits())
                .next()
                .is_none()
    }

    /// Pushes onto `out` every shower whose cone meets `cone` widened by
    /// [`CONE_PAD`] on each side, and every shower not indexed: the only
    /// ones a polygon with that cone at the hub can overlap. A shower may
    /// come twice.
    pub(super) fn candidates(&self, cone: (f64, f64), out: &mut Vec<u32>) {
        out.extend_from_slice(&self.others);
        for (lo, hi) in pieces(cone, CONE_PAD) {
            let before = self.cones.range(..lo.to_bits()).next_back();
            if let Some((_, &(end, shower))) = before {
                if end > lo {
                    out.push(shower);
                }
            }
            let within = self.cones.range(lo.to_bits()..hi.to_bits());
            out.extend(within.map(|(_, &(_, shower))| shower));
        }
    }
}

/// The cone `(from, to)` widened by `pad` on each side, as at most three
/// intervals `lo < hi` within `[0, 4]` (a cone crossing +x, or widened
/// across it, is cut there).
fn pieces((from, to): (f64, f64), pad: f64) -> impl Iterator<Item = (f64, f64)> {
    let (lo, hi) = (from - pad, if to < from { to + 4.0 } else { to } + pad);
    // Within [-pad, 8 + pad]: cut at 0, 4 and 8, each part moved into [0, 4].
    [(-4.0, 0.0), (0.0, 4.0), (4.0, 8.0), (8.0, 12.0)]
        .into_iter()
        .filter_map(move |(a, b)| {
            let (l, h) = (lo.max(a), hi.min(b));
            (l < h).then_some((l - a, h - a))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn pseudo_angles_increase_counter_clockwise_from_plus_x() {
        let turn: Vec<f64> = (0..64)
            .map(|k| {
                let (sin, cos) = crate::math::sin_cos(std::f64::consts::TAU * k as f64 / 64.0);
                pseudo_angle(DVec2::new(cos, sin))
            })
            .collect();
        assert_eq!(turn[0], 0.0);
        assert!(turn.windows(2).all(|w| w[0] < w[1]), "{turn:?}");
        assert!(turn[63] < 4.0);
        assert_eq!(pseudo_angle(DVec2::new(0.0, 1.0)), 1.0);
        assert_eq!(pseudo_angle(DVec2::new(-1.0, 0.0)), 2.0);
        assert_eq!(pseudo_angle(DVec2::new(0.0, -1.0)), 3.0);
    }

    #[test]
    fn a_cone_across_plus_x_is_cut_there() {
        let cut: Vec<_> = pieces((3.5, 0.5), 0.0).collect();
        assert_eq!(cut, [(3.5, 4.0), (0.0, 0.5)]);
        let padded: Vec<_> = pieces((0.0, 1.0), 0.25).collect();
        assert_eq!(padded, [(3.75, 4.0), (0.0, 1.25)]);
    }

    #[test]
    fn only_a_counter_clockwise_corner_under_half_a_turn_has_a_cone() {
        let hub = DVec2::new(1.0, 1.0);
        let (a, b) = (DVec2::new(3.0, 1.0), DVec2::new(1.0, 3.0));
        assert!(cone_at(&[hub, a, b], hub).is_some());
        assert_eq!(cone_at(&[hub, b, a], hub), None, "clockwise");
        let straight = [DVec2::new(0.0, 1.0), hub, DVec2::new(2.0, 1.0), b];
        assert_eq!(cone_at(&straight, hub), None, "a straight angle");
        assert_eq!(
            cone_at(&[a, b, DVec2::new(0.0, 0.0)], hub),
            None,
            "not a vertex"
        );
    }

    /// A fan's wedges touch along their shared edges and are indexed; a
    /// wedge overlapping one is not, and is a candidate for everything.
    #[test]
    fn touching_cones_are_indexed_and_overlapping_ones_kept_aside() {
        let hub = DVec2::new(0.5, 0.5);
        let rim = |k: u32| {
            let (sin, cos) = crate::math::sin_cos(std::f64::consts::TAU * f64::from(k) / 12.0);
            hub + 10.0 * DVec2::new(cos, sin)
        };
        let mut index = HubIndex::new(hub);
        for k in 0..12 {
            let cone = cone_at(&[hub, rim(k), rim(k + 1)], hub);
            assert!(cone.is_some());
            index.insert(k, cone);
        }
        assert!(index.others.is_empty());
        let across = cone_at(&[hub, rim(2), rim(5)], hub);
        index.insert(12, across);
        assert_eq!(index.others, [12]);
        let mut out = Vec::new();
        index.candidates(cone_at(&[hub, rim(7), rim(8)], hub).unwrap(), &mut out);
        out.sort_unstable();
        out.dedup();
        // Its neighbours (touching, within the pad), itself, and the one aside.
        assert_eq!(out, [6, 7, 8, 12]);
    }

    /// Two triangles with a vertex at the hub.
    fn pair() -> impl Strategy<Value = [[DVec2; 3]; 2]> {
        let point = (-50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y)| DVec2::new(x, y));
        let tri = (point.clone(), point).prop_filter_map("counter-clockwise", |(b, c)| {
            let hub = DVec2::new(0.25, -0.75);
            let area = (b - hub).perp_dot(c - hub);
            (area.abs() > 1e-3).then_some(if area > 0.0 { [hub, b, c] } else { [hub, c, b] })
        });
        [tri.clone(), tri]
    }

    /// Whether two convex counter-clockwise polygons share interior, by an
    /// oracle independent of cones: some point of one (a vertex nudged
    /// inward, or the centroid) lies strictly inside the other, or two
    /// edges cross properly.
    fn overlap(a: &[DVec2], b: &[DVec2]) -> bool {
        let inside = |p: DVec2, poly: &[DVec2]| {
            (0..poly.len()).all(|i| {
                let (s, e) = (poly[i], poly[(i + 1) % poly.len()]);
                (e - s).perp_dot(p - s) > 1e-9
            })
        };
        let centroid = |p: &[DVec2]| p.iter().copied().sum::<DVec2>() / p.len() as f64;
        let nudged = |p: &[DVec2]| {
            let c = centroid(p);
            p.iter()
                .map(move |&v| v + (c - v) * 1e-6)
                .collect::<Vec<_>>()
        };
        let cross = (0..a.len()).any(|i| {
            (0..b.len()).any(|j| {
                let (p, q) = (a[i], a[(i + 1) % a.len()]);
                let (r, s) = (b[j], b[(j + 1) % b.len()]);
                let d1 = (q - p).perp_dot(r - p);
                let d2 = (q - p).perp_dot(s - p);
                let d3 = (s - r).perp_dot(p - r);
                let d4 = (s - r).perp_dot(q - r);
                d1 * d2 < -1e-12 && d3 * d4 < -1e-12
            })
        });
        cross
            || nudged(a).iter().any(|&p| inside(p, b))
            || nudged(b).iter().any(|&p| inside(p, a))
            || inside(centroid(a), b)
            || inside(centroid(b), a)
    }

    proptest! {
        /// A shower the index leaves out never overlaps the newcomer.
        #[test]
        fn a_shower_left_out_never_overlaps(pair in pair()) {
            let hub = pair[0][0];
            let mut index = HubIndex::new(hub);
            index.insert(0, cone_at(&pair[0], hub));
            let mut out = Vec::new();
            index.candidates(cone_at(&pair[1], hub).unwrap(), &mut out);
            if out.is_empty() {
                prop_assert!(!overlap(&pair[0], &pair[1]), "{pair:?}");
            }
        }
    }
}
