//! Compiles the CGAL driver (`cgal/dt3.cpp`) when CGAL's headers are present.
//!
//! Without CGAL the crate still builds: the `has_cgal` cfg stays unset and
//! the `cgal-dt3` binary becomes a stub that reports the missing dependency.
use std::path::PathBuf;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(has_cgal)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=cgal/dt3.cpp");
    println!("cargo::rerun-if-env-changed=CGAL_INCLUDE_DIR");

    let include = std::env::var_os("CGAL_INCLUDE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/include"));
    let header = include.join("CGAL/Delaunay_triangulation_3.h");
    if !header.exists() {
        println!(
            "cargo::warning=CGAL headers not found ({}): cgal-dt3 will be a stub; run scripts/setup.sh",
            header.display()
        );
        return;
    }

    cc::Build::new()
        .cpp(true)
        .std("c++17")
        .file("cgal/dt3.cpp")
        .include(&include)
        .opt_level(2)
        .define("NDEBUG", None)
        // CGAL headers are noisy under -Wall; the driver itself is tiny.
        .warnings(false)
        .compile("ref_cgal_dt3");
    println!("cargo::rustc-link-lib=gmp");
    println!("cargo::rustc-link-lib=mpfr");
    println!("cargo::rustc-cfg=has_cgal");
}
