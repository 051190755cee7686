//! Design spaces as users have them: continuous variables with bounds or distributions,
//! integer ranges, ordered and unordered categorical levels. A design is made in the
//! unit cube, where the discrepancy is defined and optimised, and mapped to the space.

pub mod dist;
