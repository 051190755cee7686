//! Latin hypercube designs: the plain randomised one, and one improved for the maximin
//! criterion (largest smallest pairwise distance) by a bounded simulated-annealing search
//! over within-column swaps.
//!
//! References: M. D. McKay, R. J. Beckman, W. J. Conover, *A comparison of three methods
//! for selecting values of input variables in the analysis of output from a computer
//! code*, Technometrics 21 (1979); M. D. Morris and T. J. Mitchell, *Exploratory designs
//! for computational experiments*, J. Statist. Plann. Inference 43 (1995) (the φ_p
//! criterion and annealing over column swaps, as in DiceDesign's `maximinSA_LHS`).

use rand::RngExt;
use rayon::prelude::*;

use super::{check_shape, prev_float, substream};
use crate::{Error, PointSet};

/// Largest n for [`lhs_maximin`]: its start costs n²·s/2 operations (finding every point's
/// nearest neighbour), a few seconds at n = 20 000, s = 20.
pub const LHS_MAXIMIN_MAX_N: usize = 20_000;

/// Labels of the random streams, so the two uses of a seed do not share numbers.
const LHS_LABEL: u64 = 0x4c48_535f_7374_7261;
const MAXIMIN_LABEL: u64 = 0x4d61_7869_6d69_6e53;

/// Coordinate-distance operations the swap search may spend: each swap costs 2·n·s, plus
/// n·s for every point whose nearest neighbour moved away and must be found again. About
/// half a second.
const MAXIMIN_WORK: u64 = 1 << 29;

/// Most swaps per point, which is what bounds the search for small designs.
const MAXIMIN_SWAPS_PER_POINT: usize = 1000;

/// Half the exponent p = 50 of the Morris–Mitchell-type criterion (DiceDesign's default):
/// large enough that the closest pairs dominate, small enough to rank near-ties.
const HALF_P: i32 = 25;

/// Start and end temperature of the geometric annealing schedule, on the relative change
/// of the criterion (a 1 % worse swap is accepted with probability e^(−1) at T = 0.01).
const T_START: f64 = 1e-2;
const T_END: f64 = 1e-5;

/// Latin hypercube sample: x_{i,j} = (π_j(i) + U_{i,j})/n with independent uniformly random
/// permutations π_j of {0, ..., n−1} (one per column) and independent uniforms U_{i,j} in
/// [0, 1), like SciPy's `qmc.LatinHypercube(scramble=True)`. Every column puts exactly one
/// point in each stratum \[k/n, (k+1)/n).
///
/// All s permutations are drawn first (Fisher–Yates, column by column), then the uniforms
/// row by row, from one Xoshiro256++ stream derived from `seed`.
///
/// Refuses n = 0 or s = 0, naming the argument.
pub fn lhs(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    let mut rng = substream(seed, LHS_LABEL, 0);
    let perms: Vec<Vec<u64>> = (0..s)
        .map(|_| {
            let mut p: Vec<u64> = (0..n as u64).collect();
            for i in (1..n).rev() {
                let j = rng.random_range(0..=i as u64) as usize;
                p.swap(i, j);
            }
            p
        })
        .collect();
    let nf = n as f64;
    let mut data = Vec::with_capacity(n * s);
    for i in 0..n {
        for perm in &perms {
            let stratum = perm[i] as f64;
            let u: f64 = rng.random();
            let x = (stratum + u) / nf;
            // stratum + u can round up to stratum + 1 when u is within an ulp of 1.
            let hi = (stratum + 1.0) / nf;
            data.push(if x >= hi { prev_float(hi) } else { x });
        }
    }
    PointSet::new(n, s, data)
}

#[inline(always)]
fn dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(&x, &y)| (x - y) * (x - y)).sum()
}

/// Nearest neighbour of point i (squared distance, index; ties to the smaller index).
fn nearest(x: &[f64], s: usize, i: usize) -> (f64, usize) {
    let xi = &x[i * s..(i + 1) * s];
    let mut best = (f64::INFINITY, usize::MAX);
    for (l, xl) in x.chunks_exact(s).enumerate() {
        if l != i {
            let d = dist2(xi, xl);
            if d < best.0 {
                best = (d, l);
            }
        }
    }
    best
}

/// The smaller of two (squared distance, index) candidates, ties to the smaller index, so
/// the result does not depend on the order candidates are met in.
#[inline(always)]
fn closer(a: (f64, usize), b: (f64, usize)) -> (f64, usize) {
    if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
        b
    } else {
        a
    }
}

/// Every point's nearest neighbour, each pair's distance computed once. Threads keep
/// their own candidates and merge them with [`closer`], which is order-independent, so
/// the result is the same for any number of threads (and equals [`nearest`] per point).
fn all_nearest(x: &[f64], s: usize) -> Vec<(f64, usize)> {
    let n = x.len() / s;
    let none = (f64::INFINITY, usize::MAX);
    (0..n)
        .into_par_iter()
        .fold(
            || vec![none; n],
            |mut acc, i| {
                let xi = &x[i * s..(i + 1) * s];
                for (l, xl) in x.chunks_exact(s).enumerate().skip(i + 1) {
                    let d = dist2(xi, xl);
                    acc[i] = closer(acc[i], (d, l));
                    acc[l] = closer(acc[l], (d, i));
                }
                acc
            },
        )
        .reduce(
            || vec![none; n],
            |mut a, b| {
                for (p, q) in a.iter_mut().zip(b) {
                    *p = closer(*p, q);
                }
                a
            },
        )
}

/// Squared distances from row `i` to every row (infinite to itself), written into `out`.
fn row_distances(x: &[f64], s: usize, i: usize, out: &mut [f64]) {
    let xi = &x[i * s..(i + 1) * s];
    let fill = |(l, (o, xl)): (usize, (&mut f64, &[f64]))| {
        *o = if l == i { f64::INFINITY } else { dist2(xi, xl) };
    };
    // Each entry is computed on its own, so splitting the work changes no bits.
    if x.len() >= 1 << 15 {
        out.par_iter_mut()
            .zip(x.par_chunks_exact(s))
            .enumerate()
            .for_each(fill);
    } else {
        out.iter_mut()
            .zip(x.chunks_exact(s))
            .enumerate()
            .for_each(fill);
    }
}

/// One point's term (d_ref² / nn²)^(p/2) of the criterion's sum; the ratio is capped so
/// no term overflows, whatever the design.
#[inline(always)]
fn term(d_ref2: f64, nn2: f64) -> f64 {
    (d_ref2 / nn2).min(1e10).powi(HALF_P)
}

/// Index of the smallest squared nearest-neighbour distance (ties to the smaller index).
fn argmin(nn2: &[f64]) -> usize {
    let mut best = 0;
    for (l, &d) in nn2.iter().enumerate() {
        if d < nn2[best] {
            best = l;
        }
    }
    best
}

/// The nearest-neighbour table of the search, with an undo log for rejected swaps.
struct Neighbours {
    nn2: Vec<f64>,
    idx: Vec<usize>,
    /// (point, previous squared distance, previous index) for every change since the last
    /// [`Neighbours::commit`].
    log: Vec<(usize, f64, usize)>,
    /// Change of the criterion's sum over the logged changes.
    delta: f64,
    d_ref2: f64,
}

impl Neighbours {
    fn set(&mut self, l: usize, d: f64, m: usize) {
        self.log.push((l, self.nn2[l], self.idx[l]));
        self.delta += term(self.d_ref2, d) - term(self.d_ref2, self.nn2[l]);
        self.nn2[l] = d;
        self.idx[l] = m;
    }

    fn commit(&mut self) {
        self.log.clear();
        self.delta = 0.0;
    }

    fn rollback(&mut self) {
        for &(l, d, m) in self.log.iter().rev() {
            self.nn2[l] = d;
            self.idx[l] = m;
        }
        self.commit();
    }

    fn sum(&self) -> f64 {
        self.nn2.iter().map(|&d| term(self.d_ref2, d)).sum()
    }
}

/// Maximin Latin hypercube: starts from [`lhs`]`(n, s, seed)` and runs a seeded simulated
/// annealing over swaps of two points' coordinates within one column (which keeps the
/// design a Latin hypercube, jitter included), returning the visited design with the
/// largest smallest pairwise Euclidean distance.
///
/// * Criterion: Φ = (Σ_l nn_l^(−50))^(1/50), nn_l the distance from point l to its nearest
///   neighbour (a Morris–Mitchell φ_p with p = 50 over nearest-neighbour distances).
/// * Moves: half the time one end of the closest pair, otherwise a uniformly random point,
///   swapped with another uniformly random point in a uniformly random column.
/// * Acceptance: always if Φ does not grow, else with probability exp(−ΔΦ/(Φ·T)).
/// * Acceptance temperature: T falls geometrically from 10^−2 to 10^−5 with the fraction
///   of the budget spent.
/// * Budget: at most 1000·n swaps and at most 2^29 coordinate operations (each swap costs
///   2·n·s, plus n·s per point whose nearest neighbour moved away), about half a second;
///   before it, one n²·s/2 nearest-neighbour pass for the start (a few seconds at
///   n = 20 000, s = 20).
///
/// Deterministic for a seed, whatever the number of threads; its smallest distance is
/// never below the start's (the start is returned if nothing beats it). For n ≤ 2 or s = 1
/// no swap changes any distance, so the start is returned.
///
/// Refuses n = 0, s = 0 and n > 20 000, naming the argument.
pub fn lhs_maximin(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    if n > LHS_MAXIMIN_MAX_N {
        return Err(Error::invalid(
            "n",
            n,
            format!("1..={LHS_MAXIMIN_MAX_N} for a maximin Latin hypercube"),
        ));
    }
    maximin_search(lhs(n, s, seed)?, seed)
}

/// The swap search of [`lhs_maximin`] from any start: points swap one coordinate, so a
/// stratified start stays stratified, with the same schedule and budget. Its smallest
/// distance is never below the start's. n at most 20 000.
pub fn maximin_search(start: PointSet, seed: u64) -> Result<PointSet, Error> {
    let (n, s) = (start.n(), start.s());
    if n > LHS_MAXIMIN_MAX_N {
        return Err(Error::invalid(
            "n",
            n,
            format!("1..={LHS_MAXIMIN_MAX_N} for a maximin search"),
        ));
    }
    if n <= 2 || s == 1 {
        return Ok(start);
    }
    let mut x = start.into_vec();
    let (nn2, idx): (Vec<f64>, Vec<usize>) = all_nearest(&x, s).into_iter().unzip();
    let mut crit = argmin(&nn2);
    let d_ref2 = nn2[crit].max(f64::MIN_POSITIVE);
    let mut nb = Neighbours {
        nn2,
        idx,
        log: Vec::new(),
        delta: 0.0,
        d_ref2,
    };
    let mut energy_sum = nb.sum();
    let mut best_min2 = nb.nn2[crit];
    let mut best_x = x.clone();

    let mut rng = substream(seed, MAXIMIN_LABEL, 0);
    let max_swaps = MAXIMIN_SWAPS_PER_POINT * n;
    let row_cost = (n * s) as u64;
    let mut work = 0u64;
    let (mut di, mut dk) = (vec![0.0; n], vec![0.0; n]);
    let mut stale: Vec<usize> = Vec::new();

    // The schedule follows the work spent, so it reaches its end temperature whichever
    // bound stops the search.
    let mut t = 0;
    while t < max_swaps && work < MAXIMIN_WORK {
        let progress = (work as f64 / MAXIMIN_WORK as f64).max(t as f64 / max_swaps as f64);
        let temperature = T_START * (T_END / T_START).powf(progress);
        let i = if rng.random::<bool>() {
            if rng.random::<bool>() {
                crit
            } else {
                nb.idx[crit]
            }
        } else {
            rng.random_range(0..n as u64) as usize
        };
        let mut k = rng.random_range(0..(n - 1) as u64) as usize;
        if k >= i {
            k += 1;
        }
        let c = rng.random_range(0..s as u64) as usize;

        x.swap(i * s + c, k * s + c);
        row_distances(&x, s, i, &mut di);
        row_distances(&x, s, k, &mut dk);
        stale.clear();
        for l in 0..n {
            if l == i || l == k {
                continue;
            }
            let (d, m) = closer((di[l], i), (dk[l], k));
            if d < nb.nn2[l] {
                // Every unmoved neighbour is at least nn2[l] away, so i or k is nearest.
                nb.set(l, d, m);
            } else if nb.idx[l] == i || nb.idx[l] == k {
                if d == nb.nn2[l] {
                    nb.set(l, d, m);
                } else {
                    // Its nearest neighbour moved away: only a full scan finds the new one.
                    stale.push(l);
                }
            }
        }
        for &l in &stale {
            let (d, m) = nearest(&x, s, l);
            nb.set(l, d, m);
        }
        work += (2 + stale.len() as u64) * row_cost;
        for (row, dist) in [(i, &di), (k, &dk)] {
            let (d, m) = dist
                .iter()
                .enumerate()
                .fold((f64::INFINITY, usize::MAX), |b, (l, &d)| closer(b, (d, l)));
            nb.set(row, d, m);
        }

        let cand_sum = energy_sum + nb.delta;
        let relative = (cand_sum / energy_sum).powf(1.0 / (2 * HALF_P) as f64) - 1.0;
        let accept = relative <= 0.0 || rng.random::<f64>() < (-relative / temperature).exp();
        if accept {
            // The closest pair changes only through logged entries; a rescan is needed
            // only when the old closest point itself moved away.
            let old = nb.nn2[crit];
            let crit_grew = nb.log.iter().any(|&(l, d, _)| l == crit && old > d);
            if crit_grew {
                crit = argmin(&nb.nn2);
            } else {
                for &(l, _, _) in &nb.log {
                    if (nb.nn2[l], l) < (nb.nn2[crit], crit) {
                        crit = l;
                    }
                }
            }
            nb.commit();
            energy_sum = cand_sum;
            if nb.nn2[crit] > best_min2 {
                best_min2 = nb.nn2[crit];
                best_x.copy_from_slice(&x);
            }
        } else {
            nb.rollback();
            x.swap(i * s + c, k * s + c);
        }
        // Incremental sums drift; a periodic exact sum keeps the criterion honest.
        if t % 256 == 255 {
            energy_sum = nb.sum();
        }
        t += 1;
    }
    PointSet::new(n, s, best_x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_nearest_matches_a_scan_per_point() {
        let x = lhs(300, 4, 3).unwrap().into_vec();
        let all = all_nearest(&x, 4);
        for (i, &got) in all.iter().enumerate() {
            assert_eq!(got, nearest(&x, 4, i), "point {i}");
        }
    }
}
