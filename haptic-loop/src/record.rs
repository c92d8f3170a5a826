//! Device logs: `--record FILE` writes every tick's pen state in the format
//! `device::Replay` reads back (`--device replay:FILE`).
//!
//! The tick only hands a fixed-size record to a bounded channel (`try_send`: no lock, no
//! allocation); a writer thread formats and writes. If the writer falls behind, records
//! are dropped and counted rather than delaying the tick.

use std::io::Write;
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};

use crate::device::{LOG_HEADER, Record};

pub struct Recorder {
    tx: Option<SyncSender<Record>>,
    writer: Option<std::thread::JoinHandle<std::io::Result<u64>>>,
    pub dropped: u64,
}

impl Recorder {
    pub fn create(path: &Path) -> Result<Self, String> {
        let file = std::fs::File::create(path)
            .map_err(|e| format!("cannot create device log {}: {e}", path.display()))?;
        let (tx, rx): (SyncSender<Record>, Receiver<Record>) = sync_channel(8192);
        let writer = std::thread::spawn(move || -> std::io::Result<u64> {
            let mut w = std::io::BufWriter::new(file);
            writeln!(w, "{LOG_HEADER}")?;
            let mut n = 0;
            for r in rx {
                let (p, v) = (r.state.position, r.state.velocity);
                writeln!(
                    w,
                    "{:.6} {} {} {} {} {} {} {}",
                    r.t, p[0], p[1], p[2], v[0], v[1], v[2], r.state.buttons
                )?;
                n += 1;
            }
            w.flush()?;
            Ok(n)
        });
        Ok(Self {
            tx: Some(tx),
            writer: Some(writer),
            dropped: 0,
        })
    }

    /// From the tick: never blocks.
    #[inline]
    pub fn push(&mut self, r: Record) {
        if let Some(tx) = &self.tx
            && let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) = tx.try_send(r)
        {
            self.dropped += 1;
        }
    }

    /// Closes the log; returns the records written.
    pub fn finish(mut self) -> Result<u64, String> {
        self.tx = None;
        match self.writer.take().map(|w| w.join()) {
            Some(Ok(Ok(n))) => Ok(n),
            Some(Ok(Err(e))) => Err(format!("writing the device log failed: {e}")),
            _ => Err("the device log writer stopped".into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::{DeviceState, HapticDevice, Replay};

    #[test]
    fn a_log_records_and_replays() {
        let path = std::env::temp_dir().join(format!("saiho-devlog-{}.txt", std::process::id()));
        let mut r = Recorder::create(&path).unwrap();
        for k in 0..100 {
            r.push(Record {
                t: k as f64 * 0.001,
                state: DeviceState {
                    position: [k as f32 * 0.001, 0.6, 0.0],
                    velocity: [1.0, 0.0, 0.0],
                    buttons: u32::from(k >= 50),
                },
            });
        }
        assert_eq!(r.finish().unwrap(), 100);
        let mut p = Replay::open(&path).unwrap();
        assert!((p.duration() - 0.099).abs() < 1e-9);
        let mut s = p.read(0.0).unwrap();
        for _ in 0..60 {
            s = p.read(0.001).unwrap();
        }
        assert!((s.position[0] - 0.060).abs() < 1.5e-3, "{:?}", s.position);
        assert_eq!(s.buttons, 1);
        std::fs::remove_file(&path).unwrap();
        assert!(
            Replay::parse("hello")
                .unwrap_err()
                .contains("not a device log")
        );
        assert!(Replay::parse(&format!("{LOG_HEADER}\n0 1 2 3 4 5 6")).is_err());
        assert!(Replay::parse(&format!("{LOG_HEADER}\n0 nan 0 0 0 0 0 0")).is_err());
        // Finite as f64 but past f32's range: it would reach the loop as infinity.
        let far = Replay::parse(&format!("{LOG_HEADER}\n0 1e39 0 0 0 0 0 0\n"));
        assert!(far.unwrap_err().contains("out of range"));
        // A log cut inside its last record (the writer killed) replays what came before,
        // and says where it was cut; a bad line anywhere else is still an error.
        let whole = format!("{LOG_HEADER}\n0 0 0.6 0 0 0 0 0\n0.001 0 0.6 0 0 0 0 1\n");
        let cut = Replay::parse(&format!("{whole}0.002 0 0.6")).unwrap();
        assert_eq!((cut.len(), cut.cut_at_line), (2, Some(4)));
        assert_eq!(Replay::parse(&whole).unwrap().cut_at_line, None);
        assert!(Replay::parse(&format!("{whole}0.002 0 0.6\n")).is_err());
        assert!(Replay::parse(&format!("{LOG_HEADER}\n0 0 0.6\n0.001 0 0.6 0 0 0 0 1")).is_err());
    }
}
