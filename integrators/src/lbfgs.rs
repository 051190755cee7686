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
//! P is [`Domain::bring_back`], a projection of any point of R^s, not the
//! [`Domain::keep_inside`] rule the DEM steps with (shorten a step that leaves, from the
//! point it left): the halving rule depends on where a point came from, so f∘P would be a
//! different function at every iterate and L-BFGS's curvature pairs would compare values
//! of different functions; a projection is one fixed map for the whole line search. On the
//! torus the two are the same wrap.
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
//! One [`Record`](crate::Record) per accepted L-BFGS iteration: `step` counts accepted iterations over
//! all chunks, `max_move` is the largest coordinate change from the previous state (on the
//! torus measured before wrapping, so a wrap is not a move of one box length) and
//! `restarted` marks the first record of a chunk after a restart. The first record is the
//! start (step 0); accepted energies never rise, so the last record is the lowest state
//! seen, and it is the one returned. [`RunOutput::info`](crate::RunOutput::info) reports `iterations`, `restarts`
//! (with `projection_restarts` and `stall_restarts`), `line_search_failures`,
//! `evaluations` (energy evaluations, each value and gradient), `start_grad_norm` and
//! `final_grad_norm` (max-norms of the gradient L-BFGS sees).
//!
//! The run is sequential apart from the energy, whose evaluations are deterministic, so
//! the result has the same bits for any number of rayon threads.

use crate::{Integrator, Move, Problem, Step, StopReason};
use argmin::core::{
    CostFunction, Error as ArgminError, Executor, Gradient, IterState, OptimizationResult, State,
    TerminationReason, TerminationStatus,
};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::LBFGS;
use nalgebra::DVector;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::cell::RefCell;
use std::fmt;
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
/// module documentation for the treatment of domains and kinks. Its budget of accepted
/// iterations over all restarts is the executor's step budget.
#[derive(Debug, Clone, PartialEq)]
pub struct Lbfgs {
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
            memory: 10,
            tol_grad: 1e-10,
            // About 50 ulps: a smaller relative decrease is rounding, not progress.
            tol_cost: 1e-14,
            max_restarts: 20,
        }
    }
}

impl Lbfgs {
    fn validate(&self) -> Result<()> {
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

/// What the evaluator keeps between calls: the last argument and what it gave, the
/// evaluation counters and the best trial of the current iteration. Part of the L-BFGS
/// state, so that a resumed run counts and caches exactly as the uninterrupted one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct EvalCache {
    /// The last argument x, valid when `valid`.
    param: Vec<f64>,
    valid: bool,
    /// P(x).
    points: PointSet,
    /// The gradient handed to argmin (unscaled).
    grad: Vec<f64>,
    /// f(P(x)).
    #[serde(with = "crate::json_f64")]
    value: f64,
    /// Whether P moved some point (x had a point outside).
    moved: bool,
    evaluations: usize,
    /// Evaluations left to the current iteration.
    calls_left: usize,
    /// The lowest energy evaluated in the current iteration, if below its start, and
    /// where.
    #[serde(with = "crate::json_f64")]
    trial_value: f64,
    trial_param: Vec<f64>,
    has_trial: bool,
}

impl EvalCache {
    fn new(start: &PointSet) -> Self {
        EvalCache {
            param: start.as_slice().to_vec(),
            valid: false,
            points: start.clone(),
            grad: vec![0.0; start.coordinate_count()],
            value: f64::NAN,
            moved: false,
            evaluations: 0,
            calls_left: 0,
            trial_value: f64::NEG_INFINITY,
            trial_param: start.as_slice().to_vec(),
            has_trial: false,
        }
    }
}

/// Evaluates f(P(x)) and its gradient, keeping the last argument so that argmin's cost
/// and gradient calls at one point (More–Thuente asks for both) cost one evaluation.
struct Evaluator<'a> {
    energy: &'a dyn Energy,
    domain: &'a dyn Domain,
    periodic: bool,
    /// The `prev` argument of `bring_back`, which nothing here reads back.
    scratch: Vec<f64>,
    c: EvalCache,
}

impl<'a> Evaluator<'a> {
    fn new(problem: &'a Problem<'a>, c: EvalCache) -> Self {
        let domain = problem.domain();
        Evaluator {
            energy: problem.energy(),
            domain,
            periodic: domain.is_periodic(),
            scratch: vec![0.0; c.points.s()],
            c,
        }
    }

    /// Resets the per-iteration evaluation cap and the best trial, which must beat `u`.
    fn begin_iteration(&mut self, u: f64) {
        self.c.calls_left = MAX_EVALUATIONS_PER_ITERATION;
        self.c.trial_value = u;
        self.c.has_trial = false;
    }

    /// The argument of the lowest energy evaluated in this iteration, if it beat the start.
    /// Allows the one evaluation needed to bring the cache back to it.
    fn take_best_trial(&mut self) -> Option<Vec<f64>> {
        if !self.c.has_trial {
            return None;
        }
        self.c.has_trial = false;
        self.c.calls_left = self.c.calls_left.max(1);
        Some(self.c.trial_param.clone())
    }

    /// Makes the cache describe x.
    fn evaluate(&mut self, x: &[f64]) -> std::result::Result<(), Failure> {
        if self.c.valid
            && x.len() == self.c.param.len()
            && x.iter()
                .zip(&self.c.param)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        {
            return Ok(());
        }
        self.c.valid = false;
        if self.c.calls_left == 0 {
            return Err(Failure::TooManyEvaluations);
        }
        self.c.calls_left -= 1;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Failure::NonFiniteArgument);
        }
        self.c.param.copy_from_slice(x);
        self.c.points.as_mut_slice().copy_from_slice(x);
        let s = self.c.points.s();
        self.c.moved = false;
        for (i, row) in self.c.points.as_mut_slice().chunks_exact_mut(s).enumerate() {
            if self.domain.contains(row) {
                continue;
            }
            self.scratch.copy_from_slice(row);
            self.domain.bring_back(row, &mut self.scratch);
            if !(self.domain.contains(row) && row.iter().all(|v| v.is_finite())) {
                return Err(Failure::NotBroughtBack(i));
            }
            self.c.moved = true;
        }
        self.c.evaluations += 1;
        // The trait says the gradient is written, not added; zeroing first keeps an
        // energy that accumulates into its buffer from carrying one trial into the next.
        self.c.grad.fill(0.0);
        self.c.value = self
            .energy
            .value_and_gradient(&self.c.points, &mut self.c.grad);
        if !self.c.value.is_finite() {
            return Err(Failure::NonFiniteEnergy(self.c.value));
        }
        if self.c.grad.iter().any(|g| !g.is_finite()) {
            return Err(Failure::NonFiniteGradient);
        }
        if self.c.moved && !self.periodic {
            self.drop_normal_components();
        }
        self.c.valid = true;
        if self.c.value < self.c.trial_value {
            self.c.trial_value = self.c.value;
            self.c.trial_param.copy_from_slice(x);
            self.c.has_trial = true;
        }
        Ok(())
    }

    /// Removes from each projected point's gradient its component along x_i − P(x_i),
    /// the direction in which f∘P is flat.
    fn drop_normal_components(&mut self) {
        let s = self.c.points.s();
        let pts = self.c.points.as_slice();
        for ((g, x), p) in self
            .c
            .grad
            .chunks_exact_mut(s)
            .zip(self.c.param.chunks_exact(s))
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
        Ok(w.c.value * self.scale)
    }
}

impl Gradient for Composite<'_, '_> {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;

    fn gradient(&self, x: &Self::Param) -> std::result::Result<Self::Gradient, ArgminError> {
        let mut w = self.work.borrow_mut();
        w.evaluate(x.as_slice()).map_err(argmin_error)?;
        Ok(DVector::from_iterator(
            w.c.grad.len(),
            w.c.grad.iter().map(|g| g * self.scale),
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

/// argmin's solver and iterate between two iterations of a chunk. They hold ±∞ (the best
/// cost before any), which JSON cannot, so they are kept as the hexadecimal digits of
/// their postcard encoding, which keeps every f64 bit.
#[derive(Clone)]
struct Carry {
    solver: Solver,
    iterate: Iterate,
}

impl Serialize for Carry {
    fn serialize<S: Serializer>(&self, ser: S) -> std::result::Result<S::Ok, S::Error> {
        let bytes = postcard::to_allocvec(&(&self.solver, &self.iterate))
            .map_err(serde::ser::Error::custom)?;
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        ser.serialize_str(&hex)
    }
}

impl<'de> Deserialize<'de> for Carry {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        let hex = String::deserialize(de)?;
        if hex.len() % 2 != 0 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(serde::de::Error::custom(
                "argmin state: not hexadecimal digits",
            ));
        }
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap_or(0))
            .collect();
        let (solver, iterate): (Solver, Iterate) =
            postcard::from_bytes(&bytes).map_err(serde::de::Error::custom)?;
        Ok(Carry { solver, iterate })
    }
}

/// A chunk: L-BFGS with an empty memory from the state it began at.
#[derive(Clone, Serialize, Deserialize)]
struct Chunk {
    /// The constant the cost is scaled by (see "Step scale").
    scale: f64,
    /// The energy where the chunk began.
    u_start: f64,
    /// The energy of the last accepted state.
    u_prev: f64,
    /// The last accepted argument, before any wrap.
    prev_raw: Vec<f64>,
    /// Accepted iterations of the chunk.
    len: usize,
    /// argmin's solver and iterate, when the last iteration can be continued.
    carry: Option<Carry>,
    /// Whether the last accepted state had points outside a bounded region.
    left_region: bool,
    /// Whether the last accepted state still awaits the checks that decide how the
    /// chunk goes on (made when the next step is asked for, so that a run that ends at
    /// that state counts nothing more).
    pending: bool,
}

/// Everything L-BFGS needs to continue bit for bit: the accepted state, the counters, the
/// current chunk with argmin's solver and iterate, and the evaluator's cache.
#[derive(Clone, Serialize, Deserialize)]
pub struct LbfgsState {
    current: PointSet,
    gnorm0: f64,
    gnorm: f64,
    gtol: f64,
    spacing: f64,
    first_move: f64,
    total: usize,
    projection_restarts: usize,
    stall_restarts: usize,
    failures: usize,
    pending_restart: bool,
    fresh: bool,
    chunk: Option<Chunk>,
    cache: EvalCache,
}

impl std::fmt::Debug for LbfgsState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LbfgsState")
            .field("iterations", &self.total)
            .field("evaluations", &self.cache.evaluations)
            .finish_non_exhaustive()
    }
}

/// How a chunk ended: the run goes on with a restart, or ends.
enum AfterChunk {
    Restart,
    End(StopReason),
}

impl Lbfgs {
    /// The checks after an accepted state that the original loop made before its next
    /// iteration: stop the chunk at a small decrease, at a lost carry, or after
    /// [`PROJECTION_CHUNK`] iterations with points outside.
    fn settle(&self, st: &mut LbfgsState) -> Option<ChunkEnd> {
        let chunk = st.chunk.as_mut()?;
        if !chunk.pending {
            return None;
        }
        chunk.pending = false;
        let u = st.cache.value;
        let small = chunk.u_prev - u <= self.tol_cost * chunk.u_prev.abs();
        chunk.u_prev = u;
        if chunk.carry.is_none() || small {
            return Some(ChunkEnd::Stalled);
        }
        chunk.len += 1;
        if chunk.left_region && chunk.len >= PROJECTION_CHUNK {
            return Some(ChunkEnd::Projected);
        }
        None
    }

    fn end_chunk(&self, st: &mut LbfgsState, end: ChunkEnd) -> AfterChunk {
        let Some(chunk) = st.chunk.take() else {
            return AfterChunk::Restart;
        };
        match end {
            ChunkEnd::Projected => st.projection_restarts += 1,
            ChunkEnd::Stalled => {
                if chunk.u_start - chunk.u_prev <= self.tol_cost * chunk.u_start.abs() {
                    return AfterChunk::End(StopReason::Converged);
                }
                if st.stall_restarts == self.max_restarts {
                    return AfterChunk::End(StopReason::StepBudget);
                }
                st.stall_restarts += 1;
            }
        }
        st.pending_restart = true;
        AfterChunk::Restart
    }

    /// Begins a chunk at the current state.
    fn begin_chunk(&self, problem: &Problem<'_>, st: &mut LbfgsState) -> Result<()> {
        let x0 = st.current.as_slice().to_vec();
        let mut w = Evaluator::new(
            problem,
            std::mem::replace(&mut st.cache, EvalCache::empty()),
        );
        w.c.calls_left = 1;
        let evaluated = w.evaluate(&x0);
        let g = max_abs(&w.c.grad);
        let scale = if g > 0.0 { st.first_move / g } else { 1.0 };
        let gv = DVector::from_iterator(w.c.grad.len(), w.c.grad.iter().map(|v| v * scale));
        let u_start = w.c.value;
        st.cache = w.c;
        evaluated.map_err(|e| {
            Error::Numerical(format!(
                "cannot restart L-BFGS at a state it has already visited: {e}"
            ))
        })?;
        let solver = LBFGS::new(MoreThuenteLineSearch::new(), self.memory)
            .with_tolerance_grad(0.0)
            .and_then(|l| l.with_tolerance_cost(0.0))
            .map_err(|e| Error::Numerical(format!("argmin L-BFGS: {e}")))?;
        let iterate: Iterate = IterState::new()
            .param(DVector::from_vec(x0.clone()))
            .cost(u_start * scale)
            .gradient(gv)
            .max_iters(1);
        st.chunk = Some(Chunk {
            scale,
            u_start,
            u_prev: u_start,
            prev_raw: x0,
            len: 0,
            carry: Some(Carry { solver, iterate }),
            left_region: false,
            pending: false,
        });
        Ok(())
    }

    /// One argmin iteration of the current chunk: the accepted state, or `None` when the
    /// chunk stalled.
    fn iterate(&self, problem: &Problem<'_>, st: &mut LbfgsState) -> Option<Move> {
        let periodic = problem.domain().is_periodic();
        let chunk = st.chunk.as_mut()?;
        let Carry { solver, iterate } = chunk.carry.take()?;
        let work = RefCell::new(Evaluator::new(
            problem,
            std::mem::replace(&mut st.cache, EvalCache::empty()),
        ));
        work.borrow_mut().begin_iteration(chunk.u_prev);
        // One iteration per executor run: the observer and the stopping rules act
        // between iterations.
        let result = Executor::new(
            Composite {
                work: &work,
                scale: chunk.scale,
            },
            solver,
        )
        .configure(|_| iterate)
        .ctrlc(false)
        .run();
        let mut proposal = None;
        match result {
            Ok(OptimizationResult {
                solver: sv,
                state: it,
                ..
            }) => {
                if let TerminationStatus::Terminated(TerminationReason::SolverExit(_)) =
                    it.get_termination_status()
                {
                    st.failures += 1;
                } else if let Some(x) = it.get_param() {
                    proposal = Some((x.as_slice().to_vec(), sv, it));
                }
            }
            Err(_) => st.failures += 1,
        }
        let mut w = work.into_inner();
        let mut next = None;
        w.c.calls_left = w.c.calls_left.max(1);
        if let Some((x, sv, it)) = proposal {
            if w.evaluate(&x).is_ok() && w.c.value <= chunk.u_prev {
                next = Some(x);
                let iter = it.get_iter();
                let mut it = it;
                it.termination_status = TerminationStatus::NotTerminated;
                chunk.carry = Some(Carry {
                    solver: sv,
                    iterate: it.max_iters(iter + 1),
                });
            }
        }
        if next.is_none() {
            // The line search failed or ended on a worse point, but it may have seen a
            // lower one on the way: take that, then restart.
            if let Some(t) = w.take_best_trial() {
                if w.evaluate(&t).is_ok() {
                    next = Some(t);
                }
            }
        }
        let result = next.and_then(|x| {
            let u = w.c.value;
            let max_move = if periodic {
                x.iter()
                    .zip(&chunk.prev_raw)
                    .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
            } else {
                w.c.points
                    .as_slice()
                    .iter()
                    .zip(st.current.as_slice())
                    .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
            };
            if max_move == 0.0 {
                return None;
            }
            st.total += 1;
            st.first_move = (2.0 * max_move).min(FIRST_STEP * st.spacing);
            st.current
                .as_mut_slice()
                .copy_from_slice(w.c.points.as_slice());
            st.gnorm = max_abs(&w.c.grad);
            chunk.left_region = w.c.moved && !periodic;
            chunk.prev_raw.copy_from_slice(&x);
            chunk.pending = true;
            let restarted = st.pending_restart;
            st.pending_restart = false;
            Some(Move {
                energy: u,
                max_move,
                restarted,
            })
        });
        st.cache = w.c;
        result
    }
}

impl EvalCache {
    /// A placeholder while the cache is lent to an [`Evaluator`].
    fn empty() -> Self {
        EvalCache {
            param: Vec::new(),
            valid: false,
            points: PointSet::new(1, 1, vec![0.0]).expect("one finite coordinate"),
            grad: Vec::new(),
            value: f64::NAN,
            moved: false,
            evaluations: 0,
            calls_left: 0,
            trial_value: f64::NEG_INFINITY,
            trial_param: Vec::new(),
            has_trial: false,
        }
    }
}

impl Integrator for Lbfgs {
    type State = LbfgsState;

    fn name(&self) -> String {
        format!("L-BFGS(m={})", self.memory)
    }

    fn init(&self, problem: &Problem<'_>, start: PointSet) -> Result<(LbfgsState, f64)> {
        self.validate()?;
        problem.check_inside("start point", &start)?;
        let energy = problem.energy();
        let mut w = Evaluator::new(problem, EvalCache::new(&start));
        w.c.calls_left = 1;
        let (u0, gnorm0) = match w.evaluate(start.as_slice()) {
            Ok(()) => (w.c.value, max_abs(&w.c.grad)),
            Err(Failure::NonFiniteEnergy(u)) => {
                return Err(Error::Numerical(format!(
                    "the energy {} of the start is not finite ({u}): two points coincide, \
                     a point is on the boundary, or the distances to the power −p \
                     overflow (p too large or too small for this n)",
                    energy.name()
                )))
            }
            Err(e) => {
                return Err(Error::Numerical(format!(
                    "cannot start L-BFGS with the energy {}: {e}",
                    energy.name()
                )))
            }
        };
        let spacing = typical_spacing(problem.domain(), start.n());
        let state = LbfgsState {
            current: start,
            gnorm0,
            gnorm: gnorm0,
            gtol: self.tol_grad * gnorm0,
            spacing,
            first_move: FIRST_STEP * spacing,
            total: 0,
            projection_restarts: 0,
            stall_restarts: 0,
            failures: 0,
            pending_restart: false,
            fresh: true,
            chunk: None,
            cache: w.c,
        };
        Ok((state, u0))
    }

    fn step(&self, problem: &Problem<'_>, st: &mut LbfgsState) -> Result<Step> {
        if std::mem::take(&mut st.fresh) && st.gnorm <= st.gtol {
            return Ok(Step::Ended(StopReason::Converged));
        }
        if let Some(end) = self.settle(st) {
            if let AfterChunk::End(reason) = self.end_chunk(st, end) {
                return Ok(Step::Ended(reason));
            }
        }
        loop {
            if st.chunk.is_none() {
                self.begin_chunk(problem, st)?;
            }
            match self.iterate(problem, st) {
                Some(mv) if st.gnorm <= st.gtol => return Ok(Step::Converged(mv)),
                Some(mv) => return Ok(Step::Moved(mv)),
                None => {
                    if let AfterChunk::End(reason) = self.end_chunk(st, ChunkEnd::Stalled) {
                        return Ok(Step::Ended(reason));
                    }
                }
            }
        }
    }

    fn points<'s>(&self, st: &'s LbfgsState) -> &'s PointSet {
        &st.current
    }

    fn info(&self, st: &LbfgsState) -> Vec<(String, f64)> {
        vec![
            ("iterations".to_string(), st.total as f64),
            (
                "restarts".to_string(),
                (st.projection_restarts + st.stall_restarts) as f64,
            ),
            (
                "projection_restarts".to_string(),
                st.projection_restarts as f64,
            ),
            ("stall_restarts".to_string(), st.stall_restarts as f64),
            ("line_search_failures".to_string(), st.failures as f64),
            ("evaluations".to_string(), st.cache.evaluations as f64),
            ("start_grad_norm".to_string(), st.gnorm0),
            ("final_grad_norm".to_string(), st.gnorm),
        ]
    }

    fn check_state(&self, problem: &Problem<'_>, start: &PointSet, st: &LbfgsState) -> Result<()> {
        self.validate()?;
        let c = &st.current;
        if c.n() != start.n() || c.s() != start.s() || st.cache.points.n() != c.n() {
            return Err(Error::invalid(
                "checkpoint",
                format!("{} points in {} dimensions", c.n(), c.s()),
                format!(
                    "a state of this run ({} points in {} dimensions)",
                    start.n(),
                    start.s()
                ),
            ));
        }
        problem.check_inside("checkpoint point", c)?;
        let len = c.coordinate_count();
        let lens_ok = st.cache.param.len() == len
            && st.cache.grad.len() == len
            && st.cache.trial_param.len() == len
            && st.chunk.as_ref().is_none_or(|k| k.prev_raw.len() == len);
        let finite = [st.gnorm0, st.gnorm, st.gtol, st.spacing, st.first_move]
            .iter()
            .all(|v| v.is_finite())
            && st
                .cache
                .param
                .iter()
                .chain(&st.cache.grad)
                .all(|v| v.is_finite())
            && st.chunk.as_ref().is_none_or(|k| {
                k.scale.is_finite() && k.u_start.is_finite() && k.u_prev.is_finite()
            });
        let carry_ok = st
            .chunk
            .as_ref()
            .and_then(|k| k.carry.as_ref())
            .is_none_or(|k| k.iterate.get_param().is_some_and(|p| p.len() == len));
        if !(lens_ok && finite && carry_ok) {
            return Err(Error::invalid(
                "checkpoint",
                "an L-BFGS state with buffers of the wrong length or non-finite numbers",
                format!("a state of this run ({len} finite coordinates per buffer)"),
            ));
        }
        Ok(())
    }
}
