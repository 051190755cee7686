//! Growing sets: `--extend` keeps the old points first and bit for bit, the union beats
//! the old points plus random or scrambled-Sobol' points, and extending stage by stage is
//! one `--nested` run.

mod common;

use common::{bin, TempDir};
use stillpoint::goals::integration::{extend_set, integration_set, nested_set};
use stillpoint::quality::effort::Effort;
use stillpoint::quality::metrics::Metrics;
use stillpoint::quality::stratification::is_stratified;
use stillpoint::quality::target::Target;
use stillpoint::sequences;
use stillpoint::PointSet;

fn union(old: &PointSet, new: &PointSet) -> PointSet {
    let mut data = old.as_slice().to_vec();
    data.extend_from_slice(new.as_slice());
    PointSet::new(old.n() + new.n(), old.s(), data).unwrap()
}

#[test]
fn the_union_keeps_the_old_points_and_beats_random_and_sobol_additions() {
    let target = Target::blend();
    let effort = Effort::default();
    for (n, m, s) in [(40, 20, 2), (64, 64, 3), (100, 50, 5)] {
        let (old, _) = integration_set(n, s, &target, 1, &effort).unwrap();
        let ext = extend_set(&old, m, &target, 1, &effort).unwrap();
        let u = &ext.points;
        assert_eq!(&u.as_slice()[..n * s], old.as_slice());
        assert!(u.check_unit_cube().is_ok());
        let ours = Metrics::compute(u);
        let reps = 16;
        let (mut random, mut sobol) = ([0.0; 2], [0.0; 2]);
        for seed in 0..reps {
            let r = Metrics::compute(&union(&old, &sequences::random(m, s, seed).unwrap()));
            let q = Metrics::compute(&union(
                &old,
                &sequences::sobol_scrambled(m, s, 50 + seed).unwrap(),
            ));
            random[0] += r.modified_l2 / reps as f64;
            random[1] += r.star_l2 / reps as f64;
            sobol[0] += q.modified_l2 / reps as f64;
            sobol[1] += q.star_l2 / reps as f64;
        }
        for (name, base) in [("random", random), ("Sobol'", sobol)] {
            assert!(
                ours.modified_l2 < base[0],
                "{n}+{m}, s = {s}: D_MD vs {name}"
            );
            assert!(ours.star_l2 < base[1], "{n}+{m}, s = {s}: D_L2* vs {name}");
        }
        // m a multiple of n on a stratified set: the union is stratified too.
        if m % n == 0 {
            assert!(ext.stratified && is_stratified(u));
        }
    }
}

#[test]
fn extending_by_nothing_returns_the_set() {
    let old = sequences::lhs(30, 3, 2).unwrap();
    let ext = extend_set(&old, 0, &Target::blend(), 0, &Effort::default()).unwrap();
    assert_eq!(ext.points.as_slice(), old.as_slice());
}

#[test]
fn extend_then_extend_on_the_command_line_is_one_nested_run() {
    let d = TempDir::new("nested");
    let path = |name: &str| d.0.join(name);
    let run = |args: &[&str]| {
        let o = bin().args(args).output().unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let (a, b, c) = (path("a.npy"), path("b.npy"), path("c.npy"));
    run(&[
        "generate",
        "-n",
        "24",
        "-s",
        "3",
        "--seed",
        "4",
        "-q",
        "-o",
        a.to_str().unwrap(),
    ]);
    run(&[
        "generate",
        "--extend",
        a.to_str().unwrap(),
        "-n",
        "24",
        "--seed",
        "4",
        "-q",
        "-o",
        b.to_str().unwrap(),
    ]);
    run(&[
        "generate",
        "--extend",
        b.to_str().unwrap(),
        "-n",
        "12",
        "--seed",
        "4",
        "-q",
        "-o",
        c.to_str().unwrap(),
    ]);
    let stepwise = stillpoint::io::read_points(&c).unwrap();
    let nested = nested_set(&[24, 48, 60], 3, &Target::blend(), 4, &Effort::default()).unwrap();
    assert_eq!(stepwise.as_slice(), nested.as_slice());
    let first = stillpoint::io::read_points(&a).unwrap();
    assert_eq!(
        &stepwise.as_slice()[..first.as_slice().len()],
        first.as_slice()
    );
    // The command line's --nested writes the same bytes.
    let n = path("n.npy");
    run(&[
        "generate",
        "--nested",
        "24,48,60",
        "-s",
        "3",
        "--seed",
        "4",
        "-q",
        "-o",
        n.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read(&n).unwrap(), std::fs::read(&c).unwrap());
}

#[test]
fn growing_options_are_checked() {
    let d = TempDir::new("checks");
    let a = d.0.join("a.csv");
    let o = bin()
        .args(["generate", "-n", "10", "-s", "2", "-q", "-o"])
        .arg(&a)
        .output()
        .unwrap();
    assert!(o.status.success());
    for (args, needle) in [
        (vec!["--extend", a.to_str().unwrap()], "-n M"),
        (
            vec![
                "--extend",
                a.to_str().unwrap(),
                "-n",
                "5",
                "--method",
                "paper",
            ],
            "--extend",
        ),
        (vec!["--nested", "10,5", "-s", "2"], "--nested"),
        (vec!["--nested", "10,x", "-s", "2"], "--nested"),
        (
            vec![
                "--extend",
                a.to_str().unwrap(),
                "-n",
                "5",
                "-o",
                a.to_str().unwrap(),
            ],
            "--extend",
        ),
    ] {
        let o = bin()
            .arg("generate")
            .args(&args)
            .arg("-q")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} was accepted");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn a_region_set_grows_with_its_old_points_fixed_and_every_point_inside() {
    let d = TempDir::new("region");
    let (a, b, pic) = (d.0.join("a.csv"), d.0.join("b.csv"), d.0.join("b.png"));
    let region = ["--shape", "ball:1", "-s", "2", "--steps", "300", "-q"];
    let o = bin()
        .args(["generate", "-n", "30"])
        .args(region)
        .arg("-o")
        .arg(&a)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = bin()
        .args(["generate", "-n", "15", "--extend"])
        .arg(&a)
        .args(region)
        .arg("-o")
        .arg(&b)
        .arg("--plot")
        .arg(&pic)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (old, union) = (
        stillpoint::io::read_points(&a).unwrap(),
        stillpoint::io::read_points(&b).unwrap(),
    );
    assert_eq!(union.n(), 45);
    assert_eq!(&union.as_slice()[..60], old.as_slice());
    for r in union.rows() {
        assert!(
            r[0] * r[0] + r[1] * r[1] <= 1.0 + 1e-12,
            "{r:?} outside the disc"
        );
    }
    // The new points keep away from the old ones: no new point sits on an old one.
    let min_new_to_old = union
        .rows()
        .skip(30)
        .flat_map(|p| {
            old.rows()
                .map(move |q| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt())
        })
        .fold(f64::INFINITY, f64::min);
    assert!(min_new_to_old > 0.05, "{min_new_to_old}");
    assert!(pic.exists());
}
