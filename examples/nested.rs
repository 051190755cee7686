//! The price of nesting: a nested set of 16, 32, …, 1024 points (every prefix made for
//! its size by extension) against the scrambled-Sobol' prefix of the same length (mean
//! over 16 scrambles), the prefix of the extensible lattice sequence `quad` and
//! `Engine` draw from (mean over 16 shifts, tent-transformed) and a set optimised for
//! that n alone, in D_MD and D_L2*: whether `--nested` should be that sequence.
//! Writes results/nested/nested.md.
//!
//!     cargo run --release -p stillpoint --example nested

use std::fmt::Write as _;
use std::time::Instant;
use stillpoint::goals::integration::{integration_set, nested_set};
use stillpoint::quality::effort::Effort;
use stillpoint::quality::metrics::Metrics;
use stillpoint::quality::target::Target;
use stillpoint::sequences;
use stillpoint::PointSet;

fn prefix(p: &PointSet, k: usize) -> PointSet {
    PointSet::new(k, p.s(), p.as_slice()[..k * p.s()].to_vec()).unwrap()
}

fn main() {
    let stages: Vec<usize> = (4..=10).map(|e| 1usize << e).collect();
    let (target, effort) = (Target::blend(), Effort::default());
    let scrambles = 16;
    let mut md = String::from(
        "# Nested sets: every prefix against scrambled Sobol' and a set made for its size\n\n\
         Command: `cargo run --release -p stillpoint --example nested` on a 2-core machine. Each row is a\n\
         prefix of one nested set made with the blend target (`stillpoint generate --nested\n\
         16,32,...,1024` at s ≤ 5; from s = 8 the command line's target is the curved one);\n\
         Sobol' is the mean over 16 Owen scrambles of the first n points of the sequence;\n\
         \"lattice\" the mean over 16 shifts of the first n points of the extensible lattice\n\
         sequence (`stillpoint.Engine(d)`, tent-transformed); \"alone\" is the descent's set\n\
         made for that n with the same target (`generate -n N --target blend`: from 500 points\n\
         the default is a lattice instead). Nesting price = nested / alone − 1.\n\n",
    );
    for s in [2, 3, 5, 10] {
        let clock = Instant::now();
        let nested = nested_set(&stages, s, &target, 0, &effort).unwrap();
        let secs = clock.elapsed().as_secs_f64();
        let sobol: Vec<PointSet> = (0..scrambles)
            .map(|k| sequences::sobol_scrambled(1024, s, 7000 + k).unwrap())
            .collect();
        let lattice: Vec<PointSet> = (0..scrambles)
            .map(|k| {
                sequences::ExtensibleLattice::new(s, 7000, k)
                    .and_then(|e| e.points(0, 1024))
                    .unwrap()
            })
            .collect();
        writeln!(md, "## s = {s} (nested set built in {secs:.1} s)\n").unwrap();
        md += "| n | D_MD nested | D_MD Sobol' | D_MD lattice | D_MD alone | D_L2* nested | D_L2* Sobol' | D_L2* lattice | D_L2* alone | below Sobol' (both) | below lattice (both) | nesting price D_MD |\n";
        md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for &n in &stages {
            let ours = Metrics::compute(&prefix(&nested, n));
            let (mut sm, mut sl) = (0.0, 0.0);
            for q in &sobol {
                let m = Metrics::compute(&prefix(q, n));
                sm += m.modified_l2 / scrambles as f64;
                sl += m.star_l2 / scrambles as f64;
            }
            let (mut lm, mut ll) = (0.0, 0.0);
            for q in &lattice {
                let m = Metrics::compute(&prefix(q, n));
                lm += m.modified_l2 / scrambles as f64;
                ll += m.star_l2 / scrambles as f64;
            }
            let alone = Metrics::compute(&integration_set(n, s, &target, 0, &effort).unwrap().0);
            writeln!(
                md,
                "| {n} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {} | {} | {:+.1}% |",
                ours.modified_l2,
                sm,
                lm,
                alone.modified_l2,
                ours.star_l2,
                sl,
                ll,
                alone.star_l2,
                if ours.modified_l2 < sm && ours.star_l2 < sl {
                    "yes"
                } else {
                    "no"
                },
                if ours.modified_l2 < lm && ours.star_l2 < ll {
                    "yes"
                } else {
                    "no"
                },
                100.0 * (ours.modified_l2 / alone.modified_l2 - 1.0)
            )
            .unwrap();
        }
        md += "\n";
        eprintln!("s = {s} done");
    }
    std::fs::create_dir_all("results/nested").unwrap();
    std::fs::write("results/nested/nested.md", &md).unwrap();
    print!("{md}");
}
