//! What the view shows besides the cloth's own triangles, as vertex lists: the cloth's
//! vertices (one per distinct vertex and UV), the body, the lines (floor grid, the
//! cloth's border and seams, the pinch spring, the pen, the pins' shafts) and the lit
//! markers (the pen tip, the pins' heads).

use glam::Vec3;

use super::gpu::Vertex;
use crate::store::{Mesh, Store};

/// Lines over the cloth: its border and cuts, and sewn edges. Stitches still pulling are
/// drawn in their seam's colour ([`seam_colour`]).
pub const BORDER_COLOUR: [f32; 4] = [0.95, 0.55, 0.1, 1.0];
pub const SEWN_COLOUR: [f32; 4] = [0.3, 0.65, 1.0, 1.0];

/// Seam `i`'s colour in the 3D view, the seam list and the pattern view (six, in turn),
/// none of them near the border's orange, the sewn edges' blue or the selection's peach.
pub fn seam_colour(i: usize) -> [f32; 4] {
    const PALETTE: [[f32; 3]; 6] = [
        [0.9, 0.24, 0.24],
        [0.35, 0.78, 0.27],
        [0.16, 0.78, 0.86],
        [0.47, 0.39, 1.0],
        [0.86, 0.31, 0.86],
        [0.75, 0.75, 0.2],
    ];
    let [r, g, b] = PALETTE[i % PALETTE.len()];
    [r, g, b, 1.0]
}
/// The selected piece's tint (times the texture).
pub const HIGHLIGHT: [f32; 4] = [1.0, 0.78, 0.45, 1.0];

/// Extra things to draw this frame besides cloth and body.
#[derive(Clone, Debug, Default)]
pub struct Overlay {
    /// The pen tip.
    pub pen: Option<Vec3>,
    /// The pinch spring: from the tip to the pinched vertex.
    pub spring: Option<(Vec3, Vec3)>,
    /// A vertex picked by the first click of a sew.
    pub marked: Option<Vec3>,
    /// A dart being dragged on the cloth: from its point to the mouse's last place on
    /// the cloth.
    pub dart: Option<(Vec3, Vec3)>,
    /// Closed polylines and their colours: the tape measure's rings (`crate::fit`).
    pub rings: Vec<(Vec<Vec3>, [f32; 4])>,
}

/// The cloth's distinct (vertex, UV) pairs and the triangles over them (UVs are per
/// corner, so a seam or cut gives a vertex two): a grid cloth then shades each vertex
/// once, not six times.
pub(super) fn cloth_keys(mesh: Option<&Mesh>, keys: &mut Vec<(u32, [f32; 2])>) -> Vec<u32> {
    keys.clear();
    let mut index = Vec::new();
    if let Some(m) = mesh {
        let mut seen: std::collections::HashMap<(u32, u32, u32), u32> = Default::default();
        for c in &m.corners {
            let k = (c.vertex, c.u.to_bits(), c.v.to_bits());
            let i = *seen.entry(k).or_insert_with(|| {
                keys.push((c.vertex, [c.u, c.v]));
                (keys.len() - 1) as u32
            });
            index.push(i);
        }
    }
    index
}

/// The cloth's vertices for `keys` at the store's positions; nothing when the positions
/// belong to another mesh (drawing nothing beats drawing garbage). With a map shown, each
/// takes the map's colour instead of the selection's tint.
pub(super) fn cloth_vertices(keys: &[(u32, [f32; 2])], store: &Store, out: &mut Vec<Vertex>) {
    out.clear();
    let (x, n) = (&store.x, &store.normals);
    // The selected piece, tinted.
    let piece_of = store.mesh.as_ref().map(|m| &m.piece_of);
    let tint = |v: u32, uv: [f32; 2]| match (&store.stretch, store.highlight, piece_of) {
        (Some(map), _, _) => map.colour_of(v),
        (None, Some(h), Some(p)) if p.get(&crate::store::key(v, uv)) == Some(&h) => HIGHLIGHT,
        _ => [1.0; 4],
    };
    for &(v, uv) in keys {
        let i = v as usize;
        let (Some(p), Some(nn)) = (x.get(i), n.get(i)) else {
            out.clear();
            return;
        };
        out.push(Vertex {
            pos: *p,
            nrm: *nn,
            // cloth-sim's texture coordinates run up the image (row `(1 - v) * height`,
            // as the OBJ export writes them); the GPU's run down it.
            uv: [uv[0], 1.0 - uv[1]],
            col: tint(v, uv),
        });
    }
}

/// The body's triangles, flat-shaded.
pub(super) fn body_vertices(store: &Store, out: &mut Vec<Vertex>) {
    out.clear();
    if let Some((v, t)) = &store.body {
        for tri in t {
            let [a, b, c] = tri.map(|i| Vec3::from(v[i as usize]));
            let nrm = (b - a).cross(c - a).normalize_or(Vec3::Y).to_array();
            for p in [a, b, c] {
                out.push(Vertex {
                    pos: p.to_array(),
                    nrm,
                    uv: [0.0; 2],
                    col: [0.55, 0.6, 0.68, 1.0],
                });
            }
        }
    }
}

/// A line from `a` to `b`; `lift`: how far towards the eye it is drawn (see vs_line), m.
fn line_lifted(s: &mut Vec<Vertex>, a: Vec3, b: Vec3, col: [f32; 4], lift: f32) {
    for p in [a, b] {
        s.push(Vertex {
            pos: p.to_array(),
            nrm: [lift, 0.0, 0.0],
            col,
            ..Default::default()
        });
    }
}

fn line(s: &mut Vec<Vertex>, a: Vec3, b: Vec3, col: [f32; 4]) {
    line_lifted(s, a, b, col, 0.0);
}

fn cross(s: &mut Vec<Vertex>, c: Vec3, r: f32, col: [f32; 4]) {
    for d in [Vec3::X, Vec3::Y, Vec3::Z] {
        line(s, c - d * r, c + d * r, col);
    }
}

/// A dart's line while it is dragged on the cloth (the pattern view's cut line's hue).
const DART_COLOUR: [f32; 4] = [0.95, 0.45, 0.9, 1.0];

/// The lines: the floor grid, the cloth's border and cuts, sewn edges and open
/// stitches, the pinch spring, a dart being dragged, the tape measure's rings, the pen,
/// the first vertex of a sew and the pins' shafts (towards `eye`).
pub(super) fn lines(store: &Store, overlay: &Overlay, eye: Vec3, out: &mut Vec<Vertex>) {
    out.clear();
    for k in -10..=10 {
        let f = k as f32 * 0.1;
        let col = [0.06, 0.065, 0.075, 1.0];
        line(out, Vec3::new(f, 0.0, -1.0), Vec3::new(f, 0.0, 1.0), col);
        line(out, Vec3::new(-1.0, 0.0, f), Vec3::new(1.0, 0.0, f), col);
    }
    // Edges over the cloth, lifted 3 mm so the cloth's own depth does not hide them.
    let (border, sewn) = store
        .mesh
        .as_ref()
        .map_or((&[][..], &[][..]), |m| (&m.border[..], &m.sewn[..]));
    let coloured = [(border, BORDER_COLOUR), (sewn, SEWN_COLOUR)]
        .into_iter()
        .flat_map(|(edges, colour)| edges.iter().map(move |&[a, b]| (a, b, colour)));
    let stitches = store
        .stitches
        .iter()
        .map(|&[a, b, seam]| (a, b, seam_colour(seam as usize)));
    for (a, b, colour) in coloured.chain(stitches) {
        if let (Some(pa), Some(pb)) = (store.x.get(a as usize), store.x.get(b as usize)) {
            line_lifted(out, Vec3::from(*pa), Vec3::from(*pb), colour, 0.003);
        }
    }
    if let Some((a, b)) = overlay.spring {
        line(out, a, b, [0.2, 0.9, 0.4, 1.0]);
    }
    if let Some((a, b)) = overlay.dart {
        line_lifted(out, a, b, DART_COLOUR, 0.004);
    }
    for (ring, colour) in &overlay.rings {
        for (k, &a) in ring.iter().enumerate() {
            line_lifted(out, a, ring[(k + 1) % ring.len()], *colour, 0.003);
        }
    }
    if let Some(p) = overlay.pen {
        cross(out, p, 0.02, [1.0, 0.95, 0.3, 1.0]);
    }
    if let Some(p) = overlay.marked {
        cross(out, p, 0.015, [0.3, 0.7, 1.0, 1.0]);
    }
    for &v in &store.pins {
        if let Some((p, head, _)) = pin_head(store, v, eye) {
            line(out, p, head, [0.85, 0.85, 0.9, 1.0]);
        }
    }
}

/// A pin's head: its colour, and its radius as a share of its distance from the eye (so
/// it shows the same size near and far; within 3 mm and 3 cm). It stands 2.5 radii
/// over the cloth.
pub const PIN_COLOUR: [f32; 4] = [0.95, 0.2, 0.55, 1.0];
const PIN_HEAD_SHARE: f32 = 0.01;

/// Where pinned vertex `v` is and its head is drawn (over the cloth on the side of
/// `eye`), and the head's radius; `None` for a vertex the positions do not have.
pub fn pin_head(store: &Store, v: u32, eye: Vec3) -> Option<(Vec3, Vec3, f32)> {
    let p = Vec3::from(*store.x.get(v as usize)?);
    let n = Vec3::from(*store.normals.get(v as usize)?).normalize_or(Vec3::Y);
    let n = if n.dot(eye - p) < 0.0 { -n } else { n };
    let r = (PIN_HEAD_SHARE * eye.distance(p)).clamp(0.003, 0.03);
    Some((p, p + n * 2.5 * r, r))
}

/// The lit markers: the pen tip, and a pin's head over each pinned vertex (its shaft is
/// one of [`lines`]), seen from `eye`.
pub(super) fn markers(store: &Store, overlay: &Overlay, eye: Vec3, out: &mut Vec<Vertex>) {
    out.clear();
    if let Some(c) = overlay.pen {
        octahedron(c, 0.008, [1.0, 0.85, 0.2, 1.0], out);
    }
    for &v in &store.pins {
        if let Some((_, head, r)) = pin_head(store, v, eye) {
            octahedron(head, r, PIN_COLOUR, out);
        }
    }
}

/// A small lit octahedron of radius `r` at `c`.
fn octahedron(c: Vec3, r: f32, col: [f32; 4], out: &mut Vec<Vertex>) {
    let d = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    for (i, j, k) in [
        (0, 1, 2),
        (1, 3, 2),
        (3, 4, 2),
        (4, 0, 2),
        (1, 0, 5),
        (3, 1, 5),
        (4, 3, 5),
        (0, 4, 5),
    ] {
        let n = (d[i] + d[j] + d[k]).normalize();
        for q in [i, j, k] {
            out.push(Vertex {
                pos: (c + d[q] * r).to_array(),
                nrm: n.to_array(),
                uv: [0.0; 2],
                col,
            });
        }
    }
}
