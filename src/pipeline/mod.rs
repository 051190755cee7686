//! The pipeline of every run: a [`Request`] is resolved once into a configuration
//! ([`request`]); [`generate_with`] runs its [`Pipeline`] (the one choice of pipeline,
//! [`dispatch`]: integration, space-filling or the paper's) through the one executor,
//! applies the post-steps (randomisation last), and reports on the set it returns.
//! [`generate`], [`paper`] and [`region`] are the one-call entry points.

pub mod calls;
pub mod dispatch;
pub mod estimate;
pub mod evaluation;
pub mod integration;
pub mod measure;
pub mod options;
pub mod request;
pub mod worker;

use crate::integrators::Record;
use crate::{Error, PointSet};
use std::time::Instant;

use crate::config::GenerateConfig;
use crate::post::randomize::Randomize;
use crate::report::{quality, GenerateReport, Stage};
use crate::solve::checkpoint::CheckpointPlan;
use crate::solve::Event;
pub use dispatch::Pipeline;
use request::{Arg, Job, Request, Resolved};

/// The default set: `n` points in [0, 1)^`s` for integration, stratified in every
/// coordinate with the discrepancy as low as the descent reaches (what `stillpoint
/// generate -n N -s S` writes).
pub fn generate(n: usize, s: usize) -> Result<PointSet, Error> {
    Ok(Request::new(n, s).resolve()?.run(None, |_| {})?.points)
}

/// The paper's pipeline for `n` points in [0, 1)^`s`: Halton start, U_{q,p} with (q, p)
/// from eq. 48, 1000 steps of the damped dynamics, the best of 64 periodic shifts.
pub fn paper(n: usize, s: usize) -> Result<PointSet, Error> {
    let mut r = Request::new(n, s);
    r.method = Some("paper".into());
    Ok(r.resolve()?.run(None, |_| {})?.points)
}

/// `n` points spread over a region given as text: a shape (`ball:1@0,0`,
/// `ellipsoid:2,1`, `box:0,1,0,2`, `polytope:FILE` with `bbox`) or an expression g(x)
/// with the region {g ≤ 0} inside `bbox` (LO1,HI1,LO2,HI2,...). `bbox` is empty for a
/// shape that carries its own extent.
pub fn region(n: usize, text: &str, bbox: &[f64]) -> Result<PointSet, Error> {
    let shape = ["ball:", "ellipsoid:", "box:", "simplex", "polytope:"]
        .iter()
        .any(|k| text.trim_start().starts_with(k));
    let mut r = Request {
        n: Some(n.into()),
        ..Request::default()
    };
    if shape {
        r.shape = Some(text.into());
    } else {
        r.region = Some(text.into());
    }
    if !bbox.is_empty() {
        r.bbox = Some(Arg::Numbers(bbox.to_vec()));
    }
    Ok(r.resolve()?.run(None, |_| {})?.points)
}

/// What a resolved request produced: the points as written (scaled to the bounds when
/// asked, a mixture's last component appended), and for a run its report (on the run's
/// own points: a mixture's first S − 1 components) and configuration.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The points as the caller receives them.
    pub points: PointSet,
    /// The run's report (none for a baseline).
    pub report: Option<GenerateReport>,
    /// The design, for a request with a design space (then `points` holds its numbers:
    /// values, integers, label indices).
    pub design: Option<crate::design::Design>,
}

impl Resolved {
    /// Runs what the request asked for, with checkpoints as `checkpoint` says and every
    /// [`Event`] passed to `on_event`.
    pub fn run(
        &self,
        checkpoint: Option<&CheckpointPlan>,
        on_event: impl FnMut(Event),
    ) -> Result<Outcome, Error> {
        let (points, report) = match &self.job {
            Job::Baseline {
                baseline,
                n,
                s,
                seed,
            } => (baseline.generate(*n, *s, *seed)?, None),
            Job::Law {
                n,
                unbounded,
                seed,
                picked: false,
            } => (crate::sequences::law_lattice(*n, unbounded, *seed)?, None),
            Job::Law {
                n,
                unbounded,
                seed,
                picked: true,
            } => {
                // The draws are judged on normal scores; the laws live in `design`.
                let normal = crate::design::Marginal::Normal {
                    mu: 0.0,
                    sigma: 1.0,
                };
                let ppf = move |u: f64| normal.ppf(u);
                let cube = cube_default(*n, unbounded.len(), *seed)?;
                let points =
                    crate::sequences::law_lattice_picked_or(*n, unbounded, *seed, &ppf, cube)?;
                (points, None)
            }
            Job::Run(cfg) => {
                let report = generate_with(cfg, checkpoint, on_event)?;
                (report.output.points.clone(), Some(report))
            }
        };
        let points = match (&self.bounds, &self.mixture) {
            (Some(b), _) => b.scale(&points)?,
            (None, Some(m)) => m.lift(&points)?,
            (None, None) => points,
        };
        let Some(space) = &self.design else {
            return Ok(Outcome {
                points,
                report,
                design: None,
            });
        };
        use crate::design::balance::Finish;
        let (seed, finish) = match &self.job {
            Job::Run(cfg) => (cfg.seed, Pipeline::of(cfg).finish(cfg)),
            Job::Baseline { seed, .. } | Job::Law { seed, .. } => (*seed, Finish::Nothing),
        };
        let rule = self.rule.unwrap_or(measure::CubeRule::Dealt);
        let design = rule.design(space, &points, seed, finish)?;
        Ok(Outcome {
            points: design.numbers()?,
            report,
            design: Some(design),
        })
    }
}

/// The set the cube's default makes for n, s and the seed (a request with nothing else),
/// the picked lattice's seventeenth candidate.
fn cube_default(n: usize, s: usize, seed: u64) -> Result<Option<PointSet>, Error> {
    match Job::default_config(n, s, seed) {
        Some(cfg) => Ok(Some(generate_with(&cfg, None, |_| {})?.output.points)),
        None => Ok(None),
    }
}

/// Runs a configuration, calling `on_record` with every trajectory record.
pub fn run_config(
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
    let pipeline = Pipeline::of(cfg);
    // The request's resolution refuses every combination below; a configuration made
    // by hand is the caller's to keep valid.
    debug_assert!(
        cfg.randomize.is_none() || cfg.region().is_none(),
        "randomisation in a region"
    );
    debug_assert!(
        pipeline.name(cfg).is_none() || cfg.region().is_some() || checkpoint.is_none(),
        "a checkpoint of a goal's run in the cube"
    );
    debug_assert!(
        cfg.nested.is_empty() || matches!(pipeline, Pipeline::Descent(_)),
        "nested sizes outside the integration goal in the cube"
    );
    debug_assert!(
        cfg.extend.is_none()
            || match cfg.region() {
                None => matches!(pipeline, Pipeline::Descent(_)),
                Some(domain) => {
                    pipeline.target().is_none()
                        && cfg.extend.as_ref().is_some_and(|old| {
                            old.s() == cfg.s
                                && old.n() <= cfg.n
                                && old.rows().all(|r| domain.contains(r))
                        })
                }
            },
        "points to extend that the run cannot keep"
    );
    let mut report = pipeline.run(cfg, checkpoint, &mut on_event)?;
    crate::solve::stop_if_cancelled()?;
    if let Some(kind) = cfg.randomize {
        report.output.points =
            crate::post::randomize::randomize(&report.output.points, kind, cfg.seed);
        report.quality.1 = quality(cfg, &report.output.points)?;
        // Every row of the report describes the written set: the value the run lowered
        // is evaluated again on the randomised points.
        report.energy.1 = pipeline.value_on(cfg, &mut report)?;
        report.stages.push(Stage::Randomized {
            how: match kind {
                Randomize::Shift => "uniform shift modulo 1",
                Randomize::Cells => "cells rotated, offsets shifted within their cells",
                Randomize::Tent => "uniform shift modulo 1, then the tent transform",
            }
            .into(),
            seed: cfg.seed,
        });
    }
    if crate::solve::cancelled() {
        return Err(crate::solve::interrupted());
    }
    report.seconds = clock.elapsed().as_secs_f64();
    Ok(report)
}
