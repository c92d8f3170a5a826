//! `fuzz-run TARGET FILE|DIR...`: runs a target over files without AFL (a corpus, or a
//! crash AFL found), saying which file it is on, so a panic names its input.
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((name, paths)) = args.split_first() else {
        eprintln!("usage: fuzz-run TARGET FILE|DIR...");
        std::process::exit(2);
    };
    let Some((_, target)) = saiho_fuzz::TARGETS.iter().find(|(n, _)| n == name) else {
        let names: Vec<&str> = saiho_fuzz::TARGETS.iter().map(|t| t.0).collect();
        eprintln!("unknown target {name}; targets: {}", names.join(", "));
        std::process::exit(2);
    };
    let mut files = Vec::new();
    for p in paths {
        let p = std::path::PathBuf::from(p);
        match std::fs::read_dir(&p) {
            Ok(dir) => files.extend(dir.filter_map(|e| e.ok()).map(|e| e.path())),
            Err(_) => files.push(p),
        }
    }
    files.sort();
    // FUZZ_REPEAT=N runs each input N times and prints the time per run.
    let repeat: u32 = std::env::var("FUZZ_REPEAT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    for f in &files {
        match std::fs::read(f) {
            Ok(bytes) => {
                eprintln!("{}", f.display());
                let t = std::time::Instant::now();
                for _ in 0..repeat.max(1) {
                    target(&bytes);
                }
                if repeat > 1 {
                    eprintln!(
                        "  {:.3} ms a run",
                        t.elapsed().as_secs_f64() * 1e3 / repeat as f64
                    );
                }
            }
            Err(e) => eprintln!("{}: {e}", f.display()),
        }
    }
    eprintln!("{} inputs, no panic", files.len());
}
