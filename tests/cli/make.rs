//! The examples' Makefile with `--depfile` (issue 22, item 3): the pattern
//! files a scene names reach make through the rules the tools write, not
//! through lists kept by hand.

use crate::util::repo;

/// `make -C examples` with the test's binaries and `out` as the output folder.
fn make(out: &std::path::Path, args: &[&str]) -> std::process::Output {
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_polyfill3"))
        .parent()
        .unwrap()
        .to_path_buf();
    std::process::Command::new("make")
        .arg("-C")
        .arg(repo("examples"))
        .arg(format!("BIN={}", bin.display()))
        .arg(format!("OUT={}", out.display()))
        .args(args)
        .output()
        .expect("GNU make runs")
}

clitest!(
    the_examples_makefile_learns_pattern_files_from_depfiles,
    |dir| {
        let out = dir.path().join("out");
        let target = out.join("demo2.ndjson");
        let target = target.to_str().unwrap();
        let built = make(&out, &[target]);
        assert!(built.status.success(), "{built:?}");
        let rule = std::fs::read_to_string(out.join("demo2.ndjson.d")).unwrap();
        assert!(rule.starts_with(&format!("{target}:")), "{rule}");
        for dep in [
            "scenes/demo2.json",
            "../fixtures/patterns/pyr.pat",
            "../fixtures/patterns/chex.pat",
        ] {
            assert!(rule.contains(&format!("\n{dep}:\n")), "{dep} in {rule}");
        }
        // Up to date, until a pattern changes: make knows it from the rule alone
        // (the Makefile lists no pattern for this target).
        assert!(make(&out, &["-q", target]).status.success());
        // Named as the Makefile (run in examples/) and the rule spell it.
        let what_if = "--what-if=../fixtures/patterns/pyr.pat";
        assert_eq!(make(&out, &["-q", what_if, target]).status.code(), Some(1));
        std::fs::remove_file(out.join("demo2.ndjson.d")).unwrap();
        assert!(
            make(&out, &["-q", what_if, target]).status.success(),
            "without the depfile make does not know the pattern"
        );
    }
);

clitest!(depfiles_name_every_file_read_and_every_frame, |dir| {
    // scene-render: the stream, its patterns, the camera and background
    // files; with --frames every frame is a target. Names with spaces are
    // escaped for make.
    dir.write("cam.json", r#"{"ortho2": [0, 8, 0, 8]}"#);
    std::fs::copy(
        repo("fixtures/patterns/brick.pat"),
        dir.path().join("my brick.pat"),
    )
    .unwrap();
    dir.write(
        "s.json",
        r#"{"vertices": [[0,0],[8,0],[0,8]], "pattern": {"file": "my brick.pat", "mode": "screen"}}"#,
    );
    dir.cmd("scene-render")
        .args(["--camera", "cam.json", "--size", "8x8", "--frames", "2"])
        .args(["--depfile", "f.d", "-o", "f-%d.png", "s.json"])
        .assert()
        .success();
    let rule = String::from_utf8(dir.read("f.d")).unwrap();
    assert!(rule.starts_with("f-0.png f-1.png: \\\n  s.json"), "{rule}");
    assert!(
        rule.contains("my\\ brick.pat") && rule.contains("cam.json"),
        "{rule}"
    );
    assert!(
        rule.contains("\ncam.json:\n"),
        "an empty rule per dependency: {rule}"
    );
    dir.cmd("scene-render")
        .args(["--depfile", "x.d", "s.json"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("--depfile needs -o FILE"));
    // One name for two outputs: the rule would have replaced the image.
    for (tool, args, said) in [
        (
            "scene-render",
            ["--depfile", "x.png", "-o", "x.png"],
            "--depfile x.png: the same file as -o",
        ),
        (
            "scene-render",
            ["--compare", "x.png", "--diff", "x.png"],
            "--diff x.png: the same file as -o",
        ),
        (
            "polyfill3",
            ["--depfile", "x.nd", "-o", "x.nd"],
            "--depfile x.nd: the same file as -o",
        ),
    ] {
        let mut cmd = dir.cmd(tool);
        if args[0] == "--compare" {
            cmd.args(["-o", "x.png"]);
        }
        cmd.args(args)
            .arg("s.json")
            .assert()
            .code(2)
            .stderr(predicates::str::contains(said));
    }
    assert!(!dir.path().join("x.png").exists() && !dir.path().join("x.nd").exists());
    // polyfill3: the input, the patterns and --pattern.
    dir.cmd("polyfill3")
        .args([
            "--pattern",
            "my brick.pat",
            "--depfile",
            "p.d",
            "-o",
            "p.ndjson",
            "s.json",
        ])
        .assert()
        .success();
    let rule = String::from_utf8(dir.read("p.d")).unwrap();
    assert!(
        rule.starts_with("p.ndjson: \\\n  s.json \\\n  my\\ brick.pat"),
        "{rule}"
    );
});

clitest!(a_file_spelled_two_ways_is_read_once, |dir| {
    // The readers kept what they read by the name as written, so one
    // pattern or stripe map named `b.pat`, `./b.pat`, `sub/../b.pat` or by
    // a link was read, and held, once per spelling: a photograph named two
    // ways took twice its memory. The depfile lists what was read.
    std::fs::copy(
        repo("fixtures/patterns/brick.pat"),
        dir.path().join("b.pat"),
    )
    .unwrap();
    dir.write("m.map", "STRIPE 8\n0 32 64 96 128 160 192 255\n");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::os::unix::fs::symlink("b.pat", dir.path().join("link.pat")).unwrap();
    std::os::unix::fs::symlink("m.map", dir.path().join("link.map")).unwrap();
    let square = r#""vertices": [[0,0],[4,0],[4,4],[0,4]]"#;
    let mut scene = String::new();
    for name in ["b.pat", "./b.pat", "sub/../b.pat", "link.pat"] {
        scene += &format!("{{{square}, \"pattern\": {{\"file\": \"{name}\"}}}}\n");
    }
    for name in ["m.map", "./m.map", "link.map"] {
        scene += &format!(
            "{{{square}, \"stripe\": {{\"map\": \"{name}\", \"spacing\": 0.5, \"yaw\": 0}}}}\n"
        );
    }
    dir.write("s.json", &scene);
    dir.cmd("scene-render")
        .args(["--size", "8x8", "--depfile", "s.d", "-o", "s.png", "s.json"])
        .assert()
        .success();
    let rule = String::from_utf8(dir.read("s.d")).unwrap();
    assert_eq!(rule.lines().next(), Some("s.png: \\"), "one target: {rule}");
    let deps: Vec<&str> = rule.lines().skip(1).map(str::trim).collect();
    assert_eq!(
        deps,
        [
            "s.json \\",
            "b.pat \\",
            "m.map",
            "",
            "s.json:",
            "",
            "b.pat:",
            "",
            "m.map:"
        ],
        "each file once, as first named: {rule}"
    );
    // polyfill3 partitions the pattern records (its input's stripes are
    // passed on as written, unread).
    let patterned: String = scene.lines().take(4).map(|l| format!("{l}\n")).collect();
    dir.write("p.json", &patterned);
    dir.cmd("polyfill3")
        .args(["--depfile", "p.d", "-o", "p.ndjson", "p.json"])
        .assert()
        .success();
    let rule = String::from_utf8(dir.read("p.d")).unwrap();
    assert!(
        rule.starts_with("p.ndjson: \\\n  p.json \\\n  b.pat\n"),
        "{rule}"
    );
});

clitest!(two_outputs_spelled_differently_are_still_one_file, |dir| {
    // A hostile-input review: output names were compared as text, so the
    // same file spelled another way (`./x.png`, `sub/../x.png`, a link to
    // it, a frame of the pattern) lost one of the two outputs with status 0.
    dir.triangle_and_its_image();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::os::unix::fs::symlink("x.png", dir.path().join("l.png")).unwrap();
    for (tool, args, said) in [
        (
            "scene-render",
            vec!["--depfile", "./x.png", "-o", "x.png"],
            "--depfile ./x.png: the same file as -o x.png",
        ),
        (
            "scene-render",
            vec!["--depfile", "l.png", "-o", "x.png"],
            "--depfile l.png: the same file as -o x.png",
        ),
        (
            "scene-render",
            vec![
                "--compare",
                "ref.png",
                "--diff",
                "sub/../x.png",
                "-o",
                "x.png",
            ],
            "--diff sub/../x.png: the same file as -o x.png",
        ),
        (
            "scene-render",
            vec!["--frames", "3", "-o", "g-%d.png", "--depfile", "./g-1.png"],
            "--depfile ./g-1.png: the same file as frame 1 of -o g-1.png",
        ),
        (
            "scene-render",
            vec!["--frames", "3", "-o", "g-%d.png", "--depfile", "g-2.png"],
            "--depfile g-2.png: the same file as frame 2 of -o: each output needs its own name",
        ),
        (
            "scene-render",
            vec!["-o", "-", "--compare", "ref.png", "--diff", "/dev/stdout"],
            "--diff /dev/stdout: the same file as -o -",
        ),
        (
            // The report goes to standard output when the image does not.
            "scene-render",
            vec!["-o", "x.png", "--compare", "ref.png", "--diff", "-"],
            "--diff -: the same file as the report",
        ),
        (
            "polyfill3",
            vec!["--depfile", "sub/../x.nd", "-o", "x.nd"],
            "--depfile sub/../x.nd: the same file as -o x.nd",
        ),
    ] {
        let mut cmd = dir.cmd(tool);
        if tool == "scene-render" {
            cmd.args(["--size", "8x8"]);
        }
        cmd.args(&args)
            .arg("s.json")
            .assert()
            .code(2)
            .stderr(predicates::str::contains(said));
    }
    assert_eq!(dir.files(), ["l.png", "ref.png", "s.json", "sub"]);
    // Names of one directory entry only: a hard link is another entry, and
    // each output is renamed onto its own.
    dir.cmd("scene-render")
        .args(["--size", "8x8", "s.json", "-o", "x.png", "--depfile", "x.d"])
        .assert()
        .success();
    std::fs::hard_link(dir.path().join("x.png"), dir.path().join("h.png")).unwrap();
    dir.cmd("scene-render")
        .args([
            "--size",
            "8x8",
            "s.json",
            "-o",
            "x.png",
            "--depfile",
            "h.png",
        ])
        .assert()
        .success();
    assert!(dir.read("x.png").starts_with(b"\x89PNG"));
    assert!(dir.read("h.png").starts_with(b"x.png:"));
});

clitest!(check_demos_fails_when_a_comparison_cannot_run, |dir| {
    // Issue 17, item 7: with no rendered demos (`-o demos`: do not make
    // them) every comparison fails; before pipefail, awk's status on empty
    // input hid that and `make check-demos` passed.
    let out = dir.path().join("none");
    std::fs::create_dir(&out).unwrap();
    let run = make(&out, &["-o", "demos", "check-demos"]);
    assert!(!run.status.success(), "{run:?}");
});

clitest!(
    make_install_puts_tools_man_pages_and_completions_under_a_prefix,
    |dir| {
        let bin = std::path::Path::new(env!("CARGO_BIN_EXE_polyfill3"))
            .parent()
            .unwrap()
            .to_path_buf();
        let prefix = dir.path().join("prefix");
        let run = |target: &str| {
            let out = std::process::Command::new("make")
                .arg("-C")
                .arg(repo("."))
                .arg(target)
                .arg(format!("BIN={}", bin.display()))
                .arg(format!("PREFIX={}", prefix.display()))
                .output()
                .expect("GNU make runs");
            assert!(
                out.status.success(),
                "make {target}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        };
        run("install");
        let tools = [
            "pat-from-image",
            "pat-info",
            "pat-tile",
            "polyfill3",
            "scene-render",
        ];
        for t in tools {
            let installed = prefix.join("bin").join(t);
            let v = std::process::Command::new(&installed)
                .arg("--version")
                .output()
                .unwrap();
            assert!(
                String::from_utf8_lossy(&v.stdout).starts_with(t),
                "{t} --version"
            );
            let man =
                std::fs::read_to_string(prefix.join(format!("share/man/man1/{t}.1"))).unwrap();
            assert!(man.starts_with(".ie") || man.contains(".TH"), "{t}.1");
            for (_, place) in patkit::cli::COMPLETION_SHELLS {
                assert!(
                    prefix.join(place.replace("{}", t)).is_file(),
                    "{place} for {t}"
                );
            }
            // bash loads the completion and completes the tool's flags.
            let script = prefix.join(format!("share/bash-completion/completions/{t}"));
            let complete = std::process::Command::new("bash")
                .arg("-c")
                .arg(format!(
                    "source '{}' && COMP_WORDS=({t} --he) COMP_CWORD=1 && \
                 $(complete -p {t} | sed -E 's/.*-F ([^ ]+).*/\\1/') {t} --he {t} && \
                 printf '%s\\n' \"${{COMPREPLY[@]}}\"",
                    script.display()
                ))
                .output()
                .unwrap();
            let words = String::from_utf8_lossy(&complete.stdout).to_string();
            assert!(
                words.lines().any(|w| w == "--help"),
                "{t}: bash completes --he to {words:?} ({})",
                String::from_utf8_lossy(&complete.stderr)
            );
        }
        // The file formats' section-5 pages, which every SEE ALSO names.
        for page in patkit::cli::FORMAT_PAGES {
            let man = std::fs::read_to_string(prefix.join(format!("share/man/man5/{page}.5")))
                .unwrap_or_else(|e| panic!("{page}.5: {e}"));
            assert!(
                man.starts_with(&format!(".TH {} 5", page.to_uppercase())),
                "{page}.5"
            );
        }
        run("uninstall");
        let left: Vec<_> = walk(&prefix).into_iter().filter(|p| p.is_file()).collect();
        assert!(left.is_empty(), "left after uninstall: {left:?}");
    }
);

fn walk(p: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut all = vec![p.to_path_buf()];
    if p.is_dir() {
        for e in std::fs::read_dir(p).unwrap() {
            all.extend(walk(&e.unwrap().path()));
        }
    }
    all
}

clitest!(
    demo2_makefile_pipeline_draws_the_full_partitions_picture,
    |dir| {
        // The Makefile gives polyfill3 the camera (--cull) and --merge=blocks:
        // fewer, larger polygons (0.38 MB against 4.5), and the picture of the
        // whole partition.
        let out = dir.path().join("out");
        let png = out.join("demo2.png");
        let built = make(&out, &[png.to_str().unwrap()]);
        assert!(built.status.success(), "{built:?}");
        dir.cmd("polyfill3")
            .arg(repo("examples/scenes/demo2.json"))
            .args(["-o", "full.ndjson"])
            .assert()
            .success();
        dir.cmd("scene-render")
            .args([
                "--perspective",
                "55,1,0,1000",
                "--lookat",
                "0,100,-5,0,0,-900",
            ])
            .args(["--cull", "back", "--background-pattern"])
            .arg(repo("fixtures/patterns/bkgrnd.pat"))
            .args(["-o", "full.png", "full.ndjson"])
            .assert()
            .success();
        assert!(
            std::fs::read(&png).unwrap() == dir.read("full.png"),
            "the Makefile's demo 2 differs from the whole partition's"
        );
        let size = |p: &std::path::Path| std::fs::metadata(p).unwrap().len();
        let (cut, full) = (
            size(&out.join("demo2.ndjson")),
            size(&dir.path().join("full.ndjson")),
        );
        assert!(10 * cut < full, "{cut} bytes against {full}");
    }
);

clitest!(every_target_of_the_examples_makefile_builds, |dir| {
    // What `make -C examples` and `make -C examples -j spin` (README) build,
    // with `turn` and `check-demos`: every target the Makefile names, in one
    // parallel run, each output non-empty and the demos within one code of
    // their golden images.
    let out = dir.path().join("out");
    let built = make(&out, &["-j2", "all", "spin", "turn", "check-demos"]);
    assert!(built.status.success(), "{built:?}");
    for file in [
        "marble.pat",
        "marble-info.txt",
        "marble-wall.png",
        "brick-wall.png",
        "demo1.png",
        "demo2.png",
        "demo2-fig51.png",
        "two-spheres.png",
        "earth-photo.png",
        "earth-lit.png",
        "house.png",
        "turn.png",
    ] {
        let len = std::fs::metadata(out.join(file)).map_or(0, |m| m.len());
        assert!(len > 0, "{file}: {len} bytes");
    }
    let frames = std::fs::read_dir(out.join("spin"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".png")
        })
        .count();
    assert_eq!(frames, 36, "spin's frames");
    // An animated PNG's acTL chunk: its frame count, big-endian.
    let turn = std::fs::read(out.join("turn.png")).unwrap();
    let at = turn
        .windows(4)
        .position(|w| w == b"acTL")
        .expect("an animated PNG");
    assert_eq!(turn[at + 4..at + 8], 36u32.to_be_bytes(), "turn's frames");
    let report = String::from_utf8_lossy(&built.stdout);
    for demo in ["demo1", "demo2", "two-spheres", "demo2-fig51"] {
        assert!(report.contains(&format!("{demo}: rmse ")), "{report}");
    }
});

clitest!(depfiles_name_hostile_file_names_as_make_reads_them, |dir| {
    // Names make reads specially: `:` stopped make ("multiple target
    // patterns"), `back\slash` was written `back\\slash` (a file that does
    // not exist), `pct%.pat:` was a pattern rule, and a `*` was a wildcard
    // (`a*b.pat` also named `axb.pat`). Each must be up to date after the
    // run and out of date once touched, as make itself reads the rule.
    let found = std::process::Command::new("sh")
        .args(["-c", "command -v make"])
        .output()
        .unwrap();
    if !crate::util::required("GNU make", found.status.success()) {
        return;
    }
    let deps = [
        "g:h.pat",
        "back\\slash.pat",
        "pct%.pat",
        "a b.pat",
        "c$d.pat",
        "e#f.pat",
        "x\\ y.pat",
        "x\\#y.pat",
        "a*b.pat",
        "q?[r].pat",
    ];
    let brick = std::fs::read(repo("fixtures/patterns/brick.pat")).unwrap();
    for d in deps {
        dir.write(d, &brick);
    }
    // Matches `a*b.pat` as a wildcard: not a dependency.
    dir.write("axb.pat", &brick);
    // Screen patterns for scene-render; polyfill3 reads only those in the
    // object's own coordinates.
    let stream = |names: &[&str], how: &str| {
        names
            .iter()
            .map(|n| {
                let file = serde_json::to_string(n).unwrap();
                format!(
                    "{{\"vertices\": [[0,0,0],[8,0,0],[0,8,0]], \"pattern\": {{\"file\": {file}, {how}}}}}\n"
                )
            })
            .collect::<String>()
    };
    dir.write("screen.json", stream(&deps, "\"mode\": \"screen\""));
    dir.write("object.json", stream(&deps, "\"incr\": 1"));
    let at = |secs: u64| std::time::UNIX_EPOCH + std::time::Duration::from_secs(secs);
    let set_time = |name: &str, secs: u64| {
        std::fs::File::options()
            .write(true)
            .open(dir.path().join(name))
            .unwrap()
            .set_modified(at(secs))
            .unwrap();
    };
    for (tool, target) in [("scene-render", "o:ut$.png"), ("polyfill3", "o%ut#.ndjson")] {
        let mut cmd = dir.cmd(tool);
        if tool == "scene-render" {
            cmd.args(["--size", "8x8", "--ortho2", "0,8,0,8"]);
        }
        let input = if tool == "polyfill3" {
            "object.json"
        } else {
            "screen.json"
        };
        cmd.args(["--depfile", "d.d", "-o", target, input])
            .assert()
            .success();
        // The rule the tool wrote, with a recipe for its target (make -q
        // calls a target with no recipe up to date).
        let rule = String::from_utf8(dir.read("d.d")).unwrap();
        let targets = rule.lines().next().unwrap().trim_end_matches(": \\");
        dir.write("M", format!("include d.d\n{targets}:\n\t@echo remake\n"));
        let up_to_date = || {
            let run = std::process::Command::new("make")
                .current_dir(dir.path())
                .args(["-q", "-f", "M", target])
                .output()
                .unwrap();
            match run.status.code() {
                Some(0) => true,
                Some(1) => false,
                _ => panic!("{tool}: make failed on the rule\n{rule}\n{run:?}"),
            }
        };
        for d in deps.iter().chain(&[input, "axb.pat"]) {
            set_time(d, 1_000_000_000);
        }
        set_time(target, 1_000_000_100);
        assert!(up_to_date(), "{tool}: {rule}");
        for d in deps.iter().chain(&[input]) {
            set_time(d, 1_000_000_200);
            assert!(!up_to_date(), "{tool}: {d} touched\n{rule}");
            set_time(d, 1_000_000_000);
        }
        set_time("axb.pat", 1_000_000_200);
        assert!(up_to_date(), "{tool}: axb.pat is no dependency\n{rule}");
        // A deleted dependency: its empty rule makes the target out of date.
        std::fs::rename(dir.path().join("pct%.pat"), dir.path().join("keep")).unwrap();
        assert!(!up_to_date(), "{tool}: pct%.pat deleted\n{rule}");
        std::fs::rename(dir.path().join("keep"), dir.path().join("pct%.pat")).unwrap();
    }
    // Names no make rule can spell: refused by name, and neither the rule
    // nor the output is written.
    dir.write("n\nl.pat", &brick);
    dir.write("bad.json", stream(&["n\nl.pat"], "\"incr\": 1"));
    for (names, said) in [
        (
            ["bad.json", "new.png"],
            "make cannot name the file \"n\\nl.pat\": a newline",
        ),
        (
            ["object.json", "o;x.png"],
            "make cannot name the file \"o;x.png\": make reads what follows ';'",
        ),
    ] {
        for tool in ["scene-render", "polyfill3"] {
            let mut cmd = dir.cmd(tool);
            if tool == "scene-render" {
                cmd.args(["--size", "8x8", "--ortho2", "0,8,0,8"]);
            }
            cmd.args(["--depfile", "new.d", "-o", names[1], names[0]])
                .assert()
                .code(1)
                .stderr(predicates::str::contains(said));
            assert!(!dir.path().join("new.d").exists(), "{tool}");
            assert!(!dir.path().join(names[1]).exists(), "{tool}");
        }
    }
});
