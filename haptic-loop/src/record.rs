//! Device logs: `--record FILE` writes every tick's pen state; `--device replay:FILE`
//! plays one back (positions, velocities and buttons by time; the recorded hand does not
//! react to the rendered force).
//!
//! Format: text, one tick per line, `t x y z vx vy vz buttons` (seconds since the start,
//! scene metres, m/s, bit mask), after a first line `# saiho device log v1`.
//!
//! The tick only hands a fixed-size record to a bounded channel (`try_send`: no lock, no
//! allocation); a writer thread formats and writes. If the writer falls behind, records
//! are dropped and counted rather than delaying the tick.

use std::io::Write;
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};

use crate::device::{DeviceError, DeviceState, HapticDevice};

pub const HEADER: &str = "# saiho device log v1";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    pub t: f64,
    pub state: DeviceState,
}

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
            writeln!(w, "{HEADER}")?;
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

/// Plays a device log back.
#[derive(Debug)]
pub struct Replay {
    records: Vec<Record>,
    t: f64,
    at: usize,
}

impl Replay {
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        if lines.next().map(str::trim) != Some(HEADER) {
            return Err(format!(
                "not a device log (the first line must be '{HEADER}')"
            ));
        }
        let mut records = Vec::new();
        for (k, line) in lines.enumerate() {
            let n = k + 2;
            let f: Vec<&str> = line.split_whitespace().collect();
            if f.is_empty() {
                continue;
            }
            if f.len() != 8 {
                return Err(format!("line {n}: expected 8 fields, got {}", f.len()));
            }
            let num = |s: &str| -> Result<f64, String> {
                s.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("line {n}: '{s}' is not a finite number"))
            };
            let t = num(f[0])?;
            if records.last().is_some_and(|r: &Record| t < r.t) {
                return Err(format!("line {n}: time goes backwards"));
            }
            let buttons: u32 = f[7]
                .parse()
                .map_err(|_| format!("line {n}: buttons '{}' is not a bit mask", f[7]))?;
            records.push(Record {
                t,
                state: DeviceState {
                    position: [num(f[1])? as f32, num(f[2])? as f32, num(f[3])? as f32],
                    velocity: [num(f[4])? as f32, num(f[5])? as f32, num(f[6])? as f32],
                    buttons: buttons & 0b11,
                },
            });
        }
        if records.is_empty() {
            return Err("the device log has no records".into());
        }
        Ok(Self {
            records,
            t: 0.0,
            at: 0,
        })
    }

    pub fn open(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read device log {}: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn duration(&self) -> f64 {
        self.records.last().map_or(0.0, |r| r.t)
    }
}

impl HapticDevice for Replay {
    fn name(&self) -> &str {
        "replay"
    }

    fn read(&mut self, dt: f32) -> Result<DeviceState, DeviceError> {
        self.t += dt.clamp(0.0, 0.005) as f64;
        while self.at + 1 < self.records.len() && self.records[self.at + 1].t <= self.t {
            self.at += 1;
        }
        Ok(self.records[self.at].state)
    }

    fn write_force(&mut self, _force: [f32; 3]) -> Result<(), DeviceError> {
        Ok(())
    }
}

impl crate::looper::PointerTarget for Replay {}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert!(Replay::parse(&format!("{HEADER}\n0 1 2 3 4 5 6")).is_err());
        assert!(Replay::parse(&format!("{HEADER}\n0 nan 0 0 0 0 0 0")).is_err());
    }
}
