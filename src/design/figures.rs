//! The figures of a mixed design, all on the unit scale (continuous values through
//! their marginal's CDF): level and level-pair balance, stratification and centred L2
//! discrepancy of the continuous part within every slice of every unordered factor and
//! overall, and the smallest distance between two points with every variable counted
//! by its type.

use super::{Design, Kind};
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

/// One discrete variable's level counts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct LevelCounts {
    /// The variable.
    pub name: String,
    /// How many points take each level, in the order of the levels.
    pub counts: Vec<usize>,
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
            .filter(|&j| matches!(vars[j].kind, Kind::Continuous(_)))
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
                    excess: excess(&counts, n),
                    counts,
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

/// The smallest distance of [`DesignFigures::min_distance`], over every pair: O(n² s),
/// for the sizes designs have.
fn min_mixed_distance(design: &Design) -> f64 {
    let n = design.n();
    let vars = &design.space.vars;
    // Per variable, a point's coordinate on the distance's scale, and whether a
    // difference counts as 0/1 (unordered levels).
    let scale: Vec<(bool, f64)> = vars
        .iter()
        .map(|v| match &v.kind {
            Kind::Continuous(_) => (false, 1.0),
            Kind::Levels { ordered: false, .. } => (true, 1.0),
            k => (false, 1.0 / (k.levels().unwrap_or(2).max(2) - 1) as f64),
        })
        .collect();
    let coord = |i: usize, j: usize| -> f64 {
        match vars[j].kind {
            Kind::Continuous(_) => design.unit.point(i)[j],
            _ => design.levels[j][i] as f64 * scale[j].1,
        }
    };
    let mut best = f64::INFINITY;
    for a in 0..n {
        for b in a + 1..n {
            let d2: f64 = (0..vars.len())
                .map(|j| {
                    if scale[j].0 {
                        f64::from(u8::from(design.levels[j][a] != design.levels[j][b]))
                    } else {
                        (coord(a, j) - coord(b, j)).powi(2)
                    }
                })
                .sum();
            best = best.min(d2);
        }
    }
    best.sqrt()
}
