//! Where the points live: the [`Domain`] trait and the periodic unit cube.
//!
//! A domain gives an integrator what it needs to keep a moving set inside: a containment
//! test, a uniform start, and a rule that brings a point that left back in. Domains with a
//! boundary (implicit regions g(x) ≤ 0) also give the closest boundary point, which the
//! boundary-aware energies use; the periodic cube has no boundary.

use crate::{Error, PointSet, Result};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// A region of R^s that points are spread over.
pub trait Domain: Send + Sync + std::fmt::Debug {
    /// The dimension s.
    fn dim(&self) -> usize;

    /// Whether `x` lies in the domain (boundary included).
    fn contains(&self, x: &[f64]) -> bool;

    /// n points drawn uniformly from the domain with a seeded generator.
    fn sample(&self, n: usize, seed: u64) -> Result<PointSet>;

    /// Brings a point that an integrator moved to `x` back into the domain. `prev` is the
    /// point's previous position, which a two-step scheme needs moved consistently (the
    /// periodic cube shifts it by the same integer vector, so the velocity is unchanged).
    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]);

    /// The one rule every integrator follows when a step moves a point from `from`
    /// (inside) to `to`: afterwards `to` is inside. `prev` is the point's previous
    /// position, which a two-step scheme keeps consistent. Returns true when the point
    /// must lose its velocity (the caller sets `prev` to the new position).
    ///
    /// The default, for a bounded domain, keeps a step that stays inside; otherwise it
    /// takes the largest of the halved steps (1/2, 1/4, … 2^-40) that stays inside, or
    /// no step at all, and stops the point there. Projecting onto the boundary instead
    /// would put the point at distance 0 from it, where the boundary-aware energies are
    /// infinite. The periodic cube wraps instead (see [`PeriodicCube`]).
    fn keep_inside(&self, from: &[f64], to: &mut [f64], _prev: &mut [f64]) -> bool {
        if self.contains(to) {
            return false;
        }
        let mut t = 0.5;
        let mut trial = vec![0.0; to.len()];
        for _ in 0..40 {
            for ((y, a), b) in trial.iter_mut().zip(from).zip(to.iter()) {
                *y = a + t * (b - a);
            }
            if self.contains(&trial) {
                to.copy_from_slice(&trial);
                return true;
            }
            t *= 0.5;
        }
        to.copy_from_slice(from);
        true
    }

    /// The DEM's restart for unbiasedness (eqs. 44–45): if the mean of the set is more
    /// than `eps` from the domain's centre in some coordinate, move the set back to mean
    /// exactly the centre by a motion the energy does not see, and return true. Only a
    /// domain with such a motion (the torus: a periodic shift) does anything; the default
    /// returns false.
    fn recentre(&self, _points: &mut PointSet, _eps: f64) -> bool {
        false
    }

    /// Maps `u` in [0, 1)^s to `x` in the domain so that uniform u gives uniform x, by a
    /// piecewise smooth map that keeps a low-discrepancy set's evenness (a quasi-Monte
    /// Carlo picture of a region that fills too little of its box for rejection); false,
    /// with `x` untouched, where the domain has no such map (the default).
    fn map_from_cube(&self, _u: &[f64], _x: &mut [f64]) -> bool {
        false
    }

    /// True for a domain without boundary whose translates tile space (the torus).
    fn is_periodic(&self) -> bool {
        false
    }

    /// Distance from `x` to the boundary and the closest boundary point, written to
    /// `foot`; `None` for a domain without boundary.
    fn closest_boundary_point(&self, _x: &[f64], _foot: &mut [f64]) -> Option<f64> {
        None
    }

    /// The axis-aligned box `(lo, hi)` that holds the domain.
    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>);

    /// A level function of the domain, ≤ 0 inside and > 0 outside (for drawing its
    /// boundary); `None` where the domain has no boundary.
    fn level(&self, _x: &[f64]) -> Option<f64> {
        None
    }
}

/// The unit cube [0, 1)^s with opposite faces identified (the flat torus).
///
/// A coordinate that leaves [0, 1) is wrapped back by an integer (eq. 42 of the paper,
/// with the floor rather than the nearest integer so that the result is in [0, 1)).
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicCube {
    s: usize,
}

impl PeriodicCube {
    /// The periodic unit cube in s ≥ 1 dimensions.
    pub fn new(s: usize) -> Result<Self> {
        if s == 0 {
            return Err(Error::invalid("s", s, "at least 1 dimension"));
        }
        Ok(PeriodicCube { s })
    }

    /// Wraps every coordinate of a set into [0, 1).
    pub fn wrap_set(points: &mut PointSet) {
        for v in points.as_mut_slice() {
            *v = wrap_unit(*v).0;
        }
    }
}

impl PeriodicCube {
    /// Shifts the set periodically, coordinate by coordinate, so that the mean of the
    /// wrapped coordinates is exactly 0.5 (eq. 43), choosing the smallest such shift.
    /// Returns the shift applied to each coordinate.
    ///
    /// On the torus eq. 45 (subtract the mean, add 0.5) does not do this by itself: the
    /// points it pushes across a face wrap and pull the mean back. For a shift c the
    /// wrapped mean is M + c − W(c)/n with W(c) = #{v ≥ 1 − c}, so the candidates are
    /// c_w = 0.5 − M + w/n for w wrapped points, each valid when exactly w points wrap.
    pub fn centre_mean(points: &mut PointSet) -> Vec<f64> {
        let (n, s) = (points.n(), points.s());
        let mut shifts = vec![0.0; s];
        let mut col = vec![0.0; n];
        for (k, shift) in shifts.iter_mut().enumerate() {
            for (i, c) in col.iter_mut().enumerate() {
                *c = points.as_slice()[i * s + k];
            }
            let mean = col.iter().sum::<f64>() / n as f64;
            col.sort_by(|a, b| b.total_cmp(a));
            let mut best: Option<f64> = None;
            for w in 0..=n {
                let c = 0.5 - mean + w as f64 / n as f64;
                if !(0.0..1.0).contains(&c) {
                    continue;
                }
                // Exactly w points wrap: the w largest reach 1, the next does not.
                let wraps_w = w == 0 || col[w - 1] + c >= 1.0;
                let not_next = w == n || col[w] + c < 1.0;
                if wraps_w && not_next {
                    let better = best.is_none_or(|b| c.min(1.0 - c) < b.min(1.0 - b));
                    if better {
                        best = Some(c);
                    }
                }
            }
            let c = best.unwrap_or(0.5 - mean);
            for row in points.as_mut_slice().chunks_exact_mut(s) {
                row[k] = wrap_unit(row[k] + c).0;
            }
            *shift = c;
        }
        shifts
    }
}

/// Wraps a coordinate onto the unit circle: returns `(v - floor(v), floor(v))`, the
/// fractional part and the whole turns removed, with the rounding case
/// `v - floor(v) == 1` (tiny negative v) sent to `(0, floor(v) + 1)` so the first value is
/// always in [0, 1). This is the periodic cube's wrap; use it wherever a coordinate is
/// taken mod 1.
#[inline]
pub fn wrap_unit(v: f64) -> (f64, f64) {
    let f = v.floor();
    let r = v - f;
    if r >= 1.0 {
        (0.0, f + 1.0)
    } else {
        (r, f)
    }
}

impl Domain for PeriodicCube {
    fn dim(&self) -> usize {
        self.s
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.s && x.iter().all(|v| (0.0..1.0).contains(v))
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        if n == 0 {
            return Err(Error::invalid("n", n, "at least 1 point"));
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let data = (0..n * self.s).map(|_| rng.random::<f64>()).collect();
        PointSet::new(n, self.s, data)
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        for (v, p) in x.iter_mut().zip(prev.iter_mut()) {
            if !(0.0..1.0).contains(v) {
                let (r, f) = wrap_unit(*v);
                *v = r;
                *p -= f;
            }
        }
    }

    fn keep_inside(&self, _from: &[f64], to: &mut [f64], prev: &mut [f64]) -> bool {
        self.bring_back(to, prev);
        false
    }

    fn recentre(&self, points: &mut PointSet, eps: f64) -> bool {
        let gap = points
            .mean()
            .iter()
            .map(|m| (m - 0.5).abs())
            .fold(0.0, f64::max);
        if gap <= eps {
            return false;
        }
        PeriodicCube::centre_mean(points);
        true
    }

    fn is_periodic(&self) -> bool {
        true
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![0.0; self.s], vec![1.0; self.s])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_velocity_and_lands_in_unit_interval() {
        let cube = PeriodicCube::new(3).unwrap();
        let mut x = vec![1.25, -0.5, -1e-18];
        let mut prev = vec![1.2, -0.45, 0.01];
        let vel: Vec<f64> = x.iter().zip(&prev).map(|(a, b)| a - b).collect();
        cube.bring_back(&mut x, &mut prev);
        assert!(x.iter().all(|v| (0.0..1.0).contains(v)), "{x:?}");
        for k in 0..3 {
            assert!((x[k] - prev[k] - vel[k]).abs() < 1e-12);
        }
        assert!(cube.contains(&x));
    }

    #[test]
    fn sample_is_seeded_and_inside() {
        let cube = PeriodicCube::new(4).unwrap();
        let a = cube.sample(50, 7).unwrap();
        let b = cube.sample(50, 7).unwrap();
        assert_eq!(a, b);
        assert!(a.rows().all(|r| cube.contains(r)));
        assert_ne!(a, cube.sample(50, 8).unwrap());
        assert!(PeriodicCube::new(0).is_err());
        assert!(cube.sample(0, 1).is_err());
    }

    #[test]
    fn centre_mean_reaches_one_half_exactly() {
        let cube = PeriodicCube::new(3).unwrap();
        for seed in 0..20 {
            let mut x = cube.sample(37, seed).unwrap();
            // Skew the set so that plain subtraction of the mean would wrap many points.
            for v in x.as_mut_slice() {
                *v = (*v * *v + 0.3).fract();
            }
            let before = x.clone();
            PeriodicCube::centre_mean(&mut x);
            for m in x.mean() {
                assert!((m - 0.5).abs() < 1e-13, "seed {seed}: mean {m}");
            }
            assert!(x.rows().all(|r| cube.contains(r)));
            // A periodic shift keeps all torus distances.
            let d = |a: &[f64], b: &[f64]| -> f64 {
                a.iter()
                    .zip(b)
                    .map(|(u, v)| {
                        let t = (u - v).abs();
                        t.min(1.0 - t).powi(2)
                    })
                    .sum()
            };
            assert!(
                (d(x.point(0), x.point(5)) - d(before.point(0), before.point(5))).abs() < 1e-12
            );
        }
    }
}
