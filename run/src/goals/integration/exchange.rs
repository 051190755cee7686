//! The L2 discrepancies whose closed form is a product over coordinates, in plain scalar
//! code, from the factors of their [`DiscrepancyKernel`]s: an independent check of the
//! vectorised kernels behind `stillpoint::metrics` (which compute all five, the mixture
//! included, in one pass), and the O(n) update of a squared discrepancy when two points
//! swap one coordinate — the move of the stratified descent
//! ([`crate::goals::integration`]) and of optimised Latin hypercubes. The plain products
//! here overflow beyond a few hundred dimensions; the metrics do not.
//!
//! Every form here is
//!
//! D² = C^s − (2/n) Σ_i Π_k g(x_ik) + (1/n²) Σ_{i,l} Π_k h(x_ik, x_lk)
//!
//! with C, g and h of the kernel (the table of [`stillpoint_energies::discrepancy`]). On
//! [0, 1) every h is positive, which the swap update relies on (it rescales pair products
//! by ratios of h).

use crate::PointSet;
use rayon::prelude::*;
use stillpoint_energies::discrepancy::{DiscrepancyKernel, DiscrepancyKind};
use stillpoint_energies::with_kernel;
use stillpoint_quality::effort::EXCHANGE_MAX_N;

/// C^s, the constant term (negative for the wrap-around L2), by `powi`.
fn constant<K: DiscrepancyKernel>(s: usize) -> f64 {
    K::CONSTANT_SIGN * K::CONSTANT_BASE.powi(s as i32)
}

/// The single product Π_k g(x_k) of one point, 0 for a kernel without the single sum.
fn single_product<K: DiscrepancyKernel>(x: &[f64]) -> f64 {
    if K::HAS_SINGLE {
        x.iter().map(|&v| K::single_factor(v)).product()
    } else {
        0.0
    }
}

/// Σ_l p_il·(h(x_j, c_l)/h(x_i, c_l) − 1) + p_jl·(h(x_i, c_l)/h(x_j, c_l) − 1) over
/// the slices: the pair part of a swap of x_i and x_j in one coordinate whose values are
/// `column`, for the points whose pair products with i and j are `pi` and `pj`. One
/// division per l: pi·(hj/hi − 1) + pj·(hi/hj − 1) = (pi·hj² + pj·hi²)/(hi·hj) − pi − pj.
pub fn swap_sum<K: DiscrepancyKernel>(
    xi: f64,
    xj: f64,
    pi: &[f64],
    pj: &[f64],
    column: &[f64],
) -> f64 {
    let mut off = 0.0;
    for ((&a, &b), &xl) in pi.iter().zip(pj).zip(column) {
        let (hi, hj) = (K::pair_factor(xi, xl), K::pair_factor(xj, xl));
        off += (a * hj * hj + b * hi * hi) / (hi * hj) - a - b;
    }
    off
}

/// Two points i ≠ j about to swap their values xi ≠ xj of one coordinate, with their single
/// products Π_k g (0 for a form without the single sum).
#[derive(Debug, Clone, Copy)]
pub struct Swap {
    /// The first point.
    pub i: usize,
    /// The second point.
    pub j: usize,
    /// The first point's value of the coordinate.
    pub xi: f64,
    /// The second point's value.
    pub xj: f64,
    /// The single products of i and j.
    pub singles: (f64, f64),
}

/// The change of the squared discrepancy of n = `column.len()` points under `swap`,
/// from the pair-product rows `pi`, `pj` of its two points (over all n points) and
/// `sum`, [`swap_sum`] over all of them (which callers may form in parts). The sum's
/// terms of l = i and l = j are taken out again and the diagonal put in.
pub fn swap_delta<K: DiscrepancyKernel>(
    swap: &Swap,
    pi: &[f64],
    pj: &[f64],
    column: &[f64],
    sum: f64,
) -> f64 {
    let Swap { i, j, xi, xj, .. } = *swap;
    let n = column.len();
    let h = K::pair_factor;
    let single = if K::HAS_SINGLE {
        let (gi, gj) = (K::single_factor(xi), K::single_factor(xj));
        swap.singles.0 * (gj / gi - 1.0) + swap.singles.1 * (gi / gj - 1.0)
    } else {
        0.0
    };
    let term = |l: usize| {
        let xl = column[l];
        let (hi, hj) = (h(xi, xl), h(xj, xl));
        (pi[l] * hj * hj + pj[l] * hi * hi) / (hi * hj) - pi[l] - pj[l]
    };
    let off = sum - (term(i) + term(j));
    let diag = pi[i] * (h(xj, xj) / h(xi, xi) - 1.0) + pj[j] * (h(xi, xi) / h(xj, xj) - 1.0);
    let nf = n as f64;
    -2.0 / nf * single + (2.0 * off + diag) / (nf * nf)
}

/// The squared discrepancy of `points` in the kernel's closed form, clamped at 0 against
/// rounding. O(n² s) time, rows in parallel, summed in row order: the same bits for any
/// number of threads.
pub fn squared<K: DiscrepancyKernel>(points: &PointSet) -> f64 {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let rows: Vec<(f64, f64)> = (0..n)
        .into_par_iter()
        .map(|i| {
            let xi = &x[i * s..(i + 1) * s];
            let single = single_product::<K>(xi);
            let pairs = (0..n)
                .map(|l| {
                    let xl = &x[l * s..(l + 1) * s];
                    xi.iter()
                        .zip(xl)
                        .map(|(&a, &b)| K::pair_factor(a, b))
                        .product::<f64>()
                })
                .sum::<f64>();
            (single, pairs)
        })
        .collect();
    let (single, pairs) = rows
        .iter()
        .fold((0.0, 0.0), |(a, b), &(c, d)| (a + c, b + d));
    let nf = n as f64;
    (constant::<K>(s) - 2.0 / nf * single + pairs / (nf * nf)).max(0.0)
}

/// The root of [`squared`].
pub fn root<K: DiscrepancyKernel>(points: &PointSet) -> f64 {
    squared::<K>(points).sqrt()
}

/// A squared discrepancy kept up to date under swaps of one coordinate between two
/// points, in O(n) per swap: it holds every pair product P_il = Π_k h(x_ik, x_lk) and
/// every single product G_i = Π_k g(x_ik), and rescales the rows of the two points by
/// ratios of factors. Needs every coordinate in [0, 1) (where h > 0).
#[derive(Debug, Clone)]
pub struct Exchange {
    kind: DiscrepancyKind,
    n: usize,
    s: usize,
    x: Vec<f64>,
    /// The coordinates column by column, so the swap loops read one column contiguously.
    columns: Vec<f64>,
    pairs: Vec<f64>,
    single: Vec<f64>,
    value: f64,
    swaps_since_refresh: usize,
}

impl Exchange {
    /// Builds the tables for `points` (O(n² s)); n at most [`EXCHANGE_MAX_N`].
    pub fn new(points: &PointSet, kind: DiscrepancyKind) -> Exchange {
        let (n, s) = (points.n(), points.s());
        debug_assert!(n <= EXCHANGE_MAX_N);
        let mut e = Exchange {
            kind,
            n,
            s,
            x: points.as_slice().to_vec(),
            columns: (0..s)
                .flat_map(|k| points.as_slice()[k..].iter().step_by(s).copied())
                .collect(),
            pairs: vec![0.0; n * n],
            single: vec![0.0; n],
            value: 0.0,
            swaps_since_refresh: 0,
        };
        e.refresh();
        e
    }

    /// Recomputes every table from the coordinates, removing the rounding the ratio
    /// updates accumulate.
    pub fn refresh(&mut self) {
        with_kernel!(self.kind, K => self.refresh_with::<K>())
    }

    fn refresh_with<K: DiscrepancyKernel>(&mut self) {
        let (n, s) = (self.n, self.s);
        let x = &self.x;
        self.pairs
            .par_chunks_mut(n)
            .enumerate()
            .for_each(|(i, row)| {
                let xi = &x[i * s..(i + 1) * s];
                for (l, p) in row.iter_mut().enumerate() {
                    let xl = &x[l * s..(l + 1) * s];
                    *p = xi
                        .iter()
                        .zip(xl)
                        .map(|(&a, &b)| K::pair_factor(a, b))
                        .product();
                }
            });
        for i in 0..n {
            self.single[i] = single_product::<K>(&x[i * s..(i + 1) * s]);
        }
        let single: f64 = self.single.iter().sum();
        let pairs: f64 = self.pairs.iter().sum();
        let nf = n as f64;
        self.value = constant::<K>(s) - 2.0 / nf * single + pairs / (nf * nf);
        self.swaps_since_refresh = 0;
    }

    /// The current squared discrepancy (not clamped).
    pub fn value(&self) -> f64 {
        self.value
    }

    /// The coordinates, row by row.
    pub fn coordinates(&self) -> &[f64] {
        &self.x
    }

    /// The change of the squared discrepancy if points `i` and `j` swapped coordinate `k`.
    pub fn delta(&self, i: usize, j: usize, k: usize) -> f64 {
        with_kernel!(self.kind, K => self.delta_with::<K>(i, j, k))
    }

    fn delta_with<K: DiscrepancyKernel>(&self, i: usize, j: usize, k: usize) -> f64 {
        let (n, s) = (self.n, self.s);
        let (xi, xj) = (self.x[i * s + k], self.x[j * s + k]);
        if i == j || xi == xj {
            return 0.0;
        }
        let (pi, pj) = (
            &self.pairs[i * n..(i + 1) * n],
            &self.pairs[j * n..(j + 1) * n],
        );
        let column = &self.columns[k * n..(k + 1) * n];
        let swap = Swap {
            i,
            j,
            xi,
            xj,
            singles: (self.single[i], self.single[j]),
        };
        swap_delta::<K>(&swap, pi, pj, column, swap_sum::<K>(xi, xj, pi, pj, column))
    }

    /// Swaps coordinate `k` of points `i` and `j`, updating the tables by `delta`, which
    /// must be [`Exchange::delta`] of the same swap.
    pub fn swap(&mut self, i: usize, j: usize, k: usize, delta: f64) {
        with_kernel!(self.kind, K => self.swap_with::<K>(i, j, k, delta))
    }

    fn swap_with<K: DiscrepancyKernel>(&mut self, i: usize, j: usize, k: usize, delta: f64) {
        let (n, s) = (self.n, self.s);
        let h = K::pair_factor;
        let (xi, xj) = (self.x[i * s + k], self.x[j * s + k]);
        if i == j || xi == xj {
            return;
        }
        if K::HAS_SINGLE {
            let g = K::single_factor;
            self.single[i] *= g(xj) / g(xi);
            self.single[j] *= g(xi) / g(xj);
        }
        let (hii, hjj) = (h(xi, xi), h(xj, xj));
        for l in 0..n {
            if l == i || l == j {
                continue;
            }
            let xl = self.x[l * s + k];
            let (hi, hj) = (h(xi, xl), h(xj, xl));
            let (ri, rj) = (hj / hi, hi / hj);
            self.pairs[i * n + l] *= ri;
            self.pairs[l * n + i] *= ri;
            self.pairs[j * n + l] *= rj;
            self.pairs[l * n + j] *= rj;
        }
        self.pairs[i * n + i] *= hjj / hii;
        self.pairs[j * n + j] *= hii / hjj;
        self.x.swap(i * s + k, j * s + k);
        self.columns.swap(k * n + i, k * n + j);
        self.value += delta;
        self.swaps_since_refresh += 1;
        // Each ratio update carries a relative rounding error of a few ulps; a full
        // refresh after n swaps costs as much as n of them and keeps the drift ~1e-13.
        if self.swaps_since_refresh >= n.max(64) * 4 {
            self.refresh_with::<K>();
        }
    }

    /// The current set.
    pub fn points(&self) -> PointSet {
        PointSet::new(self.n, self.s, self.x.clone()).expect("same shape as the start")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stillpoint_energies::discrepancy::{discrepancy_root, Mixture};
    use stillpoint_quality::metrics;

    fn sample(n: usize, s: usize, seed: u64) -> PointSet {
        stillpoint_sequences::random(n, s, seed).unwrap()
    }

    #[test]
    fn scalar_forms_match_the_vectorised_kernels() {
        for (n, s) in [(1, 1), (7, 3), (40, 5)] {
            let p = sample(n, s, 3);
            let close = |what: &str, got: f64, want: f64| {
                assert!(
                    (got - want).abs() <= 1e-12 * want,
                    "{what}: {got} vs {want}"
                );
            };
            for &kind in DiscrepancyKind::ALL {
                let got = with_kernel!(kind, K => root::<K>(&p));
                close(kind.label(), got, discrepancy_root(&p, kind));
            }
            close("mixture", root::<Mixture>(&p), metrics::mixture(&p));
        }
    }

    #[test]
    fn mixture_of_zhou_fang_ning_example_4() {
        // The 7-run, 6-factor two-level design of Zhou, Fang and Ning (2013), Example 4,
        // levels k mapped to (2k − 1)/4, as in SciPy's test_discrepancy: MD² = 2.5000 and
        // WD² = 1.3680 (to 4 digits).
        let design = [
            [2, 1, 1, 2, 2, 2],
            [1, 2, 2, 2, 2, 2],
            [2, 1, 1, 1, 1, 1],
            [1, 1, 1, 1, 2, 2],
            [1, 2, 2, 2, 1, 1],
            [2, 2, 2, 2, 1, 1],
            [2, 2, 2, 1, 2, 2],
        ];
        let rows: Vec<Vec<f64>> = design
            .iter()
            .map(|r| r.iter().map(|&k| (2.0 * k as f64 - 1.0) / 4.0).collect())
            .collect();
        let p = PointSet::from_rows(&rows).unwrap();
        let md2 = squared::<Mixture>(&p);
        assert!((md2 - 2.5000).abs() < 1e-4, "{md2}");
        let wd2 = squared::<stillpoint_energies::discrepancy::Wrap>(&p);
        assert!((wd2 - 1.3680).abs() < 1e-4, "{wd2}");
    }

    #[test]
    fn swap_updates_match_a_recomputation() {
        for &kind in DiscrepancyKind::ALL {
            let p = sample(30, 4, 11);
            let mut e = Exchange::new(&p, kind);
            for (t, (i, j, k)) in [(0, 5, 1), (3, 29, 0), (7, 8, 3), (12, 2, 2)]
                .into_iter()
                .enumerate()
            {
                let d = e.delta(i, j, k);
                let mut q = e.points().into_vec();
                q.swap(i * 4 + k, j * 4 + k);
                let want = with_kernel!(kind, K => squared::<K>(&PointSet::new(30, 4, q).unwrap()));
                e.swap(i, j, k, d);
                // The smoothness-2 errors are −1 plus terms near 1: exact to rounding of 1.
                let scale = if kind.smoothness() == 2 {
                    1.0
                } else {
                    want.abs().max(1e-6)
                };
                assert!(
                    (e.value() - want).abs() < 1e-12 * scale,
                    "{kind:?} swap {t}: {} vs {want}",
                    e.value()
                );
            }
        }
    }
}
