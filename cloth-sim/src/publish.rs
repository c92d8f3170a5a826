//! What cloth-sim publishes: the local model the haptic loop renders force from, the
//! cloth (positions and normals every frame, the mesh when its topology changes), the
//! body, and the texture as tiles.

use glam::Vec3;
use shared::Header;
use shared::services::SlicePub;
use shared::sim_to_haptic::{LocalModel, MAX_PLANES, workspace_covering};
use shared::sim_to_ui::{
    BodyMeshHeader, ClothFrameHeader, MAX_LISTED, MAX_PINS, MAX_SEAM_STRETCH, MeshCorner,
    MeshHeader, OutlineSegment, PieceList, SeamEntry, SeamSegment, TextureTile, dart, outline,
    put_text,
};
use sim_core::collision::Body;
use sim_core::design::sewing_pattern::seam_label;
use sim_core::design::{Design, TILE, Texture};
use sim_core::solver::{Between, Cloth, Held};

fn port_error(e: impl std::fmt::Debug) -> String {
    format!("{e:?}")
}

/// The pen's workspace for `design`'s scene: the default mapping, grown to reach the
/// whole body (`workspace_covering`); the default without a body.
pub(crate) fn scene_workspace(design: &Design) -> [f32; 4] {
    let Some(body) = &design.sim.body else {
        return [0.0; 4];
    };
    let (lo, hi) = body.vertices.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    workspace_covering(lo.to_array(), hi.to_array())
}

/// The local model for a pen at `tip`: the pinched vertex while pinching, otherwise the
/// body, cloth and floor planes near the tip; in the scene's `workspace`.
pub(crate) fn local_model(
    design: &Design,
    tip: Vec3,
    pen_sent_ns: u64,
    seq: &mut u64,
    spring: (f32, [f32; 4]),
) -> LocalModel {
    let sim = &design.sim;
    if let Some(p) = sim.pinch() {
        let i = p.vertex as usize;
        let held = Held {
            position: sim.cloth.x[i],
            velocity: sim.cloth.v[i],
        };
        return pinch_model(sim.frame, held, pen_sent_ns, seq, spring);
    }
    let floor = sim.env.floor;
    let m = touch_model(
        sim.body.as_ref(),
        &sim.cloth,
        floor,
        tip,
        pen_sent_ns,
        seq,
        spring,
    );
    LocalModel {
        frame: sim.frame,
        ..m
    }
}

/// The local model of a pen at `tip` that pinches nothing: the body's surface within
/// 5 cm, a plane through the vertex of `cloth` nearest the tip (within 3 cm) facing it,
/// and the floor, each `(normal, offset)` with free space on the normal's side. cloth-sim
/// sends it before and after each frame, and in the middle of a slow one from the cloth
/// as the substeps so far left it (its caller sets the frame).
pub(crate) fn touch_model(
    body: Option<&Body>,
    cloth: &Cloth,
    floor: Option<f32>,
    tip: Vec3,
    pen_sent_ns: u64,
    seq: &mut u64,
    (stiffness, workspace): (f32, [f32; 4]),
) -> LocalModel {
    let mut m = LocalModel {
        header: Header::next(seq),
        pen_sent_ns,
        stiffness,
        workspace,
        ..Default::default()
    };
    let body_plane = body
        .and_then(|b| b.contact(tip, 0.05, u32::MAX))
        .map(|c| [c.normal.x, c.normal.y, c.normal.z, c.normal.dot(c.point)]);
    let cloth_plane = cloth.nearest_vertex(tip, 0.03).and_then(|v| {
        let x = cloth.x[v as usize];
        let mut n = cloth.vertex_normal(v);
        if n.dot(tip - x) < 0.0 {
            n = -n;
        }
        (n != Vec3::ZERO).then(|| [n.x, n.y, n.z, n.dot(x)])
    });
    let floor_plane = floor.map(|f| [0.0, 1.0, 0.0, f]);
    for p in [body_plane, cloth_plane, floor_plane]
        .into_iter()
        .flatten()
        .take(MAX_PLANES)
    {
        m.planes[m.plane_count as usize] = p;
        m.plane_count += 1;
    }
    m
}

/// The haptic loop extrapolates a pinched vertex with its velocity this far at most, s
/// (`ProxyParams::max_extrapolation_s`).
const MAX_LEAD_S: f32 = 0.05;

/// The local model sent in the middle of frame `frame` (the scene's `floor`), between
/// substeps or beside a long search (`b`), for the pen at `tip` (its sample sent at
/// `sent_ns`), the pinched vertex having last gone out `since` ago: the touch planes, or
/// the pinched vertex. Beside a search the cloth stands still, so the vertex goes out
/// where the loop's extrapolation has got it by now (at most its 50 ms) and at rest: the
/// pull does not saw back at each beat.
pub(crate) fn mid_frame_model(
    b: &Between<'_>,
    (frame, floor): (u64, Option<f32>),
    ((tip, sent_ns), since): ((Vec3, u64), std::time::Duration),
    seq: &mut u64,
    spring: (f32, [f32; 4]),
) -> LocalModel {
    match b.held {
        Some(held) => {
            let lead = since.as_secs_f32().min(MAX_LEAD_S);
            let still = Held {
                position: held.position + held.velocity * lead,
                velocity: Vec3::ZERO,
            };
            pinch_model(frame, still, sent_ns, seq, spring)
        }
        None => LocalModel {
            frame,
            ..touch_model(b.body, b.cloth, floor, tip, sent_ns, seq, spring)
        },
    }
}

/// The local model of a pinch in the middle of frame `frame`, from the pinched vertex as
/// the substeps so far left it (`held`, told to the pen before each substep).
pub(crate) fn pinch_model(
    frame: u64,
    held: Held,
    pen_sent_ns: u64,
    seq: &mut u64,
    (stiffness, workspace): (f32, [f32; 4]),
) -> LocalModel {
    LocalModel {
        header: Header::next(seq),
        frame,
        pen_sent_ns,
        stiffness,
        workspace,
        pinching: 1,
        vertex_position: held.position.to_array(),
        vertex_velocity: held.velocity.to_array(),
        ..Default::default()
    }
}

/// Publishes the body's triangles (nothing when there is no body).
pub(crate) fn publish_body(
    body_pub: &SlicePub<f32, BodyMeshHeader>,
    design: &Design,
) -> Result<(), String> {
    let Some(b) = &design.sim.body else {
        return Ok(());
    };
    let (v, t) = (b.vertices.len(), b.triangles.len());
    let mut s = body_pub
        .loan_slice_uninit(3 * v + 3 * t)
        .map_err(port_error)?;
    *s.user_header_mut() = BodyMeshHeader {
        header: Header::next(&mut 0),
        vertices: v as u32,
        triangles: t as u32,
    };
    let s = s.write_from_fn(|i| {
        if i < 3 * v {
            b.vertices[i / 3][i % 3]
        } else {
            let j = i - 3 * v;
            b.triangles[j / 3][j % 3] as f32
        }
    });
    s.send().map_err(port_error)?;
    Ok(())
}

/// Publishes texture tile `(x, y)` (in tiles).
pub(crate) fn publish_tile(
    tex: &Texture,
    tile_pub: &SlicePub<u8, TextureTile>,
    x: usize,
    y: usize,
    seq: &mut u64,
) -> Result<(), String> {
    let (x0, y0) = (x * TILE, y * TILE);
    let (w, h) = (TILE.min(tex.width - x0), TILE.min(tex.height - y0));
    let mut s = tile_pub.loan_slice_uninit(4 * w * h).map_err(port_error)?;
    *s.user_header_mut() = TextureTile {
        header: Header::next(seq),
        texture_version: tex.version,
        width: tex.width as u32,
        height: tex.height as u32,
        x0: x0 as u32,
        y0: y0 as u32,
        w: w as u32,
        h: h as u32,
    };
    let row = 4 * w;
    let s = s.write_from_fn(|i| {
        let (r, c) = (i / row, i % row);
        tex.rgba[4 * ((y0 + r) * tex.width + x0) + c]
    });
    s.send().map_err(port_error)?;
    Ok(())
}

/// The cloth publishers, their sequence numbers, and what they last sent.
#[derive(Default)]
pub(crate) struct ClothOut {
    seq_frame: u64,
    seq_mesh: u64,
    /// The topology version last sent as a mesh.
    pub(crate) mesh_sent: Option<u64>,
    normals: Vec<Vec3>,
}

impl ClothOut {
    /// Publishes this frame's positions and normals, and the mesh when its topology
    /// changed.
    pub(crate) fn publish(
        &mut self,
        design: &Design,
        frame_pub: &SlicePub<f32, ClothFrameHeader>,
        mesh_pub: &SlicePub<MeshCorner, MeshHeader>,
        pen_sent_ns: u64,
    ) -> Result<(), String> {
        let sim = &design.sim;
        let live = &sim.cloth.live;
        let n = sim.cloth.len();
        let topology = live.version();
        if self.mesh_sent != Some(topology) {
            let t = live.tri_count();
            let mut s = mesh_pub.loan_slice_uninit(3 * t).map_err(port_error)?;
            *s.user_header_mut() = MeshHeader {
                header: Header::next(&mut self.seq_mesh),
                topology,
                vertices: n as u32,
                triangles: t as u32,
            };
            let mut corners = live.iter().flat_map(|(_, tri)| {
                (0..3).map(move |k| MeshCorner {
                    vertex: tri.v[k],
                    u: tri.uv[k].x,
                    v: tri.uv[k].y,
                    pattern: [tri.rest[k].x, -tri.rest[k].z],
                })
            });
            let s = s.write_from_fn(|_| corners.next().unwrap_or_default());
            s.send().map_err(port_error)?;
            self.mesh_sent = Some(topology);
        }
        let normals = &mut self.normals;
        normals.clear();
        normals.resize(n, Vec3::ZERO);
        for (_, t) in live.iter() {
            let [a, b, c] = t.v.map(|i| sim.cloth.x[i as usize]);
            let nn = (b - a).cross(c - a);
            for &i in &t.v {
                normals[i as usize] += nn;
            }
        }
        let stitches: Vec<(u32, u32, u32)> = design
            .seams
            .iter()
            .enumerate()
            .flat_map(|(k, s)| s.open_pairs().map(move |(a, b)| (a, b, k as u32)))
            .collect();
        let mut s = frame_pub
            .loan_slice_uninit(6 * n + 3 * stitches.len())
            .map_err(port_error)?;
        *s.user_header_mut() = ClothFrameHeader {
            header: Header::next(&mut self.seq_frame),
            frame: sim.frame,
            topology,
            texture_version: design.texture.version,
            pen_sent_ns,
            vertices: n as u32,
            stitches: stitches.len() as u32,
        };
        let x = &sim.cloth.x;
        let s = s.write_from_fn(|i| {
            if i < 3 * n {
                x[i / 3][i % 3]
            } else if i < 6 * n {
                let j = i - 3 * n;
                normals[j / 3].normalize_or(Vec3::Y)[j % 3]
            } else {
                let j = i - 6 * n;
                let (a, b, seam) = stitches[j / 3];
                [a, b, seam][j % 3] as f32
            }
        });
        s.send().map_err(port_error)?;
        Ok(())
    }
}

/// The design's pieces as `saiho/pieces` carries them (the first [`MAX_LISTED`]).
pub(crate) fn piece_list(design: &Design, seq: &mut u64) -> PieceList {
    // The list and the pattern view from one pass over the cloth's parts.
    let (pieces, view) = design.piece_list_and_view();
    let mut l = PieceList {
        header: Header::next(seq),
        topology: design.sim.cloth.live.version(),
        total: pieces.len() as u32,
        count: pieces.len().min(MAX_LISTED) as u32,
        ..PieceList::default()
    };
    for (e, p) in l.entries.iter_mut().zip(&pieces) {
        e.name_len = put_text(&mut e.name, &p.name);
        e.fabric_len = put_text(&mut e.fabric, &p.fabric);
        e.vertices = p.vertices as u32;
        e.triangles = p.triangles as u32;
        if let Some((v, uv)) = p.anchor {
            e.anchor_vertex = v;
            e.anchor_uv = uv.to_array();
        }
    }
    l.seam_total = design.seams.len() as u32;
    l.seam_count = design.seams.len().min(MAX_LISTED) as u32;
    for (i, (e, s)) in l.seams.iter_mut().zip(&design.seams).enumerate() {
        let (a, b) = design.seam_lengths(s);
        let mut label = [0u8; 4];
        let label_len = put_text(&mut label, &seam_label(i));
        let mut name = [0u8; shared::sim_to_ui::SEAM_NAME_LEN];
        let name_len = put_text(&mut name, &s.name);
        let (stalled, lo, hi) = design.stalled_in(i).unwrap_or_default();
        *e = SeamEntry {
            label,
            label_len,
            pairs: s.pairs.len() as u32,
            open: s.open_pairs().count() as u32,
            lengths: [a, b],
            name_len,
            name,
            stalled: stalled as u32,
            stalled_gap: [lo, hi],
            dart: dart::NONE,
        };
    }
    // The pattern as the export makes it: each seam's sides and each piece's lines, a
    // seam's stretches ("B1", "B2": its sides run over more than two pieces) by number.
    let seam_index: std::collections::HashMap<String, usize> = (0..design.seams.len())
        .map(|i| (seam_label(i), i))
        .collect();
    let of_label = |label: &str| {
        let base = label.trim_end_matches(|c: char| c.is_ascii_digit());
        let stretch = match &label[base.len()..] {
            "" => 0,
            k => k.parse::<u32>().ok().filter(|&k| k <= MAX_SEAM_STRETCH)?,
        };
        Some((*seam_index.get(base)?, stretch))
    };
    // A seam whose stretch the pattern finds closing a dart is listed as one.
    for (label, ..) in view.iter().flat_map(|p| &p.presses) {
        let Some((i, _)) = of_label(label).filter(|&(i, _)| i < l.seam_count as usize) else {
            continue;
        };
        l.seams[i].dart = if design.seams[i].press_second {
            dart::SECOND
        } else {
            dart::FIRST
        };
    }
    let listed = view
        .iter()
        .flat_map(|p| &p.seams)
        .filter_map(|(label, a, b)| Some((of_label(label)?, a, b)))
        .filter(|((seam, _), ..)| *seam < MAX_LISTED);
    for (g, ((seam, stretch), a, b)) in l.segments.iter_mut().zip(listed) {
        *g = SeamSegment {
            seam: seam as u32,
            a: a.as_vec2().to_array(),
            b: b.as_vec2().to_array(),
            stretch,
        };
        l.segment_count += 1;
    }
    let lines = view.iter().flat_map(|p| {
        // Names are unique in the list: the view's piece is the listed one of its name.
        let piece = pieces
            .iter()
            .take(MAX_LISTED)
            .position(|e| e.name == p.name)
            .map_or(u32::MAX, |i| i as u32);
        let sewing = p.loops.iter().flat_map(|l| {
            (0..l.len()).map(move |i| (outline::SEWING_LINE, l[i], l[(i + 1) % l.len()]))
        });
        let notches = p.notches.iter().map(|&(a, b)| (outline::NOTCH, a, b));
        let grain = std::iter::once((outline::GRAIN, p.grain.0, p.grain.1));
        let drills = p.drills.iter().map(|&q| (outline::DRILL, q, q));
        let presses = p.presses.iter().map(|(_, a, b)| (outline::PRESS, *a, *b));
        sewing
            .chain(notches)
            .chain(grain)
            .chain(drills)
            .chain(presses)
            .map(move |(kind, a, b)| (piece, kind, a, b))
    });
    for (piece, kind, a, b) in lines {
        if let Some(g) = l.outline.get_mut(l.outline_total as usize) {
            *g = OutlineSegment {
                piece,
                kind,
                a: a.as_vec2().to_array(),
                b: b.as_vec2().to_array(),
            };
            l.outline_count += 1;
        }
        l.outline_total += 1;
    }
    let pins = design.pinned_vertices();
    l.pin_total = pins.len() as u32;
    l.pin_count = pins.len().min(MAX_PINS) as u32;
    l.pins[..l.pin_count as usize].copy_from_slice(&pins[..l.pin_count as usize]);
    l
}

#[cfg(test)]
pub(crate) mod tests;
