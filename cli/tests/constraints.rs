//! Linear constraints and mixtures from the command line: every point inside and every
//! constraint held, mixtures that sum to 1 within their bounds, the guide's examples, and
//! the refusals of what has no points.

mod common;
use common::{bin, doc_lines, succeeded, TempDir};
use stillpoint::PointSet;

fn run(dir: &TempDir, out: &str, args: &[&str]) -> PointSet {
    succeeded(
        bin()
            .arg("generate")
            .args(args)
            .args(["-q", "-o"])
            .arg(dir.path(out)),
        &args,
    );
    stillpoint::io::read_points(&dir.path(out)).unwrap()
}

/// The largest violation of a·x ≤ b over the points (negative when all hold strictly).
fn worst(p: &PointSet, a: &[f64], b: f64) -> f64 {
    p.rows()
        .map(|x| x.iter().zip(a).map(|(x, a)| x * a).sum::<f64>() - b)
        .fold(f64::NEG_INFINITY, f64::max)
}

fn in_box(p: &PointSet, lo: &[f64], hi: &[f64]) -> bool {
    p.rows()
        .all(|x| (0..x.len()).all(|k| lo[k] <= x[k] && x[k] <= hi[k]))
}

#[test]
fn constrained_points_are_inside_for_both_goals() {
    let dir = TempDir::new("inside");
    let args = [
        "--constraint",
        "x1 + 2*x2 <= 1",
        "--constraint",
        "3 x3 >= x1 - 0.5",
        "--box",
        "0,1,0,1,0,1",
        "-n",
        "40",
        "--seed",
        "3",
    ];
    let integration = run(
        &dir,
        "i.npy",
        &[&args[..], &["--goal", "integration"]].concat(),
    );
    let filling = run(
        &dir,
        "f.csv",
        &[&args[..], &["--goal", "space-filling", "--steps", "1500"]].concat(),
    );
    for p in [&integration, &filling] {
        assert_eq!((p.n(), p.s()), (40, 3));
        assert!(in_box(p, &[0.0; 3], &[1.0; 3]));
        assert!(worst(p, &[1.0, 2.0, 0.0], 1.0) <= 1e-12);
        assert!(worst(p, &[1.0, 0.0, -3.0], 0.5) <= 1e-12);
        // The points spread: no two on top of each other.
        assert!(stillpoint::quality::metrics::min_distance_euclidean(p) > 0.02);
    }
    // The constraint binds: a set of the whole box would cross x1 + 2 x2 = 1.
    assert!(worst(&integration, &[1.0, 2.0, 0.0], 1.0) > -0.1);
    assert_ne!(integration, filling);
    let again = run(
        &dir,
        "j.npy",
        &[&args[..], &["--goal", "integration"]].concat(),
    );
    assert_eq!(integration, again);
}

#[test]
fn mixtures_sum_to_one_within_their_bounds() {
    let dir = TempDir::new("mixture");
    let (lo, hi) = ([0.1, 0.0, 0.05, 0.0], [0.7, 0.6, 1.0, 0.5]);
    let bounds = "0.1,0.7,0,0.6,0.05,1,0,0.5";
    for goal in ["integration", "space-filling"] {
        let p = run(
            &dir,
            &format!("{goal}.npy"),
            &[
                "--mixture",
                "-s",
                "4",
                "--box",
                bounds,
                "--constraint",
                "x1 + x4 >= 0.3",
                "--constraint",
                "x3 <= 2*x2",
                "-n",
                "30",
                "--goal",
                goal,
            ],
        );
        assert_eq!((p.n(), p.s()), (30, 4));
        for x in p.rows() {
            assert!((x.iter().sum::<f64>() - 1.0).abs() <= 1e-12, "{x:?}");
        }
        assert!(in_box(&p, &lo, &hi), "{goal}");
        assert!(worst(&p, &[-1.0, 0.0, 0.0, -1.0], -0.3) <= 1e-12, "{goal}");
        assert!(worst(&p, &[0.0, -2.0, 1.0, 0.0], 0.0) <= 1e-12, "{goal}");
        assert!(stillpoint::quality::metrics::min_distance_euclidean(&p) > 0.01);
    }
    // Without a box, the components lie in [0, 1]; the last one is not a constant.
    let p = run(
        &dir,
        "plain.csv",
        &["--mixture", "-s", "3", "-n", "25", "--goal", "integration"],
    );
    assert!(in_box(&p, &[0.0; 3], &[1.0; 3]));
    assert!(p
        .rows()
        .all(|x| (x.iter().sum::<f64>() - 1.0).abs() <= 1e-12));
    let last: Vec<f64> = p.rows().map(|x| x[2]).collect();
    let spread =
        last.iter().cloned().fold(0.0, f64::max) - last.iter().cloned().fold(1.0, f64::min);
    assert!(spread > 0.5, "{spread}");
    // Eight components: the 7-simplex keeps 1 in 5040 draws of its box, so its uniform
    // points come from the simplex itself.
    let p = run(
        &dir,
        "eight.npy",
        &["--mixture", "-s", "8", "-n", "20", "--goal", "integration"],
    );
    assert_eq!((p.n(), p.s()), (20, 8));
    assert!(in_box(&p, &[0.0; 8], &[1.0; 8]));
    assert!(p
        .rows()
        .all(|x| (x.iter().sum::<f64>() - 1.0).abs() <= 1e-12));
}

#[test]
fn a_mixture_report_describes_the_written_components() {
    let o = bin()
        .args([
            "generate",
            "--mixture",
            "-s",
            "3",
            "-n",
            "12",
            "--goal",
            "integration",
        ])
        .args(["--json", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["s"], 3);
    assert!(v["figures_in"].as_str().unwrap().contains("x1..x2"), "{v}");
    assert_eq!(v["points"].as_array().unwrap().len(), 12);
    assert_eq!(v["points"][0].as_array().unwrap().len(), 3);
    let table = bin()
        .args([
            "generate",
            "--mixture",
            "-s",
            "3",
            "-n",
            "12",
            "--goal",
            "integration",
        ])
        .arg("-q")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&table.stderr);
    assert!(text.contains("s = 3 in mixtures of 3 components"), "{text}");
}

#[test]
fn the_guides_examples_run_as_written() {
    let lines = doc_lines("docs/regions.md", |l| {
        l.starts_with("stillpoint ") && (l.contains("initial.csv") || l.contains("blend.csv"))
    });
    assert_eq!(lines.len(), 2, "{lines:?}");
    let dir = TempDir::new("guide");
    for line in &lines {
        let words = common::shell_words(line.trim_start_matches("stillpoint "), '"');
        succeeded(bin().current_dir(&dir.0).args(&words).arg("-q"), line);
    }
    let initial = stillpoint::io::read_points(&dir.path("initial.csv")).unwrap();
    assert_eq!((initial.n(), initial.s()), (32, 3));
    assert!(in_box(&initial, &[0.0; 3], &[1.0; 3]));
    assert!(worst(&initial, &[1.0, 2.0, 0.0], 1.0) <= 1e-12);
    assert!(worst(&initial, &[0.0, -1.0, -1.0], -0.2) <= 1e-12);
    let blend = stillpoint::io::read_points(&dir.path("blend.csv")).unwrap();
    assert_eq!((blend.n(), blend.s()), (20, 3));
    assert!(in_box(&blend, &[0.1, 0.0, 0.0], &[0.8, 0.6, 1.0]));
    assert!(worst(&blend, &[-1.0, -1.0, 0.0], -0.3) <= 1e-12);
    // The CSV's numbers are the shortest that read back, so the sum holds after reading.
    assert!(blend
        .rows()
        .all(|x| (x.iter().sum::<f64>() - 1.0).abs() <= 1e-12));
}

#[test]
fn what_leaves_no_points_is_refused_naming_the_option() {
    let dir = TempDir::new("refusals");
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["--constraint", "x1 + x2 >= 3", "--box", "0,1,0,1"],
            &["invalid --constraint = x1 + x2 >= 3", "interior"],
        ),
        (
            &["--constraint", "x3 <= 1", "--box", "0,1,0,1"],
            &["invalid --constraint = x3 <= 1", "x1..x2"],
        ),
        (
            &["--constraint", "x1*x2 <= 0.5", "--box", "0,1,0,1"],
            &["invalid --constraint", "not linear"],
        ),
        (
            &["--constraint", "x1^2 + x2 <= 0.5", "--box", "0,1,0,1"],
            &["invalid --constraint", "not linear"],
        ),
        (
            &["--constraint", "x1 + x2 = 1", "--box", "0,1,0,1"],
            &["invalid --constraint", "--mixture"],
        ),
        (
            &["--constraint", "2 <= 3", "--box", "0,1,0,1"],
            &["invalid --constraint", "no variable"],
        ),
        (
            &["--constraint", "x1 <= 0.5"],
            &["invalid --box", "--constraint needs a box"],
        ),
        (
            &[
                "--constraint",
                "x1 <= 0.5",
                "--box",
                "0,1,0,1",
                "--region",
                "x1 - 1",
            ],
            &["invalid --region", "--constraint"],
        ),
        (
            &["--mixture", "-s", "3", "--box", "0.5,1,0.6,1,0,1"],
            &["invalid --box", "--mixture", "sum below 1"],
        ),
        (
            &["--mixture", "-s", "3", "--box", "0,0.3,0,0.3,0,0.3"],
            &["invalid --box", "--mixture", "highs above 1"],
        ),
        (
            &[
                "--mixture",
                "-s",
                "3",
                "--constraint",
                "x1 >= 0.6",
                "--constraint",
                "x2 >= 0.6",
            ],
            &["invalid --constraint", "--mixture", "room"],
        ),
        (
            &[
                "--mixture",
                "-s",
                "3",
                "--constraint",
                "x1 + x2 + x3 >= 1.5",
            ],
            &["invalid --constraint", "--mixture"],
        ),
        (&["--mixture", "-s", "1"], &["invalid -s = 1", "at least 2"]),
        (&["--mixture"], &["invalid -s", "--mixture"]),
        (
            &["--mixture", "-s", "2", "--box", "0,1,0,1,0,1"],
            &["invalid -s = 2", "3"],
        ),
    ];
    for (args, says) in cases {
        let out = dir.path("x.csv");
        let o = bin()
            .arg("generate")
            .args(*args)
            .args(["-n", "10", "-q", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} was accepted");
        for s in *says {
            assert!(err.contains(s), "{args:?}: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists(), "{args:?} wrote a file");
    }
}

#[test]
fn eval_measures_constrained_sets_and_mixtures_in_their_region() {
    let dir = TempDir::new("eval-constraints");
    let cut = "x1 + 2*x2 <= 1.5";
    run(
        &dir,
        "c.csv",
        &[
            "-n",
            "80",
            "--goal",
            "integration",
            "--constraint",
            cut,
            "--box",
            "0,1,0,1",
        ],
    );
    let eval = |args: &[&str]| {
        let o = bin()
            .current_dir(&dir.0)
            .arg("eval")
            .args(args)
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stdout).to_string(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (ok, out, err) = eval(&["--json", "--constraint", cut, "--box", "0,1,0,1", "c.csv"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["fraction_inside"], 1.0);
    assert!(v["energy_distance"].as_f64().unwrap() > 0.0);
    // A cut that half the points break: the share inside says so.
    let (ok, out, _) = eval(&[
        "--json",
        "--constraint",
        "x1 <= 0.5",
        "--box",
        "0,1,0,1",
        "c.csv",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let inside = v["fraction_inside"].as_f64().unwrap();
    assert!(ok && inside > 0.3 && inside < 0.7, "{inside}");
    run(
        &dir,
        "m.csv",
        &["-n", "60", "-s", "3", "--mixture", "--goal", "integration"],
    );
    let (ok, out, err) = eval(&["--json", "--mixture", "m.csv"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["mixture"].as_bool(), v["s"].as_u64()),
        (Some(true), Some(2))
    );
    let (ok, _, err) = eval(&["--mixture", "c.csv"]);
    assert!(!ok && err.contains("summing to 1"), "{err}");
    let (ok, _, err) = eval(&["--constraint", cut, "--shape", "simplex", "c.csv"]);
    assert!(!ok && err.contains("one way"), "{err}");
}
