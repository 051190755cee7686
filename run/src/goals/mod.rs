//! The goals: what a run is for decides its pipeline. [`integration`] (the cube's
//! default; in a region [`region_integration`]), [`space_filling`] and the [`paper`]'s
//! own pipeline.

pub mod integration;
pub mod paper;
pub mod region_integration;
pub mod space_filling;

use crate::config::GenerateConfig;
use crate::report::{quality, GenerateReport, Stage};
use crate::Error;
use stillpoint_domains::PointSet;
use stillpoint_integrators::RunOutput;

/// A goal's run as a report: the start and the result with their quality, the value the
/// goal lowered (or raised) as the energy pair, and its stages. A goal run is no single
/// solver run, so the report's solver output carries only the points (see
/// [`GenerateReport::solver`]).
pub fn goal_report(
    cfg: &GenerateConfig,
    start: PointSet,
    points: PointSet,
    energy: (f64, f64),
    energy_name: String,
    stages: Vec<Stage>,
) -> Result<GenerateReport, Error> {
    let clock = std::time::Instant::now();
    let after = quality(cfg, &points)?;
    // A construction with no start of its own reports its set as both: one pass over the
    // pairs, not two.
    let before = if start == points {
        after.clone()
    } else {
        quality(cfg, &start)?
    };
    let quality_pair = (before, after);
    let timings = vec![("figures".to_string(), clock.elapsed().as_secs_f64())];
    Ok(GenerateReport {
        start,
        output: RunOutput {
            points,
            trajectory: Vec::new(),
            // The type asks for a stop reason; no report reads it, as `solver()` is `None`
            // without an energy choice. Each solver run's own stop is in the stages.
            stop: stillpoint_integrators::StopReason::Converged,
            info: Vec::new(),
        },
        energy,
        energy_name,
        quality: quality_pair,
        choice: None,
        shift: None,
        polish: None,
        stages,
        seconds: 0.0,
        timings,
    })
}
