//! One file in two roles, forged checkpoints and the recorded kernel path: every refusal
//! exits non-zero with a message naming the option, and leaves every file as it was.

mod common;
use common::{bin, TempDir};
use std::collections::BTreeMap;
use std::path::Path;

/// Every file of the directory with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let bytes = std::fs::read(e.path()).unwrap_or_default();
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect()
}

fn refused(dir: &Path, args: &[&str], needle: &str) {
    let before = snapshot(dir);
    let o = bin().current_dir(dir).args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} succeeded");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
}

#[test]
fn one_file_in_two_roles_is_refused_before_the_run() {
    let d = TempDir::new("two-roles");
    let ok = bin()
        .current_dir(&d.0)
        .args(["baseline", "halton", "-n", "20", "-s", "2", "-o", "a.csv"])
        .output()
        .unwrap();
    assert!(ok.status.success());
    std::os::unix::fs::symlink("a.csv", d.path("link.csv")).unwrap();
    std::fs::create_dir(d.path("sub")).unwrap();
    let gen = |extra: &[&str]| -> Vec<String> {
        ["generate", "-n", "20", "-s", "2", "--steps", "20", "-q"]
            .iter()
            .chain(extra)
            .map(|s| s.to_string())
            .collect()
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            gen(&["--init", "a.csv", "--checkpoint", "a.csv"]),
            "--checkpoint",
        ),
        (gen(&["--init", "a.csv", "-o", "a.csv"]), "--init"),
        (gen(&["--init", "link.csv", "-o", "a.csv"]), "--init"),
        (
            gen(&["--init", "a.csv", "-o", "./sub/../link.csv"]),
            "--init",
        ),
        (gen(&["--checkpoint", "out.csv", "-o", "out.csv"]), "-o"),
        (gen(&["--plot", "x.png", "-o", "./x.png"]), "-o"),
        (
            gen(&["--trajectory", "t.json", "-o", "sub/../t.json"]),
            "-o",
        ),
        (
            gen(&["--trajectory", "t.json", "--checkpoint", "t.json"]),
            "--trajectory",
        ),
        (
            gen(&[
                "--checkpoint",
                "c.ckpt",
                "--trajectory",
                "link2.json",
                "-o",
                "c.ckpt",
            ]),
            "-o",
        ),
    ];
    for (args, needle) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&d.0, &args, needle);
    }
}

/// A change to a checkpoint's state.
type Edit = Box<dyn Fn(&mut serde_json::Value)>;

/// A checkpoint whose state was edited and whose checksum was recomputed to match.
fn forge(file: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(file).unwrap()).unwrap();
    edit(&mut v["state"]);
    let checksum =
        stillpoint::solve::checkpoint::fnv1a64(&serde_json::to_vec(&v["state"]).unwrap());
    v["checksum"] = format!("{checksum:016x}").into();
    std::fs::write(file, serde_json::to_vec(&v).unwrap()).unwrap();
}

#[test]
fn forged_checkpoints_are_refused_without_a_panic() {
    let d = TempDir::new("forged");
    for solver in ["dem", "lbfgs"] {
        let run = |extra: &[&str]| {
            let mut a = vec![
                "generate",
                "-n",
                "30",
                "-s",
                "2",
                "--steps",
                "20",
                "--integrator",
                solver,
                "--checkpoint",
                "run.ckpt",
                "--checkpoint-every",
                "5",
                "-o",
                "out.csv",
                "-q",
            ];
            a.extend_from_slice(extra);
            a.into_iter().map(String::from).collect::<Vec<_>>()
        };
        let o = bin().current_dir(&d.0).args(run(&[])).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let good = std::fs::read(d.path("run.ckpt")).unwrap();
        let edits: Vec<(&str, Edit)> = vec![
            (
                "a point far outside",
                Box::new(|s| s["state"]["current"]["data"][1] = 1e300.into()),
            ),
            (
                "a point just outside",
                Box::new(|s| s["state"]["current"]["data"][0] = (-0.25).into()),
            ),
            (
                "a buffer of the wrong length",
                Box::new(|s| {
                    s["state"]["current"]["data"].as_array_mut().unwrap().pop();
                }),
            ),
            (
                "another n",
                Box::new(|s| s["state"]["current"]["n"] = 31.into()),
            ),
            (
                "a step past the budget",
                Box::new(|s| s["step"] = 1000.into()),
            ),
            (
                "no trajectory",
                Box::new(|s| s["trajectory"] = serde_json::json!([])),
            ),
            (
                "a negative time",
                Box::new(|s| s["seconds"] = (-1.0).into()),
            ),
        ];
        for (what, edit) in edits {
            std::fs::write(d.path("run.ckpt"), &good).unwrap();
            forge(&d.path("run.ckpt"), edit);
            let args = run(&["--resume"]);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let before = snapshot(&d.0);
            let o = bin().current_dir(&d.0).args(&args).output().unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(!o.status.success(), "{solver}, {what}: accepted");
            assert!(!err.contains("panicked"), "{solver}, {what}: {err}");
            assert!(err.contains("--resume"), "{solver}, {what}: {err}");
            assert_eq!(snapshot(&d.0), before, "{solver}, {what}: a file changed");
        }
    }
}

#[test]
fn the_kernel_path_is_recorded_and_a_resume_on_another_path_is_refused() {
    let d = TempDir::new("kernel");
    let args = [
        "generate",
        "-n",
        "30",
        "-s",
        "2",
        "--steps",
        "20",
        "--checkpoint",
        "run.ckpt",
        "--checkpoint-every",
        "5",
        "-o",
        "out.csv",
        "-q",
    ];
    let o = bin().current_dir(&d.0).args(args).output().unwrap();
    assert!(o.status.success());
    let text = std::fs::read_to_string(d.path("out.csv")).unwrap();
    let path = stillpoint::energies::pairs::vector_path();
    assert!(
        text.lines()
            .any(|l| l.starts_with("# run:") && l.contains(path)),
        "{text}"
    );
    let ck: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.path("run.ckpt")).unwrap()).unwrap();
    assert_eq!(ck["config"]["kernel"], path);
    if path != "portable" {
        let mut resume = args.to_vec();
        resume.push("--resume");
        let before = snapshot(&d.0);
        let o = bin()
            .current_dir(&d.0)
            .env("STILLPOINT_PORTABLE", "1")
            .args(&resume)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(
            err.contains("kernel = avx2+fma (this run: portable)"),
            "{err}"
        );
        assert_eq!(snapshot(&d.0), before);
    }
}

#[test]
fn counts_and_ranges_are_checked_before_anything_is_allocated_or_written() {
    let d = TempDir::new("ranges");
    let ok = bin()
        .current_dir(&d.0)
        .args(["baseline", "halton", "-n", "20", "-s", "2", "-o", "a.csv"])
        .output()
        .unwrap();
    assert!(ok.status.success());
    std::fs::write(d.path("existing"), "a file").unwrap();
    std::fs::write(d.path("poly.txt"), "1e308 0 1\n0 1 1\n-1 0 1\n0 -1 1\n").unwrap();
    let huge = "1000000000000000000";
    let huge_case = format!("2x{huge}");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["generate", "-n", huge, "-s", "2", "-q"],
            "invalid -n = ",
        ),
        (
            vec!["generate", "-n", "400000000", "-s", "20", "-q"],
            "memory",
        ),
        (
            vec!["generate", "--shape", "ball:1", "-s", "2", "-n", huge, "-q"],
            "invalid -n = ",
        ),
        (
            vec!["baseline", "random", "-n", huge, "-s", "2"],
            "invalid -n = ",
        ),
        (
            vec!["baseline", "sobol", "-n", "100000000000", "-s", "3"],
            "invalid -n = ",
        ),
        (
            vec!["compare", "--cases", &huge_case, "--out", "cmp"],
            "--cases",
        ),
        (
            vec![
                "generate",
                "-n",
                "20",
                "-s",
                "2",
                "--shifts",
                "100000000000",
                "-q",
            ],
            "--shifts",
        ),
        (vec!["--threads", "10000", "eval", "a.csv"], "--threads"),
        (
            vec!["plot", "a.csv", "--box", "-1e308,1e308,0,1", "-o", "p.png"],
            "--box",
        ),
        (
            vec!["plot", "a.csv", "--box", "0,1e-300,0,1", "-o", "p.png"],
            "--box",
        ),
        (
            vec![
                "generate",
                "--region",
                "x^2+y^2-1",
                "--box",
                "-1e-300,1e-300,0,1",
                "-n",
                "3",
            ],
            "--box",
        ),
        (vec!["compare", "--quick", "--out", "existing"], "existing"),
        (
            vec![
                "generate",
                "--shape",
                "ball:1e308",
                "-s",
                "2",
                "-n",
                "5",
                "-q",
            ],
            "radius",
        ),
        (
            vec!["generate", "--shape", "ball:1e200@0,0", "-n", "5", "-q"],
            "radius",
        ),
        (
            vec!["generate", "--shape", "ellipsoid:1,1e300", "-n", "5", "-q"],
            "semi-axis 2",
        ),
        (
            vec![
                "generate",
                "--shape",
                "polytope:poly.txt",
                "--box",
                "-2,2,-2,2",
                "-n",
                "5",
            ],
            "row 1 of a",
        ),
    ];
    for (args, needle) in cases {
        refused(&d.0, &args, needle);
    }
    assert!(
        !d.path("cmp").exists(),
        "a refused comparison made its folder"
    );
}

#[test]
fn an_output_through_a_dangling_link_is_checked_where_it_leads_before_the_run() {
    // The link's target directory does not exist: refused at once, naming the option,
    // as a missing directory given plainly is (it was refused only when the result was
    // written, after the run).
    let d = TempDir::new("dangling");
    std::os::unix::fs::symlink("missing-dir/t.csv", d.path("d.csv")).unwrap();
    for option in ["-o", "--trajectory"] {
        let args = [
            "generate", "-n", "300", "-s", "8", "--method", "paper", "--steps", "3000", "-q",
            option, "d.csv",
        ];
        refused(&d.0, &args, "does not exist");
        let o = bin().current_dir(&d.0).args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(option) && err.contains("missing-dir"), "{err}");
    }
}
