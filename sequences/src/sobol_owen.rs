//! Sobol' points from the Joe–Kuo D6 direction numbers, plain and with Owen's nested
//! uniform scrambling.
//!
//! The net is the standard digital construction: the 32-bit value of point i in
//! dimension j is the XOR of the direction numbers v_{j,k} over the set bits k of i
//! (natural order, not the Gray-code order most iterators use; both orders give the same
//! set for n = 2^m, but only natural order makes the first n points a prefix of any
//! longer run). Direction numbers come from the `sobol` crate's copy of Joe and Kuo's
//! `new-joe-kuo-6.21201` table (S. Joe, F. Y. Kuo, *Constructing Sobol sequences with
//! better two-dimensional projections*, SIAM J. Sci. Comput. 30 (2008) 2635–2654).
//!
//! Owen's nested scrambling (A. B. Owen, *Randomly permuted (t,m,s)-nets and
//! (t,s)-sequences*, 1995) flips bit ℓ of a coordinate according to an independent random
//! bit attached to the node (ℓ, first ℓ−1 bits) of the binary tree of intervals. Storing
//! those 2^ℓ bits per level is impossible, so each is a hash of (seed, dimension, level,
//! prefix), as in Burley's and Laine–Karras's hash-based Owen scrambling; each level is
//! hashed separately here rather than with their one-multiply approximation, so the
//! flips are as independent as the hash is good. A sequence never taken past 2^k points
//! ([`sobol_scrambled_short_ranges`]) draws the flips below level k, where each node holds
//! one of its points at most, from one hash per point.

use std::sync::OnceLock;

use rayon::prelude::*;
use sobol::params::JoeKuoD6;
use sobol::Sobol;

use super::{check_shape, hash2, hash2_inner, mix64};
use crate::{Error, PointSet};
use stillpoint_domains::{vector_build, VectorBuild};

/// Largest dimension the bundled Joe–Kuo D6 table covers.
pub const SOBOL_MAX_S: usize = 21_201;

/// Largest number of points: the direction numbers have 32 bits, so indices beyond 2^32
/// would repeat the net.
pub const SOBOL_MAX_N: usize = 1 << 32;

/// Distinguishes the Sobol' scramble's hash stream from other users of the same seed.
const SOBOL_LABEL: u64 = 0x536f_626f_6c27_4f77;

/// Bits of resolution of the direction numbers (and of the plain net's coordinates).
const BITS: u32 = 32;

/// Direction numbers v_{j,1..32} for dimensions 1..=s, each left-aligned in a u32 so
/// that bit 31 is the 1/2 digit.
fn direction_numbers(s: usize) -> Vec<Vec<u32>> {
    // The crate ships three sizes of the same table; parsing the 21 201-dimension one
    // costs tens of milliseconds, so load the smallest that covers s, once per process.
    static MINIMAL: OnceLock<JoeKuoD6> = OnceLock::new();
    static STANDARD: OnceLock<JoeKuoD6> = OnceLock::new();
    static EXTENDED: OnceLock<JoeKuoD6> = OnceLock::new();
    let params = if s <= 100 {
        MINIMAL.get_or_init(JoeKuoD6::minimal)
    } else if s <= 1000 {
        STANDARD.get_or_init(JoeKuoD6::standard)
    } else {
        EXTENDED.get_or_init(JoeKuoD6::extended)
    };
    Sobol::<u32>::init_direction_vals::<u32>(s, BITS as usize, params)
}

fn check_sobol_shape(n: usize, s: usize) -> Result<(), Error> {
    // The generator's own limits first: they hold on any machine.
    if n > SOBOL_MAX_N {
        return Err(Error::invalid(
            "n",
            n,
            format!("1..={SOBOL_MAX_N} (2^32) for Sobol' points with 32-bit direction numbers"),
        ));
    }
    if s > SOBOL_MAX_S {
        return Err(Error::invalid(
            "s",
            s,
            format!("1..={SOBOL_MAX_S} for Sobol' points (the Joe–Kuo D6 table's dimensions)"),
        ));
    }
    check_shape(n, s)
}

/// The 32-bit net values of points start..end in one dimension, natural order.
fn net_column(start: usize, end: usize, v: &[u32]) -> Vec<u32> {
    // Going from i to i + 1 clears i's trailing ones and sets the bit above them, the
    // lowest set bit of i + 1: XOR the direction numbers of all those bits at once.
    let mut through = v.to_vec();
    for k in 1..through.len() {
        through[k] ^= through[k - 1];
    }
    let mut y = Vec::with_capacity(end - start);
    // Point `start` directly: the XOR of the direction numbers of its set bits.
    let mut current = (0..v.len())
        .filter(|&k| (start >> k) & 1 == 1)
        .fold(0u32, |acc, k| acc ^ v[k]);
    y.push(current);
    for i in start + 1..end {
        current ^= through[i.trailing_zeros() as usize];
        y.push(current);
    }
    y
}

/// Lays columns (one slice per dimension) out row by row.
fn rows_from_columns<C: AsRef<[f64]>>(n: usize, columns: &[C]) -> Vec<f64> {
    let s = columns.len();
    let mut data = vec![0.0; n * s];
    // A block of rows at a time, so that the rows written stay in cache while every
    // column fills its place in them (one column at a time over all n rows writes a
    // different cache line for each value once n·s values outgrow the cache).
    const ROWS: usize = 64;
    for (b, block) in data.chunks_mut(ROWS * s).enumerate() {
        for (j, col) in columns.iter().enumerate() {
            let col = &col.as_ref()[b * ROWS..];
            for (row, &x) in block.chunks_exact_mut(s).zip(col) {
                row[j] = x;
            }
        }
    }
    data
}

/// Unscrambled Sobol' points with indices 0..n−1 in natural order, Joe–Kuo D6 direction
/// numbers, each coordinate an exact multiple of 2^−32.
///
/// The first points are (0, 0, 0), (1/2, 1/2, 1/2), (1/4, 3/4, 3/4), (3/4, 1/4, 1/4),
/// (1/8, 5/8, 3/8), ...; the first 2^m points are the same set as SciPy's
/// `qmc.Sobol(scramble=False)`, which lists them in Gray-code order. Point 0 is the
/// origin.
///
/// Refuses n = 0, s = 0, n > 2^32 and s > 21 201, naming the argument.
pub fn sobol_plain(n: usize, s: usize) -> Result<PointSet, Error> {
    check_sobol_shape(n, s)?;
    let dirs = direction_numbers(s);
    let scale = (-f64::from(BITS)).exp2();
    let columns: Vec<Vec<f64>> = dirs
        .par_iter()
        .map(|v| {
            net_column(0, n, v)
                .into_iter()
                .map(|y| f64::from(y) * scale)
                .collect()
        })
        .collect();
    PointSet::new(n, s, rows_from_columns(n, &columns))
}

/// Owen's nested uniform scramble of one 32-bit net value, extended to 53 random-looking
/// bits: bit ℓ (ℓ = 1 is the 1/2 digit) is flipped by a hash of (dimension key, ℓ, the
/// original first ℓ−1 bits), and the 21 bits below the net's resolution, which are all
/// zero in the net, become hash bits of the whole 32-bit value, as nested scrambling of
/// those zero digits implies. The flips of the first `top.levels` levels are read from
/// `top`, the same hashes computed once per node instead of once per point; the flips
/// below `top.depth` are bits of the whole value's hash too ([`TopFlips::new`]).
fn owen_scramble(y: u32, dim_key: u64, top: &TopFlips) -> u64 {
    let y = u64::from(y);
    let mut out = (y ^ top.mask(y)) & !(u64::from(u32::MAX) >> top.levels) & 0xffff_ffff;
    for level in top.levels + 1..=top.depth {
        out |= (((y >> (BITS - level)) & 1) ^ flip(dim_key, level, y)) << (BITS - level);
    }
    let whole = hash2(dim_key, (1u64 << BITS) | y);
    out |= (y ^ whole) & top.deep_mask();
    (out << 21) | (whole >> (64 - 21))
}

/// The flip of bit `level` of net value y: a hash of the node (level, y's first
/// level − 1 bits).
fn flip(dim_key: u64, level: u32, y: u64) -> u64 {
    // A leading 1 marks the prefix length, so (level, prefix) pairs never collide.
    let node = (1u64 << (level - 1)) | (y >> (BITS - level + 1));
    hash2(dim_key, node) >> 63
}

/// The flips of the first `levels` levels of one dimension's scramble for every prefix,
/// as masks over the top bits, indexed by the first levels − 1 bits: 2^levels − 1 hashes,
/// worth it when more than 2^levels points are scrambled at once. `depth` is the last
/// level flipped by a hash of its own node.
struct TopFlips {
    levels: u32,
    depth: u32,
    masks: Vec<u64>,
}

impl TopFlips {
    /// The deepest table worth building for `count` points (at most 2^16 nodes), for a
    /// scramble of a sequence's first 2^depth points at most. Below level `depth` every
    /// node of the scramble's tree holds at most one of those points (the first 2^depth
    /// points of each coordinate have distinct first `depth` digits), so its flips are
    /// independent bits per point: they are taken from the hash of the whole value that
    /// also gives the 21 bits below the net, the same law at fewer hashes. Depth 32 (the
    /// whole sequence) hashes every level's node.
    fn new(dim_key: u64, count: usize, depth: u32) -> TopFlips {
        let levels = count.max(1).ilog2().min(16).min(depth);
        let mut masks = vec![0u64];
        for level in 1..=levels {
            // Level ℓ's nodes are the prefixes p of ℓ − 1 bits; a prefix's mask is its
            // parent's with this level's flip added.
            masks = (0..1u64 << (level - 1))
                .map(|p| {
                    let y = p << (BITS - level + 1);
                    masks[(p >> 1) as usize] | flip(dim_key, level, y) << (BITS - level)
                })
                .collect();
        }
        TopFlips {
            levels,
            depth,
            masks,
        }
    }

    /// The net's bits below level `depth` (the flips taken from the whole value's hash).
    fn deep_mask(&self) -> u64 {
        (1u64 << (BITS - self.depth)) - 1
    }

    /// The flips of the first `levels` bits of y, in place.
    fn mask(&self, y: u64) -> u64 {
        if self.levels == 0 {
            0
        } else {
            self.masks[(y >> (BITS - self.levels + 1)) as usize]
        }
    }
}

/// Points scrambled together in [`scramble_lanes`]: eight 64-bit lanes fill one AVX-512
/// register, so each level's hash runs on eight points at once.
const LANES: usize = 8;

/// Work (points × dimensions × scrambles) below which a range is scrambled on the
/// calling thread: waking the thread pool costs more than the hashes of a few thousand
/// coordinates (`quad` asks for ranges of 32–1 024 points per replicate).
const PARALLEL_WORK: usize = 1 << 14;

/// The scrambles of one column of net values under several keys (one per scramble), as
/// f64 in [0, 1): the values of [`owen_scramble`], bit for bit. A node's hash is
/// hash2(key, node) = mix64(key ^ hash2_inner(node)), and the inner half is the same for
/// every key, so it is computed once per point and level for all the keys. Eight
/// points at a time where the processor has AVX-512 F and DQ (64-bit lane multiplies)
/// or AVX2 (multiplies built from 32-bit ones, still 1.3–1.4× the scalar loop), one at a
/// time elsewhere or when `STILLPOINT_PORTABLE=1` asks for the portable build
/// ([`vector_build`]). `tops[r]` holds key r's first levels.
fn scramble_column(ys: &[u32], keys: &[u64], tops: &[TopFlips]) -> Vec<Vec<f64>> {
    let mut outs = vec![vec![0.0; ys.len()]; keys.len()];
    match vector_build() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX-512 F and DQ (checked by `vector_build`).
        VectorBuild::Avx512 => unsafe { scramble_lanes_avx512(ys, keys, tops, &mut outs) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX2 (checked by `vector_build`).
        VectorBuild::Avx2 => unsafe { scramble_lanes_avx2(ys, keys, tops, &mut outs) },
        _ => scramble_points(ys, keys, tops, &mut outs),
    }
    outs
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq")]
unsafe fn scramble_lanes_avx512(
    ys: &[u32],
    keys: &[u64],
    tops: &[TopFlips],
    outs: &mut [Vec<f64>],
) {
    scramble_lanes(ys, keys, tops, outs)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn scramble_lanes_avx2(ys: &[u32], keys: &[u64], tops: &[TopFlips], outs: &mut [Vec<f64>]) {
    scramble_lanes(ys, keys, tops, outs)
}

/// [`owen_scramble`] point by point: without vector multiplies the compiler's lanes are
/// no faster than this loop.
fn scramble_points(ys: &[u32], keys: &[u64], tops: &[TopFlips], outs: &mut [Vec<f64>]) {
    let scale = (-53f64).exp2();
    for ((&key, top), out) in keys.iter().zip(tops).zip(outs.iter_mut()) {
        for (o, &y) in out.iter_mut().zip(ys) {
            *o = owen_scramble(y, key, top) as f64 * scale;
        }
    }
}

/// [`owen_scramble`] over whole blocks of [`LANES`] points, written lane by lane so that
/// the compiler keeps each level's hashes in one vector, each point's inner hashes
/// shared by the keys; the points after the last whole block one by one.
#[inline(always)]
fn scramble_lanes(ys: &[u32], keys: &[u64], tops: &[TopFlips], outs: &mut [Vec<f64>]) {
    let scale = (-53f64).exp2();
    let whole = ys.len() / LANES * LANES;
    let mut bits = vec![[0u64; LANES]; keys.len()];
    for (block, yc) in ys[..whole].chunks_exact(LANES).enumerate() {
        let mut y = [0u64; LANES];
        for k in 0..LANES {
            y[k] = u64::from(yc[k]);
        }
        for (b, top) in bits.iter_mut().zip(tops) {
            let below_top = !(u64::from(u32::MAX) >> top.levels) & 0xffff_ffff;
            for k in 0..LANES {
                b[k] = (y[k] ^ top.mask(y[k])) & below_top;
            }
        }
        // Every key's table has the same levels and depth: they depend on the count and the
        // sequence's length alone.
        for level in tops[0].levels + 1..=tops[0].depth {
            let lead = 1u64 << (level - 1);
            let shift = BITS - level;
            let mut inner = [0u64; LANES];
            let mut digit = [0u64; LANES];
            for k in 0..LANES {
                inner[k] = hash2_inner(lead | (y[k] >> (shift + 1)));
                digit[k] = (y[k] >> shift) & 1;
            }
            for (b, &key) in bits.iter_mut().zip(keys) {
                for k in 0..LANES {
                    b[k] |= (digit[k] ^ (mix64(key ^ inner[k]) >> 63)) << shift;
                }
            }
        }
        let mut inner = [0u64; LANES];
        for k in 0..LANES {
            inner[k] = hash2_inner((1u64 << BITS) | y[k]);
        }
        let deep = tops[0].deep_mask();
        for ((b, &key), out) in bits.iter().zip(keys).zip(outs.iter_mut()) {
            let oc = &mut out[block * LANES..(block + 1) * LANES];
            for k in 0..LANES {
                let whole = mix64(key ^ inner[k]);
                let top = b[k] | ((y[k] ^ whole) & deep);
                oc[k] = ((top << 21) | (whole >> (64 - 21))) as f64 * scale;
            }
        }
    }
    for ((&key, top), out) in keys.iter().zip(tops).zip(outs.iter_mut()) {
        for (o, &y) in out[whole..].iter_mut().zip(&ys[whole..]) {
            *o = owen_scramble(y, key, top) as f64 * scale;
        }
    }
}

/// Owen-scrambled Sobol' points: the net of [`sobol_plain`] (indices 0..n−1, natural
/// order, Joe–Kuo D6) with an independent nested uniform scramble per dimension, seeded by
/// `seed`, as 53-bit f64 values in [0, 1).
///
/// Every 2^m-point prefix keeps the net's structure: each one-dimensional projection has
/// one point in each interval \[k/2^m, (k+1)/2^m), and dimensions 1 and 2 form a
/// (0, m, 2)-net. Unlike SciPy's `qmc.Sobol(scramble=True)`, which applies a linear matrix
/// scramble plus a digital shift (LMS + shift), this is Owen's full nested scramble.
///
/// Refuses n = 0, s = 0, n > 2^32 and s > 21 201, naming the argument.
pub fn sobol_scrambled(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    sobol_scrambled_range(0, n, s, seed)
}

/// The points with indices start..end of the sequence of [`sobol_scrambled`] (same seed,
/// same scramble): bit for bit rows start..end of `sobol_scrambled(end, s, seed)`, at the
/// cost of end − start points, so a sequence extended in rounds computes each point once.
///
/// Refuses end ≤ start (naming `start`), end > 2^32 (naming `n`) and s = 0 or s > 21 201
/// (naming `s`).
pub fn sobol_scrambled_range(
    start: usize,
    end: usize,
    s: usize,
    seed: u64,
) -> Result<PointSet, Error> {
    let mut sets = sobol_scrambled_ranges(start, end, s, &[seed])?;
    Ok(sets.pop().expect("one set per seed"))
}

/// The points with indices start..end of several scrambles of the sequence of
/// [`sobol_scrambled`], one per seed: set r is bit for bit
/// `sobol_scrambled_range(start, end, s, seeds[r])`. The scrambles share the net's values
/// and the key-free half of each node's hash, so R of them cost about (R + 1)/2R of R
/// separate calls (the replicates of an integration are R scrambles of one range).
///
/// Refuses end ≤ start (naming `start`), end > 2^32 (naming `n`), s = 0 or s > 21 201
/// (naming `s`) and no seeds (naming `seeds`).
pub fn sobol_scrambled_ranges(
    start: usize,
    end: usize,
    s: usize,
    seeds: &[u64],
) -> Result<Vec<PointSet>, Error> {
    sobol_scrambled_short_ranges(start, end, s, seeds, SOBOL_MAX_N)
}

/// [`sobol_scrambled_ranges`] for sequences that are never taken past their first
/// `max_points` points (a power of two up to 2^32): Owen's nested scramble with the same
/// law for those points at fewer hashes. Among the first 2^k points of a Sobol'
/// coordinate the first k digits are distinct, so every node of the scramble's tree
/// below level k holds at most one of them and its flips are independent bits per point;
/// they are drawn from the hash of the point's whole value, which already gives the 21
/// bits below the net, instead of one hash per level (11 hashes a coordinate instead of
/// 23 for 1 024 points of a sequence that stops at 2^20 points, as `quad`'s do). With
/// `max_points` = 2^32 the values are [`sobol_scrambled_ranges`]' bit for bit; with less,
/// they differ from them below level k.
///
/// Refuses `max_points` not a power of two or above 2^32 (naming `max_points`), end above
/// it (naming `end`), and what [`sobol_scrambled_ranges`] refuses.
pub fn sobol_scrambled_short_ranges(
    start: usize,
    end: usize,
    s: usize,
    seeds: &[u64],
    max_points: usize,
) -> Result<Vec<PointSet>, Error> {
    check_sobol_shape(end, s)?;
    if !max_points.is_power_of_two() || max_points > SOBOL_MAX_N {
        return Err(Error::invalid(
            "max_points",
            max_points,
            format!("a power of two up to {SOBOL_MAX_N} (2^32)"),
        ));
    }
    if end > max_points {
        return Err(Error::invalid(
            "end",
            end,
            format!("at most max_points = {max_points}"),
        ));
    }
    let depth = max_points.ilog2();
    if start >= end {
        return Err(Error::invalid(
            "start",
            start,
            format!("an index below the end of the range, {end}"),
        ));
    }
    if seeds.is_empty() {
        return Err(Error::invalid("seeds", "none", "one seed or more"));
    }
    let dirs = direction_numbers(s);
    // A label of its own keeps these bits unrelated to other generators fed the same seed.
    let seed_keys: Vec<u64> = seeds
        .iter()
        .map(|&seed| hash2(mix64(seed), SOBOL_LABEL))
        .collect();
    let column = |(j, v): (usize, &Vec<u32>)| {
        let keys: Vec<u64> = seed_keys.iter().map(|&k| hash2(k, j as u64)).collect();
        let tops: Vec<TopFlips> = keys
            .iter()
            .map(|&k| TopFlips::new(k, end - start, depth))
            .collect();
        scramble_column(&net_column(start, end, v), &keys, &tops)
    };
    // columns[j][r]: dimension j of scramble r.
    let columns: Vec<Vec<Vec<f64>>> = if (end - start) * s * seeds.len() < PARALLEL_WORK {
        dirs.iter().enumerate().map(column).collect()
    } else {
        dirs.par_iter().enumerate().map(column).collect()
    };
    let n = end - start;
    (0..seeds.len())
        .map(|r| {
            let columns: Vec<&[f64]> = columns.iter().map(|c| &c[r][..]).collect();
            PointSet::new(n, s, rows_from_columns(n, &columns))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of rows start..end of a set, to compare sets exactly.
    fn rows_bits(p: &PointSet, start: usize, end: usize) -> Vec<u64> {
        let s = p.s();
        p.as_slice()[start * s..end * s]
            .iter()
            .map(|x| x.to_bits())
            .collect()
    }

    #[test]
    fn a_range_is_the_prefix_s_rows_bit_for_bit() {
        let (s, seed) = (5, 17);
        let all = sobol_scrambled(1000, s, seed).unwrap();
        // Starts at 0, inside a power of two, at a power of two, and ranges of one point.
        for (start, end) in [
            (0, 1),
            (0, 1000),
            (1, 2),
            (3, 64),
            (64, 128),
            (100, 1000),
            (999, 1000),
        ] {
            let part = sobol_scrambled_range(start, end, s, seed).unwrap();
            assert_eq!(part.n(), end - start);
            assert_eq!(
                rows_bits(&part, 0, part.n()),
                rows_bits(&all, start, end),
                "rows {start}..{end}"
            );
        }
    }

    #[test]
    fn a_range_far_out_matches_the_net_s_definition() {
        // Point i's net value is the XOR of the direction numbers of i's set bits; the
        // range starting at a large i must agree with that, unscrambled, digit for digit.
        let s = 3;
        let dirs = direction_numbers(s);
        let start = (1usize << 31) + 12_345;
        for (j, v) in dirs.iter().enumerate() {
            let col = net_column(start, start + 70, v);
            for (offset, y) in col.iter().enumerate() {
                let i = start + offset;
                let direct = (0..32)
                    .filter(|k| (i >> k) & 1 == 1)
                    .fold(0u32, |acc, k| acc ^ v[k]);
                assert_eq!(*y, direct, "dimension {j}, point {i}");
            }
        }
    }

    /// The scramble as defined, one hash per level and point down to level `depth`, the
    /// whole value's hash below it (its top 21 bits below the net, its low bits the flips
    /// of the net's digits below `depth`).
    fn owen_by_levels(y: u32, dim_key: u64, depth: u32) -> u64 {
        let y = u64::from(y);
        let whole = hash2(dim_key, (1u64 << BITS) | y);
        let mut out = 0u64;
        for level in 1..=BITS {
            let node = (1u64 << (level - 1)) | (y >> (BITS - level + 1));
            let bit = (y >> (BITS - level)) & 1;
            let flip = if level <= depth {
                hash2(dim_key, node) >> 63
            } else {
                (whole >> (BITS - level)) & 1
            };
            out |= (bit ^ flip) << (BITS - level);
        }
        (out << 21) | (whole >> (64 - 21))
    }

    #[test]
    fn the_table_of_top_flips_gives_the_per_level_hashes() {
        let dirs = direction_numbers(2);
        let ys = net_column(0, 5000, &dirs[1]);
        for depth in [BITS, 20, 5, 0] {
            for count in [1, 2, 3, 4096, 1 << 17] {
                let top = TopFlips::new(99, count, depth);
                assert_eq!(top.levels, (count as u32).ilog2().min(16).min(depth));
                for &y in ys.iter().chain(&[0, u32::MAX, 1 << 31]) {
                    assert_eq!(
                        owen_scramble(y, 99, &top),
                        owen_by_levels(y, 99, depth),
                        "{y} {count} {depth}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_column_builds_give_the_scramble_of_each_point() {
        // Lengths around a whole number of lanes, so both the blocks and the points after
        // the last block are checked; one key and several sharing their inner hashes; the
        // machine's own build and each body compiled without a target feature.
        let dirs = direction_numbers(3);
        let scale = (-53f64).exp2();
        for (keys, depth) in [
            (vec![7u64], BITS),
            (vec![7, 8, 123_456_789, u64::MAX], BITS),
            (vec![7, 8, 123_456_789, u64::MAX], 20),
        ] {
            for len in [1, 7, 8, 9, 1003] {
                let ys = net_column(5, 5 + len, &dirs[2]);
                let tops: Vec<TopFlips> =
                    keys.iter().map(|&k| TopFlips::new(k, len, depth)).collect();
                let want: Vec<Vec<u64>> = keys
                    .iter()
                    .map(|&k| {
                        ys.iter()
                            .map(|&y| (owen_by_levels(y, k, depth) as f64 * scale).to_bits())
                            .collect()
                    })
                    .collect();
                let bits = |outs: &[Vec<f64>]| -> Vec<Vec<u64>> {
                    outs.iter()
                        .map(|o| o.iter().map(|x| x.to_bits()).collect())
                        .collect()
                };
                let built = scramble_column(&ys, &keys, &tops);
                assert_eq!(bits(&built), want, "length {len}, {} keys", keys.len());
                for body in [scramble_lanes, scramble_points] {
                    let mut got = vec![vec![0.0; len]; keys.len()];
                    body(&ys, &keys, &tops, &mut got);
                    assert_eq!(bits(&got), want, "length {len}, a build's body");
                }
            }
        }
    }

    #[test]
    fn several_scrambles_of_a_range_are_each_seed_s_own() {
        let seeds = [3u64, 4, 99];
        // Small (one thread) and large (the thread pool) ranges.
        for (start, end, s) in [(0, 40, 3), (64, 128, 2), (1_000, 4_000, 5)] {
            let sets = sobol_scrambled_ranges(start, end, s, &seeds).unwrap();
            assert_eq!(sets.len(), seeds.len());
            for (set, &seed) in sets.iter().zip(&seeds) {
                let alone = sobol_scrambled(end, s, seed).unwrap();
                assert_eq!(
                    rows_bits(set, 0, set.n()),
                    rows_bits(&alone, start, end),
                    "rows {start}..{end}, seed {seed}"
                );
            }
        }
        let e = sobol_scrambled_ranges(0, 4, 2, &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("seeds"), "{e}");
    }

    #[test]
    fn a_short_sequence_s_scramble_keeps_the_net_and_its_prefixes() {
        let (s, seeds) = (3, [5u64, 6]);
        let max = 1 << 10;
        let all = sobol_scrambled_short_ranges(0, max, s, &seeds, max).unwrap();
        // The whole sequence's scramble down to level 32 where the sequence may be long.
        let long = sobol_scrambled_short_ranges(0, 64, s, &seeds, SOBOL_MAX_N).unwrap();
        let plain = sobol_scrambled_ranges(0, 64, s, &seeds).unwrap();
        assert_eq!(long, plain);
        // Below the first 10 digits the short scramble differs; above, the same flips.
        let (a, b) = (all[0].as_slice(), long[0].as_slice());
        assert_ne!(a[..64 * s], *b);
        for (x, y) in a.iter().zip(b) {
            assert_eq!((x * 1024.0).floor(), (y * 1024.0).floor());
        }
        for (set, &seed) in all.iter().zip(&seeds) {
            // A range is the rows of the prefix, bit for bit.
            let part = sobol_scrambled_short_ranges(100, 900, s, &[seed], max).unwrap();
            assert_eq!(rows_bits(&part[0], 0, 800), rows_bits(set, 100, 900));
            // Every 2^m prefix: one point per interval of width 2^−m in each dimension.
            for m in 0..=10u32 {
                let n = 1usize << m;
                for j in 0..s {
                    let mut cells: Vec<usize> = (0..n)
                        .map(|i| (set.as_slice()[i * s + j] * n as f64) as usize)
                        .collect();
                    cells.sort_unstable();
                    assert_eq!(cells, (0..n).collect::<Vec<_>>(), "m = {m}, dimension {j}");
                }
            }
        }
        let e = sobol_scrambled_short_ranges(0, 2048, s, &seeds, max).unwrap_err();
        assert!(e.to_string().contains("end"), "{e}");
        let e = sobol_scrambled_short_ranges(0, 8, s, &seeds, 1000).unwrap_err();
        assert!(e.to_string().contains("max_points"), "{e}");
    }

    #[test]
    fn an_empty_or_too_long_range_is_refused_by_name() {
        let e = sobol_scrambled_range(5, 5, 2, 0).unwrap_err().to_string();
        assert!(e.contains("start") && e.contains('5'), "{e}");
        let e = sobol_scrambled_range(0, SOBOL_MAX_N + 1, 2, 0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("n") && e.contains("4294967297"), "{e}");
    }
}
