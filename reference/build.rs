//! Compiles the CGAL drivers (`cgal/dt3.cpp`, `cgal/mesh3.cpp`) when CGAL's headers are present.
//!
//! Without CGAL the crate still builds: the `has_cgal` cfg stays unset and
//! the `cgal-dt3` and `cgal-mesh3` binaries become stubs that report the missing dependency.
//!
//! `mesh3.cpp` (Mesh_3) takes about 1.5 minutes and 3.4 GB to compile, so it is its own
//! static library, cached under `target/<dir>/build/cgal-mesh3-cache/` and reused while
//! its source and flags are unchanged (the build script reruns whenever any driver
//! changes, and each profile runs it separately).
use std::path::{Path, PathBuf};

/// Compiler settings of [`build`], part of the Mesh_3 cache key: keep them in sync.
const FLAGS: &str = "c++17 -O2 -DNDEBUG -g0 -pipe";

fn main() {
    println!("cargo::rustc-check-cfg=cfg(has_cgal)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=cgal/dt3.cpp");
    println!("cargo::rerun-if-changed=cgal/mesh3.cpp");
    println!("cargo::rerun-if-env-changed=CGAL_INCLUDE_DIR");

    let include = std::env::var_os("CGAL_INCLUDE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/include"));
    for header in [
        "CGAL/Delaunay_triangulation_3.h",
        "CGAL/Polyhedral_mesh_domain_with_features_3.h",
    ] {
        let header = include.join(header);
        if !header.exists() {
            println!(
                "cargo::warning=CGAL headers not found ({}): cgal-dt3 and cgal-mesh3 will be stubs; run scripts/setup.sh",
                header.display()
            );
            return;
        }
    }

    build(&include).file("cgal/dt3.cpp").compile("ref_cgal_dt3");
    compile_mesh3(&include);
    println!("cargo::rustc-link-lib=gmp");
    println!("cargo::rustc-link-lib=mpfr");
    println!("cargo::rustc-cfg=has_cgal");
}

fn build(include: &Path) -> cc::Build {
    let mut b = cc::Build::new();
    b.cpp(true)
        .std("c++17")
        .include(include)
        .opt_level(2)
        .define("NDEBUG", None)
        // No debug info: with it Mesh_3's object is ~130 MB and the assembler file gcc
        // writes to /tmp on the way is larger still, which once filled a CI machine's
        // disk. -pipe keeps that intermediate file off the disk altogether.
        .debug(false)
        .flag_if_supported("-pipe")
        // CGAL headers are noisy under -Wall; the drivers themselves are tiny.
        .warnings(false);
    b
}

/// Builds `libref_cgal_mesh3.a` unless a cached archive matches source and flags.
///
/// The cache sits beside the per-profile build folders (`target/<dir>/build/`), so the
/// dev, test and check profiles, which each get their own `OUT_DIR`, share one compile.
/// Archives are named by a hash of source, flags and include folder.
fn compile_mesh3(include: &Path) {
    use std::hash::{Hash, Hasher};
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let source = std::fs::read_to_string("cgal/mesh3.cpp").expect("cgal/mesh3.cpp is readable");
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (FLAGS, include, &source).hash(&mut hasher);
    let cached = out.ancestors().nth(2).map(|b| {
        b.join(format!(
            "cgal-mesh3-cache/libref_cgal_mesh3-{:016x}.a",
            hasher.finish()
        ))
    });
    let archive = out.join("libref_cgal_mesh3.a");
    if let Some(cached) = cached.as_deref().filter(|c| c.is_file()) {
        if std::fs::copy(cached, &archive).is_ok() {
            println!("cargo::rustc-link-search=native={}", out.display());
            println!("cargo::rustc-link-lib=static=ref_cgal_mesh3");
            return;
        }
    }
    build(include)
        .file("cgal/mesh3.cpp")
        .compile("ref_cgal_mesh3");
    if let Some((cached, dir)) = cached.as_deref().and_then(|c| Some((c, c.parent()?))) {
        // Best effort (a failure only costs a compile next time); the rename makes the
        // archive appear whole to a concurrent build script.
        let tmp = dir.join(format!("tmp-{}", std::process::id()));
        let _ = std::fs::create_dir_all(dir)
            .and_then(|_| std::fs::copy(&archive, &tmp))
            .and_then(|_| std::fs::rename(&tmp, cached));
    }
}
