//! Scissors along a stroke on the cloth (the pen's path in 3D), cut exactly: the stroke
//! is taken to the cloth's surface and from there into the pattern, where its crossings
//! with the edges become vertices on it (as `trim.rs` makes them); the cloth is then
//! split along the chain of those vertices. Splitting the vertices nearest the stroke
//! instead (until 2026-11-30) cut along the mesh's edges: a staircase in the pattern out.

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;
use super::transaction::Batch;
use super::trim::{distance_to_segment, plane};
use crate::collision::obb::geometry::closest_point_on_triangle;
use crate::mesh::Tri;

/// How much further than the stroke moved a place may move in the pattern before the
/// stroke is taken to have crossed to another piece, m.
const RUN_JUMP_M: f32 = 0.005;

/// The longest stretch of a stroke off the cloth that a cut bridges, m.
const MAX_GAP_M: f32 = 0.05;

/// The angle from `a` to `b` counter-clockwise, in [0, 2 pi).
fn ccw(a: Vec2, b: Vec2) -> f32 {
    let t = a.perp_dot(b).atan2(a.dot(b));
    if t < 0.0 {
        t + std::f32::consts::TAU
    } else {
        t
    }
}

/// How far past a piece's band of the pattern plane a cut line is taken, so that it
/// starts beside the piece's border rather than on it, m.
const BAND_MARGIN_M: f32 = 0.001;

/// The part of segment `a`-`b` whose x lies within `lo..=hi` (`None`: none of it).
fn clip_to_band(a: Vec2, b: Vec2, lo: f32, hi: f32) -> Option<(Vec2, Vec2)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    if d.x.abs() < 1e-9 {
        if a.x < lo || a.x > hi {
            return None;
        }
    } else {
        let (u, w) = ((lo - a.x) / d.x, (hi - a.x) / d.x);
        t0 = t0.max(u.min(w));
        t1 = t1.min(u.max(w));
    }
    (t1 - t0 > 1e-6).then(|| (a + d * t0, a + d * t1))
}

/// Barycentric coordinates of `p` (on the triangle's plane) in triangle `a`, `b`, `c`;
/// the centre for a degenerate triangle.
fn barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (e0, e1, e2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (e2.dot(e0), e2.dot(e1));
    let den = d00 * d11 - d01 * d01;
    if den.abs() <= f32::EPSILON * d00 * d11 {
        return Vec3::splat(1.0 / 3.0);
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    Vec3::new(1.0 - v - w, v, w)
}

impl Design {
    /// Scissors: cuts the cloth along the polyline `points` (the pointer's path), as one
    /// undoable operation ("cut stroke"). Each run of the stroke within `radius` of the
    /// cloth and on one piece of its pattern is cut exactly along it there: the new
    /// borders follow the stroke, not the mesh's edges. A stroke that starts or ends on
    /// the cloth cuts a slit that ends there, closed. Returns how many vertices were
    /// split.
    pub fn cut_stroke(&mut self, points: &[Vec3], radius: f32) -> Result<usize, EditError> {
        if points.iter().any(|p| !p.is_finite()) || !(radius.is_finite() && radius > 0.0) {
            return Err(EditError::BadDirection);
        }
        self.check_editable()?;
        let runs = self.stroke_runs(points, radius);
        self.cut_runs(&runs, "cut stroke")
    }

    /// Scissors in the pattern: cuts the cloth along the straight line from `a` to `b`
    /// in the design's pattern plane (m), as one undoable operation ("cut line"), exactly
    /// along it on each piece it crosses (the line taken piece by piece, within each
    /// piece's band of the plane). A line from beside a piece to beside it cuts the piece
    /// in two; one that starts or ends on a piece cuts a slit. Returns how many vertices
    /// were split.
    pub fn cut_line(&mut self, a: Vec2, b: Vec2) -> Result<usize, EditError> {
        if !(a.is_finite() && b.is_finite()) || a.distance(b) < 1e-4 {
            return Err(EditError::BadValue {
                name: "cut line",
                rule: "two finite points at least 0.1 mm apart",
                value: format!("{a} to {b}"),
            });
        }
        self.check_editable()?;
        let runs: Vec<Vec<Vec2>> = if self.pieces.is_empty() {
            vec![vec![a, b]]
        } else {
            (self.pieces.iter())
                .filter_map(|r| {
                    let (lo, hi) = r.band();
                    clip_to_band(a, b, lo - BAND_MARGIN_M, hi + BAND_MARGIN_M)
                })
                .map(|(p, q)| vec![p, q])
                .collect()
        };
        self.cut_runs(&runs, "cut line").map_err(|e| match e {
            EditError::EmptyStroke => EditError::NothingOnPattern {
                what: "cloth along the line",
            },
            e => e,
        })
    }

    /// Splits the cloth along each run (pattern plane, one piece each) as one undoable
    /// operation named `what`; nothing changes unless a vertex is split.
    fn cut_runs(&mut self, runs: &[Vec<Vec2>], what: &'static str) -> Result<usize, EditError> {
        let mut applied = Vec::new();
        let mut batch = Batch::default();
        let mut splits = 0;
        for run in runs {
            let done = self
                .split_along(run, &mut applied, &mut batch)
                .and_then(|chain| self.ends_on_cloth(run, chain, &mut applied, &mut batch))
                .and_then(|chain| self.split_chain(&chain, run, &mut applied, &mut batch));
            match done {
                Ok(n) => splits += n,
                Err(e) => {
                    self.abandon_batch(&applied, batch);
                    return Err(e);
                }
            }
        }
        if splits == 0 {
            self.abandon_batch(&applied, batch);
            return Err(EditError::EmptyStroke);
        }
        self.record_batch(what, applied, batch);
        Ok(splits)
    }

    /// The stroke in the pattern: points every half `radius` along it, each within
    /// `radius` of the cloth taken to the nearest place on its surface and from there to
    /// the pattern plane, in runs on one piece each (a stretch off the cloth longer than
    /// [`MAX_GAP_M`], or a place that jumps across the pattern, ends a run; a shorter
    /// stretch is bridged straight in the pattern; runs of one point are dropped).
    fn stroke_runs(&self, points: &[Vec3], radius: f32) -> Vec<Vec<Vec2>> {
        let segments: Vec<(Vec3, Vec3)> = if points.len() == 1 {
            vec![(points[0], points[0])]
        } else {
            points.windows(2).map(|w| (w[0], w[1])).collect()
        };
        let near = self.vertices_near(points, radius);
        let mut runs: Vec<Vec<Vec2>> = Vec::new();
        let mut run: Vec<Vec2> = Vec::new();
        let mut last: Option<(Vec3, Vec2)> = None;
        for (p, q) in segments {
            let steps = ((q - p).length() / (radius * 0.5))
                .ceil()
                .clamp(1.0, 4096.0) as usize;
            for s in 0..=steps {
                let at = p.lerp(q, s as f32 / steps as f32);
                let Some(place) = self.surface_place(at, radius, &near) else {
                    // The pen off the cloth for a moment (it rides the surface with a
                    // lag): the run goes on across a short gap, ends at a long one.
                    if last.is_some_and(|(at0, _)| at.distance(at0) > MAX_GAP_M) {
                        runs.push(std::mem::take(&mut run));
                        last = None;
                    }
                    continue;
                };
                // Another piece (across a seam, whose sides lie apart in the pattern):
                // a place far further from the last than the stroke went.
                if let Some((at0, place0)) = last
                    && place.distance(place0) > 2.0 * at.distance(at0) + RUN_JUMP_M
                {
                    runs.push(std::mem::take(&mut run));
                }
                if run.last() != Some(&place) {
                    run.push(place);
                }
                last = Some((at, place));
            }
        }
        runs.push(run);
        runs.retain(|r| r.len() >= 2);
        runs
    }

    /// The live vertices that may be nearest a point within `radius` of the cloth's
    /// surface along the polyline `points`: those in its box grown by `radius` and the
    /// longest edge (a point that near a triangle is that near its corners), in order.
    /// The stroke looked for the nearest vertex among all the cloth's at every point it
    /// sampled: a third of a 20-cell stroke's time on 16k vertices.
    fn vertices_near(&self, points: &[Vec3], radius: f32) -> Vec<u32> {
        let cloth = &self.sim.cloth;
        let longest = (cloth.live.iter())
            .flat_map(|(_, t)| {
                t.edges()
                    .map(|(a, b, _)| cloth.x[a as usize].distance_squared(cloth.x[b as usize]))
            })
            .fold(0.0f32, f32::max)
            .sqrt();
        let grow = Vec3::splat(radius + longest);
        let lo = points.iter().fold(Vec3::INFINITY, |l, p| l.min(*p)) - grow;
        let hi = points.iter().fold(Vec3::NEG_INFINITY, |h, p| h.max(*p)) + grow;
        (0..cloth.len() as u32)
            .filter(|&v| {
                let x = cloth.x[v as usize];
                x.cmpge(lo).all() && x.cmple(hi).all() && cloth.live.vertex_alive(v)
            })
            .collect()
    }

    /// The place on the cloth's surface nearest `at` (among the triangles round the
    /// nearest vertex of `near` and its neighbours), if within `radius`: its place in the
    /// pattern.
    fn surface_place(&self, at: Vec3, radius: f32, near: &[u32]) -> Option<Vec2> {
        let cloth = &self.sim.cloth;
        let v = *near.iter().min_by(|&&a, &&b| {
            let d = |v: u32| cloth.x[v as usize].distance_squared(at);
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        })?;
        let mut best: Option<(f32, Vec2)> = None;
        for u in std::iter::once(v).chain(cloth.live.neighbours(v)) {
            for &slot in cloth.live.tris_of(u) {
                let Some(t) = cloth.live.tri(slot) else {
                    continue;
                };
                let [a, b, c] = t.v.map(|i| cloth.x[i as usize]);
                let (p, _) = closest_point_on_triangle(at, a, b, c);
                let d = p.distance_squared(at);
                if best.is_none_or(|(bd, ..)| d < bd) {
                    let w = barycentric(p, a, b, c);
                    let r = t.rest.map(plane);
                    best = Some((d, r[0] * w.x + r[1] * w.y + r[2] * w.z));
                }
            }
        }
        best.filter(|(d, _)| *d <= radius * radius)
            .map(|(_, place)| place)
    }

    /// Splits the cloth along `chain` (the vertices on the run's path, in order): at each
    /// vertex the triangles of its fan on this piece (its place in the pattern nearest
    /// the run) that lie right of the path get a new vertex; at the chain's ends, right
    /// of the path's line through it (as the paper's cut split them: for a stroke along
    /// x on a cloth facing up, the +z side). Consecutive vertices that are not neighbours are
    /// joined through the mesh first. Returns how many vertices were split.
    fn split_chain(
        &mut self,
        chain: &[u32],
        run: &[Vec2],
        applied: &mut Vec<Prim>,
        batch: &mut Batch,
    ) -> Result<usize, EditError> {
        let mut joined: Vec<u32> = Vec::new();
        for &v in chain {
            match joined.last() {
                Some(&u) if u != v && !self.sim.cloth.live.neighbours(u).contains(&v) => {
                    joined.extend(self.mesh_path(u, v, 8).into_iter().skip(1));
                }
                Some(&u) if u == v => {}
                _ => joined.push(v),
            }
        }
        joined.dedup();
        // Each vertex's place on this piece: the one nearest the run.
        let places: Vec<Option<Vec2>> = joined.iter().map(|&v| self.place_near(v, run)).collect();
        if joined.len() < 2 || places.iter().any(Option::is_none) {
            return Ok(0);
        }
        let places: Vec<Vec2> = places.into_iter().flatten().collect();
        let n = joined.len();
        // Whether each end lies inside the cloth, before the splits next to it put it on
        // the new border: not on the cloth's border, nor on a welded seam (a piece's
        // outline, where the vertex has a place on each side).
        let live = &self.sim.cloth.live;
        let inner = |v: u32| {
            let mut places = (live.tris_of(v).iter())
                .filter_map(|&slot| live.tri(slot))
                .filter_map(|t| Some(t.rest[t.corner(v)?]));
            let first = places.next();
            !live.is_boundary(v) && places.all(|p| Some(p) == first)
        };
        let inner_ends = (inner(joined[0]), inner(joined[n - 1]));
        let mut splits = 0;
        for k in 0..n {
            let (v, p) = (joined[k], places[k]);
            // A slit's end inside the cloth stays whole: split, it opened the slit on
            // to the vertex past it.
            if (k == 0 && inner_ends.0) || (k + 1 == n && inner_ends.1) {
                continue;
            }
            let fwd = if k + 1 < n {
                places[k + 1] - p
            } else {
                p - places[k - 1]
            };
            let back = if k > 0 { places[k - 1] - p } else { -fwd };
            if fwd.length_squared() < 1e-14 || back.length_squared() < 1e-14 {
                continue;
            }
            let turn = ccw(fwd, back);
            let live = &self.sim.cloth.live;
            let fan: Vec<(u32, Tri)> = (live.tris_of(v).iter())
                .filter_map(|&slot| live.tri(slot).map(|t| (slot, *t)))
                .collect();
            let on_piece = |t: &Tri| {
                t.corner(v)
                    .is_some_and(|c| plane(t.rest[c]).distance(p) < 1e-6)
            };
            let mut moving: Vec<(u32, Tri)> = fan
                .iter()
                .filter(|(_, t)| {
                    let mid = plane((t.rest[0] + t.rest[1] + t.rest[2]) / 3.0);
                    on_piece(t) && ccw(fwd, mid - p) > turn
                })
                .copied()
                .collect();
            // At an end on the outline, only those next to the cut, round to the
            // outline: split by the whole line through it, the end of a dart's second
            // leg (on the first leg's slit) opened a slit past it.
            let toward = match k {
                0 => Some((joined[1], fwd)),
                _ if k + 1 == n => Some((joined[k - 1], back)),
                _ => None,
            };
            if let Some((w, d)) = toward {
                let mine: Vec<(u32, Tri)> =
                    fan.iter().filter(|(_, t)| on_piece(t)).copied().collect();
                if let Some(side) = beside_cut(v, w, p, d, &moving, &mine) {
                    moving = side;
                }
            }
            if moving.is_empty() || moving.len() == fan.len() {
                continue;
            }
            let prims = self.split_off_prims(v, &moving)?;
            self.apply_unsynced(&prims, batch)?;
            applied.extend(prims);
            splits += 1;
        }
        Ok(splits)
    }

    /// `chain` (the vertices a run's crossings made) with a vertex made where the run
    /// starts or ends on the cloth, exactly there ([`Design::vertex_at`]): the slit a
    /// run that ends on the cloth makes ends where it was drawn.
    fn ends_on_cloth(
        &mut self,
        run: &[Vec2],
        mut chain: Vec<u32>,
        applied: &mut Vec<Prim>,
        batch: &mut Batch,
    ) -> Result<Vec<u32>, EditError> {
        let (Some(&first), Some(&last)) = (run.first(), run.last()) else {
            return Ok(chain);
        };
        if let Some(v) = self.vertex_at(first, applied, batch)?
            && chain.first() != Some(&v)
        {
            chain.insert(0, v);
        }
        if let Some(v) = self.vertex_at(last, applied, batch)?
            && chain.last() != Some(&v)
        {
            chain.push(v);
        }
        Ok(chain)
    }

    /// Vertex `v`'s place in the pattern nearest the polyline `run` (a vertex on a seam
    /// has one on each piece).
    fn place_near(&self, v: u32, run: &[Vec2]) -> Option<Vec2> {
        let live = &self.sim.cloth.live;
        let dist = |q: Vec2| {
            run.windows(2)
                .map(|w| distance_to_segment(q, (w[0], w[1])))
                .fold(f32::MAX, f32::min)
        };
        (live.tris_of(v).iter())
            .filter_map(|&slot| {
                let t = live.tri(slot)?;
                Some(plane(t.rest[t.corner(v)?]))
            })
            .min_by(|a, b| dist(*a).total_cmp(&dist(*b)))
    }
}

/// The triangles of `mine` (vertex `v`'s on its piece, `v` placed at `p`) on one side
/// of a cut that ends at `v` on the outline, coming in from `w` (direction `d` from
/// `v`): from the triangle of `side` (that side by the line through `v`) whose middle
/// lies nearest `d`, round across the edges they share at `v` (not the cut's, to `w`)
/// to the outline. `None` when that goes all the way round.
fn beside_cut(
    v: u32,
    w: u32,
    p: Vec2,
    d: Vec2,
    side: &[(u32, Tri)],
    mine: &[(u32, Tri)],
) -> Option<Vec<(u32, Tri)>> {
    let angle = |t: &Tri| {
        let mid = plane((t.rest[0] + t.rest[1] + t.rest[2]) / 3.0);
        d.angle_to(mid - p).abs()
    };
    let start = side
        .iter()
        .min_by(|a, b| angle(&a.1).total_cmp(&angle(&b.1)))?;
    let mut joined = vec![*start];
    let mut k = 0;
    while k < joined.len() {
        let t = joined[k].1;
        for &(slot, u) in mine {
            let shares =
                t.v.iter()
                    .any(|&x| x != v && x != w && u.corner(x).is_some());
            if shares && !joined.iter().any(|(s, _)| *s == slot) {
                joined.push((slot, u));
            }
        }
        k += 1;
    }
    (joined.len() < mine.len()).then_some(joined)
}
