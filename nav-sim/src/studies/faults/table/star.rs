//! Fault rows 13–18: star-sensor outages, sign flips, non-unit quaternions and outliers.

use super::*;

/// The star-sensor rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "star outages 0.5 s, 5 s, 60 s",
            injected: "no star measurement for 0.5 s (at 0 s), 5 s (at 2 s), 60 s (at 10 s)",
            reaction: "navigation on IMU + GNSS; an outage longer than the 2 s timeout \
                       counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(2))],
            injection_s: 70.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    let silent = [
                        (0, f.frames(0.5)),
                        (f.frames(2.0), f.frames(5.0)),
                        (f.frames(10.0), f.frames(60.0)),
                    ]
                    .iter()
                    .any(|(start, length)| (*start..start + length).contains(&relative));
                    if silent {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "star outage 600 s",
            injected: "no star measurement for 600 s (across the +x burn)",
            reaction: "navigation on IMU + GNSS; the outage counted once",
            counts: vec![(counter!(star_outages), Expected::Exactly(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    if (0..f.frames(600.0)).contains(&relative) {
                        ports.star.0.clear();
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion sign flips",
            injected: "q → −q on every other measurement, 10 measurements",
            reaction: "undone (q and −q are one attitude), each change of sign counted",
            counts: vec![(counter!(star_sign_flip), Expected::Exactly(10))],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    if n < 10 && n % 2 == 0 {
                        if let Some(m) = star(ports) {
                            m.sensor_to_gcrf_wxyz.iter_mut().for_each(|c| *c = -*c);
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "star quaternion non-unit and zero",
            injected: "|q| = 1.1, 0.9, 1.002 and 0 (4 measurements, every other one); |q| = \
                       1.0005 (within the 1e-3 tolerance)",
            reaction: "|q| − 1 beyond the tolerance: dropped; within: normalised and used",
            counts: vec![(counter!(star_not_unit), Expected::Exactly(4))],
            injection_s: 1.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    let Some(m) = star(ports) else { return };
                    let scale = match n {
                        0 => 1.1,
                        2 => 0.9,
                        4 => 1.002,
                        6 => 0.0,
                        8 => 1.0005,
                        _ => return,
                    };
                    m.sensor_to_gcrf_wxyz.iter_mut().for_each(|c| *c *= scale);
                })
            },
        },
        FaultClass {
            name: "star outliers 5°",
            injected: "3 measurements rotated 5° about x, y, z (1 s apart)",
            reaction: "rejected by the innovation gate (NIS ≫ 16.27)",
            counts: vec![(counter!(star_gate_rejections), Expected::Exactly(3))],
            injection_s: 2.1,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    if n % 10 == 0 && n < 30 {
                        if let Some(m) = star(ports) {
                            rotate_star(m, (n / 10) as usize, 5.0);
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "star outliers 180°",
            injected: "3 measurements rotated 180° about x, y, z (1 s apart)",
            reaction: "rejected by the innovation gate",
            counts: vec![(counter!(star_gate_rejections), Expected::Exactly(3))],
            injection_s: 2.1,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_star(|n, ports| {
                    if n % 10 == 0 && n < 30 {
                        if let Some(m) = star(ports) {
                            rotate_star(m, (n / 10) as usize, 180.0);
                        }
                    }
                })
            },
        },
    ]
}
