//! The error of one scrambled Sobol' sequence as a Bayesian cubature sees it: f is taken
//! as a draw of a Gaussian process with a constant mean and a covariance that depends on
//! x ⊕ y, the digit-wise difference of two points, and the posterior of its integral given
//! the n values is normal around their mean (Jagadeeswaran and Hickernell 2022, "Fast
//! automatic Bayesian cubature using Sobol' sampling"; QMCPy's `CubBayesNetG`). On a
//! digital net in its natural order x_i ⊕ x_k is the net's point i ⊕ k less the shift, so
//! the Gram matrix is diagonal in the Walsh functions: its eigenvalues are one
//! Walsh–Hadamard transform, O(n log n) per θ tried, with no periodicity asked of f. That
//! is what a lattice's posterior ([`crate::posterior`]) cannot give an f that is steep at a
//! face of the cube (a lognormal input's quantile function written into it): the lattice
//! without the tent sees the jump between its faces and the tent lattice its kink.
//!
//! The kernel is K(x, y) = Π_j (1 + θ/10·ω(x_j ⊕ y_j)) with the order-1 Walsh kernel
//! ω(t) = 1 − 6·2^(⌊log₂ t⌋ − 1) (ω(0) = 1), θ over e^[−5, 0] as QMCPy searches it. The
//! points come Owen-scrambled, whose nested scramble keeps the net's strata but not its
//! group: the column is taken at x_i ⊕ x_0 on the points' first [`DIGITS`] digits, which
//! is the Gram matrix's column for a linearly scrambled net and measured to hold the
//! interval's level on the nested one (results/quad/bayes-net/bayes-net.md: 93.3–100 % at
//! level 0.95 over 300 seeds on four model families at 1 024–16 384 points). Half a
//! doubling past a net is three cosets of the net of half its points, whose posterior is
//! a 3×3 solve per Walsh frequency ([`crate::cosets`], results/quad/short-bayes).

use crate::cosets::{self, Block, CosetFit};
use crate::posterior::{brent_minimum, LogProduct, Posterior, LN_THETA, LN_THETA_TOL, TINY};

/// The digits of each coordinate the kernel reads: a sequence of at most 2^20 points
/// tells its points apart within its first 20 digits in every coordinate (each coordinate
/// of a 2^m net is stratified into 2^m intervals), and the ten more put the kernel of two
/// points within 1.5·2^−30 of its value at the exact coordinates.
pub const DIGITS: u32 = 30;

/// The kernel's scale is θ times this (QMCPy's `CubBayesNetG`, whose search for θ over
/// e^[−5, 0] it keeps).
const SCALE: f64 = 0.1;

/// The order-1 Walsh kernel ω at a difference whose first nonzero digit is digit
/// `DIGITS + 1 − b` (b the bit length of the difference's [`DIGITS`] digits as an
/// integer, ⌊log₂ t⌋ = b − 1 − DIGITS): ω = 1 − 1.5·2^(b − DIGITS), and 1 at b = 0 (the
/// same point).
fn omega(b: u8) -> f64 {
    if b == 0 {
        1.0
    } else {
        1.0 - 1.5 * libm::exp2(f64::from(b) - f64::from(DIGITS))
    }
}

/// For points in [0, 1)^d (row-major), the bit length of each coordinate's difference
/// from the sequence's first point `first` (d coordinates) on their first [`DIGITS`]
/// digits: what the kernel reads of point i's coordinate j ([`walsh_posterior`]'s
/// `lengths`).
pub fn digit_lengths(points: &[f64], first: &[f64]) -> Vec<u8> {
    let d = first.len();
    let digits = |x: f64| (x * f64::from(1u32 << DIGITS)) as u32;
    let first: Vec<u32> = first.iter().map(|&x| digits(x)).collect();
    points
        .chunks_exact(d)
        .flat_map(|row| {
            row.iter()
                .zip(&first)
                .map(|(&x, &x0)| (32 - (digits(x) ^ x0).leading_zeros()) as u8)
        })
        .collect()
}

/// The points a thread takes at once in the transform and the kernel's column: the
/// chunks are the same on any count of threads, and so are the sums over them, so the
/// posterior has the same bits on any.
const CHUNK: usize = 1 << 12;

/// The unnormalised Walsh–Hadamard transform in place: a_k ← Σ_i (−1)^popcount(i & k)·a_i,
/// n a power of two. The levels within a chunk of 2^12 run chunk by chunk, the others pair
/// the chunks of two halves, on the thread pool; each element sees the same additions in
/// the same order either way.
pub fn fwht(a: &mut [f64]) {
    use rayon::prelude::*;
    let n = a.len();
    let within = n.min(CHUNK);
    a.par_chunks_mut(within)
        .for_each(|c| fwht_levels(c, within));
    let mut h = within;
    while h < n {
        a.par_chunks_mut(2 * h).for_each(|block| {
            let (lo, hi) = block.split_at_mut(h);
            lo.par_chunks_mut(CHUNK)
                .zip(hi.par_chunks_mut(CHUNK))
                .for_each(|(lo, hi)| butterfly(lo, hi));
        });
        h *= 2;
    }
}

/// The transform's levels of pairs closer than `upto` within `a`.
fn fwht_levels(a: &mut [f64], upto: usize) {
    let mut h = 1;
    while h < upto {
        for block in a.chunks_exact_mut(2 * h) {
            let (lo, hi) = block.split_at_mut(h);
            butterfly(lo, hi);
        }
        h *= 2;
    }
}

/// (u, v) ← (u + v, u − v) elementwise.
fn butterfly(lo: &mut [f64], hi: &mut [f64]) {
    for (x, y) in lo.iter_mut().zip(hi.iter_mut()) {
        let (u, v) = (*x, *y);
        *x = u + v;
        *y = u - v;
    }
}

/// What the likelihood gives at one θ: its objective (the negative log-likelihood up to
/// constants) and the posterior standard deviation of the integral.
#[derive(Debug, Clone, Copy)]
struct Fit {
    objective: f64,
    sd: f64,
}

/// Σ ln(factor·l) over the kept `lambda` (above `floor`) and Σ p/l over the kept k > 0,
/// one [`CHUNK`] at a time.
fn chunk_sums(lambda: &[f64], power: &[f64], first: bool, floor: f64, factor: f64) -> (f64, f64) {
    let (mut logs, mut ratio) = (LogProduct::new(), 0.0);
    for (k, (&l, &p)) in lambda.iter().zip(power).enumerate() {
        if l <= floor {
            continue;
        }
        logs.push(factor * l);
        if !(first && k == 0) {
            ratio += p / l;
        }
    }
    (logs.ln(), ratio)
}

/// K(x_i, x_0) − 1 = Π_j (1 + c·ω_ij) − 1 into `column` for the points whose `lengths`
/// are given (d per point), `table` holding c·ω at each bit length, by the recurrence
/// k ← c·ω·(1 + k) + k, which keeps the small differences of a product near 1; the
/// largest |K − 1|.
fn kernel_column(table: &[f64], lengths: &[u8], d: usize, column: &mut [f64]) -> f64 {
    use rayon::prelude::*;
    column
        .par_chunks_mut(CHUNK)
        .zip(lengths.par_chunks(CHUNK * d))
        .map(|(out, rows)| {
            let (mut largest, len) = (0.0f64, out.len());
            // Each entry is a chain of d dependent steps, which one entry at a time
            // leaves waiting on the last; LANES entries side by side overlap their
            // chains, each entry's steps the same and in the same order (the same bits).
            let mut blocks = out.chunks_exact_mut(LANES);
            for (block, rows) in blocks.by_ref().zip(rows.chunks_exact(LANES * d)) {
                let mut k = [0.0; LANES];
                for j in 0..d {
                    for (l, k) in k.iter_mut().enumerate() {
                        *k += table[rows[l * d + j] as usize] * (1.0 + *k);
                    }
                }
                for (o, k) in block.iter_mut().zip(k) {
                    *o = k;
                    largest = largest.max(k.abs());
                }
            }
            let done = len - blocks.into_remainder().len();
            for (o, row) in out[done..].iter_mut().zip(rows[done * d..].chunks_exact(d)) {
                let mut k = 0.0;
                for &b in row {
                    k += table[b as usize] * (1.0 + k);
                }
                *o = k;
                largest = largest.max(k.abs());
            }
            largest
        })
        .reduce(|| 0.0, f64::max)
}

/// Entries of the kernel's column built side by side ([`kernel_column`]).
const LANES: usize = 8;

/// The fit at scale c = θ·[`SCALE`] of values whose squared transform is `power`, the
/// points' `lengths` ([`digit_lengths`], d per point); `column` and `lambda` are n-long
/// work buffers.
fn fit_at(c: f64, power: &[f64], lengths: &[u8], d: usize, buf: &mut [Vec<f64>; 2]) -> Fit {
    use rayon::prelude::*;
    let n = power.len();
    let [column, lambda] = buf;
    // c·ω for each bit length, looked up rather than computed per coordinate.
    let mut table = [0.0; DIGITS as usize + 1];
    for (b, t) in table.iter_mut().enumerate() {
        *t = c * omega(b as u8);
    }
    let largest = kernel_column(&table, lengths, d, column);
    let factor = if largest > 0.0 { largest } else { 1.0 };
    lambda
        .par_chunks_mut(CHUNK)
        .zip(column.par_chunks(CHUNK))
        .for_each(|(l, k)| l.iter_mut().zip(k).for_each(|(l, k)| *l = k / factor));
    fwht(lambda);
    let ring0 = lambda[0];
    // The all-ones part of the kernel adds n at frequency 0.
    lambda[0] += n as f64 / factor;
    let top = lambda
        .par_chunks_mut(CHUNK)
        .map(|c| {
            c.iter_mut().fold(0.0f64, |m, l| {
                *l = l.abs();
                m.max(*l)
            })
        })
        .reduce(|| 0.0, f64::max);
    let sums: Vec<(f64, f64)> = lambda
        .par_chunks(CHUNK)
        .zip(power.par_chunks(CHUNK))
        .enumerate()
        .map(|(i, (l, p))| chunk_sums(l, p, i == 0, TINY * top, factor))
        .collect();
    let (log_det, ratio) = sums
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let ratio = ratio / factor;
    let left = (factor * ring0 / (n as f64 + factor * ring0)).abs();
    Fit {
        objective: log_det + n as f64 * ratio.max(f64::MIN_POSITIVE).ln(),
        sd: (left * ratio / (n as f64 * n as f64)).sqrt(),
    }
}

/// The posterior of the integral of f from its values `y` at the first n points of a
/// scrambled Sobol' sequence in natural order, `lengths` those points' [`digit_lengths`] in
/// d coordinates: θ by maximum likelihood (Brent's method over ln θ in [−5, 0], as the
/// lattice's posterior searches it). `decay` is 1, the Walsh kernel's order. n is a power
/// of two (a net), or three times one, m = n/3 ≥ 2: half a doubling past a net, the net
/// of 2m points and the first half of its next doubling, three cosets of the net of m
/// ([`Posterior::cosets`] then holds the estimate's weights on their means). Its
/// `lengths` then cover the whole next doubling, 4m points (the last m are read, not
/// evaluated). `None` for values that are all equal, too few points or lengths that do
/// not match.
pub fn walsh_posterior(y: &[f64], lengths: &[u8], d: usize) -> Option<Posterior> {
    let n = y.len();
    let cosets = if n.is_power_of_two() { 1 } else { 3 };
    let m = n / cosets;
    if n < 4 || m * cosets != n || !m.is_power_of_two() || d == 0 {
        return None;
    }
    if lengths.len() != n.next_power_of_two() * d || y.iter().all(|v| *v == y[0]) {
        return None;
    }
    let (ln_theta, fit) = if cosets == 1 {
        let mut power = y.to_vec();
        fwht(&mut power);
        for p in power.iter_mut() {
            *p *= *p;
        }
        let mut buf = [vec![0.0; n], vec![0.0; n]];
        brent_minimum(
            |t| {
                let fit = fit_at(t.exp() * SCALE, &power, lengths, d, &mut buf);
                (fit.objective, (fit.sd, None))
            },
            LN_THETA,
            LN_THETA_TOL,
        )
    } else {
        let cosets = Cosets::new(y);
        let mut buf = vec![vec![0.0; m]; COSET_COLUMNS];
        brent_minimum(
            |t| {
                let fit = coset_fit_at(t.exp() * SCALE, &cosets, lengths, d, &mut buf);
                (fit.objective, (fit.sd, Some(fit.weights)))
            },
            LN_THETA,
            LN_THETA_TOL,
        )
    };
    let (sd, cosets) = fit;
    sd.is_finite().then_some(Posterior {
        sd,
        decay: 1.0,
        theta: ln_theta.exp(),
        cosets,
    })
}

/// The Gram matrix's columns three cosets of a net need: the kernel at x_i ⊕ x_0 ⊕ δ for
/// δ each coset's offset and the offset of the last two together (points q·m + r of the
/// doubling, q = 0..3).
const COSET_COLUMNS: usize = 4;

/// The values on the three cosets of a net of m points, each coset in the net's natural
/// order (the first 3m points of a digital sequence: point q·m + r is point r of the net
/// ⊕ the offset of coset q), less the mean of all, Walsh–Hadamard transformed
/// (unnormalised).
struct Cosets {
    transformed: Vec<Vec<f64>>,
    m: usize,
}

impl Cosets {
    fn new(y: &[f64]) -> Cosets {
        let m = y.len() / 3;
        let transformed = cosets::centred_transforms(y, m, |v| v, fwht);
        Cosets { transformed, m }
    }
}

/// The fit at scale c = θ·[`SCALE`] of values on three cosets of a net of m points,
/// `lengths` the [`digit_lengths`] of the whole doubling, 4m points (d per point); `buf`
/// holds [`COSET_COLUMNS`] work columns of m.
///
/// On a digital net the kernel of points i and j reads x_i ⊕ x_j, so the Gram matrix's
/// block of cosets a and b is the net's dyadic convolution by the kernel at x_r ⊕ x_0 ⊕
/// δ_{a⊕b} (point (a ⊕ b)·m + r), and one Walsh–Hadamard transform of m per column
/// makes every block diagonal together: the likelihood and the posterior are sums over
/// the m frequencies of 3×3 solves, finished as the lattice's cosets are
/// ([`cosets::finish`]: the mean unknown, the estimate weighted over the cosets).
fn coset_fit_at(
    c: f64,
    cosets: &Cosets,
    lengths: &[u8],
    d: usize,
    buf: &mut [Vec<f64>],
) -> CosetFit {
    use rayon::prelude::*;
    let m = cosets.m;
    let mut table = [0.0; DIGITS as usize + 1];
    for (b, t) in table.iter_mut().enumerate() {
        *t = c * omega(b as u8);
    }
    // K(x_{q·m + r}, x_0) − 1 for each column q.
    let mut largest = 0.0f64;
    for (q, column) in buf.iter_mut().enumerate() {
        let rows = &lengths[q * m * d..(q + 1) * m * d];
        largest = largest.max(kernel_column(&table, rows, d, column));
    }
    let factor = if largest > 0.0 { largest } else { 1.0 };
    for column in buf.iter_mut() {
        column.par_iter_mut().for_each(|v| *v /= factor);
        fwht(column);
    }
    // The all-ones part of the kernel adds m to every block at frequency 0.
    let top = buf[0]
        .iter()
        .fold(0.0f64, |t, l| t.max(l.abs()))
        .max(3.0 * m as f64 / factor + buf[0][0].abs());
    let floor = TINY * top;
    let buf = &*buf;
    // The blocks are real: a Walsh transform of a real column is real.
    let block_at = |k: usize| {
        let a: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| buf[i ^ j][k]));
        Block::new(&a, floor)
    };
    let values_at = |k: usize| -> [f64; 3] { std::array::from_fn(|a| cosets.transformed[a][k]) };
    let ring: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| buf[i ^ j][0]));
    cosets::fit_over_frequencies(m, factor, floor, &ring, block_at, values_at)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A digital net in natural order with a digital shift: point i's coordinate j is
    /// C_j·i ⊕ Δ_j on [`DIGITS`] digits, C_j upper triangular with ones on its diagonal
    /// (given by its columns' bit patterns, the first digit the top bit).
    fn shifted_net(m: u32, columns: &[[u32; 5]], shift: &[u32]) -> Vec<f64> {
        let n = 1usize << m;
        let mut x = Vec::with_capacity(n * columns.len());
        for i in 0..n {
            for (c, s) in columns.iter().zip(shift) {
                let mut v = 0u32;
                for (r, col) in c.iter().enumerate().take(m as usize) {
                    if i >> r & 1 == 1 {
                        v ^= col;
                    }
                }
                x.push(f64::from(v ^ s) / f64::from(1u32 << DIGITS));
            }
        }
        x
    }

    /// Column r's pattern: digit r + 1 set (the diagonal) and those of `above` that come
    /// before it (upper triangular, so the net's points are distinct).
    fn column(r: u32, above: u32) -> u32 {
        let diagonal = 1u32 << (DIGITS - 1 - r);
        let before = ((1u32 << DIGITS) - 1) & !(2 * diagonal - 1);
        diagonal | (above & before)
    }

    #[test]
    fn the_transform_is_the_walsh_sum() {
        let y: Vec<f64> = (0..16).map(|i| ((i * 7 + 3) % 11) as f64 - 4.5).collect();
        let mut a = y.clone();
        fwht(&mut a);
        for (k, a) in a.iter().enumerate() {
            let want: f64 = y
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    if (i & k).count_ones() % 2 == 0 {
                        *v
                    } else {
                        -*v
                    }
                })
                .sum();
            assert!((a - want).abs() < 1e-12, "k {k}: {a} vs {want}");
        }
        // Past a chunk, on the thread pool: the same bits as level after level on one.
        let n = 4 * CHUNK;
        let y: Vec<f64> = (0..n)
            .map(|i| ((i * 7919) % 1013) as f64 / 97.0 - 5.0)
            .collect();
        let (mut pooled, mut one) = (y.clone(), y);
        fwht(&mut pooled);
        fwht_levels(&mut one, n);
        assert_eq!(pooled, one);
    }

    #[test]
    fn omega_is_the_order_one_walsh_kernel() {
        // 1 − 6·2^(⌊log₂ t⌋ − 1) at t in [½, 1), [¼, ½), [2^−30, 2^−29).
        assert_eq!(omega(30), -0.5);
        assert_eq!(omega(29), 0.25);
        assert_eq!(omega(1), 1.0 - 1.5 * 2f64.powi(-29));
        let lengths = digit_lengths(&[0.25, 0.25, 0.8, 0.25 + 2f64.powi(-29)], &[0.25]);
        assert_eq!(lengths, vec![0, 0, 30, 2]);
    }

    /// A shifted digital net of 2^m points in 3 dimensions and a function's values there.
    fn test_net(m: u32) -> (Vec<f64>, Vec<f64>) {
        let d = 3;
        let columns: Vec<[u32; 5]> = [0x2a5u32, 0x1337, 0x0f0f]
            .iter()
            .map(|&p| std::array::from_fn(|r| column(r as u32, p.rotate_left(7 * r as u32))))
            .collect();
        let x = shifted_net(
            m,
            &columns,
            &[0x1234_5678 >> 2, 0x0abc_def0 >> 2, 0x3141_5926 >> 2],
        );
        let y: Vec<f64> = x
            .chunks_exact(d)
            .map(|p| {
                (2.0 * p[0]).sin() + p[1] * p[1] * p[2] + (-3.0 * p[2]).exp() / p[0].sqrt().max(0.1)
            })
            .collect();
        (x, y)
    }

    /// The kernel's Gram matrix of the first n points of `x` (d per point) at scale c,
    /// built point by point.
    fn gram(x: &[f64], n: usize, d: usize, c: f64) -> Vec<f64> {
        let digits = |v: f64| (v * f64::from(1u32 << DIGITS)) as u32;
        let kernel = |a: &[f64], b: &[f64]| {
            (0..d)
                .map(|j| {
                    let b = (32 - (digits(a[j]) ^ digits(b[j])).leading_zeros()) as u8;
                    1.0 + c * omega(b)
                })
                .product::<f64>()
        };
        let rows: Vec<&[f64]> = x.chunks_exact(d).collect();
        (0..n * n)
            .map(|e| kernel(rows[e / n], rows[e % n]))
            .collect()
    }

    #[test]
    fn the_walsh_posterior_is_the_dense_gaussian_process_posterior() {
        // On a shifted digital net of 32 points in 3 dimensions, at one θ: the transform's
        // likelihood and posterior against the Gram matrix built point by point and
        // solved by Cholesky.
        let (m, d, c) = (5u32, 3usize, 0.3);
        let n = 1usize << m;
        let (x, y) = test_net(m);
        let (sd, objective) = crate::posterior::tests::dense_posterior(&gram(&x, n, d, c), &y);

        let mut power = y.clone();
        fwht(&mut power);
        power.iter_mut().for_each(|p| *p *= *p);
        let lengths = digit_lengths(&x, &x[..d]);
        let mut buf = [vec![0.0; n], vec![0.0; n]];
        let fit = fit_at(c, &power, &lengths, d, &mut buf);
        assert!((fit.sd - sd).abs() < 1e-10 * sd, "{} vs {sd}", fit.sd);
        // The likelihood up to the constant n·ln n that the transform's scale adds.
        assert!(
            (fit.objective - objective).abs() < 1e-8,
            "{} vs {objective}",
            fit.objective
        );
    }

    #[test]
    fn three_cosets_of_a_net_take_the_dense_gaussian_process_posterior() {
        // The first 24 points of a net of 32 (the net of 16 and half its next doubling):
        // the blocks' likelihood, posterior and estimate against the dense Gram matrix of
        // those 24, the process's mean unknown.
        let (d, c) = (3usize, 0.3);
        let (x, y) = test_net(5);
        let lengths = digit_lengths(&x, &x[..d]);
        let (sd, objective, estimate) = cosets::tests::dense_gls(&gram(&x, 24, d, c), &y[..24]);
        let mut buf = vec![vec![0.0; 8]; COSET_COLUMNS];
        let fit = coset_fit_at(c, &Cosets::new(&y[..24]), &lengths, d, &mut buf);
        assert!((fit.sd - sd).abs() < 1e-10 * sd, "{} vs {sd}", fit.sd);
        assert!(
            (fit.objective - objective).abs() < 1e-8,
            "{} vs {objective}",
            fit.objective
        );
        let weighted: f64 = (0..3)
            .map(|a| fit.weights[a] * y[8 * a..8 * (a + 1)].iter().sum::<f64>() / 8.0)
            .sum();
        assert!(
            (weighted - estimate).abs() < 1e-12,
            "{weighted} vs {estimate}"
        );
        // Through the entry point: 24 values with the lengths of 32 points, θ fitted; the
        // lengths of 24 points alone are refused.
        let p = walsh_posterior(&y[..24], &lengths, d).unwrap();
        assert!(p.sd > 0.0 && p.sd.is_finite() && (0.0..=1.0).contains(&p.theta));
        assert!(p
            .cosets
            .is_some_and(|w| (w.iter().sum::<f64>() - 1.0).abs() < 1e-12));
        assert!(walsh_posterior(&y[..24], &lengths[..24 * d], d).is_none());
        assert!(walsh_posterior(&y[..20], &lengths, d).is_none());
        assert!(walsh_posterior(&y, &lengths, d).unwrap().cosets.is_none());
    }
}
