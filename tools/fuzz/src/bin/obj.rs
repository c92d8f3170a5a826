//! `cargo afl fuzz ... target/release/obj`: see `saiho_fuzz::obj`.
fn main() {
    afl::fuzz!(|data: &[u8]| saiho_fuzz::obj(data));
}
