//! What cloth-sim publishes: the local model the haptic loop renders force from, the
//! cloth (positions and normals every frame, the mesh when its topology changes), the
//! body, and the texture as tiles.

use glam::Vec3;
use shared::Header;
use shared::services::SlicePub;
use shared::sim_to_haptic::{LocalModel, MAX_PLANES, workspace_covering};
use shared::sim_to_ui::{
    BodyMeshHeader, ClothFrameHeader, MAX_LISTED, MAX_PINS, MAX_SEAM_STRETCH, MeshCorner,
    MeshHeader, OutlineSegment, PieceList, SeamEntry, SeamSegment, TextureTile, outline, put_text,
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
        sewing
            .chain(notches)
            .chain(grain)
            .chain(drills)
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
mod tests {
    use super::*;
    use sim_core::scenario::garment::SEAM_PULL;
    use sim_core::scenario::{ScenarioConfig, ScenarioName, build_scene};

    /// The dress's list names its seams and draws each of its four seams along both its
    /// sides: the segments
    /// of a seam are as long as its two sides together, but for an edge at each end
    /// (the pattern's seam marks, as in pattern.svg, stop short of a corner where the
    /// stitched vertices skip one). One side alone would be half.
    #[test]
    fn the_piece_list_draws_every_seam_along_both_sides() {
        let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
        cfg.piece_edge = 0.06;
        let (mut d, spec) = build_scene(&cfg).unwrap();
        sim_core::design::garment::sew(&mut d, &spec.unwrap(), SEAM_PULL).unwrap();
        d.name_seam(2, "left side, the longest name a seam could ever have")
            .unwrap();
        let mut l = piece_list(&d, &mut 0);
        let seams = shared::sim_to_ui::check_seams(&l).unwrap();
        let segments = shared::sim_to_ui::check_seam_segments(&l).unwrap();
        assert_eq!(seams.len(), 4);
        // A name is carried, cut at its array's 32 bytes.
        assert_eq!(seams[2].name(), "left side, the longest name a se");
        assert_eq!(seams[0].name(), "");
        for (i, s) in seams.iter().enumerate() {
            let drawn: f32 = segments
                .iter()
                .filter(|g| g.seam as usize == i)
                .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
                .sum();
            let sides = s.lengths[0] + s.lengths[1];
            assert!(
                drawn <= sides + 0.01 && drawn >= sides - 2.0 * cfg.piece_edge,
                "seam {}: drawn {drawn} m, sides {sides} m",
                s.label()
            );
        }
        // The pattern's lines: each listed piece's sewing line as long as the pattern
        // out's, its notches (one per shoulder side, three per side seam side) and one
        // grain line.
        let lines = shared::sim_to_ui::check_outline(&l).unwrap();
        assert_eq!(l.outline_total as usize, lines.len());
        let cut = sim_core::design::sewing_pattern::pieces(&d);
        let listed = shared::sim_to_ui::check_pieces(&l).unwrap();
        assert_eq!(listed.len(), 2);
        for (i, piece) in listed.iter().enumerate() {
            let of = |kind| {
                lines
                    .iter()
                    .filter(move |g| g.piece == i as u32 && g.kind == kind)
            };
            let sewing: f32 = of(outline::SEWING_LINE)
                .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
                .sum();
            let want = cut
                .iter()
                .find(|p| p.name == piece.name)
                .unwrap()
                .perimeters()[0];
            assert!(
                (sewing as f64 * 1000.0 - want).abs() < 0.5,
                "{}: {sewing} m drawn, {want} mm cut",
                piece.name
            );
            assert_eq!(of(outline::NOTCH).count(), 8, "{}", piece.name);
            assert_eq!(of(outline::GRAIN).count(), 1, "{}", piece.name);
        }
        // Lines naming no listed piece, of no known kind, or not finite are refused.
        for spoil in [
            |g: &mut OutlineSegment| g.piece = 2,
            |g: &mut OutlineSegment| g.kind = 7,
            |g: &mut OutlineSegment| g.b[1] = f32::NAN,
        ] {
            let kept = l.outline[5];
            spoil(&mut l.outline[5]);
            assert!(shared::sim_to_ui::check_outline(&l).is_err());
            l.outline[5] = kept;
        }
        l.outline_count = l.outline_total + 1;
        assert!(shared::sim_to_ui::check_outline(&l).is_err());
    }

    /// The front cut across at the waist: each side seam is drawn by its two stretches,
    /// numbered as the pattern out labels them (B1 front to back, B2 lower front to back),
    /// and drawn as long as before the cut but for the cut's own edges (the view dropped
    /// a split seam's every segment: "B1" named no seam).
    #[test]
    fn a_seam_cut_across_is_drawn_by_its_stretches() {
        let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
        cfg.piece_edge = 0.06;
        let (mut d, spec) = build_scene(&cfg).unwrap();
        sim_core::design::garment::sew(&mut d, &spec.unwrap(), SEAM_PULL).unwrap();
        let drawn = |l: &PieceList, seam: u32, stretch: u32| -> f32 {
            let segments = shared::sim_to_ui::check_seam_segments(l).unwrap();
            (segments.iter())
                .filter(|g| g.seam == seam && g.stretch == stretch)
                .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
                .sum()
        };
        let before = piece_list(&d, &mut 0);
        let whole = [1, 3].map(|s| drawn(&before, s, 0));
        let (lo, hi) = sim_core::mesh::bounds2(&d.pieces[0].outline.loops[0]);
        let y = 0.5 * (lo.y + hi.y);
        let off = d.pieces[0].offset;
        let (a, b) = (
            glam::Vec2::new(lo.x - 0.02, y) + off,
            glam::Vec2::new(hi.x + 0.02, y) + off,
        );
        d.cut_line(a, b).unwrap();
        let l = piece_list(&d, &mut 0);
        for (k, seam) in [1, 3].into_iter().enumerate() {
            let parts = [0, 1, 2].map(|s| drawn(&l, seam, s));
            assert_eq!(parts[0], 0.0, "seam {seam} drawn whole: {parts:?}");
            assert!(parts[1] > 0.1 && parts[2] > 0.1, "seam {seam}: {parts:?}");
            let sum = parts[1] + parts[2];
            assert!(
                sum <= whole[k] + 1e-3 && sum >= whole[k] - 4.0 * cfg.piece_edge,
                "seam {seam}: {sum} m drawn, {} before the cut",
                whole[k]
            );
        }
        let a = (shared::sim_to_ui::check_seam_segments(&l)
            .unwrap()
            .into_iter())
        .find(|g| g.seam == 1 && g.stretch == 2)
        .unwrap();
        assert_eq!(a.label("B"), "B2");
    }

    /// A dart's drill hole reaches the pattern view where the export drills it: a dart
    /// up from the front's hem, one DRILL line (a point) on the front, none before.
    #[test]
    fn the_piece_list_carries_a_darts_drill_hole() {
        let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
        cfg.piece_edge = 0.03;
        let (mut d, _) = build_scene(&cfg).unwrap();
        let drills = |l: &PieceList| -> Vec<OutlineSegment> {
            (shared::sim_to_ui::check_outline(l).unwrap().into_iter())
                .filter(|g| g.kind == outline::DRILL)
                .collect()
        };
        assert!(drills(&piece_list(&d, &mut 0)).is_empty());
        let (lo, hi) = sim_core::mesh::bounds2(&d.pieces[0].outline.loops[0]);
        let off = d.pieces[0].offset;
        let x = 0.5 * (lo.x + hi.x);
        let point = glam::Vec2::new(x, lo.y + 0.3) + off;
        let toward = glam::Vec2::new(x, lo.y - 0.05) + off;
        d.dart_on_plane(point, toward, 0.04).unwrap();
        let l = piece_list(&d, &mut 0);
        let got = drills(&l);
        assert_eq!(got.len(), 1, "{got:?}");
        assert_eq!(got[0].a, got[0].b);
        // Where the export drills it: the same place from the piece's lowest, leftmost
        // corner (the export lays pieces out, in mm; the view keeps the plane's metres).
        use sim_core::design::sewing_pattern::{finish, pieces};
        let cut = finish(pieces(&d), 0.0);
        let piece = cut.iter().find(|p| !p.drills.is_empty()).unwrap();
        assert_eq!(piece.drills.len(), 1);
        let names = shared::sim_to_ui::check_pieces(&l).unwrap();
        assert_eq!(names[got[0].piece as usize].name, piece.name);
        let corner = |l: &[glam::DVec2]| l.iter().fold(glam::DVec2::INFINITY, |m, q| m.min(*q));
        let sewing: Vec<glam::DVec2> = (shared::sim_to_ui::check_outline(&l).unwrap().iter())
            .filter(|g| g.piece == got[0].piece && g.kind == outline::SEWING_LINE)
            .map(|g| glam::Vec2::from(g.a).as_dvec2() * 1000.0)
            .collect();
        let at = glam::Vec2::from(got[0].a).as_dvec2() * 1000.0 - corner(&sewing);
        let want = piece.drills[0] - corner(&piece.loops[0]);
        assert!(at.distance(want) < 0.05, "{at} mm against {want} mm");
    }

    /// A seam whose pairs stopped closing is listed so: a cloth hung from two corners
    /// 0.5 m apart, stitched together, which can never close. Before the watch's three
    /// seconds the list says nothing stalled; after them, both pairs and their gaps.
    /// Beside a long search the pinched vertex goes out at rest where the loop's
    /// extrapolation has got it (at most 50 ms on); not pinching, the touch planes.
    #[test]
    fn the_mid_frame_model_holds_a_pinched_vertex_still_beside_a_search() {
        use sim_core::mesh::ClothMesh;
        use sim_core::solver::{Cloth, Material};
        let mesh = ClothMesh::grid(0.2, 0.2, 4, 4, 0.5).unwrap();
        let cloth = Cloth::new(mesh, &Material::default()).unwrap();
        let held = Held {
            position: Vec3::new(0.0, 0.5, 0.0),
            velocity: Vec3::new(1.0, 0.0, 0.0),
        };
        let b = Between {
            substep: 2,
            substeps: 5,
            held: Some(held),
            cloth: &cloth,
            body: None,
            heartbeat: true,
        };
        let at = |ms: u64| {
            let since = std::time::Duration::from_millis(ms);
            let m = mid_frame_model(
                &b,
                (7, Some(0.0)),
                ((Vec3::ZERO, 9), since),
                &mut 0,
                (100.0, [0.0; 4]),
            );
            assert_eq!((m.pinching, m.frame, m.pen_sent_ns), (1, 7, 9));
            assert_eq!(m.vertex_velocity, [0.0; 3]);
            m.vertex_position[0]
        };
        assert!((at(20) - 0.02).abs() < 1e-6 && (at(400) - 0.05).abs() < 1e-6);
        let b = Between { held: None, ..b };
        let tip = Vec3::new(0.0, 0.5, 0.0);
        let m = mid_frame_model(
            &b,
            (7, Some(0.0)),
            ((tip, 9), Default::default()),
            &mut 0,
            (100.0, [0.0; 4]),
        );
        // The cloth's plane through its vertex under the tip, and the floor.
        assert_eq!((m.pinching, m.plane_count, m.frame), (0, 2, 7));
    }

    #[test]
    fn the_list_marks_the_pairs_that_stopped_closing() {
        use sim_core::design::{Design, STALL_TOLD_AFTER};
        use sim_core::mesh::ClothMesh;
        use sim_core::solver::{Cloth, Environment, Material, ModelKind, Simulation};
        let n = 8u32;
        let mesh = ClothMesh::grid(0.5, 0.5, n as usize, n as usize, 1.0).unwrap();
        let m = Material::default();
        let cloth = Cloth::new(mesh, &m).unwrap();
        let env = Environment {
            floor: None,
            ..Environment::default()
        };
        let sim = Simulation::new(cloth, None, ModelKind::Xpbd, m, env, None).unwrap();
        let mut d = Design::new(sim);
        d.sim.pin(0);
        d.sim.pin(n as usize);
        d.add_seam(&[0, 1], &[n, n - 1], 0.5).unwrap();
        let stalled = |d: &Design| {
            let l = piece_list(d, &mut 0);
            let s = shared::sim_to_ui::check_seams(&l).unwrap()[0];
            (s.open, s.stalled, s.stalled_gap)
        };
        d.step().unwrap();
        assert_eq!(stalled(&d), (2, 0, [0.0; 2]));
        for _ in 0..STALL_TOLD_AFTER + 60 {
            d.step().unwrap();
        }
        let (open, n, [lo, hi]) = stalled(&d);
        assert_eq!((open, n), (2, 2));
        assert!(0.0 < lo && lo <= hi && (hi - 0.5).abs() < 1e-3, "{lo} {hi}");
    }

    /// The local model carries the scene's workspace: on the mannequin it reaches the
    /// body's top and its feet (the default reached only 0.3-0.9 m up), and a pinch's
    /// model carries the same one; without a body, the default (all zero).
    #[test]
    fn the_model_carries_a_workspace_that_reaches_the_whole_body() {
        use shared::sim_to_haptic::TOUCH_HALF_EXTENT_M;
        let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
        cfg.piece_edge = 0.06;
        let (d, _) = build_scene(&cfg).unwrap();
        let body = d.sim.body.as_ref().unwrap();
        let ws = scene_workspace(&d);
        let tip = Vec3::new(0.0, 1.0, 0.5);
        let m = local_model(&d, tip, 0, &mut 0, (100.0, ws));
        shared::Checked::check_body(&m).unwrap();
        assert_eq!(m.workspace, ws);
        for p in &body.vertices {
            for i in 0..3 {
                let reach = TOUCH_HALF_EXTENT_M[i] * ws[3];
                assert!((p[i] - ws[i]).abs() <= reach, "{p} out of {ws:?}");
            }
        }
        let top = body.vertices.iter().map(|p| p.y).fold(0.0, f32::max);
        assert!(top > 1.6, "the mannequin's top at {top} m");
        let held = Held {
            position: Vec3::new(0.0, 1.4, 0.1),
            velocity: Vec3::ZERO,
        };
        assert_eq!(pinch_model(3, held, 0, &mut 0, (100.0, ws)).workspace, ws);
        let mut bare = ScenarioConfig::new(ScenarioName::DrapeCube);
        bare.grid = 4;
        let (mut d, _) = build_scene(&bare).unwrap();
        d.sim.body = None;
        assert_eq!(scene_workspace(&d), [0.0; 4]);
    }
}
