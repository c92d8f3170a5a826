//! A seam's two sides' lengths in the pattern, as the seam list shows them. Once a pair
//! welds, its vertex is on both sides, and a seam edge between two welded vertices is
//! held by a triangle of each side, each with its own rest length. A side's own
//! triangles are told apart by their rest places: along a side each edge starts where
//! the one before it ended; where none does (a weld collapsed a stretch of the side into
//! one vertex, or the side's triangles do not hold the edge), the walk goes straight on
//! to the next vertex's place nearest it (the stretch counted in). An edge that starts
//! elsewhere may be the other side's, on the same piece (a tube, a dart).

use std::collections::HashSet;

use glam::{Vec2, Vec3};

use super::document::Design;
use super::parts::Seam;

impl Design {
    /// Each seam's two sides' pattern lengths (the A side's vertices, then the B side's,
    /// each in order without repeats), m, each side measured on its own triangles, also
    /// once pairs have welded. (Read from whichever triangle held an edge first, a
    /// welded side took the other side's lengths, and lost any stretch a weld had
    /// collapsed into one vertex: the dress's 140 mm shoulder read 117 / 117 mm once
    /// sewn.) A side is walked from a vertex only it has; when every
    /// pair has welded there is none, and the A side starts from its first vertex's place
    /// that comes first by x, then z, the B side from another.
    pub fn seam_lengths(&self, seam: &Seam) -> (f32, f32) {
        let path = |pick: fn(&(u32, u32)) -> u32| {
            let mut p: Vec<u32> = seam.pairs.iter().map(pick).collect();
            p.dedup();
            p
        };
        let (a, b) = (path(|p| p.0), path(|p| p.1));
        if seam.pairs.iter().all(|(p, q)| p != q) {
            return (self.pattern_length(&a), self.pattern_length(&b));
        }
        let (la, used) = self.side_length(&a, &b, &[]);
        let (lb, _) = self.side_length(&b, &a, &used);
        (la, lb)
    }

    /// The distinct rest places of vertex `v` (one per side it is on, more where a weld
    /// collapsed a stretch into it), in x, then z order.
    fn rest_places(&self, v: u32) -> Vec<Vec3> {
        let live = &self.sim.cloth.live;
        let mut p: Vec<Vec3> = live
            .tris_of(v)
            .iter()
            .filter_map(|&t| live.tri(t))
            .filter_map(|t| Some(t.rest[t.corner(v)?]))
            .collect();
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.z.total_cmp(&b.z)));
        p.dedup();
        p
    }

    /// The rest places of edge `(u, v)`'s ends in each triangle that holds it.
    fn edge_places(&self, u: u32, v: u32) -> Vec<(Vec3, Vec3)> {
        let live = &self.sim.cloth.live;
        live.tris_of(u)
            .iter()
            .filter_map(|&t| live.tri(t))
            .filter_map(|t| Some((t.rest[t.corner(u)?], t.rest[t.corner(v)?])))
            .collect()
    }

    /// A side's length along `path`, walked from a vertex the `other` side does not
    /// have (else from the first vertex's first place not `taken`), and the places it
    /// went through.
    fn side_length(&self, path: &[u32], other: &[u32], taken: &[Vec3]) -> (f32, Vec<Vec3>) {
        let shared: HashSet<u32> = other.iter().copied().collect();
        let start = path
            .iter()
            .enumerate()
            .find_map(|(k, &v)| match self.rest_places(v)[..] {
                [p] if !shared.contains(&v) => Some((k, p)),
                _ => None,
            });
        // Pieces can lie side by side in the pattern plane, a seam's two sides 50 mm
        // apart: the walk stays on its start's piece.
        let piece = |p: Vec3| self.record_at(Vec2::new(p.x, -p.z));
        let Some((k0, p0)) = start.or_else(|| {
            let places = self.rest_places(*path.first()?);
            // A place on a piece every vertex of the side has one on: a cut sewn up
            // has both sides on one piece, and its end vertex, on another seam too, a
            // place on the piece across that seam, where this side does not run.
            let mut common: Option<HashSet<Option<usize>>> = None;
            for &v in path {
                let on: HashSet<Option<usize>> =
                    self.rest_places(v).into_iter().map(piece).collect();
                common = Some(match common {
                    Some(c) => c.intersection(&on).copied().collect(),
                    None => on,
                });
            }
            let on_side = |p: &&Vec3| common.as_ref().is_none_or(|c| c.contains(&piece(**p)));
            // Of the second side's places, the one farthest from the next vertex: the
            // end of a stretch a weld collapsed into it (the nearer one left a dart's
            // second leg 4 mm short).
            let next: Vec<Vec3> = path.get(1).map_or(Vec::new(), |&v| self.rest_places(v));
            let reach = |p: &&Vec3| next.iter().map(|q| p.distance(*q)).fold(f32::MAX, f32::min);
            let free: Vec<&Vec3> = (places.iter())
                .filter(on_side)
                .filter(|p| !taken.contains(p))
                .collect();
            // Of those, the places an edge of the side's own triangles leads on from
            // to the next vertex, where any does: a set-in sleeve's armpit, welded to
            // the underarm seam too, has a place at each end of the cap, and the walk
            // from the far one jumped 335 mm across the sleeve (a 222 mm cap half read
            // 555 mm).
            let edges: Vec<(Vec3, Vec3)> = path
                .get(1)
                .map_or(Vec::new(), |&n| self.edge_places(path[0], n));
            let linked: Vec<&Vec3> = (free.iter().copied())
                .filter(|p| edges.iter().any(|(a, _)| a == *p))
                .collect();
            let free = if linked.is_empty() { free } else { linked };
            let far = (!taken.is_empty())
                .then(|| {
                    free.iter()
                        .copied()
                        .max_by(|a, b| reach(a).total_cmp(&reach(b)))
                })
                .flatten();
            let p = far
                .or_else(|| free.first().copied())
                .or_else(|| places.iter().find(on_side))
                .or_else(|| places.iter().find(|p| !taken.contains(p)))
                .or(places.first())?;
            Some((0, *p))
        }) else {
            return (self.pattern_length(path), Vec::new());
        };
        let own = piece(p0);
        let mut used = vec![p0];
        let mut len = 0.0;
        // Forward from the start, then back from it: each edge from the place nearest
        // to where the walk is.
        for forward in [true, false] {
            let mut at = p0;
            let edges: Vec<usize> = if forward {
                (k0..path.len().saturating_sub(1)).collect()
            } else {
                (0..k0).rev().collect()
            };
            for k in edges {
                let (u, v) = if forward {
                    (path[k], path[k + 1])
                } else {
                    (path[k + 1], path[k])
                };
                let next = || {
                    (self.rest_places(v).into_iter())
                        .filter(|&q| piece(q) == own)
                        .min_by(|x, y| x.distance(at).total_cmp(&y.distance(at)))
                };
                // An edge that does not start where the walk is may be the other
                // side's (both sides on one piece, a tube or a dart: this side's
                // triangles do not hold the edge where a weld collapsed a stretch):
                // straight on to the next vertex's nearest place instead.
                let nearest = (self.edge_places(u, v).into_iter())
                    .filter(|e| piece(e.0) == own)
                    .min_by(|x, y| x.0.distance(at).total_cmp(&y.0.distance(at)))
                    .filter(|e| e.0.distance(at) < 1e-5);
                let Some((from, to)) = nearest else {
                    // No triangle of this side holds the edge (its vertices are not
                    // neighbours on this side: a pair between them is open, its vertex
                    // left out of the path): straight on to the next vertex's place.
                    match next() {
                        Some(q) => {
                            len += at.distance(q);
                            used.push(q);
                            at = q;
                        }
                        None => len += self.pattern_length(&[u, v]),
                    }
                    continue;
                };
                len += at.distance(from) + from.distance(to);
                used.extend([from, to]);
                at = to;
            }
        }
        (len, used)
    }
}
