//! Operations given on the pattern, as a designer selects in a 2D pattern view: delete a
//! rectangle of cloth, or seam two boundary paths drawn as segments (in UV space, or in
//! the design's pattern plane, where pieces added later never overlap).

use glam::Vec2;

use super::document::Design;
use super::error::EditError;
use super::parts::STITCH_PULL;

impl Design {
    /// Where live vertex `v` sits on the pattern (the UV of its first triangle's corner).
    pub fn vertex_uv(&self, v: u32) -> Option<Vec2> {
        let live = &self.sim.cloth.live;
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
            .sim
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
        self.path_near(a, b, tol, |v| vertex_places(self, v, |t, k| t.uv[k]))
    }

    /// [`Design::pattern_path`] in the design's pattern plane (its x and -z, m): what the
    /// studio's pattern view draws, where pieces never overlap (their UVs may).
    pub fn plane_path(&self, a: Vec2, b: Vec2, tol: f32) -> Vec<u32> {
        self.path_near(a, b, tol, |v| {
            vertex_places(self, v, |t, k| Vec2::new(t.rest[k].x, -t.rest[k].z))
        })
    }

    /// The border vertices with a place (of those `places` gives) within `tol` of segment
    /// `a -> b`, past its start, in order from `a` to `b`.
    fn path_near(&self, a: Vec2, b: Vec2, tol: f32, places: impl Fn(u32) -> Vec<Vec2>) -> Vec<u32> {
        let d = b - a;
        let len2 = d.length_squared();
        if len2 <= 0.0 || tol.is_nan() || tol <= 0.0 {
            return Vec::new();
        }
        let len = len2.sqrt();
        let live = &self.sim.cloth.live;
        let mut on: Vec<(f32, u32)> = (0..self.sim.cloth.len() as u32)
            .filter(|&v| live.vertex_alive(v) && live.is_boundary(v))
            .filter_map(|v| {
                places(v).into_iter().find_map(|p| {
                    let t = (p - a).dot(d) / len2;
                    let dist = (p - (a + d * t.clamp(0.0, 1.0))).length();
                    (dist < tol && t * len > tol && t <= 1.0 + tol / len).then_some((t, v))
                })
            })
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        on.into_iter().map(|(_, v)| v).collect()
    }

    /// A seam between the border paths along two pattern segments (see
    /// [`Design::pattern_path`]); returns the stitched pairs.
    pub fn seam_on_pattern(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
    ) -> Result<usize, EditError> {
        self.seam_along(a, b, tol, Self::pattern_path)
    }

    /// [`Design::seam_on_pattern`] with segments in the design's pattern plane (m), as
    /// the studio's pattern view draws it; returns the stitched pairs.
    pub fn seam_on_plane(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
    ) -> Result<usize, EditError> {
        self.seam_along(a, b, tol, Self::plane_path)
    }

    /// A seam between the border paths `path` finds along segments `a` and `b`.
    fn seam_along(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
        path: fn(&Self, Vec2, Vec2, f32) -> Vec<u32>,
    ) -> Result<usize, EditError> {
        seam_tolerance(tol)?;
        let (pa, pb) = (path(self, a[0], a[1], tol), path(self, b[0], b[1], tol));
        if pa.len() < 2 || pb.len() < 2 {
            return Err(EditError::NothingOnPattern {
                what: "border path of two or more vertices",
            });
        }
        let pull = self.pair_pull(&pa, &pb, STITCH_PULL);
        self.add_seam(&pa, &pb, pull)
    }
}

/// Vertex `v`'s places in the pattern, one per triangle corner it has (`at` reads one).
fn vertex_places(d: &Design, v: u32, at: impl Fn(&crate::mesh::Tri, usize) -> Vec2) -> Vec<Vec2> {
    let live = &d.sim.cloth.live;
    live.tris_of(v)
        .iter()
        .filter_map(|&t| live.tri(t))
        .filter_map(|t| t.corner(v).map(|k| at(t, k)))
        .collect()
}

/// A seam's tolerance must be a positive distance.
fn seam_tolerance(tol: f32) -> Result<(), EditError> {
    if tol.is_finite() && tol > 0.0 {
        Ok(())
    } else {
        Err(EditError::BadValue {
            name: "seam tolerance",
            rule: "a positive distance on the pattern",
            value: tol.to_string(),
        })
    }
}
