//! A pattern made cloth: its pieces laid side by side in the design's pattern plane,
//! meshed, started where their placements put them; then its seams sewn.

use glam::{Vec2, Vec3};

use super::conform::{self, SeamSides, arc, project};
use super::place::{Landmarks, Place, PlaceError, Placement, place};
use super::spec::{EdgeRef, HOLD_BELOW_WAIST, PatternSpec, PieceSpec, SpecError};
use super::waist::{ABOVE, cloth_top};
use crate::design::{Design, EditError, PieceRecord};
use crate::mesh::mesher::{self, Border, MeshError, Outline};
use crate::mesh::{ClothMesh, MAX_VERTICES, bounds2};

/// Space between pieces in the design's pattern plane, m.
pub(crate) const PATTERN_GAP: f32 = 0.05;

/// Outline points closer than this many edge lengths to the one before are dropped
/// (`mesher::simplify`): the outline moves by less than this, well within an edge.
pub(crate) const SIMPLIFY: f32 = 0.4;

#[derive(Debug, thiserror::Error)]
pub enum GarmentError {
    #[error(transparent)]
    Spec(#[from] SpecError),
    #[error("piece {piece}: {source}")]
    Mesh { piece: String, source: MeshError },
    #[error(transparent)]
    Place(#[from] PlaceError),
    #[error("seam {label}: {source}")]
    Seam { label: String, source: EditError },
    #[error(
        "seam {label}: no border of piece {piece} runs between the points it names (its outline may have been cut)"
    )]
    NoStretch { label: String, piece: String },
}

/// The cloth of a pattern, before it is simulated.
pub struct Assembled {
    /// Every piece, flat in the design's pattern plane (rest shape).
    pub mesh: ClothMesh,
    /// Where each vertex starts.
    pub starts: Vec<Vec3>,
    pub records: Vec<PieceRecord>,
    /// Each piece's vertices, in the records' order.
    pub ranges: Vec<std::ops::Range<usize>>,
}

/// Lays out, meshes (triangles of about `edge` m) and places every piece of `spec`
/// (normalised and arranged: see [`PatternSpec`]).
pub fn assemble(
    spec: &PatternSpec,
    marks: &Landmarks,
    edge: f32,
) -> Result<Assembled, GarmentError> {
    let mesh_error = |piece: &str, source| GarmentError::Mesh {
        piece: piece.into(),
        source,
    };
    // The edge and the size before any work: resampling the seams' sides below splits
    // them into parts of `edge`, so a piece kilometres wide (a mistyped number in a
    // file) would ask for more points than memory holds.
    if !(mesher::EDGE_RANGE.0..=mesher::EDGE_RANGE.1).contains(&edge) {
        return Err(mesh_error("(all)", MeshError::EdgeLength(edge)));
    }
    let mut total = 0usize;
    for p in &spec.pieces {
        mesher::check(&p.outline).map_err(|source| mesh_error(&p.name, source))?;
        let own = mesher::estimate_vertices(&p.outline, edge);
        total = total.saturating_add(own);
        if total > MAX_VERTICES {
            let (piece, vertices) = if own > MAX_VERTICES {
                (p.name.as_str(), own)
            } else {
                ("(all)", total)
            };
            let max = MAX_VERTICES;
            return Err(mesh_error(piece, MeshError::TooLarge { vertices, max }));
        }
    }
    let mut simplified = Vec::with_capacity(spec.pieces.len());
    for (i, p) in spec.pieces.iter().enumerate() {
        // Points much closer than the edge length would mesh as tiny stiff triangles;
        // the seams' ends stay where they are.
        let ends: Vec<Vec2> = spec
            .seams
            .iter()
            .flat_map(|s| [s.a, s.b])
            .filter(|side| side.piece == i)
            .flat_map(|side| [side.from, side.to])
            .collect();
        simplified.push(mesher::simplify(&p.outline, SIMPLIFY * edge, &ends));
    }
    // Each seam's two sides with their border points at the same places (`conform`).
    let placements = layered(spec, marks);
    let seams = seam_sides(spec, &simplified, &placements, marks)?;
    let (mesh, ranges, offsets, outlines) = mesh_conformed(&simplified, &seams, edge)?;
    let mut records: Vec<PieceRecord> = spec
        .pieces
        .iter()
        .zip(outlines)
        .zip(&offsets)
        .map(|((p, outline), &offset)| PieceRecord {
            name: p.name.clone(),
            fabric: p.fabric.clone(),
            grain: p.grain,
            placement: p.placement,
            offset,
            outline,
            parts: Vec::new(),
            frame: p.start.as_ref().map(|s| Box::new(s.bounds)),
        })
        .collect();
    let mut starts = vec![Vec3::ZERO; mesh.positions.len()];
    for (i, (((p, r), range), placement)) in (spec.pieces.iter())
        .zip(&mut records)
        .zip(ranges.iter().cloned())
        .zip(placements)
        .enumerate()
    {
        r.placement = Some(placement);
        let own: Vec<Vec2> = mesh.positions[range.clone()]
            .iter()
            .map(|q| Vec2::new(q.x, -q.z) - r.offset)
            .collect();
        let x = place(
            &p.name,
            &own,
            spec.start_bounds(i, &r.outline),
            &placement,
            marks,
        )?;
        starts[range].copy_from_slice(&x);
    }
    Ok(Assembled {
        mesh,
        starts,
        records,
        ranges,
    })
}

/// Each seam of `spec` as the meshing sees it; which of its ends meet is the file's, or
/// else decided as [`sew`] decides it, from where the placements start them.
fn seam_sides(
    spec: &PatternSpec,
    outlines: &[Outline],
    placements: &[Placement],
    marks: &Landmarks,
) -> Result<Vec<SeamSides>, PlaceError> {
    let ends = |e: &EdgeRef| -> Result<Vec<Vec3>, PlaceError> {
        let bounds = spec.start_bounds(e.piece, &outlines[e.piece]);
        let name = &spec.pieces[e.piece].name;
        place(name, &[e.from, e.to], bounds, &placements[e.piece], marks)
    };
    spec.seams
        .iter()
        .map(|s| {
            let reversed = match s.reversed {
                Some(r) => r,
                None => {
                    let (a, b) = (ends(&s.a)?, ends(&s.b)?);
                    let d = |p: Vec3, q: Vec3| p.distance(q);
                    d(a[0], b[1]) + d(a[1], b[0]) < d(a[0], b[0]) + d(a[1], b[1])
                }
            };
            Ok(SeamSides {
                a: s.a,
                b: s.b,
                reversed,
            })
        })
        .collect()
}

/// The smallest angle a garment's triangle may have, degrees (the mesher's own aim is
/// [`mesher::MIN_ANGLE_DEG`]; its border kept as given, it reaches 21 on the dress).
const GARMENT_MIN_ANGLE_DEG: f32 = 20.0;

/// The pieces' `simplified` outlines meshed with every seam's sides conforming (see
/// `conform`): the cloth, each piece's vertices, how far each was moved when laid out,
/// and the outlines as meshed (the seams' sides resampled).
///
/// First with the resampled borders kept as they are (no point added to them). Should
/// that leave a triangle with an angle under [`GARMENT_MIN_ANGLE_DEG`] (the refinement
/// may not split a border side, so a tight corner can keep a thin triangle): meshed with
/// the borders refined, the points that adds shared between each seam's sides, and
/// meshed again with those kept. Should that fail too, the refined meshing (its seams'
/// sides then differ, and sewing eases them).
#[allow(clippy::type_complexity)]
fn mesh_conformed(
    simplified: &[Outline],
    seams: &[SeamSides],
    edge: f32,
) -> Result<
    (
        ClothMesh,
        Vec<std::ops::Range<usize>>,
        Vec<Vec2>,
        Vec<Outline>,
    ),
    GarmentError,
> {
    let mesh_all = |outlines: &[Outline], border| {
        let (laid, offsets) = laid_out(outlines);
        let (mesh, ranges) = mesher::mesh_pieces_ranged(&laid, edge, border).map_err(|source| {
            GarmentError::Mesh {
                piece: "(all)".into(),
                source,
            }
        })?;
        Ok::<_, GarmentError>((mesh, ranges, offsets))
    };
    let good = |m: &ClothMesh| m.min_angle_deg() >= GARMENT_MIN_ANGLE_DEG;
    let mut outlines = simplified.to_vec();
    conform::conform(&mut outlines, seams, edge);
    if sane(&mut outlines, simplified) == 0
        && let Ok((mesh, ranges, offsets)) = mesh_all(&outlines, Border::Keep)
        && good(&mesh)
    {
        return Ok((mesh, ranges, offsets, outlines));
    }
    let (mesh, ranges, offsets) = mesh_all(&outlines, Border::Refine)?;
    let mut kept = outlines.clone();
    conform::agree(&mut kept, seams, edge, (&mesh, &ranges, &offsets));
    if sane(&mut kept, &outlines) == 0
        && let Ok((m, r, o)) = mesh_all(&kept, Border::Keep)
        && good(&m)
    {
        return Ok((m, r, o, kept));
    }
    Ok((mesh, ranges, offsets, outlines))
}

/// Puts back `simplified`'s outline for every piece of `outlines` that crosses itself (a
/// side resampled across a tight curve); how many.
fn sane(outlines: &mut [Outline], simplified: &[Outline]) -> usize {
    let mut n = 0;
    for (o, s) in outlines.iter_mut().zip(simplified) {
        if mesher::check(o).is_err() {
            o.clone_from(s);
            n += 1;
        }
    }
    n
}

/// The pieces laid side by side in the design's pattern plane, left to right, tops level
/// at 0: each outline moved, and by how much.
fn laid_out(pieces: &[Outline]) -> (Vec<Outline>, Vec<Vec2>) {
    let mut cursor = 0.0f32;
    pieces
        .iter()
        .map(|o| {
            let (lo, hi) = bounds2(&o.loops[0]);
            let offset = Vec2::new(cursor - lo.x, -hi.y);
            cursor += hi.x - lo.x + PATTERN_GAP;
            let moved = Outline {
                loops: o
                    .loops
                    .iter()
                    .map(|l| l.iter().map(|&q| q + offset).collect())
                    .collect(),
            };
            (moved, offset)
        })
        .unzip()
}

/// Space between layers of pieces that would start in one place, m.
pub const LAYER: f32 = 0.015;

/// Every piece's placement (the front for one without), each piece round the torso that
/// would start on or within 1 cm of an earlier one (their arcs and heights overlapping)
/// moved a layer out from its own, until it starts clear of them all.
fn layered(spec: &PatternSpec, marks: &Landmarks) -> Vec<Placement> {
    let girth = marks.girth();
    // Arc interval (centre, half width) and height interval of a piece round the torso.
    let span = |p: &PieceSpec, pl: &Placement| -> Option<(f32, f32, f32, f32)> {
        let Placement::Around { angle, top, .. } = *pl else {
            return None;
        };
        let (lo, hi) = bounds2(&p.outline.loops[0]);
        let s = super::place::arc_of_angle(marks, angle);
        Some((s, 0.5 * (hi.x - lo.x), top - (hi.y - lo.y), top))
    };
    let mut out: Vec<Placement> = Vec::with_capacity(spec.pieces.len());
    for p in &spec.pieces {
        let mut pl = p.placement.unwrap_or(Place::Front.at(marks.shoulders));
        if let Some((s, hw, y0, y1)) = span(p, &pl) {
            let clash = |layer: f32, placed: &[Placement]| {
                placed.iter().zip(&spec.pieces).any(|(q, qs)| {
                    let Placement::Around { out: o, .. } = *q else {
                        return false;
                    };
                    let Some((t, tw, z0, z1)) = span(qs, q) else {
                        return false;
                    };
                    let d = (s - t).rem_euclid(girth);
                    let d = d.min(girth - d);
                    (o - layer).abs() < 0.5 * LAYER
                        && d < hw + tw + 0.01
                        && y0 < z1 + 0.01
                        && z0 < y1 + 0.01
                })
            };
            // From where the piece's placement puts it (further out where nearer it
            // would start through the body: the garment scenarios' `placed_garment`),
            // at most as far as layering goes (a file's start says any `out` up to 100 m).
            let most = 20.0 * LAYER;
            let mut layer = match pl {
                Placement::Around { out: o, .. } => o.max(0.0).min(most),
                _ => 0.0,
            };
            while clash(layer, &out) && layer < most {
                layer += LAYER;
            }
            if let Placement::Around { out: o, .. } = &mut pl {
                *o = layer;
            }
        }
        out.push(pl);
    }
    out
}

/// What sewing a pattern did.
#[derive(Clone, Debug, Default)]
pub struct Sewn {
    pub seams: usize,
    pub pairs: usize,
    /// The largest difference between a seam's two sides' pattern lengths, m.
    pub mismatch_m: f32,
    /// Seams left open, and why.
    pub open: Vec<String>,
}

/// The border vertices of piece `side.piece` along the stretch, in order, and the
/// stretch's length along the piece's outline, m.
fn stretch(design: &Design, side: &EdgeRef) -> (Vec<u32>, f32) {
    let Some(rec) = design.pieces.get(side.piece) else {
        return (Vec::new(), 0.0);
    };
    let l = &rec.outline.loops[0];
    let cum = arc(l);
    let per = cum[l.len()];
    let (t0, _) = project(l, &cum, side.from);
    let (t1, _) = project(l, &cum, side.to);
    let span = (t1 - t0).rem_euclid(per);
    let live = &design.sim.cloth.live;
    // Each border vertex's place in this piece's band of the pattern (from the live
    // triangles: a piece added to a design has no place in the original mesh).
    let mut seen = std::collections::HashSet::new();
    let mut on: Vec<(f32, u32)> = live
        .iter()
        .flat_map(|(_, t)| (0..3).map(move |k| (t.v[k], t.rest[k])))
        .filter(|&(v, _)| live.is_boundary(v))
        .filter_map(|(v, r)| {
            let q = Vec2::new(r.x, -r.z);
            if design.record_at(q) != Some(side.piece) || !seen.insert(v) {
                return None;
            }
            let (t, d) = project(l, &cum, q - rec.offset);
            let mut s = (t - t0).rem_euclid(per);
            if s > per - 1e-5 {
                s = 0.0;
            }
            (d < 1e-4 && s <= span + 1e-5).then_some((s, v))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    (on.into_iter().map(|(_, v)| v).collect(), span)
}

/// Most force a hold pulls one vertex with, N. GarmentCode's pencil dress welds 443-444
/// of its 446 stitched pairs with it and 433-434 with 0.2 N, whose harder hold keeps the
/// waist seam from where the bodice brings it (docs/garments.md).
pub const HOLD_PULL: f32 = 0.05;

/// The holds of `spec` (whose pieces are `design.pieces`, in order) on `design`'s
/// vertices: every border vertex along each held stretch, pulled with at most
/// [`HOLD_PULL`] N. For [`Design::hold_while_draping`].
///
/// A hold measured on this body (a fan's or a skirt's waist: `HoldSpec::measured`) holds
/// as it is, or [`HOLD_BELOW_WAIST`] under where its stretch starts if that is lower (a
/// skirt started lower where its file saved it). GarmentCode's plane is its own body's
/// waist, `human`'s; on another body whose waist is known, a garment that hangs from the
/// held stretch (a skirt, trousers: none of its cloth more than [`ABOVE`] higher) is held
/// at that body's waist instead (GarmentCode's circle skirts fell to the mannequin's feet
/// unheld), and one that does not is not held: on the mannequin, held 10 cm above its
/// own waist (`GC_RAISE`), GarmentCode's pencil dress and jumpsuit were still moving 100
/// frames after the holds let go, at twice the frame time; they stay on it without.
pub fn holds(design: &Design, spec: &PatternSpec) -> Vec<crate::solver::Hold> {
    let mut out: Vec<crate::solver::Hold> = Vec::new();
    let human =
        design.sim.body.as_ref().map(|b| b.name.as_str()) == Some(crate::collision::body::HUMAN);
    let waist = if human {
        None
    } else {
        Landmarks::of(design.sim.body.as_ref()).waist
    };
    let top = cloth_top(design);
    let x = &design.sim.cloth.x;
    for h in &spec.holds {
        let Some(normal) = h.normal.try_normalize() else {
            continue;
        };
        let held = stretch(design, &h.edge).0;
        if held.is_empty() {
            continue;
        }
        let mean = held.iter().map(|&v| x[v as usize].y).sum::<f32>() / held.len() as f32;
        let level = if h.measured {
            // Never above where the stretch starts: a skirt started where its file saved
            // it, lower than the waist, is not pulled up to it.
            h.level.min(mean - HOLD_BELOW_WAIST)
        } else if human {
            h.level
        } else {
            match waist {
                Some(w) if top <= mean + ABOVE => w - HOLD_BELOW_WAIST,
                _ => continue,
            }
        };
        for vertex in held {
            if !out.iter().any(|o| o.vertex == vertex) {
                out.push(crate::solver::Hold {
                    vertex,
                    normal,
                    level,
                    max_force: HOLD_PULL,
                });
            }
        }
    }
    out
}

/// Sews every seam of `spec` (whose pieces are `design.pieces`, in order), each pulling
/// `pull` N per metre of seam ([`Design::pair_pull`]); each seam's ends meet the way the
/// file says, or else the way its sides start closer.
pub fn sew(design: &mut Design, spec: &PatternSpec, pull: f32) -> Result<Sewn, GarmentError> {
    let mut sewn = Sewn::default();
    let edge = design.sim.cloth.live.mean_rest_side();
    for s in &spec.seams {
        let ((mut a, span_a), (mut b, span_b)) = (stretch(design, &s.a), stretch(design, &s.b));
        // A side shorter than the mesh's edge has no border edge of its own to sew
        // (GarmentCode has edges of a hundredth of a millimetre): say so, sew the rest.
        if (a.len() < 2 && span_a < edge) || (b.len() < 2 && span_b < edge) {
            sewn.open.push(format!(
                "seam {}: a side is {:.1} mm long, shorter than the mesh's edge; left unsewn",
                s.label,
                1000.0 * span_a.min(span_b)
            ));
            continue;
        }
        // A dart's two sides meet at its point: that vertex is sewn already.
        let shared: Vec<u32> = a.iter().copied().filter(|v| b.contains(v)).collect();
        if !shared.is_empty() {
            a.retain(|v| !shared.contains(v));
            b.retain(|v| !shared.contains(v));
            if a.len() < 2 || b.len() < 2 {
                sewn.open.push(format!(
                    "seam {}: a side has fewer than two vertices besides the point both share (mesh finer to sew it)",
                    s.label
                ));
                continue;
            }
        }
        for (side, path) in [(&s.a, &a), (&s.b, &b)] {
            if path.len() < 2 {
                return Err(GarmentError::NoStretch {
                    label: s.label.clone(),
                    piece: design
                        .pieces
                        .get(side.piece)
                        .map_or_else(|| side.piece.to_string(), |r| r.name.clone()),
                });
            }
        }
        let x = &design.sim.cloth.x;
        let d = |i: u32, j: u32| (x[i as usize] - x[j as usize]).length();
        let (a0, a1, b0, b1) = (a[0], a[a.len() - 1], b[0], b[b.len() - 1]);
        let closer = d(a0, b1) + d(a1, b0) < d(a0, b0) + d(a1, b1);
        if s.reversed.unwrap_or(closer) {
            b.reverse();
        }
        let m = (design.pattern_length(&a) - design.pattern_length(&b)).abs();
        sewn.mismatch_m = sewn.mismatch_m.max(m);
        let pair_pull = design.pair_pull(&a, &b, pull);
        sewn.pairs += design
            .add_seam(&a, &b, pair_pull)
            .map_err(|source| GarmentError::Seam {
                label: s.label.clone(),
                source,
            })?;
        sewn.seams += 1;
    }
    Ok(sewn)
}
