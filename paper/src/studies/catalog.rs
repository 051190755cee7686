//! Section 5.2's catalog: DEM sets for s = 2..20 and n ∈ {10, 20, 50, 100, 200, 400, 800,
//! 1500} with n ≥ 2s (127 sets), written to a directory with a manifest, resumable.
//!
//! s = 1..20 with n ≥ 2s would give 135 sets; the paper's count of 127 is exactly the
//! s ≥ 2 part (its test function F8 needs two coordinates), so that is what is built.
//! Every set is the default `stillpoint generate` pipeline. The manifest is rewritten
//! atomically after every set, so an interrupted run resumes where it stopped and gives
//! the same files as an uninterrupted one.

use super::{human_seconds, markdown_table, Body, StudyOptions};
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use stillpoint::config::GenerateConfig;
use stillpoint::io;
use stillpoint::pipeline::run_config;
use stillpoint::quality::metrics::Metrics;
use stillpoint::PointSet;

/// The sizes of the paper's catalog.
pub const CATALOG_N: [usize; 8] = [10, 20, 50, 100, 200, 400, 800, 1500];

/// The catalog's (s, n) pairs: full (127 sets) or quick (a small corner of it).
pub fn catalog_cases(quick: bool) -> Vec<(usize, usize)> {
    let (dims, ns): (Vec<usize>, &[usize]) = if quick {
        ((2..=4).collect(), &CATALOG_N[..3])
    } else {
        ((2..=20).collect(), &CATALOG_N[..])
    };
    let mut cases = vec![];
    for &s in &dims {
        for &n in ns {
            if n >= 2 * s {
                cases.push((s, n));
            }
        }
    }
    cases
}

/// One finished set.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Entry {
    /// Dimension.
    pub s: usize,
    /// Number of points.
    pub n: usize,
    /// File name inside the catalog directory.
    pub file: String,
    /// q and p of U_{q,p} (eq. 48).
    pub q: String,
    /// p.
    pub p: f64,
    /// DEM steps taken.
    pub steps: usize,
    /// D_MD of the set (root of eq. 47).
    pub modified_l2: f64,
    /// D_L2* of the set (root of eq. 46).
    pub star_l2: f64,
    /// D_MD of the Halton start.
    pub start_modified_l2: f64,
    /// D_L2* of the Halton start.
    pub start_star_l2: f64,
    /// Smallest Euclidean distance.
    pub min_distance: f64,
    /// Wall time of the run in seconds.
    pub seconds: f64,
}

/// The catalog's manifest (`manifest.json`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Manifest {
    /// Version of stillpoint that made it.
    pub stillpoint: String,
    /// DEM step budget of every set.
    pub steps: usize,
    /// Whether this is the quick catalog.
    pub quick: bool,
    /// How each set was made.
    pub pipeline: String,
    /// Finished sets, in the catalog's order.
    pub sets: Vec<Entry>,
}

/// The file name of a set.
pub fn file_name(s: usize, n: usize) -> String {
    format!("P_s{s:02}_n{n:04}.csv")
}

fn read_manifest(path: &Path) -> Result<Option<Manifest>> {
    if !path.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the catalog manifest {}", path.display()))?;
    let m: Manifest = serde_json::from_str(&text).with_context(|| {
        format!(
            "{} is not a catalog manifest; move it away or choose another --out",
            path.display()
        )
    })?;
    Ok(Some(m))
}

/// Builds the catalog in `opts.catalog_dir`, or completes it after an interruption, and
/// returns the manifest with every set. Sets whose file is present and listed are kept.
pub fn ensure(opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<(Manifest, PathBuf)> {
    let dir = opts.catalog_dir.clone();
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create the catalog directory {}", dir.display()))?;
    let steps = if opts.quick { 100 } else { 1000 };
    let manifest_path = dir.join("manifest.json");
    let mut manifest = match read_manifest(&manifest_path)? {
        Some(m) => {
            if m.steps != steps || m.quick != opts.quick {
                bail!(
                    "the catalog in {} was made with {} steps (quick: {}), this run asks for {} \
                     (quick: {}); use another --out or remove that directory",
                    dir.display(),
                    m.steps,
                    m.quick,
                    steps,
                    opts.quick
                );
            }
            m
        }
        None => Manifest {
            stillpoint: env!("CARGO_PKG_VERSION").into(),
            steps,
            quick: opts.quick,
            pipeline: "stillpoint generate --method paper: U_{q,p} with (q, p) from eq. 48, plain \
                       Halton start (indices 1..n), DEM with κ trial from 100 and restart \
                       ε_p = 2/n, then the best of 64 periodic shifts by D_MD"
                .into(),
            sets: vec![],
        },
    };
    // Keep only listed sets whose file is really there with the right shape.
    manifest.sets.retain(|e| {
        io::read_points(&dir.join(&e.file))
            .map(|p| p.n() == e.n && p.s() == e.s)
            .unwrap_or(false)
    });
    let todo: Vec<(usize, usize)> = catalog_cases(opts.quick)
        .into_iter()
        .filter(|&(s, n)| !manifest.sets.iter().any(|e| e.s == s && e.n == n))
        .collect();
    if !todo.is_empty() {
        log(&format!(
            "catalog: {} of {} sets to make in {}",
            todo.len(),
            catalog_cases(opts.quick).len(),
            dir.display()
        ));
    }
    let shared = Mutex::new((manifest, Vec::<String>::new()));
    let make = |&(s, n): &(usize, usize)| -> Result<()> {
        let entry = make_set(&dir, s, n, steps)?;
        let mut guard = shared
            .lock()
            .map_err(|_| anyhow::anyhow!("catalog lock poisoned"))?;
        let (m, lines) = &mut *guard;
        lines.push(format!(
            "catalog P_{{{s},{n}}}: D_MD {:.6} (Halton {:.6}), {}",
            entry.modified_l2,
            entry.start_modified_l2,
            human_seconds(entry.seconds)
        ));
        m.sets.push(entry);
        let order = catalog_cases(opts.quick);
        m.sets.sort_by_key(|e| {
            order
                .iter()
                .position(|&c| c == (e.s, e.n))
                .unwrap_or(usize::MAX)
        });
        io::write_atomic(&manifest_path, &serde_json::to_vec_pretty(m)?)?;
        Ok(())
    };
    // Sets run side by side, as many at a time as there are worker threads, largest
    // first (n²·s orders their cost): a set alone cannot keep every thread busy, and its
    // kernels use the threads the other sets leave idle. Each set's bits do not depend on
    // how many threads work on it, so this changes no output.
    let mut order = todo.clone();
    order.sort_by_key(|&(s, n)| std::cmp::Reverse(n * n * s));
    let next = AtomicUsize::new(0);
    let failed: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let running = AtomicUsize::new(rayon::current_num_threads().clamp(1, order.len().max(1)));
    std::thread::scope(|scope| -> Result<()> {
        for _ in 0..running.load(Ordering::SeqCst) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let stop = failed.lock().map_or(true, |f| f.is_some());
                    if i >= order.len() || stop {
                        break;
                    }
                    if let Err(e) = make(&order[i]) {
                        if let Ok(mut f) = failed.lock() {
                            f.get_or_insert(e);
                        }
                    }
                }
                running.fetch_sub(1, Ordering::SeqCst);
            });
        }
        // Progress lines as the sets finish.
        while running.load(Ordering::SeqCst) > 0 {
            std::thread::sleep(std::time::Duration::from_millis(200));
            flush(&shared, log)?;
        }
        Ok(())
    })?;
    flush(&shared, log)?;
    if let Some(e) = failed
        .into_inner()
        .map_err(|_| anyhow::anyhow!("catalog lock poisoned"))?
    {
        return Err(e);
    }
    let (manifest, _) = shared
        .into_inner()
        .map_err(|_| anyhow::anyhow!("catalog lock poisoned"))?;
    Ok((manifest, dir))
}

fn flush(shared: &Mutex<(Manifest, Vec<String>)>, log: &mut dyn FnMut(&str)) -> Result<()> {
    let mut guard = shared
        .lock()
        .map_err(|_| anyhow::anyhow!("catalog lock poisoned"))?;
    for line in guard.1.drain(..) {
        log(&line);
    }
    Ok(())
}

fn make_set(dir: &Path, s: usize, n: usize, steps: usize) -> Result<Entry> {
    let mut cfg = GenerateConfig::new(n, s);
    cfg.steps = steps;
    let r = run_config(&cfg, |_| {})?;
    let (m0, m1) = r.cube_metrics()?;
    let (m0, m1): (Metrics, Metrics) = (*m0, *m1);
    let choice = r.choice.clone().context("the paper's (q, p)")?;
    let file = file_name(s, n);
    let meta = json!({
        "generator": "stillpoint study catalog",
        "n": n, "s": s, "q": choice.q, "p": choice.p, "steps": steps,
        "modified_l2": m1.modified_l2, "star_l2": m1.star_l2,
    });
    io::write_points(&dir.join(&file), &r.output.points, &meta)?;
    Ok(Entry {
        s,
        n,
        file,
        q: choice.q,
        p: choice.p,
        steps: r.output.trajectory.last().map_or(0, |t| t.step),
        modified_l2: m1.modified_l2,
        star_l2: m1.star_l2,
        start_modified_l2: m0.modified_l2,
        start_star_l2: m0.star_l2,
        min_distance: m1.min_distance,
        seconds: r.seconds,
    })
}

/// Reads a catalog set back.
pub fn load_set(dir: &Path, e: &Entry) -> Result<PointSet> {
    Ok(io::read_points(&dir.join(&e.file))?)
}

pub(crate) fn run(opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<Body> {
    let (manifest, dir) = ensure(opts, log)?;
    let dims: Vec<usize> = {
        let mut d: Vec<usize> = manifest.sets.iter().map(|e| e.s).collect();
        d.dedup();
        d
    };
    let ns: Vec<usize> = CATALOG_N
        .iter()
        .copied()
        .filter(|n| manifest.sets.iter().any(|e| e.n == *n))
        .collect();
    let mut header = vec!["s \\ n".to_string()];
    header.extend(ns.iter().map(|n| n.to_string()));
    let grid = |f: &dyn Fn(&Entry) -> String| -> Vec<Vec<String>> {
        dims.iter()
            .map(|&s| {
                let mut row = vec![s.to_string()];
                for &n in &ns {
                    row.push(
                        manifest
                            .sets
                            .iter()
                            .find(|e| e.s == s && e.n == n)
                            .map_or(String::new(), f),
                    );
                }
                row
            })
            .collect()
    };
    let total: f64 = manifest.sets.iter().map(|e| e.seconds).sum();
    let better = manifest
        .sets
        .iter()
        .filter(|e| e.modified_l2 < e.start_modified_l2)
        .count();
    let mut md = format!(
        "# The catalog: {} DEM sets\n\nFiles and `manifest.json` in `{}`; {} DEM steps per set; \
         pipeline: {}.\n\nD_MD is below the Halton start's in {better} of {} sets. Sum of the \
         per-set run times: {}.\n\n## D_MD (root of eq. 47)\n\n",
        manifest.sets.len(),
        dir.display(),
        manifest.steps,
        manifest.pipeline,
        manifest.sets.len(),
        human_seconds(total)
    );
    md += &markdown_table(&header, &grid(&|e| format!("{:.5}", e.modified_l2)));
    md += "\n## D_MD relative to the Halton start\n\n";
    md += &markdown_table(
        &header,
        &grid(&|e| format!("{:.3}", e.modified_l2 / e.start_modified_l2)),
    );
    md += "\n## D_L2* (root of eq. 46)\n\n";
    md += &markdown_table(&header, &grid(&|e| format!("{:.6}", e.star_l2)));
    md += "\n## Seconds per set\n\n";
    md += &markdown_table(&header, &grid(&|e| format!("{:.1}", e.seconds)));
    Ok(Body {
        markdown: md,
        json: json!({"study": "catalog", "directory": dir, "manifest": manifest}),
        files: vec![dir.join("manifest.json")],
    })
}
