//! Every change to the design is a list of primitive edits ([`Prim`]), each of which
//! knows its inverse; an operation's list is one [`Edit`] in the history. Applying them is
//! `transaction`'s.

use glam::{Vec2, Vec3};

use super::parts::Seam;
use super::pieces::PieceRecord;
use super::texture::PaintPatch;
use crate::mesh::Tri;

/// Where an added vertex lies: at share `s` of the way from vertex `a` to vertex `b`
/// (`a == b`: a copy of `a`, a cut's other side). Applied, it is placed between them as
/// they stand then, so that a cut redone after the cloth has moved is made where the
/// cloth is (placed where the cut had found it, its copy stood 40 cm off its triangles on
/// a cloth that had fallen since the undo).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Between {
    pub a: u32,
    pub b: u32,
    pub s: f32,
}

impl Between {
    /// The position and velocity between `a` and `b` in `x` and `v`; `None` when either
    /// is not there.
    pub fn place(&self, x: &[Vec3], v: &[Vec3]) -> Option<(Vec3, Vec3)> {
        let (a, b) = (self.a as usize, self.b as usize);
        let (xa, xb, va, vb) = (x.get(a)?, x.get(b)?, v.get(a)?, v.get(b)?);
        Some((xa.lerp(*xb, self.s), va.lerp(*vb, self.s)))
    }

    /// The point `s` of the way from `xa` to `xb`, as `xa + (xb - xa) s` (a zip's place
    /// on its edge; [`Between::place`] rounds as a split edge's new vertex does).
    pub fn along(&self, xa: Vec3, xb: Vec3) -> Vec3 {
        xa + (xb - xa) * self.s
    }
}

/// Where a merge puts its vertex: halfway between the two (a sew), or at either's place
/// (a seam's weld whose middle would cross).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MergeAt {
    Middle,
    A,
    B,
}

impl MergeAt {
    /// The place between `xa` and `xb`.
    pub fn of(self, xa: Vec3, xb: Vec3) -> Vec3 {
        match self {
            MergeAt::Middle => (xa + xb) * 0.5,
            MergeAt::A => xa,
            MergeAt::B => xb,
        }
    }
}

/// One reversible change.
#[derive(Clone, Debug, PartialEq)]
pub enum Prim {
    /// Triangle slot `slot` goes from `old` to `new` (`None`: no triangle).
    Tri {
        slot: u32,
        old: Option<Tri>,
        new: Option<Tri>,
    },
    /// Triangle slot `slot`'s texture coordinates go from `old` to `new`: moved and
    /// scaled alike in both directions (the texture's room for a new piece), so its warp
    /// direction, and so what the models solve, stays as it was.
    Uv {
        slot: u32,
        old: [Vec2; 3],
        new: [Vec2; 3],
    },
    /// A vertex appended at `index` (always the end) with this position and velocity,
    /// or, made `from` others ([`Between`]: a cut's copy, a split edge's new vertex),
    /// between them as they stand when it is applied.
    AddVertex {
        index: u32,
        x: Vec3,
        v: Vec3,
        from: Option<Between>,
    },
    /// The last vertex removed (it must be unused): the inverse of `AddVertex`.
    RemoveVertex {
        index: u32,
        x: Vec3,
        v: Vec3,
        from: Option<Between>,
    },
    /// A vertex moved (its velocity too).
    Move {
        vertex: u32,
        old: (Vec3, Vec3),
        new: (Vec3, Vec3),
    },
    /// Vertex `a` moved onto `b` (a sew, a seam's weld): to where `at` says between them
    /// as they stand, its velocity to the mean of theirs. `apart`: where `a` and `b` lay
    /// from that point when the edit was made; its inverse, [`Prim::Unmerge`], puts them
    /// so far from where `a` stands then, so that a sew undone, or redone, after the cloth
    /// has moved is taken apart, or made, where the cloth is (with absolute places, both
    /// went back where the sew had found them: 0.56 m off their triangles on a cloth that
    /// had fallen since).
    Merge {
        a: u32,
        b: u32,
        at: MergeAt,
        apart: [Vec3; 2],
    },
    /// The inverse of [`Prim::Merge`]: `a` and `b` go `apart` from where `a` stands,
    /// `b` with `a`'s velocity.
    Unmerge {
        a: u32,
        b: u32,
        at: MergeAt,
        apart: [Vec3; 2],
    },
    /// Vertex `vertex` moved onto the segment between two others (a seam's zip eases it
    /// into the edge across its slit), at `to` of the way from `to.a` as they stand
    /// ([`Between::along`]); `back`: where it lay from that point when the edit was made,
    /// which its inverse, [`Prim::MoveOff`], puts it at from where it stands. Its
    /// velocity stays.
    MoveOnto {
        vertex: u32,
        to: Between,
        back: Vec3,
    },
    /// The inverse of [`Prim::MoveOnto`]: `vertex` moved by `back` from where it stands.
    MoveOff {
        vertex: u32,
        to: Between,
        back: Vec3,
    },
    /// A vertex moved by `by` from wherever it is (a cut's sides parted: undone, they
    /// come back by as much, where the cloth has taken them since).
    Nudge {
        vertex: u32,
        by: Vec3,
    },
    Pin {
        vertex: u32,
        old: bool,
        new: bool,
    },
    Paint(PaintPatch),
    /// Seam `index` goes from `old` to `new` (`index == len` with `old == None` appends).
    Seam {
        index: u32,
        old: Option<Seam>,
        new: Option<Seam>,
    },
    /// The design's substeps a frame go from `old` to `new`: a piece added low under
    /// xpbd runs it firmer ([`Design::firm_with_last_edit`](super::Design)), and its
    /// undo takes that back with the piece.
    Substeps {
        old: u32,
        new: u32,
    },
    /// Piece record `index` goes from `old` to `new` (`index == len` with `old == None`
    /// appends; `new == None` removes the last).
    Piece {
        index: u32,
        old: Option<PieceRecord>,
        new: Option<PieceRecord>,
    },
}

impl Prim {
    /// Where the vertices this primitive places end up (up to two), `now` saying where a
    /// vertex stands before it (`None`: not there): the one definition of a move that
    /// applying the primitive ([`Design::apply_prims`](super::Design)) and the history's
    /// crossing check (`no_cross`) both follow. Primitives that place no vertex: none.
    pub fn placed(&self, now: impl Fn(u32) -> Option<Vec3>) -> [Option<(u32, Vec3)>; 2] {
        let one = |p: Option<(u32, Vec3)>| [p, None];
        match self {
            Prim::Move { vertex, new, .. } => one(Some((*vertex, new.0))),
            Prim::MoveOnto { vertex, to, .. } => one(now(to.a)
                .zip(now(to.b))
                .map(|(a, b)| (*vertex, to.along(a, b)))),
            Prim::MoveOff { vertex, back, .. } => one(now(*vertex).map(|p| (*vertex, p + *back))),
            Prim::Nudge { vertex, by } => one(now(*vertex).map(|p| (*vertex, p + *by))),
            Prim::Merge { a, b, at, .. } => {
                one(now(*a).zip(now(*b)).map(|(xa, xb)| (*a, at.of(xa, xb))))
            }
            Prim::Unmerge { a, b, apart, .. } => match now(*a) {
                Some(p) => [Some((*a, p + apart[0])), Some((*b, p + apart[1]))],
                None => [None, None],
            },
            Prim::AddVertex { index, x, from, .. } => {
                let between = from.and_then(|f| Some(now(f.a)?.lerp(now(f.b)?, f.s)));
                one(Some((*index, between.unwrap_or(*x))))
            }
            _ => [None, None],
        }
    }

    pub fn inverse(&self) -> Prim {
        match self.clone() {
            Prim::Tri { slot, old, new } => Prim::Tri {
                slot,
                old: new,
                new: old,
            },
            Prim::Uv { slot, old, new } => Prim::Uv {
                slot,
                old: new,
                new: old,
            },
            Prim::AddVertex { index, x, v, from } => Prim::RemoveVertex { index, x, v, from },
            Prim::RemoveVertex { index, x, v, from } => Prim::AddVertex { index, x, v, from },
            Prim::Move { vertex, old, new } => Prim::Move {
                vertex,
                old: new,
                new: old,
            },
            Prim::MoveOnto { vertex, to, back } => Prim::MoveOff { vertex, to, back },
            Prim::MoveOff { vertex, to, back } => Prim::MoveOnto { vertex, to, back },
            Prim::Merge { a, b, at, apart } => Prim::Unmerge { a, b, at, apart },
            Prim::Unmerge { a, b, at, apart } => Prim::Merge { a, b, at, apart },
            Prim::Nudge { vertex, by } => Prim::Nudge { vertex, by: -by },
            Prim::Pin { vertex, old, new } => Prim::Pin {
                vertex,
                old: new,
                new: old,
            },
            Prim::Paint(p) => Prim::Paint(p.inverse()),
            Prim::Seam { index, old, new } => Prim::Seam {
                index,
                old: new,
                new: old,
            },
            Prim::Piece { index, old, new } => Prim::Piece {
                index,
                old: new,
                new: old,
            },
            Prim::Substeps { old, new } => Prim::Substeps { old: new, new: old },
        }
    }

    /// Rough heap size, for the history's memory bound.
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Prim>()
            + match self {
                Prim::Paint(p) => p.bytes(),
                Prim::Seam { old, new, .. } => {
                    8 * (old.as_ref().map_or(0, |s| s.pairs.len())
                        + new.as_ref().map_or(0, |s| s.pairs.len()))
                }
                _ => 0,
            }
    }
}

/// One operation as the history keeps it.
#[derive(Clone, Debug)]
pub struct Edit {
    pub label: &'static str,
    pub prims: Vec<Prim>,
    /// Made by the design itself, not asked for: a seam's weld as its stitches close. An
    /// undo takes those that depend on the designer's operation under them back with it
    /// (undone alone, a weld closes again in the next frame; `commute`), and a redo
    /// brings them back with it.
    pub auto: bool,
}

impl Edit {
    pub fn bytes(&self) -> usize {
        self.prims.iter().map(Prim::bytes).sum::<usize>() + std::mem::size_of::<Edit>()
    }
}
