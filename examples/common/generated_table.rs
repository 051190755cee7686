//! What the examples that regenerate a tabulated generating vector share: the Rust
//! source of the table they print to standard output.

/// Prints `header` (comment lines saying how the table was made) and `z` as the
/// `GENERATOR` constant a sequences/src/*_table.rs file holds, eight entries a line.
pub fn print_generator(header: &str, z: &[u32]) {
    println!("{header}");
    println!("pub(super) const GENERATOR: [u32; {}] = [", z.len());
    for row in z.chunks(8) {
        let items: Vec<String> = row.iter().map(|v| format!("{v},")).collect();
        println!("    {}", items.join(" "));
    }
    println!("];");
}
