//! `polyfill3` end to end: pass-through, fields, bad input, the thesis's counts.

use crate::util::OkStdout;
use assert_cmd::Command;
use serde_json::Value;
use std::path::Path;

fn polyfill3() -> Command {
    Command::cargo_bin("polyfill3").unwrap()
}

/// A SIZE x SIZE pattern in the `.pat` text format: every texel colour 0
/// (opaque), except those `transparent` says.
fn write_pat(path: &Path, size: usize, transparent: impl Fn(usize, usize) -> bool) {
    let mut s = format!("{size} 1\n200 100 50\n");
    for row in 0..size {
        let words: Vec<String> = (0..size / 16)
            .map(|w| {
                let mut bits = 0u16;
                for b in 0..16 {
                    if !transparent(w * 16 + b, row) {
                        bits |= 0x8000 >> b;
                    }
                }
                format!("{bits:04x}")
            })
            .collect();
        s += &words.join(" ");
        s += "\n";
    }
    std::fs::write(path, s).unwrap();
}

fn lines(out: &[u8]) -> Vec<Value> {
    std::str::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn area(v: &Value) -> f64 {
    let p: Vec<[f64; 3]> = serde_json::from_value(v["vertices"].clone()).unwrap();
    let mut n = [0.0; 3];
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0
}

#[test]
fn records_without_a_pattern_pass_through_byte_for_byte() {
    let line = r#"{"id":7,"vertices":[[0,0,0],[1,0,0],[0,1,0]],"color":[1,2,3],"tag":{"x":[1.5]}}"#;
    let out = polyfill3()
        .write_stdin(format!("{line}\n"))
        .assert()
        .success();
    assert_eq!(
        String::from_utf8_lossy(&out.get_output().stdout),
        format!("{line}\n")
    );
}

#[test]
fn cells_carry_unknown_fields_colour_and_texel() {
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |c, r| c == 1 && r == 0);
    let scene = dir.path().join("s.json");
    std::fs::write(
        &scene,
        r#"[{"id":"sq","vertices":[[0,0],[2,0],[2,2],[0,2]],"pattern":{"file":"p.pat","incr":1},"uv_note":1}]"#,
    )
    .unwrap();
    let out = polyfill3().arg(&scene).assert().success();
    let recs = lines(&out.get_output().stdout);
    // 4 cells, texel (1, 0) transparent.
    assert_eq!(recs.len(), 3);
    for r in &recs {
        assert_eq!(r["id"], "sq");
        assert_eq!(r["uv_note"], 1);
        assert_eq!(r["color"], serde_json::json!([200, 100, 50]));
        assert!(r.get("pattern").is_none());
        assert_eq!(r["vertices"][0].as_array().unwrap().len(), 3);
    }
    assert_eq!(recs[0]["texel"], serde_json::json!([0, 0]));
    assert_eq!(recs[1]["texel"], serde_json::json!([0, 1]));
    assert_eq!(
        recs[0]["vertices"],
        serde_json::json!([
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0]
        ])
    );
}

#[test]
fn two_d_records_with_a_pattern_are_partitioned() {
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    let out = polyfill3()
        .current_dir(dir.path())
        .args(["--pattern", "p.pat", "--incr", "10"])
        .write_stdin(
            "{\"rect\":[0,0,100,50],\"pattern\":{}}\n{\"circle\":{\"center\":[0,0],\"radius\":10},\"pattern\":{\"incr\":1}}\n",
        )
        .assert()
        .success();
    let recs = lines(&out.get_output().stdout);
    let rect: f64 = recs.iter().take(50).map(area).sum();
    assert!((rect - 5000.0).abs() < 1e-9);
    let disc: f64 = recs.iter().skip(50).map(area).sum();
    // Chords within --tolerance 0.01 of the circle lose about 2/3 * 0.01 * 2πr.
    assert!((disc - std::f64::consts::PI * 100.0).abs() < 0.5, "{disc}");
}

#[test]
fn merge_covers_the_same_area_with_fewer_polygons() {
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |c, _| c % 4 == 3);
    let scene = r#"{"vertices":[[0,0,0],[30,0,0],[30,0,-20],[0,0,-20]],"pattern":{"file":"p.pat","incr":1.5}}"#;
    std::fs::write(dir.path().join("s.json"), scene).unwrap();
    let plain = polyfill3()
        .current_dir(dir.path())
        .arg("s.json")
        .assert()
        .success();
    let merged = polyfill3()
        .current_dir(dir.path())
        .args(["--merge", "s.json"])
        .assert()
        .success();
    let (a, b) = (
        lines(&plain.get_output().stdout),
        lines(&merged.get_output().stdout),
    );
    let blocks = polyfill3()
        .current_dir(dir.path())
        .args(["--merge=blocks", "s.json"])
        .assert()
        .success();
    let c = lines(&blocks.get_output().stdout);
    assert!(b.len() * 2 < a.len(), "{} vs {}", b.len(), a.len());
    // The pattern's runs of three columns repeat from row to row: the
    // blocks join them down the plane (80 runs, 20 blocks).
    assert!(c.len() * 3 < b.len(), "{} vs {}", c.len(), b.len());
    let sa: f64 = a.iter().map(area).sum();
    for merged in [&b, &c] {
        let sb: f64 = merged.iter().map(area).sum();
        assert!((sa - sb).abs() < 1e-9 * sa);
        let cells: u64 = merged
            .iter()
            .map(|r| r.get("cells").and_then(Value::as_u64).unwrap_or(1))
            .sum();
        assert_eq!(cells as usize, a.len());
    }
}

/// A 64x64 pattern of two colours in bands 8 texels wide and 5 high, every
/// fourth column transparent: runs of three cells, and blocks of them five
/// rows high.
fn write_banded_pat(path: &Path) {
    let mut planes = [String::new(), String::new()];
    for row in 0..64 {
        for (colour, plane) in planes.iter_mut().enumerate() {
            let words: Vec<String> = (0..4)
                .map(|w| {
                    let bits = (0..16)
                        .filter(|b| {
                            let c = w * 16 + b;
                            c % 4 != 3 && (c / 8 + row / 5) % 2 == colour
                        })
                        .fold(0u16, |bits, b| bits | 0x8000 >> b);
                    format!("{bits:04x}")
                })
                .collect();
            *plane += &words.join(" ");
            *plane += "\n";
        }
    }
    let [a, b] = planes;
    std::fs::write(path, format!("64 2\n200 100 50\n{a}30 60 200\n{b}")).unwrap();
}

/// Merged runs and blocks cover the cells' region through every grid corner
/// on their sides: scene-render draws the same picture from the cells, the
/// runs and the blocks, to the bit (PFM), with each anti-aliasing (the
/// pyramid of demo 2 at incr 0.5, seen from above two of its faces).
#[test]
fn merged_runs_and_blocks_draw_the_picture_of_the_cells() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_banded_pat(&d.join("p.pat"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/scenes");
    let faces = std::fs::read_to_string(root.join("demo2-faces.json")).unwrap();
    let faces = faces
        .replace("../patterns/pyr.pat", "p.pat")
        .replace("\"incr\":2", "\"incr\":0.5");
    assert!(faces.contains("p.pat") && faces.contains("0.5"));
    std::fs::write(d.join("faces.json"), faces).unwrap();
    std::fs::write(
        d.join("above.json"),
        r#"{"lookat": {"eye": [250, 150, 300], "center": [0, 50, 0], "twist": 0},
            "perspective": {"fovy": 40, "aspect": 1.0, "near": 1, "far": 1000}}"#,
    )
    .unwrap();
    let kinds: [(&str, &[&str]); 3] = [
        ("cells", &[]),
        ("runs", &["--merge"]),
        ("blocks", &["--merge=blocks"]),
    ];
    let mut sizes = Vec::new();
    for (kind, args) in kinds {
        let out = format!("{kind}.ndjson");
        polyfill3()
            .current_dir(d)
            .args(args)
            .args(["faces.json", "-o", &out])
            .assert()
            .success();
        sizes.push(std::fs::metadata(d.join(&out)).unwrap().len());
    }
    assert!(sizes[2] * 2 < sizes[1] && sizes[1] < sizes[0], "{sizes:?}");
    for aa in ["exact", "none", "ss4"] {
        let pictures: Vec<Vec<u8>> = kinds
            .iter()
            .map(|(kind, _)| {
                let out = format!("{kind}-{aa}.pfm");
                Command::cargo_bin("scene-render")
                    .unwrap()
                    .current_dir(d)
                    .args(["--camera", "above.json", "--size", "96x96", "--aa", aa])
                    .args([&format!("{kind}.ndjson"), "-o", &out])
                    .assert()
                    .success();
                std::fs::read(d.join(out)).unwrap()
            })
            .collect();
        assert!(
            pictures[1] == pictures[0],
            "--aa {aa}: the runs' picture differs"
        );
        assert!(
            pictures[2] == pictures[0],
            "--aa {aa}: the blocks' picture differs"
        );
    }
}

/// The App. C scenes with patterns written in the tempdir: an opaque 64x64
/// stand-in for the lost pyr.pat, an opaque 16x16 for chex.pat.
fn demo2(dir: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/scenes");
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    std::fs::create_dir_all(dir.join("patterns")).unwrap();
    for f in ["demo2-faces.json", "demo2-plain.json", "demo2-fig51.json"] {
        std::fs::copy(root.join(f), dir.join("scenes").join(f)).unwrap();
    }
    write_pat(&dir.join("patterns/pyr.pat"), 64, |_, _| false);
    write_pat(&dir.join("patterns/chex.pat"), 16, |_, _| false);
}

/// [`demo2`]'s scenes and patterns, and the thesis's demo2 camera as
/// `cam.json` (docs/camera.md).
fn demo2_and_its_camera(dir: &Path) {
    demo2(dir);
    std::fs::write(
        dir.join("cam.json"),
        r#"{"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900], "twist": 0},
            "perspective": {"fovy": 55, "aspect": 1.0, "near": 0, "far": 1000}}"#,
    )
    .unwrap();
}

fn count(dir: &Path, args: &[&str]) -> usize {
    let out = polyfill3().current_dir(dir).args(args).assert().success();
    out.get_output()
        .stdout
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

#[test]
fn thesis_counts_on_the_demo2_scenes() {
    let dir = tempfile::tempdir().unwrap();
    demo2(dir.path());
    let d = dir.path();
    // The plain: 1,353 in the thesis (19,289 - 17,936), of which 1,280 have area.
    assert_eq!(
        count(d, &["--compat", "thesis", "scenes/demo2-plain.json"]),
        1353
    );
    assert_eq!(count(d, &["scenes/demo2-plain.json"]), 1280);
    // The pyramid at incr 2 (App. C): the thesis counts 17,936; its loop in
    // double precision gives 17,932 (one touching cell per face fewer).
    assert_eq!(
        count(d, &["--compat", "thesis", "scenes/demo2-faces.json"]),
        17932
    );
    assert_eq!(count(d, &["scenes/demo2-faces.json"]), 17928);
}

#[test]
fn bad_input_names_the_record_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    std::fs::write(dir.path().join("bad.pat"), "16 1\n1 2 3\nzz\n").unwrap();
    let ok = r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"p.pat","incr":0.25}}"#;
    let cases: &[(&str, &str)] = &[
        (
            r#"{"vertices":[[0,0],[1,0]],"pattern":{"file":"p.pat"}}"#,
            "at least 3 vertices",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[2,0]],"pattern":{"file":"p.pat"}}"#,
            "no area",
        ),
        (
            r#"{"vertices":[[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]],"pattern":{"file":"p.pat"}}"#,
            "not planar",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[0,NaN]],"pattern":{"file":"p.pat"}}"#,
            "invalid JSON",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"p.pat","incr":0}}"#,
            "incr",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"nope.pat"}}"#,
            "nope.pat",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"bad.pat"}}"#,
            "bad.pat",
        ),
        (
            r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{}}"#,
            "no --pattern",
        ),
        (
            r#"{"vertices":[[0,0],[1000,0],[0,1000]],"pattern":{"file":"p.pat","incr":0.01}}"#,
            "--max-polygons",
        ),
    ];
    for (bad, want) in cases {
        let out = polyfill3()
            .current_dir(dir.path())
            .args(["--max-polygons", "1000000"])
            .write_stdin(format!("{ok}\n{bad}\n"))
            .assert()
            .code(1);
        let o = out.get_output();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.starts_with("polyfill3: error: <stdin>: record 1"),
            "{bad}: {err}"
        );
        assert!(err.contains(want), "{bad}: {err}");
        assert!(o.stdout.is_empty(), "{bad}");
    }
    // The non-planar error gives the deviation.
    let out = polyfill3()
        .current_dir(dir.path())
        .write_stdin(cases[2].0)
        .assert()
        .code(1);
    assert!(String::from_utf8_lossy(&out.get_output().stderr).contains("from its plane"));
    // A bad flag is a usage error; a failed run leaves no output file.
    polyfill3()
        .args(["--incr", "0"])
        .write_stdin(ok)
        .assert()
        .code(2);
    polyfill3()
        .args(["--incr", "-1"])
        .write_stdin(ok)
        .assert()
        .code(2);
    let target = dir.path().join("out.json");
    polyfill3()
        .current_dir(dir.path())
        .arg("-o")
        .arg(&target)
        .write_stdin(format!("{ok}\n{}\n", cases[1].0))
        .assert()
        .code(1);
    assert!(!target.exists());
}

#[test]
fn help_has_examples_and_defaults() {
    let out = polyfill3().arg("--help").assert().success();
    let s = String::from_utf8_lossy(&out.get_output().stdout).to_string();
    assert!(s.contains("Examples:"));
    assert!(s.contains("[default: 1]"));
    assert!(s.contains("--max-polygons"));
}

#[test]
fn cull_drops_back_faces_and_cells_out_of_view() {
    let dir = tempfile::tempdir().unwrap();
    demo2_and_its_camera(dir.path());
    let d = dir.path();
    let all = count(d, &["scenes/demo2-plain.json"]);
    let seen = count(
        d,
        &["--camera", "cam.json", "--cull", "scenes/demo2-plain.json"],
    );
    // The plain's near cells lie below the 55° view, its far ones are kept.
    assert!(seen > 0 && seen < all, "{seen} of {all}");
    // The plain turned over faces away from the camera: nothing is written.
    let under = r#"{"vertices":[[-500,0,-800],[500,0,-800],[500,0,0],[-500,0,0]],"pattern":{"file":"patterns/chex.pat","incr":25}}"#;
    std::fs::write(d.join("under.json"), under).unwrap();
    assert_eq!(
        count(d, &["--camera", "cam.json", "--cull", "under.json"]),
        0
    );
    // --camera alone is a usage error, --cull alone too.
    polyfill3()
        .current_dir(d)
        .args(["--camera", "cam.json", "under.json"])
        .assert()
        .code(2);
    polyfill3()
        .current_dir(d)
        .args(["--cull", "under.json"])
        .assert()
        .code(2);
}

/// `polyfill3 --cull=FACES` leaves out only what `scene-render --cull FACES`
/// with the same camera does not draw: the picture of the culled cells is the
/// picture of the whole partition, to the bit (PFM), for each choice of faces.
#[test]
fn cull_faces_leave_the_picture_of_scene_render_with_the_same_cull() {
    let dir = tempfile::tempdir().unwrap();
    demo2_and_its_camera(dir.path());
    let d = dir.path();
    // Beside the demo2 camera, one looking at the pyramid of
    // demo2-faces.json (at the origin) from above its faces 1 and 3, and a
    // parallel view along the plain (level, 50 above it, turned 17 degrees
    // about the line of sight), which sees it exactly edge-on: with the old
    // rule (edge-on dropped by either face) `--aa ss4` drew slivers of it
    // that the culled stream did not have.
    std::fs::write(
        d.join("above.json"),
        r#"{"lookat": {"eye": [250, 150, 300], "center": [0, 50, 0], "twist": 0},
            "perspective": {"fovy": 40, "aspect": 1.0, "near": 1, "far": 1000}}"#,
    )
    .unwrap();
    std::fs::write(
        d.join("edge-on.json"),
        r#"{"lookat": {"eye": [300, 50, 200], "center": [0, 50, -500], "twist": 17},
            "ortho": {"left": -400, "right": 400, "bottom": -150, "top": 150, "near": 0, "far": 2000}}"#,
    )
    .unwrap();
    let render = |camera: &str, cells: &str, faces: &str, aa: &str, out: &str| {
        Command::cargo_bin("scene-render")
            .unwrap()
            .current_dir(d)
            .args(["--camera", camera, "--size", "96x96", "--cull", faces])
            .args(["--aa", aa, cells, "-o", out])
            .assert()
            .success();
        std::fs::read(d.join(out)).unwrap()
    };
    // The plain's near cells lie below the view. Seen from above, all of the
    // pyramid is in view, faces 1 and 3 turned to the camera; the demo2
    // camera at z = -5 sees part of it, the rest behind the eye.
    for (scene, camera) in [
        ("scenes/demo2-plain.json", "cam.json"),
        ("scenes/demo2-plain.json", "edge-on.json"),
        ("scenes/demo2-faces.json", "above.json"),
        ("scenes/demo2-faces.json", "cam.json"),
    ] {
        polyfill3()
            .current_dir(d)
            .args([scene, "-o", "all.ndjson"])
            .assert()
            .success();
        let all = count(d, &[scene]);
        let mut kept = Vec::new();
        for faces in ["none", "back", "front"] {
            let cull = format!("--cull={faces}");
            let args = ["--camera", camera, &cull, scene];
            polyfill3()
                .current_dir(d)
                .args(args)
                .args(["-o", "seen.ndjson"])
                .assert()
                .success();
            kept.push(count(d, &args));
            for aa in ["exact", "none", "ss4"] {
                assert!(
                    render(camera, "seen.ndjson", faces, aa, "seen.pfm")
                        == render(camera, "all.ndjson", faces, aa, "all.pfm"),
                    "{scene} {camera} {cull} --aa {aa}: the picture changed"
                );
            }
        }
        let [none, back, front] = kept[..] else {
            unreachable!()
        };
        let what = format!("{scene} {camera}: of {all}, {none} / {back} / {front} kept");
        // Edge-on polygons are kept by either face: the renderer decides.
        match camera {
            "above.json" => assert!(none == all && back > 0 && front > 0, "{what}"),
            "edge-on.json" => assert!(back == none && front == none && none > 0, "{what}"),
            _ => assert!(0 < none && none < all && back + front == none, "{what}"),
        }
    }
    // `--cull none`, as scene-render's --cull is written, is `--cull=none`;
    // any other word after --cull is the input.
    let plain = "scenes/demo2-plain.json";
    assert_eq!(
        count(d, &["--camera", "cam.json", "--cull", "none", plain]),
        count(d, &["--camera", "cam.json", "--cull=none", plain])
    );
    assert_eq!(
        count(d, &["--camera", "cam.json", "--cull", plain]),
        count(d, &["--camera", "cam.json", "--cull=back", plain])
    );
}

#[test]
fn json_summary_rotation_and_compat_shifts() {
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    let d = dir.path();
    let tri = r#"{"vertices":[[0,0,0],[4,0,0],[0,4,0]],"pattern":{"file":"p.pat"}}"#;
    std::fs::write(
        d.join("t.json"),
        format!("{tri}\n{{\"rect\":[0,0,1,1],\"color\":[1,1,1]}}\n"),
    )
    .unwrap();
    let out = polyfill3()
        .current_dir(d)
        .args(["--json", "t.json"])
        .assert()
        .success();
    let o = out.get_output();
    let summary: Value = serde_json::from_slice(&o.stderr).unwrap();
    assert_eq!(summary["version"], 1);
    assert_eq!(summary["records"], 2);
    assert_eq!(summary["passed_through"], 1);
    assert_eq!(summary["partitioned"], 1);
    let n = o.stdout.iter().filter(|&&b| b == b'\n').count() as u64;
    assert_eq!(summary["polygons"].as_u64().unwrap() + 1, n);
    // Rotating the pattern 45 degrees changes the cells, not the area.
    let out = polyfill3()
        .current_dir(d)
        .args(["--rotate", "45", "t.json"])
        .assert()
        .success();
    let recs = lines(&out.get_output().stdout);
    let cut: Vec<&Value> = recs.iter().filter(|r| r.get("texel").is_some()).collect();
    assert!((cut.iter().map(|r| area(r)).sum::<f64>() - 8.0).abs() < 1e-12);
    assert_ne!(cut.len() as u64 + 1, n);
    // The thesis's loop takes integer shifts only.
    let out = polyfill3()
        .current_dir(d)
        .args(["--compat", "thesis", "--horz", "0.5", "t.json"])
        .assert()
        .code(1);
    assert!(String::from_utf8_lossy(&out.get_output().stderr).contains("must be integers"));
}

/// Vertex coordinates of cells placed by an instance and of cells cut from the
/// already placed face differ by rounding only (a rotation by 90 degrees is
/// exact in cos/sin only up to 1e-16): far below anything 8-bit output shows.
const INSTANCE_VERTEX_TOL: f64 = 1e-9;

clitest!(
    objects_are_partitioned_once_and_instances_pass_through,
    |dir| {
        demo2(dir.path());
        let out = dir
            .cmd("polyfill3")
            .args(["scenes/demo2-fig51.json", "--json"])
            .assert()
            .success();
        let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
        let summary: Value = serde_json::from_slice(&out.get_output().stderr).unwrap();
        assert_eq!(summary["objects"], 1);
        assert_eq!(summary["instances"], 4);
        let input = std::fs::read_to_string(dir.path().join("scenes/demo2-fig51.json")).unwrap();
        let in_lines: Vec<&str> = input.lines().collect();
        let out_lines: Vec<&str> = text.lines().collect();
        // One object, four instances byte for byte, then the plain's 1,280 cells.
        assert_eq!(out_lines.len(), 1 + 4 + 1280);
        assert_eq!(&out_lines[1..5], &in_lines[1..5]);
        let object: Value = serde_json::from_str(out_lines[0]).unwrap();
        assert_eq!(object["object"], "face");
        // The object's records are exactly face 1 of the four-face scene cut on
        // its own: 17,928 / 4 cells, written once.
        let faces = dir
            .cmd("polyfill3")
            .arg("scenes/demo2-faces.json")
            .assert()
            .success();
        let face_cells = lines(&faces.get_output().stdout);
        let records = object["records"].as_array().unwrap();
        assert_eq!(records.len(), 17928 / 4);
        assert_eq!(records.as_slice(), &face_cells[..records.len()]);
        // Expanding the instances (the copying path) gives the cells of the
        // four faces, the same texels in the same places.
        let mut expanded = Vec::new();
        patkit::stream::for_each_record(text.as_bytes(), "out", |r| {
            expanded.push(r);
            Ok::<(), patkit::stream::StreamError>(())
        })
        .unwrap();
        assert_eq!(expanded.len(), 17928 + 1280);
        // The instances are listed as faces 1, 2, 4, 3; demo2-faces.json has the
        // pyramid at the origin, the instances move it to z = -500.
        let shift = glam::DVec3::new(0.0, 0.0, -500.0);
        let per_face = records.len();
        for (k, face) in [0usize, 1, 3, 2].into_iter().enumerate() {
            for i in 0..per_face {
                let got = &expanded[k * per_face + i];
                let want = &face_cells[face * per_face + i];
                assert_eq!(got.fields["texel"], want["texel"]);
                let w: Vec<[f64; 3]> = serde_json::from_value(want["vertices"].clone()).unwrap();
                let patkit::geom::Shape::Polygon(g) = &got.shape else {
                    panic!("cells are polygons")
                };
                assert_eq!(g.len(), w.len());
                for (a, b) in g.iter().zip(&w) {
                    let d = (*a - glam::DVec3::from_array(*b) - shift).length();
                    assert!(
                        d < INSTANCE_VERTEX_TOL,
                        "face {face} cell {i}: {a} vs {b:?}"
                    );
                }
            }
        }
    }
);

clitest!(
    bad_objects_and_instances_name_the_record_and_write_nothing,
    |dir| {
        write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
        let face = r#"{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"p.pat"}}"#;
        let cases = [
        (
            format!("{face}\n{{\"instance\":\"ghost\"}}"),
            "s.json: record 1: instance of unknown object `ghost`",
        ),
        (
            r#"{"object":"a","records":[{"instance":"a"}]}"#.to_string(),
            "s.json: record 0: object `a` places an instance of itself: a cycle",
        ),
        (
            format!("{{\"object\":\"a\",\"records\":[{face}]}}\n{{\"object\":\"a\",\"records\":[]}}"),
            "s.json: record 1: object `a` is defined twice",
        ),
        (
            r#"{"object":"a","records":[]}
{"instance":"a","transform":{"scale":[1,0,1]}}"#
                .to_string(),
            "s.json: record 1: instance of `a`: transform step 0: scale: singular",
        ),
        (
            r#"{"object":"a","records":[{"vertices":[[0,0],[1,0],[2,0]],"pattern":{"file":"p.pat"}}]}"#
                .to_string(),
            "s.json: record 0: object `a` records[0]",
        ),
    ];
        for (text, want) in cases {
            dir.write("s.json", &text);
            dir.cmd("polyfill3")
                .args(["s.json", "-o", "out.json"])
                .assert()
                .code(1)
                .stderr(predicates::str::contains(want));
            assert!(!dir.path().join("out.json").exists(), "{want}");
        }
    }
);

/// A 16x16 pattern of one opaque colour, `rgb`.
fn write_solid_pat(path: &Path, rgb: [u8; 3]) {
    let mut s = format!("16 1\n{} {} {}\n", rgb[0], rgb[1], rgb[2]);
    s += &"ffff\n".repeat(16);
    std::fs::write(path, s).unwrap();
}

clitest!(pattern_flag_partitions_polygons_without_a_pattern, |dir| {
    // Issue 16 (8): `--pattern FILE` used to do nothing for records without
    // a "pattern": they passed through whole.
    write_pat(&dir.path().join("p.pat"), 16, |c, r| c == 1 && r == 0);
    dir.write(
        "faces.ndjson",
        "{\"id\":1,\"vertices\":[[0,0],[2,0],[2,2],[0,2]],\"color\":[1,2,3]}\n{\"id\":2,\"rect\":[10,0,12,2],\"color\":[1,2,3]}\n",
    );
    let out = dir
        .cmd("polyfill3")
        .args(["--pattern", "p.pat", "faces.ndjson"])
        .ok_stdout();
    let recs = lines(&out);
    // 4 cells each, texel (1, 0) transparent.
    assert_eq!(recs.len(), 6, "{recs:?}");
    for (i, r) in recs.iter().enumerate() {
        assert_eq!(r["id"], if i < 3 { 1 } else { 2 });
        assert_eq!(r["color"], serde_json::json!([200, 100, 50]));
        assert!(r.get("texel").is_some());
        assert!(r.get("pattern").is_none() && r.get("rect").is_none());
    }
    let total: f64 = recs.iter().map(area).sum();
    assert!((total - 6.0).abs() < 1e-12, "{total}");
    // Without --pattern they still pass through unchanged.
    let out = dir.cmd("polyfill3").arg("faces.ndjson").ok_stdout();
    assert_eq!(out, dir.read("faces.ndjson"));
});

clitest!(pattern_flag_colours_bare_records, |dir| {
    // `--pattern FILE` gives every polygon record without a texture the
    // pattern, so a record of bare geometry (no "color" either) is one it
    // colours: it was refused by the reader ("no \"color\" and no
    // \"pattern\"") before --pattern was looked at. Inside an object too; a
    // quadric, which --pattern leaves alone, still needs a colour.
    write_pat(&dir.path().join("p.pat"), 16, |c, r| c == 1 && r == 0);
    dir.write(
        "bare.ndjson",
        "{\"id\":1,\"vertices\":[[0,0],[2,0],[2,2],[0,2]]}\n\
         {\"object\":\"o\",\"records\":[{\"id\":2,\"rect\":[10,0,12,2]}]}\n\
         {\"instance\":\"o\"}\n",
    );
    let out = dir
        .cmd("polyfill3")
        .args(["--pattern", "p.pat", "bare.ndjson"])
        .ok_stdout();
    let recs = lines(&out);
    let cells: Vec<&Value> = recs.iter().filter(|r| r.get("texel").is_some()).collect();
    // 4 cells each, texel (1, 0) transparent; the object's kept whole,
    // its instance passed on.
    assert_eq!(cells.len(), 3, "{recs:?}");
    assert!(cells
        .iter()
        .all(|r| r["id"] == 1 && r["color"] == serde_json::json!([200, 100, 50])));
    let object = recs.iter().find(|r| r.get("object").is_some()).unwrap();
    let inner = object["records"].as_array().unwrap();
    assert_eq!(inner.len(), 3, "{object}");
    assert!(inner
        .iter()
        .all(|r| r["id"] == 2 && r["color"] == serde_json::json!([200, 100, 50])));
    assert!(recs.iter().any(|r| r["instance"] == "o"));

    let refused = "polyfill3: error: s.ndjson: record 0: no \"color\" and no \"pattern\": \
                   expected at least one\n";
    dir.write("s.ndjson", "{\"sphere\":{\"radius\":1}}\n");
    dir.cmd("polyfill3")
        .args(["--pattern", "p.pat", "s.ndjson"])
        .assert()
        .code(1)
        .stdout("")
        .stderr(refused);
    // Without --pattern a bare record is refused as before.
    dir.write("s.ndjson", "{\"vertices\":[[0,0],[2,0],[2,2]]}\n");
    dir.cmd("polyfill3")
        .arg("s.ndjson")
        .assert()
        .code(1)
        .stdout("")
        .stderr(refused);
});

clitest!(pattern_flag_refuses_stdin, |dir| {
    // A hostile-input review: `--pattern -` was looked up as a file named
    // `-`, and the first record that needed it failed with "-: No such file
    // or directory" (status 1) after the records before it were written.
    // Records written may name --pattern's file, so it must be a file.
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    dir.write(
        "faces.ndjson",
        "{\"id\":1,\"vertices\":[[0,0],[2,0],[2,2],[0,2]],\"color\":[1,2,3]}\n",
    );
    dir.cmd("polyfill3")
        .args(["--pattern", "-", "faces.ndjson"])
        .write_stdin(dir.read("p.pat"))
        .assert()
        .code(2)
        .stdout("")
        .stderr(
            "polyfill3: error: --pattern -: the pattern must be a file (records written may \
             name it for the renderer), not standard input\n",
        );
});

clitest!(pattern_flag_leaves_a_records_own_texture, |dir| {
    // A record's own pattern (file and placement) is kept; a stripe is a
    // texture of its own too; a quadric is left as before.
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    write_solid_pat(&dir.path().join("q.pat"), [10, 20, 30]);
    let stripe = r#"{"id":"stripe","vertices":[[0,0,0],[1,0,0],[0,1,0]],"stripe":{"map":"m.map","spacing":1,"yaw":0}}"#;
    let sphere = r#"{"id":"ball","sphere":{"radius":1,"slices":3,"stacks":2},"color":[9,9,9]}"#;
    dir.write(
        "s.ndjson",
        format!(
            "{{\"id\":\"own\",\"vertices\":[[0,0],[4,0],[4,4],[0,4]],\"pattern\":{{\"file\":\"q.pat\",\"incr\":2}}}}\n\
             {{\"id\":\"nofile\",\"vertices\":[[0,0],[4,0],[4,4],[0,4]],\"pattern\":{{\"incr\":4}}}}\n\
             {{\"id\":\"plain\",\"vertices\":[[0,0],[4,0],[4,4],[0,4]],\"color\":[1,2,3]}}\n{stripe}\n{sphere}\n"
        ),
    );
    let out = dir
        .cmd("polyfill3")
        .args(["--pattern", "p.pat", "--incr", "1", "s.ndjson"])
        .ok_stdout();
    let recs = lines(&out);
    let of = |id: &str| -> Vec<&Value> { recs.iter().filter(|r| r["id"] == id).collect() };
    let own = of("own");
    assert_eq!(own.len(), 4);
    assert!(own
        .iter()
        .all(|r| r["color"] == serde_json::json!([10, 20, 30])));
    let nofile = of("nofile");
    assert_eq!(nofile.len(), 1);
    assert_eq!(nofile[0]["color"], serde_json::json!([200, 100, 50]));
    let plain = of("plain");
    assert_eq!(plain.len(), 16);
    assert!(plain
        .iter()
        .all(|r| r["color"] == serde_json::json!([200, 100, 50])));
    // Passed through whole, its map named for a reader in another directory.
    let mut forwarded = serde_json::from_str::<Value>(stripe).unwrap();
    let map = std::fs::canonicalize(dir.path()).unwrap().join("m.map");
    forwarded["stripe"]["map"] = map.to_str().unwrap().into();
    assert_eq!(of("stripe"), vec![&forwarded]);
    let ball = of("ball");
    assert!(!ball.is_empty());
    assert!(ball
        .iter()
        .all(|r| r.get("pattern").is_none() && r["color"] == serde_json::json!([9, 9, 9])));
});

clitest!(placement_flags_apply_to_polygons_without_a_pattern, |dir| {
    // --incr, --rotate, --horz and --vert place --pattern on a plain polygon
    // exactly as the same values written in its "pattern" do.
    write_pat(&dir.path().join("p.pat"), 16, |c, r| (c + 2 * r) % 5 == 0);
    let verts = r#""vertices":[[0,0,0],[7,1,0],[6,6,0.5],[-1,5,0.5]]"#;
    dir.write(
        "plain.ndjson",
        format!("{{\"id\":5,{verts},\"color\":[1,2,3]}}\n"),
    );
    dir.write(
        "own.ndjson",
        format!("{{\"id\":5,{verts},\"pattern\":{{\"file\":\"p.pat\",\"incr\":0.7,\"rotate\":30,\"horz\":0.5,\"vert\":-0.25}}}}\n"),
    );
    let flags = [
        "--pattern",
        "p.pat",
        "--incr",
        "0.7",
        "--rotate",
        "30",
        "--horz",
        "0.5",
        "--vert",
        "-0.25",
    ];
    let plain = dir
        .cmd("polyfill3")
        .args(flags)
        .arg("plain.ndjson")
        .ok_stdout();
    let own = dir.cmd("polyfill3").arg("own.ndjson").ok_stdout();
    assert!(lines(&plain).len() > 50);
    assert_eq!(
        String::from_utf8(plain.clone()).unwrap(),
        String::from_utf8(own).unwrap()
    );
    // Each flag matters.
    for (i, changed) in [(3, "1"), (5, "0"), (7, "0"), (9, "0")] {
        let mut f = flags;
        f[i] = changed;
        let other = dir.cmd("polyfill3").args(f).arg("plain.ndjson").ok_stdout();
        assert_ne!(other, plain, "{}", flags[i - 1]);
    }
    // In objects too, and with --uv the polygon gets the pattern in uv mode.
    dir.write(
        "obj.ndjson",
        format!("{{\"object\":\"o\",\"records\":[{{\"id\":5,{verts},\"color\":[1,2,3]}}]}}\n{{\"instance\":\"o\"}}\n"),
    );
    let obj = dir
        .cmd("polyfill3")
        .args(flags)
        .arg("obj.ndjson")
        .ok_stdout();
    let obj = lines(&obj);
    assert_eq!(obj.len(), 2);
    assert_eq!(
        obj[0]["records"].as_array().unwrap().as_slice(),
        lines(&plain).as_slice()
    );
    let uv = dir
        .cmd("polyfill3")
        .args(flags)
        .args(["--uv", "plain.ndjson"])
        .ok_stdout();
    let uv = lines(&uv);
    assert_eq!(uv.len(), 1);
    assert_eq!(uv[0]["pattern"]["mode"], "uv");
    assert!(Path::new(uv[0]["pattern"]["file"].as_str().unwrap()).is_absolute());
    assert_eq!(uv[0]["uv"].as_array().unwrap().len(), 4);
});

clitest!(readme_pattern_example_cuts_plain_faces, |dir| {
    // README's `polyfill3 --pattern fixtures/patterns/brick.pat --incr 2
    // --horz -5 faces.json` and --help's `polyfill3 --pattern brick.pat
    // --incr 2 --horz -5 faces.json`, on demo 2's faces without their
    // patterns: every face is cut.
    let faces =
        std::fs::read_to_string(crate::util::repo("fixtures/scenes/demo2-faces.json")).unwrap();
    let mut plain = String::new();
    for l in faces.lines() {
        let mut v: Value = serde_json::from_str(l).unwrap();
        v.as_object_mut().unwrap().remove("pattern");
        plain += &format!("{v}\n");
    }
    dir.write("faces.json", plain);
    let brick = std::fs::read(crate::util::repo("fixtures/patterns/brick.pat")).unwrap();
    dir.write("fixtures/patterns/brick.pat", &brick);
    dir.write("brick.pat", &brick);
    let run = |pat: &str| {
        dir.cmd("polyfill3")
            .args([
                "--pattern",
                pat,
                "--incr",
                "2",
                "--horz",
                "-5",
                "faces.json",
            ])
            .ok_stdout()
    };
    let out = run("fixtures/patterns/brick.pat");
    assert_eq!(out, run("brick.pat"));
    let recs = lines(&out);
    for face in 1..=4 {
        let n = recs.iter().filter(|r| r["face"] == face).count();
        assert!(n > 1000, "face {face}: {n} cells");
    }
    assert!(recs.iter().all(|r| r.get("texel").is_some()));
});

/// Every `"file"`, `"map"` and `"colors"` (or the old `"colours"`) of a stream (recursively: object
/// definitions hold records).
fn file_refs(v: &Value, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                match (k.as_str(), x) {
                    ("file" | "map" | "colors" | "colours", Value::String(s)) => {
                        out.push(s.clone())
                    }
                    _ => file_refs(x, out),
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|x| file_refs(x, out)),
        _ => {}
    }
}

clitest!(
    forwarded_file_references_survive_a_pipe_from_elsewhere,
    |dir| {
        // Issue 16, item 4: run from a directory that is neither the scene's nor
        // the reader's, the pipe of the issue worked only from the scene's own
        // directory ("./../patterns/earth.pat: No such file").
        let reader = dir.path().join("reader");
        std::fs::create_dir(&reader).unwrap();
        for name in ["two-spheres.json", "demo2-fig51.json", "demo2-plain.json"] {
            let scene = crate::util::repo(&format!("fixtures/scenes/{name}"));
            for extra in [&[][..], &["--uv"][..]] {
                let out = dir.cmd("polyfill3").args(extra).arg(&scene).ok_stdout();
                let mut refs = Vec::new();
                for line in lines(&out) {
                    file_refs(&line, &mut refs);
                }
                // Partitioned polygons carry colours, not patterns; quadrics'
                // triangles and --uv polygons name their pattern.
                let forwards = name == "two-spheres.json" || !extra.is_empty();
                assert_eq!(!refs.is_empty(), forwards, "{name} {extra:?}");
                for r in &refs {
                    let p = std::path::Path::new(r);
                    assert!(p.is_absolute() && p.exists(), "{r}");
                    assert!(!r.contains("/./") && !r.contains("/../"), "normalised: {r}");
                }
                dir.cmd("scene-render")
                    .current_dir(&reader)
                    .args([
                        "--ortho",
                        "-80,80,-60,60,0,100",
                        "--size",
                        "40x30",
                        "-",
                        "-o",
                    ])
                    .arg(reader.join("out.png"))
                    .write_stdin(out)
                    .assert()
                    .success();
            }
        }
    }
);

clitest!(
    forwarded_file_references_are_relative_to_the_output_file,
    |dir| {
        // With -o, the output and its files move together: each name is
        // relative to the output's directory, whatever the current one.
        let scene = crate::util::repo("fixtures/scenes/two-spheres.json");
        dir.cmd("polyfill3")
            .args(["-o", "sub/deeper/out.ndjson"])
            .arg(&scene)
            .assert()
            .failure(); // the directory does not exist: nothing is written
        std::fs::create_dir_all(dir.path().join("sub/deeper")).unwrap();
        dir.cmd("polyfill3")
            .args(["-o", "sub/deeper/out.ndjson"])
            .arg(&scene)
            .assert()
            .success();
        let out = dir.read("sub/deeper/out.ndjson");
        let mut refs = Vec::new();
        for line in lines(&out) {
            file_refs(&line, &mut refs);
        }
        let patterns = std::fs::canonicalize(crate::util::repo("fixtures/patterns")).unwrap();
        let here = std::fs::canonicalize(dir.path().join("sub/deeper")).unwrap();
        assert!(!refs.is_empty());
        for r in &refs {
            assert!(std::path::Path::new(r).is_relative(), "{r}");
            let named = std::fs::canonicalize(here.join(r)).unwrap();
            assert_eq!(named.parent(), Some(patterns.as_path()), "{r}");
        }
        // Read from the repository, not from the output's directory.
        dir.cmd("scene-render")
            .current_dir(crate::util::repo("."))
            .args(["--ortho", "-80,80,-60,60,0,100", "--size", "40x30", "-o"])
            .arg(dir.path().join("o.png"))
            .arg(dir.path().join("sub/deeper/out.ndjson"))
            .assert()
            .success();
    }
);

/// Unknown fields as a user writes them: spellings serde_json would change
/// (a 30-digit integer, `1e2`, `-0`, `1.50`, `1E+2`, `-0.0`, escapes it would
/// not write), with whitespace around and inside them.
const UNKNOWN_IN: &str = r#""id": 123456789012345678901234567890, "e":1e2, "z": -0,
    "d": 1.50, "s": "caf\u00e9 \/ \"q\"\t a b", "n": [ 1E+2 , {"k" : -0.0} ]"#;

/// [`UNKNOWN_IN`] as it must come out: byte for byte, but for the whitespace
/// between tokens (strings keep theirs).
const UNKNOWN_OUT: &str = r#""id":123456789012345678901234567890,"e":1e2,"z":-0,"d":1.50,"s":"caf\u00e9 \/ \"q\"\t a b","n":[1E+2,{"k":-0.0}]"#;

/// Every kind of record polyfill3 forwards, each with the unknown fields
/// `u`: plain polygons passed through (the NDJSON fast path and the general
/// path), a polygon cut into cells, an object definition with such a polygon
/// inside, an instance, a sphere made triangles, a uv record passed through.
fn every_kind_of_record(u: &str) -> Vec<String> {
    let square = r#""vertices":[[0,0],[2,0],[2,2],[0,2]]"#;
    vec![
        format!(r#"{{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],{u}}}"#),
        format!(r#"{{"rect":[0,0,1,1],"color":[1,2,3],{u}}}"#),
        format!(r#"{{{square},"pattern":{{"file":"p.pat","incr":1}},{u}}}"#),
        format!(
            r#"{{"object":"o","records":[{{{square},"pattern":{{"file":"p.pat"}},{u}}}],{u}}}"#
        ),
        format!(r#"{{"instance":"o",{u}}}"#),
        format!(
            r#"{{"sphere":{{"radius":1,"slices":4,"stacks":2}},"pattern":{{"file":"p.pat"}},{u}}}"#
        ),
        format!(
            r#"{{"vertices":[[0,0],[1,0],[0,1]],"uv":[[0,0],[1,0],[0,1]],"pattern":{{"file":"p.pat"}},{u}}}"#
        ),
    ]
}

clitest!(unknown_fields_come_out_exactly_as_written, |dir| {
    // Issue 16 (5): an "id" of 123456789012345678901234567890 came out as
    // 1.2345678901234568e+29, `1e2` as 100.0, "\u00e9" as "é".
    write_pat(&dir.path().join("p.pat"), 16, |c, r| c == 1 && r == 0);
    let records = every_kind_of_record(UNKNOWN_IN);
    // NDJSON (one record per line: the input's own line breaks go) and a
    // JSON array, spread over lines.
    let ndjson = records
        .iter()
        .map(|r| r.replace('\n', " ") + "\n")
        .collect::<String>();
    let array = format!("[\n{}\n]\n", records.join(",\n"));
    for (name, text) in [("s.ndjson", ndjson), ("s.json", array)] {
        dir.write(name, &text);
        for uv in [false, true] {
            let mut cmd = dir.cmd("polyfill3");
            if uv {
                cmd.arg("--uv");
            }
            let out = String::from_utf8(cmd.arg(name).ok_stdout()).unwrap();
            let lines: Vec<&str> = out.lines().collect();
            let what = format!("{name}, --uv {uv}");
            // The plain polygon and the rect pass through whole (--uv writes
            // every record as a polygon, its "vertices" last).
            if !uv {
                assert_eq!(
                    lines[0],
                    format!(r#"{{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],{UNKNOWN_OUT}}}"#),
                    "{what}"
                );
                assert_eq!(
                    lines[1],
                    format!(r#"{{"rect":[0,0,1,1],"color":[1,2,3],{UNKNOWN_OUT}}}"#),
                    "{what}"
                );
            }
            let mut kinds = [0usize; 5];
            for line in &lines {
                let v: Value = serde_json::from_str(line).unwrap();
                let records = v.get("records").and_then(Value::as_array);
                // A definition carries the fields itself and in each of its
                // records (cells, or with --uv the polygon whole).
                let want = 1 + records.map_or(0, Vec::len);
                assert_eq!(line.matches(UNKNOWN_OUT).count(), want, "{what}: {line}");
                let kind = if records.is_some() {
                    0
                } else if v.get("instance").is_some() {
                    1
                } else if v.get("texel").is_some() {
                    2
                } else if v.get("uv").is_some() {
                    3
                } else {
                    4
                };
                kinds[kind] += 1;
            }
            // One definition, one instance; without --uv 3 cells of the
            // square (and 3 inside the definition); the sphere's 8 triangles,
            // the uv record and with --uv the square, written whole; the
            // polygon and the rect.
            let want = if uv {
                [1, 1, 0, 10, 2]
            } else {
                [1, 1, 3, 9, 2]
            };
            assert_eq!(kinds, want, "{what}: {out}");
        }
    }
});

clitest!(unknown_fields_may_hold_any_json, |dir| {
    // Kept as text, an unknown field may hold numbers no double holds and
    // any nesting, which the tools used to refuse as invalid JSON; known
    // fields still may not.
    let deep = format!("{}1{}", "[".repeat(500), "]".repeat(500));
    let u = format!(r#""big":1e400,"small":-1e-400,"deep":{deep}"#);
    let line = format!(r#"{{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],{u}}}"#);
    dir.write("s.ndjson", format!("{line}\n"));
    dir.write("s.json", format!("[{line}]"));
    for name in ["s.ndjson", "s.json"] {
        let out = dir.cmd("polyfill3").arg(name).ok_stdout();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            format!("{line}\n"),
            "{name}"
        );
    }
    dir.write(
        "bad.ndjson",
        r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],"transform":{"translate":[1e400,0,0]}}"#,
    );
    dir.cmd("polyfill3")
        .arg("bad.ndjson")
        .assert()
        .code(1)
        .stderr(predicates::str::contains(
            "bad.ndjson: record 0: invalid JSON",
        ));
});

clitest!(
    polyfill3_cull_needs_a_camera_given_as_a_file_or_as_flags,
    |dir| {
        // Issue 18, item 3: polyfill3 takes scene-render's camera flags.
        dir.write(
            "s.json",
            r#"{"vertices":[[0,0,0],[1,0,0],[1,1,0]],"color":[1,2,3]}"#,
        );
        dir.cmd("polyfill3")
        .args(["--cull", "s.json"])
        .assert()
        .code(2)
        .stderr("polyfill3: error: --cull needs a camera: --camera FILE, or camera flags such as --perspective and --lookat\n");
        dir.cmd("polyfill3")
            .args(["--ortho2", "0,1,0,1", "s.json"])
            .assert()
            .code(2)
            .stderr(predicates::str::contains("a camera is only used by --cull"));
        dir.cmd("polyfill3")
            .args(["--cull", "--ortho2", "0,1,0,1", "s.json"])
            .assert()
            .success();
        dir.cmd("polyfill3")
            .args(["--cull", "--perspective", "60,auto,1,10", "s.json"])
            .assert()
            .failure()
            .stderr(predicates::str::contains("polyfill3 draws no image"));
    }
);

/// Writes `input` (NDJSON records naming `solid.pat`, a one-colour
/// pattern) to a temporary directory, cuts it with polyfill3 plain, with
/// `--merge` and with `--merge=blocks`, and checks that scene-render reads
/// back every polygon each wrote.
fn every_mode_is_read_back(input: &str) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_pat(&d.join("solid.pat"), 16, |_, _| false);
    std::fs::write(d.join("input.json"), format!("{input}\n")).unwrap();
    for merge in [None, Some("--merge"), Some("--merge=blocks")] {
        polyfill3()
            .current_dir(d)
            .args(merge)
            .args(["input.json", "-o", "cells.ndjson"])
            .assert()
            .success();
        Command::cargo_bin("scene-render")
            .unwrap()
            .current_dir(d)
            .args(["--size", "32x32", "cells.ndjson", "-o", "cells.png"])
            .assert()
            .success();
    }
}

/// A polygon record of `vertices` (JSON arrays) in `solid.pat` at `incr`.
fn solid_record(vertices: &[String], incr: f64) -> String {
    format!(
        r#"{{"vertices": [{}], "color": [100, 100, 100], "pattern": {{"file": "solid.pat", "incr": {incr:?}}}}}"#,
        vertices.join(", ")
    )
}

/// A comb's walls, right to left: at each x, a vertex at `a` then one at
/// `b` (each "y, z"), the two swapping at every wall, so that the outline
/// runs up one wall and down the next.
fn comb_walls(xs: &[&str], (a, b): (&str, &str)) -> Vec<String> {
    let mut walls = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        let (first, second) = if i % 2 == 0 { (a, b) } else { (b, a) };
        walls.push(format!("[{x}, {first}]"));
        walls.push(format!("[{x}, {second}]"));
    }
    walls
}

/// Regression (review of 2026-11-29): a comb tilted 0.3 rad whose notches'
/// floors lie within rounding of a grid row. A cell there was clipped with
/// a zero-width spike up the tooth beside it (two vertices one ulp apart),
/// and scene-render refused the stream: "the polygon runs along itself".
#[test]
fn cells_beside_a_notch_on_a_grid_line_have_no_spike() {
    let (lo, hi) = (
        "3.821345956502424, 1.1820808266453582",
        "19.10672978251212, 5.910404133226791",
    );
    // Right to left: up a tooth's right side, across its top, down its
    // left side, across the floor of the notch to the next tooth.
    let xs = [
        "23.0", "20.0", "18.0", "15.0", "13.0", "10.0", "8.0", "5.0", "3.0",
    ];
    let mut vertices = vec!["[0, 0.0, 0.0]".to_string(), "[23.0, 0.0, 0.0]".to_string()];
    vertices.extend(comb_walls(&xs, (lo, hi)));
    vertices.push(format!("[0.0, {hi}]"));
    every_mode_is_read_back(&solid_record(&vertices, 0.5));
}

/// Regression (second review of 2026-11-29): a square notched to a tip on
/// a grid column, level, and 2 ulps off the column in a tilted plane. The
/// cell beside the tip holds two parts touching there; polyfill3 wrote them
/// as one ring, and scene-render refused it ("vertex 1 lies on edge 4").
/// They are now written as two polygons (`geom::partition::tidy`).
#[test]
fn notch_tips_on_a_grid_column_are_written_as_two_parts() {
    let level = [
        "[0, 0, 0]",
        "[1, 0, 0]",
        "[0.5, 0.8, 0]",
        "[1, 1, 0]",
        "[0, 1, 0]",
    ];
    let tilted = [
        "[1.1, 2.3, -7.7]",
        "[2.1, 2.3, -7.7]",
        "[1.6, 2.825435069019083, -7.537463886336264]",
        "[2.1, 3.2553364891256056, -7.404479793338661]",
        "[1.1, 3.2553364891256056, -7.404479793338661]",
    ];
    for vertices in [level, tilted] {
        let vertices: Vec<String> = vertices.iter().map(|v| v.to_string()).collect();
        every_mode_is_read_back(&solid_record(&vertices, 0.25));
    }
}

/// Regressions (reviews of 2026-11-29): inputs off their plane (within
/// `--planarity-tol`), simple as readers judge them, whose projection onto
/// the plane crosses itself. A quadrilateral whose vertices 1 and 2 are
/// 3.5e-7 apart: scene-render refused a cell ("record 2: the polygon
/// crosses itself"). A notch whose tip comes within its distance off the
/// plane of another edge: a first fix, which removed vertices, refused it.
/// polyfill3 now projects such an input along the axis readers drop
/// (`geom::partition::simple_on_plane`), and cuts it; an input it cannot
/// make simple so is cut as before.
#[test]
fn inputs_that_cross_themselves_only_once_projected_are_cut() {
    let quad = r#"{"vertices": [[1.5, 0.3, 0.0], [0.90982636, 0.545175, 0.35355339], [0.90982636, 0.545175, 0.353553], [0.6, 2.0, 1.8]], "color": [100, 100, 100], "pattern": {"file": "solid.pat", "incr": 0.5, "rotate": 270}}"#;
    let notch = r#"{"vertices": [[-1.9014292945093982, -5.67270629170941, -31260.54190259487], [-1.8849057000107814, -5.686284134770423, -31260.509178832246], [-1.8847218339996177, -5.722358576610978, -31260.52423979094], [-1.9013538296999375, -5.68750918211886, -31260.548082760488], [-1.8847665375279228, -5.713585406395296, -31260.520577027713]], "color": [100, 100, 100], "pattern": {"file": "solid.pat", "incr": 0.0017588730511829433}}"#;
    // Planar to within an ulp, 1e7 from the origin: projected along the
    // axis in world units, not relative to the plane's origin, it was
    // rounded into a crossing and refused (a second review).
    let far = r#"{"vertices": [[1229687.649887417, -377967.6252913975, -9322549.504618298], [1229687.3080317217, -377968.15223280236, -9322548.993084528], [1229687.9812379135, -377966.1656427618, -9322548.889268614], [1229687.2387476182, -377967.89497433446, -9322548.463103639], [1229687.3579517286, -377968.33759053645, -9322549.374941954]], "color": [100, 100, 100], "pattern": {"file": "solid.pat", "incr": 0.07744923178250626, "rotate": 90}}"#;
    for input in [quad, notch, far] {
        every_mode_is_read_back(input);
    }
}

/// Regression (review of 2026-11-29, after the spike fix): a comb tilted
/// 0.3 rad, an ulp or two off the grid. The pieces beside its notches were
/// simple in the plane, a staircase of ulp steps, but their world vertices
/// rounded into a fold ("record 18: the polygon runs along itself") that
/// scene-render refused. polyfill3 now writes each piece as simple as
/// readers judge it (`geom::partition::tidy`).
#[test]
fn tilted_comb_pieces_that_rounding_folds_are_written_simple() {
    let (top, floor) = (
        "8.987355423879242, -5.631358553370623",
        "3.2553364891256056, -7.404479793338661",
    );
    let mut vertices = vec![
        "[1.1, 2.3, -7.7]".to_string(),
        "[27.1, 2.3, -7.7]".to_string(),
        format!("[27.1, {top}]"),
    ];
    // Right to left: across a tooth's top, down into the notch, along its
    // floor, up the next tooth.
    let xs = [
        "25.1", "23.1", "21.1", "19.1", "17.1", "15.1", "13.1", "11.1", "9.1", "7.1", "5.1", "3.1",
    ];
    vertices.extend(comb_walls(&xs, (top, floor)));
    vertices.push(format!("[1.1, {top}]"));
    every_mode_is_read_back(&solid_record(&vertices, 1.0));
}

#[test]
fn quarter_turned_placements_cut_on_whole_numbers_and_a_turn_more_is_the_same() {
    // A 4x4 square cut in unit texels: at 0, 90, 180 and 270 degrees every
    // vertex is a whole number, as the exact sine and cosine of a quarter
    // turn give (math::sin_cos_degrees; cos 90 was 6.1e-17, which printed
    // 2.220446049250313e-16 and 0.9999999999999998 here). A turn more or
    // less cuts the same bytes.
    let dir = tempfile::tempdir().unwrap();
    write_pat(&dir.path().join("p.pat"), 16, |_, _| false);
    let square = r#"{"vertices":[[0,0,0],[4,0,0],[4,4,0],[0,4,0]],"color":[1,2,3]}"#;
    std::fs::write(dir.path().join("sq.json"), format!("{square}\n")).unwrap();
    let cut = |rotate: &str| {
        polyfill3()
            .current_dir(dir.path())
            .args([
                "--pattern",
                "p.pat",
                "--incr",
                "1",
                "--rotate",
                rotate,
                "sq.json",
            ])
            .ok_stdout()
    };
    for rotate in ["0", "90", "180", "270", "-90"] {
        let out = cut(rotate);
        let cells = lines(&out);
        assert_eq!(cells.len(), 16, "{rotate}");
        for c in &cells {
            for v in c["vertices"].as_array().unwrap() {
                for x in v.as_array().unwrap() {
                    let x = x.as_f64().unwrap();
                    assert_eq!(x, x.round(), "rotate {rotate}: {c}");
                }
            }
        }
    }
    assert_eq!(cut("450"), cut("90"));
    assert_eq!(cut("-270"), cut("90"));
    assert_eq!(cut("1170"), cut("90"));
    // No turn and whole turns, on an edge whose direction is not a unit
    // vector to the bit: 360 normalized it once more than 0 did (a review).
    let sloped = r#"{"vertices":[[0,0,0],[18,5,0],[10,20,0],[-5,10,0]],"color":[1,2,3]}"#;
    std::fs::write(dir.path().join("sq.json"), format!("{sloped}\n")).unwrap();
    for turns in ["360", "-360", "720", "-0"] {
        assert_eq!(cut(turns), cut("0"), "{turns}");
    }
}
