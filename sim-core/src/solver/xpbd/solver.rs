//! The XPBD model behind the `Solver` trait: its frame (`step`), following edits (`edit`),
//! a material change in place.

use super::groups::Loc;
use super::step::Xpbd;
use crate::error::ConfigError;
use crate::solver::material::{Material, ModelKind};
use crate::solver::model::{Drive, FrameInput, Solver, StepError};
use crate::solver::state::Cloth;

impl Solver for Xpbd {
    fn kind(&self) -> ModelKind {
        ModelKind::Xpbd
    }

    fn step(&mut self, frame: FrameInput<'_>, drive: &mut Drive<'_, '_>) -> Result<(), StepError> {
        let FrameInput {
            cloth,
            body,
            contacts,
            env,
            substeps,
        } = frame;
        self.frame(cloth, body, contacts, env, substeps, drive);
        Ok(())
    }

    fn constraint_count(&self, _cloth: &Cloth) -> usize {
        let membranes = self
            .membrane_loc
            .iter()
            .filter(|l| **l != Loc::None)
            .count();
        3 * membranes + self.bend_loc.len()
    }

    fn editable(&self) -> bool {
        true
    }

    fn sync(&mut self, cloth: &Cloth, tris: &[u32], edges: &[u64], verts: &[u32]) {
        self.follow_edit(cloth, tris, edges, verts);
        self.settle.edited(cloth, tris);
        // An edit that touched no triangle, edge or vertex (paint) leaves the guard's
        // mesh and pairs as they were (its rebuild is 2.5 ms on 16k vertices); one that
        // touched vertices only (a pin) changes which are free, and the next search,
        // seeing that, searches in full.
        if let Some(g) = &mut self.guard {
            if !(tris.is_empty() && edges.is_empty()) {
                g.follow_edit(cloth, edges, verts);
            } else if !verts.is_empty() {
                g.refresh_free(cloth);
            }
        }
    }

    fn pinned(&mut self, cloth: &Cloth, vertex: u32) {
        self.follow_edit(cloth, &[], &[], &[vertex]);
        if let Some(g) = &mut self.guard {
            g.refresh_free(cloth);
        }
    }

    /// Rebuilds the constraints from the live mesh with the new stiffness, keeping the
    /// stretch limits' lattice (rescaled), the substep-start positions and the threads.
    fn set_material(&mut self, cloth: &mut Cloth, material: &Material) -> Result<(), ConfigError> {
        if material.density != self.material.density {
            cloth.set_density(material.density);
        }
        self.rebuild(cloth, material);
        Ok(())
    }

    fn set_threads(&mut self, threads: usize) {
        self.threads = threads;
    }

    fn contact_stats(&self) -> Option<crate::solver::model::ContactStats> {
        self.guard.as_ref().map(|g| g.stats)
    }

    fn never_crosses(&self) -> bool {
        self.guard.is_some()
    }

    fn set_guard(&mut self, cloth: &Cloth, on: bool) -> bool {
        if on != self.guard.is_some() {
            self.guard = on.then(|| super::guard::Guard::new(cloth));
        }
        true
    }
}
