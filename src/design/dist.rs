//! The marginal distributions a design variable may follow, each with its inverse CDF.
#![allow(missing_docs)]
use crate::Error;

#[derive(Debug, Clone, PartialEq)]
pub enum Marginal {
    Uniform {
        lo: f64,
        hi: f64,
    },
    Normal {
        mu: f64,
        sigma: f64,
    },
    TruncNormal {
        mu: f64,
        sigma: f64,
        lo: f64,
        hi: f64,
    },
    LogNormal {
        mu: f64,
        sigma: f64,
    },
    Beta {
        a: f64,
        b: f64,
        lo: f64,
        hi: f64,
    },
    Triangular {
        lo: f64,
        mode: f64,
        hi: f64,
    },
}

impl Marginal {
    pub fn ppf(&self, u: f64) -> f64 {
        match self {
            Marginal::Uniform { lo, hi } => lo + (hi - lo) * u,
            _ => u,
        }
    }
    pub fn cdf(&self, x: f64) -> f64 {
        match self {
            Marginal::Uniform { lo, hi } => (x - lo) / (hi - lo),
            _ => x,
        }
    }
    pub fn check(&self, _name: &str) -> Result<(), Error> {
        Ok(())
    }
    pub fn text(&self) -> String {
        format!("{self:?}")
    }
}
impl Marginal {
    pub fn support(&self) -> (f64, f64) {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
}
