//! docs/conventions.md's table, checked cell by cell (issue 18, item 3):
//! each notion has one check, run for every tool whose cell says `yes` (the
//! tool does it) or `no` (it refuses it as a usage error); `—` is skipped.

use crate::util::{checker16, repo, Dir};
use std::process::{Command, Output, Stdio};

const TOOLS: [&str; 5] = [
    "pat-from-image",
    "pat-info",
    "pat-tile",
    "polyfill3",
    "scene-render",
];

/// The table: (notion key, one cell per tool in [`TOOLS`] order).
fn table() -> Vec<(String, Vec<String>)> {
    let text = std::fs::read_to_string(repo("docs/conventions.md")).unwrap();
    let mut rows = Vec::new();
    let mut header_seen = false;
    for line in text.lines().filter(|l| l.starts_with('|')) {
        // Split on `|` not escaped as `\|`.
        let cells: Vec<String> = line
            .replace("\\|", "\u{0}")
            .split('|')
            .map(|c| c.trim().replace('\u{0}', "|"))
            .collect();
        let cells = &cells[1..cells.len() - 1];
        if !header_seen {
            assert_eq!(cells[1..], TOOLS.map(String::from), "the table's columns");
            header_seen = true;
            continue;
        }
        if cells[0].starts_with("---") {
            continue;
        }
        let key = cells[0]
            .strip_prefix('`')
            .and_then(|c| c.split_once('`'))
            .map(|(k, _)| k.to_string())
            .unwrap_or_else(|| panic!("a notion starts with its `key`: {line}"));
        rows.push((key, cells[1..].to_vec()));
    }
    rows
}

/// What a tool needs to run once: its arguments for an input file, the
/// input's bytes, a bad input's bytes, and the extension of its output.
struct Job {
    tool: &'static str,
    input: Vec<u8>,
    bad: Vec<u8>,
    out_ext: &'static str,
    /// Extra arguments that make the output large (over a pipe's buffer),
    /// for the closed-pipe check.
    large: &'static [&'static str],
    /// What `--json` needs beside it (scene-render reports on a measurement).
    json: &'static [&'static str],
}

fn job(tool: &'static str, dir: &Dir) -> Job {
    let pat = checker16().into_bytes();
    let stream = br#"{"vertices":[[0,0,0],[60,0,0],[60,60,0],[0,60,0]],"color":[9,9,9],"pattern":{"file":"p.pat","incr":0.5}}"#.to_vec();
    dir.write("p.pat", checker16());
    match tool {
        "pat-from-image" => Job {
            tool,
            input: std::fs::read(repo("fixtures/images/brick.png")).unwrap(),
            bad: b"not a picture".to_vec(),
            out_ext: "pat",
            large: &["--size", "512", "--colors", "64"],
            json: &[],
        },
        "pat-info" => Job {
            tool,
            input: pat,
            bad: b"16 two\n".to_vec(),
            out_ext: "",
            large: &["--json"],
            json: &[],
        },
        "pat-tile" => Job {
            tool,
            input: pat,
            bad: b"16 two\n".to_vec(),
            out_ext: "png",
            large: &[
                "--size",
                "1024x1024",
                "--format",
                "ppm",
                "--background",
                "0,0,0",
            ],
            json: &[],
        },
        "polyfill3" => Job {
            tool,
            input: stream,
            bad: br#"{"vertices":1}"#.to_vec(),
            out_ext: "ndjson",
            large: &[],
            json: &[],
        },
        "scene-render" => Job {
            tool,
            input: stream,
            bad: br#"{"vertices":1}"#.to_vec(),
            out_ext: "png",
            large: &["--size", "1024x1024", "--format", "ppm"],
            json: &["--reference"],
        },
        other => panic!("no job for {other}"),
    }
}

fn bin(tool: &str) -> std::path::PathBuf {
    assert_cmd::cargo::cargo_bin(tool)
}

/// Runs `tool args` in `dir` with `stdin` (nothing if `None`).
fn run(dir: &Dir, tool: &str, args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut c = Command::new(bin(tool));
    c.args(args).current_dir(dir.path());
    c.stdin(if stdin.is_some() {
        Stdio::piped()
    } else {
        Stdio::null()
    });
    c.stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = c.spawn().unwrap();
    if let Some(bytes) = stdin {
        use std::io::Write;
        let mut w = child.stdin.take().unwrap();
        // A tool may refuse before reading it all.
        let _ = w.write_all(bytes);
    }
    child.wait_with_output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The check of one notion for one tool; `yes` says which way it must hold.
fn check(key: &str, j: &Job, yes: bool, dir: &Dir) {
    let tool = j.tool;
    dir.write("in", &j.input);
    dir.write("bad", &j.bad);
    let ok = |o: &Output, what: &str| {
        assert!(
            o.status.success(),
            "{tool} {key}: {what}: {}",
            text(&o.stderr)
        )
    };
    let usage = |o: &Output, what: &str| {
        assert_eq!(o.status.code(), Some(2), "{tool} {key}: {what}");
        assert!(o.stdout.is_empty(), "{tool} {key}: {what}: output");
        assert!(
            text(&o.stderr).starts_with(&format!("{tool}: error: ")),
            "{tool} {key}: {}",
            text(&o.stderr)
        );
    };
    match (key, yes) {
        ("stdin-dash", true) => {
            let o = run(dir, tool, &["-"], Some(&j.input));
            ok(&o, "`-`");
            assert!(!o.stdout.is_empty(), "{tool}: nothing written");
        }
        ("stdin-default", true) => {
            let o = run(dir, tool, &[], Some(&j.input));
            ok(&o, "no input");
            assert!(!o.stdout.is_empty(), "{tool}: nothing written");
        }
        ("stdout-default", true) => {
            let o = run(dir, tool, &["in"], None);
            ok(&o, "no -o");
            assert!(!o.stdout.is_empty(), "{tool}: nothing on standard output");
        }
        ("atomic-output", true) => {
            let out = format!("out.{}", j.out_ext);
            let before = dir.files();
            let o = run(dir, tool, &["bad", "-o", &out], None);
            assert_eq!(o.status.code(), Some(1), "{tool}: {}", text(&o.stderr));
            assert_eq!(dir.files(), before, "{tool} left files behind");
        }
        ("error-line", true) => {
            let o = run(dir, tool, &["missing-file"], None);
            assert_eq!(o.status.code(), Some(1));
            let err = text(&o.stderr);
            assert!(
                err.starts_with(&format!("{tool}: error: missing-file"))
                    && err.lines().count() == 1,
                "{tool}: {err}"
            );
        }
        ("usage-exit-2", true) => {
            usage(&run(dir, tool, &["--no-such-flag"], None), "--no-such-flag")
        }
        ("help-examples", true) => {
            let o = run(dir, tool, &["--help"], None);
            ok(&o, "--help");
            assert!(text(&o.stdout).contains("Examples:"), "{tool} --help");
        }
        ("version", true) => {
            let o = run(dir, tool, &["--version"], None);
            ok(&o, "--version");
            assert_eq!(
                text(&o.stdout),
                format!("{tool} {}\n", env!("CARGO_PKG_VERSION"))
            );
        }
        ("closed-pipe", true) => {
            // The tool's status, from the shell, with `head` reading one byte.
            let files = if tool == "pat-info" {
                vec!["in"; 3000].join(" ")
            } else {
                "in".to_string()
            };
            let script = format!(
                "('{}' {} {files}; echo \"status $?\" >&2) | head -c 1 >/dev/null",
                bin(tool).display(),
                j.large.join(" ")
            );
            let o = Command::new("sh")
                .args(["-c", &script])
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert_eq!(text(&o.stderr), "status 0\n", "{tool}");
        }
        ("json-versioned", true) => {
            let with = |extra: &[&str]| {
                let mut args = vec!["--json"];
                args.extend(j.json);
                args.push("in");
                args.extend(extra);
                run(dir, tool, &args, None)
            };
            let o = with(&["-o", "/dev/null"]);
            let o = if o.status.code() == Some(2) {
                // pat-info has no -o: its report is its output.
                with(&[])
            } else {
                o
            };
            ok(&o, "--json");
            let doc = if o.stdout.is_empty() {
                &o.stderr
            } else {
                &o.stdout
            };
            let v: serde_json::Value = serde_json::from_slice(doc)
                .unwrap_or_else(|e| panic!("{tool} --json: {e}: {}", text(doc)));
            assert_eq!(v["version"], 1, "{tool}: {v}");
            assert_eq!(v["tool"], tool, "{tool}: {v}");
        }
        ("json-versioned", false) => usage(&run(dir, tool, &["--json", "in"], None), "--json"),
        ("threads", true) => {
            let a = run(dir, tool, &["--threads", "1", "in"], None);
            let b = run(dir, tool, &["--threads", "2", "in"], None);
            ok(&a, "--threads 1");
            ok(&b, "--threads 2");
            assert!(
                a.stdout == b.stdout,
                "{tool}: output differs by thread count"
            );
        }
        ("threads", false) => usage(
            &run(dir, tool, &["--threads", "2", "in"], None),
            "--threads",
        ),
        ("several-inputs", true) => {
            let o = run(dir, tool, &["in", "in"], None);
            ok(&o, "two inputs");
        }
        ("several-inputs", false) => usage(&run(dir, tool, &["in", "in"], None), "two inputs"),
        ("camera-flags", true) => {
            // polyfill3 uses its camera for --cull only.
            let cull: &[&str] = if tool == "polyfill3" {
                &["--cull"]
            } else {
                &[]
            };
            dir.write(
                "cam.json",
                r#"{"lookat": {"eye": [30, 30, 100], "center": [30, 30, 0]},
                    "perspective": {"fovy": 40, "aspect": 1, "near": 1, "far": 1000}}"#,
            );
            let file = [cull, &["--camera", "cam.json", "in"]].concat();
            let flags = [
                cull,
                &[
                    "--perspective",
                    "40,1,1,1000",
                    "--lookat",
                    "30,30,100,30,30,0",
                    "in",
                ],
            ]
            .concat();
            let (a, b) = (run(dir, tool, &file, None), run(dir, tool, &flags, None));
            ok(&a, "--camera");
            ok(&b, "camera flags");
            assert!(
                !a.stdout.is_empty() && a.stdout == b.stdout,
                "{tool}: file and flags differ"
            );
        }
        (key, yes) => panic!("docs/conventions.md: no check for `{key}` = {yes}"),
    }
}

clitest!(every_cell_holds, |dir| {
    let rows = table();
    assert!(rows.len() >= 10, "{} notions", rows.len());
    for (key, cells) in rows {
        for (tool, cell) in TOOLS.iter().zip(&cells) {
            let j = job(tool, &dir);
            match cell.as_str() {
                "yes" => check(&key, &j, true, &dir),
                "no" => check(&key, &j, false, &dir),
                "—" => {}
                other => panic!("docs/conventions.md: `{key}` for {tool} is `{other}`"),
            }
        }
    }
});

// An argument that is not UTF-8 (a file name in Latin-1) is refused by
// every tool before anything is read or written, naming it with its bytes
// escaped; clap said "invalid UTF-8 was detected in one or more
// arguments". The same file read as `-` is read, and `polyfill3 --pattern`
// takes such a name.
clitest!(an_argument_that_is_not_utf8_is_named, |dir| {
    use std::os::unix::ffi::OsStrExt as _;
    let name = std::ffi::OsStr::from_bytes(b"caf\xe9.pat");
    std::fs::write(dir.path().join(name), checker16()).unwrap();
    for tool in TOOLS {
        dir.cmd(tool)
            .arg(name)
            .assert()
            .code(2)
            .stdout("")
            .stderr(format!(
                "{tool}: error: argument 1, \"caf\\xE9.pat\", is not UTF-8: file names and values \
                 are read as UTF-8 text (rename the file, or link it under a UTF-8 name)\n"
            ));
    }
    dir.cmd("pat-info")
        .args(["--check", "-"])
        .pipe_stdin(dir.path().join(name))
        .unwrap()
        .assert()
        .success();
    dir.write(
        "one.json",
        r#"{"vertices":[[0,0,0],[32,0,0],[0,32,0]],"color":[1,2,3]}"#,
    );
    dir.cmd("polyfill3")
        .arg("--pattern")
        .arg(name)
        .arg("one.json")
        .assert()
        .success();
});

// A negative value is read as the flag's value and refused for what it is:
// clap took `-16` for the short flags `-1 -6` and said "unexpected
// argument '-1'" (a hostile-input review).
clitest!(a_negative_value_is_named_as_typed, |dir| {
    for (tool, args, said) in [
        (
            "pat-from-image",
            &["--size", "-16"][..],
            "invalid value '-16' for '--size <N>'",
        ),
        (
            "pat-from-image",
            &["--colors", "-3"],
            "invalid value '-3' for '--colors <K>'",
        ),
        (
            "pat-tile",
            &["--size", "-1x5"],
            "invalid value '-1x5' for '--size <SIZE>'",
        ),
        (
            "scene-render",
            &["--size", "-5x5"],
            "invalid value '-5x5' for '--size <SIZE>'",
        ),
        // A flag after one that wants its value is not taken for it.
        (
            "pat-tile",
            &["--size", "-o", "x.png"],
            "a value is required for '--size <SIZE>'",
        ),
    ] {
        let out = dir
            .cmd(tool)
            .args(args)
            .assert()
            .code(2)
            .get_output()
            .clone();
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert!(
            stderr.starts_with(&format!("{tool}: error: {said}")),
            "{stderr}"
        );
    }
});
