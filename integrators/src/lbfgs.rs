//! argmin's L-BFGS as an [`Integrator`], over the same energies and domains as the DEM.
//!
//! L-BFGS minimises the energy directly instead of letting the points settle under
//! damping: it is the comparison solver of the design notes, and on smooth energies it
//! usually reaches a much smaller gradient in far fewer energy evaluations. It runs
//! [`argmin`]'s `LBFGS` with the More–Thuente line search on `nalgebra::DVector<f64>`; the
//! point set is copied to and from the flat [`PointSet`] buffer only where argmin hands a
//! vector over.
//!
//! # What the line search may evaluate
//!
//! argmin's iterates and line-search trials live in R^{n·s} and may leave the domain, but
//! the energies are only meaningful for points inside (the boundary-aware energies, for
//! one, measure an *unsigned* distance to the boundary). So the problem given to argmin is
//! the composite f(P(x)): P applies [`Domain::bring_back`] to every point of the argument
//! that lies outside, and the energy is evaluated only at P(x), which is inside. Every
//! state that is recorded, shown to the observer or returned is such a P(x).
//!
//! - **Periodic domain** ([`Domain::is_periodic`], the torus). P wraps coordinates back by
//!   integers. The torus energies (U_{q,p} with a q-distance or the torus distance,
//!   U_{E,∞} with the torus distance) are periodic, so f∘P = f: L-BFGS optimises freely in
//!   R^{n·s}, its curvature pairs are never disturbed by a wrap, and ∇(f∘P) = (∇f)∘P
//!   exactly, since P is locally a translation. An energy that is not periodic (U_{q,p}
//!   with the Euclidean distance) jumps where a point crosses a face; the line search
//!   then fails there and the run restarts as at a kink (below).
//! - **Bounded region** (shapes, implicit regions, the closed unit cube of the
//!   discrepancy energies). P is the domain's projection back inside (for the shapes,
//!   the closest point moved 1e-9 of the diameter inwards). While every point of the
//!   iterate is inside, P is the identity and L-BFGS sees f itself. When an accepted
//!   iterate has points outside, the recorded state is P(x), whose energy is exactly the
//!   cost the line search accepted, and L-BFGS goes on over f∘P; once the chunk has run
//!   [`PROJECTION_CHUNK`] iterations with points outside, the iterate is replaced by P(x)
//!   and L-BFGS restarts from there with an empty memory, whose curvature pairs mixed the
//!   two sides of the kink that P puts at the boundary. For a point that P moves, the
//!   gradient handed to argmin is ∇f at P(x) without its component along x_i − P(x_i):
//!   a projection is constant along the outward normal, so this is J_Pᵀ∇f up to the
//!   curvature factor of the boundary (r/|x − c| for a ball, close to 1 at the wall),
//!   and the line search is not told that moving further out helps.
//!
//! # Kinks, stalls and restarts
//!
//! Max-type energies (U_{E,∞}, U_{E,∞,g}) and the discrepancies (kinks where two points
//! share a coordinate) stop L-BFGS early: its line search fails, or an iteration makes
//! no progress. The treatment does not depend on [`Energy::is_smooth`], so an energy that
//! misreports it is still handled. A stalled chunk ends without error; when the line
//! search failed or ended on a point above the previous state (More–Thuente's "unusual
//! termination" returns its last trial, not its best), the lowest trial it evaluated is
//! taken instead if it is below the previous state. L-BFGS then restarts with an empty
//! memory from the best state so far. The run ends as converged when a whole chunk lowers
//! the energy by no more than `tol_cost` relative (a restart that gives no progress), and
//! as out of budget after `max_restarts` such restarts. Projection restarts (above) do
//! not count against `max_restarts`: each follows [`PROJECTION_CHUNK`] accepted
//! iterations, so the iteration budget bounds them.
//!
//! Safeguards, each ending the chunk as a stall: a line search that needs more than
//! [`MAX_EVALUATIONS_PER_ITERATION`] energy evaluations (argmin's More–Thuente search has
//! no cap of its own); a non-finite argument, energy or gradient (argmin is told by an
//! error, which ends its line search; the start alone is refused with
//! [`Error::Numerical`]); an iterate that does not move (a zero step would make L-BFGS's
//! next curvature pair 0/0).
//!
//! # Step scale
//!
//! The first iteration of a chunk has no curvature information: argmin tries the step
//! −∇f with length 1, which in the energy's own units may move a point by thousands of box
//! lengths. The cost handed to argmin is therefore scaled per chunk so that this first
//! trial moves the fastest coordinate by a chosen length: [`FIRST_STEP`] of the typical
//! spacing (volume of the bounding box / n)^{1/s} for the first chunk, and for a restart
//! twice the last accepted move, capped by the same length. The last move measures the
//! scale on which the energy currently changes (near a discrepancy's kinks it is about
//! 1/n, far below the spacing); twice it lets the line search grow. Later steps use the
//! curvature pairs, whose scaling γ = sᵀy/yᵀy cancels a constant factor of the cost, so
//! the scale changes nothing else. Records and tolerances use the unscaled energy.
//!
//! # Trajectory
//!
//! One [`Record`] per accepted L-BFGS iteration: `step` counts accepted iterations over
//! all chunks, `max_move` is the largest coordinate change from the previous state (on the
//! torus measured before wrapping, so a wrap is not a move of one box length) and
//! `restarted` marks the first record of a chunk after a restart. The first record is the
//! start (step 0); accepted energies never rise, so the last record is the lowest state
//! seen, and it is the one returned. [`RunOutput::info`] reports `iterations`, `restarts`
//! (with `projection_restarts` and `stall_restarts`), `line_search_failures`,
//! `evaluations` (energy evaluations, each value and gradient), `start_grad_norm` and
//! `final_grad_norm` (max-norms of the gradient L-BFGS sees).
//!
//! The run is sequential apart from the energy, whose evaluations are deterministic, so
//! the result has the same bits for any number of rayon threads.

use crate::{Control, Integrator, Observer, Record, RunOutput, StopReason};
use argmin::core::{
    CostFunction, Error as ArgminError, Executor, Gradient, IterState, OptimizationResult, State,
    TerminationReason, TerminationStatus,
};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::LBFGS;
use nalgebra::DVector;
use std::cell::RefCell;
use std::fmt;
use std::time::Instant;
use stillpoint_energies::{Domain, Energy, Error, PointSet, Result};

/// The first trial step of the first chunk moves the fastest coordinate by this fraction
/// of the typical spacing (and a restart's by at most this): small enough not to jump
/// over neighbours, and More–Thuente extrapolates (by up to 5× per trial) when it is too
/// short.
pub const FIRST_STEP: f64 = 0.1;

/// In a bounded region, L-BFGS goes on over f∘P while some points of its iterate are
/// outside, for at least this many iterations of a chunk; then the iterate is projected
/// and L-BFGS restarts from P(x). Long enough for the memory (m = 10 by default) to fill
/// and be used; short enough that points outside, where P flattens the energy, do not
/// stay there long. Measured on a ball with U_{q,p} (Euclidean), which presses points onto
/// the wall: restarting at every exit (a chunk of 1) left U 1.7 % higher after 4× the
/// iterations; chunks of 20 and 100 ended alike.
pub const PROJECTION_CHUNK: usize = 20;

/// The most energy evaluations one L-BFGS iteration (its line search) may use before the
/// chunk is abandoned as stalled. More–Thuente needs one to three on smooth energies.
pub const MAX_EVALUATIONS_PER_ITERATION: usize = 64;

/// L-BFGS (argmin, More–Thuente line search) with projection and restarts; see the
/// module documentation for the treatment of domains and kinks.
#[derive(Debug, Clone, PartialEq)]
pub struct Lbfgs {
    /// Budget of accepted L-BFGS iterations over all restarts (the trajectory has at most
    /// this many records after the start).
    pub iterations: usize,
    /// Number m of curvature pairs kept (≥ 1).
    pub memory: usize,
    /// Converged when the max-norm of the gradient falls to `tol_grad` times its value at
    /// the start (relative, so it does not depend on the energy's units; 0 disables).
    pub tol_grad: f64,
    /// An iteration that lowers the energy by at most `tol_cost`·|U| ends its chunk; a
    /// chunk that does so in total ends the run as converged (relative; 0 means only an
    /// exact standstill counts).
    pub tol_cost: f64,
    /// Restarts allowed after stalls (line-search failures, kinks); restarts after a
    /// projection back into a region are not counted.
    pub max_restarts: usize,
}

impl Default for Lbfgs {
    fn default() -> Self {
        Lbfgs {
            iterations: 1000,
            memory: 10,
            tol_grad: 1e-10,
            // About 50 ulps: a smaller relative decrease is rounding, not progress.
            tol_cost: 1e-14,
            max_restarts: 20,
        }
    }
}

impl Lbfgs {
    fn validate(&self, domain: &dyn Domain, start: &PointSet) -> Result<()> {
        crate::check_start(domain, start)?;
        if self.memory == 0 {
            return Err(Error::invalid(
                "L-BFGS memory",
                self.memory,
                "at least 1 curvature pair",
            ));
        }
        let tolerance = |name: &str, v: f64| {
            if v >= 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(Error::invalid(name, v, "a finite number ≥ 0"))
            }
        };
        tolerance("L-BFGS tol_grad", self.tol_grad)?;
        tolerance("L-BFGS tol_cost", self.tol_cost)
    }
}

/// Why the composite could not be evaluated at an argument.
#[derive(Debug)]
enum Failure {
    NonFiniteArgument,
    NotBroughtBack(usize),
    NonFiniteEnergy(f64),
    NonFiniteGradient,
    TooManyEvaluations,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::NonFiniteArgument => write!(f, "a trial state has a non-finite coordinate"),
            Failure::NotBroughtBack(i) => {
                write!(f, "the domain could not bring point {} back inside", i + 1)
            }
            Failure::NonFiniteEnergy(u) => write!(f, "the energy of a trial state is {u}"),
            Failure::NonFiniteGradient => {
                write!(f, "the gradient of a trial state is not finite")
            }
            Failure::TooManyEvaluations => write!(
                f,
                "the line search used more than {MAX_EVALUATIONS_PER_ITERATION} evaluations"
            ),
        }
    }
}

/// Evaluates f(P(x)) and its gradient, keeping the last argument so that argmin's cost
/// and gradient calls at one point (More–Thuente asks for both) cost one evaluation.
struct Evaluator<'a> {
    energy: &'a dyn Energy,
    domain: &'a dyn Domain,
    periodic: bool,
    /// The last argument x, valid when `valid`.
    param: Vec<f64>,
    valid: bool,
    /// P(x).
    points: PointSet,
    /// The gradient handed to argmin (unscaled).
    grad: Vec<f64>,
    /// f(P(x)).
    value: f64,
    /// Whether P moved some point (x had a point outside).
    moved: bool,
    /// The `prev` argument of `bring_back`, which nothing here reads back.
    scratch: Vec<f64>,
    evaluations: usize,
    /// Evaluations left to the current iteration.
    calls_left: usize,
    /// The lowest energy evaluated in the current iteration, if below its start, and
    /// where.
    trial_value: f64,
    trial_param: Vec<f64>,
    has_trial: bool,
}

impl<'a> Evaluator<'a> {
    fn new(energy: &'a dyn Energy, domain: &'a dyn Domain, start: &PointSet) -> Self {
        Evaluator {
            energy,
            domain,
            periodic: domain.is_periodic(),
            param: start.as_slice().to_vec(),
            valid: false,
            points: start.clone(),
            grad: vec![0.0; start.len()],
            value: f64::NAN,
            moved: false,
            scratch: vec![0.0; start.s()],
            evaluations: 0,
            calls_left: 0,
            trial_value: f64::NEG_INFINITY,
            trial_param: start.as_slice().to_vec(),
            has_trial: false,
        }
    }

    /// Resets the per-iteration evaluation cap and the best trial, which must beat `u`.
    fn begin_iteration(&mut self, u: f64) {
        self.calls_left = MAX_EVALUATIONS_PER_ITERATION;
        self.trial_value = u;
        self.has_trial = false;
    }

    /// The argument of the lowest energy evaluated in this iteration, if it beat the start.
    /// Allows the one evaluation needed to bring the cache back to it.
    fn take_best_trial(&mut self) -> Option<Vec<f64>> {
        if !self.has_trial {
            return None;
        }
        self.has_trial = false;
        self.calls_left = self.calls_left.max(1);
        Some(self.trial_param.clone())
    }

    /// Makes the cache describe x.
    fn evaluate(&mut self, x: &[f64]) -> std::result::Result<(), Failure> {
        if self.valid
            && x.len() == self.param.len()
            && x.iter()
                .zip(&self.param)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        {
            return Ok(());
        }
        self.valid = false;
        if self.calls_left == 0 {
            return Err(Failure::TooManyEvaluations);
        }
        self.calls_left -= 1;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Failure::NonFiniteArgument);
        }
        self.param.copy_from_slice(x);
        self.points.as_mut_slice().copy_from_slice(x);
        let s = self.points.s();
        self.moved = false;
        for (i, row) in self.points.as_mut_slice().chunks_exact_mut(s).enumerate() {
            if self.domain.contains(row) {
                continue;
            }
            self.scratch.copy_from_slice(row);
            self.domain.bring_back(row, &mut self.scratch);
            if !(self.domain.contains(row) && row.iter().all(|v| v.is_finite())) {
                return Err(Failure::NotBroughtBack(i));
            }
            self.moved = true;
        }
        self.evaluations += 1;
        // The trait says the gradient is written, not added; zeroing first keeps an
        // energy that accumulates into its buffer from carrying one trial into the next.
        self.grad.fill(0.0);
        self.value = self.energy.value_and_gradient(&self.points, &mut self.grad);
        if !self.value.is_finite() {
            return Err(Failure::NonFiniteEnergy(self.value));
        }
        if self.grad.iter().any(|g| !g.is_finite()) {
            return Err(Failure::NonFiniteGradient);
        }
        if self.moved && !self.periodic {
            self.drop_normal_components();
        }
        self.valid = true;
        if self.value < self.trial_value {
            self.trial_value = self.value;
            self.trial_param.copy_from_slice(x);
            self.has_trial = true;
        }
        Ok(())
    }

    /// Removes from each projected point's gradient its component along x_i − P(x_i),
    /// the direction in which f∘P is flat.
    fn drop_normal_components(&mut self) {
        let s = self.points.s();
        let pts = self.points.as_slice();
        for ((g, x), p) in self
            .grad
            .chunks_exact_mut(s)
            .zip(self.param.chunks_exact(s))
            .zip(pts.chunks_exact(s))
        {
            let norm2: f64 = x.iter().zip(p).map(|(a, b)| (a - b) * (a - b)).sum();
            if norm2 == 0.0 {
                continue;
            }
            let along: f64 = g.iter().zip(x).zip(p).map(|((g, a), b)| g * (a - b)).sum();
            let c = along / norm2;
            for ((g, a), b) in g.iter_mut().zip(x).zip(p) {
                *g -= c * (a - b);
            }
        }
    }
}

/// The problem argmin sees: f∘P, scaled by a per-chunk constant (see "Step scale").
struct Composite<'w, 'a> {
    work: &'w RefCell<Evaluator<'a>>,
    scale: f64,
}

fn argmin_error(f: Failure) -> ArgminError {
    ArgminError::msg(f.to_string())
}

impl CostFunction for Composite<'_, '_> {
    type Param = DVector<f64>;
    type Output = f64;

    fn cost(&self, x: &Self::Param) -> std::result::Result<f64, ArgminError> {
        let mut w = self.work.borrow_mut();
        w.evaluate(x.as_slice()).map_err(argmin_error)?;
        Ok(w.value * self.scale)
    }
}

impl Gradient for Composite<'_, '_> {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;

    fn gradient(&self, x: &Self::Param) -> std::result::Result<Self::Gradient, ArgminError> {
        let mut w = self.work.borrow_mut();
        w.evaluate(x.as_slice()).map_err(argmin_error)?;
        Ok(DVector::from_iterator(
            w.grad.len(),
            w.grad.iter().map(|g| g * self.scale),
        ))
    }
}

type Solver =
    LBFGS<MoreThuenteLineSearch<DVector<f64>, DVector<f64>, f64>, DVector<f64>, DVector<f64>, f64>;
type Iterate = IterState<DVector<f64>, DVector<f64>, (), (), (), f64>;

/// How a chunk of L-BFGS iterations ended, when the run goes on.
enum ChunkEnd {
    /// The iterate still had points outside the region after [`PROJECTION_CHUNK`]
    /// iterations; restart from its projection.
    Projected,
    /// The line search failed or progress stopped; restart from the best state.
    Stalled,
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// (volume of the bounding box / n)^{1/s}, the spacing of n evenly spread points.
fn typical_spacing(domain: &dyn Domain, n: usize) -> f64 {
    let (lo, hi) = domain.bounding_box();
    let widths: Vec<f64> = lo.iter().zip(&hi).map(|(l, h)| h - l).collect();
    let s = widths.len().max(1) as f64;
    let volume: f64 = widths.iter().product();
    let h = (volume / n as f64).powf(1.0 / s);
    if h > 0.0 && h.is_finite() {
        h
    } else {
        let w = max_abs(&widths);
        if w > 0.0 && w.is_finite() {
            w / (n as f64).powf(1.0 / s)
        } else {
            1.0
        }
    }
}

impl Integrator for Lbfgs {
    fn name(&self) -> String {
        format!("L-BFGS(m={})", self.memory)
    }

    fn run(
        &self,
        energy: &dyn Energy,
        domain: &dyn Domain,
        start: PointSet,
        observer: &mut dyn Observer,
    ) -> Result<RunOutput> {
        self.validate(domain, &start)?;
        let clock = Instant::now();
        let periodic = domain.is_periodic();
        let work = RefCell::new(Evaluator::new(energy, domain, &start));
        let (u0, gnorm0) = {
            let mut w = work.borrow_mut();
            w.calls_left = 1;
            match w.evaluate(start.as_slice()) {
                Ok(()) => (w.value, max_abs(&w.grad)),
                Err(Failure::NonFiniteEnergy(u)) => {
                    return Err(Error::Numerical(format!(
                        "the energy {} of the start is not finite ({u}): two points coincide, \
                         a point is on the boundary, or p is too small for this n (the \
                         energy overflows)",
                        energy.name()
                    )))
                }
                Err(e) => {
                    return Err(Error::Numerical(format!(
                        "cannot start L-BFGS with the energy {}: {e}",
                        energy.name()
                    )))
                }
            }
        };
        let spacing = typical_spacing(domain, start.n());
        let gtol = self.tol_grad * gnorm0;

        let mut cur = start;
        let mut trajectory: Vec<Record> = Vec::with_capacity(self.iterations.min(100_000) + 1);
        let mut rec = Record {
            step: 0,
            energy: u0,
            seconds: clock.elapsed().as_secs_f64(),
            max_move: 0.0,
            restarted: false,
            metrics: Vec::new(),
        };
        let ctl = observer.observe(&mut rec, &cur);
        trajectory.push(rec);

        let mut gnorm = gnorm0;
        let mut total = 0usize;
        let (mut projection_restarts, mut stall_restarts, mut failures) = (0usize, 0usize, 0usize);
        let mut pending_restart = false;
        // Largest coordinate move of a chunk's first trial (see "Step scale").
        let mut first_move = FIRST_STEP * spacing;
        let stop = if self.iterations == 0 {
            StopReason::StepBudget
        } else if ctl == Control::Stop {
            StopReason::Observer
        } else if gnorm <= gtol {
            StopReason::Converged
        } else {
            'run: loop {
                // A chunk: L-BFGS with an empty memory from `cur`, which is inside.
                let x0 = cur.as_slice().to_vec();
                let (u_start, scale, g_start) = {
                    let mut w = work.borrow_mut();
                    w.calls_left = 1;
                    w.evaluate(&x0).map_err(|e| {
                        Error::Numerical(format!(
                            "cannot restart L-BFGS at a state it has already visited: {e}"
                        ))
                    })?;
                    let g = max_abs(&w.grad);
                    let scale = if g > 0.0 { first_move / g } else { 1.0 };
                    let gv = DVector::from_iterator(w.grad.len(), w.grad.iter().map(|v| v * scale));
                    (w.value, scale, gv)
                };
                let mut solver: Option<Solver> = Some(
                    LBFGS::new(MoreThuenteLineSearch::new(), self.memory)
                        .with_tolerance_grad(0.0)
                        .and_then(|l| l.with_tolerance_cost(0.0))
                        .map_err(|e| Error::Numerical(format!("argmin L-BFGS: {e}")))?,
                );
                let mut problem = Some(Composite { work: &work, scale });
                let mut state: Option<Iterate> = Some(
                    IterState::new()
                        .param(DVector::from_vec(x0.clone()))
                        .cost(u_start * scale)
                        .gradient(g_start)
                        .max_iters(1),
                );
                let mut prev_raw = x0;
                let mut u_prev = u_start;
                let mut chunk_len = 0usize;
                let end = loop {
                    // One iteration per executor run: the observer and the stopping rules
                    // act between iterations with full access to the caller's observer,
                    // which argmin's own observers (held as 'static) could not borrow.
                    let (Some(p), Some(sv), Some(st)) =
                        (problem.take(), solver.take(), state.take())
                    else {
                        break ChunkEnd::Stalled;
                    };
                    work.borrow_mut().begin_iteration(u_prev);
                    let result = Executor::new(p, sv).configure(|_| st).ctrlc(false).run();
                    // L-BFGS's new iterate, with what it needs to go on from there.
                    let mut proposal = None;
                    match result {
                        Ok(OptimizationResult {
                            problem: p,
                            solver: sv,
                            state: st,
                        }) => {
                            if let TerminationStatus::Terminated(TerminationReason::SolverExit(_)) =
                                st.get_termination_status()
                            {
                                failures += 1;
                            } else if let Some(x) = st.get_param() {
                                proposal = Some((x.as_slice().to_vec(), p, sv, st));
                            }
                        }
                        Err(_) => failures += 1,
                    }
                    let mut w = work.borrow_mut();
                    let mut carry = None;
                    let mut next = None;
                    w.calls_left = w.calls_left.max(1);
                    if let Some((x, p, sv, st)) = proposal {
                        if w.evaluate(&x).is_ok() && w.value <= u_prev {
                            next = Some(x);
                            carry = Some((p, sv, st));
                        }
                    }
                    if next.is_none() {
                        // The line search failed or ended on a worse point, but it may have
                        // seen a lower one on the way: take that, then restart.
                        if let Some(t) = w.take_best_trial() {
                            if w.evaluate(&t).is_ok() {
                                next = Some(t);
                            }
                        }
                    }
                    let Some(x) = next else {
                        break ChunkEnd::Stalled;
                    };
                    let u = w.value;
                    let max_move = if periodic {
                        x.iter()
                            .zip(&prev_raw)
                            .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
                    } else {
                        w.points
                            .as_slice()
                            .iter()
                            .zip(cur.as_slice())
                            .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
                    };
                    if max_move == 0.0 {
                        break ChunkEnd::Stalled;
                    }
                    total += 1;
                    first_move = (2.0 * max_move).min(FIRST_STEP * spacing);
                    cur.as_mut_slice().copy_from_slice(w.points.as_slice());
                    gnorm = max_abs(&w.grad);
                    let left_region = w.moved && !periodic;
                    drop(w);
                    let mut rec = Record {
                        step: total,
                        energy: u,
                        seconds: clock.elapsed().as_secs_f64(),
                        max_move,
                        restarted: pending_restart,
                        metrics: Vec::new(),
                    };
                    pending_restart = false;
                    let ctl = observer.observe(&mut rec, &cur);
                    trajectory.push(rec);
                    if ctl == Control::Stop {
                        break 'run StopReason::Observer;
                    }
                    if gnorm <= gtol {
                        break 'run StopReason::Converged;
                    }
                    if total == self.iterations {
                        break 'run StopReason::StepBudget;
                    }
                    let small = u_prev - u <= self.tol_cost * u_prev.abs();
                    u_prev = u;
                    let Some((mut p, sv, mut st)) = carry else {
                        break ChunkEnd::Stalled;
                    };
                    if small {
                        break ChunkEnd::Stalled;
                    }
                    chunk_len += 1;
                    if left_region && chunk_len >= PROJECTION_CHUNK {
                        break ChunkEnd::Projected;
                    }
                    prev_raw.copy_from_slice(&x);
                    let iter = st.get_iter();
                    st.termination_status = TerminationStatus::NotTerminated;
                    problem = p.take_problem();
                    solver = Some(sv);
                    state = Some(st.max_iters(iter + 1));
                };
                match end {
                    ChunkEnd::Projected => projection_restarts += 1,
                    ChunkEnd::Stalled => {
                        if u_start - u_prev <= self.tol_cost * u_start.abs() {
                            break 'run StopReason::Converged;
                        }
                        if stall_restarts == self.max_restarts {
                            break 'run StopReason::StepBudget;
                        }
                        stall_restarts += 1;
                    }
                }
                pending_restart = true;
            }
        };
        let evaluations = work.borrow().evaluations;
        let info = vec![
            ("iterations".to_string(), total as f64),
            (
                "restarts".to_string(),
                (projection_restarts + stall_restarts) as f64,
            ),
            (
                "projection_restarts".to_string(),
                projection_restarts as f64,
            ),
            ("stall_restarts".to_string(), stall_restarts as f64),
            ("line_search_failures".to_string(), failures as f64),
            ("evaluations".to_string(), evaluations as f64),
            ("start_grad_norm".to_string(), gnorm0),
            ("final_grad_norm".to_string(), gnorm),
        ];
        Ok(RunOutput {
            points: cur,
            trajectory,
            stop,
            info,
        })
    }
}
