//! A frame's output record from the C structs: nav-fsw's `replay::output_words`, word for word
//! (`OUTPUT_FIELD_NAMES` order), read from what a C caller holds, so the C replay's records
//! compare bit for bit with the Rust replay's (tests/c_host.rs compares them).

use nav_fsw::replay::{AssemblyCounts, OUTPUT_WORDS};

use crate::types::{NavFusion, NavReportedStates, NavTelemetry};

/// The fusion's word (its C value).
fn fusion_code(fusion: NavFusion) -> u64 {
    match fusion {
        NavFusion::None => 0,
        NavFusion::StarAccepted => 1,
        NavFusion::StarRejected => 2,
        NavFusion::GnssAccepted => 3,
        NavFusion::GnssRejected => 4,
        NavFusion::GnssVelocityAccepted => 5,
        NavFusion::GnssVelocityRejected => 6,
    }
}

/// The output record of a frame (one line per word, in the order of the names, so the two
/// read side by side).
pub fn output_words(
    t: &NavTelemetry,
    states: &NavReportedStates,
    counts: &AssemblyCounts,
) -> [u64; OUTPUT_WORDS] {
    let h = &t.health;
    let mut words = [0_u64; OUTPUT_WORDS];
    let mut slots = words.iter_mut();
    let mut put = |value: u64| {
        if let Some(slot) = slots.next() {
            *slot = value;
        }
    };
    put(u64::from(t.frame));
    put(t.time_s.to_bits());
    let navigation = t
        .attitude_wxyz
        .iter()
        .chain(&t.position_m)
        .chain(&t.velocity_mps);
    for value in navigation {
        put(value.to_bits());
    }
    put(fusion_code(t.fusion));
    put(t.last_star_nis.to_bits());
    put(t.last_gnss_nis.to_bits());
    put(u64::from(t.star_faulty));
    put(u64::from(t.gnss_faulty));
    put(u64::from(t.converged_blocks));
    put(u64::from(t.frozen_blocks));
    let c = &t.calibration;
    let entries = [
        &c.gyro_bias_rad_s,
        &c.accel_bias_mps2,
        &c.star_installation_rad,
        &c.gyro_scale_factor,
        &c.accel_scale_factor,
    ];
    for value in entries.iter().flat_map(|entry| entry.value) {
        put(value.to_bits());
    }
    for value in entries.iter().flat_map(|entry| entry.sigma) {
        put(value.to_bits());
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
    for noise in states.star_noise_rad {
        put(noise.to_bits());
    }
    put(u64::from(h.star_pair_rejections));
    put(u64::from(h.star_heads_inconsistent));
    put(u64::from(h.star_head_handovers));
    put(u64::from(h.star_unknown_head));
    put(u64::from(states.active_star_head));
    put(u64::from(h.star_aberration_suspected));
    put(u64::from(h.frame_overruns));
    put(u64::from(h.star_outages));
    put(u64::from(h.gnss_outages));
    let c = &t.commands;
    let commands = [
        c.accepted,
        c.refused,
        c.measurements_of_disabled_aid,
        c.calibration_records_loaded,
        c.calibration_records_refused,
    ];
    for counter in commands {
        put(u64::from(counter));
    }
    put(u64::from(states.blocks));
    let s = states;
    let optional = s
        .gnss_error_m
        .iter()
        .chain(&s.gnss_error_sigma_m)
        .chain(&s.gyro_non_orthogonality_rad)
        .chain(&s.gyro_non_orthogonality_sigma_rad)
        .chain(&s.accel_misalignment_rad)
        .chain(&s.accel_misalignment_sigma_rad)
        .chain(&s.gyro_g_sensitivity_rad_s_per_mps2)
        .chain(&s.gyro_g_sensitivity_sigma_rad_s_per_mps2);
    for value in optional {
        put(value.to_bits());
    }
    words
}
