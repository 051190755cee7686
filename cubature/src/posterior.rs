//! The error of one shifted rank-1 lattice rule as a Bayesian cubature sees it: f is taken
//! as a draw of a Gaussian process with a constant mean and a shift-invariant covariance,
//! and the posterior of its integral given the n values is normal around their mean
//! (Jagadeeswaran and Hickernell 2019, "Fast automatic Bayesian cubature using lattice
//! sampling"; QMCPy's `CubBayesLatticeG`). On a lattice in its natural order the Gram matrix
//! of such a kernel is circulant, so its eigenvalues are one FFT (of a real, even sequence:
//! half of one complex FFT of n/2 points), and every quantity below costs O(n log n) per θ
//! tried and O(n) more per output fitted at it.
//!
//! The kernel is K(x, y) = Π_j (1 + θ·η_α(x_j − y_j)) with
//! η_α(t) = Σ_{h ≠ 0} e^{2πiht}/|h|^α: a Sobolev space of periodic functions whose Fourier
//! coefficients decay like |h|^−α/2 (α = 2 and 4 are the Bernoulli kernels of order 1 and 2
//! that QMCPy takes). Its scale θ and decay α are chosen by maximum likelihood among
//! [`DECAYS`] (θ over e^[−5, 0], as QMCPy searches it): a rough integrand (Keister's
//! function of normal inputs) is fitted with a slow decay and priced as rough, a smooth one
//! (a Gaussian bump of normal inputs) with a fast decay, which a fixed order prices
//! wrongly one way or the other (results/quad/bayes-lattice/bayes-lattice.md: with α = 4
//! alone 82.5–91 % of the runs on Keister's function met their tolerance within it in four
//! of five cells, with α = 2 alone the bump took 2–4× the evaluations).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use stillpoint_domains::{vector_build, VectorBuild};

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// The kernel decays α the likelihood chooses among.
pub const DECAYS: [f64; 5] = [2.0, 2.5, 3.0, 3.5, 4.0];

/// The most values of η (points × coordinates) gathered once per decay rather than looked
/// up at every θ tried (32 MiB).
const GATHERED: usize = 1 << 22;

/// The range of ln θ searched (QMCPy's `CubBayesLatticeG`'s).
pub(crate) const LN_THETA: (f64, f64) = (-5.0, 0.0);

/// The search for ln θ stops within this of the optimum (SciPy's `fminbound` default
/// that QMCPy's search uses).
pub(crate) const LN_THETA_TOL: f64 = 1e-2;

/// Eigenvalues below this share of the largest are left out of the likelihood and the
/// norm (the kernel is numerically singular along them), as QMCPy leaves them out.
pub(crate) const TINY: f64 = 100.0 * f64::EPSILON;

/// What the likelihood chose and the posterior's standard deviation of the integral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Posterior {
    /// The posterior standard deviation of the integral (f's units).
    pub sd: f64,
    /// The kernel's decay α chosen.
    pub decay: f64,
    /// The kernel's scale θ chosen.
    pub theta: f64,
    /// Half a doubling past a whole rule ([`crate::cosets`]): the estimate's weights on
    /// the means of its three cosets (the sequence's points 0..m, m..2m, 2m..3m), which
    /// sum to 1; `None` for a whole lattice or net, whose estimate is the mean.
    pub cosets: Option<[f64; 3]>,
}

/// ζ(s, x) = Σ_{j ≥ 0} (x + j)^−s for s > 1 and x in (0, 1], by Euler–Maclaurin after
/// [`ZETA_TERMS`] terms (the decay table it builds is within 10⁻¹⁰ of the Bernoulli closed
/// forms at s = 2 and 4 and of the series summed directly at s = 3: the tests).
fn hurwitz_zeta(s: f64, x: f64) -> f64 {
    let mut sum = 0.0;
    for j in 0..ZETA_TERMS {
        sum += (x + j as f64).powf(-s);
    }
    let a = x + ZETA_TERMS as f64;
    // Σ_{j ≥ 0} (a + j)^−s = a^{1−s}/(s − 1) + a^−s/2 + Σ_k B_2k/(2k)!·(s)_{2k−1}·a^{−s−2k+1}
    let mut tail = a.powf(1.0 - s) / (s - 1.0) + 0.5 * a.powf(-s);
    let mut rising = s; // s(s + 1)…(s + 2k − 2)
    let mut power = a.powf(-s - 1.0);
    for (k, b) in [1.0 / 6.0, -1.0 / 30.0, 1.0 / 42.0].iter().enumerate() {
        let factorial = [2.0, 24.0, 720.0][k];
        tail += b / factorial * rising * power;
        rising *= (s + 2.0 * k as f64 + 1.0) * (s + 2.0 * k as f64 + 2.0);
        power /= a * a;
    }
    sum + tail
}

/// Terms summed before Euler–Maclaurin's tail in [`hurwitz_zeta`].
const ZETA_TERMS: usize = 8;

/// Chebyshev nodes of the smooth part of the folded series ([`FoldedTail`]): its
/// singularities lie at x = −1 and 2, five half-widths of [0, ½] from its centre, so the
/// interpolant's error falls like (5 + √24)^−N = 9.9^−N; 20 nodes stay within 10⁻¹⁴ of
/// the Euler–Maclaurin sums they replace (the test; 16 miss by 2·10⁻¹⁴ at α = 3).
const TAIL_NODES: usize = 20;

/// T(x) = ζ(α, 1 + x) + ζ(α, 2 − x) on [0, ½], the part of the folded series
/// n^α·c_q = x^−α + (1 − x)^−α + T(x) (x = q/n) left once its two nearest terms are taken
/// out: analytic there, so a Chebyshev interpolant of [`hurwitz_zeta`] replaces the two
/// Euler–Maclaurin sums (twenty powers) per frequency with one short recurrence.
struct FoldedTail {
    coefficients: [f64; TAIL_NODES],
}

impl FoldedTail {
    fn new(alpha: f64) -> FoldedTail {
        let pi = std::f64::consts::PI;
        let node = |k: usize| (pi * (k as f64 + 0.5) / TAIL_NODES as f64).cos();
        let values: Vec<f64> = (0..TAIL_NODES)
            .map(|k| {
                let x = (node(k) + 1.0) / 4.0;
                hurwitz_zeta(alpha, 1.0 + x) + hurwitz_zeta(alpha, 2.0 - x)
            })
            .collect();
        let mut coefficients = [0.0; TAIL_NODES];
        for (j, c) in coefficients.iter_mut().enumerate() {
            let sum: f64 = (0..TAIL_NODES)
                .map(|k| values[k] * (pi * j as f64 * (k as f64 + 0.5) / TAIL_NODES as f64).cos())
                .sum();
            *c = 2.0 * sum / TAIL_NODES as f64;
        }
        coefficients[0] /= 2.0;
        FoldedTail { coefficients }
    }

    /// T(x) for x in [0, ½] (Clenshaw's recurrence on t = 4x − 1), four at a time: the
    /// recurrence is a chain of dependent steps, and four chains side by side fill the
    /// lanes one chain leaves idle.
    fn at(&self, x: [f64; 4]) -> [f64; 4] {
        let t = x.map(|x| 4.0 * x - 1.0);
        let (mut b1, mut b2) = ([0.0; 4], [0.0; 4]);
        for c in self.coefficients.iter().skip(1).rev() {
            for l in 0..4 {
                let b0 = 2.0 * t[l] * b1[l] - b2[l] + c;
                b2[l] = b1[l];
                b1[l] = b0;
            }
        }
        std::array::from_fn(|l| t[l] * b1[l] - b2[l] + self.coefficients[0])
    }
}

/// The discrete Fourier transform of real sequences of one even length n by a complex
/// transform of n/2 (even and odd samples packed as one complex sequence) and one pass of
/// twiddles computed once: every transform a posterior takes (the values', each decay's
/// table, the kernel at every θ tried) is of a real sequence at the same n, and its
/// second half is the first's conjugate, so half a transform carries all of it.
struct RealDft {
    n: usize,
    half: Arc<dyn Fft<f64>>,
    /// e^{−2πik/n} for k = 0..=n/2.
    twiddles: Vec<Complex<f64>>,
}

impl RealDft {
    /// [`RealDft::new`], kept for the process where n ≤ [`SHARED_N`].
    fn shared(n: usize) -> Arc<RealDft> {
        static DFTS: OnceLock<Mutex<HashMap<usize, Arc<RealDft>>>> = OnceLock::new();
        if n > SHARED_N {
            return Arc::new(RealDft::new(n));
        }
        // A map another thread left by panicking still holds only whole entries.
        let mut dfts = DFTS
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        Arc::clone(dfts.entry(n).or_insert_with(|| Arc::new(RealDft::new(n))))
    }

    /// The transform for n, a power of two of at least 4.
    fn new(n: usize) -> RealDft {
        let half = FftPlanner::new().plan_fft_forward(n / 2);
        let twiddles = (0..=n / 2)
            .map(|k| {
                let (s, c) = (-2.0 * std::f64::consts::PI * k as f64 / n as f64).sin_cos();
                Complex::new(c, s)
            })
            .collect();
        RealDft { n, half, twiddles }
    }

    /// The work space of one thread's transforms at this n, made once and reused: a
    /// transform of 2^19 points otherwise maps fresh pages for megabytes each time.
    fn buffers(&self) -> Buffers {
        let h = self.n / 2;
        Buffers {
            column: vec![0.0; h + 1],
            half: vec![Complex::new(0.0, 0.0); h],
            scratch: vec![Complex::new(0.0, 0.0); self.half.get_inplace_scratch_len()],
            lambda: vec![0.0; h + 1],
        }
    }

    /// X_k = Σ_i x_i·e^{−2πiik/n} for k = 0..=n/2 of the real sequence x_i = `x(i)`,
    /// i = 0..n (the rest are the conjugates X_{n−k}), each handed to `put(k, X_k)`;
    /// `half` and `scratch` from [`RealDft::buffers`]. Inlined, so that its passes take
    /// the vector registers of the caller's build ([`Kernel::new`]).
    #[inline(always)]
    fn transform(
        &self,
        x: impl Fn(usize) -> f64,
        half: &mut [Complex<f64>],
        scratch: &mut [Complex<f64>],
        mut put: impl FnMut(usize, Complex<f64>),
    ) {
        let h = self.n / 2;
        for (m, z) in half.iter_mut().enumerate() {
            *z = Complex::new(x(2 * m), x(2 * m + 1));
        }
        self.half.process_with_scratch(half, scratch);
        // X_k = E_k + w^k·O_k, E and O the transforms of the even and odd samples, read
        // off Z_k and Z_{h−k} (Z_h = Z_0).
        for k in 0..=h {
            let a = half[if k == h { 0 } else { k }];
            let b = half[if k == 0 { 0 } else { h - k }].conj();
            let even = (a + b) * 0.5;
            let d = (a - b) * 0.5;
            let odd = Complex::new(d.im, -d.re);
            put(k, even + self.twiddles[k] * odd);
        }
    }

    /// [`RealDft::transform`] into a new vector.
    fn forward(&self, x: impl Fn(usize) -> f64) -> Vec<Complex<f64>> {
        let Buffers {
            mut half,
            mut scratch,
            ..
        } = self.buffers();
        let mut out = vec![Complex::new(0.0, 0.0); self.n / 2 + 1];
        self.transform(x, &mut half, &mut scratch, |k, c| out[k] = c);
        out
    }

    /// The transform of the real even sequence x_i = x_{n−i} given by its first half
    /// (`x(i)` for i = 0..=n/2): real and even, so its first half too.
    fn even(&self, x: impl Fn(usize) -> f64) -> Vec<f64> {
        let n = self.n;
        self.forward(|i| x(i.min(n - i)))
            .iter()
            .map(|c| c.re)
            .collect()
    }
}

/// One thread's work space for [`RealDft`] and [`Kernel`] at one n.
struct Buffers {
    /// The kernel's first column, its first half.
    column: Vec<f64>,
    /// The half-length complex sequence transformed in place.
    half: Vec<Complex<f64>>,
    /// The FFT's scratch.
    scratch: Vec<Complex<f64>>,
    /// The kernel's eigenvalues, their first half.
    lambda: Vec<f64>,
}

/// η_α(k/n) for k = 0..=n/2 (η is even: η_α(k/n) = η_α((n − k)/n)): the Fourier series
/// Σ_{h ≠ 0} e^{2πihk/n}/|h|^α folded onto the n frequencies the lattice sees,
/// c_q = Σ_{h ≡ q mod n, h ≠ 0} |h|^−α (two Hurwitz zeta values, their smooth part
/// interpolated by Chebyshev), then one transform. `n` a power of two of at least 4.
pub fn decay_table(alpha: f64, n: usize) -> Vec<f64> {
    half_decay_table(alpha, &RealDft::new(n))
}

/// The largest n whose transform and decay tables a process keeps once made
/// ([`RealDft::shared`], [`shared_decay_table`]): every fit at an n it has seen (a
/// doubling of a later run, another output's or another index's fit) reads them again,
/// the same numbers, where making them was a fifth of a fit's work at 2^13 points. At
/// most 5 tables and one transform per power of two up to 2^16, about 3 MB.
const SHARED_N: usize = 1 << 16;

/// [`half_decay_table`] kept for the process where n ≤ [`SHARED_N`].
fn shared_decay_table(alpha: f64, dft: &RealDft) -> Arc<Vec<f64>> {
    type Tables = Mutex<HashMap<(u64, usize), Arc<Vec<f64>>>>;
    static TABLES: OnceLock<Tables> = OnceLock::new();
    if dft.n > SHARED_N {
        return Arc::new(half_decay_table(alpha, dft));
    }
    let key = (alpha.to_bits(), dft.n);
    // A map another thread left by panicking still holds only whole entries.
    let lock = || {
        TABLES
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    };
    if let Some(t) = lock().get(&key) {
        return Arc::clone(t);
    }
    // Made outside the lock: two threads may both make it, the same numbers.
    let made = Arc::new(half_decay_table(alpha, dft));
    Arc::clone(lock().entry(key).or_insert(made))
}

/// [`decay_table`] at the transform's n.
fn half_decay_table(alpha: f64, dft: &RealDft) -> Vec<f64> {
    let n = dft.n;
    let scale = (n as f64).powf(-alpha);
    let tail = FoldedTail::new(alpha);
    // x^−α: every decay of DECAYS is a whole number of halves, x^−k·(1/√x)^(2α−2k), a
    // fifth of a general power's cost, which the table's two per frequency dominate.
    let halves = 2.0 * alpha;
    let power = |x: f64| {
        if halves.fract() == 0.0 && halves <= 16.0 {
            let k = (halves / 2.0).floor();
            let p = x.powi(-(k as i32));
            if halves as i32 % 2 == 1 {
                p / x.sqrt()
            } else {
                p
            }
        } else {
            x.powf(-alpha)
        }
    };
    let mut c = vec![0.0; n / 2 + 4];
    for (chunk, q0) in c.chunks_exact_mut(4).zip((0..).step_by(4)) {
        let x: [f64; 4] = std::array::from_fn(|l| ((q0 + l) as f64 / n as f64).min(0.5));
        for ((v, x), t) in chunk.iter_mut().zip(x).zip(tail.at(x)) {
            *v = (power(x) + power(1.0 - x) + t) * scale;
        }
    }
    c[0] = 2.0 * hurwitz_zeta(alpha, 1.0) * scale;
    dft.even(|q| c[q])
}

/// The posterior of the integral of f from its values `y` at the n = 2^m points of one
/// shifted rank-1 lattice with generator `z`, in its natural order (`y[i]` at
/// frac(i·z/n + Δ)), θ and α by maximum likelihood. `None` for fewer than 4 points or a
/// constant y.
pub fn posterior(y: &[f64], z: &[u32]) -> Option<Posterior> {
    let n = y.len();
    if n < 4 || !n.is_power_of_two() || y.iter().all(|v| *v == y[0]) {
        return None;
    }
    let dft = RealDft::shared(n);
    let power = power_spectrum(y, &dft);
    let index = decay_index(n, z);
    use rayon::prelude::*;
    // Each decay's fit on its own thread (the same numbers on any count of threads).
    let fits: Vec<(f64, Posterior)> = DECAYS
        .par_iter()
        .map(|&alpha| {
            let table = shared_decay_table(alpha, &dft);
            let d = z.len();
            let gathered = gather(&table, n, d, &index, None);
            let rows = n / 2 + 1;
            let mut buffers = dft.buffers();
            let mut fit = |ln_theta: f64| {
                let theta = ln_theta.exp();
                let b = &mut buffers;
                let eta = |i, j| table[index(i, j)];
                Fit::new(Eta::new(d, eta, &gathered, rows), theta, &power, &dft, b)
            };
            let (ln_theta, at) = brent_minimum(
                |t| {
                    let at = fit(t);
                    (at.objective, at)
                },
                LN_THETA,
                LN_THETA_TOL,
            );
            let found = Posterior {
                sd: at.sd(),
                decay: alpha,
                theta: ln_theta.exp(),
                cosets: None,
            };
            (at.objective, found)
        })
        .collect();
    first_best(fits)
}

/// The first of the fits with the least objective (in the order given: of [`DECAYS`]).
fn first_best(fits: impl IntoIterator<Item = (f64, Posterior)>) -> Option<Posterior> {
    let mut best: Option<(f64, Posterior)> = None;
    for (objective, found) in fits {
        if best.as_ref().is_none_or(|(o, _)| objective < *o) {
            best = Some((objective, found));
        }
    }
    best.map(|(_, p)| p)
}

/// |ŷ_k|² for k = 0..=n/2, the squared discrete Fourier transform of the real values
/// (|ŷ_{n−k}| = |ŷ_k|).
fn power_spectrum(y: &[f64], dft: &RealDft) -> Vec<f64> {
    dft.forward(|i| y[i]).iter().map(|c| c.norm_sqr()).collect()
}

/// Each coordinate's index into the half decay table at point i of n: i·z_j mod n,
/// folded onto 0..=n/2 (η is even).
fn decay_index(n: usize, z: &[u32]) -> impl Fn(usize, usize) -> usize + Sync + '_ {
    let mask = (n - 1) as u64;
    move |i, j| {
        let k = ((i as u64).wrapping_mul(z[j] as u64) & mask) as usize;
        k.min(n - k)
    }
}

/// η (times each coordinate's weight, if any) at the points i = 0..=n/2 (the kernel's
/// first column is even: point n − i is point i reflected) and every coordinate,
/// coordinate-major (`[j·(n/2 + 1) + i]`: the kernel's column reads neighbouring points
/// of one coordinate together), gathered once when they fit in [`GATHERED`] values
/// (every fit reads them; the same numbers), else empty and looked up at each fit.
fn gather(
    table: &[f64],
    n: usize,
    d: usize,
    index: &impl Fn(usize, usize) -> usize,
    weights: Option<&[f64]>,
) -> Vec<f64> {
    let rows = n / 2 + 1;
    if rows * d > GATHERED {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(rows * d);
    for j in 0..d {
        let w = weights.map_or(1.0, |w| w[j]);
        out.extend((0..rows).map(|i| {
            let eta = table[index(i, j)];
            if weights.is_some() {
                w * eta
            } else {
                eta
            }
        }));
    }
    out
}

/// The kernel's eigenvalues at one θ, and what the likelihood and the posterior read from
/// them.
struct Fit {
    /// −2 log-likelihood with the process's scale profiled out, up to a constant:
    /// Σ ln λ_k + n·ln(Σ_{k ≥ 1} |ŷ_k|²/λ_k).
    objective: f64,
    /// 1 − n/λ_0: the share of the prior variance of the integral the points leave.
    left: f64,
    /// Σ_{k ≥ 1} |ŷ_k|²/λ_k/n²: the squared norm of f − mean in the kernel's space per
    /// point.
    norm: f64,
}

/// Steps of the grid of ln θ over [−5, 0] on which [`posteriors`] fits every output
/// at once (a step of 0.25).
pub const GRID_STEPS: usize = 20;

/// The posteriors of many outputs at the same n = 2^m points of one shifted rank-1
/// lattice (`ys[o]` output o's values in its natural order), each with its own α and θ by
/// maximum likelihood, θ on a grid of [`GRID_STEPS`] + 1 values of ln θ rather than by a
/// search per output: every output fitted at a θ shares the kernel's eigenvalues, so the
/// O(n·d) kernel is built (|DECAYS|)·([`GRID_STEPS`] + 1) times whatever the count of
/// outputs. The kernel is `Π_c (1 + θ·weights[c]·η_α(x_c))`: a weight scales coordinate c's
/// roughness (0 drops it). `None` for an output that is constant (or fewer than 4 points).
pub fn posteriors(ys: &[Vec<f64>], z: &[u32], weights: &[f64]) -> Vec<Option<Posterior>> {
    let Some(n) = ys.first().map(Vec::len) else {
        return Vec::new();
    };
    if n < 4 || !n.is_power_of_two() {
        return vec![None; ys.len()];
    }
    let dft = RealDft::shared(n);
    let powers: Vec<Option<Vec<f64>>> = ys
        .iter()
        .map(|y| {
            debug_assert_eq!(y.len(), n);
            let constant = y.iter().all(|v| *v == y[0]);
            (!constant).then(|| power_spectrum(y, &dft))
        })
        .collect();
    let d = z.len();
    let index = decay_index(n, z);
    use rayon::prelude::*;
    // Per decay, each output's best (objective, posterior) over the grid of θ.
    let per_decay: Vec<Vec<Option<(f64, Posterior)>>> = DECAYS
        .par_iter()
        .map(|&alpha| {
            let table = shared_decay_table(alpha, &dft);
            let gathered = gather(&table, n, d, &index, Some(weights));
            let rows = n / 2 + 1;
            let mut best: Vec<Option<(f64, Posterior)>> = vec![None; ys.len()];
            let mut buffers = dft.buffers();
            for step in 0..=GRID_STEPS {
                let ln_theta =
                    LN_THETA.0 + (LN_THETA.1 - LN_THETA.0) * step as f64 / GRID_STEPS as f64;
                let theta = ln_theta.exp();
                let eta = |i, j| weights[j] * table[index(i, j)];
                let eta = Eta::new(d, eta, &gathered, rows);
                let kernel = Kernel::new(eta, theta, &dft, &mut buffers);
                for (power, slot) in powers.iter().zip(best.iter_mut()) {
                    let Some(power) = power else { continue };
                    let at = kernel.fit(power);
                    if slot.as_ref().is_none_or(|(o, _)| at.objective < *o) {
                        let found = Posterior {
                            sd: at.sd(),
                            decay: alpha,
                            theta,
                            cosets: None,
                        };
                        *slot = Some((at.objective, found));
                    }
                }
            }
            best
        })
        .collect();
    // Per output, the first of the best in the order of DECAYS.
    (0..ys.len())
        .map(|o| first_best(per_decay.iter().filter_map(|fits| fits[o])))
        .collect()
}

/// The decay kernel η_α at the coordinates of the points i = 0..=n/2 (against point 0), as
/// the kernel's column reads it: the values [`gather`] made, coordinate-major, or, where it
/// made none, looked up per point and coordinate.
enum Eta<'a, F> {
    Gathered {
        d: usize,
        values: &'a [f64],
        rows: usize,
    },
    Lookup {
        d: usize,
        eta: F,
    },
}

impl<'a, F: Fn(usize, usize) -> f64> Eta<'a, F> {
    /// The gathered `values` (`rows` per coordinate) when there are any, else `eta(i, j)`.
    fn new(d: usize, eta: F, values: &'a [f64], rows: usize) -> Eta<'a, F> {
        if values.is_empty() {
            Eta::Lookup { d, eta }
        } else {
            Eta::Gathered { d, values, rows }
        }
    }

    /// The kernel's first column K(x_i, x_0) − 1 for i = 0..=n/2 into `column`, built as
    /// Π(1 + θη) − 1 one coordinate at a time so that a product near 1 keeps its digits
    /// (the column is even in i, so its first half). Each entry is a chain of d dependent
    /// steps; [`COLUMN_LANES`] entries side by side fill the lanes one chain leaves idle,
    /// in vector registers where the processor has them ([`vector_build`]): the same
    /// operations in the same order per entry, so the same bits on every build.
    fn column(&self, theta: f64, column: &mut [f64]) {
        match *self {
            Eta::Gathered { d, values, rows } => {
                debug_assert_eq!(column.len(), rows);
                match vector_build() {
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: the processor has AVX-512 F (checked by `vector_build`).
                    VectorBuild::Avx512 => unsafe { column_avx512(d, values, theta, column) },
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: the processor has AVX2 (checked by `vector_build`).
                    VectorBuild::Avx2 => unsafe { column_avx2(d, values, theta, column) },
                    _ => column_lanes(d, values, theta, column),
                }
            }
            Eta::Lookup { d, ref eta } => {
                for (i, v) in column.iter_mut().enumerate() {
                    let mut a = 0.0;
                    for j in 0..d {
                        a += theta * eta(i, j) * (1.0 + a);
                    }
                    *v = a;
                }
            }
        }
    }
}

/// Entries of the kernel's column built side by side ([`Eta::column`]).
const COLUMN_LANES: usize = 8;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn column_avx512(d: usize, values: &[f64], theta: f64, column: &mut [f64]) {
    column_lanes(d, values, theta, column)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn column_avx2(d: usize, values: &[f64], theta: f64, column: &mut [f64]) {
    column_lanes(d, values, theta, column)
}

/// [`Eta::column`] from gathered values, `column.len()` of them per coordinate: each block
/// of [`COLUMN_LANES`] entries over every coordinate (lane by lane, so that the compiler
/// keeps the block in vectors; Rust fuses no multiply and add, so each lane rounds as one
/// entry alone would), then the last entries one by one.
#[inline(always)]
fn column_lanes(d: usize, values: &[f64], theta: f64, column: &mut [f64]) {
    let rows = column.len();
    let mut blocks = column.chunks_exact_mut(COLUMN_LANES);
    for (b, block) in blocks.by_ref().enumerate() {
        let i0 = b * COLUMN_LANES;
        let mut acc = [0.0; COLUMN_LANES];
        for j in 0..d {
            let eta: &[f64; COLUMN_LANES] = values[j * rows + i0..j * rows + i0 + COLUMN_LANES]
                .try_into()
                .expect("a block of the lanes' width");
            for l in 0..COLUMN_LANES {
                acc[l] += theta * eta[l] * (1.0 + acc[l]);
            }
        }
        block.copy_from_slice(&acc);
    }
    let start = rows - blocks.into_remainder().len();
    for (i, v) in column.iter_mut().enumerate().skip(start) {
        let mut a = 0.0;
        for j in 0..d {
            a += theta * values[j * rows + i] * (1.0 + a);
        }
        *v = a;
    }
}

/// What the likelihood reads of the kernel's eigenvalues λ_k at one θ (divided by
/// `factor`; λ_{n−k} = λ_k, so k = 0..=n/2), which every output fitted at that θ shares.
struct Kernel<'a> {
    n: usize,
    /// 2/λ_k (1/λ_{n/2} at n/2) for the kept frequencies k = 1..=n/2 and 0 for the others
    /// and k = 0: the likelihood's weights of the values' squared transform, the
    /// eigenvalues below [`TINY`] of the largest left out.
    weights: &'a [f64],
    factor: f64,
    /// The transform of the first column at frequency 0 (before the all-ones part).
    ring0: f64,
    /// Σ ln(factor·λ_k) over the kept frequencies of 0..n, which every output fitted at
    /// this θ shares.
    log_det: f64,
}

/// The posteriors multiply eigenvalues together and take one logarithm of the product
/// whenever it leaves these bounds of 1: a kept eigenvalue is at least [`TINY`] of the
/// largest and at most n times the column's largest entry (the lattice's: at least
/// [`TINY`], the largest at least 1, and, but λ_0, at most n), so no product passes the
/// range of a double.
const PRODUCT_BOUND: f64 = 1e150;

/// Σ ln x over the factors pushed, as the logarithms of running products flushed at
/// [`PRODUCT_BOUND`]: one logarithm per few hundred factors rather than one each.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogProduct {
    logs: f64,
    product: f64,
}

impl LogProduct {
    pub(crate) fn new() -> LogProduct {
        LogProduct {
            logs: 0.0,
            product: 1.0,
        }
    }

    pub(crate) fn push(&mut self, x: f64) {
        self.product *= x;
        if !(1.0 / PRODUCT_BOUND..PRODUCT_BOUND).contains(&self.product) {
            self.logs += self.product.ln();
            self.product = 1.0;
        }
    }

    pub(crate) fn ln(self) -> f64 {
        self.logs + self.product.ln()
    }
}

/// What [`Kernel::new`] builds the eigenvalues from.
struct At<'b, F> {
    eta: Eta<'b, F>,
    theta: f64,
    dft: &'b RealDft,
}

/// [`Kernel::build`] compiled for a target feature (`unsafe`: the caller checks that the
/// processor has it).
macro_rules! kernel_with_feature {
    ($name:ident, $feature:literal) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name<F: Fn(usize, usize) -> f64>(
            at: At<'_, F>,
            buffers: &'a mut Buffers,
        ) -> Kernel<'a> {
            Kernel::build(at, buffers)
        }
    };
}

impl<'a> Kernel<'a> {
    /// The eigenvalues at θ for the transform's n points, `eta` the decay kernel at each
    /// point's coordinates (against point 0), read for i = 0..=n/2; built in `buffers`
    /// (from [`RealDft::buffers`]), which hold them while it lives.
    fn new<F: Fn(usize, usize) -> f64>(
        eta: Eta<'_, F>,
        theta: f64,
        dft: &RealDft,
        buffers: &'a mut Buffers,
    ) -> Kernel<'a> {
        // Its passes over the n/2 eigenvalues (scaling, magnitudes, the likelihood's
        // weights) in vector registers where the processor has them: element by element,
        // so the same bits on every build.
        let at = At { eta, theta, dft };
        match vector_build() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the processor has AVX-512 F (checked by `vector_build`).
            VectorBuild::Avx512 => unsafe { Kernel::new_avx512(at, buffers) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the processor has AVX2 (checked by `vector_build`).
            VectorBuild::Avx2 => unsafe { Kernel::new_avx2(at, buffers) },
            _ => Kernel::build(at, buffers),
        }
    }

    kernel_with_feature!(new_avx512, "avx512f");
    kernel_with_feature!(new_avx2, "avx2");

    /// [`Kernel::new`]'s body.
    #[inline(always)]
    fn build<F: Fn(usize, usize) -> f64>(at: At<'_, F>, buffers: &'a mut Buffers) -> Kernel<'a> {
        let At { eta, theta, dft } = at;
        let n = dft.n;
        let Buffers {
            column,
            half,
            scratch,
            lambda,
        } = buffers;
        eta.column(theta, column);
        let largest = column.iter().map(|c| c.abs()).fold(0.0, f64::max);
        // The eigenvalues divided by `largest` (the all-ones part adds n at frequency 0).
        let factor = if largest > 0.0 { largest } else { 1.0 };
        for c in column.iter_mut() {
            *c /= factor;
        }
        let column = &*column;
        dft.transform(
            |i| column[i.min(n - i)],
            half,
            scratch,
            |k, c| lambda[k] = c.re,
        );
        let ring0 = lambda[0];
        lambda[0] += n as f64 / factor;
        let mut top = 0.0f64;
        for l in lambda.iter_mut() {
            *l = l.abs();
            top = top.max(*l);
        }
        let h = n / 2;
        let keep = |l: f64| l > TINY * top;
        // Frequencies 1..n/2 stand for themselves and their mirrors n − k.
        let twice = |k: usize| if k == h { 1.0 } else { 2.0 };
        // Σ ln(factor·λ_k) over the kept k of 0..n, as logarithms of products.
        let (mut logs, mut count) = (LogProduct::new(), 0.0);
        for (k, &l) in lambda.iter().enumerate() {
            if !keep(l) {
                continue;
            }
            let times = if k == 0 { 1.0 } else { twice(k) };
            count += times;
            logs.push(if times == 2.0 { l * l } else { l });
        }
        let log_det = logs.ln() + count * factor.ln();
        // The eigenvalues are read once more, as the ratio's weights, in their place.
        for (k, l) in lambda.iter_mut().enumerate() {
            *l = if k > 0 && keep(*l) {
                twice(k) / *l
            } else {
                0.0
            };
        }
        Kernel {
            n,
            weights: lambda,
            factor,
            ring0,
            log_det,
        }
    }

    /// The likelihood and posterior of values whose squared transform is `power`
    /// (k = 0..=n/2).
    fn fit(&self, power: &[f64]) -> Fit {
        let (factor, n) = (self.factor, self.n);
        let ratio: f64 = power
            .iter()
            .zip(self.weights)
            .map(|(p, w)| p * w)
            .sum::<f64>()
            / factor;
        let objective = self.log_det + n as f64 * ratio.max(f64::MIN_POSITIVE).ln();
        Fit {
            objective,
            left: (factor * self.ring0 / (n as f64 + factor * self.ring0)).abs(),
            norm: ratio / (n as f64 * n as f64),
        }
    }
}

impl Fit {
    /// The fit at θ for the transform's n points in d coordinates, `eta(i, j)` the decay
    /// kernel at point i's coordinate j (against point 0) and `power` the values' squared
    /// transform.
    fn new<F: Fn(usize, usize) -> f64>(
        eta: Eta<'_, F>,
        theta: f64,
        power: &[f64],
        dft: &RealDft,
        buffers: &mut Buffers,
    ) -> Fit {
        Kernel::new(eta, theta, dft, buffers).fit(power)
    }

    /// The posterior standard deviation of the integral: √(left·norm).
    fn sd(&self) -> f64 {
        (self.left * self.norm).sqrt()
    }
}

/// The minimum of a unimodal g on [lo, hi] to within about `tol`, by Brent's method
/// (golden-section steps, and a parabola through the three best points whenever it falls
/// well inside the bracket): the argument and what g gave there (`g(x).0` is minimised;
/// the rest is kept so that the point found need not be evaluated again). SciPy's
/// `fminbound`, which QMCPy's search calls, is this method. On Keister's function of
/// normal inputs it took 13 evaluations a search on average against the golden
/// section's 15 (10 at α = 2, where the optimum lies inside the range; an optimum at an
/// end is approached in steps of the tolerance).
pub(crate) fn brent_minimum<T>(
    mut g: impl FnMut(f64) -> (f64, T),
    (lo, hi): (f64, f64),
    tol: f64,
) -> (f64, T) {
    // The golden section's shorter part, and the least step relative to |x| (√ε).
    let golden = (3.0 - 5f64.sqrt()) / 2.0;
    let relative = f64::EPSILON.sqrt();
    let (mut a, mut b) = (lo, hi);
    // x the best point so far, w the second best, v the third (the one w displaced).
    let mut x = a + golden * (b - a);
    let mut best = g(x);
    let (mut w, mut v) = (x, x);
    let (mut fw, mut fv) = (best.0, best.0);
    // The step taken last and the one before it.
    let (mut step, mut before) = (0.0f64, 0.0f64);
    loop {
        let middle = (a + b) / 2.0;
        let tol1 = relative * x.abs() + tol / 3.0;
        let tol2 = 2.0 * tol1;
        if (x - middle).abs() <= tol2 - (b - a) / 2.0 {
            return (x, best.1);
        }
        let mut parabolic = false;
        if before.abs() > tol1 {
            let r = (x - w) * (best.0 - fv);
            let q = (x - v) * (best.0 - fw);
            let mut p = (x - v) * q - (x - w) * r;
            let mut q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let older = before;
            before = step;
            // The parabola's step is taken when it is less than half the step before last
            // and lands inside the bracket.
            if p.abs() < (q * older / 2.0).abs() && p > q * (a - x) && p < q * (b - x) {
                step = p / q;
                parabolic = true;
                let u = x + step;
                if u - a < tol2 || b - u < tol2 {
                    step = if middle >= x { tol1 } else { -tol1 };
                }
            }
        }
        if !parabolic {
            before = if x >= middle { a - x } else { b - x };
            step = golden * before;
        }
        let u = x + if step.abs() >= tol1 {
            step
        } else if step >= 0.0 {
            tol1
        } else {
            -tol1
        };
        let at = g(u);
        if at.0 <= best.0 {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, best.0);
            x = u;
            best = at;
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if at.0 <= fw || w == x {
                (v, fv) = (w, fw);
                (w, fw) = (u, at.0);
            } else if at.0 <= fv || v == x || v == w {
                (v, fv) = (u, at.0);
            }
        }
    }
}

/// The natural order of the first n = 2^m points of an extensible lattice in radical-
/// inverse order: point k of the sequence is point rev_m(k) of the lattice frac(i·z/n + Δ).
pub fn natural_index(k: usize, n: usize) -> usize {
    let m = n.trailing_zeros();
    if m == 0 {
        0
    } else {
        k.reverse_bits() >> (usize::BITS - m)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// η at α = 2 and 4 in closed form: 2π²B₂(t) and −(2π⁴/3)B₄(t).
    fn bernoulli(alpha: f64, t: f64) -> f64 {
        let pi = std::f64::consts::PI;
        if alpha == 2.0 {
            2.0 * pi * pi * (t * t - t + 1.0 / 6.0)
        } else {
            -(2.0 * pi.powi(4) / 3.0) * (t.powi(4) - 2.0 * t.powi(3) + t * t - 1.0 / 30.0)
        }
    }

    #[test]
    fn the_decay_table_is_the_bernoulli_kernel_at_two_and_four() {
        for alpha in [2.0, 4.0] {
            for n in [8, 64, 1024] {
                let table = decay_table(alpha, n);
                for (k, v) in table.iter().enumerate() {
                    let want = bernoulli(alpha, k as f64 / n as f64);
                    assert!(
                        (v - want).abs() < 1e-10,
                        "α {alpha}, n {n}, k {k}: {v} vs {want}"
                    );
                }
            }
        }
        // Between them, the series summed directly (to |h| = 10⁶, tail below 10⁻⁸).
        for alpha in [2.5, 3.0, 3.5] {
            let table = decay_table(alpha, 16);
            for (k, v) in table.iter().enumerate() {
                let t = k as f64 / 16.0;
                let direct: f64 = (1..1_000_000)
                    .map(|h| {
                        let angle = 2.0 * std::f64::consts::PI * h as f64 * t;
                        2.0 * angle.cos() / (h as f64).powf(alpha)
                    })
                    .sum();
                assert!(
                    (v - direct).abs() < 1e-8,
                    "α {alpha}, k {k}: {v} vs {direct}"
                );
            }
        }
    }

    #[test]
    fn the_folded_tail_is_the_two_zeta_values_it_interpolates() {
        for alpha in DECAYS {
            let tail = FoldedTail::new(alpha);
            for i in 0..=1000 {
                let x = i as f64 / 2000.0;
                let want = hurwitz_zeta(alpha, 1.0 + x) + hurwitz_zeta(alpha, 2.0 - x);
                let got = tail.at([x; 4])[0];
                assert!(
                    (got - want).abs() < 1e-14 * want,
                    "α {alpha}, x {x}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn the_real_transform_is_the_discrete_fourier_transform() {
        // Against the sum written out, for a sequence with no symmetry and for an even one.
        for n in [4usize, 8, 64, 256] {
            let dft = RealDft::new(n);
            let x = |i: usize| ((i * i) as f64 * 0.37).sin() + 0.1 * i as f64;
            let direct = |k: usize, x: &dyn Fn(usize) -> f64| {
                (0..n).fold(Complex::new(0.0, 0.0), |acc, i| {
                    let angle = -2.0 * std::f64::consts::PI * (i * k % n) as f64 / n as f64;
                    acc + Complex::new(angle.cos(), angle.sin()) * x(i)
                })
            };
            let got = dft.forward(x);
            assert_eq!(got.len(), n / 2 + 1);
            for (k, g) in got.iter().enumerate() {
                let want = direct(k, &x);
                assert!(
                    (g - want).norm() < 1e-10 * n as f64,
                    "n {n}, k {k}: {g} vs {want}"
                );
            }
            let even = |i: usize| (i.min(n - i) as f64 * 0.9).cos();
            let got = dft.even(|i| (i as f64 * 0.9).cos());
            for (k, g) in got.iter().enumerate() {
                let want = direct(k, &even);
                assert!(want.im.abs() < 1e-10 * n as f64);
                assert!(
                    (g - want.re).abs() < 1e-10 * n as f64,
                    "n {n}, k {k}: {g} vs {want}"
                );
            }
        }
    }

    #[test]
    fn the_natural_index_puts_the_sequence_on_its_lattice() {
        use stillpoint_sequences::{ExtensibleLattice, SequenceTable};
        let (d, n) = (3, 64usize);
        let seq = ExtensibleLattice::with_table(SequenceTable::FirstOrder, d, 5, 0).unwrap();
        let mut x = vec![0.0; n * d];
        seq.fill_folding(0, n, &vec![false; d], &mut x).unwrap();
        let z = seq.generator();
        let shift = seq.shift();
        for k in 0..n {
            let i = natural_index(k, n);
            for j in 0..d {
                let want = ((i as u64 * z[j] as u64 % n as u64) as f64 / n as f64 + shift[j]) % 1.0;
                assert!((x[k * d + j] - want).abs() < 1e-12, "k {k}, j {j}");
            }
        }
    }

    /// A Gram matrix (row-major, n×n) factored by Cholesky, for the transforms' posteriors
    /// to be checked against.
    pub(crate) struct Dense {
        l: Vec<f64>,
        n: usize,
    }

    impl Dense {
        pub(crate) fn new(gram: &[f64], n: usize) -> Dense {
            let mut l = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..=i {
                    let s: f64 = (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum();
                    l[i * n + j] = if i == j {
                        (gram[i * n + i] - s).sqrt()
                    } else {
                        (gram[i * n + j] - s) / l[j * n + j]
                    };
                }
            }
            Dense { l, n }
        }

        /// K⁻¹b.
        pub(crate) fn solve(&self, b: &[f64]) -> Vec<f64> {
            let (l, n) = (&self.l, self.n);
            let mut w = b.to_vec();
            for i in 0..n {
                w[i] = (w[i] - (0..i).map(|k| l[i * n + k] * w[k]).sum::<f64>()) / l[i * n + i];
            }
            for i in (0..n).rev() {
                w[i] = (w[i] - (i + 1..n).map(|k| l[k * n + i] * w[k]).sum::<f64>()) / l[i * n + i];
            }
            w
        }

        /// bᵀK⁻¹b.
        pub(crate) fn form(&self, b: &[f64]) -> f64 {
            b.iter().zip(self.solve(b)).map(|(a, c)| a * c).sum()
        }

        pub(crate) fn log_det(&self) -> f64 {
            (0..self.n).map(|i| 2.0 * self.l[i * self.n + i].ln()).sum()
        }
    }

    /// A Gaussian process's posterior written out densely, for the transforms' to be
    /// checked against: with `gram` the Gram matrix (row-major) of the points where f took
    /// the values `y`, (the posterior standard deviation of the integral, the negative
    /// log-likelihood up to the constant n·ln n that a transform's scale adds), by
    /// Cholesky.
    pub(crate) fn dense_posterior(gram: &[f64], y: &[f64]) -> (f64, f64) {
        let n = y.len();
        let dense = Dense::new(gram, n);
        let mean = y.iter().sum::<f64>() / n as f64;
        let centred: Vec<f64> = y.iter().map(|v| v - mean).collect();
        let quad_form = dense.form(&centred);
        let ones_k_ones: f64 = gram.iter().sum();
        let log_det = dense.log_det();
        let left = 1.0 - (n * n) as f64 / ones_k_ones;
        let sd = (left * quad_form / n as f64).sqrt();
        (sd, log_det + n as f64 * (quad_form * n as f64).ln())
    }

    #[test]
    fn the_fft_posterior_is_the_dense_gaussian_process_posterior() {
        // On 32 lattice points in 3 dimensions, at one θ and α: the circulant route's
        // likelihood and posterior against the Gram matrix built point by point and
        // solved by Cholesky.
        let (n, d) = (32usize, 3usize);
        let z = [1u32, 13, 21];
        let x: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..d)
                    .map(|j| ((i as u64 * z[j] as u64) % n as u64) as f64 / n as f64)
                    .collect()
            })
            .collect();
        let y: Vec<f64> = x
            .iter()
            .map(|p| (2.0 * p[0]).sin() + p[1] * p[1] * p[2] + (6.0 * p[2]).cos())
            .collect();
        let (alpha, theta) = (2.0, 0.3);
        let kernel = |a: &[f64], b: &[f64]| {
            (0..d)
                .map(|j| 1.0 + theta * bernoulli(alpha, (a[j] - b[j]).rem_euclid(1.0)))
                .product::<f64>()
        };
        let gram: Vec<f64> = (0..n * n).map(|e| kernel(&x[e / n], &x[e % n])).collect();
        let (sd, objective) = dense_posterior(&gram, &y);

        let dft = RealDft::new(n);
        let table = decay_table(alpha, n);
        let power = power_spectrum(&y, &dft);
        let index = decay_index(n, &z);
        let mut buffers = dft.buffers();
        let eta = |i, j| table[index(i, j)];
        let fit = Fit::new(Eta::new(d, eta, &[], 0), theta, &power, &dft, &mut buffers);
        assert!((fit.sd() - sd).abs() < 1e-10 * sd, "{} vs {sd}", fit.sd());
        // The gathered values' column (in vector lanes where the processor has them) is
        // the looked-up one, bit for bit.
        let gathered = gather(&table, n, d, &index, None);
        let rows = n / 2 + 1;
        let lanes = Fit::new(
            Eta::new(d, eta, &gathered, rows),
            theta,
            &power,
            &dft,
            &mut buffers,
        );
        assert!(!gathered.is_empty());
        assert_eq!((lanes.objective, lanes.sd()), (fit.objective, fit.sd()));
        // The likelihood up to the constant n·ln n that the spectrum's scale adds.
        assert!(
            (fit.objective - objective).abs() < 1e-8,
            "{} vs {objective}",
            fit.objective
        );
    }

    #[test]
    fn the_likelihood_prices_a_rough_f_with_a_slow_decay_and_a_smooth_one_with_a_fast_one() {
        use stillpoint_sequences::SequenceTable;
        let n = 1024usize;
        let z = &SequenceTable::FirstOrder.generator()[..2];
        let at = |i: usize, j: usize| ((i as u64 * z[j] as u64) % n as u64) as f64 / n as f64 + 0.1;
        let smooth: Vec<f64> = (0..n)
            .map(|i| {
                (2.0 * std::f64::consts::PI * at(i, 0)).cos()
                    * (2.0 * std::f64::consts::PI * at(i, 1)).sin()
            })
            .map(|v| v.exp())
            .collect();
        let rough: Vec<f64> = (0..n)
            .map(|i| ((at(i, 0) % 1.0) - 0.5).abs() + ((at(i, 1) % 1.0) - 0.3).abs())
            .collect();
        let (s, r) = (
            posterior(&smooth, z).unwrap(),
            posterior(&rough, z).unwrap(),
        );
        assert_eq!(s.decay, 4.0, "{s:?}");
        assert!(r.decay <= 2.5, "{r:?}");
        assert!(posterior(&[1.0; 16], z).is_none());
    }

    #[test]
    fn posteriors_weigh_coordinates_and_agree_with_the_search() {
        // A smooth periodic f of two coordinates on 256 points of a three-coordinate
        // lattice: weight 0 drops the third coordinate (the same bits as the lattice of
        // two), and the grid's fit is within a few percent of the golden search's.
        let n = 256;
        let z = &stillpoint_sequences::SequenceTable::FirstOrder.generator()[..3];
        let y: Vec<f64> = (0..n)
            .map(|i| {
                let x: Vec<f64> = z
                    .iter()
                    .map(|&g| (i as f64 * g as f64 / n as f64).fract())
                    .collect();
                (2.0 * std::f64::consts::PI * x[0]).cos()
                    * (1.0 + 0.3 * (2.0 * std::f64::consts::PI * x[1]).sin())
            })
            .collect();
        let flat = vec![y.clone()];
        let dropped = posteriors(&flat, z, &[1.0, 1.0, 0.0])[0].unwrap();
        let two = posteriors(&flat, &z[..2], &[1.0, 1.0])[0].unwrap();
        assert_eq!(dropped, two);
        let grid = posteriors(&flat, z, &[1.0; 3])[0].unwrap();
        let searched = posterior(&y, z).unwrap();
        assert!(
            (grid.sd / searched.sd - 1.0).abs() < 0.05,
            "{grid:?} {searched:?}"
        );
        // A constant output has none, the others theirs.
        let both = posteriors(&[vec![1.0; n], y.clone()], z, &[1.0; 3]);
        assert!(both[0].is_none());
        assert_eq!(both[1], Some(grid));
    }

    #[test]
    fn brent_search_finds_a_parabola_s_minimum_and_a_kink_s() {
        let mut calls = 0;
        let (m, value) = brent_minimum(
            |t| {
                calls += 1;
                ((t + 1.7).powi(2), t)
            },
            (-5.0, 0.0),
            1e-6,
        );
        assert_eq!(value, m);
        // A parabola is found by the first parabolic step.
        assert!(calls <= 8, "{calls} evaluations");
        assert!((m + 1.7).abs() < 1e-5);
        // At an end of the range, the end.
        assert!(brent_minimum(|t| (t, ()), (-5.0, 0.0), 1e-3).0 < -4.99);
        // A minimum at a kink, where parabolas do not fit: golden sections find it.
        let (m, _) = brent_minimum(|t| ((t + 3.3).abs(), ()), (-5.0, 0.0), 1e-4);
        assert!((m + 3.3).abs() < 1e-4, "{m}");
    }
}
