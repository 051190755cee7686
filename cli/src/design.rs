//! A design space's outputs on the command line: the labelled table (CSV or TSV; numeric
//! formats only for a space without labels), the design's figures as a table or JSON,
//! and `eval --space` of a labelled file.

use super::*;
use stillpoint::design::figures::DesignFigures;
use stillpoint::design::{Design, DesignSpace};
use stillpoint::quality::metrics::Sums;

/// Refuses, before any work, an output format that cannot hold the space's labels.
pub(crate) fn check_design_output(space: &DesignSpace, output: Option<&PathBuf>) -> Result<()> {
    let Some(path) = output else { return Ok(()) };
    let format = io::Format::from_path(path);
    if space.has_labels() && !matches!(format, io::Format::Csv | io::Format::Tsv) {
        bail!(
            "invalid -o {}: a design with levels is written as .csv or .tsv (its labels are \
             text; .npy and .json hold numbers)",
            path.display()
        );
    }
    Ok(())
}

/// Writes the design (to `output`, or as CSV to standard output) and its figures (a
/// table on standard output, or standard error when the points went there; or JSON).
/// `sums` says whether its pair figures are exact (the run's `--exact`) or follow the
/// report's rule.
pub(crate) fn emit_design(
    design: &Design,
    sums: Sums,
    meta: &Value,
    run_line: &str,
    output: Option<&PathBuf>,
    json_out: bool,
    staging: io::Staging,
) -> Result<()> {
    // The figures are those of the values as written (and read back by `eval`): a value
    // rounded to a float, a correlated column decorrelated again.
    let figures = DesignFigures::of_with(&design.as_written()?, sums);
    // The header describes the written design: the unit-cube set's metrics would not.
    let mut meta = meta.clone();
    if let Some(m) = meta.as_object_mut() {
        m.remove("metrics");
        m.insert("figures".into(), json!(figures));
    }
    let meta = &meta;
    if let Some(path) = output {
        let bytes = match io::Format::from_path(path) {
            io::Format::Csv => design.to_text(meta, ',').into_bytes(),
            io::Format::Tsv => design.to_text(meta, '\t').into_bytes(),
            other => io::encode(&design.numbers()?, meta, other),
        };
        io::write_atomic(path, &bytes)?;
    }
    staging.commit()?;
    if json_out {
        let mut v = json!({"run": run_line, "figures": figures});
        record(&mut v, [(Opt::space, json!(design.space.texts()))]);
        if let Some(c) = design.space.correlation_text() {
            record(&mut v, [(Opt::correlation, json!(c))]);
        }
        if output.is_none() {
            v["rows"] = Value::String(design.to_text(&Value::Null, ','));
        }
        outln!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    let table = design_table(design, &figures, run_line);
    match output {
        Some(_) => out!("{table}"),
        None => {
            out!("{}", design.to_text(meta, ','));
            note!("{table}");
        }
    }
    Ok(())
}

/// The figures as a table: level counts, pair balance, slices, the continuous part.
pub(crate) fn design_table(design: &Design, f: &DesignFigures, run_line: &str) -> String {
    let texts = design.space.texts();
    // A path is one variable written as m columns: both counts, where they differ.
    let columns = match design.space.dim() {
        d if d == texts.len() => String::new(),
        d => format!(", {d} columns"),
    };
    let mut t = format!(
        "stillpoint: design of {} points in {} variables{columns} ({}); figures on the unit \
         scale (continuous values through their CDF)\n",
        f.n,
        texts.len(),
        texts.join(" ")
    );
    if !run_line.is_empty() {
        t.push_str(&format!("  {run_line}\n"));
    }
    for l in &f.levels {
        t.push_str(&format!(
            "  levels of {:<12} {}  (largest excess over ⌊n/L⌋..⌈n/L⌉: {})\n",
            l.name,
            level_counts(l),
            l.excess
        ));
    }
    for p in &f.pairs {
        t.push_str(&format!(
            "  pairs {} × {}: largest excess over ⌊n/(L_a L_b)⌋..⌈n/(L_a L_b)⌉: {}\n",
            p.names.0, p.names.1, p.excess
        ));
    }
    for s in &f.slices {
        match mean_max(&s.centered_l2) {
            Some((mean, max)) => t.push_str(&format!(
                "  slices of {}: stratified in {} of {} (slice, continuous column); centred \
                 L2 per slice mean {:.6}, max {:.6}{}\n",
                s.name,
                s.stratified,
                s.columns,
                mean,
                max,
                s.centered_l2_errors
                    .as_ref()
                    .map_or(String::new(), |e| format!(
                        " (estimated from random pairs, standard errors up to {:.1e})",
                        e.iter().cloned().fold(0.0, f64::max)
                    ))
            )),
            None => t.push_str(&format!(
                "  slices of {}: no continuous column to stratify within its levels\n",
                s.name
            )),
        }
    }
    if f.continuous > 0 {
        t.push_str(&format!(
            "  continuous part: stratified in {} of {} columns; centred L2 {}\n",
            f.stratified,
            f.continuous,
            match (
                f.centered_l2,
                f.estimate.as_ref().and_then(|e| e.centered_l2_error)
            ) {
                (None, _) => "-".into(),
                (Some(v), None) => format!("{v:.6}"),
                (Some(v), Some(e)) => format!(
                    "{v:.6} ± {e:.1e} (estimated from {} random pairs)",
                    f.estimate.as_ref().map_or(0, |e| e.pairs)
                ),
            }
        ));
    }
    if f.n > 1 {
        t.push_str(&format!(
            "  minimum distance (unit scale; levels by rank, unordered levels 0/1): {}\n",
            if f.min_distance.is_nan() {
                "not computed (above the exact size the grid of cells could not prove it; \
                 --exact computes it over every pair)"
                    .to_string()
            } else {
                format!("{:.6}", f.min_distance)
            }
        ));
    } else {
        t.push_str("  minimum distance: none (a single point has no pair)\n");
    }
    t
}

/// The most level counts a table line lists one by one; past it, a summary (a line per
/// level of `int(0,1000000)` would be megabytes long).
const MAX_COUNTS_SHOWN: usize = 32;

/// A variable's level counts as one line of bounded length.
fn level_counts(l: &stillpoint::design::figures::LevelCounts) -> String {
    match &l.counts {
        Some(counts) if counts.len() <= MAX_COUNTS_SHOWN => counts
            .iter()
            .map(|c| c.to_string())
            .collect::<Vec<_>>()
            .join(" "),
        _ => format!(
            "{} levels, {} taken, counts {} to {}",
            l.levels, l.taken, l.least, l.most
        ),
    }
}

/// The mean and largest of the slices' figures; `None` without any (no continuous
/// column), never NaN.
fn mean_max(v: &[f64]) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    Some((
        v.iter().sum::<f64>() / v.len() as f64,
        v.iter().cloned().fold(f64::MIN, f64::max),
    ))
}

/// `stillpoint eval --var ... FILE` (or `--space`): each labelled file read back onto
/// the unit scale and measured as a design.
/// `sums` as [`emit_design`]'s (`eval --exact`).
pub(crate) fn design_eval(
    files: &[PathBuf],
    json_out: bool,
    space: &DesignSpace,
    sums: Sums,
) -> Result<()> {
    let mut all = Vec::new();
    for file in files {
        let source = file.display().to_string();
        let design = match io::Format::from_path(file) {
            // The numeric formats hold a space without labels, one column per variable.
            io::Format::Npy | io::Format::Json => {
                Design::from_numbers(space, &io::read_points(file)?, &source)?
            }
            _ => {
                let bytes = io::read_bounded(file).with_context(|| source.clone())?;
                if bytes.starts_with(b"\x93NUMPY") {
                    Design::from_numbers(space, &io::read_points(file)?, &source)?
                } else {
                    let text = String::from_utf8(bytes).map_err(|_| {
                        anyhow::anyhow!(
                            "invalid {source}: not UTF-8 text (expected a design as .csv or \
                             .tsv, or .npy or .json for a space without labels)"
                        )
                    })?;
                    Design::from_text(space, &text, &source)?
                }
            }
        };
        let figures = DesignFigures::of_with(&design, sums);
        if json_out {
            all.push(json!({"file": file.display().to_string(), "figures": figures}));
        } else {
            out!(
                "{}: {}",
                file.display(),
                design_table(&design, &figures, "")
            );
        }
    }
    if json_out {
        let v = if all.len() == 1 {
            all.remove(0)
        } else {
            Value::Array(all)
        };
        outln!("{}", serde_json::to_string_pretty(&v)?);
    }
    Ok(())
}
