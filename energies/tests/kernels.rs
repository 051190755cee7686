//! The discrepancy kernels are one table: every kind of `DiscrepancyKind::ALL` is one
//! `DiscrepancyKernel`, whose constants, one-point factor and pair factor belong together
//! (g(x) = ∫ K(x, y) dy and |C| = ∫∫ K, as for every worst-case error of a reproducing
//! kernel), whose energy is the closed form built from those factors alone, and whose
//! names, energy name, periodicity and place in the report's fused pass are the ones the
//! rest of the crate sees.

use stillpoint_energies::discrepancy::{
    squared_discrepancies, squared_discrepancies_with_mixture, DiscrepancyEnergy,
    DiscrepancyKernel, DiscrepancyKind, Mixture,
};
use stillpoint_energies::{with_kernel, Energy, PointSet};

mod common;
use common::random_set;

/// ∫₀¹ f by the midpoint rule on m cells (error O(1/m²), also across a kink).
fn integral(m: usize, f: impl Fn(f64) -> f64) -> f64 {
    (0..m).map(|c| f((c as f64 + 0.5) / m as f64)).sum::<f64>() / m as f64
}

/// g(x) = ∫ K(x, y) dy for a kernel with the single sum (∫ K(x, y) dy = CONSTANT_BASE
/// for every x without it, its middle term merged into C_s with the sign −), and
/// |C| = ∫∫ K: checked on a grid of x.
fn factors_belong_together<K: DiscrepancyKernel>(what: &str) {
    let m = 20_000;
    for t in 0..=10 {
        let x = t as f64 / 10.0;
        let row = integral(m, |y| K::pair_factor(x, y));
        let want = if K::HAS_SINGLE {
            K::single_factor(x)
        } else {
            K::CONSTANT_BASE
        };
        assert!(
            (row - want).abs() < 1e-8,
            "{what}: ∫ K({x}, y) dy = {row}, g = {want}"
        );
    }
    let whole = integral(2000, |x| integral(2000, |y| K::pair_factor(x, y)));
    assert!(
        (whole - K::CONSTANT_BASE).abs() < 1e-6,
        "{what}: ∫∫ K = {whole}, base {}",
        K::CONSTANT_BASE
    );
    let sign = if K::HAS_SINGLE { 1.0 } else { -1.0 };
    assert_eq!(K::CONSTANT_SIGN, sign, "{what}");
    for s in 0..5 {
        let want = sign * K::CONSTANT_BASE.powi(s as i32);
        assert!((K::constant(s) - want).abs() < 1e-15 * want.abs(), "{what}");
    }
}

/// The derivatives `single` and `pair` give are those of their own values (central
/// differences at points away from every kink), and each factor lies below
/// LARGEST_FACTOR.
fn derivatives_and_bound<K: DiscrepancyKernel>(what: &str) {
    let h = 1e-6;
    let grid = [0.03, 0.21, 0.37, 0.62, 0.79, 0.97];
    for &x in &grid {
        if K::HAS_SINGLE {
            let (_, dg) = K::single(x);
            let fd = (K::single_factor(x + h) - K::single_factor(x - h)) / (2.0 * h);
            assert!((dg - fd).abs() < 1e-7, "{what}: g'({x}) {dg} vs {fd}");
        }
        for &y in &grid {
            if x == y {
                continue;
            }
            let (_, dx, dy) = K::pair(x, y);
            let fx = (K::pair_factor(x + h, y) - K::pair_factor(x - h, y)) / (2.0 * h);
            let fy = (K::pair_factor(x, y + h) - K::pair_factor(x, y - h)) / (2.0 * h);
            assert!(
                (dx - fx).abs() < 1e-7,
                "{what}: ∂K/∂x({x}, {y}) {dx} vs {fx}"
            );
            assert!(
                (dy - fy).abs() < 1e-7,
                "{what}: ∂K/∂y({x}, {y}) {dy} vs {fy}"
            );
        }
    }
    for i in 0..=100 {
        let x = i as f64 / 100.0;
        if K::HAS_SINGLE {
            assert!(K::single_factor(x) <= K::LARGEST_FACTOR, "{what}: g({x})");
        }
        for j in 0..=100 {
            let y = j as f64 / 100.0;
            assert!(
                K::pair_factor(x, y) <= K::LARGEST_FACTOR,
                "{what}: K({x}, {y})"
            );
        }
    }
}

/// D² = C_s − (2/n) Σ_i Π_k g(x_ik) + (1/n²) Σ_{i,l} Π_k K(x_ik, x_lk), every ordered pair
/// in a plain double loop, from the kernel's factors alone.
fn double_sum<K: DiscrepancyKernel>(p: &PointSet) -> f64 {
    let n = p.n() as f64;
    let mut single = 0.0;
    let mut pairs = 0.0;
    for a in p.rows() {
        if K::HAS_SINGLE {
            single += a.iter().map(|&x| K::single_factor(x)).product::<f64>();
        }
        for b in p.rows() {
            pairs += a
                .iter()
                .zip(b)
                .map(|(&x, &y)| K::pair_factor(x, y))
                .product::<f64>();
        }
    }
    K::constant(p.s()) - 2.0 * single / n + pairs / (n * n)
}

#[test]
fn each_kernels_factors_and_constants_belong_together() {
    for &kind in DiscrepancyKind::ALL {
        with_kernel!(kind, K => factors_belong_together::<K>(kind.label()));
        with_kernel!(kind, K => derivatives_and_bound::<K>(kind.label()));
    }
    factors_belong_together::<Mixture>("mixture");
    derivatives_and_bound::<Mixture>("mixture");
}

#[test]
fn each_energy_is_the_double_sum_of_its_kernels_factors() {
    for (n, s, seed) in [(1, 3, 1), (13, 2, 2), (40, 5, 3), (57, 9, 4)] {
        let p = random_set(n, s, seed);
        let fused = squared_discrepancies_with_mixture(&p);
        for &kind in DiscrepancyKind::ALL {
            let e = DiscrepancyEnergy::new(kind);
            let value = e.value(&p);
            let want = with_kernel!(kind, K => double_sum::<K>(&p));
            // The terms are of order 1 (the smoothness-2 error is −1 plus terms near 1).
            let scale = with_kernel!(kind, K => K::CONSTANT_BASE.powi(s as i32)).max(1.0);
            assert!(
                (value - want).abs() < 1e-12 * scale,
                "{kind:?} n={n} s={s}: {value} vs {want}"
            );
            assert_eq!(
                value.to_bits(),
                squared_discrepancies(&p, &[kind])[0].to_bits(),
                "{kind:?}"
            );
            // Its place in the report's fused pass is its own.
            if let Some(m) = kind.reported() {
                assert_eq!(value.to_bits(), fused[m].to_bits(), "{kind:?}");
            }
        }
        let mixture = double_sum::<Mixture>(&p);
        assert!((fused[4] - mixture).abs() < 1e-12 * (19.0f64 / 12.0).powi(s as i32));
    }
}

#[test]
fn the_names_round_trip_and_are_the_energies_own() {
    let mut seen = Vec::new();
    let accepted = DiscrepancyKind::accepted();
    for &kind in DiscrepancyKind::ALL {
        assert_eq!(kind.label(), kind.names()[0]);
        for &name in kind.names() {
            assert!(!seen.contains(&name), "{name} names two kinds");
            seen.push(name);
            for spelled in [name.to_string(), format!(" {} ", name.to_ascii_uppercase())] {
                assert_eq!(DiscrepancyKind::parse(&spelled).unwrap(), kind, "{spelled}");
            }
            assert!(accepted.contains(&format!("`{name}`")), "{accepted}");
        }
        assert!(accepted.contains(kind.description()), "{accepted}");
        let energy = DiscrepancyEnergy::new(kind).name();
        assert_eq!(energy, with_kernel!(kind, K => K::ENERGY_NAME));
        assert!(energy.starts_with("D²_"), "{energy}");
    }
    let names: Vec<String> = DiscrepancyKind::ALL
        .iter()
        .map(|k| DiscrepancyEnergy::new(*k).name())
        .collect();
    for (i, a) in names.iter().enumerate() {
        assert!(!names[i + 1..].contains(a), "{a} twice");
    }
    let err = DiscrepancyKind::parse("mixture").unwrap_err().to_string();
    assert!(err.contains(&accepted), "{err}");
}

#[test]
fn only_the_periodic_kinds_are_unchanged_by_a_periodic_shift() {
    let p = random_set(30, 3, 9);
    let shifted = PointSet::new(
        30,
        3,
        p.as_slice().iter().map(|v| (v + 0.377) % 1.0).collect(),
    )
    .unwrap();
    for &kind in DiscrepancyKind::ALL {
        let e = DiscrepancyEnergy::new(kind);
        let (a, b) = (e.value(&p), e.value(&shifted));
        let unchanged = (a - b).abs() < 1e-12 * a.abs().max(1e-3);
        assert_eq!(unchanged, kind.is_periodic(), "{kind:?}: {a} vs {b}");
    }
}
