//! The fast component-by-component step for rank-1 lattices (Nuyens and Cools 2006, *Fast
//! algorithms for component-by-component construction of rank-1 lattice rules in
//! shift-invariant reproducing kernel Hilbert spaces*, Math. Comp. 75, and *… for non-prime
//! n*, J. Complexity 22): the criterion of every candidate for the next coordinate at once,
//! in O(n log n), where trying them one by one costs O(n) each.
//!
//! With q_k the per-point Π(1 + t) − 1 of the coordinates chosen so far and t_r the
//! kernel's term at r/n, a candidate z (coprime to n) changes the criterion's sum by
//! T(z) = Σ_k q_k t_{kz mod n} plus terms that do not depend on z. Split k by
//! d = gcd(k, n): with m = n/d and k = d·u, u runs over the units U_m of Z_m, and
//! kz mod n = d·(uz mod m), so the part of T from d is Σ_{u ∈ U_m} q_{du} t_{d(uz mod m)},
//! a correlation over the group U_m. U_m is a product of cyclic groups (an odd prime
//! power's units are cyclic, 2^e's are {±1} × ⟨5⟩, and the Chinese remainder theorem joins
//! the prime powers), so in discrete-log coordinates the correlation is a cyclic one on a
//! small multi-dimensional grid, which an FFT computes for every z mod m at once. The
//! grids have φ(m) cells and Σ_{m | n} φ(m) = n, so one coordinate costs O(n log n); the
//! kernel's transforms are made once for all coordinates.
//!
//! Every block's grid has the axes of U_n's (one per odd prime of n, two for a power of
//! two from 8 on), with the same generators, each of a length dividing U_n's (1 where m
//! lacks the prime): reducing a unit mod m then reduces its discrete logs axis by axis,
//! so the blocks' values are added onto U_n's grid in order, not gathered unit by unit.

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// A factorisation: (prime, exponent) per prime, increasing.
type Factors = [(u64, u32)];

/// One block of the split: the points k = d·u, u ∈ U_m, with m = n/d ≥ 2.
struct Block {
    d: usize,
    /// The length of each axis of the grid (those of U_n's grid, 1 where m lacks the
    /// axis), outermost first.
    lens: Vec<usize>,
    /// The lengths above 1, the axes the transforms run along.
    dims: Vec<usize>,
    /// The unit u (mod m) at each cell of the grid, in row-major order.
    units: Vec<u32>,
    /// The forward transform of the kernel's terms t_{d·u} on the grid.
    kernel: Vec<Complex<f64>>,
    /// The kernel terms' Euclidean norm on the grid (for the rounding bound).
    kernel_norm: f64,
    forward: Vec<Arc<dyn Fft<f64>>>,
    inverse: Vec<Arc<dyn Fft<f64>>>,
}

/// The blocks and transforms for one n and one kernel, made once and used for every
/// coordinate.
pub(crate) struct FastCbc {
    blocks: Vec<Block>,
    /// The cell of U_n's grid (the block m = n) of each candidate.
    cells: Vec<u32>,
}

impl FastCbc {
    /// Plans the blocks of n = terms.len() points for the kernel terms t_r at r/n, to
    /// score the `candidates` (units of Z_n).
    pub(crate) fn new(terms: &[f64], candidates: &[u64]) -> FastCbc {
        let n = terms.len();
        let mut planner = FftPlanner::new();
        let factors = factorize(n as u64);
        let axes = unit_axes(&factors);
        // Short axes outermost: the long ones are contiguous.
        let mut order: Vec<usize> = (0..axes.len()).collect();
        order.sort_by_key(|&i| axes[i].0);
        let blocks: Vec<Block> = divisors(&factors)
            .into_iter()
            .filter(|(m, _)| *m >= 2)
            .map(|(m, mf)| Block::new(n, m as usize, (&factors, &mf), &order, terms, &mut planner))
            .collect();
        let whole = blocks.last().expect("n ≥ 2 has the block m = n");
        let mut cell = vec![u32::MAX; n];
        for (i, &u) in whole.units.iter().enumerate() {
            cell[u as usize] = i as u32;
        }
        let cells = candidates.iter().map(|&z| cell[z as usize]).collect();
        FastCbc { blocks, cells }
    }

    /// T(z) = Σ_{k, gcd(k, n) < n} q_k t_{kz mod n} for each candidate z given to
    /// [`FastCbc::new`], and a bound on the rounding of the transforms in them. The sums
    /// over the blocks are taken in one fixed order, so the values do not depend on the
    /// number of threads.
    pub(crate) fn scores(&self, q: &[f64]) -> (Vec<f64>, f64) {
        let parts: Vec<(Vec<f64>, f64)> = self.blocks.par_iter().map(|b| b.correlate(q)).collect();
        let bound = parts.iter().map(|p| p.1).sum();
        let whole = self.blocks.last().expect("n ≥ 2 has the block m = n");
        let mut grid = vec![0.0f64; whole.units.len()];
        // Split along U_n's outermost axis: each part adds every block in the same order.
        let outer = whole.lens.first().copied().unwrap_or(1);
        let inner = grid.len() / outer;
        grid.par_chunks_mut(inner)
            .enumerate()
            .for_each(|(a, part)| {
                for (block, (corr, _)) in self.blocks.iter().zip(&parts) {
                    let len = block.lens.first().copied().unwrap_or(1);
                    let from = &corr[(a % len) * (corr.len() / len)..][..corr.len() / len];
                    add_onto(part, tail(&whole.lens), from, tail(&block.lens));
                }
            });
        (
            self.cells.iter().map(|&c| grid[c as usize]).collect(),
            bound,
        )
    }
}

/// The lengths after the outermost.
fn tail(lens: &[usize]) -> &[usize] {
    lens.get(1..).unwrap_or(&[])
}

/// Adds the values of a grid of lengths `lens` onto the grid `out` of lengths `out_lens`
/// (row-major, each length of the first dividing the second's), cell a taking the value
/// at a mod lens.
fn add_onto(out: &mut [f64], out_lens: &[usize], from: &[f64], lens: &[usize]) {
    match (out_lens, lens) {
        ([], _) => out[0] += from[0],
        ([_], [len]) => {
            for chunk in out.chunks_mut(*len) {
                for (o, f) in chunk.iter_mut().zip(from) {
                    *o += f;
                }
            }
        }
        ([outer, rest @ ..], [len, inner_lens @ ..]) => {
            let (out_inner, inner) = (out.len() / outer, from.len() / len);
            for (a, part) in out.chunks_mut(out_inner).enumerate() {
                add_onto(part, rest, &from[(a % len) * inner..][..inner], inner_lens);
            }
        }
        _ => unreachable!("the grids have as many axes"),
    }
}

impl Block {
    fn new(
        n: usize,
        m: usize,
        (n_factors, factors): (&Factors, &Factors),
        order: &[usize],
        terms: &[f64],
        planner: &mut FftPlanner<f64>,
    ) -> Block {
        let d = n / m;
        let axes = unit_group(m as u64, n_factors, factors);
        let mut units = vec![1u64];
        for &(len, g) in order.iter().map(|&i| &axes[i]) {
            let mut next = Vec::with_capacity(units.len() * len);
            for &u in &units {
                let mut x = u;
                for _ in 0..len {
                    next.push(x);
                    x = mul_mod(x, g, m as u64);
                }
            }
            units = next;
        }
        let units: Vec<u32> = units.into_iter().map(|u| u as u32).collect();
        let lens: Vec<usize> = order.iter().map(|&i| axes[i].0).collect();
        let dims: Vec<usize> = lens.iter().copied().filter(|&l| l > 1).collect();
        let forward: Vec<_> = dims.iter().map(|&l| planner.plan_fft_forward(l)).collect();
        let inverse: Vec<_> = dims.iter().map(|&l| planner.plan_fft_inverse(l)).collect();
        let mut kernel: Vec<Complex<f64>> = units
            .iter()
            .map(|&u| Complex::new(terms[d * u as usize], 0.0))
            .collect();
        let kernel_norm = kernel.iter().map(|c| c.re * c.re).sum::<f64>().sqrt();
        transform(&mut kernel, &dims, &forward);
        Block {
            d,
            lens,
            dims,
            units,
            kernel,
            kernel_norm,
            forward,
            inverse,
        }
    }

    /// Σ_{u ∈ U_m} q_{du} t_{d(uz mod m)} at each cell of z on the grid, and a bound on
    /// its rounding.
    fn correlate(&self, q: &[f64]) -> (Vec<f64>, f64) {
        let mut buf: Vec<Complex<f64>> = self
            .units
            .iter()
            .map(|&u| Complex::new(q[self.d * u as usize], 0.0))
            .collect();
        let norm = buf.iter().map(|c| c.re * c.re).sum::<f64>().sqrt();
        transform(&mut buf, &self.dims, &self.forward);
        // Σ_e A(e) B(e + f) has the transform conj(Â)·B̂ for real A.
        for (x, k) in buf.iter_mut().zip(&self.kernel) {
            *x = x.conj() * k;
        }
        transform(&mut buf, &self.dims, &self.inverse);
        let cells = buf.len() as f64;
        let corr = buf.iter().map(|x| x.re / cells).collect();
        // A transform's rounding per entry is a few ulps of the norms times log₂ of its
        // length (Higham, *Accuracy and Stability of Numerical Algorithms*, §24.1).
        let bound = 8.0 * f64::EPSILON * (1.0 + cells.log2()) * norm * self.kernel_norm;
        (corr, bound)
    }
}

/// The multi-dimensional transform of `buf` (row-major on `dims`), axis by axis; the
/// axes other than the last are transposed to be contiguous.
fn transform(buf: &mut [Complex<f64>], dims: &[usize], plans: &[Arc<dyn Fft<f64>>]) {
    let mut inner = buf.len();
    for (&len, plan) in dims.iter().zip(plans) {
        inner /= len;
        let mut scratch = vec![Complex::new(0.0, 0.0); plan.get_inplace_scratch_len()];
        if inner == 1 {
            plan.process_with_scratch(buf, &mut scratch);
            continue;
        }
        let mut lines = vec![Complex::new(0.0, 0.0); len * inner];
        for chunk in buf.chunks_mut(len * inner) {
            for i in 0..len {
                for off in 0..inner {
                    lines[off * len + i] = chunk[i * inner + off];
                }
            }
            plan.process_with_scratch(&mut lines, &mut scratch);
            for i in 0..len {
                for off in 0..inner {
                    chunk[i * inner + off] = lines[off * len + i];
                }
            }
        }
    }
}

pub(super) fn mul_mod(a: u64, b: u64, m: u64) -> u64 {
    ((u128::from(a) * u128::from(b)) % u128::from(m)) as u64
}

fn pow_mod(mut a: u64, mut e: u64, m: u64) -> u64 {
    let mut r = 1 % m;
    a %= m;
    while e > 0 {
        if e & 1 == 1 {
            r = mul_mod(r, a, m);
        }
        a = mul_mod(a, a, m);
        e >>= 1;
    }
    r
}

/// The prime factorisation of n ≥ 1, primes increasing.
fn factorize(mut n: u64) -> Vec<(u64, u32)> {
    let mut out = Vec::new();
    let mut p = 2u64;
    while p * p <= n {
        if n.is_multiple_of(p) {
            let mut e = 0;
            while n.is_multiple_of(p) {
                n /= p;
                e += 1;
            }
            out.push((p, e));
        }
        p += 1;
    }
    if n > 1 {
        out.push((n, 1));
    }
    out
}

/// Every divisor of the number factorised as `factors`, each with its own factorisation.
fn divisors(factors: &Factors) -> Vec<(u64, Vec<(u64, u32)>)> {
    let mut out = vec![(1u64, Vec::new())];
    for &(p, e) in factors {
        let mut next = Vec::with_capacity(out.len() * (e as usize + 1));
        for (m, f) in &out {
            let mut pk = 1u64;
            for k in 0..=e {
                let mut fk = f.clone();
                if k > 0 {
                    fk.push((p, k));
                }
                next.push((m * pk, fk));
                pk *= p;
            }
        }
        out = next;
    }
    out
}

/// The inverse of a modulo m (gcd(a, m) = 1; 0 for m = 1).
pub(super) fn inverse_mod(a: u64, m: u64) -> u64 {
    let (mut r0, mut r1) = (i128::from(m), i128::from(a % m));
    let (mut s0, mut s1) = (0i128, 1i128);
    while r1 != 0 {
        let t = r0 / r1;
        (r0, r1) = (r1, r0 - t * r1);
        (s0, s1) = (s1, s0 - t * s1);
    }
    s0.rem_euclid(i128::from(m)) as u64
}

/// The smallest primitive root modulo the odd prime p that is also one modulo p².
fn primitive_root(p: u64) -> u64 {
    let orders: Vec<u64> = factorize(p - 1).iter().map(|&(r, _)| (p - 1) / r).collect();
    let g = (2..p)
        .find(|&g| orders.iter().all(|&o| pow_mod(g, o, p) != 1))
        .unwrap_or(1);
    // g generates U_{p^e} for every e unless g^(p−1) ≡ 1 (mod p²); then g + p does.
    if pow_mod(g, p - 1, p * p) == 1 {
        g + p
    } else {
        g
    }
}

/// The axes of U_n's grid for the factorisation of n: (prime, which) per axis, `which`
/// 0 for an odd prime's generator or −1 and 1 for 5 (powers of two from 4 and from 8 on).
fn unit_axes(n_factors: &Factors) -> Vec<(usize, (u64, u8))> {
    let mut axes = Vec::new();
    for &(p, e) in n_factors {
        if p == 2 {
            if e >= 2 {
                axes.push((2, (2, 0)));
            }
            if e >= 3 {
                axes.push((1 << (e - 2), (2, 1)));
            }
        } else {
            axes.push(((p - 1) as usize * p.pow(e - 1) as usize, (p, 0)));
        }
    }
    axes
}

/// U_m (m | n) as a product of cyclic groups on the axes of U_n's grid
/// ([`unit_axes`]): (order, generator mod m) per axis, order 1 where m lacks it, each
/// generator one modulo the other prime powers of m and the same modulo its own as
/// U_n's, so that reducing mod m reduces the discrete logs axis by axis.
fn unit_group(m: u64, n_factors: &Factors, m_factors: &Factors) -> Vec<(usize, u64)> {
    unit_axes(n_factors)
        .into_iter()
        .map(|(_, (p, which))| {
            let e = m_factors.iter().find(|f| f.0 == p).map_or(0, |f| f.1);
            let pe = p.pow(e);
            let rest = m / pe;
            // x ≡ g (mod p^e), x ≡ 1 (mod the rest).
            let lift = |g: u64| {
                let t = mul_mod((g + pe - 1) % pe, inverse_mod(rest % pe, pe), pe);
                (1 + rest * t) % m
            };
            match (p, which, e) {
                (_, _, 0) => (1, 1 % m),
                (2, 0, e) if e >= 2 => (2, lift(pe - 1)),
                (2, 1, e) if e >= 3 => ((pe / 4) as usize, lift(5)),
                (2, _, _) => (1, 1 % m),
                _ => (((p - 1) * pe / p) as usize, lift(primitive_root(p))),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gcd(mut a: u64, mut b: u64) -> u64 {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    }

    #[test]
    fn the_grids_enumerate_each_unit_group_once() {
        for m in 2..=600u64 {
            let f = factorize(m);
            let axes = unit_group(m, &f, &f);
            let order: Vec<usize> = (0..axes.len()).collect();
            let terms = vec![0.0; m as usize];
            let block = Block::new(
                m as usize,
                m as usize,
                (&f, &f),
                &order,
                &terms,
                &mut FftPlanner::new(),
            );
            let mut got: Vec<u64> = block.units.iter().map(|&u| u64::from(u)).collect();
            got.sort_unstable();
            let want: Vec<u64> = (1..m).filter(|&u| gcd(u, m) == 1).collect();
            assert_eq!(got, want, "m = {m}, axes {axes:?}");
        }
    }

    #[test]
    fn the_scores_are_the_direct_sums() {
        // Arbitrary q and t: every candidate's T(z) against Σ_{k ≥ 1} q_k t_{kz mod n}.
        for n in [12usize, 30, 64, 97, 210, 243, 250, 720, 1000] {
            let terms: Vec<f64> = (0..n).map(|r| ((r * r % 17) as f64 - 8.0) / 9.0).collect();
            let q: Vec<f64> = (0..n).map(|k| ((k * 7 % 11) as f64 - 5.0) / 4.0).collect();
            let cands: Vec<u64> = (1..n as u64).filter(|&z| gcd(z, n as u64) == 1).collect();
            let (got, bound) = FastCbc::new(&terms, &cands).scores(&q);
            for (&z, &g) in cands.iter().zip(&got) {
                let direct: f64 = (1..n)
                    .map(|k| q[k] * terms[k * z as usize % n])
                    .sum::<f64>();
                assert!(
                    (g - direct).abs() <= bound + 1e-12,
                    "n = {n}, z = {z}: {g} {direct}"
                );
            }
            assert!(bound < 1e-10, "{bound}");
        }
    }
}
