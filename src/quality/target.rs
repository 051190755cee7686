//! What the integration goal lowers: a weighted sum of squared L2 discrepancies.

use crate::energies::discrepancy::{squared_discrepancies, DiscrepancyEnergy, DiscrepancyKind};
use crate::energies::Energy;
use crate::PointSet;

/// What the integration goal lowers: a weighted sum of squared L2 discrepancies.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// The discrepancies and their weights.
    pub parts: Vec<(DiscrepancyKind, f64)>,
}

impl Target {
    /// One squared discrepancy.
    pub fn single(kind: DiscrepancyKind) -> Target {
        Target {
            parts: vec![(kind, 1.0)],
        }
    }

    /// The default blend: D²_MD + D²_L2* + D²_CD, each divided by its value at the start,
    /// so that no one of the three figures users compare is bought at the others' cost.
    pub fn blend() -> Target {
        Target {
            parts: vec![
                (DiscrepancyKind::ModifiedL2, 1.0),
                (DiscrepancyKind::StarL2, 1.0),
                (DiscrepancyKind::CenteredL2, 1.0),
            ],
        }
    }

    /// The target as a formula, e.g. `D²_MD/… + D²_L2*/…` for the blend.
    pub fn name(&self) -> String {
        let names: Vec<String> = self
            .parts
            .iter()
            .map(|&(k, w)| {
                let e = DiscrepancyEnergy::new(k).name();
                if w == 1.0 {
                    e
                } else {
                    format!("{w}·{e}")
                }
            })
            .collect();
        if self.parts.len() > 1 && self.parts.iter().all(|&(_, w)| w == 1.0) {
            format!("{} (each relative to the start)", names.join(" + "))
        } else {
            names.join(" + ")
        }
    }

    pub(crate) fn kinds(&self) -> Vec<DiscrepancyKind> {
        self.parts.iter().map(|&(k, _)| k).collect()
    }

    /// The weighted sum at `points` (one fused pass over the pairs).
    pub fn value(&self, points: &PointSet) -> f64 {
        squared_discrepancies(points, &self.kinds())
            .iter()
            .zip(&self.parts)
            .map(|(v, &(_, w))| w * v)
            .sum()
    }

    /// [`Target::value`] where `sums` asks for exact sums; above its size, the weighted
    /// sum of the squared discrepancies estimated from random pairs
    /// ([`crate::quality::metrics::Metrics::compute_with`]), O(n s + pairs · s).
    pub fn value_with(&self, points: &PointSet, sums: crate::quality::metrics::Sums) -> f64 {
        if !sums.estimates(points.n()) {
            return self.value(points);
        }
        let sampled = crate::energies::discrepancy::sampled_squared_discrepancies(
            points, sums.pairs, sums.seed,
        );
        self.parts
            .iter()
            // The estimates come in the order of `DiscrepancyKind`'s variants.
            .map(|&(k, w)| w * sampled[k as usize].value)
            .sum()
    }

    /// The same target with each weight divided by its discrepancy at `points`, so every
    /// part starts at its weight.
    pub fn normalised_at(&self, points: &PointSet) -> Target {
        let values = squared_discrepancies(points, &self.kinds());
        Target {
            parts: self
                .parts
                .iter()
                .zip(values)
                .map(|(&(k, w), v)| (k, if v > 0.0 { w / v } else { w }))
                .collect(),
        }
    }

    pub(crate) fn fits(&self, s: usize) -> bool {
        self.parts
            .iter()
            .all(|&(k, _)| crate::energies::discrepancy::closed_form_fits(k, s))
    }
}
