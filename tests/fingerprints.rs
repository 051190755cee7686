//! The results a page cites still describe what ships. Every results file that README.md,
//! BENCHMARKS.md or a page of docs/ links to either carries fingerprints (the commit it
//! was made at, the command that remakes it, and per cell the command that made our set
//! with the SHA-256 of its coordinates) or is marked with the commit it describes. For
//! every fingerprinted file the cheapest cells are made again through the library's
//! [`Request`], as the command line makes them, and hashed: a changed hash names the
//! file and the command that remakes it.
//!
//! The line formats (written by benches/fingerprint.py):
//!
//! ```text
//!     commit: <40 hex digits>
//!     remake: <command>
//!     fingerprint: generate -n 16 -s 2 [--flag [value]]... sha256:<64 hex digits>
//!     describes commit: <hex> (<why it carries no fingerprint>)
//! ```

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use stillpoint::pipeline::request::Arg;
use stillpoint::Request;

/// The pages whose links to results/ are checked.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut out = vec![root.join("README.md"), root.join("BENCHMARKS.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("a docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    out.extend(docs);
    out
}

/// `path` with `.` and `..` folded away (the files need not exist).
fn normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// The files under results/ a page links to (Markdown `](target)` links; an anchor is
/// dropped, a link to a folder is not a file and is skipped), relative to the root.
fn cited(root: &Path, page: &Path) -> BTreeSet<PathBuf> {
    let text = std::fs::read_to_string(page).expect("a page");
    let dir = page.parent().expect("a page's folder");
    let mut out = BTreeSet::new();
    for piece in text.split("](").skip(1) {
        let Some(end) = piece.find(')') else { continue };
        let target = piece[..end].split('#').next().unwrap_or("");
        if target.contains("://") || !target.contains("results/") {
            continue;
        }
        let full = normal(&dir.join(target));
        let Ok(rel) = full.strip_prefix(normal(root)) else {
            continue;
        };
        // results/README.md is the index of the results, not a file of figures.
        if rel.starts_with("results")
            && rel != Path::new("results/README.md")
            && root.join(rel).is_file()
        {
            out.insert(rel.to_path_buf());
        }
    }
    out
}

/// One fingerprinted cell: the `generate` options as typed and the expected hash.
struct Cell {
    options: Vec<String>,
    n: usize,
    s: usize,
    sha256: String,
}

impl Cell {
    fn parse(line: &str) -> Option<Cell> {
        let rest = line.trim().strip_prefix("fingerprint: ")?;
        let (command, hash) = rest.rsplit_once(" sha256:")?;
        let hash = hash.trim();
        if hash.len() != 64 || !hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let mut words = command.split_whitespace();
        if words.next()? != "generate" {
            return None;
        }
        let options: Vec<String> = words.map(str::to_string).collect();
        let value = |flag: &str| {
            let i = options.iter().position(|w| w == flag)?;
            options.get(i + 1)?.parse().ok()
        };
        Some(Cell {
            n: value("-n")?,
            s: value("-s")?,
            sha256: hash.to_string(),
            options,
        })
    }

    /// The cell's set as the command line makes it: each `--flag value` set on a
    /// [`Request`] under the flag's library name, a flag without a value set true.
    fn make(&self) -> stillpoint::PointSet {
        let mut req = Request::new(self.n, self.s);
        let mut i = 0;
        while i < self.options.len() {
            let word = &self.options[i];
            if word == "-n" || word == "-s" {
                i += 2;
                continue;
            }
            let name = word.trim_start_matches('-').replace('-', "_");
            let value = self.options.get(i + 1).filter(|v| !v.starts_with("--"));
            let arg = value.map_or(Arg::Bool(true), |v| Arg::Text(v.clone()));
            req.set(&name, arg)
                .unwrap_or_else(|e| panic!("{}: {e}", self.options.join(" ")));
            i += if value.is_some() { 2 } else { 1 };
        }
        req.resolve()
            .and_then(|r| r.run(None, |_| {}))
            .unwrap_or_else(|e| panic!("generate {}: {e}", self.options.join(" ")))
            .points
    }
}

/// What a results file says of itself.
struct Record {
    commit: Option<String>,
    remake: Option<String>,
    describes: Option<String>,
    cells: Vec<Cell>,
}

fn record(text: &str) -> Record {
    let field = |key: &str| {
        text.lines()
            .find_map(|l| l.trim().strip_prefix(key).map(|v| v.trim().to_string()))
    };
    Record {
        commit: field("commit: "),
        remake: field("remake: "),
        describes: field("describes commit: "),
        cells: text.lines().filter_map(Cell::parse).collect(),
    }
}

/// The cells remade per file: the two cheapest, and the cheapest lattice cell (from 500
/// points on the default is the lattice) — cheap both, and the two pipelines a size
/// can take.
fn cheap(cells: &[Cell]) -> Vec<&Cell> {
    let mut by_cost: Vec<&Cell> = cells.iter().collect();
    by_cost.sort_by_key(|c| c.n * c.s);
    let mut out: Vec<&Cell> = by_cost.iter().copied().take(2).collect();
    if let Some(c) = by_cost.iter().find(|c| c.n >= 500 && c.n * c.s <= 20_000) {
        if !out.iter().any(|o| std::ptr::eq(*o, *c)) {
            out.push(c);
        }
    }
    out
}

#[test]
fn every_cited_results_file_is_fingerprinted_or_marked_and_its_cheap_cells_still_hash_alike() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files: BTreeSet<PathBuf> = pages(root).iter().flat_map(|p| cited(root, p)).collect();
    assert!(
        files.contains(Path::new("results/anchors/anchors.md")),
        "the pages cite the anchors' results: {files:?}"
    );
    let mut failures = Vec::new();
    let mut remade = 0;
    for file in &files {
        let text = std::fs::read_to_string(root.join(file)).expect("a results file");
        let rec = record(&text);
        let name = file.display();
        if rec.cells.is_empty() {
            if rec.describes.is_none() {
                failures.push(format!(
                    "{name}: neither fingerprints nor a `describes commit:` line"
                ));
            }
            continue;
        }
        let (Some(_), Some(remake)) = (&rec.commit, &rec.remake) else {
            failures.push(format!(
                "{name}: fingerprints without `commit:` and `remake:`"
            ));
            continue;
        };
        for cell in cheap(&rec.cells) {
            let now = sha256(&le_bytes(&cell.make()));
            remade += 1;
            if now != cell.sha256 {
                failures.push(format!(
                    "{name}: `generate {}` now makes sha256:{now}, the file measured \
                     sha256:{}; remake it with `{remake}`",
                    cell.options.join(" "),
                    cell.sha256
                ));
            }
        }
    }
    assert!(remade > 0, "no cell was remade");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The coordinates row by row as little-endian f64 (what benches/fingerprint.py hashes).
fn le_bytes(x: &stillpoint::PointSet) -> Vec<u8> {
    x.as_slice().iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// SHA-256 (FIPS 180-4) in lowercase hex; the test needs no dependency for it.
fn sha256(data: &[u8]) -> String {
    const K: [u32; 64] = [
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2,
    ];
    let mut h: [u32; 8] = [
        0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab,
        0x5be0cd19,
    ];
    let mut msg = data.to_vec();
    msg.push(0x80);
    while msg.len() % 64 != 56 {
        msg.push(0);
    }
    msg.extend_from_slice(&((data.len() as u64) * 8).to_be_bytes());
    for block in msg.chunks_exact(64) {
        let mut w = [0u32; 64];
        for (i, word) in block.chunks_exact(4).enumerate() {
            w[i] = u32::from_be_bytes([word[0], word[1], word[2], word[3]]);
        }
        for i in 16..64 {
            let s0 = w[i - 15].rotate_right(7) ^ w[i - 15].rotate_right(18) ^ (w[i - 15] >> 3);
            let s1 = w[i - 2].rotate_right(17) ^ w[i - 2].rotate_right(19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16]
                .wrapping_add(s0)
                .wrapping_add(w[i - 7])
                .wrapping_add(s1);
        }
        let [mut a, mut b, mut c, mut d, mut e, mut f, mut g, mut hh] = h;
        for i in 0..64 {
            let t1 = hh
                .wrapping_add(e.rotate_right(6) ^ e.rotate_right(11) ^ e.rotate_right(25))
                .wrapping_add((e & f) ^ (!e & g))
                .wrapping_add(K[i])
                .wrapping_add(w[i]);
            let t2 = (a.rotate_right(2) ^ a.rotate_right(13) ^ a.rotate_right(22))
                .wrapping_add((a & b) ^ (a & c) ^ (b & c));
            hh = g;
            g = f;
            f = e;
            e = d.wrapping_add(t1);
            d = c;
            c = b;
            b = a;
            a = t1.wrapping_add(t2);
        }
        for (x, y) in h.iter_mut().zip([a, b, c, d, e, f, g, hh]) {
            *x = x.wrapping_add(y);
        }
    }
    h.iter().map(|v| format!("{v:08x}")).collect()
}

#[test]
fn the_hash_is_sha256_of_the_bytes_benches_fingerprint_py_hashes() {
    // FIPS 180-4's examples (one block, empty, two blocks), then a set whose hash
    // Python's hashlib gave for np.array([[0.5, 0.25], [0.125, 1/3], [0.1, 0.9]]).
    assert_eq!(
        sha256(b""),
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    );
    assert_eq!(
        sha256(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
    assert_eq!(
        sha256(b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
    );
    let x = stillpoint::PointSet::from_rows(&[[0.5, 0.25], [0.125, 1.0 / 3.0], [0.1, 0.9]])
        .expect("a set");
    assert_eq!(
        sha256(&le_bytes(&x)),
        "ae009a28d364715e499e9913f7762abc19efec80028fc6a7baaf75f1ca225725"
    );
}
