//! Randomised sets under a design space: each seed's mean of f over the points is an
//! unbiased estimate of E f(X) under the space's law (normal, lognormal, uniform,
//! integer, labelled and correlated variables; closed-form expectations), every column
//! is the exact inverse-CDF image of the randomised unit-cube set, the rule that makes a
//! space's set is the one `cube_rule` gives (a scrambled Sobol' rule chosen there runs
//! and is priced as its construction), the default under unbounded laws is the best of
//! its drawn lattices, and what stays unsupported is refused by name.

use stillpoint::design::{Design, DesignSpace, Marginal};
use stillpoint::pipeline::measure::{cube_rule, CubeRule};
use stillpoint::pipeline::request::{Arg, Job, Resolved};
use stillpoint::post::randomize::Randomize;
use stillpoint::sequences::{law_lattice_drawn, law_lattice_picked, PICKED_DRAWS};
use stillpoint::Request;

/// Independent laws of every kind a space takes: x normal(1, 2), w lognormal(0.3, 0.5),
/// u uniform(−1, 3), k int(1, 4), c one of three labels.
const MIXED: [&str; 5] = [
    "x=normal(1,2)",
    "w=lognormal(0.3,0.5)",
    "u=uniform(-1,3)",
    "k=int(1,4)",
    "c={a,b,c}",
];

/// Three variables correlated by a Gaussian copula.
const CORRELATED: [&str; 3] = ["y1=normal(0,1)", "y2=normal(2,3)", "y3=lognormal(0,0.4)"];
const CORRELATION: &str = "1,0.6,0.3;0.6,1,-0.2;0.3,-0.2,1";

/// A statistic f of one point (its values as `Design::numbers` writes them: a label as
/// its index) and its exact mean under the space's law.
type Stat = (&'static str, fn(&[f64]) -> f64, f64);

fn mixed_stats() -> Vec<Stat> {
    let ew = (0.3f64 + 0.125).exp();
    vec![
        // E x² + E x = (μ² + σ²) + μ.
        ("x^2+x", |p| p[0] * p[0] + p[0], 6.0),
        ("w", |p| p[1], ew),
        // E w² = exp(2μ + 2σ²).
        ("w^2", |p| p[1] * p[1], 1.1f64.exp()),
        // E u² = (lo² + lo·hi + hi²)/3.
        ("u^2", |p| p[2] * p[2], 7.0 / 3.0),
        ("k^2", |p| p[3] * p[3], 7.5),
        ("1{c=b}", |p| f64::from(p[4] == 1.0), 1.0 / 3.0),
        // Independent variables: the mean of a product is the product of the means.
        ("x*k", |p| p[0] * p[3], 2.5),
        ("w*u", |p| p[1] * p[2], ew),
        ("k*1{c=a}", |p| p[3] * f64::from(p[4] == 0.0), 2.5 / 3.0),
    ]
}

fn correlated_stats() -> Vec<Stat> {
    vec![
        // ρ σ₁ σ₂ + μ₁ μ₂.
        ("y1*y2", |p| p[0] * p[1], 0.6 * 3.0),
        // Stein's lemma: E[Z₁ e^{0.4 Z₃}] = ρ₁₃ · 0.4 · E e^{0.4 Z₃}.
        ("y1*y3", |p| p[0] * p[2], 0.3 * 0.4 * 0.08f64.exp()),
        // E[y2 · y3] = E[(2 + 3 Z₂) e^{0.4 Z₃}] = (2 + 3 · 0.4 ρ₂₃) E e^{0.4 Z₃}.
        (
            "y2*y3",
            |p| p[1] * p[2],
            (2.0 + 3.0 * 0.4 * -0.2) * 0.08f64.exp(),
        ),
        ("y2^2", |p| p[1] * p[1], 13.0),
        ("y3", |p| p[2], 0.08f64.exp()),
    ]
}

fn request(
    n: usize,
    items: &[&str],
    correlation: Option<&str>,
    kind: impl Into<Option<Randomize>>,
    seed: u64,
) -> Request {
    let mut r = Request::default();
    r.set("n", Arg::Int(n as i128)).unwrap();
    r.set(
        "space",
        Arg::Texts(items.iter().map(|s| s.to_string()).collect()),
    )
    .unwrap();
    if let Some(c) = correlation {
        r.set("correlation", Arg::Text(c.into())).unwrap();
    }
    if let Some(kind) = kind.into() {
        r.set("randomize", Arg::Text(kind.name().into())).unwrap();
    }
    r.set("seed", Arg::Int(seed.into())).unwrap();
    r
}

fn design_of(resolved: &Resolved) -> Design {
    resolved.run(None, |_| {}).unwrap().design.unwrap()
}

/// Over `seeds` independent seeds, each statistic's mean over the seeds' estimates lies
/// within 4.5 standard errors of its exact value (a few ulps where every seed's estimate
/// is the same).
fn assert_unbiased(what: &str, seeds: u64, stats: &[Stat], design: impl Fn(u64) -> Design) {
    let mut sums = vec![(0.0f64, 0.0f64); stats.len()];
    for seed in 0..seeds {
        let values = design(seed).numbers().unwrap();
        for (k, (_, f, _)) in stats.iter().enumerate() {
            let est = values.rows().map(f).sum::<f64>() / values.n() as f64;
            sums[k].0 += est;
            sums[k].1 += est * est;
        }
    }
    let r = seeds as f64;
    for ((name, _, exact), (s, ss)) in stats.iter().zip(sums) {
        let mean = s / r;
        let var = ((ss - s * s / r) / (r - 1.0)).max(0.0);
        let se = (var / r).sqrt();
        assert!(
            (mean - exact).abs() <= 4.5 * se + 1e-12 * (1.0 + exact.abs()),
            "{what}: E {name} = {exact}, the mean of {seeds} seeds' estimates {mean} (standard \
             error {se:e})"
        );
    }
}

#[test]
fn every_seed_gives_an_unbiased_estimate_under_the_space_law() {
    for kind in [Randomize::Tent, Randomize::Cells, Randomize::Shift] {
        assert_unbiased(
            &format!("{} mixed", kind.name()),
            300,
            &mixed_stats(),
            |seed| design_of(&request(48, &MIXED, None, kind, seed).resolve().unwrap()),
        );
        assert_unbiased(
            &format!("{} correlated", kind.name()),
            300,
            &correlated_stats(),
            |seed| {
                design_of(
                    &request(48, &CORRELATED, Some(CORRELATION), kind, seed)
                        .resolve()
                        .unwrap(),
                )
            },
        );
    }
}

#[test]
fn each_column_is_the_inverse_cdf_image_of_the_randomised_cube_set() {
    let x = Marginal::Normal {
        mu: 1.0,
        sigma: 2.0,
    };
    let w = Marginal::LogNormal {
        mu: 0.3,
        sigma: 0.5,
    };
    let u = Marginal::Uniform { lo: -1.0, hi: 3.0 };
    for kind in [Randomize::Tent, Randomize::Cells, Randomize::Shift] {
        for seed in [0u64, 7, 123] {
            let mut r = request(40, &MIXED, None, kind, seed);
            let resolved = r.resolve().unwrap();
            assert_eq!(resolved.rule, Some(CubeRule::Randomized(kind)));
            r.randomize = None;
            assert_eq!(r.resolve().unwrap().rule, Some(CubeRule::Dealt));
            let d = design_of(&resolved);
            // The same request without the space: the unit-cube set the space's set is.
            let mut cube = Request::new(40, MIXED.len());
            cube.set("randomize", Arg::Text(kind.name().into()))
                .unwrap();
            cube.set("seed", Arg::Int(seed.into())).unwrap();
            let cube = cube.resolve().unwrap().run(None, |_| {}).unwrap().points;
            assert_eq!(d.unit, cube, "{kind:?} {seed}");
            let values = d.numbers().unwrap();
            for (row, p) in cube.rows().zip(values.rows()) {
                for (j, m) in [(0, &x), (1, &w), (2, &u)] {
                    assert_eq!(
                        p[j].to_bits(),
                        m.ppf(row[j]).to_bits(),
                        "{kind:?} {seed} {j}"
                    );
                }
                assert_eq!(p[3], 1.0 + ((row[3] * 4.0) as usize).min(3) as f64);
                assert_eq!(p[4], ((row[4] * 3.0) as usize).min(2) as f64);
            }
        }
    }
    // Correlated: the scores go through the copula, then each quantile function.
    let resolved = request(40, &CORRELATED, Some(CORRELATION), Randomize::Tent, 5)
        .resolve()
        .unwrap();
    let space = resolved.design.clone().unwrap();
    let copula = space.copula.clone().unwrap();
    let d = design_of(&resolved);
    let laws = [
        Marginal::Normal {
            mu: 0.0,
            sigma: 1.0,
        },
        Marginal::Normal {
            mu: 2.0,
            sigma: 3.0,
        },
        Marginal::LogNormal {
            mu: 0.0,
            sigma: 0.4,
        },
    ];
    for (row, p) in d.unit.rows().zip(d.numbers().unwrap().rows()) {
        for (j, v) in copula.correlate(row).into_iter().enumerate() {
            assert_eq!(p[j].to_bits(), laws[j].ppf(v).to_bits());
        }
    }
}

/// Where every law is unbounded the tent randomisation takes the lattice made for the
/// laws (odd parts, no point paired with its reflection), and the columns are its
/// inverse-CDF image; one bounded variable brings back the cube's tent lattice.
#[test]
fn a_space_of_unbounded_laws_takes_the_lattice_made_for_the_laws() {
    let resolved = request(40, &CORRELATED, None, Randomize::Tent, 5)
        .resolve()
        .unwrap();
    assert_eq!(resolved.rule, Some(CubeRule::LawLattice));
    let d = design_of(&resolved);
    let unit = stillpoint::sequences::law_lattice(40, &[true; 3], 5).unwrap();
    assert_eq!(d.unit, unit);
    let y3 = Marginal::LogNormal {
        mu: 0.0,
        sigma: 0.4,
    };
    for (row, p) in unit.rows().zip(d.numbers().unwrap().rows()) {
        assert_eq!(p[2].to_bits(), y3.ppf(row[2]).to_bits());
    }
    let mut mixed = CORRELATED.to_vec();
    mixed.push("u=uniform(0,1)");
    let resolved = request(40, &mixed, None, Randomize::Tent, 5)
        .resolve()
        .unwrap();
    assert_eq!(resolved.rule, Some(CubeRule::Randomized(Randomize::Tent)));
}

#[test]
fn a_scrambled_sobol_rule_runs_as_its_construction_and_stays_unbiased() {
    let space = DesignSpace::parse("--var", &MIXED).unwrap();
    let plain = request(64, &MIXED, None, None, 9).resolve().unwrap();
    assert_eq!(cube_rule(&space, &plain.job), CubeRule::Dealt);
    assert_eq!(plain.rule, Some(CubeRule::Dealt));
    let ruled = |seed: u64| {
        request(64, &MIXED, None, Randomize::Shift, seed)
            .resolve()
            .unwrap()
            .with_rule(CubeRule::ScrambledSobol)
    };
    let r = ruled(9);
    assert!(
        matches!(
            r.job,
            Job::Baseline {
                n: 64,
                s: 5,
                seed: 9,
                ..
            }
        ),
        "{:?}",
        r.job
    );
    let d = design_of(&r);
    assert_eq!(
        d.unit,
        stillpoint::sequences::sobol_scrambled(64, 5, 9).unwrap()
    );
    // The estimate prices the rule's construction, not the request's run, and the
    // design's figures, which the dealt design of the same space adds to the cube's run.
    let mut sobol = Request::new(64, 5);
    sobol.set("method", Arg::Text("sobol".into())).unwrap();
    let mut cube = Request::new(64, 5);
    cube.set("seed", Arg::Int(9)).unwrap();
    let figures = plain.estimate_seconds_on(2) - cube.resolve().unwrap().estimate_seconds_on(2);
    assert!(figures > 0.0, "{figures}");
    let want = sobol.resolve().unwrap().estimate_seconds_on(2) + figures;
    let got = r.estimate_seconds_on(2);
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    assert_unbiased("scrambled Sobol' mixed", 300, &mixed_stats(), |seed| {
        design_of(&ruled(seed))
    });
}

/// A space holding a Brownian path takes Owen-scrambled Sobol' under the tent
/// randomisation: the unit set is that construction's for the seed (its first column
/// to the variable that is not a path, the next ones to the path's steps), and each seed's
/// means of W(t_j), W(t_j)² and W(t_1)·W(t_4) estimate 0, t_j and min(t_1, t_4) = t_1
/// without bias, beside a normal variable whose square has mean 1.
#[test]
fn a_space_with_a_brownian_path_takes_owen_scrambled_sobol() {
    let items = ["W=brownian(2,4,pca)", "z=normal(0,1)"];
    let resolved = request(64, &items, None, Randomize::Tent, 7)
        .resolve()
        .unwrap();
    assert_eq!(resolved.rule, Some(CubeRule::ScrambledSobol));
    let d = design_of(&resolved);
    let net = stillpoint::sequences::sobol_scrambled(64, 5, 7).unwrap();
    for (dealt, row) in d.unit.rows().zip(net.rows()) {
        assert_eq!(dealt, &[row[1], row[2], row[3], row[4], row[0]][..]);
    }
    let stats: Vec<Stat> = vec![
        ("W_1", |p| p[0], 0.0),
        ("W_4", |p| p[3], 0.0),
        // t_j = jT/m = j/2.
        ("W_1^2", |p| p[0] * p[0], 0.5),
        ("W_3^2", |p| p[2] * p[2], 1.5),
        ("W_1*W_4", |p| p[0] * p[3], 0.5),
        ("z^2", |p| p[4] * p[4], 1.0),
    ];
    assert_unbiased("a Brownian path", 300, &stats, |seed| {
        design_of(
            &request(32, &items, None, Randomize::Tent, seed)
                .resolve()
                .unwrap(),
        )
    });
}

#[test]
fn what_stays_unsupported_is_refused_by_name() {
    let cases: [(&str, Arg, &str); 4] = [
        ("bounds", Arg::Text("0,1".into()), "bounds"),
        ("nested", Arg::Text("16,48".into()), "nested"),
        ("method", Arg::Text("sobol".into()), "randomize"),
        ("goal", Arg::Text("space-filling".into()), "randomize"),
    ];
    for (name, value, named) in cases {
        let mut r = request(48, &MIXED, None, Randomize::Tent, 0);
        r.set(name, value).unwrap();
        let e = r.resolve().unwrap_err().to_string();
        assert!(e.contains(named), "{name}: {e}");
    }
    // Too few points for every label to appear stays refused with a randomised set.
    let e = request(2, &MIXED, None, Randomize::Shift, 0)
        .resolve()
        .unwrap_err()
        .to_string();
    assert!(e.contains("at least 3 points"), "{e}");
}

/// Unbounded laws the default's tests share: two normals and a lognormal.
const UNBOUNDED: [&str; 3] = ["a=normal(0,1)", "b=lognormal(0,0.5)", "c=normal(2,3)"];

/// The three test integrals' relative errors on a unit-cube set, written out here apart
/// from the library's: Z = Φ⁻¹(u) by the normal law's own quantile function, then
/// exp(−‖Z‖²/2), cos(ΣZ/√s) and exp(ΣZ/√s) against 2^(−s/2), e^(−½) and e^(½).
fn probe_errors(x: &stillpoint::PointSet) -> [f64; 3] {
    let normal = Marginal::Normal {
        mu: 0.0,
        sigma: 1.0,
    };
    let s = x.s() as f64;
    let mut sums = [0.0f64; 3];
    for row in x.rows() {
        let z: Vec<f64> = row.iter().map(|&u| normal.ppf(u)).collect();
        let w = z.iter().sum::<f64>() / s.sqrt();
        sums[0] += (-0.5 * z.iter().map(|v| v * v).sum::<f64>()).exp();
        sums[1] += w.cos();
        sums[2] += w.exp();
    }
    let exact = [0.5f64.powf(s / 2.0), (-0.5f64).exp(), 0.5f64.exp()];
    let mut e = [0.0; 3];
    for t in 0..3 {
        e[t] = (sums[t] / x.n() as f64 / exact[t] - 1.0).abs();
    }
    e
}

/// The cube's default set for n, s and the seed (a request with nothing else).
fn cube_default(n: usize, s: usize, seed: u64) -> stillpoint::PointSet {
    let mut r = Request::default();
    r.set("n", Arg::Int(n as i128)).unwrap();
    r.set("s", Arg::Int(s as i128)).unwrap();
    r.set("seed", Arg::Int(seed.into())).unwrap();
    r.resolve().unwrap().run(None, |_| {}).unwrap().points
}

/// The default under a space whose every law is unbounded is the candidate whose score
/// (each test integral's error over its median among the 17 candidates, squared and
/// summed) is the least, recomputed here from the candidates themselves: the 16 drawn
/// lattices and the cube's default set; its columns are the laws' quantiles of that set.
#[test]
fn the_default_under_unbounded_laws_is_the_candidate_with_the_least_score() {
    let mut kinds = Vec::new();
    for (n, seed) in [(200usize, 4u64), (1023, 0), (64, 17), (1024, 1), (4096, 2)] {
        let resolved = request(n, &UNBOUNDED, None, None, seed).resolve().unwrap();
        assert_eq!(resolved.rule, Some(CubeRule::PickedLattice));
        assert!(matches!(resolved.job, Job::Law { picked: true, .. }));
        let d = design_of(&resolved);
        let mut draws: Vec<_> = (0..PICKED_DRAWS)
            .map(|k| law_lattice_drawn(n, &[true; 3], seed, k).unwrap())
            .collect();
        draws.push(cube_default(n, 3, seed));
        let errors: Vec<[f64; 3]> = draws.iter().map(probe_errors).collect();
        let median = |t: usize| {
            let mut v: Vec<f64> = errors.iter().map(|e| e[t]).collect();
            v.sort_by(|a, b| a.partial_cmp(b).unwrap());
            v[8]
        };
        let m = [median(0), median(1), median(2)];
        let score: Vec<f64> = errors
            .iter()
            .map(|e| (0..3).map(|t| (e[t] / m[t]) * (e[t] / m[t])).sum())
            .collect();
        let least = score.iter().copied().fold(f64::INFINITY, f64::min);
        let kept = draws
            .iter()
            .position(|x| *x == d.unit)
            .expect("one of the candidates");
        kinds.push(kept == PICKED_DRAWS as usize);
        assert!(
            score[kept] <= least * (1.0 + 1e-9),
            "n = {n}: kept draw {kept} scores {} where the least is {least}",
            score[kept]
        );
        assert!(score.iter().any(|&v| v > 2.0 * least), "n = {n}: {score:?}");
        let laws = [
            Marginal::Normal {
                mu: 0.0,
                sigma: 1.0,
            },
            Marginal::LogNormal {
                mu: 0.0,
                sigma: 0.5,
            },
            Marginal::Normal {
                mu: 2.0,
                sigma: 3.0,
            },
        ];
        for (row, p) in d.unit.rows().zip(d.numbers().unwrap().rows()) {
            for j in 0..3 {
                assert_eq!(p[j].to_bits(), laws[j].ppf(row[j]).to_bits());
            }
        }
    }
    // Both kinds of candidate are kept somewhere: the cube's set at n = 64, seed 17.
    assert_eq!(kinds, [false, false, true, false, false]);
}

/// The same request gives the same bits on one thread and on two, where the cube's
/// default set is among the candidates (it is kept at n = 64, seed 17) and where a draw
/// is kept.
#[test]
fn the_default_under_unbounded_laws_does_not_depend_on_the_threads() {
    for (n, seed) in [(64usize, 17u64), (1023, 0)] {
        assert_same_bits_on_one_and_two_threads(|| {
            let resolved = request(n, &UNBOUNDED, None, None, seed).resolve().unwrap();
            design_of(&resolved).numbers().unwrap()
        });
    }
}

/// Runs `make` on a pool of one thread and of two, and asserts the sets are the same
/// to the bit.
fn assert_same_bits_on_one_and_two_threads(make: impl Fn() -> stillpoint::PointSet + Sync) {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(&make)
    };
    let (one, two) = (on(1), on(2));
    assert!(one
        .as_slice()
        .iter()
        .zip(two.as_slice())
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}

/// The closed forms the draws are judged by: one normal's E exp(−Z²/2) = 1/√2 (so
/// 2^(−s/2) over s independent ones), E cos Z = e^(−½) and E e^Z = e^(½) (ΣZ_j/√s is
/// one standard normal), by the midpoint rule on 2·10⁶ quantiles; and the kept set of
/// 4 099 points in 4 dimensions integrates each to 1 %.
#[test]
fn the_test_integrals_have_the_closed_forms_the_draws_are_judged_by() {
    let normal = Marginal::Normal {
        mu: 0.0,
        sigma: 1.0,
    };
    let m = 2_000_000usize;
    let mut sums = [0.0f64; 3];
    for i in 0..m {
        let z = normal.ppf((i as f64 + 0.5) / m as f64);
        sums[0] += (-0.5 * z * z).exp();
        sums[1] += z.cos();
        sums[2] += z.exp();
    }
    let exact = [0.5f64.sqrt(), (-0.5f64).exp(), 0.5f64.exp()];
    for t in 0..3 {
        let v = sums[t] / m as f64;
        assert!(
            (v / exact[t] - 1.0).abs() < 2e-4,
            "{t}: {v} vs {}",
            exact[t]
        );
    }
    let ppf = move |u: f64| normal.ppf(u);
    let x = law_lattice_picked(4099, &[true; 4], 3, &ppf).unwrap();
    let e = probe_errors(&x);
    assert!(e.iter().all(|&v| v < 0.01), "{e:?}");
}

/// The same seed gives the same bits on one thread and on two (the draws are scored in
/// parallel, each by itself).
#[test]
fn the_picked_lattice_does_not_depend_on_the_threads() {
    let normal = Marginal::Normal {
        mu: 0.0,
        sigma: 1.0,
    };
    let ppf = move |u: f64| normal.ppf(u);
    assert_same_bits_on_one_and_two_threads(|| {
        law_lattice_picked(2050, &[true; 6], 8, &ppf).unwrap()
    });
}

/// The picked lattice is the default's alone: a set the request chose (a method, a
/// goal), one variable, a correlation or a bounded law keep the dealt design.
#[test]
fn a_set_the_request_chose_and_other_spaces_stay_dealt() {
    let dealt = |r: Request| r.resolve().unwrap().rule;
    for (name, value) in [("method", "sobol"), ("goal", "space-filling")] {
        let mut r = request(64, &UNBOUNDED, None, None, 1);
        r.set(name, Arg::Text(value.into())).unwrap();
        assert_eq!(dealt(r), Some(CubeRule::Dealt), "{name}");
    }
    let mut exact = request(64, &UNBOUNDED, None, None, 1);
    exact.set("exact", Arg::Bool(true)).unwrap();
    assert_eq!(dealt(exact), Some(CubeRule::PickedLattice));
    assert_eq!(
        dealt(request(64, &UNBOUNDED[..1], None, None, 1)),
        Some(CubeRule::Dealt)
    );
    assert_eq!(
        dealt(request(64, &CORRELATED, Some(CORRELATION), None, 1)),
        Some(CubeRule::Dealt)
    );
    let mut mixed = UNBOUNDED.to_vec();
    mixed.push("u=uniform(0,1)");
    assert_eq!(
        dealt(request(64, &mixed, None, None, 1)),
        Some(CubeRule::Dealt)
    );
}
