//! Refusals echo what the user typed: the value of the flag they name, whatever the flag
//! (a target refused by a combination, nested sizes beyond the machine, a negative number
//! for any numeric flag), and an explicit `--progress` wins over `-q`.

use std::process::Output;

mod common;
use common::{bin, TempDir};

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("start stillpoint")
}

/// The first line of standard error of a refused command (its status checked: 1, as
/// for every refused value).
fn refusal(args: &[&str]) -> String {
    let o = run(args);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err.lines().next().unwrap_or_default().to_string()
}

#[test]
fn a_refused_target_is_echoed_as_typed() {
    for (extra, typed) in [
        (&["--goal", "space-filling"][..], "lattice"),
        (&["--method", "paper"][..], "md"),
        (&["--shape", "ball:1"][..], "Blend"),
        (&["--nested", "2,5"][..], "lattice"),
        (&["--randomize", "cells"][..], "lattice"),
        (&["--randomize", "tent"][..], "cd"),
        (&["--energy", "md"][..], "curved"),
    ] {
        let mut args = vec!["generate", "-n", "5", "-s", "2", "--target", typed];
        args.extend_from_slice(extra);
        let e = refusal(&args);
        assert!(
            e.starts_with(&format!("error: invalid --target = {typed}: expected ")),
            "{args:?}: {e}"
        );
        assert!(!e.contains("D²"), "{args:?}: {e}");
    }
}

#[test]
fn other_combinations_echo_the_value_typed_too() {
    for (args, head) in [
        (
            &[
                "generate",
                "-n",
                "5",
                "-s",
                "2",
                "--goal",
                "integration",
                "--method",
                "paper",
            ][..],
            "invalid --goal = integration: ",
        ),
        (
            &[
                "generate", "-n", "5", "-s", "2", "--method", "sobol", "--steps", "10",
            ][..],
            "invalid --steps = 10: ",
        ),
        (
            &[
                "generate", "-n", "5", "-s", "2", "--shape", "ball:1", "--shifts", "3",
            ][..],
            "invalid --shifts = 3: ",
        ),
        (
            &[
                "generate", "-n", "5", "-s", "2", "--bounds", "0,1,0,1", "--shape", "ball:1",
            ][..],
            "invalid --bounds = 0,1,0,1: ",
        ),
        (
            &["generate", "-n", "5", "-s", "2", "--box", "0,1,0,1"][..],
            "invalid --box = 0,1,0,1: ",
        ),
        (
            &["generate", "-n", "7", "-s", "2", "--nested", "2,5"][..],
            "invalid -n = 7: ",
        ),
        (
            &[
                "generate",
                "-n",
                "5",
                "-s",
                "2",
                "--randomize",
                "shift",
                "--nested",
                "2,5",
            ][..],
            "invalid --randomize = shift: ",
        ),
    ] {
        let e = refusal(args);
        assert!(e.starts_with(&format!("error: {head}")), "{args:?}: {e}");
    }
}

#[test]
fn nested_sizes_of_any_size_are_refused_by_nested_with_the_range() {
    for sizes in [
        "16,10000000000",
        "16,100000000000",
        "16,1000000000000000000000000000",
        "1,2,3,99999999999",
    ] {
        let args = ["generate", "-s", "2", "--nested", sizes];
        let e = refusal(&args);
        let head = format!("error: invalid --nested = {sizes}: expected at most ");
        assert!(e.starts_with(&head), "{args:?}: {e}");
        assert!(e.contains(" points in 2 dimensions"), "{args:?}: {e}");
        assert!(!e.contains("increasing"), "{args:?}: {e}");
    }
    // The form is still checked first.
    let e = refusal(&["generate", "-s", "2", "--nested", "16,8"]);
    assert!(
        e.starts_with("error: invalid --nested = 16,8: expected increasing sizes"),
        "{e}"
    );
}

#[test]
fn a_negative_number_for_any_numeric_flag_is_refused_by_name() {
    let d = TempDir::new("typed-negative");
    let points = d.path("p.csv");
    std::fs::write(&points, "0.25,0.25\n0.75,0.75\n").unwrap();
    let p = points.to_str().unwrap();
    let g = |flag: &'static str, v: &'static str| {
        let mut a = vec!["generate", "-o", "/dev/null", "-q"];
        match flag {
            "-n" => a.extend(["-s", "2"]),
            "-s" => a.extend(["-n", "5"]),
            _ => a.extend(["-n", "5", "-s", "2"]),
        }
        a.extend([flag, v]);
        a
    };
    let q = |flag: &'static str, v: &'static str| {
        let mut a = vec!["integrate", "--expr", "x1"];
        if flag != "-s" {
            a.extend(["-s", "2"]);
        }
        a.extend([flag, v]);
        a
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (g("-n", "-1"), "invalid -n = -1: expected at least 1"),
        (g("-s", "-2"), "invalid -s = -2: expected at least 1"),
        (
            g("--seed", "-3"),
            "invalid --seed = -3: expected a whole number",
        ),
        (
            g("--steps", "-5"),
            "invalid --steps = -5: expected a whole number of steps ≥ 1",
        ),
        (
            g("--shifts", "-1"),
            "invalid --shifts = -1: expected a whole number",
        ),
        (
            g("--log-every", "-2"),
            "invalid --log-every = -2: expected a whole number",
        ),
        (
            g("--kappa", "-1"),
            "invalid --kappa = -1: expected auto or a finite number ≥ 1",
        ),
        (
            g("--tolerance", "-0.5"),
            "invalid --tolerance = -0.5: expected a number ≥ 0",
        ),
        (
            g("--p", "-1e3"),
            "invalid --p = -1e3: expected a finite number > 0",
        ),
        (
            g("--checkpoint-every", "-1"),
            "invalid --checkpoint-every = -1: expected a number of steps ≥ 1",
        ),
        (
            g("--threads", "-2"),
            "invalid --threads = -2: expected 1 to 1024 threads",
        ),
        (
            q("--max-n", "-4"),
            "invalid --max-n = -4: expected a whole number ≥ 1",
        ),
        (
            q("--replicates", "-8"),
            "invalid --replicates = -8: expected 2 to 16384",
        ),
        (
            q("--seed", "-1"),
            "invalid --seed = -1: expected a whole number in [0, 2^64)",
        ),
        (
            q("-s", "-2"),
            "invalid -s = -2: expected at least 1 dimension",
        ),
        (
            vec!["plot", p, "-o", "/dev/null.png", "--dims", "-3"],
            "invalid --dims = -3: expected 1 ≤ K ≤ s = 2 (the file's dimension)",
        ),
        (
            vec!["eval", p, "--threads", "-1"],
            "invalid --threads = -1: expected 1 to 1024 threads",
        ),
    ];
    for (args, want) in cases {
        let e = refusal(&args);
        assert!(e.starts_with(&format!("error: {want}")), "{args:?}: {e}");
        assert!(!e.contains("-- -"), "{args:?}: {e}");
    }
}

#[test]
fn an_explicit_progress_wins_over_quiet() {
    let lines = |extra: &[&str]| -> usize {
        let mut args = vec!["generate", "-n", "40", "-s", "2", "-o", "/dev/null"];
        args.extend_from_slice(extra);
        let o = run(&args);
        assert!(o.status.success(), "{args:?}");
        String::from_utf8_lossy(&o.stderr)
            .lines()
            .filter(|l| l.starts_with("stillpoint: ") && l.contains("elapsed"))
            .count()
    };
    // Off a terminal the default is plain lines; -q silences them, an explicit
    // --progress (before or after -q) decides whatever -q says.
    assert!(lines(&[]) >= 1);
    assert_eq!(lines(&["-q"]), 0);
    assert!(lines(&["-q", "--progress", "plain"]) >= 1);
    assert!(lines(&["--progress", "plain", "-q"]) >= 1);
    assert_eq!(lines(&["--progress", "none"]), 0);
    assert_eq!(lines(&["-q", "--progress", "none"]), 0);
}
