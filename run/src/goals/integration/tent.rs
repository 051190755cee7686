//! The set `--randomize` (tent) draws from: the rank-1 lattice made for the shift-and-tent
//! randomisation, or, where n is too small for a lattice to give every coordinate a
//! generator of its own, a set descended on that randomisation's mean square error.
//!
//! A rank-1 lattice of n points has at most φ(n)/2 generators that differ up to sign (32
//! points: 8). Past that, two coordinates share one, and their two-dimensional projection
//! collapses onto a few lines: at n = 32, s = 15 or 20, randomised lattices integrated
//! the corner-peak family 1.2–1.6× worse than scrambled Sobol'. No lattice avoids it, so
//! there the lattice is only the start: L-BFGS lowers the criterion
//! ([`stillpoint_energies::tent_kernel::TentKernel`], the lattice's own criterion extended to
//! any set), then each column is replaced by the ranks of its values over n, so that each
//! coordinate is again the n multiples of 1/n, as a lattice's is, and the randomised set
//! stays stratified. The rank step costs 1–2 % of the criterion's gain (measured at
//! n = 32–64, s = 10–20: the gain was 22–60 %).
//!
//! Where every coordinate has its own generator the lattice is kept: descending from it
//! (perturbed) lowered the criterion by up to 17 % at n = 100–256, s = 10, yet integrated
//! the product-peak and Gaussian families worse. The criterion weighs only smoothness 2,
//! and a lattice is good for every smoothness at once.

use crate::goals::region_integration::Stall;
use crate::report::TentDescent;
use crate::Error;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde_json::Value;
use stillpoint_domains::{PeriodicCube, PointSet};
use stillpoint_energies::tent_kernel::TentKernel;
use stillpoint_energies::Energy;
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{Problem, Record};
use stillpoint_sequences::{self as sequences, TENT_WEIGHT};
use stillpoint_solve::{LoggingObserver, Solve};

/// L-BFGS iterations at most (the runs measured stalled after 60–200).
const MAX_ITERATIONS: usize = 300;

/// Iterations below which a descent is not worth starting: the lattice is kept.
const MIN_ITERATIONS: usize = 30;

/// Pair-coordinate terms a descent may evaluate, iterations × n² × s (about 10 s on two
/// cores): past it the lattice is kept and the report says why.
const WORK_BUDGET: f64 = 2e10;

/// The perturbation of the start, ± this share of 1/n per coordinate: the lattice is a
/// stationary point of its criterion (its differences are symmetric), so L-BFGS must
/// start off it.
const NUDGE: f64 = 0.5;

/// Seed of the start's perturbation: the set depends on (n, s) only.
const NUDGE_SEED: u64 = 0x7465_6e74;

/// The set of [`tent_set`] and how it was made.
#[derive(Debug, Clone)]
pub struct TentSet {
    /// The points, each coordinate the n multiples of 1/n once each.
    pub points: PointSet,
    /// The lattice's generating vector (component by component).
    pub generator: Vec<u64>,
    /// The lattice's criterion ([`sequences::tent_criterion`]).
    pub lattice_criterion: f64,
    /// What became of the lattice.
    pub descent: TentDescent,
}

/// Whether two coordinates of the generator z (mod n) are the same up to sign.
pub fn shares_generators(z: &[u64], n: usize) -> bool {
    let n = n as u64;
    let canon = |v: u64| {
        let v = v % n.max(1);
        v.min(n - v)
    };
    let mut seen: Vec<u64> = z.iter().map(|&v| canon(v)).collect();
    seen.sort_unstable();
    seen.windows(2).any(|w| w[0] == w[1])
}

/// The L-BFGS iterations a descent of n points in s dimensions may take (0: none).
pub fn descent_iterations(n: usize, s: usize) -> usize {
    let per = n as f64 * n as f64 * s as f64;
    let fit = (WORK_BUDGET / per) as usize;
    if fit < MIN_ITERATIONS {
        0
    } else {
        fit.min(MAX_ITERATIONS)
    }
}

/// The set the shift-and-tent randomisation draws from (see the module documentation).
/// Deterministic: a function of (n, s) only. Refuses n = 0 or s = 0, naming the argument.
pub fn tent_set(n: usize, s: usize) -> Result<TentSet, Error> {
    let generator = sequences::tent_lattice_generator(n, s)?;
    let lattice = sequences::rank1_lattice(n, &generator)?;
    let lattice_criterion = sequences::tent_criterion(n, &generator)?;
    let done = |points, descent| TentSet {
        points,
        generator: generator.clone(),
        lattice_criterion,
        descent,
    };
    // Below four points every column's ranks are the same few values: nothing to gain.
    if n < 4 || !shares_generators(&generator, n) {
        return Ok(done(lattice, TentDescent::NotNeeded));
    }
    let iterations = descent_iterations(n, s);
    if iterations == 0 {
        let work = n as f64 * n as f64 * s as f64;
        return Ok(done(lattice, TentDescent::TooCostly { work }));
    }
    let energy = TentKernel::new(TENT_WEIGHT)?;
    let mut start = lattice.clone();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(NUDGE_SEED);
    for v in start.as_mut_slice() {
        *v += NUDGE / n as f64 * (2.0 * rng.random::<f64>() - 1.0);
    }
    PeriodicCube::wrap_set(&mut start);
    let problem = Problem::new(energy, PeriodicCube::new(s)?)?;
    // The logging observer stops the run when a caller asks (Ctrl-C in Python).
    let mut observer = Stall::new(LoggingObserver::new(0, |_: &Record| {}));
    let run = Solve {
        problem: &problem,
        steps: iterations,
        checkpoint: None,
        config: &Value::Null,
    };
    let out = run.execute(Lbfgs::default(), start, &mut observer)?;
    stillpoint_solve::stop_if_cancelled()?;
    let ranked = ranks(&out.points);
    let criterion = energy.value(&ranked);
    let kept = criterion < lattice_criterion;
    let descent = TentDescent::Descended {
        criterion,
        iterations: out.trajectory.iter().map(|r| r.step).max().unwrap_or(0),
        kept,
    };
    Ok(done(if kept { ranked } else { lattice }, descent))
}

/// Each column replaced by the ranks of its values over n (ties by row): every
/// coordinate becomes the n multiples of 1/n once each.
fn ranks(points: &PointSet) -> PointSet {
    let n = points.n() as f64;
    let x = super::descent::ranks(points)
        .into_iter()
        .map(|c| c as f64 / n)
        .collect();
    PointSet::new(points.n(), points.s(), x).expect("the shape of a valid set")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_generators_are_found_up_to_sign() {
        assert!(!shares_generators(&[1, 7, 10], 32));
        assert!(shares_generators(&[1, 7, 25], 32)); // 25 = 32 − 7
        assert!(shares_generators(&[1, 3, 3], 100));
    }

    #[test]
    fn where_coordinates_share_generators_the_set_beats_the_lattice_and_stays_stratified() {
        for (n, s) in [(32usize, 15usize), (40, 12)] {
            let t = tent_set(n, s).unwrap();
            assert!(shares_generators(&t.generator, n));
            let TentDescent::Descended {
                criterion, kept, ..
            } = t.descent
            else {
                panic!("{:?}", t.descent)
            };
            assert!(kept);
            // The criterion recomputed independently: the energy on the written set.
            let again = TentKernel::new(TENT_WEIGHT).unwrap().value(&t.points);
            assert_eq!(again, criterion);
            assert!(
                criterion < 0.8 * t.lattice_criterion,
                "n = {n}, s = {s}: {criterion} vs {}",
                t.lattice_criterion
            );
            for j in 0..s {
                let mut col: Vec<u64> = t
                    .points
                    .rows()
                    .map(|r| (r[j] * n as f64).round() as u64)
                    .collect();
                col.sort_unstable();
                assert_eq!(col, (0..n as u64).collect::<Vec<_>>());
            }
            // A function of (n, s) only.
            assert_eq!(tent_set(n, s).unwrap().points, t.points);
        }
    }

    #[test]
    fn where_every_coordinate_has_its_generator_the_lattice_is_the_set() {
        let t = tent_set(100, 8).unwrap();
        assert_eq!(t.descent, TentDescent::NotNeeded);
        assert_eq!(t.points, sequences::tent_lattice(100, 8).unwrap());
        assert_eq!(descent_iterations(10_000, 1000), 0);
        assert!(matches!(
            tent_set(3, 5).unwrap().descent,
            TentDescent::NotNeeded
        ));
    }
}
