//! The paper's studies, each reproducible by one command (`stillpoint study NAME`): every
//! study writes a Markdown report with the paper's numbers beside ours, the same data as
//! JSON, and pictures where the paper has figures.
//!
//! `--quick` runs a small, honest version of each (fewer and smaller sets, fewer steps,
//! smaller Monte Carlo references) that checks the same claims in seconds; the full
//! versions are what `results/` holds.

pub mod catalog;
pub mod correlation;
pub mod regions;
pub mod table5;
pub mod table6;
pub mod uq;

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;
use stillpoint::io;

/// One of the paper's studies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Study {
    /// Tables 1–2 and Figs. 3–5: Spearman correlation of energy and discrepancy along
    /// DEM trajectories, and the final sets against the classic sequences.
    Correlation,
    /// Table 5: the four P_{s,1500} sets against every baseline and the paper's rows.
    Table5,
    /// Section 5.2: the 127 sets (s = 1..20, n ∈ {10, …, 1500}, n ≥ 2s), resumable.
    Catalog,
    /// Table 6 and Figs. 6–7: relative advantage ratios over the catalog.
    Table6,
    /// Table 7 and Fig. 8: the Kraichnan–Orszag problem with n = 200.
    KraichnanOrszag,
    /// Table 8: the 20-storey shear frame with n = 400.
    ShearFrame,
    /// Fig. 9: the four regions of eq. 58.
    Regions,
}

impl Study {
    /// Every study, in the paper's order.
    pub fn all() -> [Study; 7] {
        [
            Study::Correlation,
            Study::Table5,
            Study::Catalog,
            Study::Table6,
            Study::KraichnanOrszag,
            Study::ShearFrame,
            Study::Regions,
        ]
    }

    /// The command-line name.
    pub fn name(&self) -> &'static str {
        match self {
            Study::Correlation => "correlation",
            Study::Table5 => "table5",
            Study::Catalog => "catalog",
            Study::Table6 => "table6",
            Study::KraichnanOrszag => "kraichnan-orszag",
            Study::ShearFrame => "shear-frame",
            Study::Regions => "regions",
        }
    }

    /// Parses a command-line name.
    pub fn parse(name: &str) -> Result<Study, stillpoint::Error> {
        let t = name.trim().to_ascii_lowercase();
        Study::all()
            .into_iter()
            .find(|s| s.name() == t || (t == "table7" && *s == Study::KraichnanOrszag))
            .or_else(|| (t == "table8").then_some(Study::ShearFrame))
            .ok_or_else(|| {
                let names: Vec<&str> = Study::all().iter().map(|s| s.name()).collect();
                stillpoint::Error::invalid("study", name, format!("one of: {}", names.join(", ")))
            })
    }
}

/// How a study runs.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    /// The small version (for CI and a first look).
    pub quick: bool,
    /// Directory for the report, the JSON and the pictures (created if missing).
    pub out: PathBuf,
    /// Seed of every random choice (random starts, scrambles, Monte Carlo references).
    pub seed: u64,
    /// Where the catalog lives (the catalog study writes it, table6 reads or completes it).
    pub catalog_dir: PathBuf,
    /// Show progress bars on a terminal.
    pub progress: bool,
}

impl StudyOptions {
    /// Defaults: full size, output under `results/`, seed 0.
    pub fn new(quick: bool, out: impl Into<PathBuf>) -> Self {
        let out = out.into();
        StudyOptions {
            quick,
            catalog_dir: out.join("catalog"),
            out,
            seed: 0,
            progress: false,
        }
    }
}

/// What a study produced.
#[derive(Debug, Clone)]
pub struct StudyOutput {
    /// The Markdown report (also written to `<out>/<name>.md`).
    pub markdown: String,
    /// The same data (also written to `<out>/<name>.json`).
    pub json: serde_json::Value,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// Runs a study, writes its report, JSON and pictures under `opts.out`, and returns them.
/// `log` receives one line per finished piece of work.
pub fn run(study: Study, opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<StudyOutput> {
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("cannot create the output directory {}", opts.out.display()))?;
    let clock = Instant::now();
    let mut body = match study {
        Study::Correlation => correlation::run(opts, log)?,
        Study::Table5 => table5::run(opts, log)?,
        Study::Catalog => catalog::run(opts, log)?,
        Study::Table6 => table6::run(opts, log)?,
        Study::KraichnanOrszag => uq::run_kraichnan_orszag(opts, log)?,
        Study::ShearFrame => uq::run_shear_frame(opts, log)?,
        Study::Regions => regions::run(opts, log)?,
    };
    let seconds = clock.elapsed().as_secs_f64();
    let command = format!(
        "stillpoint study {}{}",
        study.name(),
        if opts.quick { " --quick" } else { "" }
    );
    let markdown = format!(
        "{}\n\nMade by `{}` (seed {}) in {} on {} thread(s), stillpoint {}.\n",
        body.markdown.trim_end(),
        command,
        opts.seed,
        human_seconds(seconds),
        rayon::current_num_threads(),
        env!("CARGO_PKG_VERSION")
    );
    if let serde_json::Value::Object(map) = &mut body.json {
        map.insert("command".into(), command.clone().into());
        map.insert("seconds".into(), seconds.into());
        map.insert("seed".into(), opts.seed.into());
        map.insert("quick".into(), opts.quick.into());
    }
    let md_path = opts.out.join(format!("{}.md", study.name()));
    let json_path = opts.out.join(format!("{}.json", study.name()));
    io::write_atomic(&md_path, markdown.as_bytes())?;
    io::write_atomic(&json_path, &serde_json::to_vec_pretty(&body.json)?)?;
    body.files.push(md_path);
    body.files.push(json_path);
    Ok(StudyOutput {
        markdown,
        json: body.json,
        files: body.files,
        seconds,
    })
}

/// A study's own output before the common footer.
pub(crate) struct Body {
    pub markdown: String,
    pub json: serde_json::Value,
    pub files: Vec<PathBuf>,
}

/// "12.3 s", "4 min 05 s" or "1 h 02 min": the library's one writing of a duration.
pub use stillpoint::pipeline::dispatch::human_seconds;

/// A Markdown table.
pub fn markdown_table(headers: &[String], rows: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n", headers.join(" | "));
    out += &format!("|{}\n", "---|".repeat(headers.len()));
    for r in rows {
        out += &format!("| {} |\n", r.join(" | "));
    }
    out
}

/// Spearman's rank correlation of two equally long samples: Pearson's correlation of the
/// ranks, tied values sharing their average rank. `None` for fewer than two values, a
/// length mismatch, a non-finite value, or a constant sample (the coefficient is
/// undefined there, not zero).
pub fn spearman(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.len() < 2 || a.iter().chain(b).any(|v| !v.is_finite()) {
        return None;
    }
    let (ra, rb) = (ranks(a), ranks(b));
    let n = a.len() as f64;
    let (ma, mb) = (ra.iter().sum::<f64>() / n, rb.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in ra.iter().zip(&rb) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    (saa > 0.0 && sbb > 0.0).then(|| sab / (saa * sbb).sqrt())
}

/// Average ranks (1-based) with ties sharing the mean of their positions.
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
    let mut r = vec![0.0; v.len()];
    let mut k = 0;
    while k < idx.len() {
        let mut m = k;
        while m + 1 < idx.len() && v[idx[m + 1]] == v[idx[k]] {
            m += 1;
        }
        let avg = (k + m) as f64 / 2.0 + 1.0;
        for &i in &idx[k..=m] {
            r[i] = avg;
        }
        k = m + 1;
    }
    r
}

/// Formats a number with `d` decimals, or "—" when absent or not finite.
pub(crate) fn fmt_opt(v: Option<f64>, d: usize) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.d$}"),
        _ => "—".to_string(),
    }
}

/// A percentage with one decimal.
pub(crate) fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{:.1}%", 100.0 * v)
    } else {
        "—".to_string()
    }
}

/// A percentage with two decimals (relative errors of Tables 7–8).
pub(crate) fn pct2(v: f64) -> String {
    if v.is_finite() {
        format!("{:.2}%", 100.0 * v)
    } else {
        "—".to_string()
    }
}

/// Saves line charts and records the file.
pub(crate) fn save_charts(
    path: &Path,
    charts: &[stillpoint_plot::LineChart],
    files: &mut Vec<PathBuf>,
) -> Result<()> {
    stillpoint_plot::save_line_charts(path, charts)?;
    files.push(path.to_path_buf());
    Ok(())
}
