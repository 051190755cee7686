//! The damped central-difference DEM (§4 of the paper).
//!
//! m ẍ + c ẋ + G ∇U(x) = 0 is stepped with central differences (eqs. 24–26):
//!
//! x^(j+1) = (A1 x^(j) − A2 x^(j−1) − G f^(j)) / A0,
//! A0 = m/Δt² + c/(2Δt), A1 = 2m/Δt², A2 = m/Δt² − c/(2Δt),
//!
//! started from rest with the Taylor step x^(1) = x^(0) − G f^(0) Δt² / (2m) (eq. 23 with
//! ẍ(0) = −G f/m: the paper's eq. 22 drops the sign). m and c follow eq. 41 from
//! μ0 = U(X0)/X0ᵀX0 and κ, so that A2/A0 = ((√κ − 1)/(√κ + 1))² and
//! 1/A0 = 4/(μ0 (1 + √κ)²): the scheme is heavy-ball gradient descent and Δt, G cancel.

use crate::{Integrator, Move, Problem, Step};
use serde::{Deserialize, Serialize};
use stillpoint_energies::{Error, PointSet, Result};

/// How κ of eq. 39 (μ1 ≈ κ μ0) is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kappa {
    /// Use this κ ≥ 1 as it is.
    Fixed(f64),
    /// The trial of §4.1: start at `start`; while the energy fails to decrease at every one
    /// of the first `trial_steps` steps, multiply κ by `factor` and begin again from the
    /// start, up to `max`.
    Auto {
        /// First κ tried (the paper's 100).
        start: f64,
        /// Enlargement factor per failed trial.
        factor: f64,
        /// Steps that must each lower the energy.
        trial_steps: usize,
        /// Largest κ tried; if it also fails, it is used anyway and the run says so.
        max: f64,
    },
}

impl Default for Kappa {
    fn default() -> Self {
        Kappa::Auto {
            start: 100.0,
            factor: 2.0,
            trial_steps: 20,
            max: 1e8,
        }
    }
}

/// The restart of §4.3: when the mean leaves 0.5 by more than ε_p in some coordinate
/// (eq. 44), the set is shifted on the torus to mean exactly 0.5 (eq. 45, made exact by
/// `PeriodicCube::centre_mean`) and the dynamics restart from rest. The motion is the
/// domain's ([`stillpoint_energies::Domain::recentre`]); only periodic domains have one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Restart {
    /// No restarts.
    Off,
    /// Restart when ΔP > ε_p.
    Threshold(f64),
    /// ε_p = 2/n: one point wrapping across a face moves the mean by 1/n, so a smaller
    /// threshold would restart after almost every wrap.
    Auto,
}

impl Restart {
    fn threshold(&self, n: usize) -> Option<f64> {
        match *self {
            Restart::Off => None,
            Restart::Threshold(e) => Some(e),
            Restart::Auto => Some(2.0 / n as f64),
        }
    }
}

/// The damped central-difference DEM integrator. Its step budget is the executor's
/// (the paper uses 1000).
#[derive(Debug, Clone, PartialEq)]
pub struct Dem {
    /// κ of eq. 39.
    pub kappa: Kappa,
    /// Δt (0.1 in the paper; it cancels from the scheme).
    pub dt: f64,
    /// The gravitational constant G (1 in the paper; it cancels from the scheme).
    pub g: f64,
    /// The restart for unbiasedness.
    pub restart: Restart,
    /// Stop when both the largest coordinate move of a step and the largest force step
    /// |G f|/A0 fall below this (0 disables).
    pub tolerance: f64,
}

impl Default for Dem {
    fn default() -> Self {
        Dem {
            kappa: Kappa::default(),
            dt: 0.1,
            g: 1.0,
            restart: Restart::Auto,
            tolerance: 1e-12,
        }
    }
}

impl Dem {
    fn validate(&self) -> Result<()> {
        let pos = |name: &str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(Error::invalid(name, v, "a finite number > 0"))
            }
        };
        pos("dt", self.dt)?;
        pos("G", self.g)?;
        if self.tolerance.is_nan() || self.tolerance < 0.0 {
            return Err(Error::invalid("tolerance", self.tolerance, "a number ≥ 0"));
        }
        match self.kappa {
            Kappa::Fixed(k) if !(k >= 1.0 && k.is_finite()) => {
                return Err(Error::invalid("kappa", k, "a finite number ≥ 1"))
            }
            Kappa::Auto {
                start, factor, max, ..
            } => {
                if !(start >= 1.0 && start.is_finite()) {
                    return Err(Error::invalid("kappa start", start, "a finite number ≥ 1"));
                }
                if !(factor > 1.0 && factor.is_finite()) {
                    return Err(Error::invalid("kappa factor", factor, "a number > 1"));
                }
                if !(max >= start && max.is_finite()) {
                    return Err(Error::invalid("kappa max", max, "a finite number ≥ start"));
                }
            }
            _ => {}
        }
        if let Restart::Threshold(e) = self.restart {
            if e.is_nan() || e <= 0.0 {
                return Err(Error::invalid(
                    "restart threshold ε_p",
                    e,
                    "a number > 0 (or no restart)",
                ));
            }
        }
        Ok(())
    }
}

/// The scheme's coefficients for one κ.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    a0: f64,
    a1: f64,
    a2: f64,
    g: f64,
}

impl Coefficients {
    /// Eq. 41 for m and c, then eq. 26.
    fn new(mu0: f64, kappa: f64, dt: f64, g: f64) -> Self {
        let m = (1.0 + kappa) / 4.0 * mu0 * dt * dt;
        let c = mu0 * kappa.sqrt() * dt;
        Coefficients {
            a0: m / (dt * dt) + c / (2.0 * dt),
            a1: 2.0 * m / (dt * dt),
            a2: m / (dt * dt) - c / (2.0 * dt),
            g,
        }
    }
}

/// Everything the DEM needs to continue a run bit for bit: the start (a failed κ trial
/// begins again from it), x^(j) and x^(j−1), the step j, the κ trial, the restart
/// counters, and the energies the trial compares with. The gradient at x^(j) is not
/// saved: it is recomputed, with the same bits, when a resumed run takes its next step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DemState {
    /// The start X0.
    pub start: PointSet,
    /// x^(j).
    pub current: PointSet,
    /// x^(j−1) (equal to x^(j) when the next step starts from rest).
    pub previous: PointSet,
    /// Whether the next step is the Taylor start from rest (after the start or a restart).
    pub from_rest: bool,
    /// The step j of x^(j), counted from the start of the accepted κ trial.
    pub step: usize,
    /// μ0 = U(X0)/X0ᵀX0 of eq. 39.
    pub mu0: f64,
    /// The κ in use.
    pub kappa: f64,
    /// κ trials begun so far (1 for the first).
    pub kappa_trials: usize,
    /// Whether the largest κ also failed its trial and is used anyway.
    pub kappa_trial_failed: bool,
    /// Restarts of §4.3 so far.
    pub restarts: usize,
    /// ε_p of the restart, when the domain has one (the torus).
    pub restart_threshold: Option<f64>,
    /// The energy of the start as recorded (None before it is evaluated).
    pub start_energy: Option<f64>,
    /// The energy of the last recorded state (None before the start is recorded).
    pub last_energy: Option<f64>,
    #[serde(skip)]
    grad: Vec<f64>,
}

impl DemState {
    fn new(start: PointSet, mu0: f64, kappa: f64, restart_threshold: Option<f64>) -> Self {
        DemState {
            current: start.clone(),
            previous: start.clone(),
            grad: vec![0.0; start.coordinate_count()],
            start,
            from_rest: true,
            step: 0,
            mu0,
            kappa,
            kappa_trials: 1,
            kappa_trial_failed: false,
            restarts: 0,
            restart_threshold,
            start_energy: None,
            last_energy: None,
        }
    }

    /// A failed κ trial: a larger κ, and everything else as at the start.
    fn begin_again(&mut self, factor: f64) {
        self.kappa *= factor;
        self.kappa_trials += 1;
        self.current = self.start.clone();
        self.previous = self.start.clone();
        self.grad.fill(0.0);
        self.from_rest = true;
        self.restarts = 0;
        self.step = 0;
        self.start_energy = None;
        self.last_energy = None;
    }
}

impl Dem {
    /// (κ start, factor, trial steps, κ max) of the trial; a fixed κ has no trial.
    fn trial(&self) -> (f64, f64, usize, f64) {
        match self.kappa {
            Kappa::Fixed(k) => (k, 1.0, 0, k),
            Kappa::Auto {
                start,
                factor,
                trial_steps,
                max,
            } => (start, factor, trial_steps, max),
        }
    }

    fn threshold(&self, problem: &Problem<'_>, n: usize) -> Option<f64> {
        if problem.domain().is_periodic() {
            self.restart.threshold(n)
        } else {
            None
        }
    }

    /// Evaluates x^(j) and applies the κ trial (§4.1): each of the first `trial_steps`
    /// steps of a smooth energy must lower it, or κ grows and the run begins again from
    /// the start (`None`). A max-type energy moves only its active pairs and may stall
    /// or rise a little while stable, so it must only stay below its start and end the
    /// trial lower. A blow-up after the trial (non-finite, or four times the start)
    /// means κ was still too small for a stiffer state reached later: a failed trial too.
    fn evaluate(&self, problem: &Problem<'_>, st: &mut DemState) -> Result<Option<f64>> {
        let energy = problem.energy();
        let (_, factor, trial_steps, kmax) = self.trial();
        let u = energy.value_and_gradient(&st.current, &mut st.grad);
        let j = st.step;
        let diverged =
            j >= trial_steps && (!u.is_finite() || st.start_energy.is_some_and(|u0| u > 4.0 * u0));
        if diverged && factor > 1.0 && st.kappa * factor <= kmax {
            st.begin_again(factor);
            return Ok(None);
        }
        if j < trial_steps && !st.kappa_trial_failed {
            let rising = if energy.is_smooth() {
                st.last_energy.is_some_and(|last| u >= last)
            } else {
                let u0 = st.start_energy.unwrap_or(u);
                u > u0 || (j + 1 == trial_steps && u >= u0)
            };
            if !u.is_finite() || rising {
                if st.kappa * factor <= kmax {
                    st.begin_again(factor);
                    return Ok(None);
                }
                st.kappa_trial_failed = true;
            }
        }
        if !u.is_finite() {
            return Err(Error::Numerical(format!(
                "the energy became {u} at step {j} with κ = {}; fix a larger κ",
                st.kappa
            )));
        }
        if j == 0 {
            st.start_energy = Some(u);
        }
        st.last_energy = Some(u);
        Ok(Some(u))
    }

    /// Evaluates the start after beginning again, as often as the trial asks.
    fn evaluate_start(&self, problem: &Problem<'_>, st: &mut DemState) -> Result<f64> {
        loop {
            if let Some(u) = self.evaluate(problem, st)? {
                return Ok(u);
            }
        }
    }

    /// Moves to x^(j+1) with eq. 25 (or the Taylor start). A point that leaves the domain
    /// is brought back by the domain's rule ([`stillpoint_energies::Domain::keep_inside`]:
    /// the torus wraps it with x^(j) shifted by the same integer, eq. 42; a bounded region
    /// shortens the step and stops the point). Returns (largest coordinate move, largest
    /// force step |G f|/A0).
    fn advance(&self, problem: &Problem<'_>, st: &mut DemState, co: &Coefficients) -> (f64, f64) {
        let domain = problem.domain();
        let s = st.current.s();
        let mut max_move: f64 = 0.0;
        let mut max_force: f64 = 0.0;
        let mut next = vec![0.0; s];
        let mut old = vec![0.0; s];
        let from_rest = st.from_rest;
        let cur = st.current.as_mut_slice();
        let prev = st.previous.as_mut_slice();
        for ((xc, xp), gr) in cur
            .chunks_exact_mut(s)
            .zip(prev.chunks_exact_mut(s))
            .zip(st.grad.chunks_exact(s))
        {
            let mut mv: f64 = 0.0;
            for k in 0..s {
                let f = co.g * gr[k];
                next[k] = if from_rest {
                    xc[k] - f / co.a1
                } else {
                    (co.a1 * xc[k] - co.a2 * xp[k] - f) / co.a0
                };
                mv = mv.max((next[k] - xc[k]).abs());
                max_force = max_force.max((f / co.a0).abs());
            }
            old.copy_from_slice(xc);
            xp.copy_from_slice(xc);
            if domain.keep_inside(&old, &mut next, xp) {
                mv = old
                    .iter()
                    .zip(&next)
                    .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()));
                xp.copy_from_slice(&next);
            }
            xc.copy_from_slice(&next);
            max_move = max_move.max(mv);
        }
        st.from_rest = false;
        (max_move, max_force)
    }
}

impl Integrator for Dem {
    type State = DemState;

    fn name(&self) -> String {
        match self.kappa {
            Kappa::Fixed(k) => format!("DEM(κ={k})"),
            Kappa::Auto { start, .. } => format!("DEM(κ auto from {start})"),
        }
    }

    fn init(&self, problem: &Problem<'_>, start: PointSet) -> Result<(DemState, f64)> {
        self.validate()?;
        problem.check_inside("start point", &start)?;
        let energy = problem.energy();
        let u0 = energy.value(&start);
        if !u0.is_finite() {
            return Err(Error::Numerical(format!(
                "the energy {} of the start is not finite ({u0}): two points coincide, or the \
                 distances to the power −p overflow (p too large or too small for this n)",
                energy.name()
            )));
        }
        let xtx: f64 = start.as_slice().iter().map(|v| v * v).sum();
        let mu0 = if xtx > 0.0 { u0 / xtx } else { u0 };
        if u0 == 0.0 && start.n() == 1 {
            // One star feels no force: the start is already at rest.
            let mut st = DemState::new(start, 0.0, self.trial().0, None);
            st.start_energy = Some(0.0);
            st.last_energy = Some(0.0);
            return Ok((st, 0.0));
        }
        if !(mu0 > 0.0 && mu0.is_finite()) {
            return Err(Error::Numerical(format!(
                "cannot set the DEM parameters: U(X0)/X0ᵀX0 = {mu0} (eq. 39 needs a positive, \
                 finite value)"
            )));
        }
        let eps = self.threshold(problem, start.n());
        let mut st = DemState::new(start, mu0, self.trial().0, eps);
        let u = self.evaluate_start(problem, &mut st)?;
        Ok((st, u))
    }

    fn step(&self, problem: &Problem<'_>, st: &mut DemState) -> Result<Step> {
        if st.mu0 == 0.0 {
            // The state of a single star without force (see `init`).
            return Ok(Step::Ended(crate::StopReason::Converged));
        }
        if st.grad.len() != st.current.coordinate_count() {
            // A resumed state: the gradient at x^(j), with the bits it had.
            st.grad = vec![0.0; st.current.coordinate_count()];
            problem
                .energy()
                .value_and_gradient(&st.current, &mut st.grad);
        }
        let co = Coefficients::new(st.mu0, st.kappa, self.dt, self.g);
        let (mv, mf) = self.advance(problem, st, &co);
        st.step += 1;
        if self.tolerance > 0.0 && mv < self.tolerance && mf < self.tolerance {
            let u = problem
                .energy()
                .value_and_gradient(&st.current, &mut st.grad);
            st.last_energy = Some(u);
            return Ok(Step::Converged(Move {
                energy: u,
                max_move: mv,
                restarted: false,
            }));
        }
        let mut restarted = false;
        if let Some(eps) = st.restart_threshold {
            if problem.domain().recentre(&mut st.current, eps) {
                st.previous = st.current.clone();
                st.from_rest = true;
                st.restarts += 1;
                restarted = true;
            }
        }
        Ok(match self.evaluate(problem, st)? {
            Some(u) => Step::Moved(Move {
                energy: u,
                max_move: mv,
                restarted,
            }),
            None => Step::BeganAgain(self.evaluate_start(problem, st)?),
        })
    }

    fn points<'s>(&self, state: &'s DemState) -> &'s PointSet {
        &state.current
    }

    fn info(&self, st: &DemState) -> Vec<(String, f64)> {
        vec![
            ("mu0".to_string(), st.mu0),
            ("kappa".to_string(), st.kappa),
            ("kappa_trials".to_string(), st.kappa_trials as f64),
            (
                "kappa_trial_failed".to_string(),
                if st.kappa_trial_failed { 1.0 } else { 0.0 },
            ),
            ("restarts".to_string(), st.restarts as f64),
            (
                "restart_threshold".to_string(),
                st.restart_threshold.unwrap_or(f64::INFINITY),
            ),
        ]
    }

    fn check_state(&self, problem: &Problem<'_>, start: &PointSet, st: &DemState) -> Result<()> {
        self.validate()?;
        let refuse = |what: &str, got: String, expected: String| {
            Err(Error::invalid(format!("checkpoint {what}"), got, expected))
        };
        if st.start != *start {
            return refuse(
                "start",
                format!("{} points in {} dimensions", st.start.n(), st.start.s()),
                "the start of this run (the state belongs to another run)".into(),
            );
        }
        for (what, p) in [("current", &st.current), ("previous", &st.previous)] {
            if p.n() != start.n() || p.s() != start.s() {
                return refuse(
                    what,
                    format!("{} points in {} dimensions", p.n(), p.s()),
                    format!("{} points in {} dimensions", start.n(), start.s()),
                );
            }
        }
        problem.check_inside("checkpoint point", &st.current)?;
        let eps = self.threshold(problem, start.n()).filter(|_| st.mu0 != 0.0);
        if st.restart_threshold.map(f64::to_bits) != eps.map(f64::to_bits) {
            return refuse(
                "restart threshold",
                format!("{:?}", st.restart_threshold),
                format!("{eps:?}, the restart setting of this run"),
            );
        }
        let u0 = problem.energy().value(start);
        let xtx: f64 = start.as_slice().iter().map(|v| v * v).sum();
        let mu0 = if xtx > 0.0 { u0 / xtx } else { u0 };
        if st.mu0.to_bits() != mu0.to_bits() {
            return refuse(
                "μ0",
                format!("{}", st.mu0),
                format!("μ0 = {mu0} of this start and energy (the state belongs to another run)"),
            );
        }
        let (k0, _, _, kmax) = self.trial();
        let kappa_ok = match self.kappa {
            Kappa::Fixed(k) => k.to_bits() == st.kappa.to_bits(),
            Kappa::Auto { .. } => st.kappa >= k0 && st.kappa <= kmax,
        };
        if !(kappa_ok && st.kappa.is_finite() && st.kappa_trials >= 1) {
            return refuse(
                "κ",
                format!("{}", st.kappa),
                "the κ setting of this run".into(),
            );
        }
        let finite = |v: Option<f64>| v.is_none_or(f64::is_finite);
        if !finite(st.start_energy) || !finite(st.last_energy) || st.start_energy.is_none() {
            return refuse(
                "energies",
                format!("{:?}, {:?}", st.start_energy, st.last_energy),
                "finite energies of recorded states".into(),
            );
        }
        Ok(())
    }
}
