//! The operations: cut (a vertex, or a stroke), sew, tear (by hand or by overstretch),
//! pin, paint, and the pinch spring.

use glam::{Vec2, Vec3};

use super::{EditError, Prim};
use crate::cloth::Simulation;
use crate::cloth::sim::Solver;
use crate::mesh::Tri;

/// What an overstretched edge does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TearMode {
    /// The paper's: the two triangles beside the edge are removed.
    Delete,
    /// The material separates at the edge: one end is split in two across the edge, the
    /// triangles stay (as NVIDIA Flex tears).
    Split,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TearSettings {
    /// Tearing happens at all.
    pub enabled: bool,
    /// An edge tears when longer than this times its rest length.
    pub threshold: f32,
    pub mode: TearMode,
    /// Most tears per frame (the most stretched first).
    pub max_per_frame: usize,
}

impl Default for TearSettings {
    fn default() -> Self {
        Self {
            enabled: false,
            threshold: 1.6,
            mode: TearMode::Delete,
            max_per_frame: 16,
        }
    }
}

/// The pinch: the pointer holds the vertex nearest to it (the paper's pinch) and, with a
/// grip radius, the vertices around it too, each by a spring to the pointer plus its
/// offset at the moment of grabbing. The springs share the stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct Pinch {
    /// The vertex nearest to the pointer when grabbed.
    pub vertex: u32,
    /// Held vertices and their offsets from the pointer.
    pub held: Vec<(u32, Vec3)>,
    pub target: Vec3,
    /// Total stiffness of the springs, N/m.
    pub stiffness: f32,
    /// Most force the springs together may put on the cloth in a substep, N (None: no
    /// limit). cloth-sim sets it from the force the haptic loop rendered, so the cloth
    /// is pulled no harder than the user's hand is pulled back.
    pub force_limit: Option<f32>,
}

/// The pen during one substep: where the pinch's pointer end is, and the most force the
/// pinch may exert (see [`Pinch::force_limit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenInput {
    pub target: Vec3,
    pub force_limit: Option<f32>,
}

impl Simulation {
    /// The live vertex nearest to `p` within `radius`.
    pub fn nearest_vertex(&self, p: Vec3, radius: f32) -> Option<u32> {
        let r2 = radius * radius;
        let mut best = None;
        let mut best_d = f32::INFINITY;
        for (i, x) in self.cloth.x.iter().enumerate() {
            let d = (*x - p).length_squared();
            if d <= r2 && d < best_d && self.cloth.live.vertex_alive(i as u32) {
                best_d = d;
                best = Some(i as u32);
            }
        }
        best
    }

    /// Area-weighted normal of the triangles around `v` in the current shape.
    pub fn vertex_normal(&self, v: u32) -> Vec3 {
        let x = &self.cloth.x;
        self.cloth
            .live
            .tris_of(v)
            .iter()
            .filter_map(|&t| self.cloth.live.tri(t))
            .map(|t| {
                let [a, b, c] = t.v.map(|i| x[i as usize]);
                (b - a).cross(c - a)
            })
            .sum::<Vec3>()
            .normalize_or_zero()
    }

    fn centroid(&self, t: &Tri) -> Vec3 {
        t.v.iter().map(|&i| self.cloth.x[i as usize]).sum::<Vec3>() / 3.0
    }

    /// Primitives that split `v` in two: the triangles whose centre lies on the positive
    /// side of the plane through `v` with normal `plane` move to a new vertex.
    fn split_prims(&self, v: u32, plane: Vec3) -> Result<Vec<Prim>, EditError> {
        if !plane.is_finite() || plane.length_squared() < 1e-20 {
            return Err(EditError::BadDirection);
        }
        let xv = self.cloth.x[v as usize];
        let tris: Vec<(u32, Tri)> = self
            .cloth
            .live
            .tris_of(v)
            .iter()
            .filter_map(|&t| self.cloth.live.tri(t).map(|tri| (t, *tri)))
            .collect();
        let moving: Vec<&(u32, Tri)> = tris
            .iter()
            .filter(|(_, t)| (self.centroid(t) - xv).dot(plane) > 0.0)
            .collect();
        if moving.is_empty() || moving.len() == tris.len() {
            return Err(EditError::NothingToCut(v));
        }
        let new = self.cloth.len() as u32;
        let mut prims = vec![Prim::AddVertex {
            index: new,
            x: xv,
            v: self.cloth.v[v as usize],
        }];
        for (slot, t) in moving {
            let mut n = *t;
            n.v = n.v.map(|i| if i == v { new } else { i });
            prims.push(Prim::Tri {
                slot: *slot,
                old: Some(*t),
                new: Some(n),
            });
        }
        if self.cloth.is_pinned(v as usize) {
            prims.push(Prim::Pin {
                vertex: new,
                old: false,
                new: true,
            });
        }
        Ok(prims)
    }

    /// The paper's cut: splits vertex `v` in two, its triangles divided by the plane that
    /// contains the cut direction `dir` and the surface normal. Returns the new vertex.
    pub fn cut_vertex(&mut self, v: u32, dir: Vec3) -> Result<u32, EditError> {
        self.check_vertex(v)?;
        let plane = dir.cross(self.vertex_normal(v));
        let new = self.cloth.len() as u32;
        let prims = self.split_prims(v, plane)?;
        self.commit("cut", prims)?;
        Ok(new)
    }

    /// Scissors: splits the vertices along the polyline `points` (the pointer's path),
    /// each across the local stroke direction, as one undoable operation. Returns how
    /// many vertices were split.
    pub fn cut_stroke(&mut self, points: &[Vec3], radius: f32) -> Result<usize, EditError> {
        if points.iter().any(|p| !p.is_finite()) {
            return Err(EditError::BadDirection);
        }
        let chain = self.stroke_chain(points, radius);
        if chain.len() < 2 {
            return Err(EditError::EmptyStroke);
        }
        let mut all = Vec::new();
        let mut splits = 0;
        for k in 0..chain.len() {
            let (a, b) = (
                chain[k.saturating_sub(1)],
                chain[(k + 1).min(chain.len() - 1)],
            );
            let dir = self.cloth.x[b as usize] - self.cloth.x[a as usize];
            let v = chain[k];
            let plane = dir.cross(self.vertex_normal(v));
            let Ok(prims) = self.split_prims(v, plane) else {
                continue;
            };
            if let Err(e) = self.apply_prims(&prims) {
                self.rollback(&all);
                return Err(e);
            }
            splits += 1;
            all.extend(prims);
        }
        if splits == 0 {
            return Err(EditError::EmptyStroke);
        }
        self.history.push(super::Edit {
            label: "cut stroke",
            prims: all,
        });
        Ok(splits)
    }

    fn rollback(&mut self, applied: &[Prim]) {
        let inverse: Vec<Prim> = applied.iter().rev().map(Prim::inverse).collect();
        // Inverses of applied primitives always apply.
        let _ = self.apply_prims(&inverse);
    }

    /// The chain of vertices a stroke passes: the nearest vertex to points sampled along
    /// it, consecutive ones joined through the mesh when they are not neighbours.
    fn stroke_chain(&self, points: &[Vec3], radius: f32) -> Vec<u32> {
        let mut picks: Vec<u32> = Vec::new();
        let segments: Vec<(Vec3, Vec3)> = if points.len() == 1 {
            vec![(points[0], points[0])]
        } else {
            points.windows(2).map(|w| (w[0], w[1])).collect()
        };
        for (p, q) in segments {
            let steps = ((q - p).length() / (radius * 0.5).max(1e-4))
                .ceil()
                .clamp(1.0, 4096.0) as usize;
            for s in 0..=steps {
                let at = p.lerp(q, s as f32 / steps as f32);
                if let Some(v) = self.nearest_vertex(at, radius)
                    && picks.last() != Some(&v)
                {
                    picks.push(v);
                }
            }
        }
        let mut chain: Vec<u32> = Vec::new();
        for v in picks {
            match chain.last() {
                Some(&u) if !self.cloth.live.neighbours(u).contains(&v) => {
                    chain.extend(self.mesh_path(u, v, 8).into_iter().skip(1));
                }
                _ => chain.push(v),
            }
        }
        chain.dedup();
        chain
    }

    /// Shortest edge path from `a` to `b` of at most `limit` edges (just `[a, b]` if none).
    fn mesh_path(&self, a: u32, b: u32, limit: usize) -> Vec<u32> {
        let mut prev: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        let mut frontier = vec![a];
        prev.insert(a, a);
        for _ in 0..limit {
            let mut next = Vec::new();
            for &u in &frontier {
                for w in self.cloth.live.neighbours(u) {
                    if let std::collections::hash_map::Entry::Vacant(e) = prev.entry(w) {
                        e.insert(u);
                        next.push(w);
                    }
                }
            }
            if prev.contains_key(&b) {
                let mut path = vec![b];
                let mut c = b;
                while c != a {
                    c = prev[&c];
                    path.push(c);
                }
                path.reverse();
                return path;
            }
            frontier = next;
        }
        vec![a, b]
    }

    /// The paper's sew: merges border vertices `a` and `b` into `a`, placed halfway.
    pub fn sew(&mut self, a: u32, b: u32) -> Result<(), EditError> {
        let prims = self.sew_prims(a, b)?;
        self.commit("sew", prims)
    }

    pub(crate) fn sew_prims(&self, a: u32, b: u32) -> Result<Vec<Prim>, EditError> {
        self.check_vertex(a)?;
        self.check_vertex(b)?;
        if a == b {
            return Err(EditError::SewSelf(a));
        }
        for v in [a, b] {
            if !self.cloth.live.is_boundary(v) {
                return Err(EditError::SewInterior(v));
            }
        }
        let live = &self.cloth.live;
        if live
            .tris_of(b)
            .iter()
            .any(|&t| live.tri(t).is_some_and(|t| t.corner(a).is_some()))
        {
            return Err(EditError::SewNeighbours(a, b));
        }
        let c = &self.cloth;
        let (ia, ib) = (a as usize, b as usize);
        let mut prims = vec![Prim::Move {
            vertex: a,
            old: (c.x[ia], c.v[ia]),
            new: ((c.x[ia] + c.x[ib]) * 0.5, (c.v[ia] + c.v[ib]) * 0.5),
        }];
        for &slot in live.tris_of(b) {
            if let Some(t) = live.tri(slot) {
                let mut n = *t;
                n.v = n.v.map(|i| if i == b { a } else { i });
                prims.push(Prim::Tri {
                    slot,
                    old: Some(*t),
                    new: Some(n),
                });
            }
        }
        if c.is_pinned(ib) && !c.is_pinned(ia) {
            prims.push(Prim::Pin {
                vertex: a,
                old: false,
                new: true,
            });
        }
        Ok(prims)
    }

    /// Cuts a piece away: removes the triangles in `slots` (alive ones; at least one) as
    /// one undoable operation. Returns how many went.
    pub fn remove_triangles(&mut self, slots: &[u32]) -> Result<usize, EditError> {
        self.check_editable()?;
        let mut seen = std::collections::HashSet::new();
        let prims: Vec<Prim> = slots
            .iter()
            .filter(|s| seen.insert(**s))
            .filter_map(|&s| {
                self.cloth.live.tri(s).map(|t| Prim::Tri {
                    slot: s,
                    old: Some(*t),
                    new: None,
                })
            })
            .collect();
        if prims.is_empty() {
            return Err(EditError::NothingNear { radius: 0.0 });
        }
        let n = prims.len();
        self.commit("cut away", prims)?;
        Ok(n)
    }

    /// Tears edge `(a, b)` by hand, in `mode`.
    pub fn tear_edge(&mut self, a: u32, b: u32, mode: TearMode) -> Result<(), EditError> {
        let prims = self.tear_prims(a, b, mode)?;
        self.commit("tear", prims)
    }

    fn tear_prims(&self, a: u32, b: u32, mode: TearMode) -> Result<Vec<Prim>, EditError> {
        self.check_vertex(a)?;
        self.check_vertex(b)?;
        let sides = self.cloth.live.edge(a, b);
        if sides[0] == crate::mesh::live::NONE {
            return Err(EditError::NoEdge(a, b));
        }
        match mode {
            TearMode::Delete => Ok(sides
                .iter()
                .filter_map(|&s| {
                    self.cloth.live.tri(s).map(|t| Prim::Tri {
                        slot: s,
                        old: Some(*t),
                        new: None,
                    })
                })
                .collect()),
            TearMode::Split => {
                let d = self.cloth.x[b as usize] - self.cloth.x[a as usize];
                self.split_prims(a, d).or_else(|_| self.split_prims(b, -d))
            }
        }
    }

    /// Tears the most overstretched edges (called after each frame when tearing is on).
    /// Returns how many tore.
    pub(crate) fn tear_overstretched(&mut self) -> usize {
        let s = self.tear;
        if !s.enabled || !matches!(self.solver, Solver::Xpbd(_)) {
            return 0;
        }
        let x = &self.cloth.x;
        let mut over: Vec<(f32, u32, u32)> = Vec::new();
        for (_, t) in self.cloth.live.iter() {
            for k in 0..3 {
                let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
                let rest = (t.rest[k] - t.rest[(k + 1) % 3]).length();
                let r = (x[a as usize] - x[b as usize]).length() / rest.max(1e-12);
                if r > s.threshold {
                    over.push((r, a.min(b), a.max(b)));
                }
            }
        }
        over.sort_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));
        over.dedup_by_key(|e| (e.1, e.2));
        let mut torn = 0;
        for (_, a, b) in over {
            if torn >= s.max_per_frame {
                break;
            }
            if self.tear_edge(a, b, s.mode).is_ok() {
                torn += 1;
            }
        }
        torn
    }

    /// Pins or frees vertex `v` (undoable).
    pub fn set_pin(&mut self, v: u32, pinned: bool) -> Result<(), EditError> {
        self.check_vertex(v)?;
        let old = self.cloth.is_pinned(v as usize);
        self.commit(
            "pin",
            vec![Prim::Pin {
                vertex: v,
                old,
                new: pinned,
            }],
        )
    }

    /// The texture coordinate of the cloth surface nearest to `p` (within `radius`), and
    /// texels per metre of cloth there.
    pub fn surface_uv(&self, p: Vec3, radius: f32) -> Option<(Vec2, f32)> {
        let v = self.nearest_vertex(p, radius)?;
        let x = &self.cloth.x;
        let live = &self.cloth.live;
        let mut best: Option<(f32, Vec2, f32)> = None;
        for &slot in live.tris_of(v) {
            let Some(t) = live.tri(slot) else { continue };
            let [a, b, c] = t.v.map(|i| x[i as usize]);
            let bary = closest_barycentric(p, a, b, c);
            let q = a * bary.x + b * bary.y + c * bary.z;
            let d = (q - p).length_squared();
            if best.is_none_or(|(bd, _, _)| d < bd) {
                let uv = t.uv[0] * bary.x + t.uv[1] * bary.y + t.uv[2] * bary.z;
                let (w, h) = (self.texture.width as f32, self.texture.height as f32);
                let e1 = (t.uv[1] - t.uv[0]) * Vec2::new(w, h);
                let e2 = (t.uv[2] - t.uv[0]) * Vec2::new(w, h);
                let tex_area = 0.5 * (e1.x * e2.y - e1.y * e2.x).abs();
                let scale = (tex_area / t.rest_area().max(1e-12)).sqrt();
                best = Some((d, uv, scale));
            }
        }
        best.map(|(_, uv, s)| (uv, s))
    }

    /// The paper's paint: texels within `radius` metres of the cloth point nearest to `p`
    /// take `color` (soft edge). Undoable.
    pub fn paint(&mut self, p: Vec3, radius: f32, color: [u8; 4]) -> Result<(), EditError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(EditError::BadValue {
                name: "brush radius",
                rule: "a positive number of metres",
                value: radius.to_string(),
            });
        }
        if !p.is_finite() {
            return Err(EditError::BadDirection);
        }
        let reach = radius.max(0.05);
        let (uv, scale) = self
            .surface_uv(p, reach)
            .ok_or(EditError::NothingNear { radius: reach })?;
        let center = Vec2::new(
            uv.x * self.texture.width as f32,
            (1.0 - uv.y) * self.texture.height as f32,
        );
        let patch = self
            .texture
            .brush(center, radius * scale, color, 0.6)
            .ok_or(EditError::NothingNear { radius: reach })?;
        self.commit("paint", vec![Prim::Paint(patch)])
    }

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
            .nearest_vertex(p, radius)
            .ok_or(EditError::NothingNear { radius })?;
        let centre = self.cloth.x[v as usize];
        let mut held = vec![(v, centre - p)];
        if grip > 0.0 {
            for (i, x) in self.cloth.x.iter().enumerate() {
                let i = i as u32;
                if i != v && (*x - centre).length() <= grip && self.cloth.live.vertex_alive(i) {
                    held.push((i, *x - p));
                }
            }
        }
        let Solver::Xpbd(s) = &mut self.solver else {
            return Err(EditError::Model("seed or implicit"));
        };
        s.pinch = Some(Pinch {
            vertex: v,
            held,
            target: p,
            stiffness,
            force_limit: None,
        });
        Ok(v)
    }

    /// Moves the pinch's pointer end.
    pub fn pinch_move(&mut self, target: Vec3) {
        if let Solver::Xpbd(s) = &mut self.solver
            && let Some(p) = &mut s.pinch
            && target.is_finite()
        {
            p.target = target;
        }
    }

    /// Releases the pinch (button up).
    pub fn pinch_end(&mut self) {
        if let Solver::Xpbd(s) = &mut self.solver {
            s.pinch = None;
        }
    }

    pub fn pinch(&self) -> Option<&Pinch> {
        match &self.solver {
            Solver::Xpbd(s) => s.pinch.as_ref(),
            _ => None,
        }
    }

    /// Substeps of the last frame in which the pinch pulled at its force limit.
    pub fn pinch_limited_substeps(&self) -> usize {
        match &self.solver {
            Solver::Xpbd(s) => s.pinch_limited,
            _ => 0,
        }
    }

    /// The force the pinch springs put on the cloth (their sum) in each substep of the
    /// last frame, N (the pen feels the opposite).
    pub fn pinch_forces(&self) -> &[Vec3] {
        match &self.solver {
            Solver::Xpbd(s) => &s.pinch_forces,
            _ => &[],
        }
    }
}

/// Barycentric coordinates of the point of triangle `abc` nearest to `p`.
fn closest_barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Vec3::X;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Vec3::Y;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return Vec3::new(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Vec3::Z;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return Vec3::new(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Vec3::new(0.0, 1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    if !denom.is_finite() {
        return Vec3::X;
    }
    let (v, w) = (vb * denom, vc * denom);
    Vec3::new(1.0 - v - w, v, w)
}
