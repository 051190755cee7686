//! Number-theoretic point sets: Hua–Wang good points from a cyclotomic field, and rank-1
//! lattices (Fibonacci in two dimensions, Korobov otherwise) with the generator chosen by
//! the worst-case error P_2.
//!
//! References: L.-K. Hua and Y. Wang, *Applications of Number Theory to Numerical
//! Analysis*, Springer / Science Press, 1981 (good points from the cyclotomic field,
//! γ_j = 2 cos(2πj/p)); N. M. Korobov, *Number-theoretic methods in approximate analysis*,
//! 1963; I. H. Sloan and S. Joe, *Lattice Methods for Multiple Integration*, Oxford, 1994
//! (rank-1 lattices, the criterion P_α and its Bernoulli-polynomial closed form).

use rayon::prelude::*;

use super::{check_shape, prev_float};
use crate::{Error, PointSet};

/// Inner-loop steps (one per point and coordinate of each candidate lattice) the Korobov
/// search may spend before it samples candidates instead of trying them all: about a
/// quarter to half a second on one core.
const KOROBOV_SEARCH_BUDGET: u128 = 1 << 28;

/// Fewest candidates tried when the search samples.
const KOROBOV_MIN_CANDIDATES: usize = 32;

fn is_prime(m: u64) -> bool {
    if m < 2 {
        return false;
    }
    let mut d = 2u64;
    while d * d <= m {
        if m.is_multiple_of(d) {
            return false;
        }
        d += 1;
    }
    true
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// frac(k·γ) with the rounding error of the product k·γ recovered by a fused multiply-add,
/// so the fractional part keeps its accuracy when k·γ is large; always in [0, 1).
fn frac_product(k: f64, gamma: f64) -> f64 {
    let hi = k * gamma;
    let lo = k.mul_add(gamma, -hi);
    let f = hi - hi.floor() + lo;
    let x = f - f.floor();
    // A tiny negative sum wraps to 1 − tiny, which rounds onto 1.
    if x >= 1.0 {
        prev_float(1.0)
    } else {
        x
    }
}

/// The prime p of the Hua–Wang construction for s dimensions: the smallest prime ≥ 2s + 3.
pub(crate) fn hua_wang_prime(s: usize) -> u64 {
    let mut p = 2 * s as u64 + 3;
    while !is_prime(p) {
        p += 1;
    }
    p
}

/// Hua–Wang good points from the cyclotomic field: with p the smallest prime ≥ 2s + 3 and
/// γ_j = 2 cos(2πj/p) for j = 1..s, point k (k = 1..n) is x_{k,j} = frac(k·γ_j).
///
/// Deterministic (no seed). Hua and Wang (1981) show the discrepancy of these n points is
/// O(n^(−1/2 − 1/(2(s−1)) + ε)): better than random, much worse than nets or lattices as n
/// grows; the set is a classic comparison point, used as "HW" in the paper's tables.
///
/// Refuses n = 0 or s = 0, naming the argument.
pub fn hua_wang(n: usize, s: usize) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    let p = hua_wang_prime(s) as f64;
    let gammas: Vec<f64> = (1..=s)
        .map(|j| 2.0 * (2.0 * std::f64::consts::PI * j as f64 / p).cos())
        .collect();
    let mut data = Vec::with_capacity(n * s);
    for k in 1..=n {
        let k = k as f64;
        data.extend(gammas.iter().map(|&g| frac_product(k, g)));
    }
    PointSet::new(n, s, data)
}

/// The rank-1 lattice with generating vector z: point k (k = 0..n−1) is
/// x_{k,j} = ((k·z_j) mod n)/n, computed in exact integer arithmetic. Unshifted: point 0
/// is the origin. The dimension is z.len().
///
/// Refuses n = 0 or an empty z, naming the argument.
pub fn rank1_lattice(n: usize, z: &[u64]) -> Result<PointSet, Error> {
    let s = z.len();
    check_shape(n, s)?;
    let nn = n as u128;
    let inv = n as f64;
    let mut data = Vec::with_capacity(n * s);
    for k in 0..n as u128 {
        data.extend(z.iter().map(|&zj| ((k * u128::from(zj)) % nn) as f64 / inv));
    }
    PointSet::new(n, s, data)
}

/// 1 + 2π² B2(r/n) for r = 0..n−1, with B2(x) = x² − x + 1/6: the one-dimensional factor
/// of the α = 2 Korobov kernel at the lattice's coordinate values (the only n values a
/// rank-1 lattice coordinate can take).
fn p2_factors(n: usize) -> Vec<f64> {
    let c = 2.0 * std::f64::consts::PI * std::f64::consts::PI;
    (0..n)
        .map(|r| {
            let x = r as f64 / n as f64;
            1.0 + c * (x * x - x + 1.0 / 6.0)
        })
        .collect()
}

/// P_2 of the lattice with generator z from precomputed factors, summed over k in order.
fn p2_with_factors(z: &[u64], factors: &[f64]) -> f64 {
    let n = factors.len();
    let steps: Vec<usize> = z.iter().map(|&zj| (zj % n as u64) as usize).collect();
    let mut idx = vec![0usize; z.len()];
    let mut sum = 0.0;
    for _ in 0..n {
        let mut prod = 1.0;
        // k·z_j mod n advanced by one step of z_j per point, avoiding a product and a
        // division per coordinate.
        for (i, &st) in idx.iter_mut().zip(&steps) {
            prod *= factors[*i];
            *i += st;
            if *i >= n {
                *i -= n;
            }
        }
        sum += prod;
    }
    sum / n as f64 - 1.0
}

/// P_2 of the rank-1 lattice with n points and generator z: the squared worst-case
/// integration error in the unweighted Korobov space of smoothness α = 2,
/// P_2 = −1 + (1/n) Σ_{k=0}^{n−1} Π_j (1 + 2π² B2(frac(k z_j / n))), with
/// B2(x) = x² − x + 1/6 (Sloan & Joe 1994). Smaller is better; it is 0 only in the limit.
///
/// Refuses n = 0 or an empty z, naming the argument.
pub fn korobov_p2(n: usize, z: &[u64]) -> Result<f64, Error> {
    check_shape(n, z.len())?;
    Ok(p2_with_factors(z, &p2_factors(n)))
}

/// (1, a, a², ..., a^(s−1)) mod n.
fn korobov_vector(a: u64, n: u64, s: usize) -> Vec<u64> {
    let mut z = Vec::with_capacity(s);
    let mut power = 1 % n;
    for _ in 0..s {
        z.push(power);
        power = ((u128::from(power) * u128::from(a)) % u128::from(n)) as u64;
    }
    z
}

/// The index m with F_m = n (F_1 = F_2 = 1, F_3 = 2, ...) and F_{m−1}, if n ≥ 3 is a
/// Fibonacci number.
fn fibonacci_predecessor(n: u64) -> Option<u64> {
    let (mut prev, mut cur) = (1u64, 2u64);
    while cur < n {
        let next = prev.checked_add(cur)?;
        (prev, cur) = (cur, next);
    }
    (cur == n && n >= 3).then_some(prev)
}

/// The Korobov multiplier a with the smallest P_2 (ties to the smaller a).
///
/// Candidates are a = 1..=n/2 coprime to n (a and n − a give the same P_2, since
/// B2(1 − x) = B2(x)). If trying them all would cost more than 2^28 point-coordinate
/// steps (about n > 5 000 at s = 20, n > 16 000 at s = 2), an evenly spaced sample of
/// max(32, ⌊2^28/(n·s)⌋) starting values over 1..=n/2 is tried instead, each moved up to
/// the next multiplier coprime to n.
fn korobov_multiplier(n: u64, s: usize) -> u64 {
    let half = n / 2;
    if half <= 1 {
        return 1;
    }
    let coprime = (1..=half).filter(|&a| gcd(a, n) == 1).count() as u128;
    let candidates: Vec<u64> = if coprime * u128::from(n) * s as u128 <= KOROBOV_SEARCH_BUDGET {
        (1..=half).filter(|&a| gcd(a, n) == 1).collect()
    } else {
        let count = ((KOROBOV_SEARCH_BUDGET / (u128::from(n) * s as u128)) as usize)
            .max(KOROBOV_MIN_CANDIDATES);
        let mut picks: Vec<u64> = (0..count as u128)
            .map(|t| {
                let mut a = 1 + (t * u128::from(half - 1) / count as u128) as u64;
                while gcd(a, n) != 1 {
                    a += 1;
                }
                a
            })
            .collect();
        picks.dedup();
        picks
    };
    let factors = p2_factors(n as usize);
    let scores: Vec<(f64, u64)> = candidates
        .par_iter()
        .map(|&a| (p2_with_factors(&korobov_vector(a, n, s), &factors), a))
        .collect();
    scores
        .into_iter()
        .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
        .map_or(1, |(_, a)| a)
}

/// The generating vector [`lattice`] uses for n points in s dimensions:
///
/// * s = 1, or n ≤ 2 (no choice to make): z = (1, ..., 1);
/// * s = 2 and n = F_m a Fibonacci number ≥ 3: the Fibonacci lattice z = (1, F_{m−1});
/// * otherwise the Korobov vector z = (1, a, a², ..., a^(s−1)) mod n with the multiplier a
///   (coprime to n) of smallest [`korobov_p2`], searched exhaustively over 1..=n/2 or, past
///   a work budget of 2^28 point-coordinate steps, over an evenly spaced sample of
///   max(32, ⌊2^28/(n·s)⌋) multipliers;
///
/// Refuses n = 0 or s = 0, naming the argument.
pub fn lattice_generator(n: usize, s: usize) -> Result<Vec<u64>, Error> {
    check_shape(n, s)?;
    let n64 = n as u64;
    if s == 1 || n64 <= 2 {
        return Ok(vec![1; s]);
    }
    if s == 2 {
        if let Some(prev) = fibonacci_predecessor(n64) {
            return Ok(vec![1, prev]);
        }
    }
    Ok(korobov_vector(korobov_multiplier(n64, s), n64, s))
}

/// The rank-1 lattice of [`rank1_lattice`] with the generator of [`lattice_generator`]:
/// unshifted (point 0 is the origin), n points x_k = frac(k·z/n), k = 0..n−1, each
/// coordinate a multiple of 1/n hitting every multiple exactly once (z_j is coprime to n).
///
/// Deterministic (no seed). Refuses n = 0 or s = 0, naming the argument.
pub fn lattice(n: usize, s: usize) -> Result<PointSet, Error> {
    let z = lattice_generator(n, s)?;
    rank1_lattice(n, &z)
}
