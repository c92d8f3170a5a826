//! The real Phantom / Touch through OpenHaptics' HDAPI, loaded at run time from `libHD.so`
//! (libloading: no link-time dependency, so the project builds without the SDK).
//!
//! OpenHaptics runs its own 1 kHz servo thread. Our servo callback (scheduled with
//! `hdScheduleAsynchronous` at the maximum priority) does one device frame per call:
//! `hdBeginFrame`, read `HD_CURRENT_POSITION` / `HD_CURRENT_VELOCITY` (mm, mm/s) and
//! `HD_CURRENT_BUTTONS`, write `HD_CURRENT_FORCE` (N), `hdEndFrame`, `hdGetError`. It
//! exchanges state with the haptic loop through atomics only (no lock, no allocation):
//! the loop reads the latest pen state and publishes the force the next frame sends.
//! A device error (`hdGetError` in the 0x02xx force or 0x03xx device ranges) makes the
//! callback send zero force from then on, and `read` reports it (the loop logs it once).
//!
//! Enum values are those of OpenHaptics 3.x `hdDefines.h`.

use std::ffi::{c_char, c_double, c_int, c_uint, c_ulong, c_ushort, c_void};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

use shared::sim_to_haptic::DEFAULT_WORKSPACE_SCALE;

use super::{DeviceError, DeviceState, HapticDevice, PointerTarget, Workspace};

pub type Hhd = c_uint;
pub const HD_INVALID_HANDLE: Hhd = c_uint::MAX;
pub const HD_CURRENT_BUTTONS: c_uint = 0x2000;
pub const HD_CURRENT_POSITION: c_uint = 0x2050;
pub const HD_CURRENT_VELOCITY: c_uint = 0x2051;
pub const HD_CURRENT_FORCE: c_uint = 0x2700;
pub const HD_FORCE_OUTPUT: c_uint = 0x4000;
pub const HD_CALLBACK_CONTINUE: c_uint = 1;
pub const HD_CALLBACK_DONE: c_uint = 0;
/// How far from its origin a Phantom's tip can be, mm, on any axis (a Touch's arm reaches
/// under 300 mm; its workspace is 160 x 120 x 70 mm): a reading beyond is a glitch.
pub const REACH_MM: f64 = 400.0;

pub const HD_MAX_SCHEDULER_PRIORITY: c_ushort = c_ushort::MAX;
pub const HD_CALIBRATION_OK: c_uint = 0x5000;
pub const HD_CALIBRATION_NEEDS_UPDATE: c_uint = 0x5001;
pub const HD_CALIBRATION_AUTO: c_uint = 0x0001;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct HdErrorInfo {
    pub error_code: c_uint,
    pub internal_error_code: c_int,
    pub hhd: Hhd,
}

type Callback = extern "C" fn(*mut c_void) -> c_uint;

/// The HDAPI entry points we use, resolved from the library.
#[derive(Clone, Copy)]
struct Api {
    init_device: unsafe extern "C" fn(*const c_char) -> Hhd,
    disable_device: unsafe extern "C" fn(Hhd),
    enable: unsafe extern "C" fn(c_uint),
    get_error: unsafe extern "C" fn() -> HdErrorInfo,
    begin_frame: unsafe extern "C" fn(Hhd),
    end_frame: unsafe extern "C" fn(Hhd),
    get_doublev: unsafe extern "C" fn(c_uint, *mut c_double),
    get_integerv: unsafe extern "C" fn(c_uint, *mut c_int),
    set_doublev: unsafe extern "C" fn(c_uint, *const c_double),
    schedule_asynchronous: unsafe extern "C" fn(Callback, *mut c_void, c_ushort) -> c_ulong,
    unschedule: unsafe extern "C" fn(c_ulong),
    start_scheduler: unsafe extern "C" fn(),
    stop_scheduler: unsafe extern "C" fn(),
    check_calibration: unsafe extern "C" fn() -> c_uint,
    update_calibration: unsafe extern "C" fn(c_uint),
}

/// State shared between the servo callback and the loop (f64 as bits).
struct Shared {
    hhd: AtomicU32,
    pos: [AtomicU64; 3],
    vel: [AtomicU64; 3],
    buttons: AtomicU32,
    force: [AtomicU64; 3],
    frames: AtomicU64,
    error: AtomicU32,
    stop: AtomicBool,
}

static API: OnceLock<(libloading::Library, Api)> = OnceLock::new();
static SHARED: Shared = Shared {
    hhd: AtomicU32::new(HD_INVALID_HANDLE),
    pos: [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)],
    vel: [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)],
    buttons: AtomicU32::new(0),
    force: [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)],
    frames: AtomicU64::new(0),
    error: AtomicU32::new(0),
    stop: AtomicBool::new(false),
};

fn is_fatal(code: c_uint) -> bool {
    (0x0200..0x0400).contains(&code)
}

/// The servo callback, on OpenHaptics' scheduler thread: one device frame.
#[allow(unsafe_code)]
extern "C" fn servo(_: *mut c_void) -> c_uint {
    let Some((_, api)) = API.get() else {
        return HD_CALLBACK_DONE;
    };
    if SHARED.stop.load(Ordering::Acquire) {
        return HD_CALLBACK_DONE;
    }
    let hhd = SHARED.hhd.load(Ordering::Acquire);
    let mut p = [0.0f64; 3];
    let mut v = [0.0f64; 3];
    let mut b: c_int = 0;
    let failed = SHARED.error.load(Ordering::Acquire) != 0;
    let f: [f64; 3] = if failed {
        [0.0; 3]
    } else {
        std::array::from_fn(|i| f64::from_bits(SHARED.force[i].load(Ordering::Acquire)))
    };
    // SAFETY: the function pointers come from the loaded libHD, which stays loaded (it
    // lives in the static `API`); the buffers are 3 doubles / one int as HDAPI expects
    // for these parameters, and live across each call.
    let err = unsafe {
        (api.begin_frame)(hhd);
        (api.get_doublev)(HD_CURRENT_POSITION, p.as_mut_ptr());
        (api.get_doublev)(HD_CURRENT_VELOCITY, v.as_mut_ptr());
        (api.get_integerv)(HD_CURRENT_BUTTONS, &mut b);
        (api.set_doublev)(HD_CURRENT_FORCE, f.as_ptr());
        (api.end_frame)(hhd);
        (api.get_error)()
    };
    for i in 0..3 {
        SHARED.pos[i].store(p[i].to_bits(), Ordering::Release);
        SHARED.vel[i].store(v[i].to_bits(), Ordering::Release);
    }
    SHARED.buttons.store(b as u32, Ordering::Release);
    if is_fatal(err.error_code) {
        SHARED.error.store(err.error_code, Ordering::Release);
    }
    SHARED.frames.fetch_add(1, Ordering::AcqRel);
    HD_CALLBACK_CONTINUE
}

/// The OpenHaptics device (one per process: HDAPI's scheduler is process-wide).
pub struct OpenHaptics {
    workspace: Workspace,
    handle: c_ulong,
    last_frames: u64,
    stale_reads: u32,
}

impl OpenHaptics {
    /// Loads `lib` (e.g. `libHD.so`), initialises the default device, checks the
    /// calibration, enables force output, schedules the servo callback and starts the
    /// scheduler. Returns a notice when the calibration needed an update.
    #[allow(unsafe_code)]
    pub fn open(lib: &str, workspace: Workspace) -> Result<(Self, Option<String>), DeviceError> {
        let open = |e: String| DeviceError::Open(e);
        if API.get().is_some() {
            return Err(open("OpenHaptics is already open in this process".into()));
        }
        // SAFETY: loading a shared library runs its initialisers; libHD is the vendor's
        // library (or the test stand-in) and is trusted like any linked C library.
        let library = unsafe { libloading::Library::new(lib) }
            .map_err(|e| open(format!("cannot load {lib}: {e}")))?;
        macro_rules! sym {
            ($name:literal) => {
                // SAFETY: the symbol is an HDAPI C function with the signature of the
                // field it is stored in (hd.h); the pointer is only used while the
                // library stays loaded (it lives in the static `API`).
                *unsafe { library.get($name) }.map_err(|e| {
                    open(format!(
                        "{lib} lacks {}: {e}",
                        String::from_utf8_lossy($name)
                    ))
                })?
            };
        }
        let api = Api {
            init_device: sym!(b"hdInitDevice"),
            disable_device: sym!(b"hdDisableDevice"),
            enable: sym!(b"hdEnable"),
            get_error: sym!(b"hdGetError"),
            begin_frame: sym!(b"hdBeginFrame"),
            end_frame: sym!(b"hdEndFrame"),
            get_doublev: sym!(b"hdGetDoublev"),
            get_integerv: sym!(b"hdGetIntegerv"),
            set_doublev: sym!(b"hdSetDoublev"),
            schedule_asynchronous: sym!(b"hdScheduleAsynchronous"),
            unschedule: sym!(b"hdUnschedule"),
            start_scheduler: sym!(b"hdStartScheduler"),
            stop_scheduler: sym!(b"hdStopScheduler"),
            check_calibration: sym!(b"hdCheckCalibration"),
            update_calibration: sym!(b"hdUpdateCalibration"),
        };
        let api = API.get_or_init(|| (library, api)).1;
        SHARED.stop.store(false, Ordering::Release);
        SHARED.error.store(0, Ordering::Release);
        for f in &SHARED.force {
            f.store(0f64.to_bits(), Ordering::Release);
        }
        // SAFETY: HDAPI calls with valid arguments (a null name is HD_DEFAULT_DEVICE).
        let hhd = unsafe { (api.init_device)(std::ptr::null()) };
        // SAFETY: as above.
        let err = unsafe { (api.get_error)() };
        if hhd == HD_INVALID_HANDLE || err.error_code != 0 {
            return Err(open(format!(
                "hdInitDevice failed (error {:#06x}, internal {})",
                err.error_code, err.internal_error_code
            )));
        }
        SHARED.hhd.store(hhd, Ordering::Release);
        let mut notice = None;
        // SAFETY: HDAPI calls on the initialised device; the callback is an
        // `extern "C" fn(*mut c_void) -> c_uint` that ignores its (null) argument.
        let handle = unsafe {
            let cal = (api.check_calibration)();
            if cal == HD_CALIBRATION_NEEDS_UPDATE {
                (api.update_calibration)(HD_CALIBRATION_AUTO);
                notice = Some("device calibration was out of date: updated automatically".into());
            } else if cal != HD_CALIBRATION_OK {
                notice = Some(format!(
                    "device calibration needs manual input (status {cal:#06x}): put the pen in its inkwell"
                ));
            }
            (api.enable)(HD_FORCE_OUTPUT);
            let h =
                (api.schedule_asynchronous)(servo, std::ptr::null_mut(), HD_MAX_SCHEDULER_PRIORITY);
            (api.start_scheduler)();
            h
        };
        // SAFETY: as above.
        let err = unsafe { (api.get_error)() };
        if err.error_code != 0 {
            // SAFETY: tear down what was started, in HDAPI's order.
            unsafe {
                (api.stop_scheduler)();
                (api.unschedule)(handle);
                (api.disable_device)(hhd);
            }
            return Err(open(format!(
                "starting the scheduler failed (error {:#06x})",
                err.error_code
            )));
        }
        Ok((
            Self {
                workspace,
                handle,
                last_frames: 0,
                stale_reads: 0,
            },
            notice,
        ))
    }

    /// Servo frames run so far.
    pub fn frames(&self) -> u64 {
        SHARED.frames.load(Ordering::Acquire)
    }
}

impl HapticDevice for OpenHaptics {
    fn name(&self) -> &str {
        "openhaptics"
    }

    fn read(&mut self, _dt: f32) -> Result<DeviceState, DeviceError> {
        let code = SHARED.error.load(Ordering::Acquire);
        if code != 0 {
            return Err(DeviceError::Device {
                code,
                what: "the device reported an error; forces are off",
            });
        }
        let frames = SHARED.frames.load(Ordering::Acquire);
        if frames == self.last_frames {
            self.stale_reads += 1;
            if self.stale_reads > 20 {
                return Err(DeviceError::Device {
                    code: 0,
                    what: "the servo loop stopped running (no frame for 20 ms)",
                });
            }
        } else {
            self.stale_reads = 0;
        }
        self.last_frames = frames;
        let ws = self.workspace;
        // Each value read once: the servo thread writes them meanwhile, so what is checked
        // must be what is used.
        let read = |a: &[AtomicU64; 3]| -> [f64; 3] {
            std::array::from_fn(|i| f64::from_bits(a[i].load(Ordering::Acquire)))
        };
        let (pos, vel) = (read(&SHARED.pos), read(&SHARED.vel));
        // A position the device cannot reach (a glitching encoder, a broken cable) or not
        // a number becomes no force, not a clamped push. Checked on the device's own
        // millimetres.
        let reachable = (0..3).all(|i| pos[i].abs() <= REACH_MM && vel[i].is_finite());
        if !reachable {
            return Err(DeviceError::Device {
                code: 0,
                what: "the device reported a position outside its workspace (or not a number); forces are off",
            });
        }
        // Device millimetres -> scene metres at the workspace scale, around its centre.
        let position = std::array::from_fn(|i| ws.centre[i] + ws.scale * (pos[i] * 1e-3) as f32);
        let velocity = std::array::from_fn(|i| ws.scale * (vel[i] * 1e-3) as f32);
        Ok(DeviceState {
            position,
            velocity,
            buttons: SHARED.buttons.load(Ordering::Acquire) & 0b11,
        })
    }

    /// The force goes to the device at `DEFAULT_WORKSPACE_SCALE / scale` of itself: a
    /// workspace grown to reach a tall body moves the pen further in the scene for each
    /// device millimetre, which would make every scene spring that much stiffer at the
    /// hand (and past what the Touch renders passively). Scaled back, a spring feels as it
    /// does in the default mapping; forces are only weaker, never stronger.
    fn write_force(&mut self, force: [f32; 3]) -> Result<(), DeviceError> {
        let k = (DEFAULT_WORKSPACE_SCALE / self.workspace.scale).min(1.0);
        for (slot, f) in SHARED.force.iter().zip(force) {
            let f = if f.is_finite() { (f * k) as f64 } else { 0.0 };
            slot.store(f.to_bits(), Ordering::Release);
        }
        Ok(())
    }

    fn set_workspace(&mut self, ws: Workspace) {
        self.workspace = ws;
    }
}

impl PointerTarget for OpenHaptics {}

impl Drop for OpenHaptics {
    #[allow(unsafe_code)]
    fn drop(&mut self) {
        for f in &SHARED.force {
            f.store(0f64.to_bits(), Ordering::Release);
        }
        SHARED.stop.store(true, Ordering::Release);
        if let Some((_, api)) = API.get() {
            let hhd = SHARED.hhd.load(Ordering::Acquire);
            // SAFETY: HDAPI teardown in its documented order on the device we opened.
            unsafe {
                (api.stop_scheduler)();
                (api.unschedule)(self.handle);
                (api.disable_device)(hhd);
            }
        }
    }
}
