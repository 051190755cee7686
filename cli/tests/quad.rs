//! `stillpoint integrate --expr`: an expression integrated to a tolerance, and the
//! refusals of the second mode of `integrate`.

mod common;

use common::{bin, succeeded, TempDir};

fn run_json(args: &[&str]) -> serde_json::Value {
    let mut cmd = bin();
    cmd.arg("integrate").args(args).arg("--json");
    let (out, _) = succeeded(&mut cmd, &args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
fn a_closed_form_integral_is_reached_within_the_tolerance() {
    // ∫ over [0, 1]^3 of exp(x1 + x2) · (1 + x3) = (e − 1)² · 3/2.
    let exact = (std::f64::consts::E - 1.0).powi(2) * 1.5;
    for tol in ["1e-3", "1e-5"] {
        let v = run_json(&[
            "--expr",
            "exp(x1 + x2) * (1 + x3)",
            "-s",
            "3",
            "--rel-tol",
            tol,
        ]);
        let tol: f64 = tol.parse().unwrap();
        let est = v["estimate"].as_f64().unwrap();
        assert_eq!(v["met"], true, "{v}");
        assert!((est - exact).abs() <= tol * exact, "{est} vs {exact}");
        assert!(v["half_width"].as_f64().unwrap() <= tol * est.abs());
        assert_eq!(v["replicates"], 8);
    }
    // Over a box, the volume is included: ∫_[0,2]×[1,3] x·y = 2 · 4 = 8.
    let v = run_json(&["--expr", "x*y", "-s", "2", "--bounds", "0,2,1,3"]);
    assert!((v["estimate"].as_f64().unwrap() - 8.0).abs() < 8e-3, "{v}");
}

#[test]
fn the_budget_stops_the_run_and_says_so() {
    let v = run_json(&[
        "--expr",
        "exp(x1)",
        "-s",
        "1",
        "--rel-tol",
        "1e-15",
        "--max-n",
        "4096",
    ]);
    assert_eq!(v["met"], false);
    assert_eq!(v["n"], 4096);
}

#[test]
fn a_bad_expression_names_expr() {
    let out = bin()
        .args(["integrate", "--expr", "x1 + x9", "-s", "2"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--expr") && err.contains("x9"), "{err}");
    // A NaN inside the cube is refused, naming the point.
    let out = bin()
        .args(["integrate", "--expr", "sqrt(x1 - 0.5)", "-s", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--expr") && err.contains("NaN at x = ["),
        "{err}"
    );
}

#[test]
fn expr_with_a_point_file_or_without_s_is_refused() {
    let dir = TempDir::new("quad_with_file");
    let file = dir.path("p.csv");
    std::fs::write(&file, "0.1,0.2\n0.6,0.7\n").unwrap();
    let out = bin()
        .arg("integrate")
        .arg(&file)
        .args(["--expr", "x1", "-s", "2"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--expr") && err.contains("cannot be used"),
        "{err}"
    );
    let out = bin().args(["integrate", "--expr", "x1"]).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("-s"), "{err}");
    for (flag, value) in [
        ("--replicates", "1"),
        ("--level", "1.5"),
        ("--rel-tol", "-1"),
    ] {
        let out = bin()
            .args(["integrate", "--expr", "x1", "-s", "1"])
            .arg(format!("{flag}={value}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(&format!("invalid {flag} =")),
            "{err}"
        );
    }
}

#[test]
fn the_point_file_mode_is_unchanged() {
    let out = bin().arg("integrate").output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("<FILE>") || err.contains("--expr"), "{err}");
}
