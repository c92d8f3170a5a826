//! The guard: where a vertex may go. Every position the solver gives a vertex passes
//! through [`constrain`], which keeps it in its motion box and on its side of every pair
//! it is in ([`super::pairs`]), the other vertices staying where they are. The set it
//! keeps to is convex and holds the vertex's current position, so moving there never
//! breaks a pair another vertex already keeps: each move is feasible for all.

use glam::Vec3;

use super::grid::Aabb;
use super::pairs::Proximity;

/// What the guard did to one move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Guarded {
    /// The move was free.
    #[default]
    Free,
    /// It was projected onto the box or a pair's bound.
    Projected,
    /// Projection was not enough; the move was shortened.
    Shortened,
}

/// Rounds of projection before a move is shortened instead.
const PROJECTION_ROUNDS: usize = 10;
/// The rounds stop when none moved the point further than this, m.
const CONVERGED: f32 = 1e-8;
/// The room a projected point keeps from each bound, m: a few units in the last place of
/// a coordinate near 1 m, and a thousandth of the least separation a pair keeps.
const CLEARANCE: f32 = 1e-7;

/// The position for vertex `i` nearest (or near) `target` that keeps its box and pairs;
/// `x[i]` is where it is now and must be feasible (it is, when every earlier move went
/// through here).
pub fn constrain(
    i: usize,
    target: Vec3,
    x: &[Vec3],
    bx: &Aabb,
    prox: &Proximity,
) -> (Vec3, Guarded) {
    let roles = prox.roles(i);
    let t = target.clamp(bx.lo, bx.hi);
    let how = if t == target {
        Guarded::Free
    } else {
        Guarded::Projected
    };
    if roles.is_empty() {
        return (t, how);
    }
    // Most moves checked break no bound: one pass over them, nothing kept.
    let broken = roles.iter().any(|&r| {
        let (m, h) = prox.pairs[(r / 4) as usize].bound_for((r % 4) as usize, x);
        m.dot(t) < h
    });
    if !broken {
        return (t, how);
    }
    let all = project_against(i, target, x, bx, prox, roles.iter().copied(), |_| true);
    all.unwrap_or((x[i], Guarded::Shortened))
}

/// Where vertex `i`, at `x[i]` and sent to `target` past one of its bounds, goes when
/// only the bounds of `roles` (`pair * 4 + slot`, in the order of its roles) are taken
/// into account: [`constrain`]'s projection. `None` unless `held` holds at every point
/// the projection's reckoning stood on past the vertex's current place (where it ends,
/// and where the rounds ended when it is shortened): given a region where every other
/// bound of the vertex holds with room to spare, that is the full check's point
/// ([`super::reach::Reach::project`]).
pub fn project_against(
    i: usize,
    target: Vec3,
    x: &[Vec3],
    bx: &Aabb,
    prox: &Proximity,
    roles: impl Iterator<Item = u32>,
    held: impl Fn(Vec3) -> bool,
) -> Option<(Vec3, Guarded)> {
    SCRATCH.with_borrow_mut(|s| {
        s.planes.clear();
        s.shared.clear();
        for r in roles {
            let pair = &prox.pairs[(r / 4) as usize];
            s.planes.push(pair.bound_for((r % 4) as usize, x));
            s.shared.push(pair.body_bound == f32::NEG_INFINITY);
        }
        let (p, how) = s.nearest_allowed(target, x[i], bx, &held)?;
        held(p).then_some((p, how))
    })
}

/// The bounds of the vertex being constrained, and Dykstra's corrections: scratch kept
/// between calls.
#[derive(Default)]
struct Scratch {
    /// `(m, h)`: the vertex keeps `m . x >= h`.
    planes: Vec<(Vec3, f32)>,
    /// Whether each bound is a cloth pair's (its plane moves with the partner's checks)
    /// rather than the body's.
    shared: Vec<bool>,
    /// The bounds that can touch the nearest allowed point, and each one's correction.
    near: Vec<(Vec3, f32, Vec3)>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

impl Scratch {
    /// Where a vertex at `current` sent to `target`, outside its bounds, goes: the
    /// nearest allowed point when the rounds find it, else as far toward where they
    /// ended as the bounds allow, sliding along those it touches.
    /// `None` when the rounds ended where `held` does not hold.
    fn nearest_allowed(
        &mut self,
        target: Vec3,
        current: Vec3,
        bx: &Aabb,
        held: impl Fn(Vec3) -> bool,
    ) -> Option<(Vec3, Guarded)> {
        match self.project(target, current, bx) {
            Ok(p) => Some((p, Guarded::Projected)),
            Err(last) if held(last) => {
                Some((shorten(current, last, bx, &self.planes), Guarded::Shortened))
            }
            Err(_) => None,
        }
    }

    /// The point nearest `target` in the box and every bound, by Dykstra's alternating
    /// projections (Boyle and Dykstra 1986), or where the rounds ended when that is
    /// outside them. Plain alternating projection (each set in turn, no corrections)
    /// finds *a* point of the set, not the nearest, and a vertex pressed into the body
    /// where several of its bounds meet came out where it started: on the mannequin's
    /// crown a target 6.9 mm into the head, whose nearest allowed point was 2.4 mm
    /// aside, left the vertex within 0.1 µm of where it was, every substep, holding the
    /// triangles round it stretched (docs/collision.md). Dykstra's corrections make the
    /// rounds converge to the nearest point.
    ///
    /// Only the bounds that can touch the nearest point take part: it is no farther from
    /// `target` than `current` is (which is allowed), so a bound that holds all of that
    /// ball holds it too.
    fn project(&mut self, target: Vec3, current: Vec3, bx: &Aabb) -> Result<Vec3, Vec3> {
        let ball = target.distance(current);
        self.near.clear();
        let near = self
            .planes
            .iter()
            .filter(|&&(m, h)| m.dot(target) - h < ball);
        self.near.extend(near.map(|&(m, h)| (m, h, Vec3::ZERO)));
        let mut t = target;
        let mut in_box = Vec3::ZERO;
        for _ in 0..PROJECTION_ROUNDS {
            let y = t + in_box;
            let p = y.clamp(bx.lo, bx.hi);
            in_box = y - p;
            let mut change = (p - t).length_squared();
            t = p;
            for (m, h, inc) in &mut self.near {
                let y = t + *inc;
                let d = m.dot(y) - *h;
                let p = if d < 0.0 { y - *m * d } else { y };
                *inc = y - p;
                change = change.max((p - t).length_squared());
                t = p;
            }
            if change <= CONVERGED * CONVERGED {
                break;
            }
        }
        // Dykstra ends on the bounds it converged to, where rounding may leave the point
        // a unit in the last place outside; and a cloth pair's partner checks the same
        // pair from the other side, where rounding may differ by as much. A cloth bound
        // within `CLEARANCE` is given that much room, a body bound only when it is not
        // kept; a few times, as one can undo another at a corner. (Room from every bound
        // cost the 64 x 64 mannequin drape about 15% of its resting frame, two runs
        // each in one sitting.)
        for _ in 0..3 {
            let mut moved = false;
            for (&(m, h), &shared) in self.planes.iter().zip(&self.shared) {
                let d = m.dot(t) - h;
                if d < 0.0 || (shared && d < CLEARANCE) {
                    t += m * (CLEARANCE - d);
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        let inside = t.cmpge(bx.lo).all() && t.cmple(bx.hi).all();
        if inside && self.planes.iter().all(|&(m, h)| m.dot(t) >= h) {
            Ok(t)
        } else {
            Err(t)
        }
    }
}

/// Still outside after the rounds: slide along the bounds the vertex already touches,
/// then go from `current` toward `t` as far as every bound and the box allow.
fn shorten(current: Vec3, t: Vec3, bx: &Aabb, planes: &[(Vec3, f32)]) -> Vec3 {
    let step = slide(current, t - current, planes);
    let mut tau = 1.0f32;
    for &(m, h) in planes {
        let (a, b) = (m.dot(current) - h, m.dot(step));
        if a + b * tau < 0.0 {
            tau = if a > 0.0 && b < 0.0 {
                tau.min(a / -b)
            } else {
                0.0
            };
        }
    }
    for k in 0..3 {
        let (c, d) = (current[k], step[k]);
        if d > 0.0 && c + d * tau > bx.hi[k] {
            tau = tau.min(((bx.hi[k] - c) / d).max(0.0));
        } else if d < 0.0 && c + d * tau < bx.lo[k] {
            tau = tau.min(((bx.lo[k] - c) / d).max(0.0));
        }
    }
    // A little short of the bound, so rounding cannot put it past.
    let tau = (tau * 0.999).max(0.0);
    current + step * tau
}

/// A vertex on a bound (within `TOUCH`) slides along it: `step` without the part that
/// goes into each bound the vertex touches, plus `NUDGE` out of it, so the move along the
/// bound is not shortened to nothing by rounding. Without this, a vertex pressed into
/// the body in a corner of its box and several bounds (which the rounds of projection do
/// not settle) did not move at all, in any direction: the top of the mannequin's head
/// held triangles 1.4-1.5x their rest length that every substep's solve shortened and
/// the guard put back (docs/collision.md).
fn slide(current: Vec3, mut step: Vec3, planes: &[(Vec3, f32)]) -> Vec3 {
    const TOUCH: f32 = 1e-6;
    const NUDGE: f32 = 1e-9;
    for &(m, h) in planes {
        let b = m.dot(step);
        if m.dot(current) - h <= TOUCH && b < NUDGE {
            step += m * (NUDGE - b);
        }
    }
    step
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::proximity::pair::{ClothView, ProximityParams};

    #[test]
    fn a_vertex_over_a_triangle_stays_above_it() {
        // A triangle at y = 0 and a vertex 5 mm over it pushed 2 cm down.
        let x = vec![
            Vec3::new(-0.1, 0.0, -0.1),
            Vec3::new(0.1, 0.0, -0.1),
            Vec3::new(0.0, 0.0, 0.1),
            Vec3::new(0.0, 0.005, 0.0),
        ];
        let boxes: Vec<Aabb> = x.iter().map(|&p| Aabb::point(p).grown(0.03)).collect();
        let pattern = vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(5.0, 0.0, 5.0)];
        let cloth = ClothView {
            x: &x,
            boxes: &boxes,
            tris: &[[0, 1, 2]],
            edges: &[[0, 1], [1, 2], [0, 2]],
            pattern: &pattern,
            bridged: &[],
            free: &[true; 4],
        };
        let mut prox = Proximity::default();
        let params = ProximityParams {
            radius: 0.004,
            delta: 1e-4,
            rest_exclusion: 0.01,
            floor: None,
            threads: 1,
        };
        prox.detect(&cloth, None, &params);
        assert!(!prox.pairs.is_empty());
        let (p, how) = constrain(3, Vec3::new(0.01, -0.02, 0.0), &x, &boxes[3], &prox);
        assert!(p.y >= 1e-4 - 1e-7, "{p}");
        assert_ne!(how, Guarded::Free);
        // Sideways it slides freely.
        assert!((p.x - 0.01).abs() < 1e-6, "{p}");
        // And a corner of the triangle pushed up cannot pass the vertex either.
        let (q, _) = constrain(0, Vec3::new(0.0, 0.05, 0.0), &x, &boxes[0], &prox);
        assert!(q.y <= 0.005 - 1e-4 + 1e-7, "{q}");
    }

    /// The nearest point of `{m . p >= h}` to `target`, by trying every set of up to three
    /// bounds held as equalities (each bound's plane, and their lines and corners).
    fn nearest_by_brute_force(target: Vec3, planes: &[(Vec3, f32)]) -> Vec3 {
        let holds = |p: Vec3| planes.iter().all(|&(m, h)| m.dot(p) >= h - 1e-9);
        let mut best = None::<Vec3>;
        let mut consider = |p: Vec3| {
            if p.is_finite()
                && holds(p)
                && best.is_none_or(|b| p.distance(target) < b.distance(target))
            {
                best = Some(p);
            }
        };
        consider(target);
        let n = planes.len();
        for a in 0..n {
            let (ma, ha) = planes[a];
            consider(target - ma * (ma.dot(target) - ha));
            for b in a + 1..n {
                let (mb, hb) = planes[b];
                // p = target - la ma - lb mb with both planes held.
                let g = glam::Mat2::from_cols_array(&[1.0, ma.dot(mb), ma.dot(mb), 1.0]);
                if g.determinant().abs() > 1e-9 {
                    let r = glam::Vec2::new(ma.dot(target) - ha, mb.dot(target) - hb);
                    let l = g.inverse() * r;
                    consider(target - ma * l.x - mb * l.y);
                }
                for c in b + 1..n {
                    let (mc, hc) = planes[c];
                    let m = glam::Mat3::from_cols(ma, mb, mc).transpose();
                    if m.determinant().abs() > 1e-9 {
                        consider(m.inverse() * Vec3::new(ha, hb, hc));
                    }
                }
            }
        }
        best.expect("the current position is allowed")
    }

    /// A vertex on the crown of the head, on two bounds of the body 17° apart and near a
    /// third, sent 7 mm into it: it goes (near) the nearest allowed point, 1.5 mm aside
    /// along the crease. Plain alternating projection left it where it was.
    #[test]
    fn a_vertex_pressed_into_a_crease_slides_along_it_to_the_nearest_allowed_point() {
        let mm = 1e-3;
        let planes = vec![
            (Vec3::new(0.2, 1.0, 0.0).normalize(), 0.0),
            (Vec3::new(-0.1, 1.0, 0.25).normalize(), 0.0),
            (Vec3::new(0.0, 1.0, -0.3).normalize(), -0.5 * mm),
        ];
        let current = Vec3::ZERO;
        let target = Vec3::new(0.5, -7.0, 2.0) * mm;
        let bx = Aabb {
            lo: Vec3::splat(-3.0 * mm),
            hi: Vec3::splat(3.0 * mm),
        };
        let mut all = planes.clone();
        for k in 0..3 {
            let e = Vec3::AXES[k];
            all.push((e, bx.lo[k]));
            all.push((-e, -bx.hi[k]));
        }
        let exact = nearest_by_brute_force(target, &all);
        assert!(
            exact.distance(current) > 1.0 * mm,
            "{exact}: the case moves"
        );
        let mut s = Scratch {
            shared: vec![false; planes.len()],
            planes,
            near: Vec::new(),
        };
        let (p, _) = s
            .nearest_allowed(target, current, &bx, |_| true)
            .expect("held everywhere");
        // Near it: at most a tenth of the way farther from the target, and well away
        // from where it was.
        let way = exact.distance(current);
        assert!(
            p.distance(target) <= exact.distance(target) + 0.1 * way,
            "{p} against the nearest {exact}"
        );
        assert!(p.distance(current) > 0.5 * way, "{p}");
        // What the guard answers is allowed, and no farther from the target than staying.
        assert!(s.planes.iter().all(|&(m, h)| m.dot(p) >= h));
        assert!(p.distance(target) <= current.distance(target));
    }
}
