//! The goals: what a run is for decides its pipeline. [`integration`] (the cube's
//! default), [`space_filling`] and the [`paper`]'s own pipeline.

pub mod integration;
pub mod paper;
pub mod space_filling;

use crate::energies::PointSet;
use crate::integrators::RunOutput;
use crate::plan::report::quality;
use crate::plan::*;
use crate::Error;

/// A goal's run as a report: the start and the result with their quality, the value the
/// goal lowered (or raised) as the energy pair.
pub(crate) fn goal_report(
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
