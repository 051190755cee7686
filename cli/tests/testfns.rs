//! The eight test integrands of eq. 49: zero integrals, unit second moments, the midpoint
//! rule's convergence on the smooth ones, F8 by hand, and the integration report.

use stillpoint::quality::integrands::{f8_step, integrate, TestFunction};
use stillpoint::PointSet;
use stillpoint_paper::uq::gauss_legendre;

mod common;
use common::random_set;

/// ∫_a^b g by `panels` Gauss–Legendre panels of 20 nodes.
fn quad(g: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let (x, w) = gauss_legendre(20).unwrap();
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let c = a + (p as f64 + 0.5) * h;
        for (xi, wi) in x.iter().zip(&w) {
            sum += 0.5 * h * wi * g(c + 0.5 * h * xi);
        }
    }
    sum
}

#[test]
fn every_function_has_mean_zero_under_random_sampling() {
    let n = 200_000;
    for (k, s) in [1usize, 2, 3, 5, 10].into_iter().enumerate() {
        let rep = integrate(&random_set(n, s, 11 + k as u64)).unwrap();
        for f in TestFunction::all() {
            match f.variance(s) {
                Some(var) => {
                    let est = rep.estimate(f).unwrap();
                    let se = (var / n as f64).sqrt();
                    assert!(est.abs() < 5.0 * se, "{} s={s}: {est} vs SE {se}", f.name());
                }
                None => {
                    assert_eq!((f, s), (TestFunction::F8, 1));
                    assert_eq!(rep.estimate(f), None);
                }
            }
        }
    }
}

#[test]
fn product_factors_have_zero_mean_and_unit_square() {
    for f in [
        TestFunction::F4,
        TestFunction::F5,
        TestFunction::F6,
        TestFunction::F7,
    ] {
        let g = |t: f64| f.factor(t).unwrap();
        // Split at 0.5, where F4 jumps and F5 is steepest.
        let mean = quad(g, 0.0, 0.5, 64) + quad(g, 0.5, 1.0, 64);
        let sq = quad(|t| g(t) * g(t), 0.0, 0.5, 64) + quad(|t| g(t) * g(t), 0.5, 1.0, 64);
        assert!(mean.abs() < 1e-10, "{}: ∫g = {mean}", f.name());
        assert!((sq - 1.0).abs() < 1e-10, "{}: ∫g² = {sq}", f.name());
    }
    for f in [
        TestFunction::F1,
        TestFunction::F2,
        TestFunction::F3,
        TestFunction::F8,
    ] {
        assert_eq!(f.factor(0.3), None);
    }
}

#[test]
fn sum_forms_have_unit_second_moment() {
    // F = c Σ h(x_j) with ∫h = 0, so ∫F² = c² s ∫h²; check c² ∫h² = 1/s for s = 1.
    let one = |f: TestFunction, x: f64| f.eval(&[x]).unwrap();
    let f1 = quad(|x| one(TestFunction::F1, x).powi(2), 0.0, 1.0, 4);
    let f2 = quad(|x| one(TestFunction::F2, x).powi(2), 0.0, 1.0, 4);
    // √x has an unbounded derivative at 0: substitute x = t², dx = 2t dt.
    let f3 = quad(
        |t| one(TestFunction::F3, t * t).powi(2) * 2.0 * t,
        0.0,
        1.0,
        4,
    );
    let m3 = quad(|t| one(TestFunction::F3, t * t) * 2.0 * t, 0.0, 1.0, 4);
    for (name, v) in [("F1", f1), ("F2", f2), ("F3", f3)] {
        assert!((v - 1.0).abs() < 1e-12, "{name}: {v}");
    }
    assert!(m3.abs() < 1e-12);
    // F8's step: ∫f = 1/6 − 1/2 + 1/3 = 0 and ∫f² = 1 by segment lengths.
    assert_eq!(f8_step(0.1) + f8_step(0.9), 2);
    assert_eq!(f8_step(0.5), -1);
}

#[test]
fn second_moments_are_one_by_monte_carlo() {
    let n = 400_000;
    let s = 3;
    let pts = random_set(n, s, 5);
    for f in TestFunction::all() {
        let vals: Vec<f64> = pts.rows().map(|x| f.eval(x).unwrap().powi(2)).collect();
        let m = vals.iter().sum::<f64>() / n as f64;
        let sd = (vals.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        let se = sd / (n as f64).sqrt();
        let exact = f.variance(s).unwrap();
        assert!(
            (m - exact).abs() < 5.0 * se + 1e-12,
            "{}: {m} ± {se}",
            f.name()
        );
    }
}

fn midpoint_grid(m: usize, s: usize) -> PointSet {
    let total = m.pow(s as u32);
    let mut data = Vec::with_capacity(total * s);
    for idx in 0..total {
        let mut r = idx;
        for _ in 0..s {
            data.push(((r % m) as f64 + 0.5) / m as f64);
            r /= m;
        }
    }
    PointSet::new(total, s, data).unwrap()
}

#[test]
fn midpoint_grid_errors_shrink_at_the_expected_rates() {
    let s = 2;
    let est = |m: usize, f: TestFunction| {
        integrate(&midpoint_grid(m, s))
            .unwrap()
            .estimate(f)
            .unwrap()
    };
    // F1 is linear: the midpoint rule is exact.
    assert!(est(16, TestFunction::F1).abs() < 1e-14);
    // F2: Σ over midpoints of x² misses −h²/12 per axis, exactly.
    for m in [10usize, 20, 40] {
        let h = 1.0 / m as f64;
        let exact = (45.0f64 / (4.0 * s as f64)).sqrt() * s as f64 * (-h * h / 12.0);
        assert!((est(m, TestFunction::F2) - exact).abs() < 1e-13, "m={m}");
    }
    let r2 = est(20, TestFunction::F2) / est(40, TestFunction::F2);
    assert!((r2 - 4.0).abs() < 1e-8, "F2 ratio {r2}");
    // F3: √x's singular derivative at 0 makes the midpoint error O(h^{3/2}), ratio 2^{3/2}.
    let r3 = est(40, TestFunction::F3) / est(80, TestFunction::F3);
    assert!((r3 - 2f64.powf(1.5)).abs() < 0.1, "F3 ratio {r3}");
}

#[test]
fn f8_by_hand() {
    let f8 = |x: &[f64]| TestFunction::F8.eval(x);
    let third = (1.0f64 / 3.0).sqrt(); // √(2/(3·2))
                                       // f = (+1, −1, +1): pairs −1 + 1 − 1 = −1.
    assert!((f8(&[0.1, 0.5, 0.9]).unwrap() + third).abs() < 1e-15);
    // Edges give 0 factors: f = (0, −1, +1) → pairs 0 + 0 − 1.
    assert!((f8(&[1.0 / 6.0, 0.5, 0.9]).unwrap() + third).abs() < 1e-15);
    // f = (0, 0, −1) → 0.
    assert_eq!(f8(&[4.0 / 6.0, 1.0 / 6.0, 0.3]).unwrap(), 0.0);
    // f = (+1, +1, +1) → 3 pairs.
    assert!((f8(&[0.0, 1.0, 0.7]).unwrap() - 3.0 * third).abs() < 1e-15);
    // s = 2: the scale is 1.
    assert_eq!(f8(&[0.0, 1.0]), Some(1.0));
    assert_eq!(f8(&[0.2, 0.5]), Some(1.0));
    assert_eq!(f8(&[0.1, 0.3]), Some(-1.0));
    assert_eq!(f8(&[2.0 / 3.0, 0.3]), Some(0.0));
    // Just inside and outside the edges.
    assert_eq!(f8_step(1.0 / 6.0 + 1e-16), -1);
    assert_eq!(f8_step(1.0 / 6.0 - 1e-16), 1);
    assert_eq!(f8_step(4.0 / 6.0 + 1e-15), 1);
    // s = 1: no pair, not defined.
    assert_eq!(f8(&[0.3]), None);
    assert_eq!(TestFunction::F8.variance(1), None);
    assert!(!TestFunction::F8.is_defined(1));
}

#[test]
fn f4_f5_f6_f7_values() {
    assert_eq!(TestFunction::F4.eval(&[0.2, 0.9]), Some(-1.0));
    assert_eq!(TestFunction::F4.eval(&[0.2, 0.5]), Some(0.0));
    assert_eq!(TestFunction::F5.eval(&[0.5]), Some(0.0));
    // The paper's exponential form at an interior point.
    let x = 0.61;
    let e15 = 15f64.exp();
    let e = (30.0 * x - 15.0f64).exp();
    let paper = ((15.0 * e15 + 15.0) / (13.0 * e15 + 17.0)).sqrt() * (e - 1.0) / (e + 1.0);
    assert!((TestFunction::F5.eval(&[x]).unwrap() - paper).abs() < 1e-14);
    // Extremes stay finite.
    assert!(TestFunction::F5.eval(&[0.0, 1.0]).unwrap().is_finite());
    let u = 0.3f64 - 0.5;
    let f6 = -2.4 * 7f64.sqrt() * u + 8.0 * 7f64.sqrt() * u.powi(3);
    assert!((TestFunction::F6.eval(&[0.3]).unwrap() - f6).abs() < 1e-15);
    let f7 = 2.0 * 3f64.sqrt() * (0.8 - 0.5) * 2.0 * 3f64.sqrt() * (0.1 - 0.5);
    assert!((TestFunction::F7.eval(&[0.8, 0.1]).unwrap() - f7).abs() < 1e-15);
}

#[test]
fn names_formulas_and_undefined_inputs() {
    let names: Vec<&str> = TestFunction::all().iter().map(|f| f.name()).collect();
    assert_eq!(names, ["F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8"]);
    for f in TestFunction::all() {
        assert!(!f.formula().is_empty());
        assert_eq!(f.eval(&[]), None);
        assert_eq!(f.eval(&[0.5, f64::NAN]), None);
        assert_eq!(f.eval(&[0.5, 1.5]), None);
        assert_eq!(f.eval(&[-0.1, 0.5]), None);
        assert_eq!(f.variance(0), None);
        assert_eq!(f.variance(4), Some(1.0));
    }
}

#[test]
fn report_rows_and_refusals() {
    let pts = PointSet::from_rows(&[[0.25], [0.75]]).unwrap();
    let rep = integrate(&pts).unwrap();
    assert_eq!((rep.n, rep.s), (2, 1));
    let rows = rep.rows();
    assert_eq!(rows.len(), 8);
    assert_eq!(rows[0].name, "F1");
    // Symmetric points: every odd function integrates to 0 exactly.
    for r in &rows[..7] {
        if r.name != "F2" && r.name != "F3" {
            assert_eq!(r.estimate, Some(0.0), "{}", r.name);
        }
        assert_eq!(r.abs_error, r.estimate.map(f64::abs));
    }
    assert_eq!(rows[7].estimate, None);
    assert_eq!(rows[7].abs_error, None);

    let bad = PointSet::from_rows(&[[0.25, 1.25]]).unwrap();
    let e = integrate(&bad).unwrap_err().to_string();
    assert!(
        e.contains("point 1, coordinate 2") && e.contains("[0, 1]"),
        "{e}"
    );
}

#[test]
fn integration_does_not_depend_on_threads() {
    let pts = random_set(30_000, 4, 3);
    let run = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| integrate(&pts).unwrap())
    };
    let (a, b) = (run(1), run(2));
    for (x, y) in a.estimates.iter().zip(&b.estimates) {
        assert_eq!(x.map(f64::to_bits), y.map(f64::to_bits));
    }
}
