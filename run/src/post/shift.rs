//! Periodic shift selection: the last step after a periodic energy.
//!
//! A periodic energy (U_{q,p} with finite q or q = ∞) is unchanged when the whole set is
//! shifted on the torus, x ↦ (x + c) mod 1, but the discrepancies are not: over the
//! shifts of one DEM result the modified L2 discrepancy can vary by a factor of two. So
//! after the dynamics we pick, among a fixed number of shifts, the one with the smallest
//! modified L2 discrepancy and then refine it by a compass search. The set keeps its
//! energy and its minimum periodic distance; only its placement in the cube changes.

use stillpoint_domains::wrap_unit;
use stillpoint_domains::PointSet;
use stillpoint_quality::metrics;
use stillpoint_sequences as sequences;

/// What the shift selection did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShiftOutcome {
    /// The shift c applied to every point (mod 1).
    pub shift: Vec<f64>,
    /// Modified L2 discrepancy (root) before.
    pub modified_l2_before: f64,
    /// Modified L2 discrepancy (root) after.
    pub modified_l2_after: f64,
    /// Number of discrepancy evaluations.
    pub evaluations: usize,
}

/// `points` shifted by `c` on the torus.
pub fn shifted(points: &PointSet, c: &[f64]) -> PointSet {
    let s = points.s();
    let data = points
        .as_slice()
        .iter()
        .enumerate()
        .map(|(idx, v)| wrap_unit(v + c[idx % s]).0)
        .collect();
    PointSet::new(points.n(), s, data).expect("a shift keeps a valid set valid")
}

/// Tries the zero shift and `candidates` Halton-spread shifts, keeps the one with the
/// smallest modified L2 discrepancy, then refines it by a compass search with about as
/// many evaluations again. Deterministic: no random numbers are drawn.
pub fn best_shift(points: &PointSet, candidates: usize) -> (PointSet, ShiftOutcome) {
    let s = points.s();
    let objective = |c: &[f64]| metrics::modified_l2_squared(&shifted(points, c));
    let before = metrics::modified_l2_squared(points);
    let mut best_c = vec![0.0; s];
    let mut best = before;
    let mut evals = 1;
    if candidates > 0 {
        // Halton points in the shift cube spread the candidates evenly for any count.
        let grid = sequences::halton(candidates, s).expect("candidates ≥ 1 and s ≥ 1");
        for c in grid.rows() {
            let v = objective(c);
            evals += 1;
            if v < best {
                best = v;
                best_c = c.to_vec();
            }
        }
        // Compass search: the discrepancy is piecewise smooth in c with kinks where two
        // points swap order, so a derivative-free local search is the robust choice.
        let mut step = 0.5 / (candidates as f64).powf(1.0 / s as f64);
        let budget = evals + candidates.max(4 * s);
        while step > 1e-6 && evals < budget {
            let mut improved = false;
            for k in 0..s {
                for dir in [1.0, -1.0] {
                    if evals >= budget {
                        break;
                    }
                    let mut c = best_c.clone();
                    c[k] = (c[k] + dir * step).rem_euclid(1.0);
                    let v = objective(&c);
                    evals += 1;
                    if v < best {
                        best = v;
                        best_c = c;
                        improved = true;
                    }
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
    }
    let out = shifted(points, &best_c);
    let outcome = ShiftOutcome {
        shift: best_c,
        modified_l2_before: before.max(0.0).sqrt(),
        modified_l2_after: metrics::modified_l2(&out),
        evaluations: evals,
    };
    (out, outcome)
}

#[cfg(test)]
mod tests {
    use super::*;
    use stillpoint_energies::{Distance, Energy, Uqp};

    #[test]
    fn shift_keeps_energy_and_never_worsens_md() {
        let x = sequences::random(80, 2, 3).unwrap();
        let (y, o) = best_shift(&x, 32);
        assert!(o.modified_l2_after <= o.modified_l2_before);
        assert!(o.modified_l2_after < 0.95 * o.modified_l2_before, "{o:?}");
        let e = Uqp::new(Distance::Q(0.4), 0.9).unwrap();
        assert!((e.value(&y) - e.value(&x)).abs() < 1e-10 * e.value(&x));
        let d0 = metrics::min_distance_periodic(&x);
        let d1 = metrics::min_distance_periodic(&y);
        assert!((d0 - d1).abs() < 1e-12);
        assert!(y.check_unit_cube().is_ok());
        let (_, none) = best_shift(&x, 0);
        assert_eq!(none.shift, vec![0.0, 0.0]);
    }
}
