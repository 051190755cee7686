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
        assert_eq!(v["replicates"], 4);
        assert_eq!(v["rule"], "lattice");
    }
    // Over a box, the volume is included: ∫_[0,2]×[1,3] x·y = 2 · 4 = 8.
    let v = run_json(&["--expr", "x*y", "-s", "2", "--bounds", "0,2,1,3"]);
    assert!((v["estimate"].as_f64().unwrap() - 8.0).abs() < 8e-3, "{v}");
}

#[test]
fn the_budget_stops_the_run_and_says_so() {
    let budget = |max_n: &str| {
        run_json(&[
            "--expr",
            "exp(x1)",
            "-s",
            "1",
            "--rel-tol",
            "1e-15",
            "--max-n",
            max_n,
        ])
    };
    let v = budget("4096");
    assert_eq!(v["met"], false);
    // The face test's 7 evaluations, 2 048 of the lattice, then the last doubling made
    // short: 510 of its 512 points per replicate, all the budget but one evaluation.
    assert_eq!(v["n"], 7 + 2048 + 4 * 510);
    assert_eq!(v["replicates"], 4);
    assert_eq!(v["rule"], "lattice");
    // A budget holding less than three quarters of that doubling (361 of 512 points per
    // replicate) buys whole replicates of 512 instead, as many as it holds.
    let v = budget("3500");
    assert_eq!(
        (v["n"].as_u64(), v["replicates"].as_u64()),
        (Some(7 + 2048 + 2 * 512), Some(6))
    );
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
    // Under laws the point is named by the variables' values (in [10, 20] here), not by
    // the unit point the rule drew.
    let out = bin()
        .args([
            "integrate",
            "--expr",
            "sqrt(a - 15)",
            "--var",
            "a=uniform(10,20)",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let at = err
        .split("NaN at x = [")
        .nth(1)
        .and_then(|r| r.split(']').next());
    let a: f64 = at
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    assert!((10.0..15.0).contains(&a), "{err}");
}

#[test]
fn expr_without_s_or_with_tolerance_flags_on_files_is_refused() {
    let dir = TempDir::new("quad_with_file");
    let file = dir.path("p.csv");
    std::fs::write(&file, "0.1,0.2\n0.6,0.7\n").unwrap();
    for (flag, value) in [
        ("--max-n", "4096"),
        ("--seed", "3"),
        ("--var", "a=normal(0,1)"),
    ] {
        let out = bin()
            .arg("integrate")
            .arg(&file)
            .args(["--expr", "x1", flag, value])
            .output()
            .unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("invalid {flag} with point files")),
            "{err}"
        );
    }
    // -s is checked against the file's columns.
    let out = bin()
        .arg("integrate")
        .arg(&file)
        .args(["--expr", "x1", "-s", "3"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("2 columns; expected 3, as -s 3"),
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
fn files_with_expr_give_the_mean_and_standard_error_over_the_files() {
    let dir = TempDir::new("quad_files_expr");
    let a = dir.path("a.csv");
    let b = dir.path("b.csv");
    let c = dir.path("c.csv");
    std::fs::write(&a, "0.1,0.2\n0.6,0.7\n").unwrap();
    std::fs::write(&b, "0.3,0.4\n0.5,0.9\n").unwrap();
    std::fs::write(&c, "0.2,0.2\n").unwrap();
    let v = run_json(&[
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        c.to_str().unwrap(),
        "--expr",
        "x1 + 10*x2",
    ]);
    // The files' means of x1 + 10·x2: (2.1 + 7.6)/2, (4.3 + 9.5)/2, 2.2.
    let means = [4.85, 6.9, 2.2];
    let files = v["files"].as_array().unwrap();
    for (f, m) in files.iter().zip(means) {
        assert!((f["mean"].as_f64().unwrap() - m).abs() < 1e-12, "{f}");
    }
    let mean = means.iter().sum::<f64>() / 3.0;
    let sd = (means.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
    assert!(
        (v["estimate"].as_f64().unwrap() - mean).abs() < 1e-12,
        "{v}"
    );
    let se = v["standard_error"].as_f64().unwrap();
    assert!((se - sd / 3f64.sqrt()).abs() < 1e-12, "{v}");
    // t_{2, 0.975} = 4.3027.
    let hw = v["half_width"].as_f64().unwrap();
    assert!((hw / se - 4.302652729911275).abs() < 1e-6, "{v}");
    assert_eq!(v["n"], 5);
    // One file: its mean, and no standard error.
    let v = run_json(&[a.to_str().unwrap(), "--expr", "x1"]);
    assert!((v["estimate"].as_f64().unwrap() - 0.35).abs() < 1e-15);
    assert!(v["standard_error"].is_null(), "{v}");
    // The eight test functions need one file.
    let out = bin().arg("integrate").arg(&a).arg(&b).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("2 files without --expr"),
        "{err}"
    );
}

#[test]
fn expr_under_a_space_integrates_against_its_laws() {
    // E[a² + b] with a ~ N(1, 2²) (E a² = 5) and b ~ U(0, 2): 6.
    let v = run_json(&[
        "--expr",
        "x1^2 + x2",
        "--var",
        "a=normal(1,2)",
        "--var",
        "b=uniform(0,2)",
        "--rel-tol",
        "1e-3",
    ]);
    let est = v["estimate"].as_f64().unwrap();
    assert_eq!(v["met"], true, "{v}");
    assert!((est - 6.0).abs() < 6e-3 * 2.0, "{v}");
    assert_eq!(v["s"], 2);
    // One unbounded law: its tails reached through the tail map, where a² · T′ decays,
    // so f is flat at the faces and the Bayesian lattice goes on after the probe.
    assert_eq!(v["rule"], "bayesian lattice");
    let reason = v["rule_reason"].as_str().unwrap();
    assert!(reason.contains("(a)") && reason.contains("tail map"), "{v}");
    // Bounded laws keep the tent lattice.
    let v = run_json(&["--expr", "x1", "--var", "u=uniform(0,4)"]);
    assert_eq!(v["rule"], "lattice");
    assert!((v["estimate"].as_f64().unwrap() - 2.0).abs() < 4e-3, "{v}");
    // A Brownian path: E[W(1)²] = 1 (its last column).
    let v = run_json(&[
        "--expr",
        "x4^2",
        "--var",
        "W=brownian(1,4)",
        "--rel-tol",
        "1e-2",
    ]);
    assert!((v["estimate"].as_f64().unwrap() - 1.0).abs() < 0.03, "{v}");
    // A correlation: E[x1·x2] = ρ for standard normals.
    let v = run_json(&[
        "--expr",
        "x1*x2",
        "--var",
        "p=normal(0,1)",
        "--var",
        "q=normal(0,1)",
        "--correlation",
        "1,0.5;0.5,1",
        "--rel-tol",
        "1e-2",
    ]);
    assert!((v["estimate"].as_f64().unwrap() - 0.5).abs() < 0.015, "{v}");
    // Refusals name the flag and the value as typed.
    for (args, want) in [
        (
            vec!["--var", "a=normal(0,1)", "-s", "3"],
            "invalid -s = 3: --var has 1 coordinates",
        ),
        (
            vec!["--var", "a=normal(0,1)", "--bounds", "0,1"],
            "invalid --bounds with --var",
        ),
        (
            vec!["--correlation", "1,0.5;0.5,1", "-s", "2"],
            "invalid --correlation without",
        ),
        (vec!["--var", "a=nomral(0,1)"], "--var"),
    ] {
        let out = bin()
            .args(["integrate", "--expr", "x1"])
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(want),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn the_point_file_mode_is_unchanged() {
    let out = bin().arg("integrate").output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("<FILES>") || err.contains("--expr"), "{err}");
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
    // The rule's line, the face test's (7 evaluations), then the evaluations doubling from
    // 4 replicates × 64 points up to the reported total.
    assert!(
        lines[0].starts_with("stillpoint: a face test first"),
        "{err}"
    );
    assert_eq!(lines[1], "stillpoint: n=7  rule: lattice", "{err}");
    let lines = &lines[2..];
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
    let want: Vec<u64> = (0..ns.len()).map(|i| 7 + (256 << i)).collect();
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
    assert_eq!(err.lines().count(), lines.len() + 2);
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
