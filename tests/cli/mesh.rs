//! Wavefront OBJ meshes in the stream (issue 23, item 2): `{"mesh": {"obj":
//! FILE}}` records drawn, instanced, transformed, partitioned and refused
//! with the file and line named.

use crate::util::{checker16, repo, Dir, OkStdout};
use predicates::prelude::*;
use serde_json::Value;

/// `scene-render --image A --compare B --json`'s "compare" object.
fn compare(dir: &Dir, image: &str, reference: &str) -> Value {
    let out = dir
        .cmd("scene-render")
        .args(["--image", image, "--compare", reference, "--json"])
        .ok_stdout();
    serde_json::from_slice::<Value>(&out).unwrap()["compare"].clone()
}

const HOUSE_VIEW: [&str; 6] = [
    "--perspective",
    "40,auto,1,500",
    "--lookat",
    "30,25,60,0,10,0",
    "--size",
    "240x180",
];

clitest!(the_house_model_renders_as_the_reference_does, |dir| {
    let scene = repo("fixtures/scenes/house.json");
    for (extra, out) in [(None, "house.png"), (Some("--reference"), "ref.png")] {
        dir.cmd("scene-render")
            .args(HOUSE_VIEW)
            .args(extra)
            .arg(&scene)
            .args(["-o", out])
            .assert()
            .success();
    }
    // Measured: identical (the faces are flat-lit by their normals, the
    // walls' image texture integrated exactly).
    let c = compare(&dir, "house.png", "ref.png");
    assert_eq!(c["largest_error"], 0, "{c}");
    // The marble walls (grey-white) and the red roof both show.
    let img = image::load_from_memory(&dir.read("house.png"))
        .unwrap()
        .to_rgb8();
    let reds = img
        .pixels()
        .filter(|p| p.0[0] > 150 && p.0[1] < 90 && p.0[2] < 70)
        .count();
    let marble = img
        .pixels()
        .filter(|p| p.0[0] > 180 && p.0[1] > 180 && p.0[2] > 180)
        .count();
    assert!(reds > 1000 && marble > 1000, "{reds} red, {marble} marble");
});

/// A unit square of two triangles and a quad face, with texture
/// coordinates, in `dir/m/sq.obj`.
fn square(dir: &Dir) {
    dir.write(
        "m/sq.obj",
        "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n",
    );
}

clitest!(
    a_mesh_is_an_object_its_instances_and_transforms_place,
    |dir| {
        square(&dir);
        dir.write("m/c.pat", checker16());
        let view = ["--ortho", "0,32,0,16,-10,10", "--size", "64x32"];
        // Top level with a transform, and the same mesh inside an object placed
        // by an instance with that transform: the same bytes.
        let pattern = r#""pattern": {"file": "m/c.pat", "mode": "uv"}"#;
        dir.write(
        "top.json",
        format!(
            r#"{{"mesh": {{"obj": "m/sq.obj"}}, {pattern}, "transform": {{"translate": [2, 3, 0]}}}}"#
        ),
    );
        dir.write(
        "object.json",
        format!(
            "{{\"object\": \"sq\", \"records\": [{{\"mesh\": {{\"obj\": \"m/sq.obj\"}}, {pattern}}}]}}\n\
             {{\"instance\": \"sq\", \"transform\": {{\"translate\": [2, 3, 0]}}}}\n\
             {{\"instance\": \"sq\", \"transform\": [{{\"scale\": 2}}, {{\"translate\": [16, 4, 0]}}]}}\n"
        ),
    );
        for (scene, out) in [("top.json", "top.png"), ("object.json", "object.png")] {
            dir.cmd("scene-render")
                .args(view)
                .args([scene, "-o", out])
                .assert()
                .success()
                .stderr("");
        }
        let (top, object) = (
            image::load_from_memory(&dir.read("top.png"))
                .unwrap()
                .to_rgba8(),
            image::load_from_memory(&dir.read("object.png"))
                .unwrap()
                .to_rgba8(),
        );
        // The first instance draws exactly what the top-level mesh draws.
        for y in 0..32 {
            for x in 0..20 {
                assert_eq!(top.get_pixel(x, y), object.get_pixel(x, y), "({x}, {y})");
            }
        }
        // The second, twice the size, is drawn too.
        assert!(object.get_pixel(48, 16).0[3] == 255);
        assert!(top.get_pixel(48, 16).0[3] == 0 || top.get_pixel(48, 16).0[..3] == [0, 0, 0]);
        // An animated transform turns it frame by frame.
        dir.write(
        "spin.json",
        r#"{"mesh": {"obj": "m/sq.obj"}, "color": [200, 20, 20], "transform": [{"rotate": {"start": 0, "step": 45}, "axis": "z"}, {"translate": [16, 8, 0]}]}"#,
    );
        dir.cmd("scene-render")
            .args(view)
            .args(["--frames", "2", "spin.json", "-o", "f%d.png"])
            .assert()
            .success();
        assert_ne!(dir.read("f0.png"), dir.read("f1.png"));
    }
);

clitest!(polyfill3_cuts_a_patterned_mesh_into_texel_polygons, |dir| {
    square(&dir);
    dir.write("c.pat", checker16());
    dir.write(
        "s.json",
        r#"{"mesh": {"obj": "m/sq.obj"}, "pattern": {"file": "c.pat", "incr": 0.5}, "transform": {"translate": [4, 4, 0]}}"#,
    );
    // With -o, the report goes to standard error (docs/json.md).
    let out = dir
        .cmd("polyfill3")
        .args(["s.json", "--json", "-o", "cells.ndjson"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: Value = serde_json::from_slice(&out.stderr).unwrap();
    assert_eq!(v["objects"], 1, "{v}");
    assert_eq!(v["instances"], 1, "{v}");
    // Two triangles of 8 x 8 texels each: at least 64 cells.
    assert!(v["polygons"].as_u64().unwrap() >= 64, "{v}");
    let view = ["--ortho", "0,12,0,12,-10,10", "--size", "96x96"];
    for (scene, out) in [("s.json", "direct.png"), ("cells.ndjson", "piped.png")] {
        dir.cmd("scene-render")
            .args(view)
            .args([scene, "-o", out])
            .assert()
            .success();
    }
    let c = compare(&dir, "piped.png", "direct.png");
    assert!(c["rmse"].as_f64().unwrap() < 0.5, "{c}");
});

/// The colour `scene-render` draws at the middle of `m/sq.obj` under the
/// record `record`, seen whole.
fn middle_colour(dir: &Dir, record: &str) -> [u8; 3] {
    dir.write("s.json", record);
    dir.cmd("scene-render")
        .args(["--ortho", "0,4,0,4,-10,10", "--size", "8x8"])
        .args(["s.json", "-o", "s.png"])
        .assert()
        .success()
        .stderr("");
    let img = image::load_from_memory(&dir.read("s.png"))
        .unwrap()
        .to_rgb8();
    img.get_pixel(4, 4).0
}

const RED_PPM: &str = "P3 2 2 255 255 0 0 255 0 0 255 0 0 255 0 0\n";
const BLUE_PPM: &str = "P3 2 2 255 0 0 255 0 0 255 0 0 255 0 0 255\n";

clitest!(map_kd_names_the_file_after_its_options_spaces_kept, |dir| {
    // A hostile-input review: `map_Kd my tex.ppm` took the last word, so
    // with `tex.ppm` beside `my tex.ppm` the mesh was drawn blue, status 0.
    dir.write(
        "m/sq.obj",
        "mtllib sq.mtl\nv 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         usemtl t\nf 1/1 2/2 3/3 4/4\n",
    );
    dir.write("m/my tex.ppm", RED_PPM);
    dir.write("m/tex.ppm", BLUE_PPM);
    for map in [
        "map_Kd my tex.ppm",
        "map_Kd -blendu off -o 0 0 0 -s 1 1 1 -clamp off my tex.ppm  ",
    ] {
        dir.write("m/sq.mtl", format!("newmtl t\n{map}\n"));
        let c = middle_colour(&dir, r#"{"mesh": {"obj": "m/sq.obj"}}"#);
        assert!(c[0] > 200 && c[2] < 50, "{map:?}: {c:?}");
    }
    // An option this renderer does not draw is refused, not skipped: the
    // texture was drawn unshifted and unscaled.
    dir.write(
        "m/sq.mtl",
        "newmtl t\nmap_Kd -o 0.5 0.5 0 -s 0.5 0.5 1 tex.ppm\n",
    );
    dir.write("s.json", r#"{"mesh": {"obj": "m/sq.obj"}}"#);
    for tool in ["scene-render", "polyfill3"] {
        dir.cmd(tool)
            .args(["s.json", "-o", "out"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains(
                "record 0: mesh.obj: ./m/sq.mtl:2: map_Kd: -o 0.5 0.5 0: offsetting the texture \
                 (apply the offset to the vt coordinates) is not implemented",
            ));
        assert!(!dir.path().join("out").exists());
    }
});

clitest!(mtllib_reads_every_file_it_names, |dir| {
    // `mtllib a.mtl b.mtl` was one name: "./a.mtl b.mtl: No such file".
    let obj = |mtllib: &str| {
        format!(
            "mtllib {mtllib}\nv 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nvt 0 0\nvt 1 0\nvt 1 1\n\
             vt 0 1\nusemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 4/4\n"
        )
    };
    dir.write("m/a.mtl", "newmtl a\nKd 1 0 0\n");
    dir.write("m/b.mtl", "newmtl b\nmap_Kd blue.ppm\n");
    dir.write("m/blue.ppm", BLUE_PPM);
    dir.write("m/sq.obj", obj("a.mtl b.mtl"));
    dir.write("s.json", r#"{"mesh": {"obj": "m/sq.obj"}}"#);
    dir.cmd("scene-render")
        .args(["--ortho", "0,4,0,4,-10,10", "--size", "8x8"])
        .args(["s.json", "-o", "s.png", "--depfile", "s.d"])
        .assert()
        .success()
        .stderr("");
    let img = image::load_from_memory(&dir.read("s.png"))
        .unwrap()
        .to_rgb8();
    // Below the diagonal a's red, above it b's blue texture.
    let (red, blue) = (img.get_pixel(6, 6).0, img.get_pixel(1, 1).0);
    assert!(red[0] > 200 && red[2] < 50, "{red:?}");
    assert!(blue[2] > 200 && blue[0] < 50, "{blue:?}");
    let deps = String::from_utf8(dir.read("s.d")).unwrap();
    assert!(
        deps.contains("m/a.mtl") && deps.contains("m/b.mtl"),
        "{deps}"
    );
    // A file named by the whole line, spaces and all, is that one file.
    dir.write("m/a.mtl b.mtl", "newmtl a\nKd 0 1 0\nnewmtl b\nKd 0 1 0\n");
    let c = middle_colour(&dir, r#"{"mesh": {"obj": "m/sq.obj"}}"#);
    assert!(c[1] > 200 && c[0] < 50 && c[2] < 50, "{c:?}");
    // One of the names missing: that one is named.
    dir.write("m/sq.obj", obj("a.mtl gone.mtl"));
    dir.cmd("scene-render")
        .args(["s.json", "-o", "out.png"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "record 0: mesh.obj: ./m/sq.obj:1: mtllib a.mtl gone.mtl: ./m/gone.mtl: No such file \
             or directory (os error 2) (one of 2 names on the line; no file ./m/a.mtl gone.mtl \
             either)",
        ));
});

clitest!(bad_meshes_are_refused_naming_the_file_and_line, |dir| {
    dir.write("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    for (obj, record, needle) in [
        (
            "v 0 0 0\nv 1 0 0\nf 1 2 3\n",
            r#"{"mesh": {"obj": "bad.obj"}}"#,
            "record 0: mesh.obj: ./bad.obj:3: f: `3`: vertex index 3 out of range: 2 vertices defined before this line",
        ),
        (
            "v 0 0 nan\n",
            r#"{"mesh": {"obj": "bad.obj"}}"#,
            "record 0: mesh.obj: ./bad.obj:1: v: `nan` is not a finite number",
        ),
        (
            "mtllib gone.mtl\n",
            r#"{"mesh": {"obj": "bad.obj"}}"#,
            "record 0: mesh.obj: ./bad.obj:1: mtllib gone.mtl: ./gone.mtl: No such file",
        ),
        (
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl t\nf 1 2 3\n",
            r#"{"mesh": {"obj": "bad.obj"}}"#,
            // The map_Kd's own line, in the .mtl (it named the face).
            "record 0: mesh.obj: ./m.mtl:2: map_Kd: ./nothing.png: No such file",
        ),
        (
            "v 0 0 0\nf 1 1 1\n",
            r#"{"color": [1,2,3], "mesh": {"obj": "nowhere.obj"}}"#,
            "record 0: mesh.obj: ./nowhere.obj: No such file",
        ),
        (
            "",
            r#"{"mesh": {"obj": "ok.obj"}, "vertices": [[0,0],[1,0],[0,1]]}"#,
            "record 0: mesh: a mesh is its own geometry, found \"vertices\" beside it",
        ),
        (
            "",
            r#"{"mesh": {"file": "ok.obj"}}"#,
            "record 0: mesh.file: unknown key: expected obj",
        ),
        (
            "",
            r#"{"mesh": {"obj": "/dev/zero"}}"#,
            "record 0: mesh.obj: /dev/zero: is not a regular file",
        ),
        (
            "",
            r#"{"object": "o", "records": [{"mesh": {"obj": "bad.obj"}}]}"#,
            "record 0: object `o` records[0]: mesh.obj: ./bad.obj: no faces",
        ),
        // Kept as unknown fields, these did nothing; a mesh's "instance"
        // made polyfill3 write an instance of another object.
        (
            "",
            r#"{"mesh": {"obj": "ok.obj"}, "stripe": {"map": "missing.map", "spacing": 1, "yaw": 0}}"#,
            "record 0: mesh: a mesh takes no \"stripe\": it would be dropped",
        ),
        (
            "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1e306 0\nvt 0 1\nusemtl t\nf 1/1 2/2 3/3\n",
            r#"{"mesh": {"obj": "bad.obj"}}"#,
            "record 0: mesh.obj: ./bad.obj:9: f: vt 1e306 0, times the texture's 2x2 texels, is beyond ±1e100 texels",
        ),
        (
            "",
            r#"{"mesh": {"obj": "ok.obj"}, "instance": "b"}"#,
            "record 0: mesh: a mesh takes no \"instance\"",
        ),
        (
            "",
            r#"{"object": "o", "records": [{"mesh": {"obj": "ok.obj"}, "transform": {"translate": [1, 0, 0]}}]}"#,
            "record 0: object `o` records[0]: mesh: a mesh inside an object takes no \"transform\"",
        ),
    ] {
        dir.write("bad.obj", obj);
        dir.write("m.mtl", "newmtl t\nmap_Kd nothing.png\n");
        dir.write("t.mtl", "newmtl t\nmap_Kd t.ppm\n");
        dir.write("t.ppm", "P3 2 2 255 0 0 0 0 0 0 0 0 0 0 0 0\n");
        dir.write("s.json", record);
        for tool in ["scene-render", "polyfill3"] {
            dir.cmd(tool)
                .args(["s.json", "-o", "out"])
                .assert()
                .code(1)
                .stderr(predicate::str::contains(needle));
            assert!(!dir.path().join("out").exists());
        }
    }
    // A model over the mesh limit is refused before a face is made: a
    // 1,000,001-corner face is 999,999 triangles, one more face passes it.
    let mut huge = String::new();
    for k in 0..1_000_001u32 {
        huge.push_str(&format!("v {} {} 0\n", k % 1000, k / 1000));
    }
    huge.push('f');
    for k in 1..=1_000_001u32 {
        huge.push_str(&format!(" {k}"));
    }
    huge.push_str("\nf 1 2 3\nf 1 2 3\n");
    dir.write("huge.obj", huge);
    dir.write(
        "s.json",
        r#"{"mesh": {"obj": "huge.obj"}, "color": [9, 9, 9]}"#,
    );
    dir.cmd("scene-render")
        .args(["s.json", "-o", "out.png"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "f: more than 1000000 triangles, over the most one mesh may have",
        ));
    // A model with more faces than the polygon budget is refused when read.
    let mut big = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..50 {
        big.push_str("f 1 2 3\n");
    }
    dir.write("big.obj", big);
    dir.write(
        "s.json",
        r#"{"mesh": {"obj": "big.obj"}, "color": [9, 9, 9]}"#,
    );
    dir.cmd("scene-render")
        .args(["--max-polygons", "20", "s.json", "-o", "out.png"])
        .assert()
        .code(1)
        .stderr(
            predicate::str::contains("50 polygons")
                .and(predicate::str::contains("over the limit of 20")),
        );
});
