//! Fuzz target: arbitrary bytes through `lplace_fuzz::carmen`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| lplace_fuzz::carmen(data));
