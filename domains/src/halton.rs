//! The radical inverse, the coordinate function of the Halton sequence, and its prime
//! bases.
//!
//! One implementation for the whole workspace: the plain Halton start of the periodic cube
//! (`stillpoint::sequences::halton`) and the Halton-spread candidates of the implicit
//! regions both call [`radical_inverse`].

/// Radical inverse of `index` in base `base`: its base-b digits mirrored about the point,
/// so `radical_inverse(6, 2)` (110₂) is 0.011₂ = 3/8. In (0, 1) for `index ≥ 1`; 0 for
/// `index = 0`. Coordinate k (counting from 1) of the Halton point with index i is the
/// radical inverse of i in the k-th prime base.
///
/// The digits are gathered into one integer numerator over b^m and divided once, so the
/// result is the correctly rounded value whenever b^m ≤ 2^53 (every realistic n and s);
/// summing digit × b^(−j) term by term would round at every digit instead. `base` must be
/// at least 2.
pub fn radical_inverse(mut index: u64, base: u64) -> f64 {
    let b = u128::from(base);
    let mut numerator: u128 = 0;
    let mut denominator: u128 = 1;
    while index > 0 {
        numerator = numerator * b + u128::from(index % base);
        denominator *= b;
        index /= base;
    }
    numerator as f64 / denominator as f64
}

/// The first `k` primes in increasing order (2, 3, 5, 7, ...); empty for `k = 0`.
///
/// These are the Halton bases: dimension k (counting from 1) uses the k-th prime.
pub fn first_primes(k: usize) -> Vec<u64> {
    let mut primes: Vec<u64> = Vec::with_capacity(k);
    let mut candidate = 2u64;
    while primes.len() < k {
        // Trial division by the primes found so far suffices up to √candidate.
        if primes
            .iter()
            .take_while(|&&p| p * p <= candidate)
            .all(|&p| !candidate.is_multiple_of(p))
        {
            primes.push(candidate);
        }
        candidate += if candidate == 2 { 1 } else { 2 };
    }
    primes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirrors_the_digits() {
        assert_eq!(radical_inverse(0, 2), 0.0);
        assert_eq!(radical_inverse(1, 2), 0.5);
        assert_eq!(radical_inverse(6, 2), 0.375);
        assert_eq!(radical_inverse(1, 3), 1.0 / 3.0);
        assert_eq!(radical_inverse(5, 3), 7.0 / 9.0);
    }
}
