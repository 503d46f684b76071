//! Planes and the partition into texel cells (`polyfill3`'s core) at extreme
//! scales, far from the origin, and on degenerate input.

use glam::{DVec2, DVec3};
use patkit::geom::partition::{MAX_SHIFT_TEXELS, MIN_INCR_REL};
use patkit::geom::{map_to_plane, CellSink, Grid, GridError, Partitioner, Placement, PlaneError};
use patkit::math;
use proptest::prelude::*;

/// Relative error allowed between the summed area of the cells and the
/// polygon's own area: every cell vertex is a crossing computed once from
/// an input edge, so the sum is exact up to a few ulps per cell; 1e-9 leaves
/// room for ~1e6 cells of rounding.
const AREA_REL: f64 = 1e-9;

/// Collects the cells' texel indices and summed plane area.
#[derive(Default)]
struct Sum {
    area: f64,
    cells: Vec<(i64, i64)>,
    finite: bool,
}

impl CellSink for Sum {
    fn wants(&mut self, _: i64, _: i64) -> bool {
        true
    }
    fn cell(&mut self, k: i64, j: i64, world: &[DVec3], plane: &[DVec2], _full: bool) {
        let n = plane.len();
        let a: f64 = (0..n)
            .map(|i| plane[i].perp_dot(plane[(i + 1) % n]))
            .sum::<f64>()
            / 2.0;
        self.area += a;
        self.cells.push((k, j));
        self.finite &= world.iter().all(|p| p.is_finite()) && a.is_finite() && a > 0.0;
    }
}

fn partition(v: &[DVec3], incr: f64, tol: f64) -> Result<(f64, Sum), String> {
    let poly = map_to_plane(v, 0.0, tol).map_err(|e| e.to_string())?;
    let grid = Grid::new(
        &poly.points,
        Placement {
            incr,
            horz: 0.25,
            vert: -0.5,
        },
    )
    .map_err(|e| e.to_string())?;
    let mut s = Sum {
        finite: true,
        ..Sum::default()
    };
    Partitioner::new().run(&poly, &grid, &mut s);
    Ok((poly.area, s))
}

/// A concave pentagon (an arrow head) in the unit square, scaled and moved.
fn arrow(scale: f64, at: DVec3) -> Vec<DVec3> {
    [
        [0.0, 0.0],
        [1.0, 0.1],
        [0.45, 0.4],
        [0.9, 0.95],
        [0.05, 0.8],
    ]
    .iter()
    .map(|p| at + DVec3::new(p[0], p[1], 0.0) * scale)
    .collect()
}

proptest! {
    #![proptest_config(crate::config())]

    #[test]
    fn partition_area_matches_polygon_within_1e_9_for_scales_1e_6_to_1e9(
        e in -6.0f64..9.0, cells in 1.0f64..40.0, z in -1.0f64..1.0,
    ) {
        let s = math::powf(10f64, e);
        let v = arrow(s, DVec3::new(0.0, 0.0, z * s));
        let (area, sum) = partition(&v, s / cells, 1e-6).unwrap();
        prop_assert!(sum.finite);
        prop_assert!((sum.area - area).abs() <= AREA_REL * area, "{} vs {}", sum.area, area);
    }

    #[test]
    fn translated_1e7_partition_keeps_the_same_cells_and_area_within_1e_6(
        e in -2.0f64..3.0, cells in 1.0f64..20.0,
        dir in prop::array::uniform3(-1.0f64..1.0),
    ) {
        // 1e7 away the coordinates keep 2^-52 * 1e7 ~ 2e-9 absolute precision,
        // so areas of a polygon of size >= 0.01 agree to 1e-6 relative.
        const TRANSLATED_AREA_REL: f64 = 1e-6;
        let s = math::powf(10f64, e);
        let d = DVec3::from(dir);
        prop_assume!(d.length() > 0.1);
        let far = d.normalize() * 1e7;
        let (a0, s0) = partition(&arrow(s, DVec3::ZERO), s / cells, 1e-6).unwrap();
        let (a1, s1) = partition(&arrow(s, far), s / cells, 1e-6).unwrap();
        prop_assert!(s1.finite);
        prop_assert!((a1 - a0).abs() <= TRANSLATED_AREA_REL * a0);
        prop_assert!((s1.area - a1).abs() <= TRANSLATED_AREA_REL * a1);
        let mut c0 = s0.cells.clone();
        let mut c1 = s1.cells.clone();
        c0.dedup();
        c1.dedup();
        // Cells whose piece is within rounding of empty may come and go; the
        // cell set may differ only by such pieces.
        let common = c0.iter().filter(|c| c1.contains(c)).count();
        prop_assert!(common + 2 >= c0.len().max(c1.len()), "{c0:?} vs {c1:?}");
    }

    #[test]
    fn slivers_are_partitioned_exactly_or_refused_as_zero_area(
        h in -16.0f64..0.0, incr_e in -3.0f64..0.5, skew in -2.0f64..2.0,
    ) {
        let v = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(skew, math::powf(10f64, h), 0.0),
        ];
        match partition(&v, math::powf(10f64, incr_e), 1e-6) {
            Ok((area, sum)) => {
                prop_assert!(sum.finite);
                prop_assert!((sum.area - area).abs() <= AREA_REL * area.max(1e-300));
            }
            Err(e) => prop_assert!(e.contains("no area"), "{e}"),
        }
    }

    #[test]
    fn normals_exactly_or_nearly_along_each_axis_give_unit_normals_and_exact_area(
        axis in 0usize..3, sign in prop::bool::ANY, tilt_e in -15.0f64..-1.0,
        exact in prop::bool::ANY,
    ) {
        let tilt = if exact { 0.0 } else { math::powf(10f64, tilt_e) };
        // A square in the plane through the origin perpendicular to `axis`,
        // tilted by `tilt` radians about one in-plane direction.
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut v = Vec::new();
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            let mut p = [0.0; 3];
            p[a] = x;
            p[b] = y;
            p[axis] = tilt * x;
            v.push(DVec3::from(p));
        }
        if sign {
            v.reverse();
        }
        let poly = map_to_plane(&v, 0.0, 1e-9).unwrap();
        prop_assert!((poly.frame.normal.length() - 1.0).abs() < 1e-12);
        prop_assert!((poly.frame.normal[axis].abs() - 1.0).abs() <= tilt * tilt + 1e-15);
        let (area, sum) = partition(&v, 0.1, 1e-9).unwrap();
        prop_assert!((area - (1.0 + tilt * tilt).sqrt()).abs() < 1e-12);
        prop_assert!((sum.area - area).abs() <= AREA_REL * area);
    }

    #[test]
    fn near_collinear_first_edge_lies_on_the_plane_x_axis(
        angle_e in -14.0f64..-1.0, len_e in -6.0f64..6.0,
    ) {
        // The thesis places the first edge on the x axis; with the second edge
        // almost continuing the first, the frame must still follow edge 0->1.
        let s = math::powf(10f64, len_e);
        let a = math::powf(10f64, angle_e);
        let v = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(s, 0.0, 0.0),
            DVec3::new(2.0 * s, s * a, 0.0),
            DVec3::new(s, s, 0.0),
        ];
        let poly = map_to_plane(&v, 0.0, 1e-6).unwrap();
        let e = poly.points[1] - poly.points[0];
        prop_assert!(e.y.abs() <= 1e-12 * e.length(), "{e}");
        prop_assert!(e.x > 0.0);
    }

    #[test]
    fn planarity_noise_within_the_tolerance_is_accepted_and_twice_it_refused(
        tol_e in -9.0f64..-2.0, scale_e in -3.0f64..6.0, vertex in 0usize..4,
    ) {
        let tol = math::powf(10f64, tol_e);
        let s = math::powf(10f64, scale_e);
        let square = |dz: f64| {
            let mut v: Vec<DVec3> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
                .iter()
                .map(|p| DVec3::new(p[0], p[1], 0.0) * s)
                .collect();
            v[vertex].z = dz;
            v
        };
        let size = s * 2f64.sqrt();
        // Half the tolerance: the best-fit plane spreads one vertex's offset
        // over all four, so the deviation is below the offset itself.
        prop_assert!(map_to_plane(&square(0.5 * tol * size), 0.0, tol).is_ok());
        match map_to_plane(&square(8.0 * tol * size), 0.0, tol) {
            Err(PlaneError::NonPlanar { deviation, .. }) => prop_assert!(deviation.is_finite()),
            other => prop_assert!(false, "{other:?}"),
        }
    }
}

#[test]
fn repeated_vertices_are_partitioned_like_the_polygon_without_them() {
    let v = arrow(1.0, DVec3::ZERO);
    let mut r = Vec::new();
    for p in &v {
        r.push(*p);
        r.push(*p);
    }
    let (a0, s0) = partition(&v, 0.1, 1e-6).unwrap();
    let (a1, s1) = partition(&r, 0.1, 1e-6).unwrap();
    assert_eq!(a0, a1);
    assert!((s0.area - s1.area).abs() <= AREA_REL * a0);
    assert_eq!(s0.cells, s1.cells);
}

#[test]
fn all_vertices_repeated_or_collinear_is_a_zero_area_error_not_nan() {
    let p = DVec3::new(1e7, -3.0, 2.0);
    for v in [
        vec![p, p, p, p],
        vec![p, p + DVec3::X, p + 2.0 * DVec3::X],
        vec![p, p + DVec3::X, p],
    ] {
        match map_to_plane(&v, 0.0, 1e-6) {
            Err(PlaneError::ZeroArea { .. }) => {}
            other => panic!("{other:?}"),
        }
    }
}

/// Regression (found by this suite): `incr` 1e-100 on a unit polygon made
/// `Grid::col_of` walk ~2^52 grid lines that rounded to the same value (a
/// hang), and 1e-20 overflowed the i64 column index (a panic).
#[test]
fn incr_below_min_incr_rel_of_the_coordinates_is_a_grid_error_not_a_hang() {
    let poly = map_to_plane(&arrow(1.0, DVec3::ZERO), 0.0, 1e-6).unwrap();
    for incr in [1e-20, 1e-100, 1e-300, 5e-324, f64::NAN] {
        let place = Placement {
            incr,
            horz: 0.0,
            vert: 0.0,
        };
        assert!(
            matches!(
                Grid::new(&poly.points, place),
                Err(GridError::TooFine { .. })
            ),
            "{incr}"
        );
    }
    // Just above the floor the grid is built and its lines are distinct.
    let extent = poly
        .points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let place = Placement {
        incr: 2.0 * MIN_INCR_REL * extent,
        horz: 0.0,
        vert: 0.0,
    };
    let g = Grid::new(&poly.points, place).unwrap();
    assert!(g.gx(g.k0 + 1) > g.gx(g.k0));
}

/// Regression (found by this suite): `horz` 1e17 merged 4 columns into one
/// (k + horz rounded), and 1e19 overflowed the column index.
#[test]
fn shift_beyond_max_shift_texels_is_a_grid_error_and_below_it_cells_stay_distinct() {
    let poly = map_to_plane(&arrow(1.0, DVec3::ZERO), 0.0, 1e-6).unwrap();
    for (horz, vert) in [
        (1e17, 0.0),
        (0.0, -1e19),
        (f64::INFINITY, 0.0),
        (0.0, f64::NAN),
    ] {
        let place = Placement {
            incr: 0.25,
            horz,
            vert,
        };
        assert!(
            matches!(
                Grid::new(&poly.points, place),
                Err(GridError::ShiftTooLarge { .. })
            ),
            "{horz} {vert}"
        );
    }
    // The largest allowed shift (a whole number of texels) keeps every
    // column and row: the same cells as no shift, renumbered.
    let at = |shift: f64| {
        let place = Placement {
            incr: 0.25,
            horz: shift,
            vert: -shift,
        };
        let g = Grid::new(&poly.points, place).unwrap();
        let mut s = Sum {
            finite: true,
            ..Sum::default()
        };
        Partitioner::new().run(&poly, &g, &mut s);
        (g.cells(), s.cells.len(), s.area)
    };
    assert_eq!(at(MAX_SHIFT_TEXELS), at(0.0));
}
