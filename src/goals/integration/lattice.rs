//! The default set for integration from [`LATTICE_FROM_N`] points on, and at s = 1 at
//! any n: the rank-1 lattice of the tent randomisation ([`sequences::tent_lattice`]),
//! made deterministic by a shift chosen coordinate by coordinate on the set's own
//! worst-case error, then tent-transformed.
//!
//! Why a lattice there. Above a few hundred points the descents cost O(n²) per round and
//! buy a few per cent of the equal-weight discrepancies, not integration error: at
//! 4 096–65 536 points the stratified-descent sets integrated Genz's smooth families no
//! better than scrambled Sobol' (up to 2.3× worse), while the same lattice randomly
//! shifted and tent-transformed was 3–25× better, built in seconds. Its error for
//! integrands with square-integrable mixed second derivatives decays like n⁻².
//!
//! Why this shift. The lattice's generator is chosen for the error averaged over all
//! shifts; one shift is one set, and shifts differ (shift 0 puts a point on the origin's
//! corner: the corner peak's error was 45× Sobol's at 4 096 × 10). The shift
//! Δ_j = q_j/(4n) with q_j ≡ 1 or 3 (mod 4) maps every coordinate onto the midpoints
//! (i + ½)/n after the tent transform, so each column is stratified with mean ½ at every
//! n, odd and prime included. Among such shifts the one kept lowers, greedily coordinate
//! by coordinate (as the generator itself is built), the set's squared worst-case error
//! in the half-period cosine space of smoothness 2 with product weight γ
//! ([`sequences::TENT_WEIGHT`]), truncated to the projections of order one and two:
//!
//!   e²₂ = γ Σ_j (1/n²) Σ_{k,k'} ψ(x_kj, x_k'j) + γ² Σ_{j<l} (1/n²) Σ_{k,k'} ψ(x_kj, x_k'j) ψ(x_kl, x_k'l),
//!   ψ(x, y) = Σ_{h≥1} 2 cos(πhx) cos(πhy)/h⁴.
//!
//! Among the best few shifts for each coordinate, and their reflections (x ↦ 1 − x, which
//! the cosine kernel cannot see), the one kept gives the smallest errors for the
//! exponential test functions e^{−c Σ_j x_j} peaked at the origin (`Corner`): the
//! integrands users bring are often peaked at a corner, and which points come near it
//! is what decides their error.
//!
//! Higher orders weigh γ³ and less and hardly depend on the shift; the two orders kept
//! cost O(n) per candidate and coordinate through the lattice's structure: with
//! x = φ(y) the tent transform of y, cos(πh φ(y)) = cos(2πhy), so ψ(φ(y), φ(y')) =
//! ½[ω(y − y') + ω(y + y')] with ω(t) = Σ_{h≠0} e^{2πiht}/h⁴ = −(2π)⁴B₄(t)/24, and over
//! a lattice both y − y' and y + y' run over (shifted) lattice points.

use crate::energies::PointSet;
use crate::sequences::{self, TENT_WEIGHT};
use crate::Error;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use std::time::Instant;

/// From this many points on, the default set for integration is [`lattice_rule`]
/// (without a target, a set to extend or nested sizes). Below it the stratified descent on
/// the discrepancies wins the discrepancy tables and integrates as well; from it on the
/// descent's O(n²) rounds grow past seconds while the lattice integrates better (the
/// large-n benchmark).
pub const LATTICE_FROM_N: usize = 500;

/// Candidate shifts per coordinate × n × s at most in the shift search (about a second
/// on two cores): every shift is tried while it fits, a seeded sample past it.
const SHIFT_SEARCH_BUDGET: u128 = 1 << 28;

/// Candidate shifts per coordinate at least, whatever the size.
const MIN_SHIFT_CANDIDATES: usize = 16;

/// The set of [`lattice_rule`] and how it was made.
#[derive(Debug, Clone)]
pub struct LatticeRule {
    /// The points: x_kj = φ(frac(k z_j/n + q_j/(4n))), φ(y) = 1 − |2y − 1|.
    pub points: PointSet,
    /// The generating vector z (component by component, [`sequences::tent_lattice_generator`]).
    pub generator: Vec<u64>,
    /// The shift's numerators q_j: Δ_j = q_j/(4n), q_j odd.
    pub shift: Vec<u64>,
    /// The criterion e²₂ of the set kept (module documentation).
    pub criterion: f64,
    /// The criterion of the seed's first draw of shifts (before the choice).
    pub drawn_criterion: f64,
    /// Candidate shifts tried per coordinate.
    pub candidates: usize,
    /// Wall seconds of the generator's construction and of the shift search.
    pub seconds: (f64, f64),
}

/// ω(q/(2n)) for q = 0..2n − 1: ω(t) = Σ_{h≠0} e^{2πiht}/h⁴ = −(2π)⁴ B₄(t)/24, with
/// B₄(t) = t⁴ − 2t³ + t² − 1/30, at the half-grid where sums and differences of shifted
/// lattice coordinates fall.
fn omega_table(n: usize) -> Vec<f64> {
    let c = (2.0 * std::f64::consts::PI).powi(4) / 24.0;
    (0..2 * n)
        .map(|q| {
            let t = q as f64 / (2 * n) as f64;
            -c * (t * t * (t * t - 2.0 * t + 1.0) - 1.0 / 30.0)
        })
        .collect()
}

/// The parity-class sums a pair's cross terms need (module documentation of
/// [`Criterion`]).
#[derive(Debug, Clone, Copy)]
struct ClassSums {
    /// Σ over even a, odd a of D(a) = ω(a z/n) (any z coprime to n: a permutation).
    diff: [f64; 2],
    /// Σ over even b, odd b of S(b) = ω((2r_b + e)/(2n)), for e = 1 and e = 3.
    sum: [[f64; 2]; 2],
}

/// The order-two criterion of shifted, tent-transformed lattice points, split so that a
/// shift's part costs O(n) (see the module documentation).
///
/// For coordinates j and l, with y_kj = (r_kj + e_j/4)/n, r_kj = (k z_j + m_j) mod n,
/// q_j = 4m_j + e_j and e_j ∈ {1, 3}:
/// (1/n²) Σ_{k,k'} ψψ = (1/(4n²)) [n Σ_a D_j D_l + n Σ_b S_j S_l + X_jl + X_lj], where
/// D_j(a) = ω(a z_j/n) (differences, k − k' = a), S_j(b) = ω(y_kj + y_k'j) with
/// k + k' = b, and X_jl = Σ_{k,k'} D_j(k − k') S_l(k + k'). For odd n, (k − k', k + k')
/// runs over every pair (a, b) once, and X_jl = (Σ D)(Σ S_l); for even n over the pairs
/// of equal parity twice, and X_jl = 2 Σ_{p} (Σ_{a ≡ p} D)(Σ_{b ≡ p} S_l), with the
/// parity of r_b that of b (z_l is odd).
struct Criterion<'a> {
    n: usize,
    omega: &'a [f64],
    classes: ClassSums,
}

impl<'a> Criterion<'a> {
    fn new(n: usize, omega: &'a [f64]) -> Self {
        let mut diff = [0.0; 2];
        let mut sum = [[0.0; 2]; 2];
        for r in 0..n {
            diff[r % 2] += omega[2 * r];
            for (i, e) in [1usize, 3].into_iter().enumerate() {
                sum[i][r % 2] += omega[(2 * r + e) % (2 * n)];
            }
        }
        Criterion {
            n,
            omega,
            classes: ClassSums { diff, sum },
        }
    }

    /// S(b) for b = 0..n − 1 of a coordinate with generator z and shift numerator q.
    fn sums(&self, z: u64, q: u64) -> impl Iterator<Item = f64> + '_ {
        let n = self.n;
        let step = (z % n as u64) as usize;
        let e = (q % 4) as usize;
        // r_b = (b z + 2m) mod n: the sum of two points' residues with k + k' = b.
        let mut r = (2 * (q / 4) % n as u64) as usize;
        (0..n).map(move |_| {
            // 2r + e < 2n + 3: one subtraction wraps it.
            let i = 2 * r + e;
            let v = self.omega[if i >= 2 * n { i - 2 * n } else { i }];
            r += step;
            if r >= n {
                r -= n;
            }
            v
        })
    }

    /// X_jl + X_lj for shift numerators q_j and q_l.
    fn cross(&self, qj: u64, ql: u64) -> f64 {
        let c = &self.classes;
        let class = |q: u64| usize::from(q % 4 == 3);
        let x = |q: u64| {
            let s = c.sum[class(q)];
            if self.n % 2 == 1 {
                (c.diff[0] + c.diff[1]) * (s[0] + s[1])
            } else {
                2.0 * (c.diff[0] * s[0] + c.diff[1] * s[1])
            }
        };
        x(qj) + x(ql)
    }

    /// The order-one part, γ Σ_j (1/n²) Σ_{k,k'} ψ: the same for every such shift (every
    /// column is the n midpoints).
    fn first_order(&self, s: usize, gamma: f64) -> f64 {
        let c = &self.classes;
        let n = self.n as f64;
        let one = (c.diff[0] + c.diff[1] + c.sum[0][0] + c.sum[0][1]) / (2.0 * n);
        gamma * s as f64 * one
    }

    /// Σ_{j<l} Σ_a D_j(a) D_l(a): the differences' part, the same for every shift.
    fn differences(&self, z: &[u64]) -> f64 {
        let n = self.n;
        let (mut total, mut squares) = (vec![0.0f64; n], 0.0);
        for &zj in z {
            let step = (zj % n as u64) as usize;
            let mut r = 0usize;
            for t in total.iter_mut() {
                let d = self.omega[2 * r];
                *t += d;
                squares += d * d;
                r += step;
                if r >= n {
                    r -= n;
                }
            }
        }
        0.5 * (total.iter().map(|t| t * t).sum::<f64>() - squares)
    }

    /// e²₂ of the points with generator z and shift numerators q, directly.
    fn value(&self, z: &[u64], q: &[u64], gamma: f64) -> f64 {
        let n = self.n as f64;
        let mut pairs = self.differences(z) * n;
        let mut acc = vec![0.0f64; self.n];
        for (j, (&zj, &qj)) in z.iter().zip(q).enumerate() {
            for (a, v) in acc.iter_mut().zip(self.sums(zj, qj)) {
                pairs += n * *a * v;
                *a += v;
            }
            for &ql in &q[..j] {
                pairs += self.cross(qj, ql);
            }
        }
        self.first_order(z.len(), gamma) + gamma * gamma * pairs / (4.0 * n * n)
    }
}

/// The tent-transformed point of lattice residue r (k z_j mod n) under the shift
/// numerator q: y = (r + q/4)/n mod 1, then φ(y) = 1 − |2y − 1|. In quarters of 1/n,
/// t = 4·((r + q div 4) mod n) + q mod 4 is odd, so φ(y) = t/(2n) or (4n − t)/(2n) is
/// a midpoint (2i + 1)/(2n), computed exactly.
fn tent_point(r: u64, q: u64, n: u64) -> f64 {
    let t = 4 * ((r + q / 4) % n) + q % 4;
    let odd = if t < 2 * n { t } else { 4 * n - t };
    odd as f64 / (2 * n) as f64
}

/// The points x_kj = φ(frac(k z_j/n + q_j/(4n))), row by row from [`column`]s.
fn points(n: usize, z: &[u64], q: &[u64]) -> Result<PointSet, Error> {
    let cols: Vec<Vec<f64>> = z
        .iter()
        .zip(q)
        .map(|(&zj, &qj)| column(n, zj, qj))
        .collect();
    let data = (0..n)
        .flat_map(|k| cols.iter().map(move |c| c[k]))
        .collect();
    PointSet::new(n, z.len(), data)
}

/// The shift numerators drawn for coordinate j: every odd q < 4n (q = 4m + e) while
/// [`SHIFT_SEARCH_BUDGET`] allows, else `count` seeded draws.
fn shift_candidates(n: usize, count: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<u64> {
    if count >= 2 * n {
        (0..2 * n as u64).map(|i| 2 * i + 1).collect()
    } else {
        (0..count)
            .map(|_| 2 * rng.random_range(0..2 * n as u64) + 1)
            .collect()
    }
}

/// The set of the module documentation for n points in s dimensions; `seed` draws the
/// first coordinate's shift and, past the search budget, the candidate shifts of the
/// others. Deterministic for a seed, whatever the thread count. s = 1 gives the midpoints
/// (k + ½)/n in order. Refuses n = 0 or s = 0, naming the argument.
pub fn lattice_rule(n: usize, s: usize, seed: u64) -> Result<LatticeRule, Error> {
    sequences::check_size(n, s)?;
    let clock = Instant::now();
    let generator = sequences::tent_lattice_generator(n, s)?;
    let built = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let omega = omega_table(n);
    let crit = Criterion::new(n, &omega);
    let count = ((SHIFT_SEARCH_BUDGET / (n as u128 * s as u128)) as usize)
        .max(MIN_SHIFT_CANDIDATES)
        .min(2 * n);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(sequences::stream_seed(seed, 0x1a77));
    let drawn: Vec<u64> = (0..s)
        .map(|_| 2 * rng.random_range(0..2 * n as u64) + 1)
        .collect();
    let mut shift = vec![drawn[0]];
    // P(b) = Σ over the coordinates chosen of S_l(b): a candidate's pair terms with all of
    // them in one pass.
    let mut acc: Vec<f64> = crit.sums(generator[0], drawn[0]).collect();
    let mut corner = Corner::new(n);
    corner.push(&column(n, generator[0], drawn[0]));
    for &zj in &generator[1..] {
        let candidates = shift_candidates(n, count, &mut rng);
        let scores: Vec<f64> = candidates
            .par_iter()
            .map(|&q| {
                let pairs: f64 = acc.iter().zip(crit.sums(zj, q)).map(|(a, v)| a * v).sum();
                let cross: f64 = shift.iter().map(|&ql| crit.cross(q, ql)).sum();
                n as f64 * pairs + cross
            })
            .collect();
        let mut order: Vec<usize> = (0..candidates.len()).collect();
        order.sort_by(|&a, &b| scores[a].total_cmp(&scores[b]).then(a.cmp(&b)));
        // Among the best few by the criterion, each also reflected, the one that the
        // corner test functions favour ([`Corner`]).
        let mut pick: Option<(f64, u64, Vec<f64>)> = None;
        for &i in order.iter().take(CORNER_CHOICES) {
            for q in [
                candidates[i],
                (candidates[i] + 2 * n as u64) % (4 * n as u64),
            ] {
                let col = column(n, zj, q);
                let score = corner.score(&col);
                if pick.as_ref().is_none_or(|p| score < p.0) {
                    pick = Some((score, q, col));
                }
            }
        }
        let (_, q, col) = pick.expect("at least one candidate");
        corner.push(&col);
        for (a, v) in acc.iter_mut().zip(crit.sums(zj, q)) {
            *a += v;
        }
        shift.push(q);
        crate::solve::stop_if_cancelled()?;
    }
    let criterion = crit.value(&generator, &shift, TENT_WEIGHT);
    let drawn_criterion = crit.value(&generator, &drawn, TENT_WEIGHT);
    let mut points = points(n, &generator, &shift)?;
    if s == 1 {
        // One coordinate: the midpoints in their natural order.
        points.as_mut_slice().sort_by(f64::total_cmp);
    }
    Ok(LatticeRule {
        points,
        generator,
        shift,
        criterion,
        drawn_criterion,
        candidates: if s > 1 { count } else { 0 },
        seconds: (built, clock.elapsed().as_secs_f64()),
    })
}

/// How many of the best shifts by the criterion the corner test functions choose among
/// ([`Corner`]), each also reflected (x ↦ 1 − x: q ↦ q + 2n mod 4n). Measured on the Genz
/// families (16 instances, 3 seeds) against scrambled Sobol', corner peak geometric mean
/// and worst cell: at 14 cells (s = 2–30, n = 512–4 096) the best shift alone 0.58 and
/// 11.4, with the better of it and its reflection 0.35 and 1.94; at 10 cells (s = 5–50)
/// the better reflection 0.72 and 1.94, among 4 shifts 0.59 and 1.23, among 8 0.52 and
/// 0.91, among 16 0.64 and 1.37. The other families moved within their noise.
const CORNER_CHOICES: usize = 8;

/// The rates c of the test functions e^{−c Σ_j x_j} of [`Corner`]: Genz's corner peak (1 + a·x)^{−(s+1)} is a mixture of such products
/// over c = t·a_j (its Laplace representation), with rates near 2 for its usual
/// difficulty; faster ones weigh the points nearest the origin more.
const CORNER_RATES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];

/// The coordinate with generator z under the shift numerator q, point by point.
fn column(n: usize, z: u64, q: u64) -> Vec<f64> {
    let (nn, step) = (n as u64, z % n.max(1) as u64);
    let mut r = 0u64;
    (0..n)
        .map(|_| {
            let x = tent_point(r, q, nn);
            r += step;
            if r >= nn {
                r -= nn;
            }
            x
        })
        .collect()
}

/// The relative errors of the test functions e^{−c Σ_j x_j}, c in [`CORNER_RATES`], on the
/// coordinates chosen so far: per rate, Π_j e^{−c x_kj} for every point and the exact
/// mean ((1 − e^{−c})/c)^j.
///
/// The cosine kernel cannot tell reflections apart (ψ(1 − x, 1 − y) = ψ(x, y)), nor much
/// the best few shifts, and each column is the midpoints under all of them; but
/// integrands peaked at a corner see which points come near it.
struct Corner {
    prod: Vec<Vec<f64>>,
    exact: [f64; CORNER_RATES.len()],
}

impl Corner {
    fn new(n: usize) -> Self {
        Corner {
            prod: vec![vec![1.0; n]; CORNER_RATES.len()],
            exact: [1.0; CORNER_RATES.len()],
        }
    }

    /// Σ_c (relative error)² with `col` as the next coordinate.
    fn score(&self, col: &[f64]) -> f64 {
        CORNER_RATES
            .iter()
            .zip(&self.prod)
            .zip(self.exact)
            .map(|((&c, p), e)| {
                let mean = p
                    .iter()
                    .zip(col)
                    .map(|(pk, x)| pk * (-c * x).exp())
                    .sum::<f64>()
                    / col.len() as f64;
                (mean / (e * -(-c).exp_m1() / c) - 1.0).powi(2)
            })
            .sum()
    }

    /// Takes `col` as the next coordinate.
    fn push(&mut self, col: &[f64]) {
        for ((&c, p), e) in CORNER_RATES
            .iter()
            .zip(self.prod.iter_mut())
            .zip(self.exact.iter_mut())
        {
            for (pk, x) in p.iter_mut().zip(col) {
                *pk *= (-c * x).exp();
            }
            *e *= -(-c).exp_m1() / c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ψ(x, y) = Σ_{h≥1} 2 cos(πhx) cos(πhy)/h⁴ from its series, on the written points.
    fn psi(x: f64, y: f64) -> f64 {
        use std::f64::consts::PI;
        (1..4000)
            .map(|h| {
                let h = h as f64;
                2.0 * (PI * h * x).cos() * (PI * h * y).cos() / h.powi(4)
            })
            .sum()
    }

    #[test]
    fn the_criterion_is_the_cosine_kernels_pair_sum_of_the_points() {
        for (n, s, seed) in [(13usize, 4usize, 1u64), (16, 3, 2), (21, 5, 3), (30, 4, 4)] {
            let rule = lattice_rule(n, s, seed).unwrap();
            // The order-one and order-two terms of (1/n²) Σ_{k,k'} Π_j (1 + γψ) − 1,
            // summed over the pairs of written points with ψ from its Fourier series:
            // independent of the lattice algebra (the series, cut at h = 4000, agrees to
            // about 1e-9 relative).
            let rows: Vec<&[f64]> = rule.points.rows().collect();
            let (mut one, mut two) = (0.0, 0.0);
            for a in &rows {
                for b in &rows {
                    let p: Vec<f64> = a.iter().zip(*b).map(|(x, y)| psi(*x, *y)).collect();
                    one += p.iter().sum::<f64>();
                    for j in 0..s {
                        for l in j + 1..s {
                            two += p[j] * p[l];
                        }
                    }
                }
            }
            let g = TENT_WEIGHT;
            let brute = (g * one + g * g * two) / (n * n) as f64;
            assert!(
                (brute - rule.criterion).abs() < 1e-7 * brute.abs(),
                "n = {n}, s = {s}: {brute} vs {}",
                rule.criterion
            );
        }
    }

    #[test]
    fn the_points_are_the_recorded_shift_of_the_lattice() {
        for (n, s) in [(499usize, 6usize), (1000, 9)] {
            let rule = lattice_rule(n, s, 11).unwrap();
            for (k, row) in rule.points.rows().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    // frac(k z_j/n + q_j/(4n)) in floating point, then the tent transform.
                    let y = ((k as f64 * rule.generator[j] as f64) / n as f64
                        + rule.shift[j] as f64 / (4 * n) as f64)
                        .rem_euclid(1.0);
                    let x = 1.0 - (2.0 * y - 1.0).abs();
                    assert!(
                        (x - v).abs() < 1e-9,
                        "n = {n}, k = {k}, j = {j}: {x} vs {v}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_chosen_shift_is_no_worse_than_the_drawn_one() {
        for (n, s) in [(101usize, 6usize), (128, 8), (500, 10)] {
            let rule = lattice_rule(n, s, 7).unwrap();
            assert!(rule.criterion <= rule.drawn_criterion, "n = {n}, s = {s}");
        }
    }

    #[test]
    fn every_column_is_the_midpoints_at_odd_and_prime_n() {
        for (n, s) in [(499usize, 3usize), (501, 7), (997, 5), (1000, 4), (1024, 2)] {
            let rule = lattice_rule(n, s, 3).unwrap();
            for j in 0..s {
                let mut col: Vec<f64> = rule.points.rows().map(|r| r[j]).collect();
                col.sort_by(f64::total_cmp);
                for (i, v) in col.iter().enumerate() {
                    assert_eq!(*v, (2 * i + 1) as f64 / (2 * n) as f64, "n = {n}, j = {j}");
                }
                let mean = col.iter().sum::<f64>() / n as f64;
                assert!((mean - 0.5).abs() < 1e-12, "n = {n}: mean {mean}");
            }
        }
    }

    #[test]
    fn one_dimension_is_the_midpoints_in_order() {
        for n in [1usize, 2, 7, 5000] {
            let rule = lattice_rule(n, 1, 9).unwrap();
            let want: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
            assert_eq!(rule.points.as_slice(), &want[..]);
        }
    }

    #[test]
    fn the_set_does_not_depend_on_the_thread_count() {
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| lattice_rule(30_011, 6, 5).unwrap().points)
        };
        assert_eq!(run(1).as_slice(), run(3).as_slice());
        assert_ne!(
            lattice_rule(1000, 6, 5).unwrap().points.as_slice(),
            lattice_rule(1000, 6, 6).unwrap().points.as_slice(),
            "the seed selects among the shifts"
        );
    }
}
