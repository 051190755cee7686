//! `stillpoint sensitivity`: Sobol' indices of an expression against closed forms, the
//! table, the JSON, the bar chart, and the refusals in the flags' names.

mod common;

use common::{bin, succeeded, TempDir};

const ISHIGAMI: &str = "sin(x1) + 7*sin(x2)^2 + 0.1*x3^4*sin(x1)";
const PI_BOX: &str = "-3.141592653589793,3.141592653589793,-3.141592653589793,\
                      3.141592653589793,-3.141592653589793,3.141592653589793";

fn run_json(args: &[&str]) -> serde_json::Value {
    let mut cmd = bin();
    cmd.arg("sensitivity").args(args).arg("--json");
    let (out, _) = succeeded(&mut cmd, &args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

fn refused(args: &[&str]) -> String {
    let out = bin().arg("sensitivity").args(args).output().unwrap();
    assert!(!out.status.success(), "{args:?} succeeded");
    String::from_utf8(out.stderr).unwrap()
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn ishigami_is_within_the_tolerance_of_its_closed_form() {
    let v = run_json(&["--expr", ISHIGAMI, "-s", "3", &format!("--bounds={PI_BOX}")]);
    let p4 = std::f64::consts::PI.powi(4);
    let v1 = 0.1 * p4 / 5.0 + 0.01 * p4 * p4 / 50.0 + 0.5;
    let v2 = 49.0 / 8.0;
    let v13 = 8.0 * 0.01 * p4 * p4 / 225.0;
    let var = v1 + v2 + v13;
    let first = [v1 / var, v2 / var, 0.0];
    let total = [(v1 + v13) / var, v2 / var, v13 / var];
    assert_eq!(v["met"], true, "{v}");
    for (got, want) in floats(&v["first"]).iter().zip(first) {
        assert!((got - want).abs() <= 0.01, "{v}");
    }
    for (got, want) in floats(&v["total"]).iter().zip(total) {
        assert!((got - want).abs() <= 0.01, "{v}");
    }
    assert!(floats(&v["total_half_width"]).iter().all(|h| *h <= 0.01));
    assert_eq!(v["names"], serde_json::json!(["x1", "x2", "x3"]));
    assert_eq!(v["rule"], "lattice", "a box: the tent lattice");
    // Ishigami is periodic in every input over [−π, π]: the face test (8·d evaluations,
    // counted in n) takes every input without the tent.
    assert_eq!(v["periodic"], serde_json::json!(["x1", "x2", "x3"]));
    assert_eq!(v["n"].as_u64().unwrap() % 40, 24, "{v}");
    assert_eq!(v["interval"], "posterior", "{v}");
    // By name, the blocks' interval: the same points and indices.
    let blocks = run_json(&[
        "--expr",
        ISHIGAMI,
        "-s",
        "3",
        &format!("--bounds={PI_BOX}"),
        "--interval",
        "blocks",
        "--max-n",
        &v["n"].to_string(),
        "--abs-tol",
        "0",
    ]);
    assert_eq!(blocks["interval"], "blocks", "{blocks}");
    assert_eq!((&blocks["first"], &blocks["n"]), (&v["first"], &v["n"]));
    assert_ne!(blocks["total_half_width"], v["total_half_width"]);
    let mixed = run_json(&[
        "--expr",
        "sin(x1) + x2",
        "-s",
        "2",
        "--bounds=-3.141592653589793,3.141592653589793,-1,1",
    ]);
    assert_eq!(mixed["periodic"], serde_json::json!(["x1"]));
}

/// `--second-order`: every pair of Ishigami's inputs, S_13 = V_13 / V and the others 0,
/// in the JSON and in the table.
#[test]
fn second_order_pairs_are_ishigami_s_closed_forms() {
    let args = ["--expr", ISHIGAMI, "-s", "3", "--second-order"];
    let bounds = format!("--bounds={PI_BOX}");
    let v = run_json(&[&args[..], &[bounds.as_str()]].concat());
    let p4 = std::f64::consts::PI.powi(4);
    let v13 = 8.0 * 0.01 * p4 * p4 / 225.0;
    let var = 0.1 * p4 / 5.0 + 0.01 * p4 * p4 / 50.0 + 0.5 + 49.0 / 8.0 + v13;
    assert_eq!(v["met"], true, "{v}");
    assert_eq!(v["second_order"], true);
    let pairs = v["second"].as_array().unwrap();
    let want = [
        (["x1", "x2"], 0.0),
        (["x1", "x3"], v13 / var),
        (["x2", "x3"], 0.0),
    ];
    assert_eq!(pairs.len(), 3);
    for (pair, (inputs, index)) in pairs.iter().zip(want) {
        assert_eq!(pair["inputs"], serde_json::json!(inputs));
        assert!(
            (pair["index"].as_f64().unwrap() - index).abs() <= 0.01,
            "{v}"
        );
        assert!(pair["half_width"].as_f64().unwrap() <= 0.01, "{v}");
    }
    // 2d + 2 evaluations per point of 8 blocks, and the face test's 24.
    assert_eq!((v["n"].as_u64().unwrap() - 24) % 64, 0, "{v}");
    let mut cmd = bin();
    cmd.arg("sensitivity").args(args).arg(&bounds);
    let (table, _) = succeeded(&mut cmd, &args);
    assert!(table.contains("pair") && table.contains("x1,x3"), "{table}");
    // Without the flag, no pairs.
    let plain = run_json(&["--expr", ISHIGAMI, "-s", "3", &bounds]);
    assert!(plain.get("second").is_none() && plain["second_order"] == false);
}

#[test]
fn laws_give_names_and_the_table_and_plot_are_written() {
    // x1 + 2·x2 with both normal and a third input unused: S = T = (1/5, 4/5, 0).
    let args = [
        "--expr",
        "x1 + 2*x2",
        "--var",
        "a=normal(0,1)",
        "--var",
        "b=normal(3,1)",
        "--var",
        "c=uniform(0,1)",
    ];
    let v = run_json(&args);
    assert_eq!(v["names"], serde_json::json!(["a", "b", "c"]));
    assert_eq!(
        v["rule"], "sobol",
        "unbounded laws: Sobol' points, as quad's"
    );
    assert_eq!(v["periodic"], serde_json::json!([]), "no face test");
    for (got, want) in floats(&v["first"]).iter().zip([0.2, 0.8, 0.0]) {
        assert!((got - want).abs() <= 0.01, "{v}");
    }
    let dir = TempDir::new("sensitivity-plot");
    let png = dir.path("bars.png");
    let mut cmd = bin();
    cmd.arg("sensitivity").args(args).arg("--plot").arg(&png);
    let (out, _) = succeeded(&mut cmd, &args);
    assert!(out.starts_with("input"), "{out}");
    assert!(out.contains("\nb "), "{out}");
    assert!(out.contains("met          yes"), "{out}");
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
}

#[test]
fn refusals_name_the_flag_and_the_value_as_typed() {
    for (args, want) in [
        (
            vec!["-s", "2", "--abs-tol=-1e-3"],
            "invalid --abs-tol = -1e-3",
        ),
        (vec!["-s", "501"], "invalid -s = 501"),
        (vec!["-s", "2", "--max-n", "10"], "invalid --max-n = 10"),
        (vec!["-s", "2", "--level", "2"], "invalid --level = 2"),
        (
            vec!["-s", "2", "--first-estimator", "owen"],
            "invalid --first-estimator = owen",
        ),
        (
            vec!["-s", "2", "--interval", "median"],
            "invalid --interval = median",
        ),
        (vec!["--var", "W=brownian(1,3)"], "invalid --var = W_1"),
        (vec!["-s", "2", "--bounds", "0,1"], "--bounds"),
        (vec![], "needs -s S"),
    ] {
        let mut all = vec!["--expr", "x1 + x2"];
        all.extend(args.iter().copied());
        let e = refused(&all);
        assert!(e.contains(want), "{all:?}: {e}");
    }
    let e = refused(&["--expr", "2", "-s", "2"]);
    assert!(
        e.contains("invalid --expr \"2\": 2 at every one of the first"),
        "{e}"
    );
}
