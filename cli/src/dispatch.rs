//! Runs a parsed command line: one arm per subcommand.

use super::*;

pub(crate) fn real_main(cli: Cli) -> Result<()> {
    if let Some(typed) = &cli.threads {
        let t = threads(typed)?;
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .context("cannot start the thread pool")?;
    }
    match cli.command {
        Command::Generate(args) => generate(*args)?,
        c @ Command::Eval { .. } => eval_command(c)?,
        c @ Command::Compare { .. } => compare_command(c)?,
        c @ Command::Baseline { .. } => baseline_command(c)?,
        c @ Command::Integrate { .. } => integrate_command(c)?,
        Command::Sensitivity(args) => sensitivity_command(*args)?,
        c @ Command::Study { .. } => study_command(c)?,
        c @ Command::Plot { .. } => plot_command(c)?,
        Command::Bench {
            quick,
            points,
            reps,
        } => {
            // Read whether or not --points uses it: a flag's value is refused alike
            // whatever else is given.
            let reps = whole(
                "--reps",
                &reps,
                1..=MAX_REPS,
                &format!("1 to {MAX_REPS} repetitions"),
            )?;
            match points {
                Some(path) => bench::run_points(&path, reps, &mut std::io::stdout())?,
                None => bench::run(quick, &mut std::io::stdout())?,
            }
        }
    }
    Ok(())
}

/// The most repetitions `bench --points` times (each is one evaluation of every kernel).
pub(crate) const MAX_REPS: usize = 100_000;

/// The most worker threads `--threads` starts (each is a real thread with its own stack;
/// far beyond the cores they only cost).
pub(crate) const MAX_THREADS: usize = 1024;

/// `--threads` as typed: every refusal (a negative count, zero, too many, not a number)
/// states the one range accepted, the range its help gives.
fn threads(typed: &str) -> Result<usize> {
    whole(
        "--threads",
        typed,
        1..=MAX_THREADS,
        &format!("1 to {MAX_THREADS} threads"),
    )
}

/// `stillpoint eval`: the flags become one library [`Request`], whose resolution
/// ([`Request::resolve_eval_as`]) says how the points are measured or refuses the
/// combination; then each file's figures.
fn eval_command(c: Command) -> Result<()> {
    let Command::Eval {
        files,
        json,
        bounds,
        exact,
        region,
        bbox,
        shape,
        var,
        space,
        correlation,
        constraint,
        mixture,
    } = c
    else {
        bail!("eval: not this subcommand");
    };
    let text = |v: &Option<String>| v.as_deref().map(Arg::from);
    let items = space_items(&var, space.as_deref())?;
    let request = Request {
        bounds: text(&bounds),
        exact: exact.then_some(Arg::Bool(true)),
        region: text(&region),
        bbox: text(&bbox),
        shape: text(&shape),
        space: items,
        correlation: text(&correlation),
        constraints: (!constraint.is_empty()).then(|| Arg::Texts(constraint.clone())),
        mixture: mixture.then_some(Arg::Bool(true)),
        ..Request::default()
    };
    let spell = spelling(space.is_some());
    let measure = request.resolve_eval_as(&spell)?;
    match &measure {
        stillpoint::pipeline::evaluation::Measure::Design(design) => {
            let sums = stillpoint::quality::metrics::Sums::asked(exact);
            return design_eval(&files, json, design, sums);
        }
        stillpoint::pipeline::evaluation::Measure::Region { .. }
        | stillpoint::pipeline::evaluation::Measure::Constrained { .. } => {
            return each_in_region(&files, json, |points| Ok(measure.json(points, &spell)?))
        }
        stillpoint::pipeline::evaluation::Measure::Cube { .. } => {}
    }
    let mut evaluated = Vec::new();
    for file in &files {
        let source = file.display().to_string();
        let points = measure.unit_points(io::read_points(file)?, &source, &spell)?;
        points.check_unit_cube().map_err(|e| {
            anyhow::anyhow!(
                "{source}: {e}; eval measures points in [0, 1]^s: points scaled to a box are \
                 read back with --bounds LO1,HI1,..., a design's values with its --var or \
                 --space"
            )
        })?;
        let v = measure.json(&points, &spell)?;
        evaluated.push((file.clone(), points, v));
    }
    match (json, evaluated.as_slice()) {
        (true, [(_, _, v)]) => outln!("{}", serde_json::to_string_pretty(v)?),
        (false, [(file, points, v)]) => out!("{}", eval_table(file, points, v)),
        (true, many) => {
            let all: Vec<Value> = many
                .iter()
                .map(|(f, _, v)| {
                    let mut v = v.clone();
                    v["file"] = json!(f.display().to_string());
                    v
                })
                .collect();
            outln!("{}", serde_json::to_string_pretty(&all)?)
        }
        (false, many) => out!("{}", eval_comparison(many)),
    }
    Ok(())
}

/// Each file's region figures from `figures`: a table per file, or JSON (one object, or
/// an array of them for several files).
fn each_in_region(
    files: &[PathBuf],
    json: bool,
    figures: impl Fn(&PointSet) -> Result<Value>,
) -> Result<()> {
    let mut all = Vec::new();
    for file in files {
        let points = io::read_points(file)?;
        let mut v = figures(&points).with_context(|| format!("{}", file.display()))?;
        v["file"] = json!(file.display().to_string());
        if !json {
            out!("{}", stillpoint::quality::region::region_eval_text(&v));
        }
        all.push(v);
    }
    match (json, all.as_slice()) {
        (true, [v]) => outln!("{}", serde_json::to_string_pretty(v)?),
        (true, many) => outln!("{}", serde_json::to_string_pretty(many)?),
        (false, _) => {}
    }
    Ok(())
}

/// `stillpoint compare`.
fn compare_command(c: Command) -> Result<()> {
    let Command::Compare {
        cases,
        steps,
        energy,
        out,
        quick,
    } = c
    else {
        bail!("compare: not this subcommand");
    };
    // 0 steps compares the starts: the run takes it, unlike generate's --steps.
    let steps = whole(
        flag(Opt::steps),
        &steps,
        0..=usize::MAX,
        "a whole number of steps ≥ 0",
    )?;
    let mut settings = stillpoint_paper::compare::CompareSettings {
        steps,
        discrepancy: DiscrepancyKind::parse(&energy).map_err(|_| {
            // The names the help lists, from the same declaration.
            let names = stillpoint::pipeline::options::words::discrepancies();
            let (last, rest) = names.split_last().expect("discrepancies are declared");
            anyhow::anyhow!(
                "invalid --energy = {energy}: expected {} or {last}",
                rest.join(", ")
            )
        })?,
        ..Default::default()
    };
    if quick {
        settings.cases = vec![(2, 200), (3, 200)];
        settings.steps = steps.min(200);
    }
    if let Some(c) = cases {
        settings.cases = parse_cases(&c)?;
    }
    let table = stillpoint_paper::compare::run_and_write(&settings, &out, true)?;
    out!("{table}");
    Ok(())
}

/// `stillpoint baseline`.
fn baseline_command(c: Command) -> Result<()> {
    let Command::Baseline {
        name,
        n,
        s,
        output,
        seed,
        list,
        json,
        bounds,
    } = c
    else {
        bail!("baseline: not this subcommand");
    };
    // Every value is read before --list, which takes none of them: a value refused with
    // the list is refused without it too.
    let n: Option<usize> = n.map(|t| declared(Opt::n, &t)).transpose()?;
    let s: Option<usize> = s.map(|t| declared(Opt::s, &t)).transpose()?;
    let seed: u64 = declared(Opt::seed, &seed)?;
    if list {
        for b in Baseline::all() {
            outln!("{} ({}):\n  {}\n", b.name(), b.label(), b.describe());
        }
        return Ok(());
    }
    let (Some(name), Some(n), Some(s)) = (name, n, s) else {
        bail!("missing NAME, -n N or -s S (see stillpoint baseline --help)");
    };
    if let Some(out) = &output {
        check_writable(out, "-o")?;
        check_points_extension(out, "-o")?;
    }
    let b = Baseline::parse(&name)?;
    let scale = match &bounds {
        Some(text) => Some(parse_bounds(text, s)?),
        None => None,
    };
    let points = b.generate(n, s, seed)?;
    if b == Baseline::Sobol && !n.is_power_of_two() {
        noteln!(
            "note: n = {n} is not a power of two; Sobol' points are balanced (one per \
             elementary interval, stratified in every coordinate) only at n = 2^k"
        );
    }
    let metrics = (n <= METRICS_LIMIT).then(|| Metrics::compute(&points));
    let mut meta = json!({
        "generator": format!("stillpoint baseline {}", b.name()),
        "version": env!("CARGO_PKG_VERSION"),
        "parameters": {
            "baseline": b.name(),
            "label": b.label(),
            "n": n,
            "s": s,
            "randomized": b.is_randomized(),
        },
        "metrics": metrics.as_ref().map(metrics_json),
    });
    // The seed and the box under their options' names.
    meta[Opt::seed.name()] = json!(b.is_randomized().then_some(seed));
    meta["parameters"][Opt::bounds.name()] = json!(bounds);
    // The metrics are the unit cube's; the points written are in the box.
    let points = match &scale {
        Some(b) => b.scale(&points)?,
        None => points,
    };
    if json {
        let mut v = meta.clone();
        match &output {
            Some(path) => {
                io::write_points(path, &points, &meta)?;
                v["output"] = json!(path);
            }
            None => v["points"] = points_json(&points),
        }
        outln!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    match &output {
        Some(path) => {
            io::write_points(path, &points, &meta)?;
            let quality = match metrics {
                Some(m) => format!(
                    "D_MD {:.6}, D_L2* {:.6}, centred L2 {:.6}, wrap-around L2 {:.6}, \
                     minimum distance {:.6}",
                    m.modified_l2, m.star_l2, m.centered_l2, m.wrap_around_l2, m.min_distance
                ),
                None => format!("metrics skipped above n = {METRICS_LIMIT}"),
            };
            outln!(
                "{} ({}), n = {n}, s = {s}: {quality}; written to {}",
                b.name(),
                b.label(),
                path.display()
            );
        }
        None => out!("{}", io::to_csv_string(&points, &meta)),
    }
    Ok(())
}

/// `stillpoint integrate`.
fn integrate_command(c: Command) -> Result<()> {
    let Command::Integrate { files, json, quad } = c else {
        bail!("integrate: not this subcommand");
    };
    if files.is_empty() {
        return quad_command(quad, json);
    }
    if quad.expr.is_some() {
        return files_command(&files, quad, json);
    }
    if let Some(flag) = quad.first_expr_only() {
        bail!(
            "invalid {flag} with a point file: it applies to --expr only (a file is \
             integrated as it is)"
        );
    }
    let [file] = files.as_slice() else {
        bail!(
            "invalid FILE: {} files without --expr; the eight test functions are \
             integrated with one file (give --expr EXPR to average an expression over \
             several randomised files)",
            files.len()
        );
    };
    let points = io::read_points(file)?;
    points
        .check_unit_cube()
        .with_context(|| format!("{}", file.display()))?;
    if json {
        let mut v = stillpoint::quality::integrands::report_json(&points)?;
        v["file"] = json!(file);
        outln!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let report = stillpoint::quality::integrands::integrate(&points)?;
        let fns = stillpoint::quality::integrands::TestFunction::all();
        outln!(
            "{}: n = {}, s = {}; every exact integral is 0, so |estimate| is the error\n",
            file.display(),
            points.n(),
            points.s()
        );
        outln!(
            "  {:<4} {:>14} {:>12}   integrand",
            "",
            "estimate",
            "|error|"
        );
        for (f, e) in fns.iter().zip(report.estimates) {
            match e {
                Some(v) => outln!(
                    "  {:<4} {:>14.6e} {:>12.3e}   {}",
                    f.name(),
                    v,
                    v.abs(),
                    f.formula()
                ),
                None => outln!(
                    "  {:<4} {:>14} {:>12}   {} (needs s ≥ 2)",
                    f.name(),
                    "—",
                    "—",
                    f.formula()
                ),
            }
        }
    }
    Ok(())
}

/// `stillpoint study`.
fn study_command(c: Command) -> Result<()> {
    let Command::Study {
        name,
        quick,
        out,
        seed,
        quiet,
    } = c
    else {
        bail!("study: not this subcommand");
    };
    let seed: u64 = declared(Opt::seed, &seed)?;
    let studies: Vec<Study> = if name.trim().eq_ignore_ascii_case("all") {
        Study::all().to_vec()
    } else {
        vec![Study::parse(&name)?]
    };
    let out = out.unwrap_or_else(|| {
        if quick {
            PathBuf::from("results/quick")
        } else {
            PathBuf::from("results")
        }
    });
    for study in studies {
        let mut opts = StudyOptions::new(quick, out.join(study.name()));
        opts.catalog_dir = out.join("catalog");
        opts.seed = seed;
        let mut log = |line: &str| {
            if !quiet {
                noteln!("{line}");
            }
        };
        let result = studies::run(study, &opts, &mut log)?;
        out!("{}", result.markdown);
        noteln!(
            "{}: {} file(s) in {} ({})",
            study.name(),
            result.files.len(),
            opts.out.display(),
            studies::human_seconds(result.seconds)
        );
    }
    Ok(())
}

/// `stillpoint plot`.
fn plot_command(c: Command) -> Result<()> {
    let Command::Plot {
        file,
        output,
        dims,
        region,
        bbox,
        shape,
        trajectory,
        title,
        split,
    } = c
    else {
        bail!("plot: not this subcommand");
    };
    check_writable(&output, "-o")?;
    check_picture_extension(&output, "-o")?;
    // The picture never replaces what it draws (a point file named .png is read by its
    // content, and would be lost).
    let polytope = shape
        .as_deref()
        .and_then(|t| t.strip_prefix("polytope:"))
        .map(std::path::Path::new);
    check_distinct(
        &[("-o", Some(output.as_path()))],
        &[
            ("FILE", file.as_deref()),
            (flag(Opt::trajectory), trajectory.as_deref()),
            ("--shape polytope", polytope),
        ],
    )?;
    match (trajectory, file) {
        (Some(traj), _) => plot_trajectory(&traj, &output, title)?,
        (None, Some(file)) => {
            let spec = RegionSpec {
                region: region.as_deref(),
                bbox: bbox.as_deref(),
                shape: shape.as_deref(),
            };
            plot_points(&file, &output, dims, spec, title, split)?
        }
        (None, None) => {
            bail!("missing FILE: the point file to draw (or --trajectory TRAJ)")
        }
    }
    Ok(())
}
