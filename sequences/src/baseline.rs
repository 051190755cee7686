//! One name and one `generate(n, s, seed)` for every baseline point generator, so the
//! command line and the studies can list, parse, describe and run them uniformly.

use std::fmt;
use std::str::FromStr;

use super::{
    halton, halton_scrambled, hua_wang, lattice, lhs, lhs_maximin, random, sobol_scrambled,
};
use crate::{Error, PointSet};

/// A baseline point generator that quasi-Monte Carlo users compare new point sets with.
///
/// [`Baseline::describe`] states exactly which variant each one is; the paper's tables
/// call scrambled Halton "HS", scrambled Sobol' "SS" and Hua–Wang "HW". (The optimised
/// generalised Halton of Faure and Lemieux, "HSO", is not provided.)
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Baseline {
    /// I.i.d. uniform points ([`super::random`]).
    Random,
    /// Plain Halton, indices 1..=n ([`super::halton`]).
    Halton,
    /// Halton with random digit permutations, indices 0..n−1 ([`super::halton_scrambled`]).
    ScrambledHalton,
    /// Owen-scrambled Sobol', Joe–Kuo D6 ([`super::sobol_scrambled`]).
    Sobol,
    /// Hua–Wang good points from the cyclotomic field ([`super::hua_wang`]).
    HuaWang,
    /// Unshifted rank-1 lattice, Fibonacci or Korobov ([`super::lattice`]).
    Lattice,
    /// Random Latin hypercube ([`super::lhs`]).
    Lhs,
    /// Latin hypercube improved for the maximin distance ([`super::lhs_maximin`]).
    LhsMaximin,
}

const ALL: [Baseline; 8] = [
    Baseline::Random,
    Baseline::Halton,
    Baseline::ScrambledHalton,
    Baseline::Sobol,
    Baseline::HuaWang,
    Baseline::Lattice,
    Baseline::Lhs,
    Baseline::LhsMaximin,
];

/// The names and aliases [`Baseline::parse`] reads.
const NAMES: [(&str, Baseline); 11] = [
    ("random", Baseline::Random),
    ("halton", Baseline::Halton),
    ("halton-scrambled", Baseline::ScrambledHalton),
    ("sobol", Baseline::Sobol),
    ("hua-wang", Baseline::HuaWang),
    ("lattice", Baseline::Lattice),
    ("lhs", Baseline::Lhs),
    ("lhs-maximin", Baseline::LhsMaximin),
    ("hs", Baseline::ScrambledHalton),
    ("ss", Baseline::Sobol),
    ("hw", Baseline::HuaWang),
];

/// What a refused name is told: every accepted name, aliases in brackets.
const ACCEPTED: &str = "one of: random, halton, halton-scrambled (hs), sobol (ss), \
                        hua-wang (hw), lattice, lhs, lhs-maximin";

impl Baseline {
    /// Every baseline, in the order tables list them.
    pub fn all() -> &'static [Baseline] {
        &ALL
    }

    /// The baseline with a command-line name or alias: `random`, `halton`,
    /// `halton-scrambled` (`hs`), `sobol` (`ss`), `hua-wang` (`hw`), `lattice`, `lhs`,
    /// `lhs-maximin`. Case and surrounding spaces are ignored, and `_` counts as `-`.
    pub fn parse(name: &str) -> Result<Baseline, Error> {
        let key = name.trim().to_ascii_lowercase().replace('_', "-");
        NAMES
            .iter()
            .find(|(n, _)| *n == key)
            .map(|(_, b)| *b)
            .ok_or_else(|| Error::invalid("baseline", name, ACCEPTED))
    }

    /// Every name and alias [`Baseline::parse`] accepts, names first in the order of
    /// [`Baseline::all`].
    pub fn names() -> Vec<&'static str> {
        NAMES.iter().map(|(n, _)| *n).collect()
    }

    /// The command-line name ([`Baseline::parse`] accepts it).
    pub fn name(&self) -> &'static str {
        match self {
            Baseline::Random => "random",
            Baseline::Halton => "halton",
            Baseline::ScrambledHalton => "halton-scrambled",
            Baseline::Sobol => "sobol",
            Baseline::HuaWang => "hua-wang",
            Baseline::Lattice => "lattice",
            Baseline::Lhs => "lhs",
            Baseline::LhsMaximin => "lhs-maximin",
        }
    }

    /// Short label for table columns and legends.
    pub fn label(&self) -> &'static str {
        match self {
            Baseline::Random => "random",
            Baseline::Halton => "Halton",
            Baseline::ScrambledHalton => "HS",
            Baseline::Sobol => "SS",
            Baseline::HuaWang => "HW",
            Baseline::Lattice => "lattice",
            Baseline::Lhs => "LHS",
            Baseline::LhsMaximin => "LHS-maximin",
        }
    }

    /// One paragraph saying exactly which construction this is: variant, index range,
    /// randomisation, limits and references.
    pub fn describe(&self) -> &'static str {
        match self {
            Baseline::Random => {
                "Monte Carlo: n points drawn independently and uniformly in [0,1)^s, \
                 coordinates drawn row by row from Xoshiro256++ seeded with the seed \
                 (seed_from_u64), so a shorter draw is a prefix of a longer one."
            }
            Baseline::Halton => {
                "Plain (unscrambled) Halton sequence, indices 1..=n (the origin, index 0, is \
                 skipped, as in the paper's Table 5 row [15]; SciPy's Halton(scramble=False) \
                 starts at 0), dimension j in the j-th prime base (2, 3, 5, ...), each \
                 radical inverse correctly rounded. Deterministic; known to degrade in high \
                 dimensions (correlated large bases). Halton (1960), Numer. Math. 2."
            }
            Baseline::ScrambledHalton => {
                "Scrambled Halton (HS): indices 0..n-1, dimension j in the j-th prime base b, \
                 every digit position k = 1..D of the radical inverse (leading zeros \
                 included) mapped through its own independent uniformly random permutation \
                 of {0..b-1}, D the smallest with b^D >= 2^53; the randomisation of SciPy's \
                 Halton(scramble=True) (Owen 2017, 'A randomized Halton algorithm in R', \
                 arXiv:1706.02808), not a nested scramble. Values truncated to multiples of \
                 2^-53. Keeps each dimension's van der Corput stratification. s <= 100000."
            }
            Baseline::Sobol => {
                "Scrambled Sobol' (SS): Joe-Kuo D6 direction numbers (new-joe-kuo-6.21201, \
                 SIAM J. Sci. Comput. 2008), 32-bit net, indices 0..n-1 in natural (not \
                 Gray-code) order, with Owen's nested uniform scrambling (Owen 1995) \
                 implemented by hashing (seed, dimension, bit level, all higher bits) into \
                 each bit's flip, and the 21 bits below the net's resolution drawn by hash \
                 too, giving 53-bit values in [0,1). Keeps the (t,m,s)-net structure: for \
                 n = 2^m each dimension has one point per interval of width 2^-m and \
                 dimensions 1-2 form a (0,m,2)-net. SciPy's Sobol(scramble=True) is \
                 different: a linear matrix scramble plus digital shift (LMS + shift). \
                 n <= 2^32, s <= 21201."
            }
            Baseline::HuaWang => {
                "Hua-Wang good points (HW) from the cyclotomic field: p the smallest prime \
                 >= 2s+3, gamma_j = 2cos(2*pi*j/p) for j = 1..s, point k = frac(k*gamma), \
                 k = 1..n. Deterministic. Hua & Wang (1981), Applications of Number Theory \
                 to Numerical Analysis, Springer / Science Press."
            }
            Baseline::Lattice => {
                "Unshifted rank-1 lattice (contains the origin): x_k = frac(k*z/n), \
                 k = 0..n-1, exact integer arithmetic. s = 2 with n = F_m a Fibonacci number: \
                 the Fibonacci lattice z = (1, F_{m-1}); otherwise the Korobov vector \
                 z = (1, a, a^2, ...) mod n with a coprime to n minimising P_2, the squared \
                 worst-case error in the unweighted Korobov space with alpha = 2 \
                 (P_2 = -1 + (1/n) sum_k prod_j (1 + 2 pi^2 B2({k z_j/n})), Sloan & Joe \
                 1994), searched over all a in 1..n/2 while that costs at most 2^28 \
                 point-coordinate steps (n up to about 5000 at s = 20), else over an evenly \
                 spaced sample of max(32, 2^28/(n s)) multipliers. Deterministic."
            }
            Baseline::Lhs => {
                "Latin hypercube: x_ij = (pi_j(i) + U_ij)/n with independent uniformly random \
                 permutations pi_j of the n strata and independent uniform jitter U_ij, like \
                 SciPy's LatinHypercube(scramble=True); each column has exactly one point per \
                 stratum [k/n, (k+1)/n). McKay, Beckman & Conover (1979)."
            }
            Baseline::LhsMaximin => {
                "Maximin Latin hypercube: the 'lhs' design for the same seed, improved by a \
                 seeded simulated annealing over swaps of two points' coordinates within one \
                 column (Morris & Mitchell 1995; like DiceDesign's maximinSA_LHS): criterion \
                 (sum over points of nn^-50)^(1/50), nn the nearest-neighbour distance; moves \
                 from an end of the closest pair half the time; temperature 1e-2 -> 1e-5, \
                 geometric in the budget spent, on the relative change; budget at most \
                 1000 n swaps and 2^29 coordinate operations (2 n s per swap), after an \
                 n^2 s/2 nearest-neighbour pass for the start. Returns the visited design \
                 with the largest minimum Euclidean distance, never worse than the start. \
                 n <= 20000."
            }
        }
    }

    /// Whether the seed changes the points (false for the deterministic constructions).
    pub fn is_randomized(&self) -> bool {
        matches!(
            self,
            Baseline::Random
                | Baseline::ScrambledHalton
                | Baseline::Sobol
                | Baseline::Lhs
                | Baseline::LhsMaximin
        )
    }

    /// n points in [0, 1)^s from this baseline; `seed` is ignored by the deterministic
    /// ones. Refuses n = 0, s = 0 and each generator's own limits (see
    /// [`Baseline::describe`]) with an error naming the argument and the accepted range.
    pub fn generate(&self, n: usize, s: usize, seed: u64) -> Result<PointSet, Error> {
        match self {
            Baseline::Random => random(n, s, seed),
            Baseline::Halton => halton(n, s),
            Baseline::ScrambledHalton => halton_scrambled(n, s, seed),
            Baseline::Sobol => sobol_scrambled(n, s, seed),
            Baseline::HuaWang => hua_wang(n, s),
            Baseline::Lattice => lattice(n, s),
            Baseline::Lhs => lhs(n, s, seed),
            Baseline::LhsMaximin => lhs_maximin(n, s, seed),
        }
    }
}

impl fmt::Display for Baseline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Baseline {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Baseline::parse(name)
    }
}
