//! `scene-render --filter` and friends: the seeds' worked examples as golden
//! images (seed 002, OpenGL ch. 7; seed 003, XGL), flag errors, and the
//! invariants (threads, the reference) that the filters must keep.

use crate::texture::{pattern3, pattern_from, pixel, quad, quadrant_pattern, QUADRANTS, SCENE};
use crate::util::OkStdout;
use patkit::math;

/// sRGB decoding and encoding (IEC 61966-2-1), for expected values.
fn to_linear(c: u8) -> f64 {
    let c = c as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        math::powf((c + 0.055) / 1.055, 2.4)
    }
}

fn to_code(l: f64) -> u8 {
    let c = if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * math::powf(l, 1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

/// The renderer keeps linear light in f32 before encoding: a value within
/// ~1e-7 of a rounding boundary may encode one code apart from the f64
/// expectation.
const F32_CODES: i32 = 1;

fn close(got: [u8; 3], want: [u8; 3]) -> bool {
    got.iter()
        .zip(want)
        .all(|(&g, w)| (g as i32 - w as i32).abs() <= F32_CODES)
}

clitest!(
    seed002_linear_filtering_of_the_2x2_texture_mixes_quadrants_in_linear_light,
    |dir| {
        // Seed 002's "linear interpolation" example: the 2x2 texture on the
        // 400x300 quad, GL_LINEAR. Texel centres lie at the quadrant centres
        // (100, 75), (300, 75), ...; between them the colour is the bilinear
        // mix, and at the quad's centre the mean of all four.
        dir.write("q.pat", quadrant_pattern());
        dir.write("s.json", quad(2.0));
        dir.cmd("scene-render")
            .args([
                "--size", "400x300", "--filter", "bilinear", "s.json", "-o", "o.ppm",
            ])
            .assert()
            .success();
        let img = dir.read("o.ppm");
        let expect = |x: usize, y: usize| -> [u8; 3] {
            // u = (x + 0.5) / 200 texels; centres at k + 0.5; texel k mod 2
            // (the 16x16 pattern repeats the 2x2 block).
            let a = (x as f64 + 0.5) / 200.0 - 0.5;
            let b = (y as f64 + 0.5) / 150.0 - 0.5;
            let (i, j) = (a.floor(), b.floor());
            let (fx, fy) = (a - i, b - j);
            let q = |di: f64, dj: f64| {
                let c = ((i + di).rem_euclid(2.0) + 2.0 * (j + dj).rem_euclid(2.0)) as usize;
                QUADRANTS[c].map(to_linear)
            };
            let (c00, c10, c01, c11) = (q(0., 0.), q(1., 0.), q(0., 1.), q(1., 1.));
            std::array::from_fn(|ch| {
                to_code(
                    c00[ch] * (1.0 - fx) * (1.0 - fy)
                        + c10[ch] * fx * (1.0 - fy)
                        + c01[ch] * (1.0 - fx) * fy
                        + c11[ch] * fx * fy,
                )
            })
        };
        for (x, y) in [
            (100, 75),
            (300, 225),
            (0, 0),
            (399, 299),
            (150, 100),
            (250, 40),
            (199, 149),
            (200, 150),
            (37, 263),
        ] {
            let got = pixel(&img, 400, 300, x, y);
            assert!(
                close(got, expect(x, y)),
                "({x}, {y}): {got:?} vs {:?}",
                expect(x, y)
            );
        }
        // A quarter texel-pixel from the red texel's centre (100, 75), the
        // other texels weigh in: [254, 8, 11], not pure red.
        assert_eq!(pixel(&img, 400, 300, 100, 75), [254, 8, 11]);
        // Around the centre: the linear-light mean of red, green, blue and
        // white is (0.5, 0.5, 0.5), code 188, to within the pixels' quarter
        // texel offset from it (weights 0.5 +- 0.0025).
        let mean = to_code(0.5);
        assert_eq!(mean, 188);
        for (x, y) in [(199, 149), (200, 149), (199, 150), (200, 150)] {
            let got = pixel(&img, 400, 300, x, y);
            assert!(close(got, [mean; 3]), "({x}, {y}): {got:?}");
        }
    }
);

clitest!(
    seed002_clamp_with_coordinates_0_to_10_stretches_the_edge_texels,
    |dir| {
        // Seed 002's GL_CLAMP example: texture coordinates 0..10 over the
        // 400x300 quad, the 2x2 texture clamped: it shows once in the lower
        // left tenth (40x30 pixels, texels of 20x15) and its edge texels
        // fill the rest. Here the 2x2 texture is a 16x16 pattern of 8x8
        // quadrants (the same image under nearest and box filtering) with
        // coordinates 0..160 texels, and XGL's edge boundary (GL_CLAMP under
        // GL_NEAREST is clamp to edge).
        dir.write(
            "k.pat",
            pattern_from(|c, r| Some(c / 8 + 2 * (r / 8)), &QUADRANTS),
        );
        dir.write(
            "s.json",
            r#"{"vertices":[[0,0],[400,0],[400,300],[0,300]],"uv":[[0,0],[160,0],[160,160],[0,160]],"color":[0,0,0],"pattern":{"file":"k.pat"}}"#,
        );
        for filter in ["box", "point"] {
            dir.cmd("scene-render")
                .args([
                    "--size",
                    "400x300",
                    "--boundary",
                    "edge",
                    "--filter",
                    filter,
                ])
                .args(["s.json", "-o", "o.ppm"])
                .assert()
                .success();
            let img = dir.read("o.ppm");
            for y in 0..300 {
                for x in 0..400 {
                    let q = (x >= 20) as usize + 2 * (y >= 15) as usize;
                    assert_eq!(
                        pixel(&img, 400, 300, x, y),
                        QUADRANTS[q],
                        "{filter} ({x}, {y})"
                    );
                }
            }
        }
    }
);

clitest!(
    seed002_one_dimensional_texture_on_a_line_gives_four_equal_runs,
    |dir| {
        // Seed 002's 1-D example: texels red, green, blue, cyan; a line of
        // width 5 from (-40,-30) to (40,30) under gluOrtho2D(-80,80,-60,60)
        // in an 800x600 window, s from 0 to 1: in pixels from (200,150) to
        // (600,450), each colour over a quarter, 100 pixel columns. GL widens
        // an x-major line vertically, so the line is the parallelogram 5
        // pixels tall around it; the 1-D texture is a pattern of four bands
        // of four columns, u from 0 to 16.
        const LINE: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [0, 255, 255]];
        dir.write("l.pat", pattern_from(|c, _| Some(c / 4), &LINE));
        dir.write(
            "s.json",
            r#"{"vertices":[[200,147.5],[600,447.5],[600,452.5],[200,152.5]],"uv":[[0,0],[16,0],[16,1],[0,1]],"color":[0,0,0],"pattern":{"file":"l.pat"}}"#,
        );
        for filter in ["box", "point"] {
            dir.cmd("scene-render")
                .args([
                    "--size", "800x600", "--filter", filter, "s.json", "-o", "o.ppm",
                ])
                .assert()
                .success();
            let img = dir.read("o.ppm");
            let mut runs = [0usize; 4];
            for x in 200..600 {
                // The pixel row through the line's centre at this column lies
                // wholly inside the 5-pixel-tall parallelogram.
                let y = (150.0 + 0.75 * (x as f64 + 0.5 - 200.0)).floor() as usize;
                let want = LINE[(x - 200) / 100];
                let got = pixel(&img, 800, 600, x, y);
                assert_eq!(got, want, "{filter} ({x}, {y})");
                runs[(x - 200) / 100] += 1;
            }
            assert_eq!(runs, [100; 4]);
            // Outside the line: the background.
            assert_eq!(pixel(&img, 800, 600, 400, 200), [0, 0, 0]);
        }
    }
);

clitest!(
    seed003_quad_under_bilinear_keeps_each_boundary_mode,
    |dir| {
        // Seed 003's quad, u and v from -0.5 to 1.5 of the pattern (-8..24
        // texels of a 16x16 pattern of four 4-column bands), 2 pixels per
        // texel, now bilinear: away from band edges (pixel x = 5: u = -5.25,
        // between texel centres -6.5 and -5.5, both in one band's image) the
        // boundary mode decides as under the box filter.
        const BANDS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]];
        dir.write("b.pat", pattern_from(|c, _| Some(c / 4), &BANDS));
        dir.write(
            "s.json",
            r#"{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[-8,-8],[24,-8],[24,24],[-8,24]],"color":[50,60,70],"pattern":{"file":"b.pat"}}"#,
        );
        for (mode, want) in [
            ("repeat", BANDS[2]),          // -6, -5 mod 16 = 10, 11
            ("mirror", BANDS[1]),          // 5, 4
            ("edge", BANDS[0]),            // column 0
            ("clamp", [9, 8, 7]),          // the constant
            ("transparent", [50, 60, 70]), // the polygon's own colour
        ] {
            dir.cmd("scene-render")
                .args([
                    "--size",
                    "64x64",
                    "--boundary-color",
                    "9,8,7",
                    "--filter",
                    "bilinear",
                ])
                .args(["--boundary", mode, "s.json", "-o", "o.ppm"])
                .assert()
                .success();
            let img = dir.read("o.ppm");
            assert_eq!(pixel(&img, 64, 64, 5, 32), want, "{mode}");
            // Inside, between the centres of columns 9 and 10 (band 2).
            assert_eq!(pixel(&img, 64, 64, 36, 32), BANDS[2], "{mode} inside");
        }
    }
);

clitest!(mip_filters_as_mag_filter_are_refused, |dir| {
    dir.write("q.pat", quadrant_pattern());
    dir.write("s.json", quad(2.0));
    for f in ["mip-point", "trilinear", "ewa"] {
        dir.cmd("scene-render")
            .args(["--mag-filter", f, "s.json", "-o", "o.png"])
            .assert()
            .code(2)
            .stderr(predicates::str::contains(format!("--mag-filter {f}")))
            .stderr(predicates::str::contains("base level"));
    }
    assert!(!dir.files().contains(&"o.png".to_string()));
});

clitest!(bad_lod_bias_and_filter_names_are_usage_errors, |dir| {
    dir.write("q.pat", quadrant_pattern());
    dir.write("s.json", quad(2.0));
    for bias in ["nan", "inf", "-17", "1e300"] {
        dir.cmd("scene-render")
            .args(["--lod-bias", bias, "s.json", "-o", "o.png"])
            .assert()
            .code(2)
            .stderr(predicates::str::contains("--lod-bias"));
    }
    dir.cmd("scene-render")
        .args([
            "--lod-bias",
            "-1.5",
            "--filter",
            "trilinear",
            "s.json",
            "-o",
            "o.png",
        ])
        .assert()
        .success();
    for (flag, bad) in [
        ("--filter", "cubic"),
        ("--min-filter", "linear"),
        ("--mip-build", "gauss"),
    ] {
        dir.cmd("scene-render")
            .args([flag, bad, "s.json", "-o", "x.png"])
            .assert()
            .code(2)
            .stderr(predicates::str::contains(bad));
    }
});

/// The receding scene of `texture.rs` (minified towards the back, with a
/// transparent texel), rendered with `flags`.
fn receding(dir: &crate::util::Dir, flags: &[&str], out: &str) -> Vec<u8> {
    dir.write("p.pat", pattern3());
    dir.write("s.json", SCENE);
    dir.cmd("scene-render")
        .args(["--size", "96x72", "--perspective", "60,1.333,0.1,100"])
        .args(["--lookat", "0,0.5,1,0,-0.5,-5"])
        .args(flags)
        .args(["s.json", "-o", out])
        .assert()
        .success();
    dir.read(out)
}

clitest!(every_filter_is_byte_identical_for_any_thread_count, |dir| {
    for filter in [
        "point",
        "bilinear",
        "mip-point",
        "mip-bilinear",
        "mip-point-linear",
        "trilinear",
        "ewa",
    ] {
        for aa in ["exact", "ss4", "none"] {
            let one = receding(
                &dir,
                &["--filter", filter, "--aa", aa, "--threads", "1"],
                "a.ppm",
            );
            let three = receding(
                &dir,
                &["--filter", filter, "--aa", aa, "--threads", "3"],
                "b.ppm",
            );
            assert!(one == three, "{filter} --aa {aa}");
        }
    }
});

clitest!(the_reference_ignores_the_filters, |dir| {
    let plain = receding(&dir, &["--reference"], "a.ppm");
    let filtered = receding(
        &dir,
        &[
            "--reference",
            "--filter",
            "ewa",
            "--lod-bias",
            "2",
            "--mip-build",
            "box",
        ],
        "b.ppm",
    );
    assert!(plain == filtered);
});

clitest!(min_and_mag_filters_are_chosen_per_pixel, |dir| {
    // The receding scene, minified at the back and magnified at the front:
    // --min-filter trilinear with the box for magnification equals the box
    // where texels are larger than pixels, and differs where they are not.
    let boxed = receding(&dir, &["--aa", "none"], "a.ppm");
    let mixed = receding(
        &dir,
        &["--aa", "none", "--min-filter", "trilinear"],
        "b.ppm",
    );
    let all = receding(&dir, &["--aa", "none", "--filter", "trilinear"], "c.ppm");
    assert!(boxed != mixed && mixed != all);
    let n = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    // Each change touches only its part of the image.
    assert!(
        n(&boxed, &mixed) < n(&boxed, &all),
        "{} {}",
        n(&boxed, &mixed),
        n(&boxed, &all)
    );
});

clitest!(
    mip_filters_work_on_a_non_power_of_two_pattern_under_every_boundary,
    |dir| {
        // A 48x48 checker of single texels (levels 24, 12, 6, 3, 1) on the
        // receding floor, minified to many texels per pixel at the back:
        // under repeat and mirror the far floor averages to the checker's
        // linear mean, code 188 for black and white, whichever build; the
        // other boundaries must simply render.
        let mut pat = String::from("48 2\n0 0 0\n");
        let rows = |odd: bool| {
            (0..48)
                .map(|r| {
                    let w = if (r % 2 == 0) ^ odd { "aaaa" } else { "5555" };
                    format!("{w} {w} {w}\n")
                })
                .collect::<String>()
        };
        pat += &rows(false);
        pat += "255 255 255\n";
        pat += &rows(true);
        dir.write("c.pat", pat);
        dir.write(
            "s.json",
            r#"{"vertices":[[-400,-1,-1],[400,-1,-1],[400,-1,-801],[-400,-1,-801]],"uv":[[0,0],[4800,0],[4800,4800],[0,4800]],"color":[255,0,0],"pattern":{"file":"c.pat"}}"#,
        );
        let runs = [
            ("repeat", "mitchell", "trilinear"),
            ("repeat", "box", "ewa"),
            ("repeat", "box", "mip-point-linear"),
            ("mirror", "mitchell", "trilinear"),
            ("edge", "mitchell", "trilinear"),
            ("clamp", "box", "trilinear"),
            ("transparent", "mitchell", "ewa"),
        ];
        for (boundary, build, filter) in runs {
            {
                {
                    dir.cmd("scene-render")
                        .args(["--size", "64x48", "--perspective", "60,1.333,0.5,1000"])
                        .args(["--lookat", "0,0,0,0,-0.05,-1", "--filter", filter])
                        .args(["--boundary", boundary, "--mip-build", build])
                        .args(["s.json", "-o", "o.ppm"])
                        .assert()
                        .success();
                    let img = dir.read("o.ppm");
                    // Row 26 from the bottom: just below the horizon, tens
                    // of texels per pixel, inside the pattern's 100 copies.
                    let p = pixel(&img, 64, 48, 32, 22);
                    if boundary == "repeat" || boundary == "mirror" {
                        assert!(
                            p.iter().all(|&c| (c as i32 - 188).abs() <= 3),
                            "{boundary} {build} {filter}: {p:?}"
                        );
                    }
                }
            }
        }
    }
);

// A record's own texture state: its "pattern" keys "filter", "min_filter",
// "mag_filter", "lod_bias", "boundary", "boundary_u", "boundary_v",
// "boundary_color", "compose", "compose_color1" and "compose_color2" override
// the flags of the same names for that record (issue 19).

/// Two uv quads side by side on a 64x32 image, 6 pixels apart (so that no
/// pixel sees both): 48 texels over 28 pixels (minified, and reaching outside
/// the 16x16 pattern on every side, with its transparent texel). `left` and
/// `right` are extra keys for each record's "pattern" (`,"k":v` or empty).
fn two_quads(left: &str, right: &str) -> String {
    let quad = |x0: u32, extra: &str| {
        format!(
            r#"{{"vertices":[[{x0},2],[{x1},2],[{x1},30],[{x0},30]],"uv":[[-8,-8],[40,-8],[40,40],[-8,40]],"color":[100,200,50],"pattern":{{"file":"p.pat"{extra}}}}}"#,
            x1 = x0 + 28
        )
    };
    format!("{}\n{}\n", quad(2, left), quad(36, right))
}

/// `scene` rendered at 64x32 with `flags`, as PPM bytes.
fn render_two(dir: &crate::util::Dir, scene: &str, flags: &[&str]) -> Vec<u8> {
    dir.write("p.pat", pattern3());
    dir.write("two.json", scene);
    dir.cmd("scene-render")
        .args(["--size", "64x32", "--format", "ppm"])
        .args(flags)
        .args(["two.json", "-o", "-"])
        .ok_stdout()
}

/// One key's case: (the record's `,"key":value`, the flags that mean the
/// same, the flags every rendering of the case takes, a flag that
/// contradicts the key).
type StateCase = (
    &'static str,
    &'static [&'static str],
    &'static [&'static str],
    &'static [&'static str],
);

const STATE_CASES: [StateCase; 11] = [
    (
        r#","filter":"trilinear""#,
        &["--filter", "trilinear"],
        &[],
        &["--filter", "point"],
    ),
    (
        r#","min_filter":"ewa""#,
        &["--min-filter", "ewa"],
        &[],
        &["--min-filter", "point"],
    ),
    (
        r#","mag_filter":"point""#,
        &["--mag-filter", "point"],
        &["--lod-bias", "-4"],
        &["--mag-filter", "bilinear"],
    ),
    (
        r#","lod_bias":1.5"#,
        &["--lod-bias", "1.5"],
        &["--filter", "trilinear"],
        &["--lod-bias", "-2"],
    ),
    (
        r#","boundary":"clamp""#,
        &["--boundary", "clamp"],
        &[],
        &["--boundary", "mirror"],
    ),
    (
        r#","boundary_u":"edge""#,
        &["--boundary-u", "edge"],
        &[],
        &["--boundary-u", "transparent"],
    ),
    (
        r#","boundary_v":"mirror""#,
        &["--boundary-v", "mirror"],
        &[],
        &["--boundary-v", "clamp"],
    ),
    (
        r#","boundary_color":[0,255,255]"#,
        &["--boundary-color", "0,255,255"],
        &["--boundary", "clamp"],
        &["--boundary-color", "#ff00ff"],
    ),
    (
        r#","compose":"modulate""#,
        &["--compose", "modulate"],
        &[],
        &["--compose", "blend"],
    ),
    (
        r##","compose_color1":"#804000""##,
        &["--compose-color1", "128,64,0"],
        &["--compose", "blend"],
        &["--compose-color1", "9,9,9"],
    ),
    (
        r#","compose_color2":[10,20,30]"#,
        &["--compose-color2", "10,20,30"],
        &["--compose", "blend"],
        &["--compose-color2", "#ffffff"],
    ),
];

clitest!(
    a_records_pattern_key_renders_as_its_flag_and_overrides_it,
    |dir| {
        for (key, flag, base, contra) in STATE_CASES {
            let plain = two_quads("", "");
            let keyed = two_quads(key, key);
            let by_flag = render_two(&dir, &plain, &[base, flag].concat());
            let by_key = render_two(&dir, &keyed, base);
            assert!(
                by_key == by_flag,
                "{key}: the record's key differs from {flag:?}"
            );
            let default = render_two(&dir, &plain, base);
            assert!(
                by_key != default,
                "{key}: no visible effect in the test scene"
            );
            let overridden = render_two(&dir, &keyed, &[base, contra].concat());
            assert!(
                overridden == by_flag,
                "{key}: {contra:?} won over the record"
            );
        }
    }
);

clitest!(two_records_keep_their_own_texture_state, |dir| {
    // Left trilinear with clamp, right modulate with mirror: each half must
    // be what its flags give the whole scene.
    let mixed = render_two(
        &dir,
        &two_quads(
            r#","filter":"trilinear","boundary":"clamp""#,
            r#","compose":"modulate","boundary":"mirror""#,
        ),
        &[],
    );
    let plain = two_quads("", "");
    let left = render_two(
        &dir,
        &plain,
        &["--filter", "trilinear", "--boundary", "clamp"],
    );
    let right = render_two(
        &dir,
        &plain,
        &["--compose", "modulate", "--boundary", "mirror"],
    );
    let header = mixed.len() - 64 * 32 * 3;
    let half = |img: &[u8], right_half: bool| -> Vec<u8> {
        (0..32)
            .flat_map(|y| {
                let row = header + y * 64 * 3 + if right_half { 32 * 3 } else { 0 };
                img[row..row + 32 * 3].to_vec()
            })
            .collect()
    };
    assert!(half(&mixed, false) == half(&left, false));
    assert!(half(&mixed, true) == half(&right, true));
    assert!(
        half(&left, true) != half(&right, true),
        "the states must differ"
    );
});

clitest!(
    an_unknown_key_in_pattern_or_stripe_warns_once_per_run,
    |dir| {
        dir.write("p.pat", pattern3());
        let mut scene = String::new();
        for i in 0..50 {
            scene.push_str(&format!(
            r#"{{"vertices":[[{i},0],[{j},0],[{j},1]],"color":[1,2,3],"own":1,"pattern":{{"file":"p.pat","boundry":"clamp","incr":0.5}}}}"#,
            j = i + 1
        ));
            scene.push('\n');
        }
        dir.write("s.json", &scene);
        let want = r#"warning: record 0: unknown key "boundry" in "pattern" (known: file, mode, incr, rotate, horz, vert, filter, min_filter, mag_filter, lod_bias, boundary, boundary_u, boundary_v, boundary_color, compose, compose_color1, compose_color2)"#;
        for tool in ["scene-render", "polyfill3"] {
            let out = dir
                .cmd(tool)
                .args(["s.json", "-o", "out.ppm"])
                .assert()
                .success();
            let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
            assert_eq!(err.matches("unknown key").count(), 1, "{tool}: {err}");
            assert!(err.contains(&format!("{tool}: {want}")), "{tool}: {err}");
            // The record's own unknown field ("own") passes silently.
            assert!(!err.contains("\"own\""), "{tool}: {err}");
        }
        // polyfill3 forwards stripes without reading them: a misspelt key warns
        // there (scene-render and pat-info refuse it).
        dir.write(
        "st.json",
        r#"{"vertices":[[0,0],[1,0],[1,1]],"stripe":{"map":"m.map","spacing":1,"yaw":0,"spaceing":2}}"#,
    );
        dir.cmd("polyfill3")
        .args(["st.json", "-o", "out"])
        .assert()
        .success()
        .stderr(predicates::str::contains(
            r#"polyfill3: warning: record 0: unknown key "spaceing" in "stripe" (known: map, spacing,"#,
        ));
        // pat-info --record warns where it reads the record.
        dir.write(
        "pi.json",
        r#"{"vertices":[[0,0],[1,0],[1,1]],"color":[1,1,1],"pattern":{"file":"p.pat","compse":"blend"}}"#,
    );
        dir.cmd("pat-info")
            .args(["--record", "0", "pi.json"])
            .assert()
            .failure()
            .stderr(predicates::str::contains(
                r#"pat-info: warning: record 0: unknown key "compse" in "pattern""#,
            ));
    }
);

clitest!(
    bad_texture_state_values_name_the_record_and_the_value,
    |dir| {
        dir.write("p.pat", pattern3());
        let cases = [
        (
            r#""filter":"trilinar""#,
            "s.json: record 1: pattern.filter: `trilinar` is not a filter: expected box, point, bilinear, mip-point, mip-bilinear, mip-point-linear, trilinear, ewa",
        ),
        (
            r#""boundary":"wrap""#,
            "s.json: record 1: pattern.boundary: `wrap` is not a boundary condition: expected repeat, transparent, clamp, mirror, edge",
        ),
        (
            r#""compose":"add""#,
            "s.json: record 1: pattern.compose: `add` is not a composition method: expected replace, modulate, blend, blend-intrinsic, decal, decal-intrinsic",
        ),
        (
            r#""lod_bias":"high""#,
            "s.json: record 1: pattern.lod_bias: expected a number of MIP levels from -16 to 16, found \"high\"",
        ),
        (
            r#""mag_filter":"trilinear""#,
            "s.json: record 1: pattern.mag_filter: `trilinear`: magnification samples the base level only",
        ),
        (
            r#""boundary_color":"teal""#,
            "s.json: record 1: pattern.boundary_color: expected [r,g,b] with each 0..=255, \"r,g,b\" or \"#rrggbb\", found \"teal\"",
        ),
    ];
        for (key, message) in cases {
            dir.write(
            "s.json",
            format!(
                "{}{{\"vertices\":[[0,0],[4,0],[4,4]],\"color\":[1,2,3],\"pattern\":{{\"file\":\"p.pat\",{key}}}}}\n",
                r#"{"vertices":[[0,0],[1,0],[1,1]],"color":[1,2,3]}"#.to_string() + "\n"
            ),
        );
            for tool in ["scene-render", "polyfill3"] {
                dir.cmd(tool)
                    .args(["s.json", "-o", "out.ppm"])
                    .assert()
                    .code(1)
                    .stderr(predicates::str::contains(format!(
                        "{tool}: error: {message}"
                    )));
            }
        }
        // Decal of the record, with a pattern without transparent texels: the
        // key, not --compose, is named.
        dir.write("q.pat", quadrant_pattern());
        dir.write(
        "d.json",
        r#"{"vertices":[[0,0],[4,0],[4,4]],"color":[1,2,3],"pattern":{"file":"q.pat","compose":"decal"}}"#,
    );
        dir.cmd("scene-render")
        .args(["d.json", "-o", "out.ppm"])
        .assert()
        .code(1)
        .stderr(predicates::str::contains(
            "d.json: record 0: pattern.compose decal: XGL's decal methods need a four-channel map",
        ));
    }
);

clitest!(
    polyfill3_forwards_the_texture_state_to_scene_render,
    |dir| {
        let scene = two_quads(
            r#","filter":"trilinear","lod_bias":0.5,"boundary":"clamp","boundary_color":[0,255,255]"#,
            r#","compose":"blend","compose_color1":[255,0,255],"boundary_u":"mirror""#,
        );
        let direct = render_two(&dir, &scene, &[]);
        // uv records: written whole with --uv, passed through without.
        for flags in [&["--uv"][..], &[]] {
            let out = dir.cmd("polyfill3").args(flags).arg("two.json").ok_stdout();
            let text = String::from_utf8(out.clone()).unwrap();
            assert!(text.contains(r#""compose":"blend""#), "{text}");
            dir.write("p3.json", out);
            let via = dir
                .cmd("scene-render")
                .args(["--size", "64x32", "--format", "ppm", "p3.json", "-o", "-"])
                .ok_stdout();
            assert!(via == direct, "polyfill3 {flags:?} | scene-render");
        }
        // An object-mode record is cut into flat texel polygons: its state is
        // dropped, with one warning.
        dir.write(
        "o.json",
        r#"{"vertices":[[0,0],[4,0],[4,4]],"color":[1,2,3],"pattern":{"file":"p.pat","compose":"modulate","filter":"ewa"}}
{"vertices":[[0,0],[4,0],[4,4]],"color":[1,2,3],"pattern":{"file":"p.pat","compose":"modulate"}}
"#,
    );
        let out = dir.cmd("polyfill3").arg("o.json").assert().success();
        let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
        assert_eq!(err.matches("do not apply").count(), 1, "{err}");
        assert!(
        err.contains(r#"polyfill3: warning: record 0: "pattern" keys "compose", "filter" do not apply to texel polygons"#),
        "{err}"
    );
    }
);

clitest!(
    the_documented_texture_state_example_renders_as_its_flags,
    |dir| {
        // docs/rendering.md, "Texture state per record" (and the README's
        // shorter form): the record's keys against the same flags.
        let brick = crate::util::repo("fixtures/patterns/brick.pat");
        std::fs::copy(&brick, dir.path().join("brick.pat")).unwrap();
        let record = |state: &str| {
            format!(
                r#"{{"vertices": [[0,0,0],[8,0,0],[8,8,0]], "color": [200,160,120],
 "pattern": {{"file": "brick.pat", "mode": "object", "incr": 0.5{state}}}}}"#
            )
        };
        let render = |scene: &str, flags: &[&str]| {
            dir.write("doc.json", scene);
            dir.cmd("scene-render")
                .args([
                    "--size",
                    "48x48",
                    "--ortho2",
                    "-1,9,-1,9",
                    "--format",
                    "ppm",
                ])
                .args(flags)
                .args(["doc.json", "-o", "-"])
                .ok_stdout()
        };
        let keyed = render(
            &record(
                r#", "filter": "trilinear", "lod_bias": 0.5, "boundary": "clamp",
             "boundary_color": [0,0,0], "compose": "modulate""#,
            ),
            &[],
        );
        let flagged = render(
            &record(""),
            &[
                "--filter",
                "trilinear",
                "--lod-bias",
                "0.5",
                "--boundary",
                "clamp",
                "--boundary-color",
                "0,0,0",
                "--compose",
                "modulate",
            ],
        );
        assert!(keyed == flagged);
        assert!(keyed != render(&record(""), &[]));
    }
);
