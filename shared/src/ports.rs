//! Every port a process opens, built here and nowhere else: one struct per process
//! ([`SimPorts`] for cloth-sim, [`UiPorts`] for cloth-ui, [`HapticPorts`] for the haptic
//! loop, [`DesignerPorts`] for cloth-lab's scripted designer) and the single-port
//! builders cloth-latency composes its measurements from. Each service is opened through
//! its function in [`services`](crate::services), so its quality of service is the same
//! in every process.
//!
//! Ports are `!Send` in iceoryx2: build them on the thread that uses them.

use iceoryx2::port::client::Client;
use iceoryx2::port::server::Server;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;

use crate::haptic_to_sim::{AppliedForce, DeviceSample};
use crate::services::{self, Pub, ServiceError, SlicePub, SliceSub, Sub};
use crate::sim_to_haptic::LocalModel;
use crate::sim_to_ui::{
    BodyMeshHeader, ClothFrameHeader, MeshCorner, MeshHeader, PieceList, TextureTile, ToolState,
};
use crate::telemetry::{LoopTelemetry, SimTelemetry};
use crate::ui_to_haptic::PointerInput;
use crate::ui_to_sim::{CommandReply, ToolCommand};

/// Why a port could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum PortError {
    #[error(transparent)]
    Service(#[from] ServiceError),
    #[error("cannot create a {kind} on {service}: {detail}")]
    Create {
        kind: &'static str,
        service: String,
        detail: String,
    },
}

/// The service opener of one message type (a function of [`services`]): `P` the payload
/// (a type, or a slice `[T]`), `H` the user header.
pub type Open<P, H = ()> =
    fn(&Node<ipc::Service>) -> Result<PubSubFactory<ipc::Service, P, H>, ServiceError>;
/// The same for a slice service with a user header.
pub type OpenSlice<T, H> = Open<[T], H>;

pub type CommandClient = Client<ipc::Service, ToolCommand, (), CommandReply, ()>;
pub type CommandServer = Server<ipc::Service, ToolCommand, (), CommandReply, ()>;

fn create_error(kind: &'static str, service: &str, e: impl core::fmt::Debug) -> PortError {
    PortError::Create {
        kind,
        service: service.to_string(),
        detail: format!("{e:?}"),
    }
}

/// A subscriber on `open`'s service (plain or slice); `buffer` overrides the
/// subscriber's buffer size.
pub fn subscriber<P, H>(
    node: &Node<ipc::Service>,
    open: Open<P, H>,
    buffer: Option<usize>,
) -> Result<Subscriber<ipc::Service, P, H>, PortError>
where
    P: core::fmt::Debug + IceoryxSend + ?Sized + 'static,
    H: core::fmt::Debug + ZeroCopySend + 'static,
{
    let factory = open(node)?;
    let service = factory.name().as_str().to_string();
    let mut b = factory.subscriber_builder();
    if let Some(n) = buffer {
        b = b.buffer_size(n);
    }
    b.create()
        .map_err(|e| create_error("subscriber", &service, e))
}

/// A publisher on `open`'s service.
pub fn publisher<T>(node: &Node<ipc::Service>, open: Open<T>) -> Result<Pub<T>, PortError>
where
    T: core::fmt::Debug + ZeroCopySend + 'static,
{
    let factory = open(node)?;
    let service = factory.name().as_str().to_string();
    factory
        .publisher_builder()
        .create()
        .map_err(|e| create_error("publisher", &service, e))
}

/// A publisher on a slice service whose slices start at `initial_len` elements (at least
/// one); with `grow`, larger slices get power-of-two allocations instead of failing.
pub fn slice_publisher<T, H>(
    node: &Node<ipc::Service>,
    open: OpenSlice<T, H>,
    initial_len: usize,
    grow: bool,
) -> Result<SlicePub<T, H>, PortError>
where
    T: core::fmt::Debug + ZeroCopySend + 'static,
    H: core::fmt::Debug + ZeroCopySend + 'static,
{
    let factory = open(node)?;
    let service = factory.name().as_str().to_string();
    let mut b = factory
        .publisher_builder()
        .initial_max_slice_len(initial_len.max(1));
    if grow {
        b = b.allocation_strategy(AllocationStrategy::PowerOfTwo);
    }
    b.create()
        .map_err(|e| create_error("publisher", &service, e))
}

/// The command client (cloth-ui, cloth-lab's designer).
pub fn command_client(node: &Node<ipc::Service>) -> Result<CommandClient, PortError> {
    services::commands(node)?
        .client_builder()
        .create()
        .map_err(|e| create_error("client", services::COMMANDS, e))
}

/// The command server (cloth-sim).
pub fn command_server(node: &Node<ipc::Service>) -> Result<CommandServer, PortError> {
    services::commands(node)?
        .server_builder()
        .create()
        .map_err(|e| create_error("server", services::COMMANDS, e))
}

/// A raw publish-subscribe pair of device samples with iceoryx2's default settings (not
/// the project's QoS): a publisher on service `tx` and a subscriber on `rx`.
/// cloth-latency measures it beside the device service, as the floor of the transport.
pub fn raw_device_pair(
    node: &Node<ipc::Service>,
    tx: &'static str,
    rx: &'static str,
) -> Result<(Pub<DeviceSample>, Sub<DeviceSample>), PortError> {
    let open = |n: &'static str| {
        let name: ServiceName = n.try_into().map_err(|e| create_error("service", n, e))?;
        node.service_builder(&name)
            .publish_subscribe::<DeviceSample>()
            .open_or_create()
            .map_err(|e| create_error("service", n, e))
    };
    let p = open(tx)?
        .publisher_builder()
        .create()
        .map_err(|e| create_error("publisher", tx, e))?;
    let s = open(rx)?
        .subscriber_builder()
        .create()
        .map_err(|e| create_error("subscriber", rx, e))?;
    Ok((p, s))
}

/// How large cloth-sim's slices start (they grow by powers of two after an edit).
#[derive(Clone, Copy, Debug)]
pub struct SimSizes {
    /// Floats in a cloth frame: positions and normals, `6 * vertices`.
    pub frame_floats: usize,
    /// Corners in the mesh: `3 * triangles`.
    pub mesh_corners: usize,
    /// Floats in the body: `3 * vertices + 3 * triangles`.
    pub body_floats: usize,
    /// Bytes in one texture tile.
    pub tile_bytes: usize,
}

/// cloth-sim's ports.
pub struct SimPorts {
    /// The pen's samples; up to 32 buffered, the path of a frame's interval.
    pub device: Sub<DeviceSample>,
    pub applied: Sub<AppliedForce>,
    pub model: Pub<LocalModel>,
    pub frame: SlicePub<f32, ClothFrameHeader>,
    pub mesh: SlicePub<MeshCorner, MeshHeader>,
    pub body: SlicePub<f32, BodyMeshHeader>,
    pub commands: CommandServer,
    pub tool: Pub<ToolState>,
    pub pieces: Pub<PieceList>,
    pub texture: SlicePub<u8, TextureTile>,
    pub telemetry: Pub<SimTelemetry>,
}

impl SimPorts {
    pub fn open(node: &Node<ipc::Service>, sizes: SimSizes) -> Result<Self, PortError> {
        Ok(Self {
            device: subscriber(node, services::device, Some(32))?,
            applied: subscriber(node, services::applied_force, Some(4))?,
            model: publisher(node, services::local_model)?,
            frame: slice_publisher(node, services::cloth_frame, sizes.frame_floats, true)?,
            mesh: slice_publisher(node, services::cloth_mesh, sizes.mesh_corners, true)?,
            body: slice_publisher(node, services::body_mesh, sizes.body_floats, true)?,
            commands: command_server(node)?,
            tool: publisher(node, services::tool_state)?,
            pieces: publisher(node, services::pieces)?,
            texture: slice_publisher(node, services::texture, sizes.tile_bytes, false)?,
            telemetry: publisher(node, services::sim_telemetry)?,
        })
    }
}

/// cloth-ui's ports.
pub struct UiPorts {
    pub frames: SliceSub<f32, ClothFrameHeader>,
    pub meshes: SliceSub<MeshCorner, MeshHeader>,
    pub tiles: SliceSub<u8, TextureTile>,
    pub bodies: SliceSub<f32, BodyMeshHeader>,
    pub tools: Sub<ToolState>,
    pub pieces: Sub<PieceList>,
    pub pens: Sub<DeviceSample>,
    pub models: Sub<LocalModel>,
    pub loop_telemetry: Sub<LoopTelemetry>,
    pub sim_telemetry: Sub<SimTelemetry>,
    pub commands: CommandClient,
    pub pointer: Pub<PointerInput>,
}

impl UiPorts {
    pub fn open(node: &Node<ipc::Service>) -> Result<Self, PortError> {
        Ok(Self {
            frames: subscriber(node, services::cloth_frame, None)?,
            meshes: subscriber(node, services::cloth_mesh, None)?,
            tiles: subscriber(node, services::texture, None)?,
            bodies: subscriber(node, services::body_mesh, None)?,
            tools: subscriber(node, services::tool_state, None)?,
            pieces: subscriber(node, services::pieces, None)?,
            pens: subscriber(node, services::device, None)?,
            models: subscriber(node, services::local_model, Some(1))?,
            loop_telemetry: subscriber(node, services::haptic_telemetry, None)?,
            sim_telemetry: subscriber(node, services::sim_telemetry, None)?,
            commands: command_client(node)?,
            pointer: publisher(node, services::pointer)?,
        })
    }
}

/// The haptic loop's ports.
pub struct HapticPorts {
    pub device: Pub<DeviceSample>,
    pub applied: Pub<AppliedForce>,
    pub telemetry: Pub<LoopTelemetry>,
    pub model: Sub<LocalModel>,
    pub pointer: Sub<PointerInput>,
    /// The local model's service, for the processes that publish on it.
    model_service: services::Factory<LocalModel>,
}

impl HapticPorts {
    pub fn open(node: &Node<ipc::Service>) -> Result<Self, PortError> {
        Ok(Self {
            device: publisher(node, services::device)?,
            applied: publisher(node, services::applied_force)?,
            telemetry: publisher(node, services::haptic_telemetry)?,
            model: subscriber(node, services::local_model, Some(1))?,
            pointer: subscriber(node, services::pointer, None)?,
            model_service: services::local_model(node).map_err(PortError::Service)?,
        })
    }

    /// The pids of the processes whose publishers the local model's service lists (up to
    /// two, 0 for none): cloth-sim, and a killed one until its ports are cleaned up. No
    /// allocation (iceoryx2 walks its shared list).
    pub fn model_publisher_pids(&self) -> [u32; 2] {
        use iceoryx2::service::port_factory::PortFactory as _;
        let mut out = [0u32; 2];
        let mut n = 0;
        self.model_service.dynamic_config().list_publishers(|p| {
            if let Ok(pid) = p.node_id.pid::<ipc::Service>()
                && n < out.len()
            {
                out[n] = pid.value() as u32;
                n += 1;
            }
            iceoryx2::prelude::CallbackProgression::Continue
        });
        out
    }
}

/// The ports of cloth-lab's scripted designer (a UI stand-in): the cloth in, commands out.
pub struct DesignerPorts {
    pub frames: SliceSub<f32, ClothFrameHeader>,
    pub meshes: SliceSub<MeshCorner, MeshHeader>,
    pub commands: CommandClient,
}

impl DesignerPorts {
    pub fn open(node: &Node<ipc::Service>) -> Result<Self, PortError> {
        Ok(Self {
            frames: subscriber(node, services::cloth_frame, None)?,
            meshes: subscriber(node, services::cloth_mesh, None)?,
            commands: command_client(node)?,
        })
    }
}
