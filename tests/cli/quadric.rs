//! Quadric records (docs/objects.md, Quadrics): seed 002's two spheres
//! against their golden image, the tessellation at the camera's pixel
//! tolerance, GLU's seam, errors, polyfill3's expansion and the animated PNG.

use crate::util::OkStdout;
use predicates::prelude::*;

/// A 16x16 pattern split at s = 0.5: red in columns 0-7, blue in 8-15.
const HALF: &str = "16 2\n255 0 0\n";

fn half_pattern() -> String {
    let mut s = String::from(HALF);
    s.push_str(&"ff00\n".repeat(16));
    s.push_str("0 0 255\n");
    s.push_str(&"00ff\n".repeat(16));
    s
}

fn decode(bytes: &[u8]) -> image::RgbaImage {
    image::load_from_memory(bytes).unwrap().into_rgba8()
}

fn linear(code: u8) -> f64 {
    patkit::color::srgb_to_linear_f64(code as f64 / 255.0)
}

/// `scene-render` of `file` under `--ortho 0,200,0,200,-100,100` at 200x200,
/// as PPM bytes.
fn render_200(dir: &crate::util::Dir, file: &str) -> Vec<u8> {
    dir.cmd("scene-render")
        .args([
            "--ortho",
            "0,200,0,200,-100,100",
            "--size",
            "200x200",
            "--format",
            "ppm",
        ])
        .arg(file)
        .ok_stdout()
}

/// Seed 002's view: glOrtho(-80,80,-60,60,0,100) on 800x600.
const SEED_ORTHO: [&str; 4] = ["--ortho", "-80,80,-60,60,0,100", "--size", "800x600"];

clitest!(seed_002_two_spheres_match_their_golden_image, |dir| {
    let out = dir
        .cmd("scene-render")
        .args(SEED_ORTHO)
        .arg(crate::util::repo("fixtures/scenes/two-spheres.json"))
        .assert()
        .success();
    crate::scene_render::assert_matches_golden(
        &out.get_output().stdout,
        "examples/golden/two-spheres.png",
    );
});

/// The summed coverage of a white sphere of radius `r` (pixels) on black.
fn sphere_area(dir: &crate::util::Dir, sphere: &str, extra: &[&str]) -> f64 {
    dir.write(
        "s.json",
        format!(r#"{{"sphere": {sphere}, "transform": {{"translate": [100, 100, 0]}}, "color": [255,255,255]}}"#),
    );
    let out = dir
        .cmd("scene-render")
        .args(["--ortho", "0,200,0,200,-100,100", "--size", "200x200"])
        .args(extra)
        .arg("s.json")
        .assert()
        .success();
    let img = decode(&out.get_output().stdout);
    img.pixels().map(|p| linear(p.0[0])).sum()
}

clitest!(
    a_sphere_covers_pi_r_squared_pixels_within_the_tolerance,
    |dir| {
        let r = 40.0f64;
        let exact = std::f64::consts::PI * r * r;
        for tol in [0.25, 1.0] {
            let area = sphere_area(
                &dir,
                r#"{"radius": 40}"#,
                &["--quadric-tolerance", &tol.to_string()],
            );
            // The silhouette is a polygon inscribed in the circle whose chords
            // stray at most `tol` pixels inwards, so it misses less than the
            // perimeter times `tol`; one pixel more covers 8-bit rounding.
            let bound = 2.0 * std::f64::consts::PI * r * tol + 1.0;
            assert!(
                area < exact + 1.0 && exact - area < bound,
                "tol {tol}: area {area}, pi r^2 {exact}"
            );
        }
        // Explicitly coarse: 6 slices make a hexagon (3 sqrt(3)/2 r^2) seen pole-on.
        let hex = sphere_area(&dir, r#"{"radius": 40, "slices": 6, "stacks": 40}"#, &[]);
        let want = 1.5 * 3f64.sqrt() * r * r;
        assert!((hex - want).abs() < 1.0, "hexagon {hex}, want {want}");
    }
);

clitest!(no_texel_wraps_across_the_seam, |dir| {
    dir.write("half.pat", half_pattern());
    // Rotated +90 about x, the seam (s = 0 and 1, own +y) faces the viewer
    // (+z) down the middle of the image, the sphere's north (own +z) down:
    // upside down, so s (east, GLU) runs from 0 (red) on the seam's left
    // and up to 1 (blue) on its right.
    dir.write(
        "s.json",
        r#"{"sphere": {"radius": 40, "slices": 24, "stacks": 12},
            "transform": [{"rotate": 90, "axis": "x"}, {"translate": [100, 100, 0]}],
            "color": [0,255,0], "pattern": {"file": "half.pat"}}"#,
    );
    let out = dir
        .cmd("scene-render")
        .args(["--ortho", "0,200,0,200,-100,100", "--size", "200x200"])
        .arg("s.json")
        .assert()
        .success();
    let img = decode(&out.get_output().stdout);
    for y in [85u32, 100, 115] {
        let row: Vec<[u8; 3]> = (80..120)
            .map(|x| {
                let p = img.get_pixel(x, y).0;
                [p[0], p[1], p[2]]
            })
            .collect();
        let mixed = row
            .iter()
            .filter(|p| **p != [255, 0, 0] && **p != [0, 0, 255])
            .count();
        // At most the anti-aliased pixel on the seam itself: a texel wrapping
        // across it would paint the whole pattern squeezed into one slice.
        assert!(mixed <= 1, "row {y}: {mixed} mixed pixels: {row:?}");
        assert_eq!(row[0], [255, 0, 0], "row {y}: left of the seam is s near 0");
        assert_eq!(
            row[39],
            [0, 0, 255],
            "row {y}: right of the seam is s near 1"
        );
    }
});

clitest!(bad_quadrics_are_errors_naming_the_record, |dir| {
    let cases = [
        (
            r#"{"sphere": {"radius": 0}, "color": [1,2,3]}"#,
            "record 1: sphere.radius 0 is not a positive number",
        ),
        (
            r#"{"sphere": {"radius": -2}, "color": [1,2,3]}"#,
            "record 1: sphere.radius -2 is not a positive number",
        ),
        (
            r#"{"sphere": {"radius": 1, "slices": 2}, "color": [1,2,3]}"#,
            "record 1: sphere.slices 2: expected a whole number from 3 to 16384",
        ),
        (
            r#"{"sphere": {"radius": 1, "stacks": 1}, "color": [1,2,3]}"#,
            "record 1: sphere.stacks 1: expected a whole number from 2",
        ),
        (
            r#"{"cylinder": {"base": 1, "top": 1, "height": 0}, "color": [1,2,3]}"#,
            "record 1: cylinder.height 0 is not a positive number",
        ),
        (
            r#"{"cone": {"base": -1, "height": 2}, "color": [1,2,3]}"#,
            "record 1: cone.base -1 is not a number >= 0",
        ),
        (
            r#"{"disk": {"inner": 3, "outer": 2}, "color": [1,2,3]}"#,
            "record 1: disk: inner radius 3 is not below outer radius 2",
        ),
        (
            r#"{"disk": {"outer": 2, "stacks": 3}, "color": [1,2,3]}"#,
            "record 1: disk.stacks: not a disk parameter",
        ),
        (
            r#"{"sphere": {"radius": "big"}, "color": [1,2,3]}"#,
            "record 1: sphere.radius: expected a number, found \"big\"",
        ),
        (
            r#"{"sphere": {"radius": 1e999}, "color": [1,2,3]}"#,
            "record 1",
        ),
        (
            r#"{"sphere": {"radius": 1}, "pattern": {"file": "p.pat", "mode": "object"}}"#,
            "record 1: sphere: pattern.mode \"object\"",
        ),
        (
            r#"{"sphere": {"radius": 1}, "transform": {"scale": 0}, "color": [1,2,3]}"#,
            "record 1: transform step 0: scale: singular",
        ),
    ];
    for (rec, want) in cases {
        dir.write(
            "s.json",
            format!("{{\"rect\": [0,0,1,1], \"color\": [0,0,0]}}\n{rec}\n"),
        );
        for tool in ["scene-render", "polyfill3"] {
            dir.cmd(tool)
                .arg("s.json")
                .assert()
                .failure()
                .stderr(predicate::str::contains(want));
        }
    }
});

clitest!(
    polyfill3_expands_a_quadric_into_uv_triangles_that_render_the_same,
    |dir| {
        dir.write("half.pat", half_pattern());
        let scene = r#"{"object": "ball", "records": [{"sphere": {"radius": 30, "slices": 8, "stacks": 4}, "color": [0,255,0], "pattern": {"file": "half.pat"}, "id": "b"}]}
{"instance": "ball", "transform": {"translate": [60, 100, 0]}}
{"cylinder": {"base": 20, "top": 10, "height": 40, "slices": 12, "stacks": 2}, "transform": [{"rotate": -60, "axis": "x"}, {"translate": [150, 100, 0]}], "color": [200,200,0]}
"#;
        dir.write("s.json", scene);
        let out = dir.cmd("polyfill3").arg("s.json").assert().success();
        let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        // The object: 8 x 4 quads less the 2 x 8 collapsed at the poles.
        let ball = lines[0]["records"].as_array().unwrap();
        assert_eq!(ball.len(), 8 * 4 * 2 - 2 * 8);
        for t in ball {
            assert_eq!(t["pattern"]["mode"], "uv");
            assert_eq!(t["id"], "b");
            assert_eq!(t["vertices"].as_array().unwrap().len(), 3);
            let uv = t["uv"].as_array().unwrap();
            assert!(uv
                .iter()
                .all(|c| (0.0..=16.0).contains(&c[0].as_f64().unwrap())));
            assert!(t.get("sphere").is_none());
        }
        assert_eq!(lines[1]["instance"], "ball");
        // The cylinder: 12 x 2 quads, flat colour, no uv.
        assert_eq!(lines.len(), 2 + 12 * 2 * 2);
        assert!(lines[2].get("uv").is_none() && lines[2].get("transform").is_none());
        dir.write("cells.ndjson", &text);
        let render = |f: &str| render_200(&dir, f);
        assert!(
            render("s.json") == render("cells.ndjson"),
            "direct and expanded renders differ"
        );
        // An animated quadric passes through unchanged; --max-polygons counts triangles.
        let spin = r#"{"sphere":{"radius":1},"transform":{"rotate":{"start":0,"step":5},"axis":"z"},"color":[1,2,3]}"#;
        dir.write("spin.json", spin);
        let out = dir.cmd("polyfill3").arg("spin.json").assert().success();
        let back: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
        assert_eq!(
            back,
            serde_json::from_str::<serde_json::Value>(spin).unwrap()
        );
        dir.cmd("polyfill3")
            .args(["--max-polygons", "60", "s.json"])
            .assert()
            .failure()
            .stderr(predicate::str::contains("48 triangles of the quadric would take the output past --max-polygons 60 (48 written so far)"));
    }
);

clitest!(
    an_instance_of_a_quadric_draws_like_the_moved_quadric,
    |dir| {
        let direct = r#"{"sphere": {"radius": 20}, "transform": [{"rotate": 30, "axis": "y"}, {"translate": [100, 100, 0]}], "color": [255,128,0]}"#;
        let placed = r#"{"object": "o", "records": [{"sphere": {"radius": 20}, "transform": {"rotate": 30, "axis": "y"}, "color": [255,128,0]}]}
{"instance": "o", "transform": {"translate": [100, 100, 0]}}"#;
        dir.write("a.json", direct);
        dir.write("b.json", placed);
        let render = |f: &str| render_200(&dir, f);
        assert!(render("a.json") == render("b.json"));
    }
);

clitest!(
    animate_writes_an_apng_whose_frames_are_the_single_frames,
    |dir| {
        let scene = crate::util::repo("fixtures/scenes/two-spheres-turn.json");
        let args = [
            "--ortho",
            "-80,80,-60,60,0,100",
            "--size",
            "160x120",
            "--frames",
            "3",
        ];
        dir.cmd("scene-render")
            .args(args)
            .args(["--animate", "--fps", "4", "-o", "turn.png"])
            .arg(&scene)
            .assert()
            .success();
        dir.cmd("scene-render")
            .args(args)
            .args(["-o", "f-%d.png"])
            .arg(&scene)
            .assert()
            .success();
        let bytes = dir.read("turn.png");
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let actl = reader.info().animation_control.unwrap();
        assert_eq!((actl.num_frames, actl.num_plays), (3, 0));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for k in 0..3 {
            let info = reader.next_frame(&mut buf).unwrap();
            let fc = reader.info().frame_control.unwrap();
            assert_eq!((fc.delay_num, fc.delay_den), (1, 4));
            let single = decode(&dir.read(&format!("f-{k}.png")));
            let rgb: Vec<u8> = single
                .pixels()
                .flat_map(|p| [p.0[0], p.0[1], p.0[2]])
                .collect();
            assert_eq!(&buf[..info.buffer_size()], &rgb[..], "frame {k}");
        }
        // The frames differ: the spheres turn.
        assert_ne!(dir.read("f-0.png"), dir.read("f-2.png"));
        // Usage errors.
        dir.cmd("scene-render")
            .args(args)
            .args(["--animate", "-o", "f-%d.png"])
            .arg(&scene)
            .assert()
            .code(2)
            .stderr(predicate::str::contains("--animate writes one file"));
        dir.cmd("scene-render")
            .args(args)
            .args(["--animate", "-o", "t.ppm"])
            .arg(&scene)
            .assert()
            .code(2)
            .stderr(predicate::str::contains("expected a .png or .apng name"));
        dir.cmd("scene-render")
            .args(args)
            .args(["--quadric-tolerance", "0", "-o", "f-%d.png"])
            .arg(&scene)
            .assert()
            .code(2)
            .stderr(predicate::str::contains("--quadric-tolerance 0"));
    }
);
