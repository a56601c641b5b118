//! Fault rows 1–8: the no-fault control row, then NaN, ±Inf and subnormal values in every
//! field of the IMU samples, the star measurements and the GNSS fixes.

use super::*;

/// The control row and the non-finite and subnormal rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "control: no fault",
            injected: "nothing",
            reaction: "nothing counted",
            counts: vec![
                (counter!(imu_missing), Expected::Exactly(0)),
                (counter!(star_outages + gnss_outages), Expected::Exactly(0)),
            ],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| Box::new(|_, _| {}),
        },
        FaultClass {
            name: "IMU Δθ NaN/±Inf/subnormal",
            injected: "Δθ x, y, z = NaN, +Inf, −Inf (9 samples); all = 4.9e-324 (3 samples)",
            reaction: "non-finite: sample dropped, last good increment held, counted also as \
                       missing; subnormal: a valid near-zero reading, used",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(9)),
                (counter!(imu_missing), Expected::Exactly(9)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| imu_field_injector(0),
        },
        FaultClass {
            name: "IMU Δv NaN/±Inf/subnormal",
            injected: "Δv x, y, z = NaN, +Inf, −Inf (9 samples); all = 4.9e-324 (3 samples)",
            reaction: "as Δθ",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(9)),
                (counter!(imu_missing), Expected::Exactly(9)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| imu_field_injector(1),
        },
        FaultClass {
            name: "IMU time tag NaN/±Inf/subnormal",
            injected: "time = NaN, +Inf, −Inf (3 samples); time = 4.9e-324 (1 sample)",
            reaction: "non-finite: dropped, held, counted as missing; subnormal: a time jump \
                       (the sample and the next one), increments used",
            counts: vec![
                (counter!(imu_non_finite), Expected::Exactly(3)),
                (counter!(imu_missing), Expected::Exactly(3)),
                (counter!(imu_time_jump), Expected::Exactly(2)),
            ],
            injection_s: 0.05,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                Box::new(|relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    match relative {
                        0..3 => sample.time_s = NON_FINITE[relative as usize],
                        10 => sample.time_s = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion NaN/±Inf/subnormal",
            injected: "w, x, y, z = NaN, +Inf, −Inf (12 measurements); w, x, y, z = 4.9e-324 \
                       in turn (4), all four = 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: not unit, dropped, or (a small \
                       component zeroed) a wrong attitude, gated",
            counts: vec![
                (counter!(star_non_finite), Expected::Exactly(12)),
                (
                    counter!(star_not_unit + star_gate_rejections),
                    Expected::Exactly(5),
                ),
            ],
            injection_s: 1.7,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    match n {
                        0..12 => {
                            m.sensor_to_gcrf_wxyz[(n % 4) as usize] = NON_FINITE[(n / 4) as usize]
                        }
                        12..16 => m.sensor_to_gcrf_wxyz[(n - 12) as usize] = SUBNORMAL,
                        16 => m.sensor_to_gcrf_wxyz = [SUBNORMAL; 4],
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "star time tag NaN/±Inf/subnormal",
            injected: "time tag = NaN, +Inf, −Inf (3 measurements); 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: stale, dropped",
            counts: vec![
                (counter!(star_non_finite), Expected::Exactly(3)),
                (counter!(measurement_stale), Expected::Exactly(1)),
            ],
            injection_s: 0.4,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    match n {
                        0..3 => m.time_tag_s = NON_FINITE[n as usize],
                        3 => m.time_tag_s = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS position NaN/±Inf/subnormal",
            injected: "x, y, z = NaN, +Inf, −Inf (9 fixes); x, y, z = 4.9e-324 in turn (3)",
            reaction: "non-finite: dropped; subnormal: a jump of thousands of km, dropped \
                       (a rejection)",
            counts: vec![
                (counter!(gnss_non_finite), Expected::Exactly(9)),
                (
                    counter!(gnss_jump + gnss_gate_rejections),
                    Expected::Exactly(3),
                ),
            ],
            injection_s: 1.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_gnss(|n, ports| {
                    let Some(fix) = gnss(ports) else { return };
                    match n {
                        0..9 => {
                            fix.position_ecef_m[(n % 3) as usize] = NON_FINITE[(n / 3) as usize]
                        }
                        9..12 => fix.position_ecef_m[(n - 9) as usize] = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS time tag NaN/±Inf/subnormal",
            injected: "time tag = NaN, +Inf, −Inf (3 fixes); 4.9e-324 (1)",
            reaction: "non-finite: dropped; subnormal: stale, dropped",
            counts: vec![
                (counter!(gnss_non_finite), Expected::Exactly(3)),
                (counter!(measurement_stale), Expected::Exactly(1)),
            ],
            injection_s: 0.4,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_gnss(|n, ports| {
                    let Some(fix) = gnss(ports) else { return };
                    match n {
                        0..3 => fix.gps_seconds_of_week = NON_FINITE[n as usize],
                        3 => fix.gps_seconds_of_week = SUBNORMAL,
                        _ => {}
                    }
                })
            },
        },
    ]
}
