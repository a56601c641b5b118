//! The health counters for C, field for field (a test holds `NavHealth` to nav-fsw's
//! `HealthCounters`: the same fields in the same order).

use nav_fsw::health::HealthCounters;

use nav_fsw::scheduler::CommandCounters;

use crate::types::{NavCommandCounters, NavHealth};

/// Writes `commands` into `out`.
pub fn write_commands(commands: &CommandCounters, out: &mut NavCommandCounters) {
    *out = NavCommandCounters {
        accepted: commands.accepted,
        refused: commands.refused,
        measurements_of_disabled_aid: commands.measurements_of_disabled_aid,
        calibration_records_loaded: commands.calibration_records_loaded,
        calibration_records_refused: commands.calibration_records_refused,
    };
}

/// Writes `health` into `out`.
pub fn write_health(health: &HealthCounters, out: &mut NavHealth) {
    let h = health;
    *out = NavHealth {
        imu_non_finite: h.imu_non_finite,
        imu_saturated: h.imu_saturated,
        imu_duplicate: h.imu_duplicate,
        imu_missing: h.imu_missing,
        imu_time_jump: h.imu_time_jump,
        star_non_finite: h.star_non_finite,
        star_not_unit: h.star_not_unit,
        star_sign_flip: h.star_sign_flip,
        gnss_non_finite: h.gnss_non_finite,
        gnss_jump: h.gnss_jump,
        measurement_stale: h.measurement_stale,
        measurement_future: h.measurement_future,
        measurement_overflow: h.measurement_overflow,
        star_gate_rejections: h.star_gate_rejections,
        gnss_gate_rejections: h.gnss_gate_rejections,
        gnss_velocity_gate_rejections: h.gnss_velocity_gate_rejections,
        imu_held_frames: h.imu_held_frames,
        covariance_clamps: h.covariance_clamps,
        filter_resets: h.filter_resets,
        frame_overruns: h.frame_overruns,
        star_declared_faulty: h.star_declared_faulty,
        gnss_declared_faulty: h.gnss_declared_faulty,
        ignored_from_faulty_sensor: h.ignored_from_faulty_sensor,
        star_outages: h.star_outages,
        gnss_outages: h.gnss_outages,
        filter_errors: h.filter_errors,
        strapdown_failures: h.strapdown_failures,
        gnss_innovations_correlated: h.gnss_innovations_correlated,
        star_inconsistent: h.star_inconsistent,
        gnss_inconsistent: h.gnss_inconsistent,
        gnss_velocity_inconsistent: h.gnss_velocity_inconsistent,
        inertial_suspect: h.inertial_suspect,
        gravity_allowance_short: h.gravity_allowance_short,
        gravity_field_errors: h.gravity_field_errors,
        star_noise_matched: h.star_noise_matched,
        star_pair_rejections: h.star_pair_rejections,
        star_heads_inconsistent: h.star_heads_inconsistent,
        star_head_handovers: h.star_head_handovers,
        star_unknown_head: h.star_unknown_head,
        star_aberration_suspected: h.star_aberration_suspected,
    };
}
