//! stillpoint: point sets that fill a domain as evenly as possible.
//!
//! Three tasks, one call each:
//!
//! ```
//! // The default set: stratified in every coordinate, discrepancy as low as the descent
//! // reaches (the integration goal).
//! let x = stillpoint::generate(64, 3)?;
//! assert_eq!((x.n(), x.s()), (64, 3));
//!
//! // A set in a region, given as text: an expression g(x) ≤ 0 with its box, or a shape.
//! let disc = stillpoint::region(50, "ball:1@0,0", &[])?;
//! assert!(disc.rows().all(|p| p[0] * p[0] + p[1] * p[1] <= 1.0));
//!
//! // The quality of any set in the unit cube.
//! let m = stillpoint::metrics::Metrics::compute(&x);
//! assert!(m.modified_l2 < 0.1);
//! # Ok::<(), stillpoint::Error>(())
//! ```
//!
//! [`paper`] runs the paper's pipeline (the dynamical evolutionary model: n equal
//! "stars" repel each other under U_{q,p} and a damping force until they rest). Every
//! option of a run is a field of a [`Request`], resolved once into a configuration
//! ([`pipeline::request`]); the command line and the Python package are front ends to it.
//!
//! The layout follows the roles: [`pipeline`] (request → configuration → run),
//! [`config`] (a run's settings), [`plan`] (what a run is made of: space, start,
//! problem), [`report`] (what a run did), [`goals`] (integration, space-filling, the
//! paper's), [`post`] (shift, polish, randomise), [`solve`] (the executor and
//! checkpoints), [`quality`] (metrics, closed forms, star L∞, region measures,
//! integrands), [`sequences`] (the classic sets), [`parse`] (expressions and constraints
//! as typed), [`io`]; pictures are the `stillpoint-plot` crate. The geometry is in
//! [`domains`], the potentials in [`energies`], the solvers in [`integrators`].

#![deny(missing_docs)]

pub use stillpoint_domains as domains;
pub use stillpoint_energies as energies;
pub use stillpoint_integrators as integrators;

pub use stillpoint_domains::{Domain, Error, PeriodicCube, PointSet};
pub use stillpoint_energies::{Energy, Uqp};

pub use stillpoint_cubature as cubature;
pub use stillpoint_cubature::sensitivity;
pub use stillpoint_design as design;
pub use stillpoint_io as io;
pub use stillpoint_parse as parse;
pub use stillpoint_parse::names;
pub use stillpoint_quality as quality;
pub use stillpoint_run::{config, goals, plan, post, report};
pub use stillpoint_sequences as sequences;
pub use stillpoint_solve as solve;

pub mod pipeline;

pub use cubature::{quad, Cubature, QuadOptions, QuadResult};
pub use pipeline::request::Request;
pub use pipeline::{generate, paper, region};
pub use quality::metrics;

/// The README's Rust examples, compiled and run as doctests so they stay true.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The guide's Rust examples (docs/library.md), compiled and run as doctests too.
#[doc = include_str!("../docs/library.md")]
#[cfg(doctest)]
pub struct LibraryGuideDoctests;
