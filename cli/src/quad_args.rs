//! The options of `stillpoint integrate --expr`: integration to a tolerance.

/// `integrate --expr EXPR -s S --rel-tol T ...`: ∫ EXPR over [0, 1]^s (or --bounds),
/// doubling the points of R randomly shifted copies of an extensible lattice until the
/// t interval's half-width is within the tolerance.
///
/// Every option but `--expr` is optional with its default resolved in
/// [`QuadArgs::options`], so that one given with a point file is seen and refused rather
/// than ignored.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct QuadArgs {
    /// Integrate this expression in x1..xs (the grammar of --region) to a tolerance
    /// instead of reading a point file.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub(crate) expr: Option<String>,
    /// Dimension s of --expr (with --var or --space, their count of columns, which it
    /// may repeat).
    #[arg(
        short = 's',
        value_name = "S",
        id = "dim",
        allow_negative_numbers = true
    )]
    pub(crate) s: Option<usize>,
    /// Relative tolerance: stop when the half-width ≤ max(--abs-tol, T·|estimate|)
    /// [default: 0.001].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub(crate) rel_tol: Option<Typed<f64>>,
    /// Absolute tolerance [default: 0].
    #[arg(long, value_name = "A", allow_hyphen_values = true)]
    pub(crate) abs_tol: Option<Typed<f64>>,
    /// Confidence level of the interval [default: 0.95].
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    pub(crate) level: Option<Typed<f64>>,
    /// Independent random shifts (the interval comes from their spread) [default: 8].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub(crate) replicates: Option<Typed<usize>>,
    /// The most evaluations, all replicates together [default: 1048576].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub(crate) max_n: Option<Typed<u64>>,
    /// Seed of the shifts [default: 0].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub(crate) seed: Option<Typed<u64>>,
    /// Integrate over this box instead of the unit cube: LO1,HI1,... (the volume is
    /// included).
    #[arg(long, value_name = "LO1,HI1,...", allow_hyphen_values = true)]
    pub(crate) bounds: Option<String>,
    /// Integrate against a design space's distributions instead of over the cube: a
    /// variable as `generate --var` takes it, repeatable, in column order (x1, x2, ...
    /// of --expr are their values; a `brownian(T,m)` path gives m of them).
    #[arg(long = "var", value_name = "NAME=TYPE", allow_hyphen_values = true)]
    pub(crate) var: Vec<String>,
    /// The design space's variables from a JSON file, as `generate --space` takes it.
    #[arg(long, value_name = "FILE", conflicts_with = "var")]
    pub(crate) space: Option<std::path::PathBuf>,
    /// The correlation of the space's continuous variables as rows `1,0.5;0.5,1` (a
    /// Gaussian copula), as `generate --correlation` takes it.
    #[arg(long, value_name = "ROWS", allow_hyphen_values = true)]
    pub(crate) correlation: Option<String>,
    /// No progress lines (the result is still printed).
    #[arg(long, short = 'q')]
    pub(crate) quiet: bool,
    /// How progress is shown on standard error, one line per doubling (evaluations,
    /// estimate, half-width against its target, seconds): `bar` (the default on a
    /// terminal: the lines and a spinner while a doubling is evaluated), `plain` (the
    /// lines, also off a terminal, e.g. in a job's log) or `none` (the default off a
    /// terminal). Not with -q, which asks for none.
    // The values' own help is generate's (its plain lines are timed): not shown here.
    #[arg(long, value_name = "bar|plain|none", hide_possible_values = true)]
    pub(crate) progress: Option<crate::ProgressMode>,
}

impl QuadArgs {
    /// The first option given that only `--expr` uses, as its flag (`-s`, `--seed`, ...),
    /// in the order of the help: a point file is integrated without them.
    pub(crate) fn first_expr_only(&self) -> Option<&'static str> {
        self.given().next()
    }

    /// The first option given that only the integration to a tolerance uses: point files
    /// with `--expr` take only `-s` (checked against them) and `--level`.
    pub(crate) fn first_tolerance_only(&self) -> Option<&'static str> {
        self.given().find(|flag| !matches!(*flag, "-s" | "--level"))
    }

    /// The flags given that apply to `--expr`, in the order of the help.
    fn given(&self) -> impl Iterator<Item = &'static str> {
        [
            ("-s", self.s.is_some()),
            ("--rel-tol", self.rel_tol.is_some()),
            ("--abs-tol", self.abs_tol.is_some()),
            ("--level", self.level.is_some()),
            ("--replicates", self.replicates.is_some()),
            ("--max-n", self.max_n.is_some()),
            ("--seed", self.seed.is_some()),
            ("--bounds", self.bounds.is_some()),
            ("--var", !self.var.is_empty()),
            ("--space", self.space.is_some()),
            ("--correlation", self.correlation.is_some()),
            ("-q (--quiet)", self.quiet),
            ("--progress", self.progress.is_some()),
        ]
        .into_iter()
        .filter(|(_, given)| *given)
        .map(|(flag, _)| flag)
    }

    /// The library's settings: the options given, the documented defaults for the rest
    /// (the box is set by the caller, which checks it as `--bounds`).
    pub(crate) fn options(&self) -> stillpoint::cubature::QuadOptions {
        let d = stillpoint::cubature::QuadOptions::default();
        fn or<T: Copy>(t: &Option<Typed<T>>, default: T) -> T {
            t.as_ref().map_or(default, |t| t.value)
        }
        stillpoint::cubature::QuadOptions {
            abs_tol: or(&self.abs_tol, d.abs_tol),
            rel_tol: or(&self.rel_tol, d.rel_tol),
            level: or(&self.level, d.level),
            replicates: or(&self.replicates, d.replicates),
            max_n: or(&self.max_n, d.max_n),
            seed: or(&self.seed, d.seed),
            ..d
        }
    }

    /// The text typed for the setting the library calls `name`, if it was given: a
    /// refusal shows it rather than the number parsed (`-1e-3`, not `-0.001`).
    pub(crate) fn typed(&self, name: &str) -> Option<&str> {
        fn text<T>(t: &Option<Typed<T>>) -> Option<&str> {
            t.as_ref().map(|t| t.text.as_str())
        }
        match name {
            "abs_tol" => text(&self.abs_tol),
            "rel_tol" => text(&self.rel_tol),
            "level" => text(&self.level),
            "replicates" => text(&self.replicates),
            "max_n" => text(&self.max_n),
            "seed" => text(&self.seed),
            _ => None,
        }
    }
}

/// An option's value as parsed and as typed.
#[derive(Debug, Clone)]
pub(crate) struct Typed<T> {
    /// The value.
    pub(crate) value: T,
    /// The text on the command line.
    pub(crate) text: String,
}

impl<T: std::str::FromStr> std::str::FromStr for Typed<T>
where
    T::Err: std::fmt::Display,
{
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let value = text.parse::<T>().map_err(|e| e.to_string())?;
        Ok(Typed {
            value,
            text: text.to_string(),
        })
    }
}
