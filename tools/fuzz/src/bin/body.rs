//! `cargo afl fuzz ... target/release/body`: see `saiho_fuzz::body`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::body(data));
}
