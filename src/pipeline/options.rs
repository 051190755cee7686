//! Every option of a run, declared once: its name in the library, its spelling on the
//! command line and in Python, a one-line doc and the groups whose rules it falls under.
//! The [`Request`] fields, [`Request::set`] and [`Request::names`], the lists the
//! resolution refuses by ([`Group`]), the names front ends print in refusals
//! ([`cli_name`], [`python_name`]) and the Python option table all come from the one
//! list below ([`OPTIONS`]). A new option is one line here and its rule in the
//! resolution ([`super::request`]).

use super::request::Arg;

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
    /// Taken by `eval` (Python `metrics`): how the points are measured.
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

/// One option as declared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Declared {
    /// Its name in the library: [`Request`]'s field, [`Request::set`]'s key, and the
    /// name refusals give before a front end spells it.
    pub name: &'static str,
    /// Other names [`Request::set`] accepts for it.
    pub also: &'static [&'static str],
    /// The command line's flag.
    pub cli: &'static str,
    /// Other flags of the command line that set it (a file of the same values, a resume).
    pub cli_also: &'static [&'static str],
    /// Python's keyword argument, or `None` where Python has no such option.
    pub python: Option<&'static str>,
    /// What it sets, in one line.
    pub doc: &'static str,
    /// The groups whose rules it falls under.
    pub groups: &'static [Group],
}

impl Declared {
    /// Whether the option is in `group`.
    pub fn is(&self, group: Group) -> bool {
        self.groups.contains(&group)
    }

    /// Whether `name` is the option's library name or one of its other names.
    pub fn answers_to(&self, name: &str) -> bool {
        self.name == name || self.also.contains(&name)
    }
}

/// Declares the options: the [`Request`] struct (one optional [`Arg`] per option) and
/// the table [`OPTIONS`] in the same order.
macro_rules! options {
    ($(
        $field:ident: $name:literal $([$($also:literal),*])?,
        cli $cli:literal $([$($cli_also:literal),*])?,
        python $python:expr,
        [$($group:ident),*],
        $doc:literal;
    )*) => {
        /// Every user-settable option of a run, each as a front end received it; `None`
        /// takes the default. Declared in [`OPTIONS`], which gives each field's name,
        /// spellings and groups.
        #[derive(Debug, Clone, Default, PartialEq)]
        pub struct Request {
            $(
                #[doc = $doc]
                pub $field: Option<Arg>,
            )*
        }

        /// Every option, in the order [`Request::names`] lists them.
        pub static OPTIONS: &[Declared] = &[$(
            Declared {
                name: $name,
                also: &[$($($also),*)?],
                cli: $cli,
                cli_also: &[$($($cli_also),*)?],
                python: $python,
                doc: $doc,
                groups: &[$(Group::$group),*],
            },
        )*];

        impl Request {
            /// The value slot of the option named `name` (or one of its other names).
            pub(crate) fn slot_mut(&mut self, name: &str) -> Option<&mut Option<Arg>> {
                $(
                    if name == $name $($(|| name == $also)*)? {
                        return Some(&mut self.$field);
                    }
                )*
                None
            }

            /// The value of the option named `name`, `None` when it is not given or not
            /// an option.
            pub(crate) fn get(&self, name: &str) -> Option<&Arg> {
                $(
                    if name == $name $($(|| name == $also)*)? {
                        return self.$field.as_ref();
                    }
                )*
                None
            }
        }
    };
}

options! {
    n: "n", cli "-n", python Some("n"), [Baseline],
        "Number of points (with extend: the number to add).";
    s: "s", cli "-s", python Some("d"), [Baseline],
        "Dimension (a region, a design space, extend or init points may give it).";
    seed: "seed", cli "--seed", python Some("seed"), [Baseline],
        "Seed of every random choice.";
    method: "method", cli "--method", python Some("method"), [Baseline],
        "paper (the paper's pipeline) or a baseline's name.";
    goal: "goal", cli "--goal", python Some("goal"), [],
        "What the points are for: integration or space-filling.";
    target: "target", cli "--target", python Some("target"), [],
        "The discrepancy the integration goal lowers: blend, blend-smooth, curved, lattice, md, l2star, cd, periodic or smooth.";
    randomize: "randomize", cli "--randomize", python Some("randomize"), [],
        "Randomise the set from the seed: tent, cells or shift (with a space: each law's inverse CDF, levels floor(u*L), not dealt by rank).";
    extend: "extend", cli "--extend", python Some("extend"), [Placement],
        "Points to keep, first and unchanged, while n more are added.";
    nested: "nested", cli "--nested", python Some("nested"), [Placement],
        "Increasing sizes N1,N2,...: every prefix a good set.";
    bounds: "bounds", cli "--bounds", python Some("bounds"), [Baseline, Placement, Eval],
        "Scale the points from the unit cube to the box LO1,HI1,...";
    region: "region", cli "--region", python Some("region"), [Region, Placement, Eval],
        "A region g(x) <= 0, g an expression in x1..xs.";
    bbox: "box" ["bbox"], cli "--box", python Some("box"), [Region, Placement, Eval],
        "The bounding box of a region, polytope or constraints: LO1,HI1,LO2,HI2,...";
    shape: "shape", cli "--shape", python Some("shape"), [Region, Placement, Eval],
        "A built-in region: ball, ellipsoid, box, simplex or polytope.";
    constraints: "constraints" ["constraint"], cli "--constraint", python Some("constraints"),
        [Region, Placement, Eval],
        "Linear constraints a.x <= b; with box, the region {A x <= b} within the box.";
    mixture: "mixture", cli "--mixture", python Some("mixture"), [Region, Placement, Eval],
        "The components are >= 0 and sum to 1.";
    energy: "energy", cli "--energy", python Some("energy"), [Paper],
        "The energy of the paper's pipeline.";
    integrator: "integrator", cli "--integrator", python Some("integrator"), [Paper],
        "The solver: dem or lbfgs.";
    q: "q", cli "--q", python Some("q"), [Paper],
        "q of U_{q,p}: a number > 0, inf or E.";
    p: "p", cli "--p", python Some("p"), [Paper],
        "p of U_{q,p} (or of U_{E,p,g}).";
    precision: "precision", cli "--precision", python Some("precision"), [Paper],
        "How U_{q,p}'s distance is evaluated during the run: fast or full.";
    steps: "steps", cli "--steps", python Some("steps"), [Descent],
        "The step budget of the descent.";
    init: "init", cli "--init", python Some("init"), [Paper],
        "The start: halton, random or points.";
    kappa: "kappa", cli "--kappa", python Some("kappa"), [Paper],
        "kappa of the DEM: auto or a number >= 1.";
    restart: "restart", cli "--restart", python Some("restart"), [Paper],
        "Restarts of the DEM: auto, off or a threshold > 0.";
    tolerance: "tolerance", cli "--tolerance", python Some("tolerance"), [Paper],
        "The DEM's stopping tolerance (0: the whole budget).";
    polish: "polish", cli "--polish", python Some("polish"), [Paper],
        "A last L-BFGS on a discrepancy: md, l2star, cd, periodic or none.";
    shifts: "shifts", cli "--shifts", python Some("shifts"), [Paper],
        "Candidate periodic shifts after the DEM.";
    log_every: "log_every", cli "--log-every", python Some("log_every"), [Paper],
        "Log the discrepancies every this many steps.";
    exact: "exact", cli "--exact", python Some("exact"), [Eval],
        "Exact O(n^2) metrics at every size (by default estimated above 50 000 points).";
    space: "space", cli "--var" ["--space"], python Some("space"), [Design, Eval],
        "A design space: its variables as NAME=TYPE.";
    correlation: "correlation", cli "--correlation", python Some("correlation"), [Design, Eval],
        "The correlation of the design space's continuous variables.";
    trajectory: "trajectory", cli "--trajectory", python None, [Paper],
        "The run's trajectory is recorded.";
    checkpoint: "checkpoint", cli "--checkpoint" ["--resume"], python None, [Paper],
        "The run is checkpointed or resumed.";
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
    OPTIONS.iter().find(|d| d.answers_to(name))
}

/// The options in `group`.
pub fn in_group(group: Group) -> impl Iterator<Item = &'static Declared> {
    OPTIONS.iter().filter(move |d| d.is(group))
}

/// How the command line spells the library's parameter `name` (its flag), or the name
/// itself when no flag sets it.
pub fn cli_name(name: &str) -> String {
    declared(name).map_or_else(|| name.to_string(), |d| d.cli.to_string())
}

/// How Python spells the library's parameter `name` (its keyword argument), or the name
/// itself when Python has none.
pub fn python_name(name: &str) -> String {
    declared(name)
        .and_then(|d| d.python)
        .map_or_else(|| name.to_string(), str::to_string)
}

/// The option Python's keyword `keyword` sets: its Python keyword, or (for callers that
/// use them) its library name or another name it answers to.
pub fn by_python(keyword: &str) -> Option<&'static Declared> {
    OPTIONS
        .iter()
        .filter(|d| d.python.is_some())
        .find(|d| d.python == Some(keyword) || d.answers_to(keyword))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spelling_names_one_option() {
        let mut seen = std::collections::HashSet::new();
        for d in OPTIONS {
            for name in std::iter::once(d.name).chain(d.also.iter().copied()) {
                assert!(seen.insert(format!("lib {name}")), "{name} twice");
            }
            for flag in std::iter::once(d.cli).chain(d.cli_also.iter().copied()) {
                assert!(flag.starts_with('-'), "{flag}");
                assert!(seen.insert(format!("cli {flag}")), "{flag} twice");
            }
            if let Some(p) = d.python {
                assert!(seen.insert(format!("py {p}")), "{p} twice");
            }
            assert!(!d.doc.is_empty() && !d.doc.contains('\n'), "{}", d.name);
        }
    }

    #[test]
    fn each_field_answers_to_its_own_declaration() {
        for d in OPTIONS {
            let mut r = Request::default();
            let slot = r.slot_mut(d.name).expect(d.name);
            *slot = Some(Arg::Int(7));
            assert_eq!(r.get(d.name), Some(&Arg::Int(7)), "{}", d.name);
            let others: Vec<_> = OPTIONS
                .iter()
                .filter(|o| o.name != d.name && r.get(o.name).is_some())
                .map(|o| o.name)
                .collect();
            assert!(others.is_empty(), "{}: {others:?}", d.name);
        }
    }
}
