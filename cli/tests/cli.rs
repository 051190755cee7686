//! End-to-end tests of the `stillpoint` command: outputs, reports, refusals and
//! reproducibility.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{bin, tmpdir};

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("run stillpoint")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn files_in(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn generate_improves_on_halton_and_eval_agrees() {
    let d = tmpdir("gen");
    let out = d.join("p.csv");
    let o = run(&[
        "generate",
        "-n",
        "120",
        "-s",
        "2",
        "-o",
        out.to_str().unwrap(),
        "--json",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rep: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let before = rep["metrics_start"]["modified_l2"].as_f64().unwrap();
    let after = rep["metrics_result"]["modified_l2"].as_f64().unwrap();
    assert!(after < 0.8 * before, "D_MD {before} -> {after}");
    let dmin0 = rep["metrics_start"]["min_distance"].as_f64().unwrap();
    let dmin1 = rep["metrics_result"]["min_distance"].as_f64().unwrap();
    assert!(dmin1 > dmin0);
    // eval reads the file back and reports the same figures.
    let e = run(&["eval", out.to_str().unwrap(), "--json"]);
    assert!(e.status.success(), "{}", stderr(&e));
    let ev: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
    assert_eq!(ev["n"], 120);
    assert_eq!(ev["s"], 2);
    assert_eq!(ev["modified_l2"].as_f64().unwrap(), after);
    // The table form names the metrics and says they are roots.
    let t = run(&["eval", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&t.stdout);
    assert!(
        text.contains("modified L2 discrepancy D_MD (root)"),
        "{text}"
    );
}

#[test]
fn formats_by_extension_round_trip() {
    let d = tmpdir("fmt");
    let mut results = Vec::new();
    for ext in ["csv", "tsv", "json", "npy"] {
        let f = d.join(format!("p.{ext}"));
        let o = run(&[
            "generate",
            "-n",
            "30",
            "-s",
            "3",
            "--steps",
            "20",
            "-o",
            f.to_str().unwrap(),
            "-q",
        ]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
        let e = run(&["eval", f.to_str().unwrap(), "--json"]);
        assert!(e.status.success(), "{ext}: {}", stderr(&e));
        let v: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
        results.push(v["star_l2"].as_f64().unwrap().to_bits());
    }
    assert!(results.windows(2).all(|w| w[0] == w[1]), "formats disagree");
}

#[test]
fn same_bytes_for_one_and_two_threads() {
    let d = tmpdir("threads");
    let mut bytes = Vec::new();
    for t in ["1", "2"] {
        let f = d.join(format!("p{t}.csv"));
        let o = run(&[
            "--threads",
            t,
            "generate",
            "-n",
            "90",
            "-s",
            "3",
            "--steps",
            "80",
            "--init",
            "random",
            "--seed",
            "7",
            "-o",
            f.to_str().unwrap(),
            "-q",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        bytes.push(std::fs::read(&f).unwrap());
    }
    assert_eq!(bytes[0], bytes[1]);
}

#[test]
fn points_to_stdout_report_to_stderr() {
    let o = run(&["generate", "-n", "10", "-s", "2", "--steps", "5", "-q"]);
    assert!(o.status.success());
    let csv = String::from_utf8_lossy(&o.stdout);
    let rows = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .count();
    assert_eq!(rows, 10, "{csv}");
    assert!(stderr(&o).contains("star L2 discrepancy"));
}

#[test]
fn bad_input_is_refused_clearly_and_writes_nothing() {
    let d = tmpdir("bad");
    let out = d.join("out.csv");
    let o_s = out.to_str().unwrap();
    let ragged = d.join("ragged.csv");
    std::fs::write(&ragged, "0.1,0.2\n0.3\n").unwrap();
    let words = d.join("words.csv");
    std::fs::write(&words, "0.1,0.2\n0.3,abc\n").unwrap();
    let outside = d.join("outside.csv");
    std::fs::write(&outside, "0.1,0.2\n0.3,1.5\n").unwrap();
    let nan = d.join("nan.csv");
    std::fs::write(&nan, "0.1,0.2\n0.3,nan\n").unwrap();
    let empty = d.join("empty.csv");
    std::fs::write(&empty, "# nothing\n").unwrap();
    let missing = d.join("missing.csv");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["generate", "-n", "0", "-s", "2", "-o", o_s], "n"),
        (vec!["generate", "-n", "10", "-s", "0", "-o", o_s], "s"),
        (
            vec!["generate", "-n", "10", "-s", "2", "--p", "0", "-o", o_s],
            "p",
        ),
        (
            vec!["generate", "-n", "10", "-s", "2", "--p", "-1", "-o", o_s],
            "p",
        ),
        (
            vec!["generate", "-n", "10", "-s", "2", "--p", "nan", "-o", o_s],
            "p",
        ),
        (
            vec!["generate", "-n", "10", "-s", "2", "--q", "0", "-o", o_s],
            "q",
        ),
        (
            vec!["generate", "-n", "10", "-s", "2", "--q", "-2", "-o", o_s],
            "q",
        ),
        (
            vec!["generate", "-n", "10", "-s", "2", "--q", "abc", "-o", o_s],
            "q",
        ),
        (
            vec![
                "generate", "-n", "10", "-s", "2", "--kappa", "0.5", "-o", o_s,
            ],
            "kappa",
        ),
        (
            vec![
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "--restart",
                "-1",
                "-o",
                o_s,
            ],
            "restart",
        ),
        (vec!["generate", "-n", "10", "-o", o_s], "-s"),
        (
            vec![
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "--tolerance",
                "-1",
                "-o",
                o_s,
            ],
            "tolerance",
        ),
        (
            vec!["generate", "--init", ragged.to_str().unwrap(), "-o", o_s],
            "line 2",
        ),
        (
            vec!["generate", "--init", words.to_str().unwrap(), "-o", o_s],
            "abc",
        ),
        (
            vec!["generate", "--init", outside.to_str().unwrap(), "-o", o_s],
            "[0, 1]",
        ),
        (
            vec!["generate", "--init", nan.to_str().unwrap(), "-o", o_s],
            "finite",
        ),
        (
            vec![
                "generate",
                "-n",
                "3",
                "-s",
                "2",
                "--init",
                words.to_str().unwrap(),
                "-o",
                o_s,
            ],
            "abc",
        ),
        (
            vec![
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "-o",
                "/nonexistent-dir/x.csv",
            ],
            "does not exist",
        ),
        (
            vec![
                "--threads",
                "0",
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "-o",
                o_s,
            ],
            "threads",
        ),
        (vec!["eval", ragged.to_str().unwrap()], "line 2"),
        (vec!["eval", outside.to_str().unwrap()], "[0, 1]"),
        (vec!["eval", nan.to_str().unwrap()], "finite"),
        (vec!["eval", empty.to_str().unwrap()], "no points"),
        (vec!["eval", missing.to_str().unwrap()], "missing.csv"),
    ];
    let before = files_in(&d);
    for (args, needle) in &cases {
        let o = run(args);
        let err = stderr(&o);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(
            err.contains(needle),
            "{args:?}: message {err:?} does not mention {needle:?}"
        );
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
        assert_eq!(files_in(&d), before, "{args:?} left a file behind");
    }
}

/// One point set written by `generate` in every format (chosen by extension).
fn one_set_in_every_format(d: &Path) -> Vec<PathBuf> {
    ["csv", "tsv", "json", "npy"]
        .iter()
        .map(|ext| {
            let f = d.join(format!("p.{ext}"));
            let o = run(&[
                "generate",
                "-n",
                "40",
                "-s",
                "3",
                "--steps",
                "20",
                "-o",
                f.to_str().unwrap(),
                "-q",
            ]);
            assert!(o.status.success(), "{ext}: {}", stderr(&o));
            f
        })
        .collect()
}

#[test]
fn eval_integrate_and_plot_read_every_format() {
    let d = tmpdir("every-format");
    let files = one_set_in_every_format(&d);
    let mut evals = Vec::new();
    let mut integrals = Vec::new();
    let mut pictures = Vec::new();
    for f in &files {
        let name = f.to_str().unwrap();
        let e = run(&["eval", name, "--json"]);
        assert!(e.status.success(), "eval {name}: {}", stderr(&e));
        let v: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
        assert_eq!((v["n"].as_u64(), v["s"].as_u64()), (Some(40), Some(3)));
        evals.push(e.stdout);
        let i = run(&["integrate", name, "--json"]);
        assert!(i.status.success(), "integrate {name}: {}", stderr(&i));
        let mut v: serde_json::Value = serde_json::from_slice(&i.stdout).unwrap();
        v["file"] = serde_json::Value::Null;
        assert_eq!(v["functions"].as_array().map(Vec::len), Some(8));
        integrals.push(v);
        let pic = f.with_extension(format!("{}.png", f.extension().unwrap().to_str().unwrap()));
        let p = run(&["plot", name, "-o", pic.to_str().unwrap(), "--title", "same"]);
        assert!(p.status.success(), "plot {name}: {}", stderr(&p));
        pictures.push(std::fs::read(&pic).unwrap());
    }
    // The same points in every format: the same numbers and the same picture.
    assert!(
        evals.windows(2).all(|w| w[0] == w[1]),
        "eval differs by format"
    );
    assert!(
        integrals.windows(2).all(|w| w[0] == w[1]),
        "integrate differs"
    );
    assert!(pictures.windows(2).all(|w| w[0] == w[1]), "plot differs");
}

#[test]
fn point_files_record_generator_parameters_seed_version_and_metrics() {
    let d = tmpdir("headers");
    let files = one_set_in_every_format(&d);
    let csv = std::fs::read_to_string(&files[0]).unwrap();
    let tsv = std::fs::read_to_string(&files[1]).unwrap();
    for (text, sep) in [(&csv, ","), (&tsv, "\t")] {
        let header: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
        for key in [
            "# generator: \"stillpoint generate\"",
            "# version: \"",
            "# seed: 0",
            "# parameters: {",
            "\"steps\":20",
            "\"energy\":\"U_{q,p}",
            "# metrics: {",
            "\"modified_l2\":",
        ] {
            assert!(
                header.iter().any(|l| l.contains(key)),
                "{key} missing from {header:?}"
            );
        }
        let columns = text.lines().find(|l| !l.starts_with('#')).unwrap();
        assert_eq!(columns, ["x1", "x2", "x3"].join(sep));
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&files[2]).unwrap()).unwrap();
    assert_eq!(json["meta"]["generator"], "stillpoint generate");
    assert_eq!(json["meta"]["parameters"]["n"], 40);
    assert!(json["meta"]["metrics"]["star_l2"].as_f64().unwrap() > 0.0);
    assert_eq!(json["points"].as_array().unwrap().len(), 40);
    // A baseline says which generator and seed made it, in every format.
    for ext in ["csv", "json"] {
        let f = d.join(format!("sobol.{ext}"));
        let o = run(&[
            "baseline",
            "sobol",
            "-n",
            "32",
            "-s",
            "2",
            "--seed",
            "9",
            "-o",
            f.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(text.contains("stillpoint baseline sobol"), "{text}");
        assert!(
            text.contains("\"baseline\":\"sobol\"") || text.contains("\"baseline\": \"sobol\"")
        );
        assert!(
            text.contains("\"seed\":9") || text.contains("# seed: 9"),
            "{text}"
        );
        assert!(text.contains("modified_l2"), "{text}");
    }
    // --json summaries of baseline: the points when there is no -o.
    let o = run(&["baseline", "halton", "-n", "8", "-s", "2", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), 8);
    assert_eq!(v["parameters"]["baseline"], "halton");
}

#[test]
fn generate_writes_checkpoints_and_names_them_in_its_help() {
    let d = tmpdir("ckpt");
    let ck = d.join("run.ckpt");
    let out = d.join("p.csv");
    let o = run(&[
        "generate",
        "-n",
        "30",
        "-s",
        "2",
        "--steps",
        "40",
        "--tolerance",
        "0",
        "--checkpoint",
        ck.to_str().unwrap(),
        "--checkpoint-every",
        "10",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&ck).unwrap()).unwrap();
    assert_eq!(v["format"], "stillpoint checkpoint");
    assert_eq!(v["state"]["step"], 40);
    assert_eq!(v["config"]["steps"], 40);
    assert_eq!(
        files_in(&d),
        vec!["p.csv".to_string(), "run.ckpt".to_string()]
    );
    let help = run(&["generate", "--help"]);
    let text = String::from_utf8_lossy(&help.stdout);
    for flag in ["--checkpoint", "--checkpoint-every", "--resume", "--quiet"] {
        assert!(text.contains(flag), "{flag} missing from generate --help");
    }
}
