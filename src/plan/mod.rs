//! What a run is, before it runs: its configuration ([`config`]), where its points live
//! ([`space`]; linear constraints and mixtures in [`constraints`]), its start set
//! ([`start`]), its energy and domain ([`problem`]), and what it reports ([`report`]).

pub mod config;
pub mod constraints;
pub mod problem;
pub mod report;
pub mod space;
pub mod start;

pub use config::*;
pub use problem::*;
pub use report::*;
pub use start::*;
