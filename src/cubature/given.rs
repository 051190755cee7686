//! The settings of an integration ([`Cubature`]) or a sensitivity analysis
//! ([`Sensitivity`]) from the options a front end received ([`Given`]): every default,
//! every check and every refused combination is written here once, and each refusal
//! names the option as the front end spells it and echoes the value as the user typed
//! it ([`Spelling`]). The command line and Python only collect what was given; Python's
//! continuation (`start=`) is resolved here too ([`Cubature::continued`],
//! [`Sensitivity::continued`]).

use super::{Cubature, QuadOptions, Rule};
use crate::design::DesignSpace;
use crate::pipeline::request::Arg;
use crate::sensitivity::{FirstOrder, Sensitivity, SensitivityOptions};
use crate::Error;

/// The options of an integration or a sensitivity analysis as a front end received
/// them, by the library's names; `None`: not given (the default applies).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Given {
    /// The dimension, the number of inputs.
    pub d: Option<Arg>,
    /// The box's lower corner: d numbers, or one for every dimension.
    pub a: Option<Arg>,
    /// The box's upper corner.
    pub b: Option<Arg>,
    /// The box as one list LO1,HI1,LO2,HI2,... (the command line's form).
    pub bounds: Option<Arg>,
    /// Absolute tolerance on the half-width.
    pub abs_tol: Option<Arg>,
    /// Relative tolerance on the half-width (integration only).
    pub rel_tol: Option<Arg>,
    /// Confidence level of the interval.
    pub level: Option<Arg>,
    /// Independent randomisations R.
    pub replicates: Option<Arg>,
    /// The most evaluations of f.
    pub max_n: Option<Arg>,
    /// Seed of the randomisations.
    pub seed: Option<Arg>,
    /// The rule, `lattice` or `sobol` (integration only; chosen from the laws without).
    pub rule: Option<Arg>,
    /// A design space's variables as `NAME=TYPE` texts.
    pub space: Option<Arg>,
    /// The space's correlation: rows as text, or a k × k matrix.
    pub correlation: Option<Arg>,
    /// Intervals that hold all together (sensitivity only).
    pub simultaneous: Option<Arg>,
    /// The first-order estimator (sensitivity only).
    pub first_estimator: Option<Arg>,
}

/// Declares [`Given::get`], [`Given::set`] and [`Given::names`] over the fields, in one
/// list.
macro_rules! fields {
    ($($field:ident),*) => {
        impl Given {
            /// The value given for the option the library calls `name`.
            pub fn get(&self, name: &str) -> Option<&Arg> {
                match name {
                    $(stringify!($field) => self.$field.as_ref(),)*
                    _ => None,
                }
            }

            /// Sets the option the library calls `name`; false for a name that is not one
            /// of these options.
            pub fn set(&mut self, name: &str, value: Arg) -> bool {
                match name {
                    $(stringify!($field) => self.$field = Some(value),)*
                    _ => return false,
                }
                true
            }

            /// The library's names of the options given, in the order of the fields.
            pub fn names(&self) -> Vec<&'static str> {
                let mut out = Vec::new();
                $(if self.$field.is_some() { out.push(stringify!($field)); })*
                out
            }
        }
    };
}

fields!(
    d,
    a,
    b,
    bounds,
    abs_tol,
    rel_tol,
    level,
    replicates,
    max_n,
    seed,
    rule,
    space,
    correlation,
    simultaneous,
    first_estimator
);

/// How a front end writes refusals: the option the library calls `name` as its users
/// spell it (`--max-n`, `max_n`), and a value as they typed it (`1e-3` on the command
/// line, `'x'` in Python).
#[derive(Clone, Copy)]
pub struct Spelling<'a> {
    /// The option's name as the front end spells it.
    pub name: &'a dyn Fn(&str) -> String,
    /// The value given for the option `name`, as typed.
    pub shown: &'a dyn Fn(&str, &Arg) -> String,
}

fn plain_name(name: &str) -> String {
    name.to_string()
}

fn plain_value(_: &str, value: &Arg) -> String {
    value.to_string()
}

impl Spelling<'static> {
    /// The library's own: names as they are, values as [`Arg`] writes them.
    pub const PLAIN: Spelling<'static> = Spelling {
        name: &plain_name,
        shown: &plain_value,
    };
}

impl Spelling<'_> {
    /// A library refusal as the front end shows it: the option spelled its way, and the
    /// value as typed when that option was given (the library writes the number it got:
    /// `-0.001` for `-1e-3`).
    pub fn error(&self, e: Error, given: &Given) -> Error {
        match e {
            Error::InvalidArgument {
                name,
                value,
                expected,
            } => {
                // A space's refusals name one of its variables, not the whole list.
                let typed = given.get(&name).filter(|_| name != "space");
                let value = typed.map_or(value, |v| (self.shown)(&name, v));
                Error::invalid((self.name)(&name), value, expected)
            }
            other => other,
        }
    }

    /// A refusal of two options together (`invalid a with start: ...`), in the front
    /// end's names. The library's error type has no other form for a sentence that
    /// is not `name = value: expected ...`.
    fn together(&self, head: &str, why: &str) -> Error {
        Error::Numerical(format!("invalid {head}: {why}"))
    }

    fn spell(&self, name: &str) -> String {
        (self.name)(name)
    }
}

impl Given {
    /// A real number (finiteness and range are the settings' own checks).
    fn real(&self, name: &str) -> Result<Option<f64>, Error> {
        self.get(name)
            .map(|v| match v {
                Arg::Float(x) => Ok(*x),
                Arg::Int(i) => Ok(*i as f64),
                Arg::Text(t) => t.trim().parse::<f64>().map_err(|_| not_a(name, v)),
                _ => Err(not_a(name, v)),
            })
            .transpose()
    }

    /// A whole number ≥ 0; below 0 it is taken as 0, which the range of every count
    /// refuses with the value typed echoed.
    fn count(&self, name: &str) -> Result<Option<u64>, Error> {
        self.get(name)
            .map(|v| {
                let whole = match v {
                    Arg::Int(i) => Some(*i),
                    Arg::Text(t) => t.trim().parse::<i128>().ok(),
                    _ => None,
                };
                whole
                    .map(|i| u64::try_from(i.max(0)).unwrap_or(u64::MAX))
                    .ok_or_else(|| Error::invalid(name, v, "a whole number"))
            })
            .transpose()
    }

    /// The seed: a whole number in [0, 2^64).
    fn seed(&self) -> Result<Option<u64>, Error> {
        self.get("seed")
            .map(|v| {
                let whole = match v {
                    Arg::Int(i) => u64::try_from(*i).ok(),
                    Arg::Text(t) => t.trim().parse::<u64>().ok(),
                    _ => None,
                };
                whole.ok_or_else(|| Error::invalid("seed", v, "a whole number in [0, 2^64)"))
            })
            .transpose()
    }

    /// A word (a rule's or an estimator's name).
    fn word(&self, name: &str) -> Result<Option<&str>, Error> {
        self.get(name)
            .map(|v| match v {
                Arg::Text(t) => Ok(t.as_str()),
                _ => Err(not_a(name, v)),
            })
            .transpose()
    }

    /// A truth value.
    fn truth(&self, name: &str) -> Result<Option<bool>, Error> {
        self.get(name)
            .map(|v| match v {
                Arg::Bool(b) => Ok(*b),
                _ => Err(Error::invalid(name, v, "True or False")),
            })
            .transpose()
    }

    /// The design space given, parsed and checked as an integration takes it (its
    /// continuous variables can hold [`super::SPACE_RESOLUTION`] distinct values), with
    /// its correlation; a correlation without a space is refused.
    fn design_space(&self, sp: &Spelling) -> Result<Option<DesignSpace>, Error> {
        let Some(items) = self.get("space") else {
            if self.correlation.is_some() {
                return Err(sp.together(
                    &format!("{} without {}", sp.spell("correlation"), sp.spell("space")),
                    "it correlates a space's variables",
                ));
            }
            return Ok(None);
        };
        let texts = match items {
            Arg::Texts(t) => t.clone(),
            Arg::Text(t) => vec![t.clone()],
            other => return Err(Error::invalid("space", other, "NAME=TYPE texts")),
        };
        let mut space = DesignSpace::parse("space", &texts)?;
        super::check_space(&space, "space")?;
        match &self.correlation {
            None => {}
            Some(Arg::Text(rows)) => space.correlate_rows("correlation", rows)?,
            Some(Arg::Points(m)) => space.correlate("correlation", "", m.as_slice().to_vec())?,
            Some(Arg::Numbers(m)) => space.correlate("correlation", "", m.clone())?,
            Some(other) => {
                return Err(not_a("correlation", other));
            }
        }
        Ok(Some(space))
    }

    /// The dimension: `d` as given (checked against a space's columns), else the
    /// space's, else the length of a corner given as a list (`infer`); `most` is the
    /// largest accepted, `what` the noun of the refusal.
    fn dimension(
        &self,
        space: Option<&DesignSpace>,
        infer: bool,
        sp: &Spelling,
    ) -> Result<usize, Error> {
        let given = self.count("d")?.map(|d| d as usize);
        match (given, space) {
            (Some(d), Some(space)) if d != space.dim() => {
                let typed = self
                    .d
                    .as_ref()
                    .map_or(d.to_string(), |v| (sp.shown)("d", v));
                Err(sp.together(
                    &format!("{} = {typed}", sp.spell("d")),
                    &format!(
                        "{} has {} coordinates; expected {} equal to it",
                        sp.spell("space"),
                        space.dim(),
                        sp.spell("d")
                    ),
                ))
            }
            (Some(d), _) => Ok(d),
            (None, Some(space)) => Ok(space.dim()),
            (None, None) => {
                let from_corner = [&self.a, &self.b].into_iter().find_map(|c| match c {
                    Some(Arg::Numbers(v)) if infer => Some(v.len()),
                    Some(Arg::Counts(v)) if infer => Some(v.len()),
                    _ => None,
                });
                from_corner.ok_or_else(|| {
                    Error::invalid(
                        "d",
                        "None",
                        "the number of inputs (or a space, or corners a, b of d numbers)",
                    )
                })
            }
        }
    }

    /// The box's corners (`None`: the unit cube's), checked as every box of the package
    /// is ([`crate::plan::space::intervals`]); refused with a space, whose laws give the
    /// range.
    #[allow(clippy::type_complexity)]
    fn corners(
        &self,
        d: usize,
        space: bool,
        sp: &Spelling,
    ) -> Result<(Option<Vec<f64>>, Option<Vec<f64>>), Error> {
        let by_bounds = self.bounds.is_some();
        if !by_bounds && self.a.is_none() && self.b.is_none() {
            return Ok((None, None));
        }
        let (name, shown, values) = if let Some(bounds) = &self.bounds {
            let shown = (sp.shown)("bounds", bounds);
            let values = match bounds {
                Arg::Text(t) => crate::plan::space::number_list("bounds", &shown, t)?,
                Arg::Numbers(v) => v.clone(),
                other => return Err(not_a("bounds", other)),
            };
            ("bounds".to_string(), shown, values)
        } else {
            let lo = corner(&self.a, "a", d, 0.0)?;
            let hi = corner(&self.b, "b", d, 1.0)?;
            let show =
                |n: &str, v: &Option<Arg>| v.as_ref().map_or("None".into(), |v| (sp.shown)(n, v));
            let shown = format!("({}, {})", show("a", &self.a), show("b", &self.b));
            let values = lo.iter().zip(&hi).flat_map(|(a, b)| [*a, *b]).collect();
            ("a, b".to_string(), shown, values)
        };
        if space {
            let spelled = if by_bounds {
                sp.spell("bounds")
            } else {
                format!("{}, {}", sp.spell("a"), sp.spell("b"))
            };
            return Err(sp.together(
                &format!("{spelled} with {}", sp.spell("space")),
                "the space's distributions give the range",
            ));
        }
        let bounds = crate::plan::space::Bounds::new(&name, &shown, &values, d)?;
        Ok((Some(bounds.lo), Some(bounds.hi)))
    }
}

/// A corner given as one number (every dimension) or d numbers.
fn corner(v: &Option<Arg>, name: &str, d: usize, fill: f64) -> Result<Vec<f64>, Error> {
    let expected = || format!("{d} finite numbers (one per dimension)");
    let values = match v {
        None => vec![fill; d],
        Some(Arg::Float(x)) => vec![*x; d],
        Some(Arg::Int(i)) => vec![*i as f64; d],
        Some(Arg::Numbers(v)) => v.clone(),
        Some(Arg::Counts(v)) => v.iter().map(|i| *i as f64).collect(),
        Some(other) => return Err(Error::invalid(name, other, expected())),
    };
    if values.len() != d || values.iter().any(|x| !x.is_finite()) {
        let shown = v.as_ref().map_or(String::new(), |v| v.to_string());
        return Err(Error::invalid(name, shown, expected()));
    }
    Ok(values)
}

/// A value of the wrong kind for `name`.
fn not_a(name: &str, v: &Arg) -> Error {
    let expected = match name {
        "space" => "NAME=TYPE texts",
        "correlation" => "a k × k matrix of numbers or its rows as text, 1,0.5;0.5,1",
        "rule" | "first_estimator" => "a name",
        _ => "a finite number",
    };
    Error::invalid(name, v, expected)
}

/// The options only one of the two computations takes: given to the other, refused.
const QUAD_ONLY: [&str; 3] = ["rel_tol", "rule", "correlation"];
const SENSITIVITY_ONLY: [&str; 2] = ["simultaneous", "first_estimator"];

/// Refuses an option the computation does not take (`what`), naming it.
fn refuse_foreign(g: &Given, foreign: &[&str], what: &str, sp: &Spelling) -> Result<(), Error> {
    match g.names().into_iter().find(|n| foreign.contains(n)) {
        Some(name) => Err(Error::invalid(
            name,
            g.get(name).map_or(String::new(), |v| (sp.shown)(name, v)),
            format!("no {} ({what} does not take it)", sp.spell(name)),
        )),
        None => Ok(()),
    }
}

impl Cubature {
    /// A new integration from the options a front end received: `d` (checked against a
    /// space's coordinates), the box (`a`/`b` or `bounds`, not with a space), the space
    /// and its correlation (not without a space), the tolerances, level, replicates,
    /// budget and seed (their defaults those of [`QuadOptions::default`]) and the rule
    /// (asked for, or [`Rule::for_space`]). Returns the state and the space, whose map
    /// the caller applies to the points ([`super::space_values`]).
    pub fn from_given(g: &Given, sp: &Spelling) -> Result<(Cubature, Option<DesignSpace>), Error> {
        Self::resolved(g, sp).map_err(|e| sp.error(e, g))
    }

    fn resolved(g: &Given, sp: &Spelling) -> Result<(Cubature, Option<DesignSpace>), Error> {
        refuse_foreign(g, &SENSITIVITY_ONLY, "an integration", sp)?;
        let space = g.design_space(sp)?;
        let d = g.dimension(space.as_ref(), false, sp)?;
        // The dimension first, so that d = 0 is refused as d rather than by what needs it.
        crate::sequences::ExtensibleLattice::new(d, 0, 0)?;
        let (a, b) = g.corners(d, space.is_some(), sp)?;
        let (rule, rule_reason) = match (g.word("rule")?, &g.rule) {
            (Some(word), Some(typed)) => (
                Rule::parse("rule", word)?,
                format!(
                    "as asked ({}={})",
                    sp.spell("rule"),
                    (sp.shown)("rule", typed)
                ),
            ),
            _ => Rule::for_space(space.as_ref()),
        };
        let o = QuadOptions::default();
        let options = QuadOptions {
            a,
            b,
            abs_tol: g.real("abs_tol")?.unwrap_or(o.abs_tol),
            rel_tol: g.real("rel_tol")?.unwrap_or(o.rel_tol),
            level: g.real("level")?.unwrap_or(o.level),
            replicates: g.count("replicates")?.map_or(o.replicates, |r| r as usize),
            max_n: g.count("max_n")?.unwrap_or(o.max_n),
            seed: g.seed()?.unwrap_or(o.seed),
            rule,
            rule_reason,
            ..o
        };
        Ok((Cubature::new(d, options)?, space))
    }

    /// This integration continued with the options given (the state itself is not
    /// changed): `abs_tol`, `rel_tol` (either given sets both, the other at its default),
    /// `level` and `max_n` are honoured; `d` must match; the box, space and correlation
    /// are refused, and the replicates, seed and rule unless equal to this one's.
    pub fn continued(&self, g: &Given, sp: &Spelling) -> Result<Cubature, Error> {
        let mut state = self.clone();
        let o = &self.options;
        let kept = Kept {
            what: "integration",
            sp,
            g,
        };
        (|| {
            refuse_foreign(g, &SENSITIVITY_ONLY, "an integration", sp)?;
            kept.dimension(self.d, "was computed in", "dimensions")?;
            kept.fixed(&["a", "b", "bounds", "space", "correlation"])?;
            kept.seed(o.seed)?;
            if let Some(r) = g.count("replicates")? {
                kept.equal(
                    "replicates",
                    r == o.replicates as u64,
                    &format!("{} replicates (their shifts and sums)", o.replicates),
                )?;
            }
            if let Some(rule) = g.word("rule")? {
                kept.equal(
                    "rule",
                    rule == o.rule.as_str(),
                    &format!("rule ({})", o.rule.as_str()),
                )?;
            }
            if g.abs_tol.is_some() || g.rel_tol.is_some() {
                let d = QuadOptions::default();
                let abs = g.real("abs_tol")?.unwrap_or(d.abs_tol);
                state.set_tolerance(abs, g.real("rel_tol")?.unwrap_or(d.rel_tol))?;
            }
            if let Some(level) = g.real("level")? {
                state.set_level(level)?;
            }
            if let Some(max_n) = g.count("max_n")? {
                state.set_max_n(max_n)?;
            }
            Ok(())
        })()
        .map_err(|e| sp.error(e, g))?;
        Ok(state)
    }
}

impl Sensitivity {
    /// A new sensitivity analysis from the options a front end received: `d` (or the
    /// space's inputs, or the length of a corner), the box (not with a space), a space of
    /// independent inputs (a correlation or a Brownian path refused), the tolerance,
    /// level, intervals, estimator, replicates, budget and seed (their defaults those of
    /// [`SensitivityOptions::default`]). Returns the state and the space.
    pub fn from_given(
        g: &Given,
        sp: &Spelling,
    ) -> Result<(Sensitivity, Option<DesignSpace>), Error> {
        Self::resolved(g, sp).map_err(|e| sp.error(e, g))
    }

    fn resolved(g: &Given, sp: &Spelling) -> Result<(Sensitivity, Option<DesignSpace>), Error> {
        refuse_foreign(g, &["rel_tol", "rule"], "a sensitivity analysis", sp)?;
        if let Some(c) = &g.correlation {
            return Err(Error::invalid(
                "correlation",
                (sp.shown)("correlation", c),
                "no correlation: Sobol' indices are computed for independent inputs",
            ));
        }
        let space = g.design_space(sp)?;
        if let Some(space) = &space {
            crate::sensitivity::check_independent("space", space)?;
        }
        let d = g.dimension(space.as_ref(), true, sp)?;
        Sensitivity::new(d, SensitivityOptions::default())?;
        let (a, b) = g.corners(d, space.is_some(), sp)?;
        let o = SensitivityOptions::default();
        let first_order = match g.word("first_estimator")? {
            Some(w) => FirstOrder::parse("first_estimator", w)?,
            None => o.first_order,
        };
        let options = SensitivityOptions {
            a,
            b,
            names: space
                .as_ref()
                .map(|s| s.vars.iter().map(|v| v.name.clone()).collect()),
            abs_tol: g.real("abs_tol")?.unwrap_or(o.abs_tol),
            level: g.real("level")?.unwrap_or(o.level),
            simultaneous: g.truth("simultaneous")?.unwrap_or(o.simultaneous),
            first_order,
            replicates: g.count("replicates")?.map_or(o.replicates, |r| r as usize),
            max_n: g.count("max_n")?.unwrap_or(o.max_n),
            seed: g.seed()?.unwrap_or(o.seed),
            ..o
        };
        Ok((Sensitivity::new(d, options)?, space))
    }

    /// This analysis continued with the options given (the state itself is not
    /// changed): `abs_tol`, `level`, `simultaneous` and `max_n` are honoured; `d` must
    /// match; the box and space are refused, and the replicates, estimator and seed
    /// unless equal to this one's.
    pub fn continued(&self, g: &Given, sp: &Spelling) -> Result<Sensitivity, Error> {
        let mut state = self.clone();
        let o = self.options();
        let kept = Kept {
            what: "analysis",
            sp,
            g,
        };
        (|| {
            refuse_foreign(g, &QUAD_ONLY, "a sensitivity analysis", sp)?;
            kept.dimension(self.d(), "has", "inputs")?;
            kept.fixed(&["a", "b", "bounds", "space"])?;
            kept.seed(o.seed)?;
            if let Some(r) = g.count("replicates")? {
                kept.equal(
                    "replicates",
                    r == o.replicates as u64,
                    &format!("({})", o.replicates),
                )?;
            }
            if let Some(w) = g.word("first_estimator")? {
                let earlier = format!("({})", o.first_order.as_str());
                kept.equal("first_estimator", w == o.first_order.as_str(), &earlier)?;
            }
            if let Some(t) = g.real("abs_tol")? {
                state.set_tolerance(t)?;
            }
            if let Some(level) = g.real("level")? {
                state.set_level(level)?;
            }
            if let Some(max_n) = g.count("max_n")? {
                state.set_max_n(max_n)?;
            }
            if let Some(s) = g.truth("simultaneous")? {
                state.set_simultaneous(s);
            }
            Ok(())
        })()
        .map_err(|e| sp.error(e, g))?;
        Ok(state)
    }
}

/// The refusals of a continuation: what it keeps of the earlier run (`what`: the
/// computation's noun).
struct Kept<'a> {
    what: &'static str,
    sp: &'a Spelling<'a>,
    g: &'a Given,
}

impl Kept<'_> {
    fn start(&self) -> String {
        self.sp.spell("start")
    }

    /// `d`, if given, equal to the earlier run's.
    fn dimension(&self, d: usize, verb: &str, noun: &str) -> Result<(), Error> {
        match (self.g.count("d")?, &self.g.d) {
            (Some(given), Some(typed)) if given != d as u64 => Err(self.sp.together(
                &format!("{} = {}", self.sp.spell("d"), (self.sp.shown)("d", typed)),
                &format!("{} {verb} {d} {noun}", self.start()),
            )),
            _ => Ok(()),
        }
    }

    /// Options a continuation takes from the earlier run and cannot be given.
    fn fixed(&self, names: &[&str]) -> Result<(), Error> {
        match names.iter().find(|n| self.g.get(n).is_some()) {
            Some(name) => {
                let spelled = self.sp.spell(name);
                Err(self.sp.together(
                    &format!("{spelled} with {}", self.start()),
                    &format!(
                        "a continued {} keeps the earlier one's {spelled}",
                        self.what
                    ),
                ))
            }
            None => Ok(()),
        }
    }

    /// The seed, if given, equal to the earlier run's.
    fn seed(&self, earlier: u64) -> Result<(), Error> {
        let Some(typed) = &self.g.seed else {
            return Ok(());
        };
        if self.g.seed().ok().flatten() == Some(earlier) {
            return Ok(());
        }
        Err(self.sp.together(
            &format!(
                "{} with {} = {}",
                self.sp.spell("seed"),
                self.start(),
                (self.sp.shown)("seed", typed)
            ),
            &format!(
                "a continued {} keeps the earlier one's shifts (seed {earlier})",
                self.what
            ),
        ))
    }

    /// `name`, given, refused unless `equal` to the earlier run's (`earlier`).
    fn equal(&self, name: &str, equal: bool, earlier: &str) -> Result<(), Error> {
        if equal {
            return Ok(());
        }
        let typed = self
            .g
            .get(name)
            .map_or(String::new(), |v| (self.sp.shown)(name, v));
        Err(self.sp.together(
            &format!("{} = {typed} with {}", self.sp.spell(name), self.start()),
            &format!(
                "a continued {} keeps the earlier one's {earlier}",
                self.what
            ),
        ))
    }
}
