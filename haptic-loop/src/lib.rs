//! Saiho `haptic-loop`: the 1 kHz process that owns the haptic device. It renders force
//! at every tick from the latest local model cloth-sim sent ([`proxy`]), through the
//! force safety ([`safety`]), and never waits on another process.

pub mod device;
pub mod hold_log;
pub mod looper;
pub mod proxy;
pub mod record;
pub mod rt;
pub mod safety;
pub mod sim_watch;
