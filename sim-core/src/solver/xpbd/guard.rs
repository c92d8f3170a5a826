//! The XPBD model's contact that is never crossed: the vbd model's proximity search and
//! guard (`collision::proximity`) around XPBD's substeps.
//!
//! Once per frame (once per substep while the cloth moves fast) each vertex gets a motion
//! box and the search lists the pairs of primitives that can meet in it: cloth against
//! cloth, against the body's triangles, edges and corners, and against the floor. Every
//! substep, after XPBD's constraints and the body's contact planes, the pairs within the
//! contact distance are pushed apart to it (a position-based contact constraint with
//! Coulomb friction, one Gauss-Seidel pass), and then every vertex's move over the
//! substep passes the guard, which keeps it in its box and on its side of each pair, the
//! vertices before it having moved already. Each move keeps every pair apart (the guard's
//! set is convex and holds where the vertex was), so nothing crosses, at any speed.
//! A move the guard shortens loses the velocity it lost (an inelastic contact).

use glam::Vec3;

use super::guard_pass::{Counts, GUARD_PARALLEL_FROM, Moves, ONLY_PARALLEL_FROM, each};
use crate::collision::Body;
use crate::collision::proximity::{
    Aabb, Changed, ClothView, NONE, Pair, Proximity, ProximityParams, Reach, unique_edges,
};
use crate::mesh::{edge_ends, edge_key};
use crate::solver::model::{ContactStats, Drive, Environment};
use crate::solver::motion::{FEW_FAST, Motion};
use crate::solver::pinch::beating;
use crate::solver::state::Cloth;

/// The least separation every pair keeps, m.
const SEPARATION: f32 = 1e-4;
/// A search's boxes are the motion boxes grown by this much, m (or by a seventh of the
/// mean edge on a finer mesh), and its pairs serve the frames after it while every
/// vertex's motion box stays inside its searched box: a cloth at rest is searched once in
/// many frames. On a fine mesh 2 mm is a large part of an edge, so the boxes of
/// neighbours a few edges apart overlap and become pairs: a 128 x 128 cloth (7.8 mm
/// edges) at rest on the mannequin listed 700,000 cloth pairs with 2 mm, 65,000 with 1 mm.
/// (Sewn cloth kept 2 mm until the welds' leftover vertices stopped being obstacles: the
/// tighter boxes had stretched the 9 mm dress's worst side from 9x to 21-23x; since, they
/// do not, docs/collision.md.)
const REUSE_MARGIN: f32 = 0.002;
/// ... the part of the mean edge it is at most.
const REUSE_MARGIN_PER_EDGE: f32 = 1.0 / 7.0;
/// Searches that only look again where vertices left their boxes, between two full ones.
const MAX_UPDATES: usize = 16;
/// A search after one that took this long, µs, runs beside the pen's heartbeat
/// (`Drive::heartbeat`): 2 ms, a tenth of the haptic loop's staleness limit.
const SLOW_SEARCH_US: u64 = 2_000;

/// Whether [`Guard::respond`] pushes pair `q`: a cloth pair that carries energy. The
/// body's pairs are left to its contact planes: pushed by both along different normals at
/// the cube's rims, resting cloth jittered (2 cm/s).
fn pushes(q: &Pair) -> bool {
    q.energy && q.body_bound == f32::NEG_INFINITY
}

/// Lists in `pushed` every pair of `pairs` that [`Guard::respond`] pushes, in order.
fn list_pushed(pairs: &[Pair], pushed: &mut Vec<u32>) {
    pushed.clear();
    let each = pairs.iter().enumerate();
    pushed.extend(each.filter_map(|(k, q)| pushes(q).then_some(k as u32)));
}

/// The pushed pairs (in order) after an update that changed the list only where `ch`
/// says: the places it changed are looked at again, the others kept.
fn follow_pushed(pushed: &mut Vec<u32>, pairs: &[Pair], ch: &Changed, changed: &mut Vec<u32>) {
    changed.clear();
    changed.extend_from_slice(&ch.fresh);
    changed.extend(ch.relocated.iter().flat_map(|&(a, b)| [a, b]));
    changed.extend_from_slice(&ch.energy);
    changed.sort_unstable();
    changed.dedup();
    let len = pairs.len() as u32;
    pushed.retain(|&k| k < len && changed.binary_search(&k).is_err());
    let again = changed
        .iter()
        .filter(|&&k| k < len && pushes(&pairs[k as usize]));
    pushed.extend(again);
    pushed.sort_unstable();
    #[cfg(debug_assertions)]
    {
        let mut all = Vec::new();
        list_pushed(pairs, &mut all);
        debug_assert_eq!(*pushed, all, "the pushed pairs after an update");
    }
}

#[derive(Clone, Debug, Default)]
pub struct Guard {
    tris: Vec<[u32; 3]>,
    edges: Vec<[u32; 2]>,
    /// Each vertex's place in the pattern.
    pattern: Vec<Vec3>,
    /// Neighbours over a weld that the pattern places apart, for the exclusion distance
    /// `bridged_for` (NaN: to be worked out at the next search).
    bridged: Vec<Vec<u32>>,
    bridged_for: f32,
    free: Vec<bool>,
    mean_edge: f32,
    prox: Proximity,
    /// How far each vertex may move before its pairs need checking.
    reach: Reach,
    /// The cloth pairs that carry energy, which [`Guard::respond`] pushes apart (the
    /// body's are its contact planes').
    pushed: Vec<u32>,
    /// Scratch for [`follow_pushed`].
    pushed_scratch: Vec<u32>,
    /// The boxes the pairs were searched in: the guard keeps each vertex in its box.
    boxes: Vec<Aabb>,
    /// This frame's (or search span's) motion boxes.
    need: Vec<Aabb>,
    /// Which vertices' motion boxes left their searched boxes, and how many searches
    /// since the last full one only looked again where they did.
    moved: Vec<bool>,
    updates: usize,
    motion: Motion,
    /// Where the vertices are as the guard lets them move, during a pass.
    committed: Vec<Vec3>,
    /// The same for the second half's thread, during a pass on two.
    committed_b: Vec<Vec3>,
    /// A list of vertices split as [`Reach::order`] orders them.
    split: [Vec<u32>; 3],
    /// Vertices whose triangles, edges, place in the pattern or freedom an edit changed
    /// since the last search: their pairs are searched again at the next one, as if they
    /// had left their boxes ([`Guard::follow_edit`]).
    edited: Vec<bool>,
    pub stats: ContactStats,
    /// How long the last search or update took, µs.
    last_search_us: u64,
}

impl Guard {
    pub fn new(cloth: &Cloth) -> Self {
        let mut g = Self::default();
        g.rebuild(cloth);
        g
    }

    /// Follows the live mesh (after an edit): its triangles, edges and pattern; the pairs
    /// referred to the old mesh and are forgotten.
    pub fn rebuild(&mut self, cloth: &Cloth) {
        self.tris = cloth.live.triangles();
        self.edges = unique_edges(&self.tris);
        self.follow_mesh(cloth);
    }

    /// The rest of [`Guard::rebuild`], once the triangles and edges are the live mesh's.
    fn follow_mesh(&mut self, cloth: &Cloth) {
        let n = cloth.len();
        self.mean_edge = cloth.live.mean_rest_side();
        self.pattern = cloth.live.pattern_places(n);
        self.bridged_for = f32::NAN;
        self.refresh_free(cloth);
        self.motion.resize(n);
        self.prox.clear();
        self.reach.clear();
        self.pushed.clear();
        self.boxes.clear();
        self.edited.clear();
    }

    /// [`Guard::rebuild`] after an edit whose triangles' edges (old and new, sorted
    /// keys) are `touched`: the unique edges are the old list with those that went taken
    /// out and those that came put in, in the same order as a rebuild's, without sorting
    /// every edge again (1 ms of a 2 ms cut on 16k vertices).
    ///
    /// The pairs are kept: those of the vertices the edit touched (`verts`: the corners
    /// of every triangle it changed, before and after) are searched again at the next
    /// search, like those of vertices that left their boxes, so the frame after an edit
    /// updates the pairs instead of searching the whole cloth again (60-100 ms on the
    /// 16k-vertex drape). A vertex an edit moved is outside its box, and so searched
    /// again too.
    pub fn follow_edit(&mut self, cloth: &Cloth, touched: &[u64], verts: &[u32]) {
        let live = &cloth.live;
        let here = |k: u64| {
            let (a, b) = edge_ends(k);
            live.edge(a, b).iter().any(|&t| live.tri(t).is_some())
        };
        let mut edges = Vec::with_capacity(self.edges.len() + touched.len());
        let mut sorted = touched.to_vec();
        if !touched.is_sorted() {
            sorted.sort_unstable();
        }
        sorted.dedup();
        let mut t = sorted.into_iter().peekable();
        for k in self.edges.iter().map(|&[a, b]| edge_key(a, b)) {
            while let Some(&n) = t.peek().filter(|&&n| n < k) {
                if here(n) {
                    edges.push(n);
                }
                t.next();
            }
            if t.peek() == Some(&k) {
                t.next();
                if !here(k) {
                    continue;
                }
            }
            edges.push(k);
        }
        edges.extend(t.filter(|&n| here(n)));
        self.tris = live.triangles();
        self.edges = edges
            .into_iter()
            .map(|k| {
                let (a, b) = edge_ends(k);
                [a, b]
            })
            .collect();
        debug_assert_eq!(self.edges, unique_edges(&self.tris));
        let n = cloth.len();
        let mean_edge = cloth.live.mean_rest_side();
        // A mean edge that changed sets other margins and exclusions: search in full.
        if self.boxes.is_empty() || (mean_edge - self.mean_edge).abs() > 0.02 * self.mean_edge {
            return self.follow_mesh(cloth);
        }
        let old_n = self.free.len();
        let (old_free, old_pattern) = (
            std::mem::take(&mut self.free),
            std::mem::take(&mut self.pattern),
        );
        self.pattern = cloth.live.pattern_places(n);
        self.refresh_free(cloth);
        self.motion.resize(n);
        self.bridged_for = f32::NAN;
        // New vertices are edited too.
        self.edited.resize(old_n.min(n), false);
        self.edited.resize(n, true);
        for &v in verts.iter().filter(|&&v| (v as usize) < n) {
            self.edited[v as usize] = true;
        }
        for i in 0..n.min(old_n) {
            if old_free[i] != self.free[i] || old_pattern.get(i) != self.pattern.get(i) {
                self.edited[i] = true;
            }
        }
        // New vertices have no box yet (so they are searched); gone ones take their
        // pairs with them at the next search, which follows every edit before any pair
        // is used (`Proximity::follow_mesh`: the pass over every pair cost 1.5 ms of an
        // undo on 16k vertices).
        self.boxes.resize(n, Aabb::EMPTY);
        self.pushed.clear();
    }

    /// Each vertex's neighbours over a weld for the exclusion distance `exclusion`,
    /// worked out again when it or the mesh changed; after an edit, a vertex whose
    /// neighbours changed is edited too.
    fn follow_bridges(&mut self, cloth: &Cloth, exclusion: f32) {
        if self.bridged_for == exclusion {
            return;
        }
        let bridged = cloth
            .live
            .bridged_neighbours(cloth.len(), &self.pattern, exclusion);
        if self.bridged_for.is_nan() && !self.boxes.is_empty() {
            self.edited.resize(bridged.len(), false);
            for (i, b) in bridged.iter().enumerate() {
                if self.bridged.get(i) != Some(b) {
                    self.edited[i] = true;
                }
            }
        }
        self.bridged = bridged;
        self.bridged_for = exclusion;
    }

    pub fn refresh_free(&mut self, cloth: &Cloth) {
        self.free = (0..cloth.len())
            .map(|i| cloth.inv_mass[i] > 0.0 && cloth.live.vertex_alive(i as u32))
            .collect();
    }

    /// Searches this frame takes ([`Motion::searches`]).
    pub fn searches(&self, cloth: &Cloth, env: &Environment, substeps: usize) -> usize {
        Motion::searches(cloth, &self.free, self.mean_edge, env, substeps, FEW_FAST)
    }

    /// The pairs for the next `span` seconds, searched with `thickness` on `threads`
    /// ([`Guard::motion_boxes`], then [`Guard::search_boxes`]) before substep `k` of `n`;
    /// after a slow search, on a thread of its own beside the pen's heartbeat
    /// ([`Drive::heartbeat`]).
    pub fn search(
        &mut self,
        cloth: &Cloth,
        body: Option<&Body>,
        env: &Environment,
        drive: &mut Drive<'_, '_>,
        (span, thickness, threads): (f32, f32, usize),
        (k, n): (usize, usize),
    ) {
        self.motion_boxes(cloth, env, drive, span, thickness);
        let slow = self.slow_search();
        let mut search = || self.search_boxes(cloth, body, env, thickness, threads);
        match drive.heartbeat.filter(|_| slow) {
            Some(every) => {
                let (grip, pen) = (&*drive.grip, &mut *drive.pen);
                beating(search, || grip.heartbeat((k, n), pen, cloth, body), every);
            }
            None => search(),
        }
    }

    /// Each vertex's motion box for the next `span` seconds (the pen's, the stitches' and
    /// the holds' pulls in `drive`), the first half of a search; [`Guard::search_boxes`]
    /// the second, which needs nothing of `drive` and so can run on another thread.
    pub fn motion_boxes(
        &mut self,
        cloth: &Cloth,
        env: &Environment,
        drive: &Drive<'_, '_>,
        span: f32,
        thickness: f32,
    ) {
        if self.free.len() != cloth.len() {
            self.rebuild(cloth);
        }
        self.follow_bridges(cloth, self.exclusion(thickness));
        self.motion
            .boxes(&mut self.need, cloth, &self.free, env, drive, span);
    }

    /// Neighbours nearer than this in the pattern carry no energy.
    fn exclusion(&self, thickness: f32) -> f32 {
        2.0 * thickness + 2.0 * self.mean_edge
    }

    /// Whether the last search (or update) took long enough that the pen should hear
    /// from the frame while the next one runs ([`SLOW_SEARCH_US`]).
    pub fn slow_search(&self) -> bool {
        self.last_search_us >= SLOW_SEARCH_US
    }

    /// The pairs for the motion boxes of [`Guard::motion_boxes`]: a search (or an update
    /// where vertices left their boxes) unless the last one's boxes hold them all.
    pub fn search_boxes(
        &mut self,
        cloth: &Cloth,
        body: Option<&Body>,
        env: &Environment,
        thickness: f32,
        threads: usize,
    ) {
        let exclusion = self.exclusion(thickness);
        let inside = |a: &Aabb, b: &Aabb| b.lo.cmple(a.lo).all() && a.hi.cmple(b.hi).all();
        let margin = REUSE_MARGIN.min(REUSE_MARGIN_PER_EDGE * self.mean_edge);
        let searched = self.boxes.len() == self.need.len();
        self.moved.clear();
        if searched {
            let boxes = self.need.iter().zip(&self.boxes);
            self.moved.extend(boxes.map(|(a, b)| !inside(a, b)));
            for (m, &e) in self.moved.iter_mut().zip(&self.edited) {
                *m |= e;
            }
        }
        let after_edit = self.edited.contains(&true);
        self.edited.clear();
        if searched && !self.moved.contains(&true) {
            self.stats.reused += 1;
            return;
        }
        // Some vertices left their boxes: they get new ones, and so do those whose boxes
        // have grown loose around their motion (a box from when they moved fast), and only
        // their pairs are searched again (`Proximity::update`). When many do, or after
        // many such updates, a full search gives every vertex a box as tight as its
        // motion. (Renewing the vertices about to leave their boxes too, to update less
        // often, renewed ten times as many and cost as much as a full search.)
        for (i, m) in self.moved.iter_mut().enumerate() {
            let (need, had) = (&self.need[i], &self.boxes[i]);
            *m = *m || !inside(had, &need.grown(4.0 * margin));
        }
        let renewed = self.moved.iter().filter(|&&m| m).count();
        let partial = searched && renewed * 4 <= self.need.len() && self.updates < MAX_UPDATES;
        let grow = |(b, &f): (&Aabb, &bool)| if f { b.grown(margin) } else { *b };
        if partial {
            for i in 0..self.need.len() {
                if self.moved[i] {
                    self.boxes[i] = grow((&self.need[i], &self.free[i]));
                }
            }
            self.updates += 1;
        } else {
            self.boxes.clear();
            self.boxes
                .extend(self.need.iter().zip(&self.free).map(grow));
            self.updates = 0;
        }
        let params = ProximityParams {
            radius: thickness,
            delta: SEPARATION,
            rest_exclusion: exclusion,
            floor: env.floor,
            threads,
        };
        let t0 = std::time::Instant::now();
        // Each vertex's reach and the pairs that push, worked out as soon as the pairs
        // are final (meanwhile the search indexes them, on two threads).
        let (reach, pushed, x) = (&mut self.reach, &mut self.pushed, &cloth.x[..]);
        let after = move |pairs: &[Pair]| {
            reach.compute(pairs, x);
            list_pushed(pairs, pushed);
        };
        let view = ClothView {
            x: &cloth.x,
            boxes: &self.boxes,
            tris: &self.tris,
            edges: &self.edges,
            pattern: &self.pattern,
            bridged: &self.bridged,
            free: &self.free,
        };
        if partial {
            if after_edit {
                // The mesh is another: the search is taken as of it (the edited
                // vertices are among the moved; the trees are refitted to the new
                // lists, or built again for one of another length).
                self.prox.follow_mesh(&view);
            }
            if self.prox.update(&view, body, &params, &self.moved, after) {
                let ch = self.prox.changed();
                // Each vertex's reach worked out again (anchored where every vertex
                // stands now, every room as wide as it now is), and the pushed pairs
                // followed where the update changed them (listed again after an edit).
                let pairs = &self.prox.pairs;
                self.reach.compute_on(pairs, &cloth.x, threads);
                if after_edit {
                    // An edit let the pushed list go (and may have moved pairs).
                    list_pushed(pairs, &mut self.pushed);
                } else {
                    follow_pushed(&mut self.pushed, pairs, ch, &mut self.pushed_scratch);
                }
            }
            self.stats.updates += 1;
            #[cfg(debug_assertions)]
            if after_edit {
                let mut full = Proximity::default();
                full.detect(&view, body, &params);
                debug_assert!(
                    self.prox.same_pairs_of(&full, &self.moved),
                    "the update after an edit found other pairs than a full search"
                );
            }
        } else {
            self.prox.detect_with(&view, body, &params, after);
            self.stats.searches += 1;
        }
        self.stats.pairs = self.prox.counts;
        self.last_search_us = t0.elapsed().as_micros() as u64;
        self.stats.detect_us += self.last_search_us;
    }

    /// Starts a frame's counts (the pairs' counts stay those of the last search).
    pub fn begin_frame(&mut self) {
        self.stats = ContactStats {
            pairs: self.prox.counts,
            ..ContactStats::default()
        };
    }

    /// At the end of a search's span: how far each vertex strayed, the room it gets
    /// next time.
    pub fn note_stray(&mut self, cloth: &Cloth) {
        self.motion.note_stray(cloth, &self.free);
    }

    /// At the frame's end: where the pen was.
    pub fn end_frame(&mut self, drive: &Drive<'_, '_>) {
        self.motion.end_frame(drive);
    }

    /// One Gauss-Seidel pass of cloth-cloth contact over the pairs that carry energy: each closer than
    /// `radius` is pushed apart to it along its direction, and its sliding over the
    /// substep (from `prev`) is held back by Coulomb friction on that push. A vertex on
    /// the floor (`floor`'s height plus `radius`) is not pushed into it.
    pub fn respond(
        &self,
        x: &mut [Vec3],
        prev: &mut [Vec3],
        inv_mass: &[f32],
        radius: f32,
        friction: f32,
        floor: Option<f32>,
    ) {
        for &k in &self.pushed {
            let pair = &self.prox.pairs[k as usize];
            let c = pair.gap(x) - radius;
            if c >= 0.0 {
                continue;
            }
            // A vertex lying on the floor that the push would press into it does not give
            // way: the pair's other side takes the whole push. Given half, it was pushed
            // back up by the floor's plane the next substep, a fight that in a stack of
            // layers never settled and slid the cloth along the floor (the fold scenario
            // crept at 3 cm/s, 2.2e-4 J after 1,200 frames; now 2e-5 J).
            let w_of = |k: usize, v: usize| match floor {
                Some(f) if x[v].y < f + radius + 1.0e-4 && pair.n.y * pair.w[k] < 0.0 => 0.0,
                _ => inv_mass[v],
            };
            let mut im = [0.0f32; 4];
            let mut wsum = 0.0;
            for k in 0..4 {
                if pair.v[k] != NONE {
                    im[k] = w_of(k, pair.v[k] as usize);
                    wsum += im[k] * pair.w[k] * pair.w[k];
                }
            }
            if wsum <= 0.0 {
                continue;
            }
            let lambda = -c / wsum;
            // What was already closer than `radius` at the substep's start is pushed out
            // without becoming velocity (as the body's contact planes do): resting layers
            // must not be thrown apart.
            let c_prev = pair.gap(prev) - radius;
            let lambda_prev = if c_prev < 0.0 {
                -c_prev.max(c) / wsum
            } else {
                0.0
            };
            let mut u = Vec3::ZERO;
            for k in 0..4 {
                if pair.v[k] != NONE {
                    let v = pair.v[k] as usize;
                    let dir = pair.n * (im[k] * pair.w[k]);
                    x[v] += dir * lambda;
                    prev[v] += dir * lambda_prev;
                    u += (x[v] - prev[v]) * pair.w[k];
                }
            }
            if friction <= 0.0 {
                continue;
            }
            let ut = u - pair.n * pair.n.dot(u);
            let len = ut.length();
            if len <= 0.0 {
                continue;
            }
            // Static within the cone (the whole slide undone), kinetic beyond it.
            let share = (friction * -c / len).min(1.0) / wsum;
            for k in 0..4 {
                if pair.v[k] != NONE {
                    let v = pair.v[k] as usize;
                    x[v] -= ut * (im[k] * pair.w[k] * share);
                }
            }
        }
    }

    /// Notes where the substep starts: every pair holds there.
    pub fn begin_substep(&mut self, x: &[Vec3]) {
        self.committed.clear();
        self.committed.extend_from_slice(x);
        // What moved since the last pass outside the guard (the pen's grip, a pinned
        // vertex) may have left its reach.
        for (i, &p) in x.iter().enumerate() {
            self.reach.note(i, p, &self.prox);
        }
    }

    /// Passes every vertex's move of the substep (from where [`Guard::begin_substep`]
    /// saw it to `x`) through the guard, each against the others as they stand, in the
    /// order of [`Reach::order`]: the two halves' own vertices (on two threads when
    /// `threads > 1` and the cloth has [`GUARD_PARALLEL_FROM`] vertices), then those
    /// whose pairs reach across; in vertex order before the first search. One thread or
    /// two, the order is the same and so is the cloth. A vertex the guard moved
    /// elsewhere takes its velocity from the move it made: contact shifted its `prev` by
    /// the push it gave (so the push does not become velocity), and of that shift only
    /// as much as the vertex really moved that way is kept, or a vertex held still would
    /// keep a speed it never had.
    pub fn enforce(&mut self, x: &mut [Vec3], prev: &mut [Vec3], threads: usize) {
        let n = x.len();
        if self.boxes.len() != n || self.committed.len() != n || prev.len() != n {
            return;
        }
        let moves = Moves::of(&self.free, &self.boxes, &self.reach, &self.prox);
        let committed = &mut self.committed[..];
        let targets = &*x;
        let mut counts = Counts::default();
        match moves.reach.order(n) {
            None => counts += moves.run(committed, targets, (prev, 0), 0..n),
            Some((mid, [first, second, rest])) => {
                let two = threads > 1 && n >= GUARD_PARALLEL_FROM;
                if two && !first.is_empty() && !second.is_empty() {
                    // The second half on its own copy of where the vertices stand: it
                    // reads and writes only its half's.
                    let theirs = &mut self.committed_b;
                    theirs.clear();
                    theirs.extend_from_slice(committed);
                    let (pa, pb) = prev.split_at_mut(mid);
                    let b = std::thread::scope(|s| {
                        let b = s.spawn(|| moves.run(theirs, targets, (pb, mid), each(second)));
                        counts += moves.run(committed, targets, (pa, 0), each(first));
                        b.join()
                    });
                    // A panic in the second half's thread is this one's.
                    counts += b.unwrap_or_else(|e| std::panic::resume_unwind(e));
                    committed[mid..].copy_from_slice(&theirs[mid..]);
                } else {
                    counts += moves.run(committed, targets, (&mut *prev, 0), each(first));
                    counts += moves.run(committed, targets, (&mut *prev, 0), each(second));
                }
                counts += moves.run(committed, targets, (prev, 0), each(rest));
            }
        }
        self.add(counts);
        x.copy_from_slice(&self.committed);
    }

    /// As [`Guard::enforce`] for the moves of `verts` alone, right after it: every other
    /// vertex is where that pass put it. These moves are the strain limit's, where the
    /// guard held a vertex back; they stay velocity, as the limit's moves before the
    /// guard do (with `prev` moved along, so that they did not, the drape-cube no longer
    /// settled: 2.8e-4 J after 300 frames against 9e-8).
    ///
    /// In the order of [`Reach::order`] as well (the halves' own vertices on two threads
    /// when each has [`ONLY_PARALLEL_FROM`] of them), or as listed before the first
    /// search.
    pub fn enforce_only(&mut self, x: &mut [Vec3], verts: &[u32], threads: usize) {
        let n = x.len();
        if self.boxes.len() != n || self.committed.len() != n {
            return;
        }
        let moves = Moves::of(&self.free, &self.boxes, &self.reach, &self.prox);
        let committed = &mut self.committed[..];
        let lists = &mut self.split;
        let mut counts = Counts::default();
        match moves.reach.split(verts, n, lists) {
            None => counts += moves.run_only(committed, (x, 0), verts),
            Some(mid) => {
                let [first, second, rest] = &*lists;
                let two = threads > 1 && n >= GUARD_PARALLEL_FROM;
                if two && first.len().min(second.len()) >= ONLY_PARALLEL_FROM {
                    let theirs = &mut self.committed_b;
                    theirs.clear();
                    theirs.extend_from_slice(committed);
                    let (xa, xb) = x.split_at_mut(mid);
                    let b = std::thread::scope(|s| {
                        let b = s.spawn(|| moves.run_only(theirs, (xb, mid), second));
                        counts += moves.run_only(committed, (xa, 0), first);
                        b.join()
                    });
                    counts += b.unwrap_or_else(|e| std::panic::resume_unwind(e));
                    committed[mid..].copy_from_slice(&theirs[mid..]);
                } else {
                    counts += moves.run_only(committed, (&mut *x, 0), first);
                    counts += moves.run_only(committed, (&mut *x, 0), second);
                }
                counts += moves.run_only(committed, (x, 0), rest);
            }
        }
        self.add(counts);
    }

    fn add(&mut self, c: Counts) {
        self.stats.skipped += c.skipped;
        self.stats.projected += c.projected;
        self.stats.shortened += c.shortened;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::Material;

    /// The guard searches once a frame while at most `FEW_FAST` vertices are fast, once a
    /// substep past that; vbd's rule (one fast vertex is enough) is its own test.
    #[test]
    fn a_few_fast_vertices_take_one_search_a_frame_and_more_one_a_substep() {
        let mesh = ClothMesh::grid(0.5, 0.5, 16, 16, 1.0).expect("grid");
        let mut cloth = Cloth::new(mesh, &Material::default()).expect("cloth");
        let guard = Guard::new(&cloth);
        let env = Environment::default();
        assert_eq!(guard.searches(&cloth, &env, 5), 1, "at rest");
        // 1 m/s: 1.7 cm in a frame, more than half of a 3.1 cm edge.
        for i in 0..FEW_FAST {
            cloth.v[i] = Vec3::new(0.0, -1.0, 0.0);
        }
        assert_eq!(guard.searches(&cloth, &env, 5), 1, "{FEW_FAST} fast");
        cloth.v[FEW_FAST] = Vec3::new(0.0, -1.0, 0.0);
        assert_eq!(guard.searches(&cloth, &env, 5), 5, "one more");
    }
}
