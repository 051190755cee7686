//! One request for every front end. A [`Request`] holds every option a user can set on a
//! run, each optional and each as the front end received it ([`Arg`]); [`Request::resolve`]
//! is the only place where option rules live: which pipeline runs, which options belong
//! to which space, goal and solver, the checks of nested and grown sets, the region and
//! shape grammar, the names of energies and discrepancies. It gives the run's
//! configuration ([`Resolved`]) or an error naming the parameter as the front end spells
//! it (`--log-every` on the command line, `log_every` in Python), through the `spell`
//! function the front end passes.
//!
//! An option that would have no effect on the chosen run is refused, never ignored.

use super::measure::{cube_rule, CubeRule};
use crate::config::{EnergyKind, GenerateConfig, Goal, Init, Space};
use crate::design::DesignSpace;
use crate::energies::discrepancy::DiscrepancyKind;
use crate::energies::Domain;
use crate::energies::{Distance, Precision};
use crate::goals::integration::lattice::LATTICE_FROM_N;
use crate::integrators::{Kappa, Restart};
use crate::plan::constraints::{Constrained, ConstraintSpec, Mixture};
use crate::plan::space::{numbers_text, Bounds, RegionSpec};
use crate::plan::start::MAX_SHIFTS;
use crate::post::randomize::Randomize;
use crate::quality::target::Target;
use crate::sequences::{self, Baseline};
use crate::solve::Solver;
use crate::{Error, PointSet};
use serde_json::json;
use std::sync::Arc;

/// A value as a front end received it: the command line gives text, Python gives typed
/// values; resolving gives either a meaning.
#[derive(Debug, Clone, PartialEq)]
pub enum Arg {
    /// Text (every value on the command line; strings from Python).
    Text(String),
    /// A whole number.
    Int(i128),
    /// A floating-point number.
    Float(f64),
    /// A truth value.
    Bool(bool),
    /// A list of numbers (a box or bounds as LO1,HI1,...).
    Numbers(Vec<f64>),
    /// Lower and upper ends given apart, as SciPy's `qmc.scale(l_bounds, u_bounds)`
    /// takes them; one number stands for every coordinate.
    Pair(Vec<f64>, Vec<f64>),
    /// A list of whole numbers (nested sizes).
    Counts(Vec<i128>),
    /// A point set (a start, or points to keep).
    Points(PointSet),
    /// A list of texts (a design space's variables as `NAME=TYPE`).
    Texts(Vec<String>),
}

impl std::fmt::Display for Arg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Arg::Text(t) => f.write_str(t),
            Arg::Int(i) => write!(f, "{i}"),
            // Python's 1e300 is echoed as written, not as 301 digits.
            Arg::Float(v) => f.write_str(&crate::design::dist::num(*v)),
            Arg::Bool(b) => write!(f, "{b}"),
            Arg::Numbers(v) => f.write_str(&numbers_text(v)),
            Arg::Pair(lo, hi) => write!(f, "({}; {})", numbers_text(lo), numbers_text(hi)),
            Arg::Counts(v) => {
                let t: Vec<String> = v.iter().map(|k| k.to_string()).collect();
                f.write_str(&t.join(","))
            }
            Arg::Points(p) => write!(f, "{} points in {} dimensions", p.n(), p.s()),
            Arg::Texts(v) => f.write_str(&v.join(" ")),
        }
    }
}

impl From<&str> for Arg {
    fn from(t: &str) -> Arg {
        Arg::Text(t.to_string())
    }
}
impl From<String> for Arg {
    fn from(t: String) -> Arg {
        Arg::Text(t)
    }
}
impl From<usize> for Arg {
    fn from(v: usize) -> Arg {
        Arg::Int(v as i128)
    }
}
impl From<u64> for Arg {
    fn from(v: u64) -> Arg {
        Arg::Int(v.into())
    }
}
impl From<f64> for Arg {
    fn from(v: f64) -> Arg {
        Arg::Float(v)
    }
}
impl From<PointSet> for Arg {
    fn from(p: PointSet) -> Arg {
        Arg::Points(p)
    }
}

pub use super::options::Request;
use super::options::{declared, in_group, Command, Group, ALL, OPTIONS};

/// What a resolved request runs.
#[derive(Debug, Clone)]
pub enum Job {
    /// The library's pipeline with this configuration.
    Run(Box<GenerateConfig>),
    /// A baseline construction.
    Baseline {
        /// Which.
        baseline: Baseline,
        /// Points.
        n: usize,
        /// Dimension.
        s: usize,
        /// Seed.
        seed: u64,
    },
    /// The randomised lattice made for a space's laws ([`crate::sequences::law_lattice`]).
    Law {
        /// Points.
        n: usize,
        /// Per coordinate, whether its law is unbounded (scored with the first-order
        /// kernel).
        unbounded: Vec<bool>,
        /// Seed.
        seed: u64,
    },
}

impl Job {
    /// The number of points the job makes.
    pub fn n(&self) -> usize {
        match self {
            Job::Run(cfg) => cfg.n,
            Job::Baseline { n, .. } | Job::Law { n, .. } => *n,
        }
    }

    /// The seed the job is made from.
    pub fn seed(&self) -> u64 {
        match self {
            Job::Run(cfg) => cfg.seed,
            Job::Baseline { seed, .. } | Job::Law { seed, .. } => *seed,
        }
    }
}

/// A request resolved: what runs, and how the written points are scaled.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The run or the baseline.
    pub job: Job,
    /// Scaling of the written points (a cube run with `bounds`).
    pub bounds: Option<Bounds>,
    /// The design space the set is carried into (levels, slices, marginals).
    pub design: Option<DesignSpace>,
    /// With a design space, how its unit-cube set is made and carried into it, as
    /// [`cube_rule`] decided once for the request.
    pub rule: Option<CubeRule>,
    /// The mixture whose last component is appended to the run's points.
    pub mixture: Option<Mixture>,
}

impl Resolved {
    /// The request with its design space carried by `rule`: the rule's own construction,
    /// if it has one, makes the unit-cube set in place of the request's run (same n,
    /// dimension and seed), so that the run, its estimate and its report all follow the
    /// rule. The resolution calls it with [`cube_rule`]'s answer.
    pub fn with_rule(mut self, rule: CubeRule) -> Resolved {
        let (n, seed) = (self.job.n(), self.job.seed());
        let s = match &self.job {
            Job::Run(cfg) => cfg.s,
            Job::Baseline { s, .. } => *s,
            Job::Law { unbounded, .. } => unbounded.len(),
        };
        if let Some(baseline) = rule.construction() {
            self.job = Job::Baseline {
                baseline,
                n,
                s,
                seed,
            };
        } else if rule == CubeRule::LawLattice {
            let unbounded = self
                .design
                .as_ref()
                .map_or_else(|| vec![false; s], |space| space.unbounded());
            self.job = Job::Law { n, unbounded, seed };
        }
        self.rule = Some(rule);
        self
    }
}

/// The library's own spelling of a parameter: its name as the request writes it.
pub fn plain(name: &str) -> String {
    name.to_string()
}

/// The most points a single run accepts (beyond it a set of f64 cannot be addressed).
/// The words `target` takes, as a refusal lists them.
pub(crate) const TARGETS: &str = "blend (D²_MD + D²_L2* + D²_CD), blend-smooth (the blend and the \
                       smoothness-2 error), curved (D²_CD, the smoothness-2 error with \
                       curvature weighed more and a trace of D²_L2*; the default from s = 8 \
                       below 500 points), lattice (the shifted tent lattice, no descent; the \
                       default from 500 points on and at s = 1), md, l2star, cd, periodic or \
                       smooth";

const MAX_COUNT: i128 = u32::MAX as i128 * 16;

impl Request {
    /// A request for `n` points in `s` dimensions with every other option at its default.
    pub fn new(n: usize, s: usize) -> Request {
        Request {
            n: Some(n.into()),
            s: Some(s.into()),
            ..Request::default()
        }
    }

    /// Sets the parameter `name` (as [`Request`]'s fields are named; `box` for `bbox`)
    /// to `value`; an unknown name is refused with the accepted ones. This is how a front
    /// end with keyword arguments fills a request.
    pub fn set(&mut self, name: &str, value: Arg) -> Result<(), Error> {
        let slot = self.slot_mut(name).ok_or_else(|| {
            Error::invalid(
                "keyword argument",
                name,
                format!("one of {}", Request::names().join(", ")),
            )
        })?;
        *slot = Some(value);
        Ok(())
    }

    /// The parameters [`Request::set`] accepts (each option's name in [`ALL`]).
    pub fn names() -> Vec<&'static str> {
        ALL.iter().map(|d| d.name).collect()
    }

    /// Resolves the request with the library's own parameter names.
    pub fn resolve(&self) -> Result<Resolved, Error> {
        self.resolve_as(&plain)
    }

    /// Resolves the request; `spell` writes a parameter's name as the caller's front end
    /// spells it, in every refusal.
    pub fn resolve_as(&self, spell: &dyn Fn(&str) -> String) -> Result<Resolved, Error> {
        let resolver = Resolver { r: self, spell };
        resolver.refuse_others(Command::Generate)?;
        resolver.resolve()
    }

    /// Whether the option named `name` is given.
    fn given(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    /// The first given option of `group`, in [`OPTIONS`]' order.
    fn first_given(&self, group: Group) -> Option<&'static str> {
        in_group(group).map(|d| d.name).find(|n| self.given(n))
    }
}

/// The resolution of one request: every rule of every option.
struct Resolver<'a> {
    r: &'a Request,
    spell: &'a dyn Fn(&str) -> String,
}

/// What a request's goal option asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum GoalName {
    Integration,
    SpaceFilling,
}

impl Resolver<'_> {
    /// Refuses the first option given that `command` does not take (an option of the
    /// integration to a tolerance given to `generate`, say), naming it.
    fn refuse_others(&self, command: Command) -> Result<(), Error> {
        let Some(d) = ALL
            .iter()
            .find(|d| !d.takes(command) && self.r.given(d.name))
        else {
            return Ok(());
        };
        let takes: Vec<&str> = d.commands.iter().map(|c| c.name()).collect();
        Err(self.refuse(
            d.name,
            format!(
                "no {} with {}: it is an option of {}",
                (self.spell)(d.name),
                command.name(),
                takes.join(" and ")
            ),
        ))
    }

    /// A yes/no option: `true`/`false` (as a boolean, or as text, ASCII case ignored);
    /// absent is no.
    fn flag(&self, name: &str, arg: &Option<Arg>) -> Result<bool, Error> {
        match arg {
            None | Some(Arg::Bool(false)) => Ok(false),
            Some(Arg::Bool(true)) => Ok(true),
            Some(a @ Arg::Text(t)) => match t.trim().to_ascii_lowercase().as_str() {
                "true" => Ok(true),
                "false" => Ok(false),
                _ => Err(self.bad(name, a, "true or false")),
            },
            Some(a) => Err(self.bad(name, a, "true or false")),
        }
    }

    /// The refusal of option `name` for the value `typed`, which is the value as the
    /// front end received it (never a meaning made of it, such as a description).
    fn bad(&self, name: &str, typed: &Arg, expected: impl Into<String>) -> Error {
        Error::invalid((self.spell)(name), typed, expected)
    }

    /// The refusal of the option `name` as given in the request (a combination that
    /// cannot keep its promise): its value as typed, or `none` when it is not given.
    fn refuse(&self, name: &str, expected: impl Into<String>) -> Error {
        match self.r.get(name) {
            Some(typed) => self.bad(name, typed, expected),
            None => self.absent(name, expected),
        }
    }

    /// The refusal of a missing option `name`: `none` stands for its value.
    fn absent(&self, name: &str, expected: impl Into<String>) -> Error {
        Error::invalid((self.spell)(name), "none", expected)
    }

    fn word(&self, name: &str, arg: &Arg, expected: &str) -> Result<String, Error> {
        match arg {
            Arg::Text(t) => Ok(t.trim().to_ascii_lowercase().replace('_', "-")),
            other => Err(self.bad(name, other, expected)),
        }
    }

    /// A whole number in [lo, MAX_COUNT] (text is parsed).
    fn count(&self, name: &str, arg: &Arg, lo: i128, expected: &str) -> Result<usize, Error> {
        let v = match arg {
            Arg::Int(i) => Some(*i),
            Arg::Text(t) => t.trim().parse::<i128>().ok(),
            Arg::Float(f) if f.fract() == 0.0 && f.abs() < 1e30 => Some(*f as i128),
            _ => None,
        };
        match v {
            Some(v) if v >= lo && v <= MAX_COUNT => Ok(v as usize),
            Some(v) if v > MAX_COUNT => Err(self.bad(
                name,
                arg,
                format!(
                    "{expected}, at most {MAX_COUNT} (a set that large does not fit in memory)"
                ),
            )),
            _ => Err(self.bad(name, arg, expected)),
        }
    }

    /// A finite number (text is parsed).
    fn number(&self, name: &str, arg: &Arg, expected: &str) -> Result<f64, Error> {
        let v = match arg {
            Arg::Int(i) => Some(*i as f64),
            Arg::Float(f) => Some(*f),
            Arg::Text(t) => t.trim().parse::<f64>().ok(),
            _ => None,
        };
        v.filter(|v| v.is_finite())
            .ok_or_else(|| self.bad(name, arg, expected))
    }

    fn numbers(&self, name: &str, arg: &Arg) -> Result<Vec<f64>, Error> {
        match arg {
            Arg::Numbers(v) => Ok(v.clone()),
            Arg::Counts(v) => Ok(v.iter().map(|&k| k as f64).collect()),
            Arg::Text(t) => crate::plan::space::number_list(&(self.spell)(name), t, t),
            other => Err(self.bad(name, other, "LO1,HI1,LO2,HI2,...")),
        }
    }

    fn text<'b>(&self, name: &str, arg: &'b Option<Arg>) -> Result<Option<&'b str>, Error> {
        match arg {
            None => Ok(None),
            Some(Arg::Text(t)) => Ok(Some(t.as_str())),
            Some(other) => Err(self.bad(name, other, "text")),
        }
    }

    fn points<'b>(&self, name: &str, arg: &'b Option<Arg>) -> Result<Option<&'b PointSet>, Error> {
        match arg {
            None => Ok(None),
            Some(Arg::Points(p)) => Ok(Some(p)),
            Some(other) => Err(self.bad(name, other, "a point set")),
        }
    }

    fn resolve(&self) -> Result<Resolved, Error> {
        let r = self.r;
        if r.space.is_some() {
            return self.design();
        }
        if let Some(c) = &r.correlation {
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
        let seed = match &r.seed {
            None => 0,
            Some(Arg::Int(v)) if (0..=u64::MAX as i128).contains(v) => *v as u64,
            // A whole float (7.0) is the whole number it says; below 2^64 it is exact.
            Some(Arg::Float(f))
                if f.fract() == 0.0 && (0.0..18446744073709551616.0).contains(f) =>
            {
                *f as u64
            }
            Some(Arg::Text(t)) if t.trim().parse::<u64>().is_ok() => t.trim().parse().unwrap_or(0),
            Some(other) => return Err(self.bad("seed", other, "a whole number in [0, 2^64)")),
        };
        if let Some(job) = self.baseline(seed)? {
            return Ok(job);
        }
        let constrained = r.constraints.is_some() || self.flag("mixture", &r.mixture)?;
        let in_region = r.region.is_some() || r.shape.is_some() || constrained;
        let goal = self.goal(in_region)?;
        let (mut cfg, mixture) = if in_region {
            self.region_config()?
        } else {
            (self.cube_config(&goal)?, None)
        };
        cfg.seed = seed;
        cfg.goal = match goal {
            // The default target follows the dimension ([`Target::default_for`], for a
            // grown set [`Target::default_grown_for`]).
            Goal::Integration(_) if r.target.is_none() => {
                Goal::Integration(if cfg.extend.is_some() || !cfg.nested.is_empty() {
                    Target::default_grown_for(cfg.n, cfg.s)
                } else {
                    Target::default_for(cfg.n, cfg.s)
                })
            }
            // `blend-smooth` by name weighs its smooth part for s ([`Target::smooth_blend_for`]).
            Goal::Integration(t) if t == Target::smooth_blend() => {
                Goal::Integration(Target::smooth_blend_for(cfg.s))
            }
            g => g,
        };
        self.common(&mut cfg)?;
        self.lattice(&mut cfg, in_region)?;
        if self.flag("exact", &r.exact)? {
            cfg.sums = crate::quality::metrics::Sums::EXACT;
        }
        sequences::check_size(cfg.n, cfg.s).map_err(|e| self.too_large(e, cfg.n))?;
        let bounds = match &r.bounds {
            None => None,
            Some(_) if in_region => {
                return Err(self.refuse(
                    "bounds",
                    format!(
                        "no bounds in a region: its points are in its own coordinates \
                         already ({} scales the unit cube)",
                        (self.spell)("bounds")
                    ),
                ))
            }
            Some(arg) => Some(self.bounds(arg, cfg.s)?),
        };
        Ok(Resolved {
            job: Job::Run(Box::new(cfg)),
            bounds,
            design: None,
            rule: None,
            mixture,
        })
    }

    /// A run in the unit cube of one coordinate per variable, carried into the design
    /// space afterwards by the rule [`cube_rule`] gives (dealt, or a randomised set
    /// through each law's inverse CDF): the options that place points elsewhere or grow
    /// a set are refused.
    fn design(&self) -> Result<Resolved, Error> {
        let r = self.r;
        let option = (self.spell)("space");
        let items = match &r.space {
            Some(Arg::Texts(v)) => v.clone(),
            Some(Arg::Text(t)) => vec![t.clone()],
            Some(other) => return Err(self.bad("space", other, "variables NAME=TYPE")),
            None => Vec::new(),
        };
        let mut space = DesignSpace::parse(&option, &items)?;
        let corr = (self.spell)("correlation");
        match &r.correlation {
            None => {}
            Some(Arg::Text(text)) => space.correlate_rows(&corr, text)?,
            Some(c @ Arg::Points(p)) => {
                space.correlate(&corr, &c.to_string(), p.as_slice().to_vec())?
            }
            Some(c @ Arg::Numbers(v)) => space.correlate(&corr, &c.to_string(), v.clone())?,
            Some(other) => {
                return Err(self.bad("correlation", other, "rows of numbers: 1,0.5;0.5,1"))
            }
        }
        if let Some(name) = r.first_given(Group::Placement) {
            return Err(self.refuse(
                name,
                format!(
                    "no {} with {option}: a design's variables carry their own ranges and \
                     distributions, and its levels and slices are dealt from one whole \
                     unit-cube set",
                    (self.spell)(name)
                ),
            ));
        }
        if let Some(a) = &r.s {
            let s = self.count("s", a, 1, "at least 1 dimension")?;
            if s != space.dim() {
                return Err(self.bad(
                    "s",
                    a,
                    format!(
                        "the number of variables in {option}, {} (or no {})",
                        space.dim(),
                        (self.spell)("s")
                    ),
                ));
            }
        }
        let mut inner = r.clone();
        inner.space = None;
        inner.correlation = None;
        inner.s = Some(space.dim().into());
        let mut resolved = Resolver {
            r: &inner,
            spell: self.spell,
        }
        .resolve()?;
        space.check_n(&option, resolved.job.n())?;
        let randomize = match &resolved.job {
            Job::Run(cfg) => cfg.randomize,
            Job::Baseline { .. } | Job::Law { .. } => None,
        };
        let rule = cube_rule(&space, randomize);
        resolved.design = Some(space);
        Ok(resolved.with_rule(rule))
    }

    /// A baseline asked for by `method`, which takes only n, s, seed and bounds.
    fn baseline(&self, seed: u64) -> Result<Option<Resolved>, Error> {
        let r = self.r;
        let Some(method) = &r.method else {
            return Ok(None);
        };
        let word = self.word("method", method, "paper or a baseline's name")?;
        if word == "paper" || word == "dem" {
            return Ok(None);
        }
        let baseline = Baseline::parse(&word).map_err(|_| {
            self.bad(
                "method",
                method,
                "paper (the paper's pipeline) or a baseline: random, halton, \
                 halton-scrambled, sobol, hua-wang, lattice, lhs, lhs-maximin",
            )
        })?;
        // Every option outside the baseline's own; a design space and its correlation
        // were taken off the request before.
        let refused = OPTIONS
            .iter()
            .filter(|d| !d.is(Group::Baseline) && !d.is(Group::Design))
            .map(|d| d.name)
            .find(|n| r.given(n));
        if let Some(name) = refused {
            return Err(self.refuse(
                name,
                format!(
                    "no {} with the baseline {}: a baseline takes only {}, {}, {} and {}",
                    (self.spell)(name),
                    baseline.name(),
                    (self.spell)("n"),
                    (self.spell)("s"),
                    (self.spell)("seed"),
                    (self.spell)("bounds")
                ),
            ));
        }
        let n = self.n_points()?;
        let s = match &r.s {
            Some(a) => self.count("s", a, 1, "at least 1 dimension")?,
            None => return Err(self.absent("s", "the dimension (at least 1)")),
        };
        sequences::check_size(n, s).map_err(|e| self.too_large(e, n))?;
        let bounds = match &r.bounds {
            Some(a) => Some(self.bounds(a, s)?),
            None => None,
        };
        Ok(Some(Resolved {
            job: Job::Baseline {
                baseline,
                n,
                s,
                seed,
            },
            bounds,
            design: None,
            rule: None,
            mixture: None,
        }))
    }

    /// A refusal of the run's size (n and s together) by the library's check, naming
    /// the option that gave the size with its value as typed: the nested sizes, whose last
    /// is n, or n itself (with a set to extend, the points to add; the total `n` is said).
    fn too_large(&self, e: Error, n: usize) -> Error {
        match e {
            Error::InvalidArgument { name, expected, .. } => {
                let option = if name == "n" && self.r.nested.is_some() {
                    "nested"
                } else {
                    name.as_str()
                };
                let total = match &self.r.extend {
                    Some(_) if option == "n" => format!(" (with the kept points, {n})"),
                    _ => String::new(),
                };
                self.refuse(option, format!("{expected}{total}"))
            }
            other => other,
        }
    }

    fn n_points(&self) -> Result<usize, Error> {
        match &self.r.n {
            Some(a) => self.count("n", a, 1, "at least 1 point"),
            None => Err(self.absent("n", "the number of points (at least 1)")),
        }
    }

    fn bounds(&self, arg: &Arg, s: usize) -> Result<Bounds, Error> {
        let name = (self.spell)("bounds");
        let v = match arg {
            Arg::Pair(lo, hi) => {
                let widen = |v: &Vec<f64>| -> Result<Vec<f64>, Error> {
                    match v.len() {
                        1 => Ok(vec![v[0]; s]),
                        k if k == s => Ok(v.clone()),
                        k => Err(Error::invalid(
                            &name,
                            arg,
                            format!("one number or {s} per side (the dimension), not {k}"),
                        )),
                    }
                };
                let (lo, hi) = (widen(lo)?, widen(hi)?);
                lo.iter().zip(&hi).flat_map(|(a, b)| [*a, *b]).collect()
            }
            other => self.numbers("bounds", other)?,
        };
        Bounds::new(&name, &numbers_text(&v), &v, s)
    }

    /// What the run is for: an asked goal chooses (none of the paper's options may come
    /// with it, except with space-filling in a region, whose pipeline is the region's
    /// run); without one, the paper's method, any of the paper's options or a region
    /// choose the paper's pipeline, and otherwise the integration goal.
    fn goal(&self, in_region: bool) -> Result<Goal, Error> {
        let r = self.r;
        let spell = self.spell;
        let paper = r.method.is_some();
        let asked = match &r.goal {
            None => None,
            Some(a) => Some(
                match self
                    .word("goal", a, "integration or space-filling")?
                    .as_str()
                {
                    "integration" => GoalName::Integration,
                    "space-filling" => GoalName::SpaceFilling,
                    _ => return Err(self.bad("goal", a, "integration or space-filling")),
                },
            ),
        };
        let target = match &r.target {
            None => None,
            Some(a) => Some(match self.word("target", a, TARGETS)?.as_str() {
                "blend" => Target::blend(),
                "blend-smooth" => Target::smooth_blend(),
                "curved" => Target::curved(),
                // The lattice has no target: `resolve` sets `lattice`, and the blend only
                // names the discrepancies a caller would compare.
                "lattice" => Target::blend(),
                w => Target::single(
                    DiscrepancyKind::parse(w).map_err(|_| self.bad("target", a, TARGETS))?,
                ),
            }),
        };
        // `steps` feeds the DEM stage of the space-filling goal; elsewhere it belongs to
        // the paper's pipeline.
        let expert: Vec<&str> = OPTIONS
            .iter()
            .filter(|d| d.is(Group::Paper) || d.is(Group::Descent))
            .map(|d| d.name)
            .filter(|o| r.given(o))
            .filter(|o| {
                !(declared(o).is_some_and(|d| d.is(Group::Descent))
                    && asked == Some(GoalName::SpaceFilling))
            })
            .collect();
        let goal = match asked {
            Some(g) => {
                let name = match g {
                    GoalName::Integration => "integration",
                    GoalName::SpaceFilling => "space-filling",
                };
                if paper {
                    return Err(self.refuse(
                        "goal",
                        format!(
                            "no {} with {} paper (the paper's method is its own pipeline)",
                            spell("goal"),
                            spell("method")
                        ),
                    ));
                }
                if let (Some(first), false) =
                    (expert.first(), in_region && g == GoalName::SpaceFilling)
                {
                    return Err(self.refuse(
                        first,
                        format!(
                            "no {} with {} {name}: the paper's options only with {} paper \
                             (or no {}); a goal chooses its own pipeline",
                            spell(first),
                            spell("goal"),
                            spell("method"),
                            spell("goal")
                        ),
                    ));
                }
                match g {
                    GoalName::Integration if in_region && r.extend.is_some() => {
                        return Err(self.refuse(
                            "extend",
                            format!(
                                "{} only with the space-filling run in a region (the \
                                 integration goal makes the whole set)",
                                spell("extend")
                            ),
                        ))
                    }
                    GoalName::Integration if in_region && target.is_some() => {
                        return Err(self.refuse(
                            "target",
                            "no target in a region: its discrepancies are those of the unit \
                             cube; the goal there lowers the energy distance",
                        ))
                    }
                    GoalName::Integration => Goal::Integration(Target::blend()),
                    GoalName::SpaceFilling => Goal::SpaceFilling,
                }
            }
            None if paper || !expert.is_empty() || in_region => Goal::Paper,
            None => Goal::Integration(Target::blend()),
        };
        match (goal, target) {
            (Goal::Integration(_), Some(t)) => Ok(Goal::Integration(t)),
            (_, Some(_)) => Err(self.refuse(
                "target",
                "a target only with the integration goal (the cube's default); this run's \
                 pipeline is the paper's or space-filling",
            )),
            (g, None) => Ok(g),
        }
    }

    /// The options every space shares: solver, budget, κ, restart, tolerance,
    /// randomisation, and the refusals of combinations that cannot keep their promise.
    fn common(&self, cfg: &mut GenerateConfig) -> Result<(), Error> {
        let r = self.r;
        let region = cfg.region().is_some();
        if let Some(a) = &r.integrator {
            cfg.solver = match self.word("integrator", a, "dem or lbfgs")?.as_str() {
                "dem" => Solver::Dem,
                "lbfgs" | "l-bfgs" => Solver::Lbfgs,
                _ => return Err(self.bad("integrator", a, "dem or lbfgs")),
            };
        }
        if let Some(a) = &r.steps {
            cfg.steps = self.count("steps", a, 1, "a whole number of steps ≥ 1")?;
        }
        if let Some(a) = &r.kappa {
            cfg.dem.kappa = match a {
                Arg::Text(t) if t.trim().eq_ignore_ascii_case("auto") => Kappa::default(),
                _ => {
                    let k = self.number("kappa", a, "auto or a finite number ≥ 1")?;
                    if k < 1.0 {
                        return Err(self.bad("kappa", a, "auto or a finite number ≥ 1"));
                    }
                    Kappa::Fixed(k)
                }
            };
        }
        if let Some(a) = &r.restart {
            const EXPECTED: &str = "auto (ε_p = 2/n), off, or a number ε_p > 0";
            cfg.dem.restart = match a {
                Arg::Text(t) if t.trim().eq_ignore_ascii_case("auto") => Restart::Auto,
                Arg::Text(t)
                    if ["off", "none"].contains(&t.trim().to_ascii_lowercase().as_str()) =>
                {
                    Restart::Off
                }
                _ => {
                    let e = self.number("restart", a, EXPECTED)?;
                    if e <= 0.0 {
                        return Err(self.bad("restart", a, EXPECTED));
                    }
                    Restart::Threshold(e)
                }
            };
        }
        if let Some(a) = &r.tolerance {
            let t = self.number("tolerance", a, "a number ≥ 0")?;
            if t < 0.0 {
                return Err(self.bad("tolerance", a, "a number ≥ 0"));
            }
            cfg.dem.tolerance = t;
        }
        // `randomize=True` asks for the recommended randomisation, `False` for none.
        let randomize = match &r.randomize {
            Some(Arg::Bool(false)) => None,
            other => other.as_ref(),
        };
        if let Some(a) = randomize {
            let kind = match a {
                // `true` (Python's True, the command line's bare flag): the recommended one.
                Arg::Bool(true) => Randomize::Tent,
                Arg::Text(t) if t.trim().eq_ignore_ascii_case("true") => Randomize::Tent,
                _ => Randomize::parse(&self.word("randomize", a, Randomize::EXPECTED)?)
                    .map_err(|_| self.bad("randomize", a, Randomize::EXPECTED))?,
            };
            if region {
                return Err(self.bad(
                    "randomize",
                    a,
                    "no randomisation in a region (a shift would carry points out of it; \
                     the cube only)",
                ));
            }
            if cfg.extend.is_some() || !cfg.nested.is_empty() {
                let with = if cfg.extend.is_some() {
                    "extend"
                } else {
                    "nested"
                };
                return Err(self.bad(
                    "randomize",
                    a,
                    format!(
                        "no randomisation of a grown set (here with {}): it would move the \
                         kept points ({}) and unstratify the prefixes ({}); randomise a set \
                         made for its size instead",
                        (self.spell)(with),
                        (self.spell)("extend"),
                        (self.spell)("nested")
                    ),
                ));
            }
            if kind == Randomize::Tent {
                // The tent randomisation keeps its promise only for the lattice made for
                // it, which the integration goal builds in place of its descent.
                if !matches!(cfg.goal, Goal::Integration(_)) {
                    return Err(self.bad(
                        "randomize",
                        a,
                        "tent with the integration goal (the cube's default), which makes \
                         the lattice tent is for, not with this run's pipeline (the paper's \
                         or space-filling); cells or shift randomise other sets",
                    ));
                }
                if r.target.is_some() {
                    return Err(self.refuse(
                        "target",
                        format!(
                            "no target with {} tent: the lattice for the tent randomisation \
                             is chosen by its own criterion (the randomised estimate's mean \
                             square error)",
                            (self.spell)("randomize")
                        ),
                    ));
                }
            }
            cfg.randomize = Some(kind);
        }
        Ok(())
    }

    /// Whether the integration goal's set is the shifted tent lattice: `target` lattice,
    /// or by default from [`LATTICE_FROM_N`] points on and at s = 1 (any n: the
    /// midpoints), where no target, set to extend, nested sizes or randomisation is given
    /// (`randomize` tent has its own lattice; cells and shift randomise the descent's set).
    fn lattice(&self, cfg: &mut GenerateConfig, in_region: bool) -> Result<(), Error> {
        let r = self.r;
        let asked = match &r.target {
            Some(a) => self.word("target", a, TARGETS)? == "lattice",
            None => false,
        };
        let plain = cfg.extend.is_none() && cfg.nested.is_empty() && cfg.randomize.is_none();
        if asked && (in_region || !plain) {
            return Err(self.refuse(
                "target",
                format!(
                    "lattice alone in the cube (no region, set to extend, nested sizes or \
                     randomisation): it is one set made for its size ({} \
                     tent randomises the lattice made for it)",
                    (self.spell)("randomize")
                ),
            ));
        }
        cfg.lattice = matches!(cfg.goal, Goal::Integration(_))
            && !in_region
            && (asked || (plain && r.target.is_none() && (cfg.n >= LATTICE_FROM_N || cfg.s == 1)));
        Ok(())
    }

    /// The polytope of `constraints` and `mixture`, when either is given, with the
    /// constraints' texts.
    fn constrained(
        &self,
        s: Option<usize>,
        bbox: Option<&[f64]>,
    ) -> Result<Option<(Constrained, Vec<String>)>, Error> {
        let r = self.r;
        let mixture = self.flag("mixture", &r.mixture)?;
        if r.constraints.is_none() && !mixture {
            return Ok(None);
        }
        let name = if mixture { "mixture" } else { "constraints" };
        for (other, given) in [("region", r.region.is_some()), ("shape", r.shape.is_some())] {
            if given {
                return Err(self.refuse(
                    other,
                    format!(
                        "no {} with {}: the constraints cut the box {} gives",
                        (self.spell)(other),
                        (self.spell)(name),
                        (self.spell)("box")
                    ),
                ));
            }
        }
        // A mixture runs in its first S − 1 components: points given in S would not fit.
        let points = [
            ("extend", r.extend.is_some()),
            ("init", matches!(r.init, Some(Arg::Points(_)))),
        ];
        if let (true, Some((other, _))) = (mixture, points.iter().find(|p| p.1)) {
            return Err(self.refuse(
                other,
                format!(
                    "no {} points with {}: the set is made whole, from a start of its own",
                    (self.spell)(other),
                    (self.spell)("mixture")
                ),
            ));
        }
        const EXPECTED: &str =
            "a linear constraint as text, such as \"x1 + 2*x2 <= 1\", or a list of them";
        let texts = match &r.constraints {
            None => Vec::new(),
            Some(Arg::Text(t)) => vec![t.clone()],
            Some(Arg::Texts(v)) => v.clone(),
            // An empty list reaches here typed as numbers: no constraint, the box alone.
            Some(Arg::Counts(v)) if v.is_empty() => Vec::new(),
            Some(Arg::Numbers(v)) if v.is_empty() => Vec::new(),
            Some(other) => return Err(self.bad("constraints", other, EXPECTED)),
        };
        let built = ConstraintSpec {
            texts: &texts,
            bbox,
            s,
            mixture,
        }
        .build(self.spell)?;
        Ok(Some((built, texts)))
    }

    /// The energy asked for in a region, as a word; the options that mean nothing for a
    /// region's energies are refused, not ignored.
    fn region_energy_word(&self) -> Result<Option<String>, Error> {
        let energy_word = match &self.r.energy {
            Some(a) => Some(self.word("energy", a, "e-inf-g, e-inf or e-p-g")?),
            None => None,
        };
        let r = self.r;
        let is_epg = energy_word.as_deref() == Some("e-p-g");
        for (name, given, why) in [
            ("q", r.q.is_some(), "U_{q,p} is an energy of the cube"),
            (
                "precision",
                r.precision.is_some(),
                "it sets U_{q,p}'s distance, which region energies do not use",
            ),
            (
                "polish",
                r.polish.is_some(),
                "the discrepancies it lowers live in the unit cube",
            ),
            (
                "shifts",
                r.shifts.is_some(),
                "a periodic shift would carry points out of the region",
            ),
            (
                "log_every",
                r.log_every.is_some(),
                "it logs the unit cube's discrepancies",
            ),
            (
                "p",
                r.p.is_some() && !is_epg,
                "p belongs to U_{E,p,g} (energy e-p-g) in a region",
            ),
            (
                "nested",
                r.nested.is_some(),
                "nested sets are made by the integration goal in the cube; grow a region's \
                 set with extend",
            ),
        ] {
            if given {
                return Err(self.refuse(name, format!("not in a region: {why}")));
            }
        }
        Ok(energy_word)
    }

    fn region_config(&self) -> Result<(GenerateConfig, Option<Mixture>), Error> {
        let r = self.r;
        let s = match &r.s {
            Some(a) => Some(self.count("s", a, 1, "at least 1 dimension")?),
            None => None,
        };
        let bbox = match &r.bbox {
            Some(a) => Some(self.numbers("box", a)?),
            None => None,
        };
        let spec = RegionSpec {
            expression: self.text("region", &r.region)?,
            bbox: bbox.as_deref(),
            shape: self.text("shape", &r.shape)?,
            s,
        };
        let constrained = self.constrained(s, bbox.as_deref())?;
        if r.bbox.is_some()
            && constrained.is_none()
            && spec.expression.is_none()
            && !spec.shape.is_some_and(|t| t.starts_with("polytope:"))
        {
            return Err(self.box_alone());
        }
        let (domain, mixture, texts): (Arc<dyn Domain>, _, _) = match constrained {
            Some((c, texts)) => (c.domain, c.mixture, Some(texts)),
            None => (spec.domain(self.spell)?, None, None),
        };
        let dim = domain.dim();
        let energy_word = self.region_energy_word()?;
        let old = self.points("extend", &r.extend)?.cloned();
        let m = self.n_points()?;
        let n = match &old {
            Some(p) => {
                if p.s() != dim {
                    return Err(
                        self.refuse("extend", format!("points of the region's dimension, {dim}"))
                    );
                }
                if let Some(i) = p.rows().position(|x| !domain.contains(x)) {
                    return Err(self.refuse(
                        "extend",
                        format!(
                            "old points inside the run's region; point {} is outside",
                            i + 1
                        ),
                    ));
                }
                self.grown(m, p.n())?
            }
            None => m,
        };
        let mut cfg = GenerateConfig::in_region(domain, n);
        let mut description = json!({
            "expression": self.text("region", &r.region)?,
            "box": bbox.as_deref().map(numbers_text),
            "shape": self.text("shape", &r.shape)?,
        });
        if let Some(texts) = texts {
            description["constraints"] = json!(texts);
            description["mixture"] = json!(mixture.as_ref().map(|m| m.components()));
        }
        cfg.space = Space::Region {
            domain: cfg
                .region()
                .cloned()
                .ok_or_else(|| self.absent("region", "a region"))?,
            description,
        };
        cfg.energy = match energy_word.as_deref() {
            None | Some("e-inf-g") => EnergyKind::EInfG,
            Some("e-inf") => EnergyKind::EInf,
            Some("e-p-g") => EnergyKind::EpG(match &r.p {
                Some(a) => self.positive_p(a)?,
                None => 8.0,
            }),
            Some(_) => {
                return Err(self.refuse("energy", "in a region e-inf-g (eq. 56), e-inf or e-p-g"))
            }
        };
        cfg.init = match &r.init {
            None => Init::Random,
            Some(Arg::Points(p)) => {
                if p.s() != dim || p.n() != cfg.n - old.as_ref().map_or(0, |o| o.n()) {
                    return Err(
                        self.refuse("init", format!("{} points in {dim} dimensions", cfg.n))
                    );
                }
                Init::Points(p.clone())
            }
            Some(a) => match self.word("init", a, "halton, random or points")?.as_str() {
                "random" => Init::Random,
                "halton" => Init::Halton,
                _ => return Err(self.bad("init", a, "halton, random or points")),
            },
        };
        cfg.extend = old;
        Ok((cfg, mixture))
    }

    fn box_alone(&self) -> Error {
        self.refuse(
            "box",
            format!(
                "a box only with {} EXPR or {} polytope:FILE (it bounds them)",
                (self.spell)("region"),
                (self.spell)("shape")
            ),
        )
    }

    fn positive_p(&self, a: &Arg) -> Result<f64, Error> {
        let p = self.number("p", a, "a finite number > 0")?;
        if p <= 0.0 {
            return Err(self.bad("p", a, "a finite number > 0"));
        }
        Ok(p)
    }

    /// n + m for a grown set, checked.
    fn grown(&self, m: usize, old: usize) -> Result<usize, Error> {
        m.checked_add(old)
            .filter(|&t| t as i128 <= MAX_COUNT)
            .ok_or_else(|| {
                self.refuse(
                    "n",
                    format!(
                        "a number of points to add that, with the {old} kept points, stays \
                         within {MAX_COUNT} points"
                    ),
                )
            })
    }

    fn cube_config(&self, goal: &Goal) -> Result<GenerateConfig, Error> {
        let r = self.r;
        if r.bbox.is_some() {
            return Err(self.box_alone());
        }
        let integration = matches!(goal, Goal::Integration(_));
        let mut s = match &r.s {
            Some(a) => Some(self.count("s", a, 1, "at least 1 dimension")?),
            None => None,
        };
        let old = self.points("extend", &r.extend)?.cloned();
        let init_points = match &r.init {
            Some(Arg::Points(p)) => Some(p.clone()),
            _ => None,
        };
        for (name, p) in [("extend", &old), ("init", &init_points)] {
            if let Some(p) = p {
                p.check_unit_cube()
                    .map_err(|e| self.refuse(name, format!("points in [0, 1]^s ({e})")))?;
                match s {
                    Some(s) if s != p.s() => {
                        return Err(self.refuse(
                            "s",
                            format!(
                                "the dimension of {}, {} (or no {})",
                                (self.spell)(name),
                                p.s(),
                                (self.spell)("s")
                            ),
                        ))
                    }
                    _ => s = Some(p.s()),
                }
            }
        }
        if (old.is_some() || r.nested.is_some()) && !integration {
            let name = if old.is_some() { "extend" } else { "nested" };
            return Err(self.refuse(
                name,
                format!(
                    "a grown set (not with the paper's pipeline or the space-filling goal) needs the integration goal (no {} paper, {} space-filling \
                     or paper options)",
                    (self.spell)("method"),
                    (self.spell)("goal")
                ),
            ));
        }
        if old.is_some() && r.nested.is_some() {
            return Err(self.refuse(
                "nested",
                format!(
                    "either {} or {} (a nested run builds every stage itself)",
                    (self.spell)("extend"),
                    (self.spell)("nested")
                ),
            ));
        }
        let nested = match &r.nested {
            Some(a) => self.nested(a)?,
            None => Vec::new(),
        };
        let n = match (&old, nested.last(), &init_points) {
            (Some(p), _, _) => {
                let m = match &r.n {
                    Some(a) => self.count("n", a, 1, "at least 1 point to add")?,
                    None => {
                        return Err(self.absent(
                            "n",
                            format!(
                                "{} M: the number of points to add to the {} points (at least 1)",
                                (self.spell)("n"),
                                (self.spell)("extend")
                            ),
                        ))
                    }
                };
                self.grown(m, p.n())?
            }
            (None, Some(&last), _) => {
                if let Some(a) = &r.n {
                    let n = self.count("n", a, 1, "at least 1 point")?;
                    if n != last {
                        return Err(self.refuse(
                            "n",
                            format!("the last nested size, {last} (or no {})", (self.spell)("n")),
                        ));
                    }
                }
                last
            }
            (None, None, Some(p)) => match &r.n {
                Some(a) => {
                    let n = self.count("n", a, 1, "at least 1 point")?;
                    if n != p.n() {
                        return Err(self.refuse(
                            "n",
                            format!(
                                "the number of init points, {} (or no {})",
                                p.n(),
                                (self.spell)("n")
                            ),
                        ));
                    }
                    n
                }
                None => p.n(),
            },
            (None, None, None) => self.n_points()?,
        };
        let s = s.ok_or_else(|| self.absent("s", "the dimension (at least 1)"))?;
        if n as i128 > MAX_COUNT {
            // Only nested sizes get here unchecked (a count is refused above MAX_COUNT).
            sequences::check_size(n, s).map_err(|e| self.too_large(e, n))?;
            return Err(self.refuse(
                "nested",
                format!(
                    "sizes of at most {MAX_COUNT} points (a set that large does not fit in memory)"
                ),
            ));
        }
        let mut cfg = GenerateConfig::new(n, s);
        self.paper_options(&mut cfg, init_points)?;
        cfg.extend = old;
        cfg.nested = nested;
        Ok(cfg)
    }

    /// The paper's pipeline's options in the cube: energy, (q, p), precision, start,
    /// polish, shifts, logging.
    fn paper_options(
        &self,
        cfg: &mut GenerateConfig,
        init_points: Option<PointSet>,
    ) -> Result<(), Error> {
        let r = self.r;
        if let Some(a) = &r.energy {
            const EXPECTED: &str = "in the cube uqp, e-inf, l2star, md, cd or periodic \
                                    (e-inf-g and e-p-g are energies of a region)";
            cfg.energy = match self.word("energy", a, EXPECTED)?.as_str() {
                "uqp" => EnergyKind::Uqp,
                "e-inf" => EnergyKind::EInf,
                w => EnergyKind::Discrepancy(
                    DiscrepancyKind::parse(w).map_err(|_| self.bad("energy", a, EXPECTED))?,
                ),
            };
        }
        if let Some(a) = &r.q {
            const EXPECTED: &str = "a number > 0, inf (the torus distance) or E (Euclidean)";
            let text = match a {
                Arg::Text(t) => t.clone(),
                Arg::Int(_) | Arg::Float(_) => self.number("q", a, EXPECTED)?.to_string(),
                other => return Err(self.bad("q", other, EXPECTED)),
            };
            cfg.q = Some(Distance::parse(&text).map_err(|_| self.bad("q", a, EXPECTED))?);
        }
        if let Some(a) = &r.p {
            cfg.p = Some(self.positive_p(a)?);
        }
        if let Some(a) = &r.precision {
            cfg.precision = match self.word("precision", a, "fast or full")?.as_str() {
                "fast" => Precision::Fast,
                "full" => Precision::Full,
                _ => return Err(self.bad("precision", a, "fast or full")),
            };
        }
        cfg.init = match (&r.init, init_points) {
            (_, Some(p)) => Init::Points(p),
            (None, None) => Init::Halton,
            (Some(a), None) => match self.word("init", a, "halton, random or points")?.as_str() {
                "halton" => Init::Halton,
                "random" => Init::Random,
                _ => return Err(self.bad("init", a, "halton, random or points")),
            },
        };
        if let Some(a) = &r.polish {
            const EXPECTED: &str = "none, md, l2star, cd or periodic";
            cfg.polish = match self.word("polish", a, EXPECTED)?.as_str() {
                "none" => None,
                w => Some(DiscrepancyKind::parse(w).map_err(|_| self.bad("polish", a, EXPECTED))?),
            };
        }
        if let Some(a) = &r.shifts {
            cfg.shifts = self.count(
                "shifts",
                a,
                0,
                &format!("a whole number of shifts in [0, {}]", MAX_SHIFTS),
            )?;
            if cfg.shifts > MAX_SHIFTS {
                return Err(self.bad(
                    "shifts",
                    a,
                    format!("at most {} candidate shifts", MAX_SHIFTS),
                ));
            }
        }
        cfg.log_every = match &r.log_every {
            Some(a) => self.count("log_every", a, 0, "a whole number of steps ≥ 0")?,
            None if r.trajectory.is_some() => 10,
            None => 0,
        };
        Ok(())
    }

    /// Increasing sizes N1 < N2 < ..., N1 ≥ 1, as text or a list.
    fn nested(&self, a: &Arg) -> Result<Vec<usize>, Error> {
        const EXPECTED: &str = "increasing sizes N1 < N2 < ..., N1 ≥ 1 (whole numbers)";
        let raw: Vec<i128> = match a {
            Arg::Counts(v) => v.clone(),
            Arg::Text(t) => t
                .split(',')
                .map(|x| x.trim().parse::<i128>())
                .collect::<Result<_, _>>()
                .map_err(|_| self.bad("nested", a, EXPECTED))?,
            other => return Err(self.bad("nested", other, EXPECTED)),
        };
        if raw.is_empty() || raw[0] < 1 || raw.windows(2).any(|w| w[1] <= w[0]) {
            return Err(self.bad("nested", a, EXPECTED));
        }
        // A size beyond any set's reach is kept as one just beyond it, for the check of
        // the run's size (which knows s) to refuse with the accepted range.
        Ok(raw
            .into_iter()
            .map(|k| k.min(MAX_COUNT + 1) as usize)
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(r: &Request) -> GenerateConfig {
        match r.resolve().unwrap().job {
            Job::Run(cfg) => *cfg,
            other => panic!("expected a run, got {other:?}"),
        }
    }

    #[test]
    fn defaults_are_the_integration_goal_and_paper_is_by_name() {
        assert_eq!(
            config(&Request::new(50, 3)),
            GenerateConfig::for_goal(50, 3, Goal::Integration(Target::blend()))
        );
        let mut r = Request::new(50, 3);
        r.method = Some("paper".into());
        assert_eq!(config(&r), GenerateConfig::new(50, 3));
    }

    #[test]
    fn a_region_takes_restart_and_refuses_what_has_no_effect_there() {
        let mut r = Request {
            n: Some(10usize.into()),
            s: Some(2usize.into()),
            shape: Some("ball:1".into()),
            restart: Some("off".into()),
            ..Request::default()
        };
        assert_eq!(config(&r).dem.restart, Restart::Off);
        for name in ["polish", "shifts", "q", "log_every", "precision", "p"] {
            let mut bad = r.clone();
            bad.set(name, Arg::Text("1".into())).unwrap();
            let e = bad.resolve().unwrap_err().to_string();
            assert!(e.starts_with(&format!("invalid {name} = ")), "{name}: {e}");
            assert!(e.contains("not in a region"), "{name}: {e}");
        }
        r.energy = Some("e-p-g".into());
        r.p = Some(Arg::Float(4.0));
        assert_eq!(config(&r).energy, EnergyKind::EpG(4.0));
    }

    #[test]
    fn refusals_are_spelled_by_the_caller() {
        let mut r = Request::new(10, 2);
        r.log_every = Some("-3".into());
        let plain = r.resolve().unwrap_err().to_string();
        let flag = r
            .resolve_as(&|n| format!("--{}", n.replace('_', "-")))
            .unwrap_err()
            .to_string();
        assert!(plain.starts_with("invalid log_every = -3"), "{plain}");
        assert!(flag.starts_with("invalid --log-every = -3"), "{flag}");
    }

    /// Every refusal echoes the value of the option it names as the caller typed it
    /// (`none` for an option not given), never a description or a value derived from it.
    #[test]
    fn every_refusal_echoes_the_value_typed() {
        let flag = |n: &str| format!("--{}", n.replace('_', "-"));
        let cases: &[&[(&str, &str)]] = &[
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "lattice"),
                ("goal", "space-filling"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "md"),
                ("method", "paper"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "Blend"),
                ("shape", "ball:1"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "lattice"),
                ("randomize", "cells"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "lattice"),
                ("nested", "2,5"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("target", "cd"),
                ("randomize", "tent"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("goal", "integration"),
                ("method", "paper"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("goal", "space-filling"),
                ("energy", "md"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("randomize", "tent"),
                ("goal", "space-filling"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("randomize", "shift"),
                ("nested", "2,5"),
            ],
            &[("n", "5"), ("s", "2"), ("method", "sobol"), ("steps", "10")],
            &[
                ("n", "5"),
                ("s", "2"),
                ("bounds", "0,1,0,1"),
                ("shape", "ball:1"),
            ],
            &[("n", "5"), ("s", "2"), ("box", "0,1,0,1")],
            &[
                ("n", "5"),
                ("s", "2"),
                ("shape", "ball:1"),
                ("energy", "uqp"),
            ],
            &[("n", "5"), ("s", "2"), ("shape", "ball:1"), ("shifts", "3")],
            &[
                ("n", "5"),
                ("s", "2"),
                ("shape", "ball:1"),
                ("goal", "integration"),
                ("target", "md"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("nested", "2,5"),
                ("method", "paper"),
            ],
            &[("n", "7"), ("s", "2"), ("nested", "2,5")],
            &[
                ("n", "5"),
                ("s", "2"),
                ("mixture", "true"),
                ("shape", "simplex"),
            ],
            &[
                ("n", "5"),
                ("s", "2"),
                ("constraints", "x1 <= 0.5"),
                ("region", "x1"),
            ],
            &[("n", "5"), ("space", "x=uniform(0,1)"), ("shape", "ball:1")],
            &[("n", "5"), ("s", "2"), ("nested", "16,10000000000")],
            &[("s", "2"), ("nested", "16,100000000000")],
            &[("s", "2"), ("nested", "1,2,1000000000000000000000000")],
            &[("n", "10000000000"), ("s", "2")],
            &[("n", "5")],
            &[("s", "2")],
        ];
        for &case in cases {
            let mut r = Request::default();
            for &(name, typed) in case {
                r.set(name, Arg::Text(typed.into())).unwrap();
            }
            let e = r
                .resolve_as(&flag)
                .expect_err(&format!("{case:?}"))
                .to_string();
            let (head, _) = e.split_once(": expected").expect(&e);
            let (named, value) = head
                .strip_prefix("invalid ")
                .and_then(|h| h.split_once(" = "))
                .expect(&e);
            let typed = case
                .iter()
                .find(|(name, _)| flag(name) == named)
                .map_or("none", |(_, typed)| typed);
            assert_eq!(value, typed, "{case:?}: {e}");
        }
    }

    #[test]
    fn grown_sets_keep_their_promises() {
        let old = PointSet::from_rows(&[[0.1, 0.2], [0.6, 0.7]]).unwrap();
        let mut r = Request {
            n: Some(Arg::Int(u64::MAX.into())),
            extend: Some(Arg::Points(old.clone())),
            ..Request::default()
        };
        let e = r.resolve().unwrap_err().to_string();
        assert!(e.starts_with("invalid n = 18446744073709551615"), "{e}");
        r.n = Some(Arg::Int(3));
        r.randomize = Some("cells".into());
        let e = r.resolve().unwrap_err().to_string();
        assert!(e.contains("no randomisation of a grown set"), "{e}");
        r.randomize = None;
        r.s = Some(Arg::Int(3));
        let e = r.resolve().unwrap_err().to_string();
        assert!(e.starts_with("invalid s = 3"), "{e}");
        r.s = None;
        assert_eq!(config(&r).n, 5);
    }

    /// The combinations the pipeline and the goals assume away (they only
    /// `debug_assert!` them) are each refused here, naming the option.
    #[test]
    fn the_combinations_the_pipeline_assumes_away_are_refused() {
        let old = PointSet::from_rows(&[[0.1, 0.2], [0.6, 0.7]]).unwrap();
        let far = PointSet::from_rows(&[[0.1, 0.2], [3.0, 0.7]]).unwrap();
        let ball = || Request {
            n: Some(Arg::Int(5)),
            s: Some(Arg::Int(2)),
            shape: Some("ball:1".into()),
            ..Request::default()
        };
        let refusals: Vec<(&str, Request)> = vec![
            ("randomize", {
                let mut r = ball();
                r.randomize = Some("shift".into());
                r
            }),
            ("extend", {
                let mut r = ball();
                r.goal = Some("integration".into());
                r.extend = Some(Arg::Points(old.clone()));
                r
            }),
            ("extend", {
                let mut r = ball();
                r.extend = Some(Arg::Points(far.clone()));
                r
            }),
            ("extend", {
                let mut r = ball();
                r.extend = Some(Arg::Points(
                    PointSet::from_rows(&[[0.1, 0.2, 0.3]]).unwrap(),
                ));
                r
            }),
            ("extend", {
                let mut r = Request::new(3, 2);
                r.goal = Some("space-filling".into());
                r.extend = Some(Arg::Points(old.clone()));
                r
            }),
            ("extend", {
                let mut r = Request::new(3, 2);
                r.method = Some("paper".into());
                r.extend = Some(Arg::Points(old.clone()));
                r
            }),
            ("nested", {
                let mut r = Request::new(8, 2);
                r.n = None;
                r.nested = Some("4,8".into());
                r.goal = Some("space-filling".into());
                r
            }),
            ("nested", {
                let mut r = ball();
                r.n = None;
                r.nested = Some("4,8".into());
                r
            }),
            ("checkpoint", {
                let mut r = Request::new(8, 2);
                r.goal = Some("integration".into());
                r.checkpoint = Some(Arg::Bool(true));
                r
            }),
        ];
        for (name, r) in refusals {
            let e = r.resolve().unwrap_err().to_string();
            assert!(e.starts_with(&format!("invalid {name} = ")), "{name}: {e}");
        }
        // What the pipeline does accept: old points inside the region, grown there.
        let mut r = ball();
        r.extend = Some(Arg::Points(old));
        assert_eq!(config(&r).n, 7);
    }

    #[test]
    fn an_option_of_the_integration_commands_is_refused_by_generate() {
        let mut r = Request::new(10, 2);
        r.set("abs_tol", Arg::Float(0.5)).unwrap();
        let e = r.resolve().unwrap_err().to_string();
        assert!(
            e.starts_with("invalid abs_tol = 0.5: expected no abs_tol with generate"),
            "{e}"
        );
        let mut m = Request::default();
        m.set("max_n", Arg::Int(64)).unwrap();
        let e = m.resolve_eval().unwrap_err().to_string();
        assert!(
            e.starts_with("invalid max_n = given to measure points"),
            "{e}"
        );
        // The options generate shares with the integration commands are its own.
        let mut r = Request::new(10, 2);
        r.set("seed", Arg::Int(3)).unwrap();
        assert_eq!(r.resolve().unwrap().job.seed(), 3);
    }

    #[test]
    fn nested_sizes_are_read_once_from_text_or_a_list() {
        for arg in [Arg::Text("8, 16,32".into()), Arg::Counts(vec![8, 16, 32])] {
            let r = Request {
                s: Some(Arg::Int(2)),
                nested: Some(arg),
                ..Request::default()
            };
            let cfg = config(&r);
            assert_eq!((cfg.n, cfg.nested), (32, vec![8, 16, 32]));
        }
        for bad in ["16,8", "0,8", "8,x", ""] {
            let r = Request {
                s: Some(Arg::Int(2)),
                nested: Some(bad.into()),
                ..Request::default()
            };
            assert!(r.resolve().is_err(), "{bad}");
        }
    }
}
