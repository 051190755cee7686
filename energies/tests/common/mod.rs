//! Helpers shared by the energy crate's test files: random sets, finite-difference
//! gradients and their comparison.

#![allow(dead_code)]

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use stillpoint_energies::{Energy, PointSet};

/// n points uniform in [0, 1)^s from a seeded generator.
pub fn random_set(n: usize, s: usize, seed: u64) -> PointSet {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    PointSet::new(n, s, (0..n * s).map(|_| rng.random::<f64>()).collect()).unwrap()
}

/// Central differences of the energy's value, step h, coordinate by coordinate.
pub fn fd_gradient(e: &dyn Energy, x: &PointSet, h: f64) -> Vec<f64> {
    let mut g = vec![0.0; x.coordinate_count()];
    let mut y = x.clone();
    for (idx, gi) in g.iter_mut().enumerate() {
        let v = x.as_slice()[idx];
        y.as_mut_slice()[idx] = v + h;
        let up = e.value(&y);
        y.as_mut_slice()[idx] = v - h;
        let down = e.value(&y);
        y.as_mut_slice()[idx] = v;
        *gi = (up - down) / (2.0 * h);
    }
    g
}

/// ‖a − b‖ / ‖b‖; the absolute ‖a − b‖ when b is zero.
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    let den: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    // A zero reference (one point of the wrap-around L2 feels no force) needs an
    // absolute comparison.
    if den == 0.0 {
        num
    } else {
        num / den
    }
}
