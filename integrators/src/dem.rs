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

use crate::{Control, Integrator, Observer, Record, RunOutput, StopReason};
use serde::{Deserialize, Serialize};
use std::time::Instant;
use stillpoint_energies::{Domain, Energy, Error, PeriodicCube, PointSet, Result};

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
/// [`PeriodicCube::centre_mean`]) and the dynamics restart from rest. Only periodic
/// domains are restarted (a shift is what the torus allows).
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

/// The damped central-difference DEM integrator.
#[derive(Debug, Clone, PartialEq)]
pub struct Dem {
    /// Step budget (the paper uses 1000).
    pub steps: usize,
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
            steps: 1000,
            kappa: Kappa::default(),
            dt: 0.1,
            g: 1.0,
            restart: Restart::Auto,
            tolerance: 1e-12,
        }
    }
}

impl Dem {
    fn validate(&self, domain: &dyn Domain, start: &PointSet) -> Result<()> {
        crate::check_start(domain, start)?;
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

/// The evolving state: x^(j), x^(j−1), the gradient at x^(j) and whether the next step
/// starts from rest.
struct State {
    cur: PointSet,
    prev: PointSet,
    grad: Vec<f64>,
    from_rest: bool,
}

impl State {
    fn new(start: &PointSet) -> Self {
        State {
            cur: start.clone(),
            prev: start.clone(),
            grad: vec![0.0; start.len()],
            from_rest: true,
        }
    }

    /// U(x^(j)), leaving the gradient for [`State::advance`].
    fn evaluate(&mut self, energy: &dyn Energy) -> f64 {
        energy.value_and_gradient(&self.cur, &mut self.grad)
    }

    /// Moves to x^(j+1) with eq. 25 (or the Taylor start). On the torus a point that
    /// leaves is wrapped back (eq. 42, with x^(j) shifted by the same integer). In a region
    /// a point whose step would leave takes the largest of the halved steps (1/2, 1/4, …)
    /// that stays inside and loses its velocity: projecting it onto the boundary would put
    /// it at distance 0, where the boundary-aware energies are infinite. Returns (largest coordinate move, largest force step |G f|/A0).
    fn advance(&mut self, domain: &dyn Domain, co: &Coefficients) -> (f64, f64) {
        let s = self.cur.s();
        let periodic = domain.is_periodic();
        let mut max_move: f64 = 0.0;
        let mut max_force: f64 = 0.0;
        let mut next = vec![0.0; s];
        let cur = self.cur.as_mut_slice();
        let prev = self.prev.as_mut_slice();
        for ((xc, xp), gr) in cur
            .chunks_exact_mut(s)
            .zip(prev.chunks_exact_mut(s))
            .zip(self.grad.chunks_exact(s))
        {
            let mut mv: f64 = 0.0;
            for k in 0..s {
                let f = co.g * gr[k];
                next[k] = if self.from_rest {
                    xc[k] - f / co.a1
                } else {
                    (co.a1 * xc[k] - co.a2 * xp[k] - f) / co.a0
                };
                mv = mv.max((next[k] - xc[k]).abs());
                max_force = max_force.max((f / co.a0).abs());
            }
            if periodic {
                xp.copy_from_slice(xc);
                xc.copy_from_slice(&next);
                domain.bring_back(xc, xp);
            } else if domain.contains(&next) {
                xp.copy_from_slice(xc);
                xc.copy_from_slice(&next);
            } else {
                // Halve the step until it stays inside, then stop the point there.
                xp.copy_from_slice(xc);
                let mut t = 0.5;
                mv = 0.0;
                for _ in 0..40 {
                    let trial: Vec<f64> =
                        xc.iter().zip(&next).map(|(a, b)| a + t * (b - a)).collect();
                    if domain.contains(&trial) {
                        mv = xc
                            .iter()
                            .zip(&trial)
                            .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()));
                        xc.copy_from_slice(&trial);
                        break;
                    }
                    t *= 0.5;
                }
                xp.copy_from_slice(xc);
            }
            max_move = max_move.max(mv);
        }
        self.from_rest = false;
        (max_move, max_force)
    }

    /// Eqs. 44–45: if the mean is more than `eps` from 0.5 in some coordinate, shift the
    /// set periodically back to mean exactly 0.5 and restart from rest. Returns whether it
    /// did.
    fn maybe_recentre(&mut self, eps: f64) -> bool {
        let dp = self
            .cur
            .mean()
            .iter()
            .map(|m| (m - 0.5).abs())
            .fold(0.0, f64::max);
        if dp <= eps {
            return false;
        }
        PeriodicCube::centre_mean(&mut self.cur);
        self.prev
            .as_mut_slice()
            .copy_from_slice(self.cur.as_slice());
        self.from_rest = true;
        true
    }
}

/// Everything the DEM needs to continue a run bit for bit where it was interrupted: the
/// positions x^(j) and x^(j−1), the step j, the κ trial, the restart counters, the lowest
/// state seen and the trajectory so far. The scheme is deterministic, so no random state
/// is needed; the start and μ0 are recomputed from the run's inputs and μ0 is compared
/// with [`DemState::mu0`] so that a state cannot be continued under another energy or
/// start.
///
/// A state is handed out by [`Dem::run_from`] every [`Snapshots::every`] steps, before
/// x^(j) is evaluated; [`Dem::run_from`] with `Some(state)` goes on from there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DemState {
    /// Number of points.
    pub n: usize,
    /// Dimension.
    pub s: usize,
    /// Step index j of [`DemState::current`], the next state to be evaluated and recorded.
    pub step: usize,
    /// x^(j), row per point.
    pub current: Vec<f64>,
    /// x^(j−1), row per point (equal to x^(j) when the next step starts from rest).
    pub previous: Vec<f64>,
    /// Whether the next step is the Taylor start from rest (after the start or a restart).
    pub from_rest: bool,
    /// μ0 = U(X0)/X0ᵀX0 of eq. 39, from the start.
    pub mu0: f64,
    /// The κ in use.
    pub kappa: f64,
    /// κ trials begun so far (1 for the first).
    pub kappa_trials: usize,
    /// Whether the largest κ also failed its trial and is used anyway.
    pub kappa_trial_failed: bool,
    /// Restarts of §4.3 so far.
    pub restarts: usize,
    /// Whether x^(j) came from a restart.
    pub restarted: bool,
    /// Largest coordinate move of the step that produced x^(j).
    pub last_move: f64,
    /// The lowest state seen so far, kept for non-smooth energies.
    pub best: Option<BestState>,
    /// Records of x^(0) .. x^(j−1).
    pub trajectory: Vec<Record>,
    /// Wall time of the run so far in seconds (the records' clock goes on from it).
    pub seconds: f64,
}

/// The lowest state a DEM run has seen (for non-smooth energies, which it returns).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BestState {
    /// Its energy.
    pub energy: f64,
    /// Its step.
    pub step: usize,
    /// Its points, row per point.
    pub points: Vec<f64>,
}

impl DemState {
    /// Refuses a state that cannot be continued with this start and these settings,
    /// naming what disagrees.
    fn check(&self, dem: &Dem, start: &PointSet, mu0: f64) -> Result<()> {
        let len = start.len();
        if self.n != start.n() || self.s != start.s() {
            return Err(Error::invalid(
                "checkpoint",
                format!("{} points in {} dimensions", self.n, self.s),
                format!(
                    "a state of this run ({} points in {} dimensions)",
                    start.n(),
                    start.s()
                ),
            ));
        }
        if self.current.len() != len
            || self.previous.len() != len
            || self.best.as_ref().is_some_and(|b| b.points.len() != len)
        {
            return Err(Error::invalid(
                "checkpoint",
                "a point buffer of the wrong length",
                format!("{len} coordinates per buffer"),
            ));
        }
        if self.mu0.to_bits() != mu0.to_bits() {
            return Err(Error::invalid(
                "checkpoint",
                format!("μ0 = {}", self.mu0),
                format!("μ0 = {mu0} of this start and energy (the state belongs to another run)"),
            ));
        }
        if self.step > dem.steps || self.step == 0 || self.trajectory.len() != self.step {
            return Err(Error::invalid(
                "checkpoint step",
                self.step,
                format!(
                    "a step in 1..={} with one record per earlier step",
                    dem.steps
                ),
            ));
        }
        let fixed_ok = match dem.kappa {
            Kappa::Fixed(k) => k.to_bits() == self.kappa.to_bits(),
            Kappa::Auto { start, max, .. } => self.kappa >= start && self.kappa <= max,
        };
        if !(fixed_ok && self.kappa.is_finite() && self.kappa >= 1.0) {
            return Err(Error::invalid(
                "checkpoint κ",
                self.kappa,
                "the κ setting of this run",
            ));
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.current) || !finite(&self.previous) || !self.last_move.is_finite() {
            return Err(Error::invalid(
                "checkpoint",
                "a non-finite coordinate",
                "finite positions",
            ));
        }
        Ok(())
    }
}

/// Where [`Dem::run_from`] hands out its state: `save` is called every `every` steps
/// (0: never), before the state of that step is evaluated.
pub struct Snapshots<'a> {
    /// Steps between two snapshots; 0 turns them off.
    pub every: usize,
    /// Receives each snapshot (for example to write a checkpoint file); an error ends the
    /// run with that error.
    pub save: &'a mut dyn FnMut(&DemState) -> Result<()>,
}

impl Dem {
    /// Runs from `start`, or continues `resume` (a state this run handed out earlier),
    /// handing out its state as `snapshots` asks. A continued run
    /// returns exactly the points, trajectory energies and info of the uninterrupted
    /// run; only the records' wall times differ. `save` may refuse with an error, which
    /// ends the run with that error.
    pub fn run_from(
        &self,
        energy: &dyn Energy,
        domain: &dyn Domain,
        start: PointSet,
        resume: Option<DemState>,
        observer: &mut dyn Observer,
        snapshots: Snapshots<'_>,
    ) -> Result<RunOutput> {
        let Snapshots { every, save } = snapshots;
        self.validate(domain, &start)?;
        let u0 = energy.value(&start);
        if !u0.is_finite() {
            return Err(Error::Numerical(format!(
                "the energy {} of the start is not finite ({u0}): two points coincide, or p is \
                 too small for this n (the energy overflows)",
                energy.name()
            )));
        }
        let xtx: f64 = start.as_slice().iter().map(|v| v * v).sum();
        let mu0 = if xtx > 0.0 { u0 / xtx } else { u0 };
        if !(mu0 > 0.0 && mu0.is_finite()) {
            return Err(Error::Numerical(format!(
                "cannot set the DEM parameters: U(X0)/X0ᵀX0 = {mu0} (eq. 39 needs a positive, \
                 finite value)"
            )));
        }
        let eps = if domain.is_periodic() {
            self.restart.threshold(start.n())
        } else {
            None
        };

        // κ trial (§4.1): each of the first `trial_steps` steps must lower the energy, or κ
        // grows and the run begins again from the start. An accepted trial's steps are kept.
        let (kappa0, factor, trial_steps, kmax) = match self.kappa {
            Kappa::Fixed(k) => (k, 1.0, 0, k),
            Kappa::Auto {
                start,
                factor,
                trial_steps,
                max,
            } => (start, factor, trial_steps, max),
        };
        let mut kappa = kappa0;
        let mut trials = 1usize;
        let mut trial_failed = false;
        let mut state = State::new(&start);
        let mut trajectory: Vec<Record> = Vec::with_capacity(self.steps + 1);
        let mut stop = StopReason::StepBudget;
        let mut restarts = 0usize;
        let (mut restarted, mut last_move) = (false, 0.0);
        let mut j = 0usize;
        // A max-type or kinked energy is not a descent method's friend: keep the lowest
        // state seen and return it (for a smooth energy the last state is returned).
        let keep_best = !energy.is_smooth();
        let mut best: Option<(f64, usize, PointSet)> = None;
        let mut clock_offset = 0.0;
        // The state a run resumed from is already saved; saving it again is wasted work.
        let mut saved_at = None;
        if let Some(r) = resume {
            r.check(self, &start, mu0)?;
            let (n, s) = (r.n, r.s);
            let points = |v: Vec<f64>| PointSet::new(n, s, v);
            kappa = r.kappa;
            trials = r.kappa_trials;
            trial_failed = r.kappa_trial_failed;
            state.cur = points(r.current)?;
            state.prev = points(r.previous)?;
            state.from_rest = r.from_rest;
            trajectory = r.trajectory;
            trajectory.reserve(self.steps + 1 - r.step);
            restarts = r.restarts;
            restarted = r.restarted;
            last_move = r.last_move;
            j = r.step;
            best = match r.best {
                Some(b) => Some((b.energy, b.step, points(b.points)?)),
                None => None,
            };
            clock_offset = r.seconds;
            saved_at = Some(j);
        }
        let clock = Instant::now();
        let elapsed = |clock: &Instant| clock_offset + clock.elapsed().as_secs_f64();
        let mut co = Coefficients::new(mu0, kappa, self.dt, self.g);
        loop {
            if every > 0 && j > 0 && j.is_multiple_of(every) && saved_at != Some(j) {
                let snapshot = DemState {
                    n: start.n(),
                    s: start.s(),
                    step: j,
                    current: state.cur.as_slice().to_vec(),
                    previous: state.prev.as_slice().to_vec(),
                    from_rest: state.from_rest,
                    mu0,
                    kappa,
                    kappa_trials: trials,
                    kappa_trial_failed: trial_failed,
                    restarts,
                    restarted,
                    last_move,
                    best: best.as_ref().map(|(u, step, p)| BestState {
                        energy: *u,
                        step: *step,
                        points: p.as_slice().to_vec(),
                    }),
                    trajectory: trajectory.clone(),
                    seconds: elapsed(&clock),
                };
                save(&snapshot)?;
                saved_at = Some(j);
            }
            let u = state.evaluate(energy);
            // A blow-up after the trial (the energy non-finite or four times its start)
            // means κ was still too small for a stiffer state reached later: treat it as a
            // failed trial.
            let diverged = j >= trial_steps
                && (!u.is_finite() || trajectory.first().is_some_and(|r| u > 4.0 * r.energy));
            if diverged && factor > 1.0 && kappa * factor <= kmax {
                kappa *= factor;
                trials += 1;
                co = Coefficients::new(mu0, kappa, self.dt, self.g);
                state = State::new(&start);
                trajectory.clear();
                restarts = 0;
                (restarted, last_move, j) = (false, 0.0, 0);
                saved_at = None;
                continue;
            }
            if j < trial_steps && !trial_failed {
                // A smooth energy must fall at every trial step (§4.1). A max-type energy
                // moves only its active pairs and may stall or rise a little while stable,
                // so it must only stay below its start and end the trial lower.
                let rising = if energy.is_smooth() {
                    trajectory.last().is_some_and(|r| u >= r.energy)
                } else {
                    let u0 = trajectory.first().map_or(u, |r| r.energy);
                    u > u0 || (j + 1 == trial_steps && u >= u0)
                };
                if !u.is_finite() || rising {
                    if kappa * factor <= kmax {
                        kappa *= factor;
                        trials += 1;
                        co = Coefficients::new(mu0, kappa, self.dt, self.g);
                        state = State::new(&start);
                        trajectory.clear();
                        restarts = 0;
                        (restarted, last_move, j) = (false, 0.0, 0);
                        saved_at = None;
                        continue;
                    }
                    trial_failed = true;
                }
            }
            if !u.is_finite() {
                return Err(Error::Numerical(format!(
                    "the energy became {u} at step {j} with κ = {kappa}; fix a larger κ"
                )));
            }
            let mut rec = Record {
                step: j,
                energy: u,
                seconds: elapsed(&clock),
                max_move: last_move,
                restarted,
                metrics: Vec::new(),
            };
            let ctl = observer.observe(&mut rec, &state.cur);
            trajectory.push(rec);
            if keep_best && best.as_ref().is_none_or(|b| u < b.0) {
                best = Some((u, j, state.cur.clone()));
            }
            if j == self.steps {
                break;
            }
            if ctl == Control::Stop {
                stop = StopReason::Observer;
                break;
            }
            let (mv, mf) = state.advance(domain, &co);
            last_move = mv;
            restarted = false;
            j += 1;
            if self.tolerance > 0.0 && mv < self.tolerance && mf < self.tolerance {
                stop = StopReason::Converged;
                let u = state.evaluate(energy);
                let mut rec = Record {
                    step: j,
                    energy: u,
                    seconds: elapsed(&clock),
                    max_move: mv,
                    restarted,
                    metrics: Vec::new(),
                };
                observer.observe(&mut rec, &state.cur);
                trajectory.push(rec);
                break;
            }
            if let Some(e) = eps {
                if state.maybe_recentre(e) {
                    restarts += 1;
                    restarted = true;
                }
            }
        }
        let mut returned_step = trajectory.last().map_or(0, |r| r.step);
        if let Some((u, step, points)) = best {
            if trajectory.last().is_some_and(|r| u < r.energy) {
                state.cur = points;
                returned_step = step;
                let mut rec = Record {
                    step,
                    energy: u,
                    seconds: elapsed(&clock),
                    max_move: 0.0,
                    restarted: false,
                    metrics: Vec::new(),
                };
                observer.observe(&mut rec, &state.cur);
                trajectory.push(rec);
            }
        }
        let info = vec![
            ("returned_step".to_string(), returned_step as f64),
            ("mu0".to_string(), mu0),
            ("kappa".to_string(), kappa),
            ("kappa_trials".to_string(), trials as f64),
            (
                "kappa_trial_failed".to_string(),
                if trial_failed { 1.0 } else { 0.0 },
            ),
            ("restarts".to_string(), restarts as f64),
            (
                "restart_threshold".to_string(),
                eps.unwrap_or(f64::INFINITY),
            ),
        ];
        Ok(RunOutput {
            points: state.cur,
            trajectory,
            stop,
            info,
        })
    }
}

impl Integrator for Dem {
    fn name(&self) -> String {
        match self.kappa {
            Kappa::Fixed(k) => format!("DEM(κ={k}, steps={})", self.steps),
            Kappa::Auto { start, .. } => format!("DEM(κ auto from {start}, steps={})", self.steps),
        }
    }

    fn run(
        &self,
        energy: &dyn Energy,
        domain: &dyn Domain,
        start: PointSet,
        observer: &mut dyn Observer,
    ) -> Result<RunOutput> {
        let mut ignore = |_: &DemState| Ok(());
        let snapshots = Snapshots {
            every: 0,
            save: &mut ignore,
        };
        self.run_from(energy, domain, start, None, observer, snapshots)
    }
}
