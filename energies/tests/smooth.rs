//! Checks of the smoothness-2 worst-case error ([`DiscrepancyKind::Smooth`]): its
//! gradient against central differences, its mean over random sets against the value the
//! kernel's integrals give, its value for one point written out by hand, and a rate no
//! discrepancy of smoothness 1 reaches.

use stillpoint_energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind, SMOOTH_WEIGHT};
use stillpoint_energies::{Energy, PointSet};

mod common;
use common::{fd_gradient, random_set, rel_err};

fn smooth() -> DiscrepancyEnergy {
    DiscrepancyEnergy::new(DiscrepancyKind::Smooth)
}

#[test]
fn gradient_matches_central_differences() {
    // The kernel is C¹ (B₄(|t|) has zero slope at 0), so differences converge even
    // across ties.
    for (n, s, seed) in [(2, 1, 1), (9, 3, 2), (40, 8, 3)] {
        let x = random_set(n, s, seed);
        let mut g = vec![0.0; n * s];
        smooth().value_and_gradient(&x, &mut g);
        let fd = fd_gradient(&smooth(), &x, 1e-6);
        assert!(rel_err(&g, &fd) < 1e-6, "n={n} s={s}: {}", rel_err(&g, &fd));
    }
}

#[test]
fn mean_over_random_sets_matches_the_kernel_integrals() {
    // For n independent uniform points, E e² = (∫K(x, x) dx − 1)/n, and in one coordinate
    // ∫ 1 + γ(B₁(x)² + B₂(x)²/4 − B₄(0)/24) dx = 1 + γ(1/12 + 1/720 + 1/720).
    let (n, s, reps) = (16, 3, 4000);
    let c: f64 = 1.0 + SMOOTH_WEIGHT * (1.0 / 12.0 + 2.0 / 720.0);
    let want = (c.powi(s as i32) - 1.0) / n as f64;
    let values: Vec<f64> = (0..reps)
        .map(|r| smooth().value(&random_set(n, s, 1000 + r)))
        .collect();
    let mean = values.iter().sum::<f64>() / reps as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (reps - 1) as f64;
    let se = (var / reps as f64).sqrt();
    assert!(
        (mean - want).abs() < 4.0 * se,
        "mean {mean} vs {want} (SE {se})"
    );
}

#[test]
fn one_point_written_out() {
    let x = [0.2, 0.7];
    let b1 = |t: f64| t - 0.5;
    let b2 = |t: f64| t * t - t + 1.0 / 6.0;
    let diag = |t: f64| 1.0 + SMOOTH_WEIGHT * (b1(t) * b1(t) + b2(t) * b2(t) / 4.0 + 1.0 / 720.0);
    let want = diag(x[0]) * diag(x[1]) - 1.0;
    let got = smooth().value(&PointSet::new(1, 2, x.to_vec()).unwrap());
    assert!((got - want).abs() < 1e-15, "{got} vs {want}");
}

#[test]
fn the_centred_grid_reaches_order_two_in_one_dimension() {
    // In one dimension the midpoint rule's worst-case error for smoothness 2 falls like
    // n⁻² (the star L2's like n⁻¹): quadrupling n divides e by about 16.
    let grid = |n: usize| {
        let data = (0..n).map(|i| (i as f64 + 0.5) / n as f64).collect();
        smooth().value(&PointSet::new(n, 1, data).unwrap()).sqrt()
    };
    let ratio = grid(16) / grid(64);
    assert!((14.0..18.0).contains(&ratio), "{ratio}");
}
