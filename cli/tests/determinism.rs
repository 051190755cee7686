//! Same seed, same bytes: every command gives the same output with one worker thread and
//! with two (`--threads` or `RAYON_NUM_THREADS`). Wall times, which no run can repeat, are
//! removed before comparing; everything else is compared byte for byte.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

mod common;
use common::tmpdir;

/// Runs the command with `threads` worker threads and insists on success.
fn run(threads: usize, args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .arg("--threads")
        .arg(threads.to_string())
        .args(args)
        .output()
        .expect("run stillpoint");
    assert!(
        o.status.success(),
        "{args:?} with {threads} thread(s): {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Drops what measures time (keys about seconds, times or threads; the time column of
/// curves) so that two runs can be compared.
fn strip_times(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, _| {
                let k = k.to_ascii_lowercase();
                !(k.contains("second") || k.contains("time") || k.contains("thread"))
            });
            if let Some(Value::Array(curve)) = map.get_mut("curve") {
                for point in curve {
                    if let Value::Array(p) = point {
                        if !p.is_empty() {
                            p.remove(0);
                        }
                    }
                }
            }
            map.values_mut().for_each(strip_times);
        }
        Value::Array(items) => items.iter_mut().for_each(strip_times),
        _ => {}
    }
}

/// Replaces `dir` inside every string by `DIR`: the two runs write to different places.
fn strip_dir(v: &mut Value, dir: &Path) {
    let dir = dir.to_str().unwrap();
    match v {
        Value::String(s) => *s = s.replace(dir, "DIR"),
        Value::Object(map) => map.values_mut().for_each(|x| strip_dir(x, Path::new(dir))),
        Value::Array(items) => items.iter_mut().for_each(|x| strip_dir(x, Path::new(dir))),
        _ => {}
    }
}

/// The JSON in `bytes` without times and with `dir` replaced by `DIR`.
fn normalised(bytes: &[u8], what: &str, dir: &Path) -> Value {
    let mut v = json_without_times(bytes, what);
    strip_dir(&mut v, dir);
    v
}

fn json_without_times(bytes: &[u8], what: &str) -> Value {
    let mut v: Value = serde_json::from_slice(bytes).unwrap_or_else(|e| {
        panic!(
            "{what} is not JSON ({e}): {}",
            String::from_utf8_lossy(bytes)
        )
    });
    strip_times(&mut v);
    v
}

/// Runs `args(dir)` once per thread count, each in its own directory, and returns the
/// directories with the outputs.
fn in_both(name: &str, args: impl Fn(&Path) -> Vec<String>) -> [(PathBuf, Output); 2] {
    let base = tmpdir(name);
    [1, 2].map(|t| {
        let d = base.join(format!("t{t}"));
        std::fs::create_dir_all(&d).unwrap();
        let a = args(&d);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let o = run(t, &a);
        (d, o)
    })
}

fn p(d: &Path, name: &str) -> String {
    d.join(name).to_str().unwrap().to_string()
}

fn same_file(a: &Path, b: &Path, name: &str) {
    let (x, y) = (std::fs::read(a.join(name)), std::fs::read(b.join(name)));
    let (x, y) = (
        x.unwrap_or_else(|e| panic!("{name}: {e}")),
        y.unwrap_or_else(|e| panic!("{name}: {e}")),
    );
    assert!(x == y, "{name} differs between 1 and 2 threads");
}

fn same_json_file(a: &Path, b: &Path, name: &str) {
    let x = normalised(&std::fs::read(a.join(name)).unwrap(), name, a);
    let y = normalised(&std::fs::read(b.join(name)).unwrap(), name, b);
    assert!(
        x == y,
        "{name} differs between 1 and 2 threads (times removed)"
    );
}

fn owned(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

#[test]
fn generate_in_every_mode_gives_the_same_bytes() {
    let modes: [(&str, &[&str]); 8] = [
        // The default from 500 points on: the lattice's shift search runs in parallel.
        ("lattice", &["-n", "1009", "-s", "6", "--seed", "3"]),
        (
            "cube",
            &[
                "-n", "90", "-s", "3", "--steps", "60", "--init", "random", "--seed", "4",
            ],
        ),
        (
            "cube, full precision",
            &[
                "-n",
                "90",
                "-s",
                "3",
                "--steps",
                "60",
                "--precision",
                "full",
            ],
        ),
        (
            "lbfgs",
            &[
                "-n",
                "60",
                "-s",
                "2",
                "--steps",
                "25",
                "--integrator",
                "lbfgs",
                "--energy",
                "md",
            ],
        ),
        (
            "polish",
            &["-n", "60", "-s", "2", "--steps", "40", "--polish", "md"],
        ),
        (
            "e-inf",
            &[
                "-n", "50", "-s", "2", "--steps", "40", "--energy", "e-inf", "--q", "E",
            ],
        ),
        (
            "shape",
            &["--shape", "ball:1", "-s", "3", "-n", "40", "--steps", "150"],
        ),
        (
            "region",
            &[
                "--region",
                "|x| + 2*|y| - 5",
                "--box",
                "-5.5,5.5,-3,3",
                "-n",
                "20",
                "--steps",
                "80",
            ],
        ),
    ];
    for (mode, extra) in modes {
        let [(a, oa), (b, ob)] = in_both(&format!("generate-{mode}"), |d| {
            let mut v = owned(&["generate"]);
            v.extend(owned(extra));
            v.extend([
                "-o".into(),
                p(d, "points.csv"),
                "--trajectory".into(),
                p(d, "trajectory.json"),
                "--json".into(),
                "-q".into(),
            ]);
            v
        });
        same_file(&a, &b, "points.csv");
        same_json_file(&a, &b, "trajectory.json");
        assert_eq!(
            json_without_times(&oa.stdout, mode),
            json_without_times(&ob.stdout, mode),
            "{mode}: --json report differs"
        );
    }
}

#[test]
fn rayon_num_threads_gives_the_same_bytes_as_threads() {
    let d = tmpdir("rayon-env");
    let mut outputs = Vec::new();
    for t in ["1", "2"] {
        let f = d.join(format!("p{t}.npy"));
        let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .env("RAYON_NUM_THREADS", t)
            .args([
                "generate", "-n", "80", "-s", "4", "--steps", "50", "-q", "-o",
            ])
            .arg(&f)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        outputs.push(std::fs::read(&f).unwrap());
    }
    assert_eq!(outputs[0], outputs[1]);
}

#[test]
fn every_baseline_gives_the_same_bytes() {
    for b in stillpoint::sequences::Baseline::all() {
        let name = b.name();
        let [(a, oa), (c, oc)] = in_both(&format!("baseline-{name}"), |d| {
            owned(&["baseline", name, "-n", "64", "-s", "5", "--seed", "3", "-o"])
                .into_iter()
                .chain([p(d, "points.tsv"), "--json".into()])
                .collect()
        });
        same_file(&a, &c, "points.tsv");
        assert_eq!(
            normalised(&oa.stdout, name, &a),
            normalised(&oc.stdout, name, &c),
            "baseline {name}: --json differs"
        );
    }
}

#[test]
fn eval_integrate_and_plot_give_the_same_bytes() {
    let d = tmpdir("eval");
    let points = d.join("points.json");
    let traj = d.join("trajectory.json");
    run(
        2,
        &[
            "generate",
            "-n",
            "70",
            "-s",
            "4",
            "--steps",
            "30",
            "-q",
            "-o",
            points.to_str().unwrap(),
            "--trajectory",
            traj.to_str().unwrap(),
        ],
    );
    let file = points.to_str().unwrap();
    for cmd in ["eval", "integrate"] {
        let a = run(1, &[cmd, file, "--json"]).stdout;
        let b = run(2, &[cmd, file, "--json"]).stdout;
        assert!(!a.is_empty());
        assert_eq!(a, b, "{cmd} --json differs");
    }
    let [(a, _), (b, _)] = in_both("plot-matrix", |out| {
        owned(&["plot", file, "-o"])
            .into_iter()
            .chain([p(out, "matrix.png")])
            .collect()
    });
    same_file(&a, &b, "matrix.png");
    let [(a, _), (b, _)] = in_both("plot-trajectory", |out| {
        owned(&["plot", "--trajectory", traj.to_str().unwrap(), "-o"])
            .into_iter()
            .chain([p(out, "trajectory.png")])
            .collect()
    });
    same_file(&a, &b, "trajectory.png");
    // A region's scatter plot with its boundary, in both picture formats.
    let region_points = d.join("region.csv");
    run(
        2,
        &[
            "generate",
            "--shape",
            "ball:1",
            "-s",
            "2",
            "-n",
            "30",
            "--steps",
            "50",
            "-q",
            "-o",
            region_points.to_str().unwrap(),
        ],
    );
    for pic in ["region.png", "region.svg"] {
        let [(a, _), (b, _)] = in_both(&format!("plot-{pic}"), |out| {
            owned(&[
                "plot",
                region_points.to_str().unwrap(),
                "--shape",
                "ball:1",
                "-o",
            ])
            .into_iter()
            .chain([p(out, pic)])
            .collect()
        });
        same_file(&a, &b, pic);
    }
}

#[test]
fn compare_quick_gives_the_same_results() {
    let [(a, _), (b, _)] = in_both("compare", |d| {
        owned(&[
            "compare",
            "--quick",
            "--out",
            d.join("cmp").to_str().unwrap(),
        ])
    });
    let (a, b) = (a.join("cmp"), b.join("cmp"));
    same_json_file(&a, &b, "comparison.json");
    // The Markdown table without its last column, the wall time.
    let table = |d: &Path| -> Vec<String> {
        std::fs::read_to_string(d.join("comparison.md"))
            .unwrap()
            .lines()
            .map(|l| match l.trim_end_matches('|').rsplit_once('|') {
                Some((rest, _)) if l.starts_with('|') => rest.to_string(),
                _ => l.to_string(),
            })
            .collect()
    };
    assert_eq!(table(&a), table(&b));
}

#[test]
fn studies_quick_give_the_same_results() {
    for study in ["correlation", "catalog"] {
        let [(a, _), (b, _)] = in_both(&format!("study-{study}"), |d| {
            owned(&[
                "study",
                study,
                "--quick",
                "-q",
                "--out",
                d.to_str().unwrap(),
            ])
        });
        let (a, b) = (a.join(study), b.join(study));
        let mut names: Vec<String> = std::fs::read_dir(&a)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert!(names.iter().any(|n| n.ends_with(".json")), "{names:?}");
        for name in &names {
            if name.ends_with(".json") {
                same_json_file(&a, &b, name);
            } else if name.ends_with(".csv") || name.ends_with(".png") {
                same_file(&a, &b, name);
            }
        }
        if study == "catalog" {
            assert!(names.iter().any(|n| n.ends_with(".csv")), "{names:?}");
        }
    }
}
