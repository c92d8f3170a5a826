//! Names of a cut piece's parts. A cut leaves a piece in parts that share its record
//! (its outline, fabric and grain), listed "front", "front 2"; a designer who names one
//! part names that part alone. The record keeps the name with points inside the part,
//! in the piece's own pattern coordinates: the pattern does not move as the cloth does,
//! so the points stay in the part as it drapes, and after a further cut the new part
//! holding the most of them keeps the name.

use std::collections::{HashMap, HashSet};

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::garment::PATTERN_GAP;
use super::piece_list::PieceInfo;
use super::pieces::{MAX_PART_NAMES, PART_POINTS, PartName, PieceRecord};
use super::prim::Prim;
use crate::mesh::live::Tri;

impl Design {
    /// For each part (its record and triangle slots), the index of the name of its own
    /// it has in its record: each name goes to the part of its record holding the most
    /// of its points (the larger part on a tie), unless another name took that part
    /// first.
    pub(super) fn named_parts(&self, parts: &[(Option<usize>, &[u32])]) -> Vec<Option<usize>> {
        let mut out = vec![None; parts.len()];
        let live = &self.sim.cloth.live;
        let mut of_record: HashMap<usize, Vec<usize>> = HashMap::new();
        for (i, (r, _)) in parts.iter().enumerate() {
            if let Some(r) = *r
                && self.pieces.get(r).is_some_and(|rec| !rec.parts.is_empty())
            {
                of_record.entry(r).or_default().push(i);
            }
        }
        for (r, mine) in of_record {
            let record = &self.pieces[r];
            let corners: Vec<Vec<[Vec2; 3]>> = (mine.iter())
                .map(|&i| {
                    (parts[i].1.iter())
                        .filter_map(|&s| live.tri(s))
                        .map(|t| t.rest.map(|q| Vec2::new(q.x, -q.z) - record.offset))
                        .collect()
                })
                .collect();
            for (e, part) in record.parts.iter().enumerate() {
                let held = |tris: &[[Vec2; 3]]| {
                    (part.points.iter())
                        .filter(|&&p| tris.iter().any(|&t| holds(t, p)))
                        .count()
                };
                let best = (mine.iter().zip(&corners))
                    .map(|(&i, tris)| (held(tris), tris.len(), i))
                    .filter(|&(n, ..)| n > 0)
                    .max();
                if let Some((.., i)) = best
                    && out[i].is_none()
                {
                    out[i] = Some(e);
                }
            }
        }
        out
    }

    /// Points spread over part `tris` of record `r`, in the piece's own coordinates: the
    /// centroids of up to [`PART_POINTS`] of its triangles, every so many.
    fn points_in_part(&self, r: usize, tris: &[u32]) -> Vec<Vec2> {
        let live = &self.sim.cloth.live;
        let step = tris.len().div_ceil(PART_POINTS).max(1);
        (tris.iter().step_by(step))
            .filter_map(|&s| live.tri(s))
            .map(|t| {
                let [a, b, c] = t.rest.map(|q| Vec2::new(q.x, -q.z));
                (a + b + c) / 3.0 - self.pieces[r].offset
            })
            .take(PART_POINTS)
            .collect()
    }

    /// Whether `name` is a piece's, a named part's, or listed in `list`.
    pub(super) fn name_in_use(&self, name: &str, list: &[PieceInfo]) -> bool {
        list.iter().any(|p| p.name == name)
            || (self.pieces.iter())
                .any(|r| r.name == name || r.parts.iter().any(|p| p.name == name))
    }

    /// Record `r` with listed piece `index` (one of its parts) called `name`: the part's
    /// own name changed, or the piece's when it is in one part, or else the part given a
    /// name of its own, and the piece's other parts the names they have now (so naming
    /// one part renames no other).
    pub(super) fn with_part_named(
        &self,
        r: usize,
        index: usize,
        name: &str,
    ) -> Result<super::PieceRecord, EditError> {
        let listed = self.listed();
        let keys: Vec<(Option<usize>, &[u32])> = (listed.iter())
            .map(|(info, tris)| (info.record, &tris[..]))
            .collect();
        let own = self.named_parts(&keys);
        let mut new = self.pieces[r].clone();
        if let Some(e) = own[index] {
            new.parts[e].name = name.to_string();
            return Ok(new);
        }
        let mine: Vec<usize> = (0..listed.len())
            .filter(|&i| listed[i].0.record == Some(r))
            .collect();
        if mine.len() == 1 {
            new.name = name.to_string();
            return Ok(new);
        }
        for &i in &mine {
            if i != index && own[i].is_none() {
                new.parts.push(PartName {
                    points: self.points_in_part(r, &listed[i].1),
                    name: listed[i].0.name.clone(),
                });
            }
        }
        new.parts.push(PartName {
            points: self.points_in_part(r, &listed[index].1),
            name: name.to_string(),
        });
        if new.parts.len() > MAX_PART_NAMES {
            return Err(EditError::Piece(format!(
                "{} has {MAX_PART_NAMES} named parts already",
                new.name
            )));
        }
        Ok(new)
    }
}

impl Design {
    /// The edits that make listed piece `index`, a part of record `r` among others, a
    /// piece of its own of fabric `fabric`: its triangles moved along the pattern
    /// plane's x into a band of their own (their rest shapes, and so how they hang,
    /// unchanged; the texture stays), and a record for it: the old one's outline,
    /// grain and placement, named as the part is listed. The record's other parts keep
    /// the names they have (as when a part is named). A fabric belongs to a whole
    /// pattern piece: a skirt cut from a dress at the waist is made of another fabric
    /// as a piece of its own.
    pub(super) fn separated(
        &self,
        r: usize,
        index: usize,
        fabric: &str,
    ) -> Result<Vec<Prim>, EditError> {
        let listed = self.listed();
        let keys: Vec<(Option<usize>, &[u32])> = (listed.iter())
            .map(|(info, tris)| (info.record, &tris[..]))
            .collect();
        let own = self.named_parts(&keys);
        let old = &self.pieces[r];
        let mut kept = old.clone();
        if let Some(e) = own[index] {
            kept.parts.remove(e);
        }
        for (i, (info, tris)) in listed.iter().enumerate() {
            if i != index && info.record == Some(r) && own[i].is_none() {
                kept.parts.push(PartName {
                    points: self.points_in_part(r, tris),
                    name: info.name.clone(),
                });
            }
        }
        let live = &self.sim.cloth.live;
        let right = (live.iter())
            .flat_map(|(_, t)| t.rest)
            .map(|p| p.x)
            .chain(self.pieces.iter().map(|p| p.band().1))
            .fold(f32::NEG_INFINITY, f32::max);
        let dx = right + PATTERN_GAP - old.band().0;
        let shift = Vec3::new(dx, 0.0, 0.0);
        let mut prims: Vec<Prim> = (listed[index].1.iter())
            .filter_map(|&slot| {
                let t = live.tri(slot)?;
                let moved = Tri {
                    rest: t.rest.map(|p| p + shift),
                    ..*t
                };
                Some(Prim::Tri {
                    slot,
                    old: Some(*t),
                    new: Some(moved),
                })
            })
            .collect();
        // The cloth a weld eased into a seam from the part (a folded triangle with more
        // corners on it than on the piece's other parts: along a cut both sides have
        // the same places) goes with it, as the pattern out draws it with its piece.
        let corners_of = |keep: &dyn Fn(usize) -> bool| -> HashSet<[u32; 3]> {
            (listed.iter().enumerate())
                .filter(|&(i, (info, _))| info.record == Some(r) && keep(i))
                .flat_map(|(_, (_, tris))| tris.iter().filter_map(|&slot| live.tri(slot)))
                .flat_map(|t| t.rest.map(|p| p.to_array().map(f32::to_bits)))
                .collect()
        };
        let (mine, others) = (corners_of(&|i| i == index), corners_of(&|i| i != index));
        for (i, seam) in self.seams.iter().enumerate() {
            let of_part = |t: &[Vec3; 3]| {
                let on = |set: &HashSet<[u32; 3]>| {
                    (t.iter())
                        .filter(|p| set.contains(&p.to_array().map(f32::to_bits)))
                        .count()
                };
                on(&mine) > on(&others)
            };
            if seam.eased.iter().any(of_part) {
                let mut moved = seam.clone();
                for t in moved.eased.iter_mut().filter(|t| of_part(t)) {
                    *t = t.map(|p| p + shift);
                }
                prims.push(Prim::Seam {
                    index: i as u32,
                    old: Some(seam.clone()),
                    new: Some(moved),
                });
            }
        }
        prims.push(Prim::Piece {
            index: r as u32,
            old: Some(old.clone()),
            new: Some(kept),
        });
        prims.push(Prim::Piece {
            index: self.pieces.len() as u32,
            old: None,
            new: Some(PieceRecord {
                name: listed[index].0.name.clone(),
                fabric: fabric.to_string(),
                offset: old.offset + Vec2::new(dx, 0.0),
                parts: Vec::new(),
                ..old.clone()
            }),
        });
        Ok(prims)
    }
}

/// Whether triangle `t` holds `p` (its edges included).
fn holds([a, b, c]: [Vec2; 3], p: Vec2) -> bool {
    let d = [
        (b - a).perp_dot(p - a),
        (c - b).perp_dot(p - b),
        (a - c).perp_dot(p - c),
    ];
    let eps = 1e-10;
    d.iter().all(|&x| x >= -eps) || d.iter().all(|&x| x <= eps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_holds_its_inside_and_edges_either_way_round() {
        let t = [Vec2::ZERO, Vec2::X, Vec2::Y];
        assert!(holds(t, Vec2::splat(0.25)));
        assert!(holds([t[0], t[2], t[1]], Vec2::splat(0.25)));
        assert!(holds(t, Vec2::new(0.5, 0.0)));
        assert!(!holds(t, Vec2::splat(0.6)));
        assert!(!holds(t, Vec2::new(-0.01, 0.5)));
    }
}
