//! The exact L∞ star discrepancy in one, two and three dimensions, and the worst one- and
//! two-dimensional projection of a set in any dimension.
//!
//! D*(P) = sup_{t ∈ \[0,1\]^s} |#{x ∈ P : x ∈ [0, t)}/n − t_1⋯t_s| is the quantity of the
//! optimal-point-set literature (Clément, Doerr, Paquete and co-authors; MPMC's 2-D and
//! 3-D tables). Between consecutive coordinate values of the points the count is constant
//! while the volume grows, so the supremum is reached on the grid of critical boxes: each
//! t_k a coordinate value of a point or 1, counting the points strictly inside the box
//! for the upper deviation (t_1⋯t_s − open count/n) and the points in the closed box for
//! the lower one (closed count/n − t_1⋯t_s). In 1-D that is a closed form after a sort,
//! O(n log n). In 2-D a sweep over the first coordinate keeps, for every value of the
//! second, the deviation of its box as a line in the first bound whose intercept grows by
//! one point at a time; a kinetic segment tree over those lines gives the largest at each
//! step in O(log² n) amortised, O(n log² n) in all (the order of Dobkin, Eppstein and
//! Mitchell's algorithm), and compares the deviations as the enumeration of every box
//! forms them, so the value has the same bits. In 3-D that sweep runs for every value of
//! the first coordinate, on the points below it: O(n² log² n). Exact for ties and points
//! on the boundary.

use crate::PointSet;

/// Most points [`star_discrepancy`] accepts in 2-D (about 2 s on one core).
pub const MAX_N_2D: usize = 200_000;
/// Most points [`star_discrepancy`] accepts in 3-D (under a second).
pub const MAX_N_3D: usize = 1_000;
/// Most work [`worst_projections`] spends on the 2-D projections by default, in units of
/// [`projection_work`]: about half a second on 2 cores, so that this one figure never
/// outweighs the rest of `eval`.
pub const PROJECTION_WORK: u64 = 100_000_000;

/// The work of one 2-D projection of n points in the units of [`PROJECTION_WORK`]:
/// n·min(n, 2⌈log₂ n⌉²), and at least 1 (a set of one point still costs each of its
/// s(s−1)/2 projections a visit, so that the budget bounds them at any s). A unit is about 6 ns on one core (55 ms for the sweep of 20 000
/// random points, 9·10⁶ units), the cost of one box of the O(n²) enumeration the
/// budget was first set in, which is never less: every projection computed within the
/// budget by that enumeration still is.
pub fn projection_work(n: usize) -> u64 {
    let n = n as u64;
    let log = u64::from(n.max(1).next_power_of_two().trailing_zeros());
    n.saturating_mul(n.min(2 * log * log)).max(1)
}

/// The sorted distinct values of `v` with 1 appended when it is not among them.
fn candidates(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    if v.last() != Some(&1.0) {
        v.push(1.0);
    }
    v
}

#[cfg(test)]
/// The largest deviation over boxes [0, w·t_a·t_b) given the points below the boxes
/// already fixed in earlier coordinates: `open` are those strictly below, `closed` those
/// below or on; each is a list of (a, b) coordinates.
fn sweep2_quadratic(open: &[(f64, f64)], closed: &[(f64, f64)], w: f64, n: usize) -> f64 {
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

/// The largest deviation over boxes [0, w·t_a·t_b), as in the O(m²) enumeration, in
/// O(m log² m) for m points: the same boxes and the same float deviations,
/// so the same bits, by a sweep over the first coordinate that keeps the largest upper
/// and lower deviation over the second in a [`Kinetic`] tree each.
fn sweep2(open: &[(f64, f64)], closed: &[(f64, f64)], w: f64, n: usize) -> f64 {
    let va = candidates(closed.iter().map(|p| p.0).collect());
    let vb = candidates(closed.iter().map(|p| p.1).collect());
    let rank = |b: f64| vb.partition_point(|&v| v < b);
    let by_a = |set: &[(f64, f64)]| {
        let mut v: Vec<(f64, usize)> = set.iter().map(|p| (p.0, rank(p.1))).collect();
        v.sort_by(|x, y| x.0.total_cmp(&y.0));
        v
    };
    let (by_a_open, by_a_closed) = (by_a(open), by_a(closed));
    let r = vb.len();
    let mut upper = Kinetic::new(&vb, n, true, w * va[0]);
    let mut lower = Kinetic::new(&vb, n, false, w * va[0]);
    let (mut io, mut ic) = (0, 0);
    let mut worst = 0.0f64;
    for &ta in &va {
        // A point strictly inside in its first coordinate counts in the open boxes whose
        // second bound lies above its own; one on or below, in the closed boxes from its
        // own bound on.
        while io < by_a_open.len() && by_a_open[io].0 < ta {
            upper.add(by_a_open[io].1 + 1, r);
            io += 1;
        }
        while ic < by_a_closed.len() && by_a_closed[ic].0 <= ta {
            lower.add(by_a_closed[ic].1, r);
            ic += 1;
        }
        let t = w * ta;
        worst = worst.max(upper.max_at(t)).max(lower.max_at(t));
    }
    worst
}

/// How close (in the deviation's units) two candidate boxes' deviations may come before
/// [`Kinetic`] compares them again in floating point: far above the few units of 2⁻⁵³
/// each deviation is rounded by, so that between two comparisons the float order of
/// the pair is its exact order.
const TIE_MARGIN: f64 = 1e-14;

/// The largest of R deviations g_r(t) = σ·(fl(t·b_r) − fl(c_r/n)) (σ = +1 for the upper
/// deviation, −1 for the lower) as the time t grows and the integer counts c_r grow by
/// range additions: a kinetic segment tree. Each node keeps the float-largest line of its
/// subtree at the current time and the time ("melt") before which no comparison below it
/// can change; advancing the time recomputes only the nodes that melted, a range addition
/// only the nodes it cuts. Amortised O(log² R) per operation. Every comparison is of the
/// deviations as the O(n²) sweep forms them, so the maximum has the same bits.
struct Kinetic<'a> {
    b: &'a [f64],
    nf: f64,
    upper: bool,
    t: f64,
    // Per node: the winning line, its count, the pending addition and the melt time.
    win: Vec<u32>,
    count: Vec<u32>,
    lazy: Vec<u32>,
    melt: Vec<f64>,
}

impl<'a> Kinetic<'a> {
    fn new(b: &'a [f64], n: usize, upper: bool, t: f64) -> Kinetic<'a> {
        let size = 4 * b.len().max(1);
        let mut k = Kinetic {
            b,
            nf: n as f64,
            upper,
            t,
            win: vec![0; size],
            count: vec![0; size],
            lazy: vec![0; size],
            melt: vec![f64::INFINITY; size],
        };
        k.build(1, 0, b.len());
        k
    }

    fn value(&self, r: u32, c: u32) -> f64 {
        let vol = self.t * self.b[r as usize];
        if self.upper {
            vol - c as f64 / self.nf
        } else {
            c as f64 / self.nf - vol
        }
    }

    fn build(&mut self, node: usize, lo: usize, hi: usize) {
        if hi - lo == 1 {
            self.win[node] = lo as u32;
            return;
        }
        let mid = (lo + hi) / 2;
        self.build(2 * node, lo, mid);
        self.build(2 * node + 1, mid, hi);
        self.pull(node);
    }

    fn apply(&mut self, node: usize, add: u32) {
        self.count[node] += add;
        self.lazy[node] += add;
    }

    fn push(&mut self, node: usize) {
        let add = std::mem::take(&mut self.lazy[node]);
        if add > 0 {
            self.apply(2 * node, add);
            self.apply(2 * node + 1, add);
        }
    }

    /// The node's winner from its children's at the current time, and when the loser
    /// could come within [`TIE_MARGIN`] of it.
    fn pull(&mut self, node: usize) {
        let (l, r) = (2 * node, 2 * node + 1);
        let (vl, vr) = (
            self.value(self.win[l], self.count[l]),
            self.value(self.win[r], self.count[r]),
        );
        let (w, lose, gap) = if vl >= vr {
            (l, r, vl - vr)
        } else {
            (r, l, vr - vl)
        };
        self.win[node] = self.win[w];
        self.count[node] = self.count[w];
        // The gap changes with t at the difference of the slopes σ·b.
        let (bw, bl) = (
            self.b[self.win[w] as usize],
            self.b[self.win[lose] as usize],
        );
        let closing = if self.upper { bl - bw } else { bw - bl };
        let cross = if gap <= TIE_MARGIN {
            self.t
        } else if closing > 0.0 {
            self.t + (gap - TIE_MARGIN) / closing
        } else {
            f64::INFINITY
        };
        self.melt[node] = cross.min(self.melt[l]).min(self.melt[r]);
    }

    /// Adds one to the counts of the lines in [from, to).
    fn add(&mut self, from: usize, to: usize) {
        if from < to {
            self.add_in(1, 0, self.b.len(), from, to);
        }
    }

    fn add_in(&mut self, node: usize, lo: usize, hi: usize, from: usize, to: usize) {
        if to <= lo || hi <= from {
            return;
        }
        if from <= lo && hi <= to {
            self.apply(node, 1);
            return;
        }
        self.push(node);
        let mid = (lo + hi) / 2;
        self.add_in(2 * node, lo, mid, from, to);
        self.add_in(2 * node + 1, mid, hi, from, to);
        self.pull(node);
    }

    /// Moves the time to `t` (never backwards) and returns the largest deviation then.
    fn max_at(&mut self, t: f64) -> f64 {
        self.t = t;
        self.advance(1, self.b.len());
        self.value(self.win[1], self.count[1])
    }

    fn advance(&mut self, node: usize, len: usize) {
        if self.melt[node] > self.t {
            return;
        }
        self.push(node);
        let half = len / 2;
        self.advance(2 * node, half);
        self.advance(2 * node + 1, len - half);
        self.pull(node);
    }
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
/// O(s n log n)) and among the two-dimensional ones (exact, O(s² n log² n); `None` when
/// s(s − 1)/2 times [`projection_work`] would exceed [`PROJECTION_WORK`], or s < 2).
pub fn worst_projections(points: &PointSet) -> (f64, Option<f64>) {
    worst_projections_within(points, PROJECTION_WORK)
}

/// [`worst_projections`] with the 2-D projections computed up to `work` units of
/// [`projection_work`].
pub fn worst_projections_within(points: &PointSet, work: u64) -> (f64, Option<f64>) {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let column = |k: usize| -> Vec<f64> { (0..n).map(|i| x[i * s + k]).collect() };
    let one = (0..s)
        .map(|k| one_dimensional(&column(k), n))
        .fold(0.0, f64::max);
    let pairs = (s * s.saturating_sub(1) / 2) as u64;
    if s < 2 || pairs.saturating_mul(projection_work(n)) > work {
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
            let mut p = stillpoint_sequences::random(n, s, seed).unwrap().into_vec();
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
        let q = stillpoint_sequences::random(30, 2, 8).unwrap();
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
        let p = stillpoint_sequences::lhs(200, 6, 1).unwrap();
        let (one, two) = worst_projections(&p);
        assert!(one <= 1.0 / 200.0 + 1e-15, "{one}");
        assert!(two.unwrap() > one);
    }

    /// Both sweeps over every pair of coordinates of `p`, and over the 3-D boxes' slices
    /// (the points below a third bound, with its weight), agree bit for bit.
    fn assert_sweeps_agree(p: &PointSet, what: &str) {
        let (n, s) = (p.n(), p.s());
        let x = p.as_slice();
        for a in 0..s {
            for b in 0..s {
                if a == b {
                    continue;
                }
                let pts: Vec<(f64, f64)> = (0..n).map(|i| (x[i * s + a], x[i * s + b])).collect();
                let (fast, slow) = (
                    sweep2(&pts, &pts, 1.0, n),
                    sweep2_quadratic(&pts, &pts, 1.0, n),
                );
                assert_eq!(
                    fast.to_bits(),
                    slow.to_bits(),
                    "{what}: ({a}, {b}): {fast} vs {slow}"
                );
            }
        }
        if s >= 3 {
            for t in candidates((0..n).map(|i| x[i * s + 2]).collect())
                .into_iter()
                .step_by(7)
            {
                let below = |closed: bool| -> Vec<(f64, f64)> {
                    (0..n)
                        .filter(|&i| x[i * s + 2] < t || (closed && x[i * s + 2] == t))
                        .map(|i| (x[i * s], x[i * s + 1]))
                        .collect()
                };
                let (o, c) = (below(false), below(true));
                let (fast, slow) = (sweep2(&o, &c, t, n), sweep2_quadratic(&o, &c, t, n));
                assert_eq!(
                    fast.to_bits(),
                    slow.to_bits(),
                    "{what}: t3 = {t}: {fast} vs {slow}"
                );
            }
        }
    }

    #[test]
    fn the_default_budget_keeps_every_projection_the_enumeration_computed() {
        for n in (1..5000).chain([20_000, 1 << 20, (1 << 20) + 1]) {
            let w = projection_work(n);
            assert!(w <= (n * n) as u64, "{n}: {w}");
            let log = (n as f64).log2().ceil();
            assert!(
                w as f64 <= (2.0 * n as f64 * log * log).max(1.0),
                "{n}: {w}"
            );
        }
        // One point in 20 000 dimensions: 2·10⁸ projections of one visit each pass the
        // budget, so none is computed (they were, unbounded in time and memory, at 0 work).
        assert_eq!(projection_work(1), 1);
        let one = stillpoint_sequences::random(1, 20_000, 3).unwrap();
        assert!(worst_projections(&one).1.is_none());
        // 10 000 × 5 was above the budget by the enumeration's n² (10⁹); it is now within.
        assert!(10 * projection_work(10_000) <= PROJECTION_WORK);
        assert!(
            worst_projections(&stillpoint_sequences::random(10_000, 5, 3).unwrap())
                .1
                .is_some()
        );
    }

    #[test]
    fn the_kinetic_sweep_has_the_bits_of_the_quadratic_one() {
        use stillpoint_sequences as sequences;
        for (n, seed) in [(1, 1), (2, 2), (3, 3), (50, 4), (333, 5), (1500, 6)] {
            assert_sweeps_agree(&sequences::random(n, 3, seed).unwrap(), "random");
        }
        for n in [7, 64, 257, 1024, 2039] {
            assert_sweeps_agree(&sequences::lattice(n, 4).unwrap(), "lattice");
            assert_sweeps_agree(&sequences::sobol_plain(n, 3).unwrap(), "sobol");
            assert_sweeps_agree(&sequences::halton(n, 3).unwrap(), "halton");
            assert_sweeps_agree(&sequences::lhs(n, 3, 9).unwrap(), "lhs");
        }
        // A full grid (every coordinate value shared by a row or column of points), with
        // and without the face at 1; the midpoint grid.
        for (k, scale) in [(12usize, 12.0), (12, 11.0), (31, 31.0)] {
            let rows: Vec<[f64; 3]> = (0..k * k)
                .map(|i| {
                    [
                        (i / k) as f64 / scale,
                        (i % k) as f64 / scale,
                        ((i * 7) % k) as f64 / scale,
                    ]
                })
                .collect();
            assert_sweeps_agree(&PointSet::from_rows(&rows).unwrap(), "grid");
        }
        let mid: Vec<[f64; 2]> = (0..400)
            .map(|i| {
                [
                    ((i / 20) as f64 + 0.5) / 20.0,
                    ((i % 20) as f64 + 0.5) / 20.0,
                ]
            })
            .collect();
        assert_sweeps_agree(&PointSet::from_rows(&mid).unwrap(), "midpoint grid");
        // Duplicated points, coordinates tied across points, values on the faces 0 and 1,
        // coordinates a few units of 2⁻⁵³ apart (near-parallel lines of the sweep).
        let mut v = sequences::random(600, 3, 11).unwrap().into_vec();
        for i in 0..200 {
            let j = 3 * (i + 200);
            v[j] = v[3 * i];
            v[j + 1] = v[3 * i + 1];
            v[j + 2] = v[3 * i + 2];
        }
        for i in 400..450 {
            v[3 * i] = 0.5;
            v[3 * i + 1] = if i % 2 == 0 { 1.0 } else { 0.0 };
        }
        for i in 450..500 {
            v[3 * i] = 0.25 + (i - 450) as f64 * f64::EPSILON;
            v[3 * i + 1] = 0.75 - (i - 450) as f64 * f64::EPSILON;
        }
        assert_sweeps_agree(&PointSet::new(600, 3, v).unwrap(), "ties");
        // Every point the same.
        let same = PointSet::new(100, 3, vec![0.3; 300]).unwrap();
        assert_sweeps_agree(&same, "one point repeated");
    }
}
