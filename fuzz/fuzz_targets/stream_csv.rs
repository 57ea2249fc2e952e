//! Fuzz target: arbitrary bytes read as a csv percept stream.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    lplace_fuzz::stream(data, lplace::io::stream::StreamFormat::Csv)
});
