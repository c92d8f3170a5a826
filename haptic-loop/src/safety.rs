//! Force safety, applied to every force before it reaches the device:
//!
//! - never NaN or infinite (a non-finite force becomes zero and is counted);
//! - clamped to the device's peak (3.3 N for a Touch);
//! - held to a continuous budget (0.88 N average): a 1 s running mean of the magnitude,
//!   and when it exceeds the budget the force is scaled down so the mean comes back;
//! - ramped up over `ramp_up_s` after (re)engaging, so a pen that grabs never kicks, and
//!   by at most two ticks' worth in one tick, so a late tick does not kick either;
//! - ramped to zero within `stale_ramp_s` (10 ms) once the local model is older than
//!   `stale_after_s` (20 ms), i.e. when cloth-sim is dead or stalled, and on device errors;
//!   within `gone_ramp_s` (2 ms) once cloth-sim's process is known to have exited (the
//!   kernel says so 4-5 ms after a kill -9 of a 128 x 128 cloth-sim, whose memory goes
//!   first: zero within 10 ms of the kill).
//!
//! All state is a handful of numbers: no allocation, no lock.

/// The most of the ramp up one tick may take, s (two nominal 1 kHz periods).
const MAX_RAMP_UP_TICK_S: f32 = 0.002;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SafetyLimits {
    pub max_force: f32,
    pub continuous_force: f32,
    pub ramp_up_s: f32,
    pub stale_after_s: f32,
    pub stale_ramp_s: f32,
    /// The ramp to zero once cloth-sim's process has exited (known at once, not from the
    /// model's age), s.
    pub gone_ramp_s: f32,
    /// Time constant of the running mean for the continuous budget, s.
    pub budget_window_s: f32,
}

impl Default for SafetyLimits {
    fn default() -> Self {
        Self {
            max_force: 3.3,
            continuous_force: 0.88,
            ramp_up_s: 0.1,
            stale_after_s: 0.020,
            stale_ramp_s: 0.010,
            gone_ramp_s: 0.002,
            budget_window_s: 1.0,
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct ForceSafety {
    pub limits: SafetyLimits,
    /// 0..1 scale applied to the force: ramps up while engaged and fresh, down otherwise.
    gain: f32,
    mean_force: f32,
    /// Non-finite forces replaced by zero so far.
    pub non_finite: u64,
}

/// Why the output is held off (for telemetry and logs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hold {
    None,
    Stale,
    /// Older than the staleness limit and its ramp together (the loop itself was held up,
    /// e.g. a VM frozen mid-tick): no force at all, at once.
    Expired,
    /// The process that sent the model has exited (`sim_watch`): ramped to zero over
    /// `gone_ramp_s`.
    Gone,
    DeviceError,
}

impl ForceSafety {
    pub fn new(limits: SafetyLimits) -> Self {
        Self {
            limits,
            gain: 0.0,
            mean_force: 0.0,
            non_finite: 0,
        }
    }

    pub fn gain(&self) -> f32 {
        self.gain
    }

    /// The device's mapping into the scene changed (a new scene's workspace): the pen now
    /// stands elsewhere in the scene, so the force restarts from zero and comes back over
    /// the ramp, as after engaging.
    pub fn restart_ramp(&mut self) {
        self.gain = 0.0;
    }

    /// The force to send, from the wanted `f`, after `dt` seconds; `hold` says whether the
    /// output must go to zero (stale model, device error).
    pub fn filter(&mut self, f: [f32; 3], dt: f32, hold: Hold) -> [f32; 3] {
        let l = &self.limits;
        let dt = if dt.is_finite() {
            dt.clamp(0.0, 0.1)
        } else {
            0.0
        };
        if hold == Hold::None {
            // A tick that comes late (a VM's host held the CPU for 18 ms in a soak) ramps
            // by two ticks' worth at most: the force never jumps by more than 2% of
            // itself in one tick, whatever the clock says.
            let step = dt.min(MAX_RAMP_UP_TICK_S);
            self.gain = (self.gain + step / l.ramp_up_s.max(1e-6)).min(1.0);
        } else if hold == Hold::Expired {
            self.gain = 0.0;
        } else {
            let ramp = if hold == Hold::Gone {
                l.gone_ramp_s
            } else {
                l.stale_ramp_s
            };
            self.gain = (self.gain - dt / ramp.max(1e-6)).max(0.0);
            // Ten steps of a tenth can leave a rounding error above zero (and a tick a
            // hair under 1 ms a sliver): what is left of the ramp's last step is zero.
            if self.gain < 0.02 {
                self.gain = 0.0;
            }
        }
        let mut f = f;
        if !f.iter().all(|c| c.is_finite()) {
            self.non_finite += 1;
            f = [0.0; 3];
        }
        let mag = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        // Clamped to the peak first, then ramped: a wanted force far over the peak (a pen
        // that moved on while cloth-sim was stopped) still comes back over the whole ramp.
        // Ramping first let 1% of 300 N through as the whole 3.3 N in the soak.
        let mut scale = self.gain;
        if mag > l.max_force {
            scale *= l.max_force / mag;
        }
        // Continuous budget: keep the running mean of |F| under the continuous force.
        let a = (dt / l.budget_window_s.max(1e-3)).min(1.0);
        let projected = self.mean_force + a * (mag * scale - self.mean_force);
        if projected > l.continuous_force && mag > 0.0 {
            // The largest output that keeps the mean at the budget this tick.
            let allowed = ((l.continuous_force - (1.0 - a) * self.mean_force) / a.max(1e-9))
                .max(l.continuous_force);
            scale = scale.min(allowed / mag);
        }
        let out = [f[0] * scale, f[1] * scale, f[2] * scale];
        let out_mag = mag * scale;
        self.mean_force += a * (out_mag - self.mean_force);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn norm(f: [f32; 3]) -> f32 {
        (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
    }

    #[test]
    fn clamped_finite_ramped() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        // Ramps up over 100 ms: the first ms gives 1% of the force.
        let f = s.filter([1.0, 0.0, 0.0], 0.001, Hold::None);
        assert!((f[0] - 0.01).abs() < 1e-4, "{f:?}");
        for _ in 0..200 {
            s.filter([0.1, 0.0, 0.0], 0.001, Hold::None);
        }
        // Peak clamp.
        let f = s.filter([100.0, 0.0, 0.0], 0.001, Hold::None);
        assert!(norm(f) <= 3.3 + 1e-5);
        // NaN never passes.
        let f = s.filter([f32::NAN, 1.0, 0.0], 0.001, Hold::None);
        assert_eq!(f, [0.0; 3]);
        assert_eq!(s.non_finite, 1);
    }

    #[test]
    fn a_force_over_the_peak_still_ramps() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        // 300 N wanted (100 times the peak): 1% of the peak on the first tick, not the
        // whole peak, then 1% more a tick up to the peak.
        let mags: Vec<f32> = (0..120)
            .map(|_| norm(s.filter([0.0, 0.0, 300.0], 0.001, Hold::None)))
            .collect();
        assert!((mags[0] - 0.033).abs() < 1e-4, "{:?}", &mags[..3]);
        assert!((mags[49] - 1.65).abs() < 1e-3, "{}", mags[49]);
        assert!(
            mags.windows(2).all(|w| w[1] - w[0] <= 0.034),
            "steps of 1% at most"
        );
        assert!(mags[119] <= 3.3 + 1e-5);
    }

    #[test]
    fn stale_model_ramps_to_zero_within_10_ms() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        for _ in 0..500 {
            s.filter([0.0, 0.5, 0.0], 0.001, Hold::None);
        }
        let mut last = 1.0;
        for k in 0..10 {
            let f = s.filter([0.0, 0.5, 0.0], 0.001, Hold::Stale);
            assert!(norm(f) < last || k == 0);
            last = norm(f);
        }
        assert_eq!(last, 0.0, "zero after 10 ms of staleness");
        // Ticks a hair short of 1 ms: still zero by the tenth.
        for _ in 0..500 {
            s.filter([0.0, 0.5, 0.0], 0.001, Hold::None);
        }
        let f = (0..10)
            .map(|_| s.filter([0.0, 0.5, 0.0], 0.000_99, Hold::Stale))
            .last()
            .unwrap();
        assert_eq!(norm(f), 0.0, "zero by the tenth short tick");
        // A model past the limit and its ramp (a tick held up): zero at once.
        for _ in 0..500 {
            s.filter([0.0, 0.5, 0.0], 0.001, Hold::None);
        }
        let f = s.filter([0.0, 0.5, 0.0], 0.005, Hold::Expired);
        assert_eq!(norm(f), 0.0, "expired: zero in one tick");
    }

    #[test]
    fn a_late_tick_does_not_jump_the_ramp() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        // The first tick after engaging comes 18 ms late: 2% of the force, not 18%.
        let f = s.filter([1.0, 0.0, 0.0], 0.018, Hold::None);
        assert!((f[0] - 0.02).abs() < 1e-4, "{f:?}");
        // On time again, the ramp goes on at 1% a tick.
        let f = s.filter([1.0, 0.0, 0.0], 0.001, Hold::None);
        assert!((f[0] - 0.03).abs() < 1e-4, "{f:?}");
        // Ramping down is never held back: a late stale tick takes its whole share.
        for _ in 0..200 {
            s.filter([0.5, 0.0, 0.0], 0.001, Hold::None);
        }
        let f = s.filter([0.5, 0.0, 0.0], 0.005, Hold::Stale);
        assert!((norm(f) - 0.25).abs() < 1e-3, "{f:?}");
    }

    #[test]
    fn a_gone_simulation_ramps_to_zero_within_2_ms() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        for _ in 0..200 {
            s.filter([0.0, 0.5, 0.0], 0.001, Hold::None);
        }
        let forces: Vec<f32> = (0..3)
            .map(|_| norm(s.filter([0.0, 0.5, 0.0], 0.001, Hold::Gone)))
            .collect();
        // Half after the first tick, zero from the second on.
        assert!((forces[0] - 0.25).abs() < 1e-4, "{forces:?}");
        assert_eq!(
            forces[1..],
            [0.0, 0.0],
            "zero by the second tick: {forces:?}"
        );
    }

    #[test]
    fn continuous_budget_holds_the_mean() {
        let mut s = ForceSafety::new(SafetyLimits::default());
        let mut sum = 0.0;
        let n = 5000;
        for k in 0..n {
            let f = s.filter([2.5, 0.0, 0.0], 0.001, Hold::None);
            if k >= n - 2000 {
                sum += norm(f);
            }
        }
        let mean = sum / 2000.0;
        assert!(mean <= 0.88 * 1.02, "mean force {mean}");
        assert!(mean > 0.8, "the budget is used, not wasted: {mean}");
    }
}
