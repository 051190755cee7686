//! One run of stillpoint: what it is made of and how it goes, from its settings to its
//! report.
//!
//! [`config`] holds a run's settings, [`plan`] what it is made of (space, start,
//! problem), [`goals`] the three goals (integration, space-filling, the paper's),
//! [`post`] the steps after it (shift, polish,
//! randomise) and [`report`] what the run did; the executor and checkpoints are
//! `stillpoint-solve`. The resolver that fills a configuration
//! from a request, and the dispatch that runs it, are the layer above
//! (`stillpoint::pipeline`).

#![deny(missing_docs)]

pub mod config;
pub mod goals;
pub mod plan;
pub mod post;
pub mod report;

use stillpoint_domains::{Domain, Error, PointSet};
