//! cyclictest beside the faults, read as a timeline: when each CPU was held and for how
//! long, so that a cloth-sim stall can be set beside what the host did at that moment.
//!
//! cyclictest (`-v`) prints every wakeup of its thread on each CPU as `thread:cycle:
//! latency` (µs). Its wakeups are planned a millisecond apart on the absolute clock, and a
//! wakeup `L` late makes it skip the planned times already past, so the plan of each
//! wakeup follows from the latencies before it: the timeline is rebuilt exactly, up to
//! where the first plan lies (the thread's start, a few milliseconds after the spawn).

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::thread::JoinHandle;

/// cyclictest's interval, ns.
const INTERVAL_NS: u64 = 1_000_000;
/// Wakeups at least this late are kept as "held" spans, ns.
const HELD_NS: u64 = 5_000_000;

/// One CPU's wakeups, as they are read.
#[derive(Clone, Debug, Default)]
struct Cpu {
    /// The next wakeup's planned time from the first plan, ns.
    plan: u64,
    /// The cycle the next line should have.
    next_cycle: u64,
    max_us: u64,
    /// A cycle was missing (cyclictest's buffer overflowed): the plan is lost from here.
    broken: bool,
}

/// What cyclictest saw beside the run.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct HostTimeline {
    /// The worst wakeup per CPU, µs.
    pub max_us: Vec<u64>,
    /// Spans during which a CPU was held, 5 ms or longer: (cpu, from, to), monotonic ns
    /// (from the spawn: the first plan is a few ms later, so these read a little early).
    pub held: Vec<(usize, u64, u64)>,
}

impl HostTimeline {
    /// Reads cyclictest's verbose lines; `start` is when it was spawned (monotonic ns).
    fn read(lines: impl Iterator<Item = String>, start: u64) -> Self {
        let mut cpus: Vec<Cpu> = Vec::new();
        let mut t = Self::default();
        for l in lines {
            let mut f = l.split(':').map(str::trim);
            let (Some(a), Some(b), Some(c), None) = (f.next(), f.next(), f.next(), f.next()) else {
                continue;
            };
            let (Ok(k), Ok(cycle), Ok(lat_us)) =
                (a.parse::<usize>(), b.parse::<u64>(), c.parse::<u64>())
            else {
                continue;
            };
            if k >= 256 {
                continue;
            }
            if cpus.len() <= k {
                cpus.resize(k + 1, Cpu::default());
            }
            let cpu = &mut cpus[k];
            cpu.max_us = cpu.max_us.max(lat_us);
            if cycle != cpu.next_cycle {
                cpu.broken = true;
            }
            cpu.next_cycle = cycle + 1;
            if cpu.broken {
                continue;
            }
            // The first plan is one interval after the thread's start.
            let planned = start + INTERVAL_NS + cpu.plan;
            let lat = lat_us * 1000;
            if lat >= HELD_NS {
                t.held.push((k, planned, planned + lat));
            }
            // The next plan: the first one not already past at the wakeup.
            cpu.plan += INTERVAL_NS * (lat / INTERVAL_NS + 1);
        }
        t.max_us = cpus.iter().map(|c| c.max_us).collect();
        t
    }

    /// The longest time any one CPU was held within `from..to` (monotonic ns), ms, and
    /// that CPU; `None` when none was held 5 ms or more there.
    pub fn held_within(&self, from: u64, to: u64) -> Option<(f64, usize)> {
        self.held
            .iter()
            .map(|&(k, a, b)| (b.min(to).saturating_sub(a.max(from)), k))
            .filter(|&(ns, _)| ns > 0)
            .max()
            .map(|(ns, k)| (ns as f64 * 1e-6, k))
    }
}

/// cyclictest running beside the faults, verbose, a thread on every CPU, one priority
/// above the haptic loop (on the loop's CPU it would otherwise wait behind the loop's
/// spinning; it takes a few microseconds a millisecond from the loop): the machine's floor
/// under the same load, in the same run, on the CPU the loop runs on too. A VM's host can
/// hold one CPU for milliseconds while the other runs.
pub(super) struct Beside {
    child: Child,
    reader: JoinHandle<HostTimeline>,
}

impl Beside {
    pub fn start() -> Option<Self> {
        let start = shared::monotonic_ns();
        let mut child = Command::new("cyclictest")
            .args(["-v", "-m", "-S", "-d", "0", "-p", "81", "-i", "1000"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .ok()?;
        let out = child.stdout.take()?;
        // Read to the end whatever the bytes: a reader that stopped early would close the
        // pipe, and cyclictest, killed by SIGPIPE, would leave its /dev/shm status file.
        let reader = std::thread::spawn(move || {
            let lines = BufReader::new(out)
                .split(b'\n')
                .map_while(Result::ok)
                .map(|l| String::from_utf8_lossy(&l).into_owned());
            HostTimeline::read(lines, start)
        });
        Some(Self { child, reader })
    }

    /// Stops cyclictest (SIGINT) and returns what it saw.
    pub fn end(mut self) -> HostTimeline {
        let pid = rustix::process::Pid::from_child(&self.child);
        let _ = rustix::process::kill_process(pid, rustix::process::Signal::INT);
        let _ = self.child.wait();
        self.reader.join().unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(s: &str) -> impl Iterator<Item = String> + '_ {
        s.lines().map(String::from)
    }

    #[test]
    fn wakeups_are_placed_on_the_plan_they_kept() {
        // CPU 0 on time, then 40 ms late at cycle 2 (the plans at 4-41 ms are skipped),
        // then on time; CPU 1 on time throughout.
        let text = "Thread 0 Interval: 1000\n\
            # /dev/cpu_dma_latency set to 0us\n\
                   0:       0:      12\n\
                   1:       0:      15\n\
                   0:       1:      11\n\
                   0:       2:   40000\n\
                   1:       1:      14\n\
                   0:       3:       9\n\
                   0:       4:    6500\n";
        let t = HostTimeline::read(lines(text), 1_000_000_000);
        assert_eq!(t.max_us, vec![40_000, 15]);
        let ms = 1_000_000;
        // Cycle 2 was planned at 3 ms (the first plan is 1 ms in), woke at 43 ms; cycle 3
        // was planned at 44 ms, cycle 4 at 45 ms.
        assert_eq!(
            t.held,
            vec![
                (0, 1_000_000_000 + 3 * ms, 1_000_000_000 + 43 * ms),
                (0, 1_000_000_000 + 45 * ms, 1_000_000_000 + 51 * ms + ms / 2)
            ]
        );
        let s = 1_000_000_000;
        assert_eq!(t.held_within(s, s + 20 * ms), Some((17.0, 0)));
        assert_eq!(t.held_within(s + 60 * ms, s + 90 * ms), None);
    }

    #[test]
    fn a_missing_cycle_ends_the_timeline_not_the_maximum() {
        let text = "       0:       0:      12\n\
                   0:       2:    9000\n\
                   0:       3:   70000\n";
        let t = HostTimeline::read(lines(text), 0);
        assert_eq!(t.max_us, vec![70_000]);
        assert!(t.held.is_empty());
        assert_eq!(
            HostTimeline::read(lines("garbage\n1:2\n"), 0),
            HostTimeline::default()
        );
    }
}
