//! What a run is: its configuration (space, energy, start, solver, goal, post-steps) and
//! the settings record that a checkpoint keeps and a file header shows.

use crate::post::randomize::Randomize;
use serde_json::{json, Value};
use std::sync::Arc;
use stillpoint_domains::{Domain, PointSet};
use stillpoint_energies::discrepancy::DiscrepancyKind;
use stillpoint_energies::{Distance, Precision};
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::Dem;
use stillpoint_quality::target::Target;
use stillpoint_solve::Solver;

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

/// What a run is for: the pipeline that makes the points.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// The configured start, energy and solver, then the post-steps. With the defaults of
    /// [`GenerateConfig::new`] this is exactly the paper's pipeline (Halton start, U_{q,p}
    /// with eq. 48, the DEM, shift selection): `--method paper`.
    Paper,
    /// Quasi-Monte Carlo integration: a stratified set (one point per 1/n interval in
    /// every coordinate) with the target's discrepancy as low as the descent reaches
    /// ([`crate::goals::integration::integration_set`]). The unit cube only.
    Integration(Target),
    /// Design of computer experiments: a stratified set with the largest smallest
    /// distance found, from the better of the paper's DEM result (stratified) and a
    /// Latin hypercube, each improved by the maximin swap search
    /// ([`stillpoint_sequences::maximin_search`]). In a region: the configured region run.
    SpaceFilling,
}

impl Goal {
    /// Whether the goal is integration (with any target): the rules of grown sets and of
    /// the lattice from 500 points on ask only this.
    pub fn is_integration(&self) -> bool {
        matches!(self, Goal::Integration(_))
    }
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
    /// [`crate::post::shift`].
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
    /// integration goal in the cube): [`crate::goals::integration::extend_set`].
    pub extend: Option<PointSet>,
    /// Sizes N1 < N2 < … = n of a nested set, each prefix made for its size (the
    /// integration goal in the cube): [`crate::goals::integration::nested_set`]. Empty: one set.
    pub nested: Vec<usize>,
    /// How the report's O(n²) metrics are formed: exact, or estimated above a size.
    pub sums: stillpoint_quality::metrics::Sums,
    /// The integration goal's set is the shifted tent lattice
    /// ([`crate::goals::integration::lattice::lattice_rule`]) instead of a descent on the
    /// target: the default from [`crate::goals::integration::lattice::LATTICE_FROM_N`]
    /// points on and at s = 1, or `--target lattice`.
    pub lattice: bool,
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

    /// The paper's pipeline in the cube (`generate --method paper`; the command's default
    /// is the integration goal, [`GenerateConfig::for_goal`]): (q, p) from eq. 48, plain
    /// Halton start, the paper's DEM with 1000 steps, κ trial from 100, restart threshold 2/n, then the best of 64 periodic
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
            sums: stillpoint_quality::metrics::Sums::AUTO,
            lattice: false,
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

    /// The same run as the paper's pipeline: the part of a goal's run that is the
    /// paper's (the space-filling goal's DEM run).
    pub fn as_paper(&self) -> Self {
        GenerateConfig {
            goal: Goal::Paper,
            ..self.clone()
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

/// A step after the solver. Each is one function in a module of its own; a new one is
/// one more arm here and in `stillpoint::pipeline::generate_with`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PostStep {
    /// The best of this many periodic shifts ([`crate::post::shift`]), after a periodic energy.
    Shift(usize),
    /// L-BFGS on a squared discrepancy ([`crate::post::polish`]).
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
        stillpoint_solve::checkpoint::fnv1a64(&bytes)
    )
}

/// The DEM's settings under their options' names (the fields' names are the keys).
#[derive(serde::Serialize)]
struct DemRecord {
    steps: usize,
    kappa: String,
    restart: String,
    tolerance: f64,
    dt: f64,
    #[serde(rename = "G")]
    g: f64,
}

/// The DEM's settings under their parameter names.
pub(crate) fn dem_json(dem: &Dem, steps: usize) -> Value {
    json!(DemRecord {
        steps,
        kappa: format!("{:?}", dem.kappa),
        restart: format!("{:?}", dem.restart),
        tolerance: dem.tolerance,
        dt: dem.dt,
        g: dem.g,
    })
}

/// What decides a run's output, each under its option's name: the fields' names are the
/// keys of [`config_json`], so no name is written twice. The fields a paper run never had
/// are left out when unset, so that its record is what it always was.
#[derive(serde::Serialize)]
struct ConfigRecord {
    run: &'static str,
    region: Value,
    n: usize,
    s: usize,
    energy: String,
    q: Option<String>,
    p: Option<f64>,
    precision: &'static str,
    init: String,
    seed: u64,
    integrator: String,
    log_every: usize,
    shifts: usize,
    polish: Option<String>,
    lbfgs: String,
    // The vector code path: the bytes of a run are the same for any thread count on one
    // path, and may differ in the last bits between paths.
    kernel: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    goal: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    extend: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    nested: Option<Vec<usize>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    randomize: Option<String>,
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
    let mut v = json!(ConfigRecord {
        run,
        region,
        n: cfg.n,
        s: cfg.s,
        energy: format!("{:?}", cfg.energy),
        q: cfg.q.map(|q| format!("{q:?}")),
        p: cfg.p,
        precision: cfg.precision.label(),
        init: match &cfg.init {
            Init::Halton => "halton".to_string(),
            Init::Random => "random".to_string(),
            Init::Points(p) => format!("file: {}", points_fingerprint(p)),
        },
        seed: cfg.seed,
        integrator: format!("{:?}", cfg.solver),
        log_every: cfg.log_every,
        shifts: cfg.shifts,
        polish: cfg.polish.map(|k| format!("{k:?}")),
        lbfgs: format!("{:?}", cfg.lbfgs),
        kernel: stillpoint_energies::pairs::vector_path(),
        // Only a goal run records its goal, so a paper run's record is what it always was.
        goal: (cfg.goal != Goal::Paper).then(|| format!("{:?}", cfg.goal)),
        extend: cfg.extend.as_ref().map(points_fingerprint),
        nested: (!cfg.nested.is_empty()).then(|| cfg.nested.clone()),
        randomize: cfg.randomize.map(|r| format!("{r:?}")),
    });
    if let (Value::Object(map), Value::Object(dem)) = (&mut v, dem_json(&cfg.dem, cfg.steps)) {
        map.extend(dem);
    }
    // How the region was described (an expression and box, a shape), key by key.
    if let (Value::Object(map), Value::Object(d)) = (&mut v, description) {
        map.extend(d);
    }
    v
}
