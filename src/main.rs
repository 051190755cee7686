//! The `stillpoint` command: generate evenly spread point sets, evaluate and integrate
//! with any point file, write the classic sequences, reproduce the paper's studies, and
//! benchmark the kernels.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Value};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use stillpoint::energies::discrepancy::DiscrepancyKind;
use stillpoint::energies::region::ImplicitRegion;
use stillpoint::energies::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex};
use stillpoint::energies::Domain;
use stillpoint::energies::{paper_qp, Distance, Energy, Precision, Uqp};
use stillpoint::metrics::Metrics;
use stillpoint::regions::{
    generate_in_region_with, RegionConfig, RegionEnergy, RegionInit, RegionReport,
};
use stillpoint::run::{self, CubeEnergy, GenerateConfig, GenerateReport, Init, Solver};
use stillpoint::sequences::Baseline;
use stillpoint::studies::{self, Study, StudyOptions};
use stillpoint::{bench, io, PointSet};

#[derive(Parser)]
#[command(
    name = "stillpoint",
    version,
    about = "Evenly spread point sets in [0,1]^s from the static solution of a damped \
             many-body problem (the DEM), with the numbers that prove their quality."
)]
struct Cli {
    /// Worker threads (default: all cores). Results are the same bytes for any count.
    #[arg(long, global = true, value_name = "T")]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

/// The options of `stillpoint generate`.
#[derive(clap::Args)]
struct GenerateArgs {
    /// Number of points n ≥ 1 (taken from --init FILE when omitted).
    #[arg(short = 'n', value_name = "N")]
    n: Option<usize>,
    /// Dimension s ≥ 1 (taken from --init FILE when omitted).
    #[arg(short = 's', value_name = "S")]
    s: Option<usize>,
    /// Output file: .csv (default), .tsv, .json or .npy by extension. Without it the
    /// points go to standard output as CSV and the report to standard error.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
    /// The potential energy: `uqp` (U_{q,p}, the cube's default), `e-inf` (U_{E,∞},
    /// maximin; with --q E in the closed cube, else on the torus), `e-inf-g`
    /// (U_{E,∞,g} of eq. 56, a region's default), `e-p-g` (smooth U_{E,p,g} for a
    /// region, p from --p, default 8).
    #[arg(long, value_name = "NAME")]
    energy: Option<String>,
    /// A region {x : g(x) ≤ 0}: g as an expression in x1..xs (or x, y, z), e.g.
    /// "|x| + 2*|y| - 5". Needs --box.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    region: Option<String>,
    /// Bounding box of --region (or of a polytope): LO1,HI1,LO2,HI2,...
    #[arg(long = "box", value_name = "LO1,HI1,...", allow_hyphen_values = true)]
    bbox: Option<String>,
    /// A built-in region: `ball:R[@C1,C2,..]`, `ellipsoid:A1,A2,..[@C1,..]`,
    /// `box:LO1,HI1,LO2,HI2,..`, `simplex` (dimension from -s), or `polytope:FILE`
    /// (rows a1 .. as b meaning a·x ≤ b; needs --box).
    #[arg(long, value_name = "SHAPE", allow_hyphen_values = true)]
    shape: Option<String>,
    /// Draw the start beside the result, with the region's boundary (PNG or SVG by
    /// extension; the first two coordinates).
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// q of U_{q,p}: a number > 0, `inf` (torus distance) or `E` (Euclidean).
    /// Default: eq. 48 of the paper for (n, s).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    q: Option<String>,
    /// p of U_{q,p}: a number > 0. Default: eq. 48 of the paper for (n, s).
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    p: Option<f64>,
    /// How U_{q,p}'s distance is evaluated during the run for 0.01 ≤ q ≤ 2: `fast` (a
    /// table of cubics, each coordinate's h² within 4e-9; about twice as fast) or `full`
    /// (within 1e-12). Reported energies are always full. Default: fast.
    #[arg(long, value_name = "fast|full")]
    precision: Option<String>,
    /// The solver: `dem` (the paper's damped dynamics) or `lbfgs` (argmin's L-BFGS
    /// with restarts; in the cube only).
    #[arg(long, default_value = "dem", value_name = "dem|lbfgs")]
    integrator: String,
    /// Step budget of the DEM (default 1000 in the cube, as in the paper; 10 000 in a
    /// region, where U_{E,∞,g} moves only its active elements at each step).
    #[arg(long, value_name = "K")]
    steps: Option<usize>,
    /// Start: `halton` (plain, indices 1..n; the cube's default), `random` (a region's
    /// default: uniform in the box, the first n inside), or a point file.
    #[arg(long, value_name = "halton|random|FILE")]
    init: Option<String>,
    /// Seed for the random start.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// κ of eq. 39: `auto` (trial from 100, doubled while the energy fails to fall)
    /// or a fixed number ≥ 1.
    #[arg(
        long,
        default_value = "auto",
        value_name = "auto|K",
        allow_hyphen_values = true
    )]
    kappa: String,
    /// Restart for unbiasedness (§4.3): `auto` (ε_p = 2/n), `off`, or ε_p > 0.
    #[arg(
        long,
        default_value = "auto",
        value_name = "auto|off|EPS",
        allow_hyphen_values = true
    )]
    restart: String,
    /// Polish the result with L-BFGS on a squared discrepancy: `md`, `l2star`, `cd`,
    /// `periodic`, or `none`. The best points we know how to make: the DEM spreads the
    /// points, the shift places them, the polish lowers the chosen discrepancy.
    #[arg(long, default_value = "none", value_name = "KIND")]
    polish: String,
    /// Stop early when every coordinate step and every force step |G f|/A0 is below
    /// this (0: always use the whole budget).
    #[arg(
        long,
        default_value_t = 1e-12,
        value_name = "TOL",
        allow_hyphen_values = true
    )]
    tolerance: f64,
    /// Periodic shifts tried after the DEM (0: none). The energy is unchanged by a
    /// shift on the torus, the discrepancies are not: the shift with the smallest
    /// modified L2 discrepancy is kept.
    #[arg(long, default_value_t = 64, value_name = "K")]
    shifts: usize,
    /// Record D_L2* and D_MD every K steps in the trajectory (default 10 with
    /// --trajectory, else never).
    #[arg(long, value_name = "K")]
    log_every: Option<usize>,
    /// Write the trajectory (energy each step, discrepancies every --log-every steps)
    /// as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    trajectory: Option<PathBuf>,
    /// Save the DEM's whole state to FILE every --checkpoint-every steps (atomically),
    /// so that an interrupted run can be continued with --resume.
    #[arg(long, value_name = "FILE")]
    checkpoint: Option<PathBuf>,
    /// Steps between two checkpoints.
    #[arg(long, default_value_t = 100, value_name = "K")]
    checkpoint_every: usize,
    /// Continue from a checkpoint (FILE, or the --checkpoint file when no FILE is
    /// given). Every other option must be as in the run that wrote it; the result is
    /// the same bytes as an uninterrupted run.
    #[arg(long, value_name = "FILE", num_args = 0..=1)]
    resume: Option<Option<PathBuf>>,
    /// Print the report as one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(long, short = 'q')]
    quiet: bool,
}

// Parsed once per process, so the size of the largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Generate n points in [0,1)^s with the DEM and print their quality before and after.
    Generate(Box<GenerateArgs>),
    /// Draw a point file (a scatter plot for s = 2, a matrix of 2-D projections of the
    /// first --dims coordinates for s > 2), or a run's trajectory (--trajectory), as PNG
    /// or SVG.
    Plot {
        /// The point file (CSV, TSV, whitespace, JSON, .npy).
        #[arg(value_name = "FILE", required_unless_present = "trajectory")]
        file: Option<PathBuf>,
        /// The picture: .png or .svg.
        #[arg(short = 'o', long = "output", value_name = "OUT")]
        output: PathBuf,
        /// Coordinates drawn for s > 2: the first K, as a K × K matrix of projections
        /// (histograms on the diagonal). Default min(s, 4).
        #[arg(long, value_name = "K")]
        dims: Option<usize>,
        /// Draw the boundary of the region {x : g(x) ≤ 0} (with --box), as in generate.
        #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
        region: Option<String>,
        /// The plotted box, and the bounding box of --region: LO1,HI1,LO2,HI2,...
        #[arg(long = "box", value_name = "LO1,HI1,...", allow_hyphen_values = true)]
        bbox: Option<String>,
        /// Draw the boundary of a built-in region, as in generate.
        #[arg(long, value_name = "SHAPE", allow_hyphen_values = true)]
        shape: Option<String>,
        /// Draw a trajectory written by `generate --trajectory` instead: energy and
        /// discrepancies against step and against time.
        #[arg(long, value_name = "TRAJ", conflicts_with_all = ["file", "dims", "region", "shape", "bbox"])]
        trajectory: Option<PathBuf>,
        /// Title above the picture (default: the file name).
        #[arg(long)]
        title: Option<String>,
    },
    /// Print the quality of any point file (CSV, TSV, whitespace, JSON, .npy).
    Eval {
        /// The point file; coordinates must lie in [0, 1].
        file: PathBuf,
        /// Print one JSON object (keys documented in the README).
        #[arg(long)]
        json: bool,
    },
    /// Compare the DEM and L-BFGS on U_{q,p} and on a discrepancy energy, for a list of
    /// (s, n); writes comparison.md, comparison.json and convergence pictures.
    Compare {
        /// Cases as SxN, comma-separated (default: 2x1500,3x1500,5x1500,6x1500,5x200,10x400).
        #[arg(long, value_name = "SxN,...")]
        cases: Option<String>,
        /// Step or iteration budget per run.
        #[arg(long, default_value_t = 1000)]
        steps: usize,
        /// The discrepancy energy: l2star, md, cd or periodic.
        #[arg(long, default_value = "md")]
        energy: String,
        /// Output directory.
        #[arg(long, default_value = "comparison")]
        out: PathBuf,
        /// Small cases (2x200, 3x200) and 200 steps.
        #[arg(long)]
        quick: bool,
    },
    /// Write a classic point set (a baseline to compare with): random, halton,
    /// halton-scrambled, sobol, hua-wang, lattice, lhs, lhs-maximin.
    Baseline {
        /// The generator; `stillpoint baseline --list` describes each exactly.
        #[arg(value_name = "NAME", required_unless_present = "list")]
        name: Option<String>,
        /// Number of points n ≥ 1.
        #[arg(short = 'n', value_name = "N", required_unless_present = "list")]
        n: Option<usize>,
        /// Dimension s ≥ 1.
        #[arg(short = 's', value_name = "S", required_unless_present = "list")]
        s: Option<usize>,
        /// Output file (.csv, .tsv, .json, .npy); standard output as CSV without it.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
        /// Seed of the randomized generators (scrambles, random, LHS).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Describe every generator and exit.
        #[arg(long)]
        list: bool,
        /// Print a JSON summary (with the points when there is no -o).
        #[arg(long)]
        json: bool,
    },
    /// Integrate the eight test functions F1–F8 of eq. 49 (exact integrals 0) with the
    /// points of a file and print each estimate, i.e. each integration error.
    Integrate {
        /// The point file (CSV, TSV, whitespace, JSON, .npy); coordinates in [0, 1].
        file: PathBuf,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Reproduce one of the paper's studies: correlation (Tables 1–2, Figs. 3–5), table5,
    /// catalog (the 127 sets, resumable), table6 (Figs. 6–7), kraichnan-orszag (Table 7,
    /// Fig. 8), shear-frame (Table 8), regions (Fig. 9), or `all`.
    Study {
        /// The study name, or `all`.
        #[arg(value_name = "NAME")]
        name: String,
        /// A small, fast version (what CI runs).
        #[arg(long)]
        quick: bool,
        /// Output directory (default: results/, or results/quick/ with --quick).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Seed of every random choice.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// No progress lines.
        #[arg(long, short = 'q')]
        quiet: bool,
    },
    /// Time the kernels against their baselines in one run and print the ratios.
    Bench {
        /// Smaller sizes and fewer repetitions.
        #[arg(long)]
        quick: bool,
        /// Time only the centred and star L2 discrepancies of this point file and print
        /// one JSON object (used by benches/scipy_discrepancy.py).
        #[arg(long, value_name = "FILE")]
        points: Option<PathBuf>,
        /// Repetitions for --points (the median is reported).
        #[arg(long, default_value_t = 5, value_name = "K")]
        reps: usize,
    },
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = real_main(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn real_main(cli: Cli) -> Result<()> {
    if let Some(t) = cli.threads {
        if t == 0 {
            bail!("invalid --threads = 0: expected a number of threads ≥ 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .context("cannot start the thread pool")?;
    }
    match cli.command {
        Command::Generate(args) => generate(*args)?,
        Command::Eval { file, json } => {
            let points = io::read_points(&file)?;
            points
                .check_unit_cube()
                .with_context(|| format!("{}", file.display()))?;
            let v = eval_json(&points);
            if json {
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                print!("{}", eval_table(&file, &points, &v));
            }
        }
        Command::Compare {
            cases,
            steps,
            energy,
            out,
            quick,
        } => {
            let mut settings = stillpoint::compare::CompareSettings {
                steps,
                discrepancy: DiscrepancyKind::parse(&energy)?,
                ..Default::default()
            };
            if quick {
                settings.cases = vec![(2, 200), (3, 200)];
                settings.steps = steps.min(200);
            }
            if let Some(c) = cases {
                settings.cases = parse_cases(&c)?;
            }
            let table = stillpoint::compare::run_and_write(&settings, &out, true)?;
            print!("{table}");
        }
        Command::Baseline {
            name,
            n,
            s,
            output,
            seed,
            list,
            json,
        } => {
            if list {
                for b in Baseline::all() {
                    println!("{} ({}):\n  {}\n", b.name(), b.label(), b.describe());
                }
                return Ok(());
            }
            let (Some(name), Some(n), Some(s)) = (name, n, s) else {
                bail!("missing NAME, -n N or -s S (see stillpoint baseline --help)");
            };
            if let Some(out) = &output {
                check_writable(out, "-o")?;
            }
            let b = Baseline::parse(&name)?;
            let points = b.generate(n, s, seed)?;
            let metrics = (n <= METRICS_LIMIT).then(|| Metrics::compute(&points));
            let meta = json!({
                "generator": format!("stillpoint baseline {}", b.name()),
                "version": env!("CARGO_PKG_VERSION"),
                "seed": if b.is_randomized() { Some(seed) } else { None },
                "parameters": {
                    "baseline": b.name(),
                    "label": b.label(),
                    "n": n,
                    "s": s,
                    "randomized": b.is_randomized(),
                },
                "metrics": metrics.as_ref().map(metrics_json),
            });
            if json {
                let mut v = meta.clone();
                match &output {
                    Some(path) => {
                        io::write_points(path, &points, &meta)?;
                        v["output"] = json!(path);
                    }
                    None => v["points"] = points_json(&points),
                }
                println!("{}", serde_json::to_string_pretty(&v)?);
                return Ok(());
            }
            match &output {
                Some(path) => {
                    io::write_points(path, &points, &meta)?;
                    let quality = match metrics {
                        Some(m) => format!(
                            "D_MD {:.6}, D_L2* {:.6}, minimum distance {:.6}",
                            m.modified_l2, m.star_l2, m.min_distance
                        ),
                        None => format!("metrics skipped above n = {METRICS_LIMIT}"),
                    };
                    println!(
                        "{} ({}), n = {n}, s = {s}: {quality}; written to {}",
                        b.name(),
                        b.label(),
                        path.display()
                    );
                }
                None => print!("{}", io::to_csv_string(&points, &meta)),
            }
        }
        Command::Integrate { file, json } => {
            let points = io::read_points(&file)?;
            points
                .check_unit_cube()
                .with_context(|| format!("{}", file.display()))?;
            let report = stillpoint::testfns::integrate(&points)?;
            let fns = stillpoint::testfns::TestFunction::all();
            if json {
                let rows: Vec<Value> = fns
                    .iter()
                    .zip(report.estimates)
                    .map(|(f, e)| {
                        json!({"function": f.name(), "formula": f.formula(),
                               "estimate": e, "error": e.map(f64::abs)})
                    })
                    .collect();
                let v = json!({"file": file, "n": points.n(), "s": points.s(),
                               "exact": 0.0, "functions": rows});
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!(
                    "{}: n = {}, s = {}; every exact integral is 0, so |estimate| is the error\n",
                    file.display(),
                    points.n(),
                    points.s()
                );
                println!(
                    "  {:<4} {:>14} {:>12}   integrand",
                    "", "estimate", "|error|"
                );
                for (f, e) in fns.iter().zip(report.estimates) {
                    match e {
                        Some(v) => println!(
                            "  {:<4} {:>14.6e} {:>12.3e}   {}",
                            f.name(),
                            v,
                            v.abs(),
                            f.formula()
                        ),
                        None => println!(
                            "  {:<4} {:>14} {:>12}   {} (needs s ≥ 2)",
                            f.name(),
                            "—",
                            "—",
                            f.formula()
                        ),
                    }
                }
            }
        }
        Command::Study {
            name,
            quick,
            out,
            seed,
            quiet,
        } => {
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
                        eprintln!("{line}");
                    }
                };
                let result = studies::run(study, &opts, &mut log)?;
                print!("{}", result.markdown);
                eprintln!(
                    "{}: {} file(s) in {} ({})",
                    study.name(),
                    result.files.len(),
                    opts.out.display(),
                    studies::human_seconds(result.seconds)
                );
            }
        }
        Command::Plot {
            file,
            output,
            dims,
            region,
            bbox,
            shape,
            trajectory,
            title,
        } => {
            check_writable(&output, "-o")?;
            check_picture_extension(&output, "-o")?;
            match (trajectory, file) {
                (Some(traj), _) => plot_trajectory(&traj, &output, title)?,
                (None, Some(file)) => {
                    let spec = RegionSpec {
                        region: region.as_deref(),
                        bbox: bbox.as_deref(),
                        shape: shape.as_deref(),
                    };
                    plot_points(&file, &output, dims, spec, title)?
                }
                (None, None) => {
                    bail!("missing FILE: the point file to draw (or --trajectory TRAJ)")
                }
            }
        }
        Command::Bench {
            quick,
            points,
            reps,
        } => match points {
            Some(path) => {
                if reps == 0 {
                    bail!("invalid --reps = 0: expected at least 1 repetition");
                }
                bench::run_points(&path, reps, &mut std::io::stdout())?
            }
            None => bench::run(quick, &mut std::io::stdout())?,
        },
    }
    Ok(())
}

/// Largest n whose O(n² s) metrics a baseline file's header records (above it they would
/// take longer than generating the points by far).
const METRICS_LIMIT: usize = 20_000;

/// `stillpoint generate`: a cube or region run with its outputs. Every argument and
/// output path is checked before any work is done, and outputs are written only after
/// the run succeeded.
fn generate(a: GenerateArgs) -> Result<()> {
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
    }
    if let Some(out) = &plot {
        check_writable(out, "--plot")?;
        check_picture_extension(out, "--plot")?;
    }
    if let Some(out) = &trajectory {
        check_writable(out, "--trajectory")?;
    }
    if tolerance.is_nan() || tolerance < 0.0 {
        bail!("invalid --tolerance = {tolerance}: expected a number ≥ 0");
    }
    if let Some(p) = p {
        if !(p > 0.0 && p.is_finite()) {
            bail!("invalid --p = {p}: expected a finite number > 0");
        }
    }
    // A region built from text is known to the checkpoint by that text.
    let region_extra = if region.is_some() || shape.is_some() {
        json!({"--region": region, "--box": bbox, "--shape": shape})
    } else {
        Value::Null
    };
    let plan = checkpoint_plan(
        checkpoint,
        checkpoint_every,
        resume,
        region_extra.clone(),
        quiet,
    )?;
    let mut progress = Progress::new(quiet);
    if region.is_some() || shape.is_some() {
        let domain = region_domain(region.as_deref(), bbox.as_deref(), shape.as_deref(), s)?;
        let n = n.context("missing -n N: the number of points (at least 1)")?;
        if let Some(text) = &precision {
            bail!(
                "invalid --precision = {text} for a region: it sets U_{{q,p}}'s distance,                  which region energies do not use"
            );
        }
        let mut cfg = RegionConfig::new(domain, n);
        cfg.energy = match energy.as_deref().unwrap_or("e-inf-g") {
            "e-inf-g" => RegionEnergy::EInfG,
            "e-inf" => RegionEnergy::EInf,
            "e-p-g" => RegionEnergy::EpG(p.unwrap_or(8.0)),
            other => bail!(
                "invalid --energy = {other} for a region: expected e-inf-g (eq. 56), \
                 e-inf or e-p-g"
            ),
        };
        cfg.init = match init.as_deref().unwrap_or("random") {
            "random" => RegionInit::Random,
            "halton" => RegionInit::Halton,
            path => {
                RegionInit::Points(io::read_points(std::path::Path::new(path)).context("--init")?)
            }
        };
        cfg.seed = seed;
        cfg.solver = parse_solver(&integrator)?;
        if let Some(steps) = steps {
            cfg.steps = steps;
        }
        cfg.dem.kappa = run::parse_kappa(&kappa)?;
        cfg.dem.tolerance = tolerance;
        if plot.is_some() && cfg.domain.dim() < 2 {
            bail!("invalid --plot: the region has dimension 1; plots need s ≥ 2");
        }
        let report = generate_in_region_with(&cfg, plan.as_ref(), |e| progress.event(e))?;
        progress.finish();
        let meta = region_meta(&report, &cfg, &region_extra);
        if let Some(path) = &trajectory {
            write_trajectory(path, &report.energy_name, &report.output)?;
        }
        if let Some(path) = &plot {
            plot_start_result(
                path,
                &report.start,
                &report.output.points,
                cfg.domain.as_ref(),
            )?;
        }
        let summary = if json {
            region_json(&report, &cfg)
        } else {
            Value::String(region_table(&report, &cfg, output.as_ref()))
        };
        emit(&report.output.points, &meta, output.as_ref(), summary)?;
        return Ok(());
    }
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
    cfg.energy = match energy.as_deref().unwrap_or("uqp") {
        "uqp" => CubeEnergy::Uqp,
        "e-inf" => CubeEnergy::EInf,
        "e-inf-g" | "e-p-g" => bail!(
            "invalid --energy = {} in the cube: e-inf-g and e-p-g need --region or \
             --shape; the cube accepts uqp, e-inf, l2star, md, cd, periodic",
            energy.as_deref().unwrap_or_default()
        ),
        other => CubeEnergy::Discrepancy(DiscrepancyKind::parse(other).map_err(|_| {
            anyhow::anyhow!(
                "invalid --energy = {other} in the cube: expected uqp, e-inf, \
                     l2star, md, cd or periodic"
            )
        })?),
    };
    cfg.solver = parse_solver(&integrator)?;
    cfg.q = match q.as_deref() {
        Some(text) => Some(Distance::parse(text).map_err(|_| {
            anyhow::anyhow!(
                "invalid --q = {text}: expected a number in (0, ∞), `inf` (the torus distance) \
                 or `E` (Euclidean)"
            )
        })?),
        None => None,
    };
    cfg.p = p;
    if let Some(text) = &precision {
        cfg.precision = Precision::parse(text)
            .map_err(|_| anyhow::anyhow!("invalid --precision = {text}: expected fast or full"))?;
    }
    cfg.init = init;
    cfg.seed = seed;
    cfg.steps = steps.unwrap_or(1000);
    cfg.dem.kappa = run::parse_kappa(&kappa)?;
    cfg.dem.restart = run::parse_restart(&restart)?;
    cfg.dem.tolerance = tolerance;
    cfg.shifts = shifts;
    cfg.polish = match polish.as_str() {
        "none" => None,
        other => Some(DiscrepancyKind::parse(other).map_err(|_| {
            anyhow::anyhow!("invalid --polish = {other}: expected none, md, l2star, cd or periodic")
        })?),
    };
    cfg.log_every = log_every.unwrap_or(if trajectory.is_some() { 10 } else { 0 });
    let report = run::generate_with(&cfg, plan.as_ref(), |e| progress.event(e))?;
    progress.finish();
    let meta = generate_meta(&report, &cfg);
    if let Some(path) = &trajectory {
        write_trajectory(path, &report.energy_name, &report.output)?;
    }
    if let Some(path) = &plot {
        let cube = stillpoint::PeriodicCube::new(cfg.s)?;
        plot_start_result(path, &report.start, &report.output.points, &cube)?;
    }
    let summary = if json {
        report_json(&report, &cfg)
    } else {
        Value::String(report_table(&report, &cfg, output.as_ref()))
    };
    emit(&report.output.points, &meta, output.as_ref(), summary)?;
    Ok(())
}

/// `--integrator dem|lbfgs`.
fn parse_solver(text: &str) -> Result<Solver> {
    match text {
        "dem" => Ok(Solver::Dem),
        "lbfgs" => Ok(Solver::Lbfgs),
        other => bail!("invalid --integrator = {other}: expected dem or lbfgs"),
    }
}

/// The checkpoint plan of `--checkpoint FILE [--checkpoint-every K] [--resume [FILE]]`.
fn checkpoint_plan(
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
    }))
}

/// Refuses a picture path that is not `.png` or `.svg` before any work is done.
fn check_picture_extension(path: &std::path::Path, option: &str) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "png" && ext != "svg" {
        bail!(
            "invalid {option} {}: expected a file name ending in .png or .svg",
            path.display()
        );
    }
    Ok(())
}

/// A progress bar on standard error with the stage, steps and ETA; hidden with --quiet or
/// when standard error is not a terminal.
struct Progress {
    bar: ProgressBar,
    visible: bool,
    /// The first position of a stage may jump (a resumed run), which must not count
    /// towards the rate the ETA is computed from.
    fresh: bool,
}

impl Progress {
    fn new(quiet: bool) -> Self {
        let visible = !quiet && std::io::stderr().is_terminal();
        // Drawn from the first stage on, so that no empty bar flashes up before it.
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        Progress {
            bar,
            visible,
            fresh: true,
        }
    }

    fn event(&mut self, e: run::Event) {
        if !self.visible {
            return;
        }
        match e {
            run::Event::Stage {
                name,
                steps: Some(len),
            } => {
                self.bar.disable_steady_tick();
                self.bar.set_length(len);
                self.bar.set_position(0);
                self.bar.set_style(
                    ProgressStyle::with_template(
                        "{msg:>15} {wide_bar} {pos}/{len} steps, {elapsed} elapsed, ETA {eta}",
                    )
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                self.bar.set_message(name);
                self.bar.reset_elapsed();
                self.bar.reset_eta();
                self.fresh = true;
                self.show();
            }
            run::Event::Stage { name, steps: None } => {
                self.bar.set_style(
                    ProgressStyle::with_template("{msg:>15} {spinner} {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                );
                self.bar.set_message(name);
                self.bar.reset_elapsed();
                self.show();
                self.bar
                    .enable_steady_tick(std::time::Duration::from_millis(120));
            }
            run::Event::Progress(p) => {
                self.bar.set_position(p);
                if self.fresh {
                    self.bar.reset_eta();
                    self.fresh = false;
                }
            }
            run::Event::Record(_) => {}
        }
    }

    fn show(&self) {
        if self.bar.is_hidden() {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Refuses an output path (of `option`) whose directory does not exist, or that is a
/// directory, before any work is done.
fn check_writable(path: &std::path::Path, option: &str) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "invalid {option} {}: the directory {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!(
            "invalid {option} {}: it is a directory, expected a file name",
            path.display()
        );
    }
    Ok(())
}

fn metrics_json(m: &Metrics) -> Value {
    serde_json::to_value(m).unwrap_or(Value::Null)
}

/// The `--json` report of a cube run: settings, run facts, energies and metrics of the
/// start and the result, the shift and polish, and the wall time.
fn report_json(r: &GenerateReport, cfg: &GenerateConfig) -> Value {
    let info: serde_json::Map<String, Value> = r
        .output
        .info
        .iter()
        .map(|(k, v)| (k.clone(), finite_or_null(*v)))
        .collect();
    let init = match &cfg.init {
        Init::Halton => "halton".to_string(),
        Init::Random => "random".to_string(),
        Init::Points(_) => "file".to_string(),
    };
    let mut v = json!({
        "generator": format!("stillpoint {}", env!("CARGO_PKG_VERSION")),
        "n": cfg.n,
        "s": cfg.s,
        "energy": r.energy_name,
        "q": r.choice.q,
        "p": r.choice.p,
        "precision": cfg.precision.label(),
        "init": init,
        "seed": cfg.seed,
        "steps": r.output.trajectory.iter().map(|t| t.step).max().unwrap_or(0),
        "stop": r.output.stop,
        "kappa": r.output.info("kappa"),
        "restarts": r.output.info("restarts"),
    });
    v["eq48"] = json!({
        "used": r.choice.from_eq48,
        "in_fitted_range": r.choice.eq48_in_fitted_range,
        "clamped": r.choice.eq48_clamped,
    });
    v["run"] = Value::Object(info);
    v["energy_start"] = finite_or_null(r.energy.0);
    v["energy_result"] = finite_or_null(r.energy.1);
    v["metrics_start"] = metrics_json(&r.metrics.0);
    v["metrics_result"] = metrics_json(&r.metrics.1);
    v["shift"] = serde_json::to_value(&r.shift).unwrap_or(Value::Null);
    v["polish"] = match r.polish {
        Some((a, b, it)) => json!({"before": a, "after": b, "iterations": it}),
        None => Value::Null,
    };
    v["seconds"] = json!(r.seconds);
    v
}

/// The settings of a DEM as the command line writes them.
fn dem_settings(dem: &stillpoint::integrators::Dem, steps: usize) -> Value {
    use stillpoint::integrators::{Kappa, Restart};
    json!({
        "steps": steps,
        "kappa": match dem.kappa {
            Kappa::Fixed(k) => json!(k),
            Kappa::Auto { .. } => json!("auto"),
        },
        "restart": match dem.restart {
            Restart::Auto => json!("auto"),
            Restart::Off => json!("off"),
            Restart::Threshold(e) => json!(e),
        },
        "tolerance": dem.tolerance,
    })
}

/// The header of a generated point file: what made it (generator, version, seed, every
/// parameter) and what came out (run facts and the result's metrics). Nothing in it
/// depends on the clock or the thread count, so the file is the same bytes every time.
fn generate_meta(r: &GenerateReport, cfg: &GenerateConfig) -> Value {
    let init = match &cfg.init {
        Init::Halton => "halton".to_string(),
        Init::Random => "random".to_string(),
        Init::Points(p) => format!("file: {}", run::points_fingerprint(p)),
    };
    let mut parameters = json!({
        "n": cfg.n,
        "s": cfg.s,
        "energy": r.energy_name,
        "q": r.choice.q,
        "p": finite_or_null(r.choice.p),
        "precision": cfg.precision.label(),
        "pq_from_eq48": r.choice.from_eq48,
        "init": init,
        "integrator": match cfg.solver {
            Solver::Dem => "dem",
            Solver::Lbfgs => "lbfgs",
        },
        "shifts": cfg.shifts,
        "polish": cfg.polish.map(|k| format!("{k:?}")),
    });
    if let (Value::Object(p), Value::Object(d)) =
        (&mut parameters, dem_settings(&cfg.dem, cfg.steps))
    {
        p.extend(d);
    }
    json!({
        "generator": "stillpoint generate",
        "version": env!("CARGO_PKG_VERSION"),
        "seed": cfg.seed,
        "parameters": parameters,
        "run": {
            "steps": r.output.trajectory.iter().map(|t| t.step).max().unwrap_or(0),
            "stop": r.output.stop,
            "kappa": r.output.info("kappa").map(finite_or_null),
            "restarts": r.output.info("restarts").map(finite_or_null),
        },
        "metrics": metrics_json(&r.metrics.1),
    })
}

/// The header of a point file generated in a region (see [`generate_meta`]).
fn region_meta(r: &RegionReport, cfg: &RegionConfig, region: &Value) -> Value {
    let mut parameters = json!({
        "n": cfg.n,
        "s": cfg.domain.dim(),
        "region": region,
        "domain": format!("{:?}", cfg.domain),
        "energy": r.energy_name,
        "init": match &cfg.init {
            RegionInit::Random => "random".to_string(),
            RegionInit::Halton => "halton".to_string(),
            RegionInit::Points(p) => format!("file: {}", run::points_fingerprint(p)),
        },
    });
    if let (Value::Object(p), Value::Object(d)) =
        (&mut parameters, dem_settings(&cfg.dem, cfg.steps))
    {
        p.extend(d);
    }
    json!({
        "generator": "stillpoint generate",
        "version": env!("CARGO_PKG_VERSION"),
        "seed": cfg.seed,
        "parameters": parameters,
        "run": {
            "steps": r.output.trajectory.iter().map(|t| t.step).max().unwrap_or(0),
            "stop": r.output.stop,
            "kappa": r.output.info("kappa").map(finite_or_null),
        },
        "metrics": serde_json::to_value(r.metrics.1).unwrap_or(Value::Null),
    })
}

fn finite_or_null(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

fn report_table(r: &GenerateReport, cfg: &GenerateConfig, out: Option<&PathBuf>) -> String {
    let (m0, m1) = (&r.metrics.0, &r.metrics.1);
    let init = match &cfg.init {
        Init::Halton => "plain Halton (indices 1..n)".to_string(),
        Init::Random => format!("random (seed {})", cfg.seed),
        Init::Points(_) => "points from file".to_string(),
    };
    let mut t = String::new();
    t += &format!(
        "stillpoint: n = {}, s = {}, {} from {}\n",
        cfg.n, cfg.s, r.energy_name, init
    );
    if r.choice.from_eq48 {
        t += &format!(
            "  (q, p) from eq. 48{}{}\n",
            if r.choice.eq48_in_fitted_range {
                ""
            } else {
                "; (n, s) is outside the fitted range 1 ≤ s ≤ 20, s ≤ n ≤ 1500"
            },
            if r.choice.eq48_clamped {
                "; clamped into [0.05, 1]"
            } else {
                ""
            }
        );
    }
    let steps = r
        .output
        .trajectory
        .iter()
        .map(|x| x.step)
        .max()
        .unwrap_or(0);
    t += &match r.output.info("kappa") {
        Some(kappa) => format!(
            "  DEM: {} steps ({:?}), κ = {} after {} trial(s){}, {} restart(s)\n\n",
            steps,
            r.output.stop,
            kappa,
            r.output.info("kappa_trials").unwrap_or(0.0),
            if r.output.info("kappa_trial_failed") == Some(1.0) {
                " (the energy never fell steadily: κ capped)"
            } else {
                ""
            },
            r.output.info("restarts").unwrap_or(0.0),
        ),
        None => format!(
            "  L-BFGS: {} iterations ({:?}), {} restart(s)\n\n",
            steps,
            r.output.stop,
            r.output.info("restarts").unwrap_or(0.0),
        ),
    };
    t += &format!(
        "  {:<36} {:>14} {:>14} {:>9}\n",
        "", "start", "result", "change"
    );
    let mut row = |name: &str, a: f64, b: f64, sci: bool| {
        let f = |v: f64| {
            if sci {
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
        t += &format!("  {:<36} {:>14} {:>14} {:>9}\n", name, f(a), f(b), change);
    };
    let energy_label = format!("energy {}", r.energy_name.split('(').next().unwrap_or(""));
    row(&energy_label, r.energy.0, r.energy.1, true);
    row(
        "star L2 discrepancy D_L2* (root)",
        m0.star_l2,
        m1.star_l2,
        false,
    );
    row(
        "modified L2 discrepancy D_MD (root)",
        m0.modified_l2,
        m1.modified_l2,
        false,
    );
    row(
        "centred L2 discrepancy (root)",
        m0.centered_l2,
        m1.centered_l2,
        false,
    );
    row(
        "wrap-around L2 discrepancy (root)",
        m0.wrap_around_l2,
        m1.wrap_around_l2,
        false,
    );
    row(
        "minimum distance (Euclidean)",
        m0.min_distance,
        m1.min_distance,
        false,
    );
    row(
        "minimum distance (periodic)",
        m0.min_distance_periodic,
        m1.min_distance_periodic,
        false,
    );
    let gap = |p: &PointSet| p.mean().iter().map(|v| (v - 0.5).abs()).fold(0.0, f64::max);
    row(
        "mean gap max_k |mean_k − 0.5|",
        gap(&r.start),
        gap(&r.output.points),
        false,
    );
    if let Some(sh) = &r.shift {
        t += &format!(
            "\n  shift selection: D_MD {:.6} after the DEM → {:.6} with shift ({}) ({} evaluations)\n",
            sh.modified_l2_before,
            sh.modified_l2_after,
            sh.shift.iter().map(|c| format!("{c:.4}")).collect::<Vec<_>>().join(", "),
            sh.evaluations
        );
    }
    if let Some((a, b, it)) = r.polish {
        t +=
            &format!("  polish: squared discrepancy {a:.6e} → {b:.6e} in {it} L-BFGS iterations\n");
    }
    t += &format!(
        "\n  time {:.2} s; points written to {}\n",
        r.seconds,
        out.map(|p| p.display().to_string())
            .unwrap_or_else(|| "standard output".into())
    );
    t
}

fn eval_json(points: &PointSet) -> Value {
    let m = Metrics::compute(points);
    let fit = paper_qp(points.n(), points.s());
    let uqp = Uqp::new(Distance::Q(fit.q), fit.p)
        .map(|e| e.value(points))
        .ok();
    let mean_gap = points
        .mean()
        .iter()
        .map(|v| (v - 0.5).abs())
        .fold(0.0, f64::max);
    json!({
        "n": points.n(),
        "s": points.s(),
        "star_l2": m.star_l2,
        "modified_l2": m.modified_l2,
        "centered_l2": m.centered_l2,
        "wrap_around_l2": m.wrap_around_l2,
        "min_distance": finite_or_null(m.min_distance),
        "min_distance_periodic": finite_or_null(m.min_distance_periodic),
        "energy_uqp": uqp.map(finite_or_null),
        "energy_uqp_q": fit.q,
        "energy_uqp_p": fit.p,
        "energy_e_inf": finite_or_null(1.0 / m.min_distance),
        "mean_gap": mean_gap,
    })
}

fn eval_table(file: &std::path::Path, points: &PointSet, v: &Value) -> String {
    let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let mut t = format!(
        "{}: n = {}, s = {}\n",
        file.display(),
        points.n(),
        points.s()
    );
    let rows = [
        ("star L2 discrepancy D_L2* (root)", num("star_l2")),
        ("modified L2 discrepancy D_MD (root)", num("modified_l2")),
        ("centred L2 discrepancy (root)", num("centered_l2")),
        ("wrap-around L2 discrepancy (root)", num("wrap_around_l2")),
        ("minimum distance (Euclidean)", num("min_distance")),
        ("minimum distance (periodic)", num("min_distance_periodic")),
        ("mean gap max_k |mean_k − 0.5|", num("mean_gap")),
    ];
    for (name, val) in rows {
        t += &format!("  {name:<40} {val:.6}\n");
    }
    t += &format!(
        "  {:<40} {:.6e}   (q = {:.4}, p = {:.4} from eq. 48)\n",
        "energy U_{q,p}",
        num("energy_uqp"),
        num("energy_uqp_q"),
        num("energy_uqp_p")
    );
    t += &format!(
        "  {:<40} {:.6}\n",
        "energy U_{E,∞} = 1/d_min",
        num("energy_e_inf")
    );
    t
}

fn points_json(points: &PointSet) -> Value {
    json!(points.rows().map(|r| r.to_vec()).collect::<Vec<_>>())
}

/// Parses a comma-separated list of numbers for the option `name`.
fn number_list(name: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| {
                    format!("invalid {name} = {text}: {t:?} is not a finite number (expected comma-separated numbers)")
                })
        })
        .collect()
}

/// `--box LO1,HI1,LO2,HI2,...` as (lo, hi).
fn parse_box(text: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let v = number_list("--box", text)?;
    if v.is_empty() || v.len() % 2 != 0 {
        bail!("invalid --box = {text}: expected LO1,HI1,LO2,HI2,... (two numbers per dimension)");
    }
    let lo: Vec<f64> = v.iter().step_by(2).copied().collect();
    let hi: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
    if let Some(k) = (0..lo.len()).find(|&k| lo[k] >= hi[k]) {
        bail!(
            "invalid --box = {text}: dimension {} has LO = {} ≥ HI = {} (expected LO < HI)",
            k + 1,
            lo[k],
            hi[k]
        );
    }
    Ok((lo, hi))
}

/// The domain of `--region EXPR --box ..` or `--shape SPEC`.
fn region_domain(
    region: Option<&str>,
    bbox: Option<&str>,
    shape: Option<&str>,
    s: Option<usize>,
) -> Result<Arc<dyn Domain>> {
    let dim_check = |got: usize| -> Result<()> {
        match s {
            Some(s) if s != got => {
                bail!("invalid -s = {s}: the region has dimension {got}")
            }
            _ => Ok(()),
        }
    };
    if region.is_some() && shape.is_some() {
        bail!("give either --region EXPR or --shape SHAPE, not both");
    }
    if let Some(expr) = region {
        let (lo, hi) = parse_box(bbox.context("--region needs --box LO1,HI1,LO2,HI2,...")?)?;
        dim_check(lo.len())?;
        let g = stillpoint::expr::RegionExpr::parse(expr, lo.len())
            .with_context(|| "invalid --region".to_string())?;
        let r = ImplicitRegion::new(g.into_fn(), lo, hi)?;
        r.check(4096, 0).context("--region")?;
        return Ok(Arc::new(r));
    }
    let spec = shape.unwrap_or_default();
    let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let need_s = || s.context("this --shape needs -s S (the dimension)");
    let split_at = |text: &str| -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        match text.split_once('@') {
            Some((a, c)) => Ok((number_list("--shape", a)?, Some(number_list("--shape", c)?))),
            None => Ok((number_list("--shape", text)?, None)),
        }
    };
    let domain: Arc<dyn Domain> = match kind {
        "ball" => {
            let (r, c) = split_at(rest)?;
            if r.len() != 1 {
                bail!("invalid --shape = {spec}: expected ball:R or ball:R@C1,C2,...");
            }
            let c = match c {
                Some(c) => c,
                None => vec![0.0; need_s()?],
            };
            Arc::new(Ball::new(c, r[0])?)
        }
        "ellipsoid" => {
            let (a, c) = split_at(rest)?;
            let c = c.unwrap_or_else(|| vec![0.0; a.len()]);
            Arc::new(Ellipsoid::new(c, a)?)
        }
        "box" => {
            let (lo, hi) =
                parse_box(rest).map_err(|e| anyhow::anyhow!("invalid --shape = {spec}: {e}"))?;
            Arc::new(BoxRegion::new(lo, hi)?)
        }
        "simplex" => Arc::new(Simplex::new(need_s()?)?),
        "polytope" => {
            let rows =
                io::read_points(std::path::Path::new(rest)).context("--shape polytope:FILE")?;
            if rows.s() < 2 {
                bail!("invalid --shape = {spec}: each row needs a1 .. as b (at least 2 numbers)");
            }
            let a: Vec<Vec<f64>> = rows.rows().map(|r| r[..r.len() - 1].to_vec()).collect();
            let b: Vec<f64> = rows.rows().map(|r| r[r.len() - 1]).collect();
            let (lo, hi) = parse_box(bbox.context("--shape polytope:FILE needs --box")?)?;
            Arc::new(Polytope::new(a, b, lo, hi)?)
        }
        _ => bail!(
            "invalid --shape = {spec}: expected ball:R[@C..], ellipsoid:A1,..[@C..], \
             box:LO1,HI1,.., simplex or polytope:FILE"
        ),
    };
    dim_check(domain.dim())?;
    Ok(domain)
}

/// `--region EXPR --box ..` / `--shape ..` as given on the command line.
#[derive(Clone, Copy)]
struct RegionSpec<'a> {
    region: Option<&'a str>,
    bbox: Option<&'a str>,
    shape: Option<&'a str>,
}

/// `stillpoint plot FILE`: a scatter plot (s = 2, with the region's boundary when one is
/// given) or a matrix of projections of the first `dims` coordinates.
fn plot_points(
    file: &std::path::Path,
    output: &std::path::Path,
    dims: Option<usize>,
    spec: RegionSpec,
    title: Option<String>,
) -> Result<()> {
    let points = io::read_points(file)?;
    let s = points.s();
    let k = dims.unwrap_or(s.min(4));
    if k == 0 || k > s {
        bail!("invalid --dims = {k}: expected 1 ≤ K ≤ s = {s} (the file's dimension)");
    }
    let title = title.unwrap_or_else(|| {
        file.file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    });
    let domain = if spec.region.is_some() || spec.shape.is_some() {
        Some(region_domain(spec.region, spec.bbox, spec.shape, Some(s))?)
    } else {
        None
    };
    let (lo, hi) = match (&domain, spec.bbox) {
        (Some(d), _) => d.bounding_box(),
        (None, Some(b)) => {
            let (lo, hi) = parse_box(b)?;
            if lo.len() < k {
                bail!(
                    "invalid --box = {b}: it has {} dimensions, {k} are drawn (expected \
                     LO1,HI1,..,LO{k},HI{k})",
                    lo.len()
                );
            }
            (lo, hi)
        }
        (None, None) => plot_box(&points),
    };
    if k == 2 && s == 2 {
        let boundary = match &domain {
            Some(d) if d.level(&[lo[0], lo[1]]).is_some() => stillpoint::plot::boundary_polylines(
                &|x: &[f64]| d.level(x).unwrap_or(f64::NAN),
                [lo[0], lo[1]],
                [hi[0], hi[1]],
                300,
            ),
            _ => Vec::new(),
        };
        let panel = stillpoint::plot::Panel {
            title,
            points: &points,
            lo: [lo[0], lo[1]],
            hi: [hi[0], hi[1]],
            boundary,
        };
        stillpoint::plot::save_panels(output, &[panel], 1)?;
    } else {
        stillpoint::plot::save_projection_matrix(output, &title, &points, k, &lo, &hi)?;
    }
    Ok(())
}

/// The unit cube when the points lie in it, else their bounding box padded by 5 %.
fn plot_box(points: &PointSet) -> (Vec<f64>, Vec<f64>) {
    if points.check_unit_cube().is_ok() {
        return (vec![0.0; points.s()], vec![1.0; points.s()]);
    }
    (0..points.s())
        .map(|k| {
            let (a, b) = points
                .rows()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                    (a.min(r[k]), b.max(r[k]))
                });
            let pad = if b > a { 0.05 * (b - a) } else { 0.5 };
            (a - pad, b + pad)
        })
        .unzip()
}

/// A trajectory file as `generate --trajectory` writes it.
#[derive(serde::Deserialize)]
struct TrajectoryFile {
    #[serde(default)]
    energy: Option<String>,
    records: Vec<stillpoint::integrators::Record>,
}

/// `stillpoint plot --trajectory TRAJ`: energy (relative to the start) and the logged
/// discrepancies against step and against wall time.
fn plot_trajectory(
    path: &std::path::Path,
    output: &std::path::Path,
    title: Option<String>,
) -> Result<()> {
    use stillpoint::plot::{LineChart, Series};
    let refuse = |why: String| {
        anyhow::anyhow!(
            "invalid --trajectory {}: expected a trajectory written by generate --trajectory \
             ({why})",
            path.display()
        )
    };
    let bytes = std::fs::read(path).map_err(|e| refuse(format!("cannot read it: {e}")))?;
    let traj: TrajectoryFile =
        serde_json::from_slice(&bytes).map_err(|e| refuse(format!("{e}")))?;
    // A non-smooth run repeats its returned state at the end; the curves follow the steps.
    let mut records = Vec::with_capacity(traj.records.len());
    for r in &traj.records {
        if records
            .last()
            .is_none_or(|l: &&stillpoint::integrators::Record| r.step > l.step)
        {
            records.push(r);
        }
    }
    let Some(first) = records.first() else {
        return Err(refuse("it has no records".into()));
    };
    let u0 = first.energy;
    if !(u0.is_finite() && u0 != 0.0) {
        return Err(refuse(format!("the start energy is {u0}")));
    }
    let title = title.unwrap_or_else(|| traj.energy.clone().unwrap_or_else(|| "energy".into()));
    let mut names: Vec<&str> = Vec::new();
    for r in &records {
        for (k, _) in &r.metrics {
            if !names.contains(&k.as_str()) {
                names.push(k);
            }
        }
    }
    let energy = |x: &dyn Fn(&stillpoint::integrators::Record) -> f64| Series {
        name: "U / U(start)".into(),
        points: records.iter().map(|r| (x(r), r.energy / u0)).collect(),
    };
    let metric = |x: &dyn Fn(&stillpoint::integrators::Record) -> f64| -> Vec<Series> {
        names
            .iter()
            .map(|name| Series {
                name: (*name).to_string(),
                points: records
                    .iter()
                    .filter_map(|r| {
                        r.metrics
                            .iter()
                            .find(|(k, _)| k == name)
                            .map(|(_, v)| (x(r), *v))
                    })
                    .collect(),
            })
            .collect()
    };
    let by_step = |r: &stillpoint::integrators::Record| r.step as f64;
    let by_time = |r: &stillpoint::integrators::Record| r.seconds;
    let chart = |t: String, x: &str, y: &str, series: Vec<Series>| LineChart {
        title: t,
        x_label: x.into(),
        y_label: y.into(),
        log_y: false,
        series,
    };
    let mut charts = vec![
        chart(
            format!("{title}: energy"),
            "step",
            "U / U(start)",
            vec![energy(&by_step)],
        ),
        chart(
            format!("{title}: energy"),
            "seconds",
            "U / U(start)",
            vec![energy(&by_time)],
        ),
    ];
    if !names.is_empty() {
        charts.push(chart(
            "discrepancies (roots)".into(),
            "step",
            "discrepancy",
            metric(&by_step),
        ));
        charts.push(chart(
            "discrepancies (roots)".into(),
            "seconds",
            "discrepancy",
            metric(&by_time),
        ));
    }
    stillpoint::plot::save_line_chart_grid(output, &charts, 2)?;
    Ok(())
}

/// Draws the start beside the result, with the boundary when the domain has one and s = 2.
fn plot_start_result(
    path: &std::path::Path,
    start: &PointSet,
    result: &PointSet,
    domain: &dyn Domain,
) -> Result<()> {
    if start.s() < 2 {
        bail!("invalid --plot: the points have s = 1; plots need s ≥ 2");
    }
    let (lo, hi) = domain.bounding_box();
    let (lo2, hi2) = ([lo[0], lo[1]], [hi[0], hi[1]]);
    let boundary = if start.s() == 2 && domain.level(&[lo[0], lo[1]]).is_some() {
        stillpoint::plot::boundary_polylines(
            &|x: &[f64]| domain.level(x).unwrap_or(f64::NAN),
            lo2,
            hi2,
            300,
        )
    } else {
        Vec::new()
    };
    let panels = [
        stillpoint::plot::Panel {
            title: "start".into(),
            points: start,
            lo: lo2,
            hi: hi2,
            boundary: boundary.clone(),
        },
        stillpoint::plot::Panel {
            title: "result".into(),
            points: result,
            lo: lo2,
            hi: hi2,
            boundary,
        },
    ];
    stillpoint::plot::save_panels(path, &panels, 2)?;
    Ok(())
}

/// The `--json` report of a region run.
fn region_json(r: &RegionReport, cfg: &RegionConfig) -> Value {
    let mut v = json!({
        "generator": format!("stillpoint {}", env!("CARGO_PKG_VERSION")),
        "n": cfg.n,
        "s": cfg.domain.dim(),
        "region": format!("{:?}", cfg.domain),
        "energy": r.energy_name,
        "seed": cfg.seed,
        "steps": r.output.trajectory.iter().map(|t| t.step).max().unwrap_or(0),
        "stop": r.output.stop,
        "kappa": r.output.info("kappa"),
        "energy_e_inf_g_reduction": finite_or_null(r.reduction()),
    });
    let info: serde_json::Map<String, Value> = r
        .output
        .info
        .iter()
        .map(|(k, v)| (k.clone(), finite_or_null(*v)))
        .collect();
    v["run"] = Value::Object(info);
    v["metrics_start"] = serde_json::to_value(r.metrics.0).unwrap_or(Value::Null);
    v["metrics_result"] = serde_json::to_value(r.metrics.1).unwrap_or(Value::Null);
    v["seconds"] = json!(r.seconds);
    v
}

fn region_table(r: &RegionReport, cfg: &RegionConfig, out: Option<&PathBuf>) -> String {
    let (a, b) = (&r.metrics.0, &r.metrics.1);
    let mut t = format!(
        "stillpoint: n = {}, s = {} in {:?}\n  {} from {}, DEM: {} steps ({:?}), κ = {} after {} trial(s)\n\n",
        cfg.n,
        cfg.domain.dim(),
        cfg.domain,
        r.energy_name,
        match &cfg.init {
            RegionInit::Random => format!("random start (seed {}, first n inside the box)", cfg.seed),
            RegionInit::Halton => "Halton start (first n inside the box)".into(),
            RegionInit::Points(_) => "points from file".into(),
        },
        r.output.trajectory.iter().map(|x| x.step).max().unwrap_or(0),
        r.output.stop,
        r.output.info("kappa").unwrap_or(f64::NAN),
        r.output.info("kappa_trials").unwrap_or(0.0),
    );
    t += &format!(
        "  {:<36} {:>14} {:>14} {:>9}\n",
        "", "start", "result", "change"
    );
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
        t += &format!(
            "  {:<36} {:>14.6} {:>14.6} {:>+8.1}%\n",
            name,
            x,
            y,
            100.0 * (y - x) / x
        );
    }
    t += &format!(
        "\n  U_{{E,∞,g}} reduction {:.1}%; time {:.2} s; points written to {}\n",
        100.0 * r.reduction(),
        r.seconds,
        out.map(|p| p.display().to_string())
            .unwrap_or_else(|| "standard output".into())
    );
    t
}

/// `--cases 2x1500,3x1500` as (s, n) pairs.
fn parse_cases(text: &str) -> Result<Vec<(usize, usize)>> {
    text.split(',')
        .map(|c| {
            let (s, n) = c.trim().split_once(['x', 'X']).with_context(|| {
                format!("invalid --cases = {text}: {c:?} is not SxN (e.g. 2x1500)")
            })?;
            let parse = |v: &str, what: &str| -> Result<usize> {
                match v.trim().parse::<usize>() {
                    Ok(k) if k >= 1 => Ok(k),
                    _ => bail!("invalid --cases = {text}: {what} {v:?} is not an integer ≥ 1"),
                }
            };
            Ok((parse(s, "s")?, parse(n, "n")?))
        })
        .collect()
}

/// Writes the points (to `output`, or as CSV to standard output) and the summary: a JSON
/// object (printed to standard output, with the points when there is no output file) or a
/// table (to standard output, or to standard error when the points went there).
fn emit(points: &PointSet, meta: &Value, output: Option<&PathBuf>, summary: Value) -> Result<()> {
    match summary {
        Value::String(table) => match output {
            Some(path) => {
                io::write_points(path, points, meta)?;
                print!("{table}");
            }
            None => {
                print!("{}", io::to_csv_string(points, meta));
                eprint!("{table}");
            }
        },
        mut v => {
            match output {
                Some(path) => io::write_points(path, points, meta)?,
                None => v["points"] = points_json(points),
            }
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
    }
    Ok(())
}

/// The run's trajectory as JSON (energy every step, logged metrics), written atomically.
fn write_trajectory(
    path: &std::path::Path,
    energy: &str,
    output: &stillpoint::integrators::RunOutput,
) -> Result<()> {
    let traj = serde_json::to_vec_pretty(&json!({
        "energy": energy,
        "records": output.trajectory,
    }))?;
    io::write_atomic(path, &traj)?;
    Ok(())
}
