//! The figures of a mixed design, all on the unit scale (continuous values through
//! their marginal's CDF): level and level-pair balance, stratification and centred L2
//! discrepancy of the continuous part within every slice of every unordered factor and
//! overall, and the smallest distance between two points with every variable counted
//! by its type.
//!
//! The pair figures (the centred L2 discrepancies and the smallest distance) follow the
//! unit-cube report's rule ([`Sums`]): exact up to its size, above it the discrepancies
//! estimated from random pairs with their standard errors and the smallest distance
//! found by a grid of cells where the grid proves it (NaN where it cannot), unless the
//! sums were asked exact.

use super::{Design, DesignSpace, Kind};
use crate::PointSet;
use serde::Serialize;
use stillpoint_quality::metrics::{centered_l2_with, Sums};
use stillpoint_quality::nearest::min_squared_distances_by_cells;

/// How far a set of counts is from even: the largest distance of a count from the
/// nearest of ⌊n/L⌋ and ⌈n/L⌉ (0 when every count is one of them).
fn excess(counts: &[usize], n: usize) -> usize {
    let l = counts.len().max(1);
    let (lo, hi) = (n / l, n.div_ceil(l));
    counts
        .iter()
        .map(|&c| c.saturating_sub(hi).max(lo.saturating_sub(c)))
        .max()
        .unwrap_or(0)
}

/// The most levels whose counts are listed one by one: `int(0,1000000)` has a million,
/// and a list of them would make a file header line megabytes long.
pub const MAX_LISTED_LEVELS: usize = 1024;

/// One discrete variable's level counts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct LevelCounts {
    /// The variable.
    pub name: String,
    /// Its number of levels L.
    pub levels: usize,
    /// How many levels at least one point takes.
    pub taken: usize,
    /// The smallest and the largest count.
    pub least: usize,
    /// See `least`.
    pub most: usize,
    /// How many points take each level, in the order of the levels (`None` above
    /// [`MAX_LISTED_LEVELS`] levels).
    pub counts: Option<Vec<usize>>,
    /// The largest distance of a count from ⌊n/L⌋ or ⌈n/L⌉ (0: as even as n allows).
    pub excess: usize,
}

/// Two unordered factors' level-pair counts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PairBalance {
    /// The two factors.
    pub names: (String, String),
    /// The largest distance of a pair's count from ⌊n/(L_a L_b)⌋ or ⌈n/(L_a L_b)⌉.
    pub excess: usize,
}

/// One unordered factor's slices: the continuous part within each of its levels.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SliceFigures {
    /// The factor.
    pub name: String,
    /// Slices × continuous columns in which the slice's m points fall one in each
    /// 1/m-th of [0, 1).
    pub stratified: usize,
    /// Slices × continuous columns in all.
    pub columns: usize,
    /// Centred L2 discrepancy of each slice's continuous part.
    pub centered_l2: Vec<f64>,
    /// The standard error of each slice's centred L2 discrepancy, 0 where it is exact;
    /// absent when every slice's is exact.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub centered_l2_errors: Option<Vec<f64>>,
}

/// Every figure of a design.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DesignFigures {
    /// Points.
    pub n: usize,
    /// Continuous variables.
    pub continuous: usize,
    /// Each discrete variable's counts.
    pub levels: Vec<LevelCounts>,
    /// Each two unordered factors' pair balance.
    pub pairs: Vec<PairBalance>,
    /// Each unordered factor's slices.
    pub slices: Vec<SliceFigures>,
    /// Continuous columns in which the n points fall one in each 1/n-th of [0, 1).
    pub stratified: usize,
    /// Centred L2 discrepancy of the continuous part (None without two points or
    /// without a continuous variable).
    pub centered_l2: Option<f64>,
    /// The smallest distance between two points, with continuous coordinates on the
    /// unit scale, an integer or ordered level as its rank over (L − 1), and a 1 for
    /// every unordered factor on which the two differ. NaN (null in JSON) where the
    /// figures are estimated and the grid of cells could not prove it.
    pub min_distance: f64,
    /// How the figures were estimated, when some were ([`Sums`]); absent when every
    /// figure is exact, as it is up to the estimate's size.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub estimate: Option<DesignEstimate>,
}

/// What the estimated figures of a design rest on ([`DesignFigures::estimate`]).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DesignEstimate {
    /// Random pairs of distinct points the whole set's estimated discrepancy was formed
    /// from ([`Sums::pairs_for`] its n; a slice of m points draws `pairs_for(m)`).
    pub pairs: usize,
    /// The seed they were drawn from.
    pub seed: u64,
    /// The standard error of the continuous part's centred L2 discrepancy (None when it
    /// is exact or absent).
    pub centered_l2_error: Option<f64>,
    /// Whether the smallest distance is exact (found by the grid of cells); when not,
    /// it is NaN.
    pub min_distance_exact: bool,
}

/// Whether `values` fall one in each 1/m-th of [0, 1), m = their count.
pub fn stratified(values: &[f64]) -> bool {
    let m = values.len();
    let mut seen = vec![false; m];
    values.iter().all(|&v| {
        let c = ((v * m as f64) as usize).min(m.saturating_sub(1));
        !std::mem::replace(&mut seen[c], true)
    })
}

impl DesignFigures {
    /// The figures of `design` under the report's default rule ([`Sums::AUTO`]).
    pub fn of(design: &Design) -> DesignFigures {
        DesignFigures::of_with(design, Sums::AUTO)
    }

    /// The figures of `design`, their pair figures exact or estimated as `sums` says
    /// (the unit-cube report's rule: [`Sums::estimates`] per set or slice).
    pub fn of_with(design: &Design, sums: Sums) -> DesignFigures {
        let n = design.n();
        let vars = &design.space.vars;
        let cont: Vec<usize> = (0..vars.len())
            .filter(|&j| vars[j].kind.is_continuous())
            .collect();
        let column = |j: usize, rows: &[usize]| -> Vec<f64> {
            rows.iter().map(|&i| design.unit.point(i)[j]).collect()
        };
        let all: Vec<usize> = (0..n).collect();
        let part = |rows: &[usize]| -> Option<(f64, Option<f64>)> {
            if cont.is_empty() || rows.is_empty() {
                return None;
            }
            let data: Vec<f64> = rows
                .iter()
                .flat_map(|&i| cont.iter().map(move |&j| design.unit.point(i)[j]))
                .collect();
            PointSet::new(rows.len(), cont.len(), data)
                .ok()
                .map(|p| centered_l2_with(&p, sums))
        };
        let mut levels = Vec::new();
        let mut factors = Vec::new();
        for (j, v) in vars.iter().enumerate() {
            if let Some(l) = v.kind.levels() {
                let mut counts = vec![0; l];
                for &k in &design.levels[j] {
                    counts[k] += 1;
                }
                levels.push(LevelCounts {
                    name: v.name.clone(),
                    levels: l,
                    taken: counts.iter().filter(|&&c| c > 0).count(),
                    least: counts.iter().copied().min().unwrap_or(0),
                    most: counts.iter().copied().max().unwrap_or(0),
                    excess: excess(&counts, n),
                    counts: (l <= MAX_LISTED_LEVELS).then_some(counts),
                });
                if v.kind.is_categorical() {
                    factors.push((j, l));
                }
            }
        }
        let mut pairs = Vec::new();
        for (a, &(ja, la)) in factors.iter().enumerate() {
            for &(jb, lb) in &factors[a + 1..] {
                let mut counts = vec![0; la * lb];
                for i in 0..n {
                    counts[design.levels[ja][i] * lb + design.levels[jb][i]] += 1;
                }
                pairs.push(PairBalance {
                    names: (vars[ja].name.clone(), vars[jb].name.clone()),
                    excess: excess(&counts, n),
                });
            }
        }
        let slices = factors
            .iter()
            .map(|&(j, l)| {
                let members: Vec<Vec<usize>> = (0..l)
                    .map(|k| (0..n).filter(|&i| design.levels[j][i] == k).collect())
                    .collect();
                let (centered_l2, errors): (Vec<f64>, Vec<Option<f64>>) =
                    members.iter().filter_map(|rows| part(rows)).unzip();
                SliceFigures {
                    name: vars[j].name.clone(),
                    stratified: members
                        .iter()
                        .map(|rows| {
                            cont.iter()
                                .filter(|&&c| stratified(&column(c, rows)))
                                .count()
                        })
                        .sum(),
                    columns: l * cont.len(),
                    centered_l2,
                    centered_l2_errors: errors
                        .iter()
                        .any(Option::is_some)
                        .then(|| errors.iter().map(|e| e.unwrap_or(0.0)).collect()),
                }
            })
            .collect::<Vec<_>>();
        let whole = if n > 1 { part(&all) } else { None };
        let (min_distance, min_distance_exact) = if sums.estimates(n) {
            min_distance_by_cells(design).map_or((f64::NAN, false), |d| (d, true))
        } else {
            (min_mixed_distance(design), true)
        };
        let estimated = sums.estimates(n)
            || slices
                .iter()
                .any(|s: &SliceFigures| s.centered_l2_errors.is_some());
        DesignFigures {
            n,
            continuous: cont.len(),
            levels,
            pairs,
            slices,
            stratified: cont
                .iter()
                .filter(|&&c| stratified(&column(c, &all)))
                .count(),
            centered_l2: whole.map(|(v, _)| v),
            min_distance,
            estimate: estimated.then(|| DesignEstimate {
                pairs: sums.pairs_for(n),
                seed: sums.seed,
                centered_l2_error: whole.and_then(|(_, e)| e),
                min_distance_exact,
            }),
        }
    }
}

/// The discrete variables' share of the type-aware squared distance of
/// [`DesignFigures::min_distance`]: an integer or ordered level counts as its rank over
/// L − 1, an unordered factor 1 when the two points differ.
pub struct DiscreteDistance<'a> {
    /// Per discrete variable, its column and the scale of its rank (`None`: unordered).
    parts: Vec<(usize, Option<f64>)>,
    levels: &'a [Vec<usize>],
}

impl<'a> DiscreteDistance<'a> {
    /// The distance of `space`'s discrete variables, whose levels per point are `levels`.
    pub fn new(space: &DesignSpace, levels: &'a [Vec<usize>]) -> DiscreteDistance<'a> {
        let parts = space
            .vars
            .iter()
            .enumerate()
            .filter_map(|(j, v)| match &v.kind {
                Kind::Continuous(_) | Kind::Path { .. } => None,
                Kind::Levels { ordered: false, .. } => Some((j, None)),
                k => Some((j, Some(1.0 / (k.levels().unwrap_or(2).max(2) - 1) as f64))),
            })
            .collect();
        DiscreteDistance { parts, levels }
    }

    /// The squared share between points `a` and `b`.
    pub fn squared(&self, a: usize, b: usize) -> f64 {
        self.parts
            .iter()
            .map(|&(j, scale)| {
                let (la, lb) = (self.levels[j][a], self.levels[j][b]);
                match scale {
                    None => f64::from(u8::from(la != lb)),
                    Some(w) => ((la as f64 - lb as f64) * w).powi(2),
                }
            })
            .sum()
    }
}

/// The smallest distance of [`DesignFigures::min_distance`] found by the grid of cells
/// of the unit-cube report, `None` where the grid cannot prove it: the same distance is
/// the Euclidean one of the points with continuous coordinates as they are, a rank as
/// rank/(L − 1), and each unordered factor as L coordinates, 1/√2 at its level and 0
/// elsewhere (two levels that differ then add 1 to the squared distance). O(n) cells.
fn min_distance_by_cells(design: &Design) -> Option<f64> {
    let (n, cont) = (design.n(), design.space.continuous());
    let discrete = DiscreteDistance::new(&design.space, &design.levels);
    let width = cont.len()
        + discrete
            .parts
            .iter()
            .map(|&(j, scale)| match scale {
                Some(_) => 1,
                None => design.space.vars[j].kind.levels().unwrap_or(1),
            })
            .sum::<usize>();
    let mut data = Vec::with_capacity(n * width);
    for i in 0..n {
        let x = design.unit.point(i);
        data.extend(cont.iter().map(|&j| x[j]));
        for &(j, scale) in &discrete.parts {
            let level = design.levels[j][i];
            match scale {
                Some(w) => data.push(level as f64 * w),
                None => {
                    let levels = design.space.vars[j].kind.levels().unwrap_or(1);
                    data.extend((0..levels).map(|k| {
                        if k == level {
                            std::f64::consts::FRAC_1_SQRT_2
                        } else {
                            0.0
                        }
                    }));
                }
            }
        }
    }
    let embedded = PointSet::new(n, width.max(1), data).ok()?;
    let [euclid, _] = min_squared_distances_by_cells(&embedded);
    euclid.map(f64::sqrt)
}

/// The smallest distance of [`DesignFigures::min_distance`], over every pair: O(n² s),
/// up to the size where the report's figures are exact.
fn min_mixed_distance(design: &Design) -> f64 {
    let n = design.n();
    let cont = design.space.continuous();
    let discrete = DiscreteDistance::new(&design.space, &design.levels);
    let mut best = f64::INFINITY;
    for a in 0..n {
        let (pa, rest) = (design.unit.point(a), a + 1..n);
        for b in rest {
            let pb = design.unit.point(b);
            let d2: f64 =
                cont.iter().map(|&j| (pa[j] - pb[j]).powi(2)).sum::<f64>() + discrete.squared(a, b);
            best = best.min(d2);
        }
    }
    best.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::balance::Finish;
    use crate::DesignSpace;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// A design of n points over two continuous variables, an integer, an ordered and
    /// two unordered factors, dealt from uniform random points of `seed`.
    fn design(n: usize, seed: u64) -> Design {
        let space = DesignSpace::parse(
            "--var",
            &[
                "x=uniform(0,1)",
                "y=normal(0,1)",
                "k=int(1,6)",
                "o=ordered{lo,mid,hi}",
                "c={a,b,c}",
                "d={u,v}",
            ],
        )
        .unwrap();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let data = (0..n * space.dim())
            .map(|_| rng.random_range(0.0..1.0))
            .collect();
        let base = PointSet::new(n, space.dim(), data).unwrap();
        Design::build(&space, &base, seed, Finish::Nothing).unwrap()
    }

    /// The rule with its exact size lowered to `above` points (the estimate's pairs and
    /// seed as the report's).
    fn estimated_above(above: usize) -> Sums {
        Sums {
            estimate_above: above,
            ..Sums::AUTO
        }
    }

    #[test]
    fn up_to_the_exact_size_the_figures_are_the_exact_ones_and_say_nothing_of_an_estimate() {
        for (n, seed) in [(2, 1), (40, 2), (300, 3)] {
            let d = design(n, seed);
            let auto = DesignFigures::of(&d);
            let exact = DesignFigures::of_with(&d, Sums::EXACT);
            // Every value, bit for bit, and the same JSON (no estimate field).
            assert_eq!(auto, exact, "n = {n}");
            assert!(auto.estimate.is_none());
            assert!(auto.slices.iter().all(|s| s.centered_l2_errors.is_none()));
            let json = serde_json::to_string(&auto).unwrap();
            assert!(
                !json.contains("estimate") && !json.contains("errors"),
                "{json}"
            );
            // The exact figures are the pair loop's: the centred L2 of the continuous
            // columns and the smallest type-aware distance over every pair.
            assert_eq!(exact.min_distance, min_mixed_distance(&d));
        }
    }

    #[test]
    fn above_the_exact_size_the_figures_are_estimated_with_their_error_stated() {
        let d = design(2000, 7);
        let exact = DesignFigures::of_with(&d, Sums::EXACT);
        let est = DesignFigures::of_with(&d, estimated_above(500));
        let e = est.estimate.as_ref().expect("estimated above the size");
        assert_eq!(
            (e.pairs, e.seed),
            (Sums::AUTO.pairs_for(2000), Sums::AUTO.seed)
        );
        // The overall centred L2: within 5 standard errors of the exact value.
        let (v, x) = (est.centered_l2.unwrap(), exact.centered_l2.unwrap());
        let se = e.centered_l2_error.expect("the estimate's standard error");
        assert!(se > 0.0 && se.is_finite(), "se {se}");
        assert!((v - x).abs() <= 5.0 * se, "estimate {v} ± {se}, exact {x}");
        // Slices of ~1000 and ~667 points are above 500 too: each has its error, and
        // each estimate lies within 5 of them of the exact value.
        for (s, t) in est.slices.iter().zip(&exact.slices) {
            let errors = s.centered_l2_errors.as_ref().expect("slices estimated");
            assert_eq!(errors.len(), t.centered_l2.len());
            for ((v, x), se) in s.centered_l2.iter().zip(&t.centered_l2).zip(errors) {
                assert!(*se > 0.0 && (v - x).abs() <= 5.0 * se, "{v} ± {se} vs {x}");
            }
        }
        // The smallest distance: the exact one where the grid proves it, else NaN and
        // said so.
        if e.min_distance_exact {
            assert!((est.min_distance - exact.min_distance).abs() <= 1e-12 * exact.min_distance);
        } else {
            assert!(est.min_distance.is_nan());
        }
        // The counts are not pair figures: unchanged.
        assert_eq!(est.levels, exact.levels);
        assert_eq!(est.pairs, exact.pairs);
        assert_eq!(est.stratified, exact.stratified);
        let json = serde_json::to_value(&est).unwrap();
        assert!(json["estimate"]["centered_l2_error"].as_f64().unwrap() > 0.0);
    }

    #[test]
    fn the_grid_finds_the_type_aware_distance_of_the_pair_loop() {
        // Two continuous variables and factors: few enough coordinates for the grid, so
        // that it proves the distance; it must then be the pair loop's.
        let space = DesignSpace::parse("--var", &["x=uniform(0,1)", "c={a,b,c}", "o=ordered{p,q}"])
            .unwrap();
        let mut proved = 0;
        for seed in 0..6 {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let n = 400;
            let data = (0..n * 3).map(|_| rng.random_range(0.0..1.0)).collect();
            let base = PointSet::new(n, 3, data).unwrap();
            let d = Design::build(&space, &base, seed, Finish::Nothing).unwrap();
            if let Some(v) = min_distance_by_cells(&d) {
                proved += 1;
                let x = min_mixed_distance(&d);
                assert!(
                    (v - x).abs() <= 1e-12 * x.max(1e-300),
                    "cells {v}, pairs {x}"
                );
            }
        }
        assert!(proved > 0, "the grid proved none of the distances");
    }
}
