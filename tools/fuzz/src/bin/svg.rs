//! `cargo afl fuzz ... target/release/svg`: see `saiho_fuzz::svg`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::svg(data));
}
