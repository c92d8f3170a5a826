//! The VBD model behind the `Solver` trait: its frame, following edits (the elements and
//! pairs are rebuilt from the live mesh), a material change in place.

use super::step::Vbd;
use crate::error::ConfigError;
use crate::solver::material::{Material, ModelKind};
use crate::solver::model::{ContactStats, Drive, FrameInput, Solver, StepError};
use crate::solver::state::Cloth;

impl Solver for Vbd {
    fn kind(&self) -> ModelKind {
        ModelKind::Vbd
    }

    fn step(&mut self, frame: FrameInput<'_>, drive: &mut Drive<'_, '_>) -> Result<(), StepError> {
        let FrameInput {
            cloth,
            body,
            env,
            substeps,
            ..
        } = frame;
        self.frame(cloth, body, env, substeps, drive);
        Ok(())
    }

    fn constraint_count(&self, _cloth: &Cloth) -> usize {
        3 * self.elastic.membranes.len() + self.elastic.bends.len()
    }

    fn editable(&self) -> bool {
        true
    }

    fn sync(&mut self, cloth: &Cloth, _tris: &[u32], _edges: &[u64], _verts: &[u32]) {
        self.rebuild(cloth);
    }

    fn pinned(&mut self, cloth: &Cloth, _vertex: u32) {
        self.refresh_free(cloth);
    }

    fn set_material(&mut self, cloth: &mut Cloth, material: &Material) -> Result<(), ConfigError> {
        if material.density != self.material.density {
            cloth.set_density(material.density);
        }
        self.material = *material;
        self.rebuild(cloth);
        Ok(())
    }

    fn set_threads(&mut self, threads: usize) {
        self.threads = threads;
    }

    fn contact_stats(&self) -> Option<ContactStats> {
        Some(self.stats)
    }

    fn own_contact(&self) -> bool {
        true
    }

    fn never_crosses(&self) -> bool {
        self.contact
    }
}
