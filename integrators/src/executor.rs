//! The one driver of every run: an [`Executor`] takes a [`Problem`], an [`Integrator`]
//! and a start, and owns everything around the integrator's steps — the loop, the step
//! budget, the stop rules, keeping the lowest state of a non-smooth energy, the records'
//! clock, the observer, and checkpoints ([`Snapshot`]s) that a run can be continued from
//! bit for bit. An integrator only says how to start and how to take one step from its
//! own serialisable state, so a new integrator is one `impl` (see the gradient-descent
//! integrator in this crate's tests).

use crate::{Control, Observer, Problem, Record, RunOutput, StopReason};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use stillpoint_energies::{Error, PointSet, Result};

/// A state an integrator reached, as the executor records it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Move {
    /// Energy of the new state.
    pub energy: f64,
    /// Largest coordinate change of the step that produced it.
    pub max_move: f64,
    /// Whether the new state came from a restart rather than a plain step.
    pub restarted: bool,
}

/// What one step of an integrator did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// A new state; the run goes on.
    Moved(Move),
    /// A new state at which the integrator's own convergence rule holds; the run ends
    /// with it.
    Converged(Move),
    /// The integrator began again from the start (the DEM's κ trial): the trajectory so
    /// far is dropped (the lowest state seen is kept) and the start, with this energy, is
    /// step 0 again.
    BeganAgain(f64),
    /// The integrator cannot go on and adds no state (for example L-BFGS after a chunk
    /// without progress): the run ends with the current state.
    Ended(StopReason),
}

/// A method that drives a point set to rest under a [`Problem`]'s energy, one step at a
/// time. Its [`Integrator::State`] holds everything needed to continue bit for bit, so
/// that the executor can checkpoint any integrator.
pub trait Integrator {
    /// Everything the integrator needs to take its next step.
    type State: Clone + Serialize + DeserializeOwned;

    /// Short name with parameters.
    fn name(&self) -> String;

    /// Checks the settings and the start (inside the domain) and evaluates the start:
    /// returns the state at step 0 and its energy.
    fn init(&self, problem: &Problem<'_>, start: PointSet) -> Result<(Self::State, f64)>;

    /// Takes one step.
    fn step(&self, problem: &Problem<'_>, state: &mut Self::State) -> Result<Step>;

    /// The points of the current state.
    fn points<'s>(&self, state: &'s Self::State) -> &'s PointSet;

    /// Facts about the run so far (κ used, restarts, evaluations), for reports.
    fn info(&self, state: &Self::State) -> Vec<(String, f64)>;

    /// Refuses a state read from a checkpoint that this integrator cannot continue under
    /// this problem (other settings, sizes, non-finite numbers, points outside the
    /// domain), naming what disagrees. A checkpoint is untrusted input.
    fn check_state(
        &self,
        problem: &Problem<'_>,
        start: &PointSet,
        state: &Self::State,
    ) -> Result<()>;
}

/// The lowest state a run has seen (kept for non-smooth energies, which it returns).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Best {
    /// Its energy.
    pub energy: f64,
    /// Its step.
    pub step: usize,
    /// Its points.
    pub points: PointSet,
}

/// Everything needed to continue a run bit for bit where it was saved: the step, the
/// integrator's state, the trajectory so far, the lowest state seen and the wall time
/// spent. Handed out by [`Executor::checkpoint`] when the integrator has reached the
/// state of `step` and before that state is recorded; taken back by
/// [`Executor::resume`], which records it first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot<S> {
    /// The step of the state the integrator has reached.
    pub step: usize,
    /// The integrator's name with its parameters.
    pub integrator: String,
    /// The integrator's state.
    pub state: S,
    /// The record of that state, not yet in the trajectory.
    pub record: Record,
    /// Whether the integrator's convergence rule holds at that state.
    pub converged: bool,
    /// Records of steps 0..step.
    pub trajectory: Vec<Record>,
    /// The lowest state seen, when the energy is not smooth.
    pub best: Option<Best>,
    /// Wall time of the run so far in seconds (the records' clock goes on from it).
    pub seconds: f64,
}

/// Receives each [`Snapshot`] (for example to write a checkpoint file); an error ends the
/// run with that error.
pub type SaveSnapshot<'a, S> = &'a mut dyn FnMut(&Snapshot<S>) -> Result<()>;

/// Runs an [`Integrator`] on a [`Problem`]; see the module documentation.
pub struct Executor<'p, 'o, I: Integrator> {
    problem: &'p Problem<'p>,
    integrator: I,
    max_steps: usize,
    observer: Option<&'o mut dyn Observer>,
    every: usize,
    save: Option<SaveSnapshot<'o, I::State>>,
    resume: Option<Snapshot<I::State>>,
}

impl<'p, 'o, I: Integrator> Executor<'p, 'o, I> {
    /// An executor with a budget of 1000 steps, no observer and no checkpoints.
    pub fn new(problem: &'p Problem<'p>, integrator: I) -> Self {
        Executor {
            problem,
            integrator,
            max_steps: 1000,
            observer: None,
            every: 0,
            save: None,
            resume: None,
        }
    }

    /// The step budget: at most this many steps after the start (the trajectory then
    /// has at most `steps + 1` records, plus the repeated lowest state).
    pub fn max_steps(mut self, steps: usize) -> Self {
        self.max_steps = steps;
        self
    }

    /// Shows every record to `observer`, which may attach metrics or stop the run.
    pub fn observe(mut self, observer: &'o mut dyn Observer) -> Self {
        self.observer = Some(observer);
        self
    }

    /// Hands a [`Snapshot`] to `save` every `every` steps (0: never), when the state of
    /// that step is reached and before it is recorded.
    pub fn checkpoint(mut self, every: usize, save: SaveSnapshot<'o, I::State>) -> Self {
        self.every = every;
        self.save = Some(save);
        self
    }

    /// Continues from `snapshot` (one this run handed out earlier) instead of starting
    /// afresh; `None` starts afresh. The start given to [`Executor::run`] must be the
    /// original run's start.
    pub fn resume(mut self, snapshot: Option<Snapshot<I::State>>) -> Self {
        self.resume = snapshot;
        self
    }

    /// Runs from `start` (or the resumed snapshot) and returns the final state with its
    /// trajectory. A resumed run returns exactly the points, trajectory energies and info
    /// of the uninterrupted run; only the records' wall times differ.
    pub fn run(self, start: PointSet) -> Result<RunOutput> {
        let Executor {
            problem,
            integrator,
            max_steps,
            mut observer,
            every,
            mut save,
            resume,
        } = self;
        let keep_best = !problem.energy().is_smooth();
        let mut observe = |rec: &mut Record, points: &PointSet| match observer.as_mut() {
            Some(o) => o.observe(rec, points),
            None => Control::Continue,
        };
        let clock = Instant::now();
        let mut offset = 0.0;
        let (mut state, mut trajectory, mut best, mut step, mut ctl);
        // A run that resumes records the snapshot's state first.
        let mut pending: Option<(Record, bool)> = None;
        match resume {
            Some(snap) => {
                if snap.integrator != integrator.name() {
                    return Err(Error::invalid(
                        "checkpoint integrator",
                        &snap.integrator,
                        format!("a state of {}", integrator.name()),
                    ));
                }
                integrator.check_state(problem, &start, &snap.state)?;
                if snap.step == 0
                    || snap.step > max_steps
                    || snap.trajectory.len() != snap.step
                    || snap.record.step != snap.step
                {
                    return Err(Error::invalid(
                        "checkpoint step",
                        snap.step,
                        format!("a step in 1..={max_steps} with one record per earlier step"),
                    ));
                }
                if let Some(b) = &snap.best {
                    problem.check_inside("checkpoint best point", &b.points)?;
                }
                let times = [snap.seconds, snap.record.seconds];
                if !times.iter().all(|t| *t >= 0.0 && t.is_finite()) {
                    return Err(Error::invalid(
                        "checkpoint seconds",
                        snap.seconds,
                        "a finite time ≥ 0",
                    ));
                }
                offset = snap.seconds;
                state = snap.state;
                trajectory = snap.trajectory;
                best = snap.best;
                step = snap.step;
                ctl = Control::Continue;
                pending = Some((snap.record, snap.converged));
            }
            None => {
                let (s, u) = integrator.init(problem, start)?;
                state = s;
                trajectory = Vec::new();
                best = None;
                step = 0;
                let mut rec = record(0, u, 0.0, false, offset, &clock);
                ctl = observe(&mut rec, integrator.points(&state));
                note_best(keep_best, &mut best, &rec, integrator.points(&state));
                trajectory.push(rec);
            }
        }
        let stop = loop {
            let (mut rec, converged) = match pending.take() {
                Some(p) => p,
                None => {
                    if step >= max_steps {
                        break StopReason::StepBudget;
                    }
                    if ctl == Control::Stop {
                        break StopReason::Observer;
                    }
                    let (mv, converged) = match integrator.step(problem, &mut state)? {
                        Step::Ended(reason) => break reason,
                        Step::BeganAgain(u) => {
                            // The lowest state seen is kept across beginnings: it is a
                            // state the energy was evaluated at, whatever trial reached it.
                            trajectory.clear();
                            step = 0;
                            let mut rec = record(0, u, 0.0, false, offset, &clock);
                            ctl = observe(&mut rec, integrator.points(&state));
                            note_best(keep_best, &mut best, &rec, integrator.points(&state));
                            trajectory.push(rec);
                            continue;
                        }
                        Step::Moved(mv) => (mv, false),
                        Step::Converged(mv) => (mv, true),
                    };
                    step += 1;
                    let rec = record(step, mv.energy, mv.max_move, mv.restarted, offset, &clock);
                    if every > 0 && step.is_multiple_of(every) {
                        if let Some(save) = save.as_mut() {
                            save(&Snapshot {
                                step,
                                integrator: integrator.name(),
                                state: state.clone(),
                                record: rec.clone(),
                                converged,
                                trajectory: trajectory.clone(),
                                best: best.clone(),
                                seconds: offset + clock.elapsed().as_secs_f64(),
                            })?;
                        }
                    }
                    (rec, converged)
                }
            };
            ctl = observe(&mut rec, integrator.points(&state));
            note_best(keep_best, &mut best, &rec, integrator.points(&state));
            trajectory.push(rec);
            if converged {
                break StopReason::Converged;
            }
        };
        let mut points = integrator.points(&state).clone();
        if let Some(b) = best {
            if trajectory.last().is_some_and(|r| b.energy < r.energy) {
                points = b.points;
                let mut rec = record(b.step, b.energy, 0.0, false, offset, &clock);
                observe(&mut rec, &points);
                trajectory.push(rec);
            }
        }
        let returned_step = trajectory.last().map_or(0, |r| r.step);
        let mut info = vec![("returned_step".to_string(), returned_step as f64)];
        info.extend(integrator.info(&state));
        Ok(RunOutput {
            points,
            trajectory,
            stop,
            info,
        })
    }
}

fn record(
    step: usize,
    energy: f64,
    max_move: f64,
    restarted: bool,
    offset: f64,
    clock: &Instant,
) -> Record {
    Record {
        step,
        energy,
        seconds: offset + clock.elapsed().as_secs_f64(),
        max_move,
        restarted,
        metrics: Vec::new(),
    }
}

/// Keeps the lowest state seen (strictly lower replaces, so the earliest of equal states
/// is kept).
fn note_best(keep: bool, best: &mut Option<Best>, rec: &Record, points: &PointSet) {
    if keep && best.as_ref().is_none_or(|b| rec.energy < b.energy) {
        *best = Some(Best {
            energy: rec.energy,
            step: rec.step,
            points: points.clone(),
        });
    }
}
