//! The plain C structs and enums of the interface: what the caller passes in (ground
//! constants, initial navigation, a frame's sensor inputs) and what it gets back (the frame
//! telemetry, the optional states, the return code and the fault that names the parameter or
//! input). The caller fills inputs with integers and doubles only (a flag is a `uint8_t` 0 or
//! 1), so no value a C program writes is invalid for Rust; enums only travel out.

/// Most star measurements one frame carries (nav-fsw's star queue).
pub const NAV_FRAME_STAR_CAPACITY: usize = 8;
/// Most GNSS fixes one frame carries (nav-fsw's GNSS queue).
pub const NAV_FRAME_GNSS_CAPACITY: usize = 4;

/// The return code of every function of the interface (0 is success).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavStatus {
    /// Done.
    Ok = 0,
    /// A pointer argument is NULL (`fault->argument` names it).
    NullPointer = 1,
    /// The memory is not aligned to `nav_computer_align()` (or `nav_replay_align()`).
    MisalignedMemory = 2,
    /// The memory is smaller than `nav_computer_size()` (or `nav_replay_size()`).
    MemoryTooSmall = 3,
    /// The configuration, the ground constants or the initial navigation state is refused
    /// (`fault->field`, `fault->param` and `fault->companion` name what);
    /// the memory then holds no computer.
    ConfigRefused = 4,
    /// A frame before a successful `nav_configure` (or after a refused one).
    NotConfigured = 5,
    /// A frame's inputs are malformed (`fault->input` names the field): a flag neither 0
    /// nor 1, a count beyond its capacity. The computer is unchanged (no frame was run).
    BadFrame = 6,
    /// The replay's setup, log header or a log record is refused (replay functions only).
    LogRefused = 7,
}

/// The argument of a call a fault concerns.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavArgument {
    /// None (success, or a fault about a value rather than an argument).
    None = 0,
    /// The computer's (or the replay's) memory.
    Memory = 1,
    /// The configuration (`NavConfig`).
    Config = 2,
    /// The ground constants (`NavGroundConstants`).
    GroundConstants = 3,
    /// The initial navigation state (`NavInitialState`).
    Initial = 4,
    /// The frame's inputs (`NavFrameInputs`).
    Inputs = 5,
    /// The telemetry or another output.
    Output = 6,
    /// The replay's input bytes (setup, log header or record).
    Bytes = 7,
}

/// What a refused configuration got wrong (nav-fsw's `ConfigField`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavConfigField {
    /// No configuration fault.
    None = 0,
    /// `fault->param` is outside its range, or no value of its type (a count that is no
    /// integer, a flag neither 0 nor 1, a choice index beyond its choices).
    Parameter = 1,
    /// `fault->companion` is on and `fault->param`, which must go with it, is 0.
    Companion = 2,
    /// The launch site's Earth axis is not a unit vector within 1e-4 rad of ECEF z.
    LaunchSite = 3,
    /// The GCRF → launch-inertial rotation is not unit, or the epoch's seconds of week reach
    /// the next week.
    SensorFrames = 4,
    /// `star.mounting_wxyz` is not a unit quaternion.
    StarMounting = 5,
    /// `star.second_head.mounting_wxyz` is not a unit quaternion.
    StarSecondHead = 6,
    /// `timing.max_latency_s` reaches beyond the navigation history at `imu.period_s`.
    MaxLatency = 7,
    /// `timing.future_tolerance_s` is not below `imu.period_s`.
    FutureTolerance = 8,
    /// `gravity.field.order` is above `gravity.field.degree`.
    Gravity = 9,
    /// `calibration.motion_observability` names a navigation block.
    CalibrationObservabilityTable = 10,
    /// The initial navigation state is not finite, its attitude not unit, or its time beyond
    /// 1e9 s.
    InitialNavigation = 11,
    /// A rule of a later nav-fsw this interface does not name yet.
    Other = 12,
}

/// The field of a frame's inputs a `NAV_STATUS_BAD_FRAME` concerns.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavFrameInput {
    /// None.
    None = 0,
    /// `imu_present` is neither 0 nor 1.
    ImuPresent = 1,
    /// `star_count` is above `NAV_FRAME_STAR_CAPACITY`.
    StarCount = 2,
    /// `gnss_count` is above `NAV_FRAME_GNSS_CAPACITY`.
    GnssCount = 3,
    /// A fix's `velocity_present` is neither 0 nor 1 (`fault->index` names the fix).
    GnssVelocityPresent = 4,
}

/// What went wrong, filled by every call that takes a `NavFault *` (which may be NULL): the
/// return code again, the argument, and for a refused configuration the rule and the
/// parameters (`nav_param_path` gives a parameter's path); everything else `NONE` / 0. On
/// success it is all `NONE` / 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NavFault {
    /// The return code.
    pub status: NavStatus,
    /// The argument concerned.
    pub argument: NavArgument,
    /// The configuration rule broken (`NAV_STATUS_CONFIG_REFUSED`).
    pub field: NavConfigField,
    /// The parameter refused (`NAV_CONFIG_FIELD_PARAMETER`), the one that is off
    /// (`NAV_CONFIG_FIELD_COMPANION`), as a `NavParam`; `NAV_PARAM_NONE` (0) otherwise.
    pub param: u32,
    /// The parameter that is on (`NAV_CONFIG_FIELD_COMPANION`), as a `NavParam`;
    /// `NAV_PARAM_NONE` (0) otherwise.
    pub companion: u32,
    /// The frame input malformed (`NAV_STATUS_BAD_FRAME`).
    pub input: NavFrameInput,
    /// The index of the malformed element (`NAV_FRAME_INPUT_GNSS_VELOCITY_PRESENT`: the fix);
    /// 0 otherwise.
    pub index: u32,
}

impl NavFault {
    /// The fault of `status` about `argument`, nothing else named.
    pub(crate) const fn of(status: NavStatus, argument: NavArgument) -> Self {
        Self {
            status,
            argument,
            field: NavConfigField::None,
            param: 0,
            companion: 0,
            input: NavFrameInput::None,
            index: 0,
        }
    }

    /// Success.
    pub(crate) const OK: Self = Self::of(NavStatus::Ok, NavArgument::None);
}

/// The launch's ground constants, computed on the ground for the launch
/// (`nav-sim ground-constants`): the launch site and the sensors' frames and time scale.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavGroundConstants {
    /// `launch_site.latitude_rad`: geodetic latitude (rad).
    pub latitude_rad: f64,
    /// `launch_site.longitude_rad` (rad).
    pub longitude_rad: f64,
    /// `launch_site.height_m`: above the ellipsoid (m).
    pub height_m: f64,
    /// `launch_site.azimuth_rad`: launch azimuth (rad).
    pub azimuth_rad: f64,
    /// `launch_site.earth_axis_ecef`: the Earth's rotation axis of the launch day, ECEF (unit).
    pub earth_axis_ecef: [f64; 3],
    /// `sensor_frames.gcrf_to_launch_inertial_wxyz`: GCRF → launch-inertial at the launch
    /// epoch (unit quaternion, scalar first).
    pub gcrf_to_launch_inertial_wxyz: [f64; 4],
    /// `sensor_frames.launch_epoch_gps_week`: GPS week of the launch epoch (full count).
    pub launch_epoch_gps_week: u32,
    /// `sensor_frames.launch_epoch_gps_seconds_of_week`: GPS seconds of week of the launch
    /// epoch (s).
    pub launch_epoch_gps_seconds_of_week: f64,
}

/// The navigation solution the computer starts from (launch-inertial frame).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavInitialState {
    /// Body → launch-inertial attitude (unit quaternion, scalar first).
    pub attitude_wxyz: [f64; 4],
    /// Position, launch-inertial (m).
    pub position_m: [f64; 3],
    /// Velocity, launch-inertial (m/s).
    pub velocity_mps: [f64; 3],
    /// Navigation time, since the launch epoch (s).
    pub time_s: f64,
}

/// One IMU sample: the increments over one IMU period, body frame.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavImuSample {
    /// The IMU's sample counter (a repeat is a duplicate, a gap a missing sample).
    pub sequence: u32,
    /// Navigation time at the end of the sample (s).
    pub time_s: f64,
    /// Angle increment, body frame (rad).
    pub delta_angle_body_rad: [f64; 3],
    /// Velocity increment (specific force integrated), body frame (m/s).
    pub delta_velocity_body_mps: [f64; 3],
}

/// One star-tracker measurement: the sensor's attitude relative to GCRF.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavStarMeasurement {
    /// Navigation time of validity (s).
    pub time_tag_s: f64,
    /// Sensor → GCRF attitude (unit quaternion, scalar first).
    pub sensor_to_gcrf_wxyz: [f64; 4],
    /// The tracker head (0 or, with `star.second_head`, 1).
    pub head: u8,
}

/// One GNSS fix: the antenna's position (and velocity) in ECEF, tagged in GPS time.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavGnssFix {
    /// GPS week (full count).
    pub gps_week: u32,
    /// GPS seconds of week (s).
    pub gps_seconds_of_week: f64,
    /// Antenna position, ECEF (m).
    pub position_ecef_m: [f64; 3],
    /// 1 when the fix carries a velocity, 0 when not.
    pub velocity_present: u8,
    /// Antenna velocity, ECEF (m/s); read only when `velocity_present` is 1.
    pub velocity_ecef_mps: [f64; 3],
}

/// What one 2 ms frame delivers: the IMU sample of the frame (if any) and the measurements
/// that arrived since the last frame, in arrival order.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavFrameInputs {
    /// 1 when the frame has an IMU sample, 0 when the IMU delivered none (the computer holds
    /// the last one and counts it).
    pub imu_present: u8,
    /// The IMU sample (read only when `imu_present` is 1).
    pub imu: NavImuSample,
    /// Star measurements in `stars` (0 to `NAV_FRAME_STAR_CAPACITY`).
    pub star_count: u32,
    /// The star measurements, the first `star_count` read.
    pub stars: [NavStarMeasurement; NAV_FRAME_STAR_CAPACITY],
    /// GNSS fixes in `gnss` (0 to `NAV_FRAME_GNSS_CAPACITY`).
    pub gnss_count: u32,
    /// The GNSS fixes, the first `gnss_count` read.
    pub gnss: [NavGnssFix; NAV_FRAME_GNSS_CAPACITY],
}

/// What the frame's measurement fusion did (`NavTelemetry::fusion`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NavFusion {
    /// No measurement was fused.
    #[default]
    None = 0,
    /// A star update was accepted.
    StarAccepted = 1,
    /// A star measurement was rejected (gate, jump or fault).
    StarRejected = 2,
    /// A GNSS position update was accepted.
    GnssAccepted = 3,
    /// A GNSS fix was rejected.
    GnssRejected = 4,
    /// A GNSS velocity update was accepted.
    GnssVelocityAccepted = 5,
    /// A GNSS velocity was rejected.
    GnssVelocityRejected = 6,
}

/// One calibration block: its estimate and 1σ per axis.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavCalibrationEntry {
    /// Estimate per axis (units of the block).
    pub value: [f64; 3],
    /// Filter 1σ per axis (units of the block).
    pub sigma: [f64; 3],
}

/// The calibration table: the five calibrated blocks.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavCalibration {
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: NavCalibrationEntry,
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: NavCalibrationEntry,
    /// Star-sensor installation error (rad, rotation vector).
    pub star_installation_rad: NavCalibrationEntry,
    /// Gyro scale factor (relative).
    pub gyro_scale_factor: NavCalibrationEntry,
    /// Accelerometer scale factor (relative).
    pub accel_scale_factor: NavCalibrationEntry,
}

/// What is read when it is reported (`nav_reported_states`), not in every frame: the star
/// noise in use, the active tracker head and the optional state blocks (each block's bit in
/// `blocks`, NaN in the fields of a block not flown).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavReportedStates {
    /// The star noise the next update uses, 1σ about sensor x, y, z (rad).
    pub star_noise_rad: [f64; 3],
    /// The star tracker head the filter fuses (0 or 1).
    pub active_star_head: u8,
    /// Bit 0 (1): the correlated GNSS error states; bit 1 (2): the systematic IMU errors.
    pub blocks: u32,
    /// Correlated GNSS position error, launch-inertial (m).
    pub gnss_error_m: [f64; 3],
    /// Its 1σ (m).
    pub gnss_error_sigma_m: [f64; 3],
    /// Gyro non-orthogonality `yx, zx, zy` (rad).
    pub gyro_non_orthogonality_rad: [f64; 3],
    /// Its 1σ (rad).
    pub gyro_non_orthogonality_sigma_rad: [f64; 3],
    /// Accelerometer misalignment `xy, xz, yx, yz, zx, zy` (rad).
    pub accel_misalignment_rad: [f64; 6],
    /// Its 1σ (rad).
    pub accel_misalignment_sigma_rad: [f64; 6],
    /// Gyro g-sensitivity per axis (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: [f64; 3],
    /// Its 1σ (rad/s per m/s²).
    pub gyro_g_sensitivity_sigma_rad_s_per_mps2: [f64; 3],
}

/// The health counters (nav-fsw's `HealthCounters`, field for field): every detected fault and
/// every protective action, counted saturating.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NavHealth {
    /// IMU samples with NaN/Inf fields.
    pub imu_non_finite: u32,
    /// IMU samples beyond the saturation limits.
    pub imu_saturated: u32,
    /// Repeated IMU samples (same sequence number) and late, out-of-order ones.
    pub imu_duplicate: u32,
    /// IMU samples missing (sequence gaps and frames with no sample).
    pub imu_missing: u32,
    /// IMU time-tag jumps (zero, negative or wrong step).
    pub imu_time_jump: u32,
    /// Star measurements rejected as non-finite.
    pub star_non_finite: u32,
    /// Star quaternions rejected as not unit (zero included).
    pub star_not_unit: u32,
    /// Sign changes of the star quaternion between consecutive samples (q and −q are one
    /// attitude: undone, and harmless; a sensor that keeps w ≥ 0 changes sign twice per turn).
    pub star_sign_flip: u32,
    /// GNSS fixes rejected as non-finite.
    pub gnss_non_finite: u32,
    /// GNSS fixes rejected as jumps.
    pub gnss_jump: u32,
    /// Measurements older than the allowed latency, or older than the last fused one.
    pub measurement_stale: u32,
    /// Measurements time-tagged in the future.
    pub measurement_future: u32,
    /// Measurements dropped because their buffer was full.
    pub measurement_overflow: u32,
    /// Star updates rejected by the innovation gate.
    pub star_gate_rejections: u32,
    /// GNSS updates rejected by the innovation gate.
    pub gnss_gate_rejections: u32,
    /// GNSS velocity updates rejected by the innovation gate.
    pub gnss_velocity_gate_rejections: u32,
    /// Frames whose IMU sample was held (missing or refused), each adding the held sample's
    /// uncertainty to the covariance.
    pub imu_held_frames: u32,
    /// Covariance repairs (variance clamped to its floor or ceiling).
    pub covariance_clamps: u32,
    /// Filter resets after a non-finite state or covariance.
    pub filter_resets: u32,
    /// Frames whose work exceeded the frame budget.
    pub frame_overruns: u32,
    /// Times the star sensor was declared faulty (consecutive rejections).
    pub star_declared_faulty: u32,
    /// Times the GNSS receiver was declared faulty (consecutive rejections).
    pub gnss_declared_faulty: u32,
    /// Measurements discarded because their sensor is declared faulty.
    pub ignored_from_faulty_sensor: u32,
    /// Star-sensor outages: no measurement received for longer than
    /// `timing.outage_timeout_s` (counted once per outage, when the timeout elapses).
    pub star_outages: u32,
    /// GNSS outages, as `star_outages`.
    pub gnss_outages: u32,
    /// Filter operations refused by nav-core (measurement model or update errors).
    pub filter_errors: u32,
    /// Strapdown steps refused (the navigation state was held).
    pub strapdown_failures: u32,
    /// Episodes of serially correlated GNSS position innovations (`WhitenessMonitor`): the
    /// receiver's errors are correlated beyond what the filter models, so its covariance is
    /// no longer to be trusted.
    pub gnss_innovations_correlated: u32,
    /// Episodes of star innovations inconsistent with their covariance
    /// (`crate::consistency::ConsistencyMonitor`): counted when the aid starts failing
    /// the test.
    pub star_inconsistent: u32,
    /// Episodes of inconsistent GNSS position innovations, as
    /// `star_inconsistent`.
    pub gnss_inconsistent: u32,
    /// Episodes of inconsistent GNSS velocity innovations, as
    /// `star_inconsistent`.
    pub gnss_velocity_inconsistent: u32,
    /// Runs of `timing.rejections_to_declare_faulty` gate rejections blamed on the inertial
    /// solution, not on the aiding sensor: its innovations were already inconsistent when
    /// the run began, or the other sensor's are now. The sensor is kept, and the uncertainty
    /// of the states it observes is widened (`scheduler::aid`).
    pub inertial_suspect: u32,
    /// Episodes of a gravity model too coarse for its allowance: the RMS magnitude of the
    /// field it omits, at the vehicle's radius, above `√3 gravity.omitted_field_sigma_mps2`
    /// (`scheduler::gravity`). The filter's covariance does not cover that field.
    pub gravity_allowance_short: u32,
    /// Evaluations of the field beyond `J2` refused (non-finite position or result); the
    /// last value is held.
    pub gravity_field_errors: u32,
    /// Times the star noise began to follow the innovations (`star.noise_matching`,
    /// `crate::noise_matching`): the star innovations failed the consistency test, and the
    /// update weights the tracker by the noise they show until the filter is re-initialised.
    pub star_noise_matched: u32,
    /// Pairs of the two tracker heads' measurements rejected by the pair gate
    /// (`star.second_head.pair_gate_nis`; `scheduler::heads`).
    pub star_pair_rejections: u32,
    /// Times the pairs' residuals began to fail the consistency test: the heads' relative
    /// alignment moves (a slowly varying error, an uncorrected aberration) or their noise is
    /// larger than configured.
    pub star_heads_inconsistent: u32,
    /// Times the filter's installation block was handed over to the other tracker head.
    pub star_head_handovers: u32,
    /// Star measurements of a head the configuration does not have (ignored).
    pub star_unknown_head: u32,
    /// Times the star innovations began to follow the velocity aberration the tracker leaves
    /// in while the flight software is not told to correct it (nav-fsw `aberration_monitor`).
    pub star_aberration_suspected: u32,
}

/// The command counters (nav-fsw's `CommandCounters`, field for field).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NavCommandCounters {
    /// Commands executed.
    pub accepted: u32,
    /// Commands refused.
    pub refused: u32,
    /// Measurements discarded because their sensor is disabled by command.
    pub measurements_of_disabled_aid: u32,
    /// Calibration records loaded.
    pub calibration_records_loaded: u32,
    /// Calibration records refused.
    pub calibration_records_refused: u32,
}

/// One frame's telemetry: the navigation solution, the measurement fusion, the sensors'
/// states, the calibration table with its 1σ and the health counters (`nav_reported_states`
/// adds what is read only when reported).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavTelemetry {
    /// Minor-frame counter (wraps).
    pub frame: u32,
    /// Navigation time at the end of the frame (s).
    pub time_s: f64,
    /// Body → launch-inertial attitude (unit quaternion, scalar first).
    pub attitude_wxyz: [f64; 4],
    /// Position, launch-inertial (m).
    pub position_m: [f64; 3],
    /// Velocity, launch-inertial (m/s).
    pub velocity_mps: [f64; 3],
    /// What the frame's measurement fusion did.
    pub fusion: NavFusion,
    /// NIS of the last star measurement tested.
    pub last_star_nis: f64,
    /// NIS of the last GNSS fix tested.
    pub last_gnss_nis: f64,
    /// NIS of the last GNSS velocity tested.
    pub last_gnss_velocity_nis: f64,
    /// 1 when the star sensor is declared faulty.
    pub star_faulty: u8,
    /// 1 when the GNSS receiver is declared faulty.
    pub gnss_faulty: u8,
    /// 1 when the star consistency monitor's last window failed.
    pub star_inconsistent: u8,
    /// 1 when the GNSS position consistency monitor's last window failed.
    pub gnss_inconsistent: u8,
    /// 1 when the GNSS velocity consistency monitor's last window failed.
    pub gnss_velocity_inconsistent: u8,
    /// Calibration blocks converged so far.
    pub converged_blocks: u32,
    /// Blocks frozen now (nav-core's `BlockMask` bits).
    pub frozen_blocks: u32,
    /// The calibration table: estimates and 1σ.
    pub calibration: NavCalibration,
    /// Fault and action counters.
    pub health: NavHealth,
    /// Cost of the previous frame as reported with `nav_report_frame_cost`.
    pub last_frame_cost: u32,
    /// Worst reported frame cost so far.
    pub worst_frame_cost: u32,
    /// Commands executed and refused (`nav_clear_sensor_faults` is one).
    pub commands: NavCommandCounters,
}
