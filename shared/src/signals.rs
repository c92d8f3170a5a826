//! SIGINT / SIGTERM as a flag, for processes that handle shutdown themselves (iceoryx2's
//! own handlers are disabled on every node, see `services::node`).

use std::sync::atomic::{AtomicBool, Ordering};

static TERMINATE: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    // Async-signal-safe: a single atomic store.
    TERMINATE.store(true, Ordering::SeqCst);
}

/// Installs SIGINT and SIGTERM handlers that only set a flag; returns the flag.
#[allow(unsafe_code)]
pub fn termination_flag() -> &'static AtomicBool {
    for sig in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: a zeroed sigaction is a valid initial value; the handler is an
        // `extern "C" fn(c_int)` that only stores to an atomic (async-signal-safe), and
        // the pointers passed live for the duration of the call.
        unsafe {
            let mut act: libc::sigaction = std::mem::zeroed();
            act.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as usize;
            libc::sigemptyset(&mut act.sa_mask);
            act.sa_flags = 0;
            libc::sigaction(sig, &act, std::ptr::null_mut());
        }
    }
    &TERMINATE
}
