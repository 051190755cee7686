//! Classic point sequences and designs: starts for the DEM and the baselines its results
//! are compared with.
//!
//! [`halton`] is the plain (unscrambled) Halton sequence the paper starts its Table 5 runs
//! from and lists as row \[15\]; [`random`] is seeded i.i.d. uniform sampling, the start of
//! its Section 5.1 runs and the Monte Carlo baseline.
//!
//! [`Baseline`] names every generator a quasi-Monte Carlo user compares against (random,
//! Halton, scrambled Halton, Owen-scrambled Sobol', Hua–Wang good points, rank-1
//! lattices, Latin hypercubes plain and maximin) behind one `generate(n, s, seed)`; each
//! variant's [`Baseline::describe`] states exactly which construction it is. The
//! generators are also public one by one, with the unscrambled Sobol' net and the lattice
//! generating vector exposed so their structure can be checked.

#![deny(missing_docs)]

use stillpoint_domains::{Error, PointSet};

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use stillpoint_domains::halton::radical_inverse;

mod baseline;
mod extensible;
mod fast_cbc;
mod latin;
mod lattices;
mod law_lattice;
mod scrambled_halton;
mod sobol_owen;
mod weighted_lattice;

pub use baseline::Baseline;
pub use extensible::{
    continue_first_order_generator, embedded_first_order_generator, embedded_tent_generator,
    embedded_tent_generator_with_ratios, extend_embedded_generator, extensible_shift,
    extension_weight, first_order_level_criteria, ExtensibleLattice, SequenceTable,
    ENGINE_SEQUENCE_MAX_D, EXTENSIBLE_BITS, EXTENSIBLE_CONSTRUCTED_D, EXTENSIBLE_MAX_D,
    EXTENSIBLE_MAX_POINTS,
};
pub use latin::{lhs, lhs_maximin, maximin_search, LHS_MAXIMIN_MAX_N};
pub use lattices::{
    distinct_generators, hua_wang, korobov_p2, lattice, lattice_generator, rank1_lattice,
    tent_criterion, tent_lattice, tent_lattice_generator, tent_lattice_generator_plain,
    TENT_WEIGHT,
};
pub use law_lattice::{
    law_lattice, law_lattice_drawn, law_lattice_generator, law_lattice_parts, law_lattice_picked,
    law_lattice_picked_or, picked_draw, set_probe_errors, LAW_WEIGHT, PICKED_DRAWS,
};
pub use scrambled_halton::{halton_scrambled, HALTON_SCRAMBLED_MAX_S};
pub use sobol_owen::{
    sobol_plain, sobol_scrambled, sobol_scrambled_range, sobol_scrambled_ranges,
    sobol_scrambled_short_ranges, SOBOL_MAX_N, SOBOL_MAX_S,
};

pub use weighted_lattice::{weighted_criterion, weighted_lattice_generator, LatticeKernel};

pub use stillpoint_domains::halton::first_primes;

/// Plain (unscrambled) Halton points with indices 1..=n, in s dimensions.
///
/// Coordinate k (counting from 1) of point i is the radical inverse of i in the k-th
/// prime base, so the first points in 2-D are (1/2, 1/3), (1/4, 2/3), (3/4, 1/9). Index 0
/// (the origin) is skipped, as in the paper's Table 5 row \[15\]; unlike SciPy's
/// `qmc.Halton(scramble=False)`, which starts at index 0. Any s is accepted; the primes
/// are generated as needed, though plain Halton is known to degrade for large bases
/// (strongly correlated coordinates once the base exceeds n).
///
/// Refuses `n = 0` or `s = 0`, naming the argument.
pub fn halton(n: usize, s: usize) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    let bases = first_primes(s);
    let mut data = Vec::with_capacity(n * s);
    for i in 1..=n as u64 {
        data.extend(bases.iter().map(|&b| radical_inverse(i, b)));
    }
    PointSet::new(n, s, data)
}

/// n points drawn uniformly and independently in [0, 1)^s.
///
/// The generator is `Xoshiro256PlusPlus::seed_from_u64(seed)` and the coordinates are
/// drawn row by row (all of point 1, then point 2, ...), so the same seed gives the same
/// points on every platform, and the first m points of a larger draw equal a draw of m.
///
/// Refuses `n = 0` or `s = 0`, naming the argument.
pub fn random(n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
    check_shape(n, s)?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let data = (0..n * s).map(|_| rng.random::<f64>()).collect();
    PointSet::new(n, s, data)
}

/// Refuses an empty shape, or one whose buffer length overflows, before allocating.
pub(crate) fn check_shape(n: usize, s: usize) -> Result<(), Error> {
    if n == 0 {
        return Err(Error::invalid("n", n, "at least 1 point"));
    }
    if s == 0 {
        return Err(Error::invalid("s", s, "at least 1 dimension"));
    }
    let most = max_coordinates();
    if n.checked_mul(s).is_none_or(|len| len > most) {
        return Err(Error::invalid(
            "n",
            n,
            format!(
                "at most {} points in {s} dimensions: a run holds about {COPIES} sets of n·s \
                 coordinates of 8 bytes, which must fit in this machine's memory ({:.1} GiB)",
                most / s,
                memory_bytes() as f64 / (1u64 << 30) as f64
            ),
        ));
    }
    Ok(())
}

/// Sets of n·s coordinates a run holds at once (start, current and previous state,
/// gradient, lowest state, a result and scratch), with room to spare.
const COPIES: usize = 8;

/// The machine's memory in bytes (`MemTotal` of /proc/meminfo), or 16 GiB where it cannot
/// be read; read once per process, since every set's check asks for it and reading the
/// file costs microseconds (a round of `quad` checks several sets).
fn memory_bytes() -> u64 {
    static TOTAL: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *TOTAL.get_or_init(read_memory_bytes)
}

fn read_memory_bytes() -> u64 {
    let total = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            kib.checked_mul(1024)
        });
    total.unwrap_or(16 << 30)
}

/// The most coordinates (n·s) one set of a run may have on this machine; see
/// [`check_size`].
pub fn max_coordinates() -> usize {
    (memory_bytes() / (8 * COPIES as u64)).min(usize::MAX as u64) as usize
}

/// Refuses n = 0, s = 0, or a set too large for this machine's memory, naming n and the
/// bound, before anything is allocated.
pub fn check_size(n: usize, s: usize) -> Result<(), Error> {
    check_shape(n, s)
}

/// A 64-bit mixing function (the SplitMix64 finaliser, Stafford's "variant 13"
/// constants): every input bit affects every output bit, which is what turns a structured
/// key (seed, dimension, digit level, prefix) into independent-looking random bits.
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A keyed hash of one word: distinct `(key, x)` pairs give unrelated outputs. The golden
/// ratio offset keeps x = 0 away from mix64's fixed point at 0.
pub fn hash2(key: u64, x: u64) -> u64 {
    mix64(key ^ hash2_inner(x))
}

/// The half of [`hash2`] that does not depend on the key: hash2(key, x) =
/// mix64(key ^ hash2_inner(x)), so many keys hashing one x share it.
pub(crate) fn hash2_inner(x: u64) -> u64 {
    mix64(x.wrapping_add(0x9e37_79b9_7f4a_7c15))
}

/// A seeded generator for one labelled sub-stream (a dimension, a digit position, a
/// search), so each part of a construction draws the same numbers however many other
/// parts there are and in whatever order they are computed.
pub(crate) fn substream(seed: u64, label: u64, index: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(hash2(hash2(mix64(seed), label), index))
}

/// The tent transform x ↦ 1 − |2x − 1|, which maps the uniform distribution on [0, 1)
/// onto itself; kept below 1 (x = ½ would map onto 1).
pub fn tent(x: f64) -> f64 {
    let y = 1.0 - (2.0 * x - 1.0).abs();
    if y >= 1.0 {
        prev_float(1.0)
    } else {
        y
    }
}

/// The largest f64 below `x` (for positive finite x): where a value that must stay inside
/// a half-open interval is clamped when rounding carried it onto the right end.
pub(crate) fn prev_float(x: f64) -> f64 {
    f64::from_bits(x.to_bits() - 1)
}

/// An independent seed for the `index`-th use of a run's `seed` (a SplitMix64 finaliser
/// of the two), so the random streams of a run's stages do not overlap.
pub fn stream_seed(seed: u64, index: u64) -> u64 {
    let mut h = seed ^ 0x9e37_79b9_7f4a_7c15_u64.wrapping_mul(index + 1);
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primes() {
        assert!(first_primes(0).is_empty());
        assert_eq!(
            first_primes(12),
            vec![2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37]
        );
        let p = first_primes(1000);
        assert_eq!(p[999], 7919);
    }

    #[test]
    fn first_halton_points() {
        let h = halton(3, 2).unwrap();
        assert_eq!(h.point(0), &[1.0 / 2.0, 1.0 / 3.0]);
        assert_eq!(h.point(1), &[1.0 / 4.0, 2.0 / 3.0]);
        assert_eq!(h.point(2), &[3.0 / 4.0, 1.0 / 9.0]);
    }

    #[test]
    fn halton_digits_are_mirrored() {
        // 11 = 1011₂ → 0.1101₂ = 13/16; 11 = 102₃ → 0.201₃ = 19/27; 11 = 21₅ → 0.12₅ = 7/25.
        let h = halton(11, 3).unwrap();
        assert_eq!(h.point(10), &[13.0 / 16.0, 19.0 / 27.0, 7.0 / 25.0]);
    }

    #[test]
    fn halton_high_dimension_uses_later_primes() {
        // The 30th prime is 113: index 1 maps to 1/113, index 114 = 1·113 + 1 to 1/113 + 1/113².
        let h = halton(114, 30).unwrap();
        assert_eq!(h.point(0)[29], 1.0 / 113.0);
        assert_eq!(h.point(113)[29], 114.0 / (113.0 * 113.0));
        assert!(h.as_slice().iter().all(|&v| v > 0.0 && v < 1.0));
    }

    #[test]
    fn refuses_empty_shapes() {
        for (n, s, name) in [(0, 2, "n"), (3, 0, "s")] {
            for r in [halton(n, s), random(n, s, 1)] {
                match r {
                    Err(Error::InvalidArgument { name: got, .. }) => assert_eq!(got, name),
                    other => panic!("expected an error naming {name}, got {other:?}"),
                }
            }
        }
    }

    #[test]
    fn random_is_seeded_and_in_the_unit_cube() {
        let a = random(50, 3, 7).unwrap();
        assert_eq!(a, random(50, 3, 7).unwrap());
        assert_ne!(a, random(50, 3, 8).unwrap());
        assert!(a.as_slice().iter().all(|&v| (0.0..1.0).contains(&v)));
        // Row by row: a shorter draw is a prefix of a longer one.
        let b = random(20, 3, 7).unwrap();
        assert_eq!(b.as_slice(), &a.as_slice()[..60]);
    }
}
