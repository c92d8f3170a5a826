//! `cargo afl fuzz ... target/release/dxf`: see `saiho_fuzz::dxf`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::dxf(data));
}
