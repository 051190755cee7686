//! The words the options take, each list built from the table that gives the words
//! their meaning (the discrepancy kinds, the baselines, the randomisations, the rules),
//! or, for the words only the resolution reads, the table here that it matches on.

use crate::cubature::Rule;
use crate::energies::discrepancy::DiscrepancyKind;
use crate::post::randomize::Randomize;
use crate::sensitivity::{FirstOrder, Interval};
use crate::sequences::Baseline;

/// The integration goal's name.
pub const INTEGRATION: &str = "integration";

/// The space-filling goal's name.
pub const SPACE_FILLING: &str = "space-filling";

/// The goals `goal` names.
pub const GOALS: [&str; 2] = [INTEGRATION, SPACE_FILLING];

/// The solvers `integrator` names (`l-bfgs` is `lbfgs`).
pub const INTEGRATORS: [&str; 3] = ["dem", "lbfgs", "l-bfgs"];

/// How U_{q,p}'s distance is evaluated (`precision`).
pub const PRECISIONS: [&str; 2] = ["fast", "full"];

/// The starts `init` names (besides a point set).
pub const STARTS: [&str; 2] = ["halton", "random"];

/// The energies of the unit cube besides the discrepancies.
pub const CUBE_ENERGIES: [&str; 2] = ["uqp", "e-inf"];

/// The energies of a region (`e-inf` is also the cube's).
pub const REGION_ENERGIES: [&str; 3] = ["e-inf-g", "e-inf", "e-p-g"];

/// The target that asks for the shifted tent lattice (no descent).
pub const LATTICE: &str = "lattice";

/// The words `target` takes, as a refusal lists them.
pub const TARGETS: &str = "blend (D²_MD + D²_L2* + D²_CD), blend-smooth (the blend and the \
                           smoothness-2 error), curved (D²_CD, the smoothness-2 error with \
                           curvature weighed more and a trace of D²_L2*; the default from s \
                           = 8 below 500 points), lattice (the shifted tent lattice, no \
                           descent; the default from 500 points on and at s = 1), md, \
                           l2star, cd, periodic or smooth";

/// The targets besides a single discrepancy.
pub const BLENDS: [&str; 4] = ["blend", "blend-smooth", "curved", LATTICE];

/// The names of the paper's pipeline as a `method` (`dem` is its other name).
pub const PAPER: [&str; 2] = ["paper", "dem"];

/// `kappa`'s word besides a number.
pub const KAPPA_WORDS: [&str; 1] = ["auto"];

/// `restart`'s words besides a number (`none` is `off`).
pub const RESTART_WORDS: [&str; 3] = ["auto", "off", "none"];

/// `q`'s words besides a number: the torus distance, and `e` the Euclidean one (as
/// [`crate::energies::Distance::parse`] reads them).
pub const Q_WORDS: [&str; 4] = ["inf", "infinity", "∞", "e"];

/// The built-in shapes `shape` names (each followed by its numbers, as `ball:1`), as the
/// grammar that reads them lists them.
pub const SHAPES: [&str; 5] = crate::plan::space::shape::ALL;

/// Every name of every discrepancy kind (aliases too).
pub fn discrepancies() -> Vec<&'static str> {
    DiscrepancyKind::ALL
        .iter()
        .flat_map(|k| k.names().iter().copied())
        .collect()
}

/// `method`: the paper's pipeline (`dem` is its other name) or a baseline.
pub fn methods() -> Vec<&'static str> {
    let mut v = PAPER.to_vec();
    v.extend(Baseline::names());
    v
}

/// `target`: a blend, the lattice, or one discrepancy.
pub fn targets() -> Vec<&'static str> {
    let mut v = BLENDS.to_vec();
    v.extend(discrepancies());
    v
}

/// `energy`: those of the cube (U_{q,p}, E_∞, a discrepancy) and those of a region.
pub fn energies() -> Vec<&'static str> {
    let mut v = CUBE_ENERGIES.to_vec();
    v.extend(discrepancies());
    v.extend(
        REGION_ENERGIES
            .iter()
            .filter(|e| !CUBE_ENERGIES.contains(e)),
    );
    v
}

/// `polish`: none, or the discrepancy lowered.
pub fn polishes() -> Vec<&'static str> {
    let mut v = vec!["none"];
    v.extend(discrepancies());
    v
}

/// `randomize`: `true` (the recommended one) or a randomisation by name.
pub fn randomizations() -> Vec<&'static str> {
    let mut v = vec!["true"];
    v.extend(Randomize::ALL.iter().map(|r| r.name()));
    v
}

/// `rule`: the rules of the integration to a tolerance.
pub fn rules() -> Vec<&'static str> {
    [
        Rule::TentLattice,
        Rule::Sobol,
        Rule::Pilot,
        Rule::FirstOrderLattice,
        Rule::BayesLattice,
        Rule::BayesNet,
    ]
    .iter()
    .map(|r| r.as_str())
    .collect()
}

/// `first_estimator`: the first-order estimators of the Sobol' indices.
pub fn first_estimators() -> Vec<&'static str> {
    [FirstOrder::Saltelli, FirstOrder::Janon]
        .iter()
        .map(|f| f.as_str())
        .collect()
}

/// `interval`: how the Sobol' indices' intervals are computed.
pub fn intervals() -> Vec<&'static str> {
    [Interval::Posterior, Interval::Blocks]
        .iter()
        .map(|i| i.as_str())
        .collect()
}

/// Words as a refusal lists them: `a, b or c`.
pub fn listed(words: &[&str]) -> String {
    match words.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => words.join(""),
    }
}
