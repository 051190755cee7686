//! The pipeline of every `generate` run, in the cube or in a region: a
//! [`GenerateConfig`] becomes a start set and a [`Problem`] (energy + domain), the solver
//! runs through the one executor (`Run::solve`), the post-steps follow (periodic shift
//! selection, polish), and a [`GenerateReport`] gives the quality of the start and the
//! result side by side.
//!
//! Any run can be checkpointed and resumed ([`CheckpointPlan`], [`generate_with`]): the
//! checkpoint file holds the run's configuration and the executor's snapshot, so a
//! resumed run ends with exactly the bytes of an uninterrupted one, and a checkpoint of
//! another configuration is refused with the settings that differ.

pub use crate::checkpoint::{
    encode_checkpoint, fnv1a64, read_checkpoint, Checkpoint, CheckpointPlan, CHECKPOINT_FORMAT,
    CHECKPOINT_VERSION,
};
use crate::energies::boundary::{UEInfG, UEpG};
use crate::energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use crate::energies::einf::UEInf;
use crate::energies::shapes::BoxRegion;
use crate::energies::{paper_qp, Distance, Domain, Energy, PeriodicCube, PointSet, Precision, Uqp};
use crate::integrators::lbfgs::Lbfgs;
use crate::integrators::{
    Control, Dem, Executor, Integrator, Observer, Problem, Record, RunOutput, Snapshot,
};
use crate::metrics::{self, Metrics};
use crate::regions::RegionMetrics;
use crate::sequences;
use crate::shift::{self, ShiftOutcome};
pub use crate::stratified::Target;
use crate::Error;
use serde::Serialize;
use serde_json::{json, Value};
use std::sync::Arc;
use std::time::Instant;

/// Where the points live.
#[derive(Debug, Clone)]
pub enum Space {
    /// The unit cube [0, 1)^s (periodic or closed, as the energy needs).
    Cube,
    /// A region {x : g(x) ≤ 0} or a built-in shape, with the text that described it
    /// (recorded in checkpoints, so that a resume in another region is refused).
    Region {
        /// The region.
        domain: Arc<dyn Domain>,
        /// How it was given (an expression and box, a shape), for records.
        description: Value,
    },
}

impl PartialEq for Space {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Space::Cube, Space::Cube) => true,
            (
                Space::Region {
                    domain: a,
                    description: da,
                },
                Space::Region {
                    domain: b,
                    description: db,
                },
            ) => format!("{a:?}") == format!("{b:?}") && da == db,
            _ => false,
        }
    }
}

/// Where the run starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Init {
    /// Plain Halton, indices 1..n (the paper's start in the cube); in a region, Halton
    /// points scaled to the bounding box, the first n inside.
    Halton,
    /// Uniform random points from the seed; in a region, uniform in the bounding box,
    /// the first n inside (the paper's start in a region, §5.4).
    Random,
    /// A given set (from a file), inside the space.
    Points(PointSet),
}

/// The energy of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EnergyKind {
    /// U_{q,p} (eqs. 5, 12) on the periodic cube.
    Uqp,
    /// U_{E,∞} = 1/d_min (eq. 3) with its active-pair subgradient: in the cube with the
    /// torus distance, or (q = 'E') with the Euclidean distance in the closed cube
    /// [0, 1]^s, where it gives a maximin design; in a region with the Euclidean distance
    /// and no boundary term.
    EInf,
    /// A squared L2 discrepancy as the energy: on the torus for the wrap-around L2, in
    /// the closed cube for the others.
    Discrepancy(DiscrepancyKind),
    /// U_{E,∞,g} of eq. 56 in a region (the paper's choice): 1 / min(point distances,
    /// 2 × boundary distances), with the active-element subgradient of eq. 57.
    EInfG,
    /// U_{E,p,g} in a region: the smooth finite-p version,
    /// (Σ d_ij^{−p} + Σ (2 d_ig)^{−p})^{1/p}.
    EpG(f64),
}

/// The solver of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// The damped central-difference DEM of the paper.
    Dem,
    /// argmin's L-BFGS with restarts (see [`crate::integrators::lbfgs`]).
    Lbfgs,
}

/// What a run is for: the pipeline that makes the points.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// The configured start, energy and solver, then the post-steps. With the defaults of
    /// [`GenerateConfig::new`] this is exactly the paper's pipeline (Halton start, U_{q,p}
    /// with eq. 48, the DEM, shift selection): `--method paper`.
    Paper,
    /// Quasi-Monte Carlo integration: a stratified set (one point per 1/n interval in
    /// every coordinate) with the target's discrepancy as low as the descent reaches
    /// ([`crate::stratified::integration_set`]). The unit cube only.
    Integration(Target),
    /// Design of computer experiments: a stratified set with the largest smallest
    /// distance found, from the better of the paper's DEM result (stratified) and a
    /// Latin hypercube, each improved by the maximin swap search
    /// ([`crate::sequences::maximin_search`]). In a region: the configured region run.
    SpaceFilling,
}

/// The goal a caller asked for by name (`--goal`, `goal=`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalName {
    /// `integration`.
    Integration,
    /// `space-filling`.
    SpaceFilling,
}

/// What a run is for, decided the same way for the command line and the Python package:
/// an asked goal chooses (none of the paper's options may come with it, except with
/// space-filling in a region, whose pipeline is the region's run); without one, the
/// paper's method (`paper`), any of the paper's options (`expert`, named as the caller
/// spells them) or a region choose the paper's pipeline, and otherwise the integration
/// goal. `target` applies to the integration goal only. `flag` spells an option's name
/// the caller's way (`--goal` or `goal`) in the refusals.
pub fn choose_goal(
    asked: Option<GoalName>,
    paper: bool,
    expert: &[&str],
    in_region: bool,
    target: Option<Target>,
    flag: impl Fn(&str) -> String,
) -> Result<Goal, Error> {
    let goal = match asked {
        Some(g) => {
            let name = match g {
                GoalName::Integration => "integration",
                GoalName::SpaceFilling => "space-filling",
            };
            if paper {
                return Err(Error::invalid(
                    flag("goal"),
                    name,
                    "no goal with the paper's method (it is its own pipeline)",
                ));
            }
            if let (Some(first), false) = (expert.first(), in_region && g == GoalName::SpaceFilling)
            {
                return Err(Error::invalid(
                    *first,
                    format!("given with the goal {name}"),
                    format!(
                        "the paper's options only with the paper's method (or no {}); a \
                         goal chooses its own pipeline",
                        flag("goal")
                    ),
                ));
            }
            match g {
                GoalName::Integration if in_region => {
                    return Err(Error::invalid(
                        flag("goal"),
                        "integration in a region",
                        "space-filling in a region (the discrepancies of integration are \
                         those of the unit cube)",
                    ))
                }
                GoalName::Integration => Goal::Integration(Target::blend()),
                GoalName::SpaceFilling => Goal::SpaceFilling,
            }
        }
        None if paper || !expert.is_empty() || in_region => Goal::Paper,
        None => Goal::Integration(Target::blend()),
    };
    match (goal, target) {
        (Goal::Integration(_), Some(t)) => Ok(Goal::Integration(t)),
        (_, Some(t)) => Err(Error::invalid(
            flag("target"),
            t.name(),
            "a target only with the integration goal (the cube's default); this run's \
             pipeline is the paper's or space-filling",
        )),
        (g, None) => Ok(g),
    }
}

/// How a finished set is randomised (`--randomize`), so that independent seeds give
/// independent, unbiased estimates of an integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Randomize {
    /// x ↦ (x + c) mod 1 with c uniform in [0, 1)^s: every point becomes uniform in the
    /// cube; the torus distances, the periodic energies and the wrap-around L2
    /// discrepancy are unchanged; the stratification is kept only where a coordinate's
    /// values are equally spaced.
    Shift,
    /// Per coordinate, the cells are rotated by a uniform m ∈ {0, …, n−1} and every offset
    /// inside its cell by a uniform v ∈ [0, 1), modulo the cell: x = (c + u)/n ↦
    /// ((c + m) mod n + (u + v) mod 1)/n. Every point becomes uniform in the cube and a
    /// stratified set stays stratified; the discrepancies change a little (a point whose
    /// offset wraps moves by less than 1/n).
    Cells,
}

/// Everything a `generate` run needs, in the cube or in a region.
/// [`GenerateConfig::new`] and [`GenerateConfig::in_region`] give the defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateConfig {
    /// Number of points n ≥ 1.
    pub n: usize,
    /// Dimension s ≥ 1 (a region's own dimension).
    pub s: usize,
    /// Where the points live.
    pub space: Space,
    /// The energy.
    pub energy: EnergyKind,
    /// The distance of U_{q,p}; `None` takes q from eq. 48. For U_{E,∞} in the cube:
    /// `Euclidean` selects the closed cube, anything else the torus.
    pub q: Option<Distance>,
    /// The exponent p; `None` takes p from eq. 48.
    pub p: Option<f64>,
    /// How U_{q,p}'s general-q distance is evaluated during the run: [`Precision::Fast`]
    /// by default (the forces only steer the dynamics); the reported energies of the start
    /// and the result are always evaluated with [`Precision::Full`].
    pub precision: Precision,
    /// The start.
    pub init: Init,
    /// Seed for every random choice (the random start).
    pub seed: u64,
    /// The solver.
    pub solver: Solver,
    /// The step budget of the solver (and of the polish).
    pub steps: usize,
    /// The DEM's settings.
    pub dem: Dem,
    /// L-BFGS settings.
    pub lbfgs: Lbfgs,
    /// Compute D_L2* and D_MD every this many steps into the trajectory (0: never; the
    /// cube only).
    pub log_every: usize,
    /// Candidate periodic shifts tried after a periodic energy (0: none); see
    /// [`crate::shift`].
    pub shifts: usize,
    /// A last L-BFGS run on this squared discrepancy, from the result (after the shift
    /// selection), in the closed cube for the non-periodic kinds. `None`: no polish. The
    /// cube only.
    pub polish: Option<DiscrepancyKind>,
    /// What the run is for; [`Goal::Paper`] runs the fields above as they are.
    pub goal: Goal,
    /// A last randomisation of the result from `seed` (the cube only).
    pub randomize: Option<Randomize>,
    /// Points to keep, first and unchanged, while n − their number are added (the
    /// integration goal in the cube): [`crate::stratified::extend_set`].
    pub extend: Option<PointSet>,
    /// Sizes N1 < N2 < … = n of a nested set, each prefix made for its size (the
    /// integration goal in the cube): [`crate::stratified::nested_set`]. Empty: one set.
    pub nested: Vec<usize>,
}

impl GenerateConfig {
    /// The configuration of a goal in the cube: the paper's settings for everything the
    /// goal's pipeline takes from them (the DEM run of [`Goal::SpaceFilling`]).
    pub fn for_goal(n: usize, s: usize, goal: Goal) -> Self {
        GenerateConfig {
            goal,
            ..GenerateConfig::new(n, s)
        }
    }

    /// The cube's defaults: (q, p) from eq. 48, plain Halton start, the paper's DEM with
    /// 1000 steps, κ trial from 100, restart threshold 2/n, then the best of 64 periodic
    /// shifts.
    pub fn new(n: usize, s: usize) -> Self {
        GenerateConfig {
            n,
            s,
            space: Space::Cube,
            energy: EnergyKind::Uqp,
            q: None,
            p: None,
            precision: Precision::Fast,
            init: Init::Halton,
            seed: 0,
            solver: Solver::Dem,
            steps: 1000,
            dem: Dem::default(),
            lbfgs: Lbfgs::default(),
            log_every: 0,
            shifts: 64,
            polish: None,
            goal: Goal::Paper,
            randomize: None,
            extend: None,
            nested: Vec::new(),
        }
    }

    /// A region's defaults: U_{E,∞,g}, the paper's random start with seed 0, the DEM with
    /// the κ trial and 10 000 steps. The paper's 1000 steps separate the closest pairs
    /// (U_{E,∞,g} already falls by 80–90 %) but leave most points where they started;
    /// 10 000 spread them.
    pub fn in_region(domain: Arc<dyn Domain>, n: usize) -> Self {
        GenerateConfig {
            s: domain.dim(),
            space: Space::Region {
                domain,
                description: Value::Null,
            },
            energy: EnergyKind::EInfG,
            init: Init::Random,
            steps: 10_000,
            shifts: 0,
            ..GenerateConfig::new(n, 1)
        }
    }

    /// The region, when the run is in one.
    pub fn region(&self) -> Option<&Arc<dyn Domain>> {
        match &self.space {
            Space::Cube => None,
            Space::Region { domain, .. } => Some(domain),
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

/// A step after the solver. Each is one function in a module of its own; a new one is
/// one more arm here and in [`generate_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PostStep {
    /// The best of this many periodic shifts ([`crate::shift`]), after a periodic energy.
    Shift(usize),
    /// L-BFGS on a squared discrepancy ([`crate::polish`]).
    Polish(DiscrepancyKind),
}

impl GenerateConfig {
    /// The post-steps this configuration asks for, in the order they run.
    pub fn post_steps(&self) -> Vec<PostStep> {
        let mut steps = Vec::new();
        if self.shifts > 0 {
            steps.push(PostStep::Shift(self.shifts));
        }
        if let Some(kind) = self.polish {
            steps.push(PostStep::Polish(kind));
        }
        steps
    }
}

/// The quality of a set, as fits its space.
#[derive(Debug, Clone, PartialEq)]
pub enum Quality {
    /// Discrepancies, distances and energies in the unit cube.
    Cube(Metrics),
    /// U_{E,∞,g}, the minimum point distance and boundary distance in a region.
    Region(RegionMetrics),
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
    /// Quality of the start and of the result.
    pub quality: (Quality, Quality),
    /// How the energy was chosen.
    pub choice: EnergyChoice,
    /// The shift selection after the DEM, when it ran.
    pub shift: Option<ShiftOutcome>,
    /// The polish, when it ran: (squared discrepancy before, after, L-BFGS iterations).
    pub polish: Option<(f64, f64, usize)>,
    /// What a goal's pipeline did, one line per stage (empty for [`Goal::Paper`], whose
    /// solver, shift and polish have fields of their own).
    pub stages: Vec<String>,
    /// Wall time of the whole run in seconds.
    pub seconds: f64,
}

impl GenerateReport {
    /// The cube metrics of the start and the result; an error for a region run, whose
    /// quality is measured by [`GenerateReport::region_metrics`].
    pub fn cube_metrics(&self) -> Result<(&Metrics, &Metrics), Error> {
        match &self.quality {
            (Quality::Cube(a), Quality::Cube(b)) => Ok((a, b)),
            _ => Err(Error::invalid(
                "metrics",
                "a region run",
                "a cube run (a region's figures are its region metrics)",
            )),
        }
    }

    /// The region figures of the start and the result; an error for a cube run.
    pub fn region_metrics(&self) -> Result<(&RegionMetrics, &RegionMetrics), Error> {
        match &self.quality {
            (Quality::Region(a), Quality::Region(b)) => Ok((a, b)),
            _ => Err(Error::invalid(
                "region metrics",
                "a cube run",
                "a region run (a cube's figures are its metrics)",
            )),
        }
    }

    /// 1 − U_{E,∞,g}(result) / U_{E,∞,g}(start): the paper's "optimization ratio" in a
    /// region.
    pub fn reduction(&self) -> Result<f64, Error> {
        self.region_metrics()
            .map(|(a, b)| 1.0 - b.energy_e_inf_g / a.energy_e_inf_g)
    }
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

/// The most candidate shifts the shift selection tries (each costs one discrepancy
/// evaluation; beyond this the selection gains nothing measurable).
pub const MAX_SHIFTS: usize = 1 << 20;

/// Builds the start set of a configuration, checked against n, s and the space.
pub fn start_set(cfg: &GenerateConfig) -> Result<PointSet, Error> {
    sequences::check_size(cfg.n, cfg.s)?;
    if cfg.shifts > MAX_SHIFTS {
        return Err(Error::invalid(
            "shifts",
            cfg.shifts,
            format!("at most {MAX_SHIFTS} candidate shifts"),
        ));
    }
    if let Some(domain) = cfg.region() {
        // When a set grows, the start holds the new points only.
        let n = cfg.n - cfg.extend.as_ref().map_or(0, |p| p.n().min(cfg.n));
        return crate::regions::start_in_region(domain.as_ref(), n, &cfg.init, cfg.seed);
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

/// The energy and domain of a configuration, with how (q, p) were chosen.
fn build_problem(cfg: &GenerateConfig) -> Result<(Problem<'static>, EnergyChoice), Error> {
    let no_choice = |q: &str, p: f64| EnergyChoice {
        q: q.to_string(),
        p,
        from_eq48: false,
        eq48_in_fitted_range: false,
        eq48_clamped: false,
    };
    let closed_cube = || -> Result<Arc<dyn Domain>, Error> {
        Ok(Arc::new(BoxRegion::new(
            vec![0.0; cfg.s],
            vec![1.0; cfg.s],
        )?))
    };
    let torus = || -> Result<Arc<dyn Domain>, Error> { Ok(Arc::new(PeriodicCube::new(cfg.s)?)) };
    let (energy, domain, choice): (Arc<dyn Energy>, Arc<dyn Domain>, EnergyChoice) =
        match (&cfg.space, cfg.energy) {
            (Space::Cube, EnergyKind::Uqp) => {
                let (e, choice) = choose_energy(cfg.n, cfg.s, cfg.q, cfg.p)?;
                (Arc::new(e.with_precision(cfg.precision)), torus()?, choice)
            }
            (Space::Cube, EnergyKind::EInf) => {
                if cfg.q == Some(Distance::Euclidean) {
                    (
                        Arc::new(UEInf::new(Distance::Euclidean)?),
                        closed_cube()?,
                        no_choice("E", f64::INFINITY),
                    )
                } else {
                    (
                        Arc::new(UEInf::new(Distance::Torus)?),
                        torus()?,
                        no_choice("inf", f64::INFINITY),
                    )
                }
            }
            (Space::Cube, EnergyKind::Discrepancy(kind)) => {
                // Only the wrap-around L2 is periodic; the others live in the closed cube.
                let domain = if kind.is_periodic() {
                    torus()?
                } else {
                    closed_cube()?
                };
                (
                    Arc::new(DiscrepancyEnergy::new(kind)),
                    domain,
                    no_choice("-", f64::NAN),
                )
            }
            (Space::Region { domain, .. }, EnergyKind::EInfG) => (
                Arc::new(UEInfG::new(domain.clone())?),
                domain.clone(),
                no_choice("E", f64::INFINITY),
            ),
            (Space::Region { domain, .. }, EnergyKind::EpG(p)) => (
                Arc::new(UEpG::new(domain.clone(), p)?),
                domain.clone(),
                no_choice("E", p),
            ),
            (Space::Region { domain, .. }, EnergyKind::EInf) => (
                Arc::new(UEInf::new(Distance::Euclidean)?),
                domain.clone(),
                no_choice("E", f64::INFINITY),
            ),
            (Space::Cube, other) => {
                return Err(Error::invalid(
                    "energy",
                    format!("{other:?}"),
                    "an energy of the cube (U_{q,p}, U_{E,∞} or a discrepancy); the \
                     boundary-aware energies need a region",
                ))
            }
            (Space::Region { .. }, other) => {
                return Err(Error::invalid(
                    "energy",
                    format!("{other:?}"),
                    "an energy of a region (U_{E,∞,g}, U_{E,p,g} or U_{E,∞})",
                ))
            }
        };
    // A region's set that grows: the old points take part in the energy and never move.
    let energy: Arc<dyn Energy> = match (&cfg.extend, cfg.region()) {
        (Some(old), Some(_)) => {
            Arc::new(crate::energies::fixed::WithFixed::new(energy, old.clone()))
        }
        _ => energy,
    };
    Ok((Problem::shared(energy, domain)?, choice))
}

/// About how long the solver of `cfg` takes, in seconds: one energy-and-gradient
/// evaluation timed on a set of at most 200 points of the run's space and dimension,
/// scaled by (n/200)² (the pair sums) and by the step budget. A rough figure for warning
/// before a long run, not a promise: convergence may stop a run early.
pub fn estimate_seconds(cfg: &GenerateConfig) -> Result<f64, Error> {
    sequences::check_size(cfg.n, cfg.s)?;
    let probe_n = cfg.n.clamp(2, 200);
    let mut probe = cfg.clone();
    probe.n = probe_n;
    probe.init = Init::Random;
    let (problem, _) = build_problem(&probe)?;
    let start = start_set(&probe)?;
    let mut grad = vec![0.0; start.coordinate_count()];
    let clock = Instant::now();
    let mut evaluations = 0u32;
    while evaluations < 3 || clock.elapsed().as_secs_f64() < 0.02 {
        problem.energy().value_and_gradient(&start, &mut grad);
        evaluations += 1;
        if evaluations >= 1000 {
            break;
        }
    }
    let each = clock.elapsed().as_secs_f64() / f64::from(evaluations);
    let scale = (cfg.n as f64 / probe_n as f64).powi(2);
    Ok(each * scale * cfg.steps.max(1) as f64)
}

/// The quality figures of a set in the configuration's space.
fn quality(cfg: &GenerateConfig, points: &PointSet) -> Result<Quality, Error> {
    Ok(match cfg.region() {
        Some(domain) => Quality::Region(RegionMetrics::compute(domain, points)?),
        None => Quality::Cube(Metrics::compute(points)),
    })
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

/// Runs a configuration, calling `on_record` with every trajectory record.
pub fn generate(
    cfg: &GenerateConfig,
    mut on_record: impl FnMut(&Record),
) -> Result<GenerateReport, Error> {
    generate_with(cfg, None, |e| {
        if let Event::Record(r) = e {
            on_record(r)
        }
    })
}

/// Runs a configuration as [`generate`] does, with checkpoints written (and an earlier one
/// resumed) as `checkpoint` says, and every [`Event`] passed to `on_event`: the start,
/// the solver through the executor, then the post-steps (shift selection after a
/// periodic energy, the polish), then the report. The post-steps run after a resume too.
pub fn generate_with(
    cfg: &GenerateConfig,
    checkpoint: Option<&CheckpointPlan>,
    mut on_event: impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let clock = Instant::now();
    if cfg.randomize.is_some() && cfg.region().is_some() {
        return Err(Error::invalid(
            "randomize",
            format!("{:?}", cfg.randomize),
            "no randomisation in a region (a shift would carry points out of it)",
        ));
    }
    if cfg.goal != Goal::Paper && cfg.region().is_none() && checkpoint.is_some() {
        return Err(Error::invalid(
            "checkpoint",
            "a goal run",
            "checkpoints of --method paper runs (a goal's run takes seconds)",
        ));
    }
    let cube_integration = matches!(cfg.goal, Goal::Integration(_)) && cfg.region().is_none();
    if (!cfg.nested.is_empty() && !cube_integration)
        || (cfg.extend.is_some() && !cube_integration && cfg.region().is_none())
    {
        return Err(Error::invalid(
            "extend",
            "a cube run that is not the integration goal",
            "--extend with the integration goal in the cube (the default) or in a region; \
             --nested with the integration goal",
        ));
    }
    if let (Some(old), Some(domain)) = (&cfg.extend, cfg.region()) {
        if old.s() != cfg.s || old.n() > cfg.n {
            return Err(Error::invalid(
                "extend",
                format!("{} points in {} dimensions", old.n(), old.s()),
                format!("at most n = {} points in s = {} dimensions", cfg.n, cfg.s),
            ));
        }
        if let Some(i) = old.rows().position(|r| !domain.contains(r)) {
            return Err(Error::invalid(
                "extend",
                format!("point {} outside the region", i + 1),
                "old points inside the run's region",
            ));
        }
    }
    let mut report = match (&cfg.goal, cfg.region()) {
        (Goal::Integration(_), Some(_)) => {
            return Err(Error::invalid(
                "goal",
                "integration in a region",
                "the unit cube, where the discrepancies of integration are defined; in a \
                 region the goal is space-filling",
            ))
        }
        (Goal::Integration(target), None) => integration_run(cfg, target, &mut on_event)?,
        (Goal::SpaceFilling, None) => space_filling_run(cfg, &mut on_event)?,
        _ => paper_run(cfg, checkpoint, &mut on_event)?,
    };
    if let Some(kind) = cfg.randomize {
        report.output.points = crate::stratified::randomize(&report.output.points, kind, cfg.seed);
        report.quality.1 = quality(cfg, &report.output.points)?;
        report.stages.push(format!(
            "randomised ({}) from seed {}",
            match kind {
                Randomize::Shift => "uniform shift modulo 1",
                Randomize::Cells => "cells rotated, offsets shifted within their cells",
            },
            cfg.seed
        ));
    }
    report.seconds = clock.elapsed().as_secs_f64();
    Ok(report)
}

/// A goal's run as a report: the start and the result with their quality, the value the
/// goal lowered (or raised) as the energy pair.
fn goal_report(
    cfg: &GenerateConfig,
    start: PointSet,
    points: PointSet,
    energy: (f64, f64),
    energy_name: String,
    stages: Vec<String>,
) -> Result<GenerateReport, Error> {
    let quality_pair = (quality(cfg, &start)?, quality(cfg, &points)?);
    Ok(GenerateReport {
        start,
        output: RunOutput {
            points,
            trajectory: Vec::new(),
            stop: crate::integrators::StopReason::Converged,
            info: Vec::new(),
        },
        energy,
        energy_name,
        quality: quality_pair,
        choice: EnergyChoice {
            q: "-".into(),
            p: f64::NAN,
            from_eq48: false,
            eq48_in_fitted_range: false,
            eq48_clamped: false,
        },
        shift: None,
        polish: None,
        stages,
        seconds: 0.0,
    })
}

/// The integration goal: [`crate::stratified::integration_set`].
fn integration_run(
    cfg: &GenerateConfig,
    target: &Target,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    on_event(Event::Stage {
        name: "stratified descent",
        steps: None,
    });
    let effort = crate::stratified::Effort::default();
    if let Some(old) = &cfg.extend {
        if old.s() != cfg.s || old.n() > cfg.n {
            return Err(Error::invalid(
                "extend",
                format!("{} points in {} dimensions", old.n(), old.s()),
                format!("at most n = {} points in s = {} dimensions", cfg.n, cfg.s),
            ));
        }
        let ext = crate::stratified::extend_set(old, cfg.n - old.n(), target, cfg.seed, &effort)?;
        let new = PointSet::new(
            cfg.n - ext.old,
            cfg.s,
            ext.points.as_slice()[ext.old * cfg.s..].to_vec(),
        )?;
        let figures = |p: &PointSet| {
            let m = Metrics::compute(p);
            format!(
                "D_MD {:.6}, D_L2* {:.6}, CD {:.6}",
                m.modified_l2, m.star_l2, m.centered_l2
            )
        };
        let stages = vec![
            format!(
                "extended {} old points (first, unchanged) by {} new ones, placed from {} \
                 in the free cells of the union's grid, then exchanges and in-cell L-BFGS \
                 moving the new points only",
                ext.old,
                cfg.n - ext.old,
                ext.start_label
            ),
            format!(
                "union stratified on its {} cells per coordinate: {}",
                cfg.n,
                if ext.stratified {
                    "yes".to_string()
                } else {
                    format!(
                        "no ({} old points share a cell of the union's grid with another, \
                         so as many cells stay empty)",
                        ext.collisions
                    )
                }
            ),
            format!("old points: {}", figures(old)),
            format!("new points alone: {}", figures(&new)),
            format!("union: {}", figures(&ext.points)),
        ];
        let (a, b) = (target.value(&ext.start), target.value(&ext.points));
        return goal_report(cfg, ext.start, ext.points, (a, b), target.name(), stages);
    }
    if !cfg.nested.is_empty() {
        if cfg.nested.last() != Some(&cfg.n) {
            return Err(Error::invalid(
                "nested",
                format!("{:?}", cfg.nested),
                format!("stages ending at n = {}", cfg.n),
            ));
        }
        let points = crate::stratified::nested_set(&cfg.nested, cfg.s, target, cfg.seed, &effort)?;
        let mut stages = vec![format!(
            "nested: the first {} points made for their size, each later stage added by \
             extension; every prefix below",
            cfg.nested[0]
        )];
        for &k in &cfg.nested {
            let prefix = PointSet::new(k, cfg.s, points.as_slice()[..k * cfg.s].to_vec())?;
            let m = Metrics::compute(&prefix);
            stages.push(format!(
                "first {k}: D_MD {:.6}, D_L2* {:.6}, CD {:.6}, stratified: {}",
                m.modified_l2,
                m.star_l2,
                m.centered_l2,
                if crate::stratified::is_stratified(&prefix) {
                    "yes"
                } else {
                    "no"
                }
            ));
        }
        let v = target.value(&points);
        return goal_report(cfg, points.clone(), points, (v, v), target.name(), stages);
    }
    let (points, outcome) =
        crate::stratified::integration_set(cfg.n, cfg.s, target, cfg.seed, &effort)?;
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![
        format!(
            "start: the best of {} stratified scrambled Sobol' sets and a scrambled Halton \
             set by the target: {}",
            effort.starts, outcome.start
        ),
        format!(
            "descent: {} rounds of coordinate exchanges and in-cell L-BFGS; every coordinate \
             stratified (one point in each [k/n, (k+1)/n))",
            effort.rounds
        ),
    ];
    goal_report(
        cfg,
        outcome.start_points,
        points,
        (outcome.before, outcome.after),
        target.name(),
        stages,
    )
}

/// Latin hypercube starts of the space-filling goal's maximin search (each about half a
/// second at most).
const SPACE_FILLING_LHS_STARTS: u64 = 4;
/// Further passes of the search from the best candidate.
const SPACE_FILLING_PASSES: u64 = 3;

/// The space-filling goal in the cube: the paper's run, stratified, and a Latin
/// hypercube, each through the maximin swap search; the larger smallest distance wins.
fn space_filling_run(
    cfg: &GenerateConfig,
    on_event: &mut impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let mut paper_cfg = cfg.clone();
    paper_cfg.goal = Goal::Paper;
    paper_cfg.randomize = None;
    let paper = paper_run(&paper_cfg, None, &mut *on_event)?;
    on_event(Event::Stage {
        name: "maximin search",
        steps: None,
    });
    let from_dem = crate::stratified::stratify(&paper.output.points);
    // Candidates: the DEM's set and several Latin hypercubes, each through the search.
    let mut candidates = vec![(
        "the DEM's result, stratified".to_string(),
        sequences::maximin_search(from_dem.clone(), cfg.seed)?,
    )];
    for k in 0..SPACE_FILLING_LHS_STARTS {
        candidates.push((
            format!("a Latin hypercube (seed {})", cfg.seed.wrapping_add(k)),
            sequences::lhs_maximin(cfg.n, cfg.s, cfg.seed.wrapping_add(k))?,
        ));
    }
    let min_d = |p: &PointSet| metrics::min_distance_euclidean(p);
    // Each candidate's smallest distance once (an O(n² s) pass); the first best is kept.
    let (label, _, mut points) = candidates
        .into_iter()
        .map(|(l, p)| (l, min_d(&p), p))
        .fold(None::<(String, f64, PointSet)>, |best, c| match best {
            Some(b) if b.1 >= c.1 => Some(b),
            _ => Some(c),
        })
        .expect("at least two candidates");
    // More passes of the search from the best, each with its own random stream: the
    // search never returns a set below its start, so each pass only adds.
    for pass in 0..SPACE_FILLING_PASSES {
        let stream = cfg.seed ^ 0x9e37_79b9_7f4a_7c15u64.wrapping_mul(pass + 1);
        points = sequences::maximin_search(points, stream)?;
    }
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let stages = vec![
        format!(
            "DEM on {} ({} steps), then stratified",
            paper.energy_name,
            paper.output.trajectory.last().map_or(0, |r| r.step)
        ),
        format!(
            "maximin swap search from the DEM's stratified result and from \
             {SPACE_FILLING_LHS_STARTS} Latin hypercubes: kept {label}, searched \
             {SPACE_FILLING_PASSES} more times; every coordinate stratified"
        ),
    ];
    let energy = (min_d(&from_dem), min_d(&points));
    goal_report(
        cfg,
        from_dem,
        points,
        energy,
        "minimum distance (Euclidean)".into(),
        stages,
    )
}

/// The configured pipeline: start, solver through the executor, post-steps.
fn paper_run(
    cfg: &GenerateConfig,
    checkpoint: Option<&CheckpointPlan>,
    mut on_event: impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let clock = Instant::now();
    let mut start = start_set(cfg)?;
    let (problem, choice) = build_problem(cfg)?;
    if cfg.polish.is_some() && cfg.region().is_some() {
        return Err(Error::invalid(
            "polish",
            format!("{:?}", cfg.polish),
            "no polish in a region (the discrepancies live in the unit cube)",
        ));
    }
    let (energy, domain) = (problem.energy(), problem.domain());
    if domain.is_periodic() {
        // 1.0 is the same point as 0.0 on the torus.
        PeriodicCube::wrap_set(&mut start);
    }
    let config = config_json(cfg);
    // A grown region set is reported as the union, old points first.
    let with_old = |p: &PointSet| -> Result<PointSet, Error> {
        match (&cfg.extend, cfg.region()) {
            (Some(old), Some(_)) => {
                let mut data = old.as_slice().to_vec();
                data.extend_from_slice(p.as_slice());
                PointSet::new(old.n() + p.n(), p.s(), data)
            }
            _ => Ok(p.clone()),
        }
    };
    let region_start_quality = match cfg.region() {
        Some(_) => {
            on_event(Event::Stage {
                name: "metrics",
                steps: None,
            });
            Some(quality(cfg, &with_old(&start)?)?)
        }
        None => None,
    };
    let mut output = {
        let main = match cfg.solver {
            Solver::Dem => "DEM",
            Solver::Lbfgs => "L-BFGS",
        };
        on_event(Event::Stage {
            name: main,
            steps: Some(cfg.steps as u64),
        });
        let log_every = if cfg.region().is_some() {
            0
        } else {
            cfg.log_every
        };
        let mut observer = LoggingObserver::new(log_every, |r: &Record| {
            on_event(Event::Record(r));
            on_event(Event::Progress(r.step as u64));
        });
        let run = Run {
            problem: &problem,
            steps: cfg.steps,
            checkpoint,
            config: &config,
        };
        run.solve(
            cfg.solver,
            &cfg.dem,
            &cfg.lbfgs,
            start.clone(),
            &mut observer,
        )?
    };
    // The energies reported for the start and the DEM's result, at full precision when
    // the run used the fast table.
    let full_energies = match (&cfg.space, cfg.energy) {
        (Space::Cube, EnergyKind::Uqp) if cfg.precision != Precision::Full => {
            let (e, _) = choose_energy(cfg.n, cfg.s, cfg.q, cfg.p)?;
            match e.distance() {
                Distance::Q(q) if Precision::fast_applies(q) => {
                    Some((e.value(&start), e.value(&output.points)))
                }
                _ => None,
            }
        }
        _ => None,
    };
    let (mut shift, mut polish) = (None, None);
    for step in cfg.post_steps() {
        match step {
            // A shift is a motion the energy does not see only on the torus.
            PostStep::Shift(candidates) if domain.is_periodic() => {
                on_event(Event::Stage {
                    name: "shift selection",
                    steps: None,
                });
                let (points, outcome) = shift::best_shift(&output.points, candidates);
                output.points = points;
                shift = Some(outcome);
            }
            PostStep::Shift(_) => {}
            PostStep::Polish(kind) => {
                on_event(Event::Stage {
                    name: "polish",
                    steps: Some(cfg.steps as u64),
                });
                let p =
                    crate::polish::polish(&output.points, kind, cfg.steps, &cfg.lbfgs, |step| {
                        on_event(Event::Progress(step))
                    })?;
                output.points = p.points;
                polish = Some((p.before, p.after, p.iterations));
            }
        }
    }
    debug_assert!(output.points.rows().all(|r| domain.contains(r)));
    output.points = with_old(&output.points)?;
    let start = with_old(&start)?;
    let energy_pair = full_energies.unwrap_or((
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
    ));
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let quality_pair = (
        match region_start_quality {
            Some(q) => q,
            None => quality(cfg, &start)?,
        },
        quality(cfg, &output.points)?,
    );
    Ok(GenerateReport {
        energy_name: energy.name(),
        start,
        output,
        energy: energy_pair,
        quality: quality_pair,
        choice,
        shift,
        polish,
        stages: Vec::new(),
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// One run of a solver on a problem: the budget and where checkpoints go. Every solver
/// of the crate is run through [`Run::solve`] (and so through the one executor).
pub(crate) struct Run<'a> {
    pub(crate) problem: &'a Problem<'a>,
    pub(crate) steps: usize,
    pub(crate) checkpoint: Option<&'a CheckpointPlan>,
    /// The run's configuration, recorded in checkpoints and compared on resume.
    pub(crate) config: &'a Value,
}

impl Run<'_> {
    /// Runs `solver` from `start` (or from the plan's checkpoint) through the executor.
    pub(crate) fn solve(
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

    pub(crate) fn execute<I: Integrator>(
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
                ) if name.starts_with("checkpoint") => Error::invalid(
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

/// A fingerprint of a point set: n, s and the FNV-1a hash of its coordinates' bits.
pub fn points_fingerprint(points: &PointSet) -> String {
    let bytes: Vec<u8> = points
        .as_slice()
        .iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .collect();
    format!(
        "{} points in {} dimensions, fnv1a64 {:016x}",
        points.n(),
        points.s(),
        fnv1a64(&bytes)
    )
}

/// The DEM's settings under their parameter names.
pub(crate) fn dem_json(dem: &Dem, steps: usize) -> Value {
    json!({
        "steps": steps,
        "kappa": format!("{:?}", dem.kappa),
        "restart": format!("{:?}", dem.restart),
        "tolerance": dem.tolerance,
        "dt": dem.dt,
        "G": dem.g,
    })
}

/// Everything in a configuration that decides its output, under the parameters' names:
/// what a checkpoint records and a resume compares.
pub fn config_json(cfg: &GenerateConfig) -> Value {
    let (run, region, description) = match &cfg.space {
        Space::Cube => ("cube", Value::Null, Value::Null),
        Space::Region {
            domain,
            description,
        } => ("region", json!(format!("{domain:?}")), description.clone()),
    };
    let mut v = json!({
        "run": run,
        "region": region,
        "n": cfg.n,
        "s": cfg.s,
        "energy": format!("{:?}", cfg.energy),
        "q": cfg.q.map(|q| format!("{q:?}")),
        "p": cfg.p,
        "precision": cfg.precision.label(),
        "init": match &cfg.init {
            Init::Halton => "halton".to_string(),
            Init::Random => "random".to_string(),
            Init::Points(p) => format!("file: {}", points_fingerprint(p)),
        },
        "seed": cfg.seed,
        "integrator": format!("{:?}", cfg.solver),
        "log_every": cfg.log_every,
        "shifts": cfg.shifts,
        "polish": cfg.polish.map(|k| format!("{k:?}")),
        "lbfgs": format!("{:?}", cfg.lbfgs),
        // The vector code path: the bytes of a run are the same for any thread count on
        // one path, and may differ in the last bits between paths.
        "kernel": crate::energies::pairs::vector_path(),
    });
    // Only a goal run records its goal, so a paper run's record is what it always was.
    if let (Value::Object(map), false) = (&mut v, cfg.goal == Goal::Paper) {
        map.insert("goal".into(), json!(format!("{:?}", cfg.goal)));
    }
    if let (Value::Object(map), Some(old)) = (&mut v, &cfg.extend) {
        map.insert("extend".into(), json!(points_fingerprint(old)));
    }
    if let (Value::Object(map), false) = (&mut v, cfg.nested.is_empty()) {
        map.insert("nested".into(), json!(cfg.nested));
    }
    if let (Value::Object(map), Some(r)) = (&mut v, cfg.randomize) {
        map.insert("randomize".into(), json!(format!("{r:?}")));
    }
    if let (Value::Object(map), Value::Object(dem)) = (&mut v, dem_json(&cfg.dem, cfg.steps)) {
        map.extend(dem);
    }
    // How the region was described (an expression and box, a shape), key by key.
    if let (Value::Object(map), Value::Object(d)) = (&mut v, description) {
        map.extend(d);
    }
    v
}
