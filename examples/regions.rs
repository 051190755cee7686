//! The paper's four regions (§5.4, eq. 58): n = 100 points by the DEM under U_{E,∞,g}
//! from the paper's random start, with the paper's 1000 steps and with 10 000.
//!
//! Run with `cargo run --release --example regions [-- OUTDIR]` (default `regions-output`).
//! For each region it writes the points (CSV) and a picture of the start beside the result
//! with the boundary drawn (PNG), and prints U_{E,∞,g} before and after with the reduction
//! next to the paper's (80.1 % for g1 up to 89.3 % for g4).

use serde_json::json;
use std::path::PathBuf;
use std::sync::Arc;
use stillpoint::energies::region::paper_region;
use stillpoint::energies::Domain;
use stillpoint::regions::{generate_in_region, RegionConfig};
use stillpoint::{io, plot};

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
        let domain: Arc<dyn Domain> = Arc::new(paper_region(i)?);
        let mut row = format!("| g{i} ");
        let mut last = None;
        for steps in [1000, 10_000] {
            let mut cfg = RegionConfig::new(domain.clone(), 100);
            cfg.steps = steps;
            let r = generate_in_region(&cfg, |_| {})?;
            assert!(r.output.points.rows().all(|x| domain.contains(x)));
            if steps == 1000 {
                row += &format!("| {:.4} ", r.metrics.0.energy_e_inf_g);
            }
            row += &format!(
                "| {:.4} | {:.1} % ",
                r.metrics.1.energy_e_inf_g,
                100.0 * r.reduction()
            );
            let meta = json!({"region": format!("g{i} of eq. 58"), "steps": steps,
                "energy_e_inf_g_start": r.metrics.0.energy_e_inf_g,
                "energy_e_inf_g_result": r.metrics.1.energy_e_inf_g});
            io::write_points(
                &out.join(format!("g{i}_{steps}.csv")),
                &r.output.points,
                &meta,
            )?;
            last = Some(r);
        }
        row += &format!("| {} |", paper[i - 1]);
        println!("{row}");
        let r = last.expect("two runs");
        let (lo, hi) = domain.bounding_box();
        let (lo, hi) = ([lo[0], lo[1]], [hi[0], hi[1]]);
        let level = |x: &[f64]| domain.level(x).unwrap_or(f64::NAN);
        let boundary = plot::boundary_polylines(&level, lo, hi, 300);
        let panels = [
            plot::Panel {
                title: format!("g{i}: random start"),
                points: &r.start,
                lo,
                hi,
                boundary: boundary.clone(),
            },
            plot::Panel {
                title: format!("g{i}: DEM, U_{{E,∞,g}}, 10 000 steps"),
                points: &r.output.points,
                lo,
                hi,
                boundary,
            },
        ];
        plot::save_panels(&out.join(format!("g{i}.png")), &panels, 2)?;
    }
    println!("\npoints and pictures written to {}", out.display());
    Ok(())
}
