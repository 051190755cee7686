//! Deterministic parallel loops over unordered pairs of points, and the vector types
//! their kernels are written in.
//!
//! The points are cut into blocks whose number depends on n only (never on the thread
//! count), and the block pairs are scheduled in rounds by the circle method so that the
//! tiles of one round touch disjoint gradient rows. Tiles of a round run in parallel;
//! rounds run in order. Every row therefore receives its contributions in the same order
//! whatever the number of threads, and each pair is visited once (half the work of a full
//! loop). Value-only sums visit the same tiles without the round barriers and add the
//! tiles' partial sums in the same fixed order, so they have the same bits as the sums of
//! the gradient loops.
//!
//! **Vector kernels.** `Simd` is a vector of f64 lanes with two base implementations of
//! four lanes: AVX2 + FMA intrinsics, chosen at run time when the processor has them, and
//! plain arrays for any other x86-64 or architecture. The kernels run on `Wide`, four
//! such vectors side by side (16 lanes): the powers of U_{q,p} are long chains of
//! dependent operations, and four independent chains in one instruction stream keep the
//! pipelines full where one chain would wait on latency. A kernel is written once, generic
//! over the trait, and compiled twice (see `run_sum_tile`). Both do the same IEEE
//! operations in the same order except `Simd::mul_add`, which is fused on AVX2 and a
//! rounded product plus a sum otherwise; so a kernel that avoids `mul_add` gives the same
//! bits on every machine, and one that uses it may differ in the last bits between
//! machines, never between thread counts. A third build, AVX-512 with eight lanes, runs
//! only the kernels written for it (`sum_tiles_on`): the others' arguments (horizontal
//! sums, `rows4`) are made for four lanes. The kernels read block-transposed copies of the
//! coordinates (`Blocks`: per block, coordinate k of its points is contiguous), so the
//! lanes are consecutive points j and one load fetches them.

use rayon::prelude::*;
use std::ops::Range;

/// At most this many blocks: enough tiles per round to keep every core busy, few enough
/// rounds that their synchronisation stays negligible.
const MAX_BLOCKS: usize = 64;

/// Base vectors side by side in the kernels' [`Wide`] vectors.
const WIDE: usize = 4;

/// Blocks are a multiple of this many points, so that kernels can use vectors of up to 16
/// lanes without a partial vector inside a block.
const LANES: usize = 16;

/// Smallest block of the vector kernels: a round's barrier costs a few microseconds, so a
/// tile should hold at least 32 × 32 pairs.
const MIN_BLOCK: usize = 32;

/// Below this many pair-coordinates (n² s / 2) a loop runs on the calling thread: the
/// rounds' barriers would cost more than the work. The tiles and their order are the
/// same either way, so the bits are too.
const PARALLEL_WORK: usize = 1 << 17;

/// The circle-method schedule over `real` blocks: round 0 is the diagonal tiles (b, b) in
/// block order; round r ≥ 1 pairs (r − 1, m) and (r − 1 + k, r − 1 − k) mod m, k = 1 …
/// nb/2 − 1, with m = nb − 1 and nb = real rounded up to even (tiles with the padding
/// block are dropped). Within a round no block appears twice.
fn schedule(real: usize) -> Vec<Vec<(usize, usize)>> {
    let nb = real + real % 2;
    let m = nb - 1;
    let mut rounds = vec![(0..real).map(|b| (b, b)).collect::<Vec<_>>()];
    for r in 0..m {
        let mut pairs = Vec::with_capacity(nb / 2);
        pairs.push((r, m));
        for k in 1..nb / 2 {
            let a = (r + k) % m;
            let b = (r + m - k) % m;
            pairs.push((a.min(b), a.max(b)));
        }
        pairs.retain(|&(_, b)| b < real);
        rounds.push(pairs);
    }
    rounds
}

/// Runs `tile(a, b, ga, gb)` on every tile of [`schedule`], `ga` and `gb` being the
/// `chunk`-long pieces a and b of `buf` (`gb` is `None` on the diagonal, a = b), and adds
/// the returned partial sums in the schedule's order: each round's tiles from 0.0, then the
/// rounds into the total.
fn for_each_block_pair<F>(
    real: usize,
    chunk: usize,
    buf: &mut [f64],
    parallel: bool,
    tile: F,
) -> f64
where
    F: Fn(usize, usize, &mut [f64], Option<&mut [f64]>) -> f64 + Sync,
{
    debug_assert!(buf.len() >= real * chunk);
    let mut total = 0.0;
    for round in schedule(real) {
        let mut slots: Vec<Option<&mut [f64]>> =
            buf.chunks_mut(chunk).take(real).map(Some).collect();
        let tasks: Vec<_> = round
            .into_iter()
            .map(|(a, b)| {
                let ga = slots[a].take().expect("a block appears once per round");
                let gb = if a == b {
                    None
                } else {
                    Some(slots[b].take().expect("a block appears once per round"))
                };
                (a, b, ga, gb)
            })
            .collect();
        // A stop request (Ctrl-C in Python) skips the tiles left: the caller discards
        // the partial sum.
        let run = |(a, b, ga, gb): (usize, usize, &mut [f64], Option<&mut [f64]>)| {
            if crate::stop::requested() {
                0.0
            } else {
                tile(a, b, ga, gb)
            }
        };
        let parts: Vec<f64> = if parallel {
            tasks.into_par_iter().map(run).collect()
        } else {
            tasks.into_iter().map(run).collect()
        };
        total += parts.iter().fold(0.0, |acc, v| acc + v);
    }
    total
}

/// Visits every pair i < j once. `tile(i_range, j_range, gi, gj)` handles the pairs
/// with i in `i_range` and j in `j_range` (and i < j when the ranges coincide), adding
/// forces to the gradient rows `gi` (for `i_range`) and `gj` (for `j_range`), and returns
/// a partial sum; the partial sums are added in a fixed order and returned.
///
/// For a diagonal tile `gj` is empty and all forces go to `gi`.
pub fn for_each_pair_tile<F>(n: usize, s: usize, grad: &mut [f64], tile: F) -> f64
where
    F: Fn(Range<usize>, Range<usize>, &mut [f64], &mut [f64]) -> f64 + Sync,
{
    assert_eq!(grad.len(), n * s, "gradient buffer length");
    if n < 2 {
        return 0.0;
    }
    let bs = n.div_ceil(MAX_BLOCKS.min(n));
    let real = n.div_ceil(bs);
    let range = |b: usize| (b * bs).min(n)..((b + 1) * bs).min(n);
    for_each_block_pair(real, bs * s, grad, true, |a, b, ga, gb| match gb {
        Some(gb) => tile(range(a), range(b), ga, gb),
        None => tile(range(a), range(b), ga, &mut []),
    })
}

/// Inside a tile of [`for_each_pair_tile`]: adds w·v to the gradient row of point i and
/// −w·v to that of point j (a pair force), given the first indices of the tile's two
/// blocks. On a diagonal tile `gj` is empty and both rows are in `gi`.
#[inline]
pub fn scatter_pair(
    gi: &mut [f64],
    gj: &mut [f64],
    (ri0, rj0): (usize, usize),
    (i, j): (usize, usize),
    w: f64,
    v: &[f64],
) {
    let s = v.len();
    let oi = (i - ri0) * s;
    if gj.is_empty() {
        let oj = (j - ri0) * s;
        for k in 0..s {
            gi[oi + k] += w * v[k];
            gi[oj + k] -= w * v[k];
        }
    } else {
        let oj = (j - rj0) * s;
        for k in 0..s {
            gi[oi + k] += w * v[k];
            gj[oj + k] -= w * v[k];
        }
    }
}

/// The smallest squared Euclidean distance and the smallest squared distance on the unit
/// torus (coordinate differences Δ counted as min(|Δ|, 1 − |Δ|)) over all pairs, in one
/// vectorised pass; +∞ for a single point. A minimum does not depend on the order it is
/// taken in, so the result has the same bits for any thread count, and no fused
/// multiply-add is used, so it has the same bits on every machine.
pub fn min_squared_distances(x: &[f64], n: usize, s: usize) -> [f64; 2] {
    assert_eq!(x.len(), n * s, "coordinate buffer length");
    if n < 2 {
        return [f64::INFINITY; 2];
    }
    let blocks = Blocks::new(n, s);
    let xt = blocks.transpose(x, |v| v);
    let kernel = MinDistances {
        blocks: &blocks,
        xt: &xt,
    };
    sum_tiles(
        &blocks,
        &kernel,
        || [f64::INFINITY; 2],
        |a, b| [a[0].min(b[0]), a[1].min(b[1])],
    )
}

struct MinDistances<'a> {
    blocks: &'a Blocks,
    xt: &'a [f64],
}

impl SumTiles for MinDistances<'_> {
    type Out = [f64; 2];

    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize) -> [f64; 2] {
        let bl = self.blocks;
        let (bs, s) = (bl.bs, bl.s);
        let (xa, xb) = (bl.chunk(self.xt, a), bl.chunk(self.xt, b));
        let inf = V::splat(f64::INFINITY);
        let (mut me, mut mp) = (inf, inf);
        let (one, half) = (V::splat(1.0), V::splat(0.5));
        for ii in 0..bl.len(a) {
            for (jj, mask) in bl.lanes::<V>(a, b, ii) {
                let (mut de, mut dp) = (V::splat(0.0), V::splat(0.0));
                for k in 0..s {
                    let xi = V::splat(xa[k * bs + ii]);
                    let d = xi.sub(V::load(&xb[k * bs + jj..])).abs();
                    de = de.add(d.mul(d));
                    // min(Δ, 1 − Δ) as the scalar metric writes it: Δ > ½ takes 1 − Δ.
                    let w = d.gt(half).select(one.sub(d), d);
                    dp = dp.add(w.mul(w));
                }
                me = me.min(mask.select(de, inf));
                mp = mp.min(mask.select(dp, inf));
            }
        }
        [me.hmin(), mp.hmin()]
    }
}

/// The block layout of the vector kernels: blocks of `bs` points (a multiple of
/// [`LANES`], at least [`MIN_BLOCK`], at most [`MAX_BLOCKS`] blocks), each stored
/// coordinate-major (`bs` values of coordinate 0, then of coordinate 1, …), the last
/// block padded with zeros. Depends on n and s only.
pub(crate) struct Blocks {
    /// Number of points.
    pub n: usize,
    /// Coordinates per point.
    pub s: usize,
    /// Points per block.
    pub bs: usize,
    /// Number of blocks.
    pub real: usize,
}

impl Blocks {
    pub fn new(n: usize, s: usize) -> Blocks {
        let bs = n
            .div_ceil(MAX_BLOCKS)
            .max(MIN_BLOCK)
            .min(n.next_multiple_of(LANES));
        let bs = bs.next_multiple_of(LANES);
        Blocks {
            n,
            s,
            bs,
            real: n.div_ceil(bs),
        }
    }

    /// Values per block.
    pub fn chunk_len(&self) -> usize {
        self.bs * self.s
    }

    /// Length of a block-transposed buffer.
    pub fn total_len(&self) -> usize {
        self.real * self.chunk_len()
    }

    /// Block b of a block-transposed buffer.
    #[inline(always)]
    pub fn chunk<'a>(&self, buf: &'a [f64], b: usize) -> &'a [f64] {
        &buf[b * self.chunk_len()..(b + 1) * self.chunk_len()]
    }

    /// Real points in block b.
    #[inline(always)]
    pub fn len(&self, b: usize) -> usize {
        self.bs.min(self.n - b * self.bs)
    }

    /// Whether a loop should use the rayon pool (see [`PARALLEL_WORK`]).
    pub fn parallel(&self) -> bool {
        self.n * self.n / 2 * self.s >= PARALLEL_WORK
    }

    /// The block-transposed copy of the row-major `x`, with `f` applied to every value.
    pub(crate) fn transpose(&self, x: &[f64], f: impl Fn(f64) -> f64) -> AlignedBuf {
        let (bs, s) = (self.bs, self.s);
        let mut t = AlignedBuf::zeros(self.total_len());
        for (i, row) in x.chunks_exact(s).enumerate() {
            let base = (i / bs) * bs * s + i % bs;
            for (k, &v) in row.iter().enumerate() {
                t[base + k * bs] = f(v);
            }
        }
        t
    }

    /// Writes `scale` times the block-transposed `t` into the row-major `out`.
    pub fn untranspose(&self, t: &[f64], out: &mut [f64], scale: f64) {
        let (bs, s) = (self.bs, self.s);
        for (i, row) in out.chunks_exact_mut(s).enumerate() {
            let base = (i / bs) * bs * s + i % bs;
            for (k, v) in row.iter_mut().enumerate() {
                *v = scale * t[base + k * bs];
            }
        }
    }

    /// The lane groups of row ii of block a against block b: the first point jj of each
    /// group of `V::N` in block b and the mask of its lanes that are real pairs (j < n, and
    /// j > i on the diagonal). On the diagonal the groups start at the one holding ii + 1.
    #[inline(always)]
    pub fn lanes<V: Simd>(
        &self,
        a: usize,
        b: usize,
        ii: usize,
    ) -> impl Iterator<Item = (usize, V)> {
        let len = self.len(b);
        let start = if a == b { (ii + 1) / V::N * V::N } else { 0 };
        let lo = if a == b { ii + 1 } else { 0 };
        (start..len).step_by(V::N).map(move |jj| {
            let mask = if jj >= lo && jj + V::N <= len {
                V::TRUE
            } else {
                V::from_fn(|l| {
                    let j = jj + l;
                    if j >= lo && j < len {
                        f64::from_bits(u64::MAX)
                    } else {
                        0.0
                    }
                })
            };
            (jj, mask)
        })
    }
}

/// A value-only pair kernel: `tile(a, b)` returns the partial result of the pairs between
/// blocks a and b (i < j when a = b).
pub(crate) trait SumTiles: Sync {
    type Out: Send;
    fn tile<V: Simd>(&self, a: usize, b: usize) -> Self::Out;
}

/// A pair kernel with a gradient: `tile(a, b, ga, gb)` adds the forces of the pairs
/// between blocks a and b to their block-transposed gradient chunks (`gb` is `None` when
/// a = b) and returns the partial value.
pub(crate) trait GradTiles: Sync {
    fn tile<V: Simd>(&self, a: usize, b: usize, ga: &mut [f64], gb: Option<&mut [f64]>) -> f64;
}

/// Runs a value-only kernel over every tile of [`schedule`] (in parallel, without the
/// rounds' barriers) and combines the partial results in the schedule's order, exactly as
/// [`grad_tiles`] adds its partial sums.
pub(crate) fn sum_tiles<K: SumTiles>(
    blocks: &Blocks,
    kernel: &K,
    zero: impl Fn() -> K::Out,
    add: impl Fn(&K::Out, &K::Out) -> K::Out,
) -> K::Out {
    let build = if use_avx2() {
        Build::Avx2
    } else {
        Build::Portable
    };
    sum_tiles_on(build, blocks, kernel, zero, add)
}

/// [`sum_tiles`] on the given build, which must be available (panics otherwise). Only a
/// kernel whose tiles have the same bits with base vectors of eight lanes may be run on
/// [`Build::Avx512`]: the other kernels' arguments are made for four.
pub(crate) fn sum_tiles_on<K: SumTiles>(
    build: Build,
    blocks: &Blocks,
    kernel: &K,
    zero: impl Fn() -> K::Out,
    add: impl Fn(&K::Out, &K::Out) -> K::Out,
) -> K::Out {
    assert!(build.available(), "{build:?} is not available here");
    let rounds = schedule(blocks.real);
    let flat: Vec<(usize, usize)> = rounds.iter().flatten().copied().collect();
    // A stop request (Ctrl-C in Python) skips the tiles left: the caller discards the
    // partial sum.
    let run = |&(a, b): &(usize, usize)| {
        (!crate::stop::requested()).then(|| run_sum_tile(build, kernel, a, b))
    };
    let parts: Vec<Option<K::Out>> = if blocks.parallel() {
        flat.par_iter().map(run).collect()
    } else {
        flat.iter().map(run).collect()
    };
    let mut parts = parts.into_iter().map(|p| p.unwrap_or_else(&zero));
    let mut total = zero();
    for round in &rounds {
        let mut r = zero();
        for _ in round {
            r = add(&r, &parts.next().expect("one part per tile"));
        }
        total = add(&total, &r);
    }
    total
}

/// Runs a gradient kernel over every tile of [`schedule`] on the block-transposed buffer
/// `gt` (see [`for_each_block_pair`]) and returns the sum of the partial values.
pub(crate) fn grad_tiles<K: GradTiles>(blocks: &Blocks, kernel: &K, gt: &mut [f64]) -> f64 {
    for_each_block_pair(
        blocks.real,
        blocks.chunk_len(),
        gt,
        blocks.parallel(),
        |a, b, ga, gb| run_grad_tile(kernel, a, b, ga, gb),
    )
}

/// 64 bytes of f64: the unit of [`AlignedBuf`].
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Line([f64; 8]);

/// An f64 buffer that starts on a cache line, so that the kernels' 32-byte vector loads
/// at multiples of 4 never straddle two lines (the allocator only promises 16 bytes).
#[derive(Clone, Default)]
pub(crate) struct AlignedBuf {
    lines: Vec<Line>,
    len: usize,
}

impl AlignedBuf {
    /// `len` zeros.
    pub(crate) fn zeros(len: usize) -> Self {
        AlignedBuf {
            lines: vec![Line::default(); len.div_ceil(8)],
            len,
        }
    }

    /// At least `len` values, keeping the buffer when it is long enough.
    fn grow(&mut self, len: usize) {
        if self.len < len {
            *self = AlignedBuf::zeros(len);
        }
    }
}

impl std::ops::Deref for AlignedBuf {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        // SAFETY: `lines` holds `len.div_ceil(8)` lines of 8 f64 each, contiguous
        // (`repr(C)`, size 64), so its first `len` f64 are initialised and in bounds.
        unsafe { std::slice::from_raw_parts(self.lines.as_ptr().cast::<f64>(), self.len) }
    }
}

impl std::ops::DerefMut for AlignedBuf {
    fn deref_mut(&mut self) -> &mut [f64] {
        // SAFETY: as in `deref`, borrowed mutably through `self`.
        unsafe { std::slice::from_raw_parts_mut(self.lines.as_mut_ptr().cast::<f64>(), self.len) }
    }
}

thread_local! {
    /// Each worker's scratch buffer, reused across tiles and calls.
    static SCRATCH: std::cell::Cell<AlignedBuf> = const {
        std::cell::Cell::new(AlignedBuf { lines: Vec::new(), len: 0 })
    };
}

/// This thread's scratch buffer with at least `len` values (contents unspecified; the
/// kernels write before they read). Allocates only when a larger buffer is first needed.
pub(crate) fn take_scratch(len: usize) -> AlignedBuf {
    let mut v = SCRATCH.take();
    v.grow(len);
    v
}

/// Returns a buffer from [`take_scratch`] for the next tile on this thread.
pub(crate) fn give_scratch(v: AlignedBuf) {
    SCRATCH.set(v);
}

/// Which implementation of `Simd` the kernels use: `"avx2+fma"` or `"portable"`.
/// The environment variable `STILLPOINT_PORTABLE=1` (read once) forces the portable one,
/// so that it can be tested and timed on a machine that has AVX2. The kernels that run on
/// AVX-512 where the processor has it (see `use_avx512`) give the bits of their AVX2
/// build, so the name stays that of the bits.
pub fn vector_path() -> &'static str {
    if use_avx2() {
        "avx2+fma"
    } else {
        "portable"
    }
}

/// Whether the AVX2 builds run (see [`vector_path`]): the one decision every kernel with
/// an AVX2 build follows.
pub(crate) fn use_avx2() -> bool {
    static AVX2: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVX2.get_or_init(|| {
        let forced = std::env::var("STILLPOINT_PORTABLE").is_ok_and(|v| !v.is_empty() && v != "0");
        #[cfg(target_arch = "x86_64")]
        {
            !forced && is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = forced;
            false
        }
    })
}

/// Whether the AVX-512 build of the kernels that allow it runs: where the AVX2 builds
/// run (see [`use_avx2`]), the processor has AVX-512 F and DQ, and the environment
/// variable `STILLPOINT_NO_AVX512=1` (read once) does not ask for the AVX2 build, so that
/// the two can be compared and timed on one machine. Its results have the bits of the
/// AVX2 build, so [`vector_path`] does not tell them apart.
pub(crate) fn use_avx512() -> bool {
    static AVX512: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVX512.get_or_init(|| {
        let off = std::env::var("STILLPOINT_NO_AVX512").is_ok_and(|v| !v.is_empty() && v != "0");
        !off && use_avx2() && Build::Avx512.available()
    })
}

/// The builds of a value-only kernel (see [`sum_tiles_on`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Build {
    /// Four-lane plain arrays.
    Portable,
    /// Four-lane AVX2 + FMA vectors.
    Avx2,
    /// Eight-lane AVX-512 vectors.
    Avx512,
}

impl Build {
    /// Whether the processor runs this build.
    pub(crate) fn available(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            let avx2 = || is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
            match self {
                Build::Portable => true,
                Build::Avx2 => avx2(),
                Build::Avx512 => {
                    avx2()
                        && is_x86_feature_detected!("avx512f")
                        && is_x86_feature_detected!("avx512dq")
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Build::Portable
        }
    }
}

fn run_sum_tile<K: SumTiles>(build: Build, kernel: &K, a: usize, b: usize) -> K::Out {
    match build {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX2 and FMA (`sum_tiles_on` checked the build).
        Build::Avx2 => unsafe { avx2::sum_tile(kernel, a, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX-512 F and DQ, AVX2 and FMA (`sum_tiles_on`
        // checked the build).
        Build::Avx512 => unsafe { avx512::sum_tile(kernel, a, b) },
        _ => kernel.tile::<Wide<Portable, WIDE>>(a, b),
    }
}

fn run_grad_tile<K: GradTiles>(
    kernel: &K,
    a: usize,
    b: usize,
    ga: &mut [f64],
    gb: Option<&mut [f64]>,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if use_avx2() {
        // SAFETY: the processor has AVX2 and FMA (checked by `use_avx2`).
        return unsafe { avx2::grad_tile(kernel, a, b, ga, gb) };
    }
    kernel.tile::<Wide<Portable, WIDE>>(a, b, ga, gb)
}

/// A vector of `N` f64 lanes. Comparisons return masks (all bits set in a lane that holds), which
/// [`Simd::select`] and the bitwise operations consume. `min`/`max` return the second
/// operand unless the first is strictly smaller/larger, as `vminpd`/`vmaxpd` do.
pub(crate) trait Simd: Copy + Send + Sync + 'static {
    /// Number of lanes.
    const N: usize;
    /// The all-true mask.
    const TRUE: Self;
    /// The single vector this one is made of (itself, or the part of a [`Wide`]): for
    /// kernels with short dependency chains and many live values, where side-by-side
    /// vectors would only run out of registers.
    type Base: Simd;
    fn splat(x: f64) -> Self;
    /// The first `N` values of `s`.
    fn load(s: &[f64]) -> Self;
    /// Writes the lanes to the first `N` values of `s`.
    fn store(self, s: &mut [f64]);
    /// Lane l is `f(l)`.
    fn from_fn(f: impl Fn(usize) -> f64) -> Self;
    /// The sum of the lanes in a fixed order.
    fn hsum(self) -> f64;
    /// The smallest lane.
    fn hmin(self) -> f64;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    /// self·b + c: fused (one rounding) on AVX2, two roundings on the portable path.
    fn mul_add(self, b: Self, c: Self) -> Self;
    fn min(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn lt(self, o: Self) -> Self;
    fn gt(self, o: Self) -> Self;
    fn eq(self, o: Self) -> Self;
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// Lanes of `a` where the mask `self` is set, else of `b`.
    fn select(self, a: Self, b: Self) -> Self;
    /// Whether the mask `self` is set in any lane (its sign bit, as `select` reads it).
    fn any(self) -> bool;
    /// Lane-wise u64 shift right / left by 52 bits (46 for `shr46`) and u64 addition of the
    /// bit patterns.
    fn shr52(self) -> Self;
    fn shr46(self) -> Self;
    fn shl52(self) -> Self;
    fn add_bits(self, o: Self) -> Self;
    /// The vectors (c₀, c₁, c₂, c₃) with lane l of c_k = `table[i & 2047][k]`, i the bits
    /// of `idx[l]` read as an integer: four table coefficients per lane, fetched as rows
    /// and transposed.
    fn rows4(table: &[[f64; 4]; 2048], idx: &[f64]) -> [Self; 4];
    #[inline(always)]
    fn abs(self) -> Self {
        self.and(Self::splat(f64::from_bits(!SIGN)))
    }
}

const SIGN: u64 = 1 << 63;

/// The portable implementation: plain arrays, which the compiler vectorises as far as the
/// baseline instruction set allows.
#[derive(Clone, Copy)]
pub(crate) struct Portable([f64; 4]);

impl Portable {
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Portable(self.0.map(f))
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Portable(std::array::from_fn(|l| f(self.0[l], o.0[l])))
    }
    #[inline(always)]
    fn bits(self, o: Self, f: impl Fn(u64, u64) -> u64) -> Self {
        self.zip(o, |a, b| f64::from_bits(f(a.to_bits(), b.to_bits())))
    }
    #[inline(always)]
    fn cmp(self, o: Self, f: impl Fn(f64, f64) -> bool) -> Self {
        self.zip(o, |a, b| f64::from_bits(if f(a, b) { u64::MAX } else { 0 }))
    }
}

impl Simd for Portable {
    const N: usize = 4;
    const TRUE: Self = Portable([f64::from_bits(u64::MAX); 4]);
    type Base = Self;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Portable([x; 4])
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        Portable([s[0], s[1], s[2], s[3]])
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        s[..4].copy_from_slice(&self.0);
    }
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> f64) -> Self {
        Portable([f(0), f(1), f(2), f(3)])
    }
    #[inline(always)]
    fn hsum(self) -> f64 {
        let a = self.0;
        (a[0] + a[1]) + (a[2] + a[3])
    }
    #[inline(always)]
    fn hmin(self) -> f64 {
        self.0.iter().fold(f64::INFINITY, |m, &v| m.min(v))
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.zip(o, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.zip(o, |a, b| a / b)
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        self.mul(b).add(c)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.zip(o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.zip(o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        self.cmp(o, |a, b| a < b)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        self.cmp(o, |a, b| a > b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        self.cmp(o, |a, b| a == b)
    }
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        self.bits(o, |a, b| a & b)
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        self.bits(o, |a, b| a | b)
    }
    #[inline(always)]
    fn select(self, a: Self, b: Self) -> Self {
        Portable(std::array::from_fn(|l| {
            if self.0[l].to_bits() >> 63 != 0 {
                a.0[l]
            } else {
                b.0[l]
            }
        }))
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().any(|v| v.is_sign_negative())
    }
    #[inline(always)]
    fn shr52(self) -> Self {
        self.map(|a| f64::from_bits(a.to_bits() >> 52))
    }
    #[inline(always)]
    fn shr46(self) -> Self {
        self.map(|a| f64::from_bits(a.to_bits() >> 46))
    }
    #[inline(always)]
    fn shl52(self) -> Self {
        self.map(|a| f64::from_bits(a.to_bits() << 52))
    }
    #[inline(always)]
    fn rows4(table: &[[f64; 4]; 2048], idx: &[f64]) -> [Self; 4] {
        let r: [&[f64; 4]; 4] = std::array::from_fn(|l| &table[(idx[l].to_bits() & 2047) as usize]);
        std::array::from_fn(|k| Portable(std::array::from_fn(|l| r[l][k])))
    }
    #[inline(always)]
    fn add_bits(self, o: Self) -> Self {
        self.bits(o, u64::wrapping_add)
    }
}

/// U vectors side by side: `N = U·V::N` lanes, every operation applied to each part in
/// turn, so the parts form independent dependency chains in one instruction stream.
/// Loops rather than closures, so that everything inlines into the kernel.
#[derive(Clone, Copy)]
pub(crate) struct Wide<V, const U: usize>([V; U]);

macro_rules! wide_unary {
    ($($name:ident),*) => {$(
        #[inline(always)]
        fn $name(self) -> Self {
            let mut r = self;
            for u in 0..U {
                r.0[u] = self.0[u].$name();
            }
            r
        }
    )*};
}

macro_rules! wide_binary {
    ($($name:ident),*) => {$(
        #[inline(always)]
        fn $name(self, o: Self) -> Self {
            let mut r = self;
            for u in 0..U {
                r.0[u] = self.0[u].$name(o.0[u]);
            }
            r
        }
    )*};
}

impl<V: Simd, const U: usize> Simd for Wide<V, U> {
    const N: usize = V::N * U;
    const TRUE: Self = Wide([V::TRUE; U]);
    type Base = V::Base;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Wide([V::splat(x); U])
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        let s = &s[..Self::N];
        let mut r = Wide([V::splat(0.0); U]);
        for u in 0..U {
            r.0[u] = V::load(&s[u * V::N..]);
        }
        r
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        let s = &mut s[..Self::N];
        for u in 0..U {
            self.0[u].store(&mut s[u * V::N..]);
        }
    }
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> f64) -> Self {
        let mut r = Wide([V::splat(0.0); U]);
        for u in 0..U {
            r.0[u] = V::from_fn(|l| f(u * V::N + l));
        }
        r
    }
    #[inline(always)]
    fn hsum(self) -> f64 {
        let mut t = 0.0;
        for u in 0..U {
            t += self.0[u].hsum();
        }
        t
    }
    #[inline(always)]
    fn hmin(self) -> f64 {
        let mut m = f64::INFINITY;
        for u in 0..U {
            m = m.min(self.0[u].hmin());
        }
        m
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        let mut r = self;
        for u in 0..U {
            r.0[u] = self.0[u].mul_add(b.0[u], c.0[u]);
        }
        r
    }
    #[inline(always)]
    fn select(self, a: Self, b: Self) -> Self {
        let mut r = self;
        for u in 0..U {
            r.0[u] = self.0[u].select(a.0[u], b.0[u]);
        }
        r
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().any(|v| v.any())
    }
    #[inline(always)]
    fn rows4(table: &[[f64; 4]; 2048], idx: &[f64]) -> [Self; 4] {
        let mut r = [Wide([V::splat(0.0); U]); 4];
        for u in 0..U {
            let c = V::rows4(table, &idx[u * V::N..]);
            for k in 0..4 {
                r[k].0[u] = c[k];
            }
        }
        r
    }
    wide_unary!(sqrt, shr52, shr46, shl52);
    wide_binary!(add, sub, mul, div, min, max, lt, gt, eq, and, or, add_bits);
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    //! The AVX2 + FMA implementation of [`Simd`] and the entry points compiled with those
    //! features. Only reached after `use_avx2()` has checked the processor.

    use super::{GradTiles, Simd, SumTiles, Wide, WIDE};
    use std::arch::x86_64::*;

    #[derive(Clone, Copy)]
    pub(crate) struct Avx2(__m256d);

    // The intrinsics below are only executed inside `sum_tile` / `grad_tile`, which carry
    // the target features and are called after the run-time check; `#[inline(always)]`
    // puts every use inside them.
    impl Simd for Avx2 {
        const N: usize = 4;
        const TRUE: Self = Avx2(unsafe { std::mem::transmute::<[u64; 4], __m256d>([u64::MAX; 4]) });
        type Base = Self;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            unsafe { Avx2(_mm256_set1_pd(x)) }
        }
        #[inline(always)]
        fn load(s: &[f64]) -> Self {
            let s = &s[..4];
            unsafe { Avx2(_mm256_loadu_pd(s.as_ptr())) }
        }
        #[inline(always)]
        fn store(self, s: &mut [f64]) {
            let s = &mut s[..4];
            unsafe { _mm256_storeu_pd(s.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn from_fn(f: impl Fn(usize) -> f64) -> Self {
            Self::load(&[f(0), f(1), f(2), f(3)])
        }
        #[inline(always)]
        fn hsum(self) -> f64 {
            let mut a = [0.0; 4];
            self.store(&mut a);
            (a[0] + a[1]) + (a[2] + a[3])
        }
        #[inline(always)]
        fn hmin(self) -> f64 {
            let mut a = [0.0; 4];
            self.store(&mut a);
            a.iter().fold(f64::INFINITY, |m, &v| m.min(v))
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_add_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_sub_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_mul_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn div(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_div_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul_add(self, b: Self, c: Self) -> Self {
            unsafe { Avx2(_mm256_fmadd_pd(self.0, b.0, c.0)) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_min_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_max_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            unsafe { Avx2(_mm256_sqrt_pd(self.0)) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0)) }
        }
        #[inline(always)]
        fn gt(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0)) }
        }
        #[inline(always)]
        fn eq(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, o.0)) }
        }
        #[inline(always)]
        fn and(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_and_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn or(self, o: Self) -> Self {
            unsafe { Avx2(_mm256_or_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn select(self, a: Self, b: Self) -> Self {
            unsafe { Avx2(_mm256_blendv_pd(b.0, a.0, self.0)) }
        }
        #[inline(always)]
        fn any(self) -> bool {
            unsafe { _mm256_movemask_pd(self.0) != 0 }
        }
        #[inline(always)]
        fn shr52(self) -> Self {
            unsafe {
                Avx2(_mm256_castsi256_pd(_mm256_srli_epi64::<52>(
                    _mm256_castpd_si256(self.0),
                )))
            }
        }
        #[inline(always)]
        fn shr46(self) -> Self {
            unsafe {
                Avx2(_mm256_castsi256_pd(_mm256_srli_epi64::<46>(
                    _mm256_castpd_si256(self.0),
                )))
            }
        }
        #[inline(always)]
        fn shl52(self) -> Self {
            unsafe {
                Avx2(_mm256_castsi256_pd(_mm256_slli_epi64::<52>(
                    _mm256_castpd_si256(self.0),
                )))
            }
        }
        #[inline(always)]
        fn rows4(table: &[[f64; 4]; 2048], idx: &[f64]) -> [Self; 4] {
            let r: [&[f64; 4]; 4] =
                std::array::from_fn(|l| &table[(idx[l].to_bits() & 2047) as usize]);
            unsafe {
                let [r0, r1, r2, r3] = r.map(|row| _mm256_loadu_pd(row.as_ptr()));
                let t0 = _mm256_unpacklo_pd(r0, r1);
                let t1 = _mm256_unpackhi_pd(r0, r1);
                let t2 = _mm256_unpacklo_pd(r2, r3);
                let t3 = _mm256_unpackhi_pd(r2, r3);
                [
                    Avx2(_mm256_permute2f128_pd::<0x20>(t0, t2)),
                    Avx2(_mm256_permute2f128_pd::<0x20>(t1, t3)),
                    Avx2(_mm256_permute2f128_pd::<0x31>(t0, t2)),
                    Avx2(_mm256_permute2f128_pd::<0x31>(t1, t3)),
                ]
            }
        }
        #[inline(always)]
        fn add_bits(self, o: Self) -> Self {
            unsafe {
                Avx2(_mm256_castsi256_pd(_mm256_add_epi64(
                    _mm256_castpd_si256(self.0),
                    _mm256_castpd_si256(o.0),
                )))
            }
        }
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn sum_tile<K: SumTiles>(k: &K, a: usize, b: usize) -> K::Out {
        k.tile::<Wide<Avx2, WIDE>>(a, b)
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn grad_tile<K: GradTiles>(
        k: &K,
        a: usize,
        b: usize,
        ga: &mut [f64],
        gb: Option<&mut [f64]>,
    ) -> f64 {
        k.tile::<Wide<Avx2, WIDE>>(a, b, ga, gb)
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    //! The AVX-512 implementation of [`Simd`], eight lanes, and the entry point compiled
    //! with it. Every lane does the IEEE operation of the AVX2 build (`mul_add` fused as
    //! there), so a lane's value is the same in both; only the order of a horizontal sum
    //! is the build's own (see `hsum`). Only reached after `Build::available` has checked
    //! the processor.

    use super::{Simd, SumTiles, Wide};
    use std::arch::x86_64::*;

    #[derive(Clone, Copy)]
    pub(crate) struct Avx512(__m512d);

    /// The vector mask of a comparison's mask register: all bits set where it holds.
    #[inline(always)]
    fn mask(k: __mmask8) -> Avx512 {
        // SAFETY: as for the intrinsics of `impl Simd for Avx512`.
        unsafe { Avx512(_mm512_castsi512_pd(_mm512_movm_epi64(k))) }
    }

    /// Lane-wise u64 operation `f` on the bit patterns.
    #[inline(always)]
    fn bits(a: Avx512, b: Avx512, f: impl Fn(__m512i, __m512i) -> __m512i) -> Avx512 {
        // SAFETY: as for the intrinsics of `impl Simd for Avx512`.
        unsafe {
            Avx512(_mm512_castsi512_pd(f(
                _mm512_castpd_si512(a.0),
                _mm512_castpd_si512(b.0),
            )))
        }
    }

    // SAFETY (every `unsafe` block below): the intrinsics are only executed inside
    // `sum_tile`, which carries the target features and is called after the run-time
    // check; `#[inline(always)]` puts every use inside it. The loads and stores are of
    // slices cut to eight values first.
    impl Simd for Avx512 {
        const N: usize = 8;
        // SAFETY: `__m512d` is 64 bytes of which every pattern is valid, as `[u64; 8]`.
        const TRUE: Self =
            Avx512(unsafe { std::mem::transmute::<[u64; 8], __m512d>([u64::MAX; 8]) });
        type Base = Self;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            unsafe { Avx512(_mm512_set1_pd(x)) }
        }
        #[inline(always)]
        fn load(s: &[f64]) -> Self {
            let s = &s[..8];
            unsafe { Avx512(_mm512_loadu_pd(s.as_ptr())) }
        }
        #[inline(always)]
        fn store(self, s: &mut [f64]) {
            let s = &mut s[..8];
            unsafe { _mm512_storeu_pd(s.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn from_fn(f: impl Fn(usize) -> f64) -> Self {
            Self::load(&std::array::from_fn::<f64, 8, _>(f))
        }
        /// The four-lane halves each summed as the AVX2 build sums a vector, low half
        /// first, then added.
        #[inline(always)]
        fn hsum(self) -> f64 {
            let mut a = [0.0; 8];
            self.store(&mut a);
            let half = |h: &[f64]| (h[0] + h[1]) + (h[2] + h[3]);
            half(&a[..4]) + half(&a[4..])
        }
        #[inline(always)]
        fn hmin(self) -> f64 {
            let mut a = [0.0; 8];
            self.store(&mut a);
            a.iter().fold(f64::INFINITY, |m, &v| m.min(v))
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_add_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_sub_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_mul_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn div(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_div_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul_add(self, b: Self, c: Self) -> Self {
            unsafe { Avx512(_mm512_fmadd_pd(self.0, b.0, c.0)) }
        }
        // `vminpd`/`vmaxpd` as on AVX2: the second operand unless the first is strictly
        // smaller/larger.
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_min_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            unsafe { Avx512(_mm512_max_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            unsafe { Avx512(_mm512_sqrt_pd(self.0)) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> Self {
            mask(unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn gt(self, o: Self) -> Self {
            mask(unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn eq(self, o: Self) -> Self {
            mask(unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn and(self, o: Self) -> Self {
            bits(self, o, |a, b| unsafe { _mm512_and_si512(a, b) })
        }
        #[inline(always)]
        fn or(self, o: Self) -> Self {
            bits(self, o, |a, b| unsafe { _mm512_or_si512(a, b) })
        }
        /// By the sign bit of each lane, as `vblendvpd` reads a mask.
        #[inline(always)]
        fn select(self, a: Self, b: Self) -> Self {
            unsafe {
                let k = _mm512_movepi64_mask(_mm512_castpd_si512(self.0));
                Avx512(_mm512_mask_blend_pd(k, b.0, a.0))
            }
        }
        #[inline(always)]
        fn any(self) -> bool {
            unsafe { _mm512_movepi64_mask(_mm512_castpd_si512(self.0)) != 0 }
        }
        #[inline(always)]
        fn shr52(self) -> Self {
            bits(self, self, |a, _| unsafe { _mm512_srli_epi64::<52>(a) })
        }
        #[inline(always)]
        fn shr46(self) -> Self {
            bits(self, self, |a, _| unsafe { _mm512_srli_epi64::<46>(a) })
        }
        #[inline(always)]
        fn shl52(self) -> Self {
            bits(self, self, |a, _| unsafe { _mm512_slli_epi64::<52>(a) })
        }
        #[inline(always)]
        fn add_bits(self, o: Self) -> Self {
            bits(self, o, |a, b| unsafe { _mm512_add_epi64(a, b) })
        }
        #[inline(always)]
        fn rows4(table: &[[f64; 4]; 2048], idx: &[f64]) -> [Self; 4] {
            let rows: [&[f64; 4]; 8] =
                std::array::from_fn(|l| &table[(idx[l].to_bits() & 2047) as usize]);
            std::array::from_fn(|k| Self::from_fn(|l| rows[l][k]))
        }
    }

    #[target_feature(enable = "avx2,fma,avx512f,avx512dq")]
    pub(super) unsafe fn sum_tile<K: SumTiles>(k: &K, a: usize, b: usize) -> K::Out {
        k.tile::<Wide<Avx512, 2>>(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pair_is_visited_once() {
        for n in [1usize, 2, 3, 7, 64, 65, 130, 1000] {
            let s = 1;
            let mut grad = vec![0.0; n * s];
            // Each pair adds 1 to both rows and 1 to the total: row i must end at n − 1.
            let total = for_each_pair_tile(n, s, &mut grad, |ri, rj, gi, gj| {
                let mut c = 0.0;
                if gj.is_empty() {
                    for i in ri.clone() {
                        for j in i + 1..ri.end {
                            gi[i - ri.start] += 1.0;
                            gi[j - ri.start] += 1.0;
                            c += 1.0;
                        }
                    }
                } else {
                    for i in ri.clone() {
                        for j in rj.clone() {
                            gi[i - ri.start] += 1.0;
                            gj[j - rj.start] += 1.0;
                            c += 1.0;
                        }
                    }
                }
                c
            });
            assert_eq!(total as usize, n * (n - 1) / 2, "n={n}");
            if n > 1 {
                assert!(grad.iter().all(|&g| g as usize == n - 1), "n={n}");
            }
        }
    }
}
