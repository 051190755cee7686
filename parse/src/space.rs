//! Where the points live, as users write it: boxes and bounds as LO1,HI1,..., region
//! expressions and the built-in shapes' grammar, checked once for every front end.

use crate::names;
use std::sync::Arc;
use stillpoint_domains::region::ImplicitRegion;
use stillpoint_domains::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex};
use stillpoint_domains::{Domain, Error, PointSet};

/// The built-in shapes of the grammar ([`RegionSpec::domain`]), each followed by its
/// numbers (`ball:1`): the one list the option table and help read.
pub mod shape {
    /// `ball:R[@C1,C2,..]`.
    pub const BALL: &str = "ball";
    /// `ellipsoid:A1,A2,..[@C1,..]`.
    pub const ELLIPSOID: &str = "ellipsoid";
    /// `box:LO1,HI1,LO2,HI2,..`.
    pub const BOX: &str = "box";
    /// `simplex` (its dimension from s).
    pub const SIMPLEX: &str = "simplex";
    /// `polytope:FILE` (rows a1 .. as b meaning a·x ≤ b, within a bounding box).
    pub const POLYTOPE: &str = "polytope";
    /// Every shape, in the order help lists them.
    pub const ALL: [&str; 5] = [BALL, ELLIPSOID, BOX, SIMPLEX, POLYTOPE];
}

/// A box or bounds given as LO1, HI1, LO2, HI2, …: split into (lo, hi), refusing an odd
/// count, LO ≥ HI, and a width that overflows or vanishes next to the coordinates (it
/// leaves nothing to draw or sample on). `name` and `shown` are the option and its
/// value as the caller spells them, for the refusal.
pub fn intervals(name: &str, shown: &str, v: &[f64]) -> Result<(Vec<f64>, Vec<f64>), Error> {
    if v.is_empty() || !v.len().is_multiple_of(2) || v.iter().any(|x| !x.is_finite()) {
        return Err(Error::invalid(
            name,
            shown,
            "LO1,HI1,LO2,HI2,...: two finite numbers per dimension",
        ));
    }
    let lo: Vec<f64> = v.iter().step_by(2).copied().collect();
    let hi: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
    if let Some(k) = (0..lo.len()).find(|&k| lo[k] >= hi[k]) {
        return Err(Error::invalid(
            name,
            shown,
            format!(
                "LO < HI, but dimension {} has LO = {} ≥ HI = {}",
                k + 1,
                lo[k],
                hi[k]
            ),
        ));
    }
    if let Some(k) = (0..lo.len()).find(|&k| {
        let w = hi[k] - lo[k];
        !(w.is_finite() && w > 1e-150 && w > 1e-12 * lo[k].abs().max(hi[k].abs()))
    }) {
        return Err(Error::invalid(
            name,
            shown,
            format!(
                "a width that is finite, above 1e-150 and not vanishing next to the \
                 coordinates, but dimension {} is [{:?}, {:?}]",
                k + 1,
                lo[k],
                hi[k]
            ),
        ));
    }
    Ok((lo, hi))
}

/// Comma-separated finite numbers, as a box, bounds or a shape's parameters are written.
/// `name` and `whole` spell the parameter and its whole text for the refusal.
pub fn number_list(name: &str, whole: &str, text: &str) -> Result<Vec<f64>, Error> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    Error::invalid(
                        name,
                        whole,
                        format!("comma-separated finite numbers ({t:?} is not one)"),
                    )
                })
        })
        .collect()
}

/// Scaling between the unit cube and a box [lo, hi] (the `bounds` of a cube run), as
/// SciPy's `qmc.scale` does.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    /// Lower ends, one per coordinate.
    pub lo: Vec<f64>,
    /// Upper ends.
    pub hi: Vec<f64>,
}

impl Bounds {
    /// Checked bounds for `s` coordinates from interleaved LO1,HI1,...; `name` and
    /// `shown` spell the parameter for the refusal.
    pub fn new(name: &str, shown: &str, v: &[f64], s: usize) -> Result<Bounds, Error> {
        let (lo, hi) = intervals(name, shown, v)?;
        if lo.len() != s {
            return Err(Error::invalid(
                name,
                shown,
                format!(
                    "LO1,HI1,...,LO{s},HI{s}: one interval per coordinate (s = {s}), not {}",
                    lo.len()
                ),
            ));
        }
        Ok(Bounds { lo, hi })
    }

    /// The points of [0, 1]^s mapped to the box, x ↦ lo + x·(hi − lo).
    pub fn scale(&self, points: &PointSet) -> Result<PointSet, Error> {
        let s = points.s();
        let data = points
            .as_slice()
            .iter()
            .enumerate()
            .map(|(i, &x)| self.lo[i % s] + x * (self.hi[i % s] - self.lo[i % s]))
            .collect();
        PointSet::new(points.n(), s, data)
    }

    /// Points of the box mapped back to [0, 1]^s; a point outside the box is refused,
    /// naming it (`source` says where the points came from).
    pub fn unscale(&self, points: &PointSet, source: &str) -> Result<PointSet, Error> {
        let s = points.s();
        let mut data = Vec::with_capacity(points.coordinate_count());
        for (i, &x) in points.as_slice().iter().enumerate() {
            let k = i % s;
            if !(self.lo[k] <= x && x <= self.hi[k]) {
                return Err(Error::invalid(
                    format!("{source}: point {}, coordinate {}", i / s + 1, k + 1),
                    x,
                    format!("a value inside the bounds [{}, {}]", self.lo[k], self.hi[k]),
                ));
            }
            data.push(((x - self.lo[k]) / (self.hi[k] - self.lo[k])).clamp(0.0, 1.0));
        }
        PointSet::new(points.n(), s, data)
    }

    /// The bounds as interleaved LO1,HI1,... text (what a file header records).
    pub fn text(&self) -> String {
        let v: Vec<f64> = self
            .lo
            .iter()
            .zip(&self.hi)
            .flat_map(|(a, b)| [*a, *b])
            .collect();
        numbers_text(&v)
    }
}

/// Uniform samples of the box that a region given by an expression must have at least
/// one of inside, so that an empty region (or a sign slip in g) is refused before a run
/// rather than found by a start that never fills. Fixed seed: the check is deterministic.
const REGION_PROBES: usize = 4096;

/// Where a region run's points live, as the user described it: the domain, and the
/// description recorded in checkpoints and file headers.
pub struct RegionSpec<'a> {
    /// `g(x) ≤ 0` as an expression in x1..xs (or x, y, z).
    pub expression: Option<&'a str>,
    /// The box LO1,HI1,... of an expression or a polytope.
    pub bbox: Option<&'a [f64]>,
    /// A built-in shape: `ball:R[@C..]`, `ellipsoid:A1,..[@C..]`, `box:LO1,HI1,..`,
    /// `simplex`, `polytope:FILE`.
    pub shape: Option<&'a str>,
    /// The dimension when the caller gave one (a shape without a centre needs it).
    pub s: Option<usize>,
}

impl RegionSpec<'_> {
    /// The domain, or the refusal of the first bad part; `spell` writes a parameter's
    /// name the caller's way (`--shape`, `shape`).
    pub fn domain(&self, spell: &dyn Fn(&str) -> String) -> Result<Arc<dyn Domain>, Error> {
        let dim_check = |got: usize| -> Result<(), Error> {
            match self.s {
                Some(s) if s != got => Err(Error::invalid(
                    spell("s"),
                    s,
                    format!("the region's dimension, {got} (or no {})", spell("s")),
                )),
                _ => Ok(()),
            }
        };
        let box_of = |what: &str| -> Result<(Vec<f64>, Vec<f64>), Error> {
            let v = self.bbox.ok_or_else(|| {
                Error::invalid(
                    spell(names::BOX),
                    "none",
                    format!("LO1,HI1,LO2,HI2,...: {what} needs a bounding box"),
                )
            })?;
            intervals(&spell(names::BOX), &numbers_text(v), v)
        };
        if self.expression.is_some() && self.shape.is_some() {
            return Err(Error::invalid(
                spell(names::SHAPE),
                self.shape.unwrap_or_default(),
                format!(
                    "either {} or {}, not both",
                    spell(names::REGION),
                    spell(names::SHAPE)
                ),
            ));
        }
        if let Some(expr) = self.expression {
            let (lo, hi) = box_of("a region expression")?;
            dim_check(lo.len())?;
            let g = crate::expr::RegionExpr::parse(expr, lo.len()).map_err(|e| {
                Error::invalid(
                    spell(names::REGION),
                    expr,
                    format!("an expression g(x): {e}"),
                )
            })?;
            let r = ImplicitRegion::new(g.into_fn(), lo, hi)?;
            r.check(REGION_PROBES, 0)
                .map_err(|e| Error::invalid(spell(names::REGION), expr, e.to_string()))?;
            return Ok(Arc::new(r));
        }
        let spec = self.shape.unwrap_or_default();
        let name = spell(names::SHAPE);
        let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let need_s = || {
            self.s.ok_or_else(|| {
                Error::invalid(
                    spell("s"),
                    "none",
                    format!("the dimension: the shape {spec} does not give it"),
                )
            })
        };
        let numbers = |text: &str| number_list(&name, spec, text);
        let split_at = |text: &str| -> Result<(Vec<f64>, Option<Vec<f64>>), Error> {
            match text.split_once('@') {
                Some((a, c)) => Ok((numbers(a)?, Some(numbers(c)?))),
                None => Ok((numbers(text)?, None)),
            }
        };
        let lib = |e: Error| Error::invalid(&name, spec, e.to_string());
        let domain: Arc<dyn Domain> = match kind.trim() {
            shape::BALL => {
                let (r, c) = split_at(rest)?;
                if r.len() != 1 {
                    return Err(Error::invalid(&name, spec, "ball:R or ball:R@C1,C2,..."));
                }
                let c = match c {
                    Some(c) => c,
                    None => vec![0.0; need_s()?],
                };
                Arc::new(Ball::new(c, r[0]).map_err(lib)?)
            }
            shape::ELLIPSOID => {
                let (a, c) = split_at(rest)?;
                let c = c.unwrap_or_else(|| vec![0.0; a.len()]);
                Arc::new(Ellipsoid::new(c, a).map_err(lib)?)
            }
            shape::BOX => {
                let (lo, hi) = intervals(&name, spec, &numbers(rest)?)?;
                Arc::new(BoxRegion::new(lo, hi).map_err(lib)?)
            }
            shape::SIMPLEX => Arc::new(Simplex::new(need_s()?).map_err(lib)?),
            shape::POLYTOPE => {
                let rows = stillpoint_io::read_points(std::path::Path::new(rest))
                    .map_err(|e| Error::invalid(&name, spec, format!("a readable file: {e}")))?;
                if rows.s() < 2 {
                    return Err(Error::invalid(
                        &name,
                        spec,
                        "a file whose rows are a1 .. as b, meaning a·x ≤ b (at least 2 numbers)",
                    ));
                }
                let a: Vec<Vec<f64>> = rows.rows().map(|r| r[..r.len() - 1].to_vec()).collect();
                let b: Vec<f64> = rows.rows().map(|r| r[r.len() - 1]).collect();
                let (lo, hi) = box_of("a polytope")?;
                Arc::new(Polytope::new(a, b, lo, hi).map_err(lib)?)
            }
            _ => {
                return Err(Error::invalid(
                    &name,
                    spec,
                    "ball:R[@C1,..], ellipsoid:A1,..[@C1,..], box:LO1,HI1,.., simplex or \
                     polytope:FILE",
                ))
            }
        };
        dim_check(domain.dim())?;
        Ok(domain)
    }
}

/// Numbers as the comma-separated text a user would write.
pub fn numbers_text(v: &[f64]) -> String {
    v.iter()
        .map(|&x| {
            // Whole numbers as integers, the rest in the shortest form that reads back.
            if x.fract() == 0.0 && x.abs() < 1e16 {
                format!("{}", x as i64)
            } else {
                format!("{x:?}")
            }
        })
        .collect::<Vec<_>>()
        .join(",")
}
