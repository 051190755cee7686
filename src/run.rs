//! The run driver: turns a [`GenerateConfig`] into a start set, an energy and a DEM run,
//! and reports the quality of the start and the result side by side.

use crate::energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use crate::energies::einf::UEInf;
use crate::energies::shapes::BoxRegion;
use crate::energies::{paper_qp, Distance, Domain, Energy, PeriodicCube, PointSet, Uqp};
use crate::integrators::lbfgs::Lbfgs;
use crate::integrators::{
    Control, Dem, Integrator, Kappa, NoObserver, Observer, Record, Restart, RunOutput,
};
use crate::metrics::{self, Metrics};
use crate::sequences;
use crate::shift::{self, ShiftOutcome};
use crate::Error;
use serde::Serialize;
use std::time::Instant;

/// Where the DEM starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Init {
    /// Plain Halton, indices 1..n (the paper's start).
    Halton,
    /// Uniform random points from the seed.
    Random,
    /// A given set (from a file), in [0, 1]^s.
    Points(PointSet),
}

/// The energy of a cube run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CubeEnergy {
    /// U_{q,p} (eqs. 5, 12) on the periodic cube.
    Uqp,
    /// U_{E,∞} = 1/d_min (eq. 3) with its active-pair subgradient: with the torus distance
    /// on the periodic cube, or (q = 'E') with the Euclidean distance in the closed cube
    /// [0, 1]^s, where it gives a maximin design.
    EInf,
    /// A squared L2 discrepancy as the energy: on the torus for the wrap-around L2, in
    /// the closed cube for the others.
    Discrepancy(DiscrepancyKind),
}

/// The solver of a cube run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// The damped central-difference DEM of the paper.
    Dem,
    /// argmin's L-BFGS with restarts (see [`crate::integrators::lbfgs`]).
    Lbfgs,
}

/// Everything a `generate` run needs. [`GenerateConfig::new`] gives the defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateConfig {
    /// Number of points n ≥ 1.
    pub n: usize,
    /// Dimension s ≥ 1.
    pub s: usize,
    /// The energy.
    pub energy: CubeEnergy,
    /// The distance of U_{q,p}; `None` takes q from eq. 48. For U_{E,∞}: `Euclidean`
    /// selects the closed cube, anything else the torus.
    pub q: Option<Distance>,
    /// The exponent p; `None` takes p from eq. 48.
    pub p: Option<f64>,
    /// The start.
    pub init: Init,
    /// Seed for every random choice (the random start).
    pub seed: u64,
    /// The solver.
    pub solver: Solver,
    /// The DEM's settings (its `steps` is the budget of either solver).
    pub dem: Dem,
    /// L-BFGS settings; its iteration budget is taken from `dem.steps`.
    pub lbfgs: Lbfgs,
    /// Compute D_L2* and D_MD every this many steps into the trajectory (0: never).
    pub log_every: usize,
    /// Candidate periodic shifts tried after the DEM (0: none); see [`crate::shift`].
    /// Only used with a periodic distance (q ≠ 'E').
    pub shifts: usize,
    /// A last L-BFGS run on this squared discrepancy, from the result (after the shift
    /// selection), in the closed cube for the non-periodic kinds. `None`: no polish.
    pub polish: Option<DiscrepancyKind>,
}

impl GenerateConfig {
    /// Defaults: (q, p) from eq. 48, plain Halton start, the paper's DEM with 1000 steps,
    /// κ trial from 100, restart threshold 2/n, then the best of 64 periodic shifts.
    pub fn new(n: usize, s: usize) -> Self {
        GenerateConfig {
            n,
            s,
            energy: CubeEnergy::Uqp,
            q: None,
            p: None,
            init: Init::Halton,
            seed: 0,
            solver: Solver::Dem,
            dem: Dem::default(),
            lbfgs: Lbfgs::default(),
            log_every: 0,
            shifts: 64,
            polish: None,
        }
    }
}

/// How (q, p) were chosen.
#[derive(Debug, Clone, Serialize)]
pub struct EnergyChoice {
    /// q as the paper writes it (a number, `inf` or `E`).
    pub q: String,
    /// p.
    pub p: f64,
    /// Whether q or p came from eq. 48.
    pub from_eq48: bool,
    /// Whether (n, s) lies in the range eq. 48 was fitted on (1 ≤ s ≤ 20, s ≤ n ≤ 1500).
    pub eq48_in_fitted_range: bool,
    /// Whether eq. 48's raw value had to be clamped into [0.05, 1].
    pub eq48_clamped: bool,
}

/// The outcome of a `generate` run.
#[derive(Debug, Clone)]
pub struct GenerateReport {
    /// The start set.
    pub start: PointSet,
    /// The final set.
    pub output: RunOutput,
    /// Energy of the start and of the result.
    pub energy: (f64, f64),
    /// The energy's name with its parameters.
    pub energy_name: String,
    /// Metrics of the start and of the result.
    pub metrics: (Metrics, Metrics),
    /// How the energy was chosen.
    pub choice: EnergyChoice,
    /// The shift selection after the DEM, when it ran.
    pub shift: Option<ShiftOutcome>,
    /// The polish, when it ran: (squared discrepancy before, after, L-BFGS iterations).
    pub polish: Option<(f64, f64, usize)>,
    /// Wall time of the whole run in seconds.
    pub seconds: f64,
}

/// U_{q,p} for (n, s) with the user's q and p where given, eq. 48 otherwise.
pub fn choose_energy(
    n: usize,
    s: usize,
    q: Option<Distance>,
    p: Option<f64>,
) -> Result<(Uqp, EnergyChoice), Error> {
    let fit = paper_qp(n, s);
    let distance = q.unwrap_or(Distance::Q(fit.q));
    let p_val = p.unwrap_or(fit.p);
    let energy = Uqp::new(distance, p_val)?;
    let from_eq48 = q.is_none() || p.is_none();
    let clamped = (q.is_none() && fit.q != fit.raw_q) || (p.is_none() && fit.p != fit.raw_p);
    Ok((
        energy,
        EnergyChoice {
            q: distance.label(),
            p: p_val,
            from_eq48,
            eq48_in_fitted_range: fit.in_fitted_range,
            eq48_clamped: clamped,
        },
    ))
}

/// Builds the start set of a configuration, checked against n and s.
pub fn start_set(cfg: &GenerateConfig) -> Result<PointSet, Error> {
    if cfg.n == 0 {
        return Err(Error::invalid("n", cfg.n, "at least 1 point"));
    }
    if cfg.s == 0 {
        return Err(Error::invalid("s", cfg.s, "at least 1 dimension"));
    }
    match &cfg.init {
        Init::Halton => sequences::halton(cfg.n, cfg.s),
        Init::Random => sequences::random(cfg.n, cfg.s, cfg.seed),
        Init::Points(p) => {
            if p.n() != cfg.n || p.s() != cfg.s {
                return Err(Error::invalid(
                    "init points",
                    format!("{} points in {} dimensions", p.n(), p.s()),
                    format!("{} points in {} dimensions (-n, -s)", cfg.n, cfg.s),
                ));
            }
            p.check_unit_cube()?;
            Ok(p.clone())
        }
    }
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
        Control::Continue
    }
}

/// Runs the DEM for a configuration, calling `on_record` with every trajectory record.
pub fn generate(
    cfg: &GenerateConfig,
    on_record: impl FnMut(&Record),
) -> Result<GenerateReport, Error> {
    let clock = Instant::now();
    let start = start_set(cfg)?;
    let (energy, domain, choice): (Box<dyn Energy>, Box<dyn Domain>, EnergyChoice) =
        match cfg.energy {
            CubeEnergy::Uqp => {
                let (e, choice) = choose_energy(cfg.n, cfg.s, cfg.q, cfg.p)?;
                (Box::new(e), Box::new(PeriodicCube::new(cfg.s)?), choice)
            }
            CubeEnergy::EInf => {
                let euclid = cfg.q == Some(Distance::Euclidean);
                let choice = EnergyChoice {
                    q: if euclid { "E" } else { "inf" }.to_string(),
                    p: f64::INFINITY,
                    from_eq48: false,
                    eq48_in_fitted_range: false,
                    eq48_clamped: false,
                };
                if euclid {
                    let cube = BoxRegion::new(vec![0.0; cfg.s], vec![1.0; cfg.s])?;
                    (
                        Box::new(UEInf::new(Distance::Euclidean)?),
                        Box::new(cube),
                        choice,
                    )
                } else {
                    let cube = PeriodicCube::new(cfg.s)?;
                    (
                        Box::new(UEInf::new(Distance::Torus)?),
                        Box::new(cube),
                        choice,
                    )
                }
            }
            CubeEnergy::Discrepancy(kind) => {
                let choice = EnergyChoice {
                    q: "-".to_string(),
                    p: f64::NAN,
                    from_eq48: false,
                    eq48_in_fitted_range: false,
                    eq48_clamped: false,
                };
                // Only the wrap-around L2 is periodic; the others live in the closed cube.
                let domain: Box<dyn Domain> = if kind.is_periodic() {
                    Box::new(PeriodicCube::new(cfg.s)?)
                } else {
                    Box::new(BoxRegion::new(vec![0.0; cfg.s], vec![1.0; cfg.s])?)
                };
                (Box::new(DiscrepancyEnergy::new(kind)), domain, choice)
            }
        };
    let mut start = start;
    if domain.is_periodic() {
        // 1.0 is the same point as 0.0 on the torus.
        PeriodicCube::wrap_set(&mut start);
    }
    let mut observer = LoggingObserver::new(cfg.log_every, on_record);
    let (e, d) = (energy.as_ref(), domain.as_ref());
    let mut output = match cfg.solver {
        Solver::Dem => cfg.dem.run(e, d, start.clone(), &mut observer)?,
        Solver::Lbfgs => {
            let lbfgs = Lbfgs {
                iterations: cfg.dem.steps,
                ..cfg.lbfgs.clone()
            };
            lbfgs.run(e, d, start.clone(), &mut observer)?
        }
    };
    let shift = if cfg.shifts > 0 && domain.is_periodic() {
        let (points, outcome) = shift::best_shift(&output.points, cfg.shifts);
        output.points = points;
        Some(outcome)
    } else {
        None
    };
    let polish = match cfg.polish {
        Some(kind) => {
            let e = DiscrepancyEnergy::new(kind);
            let d: Box<dyn Domain> = if kind.is_periodic() {
                Box::new(PeriodicCube::new(cfg.s)?)
            } else {
                Box::new(BoxRegion::new(vec![0.0; cfg.s], vec![1.0; cfg.s])?)
            };
            let before = e.value(&output.points);
            let lbfgs = Lbfgs {
                iterations: cfg.dem.steps,
                ..cfg.lbfgs.clone()
            };
            let out = lbfgs.run(&e, d.as_ref(), output.points.clone(), &mut NoObserver)?;
            let iterations = out.trajectory.iter().map(|r| r.step).max().unwrap_or(0);
            let after = e.value(&out.points);
            if after < before {
                output.points = out.points;
            }
            Some((before, after.min(before), iterations))
        }
        None => None,
    };
    debug_assert!(output.points.rows().all(|r| domain.contains(r)));
    let energy_pair = (
        output
            .trajectory
            .first()
            .map(|r| r.energy)
            .unwrap_or(f64::NAN),
        output
            .trajectory
            .last()
            .map(|r| r.energy)
            .unwrap_or(f64::NAN),
    );
    let metrics_pair = (Metrics::compute(&start), Metrics::compute(&output.points));
    Ok(GenerateReport {
        energy_name: energy.name(),
        start,
        output,
        energy: energy_pair,
        metrics: metrics_pair,
        choice,
        shift,
        polish,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// Parses a κ setting: `auto` (the trial from 100) or a number ≥ 1.
pub fn parse_kappa(text: &str) -> Result<Kappa, Error> {
    if text.trim().eq_ignore_ascii_case("auto") {
        return Ok(Kappa::default());
    }
    match text.trim().parse::<f64>() {
        Ok(k) if k >= 1.0 && k.is_finite() => Ok(Kappa::Fixed(k)),
        _ => Err(Error::invalid(
            "--kappa",
            text,
            "`auto` or a finite number ≥ 1",
        )),
    }
}

/// Parses a restart setting: `auto` (ε_p = 2/n), `off`, or ε_p > 0.
pub fn parse_restart(text: &str) -> Result<Restart, Error> {
    match text.trim().to_ascii_lowercase().as_str() {
        "auto" => Ok(Restart::Auto),
        "off" | "none" => Ok(Restart::Off),
        t => match t.parse::<f64>() {
            Ok(e) if e > 0.0 && !e.is_nan() => Ok(Restart::Threshold(e)),
            _ => Err(Error::invalid(
                "--restart",
                text,
                "`auto` (ε_p = 2/n), `off`, or a number ε_p > 0",
            )),
        },
    }
}
