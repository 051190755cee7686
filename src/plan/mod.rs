//! What a run is made of, before it runs: where its points live ([`space`]; linear
//! constraints and mixtures in [`constraints`]), its start set ([`start`]), and its energy
//! and domain ([`problem`]). Its settings are in [`crate::config`], what it reports in
//! [`crate::report`].

pub mod constraints;
pub mod problem;
pub mod space;
pub mod start;

/// The options the plan's checks name, as the option table ([`crate::pipeline::options`])
/// declares them. The table sits above the plan (it reads its limits), so each name is
/// written once here, a test of the table holds them equal to its declarations, and the
/// caller spells them its way (`--box`, `box`) in a refusal.
pub mod names {
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
}
