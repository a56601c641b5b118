//! Between the C structs and nav-fsw's types: the configuration through the parameter table
//! (every value set by its parameter, so a refusal names it), the frame's inputs as the
//! computer's ports (read in place, nothing copied), and the telemetry written field by field.

use nav_fsw::config::{FswConfig, Param};
use nav_fsw::error::ConfigField;
use nav_fsw::nalgebra::{Quaternion, Vector3};
use nav_fsw::nav_core::strapdown::NavigationState;
use nav_fsw::scheduler::NavigationComputer;
use nav_fsw::telemetry::{FrameFusion, FrameTelemetry};
use nav_fsw::{FswError, GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};

use crate::params::{NavConfig, CONFIG_PARAMS, NAV_CONFIG_PARAMS};
use crate::types::*;

/// The ground constants' parameters with their values in `ground`, in table order.
fn ground_values(ground: &NavGroundConstants) -> [(Param, f64); 13] {
    let g = ground;
    let [ax, ay, az] = g.earth_axis_ecef;
    let [qw, qx, qy, qz] = g.gcrf_to_launch_inertial_wxyz;
    [
        (
            Param::LaunchEpochGpsWeek,
            f64::from(g.launch_epoch_gps_week),
        ),
        (Param::LaunchLatitude, g.latitude_rad),
        (Param::LaunchLongitude, g.longitude_rad),
        (Param::LaunchHeight, g.height_m),
        (Param::LaunchAzimuth, g.azimuth_rad),
        (Param::EarthAxisX, ax),
        (Param::EarthAxisY, ay),
        (Param::EarthAxisZ, az),
        (Param::GcrfW, qw),
        (Param::GcrfX, qx),
        (Param::GcrfY, qy),
        (Param::GcrfZ, qz),
        (
            Param::LaunchEpochSecondsOfWeek,
            g.launch_epoch_gps_seconds_of_week,
        ),
    ]
}

/// The parameter's identifier for C (`NavParam`: its position in the table, from 1).
pub fn param_id(param: Param) -> u32 {
    let position = Param::ALL.iter().position(|p| *p == param);
    position
        .and_then(|index| u32::try_from(index).ok())
        .map_or(0, |index| index.saturating_add(1))
}

/// Whether the parameter is one of the ground constants' (`NavGroundConstants`).
fn is_ground_constant(param: Param) -> bool {
    let path = param.path();
    path.starts_with("launch_site.") || path.starts_with("sensor_frames.")
}

/// The argument that holds what a configuration fault names.
fn argument_of(field: ConfigField) -> NavArgument {
    match field {
        ConfigField::Parameter(param) | ConfigField::Companion(_, param)
            if is_ground_constant(param) =>
        {
            NavArgument::GroundConstants
        }
        ConfigField::LaunchSite | ConfigField::SensorFrames => NavArgument::GroundConstants,
        ConfigField::InitialNavigation => NavArgument::Initial,
        _ => NavArgument::Config,
    }
}

/// The fault of a refused configuration, naming the argument that holds what it names.
pub fn config_fault(error: FswError) -> NavFault {
    let mut fault = NavFault::of(NavStatus::ConfigRefused, NavArgument::Config);
    let FswError::InvalidConfiguration(field) = error else {
        fault.field = NavConfigField::Other;
        return fault;
    };
    fault.argument = argument_of(field);
    fault.field = match field {
        ConfigField::Parameter(param) => {
            fault.param = param_id(param);
            NavConfigField::Parameter
        }
        ConfigField::Companion(on, off) => {
            fault.param = param_id(off);
            fault.companion = param_id(on);
            NavConfigField::Companion
        }
        ConfigField::LaunchSite => NavConfigField::LaunchSite,
        ConfigField::SensorFrames => NavConfigField::SensorFrames,
        ConfigField::StarMounting => NavConfigField::StarMounting,
        ConfigField::StarSecondHead => NavConfigField::StarSecondHead,
        ConfigField::MaxLatency => NavConfigField::MaxLatency,
        ConfigField::FutureTolerance => NavConfigField::FutureTolerance,
        ConfigField::Gravity => NavConfigField::Gravity,
        ConfigField::CalibrationObservabilityTable => NavConfigField::CalibrationObservabilityTable,
        ConfigField::InitialNavigation => NavConfigField::InitialNavigation,
        _ => NavConfigField::Other,
    };
    fault
}

/// The flight software's configuration of `config` and `ground`: the defaults
/// ([`FswConfig::paper_defaults`]) with every parameter of the table set from them, in table
/// order (the second head's flag before its values).
///
/// # Errors
/// A `NavFault` (`NAV_STATUS_CONFIG_REFUSED`, `NAV_CONFIG_FIELD_PARAMETER`) naming the first
/// parameter whose number is no value of its type (a count that is no integer, a flag neither
/// 0 nor 1). The ranges and the rules between parameters are checked when the computer is
/// built.
pub fn fsw_config_of(
    config: &NavConfig,
    ground: &NavGroundConstants,
) -> Result<FswConfig, NavFault> {
    let frames = nav_fsw::sensor_frames::SensorFrames::ALIGNED;
    let site = nav_fsw::nav_core::frames::LaunchSite {
        latitude_rad: 0.0,
        longitude_rad: 0.0,
        height_m: 0.0,
        azimuth_rad: 0.0,
        earth_axis_ecef: nav_fsw::nav_core::frames::ECEF_Z_AXIS,
    };
    let mut fsw = FswConfig::paper_defaults(site, frames);
    for (param, value) in ground_values(ground) {
        param.set_number(&mut fsw, value).map_err(config_fault)?;
    }
    for (param, value) in CONFIG_PARAMS.iter().zip(config.values()) {
        param.set_number(&mut fsw, value).map_err(config_fault)?;
    }
    Ok(fsw)
}

/// The C structs of `config`: its parameters' numbers.
pub fn c_config_of(config: &FswConfig) -> (NavConfig, NavGroundConstants) {
    let mut values = [0.0; NAV_CONFIG_PARAMS];
    for (value, param) in values.iter_mut().zip(CONFIG_PARAMS) {
        *value = param.value(config);
    }
    let site = &config.launch_site;
    let frames = &config.sensor_frames;
    let ground = NavGroundConstants {
        latitude_rad: site.latitude_rad,
        longitude_rad: site.longitude_rad,
        height_m: site.height_m,
        azimuth_rad: site.azimuth_rad,
        earth_axis_ecef: site.earth_axis_ecef,
        gcrf_to_launch_inertial_wxyz: frames.gcrf_to_launch_inertial_wxyz,
        launch_epoch_gps_week: frames.launch_epoch_gps_week,
        launch_epoch_gps_seconds_of_week: frames.launch_epoch_gps_seconds_of_week,
    };
    (NavConfig::from_values(&values), ground)
}

/// The navigation state of `initial`.
pub fn navigation_state_of(initial: &NavInitialState) -> NavigationState {
    let [w, x, y, z] = initial.attitude_wxyz;
    let [px, py, pz] = initial.position_m;
    let [vx, vy, vz] = initial.velocity_mps;
    NavigationState {
        attitude: Quaternion::new(w, x, y, z),
        position_m: Vector3::new(px, py, pz),
        velocity_mps: Vector3::new(vx, vy, vz),
        time_s: initial.time_s,
    }
}

/// The C struct of `state`.
pub fn initial_state_of(state: &NavigationState) -> NavInitialState {
    let (q, p, v) = (&state.attitude, &state.position_m, &state.velocity_mps);
    NavInitialState {
        attitude_wxyz: [q.w, q.i, q.j, q.k],
        position_m: [p.x, p.y, p.z],
        velocity_mps: [v.x, v.y, v.z],
        time_s: state.time_s,
    }
}

/// Whether the flag is 0 or 1.
fn is_flag(flag: u8) -> bool {
    flag <= 1
}

/// Checks a frame's inputs are well formed: every flag 0 or 1, every count within its
/// capacity.
///
/// # Errors
/// A `NavFault` (`NAV_STATUS_BAD_FRAME`) naming the input.
pub fn check_inputs(inputs: &NavFrameInputs) -> Result<(), NavFault> {
    let bad = |input: NavFrameInput, index: u32| NavFault {
        input,
        index,
        ..NavFault::of(NavStatus::BadFrame, NavArgument::Inputs)
    };
    if !is_flag(inputs.imu_present) {
        return Err(bad(NavFrameInput::ImuPresent, 0));
    }
    if usize::try_from(inputs.star_count).map_or(true, |n| n > NAV_FRAME_STAR_CAPACITY) {
        return Err(bad(NavFrameInput::StarCount, 0));
    }
    let gnss = gnss_of(inputs).ok_or(bad(NavFrameInput::GnssCount, 0))?;
    for (index, fix) in (0_u32..).zip(gnss) {
        if !is_flag(fix.velocity_present) {
            return Err(bad(NavFrameInput::GnssVelocityPresent, index));
        }
    }
    Ok(())
}

/// The frame's GNSS fixes; `None` for a count beyond the capacity.
fn gnss_of(inputs: &NavFrameInputs) -> Option<&[NavGnssFix]> {
    let count = usize::try_from(inputs.gnss_count).ok()?;
    inputs.gnss.get(..count)
}

/// The frame's star measurements; `None` for a count beyond the capacity.
fn stars_of(inputs: &NavFrameInputs) -> Option<&[NavStarMeasurement]> {
    let count = usize::try_from(inputs.star_count).ok()?;
    inputs.stars.get(..count)
}

/// The frame's inputs as the computer's three ports, read in place.
pub struct InputPorts<'a> {
    imu: Option<&'a NavImuSample>,
    stars: core::slice::Iter<'a, NavStarMeasurement>,
    gnss: core::slice::Iter<'a, NavGnssFix>,
}

impl<'a> InputPorts<'a> {
    /// The ports of checked inputs ([`check_inputs`]).
    pub fn new(inputs: &'a NavFrameInputs) -> Self {
        Self {
            imu: (inputs.imu_present == 1).then_some(&inputs.imu),
            stars: stars_of(inputs).unwrap_or(&[]).iter(),
            gnss: gnss_of(inputs).unwrap_or(&[]).iter(),
        }
    }

    /// Runs the frame on `computer`.
    pub fn run(&mut self, computer: &mut NavigationComputer) -> FrameTelemetry {
        let mut imu = ImuInput(self.imu.take());
        let mut stars = StarInput(&mut self.stars);
        let mut gnss = GnssInput(&mut self.gnss);
        computer.run_frame(&mut imu, &mut stars, &mut gnss)
    }
}

/// The IMU port of a frame's inputs.
struct ImuInput<'a>(Option<&'a NavImuSample>);

impl ImuPort for ImuInput<'_> {
    fn read(&mut self) -> Option<ImuSample> {
        self.0.take().map(|s| {
            ImuSample::new(
                s.sequence,
                s.time_s,
                s.delta_angle_body_rad,
                s.delta_velocity_body_mps,
            )
        })
    }
}

/// The star port of a frame's inputs.
struct StarInput<'a, 'b>(&'b mut core::slice::Iter<'a, NavStarMeasurement>);

impl StarSensorPort for StarInput<'_, '_> {
    fn poll(&mut self) -> Option<StarMeasurement> {
        self.0
            .next()
            .map(|s| StarMeasurement::new(s.time_tag_s, s.sensor_to_gcrf_wxyz, s.head))
    }
}

/// The GNSS port of a frame's inputs.
struct GnssInput<'a, 'b>(&'b mut core::slice::Iter<'a, NavGnssFix>);

impl GnssPort for GnssInput<'_, '_> {
    fn poll(&mut self) -> Option<GnssFix> {
        self.0.next().map(|f| {
            GnssFix::new(f.gps_week, f.gps_seconds_of_week, f.position_ecef_m)
                .with_velocity_ecef_mps((f.velocity_present == 1).then_some(f.velocity_ecef_mps))
        })
    }
}

/// The C fusion code.
fn fusion_of(fusion: FrameFusion) -> NavFusion {
    match fusion {
        FrameFusion::None => NavFusion::None,
        FrameFusion::StarAccepted => NavFusion::StarAccepted,
        FrameFusion::StarRejected => NavFusion::StarRejected,
        FrameFusion::GnssAccepted => NavFusion::GnssAccepted,
        FrameFusion::GnssRejected => NavFusion::GnssRejected,
        FrameFusion::GnssVelocityAccepted => NavFusion::GnssVelocityAccepted,
        FrameFusion::GnssVelocityRejected => NavFusion::GnssVelocityRejected,
    }
}

/// Writes the frame's telemetry `t` and the computer's calibration table, star noise and
/// active head into `out`.
pub fn write_telemetry(t: &FrameTelemetry, computer: &NavigationComputer, out: &mut NavTelemetry) {
    out.frame = t.frame;
    out.time_s = t.time_s;
    out.attitude_wxyz = t.attitude_wxyz;
    out.position_m = t.position_m;
    out.velocity_mps = t.velocity_mps;
    out.fusion = fusion_of(t.fusion);
    out.last_star_nis = t.last_star_nis;
    out.last_gnss_nis = t.last_gnss_nis;
    out.last_gnss_velocity_nis = t.last_gnss_velocity_nis;
    out.star_faulty = u8::from(t.star_faulty);
    out.gnss_faulty = u8::from(t.gnss_faulty);
    out.star_inconsistent = u8::from(t.star_inconsistent);
    out.gnss_inconsistent = u8::from(t.gnss_inconsistent);
    out.gnss_velocity_inconsistent = u8::from(t.gnss_velocity_inconsistent);
    out.converged_blocks = t.converged_blocks;
    out.frozen_blocks = u32::from(t.frozen_blocks);
    let table = computer.calibration_table();
    let c = &mut out.calibration;
    write_entry(&table.gyro_bias, &mut c.gyro_bias_rad_s);
    write_entry(&table.accel_bias, &mut c.accel_bias_mps2);
    write_entry(&table.star_installation, &mut c.star_installation_rad);
    write_entry(&table.gyro_scale_factor, &mut c.gyro_scale_factor);
    write_entry(&table.accel_scale_factor, &mut c.accel_scale_factor);
    crate::health::write_health(&t.health, &mut out.health);
    out.last_frame_cost = t.last_frame_cost;
    out.worst_frame_cost = t.worst_frame_cost;
    crate::health::write_commands(&t.commands, &mut out.commands);
}

/// Writes a calibration entry's estimate and 1σ.
fn write_entry(
    entry: &nav_fsw::calibration_manager::CalibrationEntry,
    out: &mut NavCalibrationEntry,
) {
    out.value = entry.value;
    out.sigma = entry.sigma();
}

/// What the computer reports when asked: the star noise in use, the active head and the
/// optional state blocks (each block's bit, NaN in a block not flown).
pub fn reported_states_of(computer: &NavigationComputer) -> NavReportedStates {
    let states = computer.optional_states();
    let nan3 = [f64::NAN; 3];
    let nan6 = [f64::NAN; 6];
    let mut out = NavReportedStates {
        star_noise_rad: computer.star_noise_rad(),
        active_star_head: computer.active_star_head(),
        blocks: 0,
        gnss_error_m: nan3,
        gnss_error_sigma_m: nan3,
        gyro_non_orthogonality_rad: nan3,
        gyro_non_orthogonality_sigma_rad: nan3,
        accel_misalignment_rad: nan6,
        accel_misalignment_sigma_rad: nan6,
        gyro_g_sensitivity_rad_s_per_mps2: nan3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: nan3,
    };
    if let Some(gnss) = &states.gnss_error {
        out.blocks |= 1;
        out.gnss_error_m = gnss.estimate_m;
        out.gnss_error_sigma_m = gnss.sigma_m;
    }
    if let Some(imu) = &states.imu_error {
        out.blocks |= 2;
        out.gyro_non_orthogonality_rad = imu.gyro_non_orthogonality_rad;
        out.gyro_non_orthogonality_sigma_rad = imu.gyro_non_orthogonality_sigma_rad;
        out.accel_misalignment_rad = imu.accel_misalignment_rad;
        out.accel_misalignment_sigma_rad = imu.accel_misalignment_sigma_rad;
        out.gyro_g_sensitivity_rad_s_per_mps2 = imu.gyro_g_sensitivity_rad_s_per_mps2;
        out.gyro_g_sensitivity_sigma_rad_s_per_mps2 = imu.gyro_g_sensitivity_sigma_rad_s_per_mps2;
    }
    out
}
