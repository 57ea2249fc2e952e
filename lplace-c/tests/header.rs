//! `include/lplace.h` is what cbindgen makes of `src/lib.rs` today: the test regenerates it
//! and fails on any difference. After changing the API, run
//! `LPLACE_BLESS_HEADER=1 cargo test --release -p lplace-c --test header` and commit the header.

use std::path::Path;

#[test]
fn header_is_current() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml"))
        .expect("lplace-c/cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(crate_dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen generates the header");
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let fresh = String::from_utf8(fresh).expect("the header is UTF-8");
    let path = crate_dir.join("../include/lplace.h");
    if std::env::var_os("LPLACE_BLESS_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("include/lplace.h is writable");
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == fresh,
        "include/lplace.h is stale: regenerate it with \
         LPLACE_BLESS_HEADER=1 cargo test --release -p lplace-c --test header"
    );
}
