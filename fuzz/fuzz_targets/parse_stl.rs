//! The stl surface parser on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mesher::io::SurfaceFormat;

fuzz_target!(|data: &[u8]| mesher_fuzz::oracle::parse(SurfaceFormat::Stl, data));
