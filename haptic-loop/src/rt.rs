//! Real-time plumbing: absolute-deadline sleeps on CLOCK_MONOTONIC, optional SCHED_FIFO,
//! memory locking and CPU pinning, and a SIGINT/SIGTERM flag. The only `unsafe` in the
//! crate is here, for the syscall rustix does not wrap (sched_setscheduler).

use rustix::time::{ClockId, Timespec};

/// CLOCK_MONOTONIC now, ns.
#[inline]
pub fn now_ns() -> u64 {
    shared::monotonic_ns()
}

/// Sleeps until `deadline_ns` (CLOCK_MONOTONIC, TIMER_ABSTIME) minus `spin_ns`, then spins
/// to the deadline: the kernel's wake-up jitter lands in the spin, not in the tick.
#[inline]
pub fn wait_until(deadline_ns: u64, spin_ns: u64) {
    let sleep_to = deadline_ns.saturating_sub(spin_ns);
    if now_ns() < sleep_to {
        let ts = Timespec {
            tv_sec: (sleep_to / 1_000_000_000) as i64,
            tv_nsec: (sleep_to % 1_000_000_000) as i64,
        };
        // EINTR (a signal) just ends the sleep early; the spin finishes the wait.
        let _ = rustix::thread::clock_nanosleep_absolute(ClockId::Monotonic, &ts);
    }
    while now_ns() < deadline_ns {
        std::hint::spin_loop();
    }
}

/// The SIGINT/SIGTERM flag (see [`shared::signals`]).
pub use shared::signals::termination_flag;

/// What the real-time setup achieved (each part falls back on its own).
#[derive(Debug, Clone)]
pub struct RtStatus {
    pub fifo: Result<i32, String>,
    pub locked: Result<(), String>,
    pub pinned: Result<usize, String>,
}

impl RtStatus {
    /// The one line the processes print: "real-time: SCHED_FIFO 80 on CPU 1, memory
    /// locked", or what was not permitted and that ticks may be late.
    pub fn line(&self) -> String {
        let mut got = Vec::new();
        let mut missing = Vec::new();
        match &self.fifo {
            Ok(p) => got.push(format!("SCHED_FIFO {p}")),
            Err(e) => missing.push(format!("SCHED_FIFO ({e})")),
        }
        match &self.pinned {
            Ok(c) => got.push(format!("on CPU {c}")),
            Err(e) if e != "not asked" => missing.push(format!("a CPU of its own ({e})")),
            Err(_) => {}
        }
        match &self.locked {
            Ok(()) => got.push("memory locked".into()),
            Err(e) => missing.push(format!("memory locking ({e})")),
        }
        if missing.is_empty() {
            format!(
                "real-time: {}",
                got.join(", ").replacen(", on CPU", " on CPU", 1)
            )
        } else if got.is_empty() {
            format!(
                "real-time not permitted: {}; ticks may be late",
                missing.join(", ")
            )
        } else {
            format!(
                "real-time: {}; not permitted: {}; ticks may be late",
                got.join(", ").replacen(", on CPU", " on CPU", 1),
                missing.join(", ")
            )
        }
    }

    /// One line for the log: what is on, and why what is off is off.
    pub fn summary(&self) -> String {
        let part = |name: &str, r: Result<String, &String>| match r {
            Ok(s) => format!("{name} {s}"),
            Err(e) => format!("{name} off ({e})"),
        };
        [
            part(
                "SCHED_FIFO",
                self.fifo.as_ref().map(|p| format!("priority {p}")),
            ),
            part("mlockall", self.locked.as_ref().map(|_| "on".to_string())),
            part("CPU pin", self.pinned.as_ref().map(|c| format!("cpu {c}"))),
        ]
        .join(", ")
    }
}

/// Asks for SCHED_FIFO at `priority`, locks memory, and pins to `cpu`; each part that is
/// not permitted is reported, not fatal.
#[allow(unsafe_code)]
pub fn realtime(priority: i32, cpu: Option<usize>) -> RtStatus {
    let param = libc::sched_param {
        sched_priority: priority,
    };
    // SAFETY: `param` is a valid sched_param that outlives the call; pid 0 is this thread.
    let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
    let fifo = if rc == 0 {
        Ok(priority)
    } else {
        Err(format!(
            "{} (needs CAP_SYS_NICE or an rtprio limit)",
            std::io::Error::last_os_error()
        ))
    };
    let locked = rustix::mm::mlockall(
        rustix::mm::MlockAllFlags::CURRENT | rustix::mm::MlockAllFlags::FUTURE,
    )
    .map_err(|e| format!("{e} (needs CAP_IPC_LOCK or a memlock limit)"));
    let pinned = match cpu {
        None => Err("not asked".into()),
        Some(c) => {
            let mut set = rustix::thread::CpuSet::new();
            set.set(c);
            rustix::thread::sched_setaffinity(None, &set)
                .map(|_| c)
                .map_err(|e| e.to_string())
        }
    };
    RtStatus {
        fifo,
        locked,
        pinned,
    }
}
