//! Every pair figure of a quality report in one pass over the pairs: the pair sums of the
//! five discrepancies (star, modified, centred, wrap-around L2 and mixture), the smallest
//! squared Euclidean and torus distances, and the pair sum of U_{q,p} where its distance
//! is one the pass forms anyway (q = 1, q = ∞, Euclidean).
//!
//! Each figure has the same bits as the pass of its own (the five of
//! [`crate::discrepancy::squared_discrepancies_with_mixture`],
//! [`crate::pairs::min_squared_distances`], [`Energy::value`] of [`Uqp`]): the same
//! tiles, added in the same order, each lane forming its products and sums with the same
//! operations in the same order, so fusing changes no value. What the figures share is
//! formed once per pair and coordinate: the difference d = |x − y|, max(x, y) (the star
//! and modified factors are 1 − max(x, y) and 2 − max(x, y), as in their own passes),
//! 1 − d, d(1 − d) (the wrap-around factor's and the q = 1 distance's h), and the torus
//! difference min(d, 1 − d). Terms of one point only (1 + ½|x − ½| and 15/8 − ¼|x − ½|,
//! the first steps of the centred and mixture factors) are formed once per point.
//!
//! The centred and mixture factors take ½d in a − ½d and ½d − ¾, with
//! a = 1 + ½|x − ½| + ½|y − ½| ≥ 1. The pass forms each as one multiply-add, fused on
//! AVX2 and AVX-512 and not on the portable path, and all have the bits of the passes of
//! their own,
//! which round ½d first: ½d is exact unless d < 2^−1021, and then both exact results lie
//! within 2^−1022 of a (or of −¾), far inside half a unit in its last place, so both
//! round to it. Fusing saves an operation per pair and coordinate, and reading
//! max(x, y) rather than min(1 − x, 1 − y) and min(2 − x, 2 − y) saves the four loads of
//! 1 − x, 1 − y, 2 − x and 2 − y: the loop is bound by its loads and its additions.
//!
//! The tiles' 16 lanes are worked as four vectors of four, one after the other: the
//! running products and sums of four lanes fit the 16 vector registers, where 16 lanes of
//! them would be spilled to memory at every coordinate. Each lane still accumulates the
//! same pairs in the same order as in the 16-lane passes. The powers d^{−p} of U_{q,p}
//! (long chains of dependent operations) are taken a row at a time, 32 lanes at once, so
//! that independent chains overlap.
//!
//! Where the processor has AVX-512 the 16 lanes are two vectors of eight, each two of
//! those parts side by side, and the other points are laid out eight at a time: every
//! lane does the operations of the four-lane builds on the same pairs in the same order,
//! and each part's sums are still added as the four-lane `hsum` adds them, part after
//! part. Zen 4 splits each 512-bit operation in two, so the arithmetic takes as long,
//! but half the instructions do it: with them the pass takes about a quarter less time
//! (0.54 s against 0.70 s for `eval` at n = 10 000, s = 20 on one core).
//!
//! Where the energy does not need every pair's distances (none, or q = 1), the two
//! minimum distances are formed only for the groups of four pairs that may hold a pair
//! closer than one already found: Σ_k h_k² with h = d(1 − d), which the pass forms anyway,
//! is at most the squared torus distance, itself at most the Euclidean one, even after
//! rounding. A minimum does not depend on which larger values were left out, so the
//! result has the same bits whatever the order the tiles find their pairs in.

use crate::discrepancy::squares_from_pair_sums;
use crate::pairs::{
    sum_tiles_on, use_avx2, use_avx512, AlignedBuf, Blocks, Build, Simd, SumTiles, Wide,
};
use crate::uqp::PairPow;
use crate::{Distance, Energy, PointSet, Uqp};
use std::sync::atomic::{AtomicU64, Ordering};

/// The pair figures of a report; see [`pair_figures`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairFigures {
    /// The squared star, modified, centred, wrap-around L2 and mixture discrepancies, not
    /// clamped: the values of [`crate::discrepancy::squared_discrepancies_with_mixture`].
    pub squares: [f64; 5],
    /// The smallest squared Euclidean and torus distances (+∞ without a pair): the values
    /// of [`crate::pairs::min_squared_distances`].
    pub min_squared_distances: [f64; 2],
    /// The energy's value when one was asked for: [`Energy::value`].
    pub energy: Option<f64>,
}

/// Which U_{q,p} distance the pass accumulates (`NONE`: none).
const NONE: u8 = 0;
/// q = 1: h = d(1 − d) on the torus difference, the wrap-around factor's own d(1 − d).
const Q1: u8 = 1;
/// q = ∞: the torus distance itself.
const TORUS: u8 = 2;
/// The Euclidean distance itself.
const EUCLIDEAN: u8 = 3;

/// The pass's kind for `energy`, or `None` when its distance must be formed by a pass of
/// its own. The periodic kinds read the coordinates reduced to [0, 1) (x − ⌊x⌋); the pass
/// uses the coordinates as they are, the same only when every one is in [0, 1).
fn fused_kind(energy: &Uqp, points: &PointSet) -> Option<u8> {
    let in_unit = || points.as_slice().iter().all(|v| (0.0..1.0).contains(v));
    match energy.distance() {
        Distance::Euclidean => Some(EUCLIDEAN),
        Distance::Q(q) if q == 1.0 && in_unit() => Some(Q1),
        Distance::Torus if in_unit() => Some(TORUS),
        _ => None,
    }
}

/// The five squared discrepancies, the two smallest squared distances and, when `energy`
/// is given, its value, from one pass over the pairs where the energy's distance allows
/// (see the module documentation; otherwise the energy takes a pass of its own). Every
/// value has the same bits as the function that computes it alone, for any number of
/// threads. The points must lie in [0, 1]^s (not checked), and the closed forms overflow
/// where [`crate::discrepancy::closed_form_fits`] says so. O(n² s) time, O(n s) memory.
pub fn pair_figures(points: &PointSet, energy: Option<&Uqp>) -> PairFigures {
    let build = if use_avx512() {
        Build::Avx512
    } else if use_avx2() {
        Build::Avx2
    } else {
        Build::Portable
    };
    figures_on(build, points, energy)
}

/// [`pair_figures`] on the given build (see [`sum_tiles_on`]).
fn figures_on(build: Build, points: &PointSet, energy: Option<&Uqp>) -> PairFigures {
    let (n, s) = (points.n(), points.s());
    let kind = energy.and_then(|e| fused_kind(e, points));
    let p = energy.map_or(1.0, Uqp::p);
    let sums = if n < 2 {
        [0.0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY, f64::INFINITY, 0.0]
    } else {
        let blocks = Blocks::new(n, s);
        match kind {
            None => pass::<NONE>(build, &blocks, points, p),
            Some(Q1) => pass::<Q1>(build, &blocks, points, p),
            Some(TORUS) => pass::<TORUS>(build, &blocks, points, p),
            Some(_) => pass::<EUCLIDEAN>(build, &blocks, points, p),
        }
    };
    let energy = energy.map(|e| match kind {
        Some(_) if n >= 2 => sums[7].powf(1.0 / e.p()),
        Some(_) => 0.0,
        None => e.value(points),
    });
    PairFigures {
        squares: squares_from_pair_sums(points, std::array::from_fn(|m| sums[m])),
        min_squared_distances: [sums[5], sums[6]],
        energy,
    }
}

/// Values per point and coordinate in [`Lanes`]: the coordinate and four terms of it.
const FIELDS: usize = 3;

/// Lanes of the parts of a tile's lanes whose sums the pass keeps in the order of the
/// 16-lane passes (see the module documentation).
const LANE: usize = 4;

/// The coordinates and the per-point terms the pass reads, laid out so that one vector of
/// `width` points reads its s coordinates from one contiguous run: per block of
/// [`Blocks`], per group of `width` points, per coordinate k, the [`FIELDS`] values of
/// the group's points, `width` at a time (zeros for the padding).
struct Lanes {
    values: AlignedBuf,
    /// Points per group: the lanes of the build's base vector.
    width: usize,
    /// Values per group (s·FIELDS·width).
    group: usize,
}

impl Lanes {
    fn new(
        blocks: &Blocks,
        x: &[f64],
        width: usize,
        fields: impl Fn(f64) -> [f64; FIELDS],
    ) -> Lanes {
        let s = blocks.s;
        let group = s * FIELDS * width;
        let mut values = AlignedBuf::zeros(blocks.real * blocks.bs / width * group);
        for (i, row) in x.chunks_exact(s).enumerate() {
            let g = (i / blocks.bs) * (blocks.bs / width) + (i % blocks.bs) / width;
            let lane = i % width;
            for (k, &v) in row.iter().enumerate() {
                let at = g * group + k * FIELDS * width + lane;
                for (f, value) in fields(v).into_iter().enumerate() {
                    values[at + f * width] = value;
                }
            }
        }
        Lanes {
            values,
            width,
            group,
        }
    }

    /// The run of the group of points from j0 of block b (j0 a multiple of `width`).
    #[inline(always)]
    fn group(&self, blocks: &Blocks, b: usize, j0: usize) -> &[f64] {
        let g = b * (blocks.bs / self.width) + j0 / self.width;
        &self.values[g * self.group..(g + 1) * self.group]
    }
}

/// ½|x − ½|, the centred and mixture factors' term of one point.
fn gap(v: f64) -> f64 {
    0.5 * (v - 0.5).abs()
}

/// The eight sums of the pass: five pair product sums, two minima, the energy's pair sum.
fn pass<const E: u8>(build: Build, blocks: &Blocks, points: &PointSet, p: f64) -> [f64; 8] {
    let x = points.as_slice();
    let tiles = Tiles::<E> {
        blocks,
        bound: AtomicU64::new(f64::INFINITY.to_bits()),
        x,
        // The other point's y, ½|y − ½| and ½·½|y − ½|.
        lanes: Lanes::new(blocks, x, base_lanes(build), |v| [v, gap(v), 0.5 * gap(v)]),
        pow: PairPow::new(p),
    };
    let zero = [0.0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY, f64::INFINITY, 0.0];
    sum_tiles_on(
        build,
        blocks,
        &tiles,
        || zero,
        |a, b| {
            std::array::from_fn(|m| match m {
                5 | 6 => a[m].min(b[m]),
                _ => a[m] + b[m],
            })
        },
    )
}

struct Tiles<'a, const E: u8> {
    blocks: &'a Blocks,
    /// The smallest squared Euclidean distance the tiles have found, as f64 bits.
    bound: AtomicU64,
    /// The points, row by row.
    x: &'a [f64],
    lanes: Lanes,
    pow: PairPow,
}

/// Base vectors in a tile's 16 lanes, at most: four of four lanes (see the module
/// documentation), or two of eight.
const PARTS: usize = 4;

/// The lanes of `build`'s base vector ([`Simd::Base`]).
fn base_lanes(build: Build) -> usize {
    match build {
        Build::Avx512 => 2 * LANE,
        Build::Avx2 | Build::Portable => LANE,
    }
}

/// One vector's running sums, kept per part of the tile's lanes: the five products' sums,
/// the two minima, the energy's sum.
#[derive(Clone, Copy)]
struct Acc<B> {
    products: [B; 5],
    mins: [B; 2],
    energy: B,
}

impl<const E: u8> SumTiles for Tiles<'_, E> {
    type Out = [f64; 8];

    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize) -> [f64; 8] {
        let bl = self.blocks;
        let s = bl.s;
        // A base vector holds one or two of the parts of four lanes.
        let w = <V::Base as Simd>::N;
        let parts = V::N / w;
        assert!(
            V::N == 16 && w % LANE == 0 && parts * w == V::N && w == self.lanes.width,
            "a tile's 16 lanes in base vectors of the lanes' width, parts of four"
        );
        let (zero, inf) = (V::Base::splat(0.0), V::Base::splat(f64::INFINITY));
        let mut acc = [Acc {
            products: [zero; 5],
            mins: [inf; 2],
            energy: zero,
        }; PARTS];
        // Point i's x, 1 + ½|x − ½| and 15/8 − ½·½|x − ½| per coordinate, each in every
        // lane: the first steps of the factors, once per point.
        let mut own = AlignedBuf::zeros(s * FIELDS * w);
        // The energy's squared distances of a row, for its powers.
        let mut row = AlignedBuf::zeros(bl.bs);
        // Their powers d^{−p}.
        let mut powers = AlignedBuf::zeros(bl.bs);
        let len_b = bl.len(b);
        // The smallest squared Euclidean distance found so far, as non-negative f64 bits
        // (whose order as integers is that of the values).
        let mut bound = f64::from_bits(self.bound.load(Ordering::Relaxed));
        for ii in 0..bl.len(a) {
            // The lane groups of `Blocks::lanes`: from the group holding ii + 1 on the
            // diagonal; a base vector whose lanes are all masked would add 0 and take
            // the minimum with +∞, which changes nothing, so it is skipped. (Nor does it
            // change a sum that starts at +0, which never becomes −0: a half of eight
            // lanes that four-lane parts would skip is added.)
            let lo = if a == b { ii + 1 } else { 0 };
            if lo >= len_b {
                continue;
            }
            let i = a * bl.bs + ii;
            for (o, &v) in own
                .chunks_exact_mut(FIELDS * w)
                .zip(&self.x[i * s..(i + 1) * s])
            {
                let g = gap(v);
                let fields = [v, 1.0 + g, 1.875 - 0.5 * g];
                // Vector stores: as a loop of lanes, the compiler made it scatters.
                for (f, value) in o.chunks_exact_mut(w).zip(fields) {
                    V::Base::splat(value).store(f);
                }
            }
            let start = if a == b { lo / V::N * V::N } else { 0 };
            for jj in (start..len_b).step_by(V::N) {
                for (u, acc) in acc.iter_mut().enumerate().take(parts) {
                    let j0 = jj + u * w;
                    if j0 + w <= lo || j0 >= len_b {
                        continue;
                    }
                    let mask = group_mask::<V::Base>(j0, lo, len_b);
                    let other = self.lanes.group(bl, b, j0);
                    let d2 = self.pair_terms::<V::Base>(&own, other, mask, acc);
                    d2.store(&mut row[j0..]);
                    // Σ h² ≤ the squared torus distance ≤ the squared Euclidean one, term
                    // by term and so after rounding (h = d(1 − d) ≤ min(d, 1 − d) ≤ d):
                    // a group none of whose Σ h² is below a squared Euclidean distance
                    // already found cannot lower either minimum.
                    if Self::PRUNE && mask.and(d2.lt(V::Base::splat(bound))).any() {
                        let de = self.distances::<V::Base>(&own, other, mask, acc);
                        bound = bound.min(de);
                    }
                }
            }
            if Self::PRUNE {
                // Share the bound with the other tiles. The minima do not depend on when
                // it is read: any bound is a distance of a pair, at least the minimum.
                let shared = self.bound.fetch_min(bound.to_bits(), Ordering::Relaxed);
                bound = bound.min(f64::from_bits(shared));
            }
            if E != NONE {
                // The powers of the row after its sums, on twice the tile's lanes at once
                // where the row allows: a power is a long chain of dependent operations,
                // and the chains side by side overlap (each lane's value is its own).
                let mut jj = start;
                while jj < len_b {
                    let two = jj + 2 * V::N <= row.len();
                    if two {
                        self.pow
                            .eval(Wide::<V, 2>::load(&row[jj..]))
                            .store(&mut powers[jj..]);
                    } else {
                        self.pow.eval(V::load(&row[jj..])).store(&mut powers[jj..]);
                    }
                    jj += if two { 2 * V::N } else { V::N };
                }
                for jj in (start..len_b).step_by(V::N) {
                    for (u, acc) in acc.iter_mut().enumerate().take(parts) {
                        let j0 = jj + u * w;
                        if j0 + w <= lo || j0 >= len_b {
                            continue;
                        }
                        let e = V::Base::load(&powers[j0..]);
                        let mask = group_mask::<V::Base>(j0, lo, len_b);
                        acc.energy = acc.energy.add(mask.select(e, zero));
                    }
                }
            }
        }
        let mut out = [0.0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY, f64::INFINITY, 0.0];
        // As the 16-lane vectors add and take the minimum of their parts of four, in lane
        // order, each part's lanes summed as the four-lane builds' `hsum` sums them.
        let mut lanes = [0.0; 16];
        let mut add = |o: &mut f64, v: V::Base| {
            v.store(&mut lanes);
            for q in lanes[..w].chunks_exact(LANE) {
                *o += (q[0] + q[1]) + (q[2] + q[3]);
            }
        };
        for acc in &acc[..parts] {
            for (o, &v) in out.iter_mut().zip(&acc.products) {
                add(o, v);
            }
            out[5] = out[5].min(acc.mins[0].hmin());
            out[6] = out[6].min(acc.mins[1].hmin());
            add(&mut out[7], acc.energy);
        }
        out
    }
}

impl<const E: u8> Tiles<'_, E> {
    /// Whether the minimum distances are formed only for the groups that may hold a
    /// closer pair than one already found (see `tile`): where the energy does not need
    /// the distances of every pair.
    const PRUNE: bool = E == NONE || E == Q1;

    /// One point (`own`, see `tile`) against a group of four (`other`, a run of
    /// [`Lanes`]; the lanes of `mask`): every factor and distance term with the same
    /// operations as the passes of their own (`centered_factor`, `mixture_factor`,
    /// `Wrap::vpair`, `MinDistances`, `VecQ1::h2`), added into `acc`. Returns the
    /// energy's squared distances (0 without an energy).
    #[inline(always)]
    fn pair_terms<B: Simd>(&self, own: &[f64], other: &[f64], mask: B, acc: &mut Acc<B>) -> B {
        let (one, two) = (B::splat(1.0), B::splat(2.0));
        let (half, minus_half) = (B::splat(0.5), B::splat(-0.5));
        let zero = B::splat(0.0);
        let mut p = [one; 5];
        let (mut de, mut dp, mut du) = (zero, zero, zero);
        let step = FIELDS * B::N;
        for (o, c) in own.chunks_exact(step).zip(other.chunks_exact(step)) {
            let field = |f: &[f64], k: usize| B::load(&f[k * B::N..(k + 1) * B::N]);
            let (x, y) = (field(o, 0), field(c, 0));
            let d = x.sub(y).abs();
            let m = x.max(y);
            p[0] = p[0].mul(one.sub(m));
            p[1] = p[1].mul(two.sub(m));
            // a − ½d and ½d − ¾ as one multiply-add each, fused or not: the same bits as
            // rounding ½d first (see the module documentation).
            let sum = field(o, 1).add(field(c, 1));
            p[2] = p[2].mul(minus_half.mul_add(d, sum));
            let omd = one.sub(d);
            let t = d.mul(omd);
            p[3] = p[3].mul(B::splat(1.5).sub(t));
            let quad = d.mul(half.mul_add(d, B::splat(-0.75)));
            let mixed = field(o, 2).sub(field(c, 2));
            p[4] = p[4].mul(mixed.add(quad));
            if Self::PRUNE {
                // h = |δ|(1 − |δ|) is d(1 − d) both below ½ and above (1 − (1 − d) = d
                // exactly there): U_{q,p}'s h for q = 1, and the bound of the distances.
                du = du.add(t.mul(t));
            } else {
                de = de.add(d.mul(d));
                // min(d, 1 − d) is `d > ½ ? 1 − d : d` (1 − d is exact above ½), and
                // for coordinates in [0, 1) the torus difference |δ| the energy forms.
                let w = d.min(omd);
                dp = dp.add(w.mul(w));
            }
        }
        for (acc, v) in acc.products.iter_mut().zip(p) {
            *acc = acc.add(mask.select(v, zero));
        }
        if Self::PRUNE {
            return du;
        }
        let inf = B::splat(f64::INFINITY);
        acc.mins[0] = acc.mins[0].min(mask.select(de, inf));
        acc.mins[1] = acc.mins[1].min(mask.select(dp, inf));
        if E == TORUS {
            dp
        } else {
            de
        }
    }

    /// The squared Euclidean and torus distances of a group, with the operations of
    /// `MinDistances`, into `acc`'s minima; returns the smallest Euclidean one.
    #[inline(always)]
    fn distances<B: Simd>(&self, own: &[f64], other: &[f64], mask: B, acc: &mut Acc<B>) -> f64 {
        let one = B::splat(1.0);
        let (mut de, mut dp) = (B::splat(0.0), B::splat(0.0));
        let step = FIELDS * B::N;
        for (o, c) in own.chunks_exact(step).zip(other.chunks_exact(step)) {
            let d = B::load(o).sub(B::load(c)).abs();
            de = de.add(d.mul(d));
            let w = d.min(one.sub(d));
            dp = dp.add(w.mul(w));
        }
        let inf = B::splat(f64::INFINITY);
        let de = mask.select(de, inf);
        acc.mins[0] = acc.mins[0].min(de);
        acc.mins[1] = acc.mins[1].min(mask.select(dp, inf));
        de.hmin()
    }
}

/// The lanes of the points from j0 that pair with the point of a row: j ≥ `lo` (j > i
/// on the diagonal) and j < `len` (not padding).
#[inline(always)]
fn group_mask<B: Simd>(j0: usize, lo: usize, len: usize) -> B {
    if j0 >= lo && j0 + B::N <= len {
        B::TRUE
    } else {
        B::from_fn(|l| {
            let j = j0 + l;
            f64::from_bits(if j >= lo && j < len { u64::MAX } else { 0 })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The figures' bits: the five squares and two minima, then the energy's.
    fn bits(f: &PairFigures) -> (Vec<u64>, Option<u64>) {
        let v = f.squares.iter().chain(&f.min_squared_distances);
        (v.map(|x| x.to_bits()).collect(), f.energy.map(f64::to_bits))
    }

    /// Every available build gives the figures of the AVX2 build (and the portable one
    /// those without the energy, whose powers round a multiply-add of their own).
    fn same_on_every_build(p: &PointSet, what: &str) {
        let energies = [
            (Distance::Q(1.0), 0.05),
            (Distance::Q(1.0), 1.0),
            (Distance::Torus, 0.7),
            (Distance::Euclidean, 2.5),
            (Distance::Q(0.3), 0.4),
        ]
        .map(|(d, p)| Uqp::new(d, p).unwrap());
        let cases = std::iter::once(None).chain(energies.iter().map(Some));
        for e in cases {
            let name = e.map_or("none".into(), Uqp::name);
            let portable = bits(&figures_on(Build::Portable, p, e));
            for build in [Build::Avx2, Build::Avx512] {
                if !build.available() {
                    continue;
                }
                let f = bits(&figures_on(build, p, e));
                assert_eq!(f.0, portable.0, "{what}, {name}, {build:?}");
                if build == Build::Avx512 {
                    assert_eq!(f, bits(&figures_on(Build::Avx2, p, e)), "{what}, {name}");
                }
            }
        }
    }

    fn random(n: usize, s: usize, seed: u64) -> Vec<f64> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        (0..n * s).map(|_| rng.random::<f64>()).collect()
    }

    #[test]
    fn every_build_gives_the_same_bits() {
        // Sizes around the base vectors (4 and 8 lanes), the tile's 16, the smallest
        // block (32) and the most blocks (64), where the masks and the skipped parts
        // differ.
        for (n, s) in [
            (2, 1),
            (5, 3),
            (9, 2),
            (17, 4),
            (40, 5),
            (100, 7),
            (1031, 3),
        ] {
            let p = PointSet::new(n, s, random(n, s, 3 + n as u64)).unwrap();
            same_on_every_build(&p, &format!("n = {n}, s = {s}"));
        }
    }

    #[test]
    fn every_build_gives_the_same_bits_on_tiny_and_coinciding_points() {
        // Differences below 2^−1021 (the multiply-adds' case), subnormal coordinates,
        // coordinates at 0 and 1, and coinciding points.
        let tiny = [
            0.0,
            f64::from_bits(1),
            f64::from_bits(3),
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE + f64::from_bits(1),
            3.0 * f64::MIN_POSITIVE,
            1e-310,
            1.0,
        ];
        let (n, s) = (75, 3);
        let mut x = random(n, s, 5);
        for (i, v) in x.iter_mut().enumerate().filter(|(i, _)| i % 3 != 1) {
            *v = tiny[i % tiny.len()];
        }
        x.copy_within(0..s, 9 * s);
        let p = PointSet::new(n, s, x).unwrap();
        same_on_every_build(&p, "tiny");
        let only_tiny: Vec<f64> = (0..n * s).map(|i| tiny[(i * 7 + i / 5) % 7]).collect();
        same_on_every_build(&PointSet::new(n, s, only_tiny).unwrap(), "only tiny");
    }
}
