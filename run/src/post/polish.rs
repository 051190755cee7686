//! The polish, a post-step: L-BFGS on a squared discrepancy from a finished set, run
//! through the executor like any solver, kept only if it lowers the discrepancy.

use crate::Error;
use serde_json::Value;
use std::sync::Arc;
use stillpoint_domains::shapes::BoxRegion;
use stillpoint_domains::{Domain, PeriodicCube, PointSet};
use stillpoint_energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{Problem, Record};
use stillpoint_solve::{LoggingObserver, Solve};

/// What the polish did.
#[derive(Debug, Clone)]
pub struct Polished {
    /// The polished points, or the given points if the polish did not lower the
    /// discrepancy.
    pub points: PointSet,
    /// The squared discrepancy before.
    pub before: f64,
    /// The squared discrepancy of the kept points.
    pub after: f64,
    /// L-BFGS iterations taken.
    pub iterations: usize,
    /// The L-BFGS run's records.
    pub trajectory: Vec<Record>,
}

/// The polish: L-BFGS on a squared discrepancy from `points` (on the torus for the
/// wrap-around L2, in the closed cube for the others), keeping the result only if it is
/// lower. `on_step` sees every iteration (for progress displays).
pub fn polish(
    points: &PointSet,
    kind: DiscrepancyKind,
    steps: usize,
    lbfgs: &Lbfgs,
    mut on_step: impl FnMut(u64),
) -> Result<Polished, Error> {
    let s = points.s();
    let domain: Arc<dyn Domain> = if kind.is_periodic() {
        Arc::new(PeriodicCube::new(s)?)
    } else {
        Arc::new(BoxRegion::new(vec![0.0; s], vec![1.0; s])?)
    };
    let problem = Problem::shared(Arc::new(DiscrepancyEnergy::new(kind)), domain)?;
    let e = problem.energy();
    let before = e.value(points);
    let mut progress = LoggingObserver::new(0, |r: &Record| on_step(r.step as u64));
    let run = Solve {
        problem: &problem,
        steps,
        checkpoint: None,
        config: &Value::Null,
    };
    let out = run.execute(lbfgs.clone(), points.clone(), &mut progress)?;
    let iterations = out.trajectory.iter().map(|r| r.step).max().unwrap_or(0);
    let after = e.value(&out.points);
    let kept = if after < before {
        out.points
    } else {
        points.clone()
    };
    Ok(Polished {
        points: kept,
        before,
        after: after.min(before),
        iterations,
        trajectory: out.trajectory,
    })
}
