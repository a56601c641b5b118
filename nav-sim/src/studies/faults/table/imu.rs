//! Fault rows 9–12: IMU dropouts, spikes, saturation and a frozen channel.

use super::*;

/// The IMU rows, in row order.
pub(super) fn rows(frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    // Δθ saturated for 1 s, then Δv for 1 s: every sample of the two seconds.
    let saturated = 2 * frames.frames(1.0) as u32;
    vec![
        FaultClass {
            name: "IMU dropouts 1-500 frames",
            injected: "no sample for 1, 10, 100 and 500 frames (at 0, 1, 2, 4 s)",
            reaction: "last good increment held, time advances",
            counts: vec![(counter!(imu_missing), Expected::Exactly(611))],
            injection_s: 5.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    let dropped = [
                        (0, 1),
                        (f.frames(1.0), 10),
                        (f.frames(2.0), 100),
                        (f.frames(4.0), 500),
                    ]
                    .iter()
                    .any(|(start, length)| (*start..start + length).contains(&relative));
                    if dropped {
                        ports.imu.0 = None;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU spikes",
            injected: "10 single-sample spikes every 0.5 s: Δθ ±0.1 rad (50 rad/s) and Δv \
                       ±2 m/s (1000 m/s²) on x, y, z in turn",
            reaction: "beyond the saturation limits: dropped, held, counted also as missing",
            counts: vec![
                (counter!(imu_saturated), Expected::Exactly(10)),
                (counter!(imu_missing), Expected::Exactly(10)),
            ],
            injection_s: 5.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                let (every, end) = (f.frames(0.5), f.frames(5.0));
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if relative < 0 || relative % every != 0 || relative >= end {
                        return;
                    }
                    let spike = relative / every;
                    let sign = if spike % 2 == 0 { 1.0 } else { -1.0 };
                    let axis = (spike % 3) as usize;
                    if spike % 4 < 2 {
                        sample.delta_angle_rad[axis] = 0.1 * sign;
                    } else {
                        sample.delta_velocity_mps[axis] = 2.0 * sign;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU saturation held 1 s",
            injected: "Δθ z = 0.021 rad (10.5 rad/s, 1.5 × the limit) for 1 s, then Δv x = \
                       0.6 m/s (300 m/s²) for 1 s",
            reaction: "each sample beyond the limits dropped, last good increment held, \
                       counted also as missing",
            counts: vec![
                (counter!(imu_saturated), Expected::Exactly(saturated)),
                (counter!(imu_missing), Expected::Exactly(saturated)),
            ],
            injection_s: 3.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                let (angle, velocity) = (0..f.frames(1.0), f.frames(2.0)..f.frames(3.0));
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if angle.contains(&relative) {
                        sample.delta_angle_rad[2] = 0.021;
                    } else if velocity.contains(&relative) {
                        sample.delta_velocity_mps[0] = 0.6;
                    }
                })
            },
        },
        FaultClass {
            name: "IMU channel frozen 10 s",
            injected: "gyro x repeats the bits of its first sample for 10 s (5000 samples)",
            reaction: "a repeated value is a valid reading: no input check sees it; the \
                       attitude drift it causes is below the star gate",
            counts: vec![
                (
                    counter!(imu_non_finite + imu_saturated),
                    Expected::Exactly(0),
                ),
                (counter!(star_gate_rejections), Expected::Exactly(0)),
            ],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                let mut frozen = None;
                let frozen_frames = 0..f.frames(10.0);
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if frozen_frames.contains(&relative) {
                        let value = *frozen.get_or_insert(sample.delta_angle_rad[0]);
                        sample.delta_angle_rad[0] = value;
                    }
                })
            },
        },
    ]
}
