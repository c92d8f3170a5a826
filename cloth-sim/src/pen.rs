//! The pen as cloth-sim sees it: the device samples of each frame interval (its path,
//! replayed through the substeps), the force the haptic loop rendered, and what button 1
//! does with the current tool.

use glam::Vec3;
use shared::haptic_to_sim::{AppliedForce, BUTTON_1, DeviceSample};
use shared::services;
use shared::sim_to_ui::tool;
use shared::{Checked, MessageError};
use sim_core::design::{Design, EditError};
use sim_core::solver::PenInput;

use crate::config::{ServiceConfig, ServiceStats};

/// An applied force older than this no longer limits the pinch to its size: the haptic
/// loop is gone, so the cloth gets no pull at all.
const APPLIED_STALE_S: f64 = 0.02;
/// A pen with no sample for this long (haptic-loop stopped or killed) is let go: its
/// buttons read as released, so a pinch ends and the cloth hangs free where it was.
pub(crate) const PEN_GONE_S: f64 = 0.1;
/// A tear by the pen tears (and lets the cloth stretch far enough to tear) only this
/// close to the vertex it holds, m: the cloth tears where the hand pulls. Tearing on
/// everywhere, a pull at a sewn dress's hem tore holes at its shoulders and seams, the
/// sides stretched most under the loosened limit.
pub(crate) const PEN_TEAR_REACH: f32 = 0.08;

pub(crate) fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// The current tool and what a press of the pen is in the middle of.
#[derive(Debug)]
pub(crate) struct Tools {
    pub(crate) tool: u32,
    pub(crate) rgba: [u8; 4],
    pub(crate) brush_m: f32,
    pub(crate) sew_first: Option<u32>,
    was_down: bool,
    stroke: Vec<Vec3>,
    /// The design's tearing (on, where) before the pen's tear began.
    tear_was: (bool, Option<f32>),
    /// How many of the pen's operations have been answered, and the last answer (done,
    /// message), for the studio's status line.
    pub(crate) said: u32,
    pub(crate) last_said: (bool, String),
}

impl Default for Tools {
    fn default() -> Self {
        Self {
            tool: tool::PINCH,
            rgba: [200, 30, 40, 255],
            brush_m: 0.01,
            sew_first: None,
            was_down: false,
            stroke: Vec::new(),
            tear_was: (false, None),
            said: 0,
            last_said: (true, String::new()),
        }
    }
}

impl Tools {
    /// Takes up `tool`. A pinch or tear the pen is holding ends first (its button then
    /// let go would reach the new tool, and the cloth stayed held, tearing on).
    pub(crate) fn switch(&mut self, design: &mut Design, tool: u32, rgba: [u8; 4], brush_m: f32) {
        if self.was_down && matches!(self.tool, tool::PINCH | tool::TEAR) {
            design.pinch_end();
            if self.tool == tool::TEAR {
                (design.tear.enabled, design.tear.near_pinch) = self.tear_was;
            }
        }
        self.stroke.clear();
        self.tool = tool;
        self.rgba = rgba;
        self.brush_m = brush_m;
        self.sew_first = None;
    }
}

/// The samples of the current frame interval (the pen's path), the newest one, and the
/// newest force the haptic loop rendered.
#[derive(Debug, Default)]
pub(crate) struct PenFeed {
    /// Samples received since the last frame started, oldest first.
    pub(crate) path: Vec<DeviceSample>,
    pub(crate) latest: Option<DeviceSample>,
    applied: Option<AppliedForce>,
    /// The reason of the last rejected message, to log once.
    reject: Option<String>,
    reject_new: bool,
}

impl PenFeed {
    pub(crate) fn new() -> Self {
        Self {
            path: Vec::with_capacity(64),
            ..Self::default()
        }
    }

    /// The path starts afresh with the newest sample of the last frame.
    pub(crate) fn next_frame(&mut self) {
        if let Some(last) = self.path.last().copied() {
            self.path.clear();
            self.path.push(last);
        }
    }

    fn reject(&mut self, stats: &mut ServiceStats, e: MessageError) {
        stats.rejected += 1;
        let e = e.to_string();
        if self.reject.as_ref() != Some(&e) {
            self.reject = Some(e);
            self.reject_new = true;
        }
    }

    /// A rejected message not yet logged, once.
    pub(crate) fn take_new_reject(&mut self) -> Option<String> {
        std::mem::take(&mut self.reject_new)
            .then(|| self.reject.clone().unwrap_or_else(|| "?".into()))
    }

    /// Takes whatever arrived (never blocks).
    pub(crate) fn drain(
        &mut self,
        device: &services::Sub<DeviceSample>,
        applied: &services::Sub<AppliedForce>,
        stats: &mut ServiceStats,
    ) {
        while let Ok(Some(s)) = device.receive() {
            match s.check() {
                Ok(()) => {
                    if self.path.len() == self.path.capacity() && !self.path.is_empty() {
                        self.path.remove(0);
                    }
                    self.path.push(*s);
                    self.latest = Some(*s);
                    stats.samples += 1;
                }
                Err(e) => self.reject(stats, e),
            }
        }
        while let Ok(Some(s)) = applied.receive() {
            match s.check() {
                Ok(()) => {
                    self.applied = Some(*s);
                    stats.applied_forces += 1;
                }
                Err(e) => self.reject(stats, e),
            }
        }
    }

    /// The pen for substep `k` of `n`: the frame's path replayed at substep rate (the last
    /// substep takes the newest sample), and the pull limit from the applied force.
    pub(crate) fn input(&self, k: usize, n: usize, cfg: &ServiceConfig) -> Option<PenInput> {
        if self.path.is_empty() {
            return None;
        }
        let i = ((k + 1) * self.path.len())
            .div_ceil(n.max(1))
            .clamp(1, self.path.len())
            - 1;
        let force_limit = match (&self.applied, cfg.couple_applied_force) {
            (Some(a), true) => {
                let age_s = shared::monotonic_ns().saturating_sub(a.header.sent_ns) as f64 * 1e-9;
                // What the hand was pulled with, plus a margin against the lag between
                // the two; nothing once the haptic loop stopped rendering.
                Some(if age_s <= APPLIED_STALE_S {
                    v3(a.force).length() * 1.1 + 0.05
                } else {
                    0.0
                })
            }
            _ => None,
        };
        Some(PenInput {
            target: v3(self.path[i].position),
            force_limit,
        })
    }

    /// Lets go of a pen that went silent for [`PEN_GONE_S`]: its newest sample keeps its
    /// place with no button held. Returns whether it did so now.
    pub(crate) fn let_go_if_gone(&mut self) -> bool {
        let Some(p) = self.latest.as_mut() else {
            return false;
        };
        let age_s = shared::monotonic_ns().saturating_sub(p.header.sent_ns) as f64 * 1e-9;
        if age_s > PEN_GONE_S && p.buttons != 0 {
            p.buttons = 0;
            self.path.clear();
            self.path.push(*p);
            return true;
        }
        false
    }

    /// Where the tip is now (infinitely far without a sample), and when that sample was
    /// sent (0: none).
    pub(crate) fn tip(&self) -> (Vec3, u64) {
        self.latest.map_or((Vec3::splat(f32::INFINITY), 0), |p| {
            (v3(p.position), p.header.sent_ns)
        })
    }
}

/// What button 1 does with the current tool this frame.
pub(crate) fn pen_acts(
    design: &mut Design,
    t: &mut Tools,
    p: &DeviceSample,
    cfg: &ServiceConfig,
    stats: &mut ServiceStats,
    log: &mut dyn FnMut(&str),
) {
    let tip = v3(p.position);
    let down = p.buttons & BUTTON_1 != 0;
    let (pressed, released) = (down && !t.was_down, !down && t.was_down);
    t.was_down = down;
    // The studio shows a refusal as "Refused: " and the message.
    let mut report = |t: &mut Tools, what: &str, r: Result<String, EditError>| {
        let (ok, m) = match r {
            Ok(m) => {
                log(&m);
                (true, m)
            }
            Err(e) => {
                log(&format!("The pen's {what} was refused: {e}"));
                (false, format!("{what} by the pen: {e}"))
            }
        };
        t.said = t.said.wrapping_add(1).max(1);
        t.last_said = (ok, m);
    };
    match t.tool {
        tool::PINCH | tool::TEAR => {
            if pressed {
                if t.tool == tool::TEAR {
                    t.tear_was = (design.tear.enabled, design.tear.near_pinch);
                    design.tear.enabled = true;
                    design.tear.near_pinch = Some(PEN_TEAR_REACH);
                }
                // A grab that finds no cloth says so (a held vertex shows by itself).
                match design.pinch_begin(tip, cfg.pinch_radius, 0.0, cfg.pinch_stiffness) {
                    Ok(_) => stats.pinches += 1,
                    Err(e) => {
                        let what = if t.tool == tool::TEAR {
                            "tear"
                        } else {
                            "pinch"
                        };
                        report(t, what, Err(e));
                    }
                }
            } else if down {
                design.pinch_move(tip);
            } else if released {
                design.pinch_end();
                if t.tool == tool::TEAR {
                    (design.tear.enabled, design.tear.near_pinch) = t.tear_was;
                }
            }
        }
        tool::CUT => {
            if down {
                t.stroke.push(tip);
            } else if released {
                let stroke = std::mem::take(&mut t.stroke);
                report(
                    t,
                    "cut stroke",
                    design
                        .cut_stroke(&stroke, 0.02)
                        .map(|n| format!("Cut: {n} vertices split along the pen's stroke")),
                );
            }
        }
        // Each frame's dab is undoable on its own; refusals (off the cloth) are quiet.
        tool::PAINT if down => {
            let _ = design.paint(tip, t.brush_m, t.rgba);
        }
        tool::SEW => {
            if pressed && let Some(v) = design.sim.cloth.nearest_vertex(tip, cfg.pinch_radius) {
                match t.sew_first.take() {
                    None => t.sew_first = Some(v),
                    Some(a) => report(
                        t,
                        "sew",
                        design
                            .sew(a, v)
                            .map(|_| format!("Sew: vertices {a} and {v} joined by the pen")),
                    ),
                }
            }
        }
        tool::PIN => {
            if pressed && let Some(v) = design.sim.cloth.nearest_vertex(tip, cfg.pinch_radius) {
                let on = !design.sim.cloth.is_pinned(v as usize);
                let said = crate::commands::pin_one(design, v, on, " by the pen");
                report(t, "pin", said);
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pen held down that goes silent is let go once, where it was; a live one is not.
    #[test]
    fn a_silent_pen_is_let_go() {
        let sample = |age_s: f64| DeviceSample {
            header: shared::Header {
                sent_ns: shared::monotonic_ns() - (age_s * 1e9) as u64,
                ..shared::Header::default()
            },
            position: [0.1, 0.5, 0.0],
            buttons: BUTTON_1,
            ..DeviceSample::default()
        };
        let mut feed = PenFeed::new();
        feed.latest = Some(sample(0.01));
        assert!(!feed.let_go_if_gone(), "live");
        feed.latest = Some(sample(2.0 * PEN_GONE_S));
        assert!(feed.let_go_if_gone());
        let p = feed.latest.unwrap();
        assert_eq!((p.buttons, p.position), (0, [0.1, 0.5, 0.0]));
        assert_eq!(feed.path.len(), 1);
        assert!(!feed.let_go_if_gone(), "once");
    }
}
