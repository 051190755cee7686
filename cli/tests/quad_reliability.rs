//! `stillpoint integrate --expr` at the edges: huge and tiny magnitudes, boxes the one
//! box check refuses, the real stop reason, refusals in the flags' names, the point-file
//! mode refusing the --expr options, compact numbers, and -q against --progress.

mod common;

use common::{bin, succeeded, TempDir};

/// `integrate` with `args`: (success, standard output, standard error).
fn run(args: &[&str]) -> (bool, String, String) {
    let o = bin().arg("integrate").args(args).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `integrate ARGS --json`, which must succeed, parsed.
fn json(args: &[&str]) -> serde_json::Value {
    let mut cmd = bin();
    cmd.arg("integrate").args(args).arg("--json");
    let (out, _) = succeeded(&mut cmd, &args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

/// The refusal of `integrate ARGS`: its standard error, which must start `error: START`.
fn refused(args: &[&str], start: &str) -> String {
    let (ok, _, err) = run(args);
    assert!(!ok, "{args:?} succeeded");
    assert!(
        err.starts_with(&format!("error: {start}")),
        "{args:?}: {err}"
    );
    err
}

#[test]
fn huge_integrands_give_finite_numbers_and_meet_the_tolerance() {
    // (expression, s, exact integral over the unit cube)
    for (expr, s, exact) in [
        ("1e308*x1", "1", 5e307),
        ("1e200*(1+x1)", "1", 1.5e200),
        ("-1e307*(x1+x2)", "2", -1e307),
        ("1e-300*x1*x2", "2", 0.25e-300),
    ] {
        let v = json(&["--expr", expr, "-s", s]);
        let est = v["estimate"].as_f64().unwrap_or_else(|| panic!("{v}"));
        let hw = v["half_width"].as_f64().unwrap_or_else(|| panic!("{v}"));
        assert!((est / exact - 1.0).abs() < 1e-3, "{expr}: {v}");
        assert!(
            hw.is_finite() && hw > 0.0 && hw <= 1e-3 * est.abs(),
            "{expr}: {v}"
        );
        assert_eq!(v["met"], true, "{expr}: {v}");
        assert_eq!(v["reason"], "met", "{expr}: {v}");
    }
}

#[test]
fn a_box_whose_volume_overflows_is_integrated_or_refused_by_why() {
    let cube = "0,1e120,0,1e120,0,1e120";
    // 1e-100 over a volume of 1e360: 1e260, representable.
    let v = json(&["--expr", "1e-100", "-s", "3", "--bounds", cube]);
    assert!(
        (v["estimate"].as_f64().unwrap() / 1e260 - 1.0).abs() < 1e-12,
        "{v}"
    );
    // 1 over it: 1e360 is beyond the largest float, refused naming the expression.
    for (expr, magnitude) in [("1", "1.0e360"), ("2*x1/1e120", "1.0e360")] {
        let err = refused(
            &["--expr", expr, "-s", "3", "--bounds", cube],
            "invalid --expr",
        );
        assert!(
            err.contains(magnitude) && err.contains("largest float"),
            "{err}"
        );
    }
    // x1 over a symmetric box of volume 1.6e401: 0, but no estimate fits a float; the run
    // goes to its budget and says so.
    let err = refused(
        &[
            "--expr",
            "x1",
            "-s",
            "2",
            "--bounds=-1e200,1e200,-1e200,1e200",
            // The face test's 7 evaluations and 4 096 of the lattice.
            "--max-n",
            "4103",
        ],
        "invalid --expr \"x1\": values whose estimated",
    );
    assert!(err.contains("after 4103 evaluations"), "{err}");
    // A negative box far from 0: ∫ over [-3e200, -1e200] of 1 = 2e200.
    let v = json(&["--expr", "1", "-s", "1", "--bounds", "-3e200,-1e200"]);
    assert!(
        (v["estimate"].as_f64().unwrap() / 2e200 - 1.0).abs() < 1e-12,
        "{v}"
    );
    assert_eq!(v["half_width"], 0.0, "a constant: {v}");
}

#[test]
fn boxes_are_checked_as_bounds_everywhere() {
    for bounds in ["-1e308,1e308", "1e15,1000000000000000.1", "0,1e-160", "2,1"] {
        let err = refused(
            &["--expr", "1", "-s", "1", "--bounds", bounds],
            &format!("invalid --bounds = {bounds}: expected"),
        );
        assert!(!err.contains("panick"), "{err}");
    }
}

#[test]
fn the_stop_reason_is_the_real_one() {
    // x1·x2 at a relative tolerance of 0 with a budget of M evaluations.
    let budget = |m: &'static str| ["--expr", "x1*x2", "-s", "2", "--rel-tol", "0", "--max-n", m];
    let (ok, out, _) = run(&budget("100000000"));
    assert!(ok);
    assert!(out.contains("evaluations  4194304 (4 replicates)"), "{out}");
    assert!(
        out.contains("no: the sequence's 1048576 points per replicate reached first")
            && !out.contains("--max-n 100000000 reached"),
        "{out}"
    );
    let v = json(&budget("4096"));
    assert_eq!(
        (v["reason"].as_str(), v["n"].as_u64()),
        (Some("max_n"), Some(4096))
    );
    let (_, out, _) = run(&[
        "--expr",
        "exp(x1)",
        "-s",
        "1",
        "--rel-tol",
        "0",
        "--max-n",
        "5000",
    ]);
    assert!(
        out.contains("met          no: --max-n 5000 reached first"),
        "{out}"
    );
    let v = json(&["--expr", "exp(x1)", "-s", "1"]);
    assert_eq!(v["reason"], "met");
}

#[test]
fn refusals_name_the_flag_and_the_value_typed() {
    for (args, start) in [
        (
            &["--expr", "1", "-s", "1", "--rel-tol", "-1e-300"][..],
            "invalid --rel-tol = -1e-300: ",
        ),
        (
            &["--expr", "1", "-s", "1", "--level", "1e5"][..],
            "invalid --level = 1e5: ",
        ),
        (&["--expr", "1", "-s", "0"][..], "invalid -s = 0: "),
        (&["--expr", "1", "-s", "1001"][..], "invalid -s = 1001: "),
        (
            &["--expr", "1", "-s", "1", "--replicates", "100000"][..],
            "invalid --replicates = 100000: ",
        ),
        (
            &["--expr", "1", "-s", "1", "--replicates", "1"][..],
            "invalid --replicates = 1: ",
        ),
        (
            &[
                "--expr",
                "1",
                "-s",
                "1",
                "--replicates",
                "100",
                "--max-n",
                "1000",
            ][..],
            "invalid --max-n = 1000: ",
        ),
        (
            &["--expr", "1", "-s", "1", "--level", "-0.5"][..],
            "invalid --level = -0.5: ",
        ),
        (
            &["--expr", "1", "-s", "1", "--abs-tol", "-1e-3"][..],
            "invalid --abs-tol = -1e-3: ",
        ),
    ] {
        let err = refused(args, start);
        assert!(!err.contains("start_n") && !err.contains("tip:"), "{err}");
    }
}

#[test]
fn a_point_file_refuses_the_expr_options_by_name() {
    let dir = TempDir::new("quad_reliability_file");
    let file = dir.path("p.csv");
    std::fs::write(&file, "0.1,0.2,0.3\n0.6,0.7,0.8\n").unwrap();
    let f = file.to_str().unwrap();
    for (args, flag) in [
        (&[f, "-s", "2", "--seed", "5", "--level", "0.9"][..], "-s"),
        // The first in the order of the help.
        (&[f, "--seed", "5", "--replicates", "4"][..], "--replicates"),
        (&[f, "--bounds", "0,1,0,1,0,1"][..], "--bounds"),
        (&[f, "--rel-tol", "1e-2"][..], "--rel-tol"),
        (&[f, "--max-n", "4096"][..], "--max-n"),
        (&[f, "-q"][..], "-q"),
        (&[f, "--progress", "plain"][..], "--progress"),
    ] {
        let err = refused(args, &format!("invalid {flag}"));
        assert!(err.contains("applies to --expr only"), "{err}");
    }
    // Without them the file is integrated as before.
    let (ok, out, _) = run(&[f]);
    assert!(ok && out.contains("n = 2, s = 3"), "{out}");
}

#[test]
fn results_print_compactly_at_any_magnitude() {
    for (expr, estimate) in [("1e308*x1", "5e307"), ("0.25", "0.25"), ("1e20", "1e20")] {
        let (ok, out, _) = run(&["--expr", expr, "-s", "1"]);
        assert!(ok);
        let line = out.lines().next().unwrap();
        assert_eq!(line, format!("estimate     {estimate}"), "{out}");
        // Every number line is short (the rule's line is prose).
        assert!(
            out.lines()
                .filter(|l| !l.starts_with("rule"))
                .all(|l| l.len() < 200),
            "{out}"
        );
    }
    // Tiny: in scientific notation, reading back to the JSON's value.
    let (_, out, _) = run(&["--expr", "1e-300*(1+x1)", "-s", "1"]);
    let printed = out.lines().next().unwrap()["estimate".len()..]
        .trim()
        .to_string();
    assert!(printed.contains("e-300") && printed.len() < 30, "{out}");
    let v = json(&["--expr", "1e-300*(1+x1)", "-s", "1"]);
    assert_eq!(
        printed.parse::<f64>().unwrap(),
        v["estimate"].as_f64().unwrap()
    );
}

#[test]
fn an_explicit_progress_wins_over_quiet_as_in_generate() {
    // -q with --progress plain writes the same lines as --progress plain alone (the
    // rule of every command), and -q alone writes none.
    let args = |extra: &[&'static str]| {
        let mut v = vec!["--expr", "exp(x1)", "-s", "1", "--rel-tol", "1e-6"];
        v.extend_from_slice(extra);
        v
    };
    let (ok, out_plain, err_plain) = run(&args(&["--progress", "plain"]));
    assert!(ok && err_plain.lines().count() >= 2, "{err_plain}");
    let (ok, out_both, err_both) = run(&args(&["-q", "--progress", "plain"]));
    assert!(ok, "{err_both}");
    assert_eq!(out_both, out_plain);
    let rounds = |e: &str| {
        e.lines()
            .filter(|l| l.starts_with("stillpoint: n="))
            .count()
    };
    assert_eq!(rounds(&err_both), rounds(&err_plain), "{err_both}");
    let (ok, out_quiet, err_quiet) = run(&args(&["-q"]));
    assert!(
        ok && err_quiet.is_empty() && out_quiet == out_plain,
        "{err_quiet}"
    );
    // -q with --progress none agree; --progress plain alone prints its lines.
    let (ok, _, err) = run(&["--expr", "x1", "-s", "1", "-q", "--progress", "none"]);
    assert!(ok && err.is_empty(), "{err}");
    let (ok, _, err) = run(&[
        "--expr",
        "exp(x1)",
        "-s",
        "1",
        "--rel-tol",
        "1e-6",
        "--progress",
        "plain",
    ]);
    assert!(
        ok && err.lines().count() >= 4
            && err.starts_with("stillpoint: a face test first")
            && err.lines().nth(1) == Some("stillpoint: n=7  rule: lattice")
            && err
                .lines()
                .nth(2)
                .is_some_and(|l| l.starts_with("stillpoint: n=263")),
        "{err}"
    );
}
