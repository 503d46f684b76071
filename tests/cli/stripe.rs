//! Stripe textures on the command line: `pat-info` on modulation maps and on a
//! record's `"stripe"` object, `pat-from-image --stripe`, and every bad value
//! the issue names (w <= 0, yaw/pitch out of range, a map length that is not a
//! power of two, a table with the wrong number of entries).

use crate::util::repo;
use predicates::prelude::*;
use serde_json::Value;

/// A small canonical map: 8 entries.
const MAP8: &str = "STRIPE 8\n0 32 64 96 128 160 192 255\n";

fn stdout_of(a: &assert_cmd::assert::Assert) -> String {
    String::from_utf8(a.get_output().stdout.clone()).unwrap()
}

clitest!(pat_info_reports_a_map_and_its_levels, |dir| {
    dir.write("m.map", MAP8);
    let out = dir.cmd("pat-info").arg("m.map").assert().success();
    let text = stdout_of(&out);
    assert!(
        text.starts_with("m.map: modulation map, 8 entries, 4 levels, fade linear\n"),
        "{text}"
    );
    assert!(text.contains("      0        8    0.00  255.00"), "{text}");
    assert!(text.contains("      3        1"), "{text}");
});

clitest!(pat_info_json_mixes_maps_and_patterns, |dir| {
    dir.write("m.map", MAP8);
    dir.write("c.pat", crate::util::checker16());
    let out = dir
        .cmd("pat-info")
        .args(["--json", "m.map", "c.pat"])
        .assert()
        .success();
    let v: Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(v[0]["kind"], "modulation map");
    assert_eq!(v[0]["length"], 8);
    assert_eq!(v[0]["levels"].as_array().unwrap().len(), 4);
    assert_eq!(v[0]["levels"][0]["max"], 255.0);
    assert_eq!(v[1]["size"], 16);
});

clitest!(pat_info_checks_the_fixture_maps, |dir| {
    let maps: Vec<_> = ["furrow", "runway", "crops"]
        .iter()
        .map(|m| repo(&format!("fixtures/stripes/{m}.map")))
        .collect();
    dir.cmd("pat-info")
        .arg("--check")
        .args(&maps)
        .assert()
        .success()
        .stdout("");
});

clitest!(bad_maps_name_file_line_and_word, |dir| {
    dir.write("odd.map", "STRIPE 1000\n");
    dir.write("big.map", "STRIPE 8\n0 1 2 3 4 5 6 300\n");
    dir.cmd("pat-info")
        .args(["odd.map", "big.map"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "pat-info: error: odd.map:1: word 2 `1000`: map length 1000 is not a power of two from 1 to 65536",
        ))
        .stderr(predicate::str::contains(
            "big.map:2: word 10 `300`: out of range: expected value 8 of 8, 0..=255",
        ));
    dir.write("m.map", MAP8);
    dir.cmd("pat-info")
        .args(["--at", "0,0", "m.map"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--at names a texel of a pattern"));
});

/// A scene with a ground plane (record 0: yaw/pitch, code) and a wall
/// (record 1: reference plane, translation file), maps beside it.
fn scene(dir: &crate::util::Dir, ground_stripe: Value) {
    dir.write("maps/m.map", MAP8);
    dir.write(
        "maps/s.tm",
        format!(
            "TRANSLATE\n{}\n",
            (0..256)
                .map(|i| (255 - i).to_string())
                .collect::<Vec<_>>()
                .join(" ")
        ),
    );
    let ground = serde_json::json!({
        "vertices": [[-50, 0, 0], [50, 0, 0], [50, 0, -100], [-50, 0, -100]],
        "color": [100, 150, 60], "id": "ground", "stripe": ground_stripe
    });
    let wall = serde_json::json!({
        "vertices": [[-10, 0, -50], [10, 0, -50], [10, 10, -50], [-10, 10, -50]],
        "color": [200, 200, 200],
        "stripe": {"map": "maps/m.map", "spacing": 0.25, "plane": "yz", "theta": 30, "translation": "maps/s.tm", "select": "rb"}
    });
    dir.write("scene.json", format!("{ground}\n{wall}\n"));
}

clitest!(pat_info_record_prints_the_seeds_terms, |dir| {
    scene(
        &dir,
        serde_json::json!({"map": "maps/m.map", "spacing": 2, "phase": 3, "yaw": 90, "pitch": 0, "code": 4}),
    );
    let out = dir
        .cmd("pat-info")
        .args(["--record", "0", "scene.json"])
        .assert()
        .success();
    let text = stdout_of(&out);
    assert!(
        text.starts_with("scene.json: record 0: stripe texture\n"),
        "{text}"
    );
    assert!(
        text.contains("  map           maps/m.map (8 entries, 4 levels, fade linear)"),
        "{text}"
    );
    assert!(text.contains("  spacing       2 (w, world units per sample; repeats every 16; K_p = 1/(8 w) = 0.0625)"), "{text}");
    assert!(
        text.contains("  start point   3 (sample; P0 = 0.375)"),
        "{text}"
    );
    assert!(text.contains("  yaw           90 "), "{text}");
    assert!(text.contains("  pitch         0 "), "{text}");
    assert!(
        text.contains("  colour code   4 (0,0,204 #0000cc)"),
        "{text}"
    );
    let out = dir
        .cmd("pat-info")
        .args(["--record", "1", "--json", "scene.json"])
        .assert()
        .success();
    let v: Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(v["plane"], "yz");
    assert_eq!(v["theta"], 30.0);
    assert_eq!(v["select"], "rb");
    assert_eq!(v["translation"], "file maps/s.tm");
    // yz, theta 30: 30 degrees from Up towards North: yaw 90, pitch 60.
    assert!((v["yaw"].as_f64().unwrap() - 90.0).abs() < 1e-9, "{v}");
    assert!((v["pitch"].as_f64().unwrap() - 60.0).abs() < 1e-9, "{v}");
    assert_eq!(v["colour"]["hex"], "#c8c8c8");
});

clitest!(pat_info_record_errors_name_the_record_and_field, |dir| {
    let bad = |stripe: Value, needle: &str| {
        scene(&dir, stripe);
        dir.cmd("pat-info")
            .args(["--record", "0", "scene.json"])
            .assert()
            .code(1)
            .stdout("")
            .stderr(predicate::str::contains(needle.to_string()));
    };
    bad(
        serde_json::json!({"map": "maps/m.map", "spacing": 0, "yaw": 0}),
        "scene.json: record 0: stripe.spacing: 0 is not positive",
    );
    bad(
        serde_json::json!({"map": "maps/m.map", "spacing": -1, "yaw": 0}),
        "stripe.spacing: -1 is not positive",
    );
    bad(
        serde_json::json!({"map": "maps/m.map", "spacing": 1, "yaw": 361}),
        "stripe.yaw: 361 is out of range: expected 0 to 360 degrees",
    );
    bad(
        serde_json::json!({"map": "maps/m.map", "spacing": 1, "yaw": 0, "pitch": 95}),
        "stripe.pitch: 95 is out of range: expected -90 to 90 degrees",
    );
    bad(
        serde_json::json!({"map": "maps/none.map", "spacing": 1, "yaw": 0}),
        "maps/none.map",
    );
    dir.write("maps/short.tm", "TRANSLATE\n1 2 3\n");
    bad(
        serde_json::json!({"map": "maps/m.map", "spacing": 1, "yaw": 0, "translation": "maps/short.tm"}),
        "maps/short.tm:2: unexpected end of file: expected entry 4 of 256, 0..=255",
    );
    dir.write("maps/odd.map", "STRIPE 6\n1 2 3 4 5 6\n");
    bad(
        serde_json::json!({"map": "maps/odd.map", "spacing": 1, "yaw": 0}),
        "map length 6 is not a power of two",
    );
    scene(
        &dir,
        serde_json::json!({"map": "maps/m.map", "spacing": 1, "yaw": 0}),
    );
    dir.cmd("pat-info")
        .args(["--record", "5", "scene.json"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "scene.json: record 5 does not exist: the stream has 2 records (numbered from 0)",
        ));
    dir.write(
        "plain.json",
        "{\"vertices\": [[0,0],[1,0],[0,1]], \"color\": [1,2,3]}\n",
    );
    dir.cmd("pat-info")
        .args(["--record", "0", "plain.json"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "plain.json: record 0 has no \"stripe\" texture",
        ));
    dir.cmd("pat-info")
        .args(["--record", "0", "scene.json", "plain.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--record takes exactly one polygon stream file",
        ));
});

fn bars_png(dir: &crate::util::Dir) {
    // 8 columns alternating black/white, 4 rows.
    let img = image::RgbaImage::from_fn(8, 4, |x, _| {
        let v = if x % 2 == 0 { 0 } else { 255 };
        image::Rgba([v, v, v, 255])
    });
    img.save(dir.path().join("bars.png")).unwrap();
}

clitest!(pat_from_image_stripe_writes_a_map, |dir| {
    bars_png(&dir);
    dir.cmd("pat-from-image")
        .args(["--stripe", "--length", "8", "bars.png", "-o", "bars.map"])
        .assert()
        .success();
    assert_eq!(
        String::from_utf8(dir.read("bars.map")).unwrap(),
        "STRIPE 8\n0 255 0 255 0 255 0 255\n"
    );
    // Across the bars at 90 degrees every entry is the linear-light mean grey.
    let out = dir
        .cmd("pat-from-image")
        .args(["--stripe", "--angle", "90", "--length", "4", "bars.png"])
        .assert()
        .success();
    assert_eq!(stdout_of(&out), "STRIPE 4\n188 188 188 188\n");
    dir.cmd("pat-info").arg("bars.map").assert().success();
});

clitest!(
    pat_from_image_stripe_rejects_bad_values_and_leaves_no_file,
    |dir| {
        bars_png(&dir);
        dir.cmd("pat-from-image")
            .args(["--stripe", "--length", "1000", "bars.png", "-o", "x.map"])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(
                "invalid --length `1000`: map length 1000 is not a power of two from 1 to 65536",
            ));
        dir.cmd("pat-from-image")
            .args(["--angle", "10", "bars.png", "-o", "x.map"])
            .assert()
            .code(2);
        dir.cmd("pat-from-image")
            .args(["--stripe", "--colors", "4", "bars.png", "-o", "x.map"])
            .assert()
            .code(2);
        dir.write("junk.png", "not an image");
        dir.cmd("pat-from-image")
            .args(["--stripe", "junk.png", "-o", "x.map"])
            .assert()
            .code(1);
        assert!(
            !dir.files().contains(&"x.map".to_string()),
            "{:?}",
            dir.files()
        );
    }
);

clitest!(pat_info_previews_a_map_one_line_per_level, |dir| {
    dir.write("m.map", MAP8);
    let out = dir
        .cmd("pat-info")
        .args(["--preview", "m.map"])
        .assert()
        .success();
    let text = stdout_of(&out);
    // The report (2 + 4 lines), then one grey strip per level: 8, 4, 2, 1 cells.
    let strips: Vec<&str> = text.lines().filter(|l| l.contains("\x1b[48;2;")).collect();
    assert_eq!(strips.len(), 4, "{text}");
    assert_eq!(strips[0].matches("\x1b[48;2;").count(), 8);
    assert_eq!(strips[3].matches("\x1b[48;2;").count(), 1);
    assert!(strips[0].starts_with("\x1b[48;2;0;0;0m "), "{text}");
});
