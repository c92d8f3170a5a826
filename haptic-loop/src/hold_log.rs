//! The log lines for the force's hold (whether the local model is fresh), without a line
//! for every frame of a cloth slower than the loop's 20 ms: a 128 x 128 cloth landing on
//! one core faded and came back 180 times in 45 s, each a line. After a line that the
//! force faded (the model stale or expired), further changes between fresh, stale and
//! expired are kept quiet for [`QUIET_TICKS`]; then one line says the force kept fading,
//! and one where it stands. A device error or cloth-sim's exit is always said at once.
//! Static strings only: it runs on the loop's thread.

use crate::safety::Hold;

/// Ten seconds of 1 kHz ticks.
pub const QUIET_TICKS: u64 = 10_000;

/// What [`HoldLog`] says for each hold.
pub fn line(hold: Hold) -> &'static str {
    match hold {
        Hold::None => "local model fresh: rendering force",
        Hold::Stale => "local model stale (no new model for 20 ms): force ramped to zero",
        Hold::Expired => "local model expired (no new model for 30 ms): force zero",
        Hold::Gone => "cloth-sim exited: force ramped to zero within 2 ms",
        Hold::DeviceError => "device error: force ramped to zero",
    }
}

/// Said once the quiet time ends with changes left unsaid.
pub const KEPT_FADING: &str = "local model: came late again and again in the last 10 s \
     (cloth-sim's frames slower than 20 ms), the force fading each time; lines about it \
     at most every 10 s";

#[derive(Clone, Copy, Debug)]
pub struct HoldLog {
    was: Hold,
    /// The tick of the last line that the force faded (None: none yet).
    faded_at: Option<u64>,
    /// Changes left unsaid since.
    unsaid: bool,
}

impl HoldLog {
    /// The hold the loop starts in (not said).
    pub fn new(start: Hold) -> Self {
        Self {
            was: start,
            faded_at: None,
            unsaid: false,
        }
    }

    /// The hold at `tick`: the lines to say now, if any.
    pub fn note(&mut self, hold: Hold, tick: u64, log: &mut impl FnMut(&str)) {
        let about_model = |h: Hold| matches!(h, Hold::None | Hold::Stale | Hold::Expired);
        let quiet = self
            .faded_at
            .is_some_and(|t| tick < t.saturating_add(QUIET_TICKS));
        if hold != self.was {
            if quiet && about_model(hold) && about_model(self.was) {
                self.unsaid = true;
            } else {
                self.say(hold, tick, log);
            }
            self.was = hold;
        } else if self.unsaid && !quiet {
            self.say(hold, tick, log);
        }
    }

    fn say(&mut self, hold: Hold, tick: u64, log: &mut impl FnMut(&str)) {
        if std::mem::take(&mut self.unsaid) {
            log(KEPT_FADING);
        }
        log(line(hold));
        if matches!(hold, Hold::Stale | Hold::Expired) {
            self.faded_at = Some(tick);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(holds: &[(Hold, u64)]) -> Vec<&'static str> {
        let mut said = Vec::new();
        let mut h = HoldLog::new(Hold::Stale);
        for &(hold, tick) in holds {
            h.note(hold, tick, &mut |l| {
                said.push(match l {
                    KEPT_FADING => "kept fading",
                    l if l == line(Hold::None) => "fresh",
                    l if l == line(Hold::Stale) => "stale",
                    l if l == line(Hold::Expired) => "expired",
                    l if l == line(Hold::Gone) => "gone",
                    _ => "device",
                })
            });
        }
        said
    }

    #[test]
    fn a_flapping_model_is_said_once_in_ten_seconds_and_the_rest_at_once() {
        // Fresh, then a fade every 40 ms for 12 s, then fresh for good.
        let mut holds = vec![(Hold::None, 100)];
        for k in 1..300 {
            holds.push((Hold::Stale, 100 + 40 * k));
            holds.push((Hold::None, 120 + 40 * k));
        }
        holds.push((Hold::None, 21_000));
        assert_eq!(
            run(&holds),
            [
                "fresh",
                "stale",
                "kept fading",
                "stale",
                "kept fading",
                "fresh"
            ]
        );
        // Always at once: the device, and cloth-sim's exit, even in the quiet time.
        let holds = [
            (Hold::None, 100),
            (Hold::Stale, 200),
            (Hold::DeviceError, 300),
            (Hold::None, 400),
            (Hold::Gone, 500),
        ];
        assert_eq!(run(&holds), ["fresh", "stale", "device", "fresh", "gone"]);
        // A lone fade and its return, seconds apart, are both said.
        let holds = [
            (Hold::None, 100),
            (Hold::Stale, 20_000),
            (Hold::None, 31_000),
        ];
        assert_eq!(run(&holds), ["fresh", "stale", "fresh"]);
    }
}
