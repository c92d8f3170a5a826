//! Percentiles with hdrhistogram, the telemetry histograms turned into them, and the
//! report files (JSON, CSV) the tools write.

use std::io::Write;
use std::path::Path;

use hdrhistogram::Histogram as Hdr;
use serde::Serialize;
use shared::telemetry::{BUCKETS, Histogram};

/// A latency distribution in microseconds: 1 ns to 60 s at 3 significant digits.
pub fn new_hdr() -> Hdr<u64> {
    // Constant bounds within hdrhistogram's limits (tested below), so this cannot fail.
    #[allow(clippy::expect_used)]
    Hdr::new_with_bounds(1, 60_000_000_000, 3).expect("valid histogram bounds")
}

/// Percentiles of one distribution, µs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Percentiles {
    pub count: u64,
    pub p50: f64,
    pub p99: f64,
    pub p999: f64,
    pub max: f64,
    pub mean: f64,
}

impl Percentiles {
    /// From a histogram of nanoseconds.
    pub fn of(h: &Hdr<u64>) -> Self {
        if h.is_empty() {
            return Self::default();
        }
        let us = |ns: u64| ns as f64 / 1000.0;
        Self {
            count: h.len(),
            p50: us(h.value_at_quantile(0.5)),
            p99: us(h.value_at_quantile(0.99)),
            p999: us(h.value_at_quantile(0.999)),
            max: us(h.max()),
            mean: h.mean() / 1000.0,
        }
    }
}

/// The records of a telemetry histogram that arrived between two snapshots of it (both
/// cumulative since the publisher started), as an hdrhistogram of ns. Each bucket counts
/// at its upper edge (its lower edge plus its width), so percentiles never understate; the
/// top bucket, which holds everything above 12 ms, counts at the later snapshot's maximum.
pub fn window(before: Option<&Histogram>, after: &Histogram) -> Hdr<u64> {
    let mut h = new_hdr();
    for b in 0..BUCKETS {
        let c = after.counts[b].saturating_sub(before.map_or(0, |x| x.counts[b]));
        if c == 0 {
            continue;
        }
        let v = if b + 1 < BUCKETS {
            Histogram::bucket_floor_ns(b + 1).min(after.max_ns.max(1))
        } else {
            after.max_ns
        };
        let _ = h.record_n(v.max(1), c as u64);
    }
    h
}

/// Writes `value` as pretty JSON, saying which file failed.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))
}

/// A named time series: (seconds since start, value µs).
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            points: Vec::new(),
        }
    }
}

/// Writes series as CSV rows `series,t_s,value_us`.
pub fn write_csv(path: &Path, series: &[Series]) -> Result<(), String> {
    let e = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(e)?);
    writeln!(f, "series,t_s,value_us").map_err(e)?;
    for s in series {
        for (t, v) in &s.points {
            writeln!(f, "{},{t:.6},{v:.3}", s.name).map_err(e)?;
        }
    }
    f.flush().map_err(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_is_the_difference_of_two_snapshots() {
        let mut a = Histogram::default();
        for _ in 0..100 {
            a.record(1_000_400);
        }
        let mut b = a;
        for _ in 0..10 {
            b.record(1_500_200);
        }
        b.record(30_000_000);
        let w = window(Some(&a), &b);
        assert_eq!(w.len(), 11);
        let p = Percentiles::of(&w);
        // Buckets count at their upper edge (1 µs wide here).
        assert!((p.p50 - 1501.0).abs() < 2.0, "{p:?}");
        assert!((p.max - 30_000.0).abs() < 30.0, "{p:?}");
        // Without a first snapshot, everything counts.
        assert_eq!(window(None, &b).len(), 111);
    }
}
