//! The default lattice's corners through the command line: its criterion never negative
//! (the report's row and the header), columns that share a generator named before the
//! run, in the report and in the header, and the run's stages on standard error.

mod common;

use common::{bin, succeeded, TempDir};

/// The run's standard error and report (stdout) and the written file's text.
fn generate(dir: &TempDir, args: &[&str]) -> (String, String, String) {
    let out = dir.0.join("x.csv");
    let mut cmd = bin();
    cmd.arg("generate").args(args).arg("-o").arg(&out);
    let (stdout, stderr) = succeeded(&mut cmd, &args);
    (stderr, stdout, std::fs::read_to_string(&out).unwrap())
}

/// The header's parameters line, as JSON.
fn parameters(text: &str) -> serde_json::Value {
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("# parameters: "))
        .expect("a parameters line");
    serde_json::from_str(line).unwrap()
}

#[test]
fn the_criterion_is_positive_in_the_report_and_the_header() {
    let dir = TempDir::new("criterion");
    // 20 001 × 3 reported −6.45e-18; the others are variants at odd, prime and
    // power-of-two n.
    for (n, s) in [("20001", "3"), ("4099", "5"), ("8192", "4"), ("30011", "2")] {
        let (_, report, text) = generate(&dir, &["-n", n, "-s", s]);
        let stage = &parameters(&text)["stages"][0];
        for key in ["criterion", "drawn"] {
            let v = stage[key].as_f64().unwrap();
            assert!(v > 0.0, "n = {n}, {key} = {v}");
        }
        let row = report
            .lines()
            .find(|l| l.trim_start().starts_with("shift criterion"))
            .unwrap();
        let values: Vec<f64> = row
            .split_whitespace()
            .filter_map(|w| w.parse::<f64>().ok())
            .collect();
        assert_eq!(values.len(), 2, "{row}");
        assert!(values.iter().all(|v| *v > 0.0), "n = {n}: {row}");
    }
}

#[test]
fn columns_that_share_a_generator_are_named_before_the_run_in_the_report_and_header() {
    let dir = TempDir::new("shared");
    // φ(510)/2 = 64, φ(600)/2 = 80, φ(509)/2 = 254.
    for (n, s, shared) in [(510usize, 100usize, 36usize), (600, 90, 10), (509, 300, 46)] {
        let (stderr, report, text) = generate(&dir, &["-n", &n.to_string(), "-s", &s.to_string()]);
        assert!(
            stderr.contains(&format!("{shared} columns reuse one")),
            "n = {n}: {stderr}"
        );
        assert!(
            report.contains(&format!("note: {shared} of the {s} columns reuse")),
            "n = {n}: {report:.2000}"
        );
        let stage = &parameters(&text)["stages"][0];
        let listed = stage["shared"].as_array().unwrap();
        assert_eq!(listed.len(), shared, "n = {n}");
        let z = stage["generator"].as_array().unwrap();
        for pair in listed {
            let (j, i, zj) = (
                pair[0].as_u64().unwrap() as usize,
                pair[1].as_u64().unwrap() as usize,
                pair[2].as_u64().unwrap(),
            );
            let key = |v: u64| v.min(n as u64 - v);
            assert!(i < j, "n = {n}: {pair}");
            assert_eq!(z[j - 1].as_u64().unwrap(), zj);
            assert_eq!(key(z[i - 1].as_u64().unwrap()), key(zj), "n = {n}: {pair}");
        }
        assert!(stage["note"].as_str().unwrap().contains("φ(n)/2"));
    }
    // Within φ(n)/2 columns: no note anywhere.
    let (stderr, report, text) = generate(&dir, &["-n", "510", "-s", "64"]);
    assert!(!stderr.contains("reuse"), "{stderr}");
    assert!(!report.contains("reuse"));
    assert!(parameters(&text)["stages"][0].get("shared").is_none());
}

#[test]
fn the_lattice_shows_its_stages_with_plain_progress() {
    let dir = TempDir::new("progress");
    for (n, s) in [("600", "5"), ("2000", "40"), ("1024", "3")] {
        let (stderr, _, _) = generate(&dir, &["-n", n, "-s", s, "--progress", "plain"]);
        let stages: Vec<&str> = stderr
            .lines()
            .filter_map(|l| l.strip_prefix("stillpoint: "))
            .map(|l| l.split(',').next().unwrap())
            .collect();
        assert_eq!(
            stages,
            ["generating vector", "shift selection", "metrics"],
            "n = {n}, s = {s}: {stderr}"
        );
    }
    // -q hides them.
    let (stderr, _, _) = generate(&dir, &["-n", "600", "-s", "5", "-q"]);
    assert!(!stderr.contains("shift selection"), "{stderr}");
}
