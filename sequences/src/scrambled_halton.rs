//! Halton points with random digit permutations, the scrambled Halton (HS) baseline.
//!
//! This is the randomisation of SciPy's `qmc.Halton(scramble=True)` (A. B. Owen, *A
//! randomized Halton algorithm in R*, arXiv:1706.02808, 2017): in dimension j, with base
//! b = the j-th prime, each digit position k = 1, 2, ..., D of the radical inverse gets its
//! own independent, uniformly random permutation π_{j,k} of {0, ..., b−1}, applied to every
//! digit including the leading zeros of the index, so even index 0 maps to a random
//! point. The permutations do not depend on the higher digits (not a nested scramble).
//! D is the smallest number of digits with b^D ≥ 2^53, so the permuted digits fill an f64's
//! resolution; SciPy uses ⌈54/log2 b⌉ − 1 digits, which differs by at most one digit.

use std::collections::HashMap;

use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::{check_shape, first_primes, hash2, substream};
use crate::{Error, PointSet};

/// Largest dimension: the 100 000-th prime is 1 299 709, and bases below 2^22 keep the
/// exact integer arithmetic of a coordinate inside 128 bits.
pub const HALTON_SCRAMBLED_MAX_S: usize = 100_000;

/// Distinguishes the Halton permutations' random stream from other users of the seed.
const HALTON_LABEL: u64 = 0x4861_6c74_6f6e_5348;

/// The first `m` values of a uniformly random permutation of {0, ..., b−1}: the first m
/// steps of a forward Fisher–Yates shuffle, so a longer run extends a shorter one and
/// only the digit values that occur need be drawn. Large bases with few values keep the
/// displaced entries in a map instead of materialising all b of them; both paths consume
/// the generator identically and give the same values.
fn partial_permutation(b: u64, m: u64, rng: &mut Xoshiro256PlusPlus) -> Vec<u32> {
    if m.saturating_mul(4) >= b {
        let mut a: Vec<u32> = (0..b as u32).collect();
        for i in 0..m {
            let j = rng.random_range(i..b);
            a.swap(i as usize, j as usize);
        }
        a.truncate(m as usize);
        a
    } else {
        let mut displaced: HashMap<u64, u64> = HashMap::with_capacity(2 * m as usize);
        let mut out = Vec::with_capacity(m as usize);
        for i in 0..m {
            let j = rng.random_range(i..b);
            let vi = displaced.get(&i).copied().unwrap_or(i);
            let vj = displaced.get(&j).copied().unwrap_or(j);
            out.push(vj as u32);
            displaced.insert(j, vi);
        }
        out
    }
}

/// Smallest D with b^D ≥ 2^53.
fn digits_for_f64(b: u64) -> u32 {
    let target = 1u128 << 53;
    let mut d = 0;
    let mut power = 1u128;
    while power < target {
        power *= u128::from(b);
        d += 1;
    }
    d
}

/// One dimension of the scrambled sequence, indices 0..n−1.
fn column(n: usize, b: u64, seed: u64, j: usize) -> Vec<f64> {
    let depth = digits_for_f64(b);
    let big_b = u128::from(b);
    let label = hash2(HALTON_LABEL, j as u64);
    // Digit k of indices 0..n−1 takes the values 0..=(n−1)/b^(k−1) (capped at b−1); only
    // those entries of π_{j,k} are drawn.
    let last = (n - 1) as u128;
    let mut perms: Vec<Vec<u32>> = Vec::with_capacity(depth as usize);
    let mut place = 1u128;
    for k in 1..=depth {
        let m = (last / place + 1).min(big_b) as u64;
        let mut rng = substream(seed, label, u64::from(k));
        perms.push(partial_permutation(b, m, &mut rng));
        place = place.saturating_mul(big_b);
    }
    // tail[k] is the Horner value of π_k(0), ..., π_D(0) (digits k..D of an index whose
    // digits from k on are all zero); pow[k] = b^(D−k+1) scales the digits above them.
    let d = depth as usize;
    let mut tail = vec![0u128; d + 2];
    let mut pow = vec![1u128; d + 2];
    for k in (1..=d).rev() {
        pow[k] = pow[k + 1] * big_b;
        tail[k] = u128::from(perms[k - 1][0]) * pow[k + 1] + tail[k + 1];
    }
    let denominator = pow[1];
    let scale = (-53f64).exp2();
    (0..n as u64)
        .map(|i| {
            let mut idx = i;
            let mut head = 0u128;
            let mut k = 1usize;
            while idx > 0 {
                let digit = (idx % b) as usize;
                idx /= b;
                head = head * big_b + u128::from(perms[k - 1][digit]);
                k += 1;
            }
            let numerator = head * pow[k] + tail[k];
            // Truncate to the 2^−53 grid: exact integer arithmetic, and a value below 1.
            (((numerator << 53) / denominator) as u64) as f64 * scale
        })
        .collect()
}

/// Scrambled Halton points: indices 0..n−1, dimension j in the j-th prime base, every
/// digit position of every dimension permuted by an independent uniformly random
/// permutation drawn from `seed` (see the module notes), values truncated to multiples of
/// 2^−53 in [0, 1).
///
/// Each dimension keeps the van der Corput stratification: in base b, indices 0..b^k−1
/// put exactly one point in each interval \[i/b^k, (i+1)/b^k). The first n points of a
/// longer run with the same seed are the n-point run.
///
/// Refuses n = 0, s = 0, n > 2^53 and s > 100 000, naming the argument.
pub fn halton_scrambled(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    // Beyond 2^53 indices the D permuted digits would no longer hold every index.
    if n as u128 > 1u128 << 53 {
        return Err(Error::invalid(
            "n",
            n,
            "1..=2^53 for scrambled Halton points",
        ));
    }
    if s > HALTON_SCRAMBLED_MAX_S {
        return Err(Error::invalid(
            "s",
            s,
            format!("1..={HALTON_SCRAMBLED_MAX_S} for scrambled Halton points"),
        ));
    }
    let bases = first_primes(s);
    let columns: Vec<Vec<f64>> = bases
        .par_iter()
        .enumerate()
        .map(|(j, &b)| column(n, b, seed, j))
        .collect();
    let mut data = vec![0.0; n * s];
    for (j, col) in columns.iter().enumerate() {
        for (i, &x) in col.iter().enumerate() {
            data[i * s + j] = x;
        }
    }
    PointSet::new(n, s, data)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense and sparse shuffles, fed the same stream, give the same values, and every
    /// prefix is injective.
    #[test]
    fn sparse_and_dense_partial_permutations_agree() {
        for (b, m) in [(2u64, 2u64), (13, 5), (1223, 40), (7919, 7919)] {
            let dense = {
                let mut rng = substream(9, 1, b);
                let mut a: Vec<u32> = (0..b as u32).collect();
                for i in 0..m {
                    let j = rng.random_range(i..b);
                    a.swap(i as usize, j as usize);
                }
                a.truncate(m as usize);
                a
            };
            let mut rng = substream(9, 1, b);
            let got = partial_permutation(b, m, &mut rng);
            assert_eq!(got, dense, "b {b} m {m}");
            let mut sorted = got.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), m as usize);
            assert!(got.iter().all(|&v| u64::from(v) < b));
        }
    }

    #[test]
    fn digit_counts_reach_f64_resolution() {
        assert_eq!(digits_for_f64(2), 53);
        assert_eq!(digits_for_f64(3), 34);
        assert_eq!(digits_for_f64(1_299_709), 3);
    }
}
