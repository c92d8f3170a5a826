//! The simulated pen: a mass held by a hand (a spring-damper to the hand's target), moved
//! by the rendered force, inside the Touch's workspace; its hand follows a script, stays
//! still, or follows the UI's pointer.

use shared::haptic_to_sim::{BUTTON_1, BUTTON_2};

use super::{DeviceError, DeviceState, HapticDevice, PointerTarget, Workspace};

/// A press of the pointer's button 1 reaches the pen once the pen is at the pointer
/// ([`PRESS_AT_M`]), or has come to rest this near it, m (within the cloth's 5 cm grab
/// radius, and beyond the 2 cm a contact's rendered force can hold the pen off its
/// hand's target), or after [`PRESS_WAIT_S`]: a hand moves to a place, then presses.
/// Pressed at once, the mouse's pinch grabbed where the pen had been left (a dress's hem
/// 50 cm below the point pressed, or nothing), and a cut stroke began with the pen's trip
/// there.
pub const PRESS_REACH_M: f32 = 0.03;
/// Nearer than this to the pointer, m, the pen is there, however fast it moves.
pub const PRESS_AT_M: f32 = 0.005;
/// Slower than this, m/s, the pen has come to rest.
const PRESS_REST_M_S: f32 = 0.1;
/// The longest a press waits for the pen to reach the pointer, s (a pen the rendered
/// force keeps further off presses anyway).
pub const PRESS_WAIT_S: f64 = 0.3;

/// Where the simulated pen's hand wants to be.
pub trait TargetSource {
    /// The hand target and buttons at `t` seconds since start.
    fn target(&mut self, t: f64) -> ([f32; 3], u32);
}

/// A simulated pen: a mass held by a hand (a spring-damper to the hand's target), moved by
/// the rendered force, inside the Touch's workspace. It moves and reacts like a held pen:
/// a stiff spring pushing on it displaces it until the hand's pull balances.
pub struct SimDevice<T: TargetSource> {
    pub mass: f32,
    pub hand_stiffness: f32,
    pub hand_damping: f32,
    pub workspace: Workspace,
    source: T,
    t: f64,
    x: [f32; 3],
    v: [f32; 3],
    force: [f32; 3],
    buttons: u32,
    /// The UI's pointer, when it drives the pen (overrides the source).
    pointer: Option<([f32; 3], u32)>,
    /// How long the pointer's press has waited for the pen to reach it, s.
    press_wait: f64,
}

impl<T: TargetSource> PointerTarget for SimDevice<T> {
    fn set_pointer(&mut self, target: [f32; 3], buttons: u32) {
        self.pointer = Some((target, buttons));
    }
}

impl<T: TargetSource> SimDevice<T> {
    pub fn new(mut source: T, workspace: Workspace) -> Self {
        let (x, buttons) = source.target(0.0);
        let (mass, hand_stiffness) = (0.05f32, 150.0f32);
        Self {
            mass,
            hand_stiffness,
            // Slightly under-critical, like a relaxed grip.
            hand_damping: 0.8 * 2.0 * (mass * hand_stiffness).sqrt(),
            workspace,
            source,
            t: 0.0,
            x: workspace.clamp(x),
            v: [0.0; 3],
            force: [0.0; 3],
            buttons,
            pointer: None,
            press_wait: 0.0,
        }
    }
}

impl<T: TargetSource> SimDevice<T> {
    /// The pointer's `buttons` as the pen reports them: a new press of button 1 held
    /// back until the pen is at `target` or at rest near it ([`PRESS_REACH_M`]), or has waited
    /// [`PRESS_WAIT_S`]; a press under way and a release at once.
    fn press_when_there(&mut self, buttons: u32, target: [f32; 3], dt: f32) -> u32 {
        if buttons & BUTTON_1 == 0 || self.buttons & BUTTON_1 != 0 {
            self.press_wait = 0.0;
            return buttons;
        }
        let d2: f32 = (0..3).map(|i| (self.x[i] - target[i]).powi(2)).sum();
        let v2: f32 = self.v.iter().map(|v| v * v).sum();
        let at_rest = d2 <= PRESS_REACH_M * PRESS_REACH_M && v2 <= PRESS_REST_M_S * PRESS_REST_M_S;
        if d2 <= PRESS_AT_M * PRESS_AT_M || at_rest || self.press_wait >= PRESS_WAIT_S {
            self.press_wait = 0.0;
            buttons
        } else {
            self.press_wait += dt as f64;
            buttons & !BUTTON_1
        }
    }
}

impl<T: TargetSource> HapticDevice for SimDevice<T> {
    fn name(&self) -> &str {
        "sim"
    }

    fn read(&mut self, dt: f32) -> Result<DeviceState, DeviceError> {
        let dt = if dt.is_finite() {
            dt.clamp(0.0, 0.005)
        } else {
            0.0
        };
        self.t += dt as f64;
        let (target, buttons) = match self.pointer {
            Some(p) => p,
            None => self.source.target(self.t),
        };
        let target = self.workspace.clamp(target);
        let buttons = buttons & (BUTTON_1 | BUTTON_2);
        // Semi-implicit Euler: hand spring-damper plus the rendered force.
        for i in 0..3 {
            let a = (self.hand_stiffness * (target[i] - self.x[i]) - self.hand_damping * self.v[i]
                + self.force[i])
                / self.mass;
            self.v[i] += a * dt;
            self.x[i] += self.v[i] * dt;
        }
        let clamped = self.workspace.clamp(self.x);
        for i in 0..3 {
            if clamped[i] != self.x[i] {
                self.v[i] = 0.0;
            }
        }
        self.x = clamped;
        self.buttons = if self.pointer.is_some() {
            self.press_when_there(buttons, target, dt)
        } else {
            buttons
        };
        Ok(DeviceState {
            position: self.x,
            velocity: self.v,
            buttons: self.buttons,
        })
    }

    fn write_force(&mut self, force: [f32; 3]) -> Result<(), DeviceError> {
        self.force = force;
        Ok(())
    }

    fn set_workspace(&mut self, ws: Workspace) {
        self.workspace = ws;
    }
}

/// A fixed target (the pen held still), for tests and idle runs.
#[derive(Debug, Clone, Copy)]
pub struct Still(pub [f32; 3], pub u32);

impl TargetSource for Still {
    fn target(&mut self, _t: f64) -> ([f32; 3], u32) {
        (self.0, self.1)
    }
}

/// Timed targets: `(time s, position, buttons)`, linearly interpolated, sorted by time.
#[derive(Debug, Clone)]
pub struct Script {
    pub points: Vec<(f64, [f32; 3], u32)>,
}

impl Script {
    /// Parses lines `t x y z buttons` (seconds, metres, bit mask); `#` starts a comment.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut points = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let f: Vec<&str> = line.split_whitespace().collect();
            if f.len() != 5 {
                return Err(format!(
                    "line {}: expected 't x y z buttons', got '{line}'",
                    n + 1
                ));
            }
            let num = |s: &str| -> Result<f64, String> {
                s.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("line {}: '{s}' is not a finite number", n + 1))
            };
            let t = num(f[0])?;
            // Positions are f32: a number past its range would become infinite.
            let num32 = |s: &str| -> Result<f32, String> {
                let v = num(s)? as f32;
                v.is_finite()
                    .then_some(v)
                    .ok_or_else(|| format!("line {}: '{s}' is out of range", n + 1))
            };
            let p = [num32(f[1])?, num32(f[2])?, num32(f[3])?];
            let b: u32 = f[4]
                .parse()
                .map_err(|_| format!("line {}: buttons '{}' is not a bit mask", n + 1, f[4]))?;
            if let Some(&(last, _, _)) = points.last()
                && t < last
            {
                return Err(format!("line {}: time {t} goes backwards", n + 1));
            }
            points.push((t, p, b));
        }
        if points.is_empty() {
            return Err("the script has no points".into());
        }
        Ok(Self { points })
    }
}

impl TargetSource for Script {
    fn target(&mut self, t: f64) -> ([f32; 3], u32) {
        let pts = &self.points;
        let k = pts.partition_point(|p| p.0 <= t);
        if k == 0 {
            return (pts[0].1, pts[0].2);
        }
        if k >= pts.len() {
            let l = pts[pts.len() - 1];
            return (l.1, l.2);
        }
        let (a, b) = (pts[k - 1], pts[k]);
        let s = ((t - a.0) / (b.0 - a.0).max(1e-9)) as f32;
        (std::array::from_fn(|i| a.1[i] + (b.1[i] - a.1[i]) * s), a.2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pen_follows_its_hand_and_yields_to_force() {
        let mut d = SimDevice::new(Still([0.0, 0.6, 0.0], 0), Workspace::default());
        for _ in 0..1000 {
            d.read(0.001).unwrap();
        }
        let s = d.read(0.001).unwrap();
        assert!((s.position[1] - 0.6).abs() < 1e-4);
        // A steady 1.5 N up: it settles 1.5 / 150 = 1 cm above the hand's target.
        d.write_force([0.0, 1.5, 0.0]).unwrap();
        for _ in 0..2000 {
            d.read(0.001).unwrap();
        }
        let s = d.read(0.001).unwrap();
        assert!((s.position[1] - 0.61).abs() < 5e-4, "{:?}", s.position);
    }

    /// The pointer pressed 10 cm or more from where the pen rests: the press reaches the pen
    /// once the pen is within 5 mm of it (it used to press at once, where the pen was);
    /// held 4 cm off by a force, the press comes after 0.3 s anyway, and at once where the
    /// pen rests within 3 cm; a release is at once.
    #[test]
    fn a_press_waits_for_the_pen_to_get_there() {
        let mut d = SimDevice::new(Still([0.0, 0.6, 0.0], 0), Workspace::default());
        for _ in 0..500 {
            d.read(0.001).unwrap();
        }
        // As far up as the workspace lets the pen go.
        let there = d.workspace.clamp([0.0, 1.1, 0.0]);
        assert!(there[1] > 0.7, "{there:?}");
        d.set_pointer(there, BUTTON_1);
        let first = d.read(0.001).unwrap();
        assert_eq!(first.buttons & BUTTON_1, 0, "pressed 50 cm away");
        let mut ms = 1;
        let pressed = loop {
            let s = d.read(0.001).unwrap();
            ms += 1;
            if s.buttons & BUTTON_1 != 0 {
                break s;
            }
            assert!(ms < 400, "never pressed");
        };
        let off = (pressed.position[1] - there[1]).abs();
        assert!(off <= PRESS_AT_M, "pressed {off} m from the pointer");
        assert!(ms < 300, "{ms} ms to get there");
        d.set_pointer(there, 0);
        assert_eq!(d.read(0.001).unwrap().buttons, 0);
        // A force holding the pen 4 cm off (6 N against the hand's 150 N/m): pressed
        // after the wait.
        d.write_force([0.0, -6.0, 0.0]).unwrap();
        for _ in 0..1000 {
            d.read(0.001).unwrap();
        }
        d.set_pointer(there, BUTTON_1);
        let waited = (0..1000)
            .position(|_| d.read(0.001).unwrap().buttons & BUTTON_1 != 0)
            .unwrap();
        assert!((299..=301).contains(&waited), "pressed after {waited} ms");
        // Held 2 cm off (3 N), at rest there: pressed at once.
        d.set_pointer(there, 0);
        d.write_force([0.0, -3.0, 0.0]).unwrap();
        for _ in 0..1000 {
            d.read(0.001).unwrap();
        }
        d.set_pointer(there, BUTTON_1);
        assert_eq!(d.read(0.001).unwrap().buttons & BUTTON_1, BUTTON_1);
    }

    #[test]
    fn scripts_parse_and_interpolate() {
        let mut s = Script::parse("# t x y z buttons\n0 0 0.6 0 0\n1 0.1 0.6 0 1\n").unwrap();
        let (p, b) = s.target(0.5);
        assert!((p[0] - 0.05).abs() < 1e-6 && b == 0);
        assert_eq!(s.target(2.0), ([0.1, 0.6, 0.0], 1));
        assert!(Script::parse("0 0 0 0").is_err());
        assert!(
            Script::parse("1 0 0 0 0\n0 0 0 0 0")
                .unwrap_err()
                .contains("backwards")
        );
        assert!(Script::parse("0 nan 0 0 0").is_err());
        assert!(
            Script::parse("0 0 -1e300 0 0")
                .unwrap_err()
                .contains("out of range")
        );
    }
}
