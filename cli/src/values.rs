//! The closed sets of option values (`--integrator`, `--energy`, `--polish`,
//! `--precision`) as clap `ValueEnum`s, and the number-or-word options (`--kappa`,
//! `--restart`). Each parser names the flag and what it accepts when it refuses a value.

use super::*;
use clap::ValueEnum;

/// `--integrator`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum IntegratorArg {
    /// The paper's damped dynamics.
    Dem,
    /// argmin's L-BFGS with restarts.
    Lbfgs,
}

/// `--energy`: every energy; which ones a space accepts is checked with the space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum EnergyArg {
    /// U_{q,p} (the cube's default).
    Uqp,
    /// U_{E,∞}.
    EInf,
    /// U_{E,∞,g} (a region's default).
    EInfG,
    /// U_{E,p,g}.
    #[value(name = "e-p-g")]
    EpG,
    /// Squared star L2 discrepancy.
    L2star,
    /// Squared modified L2 discrepancy.
    Md,
    /// Squared centred L2 discrepancy.
    Cd,
    /// Squared wrap-around L2 discrepancy.
    Periodic,
}

/// `--polish`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum PolishArg {
    /// No polish.
    None,
    /// Modified L2.
    Md,
    /// Star L2.
    L2star,
    /// Centred L2.
    Cd,
    /// Wrap-around L2.
    Periodic,
}

/// `--precision`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum PrecisionArg {
    /// The table of cubics.
    Fast,
    /// The f64 formulas.
    Full,
}

/// `--goal`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum GoalArg {
    /// Quasi-Monte Carlo integration: stratified, lowest discrepancy (the cube's default).
    Integration,
    /// Design of experiments: stratified, largest minimum distance (a region's default).
    SpaceFilling,
}

/// `--method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum MethodArg {
    /// The paper's pipeline exactly: Halton start, U_{q,p} with eq. 48, the DEM, shifts.
    Paper,
}

/// `--target`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum TargetArg {
    /// D²_MD + D²_L2* + D²_CD, each relative to the start (the default).
    Blend,
    /// Modified L2.
    Md,
    /// Star L2.
    L2star,
    /// Centred L2.
    Cd,
    /// Wrap-around L2.
    Periodic,
}

pub(crate) fn goal_arg(text: &str) -> std::result::Result<GoalArg, String> {
    closed("--goal", text, "integration or space-filling")
}

pub(crate) fn method_arg(text: &str) -> std::result::Result<MethodArg, String> {
    closed("--method", text, "paper")
}

pub(crate) fn target_arg(text: &str) -> std::result::Result<run::Target, String> {
    Ok(
        match closed("--target", text, "blend, md, l2star, cd or periodic")? {
            TargetArg::Blend => run::Target::blend(),
            TargetArg::Md => run::Target::single(DiscrepancyKind::ModifiedL2),
            TargetArg::L2star => run::Target::single(DiscrepancyKind::StarL2),
            TargetArg::Cd => run::Target::single(DiscrepancyKind::CenteredL2),
            TargetArg::Periodic => run::Target::single(DiscrepancyKind::WrapAroundL2),
        },
    )
}

/// `--randomize`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum RandomizeArg {
    /// Rotate the cells and shift the offsets within them (keeps the stratification).
    Cells,
    /// A uniform shift modulo 1 (keeps the torus distances and the wrap-around L2).
    Shift,
}

pub(crate) fn randomize_arg(text: &str) -> std::result::Result<run::Randomize, String> {
    Ok(match closed("--randomize", text, "cells or shift")? {
        RandomizeArg::Cells => run::Randomize::Cells,
        RandomizeArg::Shift => run::Randomize::Shift,
    })
}

fn closed<T: ValueEnum>(flag: &str, text: &str, expected: &str) -> std::result::Result<T, String> {
    T::from_str(text.trim(), true)
        .map_err(|_| format!("invalid {flag} = {text}: expected {expected}"))
}

pub(crate) fn integrator_arg(text: &str) -> std::result::Result<Solver, String> {
    Ok(match closed("--integrator", text, "dem or lbfgs")? {
        IntegratorArg::Dem => Solver::Dem,
        IntegratorArg::Lbfgs => Solver::Lbfgs,
    })
}

pub(crate) fn energy_arg(text: &str) -> std::result::Result<EnergyArg, String> {
    EnergyArg::from_str(text.trim(), true).map_err(|_| {
        format!(
            "invalid --energy = {text} in the cube: expected uqp, e-inf, l2star, md, cd or \
             periodic; in a region: e-inf-g, e-inf or e-p-g"
        )
    })
}

impl EnergyArg {
    /// The name on the command line.
    pub(crate) fn name(self) -> String {
        self.to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }
}

/// The value of `--polish`: a discrepancy, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PolishChoice(pub(crate) Option<DiscrepancyKind>);

pub(crate) fn polish_arg(text: &str) -> std::result::Result<PolishChoice, String> {
    Ok(PolishChoice(
        match closed("--polish", text, "none, md, l2star, cd or periodic")? {
            PolishArg::None => None,
            PolishArg::Md => Some(DiscrepancyKind::ModifiedL2),
            PolishArg::L2star => Some(DiscrepancyKind::StarL2),
            PolishArg::Cd => Some(DiscrepancyKind::CenteredL2),
            PolishArg::Periodic => Some(DiscrepancyKind::WrapAroundL2),
        },
    ))
}

pub(crate) fn precision_arg(text: &str) -> std::result::Result<Precision, String> {
    Ok(match closed("--precision", text, "fast or full")? {
        PrecisionArg::Fast => Precision::Fast,
        PrecisionArg::Full => Precision::Full,
    })
}

/// `--kappa auto|K`: the trial from 100, or a fixed κ ≥ 1.
pub(crate) fn kappa_arg(text: &str) -> std::result::Result<Kappa, String> {
    if text.trim().eq_ignore_ascii_case("auto") {
        return Ok(Kappa::default());
    }
    match text.trim().parse::<f64>() {
        Ok(k) if k >= 1.0 && k.is_finite() => Ok(Kappa::Fixed(k)),
        _ => Err(format!(
            "invalid --kappa = {text}: expected `auto` or a finite number ≥ 1"
        )),
    }
}

/// `--restart auto|off|EPS`: ε_p = 2/n, none, or ε_p > 0.
pub(crate) fn restart_arg(text: &str) -> std::result::Result<Restart, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "auto" => Ok(Restart::Auto),
        "off" | "none" => Ok(Restart::Off),
        t => match t.parse::<f64>() {
            Ok(e) if e > 0.0 && !e.is_nan() => Ok(Restart::Threshold(e)),
            _ => Err(format!(
                "invalid --restart = {text}: expected `auto` (ε_p = 2/n), `off`, or a number ε_p > 0"
            )),
        },
    }
}

/// The flag that sets a library parameter (as the library names it in its settings and
/// errors), or the name itself when no flag sets it (n and s are written as the library
/// writes them: `n = 0`).
pub(crate) fn flag_name(parameter: &str) -> String {
    let flag = match parameter {
        "expression" => "--region",
        "log_every" => "--log-every",
        "resume checkpoint" => "--resume",
        "checkpoint" => "--checkpoint",
        "energy" | "q" | "p" | "precision" | "init" | "seed" | "integrator" | "shifts"
        | "polish" | "steps" | "kappa" | "restart" | "tolerance" | "box" | "shape" => {
            return format!("--{parameter}");
        }
        other => other,
    };
    flag.to_string()
}

/// A library error with the parameter it names shown as the flag that sets it.
pub(crate) fn with_flag_names(e: anyhow::Error) -> anyhow::Error {
    // An error with context says which option it concerns already.
    if e.chain().count() > 1 {
        return e;
    }
    match e.downcast::<stillpoint::Error>() {
        Ok(stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        }) => stillpoint::Error::invalid(flag_name(&name), value, expected).into(),
        Ok(other) => other.into(),
        Err(e) => e,
    }
}
