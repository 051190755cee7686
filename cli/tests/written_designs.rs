//! A design's report describes the file as written: its figures are those `eval` reads
//! back from it in every format, a space that cannot hold n distinct values is refused,
//! its correlation is recorded, its space file is an input never overwritten; and the
//! tables print no NaN, no infinity and no unbounded line.

mod common;
use common::*;
use proptest::prelude::*;
use std::fs;
use std::process::Output;

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A refusal: status 1 and one line on standard error naming `what`.
fn refused(o: &Output, what: &str) -> String {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "not refused: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(err.contains(what), "{what:?} not named in {err}");
    err
}

fn json_of(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", text(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Every figure `eval --json` reads from `file` with the variables `vars`.
fn eval_figures(file: &std::path::Path, vars: &[String], extra: &[&str]) -> serde_json::Value {
    let mut cmd = bin();
    cmd.args(["eval", "--json"]);
    for v in vars {
        cmd.args(["--var", v]);
    }
    let o = cmd.args(extra).arg(file).output().unwrap();
    json_of(&o)["figures"].clone()
}

#[test]
fn a_continuous_range_without_n_distinct_floats_is_refused() {
    let d = TempDir::new("collapsed");
    for var in [
        "x=uniform(1000000000000000,1000000000000000.1)",
        "x=uniform(0,5e-324)",
        "x=normal(1e300,1e-300)",
    ] {
        let out = d.path("out.csv");
        let o = bin()
            .args(["generate", "-n", "20", "--var", var, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let err = refused(&o, "--var x");
        assert!(err.contains("distinct values"), "{err}");
        assert!(!out.exists(), "a refused run wrote {}", out.display());
    }
    // A range that holds the n values is taken, and its figures are those of the file.
    let out = d.path("ok.csv");
    let o = bin()
        .args(["generate", "-n", "20", "--json", "--var"])
        .arg("x=uniform(1000000000000000,1000000000000100)")
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let report = json_of(&o);
    let vars = ["x=uniform(1000000000000000,1000000000000100)".to_string()];
    assert_eq!(eval_figures(&out, &vars, &[]), report["figures"]);
}

#[test]
fn extreme_parameters_are_echoed_in_scientific_notation() {
    for var in [
        "x=uniform(1e300,1e300)",
        "x=normal(1e300,-1)",
        "x=uniform(1000000000000000,1000000000000000.1)",
    ] {
        let err = refused(&run(&["generate", "-n", "20", "--var", var]), "--var");
        let longest = err
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest <= 17, "a number of {longest} digits: {err}");
    }
}

#[test]
fn a_design_without_a_continuous_column_prints_no_nan_and_bounded_lines() {
    for (n, vars) in [
        ("12", vec!["k=int(1,3)", "c={a,b}"]),
        ("7", vec!["k=int(0,1000000)"]),
        ("9", vec!["q=ordered{lo,mid,hi}", "c={a,b,c}", "e={u,v}"]),
    ] {
        let mut args = vec!["generate", "-n", n];
        for v in &vars {
            args.extend(["--var", v]);
        }
        let o = run(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let all = text(&o.stdout) + &text(&o.stderr);
        assert!(!all.contains("NaN") && !all.contains("inf"), "{all}");
        let longest = text(&o.stderr).lines().map(|l| l.chars().count()).max();
        assert!(
            longest.unwrap_or(0) < 300,
            "a line of {longest:?} characters"
        );
        // The design on standard output, with its header of figures.
        let longest = text(&o.stdout).lines().map(|l| l.chars().count()).max();
        assert!(
            longest.unwrap_or(0) < 4000,
            "a line of {longest:?} characters"
        );
    }
}

#[test]
fn a_space_file_refuses_a_repeated_or_unknown_key_by_name() {
    let d = TempDir::new("space-keys");
    let cases = [
        (
            r#"{"variables": ["x=uniform(0,1)"], "variables": ["y=normal(0,1)"]}"#,
            "duplicate key \"variables\"",
        ),
        (
            r#"{"variables": ["x=uniform(0,1)"], "correlaton": "1"}"#,
            "unknown key \"correlaton\"",
        ),
        (r#"{"vars": ["x=uniform(0,1)"]}"#, "unknown key \"vars\""),
    ];
    for (body, what) in cases {
        let space = d.path("s.json");
        fs::write(&space, body).unwrap();
        let o = bin()
            .args(["generate", "-n", "6", "--space"])
            .arg(&space)
            .output()
            .unwrap();
        refused(&o, what);
        fs::write(d.path("p.csv"), "x\n0.5\n").unwrap();
        let o = bin()
            .args(["eval", "--space"])
            .arg(&space)
            .arg(d.path("p.csv"))
            .output()
            .unwrap();
        refused(&o, what);
    }
}

#[test]
fn the_correlation_is_recorded_and_reproduces_the_header_figures() {
    let d = TempDir::new("correlation");
    for (corr, vars) in [
        ("1,0.7;0.7,1", vec!["x=normal(0,1)", "y=normal(0,1)"]),
        (
            "1,-0.3,0.2;-0.3,1,0.1;0.2,0.1,1",
            vec![
                "a=uniform(0,1)",
                "b=lognormal(0,0.5)",
                "k=int(1,3)",
                "c=beta(2,3)",
            ],
        ),
        (
            "1,0.9;0.9,1",
            vec!["x=uniform(-1,1)", "g={p,q}", "y=triangular(0,1,3)"],
        ),
    ] {
        let out = d.path("out.csv");
        let mut cmd = bin();
        cmd.args([
            "generate",
            "-n",
            "24",
            "--json",
            "--correlation",
            corr,
            "-o",
        ])
        .arg(&out);
        for v in &vars {
            cmd.args(["--var", v]);
        }
        let report = json_of(&cmd.output().unwrap());
        assert!(report["correlation"].as_str().is_some(), "{report}");
        let file = fs::read_to_string(&out).unwrap();
        let header = |key: &str| -> serde_json::Value {
            let line = file
                .lines()
                .find_map(|l| l.strip_prefix(&format!("# {key}: ")))
                .unwrap_or_else(|| panic!("no {key} in the header"));
            serde_json::from_str(line).unwrap()
        };
        let recorded = header("correlation");
        let space: Vec<String> = serde_json::from_value(header("space")).unwrap();
        let figures = eval_figures(&out, &space, &["--correlation", recorded.as_str().unwrap()]);
        assert_eq!(figures, header("figures"));
        assert_eq!(figures, report["figures"]);
    }
}

#[test]
fn eval_reads_the_npy_and_json_designs_generate_writes() {
    let d = TempDir::new("numeric-designs");
    let vars: Vec<String> = ["x=uniform(0,1)", "y=normal(2,3)", "k=int(1,5)"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for name in ["d.npy", "d.json", "d.tsv"] {
        let out = d.path(name);
        let mut cmd = bin();
        cmd.args(["generate", "-n", "15", "--json", "-o"]).arg(&out);
        for v in &vars {
            cmd.args(["--var", v]);
        }
        let report = json_of(&cmd.output().unwrap());
        assert_eq!(eval_figures(&out, &vars, &[]), report["figures"], "{name}");
    }
    // A file of numbers has no labels: a space with levels says where they go.
    let o = bin()
        .args(["eval", "--var", "x=uniform(0,1)", "--var", "c={a,b}"])
        .arg(d.path("d.npy"))
        .output()
        .unwrap();
    refused(&o, "d.npy");
}

#[test]
fn a_ball_too_small_for_finite_energies_is_refused() {
    for args in [
        &[
            "generate",
            "--goal",
            "integration",
            "--shape",
            "ball:1e-300",
            "-s",
            "2",
            "-n",
            "10",
        ][..],
        &["generate", "--shape", "ball:1e-120@0,0", "-n", "10"][..],
        &["generate", "--shape", "ellipsoid:1,1e-200", "-n", "10"][..],
    ] {
        let err = refused(&run(args), "--shape");
        assert!(err.contains("radius") || err.contains("semi-axis"), "{err}");
    }
    let d = TempDir::new("tiny-ball");
    fs::write(d.path("p.csv"), "1e-301,0\n0,1e-301\n").unwrap();
    let o = bin()
        .args(["eval", "--shape", "ball:1e-300"])
        .arg(d.path("p.csv"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
}

#[test]
fn the_space_file_is_an_input_no_output_replaces() {
    let d = TempDir::new("space-input");
    let space = d.path("s.json");
    let body = r#"["x=uniform(0,1)", "k=int(1,3)"]"#;
    fs::write(&space, body).unwrap();
    let link = d.path("link.csv");
    std::os::unix::fs::symlink(&space, &link).unwrap();
    for flag in ["-o", "--trajectory", "--plot", "--checkpoint"] {
        let target = if flag == "--plot" {
            d.path("s.png")
        } else {
            space.clone()
        };
        if flag == "--plot" {
            // A picture path that is the space file through a link.
            std::os::unix::fs::symlink(&space, &target).unwrap();
        }
        let o = bin()
            .args(["generate", "-n", "6", "--space"])
            .arg(&space)
            .arg(flag)
            .arg(&target)
            .output()
            .unwrap();
        refused(&o, "--space");
        assert_eq!(fs::read_to_string(&space).unwrap(), body);
    }
    let o = bin()
        .args(["generate", "-n", "6", "--space"])
        .arg(&space)
        .arg("-o")
        .arg(&link)
        .output()
        .unwrap();
    refused(&o, "--space");
    assert_eq!(fs::read_to_string(&space).unwrap(), body);
}

#[test]
fn plot_never_draws_over_its_input() {
    let d = TempDir::new("plot-input");
    let csv = d.path("p.csv");
    succeeded(
        bin()
            .args(["generate", "-q", "-n", "10", "-s", "2", "-o"])
            .arg(&csv),
        &"generate",
    );
    let body = fs::read(&csv).unwrap();
    // A point file named like a picture, a link to it, and a trajectory.
    let named = d.path("p.png");
    fs::write(&named, &body).unwrap();
    let link = d.path("link.svg");
    std::os::unix::fs::symlink(&csv, &link).unwrap();
    let traj = d.path("t.svg");
    fs::write(&traj, r#"{"energy": "e", "records": []}"#).unwrap();
    for (args, input) in [
        (vec![named.clone(), "-o".into(), named.clone()], &named),
        (vec![csv.clone(), "-o".into(), link.clone()], &csv),
        (
            vec![
                "--trajectory".into(),
                traj.clone(),
                "-o".into(),
                traj.clone(),
            ],
            &traj,
        ),
    ] {
        let before = fs::read(input).unwrap();
        let o = bin().arg("plot").args(&args).output().unwrap();
        refused(&o, "which the run reads");
        assert_eq!(fs::read(input).unwrap(), before);
    }
}

#[test]
fn help_and_version_to_a_full_output_fail_with_one_line() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    for args in [
        &["--help"][..],
        &["--version"][..],
        &["generate", "--help"][..],
    ] {
        let full = fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = bin().args(args).stdout(full).output().unwrap();
        refused(&o, "cannot write to standard output");
    }
}

#[test]
fn a_picture_that_cannot_be_written_keeps_the_points() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let d = TempDir::new("plot-full");
    // A picture's path that leads to a device where every write fails, as on a full disk.
    let picture = d.path("full.png");
    std::os::unix::fs::symlink("/dev/full", &picture).unwrap();
    for (out, extra) in [
        ("p.csv", vec![]),
        ("p.npy", vec!["--goal", "space-filling", "--steps", "20"]),
        ("p.json", vec!["--shape", "ball:1"]),
    ] {
        let o = bin()
            .args(["generate", "-q", "-n", "30", "-s", "2", "-o"])
            .arg(d.path(out))
            .arg("--plot")
            .arg(&picture)
            .args(&extra)
            .output()
            .unwrap();
        refused(&o, "full.png");
        let points = stillpoint::io::read_points(&d.path(out)).unwrap();
        assert_eq!(points.n(), 30, "{out}");
    }
}

#[test]
fn a_single_point_shows_no_infinite_distance_or_zero_energy() {
    for args in [
        &["generate", "-n", "1", "-s", "2"][..],
        &[
            "generate", "-n", "1", "-s", "3", "--method", "paper", "--steps", "5",
        ][..],
        &["generate", "-n", "1", "--shape", "ball:1", "-s", "2"][..],
    ] {
        let o = run(args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let table = text(&o.stderr);
        assert!(!table.contains("inf") && !table.contains("NaN"), "{table}");
        assert!(table.contains("none"), "{table}");
    }
}

#[test]
fn integration_in_a_region_reports_no_energy_reduction() {
    for shape in ["ball:1", "simplex", "box:0,1,0,2"] {
        let o = run(&[
            "generate",
            "-n",
            "40",
            "-s",
            "2",
            "--goal",
            "integration",
            "--shape",
            shape,
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let table = text(&o.stderr);
        assert!(!table.contains("reduction"), "{table}");
        assert!(!table.contains("NaN"), "{table}");
    }
}

#[test]
fn a_design_csv_from_a_spreadsheet_or_pandas_reads() {
    let d = TempDir::new("spreadsheet");
    let vars: Vec<String> = ["x=uniform(0,1)", "k=int(1,4)", "c={a,b}"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let plain = "x,k,c\n0.125,1,a\n0.375,2,b\n0.625,3,a\n0.875,4,b\n";
    fs::write(d.path("plain.csv"), plain).unwrap();
    let want = eval_figures(&d.path("plain.csv"), &vars, &[]);
    for (name, body) in [
        ("bom.csv", format!("\u{feff}{plain}")),
        (
            "quoted.csv",
            "\"x\",\"k\",\"c\"\n\"0.125\",\"1\",\"a\"\n\"0.375\",2,b\n0.625,\"3\",a\n0.875,4,\"b\"\n"
                .to_string(),
        ),
        ("pandas.csv", plain.replace(",1,", ",1.0,").replace(",4,", ",4.0,")),
    ] {
        fs::write(d.path(name), body).unwrap();
        assert_eq!(eval_figures(&d.path(name), &vars, &[]), want, "{name}");
    }
    // A fraction is no integer.
    fs::write(d.path("half.csv"), plain.replace(",2,", ",2.5,")).unwrap();
    let mut cmd = bin();
    cmd.arg("eval");
    for v in &vars {
        cmd.args(["--var", v]);
    }
    refused(&cmd.arg(d.path("half.csv")).output().unwrap(), "k");
}

/// A space whose every law is unbounded takes a set made directly (the lattice made for
/// the laws, picked or randomised), not by a run: its report is JSON on request like any
/// design's, with the figures `eval` gives the written file; a picture or a resume, which
/// need a run, are refused in one line naming the flag.
#[test]
fn a_set_made_for_the_laws_reports_json_and_refuses_what_needs_a_run() {
    let d = TempDir::new("laws-json");
    let vars: Vec<String> = ["v0=normal(0,0.01)", "v1=lognormal(0,0.5)"]
        .map(String::from)
        .to_vec();
    for (name, extra) in [
        ("picked.npy", None),
        ("randomised.npy", Some("--randomize")),
    ] {
        let out = d.path(name);
        let mut cmd = bin();
        cmd.args(["generate", "--json", "-n", "40", "--seed", "3", "-o"])
            .arg(&out);
        cmd.args(extra);
        for v in &vars {
            cmd.args(["--var", v]);
        }
        let o = cmd.output().unwrap();
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert!(report["run"]
            .as_str()
            .unwrap()
            .contains("lattice made for the laws"));
        assert_eq!(eval_figures(&out, &vars, &[]), report["figures"], "{name}");
    }
    let mut cmd = bin();
    cmd.args(["generate", "-n", "40", "-o"])
        .arg(d.path("x.npy"))
        .arg("--plot")
        .arg(d.path("x.png"));
    for v in &vars {
        cmd.args(["--var", v]);
    }
    refused(&cmd.output().unwrap(), "--plot");
    assert!(!d.path("x.npy").exists() && !d.path("x.png").exists());
}

/// A random space of one to four variables, each continuous, integer or categorical.
fn space() -> impl Strategy<Value = Vec<String>> {
    let var = prop_oneof![
        (-1e3f64..1e3, 1e-3f64..1e3).prop_map(|(lo, w)| format!("uniform({lo},{})", lo + w)),
        (-5f64..5.0, 0.01f64..4.0).prop_map(|(m, s)| format!("normal({m},{s})")),
        (0.3f64..4.0, 0.3f64..4.0).prop_map(|(a, b)| format!("beta({a},{b})")),
        (-50i64..50, 0i64..6).prop_map(|(lo, w)| format!("int({lo},{})", lo + w)),
        (2usize..4).prop_map(|k| format!("{{{}}}", ["a", "b", "c", "d"][..k].join(","))),
    ];
    prop::collection::vec(var, 1..5).prop_map(|kinds| {
        kinds
            .into_iter()
            .enumerate()
            .map(|(j, k)| format!("v{j}={k}"))
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Every figure of a design's report equals `eval` of the file it wrote.
    #[test]
    fn every_report_figure_is_eval_of_the_written_file(vars in space(), n in 4usize..40, seed in 0u64..1000) {
        let d = TempDir::new(&format!("prop-{n}-{seed}"));
        let numeric = !vars.iter().any(|v| v.contains('{'));
        let out = d.path(if numeric && seed % 2 == 0 { "d.npy" } else { "d.csv" });
        let mut cmd = bin();
        cmd.args(["generate", "--json", "-n", &n.to_string(), "--seed", &seed.to_string(), "-o"]).arg(&out);
        for v in &vars {
            cmd.args(["--var", v]);
        }
        let o = cmd.output().unwrap();
        prop_assert!(o.status.success(), "{:?}: {}", vars, text(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        prop_assert_eq!(eval_figures(&out, &vars, &[]), report["figures"].clone());
    }
}

#[test]
fn a_report_past_the_dimension_where_the_closed_forms_fit_says_so() {
    // At s = 6 000 the modified and wrap-around discrepancies pass the largest float and
    // the centred one is about 1e284: no NaN, no inf, no number printed in 285 digits,
    // and the start's candidates say the target is not representable (they were ranked
    // by NaN).
    let o = run(&["generate", "-n", "10", "-s", "6000", "-o", "/dev/null"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let table = text(&o.stdout) + &text(&o.stderr);
    assert!(!table.contains("NaN") && !table.contains(" inf"), "{table}");
    assert!(table.contains("beyond f64") && table.contains("not representable in f64"));
    let longest = table.split_whitespace().map(str::len).max().unwrap_or(0);
    assert!(longest < 40, "a field of {longest} characters: {table}");
}
