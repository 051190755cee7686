//! Discrepancies and distances that measure how evenly a point set fills the unit cube.
//!
//! Four L2-type discrepancies and the mixture discrepancy, each computed exactly by its
//! closed form in O(n² s) time and O(n) memory, and the smallest pairwise distance, plain
//! and on the torus. All of
//! them assume the points lie in [0, 1]^s and do not check it (see
//! [`PointSet::check_unit_cube`]).
//!
//! Every discrepancy comes in two forms: `*_squared`, the value of the closed form, and
//! the root, which is what the paper reports (its D_L2 and D_MD). SciPy's
//! `qmc.discrepancy` mixes the two conventions (a root for `'L2-star'`, squares for
//! `'CD'`, `'WD'`, `'MD'`), and its `'MD'` is the *mixture* discrepancy, not the modified
//! L2 discrepancy of the paper; each function below says which SciPy value it matches.
//!
//! The closed forms are those of the discrepancy energies: each squared value is
//! [`stillpoint_energies::discrepancy::squared_discrepancies`] (for the mixture,
//! [`stillpoint_energies::discrepancy::mixture_squared`]) clamped at 0. Their pair
//! sums run in the vectorised, tiled half loop of
//! [`stillpoint_energies::discrepancy::pair_product_sums`] (the minimum distances in
//! [`stillpoint_energies::pairs::min_squared_distances`]): each pair once, 16 pairs per
//! vector, on all rayon threads. [`Metrics`] takes all of them, and U_{q,p} for the
//! evaluation, from one pass over the pairs
//! ([`stillpoint_energies::report_pairs::pair_figures`]) with the same bits. The results are the same bits whatever the number of
//! threads (the tiles and the order their sums are added in depend on n only), and the
//! same bits with or without AVX2 (no fused multiply-add). O(n² s) time, O(n s) memory.

use crate::{Error, PointSet};
use stillpoint_energies::discrepancy::{
    closed_form_fits, discrepancy_root, mixture_closed_form_fits, mixture_root,
    mixture_squared as mixture_closed_form, sampled_squared_discrepancies, squared_discrepancies,
    DiscrepancyKind,
};
use stillpoint_energies::pairs::min_squared_distances;
use stillpoint_energies::report_pairs::pair_figures;
use stillpoint_energies::{Energy, Uqp};

/// Star L2 discrepancy squared, the paper's eq. 46 (Warnock's formula):
///
/// D_L2² = (1/3)^s − (2/n) Σ_i Π_k (1 − x_ik²)/2 + (1/n²) Σ_{i,l} Π_k (1 − max(x_ik, x_lk)).
///
/// It is the mean over t ∈ \[0,1\]^s of the squared local discrepancy
/// #{x_i ∈ [0, t)}/n − Π_k t_k, so it weighs only boxes anchored at the origin. Its root
/// is SciPy's `qmc.discrepancy(method='L2-star')`. Clamped at 0 against rounding.
pub fn star_l2_squared(points: &PointSet) -> f64 {
    let [star] = squared(points, [DiscrepancyKind::StarL2]);
    star
}

/// Star L2 discrepancy, the root of [`star_l2_squared`]: the paper's D_L2 (Table 5) and
/// SciPy's `qmc.discrepancy(method='L2-star')`.
pub fn star_l2(points: &PointSet) -> f64 {
    discrepancy_root(points, DiscrepancyKind::StarL2)
}

/// Modified L2 discrepancy squared (Hickernell), the paper's eq. 47:
///
/// D_MD² = (4/3)^s − (2^(1−s)/n) Σ_i Π_k (3 − x_ik²) + (1/n²) Σ_{i,l} Π_k (2 − max(x_ik, x_lk)).
///
/// It is the sum of the squared star L2 discrepancies of every projection of the set onto
/// a nonempty subset of the coordinates, so unlike the star L2 it does not fade away as s
/// grows. This is *not* SciPy's `method='MD'`, which is the mixture discrepancy; SciPy
/// has no equivalent. Clamped at 0 against rounding.
pub fn modified_l2_squared(points: &PointSet) -> f64 {
    let [modified] = squared(points, [DiscrepancyKind::ModifiedL2]);
    modified
}

/// Modified L2 discrepancy, the root of [`modified_l2_squared`]: the paper's D_MD
/// (Table 5). Not SciPy's `'MD'` (the mixture discrepancy).
pub fn modified_l2(points: &PointSet) -> f64 {
    discrepancy_root(points, DiscrepancyKind::ModifiedL2)
}

/// Centred L2 discrepancy squared (Hickernell):
///
/// D_C² = (13/12)^s − (2/n) Σ_i Π_k (1 + ½|x_ik − ½| − ½|x_ik − ½|²)
///        + (1/n²) Σ_{i,l} Π_k (1 + ½|x_ik − ½| + ½|x_lk − ½| − ½|x_ik − x_lk|).
///
/// Like the modified L2 it sums over all projections, but each box is anchored at the
/// cube corner nearest to it, so the value does not change when the cube is reflected
/// (x_k → 1 − x_k). Equals SciPy's `qmc.discrepancy(method='CD')`, which returns this
/// squared value. Clamped at 0 against rounding.
pub fn centered_l2_squared(points: &PointSet) -> f64 {
    let [centered] = squared(points, [DiscrepancyKind::CenteredL2]);
    centered
}

/// Centred L2 discrepancy, the root of [`centered_l2_squared`]; its square is SciPy's
/// `'CD'`.
pub fn centered_l2(points: &PointSet) -> f64 {
    discrepancy_root(points, DiscrepancyKind::CenteredL2)
}

/// Wrap-around L2 discrepancy squared (Hickernell):
///
/// D_W² = −(4/3)^s + (1/n²) Σ_{i,l} Π_k (3/2 − |x_ik − x_lk| (1 − |x_ik − x_lk|)).
///
/// Boxes wrap around the faces of the cube, so the value is unchanged by a periodic shift
/// x → (x + c) mod 1 of the whole set: the discrepancy that matches a periodic energy.
/// Equals SciPy's `qmc.discrepancy(method='WD')`, which returns this squared value.
/// Clamped at 0 against rounding.
pub fn wrap_around_l2_squared(points: &PointSet) -> f64 {
    let [wrap] = squared(points, [DiscrepancyKind::WrapAroundL2]);
    wrap
}

/// Wrap-around L2 discrepancy, the root of [`wrap_around_l2_squared`]; its square is
/// SciPy's `'WD'`.
pub fn wrap_around_l2(points: &PointSet) -> f64 {
    discrepancy_root(points, DiscrepancyKind::WrapAroundL2)
}

/// Mixture discrepancy squared (Zhou, Fang and Ning 2013), with a = |x − ½|, b = |y − ½|
/// and d = |x − y| in each coordinate:
///
/// D_M² = (19/12)^s − (2/n) Σ_i Π_k (5/3 − a/4 − a²/4)
///        + (1/n²) Σ_{i,l} Π_k (15/8 − a/4 − b/4 − 3d/4 + d²/2).
///
/// Its boxes mix those of the centred and the wrap-around L2 discrepancies; like them it
/// is unchanged by reflections x_k → 1 − x_k and by permutations of the coordinates.
/// Equals SciPy's `qmc.discrepancy(method='MD')`, which returns this squared value (and
/// which is not the modified L2 of [`modified_l2_squared`]). Clamped at 0 against
/// rounding. For s ≤ 954 only: beyond, the terms of the closed form may overflow, and the
/// root [`mixture`] takes the logarithmic form instead.
pub fn mixture_squared(points: &PointSet) -> f64 {
    mixture_closed_form(points).max(0.0)
}

/// Mixture discrepancy, the root of [`mixture_squared`], right at any dimension where it
/// is representable (the logarithmic form beyond s = 954); its square is SciPy's `'MD'`.
pub fn mixture(points: &PointSet) -> f64 {
    mixture_root(points)
}

/// Smallest Euclidean distance between two distinct points of the set (the separation
/// a space-filling design maximises); `f64::INFINITY` for a single point.
pub fn min_distance_euclidean(points: &PointSet) -> f64 {
    let [d2, _] = pair_mins(points);
    d2.sqrt()
}

/// Smallest distance between two distinct points on the unit torus (each coordinate
/// difference Δ counts as min(|Δ|, 1 − |Δ|)), the distance a periodic energy sees;
/// `f64::INFINITY` for a single point. Never larger than [`min_distance_euclidean`].
pub fn min_distance_periodic(points: &PointSet) -> f64 {
    let [_, d2] = pair_mins(points);
    d2.sqrt()
}

/// The star L2 and modified L2 discrepancies (roots, as the paper reports them), in one
/// pass over the pairs: what a run logs every few steps.
///
/// Returns `(star_l2, modified_l2)`, bit for bit equal to [`star_l2`] and
/// [`modified_l2`].
pub fn discrepancies(points: &PointSet) -> (f64, f64) {
    let kinds = [DiscrepancyKind::StarL2, DiscrepancyKind::ModifiedL2];
    if !kinds.iter().all(|&k| closed_form_fits(k, points.s())) {
        return (star_l2(points), modified_l2(points));
    }
    let [star, modified] = squared(points, kinds);
    (star.sqrt(), modified.sqrt())
}

/// Quality figures of a point set in [0, 1]^s.
///
/// Every field is a root (a discrepancy or a distance), never a square; each equals, bit
/// for bit, the function of the same name in this module. For a single point the two
/// distances are `f64::INFINITY` (serialised by `serde_json` as `null`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Star L2 discrepancy, root of eq. 46: the paper's D_L2. Equals SciPy's
    /// `qmc.discrepancy(method='L2-star')` (which SciPy returns as a root).
    pub star_l2: f64,
    /// Modified L2 discrepancy (Hickernell), root of eq. 47: the paper's D_MD. No SciPy
    /// equivalent (SciPy's `'MD'` is the mixture discrepancy, a different quantity).
    pub modified_l2: f64,
    /// Centred L2 discrepancy (Hickernell), root; its square is SciPy's `'CD'`.
    pub centered_l2: f64,
    /// Wrap-around L2 discrepancy (Hickernell), root; its square is SciPy's `'WD'`.
    pub wrap_around_l2: f64,
    /// Mixture discrepancy (Zhou, Fang and Ning), root; its square is SciPy's `'MD'`.
    /// Not serialised: the point-file headers and run reports carry the other fields
    /// only, and stay the same bytes.
    #[serde(skip)]
    pub mixture: f64,
    /// Smallest Euclidean distance between two points.
    pub min_distance: f64,
    /// Smallest distance between two points on the unit torus.
    pub min_distance_periodic: f64,
    /// How the pair sums were estimated, when they were (see [`Sums`]); absent from the
    /// JSON of exact metrics, which stays the same bytes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub estimate: Option<Estimate>,
}

/// How the O(n² s) pair sums of [`Metrics`] are formed: exactly up to `estimate_above`
/// points, estimated above from [`Sums::pairs_for`] random pairs (drawn from `seed`):
/// [`ESTIMATE_PAIRS_PER_POINT`] per point, at most `pairs`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sums {
    /// The largest n whose pair sums are exact.
    pub estimate_above: usize,
    /// The most random pairs of an estimate (see [`Sums::pairs_for`]).
    pub pairs: usize,
    /// Seed of the random pairs.
    pub seed: u64,
}

/// The largest n whose metrics are exact by default: the exact pass over the pairs of
/// 50 000 points takes about 4 s at s = 5 on 2 cores (and grows as n²), the estimate
/// about half as long as writing the points ([`ESTIMATE_PAIRS_PER_POINT`]).
pub const ESTIMATE_ABOVE: usize = 50_000;

/// The most random pairs of an estimate: 4·10⁶, about 0.2 s at s = 5 and 1.4 s at s = 50
/// on 2 cores; the budget of 10⁶ points ([`ESTIMATE_PAIRS_PER_POINT`]).
pub const ESTIMATE_PAIRS: usize = 4_000_000;

/// Random pairs an estimate draws per point, so that it costs a fixed share of writing
/// the points, whatever n and s: a random pair's five kernel products cost about 7 ns a
/// coordinate on 2 cores (two rows fetched from anywhere in the set), writing a point
/// about 55 ns a coordinate (`baseline sobol` at 10⁶ × 50: 2.8 s for 5·10⁷ of them), so
/// 4 pairs a point cost about half of writing the set. Its standard error grows as
/// 1/√pairs: at 10⁵ points √10 times that of the 4·10⁶ pairs drawn before at every size
/// (and stated beside each value, as before).
pub const ESTIMATE_PAIRS_PER_POINT: usize = 4;

/// The grid of cells that looks for the closest pair of an estimated set runs only where
/// n independent uniform points would have, on average, at least this many pairs nearer
/// than its cells' side ([`uniform_pairs_within`]): only such a pair can it prove the
/// closest. Below, it could prove the minimum of at most one random set in a thousand
/// (the mean bounds the chance of any pair), and of an even set (more even than random)
/// fewer still, while it costs as much as the rest of the figures (at 10⁶ × 50 more than
/// twice the random pairs). With the grid's cells (about n^(1/5) a side over five
/// coordinates) it runs up to s = 12 at 10⁵–10⁶ points and not from s = 13 on.
pub const GRID_EXPECTED_PAIRS: f64 = 1e-3;

/// The mean number of pairs nearer than `r` among n independent uniform points on the
/// unit torus, C(n, 2)·V_s·r^s (V_s the volume of the unit ball), for r ≤ ½ where a ball
/// does not wrap onto itself. It bounds the count for the Euclidean distance in the cube
/// too, which is never below the torus distance.
pub fn uniform_pairs_within(n: usize, s: usize, r: f64) -> f64 {
    // ln V_s by V_s = V_{s−2}·2π/s from V_0 = 1, V_1 = 2: in logarithms, as V_s and r^s
    // underflow apart in many dimensions.
    let (mut ln_volume, mut k) = if s.is_multiple_of(2) {
        (0.0, 2)
    } else {
        (2f64.ln(), 3)
    };
    while k <= s {
        ln_volume += (2.0 * std::f64::consts::PI / k as f64).ln();
        k += 2;
    }
    let nf = n as f64;
    let pairs = nf * (nf - 1.0) / 2.0;
    if pairs <= 0.0 {
        return 0.0;
    }
    (pairs.ln() + ln_volume + s as f64 * r.ln()).exp()
}

impl Sums {
    /// Exact at every size (`--exact`).
    pub const EXACT: Sums = Sums {
        estimate_above: usize::MAX,
        pairs: ESTIMATE_PAIRS,
        seed: 0,
    };

    /// Exact up to [`ESTIMATE_ABOVE`] points, estimated from [`ESTIMATE_PAIRS`] pairs
    /// above.
    pub const AUTO: Sums = Sums {
        estimate_above: ESTIMATE_ABOVE,
        pairs: ESTIMATE_PAIRS,
        seed: 0,
    };

    /// [`Sums::EXACT`] when the user asked for exact figures (`--exact`, `exact=True`),
    /// [`Sums::AUTO`] otherwise.
    pub fn asked(exact: bool) -> Sums {
        if exact {
            Sums::EXACT
        } else {
            Sums::AUTO
        }
    }

    /// Whether the pair sums of n points are estimated.
    pub fn estimates(&self, n: usize) -> bool {
        n > self.estimate_above
    }

    /// The random pairs an estimate of n points' pair sums draws:
    /// [`ESTIMATE_PAIRS_PER_POINT`]·n, at most [`Sums::pairs`].
    pub fn pairs_for(&self, n: usize) -> usize {
        self.pairs.min(ESTIMATE_PAIRS_PER_POINT.saturating_mul(n))
    }
}

/// The centred L2 discrepancy (root) of `points` under `sums`' rule, the one every report
/// follows: exact up to [`Sums::estimate_above`] points (the same bits as [`centered_l2`]),
/// estimated from [`Sums::pairs_for`] random pairs above, with the standard error of the
/// root ([`Estimate::root_error`]) as the second value (`None` when exact).
pub fn centered_l2_with(points: &PointSet, sums: Sums) -> (f64, Option<f64>) {
    if !sums.estimates(points.n()) {
        return (centered_l2(points), None);
    }
    let pairs = sums.pairs_for(points.n());
    let [_, _, centered, _, _] = sampled_squared_discrepancies(points, pairs, sums.seed);
    (
        centered.value.max(0.0).sqrt(),
        Some(Estimate::root_error(
            centered.value,
            centered.standard_error,
        )),
    )
}

/// What an estimate of [`Metrics`] rests on, and the standard error of each root.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Estimate {
    /// Random pairs of distinct points the pair sums were estimated from.
    pub pairs: usize,
    /// The seed they were drawn from.
    pub seed: u64,
    /// Standard error of each squared discrepancy: star, modified, centred, wrap-around
    /// L2, mixture.
    pub squared_standard_errors: [f64; 5],
    /// Standard error of each root, in the same order: by the delta method SE(D²)/(2D),
    /// at most √SE(D²) (how far the root can move while D² is within its error of 0).
    pub standard_errors: [f64; 5],
    /// Whether the minimum distances are exact (found by a grid of cells); when not, they
    /// are NaN (null in JSON): the grid could not prove them and the pair loop is O(n²).
    pub min_distances_exact: bool,
    /// Why the grid of cells was not run, when it was not ([`GRID_EXPECTED_PAIRS`]). Not
    /// serialised (the JSON says only whether the distances are exact).
    #[serde(skip)]
    pub grid_skipped: Option<GridSkipped>,
}

/// A grid of cells not run: the side of its cells and the mean number of pairs that near
/// among as many independent uniform points ([`uniform_pairs_within`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSkipped {
    /// The side of the cells: only a closer pair could be proven the closest.
    pub side: f64,
    /// Pairs nearer than `side` among n independent uniform points, on average.
    pub expected_pairs: f64,
}

impl Estimate {
    /// Why the minimum distances are missing (when they are): the grid of cells ran and
    /// could not prove the closest pair, or it was not run.
    pub fn min_distances_why(&self) -> String {
        match self.grid_skipped {
            Some(g) => format!(
                "the grid of cells could prove only a pair nearer than its side {:.3}, of \
                 which as many independent uniform points have {:.1e} on average, so it was \
                 not run",
                g.side, g.expected_pairs
            ),
            None => "the grid of cells could not prove the closest pair".to_string(),
        }
    }

    /// The standard error of a root D = √max(D², 0) from that of its square.
    pub fn root_error(square: f64, square_error: f64) -> f64 {
        let root = square.max(0.0).sqrt();
        let cap = square_error.sqrt();
        if root > 0.0 {
            (square_error / (2.0 * root)).min(cap)
        } else {
            cap
        }
    }
}

impl Metrics {
    /// Computes every figure in one pass over the pairs (the five discrepancies and the
    /// two distances, see [`pair_figures`]). O(n² s) time, O(n s) memory; the points must
    /// lie in [0, 1]^s.
    pub fn compute(points: &PointSet) -> Metrics {
        Metrics::compute_exact(points, None).0
    }

    /// [`Metrics::compute`] where `sums` asks for exact sums; above its size, the five
    /// discrepancies from [`Sums::pairs_for`] random pairs
    /// ([`sampled_squared_discrepancies`]) with their standard errors in
    /// [`Metrics::estimate`], and the minimum distances from a grid of cells where it
    /// proves them (NaN otherwise, and where [`GRID_EXPECTED_PAIRS`] finds it could prove
    /// nothing it is not run). O(n s + pairs · s) then.
    pub fn compute_with(points: &PointSet, sums: Sums) -> Metrics {
        Metrics::compute_with_energy(points, sums, None).0
    }

    /// [`Metrics::compute_with`], and the value of `energy` where the sums are exact
    /// (`None` above the size where they are estimated, or without an energy): in the
    /// same pass over the pairs when its distance is one the pass forms (U_{q,p} with
    /// q = 1, q = ∞ or the Euclidean distance), in a pass of its own otherwise. Each
    /// value has the same bits as [`Metrics::compute_with`]'s and [`Energy::value`]'s.
    pub fn compute_with_energy(
        points: &PointSet,
        sums: Sums,
        energy: Option<&Uqp>,
    ) -> (Metrics, Option<f64>) {
        if !sums.estimates(points.n()) {
            return Metrics::compute_exact(points, energy);
        }
        let pairs = sums.pairs_for(points.n());
        let sampled = sampled_squared_discrepancies(points, pairs, sums.seed);
        let root = sampled.map(|e| e.value.max(0.0).sqrt());
        let ([euclid, periodic], grid_skipped) = grid_minimum(points);
        let metrics = Metrics {
            star_l2: root[0],
            modified_l2: root[1],
            centered_l2: root[2],
            wrap_around_l2: root[3],
            mixture: root[4],
            min_distance: euclid.map_or(f64::NAN, f64::sqrt),
            min_distance_periodic: periodic.map_or(f64::NAN, f64::sqrt),
            estimate: Some(Estimate {
                pairs,
                seed: sums.seed,
                squared_standard_errors: sampled.map(|e| e.standard_error),
                standard_errors: sampled.map(|e| Estimate::root_error(e.value, e.standard_error)),
                min_distances_exact: euclid.is_some() && periodic.is_some(),
                grid_skipped,
            }),
        };
        (metrics, None)
    }

    fn compute_exact(points: &PointSet, energy: Option<&Uqp>) -> (Metrics, Option<f64>) {
        let s = points.s();
        let kinds = [
            DiscrepancyKind::StarL2,
            DiscrepancyKind::ModifiedL2,
            DiscrepancyKind::CenteredL2,
            DiscrepancyKind::WrapAroundL2,
        ];
        let fits = kinds.iter().all(|&k| closed_form_fits(k, s)) && mixture_closed_form_fits(s);
        let ([star, modified, centered, wrap, mixture], [euclid, periodic], value) = if fits {
            let f = pair_figures(points, energy);
            let roots = f.squares.map(|v| v.max(0.0).sqrt());
            (roots, f.min_squared_distances, f.energy)
        } else {
            // In very high dimension each root takes the logarithmic form of its own.
            let [a, b, c, d] = kinds.map(|k| discrepancy_root(points, k));
            let roots = [a, b, c, d, mixture_root(points)];
            (roots, pair_mins(points), energy.map(|e| e.value(points)))
        };
        let metrics = Metrics {
            star_l2: star,
            modified_l2: modified,
            centered_l2: centered,
            wrap_around_l2: wrap,
            mixture,
            min_distance: euclid.sqrt(),
            min_distance_periodic: periodic.sqrt(),
            estimate: None,
        };
        (metrics, value)
    }
}

/// The smallest squared distances (Euclidean, torus) by the grid of cells where
/// [`GRID_EXPECTED_PAIRS`] lets it run (`None` each where it cannot prove them), or why
/// it was not run. The points lie in [0, 1]^s, which the bound assumes.
fn grid_minimum(points: &PointSet) -> ([Option<f64>; 2], Option<GridSkipped>) {
    match grid_skipped(points.n(), points.s()) {
        Some(skipped) => ([None, None], Some(skipped)),
        None => (crate::nearest::min_squared_distances_by_cells(points), None),
    }
}

/// Why the grid of cells is not run on an estimated set of n points in s dimensions
/// ([`GRID_EXPECTED_PAIRS`]), or `None` where it runs; the run-time estimate asks the same.
pub fn grid_skipped(n: usize, s: usize) -> Option<GridSkipped> {
    let side = crate::nearest::grid_side(n, s)?;
    let expected_pairs = uniform_pairs_within(n, s, side);
    (expected_pairs < GRID_EXPECTED_PAIRS).then_some(GridSkipped {
        side,
        expected_pairs,
    })
}

/// The squared discrepancies of `kinds` (one fused pass over the pairs for the lists
/// [`squared_discrepancies`] fuses), each clamped at 0: when the set is nearly perfect the
/// terms of the closed form cancel to within rounding and could leave a tiny negative
/// square, whose root would be NaN.
fn squared<const M: usize>(points: &PointSet, kinds: [DiscrepancyKind; M]) -> [f64; M] {
    let values = squared_discrepancies(points, &kinds);
    std::array::from_fn(|m| values[m].max(0.0))
}

/// min over pairs of the squared Euclidean and the squared torus distance; +∞ without a
/// pair. A minimum does not depend on the order it is taken in.
fn pair_mins(points: &PointSet) -> [f64; 2] {
    min_squared_distances(points.as_slice(), points.n(), points.s())
}

/// One discrepancy (the root) by its name: `l2star` (or `l2-star`), `md` (modified),
/// `cd` (centred), `wd` or `periodic` (wrap-around), `mixture`; `name` spells the
/// parameter in the refusal.
pub fn discrepancy_by_name(name: &str, kind: &str) -> Result<fn(&PointSet) -> f64, Error> {
    let key = kind
        .trim()
        .to_ascii_lowercase()
        .replace("l2-star", "l2star");
    if key == "mixture" {
        return Ok(mixture);
    }
    Ok(match DiscrepancyKind::parse(&key) {
        Ok(DiscrepancyKind::StarL2) => star_l2,
        Ok(DiscrepancyKind::ModifiedL2) => modified_l2,
        Ok(DiscrepancyKind::CenteredL2) => centered_l2,
        Ok(DiscrepancyKind::WrapAroundL2) => wrap_around_l2,
        _ => {
            return Err(Error::invalid(
                name,
                kind,
                "l2star (star L2), md (modified L2), cd (centred L2), wd (wrap-around L2) or \
                 mixture",
            ))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(rows: &[&[f64]]) -> PointSet {
        PointSet::from_rows(rows).unwrap()
    }

    #[test]
    fn single_point_at_the_far_corner() {
        // Only the (1/3)^s term survives: every box [0, t) misses the point (1, ..., 1).
        for s in 1..=6 {
            let p = PointSet::new(1, s, vec![1.0; s]).unwrap();
            assert!((star_l2_squared(&p) - 3f64.powi(-(s as i32))).abs() < 1e-15);
            assert_eq!(min_distance_euclidean(&p), f64::INFINITY);
        }
    }

    #[test]
    fn one_dimensional_star_by_hand() {
        // n = 1, x = 1/2: ∫_0^½ t² dt + ∫_½^1 (1 − t)² dt = 1/12.
        let p = set(&[&[0.5]]);
        assert!((star_l2_squared(&p) - 1.0 / 12.0).abs() < 1e-16);
    }

    #[test]
    fn uniform_pairs_within_is_the_ball_volume_and_the_count_of_random_points() {
        // Two points: the chance that the second lies within r of the first, V_s·r^s.
        let pi = std::f64::consts::PI;
        for (s, volume) in [
            (1, 2.0),
            (2, pi),
            (3, 4.0 * pi / 3.0),
            (4, pi * pi / 2.0),
            (5, 8.0 * pi * pi / 15.0),
        ] {
            let got = uniform_pairs_within(2, s, 0.5);
            let want = volume * 0.5f64.powi(s as i32);
            assert!(
                (got - want).abs() <= 1e-12 * want,
                "s = {s}: {got} against {want}"
            );
        }
        assert_eq!(uniform_pairs_within(1, 3, 0.5), 0.0);
        // Pairs of random points on the torus counted one by one: within 5 Poisson
        // standard deviations of the mean.
        let (n, s, r) = (2000, 3, 0.05);
        let p = stillpoint_sequences::random(n, s, 17).unwrap();
        let rows: Vec<&[f64]> = p.rows().collect();
        let mut count = 0usize;
        for i in 0..n {
            for l in i + 1..n {
                let d2: f64 = rows[i]
                    .iter()
                    .zip(rows[l])
                    .map(|(a, b)| {
                        let d = (a - b).abs();
                        d.min(1.0 - d).powi(2)
                    })
                    .sum();
                count += usize::from(d2 < r * r);
            }
        }
        let mean = uniform_pairs_within(n, s, r);
        assert!(
            (count as f64 - mean).abs() <= 5.0 * mean.sqrt(),
            "{count} pairs against {mean}"
        );
    }

    #[test]
    fn the_pairs_grow_with_n_up_to_their_cap() {
        for n in [2, 1000, 50_001, 999_999] {
            assert_eq!(Sums::AUTO.pairs_for(n), ESTIMATE_PAIRS_PER_POINT * n);
        }
        for n in [1_000_000, 1_000_001, usize::MAX] {
            assert_eq!(Sums::AUTO.pairs_for(n), ESTIMATE_PAIRS);
        }
    }

    #[test]
    fn the_grid_runs_where_random_points_could_be_proven_and_not_beyond() {
        let forced = Sums {
            estimate_above: 0,
            ..Sums::AUTO
        };
        // At s = 20 the grid's side is 1/m and random points have ~0 pairs that near: not
        // run, and the report says why.
        let p = stillpoint_sequences::random(3000, 20, 1).unwrap();
        let e = Metrics::compute_with(&p, forced).estimate.unwrap();
        let side = crate::nearest::grid_side(3000, 20).unwrap();
        let g = e.grid_skipped.expect("the grid skipped");
        assert_eq!(g.side, side);
        assert!(g.expected_pairs < GRID_EXPECTED_PAIRS);
        assert!(!e.min_distances_exact);
        assert!(e.min_distances_why().contains("not run"));
        // At s = 3 it runs and proves the pair loop's minimum.
        let q = stillpoint_sequences::random(3000, 3, 1).unwrap();
        let m = Metrics::compute_with(&q, forced);
        let e = m.estimate.unwrap();
        assert!(e.grid_skipped.is_none() && e.min_distances_exact);
        assert_eq!(
            m.min_distance.to_bits(),
            min_distance_euclidean(&q).to_bits()
        );
        assert_eq!(e.pairs, ESTIMATE_PAIRS_PER_POINT * 3000);
    }

    #[test]
    fn fused_passes_match_single_ones_bitwise() {
        let p = set(&[&[0.1, 0.7], &[0.4, 0.2], &[0.9, 0.55], &[0.3, 0.95]]);
        let m = Metrics::compute(&p);
        assert_eq!(m.star_l2.to_bits(), star_l2(&p).to_bits());
        assert_eq!(m.modified_l2.to_bits(), modified_l2(&p).to_bits());
        assert_eq!(m.centered_l2.to_bits(), centered_l2(&p).to_bits());
        assert_eq!(m.wrap_around_l2.to_bits(), wrap_around_l2(&p).to_bits());
        assert_eq!(m.mixture.to_bits(), mixture(&p).to_bits());
        let (a, b) = discrepancies(&p);
        assert_eq!(a.to_bits(), m.star_l2.to_bits());
        assert_eq!(b.to_bits(), m.modified_l2.to_bits());
    }
}
