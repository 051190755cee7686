//! Prints the default lattice's generating vector and its smoothness-2 criterion at the
//! sizes where the fast search's scores cannot resolve that criterion (see
//! results/large-n/vector_ties.md): `cargo run --release -p stillpoint --example vector_ties -- N S`.

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("N and S as whole numbers"))
        .collect();
    let (n, s) = (
        args.first().copied().unwrap_or(65_536),
        args.get(1).copied().unwrap_or(2),
    );
    let z = stillpoint::sequences::tent_lattice_generator(n, s).expect("n, s ≥ 1");
    println!("n = {n}, s = {s}: z = {z:?}");
}
