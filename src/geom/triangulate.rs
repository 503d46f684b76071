//! Triangulation of a simple polygon in O(n log n): the exact resolver's
//! convex pieces of a concave polygon (`raster::project`).
//!
//! The method is the textbook one (Garey, Johnson, Preparata and Tarjan 1978;
//! de Berg et al., *Computational Geometry*, ch. 3): a sweep from top to bottom
//! adds diagonals that cut the polygon into y-monotone pieces, and each piece
//! is triangulated in linear time with a stack. It replaces ear clipping,
//! whose time grows with the square of the vertex count (a concave outline of
//! a million vertices ran for hours), and mapbox's earcut, which is fast on
//! typical outlines but also quadratic on stars and combs (measured in
//! `bench/RESULTS-triangulate.md`).
//!
//! Exactness: every decision is a comparison of coordinates or an exact
//! orientation ([`super::polygon::orient2d`]), and the triangles use the
//! polygon's own vertices, so for a simple polygon the triangles tile it
//! exactly: each has positive area, they do not overlap, and their areas add
//! up to the polygon's. Ties are broken symbolically: points of equal y are
//! swept left to right (as if the plane were turned by an infinitesimal
//! angle), so horizontal edges and equal heights need no special case.
//! Repeated vertices, collinear vertices and zero-width spikes are dropped
//! first; they bound no area.
//!
//! Input outside the contract (a polygon that crosses or touches itself,
//! which [`super::simple`] refuses when records are read) gives some
//! triangles, in the same time, without panicking: their areas need not add
//! up to anything.

use super::polygon::orient2d;
use super::sweep::{Seg, Treap};
use glam::DVec2;

const NIL: u32 = u32::MAX;

/// Triangles tiling a simple polygon, as indices of its vertices, each listed
/// in the polygon's own orientation (counter-clockwise for a counter-clockwise
/// polygon). At most n - 2 of them; none when the polygon has no area.
pub fn triangulate(p: &[DVec2]) -> Vec<[u32; 3]> {
    let n = p.len();
    if n < 3 || n >= NIL as usize || p.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let Some((next, prev, alive)) = clean_ring(p) else {
        return Vec::new();
    };
    // Vertices from the top (greatest y; at equal y, least x first).
    let mut order: Vec<u32> = alive;
    order.sort_unstable_by(|&a, &b| {
        let (pa, pb) = (p[a as usize], p[b as usize]);
        pb.y.total_cmp(&pa.y)
            .then(pa.x.total_cmp(&pb.x))
            .then(a.cmp(&b))
    });
    let mut rank = vec![0u32; n];
    for (r, &v) in order.iter().enumerate() {
        rank[v as usize] = r as u32;
    }
    // The top vertex is a corner of the convex hull, so its turn is the
    // polygon's orientation. Work counter-clockwise: `nx` follows it.
    let top = order[0] as usize;
    let flipped = orient2d(p[prev[top] as usize], p[top], p[next[top] as usize]) < 0.0;
    let (nx, pv) = if flipped { (prev, next) } else { (next, prev) };
    let ring = Ring { p, nx, pv, rank };
    let diagonals = ring.monotone_diagonals(&order);
    let mut out = Vec::with_capacity(order.len() - 2);
    ring.faces(&order, &diagonals, |face| {
        ring.triangulate_monotone(face, &mut out)
    });
    if flipped {
        for t in &mut out {
            t.swap(1, 2);
        }
    }
    out
}

/// The polygon as a ring without repeated neighbours and without vertices
/// that do not turn (collinear ones and the tips of zero-width spikes):
/// `next` and `prev` over the input's indices, and the vertices left. `None`
/// when fewer than 3 are left (no area).
#[allow(clippy::type_complexity)]
fn clean_ring(p: &[DVec2]) -> Option<(Vec<u32>, Vec<u32>, Vec<u32>)> {
    let n = p.len();
    let mut next: Vec<u32> = (1..=n as u32).collect();
    next[n - 1] = 0;
    let mut prev: Vec<u32> = (0..n as u32).map(|i| i.wrapping_sub(1)).collect();
    prev[0] = n as u32 - 1;
    let mut alive = vec![true; n];
    let mut count = n;
    let mut work: Vec<u32> = (0..n as u32).rev().collect();
    while let Some(v) = work.pop() {
        let v = v as usize;
        if !alive[v] {
            continue;
        }
        if count < 3 {
            return None;
        }
        let (a, c) = (prev[v] as usize, next[v] as usize);
        if p[a] == p[v] || orient2d(p[a], p[v], p[c]) == 0.0 {
            alive[v] = false;
            count -= 1;
            next[a] = c as u32;
            prev[c] = a as u32;
            work.push(a as u32);
            work.push(c as u32);
        }
    }
    if count < 3 {
        return None;
    }
    let left = (0..n as u32).filter(|&v| alive[v as usize]).collect();
    Some((next, prev, left))
}

/// The cleaned polygon, counter-clockwise, with each vertex's place in the sweep.
struct Ring<'a> {
    p: &'a [DVec2],
    /// Next vertex counter-clockwise; edge `v` runs from `v` to `nx[v]`.
    nx: Vec<u32>,
    /// Previous vertex counter-clockwise.
    pv: Vec<u32>,
    /// Place in the sweep: 0 for the top vertex.
    rank: Vec<u32>,
}

/// Which side of a monotone piece a vertex is on.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
}

impl Ring<'_> {
    #[inline]
    fn pt(&self, v: u32) -> DVec2 {
        self.p[v as usize]
    }

    /// Edge `e`, from its upper end down.
    #[inline]
    fn seg(&self, e: u32) -> Seg {
        [self.pt(e), self.pt(self.nx[e as usize])]
    }

    /// The sweep (de Berg et al., algorithm MakeMonotone): the diagonals that
    /// cut the polygon into y-monotone pieces. The status holds the edges on
    /// the polygon's left side that the sweep line crosses, left to right,
    /// each with its helper, the lowest vertex seen since whose connection to
    /// the edge's right stays inside.
    fn monotone_diagonals(&self, order: &[u32]) -> Vec<(u32, u32)> {
        let n = self.p.len();
        let mut status = Treap::new(n);
        let mut helper = vec![NIL; n];
        let mut is_merge = vec![false; n];
        let mut diagonals = Vec::new();
        let above = |a: u32, b: u32| self.rank[a as usize] < self.rank[b as usize];
        for &v in order {
            let vi = v as usize;
            let (a, c) = (self.pv[vi], self.nx[vi]);
            let convex = orient2d(self.pt(a), self.pt(v), self.pt(c)) > 0.0;
            // Whether an edge (running down the polygon's left side, the
            // inside on its +x side) passes to the left of v.
            let at = self.pt(v);
            let left = |&[a, b]: &Seg| orient2d(a, b, at) > 0.0;
            let left_of = |status: &Treap| status.last_where(|s, _| left(s));
            let insert = |status: &mut Treap, helper: &mut Vec<u32>| {
                status.insert(v, self.seg(v), |s, _| !left(s));
                helper[vi] = v;
            };
            // Ends the edge arriving from above at v (edge `a`).
            let close = |status: &mut Treap, diagonals: &mut Vec<(u32, u32)>| {
                let h = helper[a as usize];
                if h != NIL && is_merge[h as usize] {
                    diagonals.push((v, h));
                }
                status.remove(a);
            };
            match (above(a, v), above(c, v)) {
                // Start (convex) or split (reflex): both neighbours below.
                (false, false) => {
                    if !convex {
                        if let Some(e) = left_of(&status) {
                            diagonals.push((v, helper[e as usize]));
                            helper[e as usize] = v;
                        }
                    }
                    insert(&mut status, &mut helper);
                }
                // End (convex) or merge (reflex): both neighbours above.
                (true, true) => {
                    close(&mut status, &mut diagonals);
                    if !convex {
                        is_merge[vi] = true;
                        if let Some(e) = left_of(&status) {
                            let h = helper[e as usize];
                            if is_merge[h as usize] {
                                diagonals.push((v, h));
                            }
                            helper[e as usize] = v;
                        }
                    }
                }
                // On the left side, going down.
                (true, false) => {
                    close(&mut status, &mut diagonals);
                    insert(&mut status, &mut helper);
                }
                // On the right side, going up.
                (false, true) => {
                    if let Some(e) = left_of(&status) {
                        let h = helper[e as usize];
                        if is_merge[h as usize] {
                            diagonals.push((v, h));
                        }
                        helper[e as usize] = v;
                    }
                }
            }
        }
        diagonals
    }

    /// Calls `each` with every face of the polygon cut by `diagonals`, its
    /// vertices counter-clockwise. Each face is walked with the inside on the
    /// left: at every vertex the walk takes the first way out clockwise from
    /// the way it came in.
    fn faces(&self, order: &[u32], diagonals: &[(u32, u32)], mut each: impl FnMut(&[u32])) {
        let n = self.p.len();
        // Ways out of each vertex: its edge, then its diagonals (CSR).
        let mut start = vec![0u32; n + 1];
        for &v in order {
            start[v as usize + 1] += 1;
        }
        for &(a, b) in diagonals {
            start[a as usize + 1] += 1;
            start[b as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let total = start[n] as usize;
        let mut to = vec![NIL; total];
        let mut fill = start.clone();
        let mut put = |from: u32, t: u32| {
            to[fill[from as usize] as usize] = t;
            fill[from as usize] += 1;
        };
        for &v in order {
            put(v, self.nx[v as usize]);
        }
        for &(a, b) in diagonals {
            put(a, b);
            put(b, a);
        }
        let mut used = vec![false; total];
        let mut face: Vec<u32> = Vec::new();
        for &v in order {
            for h0 in start[v as usize]..start[v as usize + 1] {
                if used[h0 as usize] {
                    continue;
                }
                face.clear();
                let (mut from, mut h) = (v, h0);
                let closed = loop {
                    used[h as usize] = true;
                    face.push(from);
                    let w = to[h as usize];
                    let next = self.way_out(w, from, &start, &to);
                    if next == h0 {
                        break true;
                    }
                    if used[next as usize] || face.len() > total {
                        // Only for input outside the contract.
                        break false;
                    }
                    (from, h) = (w, next);
                };
                if closed && face.len() >= 3 {
                    each(&face);
                }
            }
        }
    }

    /// At vertex `w`, reached from `from`: the way out (an index into `to`)
    /// first clockwise from the direction back to `from`.
    fn way_out(&self, w: u32, from: u32, start: &[u32], to: &[u32]) -> u32 {
        let (s, e) = (start[w as usize], start[w as usize + 1]);
        if e - s == 1 {
            return s;
        }
        let (pw, pf) = (self.pt(w), self.pt(from));
        // Clockwise angle from w→from, in four classes: (0, π), π, (π, 2π), 0.
        let class = |t: u32| {
            let pt = self.pt(t);
            let o = orient2d(pw, pf, pt);
            if o < 0.0 {
                0
            } else if o > 0.0 {
                2
            } else if (pt - pw).dot(pf - pw) < 0.0 {
                1
            } else {
                3
            }
        };
        let mut best = s;
        let mut best_class = class(to[s as usize]);
        for h in s + 1..e {
            let t = to[h as usize];
            let c = class(t);
            let better = c < best_class
                || (c == best_class
                    && (c == 0 || c == 2)
                    // t is met first, turning clockwise from `from`,
                    // when it lies counter-clockwise of the best so far.
                    && orient2d(pw, self.pt(to[best as usize]), self.pt(t)) > 0.0);
            if better {
                best = h;
                best_class = c;
            }
        }
        best
    }

    /// Triangulates one y-monotone piece (de Berg et al., algorithm
    /// TriangulateMonotonePolygon): its vertices merged from top to bottom,
    /// a stack holding the reflex chain not yet cut off.
    fn triangulate_monotone(&self, f: &[u32], out: &mut Vec<[u32; 3]>) {
        let k = f.len();
        let emit = |out: &mut Vec<[u32; 3]>, a: u32, b: u32, c: u32| {
            let o = orient2d(self.pt(a), self.pt(b), self.pt(c));
            if o > 0.0 {
                out.push([a, b, c]);
            } else if o < 0.0 {
                out.push([a, c, b]);
            }
        };
        if k == 3 {
            emit(out, f[0], f[1], f[2]);
            return;
        }
        let rank = |i: usize| self.rank[f[i % k] as usize];
        let t = (0..k)
            .min_by_key(|&i| rank(i))
            .expect("a face has vertices");
        let b = (0..k)
            .max_by_key(|&i| rank(i))
            .expect("a face has vertices");
        // Down the left side from the top, then up the right side.
        let monotone = {
            let mut i = t;
            let mut ok = true;
            while i % k != b {
                ok &= rank(i) < rank(i + 1);
                i += 1;
            }
            while i % k != t {
                ok &= rank(i) > rank(i + 1);
                i += 1;
            }
            ok
        };
        if !monotone {
            // Only for input outside the contract: a fan.
            for i in 1..k - 1 {
                emit(out, f[0], f[i], f[i + 1]);
            }
            return;
        }
        let mut u: Vec<(u32, Side)> = Vec::with_capacity(k);
        u.push((f[t], Side::Left));
        let (mut l, mut r) = ((t + 1) % k, (t + k - 1) % k);
        while l != b || r != b {
            if r == b || (l != b && rank(l) < rank(r)) {
                u.push((f[l], Side::Left));
                l = (l + 1) % k;
            } else {
                u.push((f[r], Side::Right));
                r = (r + k - 1) % k;
            }
        }
        u.push((f[b], Side::Left));
        let mut stack: Vec<(u32, Side)> = vec![u[0], u[1]];
        for j in 2..k - 1 {
            let (v, side) = u[j];
            let top = *stack.last().expect("the stack holds two vertices or more");
            if side != top.1 {
                // The other side: a fan to the whole chain.
                for w in stack.windows(2) {
                    emit(out, v, w[0].0, w[1].0);
                }
                stack.clear();
                stack.push(u[j - 1]);
                stack.push(u[j]);
            } else {
                // The same side: cut off the corners that turn inwards.
                let mut last = stack.pop().expect("the stack holds two vertices or more");
                while let Some(&s) = stack.last() {
                    let (a, m, c) = (self.pt(s.0), self.pt(last.0), self.pt(v));
                    let inside = match side {
                        Side::Left => orient2d(a, m, c) > 0.0,
                        Side::Right => orient2d(c, m, a) > 0.0,
                    };
                    if !inside {
                        break;
                    }
                    emit(out, s.0, last.0, v);
                    last = stack.pop().expect("just looked");
                }
                stack.push(last);
                stack.push(u[j]);
            }
        }
        let bottom = u[k - 1].0;
        for w in stack.windows(2) {
            emit(out, bottom, w[0].0, w[1].0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polygon::area2;
    use proptest::prelude::*;

    fn pts(v: &[[f64; 2]]) -> Vec<DVec2> {
        v.iter().map(|&[x, y]| DVec2::new(x, y)).collect()
    }

    /// Sum of the triangles' doubled areas, and whether each is positive
    /// (for a counter-clockwise polygon).
    fn tri_area(p: &[DVec2], t: &[[u32; 3]]) -> (f64, bool) {
        let mut sum = 0.0;
        let mut positive = true;
        for &[a, b, c] in t {
            let x = area2(&[p[a as usize], p[b as usize], p[c as usize]]);
            positive &= x > 0.0;
            sum += x;
        }
        (sum, positive)
    }

    #[test]
    fn an_l_with_repeated_and_collinear_vertices_is_tiled() {
        let l = pts(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ]);
        let t = triangulate(&l);
        let (sum, positive) = tri_area(&l, &t);
        assert_eq!(sum, area2(&l));
        assert!(positive);
        assert!(t.len() <= l.len() - 2);
    }

    #[test]
    fn clockwise_polygons_give_clockwise_triangles() {
        let mut l = pts(&[
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ]);
        l.reverse();
        let t = triangulate(&l);
        assert_eq!(t.len(), 4);
        for &[a, b, c] in &t {
            assert!(area2(&[l[a as usize], l[b as usize], l[c as usize]]) < 0.0);
        }
        let sum: f64 = t
            .iter()
            .map(|&[a, b, c]| area2(&[l[a as usize], l[b as usize], l[c as usize]]))
            .sum();
        assert_eq!(sum, area2(&l));
    }

    #[test]
    fn degenerate_polygons_have_no_triangles() {
        assert!(triangulate(&pts(&[[0.0, 0.0], [1.0, 1.0]])).is_empty());
        assert!(triangulate(&pts(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [1.0, 1.0]])).is_empty());
        assert!(triangulate(&pts(&[[1.0, 1.0]; 6])).is_empty());
        assert!(triangulate(&pts(&[[0.0, 0.0], [f64::NAN, 1.0], [1.0, 0.0]])).is_empty());
    }

    #[test]
    fn outside_the_contract_it_still_ends() {
        // A bow-tie and a pentagram: some triangles, no panic.
        let _ = triangulate(&pts(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]));
        let star: Vec<DVec2> = (0..5)
            .map(|i| {
                let a = std::f64::consts::TAU * (2 * i) as f64 / 5.0;
                DVec2::new(crate::math::cos(a), crate::math::sin(a))
            })
            .collect();
        assert!(triangulate(&star).len() <= 3);
    }

    /// A star of `n` vertices alternating between radii 1 and `inner`.
    fn star(n: usize, inner: f64) -> Vec<DVec2> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let r = if i % 2 == 0 { 1.0 } else { inner };
                DVec2::new(r * crate::math::cos(a), r * crate::math::sin(a))
            })
            .collect()
    }

    #[test]
    fn a_million_vertex_star_is_tiled() {
        let s = star(1_000_000, 0.5);
        let t = triangulate(&s);
        assert_eq!(t.len(), s.len() - 2);
        let (sum, positive) = tri_area(&s, &t);
        assert!(positive);
        let a = area2(&s);
        assert!((sum - a).abs() <= 1e-12 * a, "{sum} vs {a}");
    }

    // ---- Independent checks on integer polygons. ----

    type P = (i64, i64);

    fn cross_i(o: P, a: P, b: P) -> i128 {
        (a.0 - o.0) as i128 * (b.1 - o.1) as i128 - (a.1 - o.1) as i128 * (b.0 - o.0) as i128
    }

    /// Nonzero winding number of `q` about the polygon (q on no edge).
    fn winding(v: &[P], q: P) -> i32 {
        let n = v.len();
        let mut w = 0;
        for i in 0..n {
            let (a, b) = (v[i], v[(i + 1) % n]);
            if a.1 <= q.1 {
                if b.1 > q.1 && cross_i(a, b, q) > 0 {
                    w += 1;
                }
            } else if b.1 <= q.1 && cross_i(a, b, q) < 0 {
                w -= 1;
            }
        }
        w
    }

    /// A random simple polygon: random points on a grid, untangled by 2-opt
    /// moves (reversing the stretch between two crossing edges) until no two
    /// edges cross, then kept only if [`super::super::simple`] finds it
    /// simple (touching is left to the filter). Vertices are then doubled
    /// and collinear midpoints added at random, which must change nothing.
    fn simple_polygon() -> impl Strategy<Value = Vec<P>> {
        (
            prop::collection::vec((0i64..30, 0i64..30), 3..40),
            prop::collection::vec(0u8..4, 40),
        )
            .prop_filter_map("not simple", |(mut v, extras)| {
                v.sort();
                v.dedup();
                let n = v.len();
                if n < 3 {
                    return None;
                }
                let crosses = |a: P, b: P, c: P, d: P| {
                    cross_i(a, b, c).signum() * cross_i(a, b, d).signum() < 0
                        && cross_i(c, d, a).signum() * cross_i(c, d, b).signum() < 0
                };
                let mut changed = true;
                let mut rounds = 0;
                while changed && rounds < 200 {
                    changed = false;
                    rounds += 1;
                    for i in 0..n {
                        for j in i + 2..n {
                            if crosses(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]) {
                                v[i + 1..=j].reverse();
                                changed = true;
                            }
                        }
                    }
                }
                let f: Vec<DVec2> = v
                    .iter()
                    .map(|&(x, y)| DVec2::new(x as f64, y as f64))
                    .collect();
                if super::super::simple::find_contact(&f).is_some() || area2(&f) == 0.0 {
                    return None;
                }
                let mut out = Vec::new();
                for (i, &p) in v.iter().enumerate() {
                    out.push(p);
                    match extras[i % extras.len()] {
                        1 => out.push(p),
                        2 => {
                            let q = v[(i + 1) % n];
                            if (p.0 + q.0) % 2 == 0 && (p.1 + q.1) % 2 == 0 {
                                out.push(((p.0 + q.0) / 2, (p.1 + q.1) / 2));
                            }
                        }
                        _ => {}
                    }
                }
                Some(out)
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Triangles of a simple integer polygon, checked in exact integer
        /// arithmetic: each turns the polygon's way with positive area, their
        /// doubled areas add up to the polygon's exactly, and every point of
        /// a fine grid off the edges is covered by exactly as many triangles
        /// as the polygon winds around it (one inside, none outside).
        #[test]
        fn triangles_tile_simple_polygons_exactly(v in simple_polygon()) {
            let p: Vec<DVec2> = v.iter().map(|&(x, y)| DVec2::new(x as f64, y as f64)).collect();
            let t = triangulate(&p);
            let n = v.len() as i128;
            let area: i128 = (0..n).map(|i| cross_i((0, 0), v[i as usize], v[((i + 1) % n) as usize])).sum();
            let sign = area.signum();
            prop_assert!(sign != 0);
            let mut sum = 0i128;
            for &[a, b, c] in &t {
                let x = cross_i(v[a as usize], v[b as usize], v[c as usize]);
                prop_assert!(x * sign > 0, "{:?}: triangle {:?}", v, [a, b, c]);
                sum += x;
            }
            prop_assert_eq!(sum, area, "{:?}", v);
            // Sample points of a fine grid, scaled so that none lies on the
            // line through two vertices: with S = 10007 and offsets (1, 97),
            // such a line's direction (dx, dy) would need dy = 97 dx with
            // |dx|, |dy| < 30, so dx = dy = 0.
            const S: i64 = 10_007;
            let s: Vec<P> = v.iter().map(|&(x, y)| (S * x, S * y)).collect();
            for gx in 0..30 {
                for gy in 0..30 {
                    let q = (S * gx + 1, S * gy + 97);
                    let want = winding(&s, q).abs();
                    let got = t
                        .iter()
                        .filter(|&&[a, b, c]| {
                            let tri = [s[a as usize], s[b as usize], s[c as usize]];
                            winding(&tri, q) != 0
                        })
                        .count() as i32;
                    prop_assert_eq!(got, want, "{:?} at {:?}", v, q);
                }
            }
        }

        /// Floating-point stars with random radii: areas add up to 1e-12.
        #[test]
        fn triangles_tile_random_stars(
            radii in prop::collection::vec(0.01f64..10.0, 3..300),
            turn in 0.0f64..1.0,
            center in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let n = radii.len();
            let p: Vec<DVec2> = radii
                .iter()
                .enumerate()
                .map(|(i, &r)| {
                    let a = std::f64::consts::TAU * (i as f64 + turn) / n as f64;
                    DVec2::new(center.0 + r * crate::math::cos(a), center.1 + r * crate::math::sin(a))
                })
                .collect();
            let t = triangulate(&p);
            let (sum, positive) = tri_area(&p, &t);
            let a = area2(&p);
            prop_assert!(positive);
            prop_assert!((sum - a).abs() <= 1e-12 * a.abs(), "{} vs {}", sum, a);
        }
    }
}
