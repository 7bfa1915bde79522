//! The fuzz targets' shared code: [`oracle`] decodes the fuzzer's bytes into inputs and
//! checks the properties (no panic is the fuzzer's own check). `mesher/tests/fuzz_regress.rs`
//! includes the same file to replay the committed regressions under `cargo test`.

pub mod oracle;
