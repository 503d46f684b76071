//! The per-test directory and helpers shared by the CLI tests.

use std::path::{Path, PathBuf};

/// A fresh temporary directory for one test; tools run with it as their
/// working directory, and it is removed when the test ends.
pub struct Dir {
    tmp: tempfile::TempDir,
}

impl Dir {
    pub fn new(test: &str) -> Dir {
        let tmp = tempfile::Builder::new()
            .prefix(&format!("patkit-{test}-"))
            .tempdir()
            .expect("creating a test directory");
        Dir { tmp }
    }

    pub fn path(&self) -> &Path {
        self.tmp.path()
    }

    /// Writes a file in the test directory and returns its path.
    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let p = self.tmp.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(&p, contents).unwrap();
        p
    }

    pub fn read(&self, name: &str) -> Vec<u8> {
        std::fs::read(self.tmp.path().join(name)).unwrap()
    }

    /// A one-triangle scene `s.json` and its 8x8 rendering `ref.png`, for
    /// the tests of `--compare` and of output names.
    pub fn triangle_and_its_image(&self) {
        self.write(
            "s.json",
            r#"{"vertices": [[0,0],[6,0],[0,6]], "color": [9,9,9]}"#,
        );
        self.cmd("scene-render")
            .args(["--size", "8x8", "s.json", "-o", "ref.png"])
            .assert()
            .success();
    }

    /// One of the project's tools, run in this directory.
    pub fn cmd(&self, tool: &str) -> assert_cmd::Command {
        let mut c = assert_cmd::Command::cargo_bin(tool).unwrap();
        c.current_dir(self.tmp.path());
        c
    }

    /// The names of the files in the directory, sorted.
    pub fn files(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(self.tmp.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

/// Whether a test that needs what a newcomer's machine may lack (GNU
/// parallel, jq, netpbm, several GB of memory) must run: `.ci/run` sets
/// `PATKIT_CI`, so CI always runs them; elsewhere they are skipped with a
/// printed reason.
pub fn required(what: &str, available: bool) -> bool {
    if available {
        return true;
    }
    assert!(
        std::env::var_os("PATKIT_CI").is_none(),
        "{what}: not available, and PATKIT_CI is set (as .ci/run sets it)"
    );
    eprintln!("skipped: {what}: not available here (.ci/run provides it and sets PATKIT_CI)");
    false
}

/// Whether the heavy cases run (`PATKIT_HEAVY=1`, which `.ci/run` sets):
/// each needs minutes and gigabytes, more than `cargo test` should take on a
/// newcomer's machine.
pub fn heavy(what: &str) -> bool {
    let on = std::env::var_os("PATKIT_HEAVY").is_some_and(|v| v == "1");
    if !on {
        eprintln!("skipped: {what}: a heavy case; PATKIT_HEAVY=1 runs it (.ci/run does)");
    }
    on
}

/// A path inside the repository (fixtures, man pages).
pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// The text of a canonical 16x16 pattern: colour 1 red where (col + row) is
/// even, colour 2 blue where odd, except texel (0,0), which is transparent.
pub fn checker16() -> String {
    let mut s = String::from("16 2\n255 0 0\n");
    for parity in [0u32, 1] {
        if parity == 1 {
            s.push_str("0 0 255\n");
        }
        for row in 0..16u32 {
            let mut word = 0u16;
            for col in 0..16u32 {
                let set = (col + row) % 2 == parity && !(col == 0 && row == 0);
                word = (word << 1) | set as u16;
            }
            s.push_str(&format!("{word:04x}\n"));
        }
    }
    s
}

/// Declares a test that gets its own [`Dir`] bound to `$dir`.
macro_rules! clitest {
    ($name:ident, |$dir:ident| $body:block) => {
        #[test]
        fn $name() {
            #[allow(unused_variables)]
            let $dir = $crate::util::Dir::new(stringify!($name));
            $body
        }
    };
}

/// The standard output of a command that must succeed.
pub trait OkStdout {
    fn ok_stdout(&mut self) -> Vec<u8>;
}

impl OkStdout for assert_cmd::Command {
    fn ok_stdout(&mut self) -> Vec<u8> {
        self.assert().success().get_output().stdout.clone()
    }
}
