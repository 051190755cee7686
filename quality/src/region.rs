//! Point sets in regions (§5.4, eq. 58): the start of a run in a region and the figures
//! that measure a set there (U_{E,∞,g}, the paper's measure of uniformity in a region,
//! where no discrepancy formula applies, with the minimum point and boundary distances;
//! and how well the set represents the region's uniform distribution, its energy
//! distance to it, [`crate::energy_distance`]).
//! Region runs themselves go through the one pipeline of `stillpoint::pipeline`.

use crate::energy_distance::{energy_distance, fraction_inside};
use crate::Error;
use std::sync::Arc;
use stillpoint_domains::{Domain, PointSet};
use stillpoint_energies::boundary::UEInfG;
use stillpoint_energies::Energy;

/// Uniformity figures of a set in a region.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RegionMetrics {
    /// U_{E,∞,g} (eq. 56): the paper's uniformity measure in a region.
    pub energy_e_inf_g: f64,
    /// Smallest distance between two points.
    pub min_distance: f64,
    /// Smallest distance from a point to the boundary.
    pub min_boundary_distance: f64,
    /// The energy distance D² to the uniform distribution on the region, estimated from
    /// an independent uniform sample ([`energy_distance`]).
    pub energy_distance: f64,
    /// Its standard error.
    pub energy_distance_se: f64,
    /// The share of the points inside the region.
    pub fraction_inside: f64,
}

/// The seed of the uniform sample every reported energy distance is measured against:
/// one fixed sample, so that two sets' figures compare without the sample's noise.
pub const MEASURE_SEED: u64 = 0x00e4_e7d1_5e7a_11ce;

impl RegionMetrics {
    /// Computes the figures (O(n²) for the distances, n boundary projections, O(n·32 768)
    /// for the energy distance).
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
        let ed = energy_distance(domain, points, MEASURE_SEED)?;
        Ok(RegionMetrics {
            energy_e_inf_g: u,
            min_distance: md,
            min_boundary_distance: mb,
            energy_distance: ed.value,
            energy_distance_se: ed.standard_error,
            fraction_inside: fraction_inside(domain, points),
        })
    }
}

/// The figures of `eval` for a set in a region, as JSON: `n`, `s`, `energy_distance`
/// (D² to the uniform distribution on the region, the square form) with
/// `energy_distance_se` and `energy_distance_reference_points`, `min_distance`,
/// `fraction_inside`. Points outside are measured as they are (and counted).
pub fn region_eval_json(
    domain: &Arc<dyn Domain>,
    points: &PointSet,
) -> Result<serde_json::Value, Error> {
    if points.n() == 0 {
        return Err(Error::invalid("points", "0 points", "at least 1 point"));
    }
    let ed = energy_distance(domain, points, MEASURE_SEED)?;
    let md = crate::metrics::min_distance_euclidean(points);
    Ok(serde_json::json!({
        "n": points.n(),
        "s": points.s(),
        "energy_distance": ed.value,
        "energy_distance_se": ed.standard_error,
        "energy_distance_reference_points": ed.reference_points,
        "min_distance": if md.is_finite() { serde_json::json!(md) } else { serde_json::Value::Null },
        "fraction_inside": fraction_inside(domain, points),
    }))
}

/// [`region_eval_json`]'s figures as the lines `eval` prints.
pub fn region_eval_text(v: &serde_json::Value) -> String {
    let f = |k: &str| {
        v[k].as_f64()
            .map_or("-".to_string(), |x| format!("{x:.6e}"))
    };
    format!(
        "{}: n = {}, s = {}\n  energy distance to uniform on the region (D², not its root) {} \
         ± {} (standard error, {} uniform points)\n  minimum distance {}\n  share inside {}\n",
        v["file"].as_str().unwrap_or("points"),
        v["n"],
        v["s"],
        f("energy_distance"),
        f("energy_distance_se"),
        v["energy_distance_reference_points"],
        f("min_distance"),
        v["fraction_inside"],
    )
}
