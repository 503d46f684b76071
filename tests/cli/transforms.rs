//! A `"transform"` on a polygon, rect, circle or arc record (issue 23, item
//! 3): applied when the record is read, as an instance's transform moves
//! it, by every tool; `polyfill3` writes the moved cells without the key. An
//! animated one is the renderer's, as an instance's is.

use crate::util::{checker16, Dir};
use serde_json::Value;

const ORTHO: [&str; 4] = ["--ortho", "0,64,0,48,-10,10", "--size", "64x48"];

/// `scene-render --image A --compare B --json`'s "compare" object.
fn compare(dir: &Dir, image: &str, reference: &str) -> Value {
    let out = dir
        .cmd("scene-render")
        .args(["--image", image, "--compare", reference, "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice::<Value>(&out.stdout).unwrap()["compare"].clone()
}

fn render(dir: &Dir, scene: &str, out: &str, extra: &[&str]) {
    dir.cmd("scene-render")
        .args(ORTHO)
        .args(extra)
        .args([scene, "-o", out])
        .assert()
        .success()
        .stderr("");
}

clitest!(
    a_record_transform_draws_the_record_where_its_moved_vertices_are,
    |dir| {
        dir.write("c.pat", checker16());
        // Translations and power-of-two scales are exact in binary, so the
        // moved records are exactly the hand-moved ones.
        dir.write(
            "moved.json",
            r#"{"rect": [0, 0, 4, 3], "color": [200, 30, 30], "transform": [{"scale": 2}, {"translate": [3, 5, 0]}]}
{"vertices": [[0,0],[8,0],[0,8]], "pattern": {"file": "c.pat", "incr": 0.5}, "transform": {"translate": [20, 4, 0]}}
{"circle": {"center": [0, 0], "radius": 4}, "color": [20, 200, 40], "transform": {"translate": [48, 30, 0]}}
"#,
        );
        dir.write(
            "by_hand.json",
            r#"{"vertices": [[3,5,0],[11,5,0],[11,11,0],[3,11,0]], "color": [200, 30, 30]}
{"vertices": [[20,4,0],[28,4,0],[20,12,0]], "pattern": {"file": "c.pat", "incr": 0.5}}
{"circle": {"center": [48, 30], "radius": 4}, "color": [20, 200, 40]}
"#,
        );
        render(&dir, "moved.json", "moved.png", &[]);
        render(&dir, "by_hand.json", "by_hand.png", &[]);
        // The circle is a polygon once moved (within INSTANCE_CURVE_TOLERANCE
        // of the circle); the rest is identical.
        let c = compare(&dir, "moved.png", "by_hand.png");
        assert!(c["rmse"].as_f64().unwrap() < 0.5, "{c}");
        assert!(c["largest_error"].as_u64().unwrap() <= 2, "{c}");
        // Without the circle, the bytes are the same.
        let first_two = |name: &str| {
            let text = String::from_utf8(dir.read(name)).unwrap();
            text.lines().take(2).collect::<Vec<_>>().join("\n")
        };
        dir.write("moved2.json", first_two("moved.json"));
        dir.write("by_hand2.json", first_two("by_hand.json"));
        render(&dir, "moved2.json", "moved2.png", &[]);
        render(&dir, "by_hand2.json", "by_hand2.png", &[]);
        assert_eq!(dir.read("moved2.png"), dir.read("by_hand2.png"));
    }
);

clitest!(
    polyfill3_applies_a_record_transform_and_drops_the_key,
    |dir| {
        dir.write("c.pat", checker16());
        dir.write(
            "s.json",
            r#"{"vertices": [[0,0],[10,0],[10,6],[0,6]], "pattern": {"file": "c.pat", "incr": 1}, "transform": [{"rotate": 30, "axis": "z"}, {"translate": [30, 10, 0]}]}
{"rect": [0, 0, 5, 5], "color": [9, 9, 9], "transform": {"translate": [2, 30, 0]}}
"#,
        );
        dir.cmd("polyfill3")
            .args(["s.json", "-o", "cells.ndjson"])
            .assert()
            .success();
        let cells = String::from_utf8(dir.read("cells.ndjson")).unwrap();
        let mut count = 0;
        for line in cells.lines() {
            let v: Value = serde_json::from_str(line).unwrap();
            assert!(v.get("transform").is_none(), "{line}");
            for p in v["vertices"].as_array().unwrap() {
                let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
                // Every vertex is in the moved place, none at the origin's.
                assert!(x >= 1.9 && y >= 9.9, "{line}");
            }
            count += 1;
        }
        assert!(count > 30, "{count} cells");
        // Through polyfill3 or direct: the same picture, to the tolerance
        // of cells cut from the moved polygon.
        render(&dir, "s.json", "direct.png", &[]);
        render(&dir, "cells.ndjson", "piped.png", &[]);
        let c = compare(&dir, "piped.png", "direct.png");
        assert!(c["rmse"].as_f64().unwrap() < 0.5, "{c}");
    }
);

clitest!(
    an_animated_record_transform_moves_it_as_an_instance_would,
    |dir| {
        dir.write("c.pat", checker16());
        let turn =
            r#"[{"rotate": {"start": 0, "step": 20}, "axis": "z"}, {"translate": [32, 24, 0]}]"#;
        let rec =
            r#""vertices": [[-10,-6],[10,-6],[0,12]], "pattern": {"file": "c.pat", "incr": 0.75}"#;
        dir.write("record.json", format!("{{{rec}, \"transform\": {turn}}}\n"));
        dir.write(
            "instance.json",
            format!(
                "{{\"object\": \"t\", \"records\": [{{{rec}}}]}}\n{{\"instance\": \"t\", \"transform\": {turn}}}\n"
            ),
        );
        for (scene, out) in [("record.json", "r-%d.png"), ("instance.json", "i-%d.png")] {
            dir.cmd("scene-render")
                .args(ORTHO)
                .args(["--frames", "3", scene, "-o", out])
                .assert()
                .success()
                .stderr("");
        }
        for k in 0..3 {
            assert_eq!(
                dir.read(&format!("r-{k}.png")),
                dir.read(&format!("i-{k}.png")),
                "frame {k}"
            );
        }
        assert_ne!(dir.read("r-0.png"), dir.read("r-1.png"));
        // polyfill3 cuts the record in its own coordinates and leaves the
        // animated transform on every cell; the renderer turns them all.
        dir.cmd("polyfill3")
            .args(["record.json", "-o", "cells.ndjson"])
            .assert()
            .success();
        let cells = String::from_utf8(dir.read("cells.ndjson")).unwrap();
        assert!(cells.lines().count() > 20);
        assert!(cells
            .lines()
            .all(|l| serde_json::from_str::<Value>(l).unwrap()["transform"].is_array()));
        dir.cmd("scene-render")
            .args(ORTHO)
            .args(["--frames", "3", "cells.ndjson", "-o", "c-%d.png"])
            .assert()
            .success();
        for k in 0..3 {
            let c = compare(&dir, &format!("c-{k}.png"), &format!("r-{k}.png"));
            assert!(c["rmse"].as_f64().unwrap() < 0.5, "frame {k}: {c}");
        }
    }
);

clitest!(
    a_record_transform_that_cannot_apply_is_refused_naming_why,
    |dir| {
        dir.write("c.pat", checker16());
        for (line, message) in [
            (
                r#"{"rect": [0,0,4,4], "pattern": {"file": "c.pat", "incr": 1}, "transform": {"scale": [2, 1, 1]}}"#,
                "record 0: transform: the transform stretches unevenly, which an object-mode pattern cannot follow: define the record as an object and place an instance of it",
            ),
            (
                r#"{"rect": [0,0,4,4], "pattern": {"file": "c.pat"}, "transform": {"scale": 2}}"#,
                "record 0: transform: the transform scales by 2: give the pattern an explicit \"incr\" so it can scale too",
            ),
            (
                r#"{"rect": [0,0,1.5e308,4], "color": [1,2,3], "transform": {"translate": [1e308, 0, 0]}}"#,
                "record 0: transform: the transform moves a vertex out of the finite numbers",
            ),
            (
                r#"{"rect": [0,0,4,4], "color": [1,2,3], "transform": {"scale": 1e300}}"#,
                "record 0: transform step 0: scale: overflows",
            ),
            (
                r#"{"rect": [0,0,4,4], "color": [1,2,3], "transform": {"spin": 2}}"#,
                "record 0: transform step 0",
            ),
        ] {
            dir.write("bad.json", line);
            for tool in ["scene-render", "polyfill3"] {
                let flags = if tool == "polyfill3" { &[][..] } else { &ORTHO[..] };
                let out = dir
                    .cmd(tool)
                    .args(flags)
                    .args(["bad.json", "-o", "out"])
                    .output()
                    .unwrap();
                let err = String::from_utf8_lossy(&out.stderr);
                assert_eq!(out.status.code(), Some(1), "{tool} {line}: {err}");
                assert!(err.contains(message), "{tool} {line}: {err}");
                assert!(!dir.path().join("out").exists());
            }
        }
        // A stretch is fine where the pattern is placed by uv, or with no pattern.
        dir.write(
            "ok.json",
            r#"{"vertices": [[0,0],[4,0],[0,4]], "uv": [[0,0],[4,0],[0,4]], "pattern": {"file": "c.pat"}, "transform": {"scale": [2, 1, 1]}}
{"rect": [0,0,4,4], "color": [1,2,3], "transform": {"scale": [3, 1, 1]}}"#,
        );
        render(&dir, "ok.json", "ok.png", &[]);
    }
);
