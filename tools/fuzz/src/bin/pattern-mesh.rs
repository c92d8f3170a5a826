//! `cargo afl fuzz ... target/release/pattern-mesh`: see `saiho_fuzz::pattern_file_mesh`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::pattern_file_mesh(data));
}
