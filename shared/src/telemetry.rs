//! every process -> cloth-ui, cloth-latency: loop timing as allocation-free histograms.

use iceoryx2::prelude::ZeroCopySend;

use crate::{Checked, Header};

/// Buckets of a [`Histogram`]: 1 µs wide up to 2 ms (so a 1 ms period is resolved to the
/// microsecond), then 100 µs wide up to 12 ms, then (since protocol 11) 1 ms wide up to
/// 1 s; the last bucket counts everything above. Before, everything above 12 ms was one
/// bucket, and a cloth whose frames mostly took longer (a garment, a 128 x 128 cloth)
/// showed its slowest frame as its median.
pub const FINE_BUCKETS: usize = 2000;
pub const COARSE_BUCKETS: usize = 100;
pub const SLOW_BUCKETS: usize = 988;
pub const BUCKETS: usize = FINE_BUCKETS + COARSE_BUCKETS + SLOW_BUCKETS + 1;

/// A fixed-size histogram of durations (no allocation, so the haptic tick can record).
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Histogram {
    pub counts: [u32; BUCKETS],
    /// Explicit padding (was implicit, `BUCKETS` being odd): every byte is a field.
    pub _pad: u32,
    pub total: u64,
    pub max_ns: u64,
}

impl Default for Histogram {
    fn default() -> Self {
        Self {
            counts: [0; BUCKETS],
            _pad: 0,
            total: 0,
            max_ns: 0,
        }
    }
}

impl Histogram {
    pub fn bucket_of(ns: u64) -> usize {
        const SLOW_FROM: usize = FINE_BUCKETS + COARSE_BUCKETS;
        let us = ns / 1000;
        if us < FINE_BUCKETS as u64 {
            us as usize
        } else if us < 12_000 {
            FINE_BUCKETS + ((us - FINE_BUCKETS as u64) / 100) as usize
        } else {
            (SLOW_FROM + ((us - 12_000) / 1000) as usize).min(BUCKETS - 1)
        }
    }

    /// The lower edge of bucket `b`, ns.
    pub fn bucket_floor_ns(b: usize) -> u64 {
        const SLOW_FROM: usize = FINE_BUCKETS + COARSE_BUCKETS;
        if b < FINE_BUCKETS {
            b as u64 * 1000
        } else if b < SLOW_FROM {
            FINE_BUCKETS as u64 * 1000 + (b - FINE_BUCKETS) as u64 * 100_000
        } else {
            12_000_000 + (b - SLOW_FROM) as u64 * 1_000_000
        }
    }

    #[inline]
    pub fn record(&mut self, ns: u64) {
        let b = Self::bucket_of(ns);
        self.counts[b] = self.counts[b].saturating_add(1);
        self.total += 1;
        self.max_ns = self.max_ns.max(ns);
    }

    /// The mean of the records, each taken at its bucket's middle (at most the maximum),
    /// ns; 0 with none.
    pub fn mean_ns(&self) -> f64 {
        if self.total == 0 {
            return 0.0;
        }
        let sum: f64 = (0..BUCKETS)
            .filter(|&b| self.counts[b] > 0)
            .map(|b| {
                let lo = Self::bucket_floor_ns(b) as f64;
                let hi = if b + 1 < BUCKETS {
                    Self::bucket_floor_ns(b + 1) as f64
                } else {
                    self.max_ns as f64
                };
                self.counts[b] as f64 * (0.5 * (lo + hi)).min(self.max_ns as f64)
            })
            .sum();
        sum / self.total as f64
    }

    /// The value under which a fraction `q` of the records fall (the bucket's upper edge,
    /// or the maximum for the last bucket), ns.
    pub fn quantile_ns(&self, q: f64) -> u64 {
        if self.total == 0 {
            return 0;
        }
        let want = ((q * self.total as f64).ceil() as u64).clamp(1, self.total);
        let mut seen = 0u64;
        for (b, &c) in self.counts.iter().enumerate() {
            seen += c as u64;
            if seen >= want {
                return if b + 1 < BUCKETS {
                    Self::bucket_floor_ns(b + 1).min(self.max_ns)
                } else {
                    self.max_ns
                };
            }
        }
        self.max_ns
    }
}

/// The haptic loop's timing since it started.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::LoopTelemetry")]
pub struct LoopTelemetry {
    pub header: Header,
    pub ticks: u64,
    /// Ticks that started more than one period late.
    pub missed: u64,
    /// Tick start minus its absolute deadline.
    pub lateness: Histogram,
    /// Time between tick starts.
    pub period: Histogram,
    /// Work inside a tick (device, proxy, messages).
    pub compute: Histogram,
    /// Age of the local model when a tick used it (tick start minus its send time).
    pub model_age: Histogram,
    /// The whole loop, once per model at its first use: from the device sample cloth-sim
    /// built the model from being sent, to the tick that rendered the model.
    pub pen_to_model: Histogram,
    /// Latest rendered force magnitude, N, and whether the local model is fresh.
    pub force_n: f32,
    pub model_fresh: u32,
}

impl Checked for LoopTelemetry {
    const WHAT: &'static str = "loop telemetry";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        if !self.force_n.is_finite() {
            return Err("force is not finite".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sim_telemetry_says_whether_the_cloth_sleeps_or_is_paused_and_nothing_else() {
        let tel = |asleep| SimTelemetry {
            asleep,
            ..Default::default()
        };
        assert!(tel(0).check_body().is_ok());
        assert!(tel(1).check_body().is_ok());
        let e = tel(7).check_body().unwrap_err();
        assert!(e.contains("sleep 7"), "{e}");
        let paused = |paused| SimTelemetry {
            paused,
            ..Default::default()
        };
        assert!(paused(1).check_body().is_ok());
        let e = paused(2).check_body().unwrap_err();
        assert!(e.contains("pause 2"), "{e}");
    }

    #[test]
    fn histogram_quantiles() {
        let mut h = Histogram::default();
        for us in 1..=1000u64 {
            h.record(us * 1000 + 500);
        }
        h.record(5_000_000);
        assert_eq!(h.total, 1001);
        // p50 is about 500 µs (bucket edges are 1 µs apart there).
        let p50 = h.quantile_ns(0.5);
        assert!((500_000..=502_000).contains(&p50), "{p50}");
        assert_eq!(h.quantile_ns(1.0), 5_000_000);
        assert_eq!(Histogram::bucket_of(2_000_000_000), BUCKETS - 1);
        // Slow frames get buckets of their own: 1 ms wide from 12 ms to 1 s.
        assert_eq!(
            Histogram::bucket_of(11_999_999),
            FINE_BUCKETS + COARSE_BUCKETS - 1
        );
        assert_eq!(
            Histogram::bucket_of(12_000_000),
            FINE_BUCKETS + COARSE_BUCKETS
        );
        assert_eq!(
            Histogram::bucket_of(20_500_000),
            FINE_BUCKETS + COARSE_BUCKETS + 8
        );
        assert_eq!(Histogram::bucket_of(999_999_999), BUCKETS - 2);
        assert_eq!(Histogram::bucket_floor_ns(BUCKETS - 1), 1_000_000_000);
        for b in 1..BUCKETS {
            let floor = Histogram::bucket_floor_ns(b);
            assert!(floor > Histogram::bucket_floor_ns(b - 1), "bucket {b}");
            assert_eq!(Histogram::bucket_of(floor), b, "bucket {b}");
        }
        // Frames of 20 ms with one of 2 s: the median is 21 ms (its bucket's top), not
        // the slowest frame (what a single bucket above 12 ms gave).
        let mut slow = Histogram::default();
        for _ in 0..99 {
            slow.record(20_500_000);
        }
        slow.record(2_000_000_000);
        assert_eq!(slow.quantile_ns(0.5), 21_000_000);
        assert_eq!(slow.quantile_ns(1.0), 2_000_000_000);
        assert_eq!(Histogram::bucket_of(1_000_700), 1000);
        assert_eq!(Histogram::bucket_of(2_150_000), FINE_BUCKETS + 1);
        assert_eq!(Histogram::bucket_floor_ns(FINE_BUCKETS + 1), 2_100_000);
        // The mean: the 1000 records lie at their buckets' middles, and
        // the 5 ms one at most its own value.
        let want = (1000.0 * 501_000.0 + 5_000_000.0) / 1001.0;
        assert!((h.mean_ns() - want).abs() < 1_000.0, "{}", h.mean_ns());
        assert_eq!(Histogram::default().mean_ns(), 0.0);
    }
}

/// cloth-sim's timing, once a second: how long frames take against their period.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::SimTelemetry")]
pub struct SimTelemetry {
    pub header: Header,
    pub frame: u64,
    /// The cloth's vertices that some triangle uses (not a deleted piece's).
    pub vertices: u32,
    pub triangles: u32,
    /// Wall time of a whole frame (collision and all substeps), since start.
    pub frame_time: Histogram,
    /// Of which the collision broad phase.
    pub collision_time: Histogram,
    /// Frames per second over the last second.
    pub rate_hz: f32,
    /// Longest time an autosave held up a frame, ms.
    pub autosave_ms_max: f32,
    /// The design's substeps per frame.
    pub substeps: u32,
    /// Its material: density kg/m^2, stretch N/m, shear N/m, bending N m, friction,
    /// damping 1/s, shear damping s, bending damping s (the order of a RESET's `uv`; the
    /// seventh since protocol 17, the eighth since 27).
    pub material: [f32; 8],
    /// The body it drapes over ([`scene_body`]).
    pub body: u32,
    /// Cells a side of the cloth it was made from (0: not a square grid, or not known).
    pub grid: u32,
    /// Pinned vertices of the design (what a test of lost edits counts after a restart).
    pub pinned: u32,
    /// The design's cloth model ([`scene_model`]).
    pub model: u32,
    /// 1 when its contact is never crossed (vbd, or xpbd with its guard on), else 0.
    pub never_crosses: u32,
    /// The xpbd model's strain limit (0.2: no triangle past 1.2x its rest length; 0:
    /// none). Since protocol 10.
    pub strain_limit: f32,
    /// 1 while the cloth sleeps: it came to rest and is not simulated until the pen, an
    /// edit or a setting wakes it; else 0. It took the place of padding, so an older
    /// cloth-sim sends 0 and an older studio ignores it.
    pub asleep: u32,
    /// 1 while the simulation is paused (SET_SIMULATING): no frame is stepped and the
    /// cloth stays where it is while edits apply; else 0. Since protocol 18, in the place
    /// of padding.
    pub paused: u32,
    /// Explicit padding (the material's eighth value, since protocol 27, took four
    /// bytes): every byte of a message is a field.
    pub _pad: u32,
}

/// [`SimTelemetry::model`] values.
pub mod scene_model {
    pub const XPBD: u32 = 0;
    pub const VBD: u32 = 1;
    pub const SEED: u32 = 2;
    pub const IMPLICIT: u32 = 3;
    pub const LAST: u32 = IMPLICIT;
    /// Each model's name, by code (as `--model` spells them).
    pub const NAMES: [&str; 4] = ["xpbd", "vbd", "seed", "implicit"];
}

/// [`SimTelemetry::body`] values.
pub mod scene_body {
    pub const CUBE: u32 = 0;
    pub const SPHERE: u32 = 1;
    pub const MANNEQUIN: u32 = 2;
    /// A body from an OBJ file.
    pub const FILE: u32 = 3;
    pub const NONE: u32 = 4;
    /// The A-posed mannequin (since protocol 9).
    pub const MANNEQUIN_APOSE: u32 = 5;
    /// The human body (since protocol 15).
    pub const HUMAN: u32 = 6;
    pub const LAST: u32 = HUMAN;
}

impl Checked for SimTelemetry {
    const WHAT: &'static str = "sim telemetry";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        if !(self.rate_hz.is_finite() && self.autosave_ms_max.is_finite()) {
            return Err("a rate or time is not finite".into());
        }
        if !(self.material.iter().all(|v| v.is_finite() && *v >= 0.0)
            && self.strain_limit.is_finite()
            && self.strain_limit >= 0.0)
        {
            return Err("a material value is negative or not finite".into());
        }
        if self.body > scene_body::LAST {
            return Err(format!("unknown body {}", self.body));
        }
        if self.model > scene_model::LAST
            || self.never_crosses > 1
            || self.asleep > 1
            || self.paused > 1
        {
            return Err(format!(
                "unknown model {}, contact {}, sleep {} or pause {}",
                self.model, self.never_crosses, self.asleep, self.paused
            ));
        }
        Ok(())
    }
}
