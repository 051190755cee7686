//! The eight test integrands F1–F8 of the paper (eq. 49) on [0, 1]^s and the quasi-Monte
//! Carlo error a point set makes on each.
//!
//! Every integrand has exact integral 0 and is normalised so that ∫F² = 1 (checked below
//! and in the tests), so the sample mean over a point set *is* the signed integration
//! error and errors are comparable across functions and dimensions.
//!
//! | F  | form | why ∫F² = 1 |
//! |----|------|-------------|
//! | F1 | √(12/s) Σ (x_j − 1/2) | Var x = 1/12, s independent terms |
//! | F2 | √(45/(4s)) Σ (x_j² − 1/3) | Var x² = 1/5 − 1/9 = 4/45 |
//! | F3 | √(18/s) Σ (√x_j − 2/3) | Var √x = 1/2 − 4/9 = 1/18 |
//! | F4 | Π sign(x_j − 1/2), sign(0) = 0 | each factor is ±1 almost everywhere |
//! | F5 | Π c·tanh(15 x_j − 7.5) | ∫tanh² = 1 − 2 tanh(7.5)/15 = 1/c² (below) |
//! | F6 | Π √7 (−2.4 u + 8 u³), u = x_j − 1/2 | 7 (5.76/12 − 38.4/80 + 64/448) = 1 |
//! | F7 | Π 2√3 (x_j − 1/2) | 12 ∫u² = 1 |
//! | F8 | √(2/(s(s−1))) Σ_{i<j} f_i f_j | the s(s−1)/2 products f_i f_j are orthonormal |
//!
//! F5's constant is c = √((15e¹⁵+15)/(13e¹⁵+17)), since 1 − 2 tanh(7.5)/15 =
//! (13e¹⁵+17)/(15(e¹⁵+1)). The paper writes F5's factor as (e^{30x−15} − 1)/(e^{30x−15} + 1),
//! which is tanh(15x − 7.5); `tanh` cannot overflow where the exponential form could.
//!
//! In F8, f = +1 for x < 1/6 or x > 4/6, −1 strictly between, 0 exactly at the two edges
//! (the `f64` nearest to 1/6 and to 4/6); ∫f = 1/6 + 2/6 − 1/2 = 0 and ∫f² = 1, so distinct
//! pairs are orthogonal. The square root scales the sum; it is not taken of it. F8 has no
//! pair to sum for s = 1, so it is reported as not defined (`None`) there rather than as 0
//! or NaN.
//!
//! The functions are evaluated only on [0, 1]^s: [`TestFunction::eval`] answers `None`
//! outside it and [`integrate`] refuses such a point set.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::{Error, PointSet};

/// One of the eight integrands of eq. 49.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum TestFunction {
    /// Linear: √(12/s) (Σ x_j − s/2).
    F1,
    /// Quadratic: √(45/(4s)) (Σ x_j² − s/3).
    F2,
    /// Square roots: √(18/s) (Σ √x_j − 2s/3).
    F3,
    /// Sign product: Π sign(x_j − 0.5).
    F4,
    /// Steep tanh product.
    F5,
    /// Cubic product with several extremes per axis.
    F6,
    /// Linear product.
    F7,
    /// Pairwise products of the three-piece step f.
    F8,
}

/// F5's normalising constant √((15e¹⁵ + 15)/(13e¹⁵ + 17)), written with e⁻¹⁵ so that no
/// large intermediate appears.
fn f5_constant() -> f64 {
    let t = (-15.0f64).exp();
    ((15.0 + 15.0 * t) / (13.0 + 17.0 * t)).sqrt()
}

/// F8's three-piece step: +1 outside [1/6, 4/6], −1 strictly inside, 0 on the edges.
/// Returned as an integer so the pair sum is exact.
pub fn f8_step(x: f64) -> i64 {
    const A: f64 = 1.0 / 6.0;
    const B: f64 = 4.0 / 6.0;
    if x == A || x == B {
        0
    } else if (A..=B).contains(&x) {
        -1
    } else {
        1
    }
}

impl TestFunction {
    /// F1 … F8 in order.
    pub const ALL: [TestFunction; 8] = [
        TestFunction::F1,
        TestFunction::F2,
        TestFunction::F3,
        TestFunction::F4,
        TestFunction::F5,
        TestFunction::F6,
        TestFunction::F7,
        TestFunction::F8,
    ];

    /// F1 … F8 in order.
    pub fn all() -> [TestFunction; 8] {
        Self::ALL
    }

    /// Position in [`TestFunction::ALL`] (F1 → 0).
    pub fn index(&self) -> usize {
        *self as usize
    }

    /// "F1" … "F8".
    pub fn name(&self) -> &'static str {
        match self {
            TestFunction::F1 => "F1",
            TestFunction::F2 => "F2",
            TestFunction::F3 => "F3",
            TestFunction::F4 => "F4",
            TestFunction::F5 => "F5",
            TestFunction::F6 => "F6",
            TestFunction::F7 => "F7",
            TestFunction::F8 => "F8",
        }
    }

    /// The formula in plain text, as implemented.
    pub fn formula(&self) -> &'static str {
        match self {
            TestFunction::F1 => "sqrt(12/s) * sum_j (x_j - 1/2)",
            TestFunction::F2 => "sqrt(45/(4s)) * sum_j (x_j^2 - 1/3)",
            TestFunction::F3 => "sqrt(18/s) * sum_j (sqrt(x_j) - 2/3)",
            TestFunction::F4 => "prod_j sign(x_j - 1/2), sign(0) = 0",
            TestFunction::F5 => "prod_j sqrt((15e^15+15)/(13e^15+17)) * tanh(15 x_j - 7.5)",
            TestFunction::F6 => "prod_j [-2.4 sqrt(7) (x_j - 1/2) + 8 sqrt(7) (x_j - 1/2)^3]",
            TestFunction::F7 => "prod_j 2 sqrt(3) (x_j - 1/2)",
            TestFunction::F8 => {
                "sqrt(2/(s(s-1))) * sum_{i<j} f_i f_j, f = +1 if x < 1/6 or x > 4/6, \
                 -1 if 1/6 < x < 4/6, 0 at x = 1/6 or 4/6 (s >= 2)"
            }
        }
    }

    /// Whether the function is defined in dimension s (F8 needs a pair, s ≥ 2).
    pub fn is_defined(&self, s: usize) -> bool {
        match self {
            TestFunction::F8 => s >= 2,
            _ => s >= 1,
        }
    }

    /// The one-dimensional factor g of a product form F = Π g(x_j) (F4–F7), `None` for
    /// the sums F1–F3 and F8. Each factor has ∫g = 0 and ∫g² = 1 over [0, 1].
    pub fn factor(&self, t: f64) -> Option<f64> {
        let u = t - 0.5;
        match self {
            TestFunction::F4 => Some(if u > 0.0 {
                1.0
            } else if u < 0.0 {
                -1.0
            } else {
                0.0
            }),
            TestFunction::F5 => Some(f5_constant() * (15.0 * t - 7.5).tanh()),
            TestFunction::F6 => {
                let r7 = 7.0f64.sqrt();
                Some(r7 * u * (-2.4 + 8.0 * u * u))
            }
            TestFunction::F7 => Some(2.0 * 3.0f64.sqrt() * u),
            _ => None,
        }
    }

    /// F at x, `None` when F is not defined there: x empty, a coordinate NaN or outside
    /// [0, 1], or F8 with one coordinate.
    pub fn eval(&self, x: &[f64]) -> Option<f64> {
        if !self.is_defined(x.len()) || x.iter().any(|v| !(0.0..=1.0).contains(v)) {
            return None;
        }
        Some(self.eval_unchecked(x))
    }

    /// F at x for x already known to lie in [0, 1]^s with F defined for s.
    fn eval_unchecked(&self, x: &[f64]) -> f64 {
        let s = x.len() as f64;
        match self {
            // Centring each term before summing keeps the result accurate for large s.
            TestFunction::F1 => (12.0 / s).sqrt() * x.iter().map(|&v| v - 0.5).sum::<f64>(),
            TestFunction::F2 => {
                (45.0 / (4.0 * s)).sqrt() * x.iter().map(|&v| v * v - 1.0 / 3.0).sum::<f64>()
            }
            TestFunction::F3 => {
                (18.0 / s).sqrt() * x.iter().map(|&v| v.sqrt() - 2.0 / 3.0).sum::<f64>()
            }
            TestFunction::F4 | TestFunction::F5 | TestFunction::F6 | TestFunction::F7 => {
                x.iter().map(|&v| self.factor(v).unwrap_or(0.0)).product()
            }
            TestFunction::F8 => {
                // Σ_{i<j} f_i f_j = ((Σ f)² − Σ f²)/2, exact in integers: O(s), not O(s²).
                let (sum, sq) = x.iter().fold((0i64, 0i64), |(a, b), &v| {
                    let f = f8_step(v);
                    (a + f, b + f * f)
                });
                let pairs = (sum * sum - sq) / 2;
                (2.0 / (s * (s - 1.0))).sqrt() * pairs as f64
            }
        }
    }

    /// Exact ∫F² over [0, 1]^s, `None` where F is not defined. All eight are normalised to
    /// 1 (see the module table), so this is also the variance of one Monte Carlo sample.
    pub fn variance(&self, s: usize) -> Option<f64> {
        self.is_defined(s).then_some(1.0)
    }
}

/// The mean of each test function over one point set: the QMC estimate, whose distance to
/// the exact 0 is the integration error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntegrationReport {
    /// Number of points.
    pub n: usize,
    /// Dimension.
    pub s: usize,
    /// Estimates of ∫F1 … ∫F8; `None` for F8 when s = 1.
    pub estimates: [Option<f64>; 8],
}

/// One line of an [`IntegrationReport`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntegrationRow {
    /// "F1" … "F8".
    pub name: &'static str,
    /// The sample mean (the estimate of an integral whose exact value is 0).
    pub estimate: Option<f64>,
    /// |estimate − 0|.
    pub abs_error: Option<f64>,
}

impl IntegrationReport {
    /// The estimate for one function.
    pub fn estimate(&self, f: TestFunction) -> Option<f64> {
        self.estimates[f.index()]
    }

    /// |estimate − 0| for one function.
    pub fn abs_error(&self, f: TestFunction) -> Option<f64> {
        self.estimate(f).map(f64::abs)
    }

    /// The report as eight rows (name, estimate, |error|), F1 first.
    pub fn rows(&self) -> Vec<IntegrationRow> {
        TestFunction::ALL
            .iter()
            .map(|f| IntegrationRow {
                name: f.name(),
                estimate: self.estimate(*f),
                abs_error: self.abs_error(*f),
            })
            .collect()
    }
}

/// Points per parallel chunk. Fixed, so that the summation order, and therefore every bit
/// of the result, is the same for any number of threads.
const CHUNK: usize = 4096;

/// Neumaier-compensated running sum: the order is fixed, and compensation keeps the
/// estimate of a zero integral accurate far below the size of the individual values.
#[derive(Clone, Copy, Default)]
struct Compensated {
    sum: f64,
    c: f64,
}

impl Compensated {
    fn add(&mut self, v: f64) {
        let t = self.sum + v;
        if self.sum.abs() >= v.abs() {
            self.c += (self.sum - t) + v;
        } else {
            self.c += (v - t) + self.sum;
        }
        self.sum = t;
    }

    fn value(&self) -> f64 {
        self.sum + self.c
    }
}

/// Integrates F1–F8 with the equal-weight rule of `points`. Refuses a coordinate outside
/// [0, 1]. Deterministic: fixed-size chunks, compensated sums combined in chunk order.
pub fn integrate(points: &PointSet) -> Result<IntegrationReport, Error> {
    points.check_unit_cube()?;
    let s = points.s();
    let data = points.as_slice();
    let partial: Vec<[Compensated; 8]> = data
        .par_chunks(CHUNK * s)
        .map(|block| {
            let mut acc = [Compensated::default(); 8];
            for x in block.chunks_exact(s) {
                for f in TestFunction::ALL {
                    if f.is_defined(s) {
                        acc[f.index()].add(f.eval_unchecked(x));
                    }
                }
            }
            acc
        })
        .collect();
    let mut total = [Compensated::default(); 8];
    for acc in &partial {
        for (t, a) in total.iter_mut().zip(acc) {
            t.add(a.sum);
            t.add(a.c);
        }
    }
    let n = points.n();
    let mut estimates = [None; 8];
    for f in TestFunction::ALL {
        if f.is_defined(s) {
            estimates[f.index()] = Some(total[f.index()].value() / n as f64);
        }
    }
    Ok(IntegrationReport { n, s, estimates })
}

/// The report of [`integrate`] as JSON, as `stillpoint integrate --json` prints it and the
/// Python package returns it: `n`, `s`, `exact` (0) and one object per integrand with
/// `function`, `formula`, `estimate` and `error`.
pub fn report_json(points: &PointSet) -> Result<serde_json::Value, Error> {
    let report = integrate(points)?;
    let rows: Vec<serde_json::Value> = TestFunction::all()
        .iter()
        .zip(report.estimates)
        .map(|(f, e)| {
            serde_json::json!({"function": f.name(), "formula": f.formula(),
                               "estimate": e, "error": e.map(f64::abs)})
        })
        .collect();
    Ok(serde_json::json!({"n": points.n(), "s": points.s(), "exact": 0.0, "functions": rows}))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f5_constant_matches_the_paper_form() {
        let e15 = 15.0f64.exp();
        let direct = ((15.0 * e15 + 15.0) / (13.0 * e15 + 17.0)).sqrt();
        assert!((f5_constant() - direct).abs() < 1e-15);
        // The tanh form equals the paper's exponential ratio.
        for &x in &[0.0, 0.2, 0.49, 0.5, 0.73, 1.0] {
            let e = (30.0 * x - 15.0f64).exp();
            let paper = (e - 1.0) / (e + 1.0);
            assert!(((15.0 * x - 7.5f64).tanh() - paper).abs() < 1e-14);
        }
    }
}
