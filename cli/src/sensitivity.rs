//! `stillpoint sensitivity --expr EXPR`: the Sobol' indices of an expression's inputs to
//! a tolerance, by the library's `stillpoint::sensitivity` driver, printed as a table or
//! JSON and drawn as bars with their intervals.

use super::*;
use stillpoint::cubature::StopReason;
use stillpoint::parse::expr::RegionExpr;
use stillpoint::pipeline::integration::{FromRequest, Spelling};
use stillpoint::pipeline::options::Opt;
use stillpoint::sensitivity::{Sensitivity, SensitivityOptions, SobolResult};

/// `sensitivity --expr EXPR (-s S | --var NAME=TYPE ...) --abs-tol T ...`.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct SensitivityArgs {
    /// The model: an expression in x1..xd (the grammar of --region), the inputs in the
    /// order of --var; the variables' own names may be written instead, and come before
    /// x, y, z (an input named x is that input, wherever it stands).
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub(crate) expr: String,
    /// Number of inputs, each uniform on [0, 1] (or on --bounds).
    #[arg(short = 's', value_name = "S", allow_hyphen_values = true)]
    pub(crate) s: Option<String>,
    /// An input and its law, as generate takes it (`x=normal(0,1)`, `k=int(1,3)`);
    /// repeat for each input. Independent inputs only.
    #[arg(long = "var", value_name = "NAME=TYPE", allow_hyphen_values = true,
          conflicts_with_all = ["s", "bounds"])]
    pub(crate) var: Vec<String>,
    /// The inputs' box instead of the unit cube: LO1,HI1,... (with -s).
    #[arg(long, value_name = "LO1,HI1,...", allow_hyphen_values = true)]
    pub(crate) bounds: Option<String>,
    #[command(flatten)]
    pub(crate) tolerance: ToleranceArgs,
    /// The intervals hold all together at --level (Bonferroni), not each on its own.
    #[arg(long)]
    pub(crate) simultaneous: bool,
    /// The first-order estimator: saltelli or janon.
    #[arg(long, value_name = "NAME")]
    pub(crate) first_estimator: Option<String>,
    /// Also every pair's second-order index S_ij (Saltelli 2002; d more evaluations per
    /// point).
    #[arg(long)]
    pub(crate) second_order: bool,
    /// How each index's interval is computed: posterior (a Bayesian cubature's of the
    /// rule of all the points) or blocks (Student's over the blocks' spread).
    #[arg(long, value_name = "NAME")]
    pub(crate) interval: Option<String>,
    /// Print one JSON object.
    #[arg(long)]
    pub(crate) json: bool,
    /// Draw the indices as bars with their intervals (.png or .svg).
    #[arg(long, value_name = "FILE")]
    pub(crate) plot: Option<PathBuf>,
    /// No progress lines.
    #[arg(long, short = 'q')]
    pub(crate) quiet: bool,
    /// Progress on standard error, one line per doubling: `plain` or `bar` (lines), or
    /// `none`. Not shown off a terminal unless asked for.
    #[arg(long, value_name = "bar|plain|none", hide_possible_values = true)]
    pub(crate) progress: Option<crate::ProgressMode>,
}

impl SensitivityArgs {
    /// The options given as the library resolves them ([`Request`]), each value as typed.
    fn given(&self) -> Result<Request> {
        Ok(self.tolerance.onto(Request {
            s: typed_arg(&self.s),
            bounds: self.bounds.as_deref().map(Arg::from),
            simultaneous: self.simultaneous.then_some(Arg::Bool(true)),
            first_estimator: self.first_estimator.as_deref().map(Arg::from),
            interval: self.interval.as_deref().map(Arg::from),
            second_order: self.second_order.then_some(Arg::Bool(true)),
            space: space_items(&self.var, None)?,
            ..Request::default()
        }))
    }
}

/// Runs `sensitivity` and prints the indices.
pub(crate) fn sensitivity_command(q: SensitivityArgs) -> Result<()> {
    let text = q.expr.as_str();
    let given = q.given()?;
    if given.s.is_none() && given.space.is_none() {
        bail!("sensitivity needs -s S (inputs uniform on [0, 1]) or --var");
    }
    let var = Opt::space.declared().cli;
    let name = |n: &str| integration_flag(n, var);
    let shown = |_: &str, v: &Arg| v.to_string();
    let spelling = Spelling {
        name: &name,
        shown: &shown,
    };
    let (mut state, space) = Sensitivity::from_request(&given, &spelling)?;
    let refused = |e| expr_refusal(e, text, |_| None, |n| integration_flag(n, var));
    let options = state.options().clone();
    let d = state.d();
    // The variables' own names (--var, --space) stand for their columns in --expr.
    let names: Vec<String> = space.as_ref().map_or(Vec::new(), |sp| {
        sp.vars.iter().map(|v| v.name.clone()).collect()
    });
    let expr = RegionExpr::parse_named(text, d, &names)
        .map_err(|e| anyhow::anyhow!("invalid --expr: {e}"))?;
    let mode = ProgressMode::chosen(q.quiet, q.progress, ProgressMode::None);
    let started = std::time::Instant::now();
    let mut failed = None;
    let f = |points: &PointSet| -> Vec<f64> {
        let values = match &space {
            None => Ok(points.clone()),
            Some(space) => stillpoint::pipeline::measure::mapped(space, points)
                .and_then(|design| design.numbers()),
        };
        match values {
            Ok(x) => x.rows().map(|p| expr.eval(p)).collect(),
            Err(e) => {
                failed = Some(e);
                vec![0.0; points.n()]
            }
        }
    };
    let after = |s: &Sensitivity| {
        if mode != ProgressMode::None {
            use std::io::Write as _;
            let line = s.progress_line("stillpoint", started.elapsed().as_secs_f64());
            // A closed standard error must not end the run.
            drop(writeln!(std::io::stderr(), "{line}"));
        }
    };
    let run = state.run_observed(f, after);
    if let Some(e) = failed {
        return Err(refused(e));
    }
    run.map_err(refused)?;
    let r = SobolResult::from(state);
    for w in &r.warnings {
        noteln!("warning: {w}");
    }
    if let Some(path) = &q.plot {
        plot_indices(path, &r, options.level)?;
    }
    if q.json {
        print_json(text, &r, &options)
    } else {
        print_table(&r, &options)
    }
}

/// Draws the indices as bars with their intervals (`--plot FILE`).
fn plot_indices(path: &std::path::Path, r: &SobolResult, level: f64) -> Result<()> {
    let chart = stillpoint_plot::BarChart {
        title: format!("Sobol' indices, intervals at level {}", level),
        y_label: "index".into(),
        groups: r.names.clone(),
        bars: vec![
            stillpoint_plot::Bars {
                name: "first order".into(),
                values: r.first.clone(),
                half_widths: r.first_half_width.clone(),
            },
            stillpoint_plot::Bars {
                name: "total".into(),
                values: r.total.clone(),
                half_widths: r.total_half_width.clone(),
            },
        ],
    };
    stillpoint_plot::save_bar_chart(path, &chart)
        .with_context(|| format!("--plot {}", path.display()))?;
    Ok(())
}

/// Prints the indices as one JSON object (`--json`).
fn print_json(text: &str, r: &SobolResult, options: &SensitivityOptions) -> Result<()> {
    let reason = r.reason.map_or("running", StopReason::as_str);
    // The inputs the lattice takes without the tent (the face test found f periodic
    // in them).
    let periodic: Vec<&String> = r
        .names
        .iter()
        .zip(r.state.periodic())
        .filter_map(|(name, &p)| p.then_some(name))
        .collect();
    let mut v = json!({"expr": text, "names": r.names, "first": r.first, "total": r.total,
                   "first_half_width": r.first_half_width,
                   "total_half_width": r.total_half_width, "n": r.n,
                   "met": r.met, "reason": reason, "periodic": periodic});
    if options.second_order {
        // One entry per pair i < j, in row order.
        v["second"] = json!(pairs(&r.names)
            .zip(r.second.iter().zip(&r.second_half_width))
            .map(|((a, b), (s, h))| json!({"inputs": [a, b], "index": s, "half_width": h}))
            .collect::<Vec<_>>());
    }
    record(
        &mut v,
        [
            (Opt::replicates, json!(options.replicates)),
            (Opt::level, json!(options.level)),
            (Opt::simultaneous, json!(options.simultaneous)),
            (Opt::abs_tol, json!(options.abs_tol)),
            (Opt::first_estimator, json!(options.first_order.as_str())),
            (Opt::second_order, json!(options.second_order)),
            (Opt::interval, json!(r.state.interval_used().as_str())),
            (Opt::rule, json!(options.rule.as_str())),
        ],
    );
    outln!("{}", serde_json::to_string_pretty(&v)?);
    Ok(())
}

/// Prints the indices as a table: a row per input, then (with second order) a row per
/// pair, then the settings and whether the tolerance was met.
fn print_table(r: &SobolResult, options: &SensitivityOptions) -> Result<()> {
    let width = r
        .names
        .iter()
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(0)
        .max(5);
    outln!(
        "{:width$}  {:>8}  {:>8}  {:>8}  {:>8}",
        "input",
        "first",
        "±",
        "total",
        "±"
    );
    for (i, name) in r.names.iter().enumerate() {
        outln!(
            "{name:width$}  {:>8.4}  {:>8.4}  {:>8.4}  {:>8.4}",
            r.first[i],
            r.first_half_width[i],
            r.total[i],
            r.total_half_width[i]
        );
    }
    if options.second_order {
        let pair_width = (2 * width + 1).max(4);
        outln!("{:pair_width$}  {:>8}  {:>8}", "pair", "second", "±");
        for ((a, b), (s, h)) in pairs(&r.names).zip(r.second.iter().zip(&r.second_half_width)) {
            outln!("{:pair_width$}  {s:>8.4}  {h:>8.4}", format!("{a},{b}"));
        }
    }
    let which = if options.simultaneous {
        "all together"
    } else {
        "each on its own"
    };
    outln!(
        "intervals    level {} ({which}; {})",
        options.level,
        r.state.interval_used().as_str()
    );
    outln!("evaluations  {} ({} replicates)", r.n, options.replicates);
    let why = match r.reason {
        Some(StopReason::Met) | None => "yes".to_string(),
        Some(StopReason::MaxN) => format!("no: --max-n {} reached first", options.max_n),
        Some(StopReason::Sequence) => "no: the sequence's 2^20 points reached first".to_string(),
    };
    outln!("met          {why}");
    Ok(())
}

/// The pairs of inputs i < j, in the order of the second-order indices.
fn pairs(names: &[String]) -> impl Iterator<Item = (&String, &String)> {
    names
        .iter()
        .enumerate()
        .flat_map(move |(i, a)| names[i + 1..].iter().map(move |b| (a, b)))
}
