//! Randomising a finished set so that independent seeds give independent, unbiased
//! estimates of an integral.

use crate::Error;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use stillpoint_domains::PointSet;
use stillpoint_quality::stratification::{cell_of, in_cell};

/// How a finished set is randomised (`--randomize`), so that independent seeds give
/// independent, unbiased estimates of an integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Randomize {
    /// x ↦ (x + c) mod 1 with c uniform in [0, 1)^s: every point becomes uniform in the
    /// cube; the torus distances, the periodic energies and the wrap-around L2
    /// discrepancy are unchanged; the stratification is kept only where a coordinate's
    /// values are equally spaced.
    Shift,
    /// Per coordinate, the cells are rotated by a uniform m ∈ {0, …, n−1} and every offset
    /// inside its cell by a uniform v ∈ [0, 1), modulo the cell: x = (c + u)/n ↦
    /// ((c + m) mod n + (u + v) mod 1)/n. Every point becomes uniform in the cube and a
    /// stratified set stays stratified; the discrepancies change a little (a point whose
    /// offset wraps moves by less than 1/n).
    Cells,
    /// x ↦ 1 − |2((x + c) mod 1) − 1| with c uniform in [0, 1)^s: a uniform shift, then
    /// the tent (baker's) transform, which keeps the uniform distribution. Every point
    /// becomes uniform in the cube. Made for the set of
    /// [`crate::goals::integration::tent::tent_set`] (a lattice, or a set descended from
    /// one), whose criterion is this randomisation's mean square error: the estimate's
    /// error decays like n⁻² for smooth integrands (Hickernell 2002), and each column of
    /// that set stays stratified (its columns are the n multiples of 1/n: the shifted
    /// column is equally spaced, and the tent folds its two halves onto alternate cells).
    Tent,
}

impl Randomize {
    /// What [`Randomize::parse`] accepts, for messages.
    pub const EXPECTED: &'static str =
        "tent (the recommended one: a lattice made for it), cells or shift";

    /// Every randomisation, the recommended one first.
    pub const ALL: [Randomize; 3] = [Randomize::Tent, Randomize::Cells, Randomize::Shift];

    /// `tent`, `cells` or `shift`.
    pub fn parse(text: &str) -> Result<Randomize, Error> {
        let key = text.trim().to_ascii_lowercase();
        Randomize::ALL
            .into_iter()
            .find(|r| r.name() == key)
            .ok_or_else(|| {
                Error::invalid(
                    stillpoint_parse::names::RANDOMIZE,
                    text,
                    Randomize::EXPECTED,
                )
            })
    }

    /// The name [`Randomize::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Randomize::Tent => "tent",
            Randomize::Cells => "cells",
            Randomize::Shift => "shift",
        }
    }
}

/// `points` randomised from `seed` as `kind` says (see [`Randomize`]): afterwards each
/// point is uniformly distributed over [0, 1)^s.
pub fn randomize(points: &PointSet, kind: Randomize, seed: u64) -> PointSet {
    let (n, s) = (points.n(), points.s());
    let mut rng =
        Xoshiro256PlusPlus::seed_from_u64(stillpoint_sequences::stream_seed(seed, 0x5261_6e64));
    match kind {
        Randomize::Shift => {
            let c: Vec<f64> = (0..s).map(|_| rng.random::<f64>()).collect();
            crate::post::shift::shifted(points, &c)
        }
        Randomize::Tent => {
            let c: Vec<f64> = (0..s).map(|_| rng.random::<f64>()).collect();
            let shifted = crate::post::shift::shifted(points, &c);
            let data = shifted
                .as_slice()
                .iter()
                .map(|&x| stillpoint_sequences::tent(x))
                .collect();
            PointSet::new(n, s, data).expect("same shape")
        }
        Randomize::Cells => {
            let turns: Vec<(usize, f64)> = (0..s)
                .map(|_| (rng.random_range(0..n), rng.random::<f64>()))
                .collect();
            let data = points
                .as_slice()
                .iter()
                .enumerate()
                .map(|(idx, &x)| {
                    let (m, v) = turns[idx % s];
                    let c = cell_of(x, n);
                    let u = (x * n as f64 - c as f64).clamp(0.0, 1.0);
                    let w = u + v;
                    in_cell((c + m) % n, if w >= 1.0 { w - 1.0 } else { w }, n)
                })
                .collect();
            PointSet::new(n, s, data).expect("same shape")
        }
    }
}
