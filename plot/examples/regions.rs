//! The paper's four regions (§5.4, eq. 58): n = 100 points by the DEM under U_{E,∞,g}
//! from the paper's random start, with the paper's 1000 steps and with 10 000. Each
//! region is a `Problem` (the boundary-aware energy tied to its domain) run through the
//! executor.
//!
//! Run with `cargo run --release -p stillpoint-plot --example regions [-- OUTDIR]`
//! (default `regions-output`). For each region it writes the points (CSV) and a picture
//! of the start beside the result with the boundary drawn (PNG), and prints U_{E,∞,g}
//! before and after with the reduction next to the paper's (80.1 % for g1 up to 89.3 %
//! for g4).

use serde_json::json;
use std::path::PathBuf;
use std::sync::Arc;
use stillpoint::energies::boundary::UEInfG;
use stillpoint::energies::region::paper_region;
use stillpoint::energies::Domain;
use stillpoint::integrators::{Dem, Executor, Problem};
use stillpoint::io;
use stillpoint_plot as plot;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "regions-output".into()),
    );
    std::fs::create_dir_all(&out)?;
    let paper = ["80.1 %", "(not given)", "(not given)", "89.3 %"];
    println!(
        "| region | U_{{E,∞,g}} start | after 1000 steps | reduction | after 10 000 steps | reduction | paper |"
    );
    println!("|---|---|---|---|---|---|---|");
    for i in 1..=4 {
        // The region and the energy that measures distances to its boundary.
        let domain: Arc<dyn Domain> = Arc::new(paper_region(i)?);
        let problem = Problem::tied(Arc::new(UEInfG::new(domain.clone())?))?;
        // The paper's start: uniform in the bounding box, the first 100 inside.
        let start = domain.sample(100, 0)?;
        let u0 = problem.energy().value(&start);
        let mut row = format!("| g{i} | {u0:.4} ");
        let mut last = None;
        for steps in [1000, 10_000] {
            let out_run = Executor::new(&problem, Dem::default())
                .max_steps(steps)
                .run(start.clone())?;
            assert!(out_run.points.rows().all(|x| domain.contains(x)));
            let u = problem.energy().value(&out_run.points);
            row += &format!("| {u:.4} | {:.1} % ", 100.0 * (1.0 - u / u0));
            let meta = json!({"region": format!("g{i} of eq. 58"), "steps": steps,
                "energy_e_inf_g_start": u0, "energy_e_inf_g_result": u});
            io::write_points(
                &out.join(format!("g{i}_{steps}.csv")),
                &out_run.points,
                &meta,
            )?;
            last = Some(out_run.points);
        }
        row += &format!("| {} |", paper[i - 1]);
        println!("{row}");
        let result = last.expect("two runs");
        let (lo, hi) = domain.bounding_box();
        let (lo, hi) = ([lo[0], lo[1]], [hi[0], hi[1]]);
        let level = |x: &[f64]| domain.level(x).unwrap_or(f64::NAN);
        let boundary = plot::boundary_polylines(&level, lo, hi, 300);
        let panels = [
            plot::Panel {
                title: format!("g{i}: random start"),
                points: &start,
                lo,
                hi,
                boundary: boundary.clone(),
                split: None,
            },
            plot::Panel {
                title: format!("g{i}: DEM, U_{{E,∞,g}}, 10 000 steps"),
                points: &result,
                lo,
                hi,
                boundary,
                split: None,
            },
        ];
        plot::save_panels(&out.join(format!("g{i}.png")), &panels, 2)?;
    }
    println!("\npoints and pictures written to {}", out.display());
    Ok(())
}
