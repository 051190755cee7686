//! What a run reports: the start and the result with their quality, and what each stage did.

use crate::config::GenerateConfig;
use crate::plan::problem::EnergyChoice;
use crate::post::shift::ShiftOutcome;
use crate::Error;
use serde::Serialize;
use std::fmt;
use stillpoint_domains::PointSet;
use stillpoint_integrators::{RunOutput, StopReason};
use stillpoint_quality::metrics::Metrics;
use stillpoint_quality::region::RegionMetrics;

/// The quality of a set, as fits its space.
#[derive(Debug, Clone, PartialEq)]
pub enum Quality {
    /// Discrepancies, distances and energies in the unit cube.
    Cube(Metrics),
    /// U_{E,∞,g}, the minimum point distance and boundary distance in a region.
    Region(RegionMetrics),
}

/// The outcome of a `generate` run.
#[derive(Debug, Clone)]
pub struct GenerateReport {
    /// The start set.
    pub start: PointSet,
    /// The final set, and for the paper's pipeline its solver's trajectory, stop and
    /// facts. A goal run is no single solver run: its trajectory and facts are empty and
    /// its `stop` says nothing (read [`GenerateReport::solver`]); what it did is in
    /// [`GenerateReport::stages`].
    pub output: RunOutput,
    /// Energy of the start and of the result.
    pub energy: (f64, f64),
    /// The energy's name with its parameters.
    pub energy_name: String,
    /// Quality of the start and of the result.
    pub quality: (Quality, Quality),
    /// How the paper's energy was chosen; `None` for a goal run, which has no (q, p).
    pub choice: Option<EnergyChoice>,
    /// The shift selection after the DEM, when it ran.
    pub shift: Option<ShiftOutcome>,
    /// The polish, when it ran: (squared discrepancy before, after, L-BFGS iterations).
    pub polish: Option<(f64, f64, usize)>,
    /// What a goal's pipeline did, stage by stage (empty for the paper's pipeline,
    /// `stillpoint::pipeline::Pipeline::Paper`, whose solver, shift and polish have fields
    /// of their own).
    pub stages: Vec<Stage>,
    /// Wall time of the whole run in seconds.
    pub seconds: f64,
    /// Where the time went: each phase of the run with its wall seconds, in order.
    pub timings: Vec<(String, f64)>,
}

impl GenerateReport {
    /// The solver's run of the paper's pipeline; `None` for a goal run, whose stages
    /// record each of its solver runs instead.
    pub fn solver(&self) -> Option<&RunOutput> {
        self.choice.as_ref().map(|_| &self.output)
    }

    /// The cube metrics of the start and the result; an error for a region run, whose
    /// quality is measured by [`GenerateReport::region_metrics`].
    pub fn cube_metrics(&self) -> Result<(&Metrics, &Metrics), Error> {
        match &self.quality {
            (Quality::Cube(a), Quality::Cube(b)) => Ok((a, b)),
            _ => Err(Error::invalid(
                "metrics",
                "a region run",
                "a cube run (a region's figures are its region metrics)",
            )),
        }
    }

    /// The region figures of the start and the result; an error for a cube run.
    pub fn region_metrics(&self) -> Result<(&RegionMetrics, &RegionMetrics), Error> {
        match &self.quality {
            (Quality::Region(a), Quality::Region(b)) => Ok((a, b)),
            _ => Err(Error::invalid(
                "region metrics",
                "a cube run",
                "a region run (a cube's figures are its metrics)",
            )),
        }
    }

    /// 1 − U_{E,∞,g}(result) / U_{E,∞,g}(start): the paper's "optimization ratio" in a
    /// region.
    pub fn reduction(&self) -> Result<f64, Error> {
        self.region_metrics()
            .map(|(a, b)| 1.0 - b.energy_e_inf_g / a.energy_e_inf_g)
    }
}

/// The quality figures of a set in the configuration's space.
pub fn quality(cfg: &GenerateConfig, points: &PointSet) -> Result<Quality, Error> {
    Ok(match cfg.region() {
        Some(domain) => Quality::Region(RegionMetrics::compute(domain, points)?),
        None => Quality::Cube(Metrics::compute_with(points, cfg.sums)),
    })
}

/// A set a goal compared with others, and the value it was judged by.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// Where the set came from, e.g. `sobol(SEED)`.
    pub label: String,
    /// The value it was judged by (the stage says which).
    pub value: f64,
}

/// One round of the stratified descent: exchanges, then L-BFGS on the offsets.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Round {
    /// Exchange proposals evaluated.
    pub proposals: usize,
    /// Exchanges accepted, each because it lowered the target.
    pub accepted: usize,
    /// L-BFGS iterations on the offsets inside the cells.
    pub lbfgs_iterations: usize,
    /// Why that L-BFGS run stopped.
    pub lbfgs_stop: StopReason,
    /// Whether its result was kept: only when it lowered the target.
    pub lbfgs_kept: bool,
}

/// The stratified descent of the integration goal, or why it did not run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Descent {
    /// The points it may move (all of them, or an extension's new ones).
    pub moving: usize,
    /// The rounds run; empty when the descent was skipped.
    pub rounds: Vec<Round>,
    /// Why no round ran, when none did.
    pub skipped: Option<String>,
    /// Why the rounds made no exchanges, when they ran without.
    pub exchanges_skipped: Option<String>,
    /// The block exchanges run where no round fits the work cap.
    pub blocks: Option<BlockExchanges>,
}

/// The exchanges of a set too large for the descent, a block of points at a time
/// ([`crate::goals::integration::blocks`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlockExchanges {
    /// Points per block.
    pub block: usize,
    /// Blocks loaded.
    pub blocks: usize,
    /// Proposals evaluated.
    pub proposals: usize,
    /// Swaps accepted, each because it lowered every discrepancy of the target.
    pub accepted: usize,
    /// Each discrepancy of the target (by its `--target` name) and the exact change of
    /// its square over the accepted swaps.
    pub changes: Vec<(String, f64)>,
}

impl fmt::Display for BlockExchanges {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let changes: Vec<String> = self
            .changes
            .iter()
            .map(|(name, d)| format!("{name} {d:+.3e}"))
            .collect();
        write!(
            f,
            "block exchanges ({} blocks of {} points, their pair rows held instead of the \
             n² table): {} of {} swaps accepted, each lowering every discrepancy of the \
             target; exact changes of the squares: {}",
            self.blocks,
            self.block,
            self.accepted,
            self.proposals,
            changes.join(", ")
        )
    }
}

impl Descent {
    /// Exchanges accepted over all rounds.
    pub fn accepted(&self) -> usize {
        self.rounds.iter().map(|r| r.accepted).sum()
    }

    /// L-BFGS iterations over all rounds.
    pub fn lbfgs_iterations(&self) -> usize {
        self.rounds.iter().map(|r| r.lbfgs_iterations).sum()
    }
}

/// Whether the lattice was descended from
/// ([`crate::goals::integration::tent::tent_set`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "descent", rename_all = "snake_case")]
pub enum TentDescent {
    /// Every coordinate has a generator of its own: the lattice is the set.
    NotNeeded,
    /// Coordinates share generators, but a descent would take more than its budget
    /// (`work` pair-coordinate terms per iteration): the lattice is the set.
    TooCostly {
        /// n²·s.
        work: f64,
    },
    /// Coordinates share generators and the set was descended from the lattice.
    Descended {
        /// The criterion of the set kept (the descended set's ranks).
        criterion: f64,
        /// L-BFGS iterations taken.
        iterations: usize,
        /// Whether the result was kept (its criterion below the lattice's).
        kept: bool,
    },
}

/// What one stage of a goal's run did, as data; its [`fmt::Display`] is the report's line.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "stage", rename_all = "snake_case")]
pub enum Stage {
    /// A start chosen among candidates by the target, the lowest kept.
    Start {
        /// The size of the set the start is for.
        n: usize,
        /// What the candidates are, e.g. how they were stratified or placed.
        made: String,
        /// The candidates with their target values.
        candidates: Vec<Candidate>,
        /// The index of the one kept.
        kept: usize,
    },
    /// The stratified descent, then the columns centred.
    Descent(Descent),
    /// An extension's facts: old points kept first, new ones added.
    Extension {
        /// Old points, unchanged.
        old: usize,
        /// New points.
        new: usize,
        /// Whether the union is stratified on its own grid.
        stratified: bool,
        /// Old points sharing a cell of the union's grid with another (summed over the
        /// coordinates): each leaves a cell empty.
        collisions: usize,
    },
    /// The root discrepancies of a part of the result.
    Figures {
        /// Which part, e.g. `first 16` or `union`.
        of: String,
        /// D_MD.
        modified_l2: f64,
        /// D_L2*.
        star_l2: f64,
        /// The centred L2 discrepancy.
        centered_l2: f64,
        /// Whether that part is stratified on its own grid, when it matters.
        stratified: Option<bool>,
    },
    /// The paper's DEM as the space-filling goal runs it.
    Dem {
        /// The energy.
        energy: String,
        /// Steps taken.
        steps: usize,
        /// Why it stopped.
        stop: StopReason,
    },
    /// The maximin swap search: candidates by their minimum distance after a search,
    /// the largest kept, then further passes from it.
    Maximin {
        /// The candidates with their minimum (Euclidean) distance after the search.
        candidates: Vec<Candidate>,
        /// The index of the one kept.
        kept: usize,
        /// The minimum distance after each further pass.
        passes: Vec<f64>,
    },
    /// The rank-1 lattice made for the tent randomisation, built component by component.
    Lattice {
        /// Its generating vector z: point k is frac(k z / n).
        generator: Vec<u64>,
        /// The coordinates' weight γ in the criterion.
        weight: f64,
        /// The criterion: the randomised estimate's mean square error bound.
        criterion: f64,
        /// Whether the set was descended from the lattice (coordinates sharing
        /// generators).
        descent: TentDescent,
    },
    /// L-BFGS on the energy distance to a reference sample of a region's uniform
    /// distribution (the integration goal in a region).
    EnergyDescent {
        /// How the start was made.
        start: String,
        /// How the reference sample was made.
        reference: String,
        /// L-BFGS iterations taken.
        iterations: usize,
        /// Why it stopped.
        stop: StopReason,
    },
    /// The default set from [`crate::goals::integration::lattice::LATTICE_FROM_N`] points
    /// on: the tent lattice under a shift chosen coordinate by coordinate, tent-transformed.
    LatticeRule {
        /// Its generating vector z.
        generator: Vec<u64>,
        /// The shift's numerators q_j: point k is φ(frac(k z_j/n + q_j/(4n))).
        shift: Vec<u64>,
        /// The coordinates' weight γ in the criterion.
        weight: f64,
        /// Candidate shift numerators per coordinate (every odd q < 4n).
        candidates: usize,
        /// The criterion of the seed's first draw of shifts.
        drawn: f64,
        /// The criterion of the set kept.
        criterion: f64,
        /// The columns that reuse an earlier column's generator up to sign, as (column,
        /// earlier column, z), counted from 1 (more columns than the lattice has
        /// generators that differ).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        shared: Vec<(usize, usize, u64)>,
        /// Why columns share a generator and which, when they do.
        #[serde(skip_serializing_if = "Option::is_none")]
        note: Option<String>,
    },
    /// The result randomised after the goal's run.
    Randomized {
        /// How.
        how: String,
        /// From which seed.
        seed: u64,
    },
}

fn candidates_text(c: &[Candidate], kept: usize, sci: bool) -> String {
    c.iter()
        .enumerate()
        .map(|(i, c)| {
            let mark = if i == kept { " (kept)" } else { "" };
            // Past the dimension where the target's closed form fits a float, no
            // candidate is ranked by it: each says so, and the first is kept.
            if !c.value.is_finite() {
                format!("{} not representable in f64{mark}", c.label)
            } else if sci || c.value.abs() >= 1e12 {
                format!("{} {:.6e}{mark}", c.label, c.value)
            } else {
                format!("{} {:.6}{mark}", c.label, c.value)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl fmt::Display for Descent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(why) = &self.skipped {
            write!(f, "descent skipped: {why}; columns centred")?;
            if let Some(b) = &self.blocks {
                write!(f, "; then {b}")?;
            }
            return Ok(());
        }
        let stops: Vec<String> = self
            .rounds
            .iter()
            .map(|r| {
                format!(
                    "{} ({:?}{})",
                    r.lbfgs_iterations,
                    r.lbfgs_stop,
                    if r.lbfgs_kept { "" } else { ", not kept" }
                )
            })
            .collect();
        write!(
            f,
            "descent of {} points: {} rounds; exchanges accepted {} of {} proposed",
            self.moving,
            self.rounds.len(),
            self.accepted(),
            self.rounds.iter().map(|r| r.proposals).sum::<usize>(),
        )?;
        if let Some(why) = &self.exchanges_skipped {
            write!(f, " (none run: {why})")?;
        }
        write!(
            f,
            "; in-cell L-BFGS iterations {} (per round: {}); columns centred",
            self.lbfgs_iterations(),
            stops.join(", ")
        )
    }
}

/// The [`Stage::LatticeRule`] line: generator, shift numerators and the criterion chosen
/// by (`values`: the seed's drawn shift's, then the kept one's).
fn lattice_rule_text(
    f: &mut fmt::Formatter<'_>,
    generator: &[u64],
    shift: &[u64],
    weight: f64,
    candidates: usize,
    values: (f64, f64),
    note: Option<&str>,
) -> fmt::Result {
    let list = |v: &[u64]| {
        v.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (drawn, criterion) = values;
    write!(
        f,
        "rank-1 lattice built component by component, z = ({}); shift q/(4n) with \
         q = ({}) (every column the midpoints (i + ½)/n after the tent transform), \
         chosen coordinate by coordinate among all {candidates} odd q < 4n on the \
         order-2 cosine-space error (weight {weight}): {criterion:.4e}, the seed's \
         drawn shift {drawn:.4e}; then the tent transform x ↦ 1 − |2x − 1|",
        list(generator),
        list(shift)
    )?;
    match note {
        Some(note) => write!(f, "\n  note: {note}"),
        None => Ok(()),
    }
}

/// The [`Stage::Extension`] line: the union's sizes and whether it is stratified (else
/// how many old values collide).
fn extension_text(
    f: &mut fmt::Formatter<'_>,
    old: usize,
    new: usize,
    stratified: bool,
    collisions: usize,
) -> fmt::Result {
    write!(
        f,
        "extended {old} old points (first, unchanged) by {new} new ones; union \
         stratified on its {} cells per coordinate: ",
        old + new
    )?;
    if stratified {
        write!(f, "yes")
    } else {
        write!(
            f,
            "no (summed over the coordinates, {collisions} old values fall in a \
             cell of the union's grid that another old point already takes, so \
             as many cells stay empty)"
        )
    }
}

/// The tail of the [`Stage::Figures`] line: whether the part is stratified, when asked.
fn stratified_text(f: &mut fmt::Formatter<'_>, stratified: Option<bool>) -> fmt::Result {
    match stratified {
        Some(yes) => write!(f, ", stratified: {}", if yes { "yes" } else { "no" }),
        None => Ok(()),
    }
}

/// The tail of the [`Stage::Lattice`] line: nothing when the lattice needed no descent,
/// else why it was or was not descended from, after a semicolon.
impl fmt::Display for TentDescent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TentDescent::NotNeeded => Ok(()),
            TentDescent::TooCostly { work } => write!(
                f,
                "; coordinates share generators, but a descent ({work:.1e} pair \
                 terms per iteration) is past its budget: the lattice is kept"
            ),
            TentDescent::Descended {
                criterion,
                iterations,
                kept: true,
            } => write!(
                f,
                "; coordinates share generators, so the set was descended on the \
                 criterion ({iterations} L-BFGS iterations) and each column \
                 replaced by its ranks: criterion {criterion:.4e}"
            ),
            TentDescent::Descended {
                criterion,
                iterations,
                kept: false,
            } => write!(
                f,
                "; coordinates share generators, but the descended set \
                 ({iterations} iterations, criterion {criterion:.4e}) was no lower: \
                 the lattice is kept"
            ),
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stage::Start {
                n,
                made,
                candidates,
                kept,
            } => write!(
                f,
                "start for {n} points: {made}; by the target (lowest kept): {}",
                candidates_text(candidates, *kept, true)
            ),
            Stage::Descent(d) => write!(f, "{d}"),
            Stage::Extension {
                old,
                new,
                stratified,
                collisions,
            } => extension_text(f, *old, *new, *stratified, *collisions),
            Stage::Figures {
                of,
                modified_l2,
                star_l2,
                centered_l2,
                stratified,
            } => {
                write!(
                    f,
                    "{of}: D_MD {modified_l2:.6}, D_L2* {star_l2:.6}, CD {centered_l2:.6}"
                )?;
                stratified_text(f, *stratified)
            }
            Stage::Dem {
                energy,
                steps,
                stop,
            } => write!(
                f,
                "DEM on {energy}: {steps} steps ({stop:?}), then stratified"
            ),
            Stage::EnergyDescent {
                start,
                reference,
                iterations,
                stop,
            } => write!(
                f,
                "L-BFGS on the energy distance to {reference}: {iterations} iterations \
                 ({stop:?}) from {start}"
            ),
            Stage::Maximin {
                candidates,
                kept,
                passes,
            } => write!(
                f,
                "maximin swap search, minimum distance after it (largest kept): {}; {} more \
                 passes from the kept one: {}",
                candidates_text(candidates, *kept, false),
                passes.len(),
                passes
                    .iter()
                    .map(|d| format!("{d:.6}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Stage::Lattice {
                generator,
                weight,
                criterion,
                descent,
            } => {
                let z: Vec<String> = generator.iter().map(|v| v.to_string()).collect();
                write!(
                    f,
                    "rank-1 lattice for the tent randomisation, built component by \
                     component: z = ({}), criterion {criterion:.4e} (weight {weight}){descent}",
                    z.join(", ")
                )
            }
            Stage::LatticeRule {
                generator,
                shift,
                weight,
                candidates,
                drawn,
                criterion,
                shared: _,
                note,
            } => lattice_rule_text(
                f,
                generator,
                shift,
                *weight,
                *candidates,
                (*drawn, *criterion),
                note.as_deref(),
            ),
            Stage::Randomized { how, seed } => write!(f, "randomised ({how}) from seed {seed}"),
        }
    }
}
