//! Solver comparison: the DEM and L-BFGS, each on U_{q,p} and on a squared discrepancy,
//! from the same Halton start, with the quality of each result and its convergence
//! against wall time. Behind `stillpoint compare` and `examples/solver_comparison.rs`.

use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;
use stillpoint::config::{EnergyKind, GenerateConfig};
use stillpoint::energies::discrepancy::DiscrepancyKind;
use stillpoint::pipeline::run_config;
use stillpoint::quality::metrics;
use stillpoint::solve::Solver;
use stillpoint_plot::{self as plot, LineChart, Series};

/// The paper's cases (Table 5) and two smaller ones: (s, n).
pub const DEFAULT_CASES: [(usize, usize); 6] = [
    (2, 1500),
    (3, 1500),
    (5, 1500),
    (6, 1500),
    (5, 200),
    (10, 400),
];

/// Table 5 for the P_{s,1500} cases: (s, U_{q,p} row D_MD, D_L2, best D_MD, best D_L2).
pub const TABLE5: [(usize, f64, f64, f64, f64); 4] = [
    (2, 0.000932, 0.000652, 0.000932, 0.000652),
    (3, 0.001986, 0.000965, 0.001986, 0.000965),
    (5, 0.006092, 0.001262, 0.005787, 0.001262),
    (6, 0.009814, 0.001177, 0.009203, 0.001177),
];

/// One run of the comparison.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CompareRow {
    /// Dimension.
    pub s: usize,
    /// Number of points.
    pub n: usize,
    /// `DEM` or `L-BFGS`.
    pub solver: String,
    /// The energy minimised.
    pub energy: String,
    /// Final energy.
    pub final_energy: f64,
    /// Modified L2 discrepancy of the result (root).
    pub modified_l2: f64,
    /// Star L2 discrepancy of the result (root).
    pub star_l2: f64,
    /// Smallest Euclidean distance of the result.
    pub min_distance: f64,
    /// Steps or iterations taken.
    pub steps: usize,
    /// Wall time in seconds.
    pub seconds: f64,
    /// (seconds, energy / start energy, D_MD where logged) along the run.
    pub curve: Vec<(f64, f64, Option<f64>)>,
}

/// What to compare.
#[derive(Debug, Clone)]
pub struct CompareSettings {
    /// (s, n) cases.
    pub cases: Vec<(usize, usize)>,
    /// Step (DEM) or iteration (L-BFGS) budget per run.
    pub steps: usize,
    /// Log D_MD every this many steps.
    pub log_every: usize,
    /// The discrepancy used as the second energy.
    pub discrepancy: DiscrepancyKind,
}

impl Default for CompareSettings {
    fn default() -> Self {
        CompareSettings {
            cases: DEFAULT_CASES.to_vec(),
            steps: 1000,
            log_every: 10,
            discrepancy: DiscrepancyKind::ModifiedL2,
        }
    }
}

/// Runs every case with both solvers on both energies, calling `on_row` as rows finish.
pub fn run(
    settings: &CompareSettings,
    mut on_row: impl FnMut(&CompareRow),
) -> Result<Vec<CompareRow>> {
    let mut rows = Vec::new();
    for &(s, n) in &settings.cases {
        for energy in [
            EnergyKind::Uqp,
            EnergyKind::Discrepancy(settings.discrepancy),
        ] {
            for solver in [Solver::Dem, Solver::Lbfgs] {
                let mut cfg = GenerateConfig::new(n, s);
                cfg.energy = energy;
                cfg.solver = solver;
                cfg.steps = settings.steps;
                cfg.log_every = settings.log_every;
                let r = run_config(&cfg, |_| {})?;
                let e0 = r.energy.0;
                let curve = r
                    .output
                    .trajectory
                    .iter()
                    .map(|rec| {
                        let md = rec
                            .metrics
                            .iter()
                            .find(|(k, _)| k == "modified_l2")
                            .map(|(_, v)| *v);
                        (rec.seconds, rec.energy / e0, md)
                    })
                    .collect();
                let row = CompareRow {
                    s,
                    n,
                    solver: match solver {
                        Solver::Dem => "DEM".into(),
                        Solver::Lbfgs => "L-BFGS".into(),
                    },
                    energy: r.energy_name.clone(),
                    final_energy: r.energy.1,
                    modified_l2: metrics::modified_l2(&r.output.points),
                    star_l2: metrics::star_l2(&r.output.points),
                    min_distance: metrics::min_distance_euclidean(&r.output.points),
                    steps: r
                        .output
                        .trajectory
                        .iter()
                        .map(|t| t.step)
                        .max()
                        .unwrap_or(0),
                    seconds: r.seconds,
                    curve,
                };
                on_row(&row);
                rows.push(row);
                if energy == EnergyKind::Uqp && solver == Solver::Dem {
                    // The DEM result (after its shift selection) polished by L-BFGS on the
                    // discrepancy: the best points the library makes.
                    let row = polish_row(settings, s, n, &r.output.points, r.seconds)?;
                    on_row(&row);
                    rows.push(row);
                }
            }
        }
    }
    Ok(rows)
}

/// The rows as a Markdown table, with Table 5's numbers where the paper has them.
pub fn markdown(rows: &[CompareRow]) -> String {
    let mut t = String::from(
        "| s | n | solver | energy | final energy | D_MD | D_L2* | min distance | steps | seconds |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {:.6e} | {:.6} | {:.6} | {:.6} | {} | {:.1} |",
            r.s,
            r.n,
            r.solver,
            r.energy,
            r.final_energy,
            r.modified_l2,
            r.star_l2,
            r.min_distance,
            r.steps,
            r.seconds
        );
        let last_of_case = rows
            .iter()
            .rposition(|x| (x.s, x.n) == (r.s, r.n))
            .is_some_and(|k| std::ptr::eq(&rows[k], r));
        if last_of_case && r.n == 1500 {
            if let Some(p) = TABLE5.iter().find(|p| p.0 == r.s) {
                let _ = writeln!(
                    t,
                    "| {} | {} | paper | U_{{q,p}} row of Table 5 | | {:.6} | {:.6} | | | |\n\
                     | {} | {} | paper | best row of Table 5 | | {:.6} | {:.6} | | | |",
                    r.s, r.n, p.1, p.2, r.s, r.n, p.3, p.4
                );
            }
        }
    }
    t
}

/// Per case, a picture of energy / start energy and D_MD against wall time.
pub fn save_pictures(dir: &Path, rows: &[CompareRow]) -> Result<()> {
    let mut cases: Vec<(usize, usize)> = rows.iter().map(|r| (r.s, r.n)).collect();
    cases.dedup();
    for (s, n) in cases {
        let these: Vec<&CompareRow> = rows.iter().filter(|r| (r.s, r.n) == (s, n)).collect();
        let name = |r: &CompareRow| {
            format!(
                "{} on {}",
                r.solver,
                r.energy.split('(').next().unwrap_or("")
            )
        };
        let energy = LineChart {
            title: format!("P_{{{s},{n}}}: energy / start energy"),
            x_label: "wall time (s)".into(),
            y_label: "U / U(start)".into(),
            log_y: true,
            series: these
                .iter()
                .map(|r| Series {
                    name: name(r),
                    points: r.curve.iter().map(|c| (c.0, c.1)).collect(),
                })
                .collect(),
        };
        let md = LineChart {
            title: format!("P_{{{s},{n}}}: modified L2 discrepancy"),
            x_label: "wall time (s)".into(),
            y_label: "D_MD".into(),
            log_y: true,
            series: these
                .iter()
                .map(|r| Series {
                    name: name(r),
                    points: r
                        .curve
                        .iter()
                        .filter_map(|c| c.2.map(|m| (c.0, m)))
                        .collect(),
                })
                .collect(),
        };
        plot::save_line_charts(
            &dir.join(format!("convergence_s{s}_n{n}.png")),
            &[energy, md],
        )?;
    }
    Ok(())
}

/// Runs a comparison and writes `comparison.md`, `comparison.json` and the pictures into
/// `dir`; returns the Markdown table.
pub fn run_and_write(settings: &CompareSettings, dir: &Path, verbose: bool) -> Result<String> {
    std::fs::create_dir_all(dir).map_err(|e| {
        anyhow::anyhow!(
            "invalid output folder {}: cannot create it ({e}); expected a folder or a new name",
            dir.display()
        )
    })?;
    let rows = run(settings, |r| {
        if verbose {
            eprintln!(
                "P_{{{},{}}} {} on {}: D_MD {:.6}, D_L2* {:.6}, {:.1} s",
                r.s, r.n, r.solver, r.energy, r.modified_l2, r.star_l2, r.seconds
            );
        }
    })?;
    let table = markdown(&rows);
    stillpoint::io::write_atomic(&dir.join("comparison.md"), table.as_bytes())?;
    stillpoint::io::write_atomic(
        &dir.join("comparison.json"),
        &serde_json::to_vec_pretty(&rows)?,
    )?;
    save_pictures(dir, &rows)?;
    Ok(table)
}

/// L-BFGS on the settings' discrepancy from `points`, as a comparison row.
fn polish_row(
    settings: &CompareSettings,
    s: usize,
    n: usize,
    points: &stillpoint::PointSet,
    seconds_before: f64,
) -> Result<CompareRow> {
    use stillpoint::energies::discrepancy::DiscrepancyEnergy;
    use stillpoint::energies::Energy;
    let clock = std::time::Instant::now();
    let e = DiscrepancyEnergy::new(settings.discrepancy);
    let p = stillpoint::post::polish::polish(
        points,
        settings.discrepancy,
        settings.steps,
        &stillpoint::integrators::lbfgs::Lbfgs::default(),
        |_| {},
    )?;
    let seconds = seconds_before + clock.elapsed().as_secs_f64();
    Ok(CompareRow {
        s,
        n,
        solver: "DEM + L-BFGS polish".into(),
        energy: e.name(),
        final_energy: e.value(&p.points),
        modified_l2: metrics::modified_l2(&p.points),
        star_l2: metrics::star_l2(&p.points),
        min_distance: metrics::min_distance_euclidean(&p.points),
        steps: p.iterations,
        seconds,
        curve: p
            .trajectory
            .iter()
            .map(|rec| (seconds_before + rec.seconds, f64::NAN, None))
            .collect(),
    })
}
