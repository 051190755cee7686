//! The solver comparison: DEM and L-BFGS on U_{q,p} and on the squared modified L2
//! discrepancy for the paper's P_{2,1500}, P_{3,1500}, P_{5,1500}, P_{6,1500} and for
//! P_{5,200}, P_{10,400}.
//!
//! `cargo run --release --example solver_comparison [-- OUTDIR [SxN,...]]` writes
//! comparison.md, comparison.json and convergence pictures to OUTDIR (default
//! `comparison`). The same as `stillpoint compare`.

use stillpoint::compare::{run_and_write, CompareSettings};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = args.next().unwrap_or_else(|| "comparison".into());
    let mut settings = CompareSettings::default();
    if let Some(cases) = args.next() {
        settings.cases = cases
            .split(',')
            .filter_map(|c| {
                let (s, n) = c.split_once('x')?;
                Some((s.parse().ok()?, n.parse().ok()?))
            })
            .collect();
    }
    let table = run_and_write(&settings, std::path::Path::new(&dir), true)?;
    println!("{table}");
    Ok(())
}
