//! `stillpoint integrate --expr`: an expression integrated to a tolerance by the
//! library's `stillpoint::cubature` driver, with its refusals in the flags' names.

use super::*;
use std::io::Write as _;
use stillpoint::cubature::{Cubature, StopReason};
use stillpoint::parse::expr::RegionExpr;
use stillpoint::pipeline::integration::{FromRequest, Spelling};
use stillpoint::sequences::EXTENSIBLE_MAX_POINTS;

/// A refusal of the library's as an `--expr` command shows it: f's own (the expression)
/// quoting the expression, any other naming its flag (`flag`) and the value as typed
/// (`typed`, else the library's rendering).
pub(crate) fn expr_refusal(
    e: stillpoint::Error,
    text: &str,
    typed: impl Fn(&str) -> Option<String>,
    flag: impl Fn(&str) -> String,
) -> anyhow::Error {
    match e {
        stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        } if name == "f" => {
            anyhow::anyhow!("invalid --expr {text:?}: {value}; expected {expected}")
        }
        stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        } => {
            let shown = typed(&name).unwrap_or(value);
            stillpoint::Error::invalid(flag(&name), shown, expected).into()
        }
        other => anyhow::Error::from(other),
    }
}

/// Runs `integrate --expr` and prints the estimate, half-width, evaluations and whether
/// the tolerance was met (and if not, what stopped it).
pub(crate) fn quad_command(q: QuadArgs, json: bool) -> Result<()> {
    let Some(text) = q.expr.as_deref() else {
        bail!("missing FILE or --expr: a point file to integrate, or --expr EXPR");
    };
    let given = q.options()?;
    if given.s.is_none() && given.space.is_none() {
        bail!("--expr needs -s (the dimension), or --var/--space");
    }
    let space_flag = q.space_flag();
    let name = |n: &str| integration_flag(n, space_flag);
    let shown = |_: &str, v: &Arg| v.to_string();
    let spelling = Spelling {
        name: &name,
        shown: &shown,
    };
    let (mut state, space) = Cubature::from_request(&given, &spelling)?;
    let refused = |e| expr_refusal(e, text, |_| None, |n| integration_flag(n, space_flag));
    let s = state.d();
    // The variables' own names (--var, --space) stand for their columns in --expr.
    let names: Vec<String> = space.as_ref().map_or(Vec::new(), |sp| {
        sp.vars.iter().map(|v| v.name.clone()).collect()
    });
    let expr = RegionExpr::parse_named(text, s, &names)
        .map_err(|e| anyhow::anyhow!("invalid --expr: {e}"))?;
    let options = state.options().clone();
    let rounds = Rounds::new(q.quiet, q.progress);
    rounds.say(&format!("stillpoint: {}", options.rule_reason));
    while !state.met() {
        let Some(points) = state.next_points() else {
            break;
        };
        rounds.evaluating(points.n());
        // Under laws the expression sees the variables' values, and a refusal names the
        // point by them (not by the unit point the rule drew).
        let mapped = match &space {
            None => None,
            Some(space) => Some(stillpoint::cubature::space_values(space, &points)?),
        };
        let seen = mapped.as_ref().unwrap_or(&points);
        let values: Vec<f64> = seen.rows().map(|p| expr.eval(p)).collect();
        state.feed(seen, &values).map_err(refused)?;
        rounds.done(&state);
    }
    state.check_representable().map_err(refused)?;
    drop(rounds);
    let r = stillpoint::cubature::QuadResult::from(state);
    for w in &r.warnings {
        noteln!("warning: {w}");
    }
    let reason = r.reason.map_or("running", StopReason::as_str);
    if json {
        let mut v = json!({"expr": text, "s": s, "estimate": r.estimate[0],
                       "half_width": r.half_width[0], "n": r.n, "met": r.met,
                       "reason": reason, "rule_reason": r.rule_reason});
        record(
            &mut v,
            [
                (Opt::replicates, json!(r.replicates)),
                (Opt::level, json!(options.level)),
                (Opt::rel_tol, json!(options.rel_tol)),
                (Opt::abs_tol, json!(options.abs_tol)),
                (Opt::rule, json!(r.rule.as_str())),
            ],
        );
        if let Some(space) = &space {
            record(
                &mut v,
                [
                    (Opt::space, json!(space.texts())),
                    (Opt::correlation, json!(space.correlation_text())),
                ],
            );
        }
        outln!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        if let Some(space) = &space {
            outln!("under        {}", space.texts().join(" "));
        }
        outln!("estimate     {}", number(r.estimate[0]));
        outln!(
            "half-width   {} (level {})",
            number(r.half_width[0]),
            options.level
        );
        let shifts = if r.replicates == 1 {
            "1 shifted lattice, a Bayesian interval".to_string()
        } else {
            format!("{} replicates", r.replicates)
        };
        outln!("evaluations  {} ({shifts})", r.n);
        outln!("rule         {}", r.rule_reason);
        let why = match r.reason {
            Some(StopReason::Met) | None => "yes".to_string(),
            Some(StopReason::MaxN) => format!("no: --max-n {} reached first", options.max_n),
            Some(StopReason::Sequence) => format!(
                "no: the sequence's {EXTENSIBLE_MAX_POINTS} points per replicate reached \
                 first ({} evaluations with {} replicates; a larger --max-n cannot help)",
                r.n, r.replicates
            ),
        };
        outln!("met          {why}");
    }
    Ok(())
}

/// `integrate FILE… --expr EXPR`: the expression's mean over each file's points (its
/// values as they are, one column per variable x1..xs), and over the files the mean, its
/// standard error and the Student t half-width at `--level` (files randomised
/// independently, e.g. `generate --randomize --seed` with different seeds, give
/// independent unbiased estimates).
pub(crate) fn files_command(files: &[PathBuf], q: QuadArgs, json: bool) -> Result<()> {
    let text = q.expr.as_deref().unwrap_or_default();
    if let Some(flag) = q.first_tolerance_only() {
        bail!(
            "invalid {flag} with point files: it applies to the integration to a tolerance \
             (--expr without FILE); the files' points are evaluated as they are"
        );
    }
    let level = q.level()?;
    let mut means = Vec::with_capacity(files.len());
    let mut rows = Vec::with_capacity(files.len());
    let mut dim: Option<(usize, String)> = match &q.s {
        Some(typed) => {
            let s: usize = declared(Opt::s, typed)?;
            Some((s, format!("-s {s}")))
        }
        None => None,
    };
    for file in files {
        let source = file.display().to_string();
        let points = io::read_points(file)?;
        match &dim {
            Some((s, what)) if *s != points.s() => bail!(
                "invalid {source}: {} columns; expected {s}, as {what}",
                points.s()
            ),
            Some(_) => {}
            None => dim = Some((points.s(), source.clone())),
        }
        let expr = RegionExpr::parse(text, points.s())
            .map_err(|e| anyhow::anyhow!("invalid --expr: {e}"))?;
        let mut sum = 0.0;
        for p in points.rows() {
            let v = expr.eval(p);
            if !v.is_finite() {
                bail!("invalid --expr {text:?}: {v} at x = {p:?} of {source}; expected a finite value at every point");
            }
            sum += v;
        }
        let mean = sum / points.n() as f64;
        means.push(mean);
        rows.push((source, points.n(), mean));
    }
    let m = stillpoint::cubature::mean_interval(&means, level)?;
    let s = dim.map_or(0, |(s, _)| s);
    let total: usize = rows.iter().map(|r| r.1).sum();
    if json {
        let per: Vec<Value> = rows
            .iter()
            .map(|(f, n, mean)| json!({"file": f, "n": n, "mean": mean}))
            .collect();
        let mut v = json!({"expr": text, "s": s, "estimate": m.mean,
                       "standard_error": m.standard_error, "half_width": m.half_width,
                       "n": total, "files": per});
        record(&mut v, [(Opt::level, json!(level))]);
        outln!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    for (f, n, mean) in &rows {
        outln!("{f}: mean {} over {n} points", number(*mean));
    }
    outln!("estimate        {}", number(m.mean));
    match (m.standard_error, m.half_width) {
        (Some(se), Some(hw)) => {
            outln!("standard error  {} ({} files)", number(se), rows.len());
            outln!("half-width      {} (level {level})", number(hw));
        }
        _ => outln!(
            "standard error  none: one file (two or more independently randomised files \
             give one)"
        ),
    }
    outln!("evaluations     {total}");
    Ok(())
}

/// A number as the result prints it: the shortest form that reads back to the same
/// float when it is moderate (0.25, 1234.5), in scientific notation when it is huge or
/// tiny (5e307, not 308 digits).
fn number(x: f64) -> String {
    let plain = format!("{x}");
    if x == 0.0 || (1e-5..1e16).contains(&x.abs()) {
        plain
    } else {
        format!("{x:e}")
    }
}

/// The progress of `integrate --expr` on standard error: after each doubling, one line
/// with the evaluations so far, the estimate, the half-width against the half-width it
/// must reach, and the seconds since the start; in [`ProgressMode::Bar`] also a spinner
/// while a doubling is evaluated (cleared at the end).
struct Rounds {
    mode: ProgressMode,
    bar: Option<ProgressBar>,
    started: std::time::Instant,
}

impl Rounds {
    /// The mode [`ProgressMode::chosen`] gives (the rule of every command: an explicit
    /// `--progress` wins over `-q`), nothing off a terminal (a script's standard error
    /// stays as it was; `--progress plain` asks for the lines there).
    fn new(quiet: bool, mode: Option<ProgressMode>) -> Self {
        let mode = ProgressMode::chosen(quiet, mode, ProgressMode::None);
        let bar = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template("{spinner} {msg}, {elapsed}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            bar
        });
        Rounds {
            mode,
            bar,
            started: std::time::Instant::now(),
        }
    }

    /// A doubling of `rows` points is being evaluated.
    fn evaluating(&self, rows: usize) {
        if let Some(bar) = &self.bar {
            bar.set_message(format!("evaluating {rows} points"));
            bar.enable_steady_tick(std::time::Duration::from_millis(120));
        }
    }

    /// A doubling is done: its line.
    fn done(&self, state: &Cubature) {
        let seconds = self.started.elapsed().as_secs_f64();
        self.say(&state.progress_line("stillpoint", seconds));
    }

    /// A line of progress (nothing in [`ProgressMode::None`]).
    fn say(&self, line: &str) {
        if self.mode == ProgressMode::None {
            return;
        }
        match &self.bar {
            Some(bar) => bar.println(line),
            // A closed standard error must not end the run.
            None => drop(writeln!(std::io::stderr(), "{line}")),
        }
    }
}

impl Drop for Rounds {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_print_compactly_at_any_magnitude() {
        for (x, want) in [
            (5e307, "5e307"),
            (-1.5e200, "-1.5e200"),
            (1e-300, "1e-300"),
            (0.25, "0.25"),
            (1234.5, "1234.5"),
            (0.0, "0"),
            (1e16, "1e16"),
            (2.5e-6, "2.5e-6"),
        ] {
            assert_eq!(number(x), want);
            assert_eq!(number(x).parse::<f64>().unwrap(), x);
        }
    }
}
