//! The L2 discrepancies whose closed form is a product over coordinates, written once as
//! three factors, in plain scalar code: an independent check of the vectorised kernels
//! behind [`crate::metrics`] (which compute all five, the mixture included, in one pass),
//! and the O(n) update of a squared discrepancy when two points swap one coordinate —
//! the move of the stratified descent ([`crate::goals::integration`]) and of optimised Latin
//! hypercubes. The plain products here overflow beyond a few hundred dimensions; the
//! metrics do not.
//!
//! Every form here is
//!
//! D² = C^s − (2/n) Σ_i Π_k g(x_ik) + (1/n²) Σ_{i,l} Π_k h(x_ik, x_lk)
//!
//! (the wrap-around L2 has a negative constant and no single sum). With a = |x − ½|,
//! b = |y − ½|, d = |x − y|:
//!
//! | form | C | g(x) | h(x, y) |
//! |---|---|---|---|
//! | star L2 (Warnock) | 1/3 | (1 − x²)/2 | 1 − max(x, y) |
//! | modified L2 (the paper's D_MD) | 4/3 | (3 − x²)/2 | 2 − max(x, y) |
//! | centred L2 (SciPy `'CD'`) | 13/12 | 1 + a/2 − a²/2 | 1 + a/2 + b/2 − d/2 |
//! | wrap-around L2 (SciPy `'WD'`) | −4/3 | — | 3/2 − d(1 − d) |
//! | mixture (SciPy `'MD'`) | 19/12 | 5/3 − a/4 − a²/4 | 15/8 − a/4 − b/4 − 3d/4 + d²/2 |
//! | smoothness 2 | −1 | — | 1 + γ(B₁(x)B₁(y) + B₂(x)B₂(y)/4 − B₄(d)/24) |
//!
//! The mixture discrepancy is that of Y.-D. Zhou, K.-T. Fang and J.-H. Ning, *Mixture
//! discrepancy for quasi-random point sets*, J. Complexity 29 (2013); its square is what
//! SciPy's `qmc.discrepancy(method='MD')` returns. On [0, 1) every h is positive, which
//! the swap update relies on (it rescales pair products by ratios of h).

use crate::energies::discrepancy::{DiscrepancyKind, CURVATURE_WEIGHT, SMOOTH_WEIGHT};
use crate::PointSet;
use rayon::prelude::*;

/// A product-form L2 discrepancy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// Star L2 (Warnock's formula, the paper's eq. 46).
    Star,
    /// Modified L2 (Hickernell, the paper's eq. 47).
    Modified,
    /// Centred L2 (Hickernell).
    Centered,
    /// Wrap-around L2 (Hickernell), invariant under periodic shifts.
    WrapAround,
    /// Mixture discrepancy (Zhou, Fang and Ning 2013).
    Mixture,
    /// The worst-case error for integrands of smoothness 2 (Bernoulli polynomials B₁,
    /// B₂, B₄; product weight γ = [`SMOOTH_WEIGHT`]).
    Smooth,
    /// [`Form::Smooth`] with the mean curvature weighed [`CURVATURE_WEIGHT`] times more.
    Curved,
}

impl From<DiscrepancyKind> for Form {
    fn from(kind: DiscrepancyKind) -> Form {
        match kind {
            DiscrepancyKind::StarL2 => Form::Star,
            DiscrepancyKind::ModifiedL2 => Form::Modified,
            DiscrepancyKind::CenteredL2 => Form::Centered,
            DiscrepancyKind::WrapAroundL2 => Form::WrapAround,
            DiscrepancyKind::Smooth => Form::Smooth,
            DiscrepancyKind::Curved => Form::Curved,
        }
    }
}

impl Form {
    /// C^s, the constant term (negative for the wrap-around L2).
    pub fn constant(self, s: usize) -> f64 {
        let s = s as i32;
        match self {
            Form::Star => (1.0f64 / 3.0).powi(s),
            Form::Modified => (4.0f64 / 3.0).powi(s),
            Form::Centered => (13.0f64 / 12.0).powi(s),
            Form::WrapAround => -(4.0f64 / 3.0).powi(s),
            Form::Mixture => (19.0f64 / 12.0).powi(s),
            Form::Smooth | Form::Curved => -1.0,
        }
    }

    /// Whether the form has the single sum Σ_i Π_k g.
    pub fn has_single(self) -> bool {
        !matches!(self, Form::WrapAround | Form::Smooth | Form::Curved)
    }

    /// The factor g of the single sum.
    #[inline]
    pub fn g(self, x: f64) -> f64 {
        let a = (x - 0.5).abs();
        match self {
            Form::Star => 0.5 * (1.0 - x * x),
            Form::Modified => 0.5 * (3.0 - x * x),
            Form::Centered => 1.0 + 0.5 * a - 0.5 * a * a,
            Form::WrapAround | Form::Smooth | Form::Curved => 0.0,
            Form::Mixture => 5.0 / 3.0 - 0.25 * a - 0.25 * a * a,
        }
    }

    /// The factor h of the pair sum (symmetric in x and y).
    #[inline]
    pub fn h(self, x: f64, y: f64) -> f64 {
        let d = (x - y).abs();
        match self {
            Form::Star => 1.0 - x.max(y),
            Form::Modified => 2.0 - x.max(y),
            Form::Centered => 1.0 + 0.5 * (x - 0.5).abs() + 0.5 * (y - 0.5).abs() - 0.5 * d,
            Form::WrapAround => 1.5 - d * (1.0 - d),
            Form::Mixture => {
                1.875 - 0.25 * (x - 0.5).abs() - 0.25 * (y - 0.5).abs() - 0.75 * d + 0.5 * d * d
            }
            Form::Smooth => smooth_h(x, y, d, 0.25),
            Form::Curved => smooth_h(x, y, d, CURVATURE_WEIGHT as f64 * 0.25),
        }
    }
}

/// The smoothness-2 factor with `b2b2` the coefficient of B₂(x)B₂(y), d = |x − y|.
#[inline]
fn smooth_h(x: f64, y: f64, d: f64, b2b2: f64) -> f64 {
    let b2 = |t: f64| t * t - t + 1.0 / 6.0;
    let e = d * (1.0 - d);
    1.0 + SMOOTH_WEIGHT
        * ((x - 0.5) * (y - 0.5) + b2b2 * b2(x) * b2(y) + 1.0 / 720.0 - e * e / 24.0)
}

impl Form {
    /// Σ_l p_il·(h(x_j, c_l)/h(x_i, c_l) − 1) + p_jl·(h(x_i, c_l)/h(x_j, c_l) − 1) over
    /// the slices: the pair part of a swap of x_i and x_j in one coordinate whose values are
    /// `column`, for the points whose pair products with i and j are `pi` and `pj`. h is
    /// dispatched once, outside the loop, so the loop has no branch and vectorises.
    pub fn swap_sum(self, xi: f64, xj: f64, pi: &[f64], pj: &[f64], column: &[f64]) -> f64 {
        match self {
            Form::Star => swap_sum_with(xi, xj, pi, pj, column, |x, y| 1.0 - x.max(y)),
            Form::Modified => swap_sum_with(xi, xj, pi, pj, column, |x, y| 2.0 - x.max(y)),
            Form::Centered => swap_sum_with(xi, xj, pi, pj, column, |x, y| Form::Centered.h(x, y)),
            Form::WrapAround => {
                swap_sum_with(xi, xj, pi, pj, column, |x, y| Form::WrapAround.h(x, y))
            }
            Form::Mixture => swap_sum_with(xi, xj, pi, pj, column, |x, y| Form::Mixture.h(x, y)),
            Form::Smooth => swap_sum_with(xi, xj, pi, pj, column, |x, y| Form::Smooth.h(x, y)),
            Form::Curved => swap_sum_with(xi, xj, pi, pj, column, |x, y| Form::Curved.h(x, y)),
        }
    }
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

impl Form {
    /// The change of the squared discrepancy of n = `column.len()` points under `swap`,
    /// from the pair-product rows `pi`, `pj` of its two points (over all n points) and
    /// `sum`, [`Form::swap_sum`] over all of them (which callers may form in parts). The
    /// sum's terms of l = i and l = j are taken out again and the diagonal put in.
    pub fn swap_delta(self, swap: &Swap, pi: &[f64], pj: &[f64], column: &[f64], sum: f64) -> f64 {
        let Swap { i, j, xi, xj, .. } = *swap;
        let n = column.len();
        let (gi, gj) = (self.g(xi), self.g(xj));
        let single = if self.has_single() {
            swap.singles.0 * (gj / gi - 1.0) + swap.singles.1 * (gi / gj - 1.0)
        } else {
            0.0
        };
        let term = |l: usize| {
            let xl = column[l];
            let (hi, hj) = (self.h(xi, xl), self.h(xj, xl));
            (pi[l] * hj * hj + pj[l] * hi * hi) / (hi * hj) - pi[l] - pj[l]
        };
        let off = sum - (term(i) + term(j));
        let diag = pi[i] * (self.h(xj, xj) / self.h(xi, xi) - 1.0)
            + pj[j] * (self.h(xi, xi) / self.h(xj, xj) - 1.0);
        let nf = n as f64;
        -2.0 / nf * single + (2.0 * off + diag) / (nf * nf)
    }
}

/// [`Form::swap_sum`] with h known at compile time. One division per l:
/// pi·(hj/hi − 1) + pj·(hi/hj − 1) = (pi·hj² + pj·hi²)/(hi·hj) − pi − pj.
#[inline(always)]
fn swap_sum_with(
    xi: f64,
    xj: f64,
    pi: &[f64],
    pj: &[f64],
    column: &[f64],
    h: impl Fn(f64, f64) -> f64,
) -> f64 {
    let mut off = 0.0;
    for ((&a, &b), &xl) in pi.iter().zip(pj).zip(column) {
        let (hi, hj) = (h(xi, xl), h(xj, xl));
        off += (a * hj * hj + b * hi * hi) / (hi * hj) - a - b;
    }
    off
}

/// The squared discrepancy of `points` in the form's closed form, clamped at 0 against
/// rounding. O(n² s) time, rows in parallel, summed in row order: the same bits for any
/// number of threads.
pub fn squared(points: &PointSet, form: Form) -> f64 {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let rows: Vec<(f64, f64)> = (0..n)
        .into_par_iter()
        .map(|i| {
            let xi = &x[i * s..(i + 1) * s];
            let single = if form.has_single() {
                xi.iter().map(|&v| form.g(v)).product()
            } else {
                0.0
            };
            let pairs = (0..n)
                .map(|l| {
                    let xl = &x[l * s..(l + 1) * s];
                    xi.iter()
                        .zip(xl)
                        .map(|(&a, &b)| form.h(a, b))
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
    (form.constant(s) - 2.0 / nf * single + pairs / (nf * nf)).max(0.0)
}

/// The root of [`squared`].
pub fn root(points: &PointSet, form: Form) -> f64 {
    squared(points, form).sqrt()
}

/// Most points whose pair table [`Exchange`] keeps (n² values: 134 MB at this n).
pub const EXCHANGE_MAX_N: usize = 4096;

/// A squared discrepancy kept up to date under swaps of one coordinate between two
/// points, in O(n) per swap: it holds every pair product P_il = Π_k h(x_ik, x_lk) and
/// every single product G_i = Π_k g(x_ik), and rescales the rows of the two points by
/// ratios of factors. Needs every coordinate in [0, 1) (where h > 0).
#[derive(Debug, Clone)]
pub struct Exchange {
    form: Form,
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
    pub fn new(points: &PointSet, form: Form) -> Exchange {
        let (n, s) = (points.n(), points.s());
        debug_assert!(n <= EXCHANGE_MAX_N);
        let mut e = Exchange {
            form,
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
        let (n, s, form) = (self.n, self.s, self.form);
        let x = &self.x;
        self.pairs
            .par_chunks_mut(n)
            .enumerate()
            .for_each(|(i, row)| {
                let xi = &x[i * s..(i + 1) * s];
                for (l, p) in row.iter_mut().enumerate() {
                    let xl = &x[l * s..(l + 1) * s];
                    *p = xi.iter().zip(xl).map(|(&a, &b)| form.h(a, b)).product();
                }
            });
        for i in 0..n {
            self.single[i] = if form.has_single() {
                x[i * s..(i + 1) * s].iter().map(|&v| form.g(v)).product()
            } else {
                0.0
            };
        }
        let single: f64 = self.single.iter().sum();
        let pairs: f64 = self.pairs.iter().sum();
        let nf = n as f64;
        self.value = form.constant(s) - 2.0 / nf * single + pairs / (nf * nf);
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
        let (n, s, form) = (self.n, self.s, self.form);
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
        form.swap_delta(&swap, pi, pj, column, form.swap_sum(xi, xj, pi, pj, column))
    }

    /// Swaps coordinate `k` of points `i` and `j`, updating the tables by `delta`, which
    /// must be [`Exchange::delta`] of the same swap.
    pub fn swap(&mut self, i: usize, j: usize, k: usize, delta: f64) {
        let (n, s, form) = (self.n, self.s, self.form);
        let (xi, xj) = (self.x[i * s + k], self.x[j * s + k]);
        if i == j || xi == xj {
            return;
        }
        if form.has_single() {
            self.single[i] *= form.g(xj) / form.g(xi);
            self.single[j] *= form.g(xi) / form.g(xj);
        }
        let (hii, hjj) = (form.h(xi, xi), form.h(xj, xj));
        for l in 0..n {
            if l == i || l == j {
                continue;
            }
            let xl = self.x[l * s + k];
            let (hi, hj) = (form.h(xi, xl), form.h(xj, xl));
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
            self.refresh();
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
    use crate::quality::metrics;

    fn sample(n: usize, s: usize, seed: u64) -> PointSet {
        crate::sequences::random(n, s, seed).unwrap()
    }

    #[test]
    fn scalar_forms_match_the_vectorised_kernels() {
        for (n, s) in [(1, 1), (7, 3), (40, 5)] {
            let p = sample(n, s, 3);
            for (form, want) in [
                (Form::Star, metrics::star_l2(&p)),
                (Form::Modified, metrics::modified_l2(&p)),
                (Form::Centered, metrics::centered_l2(&p)),
                (Form::WrapAround, metrics::wrap_around_l2(&p)),
                (Form::Mixture, metrics::mixture(&p)),
                (
                    Form::Smooth,
                    crate::energies::discrepancy::discrepancy_root(&p, DiscrepancyKind::Smooth),
                ),
                (
                    Form::Curved,
                    crate::energies::discrepancy::discrepancy_root(&p, DiscrepancyKind::Curved),
                ),
            ] {
                let got = root(&p, form);
                assert!(
                    (got - want).abs() <= 1e-12 * want,
                    "{form:?}: {got} vs {want}"
                );
            }
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
        let md2 = squared(&p, Form::Mixture);
        assert!((md2 - 2.5000).abs() < 1e-4, "{md2}");
        let wd2 = squared(&p, Form::WrapAround);
        assert!((wd2 - 1.3680).abs() < 1e-4, "{wd2}");
    }

    #[test]
    fn swap_updates_match_a_recomputation() {
        for form in [
            Form::Star,
            Form::Modified,
            Form::Centered,
            Form::WrapAround,
            Form::Mixture,
            Form::Smooth,
            Form::Curved,
        ] {
            let p = sample(30, 4, 11);
            let mut e = Exchange::new(&p, form);
            for (t, (i, j, k)) in [(0, 5, 1), (3, 29, 0), (7, 8, 3), (12, 2, 2)]
                .into_iter()
                .enumerate()
            {
                let d = e.delta(i, j, k);
                let mut q = e.points().into_vec();
                q.swap(i * 4 + k, j * 4 + k);
                let want = squared(&PointSet::new(30, 4, q).unwrap(), form);
                e.swap(i, j, k, d);
                // The smoothness-2 error is −1 plus terms near 1: exact to rounding of 1.
                let scale = if matches!(form, Form::Smooth | Form::Curved) {
                    1.0
                } else {
                    want.abs().max(1e-6)
                };
                assert!(
                    (e.value() - want).abs() < 1e-12 * scale,
                    "{form:?} swap {t}: {} vs {want}",
                    e.value()
                );
            }
        }
    }
}
