//! Operations given on the pattern (UV space), as a designer selects in a 2D pattern
//! view: delete a rectangle of cloth, or seam two boundary paths drawn as segments.

use glam::Vec2;

use super::{EditError, STITCH_FORCE};
use crate::cloth::Simulation;

impl Simulation {
    /// Where live vertex `v` sits on the pattern (the UV of its first triangle's corner).
    pub fn vertex_uv(&self, v: u32) -> Option<Vec2> {
        let live = &self.cloth.live;
        live.tris_of(v)
            .iter()
            .filter_map(|&t| live.tri(t))
            .find_map(|t| t.corner(v).map(|k| t.uv[k]))
    }

    /// Removes the triangles whose UV centre lies in `[min, max]`. Undoable as one
    /// operation; refused when the rectangle holds none.
    pub fn remove_region(&mut self, min: Vec2, max: Vec2) -> Result<usize, EditError> {
        if !(min.is_finite() && max.is_finite()) {
            return Err(EditError::BadDirection);
        }
        let (lo, hi) = (min.min(max), min.max(max));
        let slots: Vec<u32> = self
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                let c = (t.uv[0] + t.uv[1] + t.uv[2]) / 3.0;
                c.cmpge(lo).all() && c.cmple(hi).all()
            })
            .map(|(s, _)| s)
            .collect();
        if slots.is_empty() {
            return Err(EditError::NothingOnPattern { what: "triangle" });
        }
        self.remove_triangles(&slots)
    }

    /// The live border vertices within `tol` (UV) of segment `a -> b`, past its start (by
    /// more than `tol`), in order from `a` to `b`.
    pub fn pattern_path(&self, a: Vec2, b: Vec2, tol: f32) -> Vec<u32> {
        let d = b - a;
        let len2 = d.length_squared();
        if len2 <= 0.0 || tol.is_nan() || tol <= 0.0 {
            return Vec::new();
        }
        let len = len2.sqrt();
        let live = &self.cloth.live;
        let mut on: Vec<(f32, u32)> = (0..self.cloth.len() as u32)
            .filter(|&v| live.vertex_alive(v) && live.is_boundary(v))
            .filter_map(|v| {
                let p = self.vertex_uv(v)?;
                let t = (p - a).dot(d) / len2;
                let dist = (p - (a + d * t.clamp(0.0, 1.0))).length();
                (dist < tol && t * len > tol && t <= 1.0 + tol / len).then_some((t, v))
            })
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        on.into_iter().map(|(_, v)| v).collect()
    }

    /// A seam between the border paths along two pattern segments (see
    /// [`Simulation::pattern_path`]); returns the stitched pairs.
    pub fn seam_on_pattern(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
    ) -> Result<usize, EditError> {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(EditError::BadValue {
                name: "seam tolerance",
                rule: "a positive distance on the pattern",
                value: tol.to_string(),
            });
        }
        let pa = self.pattern_path(a[0], a[1], tol);
        let pb = self.pattern_path(b[0], b[1], tol);
        if pa.len() < 2 || pb.len() < 2 {
            return Err(EditError::NothingOnPattern {
                what: "border path of two or more vertices",
            });
        }
        self.add_seam(&pa, &pb, STITCH_FORCE)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use crate::edit::EditError;
    use crate::scenario::{ScenarioConfig, ScenarioName, build_simulation};

    #[test]
    fn pattern_selections_remove_and_seam_or_refuse() {
        let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
        cfg.grid = 8;
        let mut sim = build_simulation(&cfg).unwrap();
        let tris = sim.cloth.live.tri_count();
        // Nothing there: refused, nothing changes.
        assert_eq!(
            sim.remove_region(Vec2::splat(2.0), Vec2::splat(3.0)),
            Err(EditError::NothingOnPattern { what: "triangle" })
        );
        assert_eq!(sim.cloth.live.tri_count(), tris);
        // The corner square beyond u, v = 0.75: 2 x 2 cells, 8 triangles.
        assert_eq!(
            sim.remove_region(Vec2::splat(0.75), Vec2::splat(1.5)),
            Ok(8)
        );
        assert_eq!(sim.cloth.live.tri_count(), tris - 8);
        // The two flaps' edges along the cut lines, from the inner corner outwards.
        let a = sim.pattern_path(Vec2::new(0.75, 0.75), Vec2::new(0.75, 1.0), 0.03);
        let b = sim.pattern_path(Vec2::new(0.75, 0.75), Vec2::new(1.0, 0.75), 0.03);
        assert_eq!((a.len(), b.len()), (2, 2), "{a:?} {b:?}");
        let uv = |v: u32| sim.vertex_uv(v).unwrap();
        assert!(uv(a[0]).y < uv(a[1]).y && uv(b[0]).x < uv(b[1]).x);
        let pairs = sim
            .seam_on_pattern(
                [Vec2::new(0.75, 0.75), Vec2::new(0.75, 1.0)],
                [Vec2::new(0.75, 0.75), Vec2::new(1.0, 0.75)],
                0.03,
            )
            .unwrap();
        assert_eq!(pairs, 2);
        // Interior lines are no border: refused.
        let depth = sim.history.undo_len();
        assert!(
            sim.seam_on_pattern(
                [Vec2::new(0.25, 0.25), Vec2::new(0.25, 0.5)],
                [Vec2::new(0.5, 0.25), Vec2::new(0.5, 0.5)],
                0.03,
            )
            .is_err()
        );
        assert!(
            sim.seam_on_pattern([Vec2::ZERO; 2], [Vec2::ONE; 2], -1.0)
                .is_err()
        );
        assert_eq!(sim.history.undo_len(), depth);
    }
}
