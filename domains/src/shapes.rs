//! Built-in regions with exact closest points: ball, axis-aligned ellipsoid, closed box,
//! standard simplex and polytope {A x ≤ b}, in any dimension.
//!
//! The generic [`ImplicitRegion`] finds closest boundary points by searching over ray
//! directions; for these shapes the closest point has a closed form or a finite method,
//! so they are both faster and exact (to rounding), and serve as references for the
//! generic search. Each shape is a [`Domain`]:
//!
//! - `closest_boundary_point`: from inside, the nearest point of the boundary; from
//!   outside, the Euclidean projection onto the shape (ball: radial; ellipsoid: Eberly's
//!   1-D root finding; box: nearest face or clamp; simplex: nearest facet or the
//!   sort-based projection; polytope: nearest facet or a Goldfarb–Idnani dual active-set
//!   projection).
//! - `sample`: exactly uniform (ball: Gaussian direction × U^{1/s}; ellipsoid: the scaled
//!   ball; box: uniform; simplex: normalised exponentials; polytope: rejection from its
//!   box).
//! - `bring_back`: the projection, moved 1e-9 of the box diameter towards an interior
//!   point so that it is strictly inside (checked), with the velocity set to zero
//!   (`prev = x`): a point stops at the wall.
//! - `level`: a function ≤ 0 exactly on the shape; [`Ball::level_fn`] and friends give it
//!   as a [`RegionFn`] and `to_implicit` wraps it as an [`ImplicitRegion`].

use crate::projection::{dist, dot, normalise, project_halfspaces};
use crate::region::{check_box, fmt_box, place_inside, rejection_sample, ImplicitRegion, RegionFn};
use crate::{Domain, Error, PointSet, Result};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::Arc;

/// Refuses an empty or non-finite point-like argument.
fn check_vector(name: &str, v: &[f64]) -> Result<()> {
    if v.is_empty() {
        return Err(Error::invalid(
            name,
            "0 coordinates",
            "at least 1 dimension",
        ));
    }
    if let Some(k) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::invalid(
            format!("{name} coordinate {}", k + 1),
            v[k],
            "a finite number",
        ));
    }
    if let Some(k) = v.iter().position(|x| x.abs() > MAX_SCALE) {
        return Err(Error::invalid(
            format!("{name} coordinate {}", k + 1),
            format!("{:?}", v[k]),
            format!("a number of magnitude at most {MAX_SCALE:e} (squares must stay finite)"),
        ));
    }
    Ok(())
}

/// The largest magnitude a shape's parameter (centre, radius, semi-axis, polytope entry)
/// may have: the shapes square distances, and the square of anything larger would
/// overflow f64.
pub const MAX_SCALE: f64 = 1e150;

/// Refuses a length (radius, semi-axis) that is not finite, not positive, or so large
/// that its square overflows.
fn check_length(name: &str, v: f64) -> Result<()> {
    if !(v.is_finite() && (MIN_SCALE..=MAX_SCALE).contains(&v)) {
        return Err(Error::invalid(
            name,
            format!("{v:?}"),
            format!(
                "a number in [{MIN_SCALE:e}, {MAX_SCALE:e}] (squares of lengths and of the \
                 distances between points must stay finite and nonzero)"
            ),
        ));
    }
    Ok(())
}

/// The smallest length (radius, semi-axis) a shape may have: the distances between n
/// points in it are smaller still, and their squares (and the energies' powers of
/// them) must not underflow to 0 or overflow to ∞.
pub const MIN_SCALE: f64 = 1e-100;

/// Whether x and foot have s coordinates and x is finite: the shapes answer nothing else.
fn usable(s: usize, x: &[f64], foot: &[f64]) -> bool {
    x.len() == s && foot.len() == s && x.iter().all(|v| v.is_finite())
}

/// The box of a shape widened by 2 % of its width on each side: the box of the
/// [`ImplicitRegion`] made from the shape's level function, loose enough not to cut it.
fn widened(lo: &[f64], hi: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let m: Vec<f64> = lo.iter().zip(hi).map(|(l, h)| 0.02 * (h - l)).collect();
    (
        lo.iter().zip(&m).map(|(l, m)| l - m).collect(),
        hi.iter().zip(&m).map(|(h, m)| h + m).collect(),
    )
}

/// Fills `out` with independent standard normals (Box–Muller on the seeded generator).
fn gaussians(rng: &mut Xoshiro256PlusPlus, out: &mut [f64]) {
    let mut k = 0;
    while k < out.len() {
        // 1 − U is in (0, 1], so the logarithm is finite.
        let u1 = 1.0 - rng.random::<f64>();
        let u2 = rng.random::<f64>();
        let rad = (-2.0 * u1.ln()).sqrt();
        let a = std::f64::consts::TAU * u2;
        out[k] = rad * a.cos();
        if k + 1 < out.len() {
            out[k + 1] = rad * a.sin();
        }
        k += 2;
    }
}

/// A uniform point of the unit ball: a Gaussian direction times U^{1/s}.
fn unit_ball_point(rng: &mut Xoshiro256PlusPlus, out: &mut [f64]) {
    loop {
        gaussians(rng, out);
        if normalise(out) {
            break;
        }
    }
    let r = rng.random::<f64>().powf(1.0 / out.len() as f64);
    out.iter_mut().for_each(|v| *v *= r);
}

/// Shared `bring_back` of the convex shapes: project, then move towards `center` (an
/// interior point, so every point strictly between it and the foot is inside).
fn project_back(d: &dyn Domain, center: &[f64], diam: f64, x: &mut [f64], prev: &mut [f64]) {
    let s = center.len();
    if x.len() != s || prev.len() != s || d.contains(x) {
        return;
    }
    let mut foot = vec![0.0; s];
    if d.closest_boundary_point(x, &mut foot).is_some() {
        let mut inward: Vec<f64> = center.iter().zip(&foot).map(|(c, f)| c - f).collect();
        if normalise(&mut inward) && place_inside(d, &foot, &[inward], diam, x, prev) {
            return;
        }
    }
    x.copy_from_slice(center);
    prev.copy_from_slice(center);
}

/// n points, each drawn into its row by `draw` from one seeded generator.
fn n_samples<F: FnMut(&mut Xoshiro256PlusPlus, &mut [f64])>(
    s: usize,
    n: usize,
    seed: u64,
    mut draw: F,
) -> Result<PointSet> {
    if n == 0 {
        return Err(Error::invalid("n", n, "at least 1 point"));
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut data = vec![0.0; n * s];
    for row in data.chunks_exact_mut(s) {
        draw(&mut rng, row);
    }
    PointSet::new(n, s, data)
}

// ---------------------------------------------------------------------------------------

/// The closed ball |x − c| ≤ r.
#[derive(Debug, Clone, PartialEq)]
pub struct Ball {
    center: Vec<f64>,
    radius: f64,
}

impl Ball {
    /// The ball of the given centre (s ≥ 1 finite coordinates) and radius (finite, > 0).
    pub fn new(center: Vec<f64>, radius: f64) -> Result<Self> {
        check_vector("center", &center)?;
        check_length("radius", radius)?;
        Ok(Ball { center, radius })
    }

    /// The centre.
    pub fn center(&self) -> &[f64] {
        &self.center
    }

    /// The radius.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// |x − c|² − r², the level function.
    pub fn level_fn(&self) -> RegionFn {
        let b = self.clone();
        Arc::new(move |x: &[f64]| {
            let d = dist(x, &b.center);
            d * d - b.radius * b.radius
        })
    }

    /// The same ball as an [`ImplicitRegion`] (generic closest-point search) in a box 2 %
    /// wider than its bounding box on every side.
    pub fn to_implicit(&self) -> Result<ImplicitRegion> {
        let (lo, hi) = self.bounding_box();
        let (lo, hi) = widened(&lo, &hi);
        ImplicitRegion::new(self.level_fn(), lo, hi)
    }
}

impl Domain for Ball {
    fn dim(&self) -> usize {
        self.center.len()
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.center.len() && dist(x, &self.center) <= self.radius
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        n_samples(self.dim(), n, seed, |rng, row| {
            unit_ball_point(rng, row);
            for (v, c) in row.iter_mut().zip(&self.center) {
                *v = c + self.radius * *v;
            }
        })
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        project_back(self, &self.center, 2.0 * self.radius, x, prev);
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        if !usable(self.dim(), x, foot) {
            return None;
        }
        let n = dist(x, &self.center);
        if n == 0.0 {
            // Every boundary point is closest; take the one along the first axis.
            foot.copy_from_slice(&self.center);
            foot[0] += self.radius;
            return Some(self.radius);
        }
        for k in 0..foot.len() {
            foot[k] = self.center[k] + self.radius * (x[k] - self.center[k]) / n;
        }
        Some((n - self.radius).abs())
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (
            self.center.iter().map(|c| c - self.radius).collect(),
            self.center.iter().map(|c| c + self.radius).collect(),
        )
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        (x.len() == self.dim()).then(|| {
            let d = dist(x, &self.center);
            d * d - self.radius * self.radius
        })
    }
}

// ---------------------------------------------------------------------------------------

/// The axis-aligned ellipsoid Σ ((x_k − c_k)/a_k)² ≤ 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Ellipsoid {
    center: Vec<f64>,
    semi_axes: Vec<f64>,
}

impl Ellipsoid {
    /// The ellipsoid of the given centre and semi-axes (same length s ≥ 1; semi-axes
    /// finite and > 0).
    pub fn new(center: Vec<f64>, semi_axes: Vec<f64>) -> Result<Self> {
        check_vector("center", &center)?;
        if semi_axes.len() != center.len() {
            return Err(Error::invalid(
                "semi_axes",
                format!("{} values", semi_axes.len()),
                format!("one per coordinate of the centre ({})", center.len()),
            ));
        }
        for (k, a) in semi_axes.iter().enumerate() {
            check_length(&format!("semi-axis {}", k + 1), *a)?;
        }
        Ok(Ellipsoid { center, semi_axes })
    }

    /// The centre.
    pub fn center(&self) -> &[f64] {
        &self.center
    }

    /// The semi-axes.
    pub fn semi_axes(&self) -> &[f64] {
        &self.semi_axes
    }

    /// Σ ((x_k − c_k)/a_k)² − 1, the level function.
    pub fn level_fn(&self) -> RegionFn {
        let e = self.clone();
        Arc::new(move |x: &[f64]| e.scaled_sq(x) - 1.0)
    }

    /// The same ellipsoid as an [`ImplicitRegion`] in a box 2 % wider than its bounding
    /// box on every side.
    pub fn to_implicit(&self) -> Result<ImplicitRegion> {
        let (lo, hi) = self.bounding_box();
        let (lo, hi) = widened(&lo, &hi);
        ImplicitRegion::new(self.level_fn(), lo, hi)
    }

    fn scaled_sq(&self, x: &[f64]) -> f64 {
        x.iter()
            .zip(&self.center)
            .zip(&self.semi_axes)
            .map(|((x, c), a)| ((x - c) / a).powi(2))
            .sum()
    }
}

/// Eberly's distance from y (all y_i ≥ 0) to the ellipsoid with semi-axes e (sorted
/// descending): the squared distance, with the closest point written to x. This is the
/// "SqrDistanceSpecial" of D. Eberly, *Distance from a point to an ellipse, an ellipsoid,
/// or a hyperellipsoid* (2013): the closest point is x_i = e_i² y_i / (t + e_i²) with t
/// the unique root of F(t) = Σ (e_i y_i / (t + e_i²))² − 1 above −e_min², except when
/// y lies in the plane of the smallest axis, deep enough that the closest point leaves
/// that plane (then t = −e_min²).
fn eberly(e: &[f64], y: &[f64], x: &mut [f64]) -> f64 {
    let n = e.len();
    let pos: Vec<usize> = (0..n).filter(|&i| y[i] > 0.0).collect();
    let e_pos: Vec<f64> = pos.iter().map(|&i| e[i]).collect();
    let y_pos: Vec<f64> = pos.iter().map(|&i| y[i]).collect();
    let mut x_pos = vec![0.0; pos.len()];
    x.iter_mut().for_each(|v| *v = 0.0);
    let d2 = if y[n - 1] > 0.0 {
        eberly_bisector(&e_pos, &y_pos, &mut x_pos)
    } else {
        let em = e[n - 1] * e[n - 1];
        let mut inside_sub = false;
        let mut d2 = 0.0;
        // Is y inside the sub-ellipsoid where the closest point has x_{n−1} > 0? The box
        // test first guards the division when an axis equals the smallest one.
        if pos.iter().all(|&i| e[i] * y[i] < e[i] * e[i] - em) {
            let mut discr = 1.0;
            let xde: Vec<f64> = pos
                .iter()
                .map(|&i| e[i] * y[i] / (e[i] * e[i] - em))
                .collect();
            discr -= xde.iter().map(|v| v * v).sum::<f64>();
            if discr > 0.0 {
                for (j, &i) in pos.iter().enumerate() {
                    x_pos[j] = e[i] * xde[j];
                    d2 += (x_pos[j] - y[i]).powi(2);
                }
                x[n - 1] = e[n - 1] * discr.sqrt();
                d2 += x[n - 1] * x[n - 1];
                inside_sub = true;
            }
        }
        if !inside_sub {
            x[n - 1] = 0.0;
            d2 = eberly(&e_pos, &y_pos, &mut x_pos);
        }
        d2
    };
    for (j, &i) in pos.iter().enumerate() {
        x[i] = x_pos[j];
    }
    d2
}

/// Eberly's "Bisector": all y_i > 0, e sorted descending; bisection on the root of F in
/// the scaled variable s = t/e_min² to the last bit.
fn eberly_bisector(e: &[f64], y: &[f64], x: &mut [f64]) -> f64 {
    let n = e.len();
    let z: Vec<f64> = y.iter().zip(e).map(|(y, e)| y / e).collect();
    let sum_z2: f64 = z.iter().map(|v| v * v).sum();
    if sum_z2 == 1.0 {
        x.copy_from_slice(y);
        return 0.0;
    }
    let emin = e[n - 1];
    let p2: Vec<f64> = e.iter().map(|e| (e / emin).powi(2)).collect();
    let num: Vec<f64> = p2.iter().zip(&z).map(|(p, z)| p * z).collect();
    let mut smin = z[n - 1] - 1.0;
    let mut smax = if sum_z2 < 1.0 {
        0.0
    } else {
        num.iter().map(|v| v * v).sum::<f64>().sqrt() - 1.0
    };
    let mut s = 0.0;
    for _ in 0..2200 {
        s = 0.5 * (smin + smax);
        if s == smin || s == smax {
            break;
        }
        let f: f64 = num
            .iter()
            .zip(&p2)
            .map(|(nu, p)| (nu / (s + p)).powi(2))
            .sum::<f64>()
            - 1.0;
        if f > 0.0 {
            smin = s;
        } else if f < 0.0 {
            smax = s;
        } else {
            break;
        }
    }
    let mut d2 = 0.0;
    for i in 0..n {
        x[i] = p2[i] * y[i] / (s + p2[i]);
        d2 += (x[i] - y[i]).powi(2);
    }
    d2
}

impl Domain for Ellipsoid {
    fn dim(&self) -> usize {
        self.center.len()
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.dim() && self.scaled_sq(x) <= 1.0
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        // A linear image of the uniform ball is uniform.
        n_samples(self.dim(), n, seed, |rng, row| {
            unit_ball_point(rng, row);
            for ((v, c), a) in row.iter_mut().zip(&self.center).zip(&self.semi_axes) {
                *v = c + a * *v;
            }
        })
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        let diam = 2.0 * self.semi_axes.iter().cloned().fold(0.0, f64::max);
        project_back(self, &self.center, diam, x, prev);
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        let s = self.dim();
        if !usable(s, x, foot) {
            return None;
        }
        // Reflect into the first orthant and order the axes as Eberly's method wants.
        let mut order: Vec<usize> = (0..s).collect();
        order.sort_by(|&i, &j| self.semi_axes[j].total_cmp(&self.semi_axes[i]));
        let e: Vec<f64> = order.iter().map(|&i| self.semi_axes[i]).collect();
        let y: Vec<f64> = order
            .iter()
            .map(|&i| (x[i] - self.center[i]).abs())
            .collect();
        let mut p = vec![0.0; s];
        let d2 = eberly(&e, &y, &mut p);
        for (j, &i) in order.iter().enumerate() {
            let sign = if x[i] < self.center[i] { -1.0 } else { 1.0 };
            foot[i] = self.center[i] + sign * p[j];
        }
        Some(d2.max(0.0).sqrt())
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (
            self.center
                .iter()
                .zip(&self.semi_axes)
                .map(|(c, a)| c - a)
                .collect(),
            self.center
                .iter()
                .zip(&self.semi_axes)
                .map(|(c, a)| c + a)
                .collect(),
        )
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        (x.len() == self.dim()).then(|| self.scaled_sq(x) - 1.0)
    }
}

// ---------------------------------------------------------------------------------------

/// The closed box [lo, hi] (not periodic: its faces are walls).
#[derive(Debug, Clone, PartialEq)]
pub struct BoxRegion {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl BoxRegion {
    /// The box [lo_1, hi_1] × … × [lo_s, hi_s]; refuses lengths that differ, non-finite
    /// bounds and lo ≥ hi.
    pub fn new(lo: Vec<f64>, hi: Vec<f64>) -> Result<Self> {
        check_box(&lo, &hi)?;
        Ok(BoxRegion { lo, hi })
    }

    fn center(&self) -> Vec<f64> {
        self.lo
            .iter()
            .zip(&self.hi)
            .map(|(l, h)| 0.5 * (l + h))
            .collect()
    }

    /// max_k max(lo_k − x_k, x_k − hi_k), the level function (minus the distance to the
    /// boundary inside).
    pub fn level_fn(&self) -> RegionFn {
        let b = self.clone();
        Arc::new(move |x: &[f64]| b.excess(x))
    }

    fn excess(&self, x: &[f64]) -> f64 {
        x.iter()
            .zip(self.lo.iter().zip(&self.hi))
            .map(|(&v, (&l, &h))| (l - v).max(v - h))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The same box as an [`ImplicitRegion`] whose own box is 2 % wider on every side
    /// (so the level function, not the box, makes the walls).
    pub fn to_implicit(&self) -> Result<ImplicitRegion> {
        let (lo, hi) = widened(&self.lo, &self.hi);
        ImplicitRegion::new(self.level_fn(), lo, hi)
    }
}

impl Domain for BoxRegion {
    fn dim(&self) -> usize {
        self.lo.len()
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.dim()
            && x.iter()
                .zip(self.lo.iter().zip(&self.hi))
                .all(|(&v, (&l, &h))| v >= l && v <= h)
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        n_samples(self.dim(), n, seed, |rng, row| {
            for ((v, l), h) in row.iter_mut().zip(&self.lo).zip(&self.hi) {
                *v = l + (h - l) * rng.random::<f64>();
            }
        })
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        project_back(self, &self.center(), dist(&self.lo, &self.hi), x, prev);
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        if !usable(self.dim(), x, foot) {
            return None;
        }
        if self.contains(x) {
            // The nearest face.
            let mut best = (f64::INFINITY, 0, 0.0);
            for (k, &v) in x.iter().enumerate() {
                for face in [self.lo[k], self.hi[k]] {
                    let d = (v - face).abs();
                    if d < best.0 {
                        best = (d, k, face);
                    }
                }
            }
            foot.copy_from_slice(x);
            foot[best.1] = best.2;
            Some(best.0)
        } else {
            for k in 0..x.len() {
                foot[k] = x[k].clamp(self.lo[k], self.hi[k]);
            }
            Some(dist(x, foot))
        }
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (self.lo.clone(), self.hi.clone())
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        (x.len() == self.dim()).then(|| self.excess(x))
    }
}

// ---------------------------------------------------------------------------------------

/// The standard simplex {x : x_k ≥ 0, Σ x_k ≤ 1} in s dimensions.
#[derive(Debug, Clone, PartialEq)]
pub struct Simplex {
    s: usize,
}

impl Simplex {
    /// The standard simplex in s ≥ 1 dimensions.
    pub fn new(s: usize) -> Result<Self> {
        if s == 0 {
            return Err(Error::invalid("s", s, "at least 1 dimension"));
        }
        Ok(Simplex { s })
    }

    /// max(max_k −x_k, (Σx − 1)/√s), the level function (minus the distance to the
    /// boundary inside).
    pub fn level_fn(&self) -> RegionFn {
        let s = self.s;
        Arc::new(move |x: &[f64]| simplex_level(s, x))
    }

    /// The same simplex as an [`ImplicitRegion`] in the box [0, 1]^s widened by 2 %.
    pub fn to_implicit(&self) -> Result<ImplicitRegion> {
        let (lo, hi) = self.bounding_box();
        let (lo, hi) = widened(&lo, &hi);
        ImplicitRegion::new(self.level_fn(), lo, hi)
    }

    fn centroid(&self) -> Vec<f64> {
        vec![1.0 / (self.s as f64 + 1.0); self.s]
    }
}

fn simplex_level(s: usize, x: &[f64]) -> f64 {
    let neg = x.iter().map(|v| -v).fold(f64::NEG_INFINITY, f64::max);
    let top = (x.iter().sum::<f64>() - 1.0) / (s as f64).sqrt();
    neg.max(top)
}

impl Domain for Simplex {
    fn dim(&self) -> usize {
        self.s
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.s && x.iter().all(|&v| v >= 0.0) && x.iter().sum::<f64>() <= 1.0
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        // (E_1, …, E_s)/(E_0 + … + E_s) with E_j exponential is uniform on the simplex
        // (the first s coordinates of a flat Dirichlet).
        n_samples(self.s, n, seed, |rng, row| {
            let e0 = -(1.0 - rng.random::<f64>()).ln();
            let mut total = e0;
            for v in row.iter_mut() {
                *v = -(1.0 - rng.random::<f64>()).ln();
                total += *v;
            }
            if total > 0.0 {
                row.iter_mut().for_each(|v| *v /= total);
            }
        })
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        project_back(self, &self.centroid(), 2f64.sqrt(), x, prev);
    }

    /// The spacings of the sorted coordinates: for uniform u, (u_(1), u_(2) − u_(1), …,
    /// 1 − u_(s)) is uniform on the simplex of s + 1 coordinates summing to 1, and its
    /// first s coordinates are uniform on this one.
    fn map_from_cube(&self, u: &[f64], x: &mut [f64]) -> bool {
        x.copy_from_slice(u);
        x.sort_unstable_by(f64::total_cmp);
        for k in (1..x.len()).rev() {
            x[k] -= x[k - 1];
        }
        true
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        let s = self.s;
        if !usable(s, x, foot) {
            return None;
        }
        foot.copy_from_slice(x);
        let sum: f64 = x.iter().sum();
        if self.contains(x) {
            // The nearest facet: a coordinate plane x_k = 0 or the plane Σx = 1.
            let top = (1.0 - sum) / (s as f64).sqrt();
            let (k, low) =
                x.iter().enumerate().fold(
                    (0, f64::INFINITY),
                    |b, (k, &v)| if v < b.1 { (k, v) } else { b },
                );
            if low <= top {
                foot[k] = 0.0;
                return Some(low);
            }
            let shift = (1.0 - sum) / s as f64;
            foot.iter_mut().for_each(|v| *v += shift);
            return Some(top);
        }
        // Outside: project onto the orthant; if that breaks Σ ≤ 1, the constraint is
        // active and the projection is onto {x ≥ 0, Σx = 1} (sort-based algorithm).
        foot.iter_mut().for_each(|v| *v = v.max(0.0));
        if foot.iter().sum::<f64>() > 1.0 {
            let mut u = x.to_vec();
            u.sort_by(|a, b| b.total_cmp(a));
            let mut cum = 0.0;
            let mut theta = 0.0;
            for (j, &v) in u.iter().enumerate() {
                cum += v;
                let t = (cum - 1.0) / (j + 1) as f64;
                if v - t > 0.0 {
                    theta = t;
                }
            }
            for (f, &v) in foot.iter_mut().zip(x) {
                *f = (v - theta).max(0.0);
            }
        }
        Some(dist(x, foot))
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![0.0; self.s], vec![1.0; self.s])
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        (x.len() == self.s).then(|| simplex_level(self.s, x))
    }
}

// ---------------------------------------------------------------------------------------

/// The polytope {x : A x ≤ b} ∩ [lo, hi].
///
/// The box makes the polytope bounded whatever A is (uniform starts are drawn in it by
/// rejection) and is part of it: its faces are walls where they cut {A x ≤ b}. Rows are
/// normalised internally, so the level function max_i (a_i·x − b_i)/|a_i| is minus the
/// distance to the boundary inside. Construction finds the largest ball inside (the
/// Chebyshev centre, by bisection on the depth δ of the shrunk polytope
/// {a_i·x ≤ b_i − δ|a_i|}, each tested for emptiness by the projection below) and refuses
/// a polytope with no interior.
#[derive(Debug, Clone, PartialEq)]
pub struct Polytope {
    s: usize,
    /// Unit normals, row per facet, the box faces last.
    normals: Vec<f64>,
    offsets: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    diam: f64,
    center: Vec<f64>,
    inradius: f64,
}

impl Polytope {
    /// {x : A x ≤ b} ∩ [lo, hi] with A given as rows of length s = lo.len().
    ///
    /// Refuses rows of the wrong length, a zero row, non-finite entries, `b` of another
    /// length than `a`, a bad box, and a polytope whose largest inscribed ball has a
    /// radius below 1e-9 of the box diameter (empty or flat).
    pub fn new(a: Vec<Vec<f64>>, b: Vec<f64>, lo: Vec<f64>, hi: Vec<f64>) -> Result<Self> {
        check_box(&lo, &hi)?;
        let s = lo.len();
        if b.len() != a.len() {
            return Err(Error::invalid(
                "b",
                format!("{} values", b.len()),
                format!("one per row of a ({})", a.len()),
            ));
        }
        let mut normals = Vec::with_capacity((a.len() + 2 * s) * s);
        let mut offsets = Vec::with_capacity(a.len() + 2 * s);
        for (i, (row, &bi)) in a.iter().zip(&b).enumerate() {
            if row.len() != s {
                return Err(Error::invalid(
                    format!("row {} of a", i + 1),
                    format!("{} coordinates", row.len()),
                    format!("{s} coordinates (the dimension of the box)"),
                ));
            }
            check_vector(&format!("row {} of a", i + 1), row)?;
            if !bi.is_finite() {
                return Err(Error::invalid(
                    format!("b entry {}", i + 1),
                    bi,
                    "a finite number",
                ));
            }
            let n = row.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(n > 0.0 && n.is_finite()) {
                return Err(Error::invalid(
                    format!("row {} of a", i + 1),
                    "a zero row",
                    "a row with a nonzero, finite length",
                ));
            }
            normals.extend(row.iter().map(|v| v / n));
            offsets.push(bi / n);
        }
        for k in 0..s {
            let mut e = vec![0.0; s];
            e[k] = 1.0;
            normals.extend_from_slice(&e);
            offsets.push(hi[k]);
            e[k] = -1.0;
            normals.extend_from_slice(&e);
            offsets.push(-lo[k]);
        }
        let diam = dist(&lo, &hi);
        let box_center: Vec<f64> = lo.iter().zip(&hi).map(|(l, h)| 0.5 * (l + h)).collect();
        let mut p = Polytope {
            s,
            normals,
            offsets,
            lo,
            hi,
            diam,
            center: box_center.clone(),
            inradius: 0.0,
        };
        // Bisection on the depth δ: {n_i·x ≤ c_i − δ} is nonempty iff δ ≤ the inradius.
        let tol = 1e-9 * diam;
        let (mut d_lo, mut d_hi) = (0.0, 0.5 * diam);
        let mut center = p.project(&box_center, 0.0);
        if center.is_some() {
            for _ in 0..60 {
                let mid = 0.5 * (d_lo + d_hi);
                match p.project(&box_center, mid) {
                    Some(y) => {
                        d_lo = mid;
                        center = Some(y);
                    }
                    None => d_hi = mid,
                }
                if d_hi - d_lo < 1e-6 * d_hi {
                    break;
                }
            }
        }
        if d_lo < tol || center.is_none() {
            return Err(Error::invalid(
                "polytope",
                format!(
                    "{{A x ≤ b}} ∩ {} with largest inscribed ball radius {d_lo:.3e}",
                    fmt_box(&p.lo, &p.hi)
                ),
                format!(
                    "a polytope with interior (inscribed radius ≥ 1e-9 of the box \
                     diameter, {tol:.3e})"
                ),
            ));
        }
        p.center = center.unwrap_or(box_center);
        p.inradius = d_lo;
        Ok(p)
    }

    /// A point deep inside (the centre of a near-largest inscribed ball).
    pub fn interior_point(&self) -> &[f64] {
        &self.center
    }

    /// The radius of the largest inscribed ball, to 1e-6 relative.
    pub fn inradius(&self) -> f64 {
        self.inradius
    }

    /// max_i (a_i·x − b_i)/|a_i| over the rows and the box faces, the level function.
    pub fn level_fn(&self) -> RegionFn {
        let p = self.clone();
        Arc::new(move |x: &[f64]| p.max_violation(x))
    }

    /// The same polytope as an [`ImplicitRegion`] in a box 2 % wider than its own.
    pub fn to_implicit(&self) -> Result<ImplicitRegion> {
        let (lo, hi) = widened(&self.lo, &self.hi);
        ImplicitRegion::new(self.level_fn(), lo, hi)
    }

    fn rows(&self) -> usize {
        self.offsets.len()
    }

    fn normal(&self, i: usize) -> &[f64] {
        &self.normals[i * self.s..(i + 1) * self.s]
    }

    fn max_violation(&self, x: &[f64]) -> f64 {
        (0..self.rows())
            .map(|i| dot(self.normal(i), x) - self.offsets[i])
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Euclidean projection of x onto the polytope shrunk by δ, {n_i·y ≤ c_i − δ};
    /// `None` when that is empty.
    fn project(&self, x: &[f64], delta: f64) -> Option<Vec<f64>> {
        project_halfspaces(&self.normals, &self.offsets, x, delta, self.diam)
    }
}

impl Domain for Polytope {
    fn dim(&self) -> usize {
        self.s
    }

    fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.s && (0..self.rows()).all(|i| dot(self.normal(i), x) <= self.offsets[i])
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        rejection_sample(&self.lo, &self.hi, n, seed, |x| Ok(self.contains(x)))
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        project_back(self, &self.center, self.diam, x, prev);
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        if !usable(self.s, x, foot) {
            return None;
        }
        if self.contains(x) {
            // The ball of radius min slack is inside and touches the nearest facet at
            // the foot of the perpendicular.
            let (i, sl) = (0..self.rows())
                .map(|i| (i, self.offsets[i] - dot(self.normal(i), x)))
                .fold((0, f64::INFINITY), |b, c| if c.1 < b.1 { c } else { b });
            let n = self.normal(i);
            for k in 0..self.s {
                foot[k] = x[k] + sl * n[k];
            }
            return Some(sl);
        }
        let y = self.project(x, 0.0)?;
        foot.copy_from_slice(&y);
        Some(dist(x, &y))
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (self.lo.clone(), self.hi.clone())
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        (x.len() == self.s).then(|| self.max_violation(x))
    }
}

/// A mixture's polytope in its first S − 1 components, whose uniform draws come from
/// the simplex {y ≥ 0, Σ y ≤ 1} when that is smaller than the polytope's box: with many
/// components the simplex fills 1/(S − 1)! of the unit box, too little for rejection
/// from the box (S = 8 keeps 1 draw in 5040).
#[derive(Debug, Clone)]
pub struct MixtureRegion {
    polytope: Polytope,
    from_simplex: bool,
}

impl MixtureRegion {
    /// The mixture region of `polytope`, drawing from the simplex when that is the
    /// smaller of the two.
    pub fn new(polytope: Polytope) -> MixtureRegion {
        let (lo, hi) = polytope.bounding_box();
        let s = lo.len();
        let box_volume: f64 = lo.iter().zip(&hi).map(|(l, h)| h - l).product();
        let simplex_volume = 1.0 / (1..=s).map(|k| k as f64).product::<f64>();
        MixtureRegion {
            polytope,
            from_simplex: simplex_volume < box_volume,
        }
    }
}

impl Domain for MixtureRegion {
    fn dim(&self) -> usize {
        self.polytope.dim()
    }

    fn contains(&self, x: &[f64]) -> bool {
        self.polytope.contains(x)
    }

    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        if !self.from_simplex {
            return self.polytope.sample(n, seed);
        }
        if n == 0 {
            return Err(Error::invalid("n", n, "at least 1 point"));
        }
        let s = self.dim();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let max_draws = n.saturating_mul(1000).max(10_000);
        let mut data = Vec::with_capacity(n * s);
        let mut e = vec![0.0; s + 1];
        for _ in 0..max_draws {
            // Normalised exponentials are uniform on the simplex (a flat Dirichlet).
            for v in e.iter_mut() {
                *v = -(1.0 - rng.random::<f64>()).ln();
            }
            let total: f64 = e.iter().sum();
            let y: Vec<f64> = e[..s].iter().map(|v| v / total).collect();
            if self.polytope.contains(&y) {
                data.extend_from_slice(&y);
                if data.len() == n * s {
                    return PointSet::new(n, s, data);
                }
            }
        }
        Err(Error::Numerical(format!(
            "only {} of {max_draws} uniform mixtures met the bounds and constraints, and {n} \
             points were asked for: they leave too little room; loosen them",
            data.len() / s
        )))
    }

    fn bring_back(&self, x: &mut [f64], prev: &mut [f64]) {
        self.polytope.bring_back(x, prev)
    }

    fn keep_inside(&self, from: &[f64], to: &mut [f64], prev: &mut [f64]) -> bool {
        self.polytope.keep_inside(from, to, prev)
    }

    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        self.polytope.closest_boundary_point(x, foot)
    }

    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        self.polytope.bounding_box()
    }

    fn level(&self, x: &[f64]) -> Option<f64> {
        self.polytope.level(x)
    }
}
