//! `pat-tile`: orientation, formats, --pat, two routes cross-checked, failures.

use crate::util::checker16;
use crate::util::OkStdout;
use predicates::prelude::*;
use std::io::Read;

/// Decodes PNG/PPM/PAM output into RGBA rows (row 0 at the top).
fn decode(bytes: &[u8]) -> image::RgbaImage {
    patkit::io::decode_image(bytes, "out").unwrap()
}

clitest!(
    bottom_left_pixel_is_texel_0_0_and_transparency_stays_alpha,
    |dir| {
        dir.write("c.pat", checker16());
        dir.cmd("pat-tile")
            .args(["--size", "20x18", "-o", "out.png", "c.pat"])
            .assert()
            .success()
            .stdout("");
        let img = decode(&dir.read("out.png"));
        assert_eq!(img.dimensions(), (20, 18));
        // Texel (0,0) at the bottom-left is transparent; (1,0) is blue, (0,1) blue.
        assert_eq!(img.get_pixel(0, 17).0, [0, 0, 0, 0]);
        assert_eq!(img.get_pixel(1, 17).0, [0, 0, 255, 255]);
        assert_eq!(img.get_pixel(0, 16).0, [0, 0, 255, 255]);
        assert_eq!(img.get_pixel(1, 16).0, [255, 0, 0, 255]);
        // The pattern repeats every 16 pixels: pixel (16, 17) is texel (0,0) again.
        assert_eq!(img.get_pixel(16, 17).0, [0, 0, 0, 0]);
        assert_eq!(img.get_pixel(0, 1).0, [0, 0, 0, 0]);
    }
);

clitest!(scale_offset_and_background, |dir| {
    dir.write("c.pat", checker16());
    let out = dir
        .cmd("pat-tile")
        .args([
            "--size",
            "8x8",
            "--scale",
            "4",
            "--offset",
            "-1,0",
            "--background",
            "#102030",
        ])
        .args(["--format", "ppm", "c.pat"])
        .assert()
        .success();
    let img = decode(&out.get_output().stdout);
    // Lower-left 4x4 block shows texel (15, 0): (15+0) odd, blue.
    assert_eq!(img.get_pixel(0, 7).0, [0, 0, 255, 255]);
    assert_eq!(img.get_pixel(3, 4).0, [0, 0, 255, 255]);
    // The next block to the right is texel (0,0): transparent -> background.
    assert_eq!(img.get_pixel(4, 7).0, [16, 32, 48, 255]);
});

clitest!(ppm_without_background_warns_and_uses_black, |dir| {
    dir.write("c.pat", checker16());
    dir.cmd("pat-tile")
        .args(["--size", "4x4", "-o", "x.ppm", "c.pat"])
        .assert()
        .success()
        .stderr(predicate::str::starts_with(
            "pat-tile: warning: c.pat has transparent texels",
        ));
    assert!(dir.read("x.ppm").starts_with(b"P6\n4 4\n255\n"));
});

clitest!(pam_output_has_alpha_when_needed, |dir| {
    dir.write("c.pat", checker16());
    dir.cmd("pat-tile")
        .args(["--size", "3x2", "-o", "x.pam", "c.pat"])
        .assert()
        .success();
    let bytes = dir.read("x.pam");
    let header = "P7\nWIDTH 3\nHEIGHT 2\nDEPTH 4\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n";
    assert!(bytes.starts_with(header.as_bytes()));
    assert_eq!(bytes.len(), header.len() + 3 * 2 * 4);
});

clitest!(two_routes_to_the_same_image_agree, |dir| {
    // Route 1: tile the 16x16 pattern at scale 2 straight into an image.
    // Route 2: first make a 64x64 .pat at scale 2, then tile that at scale 1.
    dir.write("c.pat", checker16());
    let direct = dir
        .cmd("pat-tile")
        .args([
            "--size", "100x70", "--scale", "2", "--offset", "3,5", "--format", "pam", "c.pat",
        ])
        .ok_stdout();
    dir.cmd("pat-tile")
        .args([
            "--pat", "--size", "64x64", "--scale", "2", "--offset", "3,5", "-o", "big.pat", "c.pat",
        ])
        .assert()
        .success();
    let big = patkit::Pattern::read_file(&dir.path().join("big.pat")).unwrap();
    assert_eq!(big.size(), 64);
    let via_pat = dir
        .cmd("pat-tile")
        .args(["--size", "100x70", "--format", "pam", "big.pat"])
        .ok_stdout();
    assert_eq!(direct, via_pat);
});

clitest!(failures_leave_no_output_and_empty_stdout, |dir| {
    dir.write("bad.pat", "16 1\n");
    dir.cmd("pat-tile")
        .args(["--size", "8x8", "-o", "out.png", "bad.pat"])
        .assert()
        .code(1)
        .stdout("")
        .stderr(predicate::str::starts_with(
            "pat-tile: error: bad.pat:1: unexpected end of file",
        ));
    dir.cmd("pat-tile")
        .args(["--size", "8x8", "-o", "out.png", "missing.pat"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("missing.pat"));
    assert_eq!(dir.files(), vec!["bad.pat".to_string()]);
});

clitest!(a_long_number_in_a_pattern_is_echoed_as_written, |dir| {
    // A hostile-input review found pat-tile (and every tool but pat-info,
    // which prints its errors itself) echoing a 26-digit colour count,
    // cut to 24 characters, as `1e24...`: the user's word rewritten as a
    // number, and not even its value.
    dir.write("n.pat", format!("16 {}\n", "9".repeat(26)));
    let echo = format!("word 2 `{}...`: out of range", "9".repeat(24));
    for tool in ["pat-tile", "pat-info"] {
        dir.cmd(tool)
            .arg("n.pat")
            .assert()
            .code(1)
            .stdout("")
            .stderr(predicate::str::contains(&echo));
    }
});

clitest!(bad_sizes_and_formats_are_usage_errors, |dir| {
    dir.write("c.pat", checker16());
    for size in ["0x5", "100000x10", "60000x60000", "12", "axb"] {
        dir.cmd("pat-tile")
            .args(["--size", size, "c.pat"])
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::contains(size));
    }
    dir.cmd("pat-tile")
        .args(["--pat", "--size", "64x32", "c.pat"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--size 64x32: a pattern must be square",
        ));
    // Without --size, --pat was refused as `--size 1024x768: a pattern must
    // be square`, blaming a value the user never typed: the default.
    dir.cmd("pat-tile")
        .args(["--pat", "c.pat"])
        .assert()
        .code(2)
        .stdout("")
        .stderr(
            "pat-tile: error: --pat needs --size NxN (square, a multiple of 16 up to 4096): \
             the default size, 1024x768, is not square\n",
        );
    // The default size stays the image's.
    let png = dir.cmd("pat-tile").arg("c.pat").ok_stdout();
    assert_eq!(decode(&png).dimensions(), (1024, 768));
    // A bad output extension is a usage error, as in scene-render; no
    // extension (`/dev/null`) is PNG, as on standard output.
    // (scene-render also writes PFM; pat-tile's colours are 8-bit.)
    for (tool, formats) in [
        (&["pat-tile", "c.pat"][..], ".png, .ppm or .pam"),
        (
            &["scene-render", "empty.json"][..],
            ".png, .ppm, .pam or .pfm",
        ),
    ] {
        dir.write("empty.json", "[]");
        dir.cmd(tool[0])
            .args(["-o", "x.jpg", tool[1]])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(format!(
                "x.jpg: unknown image extension `.jpg`: expected {formats}, or give --format"
            )));
        dir.cmd(tool[0])
            .args(["-o", "/dev/null", tool[1]])
            .assert()
            .success()
            .stderr("");
    }
});

clitest!(
    a_pat_longer_than_the_bound_is_refused_before_writing,
    |dir| {
        // A hostile-input review found `pat-tile --pat --size 4096x4096` of a
        // 16x16 pattern of 65,535 colours setting out to write 344 GB. Here
        // 3,277 colours (all white, the first filling the pattern): 21 kB
        // above patkit::pat::MAX_CANONICAL_BYTES at 4096x4096.
        let mut text = String::from("16 3277\n");
        for k in 0..3277 {
            text.push_str("255 255 255\n");
            text.push_str(&if k == 0 { "ffff\n" } else { "0000\n" }.repeat(16));
        }
        dir.write("many.pat", text);
        dir.cmd("pat-tile")
            .args(["--pat", "--size", "4096x4096", "-o", "big.pat", "many.pat"])
            // Refused at once: a regression would write gigabytes first.
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stdout("")
            .stderr(
                "pat-tile: error: many.pat: the .pat would be 17180957094 bytes of text \
             (3277 colours of 4096x4096), more than the 17179869184 bytes (16 GiB) a tool \
             writes: give a smaller --size, or tile a pattern of fewer colours\n",
            );
        assert_eq!(dir.files(), vec!["many.pat".to_string()]);
    }
);

clitest!(a_background_past_the_colour_limit_names_the_file, |dir| {
    // A hostile-input review found this error without the file's name:
    // 65,535 colours (the most), texel (0,0) transparent, the first colour
    // every other texel, the others none (words written short: `0`).
    let mut text = String::from("16 65535\n0 0 0\n7fff\n");
    text.push_str(&"ffff\n".repeat(15));
    text.push_str(&"1 2 3\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n".repeat(65534));
    dir.write("full.pat", text);
    dir.cmd("pat-tile")
        .args([
            "--pat",
            "--size",
            "16x16",
            "--background",
            "9,9,9",
            "full.pat",
        ])
        .assert()
        .code(1)
        .stdout("")
        .stderr(
            "pat-tile: error: full.pat: cannot add a background colour to a pattern that \
             already has 65535 colours\n",
        );
});

#[test]
fn a_closed_output_pipe_ends_quietly() {
    let dir = crate::util::Dir::new("closed_pipe");
    dir.write("c.pat", checker16());
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("pat-tile"))
        .current_dir(dir.path())
        .args([
            "--size",
            "4096x4096",
            "--format",
            "ppm",
            "--background",
            "0,0,0",
            "c.pat",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = [0u8; 100];
    child.stdout.take().unwrap().read_exact(&mut head).unwrap();
    // The read end is dropped here, like `| head -c 100`.
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{:?}", out.status);
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    assert!(head.starts_with(b"P6\n4096 4096\n255\n"));
}

clitest!(netpbm_extensions_follow_netpbm, |dir| {
    // Issue 18, item 3: `.pnm` (netpbm's name for any of its formats) is
    // written as PPM, the colour one; `.pgm` and `.pbm` (grey, bilevel)
    // are refused as a usage error naming the converter, not written as
    // PPM or refused as unknown.
    dir.write("p.pat", crate::util::checker16());
    for tool in ["pat-tile", "scene-render"] {
        let input = if tool == "pat-tile" {
            "p.pat"
        } else {
            "s.json"
        };
        dir.write(
            "s.json",
            r#"{"vertices":[[0,0],[9,0],[9,9]],"color":[200,10,10]}"#,
        );
        dir.cmd(tool)
            .args([input, "--background", "0,0,0", "-o", "x.pnm"])
            .assert()
            .success();
        assert!(dir.read("x.pnm").starts_with(b"P6\n"), "{tool}");
        for (ext, says) in [("pgm", "ppmtopgm"), ("pbm", "pamditherbw")] {
            dir.cmd(tool)
                .args([input, "-o", &format!("x.{ext}")])
                .assert()
                .code(2)
                .stderr(predicates::str::contains(format!(
                    "x.{ext}: `.{ext}` is netpbm's"
                )))
                .stderr(predicates::str::contains(says));
            assert!(!dir.path().join(format!("x.{ext}")).exists());
        }
    }
});
