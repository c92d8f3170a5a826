//! `cargo afl fuzz ... target/release/outline`: see `saiho_fuzz::outline`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::outline(data));
}
