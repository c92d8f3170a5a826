//! Seams: two border paths paired vertex to vertex and pulled together by stitches of
//! bounded force, each pair welded (sewn) once within reach: 1.5 x the cloth's
//! thickness and at least [`WELD_REACH_MIN`], or [`ZIP_REACH`] edges beside a welded
//! pair or where the seam's two sides meet (a zip).

use glam::Vec3;

use super::document::Design;

/// Sides of a seam whose pattern lengths differ by more than this share of the longer
/// are worth a warning (not a refusal: easing a longer side in is a tailor's choice).
pub const SEAM_MISMATCH: f32 = 0.2;

/// How near, in mean edge lengths, a stitched pair beside a welded one (or at the end
/// of its seam where its sides meet) welds. Stitches alone pull with a few hundredths to
/// tenths of a newton, which under the vbd model does not bend a flap round a body's
/// edge: the paper's fit-cube welded 17-19 of its 76 pairs, the dress 51-56 of 61. Zipped
/// at two edges once a seam stalls ([`ZIP_AFTER`]), 57 and 60-61, at the price of more
/// stretch where a seam is pulled shut across a body's feature (docs/garments.md). Each
/// weld still waits while it would cross anything.
pub const ZIP_REACH: f32 = 2.0;

/// Most stretch (a share of the rest length) a zipped weld may leave on the edges it
/// moves at once (the solver then spreads it); beyond it the pair waits, its stitch
/// pulling. At 0.25 the zip hardly acted (fit-cube 23 of 76 welded), at 0.5 half of it
/// (39).
pub const ZIP_STRAIN: f32 = 1.0;

/// Frames a seam must go without a weld before it zips a pair: a seam still closing by
/// its stitches is left to them. Zipping without waiting (a whole seam in one frame, or
/// a pair every frame) stretched GarmentCode's garments more (pencil dress strain max
/// 0.55-0.69 against 0.22-0.24 unzipped) and welded fewer of their pairs.
pub const ZIP_AFTER: u32 = 10;

/// The least reach of a weld, m: the 6 mm that 1.5 thicknesses of the default 4 mm
/// contact give. The library's fabrics are 1-1.5 mm thick, and at a reach of 1.5 mm
/// stitches pulling against friction and contact left many pairs just out of it (the
/// 3 cm dress in a 1 mm contact welded 85 of 118 pairs in 400 frames, against 114 with this
/// floor). A weld from farther moves its two vertices by half the gap, and is checked not
/// to cross (see `Design::place_weld`).
pub const WELD_REACH_MIN: f32 = 0.006;

use super::error::EditError;
use super::parts::Seam;
use super::prim::{MergeAt, Prim};

impl Design {
    /// Checks that `path` is a chain of border vertices joined by border edges.
    fn check_border_path(&self, path: &[u32]) -> Result<(), EditError> {
        if path.len() < 2 {
            return Err(EditError::BadValue {
                name: "seam path",
                rule: "at least 2 vertices",
                value: path.len().to_string(),
            });
        }
        for &v in path {
            self.check_vertex(v)?;
            if !self.sim.cloth.live.is_boundary(v) {
                return Err(EditError::SewInterior(v));
            }
        }
        for w in path.windows(2) {
            let sides = self.sim.cloth.live.edge(w[0], w[1]);
            if sides[0] == crate::mesh::NONE || sides[1] != crate::mesh::NONE {
                return Err(EditError::NotBorderEdge(w[0], w[1]));
            }
        }
        Ok(())
    }

    /// The force each stitched pair of a seam between paths `a` and `b` may pull with,
    /// N, for a seam that pulls `pull_per_m` newtons per metre: each of the pairs (as
    /// many as the longer path has vertices) takes its share of the longer side's length
    /// in the pattern. So a finer mesh, with more pairs, does not sew harder: at a force
    /// per pair, the 9 mm dress was pulled with 95 N in all against 30 N at 3 cm, on a
    /// dress that weighs 1 N. Zero for a path of no length (which `add_seam` refuses).
    pub fn pair_pull(&self, a: &[u32], b: &[u32], pull_per_m: f32) -> f32 {
        let pairs = a.len().max(b.len()).max(1) as f32;
        let len = self.pattern_length(a).max(self.pattern_length(b));
        pull_per_m * len / pairs
    }

    /// The length of a vertex path in the pattern (the rest length of each of its edges,
    /// as the triangle holding the edge has it; where no triangle holds both ends, the
    /// nearest two of their places in the pattern; the present distance only for a
    /// vertex in no triangle), m. Two sides to be sewn should match: a designer is told when
    /// they differ by more than [`SEAM_MISMATCH`].
    pub fn pattern_length(&self, path: &[u32]) -> f32 {
        path.windows(2).map(|w| self.pattern_edge(w[0], w[1])).sum()
    }

    /// The length in the pattern between border vertices `a` and `b` (see
    /// [`Design::pattern_length`]), m.
    pub(super) fn pattern_edge(&self, a: u32, b: u32) -> f32 {
        let live = &self.sim.cloth.live;
        (live.tris_of(a).iter())
            .filter_map(|&t| live.tri(t))
            .find_map(|t| {
                let (i, j) = (t.corner(a)?, t.corner(b)?);
                Some((t.rest[i] - t.rest[j]).length())
            })
            .or_else(|| {
                // No triangle has both (a weld's collapse between them, or a vertex a
                // weld left out): the nearest two of their places in the
                // pattern, which lie on one piece. (The distance in 3D read the
                // dress's side seam as 543 mm against 530 while it was sewn.)
                let places = |v: u32| {
                    (live.tris_of(v).iter())
                        .filter_map(|&t| live.tri(t))
                        .filter_map(move |t| Some(t.rest[t.corner(v)?]))
                };
                (places(a).flat_map(|p| places(b).map(move |q| (p - q).length())))
                    .min_by(f32::total_cmp)
            })
            .unwrap_or_else(|| {
                let x = &self.sim.cloth.x;
                match (x.get(a as usize), x.get(b as usize)) {
                    (Some(a), Some(b)) => (*a - *b).length(),
                    _ => 0.0,
                }
            })
    }

    /// Adds a seam between border paths `a` and `b` (vertex chains along the border, in
    /// matching directions), paired by their shares of each side's length in the pattern
    /// ([`align`]): every vertex of both is stitched, two sides of as many vertices one
    /// to one. Undoable.
    pub fn add_seam(&mut self, a: &[u32], b: &[u32], max_force: f32) -> Result<usize, EditError> {
        self.check_seam(a, b, max_force)?;
        // Each side's vertices by their share of its length in the pattern (as a
        // sewist matches two edges, whatever shape the cloth has taken).
        let params = |p: &[u32]| -> Vec<f32> {
            let mut s = vec![0.0f32];
            for w in p.windows(2) {
                s.push(s.last().copied().unwrap_or(0.0) + self.pattern_edge(w[0], w[1]));
            }
            let total = s.last().copied().unwrap_or(0.0).max(1e-12);
            s.iter().map(|t| t / total).collect()
        };
        let (ta, tb) = (params(a), params(b));
        let pairs: Vec<(u32, u32)> = if a.len() >= b.len() {
            let on = align(&ta, &tb);
            (0..a.len()).map(|i| (a[i], b[on[i]])).collect()
        } else {
            let on = align(&tb, &ta);
            (0..b.len()).map(|j| (a[on[j]], b[j])).collect()
        };
        self.commit_seam(pairs, max_force)
    }

    /// Adds a seam of `pairs` as given, their sides border paths: each vertex of a cut
    /// sewn to its twin across it. Undoable.
    pub fn add_seam_pairs(
        &mut self,
        pairs: &[(u32, u32)],
        max_force: f32,
    ) -> Result<usize, EditError> {
        let (a, b): (Vec<u32>, Vec<u32>) = pairs.iter().copied().unzip();
        self.check_seam(&a, &b, max_force)?;
        self.commit_seam(pairs.to_vec(), max_force)
    }

    /// Refuses a seam whose sides are not border paths, share a vertex, or whose stitch
    /// force is not a positive number.
    fn check_seam(&self, a: &[u32], b: &[u32], max_force: f32) -> Result<(), EditError> {
        self.check_editable()?;
        self.check_border_path(a)?;
        self.check_border_path(b)?;
        if let Some(v) = a.iter().find(|v| b.contains(v)) {
            return Err(EditError::SeamOverlap(*v));
        }
        if !(max_force.is_finite() && max_force > 0.0) {
            return Err(EditError::BadValue {
                name: "stitch force",
                rule: "a positive number of newtons",
                value: max_force.to_string(),
            });
        }
        Ok(())
    }

    /// Seam `pairs` added as one undoable edit; returns the pair count.
    fn commit_seam(&mut self, pairs: Vec<(u32, u32)>, max_force: f32) -> Result<usize, EditError> {
        let seam = Seam {
            pairs,
            max_force,
            name: String::new(),
            eased: Vec::new(),
            press_second: false,
        };
        let count = seam.pairs.len();
        let index = self.seams.len() as u32;
        self.commit(
            "seam",
            vec![Prim::Seam {
                index,
                old: None,
                new: Some(seam),
            }],
        )?;
        Ok(count)
    }

    /// Names seam `index` (`name` trimmed; empty: it goes by its letter again). Undoable.
    /// A name longer than [`MAX_NAME`](super::MAX_NAME) characters is refused.
    pub fn name_seam(&mut self, index: usize, name: &str) -> Result<(), EditError> {
        let count = self.seams.len();
        let Some(old) = self.seams.get(index).cloned() else {
            return Err(EditError::NoSeam { index, count });
        };
        let name = name.trim();
        if name.chars().count() > super::MAX_NAME || name.chars().any(char::is_control) {
            return Err(EditError::BadValue {
                name: "seam name",
                rule: "at most 120 characters, none of them control characters",
                value: format!("{} characters", name.chars().count()),
            });
        }
        if old.name == name {
            return Ok(());
        }
        let new = Seam {
            name: name.to_string(),
            ..old.clone()
        };
        self.commit(
            "name seam",
            vec![Prim::Seam {
                index: index as u32,
                old: Some(old),
                new: Some(new),
            }],
        )
    }

    /// Welds stitched pairs that came within reach (after a frame); each weld is an
    /// undoable sew. Returns how many welded. The reach is 1.5 x the cloth's thickness,
    /// at least [`WELD_REACH_MIN`] (not the thickness: under penetration-free contact two
    /// pieces' edges meet at the contact distance, which is the thickness, and would
    /// never weld), and
    /// [`ZIP_REACH`] mean edges for a pair beside a welded one, or at the end of its seam
    /// where its two sides already meet (the corner a cut-away leaves, a dart's point: the
    /// pair's vertices are neighbours or share one), so that a seam closes from there like
    /// a zip, the cloth's own stiffness drawing the next pair in where stitches alone
    /// would leave it open (see there).
    pub(super) fn weld_close_stitches(&mut self) -> usize {
        let near = (1.5 * self.sim.material.thickness).max(WELD_REACH_MIN);
        // Worked out when a seam first may zip (a pass over the mesh).
        let mut zip_reach = None;
        let mut welded = 0;

        self.seam_idle.resize(self.seams.len(), 0);
        for si in 0..self.seams.len() {
            // A stalled seam zips one pair a frame: the cloth follows before the next.
            let mut zipped = self.seam_idle[si] < ZIP_AFTER;
            let before = welded;
            let mut k = 0;
            while k < self.seams[si].pairs.len() {
                let pairs = &self.seams[si].pairs;
                let (a, b) = pairs[k];
                let shut =
                    |j: Option<usize>| j.and_then(|j| pairs.get(j)).is_some_and(|p| p.0 == p.1);
                let at_end = k == 0 || k + 1 == pairs.len();
                let reach = if !zipped
                    && (shut(k.checked_sub(1))
                        || shut(Some(k + 1))
                        || (at_end && a != b && self.sim.cloth.live.meet(a, b)))
                {
                    *zip_reach.get_or_insert_with(|| {
                        near.max(ZIP_REACH * self.sim.cloth.live.mean_rest_side())
                    })
                } else {
                    near
                };
                k += 1;
                let gap = (self.sim.cloth.x[a as usize] - self.sim.cloth.x[b as usize]).length();
                if a == b || gap > reach || self.weld_refused.contains(&(a, b)) {
                    continue;
                }
                let Ok(mut prims) = self.weld_prims(a, b) else {
                    continue;
                };
                if !self.place_weld(&mut prims, a, b, gap > near) {
                    continue;
                }
                // A triangle the weld collapses is eased into this seam (`Seam::eased`).
                let folded: Vec<[Vec3; 3]> = (prims.iter())
                    .filter_map(|p| match p {
                        Prim::Tri {
                            old: Some(t),
                            new: None,
                            ..
                        } => Some(t.rest),
                        _ => None,
                    })
                    .collect();
                // Every seam now refers to `a` where it referred to `b` (this one among
                // them: `b` is in its pair `k`).
                for (sj, seam) in self.seams.iter().enumerate() {
                    if seam.pairs.iter().any(|&(p, q)| p == b || q == b) {
                        let mut new = seam.clone();
                        if sj == si {
                            new.eased.extend_from_slice(&folded);
                        }
                        for pq in &mut new.pairs {
                            *pq = (
                                if pq.0 == b { a } else { pq.0 },
                                if pq.1 == b { a } else { pq.1 },
                            );
                        }
                        prims.push(Prim::Seam {
                            index: sj as u32,
                            old: Some(seam.clone()),
                            new: Some(new),
                        });
                    }
                }
                // Undone, a weld opens where it stands, its two vertices together and
                // then parted as a cut's sides are: put back as far apart as they lay,
                // from where the sewn vertex stands once the garment has turned, they
                // went through the layers round the seam (a draped dress's side seam
                // could not be undone: 82 new crossing pairs).
                for p in &mut prims {
                    if let Prim::Merge { apart, .. } = p {
                        *apart = [Vec3::ZERO; 2];
                    }
                }
                if self.commit_auto("weld", prims).is_ok() {
                    self.hand_hold(b, a);
                    welded += 1;
                    zipped |= gap > near;
                } else {
                    self.weld_refused.push((a, b));
                }
            }
            // A stalled seam whose pairs between two welded ones wait for good: closed as
            // one slit (`slit.rs`).
            if welded == before && !zipped {
                let reach = *zip_reach.get_or_insert_with(|| {
                    near.max(ZIP_REACH * self.sim.cloth.live.mean_rest_side())
                });
                if self.zip_seam_slit(si, reach) {
                    welded += 1;
                }
            }
            self.seam_idle[si] = if welded > before {
                0
            } else {
                self.seam_idle[si].saturating_add(1)
            };
        }
        welded + self.zip_seam_slits(near)
    }

    /// Where the weld of `a` and `b` puts them (`prims` from [`Design::weld_prims`]: `a`
    /// moved to the pair's midpoint): the midpoint, else `a`'s place, else `b`'s, the first
    /// at which the edit crosses nothing it does not cross now (and, for a pair welded from
    /// beyond the thickness, `zip`, stretches no edge past [`ZIP_STRAIN`]). Two sides that
    /// meet round a body's edge or a fold often have their midpoint through the layer or
    /// the edge between them while one of the two places is clear: fit-cube's flaps, held
    /// a thickness apart by contact, waited there for good. False (nothing changed) when
    /// none of the three will do.
    fn place_weld(&self, prims: &mut [Prim], a: u32, b: u32, zip: bool) -> bool {
        let x = &self.sim.cloth.x;
        let ends = [x[a as usize], x[b as usize]];
        for place in [MergeAt::Middle, MergeAt::A, MergeAt::B] {
            for p in prims.iter_mut() {
                if let Prim::Merge {
                    a: pa, at, apart, ..
                } = p
                    && *pa == a
                {
                    let to = place.of(ends[0], ends[1]);
                    *at = place;
                    *apart = [ends[0] - to, ends[1] - to];
                }
            }
            let stretched = zip && self.stretch_after(prims) > ZIP_STRAIN;
            if !stretched && !self.edit_would_cross(prims) {
                return true;
            }
        }
        false
    }
}

/// A seam's pairs: each vertex of the longer side (`long`, each vertex's share of the
/// side's length in the pattern) on one of the shorter side's (`short`, no more vertices),
/// in order along both, each next vertex on the same one or the next, every one of the
/// shorter's taken, the shares as near as can be (the least sum of their differences).
/// Two sides of as many vertices pair one to one. (Each vertex on its nearest by share
/// left a vertex of the shorter side out of every pair where its vertices bunched, a hole
/// once the rest welded; and a left-out vertex added on its nearest then joined three
/// pairs in a Z, which pulls an edge of each side shut.)
fn align(long: &[f32], short: &[f32]) -> Vec<usize> {
    let (n, m) = (long.len(), short.len());
    if m == 0 || n < m {
        return vec![0; n];
    }
    // Row i of the least sums: long[..=i] with long[i] on short[j]; and whether long[i]
    // is on the same vertex as long[i - 1] (else on the next).
    let mut row = vec![f32::INFINITY; m];
    // Kept only across the band of `j` that can still pair (`n - m + 1` wide): a
    // long seam of two sides of a few thousand vertices each stays a few megabytes.
    let w = n - m + 1;
    let lo = |i: usize| (m + i).saturating_sub(n);
    let mut stay = vec![false; n * w];
    row[0] = (long[0] - short[0]).abs();
    for i in 1..n {
        let mut next = vec![f32::INFINITY; m];
        // Only where the rest of both sides can still pair.
        for j in lo(i)..=i.min(m - 1) {
            let step = if j > 0 { row[j - 1] } else { f32::INFINITY };
            stay[i * w + j - lo(i)] = row[j] <= step;
            next[j] = (long[i] - short[j]).abs() + row[j].min(step);
        }
        row = next;
    }
    let mut on = vec![0; n];
    let mut j = m - 1;
    for i in (0..n).rev() {
        on[i] = j;
        if i > 0 && !stay[i * w + j - lo(i)] {
            j = j.saturating_sub(1);
        }
    }
    on
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::ZIP_AFTER;
    use crate::collision::Body;
    use crate::design::Design;
    use crate::design::cut::PART_M;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// A 0.5 m cloth at y = 1 cut in two along x, the far half raised 5 mm (within the
    /// weld's reach of 6 mm), a seam joining the cut's two sides.
    fn cut_and_sewn() -> Design {
        slit_and_sewn(0.3, 0.005)
    }

    /// A 0.5 m cloth of 8 x 8 cells at y = 1 cut along x from its edge at -0.25 to `to`,
    /// the far side raised `lift`, a seam joining the cut's two sides.
    fn slit_and_sewn(to: f32, lift: f32) -> Design {
        let n = 8;
        let mesh = ClothMesh::grid(0.5, 0.5, n, n, 1.0).unwrap();
        let mut d = crate::design::floating(mesh, ModelKind::Xpbd);
        let z = 0.0021;
        d.cut_stroke(&[Vec3::new(-0.3, 1.0, z), Vec3::new(to, 1.0, z)], 0.015)
            .unwrap();
        let row = (n / 2 * (n + 1)) as u32;
        let x = d.sim.cloth.x.clone();
        // A cut's two sides lie a parting apart (`cut::PART_M` each way).
        let twins = |u: usize, v: usize| u != v && (x[u] - x[v]).length() < 3.0 * PART_M;
        let split = |v: u32| (0..x.len()).any(|u| twins(u, v as usize));
        let a: Vec<u32> = (row..row + n as u32 + 1).filter(|&v| split(v)).collect();
        let b: Vec<u32> = a
            .iter()
            .map(|&v| {
                (0..x.len() as u32)
                    .rev()
                    .find(|&u| twins(u as usize, v as usize))
                    .unwrap()
            })
            .collect();
        for i in 0..x.len() {
            if x[i].z > 0.0 || b.contains(&(i as u32)) {
                d.sim.cloth.x[i].y += lift;
            }
        }
        d.add_seam(&a, &b, 0.05).unwrap();
        d
    }

    /// A closed box, outward wound, from `lo` to `hi`.
    fn plate(lo: Vec3, hi: Vec3) -> Body {
        let v: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Body::new("plate", v, t, None).unwrap()
    }

    /// Welds for `frames` frames (no steps between: the cloth stays put); how many.
    fn weld_for(d: &mut Design, frames: usize) -> usize {
        (0..frames).map(|_| d.weld_close_stitches()).sum()
    }

    /// Two sides of as many vertices pair one to one, however differently spaced; a
    /// longer side's vertices each go on one of the other's, in order, none of the
    /// other's left out and none of the longer's on two.
    #[test]
    fn sides_pair_one_to_one_or_in_order_with_none_left_out() {
        let even = [0.0, 0.25, 0.5, 0.75, 1.0];
        assert_eq!(
            super::align(&[0.0, 0.1, 0.2, 0.3, 1.0], &even),
            [0, 1, 2, 3, 4]
        );
        // Each long vertex on its nearest by share ([0, 2, 3, 3, 4, 4]) left the short
        // side's second vertex out.
        let long = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
        let short = [0.0, 0.17, 0.22, 0.44, 1.0];
        let on = super::align(&long, &short);
        assert_eq!(on, [0, 1, 2, 3, 4, 4]);
        for (k, w) in on.windows(2).enumerate() {
            assert!(w[1] == w[0] || w[1] == w[0] + 1, "{k}: {on:?}");
        }
    }

    /// Every vertex of both sides is stitched, however unevenly they are spaced: where
    /// one side's vertices bunch and the other's are sparse, the shorter side's were left
    /// out of every pair (the longer side set the pairs), a hole once the rest welded.
    /// (Two rectangles alike, bent round the body differently, left 2 of 25 out.)
    #[test]
    fn every_vertex_of_both_sides_is_stitched() {
        let mut mesh = ClothMesh::grid(0.5, 0.5, 8, 8, 1.0).unwrap();
        // The bottom row's first five, bunched at their start in the pattern; the top
        // row's first four, bunched at their end.
        let (a, b): (Vec<u32>, Vec<u32>) = ((0..5).collect(), (72..76).collect());
        let x = &mut mesh.positions;
        for k in 1..4 {
            x[k].x = x[0].x + 0.001 * k as f32;
        }
        for k in [73, 74] {
            x[k].x = x[75].x - 0.001 * (75 - k) as f32;
        }
        let mut d = crate::design::floating(mesh, ModelKind::Xpbd);
        d.add_seam(&a, &b, 0.05).unwrap();
        let pairs = &d.seams[0].pairs;
        for v in a.iter().chain(&b) {
            let stitched = pairs.iter().any(|&(p, q)| p == *v || q == *v);
            assert!(stitched, "{v} in no pair: {pairs:?}");
        }
        // In order along both sides.
        let ordered = pairs
            .windows(2)
            .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1);
        assert!(ordered, "{pairs:?}");
    }

    /// A seam 3 cm open welds nothing by itself (its stitches pull; the reach is 6 mm);
    /// once one pair is shut, the rest zip shut from it, a pair each time the seam has
    /// stalled.
    #[test]
    fn a_seam_zips_shut_from_a_welded_pair() {
        let mut d = slit_and_sewn(0.3, 0.03);
        assert_eq!(weld_for(&mut d, 3 * ZIP_AFTER as usize), 0);
        let pairs = d.seams[0].pairs.len();
        let (a, b) = d.seams[0].pairs[0];
        d.sim.cloth.x[b as usize] = d.sim.cloth.x[a as usize] + Vec3::Y * 0.001;
        // The close pair, and its neighbour zipped (the seam had stalled).
        assert_eq!(d.weld_close_stitches(), 2);
        assert_eq!(
            weld_for(&mut d, ZIP_AFTER as usize),
            0,
            "not stalled again yet"
        );
        assert_eq!(d.weld_close_stitches(), 1, "then a pair each stall");
        assert_eq!(weld_for(&mut d, pairs * ZIP_AFTER as usize), pairs - 3);
        assert!(d.seams[0].pairs.iter().all(|(p, q)| p == q));
        d.validate().unwrap();
    }

    /// A slit's seam zips shut from its closed end, where its two sides meet.
    #[test]
    fn a_slit_zips_shut_from_its_end() {
        let mut d = slit_and_sewn(0.1, 0.03);
        let pairs = d.seams[0].pairs.len();
        assert!(pairs >= 4);
        assert_eq!(weld_for(&mut d, pairs * (ZIP_AFTER as usize + 1)), pairs);
        d.validate().unwrap();
    }

    /// A weld moves its vertices by up to 4.5 mm outside the contact guard: one that
    /// would leave the cloth through something waits.
    #[test]
    fn a_weld_that_would_cross_the_body_waits() {
        let mut open = cut_and_sewn();
        let pairs = open.seams[0].pairs.len();
        assert_eq!(
            open.weld_close_stitches(),
            pairs,
            "with nothing between, all weld"
        );

        let mut blocked = cut_and_sewn();
        // A 2 mm plate between the two sides, where the welded vertices would meet.
        blocked.sim.body = Some(plate(
            Vec3::new(-0.4, 1.0015, -0.05),
            Vec3::new(0.4, 1.0035, 0.05),
        ));
        let before = blocked.sim.cloth.x.clone();
        assert_eq!(blocked.weld_close_stitches(), 0);
        assert_eq!(blocked.sim.cloth.x, before, "nothing moved");
        assert!(blocked.seams[0].pairs.iter().all(|(p, q)| p != q));
    }

    /// Where the pair's midpoint would take the cloth through something and one side's
    /// place would not, the weld is made there: a sliver of body lies beside the near
    /// side, through which the near side's triangles would rise to the midpoint.
    #[test]
    fn a_weld_goes_where_it_crosses_nothing() {
        let mut d = cut_and_sewn();
        d.sim.body = Some(plate(
            Vec3::new(-0.4, 1.0015, -0.006),
            Vec3::new(0.4, 1.0035, -0.002),
        ));
        let pairs = d.seams[0].pairs.clone();
        for &(a, b) in &pairs {
            let mid = d.sew_prims(a, b).unwrap();
            assert!(d.edit_would_cross(&mid), "the midpoint crosses ({a}, {b})");
        }
        let near: Vec<Vec3> = pairs
            .iter()
            .map(|&(a, _)| d.sim.cloth.x[a as usize])
            .collect();
        assert_eq!(d.weld_close_stitches(), pairs.len());
        for (&(a, _), at) in pairs.iter().zip(&near) {
            assert_eq!(
                d.sim.cloth.x[a as usize], *at,
                "welded at the near side's place"
            );
        }
        assert!(d.seams[0].pairs.iter().all(|(p, q)| p == q));
        let c = d.sim.crossings();
        assert_eq!((c.self_pairs, c.body_pairs), (0, 0));
        d.validate().unwrap();
    }

    /// A seam's pull per metre is shared among its pairs: the same sides sewn on a mesh
    /// twice as fine pull with half as much a pair, the same in all.
    #[test]
    fn a_finer_mesh_sews_no_harder() {
        let total = |n: usize| {
            let mesh = ClothMesh::grid(0.4, 0.4, n, n, 1.0).unwrap();
            let d = crate::design::floating(mesh, ModelKind::Xpbd);
            let x = &d.sim.cloth.x;
            let side = |at: f32| -> Vec<u32> {
                (0..x.len() as u32)
                    .filter(|&v| (x[v as usize].x - at).abs() < 1e-5)
                    .collect()
            };
            let (a, b) = (side(-0.2), side(0.2));
            assert_eq!(a.len(), n + 1);
            let pull = d.pair_pull(&a, &b, 3.0);
            (pull, pull * a.len() as f32)
        };
        let (coarse, fine) = (total(8), total(16));
        // 9 and 17 pairs: about half a pair's pull, and 3 N/m over 0.4 m in all.
        assert!(fine.0 < 0.55 * coarse.0, "{coarse:?} {fine:?}");
        for (_, all) in [coarse, fine] {
            assert!((all - 1.2).abs() < 1e-4, "{all} N in all");
        }
    }
}
