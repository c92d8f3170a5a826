//! The paper's operations on the live cloth (pinch, tear, cut, sew, paint) plus pins,
//! with undo and redo.
//!
//! Every change to the design is a list of primitive edits ([`Prim`]), each of which
//! knows its inverse. An operation builds its list, applies it as one transaction (if any
//! primitive fails, those already applied are rolled back and the error is returned with
//! the design unchanged), and pushes it on the history; undo applies the inverses in
//! reverse order. After applying, only what the primitives touched is brought up to date:
//! the touched vertices' masses, the solver's constraints for the touched triangles and
//! edges (see `cloth::xpbd_edit`), and the contact cache's size.

pub mod design;
pub mod export;
mod history;
mod ops;
mod paint;
mod pattern;
mod seam;

use glam::Vec3;

pub use history::History;
pub use ops::{PenInput, Pinch, TearMode, TearSettings};
pub use paint::{PaintPatch, TILE, Texture};
pub(crate) use seam::stitch;
pub use seam::{STITCH_FORCE, Seam};

use crate::cloth::Simulation;
use crate::cloth::sim::Solver;
use crate::error::GeometryError;
use crate::mesh::{Tri, edge_key};

/// Why an operation was refused. The design is unchanged when one is returned.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EditError {
    #[error("operations need the xpbd model (this simulation runs {0})")]
    Model(&'static str),
    #[error("vertex {0} does not exist")]
    NoVertex(u32),
    #[error("vertex {0} was removed (no triangle uses it any more)")]
    RemovedVertex(u32),
    #[error("cannot sew vertex {0} to itself")]
    SewSelf(u32),
    #[error("vertex {0} is inside the cloth; only vertices on its border can be sewn")]
    SewInterior(u32),
    #[error("vertices {0} and {1} already share a triangle")]
    SewNeighbours(u32, u32),
    #[error("nothing to cut at vertex {0}: all its triangles lie on one side of the cut")]
    NothingToCut(u32),
    #[error("the cut direction is zero or not finite")]
    BadDirection,
    #[error("the stroke crosses no vertex of the cloth")]
    EmptyStroke,
    #[error("no cloth within {radius} m of the pointer")]
    NothingNear { radius: f32 },
    #[error("edge ({0}, {1}) does not exist")]
    NoEdge(u32, u32),
    #[error("{name} must be {rule}, got {value}")]
    BadValue {
        name: &'static str,
        rule: &'static str,
        value: String,
    },
    #[error("the edit would break the mesh: {0}")]
    Geometry(#[from] GeometryError),
    #[error("({0}, {1}) is not an edge on the cloth's border")]
    NotBorderEdge(u32, u32),
    #[error("the two seam paths share vertex {0}")]
    SeamOverlap(u32),
    #[error("the design changed underneath this edit (seam {0})")]
    StaleSeam(u32),
    #[error("the design changed underneath this edit (triangle slot {0})")]
    Stale(u32),
    #[error("no {what} on the pattern there")]
    NothingOnPattern { what: &'static str },
    #[error("nothing to undo")]
    NothingToUndo,
    #[error("nothing to redo")]
    NothingToRedo,
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
    /// A vertex appended at `index` (always the end) with this position and velocity.
    AddVertex {
        index: u32,
        x: Vec3,
        v: Vec3,
    },
    /// The last vertex removed (it must be unused): the inverse of `AddVertex`.
    RemoveVertex {
        index: u32,
        x: Vec3,
        v: Vec3,
    },
    /// A vertex moved (its velocity too).
    Move {
        vertex: u32,
        old: (Vec3, Vec3),
        new: (Vec3, Vec3),
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
}

impl Prim {
    pub fn inverse(&self) -> Prim {
        match self.clone() {
            Prim::Tri { slot, old, new } => Prim::Tri {
                slot,
                old: new,
                new: old,
            },
            Prim::AddVertex { index, x, v } => Prim::RemoveVertex { index, x, v },
            Prim::RemoveVertex { index, x, v } => Prim::AddVertex { index, x, v },
            Prim::Move { vertex, old, new } => Prim::Move {
                vertex,
                old: new,
                new: old,
            },
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
}

impl Edit {
    pub fn bytes(&self) -> usize {
        self.prims.iter().map(Prim::bytes).sum::<usize>() + std::mem::size_of::<Edit>()
    }
}

/// What a batch of primitives touched, for the incremental update.
#[derive(Default)]
struct Touched {
    tris: Vec<u32>,
    edges: Vec<u64>,
    verts: Vec<u32>,
}

impl Touched {
    fn tri(&mut self, slot: u32, t: Option<&Tri>) {
        self.tris.push(slot);
        if let Some(t) = t {
            for (a, b, _) in t.edges() {
                self.edges.push(edge_key(a, b));
            }
            self.verts.extend_from_slice(&t.v);
        }
    }
}

impl Simulation {
    pub(crate) fn check_editable(&self) -> Result<(), EditError> {
        match self.solver {
            Solver::Xpbd(_) => Ok(()),
            Solver::Seed(_) => Err(EditError::Model("seed")),
            Solver::Implicit(_) => Err(EditError::Model("implicit")),
        }
    }

    /// A vertex that exists and is still part of the cloth.
    pub fn check_vertex(&self, v: u32) -> Result<(), EditError> {
        if v as usize >= self.cloth.len() {
            Err(EditError::NoVertex(v))
        } else if !self.cloth.live.vertex_alive(v) {
            Err(EditError::RemovedVertex(v))
        } else {
            Ok(())
        }
    }

    /// Applies one primitive to the cloth, recording what it touched.
    fn apply_prim(&mut self, p: &Prim, touched: &mut Touched) -> Result<(), EditError> {
        let cloth = &mut self.cloth;
        match p {
            Prim::Tri { slot, old, new } => {
                if cloth.live.tri(*slot) != old.as_ref() {
                    return Err(EditError::Stale(*slot));
                }
                cloth.live.set(*slot, *new)?;
                touched.tri(*slot, old.as_ref());
                touched.tri(*slot, new.as_ref());
            }
            Prim::AddVertex { index, x, v } => {
                if *index as usize != cloth.len() || !x.is_finite() || !v.is_finite() {
                    return Err(EditError::NoVertex(*index));
                }
                cloth.live.push_vertex();
                cloth.x.push(*x);
                cloth.v.push(*v);
                cloth.mass.push(0.0);
                cloth.inv_mass.push(0.0);
                cloth.pinned.push(false);
            }
            Prim::RemoveVertex { index, .. } => {
                if *index as usize + 1 != cloth.len() || !cloth.live.pop_vertex() {
                    return Err(EditError::NoVertex(*index));
                }
                cloth.x.pop();
                cloth.v.pop();
                cloth.mass.pop();
                cloth.inv_mass.pop();
                cloth.pinned.pop();
                touched.verts.retain(|&i| i != *index);
            }
            Prim::Move { vertex, new, .. } => {
                let i = *vertex as usize;
                if i >= cloth.len() || !new.0.is_finite() || !new.1.is_finite() {
                    return Err(EditError::NoVertex(*vertex));
                }
                cloth.x[i] = new.0;
                cloth.v[i] = new.1;
            }
            Prim::Pin { vertex, new, .. } => {
                let i = *vertex as usize;
                if i >= cloth.len() {
                    return Err(EditError::NoVertex(*vertex));
                }
                cloth.set_pinned(i, *new);
                touched.verts.push(*vertex);
            }
            Prim::Paint(patch) => self.texture.apply(patch, false),
            Prim::Seam { index, old, new } => self.set_seam(*index, old, new)?,
        }
        Ok(())
    }

    /// Applies `prims` as one transaction and brings masses, solver and contacts up to
    /// date. On failure, rolls back and returns the error: nothing changed.
    pub(crate) fn apply_prims(&mut self, prims: &[Prim]) -> Result<(), EditError> {
        self.check_editable()?;
        let mut touched = Touched::default();
        for (k, p) in prims.iter().enumerate() {
            if let Err(e) = self.apply_prim(p, &mut touched) {
                let mut ignore = Touched::default();
                for q in prims[..k].iter().rev() {
                    // The inverse of an applied primitive always applies.
                    let _ = self.apply_prim(&q.inverse(), &mut ignore);
                }
                self.sync(&mut ignore);
                return Err(e);
            }
        }
        self.sync(&mut touched);
        Ok(())
    }

    fn sync(&mut self, touched: &mut Touched) {
        touched.verts.sort_unstable();
        touched.verts.dedup();
        touched.verts.retain(|&v| (v as usize) < self.cloth.len());
        touched.edges.sort_unstable();
        touched.edges.dedup();
        touched.tris.sort_unstable();
        touched.tris.dedup();
        for &v in &touched.verts {
            self.cloth.update_mass(v as usize, self.material.density);
        }
        self.contacts.resize(self.cloth.len());
        if let Solver::Xpbd(s) = &mut self.solver {
            s.sync(&self.cloth, &touched.tris, &touched.edges, &touched.verts);
        }
    }

    /// Applies an operation's primitives and records it for undo.
    pub(crate) fn commit(
        &mut self,
        label: &'static str,
        prims: Vec<Prim>,
    ) -> Result<(), EditError> {
        self.apply_prims(&prims)?;
        self.history.push(Edit { label, prims });
        Ok(())
    }

    /// Undoes the last operation; returns its label.
    pub fn undo(&mut self) -> Result<&'static str, EditError> {
        let edit = self.history.pop_undo().ok_or(EditError::NothingToUndo)?;
        let inverse: Vec<Prim> = edit.prims.iter().rev().map(Prim::inverse).collect();
        if let Err(e) = self.apply_prims(&inverse) {
            self.history.clear();
            return Err(e);
        }
        let label = edit.label;
        self.history.push_redo(edit);
        Ok(label)
    }

    /// Redoes the last undone operation; returns its label.
    pub fn redo(&mut self) -> Result<&'static str, EditError> {
        let edit = self.history.pop_redo().ok_or(EditError::NothingToRedo)?;
        if let Err(e) = self.apply_prims(&edit.prims) {
            self.history.clear();
            return Err(e);
        }
        let label = edit.label;
        self.history.push_after_redo(edit);
        Ok(label)
    }

    /// Checks the live mesh and state: indices, manifold edges, no degenerate triangle,
    /// UVs in range, nothing NaN.
    pub fn validate(&self) -> Result<(), GeometryError> {
        self.cloth.live.validate(&self.cloth.x)?;
        if let Some(i) = self.cloth.v.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite { vertex: i });
        }
        Ok(())
    }
}
