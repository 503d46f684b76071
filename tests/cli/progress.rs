//! Progress bars (issue 22): drawn on standard error under a terminal, never
//! into a pipe; and colour that obeys --color and NO_COLOR.

use crate::util::repo;
use std::process::Command;

/// Runs `tool args` with standard error on a pseudo-terminal (util-linux
/// `script`, standard output into a file so the tool's own output stays
/// out), and returns what the terminal showed.
fn under_pty(dir: &crate::util::Dir, tool: &str, args: &str) -> String {
    let bin = assert_cmd::cargo::cargo_bin(tool);
    let out = Command::new("script")
        .args(["-qec", &format!("{} {args}", bin.display()), "/dev/null"])
        .current_dir(dir.path())
        .env("TERM", "xterm")
        .env_remove("NO_COLOR")
        .output()
        .expect("util-linux `script` runs a command under a pseudo-terminal");
    assert!(out.status.success(), "{out:?}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn image() -> String {
    repo("fixtures/images/brick.png").display().to_string()
}

clitest!(pat_from_image_shows_its_phases_on_a_terminal_only, |dir| {
    let shown = under_pty(
        &dir,
        "pat-from-image",
        &format!("--size 64 --dither floyd-steinberg -o out.pat {}", image()),
    );
    assert!(shown.contains("pat-from-image: remap"), "{shown:?}");
    let piped = dir
        .cmd("pat-from-image")
        .args([
            "--size",
            "64",
            "--dither",
            "floyd-steinberg",
            "-o",
            "piped.pat",
            &image(),
        ])
        .assert()
        .success();
    assert!(piped.get_output().stderr.is_empty());
    // The bar changes no output byte.
    assert_eq!(dir.read("out.pat"), dir.read("piped.pat"));
    let quiet = under_pty(
        &dir,
        "pat-from-image",
        &format!("--no-progress --size 64 -o q.pat {}", image()),
    );
    assert!(!quiet.contains("remap"), "{quiet:?}");
});

clitest!(scene_render_shows_tiles_on_a_terminal_only, |dir| {
    dir.write(
        "s.json",
        r#"{"vertices":[[0,0,0],[60,0,0],[0,40,0]],"color":[200,10,10]}"#,
    );
    let shown = under_pty(
        &dir,
        "scene-render",
        "--reference --size 64x48 -o a.png s.json",
    );
    // The bar, not the report that --reference also prints.
    assert!(shown.contains("scene-render: reference ["), "{shown:?}");
    let piped = dir
        .cmd("scene-render")
        .args(["--reference", "--size", "64x48", "-o", "b.png", "s.json"])
        .assert()
        .success();
    let err = String::from_utf8_lossy(&piped.get_output().stderr);
    assert!(!err.contains("reference [") && !err.contains('\r'), "{err}");
    assert_eq!(dir.read("a.png"), dir.read("b.png"));
    let shown = under_pty(
        &dir,
        "scene-render",
        "--frames 3 --size 32x24 -o f%d.png s.json",
    );
    assert!(shown.contains("scene-render: frames"), "{shown:?}");
});

clitest!(polyfill3_shows_bytes_read_on_a_terminal_only, |dir| {
    let scene = repo("fixtures/scenes/demo2-fig51.json");
    let shown = under_pty(&dir, "polyfill3", &format!("-o a.json {}", scene.display()));
    assert!(shown.contains("polyfill3: reading"), "{shown:?}");
    let piped = dir
        .cmd("polyfill3")
        .args(["-o", "b.json", scene.to_str().unwrap()])
        .assert()
        .success();
    assert!(piped.get_output().stderr.is_empty());
    assert_eq!(dir.read("a.json"), dir.read("b.json"));
});

fn preview(dir: &crate::util::Dir, color: Option<&str>, no_color: Option<&str>) -> String {
    let mut c = dir.cmd("pat-info");
    c.args(["--preview", "--preview-size", "16"]);
    c.arg(repo("fixtures/patterns/brick.pat"));
    if let Some(w) = color {
        c.args(["--color", w]);
    }
    match no_color {
        Some(v) => c.env("NO_COLOR", v),
        None => c.env_remove("NO_COLOR"),
    };
    String::from_utf8(c.assert().success().get_output().stdout.clone()).unwrap()
}

clitest!(preview_colour_obeys_color_and_no_color, |dir| {
    let esc = |s: &str| s.contains('\x1b');
    assert!(
        !esc(&preview(&dir, None, None)),
        "default into a pipe: plain"
    );
    assert!(esc(&preview(&dir, Some("always"), None)));
    assert!(
        esc(&preview(&dir, Some("always"), Some("1"))),
        "always beats NO_COLOR"
    );
    assert!(!esc(&preview(&dir, Some("never"), None)));
    assert!(!esc(&preview(&dir, Some("auto"), Some("1"))));
    // The plain preview names colours as the table numbers them (from 1),
    // with a legend.
    let plain = preview(&dir, Some("never"), None);
    assert!(
        plain.contains("  1 #") && !plain.contains("  0 #"),
        "{plain}"
    );
    // Under a terminal, colour by default unless NO_COLOR is set.
    let bin = assert_cmd::cargo::cargo_bin("pat-info");
    let pat = repo("fixtures/patterns/brick.pat");
    let run = |no_color: Option<&str>| {
        let mut c = Command::new("script");
        c.args([
            "-qec",
            &format!("{} --preview {}", bin.display(), pat.display()),
            "/dev/null",
        ]);
        match no_color {
            Some(v) => c.env("NO_COLOR", v),
            None => c.env_remove("NO_COLOR"),
        };
        String::from_utf8_lossy(&c.output().unwrap().stdout).into_owned()
    };
    assert!(esc(&run(None)));
    assert!(esc(&run(Some(""))), "an empty NO_COLOR is unset");
    assert!(!esc(&run(Some("1"))));
});

clitest!(
    binary_output_named_as_the_terminal_is_refused_like_standard_output,
    |dir| {
        // Issue 18, item 3: `-o /dev/stdout` bypassed the refusal of `-`.
        dir.write(
            "s.json",
            r#"[{"rect": [1, 1, 6, 6], "color": [255, 0, 0]}]"#,
        );
        let bin = assert_cmd::cargo::cargo_bin("scene-render");
        for output in ["-", "/dev/stdout"] {
            let out = Command::new("script")
                .args([
                    "-qec",
                    &format!("{} --size 8x8 s.json -o {output}", bin.display()),
                    "/dev/null",
                ])
                .current_dir(dir.path())
                .env("TERM", "xterm")
                .output()
                .expect("util-linux `script` runs a command under a pseudo-terminal");
            let shown = String::from_utf8_lossy(&out.stdout);
            assert_eq!(out.status.code(), Some(1), "-o {output}: {shown:?}");
            assert!(
                shown.contains("refusing to write binary output to a terminal"),
                "-o {output}: {shown:?}"
            );
            assert!(
                !shown.contains("PNG"),
                "-o {output}: the picture reached the terminal"
            );
        }
        // Into a file through the same name, it writes.
        dir.cmd("scene-render")
            .args(["--size", "8x8", "s.json", "-o", "/dev/stdout"])
            .assert()
            .success();
    }
);
