//! Command-line behaviour of `pat-from-image`: round trips, orientation,
//! palette forcing, stdin, and every bad input (exit 2 for usage, 1 otherwise,
//! no output file left behind).

use crate::util::OkStdout;
use assert_cmd::Command;
use patkit::{Pattern, Rgb8};
use predicates::str::contains;
use std::path::{Path, PathBuf};

fn tool() -> Command {
    Command::cargo_bin("pat-from-image").unwrap()
}

/// A 32x32 RGBA test image with four colours and transparent pixels: the top
/// row is red, the bottom row blue, a transparent column at x = 5, the rest
/// green with a white dot at (3, 10).
fn sample(x: u32, y: u32) -> [u8; 4] {
    if x == 5 {
        [77, 77, 77, 0]
    } else if y == 0 {
        [255, 0, 0, 255]
    } else if y == 31 {
        [0, 0, 255, 255]
    } else if (x, y) == (3, 10) {
        [255, 255, 255, 255]
    } else {
        [0, 160, 0, 255]
    }
}

fn write_png(dir: &Path, name: &str, w: u32, h: u32, f: fn(u32, u32) -> [u8; 4]) -> PathBuf {
    let path = dir.join(name);
    image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)))
        .save(&path)
        .unwrap();
    path
}

fn read_pat(path: &Path) -> Pattern {
    Pattern::read_file(path).unwrap()
}

#[test]
fn few_colours_round_trip_texel_for_texel_with_rows_flipped() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "in.png", 32, 32, sample);
    let out = dir.path().join("out.pat");
    tool()
        .args(["--size", "32", "--colors", "4", "-o"])
        .arg(&out)
        .arg(&png)
        .assert()
        .success();
    let pat = read_pat(&out);
    assert_eq!(pat.size(), 32);
    assert_eq!(pat.palette().len(), 4);
    for y in 0..32 {
        for x in 0..32 {
            let p = sample(x, y);
            let want = (p[3] == 255).then_some(Rgb8([p[0], p[1], p[2]]));
            // Image row 0 (top) is the last pattern row.
            assert_eq!(pat.color_at(x, 31 - y), want, "({x},{y})");
        }
    }
    // Canonical output: reading and writing reproduces it byte for byte.
    assert_eq!(pat.to_canonical(), std::fs::read_to_string(&out).unwrap());
}

#[test]
fn crop_takes_the_central_square_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "wide.png", 48, 32, |x, y| {
        if (16..32).contains(&x) && (8..24).contains(&y) {
            [(x * 8) as u8, (y * 8) as u8, 0, 255]
        } else {
            [0, 0, 0, 255]
        }
    });
    let out = tool()
        .args(["--crop", "--size", "16", "--colors", "256"])
        .arg(&png)
        .ok_stdout();
    let pat = Pattern::parse(&out, "stdout").unwrap();
    assert_eq!(pat.palette().len(), 256);
    for y in 0..16u32 {
        for x in 0..16u32 {
            let want = Rgb8([((x + 16) * 8) as u8, ((y + 8) * 8) as u8, 0]);
            assert_eq!(pat.color_at(x, 15 - y), Some(want));
        }
    }
}

#[test]
fn stdin_input_and_stdout_output_work() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "in.png", 32, 32, sample);
    let bytes = std::fs::read(&png).unwrap();
    let from_file = tool().args(["--size", "32"]).arg(&png).output().unwrap();
    tool()
        .args(["--size", "32", "-"])
        .write_stdin(bytes.clone())
        .assert()
        .success()
        .stdout(String::from_utf8(from_file.stdout).unwrap());
    // The input defaults to `-`.
    tool()
        .args(["--size", "32"])
        .write_stdin(bytes)
        .assert()
        .success()
        .stdout(predicates::str::starts_with("32 4\n"));
}

#[test]
fn a_forced_palette_is_used_whole_from_a_list_or_a_pat() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "in.png", 32, 32, sample);
    let list = dir.path().join("pal.txt");
    std::fs::write(&list, "# two colours\n#000000\n250,250,250 # light\n").unwrap();
    let out = dir.path().join("out.pat");
    tool()
        .args(["--size", "16", "--palette"])
        .arg(&list)
        .arg("-o")
        .arg(&out)
        .arg(&png)
        .assert()
        .success();
    let pat = read_pat(&out);
    assert_eq!(pat.palette(), &[Rgb8([0, 0, 0]), Rgb8([250, 250, 250])]);
    // The output pattern serves as a palette file too.
    let out2 = dir.path().join("out2.pat");
    tool()
        .args(["--size", "16", "--dither", "floyd-steinberg", "--palette"])
        .arg(&out)
        .arg("-o")
        .arg(&out2)
        .arg(&png)
        .assert()
        .success();
    assert_eq!(read_pat(&out2).palette(), pat.palette());
}

#[test]
fn transparent_colour_and_alpha_threshold_make_transparent_texels() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "in.png", 32, 32, sample);
    let out = tool()
        .args(["--size", "32", "--transparent", "#00a000"])
        .arg(&png)
        .output()
        .unwrap();
    let pat = Pattern::parse(&out.stdout, "o").unwrap();
    assert_eq!(pat.palette().len(), 3);
    assert_eq!(pat.color_at(0, 15), None);
    // Threshold 0 keeps the alpha-0 column, with its stored colour.
    let out = tool()
        .args(["--size", "32", "--alpha-threshold", "0"])
        .arg(&png)
        .output()
        .unwrap();
    let pat = Pattern::parse(&out.stdout, "o").unwrap();
    assert_eq!(pat.histogram().1, 0);
}

#[test]
fn every_dither_and_a_large_resample_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "grad.png", 100, 70, |x, y| {
        [(x * 2) as u8, (y * 3) as u8, 128, 255]
    });
    for dither in ["none", "floyd-steinberg", "ordered"] {
        for size in ["16", "128"] {
            tool()
                .args([
                    "--report", "--colors", "8", "--size", size, "--dither", dither,
                ])
                .arg(&png)
                .assert()
                .success()
                .stderr(contains("PSNR"))
                .stdout(predicates::str::starts_with(format!("{size} 8\n")));
        }
    }
}

/// Runs the tool with an output file, expecting `code` and `message` on stderr
/// and no file (not even a temporary one) left behind.
fn fails(args: &[&str], stdin: Option<Vec<u8>>, code: i32, message: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.pat");
    let mut cmd = tool();
    cmd.current_dir(dir.path()).args(args).arg("-o").arg(&out);
    if let Some(s) = stdin {
        cmd.write_stdin(s);
    }
    cmd.assert().code(code).stderr(contains(message));
    assert!(!out.exists(), "{args:?} left {out:?}");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn bad_inputs_fail_with_the_right_status_and_leave_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "in.png", 32, 32, sample);
    let png = png.to_str().unwrap();
    let junk = dir.path().join("junk.png");
    std::fs::write(&junk, b"this is not an image").unwrap();
    let junk = junk.to_str().unwrap();
    let dirname = dir.path().to_str().unwrap();

    fails(&["missing.png"], None, 1, "missing.png");
    fails(&[dirname], None, 1, "is a directory");
    fails(&[junk], None, 1, "junk.png: not an image");
    fails(
        &["-"],
        Some(b"junk".to_vec()),
        1,
        "standard input: not an image",
    );
    fails(
        &["-"],
        Some(Vec::new()),
        1,
        "standard input: empty file: not an image",
    );
    let empty = dir.path().join("empty.png");
    std::fs::write(&empty, b"").unwrap();
    fails(
        &[empty.to_str().unwrap()],
        None,
        1,
        "empty.png: empty file: not an image",
    );
    for size in ["0", "17", "8192"] {
        fails(&["--size", size, png], None, 2, &format!("--size `{size}`"));
    }
    fails(&["--size", "abc", png], None, 2, "abc");
    for k in ["0", "1000"] {
        fails(&["--colors", k, png], None, 2, &format!("--colors `{k}`"));
    }
    fails(&["--transparent", "red", png], None, 2, "`red`");
    fails(&["--transparent", "1,2", png], None, 2, "`1,2`");
    fails(&["--dither", "lots", png], None, 2, "lots");
    fails(&["--alpha-threshold", "300", png], None, 2, "300");
    fails(&["--crop", "--size", "64", png], None, 1, "32x32");
    fails(&["--palette", "nopal.txt", png], None, 1, "nopal.txt");
    fails(&["--palette", png, png], None, 1, "in.png");
    fails(
        &["--colors", "4", "--palette", "x", png],
        None,
        2,
        "--palette",
    );
    let bad_list = dir.path().join("bad.txt");
    std::fs::write(&bad_list, "1,2,3\n#12345\n").unwrap();
    fails(
        &["--palette", bad_list.to_str().unwrap(), png],
        None,
        1,
        "bad.txt:2",
    );
}

/// Two routes to the same pattern (netpbm's pnmtile.test style): every fixture,
/// tiled one texel per pixel by `pat-tile` and piped into `pat-from-image`
/// with enough colours, comes back texel for texel, transparency included.
#[test]
fn every_fixture_survives_pat_tile_then_pat_from_image() {
    for name in ["brick", "wood", "weave", "mod", "bkgrnd", "pyr", "chex"] {
        let path = crate::util::repo(&format!("fixtures/patterns/{name}.pat"));
        let original = Pattern::read_file(&path).unwrap();
        let size = original.size().to_string();
        let png = Command::cargo_bin("pat-tile")
            .unwrap()
            .args([
                "--size",
                &format!("{size}x{size}"),
                "--scale",
                "1",
                "--format",
                "png",
            ])
            .arg(&path)
            .ok_stdout();
        let text = tool()
            .args(["--size", &size, "--colors", "256", "-"])
            .write_stdin(png)
            .ok_stdout();
        let back = Pattern::parse(&text, name).unwrap();
        assert_eq!(back.size(), original.size(), "{name}");
        for row in 0..original.size() {
            for col in 0..original.size() {
                assert_eq!(
                    back.color_at(col, row),
                    original.color_at(col, row),
                    "{name} texel ({col},{row})"
                );
            }
        }
    }
}

/// A PNG of `img`, with an EXIF chunk and an ICC profile if given.
fn png_with(img: &image::RgbaImage, exif: Option<Vec<u8>>, icc: Option<Vec<u8>>) -> Vec<u8> {
    use image::ImageEncoder as _;
    let mut buf = Vec::new();
    let mut enc = image::codecs::png::PngEncoder::new(&mut buf);
    if let Some(e) = exif {
        enc.set_exif_metadata(e).unwrap();
    }
    if let Some(p) = icc {
        enc.set_icc_profile(p).unwrap();
    }
    enc.write_image(
        img,
        img.width(),
        img.height(),
        image::ExtendedColorType::Rgba8,
    )
    .unwrap();
    buf
}

/// An EXIF (TIFF, big-endian) block holding one tag: orientation `o`.
fn exif_orientation(o: u16) -> Vec<u8> {
    let mut e = b"MM\0\x2a\0\0\0\x08".to_vec();
    e.extend_from_slice(&1u16.to_be_bytes()); // one entry
    e.extend_from_slice(&0x0112u16.to_be_bytes()); // Orientation
    e.extend_from_slice(&3u16.to_be_bytes()); // SHORT
    e.extend_from_slice(&1u32.to_be_bytes()); // one value
    e.extend_from_slice(&o.to_be_bytes());
    e.extend_from_slice(&[0, 0]);
    e.extend_from_slice(&0u32.to_be_bytes()); // no next IFD
    e
}

clitest!(
    phone_photos_are_turned_upright_by_their_exif_orientation,
    |dir| {
        // Issue 22, item 6: a phone held sideways stores its sensor's rows and
        // EXIF orientation 6 ("turn 90 degrees clockwise to show"). The pattern
        // must be the one of the upright picture.
        let stored = image::RgbaImage::from_fn(16, 16, |x, y| match (x < 8, y < 8) {
            (true, true) => image::Rgba([255, 0, 0, 255]),
            (false, true) => image::Rgba([0, 0, 255, 255]),
            _ => image::Rgba([0, 160, 0, 255]),
        });
        let upright = image::imageops::rotate90(&stored);
        dir.write(
            "sideways.png",
            png_with(&stored, Some(exif_orientation(6)), None),
        );
        dir.write("upright.png", png_with(&upright, None, None));
        dir.write("stored.png", png_with(&stored, None, None));
        let pattern = |name: &str| {
            dir.cmd("pat-from-image")
                .args(["--size", "16", "--colors", "3", name])
                .ok_stdout()
        };
        assert_eq!(pattern("sideways.png"), pattern("upright.png"));
        assert_ne!(pattern("sideways.png"), pattern("stored.png"));
    }
);

clitest!(
    a_colour_profile_that_is_not_applied_is_warned_about,
    |dir| {
        let img = image::RgbaImage::from_pixel(16, 16, image::Rgba([10, 20, 30, 255]));
        // Any bytes: the profile is only noticed, not read.
        dir.write("profiled.png", png_with(&img, None, Some(vec![0; 128])));
        dir.write("plain.png", png_with(&img, None, None));
        dir.cmd("pat-from-image")
        .args(["--size", "16", "profiled.png"])
        .assert()
        .success()
        .stderr(predicates::str::contains(
            "pat-from-image: warning: profiled.png: has an ICC colour profile, which is not applied",
        ));
        dir.cmd("pat-from-image")
            .args(["--size", "16", "plain.png"])
            .assert()
            .success()
            .stderr("");
    }
);

clitest!(
    pat_from_image_output_is_the_same_for_any_thread_count,
    |dir| {
        // `--threads N`, as scene-render has it (issue 18, item 3): the palette
        // search runs on N workers, and the pattern is byte-identical for any N.
        let photo = crate::util::repo("fixtures/images/earth-nasa.jpg");
        let mut outs = Vec::new();
        for n in ["1", "2", "3"] {
            let out = format!("e{n}.pat");
            dir.cmd("pat-from-image")
                .args(["--threads", n, "--colors", "32", "--size", "32"])
                .arg(&photo)
                .args(["-o", &out])
                .assert()
                .success();
            outs.push(dir.read(&out));
        }
        assert!(outs.windows(2).all(|w| w[0] == w[1]));
        dir.cmd("pat-from-image")
            .args(["--threads", "0"])
            .arg(&photo)
            .assert()
            .code(2)
            .stderr(predicates::str::contains("'0' for '--threads <N>'"));
    }
);

clitest!(
    a_pattern_larger_than_a_file_read_whole_is_read_back_by_the_other_tools,
    |dir| {
        // 2048x2048 of 256 colours is about 335.5 million bytes of text,
        // more than the 256 MiB a tool reads of a file read whole: the other
        // tools read a .pat as a stream. A small picture of 256 colours,
        // scaled up with --dither none (no new colours), makes it.
        let colours = image::RgbaImage::from_fn(16, 16, |x, y| {
            image::Rgba([(x * 16) as u8, (y * 16) as u8, ((x + y) * 8) as u8, 255])
        });
        dir.write("colours.png", png_with(&colours, None, None));
        dir.cmd("pat-from-image")
            .args(["--size", "2048", "--colors", "256", "--dither", "none"])
            .args(["colours.png", "-o", "big.pat"])
            .assert()
            .success()
            .stderr("");
        let len = std::fs::metadata(dir.path().join("big.pat")).unwrap().len();
        assert!(len > 256 << 20, "{len} bytes");
        dir.cmd("pat-info")
            .args(["--check", "big.pat"])
            .assert()
            .success()
            .stderr("");
    }
);

/// A netpbm picture whose sample exceeds its header's maxval is refused,
/// naming the sample, its pixel and the maxval, as netpbm's programs refuse
/// it; the `image` crate saturated it to white. The same picture within its
/// maxval is read, and a scene naming the bad one as a texture is refused
/// the same way.
#[test]
fn a_netpbm_sample_over_its_maxval_is_refused() {
    let mut good = b"P5\n16 16\n100\n".to_vec();
    good.extend(std::iter::repeat_n(50u8, 256));
    good[13 + 16 * 3 + 5] = 100;
    let mut bad = good.clone();
    bad[13 + 16 * 3 + 5] = 200;
    refused_by_both_routes(
        ("bad.pgm", &bad),
        ("good.pgm", &good),
        "bad.pgm: the sample 200 at pixel (5, 3) is over the header's maxval 100",
    );
}

/// `bad` (name, bytes) refused, saying `said`, by pat-from-image (which
/// leaves no output) and by scene-render naming it as a pattern; `good`
/// read by pat-from-image.
fn refused_by_both_routes(bad: (&str, &[u8]), good: (&str, &[u8]), said: &str) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(bad.0), bad.1).unwrap();
    std::fs::write(dir.path().join(good.0), good.1).unwrap();
    tool()
        .current_dir(dir.path())
        .args([bad.0, "-o", "out.pat"])
        .assert()
        .code(1)
        .stderr(contains(said));
    assert!(!dir.path().join("out.pat").exists());
    let scene = r#"{"vertices":[[0,0,0],[8,0,0],[0,8,0]],"color":[1,2,3],"pattern":{"file":"BAD","incr":1}}"#;
    std::fs::write(dir.path().join("s.json"), scene.replace("BAD", bad.0)).unwrap();
    Command::cargo_bin("scene-render")
        .unwrap()
        .current_dir(dir.path())
        .args(["s.json", "--size", "8x8", "-o", "s.png"])
        .assert()
        .code(1)
        .stderr(contains(said));
    tool()
        .current_dir(dir.path())
        .args([good.0, "-o", "out.pat"])
        .assert()
        .success();
}

/// An indexed PNG with a pixel whose index is past its palette is refused,
/// naming the index, its pixel and the palette's size; the decoder drew it
/// black. A scene naming it as a texture is refused the same way, and the
/// same picture with the index in range is read.
#[test]
fn a_png_palette_index_past_its_palette_is_refused() {
    let indexed = |last: u8| {
        let mut out = Vec::new();
        let mut e = png::Encoder::new(&mut out, 4, 2);
        e.set_color(png::ColorType::Indexed);
        e.set_palette(vec![255, 0, 0, 0, 255, 0]);
        e.write_header()
            .unwrap()
            .write_image_data(&[0, 1, 1, 0, 1, 0, 0, last])
            .unwrap();
        out
    };
    refused_by_both_routes(
        ("bad.png", &indexed(5)),
        ("good.png", &indexed(1)),
        "bad.png: the palette index 5 at pixel (3, 1) is past the palette (2 colours)",
    );
}

/// A PNG from a pipe is read to its end (IEND) and no further: followed by
/// endless zeros it was read to the 2 GiB input limit (2.1 GB resident)
/// before being refused. The writer here stops at the first refused write;
/// what it wrote is the PNG, the pipe's buffer and one 64 KiB read, not the
/// 1 GiB it offers. The pattern is the one the PNG alone makes. Cut before
/// its IEND chunk (the zeros then read as a chunk of no type) it was still
/// read to the limit; it is now read to the first chunk that is not one,
/// and refused as the cut PNG alone is.
#[test]
fn a_png_from_a_pipe_is_read_to_its_end_and_no_further() {
    use std::io::Write as _;
    let dir = tempfile::tempdir().unwrap();
    let png = write_png(dir.path(), "p.png", 16, 16, |x, y| {
        [(x * 16) as u8, (y * 16) as u8, 90, 255]
    });
    let whole = std::fs::read(&png).unwrap();
    let cut = whole[..whole.len() - 12].to_vec();
    for bytes in [whole, cut] {
        let alone = tool()
            .args(["-o", "-", "-"])
            .write_stdin(bytes.clone())
            .output()
            .unwrap();
        let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("pat-from-image"))
            .args(["-o", "-", "-"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let writer = std::thread::spawn(move || {
            let mut written = 0usize;
            if stdin.write_all(&bytes).is_err() {
                return written;
            }
            let zeros = vec![0u8; 1 << 16];
            while written < 1 << 30 && stdin.write_all(&zeros).is_ok() {
                written += zeros.len();
            }
            written
        });
        let out = child.wait_with_output().unwrap();
        let written = writer.join().unwrap();
        assert_eq!(
            (out.status.code(), &out.stdout, &out.stderr),
            (alone.status.code(), &alone.stdout, &alone.stderr)
        );
        assert!(written < 16 << 20, "{written} bytes of zeros taken");
    }
}
