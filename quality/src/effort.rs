//! How much work the integration goal spends ([`Effort`]) and what that allows at n
//! points in s dimensions ([`Budget`]). It sits with the measures, below the goals,
//! because the default target ([`crate::target::Target::default_for`]) depends on
//! whether the descent runs at all.

/// Most points whose pair table the exchanges of the descent keep (n² values: 134 MB at
/// this n).
pub const EXCHANGE_MAX_N: usize = 4096;

/// Above this many points the block exchanges get less work, as 1/n: a proposal costs
/// O(n) and a block holds fewer points, so the same time buys less.
pub const BLOCKS_FADE_FROM: usize = 200_000;

/// How much work the integration goal's descent (`integration_set`) spends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effort {
    /// Scrambled Sobol' starts (scrambled Halton is one more).
    pub starts: usize,
    /// Rounds of exchanges then offsets.
    pub rounds: usize,
    /// Exchange proposals per round, per point and coordinate.
    pub proposals: usize,
    /// L-BFGS iterations per round.
    pub lbfgs_steps: usize,
    /// A cap on the exchange work of the whole run, in pair-factor updates (one proposal
    /// costs n per discrepancy of the target, about 2.5 ns each on one core): what keeps
    /// the largest sets within seconds.
    pub exchange_work: u64,
    /// A cap on the L-BFGS work of the whole run, and through it on the starts compared,
    /// in pairs × coordinates × iterations (see [`Budget`]).
    pub work: u64,
    /// Where no L-BFGS iteration fits the cap, the work of the block exchanges that run
    /// instead (the block exchanges), in pair-factor products.
    pub block_work: u64,
    /// How the target is evaluated where no descent runs (exact, or estimated above a
    /// size): the values a report shows, not what the run compares.
    pub sums: crate::metrics::Sums,
}

impl Effort {
    /// The block exchanges' work for n points: `block_work`, shrinking as 1/n above
    /// [`BLOCKS_FADE_FROM`] (a proposal costs O(n) and a block holds fewer points, so the
    /// same time buys less, while the rest of a run of 10⁶ points stays about a minute).
    pub fn block_work_at(&self, n: usize) -> u64 {
        (self.block_work as f64 * (BLOCKS_FADE_FROM as f64 / n.max(1) as f64).min(1.0)) as u64
    }
}

impl Default for Effort {
    fn default() -> Self {
        Effort {
            starts: 8,
            rounds: 3,
            proposals: 20,
            lbfgs_steps: 30,
            exchange_work: 3_000_000_000,
            // Three rounds of 30 iterations up to n = 8 192 at s = 5 (n²·s = 3.4·10⁸),
            // which took 31 s on the 2-core machine: about 1 ns per unit.
            work: 35_000_000_000,
            // About as long as the L-BFGS cap where it stops fitting (no cliff in time at
            // that n): about 0.6 ns per product on the 2-core machine.
            block_work: 60_000_000_000,
            sums: crate::metrics::Sums::AUTO,
        }
    }
}

/// What the work cap of an [`Effort`] allows for n points in s dimensions. One L-BFGS
/// iteration on the blended target costs about n²·s units (value and gradient of its
/// discrepancies, with the line search), and each round about [`ROUND_OVERHEAD`]
/// iterations more (its start, its end and the target's normalisation); one evaluation of
/// the target to compare a start costs about n²·s·2/5. Above [`EXCHANGE_MAX_N`] points,
/// where no exchanges run between rounds, there is one round. The rounds get the whole cap, the
/// start comparisons a third of it more, so a run's cost grows smoothly with n and the
/// descent fades out (fewer iterations, fewer rounds, then fewer starts) instead of
/// stopping at one n.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    /// Rounds of exchanges then L-BFGS.
    pub rounds: usize,
    /// L-BFGS iterations per round.
    pub steps: usize,
    /// Candidate starts to compare (Sobol' sets, then Halton), at least 1.
    pub starts: usize,
}

/// The cost of a round of the descent beyond its iterations, in iterations.
pub const ROUND_OVERHEAD: usize = 3;

impl Budget {
    /// The budget of `effort` at n points in s dimensions.
    pub fn of(n: usize, s: usize, effort: &Effort) -> Budget {
        let unit = (n as u128 * n as u128 * s as u128).max(1);
        let available = (u128::from(effort.work) / unit).min(1 << 20) as usize;
        let fits = available / (1 + ROUND_OVERHEAD);
        // Without exchanges between them (their tables stop at EXCHANGE_MAX_N), rounds
        // would only restart L-BFGS: one round gets every iteration instead.
        let (rounds, most) = if n > EXCHANGE_MAX_N {
            (fits.min(1), effort.rounds * effort.lbfgs_steps)
        } else {
            (effort.rounds.min(fits), effort.lbfgs_steps)
        };
        let steps = available
            .checked_div(rounds)
            .map_or(0, |per| (per - ROUND_OVERHEAD).min(most));
        let comparable = u128::from(effort.work) * 5 / (6 * unit);
        let starts = comparable.clamp(1, effort.starts as u128 + 1) as usize;
        Budget {
            rounds,
            steps,
            starts,
        }
    }

    /// Whether the descent runs at all (at least one L-BFGS iteration fits).
    pub fn descends(&self) -> bool {
        self.steps > 0
    }
}
