//! One and two points are valid sets: every solver and space gives finite points inside
//! the space and a report without NaN.

use std::process::Command;

fn generate(args: &[&str]) -> (String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .arg("generate")
        .args(args)
        .arg("-q")
        .output()
        .unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    );
    assert!(o.status.success(), "{args:?}: {err}");
    (out, err)
}

fn points(csv: &str) -> Vec<Vec<f64>> {
    csv.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn one_and_two_points_in_the_cube() {
    for n in ["1", "2"] {
        for extra in [
            &[][..],
            &["--integrator", "lbfgs"][..],
            &["--energy", "e-inf"][..],
            &["--energy", "md", "--integrator", "lbfgs"][..],
            &["--polish", "md"][..],
        ] {
            let mut args = vec!["-n", n, "-s", "3"];
            args.extend_from_slice(extra);
            let (out, err) = generate(&args);
            let p = points(&out);
            assert_eq!(p.len(), n.parse::<usize>().unwrap(), "{args:?}");
            assert!(
                p.iter().flatten().all(|v| (0.0..=1.0).contains(v)),
                "{args:?}: {p:?}"
            );
            assert!(
                !err.contains("NaN") && !out.contains("NaN"),
                "{args:?}: {err}"
            );
        }
    }
}

#[test]
fn one_and_two_points_in_a_region() {
    for n in ["1", "2"] {
        for extra in [&[][..], &["--integrator", "lbfgs", "--energy", "e-p-g"][..]] {
            let mut args = vec!["--shape", "ball:1", "-s", "2", "-n", n, "--steps", "200"];
            args.extend_from_slice(extra);
            let (out, err) = generate(&args);
            let p = points(&out);
            assert_eq!(p.len(), n.parse::<usize>().unwrap(), "{args:?}");
            assert!(
                p.iter()
                    .all(|x| x.iter().map(|v| v * v).sum::<f64>() <= 1.0),
                "{args:?}: {p:?}"
            );
            assert!(
                !err.contains("NaN") && !out.contains("NaN"),
                "{args:?}: {err}"
            );
        }
    }
}

#[test]
fn discrepancies_in_very_high_dimension_are_finite_and_agree_with_the_plain_form() {
    use stillpoint::energies::discrepancy::{
        closed_form_fits, discrepancy_root, discrepancy_root_by_logs, DiscrepancyKind,
    };
    let kinds = [
        DiscrepancyKind::StarL2,
        DiscrepancyKind::ModifiedL2,
        DiscrepancyKind::CenteredL2,
        DiscrepancyKind::WrapAroundL2,
    ];
    // Where both forms apply they agree to rounding.
    for s in [2, 10, 60, 300] {
        let p = stillpoint::sequences::random(40, s, 3).unwrap();
        for k in kinds {
            assert!(closed_form_fits(k, s), "{k:?} at s = {s}");
            let (plain, logs) = (discrepancy_root(&p, k), discrepancy_root_by_logs(&p, k));
            assert!(
                (plain - logs).abs() <= 1e-8 * plain,
                "{k:?}, s = {s}: {plain} vs {logs}"
            );
        }
    }
    // Beyond, the roots are finite and positive where representable, and the metrics
    // that print them agree with the function of the same name.
    let p = stillpoint::sequences::random(30, 2500, 4).unwrap();
    let m = stillpoint::quality::metrics::Metrics::compute(&p);
    for (k, v) in [
        (DiscrepancyKind::ModifiedL2, m.modified_l2),
        (DiscrepancyKind::CenteredL2, m.centered_l2),
        (DiscrepancyKind::WrapAroundL2, m.wrap_around_l2),
    ] {
        assert!(!closed_form_fits(k, 2500) || k == DiscrepancyKind::CenteredL2);
        assert!(v.is_finite() && v > 1.0, "{k:?}: {v}");
        assert_eq!(v.to_bits(), discrepancy_root(&p, k).to_bits());
    }
    // The star L2 at s = 2500 is about 3^(-1250): below f64, so 0.
    assert_eq!(m.star_l2, 0.0);
}

#[test]
fn a_long_run_says_so_before_it_starts() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let dir = std::env::temp_dir().join(format!("stillpoint-long-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .current_dir(&dir)
        .args([
            "generate",
            "-n",
            "100000000",
            "-s",
            "2",
            "--method",
            "paper",
            "-o",
            "big.csv",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The notes come before the run: that (n, s) is outside eq. 48's fitted range, then
    // the estimate of the time.
    let mut reader = BufReader::new(child.stderr.take().unwrap());
    let (mut outside, mut first) = (String::new(), String::new());
    reader.read_line(&mut outside).unwrap();
    reader.read_line(&mut first).unwrap();
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        outside.contains("outside the range eq. 48 was fitted on"),
        "{outside}"
    );
    assert!(
        first.starts_with("note: this run may take about"),
        "{first}"
    );
    assert!(first.contains("--steps") && first.contains("-n"), "{first}");
    assert!(!dir.join("big.csv").exists());
    // A short run says nothing of the kind.
    let (_, err) = generate(&["-n", "50", "-s", "2", "--steps", "50"]);
    assert!(!err.contains("may take"), "{err}");
}

#[test]
fn eval_says_what_a_missing_value_stands_for_and_never_prints_nan() {
    let dir = std::env::temp_dir().join(format!("stillpoint-eval-notes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files = [
        ("one.csv", "0.5,0.5\n", "a single point has no pair"),
        (
            "dup.csv",
            "0.5,0.5\n0.5,0.5\n0.1,0.2\n",
            "two points coincide",
        ),
        (
            "edge.csv",
            "0,0\n1,1\n0.5,0.5\n",
            "0 and 1 are one coordinate",
        ),
        (
            "dup3.csv",
            "0.2,0.2,0.2\n0.2,0.2,0.2\n",
            "two points coincide",
        ),
    ];
    for (name, text, note) in files {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        for json in [false, true] {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_stillpoint"));
            cmd.arg("eval").arg(&path);
            if json {
                cmd.arg("--json");
            }
            let o = cmd.output().unwrap();
            let out = String::from_utf8_lossy(&o.stdout);
            assert!(o.status.success(), "{name}");
            assert!(
                !out.contains("NaN") && !out.contains("nan"),
                "{name}: {out}"
            );
            assert!(out.contains(note), "{name} (json {json}): {out}");
        }
    }
}
