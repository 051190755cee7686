//! Integration to a tolerance: the number of points doubles on the extensible randomised
//! lattice ([`crate::sequences::ExtensibleLattice`]) with R independent shifts, never
//! discarding an evaluation, until the confidence interval from the R replicate means is
//! narrow enough.
//!
//! [`Cubature`] is the state machine every front end drives (ask for the next batch of
//! points, feed back f's values, read the estimate); [`quad`] runs it on a Rust closure.
//!
//! The rule. After each doubling, with μ_r the mean of f over replicate r's n_r points
//! (each μ_r an unbiased estimate, independent across replicates), the estimate is the
//! mean μ of the μ_r and the half-width t_{R−1,(1+level)/2}·sd(μ_r)/√R (a Student t
//! interval, exact when the μ_r are normal; with at least 8 replicates it is robust to
//! the mild skew of lattice errors). It stops when, for every output,
//! half-width ≤ max(abs_tol, rel_tol·|estimate|), or when the next doubling would pass
//! `max_n` evaluations in total (all replicates together), and then says the tolerance
//! was not met. Over a box [a, b] the points are scaled and the estimate and half-width
//! include the volume, as in SciPy's `qmc_quad`.

use serde::{Deserialize, Serialize};

use crate::sequences::{ExtensibleLattice, EXTENSIBLE_MAX_POINTS};
use crate::{Error, PointSet};

/// Replicates (independent shifts) by default.
pub const DEFAULT_REPLICATES: usize = 8;

/// The most evaluations of f in total by default (2^20).
pub const DEFAULT_MAX_N: u64 = 1 << 20;

/// Points per replicate in the first batch by default (the smallest prefix whose quality
/// is checked against a lattice made for its size).
pub const DEFAULT_START_N: u64 = 64;

/// Fewer replicates than this get a warning: the t quantile is large (t_{2,0.975} = 4.30)
/// and the half-width itself varies so much from run to run that a stop is often early
/// or late.
pub const MIN_QUIET_REPLICATES: usize = 4;

/// Settings of an integration; [`Default`] gives the documented defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QuadOptions {
    /// Lower corner of the box (the unit cube's 0 when `None`).
    pub a: Option<Vec<f64>>,
    /// Upper corner of the box (the unit cube's 1 when `None`).
    pub b: Option<Vec<f64>>,
    /// Absolute tolerance on the half-width (0: only the relative one counts).
    pub abs_tol: f64,
    /// Relative tolerance: half-width ≤ rel_tol·|estimate| suffices.
    pub rel_tol: f64,
    /// Confidence level of the interval, in (0, 1).
    pub level: f64,
    /// Independent shifts R, at least 2.
    pub replicates: usize,
    /// The most evaluations of f, all replicates together.
    pub max_n: u64,
    /// Points per replicate in the first batch (a power of two).
    pub start_n: u64,
    /// Seed of the shifts.
    pub seed: u64,
}

impl Default for QuadOptions {
    fn default() -> Self {
        QuadOptions {
            a: None,
            b: None,
            abs_tol: 0.0,
            rel_tol: 1e-3,
            level: 0.95,
            replicates: DEFAULT_REPLICATES,
            max_n: DEFAULT_MAX_N,
            start_n: DEFAULT_START_N,
            seed: 0,
        }
    }
}

/// The state of an integration (see the module documentation). Serializable, so a
/// front end can save it and continue later with a tighter tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cubature {
    d: usize,
    options: QuadOptions,
    lower: Vec<f64>,
    width: Vec<f64>,
    /// Outputs of f (0 until the first values are fed).
    k: usize,
    /// Points evaluated per replicate.
    per_replicate: u64,
    /// Points per replicate in the batch handed out and not yet fed (0: none).
    pending: u64,
    /// Σ f over each replicate's points, replicate-major (R × k).
    sums: Vec<f64>,
}

impl Cubature {
    /// A new integration of a function of d variables. Refuses d = 0 or beyond the
    /// sequence's dimensions (naming `d`), a box of the wrong length or with b ≤ a
    /// (`a`, `b`), negative or non-finite tolerances (`abs_tol`, `rel_tol`), a level
    /// outside (0, 1) (`level`), fewer than 2 replicates (`replicates`), a `start_n` that
    /// is not a power of two, and a `max_n` below one first batch.
    pub fn new(d: usize, options: QuadOptions) -> Result<Cubature, Error> {
        ExtensibleLattice::new(d, 0, 0)?;
        let o = &options;
        let corner = |v: &Option<Vec<f64>>, name: &str, fill: f64| match v {
            None => Ok(vec![fill; d]),
            Some(v) if v.len() == d && v.iter().all(|x| x.is_finite()) => Ok(v.clone()),
            Some(v) => Err(Error::invalid(
                name,
                format!("{v:?}"),
                format!("{d} finite values (one per dimension)"),
            )),
        };
        let lower = corner(&o.a, "a", 0.0)?;
        let upper = corner(&o.b, "b", 1.0)?;
        if let Some(i) = (0..d).find(|&i| upper[i] <= lower[i]) {
            return Err(Error::invalid(
                "b",
                format!("{:?}", upper),
                format!("b[{i}] > a[{i}] = {} in every dimension", lower[i]),
            ));
        }
        for (name, t) in [("abs_tol", o.abs_tol), ("rel_tol", o.rel_tol)] {
            if !(t.is_finite() && t >= 0.0) {
                return Err(Error::invalid(name, t, "a finite value ≥ 0"));
            }
        }
        if !(o.level > 0.0 && o.level < 1.0) {
            return Err(Error::invalid("level", o.level, "a value in (0, 1)"));
        }
        if o.replicates < 2 {
            return Err(Error::invalid(
                "replicates",
                o.replicates,
                "at least 2 (the interval comes from their spread); 8 or more recommended",
            ));
        }
        if !o.start_n.is_power_of_two() || o.start_n > EXTENSIBLE_MAX_POINTS {
            return Err(Error::invalid(
                "start_n",
                o.start_n,
                format!("a power of two up to {EXTENSIBLE_MAX_POINTS}"),
            ));
        }
        let first = o.start_n.saturating_mul(o.replicates as u64);
        if o.max_n < first {
            return Err(Error::invalid(
                "max_n",
                o.max_n,
                format!(
                    "at least one first batch: start_n·replicates = {} evaluations",
                    first
                ),
            ));
        }
        let width = lower.iter().zip(&upper).map(|(a, b)| b - a).collect();
        Ok(Cubature {
            d,
            options,
            lower,
            width,
            k: 0,
            per_replicate: 0,
            pending: 0,
            sums: Vec::new(),
        })
    }

    /// The dimension d.
    pub fn d(&self) -> usize {
        self.d
    }

    /// The settings (with the current tolerances).
    pub fn options(&self) -> &QuadOptions {
        &self.options
    }

    /// Outputs of f (0 before the first values are fed).
    pub fn outputs(&self) -> usize {
        self.k
    }

    /// Evaluations of f so far, all replicates together.
    pub fn n(&self) -> u64 {
        self.per_replicate * self.options.replicates as u64
    }

    /// Points per replicate of the batch handed out and not yet fed (0: none).
    pub fn pending(&self) -> u64 {
        self.pending
    }

    /// Points evaluated per replicate so far.
    pub fn per_replicate(&self) -> u64 {
        self.per_replicate
    }

    /// Sets new tolerances (to continue after the interval met the old ones); the
    /// evaluations made are kept. Refuses negative or non-finite values, naming them.
    pub fn set_tolerance(&mut self, abs_tol: f64, rel_tol: f64) -> Result<(), Error> {
        for (name, t) in [("abs_tol", abs_tol), ("rel_tol", rel_tol)] {
            if !(t.is_finite() && t >= 0.0) {
                return Err(Error::invalid(name, t, "a finite value ≥ 0"));
            }
        }
        self.options.abs_tol = abs_tol;
        self.options.rel_tol = rel_tol;
        Ok(())
    }

    /// Points per replicate of the next batch (the first batch, then as many as already
    /// evaluated, doubling the total).
    fn next_size(&self) -> u64 {
        if self.per_replicate == 0 {
            self.options.start_n
        } else {
            self.per_replicate
        }
    }

    /// Whether the next doubling would pass `max_n` evaluations or the sequence's 2^20
    /// points per replicate.
    pub fn exhausted(&self) -> bool {
        let next = self.per_replicate + self.next_size();
        next > EXTENSIBLE_MAX_POINTS
            || next.saturating_mul(self.options.replicates as u64) > self.options.max_n
    }

    /// The next batch of points, scaled to the box, as (rows, d) row-major values:
    /// replicate 0's new points, then replicate 1's, and so on (each replicate's points
    /// n_r..2n_r of its sequence, or its first `start_n`). Asking again before
    /// [`Cubature::feed`] gives the same batch. `None` when the budget is spent
    /// ([`Cubature::exhausted`]).
    pub fn next_points(&mut self) -> Option<PointSet> {
        if self.pending == 0 {
            if self.exhausted() {
                return None;
            }
            self.pending = self.next_size();
        }
        let (r, m) = (self.options.replicates, self.pending as usize);
        let mut data = vec![0.0; r * m * self.d];
        for (rep, chunk) in data.chunks_exact_mut(m * self.d).enumerate() {
            let seq = ExtensibleLattice::new(self.d, self.options.seed, rep as u64)
                .expect("d checked at construction");
            seq.fill(self.per_replicate, m, chunk)
                .expect("range checked by exhausted()");
            for row in chunk.chunks_exact_mut(self.d) {
                for ((x, a), w) in row.iter_mut().zip(&self.lower).zip(&self.width) {
                    *x = a + w * *x;
                }
            }
        }
        Some(PointSet::new(r * m, self.d, data).expect("non-empty batch"))
    }

    /// Takes f's values at the batch of [`Cubature::next_points`]: rows × k values,
    /// row-major (k outputs per point; k is fixed by the first batch). Refuses values
    /// without a batch handed out, a length that is not a multiple of the rows (or a
    /// different k), and NaN or ±∞, naming the point; the state is unchanged then.
    pub fn feed(&mut self, points: &PointSet, values: &[f64]) -> Result<(), Error> {
        let r = self.options.replicates;
        let m = self.pending as usize;
        let rows = r * m;
        if m == 0 || points.n() != rows {
            return Err(Error::invalid(
                "values",
                format!("{} values", values.len()),
                "f's values at the points of next_points() (none are pending)",
            ));
        }
        let k = if self.k == 0 {
            values.len() / rows
        } else {
            self.k
        };
        if k == 0 || values.len() != rows * k {
            return Err(Error::invalid(
                "values",
                format!("{} values for {rows} points", values.len()),
                if self.k == 0 {
                    format!("{rows}·k values (k ≥ 1 outputs per point)")
                } else {
                    format!("{} values ({} outputs per point)", rows * k, k)
                },
            ));
        }
        if let Some(at) = values.iter().position(|v| !v.is_finite()) {
            let i = at / k;
            let p = &points.as_slice()[i * self.d..(i + 1) * self.d];
            return Err(Error::invalid(
                "f",
                format!("{} at x = {:?} (output {})", values[at], p, at % k),
                "a finite value at every point",
            ));
        }
        if self.k == 0 {
            self.k = k;
            self.sums = vec![0.0; r * k];
        }
        for (rep, block) in values.chunks_exact(m * k).enumerate() {
            let sums = &mut self.sums[rep * k..(rep + 1) * k];
            for row in block.chunks_exact(k) {
                for (s, v) in sums.iter_mut().zip(row) {
                    *s += v;
                }
            }
        }
        self.per_replicate += self.pending;
        self.pending = 0;
        Ok(())
    }

    /// The volume of the box.
    fn volume(&self) -> f64 {
        self.width.iter().product()
    }

    /// The estimate of each output's integral (empty before the first values).
    pub fn estimate(&self) -> Vec<f64> {
        self.replicate_means()
            .iter()
            .map(|m| m.iter().sum::<f64>() / m.len() as f64)
            .collect()
    }

    /// Per output, the R replicate means (scaled by the volume).
    pub fn replicate_means(&self) -> Vec<Vec<f64>> {
        let r = self.options.replicates;
        let scale = self.volume() / self.per_replicate.max(1) as f64;
        (0..self.k)
            .map(|j| {
                (0..r)
                    .map(|rep| self.sums[rep * self.k + j] * scale)
                    .collect()
            })
            .collect()
    }

    /// The half-width of each output's interval at the level asked (empty before the
    /// first values).
    pub fn half_width(&self) -> Vec<f64> {
        let r = self.options.replicates;
        let t = student_t_quantile((1.0 + self.options.level) / 2.0, (r - 1) as f64);
        self.replicate_means()
            .iter()
            .map(|m| {
                let mean = m.iter().sum::<f64>() / r as f64;
                let var = m.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (r - 1) as f64;
                t * (var / r as f64).sqrt()
            })
            .collect()
    }

    /// The half-width each output must reach: max(abs_tol, rel_tol·|estimate|) (empty
    /// before the first values).
    pub fn targets(&self) -> Vec<f64> {
        let (abs_tol, rel_tol) = (self.options.abs_tol, self.options.rel_tol);
        self.estimate()
            .iter()
            .map(|e| abs_tol.max(rel_tol * e.abs()))
            .collect()
    }

    /// Whether every output's half-width is within its [`Cubature::targets`] (false
    /// before the first values).
    pub fn met(&self) -> bool {
        self.k > 0
            && self
                .half_width()
                .iter()
                .zip(self.targets())
                .all(|(h, t)| *h <= t)
    }

    /// Warnings about the settings: too few replicates for a trustworthy interval.
    pub fn warnings(&self) -> Vec<String> {
        let r = self.options.replicates;
        if r < MIN_QUIET_REPLICATES {
            vec![format!(
                "{r} replicates give an unreliable interval at level {}: its half-width \
                 varies widely between runs (t quantile {:.2}); use 8 or more",
                self.options.level,
                student_t_quantile((1.0 + self.options.level) / 2.0, (r - 1) as f64)
            )]
        } else {
            Vec::new()
        }
    }

    /// Doubles until [`Cubature::met`] or [`Cubature::exhausted`], calling f on each
    /// batch (f returns rows × k values, row-major). Returns whether the tolerance is met.
    pub fn run<F>(&mut self, f: F) -> Result<bool, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
    {
        self.run_observed(f, |_| {})
    }

    /// [`Cubature::run`], calling `after` with the state after each doubling (progress
    /// displays).
    pub fn run_observed<F, A>(&mut self, mut f: F, mut after: A) -> Result<bool, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
        A: FnMut(&Cubature),
    {
        while !self.met() {
            let Some(points) = self.next_points() else {
                return Ok(false);
            };
            let values = f(&points);
            self.feed(&points, &values)?;
            after(self);
        }
        Ok(true)
    }
}

/// What [`quad`] returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QuadResult {
    /// The estimate of each output's integral.
    pub estimate: Vec<f64>,
    /// The half-width of each output's interval at the level asked.
    pub half_width: Vec<f64>,
    /// Evaluations of f.
    pub n: u64,
    /// Independent shifts R.
    pub replicates: usize,
    /// Whether every output met the tolerance.
    pub met: bool,
    /// Warnings about the settings.
    pub warnings: Vec<String>,
    /// The state, to continue with a tighter tolerance.
    pub state: Cubature,
}

impl From<Cubature> for QuadResult {
    /// The result a state has reached so far.
    fn from(state: Cubature) -> QuadResult {
        QuadResult {
            estimate: state.estimate(),
            half_width: state.half_width(),
            n: state.n(),
            replicates: state.options.replicates,
            met: state.met(),
            warnings: state.warnings(),
            state,
        }
    }
}

impl QuadResult {
    /// Continues with new tolerances, evaluating f only at new points.
    pub fn refine<F>(self, f: F, abs_tol: f64, rel_tol: f64) -> Result<QuadResult, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
    {
        let mut state = self.state;
        state.set_tolerance(abs_tol, rel_tol)?;
        state.run(f)?;
        Ok(QuadResult::from(state))
    }
}

/// ∫ f over [a, b] (the unit cube by default) to the tolerance of `options` (see the
/// module documentation). f gets a batch of points and returns its values, rows × k
/// row-major (k outputs per point, the same k every call).
///
/// ```
/// use stillpoint::cubature::{quad, QuadOptions};
/// let opts = QuadOptions { rel_tol: 1e-4, ..QuadOptions::default() };
/// let r = quad(|x| x.rows().map(|p| p[0] * p[1]).collect(), 2, opts)?;
/// assert!(r.met && (r.estimate[0] - 0.25).abs() < 1e-3);
/// # Ok::<(), stillpoint::Error>(())
/// ```
pub fn quad<F>(f: F, d: usize, options: QuadOptions) -> Result<QuadResult, Error>
where
    F: FnMut(&PointSet) -> Vec<f64>,
{
    let mut state = Cubature::new(d, options)?;
    state.run(f)?;
    Ok(QuadResult::from(state))
}

/// The regularised incomplete beta function I_x(a, b), by the continued fraction of
/// Numerical Recipes (Press et al., 3rd ed., §6.4), using the symmetry
/// I_x(a, b) = 1 − I_{1−x}(b, a) where the fraction converges slowly.
fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front =
        libm::lgamma(a + b) - libm::lgamma(a) - libm::lgamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_fraction(x, a, b) / a
    } else {
        1.0 - ln_front.exp() * beta_fraction(1.0 - x, b, a) / b
    }
}

/// The continued fraction of I_x(a, b) (modified Lentz).
fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    let tiny = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < tiny {
        d = tiny;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..10_000 {
        let m = m as f64;
        let m2 = 2.0 * m;
        for aa in [
            m * (b - m) * x / ((qam + m2) * (a + m2)),
            -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)),
        ] {
            d = 1.0 + aa * d;
            if d.abs() < tiny {
                d = tiny;
            }
            c = 1.0 + aa / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            h *= d * c;
        }
        if (d * c - 1.0).abs() < 1e-16 {
            break;
        }
    }
    h
}

/// The Student t distribution function with ν degrees of freedom at t.
pub fn student_t_cdf(t: f64, nu: f64) -> f64 {
    let tail = 0.5 * incomplete_beta(nu / (nu + t * t), nu / 2.0, 0.5);
    if t >= 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The p-quantile of the Student t distribution with ν > 0 degrees of freedom, for p in
/// (0, 1): [`student_t_cdf`] inverted by bisection to the last bits (a bracket found by
/// doubling), which needs no approximation of its own.
pub fn student_t_quantile(p: f64, nu: f64) -> f64 {
    if p < 0.5 {
        return -student_t_quantile(1.0 - p, nu);
    }
    if p == 0.5 {
        return 0.0;
    }
    let mut hi = 1.0;
    while student_t_cdf(hi, nu) < p && hi < 1e300 {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if student_t_cdf(mid, nu) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_the_tables() {
        // Reference values from standard t tables (and t_1 = tan(π(p − ½)) exactly).
        for (p, nu, want) in [
            (0.975, 7.0, 2.364624),
            (0.975, 1.0, 12.706205),
            (0.995, 3.0, 5.840909),
            (0.95, 30.0, 1.697261),
            (0.975, 1e7, 1.959964),
            (0.9, 2.0, 1.885618),
        ] {
            let t = student_t_quantile(p, nu);
            assert!((t - want).abs() < 2e-6, "t({p}, {nu}) = {t}, want {want}");
        }
        let t = student_t_quantile(0.8, 1.0);
        assert!((t - (std::f64::consts::PI * 0.3).tan()).abs() < 1e-10);
        assert_eq!(
            student_t_quantile(0.025, 7.0),
            -student_t_quantile(0.975, 7.0)
        );
    }

    /// Π_i (1 + c_i (x_i − ½)) + e^{x_1 + x_2}: integral 1 + (e − 1)² over the unit cube.
    fn product_exp(x: &PointSet) -> Vec<f64> {
        x.rows()
            .map(|p| {
                p.iter()
                    .enumerate()
                    .map(|(i, v)| 1.0 + (0.5 + 0.2 * i as f64) * (v - 0.5))
                    .product::<f64>()
                    + (p[0] + p[1]).exp()
            })
            .collect()
    }

    #[test]
    fn known_integrals_are_reached_within_the_tolerance() {
        let exact = 1.0 + (std::f64::consts::E - 1.0).powi(2);
        for rel_tol in [1e-2, 1e-4, 1e-6] {
            let opts = QuadOptions {
                rel_tol,
                ..QuadOptions::default()
            };
            let r = quad(product_exp, 4, opts).unwrap();
            assert!(r.met, "rel_tol {rel_tol}: {r:?}");
            assert!(
                (r.estimate[0] - exact).abs() <= rel_tol * exact,
                "rel_tol {rel_tol}: {} vs {exact}",
                r.estimate[0]
            );
            assert!(r.half_width[0] <= rel_tol * r.estimate[0].abs());
        }
    }

    #[test]
    fn a_box_scales_the_points_and_the_volume() {
        // ∫ over [1, 3] × [−1, 0] of x·y² = (9 − 1)/2 · 1/3 = 4/3.
        let opts = QuadOptions {
            a: Some(vec![1.0, -1.0]),
            b: Some(vec![3.0, 0.0]),
            abs_tol: 1e-6,
            rel_tol: 0.0,
            ..QuadOptions::default()
        };
        let r = quad(|x| x.rows().map(|p| p[0] * p[1] * p[1]).collect(), 2, opts).unwrap();
        assert!(r.met && (r.estimate[0] - 4.0 / 3.0).abs() < 1e-5, "{r:?}");
    }

    #[test]
    fn the_interval_covers_the_error_in_most_runs() {
        // A peaked integrand (Genz product peak, 3-D) at a modest tolerance, 100 seeds.
        let c = [4.0f64, 6.0, 5.0];
        let u = [0.3f64, 0.6, 0.45];
        let exact: f64 = (0..3)
            .map(|i| c[i] * ((c[i] * (1.0 - u[i])).atan() + (c[i] * u[i]).atan()))
            .product();
        let f = |x: &PointSet| -> Vec<f64> {
            x.rows()
                .map(|p| {
                    (0..3)
                        .map(|i| 1.0 / ((c[i] * c[i]).recip() + (p[i] - u[i]).powi(2)))
                        .product()
                })
                .collect()
        };
        let mut covered = 0;
        for seed in 0..100 {
            let opts = QuadOptions {
                rel_tol: 1e-3,
                seed,
                ..QuadOptions::default()
            };
            let r = quad(f, 3, opts).unwrap();
            if (r.estimate[0] - exact).abs() <= r.half_width[0] {
                covered += 1;
            }
        }
        assert!(covered >= 90, "covered {covered} of 100");
    }

    #[test]
    fn nan_is_refused_naming_the_point() {
        let e = quad(
            |x| {
                x.rows()
                    .map(|p| if p[0] > 0.9 { f64::NAN } else { p[0] })
                    .collect()
            },
            2,
            QuadOptions::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("invalid f = NaN at x = ["), "{e}");
        let at: Vec<f64> = e
            .split(['[', ']'])
            .nth(1)
            .unwrap()
            .split(", ")
            .map(|v| v.parse().unwrap())
            .collect();
        assert!(at[0] > 0.9, "{e}");
    }

    #[test]
    fn the_observer_sees_every_doubling_and_the_last_state() {
        let mut state = Cubature::new(
            3,
            QuadOptions {
                rel_tol: 1e-4,
                ..QuadOptions::default()
            },
        )
        .unwrap();
        let mut seen = Vec::new();
        let met = state
            .run_observed(product_exp, |s| {
                // The target is the stopping rule's, recomputed from its definition.
                let e = s.estimate()[0];
                assert_eq!(s.targets(), vec![1e-4 * e.abs()]);
                assert_eq!(s.met(), s.half_width()[0] <= 1e-4 * e.abs());
                seen.push(s.n());
            })
            .unwrap();
        assert!(met);
        assert!(seen.len() >= 2, "{seen:?}");
        assert!(seen.windows(2).all(|w| w[1] == 2 * w[0]), "{seen:?}");
        assert_eq!(*seen.last().unwrap(), state.n());
    }

    #[test]
    fn a_tighter_tolerance_evaluates_only_new_points() {
        let calls = std::cell::Cell::new(0u64);
        let count = |x: &PointSet| {
            calls.set(calls.get() + x.n() as u64);
            product_exp(x)
        };
        let first = quad(
            count,
            3,
            QuadOptions {
                rel_tol: 1e-2,
                ..QuadOptions::default()
            },
        )
        .unwrap();
        assert_eq!(calls.get(), first.n);
        let n1 = first.n;
        let second = first.refine(count, 0.0, 1e-6).unwrap();
        assert!(second.met && second.n > n1);
        assert_eq!(calls.get(), second.n, "every point evaluated once");
        // The same as one run at the tight tolerance from the start.
        let direct = quad(
            product_exp,
            3,
            QuadOptions {
                rel_tol: 1e-6,
                ..QuadOptions::default()
            },
        )
        .unwrap();
        assert_eq!(direct.n, second.n);
        assert_eq!(direct.estimate, second.estimate);
    }

    #[test]
    fn the_state_round_trips_through_serde() {
        let r = quad(product_exp, 2, QuadOptions::default()).unwrap();
        let text = serde_json::to_string(&r.state).unwrap();
        let back: Cubature = serde_json::from_str(&text).unwrap();
        assert_eq!(back, r.state);
    }

    #[test]
    fn stops_at_max_n_and_says_so() {
        let opts = QuadOptions {
            rel_tol: 1e-14,
            max_n: 4096,
            ..QuadOptions::default()
        };
        let r = quad(product_exp, 3, opts).unwrap();
        assert!(!r.met);
        assert_eq!(r.n, 4096);
    }

    #[test]
    fn refuses_bad_settings_by_name() {
        let bad = |o: QuadOptions, name: &str| {
            let e = Cubature::new(2, o).unwrap_err().to_string();
            assert!(e.starts_with(&format!("invalid {name} =")), "{e}");
        };
        let d = QuadOptions::default;
        bad(
            QuadOptions {
                replicates: 1,
                ..d()
            },
            "replicates",
        );
        bad(QuadOptions { level: 1.0, ..d() }, "level");
        bad(
            QuadOptions {
                rel_tol: -1.0,
                ..d()
            },
            "rel_tol",
        );
        bad(
            QuadOptions {
                abs_tol: f64::NAN,
                ..d()
            },
            "abs_tol",
        );
        bad(
            QuadOptions {
                b: Some(vec![1.0, 0.0]),
                ..d()
            },
            "b",
        );
        bad(
            QuadOptions {
                a: Some(vec![0.0]),
                ..d()
            },
            "a",
        );
        bad(QuadOptions { start_n: 48, ..d() }, "start_n");
        bad(QuadOptions { max_n: 100, ..d() }, "max_n");
        assert!(Cubature::new(0, d()).is_err());
        let few = Cubature::new(
            2,
            QuadOptions {
                replicates: 3,
                ..d()
            },
        )
        .unwrap();
        assert_eq!(few.warnings().len(), 1);
        assert!(Cubature::new(2, d()).unwrap().warnings().is_empty());
    }
}
