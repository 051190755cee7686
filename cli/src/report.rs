//! Reports: the tables and JSON a run or `eval` prints, and the point-file headers.

use super::*;
use serde::Serialize;
use std::collections::BTreeMap;
use stillpoint::integrators::{RunOutput, StopReason};
use stillpoint::pipeline::Pipeline;
use stillpoint::post::shift::ShiftOutcome;
use stillpoint::quality::region::RegionMetrics;
use stillpoint::report::Stage;

/// The key under which the DEM reports the κ it ran with (its own choice under `auto`).
const KAPPA: &str = "kappa";

pub(crate) fn metrics_json(m: &Metrics) -> Value {
    serde_json::to_value(m).unwrap_or(Value::Null)
}

/// A typed report as the JSON value the command line writes (its keys in order: the
/// writer sorts them, so a field's place in its struct does not change the bytes).
fn as_json(report: &impl Serialize) -> Result<Value> {
    Ok(serde_json::to_value(report)?)
}

/// What made a report: the package and its version.
fn generator() -> String {
    format!("stillpoint {}", env!("CARGO_PKG_VERSION"))
}

/// The largest step the solver reached.
fn last_step(output: &RunOutput) -> usize {
    output.trajectory.iter().map(|t| t.step).max().unwrap_or(0)
}

/// The facts the solver reported (κ, restarts, evaluations …), by name; a value that is
/// not finite is written as null.
fn facts(r: &GenerateReport) -> BTreeMap<&str, f64> {
    r.output
        .info
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .collect()
}

/// Where eq. 48's (q, p) came from.
#[derive(Serialize)]
struct Eq48 {
    used: bool,
    in_fitted_range: bool,
    clamped: bool,
}

/// The polish: the squared discrepancy before and after, and its L-BFGS iterations.
#[derive(Serialize)]
struct Polish {
    before: f64,
    after: f64,
    iterations: usize,
}

/// The `--json` report of a cube run of the paper's pipeline.
#[derive(Serialize)]
struct PaperJson<'a> {
    generator: String,
    n: usize,
    s: usize,
    energy: &'a str,
    q: &'a str,
    p: f64,
    precision: &'static str,
    init: &'static str,
    seed: u64,
    steps: usize,
    stop: StopReason,
    kappa: Option<f64>,
    restarts: Option<f64>,
    eq48: Eq48,
    #[serde(skip_serializing_if = "<[Stage]>::is_empty")]
    stages: &'a [Stage],
    run: BTreeMap<&'a str, f64>,
    energy_start: f64,
    energy_result: f64,
    metrics_start: &'a Metrics,
    metrics_result: &'a Metrics,
    shift: &'a Option<ShiftOutcome>,
    polish: Option<Polish>,
    seconds: f64,
}

/// A goal run's totals over its descents.
#[derive(Serialize)]
struct Totals {
    exchanges_accepted: usize,
    lbfgs_iterations: usize,
    descents_skipped: Vec<String>,
}

/// One phase of a run and its wall seconds.
#[derive(Serialize)]
struct Timing<'a> {
    phase: &'a str,
    seconds: f64,
}

/// The `--json` report of a goal run in the cube.
#[derive(Serialize)]
struct GoalJson<'a> {
    generator: String,
    n: usize,
    s: usize,
    seed: u64,
    goal: Option<String>,
    energy: &'a str,
    energy_start: f64,
    energy_result: f64,
    stages: &'a [Stage],
    totals: Totals,
    metrics_start: &'a Metrics,
    metrics_result: &'a Metrics,
    seconds: f64,
    timings: Vec<Timing<'a>>,
}

/// The `--json` report of a cube run: settings, run facts, energies and metrics of the
/// start and the result, the shift and polish, and the wall time; for a goal run, its
/// stages in place of the paper's solver facts.
pub(crate) fn report_json(r: &GenerateReport, cfg: &GenerateConfig) -> Result<Value> {
    let (m0, m1) = r.cube_metrics()?;
    let (Some(choice), Some(solver)) = (&r.choice, r.solver()) else {
        return as_json(&goal_json(r, cfg, m0, m1));
    };
    as_json(&PaperJson {
        generator: generator(),
        n: cfg.n,
        s: cfg.s,
        energy: &r.energy_name,
        q: &choice.q,
        p: choice.p,
        precision: cfg.precision.label(),
        init: match &cfg.init {
            Init::Halton => "halton",
            Init::Random => "random",
            Init::Points(_) => "file",
        },
        seed: cfg.seed,
        steps: last_step(solver),
        stop: solver.stop,
        kappa: solver.info(KAPPA),
        restarts: solver.info("restarts"),
        eq48: Eq48 {
            used: choice.from_eq48,
            in_fitted_range: choice.eq48_in_fitted_range,
            clamped: choice.eq48_clamped,
        },
        stages: &r.stages,
        run: facts(r),
        energy_start: r.energy.0,
        energy_result: r.energy.1,
        metrics_start: m0,
        metrics_result: m1,
        shift: &r.shift,
        polish: r.polish.map(|(before, after, iterations)| Polish {
            before,
            after,
            iterations,
        }),
        seconds: r.seconds,
    })
}

/// The `--json` report of a goal run: its goal, its stages as data (each start's
/// candidates, each descent's rounds, the searches), the value it lowered or raised,
/// and the metrics of the start and the result.
fn goal_json<'a>(
    r: &'a GenerateReport,
    cfg: &GenerateConfig,
    m0: &'a Metrics,
    m1: &'a Metrics,
) -> GoalJson<'a> {
    let mut totals = Totals {
        exchanges_accepted: 0,
        lbfgs_iterations: 0,
        descents_skipped: Vec::new(),
    };
    for st in &r.stages {
        if let Stage::Descent(d) = st {
            totals.exchanges_accepted += d.accepted();
            totals.lbfgs_iterations += d.lbfgs_iterations();
            totals.descents_skipped.extend(d.skipped.clone());
        }
    }
    GoalJson {
        generator: generator(),
        n: cfg.n,
        s: cfg.s,
        seed: cfg.seed,
        goal: goal_name(cfg),
        energy: &r.energy_name,
        energy_start: r.energy.0,
        energy_result: r.energy.1,
        stages: &r.stages,
        totals,
        metrics_start: m0,
        metrics_result: m1,
        seconds: r.seconds,
        timings: r
            .timings
            .iter()
            .map(|(phase, seconds)| Timing {
                phase,
                seconds: *seconds,
            })
            .collect(),
    }
}

/// A DEM setting as the command line takes it: a number or a word (`auto`, `off`).
#[derive(Serialize)]
#[serde(untagged)]
enum Setting {
    Fixed(f64),
    Word(&'static str),
}

/// The settings of a DEM as the command line writes them.
#[derive(Serialize)]
struct DemSettings {
    steps: usize,
    kappa: Setting,
    restart: Setting,
    tolerance: f64,
}

/// The settings of a DEM as the command line writes them.
fn dem_settings(dem: &stillpoint::integrators::Dem, steps: usize) -> DemSettings {
    use stillpoint::integrators::{Kappa, Restart};
    DemSettings {
        steps,
        kappa: match dem.kappa {
            Kappa::Fixed(k) => Setting::Fixed(k),
            Kappa::Auto { .. } => Setting::Word("auto"),
        },
        restart: match dem.restart {
            Restart::Auto => Setting::Word("auto"),
            Restart::Off => Setting::Word("off"),
            Restart::Threshold(e) => Setting::Fixed(e),
        },
        tolerance: dem.tolerance,
    }
}

/// A point file's header: what made it and what came out.
#[derive(Serialize)]
struct FileHeader<'a> {
    generator: &'static str,
    version: &'static str,
    seed: u64,
    parameters: Parameters<'a>,
    run: RunFacts,
    metrics: Value,
}

/// The parameters of a run as its file header records them.
#[derive(Serialize)]
struct Parameters<'a> {
    n: usize,
    s: usize,
    #[serde(flatten)]
    place: Option<Place<'a>>,
    #[serde(flatten)]
    how: How<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mixture: Option<MixtureFigures>,
    #[serde(skip_serializing_if = "Option::is_none")]
    bounds: Option<String>,
}

/// A region run's region: as the command line named it, and as the library holds it.
#[derive(Serialize)]
struct Place<'a> {
    region: &'a Value,
    domain: String,
}

/// A mixture's components, and where its figures live.
#[derive(Serialize)]
struct MixtureFigures {
    components: usize,
    figures_in: String,
}

/// What ran: a goal (its settings are its goal; the paper's it does not use would only
/// mislead), or the paper's pipeline with its settings.
#[derive(Serialize)]
#[serde(untagged)]
enum How<'a> {
    Goal {
        goal: String,
        randomize: Option<String>,
        stages: &'a [Stage],
        /// The lengths of the prefixes made for their size, old and new.
        sizes: Vec<usize>,
    },
    Paper {
        energy: &'a str,
        #[serde(flatten)]
        cube: Option<CubeSettings>,
        init: String,
        integrator: &'static str,
        #[serde(flatten)]
        dem: DemSettings,
        /// The header reproduces its file: a randomised paper run says so.
        #[serde(skip_serializing_if = "Option::is_none")]
        randomize: Option<&'static str>,
    },
}

/// The paper's settings that only the cube has.
#[derive(Serialize)]
struct CubeSettings {
    q: Option<String>,
    p: Option<f64>,
    precision: &'static str,
    pq_from_eq48: Option<bool>,
    shifts: usize,
    polish: Option<String>,
}

/// The solver's facts in a header (none for a goal, whose solver runs are its stages).
#[derive(Serialize)]
struct RunFacts {
    #[serde(flatten)]
    solver: Option<SolverFacts>,
    kernel: &'static str,
}

/// The paper's solver run in a header.
#[derive(Serialize)]
struct SolverFacts {
    steps: Option<usize>,
    stop: Option<StopReason>,
    kappa: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    restarts: Option<Option<f64>>,
}

/// The header of a generated point file, in the cube or a region: what made it
/// (generator, version, seed, every parameter) and what came out (run facts and the
/// result's quality). Nothing in it depends on the clock or the thread count, so the file
/// is the same bytes every time. `given` is how the command line named the region; a
/// mixture's header has its S components and says where its figures live.
pub(crate) fn file_header(
    r: &GenerateReport,
    cfg: &GenerateConfig,
    given: &Value,
    resolved: &Resolved,
) -> Result<Value> {
    let init = match &cfg.init {
        Init::Halton => "halton".to_string(),
        Init::Random => "random".to_string(),
        Init::Points(p) => format!("file: {}", points_fingerprint(p)),
    };
    let integrator = match cfg.solver {
        Solver::Dem => "dem",
        Solver::Lbfgs => "lbfgs",
    };
    let solver = r.solver();
    let info = |k: &str| solver.and_then(|o| o.info(k));
    let place = cfg.region().map(|domain| Place {
        region: given,
        domain: format!("{domain:?}"),
    });
    let metrics = match cfg.region() {
        None => metrics_json(r.cube_metrics()?.1),
        Some(_) => serde_json::to_value(r.region_metrics()?.1).unwrap_or(Value::Null),
    };
    let goal = goal_name(cfg);
    let how = match &goal {
        Some(goal) => How::Goal {
            goal: goal.clone(),
            randomize: cfg.randomize.map(|r| r.name().to_string()),
            stages: &r.stages,
            sizes: match (&cfg.extend, cfg.nested.is_empty()) {
                (Some(old), _) => vec![old.n(), cfg.n],
                (None, false) => cfg.nested.clone(),
                (None, true) => vec![cfg.n],
            },
        },
        None => How::Paper {
            energy: &r.energy_name,
            cube: place.is_none().then(|| CubeSettings {
                q: r.choice.as_ref().map(|c| c.q.clone()),
                p: r.choice.as_ref().map(|c| c.p),
                precision: cfg.precision.label(),
                pq_from_eq48: r.choice.as_ref().map(|c| c.from_eq48),
                shifts: cfg.shifts,
                polish: cfg.polish.map(|k| format!("{k:?}")),
            }),
            init,
            integrator,
            dem: dem_settings(&cfg.dem, cfg.steps),
            randomize: cfg.randomize.map(|k| k.name()),
        },
    };
    let solver_facts = goal.is_none().then(|| SolverFacts {
        steps: solver.map(last_step),
        stop: solver.map(|o| o.stop),
        kappa: info(KAPPA),
        restarts: place.is_none().then(|| info("restarts")),
    });
    let components = resolved.mixture.as_ref().map(|m| m.components());
    as_json(&FileHeader {
        generator: "stillpoint generate",
        version: env!("CARGO_PKG_VERSION"),
        seed: cfg.seed,
        parameters: Parameters {
            n: cfg.n,
            s: components.unwrap_or(cfg.s),
            place,
            how,
            mixture: components.map(|components| MixtureFigures {
                components,
                figures_in: mixture_figures(components),
            }),
            bounds: resolved.bounds.as_ref().map(|b| b.text()),
        },
        run: RunFacts {
            solver: solver_facts,
            kernel: stillpoint::energies::pairs::vector_path(),
        },
        metrics,
    })
}

/// The goal of a goal run, as the report names it; `None` for the paper's pipeline.
pub(crate) fn goal_name(cfg: &GenerateConfig) -> Option<String> {
    Pipeline::of(cfg).name(cfg)
}

/// What the solver did, in one line: the DEM's steps, κ and restarts, or L-BFGS's
/// iterations and restarts.
fn solver_line(output: &stillpoint::integrators::RunOutput) -> String {
    let r = output;
    let steps = r.trajectory.iter().map(|x| x.step).max().unwrap_or(0);
    let restarts = r.info("restarts").unwrap_or(0.0);
    match r.info(KAPPA) {
        Some(kappa) => format!(
            "DEM: {steps} steps ({:?}), κ = {kappa} after {} trial(s){}, {restarts} restart(s)",
            r.stop,
            r.info("kappa_trials").unwrap_or(0.0),
            if r.info("kappa_trial_failed") == Some(1.0) {
                " (the energy never fell steadily: κ capped)"
            } else {
                ""
            },
        ),
        None => format!(
            "L-BFGS: {steps} iterations ({:?}), {restarts} restart(s)",
            r.stop
        ),
    }
}

pub(crate) fn report_table(
    r: &GenerateReport,
    cfg: &GenerateConfig,
    out: Option<&PathBuf>,
) -> Result<String> {
    let (m0, m1) = r.cube_metrics()?;
    let init = match &cfg.init {
        Init::Halton => "plain Halton (indices 1..n)".to_string(),
        Init::Random => format!("random (seed {})", cfg.seed),
        Init::Points(_) => "points from file".to_string(),
    };
    let mut t = String::new();
    if let Some(goal) = goal_name(cfg) {
        t += &format!("stillpoint: n = {}, s = {}, goal {goal}\n", cfg.n, cfg.s);
        for line in &r.stages {
            t += &format!("  {line}\n");
        }
        t += "\n";
    } else {
        t += &format!(
            "stillpoint: n = {}, s = {}, {} from {}\n",
            cfg.n, cfg.s, r.energy_name, init
        );
    }
    if let Some(choice) = r.choice.as_ref().filter(|c| c.from_eq48) {
        t += &format!(
            "  (q, p) from eq. 48{}{}\n",
            if choice.eq48_in_fitted_range {
                ""
            } else {
                "; (n, s) is outside the fitted range 1 ≤ s ≤ 20, s ≤ n ≤ 1500"
            },
            if choice.eq48_clamped {
                "; clamped into [0.05, 1]"
            } else {
                ""
            }
        );
    }
    if let Some(solver) = r.solver() {
        t += &format!("  {}\n", solver_line(solver));
        // A randomised paper run says so after its solver.
        for line in &r.stages {
            t += &format!("  {line}\n");
        }
        t += "\n";
    }
    t += &figures_table(r, cfg, m0, m1);
    if let Some(e) = &m1.estimate {
        let descended = r.stages.iter().any(|st| matches!(st, Stage::Descent(_)));
        t += &estimate_lines(m1, e, cfg.sums.estimate_above, descended);
    }
    if let Some(sh) = &r.shift {
        t += &format!(
            "\n  shift selection: D_MD {:.6} after the {} → {:.6} with shift ({}) ({} evaluations)\n",
            sh.modified_l2_before,
            match cfg.solver {
                Solver::Dem => "DEM",
                Solver::Lbfgs => "L-BFGS run",
            },
            sh.modified_l2_after,
            sh.shift.iter().map(|c| format!("{c:.4}")).collect::<Vec<_>>().join(", "),
            sh.evaluations
        );
    }
    if goal_name(cfg).is_some() && cfg.region().is_none() {
        let stratified = stillpoint::quality::stratification::is_stratified(&r.output.points);
        t += &format!(
            "\n  every coordinate stratified (one point in each [k/n, (k+1)/n)): {}\n",
            if stratified { "yes" } else { "no" }
        );
    }
    if let Some((a, b, it)) = r.polish {
        t +=
            &format!("  polish: squared discrepancy {a:.6e} → {b:.6e} in {it} L-BFGS iterations\n");
    }
    let phases: Vec<String> = r
        .timings
        .iter()
        .map(|(k, v)| format!("{k} {v:.2} s"))
        .collect();
    let phases = if phases.is_empty() {
        String::new()
    } else {
        format!(" ({})", phases.join(", "))
    };
    t += &format!(
        "\n  time {:.2} s{phases}; points written to {}\n",
        r.seconds,
        out.map(|p| p.display().to_string())
            .unwrap_or_else(|| "standard output".into())
    );
    Ok(t)
}

/// The header of a table of figures at the start, the result and their change.
fn change_header() -> String {
    format!(
        "  {:<36} {:>14} {:>14} {:>9}\n",
        "", "start", "result", "change"
    )
}

/// The start/result table of a run: its energy or target, the discrepancies, minimum
/// distances and mean gap, each with its change.
fn figures_table(r: &GenerateReport, cfg: &GenerateConfig, m0: &Metrics, m1: &Metrics) -> String {
    let mut t = change_header();
    let pipeline = Pipeline::of(cfg);
    let energy_label = pipeline.value_label(&r.energy_name);
    // A construction with no start of its own (the lattice) has one set: its figures are
    // shown once, the start column only for the value it chose by. A randomised draw has
    // no target to show: only its figures.
    let drawn = pipeline.drawn();
    let same = drawn || r.start == r.output.points;
    let row = |name: &str, a: f64, b: f64, sci: bool| -> String {
        // A value the run could not compute (NaN: the note below the table says why)
        // reads as such, not as a number.
        let f = |v: f64| {
            if v.is_nan() {
                "not computed".to_string()
            } else if v.is_infinite() {
                // A single point has no pair: no distance, no pair energy.
                "none".to_string()
            } else if sci || v.abs() >= 1e12 {
                format!("{v:.6e}")
            } else {
                format!("{v:.6}")
            }
        };
        let change = if a != 0.0 && a.is_finite() && b.is_finite() {
            format!("{:+.1}%", 100.0 * (b - a) / a)
        } else {
            "-".to_string()
        };
        if same && !name.starts_with(energy_label.as_str()) {
            return format!("  {:<36} {:>14} {:>14}\n", name, "", f(b));
        }
        format!("  {:<36} {:>14} {:>14} {:>9}\n", name, f(a), f(b), change)
    };
    if drawn {
        t = format!("  {:<36} {:>14} {:>14}\n", "", "", "drawn set");
    } else if m1.estimate.is_some() && matches!(pipeline, Pipeline::Descent(_)) {
        // The target from the same random pairs: a sum of squares at or below 0 is one
        // the sample cannot resolve.
        let shown = |v: f64| {
            if v > 0.0 {
                format!("≈ {v:.6e}")
            } else {
                "unresolved".to_string()
            }
        };
        t += &format!(
            "  {:<36} {:>14} {:>14} {:>9}\n",
            energy_label,
            shown(r.energy.0),
            shown(r.energy.1),
            "-"
        );
    } else if r.output.points.n() < 2 && pipeline.target().is_none() {
        // An energy of pairs is 0 for a single point, which says nothing about it.
        t += &row(&energy_label, f64::INFINITY, f64::INFINITY, true);
    } else {
        t += &row(&energy_label, r.energy.0, r.energy.1, true);
    }
    // An estimated discrepancy is shown as such, and one within two standard errors of 0
    // as unresolved: printing its value would claim a set more even than anyone measured.
    let est = |m: &Metrics, k: usize, v: f64| -> (String, bool) {
        match &m.estimate {
            // Past the dimension where the closed form fits a float (the notes say so).
            None if !v.is_finite() => ("beyond f64".to_string(), true),
            None if v.abs() >= 1e12 => (format!("{v:.6e}"), true),
            None => (format!("{v:.6}"), true),
            Some(e) if v > 2.0 * e.standard_errors[k] => (format!("≈ {v:.6}"), true),
            Some(_) => ("unresolved".to_string(), false),
        }
    };
    let discrepancies = [
        ("star L2 discrepancy D_L2* (root)", m0.star_l2, m1.star_l2),
        (
            "modified L2 discrepancy D_MD (root)",
            m0.modified_l2,
            m1.modified_l2,
        ),
        (
            "centred L2 discrepancy (root)",
            m0.centered_l2,
            m1.centered_l2,
        ),
        (
            "wrap-around L2 discrepancy (root)",
            m0.wrap_around_l2,
            m1.wrap_around_l2,
        ),
    ];
    for (k, (name, a, b)) in discrepancies.into_iter().enumerate() {
        let ((sa, ra), (sb, rb)) = (est(m0, k, a), est(m1, k, b));
        let change = if ra && rb && a != 0.0 && a.is_finite() && b.is_finite() {
            format!("{:+.1}%", 100.0 * (b - a) / a)
        } else {
            "-".to_string()
        };
        if same {
            t += &format!("  {name:<36} {:>14} {sb:>14}\n", "");
        } else {
            t += &format!("  {name:<36} {sa:>14} {sb:>14} {change:>9}\n");
        }
    }
    t += &row(
        "minimum distance (Euclidean)",
        m0.min_distance,
        m1.min_distance,
        false,
    );
    t += &row(
        "minimum distance (periodic)",
        m0.min_distance_periodic,
        m1.min_distance_periodic,
        false,
    );
    let gap = |p: &PointSet| p.mean().iter().map(|v| (v - 0.5).abs()).fold(0.0, f64::max);
    t += &row(
        "mean gap max_k |mean_k − 0.5|",
        gap(&r.start),
        gap(&r.output.points),
        false,
    );
    t
}

/// What an estimate of a report's metrics rests on, with each discrepancy's standard
/// error and, when the distances could not be proven, why they are missing.
fn estimate_lines(
    m: &Metrics,
    e: &stillpoint::quality::metrics::Estimate,
    above: usize,
    descended: bool,
) -> String {
    let values = [
        ("D_L2*", m.star_l2),
        ("D_MD", m.modified_l2),
        ("CD", m.centered_l2),
        ("WD", m.wrap_around_l2),
        ("mixture", m.mixture),
    ];
    let each: Vec<String> = values
        .iter()
        .zip(e.standard_errors)
        .map(|((name, v), se)| format!("{name} ≈ {v:.6} ± {se:.6}"))
        .collect();
    let mut t = format!(
        "\n  above n = {above} the discrepancies and the target are estimated from {} random \
         pairs (one standard error, the roots' by the delta method); the result's: {}; an \
         error above the value means the set is more even than the sample can resolve, and \
         the start's and the result's estimates differ by that error, not by what the run \
         changed{}; --exact for the exact sums (O(n² s))\n",
        e.pairs,
        each.join(", "),
        if descended {
            " (the descent line states the exact changes it made)"
        } else {
            ""
        }
    );
    if !e.min_distances_exact {
        t += &format!(
            "  minimum distances not computed: {}; --exact computes them\n",
            e.min_distances_why()
        );
    }
    t
}

pub(crate) fn eval_table(file: &std::path::Path, points: &PointSet, v: &Value) -> String {
    let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    // A value JSON holds as null is shown by its note, never as NaN.
    let show = |k: &str, digits: usize, sci: bool| -> String {
        let se = v["estimate"]["standard_errors"][k].as_f64();
        match (v[k].as_f64(), v["notes"][k].as_str()) {
            (Some(x), _) if se.is_some() => {
                format!("≈ {x:.digits$} ± {:.digits$}", se.unwrap_or(f64::NAN))
            }
            (Some(x), _) if sci => format!("{x:.digits$e}"),
            (Some(x), _) => format!("{x:.digits$}"),
            (None, Some(note)) => note.to_string(),
            (None, None) => "-".to_string(),
        }
    };
    let mut t = format!(
        "{}: n = {}, s = {}\n",
        file.display(),
        points.n(),
        points.s()
    );
    let rows = [
        ("star L2 discrepancy D_L2* (root)", "star_l2"),
        ("modified L2 discrepancy D_MD (root)", "modified_l2"),
        ("centred L2 discrepancy (root)", "centered_l2"),
        ("wrap-around L2 discrepancy (root)", "wrap_around_l2"),
        ("mixture discrepancy (root)", "mixture"),
        ("star discrepancy D* (L∞, exact)", "star_linf"),
        ("worst 1-D projection D* (L∞)", "worst_1d_star_linf"),
        ("worst 2-D projection D* (L∞)", "worst_2d_star_linf"),
        ("minimum distance (Euclidean)", "min_distance"),
        ("minimum distance (periodic)", "min_distance_periodic"),
        ("mean gap max_k |mean_k − 0.5|", "mean_gap"),
    ];
    t += &format!(
        "  {:<40} {}\n",
        "every coordinate stratified",
        if v["stratified"].as_bool() == Some(true) {
            "yes (one point in each [k/n, (k+1)/n))"
        } else {
            "no"
        }
    );
    for (name, key) in rows {
        t += &format!("  {name:<40} {}\n", show(key, 6, false));
    }
    t += &format!(
        "  {:<40} {}   (q = {:.4}, p = {:.4} from eq. 48)\n",
        "energy U_{q,p}",
        show("energy_uqp", 6, true),
        num("energy_uqp_q"),
        num("energy_uqp_p")
    );
    t += &format!(
        "  {:<40} {}\n",
        "energy U_{E,∞} = 1/d_min",
        show("energy_e_inf", 6, false)
    );
    if let Some(pairs) = v["estimate"]["pairs"].as_u64() {
        t += &format!(
            "\n  ≈: estimated, ± one standard error: the pair sums from {pairs} random pairs \
             (above n = {}; the roots' errors by the delta method); --exact for the exact sums\n",
            v["estimate"]["above_n"]
        );
    }
    t
}

/// `eval A B C`: one column per file, one row per figure, the best value of each row
/// marked with `*` (lowest for discrepancies and energies, highest for distances) among
/// the files of the same n and s: a figure of 100 points is not comparable with one of
/// 1 000, so sets of other sizes are never ranked against each other.
pub(crate) fn eval_comparison(files: &[(PathBuf, PointSet, Value)]) -> String {
    let names: Vec<String> = files
        .iter()
        .map(|(f, _, _)| {
            let name = f
                .file_name()
                .map(|x| x.to_string_lossy().into_owned())
                .unwrap_or_else(|| f.display().to_string());
            if name.chars().count() > 14 {
                format!(
                    "…{}",
                    name.chars()
                        .rev()
                        .take(13)
                        .collect::<Vec<_>>()
                        .into_iter()
                        .rev()
                        .collect::<String>()
                )
            } else {
                name
            }
        })
        .collect();
    let mut t = String::new();
    for ((f, p, _), name) in files.iter().zip(&names) {
        t += &format!("{name}: {} (n = {}, s = {})\n", f.display(), p.n(), p.s());
    }
    t += &format!("\n  {:<36}", "");
    for name in &names {
        t += &format!(" {name:>15}");
    }
    t += "\n";
    let rows: [(&str, &str, bool); 12] = [
        ("star L2 discrepancy D_L2* (root)", "star_l2", false),
        ("modified L2 discrepancy D_MD (root)", "modified_l2", false),
        ("centred L2 discrepancy (root)", "centered_l2", false),
        ("wrap-around L2 discrepancy (root)", "wrap_around_l2", false),
        ("mixture discrepancy (root)", "mixture", false),
        ("star discrepancy D* (L∞)", "star_linf", false),
        ("worst 1-D projection D* (L∞)", "worst_1d_star_linf", false),
        ("worst 2-D projection D* (L∞)", "worst_2d_star_linf", false),
        ("minimum distance (Euclidean)", "min_distance", true),
        ("minimum distance (periodic)", "min_distance_periodic", true),
        ("mean gap max_k |mean_k − 0.5|", "mean_gap", false),
        ("energy U_{E,∞} = 1/d_min", "energy_e_inf", false),
    ];
    let size = |i: usize| (files[i].1.n(), files[i].1.s());
    let peers = |i: usize| (0..files.len()).filter(move |&j| size(j) == size(i));
    let ranked = (0..files.len()).any(|i| peers(i).count() > 1);
    for (label, key, higher) in rows {
        let values: Vec<Option<f64>> = files.iter().map(|(_, _, v)| v[key].as_f64()).collect();
        let best_among = |i: usize| {
            peers(i)
                .filter_map(|j| values[j])
                .fold(None, |b: Option<f64>, v| match b {
                    Some(b) if (higher && b >= v) || (!higher && b <= v) => Some(b),
                    _ => Some(v),
                })
        };
        t += &format!("  {label:<36}");
        for (i, v) in values.iter().enumerate() {
            let cell = match v {
                Some(x) => format!(
                    "{x:.6}{}",
                    if Some(*x) == best_among(i) && peers(i).count() > 1 {
                        "*"
                    } else {
                        " "
                    }
                ),
                None => "- ".to_string(),
            };
            t += &format!(" {cell:>15}");
        }
        t += "\n";
    }
    t += &format!("  {:<36}", "every coordinate stratified");
    for (_, _, v) in files {
        let yes = if v["stratified"].as_bool() == Some(true) {
            "yes "
        } else {
            "no "
        };
        t += &format!(" {yes:>15}");
    }
    t += if ranked {
        "\n\n  * the best of the row among the files of the same n and s: lower is better for the\n    discrepancies, the mean gap and the energy; higher for the distances. \"-\": not\n    computed (see eval FILE --json notes).\n"
    } else {
        "\n\n  No two files have the same n and s, so no value is marked best: figures of sets of\n  different sizes are not comparable. \"-\": not computed (see eval FILE --json notes).\n"
    };
    t
}

pub(crate) fn points_json(points: &PointSet) -> Value {
    json!(points.rows().map(|r| r.to_vec()).collect::<Vec<_>>())
}

/// The `--json` report of a region run.
#[derive(Serialize)]
struct RegionJson<'a> {
    generator: String,
    n: usize,
    s: usize,
    region: Option<String>,
    energy: &'a str,
    seed: u64,
    steps: usize,
    stop: StopReason,
    kappa: Option<f64>,
    energy_e_inf_g_reduction: f64,
    run: BTreeMap<&'a str, f64>,
    metrics_start: &'a RegionMetrics,
    metrics_result: &'a RegionMetrics,
    seconds: f64,
    /// A mixture's: where its figures live (the written set has one component more).
    #[serde(skip_serializing_if = "Option::is_none")]
    figures_in: Option<String>,
}

/// The `--json` report of a region run; a mixture's (of `components`) says where its
/// figures live.
pub(crate) fn region_json(
    r: &GenerateReport,
    cfg: &GenerateConfig,
    components: Option<usize>,
) -> Result<Value> {
    let (m0, m1) = r.region_metrics()?;
    as_json(&RegionJson {
        generator: generator(),
        n: cfg.n,
        s: components.unwrap_or(cfg.s),
        region: cfg.region().map(|d| format!("{d:?}")),
        energy: &r.energy_name,
        seed: cfg.seed,
        steps: last_step(&r.output),
        stop: r.output.stop,
        kappa: r.output.info(KAPPA),
        energy_e_inf_g_reduction: r.reduction()?,
        run: facts(r),
        metrics_start: m0,
        metrics_result: m1,
        seconds: r.seconds,
        figures_in: components.map(mixture_figures),
    })
}

/// Where a mixture's region figures are computed: the run's own coordinates.
pub(crate) fn mixture_figures(components: usize) -> String {
    format!(
        "the region figures are those of {} (the run's coordinates; x{components} = 1 \
         minus their sum)",
        run_coordinates(components)
    )
}

/// The coordinates a mixture of `components` runs in: x1..x{S − 1}.
fn run_coordinates(components: usize) -> String {
    match components {
        2 => "x1".into(),
        k => format!("x1..x{}", k - 1),
    }
}

/// A region of linear constraints (a mixture's among them) as the user gave it.
fn constrained_name(description: &Value) -> Option<String> {
    let texts: Vec<&str> = description[Opt::constraints.name()]
        .as_array()?
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    let cuts = if texts.is_empty() {
        String::new()
    } else {
        format!(" with {}", texts.join(", "))
    };
    let b = description[Opt::bbox.name()].as_str();
    Some(match description[Opt::mixture.name()].as_u64() {
        Some(k) => format!(
            "mixtures of {k} components (each ≥ 0, sum 1{}){cuts}; run in {}, x{k} = 1 − \
             their sum",
            b.map(|b| format!(", bounds {b}")).unwrap_or_default(),
            run_coordinates(k as usize)
        ),
        None => format!(
            "{{x : {}}} within the box {}",
            texts.join(", "),
            b.unwrap_or("")
        ),
    })
}

/// A region as the user gave it: `{x : EXPR ≤ 0} in the box …` or the shape's text,
/// not the internal form.
pub(crate) fn region_name(cfg: &GenerateConfig) -> String {
    let Space::Region { description, .. } = &cfg.space else {
        return "the unit cube".into();
    };
    if let Some(name) = constrained_name(description) {
        return name;
    }
    match (
        description["expression"].as_str(),
        description[Opt::bbox.name()].as_str(),
        description[Opt::shape.name()].as_str(),
    ) {
        (Some(e), Some(b), _) => format!("{{x : {e} ≤ 0}} within the box {b}"),
        (Some(e), None, _) => format!("{{x : {e} ≤ 0}}"),
        (None, Some(b), Some(sh)) => format!("the shape {sh} within the box {b}"),
        (None, _, Some(sh)) => format!("the shape {sh}"),
        _ => cfg.region().map(|d| format!("{d:?}")).unwrap_or_default(),
    }
}

pub(crate) fn region_table(
    r: &GenerateReport,
    cfg: &GenerateConfig,
    out: Option<&PathBuf>,
) -> Result<String> {
    let (a, b) = r.region_metrics()?;
    let domain = region_name(cfg);
    let solver = r.solver().map(solver_line).unwrap_or_default();
    // A mixture's written points have one component more than the run's.
    let shown_s = match &cfg.space {
        Space::Region { description, .. } => description[Opt::mixture.name()]
            .as_u64()
            .map_or(cfg.s, |k| k as usize),
        _ => cfg.s,
    };
    // A goal's run in a region says what its stages did instead of the start it drew.
    let integration = Pipeline::of(cfg).target().is_some();
    if integration && !r.stages.is_empty() {
        let stages: Vec<String> = r.stages.iter().map(|s| s.to_string()).collect();
        return Ok(format!(
            "stillpoint: n = {}, s = {} in {}, integration goal\n  {}\n\n",
            cfg.n,
            shown_s,
            region_name(cfg),
            stages.join("\n  ")
        ) + &region_rows(a, b, r, out, true));
    }
    let t = format!(
        "stillpoint: n = {}, s = {} in {}\n  {} from {}, {solver}\n\n",
        cfg.n,
        shown_s,
        domain,
        r.energy_name,
        match &cfg.init {
            Init::Random => format!("random start (seed {}, uniform in the region)", cfg.seed),
            Init::Halton => "Halton start (first n inside the box)".into(),
            Init::Points(_) => "points from file".into(),
        },
    );
    Ok(t + &region_rows(a, b, r, out, integration))
}

/// The start and result figures of a region run, and its closing line.
fn region_rows(
    a: &stillpoint::quality::region::RegionMetrics,
    b: &stillpoint::quality::region::RegionMetrics,
    r: &GenerateReport,
    out: Option<&PathBuf>,
    integration: bool,
) -> String {
    let mut t = change_header();
    let cell = |v: f64| {
        if v.is_finite() && v != 0.0 && !(1e-3..1e7).contains(&v.abs()) {
            // A region of radius 1e-90 has distances that six decimals show as 0, and
            // energies of ninety digits.
            format!("{v:>14.6e}")
        } else if v.is_finite() {
            format!("{v:>14.6}")
        } else {
            // A single point has no pair: its distances are infinite.
            format!("{:>14}", "none")
        }
    };
    for (name, x, y) in [
        (
            "energy U_{E,∞,g} (eq. 56)",
            a.energy_e_inf_g,
            b.energy_e_inf_g,
        ),
        ("minimum distance", a.min_distance, b.min_distance),
        (
            "minimum distance to the boundary",
            a.min_boundary_distance,
            b.min_boundary_distance,
        ),
    ] {
        // A single point has no pair: its distances are infinite and have no change.
        let change = 100.0 * (y - x) / x;
        let change = if change.is_finite() {
            format!("{change:>+8.1}%")
        } else {
            format!("{:>9}", "-")
        };
        t += &format!("  {name:<36} {} {} {change}\n", cell(x), cell(y));
    }
    t += &format!(
        "  {:<36} {:>14.4e} {:>14.4e}   (± {:.1e}; D² to uniform, not its root)\n",
        "energy distance to uniform", a.energy_distance, b.energy_distance, b.energy_distance_se
    );
    // The energy's reduction is the objective of a space-filling run only: an
    // integration goal does not lower it, and a point near the boundary can make it
    // any size at all.
    let reduction = r.reduction().ok().filter(|v| v.is_finite() && !integration);
    t += &format!(
        "\n  {}time {:.2} s; points written to {}\n",
        reduction.map_or(String::new(), |v| format!(
            "U_{{E,∞,g}} reduction {:.1}%; ",
            100.0 * v
        )),
        r.seconds,
        out.map(|p| p.display().to_string())
            .unwrap_or_else(|| "standard output".into())
    );
    t
}
