//! Every `--json` output has exactly the keys `docs/json.md` lists for its
//! tool, of the types it gives: the tables are parsed here, so the page and
//! the tools cannot drift apart.

use crate::util::{checker16, repo, Dir, OkStdout};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};

/// The documented keys of each tool: `## TOOL` section -> path -> type. The
/// first table (before any tool's section) holds the keys every tool has.
fn documented() -> BTreeMap<String, BTreeMap<String, String>> {
    let text = std::fs::read_to_string(repo("docs/json.md")).unwrap();
    let mut tools: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    let mut section = String::from("*");
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            section = h.trim().trim_matches('`').to_string();
            continue;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 4 || !cells[1].starts_with('`') {
            continue;
        }
        let path = cells[1].trim_matches('`').to_string();
        let previous = tools
            .entry(section.clone())
            .or_default()
            .insert(path.clone(), cells[2].to_string());
        assert!(previous.is_none(), "docs/json.md: {path} listed twice");
    }
    let common = tools.remove("*").expect("the keys of every tool");
    for keys in tools.values_mut() {
        keys.extend(common.clone());
    }
    tools
}

/// Every key path of a JSON value (`a.b`, `a[].b`) with the values found there.
fn paths<'a>(v: &'a Value, prefix: &str, out: &mut BTreeMap<String, Vec<&'a Value>>) {
    match v {
        Value::Object(o) => {
            for (k, x) in o {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                out.entry(p.clone()).or_default().push(x);
                paths(x, &p, out);
            }
        }
        Value::Array(a) => {
            for x in a.iter().filter(|x| x.is_object()) {
                paths(x, &format!("{prefix}[]"), out);
            }
        }
        _ => {}
    }
}

/// Whether `v` has the documented type (`integer`, `number`, `string`,
/// `boolean`, `object`, `array ...`, any of them `... or null`).
fn has_type(v: &Value, ty: &str) -> bool {
    if v.is_null() {
        return ty.ends_with(" or null");
    }
    let ty = ty.trim_end_matches(" or null");
    match ty.split(' ').next().unwrap() {
        "integer" => v.is_u64() || v.is_i64(),
        "number" => v.is_number(),
        "string" => v.is_string(),
        "boolean" => v.is_boolean(),
        "object" => v.is_object(),
        "array" => v.is_array(),
        other => panic!("docs/json.md: unknown type {other:?}"),
    }
}

/// Checks a tool's outputs against its section: each key documented and of
/// its type, and every documented key in some output.
fn check(tool: &str, outputs: &[Vec<u8>]) {
    let docs = documented();
    let keys = docs
        .get(tool)
        .unwrap_or_else(|| panic!("docs/json.md has no section {tool}"));
    let values: Vec<Value> = outputs
        .iter()
        .map(|o| serde_json::from_slice(o).unwrap_or_else(|e| panic!("{tool}: {e}")))
        .collect();
    let mut seen = BTreeSet::new();
    for v in &values {
        assert_eq!(v["version"], 1, "{tool}: {v}");
        assert_eq!(v["tool"], tool, "{v}");
        let mut found = BTreeMap::new();
        paths(v, "", &mut found);
        for (path, vals) in found {
            let ty = keys
                .get(&path)
                .unwrap_or_else(|| panic!("{tool}: {path} is not in docs/json.md"));
            for x in vals {
                assert!(has_type(x, ty), "{tool}: {path} = {x}: documented as {ty}");
            }
            seen.insert(path);
        }
    }
    let missing: Vec<&String> = keys.keys().filter(|k| !seen.contains(*k)).collect();
    assert!(
        missing.is_empty(),
        "{tool}: documented in docs/json.md but in no output: {missing:?}"
    );
}

/// A stripe texture record: with `"plane"`, and a colour code and a blend
/// to the next face colour when `code`.
fn striped(code: bool) -> String {
    let face = if code {
        r#", "code": 4, "next_code": 9, "blend": 1"#
    } else {
        ""
    };
    format!(
        r#"{{"vertices": [[0,0,0],[4,0,0],[4,0,-4],[0,0,-4]], "color": [9,9,9], "stripe": {{"map": "m.map", "spacing": 1, "plane": "yz", "theta": 30{face}}}}}"#
    )
}

clitest!(json_outputs_have_exactly_the_documented_keys, |dir| {
    pat_info(&dir);
    polyfill3(&dir);
    scene_render(&dir);
});

fn pat_info(dir: &Dir) {
    dir.write("c.pat", checker16());
    dir.write(
        "m.map",
        std::fs::read(repo("fixtures/stripes/furrow.map")).unwrap(),
    );
    let plain = striped(false);
    let coded = striped(true);
    dir.write(
        "s.json",
        format!(
            "{coded}\n{{\"object\": \"o\", \"records\": [{plain}]}}\n{{\"instance\": \"o\"}}\n"
        ),
    );
    let run = |args: &[&str]| dir.cmd("pat-info").args(args).ok_stdout();
    check(
        "pat-info",
        &[
            run(&["--json", "--at", "0,0", "c.pat"]),
            run(&["--json", "--at", "1,0", "c.pat", "m.map"][..4]),
            run(&["--json", "c.pat", "m.map"]),
            run(&["--json", "--record", "0", "s.json"]),
            run(&["--json", "--record", "1", "s.json"]),
            run(&["--json", "--record", "2", "s.json"]),
        ],
    );
}

fn polyfill3(dir: &Dir) {
    dir.write("c.pat", checker16());
    dir.write(
        "p.json",
        r#"[{"vertices": [[0,0],[3,0],[3,3]], "pattern": {"file": "c.pat"}}, {"rect": [0,0,1,1], "color": [1,2,3]}]"#,
    );
    let out = dir
        .cmd("polyfill3")
        .args(["--json", "p.json", "-o", "cells.ndjson"])
        .assert()
        .success();
    check("polyfill3", &[out.get_output().stderr.clone()]);
}

fn scene_render(dir: &Dir) {
    dir.write(
        "r.json",
        r#"{"rect": [2,2,20,14], "color": [200,30,30]}
{"circle": {"center": [24,12], "radius": 6}, "color": [30,200,30]}
"#,
    );
    // --size shapes a render: with --image (which measures) it is refused.
    let run = |args: &[&str]| {
        let size: &[&str] = if args.contains(&"--image") {
            &[]
        } else {
            &["--size", "32x24"]
        };
        dir.cmd("scene-render").args(size).args(args).ok_stdout()
    };
    let reference = run(&["--reference", "--json", "r.json", "-o", "ref.png"]);
    run(&["r.json", "-o", "me.png"]);
    let compare = run(&["--image", "me.png", "--compare", "ref.png", "--json"]);
    // A deep image (PFM, linear light) adds the linear-light errors and
    // what was compared.
    run(&["r.json", "-o", "lin.pfm"]);
    let deep = run(&["--image", "me.png", "--compare", "lin.pfm", "--json"]);
    let frames = run(&["--json", "--frames", "2", "r.json", "-o", "f-%d.png"]);
    let v: Value = serde_json::from_slice(&frames).unwrap();
    assert_eq!(v["frames"].as_array().map(Vec::len), Some(2), "{v}");
    assert_eq!(v["frames"][1]["frame"], 1, "{v}");
    // A one-texel checker ground to its horizon: fragments over more than
    // MAX_EXACT_CELLS cells are estimated, and the report says so.
    dir.write("c.pat", checker16());
    dir.write(
        "h.json",
        r#"{"vertices": [[-20000,0,20000],[20000,0,20000],[20000,0,-20000],[-20000,0,-20000]], "pattern": {"file": "c.pat", "incr": 1}}"#,
    );
    let view = [
        "--perspective",
        "60,auto,0.5,100000",
        "--lookat",
        "0,3,0,0,3,-100",
        "--size",
        "64x36",
        "h.json",
    ];
    let plain = dir
        .cmd("scene-render")
        .args(view)
        .args(["-o", "h.png"])
        .output()
        .unwrap();
    assert!(plain.status.success(), "{plain:?}");
    let horizon = dir
        .cmd("scene-render")
        .args(view)
        .args(["--compare", "h.png", "--json"])
        .output()
        .unwrap();
    assert!(horizon.status.success(), "{horizon:?}");
    for out in [&plain, &horizon] {
        let err = String::from_utf8_lossy(&out.stderr);
        let cells = patkit::texture::cells::MAX_EXACT_CELLS;
        assert!(
            err.contains(&format!(
                "too fine to integrate exactly (more than {cells} texel cells"
            )),
            "{err}"
        );
    }
    let v: Value = serde_json::from_slice(&horizon.stdout).unwrap();
    assert!(v["estimated"]["fragments"].as_u64() > Some(0), "{v}");
    assert!(v["estimated"]["bound_codes"].as_u64() > Some(0), "{v}");
    let horizon_frames = dir
        .cmd("scene-render")
        .args(view)
        .args(["--frames", "2", "-o", "hf-%d.png", "--json"])
        .output()
        .unwrap();
    assert!(horizon_frames.status.success(), "{horizon_frames:?}");
    let v: Value = serde_json::from_slice(&horizon_frames.stdout).unwrap();
    assert!(
        v["frames"][1]["estimated"]["fragments"].as_u64() > Some(0),
        "{v}"
    );
    check(
        "scene-render",
        &[
            reference,
            compare,
            deep,
            frames,
            horizon.stdout,
            horizon_frames.stdout,
        ],
    );
}

clitest!(
    scene_render_json_with_frames_on_standard_output_goes_to_standard_error,
    |dir| {
        dir.write("r.json", r#"{"rect": [2,2,20,14], "color": [200,30,30]}"#);
        let out = dir
            .cmd("scene-render")
            .args(["--size", "32x24", "--json"])
            .args(["--frames", "3", "--frame", "2", "r.json", "-o", "-"])
            .assert()
            .success();
        let o = out.get_output();
        assert!(
            o.stdout.starts_with(b"P6"),
            "a PPM frame on standard output"
        );
        let v: Value = serde_json::from_slice(&o.stderr).unwrap();
        assert_eq!(v["frames"][0]["frame"], 2, "{v}");
        assert_eq!(v["frames"].as_array().map(Vec::len), Some(1), "{v}");
    }
);

clitest!(
    an_old_colours_key_is_read_with_a_warning_naming_colors,
    |dir| {
        dir.write(
            "m.map",
            std::fs::read(repo("fixtures/stripes/furrow.map")).unwrap(),
        );
        dir.write(
            "t.ct",
            std::fs::read(repo("fixtures/stripes/terrain.ct")).unwrap(),
        );
        let record = |key: &str| {
            format!(
                r#"{{"vertices": [[0,0,0],[4,0,0],[4,0,-4],[0,0,-4]], "stripe": {{"map": "m.map", "spacing": 1, "yaw": 0, "code": 1, "{key}": "t.ct"}}}}"#
            )
        };
        dir.write("new.json", record("colors"));
        dir.write(
            "old.json",
            format!("{}\n{}\n", record("colours"), record("colours")),
        );
        let face = |file: &str| {
            let out = dir
                .cmd("pat-info")
                .args(["--json", "--record", "0", file])
                .assert()
                .success();
            let o = out.get_output();
            let v: Value = serde_json::from_slice(&o.stdout).unwrap();
            (
                v["records"][0]["color"]["hex"].clone(),
                String::from_utf8(o.stderr.clone()).unwrap(),
            )
        };
        let (new, quiet) = face("new.json");
        let (old, warned) = face("old.json");
        assert_eq!(new, old, "both spellings name the same table");
        assert_eq!(quiet, "");
        assert_eq!(
        warned,
        "pat-info: warning: record 0: \"colours\" in \"stripe\" is the old spelling of \"colors\": it is read, but write \"colors\"\n"
    );
        // scene-render reads it too, and says so once per run.
        let out = dir
            .cmd("scene-render")
            .args(["--size", "16x16", "--perspective", "60,1,0.1,100"])
            .args(["--lookat", "2,3,3,2,0,-2", "old.json", "-o", "o.png"])
            .assert()
            .success();
        let err = String::from_utf8(out.get_output().stderr.clone()).unwrap();
        assert_eq!(err.matches("old spelling").count(), 1, "{err}");
    }
);
