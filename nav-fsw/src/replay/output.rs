//! A frame's output record: fixed-layout 8-byte words, compared bit for bit.

use super::AssemblyCounts;
use crate::scheduler::NavigationComputer;
use crate::telemetry::{FrameFusion, FrameTelemetry};

/// Number of words of a frame's output record.
pub const OUTPUT_WORDS: usize = 94;

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
];

/// The output record of a frame (module docs): telemetry (without the platform's frame cost,
/// which only the target measures), the calibration table and the assembler's counts (a live
/// run, without an assembler, passes its ports' dropped measurements in
/// [`AssemblyCounts::measurements_dropped`]). One line per word in the order of
/// [`OUTPUT_FIELD_NAMES`], so the two read side by side; longer than a function usually is for
/// that reason.
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
    words
}
