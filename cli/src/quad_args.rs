//! The options of `stillpoint integrate --expr`: integration to a tolerance.

/// `integrate --expr EXPR -s S --rel-tol T ...`: ∫ EXPR over [0, 1]^s (or --bounds),
/// doubling the points of R randomly shifted copies of an extensible lattice until the
/// t interval's half-width is within the tolerance.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct QuadArgs {
    /// Integrate this expression in x1..xs (the grammar of --region) to a tolerance
    /// instead of reading a point file.
    #[arg(
        long,
        value_name = "EXPR",
        requires = "dim",
        allow_hyphen_values = true
    )]
    pub(crate) expr: Option<String>,
    /// Dimension s of --expr.
    #[arg(short = 's', value_name = "S", id = "dim", requires = "expr")]
    pub(crate) s: Option<usize>,
    /// Relative tolerance: stop when the half-width ≤ max(--abs-tol, T·|estimate|).
    #[arg(long, value_name = "T", default_value_t = 1e-3, requires = "expr")]
    pub(crate) rel_tol: f64,
    /// Absolute tolerance.
    #[arg(long, value_name = "A", default_value_t = 0.0, requires = "expr")]
    pub(crate) abs_tol: f64,
    /// Confidence level of the interval.
    #[arg(long, value_name = "P", default_value_t = 0.95, requires = "expr")]
    pub(crate) level: f64,
    /// Independent random shifts (the interval comes from their spread).
    #[arg(long, value_name = "R", default_value_t = stillpoint::cubature::DEFAULT_REPLICATES, requires = "expr")]
    pub(crate) replicates: usize,
    /// The most evaluations, all replicates together.
    #[arg(long, value_name = "M", default_value_t = stillpoint::cubature::DEFAULT_MAX_N, requires = "expr")]
    pub(crate) max_n: u64,
    /// Seed of the shifts.
    #[arg(long, value_name = "N", default_value_t = 0, requires = "expr")]
    pub(crate) seed: u64,
    /// Integrate over this box instead of the unit cube: LO1,HI1,... (the volume is
    /// included).
    #[arg(
        long,
        value_name = "LO1,HI1,...",
        allow_hyphen_values = true,
        requires = "expr"
    )]
    pub(crate) bounds: Option<String>,
    /// No progress lines (the result is still printed).
    #[arg(long, short = 'q', requires = "expr")]
    pub(crate) quiet: bool,
    /// How progress is shown on standard error, one line per doubling (evaluations,
    /// estimate, half-width against its target, seconds): `bar` (the default on a
    /// terminal: the lines and a spinner while a doubling is evaluated), `plain` (the
    /// lines, also off a terminal, e.g. in a job's log) or `none` (the default off a
    /// terminal).
    // The values' own help is generate's (its plain lines are timed): not shown here.
    #[arg(
        long,
        value_name = "bar|plain|none",
        requires = "expr",
        hide_possible_values = true
    )]
    pub(crate) progress: Option<crate::ProgressMode>,
}
