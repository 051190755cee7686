//! Helpers shared by the test files: the command, scratch directories, random sets and
//! bit patterns.

#![allow(dead_code)]

use std::fs;
use std::path::PathBuf;
use std::process::Command;

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use stillpoint::PointSet;

/// The `stillpoint` command built for these tests.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stillpoint"))
}

/// Runs `cmd` and returns its standard output and standard error, failing the test with
/// `what` and the standard error when the command fails.
pub fn succeeded(cmd: &mut Command, what: &dyn std::fmt::Debug) -> (String, String) {
    let o = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{what:?}: {err}");
    (String::from_utf8_lossy(&o.stdout).into_owned(), err)
}

/// The lines that `keep` selects of a page of the documentation, `path` relative to the
/// repository (`README.md`, `docs/regions.md`): commands a test runs as written.
pub fn doc_lines(path: &str, keep: impl Fn(&str) -> bool) -> Vec<String> {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path);
    std::fs::read_to_string(&file)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
        .lines()
        .filter(|l| keep(l))
        .map(str::to_string)
        .collect()
}

/// A fresh, empty directory `stillpoint-<test file>-<pid>-<name>` in the temporary
/// directory (left in place afterwards).
pub fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "stillpoint-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// A fresh directory per test, named like [`tmpdir`]'s, removed on drop so that failures
/// do not pile up.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(test: &str) -> TempDir {
        TempDir(tmpdir(test))
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// The names of the files in the directory, sorted.
    pub fn entries(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// n points uniform in [0, 1)^s from a seeded generator.
pub fn random_set(n: usize, s: usize, seed: u64) -> PointSet {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    PointSet::new(n, s, (0..n * s).map(|_| rng.random::<f64>()).collect()).unwrap()
}

/// The bit patterns of the coordinates, for exact comparisons.
pub fn bits(p: &PointSet) -> Vec<u64> {
    p.as_slice().iter().map(|v| v.to_bits()).collect()
}

/// A README command line's arguments: words split at spaces, except that a part between
/// two `quote` characters is one argument (as a shell reads the README's examples).
pub fn shell_words(line: &str, quote: char) -> Vec<String> {
    let mut out = Vec::new();
    for (i, part) in line.split(quote).enumerate() {
        if i % 2 == 1 {
            out.push(part.to_string());
        } else {
            out.extend(part.split_whitespace().map(String::from));
        }
    }
    out
}
