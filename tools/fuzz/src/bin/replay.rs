//! `cargo afl fuzz ... target/release/replay`: see `saiho_fuzz::replay`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::replay(data));
}
