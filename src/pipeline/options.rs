//! Every option of every command, declared once: its name in the library, its spelling
//! on the command line and in Python, a one-line doc, the groups whose rules it falls
//! under, the commands that take it, its value's [`Kind`] (which parses it), the values
//! it accepts and its default. The [`Request`] fields, the [`Opt`] names, [`Request::set`]
//! and [`Request::names`], the lists the resolution refuses by ([`Group`]), the names
//! front ends print in refusals ([`cli_name`], [`python_name`]) and the Python option
//! table all come from the one list below ([`ALL`]; [`OPTIONS`] are those of `generate`
//! and `eval`). A new option is one line here and its rule in the resolution
//! ([`super::request`]).

pub mod kind;
pub mod words;

use super::request::Arg;
use crate::PointSet;
pub use kind::{Field, FromValue, Kind, Value, MAX_COUNT};

/// A set of options one rule speaks of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// An option of the paper's pipeline: any of them selects it, a goal refuses them.
    Paper,
    /// The step budget of a descent: the paper's pipeline's, or the space-filling goal's.
    Descent,
    /// Taken by a baseline construction (which refuses every other option).
    Baseline,
    /// Describes a region (the run is then in that region, not the unit cube).
    Region,
    /// Places, scales or grows the unit-cube set: refused with a design space, whose
    /// dealing of one whole unit-cube set would undo it.
    Placement,
    /// Describes a design space.
    Design,
    /// Taken by `eval` (Python `metrics`): how the points are measured; the same options
    /// as those whose [`Declared::commands`] hold [`Command::Eval`].
    Eval,
}

impl Group {
    /// The group's name in the option table.
    pub fn name(self) -> &'static str {
        match self {
            Group::Paper => "paper",
            Group::Descent => "descent",
            Group::Baseline => "baseline",
            Group::Region => "region",
            Group::Placement => "placement",
            Group::Design => "design space",
            Group::Eval => "eval",
        }
    }
}

/// A command that takes options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// `generate` (Python `generate`, `design`): makes a set.
    Generate,
    /// `eval` (Python `metrics`): measures a set.
    Eval,
    /// `integrate --expr` (Python `quad`): integrates to a tolerance.
    Quad,
    /// `sensitivity` (Python `sobol_indices`): Sobol' indices to a tolerance.
    Sensitivity,
}

impl Command {
    /// Every command, in the order help lists them.
    pub const ALL: [Command; 4] = [
        Command::Generate,
        Command::Eval,
        Command::Quad,
        Command::Sensitivity,
    ];

    /// The command's name on the command line (`quad` is `integrate --expr` there).
    pub fn name(self) -> &'static str {
        match self {
            Command::Generate => "generate",
            Command::Eval => "eval",
            Command::Quad => "quad",
            Command::Sensitivity => "sensitivity",
        }
    }
}

/// One option as declared.
#[derive(Debug, Clone, Copy)]
pub struct Declared {
    /// Its name in the library: [`Request`]'s field, [`Request::set`]'s key, and the
    /// name refusals give before a front end spells it.
    pub name: &'static str,
    /// Other names [`Request::set`] accepts for it.
    pub also: &'static [&'static str],
    /// The command line's flag; empty where the command line has no such option
    /// ([`Declared::flag`]).
    pub cli: &'static str,
    /// Other flags of the command line that set it (a file of the same values, a resume).
    pub cli_also: &'static [&'static str],
    /// Python's keyword argument, or `None` where Python has no such option.
    pub python: Option<&'static str>,
    /// What it sets, in one line.
    pub doc: &'static str,
    /// Its line in a command where it means more than [`Declared::doc`] says (the
    /// intervals of `sensitivity`, where `quad` has one), as [`Declared::doc_in`] gives it.
    pub docs: &'static [(Command, &'static str)],
    /// The groups whose rules it falls under.
    pub groups: &'static [Group],
    /// The commands that take it; any other refuses it.
    pub commands: &'static [Command],
    /// The value it takes, which [`Declared::parse`] reads.
    pub kind: Kind,
    /// What a refusal of its value says is accepted.
    pub expected: fn() -> String,
    /// Its default for `command` as help shows it, `None` where it has none (or one that
    /// follows from other options).
    pub default: fn(Command) -> Option<String>,
}

impl Declared {
    /// Its line in `command`: the command's own where it has one, else `None`.
    pub fn doc_in(&self, command: Command) -> Option<&'static str> {
        self.docs
            .iter()
            .find(|(c, _)| *c == command)
            .map(|(_, t)| *t)
    }

    /// Whether the option is in `group`.
    pub fn is(&self, group: Group) -> bool {
        self.groups.contains(&group)
    }

    /// Whether `command` takes the option.
    pub fn takes(&self, command: Command) -> bool {
        self.commands.contains(&command)
    }

    /// Whether `name` is the option's library name or one of its other names.
    pub fn answers_to(&self, name: &str) -> bool {
        self.name == name || self.also.contains(&name)
    }

    /// The command line's flag, `None` where only Python has the option.
    pub fn flag(&self) -> Option<&'static str> {
        Some(self.cli).filter(|f| !f.is_empty())
    }

    /// Every word the option accepts (aliases too), from the table that owns them;
    /// empty for an option that takes no words.
    pub fn words(&self) -> Vec<&'static str> {
        match self.kind {
            Kind::Word(words) | Kind::WordOrPoints(words) | Kind::RealOrWord { words, .. } => {
                words()
            }
            _ => Vec::new(),
        }
    }
}

/// Declares the options: the [`Request`] struct (one optional [`Arg`] per option), the
/// [`Opt`] names, and the tables [`ALL`] and [`OPTIONS`] in the same order. The first
/// block holds the options of `generate` and `eval` (some shared with the integration
/// commands), the second those only the integration commands take.
macro_rules! options {
    ($(
        $field:ident: $name:literal $([$($also:literal),*])?,
        cli $cli:literal $([$($cli_also:literal),*])?,
        python $python:expr,
        [$($group:ident),*],
        for [$($command:ident),*],
        $ty:ty: $kind:expr, $expected:expr, default $default:expr,
        $doc:literal;
    )* ---- $(
        $ifield:ident: $iname:literal,
        cli $icli:literal,
        python $ipython:expr,
        for [$($icommand:ident),*],
        $ity:ty: $ikind:expr, $iexpected:expr, default $idefault:expr,
        $idoc:literal $(, in $hcommand:ident $hdoc:literal)*;
    )*) => {
        /// Every user-settable option of a run, each as a front end received it; `None`
        /// takes the default. Declared in [`ALL`], which gives each field's name,
        /// spellings, groups and commands.
        #[derive(Debug, Clone, Default, PartialEq)]
        pub struct Request {
            $(
                #[doc = $doc]
                pub $field: Option<Arg>,
            )*
            $(
                #[doc = $idoc]
                pub $ifield: Option<Arg>,
            )*
        }

        /// Every option by its declaration, so that a misspelt name does not compile:
        /// `Opt::seed.name()` is `"seed"`, `Opt::bbox.name()` is `"box"`.
        #[allow(non_camel_case_types)]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Opt {
            $(
                #[doc = $doc]
                $field,
            )*
            $(
                #[doc = $idoc]
                $ifield,
            )*
        }

        /// Every option of every command, in the order [`Request::names`] lists them.
        pub static ALL: &[Declared] = &[$(
            Declared {
                name: $name,
                also: &[$($($also),*)?],
                cli: $cli,
                cli_also: &[$($($cli_also),*)?],
                python: $python,
                doc: $doc,
                docs: &[],
                groups: &[$(Group::$group),*],
                commands: &[$(Command::$command),*],
                kind: $kind,
                expected: || ($expected).into(),
                default: $default,
            },
        )* $(
            Declared {
                name: $iname,
                also: &[],
                cli: $icli,
                cli_also: &[],
                python: $ipython,
                doc: $idoc,
                docs: &[$((Command::$hcommand, $hdoc)),*],
                groups: &[],
                commands: &[$(Command::$icommand),*],
                kind: $ikind,
                expected: || ($iexpected).into(),
                default: $idefault,
            },
        )*];

        /// The options of `generate` and `eval` (the first of [`ALL`]), in the order
        /// [`ALL`] lists them.
        pub static OPTIONS: &[Declared] = ALL.split_at([$($name),*].len()).0;

        impl Opt {
            /// The option's declaration.
            pub fn declared(self) -> &'static Declared {
                &ALL[self as usize]
            }

            /// The option's name in the library.
            pub fn name(self) -> &'static str {
                self.declared().name
            }

            /// The option named `name` (its library name or another it answers to).
            pub fn named(name: &str) -> Option<Opt> {
                ALL.iter().position(|d| d.answers_to(name)).map(|i| OPTS[i])
            }
        }

        impl Request {
            /// The value slot of the option named `name` (or one of its other names).
            pub(crate) fn slot_mut(&mut self, name: &str) -> Option<&mut Option<Arg>> {
                $(
                    if name == $name $($(|| name == $also)*)? {
                        return Some(&mut self.$field);
                    }
                )*
                $(
                    if name == $iname {
                        return Some(&mut self.$ifield);
                    }
                )*
                None
            }

            /// The value of the option `opt`, `None` when it is not given.
            pub fn arg(&self, opt: Opt) -> Option<&Arg> {
                match opt {
                    $(Opt::$field => self.$field.as_ref(),)*
                    $(Opt::$ifield => self.$ifield.as_ref(),)*
                }
            }
        }

        /// Every option of a [`Request`] read by its declaration's [`Kind`] in one pass
        /// ([`Parsed::of`]), each a typed [`Field`]: its value, none, or the refusal of
        /// the value as typed, which the resolution returns where its rules first read
        /// the option (so that of two faults the one a user meets first is said).
        #[derive(Debug, Clone)]
        pub struct Parsed {
            $(
                #[doc = $doc]
                pub $field: Field<$ty>,
            )*
            $(
                #[doc = $idoc]
                pub $ifield: Field<$ity>,
            )*
        }

        impl Parsed {
            /// Every option of `r` read by its declaration; `spell` writes an option's
            /// name in refusals as the front end does.
            pub fn of(r: &Request, spell: &dyn Fn(&str) -> String) -> Parsed {
                Parsed {
                    $($field: Field::read(Opt::$field, r.$field.as_ref(), spell),)*
                    $($ifield: Field::read(Opt::$ifield, r.$ifield.as_ref(), spell),)*
                }
            }
        }

        #[cfg(test)]
        impl Parsed {
            /// Whether the option's field holds a value or none (not a refusal).
            fn read_ok(&self, o: Opt) -> bool {
                match o {
                    $(Opt::$field => self.$field.get().is_ok(),)*
                    $(Opt::$ifield => self.$ifield.get().is_ok(),)*
                }
            }
        }

        /// Every [`Opt`], in [`ALL`]'s order.
        pub const OPTS: &[Opt] = &[$(Opt::$field,)* $(Opt::$ifield,)*];
    };
}

/// `|_| None`: no default to show.
fn none(_: Command) -> Option<String> {
    None
}

/// The counts of points and dimensions: at least `min`, at most [`MAX_COUNT`].
const fn points(min: u64) -> Kind {
    Kind::Count {
        min,
        max: MAX_COUNT,
    }
}

/// A number at least 0.
const NON_NEGATIVE: Kind = Kind::Real {
    min: 0.0,
    closed: true,
    below: None,
};

/// A number above 0.
const POSITIVE: Kind = Kind::Real {
    min: 0.0,
    closed: false,
    below: None,
};

options! {
    n: "n", cli "-n", python Some("n"), [Baseline], for [Generate],
        usize: points(1), "at least 1 point", default none,
        "Number of points (with extend: the number to add).";
    s: "s", cli "-s", python Some("d"), [Baseline], for [Generate, Quad, Sensitivity],
        usize: points(1), "at least 1 dimension", default none,
        "Dimension (a region, a design space, extend or init points may give it).";
    seed: "seed", cli "--seed", python Some("seed"), [Baseline],
        for [Generate, Quad, Sensitivity],
        u64: Kind::Seed, "a whole number in [0, 2^64)", default |_| Some("0".into()),
        "Seed of every random choice.";
    method: "method", cli "--method", python Some("method"), [Baseline], for [Generate],
        String: Kind::Word(words::methods),
        "paper (the paper's pipeline) or a baseline: random, halton, halton-scrambled, \
         sobol, hua-wang, lattice, lhs, lhs-maximin",
        default none,
        "paper (the paper's pipeline) or a baseline's name.";
    goal: "goal", cli "--goal", python Some("goal"), [], for [Generate],
        String: Kind::Word(|| words::GOALS.to_vec()), "integration or space-filling",
        default |_| Some(words::GOALS[0].into()),
        "What the points are for: integration or space-filling.";
    target: "target", cli "--target", python Some("target"), [], for [Generate],
        String: Kind::Word(words::targets), words::TARGETS, default none,
        "The discrepancy the integration goal lowers: blend, blend-smooth, curved, lattice, md, l2star, cd, periodic or smooth.";
    randomize: "randomize", cli "--randomize", python Some("randomize"), [], for [Generate],
        String: Kind::Word(words::randomizations), crate::post::randomize::Randomize::EXPECTED,
        default none,
        "Randomise the set from the seed: tent, cells or shift (with a space: each law's inverse CDF, levels floor(u*L), not dealt by rank).";
    extend: "extend", cli "--extend", python Some("extend"), [Placement], for [Generate],
        PointSet: Kind::Points, "a point set", default none,
        "Points to keep, first and unchanged, while n more are added.";
    nested: "nested", cli "--nested", python Some("nested"), [Placement], for [Generate],
        Vec<usize>: Kind::Sizes, "increasing sizes N1 < N2 < ..., N1 ≥ 1 (whole numbers)", default none,
        "Increasing sizes N1,N2,...: every prefix a good set.";
    bounds: "bounds", cli "--bounds", python Some("bounds"), [Baseline, Placement, Eval],
        for [Generate, Eval, Quad, Sensitivity],
        Value: Kind::Bounds, "LO1,HI1,LO2,HI2,...", default none,
        "Scale the points from the unit cube to the box LO1,HI1,...";
    region: "region", cli "--region", python Some("region"), [Region, Placement, Eval],
        for [Generate, Eval],
        String: Kind::Text, "text", default none,
        "A region g(x) <= 0, g an expression in x1..xs.";
    bbox: "box" ["bbox"], cli "--box", python Some("box"), [Region, Placement, Eval],
        for [Generate, Eval],
        Vec<f64>: Kind::Numbers, "LO1,HI1,LO2,HI2,...", default none,
        "The bounding box of a region, polytope or constraints: LO1,HI1,LO2,HI2,...";
    shape: "shape", cli "--shape", python Some("shape"), [Region, Placement, Eval],
        for [Generate, Eval],
        String: Kind::Text, "text", default none,
        "A built-in region: ball, ellipsoid, box, simplex or polytope.";
    constraints: "constraints" ["constraint"], cli "--constraint", python Some("constraints"),
        [Region, Placement, Eval], for [Generate, Eval],
        Vec<String>: Kind::Texts { empty: true },
        "a linear constraint as text, such as \"x1 + 2*x2 <= 1\", or a list of them",
        default none,
        "Linear constraints a.x <= b; with box, the region {A x <= b} within the box.";
    mixture: "mixture", cli "--mixture", python Some("mixture"), [Region, Placement, Eval],
        for [Generate, Eval],
        bool: Kind::Flag, "true or false", default none,
        "The components are >= 0 and sum to 1.";
    energy: "energy", cli "--energy", python Some("energy"), [Paper], for [Generate],
        String: Kind::Word(words::energies),
        "in the cube uqp, e-inf, l2star, md, cd or periodic (e-inf-g and e-p-g are \
         energies of a region)",
        default none,
        "The energy of the paper's pipeline.";
    integrator: "integrator", cli "--integrator", python Some("integrator"), [Paper],
        for [Generate],
        String: Kind::Word(|| words::INTEGRATORS.to_vec()), "dem or lbfgs",
        default |_| Some(words::INTEGRATORS[0].into()),
        "The solver: dem or lbfgs.";
    q: "q", cli "--q", python Some("q"), [Paper], for [Generate],
        Value: Kind::RealOrWord { words: || words::Q_WORDS.to_vec(), min: 0.0, closed: false },
        "a number > 0, inf (the torus distance) or E (Euclidean)", default none,
        "q of U_{q,p}: a number > 0, inf or E.";
    p: "p", cli "--p", python Some("p"), [Paper], for [Generate],
        f64: POSITIVE, "a finite number > 0", default none,
        "p of U_{q,p} (or of U_{E,p,g}).";
    precision: "precision", cli "--precision", python Some("precision"), [Paper],
        for [Generate],
        String: Kind::Word(|| words::PRECISIONS.to_vec()), "fast or full", default none,
        "How U_{q,p}'s distance is evaluated during the run: fast or full.";
    steps: "steps", cli "--steps", python Some("steps"), [Descent], for [Generate],
        usize: points(1), "a whole number of steps ≥ 1", default none,
        "The step budget of the descent.";
    init: "init", cli "--init", python Some("init"), [Paper], for [Generate],
        Value: Kind::WordOrPoints(|| words::STARTS.to_vec()), "halton, random or points",
        default none,
        "The start: halton, random or points.";
    kappa: "kappa", cli "--kappa", python Some("kappa"), [Paper], for [Generate],
        Value: Kind::RealOrWord { words: || words::KAPPA_WORDS.to_vec(), min: 1.0, closed: true },
        "auto or a finite number ≥ 1", default |_| Some(words::KAPPA_WORDS[0].into()),
        "kappa of the DEM: auto or a number >= 1.";
    restart: "restart", cli "--restart", python Some("restart"), [Paper], for [Generate],
        Value: Kind::RealOrWord { words: || words::RESTART_WORDS.to_vec(), min: 0.0, closed: false },
        "auto (ε_p = 2/n), off, or a number ε_p > 0",
        default |_| Some(words::RESTART_WORDS[0].into()),
        "Restarts of the DEM: auto, off or a threshold > 0.";
    tolerance: "tolerance", cli "--tolerance", python Some("tolerance"), [Paper],
        for [Generate],
        f64: NON_NEGATIVE, "a number ≥ 0", default none,
        "The DEM's stopping tolerance (0: the whole budget).";
    polish: "polish", cli "--polish", python Some("polish"), [Paper], for [Generate],
        String: Kind::Word(words::polishes), "none, md, l2star, cd or periodic", default none,
        "A last L-BFGS on a discrepancy: md, l2star, cd, periodic or none.";
    shifts: "shifts", cli "--shifts", python Some("shifts"), [Paper], for [Generate],
        usize: points(0),
        format!("a whole number of shifts in [0, {}]", crate::plan::start::MAX_SHIFTS),
        default none,
        "Candidate periodic shifts after the DEM.";
    log_every: "log_every", cli "--log-every", python Some("log_every"), [Paper],
        for [Generate],
        usize: points(0), "a whole number of steps ≥ 0", default none,
        "Log the discrepancies every this many steps.";
    exact: "exact", cli "--exact", python Some("exact"), [Eval], for [Generate, Eval],
        bool: Kind::Flag, "true or false", default none,
        "Exact O(n^2) metrics at every size (by default estimated above 50 000 points).";
    space: "space", cli "--var" ["--space"], python Some("space"), [Design, Eval],
        for [Generate, Eval, Quad, Sensitivity],
        Vec<String>: Kind::Texts { empty: false }, "variables NAME=TYPE", default none,
        "A design space: its variables as NAME=TYPE.";
    correlation: "correlation", cli "--correlation", python Some("correlation"),
        [Design, Eval], for [Generate, Eval, Quad],
        Value: Kind::Rows, "rows of numbers: 1,0.5;0.5,1", default none,
        "The correlation of the design space's continuous variables.";
    trajectory: "trajectory", cli "--trajectory", python None, [Paper], for [Generate],
        bool: Kind::Flag, "true or false", default none,
        "The run's trajectory is recorded.";
    checkpoint: "checkpoint", cli "--checkpoint" ["--resume"], python None, [Paper],
        for [Generate],
        bool: Kind::Flag, "true or false", default none,
        "The run is checkpointed or resumed.";
    ----
    abs_tol: "abs_tol", cli "--abs-tol", python Some("abs_tol"), for [Quad, Sensitivity],
        f64: NON_NEGATIVE, "a finite value ≥ 0",
        default |c| Some(match c {
            Command::Sensitivity => crate::sensitivity::DEFAULT_ABS_TOL.to_string(),
            _ => crate::cubature::QuadOptions::default().abs_tol.to_string(),
        }),
        "Absolute tolerance on the half-width.",
        in Sensitivity "The half-width every index must reach.";
    rel_tol: "rel_tol", cli "--rel-tol", python Some("rel_tol"), for [Quad],
        f64: NON_NEGATIVE, "a finite value ≥ 0",
        default |_| Some(crate::cubature::QuadOptions::default().rel_tol.to_string()),
        "Relative tolerance: the half-width within rel_tol times |estimate| suffices.";
    level: "level", cli "--level", python Some("level"), for [Quad, Sensitivity],
        f64: Kind::Real { min: 0.0, closed: false, below: Some(1.0) }, "a value in (0, 1)",
        default |c| Some(match c {
            Command::Sensitivity => {
                crate::sensitivity::SensitivityOptions::default().level.to_string()
            }
            _ => crate::cubature::QuadOptions::default().level.to_string(),
        }),
        "Confidence level of the interval.",
        in Sensitivity "Confidence level of the intervals.";
    replicates: "replicates", cli "--replicates", python Some("replicates"),
        for [Quad, Sensitivity],
        usize: Kind::Count { min: 2, max: crate::cubature::MAX_REPLICATES as u64 },
        crate::cubature::replicates_accepted(),
        default |c| Some(match c {
            Command::Sensitivity => crate::sensitivity::REPLICATES.to_string(),
            _ => crate::cubature::DEFAULT_REPLICATES.to_string(),
        }),
        "Independent random shifts (the interval comes from their spread).",
        in Sensitivity "Blocks of one randomised sequence: the blocks' interval comes from their spread, the posterior needs a power of two; the estimate uses all the points.";
    max_n: "max_n", cli "--max-n", python Some("max_n"), for [Quad, Sensitivity],
        u64: Kind::Count { min: 1, max: u64::MAX }, "a whole number ≥ 1",
        default |c| Some(match c {
            Command::Sensitivity => crate::sensitivity::DEFAULT_MAX_N.to_string(),
            _ => crate::cubature::DEFAULT_MAX_N.to_string(),
        }),
        "The most evaluations, all replicates together.",
        in Sensitivity "The most evaluations, all rounds.";
    rule: "rule", cli "", python Some("rule"), for [Quad],
        String: Kind::Word(words::rules),
        "lattice (the tent-transformed extensible lattice), sobol (Owen-scrambled Sobol'), pilot (the one a first round of both shows narrower), first-order lattice (the same lattice with Engine(d)'s table, made for unbounded laws) bayesian lattice (one shift of that lattice without the tent, a Bayesian cubature's interval) or bayesian net (one scrambled Sobol' sequence, a Bayesian cubature's interval with a digital kernel)",
        default none,
        "The randomised rule: lattice, sobol, pilot, first-order lattice, bayesian lattice or bayesian net (by default chosen from the laws and f).";
    simultaneous: "simultaneous", cli "--simultaneous", python Some("simultaneous"),
        for [Sensitivity],
        bool: Kind::Flag, "true or false", default |_| Some("false".into()),
        "The intervals hold all together at level (Bonferroni), not each on its own.";
    second_order: "second_order", cli "--second-order", python Some("second_order"),
        for [Sensitivity],
        bool: Kind::Flag, "true or false", default |_| Some("false".into()),
        "Also every pair's second-order index S_ij (Saltelli 2002; d more evaluations per point).";
    first_estimator: "first_estimator", cli "--first-estimator",
        python Some("first_estimator"), for [Sensitivity],
        String: Kind::Word(words::first_estimators), "saltelli or janon",
        default |_| Some(crate::sensitivity::FirstOrder::default().as_str().into()),
        "The first-order estimator: saltelli or janon.";
    interval: "interval", cli "--interval", python Some("interval"), for [Sensitivity],
        String: Kind::Word(words::intervals), "posterior or blocks",
        default |_| Some(crate::sensitivity::Interval::default().as_str().into()),
        "How each index's interval is computed: posterior (a Bayesian cubature's of the rule of all the points) or blocks (Student's over the blocks' spread).";
    start: "start", cli "", python Some("start"), for [Quad, Sensitivity],
        Value: Kind::FrontEnd, "an earlier result of the same command", default none,
        "An earlier result to continue from: its evaluations are kept.";
}

/// Names the library's parsers give a part of an option in their refusals, with the
/// option they belong to.
const PARTS: [(&str, &str); 1] = [("expression", "region")];

/// The declaration of the option `name` names (its library name, another name it
/// answers to, or the name of one of its parts).
pub fn declared(name: &str) -> Option<&'static Declared> {
    let name = PARTS
        .iter()
        .find(|(part, _)| *part == name)
        .map_or(name, |(_, option)| option);
    ALL.iter().find(|d| d.answers_to(name))
}

/// The options in `group`.
pub fn in_group(group: Group) -> impl Iterator<Item = &'static Declared> {
    ALL.iter().filter(move |d| d.is(group))
}

/// The options `command` takes.
pub fn of_command(command: Command) -> impl Iterator<Item = &'static Declared> {
    ALL.iter().filter(move |d| d.takes(command))
}

/// How the command line spells the library's parameter `name` (its flag), or the name
/// itself when no flag sets it.
pub fn cli_name(name: &str) -> String {
    declared(name)
        .and_then(Declared::flag)
        .map_or_else(|| name.to_string(), str::to_string)
}

/// How Python spells the library's parameter `name` (its keyword argument), or the name
/// itself when Python has none.
pub fn python_name(name: &str) -> String {
    declared(name)
        .and_then(|d| d.python)
        .map_or_else(|| name.to_string(), str::to_string)
}

/// The option of `generate` or `eval` ([`OPTIONS`]) Python's keyword `keyword` sets: its
/// Python keyword, or (for callers that use them) its library name or another name it
/// answers to.
pub fn by_python(keyword: &str) -> Option<&'static Declared> {
    python_keyword(OPTIONS.iter(), keyword)
}

/// The option of `command` Python's keyword `keyword` sets, as [`by_python`] finds it.
pub fn by_python_for(command: Command, keyword: &str) -> Option<&'static Declared> {
    python_keyword(of_command(command), keyword)
}

fn python_keyword(
    mut among: impl Iterator<Item = &'static Declared>,
    keyword: &str,
) -> Option<&'static Declared> {
    among.find(|d| d.python.is_some() && (d.python == Some(keyword) || d.answers_to(keyword)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spelling_names_one_option() {
        let mut seen = std::collections::HashSet::new();
        for d in ALL {
            for name in std::iter::once(d.name).chain(d.also.iter().copied()) {
                assert!(seen.insert(format!("lib {name}")), "{name} twice");
            }
            for flag in d.flag().into_iter().chain(d.cli_also.iter().copied()) {
                assert!(flag.starts_with('-'), "{flag}");
                assert!(seen.insert(format!("cli {flag}")), "{flag} twice");
            }
            if let Some(p) = d.python {
                assert!(seen.insert(format!("py {p}")), "{p} twice");
            }
            assert!(!d.doc.is_empty() && !d.doc.contains('\n'), "{}", d.name);
            assert!(d.flag().is_some() || d.python.is_some(), "{}", d.name);
            assert!(!d.commands.is_empty(), "{}", d.name);
        }
    }

    #[test]
    fn options_are_those_of_generate_and_eval_and_eval_is_its_group() {
        for d in ALL {
            let run = d.takes(Command::Generate) || d.takes(Command::Eval);
            let listed = OPTIONS.iter().any(|o| o.name == d.name);
            assert_eq!(run, listed, "{}", d.name);
            assert_eq!(d.is(Group::Eval), d.takes(Command::Eval), "{}", d.name);
        }
        assert!(OPTIONS.len() < ALL.len());
    }

    #[test]
    fn each_opt_is_its_declaration() {
        assert_eq!(OPTS.len(), ALL.len());
        for (i, o) in OPTS.iter().enumerate() {
            assert_eq!(*o as usize, i);
            assert_eq!(o.declared().name, ALL[i].name);
        }
        assert_eq!(Opt::bbox.name(), "box");
        assert_eq!(Opt::abs_tol.declared().flag(), Some("--abs-tol"));
        assert_eq!(Opt::rule.declared().flag(), None);
    }

    #[test]
    fn the_names_below_the_table_are_declared_options() {
        use crate::names as n;
        for (name, opt) in [
            (n::ABS_TOL, Opt::abs_tol),
            (n::REL_TOL, Opt::rel_tol),
            (n::INTERVAL, Opt::interval),
            (n::LEVEL, Opt::level),
            (n::MAX_N, Opt::max_n),
            (n::REPLICATES, Opt::replicates),
            (n::BOX, Opt::bbox),
            (n::CONSTRAINTS, Opt::constraints),
            (n::MIXTURE, Opt::mixture),
            (n::REGION, Opt::region),
            (n::SHAPE, Opt::shape),
            (n::ENERGY, Opt::energy),
            (n::SHIFTS, Opt::shifts),
            (n::POLISH, Opt::polish),
            (n::NESTED, Opt::nested),
            (n::CHECKPOINT, Opt::checkpoint),
            (n::RANDOMIZE, Opt::randomize),
            (n::SPACE, Opt::space),
            (n::RULE, Opt::rule),
        ] {
            assert_eq!(name, opt.name());
        }
    }

    /// Every word an option lists is read back as itself, and the refusal of a word it
    /// does not list names the option as spelt and echoes the value as typed.
    #[test]
    fn every_listed_word_parses_and_others_are_refused_as_typed() {
        let flag = |n: &str| cli_name(n);
        for d in ALL {
            for w in d.words() {
                let got = d.parse(&Arg::Text(w.to_uppercase()), &flag);
                assert_eq!(got.unwrap(), Some(Value::Word(w.to_string())), "{}", d.name);
            }
            if !d.words().is_empty() {
                let e = d.parse(&Arg::Text("Nonsense".into()), &flag).unwrap_err();
                let want = format!("invalid {} = Nonsense: expected ", flag(d.name));
                assert!(e.to_string().starts_with(&want), "{e}");
            }
        }
        for w in ["smooth", "curved", "wd"] {
            assert!(Opt::target.declared().words().contains(&w), "{w}");
            assert!(Opt::energy.declared().words().contains(&w), "{w}");
        }
        assert!(Opt::method.declared().words().contains(&"lhs-maximin"));
    }

    #[test]
    fn each_kind_reads_its_values_and_refuses_others_as_typed() {
        let plain = |n: &str| n.to_string();
        let parse = |o: Opt, a: Arg| o.declared().parse(&a, &plain);
        assert_eq!(parse(Opt::n, "12".into()).unwrap(), Some(Value::Count(12)));
        assert_eq!(
            parse(Opt::seed, Arg::Float(7.0)).unwrap(),
            Some(Value::Seed(7))
        );
        assert_eq!(
            parse(Opt::level, "0.9".into()).unwrap(),
            Some(Value::Real(0.9))
        );
        assert_eq!(parse(Opt::randomize, Arg::Bool(false)).unwrap(), None);
        assert_eq!(
            parse(Opt::kappa, "AUTO".into()).unwrap(),
            Some(Value::Word("auto".into()))
        );
        assert_eq!(
            parse(Opt::nested, "8, 16".into()).unwrap(),
            Some(Value::Sizes(vec![8, 16]))
        );
        for (o, typed, expected) in [
            (Opt::n, "0", "at least 1 point"),
            (Opt::level, "1", "a value in (0, 1)"),
            (Opt::abs_tol, "-1e-3", "a finite value ≥ 0"),
            (Opt::replicates, "1", "2 to "),
            (Opt::kappa, "0.5", "auto or a finite number ≥ 1"),
            (Opt::seed, "-1", "a whole number in [0, 2^64)"),
            (Opt::nested, "8,4", "increasing sizes"),
        ] {
            let e = parse(o, typed.into()).unwrap_err().to_string();
            let want = format!("invalid {} = {typed}: expected {expected}", o.name());
            assert!(e.starts_with(&want), "{e}");
        }
        let e = parse(Opt::n, "99999999999999".into())
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not fit in memory"), "{e}");
    }

    /// A value of each kind reads into its option's typed field: the kinds and the
    /// fields' types agree.
    #[test]
    fn a_good_value_of_each_kind_reads_into_its_typed_field() {
        let plain = |n: &str| n.to_string();
        for o in OPTS {
            let d = o.declared();
            let good = match d.kind {
                Kind::Count { min, .. } => Arg::Int(min.into()),
                Kind::Seed => Arg::Int(3),
                Kind::Real { min, below, .. } => {
                    Arg::Float(below.map_or(min + 1.0, |b| (min + b) / 2.0))
                }
                Kind::Flag => Arg::Bool(true),
                Kind::Word(_) | Kind::RealOrWord { .. } | Kind::WordOrPoints(_) => {
                    Arg::Text(d.words()[0].to_string())
                }
                Kind::Numbers | Kind::Bounds => Arg::Numbers(vec![0.0, 1.0]),
                Kind::Sizes => Arg::Text("2,4".into()),
                Kind::Points => Arg::Points(PointSet::from_rows(&[[0.5]]).unwrap()),
                Kind::Text | Kind::Rows => Arg::Text("1".into()),
                Kind::Texts { .. } => Arg::Texts(vec!["x".into()]),
                Kind::FrontEnd => continue,
            };
            let mut r = Request::default();
            r.set(d.name, good.clone()).unwrap();
            assert!(Parsed::of(&r, &plain).read_ok(*o), "{} = {good}", d.name);
        }
    }

    #[test]
    fn defaults_come_from_the_library() {
        let d = |o: Opt, c: Command| (o.declared().default)(c);
        assert_eq!(d(Opt::max_n, Command::Quad), Some((1u64 << 20).to_string()));
        assert_eq!(
            d(Opt::max_n, Command::Sensitivity),
            Some((1u64 << 22).to_string())
        );
        assert_eq!(d(Opt::abs_tol, Command::Sensitivity), Some("0.01".into()));
        assert_eq!(d(Opt::rel_tol, Command::Quad), Some("0.001".into()));
        assert_eq!(d(Opt::seed, Command::Generate), Some("0".into()));
        assert_eq!(d(Opt::n, Command::Generate), None);
    }

    #[test]
    fn each_field_answers_to_its_own_declaration() {
        for d in ALL {
            let mut r = Request::default();
            let slot = r.slot_mut(d.name).expect(d.name);
            *slot = Some(Arg::Int(7));
            let get = |r: &Request, name: &str| r.arg(Opt::named(name).unwrap()).cloned();
            assert_eq!(get(&r, d.name), Some(Arg::Int(7)), "{}", d.name);
            let others: Vec<_> = ALL
                .iter()
                .filter(|o| o.name != d.name && get(&r, o.name).is_some())
                .map(|o| o.name)
                .collect();
            assert!(others.is_empty(), "{}: {others:?}", d.name);
        }
    }
}
