//! The orbit camera and picking: rays from the mouse into the scene, the cloth triangle
//! and vertex under the mouse.

use glam::{Mat4, Vec2, Vec3};

/// An orbit camera around `target`, Y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub target: Vec3,
    pub distance: f32,
    /// Around Y, radians.
    pub yaw: f32,
    /// Above the horizon, radians.
    pub pitch: f32,
    pub fov_y: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            target: Vec3::new(0.0, 0.35, 0.0),
            distance: 2.0,
            yaw: 0.6,
            pitch: 0.55,
            fov_y: 45f32.to_radians(),
        }
    }
}

impl Camera {
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }

    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    pub fn proj(&self, aspect: f32) -> Mat4 {
        // wgpu's clip space: depth 0..1 (as Direct3D and Vulkan).
        glam::camera::rh::proj::directx::perspective(self.fov_y, aspect.max(0.01), 0.01, 50.0)
    }

    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.proj(aspect) * self.view()
    }

    pub fn orbit(&mut self, d: Vec2) {
        self.yaw -= d.x * 0.01;
        self.pitch = (self.pitch + d.y * 0.01).clamp(-1.5, 1.5);
    }

    /// Moves the target in the view plane by a drag of `d` pixels in a view `h` high.
    pub fn pan(&mut self, d: Vec2, h: f32) {
        let fwd = (self.target - self.eye()).normalize_or_zero();
        let right = fwd.cross(Vec3::Y).normalize_or(Vec3::X);
        let up = right.cross(fwd);
        let scale = 2.0 * self.distance * (0.5 * self.fov_y).tan() / h.max(1.0);
        self.target += (-d.x * right + d.y * up) * scale;
    }

    /// Looks at the box `[min, max]` from the current direction, near enough that it
    /// fills most of a view of `aspect` (width / height) and all of it stays inside.
    pub fn fit(&mut self, min: Vec3, max: Vec3, aspect: f32) {
        if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
            return;
        }
        let radius = ((max - min).length() * 0.5).max(0.05);
        let half_v = 0.5 * self.fov_y;
        let half_h = (half_v.tan() * aspect.clamp(0.2, 5.0)).atan();
        // The bounding sphere inside the narrower of the two angles, with a margin.
        self.distance = (1.1 * radius / half_v.min(half_h).sin()).clamp(0.1, 20.0);
        self.target = (min + max) * 0.5;
    }

    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * (-steps * 0.1).exp()).clamp(0.1, 20.0);
    }

    /// The ray through pixel `p` of a view of `size` pixels: origin and unit direction.
    pub fn ray(&self, p: Vec2, size: Vec2) -> (Vec3, Vec3) {
        let ndc = Vec2::new(
            2.0 * p.x / size.x.max(1.0) - 1.0,
            1.0 - 2.0 * p.y / size.y.max(1.0),
        );
        let inv = self.view_proj(size.x / size.y.max(1.0)).inverse();
        let a = inv.project_point3(ndc.extend(0.0));
        let b = inv.project_point3(ndc.extend(1.0));
        (a, (b - a).normalize_or(Vec3::NEG_Z))
    }

    /// Where `world` lands in a view of `size` pixels (None behind the camera).
    pub fn to_screen(&self, world: Vec3, size: Vec2) -> Option<Vec2> {
        let c = self.view_proj(size.x / size.y.max(1.0)) * world.extend(1.0);
        (c.w > 1e-6).then(|| {
            let n = c.truncate() / c.w;
            Vec2::new((n.x + 1.0) * 0.5 * size.x, (1.0 - n.y) * 0.5 * size.y)
        })
    }
}

/// Möller–Trumbore: the distance along the ray to triangle `abc`, if it is hit.
pub fn ray_triangle(o: Vec3, d: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}

/// What the mouse points at on the cloth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub point: Vec3,
    /// The hit triangle's vertex nearest to the point.
    pub vertex: u32,
    pub distance: f32,
    /// Where the point lies in the design's pattern plane (m), and the key of a corner
    /// of its triangle (`Mesh::piece_of` gives its piece); none for a pin's head.
    pub place: Option<([f32; 2], crate::store::Key)>,
}

/// The nearest cloth triangle along the ray (corners index `x`).
pub fn pick(
    o: Vec3,
    d: Vec3,
    corners: &[shared::sim_to_ui::MeshCorner],
    x: &[[f32; 3]],
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for t in corners.chunks_exact(3) {
        let v = [t[0].vertex, t[1].vertex, t[2].vertex];
        let Some(p) = v
            .iter()
            .map(|&i| x.get(i as usize).map(|p| Vec3::from(*p)))
            .collect::<Option<Vec<_>>>()
        else {
            continue;
        };
        if let Some(dist) = ray_triangle(o, d, p[0], p[1], p[2])
            && best.is_none_or(|b| dist < b.distance)
        {
            let point = o + d * dist;
            let k = (0..3)
                .min_by(|&i, &j| {
                    (p[i] - point)
                        .length_squared()
                        .total_cmp(&(p[j] - point).length_squared())
                })
                .unwrap_or(0);
            // The point's share of each corner, to carry it into the pattern.
            let area = |a: Vec3, b: Vec3, c: Vec3| (b - a).cross(c - a).length();
            let whole = area(p[0], p[1], p[2]).max(1e-12);
            let w = [
                area(point, p[1], p[2]) / whole,
                area(p[0], point, p[2]) / whole,
                area(p[0], p[1], point) / whole,
            ];
            let pattern = [0, 1].map(|c| (0..3).map(|i| w[i] * t[i].pattern[c]).sum::<f32>());
            best = Some(Hit {
                point,
                vertex: v[k],
                distance: dist,
                place: Some((pattern, crate::store::key(t[0].vertex, [t[0].u, t[0].v]))),
            });
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_through_the_screen_centre_hits_the_target() {
        let c = Camera::default();
        let size = Vec2::new(800.0, 600.0);
        let (o, d) = c.ray(size * 0.5, size);
        let to_target = (c.target - o).normalize();
        assert!(d.dot(to_target) > 0.9999, "{d} {to_target}");
        let s = c.to_screen(c.target, size).unwrap();
        assert!((s - size * 0.5).length() < 0.5, "{s}");
    }

    #[test]
    fn picking_finds_the_nearest_vertex_of_the_hit_triangle() {
        let (m, x) = crate::store::Store::demo_cloth(2, 0.0);
        let hit = pick(Vec3::new(-0.45, 1.0, -0.45), Vec3::NEG_Y, &m.corners, &x).unwrap();
        assert_eq!(hit.vertex, 0);
        assert!((hit.distance - 1.0).abs() < 1e-5);
        assert!(pick(Vec3::new(2.0, 1.0, 0.0), Vec3::NEG_Y, &m.corners, &x).is_none());
    }
}
