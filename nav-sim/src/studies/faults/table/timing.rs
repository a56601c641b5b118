//! Fault rows 24–29: stale, duplicated, out-of-order and future time tags, IMU clock jumps
//! and the IMU sequence-counter wrap.

use super::*;

/// The timing rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "stale time tags",
            injected: "one star measurement and one fix time-tagged 1 s late",
            reaction: "older than the latency limit: dropped",
            counts: vec![(counter!(measurement_stale), Expected::Exactly(2))],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                both(
                    on_star(|n, ports| {
                        if let (0, Some(m)) = (n, star(ports)) {
                            m.time_tag_s -= 1.0;
                        }
                    }),
                    on_gnss(|n, ports| {
                        if let (0, Some(fix)) = (n, gnss(ports)) {
                            fix.gps_seconds_of_week -= 1.0;
                        }
                    }),
                )
            },
        },
        FaultClass {
            name: "duplicated samples",
            injected: "one star measurement and one fix delivered twice; one IMU sample \
                       repeated (replacing the next)",
            reaction: "measurement not newer than the last: dropped; IMU: dropped, held, the \
                       replaced sample counted missing",
            counts: vec![
                (counter!(measurement_stale), Expected::Exactly(2)),
                (counter!(imu_duplicate), Expected::Exactly(1)),
                (counter!(imu_missing), Expected::Exactly(1)),
            ],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                let mut previous = None;
                both(
                    Box::new(move |relative, ports| {
                        if relative == 0 {
                            ports.imu.0 = previous;
                        }
                        previous = ports.imu.0;
                    }),
                    both(
                        on_star(|n, ports| {
                            if let (0, Some(m)) = (n, ports.star.0.front().copied()) {
                                let _ = ports.star.0.push_back(m);
                            }
                        }),
                        on_gnss(|n, ports| {
                            if let (0, Some(fix)) = (n, ports.gnss.0.front().copied()) {
                                let _ = ports.gnss.0.push_back(fix);
                            }
                        }),
                    ),
                )
            },
        },
        FaultClass {
            name: "out-of-order samples",
            injected: "a star measurement and a fix followed by one 20 ms older; IMU sample \
                       k−2 delivered after k−1, in place of k",
            reaction: "measurement older than the last fused: dropped; IMU: the late sample \
                       dropped (out of order), held; the lost sample k counted missing",
            counts: vec![
                (counter!(measurement_stale), Expected::Exactly(2)),
                (counter!(imu_duplicate), Expected::Exactly(1)),
                (counter!(imu_missing), Expected::Exactly(1)),
            ],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                let mut history: [Option<ImuSample>; 2] = [None; 2];
                both(
                    Box::new(move |relative, ports| {
                        let current = ports.imu.0;
                        if relative == 0 {
                            // Sample k−2 arrives late, after k−1, in place of sample k.
                            ports.imu.0 = history[0];
                        }
                        history = [history[1], current];
                    }),
                    both(
                        on_star(|n, ports| {
                            if let (0, Some(mut m)) = (n, ports.star.0.front().copied()) {
                                m.time_tag_s -= 0.02;
                                let _ = ports.star.0.push_back(m);
                            }
                        }),
                        on_gnss(|n, ports| {
                            if let (0, Some(mut fix)) = (n, ports.gnss.0.front().copied()) {
                                fix.gps_seconds_of_week -= 0.02;
                                let _ = ports.gnss.0.push_back(fix);
                            }
                        }),
                    ),
                )
            },
        },
        FaultClass {
            name: "future time tags",
            injected: "one star measurement and one fix time-tagged 1 s ahead",
            reaction: "beyond the future tolerance: dropped",
            counts: vec![(counter!(measurement_future), Expected::Exactly(2))],
            injection_s: 0.2,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                both(
                    on_star(|n, ports| {
                        if let (0, Some(m)) = (n, star(ports)) {
                            m.time_tag_s += 1.0;
                        }
                    }),
                    on_gnss(|n, ports| {
                        if let (0, Some(fix)) = (n, gnss(ports)) {
                            fix.gps_seconds_of_week += 1.0;
                        }
                    }),
                )
            },
        },
        FaultClass {
            name: "IMU clock jumps",
            injected: "time step 0 (at 0 s), −1 period (1 s), +10 periods (2 s); 32-bit µs \
                       clock wrap, −4294.967296 s from 3 s on",
            reaction: "time jump counted (the sample and the next one; the wrap once, the \
                       time base re-anchored); increments used, time frame-driven",
            counts: vec![(counter!(imu_time_jump), Expected::Exactly(7))],
            injection_s: 3.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    let period = f.period_s();
                    match relative {
                        0 => sample.time_s -= period,
                        r if r == f.frames(1.0) => sample.time_s -= 2.0 * period,
                        r if r == f.frames(2.0) => sample.time_s += 9.0 * period,
                        r if r >= f.frames(3.0) => sample.time_s -= 4_294.967_296,
                        _ => {}
                    }
                })
            },
        },
        FaultClass {
            name: "IMU sequence counter wrap",
            injected: "sequence numbers offset so the counter wraps u32::MAX → 0 at 10 ms",
            reaction: "continuous through the wrap: nothing missing, nothing repeated",
            counts: vec![
                (counter!(imu_missing), Expected::Exactly(0)),
                (
                    counter!(imu_duplicate + imu_time_jump),
                    Expected::Exactly(0),
                ),
            ],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                let mut offset = None;
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    // Sequence u32::MAX − 4 at the fault start: 0 five frames later.
                    let offset = *offset.get_or_insert_with(|| {
                        (u32::MAX - 4)
                            .wrapping_add(relative as u32)
                            .wrapping_sub(sample.sequence)
                    });
                    sample.sequence = sample.sequence.wrapping_add(offset);
                })
            },
        },
    ]
}
