//! The same frame on every host (issue 22, item 8): no value that reaches a
//! pixel may come from the platform's C maths library, whose last bits differ
//! between hosts and versions. `patkit::math` (libm, pure Rust) computes them;
//! this checks the binaries import none of the C library's functions.

/// The C library's transcendental functions, in double and single precision.
const C_MATHS: [&str; 21] = [
    "sin", "cos", "sincos", "tan", "asin", "acos", "atan", "atan2", "hypot", "pow", "exp", "exp2",
    "expm1", "log", "log2", "log10", "log1p", "cbrt", "sinh", "cosh", "tanh",
];

/// The symbols `binary` takes from shared libraries, as `nm -D` lists them.
fn imports(binary: &str) -> Vec<String> {
    let out = std::process::Command::new("nm")
        .args(["-D", "--undefined-only", binary])
        .output()
        .expect("nm (binutils) runs: it comes with the C toolchain cargo links with");
    assert!(out.status.success(), "nm {binary}: {:?}", out);
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().last())
        .map(|s| s.split('@').next().unwrap_or(s).to_string())
        .collect()
}

#[test]
fn binaries_import_no_maths_from_the_c_library() {
    let binaries = [
        env!("CARGO_BIN_EXE_pat-from-image"),
        env!("CARGO_BIN_EXE_pat-info"),
        env!("CARGO_BIN_EXE_pat-tile"),
        env!("CARGO_BIN_EXE_polyfill3"),
        env!("CARGO_BIN_EXE_scene-render"),
    ];
    for binary in binaries {
        let imported = imports(binary);
        // The check itself works: every binary takes something from libc.
        assert!(
            imported.iter().any(|s| s == "malloc" || s == "write"),
            "{binary}: {imported:?}"
        );
        let maths: Vec<&String> = imported
            .iter()
            .filter(|s| {
                let base = s.strip_suffix('f').unwrap_or(s);
                C_MATHS.contains(&s.as_str()) || C_MATHS.contains(&base)
            })
            .collect();
        assert!(
            maths.is_empty(),
            "{binary} imports {maths:?} from the C library"
        );
    }
}
