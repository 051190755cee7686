//! The energy distance to a target distribution, as a potential energy: what a set must
//! lower to represent the uniform distribution on a region (rather than to fill it).
//!
//! For a set x_1 … x_n and a target distribution μ the energy distance is
//!
//! D²(x, μ) = (2/n) Σ_i E_Y|x_i − Y| − (1/n²) Σ_{i,j} |x_i − x_j| − E|Y − Y′|,
//!
//! the maximum mean discrepancy with the kernel −|x − y| (Székely–Rizzo); it is ≥ 0 and 0
//! only for the set's empirical measure equal to μ. The last term does not depend on the
//! set and is left out, so [`EnergyDistance`] is D² up to a constant. Its pair term is a
//! repulsion (each pair adds −|x_i − x_j|), its first an attraction towards μ's mass.
//! E_Y|x − Y| is the mean over a fixed reference sample y_1 … y_m of μ: with a
//! low-discrepancy reference of m ≫ n points the set cannot fit the reference's own
//! error, which is far below the n-point set's distance to μ.
//!
//! Cost: O(n·m·s) for the attraction (in parallel over the points, each point's sums in a
//! fixed order, so the bits do not depend on the thread count) and O(n²·s) for the pairs.

use crate::{Energy, Error, PointSet, Result};
use rayon::prelude::*;

/// D²(x, μ) − E|Y − Y′| for the distribution μ of a reference sample (see the module
/// documentation). The gradient is exact; at a point that coincides with another (or
/// with a reference point) the zero vector is used, a subgradient of |·| there.
#[derive(Debug, Clone)]
pub struct EnergyDistance {
    reference: PointSet,
    /// The reference coordinate by coordinate (coordinate c of point k at c·m + k), so
    /// that the kernel reads [`BLOCK`] consecutive reference points per load.
    columns: Vec<f64>,
}

/// Reference points handled together by the kernel: independent lanes the compiler
/// turns into vector instructions.
const BLOCK: usize = 64;

/// Independent partial sums of a block's reductions (a fixed order, so fixed bits).
const LANES: usize = 8;

impl EnergyDistance {
    /// The energy distance to the distribution of `reference` (at least one point).
    pub fn new(reference: PointSet) -> Result<Self> {
        if reference.n() == 0 {
            return Err(Error::invalid(
                "reference sample",
                "0 points",
                "at least 1 point",
            ));
        }
        let (m, s) = (reference.n(), reference.s());
        let mut columns = vec![0.0; m * s];
        for (k, y) in reference.rows().enumerate() {
            for (c, v) in y.iter().enumerate() {
                columns[c * m + k] = *v;
            }
        }
        Ok(EnergyDistance { reference, columns })
    }

    /// The reference sample.
    pub fn reference(&self) -> &PointSet {
        &self.reference
    }

    /// Σ_i (1/m) Σ_k |x_i − y_k|, with the gradient of each term written to `grad` when
    /// given, scaled by `scale`.
    fn attraction(&self, points: &PointSet, grad: Option<&mut [f64]>, scale: f64) -> f64 {
        let s = points.s();
        let m = self.reference.n() as f64;
        let row_mean = |x: &[f64], g: Option<&mut [f64]>| -> f64 {
            let total = match g {
                None => self.row_sum(x, None),
                Some(g) => {
                    let total = self.row_sum(x, Some(&mut *g));
                    g.iter_mut().for_each(|v| *v *= scale / m);
                    total
                }
            };
            total / m
        };
        let rows: Vec<f64> = match grad {
            None => points
                .as_slice()
                .par_chunks_exact(s)
                .map(|x| row_mean(x, None))
                .collect(),
            Some(grad) => points
                .as_slice()
                .par_chunks_exact(s)
                .zip(grad.par_chunks_exact_mut(s))
                .map(|(x, g)| row_mean(x, Some(g)))
                .collect(),
        };
        rows.iter().sum()
    }
}

impl EnergyDistance {
    /// Σ_k |x − y_k|, and Σ_k (x − y_k)/|x − y_k| written to `g` when given: whole
    /// blocks of [`BLOCK`] reference points in lanes, the rest one by one.
    fn row_sum(&self, x: &[f64], mut g: Option<&mut [f64]>) -> f64 {
        let (m, s) = (self.reference.n(), self.reference.s());
        if let Some(g) = g.as_deref_mut() {
            g.iter_mut().for_each(|v| *v = 0.0);
        }
        let mut totals = [0.0; BLOCK];
        let mut d2 = [0.0; BLOCK];
        let mut inv = [0.0; BLOCK];
        let full = m / BLOCK * BLOCK;
        for base in (0..full).step_by(BLOCK) {
            d2.fill(0.0);
            for (c, xc) in x.iter().enumerate() {
                let col = &self.columns[c * m + base..c * m + base + BLOCK];
                for (d, y) in d2.iter_mut().zip(col) {
                    let t = xc - y;
                    *d += t * t;
                }
            }
            for ((d, i), tot) in d2.iter().zip(inv.iter_mut()).zip(totals.iter_mut()) {
                let r = d.sqrt();
                *tot += r;
                *i = if r > 0.0 { 1.0 / r } else { 0.0 };
            }
            if let Some(g) = g.as_deref_mut() {
                for (c, xc) in x.iter().enumerate() {
                    let col = &self.columns[c * m + base..c * m + base + BLOCK];
                    let mut acc = [0.0; LANES];
                    for (yc, ic) in col.chunks_exact(LANES).zip(inv.chunks_exact(LANES)) {
                        for ((a, y), i) in acc.iter_mut().zip(yc).zip(ic) {
                            *a += (xc - y) * i;
                        }
                    }
                    g[c] += acc.iter().sum::<f64>();
                }
            }
        }
        let mut total: f64 = totals.iter().sum();
        for yk in self.reference.as_slice()[full * s..].chunks_exact(s) {
            let d = distance(x, yk);
            total += d;
            if let (Some(g), true) = (g.as_deref_mut(), d > 0.0) {
                for ((gk, a), b) in g.iter_mut().zip(x).zip(yk) {
                    *gk += (a - b) / d;
                }
            }
        }
        total
    }
}

/// Euclidean distance.
#[inline]
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(u, v)| (u - v) * (u - v))
        .sum::<f64>()
        .sqrt()
}

/// Σ_{i<j} |x_i − x_j|, with `scale` × its gradient added to `grad` when given. One
/// thread, in a fixed order: at n ≤ a few thousand this is a small part of the
/// attraction's O(n·m·s).
pub fn pair_distance_sum(points: &PointSet, mut grad: Option<&mut [f64]>, scale: f64) -> f64 {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let mut total = 0.0;
    for i in 0..n {
        let xi = &x[i * s..(i + 1) * s];
        for j in i + 1..n {
            let xj = &x[j * s..(j + 1) * s];
            let d = distance(xi, xj);
            total += d;
            if let (Some(g), true) = (grad.as_deref_mut(), d > 0.0) {
                for k in 0..s {
                    let f = scale * (xi[k] - xj[k]) / d;
                    g[i * s + k] += f;
                    g[j * s + k] -= f;
                }
            }
        }
    }
    total
}

impl Energy for EnergyDistance {
    fn name(&self) -> String {
        format!(
            "energy distance to a reference sample of {} points",
            self.reference.n()
        )
    }

    fn value(&self, points: &PointSet) -> f64 {
        let n = points.n() as f64;
        2.0 / n * self.attraction(points, None, 0.0)
            - 2.0 / (n * n) * pair_distance_sum(points, None, 0.0)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        let n = points.n() as f64;
        let a = self.attraction(points, Some(&mut *grad), 2.0 / n);
        let p = pair_distance_sum(points, Some(grad), -2.0 / (n * n));
        2.0 / n * a - 2.0 / (n * n) * p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Domain, PeriodicCube};

    #[test]
    fn gradient_matches_finite_differences() {
        let cube = PeriodicCube::new(3).unwrap();
        let reference = cube.sample(300, 1).unwrap();
        let e = EnergyDistance::new(reference).unwrap();
        let x = cube.sample(12, 2).unwrap();
        let mut g = vec![0.0; x.coordinate_count()];
        let v = e.value_and_gradient(&x, &mut g);
        assert!((v - e.value(&x)).abs() < 1e-12 * v.abs().max(1.0));
        let h = 1e-6;
        for (c, gc) in g.iter().enumerate() {
            let mut up = x.clone();
            up.as_mut_slice()[c] += h;
            let mut down = x.clone();
            down.as_mut_slice()[c] -= h;
            let fd = (e.value(&up) - e.value(&down)) / (2.0 * h);
            assert!(
                (fd - gc).abs() < 1e-6 * (1.0 + gc.abs()),
                "coordinate {c}: analytic {gc} finite difference {fd}"
            );
        }
    }

    #[test]
    fn pair_sum_counts_each_pair_once() {
        let x = PointSet::from_rows(&[[0.0, 0.0], [3.0, 4.0], [0.0, 1.0]]).unwrap();
        let brute: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| distance(x.point(i), x.point(j)))
            .sum();
        assert!((pair_distance_sum(&x, None, 0.0) - brute / 2.0).abs() < 1e-12);
    }
}
