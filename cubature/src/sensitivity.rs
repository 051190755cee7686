//! Sobol' sensitivity indices to a tolerance: which inputs of a model matter, as the
//! first-order index S_i (the share of the output's variance explained by input i alone)
//! and the total index T_i (the share in which input i takes part at all), each with a
//! confidence interval, for independent inputs.
//!
//! The design is pick-freeze on a randomised extensible rule in 2d dimensions (by
//! default the tent-transformed lattice [`stillpoint_sequences::ExtensibleLattice`], or
//! Owen-scrambled Sobol' points, [`Rule`]): point k of replicate r is u ∈ [0, 1)^{2d},
//! input i's A coordinate is u_{2i−1} and its B coordinate u_{2i} (neighbours among the
//! rule's leading coordinates, whose projections are its best), and f is evaluated at A, at B and, for each input i, at AB_i (A with
//! coordinate i taken from B): d + 2 evaluations per point. The points are the first N
//! of one randomised sequence, cut into R aligned blocks of N/R (8 by default, the
//! replicates); N doubles, each batch extending the last (no evaluation is discarded;
//! the earlier blocks merge in pairs), until every index's half-width is at most
//! `abs_tol`. The lattice has 1 000 coordinates, so d ≤ 500 inputs, and 2^20 points. A
//! doubling comes as batches of at most [`BATCH_COORDINATES`], so a run's memory is
//! bounded whatever d and N are.
//! Before the lattice's first batch a face test (8·d evaluations, counted in n) finds the
//! inputs f is periodic in, whose coordinates the lattice then takes without the tent
//! ([`Sensitivity::periodic`]): the tent doubles a periodic model's frequencies.
//!
//! The estimators (with y the output centred by a constant fixed at the first batch, V
//! its variance from the A and B values together):
//!
//! ```text
//! total:  T_i = (1/2n) Σ (y_A − y_ABi)² / V_i                (Janon et al. 2014)
//!     or  T_i = (1/2n) Σ (y_A − y_ABi)² / V                  (Jansen 1999)
//! first:  S_i = (1/n) Σ y_B (y_ABi − y_A) / V                (Saltelli et al. 2010)
//!     or  S_i = Janon et al. (2014): the correlation of y_B and y_ABi with the means and
//!               variances pooled over both
//! pairs:  S_ij = [(1/2n) Σ (y_BAi·y_ABj + y_BAj·y_ABi) − (1/n) Σ y_A·y_B] / V − S_i − S_j
//!               (Saltelli 2002, symmetrised; by name, `second_order`: f also at each
//!               BA_i, B with coordinate i taken from A, 2d + 2 evaluations per point)
//! ```
//!
//! Janon's total is 1 minus the pooled correlation of y_A and y_ABi (which share every
//! input but i), which is Jansen's numerator over V_i, the variance of the A and AB_i
//! values together, rather than over V: at equal evaluations its error was 0.94× Jansen's
//! in geometric mean over the seven models of the benchmark, with the same coverage
//! (results/sensitivity/design.md). Of the first-order ones, Saltelli 2010's difference form has a variance that vanishes
//! with T_i (small indices are estimated well); Janon's is asymptotically efficient for
//! large S_i. `benches/sensitivity.py` and `tests/sensitivity.rs` measure both; the
//! default is the one with the lower error over the closed-form models
//! ([`FirstOrder::Saltelli`]).
//!
//! The interval ([`Interval`]): every index is a smooth function of means over the
//! points, and the estimate uses the means pooled over the R blocks (the one rule of N
//! points). By default ([`Interval::Posterior`], on the lattice) its error is priced as a
//! Bayesian cubature prices the rule of all N points: the index's linearisation ψ at each
//! point, a shift-invariant kernel over the 2d coordinates weighted by each input's total
//! index and fitted to ψ by maximum likelihood, and the posterior's normal quantile at
//! 1 − (1 − level)/[`crate::POSTERIOR_MISS`] (see [`Sensitivity::posterior_sd`]). To
//! 0.02 it took half the evaluations of the blocks' interval on four of the seven models
//! of the benchmark and no more on the others (results/sensitivity/sensitivity.md).
//! Otherwise ([`Interval::Blocks`]; Owen-scrambled points, R not a power of two, states
//! saved before) the standard error is the jackknife over the blocks (leave one block
//! out; each block is itself a randomised rule, and as they are dependent the jackknife
//! measures the spread of rules of N/R points, wider than the error of the rule of N when
//! that errs less than R independent rules of N/R would), with the Student t quantile on
//! R − 1 degrees of freedom, as `stillpoint::cubature`'s interval. Either is raised to the
//! index's change since half the points when that is larger (quad's round guard: it
//! costs no evaluation, and catches replicates that agree by chance).
//! Each index has its own interval at `level`; `simultaneous` widens every one
//! (Bonferroni over the 2·d·k indices) so that all hold together at `level`.

use serde::{Deserialize, Serialize};

use crate::{student_t_quantile, Rule, StopReason, BATCH_COORDINATES, DEFAULT_START_N};
use crate::{Error, PointSet};
use stillpoint_sequences::{ExtensibleLattice, EXTENSIBLE_MAX_D, EXTENSIBLE_MAX_POINTS};

/// Replicates (blocks of the one sequence) by default: 8, not quad's 4. The estimate
/// is the rule of all N points whatever R is, so more blocks cost no accuracy, and the
/// interval on 7 degrees of freedom rather than 3 reached a half-width of 0.02 in at
/// most the evaluations of SALib's bootstrap on all seven models of the benchmark (the
/// G function with six a = 0 in a quarter of 4 blocks' evaluations, the product in half;
/// results/sensitivity/design.md).
pub const REPLICATES: usize = 8;

/// The rule by default: the tent lattice, whose error at equal evaluations was lower
/// than Owen-scrambled Sobol' points' on five of seven models and which reaches a
/// tolerance in up to 8× fewer evaluations on a G function with six equal inputs
/// (results/sensitivity/design.md).
pub const DEFAULT_RULE: Rule = Rule::TentLattice;

/// The most values of f a state keeps for the posterior interval (2^24, 128 MiB): at the
/// default budget of 2^22 evaluations every run of up to 4 outputs; a run past it goes on
/// with the blocks' interval ([`Interval::Blocks`]).
pub const MOST_VALUES: usize = 1 << 24;

/// Keeps the replicates' scrambles apart from other users of the same seed.
const SOBOL_KEY: u64 = 0x7365_6e73_536f_626f;

/// Points of the face test: each is evaluated with every input in turn at both ends
/// of its range (see [`Sensitivity::periodic`]), 2·d evaluations per point.
pub const FACE_POINTS: usize = 4;

/// How far inside its range the face test puts an input (a share of its width): one step
/// of the lattice's finest grid, so that a model defined on the open box is never
/// evaluated on its boundary.
const FACE_INSET: f64 = 1.0 / EXTENSIBLE_MAX_POINTS as f64;

/// An input is taken as periodic when every jump of f between the two ends of its range
/// is within this share of f's spread over the face test's values: far below any
/// tolerance on the indices, and far above the change a smooth periodic model shows over
/// its inset (2^-20 of the range).
pub const PERIODIC_JUMP: f64 = 1e-3;

/// The face test's points are the first of the lattice's replicate with this number
/// (no run's replicates reach it).
const FACE_REPLICATE: u64 = u64::MAX;

/// The evaluations of the face test on d inputs (made when the rule is the lattice,
/// before the first batch, and counted in `n`).
pub fn face_evaluations(d: usize) -> u64 {
    (2 * FACE_POINTS * d) as u64
}

/// The most inputs: the sequence's coordinates hold the two halves A and B.
pub const MAX_INPUTS: usize = EXTENSIBLE_MAX_D / 2;

/// The most evaluations of f by default (2^22).
pub const DEFAULT_MAX_N: u64 = 1 << 22;

/// The absolute tolerance on every index's half-width by default.
pub const DEFAULT_ABS_TOL: f64 = 0.01;

/// The estimator of first-order indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum FirstOrder {
    /// Saltelli et al. (2010): (1/n) Σ y_B (y_ABi − y_A) / V.
    #[default]
    Saltelli,
    /// Janon, Klein, Lagnoux, Nodet and Prieur (2014): the pooled correlation of y_B and
    /// y_ABi.
    Janon,
}

impl FirstOrder {
    /// The estimator as front ends name it: `saltelli` or `janon`.
    pub fn as_str(self) -> &'static str {
        match self {
            FirstOrder::Saltelli => "saltelli",
            FirstOrder::Janon => "janon",
        }
    }

    /// The estimator named `text` (`saltelli`, `janon`), refused naming `name`.
    pub fn parse(name: &str, text: &str) -> Result<FirstOrder, Error> {
        match text {
            "saltelli" => Ok(FirstOrder::Saltelli),
            "janon" => Ok(FirstOrder::Janon),
            _ => Err(Error::invalid(name, text, "saltelli or janon")),
        }
    }
}

/// The estimator of total indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum TotalOrder {
    /// Janon et al. (2014): 1 − the pooled correlation of y_A and y_ABi, Jansen's
    /// numerator over the variance of the A and AB_i values together.
    #[default]
    Janon,
    /// Jansen (1999): (1/2n) Σ (y_A − y_ABi)² / V (states saved before the choice).
    Jansen,
}

impl TotalOrder {
    /// The estimator of states saved before it was kept: Jansen's.
    fn saved() -> TotalOrder {
        TotalOrder::Jansen
    }
}

/// How each index's interval is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Interval {
    /// The posterior of a Bayesian cubature of the index's linearisation over all N
    /// points of the lattice ([`Sensitivity::posterior_sd`]); the blocks' jackknife where
    /// it cannot be formed (Owen-scrambled points, R not a power of two) or past
    /// [`MOST_VALUES`] values kept.
    #[default]
    Posterior,
    /// The jackknife over the R blocks with Student's quantile (states saved before the
    /// posterior).
    Blocks,
}

impl Interval {
    fn saved() -> Interval {
        Interval::Blocks
    }

    /// The name the front ends take.
    pub fn as_str(self) -> &'static str {
        match self {
            Interval::Posterior => "posterior",
            Interval::Blocks => "blocks",
        }
    }

    /// Parses `posterior` or `blocks`; any other text is refused naming `name`.
    pub fn parse(name: &str, text: &str) -> Result<Interval, Error> {
        match text {
            "posterior" => Ok(Interval::Posterior),
            "blocks" => Ok(Interval::Blocks),
            _ => Err(Error::invalid(name, text, "'posterior' or 'blocks'")),
        }
    }
}

/// Settings of a sensitivity analysis; [`Default`] gives the documented defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensitivityOptions {
    /// Lower corner of the inputs' box (0 when `None`).
    pub a: Option<Vec<f64>>,
    /// Upper corner of the inputs' box (1 when `None`).
    pub b: Option<Vec<f64>>,
    /// The inputs' names (`x1` … `xd` when `None`).
    pub names: Option<Vec<String>>,
    /// Absolute tolerance on every index's half-width.
    pub abs_tol: f64,
    /// Confidence level of the intervals, in (0, 1).
    pub level: f64,
    /// Whether the intervals hold all together at `level` (Bonferroni) rather than each
    /// on its own.
    pub simultaneous: bool,
    /// The first-order estimator.
    pub first_order: FirstOrder,
    /// The total estimator (states saved before it existed: Jansen's).
    #[serde(default = "TotalOrder::saved")]
    pub total_order: TotalOrder,
    /// Replicates R, at least 2: aligned blocks of the one randomised sequence (in states
    /// saved before blocks, independent randomisations).
    pub replicates: usize,
    /// The most evaluations of f, all replicates together.
    pub max_n: u64,
    /// Points per replicate in the first batch (a power of two).
    pub start_n: u64,
    /// Seed of the shifts.
    pub seed: u64,
    /// The randomised rule the pick-freeze points come from (states saved before it
    /// existed: the tent lattice).
    #[serde(default)]
    pub rule: Rule,
    /// Whether the second-order indices of every pair of inputs are estimated too (d
    /// more evaluations per point: f at each BA_i; states saved before: no).
    #[serde(default)]
    pub second_order: bool,
    /// How each index's interval is computed (states saved before the posterior: the
    /// blocks').
    #[serde(default = "Interval::saved")]
    pub interval: Interval,
}

impl Default for SensitivityOptions {
    fn default() -> Self {
        SensitivityOptions {
            a: None,
            b: None,
            names: None,
            abs_tol: DEFAULT_ABS_TOL,
            level: 0.95,
            simultaneous: false,
            first_order: FirstOrder::default(),
            total_order: TotalOrder::default(),
            replicates: REPLICATES,
            max_n: DEFAULT_MAX_N,
            start_n: DEFAULT_START_N,
            seed: 0,
            rule: DEFAULT_RULE,
            second_order: false,
            interval: Interval::default(),
        }
    }
}

/// Sums kept per replicate and output: Σ y_A, Σ y_B, Σ y_A², Σ y_B².
const HEAD: usize = 4;
/// Sums kept per replicate, output and input: Σ y_B(y_ABi − y_A), Σ (y_A − y_ABi)²,
/// Σ y_B·y_ABi, Σ y_ABi, Σ y_ABi².
const PER_INPUT: usize = 5;

/// With second-order indices, the sums after the inputs': Σ y_A·y_B, then per pair
/// i < j (row after row) Σ (y_BAi·y_ABj + y_BAj·y_ABi).
const PAIR_HEAD: usize = 1;

/// The pairs i < j of d inputs.
fn pairs(d: usize) -> usize {
    d * d.saturating_sub(1) / 2
}

/// The pairs (i, j), i < j, of d inputs in row order (the order of the pairs' sums).
fn row_order(d: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..d).flat_map(move |i| (i + 1..d).map(move |j| (i, j)))
}

/// The inputs (i, j) of pair p in row order (i < j).
fn pair_of(mut p: usize, d: usize) -> (usize, usize) {
    for i in 0..d {
        let row = d - 1 - i;
        if p < row {
            return (i, i + 1 + p);
        }
        p -= row;
    }
    unreachable!("pair index within d(d − 1)/2")
}

/// The means an output's indices are formed from ([`Sensitivity::moments`]).
struct Moments {
    /// The mean of the A and B values together, and their variance V.
    mean: f64,
    v: f64,
    /// Per input.
    inputs: Vec<InputMoments>,
    /// Per pair i < j (row after row), the closed index's numerator V^c_ij.
    closed: Vec<f64>,
}

/// An input's means: those of Janon's total (the mean of the A and AB_i values together,
/// and the total's denominator, V itself for Jansen's) and of Janon's first order (the
/// mean of the B and AB_i values together, and their variance).
struct InputMoments {
    total_mean: f64,
    over: f64,
    first_mean: f64,
    den: f64,
}

/// The state of a sensitivity analysis (see the module documentation): ask for the next
/// batch of points, feed back f's values, read the indices. Serializable, so a front end
/// can save it and continue with a tighter tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sensitivity {
    d: usize,
    options: SensitivityOptions,
    names: Vec<String>,
    lower: Vec<f64>,
    width: Vec<f64>,
    /// Outputs of f (0 until the first values are fed).
    k: usize,
    /// Points evaluated per replicate (each d + 2 evaluations).
    per_replicate: u64,
    /// Points per replicate in the batch handed out and not yet fed (0: none).
    pending: u64,
    /// Per output, the centre subtracted and the power of two divided by before summing
    /// (fixed by the first batch; no index depends on the power, and Saltelli's
    /// first-order estimate moves with the centre only by its shift times the mean of
    /// y_ABi − y_A, an error of the rule).
    centre: Vec<f64>,
    scale: Vec<i32>,
    /// The sums, replicate-major, then output, then [`HEAD`] + d·[`PER_INPUT`].
    sums: Vec<f64>,
    /// The sums before the last batch (half the points), for the round guard (empty
    /// after one batch, and in states saved before it existed).
    #[serde(default)]
    half_sums: Vec<f64>,
    /// Which coordinates of the 2d-dimensional points are A's and which B's.
    #[serde(default)]
    layout: Layout,
    /// How the R replicates are drawn (states saved before blocks were kept:
    /// independent randomisations).
    #[serde(default)]
    replicas: Replicas,
    /// The face test (see [`Sensitivity::periodic`]): whether it is made (the lattice's
    /// runs; states saved before it existed: no), whether its batch is handed out, its
    /// evaluations once fed (0 before), and per input whether the lattice takes it
    /// without the tent (empty before the test: the tent for every input).
    #[serde(default)]
    face_test: bool,
    #[serde(default)]
    face_pending: bool,
    #[serde(default)]
    face_evaluations: u64,
    #[serde(default)]
    periodic: Vec<bool>,
    /// Points of the pending doubling already fed, all replicates together (its batches
    /// come replicate after replicate, [`BATCH_COORDINATES`] at most each), and the
    /// doubling's sums so far: the new blocks' alone when they merge with earlier ones
    /// (blocks after the first doubling), else the earlier sums with the batches added.
    #[serde(default)]
    fed: u64,
    #[serde(default)]
    round_sums: Vec<f64>,
    /// Per output during the first doubling: its first value, and whether a later one
    /// differed (an output that never varies is refused when the doubling is complete).
    #[serde(default)]
    first_value: Vec<f64>,
    #[serde(default)]
    varies: Vec<bool>,
    /// With the posterior interval, every point's values in the sequence's order (rows ×
    /// k per point, as fed), and after each doubling every index's posterior standard
    /// deviation (index-major, `[i·k + j]`; empty when none was fitted).
    #[serde(default)]
    values: Vec<f64>,
    #[serde(default)]
    posterior_sd: Vec<f64>,
    /// The most coordinates of one batch: [`BATCH_COORDINATES`] (less in tests, to cut
    /// small doublings).
    #[serde(skip, default = "batch_coordinates")]
    most_coordinates: usize,
    /// The most values kept for the posterior: [`MOST_VALUES`] (less in tests).
    #[serde(skip, default = "most_values")]
    most_values: usize,
}

fn most_values() -> usize {
    MOST_VALUES
}

fn batch_coordinates() -> usize {
    BATCH_COORDINATES
}

/// How the R replicates the interval is computed from are drawn. As blocks, the points
/// are the first N of one randomised sequence and replicate r is its r-th aligned block
/// of N/R (for the lattice a randomly shifted copy of the N/R-point lattice, for
/// Owen-scrambled Sobol' a scrambled net): each block is an unbiased rule, and the
/// estimate pools them into the one rule of N points, whose error on smooth models is
/// far below that of R independent rules of N/R points pooled (at N = 1 024 base points:
/// 17× lower on the linear model, 2× on the product, 1.3–1.6× on three G functions;
/// results/sensitivity/design.md). The blocks are dependent, so the jackknife over them
/// measures the spread of rules of N/R points rather than the pooled rule's error: the
/// interval is wider than the error it bounds whenever the rule of N points errs less
/// than R independent rules of N/R would (the expected squared spread exceeds the
/// pooled error's variance when the variance falls at least as fast as 1/N).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
enum Replicas {
    /// R independent randomisations of N/R points each (states saved before blocks).
    #[default]
    Independent,
    /// R aligned blocks of one randomised sequence of N points.
    Blocks,
}

/// Where A and B sit among the sequence's 2d coordinates. Interleaved, each input's A
/// and B coordinates are neighbours among the lattice's leading coordinates, whose
/// projections are its best: against the split layout, the RMSE of the indices at 2^13
/// base points fell 3.4× on Ishigami and 1.4× and 2× on two G functions, and held on
/// the others (results/sensitivity/design.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
enum Layout {
    /// A in coordinates 1..d, B in d+1..2d (states saved before the layout was kept).
    #[default]
    Split,
    /// A in the odd coordinates 1, 3, …, B in the even ones.
    Interleaved,
}

impl Layout {
    /// The input whose A or B column coordinate c (from 0) of the 2d is.
    fn input_of(self, c: usize, d: usize) -> usize {
        match self {
            Layout::Split => c % d,
            Layout::Interleaved => c / 2,
        }
    }

    /// A point of 2d coordinates as its A and B halves.
    fn split(self, point: &[f64], a: &mut [f64], b: &mut [f64]) {
        match self {
            Layout::Split => {
                let (x, y) = point.split_at(a.len());
                a.copy_from_slice(x);
                b.copy_from_slice(y);
            }
            Layout::Interleaved => {
                for ((pair, x), y) in point.chunks_exact(2).zip(a.iter_mut()).zip(b.iter_mut()) {
                    (*x, *y) = (pair[0], pair[1]);
                }
            }
        }
    }
}

impl Sensitivity {
    /// A new analysis of a function of d inputs. Refuses d = 0 or beyond [`MAX_INPUTS`]
    /// (naming `d`), corners of the wrong length or an empty box (`a`, `b`, `a, b`),
    /// names of the wrong length (`names`), a tolerance that is negative or not finite
    /// (`abs_tol`), a level outside (0, 1) (`level`), fewer than 2 replicates
    /// (`replicates`), a `start_n` that is not a power of two, a `max_n` below one
    /// first batch and a rule the indices do not take (`rule`: the tent lattice or
    /// scrambled Sobol'; `quad`'s probes, tests and Bayesian rules are its own).
    pub fn new(d: usize, options: SensitivityOptions) -> Result<Sensitivity, Error> {
        if !matches!(options.rule, Rule::TentLattice | Rule::Sobol) {
            return Err(Error::invalid(
                crate::names::RULE,
                format!("{:?}", options.rule.as_str()),
                "lattice or sobol (the rules of the Sobol' indices)",
            ));
        }
        if d == 0 || d > MAX_INPUTS {
            return Err(Error::invalid(
                "d",
                d,
                format!(
                    "1 to {MAX_INPUTS} inputs (the sequence's {EXTENSIBLE_MAX_D} coordinates \
                     hold two points per input)"
                ),
            ));
        }
        // The box, tolerance, level, replicates, start and budget are checked as quad
        // checks them (one rule), on the 2d-dimensional cube the design lives in.
        let o = &options;
        let lower = o.a.clone().unwrap_or_else(|| vec![0.0; d]);
        let upper = o.b.clone().unwrap_or_else(|| vec![1.0; d]);
        for (name, v) in [("a", &o.a), ("b", &o.b)] {
            if let Some(v) = v {
                if v.len() != d {
                    return Err(Error::invalid(
                        name,
                        format!("{v:?}"),
                        format!("{d} finite values (one per input)"),
                    ));
                }
            }
        }
        crate::Cubature::new(d, quad_options(o))?;
        if let Some(names) = &o.names {
            if names.len() != d {
                return Err(Error::invalid(
                    "names",
                    format!("{names:?}"),
                    format!("{d} names (one per input)"),
                ));
            }
        }
        check_budget(o, d)?;
        let names = o
            .names
            .clone()
            .unwrap_or_else(|| (1..=d).map(|i| format!("x{i}")).collect());
        let width = lower.iter().zip(&upper).map(|(a, b)| b - a).collect();
        // The face test decides the lattice's tent per input; Owen-scrambled points (the
        // rule under unbounded laws, whose ends are infinite) have no tent to decide.
        let face_test = options.rule != Rule::Sobol;
        Ok(Sensitivity {
            d,
            options,
            names,
            lower,
            width,
            k: 0,
            per_replicate: 0,
            pending: 0,
            centre: Vec::new(),
            scale: Vec::new(),
            sums: Vec::new(),
            half_sums: Vec::new(),
            layout: Layout::Interleaved,
            replicas: Replicas::Blocks,
            face_test,
            face_pending: false,
            face_evaluations: 0,
            periodic: Vec::new(),
            fed: 0,
            round_sums: Vec::new(),
            first_value: Vec::new(),
            varies: Vec::new(),
            values: Vec::new(),
            posterior_sd: Vec::new(),
            most_coordinates: BATCH_COORDINATES,
            most_values: MOST_VALUES,
        })
    }

    /// The number of inputs d.
    pub fn d(&self) -> usize {
        self.d
    }

    /// The inputs' names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The settings (with the current tolerance, level and budget).
    pub fn options(&self) -> &SensitivityOptions {
        &self.options
    }

    /// Outputs of f (0 before the first values are fed).
    pub fn outputs(&self) -> usize {
        self.k
    }

    /// Evaluations of f so far: [`Sensitivity::rows`] per point, all replicates together,
    /// and the face test's.
    pub fn n(&self) -> u64 {
        self.per_replicate * self.options.replicates as u64 * self.rows() as u64
            + self.face_evaluations
    }

    /// Per input, whether the lattice takes its coordinates without the tent transform
    /// (empty before the face test, and when none was made: the tent for every input).
    ///
    /// The tent makes the lattice's rule of order n⁻² for any smooth model, but it folds
    /// each coordinate, doubling the frequencies a model periodic in that input has, and
    /// the pick-freeze sums double them again: on Ishigami (periodic in every input over
    /// [−π, π]) and the G functions the lattice without the tent erred 2.5–19× less at
    /// equal evaluations, on the linear and product models (whose values at the two ends
    /// of a range differ) 2.4–125× more (results/sensitivity/design.md, "The tent by
    /// input"). So before the first batch the face test evaluates f at [`FACE_POINTS`]
    /// points with each input in turn just inside either end of its range (2·d per point,
    /// counted in `n`), and an input is periodic when every jump between the two ends is
    /// within [`PERIODIC_JUMP`] of the spread of those values, on every output.
    pub fn periodic(&self) -> &[bool] {
        &self.periodic
    }

    /// Whether the face test is still to be handed out.
    fn face_due(&self) -> bool {
        self.face_test && self.face_evaluations == 0 && self.per_replicate == 0
    }

    /// The evaluations of the face test, made or still to make.
    fn face_cost(&self) -> u64 {
        if self.face_due() {
            face_evaluations(self.d)
        } else {
            self.face_evaluations
        }
    }

    /// Points per replicate so far (each d + 2 evaluations).
    pub fn per_replicate(&self) -> u64 {
        self.per_replicate
    }

    /// Points per replicate of the batch handed out and not yet fed (0: none; the face
    /// test's [`FACE_POINTS`] while that is handed out).
    pub fn pending(&self) -> u64 {
        if self.face_pending {
            FACE_POINTS as u64
        } else {
            self.pending
        }
    }

    /// Sets a new tolerance (the evaluations made are kept). Refuses a negative or
    /// non-finite one, naming `abs_tol`.
    pub fn set_tolerance(&mut self, abs_tol: f64) -> Result<(), Error> {
        let mut o = self.options.clone();
        o.abs_tol = abs_tol;
        crate::Cubature::new(self.d, quad_options(&o))?;
        self.options.abs_tol = abs_tol;
        Ok(())
    }

    /// Sets a new budget (a larger one continues a run stopped by `max_n`). Refuses less
    /// than one first batch, or than the evaluations already made, naming `max_n`.
    pub fn set_max_n(&mut self, max_n: u64) -> Result<(), Error> {
        let o = SensitivityOptions {
            max_n,
            ..self.options.clone()
        };
        check_budget(&o, self.d)?;
        crate::check_not_spent(max_n, self.n())?;
        self.options.max_n = max_n;
        Ok(())
    }

    /// Sets a new confidence level (the half-widths are recomputed from the same sums).
    /// Refuses a level outside (0, 1), naming `level`.
    pub fn set_level(&mut self, level: f64) -> Result<(), Error> {
        let o = SensitivityOptions {
            level,
            ..self.options.clone()
        };
        crate::Cubature::new(self.d, quad_options(&o))?;
        self.options.level = level;
        Ok(())
    }

    /// The interval the half-widths come from: the one asked for, or the blocks' where the
    /// posterior cannot be formed (Owen-scrambled points, R not a power of two, past
    /// [`MOST_VALUES`] values).
    pub fn interval_used(&self) -> Interval {
        if self.keeps_values() {
            Interval::Posterior
        } else {
            Interval::Blocks
        }
    }

    /// Sets how the intervals are computed: the blocks' at any time (the values kept for
    /// the posterior are let go), the posterior only where it is already computed or
    /// nothing is fed yet; refuses the posterior after a run that kept no values (the
    /// blocks' interval, Owen-scrambled points, R not a power of two), naming `interval`.
    pub fn set_interval(&mut self, interval: Interval) -> Result<(), Error> {
        if interval == self.options.interval {
            return Ok(());
        }
        if interval == Interval::Blocks {
            self.options.interval = interval;
            self.values = Vec::new();
            self.posterior_sd = Vec::new();
            return Ok(());
        }
        let before = self.options.interval;
        self.options.interval = interval;
        if self.k > 0 || !self.keeps_values() {
            self.options.interval = before;
            return Err(Error::invalid(
                crate::names::INTERVAL,
                interval.as_str(),
                "blocks: the posterior needs every value from the first point, which this \
                 run did not keep (it used the blocks' interval, Owen-scrambled points or a \
                 count of replicates that is not a power of two)",
            ));
        }
        Ok(())
    }

    /// Whether the intervals hold all together (Bonferroni) or each on its own.
    pub fn set_simultaneous(&mut self, simultaneous: bool) {
        self.options.simultaneous = simultaneous;
    }

    fn next_size(&self) -> u64 {
        if self.per_replicate == 0 {
            self.options.start_n
        } else {
            self.per_replicate
        }
    }

    /// Evaluations per point: A, B and each AB_i, and each BA_i with second-order
    /// indices.
    pub fn rows(&self) -> usize {
        rows_per_point(self.d, self.options.second_order)
    }

    /// Sums per replicate and output.
    fn width(&self) -> usize {
        HEAD + self.d * PER_INPUT
            + if self.options.second_order {
                PAIR_HEAD + pairs(self.d)
            } else {
                0
            }
    }

    /// Evaluations of a batch of `m` points per replicate.
    fn cost(&self, m: u64) -> u64 {
        m.saturating_mul(self.options.replicates as u64)
            .saturating_mul(self.rows() as u64)
    }

    /// Whether the next doubling would pass the sequence's 2^20 points (per replicate
    /// for independent ones, all blocks together for blocks of one sequence).
    fn beyond_sequence(&self) -> bool {
        let next = self.per_replicate + self.next_size();
        let points = match self.replicas {
            Replicas::Independent => next,
            Replicas::Blocks => next.saturating_mul(self.options.replicates as u64),
        };
        points > EXTENSIBLE_MAX_POINTS
    }

    /// Whether the next doubling would pass `max_n` evaluations or the sequence's 2^20
    /// points.
    pub fn exhausted(&self) -> bool {
        let next = self.per_replicate + self.next_size();
        self.beyond_sequence()
            || self.cost(next).saturating_add(self.face_cost()) > self.options.max_n
    }

    /// Why the run stops here: `None` while another doubling may be made and the
    /// tolerance is not met.
    pub fn reason(&self) -> Option<StopReason> {
        if self.met() {
            Some(StopReason::Met)
        } else if self.beyond_sequence() {
            Some(StopReason::Sequence)
        } else if self.exhausted() {
            Some(StopReason::MaxN)
        } else {
            None
        }
    }

    /// The next batch, scaled to the box, as rows of d values: for each of its points,
    /// the point's A, B, AB_1, …, AB_d in turn. A doubling is m new points for each of
    /// the R replicates, replicate 0's first: it comes as one batch of R·m·(d + 2) rows
    /// when that holds at most [`BATCH_COORDINATES`] coordinates, else as consecutive
    /// stretches of its points that do. Asking again before
    /// [`Sensitivity::feed`] gives the same batch. `None` when the budget is spent
    /// ([`Sensitivity::exhausted`]).
    pub fn next_points(&mut self) -> Option<PointSet> {
        if self.face_pending || (self.face_due() && !self.exhausted()) {
            self.face_pending = true;
            return Some(self.face_points());
        }
        if self.pending == 0 {
            if self.exhausted() {
                return None;
            }
            self.pending = self.next_size();
            self.fed = 0;
        }
        let (start, len) = self.batch();
        let (d, m, r) = (self.d, self.pending, self.options.replicates as u64);
        let rows = self.rows();
        let mut raw = vec![0.0; len * 2 * d];
        match self.replicas {
            // Each replicate's new points m at a time, in the batch's stretch of them.
            Replicas::Independent => {
                let mut at = 0;
                for rep in start / m..(start + len as u64).div_ceil(m) {
                    let from = start.max(rep * m);
                    let to = (start + len as u64).min((rep + 1) * m);
                    let out = &mut raw[at..at + (to - from) as usize * 2 * d];
                    let rep = rep as usize;
                    self.fill_replicates(
                        rep..rep + 1,
                        self.per_replicate + from - rep as u64 * m,
                        out,
                    );
                    at += out.len();
                }
            }
            // The doubling is the next R·m points of the one sequence: R new blocks of
            // m, which merge with the earlier R in pairs (see `merged`).
            Replicas::Blocks => self.fill(0, r * self.per_replicate + start, len, &mut raw),
        }
        let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
        let mut data = vec![0.0; len * rows * d];
        for (point, block) in raw.chunks_exact(2 * d).zip(data.chunks_exact_mut(rows * d)) {
            self.layout.split(point, &mut a, &mut b);
            let (a, b) = (&a[..], &b[..]);
            let mut rows_of = block.chunks_exact_mut(d);
            rows_of.next().expect("A").copy_from_slice(a);
            rows_of.next().expect("B").copy_from_slice(b);
            for (i, row) in rows_of.by_ref().take(d).enumerate() {
                row.copy_from_slice(a);
                row[i] = b[i];
            }
            // BA_i (B with input i taken from A), with second-order indices.
            for (i, row) in rows_of.enumerate() {
                row.copy_from_slice(b);
                row[i] = a[i];
            }
        }
        for row in data.chunks_exact_mut(d) {
            for ((x, lo), w) in row.iter_mut().zip(&self.lower).zip(&self.width) {
                *x = lo + w * *x;
            }
        }
        Some(PointSet::new(len * rows, d, data).expect("non-empty batch"))
    }

    /// The batch due in the pending doubling: its first point among the doubling's R·m
    /// (replicate after replicate) and its points.
    fn batch(&self) -> (u64, usize) {
        let left = self.options.replicates as u64 * self.pending - self.fed;
        let most = (self.most_coordinates / (self.rows() * self.d)).max(1) as u64;
        (self.fed, most.min(left) as usize)
    }

    /// Whether a doubling is part fed: some of its batches are in, others still due.
    pub fn in_round(&self) -> bool {
        self.fed > 0
    }

    /// Points `start`.. of randomisation `rep` in 2d dimensions, before the box's
    /// scaling (as many as `out` holds); the lattice's coordinates of a periodic input
    /// without the tent.
    fn fill(&self, rep: u64, start: u64, m: usize, out: &mut [f64]) {
        debug_assert_eq!(out.len(), m * 2 * self.d);
        let rep = rep as usize;
        self.fill_replicates(rep..rep + 1, start, out);
    }

    /// [`Sensitivity::fill`] for each randomisation of `reps`, one after another in
    /// `out`: the rule's own replicates ([`Rule::fill_replicates`]: Sobol's scrambles
    /// made together) unless a periodic input keeps the lattice without its tent, then
    /// each randomisation by itself ([`crate::fill_chunks`]).
    fn fill_replicates(&self, reps: std::ops::Range<usize>, start: u64, out: &mut [f64]) {
        let s = 2 * self.d;
        let m = out.len() / (s * reps.len());
        let (seed, rule) = (self.options.seed, self.options.rule);
        if rule == Rule::Sobol || !self.periodic.contains(&true) {
            rule.fill_replicates(s, seed, SOBOL_KEY, reps, start, out);
            return;
        }
        let fold: Vec<bool> = (0..s)
            .map(|c| !self.periodic[self.layout.input_of(c, self.d)])
            .collect();
        crate::fill_chunks(reps, out, m * s, |rep, chunk| {
            ExtensibleLattice::with_table(rule.table(), s, seed, rep as u64)
                .and_then(|seq| seq.fill_folding(start, m, &fold, chunk))
                .expect("d and the range checked by new");
        });
    }

    /// The face test's batch, scaled to the box: for each of [`FACE_POINTS`] points of
    /// the lattice in d dimensions and each input i in turn, the point with input i just
    /// inside the lower end of its range, then just inside the upper end (2·d rows per
    /// point).
    fn face_points(&self) -> PointSet {
        let d = self.d;
        let mut base = vec![0.0; FACE_POINTS * d];
        ExtensibleLattice::new(d, self.options.seed, FACE_REPLICATE)
            .and_then(|seq| seq.fill(0, FACE_POINTS, &mut base))
            .expect("d and the range checked by new");
        let mut data = Vec::with_capacity(2 * FACE_POINTS * d * d);
        for point in base.chunks_exact(d) {
            for i in 0..d {
                for end in [FACE_INSET, 1.0 - FACE_INSET] {
                    let at = data.len();
                    data.extend_from_slice(point);
                    data[at + i] = end;
                }
            }
        }
        for row in data.chunks_exact_mut(d) {
            for ((x, lo), w) in row.iter_mut().zip(&self.lower).zip(&self.width) {
                *x = lo + w * *x;
            }
        }
        PointSet::new(2 * FACE_POINTS * d, d, data).expect("non-empty batch")
    }

    /// Takes f's values at the face test's batch and decides [`Sensitivity::periodic`];
    /// refuses what [`Sensitivity::feed`] refuses (a wrong length, NaN or ±∞ naming the
    /// point and the output).
    fn feed_faces(&mut self, points: &PointSet, values: &[f64]) -> Result<(), Error> {
        let d = self.d;
        let rows = 2 * FACE_POINTS * d;
        if points.n() != rows || values.is_empty() || !values.len().is_multiple_of(rows) {
            return Err(Error::invalid(
                "values",
                format!("{} values for {rows} points", values.len()),
                format!("{rows}·k values (k ≥ 1 outputs per point)"),
            ));
        }
        let k = values.len() / rows;
        refuse_non_finite(points, values, k)?;
        let mut periodic = vec![true; d];
        for j in 0..k {
            let column: Vec<f64> = values.iter().skip(j).step_by(k).copied().collect();
            let (lo, hi) = column
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            // Halves, so that outputs near ±f64::MAX do not overflow the differences.
            let spread = hi / 2.0 - lo / 2.0;
            // Rows come as (lower end, upper end) pairs, input after input per point.
            for (pair, ends) in column.chunks_exact(2).enumerate() {
                let jump = (ends[1] / 2.0 - ends[0] / 2.0).abs();
                if !(spread > 0.0 && jump <= PERIODIC_JUMP * spread) {
                    periodic[pair % d] = false;
                }
            }
        }
        self.periodic = periodic;
        self.face_evaluations = rows as u64;
        self.face_pending = false;
        Ok(())
    }

    /// Takes f's values at the batch of [`Sensitivity::next_points`]: rows × k values,
    /// row-major. Refuses values without a batch handed out, a length that is not a
    /// multiple of the rows (or another k than before), NaN or ±∞ (naming the point and
    /// the output) and values whose squares the sums cannot hold: the state is unchanged
    /// then. When the first doubling is complete, refuses an output that took one value
    /// at every one of its points (its variance, which every index divides by, is 0);
    /// the first doubling is then to be made again.
    pub fn feed(&mut self, points: &PointSet, values: &[f64]) -> Result<(), Error> {
        if self.face_pending {
            return self.feed_faces(points, values);
        }
        let r = self.options.replicates;
        let (start, len) = if self.pending == 0 {
            (0, 0)
        } else {
            self.batch()
        };
        let rows = len * self.rows();
        if len == 0 || points.n() != rows {
            return Err(Error::invalid(
                "values",
                format!("{} values", values.len()),
                "f's values at the points of next_points() (none are pending)",
            ));
        }
        let k = if self.k == 0 {
            values.len() / rows
        } else {
            self.k
        };
        if k == 0 || values.len() != rows * k {
            return Err(Error::invalid(
                "values",
                format!("{} values for {rows} points", values.len()),
                format!("{rows}·k values (k ≥ 1 outputs per point, as at the first points)"),
            ));
        }
        refuse_non_finite(points, values, k)?;
        let fresh = self.k == 0;
        if fresh {
            // From the A, B and AB_i rows alone, so that the first-order and total
            // indices are the same whether the BA_i rows are evaluated or not.
            let rows = self.rows();
            let kept: Vec<f64> = values
                .chunks_exact(rows * k)
                .flat_map(|point| &point[..(self.d + 2) * k])
                .copied()
                .collect();
            let (centre, scale) = first_scaling(&kept, k);
            self.k = k;
            self.centre = centre;
            self.scale = scale;
            self.sums = vec![0.0; r * k * self.width()];
            self.first_value = values[..k].to_vec();
            self.varies = vec![false; k];
        }
        if self.fed == 0 {
            self.round_sums = if self.merges() {
                vec![0.0; self.sums.len()]
            } else {
                self.sums.clone()
            };
        }
        let before = if self.fed == 0 {
            Vec::new()
        } else {
            self.round_sums.clone()
        };
        self.accumulate(start, len, values);
        let complete = self.fed + len as u64 == r as u64 * self.pending;
        let merged = complete.then(|| self.merged());
        let checked = merged.as_ref().unwrap_or(&self.round_sums);
        if let Some(e) = self.refuse_overflow(checked, points, values) {
            self.round_sums = before;
            if fresh {
                self.forget_outputs();
            }
            return Err(e);
        }
        if self.per_replicate == 0 {
            for (j, row) in (0..k).cycle().zip(values) {
                self.varies[j] |= *row != self.first_value[j];
            }
        }
        if self.keeps_values() {
            if self.values.len() + values.len() > self.most_values {
                // Beyond the values a state holds, the blocks' interval from here on.
                self.options.interval = Interval::Blocks;
                self.values = Vec::new();
                self.posterior_sd = Vec::new();
            } else {
                self.values.extend_from_slice(values);
            }
        }
        self.fed += len as u64;
        match merged {
            Some(sums) => self.finish_round(sums),
            None => Ok(()),
        }
    }

    /// Back to before the first values: no outputs, no centre, scale or sums.
    fn forget_outputs(&mut self) {
        self.k = 0;
        for v in [&mut self.centre, &mut self.sums, &mut self.first_value] {
            *v = Vec::new();
        }
        self.scale = Vec::new();
        self.varies = Vec::new();
        self.values = Vec::new();
        self.posterior_sd = Vec::new();
    }

    /// Whether the doubling's blocks merge in pairs with the earlier ones (blocks of one
    /// sequence after its first doubling) rather than adding to their sums.
    fn merges(&self) -> bool {
        self.replicas == Replicas::Blocks && self.per_replicate > 0
    }

    /// The sums once the complete doubling is added. Blocks of one sequence: the
    /// doubling is R new blocks as long as the earlier ones, and block r after it is the
    /// union of blocks 2r and 2r + 1 of the 2R (earlier, then new) before it.
    fn merged(&self) -> Vec<f64> {
        if !self.merges() {
            return self.round_sums.clone();
        }
        let block = self.k * self.width();
        let all: Vec<&[f64]> = self
            .sums
            .chunks_exact(block)
            .chain(self.round_sums.chunks_exact(block))
            .collect();
        all.chunks_exact(2)
            .flat_map(|pair| pair[0].iter().zip(pair[1]).map(|(x, y)| x + y))
            .collect()
    }

    /// Ends a complete doubling with the sums after it; at the first, refuses an output
    /// that never varied (and starts that doubling again).
    fn finish_round(&mut self, sums: Vec<f64>) -> Result<(), Error> {
        let rows = self.cost(self.pending);
        self.fed = 0;
        self.round_sums = Vec::new();
        if let Some(j) = self.varies.iter().position(|v| !v) {
            let (first, k) = (self.first_value[j], self.k);
            self.forget_outputs();
            return Err(Error::invalid(
                "f",
                format!(
                    "{first} at every one of the first {rows} points{}",
                    if k > 1 {
                        format!(" (output {j})")
                    } else {
                        String::new()
                    }
                ),
                "an output that varies: Sobol' indices are shares of its variance",
            ));
        }
        self.varies = Vec::new();
        self.first_value = Vec::new();
        let earlier = std::mem::replace(&mut self.sums, sums);
        self.half_sums = if self.per_replicate == 0 {
            Vec::new()
        } else {
            earlier
        };
        self.per_replicate += self.pending;
        self.pending = 0;
        if self.keeps_values() {
            self.fit_posterior();
        }
        Ok(())
    }

    /// Where `sums` are no longer all finite (values far beyond the first batch's
    /// spread, whose squares overflow even scaled by its power of two), the error naming
    /// the output and the point of the batch's largest deviation.
    fn refuse_overflow(&self, sums: &[f64], points: &PointSet, values: &[f64]) -> Option<Error> {
        if sums.iter().all(|v| v.is_finite()) {
            return None;
        }
        let (k, d) = (self.k, points.s());
        let deviation =
            |at: usize| ((values[at] - self.centre[at % k]) * pow2(-self.scale[at % k])).abs();
        let at = (0..values.len()).max_by(|&a, &b| deviation(a).total_cmp(&deviation(b)))?;
        let i = at / k;
        Some(Error::invalid(
            "f",
            format!(
                "{:e} at x = {:?} (output {})",
                values[at],
                &points.as_slice()[i * d..(i + 1) * d],
                at % k
            ),
            format!(
                "values whose squares the sums hold: within about 2^500 of the first \
                 points' spread (about 2^{}), around their mean",
                self.scale[at % k]
            ),
        ))
    }

    /// Adds a batch of `len` points from point `start` of the doubling to its sums (in
    /// the order of the points, so that the sums do not depend on how it was cut).
    fn accumulate(&mut self, start: u64, len: usize, values: &[f64]) {
        let (d, k, m) = (self.d, self.k, self.pending);
        let (width, rows, second) = (self.width(), self.rows(), self.options.second_order);
        let scale: Vec<f64> = self.scale.iter().map(|&e| pow2(-e)).collect();
        let centre = &self.centre;
        let y = |row: usize, j: usize| (values[row * k + j] - centre[j]) * scale[j];
        // A point's AB_i and BA_i values, scaled once for the pairs' O(d²) sums.
        let (mut ab, mut ba) = (vec![0.0; d], vec![0.0; d]);
        for p in 0..len {
            let rep = ((start + p as u64) / m) as usize;
            let base = p * rows;
            for j in 0..k {
                let s = &mut self.round_sums[(rep * k + j) * width..(rep * k + j + 1) * width];
                let (ya, yb) = (y(base, j), y(base + 1, j));
                s[0] += ya;
                s[1] += yb;
                s[2] += ya * ya;
                s[3] += yb * yb;
                for i in 0..d {
                    let yi = y(base + 2 + i, j);
                    let t = &mut s[HEAD + i * PER_INPUT..HEAD + (i + 1) * PER_INPUT];
                    t[0] += yb * (yi - ya);
                    t[1] += (ya - yi) * (ya - yi);
                    t[2] += yb * yi;
                    t[3] += yi;
                    t[4] += yi * yi;
                }
                if second {
                    let t = &mut s[HEAD + d * PER_INPUT..];
                    t[0] += ya * yb;
                    for i in 0..d {
                        (ab[i], ba[i]) = (y(base + 2 + i, j), y(base + 2 + d + i, j));
                    }
                    let mut at = PAIR_HEAD;
                    for i in 0..d {
                        for jj in i + 1..d {
                            t[at] += ba[i] * ab[jj] + ba[jj] * ab[i];
                            at += 1;
                        }
                    }
                }
            }
        }
    }

    /// The sums of output j in `sums` over the replicates whose flag is set, and their
    /// points (`per` each).
    fn pooled(
        &self,
        sums: &[f64],
        per: u64,
        j: usize,
        keep: impl Fn(usize) -> bool,
    ) -> (Vec<f64>, f64) {
        let width = self.width();
        let mut out = vec![0.0; width];
        let mut count = 0.0;
        for rep in (0..self.options.replicates).filter(|&rep| keep(rep)) {
            let s = &sums[(rep * self.k + j) * width..(rep * self.k + j + 1) * width];
            for (o, v) in out.iter_mut().zip(s) {
                *o += v;
            }
            count += per as f64;
        }
        (out, count)
    }

    /// Every index from pooled sums over `n` points, flat: the d first-order, the d
    /// total, then with second order the pairs i < j (row after row).
    ///
    /// A pair's index is Saltelli (2002)'s, symmetrised: BA_i and AB_j share inputs i
    /// (from A) and j (from B) and nothing else, so E y_BAi·y_ABj − E y_A·y_B is the
    /// variance of E[f | x_i, x_j] (the closed index's), from which the two first-order
    /// parts are taken: S_ij = V^c_ij / V − S_i − S_j.
    fn indices(&self, s: &[f64], n: f64) -> Vec<f64> {
        let d = self.d;
        let mo = self.moments(s, n);
        let mut out = vec![0.0; 2 * d];
        for (i, (t, m)) in s[HEAD..HEAD + d * PER_INPUT]
            .chunks_exact(PER_INPUT)
            .zip(&mo.inputs)
            .enumerate()
        {
            out[d + i] = t[1] / (2.0 * n) / m.over;
            out[i] = match self.options.first_order {
                FirstOrder::Saltelli => t[0] / n / mo.v,
                FirstOrder::Janon => (t[2] / n - m.first_mean * m.first_mean) / m.den,
            };
        }
        for ((i, j), c) in row_order(d).zip(&mo.closed) {
            out.push(c / mo.v - out[i] - out[j]);
        }
        out
    }

    /// The means every index is formed from, out of pooled sums `s` over `n` points:
    /// computed once per output, whether for the indices or for their linearisation at
    /// each point ([`Sensitivity::influence`]).
    fn moments(&self, s: &[f64], n: f64) -> Moments {
        let d = self.d;
        let mean = (s[0] + s[1]) / (2.0 * n);
        let v = (s[2] + s[3]) / (2.0 * n) - mean * mean;
        let (ma, maa, mb, mbb) = (s[0] / n, s[2] / n, s[1] / n, s[3] / n);
        let inputs = s[HEAD..HEAD + d * PER_INPUT]
            .chunks_exact(PER_INPUT)
            .map(|t| {
                let total_mean = (ma + t[3] / n) / 2.0;
                let first_mean = (mb + t[3] / n) / 2.0;
                InputMoments {
                    total_mean,
                    over: match self.options.total_order {
                        TotalOrder::Jansen => v,
                        TotalOrder::Janon => (maa + t[4] / n) / 2.0 - total_mean * total_mean,
                    },
                    first_mean,
                    den: (mbb + t[4] / n) / 2.0 - first_mean * first_mean,
                }
            })
            .collect();
        let closed = if self.options.second_order {
            let t = &s[HEAD + d * PER_INPUT..];
            let ab = t[0] / n;
            t[PAIR_HEAD..PAIR_HEAD + pairs(d)]
                .iter()
                .map(|x| x / (2.0 * n) - ab)
                .collect()
        } else {
            Vec::new()
        };
        Moments {
            mean,
            v,
            inputs,
            closed,
        }
    }

    /// Per output, every index ([`Sensitivity::indices`]), its jackknife standard error
    /// and the indices from the sums before the last batch (`None` after one batch).
    #[allow(clippy::type_complexity)]
    fn estimates(&self) -> Vec<(Vec<f64>, Vec<f64>, Option<Vec<f64>>)> {
        let r = self.options.replicates;
        let per = self.per_replicate;
        (0..self.k)
            .map(|j| {
                let (s, n) = self.pooled(&self.sums, per, j, |_| true);
                let whole = self.indices(&s, n);
                let loo: Vec<_> = (0..r)
                    .map(|out| {
                        let (s, n) = self.pooled(&self.sums, per, j, |rep| rep != out);
                        self.indices(&s, n)
                    })
                    .collect();
                let errors = (0..whole.len())
                    .map(|i| {
                        let mean = loo.iter().map(|l| l[i]).sum::<f64>() / r as f64;
                        let ss: f64 = loo.iter().map(|l| (l[i] - mean).powi(2)).sum::<f64>();
                        ((r as f64 - 1.0) / r as f64 * ss).sqrt()
                    })
                    .collect();
                let half = (!self.half_sums.is_empty()).then(|| {
                    let (s, n) = self.pooled(&self.half_sums, per / 2, j, |_| true);
                    self.indices(&s, n)
                });
                (whole, errors, half)
            })
            .collect()
    }

    /// The t quantile the standard errors are multiplied by: each index's own at
    /// `level`, or, simultaneous, Bonferroni's over the 2·d·k indices (and the pairs'
    /// with second order).
    fn quantile(&self) -> f64 {
        let nu = (self.options.replicates - 1) as f64;
        student_t_quantile(1.0 - self.miss() / 2.0, nu)
    }

    /// The chance each interval may miss: 1 − level, divided (Bonferroni) over the
    /// indices when they are to hold together.
    fn miss(&self) -> f64 {
        let alpha = 1.0 - self.options.level;
        if self.options.simultaneous {
            alpha / (self.indices_per_output() * self.k.max(1)) as f64
        } else {
            alpha
        }
    }

    /// The normal quantile the posterior standard deviations are multiplied by: at
    /// 1 − [`Sensitivity::miss`]/[`crate::POSTERIOR_MISS`], two-sided (quad's rule for
    /// its Bayesian lattice).
    fn posterior_quantile(&self) -> f64 {
        let miss = self.miss() / crate::POSTERIOR_MISS;
        stillpoint_design::Marginal::normal_score(1.0 - miss / 2.0)
    }

    /// Whether the run keeps every value for the posterior interval: asked for, on the
    /// lattice, blocks of one sequence whose N = R·m points are a whole lattice (R a power
    /// of two).
    fn keeps_values(&self) -> bool {
        self.options.interval == Interval::Posterior
            && self.options.rule != Rule::Sobol
            && self.replicas == Replicas::Blocks
            && self.options.replicates.is_power_of_two()
    }

    /// Every index's posterior standard deviation after the last doubling, index-major as
    /// the half-widths (`[i·k + j]`, the indices in the order first, total, pairs); empty
    /// under the blocks' interval.
    ///
    /// An index is a smooth function g of means over the points (the sums of
    /// `Sensitivity::accumulate`), so its error is to first order the error of the
    /// lattice's mean of its linearisation ψ(x) = ∇g · h(x), h(x) the point's terms of
    /// the sums (`Sensitivity::influence`). ψ is a function on the lattice's 2d-
    /// dimensional cube, periodic as f is after the tent (or periodic itself, for the
    /// inputs the face test took without it), and its mean's error is what a Bayesian
    /// cubature prices ([`crate::posterior`]): a shift-invariant kernel fitted to ψ's
    /// values by maximum likelihood, whose posterior standard deviation is the index's.
    /// Unlike the blocks' jackknife, which measures the spread of rules of N/R points,
    /// this prices the rule of all N points that the estimate is.
    pub fn posterior_sd(&self) -> &[f64] {
        &self.posterior_sd
    }

    /// Fits [`Sensitivity::posterior_sd`] to the values of all N points.
    fn fit_posterior(&mut self) {
        let (k, rows, m) = (self.k, self.rows(), self.indices_per_output());
        let n = self.values.len() / (rows * k);
        let z = &self.options.rule.table().generator()[..2 * self.d];
        // Indices fitted together, as many as keep their values within 2^22 floats.
        let chunk = ((1usize << 22) / n.max(1)).clamp(1, m);
        let mut sd = vec![0.0; m * k];
        let mut psi = vec![0.0; m];
        for j in 0..k {
            let (s, count) = self.pooled(&self.sums, self.per_replicate, j, |_| true);
            let est = self.indices(&s, count);
            let mo = self.moments(&s, count);
            let weights = self.coordinate_weights(&est);
            for first in (0..m).step_by(chunk) {
                let last = (first + chunk).min(m);
                let mut ys = vec![vec![0.0; n]; last - first];
                for p in 0..n {
                    let point = &self.values[p * rows * k..(p + 1) * rows * k];
                    self.influence(&mo, &est, point, j, &mut psi);
                    let at = crate::posterior::natural_index(p, n);
                    for (y, v) in ys.iter_mut().zip(&psi[first..last]) {
                        y[at] = *v;
                    }
                }
                for (i, p) in crate::posterior::posteriors(&ys, z, &weights)
                    .into_iter()
                    .enumerate()
                {
                    sd[(first + i) * k + j] = p.map_or(0.0, |p| p.sd);
                }
            }
        }
        self.posterior_sd = sd;
    }

    /// The kernel's weight of each of the 2d coordinates: its input's total index over
    /// the largest. An input's A and B coordinates enter f only through that input, so
    /// ψ varies along them about as much as f varies with the input, which its total
    /// index measures; with one weight for all (θ alone) the kernel is as rough in the
    /// coordinates of inputs that do not matter as in those that do, and the posterior
    /// priced the G function of 24 inputs (21 nearly inert) 8× too wide.
    fn coordinate_weights(&self, est: &[f64]) -> Vec<f64> {
        let d = self.d;
        let total = &est[d..2 * d];
        let top = total.iter().copied().fold(0.0, f64::max);
        (0..2 * d)
            .map(|c| {
                let t = total[self.layout.input_of(c, d)];
                if top > 0.0 {
                    (t / top).max(0.0)
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// Every index's linearisation at one point (`point` its rows × k values as fed),
    /// output j, into `out` in the order of [`Sensitivity::indices`]: the derivative of
    /// the index's formula along the point's terms of the means it is made of, with `mo`
    /// those means and `est` the indices from them. Constants are left out (a cubature's
    /// error does not see them).
    fn influence(&self, mo: &Moments, est: &[f64], point: &[f64], j: usize, out: &mut [f64]) {
        let (d, k, v) = (self.d, self.k, mo.v);
        let scale = pow2(-self.scale[j]);
        let y = |row: usize| (point[row * k + j] - self.centre[j]) * scale;
        let (ya, yb) = (y(0), y(1));
        // The variance's own linearisation, which every index divided by V shares.
        let dv = (ya * ya + yb * yb) / 2.0 - mo.mean * (ya + yb);
        for (i, m) in mo.inputs.iter().enumerate() {
            let yi = y(2 + i);
            let total = est[d + i];
            let term = (ya - yi) * (ya - yi) / 2.0;
            out[d + i] = match self.options.total_order {
                TotalOrder::Jansen => (term - total * dv) / v,
                TotalOrder::Janon => {
                    let dover = (ya * ya + yi * yi) / 2.0 - m.total_mean * (ya + yi);
                    (term - total * dover) / m.over
                }
            };
            let first = est[i];
            out[i] = match self.options.first_order {
                FirstOrder::Saltelli => (yb * (yi - ya) - first * dv) / v,
                FirstOrder::Janon => {
                    let mb = m.first_mean;
                    let dnum = yb * yi - mb * (yb + yi);
                    let dden = (yb * yb + yi * yi) / 2.0 - mb * (yb + yi);
                    (dnum - first * dden) / m.den
                }
            };
        }
        for (p, ((i, jj), closed)) in row_order(d).zip(&mo.closed).enumerate() {
            let (abi, abj) = (y(2 + i), y(2 + jj));
            let (bai, baj) = (y(2 + d + i), y(2 + d + jj));
            let term = (bai * abj + baj * abi) / 2.0 - ya * yb;
            out[2 * d + p] = (term - closed / v * dv) / v - out[i] - out[jj];
        }
    }

    /// Indices per output: 2·d, and the pairs' with second order.
    fn indices_per_output(&self) -> usize {
        2 * self.d
            + if self.options.second_order {
                pairs(self.d)
            } else {
                0
            }
    }

    /// Every index and its half-width so far, index-major (`[i·k + j]`, the indices in
    /// the order of [`Sensitivity::indices`]); the round guard raises a half-width to
    /// the index's change since half the points when that is larger. Empty before the
    /// first batch.
    fn all_current(&self) -> (Vec<f64>, Vec<f64>) {
        let t = self.quantile();
        let (m, k) = (self.indices_per_output(), self.k);
        let posterior = self.posterior_sd.len() == m * k;
        let z = self.posterior_quantile();
        let (mut value, mut half_width) = (vec![0.0; m * k], vec![0.0; m * k]);
        for (j, (now, se, half)) in self.estimates().into_iter().enumerate() {
            for i in 0..m {
                let change = half.as_ref().map_or(0.0, |h| (now[i] - h[i]).abs());
                value[i * k + j] = now[i];
                let own = if posterior {
                    z * self.posterior_sd[i * k + j]
                } else {
                    t * se[i]
                };
                half_width[i * k + j] = own.max(change);
            }
        }
        (value, half_width)
    }

    /// The indices and half-widths so far, each d × k, input-major (`[i·k + j]`):
    /// (first, total, first half-width, total half-width). Empty before the first batch.
    pub fn current(&self) -> [Vec<f64>; 4] {
        let (value, half_width) = self.all_current();
        let dk = self.d * self.k;
        if value.is_empty() {
            return std::array::from_fn(|_| Vec::new());
        }
        [
            value[..dk].to_vec(),
            value[dk..2 * dk].to_vec(),
            half_width[..dk].to_vec(),
            half_width[dk..2 * dk].to_vec(),
        ]
    }

    /// The second-order indices and their half-widths so far, pair-major over the pairs
    /// i < j in row order (`[p·k + j]`); empty without second order or before the first
    /// batch.
    pub fn second(&self) -> [Vec<f64>; 2] {
        let (value, half_width) = self.all_current();
        let dk = 2 * self.d * self.k;
        if !self.options.second_order || value.is_empty() {
            return [Vec::new(), Vec::new()];
        }
        [value[dk..].to_vec(), half_width[dk..].to_vec()]
    }

    /// Whether every half-width is within `abs_tol` (and finite), the pairs' with
    /// second order.
    pub fn met(&self) -> bool {
        if self.k == 0 {
            return false;
        }
        let (value, half_width) = self.all_current();
        let tol = self.options.abs_tol;
        value.iter().all(|x| x.is_finite()) && half_width.iter().all(|h| h.is_finite() && *h <= tol)
    }

    /// Warnings about the settings: too few replicates for a trustworthy interval.
    pub fn warnings(&self) -> Vec<String> {
        let r = self.options.replicates;
        if r < crate::MIN_QUIET_REPLICATES {
            vec![format!(
                "{r} replicates give unreliable intervals: their half-widths vary widely \
                 between runs; use {} or more",
                crate::MIN_QUIET_REPLICATES
            )]
        } else {
            Vec::new()
        }
    }

    /// Doubles until [`Sensitivity::met`] or [`Sensitivity::exhausted`], calling f on
    /// each batch (rows × k values, row-major). Returns whether the tolerance is met.
    pub fn run<F>(&mut self, f: F) -> Result<bool, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
    {
        self.run_observed(f, |_| {})
    }

    /// [`Sensitivity::run`], calling `after` with the state after each doubling
    /// (progress displays); stops with [`stillpoint_solve::interrupted`] when a stop is
    /// asked for ([`stillpoint_solve::cancel`]), between two batches.
    pub fn run_observed<F, A>(&mut self, f: F, after: A) -> Result<bool, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
        A: FnMut(&Sensitivity),
    {
        crate::run_rounds(self, f, after)?;
        Ok(self.met())
    }
}

impl crate::Rounds for Sensitivity {
    fn met(&self) -> bool {
        Sensitivity::met(self)
    }
    fn pending(&self) -> u64 {
        Sensitivity::pending(self)
    }
    fn next_points(&mut self) -> Option<PointSet> {
        Sensitivity::next_points(self)
    }
    fn feed(&mut self, points: &PointSet, values: &[f64]) -> Result<(), Error> {
        Sensitivity::feed(self, points, values)
    }
    fn in_round(&self) -> bool {
        Sensitivity::in_round(self)
    }
}

/// The settings as an integration over the inputs' box takes them: its checks of the
/// box, tolerance, level, replicates and first batch are the rule here too.
fn quad_options(o: &SensitivityOptions) -> crate::QuadOptions {
    crate::QuadOptions {
        a: o.a.clone(),
        b: o.b.clone(),
        abs_tol: o.abs_tol,
        rel_tol: 0.0,
        level: o.level,
        replicates: o.replicates,
        max_n: u64::MAX,
        start_n: o.start_n,
        seed: o.seed,
        // The pick-freeze points are the extensible lattice's in 2d dimensions; quad's
        // rule is not what this run evaluates, only its checks are shared.
        rule: crate::Rule::TentLattice,
        rule_reason: String::new(),
        rule_asked: true,
    }
}

/// Refuses a budget below one first batch (naming `max_n`).
fn check_budget(o: &SensitivityOptions, d: usize) -> Result<(), Error> {
    let faces = if o.rule == Rule::Sobol {
        0
    } else {
        face_evaluations(d)
    };
    let rows = rows_per_point(d, o.second_order);
    let first = o
        .start_n
        .saturating_mul(o.replicates as u64)
        .saturating_mul(rows as u64)
        .saturating_add(faces);
    if o.max_n < first {
        return Err(Error::invalid(
            stillpoint_parse::names::MAX_N,
            o.max_n,
            format!(
                "at least one first batch: {} points for each of the {} replicates, each \
                 {rows} evaluations ({}){}, {first} evaluations",
                o.start_n,
                o.replicates,
                if o.second_order { "2d + 2" } else { "d + 2" },
                if faces > 0 {
                    format!(", and the face test's {faces}")
                } else {
                    String::new()
                }
            ),
        ));
    }
    Ok(())
}

/// Evaluations per point of d inputs: A, B and each AB_i (d + 2), and each BA_i with
/// second-order indices (2d + 2).
fn rows_per_point(d: usize, second_order: bool) -> usize {
    if second_order {
        2 * d + 2
    } else {
        d + 2
    }
}

/// Refuses NaN or ±∞ among f's `values` (k per point), naming the first one's point and
/// output.
fn refuse_non_finite(points: &PointSet, values: &[f64], k: usize) -> Result<(), Error> {
    let Some(at) = values.iter().position(|v| !v.is_finite()) else {
        return Ok(());
    };
    let d = points.s();
    let i = at / k;
    let p = &points.as_slice()[i * d..(i + 1) * d];
    Err(Error::invalid(
        "f",
        format!("{} at x = {:?} (output {})", values[at], p, at % k),
        "a finite value at every point",
    ))
}

/// 2^e as a float (e within the normal range).
fn pow2(e: i32) -> f64 {
    f64::from_bits(((1023 + e.clamp(-1022, 1023)) as u64) << 52)
}

/// Per output, the centre (the mean of the first batch) and the power of two that brings
/// the largest deviation from it near 1, so that squares and products of later values
/// neither overflow nor underflow (1 for an output constant over the batch).
fn first_scaling(values: &[f64], k: usize) -> (Vec<f64>, Vec<i32>) {
    let rows = values.len() / k;
    let mut centre = Vec::with_capacity(k);
    let mut scale = Vec::with_capacity(k);
    for j in 0..k {
        let column = || values.iter().skip(j).step_by(k).copied();
        // The mean without overflow: each value divided before summing.
        let c = column().map(|v| v / rows as f64).sum::<f64>();
        let spread = column().map(|v| (v - c).abs()).fold(0.0f64, f64::max);
        let e = if spread.is_finite() && spread > 0.0 {
            spread.log2().floor() as i32
        } else {
            0
        };
        centre.push(c);
        scale.push(e.clamp(-1000, 1000));
    }
    (centre, scale)
}

/// What [`sobol_indices`] returns; every index vector is d × k, input-major
/// (`first[i·k + j]` is input i's index for output j).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SobolResult {
    /// First-order indices.
    pub first: Vec<f64>,
    /// Total indices.
    pub total: Vec<f64>,
    /// Half-width of each first-order index's interval (its own at `level`, or all
    /// together with `simultaneous`).
    pub first_half_width: Vec<f64>,
    /// Half-width of each total index's interval.
    pub total_half_width: Vec<f64>,
    /// Second-order indices of the pairs i < j in row order, pair-major (`[p·k + j]`);
    /// empty unless asked for (results saved before: empty).
    #[serde(default)]
    pub second: Vec<f64>,
    /// Half-width of each second-order index's interval.
    #[serde(default)]
    pub second_half_width: Vec<f64>,
    /// Outputs k.
    pub outputs: usize,
    /// The inputs' names.
    pub names: Vec<String>,
    /// Evaluations of f, all rounds.
    pub n: u64,
    /// Whether every half-width is within `abs_tol`.
    pub met: bool,
    /// Why the run stopped.
    pub reason: Option<StopReason>,
    /// Warnings about the settings.
    pub warnings: Vec<String>,
    /// The state, to continue with a tighter tolerance.
    pub state: Sensitivity,
}

impl From<Sensitivity> for SobolResult {
    fn from(state: Sensitivity) -> SobolResult {
        let [first, total, first_half_width, total_half_width] = state.current();
        let [second, second_half_width] = state.second();
        SobolResult {
            first,
            total,
            first_half_width,
            total_half_width,
            second,
            second_half_width,
            outputs: state.outputs(),
            names: state.names().to_vec(),
            n: state.n(),
            met: state.met(),
            reason: state.reason(),
            warnings: state.warnings(),
            state,
        }
    }
}

impl SobolResult {
    /// Continues with a new tolerance, evaluating f only at new points.
    pub fn refine<F>(self, f: F, abs_tol: f64) -> Result<SobolResult, Error>
    where
        F: FnMut(&PointSet) -> Vec<f64>,
    {
        let mut state = self.state;
        state.set_tolerance(abs_tol)?;
        state.run(f)?;
        Ok(SobolResult::from(state))
    }
}

/// The first-order and total Sobol' indices of f's d inputs (independent, uniform on the
/// box of `options`) to the tolerance of `options` (see the module documentation). f
/// gets a batch of points and returns rows × k values, row-major.
///
/// ```
/// use stillpoint_cubature::sensitivity::{sobol_indices, SensitivityOptions};
/// // f = x1 + 2·x2: S = T = (1/5, 4/5).
/// let r = sobol_indices(
///     |x| x.rows().map(|p| p[0] + 2.0 * p[1]).collect(),
///     2,
///     SensitivityOptions::default(),
/// )?;
/// assert!(r.met && (r.first[1] - 0.8).abs() < 0.02 && (r.total[0] - 0.2).abs() < 0.02);
/// # Ok::<(), stillpoint_domains::Error>(())
/// ```
pub fn sobol_indices<F>(f: F, d: usize, options: SensitivityOptions) -> Result<SobolResult, Error>
where
    F: FnMut(&PointSet) -> Vec<f64>,
{
    let mut state = Sensitivity::new(d, options)?;
    state.run(f)?;
    Ok(SobolResult::from(state))
}

/// Refuses a design space whose inputs are not independent, naming `option` (`space`,
/// `--var`): a correlation between its variables, or a Brownian path (whose coordinates
/// are the path's values, dependent on one another). The indices are defined here for
/// independent inputs only: under dependence their shares of the variance no longer add
/// up, and no one definition is standard.
pub fn check_independent(
    option: &str,
    space: &stillpoint_design::DesignSpace,
) -> Result<(), Error> {
    if space.copula.is_some() {
        return Err(Error::invalid(
            option,
            "variables with a correlation",
            "independent inputs (Sobol' indices are defined here for independent inputs)",
        ));
    }
    if let Some(v) = space
        .vars
        .iter()
        .find(|v| matches!(v.kind, stillpoint_design::Kind::Path { .. }))
    {
        return Err(Error::invalid(
            option,
            format!("{} (a coordinate of a Brownian path)", v.name),
            "independent inputs: a path's values depend on one another; give its \
             increments as normal(0,s) variables instead",
        ));
    }
    Ok(())
}

impl Sensitivity {
    /// `{prefix}: n=4096  widest half-width=3.1e-02 (T of x2) (target 1.0e-02)  2.3 s`: the
    /// widest interval of every first-order (S), total (T) and second-order (S of
    /// `x1,x3`) index, named by its inputs (and output, with several).
    pub fn progress_line(&self, prefix: &str, seconds: f64) -> String {
        let [_, _, first, total] = self.current();
        let [_, second] = self.second();
        let k = self.outputs().max(1);
        let names = self.names();
        let widths = first.iter().map(|h| (*h, 'S', 0)).enumerate();
        let widths = widths.chain(total.iter().map(|h| (*h, 'T', 1)).enumerate());
        let widths = widths.chain(second.iter().map(|h| (*h, 'S', 2)).enumerate());
        // The widest; among equals the total, then a pair, then the later index.
        let widest = widths.max_by(|(i, (h, _, a)), (j, (g, _, b))| {
            h.total_cmp(g)
                .then((a % 2).cmp(&(b % 2)))
                .then(a.cmp(b))
                .then(i.cmp(j))
        });
        let Some((i, (h, kind, of))) = widest else {
            return format!("{prefix}: n={}", self.n());
        };
        let output = if k > 1 {
            format!(", output {}", i % k)
        } else {
            String::new()
        };
        let inputs = if of == 2 {
            let (a, b) = pair_of(i / k, self.d);
            format!("{},{}", names[a], names[b])
        } else {
            names[i / k].clone()
        };
        format!(
            "{prefix}: n={}  widest half-width={} ({kind} of {inputs}{output}) (target {})  {seconds:.1} s",
            self.n(),
            crate::progress::sci(h, 1),
            crate::progress::sci(self.options().abs_tol, 1)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ishigami's function on [−π, π]³ with a = 7, b = 0.1.
    fn ishigami(x: &PointSet) -> Vec<f64> {
        x.rows()
            .map(|p| p[0].sin() + 7.0 * p[1].sin().powi(2) + 0.1 * p[2].powi(4) * p[0].sin())
            .collect()
    }

    fn ishigami_options() -> SensitivityOptions {
        SensitivityOptions {
            a: Some(vec![-std::f64::consts::PI; 3]),
            b: Some(vec![std::f64::consts::PI; 3]),
            abs_tol: 0.0,
            max_n: 3 * 256 * 8 + face_evaluations(3),
            second_order: true,
            ..SensitivityOptions::default()
        }
    }

    /// The terms one point adds to the sums of output 0, written out again from the
    /// estimators' formulas: y_A, y_B, y_A², y_B², per input y_B(y_ABi − y_A),
    /// (y_A − y_ABi)², y_B·y_ABi, y_ABi, y_ABi², then y_A·y_B and per pair
    /// y_BAi·y_ABj + y_BAj·y_ABi.
    fn terms(state: &Sensitivity, p: usize) -> Vec<f64> {
        let (d, rows) = (state.d, state.rows());
        let scale = pow2(-state.scale[0]);
        let y = |row: usize| (state.values[p * rows + row] - state.centre[0]) * scale;
        let (ya, yb) = (y(0), y(1));
        let mut h = vec![ya, yb, ya * ya, yb * yb];
        for i in 0..d {
            let yi = y(2 + i);
            h.extend([yb * (yi - ya), (ya - yi).powi(2), yb * yi, yi, yi * yi]);
        }
        h.push(ya * yb);
        for i in 0..d {
            for j in i + 1..d {
                h.push(y(2 + d + i) * y(2 + j) + y(2 + d + j) * y(2 + i));
            }
        }
        h
    }

    #[test]
    fn the_influence_is_the_derivative_of_every_estimator() {
        // Weight ε more on point p moves the means to μ + (ε/n)(h_p − μ), so an index
        // moves by (ε/n)(ψ(p) − ∇g·μ): the difference between two points' moves, times
        // n/ε, is ψ(p) − ψ(q) for every estimator and the pairs.
        for (first_order, total_order) in [
            (FirstOrder::Saltelli, TotalOrder::Jansen),
            (FirstOrder::Janon, TotalOrder::Janon),
        ] {
            let o = SensitivityOptions {
                first_order,
                total_order,
                ..ishigami_options()
            };
            let mut state = Sensitivity::new(3, o).unwrap();
            state.run(ishigami).unwrap();
            let (s, n) = state.pooled(&state.sums, state.per_replicate, 0, |_| true);
            let est = state.indices(&s, n);
            let mo = state.moments(&s, n);
            let m = est.len();
            let eps = 1e-6;
            let moved = |p: usize| {
                let h = terms(&state, p);
                let shifted: Vec<f64> = s.iter().zip(&h).map(|(a, b)| a + eps * b).collect();
                state.indices(&shifted, n + eps)
            };
            let (mut psi_p, mut psi_q) = (vec![0.0; m], vec![0.0; m]);
            let rows = state.rows();
            for (p, q) in [(0, 1), (5, 300), (33, 511)] {
                let row = |p: usize| &state.values[p * rows..(p + 1) * rows];
                state.influence(&mo, &est, row(p), 0, &mut psi_p);
                state.influence(&mo, &est, row(q), 0, &mut psi_q);
                let (gp, gq) = (moved(p), moved(q));
                for i in 0..m {
                    let fd = ((gp[i] - est[i]) - (gq[i] - est[i])) * n / eps;
                    let exact = psi_p[i] - psi_q[i];
                    assert!(
                        (fd - exact).abs() <= 1e-4 * (1.0 + exact.abs()),
                        "{first_order:?} {total_order:?} index {i}: {fd} against {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_posterior_interval_prices_the_rule_and_falls_back_to_the_blocks() {
        // By default the half-widths are the posterior's quantile times its standard
        // deviations (no round guard after one doubling); asked for by name, or past the
        // values a state keeps, the blocks' jackknife.
        let one = SensitivityOptions {
            second_order: false,
            max_n: 5 * 64 * 8 + face_evaluations(3),
            ..ishigami_options()
        };
        let mut posterior = Sensitivity::new(3, one.clone()).unwrap();
        posterior.run(ishigami).unwrap();
        let z = posterior.posterior_quantile();
        assert!((z - 2.5758293035489).abs() < 1e-9, "{z}");
        let [_, _, first_hw, total_hw] = posterior.current();
        let sd = posterior.posterior_sd();
        assert_eq!(sd.len(), 6);
        for (h, s) in first_hw.iter().chain(&total_hw).zip(sd) {
            assert_eq!(*h, z * s);
            assert!(*s > 0.0);
        }
        let blocks = |o: SensitivityOptions, most: usize| {
            let mut state = Sensitivity::new(3, o).unwrap();
            state.most_values = most;
            state.run(ishigami).unwrap();
            state
        };
        let named = blocks(
            SensitivityOptions {
                interval: Interval::Blocks,
                ..one.clone()
            },
            MOST_VALUES,
        );
        let full = blocks(one, 5 * 64 * 8 - 1);
        for state in [&named, &full] {
            assert!(state.posterior_sd().is_empty() && state.values.is_empty());
            assert_eq!(state.options.interval, Interval::Blocks);
            assert_eq!(state.current(), named.current());
        }
        assert_eq!(named.current()[0], posterior.current()[0]);
        assert_ne!(named.current()[2], posterior.current()[2]);
    }

    /// f = x1 + 2·x2·x3 + x3², evaluated batch by batch, recording each batch's
    /// points.
    fn run(mut state: Sensitivity, batches: &mut Vec<Vec<f64>>) -> Sensitivity {
        state
            .run(|x| {
                batches.push(x.as_slice().to_vec());
                x.rows()
                    .map(|p| p[0] + 2.0 * p[1] * p[2] + p[2] * p[2])
                    .collect()
            })
            .unwrap();
        state
    }

    fn options() -> SensitivityOptions {
        SensitivityOptions {
            abs_tol: 0.0,
            max_n: 100_000,
            ..SensitivityOptions::default()
        }
    }

    /// The pairs (i, j), i < j, in the order of `second`.
    fn pair_list(d: usize) -> Vec<(usize, usize)> {
        (0..d)
            .flat_map(|i| (i + 1..d).map(move |j| (i, j)))
            .collect()
    }

    #[test]
    fn pair_of_walks_the_pairs_in_row_order() {
        for d in 2..7 {
            let walked: Vec<_> = (0..pairs(d)).map(|p| pair_of(p, d)).collect();
            assert_eq!(walked, pair_list(d));
        }
    }

    /// Ishigami's function (a = 7, b = 0.1) on [−π, π]³: S_13 = 8b²π⁸/225 / V, the other
    /// pairs 0, and with no interaction of all three the first-order and second-order
    /// indices add up to 1.
    #[test]
    fn second_order_indices_of_ishigami_s_function_are_its_closed_forms() {
        let (a, b) = (7.0, 0.1);
        let pi = std::f64::consts::PI;
        let v = a * a / 8.0 + b * pi.powi(4) / 5.0 + b * b * pi.powi(8) / 18.0 + 0.5;
        let s13 = 8.0 * b * b * pi.powi(8) / 225.0 / v;
        let options = SensitivityOptions {
            a: Some(vec![-pi; 3]),
            b: Some(vec![pi; 3]),
            abs_tol: 0.01,
            second_order: true,
            ..SensitivityOptions::default()
        };
        let r = sobol_indices(
            |x| {
                x.rows()
                    .map(|p| p[0].sin() + a * p[1].sin().powi(2) + b * p[2].powi(4) * p[0].sin())
                    .collect()
            },
            3,
            options,
        )
        .unwrap();
        assert!(r.met);
        assert_eq!(r.second.len(), 3);
        let want = [0.0, s13, 0.0];
        for (p, &(i, j)) in pair_list(3).iter().enumerate() {
            assert!(
                (r.second[p] - want[p]).abs() <= 0.015,
                "S_{i}{j} = {} against {}",
                r.second[p],
                want[p]
            );
            assert!(r.second_half_width[p] <= 0.01);
        }
        let sum: f64 = r.first.iter().chain(&r.second).sum();
        assert!((sum - 1.0).abs() < 0.03, "{sum}");
        // d + 2 more evaluations per point than without: 2d + 2 in all.
        let per_point = (r.n - face_evaluations(3)) / (r.state.per_replicate() * 8);
        assert_eq!(per_point, 8);
    }

    /// f = x1·x2 (x3 inert): V = 7/144, V_1 = V_2 = 3/144, V_12 = 1/144, so S_12 = 1/7; and
    /// the first-order and total indices are those of the same points without the BA_i
    /// rows, bit for bit.
    #[test]
    fn second_order_adds_pairs_without_changing_the_other_indices() {
        let f = |x: &PointSet| x.rows().map(|p| p[0] * p[1]).collect::<Vec<f64>>();
        let mut with = Sensitivity::new(
            3,
            SensitivityOptions {
                second_order: true,
                ..options()
            },
        )
        .unwrap();
        let mut without = Sensitivity::new(3, options()).unwrap();
        for state in [&mut with, &mut without] {
            for _ in 0..6 {
                let x = state.next_points().unwrap();
                let y = f(&x);
                state.feed(&x, &y).unwrap();
            }
        }
        assert_eq!(with.current(), without.current());
        assert!(without.second()[0].is_empty());
        let [second, half] = with.second();
        let want = [1.0 / 7.0, 0.0, 0.0];
        for p in 0..3 {
            assert!((second[p] - want[p]).abs() < 0.01, "{second:?}");
            assert!(
                (second[p] - want[p]).abs() <= half[p].max(1e-3),
                "{second:?} {half:?}"
            );
        }
        // A state saved without the option reads as one without it.
        let mut json = serde_json::to_value(&without).unwrap();
        json["options"]
            .as_object_mut()
            .unwrap()
            .remove("second_order");
        let back: Sensitivity = serde_json::from_value(json).unwrap();
        assert_eq!(back, without);
    }

    #[test]
    fn a_doubling_cut_into_batches_gives_the_indices_of_one_batch() {
        // Blocks of one sequence, and independent replicates (states saved before
        // blocks), whose batches then cross from one replicate's points to the next's.
        for replicas in [Replicas::Blocks, Replicas::Independent] {
            let fresh = || {
                let mut state = Sensitivity::new(3, options()).unwrap();
                state.replicas = replicas;
                state
            };
            let mut all = Vec::new();
            let whole = run(fresh(), &mut all);
            let mut cut = fresh();
            // 15 coordinates per point (d + 2 rows of d): 7 points per batch, so that
            // the first doubling's 8·64 points come as 74 batches.
            cut.most_coordinates = 7 * 15;
            let mut batches = Vec::new();
            let cut = run(cut, &mut batches);
            assert_eq!(cut.n(), whole.n());
            assert!(batches.len() > 74 + all.len(), "{}", batches.len());
            // The face test's batch (4 points, 2·d rows each) is one batch; the others
            // are the same points as the whole doublings', cut.
            assert!(batches[1..].iter().all(|b| b.len() <= 7 * 15));
            assert_eq!(batches.concat(), all.concat());
            // The first batch's mean is the centre the sums are taken around, and
            // Saltelli's first-order estimate moves with it (by the centre's shift times
            // the mean of y_ABi − y_A, the rule's error): the indices agree far within
            // the intervals. Independent replicates' spread moves with it too, by a
            // small share of itself.
            let [first, total, first_width, total_width] = cut.current();
            let [whole_first, whole_total, whole_first_width, whole_total_width] = whole.current();
            let widest = whole_first_width
                .iter()
                .chain(&whole_total_width)
                .fold(0.0, |a: f64, b| a.max(*b));
            let indices = first.iter().chain(&total);
            for (a, b) in indices.zip(whole_first.iter().chain(&whole_total)) {
                assert!((a - b).abs() <= 1e-3 * widest, "{replicas:?}: {a} {b}");
            }
            let widths = first_width.iter().chain(&total_width);
            for (a, b) in widths.zip(whole_first_width.iter().chain(&whole_total_width)) {
                assert!((a - b).abs() <= 0.05 * b, "{replicas:?}: {a} {b}");
            }
        }
    }

    #[test]
    fn a_state_saved_within_a_doubling_continues_to_the_same_figures() {
        let mut state = Sensitivity::new(3, options()).unwrap();
        state.most_coordinates = 7 * 15;
        let f = |x: &PointSet| -> Vec<f64> {
            x.rows()
                .map(|p| p[0] + 2.0 * p[1] * p[2] + p[2] * p[2])
                .collect()
        };
        // Past the face test and the first doubling, then three batches into the next.
        while state.per_replicate() == 0 || state.fed < 3 * 7 {
            let points = state.next_points().unwrap();
            state.feed(&points, &f(&points)).unwrap();
        }
        assert!(state.in_round());
        let saved: Sensitivity =
            serde_json::from_str(&serde_json::to_string(&state).unwrap()).unwrap();
        // A saved state takes whole-replicate batches again: the sums do not depend on
        // the cut.
        assert_eq!(saved.most_coordinates, BATCH_COORDINATES);
        let (mut a, mut b) = (state, saved);
        a.run(f).unwrap();
        b.run(f).unwrap();
        assert_eq!(a.n(), b.n());
        assert_eq!(a.current(), b.current());
    }

    #[test]
    fn an_output_constant_over_a_first_batch_but_not_its_doubling_is_taken() {
        let mut state = Sensitivity::new(3, options()).unwrap();
        state.most_coordinates = 7 * 15;
        let faces = state.next_points().unwrap();
        let values: Vec<f64> = faces.rows().map(|p| p[0]).collect();
        state.feed(&faces, &values).unwrap();
        // f = max(0, x1 − c), with c the largest x1 of the first batch: 0 there, not
        // over the doubling; its indices are 1 for x1, 0 for the others.
        let batch = state.next_points().unwrap();
        let c = batch.rows().map(|p| p[0]).fold(0.0, f64::max);
        assert!(c < 0.99, "{c}");
        state
            .run(|x| x.rows().map(|p| (p[0] - c).max(0.0)).collect())
            .unwrap();
        let [first, total, ..] = state.current();
        assert!((first[0] - 1.0).abs() < 0.01 && (total[0] - 1.0).abs() < 0.01);
        assert!(first[1].abs() < 0.01 && total[2].abs() < 0.01);
    }

    #[test]
    fn a_rule_the_indices_do_not_take_is_refused_by_name() {
        for rule in [
            Rule::Pilot,
            Rule::Probe,
            Rule::FaceTest,
            Rule::FirstOrderLattice,
            Rule::BayesLattice,
            Rule::BayesNet,
        ] {
            let options = SensitivityOptions {
                rule,
                ..SensitivityOptions::default()
            };
            let e = Sensitivity::new(3, options).unwrap_err().to_string();
            assert!(e.contains("rule") && e.contains(rule.as_str()), "{e}");
        }
        for rule in [Rule::TentLattice, Rule::Sobol] {
            let options = SensitivityOptions {
                rule,
                ..SensitivityOptions::default()
            };
            assert!(Sensitivity::new(3, options).is_ok());
        }
    }

    #[test]
    fn an_output_constant_over_its_first_doubling_is_refused_and_it_starts_again() {
        let mut state = Sensitivity::new(2, options()).unwrap();
        state.most_coordinates = 5 * 8;
        let faces = state.next_points().unwrap();
        let values: Vec<f64> = faces.rows().map(|p| p[0]).collect();
        state.feed(&faces, &values).unwrap();
        let first = state.next_points().unwrap();
        let start = state.clone();
        let e = loop {
            let points = state.next_points().unwrap();
            if let Err(e) = state.feed(&points, &vec![4.5; points.n()]) {
                break e.to_string();
            }
        };
        // 8 replicates of 64 points, 4 evaluations each.
        assert!(
            e.starts_with("invalid f = 4.5 at every one of the first 2048 points"),
            "{e}"
        );
        assert_eq!(state, start);
        assert_eq!(state.next_points().unwrap(), first);
    }
}
