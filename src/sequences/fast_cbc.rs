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

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// One block of the split: the points k = d·u, u ∈ U_m, with m = n/d ≥ 2.
struct Block {
    m: usize,
    d: usize,
    /// The lengths of the cyclic factors of U_m, outermost first.
    dims: Vec<usize>,
    /// The unit u (mod m) at each cell of the grid, in row-major order.
    units: Vec<u32>,
    /// The cell of each residue mod m (unused where it is not a unit).
    cell: Vec<u32>,
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
}

impl FastCbc {
    /// Plans the blocks of n = terms.len() points for the kernel terms t_r at r/n.
    pub(crate) fn new(terms: &[f64]) -> FastCbc {
        let n = terms.len();
        let mut planner = FftPlanner::new();
        let factors = factorize(n as u64);
        let blocks = divisors(&factors)
            .into_iter()
            .filter(|(m, _)| *m >= 2)
            .map(|(m, mf)| Block::new(n, m as usize, &mf, terms, &mut planner))
            .collect();
        FastCbc { blocks }
    }

    /// T(z) = Σ_{k, gcd(k, n) < n} q_k t_{kz mod n} for each candidate z (coprime to n, in
    /// increasing order), and a bound on the rounding of the transforms in them. The sums
    /// over the blocks are taken in one fixed order, so the values do not depend on the
    /// number of threads.
    pub(crate) fn scores(&self, q: &[f64], candidates: &[u64]) -> (Vec<f64>, f64) {
        let parts: Vec<(Vec<f64>, f64)> = self.blocks.par_iter().map(|b| b.correlate(q)).collect();
        let bound = parts.iter().map(|p| p.1).sum();
        let mut out = vec![0.0f64; candidates.len()];
        out.par_chunks_mut(4096)
            .zip(candidates.par_chunks(4096))
            .for_each(|(out, zs)| {
                for (block, (corr, _)) in self.blocks.iter().zip(&parts) {
                    let m = block.m as u64;
                    let mut prev = zs[0];
                    let mut r = prev % m;
                    for (o, &z) in out.iter_mut().zip(zs) {
                        // z mod m carried from the previous candidate: the gaps are small.
                        r += z - prev;
                        while r >= m {
                            r -= m;
                        }
                        prev = z;
                        *o += corr[block.cell[r as usize] as usize];
                    }
                }
            });
        (out, bound)
    }
}

impl Block {
    fn new(
        n: usize,
        m: usize,
        factors: &[(u64, u32)],
        terms: &[f64],
        planner: &mut FftPlanner<f64>,
    ) -> Block {
        let d = n / m;
        let axes = unit_group(m as u64, factors);
        let mut units = vec![1u64];
        for &(len, g) in &axes {
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
        let mut cell = vec![u32::MAX; m];
        for (i, &u) in units.iter().enumerate() {
            cell[u as usize] = i as u32;
        }
        let dims: Vec<usize> = axes.iter().map(|a| a.0).collect();
        let forward: Vec<_> = dims.iter().map(|&l| planner.plan_fft_forward(l)).collect();
        let inverse: Vec<_> = dims.iter().map(|&l| planner.plan_fft_inverse(l)).collect();
        let mut kernel: Vec<Complex<f64>> = units
            .iter()
            .map(|&u| Complex::new(terms[d * u as usize], 0.0))
            .collect();
        let kernel_norm = kernel.iter().map(|c| c.re * c.re).sum::<f64>().sqrt();
        transform(&mut kernel, &dims, &forward);
        Block {
            m,
            d,
            dims,
            units,
            cell,
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

fn mul_mod(a: u64, b: u64, m: u64) -> u64 {
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
fn divisors(factors: &[(u64, u32)]) -> Vec<(u64, Vec<(u64, u32)>)> {
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

/// The inverse of a modulo m (gcd(a, m) = 1).
fn inverse_mod(a: u64, m: u64) -> u64 {
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

/// U_m as a product of cyclic groups: (order, generator mod m) per factor, the generator
/// one modulo the other prime powers of m.
fn unit_group(m: u64, factors: &[(u64, u32)]) -> Vec<(usize, u64)> {
    let mut axes = Vec::new();
    for &(p, e) in factors {
        let pe = p.pow(e);
        let rest = m / pe;
        // x ≡ g (mod p^e), x ≡ 1 (mod the rest).
        let lift = |g: u64| {
            let t = mul_mod((g + pe - 1) % pe, inverse_mod(rest % pe, pe), pe);
            (1 + rest * t) % m
        };
        if p == 2 {
            if e >= 2 {
                axes.push((2, lift(pe - 1)));
            }
            if e >= 3 {
                axes.push(((pe / 4) as usize, lift(5)));
            }
        } else {
            axes.push((((p - 1) * pe / p) as usize, lift(primitive_root(p))));
        }
    }
    axes
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
            let axes = unit_group(m, &f);
            let terms = vec![0.0; m as usize];
            let block = Block::new(m as usize, m as usize, &f, &terms, &mut FftPlanner::new());
            let mut got: Vec<u64> = block.units.iter().map(|&u| u64::from(u)).collect();
            got.sort_unstable();
            let want: Vec<u64> = (1..m).filter(|&u| gcd(u, m) == 1).collect();
            assert_eq!(got, want, "m = {m}, axes {axes:?}");
        }
    }

    #[test]
    fn the_scores_are_the_direct_sums() {
        // Arbitrary q and t: every candidate's T(z) against Σ_{k ≥ 1} q_k t_{kz mod n}.
        for n in [12usize, 30, 64, 97, 210, 243, 250] {
            let terms: Vec<f64> = (0..n).map(|r| ((r * r % 17) as f64 - 8.0) / 9.0).collect();
            let q: Vec<f64> = (0..n).map(|k| ((k * 7 % 11) as f64 - 5.0) / 4.0).collect();
            let cands: Vec<u64> = (1..n as u64).filter(|&z| gcd(z, n as u64) == 1).collect();
            let (got, bound) = FastCbc::new(&terms).scores(&q, &cands);
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
