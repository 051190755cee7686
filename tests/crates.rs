//! The crate graph as `cargo metadata` reports it: drawn in ARCHITECTURE.md (this test
//! fails, printing the graph to paste, when the two differ), every edge from a higher
//! layer to a lower one, and no crate holding more than 30 % of the workspace's non-test
//! Rust.
//!
//! A crate's layer is the length of its longest chain of workspace dependencies (the
//! geometry crate, which depends on none, is layer 0), so the graph's lines are ordered
//! bottom-up and an edge can only point down.

use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The largest share of the workspace's non-test Rust lines one crate may hold.
const MAX_SHARE: f64 = 0.30;

/// Where ARCHITECTURE.md keeps the graph: the fenced block after this line.
const MARKER: &str = "<!-- crate graph: drawn by tests/crates.rs from cargo metadata -->";

struct Workspace {
    /// Each member's workspace dependencies (normal ones: dev-dependencies may point up,
    /// as a test may reach anywhere).
    deps: BTreeMap<String, BTreeSet<String>>,
    /// Each member's directory.
    dirs: BTreeMap<String, PathBuf>,
}

fn workspace() -> Workspace {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(env!("CARGO"))
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(root)
        .output()
        .expect("cargo metadata runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: Value = serde_json::from_slice(&out.stdout).unwrap();
    let packages = meta["packages"].as_array().unwrap();
    let names: BTreeSet<String> = packages
        .iter()
        .map(|p| p["name"].as_str().unwrap().to_string())
        .collect();
    let mut deps = BTreeMap::new();
    let mut dirs = BTreeMap::new();
    for p in packages {
        let name = p["name"].as_str().unwrap().to_string();
        let normal: BTreeSet<String> = p["dependencies"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|d| d["kind"].is_null())
            .map(|d| d["name"].as_str().unwrap().to_string())
            .filter(|d| names.contains(d))
            .collect();
        let manifest = PathBuf::from(p["manifest_path"].as_str().unwrap());
        dirs.insert(name.clone(), manifest.parent().unwrap().to_path_buf());
        deps.insert(name, normal);
    }
    Workspace { deps, dirs }
}

/// Each crate's layer: 0 without workspace dependencies, else one above its highest.
fn layers(deps: &BTreeMap<String, BTreeSet<String>>) -> BTreeMap<String, usize> {
    fn layer(
        c: &str,
        deps: &BTreeMap<String, BTreeSet<String>>,
        memo: &mut BTreeMap<String, usize>,
    ) -> usize {
        if let Some(&l) = memo.get(c) {
            return l;
        }
        let l = deps[c]
            .iter()
            .map(|d| layer(d, deps, memo) + 1)
            .max()
            .unwrap_or(0);
        memo.insert(c.to_string(), l);
        l
    }
    let mut memo = BTreeMap::new();
    for c in deps.keys() {
        layer(c, deps, &mut memo);
    }
    memo
}

/// The graph as ARCHITECTURE.md draws it: one line per crate, bottom layer first, each
/// with the crates it depends on (the `stillpoint-` prefix dropped).
fn drawn(deps: &BTreeMap<String, BTreeSet<String>>) -> String {
    let layer = layers(deps);
    let mut order: Vec<&String> = deps.keys().collect();
    order.sort_by_key(|c| (layer[*c], c.as_str()));
    let short = |c: &str| c.strip_prefix("stillpoint-").unwrap_or(c).to_string();
    order
        .iter()
        .map(|c| {
            let below: Vec<String> = deps[*c].iter().map(|d| short(d)).collect();
            let line = format!("layer {} {:<12}", layer[*c], short(c));
            if below.is_empty() {
                line.trim_end().to_string()
            } else {
                format!("{line} → {}", below.join(", "))
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Lines of `code` outside `#[cfg(test)]` items (a test module inline or a file it
/// names), counted as the text stands.
fn non_test_lines(code: &str) -> usize {
    let lines: Vec<&str> = code.lines().collect();
    let (mut count, mut i) = (0, 0);
    while i < lines.len() {
        if lines[i].trim() == "#[cfg(test)]" && i + 1 < lines.len() {
            let item = lines[i + 1].trim_start();
            if item.starts_with("mod ") && item.trim_end().ends_with(';') {
                i += 2;
                continue;
            }
            if item.starts_with("mod ") {
                // Skip to the brace that closes the module.
                let mut depth = 0i64;
                let mut j = i + 1;
                loop {
                    depth += lines[j].matches('{').count() as i64;
                    depth -= lines[j].matches('}').count() as i64;
                    if depth <= 0 && lines[j].contains('}') || j + 1 == lines.len() {
                        break;
                    }
                    j += 1;
                }
                i = j + 1;
                continue;
            }
        }
        count += 1;
        i += 1;
    }
    count
}

/// The non-test Rust lines under `dir` (its src/; tests/, benches/ and examples/ are
/// not the crate's code, and files a `#[cfg(test)] mod x;` names are tests).
fn crate_lines(dir: &Path) -> usize {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(&dir.join("src"), &mut files);
    let texts: Vec<(PathBuf, String)> = files
        .into_iter()
        .map(|f| {
            let t = fs::read_to_string(&f).unwrap();
            (f, t)
        })
        .collect();
    let test_files: BTreeSet<String> = texts
        .iter()
        .flat_map(|(_, t)| {
            let lines: Vec<&str> = t.lines().collect();
            lines
                .windows(2)
                .filter(|w| w[0].trim() == "#[cfg(test)]")
                .filter_map(|w| {
                    let m = w[1].trim().strip_prefix("mod ")?.strip_suffix(';')?;
                    Some(format!("{m}.rs"))
                })
                .collect::<Vec<_>>()
        })
        .collect();
    texts
        .iter()
        .filter(|(f, _)| {
            let name = f.file_name().unwrap().to_string_lossy().to_string();
            !test_files.contains(&name)
        })
        .map(|(_, t)| non_test_lines(t))
        .sum()
}

#[test]
fn architecture_draws_the_crate_graph_cargo_reports() {
    let ws = workspace();
    let want = drawn(&ws.deps);
    let doc =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap();
    let after = doc
        .split_once(MARKER)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no line {MARKER}"))
        .1;
    let block = after
        .split_once("```text\n")
        .and_then(|(_, rest)| rest.split_once("```"))
        .map(|(b, _)| b.trim_end())
        .expect("a ```text block after the marker");
    assert_eq!(
        block, want,
        "ARCHITECTURE.md's crate graph differs from cargo metadata; the graph is:\n{want}"
    );
}

#[test]
fn every_edge_points_down_a_layer() {
    let ws = workspace();
    let layer = layers(&ws.deps);
    for (c, below) in &ws.deps {
        for d in below {
            assert!(
                layer[d] < layer[c],
                "{c} (layer {}) → {d} (layer {})",
                layer[c],
                layer[d]
            );
        }
    }
    // The graph is a chain of layers, not one crate above everything else flat: the
    // library's layers go at least six deep below the command line.
    assert!(layer["stillpoint-cli"] >= 6, "{layer:?}");
}

#[test]
fn no_crate_holds_more_than_its_share() {
    let ws = workspace();
    let lines: BTreeMap<&String, usize> =
        ws.dirs.iter().map(|(c, d)| (c, crate_lines(d))).collect();
    let total: usize = lines.values().sum();
    let table: Vec<String> = lines
        .iter()
        .map(|(c, &n)| format!("{c}: {n} ({:.1} %)", 100.0 * n as f64 / total as f64))
        .collect();
    for (c, &n) in &lines {
        assert!(
            n as f64 <= MAX_SHARE * total as f64,
            "{c} holds {n} of {total} non-test lines, above {:.0} %:\n{}",
            100.0 * MAX_SHARE,
            table.join("\n")
        );
    }
    assert!(total > 30_000, "{}", table.join("\n"));
}

#[test]
fn the_counter_skips_test_modules_only() {
    let code = "fn a() {}\n#[cfg(test)]\nmod tests {\n    fn b() {\n    }\n}\nfn c() {}\n#[cfg(test)]\nmod more;\n";
    assert_eq!(non_test_lines(code), 2);
    let mut deps = BTreeMap::new();
    deps.insert("stillpoint-a".to_string(), BTreeSet::new());
    deps.insert(
        "stillpoint-b".to_string(),
        BTreeSet::from(["stillpoint-a".to_string()]),
    );
    assert_eq!(drawn(&deps), "layer 0 a\nlayer 1 b            → a");
}
