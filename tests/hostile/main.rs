//! The hostile-input suite (issue 17): one table of cases, each a shell
//! command run against the tools with its inputs, and the outcome it must
//! have: exit status, words in the error, empty standard output where the
//! tool must write nothing, no file left behind but the ones named, and a
//! memory and time ceiling enforced by the operating system (`ulimit -v`,
//! address space, and `timeout -s KILL`). The ceilings are runaway guards at
//! about ten times what the case needs, not timing targets; the load cases
//! that need minutes or gigabytes are in `bench/` (`large_picture_memory.sh`,
//! `image_texture_memory.sh`), which print peak memory.
//!
//! Every class of the issue has cases: unbounded work from small inputs
//! (nested instances, huge quadrics, large OBJ meshes), out of memory,
//! unbounded reads (`/dev/zero`, named files that are not regular), wrong
//! pictures in silence (a huge far plane, huge coordinates), pipelines that
//! must fail, signals, outputs all-or-nothing, output problems found before
//! the work, closed pipes and closed standard output, and malformed files of
//! every format with their errors. `cargo test --test hostile` runs it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What a case's command must end with.
#[derive(Clone, Copy, Debug)]
enum Status {
    /// Exit status.
    Code(i32),
}

/// One hostile case.
struct Case {
    /// What it attacks.
    name: &'static str,
    /// Files written into the case's directory first: name and contents.
    files: Vec<(&'static str, Vec<u8>)>,
    /// A bash command (with `set -o pipefail`) run in that directory; the
    /// tools are on PATH and `$FIX` is the repository's `fixtures/`.
    sh: String,
    /// Its exit status.
    status: Status,
    /// Words its standard error must hold (all of them).
    stderr: Vec<&'static str>,
    /// Standard output must be empty: every case sends what it checks to
    /// files.
    /// Files the case may leave besides its inputs; anything else (a
    /// `.patkit-*.tmp`, a partial image) is a failure.
    leaves: Vec<&'static str>,
    /// Address-space ceiling in MiB.
    mem_mib: u64,
    /// Time ceiling in seconds.
    secs: u64,
}

impl Case {
    fn new(name: &'static str, sh: impl Into<String>) -> Case {
        Case {
            name,
            files: Vec::new(),
            sh: sh.into(),
            status: Status::Code(1),
            stderr: Vec::new(),
            leaves: Vec::new(),
            mem_mib: 1024,
            secs: 20,
        }
    }
    fn file(mut self, name: &'static str, contents: impl Into<Vec<u8>>) -> Case {
        self.files.push((name, contents.into()));
        self
    }
    fn code(mut self, c: i32) -> Case {
        self.status = Status::Code(c);
        self
    }
    fn says(mut self, words: &'static str) -> Case {
        self.stderr.push(words);
        self
    }
    fn leaves(mut self, f: &'static str) -> Case {
        self.leaves.push(f);
        self
    }
    fn within(mut self, mem_mib: u64, secs: u64) -> Case {
        self.mem_mib = mem_mib;
        self.secs = secs;
        self
    }
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A stream of `depth` objects, each placing the one before twice: 2^depth
/// polygons from a few kilobytes.
fn nested(depth: usize) -> String {
    let mut s = String::from(
        r#"{"object": "o0", "records": [{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3]}]}"#,
    );
    s.push('\n');
    for i in 1..depth {
        s.push_str(&format!(
            r#"{{"object": "o{i}", "records": [{{"instance": "o{p}"}}, {{"instance": "o{p}", "transform": {{"translate": [1, 0, 0]}}}}]}}"#,
            p = i - 1
        ));
        s.push('\n');
    }
    s.push_str(&format!("{{\"instance\": \"o{}\"}}\n", depth - 1));
    s
}

/// Passes when the last pixel of `out.ppm` (its bottom-right) is white.
const WHITE_LAST: &str = "test \"$(tail -c 3 out.ppm | od -An -tu1 | tr -s ' ')\" = ' 255 255 255'";

const TRI: &str = r#"{"vertices": [[0,0],[1,0],[0,1]], "color": [200,100,50]}"#;

fn cases() -> Vec<Case> {
    let big_face: String = {
        let mut s = String::new();
        for k in 0..1_000_001u32 {
            s.push_str(&format!("v {} {} 0\n", k % 1000, k / 1000));
        }
        s.push('f');
        for k in 1..=1_000_001u32 {
            s.push_str(&format!(" {k}"));
        }
        s.push_str("\nf 1 2 3\nf 1 2 3\n");
        s
    };
    vec![
        // --- Unbounded work from small inputs (items 1, 2).
        Case::new("nested instances: scene-render refuses before any work", "scene-render -o out.png nested.json")
            .file("nested.json", nested(40))
            .says("record 40: the scene expands to 549755813888 polygons")
            .says("--max-polygons raises it")
            .within(256, 5),
        Case::new("nested instances: pat-info --record refuses past its budget", "pat-info --record 40 nested.json")
            .file("nested.json", nested(40))
            .says("record 40: expands to 1649267441662 records and instances (nested instances multiply)")
            .within(1024, 10),
        Case::new("nested instances: polyfill3 partitions each object once", "polyfill3 nested.json -o cells.ndjson")
            .file("nested.json", nested(40))
            .code(0)
            .leaves("cells.ndjson")
            .within(256, 10),
        Case::new("a 16384-segment sphere is refused by scene-render", "scene-render -o out.png s.json")
            .file("s.json", r#"{"sphere": {"radius": 1, "slices": 16384, "stacks": 16384}, "color": [1,2,3]}"#)
            .says("536870912 polygons")
            .within(256, 5),
        Case::new("a 16384-segment sphere is refused by polyfill3", "polyfill3 s.json -o out.ndjson")
            .file("s.json", r#"{"sphere": {"radius": 1, "slices": 16384, "stacks": 16384}, "color": [1,2,3]}"#)
            .says("past --max-polygons 50000000")
            .within(256, 5),
        Case::new("polyfill3 streams a radius-1000 sphere in bounded memory", "polyfill3 --pattern $FIX/patterns/brick.pat s.json -o /dev/null")
            .file("s.json", r#"{"sphere": {"radius": 1000}, "color": [1,2,3]}"#)
            .code(0)
            .within(256, 60),
        Case::new("an OBJ mesh over a million triangles is refused at the face that passes the limit", "scene-render -o out.png s.json")
            .file("s.json", r#"{"mesh": {"obj": "huge.obj"}, "color": [9, 9, 9]}"#)
            .file("huge.obj", big_face)
            .says("f: more than 1000000 triangles, over the most one mesh may have")
            .within(1024, 20),
        // --- Out of memory (item 3).
        // The image alone is 732 MiB (16000 x 16000 x 3 bytes).
        Case::new("out of memory is an error line, not an abort", "scene-render --size 16000x16000 -o out.png s.json")
            .file("s.json", TRI)
            .says("scene-render: error: out of memory")
            .within(512, 20),
        // --- Unbounded reads (item 4).
        Case::new("pat-info /dev/zero", "pat-info /dev/zero").says("pat-info: error: /dev/zero").within(512, 5),
        Case::new("scene-render /dev/zero", "scene-render -o out.png /dev/zero").says("scene-render: error: /dev/zero").within(512, 5),
        Case::new("polyfill3 /dev/zero", "polyfill3 /dev/zero").says("polyfill3: error: /dev/zero").within(512, 5),
        Case::new("pat-tile /dev/zero", "pat-tile /dev/zero -o out.png").says("pat-tile: error: /dev/zero").within(512, 5),
        Case::new("pat-from-image /dev/zero", "pat-from-image /dev/zero -o out.pat").says("pat-from-image: error: /dev/zero").within(512, 5),
        Case::new("a pattern file that is /dev/zero", "scene-render -o out.png s.json")
            .file("s.json", r#"{"vertices": [[0,0],[1,0],[0,1]], "pattern": {"file": "/dev/zero"}}"#)
            .says("is not a regular file")
            .within(512, 5),
        Case::new("a pattern file that is not a pattern echoes none of it", "scene-render -o out.png s.json 2> said; grep -q shadow said && ! grep -q secret-word said")
            .file("s.json", r#"{"vertices": [[0,0],[1,0],[0,1]], "pattern": {"file": "shadow"}}"#)
            .file("shadow", "secret-word:x:19000:0:99999:7:::\n")
            .code(0)
            .leaves("said")
            .within(256, 5),
        Case::new("an OBJ named as /dev/zero", "polyfill3 s.json -o out.ndjson")
            .file("s.json", r#"{"mesh": {"obj": "/dev/zero"}}"#)
            .says("record 0: mesh.obj: /dev/zero: is not a regular file")
            .within(512, 5),
        // --- Wrong pictures in silence (items 5, 6).
        Case::new("a huge far plane does not hide near geometry", format!("scene-render --perspective 60,1,0.1,5.1e9 --lookat 0,0,5,0,0,0 --size 16x16 --format ppm -o out.ppm s.json && {WHITE_LAST}"))
            .file("s.json", r#"{"rect": [-10, -10, 10, 10], "color": [255, 255, 255]}"#)
            .code(0)
            .leaves("out.ppm")
            .within(256, 5),
        Case::new("a square at +-1e18 covers the whole frame", format!("scene-render --ortho -1e18,1e18,-1e18,1e18,-1,1 --size 8x8 --format ppm -o out.ppm s.json && {WHITE_LAST}"))
            .file("s.json", r#"{"rect": [-1e18, -1e18, 1e18, 1e18], "color": [255, 255, 255]}"#)
            .code(0)
            .leaves("out.ppm")
            .within(256, 5),
        // --- Pipelines (item 7).
        // scene-render cannot know its input was cut: it draws what came,
        // and the pipeline's status (pipefail) is what fails the job, as
        // `make`'s .DELETE_ON_ERROR then removes the image (examples/Makefile).
        Case::new("a failing first stage fails the pipeline", "polyfill3 bad.json | scene-render -o out.png -")
            .file("bad.json", format!("{TRI}\n{{\"vertices\": [[0,0],[1,0]], \"color\": [1,2,3]}}\n"))
            .says("polyfill3: error: bad.json: record 1")
            .leaves("out.png")
            .within(512, 10),
        // --- Signals (item 8).
        Case::new("SIGTERM mid-render removes the unfinished output", "scene-render --size 4000x4000 --ortho2 0,1,0,1 --reference -o out.png s.json & pid=$!; sleep 0.5; kill -TERM $pid; wait $pid")
            .file("s.json", r#"{"vertices": [[0,0],[1,0],[0.5,1]], "color": [200,100,50]}"#)
            .code(143)
            .within(2048, 20),
        // `env --default-signal`: bash starts a background command with
        // SIGINT ignored, and the tools leave an ignored signal ignored.
        Case::new("SIGINT mid-partition removes the unfinished output", "env --default-signal=INT polyfill3 --pattern $FIX/patterns/brick.pat --incr 0.05 s.json -o cells.ndjson & pid=$!; sleep 0.5; kill -INT $pid; wait $pid")
            .file("s.json", r#"{"vertices": [[0,0],[100,0],[100,100],[0,100]], "color": [1,2,3]}"#)
            .code(130)
            .within(1024, 20),
        // --- All outputs or none (item 9).
        Case::new("a failed --diff leaves no image", "scene-render --size 8x8 --diff d.png --compare other.png -o out.png s.json")
            .file("s.json", TRI)
            .file("other.png", std::fs::read(repo("examples/golden/demo1.png")).unwrap())
            .says("scene-render: error")
            .leaves("other.png")
            .within(512, 10),
        // --- Output problems before the work (item 10).
        Case::new("a missing output directory fails before the render", "scene-render --size 8000x8000 --aa ss16 -o nowhere/out.png $FIX/scenes/demo2-faces.json")
            .says("nowhere/out.png")
            .within(1024, 2),
        Case::new("binary output to a terminal is refused before the render", "script -qec 'scene-render --size 8000x8000 --aa ss16 $FIX/scenes/demo2-faces.json' /dev/null | tr -d '\\r' > said; grep -q 'terminal' said")
            .code(0)
            .leaves("said")
            .within(1024, 5),
        // --- Closed pipes and closed standard output (item 11).
        Case::new("pat-tile into a closed pipe ends quietly", "pat-tile --size 2000x2000 $FIX/patterns/brick.pat -o - | head -c 10 > /dev/null")
            .code(0)
            .within(1024, 10),
        Case::new("pat-info --json into a closed pipe ends quietly", "pat-info --json $FIX/patterns/*.pat $FIX/patterns/*.pat $FIX/patterns/*.pat | head -c 10 > /dev/null")
            .code(0)
            .within(512, 10),
        Case::new("a closed standard output is an error", "polyfill3 s.json >&-")
            .file("s.json", TRI)
            .says("polyfill3: error")
            .within(512, 5),
        // --- Malformed files of every format.
        Case::new("a .pat with a bad colour line", "pat-info bad.pat")
            .file("bad.pat", "16 2\n255 0 0\n0 0\n")
            .says("bad.pat:3")
            .within(256, 5),
        Case::new("a .pat with an absurd size", "pat-info bad.pat")
            .file("bad.pat", "1600000 2\n")
            .says("bad.pat:1")
            .within(256, 5),
        Case::new("a stream cut short", "scene-render -o out.png s.json")
            .file("s.json", "[{\"vertices\": [[0,0],[1,0],[0,1]], \"color\": [1,2")
            .says("s.json")
            .within(256, 5),
        Case::new("NaN and infinities in a stream", "scene-render -o out.png s.json")
            .file("s.json", r#"{"vertices": [[0,0],[1e999,0],[0,1]], "color": [1,2,3]}"#)
            .says("record 0")
            .within(256, 5),
        Case::new("100,000-deep nesting in a field the tools read", "scene-render -o out.png s.json")
            .file("s.json", format!("{{\"color\": {}{}, \"vertices\": [[0,0],[1,0],[0,1]]}}", "[".repeat(100_000), "]".repeat(100_000)))
            .says("s.json")
            .within(256, 5),
        // An unknown field is kept as the text it was written in, never
        // parsed into a tree: any depth passes, in bounded memory.
        Case::new("100,000-deep nesting in an unknown field passes through", "polyfill3 s.json -o out.ndjson && cmp -s <(head -c 100 out.ndjson) <(tr -d ' ' < s.json | head -c 100)")
            .file("s.json", format!("{{\"x\": {}{}, \"vertices\": [[0,0],[8,0],[0,8]], \"color\": [1,2,3]}}\n", "[".repeat(100_000), "]".repeat(100_000)))
            .code(0)
            .leaves("out.ndjson")
            .within(256, 5),
        Case::new("a bow-tie polygon", "scene-render -o out.png s.json")
            .file("s.json", r#"{"vertices": [[0,0],[1,1],[1,0],[0,1]], "color": [1,2,3]}"#)
            .says("record 0: vertices")
            .within(256, 5),
        Case::new("a degenerate camera", "scene-render --camera cam.json -o out.png s.json")
            .file("s.json", TRI)
            .file("cam.json", r#"{"lookat": {"eye": [0,0,0], "at": [0,0,0]}, "perspective": {"fovy": 60, "aspect": 1, "near": 1, "far": 10}}"#)
            .says("cam.json")
            .within(256, 5),
        Case::new("an OBJ with a face index out of range", "scene-render -o out.png s.json")
            .file("s.json", r#"{"mesh": {"obj": "m.obj"}}"#)
            .file("m.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n")
            .says("record 0: mesh.obj: ./m.obj:3: f: `3`: vertex index 3 out of range")
            .within(256, 5),
        Case::new("an OBJ whose material is missing", "polyfill3 s.json")
            .file("s.json", r#"{"mesh": {"obj": "m.obj"}}"#)
            .file("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl gone\nf 1 2 3\n")
            .file("m.mtl", "newmtl here\nKd 1 0 0\n")
            .says("./m.obj:5: usemtl gone: no material of that name")
            .within(256, 5),
        Case::new("a light inside an object", "scene-render -o out.png s.json")
            .file("s.json", r#"{"object": "o", "records": [{"light": {"ambient": 1}}]}"#)
            .says("lights are top-level only")
            .within(256, 5),
        Case::new("a stripe map that is not a power of two", "pat-info m.map")
            .file("m.map", "STRIPE 3\n0 1 2\n")
            .says("m.map")
            .within(256, 5),
        Case::new("a truncated PNG", "pat-from-image cut.png -o out.pat")
            .file("cut.png", std::fs::read(repo("examples/golden/demo1.png")).unwrap()[..2000].to_vec())
            .says("cut.png")
            .within(512, 5),
        Case::new("an absurd --size", "scene-render --size 100000x100000 -o out.png s.json")
            .file("s.json", TRI)
            .code(2)
            .says("100000x100000")
            .within(256, 5),
        Case::new("a missing input file", "pat-info missing.pat").says("missing.pat").within(256, 5),
    ]
}

/// The names of the files under `dir`, relative, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                stack.push(e.path());
            } else {
                out.push(e.path().strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

fn run(case: &Case) -> Result<(), String> {
    let tmp = tempfile::Builder::new()
        .prefix("patkit-hostile-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    for (name, contents) in &case.files {
        std::fs::write(dir.join(name), contents).unwrap();
    }
    let before = listing(dir);
    let bin = Path::new(env!("CARGO_BIN_EXE_scene-render"))
        .parent()
        .unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let script = format!(
        "set -o pipefail; ulimit -v {}; {}",
        case.mem_mib * 1024,
        case.sh
    );
    let start = Instant::now();
    let out = std::process::Command::new("timeout")
        .args(["-s", "KILL", &case.secs.to_string(), "bash", "-c", &script])
        .current_dir(dir)
        .env("PATH", path)
        .env("FIX", repo("fixtures"))
        .env_remove("NO_COLOR")
        .output()
        .unwrap();
    let took = start.elapsed();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let mut wrong = Vec::new();
    if took > Duration::from_secs(case.secs) || out.status.code() == Some(137) {
        wrong.push(format!("ran past its {} s ceiling", case.secs));
    }
    let Status::Code(want) = case.status;
    if out.status.code() != Some(want) {
        wrong.push(format!(
            "exit status {:?}, expected {want}",
            out.status.code()
        ));
    }
    for w in &case.stderr {
        if !stderr.contains(w) {
            wrong.push(format!("standard error lacks {w:?}"));
        }
    }
    if stderr.contains("panicked") || stderr.contains("RUST_BACKTRACE") {
        wrong.push("a panic".into());
    }
    if !out.stdout.is_empty() {
        wrong.push(format!("{} bytes on standard output", out.stdout.len()));
    }
    let after: Vec<String> = listing(dir)
        .into_iter()
        .filter(|f| !before.contains(f) && !case.leaves.contains(&f.as_str()))
        .collect();
    if !after.is_empty() {
        wrong.push(format!("left behind: {after:?}"));
    }
    match wrong.is_empty() {
        true => Ok(()),
        false => Err(format!(
            "{}: {}\n  command: {}\n  stderr: {}\n  stdout: {}",
            case.name,
            wrong.join("; "),
            case.sh,
            stderr.trim(),
            String::from_utf8_lossy(&out.stdout[..out.stdout.len().min(200)])
        )),
    }
}

#[test]
fn every_hostile_case_ends_as_it_must() {
    let cases = cases();
    let failures: Vec<String> = cases.iter().filter_map(|c| run(c).err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
}
