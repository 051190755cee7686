//! `stillpoint generate`: arguments to a run configuration, the run, its outputs.

use super::*;
use serde::Deserialize as _;

/// Largest n whose O(n² s) metrics a baseline file's header records (above it they would
/// take longer than generating the points by far).
pub(crate) const METRICS_LIMIT: usize = 20_000;

/// `stillpoint generate`: the flags become one library [`Request`], resolved by the
/// library (every option rule lives there); then the run and its outputs. Every output
/// path is checked before any work is done, and outputs are written only after the run
/// succeeded.
pub(crate) fn generate(a: GenerateArgs) -> Result<()> {
    check_outputs(&a)?;
    let request = request_of(&a)?;
    let resolved = request.resolve_as(&spelling(a.space.is_some()))?;
    if let Some(space) = &resolved.design {
        check_design_output(space, a.output.as_ref())?;
    }
    let Job::Run(cfg) = &resolved.job else {
        return write_baseline(&a, &resolved);
    };
    let cfg: &GenerateConfig = cfg;
    if a.plot.is_some() && cfg.s < 2 {
        bail!("invalid --plot with -s = {}: plots need s ≥ 2", cfg.s);
    }
    // A refused checkpoint is refused before any note, as every other refusal is.
    let plan = checkpoint_plan(
        a.checkpoint.clone(),
        &a.checkpoint_every,
        a.resume.clone(),
        Value::Null,
        a.quiet,
    )?;
    notes_before(&resolved, a.quiet, plan.as_ref().and_then(resumed_at));
    let mut progress = Progress::new(a.quiet, a.progress);
    let outcome = resolved.run(plan.as_ref(), |e| progress.event(e))?;
    progress.finish();
    let report = outcome.report.context("a run's report")?;
    // How the command line named the region: recorded in the file header.
    let mut given = json!({});
    for (opt, value) in [
        (Opt::region, json!(a.region)),
        (Opt::bbox, json!(a.bbox)),
        (Opt::shape, json!(a.shape)),
    ] {
        given[flag(opt)] = value;
    }
    if !a.constraint.is_empty() || a.mixture {
        given[flag(Opt::constraints)] = json!(a.constraint);
        given[flag(Opt::mixture)] = json!(a.mixture);
    }
    let mut meta = file_header(&report, cfg, &given, &resolved)?;
    // The run's outputs appear together or not at all.
    let staging = io::Staging::begin();
    if let Some(path) = &a.trajectory {
        write_trajectory(path, &report.energy_name, &report.output)?;
    }
    // The picture is drawn after the points are in place: a picture that cannot be
    // written (a full disk) must not lose the computed points with it.
    let plot = || -> Result<()> {
        let Some(path) = &a.plot else { return Ok(()) };
        let domain: Arc<dyn Domain> = match cfg.region() {
            Some(d) => d.clone(),
            None => Arc::new(stillpoint::PeriodicCube::new(cfg.s)?),
        };
        let old = cfg.extend.as_ref().map(|p| p.n());
        plot_start_result(
            path,
            &report.start,
            &report.output.points,
            domain.as_ref(),
            old,
        )
    };
    if let Some(design) = &outcome.design {
        design_header(&mut meta, design);
        let run_line = format!(
            "{}: from {} points in [0, 1)^{} made by the {} in {:.2} s",
            rule_header(&mut meta, &resolved),
            cfg.n,
            cfg.s,
            goal_name(cfg).map_or("paper's pipeline".into(), |g| format!("goal {g}")),
            report.seconds
        );
        emit_design(
            design,
            cfg.sums,
            &meta,
            &run_line,
            a.output.as_ref(),
            a.json,
            staging,
        )?;
        return plot();
    }
    let summary = match (a.json, cfg.region().is_some()) {
        (true, false) => report_json(&report, cfg)?,
        (true, true) => region_json(
            &report,
            cfg,
            resolved.mixture.as_ref().map(|m| m.components()),
        )?,
        (false, false) => Value::String(report_table(&report, cfg, a.output.as_ref())?),
        (false, true) => Value::String(region_table(&report, cfg, a.output.as_ref())?),
    };
    emit(&outcome.points, &meta, a.output.as_ref(), summary, staging)?;
    plot()
}

/// Every output path checked (writable, a known extension, no two the same, none an
/// input) before any work is done.
fn check_outputs(a: &GenerateArgs) -> Result<()> {
    if let Some(out) = &a.output {
        check_writable(out, "-o")?;
        check_points_extension(out, "-o")?;
    }
    if let Some(out) = &a.plot {
        check_writable(out, "--plot")?;
        check_picture_extension(out, "--plot")?;
    }
    if let Some(out) = &a.trajectory {
        check_writable(out, flag(Opt::trajectory))?;
    }
    let init_file = a
        .init
        .as_deref()
        .filter(|i| !["halton", "random"].contains(i))
        .map(std::path::Path::new);
    let resume_file = match &a.resume {
        Some(Some(r)) => Some(r.as_path()),
        Some(None) => a.checkpoint.as_deref(),
        None => None,
    };
    let polytope = a
        .shape
        .as_deref()
        .and_then(|t| t.strip_prefix("polytope:"))
        .map(std::path::Path::new);
    check_distinct(
        &[
            ("-o", a.output.as_deref()),
            ("--plot", a.plot.as_deref()),
            (flag(Opt::trajectory), a.trajectory.as_deref()),
            (flag(Opt::checkpoint), a.checkpoint.as_deref()),
        ],
        &[
            (flag(Opt::init), init_file),
            (flag(Opt::extend), a.extend.as_deref()),
            (other_flag(Opt::checkpoint), resume_file),
            ("--shape polytope", polytope),
            (other_flag(Opt::space), a.space.as_deref()),
        ],
    )
}

/// The flags as a library request: text as given, files read into points.
fn request_of(a: &GenerateArgs) -> Result<Request> {
    let text = |v: &Option<String>| v.as_deref().map(Arg::from);
    let init = match a.init.as_deref() {
        None => None,
        Some(w @ ("halton" | "random")) => Some(Arg::from(w)),
        Some(path) => Some(Arg::Points(
            io::read_points(std::path::Path::new(path)).context(flag(Opt::init))?,
        )),
    };
    let extend = match &a.extend {
        Some(path) => Some(Arg::Points(
            io::read_points(path).context(flag(Opt::extend))?,
        )),
        None => None,
    };
    Ok(Request {
        n: text(&a.n),
        s: text(&a.s),
        seed: text(&a.seed),
        method: text(&a.method),
        goal: text(&a.goal),
        target: text(&a.target),
        randomize: text(&a.randomize),
        extend,
        nested: text(&a.nested),
        bounds: text(&a.bounds),
        region: text(&a.region),
        bbox: text(&a.bbox),
        shape: text(&a.shape),
        constraints: (!a.constraint.is_empty()).then(|| Arg::Texts(a.constraint.clone())),
        mixture: a.mixture.then_some(Arg::Bool(true)),
        energy: text(&a.energy),
        integrator: text(&a.integrator),
        q: text(&a.q),
        p: text(&a.p),
        precision: text(&a.precision),
        steps: text(&a.steps),
        init,
        kappa: text(&a.kappa),
        restart: text(&a.restart),
        tolerance: text(&a.tolerance),
        polish: text(&a.polish),
        shifts: text(&a.shifts),
        log_every: text(&a.log_every),
        exact: a.exact.then_some(Arg::Bool(true)),
        trajectory: a.trajectory.is_some().then_some(Arg::Bool(true)),
        checkpoint: (a.checkpoint.is_some() || a.resume.is_some()).then_some(Arg::Bool(true)),
        space: space_of(a)?,
        correlation: text(&a.correlation),
        // The integration commands' options, which generate does not take. A flag of
        // generate left out here is caught by the walk (its bad value goes unrefused).
        ..Request::default()
    })
}

/// `--var` as given, or the variables of the `--space` file.
fn space_of(a: &GenerateArgs) -> Result<Option<Arg>> {
    if let Some(path) = &a.space {
        return Ok(Some(Arg::Texts(read_space(path)?)));
    }
    Ok((!a.var.is_empty()).then(|| Arg::Texts(a.var.clone())))
}

/// The variables of a space file: a JSON array of "NAME=TYPE" strings, or an object
/// whose "variables" is one (read through the bounded reader, as every input). A key
/// given twice, or any key but "variables", is refused by name: JSON leaves a repeated
/// key's meaning open, and an ignored key is a setting the user believes was applied.
pub(crate) fn read_space(path: &std::path::Path) -> Result<Vec<String>> {
    let bytes = io::read_bounded(path).with_context(|| format!("--space {}", path.display()))?;
    let text = std::str::from_utf8(&bytes).unwrap_or_default();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let shape = || {
        anyhow::anyhow!(
            "invalid --space {}: expected a JSON array of \"NAME=TYPE\" strings (as --var \
             takes), or an object whose \"variables\" is one",
            path.display()
        )
    };
    let file: SpaceFile = serde_json::from_str(text).map_err(|e| {
        if e.is_data() {
            anyhow::anyhow!("invalid --space {}: {e}", path.display())
        } else {
            anyhow::anyhow!(
                "invalid --space {}: not JSON ({e}); expected an array of \"NAME=TYPE\" \
                 strings",
                path.display()
            )
        }
    })?;
    match file.0 {
        Some(Value::Array(items)) if items.iter().all(|v| v.is_string()) => Ok(items
            .iter()
            .filter_map(|v| v.as_str().map(str::to_string))
            .collect()),
        _ => Err(shape()),
    }
}

/// A space file's top level: the variables list (from the array itself or the object's
/// "variables"), `None` for any other shape.
struct SpaceFile(Option<Value>);

impl<'de> serde::Deserialize<'de> for SpaceFile {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Top;
        impl<'de> serde::de::Visitor<'de> for Top {
            type Value = SpaceFile;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array of \"NAME=TYPE\" strings or an object with \"variables\"")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> std::result::Result<SpaceFile, A::Error> {
                let v = Value::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))?;
                Ok(SpaceFile(Some(v)))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<SpaceFile, A::Error> {
                use serde::de::Error as _;
                let mut variables = None;
                while let Some(key) = map.next_key::<String>()? {
                    if key != "variables" {
                        return Err(A::Error::custom(format!(
                            "unknown key \"{key}\"; a space file has only \"variables\" \
                             (an array of \"NAME=TYPE\" strings)"
                        )));
                    }
                    if variables.is_some() {
                        return Err(A::Error::custom(
                            "duplicate key \"variables\"; a space file has each key once",
                        ));
                    }
                    variables = Some(map.next_value::<Value>()?);
                }
                Ok(SpaceFile(variables))
            }
            fn visit_str<E: serde::de::Error>(self, _: &str) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
            fn visit_f64<E: serde::de::Error>(self, _: f64) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
            fn visit_i64<E: serde::de::Error>(self, _: i64) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
            fn visit_u64<E: serde::de::Error>(self, _: u64) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
            fn visit_bool<E: serde::de::Error>(self, _: bool) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
            fn visit_unit<E: serde::de::Error>(self) -> std::result::Result<SpaceFile, E> {
                Ok(SpaceFile(None))
            }
        }
        d.deserialize_any(Top)
    }
}

/// `generate --method BASELINE`: the construction's points, written as `baseline` does;
/// and a design whose unit-cube set is made directly rather than by a run (a baseline's
/// or the lattice made for its laws), written with its figures as every design is.
fn write_baseline(a: &GenerateArgs, resolved: &Resolved) -> Result<()> {
    let design = resolved.design.is_some();
    for (flag, given) in [
        ("--plot", a.plot.is_some()),
        // A design reports its figures, in JSON too; a bare baseline has none.
        ("--json", a.json && !design),
        (other_flag(Opt::checkpoint), a.resume.is_some()),
    ] {
        if !given {
            continue;
        }
        if design {
            bail!(
                "invalid {flag} under this space: its unit-cube set is made directly, not by \
                 a run (no start to draw, nothing to resume); draw the written file with \
                 `stillpoint plot FILE`"
            );
        }
        bail!(
            "invalid {flag} with --method {}: a baseline writes its points only (see `stillpoint baseline`)",
            a.method.as_deref().unwrap_or_default()
        );
    }
    notes_before(resolved, a.quiet, None);
    let outcome = resolved.run(None, |_| {})?;
    // The header records the options under their names.
    let mut meta = json!({"generator": "stillpoint"});
    record(
        &mut meta,
        [(Opt::method, json!(a.method)), (Opt::seed, json!(a.seed))],
    );
    if let Some(b) = &resolved.bounds {
        record(&mut meta, [(Opt::bounds, json!(b.text()))]);
    }
    let staging = io::Staging::begin();
    if let Some(design) = &outcome.design {
        design_header(&mut meta, design);
        let rule = rule_header(&mut meta, resolved);
        let run_line = match &resolved.job {
            Job::Law { n, seed, .. } => format!("{rule}: {n} points from seed {seed}"),
            _ => format!(
                "{rule}: from the {} set",
                a.method.as_deref().unwrap_or("scrambled Sobol'")
            ),
        };
        let sums = resolved.sums;
        return emit_design(
            design,
            sums,
            &meta,
            &run_line,
            a.output.as_ref(),
            a.json,
            staging,
        );
    }
    emit(
        &outcome.points,
        &meta,
        a.output.as_ref(),
        Value::String(String::new()),
        staging,
    )
}

/// Records a design's rule (how its unit-cube set was made and carried into the space)
/// in the file header, and gives its phrase for the report's run line.
fn rule_header(meta: &mut Value, resolved: &Resolved) -> &'static str {
    let phrase = resolved.rule.map_or("", |r| r.phrase());
    record(meta, [(Opt::rule, json!(phrase))]);
    phrase
}

/// Records a design's space and correlation (when it has one) in the file header under
/// their options' names.
fn design_header(meta: &mut Value, design: &stillpoint::design::Design) {
    record(meta, [(Opt::space, json!(design.space.texts()))]);
    if let Some(c) = design.space.correlation_text() {
        record(meta, [(Opt::correlation, json!(c))]);
    }
}

/// Says what is unusual (even with -q, which hides progress only), and how long a long
/// run may take (not with -q), before it starts; a resumed run (`resumed`: the step its
/// checkpoint holds, and whether it had stopped) by the steps it has left.
fn notes_before(resolved: &Resolved, quiet: bool, resumed: Option<(usize, bool)>) {
    let long = (!quiet).then(|| match resumed {
        Some((step, converged)) => resolved.resumed_note_as(&flag_name, step, converged),
        None => resolved.long_run_note_as(&flag_name),
    });
    for text in resolved
        .unusual_as(&flag_name)
        .into_iter()
        .chain(long.flatten())
    {
        note(&format!("note: {text}"));
    }
}

/// A note on standard error; a standard error that cannot be written loses the note, not
/// the run.
fn note(text: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{text}");
}

/// The step a resumed checkpoint holds and whether its integrator had stopped; `None`
/// when the plan resumes nothing or the file cannot be read (the run refuses it then,
/// with the reason).
fn resumed_at(plan: &CheckpointPlan) -> Option<(usize, bool)> {
    let checkpoint = read_checkpoint(plan.resume.as_ref()?).ok()?;
    let step = checkpoint.state.get("step")?.as_u64()?;
    let converged = checkpoint.state.get("converged")?.as_bool()?;
    Some((step as usize, converged))
}

/// The checkpoint plan of `--checkpoint FILE [--checkpoint-every K] [--resume [FILE]]`.
pub(crate) fn checkpoint_plan(
    checkpoint: Option<PathBuf>,
    every: &str,
    resume: Option<Option<PathBuf>>,
    extra: Value,
    quiet: bool,
) -> Result<Option<CheckpointPlan>> {
    // `--resume` without a value means "the --checkpoint file".
    let resume_path = match (&resume, &checkpoint) {
        (None, _) => None,
        (Some(Some(r)), _) => Some(r.clone()),
        (Some(None), Some(c)) => Some(c.clone()),
        (Some(None), None) => {
            bail!(
                "invalid --resume without a FILE: give --resume FILE or --checkpoint FILE --resume"
            )
        }
    };
    let every = whole(
        "--checkpoint-every",
        every,
        1..=usize::MAX,
        "a number of steps ≥ 1",
    )?;
    if let Some(r) = &resume_path {
        if !r.is_file() {
            bail!(
                "invalid --resume {}: no such checkpoint file (expected a file written by \
                 generate --checkpoint)",
                r.display()
            );
        }
    }
    let Some(path) = checkpoint.or_else(|| resume_path.clone()) else {
        return Ok(None);
    };
    check_writable(&path, flag(Opt::checkpoint))?;
    // Only a checkpoint is replaced: any other file there (a point set, a report) is
    // someone's result, not this run's state.
    if resume_path.is_none() && path.exists() && read_checkpoint(&path).is_err() {
        bail!(
            "invalid --checkpoint {}: the file exists and is not a checkpoint (expected a new \
             path, or a checkpoint of an earlier run to replace)",
            path.display()
        );
    }
    if resume_path.is_none() && path.exists() && !quiet {
        noteln!(
            "note: {} exists; this run starts afresh and replaces it (add --resume to \
             continue from it)",
            path.display()
        );
    }
    Ok(Some(CheckpointPlan {
        path,
        every,
        resume: resume_path,
        extra,
        names: flag_name,
    }))
}
