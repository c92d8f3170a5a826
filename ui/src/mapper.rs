//! Keeps the map the 3D view shows (`stretch`: the threads' stretch or the ease) current
//! with the store: worked out again when the frame, the mesh, the body, what it shows or
//! its scale changes, dropped while it is hidden; and the tape measure's girths (`fit`).

use glam::Vec3;
use sim_core::collision::Body;

use crate::store::Store;
use crate::stretch::{MapKind, StretchMap, StretchView};

/// The body as a surface to measure the ease against, by the body version it is of
/// (built when the ease map first needs it; None for a body that is no surface).
#[derive(Default)]
pub struct Mapper {
    measured_body: Option<(u64, Option<Body>)>,
    fitter: crate::fit::Fitter,
}

impl Mapper {
    /// Puts the map `view` asks for of the newest frame in `store.stretch`.
    pub fn update(&mut self, store: &mut Store, view: StretchView) {
        self.fitter.update(store, view.fit, view.fit_at);
        if !view.on {
            store.stretch = None;
            return;
        }
        let of = (store.frame, store.mesh_generation, store.body_version);
        let fresh = store.stretch.as_ref().is_some_and(|m| {
            m.of == of
                && m.kind == view.kind
                && m.full == view.scale()
                && m.vertex.len() == store.x.len()
        });
        if fresh {
            return;
        }
        let map = match view.kind {
            MapKind::Stretch => store
                .mesh
                .as_ref()
                .and_then(|m| StretchMap::of(&m.corners, m.vertices, &store.x, view.full)),
            MapKind::Ease => self
                .body_of(store)
                .filter(|_| store.mesh.is_some())
                .map(|b| StretchMap::ease(b, &store.x, view.ease_full)),
        };
        store.stretch = map.map(|m| StretchMap { of, ..m });
    }

    /// The store's body as a surface to measure distances from, built again when the
    /// body changes (None without a body, or for one that is no surface).
    fn body_of(&mut self, store: &Store) -> Option<&Body> {
        let version = store.body_version;
        if self
            .measured_body
            .as_ref()
            .is_none_or(|(v, _)| *v != version)
        {
            let body = store.body.as_ref().and_then(|(v, t)| {
                let v = v.iter().map(|p| Vec3::from(*p)).collect();
                Body::new("studio body", v, t.clone(), None).ok()
            });
            self.measured_body = Some((version, body));
        }
        self.measured_body.as_ref()?.1.as_ref()
    }
}
