//! Which pipeline a run's configuration runs, decided once ([`Pipeline::of`]): the run,
//! its estimate, its notes before it starts and what its report says all dispatch on
//! the one value, so that a new pipeline is one variant whose every arm the compiler
//! asks for.

use crate::config::{EnergyKind, GenerateConfig, Goal};
use crate::design::balance::Finish;
use crate::pipeline::options::Opt;
use crate::quality::target::Target;
use crate::report::GenerateReport;
use crate::solve::checkpoint::CheckpointPlan;
use crate::solve::{Event, Solver};
use crate::Error;

/// A run estimated above this many seconds says so, with its estimate, before it starts
/// (the note of [`crate::pipeline::request::Resolved::notes_as`]).
pub const LONG_RUN_SECONDS: f64 = 5.0;

/// The pipeline that makes a configuration's points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pipeline<'a> {
    /// The configured start, energy, solver and post-steps, in the cube or in a region
    /// (`--method paper`, and every region run but the integration goal's).
    Paper,
    /// The space-filling goal in the cube: the paper's run and Latin hypercubes through
    /// the maximin search. In a region the space-filling goal is the [`Pipeline::Paper`]
    /// run, named as the goal.
    SpaceFilling,
    /// The integration goal's stratified descent on its target in the cube (extended and
    /// nested sets too).
    Descent(&'a Target),
    /// The shifted tent lattice: one construction, no descent.
    Lattice(&'a Target),
    /// One draw of the randomised tent lattice (`--randomize tent`).
    TentDraw(&'a Target),
    /// The integration goal in a region.
    RegionIntegration(&'a Target),
}

impl<'a> Pipeline<'a> {
    /// The pipeline of `cfg`: its goal, and within the integration goal where it runs and
    /// how its set is made.
    pub fn of(cfg: &'a GenerateConfig) -> Pipeline<'a> {
        use crate::post::randomize::Randomize;
        match (&cfg.goal, cfg.region().is_some()) {
            (Goal::Paper, _) | (Goal::SpaceFilling, true) => Pipeline::Paper,
            (Goal::SpaceFilling, false) => Pipeline::SpaceFilling,
            (Goal::Integration(t), true) => Pipeline::RegionIntegration(t),
            (Goal::Integration(t), false) if cfg.randomize == Some(Randomize::Tent) => {
                Pipeline::TentDraw(t)
            }
            (Goal::Integration(t), false) if cfg.lattice => Pipeline::Lattice(t),
            (Goal::Integration(t), false) => Pipeline::Descent(t),
        }
    }

    /// Runs the pipeline on `cfg` (before the randomisation and the report's last
    /// figures, which [`crate::pipeline::generate_with`] adds to every pipeline).
    pub(crate) fn run(
        self,
        cfg: &GenerateConfig,
        checkpoint: Option<&CheckpointPlan>,
        on_event: &mut impl FnMut(Event),
    ) -> Result<GenerateReport, Error> {
        use crate::goals::{integration, paper, region_integration, space_filling};
        match self {
            Pipeline::Paper => paper::paper_run(cfg, checkpoint, on_event),
            Pipeline::SpaceFilling => space_filling::space_filling_run(cfg, on_event),
            Pipeline::Descent(t) => integration::integration_run(cfg, t, on_event),
            Pipeline::Lattice(_) => integration::lattice_run(cfg, on_event),
            Pipeline::TentDraw(t) => integration::tent_lattice_run(cfg, t),
            Pipeline::RegionIntegration(_) => {
                region_integration::region_integration_run(cfg, on_event)
            }
        }
    }

    /// The run's processor seconds on the measuring machine, one thread
    /// ([`crate::pipeline::estimate`]).
    pub(crate) fn estimate(self, cfg: &GenerateConfig) -> f64 {
        use super::estimate as e;
        match self {
            Pipeline::Paper if cfg.region().is_some() => e::region_seconds(cfg),
            Pipeline::Paper => e::paper_seconds(cfg),
            Pipeline::SpaceFilling => e::space_filling_seconds(cfg),
            Pipeline::Descent(t) => e::descent_seconds(cfg, t),
            Pipeline::Lattice(_) => e::lattice_seconds(cfg),
            Pipeline::TentDraw(_) => e::tent_draw_seconds(cfg),
            Pipeline::RegionIntegration(_) => e::region_integration_seconds(cfg.n, cfg.s),
        }
    }

    /// The goal as a report names it; `None` for the paper's pipeline, whose report
    /// shows its energy and solver instead.
    pub fn name(self, cfg: &GenerateConfig) -> Option<String> {
        match self {
            Pipeline::Paper if matches!(cfg.goal, Goal::SpaceFilling) => {
                Some("space-filling".into())
            }
            Pipeline::Paper => None,
            Pipeline::SpaceFilling => Some("space-filling".into()),
            Pipeline::Lattice(_) => Some(
                "integration (the shifted tent lattice: one construction, no target or \
                 descent)"
                    .into(),
            ),
            Pipeline::TentDraw(_) => Some(
                "integration (one draw of the randomised tent lattice: no target; its \
                 figures are the drawn set's)"
                    .into(),
            ),
            Pipeline::Descent(t) | Pipeline::RegionIntegration(t) => {
                Some(format!("integration (target {})", t.name()))
            }
        }
    }

    /// The label of the report's first row: the value the run lowered or raised.
    pub fn value_label(self, energy_name: &str) -> String {
        match self {
            Pipeline::Paper => format!("energy {}", energy_name.split('(').next().unwrap_or("")),
            Pipeline::SpaceFilling => "maximin search: min distance".into(),
            Pipeline::Lattice(_) => "shift criterion e²₂".into(),
            Pipeline::Descent(_) | Pipeline::TentDraw(_) | Pipeline::RegionIntegration(_) => {
                "target (sum of squares)".into()
            }
        }
    }

    /// The integration goal's target, for a pipeline of that goal.
    pub fn target(self) -> Option<&'a Target> {
        match self {
            Pipeline::Paper | Pipeline::SpaceFilling => None,
            Pipeline::Descent(t)
            | Pipeline::Lattice(t)
            | Pipeline::TentDraw(t)
            | Pipeline::RegionIntegration(t) => Some(t),
        }
    }

    /// Whether the set is a draw of the shift-and-tent randomisation: a random set made
    /// for the mean of f, whose figures are the draw's, not a target the run lowered.
    pub fn drawn(self) -> bool {
        matches!(self, Pipeline::TentDraw(_))
    }

    /// How a design space's set is finished after the run: what the pipeline made its
    /// set for.
    pub(crate) fn finish(self, cfg: &GenerateConfig) -> Finish {
        match self {
            Pipeline::Paper if matches!(cfg.goal, Goal::SpaceFilling) => Finish::Spread,
            Pipeline::Paper => Finish::Nothing,
            Pipeline::SpaceFilling => Finish::Spread,
            Pipeline::Descent(_)
            | Pipeline::Lattice(_)
            | Pipeline::TentDraw(_)
            | Pipeline::RegionIntegration(_) => Finish::Discrepancy,
        }
    }

    /// The value the run lowered (or raised), evaluated again on `points` (the randomised
    /// set), and for a target the start's as well, on the report's own sums.
    pub(crate) fn value_on(
        self,
        cfg: &GenerateConfig,
        report: &mut GenerateReport,
    ) -> Result<f64, Error> {
        let points = &report.output.points;
        Ok(match self.target() {
            Some(target) => {
                report.energy.0 = target.value_with(&report.start, cfg.sums);
                target.value_with(points, cfg.sums)
            }
            None if self == Pipeline::SpaceFilling => {
                crate::quality::metrics::min_distance_euclidean(points)
            }
            None => {
                let (problem, _) = crate::plan::problem::build_problem(cfg)?;
                problem.energy().value(points)
            }
        })
    }

    /// What the run will do that its caller may not expect, said before it starts (the
    /// options named by `spell`); the note of a long run is added by
    /// [`crate::pipeline::request::Resolved::notes_as`].
    pub fn notes(self, cfg: &GenerateConfig, spell: &dyn Fn(&str) -> String) -> Vec<String> {
        match self {
            Pipeline::Paper => paper_notes(cfg, spell),
            Pipeline::Lattice(_) => {
                crate::goals::integration::lattice::sharing_warning(cfg.n, cfg.s)
                    .into_iter()
                    .collect()
            }
            Pipeline::SpaceFilling
            | Pipeline::Descent(_)
            | Pipeline::TentDraw(_)
            | Pipeline::RegionIntegration(_) => Vec::new(),
        }
    }

    /// What the long-run note adds to the run's size, and what makes the run cheaper
    /// (options named by `spell`).
    fn cheaper(self, cfg: &GenerateConfig, spell: &dyn Fn(&str) -> String) -> (String, String) {
        match self {
            Pipeline::Paper | Pipeline::SpaceFilling => (
                format!(", up to {} steps", cfg.steps),
                format!(
                    "{} K or a smaller {} make it cheaper",
                    spell(Opt::steps.name()),
                    spell(Opt::n.name())
                ),
            ),
            Pipeline::Descent(_)
            | Pipeline::Lattice(_)
            | Pipeline::TentDraw(_)
            | Pipeline::RegionIntegration(_) => (String::new(), STOPS.into()),
        }
    }
}

/// What stops a long run that no option makes cheaper.
const STOPS: &str = "Ctrl-C stops it";

/// The note of a run estimated at `seconds` when that is above [`LONG_RUN_SECONDS`]: of
/// `n` points in `s` dimensions (and `detail`), with what makes it cheaper (`hint`).
fn long_run_note(seconds: f64, n: usize, s: usize, detail: &str, hint: &str) -> Option<String> {
    (seconds > LONG_RUN_SECONDS).then(|| {
        format!(
            "this run may take about {} (n = {n}, s = {s}{detail}, estimated for this \
             machine's cores); {hint}",
            human_seconds(seconds)
        )
    })
}

/// The long-run note of a job estimated at `seconds`: a configuration's run with its
/// pipeline's hint, or a construction.
pub(crate) fn job_note(
    job: &super::request::Job,
    seconds: f64,
    spell: &dyn Fn(&str) -> String,
) -> Option<String> {
    use super::request::Job;
    let (n, s, (detail, hint)) = match job {
        Job::Run(cfg) => (cfg.n, cfg.s, Pipeline::of(cfg).cheaper(cfg, spell)),
        Job::Baseline { n, s, .. } => (*n, *s, (String::new(), STOPS.into())),
        Job::Law { n, unbounded, .. } => (*n, unbounded.len(), (String::new(), STOPS.into())),
    };
    long_run_note(seconds, n, s, &detail, &hint)
}

/// The paper's pipeline's notes: the DEM on a discrepancy energy, and (q, p) taken from
/// eq. 48 outside the range it was fitted on.
fn paper_notes(cfg: &GenerateConfig, spell: &dyn Fn(&str) -> String) -> Vec<String> {
    let mut notes = Vec::new();
    if matches!(cfg.energy, EnergyKind::Discrepancy(_)) && cfg.solver == Solver::Dem {
        notes.push(format!(
            "the DEM is unstable on a discrepancy energy and returns its lowest early state; \
             {} lbfgs is the solver for discrepancy energies",
            spell(Opt::integrator.name())
        ));
    }
    let fit = crate::energies::paper_qp(cfg.n, cfg.s);
    if cfg.region().is_none()
        && cfg.energy == EnergyKind::Uqp
        && (cfg.q.is_none() || cfg.p.is_none())
        && !fit.in_fitted_range
    {
        notes.push(format!(
            "(n, s) = ({}, {}) lies outside the range eq. 48 was fitted on (1 ≤ s ≤ 20, \
             s ≤ n ≤ 1500): q and p are extrapolated{}",
            cfg.n,
            cfg.s,
            if fit.q != fit.raw_q || fit.p != fit.raw_p {
                " and clamped into [0.05, 1]"
            } else {
                ""
            }
        ));
    }
    notes
}

/// "12.3 s", "4 min 05 s" or "1 h 02 min".
pub fn human_seconds(t: f64) -> String {
    if t < 60.0 {
        format!("{t:.1} s")
    } else if t < 3600.0 {
        format!("{} min {:02} s", (t / 60.0) as u64, (t % 60.0) as u64)
    } else {
        format!(
            "{} h {:02} min",
            (t / 3600.0) as u64,
            ((t % 3600.0) / 60.0) as u64
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::request::{Arg, Job};
    use crate::Request;

    /// A request's size and its options by name.
    type Cell = (usize, usize, &'static [(&'static str, &'static str)]);

    /// A request of `n` points in `s` dimensions with `options` set by name.
    fn resolved(
        n: usize,
        s: usize,
        options: &[(&str, &str)],
    ) -> crate::pipeline::request::Resolved {
        let mut r = Request::new(n, s);
        for (name, value) in options {
            r.set(name, Arg::from(*value)).unwrap();
        }
        r.resolve().unwrap()
    }

    fn config(n: usize, s: usize, options: &[(&str, &str)]) -> GenerateConfig {
        match resolved(n, s, options).job {
            Job::Run(cfg) => *cfg,
            other => panic!("{options:?} resolves to {other:?}, not a run"),
        }
    }

    /// The index of each pipeline; exhaustive, so that a new one is given a request
    /// below.
    fn index(p: Pipeline) -> usize {
        match p {
            Pipeline::Paper => 0,
            Pipeline::SpaceFilling => 1,
            Pipeline::Descent(_) => 2,
            Pipeline::Lattice(_) => 3,
            Pipeline::TentDraw(_) => 4,
            Pipeline::RegionIntegration(_) => 5,
        }
    }

    #[test]
    fn every_pipeline_is_reached_by_a_request_and_makes_its_set() {
        let requests: [Cell; 7] = [
            (24, 2, &[("method", "paper")]),
            (24, 2, &[("goal", "space-filling")]),
            (24, 2, &[]),
            (24, 2, &[("target", "lattice")]),
            (24, 2, &[("randomize", "tent")]),
            (24, 2, &[("shape", "ball:1"), ("goal", "integration")]),
            (24, 2, &[("shape", "ball:1"), ("goal", "space-filling")]),
        ];
        let mut seen = [false; 6];
        for (n, s, options) in requests {
            let cfg = config(n, s, options);
            let pipeline = Pipeline::of(&cfg);
            seen[index(pipeline)] = true;
            let report = crate::pipeline::run_config(&cfg, |_| {}).unwrap();
            assert_eq!(report.output.points.n(), n, "{options:?}");
            // Only the paper's pipeline reports its solver in place of a goal's name; the
            // space-filling goal in a region is the paper's run under the goal's name.
            assert_eq!(
                pipeline.name(&cfg).is_none(),
                report.solver().is_some()
                    && options != [("shape", "ball:1"), ("goal", "space-filling")],
                "{options:?}"
            );
            assert!(pipeline.estimate(&cfg) > 0.0, "{options:?}");
        }
        assert!(
            seen.iter().all(|&x| x),
            "pipelines no request reaches: {seen:?}"
        );
    }

    #[test]
    fn a_run_estimated_above_five_seconds_says_so_with_its_estimate_before_it_starts() {
        // One request per pipeline, each above the threshold, with a short one beside it.
        let long: [Cell; 7] = [
            (2048, 5, &[("method", "paper")]),
            (1024, 5, &[("goal", "space-filling")]),
            (16_000, 5, &[("target", "blend")]),
            (600, 20_000, &[]),
            (50_000, 50, &[("randomize", "tent")]),
            (20_000, 8, &[("shape", "ball:1"), ("goal", "integration")]),
            (100_000, 10, &[("method", "lhs-maximin")]),
        ];
        for (n, s, options) in long {
            let r = resolved(n, s, options);
            let seconds = r.estimate_seconds();
            let notes = r.notes_as(&|p| format!("<{p}>"));
            let line = notes
                .iter()
                .find(|t| t.starts_with("this run may take about"));
            assert!(seconds > LONG_RUN_SECONDS, "{options:?}: {seconds} s");
            let line = line.unwrap_or_else(|| panic!("{options:?}: {seconds} s, {notes:?}"));
            assert!(line.contains(&human_seconds(seconds)), "{line}");
            assert!(line.contains(&format!("n = {n}, s = {s}")), "{line}");
        }
        // The paper's pipeline names the options that shorten it, as the front end spells
        // them.
        let paper = resolved(2048, 5, &[("method", "paper")]).notes_as(&|p| format!("<{p}>"));
        assert!(
            paper
                .iter()
                .any(|t| t.contains("<steps> K or a smaller <n>")),
            "{paper:?}"
        );
        for (n, s, options) in [
            (64, 3, &[][..]),
            (100, 2, &[("method", "paper"), ("steps", "50")][..]),
        ] {
            let r = resolved(n, s, options);
            assert!(r.estimate_seconds() < LONG_RUN_SECONDS);
            assert!(
                r.notes().iter().all(|t| !t.contains("may take")),
                "{options:?}: {:?}",
                r.notes()
            );
        }
    }

    #[test]
    fn an_option_of_the_paper_s_pipeline_given_alone_says_it_selects_that_pipeline() {
        let spell = |p: &str| format!("--{p}");
        let selects = |options: &[(&str, &str)]| {
            let r = resolved(600, 2, options);
            let paper = matches!(&r.job, Job::Run(cfg) if Pipeline::of(cfg) == Pipeline::Paper);
            let note = r
                .notes_as(&spell)
                .into_iter()
                .find(|t| t.contains("option of the paper's pipeline"));
            (paper, note)
        };
        let (paper, note) = selects(&[("steps", "50")]);
        assert!(paper);
        let note = note.expect("a note for --steps alone");
        assert!(
            note.starts_with("--steps is an option") && note.contains("--method paper"),
            "{note}"
        );
        // Named by the method, or the default run: nothing to point out.
        assert_eq!(
            selects(&[("method", "paper"), ("steps", "50")]),
            (true, None)
        );
        assert_eq!(selects(&[]), (false, None));
    }

    #[test]
    fn the_threshold_is_the_boundary_of_the_note() {
        let note = |t: f64| long_run_note(t, 10, 2, "", STOPS);
        assert!(note(LONG_RUN_SECONDS).is_none());
        assert_eq!(
            note(LONG_RUN_SECONDS + 0.5).as_deref(),
            Some("this run may take about 5.5 s (n = 10, s = 2, estimated for this machine's cores); Ctrl-C stops it")
        );
        assert_eq!(human_seconds(125.0), "2 min 05 s");
        assert_eq!(human_seconds(3720.0), "1 h 02 min");
    }

    #[test]
    fn the_paper_pipeline_notes_the_dem_on_a_discrepancy_energy_and_eq_48_outside_its_range() {
        let spell = |p: &str| format!("--{p}");
        let cfg = config(40, 2, &[("method", "paper"), ("energy", "md")]);
        let notes = Pipeline::of(&cfg).notes(&cfg, &spell);
        assert!(notes[0].contains("--integrator lbfgs"), "{notes:?}");
        let cfg = config(40, 30, &[("method", "paper")]);
        let notes = Pipeline::of(&cfg).notes(&cfg, &spell);
        assert!(
            notes[0].contains("(n, s) = (40, 30) lies outside"),
            "{notes:?}"
        );
        let cfg = config(40, 3, &[("method", "paper")]);
        assert!(Pipeline::of(&cfg).notes(&cfg, &spell).is_empty());
    }
}
