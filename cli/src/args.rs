//! The command line's arguments: one clap struct per subcommand.

use super::*;

#[derive(Parser)]
#[command(
    name = "stillpoint",
    version,
    about = "Point sets for integration and design of experiments: generate sets that \
             fill [0,1]^s, a region or a design space as evenly as possible, measure any \
             set, integrate to a tolerance, with the numbers that prove their quality."
)]
pub(crate) struct Cli {
    /// Worker threads, 1 to 1024 (default: all cores). Results are the same bytes for
    /// any count.
    #[arg(long, global = true, value_name = "T", allow_hyphen_values = true)]
    pub(crate) threads: Option<String>,
    #[command(subcommand)]
    pub(crate) command: Command,
}

impl Cli {
    /// clap's command, with the help of every declared flag of every subcommand written
    /// from its declaration ([`crate::help`]: the doc line, every accepted word, the
    /// default), so that the command line and Python describe an option in the same
    /// words, and with a negative number taken as a value ([`numbers_are_values`]).
    pub(crate) fn command_with_declared_help() -> clap::Command {
        use clap::CommandFactory;
        numbers_are_values(crate::help::declared_help(Cli::command()))
    }
}

/// Every value-taking option of `cmd` and of its subcommands, at any depth: a value that
/// looks like a negative number is the option's value (`-n -1`, `--max-n -4`), never a
/// flag of its own or clap's tip to write `-- -1` (which would make it a file name). One
/// walk over the built command, so that every subcommand's options (those declared
/// elsewhere too) follow the rule without a setting of their own. The value itself is
/// text, read by the command ([`crate::values::whole`], [`crate::values::declared`], or the
/// library's declarations): a refused number then exits as every refused value does.
fn numbers_are_values(cmd: clap::Command) -> clap::Command {
    let cmd = cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    });
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    names.iter().fold(cmd, |cmd, name| {
        cmd.mut_subcommand(name, numbers_are_values)
    })
}

/// The heading of the options of the paper's pipeline in `generate --help`, after the
/// few that most runs need.
const EXPERT: &str = "Expert options: the paper's pipeline (any of them selects --method paper)";

/// The options of `stillpoint generate`.
#[derive(clap::Args)]
pub(crate) struct GenerateArgs {
    /// Number of points n ≥ 1 (with --extend: the number of points to add; taken from
    /// --init FILE when omitted).
    #[arg(short = 'n', value_name = "N", allow_hyphen_values = true)]
    pub(crate) n: Option<String>,
    /// Dimension s ≥ 1 (taken from --init FILE when omitted).
    #[arg(short = 's', value_name = "S", allow_hyphen_values = true)]
    pub(crate) s: Option<String>,
    /// Output file: .csv (default), .tsv, .json or .npy by extension. Without it the
    /// points go to standard output as CSV and the report to standard error.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub(crate) output: Option<PathBuf>,
    /// What the points are for: `integration` (every coordinate stratified, discrepancy as
    /// low as we can make it) or `space-filling` (stratified, largest minimum distance;
    /// what a region is given when --goal is not).
    #[arg(long, value_name = "integration|space-filling")]
    pub(crate) goal: Option<String>,
    /// `paper`: the paper's pipeline exactly (Halton start, U_{q,p} with eq. 48, the DEM,
    /// shift selection); the expert options below (--energy, --integrator, …) also
    /// select it. Or a baseline's name (`sobol`, `halton-scrambled`, `lhs`, … see
    /// `stillpoint baseline --list`), which takes only -n, -s, --seed and --bounds.
    #[arg(long, value_name = "paper|BASELINE")]
    pub(crate) method: Option<String>,
    /// What the integration goal lowers below 500 points: `blend` (D²_MD + D²_L2* +
    /// D²_CD, each relative to the start; the default below s = 8), `curved` (D²_CD, ¾ of
    /// the worst-case error for integrands of smoothness 2 with the mean curvature weighed
    /// 24×, and 1.5 % of D²_L2*; the default from s = 8), `blend-smooth` (the blend and,
    /// with weight ¼, that smoothness-2 error), `md`, `l2star`, `cd`, `periodic` or
    /// `smooth`; or `lattice`: no target, the shifted tent lattice (the default from 500
    /// points on, and at s = 1).
    #[arg(long, value_name = "KIND")]
    pub(crate) target: Option<String>,
    /// Grow an existing set: keep the points of FILE first and unchanged and add -n M new
    /// ones for the union (the integration goal in the cube).
    #[arg(long, value_name = "FILE")]
    pub(crate) extend: Option<PathBuf>,
    /// A nested set N1,N2,...,Nk (increasing; needs -s, no -n): every prefix of those
    /// lengths is a good set, each stage an extension of the one before.
    #[arg(long, value_name = "N1,N2,...")]
    pub(crate) nested: Option<String>,
    /// Write the points scaled to the box LO1,HI1,... (like `qmc.scale`); the report's
    /// metrics are those of the unit cube, and the header records the bounds. The cube
    /// only.
    #[arg(long, value_name = "LO1,HI1,...", allow_hyphen_values = true)]
    pub(crate) bounds: Option<String>,
    /// A variable of a design space, repeatable, in column order: NAME=uniform(lo,hi),
    /// normal(mu,sigma), truncnormal(mu,sigma,lo,hi), lognormal(mu,sigma),
    /// beta(a,b[,lo,hi]), triangular(lo,mode,hi), int(lo,hi) (both ends included),
    /// {a,b,c} (unordered levels), ordered{low,mid,high}, or brownian(T,m[,pca|bridge|
    /// standard]): a standard Brownian motion at t = T/m … T, m columns NAME_1 … NAME_m
    /// (pca by default). -s is their count of columns; the CSV header holds the names
    /// and categorical columns their labels.
    #[arg(long = "var", value_name = "NAME=TYPE", allow_hyphen_values = true)]
    pub(crate) var: Vec<String>,
    /// The design space's variables from a JSON file: an array of "NAME=TYPE" strings
    /// (as --var takes), or an object whose "variables" is one.
    #[arg(long, value_name = "FILE", conflicts_with = "var")]
    pub(crate) space: Option<PathBuf>,
    /// The correlation of the space's continuous variables, in their order, as rows
    /// `1,0.5;0.5,1` (a Gaussian copula; the figures are then those of the independent
    /// scores the copula maps).
    #[arg(long, value_name = "ROWS", allow_hyphen_values = true)]
    pub(crate) correlation: Option<String>,
    /// Randomise from --seed, so that independent seeds give unbiased estimates with
    /// error bars. Alone, or `tent` (recommended): the set is a lattice made for this
    /// randomisation, shifted uniformly modulo 1 and then tent-transformed (x ↦ 1 − |2x −
    /// 1|); its error decays like n⁻² for smooth integrands. `cells` (rotate the cells
    /// and shift the offsets within them; keeps the stratification) or `shift` (uniform
    /// shift modulo 1; keeps the wrap-around discrepancy and torus distances) randomise
    /// the optimised set instead. With --var/--space each point then goes through the
    /// laws' inverse CDFs (a variable with L levels to ⌊u·L⌋, not dealt by rank); not with
    /// --bounds or a region.
    // Alone it is `true`, as Python's `randomize=True`: both mean tent, and a refusal
    // echoes the same value from either front end.
    #[arg(long, value_name = "tent|cells|shift", num_args = 0..=1, default_missing_value = "true")]
    pub(crate) randomize: Option<String>,
    /// The potential energy: `uqp` (U_{q,p}, the cube's default), `e-inf` (U_{E,∞},
    /// maximin; with --q E in the closed cube, else on the torus), `e-inf-g`
    /// (U_{E,∞,g} of eq. 56, a region's default), `e-p-g` (smooth U_{E,p,g} for a
    /// region, p from --p, default 8).
    #[arg(long, value_name = "NAME")]
    #[arg(allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) energy: Option<String>,
    /// A region {x : g(x) ≤ 0}: g as an expression in x1..xs (or x, y, z), e.g.
    /// "|x| + 2*|y| - 5". Needs --box.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub(crate) region: Option<String>,
    /// Bounding box of --region (or of a polytope): LO1,HI1,LO2,HI2,...
    #[arg(long = long(Opt::bbox), value_name = "LO1,HI1,...", allow_hyphen_values = true)]
    pub(crate) bbox: Option<String>,
    /// A built-in region: `ball:R[@C1,C2,..]`, `ellipsoid:A1,A2,..[@C1,..]`,
    /// `box:LO1,HI1,LO2,HI2,..`, `simplex` (dimension from -s), or `polytope:FILE`
    /// (rows a1 .. as b meaning a·x ≤ b; needs --box).
    #[arg(long, value_name = "SHAPE", allow_hyphen_values = true)]
    pub(crate) shape: Option<String>,
    /// A linear constraint, repeatable: e.g. "x1 + 2*x2 <= 1" (numbers, x1..xs, + - * /,
    /// parentheses; one of <=, >=, ≤, ≥, or a chain "0.2 <= x1 + x2 <= 0.8"). With --box,
    /// which gives s and bounds the set: the region {A x ≤ b} ∩ box.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub(crate) constraint: Vec<String>,
    /// Mixtures: -s S components (S ≥ 2), each ≥ 0, summing to 1; --box LO1,HI1,... bounds
    /// each component and --constraint adds cuts in x1..xS. The run spreads the first S − 1
    /// components and appends x_S = 1 − Σ x_k to every point.
    #[arg(long)]
    pub(crate) mixture: bool,
    /// Draw the start beside the result, with the region's boundary (PNG or SVG by
    /// extension; the first two coordinates).
    #[arg(long, value_name = "FILE")]
    pub(crate) plot: Option<PathBuf>,
    /// q of U_{q,p}: a number > 0, `inf` (torus distance) or `E` (Euclidean).
    /// Default: eq. 48 of the paper for (n, s).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) q: Option<String>,
    /// p of U_{q,p}: a number > 0. Default: eq. 48 of the paper for (n, s).
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) p: Option<String>,
    /// How U_{q,p}'s distance is evaluated during the run for 0.01 ≤ q ≤ 2: `fast` (a
    /// table of cubics, each coordinate's h² within 4e-9; about twice as fast) or `full`
    /// (within 1e-12). Reported energies are always full. Default: fast.
    #[arg(long, value_name = "fast|full")]
    #[arg(help_heading = EXPERT)]
    pub(crate) precision: Option<String>,
    /// The solver: `dem` (the paper's damped dynamics) or `lbfgs` (argmin's L-BFGS
    /// with restarts), in the cube or a region.
    #[arg(long, value_name = "dem|lbfgs")]
    #[arg(help_heading = EXPERT)]
    pub(crate) integrator: Option<String>,
    /// Step budget of the DEM (default 1000 in the cube, as in the paper; 10 000 in a
    /// region, where U_{E,∞,g} moves only its active elements at each step).
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) steps: Option<String>,
    /// Start: `halton` (plain, indices 1..n; the cube's default), `random` (a region's
    /// default: uniform in the box, the first n inside), or a point file.
    #[arg(long, value_name = "halton|random|FILE")]
    #[arg(help_heading = EXPERT)]
    pub(crate) init: Option<String>,
    /// Seed for every random choice: the scrambles of the integration goal's starts, the
    /// randomisation, the random start.
    #[arg(long, value_name = "SEED", allow_hyphen_values = true)]
    pub(crate) seed: Option<String>,
    /// κ of eq. 39: `auto` (trial from 100, doubled while the energy fails to fall)
    /// or a fixed number ≥ 1.
    #[arg(long, value_name = "auto|K", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) kappa: Option<String>,
    /// Restart for unbiasedness (§4.3): `auto` (ε_p = 2/n), `off`, or ε_p > 0.
    #[arg(long, value_name = "auto|off|EPS", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) restart: Option<String>,
    /// Polish the result with L-BFGS on a squared discrepancy: `md`, `l2star`, `cd`,
    /// `periodic`, or `none`; it runs after the DEM and the shift selection.
    #[arg(long, value_name = "KIND")]
    #[arg(help_heading = EXPERT)]
    pub(crate) polish: Option<String>,
    /// Stop early when every coordinate step and every force step |G f|/A0 is below
    /// this (0: always use the whole budget).
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) tolerance: Option<String>,
    /// Periodic shifts tried after the DEM (0: none). The energy is unchanged by a
    /// shift on the torus, the discrepancies are not: the shift with the smallest
    /// modified L2 discrepancy is kept.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) shifts: Option<String>,
    /// Record D_L2* and D_MD every K steps in the trajectory (default 10 with
    /// --trajectory, else never).
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    #[arg(help_heading = EXPERT)]
    pub(crate) log_every: Option<String>,
    /// Write the trajectory (energy each step, discrepancies every --log-every steps)
    /// as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    #[arg(help_heading = EXPERT)]
    pub(crate) trajectory: Option<PathBuf>,
    /// Save the DEM's whole state to FILE every --checkpoint-every steps (atomically),
    /// so that an interrupted run can be continued with --resume.
    #[arg(long, value_name = "FILE")]
    #[arg(help_heading = EXPERT)]
    pub(crate) checkpoint: Option<PathBuf>,
    /// Steps between two checkpoints, K ≥ 1.
    #[arg(
        long,
        default_value = "100",
        value_name = "K",
        allow_hyphen_values = true
    )]
    #[arg(help_heading = EXPERT)]
    pub(crate) checkpoint_every: String,
    /// Continue from a checkpoint (FILE, or the --checkpoint file when no FILE is
    /// given). Every other option must be as in the run that wrote it; the result is
    /// the same bytes as an uninterrupted run.
    #[arg(long, value_name = "FILE", num_args = 0..=1)]
    #[arg(help_heading = EXPERT)]
    pub(crate) resume: Option<Option<PathBuf>>,
    /// Exact O(n²) metrics in the report at every size; by default they are estimated
    /// from random pairs above 50 000 points, each with its standard error.
    #[arg(long)]
    pub(crate) exact: bool,
    /// Print the report as one JSON object instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
    /// No progress display (the report is still printed); an explicit --progress wins
    /// over it.
    #[arg(long, short = 'q')]
    pub(crate) quiet: bool,
    /// How progress is shown on standard error: `bar` (the default on a terminal),
    /// `plain` (a line when a stage starts and at most every 10 s; the default off a
    /// terminal, e.g. in a notebook or a job's log) or `none`. Given, it wins over -q.
    #[arg(long, value_name = "bar|plain|none")]
    pub(crate) progress: Option<ProgressMode>,
}

// Parsed once per process, so the size of the largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
pub(crate) enum Command {
    /// Generate n points in [0,1)^s or a region — for integration (the default) or a
    /// space-filling design — and print their quality.
    Generate(Box<GenerateArgs>),
    /// Draw a point file (a scatter plot for s = 2, a matrix of 2-D projections of the
    /// first --dims coordinates for s > 2), or a run's trajectory (--trajectory), as PNG
    /// or SVG.
    #[command(override_usage = "stillpoint plot [OPTIONS] <FILE> -o <OUT>\n       \
                                stillpoint plot --trajectory <TRAJ> -o <OUT>")]
    Plot {
        /// The point file (CSV, TSV, whitespace, JSON, .npy).
        #[arg(value_name = "FILE", required_unless_present = "trajectory")]
        file: Option<PathBuf>,
        /// The picture: .png or .svg.
        #[arg(short = 'o', long = "output", value_name = "OUT")]
        output: PathBuf,
        /// Coordinates drawn for s > 2: the first K (1 ≤ K ≤ s), as a K × K matrix of
        /// projections (histograms on the diagonal). Default min(s, 4).
        #[arg(long, value_name = "K", allow_hyphen_values = true)]
        dims: Option<String>,
        /// Draw the boundary of the region {x : g(x) ≤ 0} (with --box), as in generate.
        #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
        region: Option<String>,
        /// The plotted box, and the bounding box of --region: LO1,HI1,LO2,HI2,...
        #[arg(long = long(Opt::bbox), value_name = "LO1,HI1,...", allow_hyphen_values = true)]
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
        /// Draw the first K points (0 ≤ K ≤ n) in one colour and the rest in another (the
        /// old and new points of a `generate --extend` result). s = 2 only.
        #[arg(long, value_name = "K", allow_hyphen_values = true)]
        split: Option<String>,
    },
    /// Print the quality of any point file (CSV, TSV, whitespace, JSON, .npy).
    /// With several files, one table with a column per file and the best value of each
    /// row marked.
    Eval {
        /// The point files; coordinates must lie in [0, 1] (or in --bounds).
        #[arg(required = true, value_name = "FILE")]
        files: Vec<PathBuf>,
        /// Print one JSON object (an array of them for several files; its keys are in
        /// docs/metrics.md, "Metrics and their names").
        #[arg(long)]
        json: bool,
        /// The box the points were scaled to (`generate --bounds`): LO1,HI1,...; they are
        /// mapped back to [0, 1]^s before they are measured.
        #[arg(long, value_name = "LO1,HI1,...", allow_hyphen_values = true)]
        bounds: Option<String>,
        /// Exact O(n²) figures at every size; by default they are estimated from random
        /// pairs above 50 000 points, each with its standard error.
        #[arg(long)]
        exact: bool,
        /// Measure the points in the region {x : g(x) ≤ 0} (with --box), as in generate:
        /// energy distance to uniform on it, minimum distance, share inside.
        #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
        region: Option<String>,
        /// The bounding box of --region (or of a polytope): LO1,HI1,LO2,HI2,...
        #[arg(long = long(Opt::bbox), value_name = "LO1,HI1,...", allow_hyphen_values = true)]
        bbox: Option<String>,
        /// Measure the points in a built-in region, as in generate.
        #[arg(long, value_name = "SHAPE", allow_hyphen_values = true)]
        shape: Option<String>,
        /// Measure a design written by `generate --var ...` (labels and all): the same
        /// variables, repeatable; the file's values are mapped back to the unit scale.
        #[arg(long = "var", value_name = "NAME=TYPE", allow_hyphen_values = true)]
        var: Vec<String>,
        /// The design's variables from a JSON file, as generate --space takes.
        #[arg(long, value_name = "FILE", conflicts_with = "var")]
        space: Option<PathBuf>,
        /// The correlation the design was made with (generate --correlation).
        #[arg(long, value_name = "ROWS", allow_hyphen_values = true)]
        correlation: Option<String>,
        /// Measure the points in {A x ≤ b} ∩ --box, as generate --constraint makes them
        /// (repeatable): energy distance to uniform on it, minimum distance, share inside.
        #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
        constraint: Vec<String>,
        /// The points are mixtures (generate --mixture): components summing to 1, within
        /// the --box bounds and --constraint cuts; measured in the first S − 1 components.
        #[arg(long)]
        mixture: bool,
    },
    /// Compare the DEM and L-BFGS on U_{q,p} and on a discrepancy energy, for a list of
    /// (s, n); writes comparison.md, comparison.json and convergence pictures.
    Compare {
        /// Cases as SxN, comma-separated (default: 2x1500,3x1500,5x1500,6x1500,5x200,10x400).
        #[arg(long, value_name = "SxN,...")]
        cases: Option<String>,
        /// Step or iteration budget per run, K ≥ 0 (0: the starts are compared).
        #[arg(
            long,
            default_value = "1000",
            value_name = "K",
            allow_hyphen_values = true
        )]
        steps: String,
        /// The discrepancy energy.
        #[arg(long, default_value = "md",
              value_parser = crate::help::listed(stillpoint::pipeline::options::words::discrepancies()))]
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
        #[arg(value_name = "NAME", required_unless_present = "list",
              value_parser = crate::help::listed(Baseline::names()))]
        name: Option<String>,
        /// Number of points n ≥ 1.
        #[arg(
            short = 'n',
            value_name = "N",
            required_unless_present = "list",
            allow_hyphen_values = true
        )]
        n: Option<String>,
        /// Dimension s ≥ 1.
        #[arg(
            short = 's',
            value_name = "S",
            required_unless_present = "list",
            allow_hyphen_values = true
        )]
        s: Option<String>,
        /// Output file (.csv, .tsv, .json, .npy); standard output as CSV without it.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
        /// Seed of the randomized generators (scrambles, random, LHS).
        #[arg(
            long,
            default_value = "0",
            value_name = "SEED",
            allow_hyphen_values = true
        )]
        seed: String,
        /// Describe every generator and exit.
        #[arg(long)]
        list: bool,
        /// Write the points scaled to this box, LO1,HI1,... (like `qmc.scale`); the
        /// metrics are those of the unit cube.
        #[arg(long, value_name = "LO1,HI1,...", allow_hyphen_values = true)]
        bounds: Option<String>,
        /// Print a JSON summary (with the points when there is no -o).
        #[arg(long)]
        json: bool,
    },
    /// Integrate the eight test functions F1–F8 of eq. 49 (exact integrals 0) with the
    /// points of a file and print each estimate, i.e. each integration error; with
    /// --expr, integrate an expression to a tolerance over the unit cube, a box or the
    /// distributions of --var/--space; with point files and --expr, the expression's
    /// mean over each file's points and their standard error.
    // The usage names both forms: clap's own would ask for a file where --expr alone runs.
    #[command(override_usage = "stillpoint integrate [OPTIONS] <FILES>...\n       \
                                stillpoint integrate --expr <EXPR> -s <S> [OPTIONS]")]
    Integrate {
        /// The point files (CSV, TSV, whitespace, JSON, .npy); coordinates in [0, 1]
        /// without --expr.
        #[arg(required_unless_present = "expr")]
        files: Vec<PathBuf>,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        quad: QuadArgs,
    },
    /// The Sobol' indices (first-order and total) of an expression's inputs to a
    /// tolerance, with their intervals: which inputs matter.
    Sensitivity(Box<SensitivityArgs>),
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
        #[arg(
            long,
            default_value = "0",
            value_name = "SEED",
            allow_hyphen_values = true
        )]
        seed: String,
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
        /// Repetitions for --points, 1 to 100000 (the median is reported).
        #[arg(
            long,
            default_value = "5",
            value_name = "K",
            allow_hyphen_values = true
        )]
        reps: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::help::flag_of;

    /// Every value-taking flag of every subcommand, at any depth, as `(path, flag,
    /// number)`: the subcommands leading to it, the flag as typed, and whether clap reads
    /// its value as a number type.
    fn value_flags() -> Vec<(Vec<String>, String, bool)> {
        fn walk(c: &clap::Command, path: &[String], out: &mut Vec<(Vec<String>, String, bool)>) {
            use std::any::TypeId;
            let numbers = [
                TypeId::of::<usize>(),
                TypeId::of::<u64>(),
                TypeId::of::<u32>(),
                TypeId::of::<u16>(),
                TypeId::of::<u8>(),
                TypeId::of::<isize>(),
                TypeId::of::<i64>(),
                TypeId::of::<i32>(),
                TypeId::of::<f64>(),
                TypeId::of::<f32>(),
            ];
            for a in c.get_arguments() {
                if !a.get_action().takes_values() {
                    continue;
                }
                let Some(flag) = flag_of(a) else { continue };
                let id = a.get_value_parser().type_id();
                let number = numbers.iter().any(|t| id == *t);
                out.push((path.to_vec(), flag, number));
            }
            for sub in c.get_subcommands() {
                let mut p = path.to_vec();
                p.push(sub.get_name().to_string());
                walk(sub, &p, out);
            }
        }
        let mut cli = Cli::command_with_declared_help();
        cli.build();
        let mut out = Vec::new();
        walk(&cli, &[], &mut out);
        out
    }

    /// A negative number after any flag that takes a value is that flag's value: never
    /// clap's unknown argument with its tip to write `-- -1`.
    #[test]
    fn a_negative_number_is_the_value_of_every_flag_that_takes_one() {
        for (path, flag, _) in &value_flags() {
            for typed in ["-1", "-3", "-0.5", "-1e3"] {
                let mut argv = vec!["stillpoint".to_string()];
                argv.extend(path.iter().cloned());
                argv.extend([flag.clone(), typed.to_string()]);
                let Err(e) = Cli::command_with_declared_help().try_get_matches_from(&argv) else {
                    continue;
                };
                let text = e.to_string();
                assert_ne!(
                    e.kind(),
                    clap::error::ErrorKind::UnknownArgument,
                    "{argv:?}: {text}"
                );
                assert!(!text.contains("-- "), "{argv:?}: {text}");
            }
        }
    }

    /// No flag's value is a number by clap's types: clap would refuse a bad one with its
    /// usage status and its type's range (`≥ 0`), not the command's range.
    #[test]
    fn no_flag_is_read_as_a_number_by_clap() {
        let flags = value_flags();
        // The walk reaches every subcommand's flags: this many at the time of writing.
        assert!(flags.len() > 40, "{}", flags.len());
        for (path, flag, number) in &flags {
            assert!(!number, "{path:?} {flag} is read as a number by clap");
        }
    }

    /// The ranges that `--threads` and `bench --reps` refuse values outside of are the
    /// ones their help gives.
    #[test]
    fn the_help_of_threads_and_reps_gives_the_range_accepted() {
        let cli = Cli::command_with_declared_help();
        let help = |c: &clap::Command, long: &str| {
            c.get_arguments()
                .find(|a| a.get_long() == Some(long))
                .and_then(|a| a.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default()
        };
        let threads = help(&cli, "threads");
        assert!(
            threads.contains(&format!("1 to {}", crate::dispatch::MAX_THREADS)),
            "{threads}"
        );
        let bench = cli.find_subcommand("bench").expect("bench");
        let reps = help(bench, "reps");
        assert!(
            reps.contains(&format!("1 to {}", crate::dispatch::MAX_REPS)),
            "{reps}"
        );
    }
}
