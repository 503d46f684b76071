//! Quadric records as triangle records, for tools that forward polygons
//! (`polyfill3`) to readers that know no quadrics. Apart from the record
//! parsers because it writes records rather than reading them, and apart
//! from the objects because it changes a record's geometry, not its place.

use super::fields::Fields;
use super::record::{PatternMode, Record};
use crate::geom::Shape;
use serde_json::Value;

/// A quadric record as plain triangle records, for tools that forward
/// polygons (`polyfill3`): each triangle keeps the record's other fields
/// (unknown ones as written),
/// gets `"vertices"` (the record's transform applied) and, when the record
/// has a pattern, `"uv"` in texels of a `pattern_size` pattern with the
/// pattern's mode set to `"uv"` (see [`crate::geom::quadric::QuadricShape::texel_triangles`]).
/// `tolerance` is the chord tolerance in the record's space, for the slices
/// and stacks it leaves out. Not a quadric: `None`.
pub fn quadric_triangles(
    r: &Record,
    tolerance: f64,
    pattern_size: Option<u32>,
) -> Option<Result<Vec<Fields>, crate::geom::quadric::QuadricError>> {
    let Shape::Quadric(q) = &r.shape else {
        return None;
    };
    // Chords in the quadric's own units: the transform stretches them by at
    // most its largest column length (an upper bound on its largest
    // singular value within sqrt(3)).
    let m = q.transform.matrix();
    let stretch = [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|c| c.truncate().length())
        .fold(0.0, f64::max);
    let side = pattern_size.unwrap_or(1);
    let tris = match q.texel_triangles(tolerance / stretch, (side, side)) {
        Ok(t) => t,
        Err(e) => return Some(Err(e)),
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
    Some(Ok(tris
        .iter()
        .map(|t| {
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
            f
        })
        .collect()))
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
        let tris = quadric_triangles(&recs[0], 0.1, Some(16)).unwrap().unwrap();
        assert_eq!(tris.len(), 8);
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
        assert!(quadric_triangles(&recs[1], 0.1, None).is_none());
    }
}
