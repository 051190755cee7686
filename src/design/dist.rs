//! The marginal distributions a design variable may follow, each with its inverse CDF:
//! a design is made uniform in the unit cube, optimised there, and mapped coordinate by
//! coordinate through these quantile functions.

use crate::Error;

/// A continuous variable's marginal distribution.
#[derive(Debug, Clone, PartialEq)]
pub enum Marginal {
    /// Uniform on [lo, hi].
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

impl Marginal {
    /// The quantile function (inverse CDF) at u in [0, 1].
    pub fn ppf(&self, u: f64) -> f64 {
        match self {
            Marginal::Uniform { lo, hi } => lo + (hi - lo) * u,
        }
    }

    /// Checks the parameters; `name` is the variable's name for the refusal.
    pub fn check(&self, name: &str) -> Result<(), Error> {
        match self {
            Marginal::Uniform { lo, hi } if lo < hi && lo.is_finite() && hi.is_finite() => Ok(()),
            Marginal::Uniform { lo, hi } => Err(Error::invalid(
                name,
                format!("uniform({lo},{hi})"),
                "uniform(lo,hi) with finite lo < hi",
            )),
        }
    }
}
