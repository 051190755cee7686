//! `stillpoint bench`: times the pair kernels of the energies and metrics and, in the
//! same run, the baselines they are compared with and the machine's floating-point peak,
//! and prints medians and ratios.
//!
//! - **Roofline.** A tiny kernel of independent fused multiply-adds (AVX2 + FMA when the
//!   processor has them, else separate multiplies and adds) gives the f64 peak on 1 and on
//!   2 threads. Each pair kernel is reported as a fraction of it, from the floating-point
//!   operations per pair-coordinate counted in `Flops` (an FMA counts 2; add, subtract,
//!   multiply, divide, min, max and square root 1; bitwise operations, comparisons and
//!   selections 0).
//! - **Baselines.** For U_{q,p} with its gradient, [`naive_uqp_gradient`]: eqs. 11, 16
//!   and 18 as printed, every power through `powf`, both halves of the pair loop, one
//!   thread; for U_{q,p} with the fast table (`Precision::Fast`), the full kernel timed
//!   in the same run. For the discrepancies, [`naive_discrepancy_squared`]: the closed form as a
//!   plain double loop over all ordered pairs, one thread (what a direct transcription,
//!   or SciPy's `qmc.discrepancy` with one worker, does). For the metrics, the same code
//!   on one thread.
//! - **Threads.** Every kernel is timed in rayon pools of 1 and 2 threads built inside this
//!   process; the results have the same bits in both.
//! - **Scaling.** n = 500 … 20 000 (smaller in quick mode), reported as nanoseconds per
//!   pair per coordinate: constant when the loop is compute-bound.
//!
//! Timings are wall-clock medians of repeated runs after one warm-up run.
//!
//! **Points mode.** `stillpoint bench --points FILE [--reps K]` (any format `stillpoint
//! eval` reads) instead times the squared centred L2 and the star L2 discrepancy of those
//! points on the current thread pool (`--threads`), median of K runs (default 5), and
//! prints one JSON object; `benches/scipy_discrepancy.py` uses it to compare with SciPy on
//! the same points.

use std::io::Write;
use std::time::Instant;
use stillpoint::energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKernel, DiscrepancyKind};
use stillpoint::energies::pairs::vector_path;
use stillpoint::energies::{Distance, Energy, PointSet, Precision, Uqp};
use stillpoint::quality::metrics::{self, Metrics};
use stillpoint::sequences;

/// Median wall time in seconds of `reps` calls (after one warm-up call when reps > 1).
fn median_time(reps: usize, mut f: impl FnMut()) -> f64 {
    if reps > 1 {
        f();
    }
    let mut t: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let c = Instant::now();
            f();
            c.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// The straightforward U_{q,p} gradient: eq. 11 for d, eq. 16 for a_ijk, eq. 18 for f,
/// one thread, no closed forms.
pub fn naive_uqp_gradient(points: &PointSet, q: f64, p: f64, grad: &mut [f64]) -> f64 {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    let mut sum = 0.0;
    grad.fill(0.0);
    let mut a = vec![0.0; s];
    for i in 0..n {
        for j in 0..n {
            if i == j {
                continue;
            }
            let mut d2 = 0.0;
            for k in 0..s {
                let diff = x[i * s + k] - x[j * s + k];
                let dl = diff.abs();
                let w = (1.0 - dl).powf(q) + dl.powf(q);
                d2 += (dl * dl * (1.0 - dl) * (1.0 - dl)) / w.powf(2.0 / q);
                a[k] =
                    diff.signum() * dl * (1.0 - dl) * ((1.0 - dl).powf(q + 1.0) - dl.powf(q + 1.0))
                        / w.powf(1.0 + 2.0 / q);
            }
            let d = d2.sqrt();
            if j > i {
                sum += d.powf(-p);
            }
            for k in 0..s {
                grad[i * s + k] += a[k] / d.powf(p + 2.0);
            }
        }
    }
    let scale = -sum.powf(1.0 / p - 1.0);
    grad.iter_mut().for_each(|g| *g *= scale);
    sum.powf(1.0 / p)
}

/// The constant C_s (by `powi`, as a direct transcription takes it), g and h of a kernel,
/// as plain functions: the naive loop calls them through pointers.
type Factors = (f64, fn(f64) -> f64, fn(f64, f64) -> f64);

fn factors<K: DiscrepancyKernel>(s: usize) -> Factors {
    let single: fn(f64) -> f64 = if K::HAS_SINGLE {
        K::single_factor
    } else {
        |_| 0.0
    };
    (
        K::CONSTANT_SIGN * K::CONSTANT_BASE.powi(s as i32),
        single,
        K::pair_factor,
    )
}

/// The squared discrepancy of `kind` as a plain double loop over all ordered pairs (i, l),
/// one thread: the baseline of the vectorised half loop.
pub fn naive_discrepancy_squared(points: &PointSet, kind: DiscrepancyKind) -> f64 {
    let (n, s) = (points.n() as f64, points.s());
    let (constant, single, pair) = stillpoint::energies::with_kernel!(kind, K => factors::<K>(s));
    let mut singles = 0.0;
    let mut pairs = 0.0;
    for a in points.rows() {
        singles += a.iter().map(|&x| single(x)).product::<f64>();
        for b in points.rows() {
            pairs += a.iter().zip(b).map(|(&x, &y)| pair(x, y)).product::<f64>();
        }
    }
    constant - 2.0 * singles / n + pairs / (n * n)
}

/// Floating-point operations of a pair kernel: `per_coord` per pair and coordinate plus
/// `per_pair` per pair, counted from the code of `stillpoint_energies` (FMA = 2; see the
/// module documentation for the rule).
#[derive(Clone, Copy)]
struct Flops {
    per_coord: f64,
    per_pair: f64,
}

impl Flops {
    /// U_{q,p} value and gradient, general q: per coordinate the periodic reduction (4),
    /// 1/(1 − Δ) and Δ/(1 − Δ) (3), log₂ (21), ·q and the clamp (2), 2^y (24), log₂(1 + t)
    /// with σ (25), ·(−2/q) (1), the clamp and 2^y (25), h² (2), h·h' (4), d² (1) and the
    /// force scatter (3); per pair d^{−p} (48), its sum (1) and d^{−p}/d² (1).
    const UQP_GENERAL_GRAD: Flops = Flops {
        per_coord: 115.0,
        per_pair: 50.0,
    };
    /// U_{q,p} value and gradient, general q with the fast table: reduction (4), the
    /// local variable (2), two cubics (12), h² (2) and h·h' (1), d² (1), scatter (3);
    /// the interval index and the row transposes are bit operations and shuffles.
    const UQP_FAST_GRAD: Flops = Flops {
        per_coord: 25.0,
        per_pair: 50.0,
    };
    /// U_{q,p} value only, general q: the above without h·h' and the scatter.
    const UQP_GENERAL_VALUE: Flops = Flops {
        per_coord: 108.0,
        per_pair: 49.0,
    };
    /// U_{q,p} value and gradient, q = 1: reduction (4), h and h·h' (7), d² (1),
    /// scatter (3).
    const UQP_Q1_GRAD: Flops = Flops {
        per_coord: 15.0,
        per_pair: 50.0,
    };
    /// U_{q,p} value and gradient, q = ∞: reduction (4), h² (1), d² (1), scatter (3).
    const UQP_TORUS_GRAD: Flops = Flops {
        per_coord: 9.0,
        per_pair: 50.0,
    };
    /// Star L2 pair product: 1 − max(x, y) (2) and the product (1).
    const STAR: Flops = Flops {
        per_coord: 3.0,
        per_pair: 1.0,
    };
    /// Centred L2 pair product: (1 + ½|x − ½|) + ½|y − ½| − ½|x − y| with ½|· − ½|
    /// precomputed per point (4), the product (1).
    const CENTERED: Flops = Flops {
        per_coord: 5.0,
        per_pair: 1.0,
    };
    /// Modified L2 value and gradient: the factor and the product (3), the prefix
    /// product (0: a store), the suffix weight and product (2), the two derivatives
    /// (2: 0 − ∂ and ∂ − 1) and their two scatters (4).
    const MODIFIED_GRAD: Flops = Flops {
        per_coord: 11.0,
        per_pair: 1.0,
    };
    /// All metrics: star (3), modified (3), centred (5) and wrap-around (5) products in
    /// one pass, and the Euclidean (3) and torus (3) squared distances in another.
    const METRICS: Flops = Flops {
        per_coord: 22.0,
        per_pair: 6.0,
    };

    fn total(self, n: usize, s: usize) -> f64 {
        pairs(n) * (self.per_coord * s as f64 + self.per_pair)
    }
}

fn pairs(n: usize) -> f64 {
    (n * (n - 1) / 2) as f64
}

fn on_threads<T: Send>(t: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .build()
        .expect("thread pool")
        .install(f)
}

/// f64 peak in flop/s on `threads` threads: each runs [`fma_block`] on its own data.
fn fma_peak(threads: usize, reps: usize) -> f64 {
    const ITERS: usize = 20_000_000;
    let secs = on_threads(threads, || {
        median_time(reps, || {
            let v: f64 = rayon::broadcast(|ctx| fma_block(ITERS, ctx.index() as f64))
                .into_iter()
                .sum();
            std::hint::black_box(v);
        })
    });
    // 12 chains of 4 lanes, one FMA (2 flops) each per iteration.
    (threads * ITERS * 12 * 4 * 2) as f64 / secs
}

/// `iters` rounds of 12 independent chains of 4-lane fused multiply-adds: enough chains to
/// cover the latency of both FMA pipes, nothing else in the loop.
fn fma_block(iters: usize, seed: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if vector_path() == "avx2+fma" {
        // SAFETY: `vector_path` reports AVX2 and FMA only after checking the processor.
        return unsafe { fma_block_avx2(iters, seed) };
    }
    let mut acc = [[1.0 + seed * 1e-9; 4]; 12];
    let (b, c) = (
        std::hint::black_box(0.999_999_9),
        std::hint::black_box(1e-7),
    );
    for _ in 0..iters {
        for chain in acc.iter_mut() {
            for v in chain.iter_mut() {
                *v = *v * b + c;
            }
        }
    }
    acc.iter().flatten().sum()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fma_block_avx2(iters: usize, seed: f64) -> f64 {
    use std::arch::x86_64::*;
    let mut acc = [_mm256_set1_pd(1.0 + seed * 1e-9); 12];
    let b = _mm256_set1_pd(std::hint::black_box(0.999_999_9));
    let c = _mm256_set1_pd(std::hint::black_box(1e-7));
    for _ in 0..iters {
        for v in acc.iter_mut() {
            *v = _mm256_fmadd_pd(*v, b, c);
        }
    }
    let mut sum = _mm256_setzero_pd();
    for v in acc {
        sum = _mm256_add_pd(sum, v);
    }
    let mut out = [0.0; 4];
    _mm256_storeu_pd(out.as_mut_ptr(), sum);
    out.iter().sum()
}

/// One timed kernel: the median seconds on 1 and on 2 threads, and of the baseline.
struct Timing {
    baseline: Option<f64>,
    one: f64,
    two: f64,
}

/// The Markdown row of a kernel: times, ratios, the constant and the fraction of peak.
#[allow(clippy::too_many_arguments)]
fn row(
    out: &mut dyn Write,
    name: &str,
    n: usize,
    s: usize,
    baseline: &str,
    t: &Timing,
    flops: Flops,
    peak: (f64, f64),
) -> std::io::Result<()> {
    let ms = |v: f64| format!("{:.1}", v * 1e3);
    let (b_ms, vs) = match t.baseline {
        Some(b) => (ms(b), format!("{:.1}×", b / t.two)),
        None => ("—".into(), "—".into()),
    };
    let ns = t.two * 1e9 / (pairs(n) * s as f64);
    let f = flops.total(n, s);
    writeln!(
        out,
        "| {name} | {n} | {s} | {baseline} | {b_ms} | {} | {} | {vs} | {:.2}× | {ns:.3} | {:.0}% / {:.0}% |",
        ms(t.one),
        ms(t.two),
        t.one / t.two,
        100.0 * f / t.one / peak.0,
        100.0 * f / t.two / peak.1,
    )
}

/// Times `f` on 1 and 2 threads.
fn both(reps: usize, f: impl Fn() + Sync) -> (f64, f64) {
    let one = on_threads(1, || median_time(reps, &f));
    let two = on_threads(2, || median_time(reps, &f));
    (one, two)
}

/// Runs the benchmark and writes Markdown tables to `out`.
pub fn run(quick: bool, out: &mut dyn Write) -> std::io::Result<()> {
    let reps = if quick { 3 } else { 7 };
    writeln!(
        out,
        "stillpoint bench ({} mode; {} threads available; vector path {}; {}; medians of {} runs)\n",
        if quick { "quick" } else { "full" },
        rayon::current_num_threads(),
        vector_path(),
        cpu_model(),
        reps
    )?;
    let peak = (fma_peak(1, reps), fma_peak(2, reps));
    writeln!(
        out,
        "f64 peak (independent 4-lane FMAs): 1 thread {:.1} GFLOP/s, 2 threads {:.1} GFLOP/s ({:.2}×)\n",
        peak.0 * 1e-9,
        peak.1 * 1e-9,
        peak.1 / peak.0
    )?;
    writeln!(
        out,
        "| kernel | n | s | baseline | baseline ms | ours 1 thread ms | ours 2 threads ms | vs baseline (2 threads) | 2 threads vs 1 | ns per pair-coordinate (2 threads) | of f64 peak (1 / 2 threads) |"
    )?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|")?;

    kernel_table(quick, reps, peak, out)?;
    scaling_table(quick, reps, out)
}

/// One row per kernel: ours on 1 and 2 threads beside its baseline, and the share of
/// the machine's f64 peak.
fn kernel_table(
    quick: bool,
    reps: usize,
    peak: (f64, f64),
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let n_uqp = if quick { 500 } else { 1500 };
    let (q, p) = (0.3, 0.8);
    let mut full_two = Vec::new();
    for s in [2, 20] {
        let x = sequences::halton(n_uqp, s).expect("halton");
        let e = Uqp::new(Distance::Q(q), p).expect("energy");
        let base = median_time(if quick { 1 } else { 3 }, || {
            let mut g = vec![0.0; x.coordinate_count()];
            std::hint::black_box(naive_uqp_gradient(&x, q, p, &mut g));
        });
        let (one, two) = both(reps, || {
            let mut g = vec![0.0; x.coordinate_count()];
            std::hint::black_box(e.value_and_gradient(&x, &mut g));
        });
        full_two.push(two);
        let t = Timing {
            baseline: Some(base),
            one,
            two,
        };
        let name = "U_{q,p} value+gradient, q=0.3, p=0.8";
        row(
            out,
            name,
            n_uqp,
            s,
            "eqs. 11/16 as printed, 1 thread",
            &t,
            Flops::UQP_GENERAL_GRAD,
            peak,
        )?;
    }
    for (s, full) in [2, 20].into_iter().zip(full_two) {
        let x = sequences::halton(n_uqp, s).expect("halton");
        let e = Uqp::new(Distance::Q(q), p)
            .expect("energy")
            .with_precision(Precision::Fast);
        let (one, two) = both(reps, || {
            let mut g = vec![0.0; x.coordinate_count()];
            std::hint::black_box(e.value_and_gradient(&x, &mut g));
        });
        let t = Timing {
            baseline: Some(full),
            one,
            two,
        };
        row(
            out,
            "U_{q,p} value+gradient, q=0.3, p=0.8, fast (table)",
            n_uqp,
            s,
            "the full kernel above (1e-12), 2 threads",
            &t,
            Flops::UQP_FAST_GRAD,
            peak,
        )?;
    }
    let x = sequences::halton(n_uqp, 20).expect("halton");
    let e = Uqp::new(Distance::Q(q), p).expect("energy");
    let (one, two) = both(reps, || {
        std::hint::black_box(e.value(&x));
    });
    let t = Timing {
        baseline: None,
        one,
        two,
    };
    row(
        out,
        "U_{q,p} value only, q=0.3, p=0.8",
        n_uqp,
        20,
        "—",
        &t,
        Flops::UQP_GENERAL_VALUE,
        peak,
    )?;
    for (label, dist, flops) in [
        ("q=1 (closed form)", Distance::Q(1.0), Flops::UQP_Q1_GRAD),
        ("q=inf (torus)", Distance::Torus, Flops::UQP_TORUS_GRAD),
    ] {
        let e = Uqp::new(dist, p).expect("energy");
        let (one, two) = both(reps, || {
            let mut g = vec![0.0; x.coordinate_count()];
            std::hint::black_box(e.value_and_gradient(&x, &mut g));
        });
        let t = Timing {
            baseline: None,
            one,
            two,
        };
        let name = format!("U_{{q,p}} value+gradient, {label}, p=0.8");
        row(out, &name, n_uqp, 20, "—", &t, flops, peak)?;
    }

    discrepancy_rows(quick, reps, peak, out)
}

/// The discrepancy kernels' rows: each closed form, the discrepancy energy's gradient and
/// every metric of `eval` together.
fn discrepancy_rows(
    quick: bool,
    reps: usize,
    peak: (f64, f64),
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let n_uqp = if quick { 500 } else { 1500 };
    let n_disc = if quick { 1500 } else { 10_000 };
    let x = sequences::halton(n_disc, 20).expect("halton");
    for (name, kind, f, flops) in [
        (
            "centred L2 discrepancy² (metric)",
            DiscrepancyKind::CenteredL2,
            metrics::centered_l2_squared as fn(&PointSet) -> f64,
            Flops::CENTERED,
        ),
        (
            "star L2 discrepancy² (metric)",
            DiscrepancyKind::StarL2,
            metrics::star_l2_squared,
            Flops::STAR,
        ),
    ] {
        let base = median_time(1, || {
            std::hint::black_box(naive_discrepancy_squared(&x, kind));
        });
        let (one, two) = both(reps.min(5), || {
            std::hint::black_box(f(&x));
        });
        let t = Timing {
            baseline: Some(base),
            one,
            two,
        };
        row(
            out,
            name,
            n_disc,
            20,
            "closed form, all ordered pairs, 1 thread",
            &t,
            flops,
            peak,
        )?;
    }
    let x = sequences::halton(n_uqp, 20).expect("halton");
    let e = DiscrepancyEnergy::new(DiscrepancyKind::ModifiedL2);
    let (one, two) = both(reps, || {
        let mut g = vec![0.0; x.coordinate_count()];
        std::hint::black_box(e.value_and_gradient(&x, &mut g));
    });
    let t = Timing {
        baseline: None,
        one,
        two,
    };
    row(
        out,
        "modified L2² energy, value+gradient",
        n_uqp,
        20,
        "—",
        &t,
        Flops::MODIFIED_GRAD,
        peak,
    )?;
    let metric_sizes: &[(usize, usize)] = if quick {
        &[(1500, 2), (1500, 20)]
    } else {
        &[(1500, 20), (10_000, 2), (10_000, 20)]
    };
    for &(n, s) in metric_sizes {
        let x = sequences::halton(n, s).expect("halton");
        let (one, two) = both(reps.min(5), || {
            std::hint::black_box(Metrics::compute(&x));
        });
        let t = Timing {
            baseline: Some(one),
            one,
            two,
        };
        let name = "all metrics (4 discrepancies, 2 min distances)";
        row(
            out,
            name,
            n,
            s,
            "same code, 1 thread",
            &t,
            Flops::METRICS,
            peak,
        )?;
    }
    Ok(())
}

/// Nanoseconds per pair and coordinate as n grows: constant while the kernels are
/// compute-bound.
fn scaling_table(quick: bool, reps: usize, out: &mut dyn Write) -> std::io::Result<()> {
    let (q, p) = (0.3, 0.8);
    let ns: &[usize] = if quick {
        &[250, 500, 1000, 2000]
    } else {
        &[500, 1500, 5000, 20_000]
    };
    writeln!(
        out,
        "\nScaling (2 threads): nanoseconds per pair per coordinate; constant when compute-bound.\n"
    )?;
    write!(out, "| kernel | s |")?;
    for n in ns {
        write!(out, " n = {n} |")?;
    }
    writeln!(out)?;
    writeln!(out, "|---|---|{}", "---|".repeat(ns.len()))?;
    let uqp_s = 5;
    for precision in [Precision::Full, Precision::Fast] {
        let label = match precision {
            Precision::Full => "",
            Precision::Fast => ", fast",
        };
        write!(
            out,
            "| U_{{q,p}} value+gradient, q=0.3, p=0.8{label} | {uqp_s} |"
        )?;
        let e = Uqp::new(Distance::Q(q), p)
            .expect("energy")
            .with_precision(precision);
        for &n in ns {
            let x = sequences::halton(n, uqp_s).expect("halton");
            let r = if n > 5000 { 3 } else { reps };
            let t = on_threads(2, || {
                median_time(r, || {
                    let mut g = vec![0.0; x.coordinate_count()];
                    std::hint::black_box(e.value_and_gradient(&x, &mut g));
                })
            });
            write!(out, " {:.3} |", t * 1e9 / (pairs(n) * uqp_s as f64))?;
        }
        writeln!(out)?;
    }
    write!(out, "| star L2 discrepancy² | 20 |")?;
    for &n in ns {
        let x = sequences::halton(n, 20).expect("halton");
        let r = if n > 5000 { 3 } else { reps };
        let t = on_threads(2, || {
            median_time(r, || {
                std::hint::black_box(metrics::star_l2_squared(&x));
            })
        });
        write!(out, " {:.3} |", t * 1e9 / (pairs(n) * 20.0))?;
    }
    writeln!(out)?;
    Ok(())
}

/// The processor's model name, when the system says it.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown processor".into())
}

/// Times the squared centred L2 and the star L2 discrepancy of a point file (see the
/// module documentation) and prints one JSON object.
/// Points mode: the centred and star L2 discrepancies of a point file, timed (median of
/// `reps` runs after one warm-up), as one JSON object.
pub fn run_points(path: &std::path::Path, reps: usize, out: &mut dyn Write) -> std::io::Result<()> {
    let points = stillpoint::io::read_points(path)
        .map_err(|e| std::io::Error::other(format!("{}: {e}", path.display())))?;
    let reps = reps.max(1);
    // A first call outside the timing starts the thread pool.
    let mut cd = metrics::centered_l2_squared(&points);
    let t_cd = median_time(reps, || cd = metrics::centered_l2_squared(&points));
    let mut star = 0.0;
    let t_star = median_time(reps, || star = metrics::star_l2(&points));
    let v = serde_json::json!({
        "n": points.n(),
        "s": points.s(),
        "threads": rayon::current_num_threads(),
        "vector_path": vector_path(),
        "reps": reps,
        "centered_l2_squared": cd,
        "centered_seconds": t_cd,
        "star_l2": star,
        "star_seconds": t_star,
    });
    writeln!(out, "{v}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn naive_kernel_agrees_with_the_library() {
        let x = sequences::random(40, 3, 1).unwrap();
        let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
        let mut g1 = vec![0.0; x.coordinate_count()];
        let mut g2 = vec![0.0; x.coordinate_count()];
        let u1 = e.value_and_gradient(&x, &mut g1);
        let u2 = naive_uqp_gradient(&x, 0.3, 0.8, &mut g2);
        assert!((u1 - u2).abs() < 1e-12 * u1);
        for (a, b) in g1.iter().zip(&g2) {
            assert!((a - b).abs() < 1e-10 * b.abs().max(1e-3), "{a} {b}");
        }
    }

    #[test]
    fn naive_discrepancies_agree_with_the_metrics() {
        let x = sequences::random(60, 4, 2).unwrap();
        type Squared = fn(&PointSet) -> f64;
        let cases: [(DiscrepancyKind, Squared); 4] = [
            (DiscrepancyKind::StarL2, metrics::star_l2_squared),
            (DiscrepancyKind::ModifiedL2, metrics::modified_l2_squared),
            (DiscrepancyKind::CenteredL2, metrics::centered_l2_squared),
            (
                DiscrepancyKind::WrapAroundL2,
                metrics::wrap_around_l2_squared,
            ),
        ];
        for (kind, f) in cases {
            let (a, b) = (naive_discrepancy_squared(&x, kind), f(&x));
            assert!(
                (a - b).abs() < 1e-12 * b.abs().max(1e-6),
                "{kind:?}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn peak_kernel_runs() {
        assert!(fma_block(10, 0.0).is_finite());
    }
}
