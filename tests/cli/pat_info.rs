//! `pat-info`: reports, JSON, --check, --at, several files, bad input.

use crate::util::{checker16, repo};
use predicates::prelude::*;

clitest!(text_report_counts_colours_and_transparency, |dir| {
    dir.write("c.pat", checker16());
    let out = dir.cmd("pat-info").arg("c.pat").assert().success();
    let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    assert!(
        text.starts_with("c.pat: 16x16, 2 colours, 0.39% transparent\n"),
        "{text}"
    );
    assert!(text.contains("255,0,0      #ff0000      127"), "{text}");
    assert!(text.contains("0,0,255      #0000ff      128"), "{text}");
    assert!(text.contains("left/right seamless"), "{text}");
});

clitest!(json_report_is_one_versioned_object_for_scripts, |dir| {
    dir.write("c.pat", checker16());
    let out = dir
        .cmd("pat-info")
        .args(["--json", "--at", "1,0", "c.pat", "-"])
        .write_stdin(checker16())
        .assert()
        .success();
    let doc: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(
        (&doc["version"], &doc["tool"]),
        (&1.into(), &"pat-info".into())
    );
    let v = &doc["files"];
    assert_eq!(v.as_array().unwrap().len(), 2);
    assert_eq!(v[0]["kind"], "pattern");
    assert_eq!(v[0]["size"], 16);
    assert_eq!(v[0]["transparent"]["texels"], 1);
    assert_eq!(v[0]["colors"][1]["hex"], "#0000ff");
    assert_eq!(v[0]["texel"]["index"], 2);
    assert_eq!(v[1]["file"], "<stdin>");
    assert_eq!(v[0]["tiling"]["left_right"]["seamless"], true);
});

clitest!(at_reports_a_transparent_texel_and_refuses_outside, |dir| {
    dir.write("c.pat", checker16());
    dir.cmd("pat-info")
        .args(["--at", "0,0", "c.pat"])
        .assert()
        .success()
        .stdout(predicate::str::contains("texel (0,0): transparent"));
    dir.cmd("pat-info")
        .args(["--at", "0,16", "c.pat"])
        .assert()
        .code(1)
        .stdout("")
        .stderr(predicate::str::contains(
            "texel (0,16) is outside the 16x16 pattern",
        ));
    // With several files, the error names the one the texel is outside of
    // (a hostile-input review found it named none).
    let big = patkit::Pattern::parse(checker16().as_bytes(), "c.pat")
        .unwrap()
        .tiled(32, 1, (0, 0))
        .unwrap();
    dir.write("big.pat", big.to_canonical());
    dir.cmd("pat-info")
        .args(["--at", "20,0", "big.pat", "c.pat"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("texel (20,0)"))
        .stderr(
            "pat-info: error: c.pat: texel (20,0) is outside the 16x16 pattern: columns and \
             rows run 0..15\n",
        );
});

clitest!(check_is_silent_on_success_and_names_each_bad_file, |dir| {
    dir.write("good.pat", checker16());
    dir.write("bad.pat", "16 1\n1 2 300\n");
    dir.write("empty.pat", "");
    dir.cmd("pat-info")
        .args(["--check", "good.pat"])
        .assert()
        .success()
        .stdout("")
        .stderr("");
    let out = dir
        .cmd("pat-info")
        .args([
            "--check",
            "bad.pat",
            "good.pat",
            "empty.pat",
            "missing.pat",
            ".",
        ])
        .assert()
        .code(1)
        .stdout("");
    let err = String::from_utf8(out.get_output().stderr.clone()).unwrap();
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 4, "{err}");
    assert!(
        lines[0].starts_with("pat-info: error: bad.pat:2: word 5 `300`: out of range"),
        "{err}"
    );
    assert!(
        lines[1].starts_with("pat-info: error: empty.pat: empty file"),
        "{err}"
    );
    assert!(
        lines[2].starts_with("pat-info: error: missing.pat: No such file"),
        "{err}"
    );
    assert!(lines[3].contains("is a directory"), "{err}");
});

clitest!(reports_the_good_files_even_when_one_is_bad, |dir| {
    dir.write("good.pat", checker16());
    dir.write("bad.pat", "\x00\x01binary");
    dir.cmd("pat-info")
        .args(["bad.pat", "good.pat"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("good.pat: 16x16"))
        .stderr(predicate::str::contains(
            "bad.pat: byte 0x00 on line 1 (offset 0) is not text",
        ));
});

clitest!(usage_errors_exit_2_with_empty_stdout, |dir| {
    dir.cmd("pat-info")
        .arg("--bogus")
        .assert()
        .code(2)
        .stdout("");
    dir.cmd("pat-info")
        .args(["--at", "x,1", "a.pat"])
        .assert()
        .code(2)
        .stdout("");
    dir.cmd("pat-info")
        .args(["--check", "--json", "a.pat"])
        .assert()
        .code(2)
        .stdout("");
});

clitest!(preview_draws_24_bit_half_blocks, |dir| {
    dir.write("c.pat", checker16());
    let out = dir
        .cmd("pat-info")
        .args(["--preview", "--color", "always", "c.pat"])
        .assert()
        .success();
    let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    assert_eq!(text.matches('▀').count(), 16 * 8);
    assert!(text.contains("\x1b[38;2;255;0;0m"));
});

#[test]
fn every_fixture_pattern_is_valid_with_the_sizes_the_thesis_uses() {
    let expect = [
        ("brick", 64),
        ("wood", 64),
        ("weave", 32),
        ("mod", 32),
        ("bkgrnd", 64),
        ("pyr", 64),
        ("chex", 16),
    ];
    for (name, size) in expect {
        let path = repo(&format!("fixtures/patterns/{name}.pat"));
        let p = patkit::Pattern::read_file(&path).unwrap();
        assert_eq!(p.size(), size, "{name}");
        assert!(p.palette().len() >= 2, "{name} has several colours");
        // Canonical on disk: our writer reproduces the file byte for byte.
        assert_eq!(
            p.to_canonical(),
            std::fs::read_to_string(&path).unwrap(),
            "{name}"
        );
    }
    for name in ["weave", "mod", "bkgrnd"] {
        let p =
            patkit::Pattern::read_file(&repo(&format!("fixtures/patterns/{name}.pat"))).unwrap();
        assert!(p.histogram().1 > 0, "{name} has transparent texels");
    }
}

clitest!(a_number_past_u64_is_echoed_as_written, |dir| {
    // A hostile-input review found a 23-digit pattern size reported as
    // `pattern size 18446744073709551615` and a map length as `map length
    // 18446744073709551615`: the reader saturated, and the check after it
    // showed a number nobody wrote. The word is echoed now, even as a
    // file's first word (digits are nobody's secret).
    let big = "9".repeat(23);
    dir.write("big.pat", format!("{big} 1\n"));
    dir.write("big.map", format!("STRIPE {big}\n"));
    for (file, what) in [
        (
            "big.pat",
            "word 1 `99999999999999999999999`: out of range: expected the pattern size, \
             a multiple of 16 from 16 to 4096",
        ),
        (
            "big.map",
            "word 2 `99999999999999999999999`: out of range: expected the map length, \
             a power of two from 1 to 65536",
        ),
    ] {
        dir.cmd("pat-info")
            .arg(file)
            .assert()
            .code(1)
            .stdout("")
            .stderr(format!("pat-info: error: {file}:1: {what}\n"));
    }
    // u64::MAX itself is what was written: the size check shows it.
    dir.write("max.pat", "18446744073709551615 1\n");
    dir.cmd("pat-info")
        .arg("max.pat")
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "pattern size 18446744073709551615 is not a multiple of 16",
        ));
});

// Lines ended by a bare CR (classic Mac OS) are counted as lines, also in
// blank lines read past before the format is known (more than the first
// read) and where a CR LF is split between two reads; in a map a `#`
// comment ends at a CR. Errors said line 1, and the map's comment hid its
// values (a hostile-input review).
clitest!(a_bare_cr_ends_a_line_in_every_text_format, |dir| {
    let mut pat = "16 1\r1 2 3\r".to_string();
    pat.push_str(&"ffff\r".repeat(14));
    pat.push_str("zz\r");
    dir.write("cr.pat", &pat);
    dir.cmd("pat-info")
        .args(["--check", "cr.pat"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("cr.pat:17: word 20 `zz`"));
    // The first read is 4096 bytes: after " ", the 2048th CR LF is split.
    for blank in [
        "\r".repeat(5000),
        format!(" {}", "\r\n".repeat(5000)),
        "\n".repeat(5000),
    ] {
        dir.write("late.pat", format!("{blank}{pat}"));
        dir.cmd("pat-info")
            .args(["--check", "late.pat"])
            .assert()
            .code(1)
            .stderr(predicate::str::contains("late.pat:5017: word 20 `zz`"));
    }
    dir.write("cr.map", "STRIPE 4\r# fade: default\r10 20 30 40\r");
    dir.cmd("pat-info")
        .arg("cr.map")
        .assert()
        .success()
        .stdout(predicate::str::contains("modulation map, 4 entries"));
});
