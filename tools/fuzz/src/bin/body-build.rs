//! `cargo afl fuzz ... target/release/body-build`: see `saiho_fuzz::body_build`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::body_build(data));
}
