//! The exact L∞ star discrepancy in one, two and three dimensions, and the worst one- and
//! two-dimensional projection of a set in any dimension.
//!
//! D*(P) = sup_{t ∈ \[0,1\]^s} |#{x ∈ P : x ∈ [0, t)}/n − t_1⋯t_s| is the quantity of the
//! optimal-point-set literature (Clément, Doerr, Paquete and co-authors; MPMC's 2-D and
//! 3-D tables). Between consecutive coordinate values of the points the count is constant
//! while the volume grows, so the supremum is reached on the grid of critical boxes: each
//! t_k a coordinate value of a point or 1, counting the points strictly inside the box
//! for the upper deviation (t_1⋯t_s − open count/n) and the points in the closed box for
//! the lower one (closed count/n − t_1⋯t_s). The enumeration here visits that grid with
//! prefix counts: O(n log n) in 1-D, O(n²) in 2-D (a sweep over the second coordinate
//! for every value of the first) and O(n³) in 3-D (the 2-D sweep for every value of the
//! first coordinate, on the points below it). That is exact for ties and points on the
//! boundary; it is not the O(n^{1+s/2}) algorithm of Dobkin, Eppstein and Mitchell, so
//! 3-D is for n up to about a thousand.

use crate::PointSet;

/// Most points [`star_discrepancy`] accepts in 2-D (about a second).
pub const MAX_N_2D: usize = 20_000;
/// Most points [`star_discrepancy`] accepts in 3-D (about a second).
pub const MAX_N_3D: usize = 1_000;
/// Most pair-coordinate operations [`worst_projections`] spends on the 2-D projections by
/// default: about half a second on 2 cores, so that this one figure never outweighs the
/// rest of `eval` (at 10 000 × 5 its n² sweeps took five times the other figures).
pub const PROJECTION_WORK: u64 = 100_000_000;

/// The sorted distinct values of `v` with 1 appended when it is not among them.
fn candidates(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    if v.last() != Some(&1.0) {
        v.push(1.0);
    }
    v
}

/// The largest deviation over boxes [0, w·t_a·t_b) given the points below the boxes
/// already fixed in earlier coordinates: `open` are those strictly below, `closed` those
/// below or on; each is a list of (a, b) coordinates.
fn sweep2(open: &[(f64, f64)], closed: &[(f64, f64)], w: f64, n: usize) -> f64 {
    let nf = n as f64;
    let va = candidates(closed.iter().map(|p| p.0).collect());
    let vb = candidates(closed.iter().map(|p| p.1).collect());
    let rank = |b: f64| vb.partition_point(|&v| v < b);
    let mut by_a_open: Vec<(f64, usize)> = open.iter().map(|p| (p.0, rank(p.1))).collect();
    let mut by_a_closed: Vec<(f64, usize)> = closed.iter().map(|p| (p.0, rank(p.1))).collect();
    by_a_open.sort_by(|x, y| x.0.total_cmp(&y.0));
    by_a_closed.sort_by(|x, y| x.0.total_cmp(&y.0));
    let (mut cnt_open, mut cnt_closed) = (vec![0u32; vb.len()], vec![0u32; vb.len()]);
    let (mut io, mut ic) = (0, 0);
    let mut worst = 0.0f64;
    for &ta in &va {
        while io < by_a_open.len() && by_a_open[io].0 < ta {
            cnt_open[by_a_open[io].1] += 1;
            io += 1;
        }
        while ic < by_a_closed.len() && by_a_closed[ic].0 <= ta {
            cnt_closed[by_a_closed[ic].1] += 1;
            ic += 1;
        }
        let (mut below_open, mut below_closed) = (0u32, 0u32);
        for (r, &tb) in vb.iter().enumerate() {
            let vol = w * ta * tb;
            let inside_closed = below_closed + cnt_closed[r];
            worst = worst
                .max(vol - below_open as f64 / nf)
                .max(inside_closed as f64 / nf - vol);
            below_open += cnt_open[r];
            below_closed = inside_closed;
        }
    }
    worst
}

/// The exact L∞ star discrepancy for s ≤ 3; `None` above 3 dimensions or beyond
/// [`MAX_N_2D`] (2-D) and [`MAX_N_3D`] (3-D) points.
pub fn star_discrepancy(points: &PointSet) -> Option<f64> {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    match s {
        1 => Some(one_dimensional(x, n)),
        2 if n <= MAX_N_2D => {
            let p: Vec<(f64, f64)> = (0..n).map(|i| (x[2 * i], x[2 * i + 1])).collect();
            Some(sweep2(&p, &p, 1.0, n))
        }
        3 if n <= MAX_N_3D => {
            let mut worst = 0.0f64;
            for t in candidates((0..n).map(|i| x[3 * i]).collect()) {
                let below = |closed: bool| -> Vec<(f64, f64)> {
                    (0..n)
                        .filter(|&i| x[3 * i] < t || (closed && x[3 * i] == t))
                        .map(|i| (x[3 * i + 1], x[3 * i + 2]))
                        .collect()
                };
                worst = worst.max(sweep2(&below(false), &below(true), t, n));
            }
            Some(worst)
        }
        _ => None,
    }
}

/// The 1-D star discrepancy, 1/(2n) + max_i |x_(i) − (2i − 1)/(2n)| in closed form.
fn one_dimensional(values: &[f64], n: usize) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let nf = n as f64;
    v.iter()
        .enumerate()
        .map(|(i, &x)| (x - (2 * i + 1) as f64 / (2.0 * nf)).abs())
        .fold(0.0, f64::max)
        + 0.5 / nf
}

/// The largest L∞ star discrepancy among the one-dimensional projections (exact,
/// O(s n log n)) and among the two-dimensional ones (exact, O(s² n²); `None` when that
/// would exceed [`PROJECTION_WORK`] operations or s < 2).
pub fn worst_projections(points: &PointSet) -> (f64, Option<f64>) {
    worst_projections_within(points, PROJECTION_WORK)
}

/// [`worst_projections`] with the 2-D projections computed up to `work` operations.
pub fn worst_projections_within(points: &PointSet, work: u64) -> (f64, Option<f64>) {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let column = |k: usize| -> Vec<f64> { (0..n).map(|i| x[i * s + k]).collect() };
    let one = (0..s)
        .map(|k| one_dimensional(&column(k), n))
        .fold(0.0, f64::max);
    let pairs = (s * s.saturating_sub(1) / 2) as u64;
    if s < 2 || pairs.saturating_mul(n as u64).saturating_mul(n as u64) > work {
        return (one, None);
    }
    use rayon::prelude::*;
    let list: Vec<(usize, usize)> = (0..s)
        .flat_map(|a| (a + 1..s).map(move |b| (a, b)))
        .collect();
    let two = list
        .par_iter()
        .map(|&(a, b)| {
            let p: Vec<(f64, f64)> = (0..n).map(|i| (x[i * s + a], x[i * s + b])).collect();
            sweep2(&p, &p, 1.0, n)
        })
        .collect::<Vec<f64>>()
        .into_iter()
        .fold(0.0, f64::max);
    (one, Some(two))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every critical box, counted point by point: O(n^(s+1)).
    fn brute(points: &PointSet) -> f64 {
        let (n, s) = (points.n(), points.s());
        let grids: Vec<Vec<f64>> = (0..s)
            .map(|k| candidates(points.rows().map(|r| r[k]).collect()))
            .collect();
        let mut worst = 0.0f64;
        let mut idx = vec![0usize; s];
        loop {
            let t: Vec<f64> = (0..s).map(|k| grids[k][idx[k]]).collect();
            let vol: f64 = t.iter().product();
            let open = points
                .rows()
                .filter(|r| r.iter().zip(&t).all(|(a, b)| a < b))
                .count();
            let closed = points
                .rows()
                .filter(|r| r.iter().zip(&t).all(|(a, b)| a <= b))
                .count();
            worst = worst
                .max(vol - open as f64 / n as f64)
                .max(closed as f64 / n as f64 - vol);
            let mut k = 0;
            loop {
                if k == s {
                    return worst;
                }
                idx[k] += 1;
                if idx[k] < grids[k].len() {
                    break;
                }
                idx[k] = 0;
                k += 1;
            }
        }
    }

    #[test]
    fn matches_brute_force_on_small_sets_with_ties_and_edges() {
        for (n, s, seed) in [
            (1, 2, 1),
            (5, 2, 2),
            (17, 2, 3),
            (9, 3, 4),
            (23, 3, 5),
            (12, 1, 6),
        ] {
            let mut p = crate::sequences::random(n, s, seed).unwrap().into_vec();
            // Ties and points on the faces.
            if n > 3 {
                p[0] = 1.0;
                p[s] = p[2 * s];
                p[s + 1] = 0.0;
            }
            let p = PointSet::new(n, s, p).unwrap();
            let (a, b) = (star_discrepancy(&p).unwrap(), brute(&p));
            assert!((a - b).abs() < 1e-14, "n = {n}, s = {s}: {a} vs {b}");
        }
    }

    #[test]
    fn known_values() {
        // One point at the centre of the square: the closed box [0, ½]² holds it (count 1)
        // while its volume is ¼, so D* = ¾.
        let p = PointSet::from_rows(&[[0.5, 0.5]]).unwrap();
        assert!((star_discrepancy(&p).unwrap() - 0.75).abs() < 1e-15);
        // The van der Corput midpoint set {(2i − 1)/(2n)} has D* = 1/(2n).
        let n = 40;
        let v: Vec<f64> = (1..=n)
            .map(|i| (2 * i - 1) as f64 / (2 * n) as f64)
            .collect();
        let p = PointSet::new(n, 1, v).unwrap();
        assert!((star_discrepancy(&p).unwrap() - 1.0 / 80.0).abs() < 1e-15);
        // A 2-D set and its transpose, and a 3-D set with a constant third coordinate of 1
        // (which every box up to t_3 = 1 contains), have the 2-D set's value.
        let q = crate::sequences::random(30, 2, 8).unwrap();
        let t: Vec<[f64; 2]> = q.rows().map(|r| [r[1], r[0]]).collect();
        let lifted: Vec<[f64; 3]> = q.rows().map(|r| [r[0], r[1], 1.0]).collect();
        let d = star_discrepancy(&q).unwrap();
        assert_eq!(
            d,
            star_discrepancy(&PointSet::from_rows(&t).unwrap()).unwrap()
        );
        let d3 = star_discrepancy(&PointSet::from_rows(&lifted).unwrap()).unwrap();
        assert!(d3 >= d - 1e-15);
    }

    #[test]
    fn stratified_sets_have_one_dimensional_projections_within_one_over_n() {
        let p = crate::sequences::lhs(200, 6, 1).unwrap();
        let (one, two) = worst_projections(&p);
        assert!(one <= 1.0 / 200.0 + 1e-15, "{one}");
        assert!(two.unwrap() > one);
    }
}
