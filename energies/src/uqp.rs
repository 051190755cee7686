//! U_{q,p}: the p-norm of the inverse pair distances (eqs. 5 and 12), with the q-distance
//! of eq. 11, its limit q = ∞ (the torus distance, eq. 9) or the Euclidean distance (eq. 8).
//!
//! U_{q,p}(X) = (Σ_{i<j} d_ij^{-p})^{1/p}. With d_ij² = Σ_k h(Δ_ijk)² and
//! Δ_ijk = |x_ik − x_jk| the gradient is (eqs. 14–18)
//!
//! ∂U/∂x_ik = −S^{1/p−1} Σ_{j≠i} a_ijk / d_ij^{p+2},   S = Σ_{i<j} d_ij^{-p},
//!
//! where a_ijk = sgn(x_ik − x_jk)·h·h' (eq. 16 for finite q, x_ik − x_jk for 'E').
//!
//! **Kernels.** The pair loop is [`crate::pairs`]'s tiled half loop in four-lane vectors.
//! The periodic distances reduce each coordinate difference to δ ∈ [−½, ½] (h is even and
//! has period 1) and use closed forms for q = 1 (h = Δ(1 − Δ)), q = 2
//! (h² = Δ²(1 − Δ)²/(Δ² + (1 − Δ)²)) and q = ∞ (h = Δ). General q needs two powers per
//! coordinate, t = (Δ/(1 − Δ))^q and v² = (1 + t)^{−2/q} (h = Δ v, and
//! h·h' = Δ v² (1 − σ/(1 − Δ)) with σ = t/(1 + t)), and one per pair, d^{−p} (except
//! p = 1, 1/√d²). They are computed as 2^{y·log₂x} with vectorised log₂ and 2^y:
//!
//! - log₂ x = e + log₂ m with x = 2^e m, m ∈ [1/√2, √2], and log₂ m = f·P(f²),
//!   f = (m − 1)/(m + 1), |f| ≤ 0.1716, P the degree-6 Chebyshev fit of (2/ln 2)·atanh(f)/f
//!   (error below 1.8e-16 relative). log₂(1 + t) uses f = t/(t + 2) (or (t − 1)/(t + 3)
//!   above t = √2 − 1) without rounding 1 + t, and shares its division with σ.
//! - 2^y = 2^n · P(r), n = round(y), |r| ≤ ½, P the degree-10 Chebyshev fit of 2^r (error
//!   below 3.0e-16 relative).
//!
//! Each point i runs these in three passes over all its partners j in a block (see
//! `VecQ`'s `rows`): one chain through log₂, 2^y, log₂ and 2^y is ~250 cycles of
//! latency, and short passes let the processor overlap many coordinates.
//!
//! With rounding, each h² and each a = h·h' of the general-q kernel is within 1e-12 of the
//! exact value, relative to h² and to Δ·v² (the scale of a; a itself passes through 0 at
//! Δ = ½), for 0.01 ≤ q ≤ 100. `tests/fast_paths.rs` checks this bound against the
//! formulas of eqs. 11 and 16 on 4 400 values of Δ ∈ [1e-80, 1 − 1e-16] for 15 values of q
//! (worst measured: 5.7e-14, at q = 0.01), and whole energies and gradients against a
//! straightforward `powf` kernel for many (q, p, s, n) (worst 2.5e-13). The error grows
//! like (1/q)·1e-16 because v² = 2^{−(2/q)·…} amplifies the absolute error of the
//! exponent. Outside the exponent range the result saturates: a t below 2^{−1022} is taken
//! as 2^{−1022} (it only enters 1 + t), a v², h² or d^{−p} below 2^{−1022} is flushed to 0,
//! a d^{−p} above 2^{1023} is +∞, and a pair with d² below 2^{−1022} counts as coincident
//! (+∞ energy). The pair weight d^{−p−2} of the gradient overflows for d below about
//! 1e-100, as in any f64 evaluation.
//!
//! **Fast precision.** [`Precision::Fast`] replaces the two powers of the general-q kernel
//! (0.01 ≤ q ≤ 2) by a table: v² = h²/Δ² is smooth in Δ away from 0, so each binade
//! [2^e, 2^{e+1}) of Δ (e = −24 … −1) is cut into 64 intervals on which v² is a cubic,
//! interpolated at Chebyshev points from the f64 formulas when the energy is built; h·h'
//! is ½ d(h²)/dΔ of that cubic, so the forces are the exact gradient of the energy the run
//! evaluates. The interval is read off the bits of Δ and each lane fetches its interval's
//! four coefficients as one row, transposed in registers (the processor's gathers are
//! slower). Errors: h² within 9e-10, h·h' within 9e-7 of its scale (stated bounds 4e-9 and
//! 2e-6, [`Precision::FAST_BOUND_H2`], [`Precision::FAST_BOUND`]); Δ below 2^{−24} uses the
//! f64 formulas.
//!
//! **Determinism.** The sums and every gradient row are accumulated in an order fixed by n
//! alone, so the result has the same bits for any number of threads. On processors with
//! AVX2 and FMA the polynomials use fused multiply-adds, elsewhere separate roundings: the
//! general-q, Q2 and pair-power results may differ between those two kinds of machine in
//! the last bits (well within the bound above), never between thread counts.

use crate::pairs::{
    give_scratch, grad_tiles, sum_tiles, take_scratch, AlignedBuf, Blocks, GradTiles, Simd,
    SumTiles,
};
use crate::{Energy, Error, PointSet, Result};

/// The pair distance inside U_{q,p}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distance {
    /// The q-distance of eq. 11, q ∈ (0, ∞): periodic with period 1 in every coordinate,
    /// smooth for finite q.
    Q(f64),
    /// q = ∞: the torus distance of eq. 9, min(Δ, 1 − Δ) per coordinate.
    Torus,
    /// q = 'E': the Euclidean distance of eq. 8 (not periodic).
    Euclidean,
}

impl Distance {
    /// Parses `q` as the CLI writes it: a positive number, `inf` (or `∞`), or `E`.
    pub fn parse(q: &str) -> Result<Self> {
        let t = q.trim();
        match t {
            "E" | "e" => return Ok(Distance::Euclidean),
            "inf" | "Inf" | "INF" | "infinity" | "∞" => return Ok(Distance::Torus),
            _ => {}
        }
        let v: f64 = t
            .parse()
            .map_err(|_| Error::invalid("q", q, "a number in (0, ∞), `inf` or `E` (Euclidean)"))?;
        Distance::from_q(v)
    }

    /// The q-distance for a numeric q: (0, ∞) finite, or +∞ for the torus distance.
    pub fn from_q(q: f64) -> Result<Self> {
        if q.is_nan() || q <= 0.0 {
            return Err(Error::invalid(
                "q",
                q,
                "a number in (0, ∞), `inf` or `E` (Euclidean)",
            ));
        }
        Ok(if q.is_infinite() {
            Distance::Torus
        } else {
            Distance::Q(q)
        })
    }

    /// How the paper writes q: a number, `∞` or `E`.
    pub fn label(&self) -> String {
        match self {
            Distance::Q(q) => format!("{q}"),
            Distance::Torus => "inf".to_string(),
            Distance::Euclidean => "E".to_string(),
        }
    }

    /// Whether the distance is periodic with period 1 in every coordinate.
    pub fn is_periodic(&self) -> bool {
        !matches!(self, Distance::Euclidean)
    }

    /// Squared distance between two points.
    pub fn squared(&self, a: &[f64], b: &[f64]) -> f64 {
        let kern = Kernel::new(*self);
        a.iter().zip(b).map(|(x, y)| kern.eval(x - y).0).sum()
    }
}

/// Per-coordinate kernel: for the signed difference δ = x_ik − x_jk returns
/// (h(Δ)², sgn(δ)·h(Δ)·h'(Δ)), so that d² = Σ_k h² and ∂d/∂x_ik = (second) / d.
#[derive(Clone, Copy, PartialEq)]
enum Kernel {
    Euclidean,
    Torus,
    Q1,
    Q2,
    Q { q: f64, inv_q: f64 },
}

impl Kernel {
    fn new(d: Distance) -> Self {
        match d {
            Distance::Euclidean => Kernel::Euclidean,
            Distance::Torus => Kernel::Torus,
            Distance::Q(1.0) => Kernel::Q1,
            Distance::Q(2.0) => Kernel::Q2,
            Distance::Q(q) => Kernel::Q { q, inv_q: 1.0 / q },
        }
    }

    #[inline]
    fn eval(&self, delta: f64) -> (f64, f64) {
        match *self {
            Kernel::Euclidean => (delta * delta, delta),
            Kernel::Torus => {
                let (dl, sg) = unit_abs(delta);
                if dl < 0.5 {
                    (dl * dl, sg * dl)
                } else if dl > 0.5 {
                    let t = 1.0 - dl;
                    (t * t, -sg * t)
                } else {
                    // Δ = 1/2 is a kink of min(Δ, 1 − Δ); 0 is the middle of its
                    // subdifferential.
                    (0.25, 0.0)
                }
            }
            Kernel::Q1 => {
                // w = 1: h = Δ(1 − Δ), h·h' = Δ(1 − Δ)(1 − 2Δ).
                let (dl, sg) = unit_abs(delta);
                let t = dl * (1.0 - dl);
                (t * t, sg * t * (1.0 - 2.0 * dl))
            }
            Kernel::Q2 => {
                let (dl, sg) = unit_abs(delta);
                let u = 1.0 - dl;
                let t = dl * u;
                let w = u * u + dl * dl;
                (t * t / w, sg * t * (u * u * u - dl * dl * dl) / (w * w))
            }
            Kernel::Q { q, inv_q } => {
                // h is symmetric about 1/2 (h(Δ) = h(1 − Δ), so h·h' changes sign): work
                // with Δ ≤ 1/2. With t = (Δ/(1 − Δ))^q ≤ 1 and v = (1 + t)^{−1/q}, eq. 11
                // is h = Δ·v and eq. 16 is h·h' = Δ v² ((1 − Δ) − tΔ) / ((1 − Δ)(1 + t)):
                // two powers per coordinate instead of three.
                let (mut dl, mut sg) = unit_abs(delta);
                if dl > 0.5 {
                    dl = 1.0 - dl;
                    sg = -sg;
                }
                if dl == 0.0 {
                    return (0.0, 0.0);
                }
                let u = 1.0 - dl;
                let t = (dl / u).powf(q);
                let v = (1.0 + t).powf(-inv_q);
                let h = dl * v;
                (h * h, sg * h * v * (u - t * dl) / (u * (1.0 + t)))
            }
        }
    }
}

/// |δ| reduced to [0, 1) (the q-distances have period 1) and the sign of δ.
#[inline]
fn unit_abs(delta: f64) -> (f64, f64) {
    let a = delta.abs();
    let a = if a < 1.0 { a } else { a - a.floor() };
    (a, if delta < 0.0 { -1.0 } else { 1.0 })
}

/// How the general-q distance is evaluated; the sums are f64 in both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// Each h² and h·h' within 1e-12 of eqs. 11/16 (see the module documentation).
    #[default]
    Full,
    /// For q ∈ [0.01, 2] other than 1 (which has a closed form): h²/Δ² from a table of
    /// cubics on 1536 intervals that follow the bits of Δ (built once per q from the f64
    /// formulas), and h·h' = ½ d(h²)/dΔ of that same h², so the forces are the exact
    /// gradient of the energy evaluated. h² is within [`Precision::FAST_BOUND_H2`] of
    /// eq. 11, h·h' within [`Precision::FAST_BOUND`] of eq. 16. About twice as fast as
    /// [`Precision::Full`]; for the DEM's dynamics. Other q use the full kernels.
    Fast,
}

impl Precision {
    /// The stated bound of [`Precision::Fast`] on h·h', relative to Δ·v² (its scale; it
    /// passes through 0 at Δ = ½): the derivative of the interpolating cubic, at most
    /// 9e-7 over 0.01 ≤ q ≤ 2. `tests/fast_paths.rs` checks both bounds on 4 400 values of
    /// Δ for 14 values of q.
    pub const FAST_BOUND: f64 = 2e-6;
    /// The stated bound of [`Precision::Fast`] on h², relative to h²: a cubic on intervals
    /// 1/128 of their distance from 0 wide interpolates v² within 9e-10.
    pub const FAST_BOUND_H2: f64 = 4e-9;

    /// Whether [`Precision::Fast`] changes the kernel for this q.
    pub fn fast_applies(q: f64) -> bool {
        (0.01..=2.0).contains(&q) && q != 1.0 && q != 2.0
    }

    /// Parses `full` or `fast`.
    pub fn parse(text: &str) -> Result<Self> {
        match text.trim() {
            "full" => Ok(Precision::Full),
            "fast" => Ok(Precision::Fast),
            _ => Err(Error::invalid("precision", text, "`full` or `fast`")),
        }
    }

    /// `full` or `fast`.
    pub fn label(&self) -> &'static str {
        match self {
            Precision::Full => "full",
            Precision::Fast => "fast",
        }
    }
}

/// The potential energy U_{q,p} of eqs. 5/12 (G = 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Uqp {
    distance: Distance,
    p: f64,
    precision: Precision,
    /// The table of [`Precision::Fast`], when it applies to this q.
    fast: Option<std::sync::Arc<FastTable>>,
}

impl Uqp {
    /// U_{q,p} with the given distance and finite p > 0.
    pub fn new(distance: Distance, p: f64) -> Result<Self> {
        if !(p > 0.0 && p.is_finite()) {
            return Err(Error::invalid("p", p, "a finite number > 0"));
        }
        if let Distance::Q(q) = distance {
            Distance::from_q(q)?;
        }
        Ok(Uqp {
            distance,
            p,
            precision: Precision::Full,
            fast: None,
        })
    }

    /// The same energy evaluated with another [`Precision`] (it only changes the general-q
    /// distance).
    pub fn with_precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self.fast = match (precision, self.distance) {
            (Precision::Fast, Distance::Q(q)) if Precision::fast_applies(q) => {
                Some(std::sync::Arc::new(FastTable::new(q)))
            }
            _ => None,
        };
        self
    }

    /// The precision in use.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The distance in use.
    pub fn distance(&self) -> Distance {
        self.distance
    }

    /// The exponent p.
    pub fn p(&self) -> f64 {
        self.p
    }

    /// S = Σ_{i<j} d_ij^{-p}, the sum whose 1/p-th power is the energy.
    pub fn pair_sum(&self, points: &PointSet) -> f64 {
        if points.n() < 2 {
            return 0.0;
        }
        struct Sum<'a>(&'a PointSet, f64);
        impl WithKernel for Sum<'_> {
            type Out = f64;
            fn run<K: VecKernel>(self, kern: K) -> f64 {
                let tiles = UqpTiles::new(self.0, kern, self.1);
                sum_tiles(&tiles.blocks, &tiles, || 0.0, |a, b| a + b)
            }
        }
        with_kernel(self.distance, self.fast.as_deref(), Sum(points, self.p))
    }
}

impl Energy for Uqp {
    fn name(&self) -> String {
        match (self.precision, self.distance) {
            (Precision::Fast, Distance::Q(q)) if Precision::fast_applies(q) => {
                format!(
                    "U_{{q,p}}(q={}, p={:?}, fast)",
                    self.distance.label(),
                    self.p
                )
            }
            // Debug keeps an extreme p short (1e300, not 301 digits).
            _ => format!("U_{{q,p}}(q={}, p={:?})", self.distance.label(), self.p),
        }
    }

    fn value(&self, points: &PointSet) -> f64 {
        if points.n() < 2 {
            return 0.0;
        }
        self.pair_sum(points).powf(1.0 / self.p)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(
            grad.len(),
            points.coordinate_count(),
            "gradient buffer length"
        );
        grad.fill(0.0);
        if points.n() < 2 {
            return 0.0;
        }
        // Σ_j a_ijk / d_ij^{p+2} into row i (and its negative into row j), and S; the
        // common factor −S^{1/p−1} is applied when the rows are copied out.
        struct Grad<'a>(&'a PointSet, f64);
        impl WithKernel for Grad<'_> {
            type Out = (f64, Blocks, AlignedBuf);
            fn run<K: VecKernel>(self, kern: K) -> Self::Out {
                let tiles = UqpTiles::new(self.0, kern, self.1);
                let mut gt = AlignedBuf::zeros(tiles.blocks.total_len());
                let sum = grad_tiles(&tiles.blocks, &tiles, &mut gt);
                (sum, tiles.blocks, gt)
            }
        }
        let (sum, blocks, gt) =
            with_kernel(self.distance, self.fast.as_deref(), Grad(points, self.p));
        let scale = -sum.powf(1.0 / self.p - 1.0);
        if scale.is_finite() {
            blocks.untranspose(&gt, grad, scale);
        } else {
            // Coincident points: the energy is +∞ and no finite force is defined.
            grad.fill(0.0);
        }
        sum.powf(1.0 / self.p)
    }
}

/// The vector form of [`Kernel`], on the reduced difference δ ∈ [−½, ½] (or the raw
/// difference for the Euclidean distance). `h2` must be the same operations as the first
/// value of `h2_grad`, so the value and gradient paths add the same d².
trait VecKernel: Copy + Send + Sync {
    /// Whether h has period 1 (the difference is reduced before the kernel).
    const PERIODIC: bool;
    fn h2<V: Simd>(&self, d: V) -> V;
    /// (h², sgn(δ)·h·h').
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V);

    /// For one point i against the points j ∈ `rows.jlo .. rows.jhi` of a block: h² into
    /// `rows.h2` and, when `GRAD`, h·h' into `rows.force`, at `k·bs + j`. One pass here;
    /// kernels with long dependency chains split it into several (see [`VecQ`]).
    #[inline(always)]
    fn rows<V: Simd, const GRAD: bool>(&self, r: &mut Rows<'_>) {
        for k in 0..r.s {
            let xi = V::splat(r.xi[k]);
            for j in (r.jlo..r.jhi).step_by(V::N) {
                let at = k * r.bs + j;
                let d = diff::<Self, V>(xi, V::load(&r.xb[at..]));
                if GRAD {
                    let (h2, f) = self.h2_grad(d);
                    h2.store(&mut r.h2[at..]);
                    f.store(&mut r.force[at..]);
                } else {
                    self.h2(d).store(&mut r.h2[at..]);
                }
            }
        }
    }
}

/// One point i against a range of a block's points, with the block-layout buffers the
/// kernel passes fill (`s·bs` values each, index k·bs + j).
struct Rows<'a> {
    s: usize,
    bs: usize,
    jlo: usize,
    jhi: usize,
    /// Coordinates of point i (reduced like `xb`).
    xi: &'a [f64],
    /// The block's coordinates.
    xb: &'a [f64],
    h2: &'a mut [f64],
    force: &'a mut [f64],
    tmp1: &'a mut [f64],
    tmp2: &'a mut [f64],
}

/// The difference x_i − x_j, reduced to [−½, ½] when the kernel is periodic: adding and
/// subtracting 1.5·2^52 rounds to the nearest integer.
#[inline(always)]
fn diff<K: VecKernel, V: Simd>(xi: V, xj: V) -> V {
    let d = xi.sub(xj);
    if K::PERIODIC {
        let magic = V::splat(MAGIC);
        d.sub(d.add(magic).sub(magic))
    } else {
        d
    }
}

/// 1.5·2^52: x + MAGIC − MAGIC is x rounded to an integer (ties to even) for |x| < 2^51,
/// and the low bits of x + MAGIC hold that integer.
const MAGIC: f64 = 6_755_399_441_055_744.0;

/// Calls `u.run` with the vector kernel of a distance.
trait WithKernel {
    type Out;
    fn run<K: VecKernel>(self, kern: K) -> Self::Out;
}

fn with_kernel<U: WithKernel>(d: Distance, fast: Option<&FastTable>, u: U) -> U::Out {
    match Kernel::new(d) {
        Kernel::Euclidean => u.run(VecEuclidean),
        Kernel::Torus => u.run(VecTorus),
        Kernel::Q1 => u.run(VecQ1),
        Kernel::Q2 => u.run(VecQ2),
        Kernel::Q { q, inv_q } => {
            let full = VecQ {
                q,
                minus_two_over_q: -2.0 * inv_q,
            };
            match fast {
                Some(table) if table.q == q => u.run(VecQFast { full, table }),
                _ => u.run(full),
            }
        }
    }
}

#[derive(Clone, Copy)]
struct VecEuclidean;
#[derive(Clone, Copy)]
struct VecTorus;
#[derive(Clone, Copy)]
struct VecQ1;
#[derive(Clone, Copy)]
struct VecQ2;
#[derive(Clone, Copy)]
struct VecQ {
    q: f64,
    minus_two_over_q: f64,
}

impl VecKernel for VecEuclidean {
    const PERIODIC: bool = false;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        d.mul(d)
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        (d.mul(d), d)
    }
}

impl VecKernel for VecTorus {
    const PERIODIC: bool = true;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        d.mul(d)
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        // Δ = ½ is the kink of min(Δ, 1 − Δ); 0 is the middle of its subdifferential.
        let kink = d.abs().eq(V::splat(0.5));
        (d.mul(d), kink.select(V::splat(0.0), d))
    }
}

impl VecKernel for VecQ1 {
    const PERIODIC: bool = true;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        let dl = d.abs();
        let h = dl.mul(V::splat(1.0).sub(dl));
        h.mul(h)
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        // h = Δ(1 − Δ), h·h' = h(1 − 2Δ).
        let one = V::splat(1.0);
        let dl = d.abs();
        let u = one.sub(dl);
        let h = dl.mul(u);
        let a = d.mul(u).mul(one.sub(dl.add(dl)));
        (h.mul(h), a)
    }
}

impl VecKernel for VecQ2 {
    const PERIODIC: bool = true;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        self.h2_grad(d).0
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        // h² = t²/w with t = Δ(1 − Δ), w = Δ² + (1 − Δ)²; h·h' = t((1 − Δ)³ − Δ³)/w².
        let dl = d.abs();
        let u = V::splat(1.0).sub(dl);
        let (uu, dd) = (u.mul(u), dl.mul(dl));
        let inv_w = V::splat(1.0).div(uu.add(dd));
        let t = dl.mul(u);
        let cube = uu.mul(u).sub(dd.mul(dl));
        (
            t.mul(t).mul(inv_w),
            d.mul(u).mul(cube).mul(inv_w.mul(inv_w)),
        )
    }
}

/// √2 and √2 − 1, the range reduction points of [`log2`] and [`log2_1p`].
const SQRT_2: f64 = std::f64::consts::SQRT_2;
const SQRT_2_M1: f64 = std::f64::consts::SQRT_2 - 1.0;

/// Exponents below this are flushed: 2^y would be subnormal.
const MIN_EXP: f64 = -1022.0;

impl VecQ {
    /// (Δ below 2^{−1022}, 1/(1 − Δ), σ, v², h²) of the general-q kernel; see the module
    /// documentation.
    #[inline(always)]
    fn parts<V: Simd>(&self, d: V) -> (V, V, V, V, V) {
        let one = V::splat(1.0);
        let zero = V::splat(0.0);
        let dl = d.abs();
        let inv_u = one.div(one.sub(dl));
        let y1 = log2(dl.mul(inv_u))
            .mul(V::splat(self.q))
            .max(V::splat(MIN_EXP));
        let (l, sigma) = log2_1p_sigma(exp2(y1));
        let y2 = l.mul(V::splat(self.minus_two_over_q));
        let under = y2.lt(V::splat(MIN_EXP));
        let v2 = under.select(zero, exp2(y2.max(V::splat(MIN_EXP))));
        // Equal (or subnormally close) coordinates: h = 0, and log₂ 0 is not defined.
        let coincide = dl.lt(V::splat(f64::MIN_POSITIVE));
        let h2 = coincide.select(zero, dl.mul(dl).mul(v2));
        (coincide, inv_u, sigma, v2, h2)
    }
}

impl VecKernel for VecQ {
    const PERIODIC: bool = true;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        self.parts(d).4
    }

    /// The same operations as [`VecQ::parts`], in passes over the buffers: δ row by row,
    /// then three flat loops over all s·bs entries. Each pass is a short chain, so the
    /// processor overlaps many iterations of it, where one chain through log₂, 2^y, log₂
    /// and 2^y (~250 cycles of latency) would leave it waiting. The passes cover the whole
    /// block, padding and the diagonal tile's lower part included (unused, finite), so that
    /// the loops are flat.
    #[inline(always)]
    fn rows<V: Simd, const GRAD: bool>(&self, r: &mut Rows<'_>) {
        let one = V::splat(1.0);
        let zero = V::splat(0.0);
        let n = V::N;
        let len = r.s * r.bs;
        // δ into `force` (overwritten by h·h' in the last pass).
        for k in 0..r.s {
            let xi = V::splat(r.xi[k]);
            let row = k * r.bs..(k + 1) * r.bs;
            for (xj, f) in r.xb[row.clone()]
                .chunks_exact(n)
                .zip(r.force[row].chunks_exact_mut(n))
            {
                diff::<Self, V>(xi, V::load(xj)).store(f);
            }
        }
        // 1/(1 − Δ) into `tmp2`, y₁ = q·log₂(Δ/(1 − Δ)) into `tmp1`.
        for ((d, t1), t2) in r.force[..len]
            .chunks_exact(n)
            .zip(r.tmp1[..len].chunks_exact_mut(n))
            .zip(r.tmp2[..len].chunks_exact_mut(n))
        {
            let dl = V::load(d).abs();
            let inv_u = one.div(one.sub(dl));
            let y1 = log2(dl.mul(inv_u))
                .mul(V::splat(self.q))
                .max(V::splat(MIN_EXP));
            inv_u.store(t2);
            y1.store(t1);
        }
        // t = 2^{y₁}; σ = t/(1 + t) into `tmp1`, y₂ = −(2/q)·log₂(1 + t) into `h2`.
        for (t1, h2) in r.tmp1[..len]
            .chunks_exact_mut(n)
            .zip(r.h2[..len].chunks_exact_mut(n))
        {
            let (l, sigma) = log2_1p_sigma(exp2(V::load(t1)));
            sigma.store(t1);
            l.mul(V::splat(self.minus_two_over_q)).store(h2);
        }
        // v² = 2^{y₂}, h² and h·h'.
        for (((h2, f), t1), t2) in r.h2[..len]
            .chunks_exact_mut(n)
            .zip(r.force[..len].chunks_exact_mut(n))
            .zip(r.tmp1[..len].chunks_exact(n))
            .zip(r.tmp2[..len].chunks_exact(n))
        {
            let y2 = V::load(h2);
            let d = V::load(f);
            let dl = d.abs();
            let under = y2.lt(V::splat(MIN_EXP));
            let v2 = under.select(zero, exp2(y2.max(V::splat(MIN_EXP))));
            let coincide = dl.lt(V::splat(f64::MIN_POSITIVE));
            coincide.select(zero, dl.mul(dl).mul(v2)).store(h2);
            if GRAD {
                let sigma = V::load(t1);
                let inv_u = V::load(t2);
                let a = d.mul(v2).mul(one.sub(sigma.mul(inv_u)));
                coincide.select(zero, a).store(f);
            }
        }
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        let one = V::splat(1.0);
        let (coincide, inv_u, sigma, v2, h2) = self.parts(d);
        // h·h' = Δ v² (1 − σ/(1 − Δ)), σ = t/(1 + t); the sign comes with δ.
        let a = d.mul(v2).mul(one.sub(sigma.mul(inv_u)));
        (h2, coincide.select(V::splat(0.0), a))
    }
}

/// The general-q kernel of [`Precision::Fast`]: v² = h²/Δ² as cubics on a table of
/// intervals, evaluated in f64, and h·h' = ½ d(h²)/dΔ from the same cubic, so the forces are
/// the exact gradient of the energy the table defines. The intervals follow the bits of Δ:
/// each binade [2^e, 2^{e+1}), e = −24 … −1, is cut into 64 equal parts, so an interval's
/// index is the exponent and the top 6 mantissa bits of Δ, its local variable the remaining
/// bits, and no interval comes closer to the singularity of t = Δ^q·… at 0 than 128
/// half-widths. Δ below 2^{−24} (other than 0) is recomputed with the f64 formulas.
#[derive(Clone, Copy)]
struct VecQFast<'a> {
    full: VecQ,
    table: &'a FastTable,
}

/// Smallest Δ in the table (2^{−24}).
const FAST_LO: f64 = 5.960464477539063e-8;
/// Binades in the table: 2^{−24} … 2^{−1}.
const FAST_BINADES: usize = 24;
/// log₂ of the intervals per binade (the top 6 mantissa bits).
const FAST_BITS: u32 = 6;
/// Intervals per binade.
const FAST_SPLIT: usize = 1 << FAST_BITS;

/// The interpolation table of [`Precision::Fast`] for one q.
#[derive(Clone, PartialEq)]
pub(crate) struct FastTable {
    q: f64,
    /// The f64 formulas, for the table's nodes and for Δ below its range.
    kern: Kernel,
    /// Per interval, the monomial coefficients of v² in the local variable x ∈ [−1, 1);
    /// padded to 2048 rows so that an index masked to 11 bits is in range.
    rows: Box<FastRows>,
}

/// The rows of a [`FastTable`], aligned to cache lines so that no 32-byte row straddles
/// two of them.
#[derive(Clone, PartialEq)]
#[repr(C, align(64))]
struct FastRows([[f64; 4]; 2048]);

impl std::fmt::Debug for FastTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FastTable {{ q: {} }}", self.q)
    }
}

impl FastTable {
    /// Interpolates v² at the four Chebyshev points of each interval, with the f64
    /// formulas of eq. 11 (`powf`).
    pub(crate) fn new(q: f64) -> Self {
        let kern = Kernel::Q { q, inv_q: 1.0 / q };
        let nodes: [f64; 4] =
            std::array::from_fn(|k| (std::f64::consts::PI * (k as f64 + 0.5) / 4.0).cos());
        let mut rows = Box::new(FastRows([[0.0; 4]; 2048]));
        for b in 0..FAST_BINADES {
            let base = FAST_LO * (1u64 << b) as f64;
            let width = base / FAST_SPLIT as f64;
            for j in 0..FAST_SPLIT {
                let (mid, half) = (base + width * (j as f64 + 0.5), 0.5 * width);
                let f: [f64; 4] = std::array::from_fn(|k| {
                    let d = mid + half * nodes[k];
                    kern.eval(d).0 / (d * d)
                });
                rows.0[b * FAST_SPLIT + j] = cheb_to_monomial(&f, &nodes);
            }
        }
        FastTable { q, kern, rows }
    }
}

/// The cubic through (x_k, f_k) at the four Chebyshev points, as monomial coefficients:
/// Chebyshev coefficients c_j = (2/4) Σ_k f_k T_j(x_k) (c₀ halved), then T₂ = 2x² − 1 and
/// T₃ = 4x³ − 3x.
fn cheb_to_monomial(f: &[f64; 4], x: &[f64; 4]) -> [f64; 4] {
    let mut c = [0.0; 4];
    for (&fk, &xk) in f.iter().zip(x) {
        let t = [1.0, xk, 2.0 * xk * xk - 1.0, 4.0 * xk * xk * xk - 3.0 * xk];
        for j in 0..4 {
            c[j] += 0.5 * fk * t[j];
        }
    }
    c[0] *= 0.5;
    [c[0] - c[2], c[1] - 3.0 * c[3], 2.0 * c[2], 4.0 * c[3]]
}

impl VecKernel for VecQFast<'_> {
    const PERIODIC: bool = true;
    #[inline(always)]
    fn h2<V: Simd>(&self, d: V) -> V {
        self.full.h2(d)
    }
    #[inline(always)]
    fn h2_grad<V: Simd>(&self, d: V) -> (V, V) {
        self.full.h2_grad(d)
    }

    /// One pass: δ, the interval index and local variable from the bits of Δ, the two
    /// rows of each lane's interval, two cubics.
    #[inline(always)]
    fn rows<W: Simd, const GRAD: bool>(&self, r: &mut Rows<'_>) {
        type V<W> = W;
        let n = V::<W>::N;
        let zero = V::<W>::splat(0.0);
        // (bits of Δ) >> 46 is (biased exponent)·64 + top 6 mantissa bits.
        let base = V::<W>::splat(f64::from_bits(
            (((1023 - FAST_BINADES as u64) * FAST_SPLIT as u64) as i64).wrapping_neg() as u64,
        ));
        let low = V::<W>::splat(f64::from_bits((1u64 << (52 - FAST_BITS)) - 1));
        let mant = V::<W>::splat(f64::from_bits((1u64 << 52) - 1));
        let one = V::<W>::splat(1.0);
        let scale = V::<W>::splat(2.0 * FAST_SPLIT as f64);
        let shift = V::<W>::splat(-(2.0 * FAST_SPLIT as f64 + 1.0));
        let half_scale = V::<W>::splat(FAST_SPLIT as f64);
        let mut small = zero;
        let mut idx = [0.0f64; MAX_LANES];
        let rows = &self.table.rows.0;
        for k in 0..r.s {
            let xi = V::<W>::splat(r.xi[k]);
            let row = k * r.bs..(k + 1) * r.bs;
            for ((xj, h2), f) in r.xb[row.clone()]
                .chunks_exact(n)
                .zip(r.h2[row.clone()].chunks_exact_mut(n))
                .zip(r.force[row].chunks_exact_mut(n))
            {
                let d = diff::<Self, V<W>>(xi, V::<W>::load(xj));
                let dl = d.abs();
                // In 0 … 1535 for Δ ∈ [2^{−24}, ½]; `rows4` masks it to the table. Smaller Δ
                // (0 included) make it negative: its sign bit flags the row for `tiny_rows`,
                // which redoes them (Δ = 0 gives 0 on either path).
                let i = dl.shr46().add_bits(base);
                small = small.or(i);
                i.store(&mut idx);
                // x ∈ [−1, 1): the mantissa bits below the top 6, scaled (exact).
                let x = dl.and(low).or(one).mul_add(scale, shift);
                let [p0, p1, p2, p3] = V::<W>::rows4(rows, &idx);
                // The cubic and its derivative in one Horner pass.
                let b = p3.mul_add(x, p2);
                let db = b.add(p3.mul(x));
                let b = b.mul_add(x, p1);
                let dv = db.mul_add(x, b);
                let v2 = b.mul_add(x, p0);
                dl.mul(dl).mul(v2).store(h2);
                if GRAD {
                    // h·h'/Δ = v² + ½Δ·dv²/dΔ, and ½Δ·dx/dΔ = 64·m with m the mantissa
                    // of Δ in [1, 2).
                    let m = dl.and(mant).or(one);
                    d.mul(m.mul(half_scale).mul_add(dv, v2)).store(f);
                }
            }
        }
        if small.select(one, zero).hsum() > 0.0 {
            self.tiny_rows::<GRAD>(r);
        }
    }
}

/// Most lanes of the vectors the kernels use.
const MAX_LANES: usize = 16;

impl VecQFast<'_> {
    /// The differences in (0, [`FAST_LO`]) with the f64 formulas, recomputing δ as
    /// [`diff`] does.
    #[cold]
    fn tiny_rows<const GRAD: bool>(&self, r: &mut Rows<'_>) {
        let kern = self.table.kern;
        for k in 0..r.s {
            for j in 0..r.bs {
                let at = k * r.bs + j;
                let d = r.xi[k] - r.xb[at];
                let d = d - ((d + MAGIC) - MAGIC);
                if d != 0.0 && d.abs() < FAST_LO {
                    let (h2, a) = kern.eval(d);
                    r.h2[at] = h2;
                    if GRAD {
                        r.force[at] = a;
                    }
                }
            }
        }
    }
}

/// log₂ m = f·P(f²) with f = (m − 1)/(m + 1), |f| ≤ (√2 − 1)/(√2 + 1): P, lowest degree
/// first, is the degree-6 Chebyshev fit of (2/ln 2)·atanh(f)/f in f² ∈ [0, 0.02944]
/// (computed with 50-digit arithmetic; its error is below 1.8e-16 relative, checked on
/// 20 001 points). The series (2/ln 2)·Σ f^{2k}/(2k + 1) needs degree 8 for the same.
#[allow(clippy::excessive_precision)]
const LOG2_POLY: [f64; 7] = [
    2.885390081777927,
    0.9617966939243345,
    0.5770780172463286,
    0.4121984020482752,
    0.32061638813224547,
    0.2614442493522915,
    0.2429160853987535,
];

/// 2^r for r ∈ [−½, ½]: the degree-10 Chebyshev fit, lowest degree first (error below
/// 3.0e-16 relative, checked like [`LOG2_POLY`]); Taylor would need degree 12.
// The fitted coefficients, not rounded constants (the linear one is close to ln 2).
#[allow(clippy::excessive_precision, clippy::approx_constant)]
const EXP2_POLY: [f64; 11] = [
    1.0,
    0.69314718055995,
    0.24022650695910097,
    0.05550410866444772,
    0.009618129107606888,
    0.0013333558230164974,
    0.0001540353044173605,
    1.5252657260200837e-05,
    1.321544258792169e-06,
    1.0208690299958306e-07,
    7.072585949269223e-09,
];

/// f·P(f²), Horner in f².
#[inline(always)]
fn log2_series<V: Simd>(f: V) -> V {
    let z = f.mul(f);
    let mut p = V::splat(LOG2_POLY[6]);
    for &c in LOG2_POLY[..6].iter().rev() {
        p = p.mul_add(z, V::splat(c));
    }
    f.mul(p)
}

/// log₂ x for positive normal x (0 gives −1023; callers mask it).
#[inline(always)]
fn log2<V: Simd>(x: V) -> V {
    let one = V::splat(1.0);
    // x = 2^e·m with m ∈ [1, 2): the mantissa bits with the exponent of 1.0, and the
    // biased exponent read as an integer by planting it in the mantissa of 2^52.
    let m = x.and(V::splat(f64::from_bits((1 << 52) - 1))).or(one);
    let two52 = V::splat(f64::from_bits(0x4330_0000_0000_0000));
    let e = x.shr52().or(two52).sub(V::splat(4_503_599_627_371_519.0)); // 2^52 + 1023
                                                                        // Move m into [1/√2, √2] so that |f| ≤ 0.1716.
    let big = m.gt(V::splat(SQRT_2));
    let m = big.select(m.mul(V::splat(0.5)), m);
    let e = e.add(big.and(one));
    let f = m.sub(one).div(m.add(one));
    e.add(log2_series(f))
}

/// (log₂(1 + t), t/(1 + t)) for t ∈ [0, 1], without rounding 1 + t: f = t/(t + 2) is
/// (m − 1)/(m + 1) for m = 1 + t, and above t = √2 − 1 the mantissa is halved,
/// f = (t − 1)/(t + 3). Both quotients come from one division, 1/((t + 2 + c)(1 + t)).
#[inline(always)]
fn log2_1p_sigma<V: Simd>(t: V) -> (V, V) {
    let one = V::splat(1.0);
    let big = t.gt(V::splat(SQRT_2_M1)).and(one);
    let den = t.add(V::splat(2.0).add(big));
    let one_t = one.add(t);
    let r = one.div(den.mul(one_t));
    let f = t.sub(big).mul(one_t.mul(r));
    (big.add(log2_series(f)), t.mul(den.mul(r)))
}

/// 2^y for y ∈ [−1022, 1023]: 2^n by writing n + 1023 into the exponent field, times
/// [`EXP2_POLY`] at r = y − n ∈ [−½, ½].
#[inline(always)]
fn exp2<V: Simd>(y: V) -> V {
    // Adding 1.5·2^52 rounds y to an integer n (ties to even) held in the low mantissa
    // bits; subtracting it again gives n exactly.
    let magic = V::splat(MAGIC);
    let k = y.add(magic);
    let r = y.sub(k.sub(magic));
    let mut p = V::splat(EXP2_POLY[10]);
    for &c in EXP2_POLY[..10].iter().rev() {
        p = p.mul_add(r, V::splat(c));
    }
    let scale = k.add_bits(V::splat(f64::from_bits(1023))).shl52();
    p.mul(scale)
}

/// d^{−p} from d² per pair: +∞ for d² below 2^{−1022} (coincident points).
#[derive(Clone, Copy)]
pub(crate) enum PairPow {
    /// p = 1: 1/√d².
    InvSqrt,
    /// 2^{(−p/2)·log₂ d²}.
    General(f64),
}

impl PairPow {
    pub(crate) fn new(p: f64) -> Self {
        if p == 1.0 {
            PairPow::InvSqrt
        } else {
            PairPow::General(-0.5 * p)
        }
    }

    #[inline(always)]
    pub(crate) fn eval<V: Simd>(self, d2: V) -> V {
        let inf = V::splat(f64::INFINITY);
        let tiny = d2.lt(V::splat(f64::MIN_POSITIVE));
        let e = match self {
            PairPow::InvSqrt => V::splat(1.0).div(d2.sqrt()),
            PairPow::General(minus_half_p) => {
                let y = log2(d2).mul(V::splat(minus_half_p));
                let e = exp2(y.max(V::splat(MIN_EXP)).min(V::splat(1023.0)));
                let e = y.lt(V::splat(MIN_EXP)).select(V::splat(0.0), e);
                y.gt(V::splat(1023.0)).select(inf, e)
            }
        };
        tiny.select(inf, e)
    }
}

/// The pair loop of U_{q,p} over block-transposed coordinates (reduced to [0, 1) for the
/// periodic distances, whose h has period 1).
struct UqpTiles<K> {
    blocks: Blocks,
    xt: AlignedBuf,
    kern: K,
    pow: PairPow,
}

impl<K: VecKernel> UqpTiles<K> {
    fn new(points: &PointSet, kern: K, p: f64) -> Self {
        let blocks = Blocks::new(points.n(), points.s());
        let xt = if K::PERIODIC {
            blocks.transpose(points.as_slice(), |v| v - v.floor())
        } else {
            blocks.transpose(points.as_slice(), |v| v)
        };
        UqpTiles {
            blocks,
            xt,
            kern,
            pow: PairPow::new(p),
        }
    }
}

impl<K: VecKernel> UqpTiles<K> {
    /// The pairs between blocks a and b: returns Σ d^{−p} and, when `GRAD`, adds
    /// ±(d^{−p}/d²)·h·h' to the rows of `ga` (row i) and of `gb` (row j; `ga` on the
    /// diagonal). Each point i runs the kernel passes against all its partners j in the
    /// block at once, then sums d² per pair, then scatters the forces.
    #[inline(always)]
    fn tile_impl<V: Simd, const GRAD: bool>(
        &self,
        a: usize,
        b: usize,
        ga: &mut [f64],
        mut gb: Option<&mut [f64]>,
    ) -> f64 {
        let bl = &self.blocks;
        let (bs, s) = (bl.bs, bl.s);
        let (xa, xb) = (bl.chunk(&self.xt, a), bl.chunk(&self.xt, b));
        let len_b = bl.len(b);
        let jhi = len_b.next_multiple_of(V::N);
        let zero = V::splat(0.0);
        let len = 4 * s * bs + bs + s;
        let mut buf = take_scratch(len);
        let (h2, rest) = buf[..len].split_at_mut(s * bs);
        let (force, rest) = rest.split_at_mut(s * bs);
        let (tmp1, rest) = rest.split_at_mut(s * bs);
        let (tmp2, rest) = rest.split_at_mut(s * bs);
        let (w, xi) = rest.split_at_mut(bs);
        let mut total = zero;
        for ii in 0..bl.len(a) {
            let lo = if a == b { ii + 1 } else { 0 };
            let jlo = lo / V::N * V::N;
            if lo >= len_b {
                continue;
            }
            for (k, v) in xi.iter_mut().enumerate() {
                *v = xa[k * bs + ii];
            }
            let mut rows = Rows {
                s,
                bs,
                jlo,
                jhi,
                xi,
                xb,
                h2: &mut *h2,
                force: &mut *force,
                tmp1: &mut *tmp1,
                tmp2: &mut *tmp2,
            };
            self.kern.rows::<V, GRAD>(&mut rows);
            for j in (jlo..jhi).step_by(V::N) {
                let mut d2 = zero;
                for k in 0..s {
                    d2 = d2.add(V::load(&h2[k * bs + j..]));
                }
                let mask = if j >= lo && j + V::N <= len_b {
                    V::TRUE
                } else {
                    V::from_fn(|l| {
                        let jl = j + l;
                        f64::from_bits(if jl >= lo && jl < len_b { u64::MAX } else { 0 })
                    })
                };
                let e = self.pow.eval(d2);
                total = total.add(mask.select(e, zero));
                if GRAD {
                    // d^{−p}/d²; no force between coincident points (the energy is +∞).
                    let wj = mask.and(d2.gt(zero)).select(e.div(d2), zero);
                    wj.store(&mut w[j..]);
                }
            }
            if GRAD {
                for k in 0..s {
                    let mut acc = zero;
                    let gj: &mut [f64] = match &mut gb {
                        Some(g) => g,
                        None => &mut *ga,
                    };
                    for j in (jlo..jhi).step_by(V::N) {
                        let at = k * bs + j;
                        let f = V::load(&w[j..]).mul(V::load(&force[at..]));
                        acc = acc.add(f);
                        let g = &mut gj[at..];
                        V::load(g).sub(f).store(g);
                    }
                    ga[k * bs + ii] += acc.hsum();
                }
            }
        }
        give_scratch(buf);
        total.hsum()
    }
}

impl<K: VecKernel> SumTiles for UqpTiles<K> {
    type Out = f64;

    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize) -> f64 {
        self.tile_impl::<V, false>(a, b, &mut [], None)
    }
}

impl<K: VecKernel> GradTiles for UqpTiles<K> {
    #[inline(always)]
    fn tile<V: Simd>(&self, a: usize, b: usize, ga: &mut [f64], gb: Option<&mut [f64]>) -> f64 {
        self.tile_impl::<V, true>(a, b, ga, gb)
    }
}

/// (q, p) from the paper's regression (eq. 48, Table 4), with what happened to them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperQp {
    /// q to use, clamped to [`PaperQp::MIN`], 1].
    pub q: f64,
    /// p to use, clamped to [`PaperQp::MIN`], 1].
    pub p: f64,
    /// q as the regression gives it.
    pub raw_q: f64,
    /// p as the regression gives it.
    pub raw_p: f64,
    /// Whether (n, s) lies in the fitted range 1 ≤ s ≤ 20, s ≤ n ≤ 1500.
    pub in_fitted_range: bool,
}

impl PaperQp {
    /// Lower clamp for q and p. The fit was made with q, p ∈ (0, 1]; outside its range the
    /// quadratic can go negative, and very small q or p make the energy's scale overflow.
    pub const MIN: f64 = 0.05;
}

/// Eq. 48: p = α·(1, n, s, n², ns, s²), q = β·(…) with Table 4's coefficients (α for p,
/// β for q). Outside 1 ≤ s ≤ 20, s ≤ n ≤ 1500 the fit is an extrapolation: it is still
/// evaluated, flagged, and clamped to [0.05, 1].
// The coefficients are kept digit for digit as Table 4 prints them.
#[allow(clippy::excessive_precision)]
pub fn paper_qp(n: usize, s: usize) -> PaperQp {
    const ALPHA: [f64; 6] = [
        0.0503965655930105,
        0.0009192090929939,
        -0.0034365336368717,
        -0.0000002204260424,
        -0.0000308280100528,
        0.0022834280933421,
    ];
    const BETA: [f64; 6] = [
        0.1732384430740160,
        -0.0003419881219659,
        0.0046060707097167,
        0.0000001517932891,
        0.0000140768595897,
        0.0004673041886360,
    ];
    let (nf, sf) = (n as f64, s as f64);
    let basis = [1.0, nf, sf, nf * nf, nf * sf, sf * sf];
    let dot = |c: &[f64; 6]| c.iter().zip(&basis).map(|(a, b)| a * b).sum::<f64>();
    let raw_p = dot(&ALPHA);
    let raw_q = dot(&BETA);
    let clamp = |v: f64| v.clamp(PaperQp::MIN, 1.0);
    PaperQp {
        q: clamp(raw_q),
        p: clamp(raw_p),
        raw_q,
        raw_p,
        in_fitted_range: (1..=20).contains(&s) && n >= s && n <= 1500,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_q() {
        assert_eq!(Distance::parse("E").unwrap(), Distance::Euclidean);
        assert_eq!(Distance::parse("inf").unwrap(), Distance::Torus);
        assert_eq!(Distance::parse("0.5").unwrap(), Distance::Q(0.5));
        for bad in ["0", "-1", "nan", "x", ""] {
            let e = Distance::parse(bad).unwrap_err().to_string();
            assert!(e.contains("q") && e.contains("(0, ∞)"), "{e}");
        }
        assert!(Uqp::new(Distance::Torus, 0.0).is_err());
        assert!(Uqp::new(Distance::Torus, f64::INFINITY).is_err());
        assert!(Uqp::new(Distance::Q(-1.0), 1.0).is_err());
    }

    #[test]
    fn q_distance_limits() {
        // q → ∞ approaches the torus distance; q = 1 is Δ(1 − Δ); eq. 11's two forms agree.
        let a = [0.1, 0.8];
        let b = [0.35, 0.05];
        let torus = Distance::Torus.squared(&a, &b);
        let big = Distance::Q(400.0).squared(&a, &b);
        assert!((big - torus).abs() < 1e-3 * torus, "{big} vs {torus}");
        let q1 = Distance::Q(1.0).squared(&a, &b);
        let want: f64 = a
            .iter()
            .zip(&b)
            .map(|(x, y)| {
                let d = (x - y).abs();
                (d * (1.0 - d)).powi(2)
            })
            .sum();
        assert!((q1 - want).abs() < 1e-15);
        for q in [0.3, 1.7, 2.0] {
            let got = Distance::Q(q).squared(&a, &b);
            // First form of eq. 11: 1 / (Δ^{-q} + (1 − Δ)^{-q})^{2/q}.
            let want: f64 = a
                .iter()
                .zip(&b)
                .map(|(x, y)| {
                    let d: f64 = (x - y).abs();
                    (1.0 / (d.powf(-q) + (1.0 - d).powf(-q))).powf(2.0 / q)
                })
                .sum();
            assert!((got - want).abs() < 1e-13 * want, "q={q}: {got} vs {want}");
        }
    }

    #[test]
    fn paper_qp_matches_table4_fit() {
        let f = paper_qp(1500, 2);
        assert!(f.in_fitted_range);
        // Hand evaluation of eq. 48 at (1500, 2).
        assert!((f.raw_p - 0.843028).abs() < 1e-5, "{}", f.raw_p);
        assert!((f.raw_q - 0.055103).abs() < 1e-5, "{}", f.raw_q);
        let out = paper_qp(20_000, 2);
        assert!(!out.in_fitted_range);
        assert!(out.p >= PaperQp::MIN && out.p <= 1.0 && out.q >= PaperQp::MIN && out.q <= 1.0);
        assert!(!paper_qp(10, 21).in_fitted_range);
    }
}
