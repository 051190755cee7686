//! The `stillpoint` command: generate evenly spread point sets, evaluate and integrate
//! with any point file, write the classic sequences, reproduce the paper's studies, and
//! benchmark the kernels. A thin binary: clap's arguments become one library request
//! (`stillpoint::Request`), which the library resolves; only this crate knows
//! clap, indicatif and the flags' names.

mod args;
mod design;
mod dispatch;
mod generate;
mod help;
mod output;
mod plot;
mod progress;
mod quad;
mod quad_args;
mod region;
mod report;
mod sensitivity;
mod streams;
mod values;

// The submodules share one set of names (`use super::*`): the command line is one
// program split by subcommand, not separate libraries.
use {
    self::{
        args::*,
        design::*,
        dispatch::*,
        generate::*,
        output::*,
        plot::*,
        progress::*,
        quad::*,
        quad_args::*,
        region::*,
        report::*,
        sensitivity::*,
        streams::{note, noteln, out, outln},
        values::*,
    },
    anyhow::{bail, Context, Result},
    clap::{Parser, Subcommand},
    indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle},
    serde_json::{json, Value},
    std::io::IsTerminal,
    std::path::PathBuf,
    std::sync::Arc,
    stillpoint::config::{points_fingerprint, GenerateConfig, Init, Space},
    stillpoint::domains::Domain,
    stillpoint::energies::discrepancy::DiscrepancyKind,
    stillpoint::pipeline::options::Opt,
    stillpoint::pipeline::request::{Arg, Job, Resolved},
    stillpoint::quality::metrics::Metrics,
    stillpoint::report::GenerateReport,
    stillpoint::sequences::Baseline,
    stillpoint::solve::checkpoint::{read_checkpoint, CheckpointPlan},
    stillpoint::solve::{Event, Solver},
    stillpoint::Request,
    stillpoint::{io, PointSet},
    stillpoint_paper::bench,
    stillpoint_paper::studies::{self, Study, StudyOptions},
};

/// Parses the command line, runs it, and exits with status 1 and the error on failure.
fn main() {
    // Interrupted (Ctrl-C, SIGTERM): remove the temporaries of the writes under way, so
    // that every output is as it was or complete, then exit as a shell expects.
    let _ = ctrlc::set_handler(|| {
        io::abandon_writes();
        std::process::exit(130);
    });
    let parsed = Cli::command_with_declared_help()
        .try_get_matches()
        .and_then(|m| <Cli as clap::FromArgMatches>::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        // Help and version go to standard output, which may fail like any result.
        Err(e)
            if matches!(
                e.kind(),
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion
            ) =>
        {
            let printed = e
                .print()
                .map_err(|io| anyhow::Error::new(io).context("cannot write to standard output"))
                .and_then(|()| streams::flush_out());
            std::process::exit(match printed {
                Ok(()) => 0,
                Err(e) => fail(e),
            })
        }
        Err(e) => e.exit(),
    };
    let done = real_main(cli).and_then(|()| streams::flush_out());
    if let Err(e) = done.map_err(with_flag_names) {
        std::process::exit(fail(e));
    }
}

/// Reports a failed command on standard error and gives its exit status: 1, or that of
/// a program killed by SIGPIPE when the reader closed the pipe.
fn fail(e: anyhow::Error) -> i32 {
    if streams::is_closed_pipe(&e) {
        return streams::CLOSED_PIPE_STATUS;
    }
    // Not eprintln!: a closed standard error (`2>&1 | head`) must not turn a refusal
    // into a panic.
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "error: {e:#}");
    1
}
