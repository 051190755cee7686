//! The posterior of a shifted lattice and half its next doubling: the first 3m points of
//! an extensible lattice in radical-inverse order (m a power of two) are three cosets of
//! the lattice L_m of m points, shifted by 0, z/2m and z/4m. A shift-invariant kernel's
//! Gram matrix is then a 3×3 array of circulant blocks, which one discrete Fourier
//! transform of m per block column makes diagonal together: the likelihood and the
//! posterior are sums over the m frequencies of 3×3 Hermitian solves, O(m log m) per θ
//! as the whole lattice's ([`crate::posterior`]). It is what lets a Bayesian lattice
//! whose next doubling passes the budget take half of it (`quad`'s one short round of a
//! Bayesian rule), as [`crate::walsh`] does for the net.

use std::ops::{Add, Div, Mul, Sub};

use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::posterior::{
    brent_minimum, decay_table, LogProduct, Posterior, DECAYS, LN_THETA, LN_THETA_TOL, TINY,
};

/// The cosets: L_m, L_m + z/2m and L_m + z/4m, their shifts in quarters of 1/m.
const OFFSETS: [i64; 3] = [0, 2, 1];

/// The blocks' first columns: the kernel at the lattice L_m shifted by these quarters of
/// 1/m, the differences of [`OFFSETS`] (block (0, 0), (0, 1), (0, 2), (1, 2)); the blocks
/// below the diagonal are their conjugates (the kernel is even).
const DIFFERENCES: [i64; 4] = [0, -2, -1, 1];

/// Which of [`DIFFERENCES`] block (a, b) reads, and whether conjugated.
fn block_column(a: usize, b: usize) -> (usize, bool) {
    let diff = OFFSETS[a] - OFFSETS[b];
    let at = |d: i64| DIFFERENCES.iter().position(|x| *x == d);
    match at(diff) {
        Some(q) => (q, false),
        None => (
            at(-diff).expect("every difference or its negative is listed"),
            true,
        ),
    }
}

/// The points a thread takes at once in the sums over frequencies: the same chunks, and
/// the same order of sums, on any count of threads.
const CHUNK: usize = 1 << 12;

/// An entry of a block: complex on the lattice's Fourier frequencies, real on the net's
/// Walsh frequencies (whose transform of a real column is real). A real entry takes the
/// operations a complex one with a zero imaginary part would, with the same bits (its
/// products, sums and quotients are the complex ones' real parts exactly), at a quarter
/// of the arithmetic.
pub(crate) trait Entry:
    Copy
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    fn conj(self) -> Self;
    fn norm_sqr(self) -> f64;
    fn re(self) -> f64;
}

impl Entry for f64 {
    const ZERO: f64 = 0.0;
    const ONE: f64 = 1.0;
    fn conj(self) -> f64 {
        self
    }
    fn norm_sqr(self) -> f64 {
        self * self
    }
    fn re(self) -> f64 {
        self
    }
}

impl Entry for Complex<f64> {
    const ZERO: Complex<f64> = Complex::new(0.0, 0.0);
    const ONE: Complex<f64> = Complex::new(1.0, 0.0);
    fn conj(self) -> Complex<f64> {
        Complex::conj(&self)
    }
    fn norm_sqr(self) -> f64 {
        Complex::norm_sqr(&self)
    }
    fn re(self) -> f64 {
        self.re
    }
}

/// Σ of the terms from [`Entry::ZERO`], in order (as `Complex`'s `Sum` adds them).
fn sum<T: Entry>(terms: impl Iterator<Item = T>) -> T {
    terms.fold(T::ZERO, |a, b| a + b)
}

/// A Hermitian positive semidefinite 3×3 block as L·D·Lᴴ, L unit lower triangular; a
/// pivot at or below the floor leaves its direction out, as the whole lattice's route
/// leaves out eigenvalues below [`TINY`] of the largest.
pub(crate) struct Block<T> {
    l: [[T; 3]; 3],
    pivots: [f64; 3],
}

impl<T: Entry> Block<T> {
    pub(crate) fn new(a: &[[T; 3]; 3], floor: f64) -> Block<T> {
        let mut l = [[T::ZERO; 3]; 3];
        let mut pivots = [0.0; 3];
        for i in 0..3 {
            let p = a[i][i].re() - (0..i).map(|k| l[i][k].norm_sqr() * pivots[k]).sum::<f64>();
            l[i][i] = T::ONE;
            if p <= floor {
                continue;
            }
            pivots[i] = p;
            for j in i + 1..3 {
                let s = sum((0..i).map(|k| l[j][k] * l[i][k].conj() * pivots[k]));
                l[j][i] = (a[j][i] - s) / p;
            }
        }
        Block { l, pivots }
    }

    /// L⁻¹v.
    fn whiten(&self, v: &[T; 3]) -> [T; 3] {
        let mut w = [T::ZERO; 3];
        for i in 0..3 {
            w[i] = v[i] - sum((0..i).map(|k| self.l[i][k] * w[k]));
        }
        w
    }

    /// vᴴ A⁺ v over the kept pivots.
    pub(crate) fn form(&self, v: &[T; 3]) -> f64 {
        let w = self.whiten(v);
        (0..3)
            .filter(|&i| self.pivots[i] > 0.0)
            .map(|i| (w[i].conj() * w[i]).re() / self.pivots[i])
            .sum()
    }

    pub(crate) fn push_logs(&self, logs: &mut LogProduct, factor: f64) {
        for &p in self.pivots.iter().filter(|p| **p > 0.0) {
            logs.push(factor * p);
        }
    }
}

/// The fit at one decay and θ: −2 log-likelihood up to constants, the posterior standard
/// deviation of the integral and the estimate's weights on the cosets' means.
pub(crate) struct CosetFit {
    pub(crate) objective: f64,
    pub(crate) sd: f64,
    pub(crate) weights: [f64; 3],
}

/// The fit from the sums over the frequencies 1..m (`log_det`: Σ ln det of the blocks,
/// `form`: Σ vᴴ A⁻¹ v of the centred values' transforms v), the block at frequency 0
/// without the kernel's all-ones part (`ring`, real), the centred values' transforms
/// there (`v0`), the kernel's scale `factor` (every block is divided by it), m and the
/// pivots' `floor`.
///
/// With the process's mean unknown (generalised least squares, as for the whole rule),
/// in the basis u₁ = 1/√3 and U, two orthonormal vectors summing to 0: the ones add
/// 3m/factor along u₁ only, so the block at frequency 0 is [[a + 3m/factor, bᵀ], [b, C]]
/// with a = u₁ᵀRu₁, b = UᵀRu₁, C = UᵀRU, and nothing cancels against m. Its determinant
/// is det C times S = a + 3m/factor − bᵀC⁺b; the centred values' norm there is
/// (Uᵀv)ᵀC⁺(Uᵀv); the estimate's weights on the cosets' means are (u₁ − UC⁺b)/√3; and
/// the posterior variance of the integral is s²·(1/1ᵀK⁻¹1 − 1) = s²·(a − bᵀC⁺b)/(3m/factor),
/// s² the norm over N = 3m. On a net the ring is nearly 0 (the net integrates the kernel's
/// Walsh functions), C's pivots fall below the floor and the weights go to 1/3 each.
pub(crate) fn finish<T: Entry>(
    log_det: f64,
    form: f64,
    ring: &[[f64; 3]; 3],
    v0: &[T; 3],
    factor: f64,
    m: usize,
    floor: f64,
) -> CosetFit {
    let ones = 3.0 * m as f64 / factor;
    let (r2, r3, r6) = (2f64.sqrt(), 3f64.sqrt(), 6f64.sqrt());
    let u1 = [1.0 / r3; 3];
    let u = [[1.0 / r2, -1.0 / r2, 0.0], [1.0 / r6, 1.0 / r6, -2.0 / r6]];
    let quad = |x: &[f64; 3], y: &[f64; 3]| -> f64 {
        (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| x[i] * ring[i][j] * y[j])
            .sum()
    };
    let a = quad(&u1, &u1);
    let b = [quad(&u[0], &u1), quad(&u[1], &u1)];
    let c = [
        [quad(&u[0], &u[0]), quad(&u[0], &u[1])],
        [quad(&u[1], &u[0]), quad(&u[1], &u[1])],
    ];
    // C = L·D·Lᵀ, a pivot at or below the floor left out.
    let d0 = if c[0][0] > floor { c[0][0] } else { 0.0 };
    let l10 = if d0 > 0.0 { c[1][0] / d0 } else { 0.0 };
    let d1 = c[1][1] - l10 * l10 * d0;
    let d1 = if d1 > floor { d1 } else { 0.0 };
    let pinv = |x: [f64; 2]| -> [f64; 2] {
        let w = [x[0], x[1] - l10 * x[0]];
        let z = [
            if d0 > 0.0 { w[0] / d0 } else { 0.0 },
            if d1 > 0.0 { w[1] / d1 } else { 0.0 },
        ];
        [z[0] - l10 * z[1], z[1]]
    };
    let cb = pinv(b);
    let ring_left = a - b[0] * cb[0] - b[1] * cb[1];
    let mut logs = LogProduct::new();
    for p in [d0, d1].into_iter().filter(|p| *p > 0.0) {
        logs.push(factor * p);
    }
    logs.push(factor * (ring_left + ones));
    let v: [f64; 3] = std::array::from_fn(|i| v0[i].re());
    let vu = [
        (0..3).map(|i| u[0][i] * v[i]).sum::<f64>(),
        (0..3).map(|i| u[1][i] * v[i]).sum::<f64>(),
    ];
    let cv = pinv(vu);
    let log_det = log_det + logs.ln();
    let form = form + vu[0] * cv[0] + vu[1] * cv[1];
    let n = (3 * m) as f64;
    let quad_form = form / (m as f64 * factor);
    let weights: [f64; 3] =
        std::array::from_fn(|i| (u1[i] - u[0][i] * cb[0] - u[1][i] * cb[1]) / r3);
    CosetFit {
        objective: log_det + n * (quad_form * n).max(f64::MIN_POSITIVE).ln(),
        sd: (quad_form / n * (ring_left / ones).abs()).sqrt(),
        weights,
    }
}

/// The values' transforms: each coset's m values (in its rule's natural order) less the
/// mean of all, as entries (`lift`), transformed in place (`transform`: the lattice's
/// Fourier transform, the net's Walsh–Hadamard transform).
pub(crate) fn centred_transforms<T>(
    y: &[f64],
    m: usize,
    lift: impl Fn(f64) -> T,
    transform: impl Fn(&mut [T]),
) -> Vec<Vec<T>> {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    y.chunks_exact(m)
        .map(|coset| {
            let mut t: Vec<T> = coset.iter().map(|v| lift(v - mean)).collect();
            transform(&mut t);
            t
        })
        .collect()
}

/// [`centred_transforms`] of the lattice's cosets, `fft` the forward transform of m.
fn transformed(y: &[f64], m: usize, fft: &dyn Fft<f64>) -> Vec<Vec<Complex<f64>>> {
    centred_transforms(y, m, |v| Complex::new(v, 0.0), |t| fft.process(t))
}

/// The fit at decay table `table` (η_α(k/4m), k = 0..=2m) and θ of the three cosets'
/// transformed values `data`; `columns` holds [`DIFFERENCES`]'s work columns of m, `fft`
/// the forward transform of m. The dense Gaussian-process posterior's with the mean
/// unknown ([`finish`]; the test).
fn fit_at(
    table: &[f64],
    theta: f64,
    z: &[u32],
    data: &[Vec<Complex<f64>>],
    columns: &mut [Vec<Complex<f64>>],
    fft: &dyn Fft<f64>,
) -> CosetFit {
    let m = data[0].len();
    let quarters = 4 * m as u64;
    let mask = quarters - 1;
    let fold = |k: u64| k.min(quarters - k) as usize;
    // K − 1 at point l of L_m shifted by `diff` quarters, Π_j (1 + θ·η) − 1 by the
    // recurrence k ← θη·(1 + k) + k, which keeps the small differences of a product near 1.
    let mut largest = 0.0f64;
    for (column, &diff) in columns.iter_mut().zip(&DIFFERENCES) {
        let top = column
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, out)| {
                let mut top = 0.0f64;
                for (i, o) in out.iter_mut().enumerate() {
                    let l = (c * CHUNK + i) as u64;
                    let at = (4 * l).wrapping_add(diff as u64) & mask;
                    let mut k = 0.0;
                    for &zj in z {
                        let t = theta * table[fold(at.wrapping_mul(zj as u64) & mask)];
                        k += t * (1.0 + k);
                    }
                    *o = Complex::new(k, 0.0);
                    top = top.max(k.abs());
                }
                top
            })
            .reduce(|| 0.0, f64::max);
        largest = largest.max(top);
    }
    let factor = if largest > 0.0 { largest } else { 1.0 };
    for column in columns.iter_mut() {
        column.par_iter_mut().for_each(|v| *v /= factor);
        fft.process(column);
    }
    // The all-ones part of the kernel adds m to every block at frequency 0.
    let ones = m as f64 / factor;
    let top = columns[0]
        .iter()
        .fold(0.0f64, |t, l| t.max(l.norm()))
        .max(3.0 * ones + columns[0][0].norm());
    let floor = TINY * top;
    let columns = &*columns;
    let block_at = |k: usize| {
        let a: [[Complex<f64>; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let (q, conj) = block_column(i, j);
                let v = columns[q][k];
                if conj {
                    v.conj()
                } else {
                    v
                }
            })
        });
        Block::new(&a, floor)
    };
    let values_at = |k: usize| -> [Complex<f64>; 3] { std::array::from_fn(|a| data[a][k]) };
    let ring: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| columns[block_column(i, j).0][0].re));
    fit_over_frequencies(m, factor, floor, &ring, block_at, values_at)
}

/// The fit from each frequency's block and values (the m frequencies of three cosets of
/// m points): Σ ln det and Σ vᴴA⁻¹v over the frequencies 1..m a chunk at a time (the same
/// chunks and the same order of sums on any count of threads), then [`finish`] with the
/// block at frequency 0 without the kernel's all-ones part, `ring`.
pub(crate) fn fit_over_frequencies<T: Entry>(
    m: usize,
    factor: f64,
    floor: f64,
    ring: &[[f64; 3]; 3],
    block_at: impl Fn(usize) -> Block<T> + Sync,
    values_at: impl Fn(usize) -> [T; 3] + Sync,
) -> CosetFit {
    let sums: Vec<(f64, f64)> = (0..m.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let (mut logs, mut form) = (LogProduct::new(), 0.0);
            for k in (chunk * CHUNK).max(1)..((chunk + 1) * CHUNK).min(m) {
                let block = block_at(k);
                block.push_logs(&mut logs, factor);
                form += block.form(&values_at(k));
            }
            (logs.ln(), form)
        })
        .collect();
    let (log_det, form) = sums
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    finish(log_det, form, ring, &values_at(0), factor, m, floor)
}

/// The posterior of the integral of f from its values `y` at the first 3m points of a
/// shifted extensible lattice with generator `z` (m a power of two, at least 2), given
/// coset by coset (the sequence's points 0..m, m..2m and 2m..3m: L_m, L_m + z/2m and
/// L_m + z/4m) and each in L_m's natural order: the kernel's decay α that the likelihood chooses on the whole
/// lattice of the first 2m points ([`crate::posterior::posterior`], its fast route: the
/// fit of the doubling before), then θ by maximum likelihood on all 3m, whose 3×3 solves
/// would cost five times as much over every decay. `None` for another count of values or
/// a constant y.
pub fn coset_posterior(y: &[f64], z: &[u32]) -> Option<Posterior> {
    let m = y.len() / 3;
    if m < 2 || 3 * m != y.len() || !m.is_power_of_two() || y.iter().all(|v| *v == y[0]) {
        return None;
    }
    // L_2m's natural order interleaves L_m and L_m + z/2m.
    let whole: Vec<f64> = (0..2 * m).map(|l| y[(l % 2) * m + l / 2]).collect();
    let alpha = crate::posterior::posterior(&whole, z).map_or(DECAYS[0], |p| p.decay);
    // One plan for the values and every θ tried.
    let fft = FftPlanner::new().plan_fft_forward(m);
    let data = transformed(y, m, fft.as_ref());
    let table = decay_table(alpha, 4 * m);
    let mut columns = vec![vec![Complex::new(0.0, 0.0); m]; DIFFERENCES.len()];
    let (ln_theta, fit) = brent_minimum(
        |t| {
            let fit = fit_at(&table, t.exp(), z, &data, &mut columns, fft.as_ref());
            (fit.objective, fit)
        },
        LN_THETA,
        LN_THETA_TOL,
    );
    fit.sd.is_finite().then_some(Posterior {
        sd: fit.sd,
        decay: alpha,
        theta: ln_theta.exp(),
        cosets: Some(fit.weights),
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The Gaussian-process posterior of the integral with the process's mean unknown,
    /// from the Gram matrix solved by Cholesky: (sd, −2 log-likelihood up to constants as
    /// [`finish`] counts it, the estimate m̂ = 1ᵀK⁻¹y/1ᵀK⁻¹1).
    pub(crate) fn dense_gls(gram: &[f64], y: &[f64]) -> (f64, f64, f64) {
        let n = y.len();
        let dense = crate::posterior::tests::Dense::new(gram, n);
        let k_ones = dense.solve(&vec![1.0; n]);
        let t: f64 = k_ones.iter().sum();
        let mean = y.iter().zip(&k_ones).map(|(a, b)| a * b).sum::<f64>() / t;
        let r: Vec<f64> = y.iter().map(|v| v - mean).collect();
        let quad_form = dense.form(&r);
        let sd = (quad_form / n as f64 * (1.0 / t - 1.0)).sqrt();
        let objective = dense.log_det() + n as f64 * (quad_form * n as f64).ln();
        (sd, objective, mean)
    }

    #[test]
    fn a_real_block_is_the_complex_block_of_its_values_bit_for_bit() {
        // Symmetric positive semidefinite 3×3 blocks (Gram matrices of three vectors, one
        // of them rank-deficient) and values: the real entries give the pivots, the
        // determinant's logarithms and the form of the complex entries with zero
        // imaginary parts, to the bit, as the net's real blocks claim.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for case in 0..200 {
            let vectors: [[f64; 4]; 3] = std::array::from_fn(|_| std::array::from_fn(|_| next()));
            let mut a = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    let (u, v) = (
                        vectors[i],
                        if case % 7 == 0 && j == 2 {
                            vectors[0]
                        } else {
                            vectors[j]
                        },
                    );
                    let w = if case % 7 == 0 && i == 2 {
                        vectors[0]
                    } else {
                        u
                    };
                    a[i][j] = (0..4).map(|k| w[k] * v[k]).sum::<f64>();
                }
            }
            let complex: [[Complex<f64>; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| Complex::new(a[i][j], 0.0)));
            let values: [f64; 3] = std::array::from_fn(|_| next());
            let floor = 1e-12;
            let (real, lifted) = (Block::new(&a, floor), Block::new(&complex, floor));
            assert_eq!(real.pivots, lifted.pivots, "case {case}");
            let (mut x, mut y) = (LogProduct::new(), LogProduct::new());
            real.push_logs(&mut x, 3.0);
            lifted.push_logs(&mut y, 3.0);
            assert_eq!(x.ln().to_bits(), y.ln().to_bits(), "case {case}");
            let v = values.map(|v| Complex::new(v, 0.0));
            assert_eq!(
                real.form(&values).to_bits(),
                lifted.form(&v).to_bits(),
                "case {case}"
            );
        }
    }

    #[test]
    fn three_cosets_of_a_lattice_take_the_dense_gaussian_process_posterior() {
        // The first 24 points of a shifted lattice sequence of 32 in 3 dimensions (the
        // lattice of 16 and half its next doubling), at one α and θ: the blocks'
        // likelihood and posterior against the Gram matrix of those 24 points built point
        // by point and solved by Cholesky.
        let (m, d) = (8usize, 3usize);
        let z = [1u32, 13, 21];
        let shift = [0.137, 0.612, 0.904];
        let (alpha, theta) = (2.5, 0.4);
        let table = decay_table(alpha, 4 * m);
        let eta = |t: f64| {
            // η_α(t) on the grid of 1/4m, t a multiple of it.
            let k = (t.rem_euclid(1.0) * (4 * m) as f64).round() as usize % (4 * m);
            table[k.min(4 * m - k)]
        };
        let radical = |i: usize| crate::posterior::natural_index(i, 4 * m) as f64 / (4 * m) as f64;
        // Sequence order: point i at frac(φ(i)·z + Δ); y at those points.
        let points: Vec<Vec<f64>> = (0..3 * m)
            .map(|i| {
                (0..d)
                    .map(|j| (radical(i) * f64::from(z[j]) + shift[j]).rem_euclid(1.0))
                    .collect()
            })
            .collect();
        let f = |p: &[f64]| (2.0 * p[0]).sin() + p[1] * p[1] * p[2] + (-3.0 * p[2]).exp();
        let y: Vec<f64> = points.iter().map(|p| f(p)).collect();
        let n = 3 * m;
        let gram: Vec<f64> = (0..n * n)
            .map(|e| {
                let (i, k) = (e / n, e % n);
                (0..d)
                    .map(|j| 1.0 + theta * eta((radical(i) - radical(k)) * f64::from(z[j])))
                    .product()
            })
            .collect();
        let (sd, objective, estimate) = dense_gls(&gram, &y);
        // The same values coset by coset, each in L_m's natural order.
        let mut natural = vec![0.0; n];
        for (i, v) in y.iter().enumerate() {
            let (a, r) = (i / m, i % m);
            natural[a * m + crate::posterior::natural_index(r, m)] = *v;
        }
        let mut columns = vec![vec![Complex::new(0.0, 0.0); m]; DIFFERENCES.len()];
        let fft = FftPlanner::new().plan_fft_forward(m);
        let data = transformed(&natural, m, fft.as_ref());
        let fit = fit_at(&table, theta, &z, &data, &mut columns, fft.as_ref());
        assert!((fit.sd - sd).abs() < 1e-10 * sd, "{} vs {sd}", fit.sd);
        assert!(
            (fit.objective - objective).abs() < 1e-8,
            "{} vs {objective}",
            fit.objective
        );
        let means: Vec<f64> = y
            .chunks_exact(m)
            .map(|c| c.iter().sum::<f64>() / m as f64)
            .collect();
        let weighted: f64 = fit.weights.iter().zip(&means).map(|(w, c)| w * c).sum();
        assert!(
            (weighted - estimate).abs() < 1e-12,
            "{weighted} vs {estimate}"
        );
        assert!((fit.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let p = coset_posterior(&natural, &z).unwrap();
        assert!(p.sd.is_finite() && p.sd > 0.0 && DECAYS.contains(&p.decay));
        assert!(coset_posterior(&natural[..20], &z).is_none());
    }
}
