//! Measures of a point set: the L2 discrepancies and distances ([`metrics`]; exact, or
//! estimated above a size, with the grid search of [`nearest`]), the exact star L∞
//! discrepancy ([`star_inf`]), stratification ([`stratification`]), the
//! integration goal's criterion ([`target`]) and its work ([`effort`]), the figures of a set in a region
//! ([`region`], with its [`energy_distance`] to the region's uniform distribution), the
//! paper's test integrands ([`integrands`]), and every figure of `eval` in one JSON
//! object ([`evaluate`]).

#![deny(missing_docs)]

use stillpoint_domains::{Error, PointSet};

pub mod effort;
pub mod energy_distance;
pub mod evaluate;
pub mod integrands;
pub mod metrics;
pub mod nearest;
pub mod region;
pub mod star_inf;
pub mod stratification;
pub mod target;
