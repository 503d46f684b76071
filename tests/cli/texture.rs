//! `scene-render`'s direct texturing ("object" and "uv" patterns sampled per
//! pixel): against `polyfill3 | scene-render` and the reference, and the
//! worked examples of the OpenGL chapter (seed 002, ch. 7).

use crate::util::Dir;
use crate::util::OkStdout;

/// Largest channel difference (8-bit sRGB codes) allowed between two exact
/// renderings of the same scene: direct texturing and `polyfill3` both
/// compute exact areas in f64, so only the final rounding to 8 bits may
/// differ (a value within ~1e-13 of a rounding boundary), by one code.
const EXACT_MAX_CODES: u64 = 1;

/// A 16x16 pattern whose texel (c, r) has colour `(c + 2r) % 3` (red, blue,
/// green) and texel (3, 2) transparent: every neighbour differs from the next
/// in both directions, so a misplaced cell edge shows.
pub fn pattern3() -> String {
    pattern_from(
        |c, r| {
            if (c, r) == (3, 2) {
                None
            } else {
                Some((c + 2 * r) % 3)
            }
        },
        &[[255, 0, 0], [0, 0, 255], [0, 200, 0]],
    )
}

/// A canonical .pat text (docs/pat-format.md) from a texel → colour-index function.
pub fn pattern_from(f: impl Fn(u32, u32) -> Option<u32>, colors: &[[u8; 3]]) -> String {
    let mut s = format!("16 {}\n", colors.len());
    for (i, c) in colors.iter().enumerate() {
        s.push_str(&format!("{} {} {}\n", c[0], c[1], c[2]));
        for r in 0..16 {
            let mut w = 0u16;
            for c in 0..16 {
                w = (w << 1) | (f(c, r) == Some(i as u32)) as u16;
            }
            s.push_str(&format!("{w:04x}\n"));
        }
    }
    s
}

/// `--compare REF --image IMG --json`: the max channel error.
fn max_error(dir: &Dir, img: &str, reference: &str) -> u64 {
    let out = dir
        .cmd("scene-render")
        .args(["--image", img, "--compare", reference, "--json"])
        .ok_stdout();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    v["compare"]["largest_error"].as_u64().unwrap()
}

pub const SCENE: &str = r#"{"vertices":[[-3,-1,-2],[3,-1,-2],[3,-1,-12],[-3,-1,-12]],"color":[200,200,200],"pattern":{"file":"p.pat","incr":0.37,"rotate":10,"horz":0.3,"vert":0.6}}
{"vertices":[[-1,-0.5,-4],[1,-0.2,-4.5],[0.5,1.5,-5]],"color":[255,255,0],"pattern":{"file":"p.pat","incr":0.21}}
{"vertices":[[-2,-1,-7],[2,-1,-7],[2,2,-7],[-2,2,-7]],"color":[90,90,90]}
"#;

const CAMERA: [&str; 4] = [
    "--perspective",
    "60,1.333,0.1,100",
    "--lookat",
    "0,0.5,1,0,-0.5,-5",
];

clitest!(
    object_mode_direct_equals_polyfill3_and_the_reference,
    |dir| {
        dir.write("p.pat", pattern3());
        dir.write("s.json", SCENE);
        let render = |input: &str, extra: &[&str], out: &str| {
            dir.cmd("scene-render")
                .args(["--size", "96x72"])
                .args(CAMERA)
                .args(extra)
                .args([input, "-o", out])
                .assert()
                .success();
        };
        render("s.json", &[], "direct.png");
        render("s.json", &["--reference"], "ref.png");
        let out = dir.cmd("polyfill3").arg("s.json").ok_stdout();
        dir.write("p3.json", out);
        render("p3.json", &[], "p3.png");
        render("p3.json", &["--reference"], "p3ref.png");
        // The direct reference (texel lines as events) and the reference of the
        // exploded scene are two independent routes to the same image.
        assert!(max_error(&dir, "p3ref.png", "ref.png") <= EXACT_MAX_CODES);
        assert!(max_error(&dir, "direct.png", "ref.png") <= EXACT_MAX_CODES);
        assert!(max_error(&dir, "p3.png", "ref.png") <= EXACT_MAX_CODES);
        // Point sampling: the same texel lookup per sample, so identical up to
        // the samples that fall on a cell edge of the exploded scene.
        render("s.json", &["--aa", "ss16"], "ss.png");
        let ss = max_error(&dir, "ss.png", "ref.png");
        assert!(ss > 0 && ss < 128, "ss16 vs reference: {ss}");
    }
);

clitest!(pixel_aligned_texels_are_pixel_exact, |dir| {
    dir.write("p.pat", pattern3());
    // incr 2: every texel is a 2x2 block of pixels from the polygon's corner.
    dir.write(
        "s.json",
        r#"{"vertices":[[3,5],[43,5],[43,37],[3,37]],"color":[1,2,3],"pattern":{"file":"p.pat","incr":2}}"#,
    );
    for aa in ["exact", "none", "ss4"] {
        dir.cmd("scene-render")
            .args(["--size", "48x40", "--aa", aa, "s.json", "-o"])
            .arg(format!("{aa}.ppm"))
            .assert()
            .success();
    }
    let out = dir.cmd("polyfill3").arg("s.json").ok_stdout();
    dir.write("p3.json", out);
    dir.cmd("scene-render")
        .args(["--size", "48x40", "p3.json", "-o", "p3.ppm"])
        .assert()
        .success();
    let p3 = dir.read("p3.ppm");
    for aa in ["exact", "none", "ss4"] {
        assert!(dir.read(&format!("{aa}.ppm")) == p3, "{aa}");
    }
    // Texel (3, 2) is transparent: pixels (3 + 6, 5 + 4) .. show the black
    // background; its neighbour (2, 2), colour (2 + 4) % 3 = 0, is red.
    let px = |x: usize, y_up: usize| {
        let i = p3.len() - 48 * 40 * 3 + ((39 - y_up) * 48 + x) * 3;
        [p3[i], p3[i + 1], p3[i + 2]]
    };
    assert_eq!(px(9, 9), [0, 0, 0]);
    assert_eq!(px(10, 10), [0, 0, 0]);
    assert_eq!(px(8, 9), [255, 0, 0]);
});

/// Seed 002 (OpenGL ch. 7): a 2x2 texture on a 400x300 quad with texture
/// coordinates 0..1 shows one texel per quadrant (here 16x16 patterns
/// repeat the 2x2 block; texel units: 0..2).
pub fn quad(uv_max: f64) -> String {
    format!(
        r#"{{"vertices":[[0,0],[400,0],[400,300],[0,300]],"uv":[[0,0],[{m},0],[{m},{m}],[0,{m}]],"color":[0,0,0],"pattern":{{"file":"q.pat"}}}}"#,
        m = uv_max
    )
}

pub const QUADRANTS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];

pub fn quadrant_pattern() -> String {
    pattern_from(|c, r| Some((c % 2) + 2 * (r % 2)), &QUADRANTS)
}

pub fn pixel(img: &[u8], w: usize, h: usize, x: usize, y_up: usize) -> [u8; 3] {
    let i = img.len() - w * h * 3 + ((h - 1 - y_up) * w + x) * 3;
    [img[i], img[i + 1], img[i + 2]]
}

clitest!(seed002_two_by_two_texture_fills_the_quadrants, |dir| {
    dir.write("q.pat", quadrant_pattern());
    dir.write("s.json", quad(2.0));
    dir.cmd("scene-render")
        .args(["--size", "400x300", "s.json", "-o", "o.ppm"])
        .assert()
        .success();
    let img = dir.read("o.ppm");
    let at = |x, y| pixel(&img, 400, 300, x, y);
    for (x, y, q) in [
        (0, 0, 0),
        (199, 149, 0),
        (200, 0, 1),
        (399, 149, 1),
        (0, 150, 2),
        (199, 299, 2),
        (200, 150, 3),
        (399, 299, 3),
    ] {
        assert_eq!(at(x, y), QUADRANTS[q], "({x}, {y})");
    }
});

clitest!(
    seed002_repeat_with_coordinates_0_to_10_gives_20_by_15_blocks,
    |dir| {
        // OpenGL coordinates 0..10 on a 2-texel texture: 0..20 texels, 20 blocks
        // of 400/20 = 20 pixels across and 300/20 = 15 up.
        dir.write("q.pat", quadrant_pattern());
        dir.write("s.json", quad(20.0));
        dir.cmd("scene-render")
            .args(["--size", "400x300", "s.json", "-o", "o.ppm"])
            .assert()
            .success();
        let img = dir.read("o.ppm");
        for y in 0..300 {
            for x in 0..400 {
                let q = (x / 20) % 2 + 2 * ((y / 15) % 2);
                assert_eq!(pixel(&img, 400, 300, x, y), QUADRANTS[q], "({x}, {y})");
            }
        }
    }
);

const BANDS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]];

/// Seed 003 (XGL): "the texture appeared once in the center of the polygon
/// with a border of the original polygon visible around the sides": texture
/// coordinates -0.5..1.5 (here -8..24 texels of a 16x16 pattern whose
/// columns come in four bands of four) on a 64x64 quad, 2 pixels per texel.
fn xgl_quad(dir: &Dir, flags: &[&str]) -> Vec<u8> {
    dir.write("b.pat", pattern_from(|c, _| Some(c / 4), &BANDS));
    dir.write(
        "s.json",
        r#"{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[-8,-8],[24,-8],[24,24],[-8,24]],"color":[50,60,70],"pattern":{"file":"b.pat"}}"#,
    );
    dir.cmd("scene-render")
        .args(["--size", "64x64", "--boundary-color", "9,8,7"])
        .args(flags)
        .args(["s.json", "-o", "o.ppm"])
        .assert()
        .success();
    dir.read("o.ppm")
}

clitest!(
    seed003_quad_from_minus_half_to_one_and_a_half_per_boundary_mode,
    |dir| {
        // Pixel x = 1 is u in [-7.5, -7): cell -8. Pixel 32 is cell 8, inside.
        for (mode, outside) in [
            ("repeat", BANDS[2]),          // -8 mod 16 = 8
            ("mirror", BANDS[1]),          // reversed: column 7
            ("edge", BANDS[0]),            // the closest boundary texel, column 0
            ("clamp", [9, 8, 7]),          // the constant
            ("transparent", [50, 60, 70]), // the polygon's own colour
        ] {
            let img = xgl_quad(&dir, &["--boundary", mode]);
            assert_eq!(pixel(&img, 64, 64, 1, 32), outside, "{mode}");
            assert_eq!(pixel(&img, 64, 64, 32, 32), BANDS[2], "{mode} inside");
            // Right of the pattern: x = 62 is cell 23.
            let right = match mode {
                "repeat" => BANDS[1], // 23 mod 16 = 7
                "mirror" => BANDS[2], // 2*16 - 1 - 23 = 8
                "edge" => BANDS[3],   // column 15
                _ => outside,
            };
            assert_eq!(pixel(&img, 64, 64, 62, 32), right, "{mode} right");
        }
    }
);

clitest!(
    xgl_precedence_applies_only_where_both_coordinates_exceed,
    |dir| {
        let img = xgl_quad(&dir, &["--boundary-u", "repeat", "--boundary-v", "clamp"]);
        // Only u out: repeat.
        assert_eq!(pixel(&img, 64, 64, 1, 32), BANDS[2]);
        // Only v out: clamp.
        assert_eq!(pixel(&img, 64, 64, 32, 1), [9, 8, 7]);
        // Both out: clamp outranks wrap.
        assert_eq!(pixel(&img, 64, 64, 1, 1), [9, 8, 7]);
    }
);

clitest!(
    no_perspective_correction_interpolates_on_the_screen,
    |dir| {
        dir.write("q.pat", quadrant_pattern());
        // A floor quad receding from the eye: with perspective correction the
        // far half of the texture takes less than half the screen height.
        dir.write(
        "s.json",
        r#"{"vertices":[[-1,-1,-1],[1,-1,-1],[1,-1,-3],[-1,-1,-3]],"uv":[[0,0],[2,0],[2,2],[0,2]],"color":[0,0,0],"pattern":{"file":"q.pat"}}"#,
    );
        let rows_of_far_half = |flags: &[&str]| {
            dir.cmd("scene-render")
                .args([
                    "--size",
                    "100x100",
                    "--perspective",
                    "90,1,0.1,10",
                    "--aa",
                    "none",
                ])
                .args(flags)
                .args(["s.json", "-o", "o.ppm"])
                .assert()
                .success();
            let img = dir.read("o.ppm");
            // Column 50 is u = 1 on the boundary; column 40 is u < 1: quadrant
            // 0 (near, v < 1) or 2 (far).
            (0..100)
                .filter(|&y| pixel(&img, 100, 100, 40, y) == QUADRANTS[2])
                .count()
        };
        let correct = rows_of_far_half(&[]);
        let linear = rows_of_far_half(&["--no-perspective-correction"]);
        // Screen y = 50 - 50/|z| (fovy 90): the quad spans y = 0 (z = -1) to
        // 33.3 (z = -3). Perspective-correct, v = 1 at z = -2, y = 25: pixel
        // centres 25.5..32.5, 8 rows. PERSP_NONE puts v = 1 at the screen
        // midpoint, y = 16.7: centres 17.5..32.5, 16 rows.
        assert_eq!(correct, 8);
        assert_eq!(linear, 16);
    }
);

/// A 64x64 quad over one 16x16 pattern, 4 pixels per texel, `--compose`
/// flags given; the pattern: columns 0..8 white, 8..16 black, texel (0, 0)
/// transparent.
fn composed(dir: &Dir, flags: &[&str]) -> std::process::Output {
    dir.write(
        "w.pat",
        pattern_from(
            |c, r| match (c, r) {
                (0, 0) => None,
                (c, _) if c < 8 => Some(0),
                _ => Some(1),
            },
            &[[255, 255, 255], [0, 0, 0]],
        ),
    );
    dir.write(
        "s.json",
        r#"{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[0,0],[16,0],[16,16],[0,16]],"color":[255,128,0],"pattern":{"file":"w.pat"}}"#,
    );
    dir.cmd("scene-render")
        .args(["--size", "64x64", "--background", "0,255,0"])
        .args(flags)
        .args(["s.json", "-o", "o.ppm"])
        .output()
        .unwrap()
}

clitest!(xgl_composition_methods, |dir| {
    let at = |flags: &[&str]| {
        assert!(composed(&dir, flags).status.success(), "{flags:?}");
        let img = dir.read("o.ppm");
        // White texel, black texel, transparent texel.
        [(10, 30), (50, 30), (1, 1)].map(|(x, y)| pixel(&img, 64, 64, x, y))
    };
    let (w, k, g, c) = ([255, 255, 255], [0, 0, 0], [0, 255, 0], [255, 128, 0]);
    assert_eq!(at(&[]), [w, k, g]);
    // Modulate: white x colour = colour; black stays black.
    assert_eq!(at(&["--compose", "modulate"]), [c, k, g]);
    // XGL's example: blend between red and blue.
    assert_eq!(
        at(&[
            "--compose",
            "blend",
            "--compose-color1",
            "255,0,0",
            "--compose-color2",
            "0,0,255"
        ]),
        [[0, 0, 255], [255, 0, 0], g]
    );
    assert_eq!(
        at(&[
            "--compose",
            "blend-intrinsic",
            "--compose-color1",
            "0,0,255"
        ]),
        [[0, 0, 255], c, g]
    );
    assert_eq!(
        at(&["--compose", "decal", "--compose-color1", "9,9,9"]),
        [w, k, [9, 9, 9]]
    );
    assert_eq!(at(&["--compose", "decal-intrinsic"]), [w, k, c]);
});

clitest!(decal_on_a_pattern_without_alpha_is_an_error, |dir| {
    dir.write("q.pat", quadrant_pattern());
    dir.write("s.json", quad(2.0));
    dir.cmd("scene-render")
        .args([
            "--size",
            "40x30",
            "--compose",
            "decal",
            "s.json",
            "-o",
            "o.png",
        ])
        .assert()
        .code(1)
        .stderr(predicates::str::contains("four-channel"));
    assert_eq!(dir.files(), vec!["q.pat", "s.json"]);
});

/// Largest channel difference (8-bit codes) between `polyfill3 --uv |
/// scene-render` and `scene-render` on the same "object" scene: both fit the
/// texture map from `object_uv`'s vertex coordinates, and the "uv" numbers
/// travel through JSON as shortest round-trip decimals (exact), so the images
/// should be the same; one code leaves room for a different summation order
/// of the Newell fit through a rebuilt vertex list.
const UV_MAX_CODES: u64 = 1;

clitest!(polyfill3_uv_renders_as_the_object_scene, |dir| {
    dir.write("p.pat", pattern3());
    // SCENE's two placed polygons and plain one, a patterned rect, and an
    // object placed twice (its uv must be computed in object space, as
    // polyfill3 partitions objects).
    let extra = r#"{"rect":[-1,-1,1,1],"color":[9,9,9],"pattern":{"file":"p.pat","incr":0.3,"horz":0.25}}
{"object":"tri","records":[{"vertices":[[0,0,0],[1,0,0],[0,1,0]],"pattern":{"file":"p.pat","incr":0.13,"rotate":-20}}]}
{"instance":"tri","transform":[{"rotate":30,"axis":"y"},{"translate":[1,-0.5,-3]}]}
{"instance":"tri","transform":[{"translate":[-2,0,-6]}]}
"#;
    dir.write("s.json", format!("{SCENE}{extra}"));
    let uv = dir.cmd("polyfill3").args(["--uv", "s.json"]).ok_stdout();
    dir.write("uv.json", &uv);
    for (input, out) in [("s.json", "direct.png"), ("uv.json", "uv.png")] {
        dir.cmd("scene-render")
            .args(["--size", "96x72"])
            .args(CAMERA)
            .args([input, "-o", out])
            .assert()
            .success();
    }
    let err = max_error(&dir, "uv.png", "direct.png");
    assert!(err <= UV_MAX_CODES, "polyfill3 --uv vs direct: {err}");
    // The scene is textured at all: the plain render of uv.json without its
    // patterns differs.
    let plain: String = std::str::from_utf8(&uv)
        .unwrap()
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            if let Some(o) = v.as_object_mut() {
                o.remove("pattern");
            }
            v.to_string() + "\n"
        })
        .collect();
    dir.write("plain.json", plain);
    dir.cmd("scene-render")
        .args(["--size", "96x72"])
        .args(CAMERA)
        .args(["plain.json", "-o", "plain.png"])
        .assert()
        .success();
    assert!(max_error(&dir, "plain.png", "direct.png") > 64);
});

clitest!(polyfill3_uv_records, |dir| {
    dir.write("p.pat", pattern3());
    dir.write(
        "s.json",
        r#"{"id":1,"vertices":[[1,1],[5,1],[5,3]],"color":[1,2,3],"pattern":{"file":"p.pat","incr":0.5,"horz":1,"vert":-2,"tag":"t"}}
{"id":2,"circle":{"center":[0,0],"radius":2},"pattern":{"file":"p.pat","mode":"screen"}}
{"id":3,"vertices":[[0,0],[1,0],[0,1]],"color":[4,5,6]}
"#,
    );
    let out = dir
        .cmd("polyfill3")
        .args(["--uv", "--tolerance", "0.1", "s.json"])
        .ok_stdout();
    let recs: Vec<serde_json::Value> = std::str::from_utf8(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(recs.len(), 3);
    let abs = dir.path().join("p.pat").display().to_string();
    // Object placement as texel coordinates: u = (x - 1)/0.5 - 1,
    // v = (y - 1)/0.5 + 2; unknown pattern fields kept, placement dropped.
    assert_eq!(
        recs[0]["uv"],
        serde_json::json!([[-1.0, 2.0], [7.0, 2.0], [7.0, 6.0]])
    );
    assert_eq!(
        recs[0]["pattern"],
        serde_json::json!({"file": abs, "mode": "uv", "tag": "t"})
    );
    assert_eq!(recs[0]["color"], serde_json::json!([1, 2, 3]));
    assert_eq!(recs[0]["id"], 1);
    // A screen-mode circle: flattened, still screen mode, path absolute.
    let v = recs[1]["vertices"].as_array().unwrap();
    assert!(v.len() >= 8, "{} vertices", v.len());
    assert!(recs[1].get("circle").is_none() && recs[1].get("uv").is_none());
    assert_eq!(
        recs[1]["pattern"],
        serde_json::json!({"file": abs, "mode": "screen"})
    );
    // No pattern: unchanged but for the vertices written as [x, y, z].
    assert_eq!(
        recs[2],
        serde_json::json!({"id":3,"vertices":[[0.0,0.0,0.0],[1.0,0.0,0.0],[0.0,1.0,0.0]],"color":[4,5,6]})
    );
    // Partitioning options do not combine with --uv.
    dir.cmd("polyfill3")
        .args(["--uv", "--merge", "s.json"])
        .assert()
        .code(2);
});

// Regression (found by `bench/tradeoff.sh`'s tiles scene, shrunk to two
// records): a clipping sliver of the near tile, with 1e-12-pixel edges at
// screen position (423, 256), counted as an occluder and erased the far
// tile's texel piece behind it: one pixel 18 codes off the reference.
clitest!(
    a_sliver_of_a_near_textured_polygon_hides_nothing_behind_it,
    |dir| {
        let checker = pattern_from(|c, r| Some((c + r) % 2), &[[230, 230, 230], [20, 20, 120]]);
        dir.write("checker.pat", checker);
        dir.write(
            "two.json",
            r#"{"vertices":[[4.108396,-0.08379,-19.600469],[4.897864,0.045591,-19.600469],[4.891604,0.08379,-20.399531],[4.102136,-0.045591,-20.399531]],"color":[128,128,128],"pattern":{"file":"checker.pat","incr":0.1,"rotate":5.53946361142043,"horz":4.168}}
{"vertices":[[5.134618,-0.177706,-21.606405],[5.904278,0.040523,-21.606405],[5.865382,0.177706,-22.393595],[5.095722,-0.040523,-22.393595]],"color":[128,128,128],"pattern":{"file":"checker.pat","incr":0.1,"rotate":6.38166442426916,"horz":8.592}}
"#,
        );
        let cam = [
            "--size",
            "640x480",
            "--perspective",
            "60,1.333,0.1,100",
            "--lookat",
            "0,1.2,0,0,0,-12",
            "two.json",
        ];
        for (flags, out) in [(&["--reference"][..], "ref.png"), (&[][..], "exact.png")] {
            dir.cmd("scene-render")
                .args(cam)
                .args(flags)
                .args(["-o", out])
                .assert()
                .success();
        }
        assert!(max_error(&dir, "exact.png", "ref.png") <= EXACT_MAX_CODES);
    }
);

clitest!(a_polygon_no_larger_than_a_texel_warns_naming_incr, |dir| {
    let brick = crate::util::repo("fixtures/patterns/brick.pat");
    let face = |incr: &str| {
        format!(
            r#"{{"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "pattern": {{"file": "{}"{incr}}}}}"#,
            brick.display()
        )
    };
    // A unit cube's face at the default incr of 1: one texel.
    dir.write("cube.json", format!("{}\n{}\n", face(""), face("")));
    let want = "record 0: the polygon (area 1) is no larger than one texel of its pattern \
                (\"incr\" 1: texels 1 units wide), so it shows one texel's colour; \
                a smaller \"incr\" shows the pattern";
    dir.cmd("scene-render")
        .args([
            "--ortho",
            "-1,2,-1,2,-1,1",
            "--size",
            "32x32",
            "cube.json",
            "-o",
            "c.png",
        ])
        .assert()
        .success()
        .stderr(format!(
            "scene-render: warning: {want} (and 1 more records alike)\n"
        ));
    dir.cmd("polyfill3")
        .args(["cube.json", "-o", "cells.json"])
        .assert()
        .success()
        .stderr(format!("polyfill3: warning: {want}\n"));
    // At incr 0.125 the face is 64 texels: no warning.
    dir.write("fine.json", face(r#", "incr": 0.125"#));
    dir.cmd("scene-render")
        .args([
            "--ortho",
            "-1,2,-1,2,-1,1",
            "--size",
            "32x32",
            "fine.json",
            "-o",
            "f.png",
        ])
        .assert()
        .success()
        .stderr("");
    dir.cmd("polyfill3")
        .args(["fine.json", "-o", "cells.json"])
        .assert()
        .success()
        .stderr("");
});
