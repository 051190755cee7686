//! Sobol' points with Matoušek's random linear scramble and a digital shift (LMS +
//! shift), the randomisation of SciPy's `qmc.Sobol(scramble=True)` and QMCPy's
//! `DigitalNetB2`, for integration that extends a sequence in rounds.
//!
//! The net is [`super::sobol_plain`]'s (Joe–Kuo D6, natural order). Each dimension's
//! generator matrix C (32 columns, the direction numbers) is multiplied on the left by a
//! random lower-triangular matrix L with ones on its diagonal (64 rows, so the 32 digits
//! below the net's resolution become random linear functions of the point's digits), and
//! every point's 64 digits are XORed with one random shift per dimension:
//! x_i = L·C·digits(i) ⊕ Δ. A unit-diagonal L is invertible on every leading block of
//! digits, so each 2^m-point prefix stays a (t, m, s)-net with the net's t.
//!
//! Owen (*Variance with alternative scramblings of digital nets*, ACM TOMACS 13, 2003)
//! showed that this scramble has the same variance as the nested uniform scramble of
//! [`super::sobol_scrambled`] for every square-integrable integrand; it costs one XOR per
//! coordinate (the scrambled direction numbers are computed once), where nested
//! scrambling hashes every digit of every point. Their estimates differ in distribution
//! beyond the variance: a median of linearly scrambled replicates can converge faster
//! (Goda and Suzuki, 2025), and Loh's central limit theorem is proved for nested
//! scrambling only, which is why the sets the package hands out keep nested scrambling.

use super::sobol_owen::{check_sobol_shape, direction_numbers};
use super::{hash2, mix64};
use crate::{Error, PointSet};

/// Distinguishes this scramble's random bits from other users of the same seed (and from
/// the nested scramble's).
const LMS_LABEL: u64 = 0x4c4d_532b_5368_6966;

/// Index of the digital shift's hash beside L's 32 columns (indices 0..32).
const SHIFT_INDEX: u64 = 64;

/// One linear scramble plus digital shift of the Sobol' sequence in s dimensions: point
/// i of it is a pure function of i, so any range of indices is computed on its own.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearScrambledSobol {
    s: usize,
    /// `through[k·s + j]`: the XOR of dimension j's scrambled direction numbers 0..=k, what
    /// going from index i to i + 1 changes when i + 1 has k trailing zeros.
    through: Vec<u64>,
    /// `scrambled[k·s + j]`: dimension j's k-th scrambled direction number L·v_k, 64 bits,
    /// the 1/2 digit in bit 63.
    scrambled: Vec<u64>,
    /// One 64-bit digital shift per dimension.
    shift: Vec<u64>,
}

impl LinearScrambledSobol {
    /// The scramble of the s-dimensional sequence drawn from `seed`. Refuses s = 0 or
    /// s > 21 201, naming `s`.
    pub fn new(s: usize, seed: u64) -> Result<LinearScrambledSobol, Error> {
        check_sobol_shape(1, s)?;
        let dirs = direction_numbers(s);
        let bits = dirs[0].len();
        let key = hash2(mix64(seed), LMS_LABEL);
        let mut scrambled = vec![0u64; bits * s];
        let mut shift = vec![0u64; s];
        for (j, v) in dirs.iter().enumerate() {
            let dim_key = hash2(key, j as u64);
            // Column b of L (b = 0 is the 1/2 digit): its diagonal one in row b, uniform
            // random bits in the rows below it, zeros above.
            let columns: [u64; 32] = std::array::from_fn(|b| {
                let diagonal = 1u64 << (63 - b);
                diagonal | (hash2(dim_key, b as u64) & (diagonal - 1))
            });
            for (k, &vk) in v.iter().enumerate() {
                // L·v: the XOR of L's columns over v's set digits (bit 31 of v is digit 0).
                let mut rest = vk;
                let mut acc = 0;
                while rest != 0 {
                    let b = rest.leading_zeros();
                    acc ^= columns[b as usize];
                    rest &= !(1u32 << (31 - b));
                }
                scrambled[k * s + j] = acc;
            }
            shift[j] = hash2(dim_key, SHIFT_INDEX);
        }
        let mut through = scrambled.clone();
        for k in 1..bits {
            for j in 0..s {
                through[k * s + j] ^= through[(k - 1) * s + j];
            }
        }
        Ok(LinearScrambledSobol {
            s,
            through,
            scrambled,
            shift,
        })
    }

    /// The dimension s.
    pub fn s(&self) -> usize {
        self.s
    }

    /// The 64 scrambled digits of point `index` in every dimension (index < 2^32): the
    /// shift XORed with the scrambled direction numbers of index's set bits.
    fn digits(&self, index: usize, out: &mut [u64]) {
        out.copy_from_slice(&self.shift);
        let mut rest = index;
        while rest != 0 {
            let k = rest.trailing_zeros() as usize;
            for (o, &w) in out.iter_mut().zip(&self.scrambled[k * self.s..]) {
                *o ^= w;
            }
            rest &= rest - 1;
        }
    }

    /// Points start..start + count written row after row into `out` (count·s values, each
    /// the top 53 scrambled digits, in [0, 1)). Refuses a range reaching past 2^32 points
    /// (naming `count`) and an `out` of another length (naming `out`).
    pub fn fill(&self, start: usize, count: usize, out: &mut [f64]) -> Result<(), Error> {
        let s = self.s;
        let end = start.saturating_add(count);
        if count == 0 || end > super::SOBOL_MAX_N {
            return Err(Error::invalid(
                "count",
                count,
                format!(
                    "1 or more points ending at most at index {} (2^32)",
                    super::SOBOL_MAX_N
                ),
            ));
        }
        if out.len() != count * s {
            return Err(Error::invalid(
                "out",
                format!("{} values", out.len()),
                format!("count·s = {} values", count * s),
            ));
        }
        let scale = (-53f64).exp2();
        let mut current = vec![0u64; s];
        self.digits(start, &mut current);
        let mut rows = out.chunks_exact_mut(s);
        let first = rows.next().expect("count ≥ 1");
        for (o, &x) in first.iter_mut().zip(&current) {
            *o = (x >> 11) as f64 * scale;
        }
        for (i, row) in (start + 1..end).zip(rows) {
            let k = i.trailing_zeros() as usize;
            let step = &self.through[k * s..(k + 1) * s];
            for ((o, c), &w) in row.iter_mut().zip(current.iter_mut()).zip(step) {
                *c ^= w;
                *o = (*c >> 11) as f64 * scale;
            }
        }
        Ok(())
    }
}

/// The first n points of the Sobol' sequence under one linear scramble and digital shift
/// ([`LinearScrambledSobol`]) drawn from `seed`, row by row. Every 2^m-point prefix is a
/// (t, m, s)-net; the scramble is SciPy's kind (`qmc.Sobol(scramble=True)`), with other
/// random bits.
///
/// Refuses n = 0, s = 0, n > 2^32 and s > 21 201, naming the argument.
pub fn sobol_lms(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    check_sobol_shape(n, s)?;
    let seq = LinearScrambledSobol::new(s, seed)?;
    let mut data = vec![0.0; n * s];
    seq.fill(0, n, &mut data)?;
    PointSet::new(n, s, data)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scramble by its definition, one digit at a time: L as a 64 × 32 bit matrix
    /// (rows of digits), C from the direction numbers, the index's digits, then the shift.
    fn by_matrices(seed: u64, s: usize, index: usize) -> Vec<u64> {
        let dirs = direction_numbers(s);
        let key = hash2(mix64(seed), LMS_LABEL);
        (0..s)
            .map(|j| {
                let dim_key = hash2(key, j as u64);
                // l[r][b]: row r (output digit), column b (net digit).
                let l = |r: usize, b: usize| -> u64 {
                    if r < b {
                        0
                    } else if r == b {
                        1
                    } else {
                        (hash2(dim_key, b as u64) >> (63 - r)) & 1
                    }
                };
                // The net's digit b of point index: Σ_k C[b][k]·i_k mod 2.
                let net_digit = |b: usize| -> u64 {
                    (0..32)
                        .filter(|&k| (index >> k) & 1 == 1)
                        .map(|k| u64::from(dirs[j][k] >> (31 - b)) & 1)
                        .sum::<u64>()
                        & 1
                };
                let net: Vec<u64> = (0..32).map(net_digit).collect();
                let shift = hash2(dim_key, SHIFT_INDEX);
                (0..64).fold(0u64, |acc, r| {
                    let digit = (0..32).map(|b| l(r, b) & net[b]).sum::<u64>() & 1;
                    acc | ((digit ^ ((shift >> (63 - r)) & 1)) << (63 - r))
                })
            })
            .collect()
    }

    #[test]
    fn each_point_is_the_scrambled_matrix_times_its_index() {
        let (s, seed) = (4, 11);
        let seq = LinearScrambledSobol::new(s, seed).unwrap();
        for start in [0usize, 1, 5, 64, 1000, (1 << 31) + 7] {
            let mut out = vec![0.0; 3 * s];
            seq.fill(start, 3, &mut out).unwrap();
            for r in 0..3 {
                let want = by_matrices(seed, s, start + r);
                for j in 0..s {
                    let got = out[r * s + j];
                    assert_eq!(
                        got,
                        (want[j] >> 11) as f64 * (-53f64).exp2(),
                        "{start} {r} {j}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_range_is_the_prefix_s_rows_and_every_power_of_two_prefix_a_net() {
        let (s, seed) = (3, 5);
        let all = sobol_lms(1024, s, seed).unwrap();
        let seq = LinearScrambledSobol::new(s, seed).unwrap();
        for (start, count) in [(0, 1), (1, 1), (3, 61), (64, 64), (100, 924)] {
            let mut out = vec![0.0; count * s];
            seq.fill(start, count, &mut out).unwrap();
            assert_eq!(out, all.as_slice()[start * s..(start + count) * s]);
        }
        // One point per interval [k/2^m, (k+1)/2^m) in each dimension, and dimensions 1
        // and 2 a (0, m, 2)-net: one point in every elementary box of area 2^−m.
        for m in 0..=10u32 {
            let n = 1usize << m;
            for j in 0..s {
                let mut cells: Vec<usize> = (0..n)
                    .map(|i| (all.as_slice()[i * s + j] * n as f64) as usize)
                    .collect();
                cells.sort_unstable();
                assert_eq!(cells, (0..n).collect::<Vec<_>>(), "m = {m}, dimension {j}");
            }
            for a in 0..=m {
                let mut boxes: Vec<(usize, usize)> = (0..n)
                    .map(|i| {
                        let x = all.as_slice()[i * s];
                        let y = all.as_slice()[i * s + 1];
                        (
                            (x * (1 << a) as f64) as usize,
                            (y * (1 << (m - a)) as f64) as usize,
                        )
                    })
                    .collect();
                boxes.sort_unstable();
                boxes.dedup();
                assert_eq!(boxes.len(), n, "m = {m}, a = {a}");
            }
        }
    }

    #[test]
    fn its_variance_is_the_nested_scramble_s() {
        // Owen (2003): the same variance as nested uniform scrambling for every f. In one
        // dimension a scrambled (0, m, 1)-net puts one uniform point in each interval of
        // width 1/n, so the mean of x over n points has variance 1/(12 n^3) exactly.
        let n = 16;
        let seeds = 4000;
        let means: Vec<f64> = (0..seeds)
            .map(|seed| {
                sobol_lms(n, 2, seed)
                    .unwrap()
                    .as_slice()
                    .iter()
                    .step_by(2)
                    .sum::<f64>()
                    / n as f64
            })
            .collect();
        let mean = means.iter().sum::<f64>() / seeds as f64;
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (seeds - 1) as f64;
        let exact = 1.0 / (12.0 * (n as f64).powi(3));
        // The sample variance of 4 000 means has a relative sd of about √(2/4000) ≈ 2.2 %
        // for normal means (these are lighter-tailed); 10 % is over four of those.
        assert!((var / exact - 1.0).abs() < 0.10, "{var} against {exact}");
        assert!(
            (mean - 0.5).abs() < 4.0 * (exact / seeds as f64).sqrt(),
            "{mean}"
        );
        // In two dimensions against the nested scramble on a product, each variance from
        // 4 000 scrambles: equal within their sampling error.
        let product = |p: &PointSet| {
            p.as_slice()
                .chunks_exact(2)
                .map(|x| (x[0] - 0.3) * (x[1] - 0.6) + x[0] * x[0])
                .sum::<f64>()
                / p.n() as f64
        };
        let variance = |f: &dyn Fn(u64) -> f64| {
            let v: Vec<f64> = (0..seeds).map(f).collect();
            let m = v.iter().sum::<f64>() / seeds as f64;
            v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (seeds - 1) as f64
        };
        let linear = variance(&|seed| product(&sobol_lms(64, 2, seed).unwrap()));
        let nested =
            variance(&|seed| product(&super::super::sobol_scrambled(64, 2, seed).unwrap()));
        assert!(
            (linear / nested - 1.0).abs() < 0.15,
            "{linear} against {nested}"
        );
    }

    #[test]
    fn seeds_give_other_scrambles_and_bad_ranges_are_refused_by_name() {
        let a = sobol_lms(64, 3, 1).unwrap();
        let b = sobol_lms(64, 3, 2).unwrap();
        assert_ne!(a.as_slice(), b.as_slice());
        assert!(a.as_slice().iter().all(|&x| (0.0..1.0).contains(&x)));
        let seq = LinearScrambledSobol::new(3, 1).unwrap();
        let mut out = vec![0.0; 6];
        let e = seq
            .fill(super::super::SOBOL_MAX_N - 1, 2, &mut out)
            .unwrap_err();
        assert!(e.to_string().contains("count"), "{e}");
        let e = seq.fill(0, 0, &mut []).unwrap_err();
        assert!(e.to_string().contains("count"), "{e}");
        let e = seq.fill(0, 3, &mut out).unwrap_err();
        assert!(e.to_string().contains("out"), "{e}");
        let e = LinearScrambledSobol::new(0, 1).unwrap_err();
        assert!(e.to_string().contains('s'), "{e}");
        let e = sobol_lms(0, 2, 1).unwrap_err();
        assert!(e.to_string().contains('n'), "{e}");
    }
}
