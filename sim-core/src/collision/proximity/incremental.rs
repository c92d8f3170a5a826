//! An update's changes to the pair list, made in place: the pairs of the renewed vertices
//! go, the new ones take their places, and every other pair keeps its place in the list
//! (unless it is moved down from the end into a place left over). So each vertex's pairs
//! here, the counts and the pairs the guard pushes change only where the update did,
//! rather than being worked out again over every pair: at rest the 128 x 128 drape
//! renews about 120 of its 16,641 vertices an update, among 196,000 pairs, and the passes
//! over all of them took 4 of an update's 7 ms (docs/collision.md). The guard's reach is
//! still worked out over every pair ([`super::Reach::compute_on`]): kept in step with the
//! list, its rooms only shrank between full searches and the guard checked more.

use super::distance::point_triangle;
use super::pair::{ClothView, NONE, Pair, PairCounts, ProximityParams, max_along};

/// Where an update put things: what its callers keep per pair follows from this (the
/// places a pair left, if not filled again, are past the list's end).
#[derive(Clone, Debug, Default)]
pub struct Changed {
    /// The places that now hold a new pair.
    pub fresh: Vec<u32>,
    /// Kept pairs moved down from the end: (from, to).
    pub relocated: Vec<(u32, u32)>,
    /// Pairs whose energy the update gave or took after they were placed.
    pub energy: Vec<u32>,
}

/// Each vertex's pairs, `pair * 4 + slot`: vertex `i`'s are `roles[start[i]..][..len[i]]`,
/// with room for `cap[i]`, so that an update adds and removes in place. A vertex that
/// outgrows its room gets twice as much at the end of `roles` (a full search packs
/// them again).
#[derive(Clone, Debug, Default)]
pub(super) struct RoleIndex {
    start: Vec<u32>,
    len: Vec<u32>,
    cap: Vec<u32>,
    roles: Vec<u32>,
    /// Scratch for [`splice`]: each pair, whether it goes; and the vertices that lose one.
    gone: Vec<bool>,
    losing: Vec<u32>,
}

/// Whether slot `k` of `q` is a cloth vertex of the `n`.
#[inline]
pub(super) fn live(q: &Pair, k: usize, n: usize) -> bool {
    q.side[k] != 0 && (q.v[k] as usize) < n
}

impl RoleIndex {
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        match (self.start.get(i), self.len.get(i)) {
            (Some(&a), Some(&l)) => &self.roles[a as usize..(a + l) as usize],
            _ => &[],
        }
    }

    /// Whether this indexes `n` vertices (after an edit that added some, not yet).
    pub fn covers(&self, n: usize) -> bool {
        self.len.len() == n
    }

    pub fn clear(&mut self) {
        self.start.clear();
        self.len.clear();
        self.cap.clear();
        self.roles.clear();
    }

    /// Every vertex's pairs, by counting sort, each vertex given a quarter more room
    /// than it has pairs, and four.
    pub fn build(&mut self, pairs: &[Pair], n: usize) {
        self.cap.clear();
        self.len.clear();
        self.len.resize(n, 0);
        for q in pairs {
            for k in (0..4).filter(|&k| live(q, k, n)) {
                self.len[q.v[k] as usize] += 1;
            }
        }
        self.start.clear();
        self.start.reserve(n + 1);
        let mut at = 0u32;
        for &l in &self.len {
            self.start.push(at);
            self.cap.push(l + l / 4 + 4);
            at += l + l / 4 + 4;
        }
        self.roles.clear();
        self.roles.resize(at as usize, 0);
        self.len.iter_mut().for_each(|l| *l = 0);
        for (pi, q) in pairs.iter().enumerate() {
            for k in (0..4).filter(|&k| live(q, k, n)) {
                let v = q.v[k] as usize;
                self.roles[(self.start[v] + self.len[v]) as usize] = (pi * 4 + k) as u32;
                self.len[v] += 1;
            }
        }
    }

    fn segment(&mut self, v: usize) -> &mut [u32] {
        let a = self.start[v] as usize;
        &mut self.roles[a..a + self.len[v] as usize]
    }

    /// Takes out of vertex `v`'s pairs those `gone`.
    fn remove_gone(&mut self, v: usize) {
        let a = self.start[v] as usize;
        let mut kept = 0;
        for j in 0..self.len[v] as usize {
            let r = self.roles[a + j];
            if !self.gone[(r / 4) as usize] {
                self.roles[a + kept] = r;
                kept += 1;
            }
        }
        self.len[v] = kept as u32;
    }

    fn replace(&mut self, v: usize, from: u32, to: u32) {
        match self.segment(v).iter_mut().find(|x| **x == from) {
            Some(x) => *x = to,
            None => debug_assert!(false, "vertex {v} had no role {from}"),
        }
    }

    /// Adds role `r` to vertex `v`.
    fn add(&mut self, v: usize, r: u32) {
        if self.len[v] == self.cap[v] {
            let (a, l) = (self.start[v] as usize, self.len[v] as usize);
            let at = self.roles.len();
            self.roles.extend_from_within(a..a + l);
            self.cap[v] = 2 * self.cap[v] + 4;
            self.roles.resize(at + self.cap[v] as usize, 0);
            self.start[v] = at as u32;
        }
        self.roles[(self.start[v] + self.len[v]) as usize] = r;
        self.len[v] += 1;
    }

    /// Whether this holds each vertex's pairs as [`RoleIndex::build`] would (in any order).
    #[cfg(debug_assertions)]
    pub fn same_as_built(&self, pairs: &[Pair], n: usize) -> bool {
        let mut built = RoleIndex::default();
        built.build(pairs, n);
        (0..n).all(|i| {
            let (mut a, mut b) = (self.of(i).to_vec(), built.of(i).to_vec());
            a.sort_unstable();
            b.sort_unstable();
            a == b
        })
    }
}

/// Adds (`sign` 1) or takes away (-1) pair `q` in `counts`.
fn tally(counts: &mut PairCounts, q: &Pair, sign: isize) {
    let c = counts.of_kind(q.kind);
    *c = c.wrapping_add_signed(sign);
    if q.energy {
        counts.with_energy = counts.with_energy.wrapping_add_signed(sign);
    }
}

/// Takes out every pair of the vertices `renewed` (`is_renewed` says which) and puts the
/// pairs `fresh` in: into the places left, in order, then at the end; places still left
/// are filled from the end. `index` and `counts` follow; `ch` says what went where.
#[allow(clippy::too_many_arguments)]
pub(super) fn splice(
    pairs: &mut Vec<Pair>,
    index: &mut RoleIndex,
    n: usize,
    renewed: &[u32],
    is_renewed: impl Fn(u32) -> bool,
    fresh: &mut Vec<Pair>,
    counts: &mut PairCounts,
    ch: &mut Changed,
) {
    ch.fresh.clear();
    ch.relocated.clear();
    ch.energy.clear();
    let mut gone: Vec<u32> = (renewed.iter())
        .flat_map(|&v| index.of(v as usize).iter().map(|&r| r / 4))
        .collect();
    gone.sort_unstable();
    gone.dedup();
    index.gone.resize(pairs.len(), false);
    index.losing.clear();
    for &g in &gone {
        let q = &pairs[g as usize];
        tally(counts, q, -1);
        index.gone[g as usize] = true;
        let losing = (0..4).filter(|&k| live(q, k, n) && !is_renewed(q.v[k]));
        index.losing.extend(losing.map(|k| q.v[k]));
    }
    let mut losing = std::mem::take(&mut index.losing);
    losing.sort_unstable();
    losing.dedup();
    for &v in &losing {
        index.remove_gone(v as usize);
    }
    index.losing = losing;
    for &g in &gone {
        index.gone[g as usize] = false;
    }
    for &v in renewed {
        index.len[v as usize] = 0;
    }
    let mut holes = gone.into_iter();
    for q in fresh.drain(..) {
        tally(counts, &q, 1);
        let at = match holes.next() {
            Some(h) => {
                pairs[h as usize] = q;
                h
            }
            None => {
                pairs.push(q);
                (pairs.len() - 1) as u32
            }
        };
        ch.fresh.push(at);
    }
    let mut rest: Vec<u32> = holes.collect();
    let mut lo = 0;
    while lo < rest.len() {
        let last = (pairs.len() - 1) as u32;
        if rest.last() == Some(&last) {
            pairs.pop();
            rest.pop();
            continue;
        }
        let h = rest[lo];
        lo += 1;
        let Some(q) = pairs.pop() else { break };
        for k in (0..4).filter(|&k| live(&q, k, n)) {
            index.replace(q.v[k] as usize, last * 4 + k as u32, h * 4 + k as u32);
        }
        pairs[h as usize] = q;
        ch.relocated.push((last, h));
    }
    for &at in &ch.fresh {
        let q = &pairs[at as usize];
        for k in (0..4).filter(|&k| live(q, k, n)) {
            index.add(q.v[k] as usize, at * 4 + k as u32);
        }
    }
}

/// Gives out the energy of the vertex-face pairs `ks` (all of the vertices whose energy
/// is chosen again) as a search does: for each vertex, to its nearest pair per feature
/// of the cloth (face, edge or corner) among those that may carry energy. Each pair
/// whose energy this changes is noted in `flips` with what it was. `scratch`: (vertex,
/// distance, feature, pair).
pub(super) fn nearest_feature_energy(
    c: &ClothView<'_>,
    p: &ProximityParams,
    pairs: &mut [Pair],
    ks: &[u32],
    scratch: &mut Vec<(u32, f32, [u32; 3], u32)>,
    flips: &mut Vec<(u32, bool)>,
) {
    scratch.clear();
    let mut was = Vec::with_capacity(ks.len());
    for &k in ks {
        let q = &mut pairs[k as usize];
        let i = q.v[0];
        was.push((k, q.energy));
        let tri = [q.v[1], q.v[2], q.v[3]];
        let gap_max = c.boxes[i as usize].min_along(q.n) - max_along(c.boxes, &tri, q.n);
        q.energy = gap_max < p.radius && !c.rest_near(&[i], &tri, p.rest_exclusion);
        if q.energy {
            let xi = c.x[i as usize];
            let [a, b, cc] = tri.map(|v| c.x[v as usize]);
            let (at, w) = point_triangle(xi, a, b, cc);
            // The feature by its corners, in order (unused places last).
            let mut f = tri;
            for j in 0..3 {
                if w[j] <= 0.0 {
                    f[j] = NONE;
                }
            }
            f.sort_unstable();
            scratch.push((i, (xi - at).length(), f, k));
        }
    }
    scratch.sort_unstable_by(|a, b| {
        (a.0.cmp(&b.0))
            .then(a.1.total_cmp(&b.1))
            .then(a.3.cmp(&b.3))
    });
    let mut start = 0;
    while start < scratch.len() {
        let end = start
            + scratch[start..]
                .iter()
                .take_while(|e| e.0 == scratch[start].0)
                .count();
        for k in start..end {
            let first = !scratch[start..k].iter().any(|e| e.2 == scratch[k].2);
            pairs[scratch[k].3 as usize].energy = first;
        }
        start = end;
    }
    flips.extend(
        was.into_iter()
            .filter(|&(k, e)| pairs[k as usize].energy != e),
    );
}

/// After energies were given again (`flips`: each pair changed, with what it was, a pair
/// perhaps more than once): `counts` made right, and the pairs whose energy differs from
/// before the update noted in `ch`.
pub(super) fn settle_energy(
    pairs: &[Pair],
    flips: &mut Vec<(u32, bool)>,
    counts: &mut PairCounts,
    ch: &mut Changed,
) {
    // The first note of a pair has what it was before.
    flips.sort_by_key(|f| f.0);
    flips.dedup_by_key(|f| f.0);
    for &(k, was) in flips.iter() {
        let now = pairs[k as usize].energy;
        if now != was {
            counts.with_energy = counts
                .with_energy
                .wrapping_add_signed(if now { 1 } else { -1 });
            ch.energy.push(k);
        }
    }
}
