//! Lighting (issue 23, item 1): `{"light": ...}` elements, flat and smooth
//! shading, lit textures, each checked against a computation made here and
//! against `--reference`.

use crate::util::{checker16, repo, Dir, OkStdout};
use predicates::prelude::*;
use serde_json::Value;

fn encode(l: f64) -> i32 {
    (patkit::color::linear_to_srgb_f64(l.clamp(0.0, 1.0)) * 255.0).round() as i32
}

fn decode(png: &[u8]) -> image::RgbImage {
    image::load_from_memory(png).unwrap().to_rgb8()
}

/// `scene-render --image A --compare B --json`'s "compare" object.
fn compare(dir: &Dir, image: &str, reference: &str) -> Value {
    let out = dir
        .cmd("scene-render")
        .args(["--image", image, "--compare", reference, "--json"])
        .ok_stdout();
    serde_json::from_slice::<Value>(&out).unwrap()["compare"].clone()
}

/// One world unit per pixel, the origin at the image's centre.
const ORTHO: [&str; 4] = ["--ortho", "-50,50,-50,50,-100,100", "--size", "100x100"];

clitest!(a_flat_face_takes_ambient_plus_lambert_exactly, |dir| {
    // A square tilted 60 degrees about x: its normal is (0, -sin 60, cos 60),
    // so a light along -z meets it at cos 60 = 1/2.
    let (s, c) = (3f64.sqrt() / 2.0, 0.5);
    dir.write(
        "flat.json",
        format!(
            r#"{{"light": {{"direction": [0, 0, -1], "intensity": [1, 0.5, 0.25]}}}}
{{"light": {{"ambient": 0.1}}}}
{{"vertices": [[-40,-40,0],[40,-40,0],[40,{y},{z}],[-40,{y},{z}]], "color": [200, 150, 100]}}
{{"vertices": [[-48,-48,-50],[-38,-48,-50],[-38,-38,-50]], "color": [200, 150, 100], "shade": "none"}}
"#,
            y = -40.0 + 80.0 * c,
            z = 80.0 * s
        ),
    );
    let png = dir
        .cmd("scene-render")
        .args(ORTHO)
        .args(["flat.json", "-o", "-"])
        .ok_stdout();
    let img = decode(&png);
    let lin = |code: f64| patkit::color::srgb_to_linear_f64(code / 255.0);
    let colour = [lin(200.0), lin(150.0), lin(100.0)];
    let e = [0.1 + 0.5, 0.1 + 0.25, 0.1 + 0.125];
    let want: Vec<i32> = (0..3).map(|ch| encode(colour[ch] * e[ch])).collect();
    // A pixel well inside the face: one flat colour, correctly rounded.
    let p = img.get_pixel(50, 60).0.map(|v| v as i32);
    assert_eq!(p.to_vec(), want, "lit face");
    // "shade": "none" keeps the record's own colour.
    assert_eq!(img.get_pixel(9, 96).0, [200, 150, 100]);
});

clitest!(a_smooth_sphere_follows_lambert_and_the_reference, |dir| {
    dir.write(
        "sphere.json",
        r#"{"light": {"direction": [0, 0, -1]}}
{"light": {"ambient": 0}}
{"sphere": {"radius": 40, "slices": 96, "stacks": 96}, "color": [255, 255, 255]}
"#,
    );
    // The reference meets every edge of the pole's fan of triangles in the
    // pixels there (quadratic in their number): a coarser sphere keeps its
    // run short.
    dir.write(
        "coarse.json",
        String::from_utf8(dir.read("sphere.json"))
            .unwrap()
            .replace("96", "32"),
    );
    for (scene, aa, out) in [
        ("sphere.json", "exact", "exact.png"),
        ("coarse.json", "exact", "coarse.png"),
        ("coarse.json", "none", "none.png"),
    ] {
        dir.cmd("scene-render")
            .args(ORTHO)
            .args(["--aa", aa, scene, "-o", out])
            .assert()
            .success()
            .stderr("");
    }
    dir.cmd("scene-render")
        .args(ORTHO)
        .args(["--reference", "coarse.json", "-o", "ref.png"])
        .assert()
        .success();
    // Lambert on the true sphere, computed here: seen along -z, the light
    // meets the surface at cos = n_z = sqrt(1 - (x^2 + y^2) / r^2). The
    // tessellated sphere differs from it by its chords, so pixels well
    // inside the disc are within a few codes.
    let img = decode(&dir.read("exact.png"));
    let mut worst = 0;
    for py in 0..100u32 {
        for px in 0..100u32 {
            let (x, y) = (px as f64 + 0.5 - 50.0, 49.5 - py as f64);
            let r2 = (x * x + y * y) / 1600.0;
            if r2 > 0.8 {
                continue;
            }
            let want = encode((1.0 - r2).sqrt());
            let got = img.get_pixel(px, py).0[0] as i32;
            worst = worst.max((got - want).abs());
        }
    }
    assert!(worst <= 2, "largest difference from Lambert: {worst} codes");
    // The exact default against the reference: the factor is taken at each
    // fragment's area centroid, which is its mean where it is affine, as it
    // is on the screen under a parallel projection (measured: identical).
    let c = compare(&dir, "coarse.png", "ref.png");
    assert_eq!(c["largest_error"].as_u64().unwrap(), 0, "{c}");
    // In perspective it is a ratio of affine functions: measured RMSE 0.029,
    // one pixel a code off, at 160x120.
    let view = [
        "--perspective",
        "40,auto,1,500",
        "--lookat",
        "0,0,120,0,0,0",
        "--size",
        "160x120",
    ];
    for (extra, out) in [(None, "pe.png"), (Some("--reference"), "pr.png")] {
        dir.cmd("scene-render")
            .args(view)
            .args(extra)
            .args(["coarse.json", "-o", out])
            .assert()
            .success();
    }
    let c = compare(&dir, "pe.png", "pr.png");
    assert!(c["rmse"].as_f64().unwrap() < 0.1, "{c}");
    assert!(c["largest_error"].as_u64().unwrap() <= 1, "{c}");
    let n = compare(&dir, "none.png", "ref.png");
    assert!(
        n["rmse"].as_f64().unwrap() > c["rmse"].as_f64().unwrap(),
        "{n} {c}"
    );
});

clitest!(a_point_light_lights_by_direction_to_each_vertex, |dir| {
    // A point light just above a flat floor: smooth shading lights the
    // floor under it fully and the far corners at a grazing angle.
    dir.write(
        "floor.json",
        r#"{"light": {"position": [0, 0, 30]}}
{"light": {"ambient": 0}}
{"vertices": [[-40,-40,0],[0,-40,0],[0,0,0]], "color": [255, 255, 255], "shade": "smooth"}
{"vertices": [[-40,-40,0],[0,0,0],[-40,0,0]], "color": [255, 255, 255], "shade": "flat"}
"#,
    );
    let img = decode(
        &dir.cmd("scene-render")
            .args(ORTHO)
            .args(["floor.json", "-o", "-"])
            .ok_stdout(),
    );
    // Smooth: at the vertex under the light the factor is 1; at (-40, -40)
    // cos = 30/sqrt(40^2 + 40^2 + 30^2). Interpolated between, brighter
    // towards the light.
    let near = img.get_pixel(48, 52).0[0];
    let far = img.get_pixel(12, 88).0[0];
    assert!(near > far + 60, "{near} {far}");
    // Flat: one colour, the light at the centroid (-80/3, -40/3, 0).
    let (cx, cy) = (-80.0f64 / 3.0, -40.0f64 / 3.0);
    let cos = 30.0 / (cx * cx + cy * cy + 900.0f64).sqrt();
    assert_eq!(img.get_pixel(20, 60).0[0] as i32, encode(cos));
});

clitest!(a_textured_sphere_is_modulated_by_its_lit_colour, |dir| {
    dir.write("c.pat", checker16());
    dir.write(
        "tex.json",
        r#"{"light": {"direction": [0, 0, -1]}}
{"sphere": {"radius": 40, "slices": 48, "stacks": 48}, "color": [0, 0, 255], "pattern": {"file": "c.pat", "compose": "modulate"}}
"#,
    );
    dir.write(
        "replace.json",
        r#"{"light": {"direction": [0, 0, -1]}}
{"sphere": {"radius": 40, "slices": 48, "stacks": 48}, "color": [0, 0, 255], "pattern": {"file": "c.pat"}}
"#,
    );
    dir.write(
        "unlit.json",
        r#"{"sphere": {"radius": 40, "slices": 48, "stacks": 48}, "color": [0, 0, 255], "pattern": {"file": "c.pat"}}
"#,
    );
    for (scene, out, extra) in [
        ("tex.json", "tex.png", None),
        ("tex.json", "ref.png", Some("--reference")),
        ("replace.json", "replace.png", None),
        ("unlit.json", "unlit.png", None),
    ] {
        dir.cmd("scene-render")
            .args(ORTHO)
            .args(extra)
            .args([scene, "-o", out])
            .assert()
            .success();
    }
    // Modulate: only blue survives (the lit colour is blue), and it varies.
    let img = decode(&dir.read("tex.png"));
    assert!(img.pixels().all(|p| p.0[0] == 0 && p.0[1] == 0));
    // Measured RMSE 0.0058, largest 1 code: each texel's piece times the
    // factor at its own centroid, its mean over the piece under this parallel
    // projection, as the reference has it. (0.086 when a fragment's texels
    // were all multiplied by the factor at the fragment's centroid.)
    let c = compare(&dir, "tex.png", "ref.png");
    assert!(c["rmse"].as_f64().unwrap() < 0.02, "{c}");
    assert!(c["largest_error"].as_u64().unwrap() <= 1, "{c}");
    // Replace ignores the lit colour, as GL_REPLACE does: the unlit picture.
    assert_eq!(dir.read("replace.png"), dir.read("unlit.png"));
});

clitest!(the_seeds_lit_earth_and_moon_render, |dir| {
    let scene = repo("fixtures/scenes/earth-lit.json");
    let png = dir
        .cmd("scene-render")
        .args(["--ortho", "-80,80,-60,60,0,100", "--size", "160x120"])
        .arg(&scene)
        .args(["-o", "-"])
        .ok_stdout();
    let img = decode(&png);
    // glMaterial (0, 0, 1) modulated by the photographs: blue only.
    assert!(img.pixels().all(|p| p.0[0] == 0 && p.0[1] == 0));
    // Lambert: the Earth's centre (x = -30) is brighter than near its limb.
    let mean = |x0: u32, x1: u32| -> f64 {
        let mut s = 0.0;
        for x in x0..x1 {
            for y in 55..65 {
                s += img.get_pixel(x, y).0[2] as f64;
            }
        }
        s / ((x1 - x0) * 10) as f64
    };
    assert!(mean(45, 55) > mean(12, 17) + 10.0);
});

clitest!(lights_are_checked_and_passed_through, |dir| {
    for (text, needle) in [
        (
            r#"{"light": {"direction": [0, 0, 0]}}"#,
            "record 0: light.direction [0, 0, 0]: has no direction",
        ),
        (
            r#"{"light": {"direction": [0, 0, 1]}, "vertices": [[0,0],[1,0],[0,1]]}"#,
            "record 0: light: a light has no geometry of its own, found \"vertices\" beside it",
        ),
        (
            r#"{"object": "o", "records": [{"light": {"ambient": 1}}]}"#,
            "record 0: object `o` holds a light: lights are top-level only",
        ),
        (
            r#"{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3], "normals": [[0,0,1],[0,0,1]]}"#,
            "record 0: normals: 2 for 3 vertices: expected one per vertex",
        ),
        (
            r#"{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3], "shade": "phong"}"#,
            "record 0: shade: expected \"flat\", \"smooth\", \"none\" or \"auto\"",
        ),
    ] {
        dir.write("bad.json", text);
        for tool in ["scene-render", "polyfill3"] {
            dir.cmd(tool)
                .args(["bad.json", "-o", "out"])
                .assert()
                .code(1)
                .stderr(predicate::str::contains(needle));
        }
    }
    dir.write("c.pat", checker16());
    dir.write(
        "mix.json",
        r#"{"light": {"direction": [0, 0, -1]}}
{"vertices": [[0,0],[1,0],[0,1]], "normals": [[0,0,1],[0,0,1],[0,0,1]], "color": [1,2,3], "pattern": {"file": "c.pat", "compose": "decal-intrinsic"}}"#,
    );
    dir.cmd("scene-render")
        .args(["--size", "8x8", "mix.json", "-o", "x.png"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "smooth lighting with compose decal-intrinsic",
        ));
    // polyfill3 forwards lights as written and cuts lit records into flat
    // cells (per-vertex normals are the record's, not the cells').
    dir.write(
        "s.json",
        r#"{"light": {"position": [1, 2, 3]}, "id": 7}
{"vertices": [[0,0],[4,0],[0,4]], "normals": [[0,0,1],[0,0,1],[0,0,1]], "pattern": {"file": "c.pat", "incr": 1}}"#,
    );
    let out = dir.cmd("polyfill3").arg("s.json").ok_stdout();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(r#"{"light":{"position":[1,2,3]},"id":7}"#)
    );
    assert!(lines.all(|l| !l.contains("normals")));
});
