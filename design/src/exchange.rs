//! Exchanges on a design's continuous part that keep every stratification the dealing
//! made: two points swap one coordinate only when no slice of any factor ends up with
//! two points in one of its 1/m-ths (so the whole column stays one point per cell, and
//! every slice stays as stratified as it was). A swap is kept when it lowers the
//! objective: the centred L2 discrepancy (a design for integration) or the
//! Morris–Mitchell sum Σ d^{-q} over the type-aware distance (a space-filling design).

use super::slices::{SliceCounts, Slices};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use stillpoint_energies::discrepancy::{Centered, DiscrepancyKernel};

/// Proposals per point and coordinate.
const PROPOSALS_PER_VALUE: usize = 200;

/// At most this many kernel terms (proposals × n × k) per design: the exchanges stay a
/// fraction of a second next to the run that made the set.
const WORK_CAP: f64 = 4e8;

/// The centred L2 kernel's one-point factor and pair factor in one coordinate
/// (Hickernell 1998): CD² = C^k − (2/n) Σ_i Π g(x_i) + (1/n²) Σ_{i,l} Π h(x_i, x_l).
fn g(x: f64) -> f64 {
    Centered::single_factor(x)
}

fn h(x: f64, y: f64) -> f64 {
    Centered::pair_factor(x, y)
}

/// What the exchanges lower.
pub enum Objective<'a> {
    /// The centred L2 discrepancy of the continuous part.
    CenteredL2,
    /// Σ over pairs of d^{-q}, d² the continuous part's squared distance plus
    /// `extra(i, l)` (the discrete variables' share): large q makes it the minimum
    /// distance, smooth enough to climb.
    Spread {
        /// The discrete variables' squared distance between two points.
        extra: &'a dyn Fn(usize, usize) -> f64,
    },
}

/// Morris and Mitchell's exponent: large enough that the sum follows the smallest
/// distances, small enough that d^{-q} stays finite for the distances of a design.
const SPREAD_Q: i32 = 16;

/// The part of the objective that rows `p` and `q` take part in, with their rows as
/// given.
fn part(
    objective: &Objective<'_>,
    x: &[f64],
    k: usize,
    p: usize,
    q: usize,
    rp: &[f64],
    rq: &[f64],
) -> f64 {
    match objective {
        Objective::CenteredL2 => share(x, k, p, q, rp, rq),
        Objective::Spread { extra } => {
            let n = x.len() / k;
            let inv = |a: &[f64], b: &[f64], i: usize, l: usize| -> f64 {
                let d2: f64 =
                    a.iter().zip(b).map(|(u, v)| (u - v) * (u - v)).sum::<f64>() + extra(i, l);
                d2.max(1e-300).powi(-SPREAD_Q / 2)
            };
            let mut sum = inv(rp, rq, p, q);
            for l in (0..n).filter(|&l| l != p && l != q) {
                let row = &x[l * k..(l + 1) * k];
                sum += inv(rp, row, p, l) + inv(rq, row, q, l);
            }
            sum
        }
    }
}

/// The part of n²·CD² that rows `p` and `q` take part in, with their rows as given.
fn share(x: &[f64], k: usize, p: usize, q: usize, rp: &[f64], rq: &[f64]) -> f64 {
    let n = x.len() / k;
    let kern = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(&u, &v)| h(u, v)).product() };
    let mut pairs = 0.0;
    for l in (0..n).filter(|&l| l != p && l != q) {
        let row = &x[l * k..(l + 1) * k];
        pairs += kern(rp, row) + kern(rq, row);
    }
    let single: f64 =
        rp.iter().map(|&v| g(v)).product::<f64>() + rq.iter().map(|&v| g(v)).product::<f64>();
    2.0 * pairs + 2.0 * kern(rp, rq) + kern(rp, rp) + kern(rq, rq) - 2.0 * n as f64 * single
}

/// Swaps of one coordinate between two points of `x` (n × k, row-major, on the unit
/// scale), each kept when it lowers the centred L2 discrepancy and crowds no slice of
/// any factor in `slices` (labels per point, number of levels); deterministic for
/// `seed`.
pub fn exchange(
    x: &mut [f64],
    k: usize,
    slices: &Slices<'_>,
    objective: &Objective<'_>,
    seed: u64,
) {
    let n = x.len() / k.max(1);
    if k == 0 || n < 3 {
        return;
    }
    let cell = |v: f64| ((v * n as f64) as usize).min(n - 1);
    let mut counts: Vec<SliceCounts> = (0..k)
        .map(|j| SliceCounts::new(slices, n, |i| cell(x[i * k + j])))
        .collect();
    let proposals = ((PROPOSALS_PER_VALUE * n * k) as f64).min(WORK_CAP / (n * k) as f64) as usize;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0xe8c4_a2d1_9f3b_7c65);
    for _ in 0..proposals {
        let j = rng.random_range(0..k);
        let p = rng.random_range(0..n);
        let q = rng.random_range(0..n);
        if p == q {
            continue;
        }
        let (vp, vq) = (x[p * k + j], x[q * k + j]);
        let (cp, cq) = (cell(vp), cell(vq));
        // The swap may not put two points of a slice in one of its 1/m-ths.
        let t = &counts[j];
        let crowds = (0..t.factors()).any(|f| {
            if t.level(f, p) == t.level(f, q) {
                return false;
            }
            t.count(f, p, cq) > u32::from(t.block(f, p, cq) == t.block(f, p, cp))
                || t.count(f, q, cp) > u32::from(t.block(f, q, cp) == t.block(f, q, cq))
        });
        if crowds {
            continue;
        }
        let rp: Vec<f64> = x[p * k..(p + 1) * k].to_vec();
        let rq: Vec<f64> = x[q * k..(q + 1) * k].to_vec();
        let before = part(objective, x, k, p, q, &rp, &rq);
        let (mut sp, mut sq) = (rp.clone(), rq.clone());
        sp[j] = vq;
        sq[j] = vp;
        if part(objective, x, k, p, q, &sp, &sq) < before - 1e-12 * before.abs() {
            x[p * k + j] = vq;
            x[q * k + j] = vp;
            for f in 0..slices.len() {
                counts[j].shift(f, p, cp, cq);
                counts[j].shift(f, q, cq, cp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cd2(x: &[f64], k: usize) -> f64 {
        let n = x.len() / k;
        let mut s1 = 0.0;
        let mut s2 = 0.0;
        for i in 0..n {
            s1 += (0..k).map(|j| g(x[i * k + j])).product::<f64>();
            for l in 0..n {
                s2 += (0..k)
                    .map(|j| h(x[i * k + j], x[l * k + j]))
                    .product::<f64>();
            }
        }
        Centered::CONSTANT_BASE.powi(k as i32) - 2.0 * s1 / n as f64 + s2 / (n * n) as f64
    }

    #[test]
    fn the_kernel_is_the_library_centred_l2() {
        let x: Vec<f64> = (0..40).map(|i| ((i * 7919) % 97) as f64 / 97.0).collect();
        let p = crate::PointSet::new(20, 2, x.clone()).unwrap();
        let ours = cd2(&x, 2).sqrt();
        assert!((ours - stillpoint_quality::metrics::centered_l2(&p)).abs() < 1e-12);
    }

    #[test]
    fn exchanges_lower_the_discrepancy_and_keep_every_slice_stratified() {
        let n = 24;
        // A stratified but poor start: every column the same order.
        let mut x: Vec<f64> = (0..n)
            .flat_map(|i| [(i as f64 + 0.5) / n as f64; 2])
            .collect();
        let labels: Vec<usize> = (0..n).map(|i| i % 3).collect();
        let before = cd2(&x, 2);
        exchange(&mut x, 2, &[(&labels, 3)], &Objective::CenteredL2, 1);
        assert!(cd2(&x, 2) < 0.5 * before);
        for j in 0..2 {
            let mut cells: Vec<usize> =
                (0..n).map(|i| (x[i * 2 + j] * n as f64) as usize).collect();
            cells.sort();
            assert_eq!(cells, (0..n).collect::<Vec<_>>());
            for level in 0..3 {
                let mut blocks: Vec<usize> = (0..n)
                    .filter(|&i| labels[i] == level)
                    .map(|i| (x[i * 2 + j] * 8.0) as usize)
                    .collect();
                blocks.sort();
                assert_eq!(blocks, (0..8).collect::<Vec<_>>());
            }
        }
    }
}
