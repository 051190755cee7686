//! Prints the generating vector of `weighted_lattice_generator` for the path study of
//! benches/uq_rules.py (candidates `wl…`), which has no other way to reach it:
//! `weighted_lattice N tent|first WEIGHTS_FILE` (weights separated by white space).

use stillpoint_sequences::{weighted_lattice_generator, LatticeKernel};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: weighted_lattice N tent|first WEIGHTS_FILE";
    if args.len() != 4 {
        eprintln!("{usage}");
        std::process::exit(2);
    }
    let fail = |what: String| -> ! {
        eprintln!("weighted_lattice: {what}");
        std::process::exit(2)
    };
    let n: usize = args[1]
        .parse()
        .unwrap_or_else(|_| fail(format!("N: expected a count, got {:?}", args[1])));
    let kernel = match args[2].as_str() {
        "tent" => LatticeKernel::Tent,
        "first" => LatticeKernel::FirstOrder,
        other => fail(format!("kernel: expected tent or first, got {other:?}")),
    };
    let text = std::fs::read_to_string(&args[3])
        .unwrap_or_else(|e| fail(format!("WEIGHTS_FILE {:?}: {e}", args[3])));
    let weights: Vec<f64> = text
        .split_whitespace()
        .map(|w| {
            w.parse()
                .unwrap_or_else(|_| fail(format!("WEIGHTS_FILE: not a number: {w:?}")))
        })
        .collect();
    match weighted_lattice_generator(n, &weights, kernel) {
        Ok(z) => println!(
            "{}",
            z.iter().map(u64::to_string).collect::<Vec<_>>().join(" ")
        ),
        Err(e) => fail(e.to_string()),
    }
}
