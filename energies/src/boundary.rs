//! Boundary-aware energies for regions: U_{E,∞,g} (eqs. 56–57) and a smooth finite-p variant.
//!
//! In a region {g ≤ 0} the pair energies alone push the points onto the boundary. Section
//! 5.4 of the paper counts each point's distance to the boundary as an extra element: a
//! point's Voronoi cell in an evenly spread set has an inscribed radius of about half the
//! spacing, so 2·d_{i,g} is compared with the pair distances d_ij.
//!
//! - [`UEInfG`] is the paper's U_{E,∞,g} = G/d_min, d_min = min{min_{i<j} d_ij,
//!   min_i 2·d_{i,g}} (eq. 56; the paper prints d_{E,ij}^p, the distance itself is meant),
//!   with the subgradient of eq. 57.
//! - [`UEpG`] goes beyond the paper: the p-norm (Σ_{i<j} d_ij^{−p} + Σ_i (2 d_{i,g})^{−p})^{1/p}
//!   of the same elements, smooth wherever the closest boundary points are unique, so that
//!   gradient solvers apply. It tends to U_{E,∞,g} as p → ∞ (as eq. 6 for U_p).
//!
//! Both take G = 1 and the Euclidean distance. d_{i,g} comes from
//! [`Domain::closest_boundary_point`]; it is the unsigned distance, so the boundary term
//! acts as a barrier only for points inside the region (the integrators bring escaped
//! points back by projection before evaluating). A point for which the domain reports no
//! boundary, or a distance that is not a number ≥ 0, has d_{i,g} = +∞ (no boundary term).
//!
//! **Degenerate sets.** A zero element distance (coincident points, a point on the
//! boundary) gives U = +∞, and that element contributes nothing to the (sub)gradient,
//! since it has no direction; no NaN comes out.
//!
//! **Determinism.** Boundary distances are computed in parallel and collected in index
//! order; minima are order-independent; sums are fixed-order (pairs through
//! [`for_each_pair_tile`], boundary terms in index order). Results have the same bits for
//! any number of rayon threads.

use crate::einf::{add_pair_subgradient, check_tie_tolerance, Metric, PairScan};
use crate::pairs::{for_each_pair_tile, scatter_pair};
use crate::{Domain, Energy, Error, PointSet, Result};
use rayon::prelude::*;
use std::sync::Arc;

/// Checks that `domain` has a boundary, probing the centre of its bounding box.
fn check_has_boundary(domain: &dyn Domain) -> Result<()> {
    let (lo, hi) = domain.bounding_box();
    let centre: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
    let mut foot = vec![0.0; centre.len()];
    if domain.closest_boundary_point(&centre, &mut foot).is_some() {
        Ok(())
    } else {
        let what = if domain.is_periodic() {
            "the periodic cube"
        } else {
            "a domain without boundary"
        };
        Err(Error::invalid(
            "domain",
            format!("{what} (s = {})", domain.dim()),
            "a region with a boundary (closest boundary points); in the periodic cube use \
             U_{E,∞} with the torus distance or U_{q,p}",
        ))
    }
}

/// Distances d_{i,g} to the boundary (+∞ where there is none) and the feet, row per point.
fn boundary_distances(domain: &dyn Domain, points: &PointSet) -> (Vec<f64>, Vec<f64>) {
    let s = points.s();
    assert_eq!(
        s,
        domain.dim(),
        "point dimension must match the domain's dimension"
    );
    let mut feet = vec![0.0; points.coordinate_count()];
    let dist: Vec<f64> = feet
        .par_chunks_mut(s)
        .zip(points.as_slice().par_chunks(s))
        .map(|(foot, x)| {
            domain
                .closest_boundary_point(x, foot)
                .filter(|d| *d >= 0.0)
                .unwrap_or(f64::INFINITY)
        })
        .collect();
    (dist, feet)
}

/// The active elements of [`UEInfG`]: pairs and boundary points within the tie band.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ActiveSet {
    /// Active pairs (i < j) in index order: d_ij ≤ d_min·(1 + τ).
    pub pairs: Vec<(usize, usize)>,
    /// Points whose boundary element is active, ascending: 2·d_{i,g} ≤ d_min·(1 + τ).
    pub boundary: Vec<usize>,
}

/// Everything one evaluation of U_{E,∞,g} needs.
struct InfScan {
    min_d2: f64,
    pairs: Vec<(usize, usize, f64)>,
    boundary: Vec<usize>,
    dist: Vec<f64>,
    feet: Vec<f64>,
}

/// U_{E,∞,g} = 1/d_min with d_min = min{min_{i<j} d_ij, min_i 2·d_{i,g}} (eq. 56, G = 1)
/// and the subgradient of eq. 57.
///
/// An active pair adds −a_ij/d_ij³ to x_i (a_ij = x_i − x_j) and the opposite to x_j; an
/// active boundary point adds ∇(1/(2 d_{i,g})) = −(x_i − foot_i)/(2 d_{i,g}³), which is
/// eq. 57's −4(x_i − foot_i)/d_min³ when 2 d_{i,g} = d_min. Its negative, the descent
/// direction, points away from the boundary.
///
/// **Ties.** Elements (pairs and boundary points alike) within d_min·(1 + τ) are active,
/// τ the relative tie tolerance (1e-9 by default), and share the subgradient equally
/// (weights 1/|A|): the mean of the active gradients, a convex combination and so a
/// subgradient of the maximum when the ties are exact, as for [`UEInf`](crate::einf::UEInf).
#[derive(Debug, Clone)]
pub struct UEInfG {
    domain: Arc<dyn Domain>,
    rel_tol: f64,
}

impl UEInfG {
    /// U_{E,∞,g} over a region. Refuses a domain without boundary (the periodic cube),
    /// probed at the centre of its bounding box.
    pub fn new(domain: Arc<dyn Domain>) -> Result<Self> {
        check_has_boundary(domain.as_ref())?;
        Ok(UEInfG {
            domain,
            rel_tol: crate::einf::DEFAULT_TIE_TOLERANCE,
        })
    }

    /// Sets the relative tie tolerance τ (finite, ≥ 0; default 1e-9).
    pub fn with_tie_tolerance(mut self, rel_tol: f64) -> Result<Self> {
        self.rel_tol = check_tie_tolerance(rel_tol)?;
        Ok(self)
    }

    /// The relative tie tolerance τ.
    pub fn tie_tolerance(&self) -> f64 {
        self.rel_tol
    }

    /// The region.
    pub fn domain(&self) -> &Arc<dyn Domain> {
        &self.domain
    }

    /// d_min of eq. 56: the smallest of the pair distances and the doubled boundary
    /// distances (+∞ if there is no element at all).
    pub fn min_distance(&self, points: &PointSet) -> f64 {
        self.scan(points, false).min_d2.sqrt()
    }

    /// The active pairs and boundary points, in index order.
    pub fn active_set(&self, points: &PointSet) -> ActiveSet {
        let sc = self.scan(points, true);
        ActiveSet {
            pairs: sc.pairs.iter().map(|&(i, j, _)| (i, j)).collect(),
            boundary: sc.boundary,
        }
    }

    fn scan(&self, points: &PointSet, collect: bool) -> InfScan {
        let band = (1.0 + self.rel_tol) * (1.0 + self.rel_tol);
        let (dist, feet) = boundary_distances(self.domain.as_ref(), points);
        let ps = PairScan::new(points, Metric::Euclidean, band, collect);
        let b2 = |d: f64| (2.0 * d) * (2.0 * d);
        let min_d2 = dist.iter().map(|&d| b2(d)).fold(ps.min_d2, f64::min);
        let (pairs, boundary) = if collect {
            let thr2 = min_d2 * band;
            let boundary = (0..dist.len()).filter(|&i| b2(dist[i]) <= thr2).collect();
            (ps.within(thr2), boundary)
        } else {
            (Vec::new(), Vec::new())
        };
        InfScan {
            min_d2,
            pairs,
            boundary,
            dist,
            feet,
        }
    }
}

impl Energy for UEInfG {
    fn domain(&self) -> Option<Arc<dyn Domain>> {
        Some(self.domain.clone())
    }

    fn name(&self) -> String {
        "U_{E,∞,g}".to_string()
    }

    fn is_smooth(&self) -> bool {
        false
    }

    fn value(&self, points: &PointSet) -> f64 {
        1.0 / self.min_distance(points)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(
            grad.len(),
            points.coordinate_count(),
            "gradient buffer length"
        );
        grad.fill(0.0);
        let sc = self.scan(points, true);
        let count = sc.pairs.len() + sc.boundary.len();
        if count == 0 {
            return 1.0 / sc.min_d2.sqrt();
        }
        let weight = 1.0 / count as f64;
        let (x, s) = (points.as_slice(), points.s());
        for &pair in &sc.pairs {
            add_pair_subgradient(x, s, Metric::Euclidean, pair, weight, grad);
        }
        for &i in &sc.boundary {
            let d = sc.dist[i];
            if !(d > 0.0 && d.is_finite()) {
                continue;
            }
            // −(x − foot)/(2d³) = −(u/2)/d² with the unit vector u = (x − foot)/d.
            let mag = 0.5 * weight / (d * d);
            for k in 0..s {
                let u = (x[i * s + k] - sc.feet[i * s + k]) / d;
                if u != 0.0 {
                    grad[i * s + k] -= u * mag;
                }
            }
        }
        1.0 / sc.min_d2.sqrt()
    }
}

/// U_{E,p,g} = (Σ_{i<j} d_ij^{−p} + Σ_i (2 d_{i,g})^{−p})^{1/p}, Euclidean d_ij, finite
/// p > 0: a smooth boundary-aware energy for regions (not in the paper).
///
/// Gradient: with S the sum in brackets, ∂U/∂x_i = (1/p)·S^{1/p−1}·∂S/∂x_i, where a pair
/// gives ∂d_ij^{−p}/∂x_i = −p·d_ij^{−p−2}·(x_i − x_j) (eq. 18 with q = 'E') and the boundary
/// ∂(2 d_{i,g})^{−p}/∂x_i = −p·(2 d_{i,g})^{−p−1}·2·(x_i − foot_i)/d_{i,g}, since inside
/// the region the gradient of the distance to the boundary is the unit vector from the
/// foot to the point (where the closest point is unique).
///
/// Every term is scaled by the smallest element distance m before it is raised to p,
/// U = (1/m)·(Σ (m/d)^p)^{1/p}, so large p neither overflows nor underflows.
#[derive(Debug, Clone)]
pub struct UEpG {
    domain: Arc<dyn Domain>,
    p: f64,
}

impl UEpG {
    /// U_{E,p,g} over a region with finite p > 0. Refuses a non-finite or non-positive p
    /// and a domain without boundary (the periodic cube).
    pub fn new(domain: Arc<dyn Domain>, p: f64) -> Result<Self> {
        if !(p > 0.0 && p.is_finite()) {
            return Err(Error::invalid("p", p, "a finite number > 0"));
        }
        check_has_boundary(domain.as_ref())?;
        Ok(UEpG { domain, p })
    }

    /// The exponent p.
    pub fn p(&self) -> f64 {
        self.p
    }

    /// The region.
    pub fn domain(&self) -> &Arc<dyn Domain> {
        &self.domain
    }

    /// (d/m)^{−p} = r^{p/2} for r = m²/d² ∈ (0, 1].
    #[inline]
    fn scaled(&self, r: f64) -> f64 {
        if self.p == 1.0 {
            r.sqrt()
        } else if self.p == 2.0 {
            r
        } else {
            r.powf(0.5 * self.p)
        }
    }

    /// Smallest positive squared element distance m² (pairs and (2 d_{i,g})²), and
    /// whether some element distance is zero.
    fn min_positive(&self, points: &PointSet, dist: &[f64]) -> (f64, bool) {
        let (n, s) = (points.n(), points.s());
        let x = points.as_slice();
        let fold = |(m, z): (f64, bool), d2: f64| {
            if d2 > 0.0 {
                (m.min(d2), z)
            } else {
                (m, z || d2 == 0.0)
            }
        };
        let pairs = (0..n)
            .into_par_iter()
            .map(|i| {
                let xi = &x[i * s..(i + 1) * s];
                (i + 1..n)
                    .map(|j| Metric::Euclidean.d2(xi, &x[j * s..(j + 1) * s]))
                    .fold((f64::INFINITY, false), fold)
            })
            .reduce(|| (f64::INFINITY, false), |a, b| (a.0.min(b.0), a.1 || b.1));
        dist.iter()
            .map(|&d| (2.0 * d) * (2.0 * d))
            .fold(pairs, fold)
    }

    /// Value, and the gradient into `grad` when given.
    fn eval(&self, points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
        let (n, s) = (points.n(), points.s());
        let x = points.as_slice();
        let (dist, feet) = boundary_distances(self.domain.as_ref(), points);
        let (m2, zero) = self.min_positive(points, &dist);
        let value_of = |t: f64| {
            if zero {
                f64::INFINITY
            } else if m2.is_infinite() {
                0.0
            } else {
                t.powf(1.0 / self.p) / m2.sqrt()
            }
        };
        if !m2.is_finite() {
            // No element at a finite positive distance: nothing to differentiate.
            if let Some(g) = grad {
                g.fill(0.0);
            }
            return value_of(0.0);
        }
        let m = m2.sqrt();
        let b2 = |d: f64| (2.0 * d) * (2.0 * d);
        let boundary_t = |i: usize| {
            let q2 = b2(dist[i]);
            if q2 > 0.0 && q2.is_finite() {
                self.scaled(m2 / q2)
            } else {
                0.0
            }
        };

        let Some(grad) = grad else {
            let rows: Vec<f64> = (0..n)
                .into_par_iter()
                .map(|i| {
                    let xi = &x[i * s..(i + 1) * s];
                    let mut acc = boundary_t(i);
                    for j in i + 1..n {
                        let d2 = Metric::Euclidean.d2(xi, &x[j * s..(j + 1) * s]);
                        if d2 > 0.0 {
                            acc += self.scaled(m2 / d2);
                        }
                    }
                    acc
                })
                .collect();
            return value_of(rows.iter().sum());
        };

        // Rows receive Σ t·(m/d)·(a/d), each term bounded by 1 in magnitude; the common
        // factor −T^{1/p−1}/m² is applied at the end.
        let pair_t = for_each_pair_tile(n, s, grad, |ri, rj, gi, gj| {
            let mut diff = vec![0.0; s];
            let mut acc = 0.0;
            let diag = gj.is_empty();
            for i in ri.clone() {
                let xi = &x[i * s..(i + 1) * s];
                let js = if diag { i + 1..ri.end } else { rj.clone() };
                for j in js {
                    let xj = &x[j * s..(j + 1) * s];
                    let mut d2 = 0.0;
                    for k in 0..s {
                        let a = xi[k] - xj[k];
                        d2 += a * a;
                        diff[k] = a;
                    }
                    if !(d2 > 0.0 && d2.is_finite()) {
                        continue;
                    }
                    let t = self.scaled(m2 / d2);
                    acc += t;
                    let d = d2.sqrt();
                    let w = t * (m / d) / d;
                    scatter_pair(gi, gj, (ri.start, rj.start), (i, j), w, &diff);
                }
            }
            acc
        });
        // Boundary: t·(m/d_g)·(x − foot)/d_g with t = (m/(2 d_g))^p, also bounded
        // (m ≤ 2 d_g); the inner derivative 2 of 2·d_g cancels the 1/2 of 1/(2 d_g).
        let bnd_t: Vec<f64> = grad
            .par_chunks_mut(s)
            .enumerate()
            .map(|(i, gi)| {
                let t = boundary_t(i);
                if t > 0.0 {
                    let d = dist[i];
                    let w = t * (m / d) / d;
                    for k in 0..s {
                        gi[k] += w * (x[i * s + k] - feet[i * s + k]);
                    }
                }
                t
            })
            .collect();
        let total = pair_t + bnd_t.iter().sum::<f64>();
        let scale = -total.powf(1.0 / self.p - 1.0) / m2;
        // A zero row stays zero even if the scale overflowed (no 0·∞).
        grad.iter_mut()
            .filter(|g| **g != 0.0)
            .for_each(|g| *g *= scale);
        value_of(total)
    }
}

impl Energy for UEpG {
    fn domain(&self) -> Option<Arc<dyn Domain>> {
        Some(self.domain.clone())
    }

    fn name(&self) -> String {
        format!("U_{{E,p,g}}(p={})", self.p)
    }

    fn value(&self, points: &PointSet) -> f64 {
        self.eval(points, None)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(
            grad.len(),
            points.coordinate_count(),
            "gradient buffer length"
        );
        // `eval` accumulates into the buffer; callers reuse theirs between steps.
        grad.fill(0.0);
        self.eval(points, Some(grad))
    }
}
