//! How well a set represents the uniform distribution on a region: the energy distance
//! D² = 2E|X − Y| − E|X − X′| − E|Y − Y′| between the set's empirical measure (X) and
//! uniform points of the region (Y), estimated from an independent uniform sample, with
//! its standard error; and the reference samples the region's integration goal works
//! against (scrambled Sobol' points of the bounding box, kept when inside).
//!
//! D² is reported as it is defined (the square form, not its root): it is O(1/n) for
//! uniform random points and lower for a set that represents Ω better.

use crate::Error;
use std::sync::Arc;
use stillpoint_domains::{Domain, PointSet};
use stillpoint_energies::energy_distance::{cross_distance_sum, pair_distance_sum};
use stillpoint_sequences::{sobol_scrambled, stream_seed};

/// Independent batches of the uniform sample: the standard error is their spread.
pub const BATCHES: usize = 8;

/// Uniform points per batch (each batch's E|Y − Y′| costs O(BATCH² s)).
pub const BATCH: usize = 4096;

/// The energy distance of a set to the uniform distribution on a region.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct EnergyDistanceEstimate {
    /// The estimate of D² (unbiased: the mean of the batches' unbiased estimates).
    pub value: f64,
    /// Its standard error (the batches' standard deviation over √batches).
    pub standard_error: f64,
    /// Uniform points used in all.
    pub reference_points: usize,
}

/// The energy distance of `points` to the uniform distribution on `domain`, from
/// [`BATCHES`] independent uniform samples of [`BATCH`] points each drawn by the domain's
/// own sampler from `seed`. O(n² s + n·32 768·s).
pub fn energy_distance(
    domain: &Arc<dyn Domain>,
    points: &PointSet,
    seed: u64,
) -> Result<EnergyDistanceEstimate, Error> {
    let n = points.n() as f64;
    let within = 2.0 * pair_distance_sum(points) / (n * n);
    let mut estimates = Vec::with_capacity(BATCHES);
    for b in 0..BATCHES {
        let y = domain.sample(BATCH, stream_seed(seed, b as u64))?;
        estimates.push(batch_estimate(points, &y, within));
    }
    let k = BATCHES as f64;
    let mean = estimates.iter().sum::<f64>() / k;
    let var = estimates.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0);
    Ok(EnergyDistanceEstimate {
        value: mean,
        standard_error: (var / k).sqrt(),
        reference_points: BATCHES * BATCH,
    })
}

/// 2·mean|x − y| − `within` − the U-statistic of |y − y′| over the batch.
fn batch_estimate(points: &PointSet, y: &PointSet, within: f64) -> f64 {
    let m = y.n() as f64;
    let cross = cross_distance_sum(points, y) / (points.n() as f64 * m);
    let yy = 2.0 * pair_distance_sum(y) / (m * (m - 1.0));
    2.0 * cross - within - yy
}

/// The share of `points` inside `domain` (boundary included).
pub fn fraction_inside(domain: &Arc<dyn Domain>, points: &PointSet) -> f64 {
    let inside = points.rows().filter(|x| domain.contains(x)).count();
    inside as f64 / points.n().max(1) as f64
}

/// Most coordinates (candidates × s) one Sobol' draw for [`sobol_inside`] may hold; past
/// it the region fills too little of its box for rejection and its own sampler is used.
pub const MAX_CANDIDATE_COORDINATES: usize = 1 << 25;

/// The first `m` points of an Owen-scrambled Sobol' sequence (seeded by `seed`), scaled to
/// the domain's bounding box, that lie inside; `None` when the region fills so little of
/// its box that more than [`MAX_CANDIDATE_COORDINATES`] coordinates would be drawn.
/// Sobol' + rejection is the usual quasi-Monte Carlo set in a region.
pub fn sobol_inside(
    domain: &Arc<dyn Domain>,
    m: usize,
    seed: u64,
) -> Result<Option<PointSet>, Error> {
    let s = domain.dim();
    let (lo, hi) = domain.bounding_box();
    let mut total = (2 * m).next_power_of_two().max(1024);
    loop {
        if total.saturating_mul(s) > MAX_CANDIDATE_COORDINATES {
            return Ok(None);
        }
        let candidates = sobol_scrambled(total, s, seed)?;
        let mut kept = Vec::with_capacity(m * s);
        let mut row = vec![0.0; s];
        let mut count = 0;
        for u in candidates.rows() {
            for k in 0..s {
                row[k] = lo[k] + (hi[k] - lo[k]) * u[k];
            }
            if domain.contains(&row) {
                kept.extend_from_slice(&row);
                count += 1;
                if count == m {
                    return Ok(Some(PointSet::new(m, s, kept)?));
                }
            }
        }
        // The share inside so far sizes the next draw (a quarter more, for its spread).
        let need = if count == 0 {
            total * 16
        } else {
            ((m as f64 / count as f64) * total as f64 * 1.25) as usize
        };
        total = need.max(2 * total).next_power_of_two();
    }
}

/// `m` points representing the uniform distribution on `domain`: scrambled Sobol' points
/// carried onto it by [`Domain::map_from_cube`] where it has that map (the simplex, which
/// fills 1/s! of its box, so that rejection would draw s!·m points), else Sobol' +
/// rejection ([`sobol_inside`]) where the region fills enough of its box, else the
/// region's own uniform sampler, whose random error a large set would fit. The text says
/// which.
pub fn uniform_reference(
    domain: &Arc<dyn Domain>,
    m: usize,
    seed: u64,
) -> Result<(PointSet, String), Error> {
    let s = domain.dim();
    let cube = sobol_scrambled(m, s, seed)?;
    let mut mapped = vec![0.0; m * s];
    if cube
        .rows()
        .zip(mapped.chunks_exact_mut(s))
        .all(|(u, x)| domain.map_from_cube(u, x))
    {
        return Ok((
            PointSet::new(m, s, mapped)?,
            format!("{m} scrambled Sobol' points mapped onto the region"),
        ));
    }
    if let Some(p) = sobol_inside(domain, m, seed)? {
        return Ok((p, format!("{m} scrambled Sobol' points of the box inside")));
    }
    Ok((
        domain.sample(m, seed)?,
        format!("{m} uniform random points (the region fills too little of its box)"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use stillpoint_domains::shapes::{Ball, Simplex};

    #[test]
    fn a_thin_simplex_is_pictured_by_mapped_sobol_points() {
        let simplex: Arc<dyn Domain> = Arc::new(Simplex::new(8).unwrap());
        let (p, text) = uniform_reference(&simplex, 2000, 1).unwrap();
        assert!(text.contains("mapped"), "{text}");
        assert!(p.rows().all(|x| simplex.contains(x)));
        let mapped = energy_distance(&simplex, &p, 9).unwrap().value;
        let random = simplex.sample(2000, 1).unwrap();
        let random = energy_distance(&simplex, &random, 9).unwrap().value;
        assert!(mapped < random / 2.0, "mapped {mapped}, random {random}");
    }

    #[test]
    fn a_growing_uniform_sample_tends_to_zero() {
        let ball: Arc<dyn Domain> = Arc::new(Ball::new(vec![0.0; 3], 1.0).unwrap());
        let mean_of = |n: usize| -> f64 {
            (0..4)
                .map(|r| {
                    let x = ball.sample(n, 100 + r).unwrap();
                    energy_distance(&ball, &x, 7 + r).unwrap().value
                })
                .sum::<f64>()
                / 4.0
        };
        let (small, large) = (mean_of(50), mean_of(800));
        // For uniform points E D² is c/n: sixteen times the points, a sixteenth the value.
        assert!(large < small / 4.0, "n = 50: {small}, n = 800: {large}");
        assert!(large.abs() < 0.01, "{large}");
    }

    #[test]
    fn a_set_in_one_corner_is_far_and_its_error_is_small_beside_it() {
        let ball: Arc<dyn Domain> = Arc::new(Ball::new(vec![0.0; 2], 1.0).unwrap());
        let x = PointSet::from_rows(&[[0.9, 0.0], [0.85, 0.1], [0.8, -0.1]]).unwrap();
        let e = energy_distance(&ball, &x, 1).unwrap();
        assert!(e.value > 0.3, "{e:?}");
        assert!(e.standard_error < 0.05 * e.value, "{e:?}");
        assert_eq!(fraction_inside(&ball, &x), 1.0);
        let out = PointSet::from_rows(&[[0.0, 0.0], [2.0, 0.0]]).unwrap();
        assert_eq!(fraction_inside(&ball, &out), 0.5);
    }

    #[test]
    fn sobol_inside_is_inside_and_falls_back_for_a_thin_region() {
        let simplex: Arc<dyn Domain> = Arc::new(Simplex::new(3).unwrap());
        let p = sobol_inside(&simplex, 500, 3).unwrap().unwrap();
        assert_eq!(p.n(), 500);
        assert!(p.rows().all(|x| simplex.contains(x)));
        let thin: Arc<dyn Domain> = Arc::new(Simplex::new(12).unwrap());
        assert!(sobol_inside(&thin, 5000, 3).unwrap().is_none());
        let (q, how) = uniform_reference(&thin, 100, 3).unwrap();
        assert!(q.rows().all(|x| thin.contains(x)));
        assert!(how.contains("mapped"), "{how}");
        // A ball fills 2.5e-8 of its box at s = 20 and has no map from the cube.
        let ball: Arc<dyn Domain> = Arc::new(Ball::new(vec![0.0; 20], 1.0).unwrap());
        let (q, how) = uniform_reference(&ball, 100, 3).unwrap();
        assert!(q.rows().all(|x| ball.contains(x)));
        assert!(how.contains("random"), "{how}");
    }
}
