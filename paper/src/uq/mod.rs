//! The two stochastic simulation problems of the paper (Section 5.3), each turning a point
//! set in [0, 1]^d into statistical moments, with Monte Carlo and (for Kraichnan–Orszag)
//! quadrature references:
//!
//! - [`ko`]: the Kraichnan–Orszag three-mode system (eqs. 51–53), d = 3;
//! - [`frame`]: natural frequencies of a 20-storey shear frame with random storey
//!   stiffness (eqs. 54–55), d = 20.
//!
//! Moments are accumulated with Welford's update inside fixed-size chunks of samples and the
//! chunks are merged in chunk order (Chan's formula), so results are bit-identical for any
//! number of threads. Monte Carlo chunks draw from non-overlapping `Xoshiro256PlusPlus`
//! streams (one `jump()` of 2^128 apart per chunk), seeded from the user's seed.

pub mod frame;
pub mod ko;
mod tridiag;

pub use frame::{
    frame_emax, frame_frequencies, frame_moments, frame_monte_carlo, shear_frame_frequencies,
    FrameMoments, FRAME_MASS, FRAME_MODES, FRAME_STIFFNESS, FRAME_STORIES,
};
pub use ko::{
    ko_gauss, ko_moments, ko_monte_carlo, ko_relative_errors, ko_solve, KoErrors, KoMoments,
    KoSettings,
};

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use stillpoint::{Error, PointSet};

/// Samples per parallel chunk; fixed so the reduction order never depends on threads.
const CHUNK: usize = 4096;

/// Bytes of per-chunk accumulators held at once. Batching changes nothing in the result
/// (chunks are merged strictly in order either way); it only bounds memory.
const BATCH_BYTES: usize = 64 << 20;

/// Weighted running mean and sum of squared deviations of `len` quantities.
#[derive(Clone, Debug)]
pub(crate) struct Accumulator {
    weight: f64,
    mean: Vec<f64>,
    m2: Vec<f64>,
}

impl Accumulator {
    pub(crate) fn new(len: usize) -> Self {
        Accumulator {
            weight: 0.0,
            mean: vec![0.0; len],
            m2: vec![0.0; len],
        }
    }

    /// Starts a sample of weight w; returns w / (total weight), the Welford step.
    #[inline]
    pub(crate) fn begin(&mut self, w: f64) -> f64 {
        self.weight += w;
        w / self.weight
    }

    /// Adds quantity j of the current sample (weight w, step from [`Accumulator::begin`]).
    #[inline]
    pub(crate) fn add(&mut self, j: usize, x: f64, w: f64, step: f64) {
        let d = x - self.mean[j];
        self.mean[j] += d * step;
        self.m2[j] += w * d * (x - self.mean[j]);
    }

    /// Chan et al.'s pairwise merge: exact for weighted means and squared deviations.
    pub(crate) fn merge(&mut self, other: &Accumulator) {
        if other.weight == 0.0 {
            return;
        }
        if self.weight == 0.0 {
            *self = other.clone();
            return;
        }
        let w = self.weight + other.weight;
        let f = other.weight / w;
        let g = self.weight * other.weight / w;
        for j in 0..self.mean.len() {
            let d = other.mean[j] - self.mean[j];
            self.mean[j] += d * f;
            self.m2[j] += other.m2[j] + d * d * g;
        }
        self.weight = w;
    }

    pub(crate) fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// Standard deviations with the given divisor (n − 1 for samples, 1 for quadrature
    /// weights summing to 1). Rounding can leave m2 a hair below 0; that is a zero spread.
    pub(crate) fn sd(&self, divisor: f64) -> Vec<f64> {
        self.m2
            .iter()
            .map(|&m| (m.max(0.0) / divisor).sqrt())
            .collect()
    }
}

/// Runs `f` over `count` items in fixed chunks (in parallel) and merges the chunk
/// accumulators in order. `f(range, rng, acc)` gets a generator private to its chunk.
pub(crate) fn chunked<F>(count: usize, len: usize, seed: u64, f: F) -> Accumulator
where
    F: Fn(std::ops::Range<usize>, &mut Xoshiro256PlusPlus, &mut Accumulator) + Sync,
{
    let chunks = count.div_ceil(CHUNK);
    let mut stream = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut total = Accumulator::new(len);
    let per_chunk = 16 * len.max(1);
    let batch = (BATCH_BYTES / per_chunk).clamp(rayon::current_num_threads().max(1), 256);
    let mut first = 0;
    while first < chunks {
        let last = (first + batch).min(chunks);
        let rngs: Vec<Xoshiro256PlusPlus> = (first..last)
            .map(|_| {
                let r = stream.clone();
                stream.jump();
                r
            })
            .collect();
        let parts: Vec<Accumulator> = rngs
            .into_par_iter()
            .enumerate()
            .map(|(i, mut rng)| {
                let c = first + i;
                let mut acc = Accumulator::new(len);
                f(c * CHUNK..((c + 1) * CHUNK).min(count), &mut rng, &mut acc);
                acc
            })
            .collect();
        for p in &parts {
            total.merge(p);
        }
        first = last;
    }
    total
}

/// Checks a point set for a moment estimate: dimension `d`, at least two points (the SD
/// uses the n − 1 divisor), every coordinate in [0, 1].
pub(crate) fn check_points(points: &PointSet, d: usize, problem: &str) -> Result<(), Error> {
    if points.s() != d {
        return Err(Error::invalid(
            "points dimension s",
            points.s(),
            format!("s = {d} for the {problem} problem"),
        ));
    }
    if points.n() < 2 {
        return Err(Error::invalid(
            "points n",
            points.n(),
            "at least 2 points (the standard deviation uses the n - 1 divisor)",
        ));
    }
    points.check_unit_cube()
}

/// Checks a Monte Carlo sample count.
pub(crate) fn check_samples(samples: usize) -> Result<(), Error> {
    if samples < 2 {
        return Err(Error::invalid(
            "samples",
            samples,
            "at least 2 (the standard deviation uses the n - 1 divisor)",
        ));
    }
    Ok(())
}

/// Gauss–Legendre nodes and weights on [−1, 1] (weights sum to 2), by Newton's method on
/// the Legendre recurrence; accurate to a few ulps for 1 ≤ n ≤ 1024.
pub fn gauss_legendre(n: usize) -> Result<(Vec<f64>, Vec<f64>), Error> {
    if !(1..=1024).contains(&n) {
        return Err(Error::invalid("nodes", n, "1 to 1024 Gauss–Legendre nodes"));
    }
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let nf = n as f64;
    // Roots are symmetric: find the upper half and mirror.
    for i in 0..n.div_ceil(2) {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, z);
            dp = d;
            let dz = p / d;
            z -= dz;
            if dz.abs() <= 1e-16 * z.abs().max(1e-300) {
                break;
            }
        }
        let (_, d) = legendre(n, z);
        if d != 0.0 {
            dp = d;
        }
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    if n % 2 == 1 {
        x[n / 2] = 0.0;
    }
    Ok((x, w))
}

/// P_n(z) and P_n'(z).
fn legendre(n: usize, z: f64) -> (f64, f64) {
    let mut p0 = 1.0;
    let mut p1 = z;
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * z * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (z * p1 - p0) / (z * z - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        for n in [1usize, 2, 5, 16, 33, 64] {
            let (x, w) = gauss_legendre(n).unwrap();
            assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-13, "n={n}");
            for deg in 0..2 * n {
                let q: f64 = x
                    .iter()
                    .zip(&w)
                    .map(|(&x, &w)| w * x.powi(deg as i32))
                    .sum();
                let exact = if deg % 2 == 1 {
                    0.0
                } else {
                    2.0 / (deg as f64 + 1.0)
                };
                assert!((q - exact).abs() < 1e-13, "n={n} deg={deg}: {q} vs {exact}");
            }
        }
        assert!(gauss_legendre(0).is_err());
    }

    #[test]
    fn merge_matches_one_pass() {
        let xs: Vec<f64> = (0..1000).map(|i| ((i * 37 % 101) as f64).sin()).collect();
        let mut one = Accumulator::new(1);
        for &x in &xs {
            let st = one.begin(1.0);
            one.add(0, x, 1.0, st);
        }
        let mut a = Accumulator::new(1);
        let mut b = Accumulator::new(1);
        for (i, &x) in xs.iter().enumerate() {
            let acc = if i < 313 { &mut a } else { &mut b };
            let st = acc.begin(1.0);
            acc.add(0, x, 1.0, st);
        }
        a.merge(&b);
        assert!((a.mean()[0] - one.mean()[0]).abs() < 1e-15);
        assert!((a.sd(999.0)[0] - one.sd(999.0)[0]).abs() < 1e-14);
    }
}
