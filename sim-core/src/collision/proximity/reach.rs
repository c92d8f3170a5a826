//! Reach: how far each vertex may move from where a search left it before any pair it is
//! in could bind, so that the guard checks its pairs only for moves beyond that.
//!
//! At a search every pair holds with some room: a cloth pair's first side lies at least
//! `G + delta` above its second along `n`, a body pair's vertex `G + delta` above the
//! body's bound. A vertex moving `d` changes its own `n . x` by at most `d`, so while
//! every vertex of a cloth pair stays within `G / 2` of where the search saw it (and a
//! body pair's within `G`), the pair holds whatever the others do: the guard's exact
//! check of such a move would find it free. That share is the pair's room for each of its
//! vertices (less a few micrometres for rounding), and a vertex's reach is the least room
//! over its pairs: a move inside it (and inside the vertex's box) skips the pairs' check,
//! which is most of the guard's time at rest (47% of a resting 128 x 128 mannequin frame
//! before, `perf`).
//!
//! The argument for a pair needs each of its vertices inside its room for that pair. A
//! vertex that goes past the room of some of its pairs (after the exact check of those
//! pairs), or is moved outside the guard (a pinned vertex, the pen's grip), marks those
//! pairs broken until the next search. A move checks exactly the pairs it takes past
//! their room and the broken ones, and only those: a vertex pressed against the body has
//! one or two pairs with no room among 30-40 with millimetres of it (the sewn 2 x 8k dress
//! at rest spent 41% of its frame checking them all, `perf`). Skipped or not, the guard
//! lets each vertex go exactly where its full check would: the cloth does not change by a
//! bit (the debug build compares each such move with the full check).

use std::sync::atomic::Ordering::Relaxed;
use std::sync::atomic::{AtomicBool, AtomicU32};

use glam::Vec3;

use super::grid::Aabb;
use super::guard::{Guarded, project_against};
use super::pair::{NONE, Pair};
use super::pairs::Proximity;

/// Taken off every reach for rounding in the guard's dot products (positions of metres in
/// `f32`), m.
const ROUNDING: f32 = 4e-6;

/// Each vertex's reach from where the last search saw it.
///
/// What a pass marks (`touched`, `broken`, `farthest2`) is kept in atomics so that the
/// guard's two halves can mark at once through a shared `Reach`: a vertex of one half
/// marks only its own pairs and their vertices, all in its half ([`Reach::order`]), so
/// no flag is written by both; relaxed loads and stores are plain ones on x86, and the
/// threads' scope orders them for what follows.
#[derive(Clone, Debug, Default)]
pub struct Reach {
    anchor: Vec<Vec3>,
    /// Squared reach: the least of the vertex's rooms (negative: none).
    reach2: Vec<f32>,
    /// Each role (`pair * 4 + slot`): the squared room of that vertex in that pair
    /// (negative: none).
    room2: Vec<f32>,
    /// In a broken pair: its moves check those pairs.
    touched: Flags,
    /// Each pair: one of its vertices went past its room.
    broken: Flags,
    /// The farthest (squared) each vertex has stood from its anchor since the search, as
    /// far as its pairs are concerned: every pair whose room that exceeds is broken.
    farthest2: Floats,
    /// The order the guard passes the vertices in: the first half of the vertex range's
    /// vertices whose pairs lie all in that half, the same for the second half, then the
    /// rest (each in vertex order); and where the halves meet.
    order: [Vec<u32>; 3],
    /// Each vertex's list in `order`.
    part: Vec<u8>,
    mid: usize,
    /// Scratch for the second thread of [`Reach::compute_on`]: its reach and lists.
    other: (Vec<f32>, Vec<u8>),
}

/// Flags two threads may set at once, each its own.
#[derive(Debug, Default)]
struct Flags(Vec<AtomicBool>);

impl Clone for Flags {
    fn clone(&self) -> Self {
        Self(
            self.0
                .iter()
                .map(|f| AtomicBool::new(f.load(Relaxed)))
                .collect(),
        )
    }
}

impl Flags {
    fn reset(&mut self, n: usize) {
        self.0.clear();
        self.0.resize_with(n, AtomicBool::default);
    }

    #[inline]
    fn get(&self, i: usize) -> Option<bool> {
        self.0.get(i).map(|f| f.load(Relaxed))
    }

    #[inline]
    fn set(&self, i: usize) {
        if let Some(f) = self.0.get(i) {
            f.store(true, Relaxed);
        }
    }

    #[cfg(test)]
    fn to_vec(&self) -> Vec<bool> {
        self.0.iter().map(|f| f.load(Relaxed)).collect()
    }
}

/// `f32`s two threads may write at once, each its own.
#[derive(Debug, Default)]
struct Floats(Vec<AtomicU32>);

impl Clone for Floats {
    fn clone(&self) -> Self {
        Self(
            self.0
                .iter()
                .map(|f| AtomicU32::new(f.load(Relaxed)))
                .collect(),
        )
    }
}

impl Floats {
    #[inline]
    fn get(&self, i: usize) -> Option<f32> {
        self.0.get(i).map(|f| f32::from_bits(f.load(Relaxed)))
    }

    #[inline]
    fn set(&self, i: usize, v: f32) {
        if let Some(f) = self.0.get(i) {
            f.store(v.to_bits(), Relaxed);
        }
    }
}

/// The squared room for a share of `room` metres (negative: none).
fn squared(room: f32) -> f32 {
    let room = room - ROUNDING;
    // NaN (a pair with no second side) and no room alike: none.
    if room > 0.0 { room * room } else { -1.0 }
}

/// Pairs from which [`Reach::compute_on`] shares them between two threads (a handoff
/// costs 36-126 µs on the development VM; a pair, about 12 ns).
const PARALLEL_FROM: usize = 20_000;

/// Each of `pairs`' rooms (`rooms`, four each), the least of them for each vertex
/// (`reach`), and the vertices of pairs that straddle `mid` put in the last list (`part`),
/// the cloth standing at `x`.
fn rooms_of(
    pairs: &[Pair],
    x: &[Vec3],
    mid: usize,
    rooms: &mut [f32],
    reach: &mut [f32],
    part: &mut [u8],
) {
    let n = x.len();
    for (q, rooms) in pairs.iter().zip(rooms.chunks_exact_mut(4)) {
        let cloth = q.v.iter().filter(|&&v| v != NONE && (v as usize) < n);
        if cloth.clone().any(|&v| v as usize >= mid) && cloth.clone().any(|&v| (v as usize) < mid) {
            cloth.for_each(|&v| part[v as usize] = 2);
        }
        let live = |k: usize| q.side[k] != 0 && q.v[k] != NONE && (q.v[k] as usize) < n;
        if q.body_bound > f32::NEG_INFINITY {
            for k in (0..4).filter(|&k| live(k)) {
                let v = q.v[k] as usize;
                let room = q.side[k] as f32 * q.n.dot(x[v]) - q.body_bound - q.delta;
                rooms[k] = squared(room);
                reach[v] = reach[v].min(rooms[k]);
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
        let share = squared(0.5 * (first - second - q.delta));
        for k in (0..4).filter(|&k| live(k)) {
            rooms[k] = share;
            let v = q.v[k] as usize;
            reach[v] = reach[v].min(share);
        }
    }
}

impl Reach {
    /// Forgets every reach (the pairs are gone): every move is checked.
    pub fn clear(&mut self) {
        self.reach2.clear();
        self.farthest2.0.clear();
        self.order.iter_mut().for_each(Vec::clear);
    }

    /// Each vertex's reach over `pairs` (a search's), the cloth standing at `x`.
    pub fn compute(&mut self, pairs: &[Pair], x: &[Vec3]) {
        self.compute_on(pairs, x, 1);
    }

    /// [`Reach::compute`], the pairs shared between two threads when `threads` says so
    /// and they are many (each half's reach and lists are kept apart, then joined).
    pub fn compute_on(&mut self, pairs: &[Pair], x: &[Vec3], threads: usize) {
        let n = x.len();
        self.anchor.clear();
        self.anchor.extend_from_slice(x);
        self.reach2.clear();
        self.reach2.resize(n, f32::INFINITY);
        self.room2.clear();
        self.room2.resize(pairs.len() * 4, -1.0);
        self.touched.reset(n);
        self.broken.reset(pairs.len());
        let mid = n / 2;
        // Each vertex's list: its half, or the rest once a pair of it straddles `mid`.
        self.part.clear();
        self.part.extend((0..n).map(|v| u8::from(v >= mid)));
        if threads > 1 && pairs.len() >= PARALLEL_FROM {
            let h = pairs.len() / 2;
            let (a, b) = pairs.split_at(h);
            let (ra, rb) = self.room2.split_at_mut(4 * h);
            let (reach, part) = (&mut self.reach2, &mut self.part);
            let other = &mut self.other;
            other.0.clear();
            other.0.resize(n, f32::INFINITY);
            other.1.clear();
            other.1.extend_from_slice(part);
            std::thread::scope(|s| {
                s.spawn(|| rooms_of(b, x, mid, rb, &mut other.0, &mut other.1));
                rooms_of(a, x, mid, ra, reach, part);
            });
            for (r, &o) in reach.iter_mut().zip(&other.0) {
                *r = r.min(o);
            }
            for (p, &o) in part.iter_mut().zip(&other.1) {
                *p = (*p).max(o);
            }
        } else {
            rooms_of(
                pairs,
                x,
                mid,
                &mut self.room2,
                &mut self.reach2,
                &mut self.part,
            );
        }
        let far = self
            .reach2
            .iter()
            .map(|&r| AtomicU32::new(r.max(0.0).to_bits()));
        self.farthest2.0.clear();
        self.farthest2.0.extend(far);
        self.mid = mid;
        self.sort_order();
    }

    fn sort_order(&mut self) {
        self.order.iter_mut().for_each(Vec::clear);
        for (v, &list) in self.part.iter().enumerate() {
            self.order[list as usize].push(v as u32);
        }
    }

    /// Splits `verts` into the lists of [`Reach::order`] they belong to, each in the
    /// order given (`None` as there).
    pub fn split(&self, verts: &[u32], n: usize, lists: &mut [Vec<u32>; 3]) -> Option<usize> {
        self.order(n)?;
        lists.iter_mut().for_each(Vec::clear);
        for &v in verts {
            let part = self.part.get(v as usize).copied().unwrap_or(2);
            lists[part as usize].push(v);
        }
        Some(self.mid)
    }

    /// The order the guard may pass the cloth's `n` vertices in, in two threads: the
    /// first half of the vertex range's vertices whose pairs are all within that half
    /// (`lists[0]`), the second half's (`lists[1]`), then every other vertex
    /// (`lists[2]`), and `mid`, where the halves meet. A vertex's move is checked against
    /// its pairs' other vertices as they stand and marks only its own pairs, so the
    /// first two lists, passed at once, meet no vertex or pair of the other: the same
    /// as passing them one after the other. `None` when the pairs were not worked out
    /// for `n` vertices.
    pub fn order(&self, n: usize) -> Option<(usize, &[Vec<u32>; 3])> {
        let all = self.order.iter().map(Vec::len).sum::<usize>();
        (all == n && self.reach2.len() == n).then_some((self.mid, &self.order))
    }

    /// Whether vertex `i` may go to `t` with only the pairs checked that the move takes
    /// past their room, and the broken ones, and they keep their bounds with the others
    /// standing at `x`: then the guard's full check would find the move free.
    #[inline]
    pub fn within(&self, i: usize, t: Vec3, x: &[Vec3], prox: &Proximity) -> bool {
        let Some(&r2) = self.reach2.get(i) else {
            return false;
        };
        let d2 = (t - self.anchor[i]).length_squared();
        if d2 <= r2 && self.touched.get(i) == Some(false) {
            return true;
        }
        prox.roles(i).iter().all(|&r| {
            self.safe(r, d2) || {
                let (m, h) = prox.pairs[(r / 4) as usize].bound_for((r % 4) as usize, x);
                // As `constrain` tests it (a NaN bound is no violation there either).
                let d = m.dot(t) - h;
                d >= 0.0 || d.is_nan()
            }
        })
    }

    /// Whether `t` is within vertex `i`'s reach (where no pair of it can bind).
    pub fn in_reach(&self, i: usize, t: Vec3) -> bool {
        let d2 = |a: Vec3| (t - a).length_squared();
        let at = self.anchor.get(i);
        self.reach2
            .get(i)
            .zip(at)
            .is_some_and(|(&r2, &a)| d2(a) <= r2)
    }

    /// Whether role `r`'s pair holds wherever its vertex stands within `sqrt(d2)` of its
    /// anchor, the pair's other vertices standing anywhere they have stood.
    #[inline]
    fn safe(&self, r: u32, d2: f32) -> bool {
        self.broken.get((r / 4) as usize) == Some(false)
            && self.room2.get(r as usize).is_some_and(|&room| room >= d2)
    }

    /// Where vertex `i` sent to `target`, past some bound [`Reach::within`] checked,
    /// goes: the guard's projection against only the pairs that can bind within the
    /// distance from the anchor plus twice the move (those whose room that leaves, and
    /// the broken ones); every other pair holds there with a few micrometres to spare, so
    /// it is out of the projection's own reckoning too (it ends nearer the target than the
    /// vertex is, unless shortened along a straight path from the vertex, which leaves
    /// that ball once and does not come back). `None` when that cannot be said (no reach,
    /// or the projection stood farther out): check in full.
    pub fn project(
        &self,
        i: usize,
        target: Vec3,
        x: &[Vec3],
        bx: &Aabb,
        prox: &Proximity,
    ) -> Option<(Vec3, Guarded)> {
        self.reach2.get(i)?;
        let anchor = self.anchor[i];
        let radius = target.distance(anchor) + 2.0 * target.distance(x[i]);
        let r2 = radius * radius;
        let roles = prox.roles(i).iter().copied();
        let roles = roles.filter(|&r| !self.safe(r, r2));
        let held = |p: Vec3| (p - anchor).length_squared() <= r2;
        project_against(i, target, x, bx, prox, roles, held)
    }

    /// Vertex `i` now stands at `p`: the pairs whose room that is past are broken, and
    /// each of their vertices checks them at every move from now on.
    #[inline]
    pub fn note(&self, i: usize, p: Vec3, prox: &Proximity) {
        let Some(far2) = self.farthest2.get(i) else {
            return;
        };
        // Within every room it has been past already (a vertex with no room that has not
        // moved has broken nobody's assumption).
        let d2 = (p - self.anchor[i]).length_squared();
        if d2 <= far2 {
            return;
        }
        self.farthest2.set(i, d2);
        for &r in prox.roles(i) {
            let k = (r / 4) as usize;
            if self.broken.get(k) != Some(false) || self.room2[r as usize] >= d2 {
                continue;
            }
            self.broken.set(k);
            for &v in &prox.pairs[k].v {
                self.touched.set(v as usize);
            }
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
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
    pub(in crate::collision::proximity) fn noise(seed: &mut u64) -> f32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// Shared between two threads, the reach, rooms and lists are those one thread
    /// finds (the sheet's pairs between pairs of no vertex, past where two threads
    /// start, so that each thread has half of them).
    #[test]
    fn two_threads_work_out_the_reach_one_does() {
        let (x, prox) = folded_sheet();
        let mut none = prox.pairs[0];
        none.side = [0; 4];
        let pad = vec![none; PARALLEL_FROM / 2];
        let pairs = [&pad[..], &prox.pairs, &pad[..]].concat();
        let (mut one, mut two) = (Reach::default(), Reach::default());
        one.compute(&pairs, &x);
        two.compute_on(&pairs, &x, 2);
        assert_eq!(one.reach2, two.reach2);
        assert_eq!(one.room2, two.room2);
        assert_eq!(one.part, two.part);
        assert_eq!(one.order, two.order);
        let (fa, fb) = (&one.farthest2, &two.farthest2);
        assert!((0..x.len()).all(|i| fa.get(i) == fb.get(i)));
        let straddling = one.part.iter().filter(|&&p| p == 2).count();
        let limited = one.reach2.iter().filter(|r| r.is_finite()).count();
        assert!(
            straddling > 0 && limited > x.len() / 2,
            "{straddling}, {limited}"
        );
    }

    #[test]
    fn a_move_within_reach_is_one_the_guard_finds_free() {
        let (x, prox) = folded_sheet();
        let anywhere = Aabb::point(Vec3::ZERO).grown(10.0);
        let mut seed = 7u64;
        let (mut tight, mut skipped, mut partial, mut projected) = (0, 0, 0, 0);
        for round in 0..20 {
            let mut reach = Reach::default();
            reach.compute(&prox.pairs, &x);
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
                    partial += usize::from(reach.touched.get(i) == Some(true));
                    assert_eq!(constrain(i, t, &now, &anywhere, &prox), (t, Guarded::Free));
                    now[i] = t;
                } else {
                    let full = constrain(i, t, &now, &anywhere, &prox);
                    // Against the pairs it can reach, when it says, it goes where the
                    // full check sends it.
                    if let Some(near) = reach.project(i, t, &now, &anywhere, &prox) {
                        assert_eq!(near, full, "vertex {i}");
                        projected += 1;
                    }
                    now[i] = full.0;
                }
                reach.note(i, now[i], &prox);
            }
            assert!(prox.all_hold(&now, 0.0));
        }
        assert!(
            skipped > 20 * x.len() / 2 && tight > 100 && projected > 20,
            "{skipped} {tight} {projected}"
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
        reach.compute(&prox.pairs, &x);
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
    fn a_vertex_breaks_only_the_pairs_whose_room_it_passed() {
        let (x, prox) = folded_sheet();
        let mut reach = Reach::default();
        reach.compute(&prox.pairs, &x);
        // A vertex whose pairs have different rooms, moved halfway between its least room
        // and its greatest: the pairs with less room than that are broken, no others.
        let rooms = |i: usize| prox.roles(i).iter().map(|&r| reach.room2[r as usize]);
        let spread = |i: usize| {
            let (lo, hi) = rooms(i).fold((f32::INFINITY, 0.0f32), |(a, b), r| (a.min(r), b.max(r)));
            (lo > 0.0 && hi > 4.0 * lo).then_some((lo.sqrt(), hi.sqrt()))
        };
        let (i, (lo, hi)) = (0..x.len())
            .find_map(|i| spread(i).map(|s| (i, s)))
            .expect("a vertex with pairs of different room");
        let d = 0.5 * (lo + hi);
        let mut moved = x.clone();
        moved[i] += Vec3::X * d;
        reach.note(i, moved[i], &prox);
        let passed = |r: u32| reach.room2[r as usize] < d * d;
        let mine: Vec<u32> = prox.roles(i).to_vec();
        assert!(mine.iter().any(|&r| passed(r)) && mine.iter().any(|&r| !passed(r)));
        for k in 0..prox.pairs.len() {
            let expect = mine.iter().any(|&r| (r / 4) as usize == k && passed(r));
            assert_eq!(reach.broken.get(k), Some(expect), "pair {k}");
        }
        // Within what it has already passed, nothing more breaks.
        let before = reach.broken.to_vec();
        reach.note(i, x[i] + Vec3::X * (0.9 * d), &prox);
        assert_eq!(reach.broken.to_vec(), before);
    }

    #[test]
    fn a_vertex_past_its_reach_breaks_its_pairs_and_no_others() {
        let (x, prox) = folded_sheet();
        let mut reach = Reach::default();
        reach.compute(&prox.pairs, &x);
        let i = (0..x.len())
            .find(|&i| prox.roles(i).len() > 3 && reach.reach2[i] > 0.0)
            .expect("a vertex in pairs");
        let mine = |k: usize| prox.pairs[k].v.contains(&(i as u32));
        // Within its reach: nothing changes.
        reach.note(i, x[i], &prox);
        assert!(!reach.broken.to_vec().contains(&true));
        // Past it, through one of its pairs (5 cm toward the pair's other side): its pairs
        // are broken, no others.
        let r = prox.roles(i)[0];
        let q = &prox.pairs[(r / 4) as usize];
        let mut moved = x.clone();
        moved[i] -= q.n * (q.side[(r % 4) as usize] as f32 * 0.05);
        reach.note(i, moved[i], &prox);
        for k in 0..prox.pairs.len() {
            assert_eq!(reach.broken.get(k), Some(mine(k)), "pair {k}");
        }
        // A partner standing still is let through exactly when the full check finds it
        // free against the vertex where it went; a vertex in none of its pairs, as before.
        let anywhere = Aabb::point(Vec3::ZERO).grown(10.0);
        let (mut kept, mut stopped) = (0, 0);
        for j in (0..x.len()).filter(|&j| j != i && reach.reach2[j] > 0.0) {
            let full = constrain(j, x[j], &moved, &anywhere, &prox).1 == Guarded::Free;
            assert_eq!(reach.within(j, x[j], &moved, &prox), full, "vertex {j}");
            if reach.touched.get(j) == Some(true) {
                if full { kept += 1 } else { stopped += 1 }
            }
        }
        assert!(kept > 0 && stopped > 0, "{kept} {stopped}");
        // After a search nothing is broken.
        reach.compute(&prox.pairs, &moved);
        assert!(!reach.broken.to_vec().contains(&true) && !reach.touched.to_vec().contains(&true));
    }
}
