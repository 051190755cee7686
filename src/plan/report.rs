//! What a run reports: the start and the result with their quality, and what each stage did.

use crate::energies::PointSet;
use crate::integrators::RunOutput;
use crate::plan::*;
use crate::post::shift::ShiftOutcome;
use crate::quality::metrics::Metrics;
use crate::quality::region::RegionMetrics;
use crate::Error;

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

/// The quality figures of a set in the configuration's space.
pub(crate) fn quality(cfg: &GenerateConfig, points: &PointSet) -> Result<Quality, Error> {
    Ok(match cfg.region() {
        Some(domain) => Quality::Region(RegionMetrics::compute(domain, points)?),
        None => Quality::Cube(Metrics::compute(points)),
    })
}
