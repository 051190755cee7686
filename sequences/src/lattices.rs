//! Number-theoretic point sets: Hua–Wang good points from a cyclotomic field, rank-1
//! lattices (Fibonacci in two dimensions, Korobov otherwise) with the generator chosen by
//! the worst-case error P_2, and the rank-1 lattice made for the shift-and-tent
//! randomisation, its generator built component by component over every candidate by
//! the fast construction of `fast_cbc`.
//!
//! References: L.-K. Hua and Y. Wang, *Applications of Number Theory to Numerical
//! Analysis*, Springer / Science Press, 1981 (good points from the cyclotomic field,
//! γ_j = 2 cos(2πj/p)); N. M. Korobov, *Number-theoretic methods in approximate analysis*,
//! 1963; I. H. Sloan and S. Joe, *Lattice Methods for Multiple Integration*, Oxford, 1994
//! (rank-1 lattices, the criterion P_α and its Bernoulli-polynomial closed form);
//! D. Nuyens and R. Cools, *Fast algorithms for component-by-component construction of
//! rank-1 lattice rules*, Math. Comp. 75 (2006) and J. Complexity 22 (2006).

use rayon::prelude::*;

use super::fast_cbc::{inverse_mod, mul_mod, FastCbc};
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
/// the next multiplier coprime to n. (The fast construction of the tent lattice does not
/// carry over: for s ≥ 3 a multiplier's Σ_k Π_j B2(k·a^j/n) is no correlation over the
/// units of Z_n, so no transform gives every multiplier's at once.)
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

/// Weight γ of every coordinate in [`tent_criterion`]. Product weights this small make
/// the criterion care for one- and two-dimensional projections far more than for
/// high-order interactions, as the integrands users bring do. Chosen on Genz's families
/// at random parameters in (s, n) = (2, 32), (3, 64), (6, 128), (10, 256), (5, 1000),
/// (20, 1024), (15, 2048) among 0.01, 0.03, 0.05, 0.1 and 0.3: the weight matters little
/// at low s; at s ≥ 10, 0.1 and 0.3 lose the product-peak and Gaussian families and 0.01
/// the corner peak, while 0.05 keeps every smooth family near its best.
pub const TENT_WEIGHT: f64 = 0.05;

/// γ·(2π)⁴/24·(−B4(r/n)) for r = 0..n−1, with B4(x) = x⁴ − 2x³ + x² − 1/30: γ times the
/// kernel Σ_{h≠0} e^{2πihx}/h⁴ = −(2π)⁴ B4(x)/4! at the n values a lattice coordinate can
/// take. Kept apart from the factor 1 + t, so that products over the coordinates can be
/// carried as Π(1 + t) − 1 without the rounding of 1 + t.
pub(super) fn tent_terms(n: usize, gamma: f64) -> Vec<f64> {
    let c = (2.0 * std::f64::consts::PI).powi(4) / 24.0;
    (0..n)
        .map(|r| {
            let x = r as f64 / n as f64;
            -(gamma * c * (x * x * (x * x - 2.0 * x + 1.0) - 1.0 / 30.0))
        })
        .collect()
}

/// 1 + t for the terms t of [`tent_terms`]: the one-dimensional factor of the kernel.
pub(super) fn tent_factors(n: usize, gamma: f64) -> Vec<f64> {
    tent_terms(n, gamma).into_iter().map(|t| 1.0 + t).collect()
}

/// The criterion of a lattice made for the shift-and-tent randomisation:
/// −1 + (1/n) Σ_k Π_j (1 + γ ω(frac(k z_j / n))), with ω(x) = Σ_{h≠0} e^{2πihx}/h⁴ and
/// γ = [`TENT_WEIGHT`]. It is the squared worst-case error, averaged over the random shift,
/// of the shifted and tent-transformed lattice for integrands with square-integrable
/// mixed second derivatives (the half-period cosine space of smoothness 2; Hickernell
/// 2002, Dick, Nuyens and Pillichshammer 2014): what the randomised estimate's mean
/// square error is bounded by, up to the integrand's norm.
///
/// Refuses n = 0 or an empty z, naming the argument.
pub fn tent_criterion(n: usize, z: &[u64]) -> Result<f64, Error> {
    check_shape(n, z.len())?;
    Ok(p2_with_factors(z, &tent_factors(n, TENT_WEIGHT)))
}

/// How many generators of an n-point rank-1 lattice differ up to sign (φ(n)/2 for
/// n ≥ 3): with more coordinates than this, two must share one.
pub fn distinct_generators(n: usize) -> usize {
    generators(n as u64).len()
}

/// The generators 1 ≤ a ≤ n/2 coprime to n: one of each pair a, n − a, which give the
/// same lattice coordinate up to sign.
pub(super) fn generators(n: u64) -> Vec<u64> {
    (1..=(n / 2).max(1)).filter(|&a| gcd(a, n) == 1).collect()
}

/// The generating vector of [`tent_lattice`], built component by component (Sloan, Kuo
/// and Joe 2002): z_1 = 1, then each z_j the value coprime to n, 1 ≤ z_j ≤ n/2, that
/// makes [`tent_criterion`] of (z_1, …, z_j) smallest (ties to the smaller; z and n − z
/// give the same value) among those whose two-dimensional projection with every earlier
/// coordinate has no dual vector (h₁, h₂) with max(1, |h₁|)·max(1, |h₂|) < ⌊n^{1/4}⌋,
/// from 4 096 points on (such a projection lies on few lines; the criterion alone took
/// one of Zaremba index 4 at 16 384 points and 50 coordinates). Every candidate is
/// tried, at every n, by the fast construction of Nuyens and Cools (2006): the criteria
/// of all candidates at once by FFTs over the multiplicative group of Z_n, O(n log n)
/// per coordinate.
///
/// The candidates are ranked on per-point products carried as Π(1 + t) − 1, which
/// resolve differences of criteria far below the 10⁻¹⁶·√n a plain sum of the products
/// resolves. Where [`tent_lattice_generator_plain`] tries every candidate
/// (φ(n)/2 · n ≤ 2^28), those within its rounding of the best are scored once more by
/// its sum, which picks as it did, so the vector is the plain search's to the bit;
/// above, the candidates within the transforms' rounding of the best count as tied and
/// the smallest wins. The result does not depend on the number of threads.
///
/// Refuses n = 0 or s = 0, naming the argument.
pub fn tent_lattice_generator(n: usize, s: usize) -> Result<Vec<u64>, Error> {
    check_shape(n, s)?;
    Ok(fast_tent_generator(n, s, KOROBOV_SEARCH_BUDGET, &[]))
}

/// [`tent_lattice_generator`], with ties scored by the plain search's sums where
/// φ(n)/2 · n ≤ `plain_budget`, continuing the coordinates `given`.
fn fast_tent_generator(n: usize, s: usize, plain_budget: u128, given: &[u64]) -> Vec<u64> {
    let n64 = n as u64;
    let candidates = generators(n64);
    if s == 1 || candidates.len() <= 1 {
        return vec![1 % n64; s];
    }
    let plain_reach = candidates.len() as u128 * n as u128 <= plain_budget;
    let terms = tent_terms(n, TENT_WEIGHT);
    let factors: Vec<f64> = terms.iter().map(|t| 1.0 + t).collect();
    let fast = FastCbc::new(&terms, &candidates);
    let largest = factors.iter().copied().fold(0.0, f64::max);
    // Π(1 + t) − 1 per point, and the plain search's Π(1 + t) where its sums decide ties.
    let mut q = vec![0.0f64; n];
    let mut prod = if plain_reach {
        vec![1.0f64; n]
    } else {
        Vec::new()
    };
    let mut z = Vec::with_capacity(s);
    let mut guard = PairGuard::new(n64);
    // Made at the first coordinate the plain sums do not decide, carried from there on.
    let mut rough: Option<RoughTieBreak> = None;
    for j in 0..s {
        let zj = if j == 0 {
            1
        } else if let Some(&zj) = given.get(j) {
            zj
        } else {
            let (mut scores, rounding) = fast.scores(&q);
            guard.exclude(&candidates, &mut scores);
            let best = scores.iter().copied().fold(f64::INFINITY, f64::min);
            if plain_reach {
                // A plain sum of n positive terms is within γ_n·Σ|terms| of its value
                // (Higham, §4.2), the products in it within γ_j: the plain search's pick
                // is among the candidates this close to the fast best.
                let gamma_n = (n + j + 2) as f64 * f64::EPSILON;
                let plain = gamma_n * prod.iter().sum::<f64>() * largest;
                let near: Vec<u64> = candidates
                    .iter()
                    .zip(&scores)
                    .filter(|(_, &v)| v <= best + 4.0 * (plain + rounding))
                    .map(|(&c, _)| c)
                    .collect();
                let sums: Vec<(f64, u64)> = near
                    .par_iter()
                    .map(|&c| (plain_sum(&prod, &factors, c), c))
                    .collect();
                smallest(sums)
            } else {
                let rough = rough.get_or_insert_with(|| RoughTieBreak::new(n, &candidates, &z));
                pick(&candidates, &scores, rounding, || rough.scores())
            }
        };
        extend_terms(&mut q, &terms, zj);
        if let Some(rough) = rough.as_mut() {
            rough.extend(zj);
        }
        if plain_reach {
            extend_products(&mut prod, &factors, zj);
        }
        guard.add(zj);
        z.push(zj);
    }
    z
}

/// The guard on the two-dimensional projections of a component-by-component search: a
/// candidate z for the next coordinate is refused when, with some earlier coordinate
/// z_i, a dual vector (h₁, h₂) ≠ 0 with h₁·z_i + h₂·z ≡ 0 (mod n) has
/// max(1, |h₁|)·max(1, |h₂|) below [`pair_guard_bound`]: the projection's points then lie
/// on few lines (the pair's Zaremba index is that small), a defect the smoothness-2
/// criterion weighs at γ² against the higher orders' many terms and, past some thirty
/// coordinates, takes. Only candidates the criterion would have picked over every
/// allowed one change the vector; where the guard refuses every candidate (more
/// coordinates than the group has room for) it is dropped for that coordinate.
pub(super) struct PairGuard {
    n: u64,
    bound: u64,
    /// Refused residues mod n, closed under z ↦ n − z.
    refused: Vec<bool>,
}

impl PairGuard {
    /// No coordinate chosen yet, for n points.
    pub(super) fn new(n: u64) -> PairGuard {
        PairGuard::with_bound(n, pair_guard_bound(n))
    }

    /// The guard with its bound given.
    fn with_bound(n: u64, bound: u64) -> PairGuard {
        PairGuard {
            n,
            bound,
            refused: vec![false; n as usize],
        }
    }

    /// Refuses every residue z with a dual vector of the pair (zi, z) below the bound:
    /// h₂·z ≡ −h₁·zi (mod n) for 1 ≤ h₂, 1 ≤ |h₁|, |h₁|·h₂ < bound (h₁ = 0 or h₂ = 0
    /// would need a multiple of n, zi and z being units). With g = gcd(h₂, n) it has g
    /// solutions mod n when g divides h₁, none otherwise.
    pub(super) fn add(&mut self, zi: u64) {
        let n = self.n;
        if n < 2 {
            return;
        }
        for h2 in 1..self.bound {
            let g = gcd(h2, n);
            let m = n / g;
            // h₂/g is a unit mod n/g.
            let inv = inverse_mod(h2 / g, m);
            for h1 in 1..=(self.bound - 1) / h2 {
                if h1 % g != 0 {
                    continue;
                }
                // h₂·z ≡ h₁·zi (base) and h₂·z ≡ −h₁·zi (m − base).
                let base = mul_mod(mul_mod(h1 / g, zi % m, m), inv, m);
                for z0 in [(m - base) % m, base] {
                    let mut r = z0;
                    while r < n {
                        self.refused[r as usize] = true;
                        self.refused[((n - r) % n) as usize] = true;
                        r += m;
                    }
                }
            }
        }
    }

    /// Whether the candidate c is refused.
    pub(super) fn refuses(&self, c: u64) -> bool {
        self.refused[(c % self.n.max(1)) as usize]
    }

    /// Sets the scores of refused candidates to +∞, unless every candidate is refused.
    pub(super) fn exclude(&self, candidates: &[u64], scores: &mut [f64]) {
        if candidates.iter().all(|&c| self.refuses(c)) {
            return;
        }
        for (&c, v) in candidates.iter().zip(scores.iter_mut()) {
            if self.refuses(c) {
                *v = f64::INFINITY;
            }
        }
    }
}

/// The smallest bound [`PairGuard`] is used with: below 4 096 points (a fourth root
/// under 8) it is off.
const PAIR_GUARD_FROM: u64 = 8;

/// The bound of [`PairGuard`] for n points: ⌊n^{1/4}⌋, the largest T with T⁴ ≤ n, from
/// [`PAIR_GUARD_FROM`] on, and 0 (no guard) below. Each earlier coordinate refuses
/// about T·ln T of the φ(n)/2 candidates; with a fourth root the refused share at the
/// 50th coordinate is 11 % at 16 384 points (T = 11) and a third at 4 096 (T = 8),
/// while projections as coarse as the one measured at (50, 16 384) (Zaremba index 4)
/// are taken out. Below 4 096 points the share reaches half to two thirds (2 000 and
/// 1 024 points, T = 6 and 5), the search is steered off its criterion at most
/// coordinates, and the corner peak measured worse (1.02 and 1.05× scrambled Sobol' at
/// 50 coordinates, from 0.59 and 0.64), so the guard starts at T = 8.
pub(super) fn pair_guard_bound(n: u64) -> u64 {
    let mut t = 1u64;
    while (t + 1).pow(4) <= n {
        t += 1;
    }
    if t >= PAIR_GUARD_FROM {
        t
    } else {
        0
    }
}

/// γ·2π²·B2(r/n) for r = 0..n−1, B2(x) = x² − x + 1/6: γ times the first-order kernel
/// Σ_{h≠0} e^{2πihx}/h² = 2π²B2(x) at the n values a lattice coordinate takes.
pub(super) fn rough_terms(n: usize, gamma: f64) -> Vec<f64> {
    let c = 2.0 * std::f64::consts::PI * std::f64::consts::PI;
    (0..n)
        .map(|r| {
            let x = r as f64 / n as f64;
            gamma * c * (x * x - x + 1.0 / 6.0)
        })
        .collect()
}

/// The first-order criterion of the coordinates chosen so far, kept beside a smoothness-2
/// search to decide between the candidates it cannot tell apart. The smoothness-2
/// criterion of a good n-point lattice is of order n⁻⁴ while its fast scores carry a
/// rounding of order 10⁻¹⁶ relative to their terms: above a few 10⁴ points thousands of
/// candidates lie within that rounding of the best, and taking the smallest of them put
/// a two-dimensional projection on about 2 400 lines at every n from 65 536 to 10⁶. The
/// first-order criterion (order n⁻²) is still resolved there, and ranks lattices the
/// same way where both are resolved.
pub(super) struct RoughTieBreak {
    terms: Vec<f64>,
    fast: FastCbc,
    q: Vec<f64>,
}

impl RoughTieBreak {
    /// For n points, the candidates of the search and the coordinates `z` chosen so far.
    pub(super) fn new(n: usize, candidates: &[u64], z: &[u64]) -> RoughTieBreak {
        let terms = rough_terms(n, TENT_WEIGHT);
        let fast = FastCbc::new(&terms, candidates);
        let mut q = vec![0.0; n];
        for &zi in z {
            extend_terms(&mut q, &terms, zi);
        }
        RoughTieBreak { terms, fast, q }
    }

    /// Adds the coordinate z to those the criterion is of.
    pub(super) fn extend(&mut self, z: u64) {
        extend_terms(&mut self.q, &self.terms, z);
    }

    /// The first-order scores of the candidates for the next coordinate, and their
    /// rounding.
    pub(super) fn scores(&self) -> (Vec<f64>, f64) {
        self.fast.scores(&self.q)
    }
}

/// The candidate whose score is within `rounding` of the best, or where several are,
/// the one of those best by the `tie_break` scores (ties there to the first, the
/// smallest).
pub(super) fn pick(
    candidates: &[u64],
    scores: &[f64],
    rounding: f64,
    tie_break: impl FnOnce() -> (Vec<f64>, f64),
) -> u64 {
    let best = scores.iter().copied().fold(f64::INFINITY, f64::min);
    let near: Vec<usize> = (0..candidates.len())
        .filter(|&i| scores[i] <= best + rounding)
        .collect();
    if near.len() <= 1 {
        return near.first().map_or(1, |&i| candidates[i]);
    }
    let (second, second_rounding) = tie_break();
    let best2 = near
        .iter()
        .map(|&i| second[i])
        .fold(f64::INFINITY, f64::min);
    near.iter()
        .find(|&&i| second[i] <= best2 + second_rounding)
        .map_or(1, |&i| candidates[i])
}

/// Σ_k p_k·f_{kc mod n} over the points in order: the plain search's score of c.
fn plain_sum(prod: &[f64], factors: &[f64], c: u64) -> f64 {
    let n = prod.len();
    let (mut r, mut sum) = (0usize, 0.0);
    for p in prod {
        sum += p * factors[r];
        r += c as usize;
        if r >= n {
            r -= n;
        }
    }
    sum
}

/// The candidate of smallest score, ties to the smaller candidate.
fn smallest(scores: Vec<(f64, u64)>) -> u64 {
    scores
        .into_iter()
        .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
        .map_or(1, |(_, c)| c)
}

/// Multiplies the per-point products p_k by the factor f_{kz mod n}.
fn extend_products(prod: &mut [f64], factors: &[f64], z: u64) {
    let n = prod.len();
    let mut r = 0usize;
    for p in prod.iter_mut() {
        *p *= factors[r];
        r += (z % n as u64) as usize;
        if r >= n {
            r -= n;
        }
    }
}

/// Extends the per-point q_k = Π(1 + t) − 1 by the coordinate z: q_k + t + q_k·t with
/// t = t_{kz mod n}.
pub(super) fn extend_terms(q: &mut [f64], terms: &[f64], z: u64) {
    let n = q.len();
    let step = (z % n as u64) as usize;
    let mut r = 0usize;
    for qk in q.iter_mut() {
        let t = terms[r];
        *qk += t + *qk * t;
        r += step;
        if r >= n {
            r -= n;
        }
    }
}

/// The plain component-by-component search [`tent_lattice_generator`] replaced: each
/// candidate scored by its own sum over the n points, O(n) per candidate and O(n²) per
/// coordinate, and past a work budget of 2^28 point steps per coordinate (about 2–3·10⁴
/// points) an evenly spaced sample of the candidates instead of all of them, under the
/// same guard on two-dimensional projections. Kept as the
/// reference the fast construction is checked and timed against.
///
/// Refuses n = 0 or s = 0, naming the argument.
pub fn tent_lattice_generator_plain(n: usize, s: usize) -> Result<Vec<u64>, Error> {
    check_shape(n, s)?;
    let n64 = n as u64;
    let coprime = generators(n64);
    let candidates: Vec<u64> = if coprime.len() as u128 * n as u128 <= KOROBOV_SEARCH_BUDGET {
        coprime
    } else {
        let count = ((KOROBOV_SEARCH_BUDGET / n as u128) as usize).max(KOROBOV_MIN_CANDIDATES);
        let mut picks: Vec<u64> = (0..count)
            .map(|t| coprime[t * coprime.len() / count])
            .collect();
        picks.dedup();
        picks
    };
    let factors = tent_factors(n, TENT_WEIGHT);
    // The product over the coordinates chosen so far, per lattice point k.
    let mut prod = vec![1.0f64; n];
    let mut z = Vec::with_capacity(s);
    let mut guard = PairGuard::new(n64);
    for j in 0..s {
        let zj = if j == 0 {
            1
        } else {
            let allowed: Vec<u64> = candidates
                .iter()
                .copied()
                .filter(|&c| !guard.refuses(c))
                .collect();
            let tried = if allowed.is_empty() {
                &candidates
            } else {
                &allowed
            };
            smallest(
                tried
                    .par_iter()
                    .map(|&c| (plain_sum(&prod, &factors, c), c))
                    .collect(),
            )
        };
        extend_products(&mut prod, &factors, zj);
        guard.add(zj);
        z.push(zj % n64.max(1));
    }
    Ok(z)
}

/// The rank-1 lattice made for the shift-and-tent randomisation: generator
/// [`tent_lattice_generator`], unshifted (point 0 is the origin), each coordinate the n
/// multiples of 1/n once each. Randomised by
/// `stillpoint_run::post::randomize::Randomize::Tent`, the estimate is unbiased and its error
/// decays like n⁻² for smooth integrands, not n^{-3/2} as for scrambled nets.
///
/// Deterministic (no seed). Refuses n = 0 or s = 0, naming the argument.
pub fn tent_lattice(n: usize, s: usize) -> Result<PointSet, Error> {
    let z = tent_lattice_generator(n, s)?;
    rank1_lattice(n, &z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two-dimensional criterion summed over the dual lattice, every term positive:
    /// Σ_{h₂=1}^{n/2} 2·(γ/h₂⁴)·Σ_m r(h₁ + m n), h₁ ≡ −h₂z mod n, r(0) = 1, r(h) = γ/h⁴.
    /// Resolved far below the rounding of a sum over the points.
    fn dual_criterion(n: i64, z: i64, gamma: f64) -> f64 {
        let r = |h: i64| {
            if h == 0 {
                1.0
            } else {
                gamma / (h as f64).powi(4)
            }
        };
        (1..=n / 2)
            .map(|h2| {
                let mut a = (-h2 * z).rem_euclid(n);
                if a > n / 2 {
                    a -= n;
                }
                let alias: f64 = (-3..=3).map(|m| r(a + m * n)).sum();
                2.0 * gamma / (h2 as f64).powi(4) * alias
            })
            .sum()
    }

    /// Above the plain search's reach the smoothness-2 scores of the best candidates lie
    /// within their rounding of one another; the pick must still be the criterion's best
    /// (the smallest tied candidate put the points on about 2 400 lines).
    #[test]
    fn above_the_plain_reach_the_second_generator_is_the_criterions_best() {
        let n = 40_000usize;
        assert!(generators(n as u64).len() as u128 * n as u128 > KOROBOV_SEARCH_BUDGET);
        let z = tent_lattice_generator(n, 2).unwrap();
        let crit = |c: u64| dual_criterion(n as i64, c as i64, TENT_WEIGHT);
        let best = generators(n as u64)
            .par_iter()
            .map(|&c| crit(c))
            .reduce(|| f64::INFINITY, f64::min);
        assert!(
            crit(z[1]) <= 1.05 * best,
            "z₂ = {}: {} vs best {best}",
            z[1],
            crit(z[1])
        );
    }

    /// −B4(x)·(2π)⁴/24 from its Fourier series Σ_{h≠0} cos(2πhx)/h⁴, summed directly.
    fn omega_series(x: f64) -> f64 {
        (1..20_000)
            .map(|h| {
                let h = h as f64;
                2.0 * (2.0 * std::f64::consts::PI * h * x).cos() / h.powi(4)
            })
            .sum()
    }

    #[test]
    fn the_tent_criterion_is_the_pair_sum_of_its_fourier_kernel() {
        let (n, z) = (12usize, [1u64, 5, 7]);
        let p = rank1_lattice(n, &z).unwrap();
        // (1/n²) Σ_{i,j} Π_k (1 + γ ω(x_ik − x_jk)) − 1 over every pair, with ω from its
        // Fourier series: the mean square error of the shifted rule, independently of
        // the lattice's one-sum closed form.
        let mut sum = 0.0;
        for a in p.rows() {
            for b in p.rows() {
                sum += a
                    .iter()
                    .zip(b)
                    .map(|(x, y)| 1.0 + TENT_WEIGHT * omega_series((x - y).rem_euclid(1.0)))
                    .product::<f64>();
            }
        }
        let pairs = sum / (n * n) as f64 - 1.0;
        let closed = tent_criterion(n, &z).unwrap();
        assert!(
            (pairs - closed).abs() < 1e-9 * closed.abs().max(1e-9),
            "{pairs} vs {closed}"
        );
    }

    #[test]
    fn component_by_component_beats_random_generators() {
        for (n, s) in [(64usize, 4usize), (101, 6), (256, 10)] {
            let z = tent_lattice_generator(n, s).unwrap();
            assert_eq!(z.len(), s);
            assert!(z.iter().all(|&v| gcd(v, n as u64) == 1));
            let ours = tent_criterion(n, &z).unwrap();
            // Generators with coprime components drawn by a fixed LCG: ours is below all.
            let mut state = 12345u64;
            for _ in 0..50 {
                let r: Vec<u64> = (0..s)
                    .map(|_| loop {
                        state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                        let v = 1 + (state >> 33) % (n as u64 - 1);
                        if gcd(v, n as u64) == 1 {
                            break v;
                        }
                    })
                    .collect();
                assert!(
                    ours <= tent_criterion(n, &r).unwrap(),
                    "n = {n}, s = {s}: {r:?}"
                );
            }
        }
        assert_eq!(tent_lattice_generator(1, 3).unwrap(), vec![0, 0, 0]);
    }

    /// The criterion's exact invariants: the multiset over the points of the sorted
    /// coordinates folded to min(r, n − r). Lattices with equal keys have equal criteria
    /// in exact arithmetic (the kernel is even and the weights are equal).
    fn folded_points(n: usize, z: &[u64]) -> Vec<Vec<u64>> {
        let n64 = n as u64;
        let mut pts: Vec<Vec<u64>> = (0..n64)
            .map(|k| {
                let mut p: Vec<u64> = z
                    .iter()
                    .map(|&zj| {
                        let r = k * zj % n64;
                        r.min(n64 - r)
                    })
                    .collect();
                p.sort_unstable();
                p
            })
            .collect();
        pts.sort_unstable();
        pts
    }

    /// The criterion carried as Π(1 + t) − 1 and summed with Neumaier's compensation.
    fn accurate_criterion(n: usize, z: &[u64]) -> f64 {
        let terms = tent_terms(n, TENT_WEIGHT);
        let mut q = vec![0.0; n];
        for &zj in z {
            extend_terms(&mut q, &terms, zj);
        }
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for &v in &q {
            let t = sum + v;
            comp += if sum.abs() >= v.abs() {
                (sum - t) + v
            } else {
                (v - t) + sum
            };
            sum = t;
        }
        (sum + comp) / n as f64
    }

    /// Compares the fast choice of every coordinate after the plain search's prefix with
    /// the plain search's. Where they differ, the two must tie exactly (equal folded
    /// lattices) or the fast one must be at least as good by the accurate criterion
    /// (within 1e-12): the plain sum's rounding, near 10⁻¹⁶·√n, can exceed the
    /// differences between good candidates. Returns the counts of exact ties and of
    /// better choices.
    fn differences(n: usize, plain: &[u64]) -> (usize, usize) {
        let (mut ties, mut better) = (0, 0);
        let mut fast = fast_tent_generator(n, plain.len(), 0, &[]);
        while let Some(j) = plain.iter().zip(&fast).position(|(a, b)| a != b) {
            let (a, b) = (&plain[..=j], [&plain[..j], &fast[j..=j]].concat());
            assert!(gcd(fast[j], n as u64) == 1 && 2 * fast[j] <= n as u64);
            if folded_points(n, a) == folded_points(n, &b) {
                ties += 1;
            } else {
                let (ea, eb) = (accurate_criterion(n, a), accurate_criterion(n, &b));
                assert!(
                    eb <= ea + 1e-12 * ea.abs(),
                    "n = {n}: plain {a:?} ({ea:e}) against fast {b:?} ({eb:e})"
                );
                better += 1;
            }
            fast = fast_tent_generator(n, plain.len(), 0, &plain[..=j]);
        }
        (ties, better)
    }

    #[test]
    fn the_fast_search_is_the_plain_search_to_the_bit_within_its_budget() {
        let mut cases: Vec<(usize, usize)> = (1..=300).map(|n| (n, 12)).collect();
        // Primes, powers of two and composites of a hundred to a few thousand points.
        for n in [
            401, 509, 997, 1009, 2003, 4001, 256, 512, 1024, 2048, 4096, 720, 1000, 1500, 2310,
            3000, 5040,
        ] {
            cases.push((n, 10));
        }
        // The largest prime and power of two the plain search tries exhaustively.
        cases.extend([(23_167, 4), (32_768, 3)]);
        // The pair guard refuses the criterion's pick from the 36th coordinate on.
        cases.push((4_096, 40));
        for (n, s) in cases {
            let plain = tent_lattice_generator_plain(n, s).unwrap();
            assert_eq!(tent_lattice_generator(n, s).unwrap(), plain, "n = {n}");
        }
    }

    #[test]
    fn the_fast_scores_alone_choose_as_the_plain_search_but_for_exact_ties() {
        // With no plain sums to break ties, the fast scores decide on their own.
        let mut cases: Vec<(usize, usize)> = (2..=300).map(|n| (n, 12)).collect();
        for n in [401, 509, 1009, 2003, 512, 1024, 4096, 720, 1000, 2310, 5040] {
            cases.push((n, 10));
        }
        let (mut ties, mut better, mut choices) = (0, 0, 0);
        for &(n, s) in &cases {
            let plain = tent_lattice_generator_plain(n, s).unwrap();
            let (t, b) = differences(n, &plain);
            (ties, better, choices) = (ties + t, better + b, choices + s - 1);
        }
        // Most choices agree outright; the rest are exact ties or the plain sum's rounding.
        assert!(
            (ties + better) * 2 < choices,
            "{ties} ties and {better} better of {choices}"
        );
        eprintln!("{ties} exact ties and {better} better choices of {choices}");
    }

    #[test]
    fn the_exhaustive_search_beats_the_sampled_one_at_large_composite_n() {
        for n in [100_000usize, 200_000] {
            let s = 10;
            let fast = tent_lattice_generator(n, s).unwrap();
            let sampled = tent_lattice_generator_plain(n, s).unwrap();
            let (ef, es) = (
                accurate_criterion(n, &fast),
                accurate_criterion(n, &sampled),
            );
            assert!(ef <= es, "n = {n}: {ef:e} against the sampled {es:e}");
        }
    }

    /// The smallest max(1, |h₁|)·max(1, |h₂|) below `cap` over the dual vectors
    /// (h₁, h₂) ≠ 0 of the pair (a, b) mod n, h₁·a + h₂·b ≡ 0, tried one by one; `cap`
    /// if there is none.
    fn pair_index(n: u64, a: u64, b: u64, cap: i64) -> i64 {
        let mut best = cap;
        for h1 in -cap..=cap {
            for h2 in -cap..=cap {
                let size = h1.abs().max(1) * h2.abs().max(1);
                let dot = (h1 * a as i64 + h2 * b as i64).rem_euclid(n as i64);
                if (h1, h2) != (0, 0) && dot == 0 && size < best {
                    best = size;
                }
            }
        }
        best
    }

    #[test]
    fn the_pair_guard_refuses_exactly_the_units_with_a_short_dual_vector() {
        for n in [12u64, 30, 64, 97, 210, 256, 1000, 1024] {
            for bound in [2u64, 3, 5, 8, 12] {
                for zi in generators(n).into_iter().take(6) {
                    let mut guard = PairGuard::with_bound(n, bound);
                    guard.add(zi);
                    for c in (1..n).filter(|&c| gcd(c, n) == 1) {
                        let short = pair_index(n, zi, c, bound as i64) < bound as i64;
                        assert_eq!(guard.refuses(c), short, "n = {n}, T = {bound}, {zi}, {c}");
                    }
                }
            }
        }
    }

    #[test]
    fn no_two_coordinates_have_a_dual_vector_below_the_bound_where_there_is_room() {
        // At (50, 16 384) the search without the guard gave z₇ + z₄₅ = n/2: index 4.
        for n in [4_096usize, 10_000, 16_384] {
            let bound = pair_guard_bound(n as u64) as i64;
            let z = tent_lattice_generator(n, 50).unwrap();
            for j in 1..z.len() {
                for i in 0..j {
                    let index = pair_index(n as u64, z[i], z[j], bound);
                    assert!(
                        index >= bound,
                        "n = {n}: z{} = {}, z{} = {}: {index}",
                        i + 1,
                        z[i],
                        j + 1,
                        z[j]
                    );
                }
            }
        }
        assert_eq!(pair_guard_bound(16_384), 11);
        assert_eq!(
            (pair_guard_bound(65_535), pair_guard_bound(65_536)),
            (15, 16)
        );
    }

    #[test]
    fn the_guard_excludes_refused_candidates_unless_it_refuses_every_one() {
        let mut guard = PairGuard::with_bound(97, 3);
        guard.add(1);
        let cands = [1u64, 30, 40, 48];
        let mut scores = vec![1.0, 2.0, 3.0, 4.0];
        guard.exclude(&cands, &mut scores);
        // 1 (h = (1, −1)) and 48 (2·48 ≡ −1, h = (1, 2)) have a dual vector of size < 3.
        assert_eq!(scores, vec![f64::INFINITY, 2.0, 3.0, f64::INFINITY]);
        let mut all = vec![1.0, 4.0];
        guard.exclude(&[1, 48], &mut all);
        assert_eq!(all, vec![1.0, 4.0]);
    }

    #[test]
    fn the_fast_search_gives_the_same_vector_on_one_and_two_threads() {
        let on = |threads: usize, n: usize, budget: u128| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| fast_tent_generator(n, 8, budget, &[]))
        };
        for (n, budget) in [(30_030, 0), (30_030, KOROBOV_SEARCH_BUDGET), (65_536, 0)] {
            assert_eq!(on(1, n, budget), on(2, n, budget), "n = {n}");
        }
    }
}
