//! Time and criterion of the tent lattice's generating vector, fast (every candidate) against
//! the plain search it replaced (a sample of the candidates above 2^28 point steps per
//! coordinate), at each (n, s) given; one line per (n, s) and method, median of `reps` runs.
//! `cargo run --release -p stillpoint --example cbc_timing -- [REPS] [N×S ...]`, by default
//! `3 100000x20 200000x50 1000000x50`.

use std::time::Instant;

use stillpoint::sequences::{tent_criterion, tent_lattice_generator, tent_lattice_generator_plain};

type Construction = fn(usize, usize) -> Result<Vec<u64>, stillpoint::Error>;

fn main() -> Result<(), stillpoint::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bad = |what: &str| stillpoint::Error::invalid(what, "malformed", "REPS N×S ...");
    let reps: usize = match args.first() {
        Some(a) => a.parse().map_err(|_| bad("REPS"))?,
        None => 3,
    };
    let shapes: Vec<(usize, usize)> = if args.len() > 1 {
        args[1..]
            .iter()
            .map(|a| {
                let (n, s) = a.split_once('x').ok_or_else(|| bad("N×S"))?;
                Ok((
                    n.parse().map_err(|_| bad("N"))?,
                    s.parse().map_err(|_| bad("S"))?,
                ))
            })
            .collect::<Result<_, stillpoint::Error>>()?
    } else {
        vec![(100_000, 20), (200_000, 50), (1_000_000, 50)]
    };
    println!(
        "threads {}; median of {reps} runs",
        std::thread::available_parallelism().map_or(1, |p| p.get())
    );
    for (n, s) in shapes {
        let mut criteria = Vec::new();
        let methods: [(&str, Construction); 2] = [
            ("fast", tent_lattice_generator),
            ("plain", tent_lattice_generator_plain),
        ];
        for (name, make) in methods {
            let mut times = Vec::new();
            let mut z = Vec::new();
            for _ in 0..reps {
                let t = Instant::now();
                z = make(n, s)?;
                times.push(t.elapsed().as_secs_f64());
            }
            times.sort_by(f64::total_cmp);
            let e = tent_criterion(n, &z)?;
            criteria.push(e);
            println!(
                "n {n:>8} s {s:>3} {name:<5} {:>8.3} s  criterion {e:.4e}",
                times[times.len() / 2]
            );
        }
        println!(
            "n {n:>8} s {s:>3} criterion fast/plain {:.4}",
            criteria[0] / criteria[1]
        );
    }
    Ok(())
}
