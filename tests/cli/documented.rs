//! Every documented command runs (netpbm's way: the test suite runs the
//! commands its manuals show). The commands of the README's and `docs/`'s
//! ```` ```sh ```` blocks (and the whole commands their prose quotes in
//! backticks: [`inline_commands`]) and of each tool's `--help` "Examples" run in a copy
//! of `examples/try/` (the files the texts name, such as `scene.json` and
//! `photo.jpg`, with a link to `fixtures/`), in order, one copy per text, with
//! the tools just built first on `PATH`. The man pages are generated from the
//! same definitions as `--help` (the `man_pages` test keeps them equal), so
//! their examples are these.
//!
//! Each command must exit 0 with no warning; every file it writes must be
//! non-empty, every image must show more than one colour (a blank frame is
//! the commonest silent mistake), an image named like a golden image must
//! match it, and a command with an expected output ([`EXPECT`]) must print it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// Commands not run here, each with the reason and the test that covers it
/// instead (matched by prefix).
const SKIP: &[(&str, &str)] = &[
    (
        "make -C examples",
        "builds the whole examples tree; every_target_of_the_examples_makefile_builds \
         (tests/cli/make.rs) makes every target, spin and turn included",
    ),
    (
        "make install",
        "installs into the user's prefix; \
         make_install_puts_tools_man_pages_and_completions_under_a_prefix installs into a temporary one",
    ),
    (
        "cargo ",
        "cargo itself: CI runs the test and build commands",
    ),
    (
        "parallel -S",
        "needs ssh hosts; a_frame_batch_runs_through_gnu_parallel runs the same batch locally",
    ),
    (
        "bench/",
        "benchmarks take minutes and peers (bench/, not CI)",
    ),
    (
        "#SBATCH",
        "Slurm directives; the job's scene-render line is the --frame batch tested above",
    ),
];

/// Output a command must print (stdout), by a fragment of the command.
const EXPECT: &[(&str, &str)] = &[
    ("--compat thesis", "1353"),
    ("&& echo valid", "valid"),
    ("&& echo all valid", "all valid"),
    // README's "error below one 8-bit code", and the report docs/rendering.md
    // shows for it (*--compare*).
    (
        "--image exact16.png --compare exact.pfm",
        "rmse      0.000153\npsnr      124.43 dB\nmax       0.001945\n",
    ),
];

/// Images that must match a golden image: (output name in the text, golden).
const GOLDEN: &[(&str, &str)] = &[
    ("demo1.png", "examples/golden/demo1.png"),
    ("demo2.png", "examples/golden/demo2.png"),
    ("earth-lit.png", "examples/golden/earth-lit.png"),
    ("house.png", "examples/golden/house.png"),
];

/// One runnable command of a text, with where it is written.
#[derive(Debug)]
struct Documented {
    place: String,
    command: String,
}

/// The ```` ```sh ```` blocks of a Markdown file as commands: continuation
/// lines joined, comment lines dropped. Fails on an untagged fence, so a
/// block of commands cannot be left out by forgetting its tag.
fn markdown_commands(rel: &str) -> Vec<Documented> {
    let text = std::fs::read_to_string(crate::util::repo(rel)).unwrap();
    let mut out = Vec::new();
    let mut block: Option<(String, usize)> = None;
    let mut pending = String::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if let Some(tag) = line.trim_start().strip_prefix("```") {
            match block {
                None => {
                    assert!(
                        !tag.trim().is_empty(),
                        "{rel}:{n}: a fenced block needs a tag (sh for commands, which run \
                         in tests/cli/documented.rs; text, json, make, rust otherwise)"
                    );
                    block = Some((tag.trim().to_string(), n));
                }
                Some(_) => block = None,
            }
            continue;
        }
        match &block {
            Some((tag, _)) if tag == "sh" => {}
            Some(_) => continue,
            None => {
                assert!(
                    !is_command(line.strip_prefix("    ").unwrap_or("")),
                    "{rel}:{n}: a command in an indented block: put it in a ```sh block \
                     so that it runs as a test"
                );
                out.extend(inline_commands(line).into_iter().map(|command| Documented {
                    place: format!("{rel}:{n} (inline)"),
                    command,
                }));
                continue;
            }
        }
        let line = strip_comment(line);
        if let Some(head) = line.strip_suffix('\\') {
            pending.push_str(head);
            continue;
        }
        pending.push_str(&line);
        let command = std::mem::take(&mut pending).trim().to_string();
        if !command.is_empty() {
            out.push(Documented {
                place: format!("{rel}:{n}"),
                command,
            });
        }
    }
    out
}

/// The whole commands a line of prose shows in backticks: a span that
/// starts with a tool and ends in a file it reads (`.json`, `.pat`, an
/// image, a map; not the `-o` output) or in `-`, with no placeholder in
/// capitals (`N`, `FILE`).
/// Fragments (`scene-render --max-polygons N`, `polyfill3 | scene-render`)
/// are not commands; a span broken across two lines is not seen.
fn inline_commands(line: &str) -> Vec<String> {
    line.split('`')
        .skip(1)
        .step_by(2)
        .filter(|span| is_command(span))
        .filter(|span| {
            let words: Vec<&str> = span.split_whitespace().collect();
            let placeholder = words.iter().any(|w| {
                let w = w.trim_end_matches("...");
                w.chars().any(|c| c.is_ascii_uppercase())
                    && w.chars()
                        .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
            });
            let last = words.last().copied().unwrap_or("");
            let written = words.len() >= 2 && words[words.len() - 2] == "-o";
            let reads = [".json", ".pat", ".png", ".jpg", ".map", ".ndjson"]
                .iter()
                .any(|e| last.ends_with(e))
                || last == "-";
            !placeholder && reads && !written
        })
        .map(str::to_string)
        .collect()
}

/// Whether a line of text starts with one of the tools or a build command.
fn is_command(line: &str) -> bool {
    [
        "pat-from-image ",
        "pat-info ",
        "pat-tile ",
        "polyfill3 ",
        "scene-render ",
        "make ",
        "cargo ",
    ]
    .iter()
    .any(|t| line.starts_with(t))
}

/// A line without its trailing `# comment` (a `#` after a space, outside
/// quotes: `#rrggbb` colours and `'...#...'` survive).
fn strip_comment(line: &str) -> String {
    let (mut single, mut double) = (false, false);
    let mut prev = ' ';
    for (i, c) in line.char_indices() {
        match c {
            '\'' if !double => single = !single,
            '"' if !single => double = !double,
            '#' if !single && !double && prev.is_whitespace() => {
                return line[..i].trim_end().to_string()
            }
            _ => {}
        }
        prev = c;
    }
    line.trim_end().to_string()
}

/// The "Examples:" of a tool's `--help`: the lines indented by two spaces
/// (their explanations are indented further).
fn help_commands(tool: &str) -> Vec<Documented> {
    let out = Command::new(bin_dir().join(tool))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8(out.stdout).unwrap();
    let examples = help
        .split_once("Examples:\n")
        .unwrap_or_else(|| panic!("{tool} --help has no Examples"))
        .1;
    examples
        .lines()
        .take_while(|l| l.is_empty() || l.starts_with(' '))
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .map(|l| Documented {
            place: format!("{tool} --help"),
            command: l.trim().to_string(),
        })
        .collect()
}

fn bin_dir() -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_scene-render"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// A copy of `examples/try/` to run a text's commands in, links followed
/// (its `fixtures` is the repository's), so that no command can write into
/// the repository: an output over a link would replace the file linked to.
fn sandbox(dir: &Path) {
    fn copy(from: &Path, to: &Path) {
        if from.is_dir() {
            std::fs::create_dir_all(to).unwrap();
            for e in std::fs::read_dir(from).unwrap() {
                let e = e.unwrap();
                copy(&e.path(), &to.join(e.file_name()));
            }
        } else {
            std::fs::copy(from, to).unwrap();
        }
    }
    copy(&crate::util::repo("examples/try"), dir);
}

/// Size and time of every file in `dir` (not through links).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (u64, SystemTime)> {
    let mut m = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let t = e.file_type().unwrap();
            if t.is_dir() {
                stack.push(e.path());
            } else if t.is_file() {
                let md = e.metadata().unwrap();
                m.insert(e.path(), (md.len(), md.modified().unwrap()));
            }
        }
    }
    m
}

/// The external programs a command line runs, besides the tools.
fn programs(command: &str) -> Vec<String> {
    command
        .split(['|', ';'])
        .flat_map(|s| s.split("&&"))
        .filter_map(|s| s.split_whitespace().next())
        .filter(|w| !w.contains('=') && !w.starts_with('$'))
        .map(str::to_string)
        .collect()
}

fn has_program(p: &str, path: &str) -> bool {
    Command::new("bash")
        .args(["-c", &format!("command -v {p}")])
        .env("PATH", path)
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs a text's commands in order in a fresh sandbox; returns the failures.
fn run_all(name: &str, commands: &[Documented]) -> Vec<String> {
    let dir = crate::util::Dir::new(&format!("documented-{name}"));
    sandbox(dir.path());
    let path = format!(
        "{}:{}",
        bin_dir().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let strict = std::env::var_os("PATKIT_CI").is_some();
    let mut failures = Vec::new();
    for d in commands {
        // `VAR=value cmd`: matched by the command.
        let bare = d
            .command
            .split(' ')
            .skip_while(|w| w.contains('=') && !w.starts_with('-'))
            .collect::<Vec<_>>()
            .join(" ");
        if let Some((_, why)) = SKIP.iter().find(|(p, _)| bare.starts_with(p)) {
            eprintln!("{}: not run: `{}`: {why}", d.place, d.command);
            continue;
        }
        if let Some(p) = programs(&d.command)
            .into_iter()
            .find(|p| !has_program(p, &path))
        {
            let msg = format!("{}: `{}` needs {p}, not installed", d.place, d.command);
            if strict {
                failures.push(msg);
            } else {
                eprintln!("{msg}: not run (.ci/run installs it and sets PATKIT_CI)");
            }
            continue;
        }
        let before = snapshot(dir.path());
        let out = Command::new("bash")
            .args(["-o", "pipefail", "-ec", &d.command])
            .current_dir(dir.path())
            .env("PATH", &path)
            .env_remove("NO_COLOR")
            // docs/objects.md's Slurm job script, run as its task 0.
            .env("SLURM_CPUS_PER_TASK", "1")
            .env("SLURM_ARRAY_TASK_ID", "0")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let mut fail =
            |what: String| failures.push(format!("{}: `{}`: {what}", d.place, d.command));
        if !out.status.success() {
            fail(format!("exit {:?}: {stderr}", out.status.code()));
            continue;
        }
        if stderr.contains("warning:") {
            fail(format!("warns: {stderr}"));
        }
        for (fragment, want) in EXPECT {
            if d.command.contains(fragment) && !stdout.contains(want) {
                fail(format!("prints {stdout:?}, not {want:?}"));
            }
        }
        for (file, (len, time)) in snapshot(dir.path()) {
            if before.get(&file) == Some(&(len, time)) {
                continue;
            }
            let rel = file.strip_prefix(dir.path()).unwrap().display().to_string();
            if len == 0 {
                fail(format!("writes {rel} empty"));
                continue;
            }
            // A --diff image of identical images is rightly all black.
            if let Some(why) = blank_image(&file).filter(|_| !rel.starts_with("diff")) {
                fail(format!("{rel}: {why}"));
            }
            if let Some((_, golden)) = GOLDEN.iter().find(|(n, _)| *n == rel) {
                let rendered = std::fs::read(&file).unwrap();
                if let Some(why) = crate::scene_render::golden_mismatch(&rendered, golden) {
                    fail(format!("{rel} differs from {why}"));
                }
            }
        }
    }
    failures
}

/// Why an image file is blank (one colour everywhere), if it is one.
fn blank_image(path: &Path) -> Option<String> {
    let ext = path.extension()?.to_str()?;
    let bytes = std::fs::read(path).unwrap();
    if ext == "pfm" {
        let img = patkit::io::decode_pfm(&bytes).ok()?;
        let first = &img.data[..3];
        return img
            .data
            .chunks_exact(3)
            .all(|p| p == first)
            .then(|| format!("blank image: every pixel is {first:?} (linear)"));
    }
    if !["png", "ppm", "pam", "pgm", "pnm"].contains(&ext) {
        return None;
    }
    let img = patkit::io::decode_image(&bytes, &path.display().to_string()).ok()?;
    let first = *img.get_pixel(0, 0);
    img.pixels()
        .all(|p| *p == first)
        .then(|| format!("blank image: every pixel is {:?}", first.0))
}

/// One test per text, so a failure names the text.
macro_rules! documented {
    ($($name:ident: $commands:expr;)*) => {$(
        #[test]
        fn $name() {
            let commands: Vec<Documented> = $commands;
            assert!(!commands.is_empty(), "no commands found");
            let failures = run_all(stringify!($name), &commands);
            assert!(failures.is_empty(), "{}", failures.join("\n\n"));
        }
    )*};
}

documented! {
    readme: markdown_commands("README.md");
    docs_camera: markdown_commands("docs/camera.md");
    docs_json: markdown_commands("docs/json.md");
    docs_pat_format: markdown_commands("docs/pat-format.md");
    docs_stream_format: markdown_commands("docs/stream-format.md");
    docs_stripe_files: markdown_commands("docs/stripe-files.md");
    docs_objects: markdown_commands("docs/objects.md");
    docs_stripe: markdown_commands("docs/stripe.md");
    docs_lighting: markdown_commands("docs/lighting.md");
    docs_polyfill3: markdown_commands("docs/polyfill3.md");
    help_pat_from_image: help_commands("pat-from-image");
    help_pat_info: help_commands("pat-info");
    help_pat_tile: help_commands("pat-tile");
    help_polyfill3: help_commands("polyfill3");
    help_scene_render: help_commands("scene-render");
}

/// The pages with no commands have none hidden in them (an untagged fence or
/// an indented command fails in [`markdown_commands`]); a page that gains a
/// ```` ```sh ```` block belongs in the list above.
#[test]
fn docs_without_commands() {
    for page in [
        "docs/architecture.md",
        "docs/conventions.md",
        "docs/rendering.md",
    ] {
        let found = markdown_commands(page);
        assert!(found.is_empty(), "{page}: add it to documented! {found:?}");
    }
}
