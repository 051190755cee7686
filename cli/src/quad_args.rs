//! The options of `stillpoint integrate --expr`: integration to a tolerance.

use crate::values::{flag, other_flag};
use stillpoint::pipeline::options::{cli_name, Opt};
use stillpoint::pipeline::request::Arg;
use stillpoint::Request;

/// `integrate --expr EXPR -s S --rel-tol T ...`: ∫ EXPR over [0, 1]^s (or --bounds),
/// doubling the points of R randomly shifted copies of an extensible lattice until the
/// t interval's half-width is within the tolerance.
///
/// Every option but `--expr` is optional with its default resolved in
/// [`QuadArgs::options`], so that one given with a point file is seen and refused rather
/// than ignored.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct QuadArgs {
    /// Integrate this expression in x1..xs (the grammar of --region; under --var or
    /// --space also in the variables' own names) to a tolerance instead of reading a
    /// point file.
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub(crate) expr: Option<String>,
    /// Dimension s of --expr (with --var or --space, their count of columns, which it
    /// may repeat).
    #[arg(short = 's', value_name = "S", id = "dim", allow_hyphen_values = true)]
    pub(crate) s: Option<String>,
    /// Relative tolerance: stop when the half-width ≤ max(--abs-tol, T·|estimate|).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub(crate) rel_tol: Option<String>,
    #[command(flatten)]
    pub(crate) tolerance: ToleranceArgs,
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
        self.flags_given().next()
    }

    /// The first option given that only the integration to a tolerance uses: point files
    /// with `--expr` take only `-s` (checked against them) and `--level`.
    pub(crate) fn first_tolerance_only(&self) -> Option<&'static str> {
        let kept = [Opt::s, Opt::level].map(|o| o.declared().flag());
        self.flags_given().find(|flag| !kept.contains(&Some(flag)))
    }

    /// The flags given that apply to `--expr`, in the order of the help.
    fn flags_given(&self) -> impl Iterator<Item = &'static str> {
        [
            ("-s", self.s.is_some()),
            (flag(Opt::rel_tol), self.rel_tol.is_some()),
        ]
        .into_iter()
        .chain(self.tolerance.given())
        .chain([
            (flag(Opt::bounds), self.bounds.is_some()),
            (flag(Opt::space), !self.var.is_empty()),
            (other_flag(Opt::space), self.space.is_some()),
            (flag(Opt::correlation), self.correlation.is_some()),
            ("-q (--quiet)", self.quiet),
            ("--progress", self.progress.is_some()),
        ])
        .filter(|(_, given)| *given)
        .map(|(flag, _)| flag)
    }

    /// The options given as the library resolves them ([`Request`]): each value as its
    /// text typed, which the library parses, checks and echoes; `--var`/`--space` as the
    /// space's variables.
    pub(crate) fn options(&self) -> anyhow::Result<Request> {
        Ok(self.tolerance.onto(Request {
            s: typed_arg(&self.s),
            bounds: self.bounds.as_deref().map(Arg::from),
            rel_tol: typed_arg(&self.rel_tol),
            space: space_items(&self.var, self.space.as_deref())?,
            correlation: self.correlation.as_deref().map(Arg::from),
            ..Request::default()
        }))
    }

    /// The flag `--var` or `--space` that gives the space, for refusals.
    pub(crate) fn space_flag(&self) -> &'static str {
        match (&self.space, self.var.is_empty()) {
            (Some(_), _) => other_flag(Opt::space),
            (None, false) => flag(Opt::space),
            (None, true) => "--var or --space",
        }
    }

    /// `--level` read by its declaration (the integration's default when not given).
    pub(crate) fn level(&self) -> anyhow::Result<f64> {
        let Some(text) = self.tolerance.level.as_deref() else {
            return Ok(stillpoint::cubature::QuadOptions::default().level);
        };
        match Opt::level.declared().parse(&Arg::from(text), &cli_name)? {
            Some(stillpoint::pipeline::options::Value::Real(level)) => Ok(level),
            _ => anyhow::bail!("invalid --level = {text}"),
        }
    }
}

/// The options of every integration to a tolerance (`integrate --expr`, `sensitivity`),
/// one clap field each, flattened into both commands: the same flags, read the same way.
/// Their short help, default and accepted values are written from the declarations
/// ([`crate::help`]), which also give a command its own line where the option means
/// more there (the intervals of `sensitivity`).
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct ToleranceArgs {
    /// Absolute tolerance on the half-width.
    #[arg(long, value_name = "A", allow_hyphen_values = true)]
    pub(crate) abs_tol: Option<String>,
    /// Confidence level of the interval.
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    pub(crate) level: Option<String>,
    /// Independent random shifts (the interval comes from their spread).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub(crate) replicates: Option<String>,
    /// The most evaluations, all replicates together.
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub(crate) max_n: Option<String>,
    /// Seed of the shifts.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub(crate) seed: Option<String>,
}

impl ToleranceArgs {
    /// Each flag and whether it was given, in the order of the help.
    fn given(&self) -> [(&'static str, bool); 5] {
        [
            (flag(Opt::abs_tol), self.abs_tol.is_some()),
            (flag(Opt::level), self.level.is_some()),
            (flag(Opt::replicates), self.replicates.is_some()),
            (flag(Opt::max_n), self.max_n.is_some()),
            (flag(Opt::seed), self.seed.is_some()),
        ]
    }

    /// `r` with these options as typed, for the library to parse by their declarations.
    pub(crate) fn onto(&self, r: Request) -> Request {
        Request {
            abs_tol: typed_arg(&self.abs_tol),
            level: typed_arg(&self.level),
            replicates: typed_arg(&self.replicates),
            max_n: typed_arg(&self.max_n),
            seed: typed_arg(&self.seed),
            ..r
        }
    }
}

/// A value as typed, for the library to parse by its declaration.
pub(crate) fn typed_arg(t: &Option<String>) -> Option<Arg> {
    t.as_deref().map(Arg::from)
}

/// A design space's variables from `--var` (repeated) or `--space FILE`.
pub(crate) fn space_items(
    var: &[String],
    file: Option<&std::path::Path>,
) -> anyhow::Result<Option<Arg>> {
    Ok(match file {
        Some(path) => Some(Arg::Texts(crate::read_space(path)?)),
        None => (!var.is_empty()).then(|| Arg::Texts(var.to_vec())),
    })
}

/// How the integration commands spell the library's option `name`: its declared flag,
/// and for the space (and its variables, `space x`) `space_flag`, the flag that gave it.
pub(crate) fn integration_flag(name: &str, space_flag: &str) -> String {
    match name.split_once(' ') {
        Some((space, rest)) if space == Opt::space.name() => format!("{space_flag} {rest}"),
        _ if name == Opt::space.name() => space_flag.to_string(),
        _ => cli_name(name),
    }
}
