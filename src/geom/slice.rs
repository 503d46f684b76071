//! Slicing a convex polygon along a pencil of lines: the pieces between
//! consecutive lines `N(p) - t·D(p) = 0`, `t` an integer, of a projective
//! coordinate `t(p) = N(p) / D(p)` with `N`, `D` affine and `D > 0`.
//!
//! This is how a fragment is cut into texel cells (`texture::cells`): under
//! the projective map of `texture::map` the texel rows are the slices of the
//! fragment along `v = j`, and a row's cells the slices of its strip along
//! `u = k`. Clipping each cell by two half-planes costs two
//! Sutherland–Hodgman passes over the whole strip per cell. Here the
//! polygon's boundary is split once into its two chains from the vertex of
//! least `t` to the vertex of greatest `t`, and a slice is the chord at `t`,
//! the chain vertices between, and the chord at `t + 1`: O(1) per slice
//! beyond the vertices it holds, and each chord is computed once, on an
//! edge of the original polygon, so neighbouring slices share their chord's
//! points bit for bit (no gap or overlap between them).
//!
//! A crossing is found where `g = N - t·D` changes sign along an edge, at
//! `g_a / (g_a - g_b)` from its end `a` (the rule of
//! `polygon::clip_against`): `g` is affine along the edge, `t` is not.

use glam::DVec2;

/// Reusable state for slicing one convex polygon at a time.
#[derive(Default)]
pub struct Slicer {
    /// The polygon, counter-clockwise.
    verts: Vec<DVec2>,
    /// `(N, D)` at each vertex.
    nd: Vec<(f64, f64)>,
    /// `t = N / D` at each vertex.
    t: Vec<f64>,
    /// Vertex indices from least to greatest `t`, counter-clockwise.
    lower: Vec<u32>,
    /// The same, clockwise.
    upper: Vec<u32>,
    /// The slice being built.
    out: Vec<DVec2>,
}

impl Slicer {
    /// Takes the convex counter-clockwise polygon `poly` and the affine `num`
    /// and `den` (`[a, b, c]` for `a·x + b·y + c`). Returns the least and
    /// greatest `t` over its vertices, or `None` when it has fewer than three
    /// vertices, `den` is not positive at every vertex, or a `t` is not finite.
    pub fn load(&mut self, poly: &[DVec2], num: [f64; 3], den: [f64; 3]) -> Option<(f64, f64)> {
        if poly.len() < 3 {
            return None;
        }
        self.verts.clear();
        self.verts.extend_from_slice(poly);
        self.nd.clear();
        self.t.clear();
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in poly.iter().enumerate() {
            let n = num[0] * p.x + num[1] * p.y + num[2];
            let d = den[0] * p.x + den[1] * p.y + den[2];
            let t = n / d;
            if !(d > 0.0 && t.is_finite()) {
                return None;
            }
            self.nd.push((n, d));
            self.t.push(t);
            if t < self.t[lo] {
                lo = i;
            }
            if t > self.t[hi] {
                hi = i;
            }
        }
        let n = poly.len();
        self.lower.clear();
        self.upper.clear();
        let mut i = lo;
        loop {
            self.lower.push(i as u32);
            if i == hi {
                break;
            }
            i = (i + 1) % n;
        }
        let mut i = lo;
        loop {
            self.upper.push(i as u32);
            if i == hi {
                break;
            }
            i = (i + n - 1) % n;
        }
        Some((self.t[lo], self.t[hi]))
    }

    /// Calls `each(t, slice)` for each `t` of `ts` (increasing) whose slice
    /// `t <= N/D <= t + 1` of the loaded polygon has three vertices or more:
    /// convex, counter-clockwise, with no repeated consecutive vertex.
    pub fn slices(
        &mut self,
        ts: impl IntoIterator<Item = i64>,
        mut each: impl FnMut(i64, &[DVec2]),
    ) {
        if self.lower.is_empty() {
            return;
        }
        if self.lower.len() == 1 {
            // Every vertex has the same t: the polygon lies in one slice
            // (or on one line of the pencil, with no area).
            let t0 = self.t[0];
            for t in ts {
                if (t as f64) <= t0 && t0 <= (t + 1) as f64 {
                    each(t, &self.verts);
                    return;
                }
            }
            return;
        }
        // Where the walk along each chain stands: the chain edge
        // `at..at + 1` holding the crossing of the last line reached.
        let (mut lw, mut uw) = (0, 0);
        // The chord at the last `t + 1` reached, to reuse as the next
        // slice's lower chord when that slice is `t + 1`.
        let mut chord: Option<(i64, DVec2, DVec2)> = None;
        for t in ts {
            let (lo_l, lo_u) = match chord {
                Some((c, l, u)) if c == t => (l, u),
                _ => {
                    let tf = t as f64;
                    self.advance(&self.lower, &mut lw, tf);
                    self.advance(&self.upper, &mut uw, tf);
                    (
                        self.crossing(&self.lower, lw, tf),
                        self.crossing(&self.upper, uw, tf),
                    )
                }
            };
            let t1 = (t + 1) as f64;
            self.out.clear();
            self.out.push(lo_l);
            // The lower chain's vertices up to t + 1.
            let from = lw;
            self.advance(&self.lower, &mut lw, t1);
            for k in from + 1..=lw {
                let p = self.verts[self.lower[k] as usize];
                push_new(&mut self.out, p);
            }
            let hi_l = self.crossing(&self.lower, lw, t1);
            push_new(&mut self.out, hi_l);
            let from = uw;
            self.advance(&self.upper, &mut uw, t1);
            let hi_u = self.crossing(&self.upper, uw, t1);
            push_new(&mut self.out, hi_u);
            for k in (from + 1..=uw).rev() {
                let p = self.verts[self.upper[k] as usize];
                push_new(&mut self.out, p);
            }
            push_new(&mut self.out, lo_u);
            if self.out.len() > 1 && self.out.first() == self.out.last() {
                self.out.pop();
            }
            chord = Some((t + 1, hi_l, hi_u));
            if self.out.len() >= 3 {
                each(t, &self.out);
            }
        }
    }

    /// Moves the walk `at` along `chain` past every vertex with
    /// `t <= line`. Where it stops depends only on `line`, not on the lines
    /// before it, so a slice is the same whichever slices came before.
    fn advance(&self, chain: &[u32], at: &mut usize, line: f64) {
        while *at + 1 < chain.len() && self.t[chain[*at + 1] as usize] <= line {
            *at += 1;
        }
    }

    /// Where the line `t = line` crosses the chain edge `at..at + 1` (the
    /// chain's last vertex when the walk has reached it).
    fn crossing(&self, chain: &[u32], at: usize, line: f64) -> DVec2 {
        let i = chain[at] as usize;
        let a = self.verts[i];
        let Some(&j) = chain.get(at + 1) else {
            return a;
        };
        let j = j as usize;
        let b = self.verts[j];
        let ga = self.nd[i].0 - line * self.nd[i].1;
        let gb = self.nd[j].0 - line * self.nd[j].1;
        if ga >= 0.0 {
            return a;
        }
        if gb <= 0.0 {
            return b;
        }
        a + (b - a) * (ga / (ga - gb))
    }
}

/// Pushes `p` unless it repeats the last vertex.
fn push_new(out: &mut Vec<DVec2>, p: DVec2) {
    if out.last() != Some(&p) {
        out.push(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polygon::{area2, clip_line};
    use proptest::prelude::*;

    /// The slices by the independent route: two half-plane clips each.
    fn clipped(poly: &[DVec2], num: [f64; 3], den: [f64; 3], t: i64) -> Vec<DVec2> {
        let side = |k: f64, s: f64| {
            [
                s * (num[0] - k * den[0]),
                s * (num[1] - k * den[1]),
                s * (num[2] - k * den[2]),
            ]
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        clip_line(poly, side(t as f64, 1.0), &mut a);
        clip_line(&a, side((t + 1) as f64, -1.0), &mut b);
        b
    }

    /// A convex polygon: `n` points on an ellipse about `c`, in order.
    fn ellipse(c: DVec2, r: DVec2, turn: f64, n: usize) -> Vec<DVec2> {
        (0..n)
            .map(|i| {
                let a = turn + std::f64::consts::TAU * i as f64 / n as f64;
                let (sn, cs) = crate::math::sin_cos(a);
                c + DVec2::new(r.x * cs, r.y * sn)
            })
            .collect()
    }

    proptest! {
        /// Each slice has the area of the same slice clipped by two
        /// half-planes, and the slices tile the polygon.
        #[test]
        fn slices_are_the_clipped_slices_and_tile_the_polygon(
            c in proptest::array::uniform2(-50.0f64..50.0),
            r in proptest::array::uniform2(0.01f64..3.0),
            turn in 0.0f64..std::f64::consts::TAU,
            n in 3usize..12,
            num in proptest::array::uniform3(-20.0f64..20.0),
            den in proptest::array::uniform2(-0.01f64..0.01),
        ) {
            let poly = ellipse(DVec2::from(c), DVec2::from(r), turn, n);
            let den = [den[0], den[1], 1.0];
            let mut s = Slicer::default();
            let Some((lo, hi)) = s.load(&poly, num, den) else {
                return Ok(());
            };
            prop_assume!(hi - lo < 5000.0);
            let ts = lo.floor() as i64..=(hi.ceil() as i64 - 1).max(lo.floor() as i64);
            let mut got = Vec::new();
            s.slices(ts, |t, slice| got.push((t, area2(slice))));
            let total: f64 = got.iter().map(|g| g.1).sum();
            let whole = area2(&poly);
            prop_assert!((total - whole).abs() <= 1e-9 * whole.max(1.0), "{total} vs {whole}");
            for (t, a) in got {
                prop_assert!(a >= -1e-9, "slice {t} is clockwise: {a}");
                let b = area2(&clipped(&poly, num, den, t));
                prop_assert!((a - b).abs() <= 1e-9 * whole.max(1.0), "slice {t}: {a} vs {b}");
            }
        }
    }
}
