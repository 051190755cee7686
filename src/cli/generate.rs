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
            ("--resume", resume_file),
            ("--shape polytope", polytope),
        ],
    )?;
    if tolerance.is_nan() || tolerance < 0.0 {
        bail!("invalid --tolerance = {tolerance}: expected a number ≥ 0");
    }
    if let Some(p) = p {
        if !(p > 0.0 && p.is_finite()) {
            bail!("invalid --p = {p}: expected a finite number > 0");
        }
    }
    let plan = checkpoint_plan(checkpoint, checkpoint_every, resume, Value::Null, quiet)?;
    let mut progress = Progress::new(quiet);
    // How the command line named the region: recorded in checkpoints (a resume in
    // another region is refused) and in the file header.
    let given = json!({"--region": region, "--box": bbox, "--shape": shape});
    let cfg = if region.is_some() || shape.is_some() {
        let domain = region_domain(region.as_deref(), bbox.as_deref(), shape.as_deref(), s)?;
        let n = n.context("missing -n N: the number of points (at least 1)")?;
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
        cfg
    };
    // Say so before a long run starts, with what makes it cheaper.
    if !quiet {
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
    let meta = file_header(&report, &cfg, &given)?;
    // The run's outputs appear together or not at all.
    let staging = io::Staging::begin();
    if let Some(path) = &trajectory {
        write_trajectory(path, &report.energy_name, &report.output)?;
    }
    if let Some(path) = &plot {
        let domain: Arc<dyn Domain> = match cfg.region() {
            Some(d) => d.clone(),
            None => Arc::new(crate::PeriodicCube::new(cfg.s)?),
        };
        plot_start_result(path, &report.start, &report.output.points, domain.as_ref())?;
    }
    let summary = match (json, cfg.region().is_some()) {
        (true, false) => report_json(&report, &cfg)?,
        (true, true) => region_json(&report, &cfg)?,
        (false, false) => Value::String(report_table(&report, &cfg, output.as_ref())?),
        (false, true) => Value::String(region_table(&report, &cfg, output.as_ref())?),
    };
    emit(
        &report.output.points,
        &meta,
        output.as_ref(),
        summary,
        staging,
    )?;
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
