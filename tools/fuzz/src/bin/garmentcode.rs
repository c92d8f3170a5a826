//! `cargo afl fuzz ... target/release/garmentcode`: see `saiho_fuzz::garmentcode`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::garmentcode(data));
}
