//! The local spring proxy: the force at each 1 kHz tick from the latest local model
//! cloth-sim sent, without waiting for it.
//!
//! - Pinching: a spring from the pen tip to the pinched vertex, the vertex's position
//!   extrapolated with the velocity the simulation sent (at most `max_extrapolation_s`
//!   ahead), with virtual-coupling damping on the relative velocity.
//! - Otherwise: a god-object proxy against the planes near the tip (cloth and body
//!   triangles): the proxy is the tip projected out of every plane it is behind, and the
//!   force is a spring-damper from the tip to the proxy.

use shared::sim_to_haptic::LocalModel;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProxyParams {
    /// Contact stiffness against planes, N/m (the Touch stays passive up to ~400 N/m).
    pub contact_stiffness: f32,
    /// Virtual-coupling damping time: damping = stiffness x this, s.
    pub coupling_time_s: f32,
    pub max_extrapolation_s: f32,
}

impl Default for ProxyParams {
    fn default() -> Self {
        Self {
            contact_stiffness: 300.0,
            coupling_time_s: 0.002,
            max_extrapolation_s: 0.05,
        }
    }
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add_scaled(a: [f32; 3], b: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The force on the pen (N, scene frame) for tip position `x` and velocity `v`, from
/// `model` received `age_s` seconds after it was sent.
pub fn proxy_force(
    p: &ProxyParams,
    model: &LocalModel,
    age_s: f32,
    x: [f32; 3],
    v: [f32; 3],
) -> [f32; 3] {
    let age = age_s.clamp(0.0, p.max_extrapolation_s);
    if model.pinching == 1 {
        let k = model.stiffness;
        let b = k * p.coupling_time_s;
        let target = add_scaled(model.vertex_position, model.vertex_velocity, age);
        let d = sub(target, x);
        let dv = sub(model.vertex_velocity, v);
        return [
            k * d[0] + b * dv[0],
            k * d[1] + b * dv[1],
            k * d[2] + b * dv[2],
        ];
    }
    // God object: project the tip out of the planes it is behind (a few passes settle
    // corners where planes meet).
    let n = (model.plane_count as usize).min(model.planes.len());
    let mut proxy = x;
    for _ in 0..3 {
        for pl in &model.planes[..n] {
            let nrm = [pl[0], pl[1], pl[2]];
            let s = dot(nrm, proxy) - pl[3];
            if s < 0.0 {
                proxy = add_scaled(proxy, nrm, -s);
            }
        }
    }
    let d = sub(proxy, x);
    if dot(d, d) == 0.0 {
        return [0.0; 3];
    }
    let k = p.contact_stiffness;
    let b = k * p.coupling_time_s;
    // Damp only the velocity into the surface (along the push).
    let len = dot(d, d).sqrt();
    let dir = [d[0] / len, d[1] / len, d[2] / len];
    let vn = dot(v, dir).min(0.0);
    [
        k * d[0] - b * vn * dir[0],
        k * d[1] - b * vn * dir[1],
        k * d[2] - b * vn * dir[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pinch_spring_pulls_toward_the_extrapolated_vertex() {
        let m = LocalModel {
            pinching: 1,
            stiffness: 200.0,
            vertex_position: [0.0, 1.0, 0.0],
            vertex_velocity: [0.1, 0.0, 0.0],
            ..Default::default()
        };
        let f = proxy_force(
            &ProxyParams::default(),
            &m,
            0.01,
            [0.0, 0.99, 0.0],
            [0.1, 0.0, 0.0],
        );
        // 1 cm below the vertex: 2 N up; the vertex moved 1 mm in x meanwhile: 0.2 N in x.
        assert!(
            (f[1] - 2.0).abs() < 1e-4 && (f[0] - 0.2).abs() < 1e-4,
            "{f:?}"
        );
        // Extrapolation is bounded: a stale model does not fling the pen.
        let f = proxy_force(&ProxyParams::default(), &m, 10.0, [0.0, 1.0, 0.0], [0.0; 3]);
        // Target 0.1 m/s x 50 ms = 5 mm ahead: 1 N, plus coupling 0.4 N s/m x 0.1 m/s.
        assert!((f[0] - 1.04).abs() < 1e-4, "{f:?}");
    }

    #[test]
    fn god_object_pushes_out_of_planes_only_when_behind() {
        let mut m = LocalModel {
            plane_count: 2,
            ..Default::default()
        };
        m.planes[0] = [0.0, 1.0, 0.0, 0.5]; // floor at y = 0.5
        m.planes[1] = [1.0, 0.0, 0.0, 0.0]; // wall at x = 0
        let p = ProxyParams::default();
        assert_eq!(
            proxy_force(&p, &m, 0.0, [0.1, 0.6, 0.0], [0.0; 3]),
            [0.0; 3]
        );
        let f = proxy_force(&p, &m, 0.0, [0.1, 0.49, 0.0], [0.0; 3]);
        assert!((f[1] - 3.0).abs() < 1e-3 && f[0] == 0.0, "{f:?}");
        // In the corner, both push.
        let f = proxy_force(&p, &m, 0.0, [-0.01, 0.49, 0.0], [0.0; 3]);
        assert!(f[0] > 2.9 && f[1] > 2.9, "{f:?}");
    }
}
