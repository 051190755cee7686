//! Every flag of `integrate --expr` and `sensitivity` as the library declares it
//! (`stillpoint::pipeline::options`, the options of `Command::Quad` and
//! `Command::Sensitivity` that have a flag), walked: a good value is taken, a bad one is
//! refused naming the flag and echoing the value as typed, and the refused combinations
//! name both flags. The examples come from each declaration's kind, so a new option is
//! walked without editing this file.

mod common;

use common::bin;
use stillpoint::pipeline::options::{of_command, Command, Declared, Kind};

/// Runs `command` on a small model with `args`, adding a dimension and a loose tolerance
/// where `args` give none.
fn run(command: Command, args: &[String]) -> (bool, String) {
    let (sub, tolerance) = match command {
        Command::Sensitivity => ("sensitivity", ["--abs-tol", "0.05"]),
        _ => ("integrate", ["--rel-tol", "0.01"]),
    };
    let mut all: Vec<String> = [sub, "--expr", "x1 + 2*x2"].map(String::from).to_vec();
    let has = |flag: &str| args.iter().any(|a| a == flag);
    if !has("-s") && !has("--var") {
        all.extend(["-s", "2"].map(String::from));
    }
    if !has(tolerance[0]) {
        all.extend(tolerance.map(String::from));
    }
    all.extend(args.iter().cloned());
    let out = bin().args(&all).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

/// The flags walked: each declared option of `command` the command line has.
fn walked(command: Command) -> Vec<(&'static str, &'static Declared)> {
    of_command(command)
        .filter_map(|d| d.flag().map(|f| (f, d)))
        .collect()
}

/// A value the declaration accepts, as arguments (with what it needs beside it).
fn good(flag: &str, d: &Declared, command: Command) -> Vec<String> {
    let with = |v: &str| vec![flag.to_string(), v.to_string()];
    let default = (d.default)(command);
    match d.kind {
        Kind::Flag => vec![flag.to_string()],
        Kind::Seed => with("7"),
        Kind::Word(_) => with(d.words().last().copied().unwrap_or_default()),
        Kind::Count { .. } => with(default.as_deref().unwrap_or("2")),
        Kind::Real { .. } => with(match d.name {
            // A tolerance of 0 is never met: the walk asks for a reachable one.
            "abs_tol" => "0.05",
            _ => default.as_deref().unwrap_or("0.5"),
        }),
        Kind::Numbers | Kind::Bounds => with("0,1,0,2"),
        Kind::Texts { .. } => vec![
            flag.into(),
            "x=uniform(0,1)".into(),
            flag.into(),
            "y=uniform(1,2)".into(),
        ],
        Kind::Rows => vec![
            "--var".into(),
            "x=normal(0,1)".into(),
            "--var".into(),
            "y=normal(0,1)".into(),
            flag.into(),
            "1,0.5;0.5,1".into(),
        ],
        _ => Vec::new(),
    }
}

/// Values the declaration refuses.
fn bad(d: &Declared) -> Vec<&'static str> {
    match d.kind {
        Kind::Count { .. } | Kind::Seed => vec!["-1", "x", "1.5"],
        Kind::Real { below, .. } => {
            let mut v = vec!["x", "-1", "nan"];
            if below == Some(1.0) {
                v.push("1");
            }
            v
        }
        Kind::Word(_) => vec!["nope"],
        Kind::Numbers | Kind::Bounds => vec!["0,1,x,2", "0,2,1,1"],
        Kind::Texts { .. } => vec!["x=nope(1)"],
        Kind::Rows => vec!["1,a;0.5,1"],
        _ => Vec::new(),
    }
}

#[test]
fn every_flag_takes_a_good_value() {
    for command in [Command::Quad, Command::Sensitivity] {
        for (flag, d) in walked(command) {
            let args = good(flag, d, command);
            assert!(!args.is_empty(), "{flag}: no example for its kind");
            let (ok, err) = run(command, &args);
            assert!(ok, "{} {args:?}: {err}", command.name());
        }
    }
}

#[test]
fn every_flag_refuses_a_bad_value_by_name_echoing_it() {
    for command in [Command::Quad, Command::Sensitivity] {
        for (flag, d) in walked(command) {
            for value in bad(d) {
                let mut args = vec![flag.to_string(), value.to_string()];
                if matches!(d.kind, Kind::Rows) {
                    let space = ["--var", "x=normal(0,1)", "--var", "y=normal(0,1)"];
                    args.splice(0..0, space.map(String::from));
                }
                let (ok, err) = run(command, &args);
                let named = format!("invalid {flag} = {value}");
                let part = format!("invalid {flag} ");
                assert!(
                    !ok && (err.contains(&named) || d.name == "space" && err.contains(&part)),
                    "{} {args:?}: {err}",
                    command.name()
                );
            }
        }
    }
}

#[test]
fn refused_combinations_name_both_flags() {
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    for (command, args, message) in [
        (
            Command::Quad,
            s(&["--var", "x=normal(0,1)", "--bounds", "0,1"]),
            "invalid --bounds with --var",
        ),
        (
            Command::Quad,
            s(&["--correlation", "1,0.5;0.5,1"]),
            "invalid --correlation without --var or --space",
        ),
        (
            Command::Quad,
            s(&["--var", "x=normal(0,1)", "-s", "3"]),
            "invalid -s = 3: --var has 1 coordinates",
        ),
        (
            Command::Sensitivity,
            s(&["--var", "W=brownian(1,3)"]),
            "invalid --var = W_1",
        ),
    ] {
        let (ok, err) = run(command, &args);
        assert!(!ok && err.contains(message), "{args:?}: {err}");
    }
}
