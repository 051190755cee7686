//! Each crate's module graph: among the top-level modules of a workspace crate's src/, the
//! `crate::` paths (and `super::` paths that leave their top-level module) of non-test
//! code form no cycle, and no `pub use …::*` gives a type a second public path. (Between
//! crates the compiler forbids cycles; tests/crates.rs draws that graph.)
//!
//! The source is read as text: comments and string literals are blanked, then every item
//! under `#[cfg(test)]` is dropped, so that test code may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Edges that close a cycle today and are on their way out. Each is (from, to). None is
/// left; the list stays so that an exception, if one is ever needed, is named here.
const TEMPORARY_EDGES: &[(&str, &str)] = &[];

/// Every .rs file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// `text` with comments and the contents of string and character literals replaced by
/// spaces (line breaks kept), so that neither is read as code.
fn blank_comments_and_strings(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let mut i = 0;
    while i < c.len() {
        let next = c.get(i + 1).copied();
        if c[i] == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '/' && next == Some('*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
        } else if c[i] == 'r'
            && (next == Some('"') || next == Some('#'))
            && (i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_'))
        {
            // A raw string: r"…" or r#"…"#, closed by a quote and as many hashes.
            let mut j = i + 1;
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            if c.get(j) != Some(&'"') {
                out.push(c[i]);
                i += 1;
                continue;
            }
            let hashes = j - i - 1;
            out.extend(&c[i..=j]);
            i = j + 1;
            while i < c.len() {
                if c[i] == '"' && (1..=hashes).all(|k| c.get(i + k) == Some(&'#')) {
                    out.push('"');
                    out.extend(std::iter::repeat_n('#', hashes));
                    i += 1 + hashes;
                    break;
                }
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '"' {
            out.push('"');
            i += 1;
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    blank(&mut out, c[i]);
                    i += 1;
                }
                if i < c.len() {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
            out.push('"');
            i += 1;
        } else if c[i] == '\'' {
            // A character literal ('x', '\n', '\u{..}') and not a lifetime ('a).
            let end = if next == Some('\\') {
                (i + 2..c.len()).find(|&j| c[j] == '\'')
            } else if c.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match end {
                Some(e) => {
                    out.push('\'');
                    for &ch in &c[i + 1..e] {
                        blank(&mut out, ch);
                    }
                    out.push('\'');
                    i = e + 1;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// `code` (already blanked) without the items that follow `#[cfg(test)]`: up to the
/// matching closing brace, or to the semicolon of an item without a body.
fn without_test_items(code: &str) -> String {
    const MARK: &str = "#[cfg(test)]";
    let mut out = String::new();
    let mut rest = code;
    while let Some(at) = rest.find(MARK) {
        out.push_str(&rest[..at]);
        let after = &rest[at + MARK.len()..];
        let mut depth = 0usize;
        let mut end = after.len();
        for (k, ch) in after.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = k + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = k + 1;
                    break;
                }
                _ => {}
            }
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// The identifier at the start of `s`.
fn ident(s: &str) -> &str {
    let end = s
        .find(|ch: char| !(ch.is_alphanumeric() || ch == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The first segments a `crate::` path names, given the text right after `crate::`: one
/// name, or each name of a group `{a::x, b, …}`.
fn first_segments(after: &str) -> Vec<String> {
    let after = after.trim_start();
    if let Some(group) = after.strip_prefix('{') {
        let mut names = Vec::new();
        let mut depth = 0usize;
        let mut start = true;
        for (k, ch) in group.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' if depth == 0 => break,
                '}' => depth -= 1,
                ',' if depth == 0 => start = true,
                ch if ch.is_whitespace() => {}
                _ if start => {
                    names.push(ident(&group[k..]).to_string());
                    start = false;
                }
                _ => {}
            }
        }
        names
    } else {
        vec![ident(after).to_string()]
    }
}

/// Whether the path starting at byte `at` of `code` starts there: not the tail of a longer
/// name, of a longer path or of a macro's `$crate`.
fn path_starts_at(code: &str, at: usize) -> bool {
    !code[..at].ends_with(|ch: char| ch.is_alphanumeric() || ch == '_' || ch == ':' || ch == '$')
}

/// The top-level modules that the code of one file names, given the file's module path
/// below src/ (`["parse", "expr"]` for src/parse/expr.rs).
fn named_modules(code: &str, module: &[String], top: &BTreeSet<String>) -> BTreeSet<String> {
    let mut named = BTreeSet::new();
    for (at, _) in code.match_indices("crate::") {
        if !path_starts_at(code, at) {
            continue;
        }
        for name in first_segments(&code[at + "crate::".len()..]) {
            if top.contains(&name) {
                named.insert(name);
            }
        }
    }
    // A chain of `super::` as long as the module path reaches the crate root; the next
    // segment names a top-level module.
    let depth = module.len();
    for (at, _) in code.match_indices("super::") {
        if !path_starts_at(code, at) {
            continue;
        }
        let mut rest = &code[at..];
        let mut ups = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            ups += 1;
            rest = r;
        }
        if ups >= depth {
            for name in first_segments(rest) {
                if top.contains(&name) {
                    named.insert(name);
                }
            }
        }
    }
    named
}

/// The module path of a file below src/: src/a.rs and src/a/mod.rs are `a`, src/a/b.rs
/// is `a::b`; src/lib.rs is the root (empty).
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The src/ directory of every member of the workspace, read from its manifest's
/// `members` list.
fn crate_sources() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let line = manifest
        .lines()
        .find(|l| l.trim_start().starts_with("members"))
        .expect("a members list");
    let dirs: Vec<PathBuf> = line
        .split('"')
        .skip(1)
        .step_by(2)
        .map(|m| root.join(m).join("src"))
        .collect();
    assert!(
        dirs.len() > 10 && dirs.iter().all(|d| d.is_dir()),
        "{dirs:?}"
    );
    dirs
}

/// The graph among the top-level modules of `src`: for each, the others its non-test
/// code names.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let src = src.to_path_buf();
    let files = rust_files(&src);
    let top: BTreeSet<String> = files
        .iter()
        .filter_map(|f| module_path(f.strip_prefix(&src).unwrap()).first().cloned())
        .collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> =
        top.iter().map(|m| (m.clone(), BTreeSet::new())).collect();
    for f in &files {
        let module = module_path(f.strip_prefix(&src).unwrap());
        let Some(owner) = module.first() else {
            continue; // the crate root names every module by declaring it
        };
        let code = without_test_items(&blank_comments_and_strings(&fs::read_to_string(f).unwrap()));
        for name in named_modules(&code, &module, &top) {
            if &name != owner {
                graph.get_mut(owner).unwrap().insert(name);
            }
        }
    }
    graph
}

/// A cycle of `graph` as the list of its modules (first repeated at the end), if any.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        path.push(m.to_string());
        for next in &graph[m] {
            match state.get(next).copied().unwrap_or(0) {
                1 => {
                    let from = path.iter().position(|p| p == next).unwrap();
                    let mut cycle = path[from..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(next, graph, state, path) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in graph.keys() {
        if state.get(m).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(m, graph, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn top_level_modules_form_no_cycle() {
    let mut graphs: Vec<(PathBuf, BTreeMap<String, BTreeSet<String>>)> = crate_sources()
        .into_iter()
        .map(|src| (src.clone(), module_graph(&src)))
        .collect();
    for (from, to) in TEMPORARY_EDGES {
        assert!(
            graphs
                .iter_mut()
                .any(|(_, g)| g.get_mut(*from).is_some_and(|e| e.remove(*to))),
            "{from} no longer names {to}: remove the edge from TEMPORARY_EDGES"
        );
    }
    for (src, graph) in &graphs {
        check_no_cycle(src, graph);
    }
}

fn check_no_cycle(src: &Path, graph: &BTreeMap<String, BTreeSet<String>>) {
    if let Some(cycle) = find_cycle(graph) {
        let edges: Vec<String> = graph
            .iter()
            .map(|(m, e)| {
                format!(
                    "  {m} → {}",
                    e.iter().cloned().collect::<Vec<_>>().join(", ")
                )
            })
            .collect();
        panic!(
            "the top-level modules of {} form a cycle: {}\nthe graph:\n{}",
            src.display(),
            cycle.join(" → "),
            edges.join("\n")
        );
    }
}

#[test]
fn no_glob_re_exports() {
    let mut globs = Vec::new();
    for src in crate_sources() {
        for f in rust_files(&src) {
            let code = blank_comments_and_strings(&fs::read_to_string(&f).unwrap());
            for (at, _) in code.match_indices("use ") {
                let before = code[..at].trim_end();
                let public = before.ends_with("pub")
                    || (before.ends_with(')')
                        && before
                            .rfind("pub(")
                            .is_some_and(|p| !before[p..].contains([';', '{', '}'])));
                if !public || !path_starts_at(code.as_str(), at) {
                    continue;
                }
                let statement = &code[at..at + code[at..].find(';').unwrap_or(code.len() - at)];
                if statement.contains('*') {
                    let s = statement.split_whitespace().collect::<Vec<_>>().join(" ");
                    globs.push(format!("{}: {s}", f.display()));
                }
            }
        }
    }
    assert!(globs.is_empty(), "glob re-exports:\n{}", globs.join("\n"));
}

#[test]
fn the_reader_sees_through_comments_strings_and_tests() {
    let text = "use crate::a::X; // crate::b\nlet s = \"crate::c\";\n/* crate::d */\n\
                #[cfg(test)]\nmod tests { use crate::e; }\nfn f() { super::super::g::h(); }";
    let code = without_test_items(&blank_comments_and_strings(text));
    let top: BTreeSet<String> = ["a", "b", "c", "d", "e", "g"].map(String::from).into();
    let module = ["m".to_string(), "n".to_string()];
    let want: BTreeSet<String> = ["a", "g"].map(String::from).into();
    assert_eq!(named_modules(&code, &module, &top), want);
    // One `super::` from m::n stays inside m.
    let inside = named_modules("fn f() { super::g::h(); }", &module, &top);
    assert!(inside.is_empty());
    let grouped = named_modules("use crate::{a::X, g, e::{Y, Z}};", &module, &top);
    assert_eq!(grouped, ["a", "e", "g"].map(String::from).into());
    let cyclic: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(m, e)| (m.to_string(), e.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(find_cycle(&cyclic).unwrap().join(" → "), "a → b → c → a");
}
