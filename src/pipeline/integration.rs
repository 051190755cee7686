//! The settings of an integration ([`Cubature`]) or a sensitivity analysis
//! ([`Sensitivity`]) from the options a front end received (a [`Request`] holding the
//! integration options of [`crate::pipeline::options`]): each value read by its
//! declaration's kind, the defaults of [`QuadOptions`] and [`SensitivityOptions`], every
//! check and every refused combination written here once. Each refusal names the option
//! as the front end spells it and echoes the value as the user typed it ([`Spelling`]).
//! The command line and Python only collect what was given; Python's continuation
//! (`start=`) is resolved here too ([`Cubature::continued`], [`Sensitivity::continued`]).
//! Both commands are resolved by one shape, written once over what differs between
//! them (the private trait `Integration`): a new request and a continuation.

use super::options::{Command, Opt, Value, ALL};
use super::request::{Arg, Request};
use crate::cubature::{Cubature, QuadOptions, Rule};
use crate::design::DesignSpace;
use crate::sensitivity::{FirstOrder, Interval, Sensitivity, SensitivityOptions};
use crate::Error;

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

/// The option a library refusal's name belongs to: the state machines name the
/// dimension `d` and the box's corners `a`, `b`.
fn option_of(name: &str) -> &str {
    match name {
        "d" => Opt::s.name(),
        "a" | "b" | "a, b" => Opt::bounds.name(),
        other => other,
    }
}

impl Spelling<'_> {
    /// A library refusal as the front end shows it: the option spelled its way, and the
    /// value as typed when that option was given (the library writes the number it got:
    /// `-0.001` for `-1e-3`). A space's refusals name one of its variables: their value
    /// is kept.
    pub fn error(&self, e: Error, given: &Request) -> Error {
        match e {
            Error::InvalidArgument {
                name,
                value,
                expected,
            } => {
                let option = option_of(&name);
                let typed = by_name(given, option).filter(|_| option != Opt::space.name());
                let value = typed.map_or(value, |v| (self.shown)(option, v));
                Error::invalid(self.spell(option), value, expected)
            }
            other => other,
        }
    }

    /// A refusal that is not `name = value: expected ...` (`invalid a with start: ...`),
    /// in the front end's names. The library's error type carries such a sentence as
    /// its free-text variant.
    fn together(&self, head: &str, why: &str) -> Error {
        Error::Numerical(format!("invalid {head}: {why}"))
    }

    fn spell(&self, name: &str) -> String {
        (self.name)(name)
    }

    /// The option `opt` and its value as typed: `name = value`.
    fn typed(&self, opt: Opt, value: &Arg) -> String {
        format!(
            "{} = {}",
            self.spell(opt.name()),
            (self.shown)(opt.name(), value)
        )
    }
}

/// An option's value read by its declaration's kind (`None`: not given); the refusal
/// names it as the library does, which [`Spelling::error`] then spells.
fn read<T>(r: &Request, opt: Opt, typed: fn(Value) -> Option<T>) -> Result<Option<T>, Error> {
    let Some(arg) = r.arg(opt) else {
        return Ok(None);
    };
    Ok(opt.declared().parse(arg, &plain_name)?.and_then(typed))
}

fn real(r: &Request, opt: Opt) -> Result<Option<f64>, Error> {
    read(r, opt, |v| match v {
        Value::Real(x) => Some(x),
        _ => None,
    })
}

fn count(r: &Request, opt: Opt) -> Result<Option<u64>, Error> {
    read(r, opt, |v| match v {
        Value::Count(c) | Value::Seed(c) => Some(c),
        _ => None,
    })
}

fn word(r: &Request, opt: Opt) -> Result<Option<String>, Error> {
    read(r, opt, |v| match v {
        Value::Word(w) => Some(w),
        _ => None,
    })
}

fn flag(r: &Request, opt: Opt) -> Result<Option<bool>, Error> {
    read(r, opt, |v| match v {
        Value::Flag(b) => Some(b),
        _ => None,
    })
}

/// The value given for the option a refusal or a declaration names, if any.
fn by_name<'a>(r: &'a Request, name: &str) -> Option<&'a Arg> {
    Opt::named(name).and_then(|o| r.arg(o))
}

/// Refuses the first option given that `command` does not take, naming it.
fn refuse_others(r: &Request, command: Command, sp: &Spelling) -> Result<(), Error> {
    let Some(d) = ALL
        .iter()
        .find(|d| !d.takes(command) && by_name(r, d.name).is_some())
    else {
        return Ok(());
    };
    let takes: Vec<&str> = d.commands.iter().map(|c| c.name()).collect();
    Err(Error::invalid(
        d.name,
        by_name(r, d.name).map_or(String::new(), |v| v.to_string()),
        format!(
            "no {} with {}: it is an option of {}",
            sp.spell(d.name),
            command.name(),
            takes.join(" and ")
        ),
    ))
}

/// The design space given, parsed and checked as an integration takes it (its
/// continuous variables can hold [`super::SPACE_RESOLUTION`] distinct values), with its
/// correlation; a correlation without a space is refused.
fn design_space(r: &Request, sp: &Spelling) -> Result<Option<DesignSpace>, Error> {
    let texts = read(r, Opt::space, |v| match v {
        Value::Texts(t) => Some(t),
        _ => None,
    })?;
    let Some(texts) = texts.filter(|t| !t.is_empty()) else {
        if r.correlation.is_some() {
            return Err(sp.together(
                &format!(
                    "{} without {}",
                    sp.spell(Opt::correlation.name()),
                    sp.spell(Opt::space.name())
                ),
                "it correlates a space's variables",
            ));
        }
        return Ok(None);
    };
    let name = Opt::correlation.name();
    let mut space = DesignSpace::parse(Opt::space.name(), &texts)?;
    crate::cubature::check_space(&space, Opt::space.name())?;
    match opt_rows(r)? {
        None => {}
        Some(Value::RowsText(rows)) => space.correlate_rows(name, &rows)?,
        Some(Value::RowsNumbers(m)) => space.correlate(name, "", m)?,
        Some(_) => {}
    }
    Ok(Some(space))
}

fn opt_rows(r: &Request) -> Result<Option<Value>, Error> {
    read(r, Opt::correlation, Some)
}

/// The dimension: as given (checked against a space's coordinates), else the space's,
/// else (with `infer`) the length of a corner given as a list.
fn dimension(
    r: &Request,
    space: Option<&DesignSpace>,
    infer: bool,
    sp: &Spelling,
) -> Result<usize, Error> {
    let d = count(r, Opt::s)?.map(|d| d as usize);
    match (d, space, r.arg(Opt::s)) {
        (Some(d), Some(space), Some(typed)) if d != space.dim() => Err(sp.together(
            &sp.typed(Opt::s, typed),
            &format!(
                "{} has {} coordinates; expected {} equal to it",
                sp.spell(Opt::space.name()),
                space.dim(),
                sp.spell(Opt::s.name())
            ),
        )),
        (Some(d), _, _) => Ok(d),
        (None, Some(space), _) => Ok(space.dim()),
        (None, None, _) => {
            let from_corner = match r.arg(Opt::bounds) {
                Some(Arg::Pair(lo, hi)) if infer => Some(lo.len().max(hi.len())),
                _ => None,
            };
            from_corner.filter(|d| *d > 1).ok_or_else(|| {
                Error::invalid(
                    "d",
                    "None",
                    "the number of inputs (or a space, or corners a, b of d numbers)",
                )
            })
        }
    }
}

/// The box (`None`: the unit cube), checked as every box of the package is
/// ([`crate::plan::space::Bounds`]): LO1,HI1,... or the corners apart (one number for
/// every dimension, a missing one the cube's); refused with a space, whose laws give the
/// range.
#[allow(clippy::type_complexity)]
fn corners(
    r: &Request,
    d: usize,
    space: bool,
    sp: &Spelling,
) -> Result<(Option<Vec<f64>>, Option<Vec<f64>>), Error> {
    let Some(typed) = r.arg(Opt::bounds) else {
        return Ok((None, None));
    };
    let name = Opt::bounds.name();
    if space {
        return Err(sp.together(
            &format!("{} with {}", sp.spell(name), sp.spell(Opt::space.name())),
            "the space's distributions give the range",
        ));
    }
    let shown = (sp.shown)(name, typed);
    let values = match read(r, Opt::bounds, Some)? {
        Some(Value::Pair(lo, hi)) => {
            let side = |v: Vec<f64>| if v.len() == 1 { vec![v[0]; d] } else { v };
            let (lo, hi) = (side(lo), side(hi));
            if lo.len() != d || hi.len() != d {
                return Err(Error::invalid(
                    name,
                    shown,
                    format!("{d} finite numbers per corner (one per dimension), or one"),
                ));
            }
            lo.iter().zip(&hi).flat_map(|(a, b)| [*a, *b]).collect()
        }
        Some(Value::Numbers(v)) => v,
        _ => Vec::new(),
    };
    let bounds = crate::plan::space::Bounds::new(name, &shown, &values, d)?;
    Ok((Some(bounds.lo), Some(bounds.hi)))
}

/// The options every integration command takes beyond its box and space, each read by
/// its declaration (`None`: not given, the command's default).
struct Shared {
    abs_tol: Option<f64>,
    level: Option<f64>,
    replicates: Option<usize>,
    max_n: Option<u64>,
    seed: Option<u64>,
}

impl Shared {
    fn read(r: &Request) -> Result<Shared, Error> {
        Ok(Shared {
            abs_tol: real(r, Opt::abs_tol)?,
            level: real(r, Opt::level)?,
            replicates: count(r, Opt::replicates)?.map(|n| n as usize),
            max_n: count(r, Opt::max_n)?,
            seed: count(r, Opt::seed)?,
        })
    }
}

/// Where an integration runs: its dimension and its box (`None`: the unit cube).
struct Region {
    d: usize,
    a: Option<Vec<f64>>,
    b: Option<Vec<f64>>,
}

/// What differs between the integration commands' states ([`Cubature`],
/// [`Sensitivity`]): the resolution of a request ([`from_request`]) and of a
/// continuation ([`continued`]) are written once over it.
trait Integration: Clone {
    /// The command whose options it takes.
    const COMMAND: Command;
    /// The computation's noun in a continuation's refusals.
    const NOUN: &'static str;
    /// How a continuation's refusal of another dimension says the earlier one's: its
    /// verb and noun (`was computed in 2 dimensions`, `has 2 inputs`).
    const DIMENSION: (&'static str, &'static str);
    /// Whether the dimension may be read off a corner given as a list.
    const INFER_D: bool;
    /// What a continuation takes from the earlier run and refuses.
    const FIXED: &'static [Opt];

    /// Refusals said before any other.
    fn first(_r: &Request) -> Result<(), Error> {
        Ok(())
    }
    /// The space's own check, before the dimension is read.
    fn check_space(_space: &DesignSpace) -> Result<(), Error> {
        Ok(())
    }
    /// The dimension's own check, before the box is read.
    fn check_d(d: usize) -> Result<(), Error>;
    /// The state from its region, its space and the options given.
    fn build(
        region: Region,
        space: Option<&DesignSpace>,
        r: &Request,
        sp: &Spelling,
    ) -> Result<Self, Error>;

    fn d(&self) -> usize;
    fn seed(&self) -> u64;
    fn replicates(&self) -> usize;
    /// The replicates a result reports (the randomisations evaluated).
    fn evaluated_replicates(&self) -> usize {
        self.replicates()
    }
    /// How a continuation's refusal names the earlier replicates.
    fn earlier_replicates(&self) -> String;
    /// The word a continuation keeps (the rule, the estimator): its option, the earlier
    /// word and how a refusal names it.
    fn kept_word(&self) -> (Opt, &'static str, String);
    /// A flag a continuation keeps (the design of its points): its option and the
    /// earlier value.
    fn kept_flag(&self) -> Option<(Opt, bool)> {
        None
    }
    /// The tolerances given to a continuation, honoured.
    fn set_tolerances(&mut self, r: &Request) -> Result<(), Error>;
    fn set_level(&mut self, level: f64) -> Result<(), Error>;
    fn set_max_n(&mut self, max_n: u64) -> Result<(), Error>;
    /// What else a continuation honours.
    fn set_more(&mut self, _r: &Request) -> Result<(), Error> {
        Ok(())
    }
}

/// A new state of `T` from the options a front end received, with its space; every
/// refusal spelled by the front end.
fn from_request<T: Integration>(
    r: &Request,
    sp: &Spelling,
) -> Result<(T, Option<DesignSpace>), Error> {
    (|| {
        T::first(r)?;
        refuse_others(r, T::COMMAND, sp)?;
        let space = design_space(r, sp)?;
        if let Some(space) = &space {
            T::check_space(space)?;
        }
        let d = dimension(r, space.as_ref(), T::INFER_D, sp)?;
        // The dimension first, so that d = 0 is refused as d rather than by what needs it.
        T::check_d(d)?;
        let (a, b) = corners(r, d, space.is_some(), sp)?;
        Ok((T::build(Region { d, a, b }, space.as_ref(), r, sp)?, space))
    })()
    .map_err(|e| sp.error(e, r))
}

/// Whether `arg` is one of the whole numbers `ns` (as a number, or as its digits).
fn names_a_count(arg: Option<&Arg>, ns: &[usize]) -> bool {
    let given = match arg {
        Some(Arg::Int(i)) => u64::try_from(*i).ok(),
        Some(Arg::Text(t)) => t.trim().parse::<u64>().ok(),
        _ => None,
    };
    given.is_some_and(|g| ns.iter().any(|&n| n as u64 == g))
}

/// `earlier` continued with the options given (`earlier` itself is not changed): the
/// tolerances, level and budget (and what [`Integration::set_more`] takes) are honoured;
/// the dimension must match; the options of [`Integration::FIXED`] are refused, and the
/// replicates, seed and kept word unless equal to the earlier one's.
fn continued<T: Integration>(earlier: &T, r: &Request, sp: &Spelling) -> Result<T, Error> {
    let mut state = earlier.clone();
    let kept = Kept {
        what: T::NOUN,
        sp,
        r,
    };
    (|| {
        refuse_others(r, T::COMMAND, sp)?;
        let (verb, noun) = T::DIMENSION;
        kept.dimension(earlier.d(), verb, noun)?;
        kept.fixed(T::FIXED)?;
        kept.seed(earlier.seed())?;
        // The count the earlier result reports is taken as the same replicates, even
        // where it differs from the count asked for (replicates added to meet the
        // tolerance; the one lattice of a run that left for the Bayesian lattice) or a
        // new run's range refuses it (1): a continuation passes back what it was shown.
        let counts = [earlier.replicates(), earlier.evaluated_replicates()];
        if !names_a_count(r.arg(Opt::replicates), &counts) {
            if let Some(n) = count(r, Opt::replicates)? {
                let same = n == earlier.replicates() as u64;
                kept.equal(Opt::replicates, same, &earlier.earlier_replicates())?;
            }
        }
        let (opt, word_then, said) = earlier.kept_word();
        if let Some(w) = word(r, opt)? {
            kept.equal(opt, w == word_then, &said)?;
        }
        if let Some((opt, then)) = earlier.kept_flag() {
            if let Some(given) = flag(r, opt)? {
                let said = format!("design ({} = {then})", sp.spell(opt.name()));
                kept.equal(opt, given == then, &said)?;
            }
        }
        state.set_tolerances(r)?;
        if let Some(level) = real(r, Opt::level)? {
            state.set_level(level)?;
        }
        if let Some(max_n) = count(r, Opt::max_n)? {
            state.set_max_n(max_n)?;
        }
        state.set_more(r)
    })()
    .map_err(|e| sp.error(e, r))?;
    Ok(state)
}

/// An integration made from the options a front end received, and continued with more:
/// [`Cubature`] (`quad`) and [`Sensitivity`] (the Sobol' indices). A trait because the
/// states live in the cubature crate, below the options that resolve them.
pub trait FromRequest: Sized {
    /// A new state from the options given, and the space whose map the caller applies to
    /// the points.
    fn from_request(r: &Request, sp: &Spelling) -> Result<(Self, Option<DesignSpace>), Error>;

    /// This state continued with the options given (the state itself is not changed).
    fn continued(&self, r: &Request, sp: &Spelling) -> Result<Self, Error>;
}

impl FromRequest for Cubature {
    /// A new integration from the options a front end received: the dimension (checked
    /// against a space's coordinates), the box (not with a space), the space and its
    /// correlation (not without a space), the tolerances, level, replicates, budget and
    /// seed (their defaults those of [`QuadOptions::default`]) and the rule (asked for,
    /// or [`Rule::for_space`]). Returns the state and the space, whose map the caller
    /// applies to the points ([`crate::cubature::space_values`]).
    fn from_request(r: &Request, sp: &Spelling) -> Result<(Cubature, Option<DesignSpace>), Error> {
        from_request(r, sp)
    }

    /// This integration continued with the options given (the state itself is not
    /// changed): the tolerances (either given sets both, the other at its default),
    /// level and budget are honoured; the dimension must match; the box, space and
    /// correlation are refused, and the replicates, seed and rule unless equal to this
    /// one's.
    fn continued(&self, r: &Request, sp: &Spelling) -> Result<Cubature, Error> {
        continued(self, r, sp)
    }
}

impl Integration for Cubature {
    const COMMAND: Command = Command::Quad;
    const NOUN: &'static str = "integration";
    const DIMENSION: (&'static str, &'static str) = ("was computed in", "dimensions");
    const INFER_D: bool = false;
    const FIXED: &'static [Opt] = &[Opt::bounds, Opt::space, Opt::correlation];

    fn check_d(d: usize) -> Result<(), Error> {
        crate::sequences::ExtensibleLattice::new(d, 0, 0).map(|_| ())
    }

    fn build(
        region: Region,
        space: Option<&DesignSpace>,
        r: &Request,
        sp: &Spelling,
    ) -> Result<Cubature, Error> {
        let (rule, rule_reason) = match (word(r, Opt::rule)?, r.arg(Opt::rule)) {
            (Some(word), Some(typed)) => (
                Rule::parse(Opt::rule.name(), &word)?,
                format!(
                    "as asked ({}={})",
                    sp.spell(Opt::rule.name()),
                    (sp.shown)(Opt::rule.name(), typed)
                ),
            ),
            _ => Rule::for_quad(space),
        };
        let rule_asked = r.arg(Opt::rule).is_some();
        let rel_tol = real(r, Opt::rel_tol)?;
        let g = Shared::read(r)?;
        let o = QuadOptions::default();
        let options = QuadOptions {
            a: region.a,
            b: region.b,
            abs_tol: g.abs_tol.unwrap_or(o.abs_tol),
            rel_tol: rel_tol.unwrap_or(o.rel_tol),
            level: g.level.unwrap_or(o.level),
            replicates: g.replicates.unwrap_or(o.replicates),
            max_n: g.max_n.unwrap_or(o.max_n),
            seed: g.seed.unwrap_or(o.seed),
            rule,
            rule_reason,
            rule_asked,
            ..o
        };
        let mut state = Cubature::new(region.d, options)?;
        // The rule chosen from unbounded laws reaches their tails through the tail map.
        if let (Some(space), Rule::Probe) = (space, state.options().rule) {
            let unbounded = space.unbounded();
            if unbounded.len() == region.d {
                state.widen_tails(&unbounded)?;
            }
        }
        Ok(state)
    }

    fn d(&self) -> usize {
        Cubature::d(self)
    }
    fn seed(&self) -> u64 {
        self.options().seed
    }
    fn replicates(&self) -> usize {
        self.options().replicates
    }
    fn evaluated_replicates(&self) -> usize {
        Cubature::replicates(self)
    }
    fn earlier_replicates(&self) -> String {
        let n = self.options().replicates;
        format!("{n} replicates (their shifts and sums)")
    }
    fn kept_word(&self) -> (Opt, &'static str, String) {
        let rule = self.options().rule.as_str();
        (Opt::rule, rule, format!("rule ({rule})"))
    }
    fn set_tolerances(&mut self, r: &Request) -> Result<(), Error> {
        if r.abs_tol.is_some() || r.rel_tol.is_some() {
            let d = QuadOptions::default();
            let abs = real(r, Opt::abs_tol)?.unwrap_or(d.abs_tol);
            Cubature::set_tolerance(self, abs, real(r, Opt::rel_tol)?.unwrap_or(d.rel_tol))?;
        }
        Ok(())
    }
    fn set_level(&mut self, level: f64) -> Result<(), Error> {
        Cubature::set_level(self, level)
    }
    fn set_max_n(&mut self, max_n: u64) -> Result<(), Error> {
        Cubature::set_max_n(self, max_n)
    }
}

impl FromRequest for Sensitivity {
    /// A new sensitivity analysis from the options a front end received: the number of
    /// inputs (or the space's, or the length of a corner), the box (not with a space), a
    /// space of independent inputs (a correlation or a Brownian path refused), the
    /// tolerance, level, intervals, estimator, replicates, budget and seed (their
    /// defaults those of [`SensitivityOptions::default`]). Returns the state and the
    /// space.
    fn from_request(
        r: &Request,
        sp: &Spelling,
    ) -> Result<(Sensitivity, Option<DesignSpace>), Error> {
        from_request(r, sp)
    }

    /// This analysis continued with the options given (the state itself is not
    /// changed): the tolerance, level, intervals and budget are honoured; the number of
    /// inputs must match; the box and space are refused, and the replicates, estimator
    /// and seed unless equal to this one's.
    fn continued(&self, r: &Request, sp: &Spelling) -> Result<Sensitivity, Error> {
        continued(self, r, sp)
    }
}

impl Integration for Sensitivity {
    const COMMAND: Command = Command::Sensitivity;
    const NOUN: &'static str = "analysis";
    const DIMENSION: (&'static str, &'static str) = ("has", "inputs");
    const INFER_D: bool = true;
    const FIXED: &'static [Opt] = &[Opt::bounds, Opt::space];

    fn first(r: &Request) -> Result<(), Error> {
        match r.arg(Opt::correlation) {
            Some(c) => Err(Error::invalid(
                Opt::correlation.name(),
                c,
                "no correlation: Sobol' indices are computed for independent inputs",
            )),
            None => Ok(()),
        }
    }

    fn check_space(space: &DesignSpace) -> Result<(), Error> {
        crate::sensitivity::check_independent(Opt::space.name(), space)
    }

    fn check_d(d: usize) -> Result<(), Error> {
        Sensitivity::new(d, SensitivityOptions::default()).map(|_| ())
    }

    fn build(
        region: Region,
        space: Option<&DesignSpace>,
        r: &Request,
        _: &Spelling,
    ) -> Result<Sensitivity, Error> {
        let o = SensitivityOptions::default();
        let first_order = match word(r, Opt::first_estimator)? {
            Some(w) => FirstOrder::parse(Opt::first_estimator.name(), &w)?,
            None => o.first_order,
        };
        let interval = match word(r, Opt::interval)? {
            Some(w) => Interval::parse(Opt::interval.name(), &w)?,
            None => o.interval,
        };
        let simultaneous = flag(r, Opt::simultaneous)?;
        let second_order = flag(r, Opt::second_order)?;
        let g = Shared::read(r)?;
        let options = SensitivityOptions {
            a: region.a,
            b: region.b,
            names: space.map(|s| s.vars.iter().map(|v| v.name.clone()).collect()),
            abs_tol: g.abs_tol.unwrap_or(o.abs_tol),
            level: g.level.unwrap_or(o.level),
            simultaneous: simultaneous.unwrap_or(o.simultaneous),
            first_order,
            replicates: g.replicates.unwrap_or(o.replicates),
            max_n: g.max_n.unwrap_or(o.max_n),
            seed: g.seed.unwrap_or(o.seed),
            rule: Rule::for_space(space).0,
            second_order: second_order.unwrap_or(o.second_order),
            interval,
            ..o
        };
        Sensitivity::new(region.d, options)
    }

    fn d(&self) -> usize {
        Sensitivity::d(self)
    }
    fn seed(&self) -> u64 {
        self.options().seed
    }
    fn replicates(&self) -> usize {
        self.options().replicates
    }
    fn earlier_replicates(&self) -> String {
        format!("({})", self.options().replicates)
    }
    fn kept_word(&self) -> (Opt, &'static str, String) {
        let estimator = self.options().first_order.as_str();
        (Opt::first_estimator, estimator, format!("({estimator})"))
    }
    fn set_tolerances(&mut self, r: &Request) -> Result<(), Error> {
        match real(r, Opt::abs_tol)? {
            Some(t) => Sensitivity::set_tolerance(self, t),
            None => Ok(()),
        }
    }
    fn set_level(&mut self, level: f64) -> Result<(), Error> {
        Sensitivity::set_level(self, level)
    }
    fn set_max_n(&mut self, max_n: u64) -> Result<(), Error> {
        Sensitivity::set_max_n(self, max_n)
    }
    fn set_more(&mut self, r: &Request) -> Result<(), Error> {
        if let Some(s) = flag(r, Opt::simultaneous)? {
            self.set_simultaneous(s);
        }
        match word(r, Opt::interval)? {
            Some(w) => self.set_interval(Interval::parse(Opt::interval.name(), &w)?),
            None => Ok(()),
        }
    }
    fn kept_flag(&self) -> Option<(Opt, bool)> {
        // The BA_i rows are part of every point's design.
        Some((Opt::second_order, self.options().second_order))
    }
}

/// The refusals of a continuation: what it keeps of the earlier run (`what`: the
/// computation's noun).
struct Kept<'a> {
    what: &'static str,
    sp: &'a Spelling<'a>,
    r: &'a Request,
}

impl Kept<'_> {
    fn start(&self) -> String {
        self.sp.spell(Opt::start.name())
    }

    /// The dimension, if given, equal to the earlier run's.
    fn dimension(&self, d: usize, verb: &str, noun: &str) -> Result<(), Error> {
        match (count(self.r, Opt::s)?, self.r.arg(Opt::s)) {
            (Some(given), Some(typed)) if given != d as u64 => Err(self.sp.together(
                &self.sp.typed(Opt::s, typed),
                &format!("{} {verb} {d} {noun}", self.start()),
            )),
            _ => Ok(()),
        }
    }

    /// Options a continuation takes from the earlier run and cannot be given.
    fn fixed(&self, opts: &[Opt]) -> Result<(), Error> {
        match opts.iter().find(|o| self.r.arg(**o).is_some()) {
            Some(opt) => {
                let spelled = self.sp.spell(opt.name());
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
        let Some(typed) = self.r.arg(Opt::seed) else {
            return Ok(());
        };
        if count(self.r, Opt::seed).ok().flatten() == Some(earlier) {
            return Ok(());
        }
        let seed = Opt::seed.name();
        Err(self.sp.together(
            &format!(
                "{} with {} = {}",
                self.sp.spell(seed),
                self.start(),
                (self.sp.shown)(seed, typed)
            ),
            &format!(
                "a continued {} keeps the earlier one's shifts (seed {earlier})",
                self.what
            ),
        ))
    }

    /// `opt`, given, refused unless `equal` to the earlier run's (`earlier`).
    fn equal(&self, opt: Opt, equal: bool, earlier: &str) -> Result<(), Error> {
        match self.r.arg(opt) {
            Some(typed) if !equal => Err(self.sp.together(
                &format!("{} with {}", self.sp.typed(opt, typed), self.start()),
                &format!(
                    "a continued {} keeps the earlier one's {earlier}",
                    self.what
                ),
            )),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(pairs: &[(Opt, Arg)]) -> Request {
        let mut r = Request::default();
        for (opt, v) in pairs {
            r.set(opt.name(), v.clone()).unwrap();
        }
        r
    }

    fn refusal(e: Error) -> String {
        e.to_string()
    }

    #[test]
    fn the_defaults_are_the_options_and_the_declarations_say_them() {
        let (c, space) =
            Cubature::from_request(&request(&[(Opt::s, Arg::Int(3))]), &Spelling::PLAIN).unwrap();
        let o = QuadOptions::default();
        assert!(space.is_none() && c.d() == 3);
        assert_eq!(
            (c.options().replicates, c.options().max_n),
            (o.replicates, o.max_n)
        );
        let said = |opt: Opt| (opt.declared().default)(Command::Quad).unwrap();
        assert_eq!(said(Opt::replicates), o.replicates.to_string());
        assert_eq!(said(Opt::rel_tol), o.rel_tol.to_string());
        let (s, _) =
            Sensitivity::from_request(&request(&[(Opt::s, Arg::Int(2))]), &Spelling::PLAIN)
                .unwrap();
        let said = (Opt::replicates.declared().default)(Command::Sensitivity).unwrap();
        assert_eq!(s.options().replicates.to_string(), said);
    }

    #[test]
    fn refusals_are_spelled_by_the_front_end_with_the_value_typed() {
        let name = |n: &str| format!("--{}", n.replace('_', "-"));
        let shown = |_: &str, v: &Arg| format!("<{v}>");
        let sp = Spelling {
            name: &name,
            shown: &shown,
        };
        let r = request(&[(Opt::s, Arg::Int(1)), (Opt::level, Arg::Text("1e5".into()))]);
        let e = refusal(Cubature::from_request(&r, &sp).unwrap_err());
        assert_eq!(e, "invalid --level = <1e5>: expected a value in (0, 1)");
        let r = request(&[
            (Opt::s, Arg::Int(1)),
            (Opt::correlation, Arg::from("1,0.5;0.5,1")),
        ]);
        let e = refusal(Cubature::from_request(&r, &sp).unwrap_err());
        assert!(
            e.starts_with("invalid --correlation without --space: "),
            "{e}"
        );
        let r = request(&[(Opt::s, Arg::Int(2)), (Opt::rule, Arg::from("sobol"))]);
        let e = refusal(Sensitivity::from_request(&r, &sp).unwrap_err());
        assert!(
            e.starts_with("invalid --rule = <sobol>: expected no --rule with sensitivity"),
            "{e}"
        );
    }

    #[test]
    fn a_continuation_honours_or_refuses_each_option_by_name() {
        let r = request(&[(Opt::s, Arg::Int(2)), (Opt::seed, Arg::Int(5))]);
        let (c, _) = Cubature::from_request(&r, &Spelling::PLAIN).unwrap();
        let more = request(&[(Opt::max_n, Arg::Int(1 << 22)), (Opt::seed, Arg::Int(5))]);
        let later = c.continued(&more, &Spelling::PLAIN).unwrap();
        assert_eq!(later.options().max_n, 1 << 22);
        assert_eq!(
            c.options().max_n,
            QuadOptions::default().max_n,
            "the earlier one stands"
        );
        for (pairs, head) in [
            (
                vec![(Opt::seed, Arg::Int(6))],
                "invalid seed with start = 6: ",
            ),
            (
                vec![(Opt::replicates, Arg::Int(8))],
                "invalid replicates = 8 with start: ",
            ),
            (
                vec![(Opt::s, Arg::Int(3))],
                "invalid s = 3: start was computed in 2",
            ),
            (
                vec![(Opt::bounds, Arg::from("0,1,0,1"))],
                "invalid bounds with start: ",
            ),
        ] {
            let e = refusal(c.continued(&request(&pairs), &Spelling::PLAIN).unwrap_err());
            assert!(e.starts_with(head), "{e}");
        }
    }
}
