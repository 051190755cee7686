//! The smallest pairwise distances of a large set without visiting every pair: a grid of
//! cells over the first coordinates, each point compared with the points of its own and
//! the adjacent cells only. Exact whenever the smallest distance found is below the cell
//! side (a closer pair could only lie in adjacent cells); otherwise it says it cannot tell.

use crate::PointSet;
use rayon::prelude::*;

/// The most points a point is compared with on average (3^k cells of n/m^k points each);
/// beyond it the grid saves too little over the pair loop to be worth it.
const MAX_NEIGHBOURS: f64 = 600.0;

/// How many coordinates past the gridded ones are copied in cell order (the rest of a
/// point is read where it lies, for the few pairs still close after them).
const HEAD_PAST_GRID: usize = 4;

/// The grid: `k` coordinates cut into `m` cells each.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Grid {
    k: usize,
    m: usize,
}

impl Grid {
    /// The grid with about one point per cell over the most coordinates that compares
    /// each point with at most [`MAX_NEIGHBOURS`] others on average: more coordinates
    /// make wider cells, and only a closest pair nearer than a cell's side is proven.
    fn choose(n: usize, s: usize) -> Option<Grid> {
        (1..=s.min(12))
            .rev()
            .filter_map(|k| {
                let m = ((n as f64).powf(1.0 / k as f64).floor() as usize).min(1 << 16);
                // Fewer than 3 cells a side make every cell adjacent to every other.
                (m >= 3).then_some(Grid { k, m })
            })
            .find(|g| {
                let cells = (g.m as f64).powi(g.k as i32);
                3f64.powi(g.k as i32) * (n as f64 / cells).max(1.0) <= MAX_NEIGHBOURS
            })
    }

    fn cell_of(&self, x: &[f64]) -> Vec<usize> {
        x[..self.k]
            .iter()
            .map(|&v| ((v * self.m as f64).floor().max(0.0) as usize).min(self.m - 1))
            .collect()
    }

    fn index(&self, c: &[usize]) -> usize {
        c.iter().fold(0, |a, &v| a * self.m + v)
    }
}

/// The side of the cells of the grid [`min_squared_distances_by_cells`] lays over n
/// points in s coordinates (it proves a closest pair only when it is nearer than this);
/// `None` where no grid fits.
pub fn grid_side(n: usize, s: usize) -> Option<f64> {
    Grid::choose(n, s).map(|g| 1.0 / g.m as f64)
}

/// The squared distances of a pair as the pair loop of
/// [`stillpoint_energies::pairs::min_squared_distances`] forms them (same operations, same
/// order, so the same bits): Euclidean and on the torus; `None` as soon as the torus
/// distance so far reaches `limit`.
///
/// Why stop early. Only a pair closer than a cell's side can be proven the closest, and
/// in many dimensions almost every neighbour is farther: its first few coordinates say
/// so, and the rest would cost s − k more. A partial sum of non-negative terms never
/// decreases as terms are added (in floating point too), and the Euclidean sum is never
/// below the torus sum, so a pair stopped here is at least `limit` apart both ways.
///
/// Each point comes in two parts, its first coordinates and the rest, read in that order.
fn squared_pair(x: [&[f64]; 2], y: [&[f64]; 2], limit: f64) -> Option<[f64; 2]> {
    let (mut de, mut dp) = (0.0, 0.0);
    for (xs, ys) in x.iter().zip(y) {
        for (&a, &b) in xs.iter().zip(ys) {
            let d = (a - b).abs();
            de += d * d;
            let w = if d > 0.5 { 1.0 - d } else { d };
            dp += w * w;
            if dp >= limit {
                return None;
            }
        }
    }
    Some([de, dp])
}

/// The smallest squared Euclidean and torus distances, each `Some` only where the grid
/// proves it exact (the same bits as the pair loop's), `None` where the closest pair may
/// lie beyond adjacent cells or no grid fits the set. +∞ for fewer than two points.
pub fn min_squared_distances_by_cells(points: &PointSet) -> [Option<f64>; 2] {
    let (n, s) = (points.n(), points.s());
    if n < 2 {
        return [Some(f64::INFINITY); 2];
    }
    let Some(grid) = Grid::choose(n, s) else {
        return [None, None];
    };
    let cells: Vec<usize> = points
        .rows()
        .map(|x| grid.index(&grid.cell_of(x)))
        .collect();
    let count = grid.m.pow(grid.k as u32);
    // Counting sort: the points of cell c are order[start[c]..start[c + 1]].
    let mut start = vec![0usize; count + 1];
    for &c in &cells {
        start[c + 1] += 1;
    }
    for c in 0..count {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut order = vec![0usize; n];
    for (i, &c) in cells.iter().enumerate() {
        order[fill[c]] = i;
        fill[c] += 1;
    }
    let offsets: Vec<Vec<i64>> = (0..3usize.pow(grid.k as u32))
        .map(|mut o| {
            (0..grid.k)
                .map(|_| {
                    let d = (o % 3) as i64 - 1;
                    o /= 3;
                    d
                })
                .rev()
                .collect()
        })
        .collect();
    // The first coordinates in cell order, so that a cell's points, and the cells that
    // differ in the last gridded coordinate, lie together in memory. Almost every pair is
    // stopped within them (the gridded ones are what neighbours share, and one more
    // coordinate a third apart on average is past the side), so the rest is read where
    // it lies, and the copy is a fraction of the set.
    let rows = points.as_slice();
    let head = s.min(grid.k + HEAD_PAST_GRID);
    let sorted: Vec<f64> = order
        .iter()
        .flat_map(|&i| rows[i * s..i * s + head].iter().copied())
        .collect();
    let parts = |a: usize| {
        let i = order[a];
        [
            &sorted[a * head..(a + 1) * head],
            &rows[i * s + head..(i + 1) * s],
        ]
    };
    let m = grid.m as i64;
    let steps: Vec<i64> = offsets
        .iter()
        .map(|off| off.iter().fold(0, |a, &d| a * m + d))
        .collect();
    // A pair this far apart cannot be proven the closest (its root is at least the cell's
    // side, above `side` below), so its distance need not be finished.
    let limit = (1.0 / grid.m as f64).powi(2);
    let best = (0..count)
        .into_par_iter()
        .filter(|&cell| start[cell] < start[cell + 1])
        .map(|cell| {
            if stillpoint_energies::stop::requested() {
                // Ctrl-C in Python: the caller discards this minimum.
                return [f64::INFINITY; 2];
            }
            let mut home = vec![0usize; grid.k];
            let mut rest = cell;
            for h in home.iter_mut().rev() {
                *h = rest % grid.m;
                rest /= grid.m;
            }
            let mut best = [f64::INFINITY; 2];
            let mut visit = |other: usize, inside: bool| {
                for a in start[cell]..start[cell + 1] {
                    let x = parts(a);
                    let from = if other == cell { a + 1 } else { start[other] };
                    for b in from..start[other + 1] {
                        let Some([de, dp]) = squared_pair(x, parts(b), limit) else {
                            continue;
                        };
                        if inside {
                            best[0] = best[0].min(de);
                        }
                        best[1] = best[1].min(dp);
                    }
                }
            };
            if home.iter().all(|&h| h >= 1 && h + 1 < grid.m) {
                // No neighbour wraps: each is the cell's index plus its offset's step,
                // and the later ones are those with a step of at least 0.
                for &step in steps.iter().filter(|&&step| step >= 0) {
                    visit(cell + step as usize, true);
                }
                return best;
            }
            let mut c = vec![0usize; grid.k];
            for off in &offsets {
                // Euclidean pairs need the cell inside the cube; the torus wraps around.
                let mut inside = true;
                for ((ci, &h), &d) in c.iter_mut().zip(&home).zip(off) {
                    let v = h as i64 + d;
                    inside &= (0..m).contains(&v);
                    // One cell across the wrap at most: no division.
                    *ci = if v < 0 {
                        v + m
                    } else if v >= m {
                        v - m
                    } else {
                        v
                    } as usize;
                }
                // Each pair of cells once, from the lower index (adjacency is symmetric,
                // and so is whether it wraps).
                let other = grid.index(&c);
                if other < cell {
                    continue;
                }
                visit(other, inside);
            }
            best
        })
        .reduce(
            || [f64::INFINITY; 2],
            |a, b| [a[0].min(b[0]), a[1].min(b[1])],
        );
    // A pair closer than the side has each gridded coordinate less than a side apart, so
    // its cells are adjacent; the margin covers the rounding of x·m.
    let side = (1.0 - 1e-9) / grid.m as f64;
    let proven = |d2: f64| (d2.sqrt() < side).then_some(d2);
    [proven(best[0]), proven(best[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_finds_the_same_bits_as_the_pair_loop() {
        for (n, s, seed) in [(3000, 2, 1), (5000, 3, 2), (20_000, 5, 3)] {
            let p = stillpoint_sequences::random(n, s, seed).unwrap();
            let exact =
                stillpoint_energies::pairs::min_squared_distances(p.as_slice(), p.n(), p.s());
            let grid = min_squared_distances_by_cells(&p);
            for (g, e) in grid.iter().zip(exact) {
                assert_eq!(g.map(f64::to_bits), Some(e.to_bits()), "n = {n}, s = {s}");
            }
        }
    }

    #[test]
    fn in_many_dimensions_the_grid_still_finds_the_pair_loops_bits() {
        // Most neighbours are stopped after a few coordinates; a close pair planted in
        // the set (and one across the torus's wrap) must still come out to the bit.
        for (n, s, seed) in [(4000usize, 16usize, 4u64), (6000, 24, 5)] {
            let mut p = stillpoint_sequences::random(n, s, seed).unwrap();
            let near: Vec<f64> = p.point(7).iter().map(|v| (v + 1e-3).min(0.999)).collect();
            p.point_mut(8).copy_from_slice(&near);
            let mut wrapped: Vec<f64> = p.point(20).to_vec();
            wrapped[s - 1] = 0.0004;
            p.point_mut(20).copy_from_slice(&wrapped);
            wrapped[s - 1] = 0.9997;
            p.point_mut(21).copy_from_slice(&wrapped);
            let exact =
                stillpoint_energies::pairs::min_squared_distances(p.as_slice(), p.n(), p.s());
            let grid = min_squared_distances_by_cells(&p);
            for (g, e) in grid.iter().zip(exact) {
                assert_eq!(g.map(f64::to_bits), Some(e.to_bits()), "n = {n}, s = {s}");
            }
        }
    }

    #[test]
    fn the_grid_declines_when_it_cannot_prove_the_minimum() {
        // Four points a quarter apart, also across the wrap: no distance is below the side.
        let p = PointSet::new(4, 1, vec![0.1, 0.35, 0.6, 0.85]).unwrap();
        assert_eq!(min_squared_distances_by_cells(&p), [None, None]);
    }
}
