//! The Kraichnan–Orszag three-mode problem (eqs. 51–53): random initial values, mean and
//! standard deviation of each mode on a time grid, and the relative L2-in-time errors of
//! eq. 53.
//!
//! Model, as implemented:
//!
//! - u1' = u2 u3, u2' = u3 u1, u3' = −2 u1 u2 (eq. 51);
//! - u1(0) = 1 + 0.1 ξ1, u2(0) = 2 + 0.2 ξ2, u3(0) = 1 + 0.1 ξ3 with ξ_i = 2 x_i − 1, so a
//!   point x of [0, 1]^3 maps to ξ uniform in [−1, 1]^3 (eq. 52);
//! - the paper's "Euler midpoint scheme" is taken as the explicit midpoint rule (RK2):
//!   u_{k+1} = u_k + Δt f(u_k + Δt/2 f(u_k)), Δt = 0.1 on t ∈ [0, 20] by default;
//! - moments at every grid time t_k = k Δt, k = 0..=T/Δt: the sample mean and the sample
//!   SD with the n − 1 divisor (MATLAB's `std`) for point sets and Monte Carlo, and the
//!   exact weighted mean and SD for the Gauss–Legendre product rule;
//! - eq. 53's norms ‖u‖₂ = (∫₀ᵀ u² dt)^{1/2} by the trapezoid rule on the same grid.
//!
//! The system has two invariants, u1² − u2² and 2u1² + u3² (differentiate: 2u1u2u3 −
//! 2u2u3u1 = 0 and 4u1u2u3 − 4u3u1u2 = 0); the explicit midpoint rule keeps them to O(Δt²).
//! At the paper's Δt = 0.1 that is coarse: along the centre trajectory 2u1² + u3² = 3
//! drifts by about 1 by t = 20, and u(20) is far from the ODE's. Every estimate and every
//! reference here uses the same discrete model, so eq. 53 measures sampling error only;
//! a study of the ODE itself needs a smaller Δt.

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::{check_points, check_samples, chunked, gauss_legendre, Accumulator};
use stillpoint::{Error, PointSet};

/// Time grid of the integration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct KoSettings {
    /// Time step Δt (the paper: 0.1).
    pub dt: f64,
    /// Final time T (the paper: 20).
    pub t_end: f64,
}

impl Default for KoSettings {
    fn default() -> Self {
        KoSettings {
            dt: 0.1,
            t_end: 20.0,
        }
    }
}

/// Longest accepted time grid; beyond it the per-chunk moment buffers become unreasonable.
const MAX_STEPS: usize = 1_000_000;

impl KoSettings {
    /// Number of steps T/Δt, refusing a step or end time that is not positive and finite,
    /// or an end time that is not a whole number of steps.
    pub fn steps(&self) -> Result<usize, Error> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(Error::invalid("dt", self.dt, "a positive finite time step"));
        }
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(Error::invalid(
                "t_end",
                self.t_end,
                "a positive finite end time",
            ));
        }
        let r = self.t_end / self.dt;
        let k = r.round();
        if (r - k).abs() > 1e-9 * r.max(1.0) || k < 1.0 {
            return Err(Error::invalid(
                "dt",
                self.dt,
                format!("a step dividing t_end = {} into whole steps", self.t_end),
            ));
        }
        if k > MAX_STEPS as f64 {
            return Err(Error::invalid(
                "dt",
                self.dt,
                format!("at most {MAX_STEPS} steps up to t_end = {}", self.t_end),
            ));
        }
        Ok(k as usize)
    }

    /// The grid times t_k = k Δt, k = 0..=steps.
    pub fn times(&self) -> Result<Vec<f64>, Error> {
        let steps = self.steps()?;
        Ok((0..=steps).map(|k| k as f64 * self.dt).collect())
    }
}

/// Mean and SD of u1, u2, u3 at every grid time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KoMoments {
    /// t_0 = 0, …, t_K = T.
    pub times: Vec<f64>,
    /// Mean of u_i at each time, i = 1, 2, 3.
    pub mean: [Vec<f64>; 3],
    /// Standard deviation of u_i at each time (n − 1 divisor for samples; exact for the
    /// quadrature rule).
    pub sd: [Vec<f64>; 3],
    /// Number of trajectories: points, Monte Carlo samples, or quadrature nodes.
    pub samples: usize,
}

/// eq. 53's relative errors of the means and SDs of u1, u2, u3.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct KoErrors {
    /// ε of the mean of u_i.
    pub mean: [f64; 3],
    /// ε of the SD of u_i.
    pub sd: [f64; 3],
}

#[inline]
fn rhs(u: [f64; 3]) -> [f64; 3] {
    [u[1] * u[2], u[2] * u[0], -2.0 * u[0] * u[1]]
}

/// Initial values of eq. 52 for a point of [0, 1]^3.
#[inline]
fn initial(x: &[f64]) -> [f64; 3] {
    let xi = |v: f64| 2.0 * v - 1.0;
    [
        1.0 + 0.1 * xi(x[0]),
        2.0 + 0.2 * xi(x[1]),
        1.0 + 0.1 * xi(x[2]),
    ]
}

/// One explicit midpoint step.
#[inline]
fn step(u: [f64; 3], dt: f64) -> [f64; 3] {
    let k1 = rhs(u);
    let h = 0.5 * dt;
    let m = [u[0] + h * k1[0], u[1] + h * k1[1], u[2] + h * k1[2]];
    let k2 = rhs(m);
    [u[0] + dt * k2[0], u[1] + dt * k2[1], u[2] + dt * k2[2]]
}

/// Adds one trajectory from u0 to the accumulator (layout: time-major, 3 modes per time).
#[inline]
fn accumulate(mut u: [f64; 3], steps: usize, dt: f64, w: f64, acc: &mut Accumulator) {
    let st = acc.begin(w);
    for k in 0..=steps {
        if k > 0 {
            u = step(u, dt);
        }
        for (i, &ui) in u.iter().enumerate() {
            acc.add(3 * k + i, ui, w, st);
        }
    }
}

/// The trajectory from an initial value u0 = (u1, u2, u3): one row per grid time.
pub fn ko_solve(u0: [f64; 3], settings: &KoSettings) -> Result<Vec<[f64; 3]>, Error> {
    let steps = settings.steps()?;
    if let Some(v) = u0.iter().find(|v| !v.is_finite()) {
        return Err(Error::invalid("u0", v, "finite initial values"));
    }
    let mut out = Vec::with_capacity(steps + 1);
    let mut u = u0;
    out.push(u);
    for _ in 0..steps {
        u = step(u, settings.dt);
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Numerical(format!(
                "Kraichnan–Orszag solution from {u0:?} is not finite with dt = {}: \
                 the time step is too large",
                settings.dt
            )));
        }
        out.push(u);
    }
    Ok(out)
}

fn finish(
    acc: &Accumulator,
    settings: &KoSettings,
    samples: usize,
    divisor: f64,
) -> Result<KoMoments, Error> {
    let times = settings.times()?;
    let sd = acc.sd(divisor);
    let pick = |v: &[f64], i: usize| v.iter().skip(i).step_by(3).copied().collect::<Vec<_>>();
    let m = KoMoments {
        times,
        mean: [
            pick(acc.mean(), 0),
            pick(acc.mean(), 1),
            pick(acc.mean(), 2),
        ],
        sd: [pick(&sd, 0), pick(&sd, 1), pick(&sd, 2)],
        samples,
    };
    let finite = m.mean.iter().chain(&m.sd).flatten().all(|v| v.is_finite());
    if !finite {
        return Err(Error::Numerical(format!(
            "Kraichnan–Orszag moments are not finite with dt = {}: the time step is too large",
            settings.dt
        )));
    }
    Ok(m)
}

/// Moments from a point set in [0, 1]^3 (equal weights, SD with the n − 1 divisor).
pub fn ko_moments(points: &PointSet, settings: &KoSettings) -> Result<KoMoments, Error> {
    check_points(points, 3, "Kraichnan–Orszag")?;
    let steps = settings.steps()?;
    let n = points.n();
    let acc = chunked(n, 3 * (steps + 1), 0, |range, _, acc| {
        for i in range {
            accumulate(initial(points.point(i)), steps, settings.dt, 1.0, acc);
        }
    });
    finish(&acc, settings, n, (n - 1) as f64)
}

/// Plain Monte Carlo reference: `samples` uniform points from `Xoshiro256PlusPlus` streams
/// derived from `seed` (see the module [`crate::uq`]); bit-identical for any thread count.
pub fn ko_monte_carlo(
    samples: usize,
    seed: u64,
    settings: &KoSettings,
) -> Result<KoMoments, Error> {
    check_samples(samples)?;
    let steps = settings.steps()?;
    let acc = chunked(samples, 3 * (steps + 1), seed, |range, rng, acc| {
        for _ in range {
            let x: [f64; 3] = [rng.random(), rng.random(), rng.random()];
            accumulate(initial(&x), steps, settings.dt, 1.0, acc);
        }
    });
    finish(&acc, settings, samples, (samples - 1) as f64)
}

/// Reference by the tensor Gauss–Legendre rule with `nodes_per_axis` nodes in each ξ_i
/// (exact mean and SD of the discretised model up to the rule's error, which for this
/// smooth map falls far below Monte Carlo noise at 16–32 nodes). 1 to 256 nodes.
pub fn ko_gauss(nodes_per_axis: usize, settings: &KoSettings) -> Result<KoMoments, Error> {
    if !(1..=256).contains(&nodes_per_axis) {
        return Err(Error::invalid(
            "nodes_per_axis",
            nodes_per_axis,
            "1 to 256 Gauss–Legendre nodes per axis",
        ));
    }
    let steps = settings.steps()?;
    let (xi, w) = gauss_legendre(nodes_per_axis)?;
    let m = nodes_per_axis;
    let total = m * m * m;
    let acc = chunked(total, 3 * (steps + 1), 0, |range, _, acc| {
        for idx in range {
            let (a, b, c) = (idx / (m * m), (idx / m) % m, idx % m);
            // Weights on [−1,1] sum to 2 per axis; /8 makes a probability measure.
            let wt = w[a] * w[b] * w[c] / 8.0;
            let u0 = [1.0 + 0.1 * xi[a], 2.0 + 0.2 * xi[b], 1.0 + 0.1 * xi[c]];
            accumulate(u0, steps, settings.dt, wt, acc);
        }
    });
    finish(&acc, settings, total, 1.0)
}

/// Trapezoid-rule ∫ g(t)² dt on the grid.
fn l2_squared(times: &[f64], g: impl Fn(usize) -> f64) -> f64 {
    let mut s = 0.0;
    for k in 1..times.len() {
        let (a, b) = (g(k - 1), g(k));
        s += 0.5 * (times[k] - times[k - 1]) * (a * a + b * b);
    }
    s
}

/// ε = ‖u − u_r‖₂ / ‖u_r‖₂ of eq. 53 for each mean and SD curve. Refuses estimates on a
/// different time grid, and a zero reference curve unless the estimate matches it exactly
/// (then ε = 0).
pub fn ko_relative_errors(estimate: &KoMoments, reference: &KoMoments) -> Result<KoErrors, Error> {
    if estimate.times != reference.times {
        return Err(Error::invalid(
            "estimate times",
            format!(
                "{} times up to {}",
                estimate.times.len(),
                estimate.times.last().copied().unwrap_or(0.0)
            ),
            format!(
                "the reference grid ({} times up to {})",
                reference.times.len(),
                reference.times.last().copied().unwrap_or(0.0)
            ),
        ));
    }
    let t = &reference.times;
    let rel = |u: &[f64], r: &[f64], what: &str| -> Result<f64, Error> {
        let num = l2_squared(t, |k| u[k] - r[k]).sqrt();
        let den = l2_squared(t, |k| r[k]).sqrt();
        if num == 0.0 {
            Ok(0.0)
        } else if den > 0.0 {
            Ok(num / den)
        } else {
            Err(Error::invalid(
                format!("reference {what}"),
                "identically 0",
                "a reference with a nonzero L2 norm (a relative error needs one)",
            ))
        }
    };
    let mut e = KoErrors {
        mean: [0.0; 3],
        sd: [0.0; 3],
    };
    for i in 0..3 {
        e.mean[i] = rel(
            &estimate.mean[i],
            &reference.mean[i],
            &format!("mean of u{}", i + 1),
        )?;
        e.sd[i] = rel(
            &estimate.sd[i],
            &reference.sd[i],
            &format!("SD of u{}", i + 1),
        )?;
    }
    Ok(e)
}
