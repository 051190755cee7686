//! The vectorised kernels against straightforward ones written here from the paper's
//! formulas: the per-coordinate accuracy of the general-q fast path (the bound stated in
//! `uqp.rs`), whole energies and gradients for many (q, p, s, n), the fused discrepancy
//! pair sums, the minimum distances, and thread-count independence.
//!
//! The vector path in use is the processor's (AVX2 + FMA here); run the suite again with
//! `STILLPOINT_PORTABLE=1` to check the portable one against the same bounds.
//!
//! The same checks for [`Precision::Fast`] (the interpolation table) against its own
//! bound, [`Precision::FAST_BOUND`].

use stillpoint_energies::discrepancy::{pair_product_sums, DiscrepancyKind};
use stillpoint_energies::pairs::min_squared_distances;
use stillpoint_energies::{Distance, Energy, PointSet, Precision, Uqp};

mod common;
use common::random_set;

/// The stated bound: each h² and each h·h' of the general-q fast path is within this of
/// the exact value, relative to h² and to Δ·v² = h²/Δ.
const BOUND: f64 = 1e-12;

/// h(Δ)² and h·h' from eq. 11 and eq. 16 as printed, for Δ ∈ (0, 1), evaluated in the
/// most accurate f64 form at hand: h = Δ·(1 + r^q)^{−1/q}, r = Δ/(1 − Δ), through ln_1p
/// and exp, and h·h' = h²·((1 − Δ) − tΔ)/(Δ(1 − Δ)(1 + t)) (eq. 16 rearranged).
fn reference_q(delta: f64, q: f64) -> (f64, f64, f64) {
    let d = if delta > 0.5 { 1.0 - delta } else { delta };
    let u = 1.0 - d;
    let t = (q * (d / u).ln()).exp();
    let h = d * (-(t.ln_1p()) / q).exp();
    let hh = h * h * (u - t * d) / (d * u * (1.0 + t));
    let scale = h * h / d;
    (h * h, if delta > 0.5 { -hh } else { hh }, scale)
}

/// U and its gradient for two points in one dimension, with p = 1 (so d^{−p} is an exact
/// 1/√d² and only the coordinate kernel is approximated): U = 1/h, ∂U/∂x₁ = −a/h³.
fn two_points_with(q: f64, x1: f64, precision: Precision) -> (f64, f64) {
    let x = PointSet::new(2, 1, vec![x1, 0.0]).unwrap();
    let e = Uqp::new(Distance::Q(q), 1.0)
        .unwrap()
        .with_precision(precision);
    let mut g = [0.0; 2];
    let u = e.value_and_gradient(&x, &mut g);
    (u, g[0])
}

/// Δ from 1e-80 to 1 − 1e-16, log-spaced towards both ends, a uniform grid and a fine one
/// around the kink-free middle Δ = ½ (where h·h' passes through 0). Below 1e-80 the
/// kernels keep their bounds, but the two-point energy's pair weight d^{−p−2} overflows.
fn test_deltas() -> Vec<f64> {
    let mut deltas: Vec<f64> = (0..=80).map(|k| 10f64.powf(-(k as f64))).collect();
    deltas.extend((1..=16).map(|k| 1.0 - 10f64.powf(-(k as f64))));
    deltas.extend((1..2000).map(|k| k as f64 / 2000.0));
    deltas.extend((1..2000).map(|k| 0.5 + (k as f64 - 1000.0) * 1e-9));
    deltas
}

/// The worst errors of h² (relative to h²) and h·h' (relative to Δ·v²) of one precision's
/// two-point energies over [`test_deltas`], asserting `bound_h2` and `bound` on them.
fn kernel_errors(qs: &[f64], precision: Precision, bound_h2: f64, bound: f64) -> (f64, f64) {
    let deltas = test_deltas();
    let mut worst: (f64, f64) = (0.0, 0.0);
    for &q in qs {
        for &delta in &deltas {
            if delta <= 0.0 || delta >= 1.0 {
                continue;
            }
            let (h2, hh, scale) = reference_q(delta, q);
            if h2 < f64::MIN_POSITIVE || h2.is_nan() || !scale.is_finite() {
                continue; // h² below the normal range: flushed, as documented.
            }
            let (u, g) = two_points_with(q, delta, precision);
            let got_h2 = 1.0 / (u * u);
            let got_hh = -g * got_h2 * got_h2.sqrt();
            let e_h2 = (got_h2 - h2).abs() / h2;
            let e_hh = (got_hh - hh).abs() / scale;
            worst = (worst.0.max(e_h2), worst.1.max(e_hh));
            assert!(
                e_h2 <= bound_h2 && e_hh <= bound,
                "{precision:?} q={q} Δ={delta:e}: h² {got_h2:e} vs {h2:e} ({e_h2:e}), h·h' {got_hh:e} vs {hh:e} ({e_hh:e})"
            );
        }
    }
    worst
}

#[test]
fn general_q_kernel_within_the_stated_bound() {
    let qs = [
        0.01, 0.05, 0.0551, 0.1, 0.173, 0.3, 0.5, 0.84, 0.999, 1.001, 1.7, 2.5, 3.7, 10.0, 100.0,
    ];
    let (w2, w) = kernel_errors(&qs, Precision::Full, BOUND, BOUND);
    let worst = w2.max(w);
    eprintln!("general-q kernel: worst relative error {worst:e} (bound {BOUND:e})");
}

#[test]
fn fast_kernel_within_its_stated_bound() {
    // The table's range [0.01, 2] and its ends, plus q outside it (the full kernels).
    let qs = [
        0.01, 0.0173, 0.05, 0.0551, 0.1, 0.173, 0.3, 0.5, 0.84, 0.999, 1.001, 1.7, 1.99, 2.0, 3.7,
    ];
    let (b2, b) = (Precision::FAST_BOUND_H2, Precision::FAST_BOUND);
    let (w2, w) = kernel_errors(&qs, Precision::Fast, b2, b);
    eprintln!("fast kernel: worst error of h² {w2:e} (bound {b2:e}), of h·h' {w:e} (bound {b:e})");
    // The bounds are not loose by orders of magnitude: the table is a real approximation.
    assert!(w2 > 1e-11 && w > 1e-8, "{w2:e} {w:e}");
}

#[test]
fn fast_precision_only_changes_the_table_range() {
    let x = random_set(90, 4, 5);
    for (dist, changes) in [
        (Distance::Q(0.3), true),
        (Distance::Q(0.01), true),
        (Distance::Q(2.0), false),
        (Distance::Q(1.0), false),
        (Distance::Q(0.009), false),
        (Distance::Q(2.5), false),
        (Distance::Torus, false),
        (Distance::Euclidean, false),
    ] {
        let full = Uqp::new(dist, 0.8).unwrap();
        let fast = full.clone().with_precision(Precision::Fast);
        let (a, b) = (full.value(&x), fast.value(&x));
        assert_eq!(a.to_bits() != b.to_bits(), changes, "{dist:?}: {a} vs {b}");
        assert!((a - b).abs() <= Precision::FAST_BOUND_H2 * a, "{dist:?}");
    }
}

#[test]
fn fast_precision_handles_tiny_and_zero_differences() {
    // Differences of 0, 1e-30 and 1e-9 (below the table's 2^-24) and of 0.3: the first
    // three go to the f64 formulas, so the energy and gradient are as accurate as those.
    let x = PointSet::from_rows(&[
        [0.2, 0.7, 0.4],
        [0.2, 0.7 + 1e-30, 0.4 + 1e-9],
        [0.5, 0.1, 0.4],
        [0.9, 0.7, 0.1],
    ])
    .unwrap();
    for q in [0.03, 0.3, 1.5] {
        let fast = Uqp::new(Distance::Q(q), 0.9)
            .unwrap()
            .with_precision(Precision::Fast);
        let mut g = vec![0.0; x.coordinate_count()];
        let u = fast.value_and_gradient(&x, &mut g);
        let (u_ref, g_ref) = reference_uqp(&x, Distance::Q(q), 0.9);
        assert!(
            (u - u_ref).abs() <= Precision::FAST_BOUND_H2 * u_ref,
            "q={q}: {u} vs {u_ref}"
        );
        assert!(norm_err(&g, &g_ref) <= Precision::FAST_BOUND, "q={q}");
        assert!(g.iter().all(|v| v.is_finite()));
    }
}

/// Straightforward U_{q,p} with its gradient: every pair twice, the kernels as printed
/// (eq. 11 and 16 for finite q, eq. 9 for ∞, eq. 8 for 'E'), `powf` for every power.
fn reference_uqp(x: &PointSet, dist: Distance, p: f64) -> (f64, Vec<f64>) {
    let (n, s) = (x.n(), x.s());
    let mut sum = 0.0;
    let mut grad = vec![0.0; n * s];
    let mut a = vec![0.0; s];
    for i in 0..n {
        for j in 0..n {
            if i == j {
                continue;
            }
            let mut d2 = 0.0;
            for (k, ak) in a.iter_mut().enumerate() {
                let diff = x.point(i)[k] - x.point(j)[k];
                let (h2, hh) = match dist {
                    Distance::Euclidean => (diff * diff, diff),
                    Distance::Torus => {
                        let dl = diff.abs().fract();
                        let sg = diff.signum();
                        if dl <= 0.5 {
                            (dl * dl, if dl == 0.5 { 0.0 } else { sg * dl })
                        } else {
                            ((1.0 - dl) * (1.0 - dl), -sg * (1.0 - dl))
                        }
                    }
                    Distance::Q(q) => {
                        let dl = diff.abs().fract();
                        if dl == 0.0 {
                            (0.0, 0.0)
                        } else {
                            let w = dl.powf(q) + (1.0 - dl).powf(q);
                            let h2 = (dl * (1.0 - dl)).powi(2) / w.powf(2.0 / q);
                            let hh =
                                dl * (1.0 - dl) * ((1.0 - dl).powf(q + 1.0) - dl.powf(q + 1.0))
                                    / w.powf(1.0 + 2.0 / q);
                            (h2, diff.signum() * hh)
                        }
                    }
                };
                d2 += h2;
                *ak = hh;
            }
            let d = d2.sqrt();
            if j > i {
                sum += d.powf(-p);
            }
            for k in 0..s {
                grad[i * s + k] += a[k] / d.powf(p + 2.0);
            }
        }
    }
    let scale = -sum.powf(1.0 / p - 1.0);
    grad.iter_mut().for_each(|g| *g *= scale);
    (sum.powf(1.0 / p), grad)
}

fn norm_err(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>();
    let den: f64 = b.iter().map(|y| y * y).sum::<f64>();
    (num / den).sqrt()
}

#[test]
fn energies_and_gradients_match_the_straightforward_kernel() {
    let dists = [
        Distance::Q(0.05),
        Distance::Q(0.0551),
        Distance::Q(0.3),
        Distance::Q(1.0),
        Distance::Q(2.0),
        Distance::Q(3.7),
        Distance::Torus,
        Distance::Euclidean,
    ];
    let sizes = [
        (2usize, 1usize),
        (3, 2),
        (17, 3),
        (33, 1),
        (70, 7),
        (129, 20),
        (300, 2),
    ];
    let mut worst: (f64, f64) = (0.0, 0.0);
    for (di, &dist) in dists.iter().enumerate() {
        for &p in &[0.05, 0.5, 0.84, 1.0, 2.0, 3.3] {
            for &(n, s) in &sizes {
                let x = random_set(n, s, 7 + 13 * di as u64 + n as u64 * s as u64);
                let e = Uqp::new(dist, p).unwrap();
                let mut g = vec![0.0; x.coordinate_count()];
                let u = e.value_and_gradient(&x, &mut g);
                assert_eq!(u.to_bits(), e.value(&x).to_bits(), "value paths differ");
                let (u_ref, g_ref) = reference_uqp(&x, dist, p);
                let eu = (u - u_ref).abs() / u_ref;
                let eg = norm_err(&g, &g_ref);
                worst = (worst.0.max(eu), worst.1.max(eg));
                assert!(
                    eu < 1e-11 && eg < 1e-10,
                    "{dist:?} p={p} n={n} s={s}: value {eu:e}, gradient {eg:e}"
                );
            }
        }
    }
    eprintln!(
        "energy relative error ≤ {:e}, gradient ≤ {:e}",
        worst.0, worst.1
    );
}

#[test]
fn fast_energies_and_gradients_match_the_straightforward_kernel() {
    let sizes = [(2usize, 1usize), (17, 3), (70, 7), (129, 20), (300, 2)];
    let mut worst: (f64, f64) = (0.0, 0.0);
    for (qi, &q) in [0.0551, 0.17, 0.3, 0.7, 1.3, 1.9].iter().enumerate() {
        for &p in &[0.05, 0.84, 1.0, 3.3] {
            for &(n, s) in &sizes {
                let x = random_set(n, s, 3 + 11 * qi as u64 + n as u64 * s as u64);
                let e = Uqp::new(Distance::Q(q), p)
                    .unwrap()
                    .with_precision(Precision::Fast);
                let mut g = vec![0.0; x.coordinate_count()];
                let u = e.value_and_gradient(&x, &mut g);
                assert_eq!(u.to_bits(), e.value(&x).to_bits(), "value paths differ");
                let (u_ref, g_ref) = reference_uqp(&x, Distance::Q(q), p);
                let eu = (u - u_ref).abs() / u_ref;
                let eg = norm_err(&g, &g_ref);
                worst = (worst.0.max(eu), worst.1.max(eg));
                // Per coordinate within the bounds; d² and the pair sums inherit them.
                assert!(
                    eu < Precision::FAST_BOUND_H2 && eg < Precision::FAST_BOUND,
                    "q={q} p={p} n={n} s={s}: value {eu:e}, gradient {eg:e}"
                );
            }
        }
    }
    eprintln!(
        "fast: energy relative error ≤ {:e}, gradient ≤ {:e}",
        worst.0, worst.1
    );
}

#[test]
fn saturation_is_as_documented() {
    // Coincident points: +∞ energy, finite (zero) gradient; points far apart in 'E' with a
    // large p: d^{−p} underflows to 0.
    let x = PointSet::from_rows(&[[0.3, 0.3], [0.3, 0.3]]).unwrap();
    for dist in [Distance::Q(0.2), Distance::Q(1.0), Distance::Torus] {
        let e = Uqp::new(dist, 1.5).unwrap();
        let mut g = [0.0; 4];
        assert!(e.value_and_gradient(&x, &mut g).is_infinite());
        assert!(g.iter().all(|v| v.is_finite()));
    }
    // Equal coordinates in some dimensions only: h = 0 there, no NaN.
    let x = PointSet::from_rows(&[[0.3, 0.1], [0.3, 0.6], [0.2, 0.6]]).unwrap();
    let e = Uqp::new(Distance::Q(0.07), 0.9).unwrap();
    let mut g = [0.0; 6];
    let u = e.value_and_gradient(&x, &mut g);
    let (u_ref, g_ref) = reference_uqp(&x, Distance::Q(0.07), 0.9);
    assert!((u - u_ref).abs() < 1e-12 * u_ref);
    assert!(norm_err(&g, &g_ref) < 1e-10);
}

#[test]
fn same_bits_for_one_and_two_threads_every_kernel() {
    // Large enough for several blocks and the parallel schedule.
    let x = random_set(700, 5, 99);
    let run = |t: usize, e: &dyn Energy| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| {
                let mut g = vec![0.0; x.coordinate_count()];
                let u = e.value_and_gradient(&x, &mut g);
                let v = e.value(&x);
                (
                    u.to_bits(),
                    v.to_bits(),
                    g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                )
            })
    };
    for dist in [
        Distance::Q(0.06),
        Distance::Q(1.0),
        Distance::Q(2.0),
        Distance::Torus,
        Distance::Euclidean,
    ] {
        let e = Uqp::new(dist, 0.7).unwrap();
        assert_eq!(run(1, &e), run(2, &e), "{dist:?}");
        assert_eq!(run(1, &e), run(3, &e), "{dist:?}");
        let e = e.with_precision(Precision::Fast);
        assert_eq!(run(1, &e), run(2, &e), "{dist:?} fast");
        assert_eq!(run(1, &e), run(3, &e), "{dist:?} fast");
    }
}

/// Σ_{i<j} Π_k K(x_ik, x_jk) as a plain loop.
fn reference_pair_sum(x: &PointSet, k: fn(f64, f64) -> f64) -> f64 {
    let mut sum = 0.0;
    for i in 0..x.n() {
        for j in i + 1..x.n() {
            sum += x
                .point(i)
                .iter()
                .zip(x.point(j))
                .map(|(&a, &b)| k(a, b))
                .product::<f64>();
        }
    }
    sum
}

#[test]
fn fused_pair_sums_equal_single_ones_and_the_plain_loop() {
    use DiscrepancyKind::*;
    let all = [StarL2, ModifiedL2, CenteredL2, WrapAroundL2];
    let kernels: [fn(f64, f64) -> f64; 4] = [
        |x, y| 1.0 - x.max(y),
        |x, y| 2.0 - x.max(y),
        |x, y| 1.0 + 0.5 * (x - 0.5).abs() + 0.5 * (y - 0.5).abs() - 0.5 * (x - y).abs(),
        |x, y| {
            let d = (x - y).abs();
            1.5 - d * (1.0 - d)
        },
    ];
    for &(n, s) in &[(1usize, 3usize), (2, 1), (31, 4), (100, 12), (650, 3)] {
        let x = random_set(n, s, 300 + n as u64);
        let fused = pair_product_sums(&x, &all);
        let pair = pair_product_sums(&x, &[StarL2, ModifiedL2]);
        for (m, &kind) in all.iter().enumerate() {
            let single = pair_product_sums(&x, &[kind])[0];
            assert_eq!(fused[m].to_bits(), single.to_bits(), "{kind:?} n={n}");
            if m < 2 {
                assert_eq!(pair[m].to_bits(), single.to_bits(), "{kind:?} n={n}");
            }
            let want = reference_pair_sum(&x, kernels[m]);
            assert!(
                // Two summation orders of up to 2·10⁵ positive terms.
                (single - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{kind:?} n={n} s={s}: {single} vs {want}"
            );
        }
        // Other orders run kind by kind, with the same bits.
        let rev = pair_product_sums(&x, &[WrapAroundL2, StarL2]);
        assert_eq!(rev[0].to_bits(), fused[3].to_bits());
        assert_eq!(rev[1].to_bits(), fused[0].to_bits());
    }
}

#[test]
fn discrepancy_energy_value_paths_have_the_same_bits() {
    use stillpoint_energies::discrepancy::DiscrepancyEnergy;
    use DiscrepancyKind::*;
    for &(n, s) in &[(5usize, 2usize), (77, 9), (400, 3)] {
        let x = random_set(n, s, 800 + n as u64);
        for kind in [StarL2, ModifiedL2, CenteredL2, WrapAroundL2] {
            let e = DiscrepancyEnergy::new(kind);
            let mut g = vec![0.0; x.coordinate_count()];
            let v = e.value_and_gradient(&x, &mut g);
            assert_eq!(v.to_bits(), e.value(&x).to_bits(), "{kind:?} n={n} s={s}");
        }
    }
}

#[test]
fn minimum_distances_match_brute_force() {
    for &(n, s) in &[(1usize, 2usize), (2, 1), (40, 3), (333, 2), (900, 6)] {
        let mut x = random_set(n, s, 500 + n as u64);
        if n > 10 {
            // A near-duplicate pair and a pair close only across the periodic boundary.
            let p = x.point(3).to_vec();
            x.point_mut(7).copy_from_slice(&p);
            x.point_mut(7)[0] += 1e-9;
            x.point_mut(8)[0] = 0.999_999;
            let q = x.point(8).to_vec();
            x.point_mut(9).copy_from_slice(&q);
            x.point_mut(9)[0] = 0.000_001;
        }
        let got = min_squared_distances(x.as_slice(), n, s);
        let (mut e, mut t) = (f64::INFINITY, f64::INFINITY);
        for i in 0..n {
            for j in i + 1..n {
                let (mut de, mut dt) = (0.0, 0.0);
                for k in 0..s {
                    let d = (x.point(i)[k] - x.point(j)[k]).abs();
                    de += d * d;
                    let w = if d > 0.5 { 1.0 - d } else { d };
                    dt += w * w;
                }
                e = e.min(de);
                t = t.min(dt);
            }
        }
        assert_eq!(got, [e, t], "n={n} s={s}");
    }
}

#[test]
fn fast_forces_are_the_gradient_of_the_fast_energy() {
    // h·h' comes from the derivative of the same cubic as h², so inside an interval of
    // the table the fast force is the derivative of the fast energy: a central difference
    // of the two-point energy U = 1/h (p = 1) matches it to the difference's own error,
    // far closer than the fast force keeps to eq. 16.
    let mut worst_self: f64 = 0.0;
    let mut worst_exact: f64 = 0.0;
    for q in [0.07, 0.4, 1.6] {
        for k in [2, 5, 11] {
            for j in [0, 17, 40, 63] {
                let binade = 0.5f64.powi(k);
                // Near the end of interval j, where the derivative of the cubic strays
                // most; the steps stay inside the interval.
                let delta = binade * (1.0 + (j as f64 + 0.97) / 64.0);
                let step = binade / 64.0 / 100.0;
                let (u0, g) = two_points_with(q, delta, Precision::Fast);
                // The force's scale: U = 1/h, and h·h' is measured against Δ·v² = h²/Δ.
                let scale = u0 / delta;
                let u = |d: f64| two_points_with(q, d, Precision::Fast).0;
                let cd = |h: f64| (u(delta + h) - u(delta - h)) / (2.0 * h);
                // Richardson: fourth order in the step.
                let fd = (4.0 * cd(0.5 * step) - cd(step)) / 3.0;
                let (_, g_exact) = two_points_with(q, delta, Precision::Full);
                worst_self = worst_self.max((fd - g).abs() / scale);
                worst_exact = worst_exact.max((g_exact - g).abs() / scale);
            }
        }
    }
    eprintln!(
        "fast force against the difference of the fast energy {worst_self:e}, against eq. 16 \
         {worst_exact:e}"
    );
    assert!(worst_self < 1e-9, "{worst_self:e}");
    assert!(
        worst_self < worst_exact / 10.0,
        "{worst_self:e} {worst_exact:e}"
    );
}
