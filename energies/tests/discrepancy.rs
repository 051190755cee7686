//! Checks of the squared L2 discrepancies as energies: values against a brute-force
//! double loop and against SciPy, gradients against finite differences and a brute-force
//! product rule, the treatment of kinks, known facts, determinism and the CLI names.

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use stillpoint_energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use stillpoint_energies::{Energy, PointSet};

mod common;
use common::{fd_gradient, random_set, rel_err};

const KINDS: [DiscrepancyKind; 6] = [
    DiscrepancyKind::StarL2,
    DiscrepancyKind::ModifiedL2,
    DiscrepancyKind::CenteredL2,
    DiscrepancyKind::WrapAroundL2,
    DiscrepancyKind::Smooth,
    DiscrepancyKind::Curved,
];

/// γ of the smoothness-2 kernel, and its Bernoulli polynomials as Dick, Kuo and Sloan
/// print them.
const GAMMA: f64 = stillpoint_energies::discrepancy::SMOOTH_WEIGHT;
/// The coefficient of B₂(x)B₂(y): 1/4 in the standard space (Dick, Kuo and Sloan), the
/// curvature weight times that in the curved one.
fn b2b2(kind: DiscrepancyKind) -> f64 {
    match kind {
        DiscrepancyKind::Curved => stillpoint_energies::discrepancy::CURVATURE_WEIGHT as f64 / 4.0,
        _ => 1.0 / 4.0,
    }
}
fn b1(t: f64) -> f64 {
    t - 0.5
}
fn b2(t: f64) -> f64 {
    t * t - t + 1.0 / 6.0
}
fn b4(t: f64) -> f64 {
    t.powi(4) - 2.0 * t.powi(3) + t * t - 1.0 / 30.0
}

/// A random set whose coordinates are at least `gap` apart from each other (per
/// coordinate) and from ½, so that a finite-difference step of less than `gap` crosses no
/// kink of any of the four kernels.
fn set_away_from_kinks(n: usize, s: usize, seed: u64, gap: f64) -> PointSet {
    for attempt in 0..1000 {
        let x = random_set(n, s, seed.wrapping_mul(1000).wrapping_add(attempt));
        let ok = (0..s).all(|k| {
            (0..n).all(|i| {
                let a = x.point(i)[k];
                (a - 0.5).abs() > gap
                    && a > gap
                    && a < 1.0 - gap
                    && (i + 1..n).all(|l| (a - x.point(l)[k]).abs() > gap)
            })
        });
        if ok {
            return x;
        }
    }
    panic!("no set away from the kinks for n={n}, s={s}");
}

fn energy(kind: DiscrepancyKind) -> DiscrepancyEnergy {
    DiscrepancyEnergy::new(kind)
}

fn gradient(e: &dyn Energy, x: &PointSet) -> (f64, Vec<f64>) {
    let mut g = vec![f64::NAN; x.coordinate_count()];
    let v = e.value_and_gradient(x, &mut g);
    (v, g)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

// ---- Brute force: the closed forms written out directly, full double loop, no symmetry,
// no prefix products; derivatives by the plain product rule (valid away from kinks).

/// (C_s, g(x), K(x, y)) of each closed form, written independently of the crate.
fn bf_constant(kind: DiscrepancyKind, s: usize) -> f64 {
    let s = s as i32;
    match kind {
        DiscrepancyKind::StarL2 => (1.0f64 / 3.0).powi(s),
        DiscrepancyKind::ModifiedL2 => (4.0f64 / 3.0).powi(s),
        DiscrepancyKind::CenteredL2 => (13.0f64 / 12.0).powi(s),
        DiscrepancyKind::WrapAroundL2 => -(4.0f64 / 3.0).powi(s),
        DiscrepancyKind::Smooth | DiscrepancyKind::Curved => -1.0,
    }
}

/// The middle term's per-point product, written as the published formulas print it
/// (eq. 47's 2^(1−s) is kept outside, hence the separate factor).
fn bf_single_term(kind: DiscrepancyKind, xi: &[f64]) -> f64 {
    let s = xi.len() as i32;
    match kind {
        DiscrepancyKind::StarL2 => xi.iter().map(|x| (1.0 - x * x) / 2.0).product(),
        DiscrepancyKind::ModifiedL2 => {
            2f64.powi(1 - s) / 2.0 * xi.iter().map(|x| 3.0 - x * x).product::<f64>()
        }
        DiscrepancyKind::CenteredL2 => xi
            .iter()
            .map(|x| {
                let a = (x - 0.5).abs();
                1.0 + a / 2.0 - a * a / 2.0
            })
            .product(),
        DiscrepancyKind::WrapAroundL2 | DiscrepancyKind::Smooth | DiscrepancyKind::Curved => 0.0,
    }
}

fn bf_k(kind: DiscrepancyKind, x: f64, y: f64) -> f64 {
    match kind {
        DiscrepancyKind::StarL2 => 1.0 - if x > y { x } else { y },
        DiscrepancyKind::ModifiedL2 => 2.0 - if x > y { x } else { y },
        DiscrepancyKind::CenteredL2 => {
            1.0 + (x - 0.5).abs() / 2.0 + (y - 0.5).abs() / 2.0 - (x - y).abs() / 2.0
        }
        DiscrepancyKind::WrapAroundL2 => {
            let d = (x - y).abs();
            1.5 - d + d * d
        }
        DiscrepancyKind::Smooth | DiscrepancyKind::Curved => {
            1.0 + GAMMA * (b1(x) * b1(y) + b2b2(kind) * b2(x) * b2(y) - b4((x - y).abs()) / 24.0)
        }
    }
}

/// ∂K/∂x away from kinks.
fn bf_dk_dx(kind: DiscrepancyKind, x: f64, y: f64) -> f64 {
    match kind {
        DiscrepancyKind::StarL2 | DiscrepancyKind::ModifiedL2 => {
            if x > y {
                -1.0
            } else {
                0.0
            }
        }
        DiscrepancyKind::CenteredL2 => 0.5 * (x - 0.5).signum() - 0.5 * (x - y).signum(),
        DiscrepancyKind::WrapAroundL2 => (x - y).signum() * (2.0 * (x - y).abs() - 1.0),
        DiscrepancyKind::Smooth | DiscrepancyKind::Curved => {
            let d = (x - y).abs();
            let db4 = 4.0 * d.powi(3) - 6.0 * d * d + 2.0 * d;
            GAMMA * (b1(y) + b2b2(kind) * (2.0 * x - 1.0) * b2(y) - (x - y).signum() * db4 / 24.0)
        }
    }
}

/// d/dx of the per-point factor g(x) of the middle term (2/n)·Σ_i Π_k g(x_ik).
fn bf_dg(kind: DiscrepancyKind, x: f64) -> f64 {
    match kind {
        DiscrepancyKind::StarL2 | DiscrepancyKind::ModifiedL2 => -x,
        DiscrepancyKind::CenteredL2 => (x - 0.5).signum() * (0.5 - (x - 0.5).abs()),
        DiscrepancyKind::WrapAroundL2 | DiscrepancyKind::Smooth | DiscrepancyKind::Curved => 0.0,
    }
}

fn bf_g(kind: DiscrepancyKind, x: f64) -> f64 {
    match kind {
        DiscrepancyKind::StarL2 => (1.0 - x * x) / 2.0,
        DiscrepancyKind::ModifiedL2 => (3.0 - x * x) / 2.0,
        DiscrepancyKind::CenteredL2 => {
            let a = (x - 0.5).abs();
            1.0 + a / 2.0 - a * a / 2.0
        }
        DiscrepancyKind::WrapAroundL2 | DiscrepancyKind::Smooth | DiscrepancyKind::Curved => 1.0,
    }
}

fn bf_value(kind: DiscrepancyKind, x: &PointSet) -> f64 {
    let (n, s) = (x.n(), x.s());
    let nf = n as f64;
    let single: f64 = (0..n).map(|i| bf_single_term(kind, x.point(i))).sum();
    let mut pair = 0.0;
    for i in 0..n {
        for l in 0..n {
            let mut p = 1.0;
            for k in 0..s {
                p *= bf_k(kind, x.point(i)[k], x.point(l)[k]);
            }
            pair += p;
        }
    }
    bf_constant(kind, s) - 2.0 / nf * single + pair / (nf * nf)
}

fn bf_gradient(kind: DiscrepancyKind, x: &PointSet) -> Vec<f64> {
    let (n, s) = (x.n(), x.s());
    let nf = n as f64;
    let mut g = vec![0.0; n * s];
    for i in 0..n {
        let xi = x.point(i);
        for k in 0..s {
            let others_g: f64 = (0..s)
                .filter(|&m| m != k)
                .map(|m| bf_g(kind, xi[m]))
                .product();
            let mut d = -2.0 / nf * others_g * bf_dg(kind, xi[k]);
            // Every ordered pair (a, b) of Σ_{a,b} K(x_a, x_b) in which point i appears:
            // as the first argument, and as the second (both when a = b = i).
            for l in 0..n {
                let xl = x.point(l);
                let others: f64 = (0..s)
                    .filter(|&m| m != k)
                    .map(|m| bf_k(kind, xi[m], xl[m]))
                    .product();
                let first = bf_dk_dx(kind, xi[k], xl[k]);
                // K is symmetric, so ∂K(x_l, x_i)/∂x_i is ∂K(x_i, x_l)/∂x_i — except on the
                // diagonal, where the two arguments move together.
                let second = if l == i {
                    diag_second_arg(kind, xi[k])
                } else {
                    first
                };
                d += (first + second) * others / (nf * nf);
            }
            g[i * s + k] = d;
        }
    }
    g
}

/// ∂K(x, y)/∂y at y = x for the diagonal term, from the one-sided limits of the smooth
/// pieces: the total derivative of K(x, x) minus ∂K/∂x as `bf_dk_dx` gives it at x = y.
fn diag_second_arg(kind: DiscrepancyKind, x: f64) -> f64 {
    // d/dx K(x, x): 1 − x → −1; 2 − x → −1; 1 + |x − ½| → sgn(x − ½); 3/2 → 0.
    let total = match kind {
        DiscrepancyKind::StarL2 | DiscrepancyKind::ModifiedL2 => -1.0,
        DiscrepancyKind::CenteredL2 => (x - 0.5).signum(),
        DiscrepancyKind::WrapAroundL2 => 0.0,
        // d/dx of γ(B₁(x)² + c B₂(x)²) (B₄(0) is a constant).
        DiscrepancyKind::Smooth | DiscrepancyKind::Curved => {
            GAMMA * (2.0 * b1(x) + 2.0 * b2b2(kind) * (2.0 * x - 1.0) * b2(x))
        }
    };
    // `bf_dk_dx` at x = y takes the "x ≤ y" branch (0) for max, and signum(0) = +1 for
    // centred and wrap-around; give the diagonal term its true total derivative.
    total - bf_dk_dx(kind, x, x)
}

// ---- Gradient checks.

#[test]
fn gradient_matches_central_differences() {
    for (ki, &kind) in KINDS.iter().enumerate() {
        let e = energy(kind);
        for &s in &[1usize, 2, 5, 7] {
            for &n in &[5usize, 17] {
                let x =
                    set_away_from_kinks(n, s, 7 + 100 * ki as u64 + 10 * s as u64 + n as u64, 1e-4);
                let (_, g) = gradient(&e, &x);
                let fd = fd_gradient(&e, &x, 1e-6);
                let err = rel_err(&g, &fd);
                assert!(
                    err < 1e-6,
                    "{}: s={s} n={n}: relative error {err:e}",
                    e.name()
                );
            }
        }
    }
}

#[test]
fn gradient_matches_brute_force_product_rule() {
    for (ki, &kind) in KINDS.iter().enumerate() {
        for &(n, s) in &[(1usize, 3usize), (2, 1), (6, 4), (13, 9), (130, 3)] {
            let x = set_away_from_kinks(n, s, 50 + ki as u64 * 7 + s as u64, 1e-9);
            let (_, g) = gradient(&energy(kind), &x);
            let want = bf_gradient(kind, &x);
            let err = rel_err(&g, &want);
            assert!(err < 1e-12, "{kind:?}: n={n} s={s}: relative error {err:e}");
        }
    }
}

#[test]
fn zero_factors_take_the_division_free_path_and_stay_right() {
    // A coordinate equal to 1 makes the star L2 factor 1 − max(1, y) vanish for every pair
    // it meets: the product rule must then use prefix and suffix products.
    for &kind in &KINDS {
        let mut x = set_away_from_kinks(13, 5, 77, 1e-6);
        for (i, k) in [(0usize, 0usize), (3, 2), (4, 4), (9, 1), (12, 3)] {
            x.point_mut(i)[k] = 1.0;
        }
        x.point_mut(6)[0] = 0.0;
        let (v, g) = gradient(&energy(kind), &x);
        assert!(rel(v, bf_value(kind, &x)) < 1e-12, "{kind:?}");
        let err = rel_err(&g, &bf_gradient(kind, &x));
        assert!(err < 1e-12, "{kind:?}: relative error {err:e}");
    }
}

#[test]
fn large_dimension_uses_the_heap_scratch_and_stays_right() {
    // s > 64 takes the per-tile buffer instead of the stack one.
    for &kind in &KINDS {
        let x = set_away_from_kinks(4, 70, 321, 1e-4);
        let e = energy(kind);
        let (v, g) = gradient(&e, &x);
        assert!(rel(v, bf_value(kind, &x)) < 1e-12, "{kind:?}");
        let err = rel_err(&g, &bf_gradient(kind, &x));
        assert!(err < 1e-12, "{kind:?}: relative error {err:e}");
    }
}

// ---- Values.

#[test]
fn value_and_gradient_value_equals_value() {
    for &kind in &KINDS {
        let e = energy(kind);
        for &(n, s) in &[(1usize, 2usize), (2, 3), (17, 5), (300, 4), (129, 20)] {
            let x = random_set(n, s, 900 + n as u64 + s as u64);
            let (v, _) = gradient(&e, &x);
            let w = e.value(&x);
            assert!(rel(v, w) <= 1e-14, "{}: n={n} s={s}: {v} vs {w}", e.name());
        }
    }
}

#[test]
fn values_match_brute_force() {
    for &kind in &KINDS {
        for &(n, s) in &[(1usize, 1usize), (3, 2), (17, 5), (64, 7), (100, 12)] {
            let mut x = random_set(n, s, 40 + n as u64 * s as u64);
            // Include the faces and repeated coordinates: the closed cube is the domain.
            if n >= 3 {
                x.point_mut(0)[0] = 0.0;
                x.point_mut(1)[s - 1] = 1.0;
                let c = x.point(1)[0];
                x.point_mut(2)[0] = c;
            }
            let got = energy(kind).value(&x);
            let want = bf_value(kind, &x);
            // The smoothness-2 error is −1 plus terms near 1: accurate to rounding of 1.
            let scale = want.abs().max(
                if matches!(kind, DiscrepancyKind::Smooth | DiscrepancyKind::Curved) {
                    1.0
                } else {
                    0.0
                },
            );
            assert!(
                (got - want).abs() < 1e-12 * scale,
                "{kind:?}: n={n} s={s}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn values_match_scipy_and_exact_rationals() {
    // Produced in the shell with SciPy 1.17.1:
    //   X = np.array([[0.12,0.83,0.47],[0.65,0.21,0.94],[0.38,0.56,0.09],
    //                 [0.91,0.34,0.62],[0.27,0.05,0.78],[0.54,0.97,0.31]])
    //   qmc.discrepancy(X, method='L2-star')**2  -> 0.007123774922425929 (SciPy: a root)
    //   qmc.discrepancy(X, method='CD')          -> 0.03585268423353627  (SciPy: squared)
    //   qmc.discrepancy(X, method='WD')          -> 0.06328677201674138  (SciPy: squared)
    // SciPy has no modified L2 ('MD' is the mixture discrepancy), so that one, and a
    // cross-check of the others, come from the closed forms evaluated exactly in Python's
    // `fractions.Fraction` on the same doubles and rounded once to f64:
    //   star 0.007123774922425927, modified 0.04644504825575926,
    //   centred 0.03585268423353703, wrap-around 0.06328677201674072.
    let x = PointSet::from_rows(&[
        [0.12, 0.83, 0.47],
        [0.65, 0.21, 0.94],
        [0.38, 0.56, 0.09],
        [0.91, 0.34, 0.62],
        [0.27, 0.05, 0.78],
        [0.54, 0.97, 0.31],
    ])
    .unwrap();
    let cases = [
        (
            DiscrepancyKind::StarL2,
            Some(0.007123774922425929),
            0.007123774922425927,
        ),
        (DiscrepancyKind::ModifiedL2, None, 0.04644504825575926),
        (
            DiscrepancyKind::CenteredL2,
            Some(0.03585268423353627),
            0.03585268423353703,
        ),
        (
            DiscrepancyKind::WrapAroundL2,
            Some(0.06328677201674138),
            0.06328677201674072,
        ),
    ];
    for (kind, scipy, exact) in cases {
        let e = energy(kind);
        let v = e.value(&x);
        assert!(rel(v, exact) < 1e-12, "{}: {v} vs exact {exact}", e.name());
        if let Some(sp) = scipy {
            assert!(rel(v, sp) < 1e-12, "{}: {v} vs SciPy {sp}", e.name());
        }
    }
}

// ---- Known facts.

#[test]
fn single_point_at_the_far_corner() {
    // Every anchored box [0, t) misses (1, …, 1): only (1/3)^s survives.
    let e = energy(DiscrepancyKind::StarL2);
    for s in 1..=10 {
        let x = PointSet::new(1, s, vec![1.0; s]).unwrap();
        let (v, g) = gradient(&e, &x);
        let want = 3f64.powi(-(s as i32));
        assert!(rel(v, want) < 1e-14, "s={s}: {v} vs {want}");
        assert!(rel(e.value(&x), want) < 1e-14, "s={s}");
        // Factors 1 − max(1, 1) = 0 and (1 − 1²)/2 = 0: the product rule must not
        // divide by them.
        assert!(g.iter().all(|v| v.is_finite()), "s={s}: {g:?}");
    }
}

#[test]
fn wrap_around_is_invariant_under_periodic_shifts() {
    let e = energy(DiscrepancyKind::WrapAroundL2);
    for (seed, s) in [(1u64, 1usize), (2, 2), (3, 5), (4, 8)] {
        let x = random_set(40, s, seed);
        let v = e.value(&x);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed + 77);
        for _ in 0..5 {
            let c: Vec<f64> = (0..s).map(|_| rng.random::<f64>()).collect();
            let mut y = x.clone();
            for row in y.as_mut_slice().chunks_exact_mut(s) {
                for (a, ck) in row.iter_mut().zip(&c) {
                    *a = (*a + ck).rem_euclid(1.0);
                }
            }
            let w = e.value(&y);
            assert!(rel(w, v) < 1e-12, "s={s}: {w} vs {v}");
        }
        // Translation invariance: the forces sum to zero in every coordinate.
        let (_, g) = gradient(&e, &x);
        let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        for k in 0..s {
            let total: f64 = g.iter().skip(k).step_by(s).sum();
            assert!(
                total.abs() < 1e-12 * norm,
                "s={s}, k={k}: Σ_i g = {total:e}"
            );
        }
    }
    assert!(DiscrepancyKind::WrapAroundL2.is_periodic());
    for kind in &KINDS[..3] {
        assert!(!kind.is_periodic(), "{kind:?}");
    }
}

#[test]
fn permuting_points_changes_nothing_but_the_row_order() {
    for &kind in &KINDS {
        let e = energy(kind);
        let (n, s) = (23, 4);
        let x = random_set(n, s, 5);
        let perm: Vec<usize> = (0..n).map(|i| (7 * i + 3) % n).collect();
        let rows: Vec<&[f64]> = perm.iter().map(|&p| x.point(p)).collect();
        let y = PointSet::from_rows(&rows).unwrap();
        let (vx, gx) = gradient(&e, &x);
        let (vy, gy) = gradient(&e, &y);
        assert!(rel(vy, vx) < 1e-12, "{kind:?}: {vy} vs {vx}");
        for (r, &p) in perm.iter().enumerate() {
            for k in 0..s {
                let (a, b) = (gy[r * s + k], gx[p * s + k]);
                assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()), "{kind:?}");
            }
        }
    }
}

// ---- Kinks.

/// Average of the forward and backward one-sided differences of coordinate `idx`.
fn one_sided_average(e: &dyn Energy, x: &PointSet, idx: usize, h: f64) -> f64 {
    let mut y = x.clone();
    let v0 = e.value(x);
    let a = x.as_slice()[idx];
    y.as_mut_slice()[idx] = a + h;
    let fwd = (e.value(&y) - v0) / h;
    y.as_mut_slice()[idx] = a - h;
    let bwd = (v0 - e.value(&y)) / h;
    0.5 * (fwd + bwd)
}

#[test]
fn at_a_kink_the_gradient_is_the_average_of_one_sided_derivatives() {
    for (ki, &kind) in KINDS.iter().enumerate() {
        let e = energy(kind);
        let (n, s) = (9, 3);
        let mut x = set_away_from_kinks(n, s, 600 + ki as u64, 1e-3);
        // Points 1 and 4 share coordinate 0; points 2, 5 and 7 share coordinate 2 (a
        // triple tie); point 6 sits at ½ in coordinate 1 (the centred L2's own kink).
        let c = x.point(1)[0];
        x.point_mut(4)[0] = c;
        let c = x.point(2)[2];
        x.point_mut(5)[2] = c;
        x.point_mut(7)[2] = c;
        x.point_mut(6)[1] = 0.5;
        let (_, g) = gradient(&e, &x);
        assert!(g.iter().all(|v| v.is_finite()), "{kind:?}");
        for (idx, &gv) in g.iter().enumerate() {
            let want = one_sided_average(&e, &x, idx, 1e-7);
            assert!(
                (gv - want).abs() < 1e-5,
                "{kind:?}: point {}, coordinate {}: {gv} vs {want}",
                idx / s,
                idx % s,
            );
        }
    }
}

#[test]
fn coincident_points_give_a_finite_gradient() {
    for &kind in &KINDS {
        let x = PointSet::from_rows(&[[0.3, 0.7], [0.3, 0.7], [0.5, 0.5], [1.0, 0.0]]).unwrap();
        let (v, g) = gradient(&energy(kind), &x);
        assert!(v.is_finite() && g.iter().all(|v| v.is_finite()), "{kind:?}");
        for (idx, &gv) in g.iter().enumerate() {
            let want = one_sided_average(&energy(kind), &x, idx, 1e-7);
            // The last point sits on two faces: only one side exists in the cube, but the
            // closed form extends past it, so the average is still the derivative of that
            // extension.
            assert!((gv - want).abs() < 1e-5, "{kind:?}: {idx}: {gv} vs {want}");
        }
    }
}

#[test]
fn not_smooth_and_named_as_squares() {
    for &kind in &KINDS {
        let e = energy(kind);
        assert!(!e.is_smooth());
        assert!(
            e.name().contains("squared") && e.name().contains("D²"),
            "{}",
            e.name()
        );
        assert_eq!(e.kind(), kind);
    }
    assert_eq!(
        energy(DiscrepancyKind::ModifiedL2).name(),
        "D²_MD (squared modified L2)"
    );
}

// ---- Determinism.

#[test]
fn same_bits_for_one_and_two_threads() {
    let x = random_set(400, 4, 2024);
    for &kind in &KINDS {
        let e = energy(kind);
        let run = |t: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
                .install(|| {
                    let (v, g) = gradient(&e, &x);
                    (
                        v.to_bits(),
                        e.value(&x).to_bits(),
                        g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    )
                })
        };
        let one = run(1);
        assert_eq!(one, run(2), "{}", e.name());
    }
}

// ---- CLI names.

#[test]
fn parse_accepts_the_cli_names_and_refuses_others() {
    let ok = [
        ("l2star", DiscrepancyKind::StarL2),
        ("md", DiscrepancyKind::ModifiedL2),
        ("cd", DiscrepancyKind::CenteredL2),
        ("periodic", DiscrepancyKind::WrapAroundL2),
        ("wd", DiscrepancyKind::WrapAroundL2),
        (" MD ", DiscrepancyKind::ModifiedL2),
    ];
    for (name, kind) in ok {
        assert_eq!(DiscrepancyKind::parse(name).unwrap(), kind, "{name}");
    }
    for kind in KINDS {
        assert_eq!(DiscrepancyKind::parse(kind.label()).unwrap(), kind);
    }
    for bad in ["", "l2", "star", "mixture", "uqp", "l2-star"] {
        let msg = DiscrepancyKind::parse(bad).unwrap_err().to_string();
        assert!(msg.contains("discrepancy"), "{msg}");
        for name in ["l2star", "md", "cd", "periodic"] {
            assert!(msg.contains(name), "{msg} should list {name}");
        }
    }
}

// ---- The mixture discrepancy (a figure of merit sharing the pair loops).

/// The mixture's closed form as Zhou, Fang and Ning (2013) write it, a full double
/// loop: (19/12)^s − (2/n) Σ Π (5/3 − a/4 − a²/4)
/// + (1/n²) Σ Σ Π (15/8 − a/4 − b/4 − 3d/4 + d²/2).
fn bf_mixture(x: &PointSet) -> f64 {
    let (n, s) = (x.n(), x.s());
    let nf = n as f64;
    let g = |v: f64| {
        let a = (v - 0.5).abs();
        5.0 / 3.0 - a / 4.0 - a * a / 4.0
    };
    let h = |u: f64, v: f64| {
        let (a, b, d) = ((u - 0.5).abs(), (v - 0.5).abs(), (u - v).abs());
        15.0 / 8.0 - a / 4.0 - b / 4.0 - 3.0 * d / 4.0 + d * d / 2.0
    };
    let single: f64 = (0..n)
        .map(|i| x.point(i).iter().map(|&v| g(v)).product::<f64>())
        .sum();
    let mut pair = 0.0;
    for i in 0..n {
        for l in 0..n {
            pair += (0..s)
                .map(|k| h(x.point(i)[k], x.point(l)[k]))
                .product::<f64>();
        }
    }
    (19.0f64 / 12.0).powi(s as i32) - 2.0 / nf * single + pair / (nf * nf)
}

#[test]
fn mixture_matches_brute_force_and_scipy() {
    use stillpoint_energies::discrepancy::mixture_squared;
    for &(n, s) in &[
        (1usize, 1usize),
        (3, 2),
        (17, 5),
        (64, 7),
        (100, 12),
        (50, 30),
    ] {
        let mut x = random_set(n, s, 70 + n as u64 * s as u64);
        if n >= 3 {
            x.point_mut(0)[0] = 0.0;
            x.point_mut(1)[s - 1] = 1.0;
            x.point_mut(2)[0] = 0.5;
        }
        let (got, want) = (mixture_squared(&x), bf_mixture(&x));
        assert!(rel(got, want) < 1e-12, "n={n} s={s}: {got} vs {want}");
    }
    // The set of `values_match_scipy_and_exact_rationals`: qmc.discrepancy(X,
    // method='MD') with SciPy 1.17.1 gives 0.07171546364007941; the closed form in
    // `fractions.Fraction`, rounded once, 0.07171546364008101.
    let x = PointSet::from_rows(&[
        [0.12, 0.83, 0.47],
        [0.65, 0.21, 0.94],
        [0.38, 0.56, 0.09],
        [0.91, 0.34, 0.62],
        [0.27, 0.05, 0.78],
        [0.54, 0.97, 0.31],
    ])
    .unwrap();
    let v = mixture_squared(&x);
    assert!(rel(v, 0.07171546364008101) < 1e-13, "{v} vs exact");
    assert!(rel(v, 0.07171546364007941) < 1e-12, "{v} vs SciPy");
}

#[test]
fn the_five_kinds_fused_have_the_bits_of_each_alone() {
    use stillpoint_energies::discrepancy::{
        mixture_squared, squared_discrepancies, squared_discrepancies_with_mixture,
    };
    // n = 300 spans several blocks (and rounds of the schedule); n = 5 one partial block.
    for &(n, s) in &[(5usize, 3usize), (77, 9), (300, 4)] {
        let x = random_set(n, s, 500 + n as u64);
        let five = squared_discrepancies_with_mixture(&x);
        let four = squared_discrepancies(&x, &KINDS[..4]);
        for (m, &kind) in KINDS[..4].iter().enumerate() {
            let alone = squared_discrepancies(&x, &[kind])[0];
            assert_eq!(five[m].to_bits(), alone.to_bits(), "{kind:?} n={n}");
            assert_eq!(four[m].to_bits(), alone.to_bits(), "{kind:?} n={n}");
            assert_eq!(
                energy(kind).value(&x).to_bits(),
                alone.to_bits(),
                "{kind:?} n={n}"
            );
        }
        assert_eq!(five[4].to_bits(), mixture_squared(&x).to_bits(), "n={n}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| squared_discrepancies_with_mixture(&x));
        assert_eq!(one.map(f64::to_bits), five.map(f64::to_bits), "n={n}");
    }
}

#[test]
fn mixture_root_takes_the_logarithmic_form_beyond_s_954() {
    use stillpoint_energies::discrepancy::{
        mixture_closed_form_fits, mixture_root, mixture_root_by_logs, mixture_squared,
    };
    // (15/8)^954 ≈ e^599.7, the largest product of the closed form, is the last to fit.
    assert!(mixture_closed_form_fits(954));
    assert!(!mixture_closed_form_fits(955));
    for s in [1, 7, 60, 400, 954] {
        let x = random_set(12, s, 30 + s as u64);
        let plain = mixture_squared(&x).sqrt();
        assert_eq!(mixture_root(&x).to_bits(), plain.to_bits(), "s={s}");
        let logs = mixture_root_by_logs(&x);
        assert!(rel(logs, plain) < 1e-10, "s={s}: {logs} vs {plain}");
    }
    // Beyond, the plain products overflow while the root is representable.
    let x = random_set(12, 1500, 5);
    assert!(!mixture_squared(&x).is_finite());
    let root = mixture_root(&x);
    assert!(root.is_finite() && root > 1e100, "{root}");
}

#[test]
fn reflection_changes_only_the_anchored_kinds() {
    // x ↦ 1 − x in one coordinate maps B₁ to −B₁ in both arguments and keeps B₂, |x − y|
    // and |x − ½|: the centred, wrap-around and both smoothness-2 kernels are unchanged,
    // while the star and modified L2, anchored at the origin, are not.
    let x = random_set(40, 6, 91);
    let mut y = x.clone();
    for i in 0..40 {
        let v = y.point(i)[2];
        y.point_mut(i)[2] = 1.0 - v;
    }
    for &kind in &KINDS {
        let (a, b) = (energy(kind).value(&x), energy(kind).value(&y));
        let anchored = matches!(kind, DiscrepancyKind::StarL2 | DiscrepancyKind::ModifiedL2);
        if anchored {
            assert!(rel(a, b) > 1e-3, "{kind:?}: {a} vs {b}");
        } else {
            assert!(
                (a - b).abs() <= 1e-13 * a.abs().max(1.0),
                "{kind:?}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn curved_and_standard_differ_by_the_weighted_second_moment_in_one_dimension() {
    // At s = 1 the two kernels differ only in B₂(x)B₂(y)'s coefficient, so
    // D²_curved − D²_smooth = γ (c_curved − c_smooth) (mean of B₂(x_k))².
    for (n, seed) in [(1usize, 3u64), (7, 4), (50, 5)] {
        let x = random_set(n, 1, seed);
        let mean_b2 = (0..n).map(|k| b2(x.point(k)[0])).sum::<f64>() / n as f64;
        let want = GAMMA
            * (b2b2(DiscrepancyKind::Curved) - b2b2(DiscrepancyKind::Smooth))
            * mean_b2
            * mean_b2;
        let got =
            energy(DiscrepancyKind::Curved).value(&x) - energy(DiscrepancyKind::Smooth).value(&x);
        assert!((got - want).abs() < 1e-14, "n={n}: {got} vs {want}");
        assert!(want > 0.0);
    }
}
