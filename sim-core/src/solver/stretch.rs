//! How far a triangle's threads are stretched: the warp and the weft, each as many times
//! its length as cut, measured in the membranes' own material frame (`membrane_of`: the
//! warp along the texture's u, the weft across it), so exactly the `|F_u|`, `|F_v|` the
//! xpbd model's stretch constraints hold at 1. Shear, which a woven takes easily and a
//! draped garment shows everywhere, stretches no thread; a triangle side along the bias
//! does stretch under it, so the sides' strain (`Cloth::strain`) reads shear as stretch
//! and its mean lets compressed sides cancel stretched ones. The studio's stretch map and
//! the scenario reports' `thread_stretch_*` both read this.

use glam::{Vec2, Vec3};

use super::constraints::membrane_of;

/// How many times its length as cut each thread of a triangle now is, warp then weft:
/// its corners are at `x`, lay at `rest` as cut (any plane) and have texture coordinates
/// `uv`, whose u runs along the warp. None for a triangle with no area as cut or in the
/// texture, or positions that are not finite.
pub fn thread_stretch(x: [Vec3; 3], rest: [Vec3; 3], uv: [Vec2; 3]) -> Option<[f32; 2]> {
    let texture = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
    let cut = (rest[1] - rest[0]).cross(rest[2] - rest[0]).length();
    if !(texture.abs() > 1e-12 && cut > 1e-12) {
        return None;
    }
    let m = membrane_of([0, 1, 2], 0, rest, uv);
    let fu = x[0] * m.c[0] + x[1] * m.c[1] + x[2] * m.c[2];
    let fv = x[0] * m.d[0] + x[1] * m.d[1] + x[2] * m.d[2];
    let s = [fu.length(), fv.length()];
    s.iter().all(|v| v.is_finite()).then_some(s)
}

/// The threads' stretch over a cloth's triangles, each triangle's more stretched thread
/// less one (0.05: 5% longer than cut): the median, the ninetieth percentile and the
/// largest, by triangle count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ThreadStretch {
    pub p50: f64,
    pub p90: f64,
    pub max: f64,
}

impl ThreadStretch {
    /// Of triangles' stretches `s` (any order; none: all zero).
    pub fn of(mut s: Vec<f32>) -> Self {
        if s.is_empty() {
            return Self::default();
        }
        s.sort_by(f32::total_cmp);
        let at = |q: f64| s[((q * (s.len() - 1) as f64).round() as usize).min(s.len() - 1)] as f64;
        Self {
            p50: at(0.5),
            p90: at(0.9),
            max: at(1.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUT: [Vec2; 3] = [
        Vec2::new(0.0, 0.0),
        Vec2::new(0.1, 0.0),
        Vec2::new(0.0, 0.1),
    ];

    fn placed(f: impl Fn(Vec2) -> Vec3) -> [Vec3; 3] {
        CUT.map(f)
    }

    /// The threads' stretch with the warp along the pattern's x turned by `grain` rad,
    /// the pattern in the XZ plane as the cloth's rest is.
    fn threads(x: [Vec3; 3], grain: f32) -> [f32; 2] {
        let uv = CUT.map(|p| Vec2::from_angle(-grain).rotate(p));
        thread_stretch(x, CUT.map(|p| Vec3::new(p.x, 0.0, -p.y)), uv).unwrap()
    }

    fn near(a: [f32; 2], b: [f32; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-5 && (a[1] - b[1]).abs() < 1e-5
    }

    #[test]
    fn a_triangle_as_cut_moved_and_turned_is_not_stretched() {
        let turn = glam::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 1.1);
        let x = placed(|p| turn * Vec3::new(p.x, p.y, 0.0) + Vec3::new(0.3, 1.2, -0.4));
        assert!(near(threads(x, 0.0), [1.0, 1.0]));
        assert!(near(threads(x, 0.7), [1.0, 1.0]));
    }

    #[test]
    fn each_thread_is_measured_along_the_grain() {
        // 10% along the pattern's x, 3% along its y: the warp and the weft.
        let x = placed(|p| Vec3::new(1.1 * p.x, 0.0, 1.03 * p.y));
        assert!(near(threads(x, 0.0), [1.1, 1.03]));
        // Cut on the cross grain: the weft along x.
        assert!(near(threads(x, std::f32::consts::FRAC_PI_2), [1.03, 1.1]));
        // Pulled 25% along the bias: each thread by far less, unless cut on the bias.
        let d = Vec2::new(1.0, 1.0).normalize();
        let x = placed(|p| {
            let q = p + d * (0.25 * p.dot(d));
            Vec3::new(q.x, q.y, 0.0)
        });
        let straight = Vec2::new(1.125, 0.125).length();
        assert!(near(threads(x, 0.0), [straight, straight]));
        let bias = threads(x, std::f32::consts::FRAC_PI_4);
        assert!((bias[0] - 1.25).abs() < 1e-5 && (bias[1] - 1.0).abs() < 1e-5);
        // Shear stretches no thread along x, and the one along y by its slant.
        let g = 0.3f32;
        let x = placed(|p| Vec3::new(p.x + g * p.y, p.y, 0.0));
        assert!(near(threads(x, 0.0), [1.0, (1.0 + g * g).sqrt()]));
        // A texture at another scale than the pattern measures the same.
        let uv = CUT.map(|p| 3.0 * p + Vec2::new(0.2, 0.1));
        let x = placed(|p| Vec3::new(1.1 * p.x, 0.0, 0.9 * p.y));
        let rest = CUT.map(|p| p.extend(0.0));
        assert!(near(thread_stretch(x, rest, uv).unwrap(), [1.1, 0.9]));
    }

    #[test]
    fn a_triangle_with_no_area_as_cut_has_no_stretch() {
        let flat = [Vec2::ZERO, Vec2::new(0.1, 0.0), Vec2::new(0.2, 0.0)];
        let x = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let cut = CUT.map(|p| p.extend(0.0));
        assert_eq!(thread_stretch(x, flat.map(|p| p.extend(0.0)), CUT), None);
        assert_eq!(thread_stretch(x, cut, flat), None);
        let x = [Vec3::ZERO, Vec3::NAN, Vec3::Y];
        assert_eq!(thread_stretch(x, cut, CUT), None);
    }

    #[test]
    fn the_percentiles_are_of_the_triangles() {
        assert_eq!(ThreadStretch::of(Vec::new()), ThreadStretch::default());
        let s: Vec<f32> = (0..=100).rev().map(|k| k as f32 / 1000.0).collect();
        let t = ThreadStretch::of(s);
        assert!((t.p50 - 0.05).abs() < 1e-6 && (t.p90 - 0.09).abs() < 1e-6);
        assert!((t.max - 0.1).abs() < 1e-6);
    }
}
