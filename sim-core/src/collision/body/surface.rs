//! A static body: its surface, OBB tree and pseudo-normals (Bærentzen & Aanæs 2005) for a
//! robust inside/outside sign at faces, edges and corners.

use std::collections::HashMap;

use glam::Vec3;

use super::analytic::Analytic;
use super::clearance::ClearanceGrid;
use crate::collision::obb::{BuildOptions, Feature, ObbTree, SurfaceWalk};
use crate::collision::proximity::BodyGrids;
use crate::error::GeometryError;

#[derive(Clone, Debug)]
pub struct Body {
    pub name: String,
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    tree: ObbTree,
    /// Answers most queries near last frame's triangle without the tree.
    walk: SurfaceWalk,
    /// Proves most points far from the surface clear of it without a search.
    clearance: ClearanceGrid,
    face_normals: Vec<Vec3>,
    vertex_normals: Vec<Vec3>,
    /// Per triangle, per local edge k (corner k to k+1): the sum of the two face normals.
    edge_normals: Vec<[Vec3; 3]>,
    /// Exact shape when the body is made of primitives; used for reporting penetration.
    pub analytic: Option<Analytic>,
    /// What was repaired when the body was read from a file (an inside-out surface
    /// turned outward), for the user to be told.
    pub repairs: Vec<String>,
    /// Its triangles, edges and vertices in spatial hashes, for the cloth's proximity
    /// search (shared: a body never changes).
    pub grids: std::sync::Arc<BodyGrids>,
}

/// The body surface near a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyContact {
    pub tri: u32,
    pub point: Vec3,
    /// Outward unit direction from the surface toward where the point should be.
    pub normal: Vec3,
    /// Distance to the surface, negative inside.
    pub signed_distance: f32,
    /// The closest point is inside the triangle's face (not on an edge or corner), so the
    /// contact plane is the triangle's own plane.
    pub on_face: bool,
}

impl Body {
    /// Builds a body from an outward-wound surface.
    pub fn new(
        name: impl Into<String>,
        vertices: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
        analytic: Option<Analytic>,
    ) -> Result<Self, GeometryError> {
        let tree = ObbTree::build(&vertices, &triangles, BuildOptions::default())?;
        let mut face_normals = Vec::with_capacity(triangles.len());
        let mut vertex_normals = vec![Vec3::ZERO; vertices.len()];
        let mut edge_sum: HashMap<(u32, u32), Vec3> = HashMap::with_capacity(triangles.len() * 2);
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            let n = (b - a).cross(c - a);
            if n.length_squared() <= 1e-30 {
                return Err(GeometryError::Degenerate { triangle: t });
            }
            let n = n.normalize();
            face_normals.push(n);
            let p = [a, b, c];
            for k in 0..3 {
                let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                let angle = e1.dot(e2).clamp(-1.0, 1.0).acos();
                vertex_normals[tri[k] as usize] += n * angle;
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                *edge_sum.entry((i.min(j), i.max(j))).or_insert(Vec3::ZERO) += n;
            }
        }
        let edge_normals = triangles
            .iter()
            .map(|tri| {
                std::array::from_fn(|k| {
                    let (i, j) = (tri[k], tri[(k + 1) % 3]);
                    edge_sum
                        .get(&(i.min(j), i.max(j)))
                        .copied()
                        .unwrap_or(Vec3::Y)
                })
            })
            .collect();
        let grids = std::sync::Arc::new(BodyGrids::new(&vertices, &triangles));
        let mut body = Self {
            name: name.into(),
            vertices,
            triangles,
            grids,
            walk: SurfaceWalk::new(&tree),
            tree,
            face_normals,
            vertex_normals,
            edge_normals,
            analytic,
            repairs: Vec::new(),
            clearance: ClearanceGrid::default(),
        };
        body.clearance = ClearanceGrid::new(&body.vertices, |p, max_dist| {
            body.contact(p, max_dist, u32::MAX)
                .map(|c| (c.signed_distance, c.tri))
        });
        Ok(body)
    }

    /// A lower bound on how far outside the body `p` is, from distances sampled when the
    /// body was made (0 or less when it may be inside or on it), and a triangle near `p`
    /// (`u32::MAX` if none is known); no search.
    pub fn outside_by(&self, p: Vec3) -> (f32, u32) {
        self.clearance.outside_by(p)
    }

    /// The body's OBB tree. A body never moves or deforms: the walk's bounds are
    /// computed once, for this tree.
    pub fn tree(&self) -> &ObbTree {
        &self.tree
    }

    pub fn face_normal(&self, tri: u32) -> Vec3 {
        self.face_normals[tri as usize]
    }

    /// The nearest surface point within `max_dist`, with the side the query point is on.
    /// `hint` is a triangle likely to be near (last frame's), or `u32::MAX`.
    pub fn contact(&self, p: Vec3, max_dist: f32, hint: u32) -> Option<BodyContact> {
        let hint = (hint != u32::MAX).then_some(hint);
        let hit = self.tree.nearest_with_hint(p, max_dist, hint)?;
        Some(self.contact_from(p, hit.tri, hit.point, hit.feature))
    }

    /// As [`contact`](Self::contact), first trying a walk from `hint` across the
    /// surface ([`SurfaceWalk`]), which answers most queries near last frame's triangle
    /// without the tree. When the walk proves the nearest point it is returned even
    /// beyond `max_dist`. Also returns a triangle near `p` to start from next time
    /// (`u32::MAX` when none is known).
    pub fn contact_near(&self, p: Vec3, max_dist: f32, hint: u32) -> (Option<BodyContact>, u32) {
        if hint == u32::MAX {
            let found = self.contact(p, max_dist, hint);
            return (found, found.map_or(hint, |c| c.tri));
        }
        let start = match self.walk.nearest(&self.tree, p, hint) {
            Ok(hit) => {
                return (
                    Some(self.contact_from(p, hit.tri, hit.point, hit.feature)),
                    hit.tri,
                );
            }
            // Proved clear of the surface within `max_dist`: nothing to ask the tree.
            Err(miss) if miss.clear > max_dist => {
                return (
                    None,
                    if miss.near == u32::MAX {
                        hint
                    } else {
                        miss.near
                    },
                );
            }
            Err(miss) if miss.near == u32::MAX => hint,
            Err(miss) => miss.near,
        };
        let found = self.contact(p, max_dist, start);
        (found, found.map_or(start, |c| c.tri))
    }

    /// The contact with one given triangle (its closest point and side).
    pub fn contact_on(&self, p: Vec3, tri: u32) -> Option<BodyContact> {
        let [a, b, c] = self.tree.triangle(tri)?;
        let (q, f) = crate::collision::obb::geometry::closest_point_on_triangle(p, a, b, c);
        Some(self.contact_from(p, tri, q, f))
    }

    pub(crate) fn contact_from(
        &self,
        p: Vec3,
        tri: u32,
        point: Vec3,
        feature: Feature,
    ) -> BodyContact {
        let t = tri as usize;
        let pseudo = match feature {
            Feature::Face => self.face_normals[t],
            Feature::Edge(k) => self.edge_normals[t][k as usize],
            Feature::Vertex(k) => self.vertex_normals[self.triangles[t][k as usize] as usize],
        };
        let d = p - point;
        let dist = d.length();
        let outside = d.dot(pseudo) >= 0.0;
        let normal = if matches!(feature, Feature::Face) || dist < 1e-7 {
            self.face_normals[t]
        } else if outside {
            d / dist
        } else {
            -d / dist
        };
        let normal = if normal.is_finite() {
            normal
        } else {
            self.face_normals[t]
        };
        BodyContact {
            tri,
            point,
            normal,
            signed_distance: if outside { dist } else { -dist },
            on_face: matches!(feature, Feature::Face),
        }
    }

    /// Signed distance from the surface mesh (negative inside), searched up to `max_dist`;
    /// `None` when the surface is farther.
    pub fn signed_distance(&self, p: Vec3, max_dist: f32) -> Option<f32> {
        self.contact(p, max_dist, u32::MAX)
            .map(|c| c.signed_distance)
    }

    /// How deep `p` is inside the body (0 when outside): exact for primitive bodies, from
    /// the mesh otherwise.
    pub fn penetration(&self, p: Vec3) -> f32 {
        match &self.analytic {
            Some(a) => (-a.signed_distance(p)).max(0.0),
            None => self.signed_distance(p, 1e3).map_or(0.0, |d| (-d).max(0.0)),
        }
    }

    /// Axis-aligned bounds.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        crate::mesh::bounds(&self.vertices)
    }
}
