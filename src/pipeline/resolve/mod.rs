//! The one resolution of a request, shared by `generate` and `eval`: the options read
//! once by their declarations ([`Parsed`]), and the rules between them written over the
//! typed fields, one file per space — the cube ([`cube`]), a region ([`region`]), a
//! design space ([`design`]), the paper's pipeline and the goals ([`paper`]) and the
//! measuring of a set ([`eval`]). Every refusal names the option by its declaration
//! ([`Opt`]) as the front end spells it, and echoes its value as typed.

mod cube;
mod design;
pub(crate) mod eval;
mod paper;
mod region;

use crate::pipeline::options::{Command, Group, Opt, Parsed, MAX_COUNT, OPTS};
use crate::pipeline::request::{Job, Request, Resolved};
use crate::plan::space::{numbers_text, Bounds};
use crate::sequences;
use crate::Error;
use std::fmt::Display;

/// A request being resolved: as received, as read by the declarations, and how the
/// front end spells an option.
pub(crate) struct Ctx<'a> {
    /// The request as the front end gave it (the values as typed, for refusals).
    pub(crate) r: &'a Request,
    /// Every option read by its declaration.
    pub(crate) p: Parsed,
    /// The front end's spelling of an option's name.
    pub(crate) spell: &'a dyn Fn(&str) -> String,
}

impl<'a> Ctx<'a> {
    /// The request `r` read once by the declarations.
    pub(crate) fn new(r: &'a Request, spell: &'a dyn Fn(&str) -> String) -> Ctx<'a> {
        Ctx {
            r,
            p: Parsed::of(r, spell),
            spell,
        }
    }

    /// The option's name as the front end spells it.
    pub(crate) fn name(&self, o: Opt) -> String {
        (self.spell)(o.name())
    }

    /// Whether the option is given.
    pub(crate) fn given(&self, o: Opt) -> bool {
        self.r.arg(o).is_some()
    }

    /// The refusal of option `o` for the value `typed` (as the front end received it, or
    /// words saying how it was given).
    pub(crate) fn bad(&self, o: Opt, typed: &dyn Display, expected: impl Into<String>) -> Error {
        Error::invalid(self.name(o), typed, expected)
    }

    /// The refusal of the option `o` as given in the request (a combination that cannot
    /// keep its promise): its value as typed, or `none` when it is not given.
    pub(crate) fn refuse(&self, o: Opt, expected: impl Into<String>) -> Error {
        match self.r.arg(o) {
            Some(typed) => self.bad(o, typed, expected),
            None => self.absent(o, expected),
        }
    }

    /// The refusal of a missing option: `none` stands for its value.
    pub(crate) fn absent(&self, o: Opt, expected: impl Into<String>) -> Error {
        self.bad(o, &"none", expected)
    }

    /// The first given option of `group`, in the table's order.
    pub(crate) fn first_given(&self, group: Group) -> Option<Opt> {
        OPTS.iter()
            .copied()
            .find(|o| o.declared().is(group) && self.given(*o))
    }

    /// The first of `opts` that is given.
    pub(crate) fn first_of(&self, opts: &[Opt]) -> Option<Opt> {
        opts.iter().copied().find(|o| self.given(*o))
    }

    /// Refuses the first option given that `command` does not take (an option of the
    /// integration to a tolerance given to `generate`, say), naming it.
    fn refuse_others(&self, command: Command) -> Result<(), Error> {
        let Some(o) = OPTS
            .iter()
            .copied()
            .find(|o| !o.declared().takes(command) && self.given(*o))
        else {
            return Ok(());
        };
        let takes: Vec<&str> = o.declared().commands.iter().map(|c| c.name()).collect();
        Err(self.refuse(
            o,
            format!(
                "no {} with {}: it is an option of {}",
                self.name(o),
                command.name(),
                takes.join(" and ")
            ),
        ))
    }

    /// The refusal of a box without the region it bounds.
    pub(crate) fn box_alone(&self) -> Error {
        self.refuse(
            Opt::bbox,
            format!(
                "a box only with {} EXPR or {} polytope:FILE (it bounds them)",
                self.name(Opt::region),
                self.name(Opt::shape)
            ),
        )
    }

    /// A refusal of the run's size (n and s together) by the library's check, naming
    /// the option that gave the size with its value as typed: the nested sizes, whose
    /// last is n, or n itself (with a set to extend, the points to add; the total `n` is
    /// said).
    fn too_large(&self, e: Error, n: usize) -> Error {
        match e {
            Error::InvalidArgument { name, expected, .. } => {
                let named = Opt::named(&name).unwrap_or(Opt::n);
                let option = if named == Opt::n && self.given(Opt::nested) {
                    Opt::nested
                } else {
                    named
                };
                let total = match self.given(Opt::extend) {
                    true if option == Opt::n => format!(" (with the kept points, {n})"),
                    _ => String::new(),
                };
                self.refuse(option, format!("{expected}{total}"))
            }
            other => other,
        }
    }

    /// The number of points, which must be given.
    fn n_points(&self) -> Result<usize, Error> {
        self.p
            .n
            .value()?
            .ok_or_else(|| self.absent(Opt::n, "the number of points (at least 1)"))
    }

    /// n + m for a grown set, checked.
    fn grown(&self, m: usize, old: usize) -> Result<usize, Error> {
        m.checked_add(old)
            .filter(|&t| t as u64 <= MAX_COUNT)
            .ok_or_else(|| {
                self.refuse(
                    Opt::n,
                    format!(
                        "a number of points to add that, with the {old} kept points, stays \
                         within {MAX_COUNT} points"
                    ),
                )
            })
    }

    /// Exact pair figures when `exact` was asked, the report's rule otherwise.
    fn sums(&self) -> Result<crate::quality::metrics::Sums, Error> {
        Ok(crate::quality::metrics::Sums::asked(
            self.p.exact.value()? == Some(true),
        ))
    }

    /// The box `bounds` scales the unit cube's points to, for dimension `s`.
    fn bounds(&self, s: usize) -> Result<Option<Bounds>, Error> {
        use crate::pipeline::options::Value;
        let Some(arg) = self.r.arg(Opt::bounds) else {
            return Ok(None);
        };
        let name = self.name(Opt::bounds);
        let v = match self.p.bounds.value()? {
            Some(Value::Pair(lo, hi)) => {
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
                let (lo, hi) = (widen(&lo)?, widen(&hi)?);
                lo.iter().zip(&hi).flat_map(|(a, b)| [*a, *b]).collect()
            }
            Some(Value::Numbers(v)) => v,
            _ => return Ok(None),
        };
        Bounds::new(&name, &numbers_text(&v), &v, s).map(Some)
    }

    /// The request resolved for `generate`.
    pub(crate) fn resolve(&self) -> Result<Resolved, Error> {
        self.refuse_others(Command::Generate)?;
        if self.given(Opt::space) {
            return self.design();
        }
        self.correlation_without_space()?;
        let seed = self.p.seed.value()?.unwrap_or(0);
        if let Some(job) = self.baseline(seed)? {
            return Ok(job);
        }
        let constrained = self.given(Opt::constraints) || self.p.mixture.value()? == Some(true);
        let in_region = self.given(Opt::region) || self.given(Opt::shape) || constrained;
        let goal = self.goal(in_region)?;
        let paper_by = match goal {
            crate::config::Goal::Paper if !in_region && !self.given(Opt::method) => {
                self.paper_given(false).first().copied()
            }
            _ => None,
        };
        let (mut cfg, mixture) = if in_region {
            self.region_config()?
        } else {
            (self.cube_config(&goal)?, None)
        };
        cfg.seed = seed;
        cfg.goal = self.default_target(goal, &cfg);
        self.common(&mut cfg)?;
        self.lattice(&mut cfg, in_region)?;
        cfg.sums = self.sums()?;
        sequences::check_size(cfg.n, cfg.s).map_err(|e| self.too_large(e, cfg.n))?;
        if in_region && self.given(Opt::bounds) {
            return Err(self.refuse(
                Opt::bounds,
                format!(
                    "no bounds in a region: its points are in its own coordinates already \
                     ({} scales the unit cube)",
                    self.name(Opt::bounds)
                ),
            ));
        }
        Ok(Resolved {
            bounds: self.bounds(cfg.s)?,
            sums: cfg.sums,
            job: Job::Run(Box::new(cfg)),
            design: None,
            rule: None,
            mixture,
            paper_by,
        })
    }
}
