//! The energy and domain of a configuration (its [`Problem`]), with how U_{q,p}'s (q, p)
//! were chosen, and a rough time estimate for warning before a long run.

use crate::config::{EnergyKind, GenerateConfig, Init, Space};
use crate::plan::start::start_set;
use crate::Error;
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;
use stillpoint_domains::shapes::BoxRegion;
use stillpoint_domains::{Domain, PeriodicCube};
use stillpoint_energies::boundary::{UEInfG, UEpG};
use stillpoint_energies::discrepancy::DiscrepancyEnergy;
use stillpoint_energies::einf::UEInf;
use stillpoint_energies::{paper_qp, Distance, Energy, Uqp};
use stillpoint_integrators::Problem;
use stillpoint_sequences as sequences;

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

/// The energy and domain of a configuration, with how (q, p) were chosen.
pub fn build_problem(cfg: &GenerateConfig) -> Result<(Problem<'static>, EnergyChoice), Error> {
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
                    stillpoint_parse::names::ENERGY,
                    format!("{other:?}"),
                    "an energy of the cube (U_{q,p}, U_{E,∞} or a discrepancy); the \
                     boundary-aware energies need a region",
                ))
            }
            (Space::Region { .. }, other) => {
                return Err(Error::invalid(
                    stillpoint_parse::names::ENERGY,
                    format!("{other:?}"),
                    "an energy of a region (U_{E,∞,g}, U_{E,p,g} or U_{E,∞})",
                ))
            }
        };
    // A region's set that grows: the old points take part in the energy and never move.
    let energy: Arc<dyn Energy> = match (&cfg.extend, cfg.region()) {
        (Some(old), Some(_)) => Arc::new(stillpoint_energies::fixed::WithFixed::new(
            energy,
            old.clone(),
        )),
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
