//! Stripe textures on the command line: `pat-info` on modulation maps and on a
//! record's `"stripe"` object, `pat-from-image --stripe`, and every bad value
//! the issue names (w <= 0, yaw/pitch out of range, a map length that is not a
//! power of two, a table with the wrong number of entries).

use crate::util::repo;
use crate::util::OkStdout;
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
    let v = &v["files"];
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
    let records = v["records"].as_array().unwrap();
    assert_eq!(records.len(), 1, "{v}");
    let v = &records[0];
    assert_eq!(v["plane"], "yz");
    assert_eq!(v["theta"], 30.0);
    assert_eq!(v["select"], "rb");
    assert_eq!(v["translation"], "file maps/s.tm");
    // yz, theta 30: 30 degrees from Up towards North: yaw 90, pitch 60.
    assert!((v["yaw"].as_f64().unwrap() - 90.0).abs() < 1e-9, "{v}");
    assert!((v["pitch"].as_f64().unwrap() - 60.0).abs() < 1e-9, "{v}");
    assert_eq!(v["color"]["hex"], "#c8c8c8");
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

/// A square with a stripe texture of the given spacing, as NDJSON text.
fn striped(spacing: f64) -> String {
    format!(
        r#"{{"vertices": [[0,0],[4,0],[4,4],[0,4]], "stripe": {{"map": "m.map", "spacing": {spacing}, "yaw": 0}}}}"#
    )
}

clitest!(
    pat_info_record_numbers_definitions_and_instances_too,
    |dir| {
        // Issue 16 (7): on a stream with objects, `--record 0` said "record 0
        // does not exist: the stream has 2 records" (it counted the polygons the
        // instances place) while `--record 2` worked (it looked records up by
        // their place in the stream). One numbering: every element of the
        // stream counts, definitions and instances too, as in error messages.
        dir.write("m.map", MAP8);
        dir.write(
        "s.json",
        format!(
            "{{\"object\": \"w\", \"records\": [{}]}}\n{{\"instance\": \"w\", \"transform\": {{\"translate\": [0, 5, 0]}}}}\n{{\"instance\": \"w\"}}\n",
            striped(2.0)
        ),
    );
        let text = |n: &str| {
            String::from_utf8(
                dir.cmd("pat-info")
                    .args(["--record", n, "s.json"])
                    .ok_stdout(),
            )
            .unwrap()
        };
        let def = text("0");
        assert!(
            def.starts_with("s.json: record 0, polygon 0: stripe texture (object `w`)\n"),
            "{def}"
        );
        assert!(def.contains("  spacing       2 "), "{def}");
        for n in ["1", "2"] {
            let inst = text(n);
            assert!(
                inst.starts_with(&format!(
                    "s.json: record {n}, polygon 0: stripe texture (instance of `w`)\n"
                )),
                "{inst}"
            );
        }
        dir.cmd("pat-info")
            .args(["--record", "3", "s.json"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains(
                "s.json: record 3 does not exist: the stream has 3 records (numbered from 0)",
            ));
    }
);

clitest!(
    pat_info_record_errors_name_the_number_the_other_tools_give,
    |dir| {
        // Record 1 defines an object whose second record has a bad stripe:
        // scene-render names record 1, and so does `pat-info --record 1` (which
        // said "record 1 does not exist" before issue 16). Record 3 places an
        // unknown object: every tool names record 3.
        dir.write("m.map", MAP8);
        let plain = r#"{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3]}"#;
        let good = striped(2.0);
        let bad = striped(0.0);
        dir.write(
        "t.json",
        format!("{good}\n{{\"object\": \"w\", \"records\": [{plain}, {bad}]}}\n{{\"instance\": \"w\"}}\n{{\"instance\": \"ghost\"}}\n"),
    );
        dir.cmd("scene-render")
            .args(["--size", "10x10", "t.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains(
                "t.json: record 1: stripe.spacing: 0 is not positive",
            ));
        for (n, want) in [
            (
                "1",
                "t.json: record 1, polygon 1: stripe.spacing: 0 is not positive",
            ),
            (
                "2",
                "t.json: record 2, polygon 1: stripe.spacing: 0 is not positive",
            ),
            ("3", "t.json: record 3: instance of unknown object `ghost`"),
        ] {
            dir.cmd("pat-info")
                .args(["--record", n, "t.json"])
                .assert()
                .code(1)
                .stdout("")
                .stderr(predicate::str::contains(want));
        }
        dir.write("t.json", format!("{good}\n{{\"instance\": \"ghost\"}}\n"));
        dir.cmd("scene-render")
            .args(["--size", "10x10", "t.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains(
                "t.json: record 1: instance of unknown object `ghost`",
            ));
        // Elements before the one asked for are read and checked, later ones not.
        dir.cmd("pat-info")
            .args(["--record", "0", "t.json"])
            .assert()
            .success();
    }
);

clitest!(pat_info_record_lists_the_polygons_an_object_draws, |dir| {
    // An instance draws its object's polygons, all record N in errors;
    // `--record N` tells them apart as polygon 0, 1, ... in drawing order
    // and shows those with a stripe. --json lists them in "records".
    dir.write("m.map", MAP8);
    let plain = r#"{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3]}"#;
    dir.write(
        "u.json",
        format!(
            "{{\"object\": \"v\", \"records\": [{plain}]}}\n{{\"object\": \"w\", \"records\": [{plain}, {}, {{\"instance\": \"v\"}}, {}]}}\n{{\"instance\": \"w\", \"transform\": {{\"rotate\": 90, \"axis\": \"z\"}}}}\n",
            striped(2.0),
            striped(3.0)
        ),
    );
    let out = dir
        .cmd("pat-info")
        .args(["--record", "2", "--json", "u.json"])
        .ok_stdout();
    let v: Value = serde_json::from_slice(&out).unwrap();
    let list = v["records"].as_array().unwrap();
    assert_eq!(list.len(), 2, "{v}");
    assert_eq!(list[0]["record"], 2);
    assert_eq!(list[0]["polygon"], 1);
    assert_eq!(list[0]["instance_of"], "w");
    assert_eq!(list[0]["spacing"], 2.0);
    assert_eq!(list[1]["polygon"], 3);
    assert_eq!(list[1]["spacing"], 3.0);
    let out = dir
        .cmd("pat-info")
        .args(["--record", "1", "u.json"])
        .ok_stdout();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.starts_with("u.json: record 1, polygon 1: stripe texture (object `w`)\n"),
        "{text}"
    );
    assert!(
        text.contains("\nu.json: record 1, polygon 3: stripe texture (object `w`)\n"),
        "{text}"
    );
    dir.cmd("pat-info")
        .args(["--record", "0", "u.json"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "u.json: record 0 (object `v`) draws no polygon with a \"stripe\" texture",
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
        .args(["--preview", "--color", "always", "m.map"])
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

// ---------------------------------------------------------------------------
// scene-render with stripe records.

/// Decodes an 8-bit image to linear-light RGB per pixel (docs/rendering.md sRGB).
fn linear_pixels(png: &[u8]) -> Vec<[f64; 3]> {
    let img = image::load_from_memory(png).unwrap().to_rgb8();
    img.pixels()
        .map(|p| {
            p.0.map(|c| patkit::color::srgb_to_linear_f64(c as f64 / 255.0))
        })
        .collect()
}

/// RMSE in 8-bit codes over RGB between two images of the same size.
fn rmse_codes(a: &[u8], b: &[u8]) -> f64 {
    let (a, b) = (
        image::load_from_memory(a).unwrap().to_rgb8(),
        image::load_from_memory(b).unwrap().to_rgb8(),
    );
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: f64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
        .sum();
    (sum / a.as_raw().len() as f64).sqrt()
}

/// A facing wall over the whole 999 x 8 image (ortho2: one world unit per
/// pixel): stripes along x, 2.96 pixels per period of MAP8 (spacing 0.37, so
/// 2.7 samples per pixel, minified), 337.5 periods across, so the pixel
/// centres fall at every phase of the period.
const FLAT_WALL: &str = r#"{"vertices": [[0,0],[999,0],[999,8],[0,8]], "stripe": {"map": "m.map", "spacing": 0.37, "yaw": 0}}"#;

/// How far the image's mean may be from the map's mean, linear light. Every
/// filter (pyramid levels, their fade toward the mean, the exact box)
/// preserves the mean over whole periods; what is left is the half period
/// over (1/675 of the contrast), the aliasing of point samples against the
/// filtered map (largest for --cig-compat, which reads one entry per level:
/// measured 0.0029 with --aa none, at most 0.0008 otherwise), and 8-bit
/// rounding, which averages out.
const FLAT_MEAN_TOLERANCE: f64 = 0.005;

clitest!(a_flat_stripe_wall_has_the_maps_mean, |dir| {
    dir.write("m.map", MAP8);
    dir.write("wall.json", FLAT_WALL);
    let values = [0, 32, 64, 96, 128, 160, 192, 255];
    let want: f64 = values
        .iter()
        .map(|&v| patkit::color::srgb_to_linear_f64(v as f64 / 255.0))
        .sum::<f64>()
        / 8.0;
    for aa in ["none", "ss4", "exact"] {
        for lod in [
            &["--stripe-lod", "blended"][..],
            &["--stripe-lod", "nearest"],
            &["--cig-compat"],
        ] {
            let out = dir
                .cmd("scene-render")
                .args(["--size", "999x8", "--aa", aa])
                .args(lod)
                .args(["wall.json", "-o", "-"])
                .assert()
                .success();
            let px = linear_pixels(&out.get_output().stdout);
            let mean = px.iter().map(|p| p[0]).sum::<f64>() / px.len() as f64;
            assert!(
                (mean - want).abs() <= FLAT_MEAN_TOLERANCE,
                "--aa {aa} {lod:?}: mean {mean}, map mean {want}"
            );
            // Grey: a white face, all channels modulated alike.
            assert!(px.iter().all(|p| p[0] == p[1] && p[1] == p[2]));
            // Stripes, not a flat mean: the columns differ.
            let (lo, hi) = px
                .iter()
                .fold((1.0f64, 0.0f64), |(l, h), p| (l.min(p[0]), h.max(p[0])));
            assert!(hi - lo > 0.05, "--aa {aa} {lod:?}: {lo}..{hi}");
        }
    }
    // The reference too, exactly: the box over whole periods is the mean.
    let out = dir
        .cmd("scene-render")
        .args(["--size", "999x8", "--reference", "wall.json", "-o", "-"])
        .assert()
        .success();
    let px = linear_pixels(&out.get_output().stdout);
    let mean = px.iter().map(|p| p[0]).sum::<f64>() / px.len() as f64;
    assert!(
        (mean - want).abs() <= FLAT_MEAN_TOLERANCE,
        "reference mean {mean} vs {want}"
    );
});

/// A receding ground plane (stripes across the view direction, runway bars)
/// and a wall facing the camera (diagonal stripes with a colour code and a
/// select), as in `bench/stripe.sh`, at 160 x 120.
fn perspective_scene(dir: &crate::util::Dir) -> [&'static str; 6] {
    dir.write("m.map", MAP8);
    dir.write(
        "scene.json",
        concat!(
            r#"{"vertices": [[-200,0,0],[200,0,0],[200,0,-2000],[-200,0,-2000]], "color": [180,170,150], "stripe": {"map": "runway.map", "spacing": 0.05, "yaw": 90}}"#,
            "\n",
            r#"{"vertices": [[-20,0,-60],[20,0,-60],[20,25,-60],[-20,25,-60]], "stripe": {"map": "m.map", "spacing": 0.5, "yaw": 30, "pitch": 20, "code": 172, "select": "rg"}}"#,
            "\n"
        ),
    );
    std::fs::copy(
        repo("fixtures/stripes/runway.map"),
        dir.path().join("runway.map"),
    )
    .unwrap();
    [
        "--size",
        "160x120",
        "--perspective",
        "50,1.333,1,3000",
        "--lookat",
        "0,8,10,0,4,-100",
    ]
}

/// `--aa exact` against `--reference` on the perspective scene, RMSE in 8-bit
/// codes: measured 0.468 (0.479 while each fragment's stripes were averaged
/// over the whole fragment rather than the part that shows; 6.06 before
/// fragments were integrated exactly up to `stripe::MAX_EXACT_CROSSINGS`
/// boundaries). What is left is in the rows at
/// the ground's horizon, where fragments straddle it and take the LOD
/// filter, and where the reference is itself uncertain (98 pixels, up to 85
/// codes by its own estimate). Point-sampled centres give 12.7.
const EXACT_VS_REFERENCE_RMSE: f64 = 1.0;

clitest!(
    stripe_scene_exact_is_near_the_reference_and_threads_agree,
    |dir| {
        let view = perspective_scene(&dir);
        let run = |extra: &[&str]| -> Vec<u8> {
            dir.cmd("scene-render")
                .args(view)
                .args(extra)
                .args(["scene.json", "-o", "-"])
                .ok_stdout()
        };
        let exact = run(&[]);
        let reference = run(&["--reference"]);
        let e = rmse_codes(&exact, &reference);
        assert!(e <= EXACT_VS_REFERENCE_RMSE, "exact vs reference: RMSE {e}");
        let none = run(&["--aa", "none"]);
        let n = rmse_codes(&none, &reference);
        assert!(
            n > e,
            "point sampling ({n}) should be farther from the reference than exact ({e})"
        );
        for extra in [
            &["--aa", "exact"][..],
            &["--aa", "ss4"],
            &["--reference"],
            &["--cig-compat", "--aa", "none"],
        ] {
            let one = run(&[extra, &["--threads", "1"][..]].concat());
            let three = run(&[extra, &["--threads", "3"][..]].concat());
            assert!(one == three, "{extra:?}: --threads 1 and 3 differ");
        }
        // The wall's colour code 172 = 36*4 + 6*4 + 4: (204, 204, 204); select
        // rg leaves blue at the face's 204 everywhere on the wall.
        let img = image::load_from_memory(&exact).unwrap().to_rgb8();
        let centre = img.get_pixel(80, 45).0;
        assert_eq!(centre[2], 204, "{centre:?}");
        assert!(centre[0] < 204 && centre[0] == centre[1], "{centre:?}");
    }
);

/// `--cig-compat` against the default (blended) on the perspective scene:
/// the seed's rule reads one entry per level, aligned to blocks, and
/// under-estimates diagonal footprints, so it differs visibly (measured RMSE
/// 10.2, mostly on the minified ground) but stays a filter of the same map
/// (an unrelated image is 40 and more away).
const CIG_VS_BLENDED_RMSE: (f64, f64) = (0.5, 15.0);

clitest!(cig_compat_differs_from_blended_within_a_bound, |dir| {
    let view = perspective_scene(&dir);
    let run = |extra: &[&str]| -> Vec<u8> {
        dir.cmd("scene-render")
            .args(view)
            .args(extra)
            .args(["scene.json", "-o", "-"])
            .ok_stdout()
    };
    let blended = run(&[]);
    let cig = run(&["--cig-compat"]);
    let nearest = run(&["--stripe-lod", "nearest"]);
    let d = rmse_codes(&blended, &cig);
    assert!(
        d > CIG_VS_BLENDED_RMSE.0 && d < CIG_VS_BLENDED_RMSE.1,
        "--cig-compat vs blended: RMSE {d}"
    );
    // Under --aa exact both integrate the box exactly; the LOD modes are
    // the point samplers' filter.
    assert_eq!(blended, nearest);
    assert!(
        rmse_codes(
            &run(&["--aa", "none"]),
            &run(&["--aa", "none", "--stripe-lod", "nearest"])
        ) > 0.0
    );
    dir.cmd("scene-render")
        .args(["--cig-compat", "--stripe-lod", "nearest", "scene.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--cig-compat"));
    dir.cmd("scene-render")
        .args(["--stripe-lod", "trilinear", "scene.json"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("trilinear"));
});

clitest!(scene_render_stripe_errors_name_the_record, |dir| {
    perspective_scene(&dir);
    let bad = |stripe: &str, needle: &str| {
        dir.write(
            "bad.json",
            format!(
                "{{\"vertices\": [[0,0],[9,0],[9,9]], \"color\": [1,2,3]}}\n{{\"vertices\": [[0,0],[9,0],[9,9]], \"stripe\": {stripe}}}\n"
            ),
        );
        dir.cmd("scene-render")
            .args(["--size", "10x10", "bad.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains(needle.to_string()));
        assert!(!dir.path().join("out.png").exists(), "{stripe}");
    };
    bad(
        r#"{"map": "m.map", "spacing": 0, "yaw": 0}"#,
        "scene-render: error: bad.json: record 1: stripe.spacing: 0 is not positive",
    );
    bad(
        r#"{"map": "m.map", "spacing": -0.5, "yaw": 0}"#,
        "bad.json: record 1: stripe.spacing: -0.5 is not positive",
    );
    bad(
        r#"{"map": "m.map", "spacing": 1, "yaw": 400}"#,
        "bad.json: record 1: stripe.yaw: 400 is out of range: expected 0 to 360 degrees",
    );
    bad(
        r#"{"map": "m.map", "spacing": 1, "yaw": 0, "pitch": -95}"#,
        "record 1: stripe.pitch: -95 is out of range",
    );
    bad(
        r#"{"map": "m.map", "spacing": 1, "yaw": 0, "select": "rq"}"#,
        "record 1: stripe.select: `rq`",
    );
    bad(
        r#"{"map": "m.map", "spaceing": 1, "yaw": 0}"#,
        "record 1: stripe.spaceing: unknown key",
    );
    bad(
        r#"{"map": "missing.map", "spacing": 1, "yaw": 0}"#,
        "bad.json: record 1: ",
    );
    bad(
        r#"{"map": "missing.map", "spacing": 1, "yaw": 0}"#,
        "missing.map",
    );
    dir.write("odd.map", "STRIPE 6\n1 2 3 4 5 6\n");
    bad(
        r#"{"map": "odd.map", "spacing": 1, "yaw": 0}"#,
        "odd.map:1: word 2 `6`: map length 6 is not a power of two",
    );
    dir.write("short.tm", "TRANSLATE\n1 2 3\n");
    bad(
        r#"{"map": "m.map", "spacing": 1, "yaw": 0, "translation": "short.tm"}"#,
        "short.tm:2: unexpected end of file: expected entry 4 of 256",
    );
    // One texture per face.
    dir.write("c.pat", crate::util::checker16());
    dir.write(
        "both.json",
        r#"{"vertices": [[0,0],[9,0],[9,9]], "pattern": {"file": "c.pat"}, "stripe": {"map": "m.map", "spacing": 1, "yaw": 0}}"#,
    );
    dir.cmd("scene-render")
        .args(["--size", "10x10", "both.json", "-o", "out.png"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "both.json: record 0: has both \"pattern\" and \"stripe\"",
        ));
});

clitest!(stripes_stay_on_an_instanced_object, |dir| {
    // Stripes along x (yaw 0) on an object moved along y: the stripes are
    // fixed to the object, and a move across them leaves them where a
    // record drawn at the moved place has them: the same image.
    dir.write("m.map", MAP8);
    let stripe = r#""stripe": {"map": "m.map", "spacing": 0.7, "yaw": 0, "phase": 1.5}"#;
    dir.write(
        "inst.json",
        format!(
            "{{\"object\": \"w\", \"records\": [{{\"vertices\": [[3,2],[50,2],[50,20],[3,20]], {stripe}}}]}}\n{{\"instance\": \"w\", \"transform\": [{{\"translate\": [0, 11, 0]}}]}}\n"
        ),
    );
    dir.write(
        "flat.json",
        format!("{{\"vertices\": [[3,13],[50,13],[50,31],[3,31]], {stripe}}}\n"),
    );
    let run = |f: &str| {
        dir.cmd("scene-render")
            .args(["--size", "60x40", f, "-o", "-"])
            .ok_stdout()
    };
    assert!(run("inst.json") == run("flat.json"));
});

// Seed 001's next face colour: with the blend flag, the dark end of the
// modulation takes the next face colour instead of black (blend select 0),
// or the bright end does (1), channel by channel in linear light.
clitest!(a_stripe_blends_to_the_next_face_colour, |dir| {
    dir.write("m.map", MAP8);
    // Four pixels per map sample (ortho, one unit per pixel), so the centre
    // columns of each sample are inside it and take its value whole.
    let wall = |extra: &str| {
        format!(
            r#"{{"vertices": [[0,0],[64,0],[64,4],[0,4]], "color": [255, 0, 0], "stripe": {{"map": "m.map", "spacing": 4, "yaw": 0{extra}}}}}"#
        )
    };
    let render = |name: &str, extra: &str, flags: &[&str]| -> Vec<u8> {
        dir.write(name, wall(extra));
        dir.cmd("scene-render")
            .args(["--size", "64x4"])
            .args(flags)
            .args([name, "-o", "-"])
            .ok_stdout()
    };
    let plain = render("plain.json", "", &[]);
    // A clear flag, or black as the next colour, is the seed's modulation to the byte.
    assert_eq!(
        render(
            "off.json",
            r#", "next_color": [0, 0, 255], "blend": 0"#,
            &[]
        ),
        plain
    );
    assert_eq!(
        render(
            "black.json",
            r#", "next_color": [0, 0, 0], "blend": true"#,
            &[]
        ),
        plain
    );
    let to_blue = render(
        "blue.json",
        r#", "next_color": [0, 0, 255], "blend": 1"#,
        &[],
    );
    let reversed = render(
        "rev.json",
        r#", "next_color": [0, 0, 255], "blend": 1, "blend_select": 1"#,
        &[],
    );
    let (blue, rev) = (
        image::load_from_memory(&to_blue).unwrap().to_rgb8(),
        image::load_from_memory(&reversed).unwrap().to_rgb8(),
    );
    let encode = |l: f64| (patkit::color::linear_to_srgb_f64(l) * 255.0).round() as i32;
    let values = [0, 32, 64, 96, 128, 160, 192, 255];
    for (k, v) in values.iter().enumerate() {
        // The sample's modulation, computed here from the sRGB decoding.
        let w = patkit::color::srgb_to_linear_f64(*v as f64 / 255.0);
        for x in [4 * k as u32 + 1, 4 * k as u32 + 2] {
            let p = blue.get_pixel(x, 1).0.map(|c| c as i32);
            let want = [encode(w), 0, encode(1.0 - w)];
            for c in 0..3 {
                assert!(
                    (p[c] - want[c]).abs() <= 1,
                    "select 0, x {x}: {p:?} vs {want:?}"
                );
            }
            let p = rev.get_pixel(x, 1).0.map(|c| c as i32);
            let want = [encode(1.0 - w), 0, encode(w)];
            for c in 0..3 {
                assert!(
                    (p[c] - want[c]).abs() <= 1,
                    "select 1, x {x}: {p:?} vs {want:?}"
                );
            }
        }
    }
    // A colour code works as the next colour too (code 4 is (0, 0, 204)).
    let coded = render("coded.json", r#", "next_code": 4, "blend": 1"#, &[]);
    let img = image::load_from_memory(&coded).unwrap().to_rgb8();
    assert_eq!(img.get_pixel(1, 1).0, [0, 0, 204]);
    let out = dir
        .cmd("pat-info")
        .args(["--record", "0", "coded.json"])
        .ok_stdout();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("  blend         to 0,0,204 #0000cc (next colour code 4), select 0 (dark stripes take the next colour)\n"),
        "{text}"
    );
    // The exact default agrees with the reference: the blend is linear in
    // the modulation, so both filters carry over.
    let reference = render(
        "blue.json",
        r#", "next_color": [0, 0, 255], "blend": 1"#,
        &["--reference"],
    );
    assert!(rmse_codes(&to_blue, &reference) < 0.5);
});

clitest!(stripe_blend_errors_name_the_field, |dir| {
    dir.write("m.map", MAP8);
    for (extra, needle) in [
        (
            r#""blend": 1"#,
            "stripe.blend: the blend flag is set but there is no next face colour",
        ),
        (
            r#""blend": 2, "next_code": 3"#,
            "stripe.blend: expected the blend flag, 0, 1, false or true, found 2",
        ),
        (
            r#""blend": 1, "next_code": 3, "blend_select": 2"#,
            // One line, with no runs of spaces (a literal joined badly had 22).
            "stripe.blend_select: 2: seed 001 gives Blend Select 0..3 but no arithmetic; 0 \
             (dark stripes take the next face colour) and 1 (bright ones do) are read here, 2 \
             is not",
        ),
        (
            r#""next_code": 256"#,
            "stripe.next_code: expected a colour code 0..=255, found 256",
        ),
        (
            r#""next_color": [1, 2]"#,
            "stripe.next_color: expected [r,g,b], found [1,2]",
        ),
        (
            r#""next_color": [1, 2, 3], "next_code": 3"#,
            "stripe.next_color: given beside stripe.next_code",
        ),
    ] {
        dir.write(
            "bad.json",
            format!(
                r#"{{"vertices": [[0,0],[8,0],[8,8],[0,8]], "stripe": {{"map": "m.map", "spacing": 1, "yaw": 0, {extra}}}}}"#
            ),
        );
        for tool in ["scene-render", "pat-info"] {
            let args: &[&str] = match tool {
                "scene-render" => &["--size", "8x8", "bad.json", "-o", "x.png"],
                _ => &["--record", "0", "bad.json"],
            };
            dir.cmd(tool)
                .args(args)
                .assert()
                .failure()
                .stderr(predicate::str::contains(needle));
        }
    }
});
