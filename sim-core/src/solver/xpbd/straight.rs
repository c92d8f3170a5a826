//! The straight rest distance between two vertices of a flat piece, where the straight
//! line between them stays on the cloth.
//!
//! The stretch limits' links were as long as the shortest path through the rest edges.
//! On a grid that is exact along its rows, columns and diagonals, where the lattice's
//! links run; on a pattern meshed with triangles that point every way (a garment's
//! pieces) an edge path zigzags and is several percent longer than the straight line, so
//! a link let the cloth stretch that much before it held: the shipped dress hung from
//! its shoulders with its threads 6% longer than cut (median), 11% at the shoulders
//! (docs/models.md). A piece's rest places lie in one plane, so where the straight
//! segment between two vertices crosses only the piece's own triangles, its length is
//! the rest distance through the cloth. Where it leaves the cloth (a notch, a slit, the
//! border) or crosses into triangles whose rest places are another chart (across a
//! welded seam or dart), there is no such segment, and the caller keeps the edge path,
//! which is never shorter than the geodesic: the link then never holds the cloth tighter
//! than its material would.
//!
//! The walk goes from triangle to triangle across the edges the segment crosses. A vertex
//! lying on the segment (on a grid, every vertex of a row) counts as lying just above it,
//! so the segment passes beside it through one triangle's edge, never through a corner.

use glam::Vec3;

use crate::mesh::live::{LiveMesh, NONE, Tri};

/// Rest places closer than this are the same place (m): the chart test across an edge.
const SAME_PLACE: f32 = 1e-5;

/// The most triangles a walk crosses before it gives up (a link reaches about nine
/// edges; a sliver-filled patch takes more triangles than edges).
const MAX_STEPS: usize = 400;

/// The length of the straight segment between `a` and `b` in the rest chart of `a`'s
/// first triangle, if that segment lies on triangles of that chart all the way; `None`
/// if it leaves them (or the rest places are not flat there).
pub(super) fn straight_rest(live: &LiveMesh, a: u32, b: u32) -> Option<f32> {
    let first = live.tris_of(a).iter().find_map(|&s| live.tri(s))?;
    let p = first.rest[first.corner(a)?];
    let normal = {
        let [r0, r1, r2] = first.rest;
        (r1 - r0).cross(r2 - r0).try_normalize()?
    };
    // b's place in the same chart: from a triangle of b whose plane is a's (checked on
    // arrival: the walk ends only in a triangle that has b at this place).
    let q = live.tris_of(b).iter().find_map(|&s| {
        let t = live.tri(s)?;
        let r = t.rest[t.corner(b)?];
        ((r - p).dot(normal).abs() <= SAME_PLACE).then_some(r)
    })?;
    let len = (q - p).length();
    if len <= SAME_PLACE {
        return None;
    }
    // The segment passes beside the vertices on it on one side, then on the other: along
    // a straight border only the inner side is on the cloth.
    [1.0f32, -1.0].into_iter().find_map(|side| {
        let x = (q - p) / len;
        let frame = Frame {
            p,
            x,
            y: normal.cross(x) * side,
            n: normal,
        };
        walk(live, &frame, (a, p), (b, q), len)
    })
}

/// The walk along `frame`'s x axis from `a` (at rest place `p`) to `b` (at `q`), `len`
/// apart: `Some(len)` if it stays on triangles of the chart.
fn walk(
    live: &LiveMesh,
    frame: &Frame,
    (a, p): (u32, Vec3),
    (b, q): (u32, Vec3),
    len: f32,
) -> Option<f32> {
    let tol = SAME_PLACE;
    // The first triangle: one round `a` in the chart that the segment enters.
    let (mut slot, mut at) = live.tris_of(a).iter().find_map(|&s| {
        let t = live.tri(s)?;
        if !frame.holds(t, a, p) {
            return None;
        }
        let (_, exit) = crossings(frame, t, None)?;
        (exit.1 > tol).then_some((s, exit))
    })?;
    for _ in 0..MAX_STEPS {
        let t = live.tri(slot)?;
        if at.1 >= len - tol {
            // The segment ends in this triangle: at b, if b is its corner at q.
            return frame.holds(t, b, q).then_some(len);
        }
        // Across the exit edge, into the triangle on its other side (none: the border).
        let (u, v) = at.0;
        let [s0, s1] = live.edge(u, v);
        let next = if s0 == slot { s1 } else { s0 };
        if next == NONE {
            return None;
        }
        let n = live.tri(next)?;
        let (pu, pv) = (t.rest[t.corner(u)?], t.rest[t.corner(v)?]);
        if !frame.holds(n, u, pu) || !frame.holds(n, v, pv) {
            return None;
        }
        let (entry, exit) = crossings(frame, n, Some((u, v)))?;
        if exit.1 < entry.1 - tol {
            return None;
        }
        slot = next;
        at = exit;
    }
    None
}

/// The segment's frame: origin at `a`'s rest place, `x` along the segment, `y` across it
/// in the chart's plane, `n` the plane's normal.
struct Frame {
    p: Vec3,
    x: Vec3,
    y: Vec3,
    n: Vec3,
}

impl Frame {
    /// A rest place's (along, across) coordinates, or `None` off the plane.
    fn coords(&self, r: Vec3) -> Option<(f32, f32)> {
        let d = r - self.p;
        (d.dot(self.n).abs() <= SAME_PLACE).then_some((d.dot(self.x), d.dot(self.y)))
    }

    /// Whether `t` has vertex `v` at rest place `r` and lies in the plane.
    fn holds(&self, t: &Tri, v: u32, r: Vec3) -> bool {
        t.corner(v)
            .is_some_and(|k| (t.rest[k] - r).length() <= SAME_PLACE)
            && t.rest.iter().all(|&c| self.coords(c).is_some())
    }
}

/// An edge the segment crosses, and how far along the segment it does.
type Crossing = ((u32, u32), f32);

/// Where the segment (just below the x axis: a corner on it counts as above) crosses
/// `t`'s edges: (entry, exit), the exit the crossing farther along, or the one that is not
/// `entered` (the edge the walk came in by). `None` if it does not cross two of them.
fn crossings(frame: &Frame, t: &Tri, entered: Option<(u32, u32)>) -> Option<(Crossing, Crossing)> {
    let c = [
        frame.coords(t.rest[0])?,
        frame.coords(t.rest[1])?,
        frame.coords(t.rest[2])?,
    ];
    let above = |k: usize| c[k].1 > -SAME_PLACE;
    let mut found: [Option<Crossing>; 2] = [None, None];
    let mut count = 0;
    for k in 0..3 {
        let j = (k + 1) % 3;
        if above(k) == above(j) {
            continue;
        }
        let (hi, lo) = if above(k) { (k, j) } else { (j, k) };
        let yh = c[hi].1.max(0.0);
        let along = c[hi].0 + (c[lo].0 - c[hi].0) * yh / (yh - c[lo].1);
        if count < 2 {
            found[count] = Some(((t.v[k], t.v[j]), along));
        }
        count += 1;
    }
    let (e0, e1) = (found[0]?, found[1]?);
    let same = |e: (u32, u32), f: (u32, u32)| e == f || e == (f.1, f.0);
    Some(match entered {
        Some(f) if same(e0.0, f) => (e0, e1),
        Some(f) if same(e1.0, f) => (e1, e0),
        Some(_) => return None,
        None if e0.1 <= e1.1 => (e0, e1),
        None => (e1, e0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;

    fn live(mesh: &ClothMesh) -> LiveMesh {
        LiveMesh::from_mesh(mesh)
    }

    #[test]
    fn along_a_grid_row_and_across_it_the_straight_line_is_the_distance() {
        let m = live(&ClothMesh::grid(0.8, 0.8, 8, 8, 0.0).unwrap());
        let at = |i: u32, j: u32| i * 9 + j;
        // Along a row: through vertices lying on the segment.
        let d = straight_rest(&m, at(2, 1), at(2, 7)).unwrap();
        assert!((d - 0.6).abs() < 1e-5, "{d}");
        // A knight's move, which no edge path follows: sqrt(0.1^2 + 0.2^2) per step.
        let d = straight_rest(&m, at(1, 1), at(5, 3)).unwrap();
        let want = (0.4f32 * 0.4 + 0.2 * 0.2).sqrt();
        assert!((d - want).abs() < 1e-5, "{d} against {want}");
        // Corner to corner, the whole cloth.
        let d = straight_rest(&m, at(0, 0), at(8, 8)).unwrap();
        assert!((d - 0.8 * 2f32.sqrt()).abs() < 1e-5, "{d}");
    }

    #[test]
    fn a_segment_that_leaves_the_cloth_has_no_straight_distance() {
        // A grid with a slit: the triangles touching column 4 between rows 2 and 6 on its
        // left are split from those on its right, as a cut leaves them.
        let mut m = live(&ClothMesh::grid(0.8, 0.8, 8, 8, 0.0).unwrap());
        let at = |i: u32, j: u32| i * 9 + j;
        let before = straight_rest(&m, at(4, 2), at(4, 6)).unwrap();
        assert!((before - 0.4).abs() < 1e-5);
        // Cut: every triangle right of column 4 in rows 1..=7 takes copies of the
        // column's vertices.
        let mut copies = std::collections::HashMap::new();
        let slots: Vec<u32> = m.iter().map(|(s, _)| s).collect();
        for s in slots {
            let t = *m.tri(s).unwrap();
            let right = t.v.iter().all(|&v| v % 9 >= 4) && t.v.iter().any(|&v| v % 9 > 4);
            let rows = t.v.iter().all(|&v| (1..=7).contains(&(v / 9)));
            if !(right && rows) {
                continue;
            }
            let mut n = t;
            for k in 0..3 {
                let v = t.v[k];
                if v % 9 == 4 && (2..=6).contains(&(v / 9)) {
                    let c = *copies.entry(v).or_insert_with(|| m.push_vertex());
                    n.v[k] = c;
                }
            }
            m.set(s, None).unwrap();
            m.set(s, Some(n)).unwrap();
        }
        // Across the slit: the straight line runs over it, through no triangle.
        assert_eq!(straight_rest(&m, at(4, 2), at(4, 6)), None);
        // Past its tip, beside the vertex the slit ends at, still straight; and along the
        // border.
        for (from, to) in [
            (at(1, 0), at(1, 8)),
            (at(8, 0), at(8, 8)),
            (at(0, 8), at(0, 0)),
        ] {
            let d = straight_rest(&m, from, to).unwrap();
            assert!((d - 0.8).abs() < 1e-5, "{d}");
        }
    }
}
