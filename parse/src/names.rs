//! The option names the layers below the option table spell in their refusals and
//! stage lines. The table (`stillpoint::pipeline::options`) sits above those layers (it
//! reads their limits and defaults), so each such name is written once here, with no
//! import of its own so that any module may use it; a test of the table holds every
//! one equal to its declaration, and the caller spells it its own way (`--box`, `box`)
//! in a refusal.

/// `abs_tol`.
pub const ABS_TOL: &str = "abs_tol";
/// `interval`: how the Sobol' indices' intervals are computed.
pub const INTERVAL: &str = "interval";
/// `rel_tol`.
pub const REL_TOL: &str = "rel_tol";
/// `level`.
pub const LEVEL: &str = "level";
/// `max_n`.
pub const MAX_N: &str = "max_n";
/// `replicates`.
pub const REPLICATES: &str = "replicates";
/// `box`: the bounding box of a region, a polytope or constraints.
pub const BOX: &str = "box";
/// `constraints`: linear constraints.
pub const CONSTRAINTS: &str = "constraints";
/// `mixture`: the components sum to 1.
pub const MIXTURE: &str = "mixture";
/// `region`: an expression g(x) <= 0.
pub const REGION: &str = "region";
/// `shape`: a built-in region.
pub const SHAPE: &str = "shape";
/// `energy`: the energy of the paper's pipeline.
pub const ENERGY: &str = "energy";
/// `shifts`: candidate periodic shifts.
pub const SHIFTS: &str = "shifts";
/// `polish`: the paper pipeline's final polish (also the name of its stage).
pub const POLISH: &str = "polish";
/// `nested`: the sizes of a nested sequence of sets.
pub const NESTED: &str = "nested";
/// `checkpoint`: the file a long run saves its state to.
pub const CHECKPOINT: &str = "checkpoint";
/// `randomize`: how a finished set is randomised.
pub const RANDOMIZE: &str = "randomize";
/// `space`: the design space (`NAME=TYPE` variables).
pub const SPACE: &str = "space";
/// `rule`: the randomised rule of an integration.
pub const RULE: &str = "rule";
