//! Defect families found by trying the newer features as an adversarial user would, each
//! tried with its repro and variants: a shape mismatch is refused before any energy is
//! built, a grown set is never randomised, a header reproduces its file, counts never wrap,
//! a checkpoint never replaces a result, and no refusal panics or touches a file.

mod common;

use common::{bin, succeeded, TempDir};
use std::collections::BTreeMap;
use std::path::Path;

fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap_or_default(),
            )
        })
        .collect()
}

/// Runs `generate ARGS` in `dir`, expecting a refusal whose one error line contains
/// `needle`, no panic and every file as it was. Returns 1 (a case tried).
fn refused(dir: &Path, args: &[&str], needle: &str) -> usize {
    let before = snapshot(dir);
    let o = bin()
        .current_dir(dir)
        .arg("generate")
        .args(args)
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
    1
}

fn write(dir: &Path, name: &str, args: &[&str]) {
    succeeded(
        bin().current_dir(dir).args(args).args(["-o", name, "-q"]),
        &args,
    );
}

#[test]
fn every_refusal_is_clean() {
    let d = TempDir::new("reliability");
    let dir = d.0.as_path();
    write(
        dir,
        "ball2.csv",
        &[
            "generate", "--shape", "ball:2", "-s", "2", "-n", "10", "--steps", "50",
        ],
    );
    write(dir, "cube2.csv", &["generate", "-n", "100", "-s", "2"]);
    write(dir, "cube3.npy", &["generate", "-n", "20", "-s", "3"]);
    let mut tried = 0;
    // A grown set of another dimension than its space (it used to panic).
    for (file, space) in [
        ("ball2.csv", vec!["--shape", "ball:2", "-s", "3"]),
        ("ball2.csv", vec!["--shape", "ball:2@0,0,0"]),
        ("cube3.npy", vec!["--shape", "ball:2@0,0"]),
        (
            "cube2.csv",
            vec![
                "--region",
                "x1^2 + x2^2 + x3^2 - 1",
                "--box",
                "-1,1,-1,1,-1,1",
            ],
        ),
    ] {
        let mut args = vec!["--extend", file, "-n", "5"];
        args.extend(space);
        tried += refused(dir, &args, "dimension");
    }
    tried += refused(
        dir,
        &["--extend", "cube2.csv", "-n", "5", "-s", "3"],
        "invalid -s = 3",
    );
    tried += refused(
        dir,
        &["--init", "cube3.npy", "-s", "2", "--steps", "5"],
        "invalid -s = 2",
    );
    // Randomised grown sets would break the promises of the report.
    for extra in [["--randomize", "cells"], ["--randomize", "shift"]] {
        let mut a = vec!["--extend", "cube2.csv", "-n", "50"];
        a.extend(extra);
        tried += refused(dir, &a, "no randomisation of a grown set");
        let mut b = vec!["--nested", "16,32,64", "-s", "2"];
        b.extend(extra);
        tried += refused(dir, &b, "no randomisation of a grown set");
    }
    // Counts that would wrap.
    for m in [
        "18446744073709551615",
        "18446744073709551616",
        "99999999999999999999999",
    ] {
        tried += refused(dir, &["--extend", "cube2.csv", "-n", m], "invalid -n = ");
    }
    for (n, s) in [
        ("-5", "2"),
        ("0", "2"),
        ("2.5", "2"),
        ("ten", "2"),
        ("5", "0"),
        ("5", "-1"),
    ] {
        tried += refused(dir, &["-n", n, "-s", s], "invalid -");
    }
    // Misleading messages of the past.
    tried += refused(
        dir,
        &["--nested", "4,8", "--shape", "ball:1", "-s", "2"],
        "invalid --nested",
    );
    tried += refused(
        dir,
        &["--nested", "4,8", "--shape", "ball:1", "-s", "2", "-n", "8"],
        "not in a region",
    );
    // A checkpoint path that holds a result is not overwritten.
    tried += refused(
        dir,
        &[
            "-n",
            "30",
            "-s",
            "2",
            "--steps",
            "20",
            "--checkpoint",
            "cube2.csv",
        ],
        "is not a checkpoint",
    );
    assert!(tried >= 20, "{tried}");
}

#[test]
fn a_randomised_paper_run_records_it_and_rows_describe_the_written_set() {
    let d = TempDir::new("reliability-header");
    let dir = d.0.as_path();
    for (name, extra) in [
        ("paper.csv", vec!["--method", "paper", "--steps", "40"]),
        ("goal.csv", vec![]),
    ] {
        let mut args = vec![
            "generate",
            "-n",
            "64",
            "-s",
            "3",
            "--randomize",
            "cells",
            "--seed",
            "3",
        ];
        args.extend(extra);
        let o = bin()
            .current_dir(dir)
            .args(&args)
            .args(["-o", name, "--json", "-q"])
            .output()
            .unwrap();
        assert!(o.status.success());
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(
            text.contains("\"randomize\":\"cells\""),
            "{name}: header lacks randomize"
        );
        // The reported result is the written file's quality.
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let e = bin()
            .current_dir(dir)
            .args(["eval", name, "--json"])
            .output()
            .unwrap();
        let eval: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
        let reported = report["metrics_result"]["modified_l2"].as_f64().unwrap();
        let measured = eval["modified_l2"].as_f64().unwrap();
        assert!(
            (reported - measured).abs() <= 1e-12 * measured,
            "{name}: {reported} vs {measured}"
        );
        assert!(!String::from_utf8_lossy(&o.stdout).contains("NaN"));
    }
}

#[test]
fn an_extension_counts_collisions_as_values_summed_over_the_coordinates() {
    // Four old points whose first coordinates all fall in the first of the union's eight
    // cells (three collisions) and whose second coordinates are in distinct cells.
    let d = TempDir::new("collisions");
    let old = d.path("old.csv");
    std::fs::write(&old, "0.01,0.05\n0.02,0.30\n0.03,0.55\n0.04,0.80\n").unwrap();
    let o = bin()
        .args(["generate", "-n", "8", "-s", "2", "-q", "--extend"])
        .arg(&old)
        .arg("-o")
        .arg(d.path("u.csv"))
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        report.contains("summed over the coordinates, 3 old values fall in a cell"),
        "{report}"
    );
}
