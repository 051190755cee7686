//! Fig. 9: n = 100 points in each of the four regions of eq. 58 by the DEM under
//! U_{E,∞,g} from the paper's random start, with the paper's 1000 steps and with 10 000.

use super::{markdown_table, Body, StudyOptions};
use anyhow::Result;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde_json::json;
use std::sync::Arc;
use stillpoint::config::GenerateConfig;
use stillpoint::energies::region::paper_region;
use stillpoint::energies::Domain;
use stillpoint::pipeline::run_config;
use stillpoint::{io, PointSet};
use stillpoint_plot as plot;

/// The paper's reductions of U_{E,∞,g} (only g1 and g4 are given).
const PAPER_REDUCTION: [Option<f64>; 4] = [Some(0.801), None, None, Some(0.893)];

/// Fill distance (covering radius) estimated from `m` uniform points of the region: the
/// largest distance from a region point to its nearest set point. Smaller is more even;
/// unlike U_{E,∞,g} it sees every hole, not only the closest pair.
pub fn fill_distance(domain: &dyn Domain, points: &PointSet, m: usize, seed: u64) -> f64 {
    let (lo, hi) = domain.bounding_box();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut y = vec![0.0; lo.len()];
    let mut worst: f64 = 0.0;
    let mut found = 0;
    let mut tries = 0usize;
    while found < m && tries < 1000 * m {
        tries += 1;
        for k in 0..y.len() {
            y[k] = lo[k] + (hi[k] - lo[k]) * rng.random::<f64>();
        }
        if !domain.contains(&y) {
            continue;
        }
        found += 1;
        let nearest = points
            .rows()
            .map(|x| {
                x.iter()
                    .zip(&y)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
            })
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(nearest);
    }
    worst.sqrt()
}

pub(crate) fn run(opts: &StudyOptions, log: &mut dyn FnMut(&str)) -> Result<Body> {
    let (n, budgets, probes): (usize, [usize; 2], usize) = if opts.quick {
        (30, [200, 1000], 4000)
    } else {
        (100, [1000, 10_000], 20_000)
    };
    let mut rows = vec![];
    let mut json_rows = vec![];
    let mut files = vec![];
    for i in 1..=4 {
        let domain: Arc<dyn Domain> = Arc::new(paper_region(i)?);
        let mut results = vec![];
        for steps in budgets {
            let mut cfg = GenerateConfig::in_region(domain.clone(), n);
            cfg.steps = steps;
            cfg.seed = opts.seed;
            let r = run_config(&cfg, |_| {})?;
            let inside = r.output.points.rows().all(|x| domain.contains(x));
            anyhow::ensure!(inside, "a point of g{i} left the region");
            let file = opts.out.join(format!("g{i}_{steps}.csv"));
            io::write_points(
                &file,
                &r.output.points,
                &json!({"region": format!("g{i} of eq. 58"), "steps": steps, "seed": opts.seed}),
            )?;
            files.push(file);
            log(&format!(
                "regions g{i}, {steps} steps: U_E,inf,g {:.4} -> {:.4} ({:.1} %)",
                r.region_metrics()?.0.energy_e_inf_g,
                r.region_metrics()?.1.energy_e_inf_g,
                100.0 * r.reduction()?
            ));
            results.push(r);
        }
        let fill_start = fill_distance(domain.as_ref(), &results[0].start, probes, opts.seed + 7);
        let fills: Vec<f64> = results
            .iter()
            .map(|r| fill_distance(domain.as_ref(), &r.output.points, probes, opts.seed + 7))
            .collect();
        rows.push(vec![
            format!("g{i}"),
            format!("{:.4}", results[0].region_metrics()?.0.energy_e_inf_g),
            format!("{:.4}", results[0].region_metrics()?.1.energy_e_inf_g),
            format!("{:.1}%", 100.0 * results[0].reduction()?),
            format!("{:.4}", results[1].region_metrics()?.1.energy_e_inf_g),
            format!("{:.1}%", 100.0 * results[1].reduction()?),
            PAPER_REDUCTION[i - 1].map_or("—".into(), |v| format!("{:.1}%", 100.0 * v)),
            format!("{fill_start:.3}"),
            format!("{:.3}", fills[0]),
            format!("{:.3}", fills[1]),
        ]);
        json_rows.push(json!({
            "region": format!("g{i}"), "n": n, "steps": budgets,
            "energy_start": results[0].region_metrics()?.0.energy_e_inf_g,
            "energy_result": results.iter().map(|r| r.region_metrics().map(|m| m.1.energy_e_inf_g)).collect::<Result<Vec<_>, _>>()?,
            "reduction": results.iter().map(|r| r.reduction()).collect::<Result<Vec<_>, _>>()?,
            "paper_reduction": PAPER_REDUCTION[i - 1],
            "fill_distance_start": fill_start, "fill_distance_result": fills,
        }));
        let (lo, hi) = domain.bounding_box();
        let (lo, hi) = ([lo[0], lo[1]], [hi[0], hi[1]]);
        let level = |x: &[f64]| domain.level(x).unwrap_or(f64::NAN);
        let boundary = plot::boundary_polylines(&level, lo, hi, 300);
        let mut panels = vec![plot::Panel {
            title: format!("g{i}: random start"),
            points: &results[0].start,
            lo,
            hi,
            boundary: boundary.clone(),
            split: None,
        }];
        for (r, steps) in results.iter().zip(budgets) {
            panels.push(plot::Panel {
                title: format!("g{i}: DEM, U_{{E,∞,g}}, {steps} steps"),
                points: &r.output.points,
                lo,
                hi,
                boundary: boundary.clone(),
                split: None,
            });
        }
        let pic = opts.out.join(format!("fig9_g{i}.png"));
        plot::save_panels(&pic, &panels, 3)?;
        files.push(pic);
    }
    let [a, b] = budgets;
    let header: Vec<String> = [
        "region".to_string(),
        "U_{E,∞,g} start".into(),
        format!("after {a} steps"),
        "reduction".into(),
        format!("after {b} steps"),
        "reduction".into(),
        "paper reduction".into(),
        "fill distance start".into(),
        format!("fill distance {a}"),
        format!("fill distance {b}"),
    ]
    .to_vec();
    let mut md = format!("# Fig. 9: {n} points in the four regions of eq. 58\n\n");
    md += &format!(
        "Start: uniform points in the bounding box, the first {n} inside (seed {}), as §5.4. The \
         DEM minimises U_{{E,∞,g}} (eq. 56 with the distance itself, not d^p) with the κ trial; \
         every output point satisfies g ≤ 0. The reduction is the paper's measure, \
         1 − U(result)/U(start). U_{{E,∞,g}} only sees the closest pair or the point closest to \
         the boundary, so the fill distance (largest distance from any of {probes} uniform \
         region points to its nearest set point) is shown as well: it drops only when the \
         holes close.\n\n",
        opts.seed
    );
    md += &markdown_table(&header, &rows);
    md += "\nPictures (start, and the two results): ";
    md += &(1..=4)
        .map(|i| format!("[g{i}](fig9_g{i}.png)"))
        .collect::<Vec<_>>()
        .join(", ");
    md += ".\n";
    Ok(Body {
        markdown: md,
        json: json!({"study": "regions", "regions": json_rows}),
        files,
    })
}
