//! Differential property test of the partition: every polygon's cells are
//! compared with an independent per-cell clip written here (each cell of the
//! bounding grid clipped against the whole polygon by a plain
//! Sutherland–Hodgman, areas by the plain shoelace, all in plane
//! coordinates). Nothing of `clip` or `polygon` is used by the reference.
//!
//! Polygons: convex, squares with V-shaped notches (the shape that lost a
//! cell under a reflex vertex at rotate 90), integer and random coordinates,
//! star-shaped random ones; at rotate 0, 90, 180, 270, 45, 30 or anything,
//! with random incr and shifts. Checked: the same cells have positive area,
//! each cell's area agrees to 1e-9 (relative, or of incr² for tiny ones),
//! every written polygon has more than [`MIN_PIECE_AREA_REL`] area with the
//! input's winding (in the plane and as written in the world), and the areas
//! sum to the polygon's.

use super::*;
use crate::geom::plane::map_to_plane;
use proptest::prelude::*;
use std::collections::BTreeMap;

/// Relative tolerance of the comparisons.
const REL: f64 = 1e-9;

use super::props::Cells;
use crate::math;

/// The reference's shoelace (plain, about the first vertex).
fn ref_area(p: &[DVec2]) -> f64 {
    if p.len() < 3 {
        return 0.0;
    }
    let mut s = 0.0;
    for i in 1..p.len() - 1 {
        let (a, b) = (p[i] - p[0], p[i + 1] - p[0]);
        s += a.x * b.y - a.y * b.x;
    }
    s / 2.0
}

/// The reference clip: `poly` ∩ the box, one Sutherland–Hodgman pass per side,
/// crossings interpolated from the inside endpoint.
fn ref_clip(poly: &[DVec2], (x0, y0, x1, y1): (f64, f64, f64, f64)) -> Vec<DVec2> {
    let mut cur = poly.to_vec();
    let sides: [(DVec2, f64); 4] = [
        (DVec2::new(1.0, 0.0), -x0),
        (DVec2::new(-1.0, 0.0), x1),
        (DVec2::new(0.0, 1.0), -y0),
        (DVec2::new(0.0, -1.0), y1),
    ];
    for (n, c) in sides {
        let d = |p: DVec2| n.dot(p) + c;
        let mut out = Vec::with_capacity(cur.len() + 2);
        for i in 0..cur.len() {
            let (a, b) = (cur[i], cur[(i + 1) % cur.len()]);
            let (da, db) = (d(a), d(b));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let (p, q, dp, dq) = if da >= 0.0 {
                    (a, b, da, db)
                } else {
                    (b, a, db, da)
                };
                out.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        cur = out;
        if cur.is_empty() {
            break;
        }
    }
    cur
}

#[derive(Debug, Clone)]
struct DiffCase {
    /// The polygon in the z = 0 plane, counter-clockwise seen from +z.
    verts: Vec<(f64, f64)>,
    rotate: f64,
    incr: f64,
    horz: f64,
    vert: f64,
}

/// Checks the partition of `c` against the reference.
fn check(c: &DiffCase) -> Result<(), String> {
    let v: Vec<DVec3> = c
        .verts
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 0.0))
        .collect();
    let poly = map_to_plane(&v, c.rotate, 1e-6).map_err(|e| e.to_string())?;
    let place = Placement {
        incr: c.incr,
        horz: c.horz,
        vert: c.vert,
    };
    let grid = Grid::new(&poly.points, place).map_err(|e| e.to_string())?;
    let mut out = Cells::default();
    Partitioner::new().run(&poly, &grid, &mut out);
    let incr = c.incr;
    let extent = [grid.xmin, grid.xmax, grid.ymin, grid.ymax]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let min_area = (MIN_PIECE_AREA_REL * incr.min(extent) * extent)
        .min(MIN_PIECE_AREA_OF_POLYGON * ref_area(&poly.points));
    let mut ours: BTreeMap<(i64, i64), f64> = BTreeMap::new();
    for (k, j, w, p) in &out.cells {
        let a = ref_area(p);
        if a <= min_area {
            return Err(format!(
                "cell ({k},{j}) polygon has area {a:e} in the plane"
            ));
        }
        // Winding of what is written: the world polygon's area along +z (the
        // input is counter-clockwise seen from +z).
        let mut wz = 0.0;
        for i in 1..w.len() - 1 {
            let (a, b) = (w[i] - w[0], w[i + 1] - w[0]);
            wz += a.x * b.y - a.y * b.x;
        }
        if wz / 2.0 <= min_area {
            return Err(format!(
                "cell ({k},{j}) world polygon has area {:e} along +z",
                wz / 2.0
            ));
        }
        *ours.entry((*k, *j)).or_default() += a;
    }
    let tiny = REL * incr * incr;
    for j in grid.j0..=grid.j1 {
        for k in grid.k0..=grid.k1 {
            let cell = (grid.gx(k), grid.gy(j), grid.gx(k + 1), grid.gy(j + 1));
            let r = ref_area(&ref_clip(&poly.points, cell));
            let mine = ours.get(&(k, j)).copied();
            match mine {
                None if r > tiny => {
                    return Err(format!("cell ({k},{j}) missing: reference area {r}"));
                }
                None => {}
                Some(m) if (m - r).abs() > REL * r.abs().max(incr * incr) => {
                    return Err(format!("cell ({k},{j}) area {m} != reference {r}"));
                }
                Some(_) => {}
            }
        }
    }
    let want = ref_area(&poly.points);
    let total: f64 = ours.values().sum();
    if (total - want).abs() > REL * want {
        return Err(format!("areas sum to {total}, the polygon's is {want}"));
    }
    for &(k, j) in ours.keys() {
        if k < grid.k0 || k > grid.k1 || j < grid.j0 || j > grid.j1 {
            return Err(format!("cell ({k},{j}) outside the grid"));
        }
    }
    Ok(())
}

/// A square `[0,s]²` (from `o`) with a V notch cut into side `side`: the
/// notch's mouth runs from `m0` to `m1` (fractions along the side) and its
/// apex is `depth` (a fraction of s) inside, at fraction `ap` along the side.
#[allow(clippy::too_many_arguments)]
fn notched_square(
    o: (f64, f64),
    s: f64,
    side: usize,
    m0: f64,
    m1: f64,
    ap: f64,
    depth: f64,
    snap: bool,
) -> Vec<(f64, f64)> {
    let r = |x: f64| if snap { x.round() } else { x };
    // The corners counter-clockwise, and for each side its start, direction
    // and inward normal.
    let corners = [(0.0, 0.0), (s, 0.0), (s, s), (0.0, s)];
    let dirs = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
    let mut out = Vec::new();
    for i in 0..4 {
        out.push((o.0 + corners[i].0, o.1 + corners[i].1));
        if i == side {
            let (cx, cy) = corners[i];
            let (dx, dy) = dirs[i];
            let (nx, ny) = (-dy, dx);
            let (a, b) = (m0.min(m1), m0.max(m1));
            let at = |t: f64, d: f64| {
                (
                    o.0 + r(cx + dx * t * s + nx * d * s),
                    o.1 + r(cy + dy * t * s + ny * d * s),
                )
            };
            let (p0, p1) = (at(a, 0.0), at(b, 0.0));
            let apex = at(a + (b - a) * ap, depth);
            out.extend([p0, apex, p1]);
        }
    }
    out.dedup();
    out
}

fn shape_strategy() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop_oneof![
        // Squares with a V notch, integer coordinates.
        (
            (-20i32..20, -20i32..20),
            4i32..40,
            0usize..4,
            0.05f64..0.95,
            0.05f64..0.95,
            0.1f64..0.9,
            0.1f64..0.9,
        )
            .prop_map(|(o, s, side, m0, m1, ap, d)| notched_square(
                (o.0 as f64, o.1 as f64),
                s as f64,
                side,
                m0,
                m1,
                ap,
                d,
                true
            )),
        // Squares with a V notch, random coordinates.
        (
            (-20.0f64..20.0, -20.0f64..20.0),
            1.0f64..40.0,
            0usize..4,
            0.05f64..0.95,
            0.05f64..0.95,
            0.05f64..0.95,
            0.05f64..0.95,
        )
            .prop_map(|(o, s, side, m0, m1, ap, d)| notched_square(
                o, s, side, m0, m1, ap, d, false
            )),
        // Convex: points on a circle, integer (rounded) or not.
        (
            prop::collection::vec(0.0f64..std::f64::consts::TAU, 3..12),
            2.0f64..25.0,
            any::<bool>(),
        )
            .prop_map(|(mut t, r, snap)| {
                t.sort_by(f64::total_cmp);
                let mut v: Vec<(f64, f64)> = t
                    .iter()
                    .map(|a| {
                        let (x, y) = (r * math::cos(*a), r * math::sin(*a));
                        if snap {
                            (x.round(), y.round())
                        } else {
                            (x, y)
                        }
                    })
                    .collect();
                v.dedup();
                v
            }),
        // Integer triangles on a small grid (the shape of the zero-area pieces).
        prop::collection::vec((0i32..13, 0i32..13), 3)
            .prop_map(|v| v.iter().map(|&(x, y)| (x as f64, y as f64)).collect()),
        // Star-shaped, random radii: concave with many reflex vertices.
        prop::collection::vec((0.0f64..std::f64::consts::TAU, 0.2f64..1.0), 3..14).prop_map(
            |mut a| {
                a.sort_by(|x, y| x.0.total_cmp(&y.0));
                a.iter()
                    .map(|&(t, r)| (20.0 * r * math::cos(t), 20.0 * r * math::sin(t)))
                    .collect()
            }
        ),
    ]
}

/// Whether the outline is a simple polygon, counter-clockwise, with area:
/// what the partition's contract asks (self-intersecting input is outside it).
fn simple_ccw(v: &[(f64, f64)]) -> bool {
    let p: Vec<DVec2> = v.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
    let n = p.len();
    if n < 3 || ref_area(&p) <= 1e-3 {
        return false;
    }
    let orient = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    for i in 0..n {
        for j in i + 1..n {
            // Adjacent edges share a vertex; only non-adjacent pairs may not meet.
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b, c, d) = (p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]);
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            if o1 * o2 <= 0.0 && o3 * o4 <= 0.0 {
                return false;
            }
        }
    }
    true
}

fn case_strategy() -> impl Strategy<Value = DiffCase> {
    (
        shape_strategy()
            .prop_map(|mut v| {
                let p: Vec<DVec2> = v.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
                if ref_area(&p) < 0.0 {
                    v.reverse();
                }
                v
            })
            .prop_filter("simple, with area", |v| simple_ccw(v)),
        prop_oneof![
            Just(0.0),
            Just(90.0),
            Just(180.0),
            Just(270.0),
            Just(45.0),
            Just(30.0),
            -360.0f64..360.0
        ],
        prop_oneof![Just(1.0), Just(0.5), Just(2.0), 0.3f64..5.0, 10.0f64..1e6],
        prop_oneof![Just(0.0), (-3i32..3).prop_map(f64::from), -3.0f64..3.0],
        prop_oneof![Just(0.0), (-3i32..3).prop_map(f64::from), -3.0f64..3.0],
    )
        .prop_map(|(verts, rotate, incr, horz, vert)| DiffCase {
            verts,
            rotate,
            incr,
            horz,
            vert,
        })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: super::props::cases_or(96),
        ..ProptestConfig::default()
    })]

    #[test]
    fn partition_matches_an_independent_per_cell_clip(c in case_strategy()) {
        let r = check(&c);
        prop_assert!(r.is_ok(), "{:?}: {}", c, r.unwrap_err());
    }
}

fn int_case(v: &[(i32, i32)], rotate: f64) -> DiffCase {
    DiffCase {
        verts: v.iter().map(|&(x, y)| (x as f64, y as f64)).collect(),
        rotate,
        incr: 1.0,
        horz: 0.0,
        vert: 0.0,
    }
}

/// Bug 1: at rotate 90 the reflex vertex (15, 31) lands 2e-16 beside a grid
/// line, and the cell [15,16]x[30,31] under it was dropped (479 of 480): the
/// border walk of `clip::split_on_border` measured positions by a rounded
/// perimeter parameter (see `clip::BorderPos`).
#[test]
fn regression_cell_under_a_reflex_vertex_at_rotate_90() {
    let c = int_case(
        &[(8, 15), (31, 15), (31, 38), (22, 38), (15, 31), (8, 38)],
        90.0,
    );
    check(&c).unwrap();
    let poly = map_to_plane(
        &c.verts
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect::<Vec<_>>(),
        90.0,
        1e-6,
    )
    .unwrap();
    let grid = Grid::new(
        &poly.points,
        Placement {
            incr: 1.0,
            horz: 0.0,
            vert: 0.0,
        },
    )
    .unwrap();
    let mut out = Cells::default();
    Partitioner::new().run(&poly, &grid, &mut out);
    let total: f64 = out.cells.iter().map(|x| ref_area(&x.3)).sum();
    assert!((total - 480.0).abs() < 1e-9, "{total}");
    // The cell [15,16]x[30,31] is there, whole.
    let lost = out.cells.iter().find(|(_, _, w, _)| {
        w.iter()
            .all(|p| p.x > 14.99 && p.x < 16.01 && p.y > 29.99 && p.y < 31.01)
    });
    assert!(lost.is_some_and(|x| (ref_area(&x.3) - 1.0).abs() < 1e-12));
}

/// Shrunk by the differential test after the first fix: the same loss at rotate 270.
#[test]
fn regression_notch_at_rotate_270() {
    let c = int_case(&[(0, 0), (7, 0), (7, 7), (5, 2), (3, 7), (0, 7)], 270.0);
    check(&c).unwrap();
}

/// Bug 1 at rotate 270, and with the notch at the other sides.
#[test]
fn regression_notches_at_rotate_90_and_270() {
    let shape = [(8, 15), (31, 15), (31, 38), (22, 38), (15, 31), (8, 38)];
    for rotate in [90.0, 180.0, 270.0] {
        check(&int_case(&shape, rotate)).unwrap();
    }
}

/// A cell far larger than the polygon: its one piece is the whole polygon,
/// which the noise floor must not take for noise (its scale is
/// `min(incr, E) * E`, not `incr * E`; the stress test at incr 1e6 caught it).
#[test]
fn a_cell_a_million_times_the_polygon_keeps_it() {
    let mut c = int_case(&[(0, 0), (1, 0), (1, 1), (0, 1)], 0.0);
    c.incr = 1e6;
    check(&c).unwrap();
}

/// Bug 2: the triangle (0,0),(2,0),(0,2) touches cell (1,1) at a point only;
/// that cell was written as a polygon of three identical vertices (1,1,0).
/// Now exactly the three cells with area are written.
#[test]
fn regression_no_piece_where_a_triangle_touches_a_cell() {
    for (s, cells) in [(2, 3), (4, 10)] {
        let c = int_case(&[(0, 0), (s, 0), (0, s)], 0.0);
        check(&c).unwrap();
        let poly = map_to_plane(
            &[
                DVec3::ZERO,
                DVec3::new(s as f64, 0.0, 0.0),
                DVec3::new(0.0, s as f64, 0.0),
            ],
            0.0,
            1e-6,
        )
        .unwrap();
        let place = Placement {
            incr: 1.0,
            horz: 0.0,
            vert: 0.0,
        };
        let mut out = Cells::default();
        Partitioner::new().run(&poly, &Grid::new(&poly.points, place).unwrap(), &mut out);
        assert_eq!(out.cells.len(), cells, "triangle of side {s}");
    }
}

/// Bug 2 over every integer triangle of a small grid (those of the issue:
/// zero-area pieces, pieces of area 1e-13, reversed ones), at the rotations
/// where the rounding of the frame differs.
#[test]
fn regression_integer_triangles_write_only_pieces_with_area() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 13) as i32
    };
    let mut checked = 0;
    while checked < 300 {
        let t = [(next(), next()), (next(), next()), (next(), next())];
        let mut c = int_case(&t, 0.0);
        if ref_area(
            &c.verts
                .iter()
                .map(|&(x, y)| DVec2::new(x, y))
                .collect::<Vec<_>>(),
        ) <= 0.0
        {
            c.verts.reverse();
        }
        if !simple_ccw(&c.verts) {
            continue;
        }
        for rotate in [0.0, 90.0, 30.0] {
            c.rotate = rotate;
            check(&c).unwrap_or_else(|e| panic!("{c:?}: {e}"));
        }
        checked += 1;
    }
}
