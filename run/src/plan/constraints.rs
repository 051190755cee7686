//! Linear constraints as users write them (`x1 + 2*x2 <= 1`, read by
//! [`stillpoint_parse::constraint`]) and mixtures (components ≥ 0 that sum to one), made once
//! for every front end into a polytope {A x ≤ b} ∩ box.
//!
//! A mixture of S components lives on a flat set of R^S, where no region run can spread
//! points; it is run in its first S − 1 components instead, where x_S = 1 − Σ x_k turns
//! the bounds of x_S into two cuts on the sum and every constraint mentioning x_S into one
//! on the others. [`Mixture::lift`] appends x_S to every point afterwards.

use crate::{Domain, Error, PointSet};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::Arc;
pub use stillpoint_domains::shapes::MixtureRegion;
use stillpoint_domains::shapes::Polytope;
use stillpoint_parse::constraint::{parse_constraint, Row};
use stillpoint_parse::names;
use stillpoint_parse::space::{intervals, numbers_text};

/// The fewest of [`ACCEPTANCE_PROBE`] uniform draws in the box that must fall in the
/// polytope for the box to be kept as given; a smaller share (a simplex of side 1e-6 in
/// [0, 1]^6) would make every run draw millions of points in vain.
const MIN_INSIDE: usize = 100;

/// How many uniform draws in the box measure the polytope's share of it.
const ACCEPTANCE_PROBE: usize = 100_000;

/// The box shrunk to bounds the rows imply, when the polytope fills too small a share
/// of it for drawing in the box to find points: for each row a·x ≤ b and coordinate j,
/// a_j x_j ≤ b − Σ_{k≠j} min(a_k x_k) over the box, repeated while it shrinks. The set
/// {A x ≤ b} ∩ box is the same; a box the polytope fills well is kept exactly, so that
/// such runs draw what they always drew.
fn tightened(a: &[Vec<f64>], b: &[f64], lo: Vec<f64>, hi: Vec<f64>) -> (Vec<f64>, Vec<f64>) {
    let s = lo.len();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0x5eed_b0c5);
    let mut x = vec![0.0; s];
    let mut inside = 0;
    for _ in 0..ACCEPTANCE_PROBE {
        for j in 0..s {
            x[j] = lo[j] + (hi[j] - lo[j]) * rng.random::<f64>();
        }
        let ok = a
            .iter()
            .zip(b)
            .all(|(row, &bi)| row.iter().zip(&x).map(|(c, v)| c * v).sum::<f64>() <= bi);
        inside += usize::from(ok);
        if inside >= MIN_INSIDE {
            return (lo, hi);
        }
    }
    let (mut lo2, mut hi2) = (lo.clone(), hi.clone());
    for _ in 0..(4 * s).max(8) {
        let mut shrunk = false;
        for (row, &bi) in a.iter().zip(b) {
            let least: Vec<f64> = (0..s)
                .map(|k| (row[k] * lo2[k]).min(row[k] * hi2[k]))
                .collect();
            let total: f64 = least.iter().sum();
            for j in 0..s {
                if row[j] == 0.0 {
                    continue;
                }
                let bound = (bi - (total - least[j])) / row[j];
                if !bound.is_finite() {
                    continue;
                }
                if row[j] > 0.0 && bound < hi2[j] {
                    hi2[j] = bound.max(lo2[j]);
                    shrunk = true;
                } else if row[j] < 0.0 && bound > lo2[j] {
                    lo2[j] = bound.min(hi2[j]);
                    shrunk = true;
                }
            }
        }
        if !shrunk {
            break;
        }
    }
    // A box shrunk to nothing in some coordinate is left to the polytope's own refusal
    // of a set without interior, which names the user's box.
    if lo2.iter().zip(&hi2).all(|(l, h)| l < h) {
        (lo2, hi2)
    } else {
        (lo, hi)
    }
}

/// A mixture's components: bounds [lo_k, hi_k] ⊆ [0, 1] for each of S components.
#[derive(Debug, Clone, PartialEq)]
pub struct Mixture {
    /// Lower bounds of the S components.
    pub lo: Vec<f64>,
    /// Upper bounds.
    pub hi: Vec<f64>,
}

/// How far the computed last component may fall outside its bounds by rounding (the
/// sum of S − 1 numbers in [0, 1], checked by the polytope with unit normals) before it
/// is a bug rather than rounding.
fn lift_tolerance(components: usize) -> f64 {
    1e-15 * (components as f64 / 8.0).max(1.0)
}

impl Mixture {
    /// The number of components S.
    pub fn components(&self) -> usize {
        self.lo.len()
    }

    /// Points of the first S − 1 components with x_S = 1 − Σ x_k appended. A last
    /// component outside its bounds by more than rounding, or a sum off 1 by more than
    /// 1e-12, is refused rather than written.
    pub fn lift(&self, p: &PointSet) -> Result<PointSet, Error> {
        let big_s = self.components();
        if p.s() + 1 != big_s {
            return Err(Error::Numerical(format!(
                "a mixture of {big_s} components from points of {} coordinates",
                p.s()
            )));
        }
        let (lo, hi) = (self.lo[big_s - 1], self.hi[big_s - 1]);
        let tol = lift_tolerance(big_s);
        let mut data = Vec::with_capacity(p.n() * big_s);
        for (i, row) in p.rows().enumerate() {
            let mut last = 1.0 - row.iter().sum::<f64>();
            if (lo - tol..lo).contains(&last) {
                last = lo;
            } else if last > hi && last <= hi + tol {
                last = hi;
            }
            let inside = row
                .iter()
                .enumerate()
                .all(|(k, &v)| self.lo[k] <= v && v <= self.hi[k])
                && lo <= last
                && last <= hi;
            let sum = row.iter().sum::<f64>() + last;
            if !inside || (sum - 1.0).abs() > 1e-12 {
                return Err(Error::Numerical(format!(
                    "mixture point {}: components {:?} and {last:?} leave their bounds or \
                     do not sum to 1 (a bug: the run keeps points inside)",
                    i + 1,
                    row
                )));
            }
            data.extend_from_slice(row);
            data.push(last);
        }
        PointSet::new(p.n(), big_s, data)
    }
}

/// A region given by linear constraints (and a mixture's sum).
pub struct Constrained {
    /// The polytope the run spreads its points in (a mixture's first S − 1 components).
    pub domain: Arc<dyn Domain>,
    /// The mixture whose last component is appended, if one.
    pub mixture: Option<Mixture>,
}

/// What a constrained region is made from, as the caller gave it.
pub struct ConstraintSpec<'a> {
    /// The constraints' texts.
    pub texts: &'a [String],
    /// The box LO1,HI1,... (a mixture's per-component bounds).
    pub bbox: Option<&'a [f64]>,
    /// The dimension, if given (a mixture's number of components).
    pub s: Option<usize>,
    /// The components are ≥ 0 and sum to 1.
    pub mixture: bool,
}

impl ConstraintSpec<'_> {
    /// The polytope, or the refusal of the first bad part; `spell` writes a parameter's
    /// name the caller's way (`--constraint`, `constraints`).
    pub fn build(&self, spell: &dyn Fn(&str) -> String) -> Result<Constrained, Error> {
        if self.mixture {
            return self.mixture_polytope(spell);
        }
        let v = self.bbox.ok_or_else(|| {
            Error::invalid(
                spell(names::BOX),
                "none",
                format!(
                    "LO1,HI1,LO2,HI2,...: {} needs a box (it gives the dimension and \
                     bounds the set)",
                    spell(names::CONSTRAINTS)
                ),
            )
        })?;
        let (lo, hi) = intervals(&spell(names::BOX), &numbers_text(v), v)?;
        let s = lo.len();
        if let Some(given) = self.s.filter(|&g| g != s) {
            return Err(Error::invalid(
                spell("s"),
                given,
                format!("the box's dimension, {s} (or no {})", spell("s")),
            ));
        }
        let mut a = Vec::new();
        let mut b = Vec::new();
        for text in self.texts {
            for row in self.rows(text, s, spell)? {
                if row.equality {
                    return Err(Error::invalid(
                        spell(names::CONSTRAINTS),
                        text,
                        format!(
                            "an inequality (<= or >=): an equality leaves a flat set with no \
                             room for points; for components that sum to 1 use {}",
                            spell(names::MIXTURE)
                        ),
                    ));
                }
                // A row of huge or tiny coefficients (1e300*x1 <= 1e299, that is
                // x1 <= 0.1) is divided by its largest one: the polytope squares its
                // normals, which would overflow or underflow.
                let big = row.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let f = if (1e-50..=1e50).contains(&big) {
                    1.0
                } else {
                    big
                };
                a.push(row.a.iter().map(|v| v / f).collect());
                b.push(row.b / f);
            }
        }
        let (lo, hi) = tightened(&a, &b, lo, hi);
        // The rows and the box are checked above: the polytope refuses only a set
        // without interior.
        let polytope = Polytope::new(a, b, lo, hi).map_err(|_| {
            Error::invalid(
                spell(names::CONSTRAINTS),
                self.texts.join("; "),
                format!(
                    "constraints that leave a set with interior inside the box {}; these \
                     leave it empty or flat",
                    numbers_text(v)
                ),
            )
        })?;
        Ok(Constrained {
            domain: Arc::new(polytope),
            mixture: None,
        })
    }

    fn rows(
        &self,
        text: &str,
        s: usize,
        spell: &dyn Fn(&str) -> String,
    ) -> Result<Vec<Row>, Error> {
        parse_constraint(text, s).map_err(|e| {
            Error::invalid(
                spell(names::CONSTRAINTS),
                text,
                format!(
                    "a linear constraint in x1..x{s} such as \"x1 + 2*x2 <= 1\" (numbers, \
                     variables, + - * /, parentheses, one of <= >= ≤ ≥): {e}"
                ),
            )
        })
    }

    /// The mixture's bounds, checked: S pairs within [0, 1] whose lows sum below 1 and
    /// highs above it.
    fn mixture_bounds(&self, spell: &dyn Fn(&str) -> String) -> Result<Mixture, Error> {
        let (lo, hi) = match self.bbox {
            Some(v) => intervals(&spell(names::BOX), &numbers_text(v), v)?,
            None => {
                let s = self.s.ok_or_else(|| {
                    Error::invalid(
                        spell("s"),
                        "none",
                        format!(
                            "the number of components of {} (at least 2)",
                            spell(names::MIXTURE)
                        ),
                    )
                })?;
                (vec![0.0; s], vec![1.0; s])
            }
        };
        let big_s = lo.len();
        let shown = || numbers_text(self.bbox.unwrap_or_default());
        if let Some(given) = self.s.filter(|&g| g != big_s) {
            return Err(Error::invalid(
                spell("s"),
                given,
                format!(
                    "the number of components, {big_s} (one LO,HI pair of {} each)",
                    spell(names::BOX)
                ),
            ));
        }
        if big_s < 2 {
            return Err(Error::invalid(
                spell("s"),
                big_s,
                format!("at least 2 components with {}", spell(names::MIXTURE)),
            ));
        }
        if let Some(k) = (0..big_s).find(|&k| lo[k] < 0.0 || hi[k] > 1.0) {
            return Err(Error::invalid(
                spell(names::BOX),
                shown(),
                format!(
                    "bounds of mixture components within [0, 1] ({}), but component {} has \
                     [{}, {}]",
                    spell(names::MIXTURE),
                    k + 1,
                    lo[k],
                    hi[k]
                ),
            ));
        }
        let (sum_lo, sum_hi) = (lo.iter().sum::<f64>(), hi.iter().sum::<f64>());
        if sum_lo >= 1.0 || sum_hi <= 1.0 {
            return Err(Error::invalid(
                spell(names::BOX),
                shown(),
                format!(
                    "component bounds that leave mixtures with room ({}: the lows must sum \
                     below 1 and the highs above 1, but they sum to {sum_lo} and {sum_hi})",
                    spell(names::MIXTURE)
                ),
            ));
        }
        Ok(Mixture { lo, hi })
    }

    /// The polytope of a mixture in its first S − 1 components.
    fn mixture_polytope(&self, spell: &dyn Fn(&str) -> String) -> Result<Constrained, Error> {
        let m = self.mixture_bounds(spell)?;
        let big_s = m.components();
        let s = big_s - 1;
        let (sum_lo, sum_hi) = (m.lo.iter().sum::<f64>(), m.hi.iter().sum::<f64>());
        // Each component's range given the others' bounds: a tighter box, so that
        // uniform draws in it fall inside more often.
        let lo: Vec<f64> = (0..s)
            .map(|k| m.lo[k].max(1.0 - (sum_hi - m.hi[k])))
            .collect();
        let hi: Vec<f64> = (0..s)
            .map(|k| m.hi[k].min(1.0 - (sum_lo - m.lo[k])))
            .collect();
        // x_S = 1 − Σ x_k within [lo_S, hi_S].
        let mut a = vec![vec![1.0; s], vec![-1.0; s]];
        let mut b = vec![1.0 - m.lo[s], m.hi[s] - 1.0];
        for text in self.texts {
            for row in self.rows(text, big_s, spell)? {
                let last = row.a[s];
                let c: Vec<f64> = row.a[..s].iter().map(|v| v - last).collect();
                let d = row.b - last;
                let scale = row.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let tol = 1e-12 * scale.max(d.abs()).max(1.0);
                if c.iter().all(|v| v.abs() <= tol) {
                    // A multiple of the sum: always or never true of a mixture.
                    let holds = if row.equality {
                        d.abs() <= tol
                    } else {
                        d >= -tol
                    };
                    if holds {
                        continue;
                    }
                    return Err(Error::invalid(
                        spell(names::CONSTRAINTS),
                        text,
                        format!(
                            "a constraint some mixture meets: with {} the components sum \
                             to 1, which this contradicts",
                            spell(names::MIXTURE)
                        ),
                    ));
                }
                if row.equality {
                    return Err(Error::invalid(
                        spell(names::CONSTRAINTS),
                        text,
                        format!(
                            "an inequality (<= or >=): {} holds the sum to 1 already, and \
                             any other equality leaves a flat set with no room for points",
                            spell(names::MIXTURE)
                        ),
                    ));
                }
                a.push(c);
                b.push(d);
            }
        }
        let bounds: Vec<f64> = m.lo.iter().zip(&m.hi).flat_map(|(a, b)| [*a, *b]).collect();
        let polytope = Polytope::new(a, b, lo, hi).map_err(|_| {
            Error::invalid(
                spell(names::CONSTRAINTS),
                if self.texts.is_empty() {
                    "none".to_string()
                } else {
                    self.texts.join("; ")
                },
                format!(
                    "constraints that leave mixtures with room within the component bounds \
                     ({} {}, {}); these leave none, or only a flat set",
                    spell(names::BOX),
                    numbers_text(&bounds),
                    spell(names::MIXTURE)
                ),
            )
        })?;
        Ok(Constrained {
            domain: Arc::new(MixtureRegion::new(polytope)),
            mixture: Some(m),
        })
    }
}

/// `eval` of points in a constrained region: the region figures
/// ([`stillpoint_quality::region::region_eval_json`]) in the polytope of `spec`. For a
/// mixture the points have its S components, each row summing to 1 within 1e-9 (refused
/// otherwise, naming the row); the figures are taken in the first S − 1 components,
/// where the region has an interior, as the run makes them.
pub fn constrained_eval_json(
    spec: &ConstraintSpec<'_>,
    points: &PointSet,
    spell: &dyn Fn(&str) -> String,
) -> Result<serde_json::Value, Error> {
    let built = spec.build(spell)?;
    let inner = match &built.mixture {
        None => points.clone(),
        Some(m) => {
            let big_s = m.components();
            if points.s() != big_s {
                return Err(Error::invalid(
                    "points",
                    format!("{} coordinates", points.s()),
                    format!("the mixture's {big_s} components"),
                ));
            }
            if let Some(i) = points
                .rows()
                .position(|r| (r.iter().sum::<f64>() - 1.0).abs() > 1e-9)
            {
                return Err(Error::invalid(
                    format!("point {}", i + 1),
                    format!(
                        "components summing to {}",
                        points.point(i).iter().sum::<f64>()
                    ),
                    "components summing to 1 (within 1e-9), as a mixture's do",
                ));
            }
            let data: Vec<f64> = points
                .rows()
                .flat_map(|r| r[..big_s - 1].to_vec())
                .collect();
            PointSet::new(points.n(), big_s - 1, data)?
        }
    };
    let mut v = stillpoint_quality::region::region_eval_json(&built.domain, &inner)?;
    if built.mixture.is_some() {
        v[names::MIXTURE] = serde_json::json!(true);
        v["note"] = serde_json::json!(
            "a mixture's figures are taken in its first S − 1 components (the last is 1 minus \
             their sum)"
        );
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spell(name: &str) -> String {
        format!("--{name}")
    }

    #[test]
    fn a_constrained_box_is_a_polytope_and_an_empty_one_is_refused() {
        let texts = vec!["x1 + 2*x2 <= 1".to_string()];
        let spec = ConstraintSpec {
            texts: &texts,
            bbox: Some(&[0.0, 1.0, 0.0, 1.0]),
            s: None,
            mixture: false,
        };
        let c = spec.build(&spell).unwrap();
        assert!(c.domain.contains(&[0.5, 0.2]));
        assert!(!c.domain.contains(&[0.5, 0.3]));
        let empty = vec!["x1 + x2 >= 3".to_string()];
        let e = ConstraintSpec {
            texts: &empty,
            ..spec
        }
        .build(&spell)
        .err()
        .unwrap()
        .to_string();
        assert!(e.starts_with("invalid --constraints = x1 + x2 >= 3"), "{e}");
        assert!(e.contains("interior"), "{e}");
        let eq = vec!["x1 + x2 = 1".to_string()];
        let e = ConstraintSpec { texts: &eq, ..spec }
            .build(&spell)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("--mixture"), "{e}");
    }

    #[test]
    fn many_components_are_drawn_from_the_simplex() {
        let none: Vec<String> = Vec::new();
        let c = ConstraintSpec {
            texts: &none,
            bbox: None,
            s: Some(10),
            mixture: true,
        }
        .build(&spell)
        .unwrap();
        // The 9-simplex keeps 1 in 362 880 uniform draws of its box.
        let p = c.domain.sample(500, 1).unwrap();
        let x = c.mixture.unwrap().lift(&p).unwrap();
        assert_eq!((x.n(), x.s()), (500, 10));
        for r in x.rows() {
            assert!((r.iter().sum::<f64>() - 1.0).abs() <= 1e-12);
            assert!(r.iter().all(|v| (0.0..=1.0).contains(v)), "{r:?}");
        }
        // Uniform on the simplex: each component's mean is 1/10.
        let mean = x.rows().map(|r| r[9]).sum::<f64>() / 500.0;
        assert!((mean - 0.1).abs() < 0.02, "{mean}");
    }

    #[test]
    fn a_mixture_is_run_in_its_first_components_and_lifted_to_sum_one() {
        let texts = vec!["x3 <= 0.5".to_string(), "x1 + x2 + x3 = 1".to_string()];
        let spec = ConstraintSpec {
            texts: &texts,
            bbox: Some(&[0.1, 0.8, 0.0, 1.0, 0.2, 1.0]),
            s: Some(3),
            mixture: true,
        };
        let c = spec.build(&spell).unwrap();
        let m = c.mixture.clone().unwrap();
        assert_eq!(c.domain.dim(), 2);
        // x3 = 1 − x1 − x2 ≤ 0.5 ⇔ x1 + x2 ≥ 0.5; x3 ≥ 0.2 ⇔ x1 + x2 ≤ 0.8.
        assert!(c.domain.contains(&[0.3, 0.3]));
        assert!(!c.domain.contains(&[0.2, 0.2]));
        assert!(!c.domain.contains(&[0.5, 0.4]));
        let p = c.domain.sample(200, 3).unwrap();
        let x = m.lift(&p).unwrap();
        for r in x.rows() {
            assert!((r.iter().sum::<f64>() - 1.0).abs() <= 1e-12);
            assert!(
                (0.2..=0.5).contains(&r[2]) && (0.1..=0.8).contains(&r[0]),
                "{r:?}"
            );
        }
        let far = PointSet::from_rows(&[[0.7, 0.3]]).unwrap();
        assert!(m.lift(&far).is_err());
        for (bbox, says) in [
            (vec![0.5, 1.0, 0.6, 1.0, 0.0, 1.0], "sum below 1"),
            (vec![0.0, 0.3, 0.0, 0.3, 0.0, 0.3], "sum below 1"),
            (vec![-0.1, 1.0, 0.0, 1.0, 0.0, 1.0], "within [0, 1]"),
        ] {
            let e = ConstraintSpec {
                bbox: Some(&bbox),
                ..spec
            }
            .build(&spell)
            .err()
            .unwrap()
            .to_string();
            assert!(e.starts_with("invalid --box") && e.contains(says), "{e}");
        }
        let never = vec!["x1 + x2 + x3 >= 2".to_string()];
        let e = ConstraintSpec {
            texts: &never,
            ..spec
        }
        .build(&spell)
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("contradicts"), "{e}");
        let nothing = vec!["x1 >= 0.79".to_string(), "x2 >= 0.2".to_string()];
        let e = ConstraintSpec {
            texts: &nothing,
            ..spec
        }
        .build(&spell)
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("room") && e.contains("--mixture"), "{e}");
    }
}
