//! Property tests of the partition's invariants (the list): random
//! convex and concave (star-shaped) polygons, with repeated and collinear
//! vertices, in planes whose normals lie exactly or nearly along each axis or
//! anywhere, up to 1e7 from the origin, at incr from 1e-3 to 1e3 of the size.
//!
//! Tolerances: plane-coordinate checks use 1e-9 of the polygon's size. World
//! vertices cannot be closer to the plane than the rounding of their own
//! coordinates, so the on-plane check allows 1e-9 of the size plus
//! [`ULP_SLACK`] of the largest coordinate.

use super::*;
use crate::geom::clip::clip_closed;
use crate::geom::plane::{map_to_plane, signed_area};
use crate::math;
use proptest::prelude::*;
use std::collections::{BTreeMap, BTreeSet};

/// How many cases a property test draws: `PROPTEST_CASES` if set (for a
/// longer hunt), else `default` (the CI budget). Shared with `differential`.
pub(super) fn cases_or(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Relative tolerance of every invariant (the 1e-9).
const REL: f64 = 1e-9;
/// Rounding of a world coordinate of magnitude m is about m * 2^-53; a few of
/// those per operation of `(origin + ey*y) + ex*x`.
const ULP_SLACK: f64 = 8.0 * f64::EPSILON;

/// Collects every cell a partition hands over (shared with `differential`).
#[derive(Default)]
pub(super) struct Cells {
    pub(super) cells: Vec<(i64, i64, Vec<DVec3>, Vec<DVec2>)>,
}
impl CellSink for Cells {
    fn wants(&mut self, _: i64, _: i64) -> bool {
        true
    }
    fn cell(&mut self, k: i64, j: i64, w: &[DVec3], p: &[DVec2], _: bool) {
        self.cells.push((k, j, w.to_vec(), p.to_vec()));
    }
}

/// The polygon in the plane, as (angle, radius) pairs sorted by angle: a
/// star-shaped, hence simple, polygon; convex when all radii are equal.
fn outline_2d(spokes: &[(f64, f64)], convex: bool, size: f64) -> Vec<DVec2> {
    let mut a: Vec<(f64, f64)> = spokes.to_vec();
    a.sort_by(|x, y| x.0.total_cmp(&y.0));
    a.dedup_by(|x, y| (x.0 - y.0).abs() < 1e-3);
    // Star-shaped about the origin only if the origin is inside: no angular
    // gap of π or more (else the polygon may cross itself).
    let gap = |i: usize| {
        let next = if i + 1 < a.len() {
            a[i + 1].0
        } else {
            a[0].0 + std::f64::consts::TAU
        };
        next - a[i].0
    };
    if a.len() < 3 || (0..a.len()).any(|i| gap(i) >= std::f64::consts::PI - 1e-3) {
        return Vec::new();
    }
    a.iter()
        .map(|&(t, r)| {
            let r = if convex { size } else { size * r };
            DVec2::new(r * math::cos(t), r * math::sin(t))
        })
        .collect()
}

/// Normal directions: exact axes, axes tilted by 1e-9, and anything.
fn normal_strategy() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        (0usize..6).prop_map(|i| [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            -DVec3::X,
            -DVec3::Y,
            -DVec3::Z
        ][i]),
        (0usize..6, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(i, a, b)| {
            let n = [
                DVec3::X,
                DVec3::Y,
                DVec3::Z,
                -DVec3::X,
                -DVec3::Y,
                -DVec3::Z,
            ][i];
            (n + n.any_orthonormal_pair().0 * (a * 1e-9) + n.any_orthonormal_pair().1 * (b * 1e-9))
                .normalize()
        }),
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
            .prop_filter("non-zero", |(a, b, c)| a * a + b * b + c * c > 1e-2)
            .prop_map(|(a, b, c)| DVec3::new(a, b, c).normalize()),
    ]
}

#[derive(Debug, Clone)]
struct Case {
    spokes: Vec<(f64, f64)>,
    convex: bool,
    /// Index of a vertex to repeat and of an edge to split at its midpoint.
    dup: usize,
    mid: usize,
    normal: DVec3,
    offset: DVec3,
    size: f64,
    /// log10 of incr / size.
    incr_exp: f64,
    horz: f64,
    vert: f64,
    rotate: f64,
}

fn case_strategy(incr_lo: f64) -> impl Strategy<Value = Case> {
    (
        prop::collection::vec((0.0f64..std::f64::consts::TAU, 0.2f64..1.0), 3..14),
        any::<bool>(),
        0usize..20,
        0usize..20,
        normal_strategy(),
        prop_oneof![
            Just(DVec3::ZERO),
            (-1e7f64..1e7, -1e7f64..1e7, -1e7f64..1e7).prop_map(|(a, b, c)| DVec3::new(a, b, c))
        ],
        prop_oneof![Just(1.0), 1e-2f64..1e3],
        incr_lo..3.0f64,
        -3.0f64..3.0,
        -3.0f64..3.0,
        prop_oneof![Just(0.0), -360.0f64..360.0],
    )
        .prop_map(
            |(spokes, convex, dup, mid, normal, offset, size, incr_exp, horz, vert, rotate)| Case {
                spokes,
                convex,
                dup,
                mid,
                normal,
                offset,
                size,
                incr_exp,
                horz,
                vert,
                rotate,
            },
        )
}

fn world_polygon(c: &Case) -> Option<Vec<DVec3>> {
    let mut p = outline_2d(&c.spokes, c.convex, c.size);
    if p.len() < 3 || signed_area(&p) <= 1e-3 * c.size * c.size {
        return None;
    }
    let m = c.mid % p.len();
    let mid = (p[m] + p[(m + 1) % p.len()]) * 0.5;
    p.insert(m + 1, mid);
    let d = c.dup % p.len();
    p.insert(d, p[d]);
    let (u, w) = c.normal.any_orthonormal_pair();
    // any_orthonormal_pair gives a right-handed (u, w, n): counter-clockwise
    // in (u, w) is counter-clockwise seen from +n.
    Some(p.iter().map(|q| c.offset + u * q.x + w * q.y).collect())
}

fn point_in_or_on(poly: &[DVec2], p: DVec2, tol: f64) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        // Near the boundary counts as in.
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        if (a + ab * t - p).length() <= tol {
            return true;
        }
        if (a.y > p.y) != (b.y > p.y) && a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) > p.x {
            inside = !inside;
        }
    }
    inside
}

/// Checks every invariant; returns a description of the first broken one.
fn check(c: &Case) -> Result<(), String> {
    let Some(v) = world_polygon(c) else {
        return Ok(());
    };
    let place = Placement {
        incr: c.size * math::powf(10f64, c.incr_exp),
        horz: c.horz,
        vert: c.vert,
    };
    check_partition(&v, c.rotate, place, Junctions::VertexToVertex)
}

/// How neighbouring cells must meet on their shared grid line.
#[derive(Clone, Copy, PartialEq)]
enum Junctions {
    /// With the same vertices, bit for bit.
    VertexToVertex,
    /// Not checked: a piece whose world ring rounding folded loses a vertex
    /// its neighbour keeps (`tidy::simple_in_world`); and a piece below the
    /// noise floor (`MIN_PIECE_AREA_REL`) is not written while its
    /// neighbour keeps the vertices they share, as where an input edge
    /// crosses a column line 1.3e-8 of the size from a grid corner (a
    /// case `inputs_off_their_plane_give_simple_pieces` drew: the piece
    /// beside it, with sides about 1e-8 of the size, is far below the floor).
    Unchecked,
}

/// Partitions the world polygon `v` and checks every invariant of its cells.
fn check_partition(
    v: &[DVec3],
    rotate: f64,
    place: Placement,
    junctions: Junctions,
) -> Result<(), String> {
    let mut poly = map_to_plane(v, rotate, 1e-6).map_err(|e| e.to_string())?;
    // As polyfill3 does: an input off its plane whose projection meets
    // itself is projected along the readers' axis instead.
    if let OnPlane::MeetsItself(contact) = simple_on_plane(&mut poly, v) {
        return Err(format!("the ring in the plane meets itself: {contact}"));
    }
    let incr = place.incr;
    let grid = Grid::new(&poly.points, place).unwrap();
    let mut out = Cells::default();
    Partitioner::new().run(&poly, &grid, &mut out);
    let tol = REL * poly.size;
    // Areas sum to the polygon's.
    let total: f64 = out.cells.iter().map(|x| signed_area(&x.3)).sum();
    let want = signed_area(&poly.points);
    if (total - want).abs() > REL * want {
        return Err(format!("area {total} != {want}"));
    }
    if (want - poly.area).abs() > REL * want {
        return Err(format!("plane area {want} != 3D area {}", poly.area));
    }
    let maxabs = v.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
    let wtol = tol + ULP_SLACK * maxabs;
    // The area of a piece that world coordinates cannot hold: one moved by
    // the mapping's rounding along a cell's perimeter. Far from the origin
    // such a piece maps to a fold of no area and is not written
    // (`tidy::WorldPiece::Noise`), so cells of less area may be missing.
    let world_noise = tidy::world_rounding(maxabs) * 4.0 * incr;
    for (k, j, w, p) in &out.cells {
        if signed_area(p) <= 0.0 {
            return Err(format!("cell ({k},{j}) has no positive area"));
        }
        // Simple as every reader judges it (exactly, on the world polygon).
        if let Err(contact) = crate::geom::simple::check(w) {
            return Err(format!("cell ({k},{j}) {w:?}: {contact}"));
        }
        let (x0, x1, y0, y1) = (grid.gx(*k), grid.gx(k + 1), grid.gy(*j), grid.gy(j + 1));
        for q in p {
            if q.x < x0 - tol || q.x > x1 + tol || q.y < y0 - tol || q.y > y1 + tol {
                return Err(format!("cell ({k},{j}) point {q} outside its cell"));
            }
            if !point_in_or_on(&poly.points, *q, tol) {
                return Err(format!("cell ({k},{j}) point {q} outside the polygon"));
            }
        }
        for x in w {
            let d = (*x - poly.frame.origin).dot(poly.frame.normal).abs();
            if d > wtol {
                return Err(format!("cell ({k},{j}) vertex {x} is {d:e} off the plane"));
            }
        }
        // Winding kept: the world polygon's normal agrees with the input's
        // (checked where the cell is large enough for its rounding not to matter).
        if signed_area(p) > 1e-6 * incr * incr {
            let n = crate::geom::plane::newell_normal(w, w[0]);
            if n.dot(poly.frame.normal) <= 0.0 {
                return Err(format!("cell ({k},{j}) winding flipped"));
            }
        }
    }
    // Count = cells whose intersection has positive area, by the thesis's
    // brute force (every cell of the box clipped against the whole polygon).
    if grid.cells() <= 40_000 {
        let (mut o, mut s) = (Vec::new(), Vec::new());
        let (mut sure, mut any) = (0usize, 0usize);
        // A cell may give several polygons (the parts of a concave polygon's piece).
        let mut ours: BTreeMap<(i64, i64), f64> = BTreeMap::new();
        for x in &out.cells {
            *ours.entry((x.0, x.1)).or_default() += signed_area(&x.3);
        }
        for j in grid.j0..=grid.j1 {
            for k in grid.k0..=grid.k1 {
                clip_closed(
                    &poly.points,
                    (grid.gx(k), grid.gy(j), grid.gx(k + 1), grid.gy(j + 1)),
                    &mut o,
                    &mut s,
                );
                let a = signed_area(&o);
                // Each cell covers exactly the cell ∩ polygon: same area.
                let mine = ours.get(&(k, j)).copied().unwrap_or(0.0);
                if (mine - a).abs() > REL * incr * (incr + poly.size) + world_noise {
                    return Err(format!("cell ({k},{j}) area {mine} != brute force {a}"));
                }
                any += (a > 0.0) as usize;
                sure += (a > (REL * incr * incr).max(world_noise)) as usize;
            }
        }
        let tiny = ours.values().filter(|&&a| a <= REL * incr * incr).count();
        let n = ours.len();
        if n < sure || n > any + tiny {
            return Err(format!(
                "{n} cells; brute force {sure}..={any} (+{tiny} slivers)"
            ));
        }
    }
    if junctions == Junctions::Unchecked {
        return Ok(());
    }
    // Neighbours share their boundary vertices bit for bit: the points each
    // cell has on a grid line it shares with a neighbour are the same.
    let mut on_line: BTreeMap<(i64, i64, u8), BTreeSet<[u64; 3]>> = BTreeMap::new();
    for (k, j, w, p) in &out.cells {
        for (q, x) in p.iter().zip(w) {
            let key = x.to_array().map(f64::to_bits);
            if q.x == grid.gx(k + 1) {
                on_line.entry((*k, *j, 0)).or_default().insert(key);
            }
            if q.x == grid.gx(*k) {
                on_line.entry((k - 1, *j, 1)).or_default().insert(key);
            }
            if q.y == grid.gy(j + 1) {
                on_line.entry((*k, *j, 2)).or_default().insert(key);
            }
            if q.y == grid.gy(*j) {
                on_line.entry((*k, j - 1, 3)).or_default().insert(key);
            }
        }
    }
    for ((k, j, side), pts) in &on_line {
        if *side == 0 || *side == 2 {
            let other = on_line.get(&(*k, *j, side + 1));
            if let Some(o) = other {
                // Cells meet vertex to vertex: the same points on the shared
                // line, bit for bit (no T-junctions).
                if pts != o {
                    return Err(format!(
                        "cells across line {side} of ({k},{j}) share no vertex: {pts:?} vs {o:?}"
                    ));
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases_or(96),
        ..ProptestConfig::default()
    })]

    #[test]
    fn partition_invariants(c in case_strategy(-2.3)) {
        let r = check(&c);
        prop_assert!(r.is_ok(), "{:?}: {}", c, r.unwrap_err());
    }
}

/// A comb whose walls and notch floors lie on grid lines, or a few ulps off
/// them, or a square with a notch whose tip does, tilted and turned in
/// space: the inputs whose pieces rounding folds or crosses, or splits into
/// parts touching at a point (reviews of 2026-11-29; `tidy`). Found by
/// fuzzers of such combs, notches and stars, where about 1 in 12 combs gave
/// a piece every reader refused.
#[derive(Debug, Clone)]
struct Comb {
    shape: Shape,
    teeth: usize,
    /// Tooth width, notch floor and tooth top, in texels.
    width: f64,
    floor: f64,
    top: f64,
    /// Ulps added to every notch floor and left wall (negative: taken off).
    floor_ulps: i32,
    wall_ulps: i32,
    incr: f64,
    /// Tilt about x, then turn about z, radians; then moved by `offset`
    /// (up to 3e6 from the origin, where a cell's sliver can map to noise).
    tilt: f64,
    turn: f64,
    offset: DVec3,
    rotate: f64,
}

/// What [`Comb::world`] draws.
#[derive(Debug, Clone, Copy)]
enum Shape {
    /// The comb's teeth.
    Teeth,
    /// The comb's outline, but one notch cut from the whole right side to a
    /// tip at this column (texels) moved by `ulps`, at the notch floor's
    /// height: a reflex vertex on a grid column.
    Notch { column: u32, ulps: i32 },
}

/// `x` moved by `n` ulps.
fn ulps(x: f64, n: i32) -> f64 {
    (0..n.unsigned_abs()).fold(x, |x, _| if n > 0 { x.next_up() } else { x.next_down() })
}

impl Comb {
    /// Right to left along the top: down a notch's right wall, along its
    /// floor, up its left wall, across the next tooth.
    fn world(&self) -> Vec<DVec3> {
        let (i, w) = (self.incr, self.width * self.incr);
        let floor = ulps(self.floor * i, self.floor_ulps);
        let top = self.top * i;
        let right = (2 * self.teeth + 1) as f64 * w;
        let mut pts = vec![DVec2::ZERO, DVec2::new(right, 0.0)];
        if let Shape::Notch { column, ulps: n } = self.shape {
            let tip = ulps((column as f64 * i).min(right - i), n);
            pts.extend([DVec2::new(tip, floor), DVec2::new(right, top)]);
        }
        let mut x = right;
        let teeth = if let Shape::Teeth = self.shape {
            self.teeth
        } else {
            0
        };
        for _ in 0..teeth {
            let left_wall = ulps(x - 2.0 * w, self.wall_ulps);
            pts.extend([
                DVec2::new(x, top),
                DVec2::new(x - w, top),
                DVec2::new(x - w, floor),
                DVec2::new(left_wall, floor),
            ]);
            x -= 2.0 * w;
        }
        if let Shape::Teeth = self.shape {
            pts.extend([DVec2::new(w, top)]);
        }
        pts.push(DVec2::new(0.0, top));
        pts.dedup();
        let (st, ct) = (math::sin(self.tilt), math::cos(self.tilt));
        let (sp, cp) = (math::sin(self.turn), math::cos(self.turn));
        pts.iter()
            .map(|p| {
                let (x, y, z) = (p.x, p.y * ct, p.y * st);
                self.offset + DVec3::new(x * cp - y * sp, x * sp + y * cp, z)
            })
            .collect()
    }
}

impl Comb {
    /// Partitions the comb and checks the invariants of its pieces, but for
    /// meeting vertex to vertex (`Junctions::Unchecked`).
    fn check(&self) -> Result<(), String> {
        let place = Placement {
            incr: self.incr,
            horz: 0.0,
            vert: 0.0,
        };
        check_partition(&self.world(), self.rotate, place, Junctions::Unchecked)
    }
}

fn comb_strategy() -> impl Strategy<Value = Comb> {
    let half_turn = std::f64::consts::PI;
    (
        (
            2usize..7,
            prop::sample::select(vec![1.0, 1.5, 2.0, 3.0, 4.5]),
            prop_oneof![
                Just(Shape::Teeth),
                (1u32..12, -3i32..=3).prop_map(|(column, ulps)| Shape::Notch { column, ulps })
            ],
        ),
        (1u32..7, 1u32..7, any::<bool>(), any::<bool>()),
        (-2i32..=2, -2i32..=2),
        prop::sample::select(vec![0.1, 0.25, 0.3, 1.0 / 3.0, 0.5, 1.0]),
        (
            prop_oneof![
                prop::sample::select(vec![0.0, 0.3, 0.7, half_turn / 2.0]),
                0.0..3.0
            ],
            prop_oneof![
                prop::sample::select(vec![0.0, 0.2, half_turn / 4.0]),
                0.0..6.0
            ],
        ),
        prop::sample::select(vec![
            DVec3::ZERO,
            DVec3::new(1.1, 2.3, -7.7),
            DVec3::new(100.3, -50.1, 3.3),
            DVec3::new(1e4 + 0.3, -2e4, 7.1),
            DVec3::new(3e6, 1e6 + 0.1, -2e6),
        ]),
        prop_oneof![
            prop::sample::select(vec![0.0, 15.0, 30.0, 45.0, 90.0]),
            0.0..360.0
        ],
    )
        .prop_map(
            |(
                (teeth, width, shape),
                (floor, height, half, raised),
                (floor_ulps, wall_ulps),
                incr,
                (tilt, turn),
                offset,
                rotate,
            )| {
                let floor = floor as f64 + if half { 0.5 } else { 0.0 };
                Comb {
                    shape,
                    teeth,
                    width,
                    floor,
                    top: floor + height as f64 + if raised { 0.3 } else { 0.0 },
                    floor_ulps,
                    wall_ulps,
                    incr,
                    tilt,
                    turn,
                    offset,
                    rotate,
                }
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases_or(96),
        ..ProptestConfig::default()
    })]

    /// Every piece of a comb or notch on the grid lines is simple as
    /// readers judge it, and the pieces keep the invariants of the stars
    /// above, but for meeting vertex to vertex (`Junctions::Unchecked`).
    #[test]
    fn combs_on_grid_lines_give_simple_pieces(c in comb_strategy()) {
        // Rounding in the tilt can make the comb itself touch itself:
        // outside the contract, and refused by every reader.
        prop_assume!(crate::geom::simple::check(&c.world()).is_ok());
        let r = c.check();
        prop_assert!(r.is_ok(), "{:?}: {}", c, r.unwrap_err());
    }
}

/// A star-shaped polygon with one vertex doubled by a neighbour a tiny
/// step away, or a square with a notch whose tip comes that close to the
/// opposite side, laid in a plane and then moved off it, each vertex by up
/// to about half the default `--planarity-tol` of the size: simple as
/// readers judge it (its flat view), not always once projected onto its
/// plane.
#[derive(Debug, Clone)]
struct OffPlane {
    spokes: Vec<(f64, f64)>,
    /// The notched square instead of the star, its tip at this x (of the side).
    notch: Option<f64>,
    /// The vertex doubled, the step's log10 (of the size) and direction.
    pinch: (usize, f64, f64),
    /// Each vertex's distance off the plane, in units of the tolerance's
    /// half; or only the doubled pair's (the notch's tip and the side it
    /// nears), in opposite directions.
    lift: Vec<f64>,
    pair_only: bool,
    normal: DVec3,
    offset: DVec3,
    size: f64,
    /// log10 of incr / size.
    incr_exp: f64,
    rotate: f64,
}

impl OffPlane {
    fn world(&self) -> Option<Vec<DVec3>> {
        let (at, step, angle) = self.pinch;
        let gap = self.size * math::powf(10.0, step);
        let (p, at, partners) = if let Some(x) = self.notch {
            let (s, w) = (self.size, 0.1 * self.size);
            let tip = DVec2::new(x * s, gap);
            let p = vec![
                DVec2::ZERO,
                DVec2::new(s, 0.0),
                DVec2::new(s, s),
                DVec2::new(tip.x + w, s),
                tip,
                DVec2::new(tip.x - w, s),
                DVec2::new(0.0, s),
            ];
            (p, 4, [0, 1])
        } else {
            let mut p = outline_2d(&self.spokes, false, self.size);
            if p.len() < 3 || signed_area(&p) <= 1e-3 * self.size * self.size {
                return None;
            }
            let at = at % p.len();
            p.insert(
                at + 1,
                p[at] + DVec2::new(math::cos(angle), math::sin(angle)) * gap,
            );
            (p, at, [at + 1, at + 1])
        };
        let (u, w) = self.normal.any_orthonormal_pair();
        let (lo, hi) = p
            .iter()
            .fold((p[0], p[0]), |(lo, hi), &q| (lo.min(q), hi.max(q)));
        let half_tol = 0.5e-6 * (hi - lo).length();
        Some(
            p.iter()
                .enumerate()
                .map(|(i, q)| {
                    let lift = match (self.pair_only, i) {
                        (false, _) => self.lift[i % self.lift.len()],
                        (true, i) if i == at => 0.9,
                        // The star's doubled vertex; the side the notch's tip nears.
                        (true, i) if partners.contains(&i) => -0.9,
                        (true, _) => 0.0,
                    };
                    self.offset + u * q.x + w * q.y + self.normal * (lift * half_tol)
                })
                .collect(),
        )
    }
}

fn off_plane_strategy() -> impl Strategy<Value = OffPlane> {
    (
        prop::collection::vec((0.0f64..std::f64::consts::TAU, 0.2f64..1.0), 3..10),
        prop::option::of(0.2f64..0.8),
        (0usize..12, -9.0f64..-6.0, 0.0f64..std::f64::consts::TAU),
        prop::collection::vec(-0.9f64..0.9, 1..12),
        any::<bool>(),
        normal_strategy(),
        prop::sample::select(vec![
            DVec3::ZERO,
            DVec3::new(1.1, 2.3, -7.7),
            DVec3::new(1e4 + 0.3, -2e4, 7.1),
            DVec3::new(3e6, 1e6 + 0.1, -2e6),
        ]),
        prop_oneof![Just(1.0), 1e-2f64..1e3],
        -2.0f64..0.0,
        prop_oneof![Just(0.0), 0.0f64..360.0],
    )
        .prop_map(
            |(spokes, notch, pinch, lift, pair_only, normal, offset, size, incr_exp, rotate)| {
                OffPlane {
                    spokes,
                    notch,
                    pinch,
                    lift,
                    pair_only,
                    normal,
                    offset,
                    size,
                    incr_exp,
                    rotate,
                }
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig {
        // 1,000 cases by default (half a second): about one in fifty is
        // projected along the axis, the path under test.
        cases: cases_or(1000),
        // Inputs with no star, or that touch themselves, are skipped: many
        // of them.
        max_global_rejects: 1_000_000,
        ..ProptestConfig::default()
    })]

    /// An input off its plane, within the tolerance, that readers take
    /// (simple on its flat view) gives pieces readers take too, with the
    /// star test's invariants.
    #[test]
    fn inputs_off_their_plane_give_simple_pieces(c in off_plane_strategy()) {
        // No star (an angular gap of half a turn): nothing to test.
        let v = c.world();
        prop_assume!(v.is_some());
        let v = v.unwrap();
        // The step can make the input itself touch itself: refused by
        // every reader.
        prop_assume!(crate::geom::simple::check(&v).is_ok());
        // Lifts that tilt the best-fit plane can put a vertex past the
        // tolerance: refused as not planar, as polyfill3 does.
        prop_assume!(map_to_plane(&v, c.rotate, 1e-6).is_ok());
        let place = Placement {
            incr: c.size * math::powf(10f64, c.incr_exp),
            horz: 0.0,
            vert: 0.0,
        };
        let r = check_partition(&v, c.rotate, place, Junctions::Unchecked);
        prop_assert!(r.is_ok(), "{:?}: {}", c, r.unwrap_err());
    }
}

/// Shrunk from `combs_on_grid_lines_give_simple_pieces` before
/// `tidy::simple_in_world`: a level comb turned 90° in its plane, whose
/// notch floors lie on grid columns. A piece's world ring crossed itself.
#[test]
fn regression_comb_turned_90_degrees_whose_piece_crossed_itself() {
    let c = Comb {
        shape: Shape::Teeth,
        teeth: 2,
        width: 1.5,
        floor: 1.0,
        top: 2.3,
        floor_ulps: 0,
        wall_ulps: 0,
        incr: 0.1,
        tilt: 0.0,
        turn: 0.0,
        offset: DVec3::new(1.1, 2.3, -7.7),
        rotate: 90.0,
    };
    c.check().unwrap();
}

/// Shrunk from `combs_on_grid_lines_give_simple_pieces` without the split
/// of `tidy::simple_in_world`: a notch whose tip lies on a grid column, in
/// a plane turned about z. The cell beside the tip held two parts touching
/// there, written as one ring that touched itself.
#[test]
fn regression_notch_tip_on_a_column_gave_parts_touching_there() {
    let c = Comb {
        shape: Shape::Notch { column: 7, ulps: 0 },
        teeth: 6,
        width: 2.0,
        floor: 4.5,
        top: 9.5,
        floor_ulps: 0,
        wall_ulps: 0,
        incr: 0.3,
        tilt: 0.0,
        turn: 1.263166816823379,
        offset: DVec3::new(100.3, -50.1, 3.3),
        rotate: 0.0,
    };
    c.check().unwrap();
}

/// The smallest incr of the range, once (too slow for every case).
#[test]
fn invariants_at_a_thousandth_of_the_size() {
    let c = Case {
        spokes: vec![(0.1, 1.0), (1.9, 0.5), (2.5, 0.9), (4.0, 0.3), (5.5, 1.0)],
        convex: false,
        dup: 2,
        mid: 3,
        normal: DVec3::new(0.0, 0.0, 1.0),
        offset: DVec3::new(-9.9e6, 3e6, 7e6),
        size: 1.0,
        incr_exp: -3.0,
        horz: 0.5,
        vert: -2.0,
        rotate: 30.0,
    };
    check(&c).unwrap();
}

/// Shrunk from a proptest failure: a concave polygon whose piece in cell
/// (54, 73) falls apart. Clipping alone joined the parts by a bridge whose end
/// lay outside the polygon; the piece is now rebuilt into separate parts.
#[test]
fn regression_concave_piece_that_falls_apart() {
    let c = Case {
        spokes: vec![
            (0.9433969120055282, 0.6092170491909435),
            (0.0, 0.49829560485681196),
            (2.9466145724105077, 0.9008134614271753),
            (4.760646910690235, 0.7006252305230204),
            (3.6878889199983664, 0.2),
        ],
        convex: false,
        dup: 0,
        mid: 0,
        normal: DVec3::X,
        offset: DVec3::ZERO,
        size: 1.0,
        incr_exp: -1.9678809553572438,
        horz: 0.0,
        vert: 0.0,
        rotate: -338.6305326649017,
    };
    check(&c).unwrap();
}

/// Shrunk from a proptest failure, which was the generator's: spokes with an
/// angular gap wider than π make a self-intersecting polygon (outside the
/// contract, see `partition`'s module doc). The generator now refuses them.
#[test]
fn regression_generator_refuses_self_intersecting_stars() {
    let c = Case {
        spokes: vec![
            (4.107198959182907, 0.2),
            (5.740235107287422, 0.2),
            (5.875874954261355, 0.5898793696769893),
            (0.0, 0.8642488000348795),
        ],
        convex: false,
        dup: 0,
        mid: 0,
        normal: DVec3::X,
        offset: DVec3::ZERO,
        size: 1.0,
        incr_exp: 0.0,
        horz: 0.0,
        vert: -0.9939065859185083,
        rotate: 0.0,
    };
    assert!(world_polygon(&c).is_none());
}

/// Shrunk from a proptest failure once the shared-side check was exact: a
/// strip's bridge left a spike along cell (1, 3)'s border, one vertex of
/// which lay outside the polygon and on the neighbour's side only.
#[test]
fn regression_spike_from_a_strip_bridge() {
    let c = Case {
        spokes: vec![
            (3.850167905061518, 0.2),
            (3.869137948037556, 0.789982775867804),
            (6.173377746139083, 0.2),
            (1.1199330335824775, 0.5361689894098468),
            (0.0, 0.5981493149328583),
        ],
        convex: false,
        dup: 0,
        mid: 0,
        normal: DVec3::X,
        offset: DVec3::ZERO,
        size: 1.0,
        incr_exp: -0.7855177938428909,
        horz: 0.0,
        vert: 0.0,
        rotate: -281.5841445986469,
    };
    check(&c).unwrap();
}
