//! Checks of the one pass over the pairs of a quality report: every figure has the same
//! bits as the pass that computes it alone (the five squared discrepancies, the two
//! smallest distances, U_{q,p}), for every energy the pass fuses and for those it leaves
//! to a pass of their own, and for any number of threads.

use stillpoint_energies::discrepancy::squared_discrepancies_with_mixture;
use stillpoint_energies::pairs::min_squared_distances;
use stillpoint_energies::report_pairs::{pair_figures, PairFigures};
use stillpoint_energies::{Distance, Energy, PointSet, Uqp};

mod common;
use common::random_set;

fn energies() -> Vec<Uqp> {
    [
        (Distance::Q(1.0), 0.05),
        (Distance::Q(1.0), 1.0),
        (Distance::Torus, 0.7),
        (Distance::Euclidean, 2.5),
        (Distance::Q(0.3), 0.4),
        (Distance::Q(2.0), 1.0),
    ]
    .into_iter()
    .map(|(d, p)| Uqp::new(d, p).unwrap())
    .collect()
}

/// The figures from the passes of their own, as bit patterns.
fn alone(p: &PointSet, energy: Option<&Uqp>) -> Vec<u64> {
    let mut v: Vec<u64> = squared_discrepancies_with_mixture(p)
        .iter()
        .chain(&min_squared_distances(p.as_slice(), p.n(), p.s()))
        .map(|x| x.to_bits())
        .collect();
    v.extend(energy.map(|e| e.value(p).to_bits()));
    v
}

fn bits(f: &PairFigures) -> Vec<u64> {
    f.squares
        .iter()
        .chain(&f.min_squared_distances)
        .chain(&f.energy)
        .map(|x| x.to_bits())
        .collect()
}

#[test]
fn every_figure_has_the_bits_of_its_own_pass() {
    // Sizes around the vector width (16 lanes, parts of 4), the smallest block (32) and
    // the most blocks (64), where the masks and the skipped parts differ.
    for (n, s) in [
        (2, 1),
        (3, 2),
        (5, 3),
        (17, 4),
        (33, 5),
        (100, 7),
        (1001, 3),
        (2050, 20),
    ] {
        let p = random_set(n, s, 7 + n as u64);
        assert_eq!(bits(&pair_figures(&p, None)), alone(&p, None), "n = {n}");
        for e in energies() {
            let f = pair_figures(&p, Some(&e));
            assert_eq!(
                bits(&f),
                alone(&p, Some(&e)),
                "n = {n}, s = {s}, {}",
                e.name()
            );
        }
    }
}

#[test]
fn coordinates_at_one_and_coinciding_points_keep_the_bits() {
    // A coordinate at 1 is 0 on the torus, so the periodic energies take their own pass;
    // coinciding points make the energies infinite and the distances 0.
    let mut x = random_set(40, 3, 3).as_slice().to_vec();
    x[4] = 1.0;
    x[7] = 0.0;
    x.copy_within(0..3, 9);
    let p = PointSet::new(40, 3, x).unwrap();
    for e in energies() {
        let f = pair_figures(&p, Some(&e));
        assert_eq!(bits(&f), alone(&p, Some(&e)), "{}", e.name());
        assert_eq!(f.min_squared_distances[0], 0.0);
        assert_eq!(f.energy, Some(f64::INFINITY), "{}", e.name());
    }
}

#[test]
fn tiny_coordinates_keep_the_bits() {
    // Differences below 2^−1021, whose halves round (subnormal), where the pass's
    // multiply-adds take ½d unrounded; equal and reversed pairs of tiny values.
    let tiny = [
        0.0,
        f64::from_bits(1),
        f64::from_bits(3),
        f64::MIN_POSITIVE,
        f64::MIN_POSITIVE + f64::from_bits(1),
        3.0 * f64::MIN_POSITIVE,
        1e-310,
    ];
    let mut x = random_set(60, 3, 5).as_slice().to_vec();
    for (i, v) in x.iter_mut().enumerate().filter(|(i, _)| i % 3 != 1) {
        *v = tiny[i % tiny.len()];
    }
    let p = PointSet::new(60, 3, x).unwrap();
    assert_eq!(bits(&pair_figures(&p, None)), alone(&p, None));
    for e in energies() {
        let f = pair_figures(&p, Some(&e));
        assert_eq!(bits(&f), alone(&p, Some(&e)), "{}", e.name());
    }
}

#[test]
fn a_single_point_has_no_pair() {
    let p = PointSet::new(1, 3, vec![0.2, 0.5, 0.9]).unwrap();
    let e = Uqp::new(Distance::Q(1.0), 0.5).unwrap();
    let f = pair_figures(&p, Some(&e));
    assert_eq!(f.min_squared_distances, [f64::INFINITY; 2]);
    assert_eq!(f.energy, Some(0.0));
    assert_eq!(bits(&f), alone(&p, Some(&e)));
}

#[test]
fn the_same_bits_for_any_number_of_threads() {
    let p = random_set(3000, 6, 11);
    let e = Uqp::new(Distance::Q(1.0), 0.05).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| bits(&pair_figures(&p, Some(&e))))
    };
    let one = run(1);
    assert_eq!(run(2), one);
    assert_eq!(run(3), one);
}
