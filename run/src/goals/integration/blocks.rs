//! Exchanges for sets too large for the pair table of [`Exchange`](super::exchange::Exchange)
//! and for the in-cell descent: the move is the same (two points swap one coordinate, so
//! every column keeps its cells), but only the pair-product rows of a *block* of points
//! are held, b rows of n values per discrepancy. A proposal between two points of the
//! block costs O(n) per discrepancy, like a proposal of the full table, and loading a
//! block costs O(b n s), so each block serves many proposals. The blocks are random
//! points and the proposals swap a random coordinate: at n = 10⁵, s = 10 such swaps
//! between distant values lowered D²_MD several times more per unit of work than swaps
//! between neighbours of one coordinate (which move points by less than a block's
//! width), and screening proposals on a prefix of the points did not pay for itself.
//!
//! A swap is accepted only when it lowers *every* discrepancy of the target (not their
//! weighted sum), each by more than the rounding of its change: the result is below its
//! start in each of them, which is what a user comparing it with the stratified Sobol'
//! set it came from looks at. The changes are exact sums over all n points, so the report
//! can state them without an O(n² s) evaluation of the set.

use super::exchange::{swap_delta, swap_sum, Swap};
use crate::PointSet;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use stillpoint_energies::discrepancy::{DiscrepancyKernel, DiscrepancyKind};
use stillpoint_energies::with_kernel;

/// The pair products are summed in chunks of this many points, in order, so a change has
/// the same bits for any number of threads (and one chunk below this n).
const CHUNK: usize = 4096;

/// The memory the rows of a block may take, in bytes (b rows of n values per discrepancy).
pub const BLOCK_BYTES: usize = 256 << 20;

/// Most points in a block: proposals between more would rarely be tried.
const BLOCK_MAX: usize = 256;

/// Proposals per point of a block, spread over its coordinates.
const PROPOSALS_PER_POINT: usize = 32;

/// What [`block_exchanges`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockOutcome {
    /// Points per block.
    pub block: usize,
    /// Blocks loaded.
    pub blocks: usize,
    /// Proposals evaluated.
    pub proposals: usize,
    /// Swaps accepted (each lowered every discrepancy).
    pub accepted: usize,
    /// The change of each squared discrepancy, summed over the accepted swaps.
    pub changes: Vec<f64>,
    /// The work spent, in the units of the cap (products of one pair factor).
    pub work: u64,
}

/// The state of the exchanges: the coordinates (by rows and by columns), each kind's
/// single products, and the pair-product rows of the loaded block.
struct Blocks {
    kinds: Vec<DiscrepancyKind>,
    n: usize,
    s: usize,
    x: Vec<f64>,
    columns: Vec<f64>,
    singles: Vec<Vec<f64>>,
    members: Vec<usize>,
    /// The slot of each point in `members`, or `usize::MAX`.
    slot: Vec<usize>,
    /// Per kind, the rows of the members: `rows[f][slot * n + l]`.
    rows: Vec<Vec<f64>>,
    /// Per kind, the sum of each member's row, for the rounding bound of a change.
    row_sums: Vec<Vec<f64>>,
}

impl Blocks {
    fn new(points: &PointSet, kinds: &[DiscrepancyKind]) -> Blocks {
        let (n, s) = (points.n(), points.s());
        let x = points.as_slice().to_vec();
        let singles = kinds
            .iter()
            .map(|&kind| with_kernel!(kind, K => singles::<K>(&x, n, s)))
            .collect();
        Blocks {
            kinds: kinds.to_vec(),
            n,
            s,
            columns: (0..s)
                .flat_map(|k| x[k..].iter().step_by(s).copied())
                .collect(),
            x,
            singles,
            members: Vec::new(),
            slot: vec![usize::MAX; n],
            rows: vec![Vec::new(); kinds.len()],
            row_sums: vec![Vec::new(); kinds.len()],
        }
    }

    /// Makes `members` the block: their pair-product rows, each a product over the
    /// coordinates in order, rows in parallel.
    fn load(&mut self, members: &[usize]) {
        for &i in &self.members {
            self.slot[i] = usize::MAX;
        }
        for (t, &i) in members.iter().enumerate() {
            self.slot[i] = t;
        }
        self.members = members.to_vec();
        let (n, s) = (self.n, self.s);
        for (f, &kind) in self.kinds.iter().enumerate() {
            let rows = &mut self.rows[f];
            rows.resize(members.len() * n, 0.0);
            let (x, columns) = (&self.x, &self.columns);
            with_kernel!(kind, K => rows.par_chunks_mut(n).zip(members).for_each(|(row, &i)| {
                fill_row::<K>(&x[i * s..(i + 1) * s], columns, row)
            }));
            self.row_sums[f] = rows.chunks(n).map(|r| r.iter().sum()).collect();
        }
    }

    /// The change of kind f's squared discrepancy if block members i and j swapped
    /// coordinate k (whose values differ), with a bound on its rounding.
    fn delta(&self, f: usize, i: usize, j: usize, k: usize) -> (f64, f64) {
        with_kernel!(self.kinds[f], K => self.delta_with::<K>(f, i, j, k))
    }

    fn delta_with<K: DiscrepancyKernel>(
        &self,
        f: usize,
        i: usize,
        j: usize,
        k: usize,
    ) -> (f64, f64) {
        let (n, s) = (self.n, self.s);
        let (xi, xj) = (self.x[i * s + k], self.x[j * s + k]);
        let column = &self.columns[k * n..(k + 1) * n];
        let (ti, tj) = (self.slot[i], self.slot[j]);
        let rows = &self.rows[f];
        let (pi, pj) = (&rows[ti * n..(ti + 1) * n], &rows[tj * n..(tj + 1) * n]);
        let sum: f64 = pi
            .par_chunks(CHUNK)
            .zip(pj.par_chunks(CHUNK))
            .zip(column.par_chunks(CHUNK))
            .map(|((a, b), c)| swap_sum::<K>(xi, xj, a, b, c))
            .collect::<Vec<f64>>()
            .iter()
            .sum();
        let swap = Swap {
            i,
            j,
            xi,
            xj,
            singles: (self.singles[f][i], self.singles[f][j]),
        };
        let delta = swap_delta::<K>(&swap, pi, pj, column, sum);
        // The sum's terms are about as large as the rows' entries; its rounding is far
        // below a few hundred ulps of their total (chunked, so about √n of them at worst
        // in practice). The single products' part is bounded alike.
        let scale = self.row_sums[f][ti] + self.row_sums[f][tj];
        let nf = n as f64;
        let single = (self.singles[f][i] + self.singles[f][j]).abs();
        let bound = 512.0 * f64::EPSILON * (4.0 * scale / (nf * nf) + 4.0 * single / nf);
        (delta, bound)
    }

    /// Swaps coordinate k of block members i and j: their rows, the other members'
    /// entries of i and j, the single products and the coordinates.
    fn swap(&mut self, i: usize, j: usize, k: usize) {
        for f in 0..self.kinds.len() {
            with_kernel!(self.kinds[f], K => self.swap_rows::<K>(f, i, j, k));
        }
        let (n, s) = (self.n, self.s);
        self.x.swap(i * s + k, j * s + k);
        self.columns.swap(k * n + i, k * n + j);
    }

    /// The part of [`Blocks::swap`] of kind f: its rows and single products.
    fn swap_rows<K: DiscrepancyKernel>(&mut self, f: usize, i: usize, j: usize, k: usize) {
        let (n, s) = (self.n, self.s);
        let (xi, xj) = (self.x[i * s + k], self.x[j * s + k]);
        let (ti, tj) = (self.slot[i], self.slot[j]);
        let column = &self.columns[k * n..(k + 1) * n];
        let h = K::pair_factor;
        if K::HAS_SINGLE {
            let g = K::single_factor;
            let singles = &mut self.singles[f];
            singles[i] *= g(xj) / g(xi);
            singles[j] *= g(xi) / g(xj);
        }
        let rows = &mut self.rows[f];
        let (hii, hjj) = (h(xi, xi), h(xj, xj));
        for (t, &m) in self.members.iter().enumerate() {
            if m == i || m == j {
                continue;
            }
            let xm = column[m];
            let (hi, hj) = (h(xi, xm), h(xj, xm));
            rows[t * n + i] *= hj / hi;
            rows[t * n + j] *= hi / hj;
        }
        let (lo, hi_rows) = rows.split_at_mut(ti.max(tj) * n);
        let (row_a, row_b) = (
            &mut lo[ti.min(tj) * n..(ti.min(tj) + 1) * n],
            &mut hi_rows[..n],
        );
        let (ri, rj) = if ti < tj {
            (row_a, row_b)
        } else {
            (row_b, row_a)
        };
        // The pair (i, j) keeps its product (h is symmetric) and the diagonal takes
        // h(x, x) factors: the loop below would rescale them like the others.
        let (pij, pii, pjj) = (ri[j], ri[i], rj[j]);
        ri.par_chunks_mut(CHUNK)
            .zip(rj.par_chunks_mut(CHUNK))
            .zip(column.par_chunks(CHUNK))
            .for_each(|((a, b), c)| {
                for ((p, q), &xl) in a.iter_mut().zip(b.iter_mut()).zip(c) {
                    let (hi, hj) = (h(xi, xl), h(xj, xl));
                    *p *= hj / hi;
                    *q *= hi / hj;
                }
            });
        (ri[j], rj[i]) = (pij, pij);
        ri[i] = pii * (hjj / hii);
        rj[j] = pjj * (hii / hjj);
    }

    fn points(&self) -> PointSet {
        PointSet::new(self.n, self.s, self.x.clone()).expect("same shape as the start")
    }
}

/// The single products Π_k g(x_ik) of the n points `x` (rows of s), 0 for a kernel
/// without the single sum.
fn singles<K: DiscrepancyKernel>(x: &[f64], n: usize, s: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            if K::HAS_SINGLE {
                x[i * s..(i + 1) * s]
                    .iter()
                    .map(|&v| K::single_factor(v))
                    .product()
            } else {
                0.0
            }
        })
        .collect()
}

/// One row of pair products Π_k h(x_k, c_kl) over the points l, coordinate by coordinate
/// (the kernel known at compile time, so the loops vectorise).
fn fill_row<K: DiscrepancyKernel>(xi: &[f64], columns: &[f64], row: &mut [f64]) {
    let n = row.len();
    row.fill(1.0);
    for (k, &v) in xi.iter().enumerate() {
        for (p, &c) in row.iter_mut().zip(&columns[k * n..(k + 1) * n]) {
            *p *= K::pair_factor(v, c);
        }
    }
}

/// Swaps between points of blocks, each accepted only when it lowers every one of
/// `kinds` beyond rounding, until `work` (products of one pair factor) is spent or a stop
/// is requested. `points` must lie in [0, 1)^s (where every h is positive). Deterministic
/// for a seed, whatever the thread count.
pub fn block_exchanges(
    points: &PointSet,
    kinds: &[DiscrepancyKind],
    work: u64,
    seed: u64,
) -> (PointSet, BlockOutcome) {
    let (n, s) = (points.n(), points.s());
    let per_row = (n * kinds.len().max(1) * 8) as u64;
    let b = ((BLOCK_BYTES as u64 / per_row) as usize)
        .clamp(2, BLOCK_MAX)
        .min(n);
    let mut outcome = BlockOutcome {
        block: b,
        blocks: 0,
        proposals: 0,
        accepted: 0,
        changes: vec![0.0; kinds.len()],
        work: 0,
    };
    if n < 2 || s == 0 || kinds.is_empty() {
        return (points.clone(), outcome);
    }
    let mut state = Blocks::new(points, kinds);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x426c_6f63_6b73);
    let (load_cost, proposal_cost) = (
        (b * n * s * kinds.len()) as u64,
        (2 * n * kinds.len()) as u64,
    );
    let form_cost = 2 * n as u64;
    let mut refusals = vec![0usize; kinds.len()];
    while outcome.work + load_cost + proposal_cost <= work {
        if stillpoint_solve::cancelled() {
            break;
        }
        state.load(&rand::seq::index::sample(&mut rng, n, b).into_vec());
        outcome.blocks += 1;
        outcome.work += load_cost;
        for _ in 0..PROPOSALS_PER_POINT * b {
            // A stop request is seen within a few dozen proposals (each O(n)).
            if outcome.work + proposal_cost > work
                || (outcome.proposals.is_multiple_of(64) && stillpoint_solve::cancelled())
            {
                break;
            }
            let k = rng.random_range(0..s);
            let (a, c) = (rng.random_range(0..b), rng.random_range(0..b));
            let (i, j) = (state.members[a], state.members[c]);
            if i == j || state.x[i * s + k] == state.x[j * s + k] {
                continue;
            }
            outcome.proposals += 1;
            // Every form must fall: the one that refused most often so far is asked
            // first, and a refusal ends the proposal (most are refused, most by one form).
            let mut order: Vec<usize> = (0..kinds.len()).collect();
            order.sort_by_key(|&f| std::cmp::Reverse(refusals[f]));
            let mut deltas = vec![0.0; kinds.len()];
            let mut refused = false;
            for &f in &order {
                outcome.work += form_cost;
                let (d, bound) = state.delta(f, i, j, k);
                if d >= -bound {
                    refusals[f] += 1;
                    refused = true;
                    break;
                }
                deltas[f] = d;
            }
            if !refused {
                state.swap(i, j, k);
                for (total, d) in outcome.changes.iter_mut().zip(&deltas) {
                    *total += d;
                }
                outcome.accepted += 1;
                outcome.work += proposal_cost;
            }
        }
    }
    (state.points(), outcome)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::goals::integration::exchange::squared;
    use crate::goals::integration::stratify;

    fn start(n: usize, s: usize) -> PointSet {
        stratify(&stillpoint_sequences::sobol_scrambled(n, s, 3).unwrap())
    }

    #[test]
    fn the_stated_changes_are_the_recomputed_ones_and_every_kind_falls() {
        use DiscrepancyKind::*;
        let kinds = [ModifiedL2, StarL2, CenteredL2];
        let squared = |p: &PointSet, kind| with_kernel!(kind, K => squared::<K>(p));
        for (n, s) in [(300, 3), (257, 6)] {
            let p = start(n, s);
            let (q, o) = block_exchanges(&p, &kinds, 2_000_000_000, 7);
            assert!(o.accepted > 0, "n = {n}: {o:?}");
            assert!(stillpoint_quality::stratification::is_stratified(&q));
            for (f, &kind) in kinds.iter().enumerate() {
                let (before, after) = (squared(&p, kind), squared(&q, kind));
                assert!(after < before, "{kind:?}: {after} vs {before}");
                let change = after - before;
                assert!(
                    (change - o.changes[f]).abs() <= 1e-9 * change.abs(),
                    "{kind:?}: recomputed {change:e}, stated {:e}",
                    o.changes[f]
                );
            }
        }
    }

    #[test]
    fn the_same_bits_for_any_thread_count_and_the_work_cap_holds() {
        let p = start(9000, 2);
        let kinds = [DiscrepancyKind::ModifiedL2, DiscrepancyKind::CenteredL2];
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| block_exchanges(&p, &kinds, 400_000_000, 11))
        };
        let (a, oa) = run(1);
        let (b, ob) = run(3);
        assert_eq!(a.as_slice(), b.as_slice());
        assert_eq!(oa, ob);
        assert!(oa.work <= 400_000_000 && oa.blocks > 0);
    }
}
