//! The L2 discrepancies as energies: squared star, modified, centred and wrap-around L2,
//! with analytic (sub)gradients, so a solver can minimise the figure of merit itself.
//!
//! Each is the closed form (Warnock's eq. 46 for the star L2, eq. 47 for the modified L2,
//! Hickernell's for the centred and wrap-around L2)
//!
//! D²(X) = C_s − (2/n) Σ_i Π_k g(x_ik) + (1/n²) Σ_{i,l} Π_k K(x_ik, x_lk),
//!
//! with one-dimensional factors
//!
//! | kind        | C_s       | g(x)                   | K(x, y)                                  |
//! |-------------|-----------|------------------------|------------------------------------------|
//! | star L2     | (1/3)^s   | (1 − x²)/2             | 1 − max(x, y)                            |
//! | modified L2 | (4/3)^s   | (3 − x²)/2             | 2 − max(x, y)                            |
//! | centred L2  | (13/12)^s | 1 + a/2 − a²/2         | 1 + ½\|x − ½\| + ½\|y − ½\| − ½\|x − y\| |
//! | wrap-around | −(4/3)^s  | none (merged into C_s) | 3/2 − d(1 − d)                           |
//! | mixture     | (19/12)^s | 5/3 − a/4 − a²/4       | 15/8 − a/4 − b/4 − 3d/4 + d²/2           |
//! | smooth      | −1        | none (merged into C_s) | 1 + γ(B₁(x)B₁(y) + B₂(x)B₂(y)/4 − B₄(d)/24) |
//!
//! where a = |x − ½|, b = |y − ½| and d = |x − y|.
//!
//! The smooth row is the squared worst-case error of the equal-weight rule in the
//! unanchored Sobolev space of smoothness 2 with product weight γ = [`SMOOTH_WEIGHT`]
//! (Dick, Kuo and Sloan, *High-dimensional integration: the quasi-Monte Carlo way*,
//! Acta Numerica 2013, §5), with the Bernoulli polynomials B₁(t) = t − ½,
//! B₂(t) = t² − t + 1/6 and B₄(t) = t²(1 − t)² − 1/30. Every factor integrates to 1 in
//! either argument, so the middle term is −2 and merges with the constant 1. The L2
//! discrepancies above bound the error of integrands with one mixed derivative in each
//! coordinate, with equal weight on interactions of every order; this one bounds the
//! error of integrands with two, and its small weight makes interactions of order k count
//! γ^k: what smooth integrands in many dimensions look like. Its kernel is C¹ (B₄ has a
//! zero slope at 0), so it has no kinks of its own.
//!
//! The last row is the mixture discrepancy of Y.-D. Zhou, K.-T. Fang and J.-H. Ning
//! (*Mixture discrepancy for quasi-random point sets*, J. Complexity 29, 2013), whose
//! square is SciPy's `qmc.discrepancy(method='MD')`. It is a figure of merit here, not a
//! [`DiscrepancyKind`]: no energy, polish or target takes it. It shares the pair loops
//! ([`squared_discrepancies_with_mixture`] computes it with the other four in one pass)
//! and the logarithmic form of very high dimension ([`mixture_root`]).
//!
//! **One table.** Each row is one [`DiscrepancyKernel`] (its constant, g, K, their
//! derivatives, names and the flags the rest of the workspace asks about), and
//! [`DiscrepancyKind`] lists the rows that are energies, each with its kernel, in one
//! list (`discrepancy_kinds!` below), from which [`DiscrepancyKind::ALL`], the names
//! [`DiscrepancyKind::parse`] accepts and [`with_kernel!`](crate::with_kernel) (kind →
//! kernel type, for monomorphised loops here and in the root crate's exchanges) all
//! follow. A new kind is its kernel's impls and one line of that list, in this file; a
//! target that blends it names it there.
//!
//! The value is the *square* of the discrepancy: the closed forms give the square, and
//! its gradient needs no division by the root, which vanishes for a perfect set. The
//! metrics of the root crate take the same value ([`squared_discrepancies`]), clamp it at
//! 0 and take the root. The energy is not clamped: a clamp would make the value disagree
//! with the gradient for nearly perfect sets.
//!
//! **Gradient.**
//!
//! ∂D²/∂x_ik = −(2/n) g'(x_ik) Π_{m≠k} g(x_im)
//!             + (2/n²) Σ_{l≠i} ∂₁K(x_ik, x_lk) Π_{m≠k} K(x_im, x_lm)
//!             + (1/n²) d/dx_ik Π_m K(x_im, x_im):
//!
//! each unordered pair appears twice in Σ_{i,l}, and the diagonal terms i = l are not
//! constant (K(x, x) = 1 − x for the star L2). Π_{m≠k} K_m comes from prefix and suffix
//! products, with no division, so a zero factor (the star L2's 1 − max is 0 when a
//! coordinate is 1, where a bounded solver likes to park points) needs no special case.
//!
//! **Kinks.** The energy is continuous but only piecewise smooth. Where x_ik = x_lk for
//! some pair, max(x, y) and |x − y| have a kink, and the centred L2 has another wherever
//! x_ik = ½. At a kink this module returns the average of the two one-sided partial
//! derivatives along each coordinate: for max(x, y) at x = y each argument gets half of
//! the derivative (−½ to each point for 1 − max), |x − y| and |x − ½| get 0 (the middle of
//! [−1, 1]), and so does |x − y|(1 − |x − y|) at x = y. Because the energy is a sum of
//! products in which each kink enters linearly, this is exactly the average of the forward
//! and backward partial derivatives of D², i.e. the central difference in the limit. On the
//! diagonal it is the true derivative: d/dx (1 − max(x, x)) = −½ − ½ = −1. The choice
//! treats the points of a tie alike, so relabelling the points does not change it. Across
//! a kink the gradient jumps, so [`Energy::is_smooth`] is `false`: line searches and the
//! DEM's κ trial must not demand strict decrease there.
//!
//! **Domain.** The points are assumed to lie in [0, 1]^s and are not checked. Star,
//! modified and centred L2 are defined on the closed cube and are not periodic; the
//! wrap-around L2 is invariant under x → (x + c) mod 1 of the whole set
//! ([`DiscrepancyKind::is_periodic`]).
//!
//! **Determinism and cost.** The pair sums run through the tiled half loop of
//! [`crate::pairs`] in vectors of 16 lanes (consecutive points j), the per-point terms in
//! index order, so value and gradient have the same bits for any number of rayon threads,
//! and [`Energy::value`] sums in the same order as [`Energy::value_and_gradient`] (same
//! bits). No fused multiply-add is used, so the results are also the same bits with and
//! without AVX2. O(n² s) time, O(n s) memory (block-transposed copies of the points and
//! the gradient); the pair loop does not allocate (one reused scratch buffer per worker
//! thread). The value-only path skips the derivatives. [`squared_discrepancies`] gives
//! the values of several kinds from one pass over the pairs ([`pair_product_sums`]), and
//! [`squared_discrepancies_with_mixture`] those of all five, for the metrics of the root
//! crate.

use crate::pairs::{
    give_scratch, grad_tiles, sum_tiles, take_scratch, AlignedBuf, Blocks, GradTiles, Simd,
    SumTiles,
};
use crate::{Energy, Error, PointSet, Result};
use std::marker::PhantomData;

/// The one-dimensional factors of a discrepancy's closed form
/// D² = C_s − (2/n) Σ_i Π_k g(x_ik) + (1/n²) Σ_{i,l} Π_k K(x_ik, x_lk), with what the
/// energies, the exchanges, the reports and the targets need to know of it: one
/// implementation per discrepancy (the rows of the module documentation's table), and
/// [`DiscrepancyKind`] lists those that are energies.
///
/// The factors are written once, here; every loop that forms D² (the vectorised pair
/// loops of this module, the O(n) swap updates of the root crate's exchanges, the plain
/// double sums of the benchmarks) is generic over the kernel and monomorphised, so the
/// factors inline into it.
pub trait DiscrepancyKernel: Sync + Send + 'static {
    /// The names [`DiscrepancyKind::parse`] accepts (lower case); the first is the one
    /// [`DiscrepancyKind::label`] gives.
    const NAMES: &'static [&'static str];
    /// What the kernel measures, as a list of accepted names explains it (`star L2`).
    const DESCRIPTION: &'static str;
    /// The energy's name, [`Energy::name`] of [`DiscrepancyEnergy`].
    const ENERGY_NAME: &'static str;
    /// Per-coordinate factor of |C_s| = CONSTANT_BASE^s.
    const CONSTANT_BASE: f64;
    /// Sign of C_s (negative where the middle term has merged into it).
    const CONSTANT_SIGN: f64;
    /// Whether the closed form has the middle term −(2/n) Σ_i Π_k g(x_ik).
    const HAS_SINGLE: bool;
    /// The largest factor of the kernel's products (the pair factors and g): with
    /// [`DiscrepancyKernel::CONSTANT_BASE`] it bounds how large the terms of the closed
    /// form grow with s ([`closed_form_fits`]).
    const LARGEST_FACTOR: f64;
    /// Whether D² is unchanged by a periodic shift x → (x + c) mod 1 of the whole set.
    const PERIODIC: bool = false;
    /// The order of the derivatives of the integrands whose worst-case error D² is: 1
    /// for the L2 discrepancies, 2 for the smoothness-2 errors (whose sets start from the
    /// lattice of the tent randomisation).
    const SMOOTHNESS: u32 = 1;
    /// The kernel's place among the five squares a report forms in one pass over the
    /// pairs ([`squared_discrepancies_with_mixture`], [`sampled_squared_discrepancies`]),
    /// if it is one of them.
    const REPORTED: Option<usize> = None;

    /// g(x) and g'(x) (with the averaged one-sided derivative at a kink).
    fn single(x: f64) -> (f64, f64);

    /// K(x, y), ∂K/∂x and ∂K/∂y (averaged one-sided derivatives at a kink).
    fn pair(x: f64, y: f64) -> (f64, f64, f64);

    /// g(x) alone.
    #[inline(always)]
    fn single_factor(x: f64) -> f64 {
        Self::single(x).0
    }

    /// K(x, y) alone.
    #[inline(always)]
    fn pair_factor(x: f64, y: f64) -> f64 {
        Self::pair(x, y).0
    }

    /// C_s = ±CONSTANT_BASE^s, by repeated multiplication so that it is the same bits on
    /// every platform (`powi` is left to the backend).
    fn constant(s: usize) -> f64 {
        Self::CONSTANT_SIGN * (0..s).fold(1.0, |p, _| p * Self::CONSTANT_BASE)
    }
}

/// The lane-by-lane forms of a kernel's pair factor, for the vectorised pair loops: the
/// same operations, in the same order, as [`DiscrepancyKernel::pair`].
trait Lanes: DiscrepancyKernel {
    /// Whether the pair factor uses ½|x − ½| (the centred L2; see [`Kinds::HALF_GAP`]).
    const HALF_GAP: bool = false;

    /// K(x, y) lane by lane: the same operations as `pair`'s value.
    fn vpair<V: Simd>(x: V, y: V) -> V;

    /// ∂K/∂x and ∂K/∂y lane by lane, as `pair` gives them.
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V);

    /// K(x, y) lane by lane given `gx` = ½|x − ½| and `gy` = ½|y − ½|, which the value
    /// loops precompute once per coordinate for the kernels with [`Lanes::HALF_GAP`]:
    /// the same bits as `vpair`.
    #[inline(always)]
    fn vpair_gap<V: Simd>(x: V, y: V, _gx: V, _gy: V) -> V {
        Self::vpair(x, y)
    }
}

/// Declares [`DiscrepancyKind`], [`DiscrepancyKind::ALL`] and
/// [`with_kernel!`](crate::with_kernel) from one list of kinds and their kernels.
macro_rules! discrepancy_kinds {
    ($d:tt $($(#[$doc:meta])* $variant:ident => $kernel:ident,)*) => {
        /// Which discrepancy an energy squares (and an exchange, a polish or a target
        /// lowers): one [`DiscrepancyKernel`] each, which
        /// [`with_kernel!`](crate::with_kernel) finds.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum DiscrepancyKind {
            $($(#[$doc])* $variant,)*
        }

        impl DiscrepancyKind {
            /// Every kind, in declaration order.
            pub const ALL: &'static [DiscrepancyKind] = &[$(DiscrepancyKind::$variant),*];
        }

        /// `with_kernel!(kind, K => expr)`: `expr` with `K` the
        /// [`DiscrepancyKernel`](crate::discrepancy::DiscrepancyKernel) of the
        /// [`DiscrepancyKind`](crate::discrepancy::DiscrepancyKind) `kind`, one
        /// monomorphised copy per kind, so the factors inline into `expr`'s loops.
        #[macro_export]
        macro_rules! with_kernel {
            ($d kind:expr, $d k:ident => $d body:expr) => {
                match $d kind {
                    $($d crate::discrepancy::DiscrepancyKind::$variant => {
                        type $d k = $d crate::discrepancy::$kernel;
                        $d body
                    })*
                }
            };
        }
    };
}

discrepancy_kinds! {$
    /// Star L2 (Warnock, the paper's eq. 46): boxes anchored at the origin.
    StarL2 => Star,
    /// Modified L2 (Hickernell, the paper's eq. 47): the star L2 of every projection.
    ModifiedL2 => Modified,
    /// Centred L2 (Hickernell): boxes anchored at the nearest corner.
    CenteredL2 => Centered,
    /// Wrap-around L2 (Hickernell): boxes wrap around the faces; periodic.
    WrapAroundL2 => Wrap,
    /// The worst-case error for integrands of smoothness 2 with product weight
    /// [`SMOOTH_WEIGHT`] (the table's last row).
    Smooth => Smooth,
    /// [`DiscrepancyKind::Smooth`] with the mean of the second derivative weighing
    /// [`CURVATURE_WEIGHT`] times more: B₂(x)B₂(y)/4 becomes
    /// [`CURVATURE_WEIGHT`]·B₂(x)B₂(y)/4.
    Curved => Curved,
}

/// γ, the product weight of [`DiscrepancyKind::Smooth`]: an interaction of order k counts
/// γ^k. 1/10 matches the share of variance a coordinate adds to the smooth test
/// integrands of Genz at s ≥ 8 (a factor e^{i a x} with a ≈ 1 varies by about a tenth of
/// its mean square), and the sets it made integrated them best among 1, 0.3, 0.1 and
/// 0.05 in the integration benchmark's cells.
pub const SMOOTH_WEIGHT: f64 = 0.1;

/// How many times more [`DiscrepancyKind::Curved`] weighs the mean of each coordinate's
/// second derivative than [`DiscrepancyKind::Smooth`]. In the space's norm
/// (∫f)² + (∫f')²/γ + (∫f'')²/(γβ) + ‖f'' − ∫f''‖²/γ (one coordinate, β this weight) a
/// large β makes integrands whose coordinates are curved on average (peaks, Gaussians:
/// locally quadratic) cheap, so the rule must integrate them well: their error is the
/// degree-2 moments Σ_k B₂(x_kj)B₂(x_kl)… of the set, which the L2 discrepancies and the
/// standard weight (β = 1, where B₂B₂ counts 1/25 of B₁B₁ in a pair) barely see. 24
/// (a coefficient 6 on B₂B₂) was chosen among 1, 4, 12 and 24 on 12 cells of the
/// integration benchmark at s = 15 and 20: product peak and Gaussian fell from 1.6 and
/// 1.2 times scrambled Sobol's error to 0.6 and 0.4 (geometric means; 0.85 and 0.6 with
/// 12).
pub const CURVATURE_WEIGHT: u32 = 24;

impl DiscrepancyKind {
    /// Parses a name of a kind's [`DiscrepancyKernel::NAMES`], the names the CLI's
    /// `--energy` takes: `l2star`, `md`, `cd`, `periodic` or its alias `wd`, `smooth`,
    /// `curved` (ASCII case and surrounding spaces ignored).
    pub fn parse(name: &str) -> Result<Self> {
        let key = name.trim().to_ascii_lowercase();
        DiscrepancyKind::ALL
            .iter()
            .copied()
            .find(|k| k.names().contains(&key.as_str()))
            .ok_or_else(|| Error::invalid("discrepancy", format!("`{name}`"), Self::accepted()))
    }

    /// The names [`DiscrepancyKind::parse`] accepts, as an error message lists them:
    /// "one of `l2star` (star L2), `md` (modified L2), …".
    pub fn accepted() -> String {
        let each: Vec<String> = DiscrepancyKind::ALL
            .iter()
            .map(|k| {
                let names: Vec<String> = k.names().iter().map(|n| format!("`{n}`")).collect();
                format!("{} ({})", names.join(" or "), k.description())
            })
            .collect();
        format!("one of {}", each.join(", "))
    }

    /// The CLI name, the one [`DiscrepancyKind::parse`] maps back to this kind.
    pub fn label(&self) -> &'static str {
        self.names()[0]
    }

    /// Every name [`DiscrepancyKind::parse`] maps to this kind, the label first.
    pub fn names(&self) -> &'static [&'static str] {
        with_kernel!(*self, K => K::NAMES)
    }

    /// What the kind measures, as [`DiscrepancyKind::accepted`] explains it.
    pub fn description(&self) -> &'static str {
        with_kernel!(*self, K => K::DESCRIPTION)
    }

    /// Whether the discrepancy is unchanged by a periodic shift x → (x + c) mod 1 of the
    /// whole set: only the wrap-around L2. The others must be minimised in the closed
    /// cube, not on the torus.
    pub fn is_periodic(&self) -> bool {
        with_kernel!(*self, K => K::PERIODIC)
    }

    /// [`DiscrepancyKernel::SMOOTHNESS`] of the kind's kernel.
    pub fn smoothness(&self) -> u32 {
        with_kernel!(*self, K => K::SMOOTHNESS)
    }

    /// [`DiscrepancyKernel::REPORTED`] of the kind's kernel.
    pub fn reported(&self) -> Option<usize> {
        with_kernel!(*self, K => K::REPORTED)
    }
}

/// The squared L2 discrepancy of a point set in [0, 1]^s as an [`Energy`]; see the module
/// documentation for the formulas and the treatment of kinks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DiscrepancyEnergy {
    kind: DiscrepancyKind,
}

impl DiscrepancyEnergy {
    /// The squared discrepancy of the given kind.
    pub fn new(kind: DiscrepancyKind) -> Self {
        DiscrepancyEnergy { kind }
    }

    /// The discrepancy being squared.
    pub fn kind(&self) -> DiscrepancyKind {
        self.kind
    }
}

impl Energy for DiscrepancyEnergy {
    fn name(&self) -> String {
        with_kernel!(self.kind, K => K::ENERGY_NAME).to_string()
    }

    fn value(&self, points: &PointSet) -> f64 {
        dispatch(self.kind, points, None)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(
            grad.len(),
            points.coordinate_count(),
            "gradient buffer length"
        );
        dispatch(self.kind, points, Some(grad))
    }

    fn is_smooth(&self) -> bool {
        false
    }
}

fn dispatch(kind: DiscrepancyKind, points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
    // One monomorphised copy per kind, so the 1-D factors inline into the pair loop.
    with_kernel!(kind, K => evaluate::<K>(points, grad))
}

/// sgn(v)/2 with sgn(0) = 0, lane by lane.
#[inline(always)]
fn vhalf_sgn<V: Simd>(v: V) -> V {
    let zero = V::splat(0.0);
    let s = v.lt(zero).select(V::splat(-0.5), zero);
    v.gt(zero).select(V::splat(0.5), s)
}

/// ∂ max(x, y)/∂x lane by lane: 1, 0, or ½ on the tie.
#[inline(always)]
fn vdmax_dx<V: Simd>(x: V, y: V) -> V {
    let t = x.lt(y).select(V::splat(0.0), V::splat(0.5));
    x.gt(y).select(V::splat(1.0), t)
}

/// Sign with sgn(0) = 0, the middle of |·|'s subdifferential at 0 (`f64::signum` gives ±1).
#[inline(always)]
fn sgn(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// ∂ max(x, y)/∂x: 1, 0, or ½ on the tie (each argument takes half).
#[inline(always)]
fn dmax_dx(x: f64, y: f64) -> f64 {
    if x > y {
        1.0
    } else if x < y {
        0.0
    } else {
        0.5
    }
}

/// The star L2 discrepancy's kernel.
pub struct Star;
/// The modified L2 discrepancy's kernel.
pub struct Modified;
/// The centred L2 discrepancy's kernel.
pub struct Centered;
/// The wrap-around L2 discrepancy's kernel.
pub struct Wrap;
/// The mixture discrepancy's kernel: a figure of merit, not a [`DiscrepancyKind`].
pub struct Mixture;
/// The smoothness-2 kernel whose B₂(x)B₂(y) carries C/4: C = 1 is the standard space.
pub struct SmoothOf<const C: u32>;
/// The kernel of [`DiscrepancyKind::Smooth`].
pub type Smooth = SmoothOf<1>;
/// The kernel of [`DiscrepancyKind::Curved`].
pub type Curved = SmoothOf<CURVATURE_WEIGHT>;

impl DiscrepancyKernel for Star {
    const NAMES: &'static [&'static str] = &["l2star"];
    const DESCRIPTION: &'static str = "star L2";
    const ENERGY_NAME: &'static str = "D²_L2 (squared star L2)";
    const LARGEST_FACTOR: f64 = 1.0;
    const REPORTED: Option<usize> = Some(0);
    const CONSTANT_BASE: f64 = 1.0 / 3.0;
    const CONSTANT_SIGN: f64 = 1.0;
    const HAS_SINGLE: bool = true;

    #[inline(always)]
    fn single(x: f64) -> (f64, f64) {
        (0.5 * (1.0 - x * x), -x)
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let dx = dmax_dx(x, y);
        // ∂max/∂x + ∂max/∂y = 1 in every case, including the tie.
        (1.0 - x.max(y), -dx, dx - 1.0)
    }
}

impl Lanes for Star {
    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        V::splat(1.0).sub(x.max(y))
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let dx = vdmax_dx(x, y);
        (V::splat(0.0).sub(dx), dx.sub(V::splat(1.0)))
    }
}

impl DiscrepancyKernel for Modified {
    const NAMES: &'static [&'static str] = &["md"];
    const DESCRIPTION: &'static str = "modified L2";
    const ENERGY_NAME: &'static str = "D²_MD (squared modified L2)";
    const LARGEST_FACTOR: f64 = 2.0;
    const REPORTED: Option<usize> = Some(1);
    const CONSTANT_BASE: f64 = 4.0 / 3.0;
    const CONSTANT_SIGN: f64 = 1.0;
    const HAS_SINGLE: bool = true;

    // Eq. 47's 2^(1−s) Π (3 − x²) with the 2^(−s) spread over the factors, as in the
    // metric.
    #[inline(always)]
    fn single(x: f64) -> (f64, f64) {
        (0.5 * (3.0 - x * x), -x)
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let dx = dmax_dx(x, y);
        (2.0 - x.max(y), -dx, dx - 1.0)
    }
}

impl Lanes for Modified {
    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        V::splat(2.0).sub(x.max(y))
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let dx = vdmax_dx(x, y);
        (V::splat(0.0).sub(dx), dx.sub(V::splat(1.0)))
    }
}

impl DiscrepancyKernel for Centered {
    const NAMES: &'static [&'static str] = &["cd"];
    const DESCRIPTION: &'static str = "centred L2";
    const ENERGY_NAME: &'static str = "D²_CD (squared centred L2)";
    const LARGEST_FACTOR: f64 = 1.5;
    const REPORTED: Option<usize> = Some(2);
    const CONSTANT_BASE: f64 = 13.0 / 12.0;
    const CONSTANT_SIGN: f64 = 1.0;
    const HAS_SINGLE: bool = true;

    #[inline(always)]
    fn single(x: f64) -> (f64, f64) {
        let a = (x - 0.5).abs();
        (1.0 + 0.5 * a - 0.5 * a * a, sgn(x - 0.5) * (0.5 - a))
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let v = 1.0 + 0.5 * (x - 0.5).abs() + 0.5 * (y - 0.5).abs() - 0.5 * (x - y).abs();
        let sd = 0.5 * sgn(x - y);
        (v, 0.5 * sgn(x - 0.5) - sd, 0.5 * sgn(y - 0.5) + sd)
    }
}

impl Lanes for Centered {
    const HALF_GAP: bool = true;

    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        let (one, half) = (V::splat(1.0), V::splat(0.5));
        let ax = half.mul(x.sub(half).abs());
        let ay = half.mul(y.sub(half).abs());
        one.add(ax).add(ay).sub(half.mul(x.sub(y).abs()))
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let half = V::splat(0.5);
        let sd = vhalf_sgn(x.sub(y));
        (
            vhalf_sgn(x.sub(half)).sub(sd),
            vhalf_sgn(y.sub(half)).add(sd),
        )
    }

    #[inline(always)]
    fn vpair_gap<V: Simd>(x: V, y: V, gx: V, gy: V) -> V {
        centered_factor(x, y, gx, gy)
    }
}

impl DiscrepancyKernel for Wrap {
    const NAMES: &'static [&'static str] = &["periodic", "wd"];
    const DESCRIPTION: &'static str = "wrap-around L2";
    const ENERGY_NAME: &'static str = "D²_WD (squared wrap-around L2)";
    const LARGEST_FACTOR: f64 = 1.5;
    const PERIODIC: bool = true;
    const REPORTED: Option<usize> = Some(3);
    const CONSTANT_BASE: f64 = 4.0 / 3.0;
    const CONSTANT_SIGN: f64 = -1.0;
    // ∫ K(x, y) dy = (4/3)^s for every x: the middle term merges into the constant.
    const HAS_SINGLE: bool = false;

    #[inline(always)]
    fn single(_x: f64) -> (f64, f64) {
        (1.0, 0.0)
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let d = (x - y).abs();
        let dx = -sgn(x - y) * (1.0 - 2.0 * d);
        (1.5 - d * (1.0 - d), dx, -dx)
    }
}

impl Lanes for Wrap {
    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        let d = x.sub(y).abs();
        V::splat(1.5).sub(d.mul(V::splat(1.0).sub(d)))
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let d = x.sub(y).abs();
        let two = V::splat(2.0);
        // −sgn(x − y)(1 − 2d) = −2·(sgn/2)·(1 − 2d).
        let dx = V::splat(0.0).sub(
            two.mul(vhalf_sgn(x.sub(y)))
                .mul(V::splat(1.0).sub(two.mul(d))),
        );
        (dx, V::splat(0.0).sub(dx))
    }
}

impl DiscrepancyKernel for Mixture {
    const NAMES: &'static [&'static str] = &["mixture"];
    const DESCRIPTION: &'static str = "mixture";
    const ENERGY_NAME: &'static str = "D²_MIX (squared mixture discrepancy)";
    /// h(½, ½) = 15/8. Its smallest, h(0, 1) = 11/8 (g is at least 71/48), is above 1,
    /// so its products only grow with s.
    const LARGEST_FACTOR: f64 = 1.875;
    const REPORTED: Option<usize> = Some(4);
    const CONSTANT_BASE: f64 = 19.0 / 12.0;
    const CONSTANT_SIGN: f64 = 1.0;
    const HAS_SINGLE: bool = true;

    #[inline(always)]
    fn single(x: f64) -> (f64, f64) {
        let a = (x - 0.5).abs();
        (
            5.0 / 3.0 - 0.25 * a - 0.25 * a * a,
            -sgn(x - 0.5) * (0.25 + 0.5 * a),
        )
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let (gx, gy) = (0.5 * (x - 0.5).abs(), 0.5 * (y - 0.5).abs());
        let d = (x - y).abs();
        // The same operations, in the same order, as `mixture_factor`.
        let v = 1.875 - 0.5 * gx - 0.5 * gy + d * (0.5 * d - 0.75);
        // d/dd (d²/2 − 3d/4) = d − 3/4, times ∂d/∂x = sgn(x − y).
        let sd = sgn(x - y) * (d - 0.75);
        (v, -0.25 * sgn(x - 0.5) + sd, -0.25 * sgn(y - 0.5) - sd)
    }
}

impl Lanes for Mixture {
    const HALF_GAP: bool = true;

    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        let half = V::splat(0.5);
        let gx = half.mul(x.sub(half).abs());
        let gy = half.mul(y.sub(half).abs());
        mixture_factor(x, y, gx, gy)
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let half = V::splat(0.5);
        let d = x.sub(y).abs();
        // sgn(x − y)(d − ¾) = 2·(sgn/2)·(d − ¾); ¼ sgn(x − ½) = ½·(sgn/2).
        let sd = V::splat(2.0)
            .mul(vhalf_sgn(x.sub(y)))
            .mul(d.sub(V::splat(0.75)));
        (
            sd.sub(half.mul(vhalf_sgn(x.sub(half)))),
            V::splat(0.0).sub(sd).sub(half.mul(vhalf_sgn(y.sub(half)))),
        )
    }

    #[inline(always)]
    fn vpair_gap<V: Simd>(x: V, y: V, gx: V, gy: V) -> V {
        mixture_factor(x, y, gx, gy)
    }
}

impl<const C: u32> SmoothOf<C> {
    /// The coefficient of B₂(x)B₂(y), and twice it for the derivatives (exact in binary
    /// for every C, so C = 1 keeps the standard kernel's bits).
    const B2B2: f64 = C as f64 * 0.25;
    const B2B2_TWICE: f64 = C as f64 * 0.5;
}

/// The names, description and energy name of the smoothness-2 kernel whose B₂(x)B₂(y)
/// carries C/4 (a weight without a name is refused at compile time).
const fn smooth_text(c: u32) -> (&'static [&'static str], &'static str, &'static str) {
    match c {
        1 => (
            &["smooth"],
            "smoothness 2",
            "D²_S2 (squared worst-case error, smoothness 2)",
        ),
        CURVATURE_WEIGHT => (
            &["curved"],
            "smoothness 2, curvature weighed more",
            "D²_S2c (squared worst-case error, smoothness 2, curvature weighed more)",
        ),
        _ => panic!("a smoothness-2 weight without a name"),
    }
}

impl<const C: u32> DiscrepancyKernel for SmoothOf<C> {
    const NAMES: &'static [&'static str] = smooth_text(C).0;
    const DESCRIPTION: &'static str = smooth_text(C).1;
    const ENERGY_NAME: &'static str = smooth_text(C).2;
    /// The bracket is at most ¼ + C/144 + 1/720 (|B₁| ≤ ½, |B₂| ≤ 1/6,
    /// −B₄(d)/24 ≤ 1/720).
    const LARGEST_FACTOR: f64 = 1.0 + SMOOTH_WEIGHT * (0.25 + C as f64 / 144.0 + 1.0 / 720.0);
    const SMOOTHNESS: u32 = 2;
    const CONSTANT_BASE: f64 = 1.0;
    // 1 − 2 (each factor integrates to 1): the middle term merges into the constant.
    const CONSTANT_SIGN: f64 = -1.0;
    const HAS_SINGLE: bool = false;

    #[inline(always)]
    fn single(_x: f64) -> (f64, f64) {
        (1.0, 0.0)
    }

    #[inline(always)]
    fn pair(x: f64, y: f64) -> (f64, f64, f64) {
        let (bx, by) = (x - 0.5, y - 0.5);
        let (cx, cy) = (x * x - x + 1.0 / 6.0, y * y - y + 1.0 / 6.0);
        let d = (x - y).abs();
        let e = d * (1.0 - d);
        let v = 1.0 + SMOOTH_WEIGHT * (bx * by + Self::B2B2 * cx * cy + 1.0 / 720.0 - e * e / 24.0);
        // d/dd of d²(1 − d)²/24 is d(1 − d)(1 − 2d)/12, times ∂d/∂x = sgn(x − y).
        let t = sgn(x - y) * e * (1.0 - 2.0 * d) / 12.0;
        (
            v,
            SMOOTH_WEIGHT * (by + Self::B2B2_TWICE * bx * cy - t),
            SMOOTH_WEIGHT * (bx + Self::B2B2_TWICE * by * cx + t),
        )
    }
}

impl<const C: u32> Lanes for SmoothOf<C> {
    #[inline(always)]
    fn vpair<V: Simd>(x: V, y: V) -> V {
        let one = V::splat(1.0);
        let [bx, by, cx, cy, _, e] = smooth_parts(x, y);
        let bracket = bx
            .mul(by)
            .add(V::splat(Self::B2B2).mul(cx).mul(cy))
            .add(V::splat(1.0 / 720.0))
            .sub(e.mul(e).mul(V::splat(1.0 / 24.0)));
        one.add(V::splat(SMOOTH_WEIGHT).mul(bracket))
    }

    #[inline(always)]
    fn vderiv<V: Simd>(x: V, y: V) -> (V, V) {
        let (twice, one) = (V::splat(Self::B2B2_TWICE), V::splat(1.0));
        let [bx, by, cx, cy, d, e] = smooth_parts(x, y);
        // sgn(x − y)·e(1 − 2d)/12 = (sgn/2)·e(1 − 2d)/6.
        let t = vhalf_sgn(x.sub(y))
            .mul(e)
            .mul(one.sub(V::splat(2.0).mul(d)))
            .mul(V::splat(1.0 / 6.0));
        let w = V::splat(SMOOTH_WEIGHT);
        (
            w.mul(by.add(twice.mul(bx).mul(cy)).sub(t)),
            w.mul(bx.add(twice.mul(by).mul(cx)).add(t)),
        )
    }
}

/// B₁(x), B₁(y), B₂(x), B₂(y), d = |x − y| and d(1 − d), lane by lane: what the smooth
/// kernel's value and derivatives share.
#[inline(always)]
fn smooth_parts<V: Simd>(x: V, y: V) -> [V; 6] {
    let (half, sixth) = (V::splat(0.5), V::splat(1.0 / 6.0));
    let d = x.sub(y).abs();
    [
        x.sub(half),
        y.sub(half),
        x.mul(x).sub(x).add(sixth),
        y.mul(y).sub(y).add(sixth),
        d,
        d.mul(V::splat(1.0).sub(d)),
    ]
}

/// The mixture's pair factor 15/8 − ¼|x − ½| − ¼|y − ½| − ¾d + ½d² from `gx` = ½|x − ½|
/// and `gy` = ½|y − ½| (so ¼|x − ½| = ½·gx exactly). The quadratic in d is d(½d − ¾),
/// which lies in [−9/32, 0], so nothing cancels: every factor is in [11/8, 15/8].
#[inline(always)]
fn mixture_factor<V: Simd>(x: V, y: V, gx: V, gy: V) -> V {
    let half = V::splat(0.5);
    let d = x.sub(y).abs();
    V::splat(1.875)
        .sub(half.mul(gx))
        .sub(half.mul(gy))
        .add(d.mul(half.mul(d).sub(V::splat(0.75))))
}

/// D² of the set, and its gradient into `grad` when given.
fn evaluate<K: Lanes>(points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
    let (n, s) = (points.n(), points.s());
    let nf = n as f64;

    match grad {
        None => closed_form::<K>(points, products::<Single<K>, 1>(points)[0]),
        Some(grad) => {
            // Raw Σ_{l≠i, unordered} ∂₁K Π_{m≠k} K into every row; scaled below.
            let off = if n < 2 {
                grad.fill(0.0);
                0.0
            } else {
                let tiles = GradPairs::<K> {
                    blocks: Blocks::new(n, s),
                    xt: AlignedBuf::default(),
                    kernel: PhantomData,
                }
                .with_points(points);
                let mut gt = AlignedBuf::zeros(tiles.blocks.total_len());
                let off = grad_tiles(&tiles.blocks, &tiles, &mut gt);
                tiles.blocks.untranspose(&gt, grad, 1.0);
                off
            };
            // Per-point terms, in index order: the diagonal K(x_i, x_i) (whose derivative
            // is ∂₁K + ∂₂K) and the single product g. O(s) scratch, outside the pair loop.
            let mut pre = vec![0.0; 2 * s];
            let (pre_diag, pre_single) = pre.split_at_mut(s);
            let inv_n2 = 1.0 / (nf * nf);
            let two_inv_n = 2.0 / nf;
            let (mut single, mut diag) = (0.0, 0.0);
            for (xi, gr) in points.rows().zip(grad.chunks_exact_mut(s)) {
                let (mut pd, mut ps) = (1.0, 1.0);
                for k in 0..s {
                    pre_diag[k] = pd;
                    pre_single[k] = ps;
                    pd *= K::pair(xi[k], xi[k]).0;
                    if K::HAS_SINGLE {
                        ps *= K::single(xi[k]).0;
                    }
                }
                diag += pd;
                if K::HAS_SINGLE {
                    single += ps;
                }
                let (mut sd, mut ss) = (1.0, 1.0);
                for k in (0..s).rev() {
                    let (kv, d1, d2) = K::pair(xi[k], xi[k]);
                    let mut g = (2.0 * gr[k] + pre_diag[k] * sd * (d1 + d2)) * inv_n2;
                    sd *= kv;
                    if K::HAS_SINGLE {
                        let (gv, gd) = K::single(xi[k]);
                        g -= two_inv_n * pre_single[k] * ss * gd;
                        ss *= gv;
                    }
                    gr[k] = g;
                }
            }
            assemble(K::constant(s), single, diag, off, nf)
        }
    }
}

/// D² from the pair sum `off` = Σ_{i<l} Π_k K(x_ik, x_lk): the per-point sums
/// Σ_i Π_k g(x_ik) and Σ_i Π_k K(x_ik, x_ik), each in index order from 1, then
/// [`assemble`]. O(n s).
fn closed_form<K: DiscrepancyKernel>(points: &PointSet, off: f64) -> f64 {
    let (mut single, mut diag) = (0.0, 0.0);
    for xi in points.rows() {
        if K::HAS_SINGLE {
            single += xi.iter().fold(1.0, |p, &a| p * K::single(a).0);
        }
        diag += xi.iter().fold(1.0, |p, &a| p * K::pair(a, a).0);
    }
    assemble(
        K::constant(points.s()),
        single,
        diag,
        off,
        points.n() as f64,
    )
}

/// The squared discrepancy of each kind of `kinds`, in the same order: the closed form of
/// the module documentation, not clamped, with the pair sums of [`pair_product_sums`]
/// (one fused pass for the lists it fuses).
///
/// Each value is the same bits as [`DiscrepancyEnergy`]'s value of that kind, whichever
/// list it is computed in, for any number of threads and with or without AVX2. The
/// metrics of the root crate clamp it at 0 and take the root. The points must lie in
/// [0, 1]^s (not checked). O(n² s) time.
pub fn squared_discrepancies(points: &PointSet, kinds: &[DiscrepancyKind]) -> Vec<f64> {
    pair_product_sums(points, kinds)
        .into_iter()
        .zip(kinds)
        .map(|(off, &kind)| with_kernel!(kind, K => closed_form::<K>(points, off)))
        .collect()
}

/// Whether base^s and every product of s factors of at most `largest` stay within e^±600.
fn fits(base: f64, largest: f64, s: usize) -> bool {
    let growth = base.ln().abs().max(largest.ln());
    (s as f64) * growth < 600.0
}

/// Whether the closed form of `kind` stays within f64 at dimension s: its constant
/// base^s and every product of s factors within e^±600 (about 10^±260). Beyond, the
/// terms overflow or vanish and [`discrepancy_root`] takes the logarithmic form.
pub fn closed_form_fits(kind: DiscrepancyKind, s: usize) -> bool {
    with_kernel!(kind, K => fits(K::CONSTANT_BASE, K::LARGEST_FACTOR, s))
}

/// [`closed_form_fits`] for the mixture discrepancy: s ≤ 954, where (15/8)^s, its
/// largest product, is below e^600.
pub fn mixture_closed_form_fits(s: usize) -> bool {
    fits(Mixture::CONSTANT_BASE, Mixture::LARGEST_FACTOR, s)
}

/// The squared mixture discrepancy (the table's last row): (19/12)^s − (2/n) Σ_i Π_k g +
/// (1/n²) Σ_{i,l} Π_k h, not clamped, from one vectorised pass over the pairs. SciPy's
/// `qmc.discrepancy(method='MD')` is this value. Same bits as the fifth value of
/// [`squared_discrepancies_with_mixture`], for any number of threads and with or without
/// AVX2. Overflows beyond [`mixture_closed_form_fits`] (see [`mixture_root`]). The points
/// must lie in [0, 1]^s (not checked). O(n² s) time.
pub fn mixture_squared(points: &PointSet) -> f64 {
    closed_form::<Mixture>(points, products::<Single<Mixture>, 1>(points)[0])
}

/// The squares of the four L2 discrepancies, in the order of [`DiscrepancyKind`] (star,
/// modified, centred, wrap-around), and of the mixture discrepancy, from one pass over
/// the pairs; not clamped. Each is the same bits as [`squared_discrepancies`] of its kind
/// (and [`mixture_squared`] for the fifth), so fusing changes no value. The points must
/// lie in [0, 1]^s (not checked). O(n² s) time.
pub fn squared_discrepancies_with_mixture(points: &PointSet) -> [f64; 5] {
    squares_from_pair_sums(points, products::<AllFive, 5>(points))
}

/// The five squares of [`squared_discrepancies_with_mixture`] from their pair sums
/// Σ_{i<l} Π_k K(x_ik, x_lk), in its order.
pub(crate) fn squares_from_pair_sums(points: &PointSet, sums: [f64; 5]) -> [f64; 5] {
    let [star, modified, centered, wrap, mixture] = sums;
    [
        closed_form::<Star>(points, star),
        closed_form::<Modified>(points, modified),
        closed_form::<Centered>(points, centered),
        closed_form::<Wrap>(points, wrap),
        closed_form::<Mixture>(points, mixture),
    ]
}

/// The mixture discrepancy itself, right whenever it is representable, as
/// [`discrepancy_root`] is for the other kinds: the root of [`mixture_squared`] (0 where
/// rounding makes the square negative) while [`mixture_closed_form_fits`], the
/// logarithmic form beyond ([`mixture_root_by_logs`]).
///
/// Accuracy: both forms add terms of either sign, so both are exact to a few units of
/// rounding *of the largest term* (the constant (19/12)^s or a product of up to (15/8)^s),
/// not of D². Where D² is far below that term (many points in a dimension where the terms
/// nearly cancel) its relative error grows by their ratio, and a square lost to rounding
/// comes out as 0, exactly as for the other kinds. For few points in high dimension the
/// diagonal pair products dominate D² (h(x, x) ≥ 13/8 > 19/12) and the result is accurate
/// to about s·ε relative.
pub fn mixture_root(points: &PointSet) -> f64 {
    if mixture_closed_form_fits(points.s()) {
        return mixture_squared(points).max(0.0).sqrt();
    }
    mixture_root_by_logs(points)
}

/// The logarithmic form of [`mixture_root`] at any dimension (a logarithm per factor),
/// for checking it against the plain form where both apply.
pub fn mixture_root_by_logs(points: &PointSet) -> f64 {
    root_by_logs::<Mixture>(points)
}

/// The discrepancy itself (the root of the closed form, 0 where rounding makes the
/// square negative), right whenever it is representable: where the closed form fits f64
/// ([`closed_form_fits`]) the root of [`squared_discrepancies`]; beyond, every term of
/// the closed form is formed as a logarithm (Σ ln of its factors) and the sum is taken
/// relative to the largest, D = e^{L/2} √(Σ ± w e^{t − L}). That costs a logarithm per
/// factor, O(n² s) of them, and is only used where the plain form cannot answer. The
/// result is +∞ or 0 when the discrepancy itself lies beyond f64.
pub fn discrepancy_root(points: &PointSet, kind: DiscrepancyKind) -> f64 {
    if closed_form_fits(kind, points.s()) {
        return squared_discrepancies(points, &[kind])[0].max(0.0).sqrt();
    }
    discrepancy_root_by_logs(points, kind)
}

/// The logarithmic form of [`discrepancy_root`] at any dimension (slower: a logarithm
/// per factor), for checking it against the plain form where both apply.
pub fn discrepancy_root_by_logs(points: &PointSet, kind: DiscrepancyKind) -> f64 {
    with_kernel!(kind, K => root_by_logs::<K>(points))
}

/// The closed form with each term as (sign × weight, ln of its product); see
/// [`discrepancy_root`].
fn root_by_logs<K: DiscrepancyKernel>(points: &PointSet) -> f64 {
    let n = points.n() as f64;
    let s = points.s() as f64;
    let mut terms: Vec<(f64, f64)> = vec![(K::CONSTANT_SIGN, s * K::CONSTANT_BASE.ln())];
    let rows: Vec<&[f64]> = points.rows().collect();
    for (i, xi) in rows.iter().enumerate() {
        if K::HAS_SINGLE {
            let ln: f64 = xi.iter().map(|&a| K::single(a).0.ln()).sum();
            terms.push((-2.0 / n, ln));
        }
        for (l, xl) in rows.iter().enumerate().skip(i) {
            let ln: f64 = xi
                .iter()
                .zip(xl.iter())
                .map(|(&a, &b)| K::pair(a, b).0.ln())
                .sum();
            let weight = if l == i { 1.0 } else { 2.0 };
            terms.push((weight / (n * n), ln));
        }
    }
    let top = terms
        .iter()
        .map(|t| t.1)
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !top.is_finite() {
        return 0.0;
    }
    let sum: f64 = terms.iter().map(|(w, ln)| w * (ln - top).exp()).sum();
    if sum <= 0.0 {
        return 0.0;
    }
    (0.5 * top).exp() * sum.sqrt()
}

/// The kinds of [`pair_product_sums`]: `M` kernels whose pair products one pass forms.
trait Kinds<const M: usize>: Sync {
    /// Whether a kernel needs ½|x − ½| of each coordinate (the centred L2 and the
    /// mixture), which the loop then reads from a precomputed copy instead of forming it
    /// for every pair.
    const HALF_GAP: bool;
    /// Multiplies each product `p[m]` by kernel m's factor K_m(x, y); with
    /// [`Kinds::HALF_GAP`], `gx` = ½|x − ½| and `gy` = ½|y − ½| (else unused).
    fn mul_factors<V: Simd>(x: V, y: V, gx: V, gy: V, p: &mut [V; M]);
}

/// The centred L2 factor from `gx` = ½|x − ½| and `gy` = ½|y − ½|: the same
/// operations, in the same order, as [`Centered::vpair`], so the same bits.
#[inline(always)]
fn centered_factor<V: Simd>(x: V, y: V, gx: V, gy: V) -> V {
    V::splat(1.0)
        .add(gx)
        .add(gy)
        .sub(V::splat(0.5).mul(x.sub(y).abs()))
}

/// One kernel.
struct Single<K>(PhantomData<K>);

impl<K: Lanes> Kinds<1> for Single<K> {
    const HALF_GAP: bool = K::HALF_GAP;
    #[inline(always)]
    fn mul_factors<V: Simd>(x: V, y: V, gx: V, gy: V, p: &mut [V; 1]) {
        p[0] = p[0].mul(K::vpair_gap(x, y, gx, gy));
    }
}

/// Star and modified L2, what a run logs.
struct StarModified;

impl Kinds<2> for StarModified {
    const HALF_GAP: bool = false;
    #[inline(always)]
    fn mul_factors<V: Simd>(x: V, y: V, _: V, _: V, p: &mut [V; 2]) {
        p[0] = p[0].mul(Star::vpair(x, y));
        p[1] = p[1].mul(Modified::vpair(x, y));
    }
}

/// The four L2 discrepancies, in the order of [`DiscrepancyKind`].
struct AllFour;

impl Kinds<4> for AllFour {
    const HALF_GAP: bool = true;
    #[inline(always)]
    fn mul_factors<V: Simd>(x: V, y: V, gx: V, gy: V, p: &mut [V; 4]) {
        p[0] = p[0].mul(Star::vpair(x, y));
        p[1] = p[1].mul(Modified::vpair(x, y));
        p[2] = p[2].mul(centered_factor(x, y, gx, gy));
        p[3] = p[3].mul(Wrap::vpair(x, y));
    }
}

/// The four L2 discrepancies and the mixture: every discrepancy the metrics report.
struct AllFive;

impl Kinds<5> for AllFive {
    const HALF_GAP: bool = true;
    #[inline(always)]
    fn mul_factors<V: Simd>(x: V, y: V, gx: V, gy: V, p: &mut [V; 5]) {
        p[0] = p[0].mul(Star::vpair(x, y));
        p[1] = p[1].mul(Modified::vpair(x, y));
        p[2] = p[2].mul(centered_factor(x, y, gx, gy));
        p[3] = p[3].mul(Wrap::vpair(x, y));
        p[4] = p[4].mul(mixture_factor(x, y, gx, gy));
    }
}

/// Σ_{i<j} Π_k K(x_ik, x_jk) for each kind of `kinds`, in the same order: the pair term of
/// the closed form without the diagonal i = j (so the sum over all ordered pairs is
/// Σ_i Π_k K(x_ik, x_ik) + 2·this). The star, modified, centred and wrap-around kernels
/// are those of the module documentation.
///
/// One vectorised pass over the pairs serves all the kinds (the discrepancy, star +
/// modified, and all four in [`DiscrepancyKind`] order have fused passes; other lists run
/// one pass per kind). Each kind's sum has the same bits whichever list it is computed in,
/// for any number of threads and with or without AVX2 (no fused multiply-add), and the
/// same bits as the pair term of [`DiscrepancyEnergy`]'s value. The points must lie in
/// [0, 1]^s (not checked).
pub fn pair_product_sums(points: &PointSet, kinds: &[DiscrepancyKind]) -> Vec<f64> {
    use DiscrepancyKind::*;
    match kinds {
        [StarL2, ModifiedL2, CenteredL2, WrapAroundL2] => products::<AllFour, 4>(points).to_vec(),
        [StarL2, ModifiedL2] => products::<StarModified, 2>(points).to_vec(),
        _ => kinds
            .iter()
            .map(|&k| with_kernel!(k, K => products::<Single<K>, 1>(points)[0]))
            .collect(),
    }
}

/// Σ_{i<j} of the M pair products of `P`.
fn products<P: Kinds<M>, const M: usize>(points: &PointSet) -> [f64; M] {
    let (n, s) = (points.n(), points.s());
    if n < 2 {
        return [0.0; M];
    }
    let blocks = Blocks::new(n, s);
    let xt = blocks.transpose(points.as_slice(), |v| v);
    let gap = if P::HALF_GAP {
        blocks.transpose(points.as_slice(), |v| 0.5 * (v - 0.5).abs())
    } else {
        AlignedBuf::default()
    };
    let tiles = SumPairs::<P, M> {
        blocks: &blocks,
        xt: &xt,
        gap: &gap,
        kinds: PhantomData,
    };
    sum_tiles(
        &blocks,
        &tiles,
        || [0.0; M],
        |a, b| std::array::from_fn(|m| a[m] + b[m]),
    )
}

/// The value-only pair loop: per lane, the products multiply their factors in coordinate
/// order from 1; the lanes of a tile are summed lane by lane, then across lanes.
struct SumPairs<'a, P, const M: usize> {
    blocks: &'a Blocks,
    xt: &'a [f64],
    /// ½|x − ½|, block-transposed, when `P::HALF_GAP`.
    gap: &'a [f64],
    kinds: PhantomData<P>,
}

impl<P: Kinds<M>, const M: usize> SumTiles for SumPairs<'_, P, M> {
    type Out = [f64; M];

    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize) -> [f64; M] {
        let bl = self.blocks;
        let (bs, s) = (bl.bs, bl.s);
        let (xa, xb) = (bl.chunk(self.xt, a), bl.chunk(self.xt, b));
        let zero = V::splat(0.0);
        let mut acc = [zero; M];
        let (ga, gb) = if P::HALF_GAP {
            (bl.chunk(self.gap, a), bl.chunk(self.gap, b))
        } else {
            (&[][..], &[][..])
        };
        for ii in 0..bl.len(a) {
            for (jj, mask) in bl.lanes::<V>(a, b, ii) {
                let mut p = [V::splat(1.0); M];
                for k in 0..s {
                    let x = V::splat(xa[k * bs + ii]);
                    let y = V::load(&xb[k * bs + jj..]);
                    if P::HALF_GAP {
                        let gx = V::splat(ga[k * bs + ii]);
                        P::mul_factors(x, y, gx, V::load(&gb[k * bs + jj..]), &mut p);
                    } else {
                        P::mul_factors(x, y, zero, zero, &mut p);
                    }
                }
                for m in 0..M {
                    acc[m] = acc[m].add(mask.select(p[m], zero));
                }
            }
        }
        std::array::from_fn(|m| acc[m].hsum())
    }
}

/// The gradient pair loop of one kernel: the same products as [`SumPairs`] (so the same
/// value bits), with ∂K_k Π_{m≠k} K_m from prefix and suffix products added to row i
/// (∂₁) and row j (∂₂).
struct GradPairs<K> {
    blocks: Blocks,
    xt: AlignedBuf,
    kernel: PhantomData<K>,
}

impl<K: Lanes> GradPairs<K> {
    fn with_points(mut self, points: &PointSet) -> Self {
        self.xt = self.blocks.transpose(points.as_slice(), |v| v);
        self
    }
}

impl<K: Lanes> GradTiles for GradPairs<K> {
    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize, ga: &mut [f64], mut gb: Option<&mut [f64]>) -> f64 {
        let bl = &self.blocks;
        let (bs, s) = (bl.bs, bl.s);
        let (xa, xb) = (bl.chunk(&self.xt, a), bl.chunk(&self.xt, b));
        let zero = V::splat(0.0);
        let n = V::N;
        // Factors, prefix products and row i's lanes, s vectors each.
        let len = 3 * s * n;
        let mut buf = take_scratch(len);
        let (fac, rest) = buf[..len].split_at_mut(s * n);
        let (pre, row_i) = rest.split_at_mut(s * n);
        let mut acc = zero;
        for ii in 0..bl.len(a) {
            row_i.fill(0.0);
            for (jj, mask) in bl.lanes::<V>(a, b, ii) {
                let mut p = V::splat(1.0);
                for k in 0..s {
                    let f = K::vpair(V::splat(xa[k * bs + ii]), V::load(&xb[k * bs + jj..]));
                    p.store(&mut pre[k * n..]);
                    f.store(&mut fac[k * n..]);
                    p = p.mul(f);
                }
                acc = acc.add(mask.select(p, zero));
                let gj: &mut [f64] = match &mut gb {
                    Some(g) => g,
                    None => &mut *ga,
                };
                let mut suf = mask.select(V::splat(1.0), zero);
                for k in (0..s).rev() {
                    let w = V::load(&pre[k * n..]).mul(suf);
                    let (d1, d2) =
                        K::vderiv(V::splat(xa[k * bs + ii]), V::load(&xb[k * bs + jj..]));
                    let r = &mut row_i[k * n..];
                    V::load(r).add(w.mul(d1)).store(r);
                    let g = &mut gj[k * bs + jj..];
                    V::load(g).add(w.mul(d2)).store(g);
                    suf = suf.mul(V::load(&fac[k * n..]));
                }
            }
            for k in 0..s {
                ga[k * bs + ii] += V::load(&row_i[k * n..]).hsum();
            }
        }
        give_scratch(buf);
        acc.hsum()
    }
}

/// C − (2/n) Σ g + (1/n²) (Σ_i K(x_i, x_i) + 2 Σ_{i<l} K(x_i, x_l)), without the metric's
/// clamp at 0 (see the module documentation).
fn assemble(constant: f64, single: f64, diag: f64, off: f64, n: f64) -> f64 {
    constant - 2.0 * single / n + (diag + 2.0 * off) / (n * n)
}

/// An estimate of a squared discrepancy and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledSquare {
    /// The estimate of D² (not clamped: it may fall below 0 by a few standard errors).
    pub value: f64,
    /// Its standard error, from the spread of the sampled pair terms.
    pub standard_error: f64,
}

/// Pairs per stream of [`sampled_squared_discrepancies`]: each chunk draws its pairs from
/// its own generator, so the result does not depend on the number of threads.
const SAMPLE_CHUNK: usize = 1 << 15;

/// SplitMix64: a small, fast generator whose streams are fixed by their seed alone.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// An index in 0..n by the multiply-shift map (its bias, below n/2⁶⁴, is far below
    /// any standard error it could affect).
    fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next()) * n as u128) >> 64) as usize
    }
}

/// Count, mean and sum of squared deviations of a sample (Welford), merged in a fixed
/// order (Chan et al.).
#[derive(Clone, Copy, Default)]
struct Moments {
    count: f64,
    mean: f64,
    m2: f64,
}

impl Moments {
    fn push(&mut self, v: f64) {
        self.count += 1.0;
        let d = v - self.mean;
        self.mean += d / self.count;
        self.m2 += d * (v - self.mean);
    }

    fn merge(self, o: Moments) -> Moments {
        if self.count == 0.0 {
            return o;
        }
        if o.count == 0.0 {
            return self;
        }
        let count = self.count + o.count;
        let d = o.mean - self.mean;
        Moments {
            count,
            mean: self.mean + d * o.count / count,
            m2: self.m2 + o.m2 + d * d * self.count * o.count / count,
        }
    }
}

/// Π_k g(x_k) of the five kernels (star, modified, centred, wrap-around, mixture) at one
/// point: ∫ K(x, y) dy, which for the wrap-around L2 is the constant (4/3)^s.
fn point_integrals(x: &[f64]) -> [f64; 5] {
    let mut g = [1.0; 5];
    for &a in x {
        g[0] *= Star::single(a).0;
        g[1] *= Modified::single(a).0;
        g[2] *= Centered::single(a).0;
        g[3] *= Wrap::CONSTANT_BASE;
        g[4] *= Mixture::single(a).0;
    }
    g
}

/// How many pairs ahead of its use [`sampled_squared_discrepancies`] draws a pair and
/// asks for its points: enough misses in flight to cover memory's latency.
const PREFETCH_AHEAD: usize = 16;

/// Asks the processor to bring the two points of pair (i, l) and their integrals into
/// the cache (a hint: no effect on any value).
#[inline(always)]
fn prefetch_pair(rows: &[f64], g: &[[f64; 5]], s: usize, (i, l): (usize, usize)) {
    #[cfg(target_arch = "x86_64")]
    for k in [i, l] {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let row = &rows[k * s..(k + 1) * s];
        // One hint per cache line the row may touch, and one for the integrals.
        for part in row
            .chunks(8)
            .map(|p| p.as_ptr())
            .chain(row.last().map(|v| v as *const f64))
        {
            // SAFETY: prefetching is a hint that reads nothing; the pointer is in bounds.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(part.cast()) };
        }
        // SAFETY: as above.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(g[k].as_ptr().cast()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (rows, g, s, i, l);
}

/// The five pair products K(x, y) (star, modified, centred, wrap-around, mixture).
fn pair_products(x: &[f64], y: &[f64]) -> [f64; 5] {
    let mut p = [1.0; 5];
    for (&a, &b) in x.iter().zip(y) {
        p[0] *= Star::pair(a, b).0;
        p[1] *= Modified::pair(a, b).0;
        p[2] *= Centered::pair(a, b).0;
        p[3] *= Wrap::pair(a, b).0;
        p[4] *= Mixture::pair(a, b).0;
    }
    p
}

/// Estimates of the five squared discrepancies of [`squared_discrepancies_with_mixture`]
/// (star, modified, centred, wrap-around L2, mixture) from `pairs` random pairs of
/// distinct points, deterministic for a `seed` (and any number of threads), with their
/// standard errors. O(n s + pairs · s) time.
///
/// Only the pair sum Σ_{i<l} Π_k K(x_ik, x_lk) is estimated; the constant, the single
/// sum Σ_i Π_k g(x_ik) and the diagonal are exact. The pair sum is estimated through the
/// centred kernel K̃(x, y) = K(x, y) − G(x) − G(y) + C with G(x) = ∫ K(x, y) dy and
/// C = ∫∫ K (a control variate whose pair sum, (n − 1) Σ_i G(x_i) − N C over the
/// N = n(n − 1)/2 pairs, is exact), so the estimate is unbiased: pairs are drawn uniformly
/// with replacement, and the mean of K̃ over them estimates its mean over all N pairs.
/// The standard error is (2N/n²) · sd(K̃)/√pairs.
///
/// The terms K̃ are of order C while D² of an even set is far smaller (it is what is left
/// when they cancel), so the standard error may exceed the value itself: it says how
/// much of the estimate to believe. The points must lie in [0, 1]^s (not checked).
pub fn sampled_squared_discrepancies(
    points: &PointSet,
    pairs: usize,
    seed: u64,
) -> [SampledSquare; 5] {
    use rayon::prelude::*;
    let (n, s) = (points.n(), points.s());
    let constant = [
        Star::constant(s),
        Modified::constant(s),
        Centered::constant(s),
        Wrap::constant(s),
        Mixture::constant(s),
    ];
    // ∫∫ K of each kernel: |C_s| (for the wrap-around L2, C_s = −(4/3)^s).
    let whole = constant.map(f64::abs);
    // The closed form's middle term; the wrap-around L2 has merged it into C_s.
    let has_single = [
        Star::HAS_SINGLE,
        Modified::HAS_SINGLE,
        Centered::HAS_SINGLE,
        Wrap::HAS_SINGLE,
        Mixture::HAS_SINGLE,
    ];
    let middle = |m: usize, single: f64| if has_single[m] { single } else { 0.0 };
    let g: Vec<[f64; 5]> = points.rows().map(point_integrals).collect();
    let (mut single, mut diag) = ([0.0; 5], [0.0; 5]);
    for (x, gi) in points.rows().zip(&g) {
        let d = pair_products(x, x);
        for m in 0..5 {
            single[m] += gi[m];
            diag[m] += d[m];
        }
    }
    let nf = n as f64;
    if n < 2 || pairs == 0 {
        return std::array::from_fn(|m| SampledSquare {
            value: assemble(constant[m], middle(m, single[m]), diag[m], 0.0, nf),
            standard_error: if n < 2 { 0.0 } else { f64::INFINITY },
        });
    }
    let rows = points.as_slice();
    let chunks = pairs.div_ceil(SAMPLE_CHUNK);
    let moments: Vec<[Moments; 5]> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix(seed ^ (c as u64).wrapping_mul(0xd1b5_4a32_d192_ed03));
            let mut acc = [Moments::default(); 5];
            if crate::stop::requested() {
                // Ctrl-C in Python: the caller discards this estimate.
                return acc;
            }
            let len = SAMPLE_CHUNK.min(pairs - c * SAMPLE_CHUNK);
            let mut draw = || {
                let i = rng.below(n);
                let mut l = rng.below(n - 1);
                if l >= i {
                    l += 1;
                }
                (i, l)
            };
            // The pairs are drawn PREFETCH_AHEAD ahead of their use, in the same order,
            // and their points asked of memory then: a random pair of a large set is four
            // cache misses, which otherwise cost more than its arithmetic.
            let mut ahead = [(0usize, 0usize); PREFETCH_AHEAD];
            for slot in ahead.iter_mut().take(len) {
                *slot = draw();
                prefetch_pair(rows, &g, s, *slot);
            }
            for t in 0..len {
                let (i, l) = ahead[t % PREFETCH_AHEAD];
                if t + PREFETCH_AHEAD < len {
                    let next = draw();
                    prefetch_pair(rows, &g, s, next);
                    ahead[t % PREFETCH_AHEAD] = next;
                }
                let p = pair_products(&rows[i * s..(i + 1) * s], &rows[l * s..(l + 1) * s]);
                for m in 0..5 {
                    acc[m].push(p[m] - g[i][m] - g[l][m] + whole[m]);
                }
            }
            acc
        })
        .collect();
    let total = moments.iter().fold([Moments::default(); 5], |a, b| {
        std::array::from_fn(|m| a[m].merge(b[m]))
    });
    let count = nf * (nf - 1.0) / 2.0;
    std::array::from_fn(|m| {
        let t = total[m];
        let off = count * t.mean + (nf - 1.0) * single[m] - count * whole[m];
        let sd = if t.count > 1.0 {
            (t.m2 / (t.count - 1.0)).sqrt()
        } else {
            f64::INFINITY
        };
        SampledSquare {
            value: assemble(constant[m], middle(m, single[m]), diag[m], off, nf),
            standard_error: 2.0 * count / (nf * nf) * sd / t.count.sqrt(),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small set with every coordinate at least 0.02 from ½, from the faces and from
    /// the same coordinate of every other point: a step of 1e-6 crosses no kink.
    fn set_away_from_kinks() -> PointSet {
        let (n, s) = (6, 3);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut data = Vec::with_capacity(n * s);
        while data.len() < n * s {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let v = (state >> 11) as f64 / (1u64 << 53) as f64;
            let k = data.len() % s;
            let clear = (v - 0.5).abs() > 0.02
                && v > 0.02
                && v < 0.98
                && data
                    .iter()
                    .skip(k)
                    .step_by(s)
                    .all(|&u: &f64| (u - v).abs() > 0.02);
            if clear {
                data.push(v);
            }
        }
        PointSet::new(n, s, data).unwrap()
    }

    #[test]
    fn mixture_gradient_matches_central_differences() {
        // The mixture is not an energy, but its kernel carries the derivatives the pair
        // loops ask of every kernel; they must be right should it ever be minimised.
        let p = set_away_from_kinks();
        let mut grad = vec![f64::NAN; p.coordinate_count()];
        let v = evaluate::<Mixture>(&p, Some(&mut grad));
        assert_eq!(v.to_bits(), evaluate::<Mixture>(&p, None).to_bits());
        assert_eq!(v.to_bits(), mixture_squared(&p).to_bits());
        let h = 1e-6;
        let scale = grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        for c in 0..p.coordinate_count() {
            let moved = |dx: f64| {
                let mut x = p.as_slice().to_vec();
                x[c] += dx;
                evaluate::<Mixture>(&PointSet::new(p.n(), p.s(), x).unwrap(), None)
            };
            let fd = (moved(h) - moved(-h)) / (2.0 * h);
            assert!(
                (grad[c] - fd).abs() < 1e-6 * scale,
                "coordinate {c}: {} vs {fd}",
                grad[c]
            );
        }
    }

    #[test]
    fn mixture_kink_derivatives_are_the_averages_of_the_one_sided_ones() {
        // At x = y and at ½ the kinks contribute nothing (the middle of ±¾ and of ±¼).
        let (_, dx, dy) = Mixture::pair(0.5, 0.5);
        assert_eq!((dx, dy), (0.0, 0.0));
        assert_eq!(Mixture::single(0.5).1, 0.0);
        let (_, dx, dy) = Mixture::pair(0.3, 0.3);
        assert_eq!((dx, dy), (0.25, 0.25));
    }
}
