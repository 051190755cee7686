//! The `stillpoint` command: generate evenly spread point sets, evaluate and integrate
//! with any point file, write the classic sequences, reproduce the paper's studies, and
//! benchmark the kernels. Only this module knows clap, indicatif and the flags' names;
//! it is built with the `cli` feature, which the binary needs.

mod args;
mod dispatch;
mod generate;
mod output;
mod plot;
mod progress;
mod region;
mod report;

#[allow(unused_imports)]
use self::{
    args::*, dispatch::*, generate::*, output::*, plot::*, progress::*, region::*, report::*,
};
#[allow(unused_imports)]
use crate::energies::discrepancy::DiscrepancyKind;
#[allow(unused_imports)]
use crate::energies::region::ImplicitRegion;
#[allow(unused_imports)]
use crate::energies::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex};
#[allow(unused_imports)]
use crate::energies::Domain;
#[allow(unused_imports)]
use crate::energies::{paper_qp, Distance, Energy, Precision, Uqp};
#[allow(unused_imports)]
use crate::metrics::Metrics;
#[allow(unused_imports)]
use crate::regions::{
    generate_in_region_with, RegionConfig, RegionEnergy, RegionInit, RegionReport,
};
#[allow(unused_imports)]
use crate::run::{self, CubeEnergy, GenerateConfig, GenerateReport, Init, Solver};
#[allow(unused_imports)]
use crate::sequences::Baseline;
#[allow(unused_imports)]
use crate::studies::{self, Study, StudyOptions};
#[allow(unused_imports)]
use crate::{bench, io, PointSet};
#[allow(unused_imports)]
use anyhow::{bail, Context, Result};
#[allow(unused_imports)]
use clap::{Parser, Subcommand};
#[allow(unused_imports)]
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
#[allow(unused_imports)]
use serde_json::{json, Value};
#[allow(unused_imports)]
use std::io::IsTerminal;
#[allow(unused_imports)]
use std::path::PathBuf;
#[allow(unused_imports)]
use std::sync::Arc;

/// Parses the command line, runs it, and exits with status 1 and the error on failure.
pub fn main() {
    let cli = Cli::parse();
    if let Err(e) = real_main(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
