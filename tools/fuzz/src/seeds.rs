//! Starting inputs for each target, made by this build (nothing binary is committed): a
//! fuzzer starts from valid inputs and mutates them, so each target gets a few that
//! reach deep.

use std::path::Path;

use shared::Header;
use shared::command::{Command, MaterialChange, PieceShape, Tearing};
use shared::ui_to_sim::ToolCommand;
use sim_core::design::Design;
use sim_core::solver::{Material, ModelKind};

const DRESS_SVG: &str = include_str!("../../../sim-core/assets/dress.svg");

const SQUARE_SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="200mm" viewBox="0 0 200 200">
<g id="front"><path d="M 10 10 L 190 10 Q 200 100 190 190 L 10 190 C 0 150 0 50 10 10 Z"/></g>
</svg>"#;

const TWO_PANELS: &str = r#"{"pattern": {"panels": {
  "front": {"translation": [-25, 90, 30], "rotation": [0, 0, 0],
    "vertices": [[0, 0], [50, 0], [50, 60], [0, 60]],
    "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
      {"endpoints": [2, 3], "curvature": {"type": "quadratic", "params": [[0.5, 0.2]]}},
      {"endpoints": [3, 0]}]},
  "back": {"translation": [25, 90, -25], "rotation": [0, 180, 0],
    "vertices": [[0, 0], [50, 0], [50, 60], [0, 60]],
    "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
      {"endpoints": [2, 3], "curvature": {"type": "circle", "params": [40, 0, 1]}},
      {"endpoints": [3, 0]}]}},
  "stitches": [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
    [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}]]},
  "properties": {"units_in_meter": 100, "curvature_coords": "relative"}}"#;

const CUBE_OBJ: &str = "# a cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const CLOTH_OBJ: &str = "o cloth\nv 0 0 0\nv 0.1 0 0\nv 0.1 0 0.1\nv 0 0 0.1\nv 0.2 0 0\nv 0.2 0 0.1\n\
vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 1 0\nvt 1 1\n\
f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 2/2 5/5 6/6 3/3\n";

fn put(dir: &Path, target: &str, name: &str, bytes: &[u8]) -> std::io::Result<()> {
    let d = dir.join(target);
    std::fs::create_dir_all(&d)?;
    std::fs::write(d.join(name), bytes)
}

fn wire(c: &Command) -> Vec<u8> {
    let mut seq = 0;
    let w: ToolCommand = c
        .to_wire(Header::next(&mut seq))
        .expect("seed commands carry short paths");
    bytemuck::bytes_of(&w).to_vec()
}

/// Writes every target's seeds under `dir/TARGET/`.
pub fn write_seeds(dir: &Path) -> std::io::Result<()> {
    // Design files: the small design of the commands target, edited, under two models.
    for (name, model) in [("xpbd", ModelKind::Xpbd), ("vbd", ModelKind::Vbd)] {
        let mut d: Design = crate::small_design(model);
        let _ = d.set_pin(0, true);
        let _ = d.cut_vertex(12, glam::Vec3::X);
        let _ = d.step();
        d.refresh_png_cache().map_err(std::io::Error::other)?;
        let bytes = d.save_design().map_err(std::io::Error::other)?;
        put(dir, "design", name, &bytes)?;
    }
    // A seam, and cloth eased into it: a corner triangle folded away (removed) and kept in
    // the seam's record, which the pattern out puts back.
    let mut d = crate::small_design(ModelKind::Xpbd);
    let _ = d.add_seam(&[0, 5, 10, 15, 20], &[4, 9, 14, 19, 24], 0.05);
    let corner = d.sim.cloth.live.iter().find(|(_, t)| t.v.contains(&0));
    if let Some((slot, t)) = corner.map(|(s, t)| (s, t.rest)) {
        let _ = d.remove_triangles(&[slot]);
        if let Some(seam) = d.seams.first_mut() {
            seam.eased.push(t);
        }
    }
    d.refresh_png_cache().map_err(std::io::Error::other)?;
    let bytes = d.save_design().map_err(std::io::Error::other)?;
    put(dir, "design", "eased-seam", &bytes)?;
    // The strain limit at work under the guard: the cloth stretched 1.5x, limited to 1.2x.
    let limited = Material {
        strain_limit: 0.2,
        ..Material::default()
    };
    let mut d = crate::small_design_of(ModelKind::Xpbd, limited, 1.5);
    d.sim.set_guard(true);
    let _ = d.step();
    d.refresh_png_cache().map_err(std::io::Error::other)?;
    let bytes = d.save_design().map_err(std::io::Error::other)?;
    put(dir, "design", "xpbd-strain-limit", &bytes)?;
    put(dir, "obj", "cloth", CLOTH_OBJ.as_bytes())?;
    put(dir, "obj", "cube", CUBE_OBJ.as_bytes())?;
    put(dir, "body", "cube", CUBE_OBJ.as_bytes())?;
    put(dir, "body-build", "cube", CUBE_OBJ.as_bytes())?;
    // Outlines: a square, and a square with a square hole (edge byte first).
    let sq = |lo: u8, hi: u8| [lo, lo, hi, lo, hi, hi, lo, hi];
    let mut one = vec![60u8];
    one.extend_from_slice(&sq(0, 200));
    put(dir, "outline", "square", &one)?;
    one.push(0xff);
    one.extend_from_slice(&[80, 80, 80, 120, 120, 120, 120, 80]);
    put(dir, "outline", "holed", &one)?;
    put(dir, "pattern-mesh", "dress", DRESS_SVG.as_bytes())?;
    put(dir, "pattern-mesh", "two-panels", TWO_PANELS.as_bytes())?;
    put(dir, "pattern-mesh", "boundary", DXF_BLOCK.as_bytes())?;
    put(
        dir,
        "body",
        "negative-indices",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n",
    )?;
    put(dir, "svg", "dress", DRESS_SVG.as_bytes())?;
    put(dir, "svg", "square", SQUARE_SVG.as_bytes())?;
    put(dir, "dxf", "boundary", DXF_BLOCK.as_bytes())?;
    put(dir, "garmentcode", "two-panels", TWO_PANELS.as_bytes())?;
    // Messages: each kind, as a sender makes it (default values, this protocol).
    for kind in 0u8..12 {
        let mut bytes = vec![kind];
        let mut seq = 0;
        let h = Header::next(&mut seq);
        let mut model = shared::sim_to_haptic::LocalModel {
            header: h,
            plane_count: 1,
            ..Default::default()
        };
        model.planes[0] = [0.0, 1.0, 0.0, 0.0];
        let mut header = bytemuck::bytes_of(&h).to_vec();
        if kind == 0 {
            header = bytemuck::bytes_of(&model).to_vec();
            // Two ticks: the pen 1 cm into the plane, then pinching.
            for t in [[0.005f32, 0.0, -0.01, 0.0, 0.0, -0.1, 0.0, 0.001]; 2] {
                header.extend_from_slice(bytemuck::bytes_of(&t));
            }
        } else {
            header.resize(header.len() + 600, 0);
        }
        bytes.extend_from_slice(&header);
        put(dir, "messages", &format!("kind{kind}"), &bytes)?;
    }
    command_seeds(dir)?;
    put(
        dir,
        "replay",
        "log",
        b"# saiho device log v1\n0 0 0.6 0 0 0 0 0\n0.001 0 0.6 0 0.1 0 0 1\n0.002 0.001 0.6 0",
    )?;
    put(
        dir,
        "replay",
        "script",
        b"# t x y z buttons\n0 0 0.6 0 0\n1 0.1 0.6 0 1\n",
    )?;
    Ok(())
}

/// Commands: a session of edits and one of settings, each under every model.
fn command_seeds(dir: &Path) -> std::io::Result<()> {
    let session = [
        Command::Pin {
            vertex: 0,
            pinned: true,
        },
        Command::CutVertex {
            vertex: 12,
            direction: [1.0, 0.0, 0.0],
        },
        Command::Tear {
            a: 6,
            b: 7,
            split: true,
        },
        Command::Sew { a: 0, b: 4 },
        Command::Undo,
        Command::Paint {
            point: [0.0, 0.0, 0.0],
            radius_m: 0.05,
            rgba: [200, 10, 10, 255],
        },
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.2, h: 0.1 },
            place: 0,
            drop_m: 0.4,
            edge_m: 0.05,
        },
        Command::Seam {
            a: [[0.0, 0.0], [1.0, 0.0]],
            b: [[0.0, 1.0], [1.0, 1.0]],
            tolerance: 0.05,
        },
    ];
    let more = [
        Command::SetTearing(Tearing::On {
            threshold: 1.2,
            split: false,
        }),
        Command::SetMaterial {
            material: MaterialChange {
                stretch: Some(50.0),
                ..Default::default()
            },
            substeps: Some(3),
        },
        Command::SetFabric {
            name: "denim".into(),
        },
        Command::SetPieceFabric {
            piece: 0,
            name: "jersey-interlock".into(),
        },
        Command::NameSeam {
            seam: 0,
            name: "left side".into(),
        },
        Command::NamePiece {
            piece: 0,
            name: "front".into(),
        },
        Command::PressDart {
            seam: 0,
            second: true,
        },
        Command::DuplicatePiece {
            piece: 0,
            place: 1,
            drop_m: 0.0,
            mirrored: true,
            edge_m: 0.08,
        },
        Command::SetGuard { on: true },
        Command::SetStrainLimit { limit: 0.2 },
        Command::RemoveRegion {
            min: [0.2, 0.2],
            max: [0.6, 0.6],
        },
        Command::DeletePiece { piece: 0 },
        Command::Redo,
        Command::RemoveSeam { seam: 0 },
        Command::PlacePiece {
            piece: 0,
            place: 1,
            drop_m: 0.2,
        },
    ];
    for (name, cmds) in [("edits", &session[..]), ("settings", &more[..])] {
        for model in 0u8..3 {
            // A frame after every command, as when each arrives in its own frame.
            let mut bytes = vec![model, 0xff];
            for c in cmds.iter() {
                bytes.extend_from_slice(&wire(c));
            }
            put(dir, "commands", &format!("{name}-{model}"), &bytes)?;
        }
    }
    Ok(())
}

/// A block with a boundary polyline and a grain line, AAMA style.
const DXF_BLOCK: &str = "0\nSECTION\n2\nBLOCKS\n0\nBLOCK\n8\n0\n2\nfront\n70\n0\n10\n0\n20\n0\n30\n0\n3\nfront\n\
0\nPOLYLINE\n8\n1\n66\n1\n70\n1\n0\nVERTEX\n8\n1\n10\n0\n20\n0\n0\nVERTEX\n8\n1\n10\n400\n20\n0\n\
0\nVERTEX\n8\n1\n10\n400\n20\n600\n0\nVERTEX\n8\n1\n10\n0\n20\n600\n0\nSEQEND\n8\n1\n\
0\nLINE\n8\n7\n10\n200\n20\n100\n11\n200\n21\n500\n0\nTEXT\n8\n1\n10\n100\n20\n300\n40\n10\n1\nPiece Name: front\n\
0\nENDBLK\n8\n0\n0\nENDSEC\n0\nEOF\n";

/// Whether a seed reads as its target's input should (the first step each target takes
/// succeeds), so a seed that only exercises the refusals is noticed.
pub fn seed_reads(target: &str, bytes: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(bytes);
    let e = |e: &dyn std::fmt::Display| e.to_string();
    match target {
        "design" => Design::load_design(bytes).map(|_| ()).map_err(|x| e(&x)),
        "obj" => sim_core::mesh::obj::parse_obj(Path::new("seed.obj"), &text)
            .map(|_| ())
            .map_err(|x| e(&x)),
        "body" | "body-build" => {
            sim_core::collision::body::body_from_obj_text(Path::new("seed.obj"), &text)
                .map(|_| ())
                .map_err(|x| e(&x))
        }
        "outline" => {
            let mut loops = Vec::new();
            for part in bytes[1..].split(|&b| b == 0xff) {
                let l = part
                    .chunks_exact(2)
                    .map(|p| glam::Vec2::new(p[0] as f32 / 254.0, p[1] as f32 / 254.0))
                    .collect();
                loops.push(l);
            }
            let o = sim_core::mesh::mesher::Outline { loops };
            sim_core::mesh::mesher::mesh_outline(&o, 0.05)
                .map(|_| ())
                .map_err(|x| e(&x))
        }
        "svg" => sim_core::mesh::svg::read_svg(&text)
            .map(|_| ())
            .map_err(|x| e(&x)),
        "dxf" => sim_core::mesh::dxf::read_dxf(&text)
            .map(|_| ())
            .map_err(|x| e(&x)),
        "garmentcode" => sim_core::design::garment::read_garmentcode(
            &text,
            &sim_core::design::garment::Landmarks::of(None),
        )
        .map(|_| ()),
        "commands" => bytes[2..]
            .chunks_exact(std::mem::size_of::<ToolCommand>())
            .try_for_each(|c| {
                Command::from_wire(&bytemuck::pod_read_unaligned(c))
                    .map(|_| ())
                    .map_err(|x| e(&x))
            }),
        "replay" => haptic_loop::device::Replay::parse(&text)
            .map(|_| ())
            .or_else(|_| haptic_loop::device::Script::parse(&text).map(|_| ())),
        _ => Ok(()),
    }
}
