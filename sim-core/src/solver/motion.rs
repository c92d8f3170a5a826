//! Motion boxes: where each vertex can go until the next proximity search, for the
//! models whose contact is never crossed (vbd, and xpbd with its guard). A vertex's box
//! is its predicted path grown by how far it strayed from its path last time; a held
//! vertex's also covers the pen's path, a stitched one's a tenth of its stitch. The
//! search lists the pairs whose boxes come near, and the guard keeps each vertex in its
//! box, so pairs not listed cannot meet.

use glam::Vec3;

use crate::collision::proximity::Aabb;
use crate::solver::model::{Drive, Environment};
use crate::solver::state::Cloth;

/// How far a vertex may stray from its predicted path in a search's span at least, m.
pub const STRAY_MIN: f32 = 0.0005;
/// ... and at most (a vertex that strayed more last time gets up to this), m.
pub const STRAY_MAX: f32 = 0.02;
/// Held vertices may stray this far from the pen's predicted path, m.
pub const STRAY_HELD: f32 = 0.02;

/// Under the xpbd model's guard, as many fast vertices as this, and no more, still take
/// one search a frame ([`Motion::searches`]; vbd searches once a substep as soon as one
/// vertex is fast, its rule unmeasured against this one). The 2 x 8k dress, at rest but
/// for a few hundred vertices swinging at the shoulders (up to 0.3 m/s, the constraint pass and the strain limit at
/// odds there each substep), searched once a substep in most frames, each search an
/// update over its 150,000-400,000 pairs (docs/performance.md).
pub const FEW_FAST: usize = 64;

#[derive(Clone, Debug, Default)]
pub struct Motion {
    /// How far each vertex may stray from its predicted path, m.
    stray: Vec<f32>,
    predicted: Vec<Vec3>,
    /// Where the vertices were when the boxes were made.
    start: Vec<Vec3>,
    /// Index of each vertex in the pinch's held list (`u32::MAX`: not held).
    pub held: Vec<u32>,
    /// The pinch's target at the end of the last frame.
    pen_last: Option<Vec3>,
}

impl Motion {
    /// Room for `n` vertices (a new vertex may stray the least; the others keep theirs).
    pub fn resize(&mut self, n: usize) {
        self.stray.resize(n, STRAY_MIN);
        self.held.clear();
        self.held.resize(n, u32::MAX);
    }

    /// Searches a frame takes: one, or one per substep when more than `few` free vertices
    /// (xpbd's guard: [`FEW_FAST`]) are about to move more than half a mean edge. The
    /// motion boxes of a fast cloth are long, the boxes of neighbours in the pattern then
    /// overlap along the way, and each such pair becomes a no-crossing bound the guard
    /// must keep (a 128 x 128 cloth landing on the mannequin listed a million pairs a
    /// frame with one search, a tenth of that with one per substep); a cloth at rest needs
    /// only one, and so does one where a few vertices swing: their frame-long boxes add
    /// few pairs.
    pub fn searches(
        cloth: &Cloth,
        free: &[bool],
        mean_edge: f32,
        env: &Environment,
        substeps: usize,
        few: usize,
    ) -> usize {
        let t = env.frame_dt;
        let far = (0.5 * mean_edge).max(1e-4);
        let fast = (0..cloth.len())
            .filter(|&i| {
                free.get(i) == Some(&true)
                    && (cloth.v[i] * t + env.gravity * (0.5 * t * t)).length() > far
            })
            .take(few + 1)
            .count();
        if fast > few { substeps.max(1) } else { 1 }
    }

    /// The motion boxes for the next `t` seconds into `boxes` (one per vertex; a vertex
    /// that is not `free` gets the point where it is, and one in no triangle gets
    /// [`Aabb::EMPTY`], so the search leaves it out), and who is held.
    pub fn boxes(
        &mut self,
        boxes: &mut Vec<Aabb>,
        cloth: &Cloth,
        free: &[bool],
        env: &Environment,
        drive: &Drive<'_, '_>,
        t: f32,
    ) {
        let n = cloth.len();
        if self.stray.len() != n {
            self.resize(n);
        }
        boxes.clear();
        self.predicted.clear();
        for i in 0..n {
            let x = cloth.x[i];
            if free.get(i) != Some(&true) {
                // A pinned vertex is cloth the others must not cross; a vertex in no
                // triangle (the one a weld or the paper's sew merged away, what a tear
                // left of a corner) is not cloth at all. Kept as a point, it stood where
                // it was left as an obstacle: the dress's sewn shoulder lay draped over
                // the vertex its weld had merged away, the seam vertex held 1.5 cm up,
                // its sides at 4.6x their rest length for the rest of the drape.
                boxes.push(if cloth.live.vertex_alive(i as u32) {
                    Aabb::point(x)
                } else {
                    Aabb::EMPTY
                });
                self.predicted.push(Vec3::ZERO);
                continue;
            }
            let p = cloth.v[i] * t + env.gravity * (0.5 * t * t);
            self.predicted.push(p);
            boxes.push(Aabb::point(x).with(x + p).grown(self.stray[i]));
        }
        self.held.iter_mut().for_each(|h| *h = u32::MAX);
        if let Some(pinch) = &drive.grip.pinch {
            let pen_move = self.pen_last.map_or(Vec3::ZERO, |last| pinch.target - last);
            for (k, &(v, offset)) in pinch.held.iter().enumerate() {
                let v = v as usize;
                if v < n && free.get(v) == Some(&true) {
                    self.held[v] = k as u32;
                    let goal = pinch.target + offset;
                    boxes[v] =
                        boxes[v].union(Aabb::point(goal).with(goal + pen_move).grown(STRAY_HELD));
                }
            }
        }
        for s in drive.stitches {
            for (a, b) in [(s.a, s.b), (s.b, s.a)] {
                if let (Some(&xa), Some(&xb)) = (cloth.x.get(a as usize), cloth.x.get(b as usize)) {
                    // A stitch pulls its ends toward each other: room for a tenth of the way.
                    let reach = 0.1 * (xb - xa).length();
                    boxes[a as usize] = boxes[a as usize].grown(reach.min(STRAY_MAX));
                }
            }
        }
        for hd in drive.holds {
            if let Some(&x) = cloth.x.get(hd.vertex as usize) {
                // A hold pulls its vertex back to its plane: room for a tenth of the way.
                let reach = 0.1 * hd.past(x);
                let b = &mut boxes[hd.vertex as usize];
                *b = b.grown(reach.min(STRAY_MAX));
            }
        }
        self.start.clone_from(&cloth.x);
    }

    /// At the end of a search's span: how far each free vertex strayed from its
    /// predicted path over it, the room it gets next time.
    pub fn note_stray(&mut self, cloth: &Cloth, free: &[bool]) {
        let n = cloth.len().min(self.start.len()).min(self.stray.len());
        for i in 0..n {
            if free.get(i) != Some(&true) {
                continue;
            }
            let (a, p) = (self.start[i], self.predicted[i]);
            let d = cloth.x[i] - a;
            let s = if p.length_squared() > 0.0 {
                (d.dot(p) / p.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            self.stray[i] = (1.5 * (d - p * s).length() + STRAY_MIN).min(STRAY_MAX);
        }
    }

    /// At the frame's end: where the pen was.
    pub fn end_frame(&mut self, drive: &Drive<'_, '_>) {
        self.pen_last = drive.grip.pinch.as_ref().map(|p| p.target);
    }
}
