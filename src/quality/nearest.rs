//! The smallest pairwise distances of a large set without visiting every pair: a grid of
//! cells over the first coordinates, each point compared with the points of its own and
//! the adjacent cells only. Exact whenever the smallest distance found is below the cell
//! side (a closer pair could only lie in adjacent cells); otherwise it says it cannot tell.

use crate::PointSet;
use rayon::prelude::*;

/// The most points a point is compared with on average (3^k cells of n/m^k points each);
/// beyond it the grid saves too little over the pair loop to be worth it.
const MAX_NEIGHBOURS: f64 = 600.0;

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

/// The squared distances of a pair as the pair loop of
/// [`crate::energies::pairs::min_squared_distances`] forms them (same operations, same
/// order, so the same bits): Euclidean and on the torus.
fn squared_pair(x: &[f64], y: &[f64]) -> [f64; 2] {
    let (mut de, mut dp) = (0.0, 0.0);
    for (&a, &b) in x.iter().zip(y) {
        let d = (a - b).abs();
        de += d * d;
        let w = if d > 0.5 { 1.0 - d } else { d };
        dp += w * w;
    }
    [de, dp]
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
    // The coordinates in cell order, so that a cell's points, and the cells that differ
    // in the last gridded coordinate, lie together in memory.
    let rows = points.as_slice();
    let sorted: Vec<f64> = order
        .iter()
        .flat_map(|&i| rows[i * s..(i + 1) * s].iter().copied())
        .collect();
    let m = grid.m as i64;
    let best = (0..count)
        .into_par_iter()
        .filter(|&cell| start[cell] < start[cell + 1])
        .map(|cell| {
            if crate::energies::stop::requested() {
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
            let mut c = vec![0usize; grid.k];
            for off in &offsets {
                // Euclidean pairs need the cell inside the cube; the torus wraps around.
                let mut inside = true;
                for ((ci, &h), &d) in c.iter_mut().zip(&home).zip(off) {
                    let v = h as i64 + d;
                    inside &= (0..m).contains(&v);
                    *ci = v.rem_euclid(m) as usize;
                }
                // Each pair of cells once, from the lower index (adjacency is symmetric,
                // and so is whether it wraps).
                let other = grid.index(&c);
                if other < cell {
                    continue;
                }
                for a in start[cell]..start[cell + 1] {
                    let x = &sorted[a * s..(a + 1) * s];
                    let from = if other == cell { a + 1 } else { start[other] };
                    for b in from..start[other + 1] {
                        let [de, dp] = squared_pair(x, &sorted[b * s..(b + 1) * s]);
                        if inside {
                            best[0] = best[0].min(de);
                        }
                        best[1] = best[1].min(dp);
                    }
                }
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
            let p = crate::sequences::random(n, s, seed).unwrap();
            let exact = crate::energies::pairs::min_squared_distances(p.as_slice(), p.n(), p.s());
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
