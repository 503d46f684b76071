//! Quadric records as triangle records, for tools that forward polygons
//! (`polyfill3`) to readers that know no quadrics. Apart from the record
//! parsers because it writes records rather than reading them, and apart
//! from the objects because it changes a record's geometry, not its place.

use super::fields::Fields;
use super::record::{PatternMode, Record};
use crate::geom::Shape;
use serde_json::Value;

/// The triangles a quadric record expands into at `tolerance` (chords in
/// the record's space, for the slices and stacks it leaves out), at most
/// ([`crate::geom::quadric::Quadric::triangle_bound`]), known before anything
/// is tessellated, so a tool
/// can refuse a record over its budget first (issue 17, item 2). Not a
/// quadric: `None`.
pub fn quadric_triangle_bound(r: &Record, tolerance: f64) -> Option<u64> {
    let Shape::Quadric(q) = &r.shape else {
        return None;
    };
    Some(q.triangle_bound(tolerance / stretch(q)))
}

/// How much the record's transform stretches chords: at most its largest
/// column length (an upper bound on its largest singular value within
/// sqrt(3)), so chords in the quadric's own units are scaled by it.
fn stretch(q: &crate::geom::quadric::QuadricShape) -> f64 {
    let m = q.transform.matrix();
    [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|c| c.truncate().length())
        .fold(0.0, f64::max)
}

/// A quadric record as plain triangle records, for tools that forward
/// polygons (`polyfill3`): each triangle keeps the record's other fields
/// (unknown ones as written),
/// gets `"vertices"` (the record's transform applied) and, when the record
/// has a pattern, `"uv"` in texels of a `pattern_size` pattern with the
/// pattern's mode set to `"uv"` (see [`crate::geom::quadric::QuadricShape::texel_triangles`]).
/// `tolerance` is the chord tolerance in the record's space, for the slices
/// and stacks it leaves out. Each record is made and handed to `each` as
/// the tessellation reaches it, so none is held: a million triangles as JSON
/// values at once took 2.9 GB, and as triangles 2.3 GB at ten million.
/// Returns how many were handed over; not a quadric: `None`.
pub fn for_each_quadric_triangle<E: From<crate::geom::quadric::QuadricError>>(
    r: &Record,
    tolerance: f64,
    pattern_size: Option<u32>,
    mut each: impl FnMut(Fields) -> Result<(), E>,
) -> Option<Result<u64, E>> {
    let Shape::Quadric(q) = &r.shape else {
        return None;
    };
    let mut base = r.fields.clone();
    base.remove(q.kind);
    base.remove("transform");
    let screen = matches!(
        r.pattern.as_ref().and_then(|p| p.mode),
        Some(PatternMode::Screen)
    );
    let uv = pattern_size.is_some() && !screen;
    if let (true, Some(Value::Object(p))) = (uv, base.get_mut("pattern")) {
        p.insert("mode".into(), Value::from("uv"));
    }
    let side = pattern_size.unwrap_or(1);
    let mut count = 0u64;
    let done = q.for_each_texel_triangle(tolerance / stretch(q), (side, side), |t| {
        let mut f = base.clone();
        f.insert(
            "vertices",
            Value::Array(
                t.v.iter()
                    .map(|p| serde_json::json!([p.x, p.y, p.z]))
                    .collect(),
            ),
        );
        if uv {
            f.insert(
                "uv",
                Value::Array(t.uv.iter().map(|c| serde_json::json!(c)).collect()),
            );
        }
        count += 1;
        each(f)
    });
    Some(done.map(|()| count))
}

#[cfg(test)]
mod tests {
    use super::super::testing::read_all;
    use super::*;
    use glam::DVec3;

    #[test]
    fn quadric_triangles_become_uv_records_keeping_other_fields() {
        let recs = read_all(
            r#"{"sphere": {"radius": 1, "slices": 4, "stacks": 2}, "pattern": {"file": "p.pat"}, "id": 7, "transform": {"translate": [0, 0, 3]}}
               {"rect": [0,0,1,1], "color": [0,0,0]}"#,
        )
        .unwrap();
        let mut tris = Vec::new();
        let n = for_each_quadric_triangle(&recs[0], 0.1, Some(16), |t| {
            tris.push(t);
            Ok::<(), crate::geom::quadric::QuadricError>(())
        })
        .unwrap()
        .unwrap();
        assert_eq!((n, tris.len()), (8, 8));
        assert_eq!(quadric_triangle_bound(&recs[0], 0.1), Some(8));
        for t in &tris {
            assert_eq!(t.field("id").unwrap().to_string(), "7");
            assert_eq!(t["pattern"]["mode"], "uv");
            assert!(t.get("sphere").is_none() && t.get("transform").is_none());
            let back = Record::from_fields(0, t.clone()).unwrap();
            let Shape::Polygon(v) = &back.shape else {
                panic!()
            };
            assert!(v
                .iter()
                .all(|p| ((*p - DVec3::new(0.0, 0.0, 3.0)).length() - 1.0).abs() < 1e-12));
            assert!(back
                .uv
                .unwrap()
                .iter()
                .all(|c| (0.0..=16.0).contains(&c[0])));
        }
        assert!(for_each_quadric_triangle(&recs[1], 0.1, None, |_| Ok::<
            (),
            crate::geom::quadric::QuadricError,
        >(()))
        .is_none());
    }
}
