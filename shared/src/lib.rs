//! Saiho `shared`: what the three processes (`haptic-loop`, `cloth-sim`, `cloth-ui`) say to
//! each other over iceoryx2, and how each service is opened.
//!
//! - Message types are `#[repr(C)]` plain data (`ZeroCopySend`), in files named by
//!   direction (`haptic_to_sim`, `sim_to_haptic`, `ui_to_haptic`, `telemetry`). Every
//!   message starts with a [`Header`]: protocol version, sequence number, and send time on
//!   CLOCK_MONOTONIC. A receiver checks it ([`Header::check`]) and every value it uses
//!   ([`Checked`]): nothing from another process is trusted.
//! - [`command`]: the typed operations cloth-sim carries out ([`command::Command`]), and
//!   their one conversion to and from the wire record.
//! - [`services`] has one function per service, so every process opens it with the same
//!   quality of service; [`ports`] builds every process's ports from them, one struct per
//!   process.
//! - [`domain`] turns `--domain NAME` (or `SAIHO_DOMAIN`) into an iceoryx2 configuration of
//!   its own, so two systems, or tests running in parallel, never see each other;
//!   [`paths`] keeps each user's files private (0700 directories, 0600 shared memory).
//! - [`life`]: cloth-sim's life lock, which tells the haptic loop of its death before the
//!   kernel has torn the process down.

pub mod cli;
pub mod command;
pub mod cpus;
pub mod domain;
pub mod haptic_to_sim;
pub mod life;
pub mod paths;
pub mod ports;
pub mod services;
pub mod signals;
pub mod sim_to_haptic;
pub mod sim_to_ui;
pub mod telemetry;
pub mod ui_to_haptic;
pub mod ui_to_sim;

use iceoryx2::prelude::ZeroCopySend;

/// Bumped whenever a message's layout or meaning changes.
pub const PROTOCOL_VERSION: u32 = 27;

/// The start of every message.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
pub struct Header {
    pub protocol: u32,
    pub _reserved: u32,
    /// Per-publisher sequence number, from 1.
    pub seq: u64,
    /// CLOCK_MONOTONIC when sent, ns.
    pub sent_ns: u64,
}

/// Why a received message was rejected.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MessageError {
    #[error(
        "protocol mismatch: the peer speaks version {theirs}, this build speaks {PROTOCOL_VERSION}; run matching builds"
    )]
    Protocol { theirs: u32 },
    #[error("malformed {what}: {why}")]
    Malformed { what: &'static str, why: String },
}

impl Header {
    /// A header for the next message of a sender whose counter is `seq` (incremented).
    pub fn next(seq: &mut u64) -> Self {
        *seq += 1;
        Self {
            protocol: PROTOCOL_VERSION,
            _reserved: 0,
            seq: *seq,
            sent_ns: monotonic_ns(),
        }
    }

    pub fn check(&self) -> Result<(), MessageError> {
        if self.protocol != PROTOCOL_VERSION {
            return Err(MessageError::Protocol {
                theirs: self.protocol,
            });
        }
        Ok(())
    }
}

/// A message whose contents can be checked after it crossed a process boundary.
pub trait Checked {
    const WHAT: &'static str;
    fn header(&self) -> &Header;
    /// Checks everything but the header: finite numbers, counts within their arrays, flags.
    fn check_body(&self) -> Result<(), String>;

    fn check(&self) -> Result<(), MessageError> {
        self.header().check()?;
        self.check_body().map_err(|why| MessageError::Malformed {
            what: Self::WHAT,
            why,
        })
    }
}

pub(crate) fn finite3(name: &str, v: &[f32; 3]) -> Result<(), String> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(format!("{name} is not finite: {v:?}"))
    }
}

/// CLOCK_MONOTONIC now, ns (the clock every timestamp in the system uses).
pub fn monotonic_ns() -> u64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::Monotonic);
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}
