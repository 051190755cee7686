//! The tent criterion as an energy: its gradient against finite differences, its
//! invariance under a periodic shift, and its bits under any thread count.

use stillpoint_energies::tent_kernel::TentKernel;
use stillpoint_energies::Energy;

mod common;
use common::{fd_gradient, random_set, rel_err};

#[test]
fn gradient_matches_finite_differences() {
    for (gamma, n, s) in [(0.05, 12, 4), (0.3, 9, 7), (1.0, 5, 1)] {
        let e = TentKernel::new(gamma).unwrap();
        let x = random_set(n, s, 40 + s as u64);
        let mut g = vec![0.0; x.coordinate_count()];
        let v = e.value_and_gradient(&x, &mut g);
        assert_eq!(v, e.value(&x));
        let err = rel_err(&g, &fd_gradient(&e, &x, 1e-6));
        assert!(err < 1e-6, "γ = {gamma}, s = {s}: relative error {err:e}");
    }
}

#[test]
fn a_periodic_shift_changes_nothing() {
    let e = TentKernel::new(0.3).unwrap();
    let x = random_set(20, 3, 7);
    let mut shifted = x.clone();
    for (i, v) in shifted.as_mut_slice().iter_mut().enumerate() {
        *v = (*v + 0.37 + 0.1 * (i % 3) as f64).fract();
    }
    assert!((e.value(&shifted) - e.value(&x)).abs() < 1e-13);
}

#[test]
fn same_bits_for_one_and_three_threads() {
    let e = TentKernel::new(0.05).unwrap();
    let x = random_set(40, 6, 3);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut g = vec![0.0; x.coordinate_count()];
            let v = e.value_and_gradient(&x, &mut g);
            (
                v.to_bits(),
                g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            )
        })
    };
    assert_eq!(run(1), run(3));
}
