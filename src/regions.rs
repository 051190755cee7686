//! Point sets in regions: the driver behind `stillpoint generate --region/--shape` and the
//! paper's four examples (§5.4, eq. 58).
//!
//! A region run starts from the paper's start (uniform points in the bounding box, the
//! first n inside) or a Halton variant of it, runs the DEM under a boundary-aware energy,
//! and reports U_{E,∞,g} before and after (the paper's measure of uniformity in a region,
//! where no discrepancy formula applies), with the minimum point and boundary distances.
//! Region runs checkpoint and resume like cube runs ([`generate_in_region_with`]).

use crate::energies::boundary::{UEInfG, UEpG};
use crate::energies::einf::UEInf;
use crate::energies::{Distance, Domain, Energy, PointSet};
use crate::integrators::lbfgs::Lbfgs;
use crate::integrators::{Dem, Kappa, Problem, Record, RunOutput};
use crate::run::{
    dem_json, points_fingerprint, CheckpointPlan, Event, LoggingObserver, Run, Solver,
};
use crate::{sequences, Error};
use std::sync::Arc;
use std::time::Instant;

/// The energy a region run minimises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RegionEnergy {
    /// U_{E,∞,g} of eq. 56 (the paper's choice): 1 / min(point distances, 2 × boundary
    /// distances), with the active-element subgradient of eq. 57.
    EInfG,
    /// U_{E,p,g}: the smooth finite-p version, (Σ d_ij^{−p} + Σ (2 d_ig)^{−p})^{1/p}.
    EpG(f64),
    /// U_{E,∞} without the boundary term (points may sit on the boundary).
    EInf,
}

impl RegionEnergy {
    /// Builds the energy for a domain.
    pub fn build(&self, domain: Arc<dyn Domain>) -> Result<Box<dyn Energy>, Error> {
        Ok(match *self {
            RegionEnergy::EInfG => Box::new(UEInfG::new(domain)?),
            RegionEnergy::EpG(p) => Box::new(UEpG::new(domain, p)?),
            RegionEnergy::EInf => Box::new(UEInf::new(Distance::Euclidean)?),
        })
    }
}

/// Where a region run starts.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionInit {
    /// Uniform points in the bounding box, the first n inside (§5.4).
    Random,
    /// Halton points scaled to the bounding box, the first n inside.
    Halton,
    /// Given points, all inside the region.
    Points(PointSet),
}

/// A region run.
#[derive(Debug, Clone)]
pub struct RegionConfig {
    /// The region.
    pub domain: Arc<dyn Domain>,
    /// Number of points.
    pub n: usize,
    /// The energy.
    pub energy: RegionEnergy,
    /// The start.
    pub init: RegionInit,
    /// Seed of the random start.
    pub seed: u64,
    /// The solver.
    pub solver: Solver,
    /// The step budget.
    pub steps: usize,
    /// The DEM's settings.
    pub dem: Dem,
    /// L-BFGS settings.
    pub lbfgs: Lbfgs,
}

impl RegionConfig {
    /// Defaults: U_{E,∞,g}, the paper's random start with seed 0, the DEM with the κ trial
    /// and 10 000 steps. The paper's 1000 steps separate the closest pairs (U_{E,∞,g}
    /// already falls by 80–90 %) but leave most points where they started; 10 000 spread
    /// them.
    pub fn new(domain: Arc<dyn Domain>, n: usize) -> Self {
        RegionConfig {
            domain,
            n,
            energy: RegionEnergy::EInfG,
            init: RegionInit::Random,
            seed: 0,
            solver: Solver::Dem,
            steps: 10_000,
            dem: Dem {
                kappa: Kappa::default(),
                ..Dem::default()
            },
            lbfgs: Lbfgs::default(),
        }
    }
}

/// Uniformity figures of a set in a region.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RegionMetrics {
    /// U_{E,∞,g} (eq. 56): the paper's uniformity measure in a region.
    pub energy_e_inf_g: f64,
    /// Smallest distance between two points.
    pub min_distance: f64,
    /// Smallest distance from a point to the boundary.
    pub min_boundary_distance: f64,
}

impl RegionMetrics {
    /// Computes the figures (O(n²) for the distances, n boundary projections).
    pub fn compute(domain: &Arc<dyn Domain>, points: &PointSet) -> Result<Self, Error> {
        let u = UEInfG::new(domain.clone())?.value(points);
        let md = crate::metrics::min_distance_euclidean(points);
        let mut foot = vec![0.0; points.s()];
        let mb = points
            .rows()
            .map(|x| {
                domain
                    .closest_boundary_point(x, &mut foot)
                    .unwrap_or(f64::INFINITY)
            })
            .fold(f64::INFINITY, f64::min);
        Ok(RegionMetrics {
            energy_e_inf_g: u,
            min_distance: md,
            min_boundary_distance: mb,
        })
    }
}

/// The outcome of a region run.
#[derive(Debug, Clone)]
pub struct RegionReport {
    /// The start set.
    pub start: PointSet,
    /// The DEM output (final points and trajectory).
    pub output: RunOutput,
    /// The energy minimised, with its parameters.
    pub energy_name: String,
    /// Figures of the start and of the result.
    pub metrics: (RegionMetrics, RegionMetrics),
    /// Wall time in seconds.
    pub seconds: f64,
}

impl RegionReport {
    /// 1 − U_{E,∞,g}(result) / U_{E,∞,g}(start): the paper's "optimization ratio".
    pub fn reduction(&self) -> f64 {
        1.0 - self.metrics.1.energy_e_inf_g / self.metrics.0.energy_e_inf_g
    }
}

/// The start of a region run.
pub fn region_start(cfg: &RegionConfig) -> Result<PointSet, Error> {
    if cfg.n == 0 {
        return Err(Error::invalid("n", cfg.n, "at least 1 point"));
    }
    let d = &cfg.domain;
    match &cfg.init {
        RegionInit::Random => d.sample(cfg.n, cfg.seed),
        RegionInit::Halton => {
            let (lo, hi) = d.bounding_box();
            let s = lo.len();
            let budget = 10_000.max(1000 * cfg.n);
            let h = sequences::halton(budget, s)?;
            let mut data = Vec::with_capacity(cfg.n * s);
            let mut y = vec![0.0; s];
            for row in h.rows() {
                for k in 0..s {
                    y[k] = lo[k] + (hi[k] - lo[k]) * row[k];
                }
                if d.contains(&y) {
                    data.extend_from_slice(&y);
                    if data.len() == cfg.n * s {
                        return PointSet::new(cfg.n, s, data);
                    }
                }
            }
            Err(Error::invalid(
                "region",
                format!("{} of {budget} Halton points inside", data.len() / s),
                format!(
                    "a region filling enough of its box to hold {} points",
                    cfg.n
                ),
            ))
        }
        RegionInit::Points(p) => {
            if p.s() != d.dim() {
                return Err(Error::invalid(
                    "init points",
                    format!("dimension {}", p.s()),
                    format!("the region's dimension {}", d.dim()),
                ));
            }
            if let Some(i) = (0..p.n()).find(|&i| !d.contains(p.point(i))) {
                return Err(Error::invalid(
                    format!("init point {}", i + 1),
                    format!("{:?}", p.point(i)),
                    "a point inside the region",
                ));
            }
            Ok(p.clone())
        }
    }
}

/// Runs the DEM in a region.
pub fn generate_in_region(
    cfg: &RegionConfig,
    mut on_record: impl FnMut(&crate::integrators::Record),
) -> Result<RegionReport, Error> {
    generate_in_region_with(cfg, None, |e| {
        if let Event::Record(r) = e {
            on_record(r)
        }
    })
}

/// Runs the DEM in a region as [`generate_in_region`] does, with checkpoints written (and
/// an earlier one resumed) as `checkpoint` says, and every [`Event`] passed to
/// `on_event`. A region is only known to the checkpoint by its bounding box and kind:
/// callers that build it from text should put that text into the plan's `extra`.
pub fn generate_in_region_with(
    cfg: &RegionConfig,
    checkpoint: Option<&CheckpointPlan>,
    mut on_event: impl FnMut(Event),
) -> Result<RegionReport, Error> {
    let clock = Instant::now();
    let start = region_start(cfg)?;
    let energy = cfg.energy.build(cfg.domain.clone())?;
    let config = region_config_json(cfg);
    let problem = Problem::shared(Arc::from(energy), cfg.domain.clone())?;
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let before = RegionMetrics::compute(&cfg.domain, &start)?;
    on_event(Event::Stage {
        name: match cfg.solver {
            Solver::Dem => "DEM",
            Solver::Lbfgs => "L-BFGS",
        },
        steps: Some(cfg.steps as u64),
    });
    let output = {
        let mut observer = LoggingObserver::new(0, |r: &Record| {
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
    on_event(Event::Stage {
        name: "metrics",
        steps: None,
    });
    let after = RegionMetrics::compute(&cfg.domain, &output.points)?;
    Ok(RegionReport {
        start,
        output,
        energy_name: problem.energy().name(),
        metrics: (before, after),
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// Everything in a region configuration that decides its output, under the
/// parameters' names (the region itself by its kind and box; see
/// [`generate_in_region_with`]).
pub fn region_config_json(cfg: &RegionConfig) -> serde_json::Value {
    let mut v = serde_json::json!({
        "run": "region",
        "region": format!("{:?}", cfg.domain),
        "n": cfg.n,
        "s": cfg.domain.dim(),
        "energy": format!("{:?}", cfg.energy),
        "init": match &cfg.init {
            RegionInit::Random => "random".to_string(),
            RegionInit::Halton => "halton".to_string(),
            RegionInit::Points(p) => format!("file: {}", points_fingerprint(p)),
        },
        "seed": cfg.seed,
        "integrator": format!("{:?}", cfg.solver),
    });
    if let (serde_json::Value::Object(map), serde_json::Value::Object(dem)) =
        (&mut v, dem_json(&cfg.dem, cfg.steps))
    {
        map.extend(dem);
    }
    v
}
