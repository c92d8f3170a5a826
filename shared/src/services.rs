//! One function per service, so every process opens each with the same quality of
//! service (iceoryx2 refuses to open a service whose settings differ).
//!
//! | service | payload | direction | history | buffer |
//! |---|---|---|---|---|
//! | `saiho/device` | [`DeviceSample`] | haptic -> sim, ui | 1 (latest) | 1, overwrite |
//! | `saiho/applied-force` | [`AppliedForce`] | haptic -> sim | 1 | up to 64 (sim 4), overwrite |
//! | `saiho/local-model` | [`LocalModel`] | sim -> haptic | 1 (latest) | up to 8 (haptic, ui 1), overwrite |
//! | `saiho/pointer` | [`PointerInput`] | ui -> haptic | 1 (latest) | 1, overwrite |
//! | `saiho/telemetry/haptic` | [`LoopTelemetry`] | haptic -> ui, tools | 1 | 2, overwrite |
//! | `saiho/telemetry/sim` | [`SimTelemetry`] | sim -> ui, tools | 1 | 2, overwrite |
//! | `saiho/cloth-frame` | `[f32]` + [`ClothFrameHeader`] | sim -> ui | 1 (latest) | 1, overwrite |
//! | `saiho/cloth-mesh` | `[MeshCorner]` + [`MeshHeader`] | sim -> ui | 1 (latest) | 1, overwrite |
//!
//! | `saiho/texture` | `[u8]` + [`TextureTile`] | sim -> ui | 256 (a full texture) | 512, overwrite |
//! | `saiho/tool-state` | [`ToolState`] | sim -> ui | 1 (latest) | 1, overwrite |
//! | `saiho/pieces` | [`PieceList`] | sim -> ui | 1 (latest) | 1, overwrite |
//! | `saiho/commands` | [`ToolCommand`] -> [`CommandReply`] | ui -> sim | request-response | |
//!
//! History 1 gives a process that starts late the current value at once.

use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;

use crate::haptic_to_sim::{AppliedForce, DeviceSample};
use crate::sim_to_haptic::LocalModel;
use crate::sim_to_ui::{
    BodyMeshHeader, ClothFrameHeader, MeshCorner, MeshHeader, PieceList, TextureTile, ToolState,
};
use crate::telemetry::{LoopTelemetry, SimTelemetry};
use crate::ui_to_haptic::PointerInput;
use crate::ui_to_sim::{CommandReply, ToolCommand};

pub const DEVICE: &str = "saiho/device";
pub const APPLIED_FORCE: &str = "saiho/applied-force";
pub const LOCAL_MODEL: &str = "saiho/local-model";
pub const POINTER: &str = "saiho/pointer";
pub const HAPTIC_TELEMETRY: &str = "saiho/telemetry/haptic";
pub const SIM_TELEMETRY: &str = "saiho/telemetry/sim";
pub const CLOTH_FRAME: &str = "saiho/cloth-frame";
pub const CLOTH_MESH: &str = "saiho/cloth-mesh";
pub const COMMANDS: &str = "saiho/commands";
pub const TOOL_STATE: &str = "saiho/tool-state";
pub const PIECES: &str = "saiho/pieces";
pub const TEXTURE: &str = "saiho/texture";
pub const BODY_MESH: &str = "saiho/body-mesh";
/// cloth-latency's echo of device samples, opened with the device service's QoS.
pub const DEVICE_ECHO: &str = "saiho/latency/device-echo";
/// History of the texture service: every tile of a 1024 x 1024 texture in 64 x 64 tiles.
pub const TEXTURE_HISTORY: usize = 256;

#[derive(Debug, thiserror::Error)]
pub enum ServiceError {
    #[error(
        "service {service}: its message type differs from this build's (protocol mismatch between processes; run matching builds)"
    )]
    Mismatch { service: &'static str },
    #[error("service {service}: {detail}")]
    Open {
        service: &'static str,
        detail: String,
    },
}

pub type Factory<T> = PortFactory<ipc::Service, T, ()>;
pub type SliceFactory<T, H> = PortFactory<ipc::Service, [T], H>;
pub type Pub<T> = Publisher<ipc::Service, T, ()>;
pub type SlicePub<T, H> = Publisher<ipc::Service, [T], H>;
pub type SliceSub<T, H> = Subscriber<ipc::Service, [T], H>;
pub type Sub<T> = Subscriber<ipc::Service, T, ()>;

fn service_name(service: &'static str) -> Result<ServiceName, ServiceError> {
    service.try_into().map_err(|e| ServiceError::Open {
        service,
        detail: format!("{e:?}"),
    })
}

/// An open failure, told apart as a message-type mismatch when iceoryx2 names it
/// `mismatch` (its error variants differ per messaging pattern).
fn open_error(service: &'static str, e: impl core::fmt::Debug, mismatch: &str) -> ServiceError {
    let detail = format!("{e:?}");
    if detail.contains(mismatch) {
        ServiceError::Mismatch { service }
    } else {
        ServiceError::Open { service, detail }
    }
}

fn open<T: core::fmt::Debug + ZeroCopySend + 'static>(
    node: &Node<ipc::Service>,
    service: &'static str,
    history: usize,
    buffer: usize,
) -> Result<Factory<T>, ServiceError> {
    let name = service_name(service)?;
    node.service_builder(&name)
        .publish_subscribe::<T>()
        .history_size(history)
        .subscriber_max_buffer_size(buffer)
        .subscriber_max_borrowed_samples(2)
        .max_publishers(2)
        .max_subscribers(8)
        .enable_safe_overflow(true)
        .open_or_create()
        .map_err(|e| open_error(service, e, "IncompatibleTypes"))
}

/// Subscribers may buffer up to 32 samples: cloth-sim replays the pen's path of the last
/// frame (about 17 samples at 60 Hz) through its substeps.
pub fn device(node: &Node<ipc::Service>) -> Result<Factory<DeviceSample>, ServiceError> {
    open(node, DEVICE, 1, 32)
}

/// The device service's twin for round trips (cloth-latency ping): same QoS, so the
/// measured path is the one device samples take.
pub fn device_echo(node: &Node<ipc::Service>) -> Result<Factory<DeviceSample>, ServiceError> {
    open(node, DEVICE_ECHO, 1, 32)
}

/// Subscribers may buffer up to 64 (64 ms of forces): cloth-sim takes 4, the newest, for
/// the reaction on the cloth; an observer that checks every force (the soak, the process
/// tests) takes them all even when it is held up for tens of milliseconds.
pub fn applied_force(node: &Node<ipc::Service>) -> Result<Factory<AppliedForce>, ServiceError> {
    open(node, APPLIED_FORCE, 1, 64)
}

/// Subscribers may buffer up to 64 (half a second of models, two a 60 Hz frame): the haptic
/// loop and the studio take 1, the newest; an observer that judges the gaps between models
/// (the soak) takes all 64, so that being held up itself does not look like cloth-sim
/// stalling. With 8 (65 ms), a soak held up 66-89 ms while a UI restarted beside it read
/// three stalls that cloth-sim's own log, which then listed every gap of 50 ms, did not have.
pub fn local_model(node: &Node<ipc::Service>) -> Result<Factory<LocalModel>, ServiceError> {
    open(node, LOCAL_MODEL, 1, 64)
}

pub fn pointer(node: &Node<ipc::Service>) -> Result<Factory<PointerInput>, ServiceError> {
    open(node, POINTER, 1, 1)
}

pub fn sim_telemetry(node: &Node<ipc::Service>) -> Result<Factory<SimTelemetry>, ServiceError> {
    open(node, SIM_TELEMETRY, 1, 2)
}

pub fn tool_state(node: &Node<ipc::Service>) -> Result<Factory<ToolState>, ServiceError> {
    open(node, TOOL_STATE, 1, 1)
}

pub fn pieces(node: &Node<ipc::Service>) -> Result<Factory<PieceList>, ServiceError> {
    open(node, PIECES, 1, 1)
}

pub fn haptic_telemetry(node: &Node<ipc::Service>) -> Result<Factory<LoopTelemetry>, ServiceError> {
    open(node, HAPTIC_TELEMETRY, 1, 2)
}

fn open_slice<T, H>(
    node: &Node<ipc::Service>,
    service: &'static str,
    history: usize,
    buffer: usize,
) -> Result<SliceFactory<T, H>, ServiceError>
where
    T: core::fmt::Debug + ZeroCopySend + 'static,
    H: core::fmt::Debug + ZeroCopySend + 'static,
{
    let name = service_name(service)?;
    node.service_builder(&name)
        .publish_subscribe::<[T]>()
        .user_header::<H>()
        .history_size(history)
        .subscriber_max_buffer_size(buffer)
        .subscriber_max_borrowed_samples(2)
        .max_publishers(2)
        .max_subscribers(8)
        .enable_safe_overflow(true)
        .open_or_create()
        .map_err(|e| open_error(service, e, "IncompatibleTypes"))
}

/// Cloth positions and normals, every frame (publishers: `initial_max_slice_len` of
/// `6 * vertices` with a power-of-two allocation strategy, so cuts can grow it).
pub fn cloth_frame(
    node: &Node<ipc::Service>,
) -> Result<SliceFactory<f32, ClothFrameHeader>, ServiceError> {
    open_slice(node, CLOTH_FRAME, 1, 1)
}

/// The cloth's triangles with per-corner UVs, when the topology changes.
pub fn cloth_mesh(
    node: &Node<ipc::Service>,
) -> Result<SliceFactory<MeshCorner, MeshHeader>, ServiceError> {
    open_slice(node, CLOTH_MESH, 1, 1)
}

/// The body's triangles, once (history 1: a late viewer gets it).
pub fn body_mesh(
    node: &Node<ipc::Service>,
) -> Result<SliceFactory<f32, BodyMeshHeader>, ServiceError> {
    open_slice(node, BODY_MESH, 1, 1)
}

pub type Commands = iceoryx2::service::port_factory::request_response::PortFactory<
    ipc::Service,
    ToolCommand,
    (),
    CommandReply,
    (),
>;

/// Operations on the design, each with a reply.
pub fn commands(node: &Node<ipc::Service>) -> Result<Commands, ServiceError> {
    let service = COMMANDS;
    let name = service_name(service)?;
    node.service_builder(&name)
        .request_response::<ToolCommand, CommandReply>()
        .enable_safe_overflow_for_requests(true)
        .enable_safe_overflow_for_responses(true)
        .open_or_create()
        .map_err(|e| open_error(service, e, "IncompatibleRequestOrResponseType"))
}

/// The texture as tiles (see [`TextureTile`]).
pub fn texture(node: &Node<ipc::Service>) -> Result<SliceFactory<u8, TextureTile>, ServiceError> {
    open_slice(node, TEXTURE, TEXTURE_HISTORY, 2 * TEXTURE_HISTORY)
}

/// A node in `domain`, with iceoryx2's own signal handlers off (each process handles
/// SIGINT/SIGTERM itself) and stale resources of dead nodes removed. The domain's shared
/// memory is checked before (another user's file there is refused, not opened) and closed
/// to other users after (iceoryx2 makes its management segment world-writable).
pub fn node(
    domain: &crate::domain::Domain,
    name: &str,
) -> Result<Node<ipc::Service>, ServiceError> {
    let open = |detail: String| ServiceError::Open {
        service: "node",
        detail,
    };
    let cfg = domain.config().map_err(|e| open(e.to_string()))?;
    domain
        .secure_shared_memory()
        .map_err(|e| open(e.to_string()))?;
    cleanup_dead_nodes(&cfg);
    let node_name: NodeName = name.try_into().map_err(|e| open(format!("{e:?}")))?;
    let node = NodeBuilder::new()
        .name(&node_name)
        .config(&cfg)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .map_err(|e| open(format!("{e:?}")))?;
    domain
        .secure_shared_memory()
        .map_err(|e| open(e.to_string()))?;
    Ok(node)
}

/// How many nodes of the domain configured by `cfg` are alive now.
pub fn alive_nodes(cfg: &Config) -> usize {
    let mut alive = 0;
    let _ = Node::<ipc::Service>::list(cfg, |state| {
        if matches!(state, NodeState::Alive(_)) {
            alive += 1;
        }
        CallbackProgression::Continue
    });
    alive
}

/// A clean stop's last step, after the process's node and ports are dropped: when no
/// other node of the domain is alive, removes what the domain left (its management
/// segment in /dev/shm and its root directory), so a clean stop leaves nothing behind.
/// Returns whether it did. A process that starts in the same instant opens a new
/// management segment; the one it may have mapped is only a node counter.
pub fn release(domain: &crate::domain::Domain) -> bool {
    let Ok(cfg) = domain.config() else {
        return false;
    };
    cleanup_dead_nodes(&cfg);
    if alive_nodes(&cfg) == 0 {
        domain.remove_leftovers();
        true
    } else {
        false
    }
}

/// Calls [`release`] for its domain when dropped. Declared before a process's node, it
/// is dropped after the node and its ports, on every way out of the function (an error
/// returned included).
pub struct ReleaseOnDrop(pub crate::domain::Domain);

impl Drop for ReleaseOnDrop {
    fn drop(&mut self) {
        release(&self.0);
    }
}

/// Removes what dead processes of this domain left behind; returns how many nodes.
pub fn cleanup_dead_nodes(cfg: &Config) -> usize {
    let mut removed = 0;
    let _ = Node::<ipc::Service>::list(cfg, |state| {
        if let NodeState::Dead(view) = state
            && view.try_remove_stale_resources().is_ok()
        {
            removed += 1;
        }
        CallbackProgression::Continue
    });
    removed
}
