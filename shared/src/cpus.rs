//! Which CPUs each process runs on. On a machine with two or more CPUs the haptic loop gets
//! one of its own (the highest this process may use) and the other processes keep off it,
//! so the 1 kHz tick never waits behind a cloth frame or a software-rendered UI.

use rustix::thread::{CpuSet, sched_getaffinity, sched_setaffinity};

/// The CPUs this process may run on, in order.
pub fn allowed() -> Vec<usize> {
    match sched_getaffinity(None) {
        Ok(set) => (0..CpuSet::MAX_CPU).filter(|&c| set.is_set(c)).collect(),
        Err(_) => (0..std::thread::available_parallelism().map_or(1, |n| n.get())).collect(),
    }
}

/// The haptic loop's CPU and the others' CPUs: the highest allowed CPU for the loop and
/// the rest for everything else, or no plan on a single CPU.
pub fn plan() -> Option<(usize, Vec<usize>)> {
    let cpus = allowed();
    let (&haptic, rest) = cpus.split_last()?;
    (!rest.is_empty()).then(|| (haptic, rest.to_vec()))
}

/// Whether a process started from this one may take SCHED_FIFO at `priority`: CAP_SYS_NICE
/// in its effective set (root's, unless a container dropped it), or an RLIMIT_RTPRIO of
/// `priority` or more (a user in a real-time group; docs in the README, "Real time").
pub fn fifo_permitted(priority: u32) -> bool {
    const CAP_SYS_NICE: u32 = 23;
    let caps = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let hex = s.lines().find_map(|l| l.strip_prefix("CapEff:"))?;
            u64::from_str_radix(hex.trim(), 16).ok()
        })
        .unwrap_or(0);
    let limit = rustix::process::getrlimit(rustix::process::Resource::Rtprio).current;
    caps & (1 << CAP_SYS_NICE) != 0 || limit.is_none_or(|l| l >= u64::from(priority))
}

/// Parses a CPU list such as `0`, `0,2` or `0-3`.
pub fn parse_list(s: &str) -> Result<Vec<usize>, String> {
    let mut out = Vec::new();
    for part in s.split(',').map(str::trim) {
        let bad = || format!("'{s}' is not a CPU list (such as 0, 0,2 or 0-3)");
        match part.split_once('-') {
            Some((a, b)) => {
                let (a, b): (usize, usize) =
                    (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
                if a > b {
                    return Err(bad());
                }
                out.extend(a..=b);
            }
            None => out.push(part.parse().map_err(|_| bad())?),
        }
    }
    Ok(out)
}

/// A CPU list as `parse_list` reads it.
pub fn format_list(cpus: &[usize]) -> String {
    cpus.iter()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

/// Keeps this thread, and the threads it starts from now on, on `cpus`; every CPU must be
/// one this process may use.
pub fn keep_on(cpus: &[usize]) -> Result<(), String> {
    let allowed = allowed();
    if let Some(c) = cpus.iter().find(|c| !allowed.contains(c)) {
        return Err(format!(
            "CPU {c} is not one this process may use ({})",
            format_list(&allowed)
        ));
    }
    if cpus.is_empty() {
        return Err("the CPU list is empty".into());
    }
    let mut set = CpuSet::new();
    for &c in cpus {
        set.set(c);
    }
    sched_setaffinity(None, &set)
        .map_err(|e| format!("cannot keep to CPUs {}: {e}", format_list(cpus)))
}

/// Lowers this thread's scheduling priority to niceness `nice` (0-19), for the threads it
/// starts from now on too: a process that must give way on a shared CPU (cloth-ui to
/// cloth-sim) calls it first thing. Raising priority needs privileges; lowering does not.
pub fn lower_priority(nice: i32) -> Result<(), String> {
    if !(0..=19).contains(&nice) {
        return Err(format!("niceness {nice} is out of range (0 to 19)"));
    }
    let now = rustix::process::getpriority_process(None).unwrap_or(0);
    if nice <= now {
        return Ok(());
    }
    rustix::process::setpriority_process(None, nice)
        .map_err(|e| format!("cannot lower the priority to niceness {nice}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn priority_is_only_ever_lowered() {
        assert!(lower_priority(20).is_err() && lower_priority(-1).is_err());
        // On a thread of its own, so the test's other threads keep their priority.
        let seen = std::thread::spawn(|| {
            lower_priority(7).expect("lowering needs no privilege");
            let a = rustix::process::getpriority_process(None).expect("read");
            // Asking for less than it has already changes nothing.
            lower_priority(3).expect("no-op");
            let b = rustix::process::getpriority_process(None).expect("read");
            let child = std::thread::spawn(|| rustix::process::getpriority_process(None))
                .join()
                .expect("join")
                .expect("read");
            (a, b, child)
        })
        .join()
        .expect("join");
        assert_eq!(seen, (7, 7, 7));
    }

    #[test]
    fn cpu_lists_read_and_print() {
        assert_eq!(parse_list("0").unwrap(), vec![0]);
        assert_eq!(parse_list("0,2-4").unwrap(), vec![0, 2, 3, 4]);
        assert!(parse_list("3-1").is_err() && parse_list("x").is_err() && parse_list("").is_err());
        assert_eq!(format_list(&[0, 2]), "0,2");
        // This process may use at least one CPU; the plan leaves the others one at least.
        let cpus = allowed();
        assert!(!cpus.is_empty());
        if let Some((h, rest)) = plan() {
            assert!(!rest.contains(&h) && rest.len() + 1 == cpus.len());
        }
        assert!(keep_on(&[usize::MAX - 1]).is_err());
    }
}
