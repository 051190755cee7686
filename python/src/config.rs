//! From the arguments of the Python `generate` to a run: the run configuration of the
//! library (the same defaults as `stillpoint generate -n N -s S`), or a baseline.
//!
//! Pure Rust, with no Python type in it, so that the rules are unit-tested by
//! `cargo test` without an interpreter. Every refusal is a message that names the Python
//! argument (`invalid steps = 0: expected ...`), in the form of the library's errors.

use std::path::Path;
use std::sync::Arc;

use serde_json::json;
use stillpoint::domains::region::ImplicitRegion;
use stillpoint::domains::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex};
use stillpoint::energies::discrepancy::DiscrepancyKind;
use stillpoint::energies::{Distance, Precision};
use stillpoint::integrators::{Kappa, Restart};
use stillpoint::pipeline::{
    choose_goal, EnergyKind, GenerateConfig, Goal, GoalName, Init, Randomize, Solver, Space, Target,
};
use stillpoint::sequences::Baseline;
use stillpoint::{Domain, PointSet};

/// A refusal: the message the Python caller sees in its `ValueError`.
pub type Refusal = String;

/// `invalid NAME = VALUE: expected EXPECTED`, the form of the library's errors.
pub fn invalid(name: &str, value: impl std::fmt::Display, expected: &str) -> Refusal {
    format!("invalid {name} = {value}: expected {expected}")
}

/// A keyword option's value as it came from Python, before it is given a meaning.
#[derive(Debug, Clone, PartialEq)]
pub enum OptValue {
    /// `None`.
    None,
    /// `True` or `False`.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string.
    Str(String),
    /// A 2-D float64 array (a point set).
    Points(PointSet),
}

impl std::fmt::Display for OptValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OptValue::None => f.write_str("None"),
            OptValue::Bool(b) => f.write_str(if *b { "True" } else { "False" }),
            OptValue::Int(i) => write!(f, "{i}"),
            OptValue::Float(v) => write!(f, "{v}"),
            OptValue::Str(s) => write!(f, "{s:?}"),
            OptValue::Points(p) => write!(f, "an array of shape ({}, {})", p.n(), p.s()),
        }
    }
}

impl OptValue {
    /// The value as a finite float (an int counts).
    fn number(&self, name: &str, expected: &str) -> Result<f64, Refusal> {
        match self {
            OptValue::Int(i) => Ok(*i as f64),
            OptValue::Float(v) if v.is_finite() => Ok(*v),
            other => Err(invalid(name, other, expected)),
        }
    }

    /// The value as a non-negative integer.
    fn count(&self, name: &str, expected: &str) -> Result<usize, Refusal> {
        match self {
            OptValue::Int(i) if *i >= 0 => Ok(*i as usize),
            other => Err(invalid(name, other, expected)),
        }
    }

    /// The value as text (a number is written out), lower-cased, or `None`.
    fn word(&self) -> Option<String> {
        match self {
            OptValue::Str(s) => Some(s.trim().to_ascii_lowercase()),
            _ => None,
        }
    }
}

/// The keyword options `generate` accepts besides its named arguments, with what each
/// takes. New options of the run configuration get one line here and one arm in
/// [`apply_option`].
pub const OPTIONS: &[(&str, &str)] = &[
    (
        "q",
        "a number > 0, 'inf' (torus distance) or 'E' (Euclidean)",
    ),
    ("p", "a finite number > 0"),
    ("precision", "'fast' or 'full'"),
    ("init", "'halton', 'random' or an (n, d) array of points"),
    ("kappa", "'auto' or a finite number >= 1"),
    ("restart", "'auto', 'off' or a number > 0"),
    ("tolerance", "a number >= 0"),
    ("polish", "None, 'md', 'l2star', 'cd' or 'periodic'"),
    ("shifts", "an integer >= 0"),
    ("log_every", "an integer >= 0"),
    (
        "goal",
        "'integration' (the cube's default) or 'space-filling' (a region's)",
    ),
    (
        "target",
        "'blend' (the default), 'md', 'l2star', 'cd' or 'periodic'",
    ),
    ("randomize", "None, 'cells' or 'shift'"),
    (
        "extend",
        "an (m, d) array of points to keep, first and unchanged",
    ),
    ("nested", "increasing sizes 'N1,N2,...' ending at n"),
];

/// The options that choose what the run is for rather than set the paper's pipeline.
const GOAL_OPTIONS: &[&str] = &["goal", "target", "randomize", "extend", "nested"];

/// What a call of `generate` asks for.
#[derive(Debug, Clone, Default)]
pub struct GenerateArgs {
    /// Number of points.
    pub n: i64,
    /// Dimension (may be `None` when a region gives it).
    pub d: Option<i64>,
    /// Seed.
    pub seed: u64,
    /// `None`/`"dem"` (the energy pipeline) or a baseline's name.
    pub method: Option<String>,
    /// The energy's name.
    pub energy: Option<String>,
    /// `dem` or `lbfgs`.
    pub integrator: Option<String>,
    /// Step budget.
    pub steps: Option<i64>,
    /// A region expression g(x) <= 0.
    pub region: Option<String>,
    /// The bounding box, lo1, hi1, lo2, hi2, ...
    pub bbox: Option<Vec<f64>>,
    /// A built-in shape, as the command line's `--shape` writes it.
    pub shape: Option<String>,
    /// The keyword options, in the order given.
    pub options: Vec<(String, OptValue)>,
}

/// What `generate` runs.
#[derive(Debug, Clone)]
pub enum Plan {
    /// The energy pipeline of the library.
    Run(Box<GenerateConfig>),
    /// A baseline generator.
    Baseline(Baseline, usize, usize, u64),
}

/// The number of points, at least 1.
fn points_count(n: i64) -> Result<usize, Refusal> {
    if n < 1 {
        return Err(invalid("n", n, "at least 1 point"));
    }
    Ok(n as usize)
}

impl GenerateArgs {
    /// The plan of this call, or the refusal of its first bad argument.
    pub fn plan(&self) -> Result<Plan, Refusal> {
        let n = points_count(self.n)?;
        let seed = self.seed;
        let d = match self.d {
            Some(d) if d < 1 => return Err(invalid("d", d, "at least 1 dimension")),
            Some(d) => Some(d as usize),
            None => None,
        };
        let method = self
            .method
            .as_deref()
            .map(|m| m.trim().to_ascii_lowercase());
        match method.as_deref() {
            None | Some("dem" | "paper") => {}
            Some(name) => {
                let baseline = Baseline::parse(name).map_err(|_| {
                    invalid(
                        "method",
                        format!("{name:?}"),
                        "'dem' (the default: the energy pipeline) or a baseline: random, \
                         halton, halton-scrambled, sobol, hua-wang, lattice, lhs, lhs-maximin",
                    )
                })?;
                let others = [
                    ("energy", self.energy.is_some()),
                    ("integrator", self.integrator.is_some()),
                    ("steps", self.steps.is_some()),
                    ("region", self.region.is_some()),
                    ("box", self.bbox.is_some()),
                    ("shape", self.shape.is_some()),
                ];
                if let Some((name, _)) = others.iter().find(|(_, given)| *given) {
                    return Err(format!(
                        "invalid {name} with method = {:?}: a baseline takes only n, d and seed",
                        baseline.name()
                    ));
                }
                if let Some((key, _)) = self.options.first() {
                    return Err(format!(
                        "invalid {key} with method = {:?}: a baseline takes only n, d and seed",
                        baseline.name()
                    ));
                }
                let d = d.ok_or_else(|| invalid("d", "None", "the dimension (at least 1)"))?;
                return Ok(Plan::Baseline(baseline, n, d, seed));
            }
        }
        let solver = match self
            .integrator
            .as_deref()
            .map(|t| t.trim().to_ascii_lowercase())
        {
            None => Solver::Dem,
            Some(t) if t == "dem" => Solver::Dem,
            Some(t) if t == "lbfgs" || t == "l-bfgs" => Solver::Lbfgs,
            Some(t) => return Err(invalid("integrator", format!("{t:?}"), "'dem' or 'lbfgs'")),
        };
        let steps = match self.steps {
            Some(k) if k < 1 => return Err(invalid("steps", k, "an integer >= 1")),
            Some(k) => Some(k as usize),
            None => None,
        };
        let energy = self.energy.as_deref().map(energy_name).transpose()?;
        let mut cfg = if self.region.is_some() || self.shape.is_some() {
            let domain = region_domain(
                self.region.as_deref(),
                self.bbox.as_deref(),
                self.shape.as_deref(),
                d,
            )?;
            let mut cfg = GenerateConfig::in_region(domain.clone(), n);
            cfg.space = Space::Region {
                domain,
                description: json!({
                    "expression": self.region,
                    "box": self.bbox,
                    "shape": self.shape,
                }),
            };
            cfg.energy = match energy {
                None | Some(Energy::EInfG) => EnergyKind::EInfG,
                Some(Energy::EInf) => EnergyKind::EInf,
                Some(Energy::EpG) => EnergyKind::EpG(8.0),
                Some(other) => {
                    return Err(invalid(
                        "energy",
                        format!("{:?} for a region", other.name()),
                        "'e-inf-g' (eq. 56), 'e-inf' or 'e-p-g'",
                    ))
                }
            };
            cfg
        } else {
            if self.bbox.is_some() {
                return Err(
                    "invalid box without region: box is the bounding box of region= \
                     (or of shape='polytope:FILE')"
                        .to_string(),
                );
            }
            let d = d.ok_or_else(|| invalid("d", "None", "the dimension (at least 1)"))?;
            let mut cfg = GenerateConfig::new(n, d);
            cfg.energy = match energy {
                None | Some(Energy::Uqp) => EnergyKind::Uqp,
                Some(Energy::EInf) => EnergyKind::EInf,
                Some(Energy::Discrepancy(kind)) => EnergyKind::Discrepancy(kind),
                Some(other) => {
                    return Err(invalid(
                        "energy",
                        format!("{:?} in the cube", other.name()),
                        "'uqp', 'e-inf', 'l2star', 'md', 'cd' or 'periodic' (e-inf-g and \
                         e-p-g need region= or shape=)",
                    ))
                }
            };
            cfg
        };
        cfg.seed = seed;
        cfg.solver = solver;
        if let Some(k) = steps {
            cfg.steps = k;
        }
        let mut chosen: Vec<(&str, &OptValue)> = Vec::new();
        let mut expert: Vec<&str> = [
            ("energy", self.energy.is_some()),
            ("integrator", self.integrator.is_some()),
            ("steps", self.steps.is_some()),
        ]
        .into_iter()
        .filter_map(|(k, given)| given.then_some(k))
        .collect();
        for (key, value) in &self.options {
            if GOAL_OPTIONS.contains(&key.as_str()) {
                chosen.push((key.as_str(), value));
            } else {
                apply_option(&mut cfg, key, value)?;
                expert.push(key.as_str());
            }
        }
        let paper = method.is_some();
        apply_goal(&mut cfg, &chosen, &expert, paper)?;
        Ok(Plan::Run(Box::new(cfg)))
    }
}

/// What the run is for, as the command line decides it: `goal=` chooses; without it the
/// paper's options (or `method='paper'`) choose the paper's pipeline, a region its own,
/// and otherwise the integration goal. Then `target`, `randomize`, `extend`, `nested`.
fn apply_goal(
    cfg: &mut GenerateConfig,
    chosen: &[(&str, &OptValue)],
    expert: &[&str],
    paper: bool,
) -> Result<(), Refusal> {
    let get = |k: &str| chosen.iter().find(|(key, _)| *key == k).map(|(_, v)| *v);
    let region = cfg.region().is_some();
    let asked = match get("goal").filter(|v| **v != OptValue::None) {
        Some(v) => match v.word().as_deref().map(|w| w.replace('_', "-")).as_deref() {
            Some("integration") => Some(GoalName::Integration),
            Some("space-filling") => Some(GoalName::SpaceFilling),
            _ => return Err(invalid("goal", v, "'integration' or 'space-filling'")),
        },
        None => None,
    };
    let target = match get("target").filter(|v| **v != OptValue::None) {
        Some(v) => Some(match v.word().as_deref() {
            Some("blend") => Target::blend(),
            Some(w) => Target::single(DiscrepancyKind::parse(w).map_err(|_| {
                invalid("target", v, "'blend', 'md', 'l2star', 'cd' or 'periodic'")
            })?),
            None => {
                return Err(invalid(
                    "target",
                    v,
                    "'blend', 'md', 'l2star', 'cd' or 'periodic'",
                ))
            }
        }),
        None => None,
    };
    let goal = choose_goal(asked, paper, expert, region, target, |name| {
        name.to_string()
    })
    .map_err(|e| e.to_string())?;
    cfg.randomize = match get("randomize") {
        None | Some(OptValue::None) => None,
        Some(v) if region => {
            return Err(invalid(
                "randomize",
                v,
                "no randomisation in a region (the cube only)",
            ))
        }
        Some(v) => match v.word().as_deref() {
            Some("cells") => Some(Randomize::Cells),
            Some("shift") => Some(Randomize::Shift),
            _ => return Err(invalid("randomize", v, "None, 'cells' or 'shift'")),
        },
    };
    let integration = matches!(goal, Goal::Integration(_));
    match get("extend") {
        None | Some(OptValue::None) => {}
        Some(OptValue::Points(old)) if integration || region => {
            if old.s() != cfg.s {
                return Err(invalid(
                    "extend",
                    format!("an array of shape ({}, {})", old.n(), old.s()),
                    &format!("points of dimension d = {}", cfg.s),
                ));
            }
            cfg.n += old.n();
            cfg.extend = Some(old.clone());
        }
        Some(v) => {
            return Err(invalid(
                "extend",
                v,
                "an (m, d) array of points, with the integration goal in the cube or in a \
                 region",
            ))
        }
    }
    match get("nested") {
        None | Some(OptValue::None) => {}
        Some(v @ OptValue::Str(text)) if integration && cfg.extend.is_none() => {
            let list: Vec<usize> = text
                .split(',')
                .map(|t| t.trim().parse::<usize>())
                .collect::<Result<_, _>>()
                .map_err(|_| invalid("nested", v, "increasing sizes 'N1,N2,...'"))?;
            if list.is_empty()
                || list[0] == 0
                || list.windows(2).any(|w| w[1] <= w[0])
                || list.last() != Some(&cfg.n)
            {
                return Err(invalid(
                    "nested",
                    v,
                    &format!("increasing sizes N1 < N2 < ... ending at n = {}", cfg.n),
                ));
            }
            cfg.nested = list;
        }
        Some(v) => {
            return Err(invalid(
                "nested",
                v,
                "increasing sizes 'N1,N2,...' with the integration goal (no extend)",
            ))
        }
    }
    cfg.goal = goal;
    Ok(())
}

/// An energy by the command line's name.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Energy {
    Uqp,
    EInf,
    EInfG,
    EpG,
    Discrepancy(DiscrepancyKind),
}

impl Energy {
    fn name(self) -> &'static str {
        match self {
            Energy::Uqp => "uqp",
            Energy::EInf => "e-inf",
            Energy::EInfG => "e-inf-g",
            Energy::EpG => "e-p-g",
            Energy::Discrepancy(k) => k.label(),
        }
    }
}

fn energy_name(text: &str) -> Result<Energy, Refusal> {
    let key = text.trim().to_ascii_lowercase().replace('_', "-");
    Ok(match key.as_str() {
        "uqp" => Energy::Uqp,
        "e-inf" => Energy::EInf,
        "e-inf-g" => Energy::EInfG,
        "e-p-g" => Energy::EpG,
        "l2star" => Energy::Discrepancy(DiscrepancyKind::StarL2),
        "md" => Energy::Discrepancy(DiscrepancyKind::ModifiedL2),
        "cd" => Energy::Discrepancy(DiscrepancyKind::CenteredL2),
        "periodic" | "wd" => Energy::Discrepancy(DiscrepancyKind::WrapAroundL2),
        _ => {
            return Err(invalid(
                "energy",
                format!("{text:?}"),
                "in the cube 'uqp', 'e-inf', 'l2star', 'md', 'cd' or 'periodic'; in a \
                 region 'e-inf-g', 'e-inf' or 'e-p-g'",
            ))
        }
    })
}

/// Sets one keyword option of the run. The options the run configuration gains later
/// (a goal, a target, a randomisation) are one more arm here and one line in [`OPTIONS`].
pub fn apply_option(cfg: &mut GenerateConfig, key: &str, value: &OptValue) -> Result<(), Refusal> {
    let expected = |k: &str| {
        OPTIONS
            .iter()
            .find(|(name, _)| *name == k)
            .map_or("", |(_, e)| e)
    };
    let region = cfg.region().is_some();
    match key {
        "q" => {
            if region {
                return Err(invalid(
                    "q",
                    value,
                    "no q in a region (U_{q,p} is an energy of the cube)",
                ));
            }
            let text = match value {
                OptValue::Str(s) => s.clone(),
                OptValue::Int(_) | OptValue::Float(_) => {
                    value.number("q", expected("q"))?.to_string()
                }
                other => return Err(invalid("q", other, expected("q"))),
            };
            cfg.q = Some(Distance::parse(&text).map_err(|_| invalid("q", value, expected("q")))?);
        }
        "p" => {
            let p = value.number("p", expected("p"))?;
            if p <= 0.0 {
                return Err(invalid("p", value, expected("p")));
            }
            match cfg.energy {
                EnergyKind::EpG(_) => cfg.energy = EnergyKind::EpG(p),
                _ if region => {
                    return Err(invalid(
                        "p",
                        value,
                        "p only with energy='e-p-g' in a region",
                    ))
                }
                _ => cfg.p = Some(p),
            }
        }
        "precision" => {
            if region {
                return Err(invalid(
                    "precision",
                    value,
                    "no precision in a region: it sets U_{q,p}'s distance, which region \
                     energies do not use",
                ));
            }
            cfg.precision = match value.word().as_deref() {
                Some("fast") => Precision::Fast,
                Some("full") => Precision::Full,
                _ => return Err(invalid("precision", value, expected("precision"))),
            }
        }
        "init" => {
            cfg.init = match (value, value.word().as_deref()) {
                (_, Some("halton")) => Init::Halton,
                (_, Some("random")) => Init::Random,
                (OptValue::Points(p), _) => {
                    if !region {
                        p.check_unit_cube().map_err(|e| format!("init: {e}"))?;
                    }
                    Init::Points(p.clone())
                }
                (other, _) => return Err(invalid("init", other, expected("init"))),
            }
        }
        "kappa" => {
            cfg.dem.kappa = match (value, value.word().as_deref()) {
                (_, Some("auto")) => Kappa::default(),
                (OptValue::Int(_) | OptValue::Float(_), _) => {
                    let k = value.number("kappa", expected("kappa"))?;
                    if k < 1.0 {
                        return Err(invalid("kappa", value, expected("kappa")));
                    }
                    Kappa::Fixed(k)
                }
                (other, _) => return Err(invalid("kappa", other, expected("kappa"))),
            }
        }
        "restart" => {
            cfg.dem.restart = match (value, value.word().as_deref()) {
                (_, Some("auto")) => Restart::Auto,
                (_, Some("off" | "none")) | (OptValue::None, _) => Restart::Off,
                (OptValue::Int(_) | OptValue::Float(_), _) => {
                    let e = value.number("restart", expected("restart"))?;
                    if e <= 0.0 {
                        return Err(invalid("restart", value, expected("restart")));
                    }
                    Restart::Threshold(e)
                }
                (other, _) => return Err(invalid("restart", other, expected("restart"))),
            }
        }
        "tolerance" => {
            let t = value.number("tolerance", expected("tolerance"))?;
            if t < 0.0 {
                return Err(invalid("tolerance", value, expected("tolerance")));
            }
            cfg.dem.tolerance = t;
        }
        "polish" => {
            cfg.polish = match (value, value.word().as_deref()) {
                (OptValue::None, _) | (_, Some("none")) => None,
                (_, Some(word)) => Some(
                    DiscrepancyKind::parse(word)
                        .map_err(|_| invalid("polish", value, expected("polish")))?,
                ),
                (other, _) => return Err(invalid("polish", other, expected("polish"))),
            }
        }
        "shifts" => cfg.shifts = value.count("shifts", expected("shifts"))?,
        "log_every" => cfg.log_every = value.count("log_every", expected("log_every"))?,
        other => {
            let names: Vec<&str> = OPTIONS.iter().map(|(name, _)| *name).collect();
            return Err(format!(
                "invalid keyword argument {other} = {value}: generate accepts n, d, seed, \
                 method, energy, integrator, steps, region, box, shape, bounds, progress and \
                 the options {}",
                names.join(", ")
            ));
        }
    }
    Ok(())
}

/// `box` as (lo, hi): two finite numbers per dimension, lo < hi, a usable width (the
/// library's check, as for the command line's `--box`).
pub fn parse_box(v: &[f64]) -> Result<(Vec<f64>, Vec<f64>), Refusal> {
    stillpoint::plan::space::intervals("box", &format!("{v:?}"), v).map_err(|e| e.to_string())
}

/// Comma-separated numbers of a shape's text.
fn number_list(spec: &str, text: &str) -> Result<Vec<f64>, Refusal> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "invalid shape = {spec:?}: {t:?} is not a finite number (expected \
                         comma-separated numbers)"
                    )
                })
        })
        .collect()
}

/// The domain of `region=EXPR, box=...` or `shape=SPEC`, as the command line builds it
/// from `--region`, `--box` and `--shape`.
pub fn region_domain(
    region: Option<&str>,
    bbox: Option<&[f64]>,
    shape: Option<&str>,
    d: Option<usize>,
) -> Result<Arc<dyn Domain>, Refusal> {
    let dim_check = |got: usize| -> Result<(), Refusal> {
        match d {
            Some(d) if d != got => Err(format!("invalid d = {d}: the region has dimension {got}")),
            _ => Ok(()),
        }
    };
    if region.is_some() && shape.is_some() {
        return Err("give either region=EXPR or shape=SHAPE, not both".to_string());
    }
    if let Some(expr) = region {
        let bbox = bbox.ok_or("region= needs box=[lo1, hi1, lo2, hi2, ...]")?;
        let (lo, hi) = parse_box(bbox)?;
        dim_check(lo.len())?;
        let g = stillpoint::expr::RegionExpr::parse(expr, lo.len())
            .map_err(|e| format!("invalid region: {e}"))?;
        let r = ImplicitRegion::new(g.into_fn(), lo, hi).map_err(|e| e.to_string())?;
        r.check(4096, 0).map_err(|e| format!("region: {e}"))?;
        return Ok(Arc::new(r));
    }
    let spec = shape.unwrap_or_default();
    let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let need_d = || d.ok_or_else(|| format!("shape = {spec:?} needs d (the dimension)"));
    let split_at = |text: &str| -> Result<(Vec<f64>, Option<Vec<f64>>), Refusal> {
        match text.split_once('@') {
            Some((a, c)) => Ok((number_list(spec, a)?, Some(number_list(spec, c)?))),
            None => Ok((number_list(spec, text)?, None)),
        }
    };
    let lib = |e: stillpoint::Error| format!("shape = {spec:?}: {e}");
    let domain: Arc<dyn Domain> = match kind.trim() {
        "ball" => {
            let (r, c) = split_at(rest)?;
            if r.len() != 1 {
                return Err(invalid(
                    "shape",
                    format!("{spec:?}"),
                    "'ball:R' or 'ball:R@C1,C2,...'",
                ));
            }
            let c = match c {
                Some(c) => c,
                None => vec![0.0; need_d()?],
            };
            Arc::new(Ball::new(c, r[0]).map_err(lib)?)
        }
        "ellipsoid" => {
            let (a, c) = split_at(rest)?;
            let c = c.unwrap_or_else(|| vec![0.0; a.len()]);
            Arc::new(Ellipsoid::new(c, a).map_err(lib)?)
        }
        "box" => {
            let (lo, hi) = parse_box(&number_list(spec, rest)?)
                .map_err(|e| format!("invalid shape = {spec:?}: {e}"))?;
            Arc::new(BoxRegion::new(lo, hi).map_err(lib)?)
        }
        "simplex" => Arc::new(Simplex::new(need_d()?).map_err(lib)?),
        "polytope" => {
            let rows = stillpoint::io::read_points(Path::new(rest))
                .map_err(|e| format!("shape polytope:FILE: {e}"))?;
            if rows.s() < 2 {
                return Err(invalid(
                    "shape",
                    format!("{spec:?}"),
                    "a file whose rows are a1 .. as b (at least 2 numbers)",
                ));
            }
            let a: Vec<Vec<f64>> = rows.rows().map(|r| r[..r.len() - 1].to_vec()).collect();
            let b: Vec<f64> = rows.rows().map(|r| r[r.len() - 1]).collect();
            let bbox = bbox.ok_or("shape='polytope:FILE' needs box=[lo1, hi1, ...]")?;
            let (lo, hi) = parse_box(bbox)?;
            Arc::new(Polytope::new(a, b, lo, hi).map_err(lib)?)
        }
        _ => {
            return Err(invalid(
                "shape",
                format!("{spec:?}"),
                "'ball:R[@C..]', 'ellipsoid:A1,..[@C..]', 'box:LO1,HI1,..', 'simplex' or \
                 'polytope:FILE'",
            ))
        }
    };
    dim_check(domain.dim())?;
    Ok(domain)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(n: i64, d: i64) -> GenerateArgs {
        GenerateArgs {
            n,
            d: Some(d),
            ..Default::default()
        }
    }

    #[test]
    fn defaults_are_the_command_lines() {
        match args(50, 3).plan().unwrap() {
            Plan::Run(cfg) => assert_eq!(
                *cfg,
                GenerateConfig::for_goal(50, 3, Goal::Integration(Target::blend()))
            ),
            other => panic!("expected a run, got {other:?}"),
        }
        // The paper's options select the paper's pipeline, as on the command line.
        let paper = GenerateArgs {
            method: Some("paper".into()),
            ..args(50, 3)
        };
        match paper.plan().unwrap() {
            Plan::Run(cfg) => assert_eq!(*cfg, GenerateConfig::new(50, 3)),
            other => panic!("expected a run, got {other:?}"),
        }
    }

    #[test]
    fn refusals_name_the_argument() {
        let cases: Vec<(GenerateArgs, &str)> = vec![
            (args(0, 2), "invalid n = 0"),
            (args(5, 0), "invalid d = 0"),
            (
                GenerateArgs {
                    steps: Some(0),
                    ..args(5, 2)
                },
                "invalid steps = 0",
            ),
            (
                GenerateArgs {
                    energy: Some("e-inf-g".into()),
                    ..args(5, 2)
                },
                "invalid energy",
            ),
            (
                GenerateArgs {
                    options: vec![("goal".into(), OptValue::Int(1))],
                    ..args(5, 2)
                },
                "invalid goal",
            ),
            (
                GenerateArgs {
                    options: vec![("colour".into(), OptValue::Int(1))],
                    ..args(5, 2)
                },
                "invalid keyword argument colour",
            ),
            (
                GenerateArgs {
                    region: Some("x^2 + y^2 - 1".into()),
                    ..args(5, 2)
                },
                "needs box",
            ),
            (
                GenerateArgs {
                    region: Some("x^2 + y^2 - 1".into()),
                    bbox: Some(vec![-1.0, 1.0, 1.0, -1.0]),
                    ..args(5, 2)
                },
                "invalid box",
            ),
        ];
        for (a, want) in cases {
            let got = a.plan().unwrap_err();
            assert!(got.contains(want), "{got:?} should contain {want:?}");
        }
    }

    #[test]
    fn regions_and_baselines() {
        let a = GenerateArgs {
            d: None,
            shape: Some("ball:1@0,0".into()),
            ..args(5, 2)
        };
        match a.plan().unwrap() {
            Plan::Run(cfg) => assert_eq!((cfg.s, cfg.steps), (2, 10_000)),
            other => panic!("expected a run, got {other:?}"),
        }
        let b = GenerateArgs {
            method: Some("Sobol".into()),
            seed: 3,
            ..args(8, 2)
        };
        assert!(matches!(
            b.plan().unwrap(),
            Plan::Baseline(Baseline::Sobol, 8, 2, 3)
        ));
    }

    #[test]
    fn options_set_the_configuration() {
        let mut cfg = GenerateConfig::new(10, 2);
        apply_option(&mut cfg, "q", &OptValue::Str("inf".into())).unwrap();
        apply_option(&mut cfg, "polish", &OptValue::Str("md".into())).unwrap();
        apply_option(&mut cfg, "shifts", &OptValue::Int(0)).unwrap();
        assert_eq!(cfg.q, Some(Distance::Torus));
        assert_eq!(cfg.polish, Some(DiscrepancyKind::ModifiedL2));
        assert_eq!(cfg.shifts, 0);
        assert!(apply_option(&mut cfg, "shifts", &OptValue::Int(-1))
            .unwrap_err()
            .starts_with("invalid shifts = -1"));
    }
}
