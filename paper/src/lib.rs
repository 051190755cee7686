//! The paper's reproductions, kept out of the library so that it does not carry them:
//! its tables and studies ([`studies`]), the uncertainty-quantification examples
//! ([`uq`]), the side-by-side solver comparison ([`compare`]) and the kernel benchmarks
//! ([`mod@bench`]). Only the command line uses this crate.

#![deny(missing_docs)]

pub mod bench;
pub mod compare;
pub mod studies;
pub mod uq;
