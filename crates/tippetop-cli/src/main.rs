//! The `tippetop` command line.
fn main() {
    println!("tippetop {}", env!("CARGO_PKG_VERSION"));
}
