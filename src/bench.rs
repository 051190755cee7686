//! `stillpoint bench`: times the energy and metric kernels and, in the same run, the
//! baselines they are compared with, and prints medians and ratios.
//!
//! Baselines: for U_{q,p} with its gradient, a straightforward one-thread kernel written
//! from eqs. 11 and 16 as printed (every power through `powf`, both halves of the pair
//! loop); for the metrics, the same code on one thread. Timings are wall-clock medians.

use crate::energies::{Distance, Energy, PointSet, Uqp};
use crate::metrics::Metrics;
use crate::sequences;
use std::io::Write;
use std::time::Instant;

/// Median wall time in seconds of `reps` calls (after one warm-up call).
fn median_time(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
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

fn on_threads<T: Send>(t: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .build()
        .expect("thread pool")
        .install(f)
}

/// Runs the benchmark and writes a Markdown table to `out`.
pub fn run(quick: bool, out: &mut dyn Write) -> std::io::Result<()> {
    let threads = rayon::current_num_threads();
    let reps = if quick { 3 } else { 7 };
    writeln!(
        out,
        "stillpoint bench ({} mode, {} threads available, medians of {} runs)\n",
        if quick { "quick" } else { "full" },
        threads,
        reps
    )?;
    writeln!(
        out,
        "| kernel | n | s | baseline | baseline ms | ours 1 thread ms | ours {threads} threads ms | vs baseline | {threads} threads vs 1 |"
    )?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|")?;
    let energy_sizes: &[(usize, usize)] = if quick {
        &[(500, 2), (500, 20)]
    } else {
        &[(1500, 2), (1500, 20)]
    };
    for &(n, s) in energy_sizes {
        let x = sequences::halton(n, s).expect("halton");
        let q = 0.3;
        let p = 0.8;
        let e = Uqp::new(Distance::Q(q), p).expect("energy");
        let mut g = vec![0.0; x.len()];
        let base = median_time(reps.min(3), || {
            std::hint::black_box(naive_uqp_gradient(&x, q, p, &mut g));
        });
        let one = on_threads(1, || {
            let mut g = vec![0.0; x.len()];
            median_time(reps, || {
                std::hint::black_box(e.value_and_gradient(&x, &mut g));
            })
        });
        let all = on_threads(threads, || {
            let mut g = vec![0.0; x.len()];
            median_time(reps, || {
                std::hint::black_box(e.value_and_gradient(&x, &mut g));
            })
        });
        writeln!(
            out,
            "| U_{{q,p}} value+gradient, q=0.3, p=0.8 | {n} | {s} | eqs. 11/16 as printed, 1 thread | {:.1} | {:.1} | {:.1} | {:.2}× | {:.2}× |",
            base * 1e3,
            one * 1e3,
            all * 1e3,
            base / all,
            one / all
        )?;
    }
    let metric_sizes: &[(usize, usize)] = if quick {
        &[(1500, 2), (1500, 20)]
    } else {
        &[(1500, 2), (1500, 20), (10_000, 2), (10_000, 20)]
    };
    for &(n, s) in metric_sizes {
        let x = sequences::halton(n, s).expect("halton");
        let r = if n > 5000 { reps.min(3) } else { reps };
        let one = on_threads(1, || {
            median_time(r, || {
                std::hint::black_box(Metrics::compute(&x));
            })
        });
        let all = on_threads(threads, || {
            median_time(r, || {
                std::hint::black_box(Metrics::compute(&x));
            })
        });
        writeln!(
            out,
            "| all metrics (4 discrepancies, 2 min distances) | {n} | {s} | same code, 1 thread | {:.1} | {:.1} | {:.1} | {:.2}× | {:.2}× |",
            one * 1e3,
            one * 1e3,
            all * 1e3,
            one / all,
            one / all
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn naive_kernel_agrees_with_the_library() {
        let x = sequences::random(40, 3, 1).unwrap();
        let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
        let mut g1 = vec![0.0; x.len()];
        let mut g2 = vec![0.0; x.len()];
        let u1 = e.value_and_gradient(&x, &mut g1);
        let u2 = naive_uqp_gradient(&x, 0.3, 0.8, &mut g2);
        assert!((u1 - u2).abs() < 1e-12 * u1);
        for (a, b) in g1.iter().zip(&g2) {
            assert!((a - b).abs() < 1e-10 * b.abs().max(1e-3), "{a} {b}");
        }
    }
}
