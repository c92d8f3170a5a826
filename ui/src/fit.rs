//! The tape measure: how the garment fits at the bust, the waist and the hips, beside
//! the body's own girth there (`sim_core::design::garment::fit`, worked out here from the
//! cloth and body cloth-sim already sends). The Fit section lists each level's body
//! girth, the garment's length round and the ease between; the 3D view draws the tape
//! round the body and the garment's loop at each level while it is shown.

use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use sim_core::design::garment::fit::{Figure, Girth};

use crate::store::Store;
use crate::stretch::StretchView;

/// How often the girths are measured again while the cloth moves: a section of the
/// cloth at three levels is well under a millisecond, but the numbers are read, not
/// watched.
const EVERY: Duration = Duration::from_millis(500);

/// The tape's colour round the body, and the garment's loop's.
pub const BODY_RING: [f32; 4] = [0.85, 0.85, 0.9, 1.0];
pub const GARMENT_RING: [f32; 4] = [0.2, 0.85, 0.55, 1.0];

/// The heights a designer's own level may be set to, m.
pub const AT_RANGE: (f32, f32) = (0.1, 2.5);

/// The name of a designer's own level.
pub const OWN_LEVEL: &str = "level";

/// What a figure was found for: the body's version, and the designer's level's bits.
type FigureKey = (u64, Option<u32>);

/// The body's levels, by the body version and the designer's level they were found for,
/// and when the girths were last measured and of which frame.
#[derive(Default)]
pub struct Fitter {
    figure: Option<(FigureKey, Option<Figure>)>,
    measured: Option<(Instant, u64, u64)>,
}

impl Fitter {
    /// Puts the girths of the newest frame in `store.fit` while `on`, at most every
    /// [`EVERY`], with the designer's own level `at` (m) among them where the body has a
    /// torso there; clears them when off.
    pub fn update(&mut self, store: &mut Store, on: bool, at: Option<f32>) {
        if !on {
            store.fit = None;
            self.measured = None;
            return;
        }
        let key = (store.body_version, at.map(f32::to_bits));
        if self.figure.as_ref().is_none_or(|(k, _)| *k != key) {
            let figure = store.body.as_ref().and_then(|(v, t)| {
                let v: Vec<Vec3> = v.iter().map(|p| Vec3::from(*p)).collect();
                let mut f = Figure::of(&v, t)?;
                if let Some(h) = at {
                    f.add_level(&v, t, OWN_LEVEL, h);
                }
                Some(f)
            });
            self.figure = Some((key, figure));
            self.measured = None;
        }
        let of = (store.frame, store.mesh_generation);
        let due = self
            .measured
            .is_none_or(|(at, f, g)| (f, g) != of && at.elapsed() >= EVERY);
        if !due {
            return;
        }
        self.measured = Some((Instant::now(), of.0, of.1));
        store.fit = match (self.figure.as_ref().and_then(|f| f.1.as_ref()), &store.mesh) {
            (Some(figure), Some(mesh)) => {
                let x: Vec<Vec3> = store.x.iter().map(|p| Vec3::from(*p)).collect();
                let tris: Vec<[u32; 3]> = (mesh.corners.chunks_exact(3))
                    .map(|t| [t[0].vertex, t[1].vertex, t[2].vertex])
                    .collect();
                Some(figure.fit(&x, &tris))
            }
            (Some(_), None) => Some(Vec::new()),
            (None, _) => None,
        };
    }
}

/// The rings the 3D view draws at each measured level: the tape round the body and the
/// garment's loop, as closed polylines with their colours.
pub fn rings(store: &Store) -> Vec<(Vec<Vec3>, [f32; 4])> {
    let lift = |ring: &[Vec2], y: f32| ring.iter().map(|p| Vec3::new(p.x, y, p.y)).collect();
    (store.fit.iter().flatten())
        .flat_map(|g| {
            [
                (lift(&g.body_ring, g.height_m), BODY_RING),
                (lift(&g.garment_ring, g.height_m), GARMENT_RING),
            ]
        })
        .filter(|(r, _): &(Vec<Vec3>, _)| r.len() >= 2)
        .collect()
}

/// The Fit section: a switch, a level of the designer's own, and each level's girths
/// while it is on.
pub fn controls(ui: &mut egui::Ui, view: &mut StretchView, fit: Option<&[Girth]>) {
    ui.checkbox(&mut view.fit, "Fit (tape measure)")
        .on_hover_text(
            "The garment's length round the bust, the waist and the hips beside the body's \
         girth there (a tape round the body bridges its hollows), and the ease between: \
         what a pattern is drafted with. The view draws the tape and the garment's loop at \
         each level.",
        );
    if !view.fit {
        return;
    }
    ui.horizontal(|ui| {
        let mut own = view.fit_at.is_some();
        ui.checkbox(&mut own, "Also at")
            .on_hover_text("A level of your own to measure at too: a hem, a high hip");
        let mut h = view.fit_at.unwrap_or(1.0);
        let drag = egui::DragValue::new(&mut h)
            .range(AT_RANGE.0..=AT_RANGE.1)
            .speed(0.005)
            .fixed_decimals(3)
            .suffix(" m");
        let changed = ui.add_enabled(own, drag).changed();
        if own != view.fit_at.is_some() || changed {
            view.fit_at = own.then_some(h);
        }
    });
    let Some(fit) = fit else {
        ui.label("The body is no standing figure: no bust, waist or hips to measure at");
        return;
    };
    if fit.is_empty() {
        ui.label("No cloth to measure yet");
        return;
    }
    egui::Grid::new("fit").striped(true).show(ui, |ui| {
        for h in ["", "body", "garment", "ease"] {
            ui.label(h);
        }
        ui.end_row();
        for g in fit {
            let name = match g.level {
                OWN_LEVEL => format!("at {:.2} m", g.height_m),
                l => l.to_string(),
            };
            ui.label(name)
                .on_hover_text(format!("{:.3} m above the floor", g.height_m));
            ui.label(format!("{:.1} cm", 100.0 * g.body_m));
            match (g.garment_m, g.ease_m) {
                (Some(m), Some(e)) => {
                    ui.label(format!("{:.1} cm", 100.0 * m));
                    ui.label(format!("{:+.1} cm", 100.0 * e));
                }
                _ => {
                    let why = match g.open_cloth_m {
                        Some(m) => format!(
                            "The cloth does not go round the body here: {} run{} of cloth, \
                             {:.1} cm in all (an armhole, an open seam)",
                            g.open_runs,
                            if g.open_runs == 1 { "" } else { "s" },
                            100.0 * m
                        ),
                        None => "No cloth at this level".to_string(),
                    };
                    ui.label(if g.open_cloth_m.is_some() {
                        "open"
                    } else {
                        "none"
                    })
                    .on_hover_text(why);
                    ui.label("");
                }
            }
            ui.end_row();
        }
    });
    if let Some(h) = view.fit_at
        && !fit.iter().any(|g| g.level == OWN_LEVEL)
    {
        ui.small(format!("No torso at {h:.2} m to measure round"));
    }
    ui.small("In the view: the tape round the body (white), the garment's loop (green)");
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tube of `n` sides round the y axis, radius `r`, from `y0` to `y1`.
    fn tube(n: u32, r: f32, y0: f32, y1: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let mut x = Vec::new();
        for k in 0..n {
            let a = std::f32::consts::TAU * k as f32 / n as f32;
            x.push([r * a.cos(), y0, r * a.sin()]);
            x.push([r * a.cos(), y1, r * a.sin()]);
        }
        let t = (0..n)
            .flat_map(|k| {
                let (a, b) = (2 * k, 2 * ((k + 1) % n));
                [[a, b, a + 1], [b, b + 1, a + 1]]
            })
            .collect();
        (x, t)
    }

    #[test]
    fn a_tube_on_the_mannequin_is_measured_and_drawn_at_each_level() {
        let b = sim_core::collision::body::mannequin().unwrap();
        let mut store = Store {
            body: Some((
                b.vertices.iter().map(|p| p.to_array()).collect(),
                b.triangles.clone(),
            )),
            body_version: 1,
            ..Store::default()
        };
        let mut fitter = Fitter::default();
        // Off: nothing measured.
        fitter.update(&mut store, false, None);
        assert!(store.fit.is_none());
        // A body but no cloth yet.
        fitter.update(&mut store, true, None);
        assert_eq!(store.fit.as_deref(), Some(&[][..]));
        let (x, t) = tube(64, 0.2, 0.8, 1.45);
        let corners = t
            .iter()
            .flatten()
            .map(|&v| shared::sim_to_ui::MeshCorner {
                vertex: v,
                ..Default::default()
            })
            .collect();
        store.mesh = Some(crate::store::Mesh::new(1, x.len(), corners));
        store.mesh_generation = 1;
        store.x = x;
        // Due again at once: the mesh is new.
        fitter.measured = None;
        fitter.update(&mut store, true, None);
        let fit = store.fit.clone().unwrap();
        let levels: Vec<&str> = fit.iter().map(|g| g.level).collect();
        assert_eq!(levels, ["bust", "waist", "hips"]);
        let round = 64.0 * 2.0 * 0.2 * (std::f32::consts::PI / 64.0).sin();
        for g in &fit {
            assert!((g.garment_m.unwrap() - round).abs() < 1e-3, "{g:?}");
        }
        // Two rings a level, each at its level's height.
        let r = rings(&store);
        assert_eq!(r.len(), 6);
        for (ring, _) in &r {
            assert!(ring.iter().all(|p| fit.iter().any(|g| g.height_m == p.y)));
        }
        // A level of the designer's own, and one where the body has no torso.
        fitter.update(&mut store, true, Some(0.9));
        let fit = store.fit.clone().unwrap();
        assert_eq!(fit.len(), 4);
        assert_eq!((fit[3].level, fit[3].height_m), (OWN_LEVEL, 0.9));
        assert!((fit[3].garment_m.unwrap() - round).abs() < 1e-3);
        fitter.update(&mut store, true, Some(1.9));
        assert_eq!(store.fit.as_ref().unwrap().len(), 3);
        // A body that is no figure: no levels.
        store.body = Some((
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            vec![[0, 1, 2]],
        ));
        store.body_version = 2;
        fitter.update(&mut store, true, None);
        assert!(store.fit.is_none());
        assert!(rings(&store).is_empty());
    }
}
