//! The marginal distributions a design variable may follow, each with its inverse CDF:
//! a design is made uniform in the unit cube, optimised there, and mapped coordinate by
//! coordinate through these quantile functions.

use crate::Error;
use stillpoint_domains::{vector_build, VectorBuild};

/// The smallest probability an unbounded distribution is evaluated at, 2⁻⁵³: a design
/// point on the cube's face (u = 0) must map to a finite value, and 2⁻⁵³ is the gap
/// between 1 and the largest double below it, so `1 - U_MIN` is exact and the two ends
/// are treated alike (Φ⁻¹(2⁻⁵³) ≈ −8.21).
const U_MIN: f64 = f64::EPSILON / 2.0;

/// A truncated normal's interval must hold at least this probability: it keeps u·Z a
/// normal (not subnormal) double for every u ≥ 2⁻⁵³, so the quantile keeps full precision.
const MIN_TRUNC_MASS: f64 = f64::MIN_POSITIVE / U_MIN;

/// A continuous variable's marginal distribution.
#[derive(Debug, Clone, PartialEq)]
pub enum Marginal {
    /// Uniform on [lo, hi].
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// Normal with mean `mu` and standard deviation `sigma`.
    Normal {
        /// Mean.
        mu: f64,
        /// Standard deviation (> 0).
        sigma: f64,
    },
    /// Normal(mu, sigma²) conditioned on [lo, hi]; one end (not both) may be infinite.
    TruncNormal {
        /// Mean of the parent normal.
        mu: f64,
        /// Standard deviation of the parent normal (> 0).
        sigma: f64,
        /// Lower end of the truncation (may be −∞).
        lo: f64,
        /// Upper end of the truncation (may be +∞).
        hi: f64,
    },
    /// The distribution of exp(N(mu, sigma²)) (SciPy's `lognorm(s=sigma, scale=exp(mu))`).
    LogNormal {
        /// Mean of the logarithm.
        mu: f64,
        /// Standard deviation of the logarithm (> 0).
        sigma: f64,
    },
    /// Beta(a, b) scaled from [0, 1] to [lo, hi].
    Beta {
        /// First shape parameter (> 0).
        a: f64,
        /// Second shape parameter (> 0).
        b: f64,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// Triangular on [lo, hi] with its peak at `mode`.
    Triangular {
        /// Lower end.
        lo: f64,
        /// Peak, lo ≤ mode ≤ hi.
        mode: f64,
        /// Upper end.
        hi: f64,
    },
}

impl Marginal {
    /// The quantile function (inverse CDF) at u in [0, 1]; u outside is clamped into it.
    ///
    /// Unbounded ends are reached at u = 2⁻⁵³ and 1 − 2⁻⁵³ instead of 0 and 1, so a design
    /// point on the unit cube's face maps to a finite value (about 8.2 standard deviations
    /// out for a normal).
    pub fn ppf(&self, u: f64) -> f64 {
        if u.is_nan() {
            return f64::NAN;
        }
        let unbounded = u.clamp(U_MIN, 1.0 - U_MIN);
        let u = u.clamp(0.0, 1.0);
        match *self {
            // `min`: lo + (hi − lo)·1 may round past hi.
            Marginal::Uniform { lo, hi } => (lo + (hi - lo) * u).min(hi),
            Marginal::Normal { mu, sigma } => mu + sigma * norm_ppf(unbounded),
            Marginal::TruncNormal { mu, sigma, lo, hi } => {
                // Only an infinite end needs u kept off it; a finite end is reached exactly.
                let u_lo = if lo.is_finite() { 0.0 } else { U_MIN };
                let u_hi = if hi.is_finite() { 1.0 } else { 1.0 - U_MIN };
                let x = trunc_ppf((lo - mu) / sigma, (hi - mu) / sigma, u.clamp(u_lo, u_hi));
                (mu + sigma * x).clamp(lo, hi)
            }
            Marginal::LogNormal { mu, sigma } => (mu + sigma * norm_ppf(unbounded)).exp(),
            Marginal::Beta { a, b, lo, hi } => (lo + (hi - lo) * beta_ppf(a, b, u)).min(hi),
            Marginal::Triangular { lo, mode, hi } => {
                // Closed form; each branch measures from its own end, so values near hi
                // keep their precision instead of being 1 − (something small) rescaled.
                let c = (mode - lo) / (hi - lo);
                let x = if u < c {
                    lo + ((hi - lo) * (mode - lo) * u).sqrt()
                } else {
                    hi - ((hi - lo) * (hi - mode) * (1.0 - u)).sqrt()
                };
                x.clamp(lo, hi)
            }
        }
    }

    /// The cumulative distribution function at x.
    pub fn cdf(&self, x: f64) -> f64 {
        if x.is_nan() {
            return f64::NAN;
        }
        match *self {
            Marginal::Uniform { lo, hi } => ((x - lo) / (hi - lo)).clamp(0.0, 1.0),
            Marginal::Normal { mu, sigma } => norm_cdf((x - mu) / sigma),
            Marginal::TruncNormal { mu, sigma, lo, hi } => {
                if x <= lo {
                    return 0.0;
                }
                if x >= hi {
                    return 1.0;
                }
                trunc_cdf((lo - mu) / sigma, (hi - mu) / sigma, (x - mu) / sigma)
            }
            Marginal::LogNormal { mu, sigma } => {
                if x <= 0.0 {
                    0.0
                } else {
                    norm_cdf((x.ln() - mu) / sigma)
                }
            }
            Marginal::Beta { a, b, lo, hi } => {
                let t = (x - lo) / (hi - lo);
                inc_beta(a, b, t, ln_beta(a, b)).0
            }
            Marginal::Triangular { lo, mode, hi } => {
                if x <= lo {
                    0.0
                } else if x >= hi {
                    1.0
                } else if x < mode {
                    (x - lo) * (x - lo) / ((hi - lo) * (mode - lo))
                } else {
                    1.0 - (hi - x) * (hi - x) / ((hi - lo) * (hi - mode))
                }
            }
        }
    }

    /// The smallest closed interval holding all the mass (ends may be infinite).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Marginal::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Marginal::LogNormal { .. } => (0.0, f64::INFINITY),
            Marginal::Uniform { lo, hi }
            | Marginal::TruncNormal { lo, hi, .. }
            | Marginal::Beta { lo, hi, .. }
            | Marginal::Triangular { lo, hi, .. } => (lo, hi),
        }
    }

    /// Whether both ends of the support are finite.
    pub fn bounded(&self) -> bool {
        let (lo, hi) = self.support();
        lo.is_finite() && hi.is_finite()
    }

    /// The distribution as a user writes it, e.g. `normal(0,1)` or `beta(2,5)`.
    pub fn text(&self) -> String {
        let (f, g) = (num, num);
        match *self {
            Marginal::Uniform { lo, hi } => format!("uniform({},{})", f(lo), g(hi)),
            Marginal::Normal { mu, sigma } => format!("normal({},{})", f(mu), g(sigma)),
            Marginal::TruncNormal { mu, sigma, lo, hi } => {
                format!("truncnormal({},{},{},{})", f(mu), f(sigma), f(lo), f(hi))
            }
            Marginal::LogNormal { mu, sigma } => format!("lognormal({},{})", f(mu), g(sigma)),
            Marginal::Beta { a, b, lo, hi } if lo == 0.0 && hi == 1.0 => {
                format!("beta({},{})", f(a), g(b))
            }
            Marginal::Beta { a, b, lo, hi } => {
                format!("beta({},{},{},{})", f(a), f(b), f(lo), f(hi))
            }
            Marginal::Triangular { lo, mode, hi } => {
                format!("triangular({},{},{})", f(lo), f(mode), f(hi))
            }
        }
    }

    /// The quantile at u from the standard normal quantile z = Φ⁻¹(u) (u kept inside
    /// [2⁻⁵³, 1 − 2⁻⁵³] as [`Marginal::ppf`] keeps it), bit for bit `ppf(u)`, for the laws
    /// that are a map of a normal score; None for the others. Lets a caller that needs
    /// many laws at the same u compute Φ⁻¹ once.
    pub fn from_normal_score(&self, z: f64) -> Option<f64> {
        match *self {
            Marginal::Normal { mu, sigma } => Some(mu + sigma * z),
            Marginal::LogNormal { mu, sigma } => Some((mu + sigma * z).exp()),
            _ => None,
        }
    }

    /// Φ⁻¹ at u as [`Marginal::ppf`] takes it for the normal and lognormal laws (u kept
    /// inside [2⁻⁵³, 1 − 2⁻⁵³]), for [`Marginal::from_normal_score`].
    pub fn normal_score(u: f64) -> f64 {
        norm_ppf(u.clamp(U_MIN, 1.0 - U_MIN))
    }

    /// [`Marginal::ppf`] at each value of `us`, in place, bit for bit. For the normal and
    /// lognormal laws Φ⁻¹'s central region (85 % of uniform values) is computed eight
    /// values at a time: the same operations in the same order, so the same bits.
    pub fn ppf_in_place(&self, us: &mut [f64]) {
        if self.from_normal_score(0.0).is_none() {
            us.iter_mut().for_each(|u| *u = self.ppf(*u));
            return;
        }
        normal_scores(us);
        for u in us.iter_mut() {
            // NaN in gives ppf's NaN out, whatever sign the score's arithmetic left on it.
            *u = match self.from_normal_score(*u) {
                Some(x) if !u.is_nan() => x,
                _ => f64::NAN,
            };
        }
    }

    /// Checks the parameters; `name` is the variable's name for the refusal.
    pub fn check(&self, name: &str) -> Result<(), Error> {
        let refuse = |expected: String| Err(Error::invalid(name, self.text(), expected));
        // A span hi − lo that overflows would turn every quantile into ±∞ or NaN.
        let interval = |lo: f64, hi: f64| lo < hi && (hi - lo).is_finite();
        // The extreme quantiles a design reaches (u = 2⁻⁵³, 1 − 2⁻⁵³) must be finite.
        let ends_finite = || self.ppf(0.0).is_finite() && self.ppf(1.0).is_finite();
        match *self {
            Marginal::Uniform { lo, hi } => {
                if !interval(lo, hi) {
                    return refuse("uniform(lo,hi) with finite lo < hi".into());
                }
            }
            Marginal::Normal { mu, sigma } => {
                if !(mu.is_finite() && sigma.is_finite() && sigma > 0.0) {
                    return refuse("normal(mu,sigma) with sigma > 0 and both finite".into());
                }
                if !ends_finite() {
                    return refuse(
                        "normal(mu,sigma) with mu ± 8.21 sigma finite (the extreme values a \
                         design reaches)"
                            .into(),
                    );
                }
            }
            Marginal::LogNormal { mu, sigma } => {
                if !(mu.is_finite() && sigma.is_finite() && sigma > 0.0) {
                    return refuse("lognormal(mu,sigma) with sigma > 0 and both finite".into());
                }
                if !ends_finite() {
                    return refuse(
                        "lognormal(mu,sigma) with exp(mu + 8.21 sigma) finite (the largest \
                         value a design reaches)"
                            .into(),
                    );
                }
            }
            Marginal::TruncNormal { mu, sigma, lo, hi } => {
                let ends = lo < hi && (lo.is_finite() || hi.is_finite());
                if !(mu.is_finite() && sigma.is_finite() && sigma > 0.0 && ends) {
                    return refuse(
                        "truncnormal(mu,sigma,lo,hi) with sigma > 0, mu and sigma finite, \
                         lo < hi and not both infinite"
                            .into(),
                    );
                }
                let mass = gauss_mass((lo - mu) / sigma, (hi - mu) / sigma);
                if mass < MIN_TRUNC_MASS {
                    return refuse(format!(
                        "truncnormal(mu,sigma,lo,hi) whose interval holds a probability of at \
                         least 2e-292 under normal(mu,sigma) (this one holds {mass:e}: too far \
                         in a tail for double precision)"
                    ));
                }
            }
            Marginal::Beta { a, b, lo, hi } => {
                let shapes = a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0;
                if !(shapes && interval(lo, hi)) {
                    return refuse(
                        "beta(a,b) or beta(a,b,lo,hi) with a, b > 0 finite and finite lo < hi"
                            .into(),
                    );
                }
            }
            Marginal::Triangular { lo, mode, hi } => {
                if !(interval(lo, hi) && lo <= mode && mode <= hi) {
                    return refuse(
                        "triangular(lo,mode,hi) with finite lo ≤ mode ≤ hi and lo < hi".into(),
                    );
                }
            }
        }
        Ok(())
    }
}

/// Wichura's PPND16, Algorithm AS 241 (Applied Statistics 37(3), 1988, 477–484):
/// rational approximations of Φ⁻¹ accurate to about 1 part in 10¹⁶. The coefficients
/// carry all the paper's digits so that they can be checked against it (hence the
/// allowance for more digits than a double holds), lowest degree first; the
/// denominators' constant terms are 1.
#[allow(clippy::excessive_precision)]
mod as241 {
    /// Central region |p − 0.5| ≤ 0.425, in r = 0.425² − (p − 0.5)².
    pub(super) const A: [f64; 8] = [
        3.387_132_872_796_366_608,
        1.331_416_678_917_843_774_5e2,
        1.971_590_950_306_551_442_7e3,
        1.373_169_376_550_946_112_5e4,
        4.592_195_393_154_987_145_7e4,
        6.726_577_092_700_870_085_3e4,
        3.343_057_558_358_812_810_5e4,
        2.509_080_928_730_122_672_7e3,
    ];
    pub(super) const B: [f64; 8] = [
        1.0,
        4.231_333_070_160_091_125_2e1,
        6.871_870_074_920_579_083e2,
        5.394_196_021_424_751_107_7e3,
        2.121_379_430_158_659_586_7e4,
        3.930_789_580_009_271_061e4,
        2.872_908_573_572_194_267_4e4,
        5.226_495_278_852_854_561e3,
    ];
    /// Intermediate tail, r = √(−ln min(p, 1 − p)) ≤ 5 (down to p ≈ e⁻²⁵ ≈ 1.4e-11), in r − 1.6.
    pub(super) const C: [f64; 8] = [
        1.423_437_110_749_683_577_34,
        4.630_337_846_156_545_295_9,
        5.769_497_221_460_691_405_5,
        3.647_848_324_763_204_605_04,
        1.270_458_252_452_368_382_58,
        2.417_807_251_774_506_117_7e-1,
        2.272_384_498_926_918_458_33e-2,
        7.745_450_142_783_414_076_4e-4,
    ];
    pub(super) const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_758_821_87,
        1.676_384_830_183_803_849_4,
        6.897_673_349_851_000_045_5e-1,
        1.481_039_764_274_800_745_9e-1,
        1.519_866_656_361_645_719_66e-2,
        5.475_938_084_995_344_946e-4,
        1.050_750_071_644_416_843_24e-9,
    ];
    /// Far tail, r > 5, in r − 5.
    pub(super) const E: [f64; 8] = [
        6.657_904_643_501_103_777_2,
        5.463_784_911_164_114_369_9,
        1.784_826_539_917_291_335_8,
        2.965_605_718_285_048_912_3e-1,
        2.653_218_952_657_612_309_3e-2,
        1.242_660_947_388_078_438_6e-3,
        2.711_555_568_743_487_578_15e-5,
        2.010_334_399_292_288_132_65e-7,
    ];
    pub(super) const F: [f64; 8] = [
        1.0,
        5.998_322_065_558_879_376_9e-1,
        1.369_298_809_227_358_053_1e-1,
        1.487_536_129_085_061_485_25e-2,
        7.868_691_311_456_132_591e-4,
        1.846_318_317_510_054_681_8e-5,
        1.421_511_758_316_445_888_7e-7,
        2.044_263_103_389_939_785_64e-15,
    ];
}

/// Φ⁻¹ of each value in place, as [`Marginal::normal_score`] gives it (NaN stays NaN):
/// eight at a time on processors with AVX-512 F or AVX2 (the central region's
/// polynomials in vectors, the tails one by one), one by one elsewhere or when
/// `STILLPOINT_PORTABLE=1` asks for the portable build ([`vector_build`]).
fn normal_scores(us: &mut [f64]) {
    match vector_build() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX-512 F (checked by `vector_build`).
        VectorBuild::Avx512 => unsafe { normal_scores_avx512(us) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor has AVX2 (checked by `vector_build`).
        VectorBuild::Avx2 => unsafe { normal_scores_avx2(us) },
        _ => us.iter_mut().for_each(|u| *u = Marginal::normal_score(*u)),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn normal_scores_avx512(us: &mut [f64]) {
    normal_score_lanes(us)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn normal_scores_avx2(us: &mut [f64]) {
    normal_score_lanes(us)
}

/// [`normal_scores`]' body: each block of eight values' central-region quotient for all
/// eight lanes (written lane by lane so that the compiler keeps it in vectors; Rust
/// does not fuse a multiply and an add, so each lane rounds as the scalar code does),
/// then the values outside the central region, NaN included, one by one.
#[inline(always)]
fn normal_score_lanes(us: &mut [f64]) {
    const LANES: usize = 8;
    let mut blocks = us.chunks_exact_mut(LANES);
    for block in &mut blocks {
        let mut q = [0.0; LANES];
        let mut central = [0.0; LANES];
        for k in 0..LANES {
            q[k] = block[k].clamp(U_MIN, 1.0 - U_MIN) - 0.5;
            central[k] = norm_ppf_central(q[k]);
        }
        for k in 0..LANES {
            block[k] = if q[k].abs() <= 0.425 {
                central[k]
            } else {
                Marginal::normal_score(block[k])
            };
        }
    }
    for u in blocks.into_remainder() {
        *u = Marginal::normal_score(*u);
    }
}

fn poly(c: &[f64; 8], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
}

/// Φ⁻¹(p) by AS 241; ±∞ at p = 0 and 1. The tails use min(p, 1 − p), exact for p ≥ 0.5,
/// so the upper tail is as accurate as the lower one.
fn norm_ppf(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        return norm_ppf_central(q);
    }
    let r = (-(if q < 0.0 { p } else { 1.0 - p }).ln()).sqrt();
    let x = if r <= 5.0 {
        poly(&as241::C, r - 1.6) / poly(&as241::D, r - 1.6)
    } else {
        poly(&as241::E, r - 5.0) / poly(&as241::F, r - 5.0)
    };
    if q < 0.0 {
        -x
    } else {
        x
    }
}

/// Φ⁻¹(0.5 + q) for |q| ≤ 0.425 (AS 241's central region), from q itself: a caller
/// that has q with full relative precision gets x with it too, even very near 0.
/// (0.180625 is 0.425², so r runs from 0 at the region's edges to 0.180625 at p = 0.5.)
fn norm_ppf_central(q: f64) -> f64 {
    let r = 0.180_625 - q * q;
    q * poly(&as241::A, r) / poly(&as241::B, r)
}

/// Φ(x) through erfc, which keeps full relative precision deep in the lower tail.
fn norm_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x * std::f64::consts::FRAC_1_SQRT_2)
}

/// 1 − Φ(x) without the cancellation of subtracting from 1 (the smaller tail's
/// probability at |x|, to full relative precision).
pub fn norm_sf(x: f64) -> f64 {
    0.5 * libm::erfc(x * std::f64::consts::FRAC_1_SQRT_2)
}

/// Φ(b) − Φ(a) for a < b, each form used where its terms are the smaller, so that
/// rounding them costs least: erf(x/√2)/2 = Φ(x) − 1/2 near 0, the tails Φ(x) or 1 − Φ(x)
/// beyond ±Φ⁻¹(3/4) ≈ ±0.6745, where the two are equal (both 1/4).
fn gauss_mass(a: f64, b: f64) -> f64 {
    const QUARTILE: f64 = 0.674_489_750_196_081_7;
    if b <= -QUARTILE {
        norm_cdf(b) - norm_cdf(a)
    } else if a >= QUARTILE {
        norm_sf(a) - norm_sf(b)
    } else {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        0.5 * (libm::erf(b * s) - libm::erf(a * s))
    }
}

/// The standard normal truncated to [a, b], at u: Φ⁻¹(Φ(a) + u·Z), Z = Φ(b) − Φ(a).
/// The target is formed where it has no cancellation: near the middle as Φ(a) − 0.5 +
/// u·Z from erf (so a quantile near 0, as for a half-normal's small u, keeps its relative
/// precision), in the lower tail as Φ(a) + u·Z, and in the upper tail as the survival
/// probability (1 − Φ(b)) + (1 − u)·Z, so values near an infinite or far upper end keep
/// theirs (SciPy's truncnorm switches to the survival form by the sign of a instead).
fn trunc_ppf(a: f64, b: f64, u: f64) -> f64 {
    let z = gauss_mass(a, b);
    let q = 0.5 * libm::erf(a * std::f64::consts::FRAC_1_SQRT_2) + u * z;
    if q.abs() <= 0.425 {
        norm_ppf_central(q)
    } else if q < 0.0 {
        norm_ppf(norm_cdf(a) + u * z)
    } else {
        -norm_ppf(norm_sf(b) + (1.0 - u) * z)
    }
}

/// The standard normal truncated to [a, b], its CDF at x in (a, b): the smaller of the
/// two masses on either side of x is computed, the other is its complement, so the
/// nearer tail keeps its relative precision.
fn trunc_cdf(a: f64, b: f64, x: f64) -> f64 {
    let z = gauss_mass(a, b);
    let below = gauss_mass(a, x);
    let above = gauss_mass(x, b);
    if below <= above {
        below / z
    } else {
        1.0 - above / z
    }
}

/// ln B(a, b). Small shapes take libm's lgamma directly; once a shape is large,
/// lgamma's values are large too (ln Γ(500) ≈ 2605) and their difference loses digits
/// that a small-shape quantile amplifies by 1/a, so the large parts are combined by
/// Stirling's series into terms of the size of the result (as in TOMS 708's betaln).
fn ln_beta(a: f64, b: f64) -> f64 {
    // From 10 on, the seven terms of `stirling_tail` leave an error below 1e-16.
    const STIRLING_FROM: f64 = 10.0;
    let (p, q) = if a <= b { (a, b) } else { (b, a) };
    if q < STIRLING_FROM {
        return libm::lgamma(p) + libm::lgamma(q) - libm::lgamma(p + q);
    }
    let w = stirling_tail(q) - stirling_tail(p + q);
    if p < STIRLING_FROM {
        // ln Γ(q) − ln Γ(p + q) with the (q − 1/2)·ln terms folded into log1p(p/q).
        let gq_over_gpq = -(q - 0.5) * libm::log1p(p / q) - p * (p + q).ln() + p + w;
        return libm::lgamma(p) + gq_over_gpq;
    }
    // Both large: ½ln(2π) − ½ln q + (p − ½)·ln(p/(p + q)) − q·ln(1 + p/q) + the tails.
    let half_ln_2pi = 0.918_938_533_204_672_7;
    half_ln_2pi - 0.5 * q.ln() + (p - 0.5) * (p / (p + q)).ln() - q * libm::log1p(p / q)
        + w
        + stirling_tail(p)
}

/// ln Γ(x) − [(x − ½)ln x − x + ½ln(2π)] for x ≥ 10: Stirling's series, whose terms are
/// B₂ₖ/(2k(2k − 1)x^(2k−1)) with B₂ₖ the Bernoulli numbers 1/6, −1/30, 1/42, −1/30, 5/66,
/// −691/2730, 7/6 (the next term is below 3e-17 at x = 10).
fn stirling_tail(x: f64) -> f64 {
    const COEF: [f64; 7] = [
        1.0 / 12.0,
        -1.0 / 360.0,
        1.0 / 1260.0,
        -1.0 / 1680.0,
        1.0 / 1188.0,
        -691.0 / 360_360.0,
        1.0 / 156.0,
    ];
    let r = 1.0 / (x * x);
    COEF.iter().rev().fold(0.0, |acc, &c| acc * r + c) / x
}

/// The continued fraction of I_x(a, b) (Numerical Recipes §6.4, evaluated by the
/// modified Lentz method); it converges quickly for x < (a + 1)/(a + b + 2).
fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    // Lentz's stand-in for a zero denominator: small enough not to matter, large enough
    // that its reciprocal is finite.
    const TINY: f64 = 1e-300;
    // Terms are added until one changes the product by less than a rounding error; the
    // bound is far above the O(√max(a, b)) terms the fraction needs.
    const MAX_TERMS: usize = 10_000;
    let guard = |v: f64| if v.abs() < TINY { TINY } else { v };
    let mut c = 1.0;
    let mut d = 1.0 / guard(1.0 - (a + b) * x / (a + 1.0));
    let mut h = d;
    for m in 1..=MAX_TERMS {
        let m = m as f64;
        let m2 = 2.0 * m;
        let even = m * (b - m) * x / ((a - 1.0 + m2) * (a + m2));
        d = 1.0 / guard(1.0 + even * d);
        c = guard(1.0 + even / c);
        h *= d * c;
        let odd = -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1.0 + m2));
        d = 1.0 / guard(1.0 + odd * d);
        c = guard(1.0 + odd / c);
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() <= f64::EPSILON {
            break;
        }
    }
    h
}

/// The regularized incomplete beta I_x(a, b) and its complement 1 − I_x(a, b), each
/// accurate relative to itself where it is the smaller: the continued fraction is summed
/// on the side of x where it converges, I_x(a, b) = 1 − I_{1−x}(b, a) gives the other.
/// `lnb` is ln B(a, b).
fn inc_beta(a: f64, b: f64, x: f64, lnb: f64) -> (f64, f64) {
    if x <= 0.0 {
        return (0.0, 1.0);
    }
    if x >= 1.0 {
        return (1.0, 0.0);
    }
    // x^a (1 − x)^b / B(a, b), in logs so that neither power underflows on its own.
    let front = (a * x.ln() + b * libm::log1p(-x) - lnb).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        let i = front * beta_cf(a, b, x) / a;
        (i, 1.0 - i)
    } else {
        let c = front * beta_cf(b, a, 1.0 - x) / b;
        (1.0 - c, c)
    }
}

/// The Beta(a, b) density at x in (0, 1).
fn beta_pdf(a: f64, b: f64, x: f64, lnb: f64) -> f64 {
    ((a - 1.0) * x.ln() + (b - 1.0) * libm::log1p(-x) - lnb).exp()
}

/// A starting point for the beta quantile (Numerical Recipes §6.14): for a, b ≥ 1 the
/// normal approximation of Abramowitz & Stegun 26.5.22, otherwise the tail forms
/// I_x ≈ x^a/(a·w) near 0 and 1 − I_x ≈ (1 − x)^b/(b·w) near 1, w normalising the two.
fn beta_guess(a: f64, b: f64, u: f64) -> f64 {
    if a >= 1.0 && b >= 1.0 {
        let z = -norm_ppf(u);
        let al = (z * z - 3.0) / 6.0;
        let h = 2.0 / (1.0 / (2.0 * a - 1.0) + 1.0 / (2.0 * b - 1.0));
        let w = z * (al + h).sqrt() / h
            - (1.0 / (2.0 * b - 1.0) - 1.0 / (2.0 * a - 1.0)) * (al + 5.0 / 6.0 - 2.0 / (3.0 * h));
        a / (a + b * (2.0 * w).exp())
    } else {
        let t = (a * (a / (a + b)).ln()).exp() / a;
        let v = (b * (b / (a + b)).ln()).exp() / b;
        let w = t + v;
        if u < t / w {
            (a * w * u).powf(1.0 / a)
        } else {
            1.0 - (b * w * (1.0 - u)).powf(1.0 / b)
        }
    }
}

/// The Beta(a, b) quantile at u in [0, 1]: Halley steps from [`beta_guess`], each kept
/// inside a bracket that every evaluation narrows, with bisection when a step leaves it.
/// Below the median the residual is I_x − u, above it (1 − u) − (1 − I_x), so the target
/// is always the smaller tail probability and keeps its relative precision.
fn beta_ppf(a: f64, b: f64, u: f64) -> f64 {
    // Halley converges in a handful of steps from the guess; the bound only matters when
    // bisection takes over, and a bracket of doubles shrinks to nothing well within it.
    const MAX_STEPS: usize = 400;
    if u <= 0.0 {
        return 0.0;
    }
    if u >= 1.0 {
        return 1.0;
    }
    let lnb = ln_beta(a, b);
    let lower = u <= 0.5;
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut x = beta_guess(a, b, u);
    if !(x > 0.0 && x < 1.0) {
        x = 0.5;
    }
    for _ in 0..MAX_STEPS {
        let (i, ic) = inc_beta(a, b, x, lnb);
        let r = if lower { i - u } else { (1.0 - u) - ic };
        if r == 0.0 {
            return x;
        }
        if r < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = r / beta_pdf(a, b, x, lnb);
        // Halley's correction uses f'/f = (a − 1)/x − (b − 1)/(1 − x); it is dropped when
        // it would more than double or reverse the Newton step (far from the root).
        let bend = 0.5 * newton * ((a - 1.0) / x - (b - 1.0) / (1.0 - x));
        let step = if bend.abs() < 0.5 {
            newton / (1.0 - bend)
        } else {
            newton
        };
        let mut next = x - step;
        if !(next > lo && next < hi) {
            next = bisect(lo, hi);
        }
        if (next - x).abs() <= f64::EPSILON * next || next == x {
            return next;
        }
        x = next;
    }
    x
}

/// A point strictly inside (lo, hi) ⊂ [0, 1]: the geometric mean when the bracket spans
/// orders of magnitude (quantiles of small shapes reach 1e-30 and below), the arithmetic
/// mean otherwise.
fn bisect(lo: f64, hi: f64) -> f64 {
    if lo == 0.0 {
        // 2⁻¹⁰: a big enough jump toward 0 that a tiny root is reached in few steps,
        // after which the bracket has a positive end for the geometric mean.
        hi * (1.0 / 1024.0)
    } else if hi > 4.0 * lo {
        lo.sqrt() * hi.sqrt()
    } else {
        0.5 * (lo + hi)
    }
}

/// A parameter as a user writes it: plainly (`0.25`, `1000`) while that is short, in
/// scientific notation past 17 characters (`1e300`, not 301 digits); both read back to
/// the same float.
pub fn num(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 17 {
        plain
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_score_gives_the_quantile_bit_for_bit() {
        let laws = [
            Marginal::Normal {
                mu: 3.0,
                sigma: 0.25,
            },
            Marginal::Normal {
                mu: 1e15,
                sigma: 1e-3,
            },
            Marginal::LogNormal {
                mu: -0.4,
                sigma: 1.7,
            },
        ];
        // Faces, the clamped ends and interior points, as the centres of the checks.
        let us = [
            0.0,
            1e-300,
            2f64.powi(-53),
            1e-9,
            0.3,
            0.5,
            0.999,
            1.0 - 1e-17,
            1.0,
        ];
        for m in laws {
            for u in us {
                let z = Marginal::normal_score(u);
                let x = m.from_normal_score(z).unwrap();
                assert_eq!(x.to_bits(), m.ppf(u).to_bits(), "{m:?} at {u}");
            }
        }
        let uniform = Marginal::Uniform { lo: 0.0, hi: 1.0 };
        assert_eq!(uniform.from_normal_score(0.0), None);
    }

    #[test]
    fn a_column_s_quantiles_are_each_value_s() {
        // Every region of Φ⁻¹ (central, intermediate and far tails, the clamped ends),
        // NaN, and lengths around whole blocks of eight; the machine's build and the
        // lanes body compiled without a target feature.
        let mut us: Vec<f64> = (0..203).map(|k| (k as f64 + 0.5) / 203.0).collect();
        us.extend([
            0.0,
            1.0,
            1e-300,
            1e-12,
            1.0 - 1e-12,
            0.075,
            0.925,
            f64::NAN,
            0.5,
        ]);
        let laws = [
            Marginal::Normal {
                mu: 3.0,
                sigma: 0.25,
            },
            Marginal::LogNormal {
                mu: -0.4,
                sigma: 1.7,
            },
            Marginal::Beta {
                a: 2.0,
                b: 3.0,
                lo: 0.0,
                hi: 1.0,
            },
        ];
        for len in [0, 1, 7, 8, 9, us.len()] {
            for m in &laws {
                let want: Vec<u64> = us[..len].iter().map(|&u| m.ppf(u).to_bits()).collect();
                let mut got = us[..len].to_vec();
                m.ppf_in_place(&mut got);
                let got: Vec<u64> = got.iter().map(|x| x.to_bits()).collect();
                assert_eq!(got, want, "{m:?}, {len} values");
            }
            let want: Vec<u64> = us[..len]
                .iter()
                .map(|&u| Marginal::normal_score(u).to_bits())
                .collect();
            for body in [normal_score_lanes, normal_scores] {
                let mut got = us[..len].to_vec();
                body(&mut got);
                let got: Vec<u64> = got.iter().map(|x| x.to_bits()).collect();
                assert_eq!(got, want, "a build's body, {len} values");
            }
        }
    }

    #[test]
    fn incomplete_beta_halves_sum_to_one() {
        for &(a, b) in &[(0.3, 5.0), (2.0, 2.0), (30.0, 0.5)] {
            let lnb = ln_beta(a, b);
            // Dyadic points, so that 1 − x is exact and both sides see the same point.
            for &x in &[2f64.powi(-20), 0.125, 0.5, 0.875, 1.0 - 2f64.powi(-20)] {
                let (i, ic) = inc_beta(a, b, x, lnb);
                let (j, jc) = inc_beta(b, a, 1.0 - x, ln_beta(b, a));
                assert!((i + ic - 1.0).abs() < 1e-15);
                assert!(
                    (i - jc).abs() <= 1e-14 * i.max(1e-300),
                    "{a} {b} {x}: {i} {jc}"
                );
                assert!(
                    (ic - j).abs() <= 1e-14 * ic.max(1e-300),
                    "{a} {b} {x}: {ic} {j}"
                );
            }
        }
    }

    #[test]
    fn incomplete_beta_known_values() {
        // I_x(1, b) = 1 − (1 − x)^b and I_x(a, 1) = x^a, exactly.
        let (i, _) = inc_beta(1.0, 3.0, 0.2, ln_beta(1.0, 3.0));
        assert!((i - (1.0 - 0.8_f64.powi(3))).abs() < 1e-15);
        let (i, _) = inc_beta(0.5, 1.0, 1e-8, ln_beta(0.5, 1.0));
        assert!((i / 1e-4 - 1.0).abs() < 1e-14);
    }

    #[test]
    fn log_beta_keeps_its_digits_for_large_shapes() {
        // References from 40-digit arithmetic (mpmath's log(beta(a, b))).
        for &(a, b, lnb) in &[
            (0.05, 500.0, 2.658_196_310_379_110_5),
            (0.3, 30.0, 0.078_946_420_621_173_53),
            (30.0, 30.0, -42.019_750_927_113_47),
            (1000.0, 1000.0, -1_388.482_601_635_902_3),
            (2.5, 12.0, -6.075_775_125_342_28),
        ] {
            let got = ln_beta(a, b);
            assert!(
                (got - lnb).abs() <= 4e-16 * lnb.abs().max(1.0),
                "{a},{b}: {got}"
            );
            assert_eq!(ln_beta(b, a), got);
        }
    }

    #[test]
    fn normal_quantile_inverts_erfc_down_to_1e_300() {
        // Deep in the lower tail (beyond where design points reach) AS 241 still agrees
        // with Φ computed through erfc.
        for &p in &[1e-300, 1e-200, 1e-100, 1e-20, 1e-11, 1e-5, 0.01, 0.2, 0.4] {
            let back = norm_cdf(norm_ppf(p));
            assert!((back / p - 1.0).abs() < 1e-12, "{p}: {back}");
        }
    }
}
