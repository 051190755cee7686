//! `stillpoint generate`: arguments to a run configuration, the run, its outputs.

use super::*;

/// A run estimated to take longer than this says so before it starts.
const LONG_RUN_SECONDS: f64 = 30.0;

/// Largest n whose O(n² s) metrics a baseline file's header records (above it they would
/// take longer than generating the points by far).
pub(crate) const METRICS_LIMIT: usize = 20_000;

/// `stillpoint generate`: a cube or region run with its outputs. Every argument and
/// output path is checked before any work is done, and outputs are written only after
/// the run succeeded.
pub(crate) fn generate(a: GenerateArgs) -> Result<()> {
    let GenerateArgs {
        n,
        s,
        output,
        goal,
        method,
        target,
        randomize,
        extend,
        nested,
        bounds,
        energy,
        region,
        bbox,
        shape,
        plot,
        integrator,
        q,
        p,
        precision,
        steps,
        init,
        seed,
        kappa,
        restart,
        tolerance,
        polish,
        shifts,
        log_every,
        trajectory,
        checkpoint,
        checkpoint_every,
        resume,
        json,
        quiet,
        progress,
    } = a;
    if let Some(out) = &output {
        check_writable(out, "-o")?;
        check_points_extension(out, "-o")?;
    }
    if let Some(out) = &plot {
        check_writable(out, "--plot")?;
        check_picture_extension(out, "--plot")?;
    }
    if let Some(out) = &trajectory {
        check_writable(out, "--trajectory")?;
    }
    let init_file = init
        .as_deref()
        .filter(|i| !["halton", "random"].contains(i))
        .map(std::path::Path::new);
    let resume_file = match &resume {
        Some(Some(r)) => Some(r.as_path()),
        Some(None) => checkpoint.as_deref(),
        None => None,
    };
    let polytope = shape
        .as_deref()
        .and_then(|t| t.strip_prefix("polytope:"))
        .map(std::path::Path::new);
    check_distinct(
        &[
            ("-o", output.as_deref()),
            ("--plot", plot.as_deref()),
            ("--trajectory", trajectory.as_deref()),
            ("--checkpoint", checkpoint.as_deref()),
        ],
        &[
            ("--init", init_file),
            ("--extend", extend.as_deref()),
            ("--resume", resume_file),
            ("--shape polytope", polytope),
        ],
    )?;
    if let Some(t) = tolerance {
        if t.is_nan() || t < 0.0 {
            bail!("invalid --tolerance = {t}: expected a number ≥ 0");
        }
    }
    // The options of the paper's pipeline (custom runs): any of them selects it.
    let expert: Vec<&str> = [
        ("--energy", energy.is_some()),
        ("--integrator", integrator.is_some()),
        ("--q", q.is_some()),
        ("--p", p.is_some()),
        ("--precision", precision.is_some()),
        ("--init", init.is_some()),
        ("--kappa", kappa.is_some()),
        ("--restart", restart.is_some()),
        ("--polish", polish.is_some()),
        ("--tolerance", tolerance.is_some()),
        ("--shifts", shifts.is_some()),
        ("--log-every", log_every.is_some()),
        ("--trajectory", trajectory.is_some()),
        ("--checkpoint", checkpoint.is_some()),
        ("--resume", resume.is_some()),
        (
            "--steps",
            steps.is_some() && goal != Some(GoalArg::SpaceFilling),
        ),
    ]
    .into_iter()
    .filter_map(|(flag, given)| given.then_some(flag))
    .collect();
    let in_region = region.is_some() || shape.is_some();
    let goal = run::choose_goal(
        goal.map(|g| match g {
            GoalArg::Integration => run::GoalName::Integration,
            GoalArg::SpaceFilling => run::GoalName::SpaceFilling,
        }),
        method == Some(MethodArg::Paper),
        &expert,
        in_region,
        target,
        |name| format!("--{name}"),
    )?;
    let paper_dem = stillpoint::integrators::Dem::default();
    let (kappa, restart) = (
        kappa.unwrap_or(paper_dem.kappa),
        restart.unwrap_or(paper_dem.restart),
    );
    let (tolerance, shifts) = (tolerance.unwrap_or(1e-12), shifts.unwrap_or(64));
    let (polish, integrator) = (
        polish.unwrap_or(PolishChoice(None)),
        integrator.unwrap_or(Solver::Dem),
    );
    if let Some(p) = p {
        if !(p > 0.0 && p.is_finite()) {
            bail!("invalid --p = {p}: expected a finite number > 0");
        }
    }
    let plan = checkpoint_plan(checkpoint, checkpoint_every, resume, Value::Null, quiet)?;
    let mut progress = Progress::new(quiet, progress);
    // How the command line named the region: recorded in checkpoints (a resume in
    // another region is refused) and in the file header.
    let given = json!({"--region": region, "--box": bbox, "--shape": shape});
    let cfg = if region.is_some() || shape.is_some() {
        let domain = region_domain(region.as_deref(), bbox.as_deref(), shape.as_deref(), s)?;
        let n = n.context("missing -n N: the number of points (at least 1)")?;
        if bounds.is_some() {
            bail!("invalid --bounds in a region: a region's points are in its own coordinates already (--bounds scales the unit cube)");
        }
        if nested.is_some() {
            bail!("invalid --nested in a region: nested sets are made for the integration goal in the cube; grow a region's set with --extend");
        }
        let old = match &extend {
            Some(path) => Some(io::read_points(path).context("--extend")?),
            None => None,
        };
        let n = n + old.as_ref().map_or(0, |p| p.n());
        if let Some(precision) = precision {
            bail!(
                "invalid --precision = {} for a region: it sets U_{{q,p}}'s distance, which \
                 region energies do not use",
                precision.label()
            );
        }
        let mut cfg = GenerateConfig::in_region(domain, n);
        cfg.space = run::Space::Region {
            domain: cfg.region().cloned().context("a region")?,
            description: json!({"expression": region, "box": bbox, "shape": shape}),
        };
        cfg.energy = match energy.unwrap_or(EnergyArg::EInfG) {
            EnergyArg::EInfG => EnergyKind::EInfG,
            EnergyArg::EInf => EnergyKind::EInf,
            EnergyArg::EpG => EnergyKind::EpG(p.unwrap_or(8.0)),
            other => bail!(
                "invalid --energy = {} for a region: expected e-inf-g (eq. 56), \
                 e-inf or e-p-g",
                other.name()
            ),
        };
        cfg.init = match init.as_deref().unwrap_or("random") {
            "random" => Init::Random,
            "halton" => Init::Halton,
            path => Init::Points(io::read_points(std::path::Path::new(path)).context("--init")?),
        };
        cfg.seed = seed;
        cfg.solver = integrator;
        if let Some(steps) = steps {
            cfg.steps = steps;
        }
        cfg.dem.kappa = kappa;
        cfg.dem.tolerance = tolerance;
        if plot.is_some() && cfg.s < 2 {
            bail!("invalid --plot: the region has dimension 1; plots need s ≥ 2");
        }
        if randomize.is_some() {
            bail!(
                "invalid --randomize in a region: a random shift would carry points out of it \
                 (the cube only)"
            );
        }
        cfg.extend = old;
        cfg
    } else {
        if bbox.is_some() {
            bail!("--box needs --region EXPR or --shape polytope:FILE");
        }
        let init = match init.as_deref().unwrap_or("halton") {
            "halton" => Init::Halton,
            "random" => Init::Random,
            path => {
                let points = io::read_points(std::path::Path::new(path)).context("--init")?;
                points
                    .check_unit_cube()
                    .with_context(|| format!("--init: {path}"))?;
                Init::Points(points)
            }
        };
        let grow = matches!(goal, run::Goal::Integration(_));
        if (extend.is_some() || nested.is_some()) && !grow {
            bail!(
                "invalid {}: growing a set needs the integration goal (no --method paper, \
                 --goal space-filling or paper options)",
                if extend.is_some() {
                    "--extend"
                } else {
                    "--nested"
                }
            );
        }
        let old = match &extend {
            Some(path) => {
                let points = io::read_points(path).context("--extend")?;
                points
                    .check_unit_cube()
                    .with_context(|| format!("--extend: {}", path.display()))?;
                Some(points)
            }
            None => None,
        };
        let stages: Vec<usize> = match &nested {
            Some(text) => {
                let list: Vec<usize> = text
                    .split(',')
                    .map(|t| t.trim().parse::<usize>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| {
                        anyhow::anyhow!(
                            "invalid --nested = {text}: expected increasing sizes N1,N2,... \
                             (whole numbers ≥ 1)"
                        )
                    })?;
                if list.is_empty() || list[0] == 0 || list.windows(2).any(|w| w[1] <= w[0]) {
                    bail!("invalid --nested = {text}: expected increasing sizes N1 < N2 < ..., N1 ≥ 1");
                }
                list
            }
            None => Vec::new(),
        };
        let (n, s) = match (&old, stages.last()) {
            (Some(p), _) => {
                let m = n.context("missing -n M: the number of points to add to --extend")?;
                if s.is_some_and(|s| s != p.s()) {
                    bail!(
                        "invalid -s = {}: the --extend file has {} coordinates",
                        s.unwrap_or(0),
                        p.s()
                    );
                }
                (Some(p.n() + m), Some(p.s()))
            }
            (None, Some(&last)) => (Some(last), s),
            (None, None) => (n, s),
        };
        let (n, s) = match (&init, n, s) {
            (Init::Points(p), n, s) => (n.unwrap_or(p.n()), s.unwrap_or(p.s())),
            (_, Some(n), Some(s)) => (n, s),
            (_, None, _) => bail!("missing -n N: the number of points (at least 1)"),
            (_, _, None) => bail!("missing -s S: the dimension (at least 1)"),
        };
        if plot.is_some() && s < 2 {
            bail!("invalid --plot with -s = {s}: plots need s ≥ 2");
        }
        let mut cfg = GenerateConfig::new(n, s);
        cfg.energy = match energy.unwrap_or(EnergyArg::Uqp) {
            EnergyArg::Uqp => EnergyKind::Uqp,
            EnergyArg::EInf => EnergyKind::EInf,
            e @ (EnergyArg::EInfG | EnergyArg::EpG) => bail!(
                "invalid --energy = {} in the cube: e-inf-g and e-p-g need --region or \
                 --shape; the cube accepts uqp, e-inf, l2star, md, cd, periodic",
                e.name()
            ),
            EnergyArg::L2star => EnergyKind::Discrepancy(DiscrepancyKind::StarL2),
            EnergyArg::Md => EnergyKind::Discrepancy(DiscrepancyKind::ModifiedL2),
            EnergyArg::Cd => EnergyKind::Discrepancy(DiscrepancyKind::CenteredL2),
            EnergyArg::Periodic => EnergyKind::Discrepancy(DiscrepancyKind::WrapAroundL2),
        };
        cfg.solver = integrator;
        cfg.q = match q.as_deref() {
            Some(text) => Some(Distance::parse(text).map_err(|_| {
                anyhow::anyhow!(
                    "invalid --q = {text}: expected a number in (0, ∞), `inf` (the torus \
                     distance) or `E` (Euclidean)"
                )
            })?),
            None => None,
        };
        cfg.p = p;
        if let Some(precision) = precision {
            cfg.precision = precision;
        }
        cfg.init = init;
        cfg.seed = seed;
        cfg.steps = steps.unwrap_or(1000);
        cfg.dem.kappa = kappa;
        cfg.dem.restart = restart;
        cfg.dem.tolerance = tolerance;
        cfg.shifts = shifts;
        cfg.polish = polish.0;
        cfg.log_every = log_every.unwrap_or(if trajectory.is_some() { 10 } else { 0 });
        cfg.goal = goal;
        cfg.randomize = randomize;
        cfg.extend = old;
        cfg.nested = stages;
        cfg
    };
    if let Some(text) = &bounds {
        parse_bounds(text, cfg.s)?;
    }
    // Say what is unusual before the run starts (even with -q, which hides progress).
    if cfg.goal == run::Goal::Paper {
        if matches!(cfg.energy, EnergyKind::Discrepancy(_)) && cfg.solver == Solver::Dem {
            eprintln!(
                "note: the DEM is unstable on a discrepancy energy and returns its lowest early \
                 state; --integrator lbfgs is the solver for discrepancy energies"
            );
        }
        let fit = paper_qp(cfg.n, cfg.s);
        if cfg.region().is_none()
            && cfg.energy == EnergyKind::Uqp
            && (cfg.q.is_none() || cfg.p.is_none())
            && !fit.in_fitted_range
        {
            eprintln!(
                "note: (n, s) = ({}, {}) lies outside the range eq. 48 was fitted on \
                 (1 ≤ s ≤ 20, s ≤ n ≤ 1500): q and p are extrapolated{}",
                cfg.n,
                cfg.s,
                if fit.q != fit.raw_q || fit.p != fit.raw_p {
                    " and clamped into [0.05, 1]"
                } else {
                    ""
                }
            );
        }
    }
    // Say so before a long run starts, with what makes it cheaper.
    if !quiet && !matches!(cfg.goal, run::Goal::Integration(_)) {
        let estimate = run::estimate_seconds(&cfg)?;
        if estimate > LONG_RUN_SECONDS {
            eprintln!(
                "note: this run may take about {} (n = {}, s = {}, up to {} steps, timed on \
                 this machine); --steps K or a smaller -n make it cheaper",
                studies::human_seconds(estimate),
                cfg.n,
                cfg.s,
                cfg.steps
            );
        }
    }
    let report = run::generate_with(&cfg, plan.as_ref(), |e| progress.event(e))?;
    progress.finish();
    let mut meta = file_header(&report, &cfg, &given)?;
    // The points are written in the user's box; every figure stays the unit cube's.
    let written = match &bounds {
        Some(text) => {
            let (lo, hi) = parse_bounds(text, cfg.s)?;
            meta["parameters"]["bounds"] = json!(text);
            scale_to(&report.output.points, &lo, &hi)?
        }
        None => report.output.points.clone(),
    };
    // The run's outputs appear together or not at all.
    let staging = io::Staging::begin();
    if let Some(path) = &trajectory {
        write_trajectory(path, &report.energy_name, &report.output)?;
    }
    if let Some(path) = &plot {
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
        )?;
    }
    let summary = match (json, cfg.region().is_some()) {
        (true, false) => report_json(&report, &cfg)?,
        (true, true) => region_json(&report, &cfg)?,
        (false, false) => Value::String(report_table(&report, &cfg, output.as_ref())?),
        (false, true) => Value::String(region_table(&report, &cfg, output.as_ref())?),
    };
    emit(&written, &meta, output.as_ref(), summary, staging)?;
    Ok(())
}

/// The checkpoint plan of `--checkpoint FILE [--checkpoint-every K] [--resume [FILE]]`.
pub(crate) fn checkpoint_plan(
    checkpoint: Option<PathBuf>,
    every: usize,
    resume: Option<Option<PathBuf>>,
    extra: Value,
    quiet: bool,
) -> Result<Option<run::CheckpointPlan>> {
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
    if every == 0 {
        bail!("invalid --checkpoint-every = 0: expected a number of steps ≥ 1");
    }
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
    check_writable(&path, "--checkpoint")?;
    if resume_path.is_none() && path.exists() && !quiet {
        eprintln!(
            "note: {} exists; this run starts afresh and replaces it (add --resume to \
             continue from it)",
            path.display()
        );
    }
    Ok(Some(run::CheckpointPlan {
        path,
        every,
        resume: resume_path,
        extra,
        names: flag_name,
    }))
}
