//! The generating vectors benches/extensible_prefix.py compares, as one JSON object:
//! the extensible sequence's (its first s components) and, for each n = 2^m given, the
//! lattice made for n alone (`tent_lattice_generator`).
//! `cargo run --release -p stillpoint --example extensible_prefix -- S M1,M2,...`.

fn main() -> Result<(), stillpoint::Error> {
    let args: Vec<String> = std::env::args().collect();
    let bad = |what: &str| stillpoint::Error::invalid(what, "missing or malformed", "S M1,M2,...");
    let s: usize = args
        .get(1)
        .and_then(|a| a.parse().ok())
        .ok_or_else(|| bad("S"))?;
    let levels: Vec<u32> = args
        .get(2)
        .ok_or_else(|| bad("M1,M2,..."))?
        .split(',')
        .map(|m| m.parse().map_err(|_| bad("M1,M2,...")))
        .collect::<Result<_, _>>()?;
    let seq = stillpoint::sequences::ExtensibleLattice::new(s, 0, 0)?;
    let mut single = Vec::new();
    for m in levels {
        let z = stillpoint::sequences::tent_lattice_generator(1 << m, s)?;
        let z: Vec<String> = z.iter().map(u64::to_string).collect();
        single.push(format!("\"{m}\": [{}]", z.join(", ")));
    }
    let ext: Vec<String> = seq.generator().iter().map(u32::to_string).collect();
    println!(
        "{{\"extensible\": [{}], \"single\": {{{}}}}}",
        ext.join(", "),
        single.join(", ")
    );
    Ok(())
}
