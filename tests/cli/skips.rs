//! `scene-render --no-skip` (hidden, for benchmarks): turning off each
//! work-saving skip must not change one byte of the image.

/// A 16x16 pattern of 2x2 red dots every 8 texels on a transparent ground.
fn dots16() -> String {
    let mut s = String::from("16 1\n240 40 40\n");
    for row in 0..16 {
        s.push_str(if row % 8 < 2 { "c0c0\n" } else { "0000\n" });
    }
    s
}

/// A 16x16 opaque two-colour checker of 2x2 blocks.
fn opaque16() -> String {
    let mut s = String::from("16 2\n230 230 230\n");
    let rows = |even: &str, odd: &str| -> String {
        (0..16)
            .map(|r| format!("{}\n", if r % 4 < 2 { even } else { odd }))
            .collect()
    };
    s += &rows("cccc", "3333");
    s += "20 20 120\n";
    s += &rows("3333", "cccc");
    s
}

/// A receding sparse-dot floor (magnified in front, minified towards the
/// horizon), an opaque textured wall, and an opaque textured plane wholly
/// hidden behind the wall.
const SCENE: &str = r#"{"vertices": [[-60, 0, -1], [60, 0, -1], [60, 0, -120], [-60, 0, -120]], "color": [90, 90, 90], "pattern": {"file": "dots.pat", "incr": 0.5}}
{"vertices": [[-1, 0.2, -9], [1, 0.2, -9], [1, 1.2, -9], [-1, 1.2, -9]], "color": [10, 200, 10], "pattern": {"file": "opaque.pat", "incr": 0.1, "rotate": 20}}
{"vertices": [[-3, -1, -6], [3, -1, -6], [3, 2, -5], [-3, 2, -5]], "color": [128, 128, 128], "pattern": {"file": "opaque.pat", "incr": 0.05, "rotate": 7}}
"#;

fn render(dir: &crate::util::Dir, extra: &[&str], out: &str) -> Vec<u8> {
    dir.cmd("scene-render")
        .args([
            "--size",
            "96x64",
            "--perspective",
            "60,1.5,0.5,500",
            "--lookat",
            "0,1,0,0,0.6,-10",
            "--threads",
            "2",
        ])
        .args(extra)
        .args(["s.json", "-o", out])
        .assert()
        .success();
    dir.read(out)
}

clitest!(
    turning_off_any_skip_leaves_the_image_byte_identical,
    |dir| {
        dir.write("dots.pat", dots16());
        dir.write("opaque.pat", opaque16());
        dir.write("s.json", SCENE);
        for (i, flags) in [
            &["--aa", "exact"][..],
            &["--aa", "exact", "--filter", "trilinear"],
            &[
                "--aa",
                "exact",
                "--min-filter",
                "ewa",
                "--mag-filter",
                "box",
            ],
            &["--aa", "ss4", "--filter", "trilinear"],
        ]
        .into_iter()
        .enumerate()
        {
            let base = render(&dir, flags, &format!("base{i}.png"));
            for skip in [
                "hidden",
                "mip",
                "transparent",
                "magnify",
                "hidden,mip,transparent,magnify",
            ] {
                let mut f = flags.to_vec();
                f.extend(["--no-skip", skip]);
                let got = render(&dir, &f, &format!("no-{skip}{i}.png"));
                assert!(
                    got == base,
                    "--no-skip {skip} changed the image of {flags:?}"
                );
            }
        }
    }
);

clitest!(an_unknown_skip_is_an_error_that_repeats_it, |dir| {
    dir.write("s.json", "");
    dir.cmd("scene-render")
        .args(["--no-skip", "mip,blur", "s.json", "-o", "o.png"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("--no-skip mip,blur"))
        .stderr(predicates::str::contains("\"blur\""));
});
