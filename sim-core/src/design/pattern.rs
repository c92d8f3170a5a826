//! Operations given on the pattern, as a designer selects in a 2D pattern view: delete a
//! rectangle of cloth, or seam two boundary paths drawn as segments (in UV space, or in
//! the design's pattern plane, where pieces added later never overlap).

use std::collections::{HashMap, HashSet, VecDeque};

use glam::Vec2;

use super::document::Design;
use super::error::EditError;
use super::parts::STITCH_PULL;
use crate::mesh::live::{LiveMesh, NONE};

impl Design {
    /// Where live vertex `v` sits on the pattern (the UV of its first triangle's corner).
    pub fn vertex_uv(&self, v: u32) -> Option<Vec2> {
        let live = &self.sim.cloth.live;
        live.tris_of(v)
            .iter()
            .filter_map(|&t| live.tri(t))
            .find_map(|t| t.corner(v).map(|k| t.uv[k]))
    }

    /// Removes the triangles whose UV centre lies in `[min, max]`. Undoable as one
    /// operation; refused when the rectangle holds none.
    pub fn remove_region(&mut self, min: Vec2, max: Vec2) -> Result<usize, EditError> {
        if !(min.is_finite() && max.is_finite()) {
            return Err(EditError::BadDirection);
        }
        let (lo, hi) = (min.min(max), min.max(max));
        let slots: Vec<u32> = self
            .sim
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                let c = (t.uv[0] + t.uv[1] + t.uv[2]) / 3.0;
                c.cmpge(lo).all() && c.cmple(hi).all()
            })
            .map(|(s, _)| s)
            .collect();
        if slots.is_empty() {
            return Err(EditError::NothingOnPattern { what: "triangle" });
        }
        self.remove_triangles(&slots)
    }

    /// The live border vertices within `tol` (UV) of segment `a -> b`, in order from `a`
    /// to `b` (see `path_near`).
    pub fn pattern_path(&self, a: Vec2, b: Vec2, tol: f32) -> Vec<u32> {
        self.path_on(a, b, tol, false, &HashSet::new())
    }

    /// [`Design::pattern_path`] in the design's pattern plane (its x and -z, m): what the
    /// studio's pattern view draws, where pieces never overlap (their UVs may).
    pub fn plane_path(&self, a: Vec2, b: Vec2, tol: f32) -> Vec<u32> {
        self.path_on(a, b, tol, true, &HashSet::new())
    }

    /// The border paths a seam along segments `a` and `b` joins, on the pattern plane
    /// (`plane`) or the UVs, as [`Design::plane_path`] or [`Design::pattern_path`] finds
    /// them; but where one runs along the other (more than their ends in common, or all
    /// but its ends at the other's places), the two sides of a cut, which the pattern
    /// draws on one line (a drag along the cut twice picks both sides, to sew a cut up
    /// again or a waist seam along it): the longer path and the vertices at its places,
    /// one to one, so that the welds close it as it was; or else the border on the
    /// second's line without the first's vertices.
    pub fn seam_sides(
        &self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
        plane: bool,
    ) -> (Vec<u32>, Vec<u32>) {
        let (pa, pb, _) = self.sides_of(a, b, tol, plane);
        (pa, pb)
    }

    /// [`Design::seam_sides`], and whether the second is the first's twins (to be paired
    /// one to one, not by arc length).
    fn sides_of(
        &self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
        plane: bool,
    ) -> (Vec<u32>, Vec<u32>, bool) {
        let pa = self.path_on(a[0], a[1], tol, plane, &HashSet::new());
        let pb = self.path_on(b[0], b[1], tol, plane, &HashSet::new());
        let inner = |v: &u32| {
            !((pa.first() == Some(v) && pb.first() == Some(v))
                || (pa.last() == Some(v) && pb.last() == Some(v)))
        };
        let overlaps = pb.iter().filter(|v| inner(v)).any(|v| pa.contains(v));
        if overlaps || self.lies_along(&pb, &pa, plane) || self.lies_along(&pa, &pb, plane) {
            // The longer drag's side and its twins, or the shorter's where a vertex of the
            // longer has none (it went round a corner).
            let order = if pb.len() > pa.len() {
                [&pb, &pa]
            } else {
                [&pa, &pb]
            };
            for side in order {
                let avoid: HashSet<u32> = side.iter().copied().collect();
                if let Some(twins) = self.twins(side, plane, &avoid) {
                    return (side.clone(), twins, true);
                }
            }
            if overlaps {
                let avoid: HashSet<u32> = pa.iter().copied().collect();
                let other = self.path_on(b[0], b[1], tol, plane, &avoid);
                if other.len() >= 2 {
                    return (pa, other, false);
                }
            }
        }
        (pa, pb, false)
    }

    /// Whether path `p` lies along path `q` on the pattern (`plane`) or the UVs: every
    /// vertex of `p` but its ends at one of the places of `q`'s.
    fn lies_along(&self, p: &[u32], q: &[u32], plane: bool) -> bool {
        let on_q: HashSet<[u32; 2]> = (q.iter())
            .flat_map(|&v| self.places_of(v, plane))
            .map(place_key)
            .collect();
        p.len() >= 3
            && p[1..p.len() - 1].iter().all(|&v| {
                (self.places_of(v, plane).into_iter()).any(|x| on_q.contains(&place_key(x)))
            })
    }

    /// Vertex `v`'s places on the pattern plane (`plane`: its x and -z) or its UVs.
    pub(super) fn places_of(&self, v: u32, plane: bool) -> Vec<Vec2> {
        if plane {
            vertex_places(self, v, |t, k| Vec2::new(t.rest[k].x, -t.rest[k].z))
        } else {
            vertex_places(self, v, |t, k| t.uv[k])
        }
    }

    /// For each vertex of `path`, another border vertex (none in `avoid`) at one of its
    /// places on the pattern plane (`plane`) or the UVs, in `path`'s order: the other
    /// side of a cut along it. `None` unless every vertex has one, each its own.
    fn twins(&self, path: &[u32], plane: bool, avoid: &HashSet<u32>) -> Option<Vec<u32>> {
        let live = &self.sim.cloth.live;
        let mut at: HashMap<[u32; 2], u32> = HashMap::new();
        for v in 0..self.sim.cloth.len() as u32 {
            if live.vertex_alive(v) && live.is_boundary(v) && !avoid.contains(&v) {
                for p in self.places_of(v, plane) {
                    at.entry(place_key(p)).or_insert(v);
                }
            }
        }
        // A slit's closed end (cut to a point on the cloth) is both sides' one vertex:
        // at an end of the path with no other there, it is its own twin.
        let n = path.len();
        let twins: Vec<u32> = (path.iter().enumerate())
            .map(|(k, &v)| {
                (self.places_of(v, plane).into_iter())
                    .find_map(|p| at.get(&place_key(p)).copied())
                    .or((k == 0 || k + 1 == n).then_some(v))
            })
            .collect::<Option<_>>()?;
        let distinct: HashSet<u32> = twins.iter().copied().collect();
        (distinct.len() == twins.len()).then_some(twins)
    }

    /// [`Design::plane_path`] (`plane`) or [`Design::pattern_path`], without the
    /// vertices in `avoid`.
    fn path_on(&self, a: Vec2, b: Vec2, tol: f32, plane: bool, avoid: &HashSet<u32>) -> Vec<u32> {
        self.path_near(a, b, tol, |v| {
            if avoid.contains(&v) {
                Vec::new()
            } else {
                self.places_of(v, plane)
            }
        })
    }

    /// The border vertices with a place (of those `places` gives) within `tol` of segment
    /// `a -> b`, in order from `a` to `b`: the border walked from the vertex at `a` to
    /// the one at `b` (`border_walk`), through those near the segment. (Sorted by how far
    /// along the segment they lie, as until 2026-12-03, a drag ending near a corner took
    /// the first vertex round it, along the next side, before the corner itself: a studio
    /// drag along a 40 x 50 cm rectangle's side at 3 cm edges was refused as "not an edge
    /// on the cloth's border"; and every vertex within `tol` of the start was left out, so
    /// a seam drawn from a corner left the corner open.) Where the border does not join
    /// them, in that sorted order, and the seam says which pair is not a border edge.
    fn path_near(&self, a: Vec2, b: Vec2, tol: f32, places: impl Fn(u32) -> Vec<Vec2>) -> Vec<u32> {
        let d = b - a;
        let len2 = d.length_squared();
        if len2 <= 0.0 || tol.is_nan() || tol <= 0.0 {
            return Vec::new();
        }
        let len = len2.sqrt();
        let live = &self.sim.cloth.live;
        // Each vertex near the segment: how far along it, and how far off its line.
        let near_of = |v: u32, p: Vec2| {
            let t = (p - a).dot(d) / len2;
            Near {
                v,
                along: t * len,
                off: (p - (a + d * t)).length(),
                ends: [(p - a).length(), (p - b).length()],
            }
        };
        let border: Vec<u32> = (0..self.sim.cloth.len() as u32)
            .filter(|&v| live.vertex_alive(v) && live.is_boundary(v))
            .collect();
        let mut near: Vec<Near> = (border.iter())
            .filter_map(|&v| {
                places(v).into_iter().find_map(|p| {
                    let t = (p - a).dot(d) / len2;
                    let dist = (p - (a + d * t.clamp(0.0, 1.0))).length();
                    (dist < tol && t * len > -tol && t <= 1.0 + tol / len).then(|| near_of(v, p))
                })
            })
            .collect();
        // A drag's end with no vertex within `tol` (on a curve a vertex may be half an
        // edge from where the designer let go: an ellipse's end at 3 cm edges): the
        // border vertex nearest it, within a quarter of the drag's length.
        for k in 0..2 {
            if near.iter().any(|n| n.ends[k] < tol) {
                continue;
            }
            let nearest = (border.iter())
                .flat_map(|&v| places(v).into_iter().map(move |p| near_of(v, p)))
                .filter(|n| n.ends[k] < 0.25 * len)
                .min_by(|x, y| x.ends[k].total_cmp(&y.ends[k]));
            if let Some(n) = nearest {
                near.retain(|m| m.v != n.v);
                near.push(n);
            }
        }
        // A curved border (a sleeve's cap, a neckline) leaves the drag's straight line:
        // its vertices within half the drag's length of it may carry the walk.
        let wide = |v: u32| {
            places(v).into_iter().any(|p| {
                let t = ((p - a).dot(d) / len2).clamp(0.0, 1.0);
                (p - (a + d * t)).length() < 0.5 * len + tol
            })
        };
        border_walk(live, &near, tol, &wide).unwrap_or_else(|| {
            let mut sorted: Vec<(f32, u32)> = near.iter().map(|n| (n.along, n.v)).collect();
            sorted.sort_by(|x, y| x.0.total_cmp(&y.0));
            sorted.into_iter().map(|(_, v)| v).collect()
        })
    }

    /// A seam between the border paths along two pattern segments (see
    /// [`Design::pattern_path`]); returns the stitched pairs.
    pub fn seam_on_pattern(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
    ) -> Result<usize, EditError> {
        self.seam_along(a, b, tol, false)
    }

    /// [`Design::seam_on_pattern`] with segments in the design's pattern plane (m), as
    /// the studio's pattern view draws it; returns the stitched pairs.
    pub fn seam_on_plane(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
    ) -> Result<usize, EditError> {
        self.seam_along(a, b, tol, true)
    }

    /// A seam between the border paths along segments `a` and `b`
    /// ([`Design::seam_sides`]).
    fn seam_along(
        &mut self,
        a: [Vec2; 2],
        b: [Vec2; 2],
        tol: f32,
        plane: bool,
    ) -> Result<usize, EditError> {
        seam_tolerance(tol)?;
        let (mut pa, mut pb, twins) = self.sides_of(a, b, tol, plane);
        // A dart's two sides meet at its point (or its ends): it is not stitched to itself.
        if !pa.is_empty() && pa.first() == pb.first() {
            pa.remove(0);
            pb.remove(0);
        }
        if !pa.is_empty() && pa.last() == pb.last() {
            pa.pop();
            pb.pop();
        }
        if pa.len() < 2 || pb.len() < 2 {
            return Err(EditError::NothingOnPattern {
                what: "border path of two or more vertices",
            });
        }
        let pull = self.pair_pull(&pa, &pb, STITCH_PULL);
        if twins {
            // Vertex to its twin: by arc length in 3D, where the two sides hang
            // differently, the pairs slipped a vertex and the welds left slits.
            let pairs: Vec<(u32, u32)> = pa.into_iter().zip(pb).collect();
            self.add_seam_pairs(&pairs, pull)
        } else {
            self.add_seam(&pa, &pb, pull)
        }
    }
}

/// A place on the pattern as exact bits (0 and -0 alike): a cut's two sides have their
/// vertices at the same places.
fn place_key(p: Vec2) -> [u32; 2] {
    (p + Vec2::ZERO).to_array().map(f32::to_bits)
}

/// Vertex `v`'s places in the pattern, one per triangle corner it has (`at` reads one).
fn vertex_places(d: &Design, v: u32, at: impl Fn(&crate::mesh::Tri, usize) -> Vec2) -> Vec<Vec2> {
    let live = &d.sim.cloth.live;
    live.tris_of(v)
        .iter()
        .filter_map(|&t| live.tri(t))
        .filter_map(|t| t.corner(v).map(|k| at(t, k)))
        .collect()
}

/// A seam's tolerance must be a positive distance.
fn seam_tolerance(tol: f32) -> Result<(), EditError> {
    if tol.is_finite() && tol > 0.0 {
        Ok(())
    } else {
        Err(EditError::BadValue {
            name: "seam tolerance",
            rule: "a positive distance on the pattern",
            value: tol.to_string(),
        })
    }
}

/// A border vertex near a drawn segment.
struct Near {
    v: u32,
    /// How far along the segment it lies (negative: before its start), m or UV.
    along: f32,
    /// How far off the segment's line.
    off: f32,
    /// Its distances to the segment's start and end.
    ends: [f32; 2],
}

/// The border path through `near` from its first vertex to its last, fewest edges first;
/// where the border does not join them through `near` alone (a curve that leaves the
/// segment's line by more than `tol`), through the vertices `wide` allows as well; `None`
/// when it does not join them there either. The first is the one furthest back within
/// `tol` of the segment's start, a vertex counted back only as far as it keeps to the line
/// (a corner just before the start, not the vertex round it); the last likewise at the
/// end; with none within `tol`, the nearest. (Through `near` alone, a drag from a sleeve
/// cap's top to its corner, 16 cm long and its cap 4 cm off that line, was refused as
/// "not an edge on the cloth's border": the cap's middle vertices were not near it.)
fn border_walk(
    live: &LiveMesh,
    near: &[Near],
    tol: f32,
    wide: &dyn Fn(u32) -> bool,
) -> Option<Vec<u32>> {
    let end = |k: usize, score: fn(&Near) -> f32| {
        let close = near.iter().filter(|n| n.ends[k] < tol);
        close
            .min_by(|x, y| score(x).total_cmp(&score(y)))
            .or_else(|| near.iter().min_by(|x, y| x.ends[k].total_cmp(&y.ends[k])))
            .map(|n| n.v)
    };
    let from = end(0, |n| n.along + 2.0 * n.off)?;
    let to = end(1, |n| -n.along + 2.0 * n.off)?;
    let along: HashSet<u32> = near.iter().map(|n| n.v).collect();
    let walk = |allowed: &dyn Fn(u32) -> bool| {
        let mut came: HashMap<u32, u32> = HashMap::from([(from, from)]);
        let mut queue = VecDeque::from([from]);
        while let Some(v) = queue.pop_front() {
            if v == to {
                break;
            }
            for u in live.neighbours(v) {
                let border = live.edge(v, u)[1] == NONE;
                if border && allowed(u) && !came.contains_key(&u) {
                    came.insert(u, v);
                    queue.push_back(u);
                }
            }
        }
        came.contains_key(&to).then_some(came)
    };
    let came =
        walk(&|u| along.contains(&u)).or_else(|| walk(&|u| along.contains(&u) || wide(u)))?;
    let mut path = vec![to];
    while let Some(&prev) = path.last().and_then(|v| came.get(v)) {
        if prev == *path.last()? {
            break;
        }
        path.push(prev);
    }
    path.reverse();
    Some(path)
}
