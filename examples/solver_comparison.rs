//! The same problem under two solvers: U_{q,p} (eq. 48's q and p) on the periodic cube,
//! from plain Halton, run through the executor once with the DEM and once with L-BFGS,
//! and the squared modified L2 discrepancy in the closed cube under L-BFGS.
//!
//! `cargo run --release -p stillpoint --example solver_comparison [-- S N STEPS]` (default 2 400 1000).
//! For the full comparison with tables and pictures: `stillpoint compare`.

use stillpoint::energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use stillpoint::energies::shapes::BoxRegion;
use stillpoint::energies::{paper_qp, Distance, PeriodicCube, Uqp};
use stillpoint::integrators::lbfgs::Lbfgs;
use stillpoint::integrators::{Dem, Executor, Integrator, Problem, RunOutput};
use stillpoint::{metrics, sequences, PointSet};

fn main() -> anyhow::Result<()> {
    let arg = |i: usize, default: usize| -> anyhow::Result<usize> {
        Ok(match std::env::args().nth(i) {
            Some(text) => text.parse()?,
            None => default,
        })
    };
    let (s, n, steps) = (arg(1, 2)?, arg(2, 400)?, arg(3, 1000)?);
    let start = sequences::halton(n, s)?;

    // One problem, two solvers.
    let fit = paper_qp(n, s);
    let uqp = Problem::new(Uqp::new(Distance::Q(fit.q), fit.p)?, PeriodicCube::new(s)?)?;
    report(
        "DEM on U_{q,p}",
        &solve(&uqp, Dem::default(), steps, &start)?,
    );
    report(
        "L-BFGS on U_{q,p}",
        &solve(&uqp, Lbfgs::default(), steps, &start)?,
    );

    // A discrepancy is an energy too; it lives in the closed cube.
    let md = Problem::new(
        DiscrepancyEnergy::new(DiscrepancyKind::ModifiedL2),
        BoxRegion::new(vec![0.0; s], vec![1.0; s])?,
    )?;
    report(
        "L-BFGS on D²_MD",
        &solve(&md, Lbfgs::default(), steps, &start)?,
    );
    println!(
        "{:<20} D_MD {:.6}  D_L2* {:.6}",
        "Halton start",
        metrics::modified_l2(&start),
        metrics::star_l2(&start)
    );
    Ok(())
}

fn solve<I: Integrator>(
    problem: &Problem<'_>,
    solver: I,
    steps: usize,
    start: &PointSet,
) -> stillpoint::energies::Result<RunOutput> {
    Executor::new(problem, solver)
        .max_steps(steps)
        .run(start.clone())
}

fn report(name: &str, out: &RunOutput) {
    println!(
        "{name:<20} D_MD {:.6}  D_L2* {:.6}  {} steps ({:?})",
        metrics::modified_l2(&out.points),
        metrics::star_l2(&out.points),
        out.trajectory.last().map_or(0, |r| r.step),
        out.stop
    );
}
