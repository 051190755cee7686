//! U_{q,p}: the p-norm of the inverse pair distances (eqs. 5 and 12), with the q-distance
//! of eq. 11, its limit q = ∞ (the torus distance, eq. 9) or the Euclidean distance (eq. 8).
//!
//! U_{q,p}(X) = (Σ_{i<j} d_ij^{-p})^{1/p}. With d_ij² = Σ_k h(Δ_ijk)² and
//! Δ_ijk = |x_ik − x_jk| the gradient is (eqs. 14–18)
//!
//! ∂U/∂x_ik = −S^{1/p−1} Σ_{j≠i} a_ijk / d_ij^{p+2},   S = Σ_{i<j} d_ij^{-p},
//!
//! where a_ijk = sgn(x_ik − x_jk)·h·h' (eq. 16 for finite q, x_ik − x_jk for 'E').
//!
//! Pair sums run row by row in parallel; each row is summed sequentially and the row totals
//! are added in index order, so the result has the same bits for any thread count.

use crate::pairs::{for_each_pair_tile, scatter_pair};
use crate::{Energy, Error, PointSet, Result};
use rayon::prelude::*;

/// The pair distance inside U_{q,p}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distance {
    /// The q-distance of eq. 11, q ∈ (0, ∞): periodic with period 1 in every coordinate,
    /// smooth for finite q.
    Q(f64),
    /// q = ∞: the torus distance of eq. 9, min(Δ, 1 − Δ) per coordinate.
    Torus,
    /// q = 'E': the Euclidean distance of eq. 8 (not periodic).
    Euclidean,
}

impl Distance {
    /// Parses `q` as the CLI writes it: a positive number, `inf` (or `∞`), or `E`.
    pub fn parse(q: &str) -> Result<Self> {
        let t = q.trim();
        match t {
            "E" | "e" => return Ok(Distance::Euclidean),
            "inf" | "Inf" | "INF" | "infinity" | "∞" => return Ok(Distance::Torus),
            _ => {}
        }
        let v: f64 = t
            .parse()
            .map_err(|_| Error::invalid("q", q, "a number in (0, ∞), `inf` or `E` (Euclidean)"))?;
        Distance::from_q(v)
    }

    /// The q-distance for a numeric q: (0, ∞) finite, or +∞ for the torus distance.
    pub fn from_q(q: f64) -> Result<Self> {
        if q.is_nan() || q <= 0.0 {
            return Err(Error::invalid(
                "q",
                q,
                "a number in (0, ∞), `inf` or `E` (Euclidean)",
            ));
        }
        Ok(if q.is_infinite() {
            Distance::Torus
        } else {
            Distance::Q(q)
        })
    }

    /// How the paper writes q: a number, `∞` or `E`.
    pub fn label(&self) -> String {
        match self {
            Distance::Q(q) => format!("{q}"),
            Distance::Torus => "inf".to_string(),
            Distance::Euclidean => "E".to_string(),
        }
    }

    /// Whether the distance is periodic with period 1 in every coordinate.
    pub fn is_periodic(&self) -> bool {
        !matches!(self, Distance::Euclidean)
    }

    /// Squared distance between two points.
    pub fn squared(&self, a: &[f64], b: &[f64]) -> f64 {
        let kern = Kernel::new(*self);
        a.iter().zip(b).map(|(x, y)| kern.eval(x - y).0).sum()
    }
}

/// Per-coordinate kernel: for the signed difference δ = x_ik − x_jk returns
/// (h(Δ)², sgn(δ)·h(Δ)·h'(Δ)), so that d² = Σ_k h² and ∂d/∂x_ik = (second) / d.
#[derive(Clone, Copy)]
enum Kernel {
    Euclidean,
    Torus,
    Q1,
    Q2,
    Q { q: f64, inv_q: f64 },
}

impl Kernel {
    fn new(d: Distance) -> Self {
        match d {
            Distance::Euclidean => Kernel::Euclidean,
            Distance::Torus => Kernel::Torus,
            Distance::Q(1.0) => Kernel::Q1,
            Distance::Q(2.0) => Kernel::Q2,
            Distance::Q(q) => Kernel::Q { q, inv_q: 1.0 / q },
        }
    }

    #[inline]
    fn eval(&self, delta: f64) -> (f64, f64) {
        match *self {
            Kernel::Euclidean => (delta * delta, delta),
            Kernel::Torus => {
                let (dl, sg) = unit_abs(delta);
                if dl < 0.5 {
                    (dl * dl, sg * dl)
                } else if dl > 0.5 {
                    let t = 1.0 - dl;
                    (t * t, -sg * t)
                } else {
                    // Δ = 1/2 is a kink of min(Δ, 1 − Δ); 0 is the middle of its
                    // subdifferential.
                    (0.25, 0.0)
                }
            }
            Kernel::Q1 => {
                // w = 1: h = Δ(1 − Δ), h·h' = Δ(1 − Δ)(1 − 2Δ).
                let (dl, sg) = unit_abs(delta);
                let t = dl * (1.0 - dl);
                (t * t, sg * t * (1.0 - 2.0 * dl))
            }
            Kernel::Q2 => {
                let (dl, sg) = unit_abs(delta);
                let u = 1.0 - dl;
                let t = dl * u;
                let w = u * u + dl * dl;
                (t * t / w, sg * t * (u * u * u - dl * dl * dl) / (w * w))
            }
            Kernel::Q { q, inv_q } => {
                // h is symmetric about 1/2 (h(Δ) = h(1 − Δ), so h·h' changes sign): work
                // with Δ ≤ 1/2. With t = (Δ/(1 − Δ))^q ≤ 1 and v = (1 + t)^{−1/q}, eq. 11
                // is h = Δ·v and eq. 16 is h·h' = Δ v² ((1 − Δ) − tΔ) / ((1 − Δ)(1 + t)):
                // two powers per coordinate instead of three.
                let (mut dl, mut sg) = unit_abs(delta);
                if dl > 0.5 {
                    dl = 1.0 - dl;
                    sg = -sg;
                }
                if dl == 0.0 {
                    return (0.0, 0.0);
                }
                let u = 1.0 - dl;
                let t = (dl / u).powf(q);
                let v = (1.0 + t).powf(-inv_q);
                let h = dl * v;
                (h * h, sg * h * v * (u - t * dl) / (u * (1.0 + t)))
            }
        }
    }
}

/// |δ| reduced to [0, 1) (the q-distances have period 1) and the sign of δ.
#[inline]
fn unit_abs(delta: f64) -> (f64, f64) {
    let a = delta.abs();
    let a = if a < 1.0 { a } else { a - a.floor() };
    (a, if delta < 0.0 { -1.0 } else { 1.0 })
}

/// The potential energy U_{q,p} of eqs. 5/12 (G = 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Uqp {
    distance: Distance,
    p: f64,
}

impl Uqp {
    /// U_{q,p} with the given distance and finite p > 0.
    pub fn new(distance: Distance, p: f64) -> Result<Self> {
        if !(p > 0.0 && p.is_finite()) {
            return Err(Error::invalid("p", p, "a finite number > 0"));
        }
        if let Distance::Q(q) = distance {
            Distance::from_q(q)?;
        }
        Ok(Uqp { distance, p })
    }

    /// The distance in use.
    pub fn distance(&self) -> Distance {
        self.distance
    }

    /// The exponent p.
    pub fn p(&self) -> f64 {
        self.p
    }

    /// S = Σ_{i<j} d_ij^{-p}, the sum whose 1/p-th power is the energy.
    pub fn pair_sum(&self, points: &PointSet) -> f64 {
        let (n, s) = (points.n(), points.s());
        let x = points.as_slice();
        let kern = Kernel::new(self.distance);
        let half_p = 0.5 * self.p;
        let rows: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|i| {
                let xi = &x[i * s..(i + 1) * s];
                let mut acc = 0.0;
                for j in i + 1..n {
                    let xj = &x[j * s..(j + 1) * s];
                    let d2: f64 = xi.iter().zip(xj).map(|(a, b)| kern.eval(a - b).0).sum();
                    acc += inv_pow(d2, half_p);
                }
                acc
            })
            .collect();
        rows.iter().sum()
    }
}

/// (d²)^{-p/2}: +∞ for coincident points.
#[inline]
fn inv_pow(d2: f64, half_p: f64) -> f64 {
    if half_p == 0.5 {
        1.0 / d2.sqrt()
    } else {
        (-half_p * d2.ln()).exp()
    }
}

impl Energy for Uqp {
    fn name(&self) -> String {
        format!("U_{{q,p}}(q={}, p={})", self.distance.label(), self.p)
    }

    fn value(&self, points: &PointSet) -> f64 {
        if points.n() < 2 {
            return 0.0;
        }
        self.pair_sum(points).powf(1.0 / self.p)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(grad.len(), points.len(), "gradient buffer length");
        let (n, s) = (points.n(), points.s());
        grad.fill(0.0);
        if n < 2 {
            return 0.0;
        }
        let x = points.as_slice();
        let kern = Kernel::new(self.distance);
        let half_p = 0.5 * self.p;
        // Accumulate Σ_j a_ijk / d_ij^{p+2} into row i (and its negative into row j),
        // and S; the common factor −S^{1/p−1} is applied at the end.
        let sum = for_each_pair_tile(n, s, grad, |ri, rj, gi, gj| {
            let mut gbuf = vec![0.0; s];
            let mut acc = 0.0;
            let diag = gj.is_empty();
            for i in ri.clone() {
                let xi = &x[i * s..(i + 1) * s];
                let js = if diag { i + 1..ri.end } else { rj.clone() };
                for j in js {
                    let xj = &x[j * s..(j + 1) * s];
                    let mut d2 = 0.0;
                    for k in 0..s {
                        let (h2, g) = kern.eval(xi[k] - xj[k]);
                        d2 += h2;
                        gbuf[k] = g;
                    }
                    let e = inv_pow(d2, half_p);
                    acc += e;
                    if d2 > 0.0 {
                        scatter_pair(gi, gj, (ri.start, rj.start), (i, j), e / d2, &gbuf);
                    }
                }
            }
            acc
        });
        let scale = -sum.powf(1.0 / self.p - 1.0);
        if scale.is_finite() {
            grad.iter_mut().for_each(|g| *g *= scale);
        } else {
            // Coincident points: the energy is +∞ and no finite force is defined.
            grad.fill(0.0);
        }
        sum.powf(1.0 / self.p)
    }
}

/// (q, p) from the paper's regression (eq. 48, Table 4), with what happened to them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperQp {
    /// q to use, clamped to [`PaperQp::MIN`], 1].
    pub q: f64,
    /// p to use, clamped to [`PaperQp::MIN`], 1].
    pub p: f64,
    /// q as the regression gives it.
    pub raw_q: f64,
    /// p as the regression gives it.
    pub raw_p: f64,
    /// Whether (n, s) lies in the fitted range 1 ≤ s ≤ 20, s ≤ n ≤ 1500.
    pub in_fitted_range: bool,
}

impl PaperQp {
    /// Lower clamp for q and p. The fit was made with q, p ∈ (0, 1]; outside its range the
    /// quadratic can go negative, and very small q or p make the energy's scale overflow.
    pub const MIN: f64 = 0.05;
}

/// Eq. 48: p = α·(1, n, s, n², ns, s²), q = β·(…) with Table 4's coefficients (α for p,
/// β for q). Outside 1 ≤ s ≤ 20, s ≤ n ≤ 1500 the fit is an extrapolation: it is still
/// evaluated, flagged, and clamped to [0.05, 1].
// The coefficients are kept digit for digit as Table 4 prints them.
#[allow(clippy::excessive_precision)]
pub fn paper_qp(n: usize, s: usize) -> PaperQp {
    const ALPHA: [f64; 6] = [
        0.0503965655930105,
        0.0009192090929939,
        -0.0034365336368717,
        -0.0000002204260424,
        -0.0000308280100528,
        0.0022834280933421,
    ];
    const BETA: [f64; 6] = [
        0.1732384430740160,
        -0.0003419881219659,
        0.0046060707097167,
        0.0000001517932891,
        0.0000140768595897,
        0.0004673041886360,
    ];
    let (nf, sf) = (n as f64, s as f64);
    let basis = [1.0, nf, sf, nf * nf, nf * sf, sf * sf];
    let dot = |c: &[f64; 6]| c.iter().zip(&basis).map(|(a, b)| a * b).sum::<f64>();
    let raw_p = dot(&ALPHA);
    let raw_q = dot(&BETA);
    let clamp = |v: f64| v.clamp(PaperQp::MIN, 1.0);
    PaperQp {
        q: clamp(raw_q),
        p: clamp(raw_p),
        raw_q,
        raw_p,
        in_fitted_range: (1..=20).contains(&s) && n >= s && n <= 1500,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_q() {
        assert_eq!(Distance::parse("E").unwrap(), Distance::Euclidean);
        assert_eq!(Distance::parse("inf").unwrap(), Distance::Torus);
        assert_eq!(Distance::parse("0.5").unwrap(), Distance::Q(0.5));
        for bad in ["0", "-1", "nan", "x", ""] {
            let e = Distance::parse(bad).unwrap_err().to_string();
            assert!(e.contains("q") && e.contains("(0, ∞)"), "{e}");
        }
        assert!(Uqp::new(Distance::Torus, 0.0).is_err());
        assert!(Uqp::new(Distance::Torus, f64::INFINITY).is_err());
        assert!(Uqp::new(Distance::Q(-1.0), 1.0).is_err());
    }

    #[test]
    fn q_distance_limits() {
        // q → ∞ approaches the torus distance; q = 1 is Δ(1 − Δ); eq. 11's two forms agree.
        let a = [0.1, 0.8];
        let b = [0.35, 0.05];
        let torus = Distance::Torus.squared(&a, &b);
        let big = Distance::Q(400.0).squared(&a, &b);
        assert!((big - torus).abs() < 1e-3 * torus, "{big} vs {torus}");
        let q1 = Distance::Q(1.0).squared(&a, &b);
        let want: f64 = a
            .iter()
            .zip(&b)
            .map(|(x, y)| {
                let d = (x - y).abs();
                (d * (1.0 - d)).powi(2)
            })
            .sum();
        assert!((q1 - want).abs() < 1e-15);
        for q in [0.3, 1.7, 2.0] {
            let got = Distance::Q(q).squared(&a, &b);
            // First form of eq. 11: 1 / (Δ^{-q} + (1 − Δ)^{-q})^{2/q}.
            let want: f64 = a
                .iter()
                .zip(&b)
                .map(|(x, y)| {
                    let d: f64 = (x - y).abs();
                    (1.0 / (d.powf(-q) + (1.0 - d).powf(-q))).powf(2.0 / q)
                })
                .sum();
            assert!((got - want).abs() < 1e-13 * want, "q={q}: {got} vs {want}");
        }
    }

    #[test]
    fn paper_qp_matches_table4_fit() {
        let f = paper_qp(1500, 2);
        assert!(f.in_fitted_range);
        // Hand evaluation of eq. 48 at (1500, 2).
        assert!((f.raw_p - 0.843028).abs() < 1e-5, "{}", f.raw_p);
        assert!((f.raw_q - 0.055103).abs() < 1e-5, "{}", f.raw_q);
        let out = paper_qp(20_000, 2);
        assert!(!out.in_fitted_range);
        assert!(out.p >= PaperQp::MIN && out.p <= 1.0 && out.q >= PaperQp::MIN && out.q <= 1.0);
        assert!(!paper_qp(10, 21).in_fitted_range);
    }
}
