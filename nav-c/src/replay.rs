//! Replay of a `nav-sim` sensor log through the C interface: the replay input's setup (the
//! scenario's configuration, ground constants and initial state as the C structs
//! `nav_configure` takes), its log records placed in frames (nav-fsw's frame assembler) as
//! `NavFrameInputs`, and each frame's output record, the words `nav-sim`'s host replay and the
//! Rust firmware write (docs/guide/replay-format.md), so a C program's replay compares bit for bit.
#![allow(unsafe_code)]

use core::ffi::c_void;
use core::mem::MaybeUninit;

use nav_fsw::log_record::{decode_header, LogRecord, HEADER_SIZE, RECORD_SIZE};
use nav_fsw::replay::{FrameAssembler, FramePorts, ReplaySetup, OUTPUT_WORDS, SETUP_WORDS};

use crate::convert::{c_config_of, config_fault, initial_state_of};
use crate::ffi::report;
use crate::params::NavConfig;
use crate::types::*;

/// Bytes at the start of a replay input: the setup's words, then the log's header. A number
/// (held to nav-fsw's sizes below), so the header defines it.
pub const NAV_REPLAY_START_BYTES: usize = 648;
/// Bytes of one log record.
pub const NAV_LOG_RECORD_BYTES: usize = 80;
/// Words of a frame's output record (`nav_replay_output_record`).
pub const NAV_OUTPUT_WORDS: usize = 133;

const _: () = assert!(NAV_REPLAY_START_BYTES == SETUP_WORDS * 8 + HEADER_SIZE);
const _: () = assert!(NAV_LOG_RECORD_BYTES == RECORD_SIZE);
const _: () = assert!(NAV_OUTPUT_WORDS == OUTPUT_WORDS);

const _: () = assert!(NAV_FRAME_STAR_CAPACITY == nav_fsw::replay::FRAME_STAR_CAPACITY);
const _: () = assert!(NAV_FRAME_GNSS_CAPACITY == nav_fsw::replay::FRAME_GNSS_CAPACITY);

/// The marker of a started replay (`"NAVREPLY"` little-endian).
const STARTED: u64 = u64::from_le_bytes(*b"NAVREPLY");

/// Bytes that always hold a replay (`nav_replay_size()` or more), aligned as a `uint64_t`
/// array is (`NAV_MAX_ALIGN`). The build fails if the replay outgrows it.
pub const NAV_REPLAY_MAX_BYTES: usize = 2_048;

const _: () = assert!(core::mem::size_of::<ReplayMemory>() <= NAV_REPLAY_MAX_BYTES);
const _: () = assert!(core::mem::align_of::<ReplayMemory>() <= crate::ffi::NAV_MAX_ALIGN);

/// The caller's replay memory: the marker, then the frame assembler.
#[repr(C)]
struct ReplayMemory {
    marker: u64,
    assembler: MaybeUninit<FrameAssembler>,
}

/// Bytes of memory a replay needs.
#[no_mangle]
pub extern "C" fn nav_replay_size() -> usize {
    core::mem::size_of::<ReplayMemory>()
}

/// Alignment (bytes) a replay's memory needs.
#[no_mangle]
pub extern "C" fn nav_replay_align() -> usize {
    core::mem::align_of::<ReplayMemory>()
}

/// The replay memory at `memory`, checked non-NULL and aligned.
///
/// # Safety
/// `memory` is NULL or valid for reads and writes of `nav_replay_size()` bytes, used by
/// nothing else during the call.
unsafe fn memory_at<'a>(memory: *mut c_void) -> Result<&'a mut ReplayMemory, NavFault> {
    let memory = memory.cast::<ReplayMemory>();
    if memory.is_null() {
        return Err(NavFault::of(NavStatus::NullPointer, NavArgument::Memory));
    }
    if !memory.is_aligned() {
        return Err(NavFault::of(
            NavStatus::MisalignedMemory,
            NavArgument::Memory,
        ));
    }
    // SAFETY: non-NULL and aligned (checked), valid and unshared (the caller's contract); a
    // `u64` and a `MaybeUninit` are valid for any bytes.
    Ok(unsafe { &mut *memory })
}

/// The started replay's assembler at `memory`.
///
/// # Safety
/// As [`memory_at`].
unsafe fn assembler_at<'a>(memory: *mut c_void) -> Result<&'a mut FrameAssembler, NavFault> {
    // SAFETY: the caller's contract.
    let memory = unsafe { memory_at(memory) }?;
    if memory.marker != STARTED {
        return Err(NavFault::of(NavStatus::NotConfigured, NavArgument::Memory));
    }
    // SAFETY: the marker is written only after the assembler was written.
    Ok(unsafe { memory.assembler.assume_init_mut() })
}

/// The little-endian words of `bytes` (whole words only).
fn words_of<const N: usize>(bytes: &[u8]) -> [u64; N] {
    let mut words = [0_u64; N];
    for (word, chunk) in words.iter_mut().zip(bytes.chunks_exact(8)) {
        let mut le = [0_u8; 8];
        le.copy_from_slice(chunk);
        *word = u64::from_le_bytes(le);
    }
    words
}

/// Starts a replay in `memory` from the first `NAV_REPLAY_START_BYTES` bytes of a replay
/// input (`nav-sim replay`'s `replay-in.bin`: the setup, then the log header) and writes the
/// scenario's configuration, ground constants and initial state, ready for `nav_configure`.
///
/// Returns `NAV_STATUS_OK`, `NULL_POINTER`, `MISALIGNED_MEMORY`, `MEMORY_TOO_SMALL` or
/// `LOG_REFUSED` (the bytes are short, or no setup and header; a setup parameter that is no
/// value of its type is `CONFIG_REFUSED` naming it).
///
/// # Safety
/// `memory` as `nav_configure`'s with `memory_size`; `bytes` is NULL or valid for reads of
/// `length` bytes; the outputs are NULL or valid for their type.
#[no_mangle]
pub unsafe extern "C" fn nav_replay_start(
    memory: *mut c_void,
    memory_size: usize,
    bytes: *const u8,
    length: usize,
    config: *mut NavConfig,
    ground: *mut NavGroundConstants,
    initial: *mut NavInitialState,
    fault: *mut NavFault,
) -> NavStatus {
    // SAFETY: the caller's contract.
    let outcome = unsafe { start(memory, memory_size, bytes, length, config, ground, initial) };
    // SAFETY: the caller's contract.
    unsafe { report(fault, outcome.err().unwrap_or(NavFault::OK)) }
}

/// [`nav_replay_start`] with a `Result`.
///
/// # Safety
/// As [`nav_replay_start`].
unsafe fn start(
    memory: *mut c_void,
    memory_size: usize,
    bytes: *const u8,
    length: usize,
    config: *mut NavConfig,
    ground: *mut NavGroundConstants,
    initial: *mut NavInitialState,
) -> Result<(), NavFault> {
    let null = |argument| NavFault::of(NavStatus::NullPointer, argument);
    // SAFETY: the caller's contract; NULL is checked.
    let config = unsafe { config.as_mut() }.ok_or(null(NavArgument::Output))?;
    // SAFETY: as above.
    let ground = unsafe { ground.as_mut() }.ok_or(null(NavArgument::Output))?;
    // SAFETY: as above.
    let initial = unsafe { initial.as_mut() }.ok_or(null(NavArgument::Output))?;
    // SAFETY: as above (a slice of `length` bytes the caller vouches for).
    let bytes = unsafe { bytes_at(bytes, length) }?;
    // SAFETY: the caller's contract.
    let memory = unsafe { memory_at(memory) }?;
    if memory_size < nav_replay_size() {
        return Err(NavFault::of(NavStatus::MemoryTooSmall, NavArgument::Memory));
    }
    memory.marker = 0;
    let refused = NavFault::of(NavStatus::LogRefused, NavArgument::Bytes);
    let (setup_bytes, rest) = bytes.split_at_checked(SETUP_WORDS * 8).ok_or(refused)?;
    let header: &[u8; HEADER_SIZE] = rest
        .get(..HEADER_SIZE)
        .and_then(|header| header.try_into().ok())
        .ok_or(refused)?;
    decode_header(header).map_err(|_| refused)?;
    let setup =
        ReplaySetup::from_words(&words_of::<SETUP_WORDS>(setup_bytes)).map_err(|error| {
            NavFault {
                argument: NavArgument::Bytes,
                ..config_fault(error)
            }
        })?;
    let assembler = FrameAssembler::new(setup.frame_grid()).map_err(|_| refused)?;
    (*config, *ground) = c_config_of(&setup.config());
    *initial = initial_state_of(&setup.initial);
    memory.assembler.write(assembler);
    memory.marker = STARTED;
    Ok(())
}

/// The `length` bytes at `bytes`.
///
/// # Safety
/// `bytes` is NULL or valid for reads of `length` bytes for `'a`.
unsafe fn bytes_at<'a>(bytes: *const u8, length: usize) -> Result<&'a [u8], NavFault> {
    if bytes.is_null() {
        return Err(NavFault::of(NavStatus::NullPointer, NavArgument::Bytes));
    }
    // SAFETY: non-NULL (checked), valid for `length` bytes (the caller's contract).
    Ok(unsafe { core::slice::from_raw_parts(bytes, length) })
}

/// Takes the log's next record (`NAV_LOG_RECORD_BYTES` bytes at `record`, delivery order).
/// Take every ready frame with `nav_replay_next_frame` before the next record.
///
/// Returns `NAV_STATUS_OK`, `NULL_POINTER`, `MISALIGNED_MEMORY`, `NOT_CONFIGURED` (no replay
/// started) or `LOG_REFUSED` (a record that does not decode, or that the frames refuse: another
/// IMU rate, a time jump beyond the replay's gap); the replay is unchanged then.
///
/// # Safety
/// `memory` as `nav_replay_start`'s; `record` is NULL or valid for reads of
/// `NAV_LOG_RECORD_BYTES` bytes.
#[no_mangle]
pub unsafe extern "C" fn nav_replay_push(
    memory: *mut c_void,
    record: *const u8,
    fault: *mut NavFault,
) -> NavStatus {
    // SAFETY: the caller's contract.
    let outcome = unsafe { push(memory, record) };
    // SAFETY: the caller's contract.
    unsafe { report(fault, outcome.err().unwrap_or(NavFault::OK)) }
}

/// [`nav_replay_push`] with a `Result`.
///
/// # Safety
/// As [`nav_replay_push`].
unsafe fn push(memory: *mut c_void, record: *const u8) -> Result<(), NavFault> {
    // SAFETY: the caller's contract.
    let bytes = unsafe { bytes_at(record, RECORD_SIZE) }?;
    // SAFETY: the caller's contract.
    let assembler = unsafe { assembler_at(memory) }?;
    let refused = NavFault::of(NavStatus::LogRefused, NavArgument::Bytes);
    let (record, _) = LogRecord::decode_prefix(bytes).map_err(|_| refused)?;
    assembler.push(&record).map_err(|_| refused)
}

/// The end of the log: the last frame is complete.
///
/// # Safety
/// `memory` as `nav_replay_start`'s.
#[no_mangle]
pub unsafe extern "C" fn nav_replay_finish(memory: *mut c_void) -> NavStatus {
    // SAFETY: the caller's contract.
    match unsafe { assembler_at(memory) } {
        Ok(assembler) => {
            assembler.finish();
            NavStatus::Ok
        }
        Err(fault) => fault.status,
    }
}

/// Writes the next complete frame's inputs to `inputs` and 1 to `ready`; 0 to `ready` when no
/// frame is complete (push the next record, or finish the log).
///
/// # Safety
/// `memory` as `nav_replay_start`'s; `inputs` and `ready` are NULL or valid for their type.
#[no_mangle]
pub unsafe extern "C" fn nav_replay_next_frame(
    memory: *mut c_void,
    inputs: *mut NavFrameInputs,
    ready: *mut u8,
) -> NavStatus {
    // SAFETY: the caller's contract; NULL is checked.
    let (Some(inputs), Some(ready)) = (unsafe { inputs.as_mut() }, unsafe { ready.as_mut() })
    else {
        return NavStatus::NullPointer;
    };
    // SAFETY: the caller's contract.
    let assembler = match unsafe { assembler_at(memory) } {
        Ok(assembler) => assembler,
        Err(fault) => return fault.status,
    };
    *ready = 0;
    if let Some(frame) = assembler.next_frame() {
        write_inputs(&frame, inputs);
        *ready = 1;
    }
    NavStatus::Ok
}

/// The C inputs of a frame's ports.
fn write_inputs(frame: &FramePorts, inputs: &mut NavFrameInputs) {
    *inputs = NavFrameInputs::default();
    if let Some(sample) = frame.imu.0 {
        inputs.imu_present = 1;
        inputs.imu = NavImuSample {
            sequence: sample.sequence,
            time_s: sample.time_s,
            delta_angle_body_rad: sample.delta_angle_rad,
            delta_velocity_body_mps: sample.delta_velocity_mps,
        };
    }
    for (slot, star) in inputs.stars.iter_mut().zip(frame.star.0.iter()) {
        *slot = NavStarMeasurement {
            time_tag_s: star.time_tag_s,
            sensor_to_gcrf_wxyz: star.sensor_to_gcrf_wxyz,
            head: star.head,
        };
        inputs.star_count += 1;
    }
    for (slot, fix) in inputs.gnss.iter_mut().zip(frame.gnss.0.iter()) {
        *slot = NavGnssFix {
            gps_week: fix.gps_week,
            gps_seconds_of_week: fix.gps_seconds_of_week,
            position_ecef_m: fix.position_ecef_m,
            velocity_present: u8::from(fix.velocity_ecef_mps.is_some()),
            velocity_ecef_mps: fix.velocity_ecef_mps.unwrap_or_default(),
        };
        inputs.gnss_count += 1;
    }
}

/// Writes the frame's output record (`NAV_OUTPUT_WORDS` words, the order of nav-fsw's
/// `OUTPUT_FIELD_NAMES`; a double by its bits) of `telemetry`, the optional `states` and the
/// replay's counts to `words`.
///
/// # Safety
/// `memory` as `nav_replay_start`'s; `telemetry` and `states` are NULL or valid for their
/// type; `words` is NULL or valid for writes of `NAV_OUTPUT_WORDS` words.
#[no_mangle]
pub unsafe extern "C" fn nav_replay_output_record(
    memory: *mut c_void,
    telemetry: *const NavTelemetry,
    states: *const NavReportedStates,
    words: *mut u64,
) -> NavStatus {
    // SAFETY: the caller's contract; NULL is checked.
    let (Some(telemetry), Some(states)) =
        (unsafe { telemetry.as_ref() }, unsafe { states.as_ref() })
    else {
        return NavStatus::NullPointer;
    };
    // SAFETY: as above.
    let Some(words) = (unsafe { words.cast::<[u64; OUTPUT_WORDS]>().as_mut() }) else {
        return NavStatus::NullPointer;
    };
    // SAFETY: the caller's contract.
    let assembler = match unsafe { assembler_at(memory) } {
        Ok(assembler) => assembler,
        Err(fault) => return fault.status,
    };
    *words = crate::output::output_words(telemetry, states, &assembler.counts());
    NavStatus::Ok
}
