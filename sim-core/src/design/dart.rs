//! A dart made in one step in the pattern plane: a wedge cut out of a piece from its
//! edge to a point, and its two legs seamed, as a designer takes in a dart at a waist or
//! a bust (`Design::dart_on_plane`). The same as the steps a designer can take one by one
//! (two cuts from beyond the edge to the point, the wedge between deleted, a seam up each
//! leg: docs/garments.md), done and undone as one operation, "dart".

use glam::{DVec2, Vec2};
use rustc_hash::FxHashMap as HashMap;

use super::document::Design;
use super::error::EditError;
use super::prim::Edit;
use super::sewing_pattern::{in_material, line_hit, view_of};

/// How far past the piece's edge a dart's cuts start, m: a cut that starts on the edge
/// leaves a sliver there.
const BEYOND_M: f32 = 0.01;

/// How far off a cut's line a dart's leg is looked for, m: the point, and the cut's own
/// vertices, lie on it.
const LEG_TOL_M: f32 = 1e-4;

/// How near a dart's point a vertex is taken for it, m: a cut passes through a vertex up
/// to 3 mm off its line rather than leave a sliver (`trim.rs`'s `SNAP_M`).
const LEG_OFF_M: f32 = 0.0035;

/// How far from a dart's point what its cuts leave round it is looked for (a slit, or a
/// cut's end opened on to a vertex beside the point: 10-25 mm seen at 1.5-3 cm edges).
const ROUND_M: f32 = 0.04;

/// How far outside a dart's wedge a piece parted from it may reach and still be taken
/// for a fragment of it, m.
const FRAGMENT_M: f32 = 1e-3;

/// Whether `q` lies in triangle `t` or within `tol` of it.
fn in_triangle(t: [Vec2; 3], q: Vec2, tol: f32) -> bool {
    let turn = (t[1] - t[0]).perp_dot(t[2] - t[0]).signum();
    (0..3).all(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let n = (b - a).normalize_or_zero();
        turn * n.perp_dot(q - a) >= -tol
    })
}

/// How far apart a vertex's places in the pattern are taken for two pieces (a weld),
/// not one place (the same corner in its triangles, equal to rounding), m.
const MOUTH_APART_M: f32 = 1e-3;

/// How much nearer the body's middle (or lower) one leg of a new dart must be than the
/// other for it to be pressed that way, m: a dart at the middle is left as it is.
const PRESS_TIE_M: f32 = 2e-3;

/// Which rule of [`Design::tailors_press`] chose a dart's press.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TailorsPress {
    /// A dart that runs up or down the body, pressed toward the centre front or back.
    TowardMiddle,
    /// A dart that runs round the body, pressed downward.
    Down,
}

/// A dart's width at the edge, m: from 2 mm to 0.5 m.
pub const DART_WIDTH_M: std::ops::RangeInclusive<f32> = 0.002..=0.5;

impl Design {
    /// A dart `width` m wide at the edge of the piece under `point`, from that point out
    /// along the line to `toward` (beyond the edge), in the design's pattern plane (m),
    /// as the studio's pattern view draws it: the wedge between is cut away and its two
    /// legs seamed, so the dart closes as the cloth is simulated (welded pair by pair).
    /// One undoable operation, "dart". Returns the stitched pairs. Refused, with nothing
    /// changed, when `point` is on no piece, the line does not leave the piece, the
    /// width is out of [`DART_WIDTH_M`], or a step fails (a wedge the cuts did not part
    /// from the piece, legs with too few border vertices to seam).
    pub fn dart_on_plane(
        &mut self,
        point: Vec2,
        toward: Vec2,
        width: f32,
    ) -> Result<usize, EditError> {
        if !(point.is_finite() && toward.is_finite() && point.distance(toward) > 1e-3) {
            return Err(EditError::BadValue {
                name: "dart line",
                rule: "two finite points at least 1 mm apart, from the dart's point out",
                value: format!("{point} to {toward}"),
            });
        }
        if !DART_WIDTH_M.contains(&width) {
            return Err(EditError::BadValue {
                name: "dart width",
                rule: "0.002 to 0.5 m",
                value: width.to_string(),
            });
        }
        self.check_editable()?;
        let edge = self.edge_crossing(point, toward)?;
        let side = (edge - point).perp().normalize_or_zero() * (0.5 * width);
        let mouths = [edge + side, edge - side];
        if mouths.iter().any(|m| m.distance(point) < 2.0 * width) {
            return Err(EditError::BadValue {
                name: "dart",
                rule: "at least twice as long, from its point to the edge, as it is wide",
                value: format!(
                    "{:.0} mm long, {:.0} mm wide",
                    edge.distance(point) * 1e3,
                    width * 1e3
                ),
            });
        }
        let before = self.history.undo_len();
        let done = self.dart_steps(point, mouths).and_then(|pairs| {
            self.press_as_tailors_do(self.seams.len() - 1)?;
            Ok(pairs)
        });
        let steps = self.history.undo_len() - before;
        match done {
            Ok(pairs) => {
                // The steps as one operation.
                let mut prims = Vec::new();
                let edits: Vec<Edit> = (0..steps).filter_map(|_| self.history.pop_undo()).collect();
                for e in edits.into_iter().rev() {
                    prims.extend(e.prims);
                }
                self.history.push_after_redo(Edit {
                    label: "dart",
                    prims,
                    auto: false,
                });
                Ok(pairs)
            }
            Err(e) => {
                for _ in 0..steps {
                    self.undo()?;
                }
                Err(e)
            }
        }
    }

    /// Whether dart seam `dart`'s mouth lies on cloth already sewn to other cloth: a
    /// vertex of its mouth's pair, or one beside it (a dart's cut leaves a vertex of its
    /// own on the edge), has places in two pieces of the pattern, as a weld leaves it.
    /// The other side of that seam must then gather the dart's intake, and the seam's
    /// length can hold the pairs at the mouth open (docs/garments.md, "A dart into a sewn
    /// side seam"). None for a seam that is not there or has no pairs.
    pub fn dart_mouth_sewn(&self, dart: usize) -> Option<bool> {
        let &(a, b) = self.seams.get(dart)?.pairs.first()?;
        let live = &self.sim.cloth.live;
        let welded = |v: u32| {
            let places = self.places_of(v, true);
            (places.iter()).any(|p| p.distance(places[0]) > MOUTH_APART_M)
        };
        let near = [a, b].into_iter().flat_map(|v| {
            (live.tris_of(v).iter())
                .filter_map(|&t| live.tri(t))
                .flat_map(|t| t.v)
                .chain([v])
                .collect::<Vec<u32>>()
        });
        Some(near.into_iter().any(welded))
    }

    /// The dart's steps (see [`Design::dart_on_plane`]), each its own edit.
    fn dart_steps(&mut self, point: Vec2, mouths: [Vec2; 2]) -> Result<usize, EditError> {
        let out = |m: Vec2| m + (m - point).normalize_or_zero() * BEYOND_M;
        for m in mouths {
            self.cut_line(out(m), point)?;
        }
        // The wedge: the piece under the middle of the triangle between the cuts.
        let middle = (point + mouths[0] + mouths[1]) / 3.0;
        // Each listed piece's outline (the list's order is not the parts').
        let outlines: Vec<Vec<Vec<DVec2>>> = (self.listed().iter())
            .map(|(_, slots)| {
                let view = view_of(self, std::slice::from_ref(slots));
                view.into_iter().next().map(|p| p.loops).unwrap_or_default()
            })
            .collect();
        let holds = |q: Vec2| {
            let q = DVec2::new(q.x as f64, q.y as f64);
            outlines.iter().position(|l| in_material(l, q))
        };
        let wedge = holds(middle).filter(|&w| {
            // Parted from the piece: the piece beside it is another.
            let beside = point + (point - middle).normalize_or_zero() * 0.01;
            holds(beside) != Some(w)
        });
        let Some(wedge) = wedge else {
            return Err(EditError::NothingOnPattern {
                what: "wedge parted from the piece by the dart's cuts",
            });
        };
        self.delete_piece(wedge)?;
        // A cut that passes a vertex near the edge can part a triangle or two of the
        // wedge from the rest (a one-triangle piece "front 2" was left at the hem): every
        // piece wholly inside the wedge goes with it.
        let wedge = [point, out(mouths[0]), out(mouths[1])];
        while let Some(k) = self.listed().iter().position(|(_, slots)| {
            let view = view_of(self, std::slice::from_ref(slots));
            view.first().is_some_and(|p| {
                (p.loops.iter().flatten()).all(|q| in_triangle(wedge, q.as_vec2(), FRAGMENT_M))
            })
        }) {
            self.delete_piece(k)?;
        }
        let [mut a, mut b] = mouths.map(|m| self.leg(m, point));
        // A vertex both legs reach is the point (a cut can end on a vertex beside it).
        let shared: Vec<u32> = a.iter().copied().filter(|v| b.contains(v)).collect();
        a.retain(|v| !shared.contains(v));
        b.retain(|v| !shared.contains(v));
        if a.len() < 2 || b.len() < 2 {
            return Err(EditError::NothingOnPattern {
                what: "leg of two or more border vertices",
            });
        }
        // What the cuts leave between the legs' ends round the point (a slit where they
        // went through one vertex, or on to a vertex beside the point) is sewn shut:
        // its two sides, outside in, go on the legs.
        let round = self.border_between(a[a.len() - 1], b[b.len() - 1], point);
        let half = round.len() / 2;
        a.extend(&round[..half]);
        b.extend(round[round.len() - half..].iter().rev());
        let pull = self.pair_pull(&a, &b, super::parts::STITCH_PULL);
        self.add_seam(&a, &b, pull)
    }

    /// A dart's leg from its mouth `m` to its point: the border path along the cut's line
    /// (found within [`LEG_TOL_M`]: a drag's centimetre took the other leg's vertices near
    /// the point, where the legs come that close), up to the first vertex at the point
    /// (within [`LEG_OFF_M`]: a cut can end on a vertex beside it), without it or what
    /// the border does past it (where the two cuts end on one point the border can go
    /// round a vertex beside it, or on down the other leg).
    fn leg(&self, m: Vec2, point: Vec2) -> Vec<u32> {
        let mut path = self.plane_path(m, point, LEG_TOL_M);
        let at_point =
            |v: u32| (self.places_of(v, true).iter()).any(|q| q.distance(point) <= LEG_OFF_M);
        if let Some(k) = path.iter().position(|&v| at_point(v)) {
            path.truncate(k);
        }
        path
    }

    /// The border vertices strictly between `from` and `to`, the shortest way along the
    /// border through vertices within [`ROUND_M`] of `point` (empty when there is none).
    fn border_between(&self, from: u32, to: u32, point: Vec2) -> Vec<u32> {
        let live = &self.sim.cloth.live;
        let near = |v: u32| (self.places_of(v, true).iter()).any(|q| q.distance(point) <= ROUND_M);
        let mut came: HashMap<u32, u32> = HashMap::default();
        let mut queue = std::collections::VecDeque::from([from]);
        came.insert(from, from);
        while let Some(v) = queue.pop_front() {
            if v == to {
                let mut path = Vec::new();
                let mut at = came[&to];
                while at != from {
                    path.push(at);
                    at = came[&at];
                }
                path.reverse();
                return path;
            }
            for u in live.neighbours(v) {
                let border = live.edge(v, u)[1] == crate::mesh::live::NONE;
                if border && !came.contains_key(&u) && (u == to || near(u)) {
                    came.insert(u, v);
                    queue.push_back(u);
                }
            }
        }
        Vec::new()
    }

    /// Where the line from `point` (on a piece) toward `toward` first leaves that
    /// piece's outline in the pattern plane.
    fn edge_crossing(&self, point: Vec2, toward: Vec2) -> Result<Vec2, EditError> {
        let d = |v: Vec2| DVec2::new(v.x as f64, v.y as f64);
        let (p, q) = (d(point), d(toward));
        let view = super::sewing_pattern::view_pieces(self);
        let Some(piece) = view.iter().find(|pc| in_material(&pc.loops, p)) else {
            return Err(EditError::NothingOnPattern {
                what: "cloth under the dart's point",
            });
        };
        let mut best: Option<f64> = None;
        for l in &piece.loops {
            for i in 0..l.len() {
                // `t`: the share of the way from the point to the drag's end.
                let hit = line_hit(p, q - p, l[i], l[(i + 1) % l.len()]);
                if let Some((t, _)) = hit.filter(|(t, _)| (0.0..=1.0).contains(t)) {
                    best = Some(best.map_or(t, |b: f64| b.min(t)));
                }
            }
        }
        let Some(t) = best else {
            return Err(EditError::NothingOnPattern {
                what: "edge between the dart's point and the drag's end",
            });
        };
        let e = p + (q - p) * t;
        Ok(Vec2::new(e.x as f32, e.y as f32))
    }

    /// The way a tailor presses dart seam `index`, where the body tells: a dart that runs
    /// up or down the body (a waist dart) toward the body's middle, the centre front or
    /// back; one that runs round it (a bust dart from the side seam) downward. The mouth
    /// vertex of the leg pressed toward, and which rule chose it. None without a body, or
    /// where the dart is at the middle (its legs within [`PRESS_TIE_M`] of each other).
    pub fn tailors_press(&self, index: usize) -> Option<(u32, TailorsPress)> {
        let (mn, mx) = self.sim.body.as_ref()?.bounds();
        let middle = 0.5 * (mn.x + mx.x);
        let seam = self.seams.get(index)?;
        let (&(a, b), &(pa, pb)) = (seam.pairs.first()?, seam.pairs.last()?);
        let x = &self.sim.cloth.x;
        let [xa, xb, xp] = [a, b, pa].map(|v| x[v as usize]);
        let axis = 0.5 * (xa + xb) - 0.5 * (xp + x[pb as usize]);
        let way = if axis.y.abs() >= axis.x.hypot(axis.z) {
            TailorsPress::TowardMiddle
        } else {
            TailorsPress::Down
        };
        // How much better a leg is: nearer the middle, or lower.
        let score = |p: glam::Vec3| match way {
            TailorsPress::TowardMiddle => -(p.x - middle).abs(),
            TailorsPress::Down => -p.y,
        };
        let (sa, sb) = (score(xa), score(xb));
        if (sa - sb).abs() < PRESS_TIE_M {
            return None;
        }
        Some((if sa > sb { a } else { b }, way))
    }

    /// Presses new dart seam `index` the way [`Design::tailors_press`] tells; leaves it
    /// pressed toward its first leg where that tells nothing or the pattern out does not
    /// find the seam as a dart.
    fn press_as_tailors_do(&mut self, index: usize) -> Result<(), EditError> {
        let Some((toward, _)) = self.tailors_press(index) else {
            return Ok(());
        };
        match self.pressed_legs(index) {
            Some([now, _]) if now != toward => {
                let second = !self.seams[index].press_second;
                self.press_dart(index, second)
            }
            _ => Ok(()),
        }
    }

    /// Dart seam `index`'s mouth vertices, the one of the leg its intake is pressed to
    /// first (the one its press mark points at in the pattern); None where the pattern out
    /// does not find the seam as a dart.
    pub fn pressed_legs(&self, index: usize) -> Option<[u32; 2]> {
        let &(a, b) = self.seams.get(index)?.pairs.first()?;
        let label = super::sewing_pattern::seam_label(index);
        let to = (super::sewing_pattern::view_pieces(self).iter())
            .flat_map(|p| &p.presses)
            .find(|(l, _, _)| l.trim_end_matches(|c: char| c.is_ascii_digit()) == label)
            .map(|&(_, _, to)| Vec2::new(to.x as f32, to.y as f32))?;
        let near = |v: u32| {
            (self.places_of(v, true).iter())
                .map(|q| q.distance(to))
                .fold(f32::INFINITY, f32::min)
        };
        Some(if near(a) <= near(b) { [a, b] } else { [b, a] })
    }

    /// Seam `index`, a dart, pressed toward its second leg (`second`: the one its
    /// piece's outline reaches last going counter-clockwise) or its first, undoably: the
    /// cap bridging the dart's mouth in the pattern's cut line is folded that way
    /// (`sewing_pattern::dart`). Refused, with nothing changed, for a seam that is not
    /// there or is no dart in the pattern as it is now.
    pub fn press_dart(&mut self, index: usize, second: bool) -> Result<(), EditError> {
        let count = self.seams.len();
        let Some(old) = self.seams.get(index).cloned() else {
            return Err(EditError::NoSeam { index, count });
        };
        let label = super::sewing_pattern::seam_label(index);
        let is_dart = (super::sewing_pattern::view_pieces(self).iter())
            .flat_map(|p| &p.presses)
            .any(|(l, _, _)| l.trim_end_matches(|c: char| c.is_ascii_digit()) == label);
        if !is_dart {
            return Err(EditError::NotADart { label });
        }
        if old.press_second == second {
            return Ok(());
        }
        let new = super::Seam {
            press_second: second,
            ..old.clone()
        };
        self.commit(
            "press dart",
            vec![super::Prim::Seam {
                index: index as u32,
                old: Some(old),
                new: Some(new),
            }],
        )
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    /// A dart 60 mm wide and 0.5 m long into a 1 m square of 8 x 8 cells (12.5 cm): one
    /// step, its legs seamed from the edge to the point.
    #[test]
    fn a_dart_into_a_coarse_square_is_one_step() {
        let mut d = super::super::sewing_pattern::tests::square(1.0, 8);
        let r = d.dart_on_plane(Vec2::ZERO, Vec2::new(0.0, -0.9), 0.06);
        let pairs = r.unwrap();
        assert!(pairs >= 3, "{pairs}");
        assert_eq!(d.history.undo_len(), 1);
        // Nothing is sewn to the square: its mouth is on a free edge.
        assert_eq!(d.dart_mouth_sewn(d.seams.len() - 1), Some(false));
        assert_eq!(d.dart_mouth_sewn(d.seams.len()), None);
    }

    /// New darts are pressed as a tailor presses them: on the dress round the mannequin,
    /// a dart up from the hem on either side of the front toward the middle (the
    /// centre front), one in from the side seam downward; one at the middle as it is.
    #[test]
    fn new_darts_are_pressed_toward_the_middle_or_down() {
        use crate::scenario::{ScenarioConfig, ScenarioName, build_scene};
        let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
        cfg.piece_edge = 0.03;
        let (mut d, _) = build_scene(&cfg).unwrap();
        let (lo, hi) = crate::mesh::bounds2(&d.pieces[0].outline.loops[0]);
        let off = d.pieces[0].offset;
        let at = |x: f32, y: f32| Vec2::new(x, y) + off;
        let body = d.sim.body.as_ref().unwrap().bounds();
        let middle = 0.5 * (body.0.x + body.1.x);
        let legs = |d: &super::Design| {
            let [to, other] = d.pressed_legs(d.seams.len() - 1).unwrap();
            [to, other].map(|v| d.sim.cloth.x[v as usize])
        };
        for x in [lo.x + 0.12, hi.x - 0.12] {
            d.dart_on_plane(at(x, lo.y + 0.33), at(x, lo.y - 0.06), 0.04)
                .unwrap();
            let [to, other] = legs(&d);
            assert!(
                (to.x - middle).abs() < (other.x - middle).abs(),
                "at {x}: pressed to {to}, not {other}"
            );
            // One operation: the press goes with the dart.
            d.undo().unwrap();
            assert!(
                d.seams.len() == 4 || d.seams.is_empty(),
                "{}",
                d.seams.len()
            );
        }
        d.dart_on_plane(
            at(lo.x + 0.12, hi.y - 0.38),
            at(lo.x - 0.06, hi.y - 0.40),
            0.04,
        )
        .unwrap();
        let [to, other] = legs(&d);
        assert!(to.y < other.y, "pressed to {to}, not {other}");
        d.undo().unwrap();
        // At the middle: left pressed toward its first leg.
        let mid = 0.5 * (lo.x + hi.x);
        d.dart_on_plane(at(mid, lo.y + 0.33), at(mid, lo.y - 0.06), 0.04)
            .unwrap();
        assert!(!d.seams.last().unwrap().press_second);
    }

    /// On the shipped dress sewn and draped at 3 cm edges, a dart into the front's
    /// welded side seam is told that its mouth is on a sewn seam; one up from the hem,
    /// or into the side before the seam has welded, is not.
    #[test]
    fn a_dart_into_a_sewn_seam_is_told_and_one_from_the_hem_is_not() {
        let mut d = crate::design::tests::sewn_dress(0.03, 0);
        let (lo, hi) = crate::mesh::bounds2(&d.pieces[0].outline.loops[0]);
        let off = d.pieces[0].offset;
        let side = |d: &mut super::Design| {
            let at = |x: f32, below: f32| Vec2::new(lo.x + x, hi.y - below) + off;
            d.dart_on_plane(at(0.12, 0.38), at(-0.06, 0.40), 0.04)
                .unwrap();
            d.dart_mouth_sewn(d.seams.len() - 1)
        };
        // Before a frame: nothing welded yet.
        assert_eq!(side(&mut d), Some(false));
        d.undo().unwrap();
        for _ in 0..240 {
            d.step().unwrap();
        }
        let welded = |d: &super::Design, k: usize| d.seams[k].pairs.iter().all(|p| p.0 == p.1);
        assert!(
            (0..4).all(|k| welded(&d, k)),
            "the dress's seams are not all welded"
        );
        assert_eq!(side(&mut d), Some(true));
        d.undo().unwrap();
        let up = |y: f32| Vec2::new(lo.x + 0.12, lo.y + y) + off;
        d.dart_on_plane(up(0.33), up(-0.06), 0.04).unwrap();
        assert_eq!(d.dart_mouth_sewn(d.seams.len() - 1), Some(false));
    }
}
