//! The guard's pass over a substep's moves: each vertex in turn, kept on its side of
//! its pairs ([`crate::collision::proximity::constrain`], checked only past its reach),
//! in the order [`Reach::order`] gives, the two halves' own vertices on two threads.

use glam::Vec3;

use crate::collision::proximity::{Aabb, Guarded, Proximity, Reach, constrain};

/// The vertex indices of a list.
pub(super) fn each(list: &[u32]) -> impl Iterator<Item = usize> + '_ {
    list.iter().map(|&i| i as usize)
}

/// Vertices from this many on pass the guard in two threads (when there are two): below,
/// starting the second thread costs more than it saves.
pub(super) const GUARD_PARALLEL_FROM: usize = 8_000;

/// Vertices from this many in each half of a list pass the guard's second look
/// ([`Guard::enforce_only`]) in two threads.
pub(super) const ONLY_PARALLEL_FROM: usize = 256;

/// What the guard's pass reads, shared by the two halves' threads.
pub(super) struct Moves<'a> {
    free: &'a [bool],
    boxes: &'a [Aabb],
    pub(super) reach: &'a Reach,
    prox: &'a Proximity,
}

/// What a pass did to its moves.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Counts {
    pub(super) skipped: usize,
    pub(super) projected: usize,
    pub(super) shortened: usize,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Self) {
        self.skipped += o.skipped;
        self.projected += o.projected;
        self.shortened += o.shortened;
    }
}

impl<'a> Moves<'a> {
    pub(super) fn of(
        free: &'a [bool],
        boxes: &'a [Aabb],
        reach: &'a Reach,
        prox: &'a Proximity,
    ) -> Self {
        Self {
            free,
            boxes,
            reach,
            prox,
        }
    }

    /// Passes the moves of `verts` in turn (from `committed` to `targets`), each vertex
    /// kept at `committed` as it goes; `prev` holds the vertices from `off` on.
    pub(super) fn run(
        &self,
        committed: &mut [Vec3],
        targets: &[Vec3],
        (prev, off): (&mut [Vec3], usize),
        verts: impl Iterator<Item = usize>,
    ) -> Counts {
        let mut counts = Counts::default();
        for i in verts {
            let (p, how) = self.pass(committed, i, targets[i], &mut counts);
            if how != Guarded::Free {
                // Contact shifted `prev` by the push it gave (so the push is no velocity);
                // credit no more of it than the vertex moved that way.
                let pv = &mut prev[i - off];
                *pv = credited(*pv, committed[i], p);
            }
            committed[i] = p;
        }
        counts
    }

    /// Passes the moves of `verts` in turn (from `committed` to where `x` has them), each
    /// vertex kept at `committed` and `x` as it goes; `x` holds the vertices from `off`
    /// on. Their velocity stays as the move was.
    pub(super) fn run_only(
        &self,
        committed: &mut [Vec3],
        (x, off): (&mut [Vec3], usize),
        verts: &[u32],
    ) -> Counts {
        let mut counts = Counts::default();
        for &i in verts {
            let i = i as usize;
            let (p, _) = self.pass(committed, i, x[i - off], &mut counts);
            committed[i] = p;
            x[i - off] = p;
        }
        counts
    }

    /// Where vertex `i` sent to `target` may go (from `committed`), counted in `counts`.
    pub(super) fn pass(
        &self,
        committed: &[Vec3],
        i: usize,
        target: Vec3,
        counts: &mut Counts,
    ) -> (Vec3, Guarded) {
        if !self.free[i] {
            self.reach.note(i, target, self.prox);
            return (target, Guarded::Free);
        }
        let bx = &self.boxes[i];
        let inside = target.clamp(bx.lo, bx.hi);
        let (p, how) = if self.reach.within(i, inside, committed, self.prox) {
            counts.skipped += 1;
            debug_assert!(
                self.reach.in_reach(i, inside)
                    || constrain(i, inside, committed, bx, self.prox) == (inside, Guarded::Free),
                "vertex {i}: a move past its reach let through is one the full check finds free"
            );
            let how = if inside == target {
                Guarded::Free
            } else {
                Guarded::Projected
            };
            (inside, how)
        } else if let Some(near) = self.reach.project(i, target, committed, bx, self.prox) {
            debug_assert_eq!(
                near,
                constrain(i, target, committed, bx, self.prox),
                "vertex {i}: the projection against the pairs it can reach is the full one"
            );
            near
        } else {
            constrain(i, target, committed, bx, self.prox)
        };
        self.reach.note(i, p, self.prox);
        match how {
            Guarded::Free => {}
            Guarded::Projected => counts.projected += 1,
            Guarded::Shortened => counts.shortened += 1,
        }
        (p, how)
    }
}

/// Where `prev` goes for a vertex that began the substep at `start` and ended it at `p`:
/// contact moved `prev` out with the vertex by the push it gave to a penetration that was
/// already there (`prev - start`), so that the push is no velocity; of that shift only as
/// much is kept as the vertex really moved that way, or a vertex held still would keep a
/// speed it never had.
pub(super) fn credited(prev: Vec3, start: Vec3, p: Vec3) -> Vec3 {
    let shift = prev - start;
    let len = shift.length();
    if len > 0.0 {
        let dir = shift / len;
        start + dir * (p - start).dot(dir).clamp(0.0, len)
    } else {
        start
    }
}
