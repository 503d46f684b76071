//! Indexes of a crowded pixel's showers, for `--aa exact`'s check in
//! [`super::visible`]: each fragment arriving in a pixel is checked against
//! every fragment that showed there before it, which is quadratic where
//! thousands of polygons meet one pixel without overlapping.
//!
//! - **A hub** ([`HubIndex`]). A fan of triangles round one vertex (a
//!   sphere's pole seen down its axis, an OBJ face of many corners drawn as
//!   a fan, a triangle fan) puts every triangle in the pixels round that
//!   vertex. A polygon lies in its *cone* at each of its vertices: the
//!   angle, seen from there, that holds all its other vertices (so their
//!   hull, so the polygon; [`cone_at`]). Two polygons with a vertex at the
//!   same point whose cones share no interior share no interior either, so
//!   neither do their fragments in any pixel.
//! - **An axis** ([`AxisIndex`]). A strip of thin polygons side by side
//!   (a mesh's long triangles, a sphere's slices) crossing one pixel shares
//!   no one vertex, but each fragment projects onto the axis across the
//!   strip as a short interval. Two convex fragments whose intervals on
//!   any axis are apart are apart.
//!
//! Either way a newcomer is tested only against the showers its key meets
//! ([`Crowd::candidates`]) and those not indexed, in O(log n) plus what they
//! return. Every shower left out is apart from the newcomer by more than a
//! pad, which the check's separating-axis test (`visible::disjoint`,
//! complete for convex polygons in 2D, with
//! [`super::coverage::SEPARATION_EPS`] more) finds apart too, but for edges
//! shorter than [`super::coverage::EDGE_EPS`], which it skips: fragments
//! with one are never indexed or left out (`visible::indexable`). So the
//! index spares tests and decides nothing (docs/rendering.md, *Crowds by an
//! index*, says how far that has been checked).

use glam::DVec2;
use std::collections::BTreeMap;

/// A pixel is indexed once this many showers have shown in it...
pub(super) const CROWD_MIN_SHOWERS: usize = 32;

/// ... and again at four times as many, if neither index suited most of
/// them before (the attempts cost O(n) each, so O(n) in all).
pub(super) const CROWD_RETRY_FACTOR: usize = 4;

/// Polygons with more vertices are not looked up for the hub (each
/// fragment would scan its polygon's vertices): their showers are tested
/// one by one, as before.
pub(super) const HUB_MAX_VERTICES: usize = 16;

/// How far (pseudo-angle units, 4 to the turn) a query is widened on each
/// side. Rounding moves a pseudo-angle by about 1e-16 of it; at a hub 10^6
/// pixels away the pad still spans under 1e-3 pixel, and a wider query only
/// tests more showers.
pub(super) const CONE_PAD: f64 = 1e-9;

/// Fragments spanning more of the axis (pixels) are not indexed by it but
/// tested one by one: a query looks back as far as the widest span indexed.
pub(super) const AXIS_MAX_WIDTH: f64 = 0.125;

/// How far (pixels) a span query is widened on each side: above the
/// rounding of a projection (coordinates up to 2^17 pixels, about 3e-11)
/// and of [`super::coverage::SEPARATION_EPS`].
pub(super) const SPAN_PAD: f64 = 1e-8;

/// A pixel's index: by the hub most of its showers' polygons share, or by
/// the axis across which most of its showers' fragments are narrow.
pub(super) enum Crowd {
    Hub(HubIndex),
    Axis(AxisIndex),
}

impl Crowd {
    /// A fragment's key in this index: its polygon's cone at the hub
    /// (`outline`, the polygon's vertices), or its span on
    /// the axis (`frag`, its vertices in the pixel). `None`: it has none,
    /// and is tested against every shower.
    pub(super) fn key(&self, outline: Option<&[DVec2]>, frag: &[DVec2]) -> Option<(f64, f64)> {
        match self {
            Crowd::Hub(h) => outline.and_then(|v| cone_at(v, h.at)),
            Crowd::Axis(a) => Some(span(frag, a.axis)),
        }
    }

    /// Adds shower `shower` with its key (or none).
    pub(super) fn insert(&mut self, shower: u32, key: Option<(f64, f64)>) {
        match self {
            Crowd::Hub(h) => h.insert(shower, key),
            Crowd::Axis(a) => a.insert(shower, key),
        }
    }

    /// Pushes onto `out` every shower a fragment with key `key` may
    /// overlap (a shower may come twice).
    pub(super) fn candidates(&self, key: (f64, f64), out: &mut Vec<u32>) {
        match self {
            Crowd::Hub(h) => h.candidates(key, out),
            Crowd::Axis(a) => a.candidates(key, out),
        }
    }
}

/// The least and greatest of `verts` projected on `axis`.
pub(super) fn span(verts: &[DVec2], axis: DVec2) -> (f64, f64) {
    verts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            let d = v.dot(axis);
            (lo.min(d), hi.max(d))
        })
}

/// A f64's bits, made to order as the numbers do (negatives flipped).
fn ordered(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
    }
}

/// The showers of one pixel by their fragments' spans on one axis (a unit
/// vector), and the showers too wide for it.
pub(super) struct AxisIndex {
    pub(super) axis: DVec2,
    /// Each narrow span keyed by its start ([`ordered`]) and its shower:
    /// its end.
    spans: BTreeMap<(u64, u32), f64>,
    /// The widest span indexed: a query looks back this far.
    widest: f64,
    pub(super) others: Vec<u32>,
}

impl AxisIndex {
    /// An empty index along `axis`.
    pub(super) fn new(axis: DVec2) -> AxisIndex {
        AxisIndex {
            axis,
            spans: BTreeMap::new(),
            widest: 0.0,
            others: Vec::new(),
        }
    }

    /// Adds shower `shower`, whose fragment spans `span` of the axis.
    pub(super) fn insert(&mut self, shower: u32, span: Option<(f64, f64)>) {
        match span {
            Some((lo, hi)) if hi - lo <= AXIS_MAX_WIDTH => {
                self.spans.insert((ordered(lo), shower), hi);
                self.widest = self.widest.max(hi - lo);
            }
            _ => self.others.push(shower),
        }
    }

    /// Pushes onto `out` every shower whose span meets `(lo, hi)` widened
    /// by [`SPAN_PAD`] on each side, and every shower not indexed.
    pub(super) fn candidates(&self, (lo, hi): (f64, f64), out: &mut Vec<u32>) {
        out.extend_from_slice(&self.others);
        let (lo, hi) = (lo - SPAN_PAD, hi + SPAN_PAD);
        let from = (ordered(lo - self.widest), 0);
        let to = (ordered(hi), u32::MAX);
        let near = self.spans.range(from..=to);
        out.extend(
            near.filter(|(_, &end)| end >= lo)
                .map(|(&(_, shower), _)| shower),
        );
    }
}

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

/// The cone at `hub`, one of the vertices of the polygon `verts`, that
/// holds the polygon: from the hub, the directions of all its vertices,
/// from the most clockwise to the most counter-clockwise, as pseudo-angles
/// `(from, to)` (`to < from` when it crosses +x). `None` if `hub` is not a
/// vertex, or the cone is half a turn or more.
///
/// A polygon lies in the convex hull of its vertices, so in this cone,
/// whatever its shape. The cone between the two edges at the hub would not
/// do: the tools take a polygon as convex within 1e-9 pixel
/// (`geom::polygon::is_convex`), and past an edge that short the outline
/// may turn anywhere (a review's quad, kept as the test
/// `a_polygon_convex_within_tolerance_is_held_by_its_hull_cone`, reached
/// 0.1 rad outside its edges' cone over a fan triangle, and came out 4.9
/// codes off).
pub(super) fn cone_at(verts: &[DVec2], hub: DVec2) -> Option<(f64, f64)> {
    if !(3..=HUB_MAX_VERTICES).contains(&verts.len()) || !verts.contains(&hub) {
        return None;
    }
    // Angles are measured counter-clockwise from a direction against the
    // sum of the vertices' directions, outside the cone if it is under
    // half a turn. (Any direction would do for what follows: the cone
    // found holds every vertex's direction by construction; a poor one only
    // makes it too wide, and `None`.)
    let away = pseudo_angle(-verts.iter().map(|&v| v - hub).sum::<DVec2>());
    // (Angle from `away`, angle) of the most clockwise and the most
    // counter-clockwise vertex.
    let (mut first, mut last) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
    for &v in verts.iter().filter(|&&v| v != hub) {
        let angle = pseudo_angle(v - hub);
        let turned = angle - away;
        let turned = if turned < 0.0 { turned + 4.0 } else { turned };
        if turned < first.0 {
            first = (turned, angle);
        }
        if turned > last.0 {
            last = (turned, angle);
        }
    }
    // The angles themselves, not `away` plus the turns, so that neighbours
    // sharing an edge meet exactly. Half a turn is 2.
    let wide = last.0 - first.0;
    (wide > 0.0 && wide < 1.99).then_some((first.1, last.1))
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
    fn a_cone_holds_every_vertex_whatever_the_winding() {
        let hub = DVec2::new(1.0, 1.0);
        let (a, b) = (DVec2::new(3.0, 1.0), DVec2::new(1.0, 3.0));
        assert_eq!(cone_at(&[hub, a, b], hub), Some((0.0, 1.0)));
        assert_eq!(cone_at(&[hub, b, a], hub), Some((0.0, 1.0)), "clockwise");
        let straight = [DVec2::new(0.0, 1.0), hub, DVec2::new(2.0, 1.0), b];
        assert_eq!(cone_at(&straight, hub), None, "a straight angle");
        assert_eq!(cone_at(&[a, b, DVec2::ZERO], hub), None, "not a vertex");
        // Convex within 1e-9 pixel, and 0.1 rad past the cone of its edges
        // at the hub: the cone starts at its far vertex's direction.
        let (sin, cos) = crate::math::sin_cos(0.1);
        let far = hub + 3.0 * DVec2::new(cos, -sin);
        let bulge = [
            hub,
            hub + DVec2::new(5e-10, 0.0),
            far,
            hub + DVec2::new(0.0, 3.0),
        ];
        assert_eq!(cone_at(&bulge, hub), Some((pseudo_angle(far - hub), 1.0)));
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

    #[test]
    fn ordered_bits_order_as_the_numbers_do() {
        let xs = [-1e300, -2.5, -1e-300, -0.0, 0.0, 1e-300, 0.5, 3.0, 1e300];
        let keys: Vec<u64> = xs.iter().map(|&x| ordered(x)).collect();
        assert!(keys.windows(2).all(|w| w[0] <= w[1]), "{keys:?}");
    }

    /// Spans found by start, looking back as far as the widest; a wide
    /// one is kept aside.
    #[test]
    fn spans_meeting_a_query_are_found_and_wide_ones_kept_aside() {
        let mut index = AxisIndex::new(DVec2::X);
        for k in 0..10 {
            let lo = -0.5 + 0.1 * f64::from(k);
            index.insert(k, Some((lo, lo + 0.1)));
        }
        index.insert(10, Some((0.0, 0.5)));
        assert_eq!(index.others, [10]);
        let mut out = Vec::new();
        index.candidates((0.02, 0.03), &mut out);
        out.sort_unstable();
        // The span holding it, and the one aside.
        assert_eq!(out, [5, 10]);
        out.clear();
        index.candidates((0.1, 0.1), &mut out);
        out.sort_unstable();
        // Touching spans on both sides, within the pad.
        assert_eq!(out, [5, 6, 10]);
    }

    /// Two triangles anywhere.
    fn loose_pair() -> impl Strategy<Value = [[DVec2; 3]; 2]> {
        let point = (-2.0..3.0f64, -2.0..3.0f64).prop_map(|(x, y)| DVec2::new(x, y));
        let tri = [point.clone(), point.clone(), point].prop_filter_map("area", |[a, b, c]| {
            let area = (b - a).perp_dot(c - a);
            (area.abs() > 1e-3).then_some(if area > 0.0 { [a, b, c] } else { [a, c, b] })
        });
        [tri.clone(), tri]
    }

    proptest! {
        /// A shower the axis index leaves out never overlaps the newcomer,
        /// whatever the axis.
        #[test]
        fn a_span_left_out_never_overlaps(pair in loose_pair(), turn in 0.0..std::f64::consts::TAU) {
            let (sin, cos) = crate::math::sin_cos(turn);
            let axis = DVec2::new(cos, sin);
            let mut index = AxisIndex::new(axis);
            // Width is no matter here: every span is indexed.
            index.spans.insert((ordered(span(&pair[0], axis).0), 0), span(&pair[0], axis).1);
            index.widest = span(&pair[0], axis).1 - span(&pair[0], axis).0;
            let mut out = Vec::new();
            index.candidates(span(&pair[1], axis), &mut out);
            if out.is_empty() {
                prop_assert!(!overlap(&pair[0], &pair[1]), "{pair:?}");
            }
        }

        /// A shower the hub index leaves out never overlaps the newcomer,
        /// also where the shower has a vertex 5e-10 pixel from the hub in
        /// any direction (convex within the tools' tolerance, its edges at
        /// the hub saying nothing of its shape).
        #[test]
        fn a_shower_left_out_never_overlaps(
            pair in pair(),
            bulge in proptest::option::of(0.0..std::f64::consts::TAU),
        ) {
            let hub = pair[0][0];
            let shower = match bulge {
                Some(turn) => {
                    let (sin, cos) = crate::math::sin_cos(turn);
                    vec![hub, hub + 5e-10 * DVec2::new(cos, sin), pair[0][1], pair[0][2]]
                }
                None => pair[0].to_vec(),
            };
            let (Some(own), Some(new)) = (cone_at(&shower, hub), cone_at(&pair[1], hub)) else {
                return Ok(()); // Half a turn or more: not indexed.
            };
            let mut index = HubIndex::new(hub);
            index.insert(0, Some(own));
            let mut out = Vec::new();
            index.candidates(new, &mut out);
            if out.is_empty() {
                prop_assert!(!overlap(&pair[0], &pair[1]), "{pair:?}");
            }
        }
    }
}
