//! Table 6 and Figs. 6–7: over the catalog, how often each baseline beats the DEM set of
//! the same (n, s) at integrating F1–F8 and in D_MD and D_L2* (the relative advantage
//! ratio, RAR), and the per-set discrimination coefficients b1, b2 of eq. 50.

use super::catalog;
use super::{markdown_table, pct, save_charts, Body, StudyOptions};
use anyhow::Result;
use serde_json::json;
use stillpoint::quality::integrands as testfns;
use stillpoint::quality::metrics;
use stillpoint::sequences::Baseline;
use stillpoint_plot::{LineChart, Series};

/// The paper's Table 6: RAR of each method over F1..F8, D_MD, D_L2.
const PAPER_TABLE6: [(&str, [f64; 10]); 5] = [
    (
        "HS",
        [22.0, 26.0, 37.0, 42.5, 51.2, 52.0, 49.6, 29.1, 3.1, 24.4],
    ),
    (
        "HSO",
        [22.8, 15.7, 29.1, 52.8, 56.7, 63.0, 67.7, 36.2, 10.2, 18.9],
    ),
    (
        "SS",
        [1.6, 2.4, 8.7, 50.4, 44.9, 43.3, 48.0, 27.6, 0.8, 22.0],
    ),
    (
        "HW",
        [4.7, 5.5, 5.5, 40.9, 50.4, 58.3, 48.8, 32.3, 1.6, 23.6],
    ),
    (
        "Halton",
        [0.0, 0.0, 0.0, 56.7, 61.4, 45.7, 58.3, 28.3, 0.0, 0.0],
    ),
];

/// The ten error measures of a set: |F1..F8 estimates| then D_MD, D_L2*. `None` where a
/// test function is not defined (F8 with s = 1).
fn measures(points: &stillpoint::PointSet) -> Result<[Option<f64>; 10]> {
    let rep = testfns::integrate(points)?;
    let (l2, md) = metrics::discrepancies(points);
    let mut out = [None; 10];
    for (k, e) in rep.estimates.iter().enumerate() {
        out[k] = e.map(f64::abs);
    }
    out[8] = Some(md);
    out[9] = Some(l2);
    Ok(out)
}

/// sgn(a − b) with a tie as 0.
fn sign(a: f64, b: f64) -> i32 {
    if a > b {
        1
    } else if a < b {
        -1
    } else {
        0
    }
}

pub(crate) fn run(opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<Body> {
    let (manifest, dir) = catalog::ensure(opts, log)?;
    let sets = &manifest.sets;
    let dem: Vec<[Option<f64>; 10]> = sets
        .iter()
        .map(|e| catalog::load_set(&dir, e).and_then(|p| measures(&p)))
        .collect::<Result<_>>()?;
    let names = [
        "F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8", "D_MD", "D_L2*",
    ];
    let mut header = vec!["baseline".to_string()];
    header.extend(names.iter().map(|s| s.to_string()));
    let mut rows = vec![];
    let mut json_rows = vec![];
    let mut fig6 = vec![];
    let mut fig7 = vec![];
    let mut b_summary = vec![];
    for b in Baseline::all() {
        let mut wins = [0usize; 10];
        let mut counted = [0usize; 10];
        let mut b1s = vec![];
        let mut b2s = vec![];
        for (k, e) in sets.iter().enumerate() {
            let pts = b.generate(e.n, e.s, opts.seed)?;
            let m = measures(&pts)?;
            let (mut b1, mut b2) = (0i32, 0i32);
            for i in 0..10 {
                if let (Some(x), Some(y)) = (m[i], dem[k][i]) {
                    counted[i] += 1;
                    if x < y {
                        wins[i] += 1;
                    }
                    if i < 8 {
                        b1 += sign(x, y);
                    } else {
                        b2 += sign(x, y);
                    }
                }
            }
            b1s.push((k as f64 + 1.0, b1 as f64));
            b2s.push((k as f64 + 1.0, b2 as f64));
        }
        let rar: Vec<f64> = (0..10)
            .map(|i| {
                if counted[i] == 0 {
                    f64::NAN
                } else {
                    wins[i] as f64 / counted[i] as f64
                }
            })
            .collect();
        let mut row = vec![format!("{} (ours)", b.label())];
        row.extend(rar.iter().map(|r| pct(*r)));
        rows.push(row);
        if let Some((name, vals)) = PAPER_TABLE6.iter().find(|(l, _)| *l == b.label()) {
            let mut row = vec![format!("{name} (paper)")];
            row.extend(vals.iter().map(|v| format!("{v:.1}%")));
            rows.push(row);
        }
        let count = |v: &[(f64, f64)], f: fn(f64) -> bool| v.iter().filter(|p| f(p.1)).count();
        b_summary.push(vec![
            b.label().to_string(),
            count(&b1s, |x| x > 0.0).to_string(),
            count(&b1s, |x| x == 0.0).to_string(),
            count(&b1s, |x| x < 0.0).to_string(),
            count(&b2s, |x| x > 0.0).to_string(),
            count(&b2s, |x| x == 0.0).to_string(),
            count(&b2s, |x| x < 0.0).to_string(),
        ]);
        json_rows.push(json!({
            "baseline": b.name(), "label": b.label(),
            "rar": rar.iter().map(|r| if r.is_finite() { Some(*r) } else { None }).collect::<Vec<_>>(),
            "b1": b1s.iter().map(|p| p.1).collect::<Vec<_>>(),
            "b2": b2s.iter().map(|p| p.1).collect::<Vec<_>>(),
        }));
        if matches!(
            b,
            Baseline::ScrambledHalton | Baseline::Sobol | Baseline::HuaWang
        ) {
            fig6.push(LineChart {
                title: format!("b1: {} against the DEM (> 0: DEM better)", b.label()),
                x_label: "set (catalog order)".into(),
                y_label: "b1".into(),
                log_y: false,
                series: vec![Series {
                    name: "b1".into(),
                    points: b1s.clone(),
                }],
            });
            fig7.push(LineChart {
                title: format!("b2: {} against the DEM (> 0: DEM better)", b.label()),
                x_label: "set (catalog order)".into(),
                y_label: "b2".into(),
                log_y: false,
                series: vec![Series {
                    name: "b2".into(),
                    points: b2s.clone(),
                }],
            });
        }
        log(&format!(
            "table6 {}: RAR {:?}",
            b.label(),
            rar.iter().map(|r| pct(*r)).collect::<Vec<_>>()
        ));
    }
    let mut files = vec![];
    save_charts(&opts.out.join("fig6_b1.png"), &fig6, &mut files)?;
    save_charts(&opts.out.join("fig7_b2.png"), &fig7, &mut files)?;
    let mut md = format!(
        "# Table 6: relative advantage ratios over the catalog ({} sets)\n\n",
        sets.len()
    );
    md += &format!(
        "RAR of a baseline for a measure = the fraction of the catalog's sets (same n and s) \
         where the baseline's error is strictly smaller than the DEM set's. Errors: |QMC \
         estimate of ∫F_i| (every exact integral is 0; F8 as corrected in DESIGN.md) and D_MD, \
         D_L2* themselves. A RAR below 50 % means the DEM set is more accurate more often. \
         Randomized baselines use one draw (seed {}), as the paper does. The paper's HSO \
         (optimised generalised Halton) is not among our baselines; its row is shown for \
         reference.\n\n",
        opts.seed
    );
    md += &markdown_table(&header, &rows);
    md += "\n## Discrimination coefficients (eq. 50, Figs. 6–7)\n\n";
    md += "b1 = Σ_{i=1..8} sgn(|error of the baseline on F_i| − |error of the DEM set on F_i|), \
           b2 the same over (D_MD, D_L2*); so b > 0 means the DEM set is more accurate on more \
           of the measures. (The paper's sentence after eq. 50 says b1 > 0 means the baseline \
           is more accurate more often; by its own formula a positive term means the \
           baseline's error is the larger one, which is the reading used here.) Number of sets with b > 0, \
           b = 0, b < 0:\n\n";
    md += &markdown_table(
        &[
            "baseline", "b1 > 0", "b1 = 0", "b1 < 0", "b2 > 0", "b2 = 0", "b2 < 0",
        ]
        .map(String::from),
        &b_summary,
    );
    md += "\nFig. 6 (b1 per set): [fig6_b1.png](fig6_b1.png); Fig. 7 (b2 per set): \
           [fig7_b2.png](fig7_b2.png).\n";
    Ok(Body {
        markdown: md,
        json: json!({"study": "table6", "sets": sets.len(), "measures": names, "baselines": json_rows,
                     "catalog": dir}),
        files,
    })
}
