//! Knowing at once that cloth-sim is gone. The loop otherwise learns it only from its
//! model's age: a model comes every frame, so it waits 20 ms before it calls the model
//! stale, and the force reaches zero 20-31 ms after a kill. A thread of its own here holds
//! a pidfd for each process that publishes the local model (from iceoryx2's list of the
//! service's publishers, read outside the tick) and sleeps in `poll` on them; the kernel
//! wakes it the moment such a process exits, and it raises a flag the tick reads with one
//! atomic load. The tick then ramps the force to zero over 2 ms. The kernel says a process
//! has exited once its memory is torn down: 4-5 ms after a kill -9 of a 128 x 128
//! cloth-sim here (five kills, measured with a pidfd), so the force is at zero within
//! about 7 ms of the kill.
//!
//! Only an exit is seen this way: a stopped or stalled cloth-sim is still alive, and for
//! that the model's age stays the judge. A pid that cannot be watched (no pidfd on an old
//! kernel, another user's process) is left to the age as well.

use std::os::fd::OwnedFd;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::thread::JoinHandle;

use rustix::event::{PollFd, PollFlags, poll};
use rustix::process::{Pid, PidfdFlags, pidfd_open};

/// At most this many publishers of the local model are watched (the service allows two).
pub const WATCHED: usize = 2;

/// How long the thread sleeps in `poll` before it looks at the list again, ms.
const RELOOK_MS: i64 = 20;

#[derive(Default)]
struct Shared {
    /// The processes to watch (0: none).
    pids: [AtomicU32; WATCHED],
    /// Every watched process has exited (and there was at least one).
    gone: AtomicBool,
    stop: AtomicBool,
}

/// The watcher: [`SimWatch::watch`] outside the tick, [`SimWatch::gone`] in it.
pub struct SimWatch {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl SimWatch {
    /// Starts the watching thread (start it before the loop takes real-time priority: it
    /// should run as an ordinary thread).
    pub fn start() -> Self {
        let shared = Arc::new(Shared::default());
        let s = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("sim-watch".into())
            .spawn(move || watch_loop(&s))
            .ok();
        Self { shared, thread }
    }

    /// The pids of the local model's publishers now (0 for none). Not in the tick: it may
    /// change what the thread watches.
    pub fn watch(&self, pids: [u32; WATCHED]) {
        for (slot, pid) in self.shared.pids.iter().zip(pids) {
            slot.store(pid, Ordering::Relaxed);
        }
    }

    /// Whether every process publishing the local model has exited. One atomic load.
    #[inline]
    pub fn gone(&self) -> bool {
        self.shared.gone.load(Ordering::Acquire)
    }
}

impl Drop for SimWatch {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// One watched process: its pid, its pidfd (`None` when it could not be opened), and
/// whether it has exited.
struct Watched {
    pid: u32,
    fd: Option<OwnedFd>,
    exited: bool,
}

fn open(pid: u32) -> Watched {
    let fd = i32::try_from(pid)
        .ok()
        .and_then(Pid::from_raw)
        .map(|p| pidfd_open(p, PidfdFlags::empty()));
    match fd {
        Some(Ok(fd)) => Watched {
            pid,
            fd: Some(fd),
            exited: false,
        },
        // No such process: it has exited already.
        Some(Err(rustix::io::Errno::SRCH)) => Watched {
            pid,
            fd: None,
            exited: true,
        },
        // Not watchable here (no pidfd, no permission): the model's age decides.
        _ => Watched {
            pid,
            fd: None,
            exited: false,
        },
    }
}

fn watch_loop(s: &Shared) {
    let mut watched: Vec<Watched> = Vec::with_capacity(WATCHED);
    while !s.stop.load(Ordering::Relaxed) {
        // Follow the list: keep what is still listed, open what is new.
        let want: Vec<u32> = s
            .pids
            .iter()
            .map(|p| p.load(Ordering::Relaxed))
            .filter(|&p| p != 0)
            .collect();
        watched.retain(|w| want.contains(&w.pid));
        for &pid in &want {
            if !watched.iter().any(|w| w.pid == pid) {
                watched.push(open(pid));
            }
        }
        let gone = !watched.is_empty() && watched.iter().all(|w| w.exited);
        s.gone.store(gone, Ordering::Release);
        // Sleep in poll on the pidfds of those not yet seen to exit; a pidfd becomes
        // readable when its process exits.
        let live: Vec<usize> = (0..watched.len())
            .filter(|&i| !watched[i].exited && watched[i].fd.is_some())
            .collect();
        if live.is_empty() {
            std::thread::sleep(std::time::Duration::from_millis(RELOOK_MS as u64));
            continue;
        }
        let timeout = rustix::time::Timespec {
            tv_sec: 0,
            tv_nsec: RELOOK_MS * 1_000_000,
        };
        let exited: Vec<usize> = {
            let mut fds: Vec<PollFd<'_>> = live
                .iter()
                .filter_map(|&i| watched[i].fd.as_ref())
                .map(|fd| PollFd::new(fd, PollFlags::IN))
                .collect();
            if poll(&mut fds, Some(&timeout)).is_err() {
                continue;
            }
            live.iter()
                .zip(&fds)
                .filter(|(_, f)| !f.revents().is_empty())
                .map(|(&i, _)| i)
                .collect()
        };
        for i in exited {
            watched[i].exited = true;
        }
        let gone = !watched.is_empty() && watched.iter().all(|w| w.exited);
        s.gone.store(gone, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    fn wait_for(w: &SimWatch, want: bool) -> Option<Duration> {
        let t = Instant::now();
        while t.elapsed() < Duration::from_secs(5) {
            if w.gone() == want {
                return Some(t.elapsed());
            }
            std::thread::sleep(Duration::from_micros(100));
        }
        None
    }

    #[test]
    fn an_exit_is_seen_at_once_and_a_live_process_is_not_gone() {
        let w = SimWatch::start();
        // Nothing to watch: not gone (the model's age decides).
        std::thread::sleep(Duration::from_millis(30));
        assert!(!w.gone());
        let mut child = std::process::Command::new("sleep")
            .arg("30")
            .spawn()
            .expect("sleep runs");
        w.watch([child.id(), 0]);
        std::thread::sleep(Duration::from_millis(50));
        assert!(!w.gone(), "a live process is not gone");
        // Our own process, alive, beside it: gone only when every watched one exited.
        w.watch([child.id(), std::process::id()]);
        std::thread::sleep(Duration::from_millis(50));
        let killed = Instant::now();
        child.kill().expect("kill");
        // Not reaped yet (a zombie): a pidfd is readable once the process exits all the
        // same, but our own process lives on.
        std::thread::sleep(Duration::from_millis(50));
        assert!(!w.gone(), "one of the two is alive");
        w.watch([child.id(), 0]);
        let seen = wait_for(&w, true).expect("the exit is seen");
        let _ = child.wait();
        eprintln!("exit seen {:?} after the list changed", seen);
        assert!(killed.elapsed() < Duration::from_secs(5));
        // A restarted process takes its place: not gone any more.
        let mut next = std::process::Command::new("sleep")
            .arg("30")
            .spawn()
            .expect("sleep runs");
        w.watch([child.id(), next.id()]);
        assert!(wait_for(&w, false).is_some(), "a live successor");
        let t = Instant::now();
        next.kill().expect("kill");
        let seen = wait_for(&w, true).expect("its exit is seen");
        let _ = next.wait();
        // The kernel wakes the thread at the exit: well within a millisecond or two here,
        // far within the 20 ms the model's age would take.
        eprintln!("exit seen {:?} after the kill", t.elapsed().min(seen));
        assert!(seen < Duration::from_millis(15), "{seen:?}");
    }
}
