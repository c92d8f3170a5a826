//! Keeping the XPBD solver in step with an edited cloth without rebuilding it.
//!
//! The coloured, SIMD-packed groups are built once. An edit then touches only what it
//! changed: a removed or rewritten triangle's membrane (and a hinge whose triangles
//! changed) is switched off in place (its lane's coefficients and inverse masses become
//! zero), and the new constraint goes to a short list solved after the groups. A vertex
//! whose mass changed gets its inverse mass rewritten in the lanes that hold it.

use glam::Vec3;

use super::groups::{Group, Loc};
use super::simd::LANES;
use super::step::Xpbd;
use super::tethers::tethers;
use crate::solver::constraints::{live_bend, membrane_of, weigh_membrane};
use crate::solver::material::Material;
use crate::solver::state::Cloth;

/// Where item `item` of a coloured list is: `Ok((colour, block, lane))` when packed in a
/// SIMD block, `Err((colour, item))` when in the colour's scalar remainder.
fn locate(colors: &[usize], item: usize) -> Result<(usize, usize, usize), (usize, usize)> {
    let c = colors.partition_point(|&s| s <= item).saturating_sub(1);
    let (r0, r1) = (colors[c], colors[c + 1]);
    let full = r0 + (r1 - r0) / LANES * LANES;
    if item < full {
        Ok((c, (item - r0) / LANES, (item - r0) % LANES))
    } else {
        Err((c, item))
    }
}

impl Group {
    fn disable_membrane(&mut self, item: usize) {
        if let Ok((c, b, l)) = locate(&self.membrane_colors, item) {
            self.membrane_batches[c].0[b].disable(l);
        }
        let m = &mut self.membranes[item];
        m.c = [0.0; 3];
        m.d = [0.0; 3];
    }

    fn disable_bend(&mut self, item: usize) {
        if let Ok((c, b, l)) = locate(&self.bend_colors, item) {
            self.bend_batches[c].0[b].disable(l);
        }
        let h = &mut self.bends[item];
        h.k = [0.0; 4];
        h.rest = Vec3::ZERO;
    }

    /// Rewrites vertex `v`'s inverse mass in the packed lanes of membrane `item`.
    fn membrane_w(&mut self, item: usize, v: u32, w: f32) {
        let local = v.wrapping_sub(self.off);
        let Some(corner) = self.membranes[item].v.iter().position(|&i| i == local) else {
            return;
        };
        if let Ok((c, b, l)) = locate(&self.membrane_colors, item) {
            self.membrane_batches[c].0[b].set_w(l, corner, w);
        }
    }

    fn bend_w(&mut self, item: usize, v: u32, w: f32) {
        let local = v.wrapping_sub(self.off);
        let Some(corner) = self.bends[item].v.iter().position(|&i| i == local) else {
            return;
        };
        if let Ok((c, b, l)) = locate(&self.bend_colors, item) {
            self.bend_batches[c].0[b].set_w(l, corner, w);
        }
    }
}

impl Xpbd {
    /// Builds the solver afresh for `cloth` and `material`, keeping what is not the
    /// material's: the stretch limits' lattice (rescaled), the substep's start positions,
    /// the thread count, the guard (whose `rebuild` the caller runs if the mesh changed)
    /// and any settling. A material change once dropped the guard with the rest, so a
    /// studio user's Apply or fabric choice let the cloth cross again.
    pub(super) fn rebuild(&mut self, cloth: &Cloth, material: &Material) {
        let limits = std::mem::take(&mut self.limits);
        let mut fresh = Xpbd::with_limits(cloth, material, Some(limits));
        fresh.prev = std::mem::take(&mut self.prev);
        fresh.threads = self.threads;
        fresh.guard = self.guard.take();
        fresh.settle = std::mem::take(&mut self.settle);
        *self = fresh;
    }

    /// Brings the solver in line with `cloth` after an edit: `tris` are the triangle
    /// slots that changed, `edges` the keys of every edge of their old and new triangles,
    /// `verts` the vertices whose mass or pin changed. New vertices (past the solver's
    /// arrays) are picked up from `cloth`.
    pub fn follow_edit(&mut self, cloth: &Cloth, tris: &[u32], edges: &[u64], verts: &[u32]) {
        let n = cloth.len();
        if n < self.built {
            // Vertices went that the packed groups were built with (a material change
            // after a cut, then its undo, say): a switched-off constraint there still
            // names them, so rebuild rather than leave an index past the cloth (found by
            // the commands fuzz target). Vertices added since the build live only in the
            // edits' own constraints, which the removed triangles take with them below.
            self.prev.truncate(n);
            let material = self.material;
            self.rebuild(cloth, &material);
            return;
        }
        // Vertices added by edits and now undone.
        self.prev.truncate(n);
        self.normals.truncate(n);
        self.area.truncate(n);
        for i in self.prev.len()..n {
            self.prev.push(cloth.x[i]);
            self.normals.push(Vec3::Y);
            self.area.push(0.0);
        }
        if self.membrane_loc.len() < cloth.live.slots() {
            self.membrane_loc.resize(cloth.live.slots(), Loc::None);
        }
        for &slot in tris {
            self.remove_membrane(slot);
            if let Some(t) = cloth.live.tri(slot) {
                let m = membrane_of(t.v, slot, t.rest, t.uv);
                let m = weigh_membrane(m, &cloth.zones, &self.material, &t.rest);
                self.membrane_loc[slot as usize] = Loc::Extra(self.extra_membranes.len() as u32);
                self.extra_membranes.push(m);
            }
        }
        for &key in edges {
            self.remove_bend(key);
            if let Some(b) = live_bend(&cloth.live, key, &self.material, &cloth.zones, &self.shares)
            {
                self.bend_loc
                    .insert(key, Loc::Extra(self.extra_bends.len() as u32));
                self.extra_bends.push(b);
            }
        }
        for &v in verts {
            let i = v as usize;
            if i >= n {
                continue;
            }
            let w = cloth.inv_mass[i];
            self.area[i] = cloth
                .live
                .tris_of(v)
                .iter()
                .filter_map(|&t| cloth.live.tri(t))
                .map(|t| t.rest_area() / 3.0)
                .sum();
            for &t in cloth.live.tris_of(v) {
                if let Some(Loc::Group { group, item }) = self.membrane_loc.get(t as usize) {
                    self.groups[*group as usize].membrane_w(*item as usize, v, w);
                }
                let Some(tri) = cloth.live.tri(t) else {
                    continue;
                };
                for (a, b, _) in tri.edges() {
                    if let Some(Loc::Group { group, item }) =
                        self.bend_loc.get(&crate::mesh::edge_key(a, b))
                    {
                        self.groups[*group as usize].bend_w(*item as usize, v, w);
                    }
                }
            }
        }
        if !tris.is_empty() || !verts.is_empty() {
            self.tethers = tethers(cloth, &self.material);
            let mut touched: Vec<u32> = edges
                .iter()
                .flat_map(|&k| {
                    let (a, b) = crate::mesh::edge_ends(k);
                    [a, b]
                })
                .chain(verts.iter().copied())
                .collect();
            touched.sort_unstable();
            touched.dedup();
            self.limits.update(cloth, &touched);
        }
    }

    fn remove_membrane(&mut self, slot: u32) {
        let Some(loc) = self.membrane_loc.get_mut(slot as usize) else {
            return;
        };
        match std::mem::replace(loc, Loc::None) {
            Loc::None => {}
            Loc::Group { group, item } => {
                self.groups[group as usize].disable_membrane(item as usize);
            }
            Loc::Extra(k) => {
                self.extra_membranes.swap_remove(k as usize);
                if let Some(moved) = self.extra_membranes.get(k as usize) {
                    self.membrane_loc[moved.id as usize] = Loc::Extra(k);
                }
            }
        }
    }

    fn remove_bend(&mut self, key: u64) {
        match self.bend_loc.remove(&key) {
            None | Some(Loc::None) => {}
            Some(Loc::Group { group, item }) => {
                self.groups[group as usize].disable_bend(item as usize);
            }
            Some(Loc::Extra(k)) => {
                self.extra_bends.swap_remove(k as usize);
                if let Some(moved) = self.extra_bends.get(k as usize) {
                    self.bend_loc.insert(moved.key, Loc::Extra(k));
                }
            }
        }
    }

    /// Constraints added by edits since the solver was built (solved one by one).
    pub fn extra_count(&self) -> usize {
        self.extra_membranes.len() + self.extra_bends.len()
    }
}
