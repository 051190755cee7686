//! What the integration goal lowers: a weighted sum of squared L2 discrepancies.

use crate::PointSet;
use stillpoint_energies::discrepancy::{squared_discrepancies, DiscrepancyEnergy, DiscrepancyKind};
use stillpoint_energies::Energy;

/// From this dimension on the default target is [`Target::curved`], with the smoothness-2
/// error: below it the blend's sets already integrate the smooth test integrands at least
/// as well as scrambled Sobol' (the integration benchmark), above it they do not.
pub const SMOOTH_FROM_S: usize = 8;

/// Up to this many points the default target has the smoothness-2 error (from
/// [`SMOOTH_FROM_S`]). Its sets were measured up to n = 2048; above, where one descent
/// takes most of the run's work cap, trying the smooth target and then, when its set is
/// not below stratified Sobol' sets in all three discrepancies, descending another target
/// again would double the time (n = 20 000, s = 10: 208 s instead of about 60 s).
pub const SMOOTH_MAX_N: usize = 4096;

/// Below [`SMOOTH_HIGH_FROM_S`] the default is [`Target::curved`] up to this many points
/// and [`Target::smooth_blend_for`] above. The curved sets were measured up to n = 1500;
/// above, at n = 2000, s = 12 and n = 4000, s = 10, the check against Sobol' sets refused
/// them (D_MD 0.5 % above), and each refusal costs a whole descent (4000 × 10: 87 s
/// instead of 55 s).
pub const CURVED_MAX_N_BELOW_HIGH_S: usize = 1500;

/// The weight of the smoothness-2 error in [`Target::smooth_blend`] (`--target
/// blend-smooth`, and the curved target's fallback below s = 15), against 1 for each
/// discrepancy (all relative to the start). With 1 the sets integrated the smooth test
/// integrands best, but their D_MD and CD rose to those of scrambled Sobol' or of
/// SciPy's random-cd Latin hypercube in some cells (n = 32–1024 at s = 8, 10; n = 128,
/// 200 at s = 15, 20); with 1/4 they stayed below in every cell of the integration
/// benchmark and integrated almost as well at s = 8 and 10 (less well at 15 and 20).
pub const SMOOTH_SHARE: f64 = 0.25;

/// From this dimension on the smoothness-2 error of [`Target::smooth_blend_for`] weighs
/// [`SMOOTH_SHARE_HIGH_S`]: at s = 15 and 20, with 1/4 the sets still integrated the smooth Genz families worse than
/// scrambled Sobol' (geometric means 1.34, 1.54, 1.53, 1.14 for oscillatory, product
/// peak, corner peak, Gaussian), with 1/2 less so (1.15, 1.36, 1.38, 1.04), with 3/4
/// better again (1.01, 1.29, 1.27, 0.97), while D_MD, D_L2* and CD stayed below the
/// Sobol' and random-cd LHS means in all 23 cells (CD within 0.5 % at n = 128, s = 15);
/// with 1 CD rose to those means.
pub const SMOOTH_HIGH_FROM_S: usize = 15;

/// The smoothness-2 error's weight in [`Target::smooth_blend_for`] from
/// [`SMOOTH_HIGH_FROM_S`] on, and the curved error's in [`Target::curved`] at every s.
pub const SMOOTH_SHARE_HIGH_S: f64 = 0.75;

/// The weight of D²_L2* in [`Target::curved`], against 1 for CD (both relative to the
/// start): as little as keeps D_L2* below scrambled Sobol's and the random-cd Latin
/// hypercube's means (without it, it rose above them at n = 64–400, by up to 62 %). D_L2*
/// and D_MD are anchored at the origin, and their own term of a point, Π_j (1 − x_j) and
/// Π_j (2 − x_j), grows like 2^s near it: at s = 20 the sets lowered on them (the blend)
/// kept out of that corner, and integrated Genz's corner peak, which sits there, 12–39 %
/// too low. With weight 0.015 its geometric-mean error against Sobol' went from 1.22 to
/// 0.69; with 0.05, 0.79; with 0.25, 1.03 (12 cells at s = 15 and 20, the curvature
/// weighed 12×).
pub const STAR_TRACE: f64 = 0.015;

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

    /// The blend with the worst-case error for integrands of smoothness 2 added
    /// ([`DiscrepancyKind::Smooth`]), each part relative to the start: `--target
    /// blend-smooth`, and the fallback of [`Target::curved`]. The three discrepancies weigh
    /// interactions of every order alike; at high s the integrands users have are dominated
    /// by low orders, and sets lowered on the blend alone integrate them worse than
    /// scrambled Sobol'.
    pub fn smooth_blend() -> Target {
        let mut t = Target::blend();
        t.parts.push((DiscrepancyKind::Smooth, SMOOTH_SHARE));
        t
    }

    /// [`Target::smooth_blend`] with the smooth error's weight for dimension s:
    /// [`SMOOTH_SHARE`], or [`SMOOTH_SHARE_HIGH_S`] from [`SMOOTH_HIGH_FROM_S`] on.
    pub fn smooth_blend_for(s: usize) -> Target {
        let mut t = Target::blend();
        let share = if s >= SMOOTH_HIGH_FROM_S {
            SMOOTH_SHARE_HIGH_S
        } else {
            SMOOTH_SHARE
        };
        t.parts.push((DiscrepancyKind::Smooth, share));
        t
    }

    /// The default from [`SMOOTH_FROM_S`] on: D²_CD, the smoothness-2 error with the
    /// mean curvature weighed more ([`DiscrepancyKind::Curved`]) at
    /// [`SMOOTH_SHARE_HIGH_S`], and a trace of D²_L2* ([`STAR_TRACE`]), each relative to the
    /// start. Its parts but the trace are unchanged when a coordinate is reflected
    /// (x ↦ 1 − x), so the set has no preferred corner; the curvature weight buys the
    /// product peak and Gaussian (the module docs of the discrepancies say why).
    pub fn curved() -> Target {
        Target {
            parts: vec![
                (DiscrepancyKind::CenteredL2, 1.0),
                (DiscrepancyKind::Curved, SMOOTH_SHARE_HIGH_S),
                (DiscrepancyKind::StarL2, STAR_TRACE),
            ],
        }
    }

    /// The default target for n points at dimension s, where the set is descended and
    /// n ≤ [`SMOOTH_MAX_N`]: [`Target::curved`] from [`SMOOTH_FROM_S`] on (below
    /// [`SMOOTH_HIGH_FROM_S`] only up to [`CURVED_MAX_N_BELOW_HIGH_S`] points, then
    /// [`Target::smooth_blend_for`]); [`Target::blend`] otherwise (a set too large to
    /// descend is one scrambled Sobol' set, and its report's target is then estimated from
    /// random pairs, which the smooth error has no form for).
    pub fn default_for(n: usize, s: usize) -> Target {
        use crate::effort::{Budget, Effort};
        if s >= SMOOTH_FROM_S
            && n <= SMOOTH_MAX_N
            && Budget::of(n, s, &Effort::default()).descends()
        {
            if s < SMOOTH_HIGH_FROM_S && n > CURVED_MAX_N_BELOW_HIGH_S {
                Target::smooth_blend_for(s)
            } else {
                Target::curved()
            }
        } else {
            Target::blend()
        }
    }

    /// The default target of a grown set (`--extend`, `--nested`): [`Target::default_for`],
    /// but the smooth blend where that is [`Target::curved`]. A grown set has no check
    /// against Sobol' sets to fall back on, and the curved target's nested prefixes at
    /// s = 10 were 11 % above Sobol's D_MD at 1024 points (the smooth blend's 3.5 %).
    pub fn default_grown_for(n: usize, s: usize) -> Target {
        let t = Target::default_for(n, s);
        if t.is_curved() {
            Target::smooth_blend_for(s)
        } else {
            t
        }
    }

    /// Whether the target has a smoothness-2 part, whose sets start from the lattice of
    /// the tent randomisation.
    pub fn is_smooth(&self) -> bool {
        self.parts.iter().any(|&(k, _)| k.smoothness() == 2)
    }

    /// Whether the target has the curved smoothness-2 part ([`Target::curved`]).
    pub fn is_curved(&self) -> bool {
        self.parts
            .iter()
            .any(|&(k, _)| k == DiscrepancyKind::Curved)
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

    /// The discrepancy kind of each part, in order.
    pub fn kinds(&self) -> Vec<DiscrepancyKind> {
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
    /// ([`crate::metrics::Metrics::compute_with`]), O(n s + pairs · s).
    pub fn value_with(&self, points: &PointSet, sums: crate::metrics::Sums) -> f64 {
        if !sums.estimates(points.n()) {
            return self.value(points);
        }
        let sampled = stillpoint_energies::discrepancy::sampled_squared_discrepancies(
            points,
            sums.pairs_for(points.n()),
            sums.seed,
        );
        self.parts
            .iter()
            .map(|&(k, w)| {
                // The estimates are the report's five squares; a kind without a sampled
                // form (the smoothness-2 errors) is summed exactly.
                let v = match k.reported() {
                    Some(m) => sampled[m].value,
                    None => squared_discrepancies(points, &[k])[0],
                };
                w * v
            })
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

    /// Whether every part of the target has a closed form at dimension `s` (above it the
    /// descent has nothing exact to lower).
    pub fn fits(&self, s: usize) -> bool {
        self.parts
            .iter()
            .all(|&(k, _)| stillpoint_energies::discrepancy::closed_form_fits(k, s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn smooth_share(t: &Target) -> Option<f64> {
        t.parts
            .iter()
            .find(|p| p.0 == DiscrepancyKind::Smooth)
            .map(|p| p.1)
    }

    #[test]
    fn from_s_8_the_default_is_curved_and_the_anchored_parts_give_way() {
        assert_eq!(Target::default_for(200, 7), Target::blend());
        assert_eq!(
            smooth_share(&Target::smooth_blend_for(10)),
            Some(SMOOTH_SHARE)
        );
        assert_eq!(
            Target::default_for(CURVED_MAX_N_BELOW_HIGH_S + 1, 10),
            Target::smooth_blend_for(10)
        );
        assert_eq!(
            Target::default_for(CURVED_MAX_N_BELOW_HIGH_S + 1, 15),
            Target::curved()
        );
        for s in [8, 10, 15, 20] {
            let t = Target::default_for(200, s);
            assert_eq!(t, Target::curved());
            assert!(t.is_smooth() && t.is_curved());
            // No modified L2, and the star L2 only as a trace.
            let weight = |k| t.parts.iter().find(|p| p.0 == k).map(|p| p.1);
            assert_eq!(weight(DiscrepancyKind::ModifiedL2), None);
            assert_eq!(weight(DiscrepancyKind::StarL2), Some(STAR_TRACE));
            assert_eq!(weight(DiscrepancyKind::Curved), Some(SMOOTH_SHARE_HIGH_S));
        }
        assert_eq!(
            smooth_share(&Target::smooth_blend_for(15)),
            Some(SMOOTH_SHARE_HIGH_S)
        );
    }
}
