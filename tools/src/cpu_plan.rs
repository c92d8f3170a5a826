//! Which CPUs cloth-lab gives its processes: the haptic loop one of its own (the highest
//! allowed, or `--cpu`), cloth-ui the others, cloth-sim the others too and two solver
//! threads where they are two or more. Where they are one (a two-CPU machine), the studio
//! is not running and the loop will get SCHED_FIFO, cloth-sim gets the loop's CPU as
//! well, for its second thread, which the loop preempts whenever it ticks: on this 2-CPU
//! VM the loop missed no more ticks, and a landing 128 x 128 cloth stepped 40-55% more
//! frames. Beside the studio it stepped 35% fewer: its threads, started for each parallel
//! pass, waited behind the software-rendered UI on the other CPU (docs/performance.md,
//! "Two CPUs").

/// The lab's CPUs, when real time is on and there are two or more.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// The haptic loop's CPU.
    pub haptic: usize,
    /// cloth-ui's (every allowed CPU but the loop's).
    pub others: Vec<usize>,
    /// cloth-sim's.
    pub sim: Vec<usize>,
}

impl Plan {
    /// The plan for the CPUs this process may use: none with real time off (`no_rt`) or
    /// one CPU; the loop on `cpu` if given (checked by the caller) or the highest;
    /// cloth-sim on the loop's CPU too only where it may `share` it (no studio).
    pub fn new(no_rt: bool, cpu: Option<usize>, rt_priority: u32, share: bool) -> Option<Self> {
        if no_rt {
            return None;
        }
        let allowed = shared::cpus::allowed();
        let (haptic, others) = match cpu {
            Some(c) => (
                c,
                allowed.into_iter().filter(|&x| x != c).collect::<Vec<_>>(),
            ),
            None => shared::cpus::plan()?,
        };
        if others.is_empty() {
            return None;
        }
        let mut sim = others.clone();
        if share && sim.len() == 1 && shared::cpus::fifo_permitted(rt_priority) {
            sim.push(haptic);
            sim.sort_unstable();
        }
        Some(Self {
            haptic,
            others,
            sim,
        })
    }

    /// cloth-sim's solver threads.
    pub fn sim_threads(&self) -> usize {
        threads_for(self.sim.len())
    }

    /// What the lab says about it, in one line.
    pub fn line(&self, rt_priority: u32) -> String {
        let threads = self.sim_threads();
        let plural = if threads > 1 { "s" } else { "" };
        let cpus = |list: &[usize]| {
            let s = if list.len() > 1 { "s" } else { "" };
            format!("CPU{s} {}", shared::cpus::format_list(list))
        };
        let h = self.haptic;
        let below = if self.sim.contains(&h) {
            format!(", below the loop on CPU {h}")
        } else {
            String::new()
        };
        format!(
            "asking real-time for haptic-loop (SCHED_FIFO {rt_priority} on CPU {h}); cloth-sim ({threads} thread{plural}) on {}{below}; cloth-ui on {}",
            cpus(&self.sim),
            cpus(&self.others)
        )
    }
}

/// cloth-sim's solver threads for `cpus` CPUs: two (its most) when it has two or more,
/// else one. Its frame is the same on either count; a sewn 2 x 8k dress at rest takes a
/// third less time on two.
pub fn threads_for(cpus: usize) -> usize {
    if cpus >= 2 { 2 } else { 1 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cloth_sim_shares_the_loops_cpu_only_where_it_would_have_one_and_no_studio() {
        assert_eq!(threads_for(1), 1);
        assert_eq!(threads_for(2), 2);
        assert_eq!(threads_for(15), 2);
        assert_eq!(Plan::new(true, None, 80, true), None);
        let allowed = shared::cpus::allowed();
        let Some(p) = Plan::new(false, None, 80, true) else {
            assert_eq!(allowed.len(), 1, "no plan on {allowed:?}");
            return;
        };
        assert_eq!(p.haptic, *allowed.last().unwrap());
        assert!(!p.others.contains(&p.haptic), "{p:?}");
        let shares = allowed.len() == 2 && shared::cpus::fifo_permitted(80);
        assert_eq!(p.sim.contains(&p.haptic), shares, "{p:?}");
        assert_eq!(
            p.sim_threads(),
            if allowed.len() == 2 && !shares { 1 } else { 2 }
        );
        // Beside the studio, never on the loop's CPU.
        let q = Plan::new(false, None, 80, false).unwrap();
        assert_eq!((&q.others, &q.sim), (&p.others, &p.others), "{q:?}");
        // The loop on the lowest CPU instead: the same, round it.
        let q = Plan::new(false, Some(allowed[0]), 80, true).unwrap();
        assert_eq!(q.haptic, allowed[0]);
        assert!(!q.others.contains(&allowed[0]), "{q:?}");
    }
}
