//! Pieces added to, placed in and deleted from a design that exists, each one undoable
//! edit: a new piece is meshed, given its own band of the design's pattern plane (to the
//! right of everything there) and its own part of the texture (`atlas`), and started at
//! a named place round the body, a layer out at a time until it crosses nothing; placing a piece moves its vertices to where the
//! place puts its pattern; deleting one removes its triangles.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::garment::{
    self, DEFAULT_FABRIC, LAYER, Landmarks, MAX_DROP, PATTERN_GAP, PieceSpec, Place, Placement,
    SIMPLIFY, Start, place,
};
use super::pieces::PieceRecord;
use super::prim::Prim;
use crate::collision::crossings::fan_crossings;
use crate::mesh::{MAX_VERTICES, Tri, bounds2, mesher};

/// How many layers out (each `LAYER`, as a pattern's pieces use) a new piece may try.
const LAYERS: usize = 8;

/// Most vertices one piece added to a design may have: a 0.87 m² piece at 5 mm, or
/// 2.2 m² at 8 mm. Adding it takes about half a second here (meshed, placed, checked
/// for crossings, the solver told), which holds cloth-sim's frames; larger pieces are
/// refused before meshing.
pub const MAX_PIECE_VERTICES: usize = 60_000;

impl Design {
    /// The triangle slots of piece `index` of [`Design::piece_list`].
    pub fn piece_slots(&self, index: usize) -> Result<Vec<u32>, EditError> {
        let mut listed = self.listed();
        let count = listed.len();
        if index >= count {
            return Err(EditError::NoPiece { index, count });
        }
        Ok(listed.swap_remove(index).1)
    }

    /// Adds `spec` as a new piece meshed with triangles of about `edge` m, started at its
    /// own placement or else at `at` (tops at the shoulders, sleeves at the shoulder),
    /// as many layers out as it takes to cross nothing. Returns its vertex count.
    pub fn add_piece(
        &mut self,
        spec: &PieceSpec,
        at: impl Into<Start>,
        edge: f32,
    ) -> Result<usize, EditError> {
        self.add_piece_as("add piece", spec, at.into(), edge)
    }

    /// [`Design::add_piece`], undone and redone as `label`.
    fn add_piece_as(
        &mut self,
        label: &'static str,
        spec: &PieceSpec,
        at: Start,
        edge: f32,
    ) -> Result<usize, EditError> {
        self.check_editable()?;
        let bad = |e: String| EditError::Piece(format!("{}: {e}", spec.name));
        check_drop(&spec.name, at.drop)?;
        mesher::check(&spec.outline).map_err(|e| bad(e.to_string()))?;
        if !(mesher::EDGE_RANGE.0..=mesher::EDGE_RANGE.1).contains(&edge) {
            return Err(bad(mesher::MeshError::EdgeLength(edge).to_string()));
        }
        let outline = mesher::simplify(&spec.outline, SIMPLIFY * edge, &[]);
        let (lo, hi) = bounds2(&outline.loops[0]);
        let marks = Landmarks::of(self.sim.body.as_ref());
        let base = spec
            .placement
            .unwrap_or_else(|| start_placement(at, &marks));
        // A placement a pattern file saved is measured from the bounds it saved.
        let frame = (spec.start.as_ref())
            .filter(|s| spec.placement == Some(s.placement))
            .map(|s| s.bounds);
        let from = frame.map_or((lo, hi), |b| (Vec2::new(b[0], b[1]), Vec2::new(b[2], b[3])));
        // What can be known before meshing is checked first: meshing a large piece takes
        // long, and the command would be refused after it all the same.
        place(&spec.name, &[], from, &base, &marks).map_err(|e| EditError::Piece(e.to_string()))?;
        self.check_piece_size(&spec.name, mesher::estimate_vertices(&outline, edge), edge)?;
        let mesh = mesher::mesh_outline(&outline, edge).map_err(|e| bad(e.to_string()))?;
        self.check_piece_size(&spec.name, mesh.positions.len(), edge)?;
        let offset = Vec2::new(self.next_band() - lo.x, -hi.y);
        let mut name = spec.name.clone();
        let mut k = 1;
        while self.name_in_use(&name, &[]) {
            k += 1;
            name = format!("{} ({k})", spec.name);
        }
        let own: Vec<Vec2> = mesh
            .positions
            .iter()
            .map(|p| Vec2::new(p.x, -p.z))
            .collect();
        let n0 = self.sim.cloth.len() as u32;
        let slot0 = self.sim.cloth.live.slots() as u32;
        let tris: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| t.map(|v| v + n0)).collect();
        let verts: Vec<u32> = (n0..n0 + own.len() as u32).collect();
        let others: Vec<[u32; 3]> = self.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
        let (placement, starts) = self.first_clear(
            &name,
            &verts,
            &own,
            from,
            (base, spec.fallback),
            &tris,
            &others,
        )?;
        // Its own part of the texture, the design's parts moved up to make room.
        let uvs: Vec<[Vec2; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| mesh.uvs[v as usize]))
            .collect();
        let areas: Vec<f32> = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| own[v as usize]);
                0.5 * (b - a).perp_dot(c - a).abs()
            })
            .collect();
        let (room, mut prims) = match self.make_room(&uvs, &areas) {
            Some((room, prims)) => (Some(room), prims),
            None => (None, Vec::new()),
        };
        prims.extend(starts.iter().enumerate().map(|(i, &x)| Prim::AddVertex {
            index: n0 + i as u32,
            x,
            v: Vec3::ZERO,
            from: None,
        }));
        for (k, t) in mesh.triangles.iter().enumerate() {
            let rest = t.map(|v| {
                let p = own[v as usize] + offset;
                Vec3::new(p.x, 0.0, -p.y)
            });
            prims.push(Prim::Tri {
                slot: slot0 + k as u32,
                old: None,
                new: Some(Tri {
                    v: tris[k],
                    rest,
                    uv: uvs[k].map(|uv| room.as_ref().map_or(uv, |r| r.piece(uv))),
                }),
            });
        }
        prims.push(Prim::Piece {
            index: self.pieces.len() as u32,
            old: None,
            new: Some(PieceRecord {
                name,
                fabric: spec.fabric.clone(),
                grain: spec.grain,
                placement: Some(placement),
                offset,
                outline,
                parts: Vec::new(),
                frame: frame.map(Box::new),
            }),
        });
        self.commit(label, prims)?;
        Ok(starts.len())
    }

    /// Refuses a piece of `vertices` (meshed at `edge` m, or estimated before meshing)
    /// that is larger than [`MAX_PIECE_VERTICES`] or would take the design over
    /// [`MAX_VERTICES`] (a design file larger than that is not read back).
    fn check_piece_size(&self, name: &str, vertices: usize, edge: f32) -> Result<(), EditError> {
        let total = self.sim.cloth.len().saturating_add(vertices);
        if vertices > MAX_PIECE_VERTICES || total > MAX_VERTICES {
            return Err(EditError::Piece(format!(
                "{name}: meshed at {:.1} mm it would have about {vertices} vertices \
                 (a piece may have {MAX_PIECE_VERTICES}, the design {MAX_VERTICES} in all, \
                 {} now): choose a longer edge or a smaller piece",
                edge * 1e3,
                self.sim.cloth.len()
            )));
        }
        Ok(())
    }

    /// Where a new piece's band of the pattern plane begins: [`PATTERN_GAP`] right of
    /// the cloth and every piece's band, or at 0 in an empty design.
    fn next_band(&self) -> f32 {
        let right = (self.sim.cloth.live.iter())
            .flat_map(|(_, t)| t.rest)
            .map(|p| p.x)
            .chain(self.pieces.iter().map(|r| r.band().1))
            .fold(f32::NEG_INFINITY, f32::max);
        if right.is_finite() {
            right + PATTERN_GAP
        } else {
            0.0
        }
    }

    /// Where a piece starts under `base`: the first of `base` and up to [`LAYERS`]
    /// layers further out at which its triangles `fan` cross neither `others` nor the
    /// body, and failing those, with a `fallback` (a GarmentCode panel kept flat), up to
    /// [`garment::FLAT_OUT_TRIES`] layers further from the body, then the same of
    /// `fallback` (the torso's cylinder). Its vertices `verts` (new ones numbered from the cloth's end) have pattern
    /// points `own`, whose outline bounds are `b`.
    #[allow(clippy::too_many_arguments)]
    fn first_clear(
        &self,
        name: &str,
        verts: &[u32],
        own: &[Vec2],
        b: (Vec2, Vec2),
        (base, fallback): (Placement, Option<Placement>),
        fan: &[[u32; 3]],
        others: &[[u32; 3]],
    ) -> Result<(Placement, Vec<Vec3>), EditError> {
        let marks = Landmarks::of(self.sim.body.as_ref());
        let index: HashMap<u32, usize> = verts.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        let copies = copies(own);
        let mut last = 0;
        // A piece kept flat: where its file puts it, then layers further from the body.
        let flat = (1..=garment::FLAT_OUT_TRIES)
            .filter(|_| fallback.is_some())
            .map(|k| garment::moved_out(base, b, &marks, k as f32 * LAYER));
        let fall = fallback.into_iter().flat_map(tries);
        for pl in tries(base).into_iter().chain(flat).chain(fall) {
            let mut x =
                place(name, own, b, &pl, &marks).map_err(|e| EditError::Piece(e.to_string()))?;
            part(&mut x, &copies, verts, fan, &index);
            let at = |v: u32| match index.get(&v) {
                Some(&i) => x.get(i).copied(),
                None => self.sim.cloth.x.get(v as usize).copied(),
            };
            // Against the rest and the body, and against itself (wrapped round an arm
            // more than once, its layers would meet).
            last = fan_crossings(at, fan, others, self.sim.body.as_ref())
                + fan_crossings(at, fan, fan, None);
            if last == 0 {
                return Ok((pl, x));
            }
        }
        Err(EditError::PieceWouldCross {
            piece: name.into(),
            crossings: last,
        })
    }

    /// Moves piece `index` of [`Design::piece_list`] to `at` (a [`Place`], or a
    /// [`Start`] lower down): its vertices go where the place puts its pattern, at rest,
    /// as many layers out as it takes to cross nothing (refused when none does).
    pub fn place_piece(&mut self, index: usize, at: impl Into<Start>) -> Result<(), EditError> {
        self.check_editable()?;
        let at = at.into();
        let slots = self.piece_slots(index)?;
        let live = &self.sim.cloth.live;
        let first = slots.first().and_then(|&s| live.tri(s)).map(|t| t.rest[0]);
        let record = first.and_then(|p| self.record_at(Vec2::new(p.x, -p.z)));
        let (offset, bounds, name) = match record {
            Some(r) => {
                let r = &self.pieces[r];
                (r.offset, bounds2(&r.outline.loops[0]), r.name.clone())
            }
            None => {
                let pts: Vec<Vec2> = slots
                    .iter()
                    .filter_map(|&s| live.tri(s))
                    .flat_map(|t| t.rest.map(|p| Vec2::new(p.x, -p.z)))
                    .collect();
                (Vec2::ZERO, bounds2(&pts), format!("piece {}", index + 1))
            }
        };
        // Each vertex of the piece at its pattern place (a welded one has two: the
        // first seen wins).
        let mut own: HashMap<u32, Vec2> = HashMap::new();
        for t in slots.iter().filter_map(|&s| live.tri(s)) {
            for k in 0..3 {
                own.entry(t.v[k])
                    .or_insert(Vec2::new(t.rest[k].x, -t.rest[k].z) - offset);
            }
        }
        let verts: Vec<u32> = own.keys().copied().collect();
        let pattern: Vec<Vec2> = verts.iter().map(|v| own[v]).collect();
        let marks = Landmarks::of(self.sim.body.as_ref());
        check_drop(&name, at.drop)?;
        let base = start_placement(at, &marks);
        let fan: Vec<[u32; 3]> = slots
            .iter()
            .filter_map(|&s| live.tri(s))
            .map(|t| t.v)
            .collect();
        let mine: std::collections::HashSet<u32> = slots.iter().copied().collect();
        let others: Vec<[u32; 3]> = live
            .iter()
            .filter(|(s, _)| !mine.contains(s))
            .map(|(_, t)| t.v)
            .collect();
        let (placement, x) =
            self.first_clear(&name, &verts, &pattern, bounds, (base, None), &fan, &others)?;
        let cloth = &self.sim.cloth;
        let moved: Vec<(u32, Vec3)> = verts.iter().copied().zip(x).collect();
        let mut prims: Vec<Prim> = moved
            .iter()
            .map(|&(v, p)| Prim::Move {
                vertex: v,
                old: (cloth.x[v as usize], cloth.v[v as usize]),
                new: (p, Vec3::ZERO),
            })
            .collect();
        if let Some(r) = record {
            let old = self.pieces[r].clone();
            let mut new = old.clone();
            new.placement = Some(placement);
            // Measured from its outline's bounds, as every placement made here is.
            new.frame = None;
            prims.push(Prim::Piece {
                index: r as u32,
                old: Some(old),
                new: Some(new),
            });
        }
        self.commit("place piece", prims)
    }

    /// Deletes piece `index` of [`Design::piece_list`] (its triangles; undoable).
    /// Returns how many triangles went.
    pub fn delete_piece(&mut self, index: usize) -> Result<usize, EditError> {
        let slots = self.piece_slots(index)?;
        self.remove_labelled("delete piece", &slots)
    }

    /// Names piece `index` of [`Design::piece_list`] `name` (trimmed), undoably: the
    /// list, the pattern view and the pattern out call it so. A piece in one part is
    /// renamed; a part a cut left of a piece is named alone, the piece's other parts
    /// keeping the names they have. Refused: an empty name, one longer than
    /// [`MAX_NAME`](super::MAX_NAME) characters or with control characters, one another
    /// piece or part has, and a cloth that was not made as a pattern piece. Returns the
    /// old name.
    pub fn name_piece(&mut self, index: usize, name: &str) -> Result<String, EditError> {
        let (k, list) = self.own_record(
            index,
            "no name of its own to change; add a piece (Pieces: Add piece, or a pattern file) \
             to name it",
        )?;
        let name = name.trim();
        if name.is_empty()
            || name.chars().count() > super::MAX_NAME
            || name.chars().any(char::is_control)
        {
            return Err(EditError::BadValue {
                name: "piece name",
                rule: "1 to 120 characters, none of them control characters",
                value: format!("{name:?}"),
            });
        }
        let old = list[index].name.clone();
        if old == name {
            return Ok(old);
        }
        if self.name_in_use(name, &list) {
            return Err(EditError::Piece(format!(
                "a piece is called {name} already; give {old} another name"
            )));
        }
        let new = self.with_part_named(k, index, name)?;
        self.replace_record("name piece", k, new)?;
        Ok(old)
    }

    /// Adds a copy of piece `index` of [`Design::piece_list`] as it is now (its outline
    /// after cuts and tears, holes included), of its fabric and grain, meshed with
    /// triangles of about `edge` m and started at `at`, as [`Design::add_piece`] starts a
    /// new piece; `mirrored`, the copy is the piece turned over (a left front from a
    /// right one). Its name is the piece's, numbered (`front (2)`, and a copy of that
    /// `front (3)`); its seams, paint and pins are not copied. One undoable edit.
    /// Returns the copy's name and vertex count.
    pub fn duplicate_piece(
        &mut self,
        index: usize,
        at: impl Into<Start>,
        mirrored: bool,
        edge: f32,
    ) -> Result<(String, usize), EditError> {
        let mut listed = self.listed();
        let count = listed.len();
        if index >= count {
            return Err(EditError::NoPiece { index, count });
        }
        let (info, slots) = listed.swap_remove(index);
        let view = super::sewing_pattern::view_of(self, std::slice::from_ref(&slots));
        let Some(piece) = view.into_iter().next() else {
            return Err(EditError::Piece(format!(
                "{}: it has no outline",
                info.name
            )));
        };
        let loops: Vec<Vec<Vec2>> = piece
            .loops
            .iter()
            .map(|l| {
                let mut l: Vec<Vec2> = l
                    .iter()
                    .map(|p| {
                        let x = if mirrored { -p.x } else { p.x };
                        Vec2::new(x as f32, p.y as f32)
                    })
                    .collect();
                if mirrored {
                    // Turned over, each loop keeps its way round (outer counter-clockwise).
                    l.reverse();
                }
                l
            })
            .collect();
        let record = info.record.map(|r| &self.pieces[r]);
        let grain = record.map_or(0.0, |r| r.grain);
        let spec = PieceSpec {
            name: unnumbered(&info.name).to_string(),
            outline: mesher::Outline { loops },
            fabric: record.map_or_else(|| DEFAULT_FABRIC.to_string(), |r| r.fabric.clone()),
            grain: if mirrored {
                std::f32::consts::PI - grain
            } else {
                grain
            },
            placement: None,
            start: None,
            fallback: None,
        };
        let before = self.pieces.len();
        let vertices = self.add_piece_as("copy piece", &spec, at.into(), edge)?;
        let name = self
            .pieces
            .get(before)
            .map_or(spec.name, |r| r.name.clone());
        Ok((name, vertices))
    }
}

/// `name` without the " (k)" that numbers a second piece of a name: a copy of
/// "front (2)" is "front (3)", not "front (2) (2)".
fn unnumbered(name: &str) -> &str {
    name.strip_suffix(')')
        .and_then(|n| n.rsplit_once(" ("))
        .filter(|(_, k)| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
        .map_or(name, |(base, _)| base)
}

/// Where a piece starts at `at`: tops at the shoulders, sleeves at the shoulder, each
/// `at.drop` m lower (down the arm for a sleeve).
fn start_placement(at: Start, marks: &Landmarks) -> Placement {
    match at.place {
        Place::LeftArm | Place::RightArm => at.place.at(at.drop),
        _ => at.place.at(marks.shoulders - at.drop),
    }
}

impl Design {
    /// Sets the substeps a frame to `n` as part of the designer's last operation (a
    /// piece added, placed or copied low under xpbd: `cloth-sim`'s `firm_if_hanging`),
    /// so that its undo puts them back with it and its redo sets them again. With no
    /// operation to undo, only sets them.
    pub fn firm_with_last_edit(&mut self, n: usize) {
        let step = Prim::Substeps {
            old: self.sim.substeps as u32,
            new: n as u32,
        };
        self.sim.substeps = n;
        if let Some(mut last) = self.history.pop_undo() {
            last.prims.push(step);
            self.history.push_after_redo(last);
        }
    }
}

/// The vertices (by their place in the piece's list) that share their pattern place
/// `own` with another: a cut's or a split tear's two sides.
fn copies(own: &[Vec2]) -> Vec<usize> {
    let key = |p: Vec2| p.to_array().map(f32::to_bits);
    let mut count: HashMap<[u32; 2], usize> = HashMap::new();
    for &p in own {
        *count.entry(key(p)).or_default() += 1;
    }
    (0..own.len())
        .filter(|&i| count[&key(own[i])] > 1)
        .collect()
}

/// Each of `copies` (places in `verts`, whose positions `x` are) moved into its own
/// triangles of `fan`, as a fresh cut's sides are parted (`cut::parting`): placed at its pattern place, a
/// cut piece's two sides lay together with no direction between them but the normal,
/// and could slide into each other (4 crossing pairs, found by the commands fuzzer's
/// crossing check, 2026-12-07).
fn part(
    x: &mut [Vec3],
    copies: &[usize],
    verts: &[u32],
    fan: &[[u32; 3]],
    index: &HashMap<u32, usize>,
) {
    let moves: Vec<(usize, Vec3)> = copies
        .iter()
        .filter_map(|&i| {
            let mine = fan.iter().filter(|t| t.contains(&verts[i]));
            let corners = mine.filter_map(|t| {
                let [a, b, c] = t.map(|u| index.get(&u).and_then(|&j| x.get(j).copied()));
                Some([a?, b?, c?])
            });
            Some((i, super::cut::parting(x[i], corners)?))
        })
        .collect();
    for (i, by) in moves {
        x[i] += by;
    }
}

/// Where a new or moved piece tries to start, in order, until one crosses nothing: round
/// the torso, `LAYERS` layers out; round an arm, `ARM_LAYERS` layers out at each of
/// `LAYERS` steps of [`ARM_STEP`] down the arm (a bodice's shoulder covers the top of
/// the arm, so that no layer out clears a sleeve's top there, but a few centimetres
/// down does; a sleeve on a sleeve needs a layer out); elsewhere only where asked.
fn tries(base: Placement) -> Vec<Placement> {
    match base {
        Placement::Around { .. } => (0..LAYERS)
            .map(|k| {
                let mut pl = base;
                if let Placement::Around { out, .. } = &mut pl {
                    *out += k as f32 * LAYER;
                }
                pl
            })
            .collect(),
        Placement::Arm { .. } => (0..LAYERS)
            .flat_map(|step| (0..ARM_LAYERS).map(move |k| (step, k)))
            .map(|(step, k)| {
                let mut pl = base;
                if let Placement::Arm { down, room, .. } = &mut pl {
                    *down += step as f32 * ARM_STEP;
                    *room += k as f32 * LAYER;
                }
                pl
            })
            .collect(),
        _ => vec![base],
    }
}

/// How many layers out a piece round an arm tries at each height.
const ARM_LAYERS: usize = 3;

/// How far down the arm each next height a piece round an arm tries is, m.
pub const ARM_STEP: f32 = 0.03;

/// Refuses a drop that is not a number or is outside `0..=MAX_DROP` m.
fn check_drop(name: &str, drop: f32) -> Result<(), EditError> {
    if (0.0..=MAX_DROP).contains(&drop) {
        Ok(())
    } else {
        Err(EditError::Piece(format!(
            "{name}: its top {drop} m below the place's start (0 to {MAX_DROP} m)"
        )))
    }
}
