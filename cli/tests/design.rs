//! `generate --var` / `--space` and `eval --var` on the command line: the labelled CSV,
//! its figures read back by eval, the JSON space file, and the refusals.

mod common;
use common::*;
use std::fs;

const VARS: [&str; 4] = [
    "x=uniform(0,1)",
    "y=uniform(-2,2)",
    "k=int(1,5)",
    "c={a,b,c}",
];

fn var_args() -> Vec<String> {
    VARS.iter()
        .flat_map(|v| ["--var".to_string(), v.to_string()])
        .collect()
}

#[test]
fn a_design_is_written_with_names_and_labels_and_eval_reads_the_same_figures() {
    let dir = TempDir::new("design-csv");
    let out = dir.0.join("d.csv");
    let o = bin()
        .args(["generate", "-n", "30", "--json", "-o"])
        .arg(&out)
        .args(var_args())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let text = fs::read_to_string(&out).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(rows.next(), Some("x,y,k,c"));
    let rows: Vec<Vec<&str>> = rows.map(|r| r.split(',').collect()).collect();
    assert_eq!(rows.len(), 30);
    for r in &rows {
        let y: f64 = r[1].parse().unwrap();
        let k: i64 = r[2].parse().unwrap();
        assert!(
            (-2.0..=2.0).contains(&y) && (1..=5).contains(&k) && ["a", "b", "c"].contains(&r[3])
        );
    }
    for label in ["a", "b", "c"] {
        assert_eq!(rows.iter().filter(|r| r[3] == label).count(), 10);
    }
    let e = bin()
        .args(["eval", "--json"])
        .args(var_args())
        .arg(&out)
        .output()
        .unwrap();
    assert!(e.status.success(), "{}", String::from_utf8_lossy(&e.stderr));
    let eval: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
    assert_eq!(eval["figures"], report["figures"]);
    assert_eq!(report["figures"]["slices"][0]["stratified"], 6);
}

#[test]
fn eval_takes_exact_for_a_design_and_below_the_estimate_s_size_it_changes_nothing() {
    let dir = TempDir::new("design-exact");
    let out = dir.0.join("d.csv");
    let o = bin()
        .args(["generate", "-n", "40", "-q", "-o"])
        .arg(&out)
        .args(var_args())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let figures = |exact: bool| -> serde_json::Value {
        let mut c = bin();
        c.args(["eval", "--json"]).args(var_args()).arg(&out);
        if exact {
            c.arg("--exact");
        }
        let e = c.output().unwrap();
        assert!(e.status.success(), "{}", String::from_utf8_lossy(&e.stderr));
        serde_json::from_slice::<serde_json::Value>(&e.stdout).unwrap()["figures"].clone()
    };
    let (exact, auto) = (figures(true), figures(false));
    assert_eq!(exact, auto);
    assert!(exact.get("estimate").is_none(), "{exact}");
}

#[test]
fn a_space_file_gives_the_bytes_of_the_same_vars() {
    let dir = TempDir::new("design-file");
    let space = dir.0.join("space.json");
    fs::write(
        &space,
        serde_json::to_string(&serde_json::json!({"variables": VARS})).unwrap(),
    )
    .unwrap();
    let a = bin()
        .args(["generate", "-n", "12", "-q"])
        .args(var_args())
        .output()
        .unwrap();
    let b = bin()
        .args(["generate", "-n", "12", "-q", "--space"])
        .arg(&space)
        .output()
        .unwrap();
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
    fs::write(&space, "[1, 2]").unwrap();
    let e = bin()
        .args(["generate", "-n", "12", "--space"])
        .arg(&space)
        .output()
        .unwrap();
    assert!(!e.status.success());
    assert!(String::from_utf8_lossy(&e.stderr).contains("\"NAME=TYPE\" strings"));
}

#[test]
fn refusals_come_before_any_work_and_name_the_option() {
    let dir = TempDir::new("design-refusals");
    let npy = dir.0.join("d.npy");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "-n".into(),
                "30".into(),
                "-o".into(),
                npy.display().to_string(),
            ],
            ".csv or .tsv",
        ),
        (
            vec!["-n".into(), "30".into(), "--bounds".into(), "0,1".into()],
            "--bounds",
        ),
        (vec!["-n".into(), "2".into()], "at least 3 points"),
        (
            vec!["-n".into(), "30".into(), "-s".into(), "3".into()],
            "number of variables",
        ),
        (
            vec![
                "-n".into(),
                "30".into(),
                "--randomize".into(),
                "--method".into(),
                "sobol".into(),
            ],
            "--randomize",
        ),
    ];
    for (extra, expected) in cases {
        let o = bin()
            .arg("generate")
            .args(&extra)
            .args(var_args())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(expected),
            "{extra:?}: {err}"
        );
    }
    assert!(!npy.exists());
    let o = bin()
        .args([
            "generate",
            "-n",
            "5",
            "--var",
            "c={a,b}",
            "--var",
            "c=int(1,2)",
        ])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("already a variable"));
}

#[test]
fn eval_refuses_a_cell_outside_its_variable_naming_the_line() {
    let dir = TempDir::new("design-eval");
    let f = dir.0.join("d.csv");
    fs::write(&f, "x,y,k,c\n0.5,0,3,a\n0.2,1,9,b\n").unwrap();
    let o = bin().arg("eval").args(var_args()).arg(&f).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("line 3, k") && err.contains("[1, 5]"),
        "{err}"
    );
    fs::write(&f, "x,y,k,c\n0.5,0,3,d\n").unwrap();
    let o = bin().arg("eval").args(var_args()).arg(&f).output().unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("one of a, b, c"));
}

/// The guide's design-space commands (docs/design.md), run as written: the plan has the
/// promised header, level counts and slices, and eval reads it back.
#[test]
fn guide_design_space_example_runs() {
    let lines = doc_lines("docs/design.md", |l| {
        l.starts_with("stillpoint ") && l.contains("--var") && l.contains("plan.csv")
    });
    assert_eq!(lines.len(), 2, "{lines:?}");
    let words = |line: &str| shell_words(line.trim_start_matches("stillpoint "), '\'');
    let dir = TempDir::new("guide-design");
    for line in &lines {
        let o = bin()
            .current_dir(&dir.0)
            .args(words(line))
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{line}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let text = fs::read_to_string(dir.0.join("plan.csv")).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(rows.next(), Some("x,T,layers,catalyst"));
    let rows: Vec<&str> = rows.collect();
    for c in ["Pt", "Pd", "Ni"] {
        assert_eq!(
            rows.iter()
                .filter(|r| r.ends_with(&format!(",{c}")))
                .count(),
            20
        );
    }
}
