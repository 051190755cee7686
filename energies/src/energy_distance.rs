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
//! Cost: O(n·m·s) for the attraction and O(n²·s) for the pairs, both in parallel over the
//! points (each point's sums in a fixed order, so the bits do not depend on the thread
//! count).

use crate::{Energy, Error, PointSet, Result};
use rayon::prelude::*;

/// D²(x, μ) − E|Y − Y′| for the distribution μ of a reference sample (see the module
/// documentation). The gradient is exact; at a point that coincides with another (or
/// with a reference point) the zero vector is used, a subgradient of |·| there.
#[derive(Debug, Clone)]
pub struct EnergyDistance {
    reference: PointSet,
    /// The reference coordinate by coordinate, for [`row_sum`].
    columns: Vec<f64>,
}

/// Points handled together by [`row_sum`]: independent lanes the compiler turns into
/// vector instructions.
const BLOCK: usize = 64;

/// Independent partial sums of a block's reductions (a fixed order, so fixed bits).
const LANES: usize = 8;

/// `points` coordinate by coordinate (coordinate c of point k at c·m + k), so that
/// [`row_sum`] reads [`BLOCK`] consecutive points per load.
fn columns_of(points: &PointSet) -> Vec<f64> {
    let (m, s) = (points.n(), points.s());
    let mut columns = vec![0.0; m * s];
    for (k, y) in points.rows().enumerate() {
        for (c, v) in y.iter().enumerate() {
            columns[c * m + k] = *v;
        }
    }
    columns
}

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
        let columns = columns_of(&reference);
        Ok(EnergyDistance { reference, columns })
    }

    /// The reference sample.
    pub fn reference(&self) -> &PointSet {
        &self.reference
    }

    /// The energy and, when `grad` is given, its gradient written there. Attraction and
    /// repulsion are summed point by point in one parallel pass; each point's whole row
    /// of pairs is summed (every pair twice, halved), which costs twice the pairs of a
    /// triangle but runs on every core in [`row_sum`]'s vector lanes. Each point's sums
    /// have a fixed order and the points' totals are added in index order, so the bits do
    /// not depend on the thread count.
    fn evaluate(&self, points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
        let (n, s) = (points.n(), points.s());
        let (nf, m) = (n as f64, self.reference.n() as f64);
        let (attract, repel) = (2.0 / (nf * m), 2.0 / (nf * nf));
        let own = columns_of(points);
        let reference = (self.columns.as_slice(), self.reference.as_slice());
        let pairs = (own.as_slice(), points.as_slice());
        let rows: Vec<(f64, f64)> = match grad {
            None => points
                .as_slice()
                .par_chunks_exact(s)
                .map(|x| {
                    // Ctrl-C in Python: the caller discards the partial sum.
                    if crate::stop::requested() {
                        return (0.0, 0.0);
                    }
                    (row_sum(reference, x, None), row_sum(pairs, x, None))
                })
                .collect(),
            Some(grad) => points
                .as_slice()
                .par_chunks_exact(s)
                .zip(grad.par_chunks_exact_mut(s))
                .map(|(x, g)| {
                    let mut gp = vec![0.0; s];
                    let a = row_sum(reference, x, Some(&mut *g));
                    let p = row_sum(pairs, x, Some(&mut gp));
                    for (gk, pk) in g.iter_mut().zip(&gp) {
                        *gk = attract * *gk - repel * pk;
                    }
                    (a, p)
                })
                .collect(),
        };
        let a: f64 = rows.iter().map(|r| r.0).sum();
        let p: f64 = rows.iter().map(|r| r.1).sum();
        attract * a - 0.5 * repel * p
    }
}

/// Σ_k |x − y_k| over the points y of (`columns`, `rows`) (one set, coordinate by
/// coordinate and point by point), and Σ_k (x − y_k)/|x − y_k| written to `g` when given.
/// Compiled twice, for AVX2 where the processor has it and portably: the lanes are
/// explicit and no multiply–add is fused, so both give the same bits, twice the lanes
/// for AVX2.
fn row_sum(set: (&[f64], &[f64]), x: &[f64], g: Option<&mut [f64]>) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if crate::pairs::use_avx2() {
        // SAFETY: the processor has AVX2 (checked by `use_avx2`, which also honours
        // `STILLPOINT_PORTABLE`).
        return unsafe { row_sum_avx2(set, x, g) };
    }
    row_sum_lanes(set, x, g)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn row_sum_avx2(set: (&[f64], &[f64]), x: &[f64], g: Option<&mut [f64]>) -> f64 {
    row_sum_lanes(set, x, g)
}

/// [`row_sum`]'s body: whole blocks of [`BLOCK`] points in lanes, the rest one by one.
#[inline(always)]
fn row_sum_lanes((columns, rows): (&[f64], &[f64]), x: &[f64], mut g: Option<&mut [f64]>) -> f64 {
    let s = x.len();
    let m = rows.len() / s;
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
            let col = &columns[c * m + base..c * m + base + BLOCK];
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
                let col = &columns[c * m + base..c * m + base + BLOCK];
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
    for yk in rows[full * s..].chunks_exact(s) {
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

/// Euclidean distance.
#[inline]
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(u, v)| (u - v) * (u - v))
        .sum::<f64>()
        .sqrt()
}

/// Σ_{i<j} |x_i − x_j|: every point's row of distances in parallel (`row_sum`'s lanes),
/// halved; the rows are added in index order, so the bits do not depend on the thread
/// count.
pub fn pair_distance_sum(points: &PointSet) -> f64 {
    0.5 * cross_distance_sum(points, points)
}

/// Σ_i Σ_k |x_i − y_k| over two sets of the same dimension, in parallel over the x_i and
/// added in index order (fixed bits).
pub fn cross_distance_sum(x: &PointSet, y: &PointSet) -> f64 {
    let columns = columns_of(y);
    let set = (columns.as_slice(), y.as_slice());
    let rows: Vec<f64> = x
        .as_slice()
        .par_chunks_exact(x.s())
        .map(|xi| {
            // Ctrl-C in Python: the caller discards the partial sum.
            if crate::stop::requested() {
                return 0.0;
            }
            row_sum(set, xi, None)
        })
        .collect();
    rows.iter().sum()
}

impl Energy for EnergyDistance {
    fn name(&self) -> String {
        format!(
            "energy distance to a reference sample of {} points",
            self.reference.n()
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
    fn every_build_of_the_row_kernel_gives_the_same_bits() {
        let cube = PeriodicCube::new(5).unwrap();
        let y = cube.sample(300, 3).unwrap();
        let columns = columns_of(&y);
        let set = (columns.as_slice(), y.as_slice());
        for x in cube.sample(7, 4).unwrap().rows() {
            let (mut g1, mut g2) = (vec![0.0; 5], vec![0.0; 5]);
            let a = row_sum(set, x, Some(&mut g1));
            let b = row_sum_lanes(set, x, Some(&mut g2));
            assert_eq!(a.to_bits(), b.to_bits());
            assert_eq!(g1, g2);
            assert!(a > 0.0 && g1.iter().any(|v| *v != 0.0));
        }
    }

    #[test]
    fn pair_sum_counts_each_pair_once() {
        let x = PointSet::from_rows(&[[0.0, 0.0], [3.0, 4.0], [0.0, 1.0]]).unwrap();
        let brute: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| distance(x.point(i), x.point(j)))
            .sum();
        assert!((pair_distance_sum(&x) - brute / 2.0).abs() < 1e-12);
        let y = PointSet::from_rows(&[[1.0, 0.0]]).unwrap();
        let cross = 1.0 + (4.0f64 + 16.0).sqrt() + 2.0f64.sqrt();
        assert!((cross_distance_sum(&x, &y) - cross).abs() < 1e-12);
    }
}
