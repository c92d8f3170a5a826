//! `cargo afl fuzz ... target/release/commands`: see `saiho_fuzz::commands`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::commands(data));
}
