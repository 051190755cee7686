//! Helpers shared by this crate's tests.
#![allow(dead_code)]

use stillpoint_energies::{Domain, Energy, PointSet, Result};
use stillpoint_integrators::{Executor, Integrator, Observer, Problem, RunOutput, Snapshot};

/// An integrator with a step budget, run through the executor on a borrowed energy and
/// domain: `Budget(300, dem).run(&e, &cube, start, &mut NoObserver)`.
#[derive(Debug, Clone)]
pub struct Budget<I>(pub usize, pub I);

impl<I: Integrator + Clone> Budget<I> {
    /// Runs from `start` with the executor.
    pub fn run(
        &self,
        e: &dyn Energy,
        d: &dyn Domain,
        start: PointSet,
        observer: &mut dyn Observer,
    ) -> Result<RunOutput> {
        let problem = Problem::borrowed(e, d)?;
        Executor::new(&problem, self.1.clone())
            .max_steps(self.0)
            .observe(observer)
            .run(start)
    }
}

/// Runs with a snapshot every `every` steps and returns the output with the snapshots,
/// each passed through JSON as a checkpoint file holds it.
pub fn run_with_snapshots<I: Integrator + Clone>(
    b: &Budget<I>,
    e: &dyn Energy,
    d: &dyn Domain,
    start: &PointSet,
    every: usize,
) -> (RunOutput, Vec<Snapshot<I::State>>) {
    let problem = Problem::borrowed(e, d).unwrap();
    let mut snaps: Vec<Snapshot<I::State>> = Vec::new();
    let mut keep = |s: &Snapshot<I::State>| {
        let text = serde_json::to_string(s).unwrap();
        snaps.push(serde_json::from_str(&text).unwrap());
        Ok(())
    };
    let out = Executor::new(&problem, b.1.clone())
        .max_steps(b.0)
        .checkpoint(every, &mut keep)
        .run(start.clone())
        .unwrap();
    (out, snaps)
}

/// Continues `snap` under `b` on `e`, `d` from `start`.
pub fn resume<I: Integrator + Clone>(
    b: &Budget<I>,
    e: &dyn Energy,
    d: &dyn Domain,
    start: &PointSet,
    snap: Snapshot<I::State>,
) -> Result<RunOutput> {
    let problem = Problem::borrowed(e, d)?;
    Executor::new(&problem, b.1.clone())
        .max_steps(b.0)
        .resume(Some(snap))
        .run(start.clone())
}

/// The bits of a run: points, (step, energy, restarted) of every record, stop, info.
pub type RunBits = (
    Vec<u64>,
    Vec<(usize, u64, bool)>,
    String,
    Vec<(String, u64)>,
);

/// The [`RunBits`] of an output.
pub fn run_bits(o: &RunOutput) -> RunBits {
    (
        o.points.as_slice().iter().map(|v| v.to_bits()).collect(),
        o.trajectory
            .iter()
            .map(|r| (r.step, r.energy.to_bits(), r.restarted))
            .collect(),
        format!("{:?}", o.stop),
        o.info
            .iter()
            .map(|(k, v)| (k.clone(), v.to_bits()))
            .collect(),
    )
}
