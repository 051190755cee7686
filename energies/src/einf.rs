//! U_{E,∞}: the inverse minimum distance, with its active-pair subgradient (eq. 19).
//!
//! U_{E,∞}(X) = max_{i<j} 1/d_ij = 1/d_min (eq. 3, the p → ∞ limit of eq. 5 by eq. 6),
//! with the Euclidean distance (eq. 8) or the torus distance (eq. 9, for the periodic
//! cube). Maximising the minimum distance of a set is minimising this energy.
//!
//! The energy is a maximum of smooth pieces 1/d_ij, so it is differentiable only where a
//! single pair is closest. Its subgradient (eq. 19, G = 1) acts on the active pairs only:
//! ∂(1/d_ij)/∂x_i = −a_ij/d_ij³ with a_ij = x_i − x_j (the minimum-image difference on
//! the torus), and the opposite on x_j.
//!
//! **Ties.** A pair is active when d_ij ≤ d_min·(1 + τ), τ the relative tie tolerance
//! (1e-9 by default). All active pairs share the subgradient equally: it is the mean of
//! their gradients, a convex combination, hence an element of the (Clarke) subdifferential
//! of the maximum when the ties are exact. Equal weights keep the result independent of
//! the pair order and symmetric under relabelling; the tolerance absorbs the rounding that
//! makes ties of a symmetric configuration (a lattice, a square) unequal in floating point.
//!
//! **Coincident points.** d_min = 0 gives U = +∞; a coincident pair has no direction, so
//! its contribution to the subgradient is zero (never a NaN).
//!
//! **Determinism.** d_min is a minimum, which does not depend on the order of evaluation;
//! the active pairs are collected in index order (i, then j) and accumulated sequentially,
//! so value and subgradient have the same bits for any number of rayon threads.

use crate::{Distance, Energy, Error, PointSet, Result};
use rayon::prelude::*;

/// Default relative tie tolerance τ: pairs within d_min·(1 + τ) are active.
pub const DEFAULT_TIE_TOLERANCE: f64 = 1e-9;

/// The distances this module supports (a q-distance has no useful max-form energy here).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Metric {
    Euclidean,
    Torus,
}

impl Metric {
    /// For the signed coordinate difference δ returns (contribution to d², component of
    /// the difference vector a whose length is d).
    #[inline]
    pub(crate) fn coord(self, delta: f64) -> (f64, f64) {
        match self {
            Metric::Euclidean => (delta * delta, delta),
            Metric::Torus => {
                // Reduce to [0, 1): the torus distance has period 1.
                let a = delta.abs();
                let a = if a < 1.0 { a } else { a - a.floor() };
                let sg = if delta < 0.0 { -1.0 } else { 1.0 };
                if a < 0.5 {
                    (a * a, sg * a)
                } else if a > 0.5 {
                    let t = 1.0 - a;
                    (t * t, -sg * t)
                } else {
                    // Δ = 1/2: both images are equally near, the coordinate's
                    // subdifferential is [−1/2, 1/2]; 0 is its middle (as in U_{q,p}).
                    (0.25, 0.0)
                }
            }
        }
    }

    #[inline]
    pub(crate) fn d2(self, a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| self.coord(x - y).0).sum()
    }
}

/// One pass over all pairs: the smallest squared distance, and per row the pairs that
/// can still be active once the global minimum is known.
pub(crate) struct PairScan {
    /// min_{i<j} d_ij² (+∞ for fewer than two points).
    pub(crate) min_d2: f64,
    /// Row i holds (j, d_ij²), j > i ascending, for the pairs within the tie band of the
    /// row's own minimum. The global minimum is not larger than a row's, so every pair
    /// within the global band is here.
    rows: Vec<Vec<(usize, f64)>>,
}

impl PairScan {
    /// Scans all pairs; `band` is (1 + τ)², and candidates are kept only if `collect`.
    pub(crate) fn new(points: &PointSet, metric: Metric, band: f64, collect: bool) -> Self {
        let (n, s) = (points.n(), points.s());
        let x = points.as_slice();
        let per_row: Vec<(f64, Vec<(usize, f64)>)> = (0..n)
            .into_par_iter()
            .map(|i| {
                let xi = &x[i * s..(i + 1) * s];
                let mut m = f64::INFINITY;
                let mut cand = Vec::new();
                for j in i + 1..n {
                    let d2 = metric.d2(xi, &x[j * s..(j + 1) * s]);
                    if d2 < m {
                        m = d2;
                        if collect {
                            // Thresholds only shrink, so pruning now never drops a pair
                            // that the final row band would keep.
                            let thr = m * band;
                            cand.retain(|&(_, e)| e <= thr);
                        }
                    }
                    if collect && d2 <= m * band {
                        cand.push((j, d2));
                    }
                }
                (m, cand)
            })
            .collect();
        let min_d2 = per_row.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
        PairScan {
            min_d2,
            rows: per_row.into_iter().map(|r| r.1).collect(),
        }
    }

    /// The pairs (i, j, d_ij²) with d_ij² ≤ `thr2`, in index order.
    pub(crate) fn within(&self, thr2: f64) -> Vec<(usize, usize, f64)> {
        self.rows
            .iter()
            .enumerate()
            .flat_map(|(i, row)| {
                row.iter()
                    .filter(move |&&(_, d2)| d2 <= thr2)
                    .map(move |&(j, d2)| (i, j, d2))
            })
            .collect()
    }
}

/// Checks a relative tie tolerance: finite and ≥ 0.
pub(crate) fn check_tie_tolerance(rel_tol: f64) -> Result<f64> {
    if rel_tol.is_finite() && rel_tol >= 0.0 {
        Ok(rel_tol)
    } else {
        Err(Error::invalid(
            "tie tolerance",
            rel_tol,
            "a finite relative tolerance ≥ 0 (default 1e-9)",
        ))
    }
}

/// Adds `weight`·∇_{x_i}(1/d_ij) to row i and its negative to row j, for a pair with
/// squared distance `d2`. A coincident pair (d = 0) or one at non-finite distance adds
/// nothing: its direction is undefined.
#[inline]
pub(crate) fn add_pair_subgradient(
    x: &[f64],
    s: usize,
    metric: Metric,
    (i, j, d2): (usize, usize, f64),
    weight: f64,
    grad: &mut [f64],
) {
    if !(d2 > 0.0 && d2.is_finite()) {
        return;
    }
    let d = d2.sqrt();
    // −a/d³ = −(a/d)·(1/d²): the unit vector stays finite even when 1/d² overflows.
    let mag = weight / d2;
    for k in 0..s {
        let a = metric.coord(x[i * s + k] - x[j * s + k]).1;
        if a != 0.0 {
            let c = (a / d) * mag;
            grad[i * s + k] -= c;
            grad[j * s + k] += c;
        }
    }
}

/// The energy U_{E,∞} = 1/min_{i<j} d_ij (eqs. 3 and 6, G = 1) with the active-pair
/// subgradient of eq. 19; see the module documentation for the tie rule.
///
/// It needs only the points, so it applies in the cube (torus distance) and in any region
/// (Euclidean distance). For a region with a boundary see
/// [`UEInfG`](crate::boundary::UEInfG), which also keeps points off the boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct UEInf {
    metric: Metric,
    rel_tol: f64,
}

impl UEInf {
    /// U_{E,∞} with the Euclidean distance (eq. 8) or the torus distance (eq. 9).
    /// A q-distance is refused: the paper defines U_∞ with these two only.
    pub fn new(distance: Distance) -> Result<Self> {
        let metric = match distance {
            Distance::Euclidean => Metric::Euclidean,
            Distance::Torus => Metric::Torus,
            Distance::Q(q) => {
                return Err(Error::invalid(
                    "distance",
                    format!("q = {q}"),
                    "`E` (Euclidean, eq. 8) or `inf` (torus, eq. 9) for U_{E,∞}",
                ))
            }
        };
        Ok(UEInf {
            metric,
            rel_tol: DEFAULT_TIE_TOLERANCE,
        })
    }

    /// Sets the relative tie tolerance τ (finite, ≥ 0; default 1e-9): pairs with
    /// d_ij ≤ d_min·(1 + τ) are active and share the subgradient equally.
    pub fn with_tie_tolerance(mut self, rel_tol: f64) -> Result<Self> {
        self.rel_tol = check_tie_tolerance(rel_tol)?;
        Ok(self)
    }

    /// The relative tie tolerance τ.
    pub fn tie_tolerance(&self) -> f64 {
        self.rel_tol
    }

    /// The distance in use.
    pub fn distance(&self) -> Distance {
        match self.metric {
            Metric::Euclidean => Distance::Euclidean,
            Metric::Torus => Distance::Torus,
        }
    }

    /// The smallest pair distance d_min (+∞ for fewer than two points).
    pub fn min_distance(&self, points: &PointSet) -> f64 {
        PairScan::new(points, self.metric, 1.0, false).min_d2.sqrt()
    }

    /// The active pairs (i < j) in index order: those with d_ij ≤ d_min·(1 + τ).
    pub fn active_pairs(&self, points: &PointSet) -> Vec<(usize, usize)> {
        let band = self.band();
        let scan = PairScan::new(points, self.metric, band, true);
        scan.within(scan.min_d2 * band)
            .into_iter()
            .map(|(i, j, _)| (i, j))
            .collect()
    }

    fn band(&self) -> f64 {
        (1.0 + self.rel_tol) * (1.0 + self.rel_tol)
    }
}

/// Named `U_{E,∞}` with the Euclidean distance and `U_{T,∞}` with the torus distance.
impl Energy for UEInf {
    fn name(&self) -> String {
        // d_T is the paper's name for the torus distance (eq. 9).
        match self.metric {
            Metric::Euclidean => "U_{E,∞}".to_string(),
            Metric::Torus => "U_{T,∞}".to_string(),
        }
    }

    fn is_smooth(&self) -> bool {
        false
    }

    fn value(&self, points: &PointSet) -> f64 {
        if points.n() < 2 {
            return 0.0;
        }
        1.0 / self.min_distance(points)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(
            grad.len(),
            points.coordinate_count(),
            "gradient buffer length"
        );
        grad.fill(0.0);
        if points.n() < 2 {
            return 0.0;
        }
        let band = self.band();
        let scan = PairScan::new(points, self.metric, band, true);
        let active = scan.within(scan.min_d2 * band);
        let weight = 1.0 / active.len() as f64;
        let (x, s) = (points.as_slice(), points.s());
        for &pair in &active {
            add_pair_subgradient(x, s, self.metric, pair, weight, grad);
        }
        1.0 / scan.min_d2.sqrt()
    }
}
