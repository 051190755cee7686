//! Mixed design spaces: level balance, pair balance and slice stratification as
//! properties over random spaces and n; the written table read back; refusals.

use proptest::prelude::*;
use stillpoint::design::figures::{stratified, DesignFigures};
use stillpoint::design::{Design, DesignSpace, Kind};
use stillpoint::pipeline::request::Arg;
use stillpoint::{PointSet, Request};

/// The design the library's pipeline makes for `items` at `n` points.
fn design(n: usize, items: &[String], seed: u64) -> Design {
    let mut r = Request::default();
    r.set("n", Arg::Int(n as i128)).unwrap();
    r.set("space", Arg::Texts(items.to_vec())).unwrap();
    r.set("seed", Arg::Int(seed.into())).unwrap();
    r.resolve()
        .unwrap()
        .run(None, |_| {})
        .unwrap()
        .design
        .unwrap()
}

fn space_items(cont: usize, ints: &[i64], cats: &[usize]) -> Vec<String> {
    let mut v: Vec<String> = (0..cont).map(|k| format!("x{k}=uniform(0,1)")).collect();
    for (k, &hi) in ints.iter().enumerate() {
        v.push(format!("k{k}=int(1,{hi})"));
    }
    for (k, &l) in cats.iter().enumerate() {
        let labels: Vec<String> = (0..l).map(|i| format!("L{i}")).collect();
        v.push(format!("c{k}={{{}}}", labels.join(",")));
    }
    v
}

/// The largest distance of a count from ⌊n/L⌋..⌈n/L⌉, counted here from the levels.
fn excess(levels: &[usize], l: usize) -> usize {
    let n = levels.len();
    (0..l)
        .map(|k| {
            let c = levels.iter().filter(|&&x| x == k).count();
            c.saturating_sub(n.div_ceil(l))
                .max((n / l).saturating_sub(c))
        })
        .max()
        .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Every level of every discrete variable appears ⌊n/L⌋ or ⌈n/L⌉ times, and every
    /// continuous column is stratified, for any space and n.
    #[test]
    fn levels_are_as_even_as_n_allows(
        cont in 1usize..4,
        ints in proptest::collection::vec(2i64..7, 0..2),
        cats in proptest::collection::vec(2usize..5, 0..3),
        extra in 0usize..40,
        seed in 0u64..1000,
    ) {
        let items = space_items(cont, &ints, &cats);
        let n = cats.iter().copied().max().unwrap_or(1) + extra;
        let d = design(n, &items, seed);
        for (j, v) in d.space.vars.iter().enumerate() {
            if let Some(l) = v.kind.levels() {
                prop_assert_eq!(excess(&d.levels[j], l), 0, "{} at n = {}", v.name, n);
            } else {
                let col: Vec<f64> = (0..n).map(|i| d.unit.point(i)[j]).collect();
                prop_assert!(stratified(&col), "{} not stratified at n = {}", v.name, n);
            }
        }
        prop_assert!(d.unit.as_slice().iter().all(|u| (0.0..1.0).contains(u)));
    }

    /// One factor with n/L whole: a sliced Latin hypercube (every slice stratified in
    /// every continuous column, the whole too).
    #[test]
    fn one_factor_gives_a_sliced_latin_hypercube(
        cont in 1usize..5,
        l in 2usize..6,
        m in 1usize..12,
        seed in 0u64..1000,
    ) {
        let items = space_items(cont, &[], &[l]);
        let d = design(l * m, &items, seed);
        let f = DesignFigures::of(&d);
        prop_assert_eq!(f.slices[0].stratified, f.slices[0].columns);
        prop_assert_eq!(f.stratified, cont);
    }

    /// Two factors whose level-pair counts can be equal (n a multiple of L_a L_b):
    /// they are, and every slice of both is stratified when one L divides the other.
    #[test]
    fn nested_factors_are_balanced_in_pairs_and_sliced(
        la in 2usize..4,
        times in 1usize..3,
        m in 1usize..6,
        seed in 0u64..1000,
    ) {
        let lb = la * times;
        let items = space_items(2, &[], &[la, lb]);
        let n = la * lb * m;
        let d = design(n, &items, seed);
        let f = DesignFigures::of(&d);
        prop_assert_eq!(f.pairs[0].excess, 0);
        for s in &f.slices {
            prop_assert_eq!(s.stratified, s.columns, "slices of {} at n = {}", s.name, n);
        }
    }
}

#[test]
fn pair_counts_follow_an_orthogonal_array_of_three_factors() {
    // 2 × 2 × 2 in 8 runs: each pair of factors shows each of its 4 pairs twice.
    let d = design(8, &space_items(1, &[], &[2, 2, 2]), 3);
    let f = DesignFigures::of(&d);
    assert_eq!(f.pairs.len(), 3);
    assert!(f.pairs.iter().all(|p| p.excess == 0), "{:?}", f.pairs);
}

#[test]
fn the_written_table_reads_back_to_the_same_design() {
    let items = space_items(2, &[4], &[3]);
    let d = design(30, &items, 1);
    let text = d.to_text(&serde_json::json!({"seed": 1}), ',');
    let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
    assert_eq!(header, "x0,x1,k0,c0");
    let back = Design::from_text(&d.space, &text, "table").unwrap();
    assert_eq!(back.levels, d.levels);
    for (a, b) in back.unit.as_slice().iter().zip(d.unit.as_slice()) {
        assert!((a - b).abs() < 1e-15, "{a} vs {b}");
    }
    assert_eq!(DesignFigures::of(&back), DesignFigures::of(&d));
}

#[test]
fn ordered_and_integer_levels_keep_the_order_of_their_coordinate() {
    let d = design(
        40,
        &["x=uniform(0,1)".into(), "q=ordered{lo,mid,hi}".into()],
        0,
    );
    let base = stillpoint::generate(40, 2).unwrap();
    // The level of each point rises with its coordinate in the set it was dealt from.
    let mut pairs: Vec<(f64, usize)> = (0..40)
        .map(|i| (base.point(i)[1], d.levels[1][i]))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(pairs.windows(2).all(|w| w[0].1 <= w[1].1));
}

#[test]
fn refusals_name_the_variable_and_what_is_accepted() {
    let cases: [(&[&str], &str); 8] = [
        (&["c={}"], "one or more non-empty labels"),
        (&["c={a,,b}"], "one or more non-empty labels"),
        (&["c={a,a}"], "distinct labels"),
        (&["x=normal(0,-1)"], "sigma"),
        (&["x=beta(0,1)"], "beta"),
        (&["k=int(5,1)"], "lo ≤ hi"),
        (&["x=uniform(0,1)", "x=uniform(0,2)"], "already a variable"),
        (&["x=gamma(2)"], "one of uniform(lo,hi)"),
    ];
    for (items, expected) in cases {
        let e = DesignSpace::parse("--var", items).unwrap_err().to_string();
        assert!(
            e.contains("--var") && e.contains(expected),
            "{items:?}: {e}"
        );
    }
    let mut r = Request::default();
    r.set("n", Arg::Int(2)).unwrap();
    r.set("space", Arg::Texts(vec!["c={a,b,c}".into()]))
        .unwrap();
    let e = r.resolve().unwrap_err().to_string();
    assert!(e.contains("at least 3 points") && e.contains("c"), "{e}");
    r.set("n", Arg::Int(9)).unwrap();
    r.set("randomize", Arg::Bool(true)).unwrap();
    r.set("goal", Arg::Text("space-filling".into())).unwrap();
    let e = r.resolve().unwrap_err().to_string();
    assert!(e.contains("randomize") && e.contains("tent"), "{e}");
}

#[test]
fn a_space_given_with_another_dimension_is_refused() {
    let mut r = Request::default();
    r.set("n", Arg::Int(10)).unwrap();
    r.set("s", Arg::Int(3)).unwrap();
    r.set(
        "space",
        Arg::Texts(vec!["x=uniform(0,1)".into(), "c={a,b}".into()]),
    )
    .unwrap();
    let e = r.resolve().unwrap_err().to_string();
    assert!(e.contains("number of variables"), "{e}");
}

#[test]
fn kinds_report_their_levels() {
    let s = DesignSpace::parse(
        "space",
        &["k=int(-2,2)", "c=ordered{a,b}", "x=uniform(0,1)"],
    )
    .unwrap();
    let levels: Vec<Option<usize>> = s.vars.iter().map(|v| v.kind.levels()).collect();
    assert_eq!(levels, [Some(5), Some(2), None]);
    assert!(matches!(s.vars[1].kind, Kind::Levels { ordered: true, .. }));
    let _ = PointSet::new(1, 1, vec![0.5]).unwrap();
}

#[test]
fn a_space_filling_design_spreads_the_type_aware_distance_and_keeps_its_slices() {
    let items = space_items(2, &[5], &[3]);
    let mut r = Request::default();
    r.set("n", Arg::Int(60)).unwrap();
    r.set("space", Arg::Texts(items.clone())).unwrap();
    r.set("goal", Arg::Text("space-filling".into())).unwrap();
    let spread = r
        .resolve()
        .unwrap()
        .run(None, |_| {})
        .unwrap()
        .design
        .unwrap();
    let f = DesignFigures::of(&spread);
    let g = DesignFigures::of(&design(60, &items, 0));
    assert!(
        f.min_distance > 1.2 * g.min_distance,
        "{} vs {}",
        f.min_distance,
        g.min_distance
    );
    assert_eq!(f.slices[0].stratified, f.slices[0].columns);
    assert!(f.levels.iter().all(|l| l.excess == 0));
}
