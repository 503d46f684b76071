//! Whether a polygon is simple, and if not, where it meets itself.
//!
//! docs/stream-format.md's polygons are planar and simple (docs/rendering.md): the
//! resolvers fill by nonzero winding, the exact one by triangles, polyfill3 by
//! even-odd runs, and these only agree on simple polygons. A polygon is
//! *simple* here when no edge meets another except its two neighbours, each at
//! their one shared vertex. Two relaxations keep what the tools always took:
//! a vertex repeated by the next one (closing a ring by repeating vertex 0
//! included) is one vertex, and collinear vertices are ordinary vertices. A
//! polygon whose vertices are all collinear is left alone: it has no area,
//! which the plane fit words better ([`super::plane::PlaneError::ZeroArea`]).
//!
//! Everything else is refused, by the first contact found ([`Contact`]):
//! two edges crossing, a vertex on another edge (touching: a keyhole's bridge
//! end, or the boundary passing through the edge there), two vertices at one
//! point (a pinch), two edges overlapping (a bridge, or an edge doubling back
//! along its neighbour). Touching is refused like crossing: it is where the
//! fill rules start to disagree, and nothing the tools write or ship has it.
//!
//! The test is Shamos and Hoey's sweep (1976): the edges are swept left to
//! right in a balanced tree (`super::sweep`) ordered by height, and an edge
//! is tested only against its neighbours in that order when they become
//! neighbours. Before the first contact the order is consistent, so the
//! first contact's two edges are neighbours at some event and it is found:
//! O(n log n) time and O(n) memory. Every decision is an exact orientation
//! ([`super::polygon::orient2d`]) or a comparison of coordinates, on the
//! polygon seen flat along its plane's main axis ([`super::plane::flat_view`],
//! which copies coordinates without arithmetic): the answer is exact for the
//! polygon as written, however close its edges pass.

use super::plane::flat_view;
use super::polygon::orient2d;
use super::sweep::Treap;
use glam::{DVec2, DVec3};
use smallvec::SmallVec;
use std::cmp::Ordering;
use std::fmt;

/// Where a polygon meets itself. Vertices and edges are numbered from 0 as the
/// polygon lists them; edge `k` runs from vertex `k` to vertex `k + 1`
/// (vertex 0 for the last edge).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    /// Edges `a` and `b` cross at a point inside both.
    Cross {
        /// The lower-numbered edge.
        a: usize,
        /// The other edge.
        b: usize,
        /// The polygon's vertex count.
        n: usize,
    },
    /// Vertex `vertex` lies inside edge `edge`, which does not end there.
    VertexOnEdge {
        /// The vertex.
        vertex: usize,
        /// The edge.
        edge: usize,
        /// The polygon's vertex count.
        n: usize,
    },
    /// Vertices `a` and `b`, not neighbours, are the same point.
    SamePoint {
        /// The lower-numbered vertex.
        a: usize,
        /// The other vertex.
        b: usize,
    },
    /// Edges `a` and `b` overlap along a segment (for neighbours: the
    /// polygon doubles back at their shared vertex).
    Overlap {
        /// The lower-numbered edge.
        a: usize,
        /// The other edge.
        b: usize,
        /// The polygon's vertex count.
        n: usize,
    },
}

impl Contact {
    /// The vertices where the polygon meets itself: the ends of the two
    /// edges that cross or overlap, the vertex and the ends of the edge it
    /// lies on, or the two vertices at one point.
    pub(crate) fn vertices(self) -> SmallVec<[usize; 4]> {
        match self {
            Contact::Cross { a, b, n } | Contact::Overlap { a, b, n } => {
                SmallVec::from_buf([a, (a + 1) % n, b, (b + 1) % n])
            }
            Contact::VertexOnEdge { vertex, edge, n } => {
                SmallVec::from_slice(&[vertex, edge, (edge + 1) % n])
            }
            Contact::SamePoint { a, b } => SmallVec::from_slice(&[a, b]),
        }
    }

    /// Of [`Contact::vertices`], the one nearest the chord of its two
    /// neighbours in the ring `p` (the polygon as the contact numbers it),
    /// and that distance: the vertex whose removal changes the ring least.
    /// The distance is NaN where the neighbours coincide (a spike).
    pub(crate) fn nearest_to_chord(self, p: &[DVec2]) -> (usize, f64) {
        let n = p.len();
        let off_chord = |k: usize| {
            let (a, b, c) = (p[(k + n - 1) % n], p[k], p[(k + 1) % n]);
            orient2d(a, b, c).abs() / (c - a).length()
        };
        self.vertices()
            .into_iter()
            .map(|k| (k, off_chord(k)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("a contact has vertices")
    }
}

/// "edge 3 (vertex 3 to 0)".
struct Edge(usize, usize);

impl fmt::Display for Edge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Edge(k, n) = *self;
        write!(f, "edge {k} (vertex {k} to {})", (k + 1) % n)
    }
}

impl fmt::Display for Contact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const SIMPLE: &str = "and a polygon must be simple";
        match *self {
            Contact::Cross { a, b, n } => write!(
                f,
                "the polygon crosses itself: {} crosses {}",
                Edge(a, n),
                Edge(b, n)
            ),
            Contact::VertexOnEdge { vertex, edge, n } => write!(
                f,
                "the polygon touches itself: vertex {vertex} lies on {}, {SIMPLE}",
                Edge(edge, n)
            ),
            Contact::SamePoint { a, b } => write!(
                f,
                "the polygon touches itself: vertices {a} and {b} are the same point, {SIMPLE}"
            ),
            Contact::Overlap { a, b, n } => write!(
                f,
                "the polygon runs along itself: {} overlaps {}, {SIMPLE}",
                Edge(a, n),
                Edge(b, n)
            ),
        }
    }
}

impl std::error::Error for Contact {}

/// Whether a 3D polygon (planar, up to the planarity tolerance) is simple,
/// judged on its flat view ([`flat_view`]). Triangles are always simple;
/// polygons whose vertices are all collinear are let through (no plane).
pub fn check(v: &[DVec3]) -> Result<(), Contact> {
    if v.len() <= 3 {
        return Ok(());
    }
    match flat_view(v) {
        Some(flat) if turns_strictly_one_way(&flat) || convex_without_repeats(&flat) => Ok(()),
        Some(flat) => find_contact(&flat).map_or(Ok(()), Err),
        None => Ok(()),
    }
}

/// A quadrilateral that turns strictly the same way at each of its four
/// vertices (exact orientations), which is simple: each exterior angle is
/// then below a half turn, so the four sum to less than two turns, and a
/// closed polygon turns through whole turns, so it goes round once, convex.
/// [`find_contact`] says so too, through its ring; this is the common case
/// (every cell polyfill3 writes, every quad of a mesh, is checked as it is
/// read), in four orientations: [`convex_without_repeats`] took 4% more of
/// reading and drawing polyfill3's cells (callgrind).
fn turns_strictly_one_way(p: &[DVec2]) -> bool {
    let &[a, b, c, d] = p else {
        return false;
    };
    let t = [
        orient2d(d, a, b),
        orient2d(a, b, c),
        orient2d(b, c, d),
        orient2d(c, d, a),
    ];
    t.iter().all(|&o| o > 0.0) || t.iter().all(|&o| o < 0.0)
}

/// Whether a polygon with no vertex repeated by the next (the last and the
/// first included) is convex and gone round once ([`convex_once`]) without
/// doubling back ([`fold_back_at`]): simple. Such a polygon is its own
/// ring, so this is what [`find_contact`] decides, without building the
/// ring: the common case (every cell and merged run polyfill3 writes, a
/// mesh's faces) is checked as it is read. (20,000 of polyfill3's merged
/// runs were checked in 113 M instructions against 180 M through the
/// ring, callgrind.)
fn convex_without_repeats(p: &[DVec2]) -> bool {
    let m = p.len();
    (0..m).all(|k| p[k] != p[(k + 1) % m]) && fold_back_at(p).is_none() && convex_once(p)
}

/// The first vertex where the polygon turns back on itself: the edges
/// either side of it overlap (a zero-width spike).
fn fold_back_at(q: &[DVec2]) -> Option<usize> {
    let m = q.len();
    (0..m).find(|&k| folds_back(q[(k + m - 1) % m], q[k], q[(k + 1) % m]))
}

/// Whether a ring through `a`, `b`, `c` turns straight back at `b`: the
/// three are collinear (exact orientation) and `a` and `c` lie on the same
/// side of `b`, so the edges either side of `b` overlap.
pub(crate) fn folds_back(a: DVec2, b: DVec2, c: DVec2) -> bool {
    orient2d(a, b, c) == 0.0 && (lex(a, b) == lex(c, b))
}

/// Whether the polygon is convex and gone round once, which is simple: it
/// turns the same way at every vertex (or goes straight on; doubling back
/// is [`fold_back_at`]'s), and its edges turn through one full turn in
/// all, not two or more like a pentagram's, which shows in the sign of
/// their x extent changing exactly twice. O(n), and the common case
/// (rectangles, circles, a mesh's faces).
fn convex_once(q: &[DVec2]) -> bool {
    let m = q.len();
    let mut turn = 0.0f64;
    for k in 0..m {
        let o = orient2d(q[(k + m - 1) % m], q[k], q[(k + 1) % m]);
        if o * turn < 0.0 {
            return false;
        }
        if o != 0.0 {
            turn = o;
        }
    }
    let dx = |k: usize| q[(k + 1) % m].x.total_cmp(&q[k].x) as i8;
    let signs = (0..m).map(dx).filter(|&s| s != 0);
    let mut changes = 0;
    let (mut first, mut last) = (0i8, 0i8);
    for s in signs {
        if first == 0 {
            first = s;
        } else if s != last {
            changes += 1;
        }
        last = s;
    }
    if first != last {
        changes += 1;
    }
    changes == 2
}

/// Up to this many distinct vertices every pair of edges is tested (the
/// quadrilaterals of a mesh cost two pair tests), past it the sweep.
const PAIRWISE_MAX: usize = 24;

/// The first contact of a 2D polygon with itself, if it has one (see the
/// module's documentation for what counts).
pub fn find_contact(p: &[DVec2]) -> Option<Contact> {
    let ring = Ring::new(p)?;
    ring.fold_back().or_else(|| {
        if convex_once(&ring.q) {
            None
        } else if ring.q.len() <= PAIRWISE_MAX {
            ring.pairwise()
        } else {
            ring.sweep()
        }
    })
}

/// The sweep alone, whatever the size (tests compare it with the pairwise test).
#[cfg(test)]
fn find_contact_by_sweep(p: &[DVec2]) -> Option<Contact> {
    let ring = Ring::new(p)?;
    ring.fold_back().or_else(|| ring.sweep())
}

/// Lexicographic order (x, then y): the sweep's order of points.
#[inline]
fn lex(a: DVec2, b: DVec2) -> Ordering {
    a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
}

/// The polygon without repeated neighbours: vertex `k` of `q` stands for the
/// input's vertices `first[k]..=last[k]` (cyclically), and its edge `k`, from
/// `q[k]` to `q[k + 1]`, is the input's edge `last[k]`.
struct Ring {
    // Inline up to 8 vertices: a quad's ring (every cell polyfill3 writes
    // is checked as it is read) makes no heap block.
    q: SmallVec<[DVec2; 8]>,
    first: SmallVec<[usize; 8]>,
    last: SmallVec<[usize; 8]>,
    /// The input's vertex count.
    n: usize,
}

impl Ring {
    /// `None` when the polygon has fewer than 4 distinct vertices (a triangle
    /// or less, simple or without area) or they are all collinear.
    fn new(p: &[DVec2]) -> Option<Ring> {
        let n = p.len();
        // A vertex that differs from the one before it starts a run.
        let start = (0..n).find(|&i| p[i] != p[(i + n - 1) % n])?;
        let (mut q, mut first, mut last) = (SmallVec::new(), SmallVec::new(), SmallVec::new());
        for k in 0..n {
            let i = (start + k) % n;
            if k > 0 && p[i] == p[(i + n - 1) % n] {
                *last.last_mut().expect("a run is open") = i;
            } else {
                q.push(p[i]);
                first.push(i);
                last.push(i);
            }
        }
        if q.len() <= 3 || q.iter().all(|&c| orient2d(q[0], q[1], c) == 0.0) {
            return None;
        }
        Some(Ring { q, first, last, n })
    }

    #[inline]
    fn len(&self) -> usize {
        self.q.len()
    }

    /// The endpoints of edge `k`.
    #[inline]
    fn ends(&self, k: usize) -> (DVec2, DVec2) {
        (self.q[k], self.q[(k + 1) % self.len()])
    }

    /// Edge `k` as the input numbers it.
    #[inline]
    fn edge_name(&self, k: usize) -> usize {
        self.last[k]
    }

    fn adjacent(&self, a: usize, b: usize) -> bool {
        let m = self.len();
        (a + 1) % m == b || (b + 1) % m == a
    }

    fn cross(&self, a: usize, b: usize) -> Contact {
        let (a, b) = (self.edge_name(a), self.edge_name(b));
        Contact::Cross {
            a: a.min(b),
            b: a.max(b),
            n: self.n,
        }
    }

    fn overlap(&self, a: usize, b: usize) -> Contact {
        let (a, b) = (self.edge_name(a), self.edge_name(b));
        Contact::Overlap {
            a: a.min(b),
            b: a.max(b),
            n: self.n,
        }
    }

    fn same_point(&self, u: usize, v: usize) -> Contact {
        let (a, b) = (self.first[u], self.first[v]);
        Contact::SamePoint {
            a: a.min(b),
            b: a.max(b),
        }
    }

    fn on_edge(&self, vertex: usize, edge: usize) -> Contact {
        Contact::VertexOnEdge {
            vertex: self.first[vertex],
            edge: self.edge_name(edge),
            n: self.n,
        }
    }

    /// Two neighbouring edges overlapping: the polygon turns back at their
    /// shared vertex (a zero-width spike).
    fn fold_back(&self) -> Option<Contact> {
        let m = self.len();
        fold_back_at(&self.q).map(|k| self.overlap((k + m - 1) % m, k))
    }

    /// Whether edges `i` and `j`, not neighbours, meet, and how.
    fn contact(&self, i: usize, j: usize) -> Option<Contact> {
        let m = self.len();
        let (a, b) = self.ends(i);
        let (c, d) = self.ends(j);
        let s = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
        let (o1, o2) = (s(orient2d(a, b, c)), s(orient2d(a, b, d)));
        let (o3, o4) = (s(orient2d(c, d, a)), s(orient2d(c, d, b)));
        if o1 * o2 < 0 && o3 * o4 < 0 {
            return Some(self.cross(i, j));
        }
        // (point, its vertex in q) for the four endpoints.
        let (va, vb, vc, vd) = (i, (i + 1) % m, j, (j + 1) % m);
        let lo_hi = |x: DVec2, y: DVec2| {
            if lex(x, y) == Ordering::Greater {
                (y, x)
            } else {
                (x, y)
            }
        };
        let within = |p: DVec2, (lo, hi): (DVec2, DVec2)| {
            lex(lo, p) != Ordering::Greater && lex(p, hi) != Ordering::Greater
        };
        if o1 == 0 && o2 == 0 {
            // Collinear: the two spans along the line.
            let (ab, cd) = (lo_hi(a, b), lo_hi(c, d));
            let lo = if lex(ab.0, cd.0) == Ordering::Greater {
                ab.0
            } else {
                cd.0
            };
            let hi = if lex(ab.1, cd.1) == Ordering::Less {
                ab.1
            } else {
                cd.1
            };
            return match lex(lo, hi) {
                Ordering::Less => Some(self.overlap(i, j)),
                Ordering::Equal => {
                    let u = if lo == a { va } else { vb };
                    let v = if lo == c { vc } else { vd };
                    Some(self.same_point(u, v))
                }
                Ordering::Greater => None,
            };
        }
        // One endpoint on the other edge (at most one per edge now).
        let (ab, cd) = (lo_hi(a, b), lo_hi(c, d));
        for (o, p, vp, span, other, (e0, e1)) in [
            (o1, c, vc, ab, i, (va, vb)),
            (o2, d, vd, ab, i, (va, vb)),
            (o3, a, va, cd, j, (vc, vd)),
            (o4, b, vb, cd, j, (vc, vd)),
        ] {
            if o == 0 && within(p, span) {
                return Some(if p == self.q[e0] {
                    self.same_point(vp, e0)
                } else if p == self.q[e1] {
                    self.same_point(vp, e1)
                } else {
                    self.on_edge(vp, other)
                });
            }
        }
        None
    }

    /// Every pair of edges that are not neighbours.
    fn pairwise(&self) -> Option<Contact> {
        let m = self.len();
        (0..m).find_map(|i| {
            (i + 2..m)
                .filter(|&j| !(i == 0 && j == m - 1))
                .find_map(|j| self.contact(i, j))
        })
    }

    /// Shamos–Hoey: the first contact found by the sweep.
    fn sweep(&self) -> Option<Contact> {
        let m = self.len();
        let q = &self.q;
        let mut sorted: Vec<(f64, f64, u32)> = q
            .iter()
            .enumerate()
            .map(|(i, v)| (v.x, v.y, i as u32))
            .collect();
        sorted.sort_unstable_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then(a.1.total_cmp(&b.1))
                .then(a.2.cmp(&b.2))
        });
        // Two vertices at one point (never neighbours: those were merged).
        if let Some(w) = sorted
            .windows(2)
            .find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
        {
            return Some(self.same_point(w[0].2 as usize, w[1].2 as usize));
        }
        // Each edge's left end (smaller in the sweep's order) and right end,
        // and the vertex at its left end.
        let mut seg: Vec<(DVec2, DVec2)> = Vec::with_capacity(m);
        let mut left_v: Vec<u32> = Vec::with_capacity(m);
        for k in 0..m {
            let j = (k + 1) % m;
            if lex(q[k], q[j]) == Ordering::Less {
                seg.push((q[k], q[j]));
                left_v.push(k as u32);
            } else {
                seg.push((q[j], q[k]));
                left_v.push(j as u32);
            }
        }
        let mut status = Treap::new(m);
        let test = |a: Option<u32>, b: Option<u32>| -> Option<Contact> {
            let (a, b) = (a? as usize, b? as usize);
            if self.adjacent(a, b) {
                None
            } else {
                self.contact(a, b)
            }
        };
        for &(x, y, v) in &sorted {
            let p = DVec2::new(x, y);
            let incident = [(v as usize + m - 1) % m, v as usize];
            for &e in &incident {
                if left_v[e] != v {
                    continue;
                }
                let er = seg[e].1;
                let mut found = None;
                status.insert(e as u32, [seg[e].0, er], |&[tl, tr], t| {
                    let s = orient2d(tl, tr, p);
                    if s != 0.0 {
                        return s < 0.0;
                    }
                    // p lies on t (t spans p's place in the sweep).
                    if tr == p {
                        // t is the edge ending at v: order by the far ends.
                        orient2d(tl, tr, er) < 0.0
                    } else if tl == p {
                        // t is the other edge leaving v.
                        orient2d(p, tr, er) < 0.0
                    } else {
                        found.get_or_insert(self.on_edge(v as usize, t as usize));
                        false
                    }
                });
                if found.is_some() {
                    return found;
                }
                let id = Some(e as u32);
                let below = test(status.prev(e as u32), id);
                if let Some(c) = below.or_else(|| test(id, status.next(e as u32))) {
                    return Some(c);
                }
            }
            for &e in &incident {
                if left_v[e] == v {
                    continue;
                }
                let (below, above) = (status.prev(e as u32), status.next(e as u32));
                status.remove(e as u32);
                if let Some(c) = test(below, above) {
                    return Some(c);
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pts(v: &[[f64; 2]]) -> Vec<DVec2> {
        v.iter().map(|&[x, y]| DVec2::new(x, y)).collect()
    }

    /// Both ways of searching, which must agree with each other.
    fn contact(v: &[[f64; 2]]) -> Option<Contact> {
        let p = pts(v);
        let a = find_contact(&p);
        let b = find_contact_by_sweep(&p);
        assert_eq!(a.is_some(), b.is_some(), "{v:?}: {a:?} vs {b:?}");
        a
    }

    #[test]
    fn bow_ties_cross_and_say_which_edges() {
        // Symmetric: no area at all, which the plane fit would call collinear.
        let sym = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        let c = contact(&sym).unwrap();
        assert_eq!(c, Contact::Cross { a: 0, b: 2, n: 4 });
        assert_eq!(
            c.to_string(),
            "the polygon crosses itself: edge 0 (vertex 0 to 1) crosses edge 2 (vertex 2 to 3)"
        );
        let asym = [[0.0, 0.0], [4.0, 0.0], [0.0, 1.0], [4.0, 3.0]];
        assert_eq!(contact(&asym), Some(Contact::Cross { a: 1, b: 3, n: 4 }));
        assert_eq!(
            contact(&asym).unwrap().to_string(),
            "the polygon crosses itself: edge 1 (vertex 1 to 2) crosses edge 3 (vertex 3 to 0)"
        );
    }

    #[test]
    fn a_pentagram_crosses_itself() {
        let star: Vec<[f64; 2]> = (0..5)
            .map(|i| {
                let a = std::f64::consts::TAU * (2 * i) as f64 / 5.0;
                [crate::math::cos(a), crate::math::sin(a)]
            })
            .collect();
        assert!(matches!(contact(&star), Some(Contact::Cross { .. })));
        // The same five points in order: a convex pentagon.
        let pentagon: Vec<[f64; 2]> = (0..5)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 5.0;
                [crate::math::cos(a), crate::math::sin(a)]
            })
            .collect();
        assert_eq!(contact(&pentagon), None);
    }

    #[test]
    fn repeated_and_collinear_vertices_are_accepted() {
        // An L with a repeated vertex, a collinear one, and vertex 0 repeated
        // at the end to close the ring.
        let l = [
            [0.0, 0.0],
            [2.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
            [0.0, 0.0],
        ];
        assert_eq!(contact(&l), None);
        // All collinear: no plane, left to the plane fit to refuse.
        assert_eq!(
            contact(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 0.0]]),
            None
        );
        assert_eq!(contact(&[[3.0, 3.0]; 5]), None);
    }

    #[test]
    fn touching_is_refused_and_named() {
        // A keyhole: a square with a square hole joined by a two-way bridge.
        let keyhole = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 3.0],
            [3.0, 3.0],
            [3.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let c = contact(&keyhole).unwrap();
        assert!(
            matches!(c, Contact::Overlap { .. } | Contact::SamePoint { .. }),
            "{c:?}"
        );
        // A vertex on another edge.
        let t = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(
            contact(&t),
            Some(Contact::VertexOnEdge {
                vertex: 3,
                edge: 0,
                n: 5
            })
        );
        assert_eq!(
            contact(&t).unwrap().to_string(),
            "the polygon touches itself: vertex 3 lies on edge 0 (vertex 0 to 1), and a polygon must be simple"
        );
        // Two vertices at one point: a figure of eight pinched at (2, 2).
        let eight = [
            [0.0, 0.0],
            [2.0, 2.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [2.0, 2.0],
            [0.0, 4.0],
        ];
        assert_eq!(contact(&eight), Some(Contact::SamePoint { a: 1, b: 4 }));
        // A spike: the polygon doubles back along an edge.
        let spike = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [4.0, 6.0],
            [4.0, 5.0],
            [0.0, 4.0],
        ];
        assert_eq!(contact(&spike), Some(Contact::Overlap { a: 2, b: 3, n: 6 }));
    }

    #[test]
    fn crossings_one_ulp_away_are_found_exactly() {
        // Vertex 3 one ulp above the line y = x of edge 0, then one ulp below.
        let x = 3.0 * 0.1;
        let up = x * (1.0 + f64::EPSILON);
        let down = x * (1.0 - f64::EPSILON);
        assert!(up > x && down < x);
        let above = [[0.0, 0.0], [1.0, 1.0], [1.0, 2.0], [x, up], [-1.0, 2.0]];
        assert_eq!(contact(&above), None);
        let on = [[0.0, 0.0], [1.0, 1.0], [1.0, 2.0], [x, x], [-1.0, 2.0]];
        assert!(matches!(
            contact(&on),
            Some(Contact::VertexOnEdge {
                vertex: 3,
                edge: 0,
                ..
            })
        ));
        let below = [[0.0, 0.0], [1.0, 1.0], [1.0, 2.0], [x, down], [-1.0, 2.0]];
        assert!(matches!(contact(&below), Some(Contact::Cross { .. })));
    }

    #[test]
    fn three_dimensional_polygons_are_judged_in_their_plane() {
        // The symmetric bow-tie tilted out of every axis plane.
        let m = glam::DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
        let tie: Vec<DVec3> = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]
            .iter()
            .map(|&[x, y]| m * DVec3::new(x, y, 0.0) + DVec3::new(5.0, -2.0, 7.0))
            .collect();
        assert!(matches!(
            check(&tie),
            Err(Contact::Cross { a: 0, b: 2, n: 4 })
        ));
        let square: Vec<DVec3> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .map(|&[x, y]| m * DVec3::new(x, y, 0.0))
            .collect();
        assert_eq!(check(&square), Ok(()));
        // A vertical wall (no extent in y) and a collinear 3D "polygon".
        let wall = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        assert!(matches!(check(&wall), Err(Contact::Cross { .. })));
        let line = [DVec3::ZERO, DVec3::ONE, DVec3::ONE * 2.0, DVec3::ONE];
        assert_eq!(check(&line), Ok(()));
    }

    /// A star of `n` vertices alternating between radii 1 and 0.5.
    fn star(n: usize) -> Vec<DVec2> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let r = if i % 2 == 0 { 1.0 } else { 0.5 };
                DVec2::new(r * crate::math::cos(a), r * crate::math::sin(a))
            })
            .collect()
    }

    #[test]
    fn a_million_vertex_star_is_simple_and_one_moved_vertex_is_found() {
        let mut s = star(1_000_000);
        let t = std::time::Instant::now();
        assert_eq!(find_contact(&s), None);
        let took = t.elapsed();
        // Generous: about 0.3 s optimised; the test profile is opt-level 1
        // and the machine may be shared.
        assert!(took.as_secs_f64() < 20.0, "{took:?}");
        // Vertex 500,001 (an inner one, on the left) pulled out past the right.
        s[500_001] = DVec2::new(1.5, 0.1);
        assert!(find_contact(&s).is_some());
    }

    // ---- The oracle: every pair of edges, in exact integer arithmetic. ----

    type P = (i64, i64);

    fn cross_i(o: P, a: P, b: P) -> i128 {
        (a.0 - o.0) as i128 * (b.1 - o.1) as i128 - (a.1 - o.1) as i128 * (b.0 - o.0) as i128
    }

    /// Whether closed segments ab and cd share a point.
    fn meet(a: P, b: P, c: P, d: P) -> bool {
        let (d1, d2) = (cross_i(a, b, c).signum(), cross_i(a, b, d).signum());
        let (d3, d4) = (cross_i(c, d, a).signum(), cross_i(c, d, b).signum());
        let on = |p: P, q: P, r: P| {
            r.0 >= p.0.min(q.0) && r.0 <= p.0.max(q.0) && r.1 >= p.1.min(q.1) && r.1 <= p.1.max(q.1)
        };
        (d1 * d2 < 0 && d3 * d4 < 0)
            || (d1 == 0 && on(a, b, c))
            || (d2 == 0 && on(a, b, d))
            || (d3 == 0 && on(c, d, a))
            || (d4 == 0 && on(c, d, b))
    }

    /// Whether the polygon (repeated neighbours merged) is simple in the
    /// module's sense, by every pair of edges: `None` when all collinear.
    fn oracle(v: &[P]) -> Option<bool> {
        let mut r: Vec<P> = Vec::new();
        for &p in v {
            if r.last() != Some(&p) {
                r.push(p);
            }
        }
        while r.len() > 1 && r.first() == r.last() {
            r.pop();
        }
        let m = r.len();
        if m <= 3 || r.iter().all(|&c| cross_i(r[0], r[1], c) == 0) {
            return None;
        }
        for i in 0..m {
            let (a, b, c) = (r[i], r[(i + 1) % m], r[(i + 2) % m]);
            // Neighbours meet beyond their shared vertex only when the
            // polygon doubles back there.
            let dot = (a.0 - b.0) as i128 * (c.0 - b.0) as i128
                + (a.1 - b.1) as i128 * (c.1 - b.1) as i128;
            if cross_i(a, b, c) == 0 && dot > 0 {
                return Some(false);
            }
            for j in i + 2..m {
                if i == 0 && j == m - 1 {
                    continue;
                }
                if meet(r[i], r[(i + 1) % m], r[j], r[(j + 1) % m]) {
                    return Some(false);
                }
            }
        }
        Some(true)
    }

    fn float(v: &[P]) -> Vec<DVec2> {
        v.iter()
            .map(|&(x, y)| DVec2::new(x as f64, y as f64))
            .collect()
    }

    /// A random polygon on a small grid: crossings, touches, overlaps,
    /// collinear runs and repeats are all frequent.
    fn grid_polygon() -> impl Strategy<Value = Vec<P>> {
        prop::collection::vec((0i64..6, 0i64..6), 4..14)
    }

    /// A random star-shaped polygon (simple unless two angles coincide),
    /// snapped to a grid so that some vertices touch edges.
    fn star_polygon() -> impl Strategy<Value = Vec<P>> {
        prop::collection::vec((0.0f64..std::f64::consts::TAU, 1i64..40), 4..60).prop_map(|mut v| {
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.iter()
                .map(|&(a, r)| {
                    let r = r as f64;
                    (
                        (r * crate::math::cos(a)).round() as i64,
                        (r * crate::math::sin(a)).round() as i64,
                    )
                })
                .collect()
        })
    }

    #[test]
    fn convex_quads_take_the_quad_shortcut_and_others_do_not() {
        let quad = |v: [[f64; 2]; 4]| turns_strictly_one_way(&pts(&v));
        assert!(quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]));
        assert!(quad([[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]));
        assert!(
            !quad([[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]),
            "a bow tie"
        );
        assert!(
            !quad([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, 0.5]]),
            "concave"
        );
        assert!(
            !quad([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]]),
            "a straight vertex"
        );
    }

    #[test]
    fn convex_polygons_take_the_shortcut_and_others_do_not() {
        let shortcut = |v: &[[f64; 2]]| convex_without_repeats(&pts(v));
        assert!(shortcut(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]));
        assert!(shortcut(&[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]));
        assert!(shortcut(&[
            [98.8, 1.6],
            [98.8, 1.6 + 1e-9],
            [100.0, 0.0],
            [99.0, 0.5]
        ]));
        // A merged run: straight on at the cells' shared corners.
        assert!(shortcut(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [0.0, 1.0]
        ]));
        for (v, why) in [
            (
                [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],
                "a bow tie",
            ),
            ([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, 0.5]], "concave"),
            ([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0]], "a repeat"),
            (
                [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
                "doubling back",
            ),
        ] {
            assert!(!shortcut(&v), "{why}");
        }
        let pentagram = [
            [0.0, 10.0],
            [6.0, -8.0],
            [-9.0, 3.0],
            [9.0, 3.0],
            [-6.0, -8.0],
        ];
        assert!(!shortcut(&pentagram), "round twice");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        #[test]
        fn the_sweep_agrees_with_every_pair_of_edges(v in grid_polygon()) {
            let p = float(&v);
            let want = oracle(&v);
            let sweep = find_contact_by_sweep(&p);
            let pairs = Ring::new(&p).and_then(|r| r.fold_back().or_else(|| r.pairwise()));
            prop_assert_eq!(sweep.is_none(), want != Some(false), "{:?} {:?}", v, sweep);
            prop_assert_eq!(pairs.is_none(), want != Some(false), "{:?} {:?}", v, pairs);
            // With the convex shortcut.
            prop_assert_eq!(find_contact(&p).is_none(), want != Some(false), "{:?}", v);
        }

        #[test]
        fn the_sweep_agrees_on_star_shapes(v in star_polygon()) {
            let p = float(&v);
            let want = oracle(&v);
            let sweep = find_contact_by_sweep(&p);
            prop_assert_eq!(sweep.is_none(), want != Some(false), "{:?} {:?}", v, sweep);
            prop_assert_eq!(find_contact(&p).is_none(), want != Some(false), "{:?}", v);
        }

        /// The quadrilateral shortcut calls simple only what is.
        #[test]
        fn a_quad_turning_one_way_is_simple(v in prop::collection::vec((0i64..6, 0i64..6), 4)) {
            if turns_strictly_one_way(&float(&v)) {
                prop_assert_eq!(oracle(&v), Some(true), "{:?}", v);
                prop_assert!(find_contact(&float(&v)).is_none(), "{:?}", v);
            }
        }

        /// The convex shortcut calls simple only what is.
        #[test]
        fn a_convex_polygon_without_repeats_is_simple(v in grid_polygon()) {
            if convex_without_repeats(&float(&v)) {
                prop_assert_ne!(oracle(&v), Some(false), "{:?}", v);
                prop_assert!(find_contact(&float(&v)).is_none(), "{:?}", v);
            }
        }

        /// Convex polygons gone round once or more (a regular polygon's
        /// vertices taken k at a time: a pentagram for 5 and 2).
        #[test]
        fn the_convex_shortcut_counts_the_turns(n in 3usize..40, k in 1usize..5, r in 1i64..1000) {
            let v: Vec<P> = (0..n)
                .map(|i| {
                    let a = std::f64::consts::TAU * (i * k) as f64 / n as f64;
                    ((r as f64 * crate::math::cos(a)).round() as i64, (r as f64 * crate::math::sin(a)).round() as i64)
                })
                .collect();
            let want = oracle(&v);
            let p = float(&v);
            prop_assert_eq!(find_contact(&p).is_none(), want != Some(false), "{:?}", v);
            prop_assert_eq!(find_contact_by_sweep(&p).is_none(), want != Some(false), "{:?}", v);
            if convex_without_repeats(&p) {
                prop_assert_ne!(want, Some(false), "{:?}", v);
            }
        }

        /// The reported edges really meet (or the vertices coincide).
        #[test]
        fn the_contact_named_is_real(v in grid_polygon()) {
            let p = float(&v);
            let n = v.len();
            if let Some(c) = find_contact_by_sweep(&p) {
                let seg = |k: usize| (v[k], v[(k + 1) % n]);
                match c {
                    Contact::Cross { a, b, .. } | Contact::Overlap { a, b, .. } => {
                        let ((p0, p1), (p2, p3)) = (seg(a), seg(b));
                        prop_assert!(meet(p0, p1, p2, p3), "{:?} {:?}", v, c);
                    }
                    Contact::VertexOnEdge { vertex, edge, .. } => {
                        let (p0, p1) = seg(edge);
                        prop_assert!(meet(p0, p1, v[vertex], v[vertex]), "{:?} {:?}", v, c);
                    }
                    Contact::SamePoint { a, b } => prop_assert_eq!(v[a], v[b], "{:?}", c),
                }
            }
        }
    }
}
