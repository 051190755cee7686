//! The posterior of a shifted lattice and half its next doubling: the first 3m points of
//! an extensible lattice in radical-inverse order (m a power of two) are three cosets of
//! the lattice L_m of m points, shifted by 0, z/2m and z/4m. A shift-invariant kernel's
//! Gram matrix is then a 3×3 array of circulant blocks, which one discrete Fourier
//! transform of m per block column makes diagonal together: the likelihood and the
//! posterior are sums over the m frequencies of 3×3 Hermitian solves, O(m log m) per θ
//! as the whole lattice's ([`crate::posterior`]). It is what lets a Bayesian lattice
//! whose next doubling passes the budget take half of it (`quad`'s one short round of a
//! Bayesian rule), as [`crate::walsh`] does for the net.

use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

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

/// A Hermitian positive semidefinite 3×3 block as L·D·Lᴴ, L unit lower triangular; a
/// pivot at or below the floor leaves its direction out, as the whole lattice's route
/// leaves out eigenvalues below [`TINY`] of the largest.
pub(crate) struct Block {
    l: [[Complex<f64>; 3]; 3],
    pivots: [f64; 3],
}

impl Block {
    pub(crate) fn new(a: &[[Complex<f64>; 3]; 3], floor: f64) -> Block {
        let zero = Complex::new(0.0, 0.0);
        let mut l = [[zero; 3]; 3];
        let mut pivots = [0.0; 3];
        for i in 0..3 {
            let p = a[i][i].re - (0..i).map(|k| l[i][k].norm_sqr() * pivots[k]).sum::<f64>();
            l[i][i] = Complex::new(1.0, 0.0);
            if p <= floor {
                continue;
            }
            pivots[i] = p;
            for j in i + 1..3 {
                let s: Complex<f64> = (0..i).map(|k| l[j][k] * l[i][k].conj() * pivots[k]).sum();
                l[j][i] = (a[j][i] - s) / p;
            }
        }
        Block { l, pivots }
    }

    /// L⁻¹v.
    fn whiten(&self, v: &[Complex<f64>; 3]) -> [Complex<f64>; 3] {
        let mut w = [Complex::new(0.0, 0.0); 3];
        for i in 0..3 {
            w[i] = v[i] - (0..i).map(|k| self.l[i][k] * w[k]).sum::<Complex<f64>>();
        }
        w
    }

    /// vᴴ A⁺ v over the kept pivots.
    pub(crate) fn form(&self, v: &[Complex<f64>; 3]) -> f64 {
        let w = self.whiten(v);
        (0..3)
            .filter(|&i| self.pivots[i] > 0.0)
            .map(|i| (w[i].conj() * w[i]).re / self.pivots[i])
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
pub(crate) fn finish(
    log_det: f64,
    form: f64,
    ring: &[[f64; 3]; 3],
    v0: &[Complex<f64>; 3],
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
    let v: [f64; 3] = std::array::from_fn(|i| v0[i].re);
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

/// The values' transforms: each coset's values (in L_m's natural order) less the mean of
/// all, transformed.
fn transformed(y: &[f64], m: usize) -> Vec<Vec<Complex<f64>>> {
    let fft = FftPlanner::new().plan_fft_forward(m);
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    y.chunks_exact(m)
        .map(|coset| {
            let mut t: Vec<Complex<f64>> =
                coset.iter().map(|v| Complex::new(v - mean, 0.0)).collect();
            fft.process(&mut t);
            t
        })
        .collect()
}

/// The fit at decay table `table` (η_α(k/4m), k = 0..=2m) and θ of the three cosets'
/// transformed values `data`; `columns` holds [`DIFFERENCES`]'s work columns of m. The
/// dense Gaussian-process posterior's with the mean unknown ([`finish`]; the test).
fn fit_at(
    table: &[f64],
    theta: f64,
    z: &[u32],
    data: &[Vec<Complex<f64>>],
    columns: &mut [Vec<Complex<f64>>],
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
    let fft = FftPlanner::new().plan_fft_forward(m);
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
pub(crate) fn fit_over_frequencies(
    m: usize,
    factor: f64,
    floor: f64,
    ring: &[[f64; 3]; 3],
    block_at: impl Fn(usize) -> Block + Sync,
    values_at: impl Fn(usize) -> [Complex<f64>; 3] + Sync,
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
    let data = transformed(y, m);
    let table = decay_table(alpha, 4 * m);
    let mut columns = vec![vec![Complex::new(0.0, 0.0); m]; DIFFERENCES.len()];
    let (ln_theta, fit) = brent_minimum(
        |t| {
            let fit = fit_at(&table, t.exp(), z, &data, &mut columns);
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
        let fit = fit_at(&table, theta, &z, &transformed(&natural, m), &mut columns);
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
