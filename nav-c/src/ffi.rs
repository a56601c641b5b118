//! The computer's C functions: its memory's size and alignment, the defaults, configuration,
//! the frame, the frame cost, the optional states and the parameters' paths. Every pointer is
//! checked for NULL and the memory for its alignment before use; the memory carries a marker
//! written only by a successful configuration, so a frame before it is refused.
#![allow(unsafe_code)]

use core::ffi::{c_char, c_void};
use core::mem::MaybeUninit;

use nav_fsw::scheduler::NavigationComputer;

use crate::convert::{
    check_inputs, config_fault, fsw_config_of, navigation_state_of, reported_states_of,
    write_telemetry, InputPorts,
};
use crate::params::{NavConfig, PARAM_PATHS};
use crate::types::*;

/// The marker of configured memory (`"NAVCOMPU"` little-endian).
const CONFIGURED: u64 = u64::from_le_bytes(*b"NAVCOMPU");

/// Bytes that always hold the computer (`nav_computer_size()` or more): a C program's
/// static memory, `static uint64_t memory[NAV_COMPUTER_MAX_BYTES / 8];` (a `uint64_t` array
/// is aligned to `NAV_MAX_ALIGN`). The build fails if the computer outgrows it.
pub const NAV_COMPUTER_MAX_BYTES: usize = 49_152;
/// The largest alignment (bytes) the interface's memory needs.
pub const NAV_MAX_ALIGN: usize = 8;

const _: () = assert!(core::mem::size_of::<ComputerMemory>() <= NAV_COMPUTER_MAX_BYTES);
const _: () = assert!(core::mem::align_of::<ComputerMemory>() <= NAV_MAX_ALIGN);

/// The caller's memory: the marker, then the computer.
#[repr(C)]
pub(crate) struct ComputerMemory {
    marker: u64,
    computer: MaybeUninit<NavigationComputer>,
}

/// Writes `fault` where the caller asked (a NULL `out` asks for nothing) and returns its
/// status.
///
/// # Safety
/// `out` is NULL or valid for a write of a `NavFault`.
pub(crate) unsafe fn report(out: *mut NavFault, fault: NavFault) -> NavStatus {
    // SAFETY: the caller's contract; NULL is checked.
    if let Some(out) = unsafe { out.as_mut() } {
        *out = fault;
    }
    fault.status
}

/// The memory at `memory`, checked non-NULL and aligned; not yet checked configured.
///
/// # Safety
/// `memory` is NULL or valid for reads and writes of `nav_computer_size()` bytes, not used by
/// anything else during the call.
unsafe fn memory_at<'a>(memory: *mut c_void) -> Result<&'a mut ComputerMemory, NavFault> {
    let memory = memory.cast::<ComputerMemory>();
    if memory.is_null() {
        return Err(NavFault::of(NavStatus::NullPointer, NavArgument::Memory));
    }
    if !memory.is_aligned() {
        return Err(NavFault::of(
            NavStatus::MisalignedMemory,
            NavArgument::Memory,
        ));
    }
    // SAFETY: non-NULL and aligned (checked above), valid and unshared (the caller's
    // contract); `ComputerMemory` is a `u64` and a `MaybeUninit`, which any bytes the caller
    // wrote are valid for.
    Ok(unsafe { &mut *memory })
}

/// The configured computer at `memory`.
///
/// # Safety
/// As [`memory_at`].
unsafe fn computer_at<'a>(memory: *mut c_void) -> Result<&'a mut NavigationComputer, NavFault> {
    // SAFETY: the caller's contract.
    let memory = unsafe { memory_at(memory) }?;
    if memory.marker != CONFIGURED {
        return Err(NavFault::of(NavStatus::NotConfigured, NavArgument::Memory));
    }
    // SAFETY: the marker is written only after `init_in_place` initialised the computer, and
    // cleared before anything else writes it.
    Ok(unsafe { memory.computer.assume_init_mut() })
}

/// Bytes of memory the computer needs (`nav_configure`'s `memory_size` at least).
#[no_mangle]
pub extern "C" fn nav_computer_size() -> usize {
    core::mem::size_of::<ComputerMemory>()
}

/// Alignment (bytes) the computer's memory needs.
#[no_mangle]
pub extern "C" fn nav_computer_align() -> usize {
    core::mem::align_of::<ComputerMemory>()
}

/// Fills `config` with every parameter's default (the paper's values and documented
/// choices; docs/reference/flight-parameters.md). A parameter the mission must give (the
/// second head's, when it has one) is 0.
///
/// # Safety
/// `config` is NULL or valid for a write of a `NavConfig`.
#[no_mangle]
pub unsafe extern "C" fn nav_config_defaults(config: *mut NavConfig) -> NavStatus {
    // SAFETY: the caller's contract; NULL is checked.
    let Some(config) = (unsafe { config.as_mut() }) else {
        return NavStatus::NullPointer;
    };
    let site = nav_fsw::nav_core::frames::LaunchSite {
        latitude_rad: 0.0,
        longitude_rad: 0.0,
        height_m: 0.0,
        azimuth_rad: 0.0,
        earth_axis_ecef: nav_fsw::nav_core::frames::ECEF_Z_AXIS,
    };
    let frames = nav_fsw::sensor_frames::SensorFrames::ALIGNED;
    let defaults = nav_fsw::FswConfig::paper_defaults(site, frames);
    *config = crate::convert::c_config_of(&defaults).0;
    NavStatus::Ok
}

/// Builds the computer in `memory` from `config`, the launch's ground constants `ground` and
/// the initial navigation state `initial`; a computer already there is replaced. On a refusal
/// the memory holds no computer (`nav_run_frame` returns `NAV_STATUS_NOT_CONFIGURED`).
///
/// Returns `NAV_STATUS_OK`, `NULL_POINTER` (`fault->argument` names it),
/// `MISALIGNED_MEMORY`, `MEMORY_TOO_SMALL` or `CONFIG_REFUSED` (`fault->field`,
/// `fault->param`, `fault->companion` name what). `fault` may be NULL.
///
/// # Safety
/// `memory` is NULL or valid for reads and writes of `memory_size` bytes, used by nothing
/// else during the call; the other pointers are NULL or valid for their type.
#[no_mangle]
pub unsafe extern "C" fn nav_configure(
    memory: *mut c_void,
    memory_size: usize,
    config: *const NavConfig,
    ground: *const NavGroundConstants,
    initial: *const NavInitialState,
    fault: *mut NavFault,
) -> NavStatus {
    // SAFETY: the caller's contract.
    let outcome = unsafe { configure(memory, memory_size, config, ground, initial) };
    // SAFETY: the caller's contract.
    unsafe { report(fault, outcome.err().unwrap_or(NavFault::OK)) }
}

/// [`nav_configure`] with a `Result`.
///
/// # Safety
/// As [`nav_configure`].
unsafe fn configure(
    memory: *mut c_void,
    memory_size: usize,
    config: *const NavConfig,
    ground: *const NavGroundConstants,
    initial: *const NavInitialState,
) -> Result<(), NavFault> {
    let null = |argument| NavFault::of(NavStatus::NullPointer, argument);
    // SAFETY: the caller's contract; NULL is checked.
    let config = unsafe { config.as_ref() }.ok_or(null(NavArgument::Config))?;
    // SAFETY: as above.
    let ground = unsafe { ground.as_ref() }.ok_or(null(NavArgument::GroundConstants))?;
    // SAFETY: as above.
    let initial = unsafe { initial.as_ref() }.ok_or(null(NavArgument::Initial))?;
    // SAFETY: the caller's contract.
    let memory = unsafe { memory_at(memory) }?;
    if memory_size < nav_computer_size() {
        return Err(NavFault::of(NavStatus::MemoryTooSmall, NavArgument::Memory));
    }
    memory.marker = 0;
    let fsw = fsw_config_of(config, ground)?;
    let state = navigation_state_of(initial);
    NavigationComputer::init_in_place(&mut memory.computer, fsw, state).map_err(config_fault)?;
    memory.marker = CONFIGURED;
    Ok(())
}

/// Runs one minor frame with `inputs` and writes its telemetry to `telemetry`.
///
/// Returns `NAV_STATUS_OK`, `NULL_POINTER`, `MISALIGNED_MEMORY`, `NOT_CONFIGURED` or
/// `BAD_FRAME` (`fault->input` names the field; no frame was run). A sensor's bad values (NaN,
/// a time jump, a non-unit quaternion) are no error: the computer refuses and counts them in
/// the health counters, as in flight. `fault` may be NULL.
///
/// # Safety
/// `memory` is NULL or the memory given to `nav_configure`, used by nothing else during the
/// call; `inputs` and `telemetry` are NULL or valid for their type.
#[no_mangle]
pub unsafe extern "C" fn nav_run_frame(
    memory: *mut c_void,
    inputs: *const NavFrameInputs,
    telemetry: *mut NavTelemetry,
    fault: *mut NavFault,
) -> NavStatus {
    // SAFETY: the caller's contract.
    let outcome = unsafe { run_frame(memory, inputs, telemetry) };
    // SAFETY: the caller's contract.
    unsafe { report(fault, outcome.err().unwrap_or(NavFault::OK)) }
}

/// [`nav_run_frame`] with a `Result`.
///
/// # Safety
/// As [`nav_run_frame`].
unsafe fn run_frame(
    memory: *mut c_void,
    inputs: *const NavFrameInputs,
    telemetry: *mut NavTelemetry,
) -> Result<(), NavFault> {
    let null = |argument| NavFault::of(NavStatus::NullPointer, argument);
    // SAFETY: the caller's contract; NULL is checked.
    let inputs = unsafe { inputs.as_ref() }.ok_or(null(NavArgument::Inputs))?;
    // SAFETY: as above.
    let telemetry = unsafe { telemetry.as_mut() }.ok_or(null(NavArgument::Output))?;
    // SAFETY: the caller's contract.
    let computer = unsafe { computer_at(memory) }?;
    check_inputs(inputs)?;
    let frame = InputPorts::new(inputs).run(computer);
    write_telemetry(&frame, computer, telemetry);
    Ok(())
}

/// Reports the cost of the frame just run (instructions or cycles, the unit of the budget):
/// the telemetry's `last_frame_cost`, `worst_frame_cost` and the `frame_overruns` counter.
///
/// # Safety
/// As `nav_run_frame`'s `memory`.
#[no_mangle]
pub unsafe extern "C" fn nav_report_frame_cost(memory: *mut c_void, cost: u32) -> NavStatus {
    // SAFETY: the caller's contract.
    match unsafe { computer_at(memory) } {
        Ok(computer) => {
            computer.report_frame_cost(cost);
            NavStatus::Ok
        }
        Err(fault) => fault.status,
    }
}

/// Sets the frame budget a reported cost is an overrun beyond.
///
/// # Safety
/// As `nav_run_frame`'s `memory`.
#[no_mangle]
pub unsafe extern "C" fn nav_set_frame_budget(memory: *mut c_void, budget: u32) -> NavStatus {
    // SAFETY: the caller's contract.
    match unsafe { computer_at(memory) } {
        Ok(computer) => {
            computer.set_frame_budget(budget);
            NavStatus::Ok
        }
        Err(fault) => fault.status,
    }
}

/// Clears the sensors' fault declarations (a ground command): their measurements are used
/// again.
///
/// # Safety
/// As `nav_run_frame`'s `memory`.
#[no_mangle]
pub unsafe extern "C" fn nav_clear_sensor_faults(memory: *mut c_void) -> NavStatus {
    // SAFETY: the caller's contract.
    match unsafe { computer_at(memory) } {
        Ok(computer) => match computer.command(nav_fsw::scheduler::Command::ClearSensorFaults) {
            Ok(()) => NavStatus::Ok,
            Err(_) => NavStatus::ConfigRefused,
        },
        Err(fault) => fault.status,
    }
}

/// Writes the star noise in use, the active tracker head and the optional state blocks'
/// estimates and 1σ to `states`: read when reported, not in every frame (the blocks' square
/// roots and the IMU block's covariance would cost every frame its share).
///
/// # Safety
/// As `nav_run_frame`'s `memory`; `states` is NULL or valid for a write of its type.
#[no_mangle]
pub unsafe extern "C" fn nav_reported_states(
    memory: *mut c_void,
    states: *mut NavReportedStates,
) -> NavStatus {
    // SAFETY: the caller's contract; NULL is checked.
    let Some(states) = (unsafe { states.as_mut() }) else {
        return NavStatus::NullPointer;
    };
    // SAFETY: the caller's contract.
    match unsafe { computer_at(memory) } {
        Ok(computer) => {
            *states = reported_states_of(computer);
            NavStatus::Ok
        }
        Err(fault) => fault.status,
    }
}

/// The path of parameter `param` (a `NavParam`) in the flight software's configuration,
/// e.g. `"gnss.noise_m"` (docs/reference/flight-parameters.md); NULL for `NAV_PARAM_NONE` or a
/// number that is no parameter. The string is static.
#[no_mangle]
pub extern "C" fn nav_param_path(param: u32) -> *const c_char {
    let path = usize::try_from(param)
        .ok()
        .and_then(|param| param.checked_sub(1))
        .and_then(|index| PARAM_PATHS.get(index));
    path.map_or(core::ptr::null(), |path| path.as_ptr().cast())
}
