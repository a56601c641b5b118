//! Fault rows 19–23: GNSS steps, a slow ramp below the gate and a 10-minute outage.

use super::*;

/// The GNSS rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "GNSS steps 100 m-10 km (1 s)",
            injected: "10 fixes offset by 100 m (x), 500 m (y), 2 km (z), 10 km (x); 10 good \
                       fixes between steps",
            reaction: "below the 1 km jump limit: gated; beyond: dropped as jumps; no \
                       declaration (the receiver recovers between steps)",
            counts: vec![
                (counter!(gnss_gate_rejections), Expected::Exactly(20)),
                (counter!(gnss_jump), Expected::Exactly(20)),
            ],
            injection_s: 7.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_gnss(|n, ports| {
                    let steps = [100.0, 500.0, 2_000.0, 10_000.0];
                    let (step, within) = ((n / 20) as usize, n % 20 < 10);
                    if let (Some(offset), true, Some(fix)) = (steps.get(step), within, gnss(ports))
                    {
                        fix.position_ecef_m[step % 3] += offset;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS step 100 m held",
            injected: "every fix from the fault on offset by 100 m (x)",
            reaction: "gated; after 20 rejections in a row the receiver is declared faulty \
                       (once) and ignored; navigation continues on the star sensor",
            counts: vec![
                (counter!(gnss_gate_rejections), Expected::Exactly(20)),
                (counter!(gnss_declared_faulty), Expected::Exactly(1)),
                (counter!(ignored_from_faulty_sensor), Expected::AtLeast(1)),
            ],
            injection_s: 3.0,
            declared_faulty: [0, 1],
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_gnss(|_, ports| {
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[0] += 100.0;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS step 10 km held",
            injected: "every fix from the fault on offset by 10 km (y)",
            reaction: "dropped as jumps (each a rejection); after 20 the receiver is declared \
                       faulty (once) and ignored",
            counts: vec![
                (counter!(gnss_jump), Expected::Exactly(20)),
                (counter!(gnss_declared_faulty), Expected::Exactly(1)),
                (counter!(ignored_from_faulty_sensor), Expected::AtLeast(1)),
            ],
            injection_s: 3.0,
            declared_faulty: [0, 1],
            criterion: calibration,
            scenario_change: None,
            injector: |_| {
                on_gnss(|_, ports| {
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[1] += 10_000.0;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS slow ramp below the gate",
            injected: "fixes drift 0.05 m/s along ECEF x for 600 s (30 m), then held",
            reaction: "indistinguishable from truth, followed: no check or gate can see it, \
                       so not counted (gate rejections at the natural 0.1 % rate); the \
                       position error follows the ramp, bounded by it",
            counts: vec![
                (counter!(gnss_jump), Expected::Exactly(0)),
                (counter!(gnss_declared_faulty), Expected::Exactly(0)),
            ],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: Criterion::CalibrationAndPositionWithinRamp { ramp_m: 30.0 },
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    if relative < 0 {
                        return;
                    }
                    let elapsed_s = (relative.min(f.frames(600.0)) as f64) / f.rate_hz();
                    if let Some(fix) = gnss(ports) {
                        fix.position_ecef_m[0] += 0.05 * elapsed_s;
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS outage 10 min",
            injected: "no fix for 600 s (across the +x burn)",
            reaction: "navigation on IMU + star sensor; the outage counted once; fixes \
                       accepted again after it",
            counts: vec![(counter!(gnss_outages), Expected::Exactly(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: None,
            injector: |f| {
                Box::new(move |relative, ports| {
                    if (0..f.frames(600.0)).contains(&relative) {
                        ports.gnss.0.clear();
                    }
                })
            },
        },
    ]
}
