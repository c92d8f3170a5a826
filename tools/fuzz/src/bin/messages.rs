//! `cargo afl fuzz ... target/release/messages`: see `saiho_fuzz::messages`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::messages(data));
}
