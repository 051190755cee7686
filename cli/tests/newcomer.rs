//! What a newcomer meets first: comparing files side by side, points in their own box,
//! progress off a terminal, and notes on unusual choices.

mod common;

use common::{bin, succeeded, TempDir};
use std::process::Output;

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn ok(args: &[&str]) -> (String, String) {
    succeeded(bin().args(args), &args)
}

#[test]
fn eval_compares_files_side_by_side() {
    let d = TempDir::new("compare");
    let (a, b) = (d.0.join("ours.csv"), d.0.join("sobol.csv"));
    ok(&[
        "generate",
        "-n",
        "32",
        "-s",
        "2",
        "-q",
        "-o",
        a.to_str().unwrap(),
    ]);
    ok(&[
        "baseline",
        "sobol",
        "-n",
        "32",
        "-s",
        "2",
        "-o",
        b.to_str().unwrap(),
    ]);
    let (table, _) = ok(&["eval", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert!(
        table.contains("ours.csv") && table.contains("sobol.csv"),
        "{table}"
    );
    assert!(
        table.contains('*') && table.contains("lower is better"),
        "{table}"
    );
    // Every figure row marks exactly one best value.
    let marked = table
        .lines()
        .filter(|l| l.contains("discrepancy") || l.contains("distance"))
        .filter(|l| l.contains('*'))
        .count();
    assert!(marked >= 8, "{table}");
    let (json, _) = ok(&["eval", a.to_str().unwrap(), b.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    assert!(rows[0]["file"].as_str().unwrap().ends_with("ours.csv"));
    assert!(rows[1]["star_l2"].as_f64().unwrap() > 0.0);
}

#[test]
fn bounds_scale_the_written_points_and_eval_reads_them_back() {
    let d = TempDir::new("bounds");
    let (unit, scaled) = (d.0.join("u.npy"), d.0.join("b.csv"));
    let bounds = "--bounds=-1,1,10,20,0,0.5";
    ok(&[
        "generate",
        "-n",
        "40",
        "-s",
        "3",
        "-q",
        "-o",
        unit.to_str().unwrap(),
    ]);
    ok(&[
        "generate",
        "-n",
        "40",
        "-s",
        "3",
        "-q",
        bounds,
        "-o",
        scaled.to_str().unwrap(),
    ]);
    let p = stillpoint::io::read_points(&scaled).unwrap();
    let (lo, hi) = ([-1.0, 10.0, 0.0], [1.0, 20.0, 0.5]);
    for r in p.rows() {
        for k in 0..3 {
            assert!(lo[k] <= r[k] && r[k] <= hi[k], "{r:?}");
        }
    }
    let header = std::fs::read_to_string(&scaled).unwrap();
    assert!(header.contains("\"bounds\":\"-1,1,10,20,0,0.5\""));
    let (a, _) = ok(&["eval", unit.to_str().unwrap(), "--json"]);
    let (b, _) = ok(&["eval", scaled.to_str().unwrap(), bounds, "--json"]);
    let (a, b): (serde_json::Value, serde_json::Value) = (
        serde_json::from_str(&a).unwrap(),
        serde_json::from_str(&b).unwrap(),
    );
    for key in ["star_l2", "modified_l2", "centered_l2"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!((x - y).abs() < 1e-9 * x, "{key}: {x} vs {y}");
    }
    // A baseline is scaled the same way; a wrong count of intervals is refused.
    let c = d.0.join("c.csv");
    ok(&[
        "baseline",
        "lhs",
        "-n",
        "20",
        "-s",
        "2",
        "--bounds=5,6,-3,-2",
        "-o",
        c.to_str().unwrap(),
    ]);
    let q = stillpoint::io::read_points(&c).unwrap();
    assert!(q
        .rows()
        .all(|r| (5.0..=6.0).contains(&r[0]) && (-3.0..=-2.0).contains(&r[1])));
    let o = run(&["generate", "-n", "5", "-s", "3", "-q", "--bounds=0,1"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--bounds"));
    let o = run(&["eval", scaled.to_str().unwrap(), "--bounds=0,1,0,1,0,1"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("inside the bounds"));
}

#[test]
fn progress_off_a_terminal_is_plain_lines_and_nothing_with_quiet() {
    let args = [
        "generate",
        "-n",
        "300",
        "-s",
        "3",
        "--method",
        "paper",
        "-o",
        "/dev/null",
    ];
    let clock = std::time::Instant::now();
    let (_, err) = ok(&args);
    let seconds = clock.elapsed().as_secs_f64();
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("stillpoint: "))
        .collect();
    // A line per stage (DEM, shift selection, metrics), and at most one more per 10 s.
    assert!(
        lines.iter().any(|l| l.starts_with("stillpoint: DEM")),
        "{err}"
    );
    assert!(lines.len() <= 4 + (seconds / 10.0) as usize + 1, "{err}");
    assert!(!err.contains("ETA 0s"), "{err}");
    let quiet: Vec<&str> = args.iter().copied().chain(["-q"]).collect();
    let (_, err) = ok(&quiet);
    assert!(
        !err.lines().any(|l| l.starts_with("stillpoint: DEM")),
        "{err}"
    );
    let none: Vec<&str> = args.iter().copied().chain(["--progress", "none"]).collect();
    let (_, err) = ok(&none);
    assert!(
        !err.lines().any(|l| l.starts_with("stillpoint: DEM")),
        "{err}"
    );
}

#[test]
fn unusual_choices_are_named_before_the_run() {
    let (_, err) = ok(&[
        "generate",
        "-n",
        "20",
        "-s",
        "2",
        "--energy",
        "md",
        "--steps",
        "20",
        "-q",
        "-o",
        "/dev/null",
    ]);
    assert!(err.contains("--integrator lbfgs is the solver"), "{err}");
    let d = TempDir::new("notes");
    let s = d.0.join("s.csv");
    let (_, err) = ok(&[
        "baseline",
        "sobol",
        "-n",
        "100",
        "-s",
        "2",
        "-o",
        s.to_str().unwrap(),
    ]);
    assert!(err.contains("not a power of two"), "{err}");
    let (_, err) = ok(&[
        "baseline",
        "sobol",
        "-n",
        "128",
        "-s",
        "2",
        "-o",
        s.to_str().unwrap(),
    ]);
    assert!(!err.contains("power of two"), "{err}");
    let (out, _) = ok(&[
        "generate",
        "-n",
        "20",
        "-s",
        "2",
        "--integrator",
        "lbfgs",
        "--steps",
        "20",
        "-q",
        "-o",
        "/dev/null",
    ]);
    assert!(
        out.contains("after the L-BFGS run") && !out.contains("after the DEM"),
        "{out}"
    );
    // A region is named as it was given, not by an internal form.
    let (out, _) = ok(&[
        "generate",
        "-n",
        "10",
        "--shape",
        "ball:1",
        "-s",
        "2",
        "--steps",
        "20",
        "-q",
        "-o",
        "/dev/null",
    ]);
    assert!(
        out.contains("the shape ball:1") && !out.contains("Ball {"),
        "{out}"
    );
}
