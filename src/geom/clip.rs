//! Polygon clipping against axis-parallel lines (Sutherland–Hodgman), the
//! primitive of the thesis's `clip_and_fill` (Fig. 4.5, App. E).
//!
//! Two flavours:
//!
//! - [`clip_tagged`]: every vertex carries what the segment leaving it lies on
//!   (an original edge of the input polygon, or a grid line). A crossing is
//!   always computed from the ORIGINAL edge's endpoints in a canonical order
//!   ([`cross_x`], [`cross_y`]), never from a sub-segment produced by an
//!   earlier clip. So the two cells on either side of a grid line compute the
//!   same crossing with the same bits, and a rasterizer sees no cracks.
//! - [`clip_closed`]: plain inclusive clipping of a polygon to a closed box,
//!   as the thesis does it (points on a line count as inside, so a polygon that
//!   only touches the box yields a degenerate, zero-area result). Used by
//!   `--compat thesis`.

use glam::DVec2;

/// What the segment from a vertex to the next lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tag {
    /// Part of the input polygon's edge from vertex `i` to vertex `i + 1`.
    Edge(u32),
    /// Along a horizontal grid line (constant y).
    Horizontal,
    /// Along a vertical grid line (constant x).
    Vertical,
}

/// A vertex of a polygon being clipped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TVertex {
    /// The position, in plane coordinates.
    pub p: DVec2,
    /// What the segment to the next vertex lies on.
    pub tag: Tag,
}

/// Which coordinate a clip line fixes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// A vertical line `x = c` (a column border).
    X,
    /// A horizontal line `y = c` (a row border).
    Y,
}

/// The point where the segment `a`–`b` crosses the line x = `c`, computed in a
/// canonical order (the lexicographically smaller endpoint first) so that it
/// does not depend on the direction the segment is walked. Exact at the
/// endpoints; the result's y is kept between the endpoints' y.
#[inline]
pub fn cross_x(a: DVec2, b: DVec2, c: f64) -> DVec2 {
    let (a, b) = if (a.x, a.y) <= (b.x, b.y) {
        (a, b)
    } else {
        (b, a)
    };
    if c <= a.x {
        return DVec2::new(c, a.y);
    }
    if c >= b.x {
        return DVec2::new(c, b.y);
    }
    let t = (c - a.x) / (b.x - a.x);
    let y = a.y + t * (b.y - a.y);
    DVec2::new(c, y.clamp(a.y.min(b.y), a.y.max(b.y)))
}

/// The point where the segment `a`–`b` crosses the line y = `c`; see [`cross_x`].
#[inline]
pub fn cross_y(a: DVec2, b: DVec2, c: f64) -> DVec2 {
    let (a, b) = if (a.y, a.x) <= (b.y, b.x) {
        (a, b)
    } else {
        (b, a)
    };
    if c <= a.y {
        return DVec2::new(a.x, c);
    }
    if c >= b.y {
        return DVec2::new(b.x, c);
    }
    let t = (c - a.y) / (b.y - a.y);
    let x = a.x + t * (b.x - a.x);
    DVec2::new(x.clamp(a.x.min(b.x), a.x.max(b.x)), c)
}

#[inline]
fn coord(p: DVec2, axis: Axis) -> f64 {
    match axis {
        Axis::X => p.x,
        Axis::Y => p.y,
    }
}

/// A polygon's vertices as a ring to clip: vertex `i` tagged with its edge
/// to vertex `i + 1`, whose crossings [`clip_tagged`] makes from `points`.
pub fn tagged(points: &[DVec2]) -> impl Iterator<Item = TVertex> + '_ {
    points.iter().enumerate().map(|(i, &p)| TVertex {
        p,
        tag: Tag::Edge(i as u32),
    })
}

/// Clips `input` to the half-plane `coord >= c` (`keep_above`) or `coord <= c`,
/// appending the result to `out` (cleared first). Points on the line are
/// inside. Crossings of `Edge(i)` segments come from `orig[i]`–`orig[i+1]`;
/// a crossing's y (for [`Axis::X`]) is clamped into `clamp` so that a cell's
/// points never leave its strip by a rounding error. Consecutive equal points
/// are merged (the later one's tag wins: it describes the segment that follows).
pub fn clip_tagged(
    input: &[TVertex],
    orig: &[DVec2],
    axis: Axis,
    c: f64,
    keep_above: bool,
    clamp: (f64, f64),
    out: &mut Vec<TVertex>,
) {
    out.clear();
    let n = input.len();
    if n == 0 {
        return;
    }
    let inside = |p: DVec2| {
        if keep_above {
            coord(p, axis) >= c
        } else {
            coord(p, axis) <= c
        }
    };
    let line_tag = match axis {
        Axis::X => Tag::Vertical,
        Axis::Y => Tag::Horizontal,
    };
    let cross = |s: &TVertex, e: &TVertex| -> DVec2 {
        if coord(e.p, axis) == c {
            return e.p;
        }
        if coord(s.p, axis) == c {
            return s.p;
        }
        match s.tag {
            Tag::Edge(i) => {
                let i = i as usize;
                let (a, b) = (orig[i], orig[(i + 1) % orig.len()]);
                match axis {
                    Axis::X => {
                        let q = cross_x(a, b, c);
                        DVec2::new(c, q.y.clamp(clamp.0, clamp.1))
                    }
                    Axis::Y => cross_y(a, b, c),
                }
            }
            // A segment along a grid line: the crossing is the grid point itself.
            Tag::Horizontal | Tag::Vertical => match axis {
                Axis::X => DVec2::new(c, s.p.y),
                Axis::Y => DVec2::new(s.p.x, c),
            },
        }
    };
    let push = |v: TVertex, out: &mut Vec<TVertex>| {
        if let Some(last) = out.last_mut() {
            if last.p == v.p {
                *last = v;
                return;
            }
        }
        out.push(v);
    };
    let mut s = &input[n - 1];
    let mut s_in = inside(s.p);
    for e in input {
        let e_in = inside(e.p);
        if e_in {
            if !s_in {
                push(
                    TVertex {
                        p: cross(s, e),
                        tag: s.tag,
                    },
                    out,
                );
            }
            push(*e, out);
        } else if s_in {
            push(
                TVertex {
                    p: cross(s, e),
                    tag: line_tag,
                },
                out,
            );
        }
        s = e;
        s_in = e_in;
    }
    // The ring closes: a last point equal to the first is the same vertex,
    // and the first comes after it, so its tag wins.
    while out.len() > 1 && out[out.len() - 1].p == out[0].p {
        out.pop();
    }
}

/// A point's position along a cell's border, counter-clockwise from the
/// lower-left corner: the side (0 bottom, 1 right, 2 top, 3 left) and a
/// coordinate that grows counter-clockwise along it (x, y, -x, -y). Compared
/// lexicographically, positions order border points exactly as the walk
/// around the border meets them.
///
/// Why not a perimeter parameter `t` in `[0, 2(w+h))` (as this once was): `t`
/// is a sum such as `w + h + (xr - x)`, rounded to the spacing of floats near
/// `2(w+h)`. Two distinct points of a side closer than that got the same `t`.
/// With the plane frame rotated by 90°, `cos 90°` is 6e-17, not 0, so integer
/// input lands a few 1e-16 beside the grid lines: a concave polygon's reflex
/// vertex at (15, 31) lay 2e-16 left of a column line, the top of the cell
/// below it was cut by a sliver, and the chain that entered at the cell's
/// top-right corner left through the top side 2e-16 further on. Its exit and
/// entry then had the same `t`: "the next entry counter-clockwise from the
/// exit" was found at distance 0 instead of once round the border, the piece
/// was rebuilt as the two-point chain alone, and the whole cell was dropped
/// (area 479 of 480). The side's own coordinate has no such rounding: the
/// comparison is of the points' own bits.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
struct BorderPos(u8, f64);

impl BorderPos {
    /// The position of `p`, a point on the border of `[xl,xr] x [ylo,yhi]`
    /// (a corner counts on the side it begins).
    fn of(p: DVec2, (xl, ylo, xr, yhi): (f64, f64, f64, f64)) -> BorderPos {
        if p.y == ylo {
            BorderPos(0, p.x)
        } else if p.x == xr {
            BorderPos(1, p.y)
        } else if p.y == yhi {
            BorderPos(2, -p.x)
        } else {
            debug_assert!(p.x == xl, "{p} is not on the border of the cell");
            BorderPos(3, -p.y)
        }
    }

    /// A key ordering border points as a counter-clockwise walk from `self`
    /// meets them: `self` itself first (distance 0), then the points after
    /// it on the border, then, once round the lower-left corner, those before.
    fn ahead(self, to: BorderPos) -> (bool, BorderPos) {
        (to < self, to)
    }
}

/// Splits the clip of a polygon to a cell into its separate parts.
///
/// Sutherland–Hodgman gives one ring even when a concave polygon's piece of
/// the cell falls apart: the parts are joined by zero-width bridges along the
/// cell's border. Here the ring `q` (the output of clipping to the cell
/// `[xl,xr] x [ylo,yhi]`) is cut into its chains of input edges, each of which
/// enters and leaves through the border; each chain's exit is joined to the
/// next entry counter-clockwise along the border, passing the cell corners in
/// between (Weiler–Atherton for a rectangle). Every point is kept with its
/// bits; the only new points are cell corners.
///
/// With one chain this still matters: the ring can carry a zero-width spike
/// along the border, left by a bridge of the strip the cell was cut from.
///
/// Returns false, leaving `rings` empty, when there is nothing to rebuild (no
/// chain: the cell is whole) or the chains do not pair up (a degenerate
/// touch): then `q` itself is the answer.
pub fn split_on_border(
    q: &[TVertex],
    (xl, ylo, xr, yhi): (f64, f64, f64, f64),
    rings: &mut Vec<Vec<DVec2>>,
) -> bool {
    rings.clear();
    let n = q.len();
    let is_edge = |i: usize| matches!(q[i % n].tag, Tag::Edge(_));
    let pos = |p: DVec2| BorderPos::of(p, (xl, ylo, xr, yhi));
    // The common case, without allocating: one chain, and the way back along
    // the border runs counter-clockwise from its exit to its entry without
    // turning back. Then `q` is already right.
    let (mut count, mut s0) = (0, 0);
    for i in 0..n {
        if is_edge(i) && !is_edge(i + n - 1) {
            count += 1;
            s0 = i;
        }
    }
    if count == 0 {
        return false;
    }
    if count == 1 {
        let mut e = s0;
        while is_edge(e) {
            e = (e + 1) % n;
        }
        let te = pos(q[e].p);
        let to_entry = te.ahead(pos(q[s0].p));
        let (mut i, mut prev, mut monotone) = (e, te.ahead(te), true);
        loop {
            i = (i + 1) % n;
            if i == s0 {
                break;
            }
            let d = te.ahead(pos(q[i].p));
            if d < prev || d > to_entry {
                monotone = false;
                break;
            }
            prev = d;
        }
        if monotone {
            return false;
        }
    }
    let starts: Vec<usize> = (0..n)
        .filter(|&i| is_edge(i) && !is_edge(i + n - 1))
        .collect();
    // Each chain: vertices s..=e (cyclically), entering at s, leaving at e.
    let chains: Vec<(usize, usize, BorderPos, BorderPos)> = starts
        .iter()
        .map(|&s| {
            let mut e = s;
            while is_edge(e) {
                e = (e + 1) % n;
            }
            (s, e, pos(q[s].p), pos(q[e].p))
        })
        .collect();
    // The next chain after each one: the first entry counter-clockwise from
    // its exit (the least entry at or after it on the border, else the least
    // once round), the lowest-numbered of equal ones. The entries are sorted
    // once and searched: comparing every exit with every entry cost O(k²) for
    // k chains, and a concave star of a million vertices crosses a cell in
    // thousands (minutes for polyfill3 at incr 1).
    let mut by_entry: Vec<usize> = (0..chains.len()).collect();
    by_entry.sort_by(|&a, &b| {
        (chains[a].2)
            .partial_cmp(&chains[b].2)
            .expect("finite border positions")
            .then(a.cmp(&b))
    });
    let next: Vec<(usize, (bool, BorderPos))> = chains
        .iter()
        .map(|&(_, _, _, te)| {
            let at = by_entry.partition_point(|&i| chains[i].2 < te);
            let i = by_entry[if at < by_entry.len() { at } else { 0 }];
            (i, te.ahead(chains[i].2))
        })
        .collect();
    let mut hit = vec![false; chains.len()];
    for &(i, _) in &next {
        if std::mem::replace(&mut hit[i], true) {
            return false;
        }
    }
    let corners = [
        DVec2::new(xl, ylo),
        DVec2::new(xr, ylo),
        DVec2::new(xr, yhi),
        DVec2::new(xl, yhi),
    ];
    let mut used = vec![false; chains.len()];
    for c0 in 0..chains.len() {
        if used[c0] {
            continue;
        }
        let mut ring: Vec<DVec2> = Vec::new();
        let mut c = c0;
        while !used[c] {
            used[c] = true;
            let (s, e, _, te) = chains[c];
            let mut i = s;
            loop {
                if ring.last() != Some(&q[i].p) {
                    ring.push(q[i].p);
                }
                if i == e {
                    break;
                }
                i = (i + 1) % n;
            }
            let (nx, d) = next[c];
            let mut passed: Vec<((bool, BorderPos), DVec2)> = corners
                .iter()
                .map(|&p| (te.ahead(pos(p)), p))
                .filter(|&(dc, _)| dc > te.ahead(te) && dc < d)
                .collect();
            passed.sort_by(|a, b| a.0.partial_cmp(&b.0).expect("finite border positions"));
            for (_, p) in passed {
                if ring.last() != Some(&p) {
                    ring.push(p);
                }
            }
            c = nx;
        }
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        rings.push(ring);
    }
    true
}

/// Inclusive clip of a polygon to the closed box `[x0,x1] x [y0,y1]` (the
/// thesis's four clipping boundaries, Fig. 4.5), appending to `out`. The
/// result is empty only when the polygon does not reach the box at all; a
/// polygon touching the box along a line or at a point gives a degenerate
/// result, as in the thesis. `scratch` is reused working space.
pub fn clip_closed(
    poly: &[DVec2],
    (x0, y0, x1, y1): (f64, f64, f64, f64),
    out: &mut Vec<DVec2>,
    scratch: &mut Vec<DVec2>,
) {
    out.clear();
    out.extend_from_slice(poly);
    for (axis, c, above) in [
        (Axis::X, x0, true),
        (Axis::Y, y0, true),
        (Axis::X, x1, false),
        (Axis::Y, y1, false),
    ] {
        std::mem::swap(out, scratch);
        out.clear();
        let n = scratch.len();
        if n == 0 {
            return;
        }
        let inside = |p: DVec2| {
            let v = coord(p, axis);
            if above {
                v >= c
            } else {
                v <= c
            }
        };
        let cross = |a: DVec2, b: DVec2| match axis {
            Axis::X => cross_x(a, b, c),
            Axis::Y => cross_y(a, b, c),
        };
        let mut s = scratch[n - 1];
        for &e in scratch.iter() {
            if inside(e) {
                if !inside(s) {
                    out.push(cross(s, e));
                }
                out.push(e);
            } else if inside(s) {
                out.push(cross(s, e));
            }
            s = e;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::plane::signed_area;

    #[test]
    fn crossings_do_not_depend_on_direction() {
        let a = DVec2::new(0.1, 0.7);
        let b = DVec2::new(3.3, -2.9);
        for c in [0.2, 1.0, 1.7, 3.2] {
            assert_eq!(cross_x(a, b, c), cross_x(b, a, c));
        }
        for c in [0.5, -1.0, -2.8] {
            assert_eq!(cross_y(a, b, c), cross_y(b, a, c));
        }
        assert_eq!(cross_x(a, b, 0.1), a);
    }

    #[test]
    fn clipping_a_square_to_a_half_plane() {
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let mut out = Vec::new();
        clip_tagged(
            &tagged(&sq).collect::<Vec<_>>(),
            &sq,
            Axis::X,
            0.5,
            true,
            (0.0, 2.0),
            &mut out,
        );
        let pts: Vec<DVec2> = out.iter().map(|v| v.p).collect();
        assert_eq!(signed_area(&pts), 3.0);
        // The new edge along x = 0.5 is tagged as a grid line.
        assert!(out.iter().any(|v| v.tag == Tag::Vertical));
        // A line through a vertex adds no duplicate points.
        clip_tagged(
            &tagged(&sq).collect::<Vec<_>>(),
            &sq,
            Axis::X,
            2.0,
            true,
            (0.0, 2.0),
            &mut out,
        );
        assert_eq!(out.len(), 2);
    }

    #[test]
    fn closed_clip_keeps_touching_polygons_degenerate() {
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let (mut out, mut s) = (Vec::new(), Vec::new());
        clip_closed(&sq, (1.0, 0.0, 2.0, 1.0), &mut out, &mut s);
        assert!(!out.is_empty());
        assert_eq!(signed_area(&out), 0.0);
        clip_closed(&sq, (1.5, 0.0, 2.0, 1.0), &mut out, &mut s);
        assert!(out.is_empty());
    }
}
