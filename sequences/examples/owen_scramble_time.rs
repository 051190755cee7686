//! Times Owen-scrambled Sobol' ranges of the sizes `quad` and the Sobol' indices ask
//! for (a replicate's next 32–1 024 points) and of a whole set, in nanoseconds per
//! coordinate, and four scrambles of one range made together (as `quad`'s four
//! replicates are) against one at a time. Beside each case the same range of a sequence
//! never taken past 2^20 points (`sobol_scrambled_short_ranges`, what `quad` and the
//! Sobol' indices scramble: the levels below 20 from one hash per point) and its time
//! over the whole sequence's scramble. Run it twice to compare the vector build with the portable one (the same
//! bits):
//!
//! ```text
//! cargo run --release -p stillpoint-sequences --example owen_scramble_time
//! STILLPOINT_PORTABLE=1 cargo run --release -p stillpoint-sequences --example owen_scramble_time
//! ```

use std::time::Instant;

fn main() {
    let cases = [
        (0usize, 32usize, 8usize),
        (0, 128, 5),
        (128, 128, 5),
        (1024, 1024, 5),
        (0, 512, 32),
        (0, 65_536, 8),
    ];
    for (start, n, s) in cases {
        // Enough repetitions for about 10⁸ coordinates' worth of work per case.
        let reps = (100_000_000 / (n * s)).clamp(5, 20_000);
        let t = Instant::now();
        for seed in 0..reps as u64 {
            let p = stillpoint_sequences::sobol_scrambled_range(start, start + n, s, seed)
                .expect("a valid range");
            std::hint::black_box(p);
        }
        let per = t.elapsed().as_secs_f64() / reps as f64;
        let t = Instant::now();
        for seed in 0..reps as u64 {
            let p = stillpoint_sequences::sobol_scrambled_short_ranges(
                start,
                start + n,
                s,
                &[seed],
                1 << 20,
            )
            .expect("a valid range");
            std::hint::black_box(p);
        }
        let short = t.elapsed().as_secs_f64() / reps as f64;
        println!(
            "points {start}..{} in {s} dimensions: {:.3} ms, {:.1} ns a coordinate; \
             of a sequence of at most 2^20 points {:.1} ns ({:.2}×)",
            start + n,
            per * 1e3,
            per * 1e9 / (n * s) as f64,
            short * 1e9 / (n * s) as f64,
            short / per
        );
    }
    let (start, n, s) = (1024usize, 1024usize, 8usize);
    let reps = 2_000;
    let t = Instant::now();
    for seed in 0..reps as u64 {
        for r in 0..4 {
            let p = stillpoint_sequences::sobol_scrambled_range(start, start + n, s, 4 * seed + r)
                .expect("a valid range");
            std::hint::black_box(p);
        }
    }
    let alone = t.elapsed().as_secs_f64() / reps as f64;
    let t = Instant::now();
    for seed in 0..reps as u64 {
        let seeds = [4 * seed, 4 * seed + 1, 4 * seed + 2, 4 * seed + 3];
        let p = stillpoint_sequences::sobol_scrambled_ranges(start, start + n, s, &seeds)
            .expect("a valid range");
        std::hint::black_box(p);
    }
    let together = t.elapsed().as_secs_f64() / reps as f64;
    println!(
        "4 scrambles of points {start}..{} in {s} dimensions: {:.3} ms one at a time, \
         {:.3} ms together ({:.2}×)",
        start + n,
        alone * 1e3,
        together * 1e3,
        together / alone
    );
}
