//! `scene-render` output deeper than 8 bits (issue 15, item 5): 16-bit PNG,
//! PPM and PAM (sRGB), PFM (linear float), chosen by `--depth` and the
//! extension or `--format`; `--compare` and `--image` read them back.

use crate::util::Dir;

/// A small scene with anti-aliased edges in odd colours, a concave polygon
/// and dark shades (where 16-bit codes are narrowest in linear light).
const SCENE: &str = r#"[
  {"vertices": [[1.3, 2.1], [61.7, 5.9], [30.2, 45.6]], "color": [200, 40, 7]},
  {"vertices": [[10.5, 40.25], [50.1, 30.3], [55.9, 46.7], [33, 38], [12.2, 47.1]], "color": [3, 120, 201]},
  {"circle": {"center": [40, 20], "radius": 9.7}, "color": [1, 2, 3]},
  {"rect": [2.5, 25.5, 9.25, 31.75], "color": [255, 254, 128]}
]"#;

const SIZE: &str = "64x48";

/// Renders `SCENE` to `out` with `extra` flags.
fn render(dir: &Dir, out: &str, extra: &[&str]) {
    dir.write("s.json", SCENE);
    dir.cmd("scene-render")
        .args([
            "--size",
            SIZE,
            "--background",
            "17,34,51",
            "s.json",
            "-o",
            out,
        ])
        .args(extra)
        .assert()
        .success()
        .stderr("");
}

/// `scene-render --image IMAGE --compare REF --json`'s "compare" object.
fn compare(dir: &Dir, image: &str, reference: &str) -> serde_json::Value {
    let out = dir
        .cmd("scene-render")
        .args(["--image", image, "--compare", reference, "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{image} against {reference}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["compare"].clone()
}

/// A PFM's samples, row 0 at the top, read here independently of the
/// library (the format: `PF`, width, height, scale, rows bottom to top).
fn read_pfm(bytes: &[u8]) -> (usize, usize, Vec<f32>) {
    let mut fields = Vec::new();
    let mut at = 0;
    for _ in 0..4 {
        while bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        fields.push(std::str::from_utf8(&bytes[start..at]).unwrap().to_string());
    }
    assert_eq!(fields[0], "PF");
    assert_eq!(fields[3], "-1.0", "little-endian, as written");
    let (w, h): (usize, usize) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let data = &bytes[at + 1..];
    assert_eq!(data.len(), w * h * 12);
    let mut out = vec![0f32; w * h * 3];
    for (i, b) in data.chunks_exact(4).enumerate() {
        let (px, ch) = (i / 3, i % 3);
        let (x, y) = (px % w, h - 1 - px / w);
        out[(y * w + x) * 3 + ch] = f32::from_le_bytes(b.try_into().unwrap());
    }
    (w, h, out)
}

/// The exact sRGB encoding (IEC 61966-2-1) in f64 with the standard
/// library's `powf`, not the library's.
// The platform's `pow` on purpose: an independent check of `libm`'s.
#[allow(clippy::disallowed_methods)]
fn srgb(l: f64) -> f64 {
    if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

clitest!(
    deep_outputs_read_back_through_compare_with_zero_error,
    |dir| {
        render(&dir, "x.pfm", &[]);
        for (out, depth) in [
            ("x16.png", "16"),
            ("x16.pam", "16"),
            ("x16.ppm", "16"),
            ("x16.pnm", "16"),
            ("x8.png", "8"),
        ] {
            render(&dir, out, &["--depth", depth]);
        }
        // `--format pfm` on a name without the extension.
        render(&dir, "linear.out", &["--format", "pfm"]);
        assert_eq!(dir.read("linear.out"), dir.read("x.pfm"));
        for name in ["x.pfm", "x16.png", "x16.pam", "x16.ppm", "x16.pnm"] {
            let m = compare(&dir, name, name);
            assert_eq!(m["rmse"], 0.0, "{name}: {m}");
            assert_eq!(m["largest_error"], 0.0, "{name}: {m}");
            assert_eq!(m["linear"]["largest_error"], 0.0, "{name}: {m}");
            assert!(m["psnr"].is_null(), "{name}: {m}");
        }
        // The three 16-bit files hold the same codes.
        for name in ["x16.pam", "x16.ppm"] {
            assert_eq!(compare(&dir, name, "x16.png")["largest_error"], 0.0);
        }
        // 16-bit against the linear values: within half a 16-bit code (0.5/257
        // of an 8-bit one); 8-bit: within half an 8-bit code, and its
        // quantisation shows.
        let m16 = compare(&dir, "x16.png", "x.pfm");
        assert_eq!(m16["image_encoding"], "16-bit sRGB");
        assert_eq!(m16["reference_encoding"], "linear float");
        let e16 = m16["largest_error"].as_f64().unwrap();
        assert!(e16 > 0.0 && e16 <= 0.5 / 257.0 + 1e-9, "{m16}");
        let m8 = compare(&dir, "x8.png", "x.pfm");
        let e8 = m8["largest_error"].as_f64().unwrap();
        assert!(e8 > 0.1 && e8 <= 0.5 + 1e-9, "{m8}");
        // Two 8-bit images: the report as it always was (an integer largest
        // error, no linear or encodings keys).
        let m = compare(&dir, "x8.png", "x8.png");
        assert_eq!(m["largest_error"], 0);
        assert!(
            m.get("linear").is_none() && m.get("image_encoding").is_none(),
            "{m}"
        );
    }
);

clitest!(sixteen_bit_codes_are_the_nearest_to_the_pfm_values, |dir| {
    render(&dir, "x.pfm", &[]);
    render(&dir, "x16.png", &["--depth", "16"]);
    let (w, h, linear) = read_pfm(&dir.read("x.pfm"));
    let png = image::load_from_memory(&dir.read("x16.png"))
        .unwrap()
        .into_rgb16();
    assert_eq!((png.width() as usize, png.height() as usize), (w, h));
    let mut near_a_tie = 0;
    for (&l, &code) in linear.iter().zip(png.as_raw()) {
        let exact = srgb((l as f64).clamp(0.0, 1.0)) * 65535.0;
        // Rounding is decided by the exact value; this test's f64 formula
        // could only disagree within its own error of a tie.
        if ((exact - exact.floor()) - 0.5).abs() < 1e-6 {
            near_a_tie += 1;
            assert!((exact - code as f64).abs() <= 0.5 + 1e-6);
        } else {
            assert_eq!(code as f64, exact.round(), "linear {l:e}");
        }
    }
    assert_eq!(
        near_a_tie, 0,
        "no value of this scene lies within 1e-6 of a tie"
    );
});

clitest!(
    eight_bit_output_is_the_rounded_frame_and_pngs_say_srgb,
    |dir| {
        render(&dir, "x.pfm", &[]);
        render(&dir, "x8.png", &[]);
        render(&dir, "x8.ppm", &[]);
        let (_, _, linear) = read_pfm(&dir.read("x.pfm"));
        let png = image::load_from_memory(&dir.read("x8.png"))
            .unwrap()
            .into_rgb8();
        let ppm = image::load_from_memory(&dir.read("x8.ppm"))
            .unwrap()
            .into_rgb8();
        assert_eq!(png.as_raw(), ppm.as_raw());
        // Each 8-bit code is the 8-bit encoder's rounding of the frame's value.
        for (&l, &code) in linear.iter().zip(png.as_raw()) {
            assert_eq!(code, patkit::color::linear_to_srgb(l), "linear {l:e}");
        }
        // The sRGB chunk (rendering intent 0, perceptual) in 8- and 16-bit PNGs,
        // before the image data.
        render(&dir, "x16.png", &["--depth", "16"]);
        for name in ["x8.png", "x16.png"] {
            let bytes = dir.read(name);
            let at = bytes.windows(4).position(|w| w == b"sRGB").expect(name);
            assert_eq!(
                &bytes[at - 4..at],
                &[0, 0, 0, 1],
                "{name}: one byte of data"
            );
            assert_eq!(bytes[at + 4], 0, "{name}: perceptual");
            assert!(at < bytes.windows(4).position(|w| w == b"IDAT").unwrap());
        }
    }
);

clitest!(frames_and_streams_take_the_deep_formats, |dir| {
    dir.write("s.json", SCENE);
    for (out, extra) in [
        ("f-%02d.pfm", &[][..]),
        ("g-%02d.png", &["--depth", "16"][..]),
        ("h-%02d.pam", &["--depth", "16"][..]),
    ] {
        dir.cmd("scene-render")
            .args(["--size", SIZE, "--frames", "2", "s.json", "-o", out])
            .args(extra)
            .assert()
            .success();
    }
    for name in ["f-00.pfm", "f-01.pfm", "g-00.png", "g-01.png", "h-01.pam"] {
        assert!(dir.files().contains(&name.to_string()), "{name}");
    }
    // A 16-bit frame and a frame in PFM: within half a 16-bit code.
    let m = compare(&dir, "g-01.png", "f-01.pfm");
    assert!(
        m["largest_error"].as_f64().unwrap() <= 0.5 / 257.0 + 1e-9,
        "{m}"
    );
    // On standard output, frames are PPM: MAXVAL 65535 at --depth 16.
    let out = dir
        .cmd("scene-render")
        .args([
            "--size", "4x3", "--frames", "2", "--depth", "16", "s.json", "-o", "-",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(out.stdout.starts_with(b"P6\n4 3\n65535\n"));
    assert_eq!(out.stdout.len(), 2 * (13 + 4 * 3 * 6));
});

clitest!(malformed_pfm_inputs_are_refused_with_clear_errors, |dir| {
    render(&dir, "good.pfm", &[]);
    let good = dir.read("good.pfm");
    let header = b"PF\n64 48\n-1.0\n".len();
    let mut nan = good.clone();
    nan[header + 4..header + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "truncated.pfm",
            good[..good.len() - 5].to_vec(),
            "truncated.pfm: not a valid PFM image: truncated: 64x48 pixels of 3 f32 need 36864 \
             bytes after the header, the file has 36859",
        ),
        (
            "nan.pfm",
            nan,
            "nan.pfm: not a valid PFM image: pixel (0, 47) from the top-left, channel 1, is NaN: \
             expected a finite number",
        ),
        (
            "width.pfm",
            b"PF\n6x4 48\n-1.0\n".to_vec(),
            "width.pfm: not a valid PFM image: header: the width is `6x4`: expected a whole \
             number of pixels",
        ),
        (
            "huge.pfm",
            b"PF\n65535 65535\n-1.0\n".to_vec(),
            "huge.pfm: not a valid PFM image: header: image size 65535x65535 is too large: at \
             most 268435456 pixels",
        ),
        (
            "scale.pfm",
            b"PF\n1 1\n0\n\0\0\0\0\0\0\0\0\0\0\0\0".to_vec(),
            "scale.pfm: not a valid PFM image: header: the scale is `0`: expected a finite \
             non-zero number",
        ),
        (
            "trailing.pfm",
            [&good[..], b"\n"].concat(),
            "trailing.pfm: not a valid PFM image: 1 byte(s) after the 64x48 pixels",
        ),
    ];
    for (name, bytes, want) in cases {
        dir.write(name, bytes);
        for args in [
            ["--image", name, "--compare", "good.pfm"],
            ["--image", "good.pfm", "--compare", name],
        ] {
            let out = dir.cmd("scene-render").args(args).output().unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{name}: {err}");
            assert!(
                err.starts_with(&format!("scene-render: error: {want}")),
                "{name}: {err}"
            );
        }
    }
});

clitest!(depth_and_pfm_flags_are_checked_as_usage, |dir| {
    dir.write("s.json", SCENE);
    render(&dir, "x.pfm", &[]);
    let cases: [(&[&str], &str); 7] = [
        (
            &["s.json", "-o", "x2.pfm", "--depth", "16"],
            "--depth 16: PFM stores 32-bit floats",
        ),
        (
            &["s.json", "--format", "pfm", "--depth", "8", "-o", "y"],
            "--depth 8: PFM stores",
        ),
        (
            &["s.json", "--background", "none", "-o", "a.pfm"],
            "PFM has no alpha channel",
        ),
        (
            &["--image", "x.pfm", "--compare", "x.pfm", "--diff", "d.pfm"],
            "d.pfm: `.pfm` stores a rendered frame's linear light, and this image has 8-bit \
             colours: expected .png, .ppm or .pam",
        ),
        (
            &[
                "s.json",
                "--frames",
                "2",
                "--animate",
                "--depth",
                "16",
                "-o",
                "t.png",
            ],
            "cannot be used with",
        ),
        (
            &["--image", "x.pfm", "--compare", "x.pfm", "--depth", "16"],
            "cannot be used with",
        ),
        (
            &["s.json", "-o", "x.exr"],
            "expected .png, .ppm, .pam or .pfm",
        ),
    ];
    for (args, want) in cases {
        // --size shapes a render: with --image it is refused itself.
        let size: &[&str] = if args[0] == "--image" {
            &[]
        } else {
            &["--size", SIZE]
        };
        let out = dir
            .cmd("scene-render")
            .args(size)
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    // pat-tile writes 8-bit colours only.
    let brick = crate::util::repo("fixtures/patterns/brick.pat");
    for args in [
        &["-o", "t.pfm"][..],
        &["--format", "pfm"],
        &["--depth", "16"],
    ] {
        let out = dir.cmd("pat-tile").args(args).arg(&brick).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
    assert!(!dir
        .files()
        .iter()
        .any(|f| f.starts_with("t.") || f == "x2.pfm"));
});

clitest!(diff_of_deep_images_is_an_8_bit_picture, |dir| {
    render(&dir, "x.pfm", &[]);
    render(&dir, "x8.png", &[]);
    dir.cmd("scene-render")
        .args(["--image", "x8.png", "--compare", "x.pfm", "--diff", "d.png"])
        .assert()
        .success();
    let d = image::load_from_memory(&dir.read("d.png")).unwrap();
    assert_eq!(d.color(), image::ColorType::Rgb8);
    // Half a code at most, times 16: 8 at most, and some pixel shows it.
    let max = d.into_rgb8().as_raw().iter().copied().max().unwrap();
    assert!((1..=8).contains(&max), "{max}");
});
