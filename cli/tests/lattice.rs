//! The default from 500 points on, through the command line: the README's promises
//! (every column stratified, every column's mean ½) at odd and prime n, s = 1 as the
//! midpoints at any n, the construction recorded in the file, and `--target lattice`.

mod common;

use common::{bin, succeeded};
use std::path::PathBuf;

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stillpoint-lattice-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join("x.csv")
}

fn generate(name: &str, args: &[&str]) -> (stillpoint::PointSet, String) {
    let out = temp(name);
    let mut cmd = bin();
    cmd.arg("generate").args(args).arg("-o").arg(&out).arg("-q");
    succeeded(&mut cmd, &args);
    let text = std::fs::read_to_string(&out).unwrap();
    let points = stillpoint::io::read_points(&out).unwrap();
    std::fs::remove_dir_all(out.parent().unwrap()).ok();
    (points, text)
}

#[test]
fn columns_are_the_midpoints_with_mean_a_half_at_odd_and_prime_n() {
    for (n, s) in [(501usize, 4usize), (1009, 7), (7919, 3), (2000, 12)] {
        let (p, header) = generate(
            &format!("{n}"),
            &["-n", &n.to_string(), "-s", &s.to_string()],
        );
        assert!(
            header.contains("\"stage\":\"lattice_rule\""),
            "{n}: {header:.400}"
        );
        for j in 0..s {
            let mut col: Vec<f64> = p.rows().map(|r| r[j]).collect();
            col.sort_by(f64::total_cmp);
            for (i, v) in col.iter().enumerate() {
                // Written as text and read back: the midpoint to the last digit.
                let want = (2 * i + 1) as f64 / (2 * n) as f64;
                assert!((v - want).abs() < 1e-15, "n = {n}, j = {j}, i = {i}: {v}");
            }
            let mean = col.iter().sum::<f64>() / n as f64;
            assert!((mean - 0.5).abs() < 1e-12, "n = {n}, j = {j}: mean {mean}");
        }
    }
}

#[test]
fn one_dimension_is_the_midpoints_at_any_n() {
    for n in [3usize, 499, 20_001] {
        let (p, _) = generate(&format!("s1-{n}"), &["-n", &n.to_string(), "-s", "1"]);
        for (k, v) in p.as_slice().iter().enumerate() {
            assert!(
                (v - (k as f64 + 0.5) / n as f64).abs() < 1e-15,
                "n = {n}, k = {k}"
            );
        }
    }
}

#[test]
fn the_lattice_is_asked_for_by_name_and_refused_where_it_cannot_be() {
    // Below 500 points by name: the same construction.
    let (_, header) = generate("named", &["-n", "64", "-s", "3", "--target", "lattice"]);
    assert!(header.contains("lattice_rule"));
    // A grown set is not one set made for its size.
    let o = bin()
        .args([
            "generate", "-n", "64", "-s", "3", "--target", "lattice", "--nested", "32,64",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--target"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
