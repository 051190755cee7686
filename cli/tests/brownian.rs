//! Brownian paths on the command line: `generate --var 'W=brownian(T,m,…)'` writes m
//! columns W_1 … W_m in every format, `eval --var` reads them back to the report's
//! figures, a 1 000-step path goes through `generate` and `integrate --expr` reaches
//! 1 000 dimensions, and bad parameters are refused on one line naming the option, the
//! text as typed and what is accepted.

mod common;

use common::{bin, succeeded, TempDir};

fn json(cmd: &mut std::process::Command, what: &dyn std::fmt::Debug) -> serde_json::Value {
    let (out, _) = succeeded(cmd, what);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
fn a_path_writes_m_named_columns_that_read_back_in_every_format() {
    let d = TempDir::new("brownian-formats");
    let vars = ["S0=lognormal(4.6,0.1)", "W=brownian(2,6,bridge)"];
    for ext in ["csv", "tsv", "json", "npy"] {
        let out = d.path(&format!("paths.{ext}"));
        let mut cmd = bin();
        cmd.args(["generate", "-n", "32", "--json", "-o"]).arg(&out);
        for v in vars {
            cmd.args(["--var", v]);
        }
        let report = json(&mut cmd, &ext);
        // The report shows the path as typed, with its construction.
        let shown = report.to_string();
        assert!(shown.contains("W=brownian(2,6,bridge)"), "{shown}");
        let mut eval = bin();
        eval.args(["eval", "--json"]);
        for v in vars {
            eval.args(["--var", v]);
        }
        let back = json(eval.arg(&out), &ext);
        assert_eq!(back["figures"], report["figures"], "{ext}");
        if ext == "csv" {
            let text = std::fs::read_to_string(&out).unwrap();
            let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
            assert_eq!(header, "S0,W_1,W_2,W_3,W_4,W_5,W_6");
            assert_eq!(text.lines().filter(|l| !l.starts_with('#')).count(), 33);
        }
    }
}

#[test]
fn a_thousand_step_path_is_generated_and_integrated() {
    let d = TempDir::new("brownian-1000");
    let out = d.path("w.csv");
    succeeded(
        bin()
            .args([
                "generate",
                "-n",
                "8",
                "-q",
                "--var",
                "W=brownian(1,1000,pca)",
                "-o",
            ])
            .arg(&out),
        &"generate",
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let header: Vec<&str> = text
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .split(',')
        .collect();
    assert_eq!(header.len(), 1000);
    assert_eq!((header[0], header[999]), ("W_1", "W_1000"));
    // The cubature's lattice reaches 1 000 dimensions: ∫ x1000 = 1/2.
    let v = json(
        bin().args([
            "integrate",
            "--expr",
            "x1000 + x1",
            "-s",
            "1000",
            "--rel-tol",
            "1e-3",
            "--json",
        ]),
        &"integrate",
    );
    assert_eq!(v["met"], true, "{v}");
    assert!((v["estimate"].as_f64().unwrap() - 1.0).abs() < 2e-3, "{v}");
    let o = bin()
        .args(["integrate", "--expr", "x1", "-s", "1001"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("1000"), "{err}");
}

#[test]
fn bad_paths_are_refused_on_one_line_naming_the_option_and_the_text() {
    for (var, says) in [
        ("W=brownian(0,16)", "T = 0"),
        ("W=brownian(1,0,pca)", "m = 0"),
        ("W=brownian(1,9999)", "m = 9999"),
        (
            "W=brownian(1,16,sobol)",
            "pca (the default), bridge or standard",
        ),
    ] {
        let o = bin()
            .args(["generate", "-n", "8", "--var", var])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{var}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(
            err.contains("--var") && err.contains(var) && err.contains(says),
            "{var}: {err}"
        );
    }
    // A correlation that counts the path's columns names the path.
    let o = bin()
        .args([
            "generate",
            "-n",
            "8",
            "--var",
            "x=normal(0,1)",
            "--var",
            "W=brownian(1,1)",
            "--correlation",
            "1,0.5;0.5,1",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--correlation") && err.contains("W=brownian(1,1,pca)"),
        "{err}"
    );
}
