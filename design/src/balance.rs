//! Turning a stratified unit-cube set into a mixed design without losing its balance:
//!
//! - levels dealt by rank, so a variable with L levels shows each ⌊n/L⌋ or ⌈n/L⌉ times
//!   and an ordered or integer variable keeps the order of its coordinate;
//! - unordered factors' labels swapped (each factor's counts unchanged) until the
//!   level-pair counts of every two factors are as even as the search reaches;
//! - every continuous coordinate re-dealt over its n cells so that, within each level
//!   of each unordered factor, the points fall one per 1/m-th of [0, 1) (a sliced Latin
//!   hypercube when m = n/L is whole), moving each point as little as that allows.

use super::slices::{SliceCounts, Slices};
use super::DesignSpace;
use crate::PointSet;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::collections::BTreeSet;

/// Proposals per point and factor of the pair-balancing search: enough that the
/// benchmarked spaces reach their best counts, cheap next to the run that made the set.
const SWAPS_PER_POINT: usize = 200;

/// The unit-scale design and each discrete variable's level indices (see the module).
/// Then the continuous part goes through slice-keeping exchanges as `finish` says.
pub fn arrange(
    space: &DesignSpace,
    base: &PointSet,
    seed: u64,
    finish: Finish,
) -> (PointSet, Vec<Vec<usize>>) {
    let (n, s) = (base.n(), base.s());
    let column = |j: usize| -> Vec<f64> { (0..n).map(|i| base.point(i)[j]).collect() };
    let mut levels: Vec<Vec<usize>> = space
        .vars
        .iter()
        .enumerate()
        .map(|(j, v)| match v.kind.levels() {
            Some(l) => by_rank(&column(j), l),
            None => Vec::new(),
        })
        .collect();
    let factors: Vec<usize> = (0..s)
        .filter(|&j| space.vars[j].kind.is_categorical())
        .collect();
    let sizes: Vec<usize> = factors
        .iter()
        .map(|&j| space.vars[j].kind.levels().unwrap_or(1))
        .collect();
    if factors.len() > 1 {
        let mut labels: Vec<Vec<usize>> = factors.iter().map(|&j| levels[j].clone()).collect();
        balance_pairs(&mut labels, &sizes, seed);
        for (k, &j) in factors.iter().enumerate() {
            levels[j] = std::mem::take(&mut labels[k]);
        }
    }
    let mut unit = base.clone();
    let slices: Vec<(&[usize], usize)> = factors
        .iter()
        .zip(&sizes)
        .map(|(&j, &l)| (levels[j].as_slice(), l))
        .collect();
    for (j, var) in space.vars.iter().enumerate() {
        match &var.kind {
            kind if kind.is_continuous() && !slices.is_empty() => {
                let dealt = slice_column(&column(j), &slices);
                for (i, v) in dealt.into_iter().enumerate() {
                    unit.point_mut(i)[j] = v;
                }
            }
            kind if kind.is_continuous() => {}
            kind => {
                let l = kind.levels().unwrap_or(1) as f64;
                for (i, &k) in levels[j].iter().enumerate() {
                    unit.point_mut(i)[j] = (k as f64 + 0.5) / l;
                }
            }
        }
    }
    match finish {
        Finish::Discrepancy if !slices.is_empty() => {
            polish_continuous(space, &mut unit, &slices, seed)
        }
        Finish::Spread => spread_continuous(space, &mut unit, &levels, &slices, seed),
        _ => {}
    }
    (unit, levels)
}

/// What the dealing does last, after the levels and slices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Finish {
    /// Nothing: the set as dealt (a baseline's, say).
    Nothing,
    /// Lower the continuous part's discrepancy (a set made for integration).
    Discrepancy,
    /// Widen the smallest type-aware distances (a space-filling set).
    Spread,
}

/// The continuous part of `unit` as an n × k row-major block, and the columns it came
/// from.
fn continuous_block(space: &DesignSpace, unit: &PointSet) -> (Vec<f64>, Vec<usize>) {
    let cont = space.continuous();
    let data = (0..unit.n())
        .flat_map(|i| cont.iter().map(move |&j| (i, j)))
        .map(|(i, j)| unit.point(i)[j])
        .collect();
    (data, cont)
}

/// Slice-keeping exchanges on the Morris–Mitchell sum of the type-aware distance of
/// [`crate::figures::DesignFigures::min_distance`].
fn spread_continuous(
    space: &DesignSpace,
    unit: &mut PointSet,
    levels: &[Vec<usize>],
    slices: &[(&[usize], usize)],
    seed: u64,
) {
    let n = unit.n();
    let (mut data, cont) = continuous_block(space, unit);
    if cont.is_empty() || !(3..=POLISH_MAX_N).contains(&n) {
        return;
    }
    let discrete = super::figures::DiscreteDistance::new(space, levels);
    let extra = |a: usize, b: usize| discrete.squared(a, b);
    let objective = super::exchange::Objective::Spread { extra: &extra };
    super::exchange::exchange(&mut data, cont.len(), slices, &objective, seed);
    put_continuous(unit, &cont, &data);
}

/// Iterations of the in-cell descent after the dealing: enough to take back most of the
/// discrepancy the moves between cells cost.
const POLISH_STEPS: usize = 60;

/// The largest design whose continuous part is polished (the descent's pair sums are
/// O(n²) per iteration).
const POLISH_MAX_N: usize = 4096;

/// L-BFGS on the offsets of the continuous part within its cells (every cell, hence
/// every slice's stratification, is kept), lowering the discrepancy that re-dealing the
/// cells raised.
fn polish_continuous(
    space: &DesignSpace,
    unit: &mut PointSet,
    slices: &[(&[usize], usize)],
    seed: u64,
) {
    let n = unit.n();
    let (mut data, cont) = continuous_block(space, unit);
    if cont.is_empty() || !(2..=POLISH_MAX_N).contains(&n) {
        return;
    }
    super::exchange::exchange(
        &mut data,
        cont.len(),
        slices,
        &super::exchange::Objective::CenteredL2,
        seed,
    );
    let Ok(part) = PointSet::new(n, cont.len(), data) else {
        return;
    };
    let target = stillpoint_quality::target::Target::default_for(n, cont.len());
    let lbfgs = stillpoint_integrators::lbfgs::Lbfgs::default();
    let better = stillpoint_solve::cells::descend_in_cells(&part, &target, POLISH_STEPS, &lbfgs)
        .unwrap_or(part);
    put_continuous(unit, &cont, better.as_slice());
}

/// Writes an n × k block back into the continuous columns `cont` of `unit`.
fn put_continuous(unit: &mut PointSet, cont: &[usize], data: &[f64]) {
    for i in 0..unit.n() {
        for (k, &j) in cont.iter().enumerate() {
            unit.point_mut(i)[j] = data[i * cont.len() + k];
        }
    }
}

/// Level `⌊r·L/n⌋` for the point of rank r: every level ⌊n/L⌋ or ⌈n/L⌉ times, in the
/// coordinate's order (ties broken by index, so the result is the same on every run).
pub fn by_rank(values: &[f64], l: usize) -> Vec<usize> {
    let n = values.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    let mut level = vec![0; n];
    for (r, &i) in order.iter().enumerate() {
        level[i] = r * l / n;
    }
    level
}

/// The sum over every two factors of the squared distance of each level pair's count
/// from n/(L_a L_b): zero exactly when every pair is equally frequent.
pub fn pair_imbalance(labels: &[Vec<usize>], sizes: &[usize]) -> f64 {
    let n = labels.first().map_or(0, |l| l.len());
    let mut total = 0.0;
    for a in 0..labels.len() {
        for b in a + 1..labels.len() {
            let ideal = n as f64 / (sizes[a] * sizes[b]) as f64;
            let mut counts = vec![0usize; sizes[a] * sizes[b]];
            for i in 0..n {
                counts[labels[a][i] * sizes[b] + labels[b][i]] += 1;
            }
            total += counts
                .iter()
                .map(|&c| (c as f64 - ideal).powi(2))
                .sum::<f64>();
        }
    }
    total
}

/// Random swaps of two points' labels within one factor (so every factor's own counts
/// stay as dealt), kept when they lower [`pair_imbalance`]; the change of a swap is read
/// off the pair-count tables in O(factors).
fn balance_pairs(labels: &mut [Vec<usize>], sizes: &[usize], seed: u64) {
    let f = labels.len();
    let n = labels[0].len();
    if n < 2 {
        return;
    }
    let mut counts: Vec<Vec<Vec<i64>>> = vec![vec![Vec::new(); f]; f];
    for a in 0..f {
        for b in 0..f {
            if a != b {
                let mut c = vec![0i64; sizes[a] * sizes[b]];
                for i in 0..n {
                    c[labels[a][i] * sizes[b] + labels[b][i]] += 1;
                }
                counts[a][b] = c;
            }
        }
    }
    let ideal = |a: usize, b: usize| n as f64 / (sizes[a] * sizes[b]) as f64;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x5ca1_ab1e_0dd5_eed5);
    let budget = SWAPS_PER_POINT * n * f;
    for _ in 0..budget {
        let a = rng.random_range(0..f);
        let (p, q) = (rng.random_range(0..n), rng.random_range(0..n));
        let (lp, lq) = (labels[a][p], labels[a][q]);
        if lp == lq {
            continue;
        }
        // Moving p from level lp to lq and q from lq to lp changes, for every other
        // factor b, four cells of the (a, b) table by ±1.
        let mut delta = 0.0;
        for b in (0..f).filter(|&b| b != a) {
            let (bp, bq) = (labels[b][p], labels[b][q]);
            if bp == bq {
                continue;
            }
            let t = &counts[a][b];
            let w = ideal(a, b);
            let cell = |l: usize, m: usize| t[l * sizes[b] + m] as f64 - w;
            // Cells (lp,bp) and (lq,bq) lose one, (lq,bp) and (lp,bq) gain one.
            let (x1, x2, x3, x4) = (cell(lp, bp), cell(lq, bq), cell(lq, bp), cell(lp, bq));
            delta += (-2.0 * x1 + 1.0) + (-2.0 * x2 + 1.0) + (2.0 * x3 + 1.0) + (2.0 * x4 + 1.0);
        }
        if delta < -1e-9 {
            for b in (0..f).filter(|&b| b != a) {
                let (bp, bq) = (labels[b][p], labels[b][q]);
                let sb = sizes[b];
                let sa = sizes[a];
                counts[a][b][lp * sb + bp] -= 1;
                counts[a][b][lq * sb + bq] -= 1;
                counts[a][b][lq * sb + bp] += 1;
                counts[a][b][lp * sb + bq] += 1;
                counts[b][a][bp * sa + lp] -= 1;
                counts[b][a][bq * sa + lq] -= 1;
                counts[b][a][bp * sa + lq] += 1;
                counts[b][a][bq * sa + lp] += 1;
            }
            labels[a].swap(p, q);
        }
    }
}

/// One continuous coordinate re-dealt over its n cells [c/n, (c+1)/n): a point of rank
/// k among the m points of its slice asks for a cell in [k/m, (k+1)/m) (the cells that
/// overlap it), for every factor at once where the asks meet, else for the factor with
/// the most levels. Asks are served earliest end first with the lowest free cell, which
/// serves every ask whenever they can all be served; within a shared end the points
/// keep their order. A point keeps its place inside its cell.
pub fn slice_column(values: &[f64], slices: &[(&[usize], usize)]) -> Vec<f64> {
    let n = values.len();
    let nf = n as f64;
    let mut asks: Vec<(usize, usize)> = vec![(0, n - 1); n];
    let finest = (0..slices.len()).max_by_key(|&k| slices[k].1).unwrap_or(0);
    let mut own: Vec<(usize, usize)> = vec![(0, n - 1); n];
    for (k, &(labels, l)) in slices.iter().enumerate() {
        for level in 0..l {
            let mut members: Vec<usize> = (0..n).filter(|&i| labels[i] == level).collect();
            members.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
            let m = members.len();
            for (r, &i) in members.iter().enumerate() {
                let lo = (r * n) / m;
                let hi = ((r + 1) * n).div_ceil(m) - 1;
                let (a, b) = asks[i];
                asks[i] = (a.max(lo), b.min(hi));
                if k == finest {
                    own[i] = (lo, hi);
                }
            }
        }
    }
    for i in 0..n {
        if asks[i].0 > asks[i].1 {
            asks[i] = own[i];
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| {
        asks[a]
            .1
            .cmp(&asks[b].1)
            .then(values[a].total_cmp(&values[b]))
            .then(a.cmp(&b))
    });
    let mut free: BTreeSet<usize> = (0..n).collect();
    let mut cell = vec![0usize; n];
    for &i in &order {
        let (lo, hi) = asks[i];
        cell[i] = match free.range(lo..).next() {
            Some(&c) if c <= hi => c,
            // An ask no cell can serve any more takes the nearest free cell.
            _ => {
                let above = free.range(lo..).next().copied();
                let below = free.range(..lo).next_back().copied();
                match (below, above) {
                    (Some(b), Some(a)) if lo - b <= a.saturating_sub(hi) => b,
                    (Some(b), None) => b,
                    (_, Some(a)) => a,
                    (None, None) => unreachable!("as many cells as points"),
                }
            }
        };
        free.remove(&cell[i]);
    }
    if slices.len() > 1 {
        untangle(&mut cell, values, slices, seed_of(values));
    }
    let mut out = vec![0.0; n];
    for i in 0..n {
        let place = (values[i] * nf).fract().clamp(0.0, 1.0 - f64::EPSILON);
        out[i] = ((cell[i] as f64 + place) / nf).min(1.0 - f64::EPSILON / 2.0);
    }
    out
}

/// A seed for [`untangle`] from the column itself, so that the dealing is a function
/// of the set (same set, same design).
fn seed_of(values: &[f64]) -> u64 {
    values.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    })
}

/// Proposals per point of [`untangle`]'s search.
const UNTANGLE_PER_POINT: usize = 400;

/// With several factors the asks of one cannot always be met with the others'; this
/// search swaps the cells of two nearby points (each column stays one point per cell)
/// when that lowers the number of points sharing a 1/m-th of [0, 1) with another point
/// of their slice, summed over every factor, so that a design of nested or balanced
/// factors is stratified within every slice of every factor where such a dealing exists.
fn untangle(cell: &mut [usize], values: &[f64], slices: &Slices<'_>, seed: u64) {
    let n = cell.len();
    let mut counts = SliceCounts::new(slices, n, |i| cell[i]);
    let mut at = vec![0usize; n];
    for i in 0..n {
        at[cell[i]] = i;
    }
    let reach = (2 * slices.iter().map(|s| s.1).product::<usize>()).min(n);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    // Two phases: first any swap that does not add to the crowding (a walk over the
    // plateaus toward none), then only swaps that keep the crowding and bring the
    // points back toward where the set had them.
    let home: Vec<f64> = values.iter().map(|v| v * n as f64).collect();
    let away = |i: usize, c: usize| (c as f64 + 0.5 - home[i]).powi(2);
    for phase in 0..2 {
        for _ in 0..UNTANGLE_PER_POINT * n {
            let p = rng.random_range(0..n);
            if phase == 0 && !counts.crowded(p, cell[p]) {
                continue;
            }
            let lo = cell[p].saturating_sub(reach);
            let hi = (cell[p] + reach).min(n - 1);
            let q = at[rng.random_range(lo..=hi)];
            if q == p {
                continue;
            }
            let (cp, cq) = (cell[p], cell[q]);
            let closer = away(p, cq) + away(q, cp) < away(p, cp) + away(q, cq);
            // Excess over one per block, before and after the swap, for the blocks
            // touched.
            let mut delta: i64 = 0;
            for f in 0..counts.factors() {
                delta += counts.shift(f, p, cp, cq);
                delta += counts.shift(f, q, cq, cp);
            }
            let take = if phase == 0 {
                delta <= 0
            } else {
                delta < 0 || (delta == 0 && closer)
            };
            if take {
                cell.swap(p, q);
                at[cp] = q;
                at[cq] = p;
                continue;
            }
            for f in 0..counts.factors() {
                counts.shift(f, q, cp, cq);
                counts.shift(f, p, cq, cp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_deal_every_level_floor_or_ceil_times() {
        for (n, l) in [(10, 3), (7, 7), (100, 6), (5, 9)] {
            let values: Vec<f64> = (0..n).map(|i| ((i * 37) % n) as f64 / n as f64).collect();
            let level = by_rank(&values, l);
            for k in 0..l {
                let c = level.iter().filter(|&&x| x == k).count();
                assert!(
                    c == n / l || c == n.div_ceil(l),
                    "n {n} L {l} level {k}: {c}"
                );
            }
        }
    }

    #[test]
    fn a_sliced_column_is_stratified_overall_and_per_slice_when_m_divides() {
        let n = 24;
        let values: Vec<f64> = (0..n)
            .map(|i| (((i * 7) % n) as f64 + 0.3) / n as f64)
            .collect();
        let labels: Vec<usize> = (0..n).map(|i| (i * 5) % 3).collect();
        let out = slice_column(&values, &[(&labels, 3)]);
        let mut cells: Vec<usize> = out.iter().map(|v| (v * n as f64) as usize).collect();
        cells.sort();
        assert_eq!(cells, (0..n).collect::<Vec<_>>());
        for level in 0..3 {
            let mut blocks: Vec<usize> = (0..n)
                .filter(|&i| labels[i] == level)
                .map(|i| (out[i] * 8.0) as usize)
                .collect();
            blocks.sort();
            assert_eq!(blocks, (0..8).collect::<Vec<_>>());
        }
    }

    #[test]
    fn pair_swaps_reach_an_orthogonal_array_when_one_exists() {
        // 2 × 3 × 4 factors on 24 points: the full factorial is the balanced answer.
        let n = 24;
        let sizes = [2, 3, 4];
        let mut labels: Vec<Vec<usize>> = sizes
            .iter()
            .map(|&l| (0..n).map(|i| i * l / n).collect())
            .collect();
        let before = pair_imbalance(&labels, &sizes);
        balance_pairs(&mut labels, &sizes, 1);
        assert!(before > 1.0);
        assert!(pair_imbalance(&labels, &sizes) < 1e-9);
        for (k, &l) in sizes.iter().enumerate() {
            for level in 0..l {
                assert_eq!(labels[k].iter().filter(|&&x| x == level).count(), n / l);
            }
        }
    }
}
