//! stillpoint: point sets that fill a domain as evenly as possible, as the static solution
//! of a damped many-body problem (the dynamical evolutionary model, DEM).
//!
//! This crate composes the workspace: [`domains`] (geometry: point sets, the periodic
//! cube, implicit regions, shapes), [`energies`] (potentials, re-exporting the geometry),
//! [`integrators`] (the damped central-difference DEM), and here the metrics that prove a
//! set's quality, the classic sequences it starts from or is compared with, file I/O and
//! the run driver behind the `stillpoint` command.

#![deny(missing_docs)]

pub use stillpoint_domains as domains;
pub use stillpoint_energies as energies;
pub use stillpoint_integrators as integrators;

pub use stillpoint_energies::{Domain, Energy, Error, PeriodicCube, PointSet, Uqp};

pub mod bench;
pub mod checkpoint;
#[cfg(feature = "cli")]
pub mod cli;
pub mod compare;
pub mod evaluate;
pub mod expr;
pub mod io;
pub mod metrics;
pub mod plot;
pub mod polish;
pub mod product_form;
pub mod regions;
pub mod run;
pub mod sequences;
pub mod shift;
pub mod star_inf;
pub mod stratified;
pub mod studies;
pub mod testfns;
pub mod uq;

/// The README's Rust examples, compiled and run as doctests so they stay true.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
