//! Property tests: invariances and bounds of the energies and metrics over random point
//! sets, bit-exact round trips of every file format, parsers that never panic on any
//! input, and DEM runs that resume bit for bit from any snapshot.

use proptest::prelude::*;
use stillpoint::energies::{Distance, Energy, PeriodicCube, PointSet, Uqp};
use stillpoint::integrators::{Dem, DemState, Executor, Problem, Restart, Snapshot};
use stillpoint::io::{self, Format};
use stillpoint::metrics;
use stillpoint::post::shift;

mod common;
use common::bits;

/// Relative closeness for sums taken in another order.
fn close(a: f64, b: f64, rel: f64) -> bool {
    a == b || (a - b).abs() <= rel * a.abs().max(b.abs())
}

/// n points in [0, 1)^s, n in 2..=max_n, s in 1..=max_s, no two closer than 1e-6 (the
/// energies are infinite for coincident points).
fn unit_sets(max_n: usize, max_s: usize) -> impl Strategy<Value = PointSet> {
    (2..=max_n, 1..=max_s)
        .prop_flat_map(|(n, s)| (Just(n), Just(s), prop::collection::vec(0.0f64..1.0, n * s)))
        .prop_map(|(n, s, data)| PointSet::new(n, s, data).unwrap())
        .prop_filter("points too close", |p| {
            metrics::min_distance_euclidean(p) > 1e-6
        })
}

/// A set with a permutation of its points.
fn permuted(p: &PointSet, seed: u64) -> PointSet {
    let mut order: Vec<usize> = (0..p.n()).collect();
    let mut state = seed | 1;
    for i in (1..order.len()).rev() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        order.swap(i, (state % (i as u64 + 1)) as usize);
    }
    let rows: Vec<&[f64]> = order.iter().map(|&i| p.point(i)).collect();
    PointSet::from_rows(&rows).unwrap()
}

fn all_metrics(p: &PointSet) -> [f64; 6] {
    [
        metrics::star_l2(p),
        metrics::modified_l2(p),
        metrics::centered_l2(p),
        metrics::wrap_around_l2(p),
        metrics::min_distance_euclidean(p),
        metrics::min_distance_periodic(p),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn metrics_and_energies_ignore_the_order_of_the_points(
        p in unit_sets(30, 5),
        seed in any::<u64>(),
        q in 0.05f64..2.0,
        pw in 0.2f64..2.0,
    ) {
        let r = permuted(&p, seed);
        for (a, b) in all_metrics(&p).iter().zip(all_metrics(&r)) {
            prop_assert!(close(*a, b, 1e-10), "{a} vs {b}");
        }
        for d in [Distance::Q(q), Distance::Torus, Distance::Euclidean] {
            let e = Uqp::new(d, pw).unwrap();
            let (a, b) = (e.value(&p), e.value(&r));
            prop_assert!(close(a, b, 1e-10), "{d:?}: {a} vs {b}");
        }
    }

    #[test]
    fn periodic_quantities_ignore_a_periodic_shift(
        p in unit_sets(30, 5),
        c in prop::collection::vec(0.0f64..1.0, 5),
        q in 0.05f64..2.0,
        pw in 0.2f64..2.0,
    ) {
        let shifted = shift::shifted(&p, &c[..p.s()]);
        prop_assert!(shifted.check_unit_cube().is_ok());
        // The wrap-around L2 discrepancy and the torus distance live on the torus.
        let (a, b) = (metrics::wrap_around_l2(&p), metrics::wrap_around_l2(&shifted));
        prop_assert!(close(a, b, 1e-9), "wrap-around L2 {a} vs {b}");
        let (a, b) = (metrics::min_distance_periodic(&p), metrics::min_distance_periodic(&shifted));
        prop_assert!(close(a, b, 1e-9), "periodic min distance {a} vs {b}");
        for d in [Distance::Q(q), Distance::Torus] {
            let e = Uqp::new(d, pw).unwrap();
            let (a, b) = (e.value(&p), e.value(&shifted));
            prop_assert!(close(a, b, 1e-9), "U_{{q,p}} {d:?}: {a} vs {b}");
        }
    }

    #[test]
    fn metrics_stay_within_their_bounds(p in unit_sets(40, 6)) {
        let s = p.s() as f64;
        let m = metrics::Metrics::compute(&p);
        for v in [m.star_l2, m.modified_l2, m.centered_l2, m.wrap_around_l2] {
            prop_assert!(v.is_finite() && v >= 0.0, "{v}");
        }
        // A local discrepancy of points in the unit cube is at most 1 in size.
        prop_assert!(m.star_l2 <= 1.0);
        prop_assert!(m.min_distance > 0.0 && m.min_distance <= s.sqrt());
        prop_assert!(m.min_distance_periodic <= m.min_distance);
        prop_assert!(m.min_distance_periodic <= s.sqrt() / 2.0 + 1e-15);
        // The struct is the functions, bit for bit.
        prop_assert_eq!(all_metrics(&p).map(f64::to_bits), [
            m.star_l2, m.modified_l2, m.centered_l2, m.wrap_around_l2,
            m.min_distance, m.min_distance_periodic,
        ].map(f64::to_bits));
    }

    #[test]
    fn energies_are_positive_and_finite(p in unit_sets(30, 4), q in 0.05f64..2.0, pw in 0.2f64..2.0) {
        for d in [Distance::Q(q), Distance::Torus, Distance::Euclidean] {
            let e = Uqp::new(d, pw).unwrap();
            let u = e.value(&p);
            prop_assert!(u.is_finite() && u > 0.0, "{d:?}: {u}");
            let mut g = vec![0.0; p.coordinate_count()];
            let u2 = e.value_and_gradient(&p, &mut g);
            prop_assert!(close(u, u2, 1e-9), "{u} vs {u2}");
            prop_assert!(g.iter().all(|v| v.is_finite()));
        }
    }
}

/// Any finite coordinates, with the values that printing most easily gets wrong mixed in.
fn any_sets() -> impl Strategy<Value = PointSet> {
    let coord = prop_oneof![
        4 => any::<f64>().prop_filter("finite", |v| v.is_finite()),
        4 => 0.0f64..1.0,
        1 => prop::sample::select(vec![
            0.0, -0.0, 1.0, 5e-324, f64::MIN_POSITIVE, f64::MAX, -f64::MAX,
            1.0 - f64::EPSILON / 2.0, 0.1, 1.0 / 3.0, 1e-5, 1e16, 1e16 - 2.0,
        ]),
    ];
    (1usize..=12, 1usize..=5)
        .prop_flat_map(move |(n, s)| {
            (
                Just(n),
                Just(s),
                prop::collection::vec(coord.clone(), n * s),
            )
        })
        .prop_map(|(n, s, data)| PointSet::new(n, s, data).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn every_format_round_trips_bit_for_bit(p in any_sets(), case in any::<u32>()) {
        let dir = std::env::temp_dir().join(format!(
            "stillpoint-props-{}-{case}",
            std::process::id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let meta = serde_json::json!({"generator": "props", "seed": case});
        for ext in ["csv", "tsv", "json", "npy", "dat"] {
            let path = dir.join(format!("p.{ext}"));
            io::write_points(&path, &p, &meta).unwrap();
            let back = io::read_points(&path).unwrap();
            prop_assert_eq!((back.n(), back.s()), (p.n(), p.s()), "{}", ext);
            prop_assert_eq!(bits(&back), bits(&p), "{}", ext);
        }
        // Text also round-trips without a file.
        for f in [Format::Csv, Format::Tsv] {
            let text = String::from_utf8(io::encode(&p, &meta, f)).unwrap();
            let back = io::parse_text(&text, "text").unwrap();
            prop_assert_eq!(bits(&back), bits(&p));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn the_text_parser_never_panics(text in any::<String>()) {
        let _ = io::parse_text(&text, "input");
    }

    #[test]
    fn the_text_parser_never_panics_on_number_like_text(
        text in "[0-9eE.,;+\\- \t\n#\"xna]{0,80}"
    ) {
        if let Ok(p) = io::parse_text(&text, "input") {
            prop_assert!(p.as_slice().iter().all(|v| v.is_finite()));
            prop_assert!(p.n() >= 1 && p.s() >= 1);
        }
    }

    #[test]
    fn the_expression_parser_never_panics(text in any::<String>(), s in 0usize..4) {
        if let Ok(g) = stillpoint::parse::expr::RegionExpr::parse(&text, s) {
            let _ = g.eval(&[0.5; 4]);
        }
    }

    #[test]
    fn the_expression_parser_never_panics_on_expression_like_text(
        text in "[xyz0-9 +*/^()|.,eE-]{0,40}|(abs|sqrt|min|max|sin|ln|pi|x1|x2|x3|[-+*/^(),| .0-9xy]){0,25}",
        s in 1usize..4,
        x in prop::collection::vec(-10.0f64..10.0, 3),
    ) {
        if let Ok(g) = stillpoint::parse::expr::RegionExpr::parse(&text, s) {
            let _ = g.eval(&x);
            let _ = g.eval(&x[..s - 1]);
        }
    }

    #[test]
    fn reading_any_bytes_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..200), which in 0usize..4) {
        let ext = ["csv", "json", "npy", "bin"][which];
        let path = std::env::temp_dir().join(format!(
            "stillpoint-props-bytes-{}-{ext}",
            std::process::id()
        ));
        // Half the time behind a real .npy header, to reach the data checks.
        let mut content = Vec::new();
        if which == 2 && bytes.first().is_some_and(|b| b % 2 == 0) {
            content.extend_from_slice(b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }");
            content.resize(10 + 0x76 - 1, b' ');
            content.push(b'\n');
        }
        content.extend_from_slice(&bytes);
        std::fs::write(&path, &content).unwrap();
        if let Ok(p) = io::read_points(&path) {
            prop_assert!(p.as_slice().iter().all(|v| v.is_finite()));
        }
        let _ = stillpoint::solve::checkpoint::read_checkpoint(&path);
        let _ = std::fs::remove_file(&path);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn the_dem_resumes_bit_for_bit_from_any_snapshot(
        n in 3usize..20,
        s in 1usize..4,
        seed in 0u64..1000,
        steps in 5usize..60,
        every in 1usize..9,
        eps in prop::sample::select(vec![0.0, 0.01, 0.05]),
    ) {
        let cube = PeriodicCube::new(s).unwrap();
        let start = stillpoint::Domain::sample(&cube, n, seed).unwrap();
        prop_assume!(metrics::min_distance_periodic(&start) > 1e-6);
        let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
        let dem = Dem {
            restart: if eps > 0.0 { Restart::Threshold(eps) } else { Restart::Off },
            ..Dem::default()
        };
        let problem = Problem::borrowed(&e, &cube).unwrap();
        let reference = Executor::new(&problem, dem.clone())
            .max_steps(steps)
            .run(start.clone())
            .unwrap();
        let mut states: Vec<Snapshot<DemState>> = Vec::new();
        let mut keep = |st: &Snapshot<DemState>| {
            states.push(st.clone());
            Ok(())
        };
        Executor::new(&problem, dem.clone())
            .max_steps(steps)
            .checkpoint(every, &mut keep)
            .run(start.clone())
            .unwrap();
        for st in states {
            let st: Snapshot<DemState> =
                serde_json::from_str(&serde_json::to_string(&st).unwrap()).unwrap();
            let step = st.step;
            let out = Executor::new(&problem, dem.clone())
                .max_steps(steps)
                .resume(Some(st))
                .run(start.clone())
                .unwrap();
            prop_assert_eq!(bits(&out.points), bits(&reference.points), "from step {}", step);
            prop_assert_eq!(out.trajectory.len(), reference.trajectory.len());
        }
    }
}

#[test]
fn star_and_modified_l2_are_not_shift_invariant() {
    // The anchored discrepancies see where the set sits in the cube: a shift moves them,
    // while the wrap-around L2 does not move.
    let p = stillpoint::sequences::halton(50, 2).unwrap();
    let c = [0.37, 0.61];
    let q = shift::shifted(&p, &c);
    assert!((metrics::star_l2(&p) - metrics::star_l2(&q)).abs() > 1e-4);
    assert!((metrics::modified_l2(&p) - metrics::modified_l2(&q)).abs() > 1e-4);
    assert!(close(
        metrics::wrap_around_l2(&p),
        metrics::wrap_around_l2(&q),
        1e-12
    ));
}
