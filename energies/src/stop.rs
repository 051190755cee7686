//! A process-wide request to stop the long sums over pairs early: Python's Ctrl-C sets
//! it so that a metric of 40 000 points ends within a tile rather than after minutes.
//! The sums then return partial values, which the caller that asked to stop discards;
//! nothing else ever sets it.

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

/// Asks every pair sum under way to stop at its next tile.
pub fn request() {
    STOP.store(true, Ordering::SeqCst);
}

/// Clears a stop request (before a new call).
pub fn clear() {
    STOP.store(false, Ordering::SeqCst);
}

/// Whether a stop was asked for.
#[inline]
pub fn requested() -> bool {
    STOP.load(Ordering::Relaxed)
}
