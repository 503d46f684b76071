//! The dependency rule, kept by a test: modules form layers in the order the
//! data flows, and a module may use only modules of lower layers.
//!
//! The test reads every source file of the crate, drops comments and string
//! literals, and collects the crate modules each file names: `use crate::…`
//! lines (grouped `crate::{a, b::c}` included), inline `crate::x::…` paths, and
//! `super::` chains that climb to the crate root. It fails on an upward or
//! sideways import, and on a `crate::Name` that is not a module (a crate-root
//! re-export would hide the real dependency). It also checks that `benches/`
//! and `examples/` use no `patkit::cli`, and that the binaries use only it.
//! `docs/architecture.md` explains the layers.

/// The layers, lowest first. A module may import modules of lower layers only;
/// modules of one layer are independent of each other.
pub const LAYERS: &[&[&str]] = &[
    &["math", "progress", "vector"],
    &["color", "error", "text"],
    &["io"],
    &["pat"],
    &["quantize", "geom", "light"],
    &["stream"],
    &["camera"],
    &["view"],
    &["texture", "stripe"],
    &["raster"],
    &["scene"],
    &["cli"],
];

/// The layer of a top-level module, `None` for a name that is not one.
pub fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// Source text with comments, string and character literals blanked (each
/// replaced by spaces, newlines kept), so that only code is searched.
pub fn code_only(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    let blank = |out: &mut Vec<u8>, bytes: &[u8]| {
        out.extend(bytes.iter().map(|&c| if c == b'\n' { b'\n' } else { b' ' }))
    };
    while i < b.len() {
        let rest = &b[i..];
        if rest.starts_with(b"//") {
            let end = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
            blank(&mut out, &rest[..end]);
            i += end;
        } else if rest.starts_with(b"/*") {
            // Block comments nest in Rust.
            let (mut depth, mut k) = (0usize, 0);
            while k < rest.len() {
                if rest[k..].starts_with(b"/*") {
                    depth += 1;
                    k += 2;
                } else if rest[k..].starts_with(b"*/") {
                    depth -= 1;
                    k += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    k += 1;
                }
            }
            blank(&mut out, &rest[..k]);
            i += k;
        } else if let Some(len) = raw_string_len(rest) {
            blank(&mut out, &rest[..len]);
            i += len;
        } else if rest[0] == b'"' {
            let mut k = 1;
            while k < rest.len() && rest[k] != b'"' {
                k += if rest[k] == b'\\' { 2 } else { 1 };
            }
            let len = (k + 1).min(rest.len());
            blank(&mut out, &rest[..len]);
            i += len;
        } else if rest[0] == b'\'' {
            // A character literal ('x', '\n', '\''); otherwise a lifetime.
            let len = if rest.len() > 2 && rest[1] == b'\\' {
                rest[2..].iter().position(|&c| c == b'\'').map(|p| p + 3)
            } else if rest.len() > 2 {
                let ch = std::str::from_utf8(&rest[1..rest.len().min(6)])
                    .ok()
                    .or_else(|| std::str::from_utf8(&rest[1..rest.len().min(5)]).ok())
                    .or_else(|| std::str::from_utf8(&rest[1..rest.len().min(4)]).ok())
                    .or_else(|| std::str::from_utf8(&rest[1..rest.len().min(3)]).ok())
                    .and_then(|s| s.chars().next());
                ch.and_then(|c| {
                    let n = 1 + c.len_utf8();
                    (rest.get(n) == Some(&b'\'')).then_some(n + 1)
                })
            } else {
                None
            };
            match len {
                Some(len) => {
                    blank(&mut out, &rest[..len]);
                    i += len;
                }
                None => {
                    out.push(b'\'');
                    i += 1;
                }
            }
        } else {
            out.push(rest[0]);
            i += 1;
        }
    }
    String::from_utf8(out).expect("only ASCII bytes were replaced")
}

/// The length of a raw string literal (`r"…"`, `r#"…"#`, `br"…"`) at the
/// start of `s`, if one starts there.
fn raw_string_len(s: &[u8]) -> Option<usize> {
    let start = if s.starts_with(b"br") {
        2
    } else if s.starts_with(b"r") {
        1
    } else {
        return None;
    };
    let hashes = s[start..].iter().take_while(|&&c| c == b'#').count();
    if s.get(start + hashes) != Some(&b'"') {
        return None;
    }
    let mut close = vec![b'"'];
    close.extend(std::iter::repeat_n(b'#', hashes));
    let body = start + hashes + 1;
    let end = s[body..].windows(close.len()).position(|w| w == close)?;
    Some(body + end + close.len())
}

/// One reference from a file to a crate module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reference {
    /// 1-based line of the reference.
    pub line: usize,
    /// The first path segment after the crate root.
    pub target: String,
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The crate-root names a file refers to. `module_path` is the file's module
/// path below the crate root (`["raster", "coverage"]` for
/// `src/raster/coverage.rs`, `["raster"]` for `src/raster/mod.rs`), so that
/// `super::` chains that leave the crate's top-level module are followed.
pub fn references(code: &str, module_path: &[&str]) -> Vec<Reference> {
    let b = code.as_bytes();
    let mut refs = Vec::new();
    // Inline `mod name {` blocks: the brace depths at which they opened.
    let mut inline_mods: Vec<usize> = Vec::new();
    let mut depth = 0usize;
    let line_at = |i: usize| code[..i].bytes().filter(|&c| c == b'\n').count() + 1;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'{' {
            depth += 1;
            i += 1;
            continue;
        }
        if c == b'}' {
            depth = depth.saturating_sub(1);
            if inline_mods.last() == Some(&depth) {
                inline_mods.pop();
            }
            i += 1;
            continue;
        }
        let word_start = i == 0 || !is_ident(b[i - 1]);
        if !word_start || !is_ident(c) {
            i += 1;
            continue;
        }
        let end = i + b[i..].iter().take_while(|&&c| is_ident(c)).count();
        let word = &code[i..end];
        if word == "mod" {
            // `mod name {` opens an inline module; `mod name;` does not.
            let after = code[end..].trim_start();
            let name_len = after.bytes().take_while(|&c| is_ident(c)).count();
            if after[name_len..].trim_start().starts_with('{') {
                inline_mods.push(depth);
            }
            i = end;
            continue;
        }
        let root_after = if word == "crate" {
            Some(end)
        } else if word == "super" {
            // Count the chain; it reaches the root after one more `super`
            // than the file's and inline modules' depth below the root.
            let mut k = i;
            let mut supers = 0;
            while code[k..].starts_with("super::") {
                supers += 1;
                k += "super::".len();
            }
            let levels = module_path.len() + inline_mods.len();
            if supers > 0 && supers >= levels && levels > 0 {
                Some(k - 2)
            } else {
                i = k.max(end);
                continue;
            }
        } else {
            None
        };
        let Some(after) = root_after else {
            i = end;
            continue;
        };
        let rest = &code[after..];
        if let Some(tail) = rest.strip_prefix("::") {
            let line = line_at(i);
            let tail_t = tail.trim_start();
            if let Some(group) = tail_t.strip_prefix('{') {
                // `crate::{a, b::c, d::{e, f}}`: the first segment of each
                // item at the group's own level.
                let mut level = 0;
                let mut item_start = true;
                let gb = group.as_bytes();
                let mut k = 0;
                while k < gb.len() {
                    match gb[k] {
                        b'{' => level += 1,
                        b'}' if level == 0 => break,
                        b'}' => level -= 1,
                        b',' if level == 0 => item_start = true,
                        ch if item_start && level == 0 && is_ident(ch) => {
                            let n = gb[k..].iter().take_while(|&&c| is_ident(c)).count();
                            refs.push(Reference {
                                line,
                                target: group[k..k + n].to_string(),
                            });
                            item_start = false;
                            k += n;
                            continue;
                        }
                        _ => {}
                    }
                    k += 1;
                }
            } else {
                let n = tail_t.bytes().take_while(|&c| is_ident(c)).count();
                if n > 0 {
                    refs.push(Reference {
                        line,
                        target: tail_t[..n].to_string(),
                    });
                }
            }
        }
        i = end;
    }
    refs
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::{Path, PathBuf};

    fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                rust_files(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }

    /// The module path of a file below `src/`.
    fn module_path(rel: &Path) -> Vec<String> {
        let mut parts: Vec<String> = rel
            .iter()
            .map(|s| s.to_string_lossy().into_owned())
            .collect();
        let last = parts.pop().expect("a file name");
        let stem = last.trim_end_matches(".rs");
        if stem != "mod" && stem != "lib" {
            parts.push(stem.to_string());
        }
        parts
    }

    /// Every violation of the rule in the crate's sources.
    fn violations(root: &Path) -> Vec<String> {
        let src = root.join("src");
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let mut bad = Vec::new();
        for file in &files {
            let rel = file.strip_prefix(&src).expect("below src");
            let shown = format!("src/{}", rel.display());
            if rel.starts_with("bin") {
                continue;
            }
            let path = module_path(rel);
            let Some(own) = path.first() else {
                continue; // lib.rs: the table of contents.
            };
            let Some(own_layer) = layer_of(own) else {
                if own != "layering" && own != "test_util" {
                    bad.push(format!("{shown}: module `{own}` is in no layer"));
                }
                continue;
            };
            let text = std::fs::read_to_string(file).expect("readable source");
            let path_refs: Vec<&str> = path.iter().map(String::as_str).collect();
            for r in references(&code_only(&text), &path_refs) {
                if r.target == *own || r.target == "test_util" {
                    continue;
                }
                match layer_of(&r.target) {
                    Some(l) if l < own_layer => {}
                    Some(l) => bad.push(format!(
                        "{shown}:{}: `{own}` (layer {own_layer}) uses `{}` (layer {l}): \
                         a module may use only lower layers",
                        r.line, r.target
                    )),
                    None => bad.push(format!(
                        "{shown}:{}: `crate::{}` is not a module: name the module it lives in",
                        r.line, r.target
                    )),
                }
            }
        }
        bad
    }

    /// Files of `dir` that name `patkit::cli`.
    fn cli_users(dir: &Path) -> Vec<String> {
        let mut files = Vec::new();
        rust_files(dir, &mut files);
        files
            .into_iter()
            .filter(|f| {
                let text = std::fs::read_to_string(f).expect("readable source");
                code_only(&text).contains("patkit::cli")
            })
            .map(|f| f.display().to_string())
            .collect()
    }

    #[test]
    fn every_module_uses_only_lower_layers() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let bad = violations(root);
        assert!(bad.is_empty(), "{}", bad.join("\n"));
    }

    /// The library's errors are typed (issue 21): `anyhow`, a front end's way
    /// of gathering any error, belongs to the command line. (`cargo check
    /// --lib --no-default-features` in `.ci/run` proves it for the non-test
    /// code, where anyhow is not even a dependency; this covers the tests too.)
    #[test]
    fn untyped_errors_stay_in_the_command_line() {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let users: Vec<String> = files
            .iter()
            .filter(|f| {
                let rel = f.strip_prefix(&src).expect("below src");
                !rel.starts_with("cli") && !rel.starts_with("bin")
            })
            .filter(|f| {
                let text = std::fs::read_to_string(f).expect("readable source");
                code_only(&text).contains("anyhow")
            })
            .map(|f| f.display().to_string())
            .collect();
        assert!(users.is_empty(), "anyhow outside src/cli: {users:?}");
    }

    #[test]
    fn benches_and_examples_use_the_library_not_the_command_line() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut bad = cli_users(&root.join("benches"));
        bad.extend(cli_users(&root.join("examples")));
        assert!(bad.is_empty(), "{bad:?}");
    }

    #[test]
    fn the_rule_catches_upward_and_grouped_imports() {
        let code = code_only(
            "use crate::color::Rgb8;\n\
             use crate::{raster::render, pat};\n\
             fn f() { let s = \"crate::cli\"; crate::scene::load(); }\n\
             // crate::cli in a comment\n",
        );
        let targets: Vec<String> = references(&code, &["geom"])
            .into_iter()
            .map(|r| r.target)
            .collect();
        assert_eq!(targets, ["color", "raster", "pat", "scene"]);
    }

    #[test]
    fn super_chains_that_leave_the_top_module_count() {
        // In src/raster/coverage.rs, `super::super::x` is the crate root's x;
        // inside its `mod tests { }`, one more `super` is needed.
        let code = code_only(
            "use super::gather::Local;\nuse super::super::cli::X;\n\
             pub(super) fn f() {}\n\
             mod tests { use super::super::Frame; use super::super::super::scene; }\n",
        );
        let targets: Vec<String> = references(&code, &["raster", "coverage"])
            .into_iter()
            .map(|r| r.target)
            .collect();
        assert_eq!(targets, ["cli", "scene"]);
    }

    #[test]
    fn literals_and_lifetimes_are_not_code() {
        let code = code_only(
            "fn f<'a>(x: &'a str) -> char { let _ = r#\"crate::cli\"#; let _ = b\"crate::x\"; '\"' }",
        );
        assert!(!code.contains("crate::"), "{code}");
        assert!(code.contains("fn f<'a>(x: &'a str)"), "{code}");
    }
}
