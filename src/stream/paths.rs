//! Where the files a record names are found (docs/stream-format.md): relative to the
//! stream's own file, so that a scene and its patterns move together. Apart
//! from the reader because the tools resolve paths long after reading.
//!
//! A tool that forwards records (`polyfill3`) writes a stream that is read
//! from another directory than its input, so it rewrites every file a record
//! names ([`forward_file_refs`]): as an absolute path when the reader's
//! directory is unknown (standard output), else relative to the output file's
//! directory, so that the output and its files still move together.

use super::fields::Fields;
use serde_json::Value;
use std::path::{Component, Path, PathBuf};

/// Where relative pattern paths resolve (docs/stream-format.md): the stream file's directory,
/// or the current directory for standard input.
pub fn base_dir(input_name: &str) -> PathBuf {
    if input_name == crate::io::STDIO {
        PathBuf::from(".")
    } else {
        Path::new(input_name)
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
    }
}

/// Resolves a pattern path against a stream's base directory.
pub fn resolve(base: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

/// The file each spelling of a path names, so that a file read for a
/// stream is read once however its records spell it (`a.pat`, `./a.pat`,
/// `sub/../a.pat`, a symbolic link to it): keyed by spelling, a scene that
/// named one 4096² photograph two ways decoded and held it twice.
///
/// The file is the path with its links followed and `.`/`..` resolved
/// ([`std::fs::canonicalize`]), found once per spelling, not once per
/// record (a stream may have millions naming one pattern). A path that
/// cannot be resolved (a missing file) stands for itself, and its reader
/// then reports it. Hard links stay two files, as they have two names.
#[derive(Debug, Default)]
pub struct FileIds {
    by_spelling: std::collections::HashMap<PathBuf, PathBuf>,
}

impl FileIds {
    /// The file `path` names.
    pub fn file(&mut self, path: &Path) -> &Path {
        if !self.by_spelling.contains_key(path) {
            let file = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
            self.by_spelling.insert(path.to_path_buf(), file);
        }
        &self.by_spelling[path]
    }
}

/// Where the file references of forwarded records point.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RefTarget {
    /// Absolute, normalised paths: for standard output, whose reader's
    /// directory is unknown.
    Absolute,
    /// Paths relative to this directory (absolute and normalised: see
    /// [`RefTarget::relative_to_output`]), where the output file is written.
    RelativeTo(PathBuf),
}

impl RefTarget {
    /// The target for an output named `output` (`-`: standard output).
    /// A device or pipe named as the output (`-o /dev/stdout`) counts as
    /// standard output: its reader's directory is unknown.
    pub fn for_output(output: &str) -> std::io::Result<RefTarget> {
        let device = std::fs::metadata(output).is_ok_and(|m| !m.file_type().is_file());
        if output == crate::io::STDIO || device {
            Ok(RefTarget::Absolute)
        } else {
            RefTarget::relative_to_output(Path::new(output))
        }
    }

    /// Relative to the directory `output` is written in.
    pub fn relative_to_output(output: &Path) -> std::io::Result<RefTarget> {
        let dir = match output.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Ok(RefTarget::RelativeTo(normalised(dir)?))
    }

    /// `file` (a path as the reader found it: resolved against the input's
    /// directory, or the current directory's) as this target writes it.
    pub fn path(&self, file: &Path) -> std::io::Result<String> {
        let file = normalised(file)?;
        let written = match self {
            RefTarget::Absolute => file,
            RefTarget::RelativeTo(dir) => relative(&file, dir),
        };
        Ok(written.to_string_lossy().into_owned())
    }
}

/// `path` made absolute: the real path when it exists (links resolved), else
/// with `.` and `..` removed by the letter (a missing file is reported by the
/// tool that opens it, which sees the same name).
fn normalised(path: &Path) -> std::io::Result<PathBuf> {
    if let Ok(real) = std::fs::canonicalize(path) {
        return Ok(real);
    }
    let mut out = PathBuf::new();
    for c in std::path::absolute(path)?.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    Ok(out)
}

/// `file` relative to `dir`, both absolute and normalised: `..` for each
/// component of `dir` past their common start.
fn relative(file: &Path, dir: &Path) -> PathBuf {
    let (f, d): (Vec<Component>, Vec<Component>) =
        (file.components().collect(), dir.components().collect());
    let common = f.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..d.len() {
        out.push("..");
    }
    for c in &f[common..] {
        out.push(c);
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

/// The file names of a record, as `(object, key)` pairs: a pattern's file,
/// a stripe texture's map, colour table and translation file (a translation
/// given as a string other than `"identity"`, docs/stripe.md).
const FILE_REFS: [(&str, &str); 5] = [
    ("pattern", "file"),
    ("stripe", "map"),
    ("stripe", "colors"),
    // The old spelling, still read (crate::stripe::record::OLD_KEYS).
    ("stripe", "colours"),
    ("stripe", "translation"),
];

/// Whether a record names a file (a pattern's file; a stripe's map, colour
/// table or translation file): a cheap test before [`forward_file_refs`]
/// copies the record.
pub fn names_files(fields: &Fields) -> bool {
    FILE_REFS
        .iter()
        .any(|(object, key)| fields.get(object).is_some_and(|o| o.get(*key).is_some()))
}

/// Rewrites every file a record names (see [`names_files`]), resolved against
/// `base` (the input's directory), for `to`. Anything else is left as it is.
/// Each file resolved is added to `named` unless it is there already: what
/// the output will point at, which it must not replace.
pub fn forward_file_refs(
    fields: &mut Fields,
    base: &Path,
    to: &RefTarget,
    named: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    for (object, key) in FILE_REFS {
        let Some(Value::Object(o)) = fields.get_mut(object) else {
            continue;
        };
        let Some(Value::String(file)) = o.get_mut(key) else {
            continue;
        };
        if key == "translation" && file == "identity" {
            continue;
        }
        let resolved = resolve(base, file);
        *file = to.path(&resolved)?;
        if !named.contains(&resolved) {
            named.push(resolved);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_pattern_paths_resolve_against_the_stream_directory() {
        assert_eq!(
            resolve(&base_dir("scenes/a.json"), "p.pat"),
            PathBuf::from("scenes/p.pat")
        );
        assert_eq!(
            resolve(&base_dir("a.json"), "p.pat"),
            PathBuf::from("./p.pat")
        );
        assert_eq!(
            resolve(&base_dir("-"), "/x/p.pat"),
            PathBuf::from("/x/p.pat")
        );
    }

    #[test]
    fn forwarded_paths_are_absolute_or_relative_to_the_output() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        std::fs::create_dir_all(root.join("in/pats")).unwrap();
        std::fs::create_dir_all(root.join("out/deep")).unwrap();
        std::fs::write(root.join("in/pats/p.pat"), "").unwrap();
        let base = root.join("in/sub/..");
        let mut fields: Fields = serde_json::from_str::<serde_json::Map<String, Value>>(
            r#"{"pattern": {"file": "pats/p.pat", "incr": 2},
                "stripe": {"map": "m.map", "translation": "identity", "colours": "../c.tab"},
                "id": 7}"#,
        )
        .unwrap()
        .into();
        assert!(names_files(&fields));
        let mut absolute = fields.clone();
        forward_file_refs(&mut absolute, &base, &RefTarget::Absolute, &mut Vec::new()).unwrap();
        let p = root.join("in/pats/p.pat");
        assert_eq!(absolute["pattern"]["file"], p.to_str().unwrap());
        assert_eq!(
            absolute["stripe"]["map"],
            root.join("in/m.map").to_str().unwrap()
        );
        assert_eq!(
            absolute["stripe"]["colours"],
            root.join("c.tab").to_str().unwrap()
        );
        assert_eq!(absolute["stripe"]["translation"], "identity");
        let to = RefTarget::relative_to_output(&root.join("out/deep/o.ndjson")).unwrap();
        forward_file_refs(&mut fields, &base, &to, &mut Vec::new()).unwrap();
        assert_eq!(fields["pattern"]["file"], "../../in/pats/p.pat");
        assert_eq!(fields["stripe"]["map"], "../../in/m.map");
        assert_eq!(fields["stripe"]["colours"], "../../c.tab");
        assert_eq!(fields["pattern"]["incr"], 2);
        assert_eq!(fields.field("id").unwrap().to_string(), "7");
        let plain: serde_json::Map<String, Value> =
            serde_json::from_str(r#"{"color": [1, 2, 3]}"#).unwrap();
        assert!(!names_files(&plain.into()));
    }
}
