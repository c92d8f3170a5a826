//! `--device replay:FILE`: a device log (see `record`) played back by time: positions,
//! velocities and buttons; the recorded hand does not react to the rendered force.
//!
//! Format: text, one tick per line, `t x y z vx vy vz buttons` (seconds since the start,
//! scene metres, m/s, bit mask), after a first line [`LOG_HEADER`].

use std::path::Path;

use super::{DeviceError, DeviceState, HapticDevice, PointerTarget};

pub const LOG_HEADER: &str = "# saiho device log v1";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    pub t: f64,
    pub state: DeviceState,
}

/// Plays a device log back.
#[derive(Debug)]
pub struct Replay {
    records: Vec<Record>,
    t: f64,
    at: usize,
    /// The log ended inside a record (a writer killed mid-line): the line it was cut at.
    pub cut_at_line: Option<usize>,
}

impl Replay {
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        if lines.next().map(str::trim) != Some(LOG_HEADER) {
            return Err(format!(
                "not a device log (the first line must be '{LOG_HEADER}')"
            ));
        }
        let lines: Vec<&str> = lines.collect();
        // A last line without its newline was cut off by a killed writer: if it does not
        // read, the records before it are kept.
        let unfinished = !text.ends_with('\n');
        let mut records: Vec<Record> = Vec::new();
        let mut cut_at_line = None;
        for (k, line) in lines.iter().enumerate() {
            let n = k + 2;
            if line.split_whitespace().next().is_none() {
                continue;
            }
            match record(line, n, records.last()) {
                Ok(r) => records.push(r),
                Err(_) if unfinished && k + 1 == lines.len() => cut_at_line = Some(n),
                Err(e) => return Err(e),
            }
        }
        if records.is_empty() {
            return Err("the device log has no whole record".into());
        }
        Ok(Self {
            records,
            t: 0.0,
            at: 0,
            cut_at_line,
        })
    }

    /// The whole records replayed.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
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

/// One line of a device log (line number `n`; `last`: the record before it).
fn record(line: &str, n: usize, last: Option<&Record>) -> Result<Record, String> {
    let f: Vec<&str> = line.split_whitespace().collect();
    if f.len() != 8 {
        return Err(format!("line {n}: expected 8 fields, got {}", f.len()));
    }
    let num = |s: &str| -> Result<f64, String> {
        s.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("line {n}: '{s}' is not a finite number"))
    };
    // Positions and velocities are f32 on the wire: a number past f32's range would
    // become infinite there.
    let num32 = |s: &str| -> Result<f32, String> {
        let v = num(s)? as f32;
        v.is_finite()
            .then_some(v)
            .ok_or_else(|| format!("line {n}: '{s}' is out of range"))
    };
    let t = num(f[0])?;
    if last.is_some_and(|r| t < r.t) {
        return Err(format!("line {n}: time goes backwards"));
    }
    let buttons: u32 = f[7]
        .parse()
        .map_err(|_| format!("line {n}: buttons '{}' is not a bit mask", f[7]))?;
    Ok(Record {
        t,
        state: DeviceState {
            position: [num32(f[1])?, num32(f[2])?, num32(f[3])?],
            velocity: [num32(f[4])?, num32(f[5])?, num32(f[6])?],
            buttons: buttons & 0b11,
        },
    })
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

impl PointerTarget for Replay {}
