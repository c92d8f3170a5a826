//! Frame times while the pen pinches a draped cloth and swings it, as a designer does:
//! `cargo run --release -p sim-core --example pinch_frames -- DESIGN.saiho [FRAMES]
//! [THREADS]`. The pinch takes the vertex nearest the chest's front (0.01, 1.34, 0.19)
//! within 5 cm with cloth-sim's default spring (100 N/m) and swings it 10 cm either way
//! along x, once every two seconds; prints the frames' p50, p90 and max and the
//! guard's searches.

#![allow(clippy::unwrap_used)] // a tool: a failure should stop it

use std::time::Instant;

use glam::Vec3;
use sim_core::design::Design;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: pinch_frames DESIGN.saiho [FRAMES] [THREADS]");
    let frames: usize = args.get(2).map_or(120, |s| s.parse().unwrap());
    let threads: usize = args.get(3).map_or(2, |s| s.parse().unwrap());
    let mut d = Design::load_design_file(std::path::Path::new(path)).unwrap();
    d.sim.set_threads(threads);
    let at = Vec3::new(0.01, 1.34, 0.19);
    d.pinch_begin(at, 0.05, 0.0, 100.0).unwrap();
    let mut times = Vec::with_capacity(frames);
    let (mut search_ms, mut pairs) = (Vec::new(), Vec::new());
    for f in 0..frames {
        let phase = f as f32 / 120.0 * std::f32::consts::TAU;
        d.pinch_move(at + Vec3::X * 0.1 * phase.sin());
        let t = Instant::now();
        let stats = d.step().unwrap();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        search_ms.push(stats.collision_ms);
        pairs.push(stats.queries);
    }
    d.pinch_end();
    let median = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        (s[s.len() / 2], s[s.len() * 9 / 10], s[s.len() - 1])
    };
    let (p50, p90, max) = median(&times);
    let (s50, ..) = median(&search_ms);
    let (q50, ..) = median(&pairs.iter().map(|&p| p as f64).collect::<Vec<_>>());
    println!(
        "pinched frames: {frames} on {threads} threads: p50 {p50:.1} ms, p90 {p90:.1} ms, \
         max {max:.1} ms; the search's share p50 {s50:.1} ms; pairs p50 {q50:.0}"
    );
}
