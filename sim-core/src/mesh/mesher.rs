//! Pattern pieces meshed as well-shaped triangles: an outline (an outer loop and any
//! holes, in metres in the pattern plane) is resampled so no boundary segment is longer
//! than the asked edge length, triangulated with the boundary as constraints (spade's
//! constrained Delaunay triangulation), then refined by Ruppert's method until no
//! triangle has an angle under [`MIN_ANGLE_DEG`] (except where the outline's own corner is
//! sharper) and none is much larger than an equilateral triangle of the edge length. The
//! boundary vertices lie on the outline, so the mesh's boundary is the outline.
//!
//! The piece lies in the XZ plane at height 0, its pattern's y along -Z, wound so its
//! normal points +Y like [`ClothMesh::grid`]; UVs are the pattern scaled by its larger
//! side (warp along u).

use glam::{Vec2, Vec3};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::ClothMesh;
use super::cloth_mesh::MAX_VERTICES;

/// The least triangle angle the refinement aims for, degrees (the refinement is proven
/// to end for limits up to about 34 degrees).
pub const MIN_ANGLE_DEG: f64 = 25.0;

/// The edge lengths a piece may be meshed with, m.
pub const EDGE_RANGE: (f32, f32) = (0.001, 0.5);

/// The most a pattern piece may span in either direction, m: a theatre curtain, not a
/// mistyped number. A sliver kilometres long (found by fuzzing, 2026-12-01) passed the
/// vertex estimate at a long edge and took the triangulation 20-25 s.
pub const MAX_SPAN: f32 = 10.0;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    #[error("an outline needs at least 3 points; loop {looped} has {points}")]
    TooFewPoints { looped: usize, points: usize },
    #[error("point {point} of loop {looped} is not a finite number")]
    NotFinite { looped: usize, point: usize },
    #[error("loop {looped} encloses no area")]
    NoArea { looped: usize },
    #[error(
        "the outline crosses itself: side {a} of loop {la} meets side {b} of loop {lb} (side k joins points k and k+1, counted from 0)"
    )]
    SelfIntersecting {
        la: usize,
        a: usize,
        lb: usize,
        b: usize,
    },
    #[error("edge length must be between 0.001 and 0.5 m, got {0}")]
    EdgeLength(f32),
    #[error("the piece would have {vertices} vertices, more than {max}: use a longer edge")]
    TooLarge { vertices: usize, max: usize },
    #[error(
        "the outline spans {0:.1} m, more than the {max} m a pattern piece may (another unit, or a damaged file?)",
        max = MAX_SPAN
    )]
    Span(f32),
    #[error("triangulation failed: {0}")]
    Triangulation(String),
    #[error(
        "the outline's sides meet in {0} places once divided into edges (a sliver, or corners on one line); widen it or move the points apart"
    )]
    SidesMeet(usize),
}

/// A piece's outline: the outer loop first, then holes, each a closed polygon (the last
/// point joins the first), metres.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Outline {
    pub loops: Vec<Vec<Vec2>>,
}

impl Outline {
    /// A `w` x `h` rectangle with its lower left corner at the origin.
    pub fn rectangle(w: f32, h: f32) -> Self {
        Self {
            loops: vec![vec![
                Vec2::ZERO,
                Vec2::new(w, 0.0),
                Vec2::new(w, h),
                Vec2::new(0.0, h),
            ]],
        }
    }

    /// An ellipse of semi-axes `rx`, `ry` centred at the origin, as a polygon whose
    /// sides are at most `edge` long.
    pub fn ellipse(rx: f32, ry: f32, edge: f32) -> Self {
        // Ramanujan's perimeter, then sides of at most `edge`.
        let (a, b) = (rx.abs(), ry.abs());
        let h = ((a - b) / (a + b).max(1e-9)).powi(2);
        let per =
            std::f32::consts::PI * (a + b) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()));
        let n = ((per / edge.max(1e-4)).ceil() as usize).clamp(8, 100_000);
        let pts = (0..n)
            .map(|k| {
                let t = k as f32 / n as f32 * std::f32::consts::TAU;
                Vec2::new(a * t.cos(), b * t.sin())
            })
            .collect();
        Self { loops: vec![pts] }
    }
}

/// Twice the signed area of closed polygon `l` (positive counter-clockwise).
pub fn signed_area2(l: &[Vec2]) -> f64 {
    (0..l.len())
        .map(|i| l[i].as_dvec2().perp_dot(l[(i + 1) % l.len()].as_dvec2()))
        .sum()
}

/// Whether closed segments `p0 p1` and `q0 q1` intersect (exact orientation tests).
fn segments_cross(p0: Vec2, p1: Vec2, q0: Vec2, q1: Vec2) -> bool {
    let o = |a: Vec2, b: Vec2, c: Vec2| {
        robust::orient2d(
            robust::Coord {
                x: a.x as f64,
                y: a.y as f64,
            },
            robust::Coord {
                x: b.x as f64,
                y: b.y as f64,
            },
            robust::Coord {
                x: c.x as f64,
                y: c.y as f64,
            },
        )
    };
    let (d1, d2) = (o(q0, q1, p0), o(q0, q1, p1));
    let (d3, d4) = (o(p0, p1, q0), o(p0, p1, q1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: Vec2, b: Vec2, c: Vec2, d: f64| {
        d == 0.0
            && c.x >= a.x.min(b.x)
            && c.x <= a.x.max(b.x)
            && c.y >= a.y.min(b.y)
            && c.y <= a.y.max(b.y)
    };
    on(q0, q1, p0, d1) || on(q0, q1, p1, d2) || on(p0, p1, q0, d3) || on(p0, p1, q1, d4)
}

/// Checks the outline: enough finite points, area, and no two segments meeting except
/// neighbours at their shared point.
pub fn check(outline: &Outline) -> Result<(), MeshError> {
    let segs: Vec<(usize, usize, Vec2, Vec2)> = outline
        .loops
        .iter()
        .enumerate()
        .flat_map(|(li, l)| (0..l.len()).map(move |i| (li, i, l[i], l[(i + 1) % l.len()])))
        .collect();
    for (li, l) in outline.loops.iter().enumerate() {
        if l.len() < 3 {
            return Err(MeshError::TooFewPoints {
                looped: li,
                points: l.len(),
            });
        }
        if let Some(i) = l.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NotFinite {
                looped: li,
                point: i,
            });
        }
    }
    if outline.loops.is_empty() {
        return Err(MeshError::TooFewPoints {
            looped: 0,
            points: 0,
        });
    }
    let (lo, hi) = outline
        .loops
        .iter()
        .flatten()
        .fold((Vec2::MAX, Vec2::MIN), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let span = (hi - lo).max_element();
    if span > MAX_SPAN {
        return Err(MeshError::Span(span));
    }
    // All pairs, pruned by bounding boxes on a sort by x (outlines are small).
    let mut order: Vec<usize> = (0..segs.len()).collect();
    order.sort_by(|&a, &b| {
        let xa = segs[a].2.x.min(segs[a].3.x);
        let xb = segs[b].2.x.min(segs[b].3.x);
        xa.total_cmp(&xb)
    });
    for (k, &i) in order.iter().enumerate() {
        let (la, a, p0, p1) = segs[i];
        let xmax = p0.x.max(p1.x);
        for &j in &order[k + 1..] {
            let (lb, b, q0, q1) = segs[j];
            if q0.x.min(q1.x) > xmax {
                break;
            }
            let n = outline.loops[la].len();
            let neighbours = la == lb && (a.abs_diff(b) == 1 || a.abs_diff(b) == n - 1);
            if neighbours {
                // Neighbours share one point; they cross only by folding back on it.
                let (shared, pa, pb) = if (a + 1) % n == b {
                    (p1, p0, q1)
                } else {
                    (p0, p1, q0)
                };
                let d = (pa - shared).perp_dot(pb - shared);
                if d == 0.0 && (pa - shared).dot(pb - shared) > 0.0 {
                    return Err(MeshError::SelfIntersecting { la, a, lb, b });
                }
                continue;
            }
            if segments_cross(p0, p1, q0, q1) {
                let ((la, a), (lb, b)) = if (la, a) <= (lb, b) {
                    ((la, a), (lb, b))
                } else {
                    ((lb, b), (la, a))
                };
                return Err(MeshError::SelfIntersecting { la, a, lb, b });
            }
        }
    }
    if let Some(li) = outline
        .loops
        .iter()
        .position(|l| signed_area2(l).abs() < 1e-12)
    {
        return Err(MeshError::NoArea { looped: li });
    }
    Ok(())
}

/// A corner sharper than this (turn between the sides, degrees) is kept by
/// [`simplify`] however close it lies to its neighbours.
const KEEP_TURN_DEG: f32 = 30.0;

/// Kept points (corners, seam ends) closer than this share of [`simplify`]'s length to
/// the point before are merged all the same: GarmentCode has edges of 0.01 mm.
const CROWDED: f32 = 0.25;

/// `outline` without the points that lie closer than `min_len` to the point kept before
/// them, except corners (a turn over [`KEEP_TURN_DEG`]) and any point within 0.1 mm of one
/// of `keep` (a seam's end, say) unless they are closer than a quarter of `min_len`. Curves sampled densely (a GarmentCode curve is 64
/// points however short) would otherwise be meshed as triangles a tenth of the asked edge,
/// light and stiff, which no step length suits; the outline moves by less than `min_len`.
/// Returns the outline unchanged when dropping points would leave a loop under three
/// points or make it cross itself.
pub fn simplify(outline: &Outline, min_len: f32, keep: &[Vec2]) -> Outline {
    let cos_keep = KEEP_TURN_DEG.to_radians().cos();
    let kept = |l: &[Vec2], i: usize| {
        let n = l.len();
        let (a, p, b) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
        let (u, v) = ((p - a).normalize_or_zero(), (b - p).normalize_or_zero());
        u.dot(v) < cos_keep || keep.iter().any(|k| (*k - p).length() < 1e-4)
    };
    let loops: Vec<Vec<Vec2>> = outline
        .loops
        .iter()
        .map(|l| {
            // Start at a kept point when there is one, so the loop's seam is not special.
            let start = (0..l.len()).find(|&i| kept(l, i)).unwrap_or(0);
            let mut out: Vec<(Vec2, bool)> = Vec::with_capacity(l.len());
            for k in 0..l.len() {
                let i = (start + k) % l.len();
                let must = k == 0 || kept(l, i);
                if must {
                    // A kept point pushes aside the ordinary points just before it.
                    while let Some(&(q, false)) = out.last() {
                        if (l[i] - q).length() >= min_len {
                            break;
                        }
                        out.pop();
                    }
                }
                let gap = out.last().map_or(f32::INFINITY, |q| (l[i] - q.0).length());
                // Even kept points merge when all but on top of each other.
                if (must && gap >= CROWDED * min_len) || gap >= min_len {
                    out.push((l[i], must));
                }
            }
            // The loop closes on its first point: the last ones must not crowd it.
            while out.len() > 1 {
                let (q, must) = out[out.len() - 1];
                let gap = (q - out[0].0).length();
                if (must && gap >= CROWDED * min_len) || gap >= min_len {
                    break;
                }
                out.pop();
            }
            out.into_iter().map(|(q, _)| q).collect()
        })
        .collect();
    let simpler = Outline { loops };
    if simpler.loops.iter().any(|l| l.len() < 3) || check(&simpler).is_err() {
        return outline.clone();
    }
    simpler
}

/// Whether `p` crosses an odd number of `l`'s sides going toward +x (inside `l`, for a
/// simple polygon).
pub fn contains(l: &[Vec2], p: Vec2) -> bool {
    let mut c = false;
    for i in 0..l.len() {
        let (a, b) = (l[i], l[(i + 1) % l.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            c = !c;
        }
    }
    c
}

/// Whether `p` lies inside the outline (even-odd over all its loops).
fn inside(outline: &Outline, p: Vec2) -> bool {
    outline.loops.iter().filter(|l| contains(l, p)).count() % 2 == 1
}

/// About how many vertices meshing `outline` at `edge` m makes, before any work: the
/// refinement leaves triangles of about two thirds of an equilateral triangle's area
/// (measured: the estimate is within 4% on rectangles), twice as many as the vertices
/// inside; every boundary side split into parts of `edge` adds its points. Loops after
/// the first are holes in it.
pub fn estimate_vertices(outline: &Outline, edge: f32) -> usize {
    let e = f64::from(edge.max(EDGE_RANGE.0));
    let areas = outline.loops.iter().map(|l| signed_area2(l).abs() * 0.5);
    let area = areas
        .enumerate()
        .map(|(k, a)| if k == 0 { a } else { -a })
        .sum::<f64>()
        .max(0.0);
    let inside = area / (2.0 * 0.433 * 0.67 * e * e);
    let boundary: f64 = outline
        .loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|i| f64::from((l[(i + 1) % l.len()] - l[i]).length()) / e)
                .sum::<f64>()
        })
        .sum();
    (inside + boundary).min(usize::MAX as f64 / 2.0) as usize
}

/// Meshes `outline` with triangles of about `edge` metres a side (see the module doc).
pub fn mesh_outline(outline: &Outline, edge: f32) -> Result<ClothMesh, MeshError> {
    mesh_outline_as(outline, edge, Border::Refine)
}

/// What the meshing may do to an outline's border.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Border {
    /// Split each side into equal parts no longer than the edge, and more where the
    /// refinement needs it.
    Refine,
    /// Keep the outline's points as the border's vertices and split each side only into
    /// equal parts no longer than the edge: the refinement adds no border point (the
    /// two sides of a seam, resampled alike, must stay alike). Triangles beside a tight
    /// corner may then stay thinner than [`MIN_ANGLE_DEG`].
    Keep,
}

/// [`mesh_outline`], its border as `border` says.
pub fn mesh_outline_as(
    outline: &Outline,
    edge: f32,
    border: Border,
) -> Result<ClothMesh, MeshError> {
    if !(EDGE_RANGE.0..=EDGE_RANGE.1).contains(&edge) {
        return Err(MeshError::EdgeLength(edge));
    }
    check(outline)?;
    // Size check before any work.
    let estimate = estimate_vertices(outline, edge);
    if estimate > MAX_VERTICES {
        return Err(MeshError::TooLarge {
            vertices: estimate,
            max: MAX_VERTICES,
        });
    }
    // The boundary, every side split into equal parts no longer than `edge`.
    let mut points: Vec<Point2<f64>> = Vec::new();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for l in &outline.loops {
        let first = points.len();
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            let parts = match border {
                Border::Refine => (((b - a).length() / edge).ceil() as usize).max(1),
                // A side at the edge's length to within rounding stays whole.
                Border::Keep => (((b - a).length() / edge - 1e-3).ceil() as usize).max(1),
            };
            for k in 0..parts {
                let p = a.lerp(b, k as f32 / parts as f32);
                points.push(Point2::new(p.x as f64, p.y as f64));
            }
        }
        let n = points.len() - first;
        for k in 0..n {
            edges.push([first + k, first + (k + 1) % n]);
        }
    }
    // Sides that check() passed can still meet once resampled (a sliver whose corners
    // lie on one line to within rounding): spade reports them here instead of panicking.
    let mut conflicts = 0usize;
    let mut cdt =
        ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(points, edges, |_| {
            conflicts += 1
        })
        .map_err(|e| MeshError::Triangulation(format!("{e:?}")))?;
    if conflicts > 0 {
        return Err(MeshError::SidesMeet(conflicts));
    }
    let max_area = 0.5 * 0.433 * 2.0 * (edge as f64).powi(2);
    let budget = estimate.saturating_mul(3).clamp(1000, MAX_VERTICES);
    let mut params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(MIN_ANGLE_DEG))
        .with_max_allowed_area(max_area)
        .with_min_required_area(max_area * 1e-4)
        .with_max_additional_vertices(budget);
    if border == Border::Keep {
        params = params.keep_constraint_edges();
    }
    let refined = cdt.refine(params);
    if cdt.num_vertices() > MAX_VERTICES {
        return Err(MeshError::TooLarge {
            vertices: cdt.num_vertices(),
            max: MAX_VERTICES,
        });
    }
    // The faces inside the outline, counter-clockwise in the pattern: not outside it
    // (spade's outer faces, slivers along the hull included) and not in a hole.
    let outer: std::collections::HashSet<usize> =
        refined.excluded_faces.iter().map(|f| f.index()).collect();
    let mut index = vec![u32::MAX; cdt.num_vertices()];
    let mut pattern: Vec<Vec2> = Vec::new();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if outer.contains(&face.fix().index()) {
            continue;
        }
        let vs = face.vertices();
        let p = vs.map(|v| {
            let q = v.position();
            Vec2::new(q.x as f32, q.y as f32)
        });
        if !inside(outline, (p[0] + p[1] + p[2]) / 3.0) {
            continue;
        }
        let mut t = [0u32; 3];
        for k in 0..3 {
            let h = vs[k].fix().index();
            if index[h] == u32::MAX {
                index[h] = pattern.len() as u32;
                pattern.push(p[k]);
            }
            t[k] = index[h];
        }
        if (p[1] - p[0]).perp_dot(p[2] - p[0]) < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    let (lo, hi) = super::bounds2(&pattern);
    let side = (hi - lo).max_element().max(1e-6);
    let mesh = ClothMesh {
        positions: pattern.iter().map(|p| Vec3::new(p.x, 0.0, -p.y)).collect(),
        uvs: pattern
            .iter()
            .map(|p| Vec2::new((p.x - lo.x) / side, (hi.y - p.y) / side))
            .collect(),
        triangles,
    };
    mesh.validate()
        .map_err(|e| MeshError::Triangulation(e.to_string()))?;
    Ok(mesh)
}

/// Several outlines meshed into one cloth, each a piece where its outline lies; UVs span
/// the pieces together (the square of their bounds), so paint on one never shows on
/// another.
pub fn mesh_pieces(outlines: &[Outline], edge: f32) -> Result<ClothMesh, MeshError> {
    Ok(mesh_pieces_ranged(outlines, edge, Border::Refine)?.0)
}

/// [`mesh_pieces`], with each outline's range of vertices in the cloth, their borders as
/// `border` says.
pub fn mesh_pieces_ranged(
    outlines: &[Outline],
    edge: f32,
    border: Border,
) -> Result<(ClothMesh, Vec<std::ops::Range<usize>>), MeshError> {
    let mut ranges = Vec::with_capacity(outlines.len());
    let mut out = ClothMesh {
        positions: Vec::new(),
        uvs: Vec::new(),
        triangles: Vec::new(),
    };
    for o in outlines {
        let m = mesh_outline_as(o, edge, border)?;
        let base = out.positions.len() as u32;
        out.positions.extend(m.positions);
        ranges.push(base as usize..out.positions.len());
        out.triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
        if out.positions.len() > MAX_VERTICES {
            return Err(MeshError::TooLarge {
                vertices: out.positions.len(),
                max: MAX_VERTICES,
            });
        }
    }
    let (lo, hi) = super::bounds(&out.positions);
    let side = (hi.x - lo.x).max(hi.z - lo.z).max(1e-6);
    out.uvs = out
        .positions
        .iter()
        .map(|p| Vec2::new((p.x - lo.x) / side, (p.z - lo.z) / side))
        .collect();
    Ok((out, ranges))
}

#[cfg(test)]
mod tests;
