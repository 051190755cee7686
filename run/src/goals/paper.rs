//! The paper's pipeline.

use crate::config::{config_json, EnergyKind, GenerateConfig, PostStep, Space};
use crate::plan::problem::{build_problem, choose_energy};
use crate::plan::start::start_set;
use crate::post::shift::{self};
use crate::report::{quality, GenerateReport};
use crate::Error;
use std::time::Instant;
use stillpoint_domains::{PeriodicCube, PointSet};
use stillpoint_energies::{Distance, Energy, Precision};
use stillpoint_integrators::Record;
use stillpoint_solve::checkpoint::CheckpointPlan;
use stillpoint_solve::Solver;
use stillpoint_solve::{Event, LoggingObserver, Solve};

/// The configured pipeline: start, solver through the executor, post-steps.
pub fn paper_run(
    cfg: &GenerateConfig,
    checkpoint: Option<&CheckpointPlan>,
    mut on_event: impl FnMut(Event),
) -> Result<GenerateReport, Error> {
    let clock = Instant::now();
    let mut start = start_set(cfg)?;
    let (problem, choice) = build_problem(cfg)?;
    if cfg.polish.is_some() && cfg.region().is_some() {
        return Err(Error::invalid(
            stillpoint_parse::names::POLISH,
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
        let run = Solve {
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
    let full_energies = full_energies(cfg, &start, &output.points)?;
    let (shift, polish) = post_steps(cfg, domain.is_periodic(), &mut output, &mut on_event)?;
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
        choice: Some(choice),
        shift,
        polish,
        stages: Vec::new(),
        seconds: clock.elapsed().as_secs_f64(),
        timings: Vec::new(),
    })
}

/// The energies reported for the start and the DEM's result, at full precision when the
/// run used the fast table (`None`: the run's own values are already exact).
fn full_energies(
    cfg: &GenerateConfig,
    start: &PointSet,
    result: &PointSet,
) -> Result<Option<(f64, f64)>, Error> {
    Ok(match (&cfg.space, cfg.energy) {
        (Space::Cube, EnergyKind::Uqp) if cfg.precision != Precision::Full => {
            let (e, _) = choose_energy(cfg.n, cfg.s, cfg.q, cfg.p)?;
            match e.distance() {
                Distance::Q(q) if Precision::fast_applies(q) => {
                    Some((e.value(start), e.value(result)))
                }
                _ => None,
            }
        }
        _ => None,
    })
}

/// The configured post-steps on the solver's result, in order: the best periodic shift
/// (on the torus only, where a shift is a motion the energy does not see) and the polish.
#[allow(clippy::type_complexity)]
fn post_steps(
    cfg: &GenerateConfig,
    periodic: bool,
    output: &mut stillpoint_integrators::RunOutput,
    on_event: &mut impl FnMut(Event),
) -> Result<(Option<shift::ShiftOutcome>, Option<(f64, f64, usize)>), Error> {
    let (mut shift, mut polish) = (None, None);
    for step in cfg.post_steps() {
        match step {
            PostStep::Shift(candidates) if periodic => {
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
                    name: stillpoint_parse::names::POLISH,
                    steps: Some(cfg.steps as u64),
                });
                let p = crate::post::polish::polish(
                    &output.points,
                    kind,
                    cfg.steps,
                    &cfg.lbfgs,
                    |step| on_event(Event::Progress(step)),
                )?;
                output.points = p.points;
                polish = Some((p.before, p.after, p.iterations));
            }
        }
    }
    Ok((shift, polish))
}
