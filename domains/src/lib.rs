//! Geometry for the stillpoint many-body model: point sets and the domains they fill.
//!
//! A [`PointSet`] is n points × s coordinates stored row per point in one contiguous
//! buffer; every crate of the workspace uses it. A [`Domain`] says where the points live:
//! the periodic unit cube ([`PeriodicCube`]), implicit regions {g ≤ 0} cut by a box
//! ([`region`]), and closed-form shapes — ball, ellipsoid, box, simplex, polytope
//! ([`shapes`]). [`Error`] and [`Result`] are the error type of the whole model; this is its
//! lowest layer. [`halton::radical_inverse`] is the one Halton coordinate of the workspace
//! and [`wrap_unit`] the one periodic wrap; [`vector_build`] decides, once, which vector
//! build the kernels that have one run.
//!
//! The potential energies over these sets live in `stillpoint-energies`, which re-exports
//! everything here.

#![deny(missing_docs)]

mod domain;
mod error;
pub mod halton;
mod pointset;
mod projection;
pub mod region;
pub mod shapes;
mod vector;

pub use domain::{wrap_unit, Domain, PeriodicCube};
pub use error::{Error, Result};
pub use pointset::PointSet;
pub use vector::{vector_build, VectorBuild};
