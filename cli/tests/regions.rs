//! Point sets in regions: every point inside, the boundary-aware energy falls, runs are
//! reproducible, and bad regions are refused.

use std::sync::Arc;
use stillpoint::config::{EnergyKind, GenerateConfig, Init};
use stillpoint::energies::boundary::UEpG;
use stillpoint::energies::region::paper_region;
use stillpoint::energies::shapes::Ball;
use stillpoint::energies::{Domain, Energy};
use stillpoint::pipeline::run_config;

mod common;
use common::{bin, doc_lines, shell_words, tmpdir};

fn g4(x: &[f64]) -> f64 {
    x[0].abs() + 2.0 * x[1].abs() - 5.0
}

#[test]
fn paper_region_points_stay_inside_and_the_energy_falls() {
    let domain: Arc<dyn Domain> = Arc::new(paper_region(4).unwrap());
    let mut cfg = GenerateConfig::in_region(domain.clone(), 40);
    cfg.steps = 3000;
    let r = run_config(&cfg, |_| {}).unwrap();
    assert!(r.output.points.rows().all(|x| g4(x) <= 0.0));
    assert!(r.start.rows().all(|x| g4(x) <= 0.0));
    assert!(
        r.reduction().unwrap() > 0.5,
        "U_E,inf,g {} -> {}",
        r.region_metrics().unwrap().0.energy_e_inf_g,
        r.region_metrics().unwrap().1.energy_e_inf_g
    );
    assert!(
        r.region_metrics().unwrap().1.min_distance
            > 2.0 * r.region_metrics().unwrap().0.min_distance
    );
    assert!(
        r.region_metrics().unwrap().1.min_boundary_distance
            > r.region_metrics().unwrap().0.min_boundary_distance
    );
}

#[test]
fn ball_in_three_dimensions_and_the_smooth_energy() {
    let ball: Arc<dyn Domain> = Arc::new(Ball::new(vec![0.5, -1.0, 2.0], 1.5).unwrap());
    let mut cfg = GenerateConfig::in_region(ball.clone(), 30);
    cfg.energy = EnergyKind::EpG(6.0);
    cfg.init = Init::Halton;
    cfg.steps = 1500;
    let r = run_config(&cfg, |_| {}).unwrap();
    assert!(r.output.points.rows().all(|x| ball.contains(x)));
    let e = UEpG::new(ball, 6.0).unwrap();
    assert!(e.value(&r.output.points) < e.value(&r.start));
}

#[test]
fn same_bits_for_one_and_two_threads() {
    let domain: Arc<dyn Domain> = Arc::new(paper_region(1).unwrap());
    let mut cfg = GenerateConfig::in_region(domain, 25);
    cfg.steps = 400;
    let run = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| run_config(&cfg, |_| {}).unwrap().output.points)
    };
    let (a, b) = (run(1), run(2));
    let bits =
        |p: &stillpoint::PointSet| p.as_slice().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b));
}

#[test]
fn cli_region_run_writes_points_inside_and_a_picture() {
    let d = tmpdir("ok");
    let f = d.join("g4.csv");
    let png = d.join("g4.png");
    let o = bin()
        .args([
            "generate",
            "--region",
            "|x| + 2*|y| - 5",
            "--box",
            "-5.5,5.5,-3,3",
            "-n",
            "30",
            "--steps",
            "800",
            "-q",
            "--json",
            "-o",
            f.to_str().unwrap(),
            "--plot",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["energy_e_inf_g_reduction"].as_f64().unwrap() > 0.3, "{v}");
    let pts = stillpoint::io::read_points(&f).unwrap();
    assert_eq!(pts.n(), 30);
    assert!(pts.rows().all(|x| g4(x) <= 0.0));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    // A built-in shape.
    let o = bin()
        .args([
            "generate",
            "--shape",
            "ball:2@1,1,1",
            "-n",
            "20",
            "--steps",
            "300",
            "-q",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = String::from_utf8_lossy(&o.stdout);
    let p = stillpoint::io::parse_text(&csv, "stdout").unwrap();
    assert_eq!((p.n(), p.s()), (20, 3));
    assert!(p
        .rows()
        .all(|x| x.iter().map(|v| (v - 1.0) * (v - 1.0)).sum::<f64>() <= 4.0));
}

#[test]
fn bad_regions_are_refused_and_write_nothing() {
    let d = tmpdir("bad");
    let f = d.join("out.csv");
    let o_s = f.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--region", "x^2 + y^2 + 1", "--box", "-1,1,-1,1"],
            "no point with g ≤ 0",
        ),
        (vec!["--region", "x + w", "--box", "-1,1,-1,1"], "w"),
        (vec!["--region", "x +* 2", "--box", "-1,1,-1,1"], "^"),
        (
            vec!["--region", "sqrt(-1) + x", "--box", "-1,1,-1,1"],
            "NaN",
        ),
        (vec!["--region", "x^2 + y^2 - 1"], "--box"),
        (vec!["--region", "x^2 + y^2 - 1", "--box", "1,0,-1,1"], "LO"),
        (
            vec!["--region", "x^2 + y^2 - 1", "--box", "-1,1,-1,a"],
            "--box",
        ),
        (
            vec!["--region", "x^2 + y^2 - 1", "--box", "-1,1,-1,1", "-s", "3"],
            "-s",
        ),
        (
            vec![
                "--region",
                "x^2 + y^2 - 1",
                "--box",
                "-1,1,-1,1",
                "--energy",
                "uqp",
            ],
            "energy",
        ),
        (vec!["--shape", "ball:-1", "-s", "2"], "radius"),
        (vec!["--shape", "ball:1"], "-s"),
        (vec!["--shape", "cone:1"], "--shape"),
        (vec!["--shape", "ellipsoid:1,0"], "semi"),
        (vec!["--energy", "e-inf-g", "-s", "2"], "energy"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["generate", "-n", "10", "-o", o_s, "-q"];
        all.extend(args.iter());
        let o = bin().args(&all).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(
            err.contains(needle),
            "{args:?}: {err:?} does not mention {needle:?}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!f.exists(), "{args:?} wrote a file");
    }
}

/// The guide's integration-in-a-region commands (docs/regions.md), run as written: the
/// design is inside its linear constraint and `eval --json` finds it closer to uniform on
/// the region than as many uniform points.
#[test]
fn guide_region_integration_example_runs() {
    let lines = doc_lines("docs/regions.md", |l| {
        l.starts_with("stillpoint ") && l.contains("design.csv")
    });
    assert_eq!(lines.len(), 2, "{lines:?}");
    let dir = tmpdir("guide_region_integration");
    // The quoted expression is one argument.
    let words = |line: &str| shell_words(line.trim_start_matches("stillpoint "), '"');
    let generate = bin()
        .current_dir(&dir)
        .args(words(&lines[0]))
        .arg("-q")
        .output()
        .unwrap();
    assert!(
        generate.status.success(),
        "{}",
        String::from_utf8_lossy(&generate.stderr)
    );
    let design = stillpoint::io::read_points(&dir.join("design.csv")).unwrap();
    assert_eq!((design.n(), design.s()), (64, 3));
    for x in design.rows() {
        assert!(x.iter().all(|v| (0.0..=1.0).contains(v)), "{x:?}");
        assert!(x[0] + 2.0 * x[1] + x[2] <= 1.5, "{x:?}");
    }
    let eval = |file: &str| -> serde_json::Value {
        let mut args = words(&lines[1]);
        args[1] = file.to_string();
        let o = bin()
            .current_dir(&dir)
            .args(args)
            .arg("--json")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let ours = eval("design.csv");
    assert_eq!(ours["fraction_inside"], 1.0);
    let domain = stillpoint::plan::space::RegionSpec {
        expression: Some("x1 + 2*x2 + x3 - 1.5"),
        bbox: Some(&[0.0, 1.0, 0.0, 1.0, 0.0, 1.0]),
        shape: None,
        s: None,
    }
    .domain(&|n| n.to_string())
    .unwrap();
    let uniform = domain.sample(64, 9).unwrap();
    stillpoint::io::write_points(&dir.join("uniform.csv"), &uniform, &serde_json::Value::Null)
        .unwrap();
    let theirs = eval("uniform.csv");
    assert!(
        ours["energy_distance"].as_f64().unwrap() < theirs["energy_distance"].as_f64().unwrap(),
        "{ours} {theirs}"
    );
}
