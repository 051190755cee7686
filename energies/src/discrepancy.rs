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
//!
//! where a = |x − ½| and d = |x − y|.
//!
//! The value is the *square* of the discrepancy: the closed forms give the square, and
//! its gradient needs no division by the root, which vanishes for a perfect set. It equals
//! the square of the matching metric of the root crate to rounding. Unlike the metric it
//! is not clamped at 0: a clamp would make the value disagree with the gradient for
//! nearly perfect sets.
//!
//! **Gradient.**
//!
//! ∂D²/∂x_ik = −(2/n) g'(x_ik) Π_{m≠k} g(x_im)
//!             + (2/n²) Σ_{l≠i} ∂₁K(x_ik, x_lk) Π_{m≠k} K(x_im, x_lm)
//!             + (1/n²) d/dx_ik Π_m K(x_im, x_im):
//!
//! each unordered pair appears twice in Σ_{i,l}, and the diagonal terms i = l are not
//! constant (K(x, x) = 1 − x for the star L2). For a pair, Π_{m≠k} K_m is the pair's
//! product divided by K_k when that product is a normal nonzero number (then no factor is
//! 0, and the divisions vectorise); otherwise (the star L2's factor 1 − max is 0 when a
//! coordinate is 1, or the product underflowed) it comes from prefix and suffix products,
//! with no division. The per-point terms always use prefix and suffix products.
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
//! **Determinism and cost.** The pair sum runs through
//! [`for_each_pair_tile`], the per-point terms in index order, so value and gradient have
//! the same bits for any number of rayon threads, and [`Energy::value`] sums in the same
//! order as [`Energy::value_and_gradient`]. O(n² s) time, O(n s) memory; the pair loop does
//! not allocate (its scratch lives on the stack for s ≤ 64, in one buffer per tile above).
//! The value-only path skips the derivatives and costs about a third of the gradient.

use crate::pairs::for_each_pair_tile;
use crate::{Energy, Error, PointSet, Result};

/// Which L2 discrepancy an energy squares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscrepancyKind {
    /// Star L2 (Warnock, the paper's eq. 46): boxes anchored at the origin.
    StarL2,
    /// Modified L2 (Hickernell, the paper's eq. 47): the star L2 of every projection.
    ModifiedL2,
    /// Centred L2 (Hickernell): boxes anchored at the nearest corner.
    CenteredL2,
    /// Wrap-around L2 (Hickernell): boxes wrap around the faces; periodic.
    WrapAroundL2,
}

/// The names [`DiscrepancyKind::parse`] accepts, as an error message lists them.
const ACCEPTED: &str = "one of `l2star` (star L2), `md` (modified L2), `cd` (centred L2), \
                        `periodic` or `wd` (wrap-around L2)";

impl DiscrepancyKind {
    /// Parses the name the CLI's `--energy` takes: `l2star`, `md`, `cd`, `periodic` or
    /// its alias `wd` (ASCII case and surrounding spaces ignored).
    pub fn parse(name: &str) -> Result<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "l2star" => Ok(DiscrepancyKind::StarL2),
            "md" => Ok(DiscrepancyKind::ModifiedL2),
            "cd" => Ok(DiscrepancyKind::CenteredL2),
            "periodic" | "wd" => Ok(DiscrepancyKind::WrapAroundL2),
            _ => Err(Error::invalid("--energy", format!("`{name}`"), ACCEPTED)),
        }
    }

    /// The CLI name, the one [`DiscrepancyKind::parse`] maps back to this kind.
    pub fn label(&self) -> &'static str {
        match self {
            DiscrepancyKind::StarL2 => "l2star",
            DiscrepancyKind::ModifiedL2 => "md",
            DiscrepancyKind::CenteredL2 => "cd",
            DiscrepancyKind::WrapAroundL2 => "periodic",
        }
    }

    /// Whether the discrepancy is unchanged by a periodic shift x → (x + c) mod 1 of the
    /// whole set: only the wrap-around L2. The others must be minimised in the closed
    /// cube, not on the torus.
    pub fn is_periodic(&self) -> bool {
        matches!(self, DiscrepancyKind::WrapAroundL2)
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
        match self.kind {
            DiscrepancyKind::StarL2 => "D²_L2 (squared star L2)",
            DiscrepancyKind::ModifiedL2 => "D²_MD (squared modified L2)",
            DiscrepancyKind::CenteredL2 => "D²_CD (squared centred L2)",
            DiscrepancyKind::WrapAroundL2 => "D²_WD (squared wrap-around L2)",
        }
        .to_string()
    }

    fn value(&self, points: &PointSet) -> f64 {
        dispatch(self.kind, points, None)
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        assert_eq!(grad.len(), points.len(), "gradient buffer length");
        dispatch(self.kind, points, Some(grad))
    }

    fn is_smooth(&self) -> bool {
        false
    }
}

fn dispatch(kind: DiscrepancyKind, points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
    // One monomorphised copy per kind, so the 1-D factors inline into the pair loop.
    match kind {
        DiscrepancyKind::StarL2 => evaluate::<Star>(points, grad),
        DiscrepancyKind::ModifiedL2 => evaluate::<Modified>(points, grad),
        DiscrepancyKind::CenteredL2 => evaluate::<Centered>(points, grad),
        DiscrepancyKind::WrapAroundL2 => evaluate::<Wrap>(points, grad),
    }
}

/// The one-dimensional factors of a discrepancy's closed form.
trait Kernel {
    /// Per-coordinate factor of |C_s| = CONSTANT_BASE^s.
    const CONSTANT_BASE: f64;
    /// Sign of C_s (negative for the wrap-around L2).
    const CONSTANT_SIGN: f64;
    /// Whether the closed form has the middle term −(2/n) Σ_i Π_k g(x_ik).
    const HAS_SINGLE: bool;

    /// g(x) and g'(x) (with the averaged one-sided derivative at a kink).
    fn single(x: f64) -> (f64, f64);

    /// K(x, y), ∂K/∂x and ∂K/∂y (averaged one-sided derivatives at a kink). The value must
    /// be the same expression as the root crate's metric so that the two agree closely.
    fn pair(x: f64, y: f64) -> (f64, f64, f64);
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

struct Star;
struct Modified;
struct Centered;
struct Wrap;

impl Kernel for Star {
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

impl Kernel for Modified {
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

impl Kernel for Centered {
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

impl Kernel for Wrap {
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

/// Pairs handled together: each pair's value is a chain of s dependent multiplications,
/// so a lone pair waits on multiplier latency; interleaving independent pairs fills the
/// pipeline. Each pair still multiplies its factors in coordinate order and every sum
/// still runs in j order, so the bits do not depend on it.
const LANES: usize = 4;

/// Largest s whose pair scratch lives on the stack.
const STACK_S: usize = 64;

/// Scratch rows of length s per call of [`pair_terms`]: factors, ∂₁ and ∂₂ for each
/// lane, and one row of prefix products.
const SCRATCH: usize = 3 * LANES + 1;

/// D² of the set, and its gradient into `grad` when given.
fn evaluate<K: Kernel>(points: &PointSet, grad: Option<&mut [f64]>) -> f64 {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let nf = n as f64;
    let constant = K::CONSTANT_SIGN * (0..s).fold(1.0, |p, _| p * K::CONSTANT_BASE);

    match grad {
        None => {
            // The tiles depend on n only, so a one-column dummy buffer gives the same
            // summation order as the gradient path and the same bits for the value.
            let mut dummy = vec![0.0; n];
            let off = for_each_pair_tile(n, 1, &mut dummy, |ri, rj, _, gj| {
                let diag = gj.is_empty();
                let mut acc = 0.0;
                for i in ri.clone() {
                    let xi = &x[i * s..(i + 1) * s];
                    let js = if diag { i + 1..ri.end } else { rj.clone() };
                    let mut j = js.start;
                    while j + LANES <= js.end {
                        for p in pair_values::<K, LANES>(xi, &x[j * s..(j + LANES) * s]) {
                            acc += p;
                        }
                        j += LANES;
                    }
                    for j in j..js.end {
                        acc += pair_values::<K, 1>(xi, &x[j * s..(j + 1) * s])[0];
                    }
                }
                acc
            });
            let (mut single, mut diag) = (0.0, 0.0);
            for xi in points.rows() {
                if K::HAS_SINGLE {
                    single += xi.iter().fold(1.0, |p, &a| p * K::single(a).0);
                }
                diag += xi.iter().fold(1.0, |p, &a| p * K::pair(a, a).0);
            }
            assemble(constant, single, diag, off, nf)
        }
        Some(grad) => {
            grad.fill(0.0);
            // Raw Σ_{l≠i, unordered} ∂₁K Π_{m≠k} K into every row; scaled below.
            let off = for_each_pair_tile(n, s, grad, |ri, rj, gi, gj| {
                let mut stack = [0.0; SCRATCH * STACK_S];
                let mut heap = Vec::new();
                let scratch: &mut [f64] = if s <= STACK_S {
                    &mut stack[..SCRATCH * s]
                } else {
                    heap.resize(SCRATCH * s, 0.0);
                    &mut heap
                };
                let diag = gj.is_empty();
                let mut acc = 0.0;
                for i in ri.clone() {
                    let xi = &x[i * s..(i + 1) * s];
                    let js = if diag { i + 1..ri.end } else { rj.clone() };
                    // Row j's position: in `gi` for a diagonal tile, in `gj` otherwise.
                    let (oi, jb) = ((i - ri.start) * s, if diag { ri.start } else { rj.start });
                    let mut j = js.start;
                    while j + LANES <= js.end {
                        let (g_i, g_j) = grad_rows(gi, gj, oi, (j - jb) * s, LANES * s);
                        let xj = &x[j * s..(j + LANES) * s];
                        for p in pair_terms::<K, LANES>(xi, xj, g_i, g_j, scratch) {
                            acc += p;
                        }
                        j += LANES;
                    }
                    for j in j..js.end {
                        let (g_i, g_j) = grad_rows(gi, gj, oi, (j - jb) * s, s);
                        let xj = &x[j * s..(j + 1) * s];
                        acc += pair_terms::<K, 1>(xi, xj, g_i, g_j, scratch)[0];
                    }
                }
                acc
            });

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
            assemble(constant, single, diag, off, nf)
        }
    }
}

/// Gradient row i (s values at offset `oi` of `gi`) and the `len` values of rows j, … at
/// offset `oj`, as disjoint slices. In a diagonal tile (`gj` empty) both live in `gi`
/// with j > i, so the split goes before row j; otherwise rows j, … are in `gj`.
#[inline(always)]
fn grad_rows<'a>(
    gi: &'a mut [f64],
    gj: &'a mut [f64],
    oi: usize,
    oj: usize,
    len: usize,
) -> (&'a mut [f64], &'a mut [f64]) {
    if gj.is_empty() {
        let (a, b) = gi.split_at_mut(oj);
        (&mut a[oi..], &mut b[..len])
    } else {
        (&mut gi[oi..], &mut gj[oj..oj + len])
    }
}

/// Π_k K(x_ik, x_jk) for the L pairs (i, j), j over the L consecutive rows of `xj`.
#[inline(always)]
fn pair_values<K: Kernel, const L: usize>(xi: &[f64], xj: &[f64]) -> [f64; L] {
    let s = xi.len();
    let xj = &xj[..L * s];
    let mut p = [1.0; L];
    for k in 0..s {
        let a = xi[k];
        for (l, pl) in p.iter_mut().enumerate() {
            *pl *= K::pair(a, xj[l * s + k]).0;
        }
    }
    p
}

/// Π_k K(x_ik, x_jk) for the L pairs (i, j), j over the L consecutive rows of `xj`,
/// adding ∂₁K_k Π_{m≠k} K_m to `gi[k]` and ∂₂K_k Π_{m≠k} K_m to row j of `gj`.
/// `scratch` holds (3·L + 1)·s values. Row i receives the pairs' contributions in j order.
#[inline(always)]
fn pair_terms<K: Kernel, const L: usize>(
    xi: &[f64],
    xj: &[f64],
    gi: &mut [f64],
    gj: &mut [f64],
    scratch: &mut [f64],
) -> [f64; L] {
    let s = xi.len();
    let (xj, gi, gj) = (&xj[..L * s], &mut gi[..s], &mut gj[..L * s]);
    let (f, rest) = scratch.split_at_mut(L * s);
    let (d1, rest) = rest.split_at_mut(L * s);
    let (d2, pre) = rest.split_at_mut(L * s);
    let pre = &mut pre[..s];
    // Factors and their partial derivatives, lane by lane; independent across k, so the
    // loop vectorises.
    for l in 0..L {
        let (xr, fr) = (&xj[l * s..(l + 1) * s], &mut f[l * s..(l + 1) * s]);
        let (ar, br) = (&mut d1[l * s..(l + 1) * s], &mut d2[l * s..(l + 1) * s]);
        for k in 0..s {
            let (kv, a, b) = K::pair(xi[k], xr[k]);
            fr[k] = kv;
            ar[k] = a;
            br[k] = b;
        }
    }
    // The pairs' values, each multiplied in coordinate order like `pair_values`; the
    // lanes interleave so the dependent chains overlap.
    let mut p = [1.0; L];
    for k in 0..s {
        for l in 0..L {
            p[l] *= f[l * s + k];
        }
    }
    for l in 0..L {
        let (fr, ar, br) = (
            &f[l * s..(l + 1) * s],
            &d1[l * s..(l + 1) * s],
            &d2[l * s..(l + 1) * s],
        );
        let gr = &mut gj[l * s..(l + 1) * s];
        if p[l].abs() >= f64::MIN_POSITIVE {
            // No factor is 0 and the product did not underflow: Π_{m≠k} = p / K_k.
            for k in 0..s {
                let w = p[l] / fr[k];
                gi[k] += w * ar[k];
                gr[k] += w * br[k];
            }
        } else {
            // A zero factor (the star L2 at a coordinate equal to 1, where a bounded
            // solver likes to park points) or an underflow: prefix and suffix products.
            let mut acc = 1.0;
            for (pk, &fk) in pre.iter_mut().zip(fr) {
                *pk = acc;
                acc *= fk;
            }
            let mut suf = 1.0;
            for k in (0..s).rev() {
                let w = pre[k] * suf;
                gi[k] += w * ar[k];
                gr[k] += w * br[k];
                suf *= fr[k];
            }
        }
    }
    p
}

/// C − (2/n) Σ g + (1/n²) (Σ_i K(x_i, x_i) + 2 Σ_{i<l} K(x_i, x_l)), as the metric
/// assembles it, but without its clamp at 0 (see the module documentation).
fn assemble(constant: f64, single: f64, diag: f64, off: f64, n: f64) -> f64 {
    constant - 2.0 * single / n + (diag + 2.0 * off) / (n * n)
}
