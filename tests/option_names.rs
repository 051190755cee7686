//! Option names are read from their declarations, not written again: outside the option
//! table (`src/pipeline/options.rs`) and test modules, a string literal equal to a
//! declared name, alias, flag or Python keyword appears at most as often as
//! ARCHITECTURE.md ("Option names in code") accounts for, each kind there explained.
//! The one-letter `n`, `s`, `d` (and `-n`, `-s`) are left out: they are also plain
//! words of the code's own.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use stillpoint::pipeline::options::ALL;

/// The literals ARCHITECTURE.md accounts for: 24 naming an option (the constants of
/// `parse/src/names.rs`, clap ids) and 20 words of other tables spelt like one.
const ACCOUNTED: usize = 44;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every spelling of every declared option.
fn spellings() -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for d in ALL {
        names.insert(d.name.to_string());
        names.extend(d.also.iter().map(|a| a.to_string()));
        if !d.cli.is_empty() {
            names.insert(d.cli.to_string());
        }
        names.extend(d.cli_also.iter().map(|a| a.to_string()));
        names.extend(d.python.map(str::to_string));
    }
    for short in ["n", "s", "d", "-n", "-s"] {
        names.remove(short);
    }
    names
}

#[test]
fn option_names_are_not_written_again_outside_the_table() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let names = spellings();
    assert!(names.contains("seed") && names.contains("--abs-tol") && names.contains("box"));
    let mut files = Vec::new();
    for dir in [
        "src",
        "io/src",
        "parse/src",
        "sequences/src",
        "quality/src",
        "solve/src",
        "run/src",
        "design/src",
        "cubature/src",
        "cli/src",
        "python/src",
    ] {
        rust_files(&root.join(dir), &mut files);
    }
    files.sort();
    let mut found = Vec::new();
    for path in files {
        if path.ends_with("pipeline/options.rs") {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap_or_default();
        for (i, line) in code.lines().enumerate() {
            for name in &names {
                let quoted = format!("\"{name}\"");
                for _ in line.matches(quoted.as_str()) {
                    let shown = path.strip_prefix(root).unwrap_or(&path).display();
                    found.push(format!("{shown}:{}: {quoted}", i + 1));
                }
            }
        }
    }
    assert!(
        found.len() <= ACCOUNTED,
        "{} option names written as string literals outside the option table, {} \
         accounted for in ARCHITECTURE.md; name the option by its declaration \
         (`Opt::x.name()`, `values::flag(Opt::x)`, a constant of `parse/src/names.rs`):\n{}",
        found.len(),
        ACCOUNTED,
        found.join("\n")
    );
}
