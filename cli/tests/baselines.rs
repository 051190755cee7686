//! Checks of the baseline point generators in `stillpoint::sequences`: the structure each
//! construction promises (nets, stratification, lattices, Latin hypercubes), the exact
//! formulas, seeding and determinism, and the refusals of bad input.

use stillpoint::quality::metrics::{min_distance_euclidean, min_distance_periodic, modified_l2};
use stillpoint::sequences::{
    halton_scrambled, hua_wang, korobov_p2, lattice, lattice_generator, lhs, lhs_maximin, random,
    sobol_plain, sobol_scrambled, Baseline,
};
use stillpoint::{Error, PointSet};

mod common;
use common::bits;

fn column(p: &PointSet, j: usize) -> Vec<f64> {
    p.rows().map(|r| r[j]).collect()
}

/// The name of the argument an error blames, or a panic if it is not an argument error.
fn blamed<T: std::fmt::Debug>(r: Result<T, Error>) -> String {
    match r {
        Err(Error::InvalidArgument { name, .. }) => name,
        other => panic!("expected an argument error, got {other:?}"),
    }
}

/// Asserts that every value of `xs`, scaled by `cells`, falls in a distinct integer cell
/// and that all `cells` cells are hit (so xs.len() == cells).
fn assert_one_per_cell(xs: &[f64], cells: u64, what: &str) {
    assert_eq!(xs.len() as u64, cells, "{what}: wrong count");
    let mut hit = vec![false; cells as usize];
    for &x in xs {
        let c = (x * cells as f64).floor() as usize;
        assert!(c < hit.len(), "{what}: {x} outside [0,1)");
        assert!(!hit[c], "{what}: two points in cell {c} of {cells}");
        hit[c] = true;
    }
}

// ---------------------------------------------------------------------------------------
// The common API.
// ---------------------------------------------------------------------------------------

#[test]
fn every_baseline_has_the_right_shape_and_stays_in_the_unit_cube() {
    for &b in Baseline::all() {
        for (n, s) in [(1, 1), (2, 3), (3, 2), (7, 2), (89, 2), (100, 5), (257, 12)] {
            let p = b.generate(n, s, 11).unwrap();
            assert_eq!((p.n(), p.s()), (n, s), "{b} shape");
            assert!(
                p.as_slice()
                    .iter()
                    .all(|&v| v.is_finite() && (0.0..1.0).contains(&v)),
                "{b} ({n}, {s}) left [0,1)"
            );
        }
    }
}

#[test]
fn every_baseline_refuses_empty_shapes_naming_the_argument() {
    for &b in Baseline::all() {
        assert_eq!(blamed(b.generate(0, 3, 1)), "n", "{b}");
        assert_eq!(blamed(b.generate(5, 0, 1)), "s", "{b}");
    }
}

#[test]
fn generator_limits_are_refused_naming_the_argument_and_range() {
    for (r, name, range) in [
        (sobol_plain(4, 21_202).map(|_| ()), "s", "21201"),
        (
            sobol_scrambled((1 << 32) + 1, 1, 0).map(|_| ()),
            "n",
            "4294967296",
        ),
        (halton_scrambled(4, 100_001, 0).map(|_| ()), "s", "100000"),
        (lhs_maximin(20_001, 2, 0).map(|_| ()), "n", "20000"),
    ] {
        let msg = r.clone().unwrap_err().to_string();
        assert_eq!(blamed(r), name);
        assert!(msg.contains(range), "message {msg:?} should state {range}");
    }
}

#[test]
fn unknown_baseline_names_are_refused_naming_the_argument() {
    for bad in ["", "owen", "sobol2", "halton-", "latin"] {
        let err = Baseline::parse(bad).unwrap_err();
        let msg = err.to_string();
        assert_eq!(blamed::<Baseline>(Err(err)), "baseline");
        for &b in Baseline::all() {
            assert!(msg.contains(b.name()), "{msg:?} should list {}", b.name());
        }
    }
}

#[test]
fn names_aliases_and_labels() {
    let all = Baseline::all();
    assert_eq!(all.len(), 8);
    for (i, &b) in all.iter().enumerate() {
        assert_eq!(Baseline::parse(b.name()).unwrap(), b);
        assert_eq!(b.name().parse::<Baseline>().unwrap(), b);
        assert_eq!(b.to_string(), b.name());
        assert!(b.describe().len() > 100, "{b}: describe too short");
        assert!(all[..i].iter().all(|&o| o != b && o.name() != b.name()));
    }
    for (alias, b) in [
        ("hs", Baseline::ScrambledHalton),
        ("HS", Baseline::ScrambledHalton),
        ("ss", Baseline::Sobol),
        ("hw", Baseline::HuaWang),
        (" Lhs_Maximin ", Baseline::LhsMaximin),
    ] {
        assert_eq!(Baseline::parse(alias).unwrap(), b, "{alias}");
    }
    let labels: Vec<&str> = all.iter().map(|b| b.label()).collect();
    assert_eq!(
        labels,
        [
            "random",
            "Halton",
            "HS",
            "SS",
            "HW",
            "lattice",
            "LHS",
            "LHS-maximin"
        ]
    );
    let randomized: Vec<bool> = all.iter().map(|b| b.is_randomized()).collect();
    assert_eq!(
        randomized,
        [true, false, true, true, false, false, true, true]
    );
    assert!(Baseline::Sobol.describe().contains("LMS"));
}

#[test]
fn same_seed_same_bits_and_only_randomized_baselines_use_the_seed() {
    for &b in Baseline::all() {
        let a = b.generate(60, 4, 7).unwrap();
        assert_eq!(bits(&a), bits(&b.generate(60, 4, 7).unwrap()), "{b}");
        let other = b.generate(60, 4, 8).unwrap();
        assert_eq!(bits(&a) != bits(&other), b.is_randomized(), "{b}");
    }
    assert_eq!(
        bits(&Baseline::Random.generate(30, 2, 3).unwrap()),
        bits(&random(30, 2, 3).unwrap())
    );
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    // Sizes large enough to take the parallel paths (per-column work, the Korobov search,
    // the maximin distance rows).
    let cases = [
        (Baseline::Sobol, 4096, 10),
        (Baseline::ScrambledHalton, 4096, 10),
        (Baseline::Lattice, 3000, 6),
        (Baseline::LhsMaximin, 3000, 12),
    ];
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for (b, n, s) in cases {
        let serial = one.install(|| b.generate(n, s, 5).unwrap());
        let parallel = b.generate(n, s, 5).unwrap();
        assert_eq!(bits(&serial), bits(&parallel), "{b}");
    }
}

// ---------------------------------------------------------------------------------------
// Sobol'.
// ---------------------------------------------------------------------------------------

#[test]
fn sobol_plain_matches_the_known_first_points() {
    let p = sobol_plain(8, 3).unwrap();
    // Natural order, Joe–Kuo D6: v_1 = (1/2, 1/2, 1/2), v_2 = (1/4, 3/4, 3/4),
    // v_3 = (1/8, 5/8, 3/8); point i is the XOR of v_k over the set bits of i.
    let want = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.5],
        [0.25, 0.75, 0.75],
        [0.75, 0.25, 0.25],
        [0.125, 0.625, 0.375],
        [0.625, 0.125, 0.875],
        [0.375, 0.375, 0.625],
        [0.875, 0.875, 0.125],
    ];
    for (i, w) in want.iter().enumerate() {
        assert_eq!(p.point(i), w, "point {i}");
    }
    // The same set as SciPy's Sobol(d=3, scramble=False).random(8), listed in Gray-code order.
    let scipy = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.5],
        [0.75, 0.25, 0.25],
        [0.25, 0.75, 0.75],
        [0.375, 0.375, 0.625],
        [0.875, 0.875, 0.125],
        [0.625, 0.125, 0.875],
        [0.125, 0.625, 0.375],
    ];
    for q in scipy {
        assert!(p.rows().any(|r| r == q), "{q:?} missing");
    }
}

#[test]
fn sobol_plain_is_a_net_in_every_dimension_pair_of_the_first_two() {
    let m = 10;
    let p = sobol_plain(1 << m, 20).unwrap();
    for j in 0..20 {
        assert_one_per_cell(&column(&p, j), 1 << m, &format!("dim {j}"));
    }
    assert_02m_net(&p, m, "plain");
}

/// Dimensions 1 and 2 (0-based 0, 1) form a (0, m, 2)-net: every elementary interval
/// [a/2^k, (a+1)/2^k) × [b/2^(m−k), (b+1)/2^(m−k)) holds exactly one point.
fn assert_02m_net(p: &PointSet, m: u32, what: &str) {
    for k in 0..=m {
        let (cx, cy) = (1u64 << k, 1u64 << (m - k));
        let mut hit = vec![false; 1 << m];
        for r in p.rows() {
            let a = (r[0] * cx as f64).floor() as u64;
            let b = (r[1] * cy as f64).floor() as u64;
            let cell = (a * cy + b) as usize;
            assert!(
                !hit[cell],
                "{what}: split {k}/{}: cell ({a}, {b}) twice",
                m - k
            );
            hit[cell] = true;
        }
    }
}

#[test]
fn scrambled_sobol_keeps_the_net_structure() {
    for seed in [0, 1, 2, 42, u64::MAX] {
        for m in [1, 4, 7, 11] {
            let p = sobol_scrambled(1 << m, 6, seed).unwrap();
            for j in 0..6 {
                assert_one_per_cell(
                    &column(&p, j),
                    1 << m,
                    &format!("seed {seed} m {m} dim {j}"),
                );
            }
            assert_02m_net(&p, m, &format!("seed {seed} m {m}"));
        }
    }
}

#[test]
fn scrambled_sobol_is_random_below_the_net_resolution_and_seeded() {
    let a = sobol_scrambled(256, 4, 1).unwrap();
    let b = sobol_scrambled(256, 4, 2).unwrap();
    assert_ne!(bits(&a), bits(&b));
    assert_ne!(bits(&a), bits(&sobol_plain(256, 4).unwrap()));
    // The bits below 2^−32 are filled in, not left zero as in the net.
    let fine = a
        .as_slice()
        .iter()
        .filter(|&&v| (v * 2f64.powi(32)).fract() != 0.0)
        .count();
    assert!(
        fine > 1000,
        "only {fine} of 1024 values use bits below 2^-32"
    );
    // A longer run starts with the shorter one (natural order, same scramble).
    let long = sobol_scrambled(1000, 4, 1).unwrap();
    assert_eq!(bits(&a), bits(&long)[..1024]);
}

#[test]
fn scrambled_sobol_beats_random_on_the_modified_l2_discrepancy() {
    let seeds = 0..10u64;
    let mean = |f: &dyn Fn(u64) -> PointSet| {
        seeds.clone().map(|sd| modified_l2(&f(sd))).sum::<f64>() / 10.0
    };
    let ss = mean(&|sd| sobol_scrambled(1024, 2, sd).unwrap());
    let mc = mean(&|sd| random(1024, 2, sd).unwrap());
    eprintln!("mean D_MD at n = 1024, s = 2: scrambled Sobol' {ss:.3e}, random {mc:.3e}");
    assert!(ss * 10.0 < mc, "scrambled Sobol' {ss} vs random {mc}");
}

// ---------------------------------------------------------------------------------------
// Scrambled Halton.
// ---------------------------------------------------------------------------------------

#[test]
fn scrambled_halton_stratifies_every_dimension_in_its_base() {
    let n = 2200;
    for seed in [0, 3, 99] {
        let p = halton_scrambled(n, 8, seed).unwrap();
        for (j, b) in [2u64, 3, 5, 7, 11, 13, 17, 19].into_iter().enumerate() {
            let col = column(&p, j);
            let mut cells = b;
            while cells as usize <= n {
                assert_one_per_cell(
                    &col[..cells as usize],
                    cells,
                    &format!("seed {seed} base {b}"),
                );
                cells *= b;
            }
        }
    }
}

#[test]
fn scrambled_halton_is_a_seeded_extensible_sequence() {
    let short = halton_scrambled(100, 5, 4).unwrap();
    let long = halton_scrambled(700, 5, 4).unwrap();
    assert_eq!(bits(&short), bits(&long)[..500]);
    assert_ne!(bits(&short), bits(&halton_scrambled(100, 5, 5).unwrap()));
    // Index 0 is scrambled too: not the origin.
    assert!(short.point(0).iter().all(|&v| v > 0.0));
    // Bases far above n (the 300th prime is 1987) still give distinct values.
    let wide = halton_scrambled(50, 300, 1).unwrap();
    let mut last = column(&wide, 299);
    last.sort_by(f64::total_cmp);
    last.dedup();
    assert_eq!(last.len(), 50);
}

// ---------------------------------------------------------------------------------------
// Hua–Wang.
// ---------------------------------------------------------------------------------------

#[test]
fn hua_wang_equals_the_formula() {
    // p = smallest prime ≥ 2s + 3: 7 for s = 2, 11 for s = 4, 17 for s = 6 (15 is not prime).
    for (s, p) in [(1, 5.0), (2, 7.0), (4, 11.0), (6, 17.0)] {
        let x = hua_wang(2000, s).unwrap();
        for (k, row) in x.rows().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                let gamma = 2.0 * (2.0 * std::f64::consts::PI * (j + 1) as f64 / p).cos();
                let want = ((k + 1) as f64 * gamma).rem_euclid(1.0);
                let diff = (v - want).abs();
                assert!(
                    diff.min(1.0 - diff) < 1e-9,
                    "s {s} k {} j {}: {v} vs {want}",
                    k + 1,
                    j + 1
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Lattices.
// ---------------------------------------------------------------------------------------

#[test]
fn lattice_points_are_frac_kz_over_n_for_the_reported_generator() {
    for (n, s) in [
        (1, 3),
        (2, 2),
        (89, 2),
        (100, 2),
        (101, 3),
        (64, 4),
        (1000, 5),
    ] {
        let z = lattice_generator(n, s).unwrap();
        assert_eq!(z.len(), s);
        assert_eq!(z[0], 1);
        let p = lattice(n, s).unwrap();
        for (k, row) in p.rows().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                let want = ((k as u64 * z[j]) % n as u64) as f64 / n as f64;
                assert_eq!(v, want, "n {n} k {k} j {j}");
            }
        }
        assert!(p.point(0).iter().all(|&v| v == 0.0), "unshifted");
        // Each coordinate is a multiple of 1/n, and each multiple occurs once.
        for j in 0..s {
            let mut seen = vec![false; n];
            for v in column(&p, j) {
                let c = (v * n as f64).round();
                assert!((v * n as f64 - c).abs() < 1e-9, "n {n} dim {j}: {v}");
                assert!(
                    !std::mem::replace(&mut seen[c as usize], true),
                    "n {n} dim {j}: {v} twice"
                );
            }
        }
    }
}

#[test]
fn two_dimensional_fibonacci_lattices() {
    let fib = [
        1u64, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 233, 377, 610, 987, 1597,
    ];
    for m in 6..fib.len() {
        let n = fib[m] as usize;
        assert_eq!(
            lattice_generator(n, 2).unwrap(),
            vec![1, fib[m - 1]],
            "n {n}"
        );
        // Fibonacci lattices are nearly square or hexagonal: separation about 1/√n on the
        // torus (a random set's shrinks like 1/n). For n = F_{2k+1} = F_k² + F_{k+1}² the
        // shortest lattice vector is (F_k, F_{k+1})/n, of length exactly 1/√n; for even
        // indices it tends to (4/5)^(1/4)/√n ≈ 0.946/√n.
        let d = min_distance_periodic(&lattice(n, 2).unwrap()) * (n as f64).sqrt();
        assert!(d > 0.92, "n {n}: separation·√n = {d}");
        let fib_index = m + 1;
        if fib_index % 2 == 1 {
            assert!(
                (d - 1.0).abs() < 1e-9,
                "n = F_{fib_index}: separation·√n = {d}"
            );
        }
    }
    // Not a Fibonacci number: a Korobov search, not (1, F_{m−1}).
    assert_eq!(lattice_generator(100, 2).unwrap()[0], 1);
}

#[test]
fn korobov_generator_minimises_p2_over_all_multipliers() {
    for (n, s) in [(100, 2), (101, 3), (64, 4), (127, 5), (210, 3)] {
        let z = lattice_generator(n, s).unwrap();
        let chosen = korobov_p2(n, &z).unwrap();
        let mut worst: f64 = 0.0;
        for a in 1..n as u64 {
            if gcd(a, n as u64) != 1 {
                continue;
            }
            let za: Vec<u64> = (0..s as u32)
                .map(|j| ((a as u128).pow(j) % n as u128) as u64)
                .collect();
            let p2 = korobov_p2(n, &za).unwrap();
            assert!(
                chosen <= p2 * (1.0 + 1e-12),
                "n {n} s {s}: chosen {z:?} P2 {chosen} > a = {a}: {p2}"
            );
            worst = worst.max(p2);
        }
        assert!(
            chosen * 2.0 < worst,
            "n {n} s {s}: search made no difference"
        );
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

#[test]
fn korobov_p2_closed_form_matches_its_series() {
    // One point at the origin: every term 1 + 2π²/6 = 1 + π²/3.
    let c = 1.0 + std::f64::consts::PI.powi(2) / 3.0;
    assert!((korobov_p2(1, &[1, 1]).unwrap() - (c * c - 1.0)).abs() < 1e-12);
    // The grid k/n: the dual lattice is nℤ, so P_2 = Σ_{h≠0} (nh)^−2 = π²/(3n²).
    for n in [2usize, 10, 97, 1000] {
        let want = std::f64::consts::PI.powi(2) / (3.0 * (n * n) as f64);
        let got = korobov_p2(n, &[1]).unwrap();
        assert!(
            (got - want).abs() < 1e-9 * want.max(1e-6),
            "n {n}: {got} vs {want}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Latin hypercubes.
// ---------------------------------------------------------------------------------------

/// Each column has exactly one value in each stratum [i/n, (i+1)/n).
fn assert_latin(p: &PointSet, what: &str) {
    let n = p.n();
    for j in 0..p.s() {
        let mut col = column(p, j);
        col.sort_by(f64::total_cmp);
        for (i, &v) in col.iter().enumerate() {
            let (lo, hi) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
            assert!(
                lo <= v && v < hi,
                "{what}: column {j}: {v} not in stratum {i}"
            );
        }
    }
}

#[test]
fn lhs_puts_one_point_in_each_stratum_of_each_column() {
    for (n, s) in [(1, 1), (2, 5), (10, 3), (997, 4), (5000, 2)] {
        for seed in [0, 1, 77] {
            assert_latin(
                &lhs(n, s, seed).unwrap(),
                &format!("lhs n {n} s {s} seed {seed}"),
            );
        }
    }
}

#[test]
fn lhs_maximin_stays_latin_and_never_loses_separation() {
    for (n, s) in [(3, 2), (20, 2), (50, 3), (100, 5), (300, 8)] {
        for seed in 0..4 {
            let start = lhs(n, s, seed).unwrap();
            let best = lhs_maximin(n, s, seed).unwrap();
            let what = format!("n {n} s {s} seed {seed}");
            assert_latin(&best, &what);
            let (d0, d1) = (
                min_distance_euclidean(&start),
                min_distance_euclidean(&best),
            );
            assert!(d1 >= d0, "{what}: {d1} < start {d0}");
            // The same multiset of coordinates per column: only swaps happened.
            for j in 0..s {
                let (mut a, mut b) = (column(&start, j), column(&best, j));
                a.sort_by(f64::total_cmp);
                b.sort_by(f64::total_cmp);
                assert_eq!(a, b, "{what}: column {j} changed values");
            }
        }
    }
}

#[test]
fn lhs_maximin_clearly_improves_a_small_design() {
    for seed in 0..5 {
        let d0 = min_distance_euclidean(&lhs(50, 3, seed).unwrap());
        let d1 = min_distance_euclidean(&lhs_maximin(50, 3, seed).unwrap());
        eprintln!("seed {seed}: min distance {d0:.4} -> {d1:.4}");
        assert!(d1 > 1.5 * d0, "seed {seed}: {d0} -> {d1}");
    }
}
