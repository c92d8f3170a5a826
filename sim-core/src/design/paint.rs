//! The paper's paint: a soft brush dab on the texture where the pen touches the cloth.

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;

impl Design {
    /// The texture coordinate of the cloth surface nearest to `p` (within `radius`), and
    /// texels per metre of cloth there.
    pub fn surface_uv(&self, p: Vec3, radius: f32) -> Option<(Vec2, f32)> {
        let v = self.sim.cloth.nearest_vertex(p, radius)?;
        let x = &self.sim.cloth.x;
        let live = &self.sim.cloth.live;
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
