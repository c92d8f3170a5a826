//! Reach: how far each vertex may move from where a search left it before any pair it is
//! in could bind, so that the guard checks its pairs only for moves beyond that.
//!
//! At a search every pair holds with some room: a cloth pair's first side lies at least
//! `G + delta` above its second along `n`, a body pair's vertex `G + delta` above the
//! body's bound. A vertex moving `d` changes its own `n . x` by at most `d`, so while
//! every vertex of a cloth pair stays within `G / 2` of where the search saw it (and a
//! body pair's within `G`), the pair holds whatever the others do: the guard's exact
//! check of such a move would find it free. A vertex's reach is the least such share over
//! its pairs (less a few micrometres for rounding), and a move inside it and inside the
//! vertex's box skips the pairs' check, which is most of the guard's time at rest (47% of
//! a resting 128 x 128 mannequin frame before, `perf`).
//!
//! The argument for a pair needs each of its vertices inside its own reach. A vertex that
//! leaves its reach (after the full check, which keeps its pairs exactly), or is moved
//! outside the guard (a pinned vertex, the pen's grip), marks its pairs broken until the
//! next search: a move of a partner inside its own reach then checks those pairs exactly,
//! and only those (at rest, most of the moves checked at all were of partners of the
//! hundred or so vertices pressed against a bound, with 30-40 pairs each). Skipped or
//! not, the guard lets each vertex go exactly where its full check would: the cloth does
//! not change by a bit.

use glam::Vec3;

use super::pair::NONE;
use super::pairs::Proximity;

/// Taken off every reach for rounding in the guard's dot products (positions of metres in
/// `f32`), m.
const ROUNDING: f32 = 4e-6;

/// Each vertex's reach from where the last search saw it.
#[derive(Clone, Debug, Default)]
pub struct Reach {
    anchor: Vec<Vec3>,
    /// Squared reach (negative: none).
    reach2: Vec<f32>,
    /// In a broken pair: its moves check those pairs.
    touched: Vec<bool>,
    /// Each pair: one of its vertices left its reach.
    broken: Vec<bool>,
    /// Left its own reach since the search (its pairs are broken).
    left: Vec<bool>,
}

impl Reach {
    /// Forgets every reach (the pairs are gone): every move is checked.
    pub fn clear(&mut self) {
        self.reach2.clear();
    }

    /// Each vertex's reach over the pairs `prox` lists, the cloth standing at `x`.
    pub fn compute(&mut self, prox: &Proximity, x: &[Vec3]) {
        let n = x.len();
        self.anchor.clear();
        self.anchor.extend_from_slice(x);
        self.reach2.clear();
        self.reach2.resize(n, f32::INFINITY);
        self.touched.clear();
        self.touched.resize(n, false);
        self.broken.clear();
        self.broken.resize(prox.pairs.len(), false);
        self.left.clear();
        self.left.resize(n, false);
        let reach = &mut self.reach2;
        for q in &prox.pairs {
            let live = |k: usize| q.side[k] != 0 && q.v[k] != NONE && (q.v[k] as usize) < n;
            if q.body_bound > f32::NEG_INFINITY {
                for k in (0..4).filter(|&k| live(k)) {
                    let v = q.v[k] as usize;
                    let room = q.side[k] as f32 * q.n.dot(x[v]) - q.body_bound - q.delta;
                    reach[v] = reach[v].min(room);
                }
                continue;
            }
            let (mut first, mut second) = (f32::INFINITY, f32::NEG_INFINITY);
            for k in (0..4).filter(|&k| live(k)) {
                let h = q.n.dot(x[q.v[k] as usize]);
                if q.side[k] > 0 {
                    first = first.min(h);
                } else {
                    second = second.max(h);
                }
            }
            let share = 0.5 * (first - second - q.delta);
            for k in (0..4).filter(|&k| live(k)) {
                let v = q.v[k] as usize;
                reach[v] = reach[v].min(share);
            }
        }
        for r in reach.iter_mut() {
            let room = *r - ROUNDING;
            // NaN (a pair with no second side) and no room alike: no reach.
            *r = if room > 0.0 { room * room } else { -1.0 };
        }
    }

    /// Whether vertex `i` may go to `t` with only its broken pairs checked, and they keep
    /// their bounds with the others standing at `x`: then the guard's full check would
    /// find the move free.
    #[inline]
    pub fn within(&self, i: usize, t: Vec3, x: &[Vec3], prox: &Proximity) -> bool {
        let Some(&r2) = self.reach2.get(i) else {
            return false;
        };
        if (t - self.anchor[i]).length_squared() > r2 {
            return false;
        }
        if !self.touched[i] {
            return true;
        }
        prox.roles(i).iter().all(|&r| {
            let k = (r / 4) as usize;
            self.broken.get(k) != Some(&true) || {
                let (m, h) = prox.pairs[k].bound_for((r % 4) as usize, x);
                // As `constrain` tests it (a NaN bound is no violation there either).
                let d = m.dot(t) - h;
                d >= 0.0 || d.is_nan()
            }
        })
    }

    /// Vertex `i` now stands at `p`: if that is past its reach, its pairs are broken, and
    /// each of their vertices checks them at every move from now on.
    #[inline]
    pub fn note(&mut self, i: usize, p: Vec3, prox: &Proximity) {
        let Some(&r2) = self.reach2.get(i) else {
            return;
        };
        // A vertex with no reach that has not moved has broken nobody's assumption.
        if self.left[i] || (p - self.anchor[i]).length_squared() <= r2.max(0.0) {
            return;
        }
        self.left[i] = true;
        for &r in prox.roles(i) {
            let k = (r / 4) as usize;
            self.broken[k] = true;
            for &v in &prox.pairs[k].v {
                if let Some(c) = self.touched.get_mut(v as usize) {
                    *c = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::body::sphere;
    use crate::collision::proximity::grid::{Aabb, unique_edges};
    use crate::collision::proximity::guard::{Guarded, constrain};
    use crate::collision::proximity::pair::{ClothView, Pair, ProximityParams};
    use crate::collision::proximity::pairs::sheet_over_a_sphere;

    /// A 24 x 24 sheet (1 cm cells) lying 1-3 mm over a 30 cm sphere with its first six
    /// rows folded back 3 mm over the rows under them: cloth pairs and body pairs, some
    /// with little room. Its pairs, searched in boxes 2 mm round each vertex.
    fn folded_sheet() -> (Vec<Vec3>, Proximity) {
        let side = 24;
        let (mut x, tris, pattern) = sheet_over_a_sphere(side);
        for j in 0..6 {
            for i in 0..side {
                x[j * side + i] = x[(11 - j) * side + i] + Vec3::Y * 0.003;
            }
        }
        let boxes: Vec<Aabb> = x.iter().map(|&p| Aabb::point(p).grown(0.002)).collect();
        let edges = unique_edges(&tris);
        let free = vec![true; x.len()];
        let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
        let view = ClothView::unwelded((&x, &boxes), (&tris, &edges), &pattern, &free);
        let mut prox = Proximity::default();
        prox.detect(&view, Some(&body), &ProximityParams::for_tests(1, None));
        assert!(prox.counts.vertex_face > 50 && prox.counts.body_vertex_face > 50);
        (x, prox)
    }

    /// Steps of a small deterministic generator in [-1, 1).
    fn noise(seed: &mut u64) -> f32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    #[test]
    fn a_move_within_reach_is_one_the_guard_finds_free() {
        let (x, prox) = folded_sheet();
        let anywhere = Aabb::point(Vec3::ZERO).grown(10.0);
        let mut seed = 7u64;
        let (mut tight, mut skipped, mut partial) = (0, 0, 0);
        for round in 0..20 {
            let mut reach = Reach::default();
            reach.compute(&prox, &x);
            // Every vertex in turn, as the guard's pass goes, the others where they went
            // before it: to a random place within its reach, or (every seventh, from the
            // second round) well past it, as the full check lets it.
            let mut now = x.clone();
            for i in 0..x.len() {
                let r = reach.reach2[i].max(0.0).sqrt().min(0.01);
                let dir = Vec3::new(noise(&mut seed), noise(&mut seed), noise(&mut seed));
                let far = round > 0 && (i + round) % 7 == 0;
                let step = if far {
                    3.0 * r + 0.002
                } else {
                    r * noise(&mut seed).abs()
                };
                let t = x[i] + dir.normalize_or_zero() * step;
                if reach.within(i, t, &now, &prox) {
                    skipped += 1;
                    tight += usize::from(r < 1e-3 && !prox.roles(i).is_empty());
                    partial += usize::from(reach.touched[i]);
                    assert_eq!(constrain(i, t, &now, &anywhere, &prox), (t, Guarded::Free));
                    now[i] = t;
                } else {
                    now[i] = constrain(i, t, &now, &anywhere, &prox).0;
                }
                reach.note(i, now[i], &prox);
            }
            assert!(prox.all_hold(&now, 0.0));
        }
        assert!(
            skipped > 20 * x.len() / 2 && tight > 100,
            "{skipped} {tight}"
        );
        assert!(
            partial > 200,
            "moves checked against broken pairs only: {partial}"
        );
    }

    #[test]
    fn a_reach_is_all_the_room_a_pair_has() {
        let (x, prox) = folded_sheet();
        let mut reach = Reach::default();
        reach.compute(&prox, &x);
        // The cloth pair with the least room: its two sides pushed toward each other by
        // just under their reach keep it, by a little over, break it.
        let room = |q: &Pair| {
            let r =
                q.v.iter()
                    .filter(|&&v| v != NONE)
                    .map(|&v| reach.reach2[v as usize]);
            r.fold(f32::INFINITY, f32::min)
        };
        let cloth = prox
            .pairs
            .iter()
            .filter(|q| q.body_bound == f32::NEG_INFINITY);
        let q = cloth
            .filter(|q| room(q) > 0.0)
            .min_by(|a, b| room(a).total_cmp(&room(b)))
            .expect("a cloth pair with room");
        let pushed = |by: f32| {
            let mut y = x.clone();
            for k in (0..4).filter(|&k| q.side[k] != 0) {
                let r = reach.reach2[q.v[k] as usize].sqrt();
                y[q.v[k] as usize] -= q.n * (q.side[k] as f32 * r * by);
            }
            q.holds(&y, 0.0)
        };
        assert!(pushed(0.99));
        assert!(!pushed(1.2));
    }

    #[test]
    fn a_vertex_past_its_reach_breaks_its_pairs_and_no_others() {
        let (x, prox) = folded_sheet();
        let mut reach = Reach::default();
        reach.compute(&prox, &x);
        let i = (0..x.len())
            .find(|&i| prox.roles(i).len() > 3 && reach.reach2[i] > 0.0)
            .expect("a vertex in pairs");
        let mine = |k: usize| prox.pairs[k].v.contains(&(i as u32));
        // Within its reach: nothing changes.
        reach.note(i, x[i], &prox);
        assert!(!reach.broken.contains(&true));
        // Past it, through one of its pairs (5 cm toward the pair's other side): its pairs
        // are broken, no others.
        let r = prox.roles(i)[0];
        let q = &prox.pairs[(r / 4) as usize];
        let mut moved = x.clone();
        moved[i] -= q.n * (q.side[(r % 4) as usize] as f32 * 0.05);
        reach.note(i, moved[i], &prox);
        for k in 0..prox.pairs.len() {
            assert_eq!(reach.broken[k], mine(k), "pair {k}");
        }
        // A partner standing still is let through exactly when the full check finds it
        // free against the vertex where it went; a vertex in none of its pairs, as before.
        let anywhere = Aabb::point(Vec3::ZERO).grown(10.0);
        let (mut kept, mut stopped) = (0, 0);
        for j in (0..x.len()).filter(|&j| j != i && reach.reach2[j] > 0.0) {
            let full = constrain(j, x[j], &moved, &anywhere, &prox).1 == Guarded::Free;
            assert_eq!(reach.within(j, x[j], &moved, &prox), full, "vertex {j}");
            if reach.touched[j] {
                if full { kept += 1 } else { stopped += 1 }
            }
        }
        assert!(kept > 0 && stopped > 0, "{kept} {stopped}");
        // After a search nothing is broken.
        reach.compute(&prox, &moved);
        assert!(!reach.broken.contains(&true) && !reach.touched.contains(&true));
    }
}
