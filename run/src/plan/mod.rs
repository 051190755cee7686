//! What a run is made of, before it runs: where its points live ([`space`]; linear
//! constraints and mixtures in [`constraints`]), its start set ([`start`]), and its energy
//! and domain ([`problem`]). Its settings are in [`crate::config`], what it reports in
//! [`crate::report`].

pub mod constraints;
pub mod problem;
pub use stillpoint_parse::space;
pub mod start;
