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

/// `integrate --expr` with `extra` flags: (standard output, standard error).
fn run_with(extra: &[&str]) -> (String, String) {
    let mut cmd = bin();
    cmd.args([
        "integrate",
        "--expr",
        "exp(x1 + x2) * (1 + x3)",
        "-s",
        "3",
        "--rel-tol",
        "1e-4",
    ])
    .args(extra);
    succeeded(&mut cmd, &extra)
}

#[test]
fn progress_plain_writes_a_line_per_doubling_and_leaves_the_result_alone() {
    let (quiet_out, quiet_err) = run_with(&["-q"]);
    assert_eq!(quiet_err, "", "-q writes nothing on standard error");
    // Off a terminal (as here) the default is no progress either.
    let (default_out, default_err) = run_with(&[]);
    assert_eq!(default_err, "");
    assert_eq!(default_out, quiet_out);
    let (out, err) = run_with(&["--progress", "plain"]);
    assert_eq!(out, quiet_out, "standard output is unchanged");
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines.len() >= 2, "{err}");
    // The evaluations double from 8 replicates × 64 points up to the reported total.
    let ns: Vec<u64> = lines
        .iter()
        .map(|l| {
            assert!(
                l.starts_with("stillpoint: n=")
                    && l.contains("estimate=")
                    && l.contains("half-width=")
                    && l.contains("(target ")
                    && l.ends_with(" s"),
                "{l}"
            );
            let n = l["stillpoint: n=".len()..]
                .split_whitespace()
                .next()
                .unwrap();
            n.parse().unwrap()
        })
        .collect();
    let want: Vec<u64> = (0..ns.len()).map(|i| 512 << i).collect();
    assert_eq!(ns, want);
    let total = out
        .lines()
        .find_map(|l| l.strip_prefix("evaluations"))
        .and_then(|l| l.split_whitespace().next())
        .unwrap();
    assert_eq!(total, ns.last().unwrap().to_string(), "{out}");
    // The last line's target is the tolerance at the last estimate.
    let last = lines.last().unwrap();
    let field = |key: &str| -> f64 {
        let rest = &last[last.find(key).unwrap() + key.len()..];
        rest.split([' ', ')']).next().unwrap().parse().unwrap()
    };
    let (estimate, half_width, target) =
        (field("estimate="), field("half-width="), field("(target "));
    assert!((target - 1e-4 * estimate).abs() <= 0.06 * target, "{last}");
    assert!(half_width <= target * 1.06, "{last}");
    // -q agrees with --progress none (an explicit plain wins, see quad_reliability);
    // none is none; JSON output is unchanged too.
    assert_eq!(run_with(&["-q", "--progress", "none"]).1, "");
    assert_eq!(run_with(&["--progress", "none"]).1, "");
    let (json_plain, err) = run_with(&["--json", "--progress", "plain"]);
    assert_eq!(json_plain, run_with(&["--json"]).0);
    assert_eq!(err.lines().count(), lines.len());
}

#[test]
fn progress_flags_need_expr() {
    let dir = TempDir::new("quad_progress_file");
    let file = dir.path("p.csv");
    std::fs::write(&file, "0.1,0.2\n0.6,0.7\n").unwrap();
    let out = bin()
        .arg("integrate")
        .arg(&file)
        .args(["--progress", "plain"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--expr"), "{err}");
}
