//! Point sets in regions (§5.4, eq. 58): the start of a run in a region and the figures
//! that measure a set there (U_{E,∞,g}, the paper's measure of uniformity in a region,
//! where no discrepancy formula applies, with the minimum point and boundary distances).
//! Region runs themselves go through the one pipeline of [`crate::pipeline`].

use crate::energies::boundary::UEInfG;
use crate::energies::{Domain, Energy, PointSet};
use crate::Error;
use std::sync::Arc;

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
        let md = crate::quality::metrics::min_distance_euclidean(points);
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
