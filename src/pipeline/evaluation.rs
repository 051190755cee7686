//! The request of `eval` (Python's `metrics`): a [`Request`] holding options of the
//! [`Group::Eval`] group, resolved into how a point set is measured ([`Measure`]). As
//! for a run, the resolution is the only place where a combination is refused, each
//! refusal naming the option as the front end spells it.

use super::options::{in_group, Command, Group, ALL};
use super::request::{plain, Arg, Request};
use crate::design::DesignSpace;
use crate::plan::constraints::ConstraintSpec;
use crate::plan::space::{number_list, Bounds, RegionSpec};
use crate::quality::metrics::Sums;
use crate::{Error, PointSet};

/// How a point set is measured.
#[derive(Debug, Clone)]
pub enum Measure {
    /// The unit cube's figures (`eval`'s default).
    Cube {
        /// The box the points were scaled to (as given, and its numbers), mapped back to
        /// the unit cube first.
        bounds: Option<(String, Vec<f64>)>,
        /// Exact or estimated pair sums.
        sums: Sums,
    },
    /// The figures in a region given by an expression (with its box) or a shape.
    Region {
        /// g of {g ≤ 0}.
        expression: Option<String>,
        /// The bounding box.
        bbox: Option<Vec<f64>>,
        /// A built-in shape.
        shape: Option<String>,
    },
    /// The figures in {A x ≤ b} ∩ box, or of mixtures.
    Constrained {
        /// The constraints' texts.
        texts: Vec<String>,
        /// The box.
        bbox: Option<Vec<f64>>,
        /// The points are mixtures.
        mixture: bool,
    },
    /// A design's figures in its space.
    Design(Box<DesignSpace>),
}

impl Request {
    /// Resolves an `eval` request with the library's own parameter names.
    pub fn resolve_eval(&self) -> Result<Measure, Error> {
        self.resolve_eval_as(&plain)
    }

    /// Resolves an `eval` request: how the points are measured, or a refusal naming the
    /// option as `spell` writes it. Only options of [`Group::Eval`] are taken.
    pub fn resolve_eval_as(&self, spell: &dyn Fn(&str) -> String) -> Result<Measure, Error> {
        EvalResolver { r: self, spell }.resolve()
    }
}

/// The resolution of one `eval` request: each measure's rules in a method of its own.
struct EvalResolver<'a> {
    r: &'a Request,
    spell: &'a dyn Fn(&str) -> String,
}

impl EvalResolver<'_> {
    fn bad(&self, name: &str, value: &dyn std::fmt::Display, expected: String) -> Error {
        Error::invalid((self.spell)(name), value, expected)
    }

    fn given(&self, name: &str) -> bool {
        self.r.get(name).is_some()
    }

    /// The first of `names` that is given.
    fn first(&self, names: &[&'static str]) -> Option<&'static str> {
        names.iter().copied().find(|n| self.given(n))
    }

    fn text(&self, name: &str) -> Result<Option<String>, Error> {
        match self.r.get(name) {
            None => Ok(None),
            Some(Arg::Text(t)) => Ok(Some(t.clone())),
            Some(other) => Err(self.bad(name, other, "text".into())),
        }
    }

    fn numbers(&self, name: &str) -> Result<Option<Vec<f64>>, Error> {
        match self.r.get(name) {
            None => Ok(None),
            Some(Arg::Numbers(v)) => Ok(Some(v.clone())),
            Some(Arg::Counts(v)) => Ok(Some(v.iter().map(|&k| k as f64).collect())),
            Some(Arg::Text(t)) => number_list(&(self.spell)(name), t, t).map(Some),
            Some(other) => Err(self.bad(name, other, "LO1,HI1,LO2,HI2,...".into())),
        }
    }

    fn resolve(&self) -> Result<Measure, Error> {
        if let Some(d) = ALL
            .iter()
            .find(|d| !d.takes(Command::Eval) && self.given(d.name))
        {
            let taken: Vec<String> = in_group(Group::Eval)
                .map(|d| (self.spell)(d.name))
                .collect();
            return Err(self.bad(
                d.name,
                &"given to measure points",
                format!(
                    "only the options that say how to measure: {}",
                    taken.join(", ")
                ),
            ));
        }
        let exact = match self.r.get("exact") {
            None | Some(Arg::Bool(false)) => false,
            Some(Arg::Bool(true)) => true,
            Some(a @ Arg::Text(t)) => match t.trim().to_ascii_lowercase().as_str() {
                "true" => true,
                "false" => false,
                _ => return Err(self.bad("exact", a, "true or false".into())),
            },
            Some(a) => return Err(self.bad("exact", a, "true or false".into())),
        };
        let mixture = match self.r.get("mixture") {
            None | Some(Arg::Bool(false)) => false,
            Some(Arg::Bool(true)) => true,
            Some(a) => return Err(self.bad("mixture", a, "true or false".into())),
        };
        // The figures of a region or a design are exact at every size: `exact` would
        // change nothing there.
        let not_cube = self.given("region")
            || self.given("shape")
            || self.given("constraints")
            || mixture
            || self.given("space");
        if exact && not_cube {
            return Err(self.bad(
                "exact",
                &"given to measure points in a region or a design space",
                "exact only for the unit cube's figures (a region's and a design's are \
                 computed whole)"
                    .into(),
            ));
        }
        if self.given("constraints") || mixture {
            return self.constrained(mixture);
        }
        if self.given("space") {
            return self.design();
        }
        if let Some(c) = self.r.get("correlation") {
            return Err(self.bad(
                "correlation",
                c,
                format!(
                    "a correlation with a design space ({}) whose continuous variables it \
                     correlates",
                    (self.spell)("space")
                ),
            ));
        }
        if self.given("region") || self.given("shape") {
            return self.region();
        }
        self.cube(exact)
    }

    /// Points in {A x ≤ b} ∩ box, or mixtures.
    fn constrained(&self, mixture: bool) -> Result<Measure, Error> {
        let spell = self.spell;
        let name = if mixture { "mixture" } else { "constraints" };
        if let Some(other) = self.first(&["region", "shape", "bounds", "space"]) {
            return Err(self.bad(
                other,
                &format!("given with {}", spell(name)),
                format!(
                    "no {} with {}: give the region one way (the constraints cut the \
                     box {} gives)",
                    spell(other),
                    spell(name),
                    spell("box")
                ),
            ));
        }
        let texts = match self.r.get("constraints") {
            None => Vec::new(),
            Some(Arg::Text(t)) => vec![t.clone()],
            Some(Arg::Texts(v)) => v.clone(),
            Some(Arg::Counts(v)) if v.is_empty() => Vec::new(),
            Some(Arg::Numbers(v)) if v.is_empty() => Vec::new(),
            Some(other) => {
                return Err(self.bad(
                    "constraints",
                    other,
                    "a linear constraint as text, such as \"x1 + 2*x2 <= 1\", or a list \
                     of them"
                        .into(),
                ))
            }
        };
        Ok(Measure::Constrained {
            texts,
            bbox: self.numbers("box")?,
            mixture,
        })
    }

    /// A design in its space (and the correlation of its continuous variables).
    fn design(&self) -> Result<Measure, Error> {
        let spell = self.spell;
        if let Some(other) = self.first(&["region", "shape", "box", "bounds"]) {
            return Err(self.bad(
                other,
                &format!("given with {}", spell("space")),
                format!(
                    "no {} with {}: a design's variables carry their own ranges",
                    spell(other),
                    spell("space")
                ),
            ));
        }
        let items = match self.r.get("space") {
            Some(Arg::Texts(v)) => v.clone(),
            Some(Arg::Text(t)) => vec![t.clone()],
            Some(other) => return Err(self.bad("space", other, "variables NAME=TYPE".into())),
            None => Vec::new(),
        };
        let mut space = DesignSpace::parse(&spell("space"), &items)?;
        let corr = spell("correlation");
        match self.r.get("correlation") {
            None => {}
            Some(Arg::Text(t)) => space.correlate_rows(&corr, t)?,
            Some(c @ Arg::Points(p)) => {
                space.correlate(&corr, &c.to_string(), p.as_slice().to_vec())?
            }
            Some(c @ Arg::Numbers(v)) => space.correlate(&corr, &c.to_string(), v.clone())?,
            Some(other) => {
                return Err(self.bad("correlation", other, "rows of numbers: 1,0.5;0.5,1".into()))
            }
        }
        Ok(Measure::Design(Box::new(space)))
    }

    /// Points in a region given by an expression or a shape.
    fn region(&self) -> Result<Measure, Error> {
        let spell = self.spell;
        if self.given("bounds") {
            return Err(self.bad(
                "bounds",
                &"given with a region",
                format!(
                    "no {} with {} or {}: a region's points are in its own coordinates",
                    spell("bounds"),
                    spell("region"),
                    spell("shape")
                ),
            ));
        }
        Ok(Measure::Region {
            expression: self.text("region")?,
            bbox: self.numbers("box")?,
            shape: self.text("shape")?,
        })
    }

    /// Points in the unit cube (or scaled to `bounds`).
    fn cube(&self, exact: bool) -> Result<Measure, Error> {
        if let Some(b) = self.r.get("box") {
            let spell = self.spell;
            return Err(self.bad(
                "box",
                b,
                format!(
                    "a box only with {} EXPR or {} polytope:FILE (it bounds them)",
                    spell("region"),
                    spell("shape")
                ),
            ));
        }
        let bounds = match self.r.get("bounds") {
            None => None,
            Some(a @ Arg::Pair(lo, hi)) if lo.len() == hi.len() => Some((
                a.to_string(),
                lo.iter().zip(hi).flat_map(|(a, b)| [*a, *b]).collect(),
            )),
            Some(a) => self.numbers("bounds")?.map(|v| (a.to_string(), v)),
        };
        Ok(Measure::Cube {
            bounds,
            sums: if exact { Sums::EXACT } else { Sums::AUTO },
        })
    }
}

impl Measure {
    /// The points in the unit cube the figures are of: mapped back from the bounds, and
    /// checked to lie in [0, 1]^s (`source` names them in a refusal).
    pub fn unit_points(
        &self,
        points: PointSet,
        source: &str,
        spell: &dyn Fn(&str) -> String,
    ) -> Result<PointSet, Error> {
        let points = match self {
            Measure::Cube {
                bounds: Some((shown, v)),
                ..
            } => Bounds::new(&spell("bounds"), shown, v, points.s())?.unscale(&points, source)?,
            _ => points,
        };
        Ok(points)
    }

    /// The figures `eval --json` prints for `points` (a design's are
    /// [`crate::design::figures::DesignFigures`], from the file's cells).
    pub fn json(
        &self,
        points: &PointSet,
        spell: &dyn Fn(&str) -> String,
    ) -> Result<serde_json::Value, Error> {
        match self {
            Measure::Cube { sums, .. } => {
                points.check_unit_cube()?;
                Ok(crate::quality::evaluate::eval_json_with(points, *sums))
            }
            Measure::Region {
                expression,
                bbox,
                shape,
            } => {
                let domain = RegionSpec {
                    expression: expression.as_deref(),
                    bbox: bbox.as_deref(),
                    shape: shape.as_deref(),
                    s: Some(points.s()),
                }
                .domain(spell)?;
                crate::quality::region::region_eval_json(&domain, points)
            }
            Measure::Constrained {
                texts,
                bbox,
                mixture,
            } => crate::plan::constraints::constrained_eval_json(
                &ConstraintSpec {
                    texts,
                    bbox: bbox.as_deref(),
                    s: Some(points.s()),
                    mixture: *mixture,
                },
                points,
                spell,
            ),
            Measure::Design(_) => Err(Error::invalid(
                spell("space"),
                "given for a point set",
                "a design's figures come from its cells (labels and all)",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(pairs: &[(&str, Arg)]) -> Request {
        let mut r = Request::default();
        for (k, v) in pairs {
            r.set(k, v.clone()).unwrap();
        }
        r
    }

    #[test]
    fn every_refusal_names_an_option_that_was_given() {
        let text = |t: &str| Arg::Text(t.into());
        for (pairs, named) in [
            (vec![("n", Arg::Int(3))], "n"),
            (
                vec![("constraints", text("x1 <= 1")), ("region", text("x"))],
                "region",
            ),
            (
                vec![("space", text("a=normal(0,1)")), ("box", text("0,1"))],
                "box",
            ),
            (vec![("correlation", text("1,0.5;0.5,1"))], "correlation"),
            (vec![("box", text("0,1,0,1"))], "box"),
            (
                vec![("shape", text("ball:1")), ("bounds", text("0,2"))],
                "bounds",
            ),
            (
                vec![("shape", text("ball:1")), ("exact", Arg::Bool(true))],
                "exact",
            ),
        ] {
            let e = request(&pairs).resolve_eval().unwrap_err().to_string();
            assert!(e.starts_with(&format!("invalid {named} = ")), "{e}");
        }
    }

    #[test]
    fn the_cube_maps_bounds_back_before_it_measures() {
        let r = request(&[("bounds", Arg::Text("0,2,-1,1".into()))]);
        let m = r.resolve_eval().unwrap();
        let scaled = PointSet::from_rows(&[[0.5, 0.0], [1.5, 0.5]]).unwrap();
        let unit = m.unit_points(scaled, "x", &plain).unwrap();
        assert_eq!(unit.as_slice(), &[0.25, 0.5, 0.75, 0.75]);
        assert_eq!(m.json(&unit, &plain).unwrap()["n"], 2);
    }
}
