//! The evaluation of a point set in the unit cube: every figure `stillpoint eval --json`
//! prints, as one JSON object, shared by the command line and the Python package so the
//! two give the same keys and the same numbers.

use crate::metrics::{Metrics, Sums};
use crate::PointSet;
use serde_json::{json, Value};
use stillpoint_energies::{paper_qp, Distance, Uqp};

/// A finite number, or `null` where JSON cannot hold the value (its note says why).
fn finite_or_null(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// Every figure of `points` (in [0, 1]^s): the discrepancies (roots; `mixture` is the
/// mixture discrepancy of Zhou, Fang and Ning, whose square is SciPy's `'MD'`), whether
/// every coordinate is stratified (one point in each [k/n, (k+1)/n)), the minimum
/// distances, U_{q,p} at the paper's fit for (n, s), E_∞, the largest gap between a
/// coordinate's mean and ½, and `notes` saying what each `null` stands for.
pub fn eval_json(points: &PointSet) -> Value {
    eval_json_with(points, Sums::EXACT)
}

/// [`eval_json`] with the O(n²) figures as `sums` asks: above its size the discrepancies
/// are estimated from random pairs, with an `estimate` object (the pairs, the seed and
/// each discrepancy's standard error), the minimum distances come from a grid of cells
/// (null where it cannot prove them) and U_{q,p} is not computed (null); `notes` says so.
pub fn eval_json_with(points: &PointSet, sums: Sums) -> Value {
    let fit = paper_qp(points.n(), points.s());
    let energy = Uqp::new(Distance::Q(fit.q), fit.p).ok();
    // U_{q,p} at the fit shares the metrics' pass over the pairs where its distance allows.
    let (m, uqp) = Metrics::compute_with_energy(points, sums, energy.as_ref());
    let star = crate::star_inf::star_discrepancy(points);
    // --exact asks for every figure whatever it costs, the 2-D projections among them.
    let work = if sums == Sums::EXACT {
        u64::MAX
    } else {
        crate::star_inf::PROJECTION_WORK
    };
    let (one, two) = crate::star_inf::worst_projections_within(points, work);
    let mean_gap = points
        .mean()
        .iter()
        .map(|v| (v - 0.5).abs())
        .fold(0.0, f64::max);
    let mut v = json!({
        "n": points.n(),
        "s": points.s(),
        "star_l2": m.star_l2,
        "modified_l2": m.modified_l2,
        "centered_l2": m.centered_l2,
        "wrap_around_l2": m.wrap_around_l2,
        "mixture": m.mixture,
        "stratified": crate::stratification::is_stratified(points),
        "star_linf": star.map(finite_or_null),
        "worst_1d_star_linf": one,
        "worst_2d_star_linf": two.map(finite_or_null),
        "min_distance": finite_or_null(m.min_distance),
        "min_distance_periodic": finite_or_null(m.min_distance_periodic),
        "energy_uqp": uqp.map(finite_or_null),
        "energy_uqp_q": fit.q,
        "energy_uqp_p": fit.p,
        "energy_e_inf": finite_or_null(1.0 / m.min_distance),
        "mean_gap": mean_gap,
        "notes": value_notes(points, &m, uqp, star.is_some(), two.is_some()),
    });
    if let Some(e) = &m.estimate {
        let by_key = |errors: &[f64; 5]| -> Value {
            DISCREPANCY_KEYS
                .iter()
                .zip(errors)
                .map(|(k, &se)| (k.to_string(), finite_or_null(se)))
                .collect::<serde_json::Map<_, _>>()
                .into()
        };
        v["estimate"] = json!({
            "pairs": e.pairs,
            "seed": e.seed,
            "above_n": sums.estimate_above,
            "standard_errors": by_key(&e.standard_errors),
            "squared_standard_errors": by_key(&e.squared_standard_errors),
        });
    }
    v
}

/// The keys of the five discrepancies, in the order of [`Metrics::estimate`]'s errors.
pub const DISCREPANCY_KEYS: [&str; 5] = [
    "star_l2",
    "modified_l2",
    "centered_l2",
    "wrap_around_l2",
    "mixture",
];

/// What a value that JSON cannot hold (null) stands for: a single point has no pair
/// (no distance, energies 0), coinciding points have distance 0 and infinite energies
/// (on the torus, 0 and 1 are the same coordinate). Only the keys concerned appear.
fn value_notes(
    points: &PointSet,
    m: &Metrics,
    uqp: Option<f64>,
    has_star: bool,
    has_two: bool,
) -> Value {
    let n = points.n();
    let mut notes = serde_json::Map::new();
    let mut note = |k: &str, text: &str| {
        notes.insert(k.to_string(), json!(text));
    };
    if n == 1 {
        note("min_distance", "none: a single point has no pair");
        note("min_distance_periodic", "none: a single point has no pair");
    } else {
        if m.min_distance == 0.0 {
            note("energy_e_inf", "infinite: two points coincide");
        }
        if m.min_distance_periodic == 0.0 && uqp.is_some_and(|u| !u.is_finite()) {
            note(
                "energy_uqp",
                if m.min_distance == 0.0 {
                    "infinite: two points coincide"
                } else {
                    "infinite: two points coincide on the torus (0 and 1 are one coordinate)"
                },
            );
        }
    }
    if m.estimate.is_some() {
        let skipped = "not computed: above the size where the O(n² s) sums are estimated, \
                       this pair sum is skipped (--exact computes it)";
        note("energy_uqp", skipped);
        if let Some(e) = m.estimate.filter(|_| m.min_distance.is_nan()) {
            let why = format!(
                "not computed: {} and the pair loop is O(n² s) (--exact computes it)",
                e.min_distances_why()
            );
            note("min_distance", &why);
            note("min_distance_periodic", &why);
            note("energy_e_inf", &why);
        }
        for k in DISCREPANCY_KEYS {
            note(
                k,
                "estimated from random pairs; its standard error is in `estimate` \
                 (--exact for the exact sum)",
            );
        }
    }
    if !has_star {
        note(
            "star_linf",
            &format!(
                "computed exactly for s ≤ 3 only (n ≤ {} in 2-D, n ≤ {} in 3-D)",
                crate::star_inf::MAX_N_2D,
                crate::star_inf::MAX_N_3D
            ),
        );
    }
    if !has_two {
        note(
            "worst_2d_star_linf",
            if points.s() < 2 {
                "none: the set has one coordinate"
            } else {
                "not computed: s(s−1)/2 projections of n·min(n, 2⌈log2 n⌉²) work each \
                 exceed the default budget of 10^8 units (--exact computes it)"
            },
        );
    }
    for (k, v) in [
        ("star_l2", m.star_l2),
        ("modified_l2", m.modified_l2),
        ("centered_l2", m.centered_l2),
        ("wrap_around_l2", m.wrap_around_l2),
        ("mixture", m.mixture),
    ] {
        if !v.is_finite() {
            note(k, "not representable in f64 at this dimension");
        }
    }
    Value::Object(notes)
}
