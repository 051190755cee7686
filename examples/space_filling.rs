//! The space-filling goal against a maximin Latin hypercube and the paper's DEM set: the
//! smallest Euclidean distance (higher is better) and whether each set is stratified.
//! Writes results/space-filling/space-filling.md.
//!
//!     cargo run --release -p stillpoint --example space_filling

use std::fmt::Write as _;
use std::time::Instant;
use stillpoint::config::{GenerateConfig, Goal};
use stillpoint::pipeline::{self as run};
use stillpoint::quality::metrics::min_distance_euclidean;
use stillpoint::quality::stratification::is_stratified;
use stillpoint::sequences;

fn main() {
    let mut md = String::from(
        "# Space-filling goal: smallest distance against a maximin LHS and the paper's set\n\n\
         Command: `cargo run --release -p stillpoint --example space_filling` on a 2-core machine.\n\
         `goal` is `stillpoint generate --goal space-filling` (seed 0); `LHS-maximin` is\n\
         `stillpoint baseline lhs-maximin` (best of seeds 0–3); `paper` is `--method paper`.\n\
         Minimum Euclidean distance, higher is better.\n\n\
         | n | s | goal | LHS-maximin (best of 4) | paper | goal stratified | goal above both | seconds |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let mut wins = 0;
    let mut cells = 0;
    for s in [2, 3, 5, 10] {
        for n in [16, 64, 256, 1024] {
            let clock = Instant::now();
            let goal = run::run_config(&GenerateConfig::for_goal(n, s, Goal::SpaceFilling), |_| {})
                .unwrap()
                .output
                .points;
            let secs = clock.elapsed().as_secs_f64();
            let lhs = (0..4)
                .map(|seed| min_distance_euclidean(&sequences::lhs_maximin(n, s, seed).unwrap()))
                .fold(0.0, f64::max);
            let paper = min_distance_euclidean(
                &run::run_config(&GenerateConfig::new(n, s), |_| {})
                    .unwrap()
                    .output
                    .points,
            );
            let ours = min_distance_euclidean(&goal);
            let above = ours > lhs && ours > paper;
            wins += usize::from(above);
            cells += 1;
            writeln!(
                md,
                "| {n} | {s} | {ours:.4} | {lhs:.4} | {paper:.4} | {} | {} | {secs:.1} |",
                if is_stratified(&goal) { "yes" } else { "no" },
                if above { "yes" } else { "no" }
            )
            .unwrap();
            eprintln!("n = {n}, s = {s} done");
        }
    }
    writeln!(
        md,
        "\nThe goal's set is above both in {wins} of {cells} cells."
    )
    .unwrap();
    std::fs::create_dir_all("results/space-filling").unwrap();
    std::fs::write("results/space-filling/space-filling.md", &md).unwrap();
    print!("{md}");
}
