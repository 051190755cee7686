//! Discrepancies and distances that measure how evenly a point set fills the unit cube.
