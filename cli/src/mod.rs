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
mod values;

// The submodules share one set of names (`use super::*`): the command line is one
// program split by subcommand, not separate libraries.
#[allow(unused_imports)]
use {
    self::{
        args::*, dispatch::*, generate::*, output::*, plot::*, progress::*, region::*, report::*,
        values::*,
    },
    crate::energies::discrepancy::DiscrepancyKind,
    crate::energies::region::ImplicitRegion,
    crate::energies::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex},
    crate::energies::{paper_qp, Distance, Domain, Energy, Precision, Uqp},
    crate::integrators::{Kappa, Restart},
    crate::metrics::Metrics,
    crate::run::{self, EnergyKind, GenerateConfig, GenerateReport, Init, Solver},
    crate::sequences::Baseline,
    crate::studies::{self, Study, StudyOptions},
    crate::{bench, io, PointSet},
    anyhow::{bail, Context, Result},
    clap::{Parser, Subcommand},
    indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle},
    serde_json::{json, Value},
    std::io::IsTerminal,
    std::path::PathBuf,
    std::sync::Arc,
};

/// Parses the command line, runs it, and exits with status 1 and the error on failure.
pub fn main() {
    // Interrupted (Ctrl-C, SIGTERM): remove the temporaries of the writes under way, so
    // that every output is as it was or complete, then exit as a shell expects.
    let _ = ctrlc::set_handler(|| {
        io::abandon_writes();
        std::process::exit(130);
    });
    let cli = Cli::parse();
    if let Err(e) = real_main(cli).map_err(with_flag_names) {
        // Not eprintln!: a closed standard error (`2>&1 | head`) must not turn a refusal
        // into a panic.
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "error: {e:#}");
        std::process::exit(1);
    }
}
