//! The UI's connection to the running system over iceoryx2: everything cloth-sim and
//! haptic-loop publish comes in here, is checked, and lands in the `Store`; commands go
//! out with their replies collected; the mouse goes to the simulated pen. Nothing from
//! another process is trusted: a message that fails its checks is counted and shown, never
//! used.

use iceoryx2::pending_response::PendingResponse;
use iceoryx2::prelude::*;
use shared::command::Command;
use shared::domain::Domain;
use shared::ports::UiPorts;
use shared::sim_to_ui::{
    check_body, check_frame, check_mesh, check_outline, check_pieces, check_pins,
    check_seam_segments, check_seams, check_source, check_tile, check_tool_state, frame_stitches,
};
use shared::ui_to_haptic::PointerInput;
use shared::ui_to_sim::{CommandReply, ToolCommand};
use shared::{Checked, Header, services};

use crate::store::{Mesh, Store, vertex_normals};

type Pending = PendingResponse<ipc::Service, ToolCommand, (), CommandReply, ()>;

pub struct Link {
    pub domain: Domain,
    _node: Node<ipc::Service>,
    ports: UiPorts,
    pending: Vec<(u32, Pending, std::time::Instant)>,
    /// The pen's answers (a cut stroke, a sew or pin by the pen) that came with the tool
    /// state since the last poll: what the mouse's stroke did, for the status line.
    pen_answers: Vec<Answer>,
    seq_cmd: u64,
    seq_ptr: u64,
    /// Last, so dropped after the node and ports: a clean stop leaves nothing behind.
    _release: services::ReleaseOnDrop,
}

/// A reply to a command the UI sent, or that none came.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    /// The command's op; for an answer of the pen, `SET_TOOL` (the tool it acted with).
    pub op: u32,
    pub ok: bool,
    pub message: String,
}

impl Link {
    /// Opens every port in `domain`; the error says which one failed and why (a protocol
    /// mismatch says so).
    pub fn open(domain: &Domain) -> Result<Self, String> {
        let node = services::node(domain, "cloth-ui").map_err(|x| x.to_string())?;
        let ports = UiPorts::open(&node).map_err(|x| x.to_string())?;
        Ok(Self {
            ports,
            _node: node,
            domain: domain.clone(),
            pending: Vec::new(),
            pen_answers: Vec::new(),
            seq_cmd: 0,
            seq_ptr: 0,
            _release: services::ReleaseOnDrop(domain.clone()),
        })
    }

    /// Takes in everything that arrived; returns the replies to commands.
    pub fn poll(&mut self, store: &mut Store) -> Vec<Answer> {
        let now = std::time::Instant::now();
        self.poll_cloth(store, now);
        self.poll_state(store, now);
        self.answers()
    }

    /// The cloth (mesh, positions, texture) and the body.
    fn poll_cloth(&mut self, store: &mut Store, now: std::time::Instant) {
        let p = &self.ports;
        // The mesh before the frames, so positions meet their triangles.
        while let Ok(Some(m)) = p.meshes.receive() {
            let h = *m.user_header();
            match check_mesh(&h, m.payload()) {
                Ok(()) => {
                    store.mesh = Some(Mesh::new(
                        h.topology,
                        h.vertices as usize,
                        m.payload().to_vec(),
                    ));
                    store.mesh_generation += 1;
                    store.heard.sim = Some(now);
                }
                Err(x) => store.record(&x),
            }
        }
        let mut newest = None;
        while let Ok(Some(f)) = p.frames.receive() {
            let h = *f.user_header();
            match check_frame(&h, f.payload()) {
                Ok(()) => newest = Some((h, f.payload().to_vec())),
                Err(x) => store.record(&x),
            }
        }
        if let Some((h, p)) = newest {
            let n = h.vertices as usize;
            store.x = p[..3 * n]
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            store.normals = p[3 * n..]
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            if store.normals.len() != n {
                store.normals = vertex_normals(store.mesh.as_ref(), &store.x);
            }
            store.stitches = frame_stitches(&h, &p);
            store.frame = h.frame;
            store.heard.sim = Some(now);
        }
        while let Ok(Some(t)) = p.tiles.receive() {
            let h = *t.user_header();
            match check_tile(&h, t.payload()) {
                Ok(()) => store.texture.apply(
                    h.width as usize,
                    h.height as usize,
                    [h.x0, h.y0, h.w, h.h].map(|v| v as usize),
                    t.payload(),
                ),
                Err(x) => store.record(&x),
            }
        }
        while let Ok(Some(b)) = p.bodies.receive() {
            match check_body(b.user_header(), b.payload()) {
                Ok(body) => {
                    store.body = Some(body);
                    store.body_version += 1;
                }
                Err(x) => store.record(&x),
            }
        }
    }

    /// The tool state, the pen, the local model and both telemetries.
    fn poll_state(&mut self, store: &mut Store, now: std::time::Instant) {
        let p = &self.ports;
        while let Ok(Some(l)) = p.pieces.receive() {
            let checked = check_pieces(&l).and_then(|p| {
                Ok((
                    p,
                    check_seams(&l)?,
                    check_seam_segments(&l)?,
                    (check_outline(&l)?, check_source(&l)?, check_pins(&l)?),
                ))
            });
            match checked {
                Ok((list, seams, segments, (outline, source, pins))) => {
                    store.source = source;
                    store.pins = pins;
                    store.pins_total = l.pin_total;
                    store.pieces = list;
                    store.pieces_total = l.total;
                    store.seams = seams;
                    store.seams_total = l.seam_total;
                    store.seam_segments = segments;
                    store.outline = outline;
                    store.outline_total = l.outline_total;
                }
                Err(x) => store.record(&x),
            }
        }
        while let Ok(Some(s)) = p.tools.receive() {
            match check_tool_state(&s) {
                Ok(said) => {
                    // A new answer of the pen (not the one a newly started studio finds).
                    let before = store.tool.map(|t| t.pen_said);
                    if let (Some((ok, message)), Some(b)) = (said, before)
                        && b != s.pen_said
                    {
                        self.pen_answers.push(Answer {
                            op: shared::ui_to_sim::op::SET_TOOL,
                            ok,
                            message,
                        });
                    }
                    store.tool = Some(*s);
                }
                Err(x) => store.record(&x),
            }
        }
        while let Ok(Some(s)) = p.pens.receive() {
            match s.check() {
                Ok(()) => {
                    store.pen = Some(*s);
                    store.heard.haptic = Some(now);
                }
                Err(x) => store.record(&x),
            }
        }
        while let Ok(Some(s)) = p.models.receive() {
            match s.check() {
                Ok(()) => store.model = Some(*s),
                Err(x) => store.record(&x),
            }
        }
        let mut sample = false;
        while let Ok(Some(s)) = p.loop_telemetry.receive() {
            match s.check() {
                Ok(()) => {
                    store.loop_tel = Some(Box::new(*s));
                    store.heard.haptic = Some(now);
                    sample = true;
                }
                Err(x) => store.record(&x),
            }
        }
        while let Ok(Some(s)) = p.sim_telemetry.receive() {
            match s.check() {
                Ok(()) => store.sim_tel = Some(Box::new(*s)),
                Err(x) => store.record(&x),
            }
        }
        if sample {
            store.push_sample();
        }
    }

    /// The replies that came in, and the commands that waited too long for one.
    fn answers(&mut self) -> Vec<Answer> {
        let mut answers = std::mem::take(&mut self.pen_answers);
        self.pending.retain(|(op, p, sent)| match p.receive() {
            Ok(Some(r)) => {
                answers.push(match r.check() {
                    Ok(()) => Answer {
                        op: *op,
                        ok: r.ok == 1,
                        message: r.message().to_string(),
                    },
                    Err(x) => Answer {
                        op: *op,
                        ok: false,
                        message: format!("unreadable reply: {x}"),
                    },
                });
                false
            }
            _ if sent.elapsed().as_secs_f64() > 5.0 => {
                answers.push(Answer {
                    op: *op,
                    ok: false,
                    message: "no reply from cloth-sim within 5 s".into(),
                });
                false
            }
            _ => true,
        });
        answers
    }

    /// Sends a command; its reply comes back from a later `poll`.
    pub fn send(&mut self, command: &Command) -> Result<(), String> {
        let c = command
            .to_wire(Header::next(&mut self.seq_cmd))
            .map_err(|x| x.to_string())?;
        let p = self
            .ports
            .commands
            .send_copy(c)
            .map_err(|x| format!("Sending the command failed: {x:?}"))?;
        if p.number_of_server_connections() == 0 {
            return Err(
                "cloth-sim is not running: the command was not delivered (start it, or cloth-lab)"
                    .into(),
            );
        }
        self.pending.push((c.op, p, std::time::Instant::now()));
        Ok(())
    }

    /// Moves the simulated pen's hand to `target` with `buttons`.
    pub fn point(&mut self, target: [f32; 3], buttons: u32) {
        let _ = self.ports.pointer.send_copy(PointerInput {
            header: Header::next(&mut self.seq_ptr),
            target,
            buttons,
            _reserved: 0,
            _pad: 0,
        });
    }
}
