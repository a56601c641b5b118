//! Fault rows 32–33: a manoeuvre that blinds the star tracker and one beyond the IMU range.

use super::*;

/// The manoeuvre rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "star tracker loses track in a slew",
            injected: "a 10 °/s slew (9 s, 80°) at 0 s; the tracker delivers nothing while \
                       the body rate exceeds 3 °/s and for 10 s after (re-acquisition)",
            reaction: "navigation on IMU + GNSS through the blind slew; the outage counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(1))],
            injection_s: 30.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                insert_segments(scenario, FAULT_START_S, &[slew(9.0, [0.0, 10.0, 0.0])]);
            }),
            injector: |f| {
                let mut blind_until = i64::MIN;
                Box::new(move |relative, ports| {
                    if relative < 0 {
                        return;
                    }
                    let rate_deg_s = ports.imu.0.as_ref().map_or(0.0, |sample| {
                        Vector3::from(sample.delta_angle_rad).norm().to_degrees() * f.rate_hz()
                    });
                    if rate_deg_s > 3.0 {
                        blind_until = relative + f.frames(10.0);
                    }
                    if relative < blind_until {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "manoeuvre beyond the IMU range",
            injected: "450 °/s about z for 2 s at 0 s, then 250 m/s² along x for 2 s at 7 s \
                       (ranges 401 °/s, 200 m/s²): the IMU outputs its full scale",
            reaction: "each full-scale sample refused as saturated and the last good one held; \
                       the covariance grows by the range per held frame, so the star sensor \
                       and GNSS pull the solution back and neither is declared faulty",
            // Frames at or beyond full scale: the raised-cosine ramps (0.5 s) pass 401/450 of
            // the peak rate 0.107 s before the plateau ends, 250/200 of the force 0.148 s:
            // (1 + 2 × 0.107) s + (1 + 2 × 0.148) s at 500 Hz ≈ 607 + 648 frames. The count is
            // the one flown at the default 500 Hz; it scales with the IMU rate.
            counts: vec![(counter!(imu_saturated), Expected::Exactly(1254))],
            injection_s: 10.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                insert_segments(
                    scenario,
                    FAULT_START_S,
                    &[
                        slew(2.0, [0.0, 0.0, 450.0]),
                        slew(5.0, [0.0; 3]),
                        thrust(2.0, [250.0, 0.0, 0.0]),
                    ],
                );
            }),
            injector: |f| {
                Box::new(move |relative, ports| {
                    let Some(sample) = imu(ports) else { return };
                    if relative < 0 {
                        return;
                    }
                    // The default limits (nav-fsw ImuLimits): 7 rad/s and 200 m/s².
                    let period_s = f.period_s();
                    let clip = |value: &mut f64, range: f64| *value = value.clamp(-range, range);
                    for value in sample.delta_angle_rad.iter_mut() {
                        clip(value, 7.0 * period_s);
                    }
                    for value in sample.delta_velocity_mps.iter_mut() {
                        clip(value, 200.0 * period_s);
                    }
                })
            },
        },
    ]
}
