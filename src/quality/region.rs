//! Point sets in regions (§5.4, eq. 58): the start of a run in a region and the figures
//! that measure a set there (U_{E,∞,g}, the paper's measure of uniformity in a region,
//! where no discrepancy formula applies, with the minimum point and boundary distances).
//! Region runs themselves go through the one pipeline of [`crate::run`].

use crate::energies::boundary::UEInfG;
use crate::energies::{Domain, Energy, PointSet};
use crate::run::Init;
use crate::{sequences, Error};
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

/// The start of a run in a region: the paper's (uniform in the box, the first n inside),
/// Halton points in the box (the first n inside), or given points, all inside.
pub fn start_in_region(
    d: &dyn Domain,
    n: usize,
    init: &Init,
    seed: u64,
) -> Result<PointSet, Error> {
    if n == 0 {
        return Err(Error::invalid("n", n, "at least 1 point"));
    }
    match init {
        Init::Random => d.sample(n, seed),
        Init::Halton => {
            let (lo, hi) = d.bounding_box();
            let s = lo.len();
            let budget = 10_000.max(1000 * n);
            let h = sequences::halton(budget, s)?;
            let mut data = Vec::with_capacity(n * s);
            let mut y = vec![0.0; s];
            for row in h.rows() {
                for k in 0..s {
                    y[k] = lo[k] + (hi[k] - lo[k]) * row[k];
                }
                if d.contains(&y) {
                    data.extend_from_slice(&y);
                    if data.len() == n * s {
                        return PointSet::new(n, s, data);
                    }
                }
            }
            Err(Error::invalid(
                "region",
                format!("{} of {budget} Halton points inside", data.len() / s),
                format!("a region filling enough of its box to hold {} points", n),
            ))
        }
        Init::Points(p) => {
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

/// A box or bounds given as LO1, HI1, LO2, HI2, …: split into (lo, hi), refusing an odd
/// count, LO ≥ HI, and a width that overflows or vanishes next to the coordinates (it
/// leaves nothing to draw or sample on). `name` and `shown` are the option and its
/// value as the caller spells them, for the refusal.
pub fn intervals(name: &str, shown: &str, v: &[f64]) -> Result<(Vec<f64>, Vec<f64>), Error> {
    if v.is_empty() || !v.len().is_multiple_of(2) || v.iter().any(|x| !x.is_finite()) {
        return Err(Error::invalid(
            name,
            shown,
            "LO1,HI1,LO2,HI2,...: two finite numbers per dimension",
        ));
    }
    let lo: Vec<f64> = v.iter().step_by(2).copied().collect();
    let hi: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
    if let Some(k) = (0..lo.len()).find(|&k| lo[k] >= hi[k]) {
        return Err(Error::invalid(
            name,
            shown,
            format!(
                "LO < HI, but dimension {} has LO = {} ≥ HI = {}",
                k + 1,
                lo[k],
                hi[k]
            ),
        ));
    }
    if let Some(k) = (0..lo.len()).find(|&k| {
        let w = hi[k] - lo[k];
        !(w.is_finite() && w > 1e-150 && w > 1e-12 * lo[k].abs().max(hi[k].abs()))
    }) {
        return Err(Error::invalid(
            name,
            shown,
            format!(
                "a width that is finite, above 1e-150 and not vanishing next to the \
                 coordinates, but dimension {} is [{:?}, {:?}]",
                k + 1,
                lo[k],
                hi[k]
            ),
        ));
    }
    Ok((lo, hi))
}
