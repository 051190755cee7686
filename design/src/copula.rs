//! Correlated continuous inputs through a Gaussian copula. The design is made and
//! measured in independent uniform scores u; the written values take z = Φ⁻¹(u), then
//! L z with L the Cholesky factor of the correlation matrix, then Φ and each marginal's
//! quantile function. That map is the inverse of the joint law's Rosenblatt transform,
//! so the figures on the unit scale say how well the written points represent the
//! correlated law, and `eval` maps a file back through the same transform.

use super::dist::Marginal;
use crate::Error;

/// A correlation matrix of the continuous variables (in their order), kept as its
/// lower Cholesky factor.
#[derive(Debug, Clone, PartialEq)]
pub struct Copula {
    k: usize,
    /// The matrix, row-major, as given.
    pub matrix: Vec<f64>,
    lower: Vec<f64>,
}

const STANDARD: Marginal = Marginal::Normal {
    mu: 0.0,
    sigma: 1.0,
};

impl Copula {
    /// The copula of a k × k correlation matrix (row-major): symmetric to 1e-12, ones on
    /// the diagonal, off-diagonal entries in (−1, 1), positive definite. `option` and
    /// `shown` name the option and its value in refusals.
    pub fn new(option: &str, shown: &str, k: usize, matrix: Vec<f64>) -> Result<Copula, Error> {
        let bad = |expected: String| Error::invalid(option, shown, expected);
        if matrix.len() != k * k {
            return Err(bad(format!(
                "a {k} × {k} matrix, one row and column per continuous variable ({} numbers)",
                k * k
            )));
        }
        for i in 0..k {
            if (matrix[i * k + i] - 1.0).abs() > 1e-12 {
                return Err(bad(format!(
                    "ones on the diagonal (row {} has {})",
                    i + 1,
                    matrix[i * k + i]
                )));
            }
            for j in 0..i {
                let (a, b) = (matrix[i * k + j], matrix[j * k + i]);
                if !(a.is_finite() && a.abs() < 1.0) || (a - b).abs() > 1e-12 {
                    return Err(bad(format!(
                        "a symmetric matrix with entries in (-1, 1), but ({}, {}) is {a} and \
                         ({}, {}) is {b}",
                        i + 1,
                        j + 1,
                        j + 1,
                        i + 1
                    )));
                }
            }
        }
        let mut lower = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..=i {
                let dot: f64 = (0..j).map(|m| lower[i * k + m] * lower[j * k + m]).sum();
                if i == j {
                    let d = matrix[i * k + i] - dot;
                    // A pivot this small leaves the scores numerically dependent.
                    if d <= 1e-10 {
                        return Err(bad(
                            "a positive definite matrix (a correlation that some law can have)"
                                .into(),
                        ));
                    }
                    lower[i * k + i] = d.sqrt();
                } else {
                    lower[i * k + j] = (matrix[i * k + j] - dot) / lower[j * k + j];
                }
            }
        }
        Ok(Copula { k, matrix, lower })
    }

    /// The number of variables it correlates.
    pub fn k(&self) -> usize {
        self.k
    }

    /// Independent uniform scores to correlated ones (each still uniform on its own).
    pub fn correlate(&self, u: &[f64]) -> Vec<f64> {
        let z: Vec<f64> = u.iter().map(|&v| STANDARD.ppf(v)).collect();
        (0..self.k)
            .map(|i| {
                let zi: f64 = (0..=i).map(|j| self.lower[i * self.k + j] * z[j]).sum();
                STANDARD.cdf(zi)
            })
            .collect()
    }

    /// The inverse of [`Copula::correlate`]: correlated uniform scores back to
    /// independent ones.
    pub fn decorrelate(&self, v: &[f64]) -> Vec<f64> {
        let zc: Vec<f64> = v.iter().map(|&x| STANDARD.ppf(x)).collect();
        let mut z = vec![0.0; self.k];
        for i in 0..self.k {
            let dot: f64 = (0..i).map(|j| self.lower[i * self.k + j] * z[j]).sum();
            z[i] = (zc[i] - dot) / self.lower[i * self.k + i];
        }
        z.iter().map(|&x| STANDARD.cdf(x)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scores_take_the_asked_correlation_and_come_back() {
        let c = Copula::new("c", "m", 2, vec![1.0, 0.6, 0.6, 1.0]).unwrap();
        let n = 4000;
        let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let u = [
                (i as f64 + 0.5) / n as f64,
                ((i * 1597) % n) as f64 / n as f64 + 0.5 / n as f64,
            ];
            let v = c.correlate(&u);
            let z: Vec<f64> = v.iter().map(|&x| STANDARD.ppf(x)).collect();
            sxy += z[0] * z[1];
            sxx += z[0] * z[0];
            syy += z[1] * z[1];
            let back = c.decorrelate(&v);
            assert!((back[0] - u[0]).abs() < 1e-12 && (back[1] - u[1]).abs() < 1e-10);
        }
        let r = sxy / (sxx * syy).sqrt();
        assert!((r - 0.6).abs() < 0.02, "{r}");
    }

    #[test]
    fn bad_matrices_are_refused() {
        for (m, want) in [
            (vec![1.0, 0.5, 0.4, 1.0], "symmetric"),
            (vec![1.0, 1.0, 1.0, 1.0], "(-1, 1)"),
            (vec![2.0, 0.0, 0.0, 1.0], "diagonal"),
            (vec![1.0, 0.0, 1.0], "2 × 2"),
        ] {
            let e = Copula::new("--correlation", "m", 2, m)
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        }
        let e = Copula::new(
            "c",
            "m",
            3,
            vec![1.0, 0.9, -0.9, 0.9, 1.0, 0.9, -0.9, 0.9, 1.0],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("positive definite"), "{e}");
    }
}
