//! A deterministic parallel loop over unordered pairs, for energies whose gradient is a
//! sum of pair forces.
//!
//! The points are cut into a fixed number of blocks (independent of the thread count),
//! and the block pairs are scheduled in rounds by the circle method so that the tiles of
//! one round touch disjoint gradient rows. Tiles of a round run in parallel; rounds run
//! in order. Every row therefore receives its contributions in the same order whatever
//! the number of threads, and each pair is visited once (half the work of a full loop).

use rayon::prelude::*;

/// At most this many blocks: enough tiles per round to keep every core busy, few enough
/// rounds that their synchronisation stays negligible.
const MAX_BLOCKS: usize = 64;

/// Visits every pair i < j once. `tile(i_range, j_range, gi, gj)` handles the pairs
/// with i in `i_range` and j in `j_range` (and i < j when the ranges coincide), adding
/// forces to the gradient rows `gi` (for `i_range`) and `gj` (for `j_range`), and returns
/// a partial sum; the partial sums are added in a fixed order and returned.
///
/// For a diagonal tile `gj` is empty and all forces go to `gi`.
pub fn for_each_pair_tile<F>(n: usize, s: usize, grad: &mut [f64], tile: F) -> f64
where
    F: Fn(std::ops::Range<usize>, std::ops::Range<usize>, &mut [f64], &mut [f64]) -> f64 + Sync,
{
    assert_eq!(grad.len(), n * s, "gradient buffer length");
    if n < 2 {
        return 0.0;
    }
    let bs = n.div_ceil(MAX_BLOCKS.min(n));
    let real = n.div_ceil(bs);
    let nb = real + real % 2;
    let range = |b: usize| (b * bs).min(n)..((b + 1) * bs).min(n);
    let mut total = 0.0;

    // Round 0: the diagonal tiles, each alone on its block.
    let diag: Vec<f64> = grad
        .par_chunks_mut(bs * s)
        .enumerate()
        .map(|(b, g)| tile(range(b), range(b), g, &mut []))
        .collect();
    total += diag.iter().sum::<f64>();

    // Circle method: block nb − 1 stays, the others rotate; round r pairs (r, nb − 1) and
    // (r + k, r − k) mod (nb − 1) for k = 1 .. nb/2 − 1.
    let m = nb - 1;
    for r in 0..m {
        let mut pairs = Vec::with_capacity(nb / 2);
        pairs.push((r, m));
        for k in 1..nb / 2 {
            let a = (r + k) % m;
            let b = (r + m - k) % m;
            pairs.push((a.min(b), a.max(b)));
        }
        let mut slots: Vec<Option<&mut [f64]>> = grad.chunks_mut(bs * s).map(Some).collect();
        slots.resize_with(nb, || None);
        let tasks: Vec<_> = pairs
            .into_iter()
            .filter(|&(_, b)| b < real)
            .map(|(a, b)| {
                let ga = slots[a].take().expect("a block appears once per round");
                let gb = slots[b].take().expect("a block appears once per round");
                (a, b, ga, gb)
            })
            .collect();
        let parts: Vec<f64> = tasks
            .into_par_iter()
            .map(|(a, b, ga, gb)| tile(range(a), range(b), ga, gb))
            .collect();
        total += parts.iter().sum::<f64>();
    }
    total
}

/// Inside a tile of [`for_each_pair_tile`]: adds w·v to the gradient row of point i and
/// −w·v to that of point j (a pair force), given the first indices of the tile's two
/// blocks. On a diagonal tile `gj` is empty and both rows are in `gi`.
#[inline]
pub fn scatter_pair(
    gi: &mut [f64],
    gj: &mut [f64],
    (ri0, rj0): (usize, usize),
    (i, j): (usize, usize),
    w: f64,
    v: &[f64],
) {
    let s = v.len();
    let oi = (i - ri0) * s;
    if gj.is_empty() {
        let oj = (j - ri0) * s;
        for k in 0..s {
            gi[oi + k] += w * v[k];
            gi[oj + k] -= w * v[k];
        }
    } else {
        let oj = (j - rj0) * s;
        for k in 0..s {
            gi[oi + k] += w * v[k];
            gj[oj + k] -= w * v[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pair_is_visited_once() {
        for n in [1usize, 2, 3, 7, 64, 65, 130, 1000] {
            let s = 1;
            let mut grad = vec![0.0; n * s];
            // Each pair adds 1 to both rows and 1 to the total: row i must end at n − 1.
            let total = for_each_pair_tile(n, s, &mut grad, |ri, rj, gi, gj| {
                let mut c = 0.0;
                if gj.is_empty() {
                    for i in ri.clone() {
                        for j in i + 1..ri.end {
                            gi[i - ri.start] += 1.0;
                            gi[j - ri.start] += 1.0;
                            c += 1.0;
                        }
                    }
                } else {
                    for i in ri.clone() {
                        for j in rj.clone() {
                            gi[i - ri.start] += 1.0;
                            gj[j - rj.start] += 1.0;
                            c += 1.0;
                        }
                    }
                }
                c
            });
            assert_eq!(total as usize, n * (n - 1) / 2, "n={n}");
            if n > 1 {
                assert!(grad.iter().all(|&g| g as usize == n - 1), "n={n}");
            }
        }
    }
}
