//! The mean square error of the shift-and-tent randomisation, as a potential energy: what
//! a set must lower so that its randomised copies (x ↦ 1 − |2((x + c) mod 1) − 1|, c
//! uniform) integrate smooth functions well, for any set and not only for lattices.
//!
//! For integrands with square-integrable mixed second derivatives (the half-period cosine
//! space of smoothness 2 with product weight γ; Dick, Nuyens and Pillichshammer 2014),
//! the tent turns cos(πhx) into cos(2πht), and averaging over the shift leaves a kernel of
//! the differences only. The squared worst-case error, averaged over the shift, is
//!
//! Φ(x) = (1/n²) Σ_{k,l} Π_j F(x_kj − x_lj) − 1,  F(d) = 1 + γ ω(d mod 1),
//!
//! with ω(d) = Σ_{h≠0} e^{2πihd}/h⁴ = −(2π)⁴ B4(d)/4! and B4(d) = d²(1 − d)² − 1/30. On a
//! rank-1 lattice the differences are lattice points and Φ is the lattice criterion
//! (1/n) Σ_k Π_j F(k z_j / n) − 1. F is periodic, even, C² on the torus and lies in
//! [1 − γ·0.0292·(2π)⁴/24, 1 + γ·(2π)⁴/720] (0.905 to 1.108 at γ = 0.05), so no factor
//! is near zero and the gradient divides by it safely.
//!
//! Cost: O(n²·s) per value or gradient, in parallel over the points; each point's row is
//! summed in a fixed order and the rows are added in order, so the bits do not depend on
//! the thread count.

use crate::{Energy, Error, PointSet, Result};
use rayon::prelude::*;

/// Φ of the module documentation, with product weight γ on every coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TentKernel {
    gamma: f64,
}

/// (2π)⁴/4!: ω(d) = −(2π)⁴ B4(d)/4!.
const C4: f64 = 64.939_394_022_668_28;

impl TentKernel {
    /// The criterion with weight γ > 0 (finite) on every coordinate.
    pub fn new(gamma: f64) -> Result<TentKernel> {
        if !(gamma.is_finite() && gamma > 0.0) {
            return Err(Error::invalid("weight", gamma, "a finite weight above 0"));
        }
        Ok(TentKernel { gamma })
    }

    /// F(d) and F′(d) for a difference d of two coordinates.
    #[inline(always)]
    fn factor(&self, d: f64) -> (f64, f64) {
        let d = d - d.floor();
        let e = d * (1.0 - d);
        let f = 1.0 - self.gamma * C4 * (e * e - 1.0 / 30.0);
        let df = -self.gamma * C4 * 2.0 * e * (1.0 - 2.0 * d);
        (f, df)
    }

    /// Σ_l Π_j F(x_kj − x_lj) for point k, and with `grad` Σ_l P_kl F′/F, its gradient's
    /// row up to the factor 2/n² (2: the pair (k, l) appears as (l, k) too).
    fn row(&self, x: &[f64], s: usize, k: usize, grad: Option<&mut [f64]>) -> f64 {
        let own = &x[k * s..(k + 1) * s];
        let mut sum = 0.0;
        let mut ratios = vec![0.0; s];
        match grad {
            None => {
                for other in x.chunks_exact(s) {
                    let p: f64 = own
                        .iter()
                        .zip(other)
                        .map(|(a, b)| self.factor(a - b).0)
                        .product();
                    sum += p;
                }
            }
            Some(g) => {
                g.fill(0.0);
                for other in x.chunks_exact(s) {
                    let mut p = 1.0;
                    for ((r, a), b) in ratios.iter_mut().zip(own).zip(other) {
                        let (f, df) = self.factor(a - b);
                        p *= f;
                        *r = df / f;
                    }
                    sum += p;
                    for (gj, r) in g.iter_mut().zip(&ratios) {
                        *gj += p * r;
                    }
                }
            }
        }
        sum
    }

    fn evaluate(&self, points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
        let (n, s) = (points.n(), points.s());
        if n == 0 {
            return 0.0;
        }
        let x = points.as_slice();
        let scale = 1.0 / (n as f64 * n as f64);
        let rows: Vec<f64> = match grad {
            None => (0..n)
                .into_par_iter()
                .map(|k| self.row(x, s, k, None))
                .collect(),
            Some(g) => g
                .par_chunks_exact_mut(s)
                .enumerate()
                .map(|(k, gk)| {
                    let r = self.row(x, s, k, Some(&mut *gk));
                    for v in gk.iter_mut() {
                        *v *= 2.0 * scale;
                    }
                    r
                })
                .collect(),
        };
        rows.iter().sum::<f64>() * scale - 1.0
    }
}

impl Energy for TentKernel {
    fn name(&self) -> String {
        format!(
            "mean square error of the shift-and-tent randomisation (weight {})",
            self.gamma
        )
    }

    fn value(&self, points: &PointSet) -> f64 {
        self.evaluate(points, None)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        self.evaluate(points, Some(grad))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(n: usize, z: &[u64]) -> PointSet {
        let x = (0..n as u64)
            .flat_map(|k| {
                z.iter()
                    .map(move |&zj| ((k * zj) % n as u64) as f64 / n as f64)
            })
            .collect();
        PointSet::new(n, z.len(), x).unwrap()
    }

    #[test]
    fn on_a_lattice_it_is_the_lattice_criterion_from_the_fourier_series() {
        // (1/n) Σ_k Π_j (1 + γ Σ_{0<|h|≤H} cos(2πh k z_j/n)/h⁴): the series, not B4.
        let (n, z, gamma) = (31usize, [1u64, 12, 7], 0.05);
        let omega = |x: f64| {
            (1..=20_000)
                .map(|h| {
                    2.0 * (2.0 * std::f64::consts::PI * h as f64 * x).cos() / (h as f64).powi(4)
                })
                .sum::<f64>()
        };
        let series = (0..n)
            .map(|k| {
                z.iter()
                    .map(|&zj| 1.0 + gamma * omega(((k as u64 * zj) % n as u64) as f64 / n as f64))
                    .product::<f64>()
            })
            .sum::<f64>()
            / n as f64
            - 1.0;
        let e = TentKernel::new(gamma).unwrap();
        let v = e.value(&lattice(n, &z));
        assert!((v - series).abs() < 1e-12, "{v} vs {series}");
    }

    #[test]
    fn refuses_a_weight_that_is_not_positive() {
        for g in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let err = TentKernel::new(g).unwrap_err().to_string();
            assert!(err.contains("weight"), "{err}");
        }
    }
}
