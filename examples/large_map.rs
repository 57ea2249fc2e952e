//! Prints a generated map of N places (issue 16's scale maps): `cargo run --release --example
//! large_map -- 10000 > big.map`, then `lplace check big.map rules/office.lpl`.

fn main() {
    let n = std::env::args()
        .nth(1)
        .and_then(|a| a.parse::<usize>().ok())
        .unwrap_or(1000);
    print!("{}", lplace::sim::large_map::lattice_office(n, 1));
}
