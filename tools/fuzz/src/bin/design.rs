//! `cargo afl fuzz ... target/release/design`: see `saiho_fuzz::design`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::design(data));
}
