//! The cloth's pieces now: [`Design::piece_list`] finds the connected parts of the
//! pattern and names each by the [`PieceRecord`] whose band holds it, so cutting a piece
//! in two lists two pieces ("front" and "front 2") and a piece torn away keeps its name.

use std::collections::{HashMap, HashSet};

use glam::Vec2;

use super::document::Design;
use super::error::EditError;
use super::pieces::PieceRecord;
use super::prim::Prim;

/// A piece as the cloth has it now.
#[derive(Clone, Debug, PartialEq)]
pub struct PieceInfo {
    pub name: String,
    /// The record it came from (`None`: a cloth made without pieces).
    pub record: Option<usize>,
    pub fabric: String,
    pub vertices: usize,
    pub triangles: usize,
    /// One corner of the piece: its vertex and UV (a viewer finds the piece's triangles
    /// from it, as those joined to it in the pattern).
    pub anchor: Option<(u32, Vec2)>,
}

impl Design {
    /// The record of piece `index` of [`Design::piece_list`], with the list; a cloth not
    /// made as a pattern piece is refused, `what` saying what it has none of.
    pub(super) fn own_record(
        &self,
        index: usize,
        what: &str,
    ) -> Result<(usize, Vec<PieceInfo>), EditError> {
        let list = self.piece_list();
        let info = list.get(index).ok_or(EditError::NoPiece {
            index,
            count: list.len(),
        })?;
        match info.record {
            Some(k) => Ok((k, list)),
            None => Err(EditError::Piece(format!(
                "{} was not made as a pattern piece, so it has {what}",
                info.name
            ))),
        }
    }

    /// Record `k` replaced by `new` as one undoable edit labelled `label`; returns the
    /// name it had.
    pub(super) fn replace_record(
        &mut self,
        label: &'static str,
        k: usize,
        new: PieceRecord,
    ) -> Result<String, EditError> {
        let old = self.pieces[k].clone();
        let name = old.name.clone();
        self.commit(
            label,
            vec![Prim::Piece {
                index: k as u32,
                old: Some(old),
                new: Some(new),
            }],
        )?;
        Ok(name)
    }

    /// The record of the piece whose band holds pattern point `p` (the design's pattern
    /// x and -z).
    pub fn record_at(&self, p: Vec2) -> Option<usize> {
        self.pieces.iter().position(|r| {
            let (lo, hi) = r.band();
            p.x >= lo - 1e-4 && p.x <= hi + 1e-4
        })
    }

    /// The triangle slots of record `k`'s piece whose centre, in the piece's own
    /// coordinates (its outline's), satisfies `keep`: a region of a piece, as a
    /// designer's pattern names it.
    pub fn record_slots(&self, k: usize, keep: impl Fn(Vec2) -> bool) -> Vec<u32> {
        let Some(rec) = self.pieces.get(k) else {
            return Vec::new();
        };
        self.sim
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                let c = (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0;
                let q = Vec2::new(c.x, -c.z);
                self.record_at(q) == Some(k) && keep(q - rec.offset)
            })
            .map(|(s, _)| s)
            .collect()
    }

    /// The pieces of the cloth now: its parts connected in the pattern, listed by
    /// record and largest first within one, named by their record (a second part of one
    /// record gets " 2", and so on); parts of a cloth made without pieces are "piece 1",
    /// "piece 2", ...
    pub fn piece_list(&self) -> Vec<PieceInfo> {
        self.listed().into_iter().map(|(info, _)| info).collect()
    }

    /// [`Design::piece_list`] with each piece's triangle slots.
    pub(super) fn listed(&self) -> Vec<(PieceInfo, Vec<u32>)> {
        let parts = super::sewing_pattern::pattern_parts(self);
        in_list_order(self.describe(&parts).into_iter().zip(parts).collect())
    }

    /// [`Design::piece_list`] and the studio's pattern view
    /// ([`sewing_pattern::view_pieces`](super::sewing_pattern::view_pieces)), the cloth's
    /// parts found once for both (cloth-sim sends both after every cut).
    pub fn piece_list_and_view(&self) -> (Vec<PieceInfo>, Vec<super::sewing_pattern::Piece>) {
        let parts = super::sewing_pattern::pattern_parts(self);
        let view = super::sewing_pattern::view_of(self, &parts);
        let list = in_list_order(self.describe(&parts).into_iter().zip(parts).collect());
        (list.into_iter().map(|(info, _)| info).collect(), view)
    }

    /// Each part (its triangle slots) named as [`Design::piece_list`] says, in the
    /// parts' order.
    pub(super) fn describe(&self, parts: &[Vec<u32>]) -> Vec<PieceInfo> {
        let live = &self.sim.cloth.live;
        let mut out: Vec<PieceInfo> = Vec::with_capacity(parts.len());
        for tris in parts {
            let mut verts: Vec<u32> = tris
                .iter()
                .filter_map(|&s| live.tri(s))
                .flat_map(|t| t.v)
                .collect();
            verts.sort_unstable();
            verts.dedup();
            let centre = tris
                .first()
                .and_then(|&s| live.tri(s))
                .map(|t| (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0)
                .unwrap_or_default();
            let record = self.record_at(Vec2::new(centre.x, -centre.z));
            let anchor = tris
                .first()
                .and_then(|&s| live.tri(s))
                .map(|t| (t.v[0], t.uv[0]));
            out.push(PieceInfo {
                name: String::new(),
                record,
                fabric: record
                    .map(|r| self.pieces[r].fabric.clone())
                    .unwrap_or_else(|| "cloth".into()),
                vertices: verts.len(),
                triangles: tris.len(),
                anchor,
            });
        }
        // Within a record, the largest part keeps the name (the bigger side of a cut).
        let mut order: Vec<usize> = (0..out.len()).collect();
        order.sort_by(|&a, &b| {
            (out[a].record.cmp(&out[b].record))
                .then(out[b].triangles.cmp(&out[a].triangles))
                .then(a.cmp(&b))
        });
        // A part with a name of its own has it; the others are numbered round them.
        let keys: Vec<(Option<usize>, &[u32])> = (out.iter().zip(parts))
            .map(|(info, tris)| (info.record, &tris[..]))
            .collect();
        let own = self.named_parts(&keys);
        let taken: HashSet<String> = (out.iter().zip(&own))
            .filter_map(|(info, e)| Some(self.pieces[info.record?].parts[(*e)?].name.clone()))
            .collect();
        // A part separated from a piece (its own fabric; a later record) may have the
        // piece's name, which the piece's parts then number past.
        let later = |r: usize| {
            self.pieces[r + 1..]
                .iter()
                .any(|p| p.name == self.pieces[r].name)
        };
        let mut seen: HashMap<usize, usize> = HashMap::new();
        let mut loose = 0;
        for i in order {
            out[i].name = match (out[i].record, own[i]) {
                (Some(r), Some(e)) => self.pieces[r].parts[e].name.clone(),
                (Some(r), None) => loop {
                    let k = seen.entry(r).or_insert(0);
                    *k += 1;
                    let name = if *k == 1 {
                        self.pieces[r].name.clone()
                    } else {
                        format!("{} {}", self.pieces[r].name, k)
                    };
                    let shared = *k == 1 && later(r);
                    if !taken.contains(&name) && !shared {
                        break name;
                    }
                },
                (None, _) => {
                    loose += 1;
                    format!("piece {loose}")
                }
            };
        }
        out
    }
}

/// Pieces in the list's order: by record, largest first within one.
fn in_list_order(mut parts: Vec<(PieceInfo, Vec<u32>)>) -> Vec<(PieceInfo, Vec<u32>)> {
    parts.sort_by(|(a, _), (b, _)| a.record.cmp(&b.record).then(b.triangles.cmp(&a.triangles)));
    parts
}
