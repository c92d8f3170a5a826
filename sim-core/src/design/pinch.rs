//! The paper's pinch as the designer uses it: the pen grabs the vertex nearest to it (and,
//! with a grip radius, those around it); the spring itself is the solver's (`solver::Pinch`).

use glam::Vec3;

use super::document::Design;
use super::error::EditError;
use crate::solver::Pinch;

impl Design {
    /// Grabs the vertex nearest to `p` within `radius` with a spring of `stiffness` N/m,
    /// and with `grip > 0` every vertex within `grip` of that one as well.
    pub fn pinch_begin(
        &mut self,
        p: Vec3,
        radius: f32,
        grip: f32,
        stiffness: f32,
    ) -> Result<u32, EditError> {
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(EditError::BadValue {
                name: "pinch stiffness",
                rule: "a positive number of N/m",
                value: stiffness.to_string(),
            });
        }
        if !(p.is_finite() && grip.is_finite() && grip >= 0.0) {
            return Err(EditError::BadDirection);
        }
        self.check_editable()?;
        let v = self
            .sim
            .cloth
            .nearest_vertex(p, radius)
            .ok_or(EditError::NothingNear { radius })?;
        let centre = self.sim.cloth.x[v as usize];
        let mut held = vec![(v, centre - p)];
        if grip > 0.0 {
            for (i, x) in self.sim.cloth.x.iter().enumerate() {
                let i = i as u32;
                if i != v && (*x - centre).length() <= grip && self.sim.cloth.live.vertex_alive(i) {
                    held.push((i, *x - p));
                }
            }
        }
        self.sim.set_pinch(Some(Pinch {
            vertex: v,
            held,
            target: p,
            stiffness,
            force_limit: None,
        }));
        Ok(v)
    }

    /// Moves the pinch's pointer end.
    pub fn pinch_move(&mut self, target: Vec3) {
        self.sim.pinch_move(target);
    }

    /// Releases the pinch (button up).
    pub fn pinch_end(&mut self) {
        self.sim.set_pinch(None);
    }
}
