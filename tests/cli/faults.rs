//! Faults around the tools (issue 17, items 8 and 11): closed pipes, a
//! closed standard output, and signals while an output is being written.

use crate::util::repo;

/// Runs `script` with `sh -c` in `dir`, the tools' directory first on PATH.
fn sh(dir: &std::path::Path, script: &str) -> std::process::Output {
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_pat-tile"))
        .parent()
        .unwrap()
        .to_path_buf();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    std::process::Command::new("sh")
        .arg("-c")
        .arg(script)
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .unwrap()
}

/// [`sh`] of a script that must fail with status 1 (a clear error, not a
/// crash or a usage error); its standard error.
fn sh_fails(dir: &std::path::Path, script: &str) -> String {
    let out = sh(dir, script);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{script}: {err}");
    err
}

/// The status of `first` (a shell command) writing into a pipe that
/// `head -c 10` closes early, and what the pipeline said on standard error.
fn through_closed_pipe(dir: &std::path::Path, first: &str) -> (String, String) {
    let out = sh(
        dir,
        &format!("( {first}; echo $? > status ) | head -c 10 > /dev/null"),
    );
    assert!(out.status.success());
    let status = std::fs::read_to_string(dir.join("status")).unwrap();
    let said = String::from_utf8_lossy(&out.stderr).into_owned();
    (status.trim().to_string(), said)
}

clitest!(a_closed_pipe_ends_every_output_quietly, |dir| {
    // `| head` closes the pipe early: the tool stops with status 0 and says
    // nothing, whatever encoder met the closed pipe (PNG's words its own
    // error; serde_json's is not an io::Error).
    let pats = repo("fixtures/patterns");
    let many: String = (0..60)
        .map(|_| format!("{}/*.pat ", pats.display()))
        .collect();
    for first in [
        format!(
            "pat-tile --size 2000x2000 {}/brick.pat -o -",
            pats.display()
        ),
        format!("pat-info --json {many}"),
        format!("pat-info {many}"),
    ] {
        let (status, said) = through_closed_pipe(dir.path(), &first);
        assert_eq!(status, "0", "{first}: {said}");
        assert!(said.is_empty(), "{first}: {said}");
    }
});

clitest!(an_unwritable_standard_error_changes_no_status, |dir| {
    // Errors, warnings, reports for people and timings to a full device or
    // a closed pipe are dropped: each tool ends with the status it would
    // have given (they panicked, status 101, at the first message).
    // polyfill3's --json summary is an output: see
    // a_report_on_standard_error_that_cannot_be_written_fails.
    let brick = repo("fixtures/patterns/brick.pat");
    let faces = repo("fixtures/scenes/demo2-faces.json");
    let photo = repo("fixtures/images/earth-nasa.jpg");
    for (cmd, status) in [
        ("pat-info missing.pat".to_string(), 1),
        (format!("pat-info --json {}", brick.display()), 0),
        ("polyfill3 missing.json".to_string(), 1),
        (format!("polyfill3 {} -o cells.ndjson", faces.display()), 0),
        (
            format!("pat-tile --size 8x8 {} -o t.png", brick.display()),
            0,
        ),
        ("pat-tile --size 0x8 missing.pat".to_string(), 2),
        (
            format!(
                "pat-from-image --report --size 16 {} -o p.pat",
                photo.display()
            ),
            0,
        ),
        (
            format!(
                "scene-render --timings --size 8x8 {} -o s.png",
                faces.display()
            ),
            0,
        ),
        ("scene-render missing.json -o s.png".to_string(), 1),
    ] {
        for script in [
            format!("{cmd} 2>/dev/full; echo $? > status"),
            // Standard error into a pipe that `true` closes.
            format!("( {cmd}; echo $? > status ) 2>&1 >/dev/null | true"),
        ] {
            sh(dir.path(), &script);
            let got = std::fs::read_to_string(dir.path().join("status")).unwrap();
            assert_eq!(got.trim(), status.to_string(), "{script}");
        }
    }
});

clitest!(
    polyfill3_into_a_closed_pipe_exits_0_quietly_at_every_size,
    |dir| {
        // A closed pipe met while the end of polyfill3's output was written
        // (outputs of about 90 KB to 3 MB of cells) failed with status 1 and
        // "Broken pipe (os error 32)": the I/O error came back as the
        // stream's own write error, which the check for a closed pipe did not
        // look inside. Smaller outputs fit in the pipe; larger ones met it
        // inside a record. The output goes to `head` through the shell's
        // pipe, so no output is too large for the test to take.
        let chex = repo("fixtures/patterns/chex.pat");
        dir.write(
            "tri.json",
            r#"{"vertices":[[0,0],[10,0],[0,10]],"color":[1,2,3]}"#,
        );
        // About 22 KB, 93 KB, 206 KB, 825 KB and 3.3 MB of cells.
        for incr in ["0.5", "0.3", "0.2", "0.1", "0.05"] {
            let first = format!(
                "polyfill3 --pattern {} --incr {incr} tri.json",
                chex.display()
            );
            let (status, said) = through_closed_pipe(dir.path(), &first);
            assert_eq!(status, "0", "incr {incr}: {said}");
            assert!(said.is_empty(), "incr {incr}: {said}");
        }
    }
);

clitest!(a_closed_standard_output_is_an_error, |dir| {
    // `tool >&-`: writes would vanish (Rust puts /dev/null in its place),
    // so a tool that writes there fails; `> /dev/null` stays fine.
    let brick = repo("fixtures/patterns/brick.pat");
    let faces = repo("fixtures/scenes/demo2-faces.json");
    for cmd in [
        format!("pat-info {}", brick.display()),
        format!("polyfill3 {}", faces.display()),
        format!("pat-tile --size 8x8 {}", brick.display()),
    ] {
        let out = sh(dir.path(), &format!("{cmd} >&-"));
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("standard output is closed"),
            "{cmd}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            sh(dir.path(), &format!("{cmd} > /dev/null"))
                .status
                .success(),
            "{cmd}"
        );
    }
});

clitest!(a_closed_standard_output_is_fine_where_nothing_goes, |dir| {
    // `pat-info --check` prints nothing on success, yet failed with a
    // closed standard output, suggesting `-o FILE`, which pat-info lacks.
    // It checks now, and the tools that write there say what they can.
    let brick = repo("fixtures/patterns/brick.pat");
    dir.write("bad.pat", "16 1\n");
    let out = sh(
        dir.path(),
        &format!("pat-info --check {} >&-", brick.display()),
    );
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    let err = sh_fails(dir.path(), "pat-info --check bad.pat >&-");
    assert!(err.starts_with("pat-info: error: bad.pat:"), "{err}");
    for (cmd, hint) in [
        (
            format!("pat-info {}", brick.display()),
            "redirect it to a file, or give --check to validate only",
        ),
        (
            format!(
                "pat-tile --size 8x8 -o ref.png {} && scene-render --compare ref.png --image ref.png",
                brick.display()
            ),
            "the report goes there: redirect it to a file",
        ),
        (
            format!("pat-tile --size 8x8 {}", brick.display()),
            "use -o FILE",
        ),
    ] {
        let err = sh_fails(dir.path(), &format!("{cmd} >&-"));
        let said = format!("standard output is closed: nothing could be written ({hint})\n");
        assert!(err.ends_with(&said), "{cmd}: {err}");
    }
});

clitest!(
    a_report_that_cannot_be_written_leaves_the_old_output,
    |dir| {
        // A hostile-input review: `--compare` or `--reference --json` with
        // standard output closed or full failed (status 1) only after the
        // render and with the new image already in place of the old one. A
        // closed one is refused before the work now, and the report is written
        // before the files take their names.
        dir.triangle_and_its_image();
        let run = "scene-render --size 8x8 -o out.png --diff diff.png s.json";
        for (flags, to) in [
            ("--compare ref.png", ">&-"),
            ("--compare ref.png", ">/dev/full"),
            ("--compare ref.png --json", ">/dev/full"),
            ("--reference --json", ">&-"),
            ("--reference --json", ">/dev/full"),
        ] {
            let run = if flags.starts_with("--reference") {
                run.replace(" --diff diff.png", "")
            } else {
                run.to_string()
            };
            dir.write("out.png", "old");
            dir.write("diff.png", "old diff");
            let err = sh_fails(dir.path(), &format!("{run} {flags} {to}"));
            let said = if to == ">&-" {
                "scene-render: error: standard output is closed: nothing could be written (the \
             report goes there: redirect it to a file)\n"
            } else {
                "scene-render: error: writing standard output: No space left on device (os error \
             28)\n"
            };
            assert_eq!(err, said, "{flags} {to}");
            assert_eq!(dir.read("out.png"), b"old", "{flags} {to}");
            assert_eq!(dir.read("diff.png"), b"old diff", "{flags} {to}");
            let mut left = dir.files();
            left.retain(|f| !["ref.png", "s.json", "out.png", "diff.png"].contains(&f.as_str()));
            assert!(left.is_empty(), "{flags} {to}: {left:?}");
        }
    }
);

clitest!(
    a_report_on_standard_error_that_cannot_be_written_fails,
    |dir| {
        // A hostile-input review: polyfill3's --json summary, and scene-render's
        // report when the image is on standard output, go to standard error,
        // and with it full or closed they were lost with status 0. The error
        // has nowhere to go; the status says it, and polyfill3's old output stays.
        dir.triangle_and_its_image();
        let brick = crate::util::repo("fixtures/patterns/brick.pat");
        std::fs::copy(brick, dir.path().join("b.pat")).unwrap();
        for to in ["2>/dev/full", "2>&-"] {
            dir.write("cells.nd", "old");
            let err = sh_fails(
                dir.path(),
                &format!("polyfill3 --pattern b.pat --json -o cells.nd s.json {to}"),
            );
            assert_eq!(err, "", "{to}");
            assert_eq!(dir.read("cells.nd"), b"old", "{to}");
            let run = format!("scene-render --size 8x8 --compare ref.png -o - --json s.json {to}");
            assert_eq!(
                sh_fails(dir.path(), &format!("{run} >/dev/null")),
                "",
                "{to}"
            );
        }
        // A closed pipe is a reader that wanted no more, as on standard
        // output.
        let pipe = "polyfill3 --pattern b.pat --json -o cells.nd s.json; echo $? > status";
        sh(dir.path(), &format!("( {pipe} ) 2>&1 >/dev/null | true"));
        assert_eq!(dir.read("status"), b"0\n");
        assert_ne!(dir.read("cells.nd"), b"old");
        let mut left = dir.files();
        let ours = ["ref.png", "s.json", "cells.nd", "b.pat", "status"];
        left.retain(|f| !ours.contains(&f.as_str()));
        assert!(left.is_empty(), "{left:?}");
    }
);

/// A command of each tool that reads standard input, and what its error
/// calls that input.
const STDIN_READERS: [(&str, &str); 5] = [
    ("scene-render --size 8x8 -o out.png", "the stream"),
    ("polyfill3", "the stream"),
    ("pat-tile --size 8x8 -o out.png", "the pattern"),
    ("pat-info", "file 1"),
    ("pat-from-image --size 16 -o out.pat", "the picture"),
];

clitest!(standard_streams_open_the_wrong_way_are_errors, |dir| {
    // A hostile-input review: standard input open for writing only
    // (`tool 0>>file`) read as empty, and `polyfill3` and `scene-render`
    // went on with status 0; standard output open for reading only
    // (`tool 1<file`) took the whole output with status 0 and kept none of
    // it. Rust takes the descriptor's EBADF as the end of the input and as
    // a write done.
    dir.write("file", "untouched");
    let brick = repo("fixtures/patterns/brick.pat");
    let scene = repo("fixtures/scenes/demo2-faces.json");
    for (tool, what) in STDIN_READERS {
        let err = sh_fails(dir.path(), &format!("{tool} 0>>file"));
        assert_eq!(
            err,
            format!(
                "{}: error: {what} is standard input, which is open for writing only: nothing \
                 could be read (give a file)\n",
                tool.split(' ').next().unwrap()
            )
        );
    }
    for cmd in [
        format!("pat-info {}", brick.display()),
        format!("polyfill3 {}", scene.display()),
        format!("pat-tile --size 8x8 {}", brick.display()),
        format!("scene-render --size 8x8 {}", scene.display()),
        format!(
            "pat-from-image --size 16 {}",
            repo("fixtures/images/earth.png").display()
        ),
    ] {
        let err = sh_fails(dir.path(), &format!("{cmd} 1<file"));
        assert!(
            err.contains(
                "error: standard output is open for reading only: nothing could be written"
            ),
            "{cmd}: {err}"
        );
    }
    let out = sh(dir.path(), "pat-tile --help 1<file");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "pat-tile: error: standard output is open for reading only\n"
    );
    assert_eq!(dir.read("file"), b"untouched");
    assert_eq!(dir.files(), ["file"]);
});

clitest!(a_closed_standard_input_is_an_error, |dir| {
    // `tool <&-`: it read as empty (Rust puts /dev/null in its place), and
    // scene-render drew a blank image with status 0. `< /dev/null` is an
    // empty input, as before, and a file needs no standard input.
    let scene = repo("fixtures/scenes/demo2-faces.json");
    for (tool, what) in STDIN_READERS {
        let out = sh(dir.path(), &format!("{tool} <&-"));
        assert_eq!(out.status.code(), Some(1), "{tool}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "{}: error: {what} is standard input, which is closed: nothing could be read \
                 (give a file)\n",
                tool.split(' ').next().unwrap()
            )
        );
    }
    assert!(!dir.path().join("out.png").exists());
    assert!(
        sh(dir.path(), "scene-render --size 8x8 -o out.png < /dev/null")
            .status
            .success()
    );
    let out = sh(
        dir.path(),
        &format!("scene-render --size 8x8 -o out.png {} <&-", scene.display()),
    );
    assert!(out.status.success(), "{out:?}");
});

clitest!(a_signal_removes_the_output_being_written, |dir| {
    // SIGTERM (a scheduler's pre-emption), SIGINT and SIGHUP while polyfill3
    // writes a large output: the temporary file goes, the target never
    // appears, and the shell sees death by the signal (128 + N).
    dir.write(
        "big.json",
        format!(
            r#"{{"vertices": [[0,0],[3000,0],[0,3000]], "pattern": {{"file": "{}", "incr": 1}}}}"#,
            repo("fixtures/patterns/brick.pat").display()
        ),
    );
    // A hostile-input review: SIGQUIT (Ctrl-\\) and SIGUSR1 left the
    // temporary file.
    for (name, number) in [
        ("TERM", 15),
        ("INT", 2),
        ("HUP", 1),
        ("QUIT", 3),
        ("USR1", 10),
    ] {
        // Without job control a shell starts background commands with
        // SIGINT and SIGQUIT ignored, and an ignored signal stays so: `env
        // --default-signal` (GNU coreutils) gives them back.
        let script = format!(
            "env --default-signal=INT,QUIT polyfill3 big.json -o out.ndjson & pid=$!; \
             while ! ls -a | grep -q '^\\.patkit-'; do sleep 0.05; done; \
             kill -{name} $pid; wait $pid; echo $? > status"
        );
        let out = sh(dir.path(), &script);
        assert!(out.status.success(), "{out:?}");
        let status = std::fs::read_to_string(dir.path().join("status")).unwrap();
        assert_eq!(status.trim(), (128 + number).to_string(), "SIG{name}");
        let left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".patkit-") || n == "out.ndjson")
            .collect();
        assert!(left.is_empty(), "SIG{name} left {left:?}");
    }
    // Ignored when the tool starts (nohup): the handler made it kill.
    let script = "trap '' HUP; (sleep 1; echo) | polyfill3 -o out.ndjson & pid=$!; \
                  sleep 0.3; kill -HUP $pid; wait $pid; echo $? > status";
    assert!(sh(dir.path(), script).status.success());
    let status = std::fs::read_to_string(dir.path().join("status")).unwrap();
    assert_eq!(status.trim(), "0", "an ignored SIGHUP");
    assert!(dir.path().join("out.ndjson").exists());
});

clitest!(
    a_failed_write_names_the_output_not_its_temporary_file,
    |dir| {
        // A file output that cannot grow (here `ulimit -f`, with SIGXFSZ
        // ignored, so that the write fails with EFBIG as on a full disk): the
        // error names the output, not `tempfile`'s `.patkit-*.tmp` (which is
        // gone by then), and the old file is kept. Writes fail during the
        // encoding (2000x2000) or only at the last flush (100x100).
        dir.write("out.ppm", "old");
        let brick = repo("fixtures/patterns/brick.pat");
        let img = repo("fixtures/images/brick.png");
        for cmd in [
            format!("pat-tile --size 2000x2000 '{}' -o out.ppm", brick.display()),
            format!("pat-tile --size 100x100 '{}' -o out.ppm", brick.display()),
            format!("pat-from-image --size 256 '{}' -o out.ppm", img.display()),
        ] {
            let out = sh(
                dir.path(),
                &format!("trap '' XFSZ; ulimit -f 40; {cmd}; echo $? > status"),
            );
            let said = String::from_utf8_lossy(&out.stderr).into_owned();
            let status = std::fs::read_to_string(dir.path().join("status")).unwrap();
            assert_eq!(status.trim(), "1", "{cmd}: {said}");
            assert!(said.contains("error: writing out.ppm: "), "{cmd}: {said}");
            assert!(!said.contains(".patkit-"), "{cmd}: {said}");
            assert_eq!(dir.read("out.ppm"), b"old", "{cmd}");
            assert_eq!(dir.files(), ["out.ppm", "status"], "{cmd}");
        }
    }
);

clitest!(a_fifo_named_as_the_output_gets_the_whole_output, |dir| {
    // `-o fifo` with a reader waiting: the output checked before the work
    // must not open and close the FIFO (the reader saw an empty input and
    // the tool then waited for another reader for ever).
    dir.write(
        "t.json",
        r#"{"vertices": [[0,0],[9,0],[0,9]], "color": [1,2,3]}"#,
    );
    let img = repo("fixtures/images/brick.png");
    for (tool, args) in [
        ("pat-from-image", format!("--size 16 '{}'", img.display())),
        ("scene-render", "--size 16x16 t.json".to_string()),
    ] {
        let script = format!(
            "rm -f fifo copy; mkfifo fifo && {{ cat fifo > copy & }}; \
             timeout 60 {tool} {args} -o fifo; echo $? > status; wait; \
             {tool} {args} -o file"
        );
        let out = sh(dir.path(), &script);
        assert!(out.status.success(), "{out:?}");
        let status = std::fs::read_to_string(dir.path().join("status")).unwrap();
        assert_eq!(status.trim(), "0", "{tool}: {out:?}");
        let (copy, file) = (dir.read("copy"), dir.read("file"));
        assert!(!file.is_empty() && copy == file, "{tool}: {}", copy.len());
    }
});

clitest!(
    a_missing_output_directory_is_refused_before_the_work,
    |dir| {
        // Issue 17, item 10: refused at once, naming the output and its
        // directory, not the temporary file; nothing is rendered first.
        dir.write(
            "t.json",
            r#"{"vertices": [[0,0],[9,0],[0,9]], "color": [1,2,3]}"#,
        );
        for args in [
            &["--size", "16x16", "t.json", "-o", "no/such/x.png"][..],
            &[
                "--size",
                "16x16",
                "--frames",
                "2",
                "t.json",
                "-o",
                "no/such/f-%d.png",
            ],
            &[
                "--size",
                "16x16",
                "t.json",
                "-o",
                "x.png",
                "--depfile",
                "no/such/x.d",
            ],
        ] {
            let out = dir.cmd("scene-render").args(args).assert().failure();
            let said = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
            assert!(said.contains("cannot create a file in no/such"), "{said}");
            assert!(!said.contains(".patkit-"), "no temporary name: {said}");
        }
        assert!(
            !dir.path().join("x.png").exists(),
            "nothing written when a later output fails"
        );
    }
);

clitest!(files_a_stream_names_are_bounded_and_not_echoed, |dir| {
    // Issue 17, item 4: a scene naming /dev/zero is refused at once, not
    // read forever; a file that is no pattern has none of its words quoted.
    dir.write("secret.txt", "hunter2 is the password\n");
    for (file, said) in [
        ("/dev/zero", "/dev/zero: is not a regular file"),
        (
            "secret.txt",
            "secret.txt:1: word 1: expected the pattern size",
        ),
    ] {
        dir.write(
            "s.json",
            format!(r#"{{"vertices": [[0,0],[4,0],[0,4]], "pattern": {{"file": "{file}"}}}}"#),
        );
        for tool in ["scene-render", "polyfill3", "pat-info"] {
            let mut cmd = dir.cmd(tool);
            if tool == "pat-info" {
                cmd.args(["--record", "0"]);
            }
            let out = cmd
                .args(["s.json"])
                .timeout(std::time::Duration::from_secs(20))
                .output()
                .unwrap();
            let text = String::from_utf8_lossy(&out.stderr);
            if tool != "pat-info" {
                assert!(text.contains(said), "{tool} {file}: {text}");
                assert_eq!(out.status.code(), Some(1), "{tool} {file}");
            }
            assert!(!text.contains("hunter2"), "{tool} {file}: {text}");
        }
    }
    // A command-line input may still be a pipe (`<(...)`).
    let out = sh(
        dir.path(),
        &format!(
            "printf '%s' '{{\"vertices\":[[0,0],[4,0],[0,4]],\"color\":[9,9,9]}}' > t.json; \
             bash -c 'scene-render --size 8x8 --background-pattern <(cat {}) t.json -o t.png'",
            repo("fixtures/patterns/brick.pat").display()
        ),
    );
    assert!(out.status.success(), "{out:?}");
});

clitest!(
    the_image_and_its_difference_appear_together_or_not_at_all,
    |dir| {
        // Issue 17, item 9: a --diff that cannot be written (an extension no
        // format has) used to leave the image behind with exit status 1.
        dir.write(
            "t.json",
            r#"{"vertices": [[0,0],[9,0],[0,9]], "color": [1,2,3]}"#,
        );
        let render = |extra: &[&str]| {
            let mut c = dir.cmd("scene-render");
            c.args(["--size", "16x16", "t.json"]).args(extra);
            c
        };
        render(&["-o", "ref.png"]).assert().success();
        render(&["-o", "out.png", "--compare", "ref.png", "--diff", "d.jpg"])
            .assert()
            .failure();
        assert!(
            !dir.path().join("out.png").exists(),
            "no image without its difference"
        );
        render(&["-o", "out.png", "--compare", "ref.png", "--diff", "d.png"])
            .assert()
            .success();
        assert!(dir.path().join("out.png").exists() && dir.path().join("d.png").exists());
    }
);

clitest!(deep_nesting_is_refused_alike_by_every_tool, |dir| {
    // A chain of objects, each placing the one before: 2,000 of them
    // overflowed scene-render's stack (an abort, status 134), 20,000
    // pat-info's. Every tool now refuses a chain deeper than the limit,
    // 64, with the same words, and draws one of 64.
    let chain = |n: usize| {
        let mut s = String::from(
            r#"{"object": "o0", "records": [{"vertices": [[0,0],[1,0],[0,1]], "color": [255,0,0]}]}"#,
        );
        for k in 1..n {
            s.push_str(&format!(
                "\n{{\"object\": \"o{k}\", \"records\": [{{\"instance\": \"o{}\"}}]}}",
                k - 1
            ));
        }
        s + &format!("\n{{\"instance\": \"o{}\"}}\n", n - 1)
    };
    dir.write("ok.json", chain(64));
    dir.write("deep.json", chain(65));
    dir.write("deeper.json", chain(2000));
    let run = |tool: &str, args: &[&str]| {
        let mut c = dir.cmd(tool);
        c.args(args).timeout(std::time::Duration::from_secs(60));
        c
    };
    run(
        "scene-render",
        &["--size", "8x8", "ok.json", "-o", "ok.png"],
    )
    .assert()
    .success();
    run("polyfill3", &["ok.json", "-o", "ok.ndjson"])
        .assert()
        .success();
    run("pat-info", &["--record", "64", "ok.json"])
        .assert()
        .code(1)
        .stderr(predicates::str::contains(
            "draws no polygon with a \"stripe\"",
        ));
    for (file, depth) in [("deep.json", 65), ("deeper.json", 65)] {
        let said = format!(
            "{file}: record 64: object `o64` nests instances {depth} deep, over the limit of 64\n"
        );
        for (tool, args) in [
            ("scene-render", vec!["--size", "8x8", file, "-o", "out.png"]),
            ("polyfill3", vec![file, "-o", "out.ndjson"]),
            ("pat-info", vec!["--record", "1999", file]),
        ] {
            run(tool, &args)
                .assert()
                .code(1)
                .stderr(format!("{tool}: error: {said}"));
        }
        assert!(!dir.path().join("out.png").exists());
        assert!(!dir.path().join("out.ndjson").exists());
    }
});

clitest!(
    nested_instances_and_huge_quadrics_are_refused_before_any_work,
    |dir| {
        // Issue 17, items 1 and 2: 40 objects, each placing the previous twice,
        // expand to 2^40 polygons (47 s and 6.9 GB before an abort); a sphere of
        // 4096 x 4096 slices and stacks to 33.5 million triangles.
        let mut s = String::from(
            r#"{"object": "o0", "records": [{"vertices": [[0,0],[1,0],[0,1]], "color": [255,0,0]}]}"#,
        );
        for k in 1..40 {
            s.push_str(&format!(
            "\n{{\"object\": \"o{k}\", \"records\": [{{\"instance\": \"o{p}\"}}, {{\"instance\": \"o{p}\"}}]}}",
            p = k - 1
        ));
        }
        s.push_str("\n{\"instance\": \"o39\"}\n");
        dir.write("nested.json", &s);
        let started = std::time::Instant::now();
        dir.cmd("scene-render")
            .args(["nested.json", "-o", "out.png"])
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stderr(
                "scene-render: error: nested.json: record 40: the scene expands to 549755813888 \
             polygons in a frame by here (instances times their objects' polygons, an empty \
             one's counting one, quadrics \
             their triangles, at most slices x stacks x 2, given or as fine as the view needs), \
             over \
             the limit of 10000000 (--max-polygons raises it)\n",
            );
        assert!(started.elapsed().as_secs() < 30, "refused before any work");
        assert!(!dir.path().join("out.png").exists());
        dir.write(
            "sphere.json",
            r#"{"sphere": {"radius": 1, "slices": 4096, "stacks": 4096}, "color": [255,255,255]}"#,
        );
        dir.cmd("scene-render")
            .args(["sphere.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(predicates::str::contains(
                "record 0: the scene expands to 33554432 polygons",
            ));
        // The flag raises the limit: a budget, not a ban.
        dir.cmd("scene-render")
            .args([
                "--max-polygons",
                "4",
                "--size",
                "8x8",
                "nested.json",
                "-o",
                "out.png",
            ])
            .assert()
            .code(1)
            .stderr(predicates::str::contains("over the limit of 4"));
        dir.write("small.json", s.replace("o39\"}\n", "o1\"}\n"));
        dir.cmd("scene-render")
            .args([
                "--max-polygons",
                "2",
                "--size",
                "8x8",
                "small.json",
                "-o",
                "out.png",
            ])
            .assert()
            .success();
        // A sphere without slices and stacks gets as many as its chords need
        // at this view: of radius 1e6 in a 64-pixel frame, 39 million
        // triangles (7.4 GB before they counted, a hostile-input review).
        // Counted when projected, they meet the same limit; so do an
        // object's, once for each instance.
        dir.write(
            "huge.json",
            r#"{"sphere": {"radius": 1e6}, "color": [1,2,3]}"#,
        );
        dir.cmd("scene-render")
            .args(["--size", "64x64", "huge.json", "-o", "huge.png"])
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stderr(predicates::str::contains(
                "huge.json: record 0: the scene expands to 39476088 polygons",
            ))
            .stderr(predicates::str::contains("(--max-polygons raises it)"));
        assert!(!dir.path().join("huge.png").exists());
        let placed = |n: usize| {
            let mut s = String::from(
                r#"{"object": "ball", "records": [{"sphere": {"radius": 20}, "color": [1,2,3]}]}"#,
            );
            for k in 0..n {
                s += &format!(
                    "\n{{\"instance\": \"ball\", \"transform\": [{{\"translate\": [{}, 32, 0]}}]}}",
                    8 * k
                );
            }
            s
        };
        dir.write("one.json", placed(1));
        dir.write("ten.json", placed(10));
        let render = |file: &str| {
            let mut c = dir.cmd("scene-render");
            c.args([
                "--max-polygons",
                "2000",
                "--size",
                "64x64",
                file,
                "-o",
                "out.png",
            ]);
            c
        };
        render("one.json").assert().success();
        render("ten.json")
            .assert()
            .code(1)
            .stderr(predicates::str::contains("over the limit of 2000"));
    }
);

clitest!(
    the_record_that_passes_the_polygon_limit_is_the_same_at_any_thread_count,
    |dir| {
        // The projection threads share the room left for view-tessellated
        // quadrics, but the join adds each run's counts in stream order, so
        // the record named is the one a single thread names. 12,000 spheres
        // of random radius (a fixed LCG), the limit passed in the second
        // projection run (records 4096 to 8191), while the first still
        // counts: a review saw the record change from run to run before.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut unit = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut s = String::new();
        for _ in 0..12_000 {
            let (r, x, y, z) = (1.0 + 7.0 * unit(), 64.0 * unit(), 64.0 * unit(), unit());
            s += &format!(
                "{{\"sphere\": {{\"radius\": {r:.3}}}, \"transform\": {{\"translate\": \
                 [{x:.2}, {y:.2}, {z:.2}]}}, \"color\": [1,2,3]}}\n"
            );
        }
        dir.write("spheres.ndjson", s);
        let refused = |threads: &str| {
            let out = dir
                .cmd("scene-render")
                .args(["--threads", threads, "--size", "64x64"])
                .args([
                    "--max-polygons",
                    "1200000",
                    "spheres.ndjson",
                    "-o",
                    "out.png",
                ])
                .assert()
                .code(1)
                .get_output()
                .stderr
                .clone();
            String::from_utf8(out).unwrap()
        };
        let one = refused("1");
        let record: usize = one
            .split("record ")
            .nth(1)
            .and_then(|rest| rest.split(':').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no record named: {one}"));
        assert!((4096..8192).contains(&record), "{one}");
        for _ in 0..4 {
            assert_eq!(refused("2"), one);
        }
        assert!(!dir.path().join("out.png").exists());
    }
);

clitest!(two_inputs_on_standard_input_are_a_usage_error, |dir| {
    // Issue 18, item 3: `--camera -` with the stream on `-` rendered an
    // empty scene with exit status 0.
    dir.write("cam.json", r#"{"ortho2": [0, 8, 0, 8]}"#);
    dir.cmd("scene-render")
        .args(["--camera", "-", "-o", "x.png"])
        .write_stdin(r#"{"ortho2": [0, 8, 0, 8]}"#)
        .assert()
        .code(2)
        .stderr(
            "scene-render: error: the stream and --camera both name `-`: standard input can be \
             read only once; give one of them a file\n",
        );
    dir.cmd("polyfill3")
        .args(["--cull", "--camera", "-", "-"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains(
            "the stream and --camera both name `-`",
        ));
    assert!(!dir.path().join("x.png").exists());
    // The second reader got an empty input and a misleading error.
    for (tool, args, said) in [
        (
            "scene-render",
            &["--image", "-", "--compare", "-"][..],
            "--image and --compare",
        ),
        (
            "scene-render",
            &["--compare", "-"][..],
            "the stream and --compare",
        ),
        ("pat-info", &["cam.json", "-", "-"][..], "file 2 and file 3"),
        (
            "pat-from-image",
            &["--palette", "-", "-"][..],
            "the picture and --palette",
        ),
    ] {
        dir.cmd(tool)
            .args(args)
            .assert()
            .code(2)
            .stderr(predicates::str::contains(format!(
                "{said} both name `-`: standard input can be read only once"
            )));
    }
    // The same under another of its names (a hostile-input review: the
    // camera took the whole pipe, and the stream rendered empty with
    // status 0).
    for (tool, args, said) in [
        (
            "scene-render",
            &["--camera", "/dev/stdin", "-"][..],
            "the stream - and --camera /dev/stdin",
        ),
        (
            "polyfill3",
            &["--cull", "--camera", "/dev/fd/0"][..],
            "the stream - and --camera /dev/fd/0",
        ),
        (
            "scene-render",
            &["--background-pattern", "/proc/self/fd/0", "/dev/stdin"][..],
            "the stream /dev/stdin and --background-pattern /proc/self/fd/0",
        ),
    ] {
        dir.cmd(tool)
            .args(args)
            .write_stdin(r#"{"ortho2": [0, 8, 0, 8]}"#)
            .assert()
            .code(2)
            .stderr(predicates::str::contains(format!(
                "{said} both name standard input: it can be read only once"
            )));
    }
    // With --image the stream is not read: its default `-` is no second reader.
    dir.write("one.ppm", b"P6\n1 1\n255\n\x01\x02\x03");
    dir.cmd("scene-render")
        .args(["--image", "-", "--compare", "one.ppm"])
        .write_stdin(dir.read("one.ppm"))
        .assert()
        .success();
});

clitest!(pat_from_image_takes_its_size_as_n_or_nxn, |dir| {
    use crate::util::OkStdout;
    let img = crate::util::repo("fixtures/images/brick.png");
    let a = dir
        .cmd("pat-from-image")
        .args(["--size", "32"])
        .arg(&img)
        .ok_stdout();
    let b = dir
        .cmd("pat-from-image")
        .args(["--size", "32x32"])
        .arg(&img)
        .ok_stdout();
    assert_eq!(a, b);
    dir.cmd("pat-from-image")
        .args(["--size", "32x16"])
        .arg(&img)
        .assert()
        .code(2)
        .stderr(predicates::str::contains(
            "invalid size `32x16`: patterns are square (NxN)",
        ));
});

clitest!(out_of_memory_is_an_error_line_and_leaves_nothing, |dir| {
    // Under an address-space limit (the OS's own accounting), an image of
    // 16000 x 16000 pixels (732 MiB of 8-bit RGB) under `ulimit -v 500000`
    // (488 MiB), and a 4096 x 4096 pattern (32 MiB of texel indices) under
    // 32 MiB, need more than the limit: the tools say so as
    // `TOOL: error: out of memory` with status 1 (not an abort, status 134)
    // and leave no temporary file.
    let row = format!("{}\n", vec!["aaaa"; 256].join(" "));
    dir.write(
        "big.pat",
        format!(
            "4096 2\n255 0 0\n{}0 0 255\n{}",
            row.repeat(4096),
            row.replace('a', "5").repeat(4096)
        ),
    );
    dir.write(
        "s.json",
        r#"{"vertices":[[0,0,0],[1,0,0],[1,1,0]],"color":[1,2,3],"pattern":{"file":"big.pat"}}"#,
    );
    for (script, tool) in [
        (
            "ulimit -v 500000; exec scene-render --size 16000x16000 -o out.png /dev/null",
            "scene-render",
        ),
        (
            "ulimit -v 32768; exec polyfill3 s.json -o cells.json",
            "polyfill3",
        ),
    ] {
        let err = sh_fails(dir.path(), script);
        assert!(
            err.starts_with(&format!("{tool}: error: out of memory: a request for ")),
            "{err}"
        );
        assert_eq!(
            dir.files(),
            ["big.pat", "s.json"],
            "{tool} left files behind"
        );
    }
});

clitest!(
    a_long_strip_is_cut_in_memory_that_does_not_grow_with_its_length,
    |dir| {
        // One row of 4,000,000 texels: polyfill3 kept a table of every column
        // line (32 bytes each, a 91.6 MiB request here, 1.5 GB at 49 million)
        // and failed under 64 MiB of address space; the columns are now
        // computed where used. The cells still all come out.
        dir.write(
            "strip.json",
            r#"{"vertices":[[0,0],[4000000,0],[4000000,1],[0,1]],"color":[1,2,3]}"#,
        );
        dir.write(
            "p.pat",
            "16 1\n200 100 50\n".to_string() + &"ffff\n".repeat(16),
        );
        let out = sh(
        dir.path(),
        "ulimit -v 65536; exec polyfill3 --threads 1 --pattern p.pat --json strip.json -o /dev/null",
    );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{err}");
        let summary: serde_json::Value = serde_json::from_str(&err).unwrap();
        assert_eq!(summary["polygons"], 4_000_000, "{err}");
    }
);

clitest!(too_little_address_space_for_threads_is_no_panic, |dir| {
    // Under 8 MB of address space a worker thread's stack does not fit:
    // each tool that starts threads (the signal watcher, the pool) says so
    // in an error line, where `std::thread::spawn` used to panic (status
    // 101).
    dir.write(
        "s.json",
        r#"{"vertices":[[0,0,0],[1,0,0],[1,1,0]],"color":[1,2,3]}"#,
    );
    for script in [
        "ulimit -v 8000; exec scene-render --size 8x8 -o out.png s.json",
        "ulimit -v 8000; exec polyfill3 s.json",
    ] {
        let out = sh(dir.path(), script);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(101), "{script}: {err}");
        assert!(!err.contains("panicked"), "{script}: {err}");
    }
});

clitest!(
    dev_zero_is_refused_at_its_first_bytes_by_every_tool,
    |dir| {
        // Issue 17, item 4: `pat-info /dev/zero` grew to 3.1 GB in 15 s and
        // `scene-render /dev/zero` aborted. Every input is checked as its first
        // bytes arrive: refused at once, under a 512 MiB address-space ceiling.
        dir.write(
            "t.json",
            r#"{"vertices":[[0,0],[1,0],[1,1]],"color":[1,1,1]}"#,
        );
        for (cmd, says) in [
            (
                "pat-info /dev/zero",
                "byte 0x00 on line 1 (offset 0) is not text",
            ),
            ("pat-info --record 0 /dev/zero", "is not text"),
            ("pat-tile /dev/zero -o z.png", "is not text"),
            (
                "pat-from-image /dev/zero -o z.pat",
                "not an image this tool can read",
            ),
            (
                "scene-render /dev/zero -o z.png",
                "starts with byte 0x00, not `[`",
            ),
            (
                "polyfill3 /dev/zero -o z.json",
                "starts with byte 0x00, not `[`",
            ),
            (
                "scene-render --image /dev/zero --compare /dev/zero",
                "not an image this tool can read",
            ),
            (
                "scene-render --background-pattern /dev/zero t.json -o z.png",
                "is not text",
            ),
        ] {
            let err = sh_fails(dir.path(), &format!("ulimit -v 524288; exec {cmd}"));
            assert!(
                err.contains("/dev/zero: ") && err.contains(says),
                "{cmd}: {err}"
            );
            assert_eq!(dir.files(), ["t.json"], "{cmd} left files behind");
        }
    }
);

clitest!(polyfill3_writes_a_large_quadric_in_bounded_memory, |dir| {
    // Issue 17, item 2: polyfill3 held every triangle of a quadric (as JSON
    // values) before writing one: 2.9 GB for a radius-1000 sphere. Now they
    // are written as they are made; this radius-200 sphere (about 130,000
    // triangles, 400 MB the old way) runs under a 256 MiB address-space
    // ceiling, and a record over --max-polygons is refused before any
    // tessellation, from its slices and stacks.
    dir.write(
        "s.json",
        format!(
            r#"{{"sphere":{{"radius":200}},"color":[1,2,3],"pattern":{{"file":"{}"}}}}"#,
            repo("fixtures/patterns/brick.pat").display()
        ),
    );
    let out = sh(
        dir.path(),
        "ulimit -v 262144; exec polyfill3 --json s.json -o cells.json",
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let summary: serde_json::Value = serde_json::from_str(err.trim()).unwrap();
    assert!(summary["polygons"].as_u64().unwrap() > 100_000, "{summary}");
    dir.write(
        "huge.json",
        r#"{"sphere":{"radius":1,"slices":16384,"stacks":16384},"color":[1,2,3]}"#,
    );
    let out = sh(
        dir.path(),
        "ulimit -v 262144; exec polyfill3 huge.json -o huge-cells.json",
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "536838144 triangles of the quadric would take the output past --max-polygons 50000000"
        ),
        "{err}"
    );
    assert!(!dir.path().join("huge-cells.json").exists());
});

#[cfg(target_os = "linux")]
clitest!(pipes_on_standard_input_and_output_are_widened, |dir| {
    // A stream through `polyfill3 | scene-render` moves in pipe-fulls: each
    // tool widens a pipe of the default 64 KiB on its standard input or
    // output to 256 KiB, and leaves a pipe someone sized alone. Both ends of
    // a pipe see its size, so it is read here from the test's end, after the
    // tool is done (for standard input, from a duplicate of the tool's read
    // end: the write end is closed to end the input).
    use std::io::Write as _;
    use std::os::fd::{AsRawFd as _, FromRawFd as _, OwnedFd};
    use std::process::{Command, Stdio};
    let pipe_size = |fd| unsafe { libc::fcntl(fd, libc::F_GETPIPE_SZ) };
    // A new pipe, close-on-exec (or the tool would hold its own input open).
    let pipe = || {
        let mut fds = [0; 2];
        assert_eq!(unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) }, 0);
        // SAFETY: both descriptors are new and owned here alone.
        unsafe {
            (
                OwnedFd::from_raw_fd(fds[0]),
                std::fs::File::from_raw_fd(fds[1]),
            )
        }
    };
    // Widening can be refused: a lower `pipe-max-size`, a spent pipe budget.
    let (probe, _) = pipe();
    let default = pipe_size(probe.as_raw_fd());
    let widens = unsafe { libc::fcntl(probe.as_raw_fd(), libc::F_SETPIPE_SZ, 1 << 18) } > 0;
    if !crate::util::required("widening a pipe to 256 KiB", widens && default == 1 << 16) {
        return;
    }
    // A few kB of cells: the tool ends whatever the pipe's size.
    let face = dir.write(
        "face.json",
        format!(
            r#"{{"vertices":[[100,0,100],[100,0,-100],[0,142.2,0]],"color":[1,2,3],"pattern":{{"file":"{}","incr":25}}}}"#,
            repo("fixtures/patterns/pyr.pat").display()
        ),
    );
    let mut p3 = Command::new(env!("CARGO_BIN_EXE_polyfill3"))
        .arg(&face)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let cells = p3.stdout.take().unwrap();
    assert!(p3.wait().unwrap().success());
    assert_eq!(pipe_size(cells.as_raw_fd()), 1 << 18);

    // scene-render reading a pipe of `size` bytes: its size after the run.
    let read_through_pipe = |size: i32| {
        let (read_end, mut input) = pipe();
        let set = unsafe { libc::fcntl(read_end.as_raw_fd(), libc::F_SETPIPE_SZ, size) };
        assert_eq!(set, size);
        let kept = read_end.try_clone().unwrap();
        let mut sr = Command::new(env!("CARGO_BIN_EXE_scene-render"))
            .args(["--size", "8x8", "-", "-o"])
            .arg(dir.path().join("out.png"))
            .stdin(Stdio::from(read_end))
            .spawn()
            .unwrap();
        input
            .write_all(br#"{"vertices":[[0,0,0],[8,0,0],[0,8,0]],"color":[9,9,9]}"#)
            .unwrap();
        drop(input);
        assert!(sr.wait().unwrap().success());
        pipe_size(kept.as_raw_fd())
    };
    assert_eq!(read_through_pipe(1 << 16), 1 << 18);
    // Pipes sized by someone else are left as they are.
    assert_eq!(read_through_pipe(1 << 14), 1 << 14);
    assert_eq!(read_through_pipe(1 << 17), 1 << 17);
});

clitest!(a_camera_file_is_read_only_to_its_limit, |dir| {
    // `--camera /dev/zero` (not text) is refused at once, and an endless
    // pipe of text stops at 1 MiB, instead of reading until memory runs out.
    let tri = r#"{"vertices":[[0,0],[4,0],[0,4]],"color":[200,100,50]}"#;
    dir.write("tri.json", tri);
    for (cmd, want) in [
        (
            "scene-render --camera /dev/zero --size 8x8 tri.json -o t.png",
            "/dev/zero: cannot read camera: byte 0x00 on line 1 (offset 0) is not text",
        ),
        (
            "yes | polyfill3 --camera - --cull tri.json -o t.ndjson",
            "is larger than the 1048576 bytes this input may have",
        ),
    ] {
        let said = sh_fails(dir.path(), cmd);
        assert!(said.contains(want), "{cmd}: {said}");
    }
});

clitest!(pat_info_names_standard_output_when_it_is_full, |dir| {
    // A hostile-input review found `pat-info brick.pat > /dev/full` saying
    // only "pat-info: error: No space left on device (os error 28)", where
    // the other tools say what they were writing.
    let brick = repo("fixtures/patterns/brick.pat");
    for flags in ["", "--json", "--preview --color never"] {
        let cmd = format!("pat-info {flags} {} > /dev/full", brick.display());
        let said = sh_fails(dir.path(), &cmd);
        assert!(
            said.starts_with("pat-info: error: writing standard output: No space left on device"),
            "{cmd}: {said}"
        );
    }
});

clitest!(
    a_pattern_input_that_is_not_one_is_refused_in_little_memory,
    |dir| {
        // A hostile-input review found `yes | pat-tile -` and
        // `yes ' ' | pat-tile -` taking 265 MB before refusing: what did not
        // start as a pattern in its first 4096 bytes was read whole, to 256 MiB.
        // The readers of nothing but patterns (and images) now stream all but
        // an image; pat-info streams all that cannot be a modulation map.
        dir.write(
            "tri.json",
            r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
        );
        let tools = [
            "pat-tile --size 8x8 -o t.png -",
            "pat-info --check -",
            "scene-render --size 8x8 --background-pattern - -o s.png tri.json",
        ];
        for (feed, said, who) in [
            (
                "yes",
                "<stdin>:1: word 1: expected the pattern size, a multiple of 16 from 16 to 4096",
                &tools[..],
            ),
            (
                "yes ' '",
                "<stdin>: is longer than the 268435456 bytes an input may have before a \
             pattern's `SIZE NCOLORS`",
                &[tools[0], tools[2]][..],
            ),
        ] {
            for tool in who {
                let script = format!("{feed} | sh -c 'ulimit -v 196608; exec {tool}'");
                let err = sh_fails(dir.path(), &script);
                let name = tool.split(' ').next().unwrap();
                assert_eq!(err, format!("{name}: error: {said}\n"), "{script}");
            }
        }
        // A pattern after 4 KiB of blank lines, streamed, counts its lines.
        let late = format!("{}16 1\n1 2 300\n", "\n".repeat(5000));
        dir.write("late.pat", &late);
        for tool in tools {
            let words: Vec<&str> = tool.split(' ').collect();
            let script = words
                .iter()
                .map(|&w| if w == "-" { "late.pat" } else { w })
                .collect::<Vec<_>>()
                .join(" ");
            let err = sh_fails(dir.path(), &script);
            assert!(
                err.contains("late.pat:5002: word 5 `300`: out of range"),
                "{script}: {err}"
            );
        }
        assert_eq!(dir.files(), ["late.pat", "tri.json"]);
    }
);

clitest!(an_empty_input_name_is_said_so_by_every_tool, |dir| {
    // A hostile-input review found `pat-tile ''` (and scene-render,
    // polyfill3, pat-from-image, --background-pattern '', --palette '')
    // saying only "No such file or directory (os error 2)": the name the
    // error shows was the empty string. It is a bad argument, as `-o ''`
    // is: status 2, said before anything is read, naming the input (it was
    // status 1, and `pat-info '' a.pat` reported it among the files).
    dir.write(
        "tri.json",
        r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3]}"#,
    );
    let photo = repo("fixtures/images/earth-nasa.jpg");
    let photo = photo.to_str().unwrap();
    let brick = repo("fixtures/patterns/brick.pat");
    let brick = brick.to_str().unwrap();
    let said = "an empty input name: expected a file name, or - for standard input";
    for (args, what) in [
        (vec!["pat-tile", "--size", "8x8", ""], "the pattern"),
        (vec!["pat-info", ""], "file 1"),
        (vec!["pat-info", brick, ""], "file 2"),
        (vec!["pat-info", "--record", "0", ""], "file 1"),
        (vec!["scene-render", "-o", "s.png", ""], "the stream"),
        (vec!["polyfill3", ""], "the stream"),
        (vec!["pat-from-image", "-o", "p.pat", ""], "the picture"),
        (
            vec![
                "scene-render",
                "--background-pattern",
                "",
                "-o",
                "s.png",
                "tri.json",
            ],
            "--background-pattern",
        ),
        (
            vec!["scene-render", "--camera", "", "-o", "s.png", "tri.json"],
            "--camera",
        ),
        (
            vec!["scene-render", "--compare", "", "-o", "s.png", "tri.json"],
            "--compare",
        ),
        (
            vec!["pat-from-image", "--palette", "", "-o", "p.pat", photo],
            "--palette",
        ),
    ] {
        dir.cmd(args[0])
            .args(&args[1..])
            .assert()
            .code(2)
            .stdout("")
            .stderr(format!("{}: error: {what}: {said}\n", args[0]));
    }
    assert_eq!(dir.files(), ["tri.json"]);
    // With standard output closed as well, the usage error is said, and
    // its status given (`pat-info '' >&-` said the closed output, status 1).
    for script in [
        "pat-info '' >&-",
        "pat-tile --size 8x8 '' >&-",
        "pat-from-image '' >&-",
        "scene-render '' >&-",
        "polyfill3 '' >&-",
    ] {
        let out = sh(dir.path(), script);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{script}: {err}");
        assert!(err.contains(said), "{script}: {err}");
    }
});

clitest!(
    pat_info_and_palette_read_past_blank_lines_in_little_memory,
    |dir| {
        // A hostile-input review found `yes ' ' | pat-info -` (and the same
        // into pat-from-image --palette -) taking 265 MB: 4096 bytes of
        // whitespace could not tell a pattern from a map (or a colour list),
        // so the input was read whole, to 256 MiB. Blank lines are now read
        // past, keeping only their count, and the lines of every error after
        // them are as before.
        let photo = repo("fixtures/images/earth-nasa.jpg");
        let palette = format!("pat-from-image --palette - -o p.pat {}", photo.display());
        for tool in ["pat-info --check -", &palette] {
            let script = format!("yes ' ' | sh -c 'ulimit -v 196608; exec {tool}'");
            let err = sh_fails(dir.path(), &script);
            assert!(
                err.ends_with(
                    "reading standard input: is larger than the 268435456 bytes this input may \
                     have\n"
                ),
                "{script}: {err}"
            );
        }
        let blank = " \r\n".repeat(3000);
        dir.write("m.map", format!("{blank}# a map\nSTRIPE 4\n1 2 3 300\n"));
        dir.write("c.pat", format!("{blank}16 1\n1 2 300\n"));
        dir.write("l.txt", format!("{blank}16,0,0\n1,2\n"));
        for (cmd, said) in [
            (
                "pat-info - < m.map",
                "<stdin>:3003: word 6 `300`: out of range",
            ),
            ("pat-info m.map", "m.map:3003: word 6 `300`: out of range"),
            (
                "pat-info - < c.pat",
                "<stdin>:3002: word 5 `300`: out of range",
            ),
            (
                &format!(
                    "pat-from-image --palette l.txt -o p.pat {}",
                    photo.display()
                ),
                "l.txt:3002: invalid colour `1,2`",
            ),
            (
                &format!(
                    "pat-from-image --palette c.pat -o p.pat {}",
                    photo.display()
                ),
                "c.pat:3002: word 5 `300`: out of range",
            ),
        ] {
            let err = sh_fails(dir.path(), cmd);
            assert!(err.contains(said), "{cmd}: {err}");
        }
        assert_eq!(dir.files(), ["c.pat", "l.txt", "m.map"]);
    }
);

clitest!(an_output_never_replaces_an_input, |dir| {
    // A hostile-input review: each of these replaced its input (the scene
    // with a PNG, the reference with the difference, the pattern with
    // polygons) and exited 0. Now a usage error before any work, or, for a
    // file the stream names, an error before the output is put in place.
    dir.write(
        "scene.json",
        r#"{"vertices": [[0,0],[6,0],[0,6]], "color": [9,9,9]}"#,
    );
    dir.write(
        "textured.json",
        r#"{"vertices": [[0,0,0],[8,0,0],[0,8,0]], "pattern": {"file": "mine.pat", "mode": "object"}}"#,
    );
    std::fs::copy(
        repo("fixtures/patterns/brick.pat"),
        dir.path().join("mine.pat"),
    )
    .unwrap();
    dir.cmd("scene-render")
        .args(["--size", "8x8", "scene.json", "-o", "ref.png"])
        .assert()
        .success();
    let kept = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    let (scene, reference, pattern) = (kept("scene.json"), kept("ref.png"), kept("mine.pat"));
    for (tool, args, code, said) in [
        ("scene-render", vec!["--format", "png", "scene.json", "-o", "./scene.json"], 2,
         "-o ./scene.json: the same file as the stream scene.json: the output would replace an input"),
        ("scene-render", vec!["--size", "8x8", "scene.json", "--compare", "ref.png", "--diff", "ref.png", "-o", "new.png"], 2,
         "--diff ref.png: the same file as --compare ref.png"),
        ("polyfill3", vec!["--depfile", "scene.json", "-o", "cells.ndjson", "scene.json"], 2,
         "--depfile scene.json: the same file as the stream scene.json"),
        ("polyfill3", vec!["--pattern", "mine.pat", "-o", "mine.pat", "scene.json"], 2,
         "-o mine.pat: the same file as --pattern mine.pat"),
        ("polyfill3", vec!["-o", "mine.pat", "textured.json"], 1,
         "-o mine.pat: the same file as the input ./mine.pat: the output would replace it"),
        ("scene-render", vec!["--size", "8x8", "--format", "png", "-o", "mine.pat", "textured.json"], 1,
         "-o mine.pat: the same file as the input ./mine.pat: the output would replace it"),
        ("pat-tile", vec!["--pat", "--size", "16x16", "-o", "mine.pat", "mine.pat"], 2,
         "-o mine.pat: the same file as the pattern mine.pat"),
        ("pat-from-image", vec!["--size", "16", "-o", "ref.png", "ref.png"], 2,
         "-o ref.png: the same file as the picture ref.png"),
    ] {
        dir.cmd(tool)
            .args(&args)
            .assert()
            .code(code)
            .stderr(predicates::str::contains(said));
    }
    // A review's cases: a later frame of an animation over an input, a
    // screen pattern polyfill3 passes on unread, standard input that is
    // the file written.
    std::fs::copy(
        dir.path().join("scene.json"),
        dir.path().join("frame-0003.png"),
    )
    .unwrap();
    dir.write(
        "screen.json",
        r#"{"vertices": [[1,1],[30,2],[10,30]], "pattern": {"file": "mine.pat", "mode": "screen"}}"#,
    );
    for (tool, args, said) in [
        (
            "scene-render",
            vec![
                "--size",
                "8x8",
                "--frames",
                "5",
                "frame-0003.png",
                "-o",
                "frame-%04d.png",
            ],
            "-o frame-0003.png: the same file as the input frame-0003.png",
        ),
        (
            "polyfill3",
            vec!["screen.json", "-o", "mine.pat"],
            "-o mine.pat: the same file as the input ./mine.pat",
        ),
    ] {
        dir.cmd(tool)
            .args(&args)
            .assert()
            .code(1)
            .stderr(predicates::str::contains(said));
    }
    let out = sh(
        dir.path(),
        "scene-render --size 8x8 - -o /dev/stdin < scene.json",
    );
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("-o /dev/stdin: the same file as the stream -"));
    assert_eq!(kept("frame-0003.png"), scene);
    assert_eq!(kept("scene.json"), scene);
    assert_eq!(kept("ref.png"), reference);
    assert_eq!(kept("mine.pat"), pattern);
    // Without --frames, `%` in -o is a name like any other.
    std::fs::copy(
        dir.path().join("scene.json"),
        dir.path().join("frame-0000.png"),
    )
    .unwrap();
    dir.cmd("scene-render")
        .args(["--size", "8x8", "frame-0000.png", "-o", "frame-%04d.png"])
        .assert()
        .success();
    // A device or another name for another file is no input.
    dir.cmd("scene-render")
        .args(["--size", "8x8", "scene.json", "-o", "/dev/null"])
        .assert()
        .success();
});

clitest!(
    a_make_rule_that_cannot_be_written_leaves_the_output_alone,
    |dir| {
        // A hostile-input review: the output was put in place before the rule
        // was written, so a failed --depfile left a new target with no rule
        // naming its files, and exit status 1.
        dir.write(
            "scene.json",
            r#"{"vertices": [[0,0],[6,0],[0,6]], "color": [9,9,9]}"#,
        );
        dir.write("out.ndjson", "ORIGINAL");
        dir.write("out.png", "ORIGINAL");
        for (tool, args) in [
            (
                "polyfill3",
                vec!["--depfile", "/dev/full", "-o", "out.ndjson", "scene.json"],
            ),
            (
                "scene-render",
                vec![
                    "--size",
                    "8x8",
                    "--depfile",
                    "/dev/full",
                    "-o",
                    "out.png",
                    "scene.json",
                ],
            ),
        ] {
            dir.cmd(tool)
                .args(&args)
                .assert()
                .code(1)
                .stderr(predicates::str::contains("writing /dev/full"));
        }
        assert_eq!(
            std::fs::read_to_string(dir.path().join("out.ndjson")).unwrap(),
            "ORIGINAL"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("out.png")).unwrap(),
            "ORIGINAL"
        );
        dir.cmd("polyfill3")
            .args([
                "--depfile",
                "no/such/dir/x.d",
                "-o",
                "out.ndjson",
                "scene.json",
            ])
            .assert()
            .failure();
        assert_eq!(
            std::fs::read_to_string(dir.path().join("out.ndjson")).unwrap(),
            "ORIGINAL"
        );
    }
);

#[cfg(target_os = "linux")]
clitest!(
    an_output_named_by_a_descriptor_is_written_through_it,
    |dir| {
        use crate::util::OkStdout;
        // `-o /dev/stdout` with standard output appending to a file: the name
        // reached the file itself, and the rename replaced it, losing what it
        // held (a hostile-input review). Each name below now writes through
        // the descriptor, as `-o -` does, after what the file held.
        let brick = repo("fixtures/patterns/brick.pat");
        let brick = brick.to_str().unwrap();
        let pat = dir
            .cmd("pat-tile")
            .args(["--pat", "--size", "16x16", brick, "-o", "-"])
            .ok_stdout();
        dir.write("log", "KEEP\n");
        let names = ["/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"];
        for name in names {
            let script = format!("pat-tile --pat --size 16x16 '{brick}' -o {name} >> log");
            assert!(sh(dir.path(), &script).status.success(), "{name}");
        }
        let mut expected = b"KEEP\n".to_vec();
        for _ in names {
            expected.extend_from_slice(&pat);
        }
        assert_eq!(dir.read("log"), expected);
        // What the group writes before and after stays too.
        let script = format!(
            "{{ echo HEADER; pat-tile --pat --size 16x16 '{brick}' -o /dev/stdout; echo FOOTER; }} > group"
        );
        assert!(sh(dir.path(), &script).status.success());
        let mut expected = b"HEADER\n".to_vec();
        expected.extend_from_slice(&pat);
        expected.extend_from_slice(b"FOOTER\n");
        assert_eq!(dir.read("group"), expected);
    }
);

#[cfg(unix)]
clitest!(outputs_through_links_and_empty_names, |dir| {
    // A link to a file not made yet: made there, as `>` makes it; it was
    // "cannot resolve the link".
    std::os::unix::fs::symlink("made.png", dir.path().join("link.png")).unwrap();
    let brick = repo("fixtures/patterns/brick.pat");
    let brick = brick.to_str().unwrap();
    dir.cmd("pat-tile")
        .args(["--size", "4x4", brick, "-o", "link.png"])
        .assert()
        .success();
    assert!(std::fs::symlink_metadata(dir.path().join("link.png"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(dir.read("made.png").starts_with(b"\x89PNG"));
    // `-o ''` is a bad flag value: status 2 (it was 1).
    for (tool, args) in [
        ("pat-tile", vec!["--size", "4x4", brick, "-o", ""]),
        ("pat-from-image", vec!["-o", "", "made.png"]),
    ] {
        dir.cmd(tool)
            .args(args)
            .assert()
            .code(2)
            .stderr(predicates::str::contains("an empty output name"));
    }
});

#[cfg(unix)]
clitest!(
    a_picture_file_past_the_limit_is_refused_by_its_length,
    |dir| {
        // A PNG followed by gigabytes: refused from the file's length before
        // any of it is read. It was read into 2 GB of memory first, which
        // `ulimit -v` (1 GiB here) makes an out-of-memory error instead.
        let png = std::fs::read(repo("fixtures/images/marble.png")).unwrap();
        let f = std::fs::File::create(dir.path().join("huge.png")).unwrap();
        std::io::Write::write_all(&mut &f, &png).unwrap();
        f.set_len(3 << 30).unwrap(); // sparse: no disk used
        let err = sh_fails(
            dir.path(),
            "ulimit -v 1048576; exec pat-from-image huge.png -o out.pat",
        );
        assert_eq!(
            err,
            "pat-from-image: error: huge.png: is larger than the 2147549184 bytes this input may have\n"
        );
        assert!(!dir.path().join("out.pat").exists());
    }
);

clitest!(
    a_picture_within_the_limits_is_not_refused_by_the_decoder,
    |dir| {
        // A 12000x12000 RGBA TIFF (576 MB of pixels, within the tools' 2^28)
        // was refused as "Memory limit exceeded": the decoder's own default
        // allowance is 512 MiB. It is now allowed the picture it holds.
        if !crate::util::heavy("a 576 MB TIFF") {
            return;
        }
        let side = 12_000u32;
        let mut pixels = vec![0u8; (side * side * 4) as usize];
        for (i, p) in pixels.chunks_exact_mut(4).enumerate() {
            p.copy_from_slice(&[(i % 251) as u8, 80, 160, 255]);
        }
        let f = std::fs::File::create(dir.path().join("big.tif")).unwrap();
        use image::ImageEncoder as _;
        image::codecs::tiff::TiffEncoder::new(std::io::BufWriter::new(f))
            .write_image(&pixels, side, side, image::ExtendedColorType::Rgba8)
            .unwrap();
        drop(pixels);
        dir.cmd("pat-from-image")
            .args(["--size", "16", "--colors", "4", "big.tif", "-o", "big.pat"])
            .assert()
            .success();
        assert!(dir.read("big.pat").starts_with(b"16 "));
    }
);

clitest!(
    a_mesh_s_obj_and_mtl_files_are_inputs_like_any_other,
    |dir| {
        // A hostile-input review: `-o` or `--depfile` naming a mesh's OBJ or
        // MTL file replaced it (exit 0), and neither tool's make rule named
        // them, so editing the model rebuilt nothing.
        let obj = std::fs::read(repo("fixtures/models/house.obj")).unwrap();
        let mtl = std::fs::read_to_string(repo("fixtures/models/house.mtl")).unwrap();
        let image = repo("fixtures/images/marble.png");
        let mtl = mtl.replace("../images/marble.png", image.to_str().unwrap());
        dir.write("house.obj", &obj);
        dir.write("house.mtl", &mtl);
        dir.write("m.json", r#"{"mesh": {"obj": "house.obj"}}"#);
        for (tool, args) in [
            ("polyfill3", vec!["m.json", "-o", "house.obj"]),
            ("polyfill3", vec!["m.json", "-o", "house.mtl"]),
            (
                "polyfill3",
                vec!["m.json", "-o", "p.ndjson", "--depfile", "house.obj"],
            ),
            (
                "scene-render",
                vec![
                    "--size",
                    "8x8",
                    "--format",
                    "png",
                    "m.json",
                    "-o",
                    "house.obj",
                ],
            ),
            (
                "scene-render",
                vec![
                    "--size",
                    "8x8",
                    "m.json",
                    "-o",
                    "s.png",
                    "--depfile",
                    "house.mtl",
                ],
            ),
        ] {
            dir.cmd(tool)
                .args(&args)
                .assert()
                .code(1)
                .stderr(predicates::str::contains("the output would replace it"));
            assert_eq!(dir.read("house.obj"), obj, "{tool} {args:?}");
            assert_eq!(dir.read("house.mtl"), mtl.as_bytes(), "{tool} {args:?}");
        }
        for (tool, args) in [
            (
                "polyfill3",
                vec!["m.json", "-o", "p.ndjson", "--depfile", "p.d"],
            ),
            (
                "scene-render",
                vec!["--size", "8x8", "m.json", "-o", "s.png", "--depfile", "s.d"],
            ),
        ] {
            dir.cmd(tool).args(&args).assert().success();
            let rule = String::from_utf8(dir.read(args.last().unwrap())).unwrap();
            for dep in ["m.json", "house.obj", "house.mtl"] {
                assert!(rule.contains(&format!("\n  {dep}")), "{tool}: {rule}");
                assert!(rule.contains(&format!("\n{dep}:\n")), "{tool}: {rule}");
            }
        }
    }
);

clitest!(
    placements_of_empty_objects_count_against_the_limits,
    |dir| {
        // Twelve objects each placing the one before ten times, the first
        // empty: 10^12 placements that draw nothing escaped --max-polygons and
        // pat-info --record's budget, which counted what is drawn (a
        // hostile-input review: hours of work for a 1 KB file).
        let mut s = String::from("{\"object\": \"o0\", \"records\": []}\n");
        for k in 1..=12 {
            let inner = format!("{{\"instance\": \"o{}\"}}", k - 1);
            let ten = vec![inner; 10].join(", ");
            s += &format!("{{\"object\": \"o{k}\", \"records\": [{ten}]}}\n");
        }
        s += "{\"instance\": \"o12\"}\n";
        dir.write("fan.json", &s);
        dir.cmd("scene-render")
            .args(["--size", "8x8", "fan.json", "-o", "out.png"])
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stderr(predicates::str::contains(
                "fan.json: record 13: the scene expands to 1000000000000 polygons",
            ));
        dir.cmd("pat-info")
            .args(["--record", "13", "fan.json"])
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stderr(
                "pat-info: error: fan.json: record 13: expands to 1111111111110 records and \
             instances (nested instances multiply), more than the 100000 that can be listed\n",
            );
        // A few empty placements are no error: an empty object draws nothing.
        dir.write("few.json", s.replace("\"o12\"}\n", "\"o2\"}\n"));
        dir.cmd("scene-render")
            .args(["--size", "8x8", "few.json", "-o", "out.png"])
            .assert()
            .success();
        dir.cmd("pat-info")
            .args(["--record", "13", "few.json"])
            .assert()
            .code(1)
            .stderr(predicates::str::contains(
                "(instance of `o2`) draws no polygon",
            ));
    }
);

clitest!(
    transforms_that_overflow_or_flatten_only_together_are_refused,
    |dir| {
        // Each step or instance fine alone, not together: the polygons were
        // dropped with at most a warning, exit 0 (a hostile-input review).
        let a = r#"{"object": "a", "records": [{"vertices": [[0,0,0],[10,0,0],[0,10,0]], "color": [255,0,0]}]}"#;
        let nested = format!(
            "{a}\n{{\"object\": \"b\", \"records\": [{{\"instance\": \"a\", \"transform\": {{\"translate\": [1e308,0,0]}}}}]}}\n\
             {{\"instance\": \"b\", \"transform\": {{\"translate\": [1e308,0,0]}}}}\n"
        );
        dir.write("nested.json", &nested);
        dir.write(
        "steps.json",
        format!(
            "{a}\n{{\"instance\": \"a\", \"transform\": [{{\"scale\": [1,1e-7,1]}}, {{\"rotate\": 45, \"axis\": \"z\"}}, {{\"scale\": [1,1e-7,1]}}]}}\n"
        ),
    );
        dir.cmd("scene-render")
            .args(["--size", "8x8", "nested.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(
                "scene-render: error: nested.json: record 2: instance of `a`: its transform with \
             those of the instances placing it: a matrix entry is not finite\n",
            );
        dir.cmd("pat-info")
            .args(["--record", "2", "nested.json"])
            .assert()
            .code(1)
            .stderr(
                "pat-info: error: nested.json: record 2: object `b`: instance of `a`: its \
             transform with those of the instances placing it: a matrix entry is not finite\n",
            );
        dir.cmd("scene-render")
            .args(["--size", "8x8", "steps.json", "-o", "out.png"])
            .assert()
            .code(1)
            .stderr(predicates::str::contains(
                "steps.json: record 1: instance of `a`: transform steps together: singular: \
             determinant 1e-14 squashes space flat",
            ));
        assert!(!dir.path().join("out.png").exists());
        // Large but finite together: drawn.
        dir.write("fine.json", nested.replace("1e308", "1e300"));
        dir.cmd("scene-render")
            .args(["--size", "8x8", "fine.json", "-o", "out.png"])
            .assert()
            .success();
    }
);

clitest!(help_and_version_that_cannot_be_written_are_errors, |dir| {
    // `--help > /dev/full` and `--help >&-` said nothing and exited 0 (a
    // hostile-input review); a reader that stops early is no error.
    let full = "writing standard output: No space left on device (os error 28)";
    for tool in [
        "pat-from-image",
        "pat-info",
        "pat-tile",
        "polyfill3",
        "scene-render",
    ] {
        for (script, said) in [
            (format!("{tool} --help > /dev/full"), full),
            (format!("{tool} --version > /dev/full"), full),
            (format!("{tool} --help >&-"), "standard output is closed"),
        ] {
            let err = sh_fails(dir.path(), &script);
            assert_eq!(err, format!("{tool}: error: {said}\n"), "{script}");
        }
        let (status, said) = through_closed_pipe(dir.path(), &format!("{tool} --help"));
        assert_eq!((status.as_str(), said.as_str()), ("0", ""), "{tool}");
    }
});

clitest!(
    a_reference_of_another_size_is_refused_before_anything_is_drawn_or_decoded,
    |dir| {
        // A hostile-input review: a 4096x4096 render took 47 s before the
        // reference was found to be 32x32, and `--image` decoded a 16000x16000
        // PNG of a few kilobytes (1.75 GB) before comparing the sizes. Now the
        // headers are compared first.
        dir.triangle_and_its_image();
        // `--timings` speaks after the render: refused before it, nothing.
        dir.cmd("scene-render")
        .args(["--size", "64x48", "--timings", "s.json", "--compare", "ref.png", "-o", "out.png"])
        .assert()
        .code(1)
        .stderr("scene-render: error: comparing with ref.png: image is 64x48 but the reference is 8x8\n");
        // A header of 16000x16000 and no pixels: decoded, it would be a
        // truncated picture; refused by its size, it is never decoded.
        let mut big = b"P6\n16000 16000\n255\n".to_vec();
        big.extend_from_slice(&[0; 12]);
        std::fs::write(dir.path().join("big.ppm"), big).unwrap();
        dir.cmd("scene-render")
            .args(["--image", "ref.png", "--compare", "big.ppm"])
            .assert()
            .code(1)
            .stderr(
                "scene-render: error: comparing with big.ppm: image is 8x8 but the reference is \
             16000x16000\n",
            );
        // A PFM's size comes from its text header too.
        dir.cmd("scene-render")
            .args([
                "--size", "8x8", "--format", "pfm", "s.json", "-o", "ref.pfm",
            ])
            .assert()
            .success();
        let mut cut = b"PF\n16000 16000\n-1.0\n".to_vec();
        cut.extend_from_slice(&[0; 12]);
        std::fs::write(dir.path().join("big.pfm"), cut).unwrap();
        for (args, said) in [
            (
                vec![
                    "--size",
                    "64x48",
                    "--timings",
                    "s.json",
                    "--compare",
                    "ref.pfm",
                ],
                "comparing with ref.pfm: image is 64x48 but the reference is 8x8",
            ),
            (
                vec!["--image", "ref.pfm", "--compare", "big.ppm"],
                "comparing with big.ppm: image is 8x8 but the reference is 16000x16000",
            ),
            (
                vec!["--image", "big.pfm", "--compare", "ref.png"],
                "comparing with ref.png: image is 16000x16000 but the reference is 8x8",
            ),
        ] {
            dir.cmd("scene-render")
                .args(&args)
                .assert()
                .code(1)
                .stderr(format!("scene-render: error: {said}\n"));
        }
        assert_eq!(
            dir.files(),
            ["big.pfm", "big.ppm", "ref.pfm", "ref.png", "s.json"]
        );
    }
);

clitest!(rayon_num_threads_is_bounded_as_threads_is, |dir| {
    // RAYON_NUM_THREADS=1000000 spent 17 s starting threads before an
    // error that named nothing (a hostile-input review).
    let marble = repo("fixtures/images/marble.png");
    let marble = marble.to_str().unwrap();
    let run = |threads: &[&str]| {
        let mut c = dir.cmd("pat-from-image");
        c.env("RAYON_NUM_THREADS", "1000000")
            .args(threads)
            .args(["--size", "16", marble, "-o", "p.pat"]);
        c
    };
    run(&[]).assert().code(2).stderr(
        "pat-from-image: error: RAYON_NUM_THREADS=1000000: at most 1024 worker threads \
         (--threads N overrides it)\n",
    );
    run(&["--threads", "2"]).assert().success();
    // What is not a number was passed over in silence (a hostile-input
    // review); 0 is rayon's "one per core", and empty is unset.
    // rayon does not trim (" 1 " is its default, not one thread), and
    // RAYON_RS_NUM_CPUS is its older name for the same thing.
    for (var, bad) in [
        ("RAYON_NUM_THREADS", "abc"),
        ("RAYON_NUM_THREADS", "-1"),
        ("RAYON_NUM_THREADS", "2.5"),
        ("RAYON_NUM_THREADS", " 1 "),
        ("RAYON_RS_NUM_CPUS", "x"),
    ] {
        let mut c = dir.cmd("pat-from-image");
        c.env(var, bad)
            .args(["--size", "16", marble, "-o", "p.pat"])
            .assert()
            .code(2)
            .stderr(format!(
                "pat-from-image: error: {var}={bad}: expected a number of worker \
                 threads, 0 for one per core (--threads N overrides it)\n"
            ));
    }
    let mut c = dir.cmd("pat-from-image");
    c.env("RAYON_RS_NUM_CPUS", "5000")
        .args(["--size", "16", marble, "-o", "p.pat"])
        .assert()
        .code(2)
        .stderr(
            "pat-from-image: error: RAYON_RS_NUM_CPUS=5000: at most 1024 worker threads \
             (--threads N overrides it)\n",
        );
    for fine in ["0", "", "2"] {
        let mut c = dir.cmd("pat-from-image");
        c.env("RAYON_NUM_THREADS", fine)
            .args(["--size", "16", marble, "-o", "p.pat"])
            .assert()
            .success();
    }
});

/// A file name holding a newline and a terminal escape, echoed in an
/// error: the message stays one line, the characters written as
/// escapes (`text::one_line`), so that a script reading one line a message
/// gets all of it and the terminal is not rewritten.
#[test]
fn a_name_with_control_characters_is_echoed_on_one_line() {
    let d = crate::util::Dir::new("control_names");
    let name = "no\nsuch\u{1b}[2J.json";
    for (tool, args) in [
        ("pat-from-image", vec![name, "-o", "out.pat"]),
        ("pat-info", vec![name]),
        ("pat-tile", vec![name, "--size", "8x8", "-o", "out.png"]),
        ("polyfill3", vec![name]),
        ("scene-render", vec![name, "-o", "out.png"]),
    ] {
        let out = d.cmd(tool).args(&args).output().unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(1), "{tool}: {err}");
        assert_eq!(err.lines().count(), 1, "{tool}: {err:?}");
        assert!(err.contains(r"no\nsuch\u{1b}[2J.json"), "{tool}: {err:?}");
        assert!(!err.contains('\u{1b}'), "{tool}: {err:?}");
    }
    // A flag's value refused by the argument parser: its message keeps
    // its own lines (usage, a tip), and the value is echoed escaped.
    for args in [
        &["--size", "1\n6", "in.png"][..],
        &["--size=1\n6", "in.png"][..],
    ] {
        let out = d.cmd("pat-from-image").args(args).output().unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(r"1\n6"), "{err:?}");
        assert!(!err.contains("1\n6"), "{err:?}");
    }
    // A name read from a record (a pattern file's, written with `\n` in
    // its JSON string) is echoed the same way.
    d.write(
        "s.json",
        br#"{"vertices":[[0,0,0],[4,0,0],[0,4,0]],"color":[1,2,3],"pattern":{"file":"a\nb.pat","incr":1}}"#,
    );
    let out = d
        .cmd("scene-render")
        .args(["s.json", "-o", "o.png"])
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err:?}");
    assert!(err.contains(r"a\nb.pat"), "{err:?}");
}
