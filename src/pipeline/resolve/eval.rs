//! The rules of measuring a set (`eval`, Python's `metrics`): only the options that say
//! how to measure, one way of giving a region, and `exact` only for the unit cube's
//! figures. The design space is read by the same rule as `generate`'s.

use super::Ctx;
use crate::pipeline::evaluation::Measure;
use crate::pipeline::options::{Command, Opt, Value, OPTS};
use crate::quality::metrics::Sums;
use crate::Error;

impl Ctx<'_> {
    /// The request resolved for `eval`: how the points are measured.
    pub(crate) fn resolve_eval(&self) -> Result<Measure, Error> {
        if let Some(o) = OPTS
            .iter()
            .copied()
            .find(|o| !o.declared().takes(Command::Eval) && self.given(*o))
        {
            let taken: Vec<String> = OPTS
                .iter()
                .filter(|t| t.declared().takes(Command::Eval))
                .map(|t| self.name(*t))
                .collect();
            return Err(self.bad(
                o,
                &"given to measure points",
                format!(
                    "only the options that say how to measure: {}",
                    taken.join(", ")
                ),
            ));
        }
        let exact = self.p.exact.value()? == Some(true);
        let mixture = self.p.mixture.value()? == Some(true);
        // The figures of a region are exact at every size: `exact` would change nothing
        // there. A design's pair figures follow the cube's rule, which `exact` lifts.
        let in_region = mixture
            || self
                .first_of(&[Opt::region, Opt::shape, Opt::constraints])
                .is_some();
        if exact && in_region {
            return Err(self.bad(
                Opt::exact,
                &"given to measure points in a region",
                "exact only for the unit cube's and a design's figures (a region's are \
                 computed whole)",
            ));
        }
        if self.given(Opt::constraints) || mixture {
            return self.measure_constrained(mixture);
        }
        if self.given(Opt::space) {
            return self.measure_design();
        }
        self.correlation_without_space()?;
        if self.given(Opt::region) || self.given(Opt::shape) {
            return self.measure_region();
        }
        self.measure_cube(exact)
    }

    /// Refuses the first of `others` given with `with`, which gives the region alone.
    fn one_way(&self, with: Opt, others: &[Opt], why: &str) -> Result<(), Error> {
        match self.first_of(others) {
            Some(other) => Err(self.bad(
                other,
                &format!("given with {}", self.name(with)),
                format!("no {} with {}: {why}", self.name(other), self.name(with)),
            )),
            None => Ok(()),
        }
    }

    /// Points in {A x ≤ b} ∩ box, or mixtures.
    fn measure_constrained(&self, mixture: bool) -> Result<Measure, Error> {
        let by = if mixture {
            Opt::mixture
        } else {
            Opt::constraints
        };
        self.one_way(
            by,
            &[Opt::region, Opt::shape, Opt::bounds, Opt::space],
            &format!(
                "give the region one way (the constraints cut the box {} gives)",
                self.name(Opt::bbox)
            ),
        )?;
        Ok(Measure::Constrained {
            texts: self.p.constraints.value()?.unwrap_or_default(),
            bbox: self.p.bbox.value()?,
            mixture,
        })
    }

    /// A design in its space (and the correlation of its continuous variables).
    fn measure_design(&self) -> Result<Measure, Error> {
        self.one_way(
            Opt::space,
            &[Opt::region, Opt::shape, Opt::bbox, Opt::bounds],
            "a design's variables carry their own ranges",
        )?;
        Ok(Measure::Design(Box::new(self.design_space()?)))
    }

    /// Points in a region given by an expression or a shape.
    fn measure_region(&self) -> Result<Measure, Error> {
        if self.given(Opt::bounds) {
            return Err(self.bad(
                Opt::bounds,
                &"given with a region",
                format!(
                    "no {} with {} or {}: a region's points are in its own coordinates",
                    self.name(Opt::bounds),
                    self.name(Opt::region),
                    self.name(Opt::shape)
                ),
            ));
        }
        Ok(Measure::Region {
            expression: self.p.region.value()?,
            bbox: self.p.bbox.value()?,
            shape: self.p.shape.value()?,
        })
    }

    /// Points in the unit cube (or scaled to `bounds`).
    fn measure_cube(&self, exact: bool) -> Result<Measure, Error> {
        if self.given(Opt::bbox) {
            return Err(self.box_alone());
        }
        let bounds = match (self.r.arg(Opt::bounds), self.p.bounds.value()?) {
            (Some(a), Some(Value::Pair(lo, hi))) if lo.len() == hi.len() => Some((
                a.to_string(),
                lo.iter().zip(&hi).flat_map(|(a, b)| [*a, *b]).collect(),
            )),
            (Some(a), Some(Value::Numbers(v))) => Some((a.to_string(), v)),
            (Some(a), Some(_)) => {
                return Err(self.bad(Opt::bounds, a, (Opt::bounds.declared().expected)()))
            }
            _ => None,
        };
        Ok(Measure::Cube {
            bounds,
            sums: if exact { Sums::EXACT } else { Sums::AUTO },
        })
    }
}
