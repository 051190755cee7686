//! The reports of goal runs say what ran: each start's candidates and the one kept, each
//! descent's exchanges and L-BFGS iterations or why it was skipped, the searches of the
//! space-filling goal; the same stages in the table, the JSON and a written file's
//! header, and no solver facts a goal run does not have.

mod common;

use common::{bin, TempDir};
use serde_json::Value;

/// `generate ARGS --json -q` as JSON, and the table of the same run.
fn run_json(args: &[&str]) -> Value {
    let out = bin()
        .arg("generate")
        .args(args)
        .args(["--json", "-q"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!text.contains("NaN") && !text.contains("nan"), "{text}");
    serde_json::from_str(&text).unwrap()
}

fn run_table(args: &[&str]) -> String {
    let out = bin().arg("generate").args(args).arg("-q").output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The stages of one kind.
fn stages<'a>(v: &'a Value, kind: &str) -> Vec<&'a Value> {
    v["stages"]
        .as_array()
        .expect("stages")
        .iter()
        .filter(|s| s["stage"] == kind)
        .collect()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn a_goal_run_reports_its_start_exchanges_and_lbfgs_and_no_solver_placeholders() {
    let d = TempDir::new("counts");
    let out = d.path("x.npy");
    let v = run_json(&["-n", "64", "-s", "3", "-o", out.to_str().unwrap()]);
    // The paper's solver facts and energy choice do not exist for a goal run.
    for key in [
        "stop", "q", "p", "eq48", "kappa", "restarts", "steps", "run",
    ] {
        assert!(v.get(key).is_none(), "{key} in {v}");
    }
    let start = stages(&v, "start");
    assert_eq!(start.len(), 1);
    let candidates = start[0]["candidates"].as_array().unwrap();
    assert!(candidates.len() >= 2, "{candidates:?}");
    let kept = start[0]["kept"].as_u64().unwrap() as usize;
    // The kept candidate is the lowest, and its value is the report's start.
    let lowest = candidates
        .iter()
        .map(|c| f(&c["value"]))
        .fold(f64::INFINITY, f64::min);
    assert_eq!(f(&candidates[kept]["value"]), lowest);
    assert_eq!(f(&v["energy_start"]), lowest);
    assert!(f(&v["energy_result"]) < lowest);

    let descent = stages(&v, "descent");
    assert_eq!(descent.len(), 1);
    assert!(descent[0]["skipped"].is_null());
    let rounds = descent[0]["rounds"].as_array().unwrap();
    assert_eq!(rounds.len(), 3);
    let accepted: u64 = rounds.iter().map(|r| r["accepted"].as_u64().unwrap()).sum();
    let iterations: u64 = rounds
        .iter()
        .map(|r| r["lbfgs_iterations"].as_u64().unwrap())
        .sum();
    assert!(accepted > 0 && iterations > 0, "{rounds:?}");
    for r in rounds {
        assert!(r["accepted"].as_u64() <= r["proposals"].as_u64());
        assert!(r["lbfgs_iterations"].as_u64().unwrap() <= 30, "{r}");
        assert!(["step_budget", "converged"].contains(&r["lbfgs_stop"].as_str().unwrap()));
    }
    assert_eq!(v["totals"]["exchanges_accepted"], accepted);
    assert_eq!(v["totals"]["lbfgs_iterations"], iterations);
    assert_eq!(v["totals"]["descents_skipped"], serde_json::json!([]));

    let table = run_table(&["-n", "64", "-s", "3", "-o", out.to_str().unwrap()]);
    assert!(
        table.contains(&format!("exchanges accepted {accepted} of")),
        "{table}"
    );
    assert!(
        table.contains(&format!("in-cell L-BFGS iterations {iterations} ")),
        "{table}"
    );
    assert!(!table.contains("best of 8"), "{table}");
}

#[test]
fn a_nested_run_starts_from_its_stages_as_placed() {
    let d = TempDir::new("nested");
    let out = d.path("x.npy");
    let v = run_json(&[
        "-n",
        "32",
        "-s",
        "3",
        "--nested",
        "16,32",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(f(&v["energy_result"]) < f(&v["energy_start"]), "{v}");
    assert_ne!(v["metrics_start"], v["metrics_result"]);
    let sizes: Vec<u64> = stages(&v, "start")
        .iter()
        .map(|s| s["n"].as_u64().unwrap())
        .collect();
    assert_eq!(sizes, [16, 32]);
    assert_eq!(stages(&v, "descent").len(), 2);
    // The later stage moves only its new points.
    assert_eq!(stages(&v, "descent")[1]["moving"], 16);
}

#[test]
fn a_skipped_descent_is_reported_with_its_reason_and_the_report_stays_finite() {
    // One point has nothing to move; where the budget allows no iteration the same
    // field carries that reason (see the descent's unit tests).
    let d = TempDir::new("skipped");
    let out = d.path("x.npy");
    let v = run_json(&["-n", "1", "-s", "3", "-o", out.to_str().unwrap()]);
    let descent = stages(&v, "descent");
    assert_eq!(descent.len(), 1);
    assert!(descent[0]["rounds"].as_array().unwrap().is_empty());
    let why = descent[0]["skipped"].as_str().expect("a reason");
    assert!(why.contains("nothing to move"), "{why}");
    assert_eq!(v["totals"]["descents_skipped"][0], why);
    let (a, b) = (f(&v["energy_start"]), f(&v["energy_result"]));
    assert!(a.is_finite() && b.is_finite());
    let start = stages(&v, "start");
    assert_eq!(
        f(&start[0]["candidates"][start[0]["kept"].as_u64().unwrap() as usize]["value"]),
        a
    );
}

#[test]
fn a_written_files_header_has_the_reports_stages() {
    let d = TempDir::new("header");
    for (file, args) in [
        ("a.csv", vec!["-n", "40", "-s", "2"]),
        ("b.csv", vec!["-n", "24", "-s", "2", "--nested", "8,24"]),
        (
            "c.csv",
            vec!["--goal", "space-filling", "-n", "20", "-s", "2"],
        ),
    ] {
        let out = d.path(file);
        let mut args = args.clone();
        args.extend(["-o", out.to_str().unwrap()]);
        let v = run_json(&args);
        let text = std::fs::read_to_string(&out).unwrap();
        let line = |key: &str| -> Value {
            let prefix = format!("# {key}: ");
            let l = text
                .lines()
                .find_map(|l| l.strip_prefix(&prefix))
                .unwrap_or_else(|| panic!("no {key} in {file}"));
            serde_json::from_str(l).unwrap()
        };
        let parameters = line("parameters");
        assert_eq!(parameters["stages"], v["stages"], "{file}");
        assert!(!parameters["stages"].as_array().unwrap().is_empty());
        let run = line("run");
        assert!(
            run.get("stop").is_none() && run.get("steps").is_none(),
            "{run}"
        );
    }
}

#[test]
fn space_filling_reports_its_candidates_distances_and_the_one_kept() {
    let v = run_json(&["--goal", "space-filling", "-n", "30", "-s", "2"]);
    let dem = stages(&v, "dem");
    assert_eq!(dem.len(), 1);
    assert!(dem[0]["steps"].as_u64().unwrap() > 0);
    let search = stages(&v, "maximin");
    assert_eq!(search.len(), 1);
    let candidates = search[0]["candidates"].as_array().unwrap();
    assert_eq!(candidates.len(), 5);
    let kept = search[0]["kept"].as_u64().unwrap() as usize;
    let largest = candidates
        .iter()
        .map(|c| f(&c["value"]))
        .fold(0.0, f64::max);
    assert_eq!(f(&candidates[kept]["value"]), largest);
    let passes = search[0]["passes"].as_array().unwrap();
    assert_eq!(f(passes.last().unwrap()), f(&v["energy_result"]));
    assert!(f(&v["energy_result"]) >= largest);
}

#[test]
fn the_papers_run_keeps_its_solver_facts() {
    let v = run_json(&["--method", "paper", "-n", "30", "-s", "2", "--steps", "40"]);
    assert!(v["q"].is_string() && v["p"].is_number(), "{v}");
    assert!(v["stop"].is_string() && v["steps"].as_u64().unwrap() > 0);
    assert!(v.get("stages").is_none());
}

/// `eval FILES` as text.
fn eval_table(files: &[&std::path::Path]) -> String {
    let out = bin().arg("eval").args(files).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The value cells of the figure rows of an `eval` comparison (the rows between the
/// column names and the stratification row), each split into its columns.
fn figure_cells(table: &str, files: usize) -> Vec<Vec<String>> {
    table
        .lines()
        .skip_while(|l| !l.ends_with(".csv") || !l.starts_with("  "))
        .skip(1)
        .take_while(|l| !l.contains("every coordinate stratified"))
        .map(|l| {
            let cells: Vec<String> = l
                .split_whitespace()
                .rev()
                .take(files)
                .map(String::from)
                .collect();
            cells.into_iter().rev().collect()
        })
        .collect()
}

#[test]
fn eval_marks_the_best_only_among_sets_of_the_same_size() {
    let dir = TempDir::new("eval-best-same-n");
    let (a, b, c) = (dir.path("a.csv"), dir.path("b.csv"), dir.path("c.csv"));
    for (file, args) in [
        (&a, vec!["generate", "-n", "64", "-s", "2", "-q"]),
        (&b, vec!["baseline", "halton", "-n", "64", "-s", "2"]),
        (&c, vec!["generate", "-n", "100", "-s", "2", "-q"]),
    ] {
        let o = bin().args(&args).arg("-o").arg(file).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // Two sets of 64 points and one of 100: a best is marked in each row among the two of
    // the same size, never on the set of 100 points, which has no peer.
    let table = eval_table(&[&a, &b, &c]);
    let rows = figure_cells(&table, 3);
    assert!(rows.len() >= 8, "{table}");
    for row in &rows {
        assert!(
            !row[2].ends_with('*'),
            "the 100-point set is ranked: {row:?}\n{table}"
        );
        if row[0] != "-" && row[1] != "-" {
            let marked = row[..2].iter().filter(|c| c.ends_with('*')).count();
            assert!(
                marked >= 1,
                "no best among the 64-point sets: {row:?}\n{table}"
            );
        }
    }
    assert!(
        table.contains("among the files of the same n and s"),
        "{table}"
    );
    // Only sets of different sizes: nothing is marked, and the note says why.
    let table = eval_table(&[&a, &c]);
    assert!(
        figure_cells(&table, 2)
            .iter()
            .flatten()
            .all(|c| !c.ends_with('*')),
        "{table}"
    );
    assert!(
        table.contains("No two files have the same n and s"),
        "{table}"
    );
}

#[test]
fn a_randomised_draw_reports_its_figures_and_no_target() {
    let dir = TempDir::new("randomised-report");
    let table = |extra: &[&str]| {
        let o = bin()
            .args(["generate", "-n", "64", "-s", "3", "-o"])
            .arg(dir.path("x.csv"))
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
    };
    let drawn = table(&["--randomize", "--seed", "5"]);
    let figures: Vec<&str> = drawn
        .lines()
        .skip_while(|l| l.trim() != "drawn set")
        .take_while(|l| !l.trim().is_empty())
        .collect();
    assert!(figures.len() >= 7, "{drawn}");
    for line in &figures {
        assert!(
            !line.contains("target") && !line.contains('%'),
            "{line}\n{drawn}"
        );
    }
    assert!(!drawn.contains("(target "), "{drawn}");
    // The deterministic run keeps its start → result table.
    let made = table(&[]);
    assert!(made.contains("start") && made.contains("change"), "{made}");
}
