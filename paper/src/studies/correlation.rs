//! Tables 1–2 and Figs. 3–5: along DEM trajectories from a random start, how closely the
//! energy (U_{1,1} or U_{E,∞}) tracks the discrepancies D_L2* and D_MD (Spearman's ρ), and
//! how the final sets compare with the classic sequences.

use super::{fmt_opt, markdown_table, save_charts, spearman, Body, StudyOptions};
use anyhow::Result;
use serde_json::json;
use stillpoint::config::{EnergyKind, GenerateConfig, Init};
use stillpoint::energies::einf::UEInf;
use stillpoint::energies::{Distance, Energy, PointSet, Uqp};
use stillpoint::pipeline::run_config;
use stillpoint::quality::metrics;
use stillpoint::sequences::Baseline;
use stillpoint_plot::{LineChart, Series};

/// Table 1 (s = 2, by n) of the paper: ρ_{1,L2}, ρ_{1,MD}, ρ_{E,L2}, ρ_{E,MD}.
const PAPER_T1: [(usize, [f64; 4]); 6] = [
    (10, [0.9970, 0.9995, 0.8930, 0.8917]),
    (20, [-0.6550, -0.0441, 0.9485, 0.9460]),
    (40, [-0.8378, -0.8290, 0.7048, 0.6971]),
    (80, [0.9342, 0.9544, 0.6885, 0.6968]),
    (160, [0.5750, 0.5700, 0.7953, 0.9733]),
    (320, [0.9625, 0.9495, 0.7639, 0.9547]),
];

/// Table 2 (n = 100, by s).
const PAPER_T2: [(usize, [f64; 4]); 5] = [
    (2, [0.8128, 0.8387, 0.7484, 0.8005]),
    (4, [0.5967, 0.8786, 0.8488, 0.8679]),
    (6, [0.6048, 0.8814, 0.9386, 0.9470]),
    (8, [0.9629, 0.9944, 0.9320, 0.9898]),
    (10, [0.6343, 0.7849, 0.9625, 0.9855]),
];

/// One DEM run's trajectory: energy, D_L2*, D_MD at every step, and the final set.
struct Trajectory {
    steps: Vec<f64>,
    energy: Vec<f64>,
    star: Vec<f64>,
    modified: Vec<f64>,
    points: PointSet,
}

fn trajectory(n: usize, s: usize, einf: bool, steps: usize, seed: u64) -> Result<Trajectory> {
    let mut cfg = GenerateConfig::new(n, s);
    cfg.init = Init::Random;
    cfg.seed = seed;
    cfg.steps = steps;
    cfg.log_every = 1;
    // The trajectory itself is studied: no shift selection after it.
    cfg.shifts = 0;
    if einf {
        cfg.energy = EnergyKind::EInf;
        cfg.q = Some(Distance::Euclidean);
    } else {
        cfg.energy = EnergyKind::Uqp;
        cfg.q = Some(Distance::Q(1.0));
        cfg.p = Some(1.0);
    }
    let report = run_config(&cfg, |_| {})?;
    let mut t = Trajectory {
        steps: vec![],
        energy: vec![],
        star: vec![],
        modified: vec![],
        points: report.output.points.clone(),
    };
    for r in &report.output.trajectory {
        let get = |k: &str| r.metrics.iter().find(|(m, _)| m == k).map(|(_, v)| *v);
        if let (Some(l2), Some(md)) = (get("star_l2"), get("modified_l2")) {
            t.steps.push(r.step as f64);
            t.energy.push(r.energy);
            t.star.push(l2);
            t.modified.push(md);
        }
    }
    Ok(t)
}

impl Trajectory {
    /// Number of leading records in which the energy does most of its fall: up to the
    /// first step where U − U_end ≤ 10⁻³ (U_0 − U_end), at least 10 records. After it the
    /// energy moves by rounding-size amounts while restarts (periodic shifts, which leave
    /// U unchanged) still move the discrepancies, so ranks there are noise.
    fn active_len(&self) -> usize {
        let (Some(&u0), Some(&u1)) = (self.energy.first(), self.energy.last()) else {
            return 0;
        };
        let fall = u0 - u1;
        let k = self
            .energy
            .iter()
            .position(|&u| u - u1 <= 1e-3 * fall)
            .unwrap_or(self.energy.len());
        (k + 1).max(10).min(self.energy.len())
    }

    /// ρ(energy, D_L2*) and ρ(energy, D_MD) over the first `len` records.
    fn rho(&self, len: usize) -> [Option<f64>; 2] {
        [
            spearman(&self.energy[..len], &self.star[..len]),
            spearman(&self.energy[..len], &self.modified[..len]),
        ]
    }
}

/// The four uniformity indexes of Figs. 4–5 for a set.
fn indexes(points: &PointSet) -> Result<[f64; 4]> {
    let (l2, md) = metrics::discrepancies(points);
    let u11 = Uqp::new(Distance::Q(1.0), 1.0)?.value(points);
    let ue = UEInf::new(Distance::Euclidean)?.value(points);
    Ok([l2, md, u11, ue])
}

pub(crate) fn run(opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<Body> {
    let (ns, ss, steps, n2): (Vec<usize>, Vec<usize>, usize, usize) = if opts.quick {
        (vec![10, 20, 40], vec![2, 4], 200, 40)
    } else {
        (
            vec![10, 20, 40, 80, 160, 320],
            vec![2, 4, 6, 8, 10],
            1000,
            100,
        )
    };
    let mut files = vec![];
    let mut json_cases = vec![];
    let mut md = String::from(
        "# Correlation of energy and discrepancy along DEM trajectories (Tables 1–2, Figs. 3–5)\n\n",
    );
    md += &format!(
        "Each set starts from uniform random points (seed {}) and runs {steps} DEM steps twice: \
         once on U_{{1,1}} (the q-distance of eq. 11, q = p = 1, periodic cube) and once on \
         U_{{E,∞}} (Euclidean distance, closed cube: the maximin energy). At every step D_L2* \
         and D_MD (roots of eqs. 46–47) are computed; ρ is Spearman's rank correlation of the \
         energy with each discrepancy over the trajectory. No shift selection is applied. \
         Paper values in parentheses.\n\n",
        opts.seed
    );
    let baselines = [
        Baseline::Random,
        Baseline::Halton,
        Baseline::ScrambledHalton,
        Baseline::Sobol,
        Baseline::HuaWang,
    ];
    for (title, cases, paper) in [
        (
            format!("Table 1: s = 2, n ∈ {ns:?}"),
            ns.iter().map(|&n| (n, 2)).collect::<Vec<_>>(),
            &PAPER_T1[..],
        ),
        (
            format!("Table 2: n = {n2}, s ∈ {ss:?}"),
            ss.iter().map(|&s| (n2, s)).collect::<Vec<_>>(),
            &PAPER_T2[..],
        ),
    ] {
        let text = table(
            &title,
            &cases,
            paper,
            opts,
            steps,
            &baselines,
            log,
            &mut files,
            &mut json_cases,
        )?;
        md += &text;
    }
    md += "Fig. 3 (the evolution of P_{2,20}): [fig3_p2_20.png](fig3_p2_20.png).\n";
    Ok(Body {
        markdown: md,
        json: json!({"study": "correlation", "cases": json_cases}),
        files,
    })
}

/// One table of the study (by n or by s): the correlations over the whole trajectory and
/// over its active phase, the final sets against the classic sequences, and the figure;
/// returns its markdown.
#[allow(clippy::too_many_arguments)]
fn table(
    title: &str,
    cases: &[(usize, usize)],
    paper: &[(usize, [f64; 4])],
    opts: &StudyOptions,
    steps: usize,
    baselines: &[Baseline],
    log: &mut dyn FnMut(&str),
    files: &mut Vec<std::path::PathBuf>,
    json_cases: &mut Vec<serde_json::Value>,
) -> Result<String> {
    let mut text = String::new();
    let by_n = paper.len() == PAPER_T1.len();
    let labels = |suffix: &str| -> Vec<Vec<String>> {
        ["ρ_{1,L2}", "ρ_{1,MD}", "ρ_{E,L2}", "ρ_{E,MD}"]
            .iter()
            .map(|l| vec![format!("{l}{suffix}")])
            .collect()
    };
    let (mut rows, mut active_rows) = (labels(""), labels(", active phase"));
    let mut header = vec![if by_n { "n" } else { "s" }.to_string()];
    // Fig. 4/5 data: index -> method -> value per case.
    let mut figure: Vec<Vec<Series>> = (0..4).map(|_| vec![]).collect();
    let method_names: Vec<String> = baselines
        .iter()
        .map(|b| b.label().to_string())
        .chain([
            "DEM U_{1,1}".to_string(),
            "DEM U_{E,∞}".to_string(),
            "DEM U_{1,1} + shift".to_string(),
            "stillpoint default".to_string(),
        ])
        .collect();
    for series in figure.iter_mut() {
        for name in &method_names {
            series.push(Series {
                name: name.clone(),
                points: vec![],
            });
        }
    }
    for &(n, s) in cases {
        let key = if by_n { n } else { s };
        header.push(key.to_string());
        let t1 = trajectory(n, s, false, steps, opts.seed)?;
        let te = trajectory(n, s, true, steps, opts.seed)?;
        let ([a, b], [c, d]) = (t1.rho(t1.energy.len()), te.rho(te.energy.len()));
        let rho = [a, b, c, d];
        let (l1, le) = (t1.active_len(), te.active_len());
        let ([a, b], [c, d]) = (t1.rho(l1), te.rho(le));
        let rho_active = [a, b, c, d];
        let paper_row = paper.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
        for (k, row) in rows.iter_mut().enumerate() {
            let p = paper_row.map_or(String::new(), |v| format!(" ({:.4})", v[k]));
            row.push(format!("{}{p}", fmt_opt(rho[k], 4)));
        }
        for (k, row) in active_rows.iter_mut().enumerate() {
            let len = if k < 2 { l1 } else { le };
            row.push(format!("{} [{len}]", fmt_opt(rho_active[k], 4)));
        }
        let mut sets: Vec<(String, PointSet)> = vec![];
        for b in baselines {
            sets.push((b.label().to_string(), b.generate(n, s, opts.seed)?));
        }
        sets.push(("DEM U_{1,1}".into(), t1.points.clone()));
        sets.push(("DEM U_{E,∞}".into(), te.points.clone()));
        // What a user gets: the same DEM result after the shift selection, and the
        // default pipeline (eq. 48, Halton start, shift selection).
        sets.push((
            "DEM U_{1,1} + shift".into(),
            stillpoint::post::shift::best_shift(&t1.points, 64).0,
        ));
        let mut cfg = GenerateConfig::new(n, s);
        cfg.steps = steps;
        sets.push((
            "stillpoint default".into(),
            run_config(&cfg, |_| {})?.output.points,
        ));
        let mut values = serde_json::Map::new();
        for (m, (name, set)) in sets.iter().enumerate() {
            let v = indexes(set)?;
            for (i, series) in figure.iter_mut().enumerate() {
                series[m].points.push((key as f64, v[i]));
            }
            values.insert(
                name.clone(),
                json!({"star_l2": v[0], "modified_l2": v[1], "u11": v[2], "u_e_inf": v[3]}),
            );
        }
        json_cases.push(json!({
            "n": n, "s": s, "steps": steps,
            "rho_1_l2": rho[0], "rho_1_md": rho[1], "rho_e_l2": rho[2], "rho_e_md": rho[3],
            "active_steps": [l1, le], "rho_active": rho_active,
            "paper": paper_row,
            "final": values,
            "dem_u11_start": {"star_l2": t1.star.first(), "modified_l2": t1.modified.first()},
            "dem_u11_end": {"star_l2": t1.star.last(), "modified_l2": t1.modified.last()},
        }));
        log(&format!(
            "correlation n={n} s={s}: ρ = {}",
            rho.iter()
                .map(|r| fmt_opt(*r, 4))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        // Fig. 3: the evolution of P_{2,20} (the paper's example of a negative ρ).
        if by_n && n == 20 {
            fig3(&t1, opts, files)?;
        }
    }
    text += &render(
        title,
        by_n,
        &header,
        &rows,
        &active_rows,
        figure,
        opts,
        files,
    )?;
    Ok(text)
}

/// Fig. 3: discrepancies and U_{1,1} along the DEM on P_{2,20}.
fn fig3(t1: &Trajectory, opts: &StudyOptions, files: &mut Vec<std::path::PathBuf>) -> Result<()> {
    let chart = |title: &str, y: &str, series: Vec<Series>| LineChart {
        title: title.into(),
        x_label: "step".into(),
        y_label: y.into(),
        log_y: true,
        series,
    };
    let zip = |v: &[f64]| t1.steps.iter().copied().zip(v.iter().copied()).collect();
    let path = opts.out.join("fig3_p2_20.png");
    save_charts(
        &path,
        &[
            chart(
                "P_{2,20}: discrepancies along the DEM on U_{1,1}",
                "discrepancy",
                vec![
                    Series {
                        name: "D_L2*".into(),
                        points: zip(&t1.star),
                    },
                    Series {
                        name: "D_MD".into(),
                        points: zip(&t1.modified),
                    },
                ],
            ),
            chart(
                "P_{2,20}: U_{1,1}",
                "U_{1,1}",
                vec![Series {
                    name: "U_{1,1}".into(),
                    points: zip(&t1.energy),
                }],
            ),
        ],
        files,
    )?;
    Ok(())
}

/// The markdown and the figure of one table from its rows and series.
#[allow(clippy::too_many_arguments)]
fn render(
    title: &str,
    by_n: bool,
    header: &[String],
    rows: &[Vec<String>],
    active_rows: &[Vec<String>],
    figure: Vec<Vec<Series>>,
    opts: &StudyOptions,
    files: &mut Vec<std::path::PathBuf>,
) -> Result<String> {
    let mut text = String::new();
    text += &format!("## {title}\n\n");
    text += &markdown_table(header, rows);
    text += "\nThe same over the active phase only (the first [k] steps, until the energy has \
           done 99.9 % of its fall):\n\n";
    text += &markdown_table(header, active_rows);
    text += "\n";
    let fig = if by_n {
        "fig4_by_n.png"
    } else {
        "fig5_by_s.png"
    };
    let labels = ["D_L2*", "D_MD", "U_{1,1}", "U_{E,∞}"];
    let charts: Vec<LineChart> = figure
        .into_iter()
        .zip(labels)
        .map(|(series, label)| LineChart {
            title: format!("{label} of the final sets"),
            x_label: if by_n { "n" } else { "s" }.into(),
            y_label: label.into(),
            log_y: true,
            series,
        })
        .collect();
    let path = opts.out.join(fig);
    stillpoint_plot::save_line_chart_grid(&path, &charts, 2)?;
    files.push(path);
    text += &format!(
        "Final sets against the classic sequences (Fig. {}): [{fig}]({fig}). D_MD of each:\n\n",
        if by_n { 4 } else { 5 }
    );
    let md_rows: Vec<Vec<String>> = charts[1]
        .series
        .iter()
        .map(|s| {
            let mut row = vec![s.name.clone()];
            row.extend(s.points.iter().map(|p| format!("{:.5}", p.1)));
            row
        })
        .collect();
    text += &markdown_table(header, &md_rows);
    text += "\n";
    Ok(text)
}
