//! The front page and the guide stay true: every relative link of README.md, BENCHMARKS.md
//! and docs/*.md leads to a file (and a heading, for `#anchor`s), each figure of the
//! front page's gains table is in the file it links to, and the front page's commands run
//! as written.

mod common;

use common::{bin, doc_lines, shell_words, succeeded, TempDir};
use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The pages checked: the front page, the benchmarks and every page of the guide.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md"), root().join("BENCHMARKS.md")];
    let mut docs: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// The lines of a Markdown text outside its fenced code blocks.
fn prose(text: &str) -> Vec<&str> {
    let mut fenced = false;
    text.lines()
        .filter(|l| {
            if l.trim_start().starts_with("```") {
                fenced = !fenced;
                return false;
            }
            !fenced
        })
        .collect()
}

/// GitHub's anchor for a heading: lower case, letters, digits, `-` and `_` kept, spaces
/// made `-`, everything else dropped; a repeated heading gets `-1`, `-2`, ….
fn anchors(text: &str) -> HashSet<String> {
    let mut seen = HashSet::new();
    for line in prose(text) {
        let Some(title) = line
            .strip_prefix('#')
            .map(|t| t.trim_start_matches('#'))
            .filter(|t| t.starts_with(' '))
        else {
            continue;
        };
        let slug: String = title
            .trim()
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let mut unique = slug.clone();
        let mut k = 0;
        while !seen.insert(unique.clone()) {
            k += 1;
            unique = format!("{slug}-{k}");
        }
    }
    seen
}

/// Every link target of a page outside code: `[text](target)` and `src="target"`, with
/// the link's text (empty for `src`).
fn links(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for line in prose(text) {
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let open = rest[..i].rfind('[').map_or(0, |j| j + 1);
            let label = rest[open..i].to_string();
            let tail = &rest[i + 2..];
            let end = tail.find(')').unwrap_or(tail.len());
            out.push((label, tail[..end].to_string()));
            rest = &tail[end..];
        }
        let mut rest = line;
        while let Some(i) = rest.find("src=\"") {
            let tail = &rest[i + 5..];
            let end = tail.find('"').unwrap_or(tail.len());
            out.push((String::new(), tail[..end].to_string()));
            rest = &tail[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_leads_to_a_file_and_heading() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = fs::read_to_string(&page).unwrap();
        for (_, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((f, a)) => (f, Some(a)),
                None => (target.as_str(), None),
            };
            let path = if file.is_empty() {
                page.clone()
            } else {
                page.parent().unwrap().join(file)
            };
            if !path.exists() {
                broken.push(format!("{}: {target} (no such file)", page.display()));
                continue;
            }
            if let Some(anchor) = anchor {
                let headings = anchors(&fs::read_to_string(&path).unwrap_or_default());
                if !headings.contains(anchor) {
                    broken.push(format!("{}: {target} (no such heading)", page.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// The gains table of the front page: each figure (a link whose text holds a digit, or
/// a stated time) is found in the results file it links to.
#[test]
fn each_figure_of_the_gains_table_is_in_the_file_it_links_to() {
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    let start = readme
        .find("\n## What you gain")
        .expect("the gains section");
    let end = readme[start + 1..]
        .find("\n## ")
        .map_or(readme.len(), |e| start + 1 + e);
    let section = &readme[start..end];
    assert!(section.contains("Above a thousand points"), "{section}");
    let mut checked = 0;
    for (label, target) in links(section) {
        if !label.chars().any(|c| c.is_ascii_digit()) && label != "under a second" {
            continue;
        }
        let file = target.split('#').next().unwrap();
        let text = fs::read_to_string(root().join(file)).unwrap();
        assert!(text.contains(&label), "{label} is not in {file}");
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} figures linked");
}

/// The front page's commands: the quick start (with `stillpoint` for `cargo run --release
/// --`), whose report has the rows the page shows, and the command-line example.
#[test]
fn the_front_pages_commands_run_as_written() {
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    assert!(readme.contains("pip install ./python"));
    assert!(readme.contains("\n./test.sh\n"));
    let dir = TempDir::new("front-page");
    let quick = doc_lines("README.md", |l| {
        l.starts_with("cargo run --release -- generate ")
    });
    assert_eq!(quick.len(), 1, "{quick:?}");
    let words = shell_words(quick[0].trim_start_matches("cargo run --release -- "), '"');
    let (out, err) = succeeded(bin().current_dir(&dir.0).args(&words).arg("-q"), &words);
    let report = out + &err;
    // Each row of the printed block is in the report, by its label.
    let block = &readme[readme.find("```text\n").unwrap()..];
    let block = &block[..block[8..].find("```").unwrap()];
    let rows: Vec<&str> = block
        .lines()
        .filter(|l| {
            l.contains("(root)") || l.contains("minimum distance") || l.contains("mean gap")
        })
        .collect();
    assert_eq!(rows.len(), 7, "{block}");
    for row in rows {
        let label = row
            .split("  ")
            .map(str::trim)
            .find(|p| !p.is_empty())
            .unwrap();
        assert!(report.contains(label), "{label} not in\n{report}");
    }
    assert!(report.contains("every coordinate stratified (one point in each [k/n, (k+1)/n)): yes"));
    assert!(dir.path("points.csv").exists());

    let lines = doc_lines("README.md", |l| {
        l.starts_with("stillpoint generate ") || l.starts_with("stillpoint eval ")
    });
    assert_eq!(lines.len(), 4, "{lines:?}");
    for line in &lines {
        let mut words = shell_words(line.trim_start_matches("stillpoint "), '"');
        if words[0] == "generate" {
            words.push("-q".into());
        }
        let (out, _) = succeeded(bin().current_dir(&dir.0).args(&words), line);
        if words[0] == "eval" {
            for f in ["ours.csv", "randomised.csv", "design.csv"] {
                assert!(out.contains(f), "{out}");
            }
        }
    }
}

/// Commands of the guide the test does not run, each with its reason; every other
/// `stillpoint` line of a ```sh block in docs/*.md runs, page by page in order, in one
/// scratch directory per page.
const NOT_RUN: &[(&str, &str)] = &[
    (
        "stillpoint generate -n 1500 -s 10 -o p.csv --checkpoint p.ckpt",
        "a run of tens of seconds, shown only for its options",
    ),
    (
        "stillpoint compare --cases 2x1500,3x1500 --out comparison",
        "minutes of DEM runs",
    ),
    (
        "stillpoint generate --region \"|x| + 2*|y| - 5\" --box -5.5,5.5,-3,3 -n 100 -o diamond.csv --plot diamond.png",
        "10 000 steps of the space-filling dynamics, minutes",
    ),
    (
        "stillpoint generate --shape ball:1 -s 3 -n 200 -o ball.csv",
        "10 000 steps of the space-filling dynamics, minutes",
    ),
];

#[test]
fn the_guides_commands_run_as_written() {
    let mut ran = 0;
    let mut skipped = HashSet::new();
    for page in pages()
        .iter()
        .filter(|p| p.parent().unwrap().ends_with("docs"))
    {
        let text = fs::read_to_string(page).unwrap();
        let mut fenced_sh = false;
        let mut commands = Vec::new();
        for line in text.lines() {
            if line.starts_with("```") {
                fenced_sh = line == "```sh";
                continue;
            }
            if fenced_sh && line.starts_with("stillpoint ") {
                let line = line.find("  #").map_or(line, |i| &line[..i]).trim_end();
                commands.push(line.to_string());
            }
        }
        if commands.is_empty() {
            continue;
        }
        let name = page.file_stem().unwrap().to_string_lossy().into_owned();
        let dir = TempDir::new(&format!("guide-{name}"));
        for line in &commands {
            if let Some((cmd, _)) = NOT_RUN.iter().find(|(c, _)| line.starts_with(c)) {
                skipped.insert(*cmd);
                continue;
            }
            let quote = if line.contains('\'') { '\'' } else { '"' };
            let words = shell_words(line.trim_start_matches("stillpoint "), quote);
            succeeded(
                bin().current_dir(&dir.0).args(&words),
                &format!("{name}: {line}"),
            );
            ran += 1;
        }
    }
    // The exempt list names only commands that are in the guide.
    assert_eq!(skipped.len(), NOT_RUN.len(), "{skipped:?}");
    assert!(ran >= 25, "only {ran} commands ran");
}
