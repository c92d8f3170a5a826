//! Strain limiting (`Material::strain_limit`, 0.2 by default): no triangle stretches in
//! any direction past `1 + limit` times its rest length (its largest principal stretch,
//! the larger singular value of the deformation gradient `F`), projected as a hard
//! constraint in every substep, before the guard and again where the guard held a
//! vertex back (Thomaszewski, Pabst & Strasser 2009; Wang, O'Brien & Ramamoorthi 2010).
//!
//! Why: with one Gauss–Seidel pass per substep a membrane carries at most about `m / h²`
//! of load before it stretches (the module docs), and where the whole hanging cloth is
//! held up by a few triangles (the top of the mannequin's head) those ended 40% longer
//! than at rest, sheared up to 80°, whatever the modulus. A woven fabric does not do
//! that: its stress-strain curve turns steeply up within a few per cent (the yarns
//! straighten), and its shear locks at 30-40° (the yarns jam), where a grid triangle's
//! diagonal is 1.2-1.25x its rest length. The limit is that stiff end of the curve; the
//! membranes still carry everything below it, so it changes nothing in cloth that is
//! not overloaded.
//!
//! The projection is exact for one triangle: with `F = X G` (`G` the membrane's warp and
//! weft coefficients `c`, `d`), the target is `F P` with `P = V diag(min(1, s / σ)) Vᵀ`
//! from the eigen decomposition of `Fᵀ F`, and the move of least mass-weighted size that
//! gives it is `Δx_a = w_a (c_a λ_u + d_a λ_v)`, with `λ` from a 2 x 2 system. Pinned
//! corners (`w = 0`) do not move; a triangle with two pinned corners is left alone.

use glam::Vec3;

use super::guard_pass::credited;
use crate::solver::constraints::Membrane;
use crate::solver::model::StretchFloor;

/// Projects every membrane of `membranes` (vertex indices into `x` and `w`) whose largest
/// principal stretch exceeds its own `s_max` (or `floor`'s there, if more) onto it (`relax` of the
/// way: 1 for all of it), in
/// order, adds the corners it moves (plus `off`: where `x` starts in the cloth) to `moved`
/// and the membranes it projected (their vertices plus `off`) to `active`.
pub(super) fn limit_membranes(
    membranes: &[Membrane],
    x: &mut [Vec3],
    w: &[f32],
    (floor, relax): (StretchFloor, f32),
    (off, moved, active): (u32, &mut Vec<u32>, &mut Vec<Membrane>),
) {
    for m in membranes {
        // A triangle within rounding of the limit (as the projection leaves it) is at it:
        // moved again by rounding alone, each vertex so moved would be checked by the
        // guard once more every substep. No limit: infinite, never over.
        let [i0, i1, i2] = m.v.map(|i| i as usize);
        let p = [x[i0], x[i1], x[i2]];
        let s_max = m.s_max.max(floor.at(&p));
        let s2 = s_max * s_max * (1.0 + 1e-5);
        let fu = p[0] * m.c[0] + p[1] * m.c[1] + p[2] * m.c[2];
        let fv = p[0] * m.d[0] + p[1] * m.d[1] + p[2] * m.d[2];
        let (a, b, c) = (fu.dot(fu), fu.dot(fv), fv.dot(fv));
        // The larger eigenvalue of FᵀF, without a square root when it is clearly under.
        let half = 0.5 * (a + c);
        let r2 = 0.25 * (a - c) * (a - c) + b * b;
        if half <= s2 && (s2 - half) * (s2 - half) >= r2 {
            continue;
        }
        let wv = [w[i0], w[i1], w[i2]];
        if let Some(d) = projection(fu, fv, (a, b, c), m, wv, s_max) {
            for (k, &i) in [i0, i1, i2].iter().enumerate() {
                if d[k] != Vec3::ZERO {
                    x[i] += d[k] * relax;
                    moved.push(i as u32 + off);
                }
            }
            active.push(Membrane {
                v: m.v.map(|i| i + off),
                ..*m
            });
        }
    }
}

/// The corners' moves that bring a triangle's largest principal stretch to `s_max`, or
/// `None` when nothing can move it (degenerate, or two corners pinned).
fn projection(
    fu: Vec3,
    fv: Vec3,
    (a, b, c): (f32, f32, f32),
    m: &Membrane,
    w: [f32; 3],
    s_max: f32,
) -> Option<[Vec3; 3]> {
    let half = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (half + r, (half - r).max(0.0));
    if !l1.is_finite() || l1 <= 0.0 {
        return None;
    }
    // The eigenvector of the larger eigenvalue, and its perpendicular.
    let v1 = if b.abs() > 1e-12 * (a + c) {
        glam::Vec2::new(l1 - c, b).normalize()
    } else if a >= c {
        glam::Vec2::X
    } else {
        glam::Vec2::Y
    };
    let v2 = v1.perp();
    let shrink = |l: f32| {
        if l > s_max * s_max {
            s_max / l.sqrt() - 1.0
        } else {
            0.0
        }
    };
    let (k1, k2) = (shrink(l1), shrink(l2));
    // P - I = k1 v1 v1ᵀ + k2 v2 v2ᵀ, and R = F (P - I), column by column.
    let q = |i: usize, j: usize| k1 * v1[i] * v1[j] + k2 * v2[i] * v2[j];
    let ru = fu * q(0, 0) + fv * q(1, 0);
    let rv = fu * q(0, 1) + fv * q(1, 1);
    let mut sa = 0.0;
    let mut sb = 0.0;
    let mut sd = 0.0;
    for k in 0..3 {
        sa += w[k] * m.c[k] * m.c[k];
        sb += w[k] * m.c[k] * m.d[k];
        sd += w[k] * m.d[k] * m.d[k];
    }
    let det = sa * sd - sb * sb;
    if det.is_nan() || det <= 1e-6 * sa * sd {
        return None;
    }
    let lu = (ru * sd - rv * sb) / det;
    let lv = (rv * sa - ru * sb) / det;
    let d = [0, 1, 2].map(|k| (lu * m.c[k] + lv * m.d[k]) * w[k]);
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// Contact undoes a penetration that was already there when the substep began without
/// making it velocity: it moves `prev` out with the vertex (`ContactCache::project`, the
/// guard's `respond`). Of that shift, each vertex of `verts` keeps only as much as it
/// really moved that way from `start`, as the guard's pass does for the vertices it
/// holds (`Xpbd::credit_pushes` calls it for every vertex at the substep's end).
/// Otherwise a vertex the limit pulls back into the contact layer every substep ends each
/// one where it began with a speed it never had, and carries that speed into the next,
/// where contact again pushes it out and the limit pulls it in: on the sewn dress with
/// the limit, a few vertices by the neck held 0.16-0.19 m/s standing still, and the
/// garment never settled.
pub(super) fn credit_moves(
    prev: &mut [Vec3],
    start: &[Vec3],
    x: &[Vec3],
    verts: impl IntoIterator<Item = u32>,
) {
    for i in verts {
        let i = i as usize;
        if prev[i] != start[i] {
            prev[i] = credited(prev[i], start[i], x[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::constraints::membrane_of;
    use glam::Vec2;

    /// A right triangle of unit legs along the warp and weft, at rest.
    fn triangle() -> (Membrane, Vec<Vec3>) {
        let rest = [Vec3::ZERO, Vec3::X, Vec3::Z];
        let m = Membrane {
            s_max: 1.2,
            ..membrane_of([0, 1, 2], 0, rest, [Vec2::ZERO, Vec2::X, Vec2::Y])
        };
        (m, rest.to_vec())
    }

    /// One whole pass of the limit at 1.2 over `ms`.
    fn limit_all(ms: &[Membrane], x: &mut [Vec3], w: &[f32]) {
        limit_membranes(
            ms,
            x,
            w,
            (StretchFloor::NONE, 1.0),
            (0, &mut Vec::new(), &mut Vec::new()),
        );
    }

    fn principal(m: &Membrane, x: &[Vec3]) -> (f32, f32) {
        let [a, b, c] = m.v.map(|i| x[i as usize]);
        let fu = a * m.c[0] + b * m.c[1] + c * m.c[2];
        let fv = a * m.d[0] + b * m.d[1] + c * m.d[2];
        let (p, q, r) = (fu.dot(fu), fu.dot(fv), fv.dot(fv));
        let h = 0.5 * (p + r);
        let d = (0.25 * (p - r) * (p - r) + q * q).sqrt();
        ((h + d).sqrt(), (h - d).max(0.0).sqrt())
    }

    #[test]
    fn a_stretched_or_sheared_triangle_is_brought_to_the_limit_and_no_further() {
        let (m, rest) = triangle();
        let w = [1.0, 1.0, 1.0];
        // Stretched 1.6x along the warp, sheared by 60° (the diagonal 1.65x), and both.
        let cases: [fn(Vec3) -> Vec3; 3] = [
            |p| Vec3::new(1.6 * p.x, p.y, p.z),
            |p| Vec3::new(p.x + 60f32.to_radians().tan() * p.z, p.y, p.z),
            |p| Vec3::new(1.3 * p.x + 0.8 * p.z, 0.3 * p.x, 1.2 * p.z),
        ];
        for f in cases {
            let mut x: Vec<Vec3> = rest.iter().map(|&p| f(p)).collect();
            let before = principal(&m, &x).0;
            assert!(before > 1.3, "{before}");
            let centroid = (x[0] + x[1] + x[2]) / 3.0;
            limit_all(&[m], &mut x, &w);
            let (s1, _) = principal(&m, &x);
            assert!((s1 - 1.2).abs() < 1e-4, "largest stretch {s1}");
            let moved = (x[0] + x[1] + x[2]) / 3.0;
            assert!(
                moved.distance(centroid) < 1e-5,
                "equal masses keep their centroid"
            );
            // Once at the limit, a second pass changes nothing.
            let again = x.clone();
            limit_all(&[m], &mut x, &w);
            assert_eq!(x, again);
        }
    }

    #[test]
    fn a_triangle_under_the_limit_or_with_two_pinned_corners_is_left_alone() {
        let (m, rest) = triangle();
        let mut x: Vec<Vec3> = rest.iter().map(|p| *p * 1.15).collect();
        let before = x.clone();
        limit_all(&[m], &mut x, &[1.0; 3]);
        assert_eq!(x, before, "1.15x is under 1.2x");
        let mut x: Vec<Vec3> = rest.iter().map(|p| *p * 2.0).collect();
        let before = x.clone();
        limit_all(&[m], &mut x, &[0.0, 0.0, 1.0]);
        assert_eq!(
            x, before,
            "two pinned corners fix the triangle's two other sides"
        );
        // One pinned corner stays where it is; the others take the whole move.
        limit_all(&[m], &mut x, &[0.0, 1.0, 1.0]);
        assert_eq!(x[0], before[0]);
        assert!((principal(&m, &x).0 - 1.2).abs() < 1e-4);
    }

    #[test]
    fn a_vertex_keeps_as_velocity_only_what_it_moved_of_a_contact_shift() {
        // Each vertex began the substep at the origin, and contact moved its `prev` 1 mm
        // up (out of the body) with it; then the limit moved it.
        let start = [Vec3::ZERO; 4];
        let shifted = Vec3::new(0.0, 1e-3, 0.0);
        let x = [
            Vec3::ZERO,                   // pulled back to where it began
            Vec3::new(0.0, 0.4e-3, 0.0),  // kept 0.4 mm of the push
            Vec3::new(2e-3, 3e-3, 0.0),   // moved out past the push, and sideways
            Vec3::new(0.0, -0.5e-3, 0.0), // pulled in past where it began
        ];
        let mut prev = [shifted; 4];
        credit_moves(&mut prev, &start, &x, [0, 1, 2, 3]);
        // Velocity (x - prev) / h: none along the push for the vertex that did not move,
        // none of it for the one that kept 0.4 mm; the others keep the shift whole, or
        // none of it.
        let near = |a: Vec3, b: Vec3| a.distance(b) < 1e-9;
        assert!(near(prev[0], Vec3::ZERO), "{}", prev[0]);
        assert!(near(prev[1], x[1]), "{}", prev[1]);
        assert!(near(prev[2], shifted), "{}", prev[2]);
        assert!(near(prev[3], Vec3::ZERO), "{}", prev[3]);
        // A vertex the limit did not move is left alone.
        let mut prev = [shifted; 4];
        credit_moves(&mut prev, &start, &x, [1]);
        assert!(near(prev[1], x[1]));
        assert_eq!([prev[0], prev[2], prev[3]], [shifted; 3]);
    }

    #[test]
    fn passes_again_over_the_projected_membranes_bring_them_toward_the_limit() {
        // A unit square of two triangles, stretched 2x along x and sheared: the pass
        // projects the first triangle, then the second, whose move of the shared corners
        // takes the first past the limit again.
        let rest = [Vec3::ZERO, Vec3::Z, Vec3::X, Vec3::new(1.0, 0.0, 1.0)];
        let uv = |p: Vec3| Vec2::new(p.x, p.z);
        let ms: Vec<Membrane> = [[0, 2, 1], [1, 2, 3]]
            .iter()
            .enumerate()
            .map(|(k, t)| {
                let r = t.map(|i| rest[i as usize]);
                Membrane {
                    s_max: 1.2,
                    ..membrane_of(*t, k as u32, r, r.map(uv))
                }
            })
            .collect();
        let w = [1.0; 4];
        let worst = |x: &[Vec3]| ms.iter().map(|m| principal(m, x).0).fold(0.0, f32::max);
        let mut x: Vec<Vec3> = rest
            .iter()
            .map(|p| Vec3::new(2.0 * p.x + 0.6 * p.z, 0.0, 1.5 * p.z))
            .collect();
        // As the second half of a split cloth: vertex indices offset by 5 in `active`.
        let (off, mut moved, mut active) = (5, Vec::new(), Vec::new());
        limit_membranes(
            &ms,
            &mut x,
            &w,
            (StretchFloor::NONE, 1.0),
            (off, &mut moved, &mut active),
        );
        let once = worst(&x);
        assert!(once > 1.21, "one pass leaves {once}");
        assert_eq!(active.len(), 2, "both triangles were projected");
        assert!(
            active
                .iter()
                .zip(&ms)
                .all(|(a, m)| a.v == m.v.map(|i| i + off))
        );
        assert!(moved.iter().all(|&i| i >= off), "moved carries the offset");
        // Passes again over what was projected (in the square's own indices here).
        let mut active: Vec<Membrane> = active
            .into_iter()
            .map(|m| Membrane {
                v: m.v.map(|i| i - off),
                ..m
            })
            .collect();
        for _ in 0..2 {
            let mut next = Vec::new();
            limit_membranes(
                &active,
                &mut x,
                &w,
                (StretchFloor::NONE, 1.0),
                (0, &mut moved, &mut next),
            );
            active = next;
        }
        let thrice = worst(&x);
        assert!(thrice - 1.2 < 0.2 * (once - 1.2), "{thrice} after {once}");
    }

    /// With tearing on the floor is the tear threshold: a triangle may stretch to it.
    #[test]
    fn a_floor_over_the_limit_lets_a_triangle_stretch_to_it() {
        let (m, rest) = triangle();
        let stretched: Vec<Vec3> = rest.iter().map(|p| *p * 1.5).collect();
        let (mut moved, mut active) = (Vec::new(), Vec::new());
        let mut x = stretched.clone();
        limit_membranes(
            &[m],
            &mut x,
            &[1.0; 3],
            (floor(1.6, None), 1.0),
            (0, &mut moved, &mut active),
        );
        assert_eq!(x, stretched, "1.5x is under the floor of 1.6x");
        // A floor around the pen's grip: a triangle with a corner within it may
        // stretch to it, one outside keeps its own limit.
        let near = Some((stretched[1] + Vec3::X * 0.09, 0.1));
        limit_membranes(
            &[m],
            &mut x,
            &[1.0; 3],
            (floor(1.6, near), 1.0),
            (0, &mut moved, &mut active),
        );
        assert_eq!(x, stretched, "a corner within the floor's reach");
        let far = Some((stretched[1] + Vec3::X * 0.2, 0.1));
        let mut y = stretched.clone();
        limit_membranes(
            &[m],
            &mut y,
            &[1.0; 3],
            (floor(1.6, far), 1.0),
            (0, &mut moved, &mut active),
        );
        assert!(
            (principal(&m, &y).0 - m.s_max).abs() < 1e-4,
            "its own limit"
        );
        limit_membranes(
            &[m],
            &mut x,
            &[1.0; 3],
            (floor(1.4, None), 1.0),
            (0, &mut moved, &mut active),
        );
        assert!((principal(&m, &x).0 - 1.4).abs() < 1e-4);
    }

    fn floor(ratio: f32, within: Option<(Vec3, f32)>) -> StretchFloor {
        StretchFloor { ratio, within }
    }

    /// A triangle of a fabric without a limit (a knit piece) is never projected.
    #[test]
    fn a_triangle_without_a_limit_is_left_alone() {
        let (m, rest) = triangle();
        let m = Membrane {
            s_max: f32::INFINITY,
            ..m
        };
        let mut x: Vec<Vec3> = rest.iter().map(|p| *p * 3.0).collect();
        let before = x.clone();
        let (mut moved, mut active) = (Vec::new(), Vec::new());
        limit_membranes(
            &[m],
            &mut x,
            &[1.0; 3],
            (StretchFloor::NONE, 1.0),
            (0, &mut moved, &mut active),
        );
        assert_eq!(x, before);
        assert!(moved.is_empty() && active.is_empty());
    }

    #[test]
    fn a_relaxed_projection_goes_part_of_the_way() {
        let (m, rest) = triangle();
        let mut x: Vec<Vec3> = rest.iter().map(|p| *p * 1.5).collect();
        let w = [1.0; 3];
        let (mut moved, mut active) = (Vec::new(), Vec::new());
        limit_membranes(
            &[m],
            &mut x,
            &w,
            (StretchFloor::NONE, 0.3),
            (0, &mut moved, &mut active),
        );
        let s = principal(&m, &x).0;
        // A uniform stretch scales about the centroid: 0.3 of the way from 1.5 to 1.2.
        assert!((s - (1.5 - 0.3 * 0.3)).abs() < 1e-4, "{s}");
        assert_eq!((moved.len(), active.len()), (3, 1));
    }
}
