//! cloth-sim's life lock: a robust, process-shared mutex in a small file of the domain's
//! private directory, which cloth-sim holds for as long as it runs, so that the haptic
//! loop learns of its death at once.
//!
//! When a process dies, the kernel lets go of the robust mutexes each of its threads
//! holds (marking them "owner died") as that thread exits, before it tears down the
//! process's memory. The other signs of an exit come after the teardown: a pidfd becomes
//! readable, files close. On this VM the teardown of a 128 x 128 cloth-sim (56 MB) takes
//! 4-6 ms after a `kill -9` on an idle machine and up to 15 ms on a busy one; a waiter on
//! the lock wakes 0.05-0.1 ms after the kill (docs/reliability.md, "Knowing at once").
//!
//! The file is `cloth-sim.life` in [`Domain::root_dir`] (0700): 4 KiB, a magic number,
//! the holder (`pid << 32 | count`, 0 for none) and the mutex. Nothing read from it is
//! trusted: a file that is not a private regular file of this user's, of another size, or
//! without the magic is not used by the watcher and is replaced by cloth-sim; the holder
//! it names is only matched against the pids iceoryx2 lists as the model's publishers.
//! The watcher waits with a timeout, so a mutex nobody releases only means the kernel's
//! exit notice (`haptic_loop::sim_watch`) is what tells the loop, a few ms later.
#![allow(unsafe_code)]

use std::cell::UnsafeCell;
use std::fs::File;
use std::io;
use std::os::fd::AsRawFd;
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::domain::Domain;

/// "SAIHOLIF".
const MAGIC: u64 = 0x5341_4948_4f4c_4946;
/// The file's size: one page.
const LEN: usize = 4096;
/// The file's name in the domain's directory.
pub const FILE_NAME: &str = "cloth-sim.life";

#[repr(C)]
struct Header {
    magic: AtomicU64,
    /// The holder: its pid in the high 32 bits, a count of holders in the low; 0 for none.
    owner: AtomicU64,
    mutex: UnsafeCell<libc::pthread_mutex_t>,
}

const _: () = assert!(std::mem::size_of::<Header>() <= LEN);

/// The life file of `domain` (its directory is made, private, if it is not there).
pub fn path(domain: &Domain) -> Result<PathBuf, String> {
    domain
        .root_dir()
        .map(|d| d.join(FILE_NAME))
        .map_err(|e| e.to_string())
}

/// The file, mapped.
struct Mapped {
    file: File,
    ptr: *mut Header,
    ino: u64,
}

impl Mapped {
    /// Opens (or, with `create`, makes) the life file at `path`: a private regular file of
    /// this user's, of the file's size (a new, empty one is sized).
    fn open(path: &Path, create: bool) -> io::Result<Self> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(create)
            .mode(0o600)
            .custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC)
            .open(path)?;
        let meta = file.metadata()?;
        if !meta.is_file() || meta.uid() != crate::paths::uid() || meta.mode() & 0o077 != 0 {
            return Err(io::Error::other(format!(
                "{} is not a private file of this user's",
                path.display()
            )));
        }
        if meta.len() != LEN as u64 {
            if !(create && meta.len() == 0) {
                return Err(io::Error::other(format!(
                    "{} is {} bytes, not a life file",
                    path.display(),
                    meta.len()
                )));
            }
            file.set_len(LEN as u64)?;
        }
        // SAFETY: FFI. A shared read-write mapping of the whole (LEN-byte) file; the fd is
        // valid for the call, and the mapping stays valid after the file is closed.
        let ptr = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                LEN,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_SHARED,
                file.as_raw_fd(),
                0,
            )
        };
        if ptr == libc::MAP_FAILED {
            return Err(io::Error::last_os_error());
        }
        Ok(Self {
            file,
            ptr: ptr.cast(),
            ino: meta.ino(),
        })
    }

    fn header(&self) -> &Header {
        // SAFETY: `ptr` is a live LEN-byte shared mapping (page-aligned) until drop, and
        // Header is at most LEN bytes; its fields are atomics and a mutex the pthread
        // functions alone touch, so shared access from other processes is sound.
        unsafe { &*self.ptr }
    }

    fn mutex(&self) -> *mut libc::pthread_mutex_t {
        self.header().mutex.get()
    }

    /// Gives the file its mutex (robust, process-shared) unless it has one, under an
    /// exclusive `flock` so two cloth-sims starting at once do not both.
    fn init(&self) -> io::Result<()> {
        let fd = self.file.as_raw_fd();
        let until = Instant::now() + Duration::from_secs(1);
        loop {
            // SAFETY: FFI on a valid fd.
            if unsafe { libc::flock(fd, libc::LOCK_EX | libc::LOCK_NB) } == 0 {
                break;
            }
            if Instant::now() > until {
                return Err(io::Error::other(
                    "the life file stays locked by another process",
                ));
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let h = self.header();
        let mut rc = 0;
        if h.magic.load(Ordering::Acquire) != MAGIC {
            // SAFETY: FFI. Nobody uses the mutex before the magic is set (the watcher
            // checks it; cloth-sims hold the flock), so initialising it here races nothing.
            unsafe {
                let mut attr: libc::pthread_mutexattr_t = std::mem::zeroed();
                libc::pthread_mutexattr_init(&mut attr);
                libc::pthread_mutexattr_setpshared(&mut attr, libc::PTHREAD_PROCESS_SHARED);
                libc::pthread_mutexattr_setrobust(&mut attr, libc::PTHREAD_MUTEX_ROBUST);
                rc = libc::pthread_mutex_init(self.mutex(), &attr);
                libc::pthread_mutexattr_destroy(&mut attr);
            }
            if rc == 0 {
                h.owner.store(0, Ordering::Relaxed);
                h.magic.store(MAGIC, Ordering::Release);
            }
        }
        // SAFETY: FFI on a valid fd.
        unsafe { libc::flock(fd, libc::LOCK_UN) };
        if rc == 0 {
            Ok(())
        } else {
            Err(io::Error::from_raw_os_error(rc))
        }
    }

    /// Takes the mutex within `wait`.
    fn lock(&self, wait: Duration) -> Locked {
        let mut now: libc::timespec = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: FFI with a valid out-pointer.
        unsafe { libc::clock_gettime(libc::CLOCK_REALTIME, &mut now) };
        let ns = now.tv_nsec as u64 + wait.subsec_nanos() as u64;
        let deadline = libc::timespec {
            tv_sec: now.tv_sec
                + wait.as_secs() as libc::time_t
                + (ns / 1_000_000_000) as libc::time_t,
            tv_nsec: (ns % 1_000_000_000) as libc::c_long,
        };
        // SAFETY: FFI on the mapped mutex, initialised (the magic is checked by callers).
        match unsafe { libc::pthread_mutex_timedlock(self.mutex(), &deadline) } {
            0 => Locked::Yes,
            libc::EOWNERDEAD => {
                // SAFETY: FFI; this thread holds the mutex (EOWNERDEAD hands it over).
                unsafe { libc::pthread_mutex_consistent(self.mutex()) };
                Locked::OwnerDied
            }
            libc::ETIMEDOUT => Locked::TimedOut,
            e => Locked::Failed(e),
        }
    }

    fn unlock(&self) {
        // SAFETY: FFI; called only by the thread that took the mutex.
        unsafe { libc::pthread_mutex_unlock(self.mutex()) };
    }
}

impl Drop for Mapped {
    fn drop(&mut self) {
        // SAFETY: FFI; unmaps the mapping made in `open`, used by nothing after this.
        unsafe { libc::munmap(self.ptr.cast(), LEN) };
    }
}

enum Locked {
    Yes,
    /// The holder died; the mutex is ours and made consistent.
    OwnerDied,
    TimedOut,
    Failed(i32),
}

/// Held by cloth-sim for its whole run (on the thread that runs it: the mutex belongs to a
/// thread, so the type cannot be sent to another). Dropped, it lets go and removes the
/// file.
pub struct LifeLock {
    map: Mapped,
    path: PathBuf,
}

impl LifeLock {
    /// Takes `domain`'s life lock. An error says why (another cloth-sim holds it, or the
    /// file cannot be made); the caller goes on without it.
    pub fn hold(domain: &Domain) -> Result<Self, String> {
        Self::hold_at(&path(domain)?)
    }

    /// [`LifeLock::hold`] at a given path (tests).
    pub fn hold_at(path: &Path) -> Result<Self, String> {
        let why = |e: &dyn std::fmt::Display| format!("life lock {}: {e}", path.display());
        let mut tries = 0;
        loop {
            tries += 1;
            let opened = Mapped::open(path, true).and_then(|m| m.init().map(|()| m));
            let map = match opened {
                Ok(m) => m,
                // Not a life file, or one whose mutex cannot be made: replaced, once.
                Err(_) if tries == 1 => {
                    let _ = std::fs::remove_file(path);
                    continue;
                }
                Err(e) => return Err(why(&e)),
            };
            match map.lock(Duration::from_secs(1)) {
                Locked::Yes | Locked::OwnerDied => {}
                Locked::TimedOut => {
                    return Err(why(&"another cloth-sim of this domain holds it"));
                }
                // A mutex left unusable (ENOTRECOVERABLE, say): a new file, once.
                Locked::Failed(_) if tries == 1 => {
                    drop(map);
                    let _ = std::fs::remove_file(path);
                    continue;
                }
                Locked::Failed(e) => return Err(why(&io::Error::from_raw_os_error(e))),
            }
            let h = map.header();
            let count = (h.owner.load(Ordering::Relaxed) as u32)
                .wrapping_add(1)
                .max(1);
            h.owner.store(
                (u64::from(std::process::id()) << 32) | u64::from(count),
                Ordering::Release,
            );
            return Ok(Self {
                map,
                path: path.to_path_buf(),
            });
        }
    }
}

impl Drop for LifeLock {
    fn drop(&mut self) {
        self.map.header().owner.store(0, Ordering::Release);
        self.map.unlock();
        // Only our file: a cloth-sim started meanwhile may have replaced it.
        if std::fs::symlink_metadata(&self.path).is_ok_and(|m| m.ino() == self.map.ino) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// The other side: waits for the holder of a domain's life lock to let go.
pub struct LifeWatch {
    path: PathBuf,
    map: Option<Mapped>,
    /// The holder last seen to let go.
    seen: u64,
    /// The holder last seen holding, not yet seen to let go: a release that happens
    /// between two waits (the field cleared, the file removed) is still reported.
    last: u64,
}

// SAFETY: the mapping is process-wide; the watcher takes and releases the mutex within one
// call of `wait`, on the calling thread, so it can move between threads between calls.
unsafe impl Send for LifeWatch {}

impl LifeWatch {
    /// A watcher of `domain`'s life lock (the file need not exist yet).
    pub fn new(domain: &Domain) -> Result<Self, String> {
        let root = domain.root_path().map_err(|e| e.to_string())?;
        Ok(Self::at(root.join(FILE_NAME)))
    }

    /// A watcher of the life lock at `path`.
    pub fn at(path: PathBuf) -> Self {
        Self {
            path,
            map: None,
            seen: 0,
            last: 0,
        }
    }

    /// The holder last seen holding, if it has not been reported: it let go unseen.
    fn released(&mut self) -> Option<u32> {
        let last = std::mem::take(&mut self.last);
        (last != 0 && last != self.seen).then(|| {
            self.seen = last;
            (last >> 32) as u32
        })
    }

    /// Waits up to about `wait` for the lock's holder to let go; returns its pid if it did
    /// (it died, or it stopped and released the lock). Not for a real-time thread.
    pub fn wait(&mut self, wait: Duration) -> Option<u32> {
        let ino = std::fs::symlink_metadata(&self.path).ok().map(|m| m.ino());
        if ino.is_none() || ino != self.map.as_ref().map(|m| m.ino) {
            self.map = ino.and_then(|_| Mapped::open(&self.path, false).ok());
            // The file watched is gone or replaced: a holder seen in it let go.
            if let Some(pid) = self.released() {
                return Some(pid);
            }
        }
        let idle = |d: Duration| {
            std::thread::sleep(d.min(Duration::from_millis(10)));
            None
        };
        let Some(m) = &self.map else {
            return idle(wait);
        };
        let h = m.header();
        if h.magic.load(Ordering::Acquire) != MAGIC {
            return idle(wait);
        }
        let before = h.owner.load(Ordering::Acquire);
        if before == 0 {
            // Let go since the last wait, if a holder was seen then.
            return self.released().or_else(|| idle(wait));
        }
        if self.last != 0 && before != self.last {
            // Another holder took over since the last wait: the one seen then let go.
            return self.released();
        }
        if before == self.seen {
            return idle(wait);
        }
        self.last = before;
        match m.lock(wait) {
            Locked::TimedOut => None,
            Locked::Failed(_) => {
                self.map = None;
                idle(wait)
            }
            got => {
                // Whoever holds the lock writes the holder field, so at a death it names
                // the one that died; at a release, the holder cleared it first.
                let now = h.owner.load(Ordering::Acquire);
                m.unlock();
                let gone = match got {
                    Locked::OwnerDied => now,
                    _ if now == 0 => before,
                    _ => 0,
                };
                self.seen = if now == 0 { before } else { now };
                self.last = 0;
                (gone != 0).then_some((gone >> 32) as u32)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("saiho-life-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(FILE_NAME)
    }

    /// Waits up to 5 s for the watcher to see a holder let go.
    fn seen(w: &mut LifeWatch) -> Option<u32> {
        let t = Instant::now();
        while t.elapsed() < Duration::from_secs(5) {
            if let Some(pid) = w.wait(Duration::from_millis(50)) {
                return Some(pid);
            }
        }
        None
    }

    #[test]
    fn a_holder_that_dies_or_lets_go_is_seen_and_a_new_one_is_followed() {
        let path = scratch("follow");
        let mut w = LifeWatch::at(path.clone());
        assert_eq!(w.wait(Duration::from_millis(5)), None, "no file, no holder");
        // A thread that ends holding the lock: the kernel lets go of it as the thread
        // exits, as it does for each thread of a killed process.
        let p = path.clone();
        std::thread::spawn(move || std::mem::forget(LifeLock::hold_at(&p).unwrap()))
            .join()
            .unwrap();
        assert_eq!(seen(&mut w), Some(std::process::id()), "a death");
        assert_eq!(w.wait(Duration::from_millis(5)), None, "seen once");
        assert!(path.exists(), "a dead holder leaves its file");
        // The next holder takes the dead one's lock and file, and lets go cleanly; the
        // watcher sees the release whether it is waiting on the mutex at that moment or
        // between two waits (then the field is cleared and the file gone before it looks).
        let next = LifeLock::hold_at(&path).expect("a dead holder's lock is taken over");
        assert_eq!(w.wait(Duration::from_millis(5)), None, "held");
        drop(next);
        assert!(!path.exists(), "a clean holder removes its file");
        assert_eq!(
            w.wait(Duration::from_millis(5)),
            Some(std::process::id()),
            "a release between two waits"
        );
        assert_eq!(w.wait(Duration::from_millis(5)), None, "seen once");
        let next = LifeLock::hold_at(&path).expect("a new holder");
        let mut w = LifeWatch::at(path.clone());
        assert_eq!(w.wait(Duration::from_millis(5)), None, "held");
        let waiter = std::thread::spawn(move || seen(&mut w));
        std::thread::sleep(Duration::from_millis(300));
        drop(next);
        assert_eq!(
            waiter.join().unwrap(),
            Some(std::process::id()),
            "a release while waiting"
        );
        // A holder that dies and is taken over between two waits: its death is reported.
        let (held, hold_tx) = (std::sync::mpsc::channel(), std::sync::mpsc::channel::<()>());
        let p = path.clone();
        let dying = std::thread::spawn(move || {
            let lock = LifeLock::hold_at(&p).unwrap();
            held.0.send(()).unwrap();
            hold_tx.1.recv().unwrap();
            std::mem::forget(lock);
        });
        held.1.recv().unwrap();
        let mut w = LifeWatch::at(path.clone());
        assert_eq!(w.wait(Duration::from_millis(5)), None, "held");
        hold_tx.0.send(()).unwrap();
        dying.join().unwrap();
        let next = LifeLock::hold_at(&path).expect("a dead holder's lock is taken over");
        assert_eq!(
            w.wait(Duration::from_millis(5)),
            Some(std::process::id()),
            "a death taken over between two waits"
        );
        drop(next);
        let _ = std::fs::remove_dir_all(path.parent().unwrap());
    }

    #[test]
    fn a_foreign_or_damaged_file_is_replaced_and_a_held_lock_refused() {
        let path = scratch("damaged");
        std::fs::write(&path, b"not a life file").unwrap();
        let mut w = LifeWatch::at(path.clone());
        assert_eq!(w.wait(Duration::from_millis(5)), None, "garbage is ignored");
        let held = LifeLock::hold_at(&path).expect("a damaged file is replaced");
        assert_eq!(std::fs::metadata(&path).unwrap().len(), LEN as u64);
        // A second holder in the same domain waits 1 s, then is told why.
        let p = path.clone();
        let second = std::thread::spawn(move || LifeLock::hold_at(&p).err());
        let err = second.join().unwrap().expect("a held lock is refused");
        assert!(err.contains("another cloth-sim"), "{err}");
        drop(held);
        // A symbolic link is not followed.
        let target = path.with_extension("target");
        std::fs::write(&target, vec![0u8; LEN]).unwrap();
        std::os::unix::fs::symlink(&target, &path).unwrap();
        assert!(Mapped::open(&path, false).is_err(), "a link is refused");
        let held = LifeLock::hold_at(&path).expect("the link is replaced by a file");
        assert!(!std::fs::symlink_metadata(&path).unwrap().is_symlink());
        drop(held);
        assert_eq!(std::fs::read(&target).unwrap(), vec![0u8; LEN], "untouched");
        let _ = std::fs::remove_dir_all(path.parent().unwrap());
    }
}
