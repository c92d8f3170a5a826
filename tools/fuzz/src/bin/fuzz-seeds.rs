//! `fuzz-seeds DIR`: writes each target's starting inputs under `DIR/TARGET/`.
fn main() {
    let Some(dir) = std::env::args().nth(1) else {
        eprintln!("usage: fuzz-seeds DIR");
        std::process::exit(2);
    };
    let dir = std::path::Path::new(&dir);
    if let Err(e) = saiho_fuzz::seeds::write_seeds(dir) {
        eprintln!("fuzz-seeds: {e}");
        std::process::exit(1);
    }
    // Say which seeds read (a seed that is refused only tries the refusals).
    let mut refused = 0;
    for (target, _) in saiho_fuzz::TARGETS {
        let Ok(entries) = std::fs::read_dir(dir.join(target)) else {
            continue;
        };
        for f in entries.filter_map(|e| e.ok()).map(|e| e.path()) {
            let bytes = std::fs::read(&f).unwrap_or_default();
            match saiho_fuzz::seeds::seed_reads(target, &bytes) {
                Ok(()) => println!("{}: reads", f.display()),
                Err(e) => {
                    refused += 1;
                    println!("{}: REFUSED: {e}", f.display());
                }
            }
        }
    }
    if refused > 0 {
        std::process::exit(1);
    }
}
