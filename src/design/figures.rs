//! The figures of a mixed design, all on the unit scale (continuous values through
//! their marginal's CDF): level and level-pair balance, stratification and centred L2
//! discrepancy of the continuous part within every slice of every unordered factor and
//! overall, and the smallest distance between two points with every variable counted
//! by its type.

use super::{Design, DesignSpace, Kind};
use crate::quality::metrics::centered_l2;
use crate::PointSet;
use serde::Serialize;

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
    /// every unordered factor on which the two differ.
    pub min_distance: f64,
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
    /// The figures of `design`.
    pub fn of(design: &Design) -> DesignFigures {
        let n = design.n();
        let vars = &design.space.vars;
        let cont: Vec<usize> = (0..vars.len())
            .filter(|&j| vars[j].kind.is_continuous())
            .collect();
        let column = |j: usize, rows: &[usize]| -> Vec<f64> {
            rows.iter().map(|&i| design.unit.point(i)[j]).collect()
        };
        let all: Vec<usize> = (0..n).collect();
        let part = |rows: &[usize]| -> Option<f64> {
            if cont.is_empty() || rows.is_empty() {
                return None;
            }
            let data: Vec<f64> = rows
                .iter()
                .flat_map(|&i| cont.iter().map(move |&j| design.unit.point(i)[j]))
                .collect();
            PointSet::new(rows.len(), cont.len(), data)
                .ok()
                .map(|p| centered_l2(&p))
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
                    centered_l2: members.iter().filter_map(|rows| part(rows)).collect(),
                }
            })
            .collect();
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
            centered_l2: if n > 1 { part(&all) } else { None },
            min_distance: min_mixed_distance(design),
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

/// The smallest distance of [`DesignFigures::min_distance`], over every pair: O(n² s),
/// for the sizes designs have.
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
