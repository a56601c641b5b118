//! A frame's output record: fixed-layout 8-byte words, compared bit for bit. The optional
//! state blocks' words are always present: a block the filter does not fly has its bit clear
//! in `optional_blocks` and NaN in its words, never values that look like estimates.

use super::AssemblyCounts;
use crate::scheduler::NavigationComputer;
use crate::telemetry::{
    FrameFusion, FrameTelemetry, OptionalStateTelemetry, GNSS_ERROR_FIELD_NAMES,
    IMU_ERROR_FIELD_NAMES,
};

/// Number of words of a frame's output record.
pub const OUTPUT_WORDS: usize = 102 + OPTIONAL_STATE_WORDS;

/// Words of the optional state blocks: the `optional_blocks` bits, then the correlated GNSS
/// error's and the systematic IMU errors' fields.
pub const OPTIONAL_STATE_WORDS: usize =
    1 + GNSS_ERROR_FIELD_NAMES.len() + IMU_ERROR_FIELD_NAMES.len();

/// `optional_blocks` bit of the correlated GNSS error states.
pub const GNSS_ERROR_BLOCK_BIT: u64 = 1;
/// `optional_blocks` bit of the systematic IMU error states.
pub const IMU_ERROR_BLOCK_BIT: u64 = 2;

/// Names of the output words, in order.
pub const OUTPUT_FIELD_NAMES: [&str; OUTPUT_WORDS] = [
    "frame",
    "time_s",
    "attitude_w",
    "attitude_x",
    "attitude_y",
    "attitude_z",
    "position_x_m",
    "position_y_m",
    "position_z_m",
    "velocity_x_mps",
    "velocity_y_mps",
    "velocity_z_mps",
    "fusion",
    "last_star_nis",
    "last_gnss_nis",
    "star_faulty",
    "gnss_faulty",
    "converged_blocks",
    "frozen_blocks",
    "gyro_bias_x",
    "gyro_bias_y",
    "gyro_bias_z",
    "accel_bias_x",
    "accel_bias_y",
    "accel_bias_z",
    "star_installation_x",
    "star_installation_y",
    "star_installation_z",
    "gyro_scale_factor_x",
    "gyro_scale_factor_y",
    "gyro_scale_factor_z",
    "accel_scale_factor_x",
    "accel_scale_factor_y",
    "accel_scale_factor_z",
    "gyro_bias_sigma_x",
    "gyro_bias_sigma_y",
    "gyro_bias_sigma_z",
    "accel_bias_sigma_x",
    "accel_bias_sigma_y",
    "accel_bias_sigma_z",
    "star_installation_sigma_x",
    "star_installation_sigma_y",
    "star_installation_sigma_z",
    "gyro_scale_factor_sigma_x",
    "gyro_scale_factor_sigma_y",
    "gyro_scale_factor_sigma_z",
    "accel_scale_factor_sigma_x",
    "accel_scale_factor_sigma_y",
    "accel_scale_factor_sigma_z",
    "imu_non_finite",
    "imu_saturated",
    "imu_duplicate",
    "imu_missing",
    "imu_time_jump",
    "star_non_finite",
    "star_not_unit",
    "star_sign_flip",
    "gnss_non_finite",
    "gnss_jump",
    "measurement_stale",
    "measurement_future",
    "measurement_overflow",
    "star_gate_rejections",
    "gnss_gate_rejections",
    "covariance_clamps",
    "filter_resets",
    "star_declared_faulty",
    "gnss_declared_faulty",
    "ignored_from_faulty_sensor",
    "filter_errors",
    "strapdown_failures",
    "dropped_measurements",
    "last_gnss_velocity_nis",
    "gnss_velocity_gate_rejections",
    "imu_held_frames",
    "gnss_innovations_correlated",
    "imu_records_dropped",
    "star_inconsistent",
    "gnss_inconsistent",
    "gnss_velocity_inconsistent",
    "inconsistent_aids",
    "inertial_suspect",
    "gravity_allowance_short",
    "gravity_field_errors",
    "star_noise_matched",
    "star_noise_x_rad",
    "star_noise_y_rad",
    "star_noise_z_rad",
    "star_pair_rejections",
    "star_heads_inconsistent",
    "star_head_handovers",
    "star_unknown_head",
    "star_active_head",
    "star_aberration_suspected",
    "frame_overruns",
    "star_outages",
    "gnss_outages",
    "commands_accepted",
    "commands_refused",
    "measurements_of_disabled_aid",
    "calibration_records_loaded",
    "calibration_records_refused",
    "optional_blocks",
    "gnss_error_x_m",
    "gnss_error_y_m",
    "gnss_error_z_m",
    "gnss_error_sigma_x_m",
    "gnss_error_sigma_y_m",
    "gnss_error_sigma_z_m",
    "gyro_non_orthogonality_yx_rad",
    "gyro_non_orthogonality_zx_rad",
    "gyro_non_orthogonality_zy_rad",
    "gyro_non_orthogonality_sigma_yx_rad",
    "gyro_non_orthogonality_sigma_zx_rad",
    "gyro_non_orthogonality_sigma_zy_rad",
    "accel_misalignment_xy_rad",
    "accel_misalignment_xz_rad",
    "accel_misalignment_yx_rad",
    "accel_misalignment_yz_rad",
    "accel_misalignment_zx_rad",
    "accel_misalignment_zy_rad",
    "accel_misalignment_sigma_xy_rad",
    "accel_misalignment_sigma_xz_rad",
    "accel_misalignment_sigma_yx_rad",
    "accel_misalignment_sigma_yz_rad",
    "accel_misalignment_sigma_zx_rad",
    "accel_misalignment_sigma_zy_rad",
    "gyro_g_sensitivity_x_rad_s_per_mps2",
    "gyro_g_sensitivity_y_rad_s_per_mps2",
    "gyro_g_sensitivity_z_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_x_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_y_rad_s_per_mps2",
    "gyro_g_sensitivity_sigma_z_rad_s_per_mps2",
];

/// The output record of a frame (module docs): telemetry (without the platform's frame cost,
/// which only the target measures), the calibration table and the assembler's counts (a live
/// run, without an assembler, passes its ports' dropped measurements in
/// [`AssemblyCounts::measurements_dropped`]). One line per word in the order of
/// [`OUTPUT_FIELD_NAMES`], so the two read side by side; longer than a function usually is for
/// that reason. Not inlined: inlined into a firmware's frame loop, its locals would be reserved
/// in the loop's stack frame on the Cortex-M7 (the replay firmware measured a deeper stack and
/// dearer frames that way).
#[inline(never)]
pub fn output_words(
    telemetry: &FrameTelemetry,
    computer: &NavigationComputer,
    counts: &AssemblyCounts,
) -> [u64; OUTPUT_WORDS] {
    let t = telemetry;
    let h = &t.health;
    let fusion = match t.fusion {
        FrameFusion::None => 0,
        FrameFusion::StarAccepted => 1,
        FrameFusion::StarRejected => 2,
        FrameFusion::GnssAccepted => 3,
        FrameFusion::GnssRejected => 4,
        FrameFusion::GnssVelocityAccepted => 5,
        FrameFusion::GnssVelocityRejected => 6,
    };
    let mut words = [0_u64; OUTPUT_WORDS];
    let mut slots = words.iter_mut();
    let mut put = |value: u64| {
        if let Some(slot) = slots.next() {
            *slot = value;
        }
    };
    put(u64::from(t.frame));
    put(t.time_s.to_bits());
    for value in t.attitude_wxyz {
        put(value.to_bits());
    }
    for value in t.position_m.iter().chain(t.velocity_mps.iter()) {
        put(value.to_bits());
    }
    put(fusion);
    put(t.last_star_nis.to_bits());
    put(t.last_gnss_nis.to_bits());
    put(u64::from(t.star_faulty));
    put(u64::from(t.gnss_faulty));
    put(u64::from(t.converged_blocks));
    put(u64::from(t.frozen_blocks));
    let table = computer.calibration_table().entries();
    for (_, entry) in table {
        for value in entry.value {
            put(value.to_bits());
        }
    }
    for (_, entry) in table {
        for value in entry.sigma() {
            put(value.to_bits());
        }
    }
    let counters = [
        h.imu_non_finite,
        h.imu_saturated,
        h.imu_duplicate,
        h.imu_missing,
        h.imu_time_jump,
        h.star_non_finite,
        h.star_not_unit,
        h.star_sign_flip,
        h.gnss_non_finite,
        h.gnss_jump,
        h.measurement_stale,
        h.measurement_future,
        h.measurement_overflow,
        h.star_gate_rejections,
        h.gnss_gate_rejections,
        h.covariance_clamps,
        h.filter_resets,
        h.star_declared_faulty,
        h.gnss_declared_faulty,
        h.ignored_from_faulty_sensor,
        h.filter_errors,
        h.strapdown_failures,
        counts.measurements_dropped,
    ];
    for counter in counters {
        put(u64::from(counter));
    }
    put(t.last_gnss_velocity_nis.to_bits());
    put(u64::from(h.gnss_velocity_gate_rejections));
    put(u64::from(h.imu_held_frames));
    put(u64::from(h.gnss_innovations_correlated));
    put(u64::from(counts.imu_records_dropped));
    put(u64::from(h.star_inconsistent));
    put(u64::from(h.gnss_inconsistent));
    put(u64::from(h.gnss_velocity_inconsistent));
    // The aids' current verdicts, one bit each: star 1, GNSS position 2, GNSS velocity 4.
    put(u64::from(t.star_inconsistent)
        | (u64::from(t.gnss_inconsistent) << 1)
        | (u64::from(t.gnss_velocity_inconsistent) << 2));
    put(u64::from(h.inertial_suspect));
    put(u64::from(h.gravity_allowance_short));
    put(u64::from(h.gravity_field_errors));
    put(u64::from(h.star_noise_matched));
    // Read from the computer, not the frame telemetry: every frame would pay for the copy.
    for noise in computer.star_noise_rad() {
        put(noise.to_bits());
    }
    put(u64::from(h.star_pair_rejections));
    put(u64::from(h.star_heads_inconsistent));
    put(u64::from(h.star_head_handovers));
    put(u64::from(h.star_unknown_head));
    put(u64::from(computer.active_star_head()));
    put(u64::from(h.star_aberration_suspected));
    put(u64::from(h.frame_overruns));
    put(u64::from(h.star_outages));
    put(u64::from(h.gnss_outages));
    for (_, counter) in t.commands.named() {
        put(u64::from(counter));
    }
    // Read from the computer at output time, not in the frame (`crate::telemetry`).
    for word in optional_state_words(&computer.optional_states()) {
        put(word);
    }
    words
}

/// The optional state blocks' words: the `optional_blocks` bits ([`GNSS_ERROR_BLOCK_BIT`],
/// [`IMU_ERROR_BLOCK_BIT`]), then each block's fields, NaN for a block not flown.
pub fn optional_state_words(states: &OptionalStateTelemetry) -> [u64; OPTIONAL_STATE_WORDS] {
    let mut words = [f64::NAN.to_bits(); OPTIONAL_STATE_WORDS];
    let gnss = states.gnss_error.map(|block| block.values());
    let imu = states.imu_error.map(|block| block.values());
    let mut blocks = 0;
    if gnss.is_some() {
        blocks |= GNSS_ERROR_BLOCK_BIT;
    }
    if imu.is_some() {
        blocks |= IMU_ERROR_BLOCK_BIT;
    }
    let (first, fields) = words.split_at_mut(1);
    if let Some(word) = first.first_mut() {
        *word = blocks;
    }
    let (gnss_words, imu_words) = fields.split_at_mut(GNSS_ERROR_FIELD_NAMES.len());
    for (slot, value) in gnss_words.iter_mut().zip(gnss.iter().flatten()) {
        *slot = value.to_bits();
    }
    for (slot, value) in imu_words.iter_mut().zip(imu.iter().flatten()) {
        *slot = value.to_bits();
    }
    words
}
