//! The fuzz targets: each takes bytes as something outside Saiho would hand them over (a
//! file a colleague sent, a message another process wrote into shared memory) and runs
//! them through the same code the programs do. A target panics only when Saiho would:
//! an `Err` is the right answer to bad input; a panic, an overflow (overflow checks are
//! on), a non-finite force or a design that does not load back is a finding.
//!
//! Each target is a binary under `src/bin/` for `cargo afl fuzz`, and [`TARGETS`] lets
//! `fuzz-run` replay files (a corpus, a crash) without AFL. See
//! `docs/reliability.md#fuzzing`.

pub mod seeds;

use std::path::Path;

use glam::Vec3;
use shared::Checked;
use shared::command::Command;
use shared::haptic_to_sim::{AppliedForce, DeviceSample};
use shared::sim_to_haptic::LocalModel;
use shared::sim_to_ui::{
    BodyMeshHeader, ClothFrameHeader, MeshCorner, MeshHeader, PieceList, TextureTile,
};
use shared::telemetry::{LoopTelemetry, SimTelemetry};
use shared::ui_to_haptic::PointerInput;
use shared::ui_to_sim::{CommandReply, ToolCommand};
use sim_core::collision::crossings;
use sim_core::design::file::MAGIC;
use sim_core::design::garment::{Landmarks, PatternSpec, assemble, pattern_from_outlines};
use sim_core::design::{CLOTH_COLOUR, Design, Texture};
use sim_core::solver::{Cloth, Environment, Material, ModelKind, Simulation};

/// A fuzz target: any bytes in, a panic only for a finding.
pub type Target = fn(&[u8]);

/// Every target by name, for `fuzz-run`.
pub const TARGETS: &[(&str, Target)] = &[
    ("design", design),
    ("obj", obj),
    ("body", body),
    ("body-build", body_build),
    ("svg", svg),
    ("dxf", dxf),
    ("garmentcode", garmentcode),
    ("pattern-mesh", pattern_file_mesh),
    ("outline", outline),
    ("messages", messages),
    ("commands", commands),
    ("replay", replay),
];

/// FNV-1a, 64 bits: the design file's checksum.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Gives bytes that look like a design file a matching checksum, so the fuzzer's
/// mutations reach the header and the sections instead of all stopping at the checksum
/// (which is tested on its own).
fn seal(bytes: &mut [u8]) {
    if bytes.len() >= 24 && bytes.starts_with(MAGIC) {
        let n = bytes.len() - 8;
        let sum = fnv1a(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
    }
}

/// A design file (`Design::load_design`, as `cloth-sim run --resume`, LOAD and the
/// autosave's resume read it). One that loads must be valid, give a sewing pattern of
/// numbers, step (under a model that never crosses, a cloth that crossed nothing crossing
/// nothing after it), and load again from what this build writes of it.
pub fn design(data: &[u8]) {
    let mut bytes = data.to_vec();
    seal(&mut bytes);
    let Ok(mut d) = Design::load_design(&bytes) else {
        return;
    };
    d.validate().expect("a loaded design is valid");
    // Its sewing pattern, as Export writes it: every point a number.
    let pattern = sim_core::design::sewing_pattern::finish(
        sim_core::design::sewing_pattern::pieces(&d),
        10.0,
    );
    for p in &pattern {
        let points = (p.loops.iter().chain(&p.cut).flatten().copied())
            .chain(p.notches.iter().flat_map(|n| [n.0, n.1]))
            .chain([p.grain.0, p.grain.1]);
        assert!(
            points.into_iter().all(|q| q.is_finite()),
            "a pattern piece with a point that is not a number: {}",
            p.name
        );
    }
    let _ = sim_core::design::sewing_pattern::svg_string(&pattern);
    let _ = sim_core::design::sewing_pattern::dxf_string(&pattern);
    let mut crossings = NoNewCrossings::of(&d);
    if d.step().is_err() {
        return;
    }
    crossings.check(&d, &"the first frame");
    d.refresh_png_cache().expect("the texture encodes");
    let out = d.save_design().expect("a loaded design saves");
    if let Err(e) = Design::load_design(&out) {
        panic!("a design this build wrote does not load back: {e}");
    }
}

/// An OBJ's text as `read_obj_text` gives it to the parsers: a zero byte is refused
/// before parsing, other bytes that are not UTF-8 are replaced.
fn obj_text(data: &[u8]) -> Option<std::borrow::Cow<'_, str>> {
    (!data.contains(&0)).then(|| String::from_utf8_lossy(data))
}

/// OBJ text as `cloth-sim scenario --cloth` reads it: parsed (tobj), validated, and the
/// crossing check every loaded cloth gets.
pub fn obj(data: &[u8]) {
    let Some(text) = obj_text(data) else {
        return;
    };
    let Ok(mesh) = sim_core::mesh::obj::parse_obj(Path::new("fuzz.obj"), &text) else {
        return;
    };
    mesh.validate().expect("a loaded mesh is valid");
    let (x, tris) = crossings::weld(&mesh.positions, &mesh.triangles);
    let _ = crossings::count_self(&x, &tris);
    let _ = Cloth::new(mesh, &Material::default());
}

/// OBJ text as `--body FILE` reads it: parsed by our reader (which keeps the file's
/// numbering for its messages) and checked to be a solid (closed, manifold, wound
/// outward, enclosing a volume). Building the body from it (OBB tree, clearance grid:
/// 0.1-0.3 s even for a tetrahedron) is left to `fuzz-run body-build`, too slow to fuzz.
pub fn body(data: &[u8]) {
    let Some(text) = obj_text(data) else {
        return;
    };
    if let Ok(b) = sim_core::collision::body::check_body_text(Path::new("fuzz.obj"), &text) {
        let n = b.vertices.len() as u32;
        assert!(b.triangles.iter().flatten().all(|&i| i < n));
        assert!(b.vertices.iter().all(|v| v.is_finite()));
    }
}

/// [`body`], then the body built from what passed (OBB tree, clearance grid); a point
/// beyond its bounds must be outside it.
pub fn body_build(data: &[u8]) {
    let Some(text) = obj_text(data) else {
        return;
    };
    let Ok(b) = sim_core::collision::body::body_from_obj_text(Path::new("fuzz.obj"), &text) else {
        return;
    };
    let (_, mx) = b.bounds();
    let far = mx + Vec3::splat(1.0);
    assert_eq!(
        b.penetration(far),
        0.0,
        "a point beyond the body's bounds is inside it"
    );
}

/// A pattern read from a file, made into a spec as `drape-pattern` and ADD_PIECE do:
/// normalised (each piece's outline checked) and arranged round the body. Meshing is the
/// `outline` target's (and `fuzz-run pattern-mesh` meshes what these read).
fn pattern(spec: Result<PatternSpec, String>) {
    let Ok(mut spec) = spec else {
        return;
    };
    if spec.normalise().is_ok() {
        spec.arrange(&Landmarks::of(None));
    }
}

/// [`pattern`], then every piece laid out and meshed (edges chosen so the pattern
/// meshes into about 300 vertices).
fn pattern_mesh(spec: Result<PatternSpec, String>) {
    let Ok(mut spec) = spec else {
        return;
    };
    if spec.normalise().is_err() {
        return;
    }
    let marks = Landmarks::of(None);
    spec.arrange(&marks);
    let area: f64 = spec
        .pieces
        .iter()
        .map(|p| sim_core::mesh::mesher::signed_area2(&p.outline.loops[0]).abs() * 0.5)
        .sum();
    let edge = ((area / 300.0).sqrt() as f32).clamp(0.005, 0.5);
    if let Ok(made) = assemble(&spec, &marks, edge) {
        made.mesh.validate().expect("a meshed pattern is valid");
        assert_eq!(made.starts.len(), made.mesh.positions.len());
    }
}

fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// An SVG pattern file.
pub fn svg(data: &[u8]) {
    let outlines = sim_core::mesh::svg::read_svg(&text(data)).map_err(|e| e.to_string());
    pattern(outlines.map(|o| pattern_from_outlines(o).0));
}

/// A DXF (AAMA) pattern file.
pub fn dxf(data: &[u8]) {
    let outlines = sim_core::mesh::dxf::read_dxf(&text(data)).map_err(|e| e.to_string());
    pattern(outlines.map(|o| pattern_from_outlines(o).0));
}

/// A GarmentCode pattern specification (JSON).
pub fn garmentcode(data: &[u8]) {
    let marks = Landmarks::of(None);
    pattern(sim_core::design::garment::read_garmentcode(
        &text(data),
        &marks,
    ));
}

/// An SVG, DXF or GarmentCode file (by its first bytes) read and meshed.
pub fn pattern_file_mesh(data: &[u8]) {
    let t = text(data);
    let marks = Landmarks::of(None);
    let spec = if t.trim_start().starts_with('{') {
        sim_core::design::garment::read_garmentcode(&t, &marks)
    } else if t.trim_start().starts_with('<') {
        sim_core::mesh::svg::read_svg(&t)
            .map(|o| pattern_from_outlines(o).0)
            .map_err(|e| e.to_string())
    } else {
        sim_core::mesh::dxf::read_dxf(&t)
            .map(|o| pattern_from_outlines(o).0)
            .map_err(|e| e.to_string())
    };
    pattern_mesh(spec);
}

/// A piece's outline as any bytes: up to 3 loops (an outer one and holes) of up to 40
/// points each, in a 1 m square, checked and meshed as ADD_PIECE meshes a shape; the
/// mesh must be valid and keep its boundary within an edge of the outline.
pub fn outline(data: &[u8]) {
    use sim_core::mesh::mesher::{Outline, check, mesh_outline};
    let Some((&e, rest)) = data.split_first() else {
        return;
    };
    let mut loops = Vec::new();
    for part in rest.split(|&b| b == 0xff).take(3) {
        let l: Vec<glam::Vec2> = part
            .chunks_exact(2)
            .take(40)
            .map(|p| glam::Vec2::new(p[0] as f32 / 254.0, p[1] as f32 / 254.0))
            .collect();
        loops.push(l);
    }
    let o = Outline { loops };
    if check(&o).is_err() {
        return;
    }
    // 2.5 cm to 0.5 m: a few to a few thousand triangles.
    let edge = 0.025 + e as f32 / 255.0 * 0.475;
    if let Ok(m) = mesh_outline(&o, edge) {
        m.validate().expect("a meshed outline is valid");
    }
}

/// `T` as another process could have written it: any bytes of its size.
fn wire<T: bytemuck::Pod>(data: &[u8]) -> Option<(T, &[u8])> {
    let n = std::mem::size_of::<T>();
    (data.len() >= n).then(|| (bytemuck::pod_read_unaligned(&data[..n]), &data[n..]))
}

/// Checks one payload of `T`s after its header, as the UI reads a frame's payload.
fn payload<T: bytemuck::Pod>(data: &[u8]) -> Vec<T> {
    let n = std::mem::size_of::<T>();
    data.chunks_exact(n)
        .map(bytemuck::pod_read_unaligned)
        .collect()
}

/// Every message type as received: the first byte picks the type, the rest are its
/// bytes (and a payload after, for the UI's sample types). Each is checked as its
/// receiver checks it; what passes goes on as it would. The haptic loop's part is the
/// strictest: whatever local model and pen state arrive, the force that reaches the
/// device is finite and within the device's peak.
pub fn messages(data: &[u8]) {
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    match kind % 12 {
        0 => haptic(rest),
        1 => {
            if let Some((m, _)) = wire::<DeviceSample>(rest) {
                let _ = m.check();
            }
        }
        2 => {
            if let Some((m, _)) = wire::<AppliedForce>(rest) {
                let _ = m.check();
            }
        }
        3 => {
            if let Some((m, _)) = wire::<ToolCommand>(rest) {
                let _ = Command::from_wire(&m);
            }
        }
        4 => {
            if let Some((m, _)) = wire::<CommandReply>(rest) {
                let _ = m.check();
            }
        }
        5 => {
            if let Some((m, p)) = wire::<ClothFrameHeader>(rest) {
                let p = payload::<f32>(p);
                if shared::sim_to_ui::check_frame(&m, &p).is_ok() {
                    let _ = shared::sim_to_ui::frame_stitches(&m, &p);
                }
            }
        }
        6 => {
            if let Some((m, p)) = wire::<MeshHeader>(rest) {
                let _ = shared::sim_to_ui::check_mesh(&m, &payload::<MeshCorner>(p));
            }
        }
        7 => {
            if let Some((m, p)) = wire::<BodyMeshHeader>(rest) {
                let _ = shared::sim_to_ui::check_body(&m, &payload::<f32>(p));
            }
        }
        8 => {
            if let Some((m, _)) = wire::<PieceList>(rest) {
                let _ = shared::sim_to_ui::check_pieces(&m);
                let _ = shared::sim_to_ui::check_seams(&m);
                let _ = shared::sim_to_ui::check_seam_segments(&m);
                let _ = shared::sim_to_ui::check_outline(&m);
            }
        }
        9 => {
            if let Some((m, p)) = wire::<TextureTile>(rest) {
                let _ = shared::sim_to_ui::check_tile(&m, p);
            }
        }
        10 => {
            // What the status panel and cloth-latency read of them: percentiles.
            if let Some((m, _)) = wire::<LoopTelemetry>(rest)
                && m.check().is_ok()
            {
                for h in [&m.lateness, &m.period, &m.compute, &m.model_age] {
                    let _ = h.quantile_ns(0.99);
                }
            }
            if let Some((m, _)) = wire::<SimTelemetry>(rest)
                && m.check().is_ok()
            {
                let _ = m.frame_time.quantile_ns(0.5);
            }
        }
        _ => {
            if let Some((m, _)) = wire::<PointerInput>(rest) {
                let _ = m.check();
            }
        }
    }
}

/// The haptic loop's ticks: a local model as received (used only if it passes its
/// check, as the loop does), then ticks of (age, pen position, pen velocity, dt) as any
/// bytes, through the proxy and the force safety.
fn haptic(data: &[u8]) {
    use haptic_loop::proxy::{ProxyParams, proxy_force};
    use haptic_loop::safety::{ForceSafety, Hold, SafetyLimits};
    let Some((model, mut ticks)) = wire::<LocalModel>(data) else {
        return;
    };
    let model = model.check().is_ok().then_some(model);
    let limits = SafetyLimits::default();
    let mut safety = ForceSafety::new(limits);
    while let Some((t, more)) = wire::<[f32; 8]>(ticks) {
        ticks = more;
        let (age, x, v, dt) = (t[0], [t[1], t[2], t[3]], [t[4], t[5], t[6]], t[7]);
        let hold = if !age.is_finite() || age > limits.stale_after_s {
            Hold::Stale
        } else {
            Hold::None
        };
        let wanted = match &model {
            Some(m) => proxy_force(&ProxyParams::default(), m, age, x, v),
            None => [0.0; 3],
        };
        let f = safety.filter(wanted, dt, hold);
        let mag = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        assert!(
            f.iter().all(|c| c.is_finite()) && mag <= limits.max_force * 1.0001,
            "force {f:?} from model {model:?}, pen {x:?} {v:?}, age {age}, dt {dt}"
        );
    }
}

/// A small design on the floor, built for each input (so no input sees another's
/// edits): 4 x 4 cells, gently rippled (a flat cloth sends every crossing test down the
/// exact predicates' slow path), the model the input's first byte picks, a 16 x 16
/// texture.
pub(crate) fn small_design(model: ModelKind) -> Design {
    small_design_of(model, Material::default(), 1.0)
}

/// As [`small_design`] with material `m`, the cloth stretched `stretch` times along x.
pub(crate) fn small_design_of(model: ModelKind, m: Material, stretch: f32) -> Design {
    let mesh = sim_core::mesh::ClothMesh::grid(0.3, 0.3, 4, 4, 0.0).expect("a 4 x 4 grid meshes");
    let mut cloth = Cloth::new(mesh, &m).expect("a grid is a cloth");
    for x in &mut cloth.x {
        x.x *= stretch;
        x.y = m.thickness + 0.01 + 0.005 * (20.0 * x.x).sin() * (17.0 * x.z).cos();
    }
    let sim = Simulation::new(cloth, None, model, m, Environment::default(), None)
        .expect("the material simulates");
    Design::with_texture(sim, Texture::new(16, 16, CLOTH_COLOUR))
}

/// Whether a new piece of `shape` at `edge` m would be valid and make the design large
/// (its estimated vertices and the design's `had` over [`SLOW_DESIGN`], the piece within
/// [`sim_core::design::MAX_PIECE_VERTICES`]): such a piece is carried out by the same code
/// as a small one, only its meshing and frames take long (a 3,000-vertex one about 20 ms,
/// up to seconds under vbd; a design of 600 vertices 20-30 ms an input, which was 60% of
/// the fuzzer's time in the ninth sitting). Larger pieces stay in: they are refused
/// before meshing.
fn is_slow_piece(shape: &shared::command::PieceShape, edge: f32, had: usize) -> bool {
    use shared::command::PieceShape;
    use sim_core::mesh::mesher::{Outline, estimate_vertices};
    let outline = match *shape {
        // As cloth-sim makes them (`add_piece`); sizes and edge are checked by now.
        PieceShape::Rectangle { w, h } => Outline::rectangle(w, h),
        PieceShape::Ellipse { w, h } => Outline::ellipse(0.5 * w, 0.5 * h, edge),
        PieceShape::File { .. } => return false,
    };
    let n = estimate_vertices(&outline, edge);
    n + had > SLOW_DESIGN && n <= sim_core::design::MAX_PIECE_VERTICES
}

/// Most vertices a design may grow to by the input's ADD_PIECE commands ([`is_slow_piece`]).
const SLOW_DESIGN: usize = 250;

/// Finest edge, m, a DUPLICATE_PIECE may mesh its copy with and be carried out: the
/// inputs' designs are a coarse square or two (edges of about 0.1 m or more).
const MIN_COPY_EDGE: f32 = 0.1;

/// Most substeps a SET_MATERIAL may ask for and be carried out: a frame's cost grows
/// with them (100 substeps of a 400-vertex piece under vbd took a second instrumented,
/// the eighth sitting's one hang), and more of them runs the same code.
const MAX_SUBSTEPS: u32 = 20;

/// `FUZZ_TRACE` set: [`commands`] prints what it carries out (read once).
static TRACE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// Commands as cloth-sim receives them: the first byte picks the model, the second which
/// commands a frame is stepped after (bit k for the k-th; cloth-sim takes every command
/// that arrived between two frames), then up to 8 `ToolCommand` records, each checked and
/// converted (`Command::from_wire`) and carried out (`cloth_sim::carry_out`) on the
/// design. A frame is always stepped after the last change (`FUZZ_TRACE=1` prints each
/// command, how long it took, why it was refused, and the cloth's size after it). Paths in SAVE and
/// ADD_PIECE are replaced by a scratch file (the fuzzer must not write where it likes);
/// LOAD, RESET, EXPORT and SET_TOOL are the service's own and not carried out here, nor
/// ADD_PIECE of a valid piece that would take the design past 250 vertices ([`is_slow_piece`]), nor SET_MATERIAL
/// of over [`MAX_SUBSTEPS`] substeps.
pub fn commands(data: &[u8]) {
    let [pick, steps, ref records @ ..] = *data else {
        return;
    };
    let mut rest = records;
    // The models, and xpbd with its guard (the proximity search's updates under edits).
    let model = [
        ModelKind::Xpbd,
        ModelKind::Vbd,
        ModelKind::Seed,
        ModelKind::Xpbd,
    ][pick as usize % 4];
    let mut d = small_design(model);
    if pick % 4 == 3 {
        assert!(d.sim.set_guard(true), "xpbd takes its guard");
    }
    let scratch = std::env::temp_dir().join(format!("saiho-fuzz-{}", std::process::id()));
    // Whether the design has been stepped since its last change.
    let mut stepped = false;
    let mut crossings = NoNewCrossings::of(&d);
    for k in 0..8 {
        let Some((wire_cmd, more)) = wire::<ToolCommand>(rest) else {
            break;
        };
        rest = more;
        let Ok(mut c) = Command::from_wire(&wire_cmd) else {
            continue;
        };
        match &mut c {
            Command::AddPiece { shape, edge_m, .. }
                if is_slow_piece(shape, *edge_m, d.sim.cloth.len()) =>
            {
                continue;
            }
            Command::SetMaterial {
                substeps: Some(s), ..
            } if *s > MAX_SUBSTEPS => continue,
            // A copy of a piece meshed finer than the design's cloth can be many times
            // its size: as slow as a big new piece, and the same code.
            Command::DuplicatePiece { edge_m, .. }
                if *edge_m < MIN_COPY_EDGE || 2 * d.sim.cloth.len() > SLOW_DESIGN =>
            {
                continue;
            }
            Command::Save { path } => *path = scratch.join("d.saiho").display().to_string(),
            Command::AddPiece {
                shape: shared::command::PieceShape::File { path },
                ..
            } => *path = scratch.join("none.svg").display().to_string(),
            Command::Load { .. }
            | Command::Reset { .. }
            | Command::Export { .. }
            | Command::SetTool { .. } => continue,
            _ => {}
        }
        let before = (
            d.sim.cloth.len(),
            d.sim.cloth.live.tri_count(),
            d.history.undo_len(),
        );
        let started = std::time::Instant::now();
        let result = cloth_sim::carry_out(&mut d, &c);
        if *TRACE.get_or_init(|| std::env::var_os("FUZZ_TRACE").is_some()) {
            eprintln!(
                "{c:?}: {} in {:.1} ms ({} vertices, {} triangles)",
                match &result {
                    Ok(_) => "done".to_string(),
                    Err(e) => format!("refused ({e})"),
                },
                started.elapsed().as_secs_f64() * 1e3,
                d.sim.cloth.len(),
                d.sim.cloth.live.tri_count()
            );
        }
        crossings.check(&d, &c);
        match result {
            Ok(_) => {
                d.validate().expect("an edit leaves a valid design");
                stepped = steps & (1 << k) != 0;
                if stepped {
                    if d.step().is_err() {
                        break;
                    }
                    crossings.check(&d, &"the frame after it");
                }
                continue;
            }
            Err(_) => {
                let after = (
                    d.sim.cloth.len(),
                    d.sim.cloth.live.tri_count(),
                    d.history.undo_len(),
                );
                assert_eq!(before, after, "a refused {c:?} changed the design");
            }
        }
        stepped = false;
    }
    // A refused command changes nothing, so the frames after refused ones, and after
    // accepted ones the step mask skipped, are one frame: the last (what any hidden change
    // a refusal left would break).
    if !stepped && d.step().is_ok() {
        crossings.check(&d, &"the last frame");
    }
    let _ = std::fs::remove_dir_all(&scratch);
}

/// The contact guarantee: under a model that never crosses (vbd, xpbd with its guard),
/// neither an edit nor a frame makes a cloth that crosses nothing cross (ARCHITECTURE.md;
/// a cloth that crosses already keeps its crossings, and may move them). (Whether the
/// model never crosses, and the count.)
struct NoNewCrossings(bool, usize);

impl NoNewCrossings {
    fn of(d: &Design) -> Self {
        let c = d.sim.crossings();
        Self(d.sim.never_crosses(), c.self_pairs + c.body_pairs)
    }

    /// Panics when `what` (an edit, or a frame) made a crossing under the guarantee.
    fn check(&mut self, d: &Design, what: &dyn std::fmt::Debug) {
        let now = Self::of(d);
        if self.0 && now.0 && self.1 == 0 {
            assert_eq!(now.1, 0, "{what:?} crossed: {} pairs", now.1);
        }
        *self = now;
    }
}

/// A device log (`--device replay:FILE`) and a simulated pen's script (`--device
/// sim:FILE`): what parses replays finite states, and time never goes backwards.
pub fn replay(data: &[u8]) {
    use haptic_loop::device::HapticDevice;
    let t = text(data);
    if let Ok(mut r) = haptic_loop::device::Replay::parse(&t) {
        for _ in 0..64 {
            let s = r.read(0.001).expect("a replay reads");
            assert!(
                s.position.iter().chain(&s.velocity).all(|c| c.is_finite()),
                "replayed {s:?}"
            );
        }
    }
    if let Ok(mut s) = haptic_loop::device::Script::parse(&t) {
        use haptic_loop::device::TargetSource;
        for k in 0..64 {
            let (p, _) = s.target(k as f64 * 0.01);
            assert!(p.iter().all(|c| c.is_finite()), "script target {p:?}");
        }
    }
}
