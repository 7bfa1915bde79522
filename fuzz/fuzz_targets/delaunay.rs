//! The Delaunay kernel on point sets decoded from arbitrary bytes (duplicates, huge and
//! tiny coordinates, coplanar and cospherical sets), validated after each batch.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mesher_fuzz::oracle::delaunay(data));
