//! The polygon stream: non-finite numbers, huge numbers, deep nesting and
//! truncation are errors that name the record, never panics.

use patkit::stream::{for_each_record, StreamError};
use proptest::prelude::*;

fn read(text: &str) -> Result<usize, String> {
    let mut n = 0;
    for_each_record(text.as_bytes(), "s.json", |_| {
        n += 1;
        Ok::<(), StreamError>(())
    })
    .map(|()| n)
    .map_err(|e| e.to_string())
}

const GOOD: &str = r#"[{"vertices":[[0,0,0],[1e9,0,-1e-6],[0,1e-6,3]],"color":[1,2,3]},
{"rect":[0,0,1,1],"color":[0,0,0],"pattern":{"file":"p.pat","incr":1e-6}},
{"circle":{"center":[5,5],"radius":1e6},"color":[4,5,6]}]"#;

#[test]
fn nan_and_infinity_literals_are_errors_naming_the_record() {
    for lit in [
        "NaN",
        "Infinity",
        "-Infinity",
        "inf",
        "nan",
        "1e400",
        "-1e999",
    ] {
        let text = format!(
            "{{\"rect\":[0,0,1,1],\"color\":[0,0,0]}}\n{{\"vertices\":[[0,0],[1,0],[0,{lit}]],\"color\":[0,0,0]}}"
        );
        let e = read(&text).unwrap_err();
        assert!(e.contains("s.json: record 1"), "{lit}: {e}");
    }
}

#[test]
fn huge_finite_numbers_are_read_or_refused_naming_the_field() {
    // 1e308 is finite: the record is read; what a tool does with it is its
    // own check (tests/cli/stress.rs).
    assert_eq!(
        read(r#"{"vertices":[[0,0],[1e308,0],[0,-1e308]],"color":[0,0,0]}"#),
        Ok(1)
    );
    let e = read(r#"{"vertices":[[0,0],[1,0],[0,1]],"color":[1e300,0,0]}"#).unwrap_err();
    assert!(e.contains("record 0: color"), "{e}");
}

#[test]
fn nesting_100000_deep_in_a_known_field_is_an_error_naming_the_record() {
    for form in ["ndjson", "array"] {
        let rec = format!(
            "{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"pattern\":{}0{}}}",
            "[".repeat(100_000),
            "]".repeat(100_000)
        );
        let text = match form {
            "array" => format!("[{{\"rect\":[0,0,1,1],\"color\":[0,0,0]}},\n{rec}]"),
            _ => format!("{{\"rect\":[0,0,1,1],\"color\":[0,0,0]}}\n{rec}"),
        };
        let e = read(&text).unwrap_err();
        assert!(e.contains("record 1: invalid JSON"), "{form}: {e}");
    }
}

#[test]
fn nesting_100000_deep_in_an_unknown_field_is_kept_as_text() {
    // An unknown field is kept as written and never parsed into a tree, so
    // its depth costs no stack (docs/polyfill3.md, "Unknown fields").
    let deep = format!(
        "{{\"rect\":[0,0,1,1],\"color\":[0,0,0]}}\n{{\"rect\":[0,0,1,1],\"color\":[0,0,0],\"x\":{}0{}}}",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    assert_eq!(read(&deep), Ok(2));
}

proptest! {
    #![proptest_config(crate::config())]

    #[test]
    fn truncated_stream_is_read_whole_or_an_error_naming_a_record(cut in 0usize..GOOD.len()) {
        match read(&GOOD[..cut]) {
            Ok(n) => prop_assert!(n <= 3),
            Err(e) => prop_assert!(e.starts_with("s.json: record ") || e.starts_with("s.json:"), "{e}"),
        }
    }

    #[test]
    fn garbage_bytes_spliced_into_a_stream_never_panic(
        at in 0usize..GOOD.len(), junk in "[\\[\\]{}\",:0-9eE.+\\-a-zN]{0,12}",
    ) {
        let text = format!("{}{}{}", &GOOD[..at], junk, &GOOD[at..]);
        if let Err(e) = read(&text) {
            prop_assert!(e.starts_with("s.json"), "{e}");
        }
    }
}
