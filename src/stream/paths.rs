//! Where the files a record names are found (SPEC §2): relative to the
//! stream's own file, so that a scene and its patterns move together. Apart
//! from the reader because the tools resolve paths long after reading.

use std::path::{Path, PathBuf};

/// Where relative pattern paths resolve (SPEC §2): the stream file's directory,
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
}
