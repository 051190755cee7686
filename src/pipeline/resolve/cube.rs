//! The rules of a run in the unit cube: a baseline construction, the size of the set
//! (n, its dimension from the points given, a set to extend, nested sizes) and whether
//! the integration goal's set is the shifted tent lattice.

use super::Ctx;
use crate::config::{GenerateConfig, Goal};
use crate::goals::integration::lattice::LATTICE_FROM_N;
use crate::pipeline::options::{words, Group, Opt, Value, MAX_COUNT, OPTS};
use crate::pipeline::request::{Job, Resolved};
use crate::sequences::{self, Baseline};
use crate::{Error, PointSet};

/// The points a cube run is given: a set to extend, and a start.
struct Given {
    old: Option<PointSet>,
    init: Option<PointSet>,
}

impl Ctx<'_> {
    /// A baseline asked for by `method`, which takes only n, s, seed and bounds.
    pub(super) fn baseline(&self, seed: u64) -> Result<Option<Resolved>, Error> {
        let Some(method) = self.r.arg(Opt::method) else {
            return Ok(None);
        };
        let word = match self.p.method.value() {
            Ok(w) => w.unwrap_or_default(),
            Err(_) if !matches!(method, crate::pipeline::request::Arg::Text(_)) => {
                return Err(self.bad(Opt::method, &method, "paper or a baseline's name"))
            }
            Err(e) => return Err(e),
        };
        if words::PAPER.contains(&word.as_str()) {
            return Ok(None);
        }
        let baseline = Baseline::parse(&word)?;
        // Every option outside the baseline's own; a design space and its correlation
        // were taken off the request before.
        let refused = OPTS.iter().copied().find(|o| {
            let d = o.declared();
            !d.is(Group::Baseline) && !d.is(Group::Design) && self.given(*o)
        });
        if let Some(o) = refused {
            return Err(self.refuse(
                o,
                format!(
                    "no {} with the baseline {}: a baseline takes only {}, {}, {} and {}",
                    self.name(o),
                    baseline.name(),
                    self.name(Opt::n),
                    self.name(Opt::s),
                    self.name(Opt::seed),
                    self.name(Opt::bounds)
                ),
            ));
        }
        let n = self.n_points()?;
        let s = self
            .p
            .s
            .value()?
            .ok_or_else(|| self.absent(Opt::s, "the dimension (at least 1)"))?;
        sequences::check_size(n, s).map_err(|e| self.too_large(e, n))?;
        Ok(Some(Resolved {
            job: Job::Baseline {
                baseline,
                n,
                s,
                seed,
            },
            bounds: self.bounds(s)?,
            design: None,
            rule: None,
            mixture: None,
            sums: self.sums()?,
            paper_by: None,
        }))
    }

    /// The points given to a cube run, each checked to lie in the unit cube and to have
    /// the run's dimension; the dimension they (or `s`) give.
    fn given_points(&self) -> Result<(Given, Option<usize>), Error> {
        let mut s = self.p.s.value()?;
        let old = self.p.extend.value()?;
        let init = match self.p.init.value() {
            Ok(Some(Value::Points(p))) => Some(p),
            _ => None,
        };
        for (o, p) in [(Opt::extend, &old), (Opt::init, &init)] {
            let Some(p) = p else { continue };
            p.check_unit_cube()
                .map_err(|e| self.refuse(o, format!("points in [0, 1]^s ({e})")))?;
            match s {
                Some(s) if s != p.s() => {
                    return Err(self.refuse(
                        Opt::s,
                        format!(
                            "the dimension of {}, {} (or no {})",
                            self.name(o),
                            p.s(),
                            self.name(Opt::s)
                        ),
                    ))
                }
                _ => s = Some(p.s()),
            }
        }
        Ok((Given { old, init }, s))
    }

    /// Refuses a grown set the run cannot grow: only the integration goal grows one, and
    /// either by extending or by nested sizes.
    fn check_grown(&self, integration: bool, extend: bool) -> Result<(), Error> {
        let nested = self.given(Opt::nested);
        if (extend || nested) && !integration {
            let o = if extend { Opt::extend } else { Opt::nested };
            return Err(self.refuse(
                o,
                format!(
                    "a grown set (not with the paper's pipeline or the space-filling goal) \
                     needs the integration goal (no {} paper, {} space-filling or paper \
                     options)",
                    self.name(Opt::method),
                    self.name(Opt::goal)
                ),
            ));
        }
        if extend && nested {
            return Err(self.refuse(
                Opt::nested,
                format!(
                    "either {} or {} (a nested run builds every stage itself)",
                    self.name(Opt::extend),
                    self.name(Opt::nested)
                ),
            ));
        }
        Ok(())
    }

    /// `n` where it must equal `size`, which `what` gives.
    fn n_equal(&self, size: usize, what: String) -> Result<usize, Error> {
        match self.p.n.value()? {
            Some(n) if n != size => Err(self.refuse(
                Opt::n,
                format!("{what}, {size} (or no {})", self.name(Opt::n)),
            )),
            _ => Ok(size),
        }
    }

    /// The run's number of points: the kept points and those to add, the last nested
    /// size, the number of init points, or n.
    fn cube_n(&self, given: &Given, nested: &[usize]) -> Result<usize, Error> {
        match (&given.old, nested.last(), &given.init) {
            (Some(p), _, _) => {
                let m = self.p.n.value().map_err(|e| to_add(e, Opt::n.declared()))?;
                let m = m.ok_or_else(|| {
                    self.absent(
                        Opt::n,
                        format!(
                            "{} M: the number of points to add to the {} points (at least 1)",
                            self.name(Opt::n),
                            self.name(Opt::extend)
                        ),
                    )
                })?;
                self.grown(m, p.n())
            }
            (None, Some(&last), _) => self.n_equal(last, "the last nested size".into()),
            (None, None, Some(p)) => self.n_equal(p.n(), "the number of init points".into()),
            (None, None, None) => self.n_points(),
        }
    }

    /// The configuration of a run in the unit cube.
    pub(super) fn cube_config(&self, goal: &Goal) -> Result<GenerateConfig, Error> {
        if self.given(Opt::bbox) {
            return Err(self.box_alone());
        }
        let (given, s) = self.given_points()?;
        self.check_grown(goal.is_integration(), given.old.is_some())?;
        let nested = self.p.nested.value()?.unwrap_or_default();
        let n = self.cube_n(&given, &nested)?;
        let s = s.ok_or_else(|| self.absent(Opt::s, "the dimension (at least 1)"))?;
        if n as u64 > MAX_COUNT {
            // Only nested sizes get here unchecked (a count is refused above MAX_COUNT).
            sequences::check_size(n, s).map_err(|e| self.too_large(e, n))?;
            return Err(self.refuse(
                Opt::nested,
                format!(
                    "sizes of at most {MAX_COUNT} points (a set that large does not fit in memory)"
                ),
            ));
        }
        let mut cfg = GenerateConfig::new(n, s);
        self.paper_options(&mut cfg, given.init)?;
        cfg.extend = given.old;
        cfg.nested = nested;
        Ok(cfg)
    }

    /// Whether the integration goal's set is the shifted tent lattice: `target` lattice,
    /// or by default from [`LATTICE_FROM_N`] points on and at s = 1 (any n: the
    /// midpoints), where no target, set to extend, nested sizes or randomisation is given
    /// (`randomize` tent has its own lattice; cells and shift randomise the descent's set).
    pub(super) fn lattice(&self, cfg: &mut GenerateConfig, in_region: bool) -> Result<(), Error> {
        let asked = self.p.target.value()?.as_deref() == Some(words::LATTICE);
        let plain = cfg.extend.is_none() && cfg.nested.is_empty() && cfg.randomize.is_none();
        if asked && (in_region || !plain) {
            return Err(self.refuse(
                Opt::target,
                format!(
                    "lattice alone in the cube (no region, set to extend, nested sizes or \
                     randomisation): it is one set made for its size ({} tent randomises \
                     the lattice made for it)",
                    self.name(Opt::randomize)
                ),
            ));
        }
        cfg.lattice = cfg.goal.is_integration()
            && !in_region
            && (asked
                || (plain && !self.given(Opt::target) && (cfg.n >= LATTICE_FROM_N || cfg.s == 1)));
        Ok(())
    }
}

/// The refusal of the points to add: "at least 1 point to add" in place of the count's
/// own words.
fn to_add(e: Error, n: &crate::pipeline::options::Declared) -> Error {
    match e {
        Error::InvalidArgument {
            name,
            value,
            expected,
        } => Error::invalid(
            name,
            value,
            expected.replacen(&(n.expected)(), "at least 1 point to add", 1),
        ),
        other => other,
    }
}
