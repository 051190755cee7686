//! The request of `eval` (Python's `metrics`): a [`Request`] holding options of the
//! [`Group::Eval`](super::options::Group::Eval) group, resolved into how a point set is measured ([`Measure`]). As
//! for a run, the resolution is the only place where a combination is refused, each
//! refusal naming the option as the front end spells it.

use super::options::Opt;
use super::request::{plain, Request};
use crate::design::DesignSpace;
use crate::plan::constraints::ConstraintSpec;
use crate::plan::space::{Bounds, RegionSpec};
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
    /// option as `spell` writes it. Only options of [`Group::Eval`](super::options::Group::Eval) are taken.
    pub fn resolve_eval_as(&self, spell: &dyn Fn(&str) -> String) -> Result<Measure, Error> {
        super::request::resolve::Ctx::new(self, spell).resolve_eval()
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
            } => Bounds::new(&spell(Opt::bounds.name()), shown, v, points.s())?
                .unscale(&points, source)?,
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
                spell(Opt::space.name()),
                "given for a point set",
                "a design's figures come from its cells (labels and all)",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::request::Arg;

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
