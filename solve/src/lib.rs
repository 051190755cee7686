//! Running a solver: one `Solve` drives any integrator through the executor, with
//! checkpoints; observers log discrepancies and pass progress events on. [`cells`] is the
//! descent that keeps a stratified set stratified, which goals and designs both run.

#![deny(missing_docs)]

pub mod cells;
pub mod checkpoint;

use stillpoint_domains::{Error, PointSet};

use crate::checkpoint::CheckpointPlan;
use serde_json::Value;
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{
    Control, Dem, Executor, Integrator, Observer, Problem, Record, RunOutput, Snapshot,
};
use stillpoint_quality::metrics::{self};

/// The solver of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// The damped central-difference DEM of the paper.
    Dem,
    /// argmin's L-BFGS with restarts (see [`stillpoint_integrators::lbfgs`]).
    Lbfgs,
}

/// Attaches discrepancies every k steps and forwards each record to a callback (used for
/// the progress bar).
pub struct LoggingObserver<F: FnMut(&Record)> {
    every: usize,
    on_record: F,
}

impl<F: FnMut(&Record)> LoggingObserver<F> {
    /// Logs D_L2* and D_MD every `every` steps (0: never) and calls `on_record`.
    pub fn new(every: usize, on_record: F) -> Self {
        LoggingObserver { every, on_record }
    }
}

impl<F: FnMut(&Record)> Observer for LoggingObserver<F> {
    fn observe(&mut self, record: &mut Record, points: &PointSet) -> Control {
        if self.every > 0 && record.step.is_multiple_of(self.every) {
            let (l2, md) = metrics::discrepancies(points);
            record.metrics.push(("star_l2".into(), l2));
            record.metrics.push(("modified_l2".into(), md));
        }
        (self.on_record)(record);
        if cancelled() {
            Control::Stop
        } else {
            Control::Continue
        }
    }
}

/// Set when a caller asks the runs under way to stop (Python's Ctrl-C): solvers stop at
/// their next step, the exchange descent at its next batch of proposals, and the
/// pipeline returns [`interrupted`] instead of a result. Process-wide, as a signal is.
static CANCEL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks every run under way to stop, and the pair sums of the metrics with it.
pub fn cancel() {
    CANCEL.store(true, std::sync::atomic::Ordering::SeqCst);
    stillpoint_energies::stop::request();
}

/// Clears a stop request (before a new run).
pub fn clear_cancel() {
    CANCEL.store(false, std::sync::atomic::Ordering::SeqCst);
    stillpoint_energies::stop::clear();
}

/// Whether a stop was asked for.
pub fn cancelled() -> bool {
    CANCEL.load(std::sync::atomic::Ordering::Relaxed)
}

/// The error of a run stopped by [`cancel`].
pub fn interrupted() -> crate::Error {
    crate::Error::Numerical("interrupted".into())
}

/// [`interrupted`] when a stop was asked for: checked between the stages of a run, so a
/// stop never waits for a report or another candidate.
pub fn stop_if_cancelled() -> Result<(), crate::Error> {
    if cancelled() {
        Err(interrupted())
    } else {
        Ok(())
    }
}

/// What a run reports while it works, for progress displays.
#[derive(Debug, Clone, Copy)]
pub enum Event<'a> {
    /// A record of the main run (DEM or L-BFGS), as it is stored in the trajectory.
    Record(&'a Record),
    /// A stage begins: its name and its length in steps when it has one.
    Stage {
        /// `DEM`, `L-BFGS`, `shift selection`, `polish` or `metrics`.
        name: &'static str,
        /// Steps or iterations the stage may take.
        steps: Option<u64>,
    },
    /// The current stage reached this step.
    Progress(u64),
}

/// One run of a solver on a problem: the budget and where checkpoints go. Every solver
/// of the workspace is run through [`Solve::solve`] (and so through the one executor).
pub struct Solve<'a> {
    /// The energy and domain.
    pub problem: &'a Problem<'a>,
    /// The step budget.
    pub steps: usize,
    /// Where checkpoints are written and read, if anywhere.
    pub checkpoint: Option<&'a CheckpointPlan>,
    /// The run's configuration, recorded in checkpoints and compared on resume.
    pub config: &'a Value,
}

impl Solve<'_> {
    /// Runs `solver` from `start` (or from the plan's checkpoint) through the executor.
    pub fn solve(
        &self,
        solver: Solver,
        dem: &Dem,
        lbfgs: &Lbfgs,
        start: PointSet,
        observer: &mut dyn Observer,
    ) -> Result<RunOutput, Error> {
        match solver {
            Solver::Dem => self.execute(dem.clone(), start, observer),
            Solver::Lbfgs => self.execute(lbfgs.clone(), start, observer),
        }
    }

    /// Runs `integrator` from `start` (or from the plan's checkpoint) through the
    /// executor, for a solver that is not one of [`Solver`]'s.
    pub fn execute<I: Integrator>(
        &self,
        integrator: I,
        start: PointSet,
        observer: &mut dyn Observer,
    ) -> Result<RunOutput, Error> {
        let resume = match self.checkpoint {
            Some(plan) => plan.load_state::<I::State>(self.config)?,
            None => None,
        };
        let mut save = |snap: &Snapshot<I::State>| -> Result<(), Error> {
            match self.checkpoint {
                Some(plan) => plan.save(self.config, snap),
                None => Ok(()),
            }
        };
        let every = self.checkpoint.map_or(0, |p| p.every);
        let resumed = self.checkpoint.and_then(|p| p.resume.as_ref());
        Executor::new(self.problem, integrator)
            .max_steps(self.steps)
            .observe(observer)
            .checkpoint(every, &mut save)
            .resume(resume)
            .run(start)
            .map_err(|e| match (e, resumed) {
                // The executor refused the snapshot: say which file it came from.
                (
                    Error::InvalidArgument {
                        name,
                        value,
                        expected,
                    },
                    Some(path),
                ) if name.starts_with(stillpoint_parse::names::CHECKPOINT) => Error::invalid(
                    "resume checkpoint",
                    path.display(),
                    format!(
                        "a checkpoint that can be continued (its {name} = {value}: \
                             expected {expected})"
                    ),
                ),
                (e, _) => e,
            })
    }
}
