//! The `stillpoint` command; everything it does lives in the library's `cli` module.

fn main() {
    stillpoint::cli::main()
}
