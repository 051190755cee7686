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
