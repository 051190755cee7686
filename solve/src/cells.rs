//! The descent inside the cells of a stratified set: L-BFGS through the one executor on a
//! target discrepancy as a function of each point's offset in its cell, written
//! u = 1/(1 + e^{−z}) so that every iterate stays stratified. The integration goal
//! alternates it with exchanges; designs polish their balanced slices with it.

use crate::{LoggingObserver, Solve};
use serde_json::Value;
use std::sync::Arc;
use stillpoint_domains::shapes::BoxRegion;
use stillpoint_domains::{Error, PointSet};
use stillpoint_energies::discrepancy::DiscrepancyEnergy;
use stillpoint_energies::fixed::WithFixed;
use stillpoint_energies::Energy;
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{Problem, Record, StopReason};
use stillpoint_quality::stratification::{cell_of, in_cell};
use stillpoint_quality::target::Target;

/// A [`Target`] as an energy: the weighted sum of the discrepancy energies.
struct TargetEnergy {
    parts: Vec<(DiscrepancyEnergy, f64)>,
}

impl TargetEnergy {
    fn new(target: &Target) -> TargetEnergy {
        TargetEnergy {
            parts: target
                .parts
                .iter()
                .map(|&(k, w)| (DiscrepancyEnergy::new(k), w))
                .collect(),
        }
    }
}

impl Energy for TargetEnergy {
    fn name(&self) -> String {
        let names: Vec<String> = self.parts.iter().map(|(e, _)| e.name()).collect();
        names.join(" + ")
    }

    fn value(&self, points: &PointSet) -> f64 {
        self.parts.iter().map(|(e, w)| w * e.value(points)).sum()
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        grad.fill(0.0);
        let mut part = vec![0.0; grad.len()];
        let mut total = 0.0;
        for (e, w) in &self.parts {
            total += w * e.value_and_gradient(points, &mut part);
            for (g, p) in grad.iter_mut().zip(&part) {
                *g += w * p;
            }
        }
        total
    }
}

/// The logistic function, u = 1/(1 + e^{−z}).
fn logistic(z: f64) -> f64 {
    1.0 / (1.0 + (-z).exp())
}

/// The squared discrepancy of the points (c + logistic(z))/n, as an energy of z: what
/// L-BFGS descends in [`descend_in_cells`].
struct CellEnergy {
    /// The target, of the moving points (with the fixed ones when there are).
    inner: Arc<dyn Energy>,
    /// The cells of the moving points.
    cells: Vec<usize>,
    /// The number of cells per coordinate (the size of the whole set).
    n: usize,
    s: usize,
}

impl CellEnergy {
    fn points(&self, z: &PointSet) -> PointSet {
        let data = z
            .as_slice()
            .iter()
            .zip(&self.cells)
            .map(|(&z, &c)| in_cell(c, logistic(z), self.n))
            .collect();
        PointSet::new(z.n(), self.s, data).expect("same shape")
    }
}

impl Energy for CellEnergy {
    fn name(&self) -> String {
        format!("{} within the cells", self.inner.name())
    }

    fn value(&self, z: &PointSet) -> f64 {
        self.inner.value(&self.points(z))
    }

    fn value_and_gradient(&self, z: &PointSet, grad: &mut [f64]) -> f64 {
        let v = self.inner.value_and_gradient(&self.points(z), grad);
        let inv_n = 1.0 / self.n as f64;
        for (g, &z) in grad.iter_mut().zip(z.as_slice()) {
            let u = logistic(z);
            *g *= u * (1.0 - u) * inv_n;
        }
        v
    }
}

/// How far z may go: logistic(±36) is within 2.4e-16 of 0 or 1, as close to a cell's edge
/// as an offset can usefully get.
const Z_BOUND: f64 = 36.0;

/// L-BFGS (at most `steps` iterations) on the target over the offsets
/// of a stratified set, its cells fixed; the result is stratified with the same cells and
/// its discrepancy is not above the start's.
pub fn descend_in_cells(
    points: &PointSet,
    target: &Target,
    steps: usize,
    lbfgs: &Lbfgs,
) -> Result<PointSet, Error> {
    descend_in_cells_after(points, 0, target, steps, lbfgs)
}

/// [`descend_in_cells`] moving only the points from index `first_movable` on; the
/// points before it take part in the target and stay where they are.
pub fn descend_in_cells_after(
    points: &PointSet,
    first_movable: usize,
    target: &Target,
    steps: usize,
    lbfgs: &Lbfgs,
) -> Result<PointSet, Error> {
    if first_movable >= points.n() {
        return Ok(points.clone());
    }
    Ok(cell_descent(points, first_movable, target, steps, lbfgs)?.0)
}

/// What one L-BFGS run of [`cell_descent`] did: its iterations, why it stopped, and
/// whether its result was kept.
pub type CellRun = (usize, StopReason, bool);

/// [`descend_in_cells_after`] with at least one movable point, and what its run did.
pub fn cell_descent(
    points: &PointSet,
    first_movable: usize,
    target: &Target,
    steps: usize,
    lbfgs: &Lbfgs,
) -> Result<(PointSet, CellRun), Error> {
    let (n, s) = (points.n(), points.s());
    let split = first_movable * s;
    let moving = &points.as_slice()[split..];
    let cells: Vec<usize> = moving.iter().map(|&v| cell_of(v, n)).collect();
    let z0: Vec<f64> = moving
        .iter()
        .zip(&cells)
        .map(|(&v, &c)| {
            let u = (v * n as f64 - c as f64).clamp(1e-12, 1.0 - 1e-12);
            (u / (1.0 - u)).ln().clamp(-Z_BOUND, Z_BOUND)
        })
        .collect();
    let whole: Arc<dyn Energy> = Arc::new(TargetEnergy::new(target));
    let inner: Arc<dyn Energy> = if first_movable == 0 {
        whole.clone()
    } else {
        let fixed = PointSet::new(first_movable, s, points.as_slice()[..split].to_vec())?;
        Arc::new(WithFixed::new(whole.clone(), fixed))
    };
    let energy = Arc::new(CellEnergy { inner, cells, n, s });
    let before = whole.value(points);
    let domain = BoxRegion::new(vec![-Z_BOUND; s], vec![Z_BOUND; s])?;
    let problem = Problem::shared(energy.clone(), Arc::new(domain))?;
    let mut quiet = LoggingObserver::new(0, |_: &Record| {});
    let run = Solve {
        problem: &problem,
        steps,
        checkpoint: None,
        config: &Value::Null,
    };
    let out = run.execute(
        lbfgs.clone(),
        PointSet::new(n - first_movable, s, z0)?,
        &mut quiet,
    )?;
    let mut data = points.as_slice()[..split].to_vec();
    data.extend_from_slice(energy.points(&out.points).as_slice());
    let result = PointSet::new(n, s, data)?;
    let iterations = out.trajectory.iter().map(|r| r.step).max().unwrap_or(0);
    Ok(if whole.value(&result) < before {
        (result, (iterations, out.stop, true))
    } else {
        (points.clone(), (iterations, out.stop, false))
    })
}
