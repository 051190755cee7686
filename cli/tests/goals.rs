//! The goals of `generate`: the integration default is stratified and below scrambled
//! Sobol' in discrepancy, space-filling is stratified with a larger minimum distance than
//! a maximin Latin hypercube, `--method paper` is the paper's configuration, and the
//! randomisations are unbiased.

mod common;

use common::{bin, TempDir};
use stillpoint::config::{GenerateConfig, Goal};
use stillpoint::energies::discrepancy::DiscrepancyKind;
use stillpoint::pipeline::{self as run};
use stillpoint::post::randomize::randomize;
use stillpoint::post::randomize::Randomize;
use stillpoint::quality::metrics::{self, Metrics};
use stillpoint::quality::stratification::is_stratified;
use stillpoint::quality::target::Target;
use stillpoint::sequences;
use stillpoint::PointSet;

fn integration(n: usize, s: usize, seed: u64) -> PointSet {
    let mut cfg = GenerateConfig::for_goal(n, s, Goal::Integration(Target::blend()));
    cfg.seed = seed;
    run::run_config(&cfg, |_| {}).unwrap().output.points
}

#[test]
fn the_default_is_stratified_including_small_and_odd_n() {
    for (n, s) in [(1, 3), (2, 5), (3, 7), (10, 2), (37, 3), (64, 4), (100, 6)] {
        let p = integration(n, s, 0);
        assert_eq!((p.n(), p.s()), (n, s));
        assert!(is_stratified(&p), "n = {n}, s = {s}");
        // Every column's mean is ½, so linear integrands are exact.
        for m in p.mean() {
            assert!((m - 0.5).abs() < 1e-12, "n = {n}, s = {s}: mean {m}");
        }
    }
}

#[test]
fn the_default_is_below_the_scrambled_sobol_mean_in_three_discrepancies() {
    for (n, s) in [(64, 2), (100, 3), (128, 5)] {
        let ours = Metrics::compute(&integration(n, s, 0));
        let mut mean = [0.0; 3];
        let scrambles = 16;
        for seed in 0..scrambles {
            let m = Metrics::compute(&sequences::sobol_scrambled(n, s, 100 + seed).unwrap());
            for (acc, v) in mean
                .iter_mut()
                .zip([m.modified_l2, m.star_l2, m.centered_l2])
            {
                *acc += v / scrambles as f64;
            }
        }
        let got = [ours.modified_l2, ours.star_l2, ours.centered_l2];
        for (k, name) in ["D_MD", "D_L2*", "CD"].iter().enumerate() {
            assert!(
                got[k] < mean[k],
                "n = {n}, s = {s}: {name} {} vs Sobol' mean {}",
                got[k],
                mean[k]
            );
        }
    }
}

#[test]
fn a_single_target_is_lowered_below_its_stratified_start() {
    let cfg = GenerateConfig::for_goal(
        50,
        3,
        Goal::Integration(Target::single(DiscrepancyKind::CenteredL2)),
    );
    let r = run::run_config(&cfg, |_| {}).unwrap();
    let (start, result) = r.cube_metrics().unwrap();
    assert!(result.centered_l2 < start.centered_l2);
    assert!(is_stratified(&r.start) && is_stratified(&r.output.points));
}

#[test]
fn space_filling_is_stratified_and_at_least_the_maximin_lhs() {
    for (n, s) in [(30, 2), (60, 4)] {
        let cfg = GenerateConfig::for_goal(n, s, Goal::SpaceFilling);
        let p = run::run_config(&cfg, |_| {}).unwrap().output.points;
        assert!(is_stratified(&p));
        let lhs = sequences::lhs_maximin(n, s, 0).unwrap();
        assert!(metrics::min_distance_euclidean(&p) >= metrics::min_distance_euclidean(&lhs));
    }
}

#[test]
fn method_paper_is_the_paper_configuration() {
    // The command line's `--method paper` and the library's paper defaults give the
    // same bytes (and the default is not the paper's any more).
    let d = TempDir::new("paper");
    let f = d.0.join("p.npy");
    let o = bin()
        .args([
            "generate", "-n", "40", "-s", "3", "--method", "paper", "-q", "-o",
        ])
        .arg(&f)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = stillpoint::io::read_points(&f).unwrap();
    let lib = run::run_config(&GenerateConfig::new(40, 3), |_| {})
        .unwrap()
        .output
        .points;
    assert_eq!(file.as_slice(), lib.as_slice());
    assert_ne!(lib.as_slice(), integration(40, 3, 0).as_slice());
}

/// `generate -n 10 -s 2` with `args` fails with a message containing `needle`.
fn refused(args: &[&str], needle: &str) {
    let o = bin()
        .args(["generate", "-n", "10", "-s", "2", "-q"])
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} was accepted");
    assert!(err.contains(needle), "{args:?}: {err}");
}

#[test]
fn goal_options_are_checked() {
    for (args, needle) in [
        (&["--goal", "integration", "--energy", "md"][..], "--energy"),
        (&["--goal", "integration", "--steps", "9"][..], "--steps"),
        (&["--target", "md", "--method", "paper"][..], "--target"),
        (&["--goal", "banana"][..], "--goal"),
        (&["--randomize", "sometimes"][..], "--randomize"),
        (
            &[
                "--goal",
                "integration",
                "--shape",
                "ball:1",
                "--target",
                "md",
            ][..],
            "no target in a region",
        ),
        (
            &["--goal", "integration", "--shape", "ball:1", "--randomize"][..],
            "no randomisation in a region",
        ),
    ] {
        refused(args, needle);
    }
}

#[test]
fn where_a_lattice_must_share_generators_the_randomised_set_is_the_descended_one() {
    use stillpoint::goals::integration::tent::tent_set;
    use stillpoint::report::TentDescent;
    // 32 points have 8 generators up to sign: 15 coordinates must share them.
    let dir = TempDir::new("tent-shared");
    let path = dir.path("x.csv");
    let o = bin()
        .args([
            "generate",
            "-n",
            "32",
            "-s",
            "15",
            "--randomize",
            "--seed",
            "5",
            "-o",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("coordinates share generators"), "{report}");
    let set = tent_set(32, 15).unwrap();
    assert!(matches!(
        set.descent,
        TentDescent::Descended { kept: true, .. }
    ));
    let written = stillpoint::io::read_points(&path).unwrap();
    let expected = randomize(&set.points, Randomize::Tent, 5);
    for (a, b) in written.as_slice().iter().zip(expected.as_slice()) {
        assert!((a - b).abs() <= 1e-15, "{a} vs {b}");
    }
    // Every draw stays stratified and in [0, 1).
    for seed in 0..50 {
        let q = randomize(&set.points, Randomize::Tent, seed);
        assert!(q.as_slice().iter().all(|v| (0.0..1.0).contains(v)));
        assert!(is_stratified(&q), "seed {seed}");
    }
}

#[test]
fn cell_randomisation_keeps_the_stratification_and_spreads_each_point_uniformly() {
    let p = integration(20, 3, 0);
    let reps = 2000;
    let mut hist = [0usize; 10];
    for seed in 0..reps {
        let q = randomize(&p, Randomize::Cells, seed);
        assert!(is_stratified(&q));
        hist[(q.as_slice()[0] * 10.0) as usize] += 1;
    }
    // The first coordinate of point 0 is uniform: each tenth gets about 200 of 2000.
    for (k, &h) in hist.iter().enumerate() {
        assert!((140..=260).contains(&h), "bin {k}: {h}");
    }
}

#[test]
fn randomised_replicates_average_to_the_integral_within_their_standard_error() {
    // f(x) = Π (1 + (x_k − ½)·sin(3 x_k)) + x_1 x_2 has a closed-form integral.
    let f = |x: &[f64]| -> f64 {
        x.iter()
            .map(|&v| 1.0 + (v - 0.5) * (3.0 * v).sin())
            .product::<f64>()
            + x[0] * x[1]
    };
    // ∫_0^1 (v − ½) sin 3v dv = (sin 3 − 3·cos 3·½ ... ) computed below by parts.
    let one = {
        let (a, b) = (3.0f64, 0.5f64);
        // ∫ (v − b) sin(a v) = −(v − b) cos(a v)/a + sin(a v)/a² on [0, 1]
        let at = |v: f64| -(v - b) * (a * v).cos() / a + (a * v).sin() / (a * a);
        1.0 + at(1.0) - at(0.0)
    };
    let exact = one.powi(3) + 0.25;
    let optimised = integration(64, 3, 0);
    let lattice = sequences::tent_lattice(64, 3).unwrap();
    for kind in [Randomize::Cells, Randomize::Shift, Randomize::Tent] {
        let p = if kind == Randomize::Tent {
            &lattice
        } else {
            &optimised
        };
        let reps = 64;
        let estimates: Vec<f64> = (0..reps)
            .map(|seed| {
                let q = randomize(p, kind, 1000 + seed);
                q.rows().map(f).sum::<f64>() / q.n() as f64
            })
            .collect();
        let mean = estimates.iter().sum::<f64>() / reps as f64;
        let var = estimates.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (reps - 1) as f64;
        let se = (var / reps as f64).sqrt();
        assert!(se > 0.0);
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "{kind:?}: {mean} vs {exact} (se {se})"
        );
    }
}

#[test]
fn tent_randomisation_spreads_each_point_uniformly_and_keeps_lattices_stratified() {
    for n in [2usize, 3, 16, 63, 64, 100, 101, 250] {
        let p = sequences::tent_lattice(n, 4).unwrap();
        // The lattice's columns are the n multiples of 1/n, each once.
        for k in 0..4 {
            let mut seen: Vec<u64> = p.rows().map(|r| (r[k] * n as f64).round() as u64).collect();
            seen.sort_unstable();
            assert_eq!(seen, (0..n as u64).collect::<Vec<_>>(), "n = {n}");
        }
        let reps = 400;
        let mut hist = [0usize; 10];
        for seed in 0..reps {
            let q = randomize(&p, Randomize::Tent, seed);
            assert!(q.as_slice().iter().all(|v| (0.0..1.0).contains(v)));
            assert!(is_stratified(&q), "n = {n}, seed {seed}");
            hist[(q.as_slice()[n / 2 * 4 + 1] * 10.0) as usize] += 1;
        }
        // One coordinate of one point is uniform over the seeds: 40 of 400 per tenth.
        for (k, &h) in hist.iter().enumerate() {
            assert!((16..=64).contains(&h), "n = {n}, bin {k}: {h}");
        }
    }
    // A coordinate exactly at ½ after the shift folds onto 1: it is kept below 1.
    let half = PointSet::new(1, 1, vec![0.5]).unwrap();
    for seed in 0..64 {
        assert!(randomize(&half, Randomize::Tent, seed).as_slice()[0] < 1.0);
    }
}

#[test]
fn a_bare_randomize_is_the_tent_lattice_randomised() {
    let dir = TempDir::new("tent");
    let run = |extra: &[&str], name: &str| -> (Vec<u8>, String) {
        let path = dir.path(name);
        let o = bin()
            .args(["generate", "-n", "50", "-s", "3", "--seed", "7", "-o"])
            .arg(&path)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (
            std::fs::read(&path).unwrap(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    let (bare, report) = run(&["--randomize"], "bare.csv");
    let (named, _) = run(&["--randomize", "tent"], "named.csv");
    assert_eq!(bare, named);
    assert!(
        report.contains("rank-1 lattice for the tent randomisation"),
        "{report}"
    );
    assert!(report.contains("tent transform"), "{report}");
    // The written set is the library's lattice randomised from the run's seed.
    let written = stillpoint::io::read_points(&dir.path("bare.csv")).unwrap();
    let expected = randomize(&sequences::tent_lattice(50, 3).unwrap(), Randomize::Tent, 7);
    for (a, b) in written.as_slice().iter().zip(expected.as_slice()) {
        assert!((a - b).abs() <= 1e-15, "{a} vs {b}");
    }
    for (args, needle) in [
        (&["--randomize", "--method", "paper"][..], "--randomize"),
        (
            &["--randomize", "tent", "--goal", "space-filling"][..],
            "--randomize",
        ),
        (&["--randomize", "--target", "md"][..], "--target"),
    ] {
        refused(args, needle);
    }
}
