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

use super::measure::CubeRule;
use crate::config::GenerateConfig;
use crate::design::DesignSpace;
use crate::plan::constraints::Mixture;
use crate::plan::space::{numbers_text, Bounds};
use crate::sequences::Baseline;
use crate::{Error, PointSet};

#[path = "resolve/mod.rs"]
pub(crate) mod resolve;

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
use super::options::ALL;

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
    /// The lattice made for a space's laws: randomised ([`crate::sequences::law_lattice`])
    /// or, `picked`, with its offsets drawn and the best of the draws and the cube's
    /// default set kept ([`crate::sequences::law_lattice_picked_or`]).
    Law {
        /// Points.
        n: usize,
        /// Per coordinate, whether its law is unbounded (scored with the first-order
        /// kernel).
        unbounded: Vec<bool>,
        /// Seed.
        seed: u64,
        /// The deterministic set with picked offsets rather than the randomised one.
        picked: bool,
    },
}

impl Job {
    /// The cube's default configuration for n, s and the seed: what a request with no
    /// other option runs (none if that request is refused).
    pub fn default_config(n: usize, s: usize, seed: u64) -> Option<Box<GenerateConfig>> {
        let mut plain = Request::new(n, s);
        plain.seed = Some(seed.into());
        match plain.resolve().map(|r| r.job) {
            Ok(Job::Run(cfg)) => Some(cfg),
            _ => None,
        }
    }

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
    /// [`cube_rule`](super::measure::cube_rule) decided once for the request.
    pub rule: Option<CubeRule>,
    /// The mixture whose last component is appended to the run's points.
    pub mixture: Option<Mixture>,
    /// How the report's pair figures are computed (exact when `exact` was asked, else
    /// estimated above the exact size), for the run and for a design's figures alike.
    pub sums: crate::quality::metrics::Sums,
    /// The option that made the run the paper's pipeline without `method` naming it (an
    /// option of that pipeline given alone), which the notes before the run point out.
    pub paper_by: Option<super::options::Opt>,
}

impl Resolved {
    /// The request with its design space carried by `rule`: the rule's own construction,
    /// if it has one, makes the unit-cube set in place of the request's run (same n,
    /// dimension and seed), so that the run, its estimate and its report all follow the
    /// rule. The resolution calls it with [`cube_rule`](super::measure::cube_rule)'s answer.
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
        } else if matches!(rule, CubeRule::LawLattice | CubeRule::PickedLattice) {
            let unbounded = self
                .design
                .as_ref()
                .map_or_else(|| vec![false; s], |space| space.unbounded());
            self.job = Job::Law {
                n,
                unbounded,
                seed,
                picked: rule == CubeRule::PickedLattice,
            };
        }
        self.rule = Some(rule);
        self
    }
}

/// The library's own spelling of a parameter: its name as the request writes it.
pub fn plain(name: &str) -> String {
    name.to_string()
}

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
        resolve::Ctx::new(self, spell).resolve()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{EnergyKind, Goal};
    use crate::integrators::Restart;
    use crate::quality::target::Target;

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
