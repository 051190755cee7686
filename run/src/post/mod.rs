//! Steps after the solver: the periodic [`shift`] selection, the L-BFGS [`polish`] on a
//! discrepancy, and the [`randomize`] step that makes a set an unbiased randomised rule.

pub mod polish;
pub mod randomize;
pub mod shift;
