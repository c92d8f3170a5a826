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
//! The argument needs every partner inside its own reach. A vertex that leaves its reach
//! (after the full check, which keeps its pairs exactly) marks every vertex it shares a
//! pair with, and those check every move in full until the next search; so does one that
//! is moved outside the guard (a pinned vertex, the pen's grip). Skipped or not, the
//! guard lets each vertex go exactly where its full check would: the cloth does not
//! change by a bit.

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
    /// A partner left its reach: every move is checked in full.
    check: Vec<bool>,
    /// Left its own reach since the search (its partners are marked).
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
        self.check.clear();
        self.check.resize(n, false);
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

    /// Whether vertex `i` may go to `t` without its pairs being checked.
    #[inline]
    pub fn within(&self, i: usize, t: Vec3) -> bool {
        match (self.reach2.get(i), self.check.get(i)) {
            (Some(&r2), Some(&false)) => (t - self.anchor[i]).length_squared() <= r2,
            _ => false,
        }
    }

    /// Vertex `i` now stands at `p`: if that is past its reach, every vertex it shares a
    /// pair with checks its moves in full from now on.
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
            let q = &prox.pairs[(r / 4) as usize];
            for &v in &q.v {
                if let Some(c) = self.check.get_mut(v as usize) {
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
        let mut reach = Reach::default();
        reach.compute(&prox, &x);
        let anywhere = Aabb::point(Vec3::ZERO).grown(10.0);
        let mut seed = 7u64;
        let (mut tight, mut skipped) = (0, 0);
        for _ in 0..20 {
            // Every vertex in turn, as the guard's pass goes, to a random place within its
            // reach, the others where they went before it.
            let mut now = x.clone();
            for i in 0..x.len() {
                let r = reach.reach2[i].max(0.0).sqrt().min(0.01);
                let dir = Vec3::new(noise(&mut seed), noise(&mut seed), noise(&mut seed));
                let t = x[i] + dir.normalize_or_zero() * r * noise(&mut seed).abs();
                if !reach.within(i, t) {
                    continue;
                }
                skipped += 1;
                tight += usize::from(r < 1e-3 && !prox.roles(i).is_empty());
                assert_eq!(constrain(i, t, &now, &anywhere, &prox), (t, Guarded::Free));
                now[i] = t;
            }
            assert!(prox.all_hold(&now, 0.0));
        }
        assert!(
            skipped > 20 * x.len() * 9 / 10 && tight > 200,
            "{skipped} {tight}"
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
    fn a_vertex_past_its_reach_makes_its_partners_check_in_full() {
        let (x, prox) = folded_sheet();
        let mut reach = Reach::default();
        reach.compute(&prox, &x);
        let i = (0..x.len())
            .find(|&i| prox.roles(i).len() > 3 && reach.reach2[i] > 0.0)
            .expect("a vertex in pairs");
        let partners: Vec<usize> = prox
            .roles(i)
            .iter()
            .flat_map(|&r| prox.pairs[(r / 4) as usize].v)
            .filter(|&v| v != NONE && v as usize != i)
            .map(|v| v as usize)
            .collect();
        let stranger = (0..x.len())
            .find(|j| !partners.contains(j) && *j != i && reach.reach2[*j] > 0.0)
            .expect("a vertex in no pair with it");
        assert!(partners.iter().any(|&j| reach.within(j, x[j])));
        // Within its reach: nothing changes.
        reach.note(i, x[i], &prox);
        assert!(partners.iter().any(|&j| reach.within(j, x[j])));
        // Past it: every partner checks, a vertex it shares no pair with need not.
        reach.note(i, x[i] + Vec3::Y * 0.05, &prox);
        assert!(partners.iter().all(|&j| !reach.within(j, x[j])));
        assert!(reach.within(stranger, x[stranger]));
        // And after a search, nobody has left.
        reach.compute(&prox, &x);
        assert!(partners.iter().any(|&j| reach.within(j, x[j])));
    }
}
