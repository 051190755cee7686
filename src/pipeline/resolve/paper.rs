//! The rules of the pipelines and their solver: which goal runs (an asked goal, or the
//! paper's pipeline chosen by its options), the target, the solver's budget and the
//! DEM's settings, the randomisation, and the paper's own options in the cube.

use super::Ctx;
use crate::config::{EnergyKind, GenerateConfig, Goal, Init};
use crate::energies::discrepancy::DiscrepancyKind;
use crate::energies::{Distance, Precision};
use crate::integrators::{Kappa, Restart};
use crate::pipeline::options::{words, Group, Opt, Value, OPTS};
use crate::pipeline::request::Arg;
use crate::plan::start::MAX_SHIFTS;
use crate::post::randomize::Randomize;
use crate::quality::target::Target;
use crate::solve::Solver;
use crate::{Error, PointSet};

impl Ctx<'_> {
    /// The target `target` names (`lattice` names the blend, whose discrepancies a
    /// caller compares: the lattice itself is chosen by [`Ctx::lattice`]).
    fn target(&self) -> Result<Option<Target>, Error> {
        let Some(word) = self.p.target.value()? else {
            return Ok(None);
        };
        Ok(Some(match word.as_str() {
            "blend-smooth" => Target::smooth_blend(),
            "curved" => Target::curved(),
            w if words::BLENDS.contains(&w) => Target::blend(),
            w => Target::single(DiscrepancyKind::parse(w)?),
        }))
    }

    /// The given options of the paper's pipeline (and the descent's budget, which the
    /// space-filling goal takes as its own).
    pub(super) fn paper_given(&self, space_filling: bool) -> Vec<Opt> {
        OPTS.iter()
            .copied()
            .filter(|o| {
                let d = o.declared();
                (d.is(Group::Paper) || d.is(Group::Descent)) && self.given(*o)
            })
            .filter(|o| !(o.declared().is(Group::Descent) && space_filling))
            .collect()
    }

    /// The refusals of an asked goal: with the paper's method, with the paper's options
    /// (but space-filling in a region, whose pipeline is the region's run), and the
    /// integration goal in a region with points to keep or a target.
    fn check_asked(&self, goal: &str, in_region: bool, target: bool) -> Result<(), Error> {
        let space_filling = goal == words::SPACE_FILLING;
        if self.given(Opt::method) {
            return Err(self.refuse(
                Opt::goal,
                format!(
                    "no {} with {} paper (the paper's method is its own pipeline)",
                    self.name(Opt::goal),
                    self.name(Opt::method)
                ),
            ));
        }
        if let (Some(&first), false) = (
            self.paper_given(space_filling).first(),
            in_region && space_filling,
        ) {
            return Err(self.refuse(
                first,
                format!(
                    "no {} with {} {goal}: the paper's options only with {} paper (or no \
                     {}); a goal chooses its own pipeline",
                    self.name(first),
                    self.name(Opt::goal),
                    self.name(Opt::method),
                    self.name(Opt::goal)
                ),
            ));
        }
        if space_filling || !in_region {
            return Ok(());
        }
        if self.given(Opt::extend) {
            return Err(self.refuse(
                Opt::extend,
                format!(
                    "{} only with the space-filling run in a region (the integration goal \
                     makes the whole set)",
                    self.name(Opt::extend)
                ),
            ));
        }
        if target {
            return Err(self.refuse(
                Opt::target,
                "no target in a region: its discrepancies are those of the unit cube; the \
                 goal there lowers the energy distance",
            ));
        }
        Ok(())
    }

    /// What the run is for: an asked goal chooses (none of the paper's options may come
    /// with it, except with space-filling in a region, whose pipeline is the region's
    /// run); without one, the paper's method, any of the paper's options or a region
    /// choose the paper's pipeline, and otherwise the integration goal.
    pub(super) fn goal(&self, in_region: bool) -> Result<Goal, Error> {
        let asked = self.p.goal.value()?;
        let target = self.target()?;
        let goal = match asked.as_deref() {
            Some(g) => {
                self.check_asked(g, in_region, target.is_some())?;
                if g == words::SPACE_FILLING {
                    Goal::SpaceFilling
                } else {
                    Goal::Integration(Target::blend())
                }
            }
            None if self.given(Opt::method) || !self.paper_given(false).is_empty() || in_region => {
                Goal::Paper
            }
            None => Goal::Integration(Target::blend()),
        };
        match (goal, target) {
            (Goal::Integration(_), Some(t)) => Ok(Goal::Integration(t)),
            (_, Some(_)) => Err(self.refuse(
                Opt::target,
                "a target only with the integration goal (the cube's default); this run's \
                 pipeline is the paper's or space-filling",
            )),
            (g, None) => Ok(g),
        }
    }

    /// The options every space shares: solver, budget, κ, restart, tolerance,
    /// randomisation.
    pub(super) fn common(&self, cfg: &mut GenerateConfig) -> Result<(), Error> {
        if let Some(w) = self.p.integrator.value()? {
            cfg.solver = if w == words::INTEGRATORS[0] {
                Solver::Dem
            } else {
                Solver::Lbfgs
            };
        }
        if let Some(steps) = self.p.steps.value()? {
            cfg.steps = steps;
        }
        match self.p.kappa.value()? {
            Some(Value::Real(k)) => cfg.dem.kappa = Kappa::Fixed(k),
            Some(_) => cfg.dem.kappa = Kappa::default(),
            None => {}
        }
        match self.p.restart.value()? {
            Some(Value::Real(e)) => cfg.dem.restart = Restart::Threshold(e),
            Some(Value::Word(w)) if w == words::RESTART_WORDS[0] => cfg.dem.restart = Restart::Auto,
            Some(_) => cfg.dem.restart = Restart::Off,
            None => {}
        }
        if let Some(t) = self.p.tolerance.value()? {
            cfg.dem.tolerance = t;
        }
        self.randomize(cfg)
    }

    /// The randomisation: `true` (Python's True, the command line's bare flag) asks for
    /// the recommended one, `false` for none; refused where it would break the set's
    /// promise (a region, a grown set, tent with a pipeline that is not the lattice's).
    fn randomize(&self, cfg: &mut GenerateConfig) -> Result<(), Error> {
        let Some(word) = self.p.randomize.value()? else {
            return Ok(());
        };
        let kind = match word.as_str() {
            "true" => Randomize::Tent,
            w => Randomize::parse(w)?,
        };
        if cfg.region().is_some() {
            return Err(self.refuse(
                Opt::randomize,
                "no randomisation in a region (a shift would carry points out of it; the \
                 cube only)",
            ));
        }
        if cfg.extend.is_some() || !cfg.nested.is_empty() {
            let with = if cfg.extend.is_some() {
                Opt::extend
            } else {
                Opt::nested
            };
            return Err(self.refuse(
                Opt::randomize,
                format!(
                    "no randomisation of a grown set (here with {}): it would move the kept \
                     points ({}) and unstratify the prefixes ({}); randomise a set made for \
                     its size instead",
                    self.name(with),
                    self.name(Opt::extend),
                    self.name(Opt::nested)
                ),
            ));
        }
        if kind == Randomize::Tent {
            self.check_tent(cfg)?;
        }
        cfg.randomize = Some(kind);
        Ok(())
    }

    /// The tent randomisation keeps its promise only for the lattice made for it, which
    /// the integration goal builds in place of its descent.
    fn check_tent(&self, cfg: &GenerateConfig) -> Result<(), Error> {
        if !matches!(cfg.goal, Goal::Integration(_)) {
            return Err(self.refuse(
                Opt::randomize,
                "tent with the integration goal (the cube's default), which makes the \
                 lattice tent is for, not with this run's pipeline (the paper's or \
                 space-filling); cells or shift randomise other sets",
            ));
        }
        if self.given(Opt::target) {
            return Err(self.refuse(
                Opt::target,
                format!(
                    "no target with {} tent: the lattice for the tent randomisation is \
                     chosen by its own criterion (the randomised estimate's mean square \
                     error)",
                    self.name(Opt::randomize)
                ),
            ));
        }
        Ok(())
    }

    /// q of U_{q,p}: a number, or a word [`Distance::parse`] reads.
    fn distance(&self) -> Result<Option<Distance>, Error> {
        let Some(a) = self.r.arg(Opt::q) else {
            return Ok(None);
        };
        let expected = (Opt::q.declared().expected)();
        let text = match a {
            Arg::Text(t) => t.clone(),
            Arg::Int(_) | Arg::Float(_) => match self.p.q.value()? {
                Some(Value::Real(q)) => q.to_string(),
                _ => return Err(self.bad(Opt::q, &a, expected)),
            },
            other => return Err(self.bad(Opt::q, &other, expected)),
        };
        Distance::parse(&text)
            .map(Some)
            .map_err(|_| self.bad(Opt::q, &a, expected))
    }

    /// The paper's pipeline's options in the cube: energy, (q, p), precision, start,
    /// polish, shifts, logging.
    pub(super) fn paper_options(
        &self,
        cfg: &mut GenerateConfig,
        init_points: Option<PointSet>,
    ) -> Result<(), Error> {
        if let Some(w) = self.p.energy.value()? {
            cfg.energy = match w.as_str() {
                "uqp" => EnergyKind::Uqp,
                "e-inf" => EnergyKind::EInf,
                w => EnergyKind::Discrepancy(
                    DiscrepancyKind::parse(w)
                        .map_err(|_| self.refuse(Opt::energy, cube_energies()))?,
                ),
            };
        }
        cfg.q = self.distance()?;
        cfg.p = self.p.p.value()?;
        if let Some(w) = self.p.precision.value()? {
            cfg.precision = Precision::parse(&w)?;
        }
        cfg.init = match (self.p.init.value()?, init_points) {
            (_, Some(p)) => Init::Points(p),
            (Some(Value::Word(w)), None) if w == words::STARTS[1] => Init::Random,
            _ => Init::Halton,
        };
        if let Some(w) = self.p.polish.value()? {
            cfg.polish = match w.as_str() {
                "none" => None,
                w => Some(DiscrepancyKind::parse(w)?),
            };
        }
        if let Some(shifts) = self.p.shifts.value()? {
            if shifts > MAX_SHIFTS {
                // The declaration's words: its other refusals state the same range so.
                return Err(self.refuse(Opt::shifts, (Opt::shifts.declared().expected)()));
            }
            cfg.shifts = shifts;
        }
        cfg.log_every = match self.p.log_every.value()? {
            Some(k) => k,
            None if self.given(Opt::trajectory) => 10,
            None => 0,
        };
        Ok(())
    }
}

/// The energies of the cube, as a refusal in the cube lists them.
fn cube_energies() -> String {
    (Opt::energy.declared().expected)()
}

impl Ctx<'_> {
    /// The goal with its target for the run's size: the default target follows the
    /// dimension ([`Target::default_for`], for a grown set [`Target::default_grown_for`]),
    /// and `blend-smooth` by name weighs its smooth part for s
    /// ([`Target::smooth_blend_for`]).
    pub(super) fn default_target(&self, goal: Goal, cfg: &crate::config::GenerateConfig) -> Goal {
        match goal {
            Goal::Integration(_) if !self.given(Opt::target) => {
                Goal::Integration(if cfg.extend.is_some() || !cfg.nested.is_empty() {
                    Target::default_grown_for(cfg.n, cfg.s)
                } else {
                    Target::default_for(cfg.n, cfg.s)
                })
            }
            Goal::Integration(t) if t == Target::smooth_blend() => {
                Goal::Integration(Target::smooth_blend_for(cfg.s))
            }
            g => g,
        }
    }
}
