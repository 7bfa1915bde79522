//! The `mesher` command line.
fn main() {}
