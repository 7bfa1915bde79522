//! The whole mesher on small closed surfaces decoded from arbitrary bytes (perturbed
//! icospheres and boxes, scaled, offset, triangles flipped): a valid mesh with the
//! enclosed volume, or a typed error.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mesher_fuzz::oracle::mesh(data));
