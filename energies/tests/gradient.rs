//! Finite-difference checks of the U_{q,p} gradient (eqs. 14–18) and its properties.

use stillpoint_energies::{Distance, Energy, PointSet, Uqp};

mod common;
use common::{fd_gradient, random_set, rel_err};

#[test]
fn gradient_matches_finite_differences() {
    let qs = [
        Distance::Q(0.3),
        Distance::Q(1.0),
        Distance::Q(2.0),
        Distance::Q(0.055),
        Distance::Q(3.7),
        Distance::Torus,
        Distance::Euclidean,
    ];
    let mut worst: f64 = 0.0;
    for (qi, &q) in qs.iter().enumerate() {
        for &p in &[0.5, 0.84, 1.0, 2.5] {
            for &s in &[1usize, 2, 7] {
                let x = random_set(8, s, 1000 + 31 * qi as u64 + s as u64);
                let e = Uqp::new(q, p).unwrap();
                let mut g = vec![0.0; x.coordinate_count()];
                let v = e.value_and_gradient(&x, &mut g);
                let v2 = e.value(&x);
                assert!((v - v2).abs() <= 1e-13 * v2.abs(), "value paths differ");
                let fd = fd_gradient(&e, &x, 1e-6);
                let err = rel_err(&g, &fd);
                worst = worst.max(err);
                assert!(err < 1e-6, "q={q:?} p={p} s={s}: relative error {err:e}");
            }
        }
    }
    eprintln!("worst relative gradient error {worst:e}");
}

#[test]
fn energy_is_invariant_under_permutation_and_periodic_shift() {
    let x = random_set(30, 3, 5);
    let rev = PointSet::from_rows(&x.rows().rev().collect::<Vec<_>>()).unwrap();
    let shifted = PointSet::new(
        30,
        3,
        x.as_slice()
            .iter()
            .enumerate()
            .map(|(i, v)| (v + [0.37, 0.81, 0.05][i % 3]).fract())
            .collect(),
    )
    .unwrap();
    for q in [Distance::Q(0.4), Distance::Torus] {
        let e = Uqp::new(q, 0.9).unwrap();
        let u = e.value(&x);
        assert!((e.value(&rev) - u).abs() < 1e-12 * u);
        assert!((e.value(&shifted) - u).abs() < 1e-10 * u, "{q:?}");
    }
    // The Euclidean distance is not periodic: the shift changes the energy.
    let e = Uqp::new(Distance::Euclidean, 0.9).unwrap();
    assert!((e.value(&shifted) - e.value(&x)).abs() > 1e-6 * e.value(&x));
}

#[test]
fn two_points_closed_form() {
    // Two points at Euclidean distance d: U_{E,p} = 1/d for any p, gradient ±(x_i − x_j)/d³.
    let x = PointSet::from_rows(&[[0.1, 0.2], [0.4, 0.6]]).unwrap();
    let e = Uqp::new(Distance::Euclidean, 1.7).unwrap();
    let mut g = vec![0.0; 4];
    let u = e.value_and_gradient(&x, &mut g);
    assert!((u - 1.0 / 0.5).abs() < 1e-12);
    let want = [0.3 / 0.125, 0.4 / 0.125, -0.3 / 0.125, -0.4 / 0.125];
    for (a, b) in g.iter().zip(want) {
        assert!((a - b).abs() < 1e-10, "{g:?}");
    }
    // q = 1 in 1-D: d = Δ(1 − Δ) with Δ = 0.3 → U = 1/0.21.
    let y = PointSet::from_rows(&[[0.1], [0.4]]).unwrap();
    let e = Uqp::new(Distance::Q(1.0), 0.6).unwrap();
    assert!((e.value(&y) - 1.0 / 0.21).abs() < 1e-12);
}

#[test]
fn same_bits_for_one_and_two_threads() {
    let x = random_set(300, 5, 9);
    let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
    let run = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| {
                let mut g = vec![0.0; x.coordinate_count()];
                let u = e.value_and_gradient(&x, &mut g);
                (
                    u.to_bits(),
                    g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                )
            })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn coincident_points_give_infinite_energy_and_no_nan() {
    let x = PointSet::from_rows(&[[0.1, 0.2], [0.1, 0.2], [0.4, 0.2]]).unwrap();
    for q in [Distance::Euclidean, Distance::Q(0.5), Distance::Torus] {
        for p in [0.5, 1.0, 2.0] {
            let e = Uqp::new(q, p).unwrap();
            let mut g = vec![0.0; 6];
            let u = e.value_and_gradient(&x, &mut g);
            assert!(u.is_infinite(), "{q:?} {p}");
            assert!(g.iter().all(|v| v.is_finite()), "{q:?} {p}: {g:?}");
        }
    }
}
