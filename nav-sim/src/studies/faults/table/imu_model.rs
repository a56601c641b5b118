//! Fault rows 34–37: IMU errors the 24-state filter does not model (a g-sensitivity, a
//! non-orthogonal accelerometer triad, a misaligned gyro triad), appearing at the fault
//! start. The 24-state filter cannot estimate them; it must not blame a healthy aid for them
//! (no sensor declared faulty), and says so where its innovations show them (the consistency
//! monitor). Where the filter explains an error with its own bias and scale-factor states the
//! innovations stay consistent and no innovation test can see it: the rows say which. Row 37
//! flies the g-sensitivity again with the systematic IMU error states on
//! (`[filter.imu_errors]`): estimated, nothing flagged, the calibration within bound.

use super::*;
use crate::studies::faults::Injector;

/// Gyro g-sensitivity of the g-sensitivity row (rad/s per m/s²): 1 °/h/g on every axis, the
/// independent review's value.
const G_SENSITIVITY_RAD_S_PER_MPS2: f64 = 4.848_137e-6 / 9.806_65;
/// Off-diagonal misalignment of the triad rows (rad): 20 µrad, a navigation-grade triad
/// after factory calibration.
const MISALIGNMENT_RAD: f64 = 2.0e-5;

/// The g-sensitivity row's error, applied to every IMU sample from the fault start.
fn g_sensitivity(sample: &mut ImuSample) {
    for axis in 0..3 {
        sample.delta_angle_rad[axis] +=
            G_SENSITIVITY_RAD_S_PER_MPS2 * sample.delta_velocity_mps[axis];
    }
}

/// The systematic IMU error states the estimated row turns on: the g-sensitivity prior is the
/// injected 1 °/h/g (a specification's value), the triads' misalignment specification that
/// of `nav-sim/scenarios/imu_errors_estimated.toml` (20 µrad per off-diagonal term).
fn estimate_imu_errors(scenario: &mut Scenario) {
    scenario.filter.imu_errors = crate::scenario::FilterImuErrors {
        gyro_misalignment_sigma_rad: 2.0e-5,
        accel_misalignment_sigma_rad: 2.0e-5,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: G_SENSITIVITY_RAD_S_PER_MPS2,
    };
}

/// An injector that passes every IMU sample from the fault start on through `error`.
fn from_the_fault_start(error: fn(&mut ImuSample)) -> Injector {
    Box::new(move |relative, ports| {
        if let (Some(sample), true) = (imu(ports), relative >= 0) {
            error(sample);
        }
    })
}

/// The unmodelled-IMU-error rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let flagged = |counter: Counter| vec![(counter, Expected::AtLeast(1))];
    let nobody_blamed = || {
        vec![(
            counter!(star_declared_faulty + gnss_declared_faulty),
            Expected::Exactly(0),
        )]
    };
    // To the end of the 800 s flight, the count window's margin inside it.
    let to_the_end_s = LONG_FLIGHT_S - FAULT_START_S - 2.0 * COUNT_MARGIN_S;
    vec![
        FaultClass {
            name: "gyro g-sensitivity 1 °/h/g, not modelled",
            injected: "from 0 s on every gyro axis reads g-sensitivity × its specific force: \
                       Δθ_i += 4.94e-7 rad/s per m/s² × Δv_i (1 °/h/g), through the +x and \
                       +y burns",
            reaction: "the star innovations grow during each burn: the consistency monitor \
                       flags them, and the rejections that follow are blamed on the inertial \
                       solution (the attitude and gyro-bias uncertainty widened), not on the \
                       star sensor",
            counts: flagged(counter!(star_inconsistent + gnss_inconsistent)),
            injection_s: to_the_end_s,
            declared_faulty: none,
            criterion: Criterion::CountedOnly,
            scenario_change: None,
            injector: |_| from_the_fault_start(g_sensitivity),
        },
        FaultClass {
            name: "accelerometer triad non-orthogonal 20 µrad, not modelled",
            injected: "from 0 s the accelerometer's y axis leans 20 µrad toward x, its z axis \
                       20 µrad toward x and y: Δv_y += 2e-5 Δv_x, Δv_z += 2e-5 (Δv_x + Δv_y), \
                       through the +x and +y burns",
            reaction: "not seen by the innovations: the filter explains the burns' cross-axis \
                       force with its accelerometer bias and scale factors, so the monitor \
                       stays quiet and the calibration ends off (docs/guide/imu-errors.md); no sensor \
                       declared faulty",
            counts: nobody_blamed(),
            injection_s: to_the_end_s,
            declared_faulty: none,
            criterion: Criterion::CountedOnly,
            scenario_change: None,
            injector: |_| {
                from_the_fault_start(|sample| {
                    let [x, y, z] = sample.delta_velocity_mps;
                    sample.delta_velocity_mps =
                        [x, y + MISALIGNMENT_RAD * x, z + MISALIGNMENT_RAD * (x + y)];
                })
            },
        },
        FaultClass {
            name: "gyro triad misaligned 20 µrad, not modelled",
            injected: "from 0 s every off-diagonal term of the gyro triad is 20 µrad \
                       (Δθ += M Δθ), and a 1800° roll about body x (18 s at 100 °/s) follows \
                       at 0 s",
            reaction: "mostly averaged out by the whole turns (the body-fixed rate error \
                       rotates with the body), the rest absorbed by the gyro bias and scale \
                       factors: the monitor stays quiet here (whole flights: \
                       docs/guide/imu-errors.md); no sensor declared faulty",
            counts: nobody_blamed(),
            injection_s: to_the_end_s,
            declared_faulty: none,
            criterion: Criterion::CountedOnly,
            scenario_change: Some(|scenario| {
                insert_segments(scenario, FAULT_START_S, &[slew(18.5, [100.0, 0.0, 0.0])]);
            }),
            injector: |_| {
                from_the_fault_start(|sample| {
                    let [x, y, z] = sample.delta_angle_rad;
                    let m = MISALIGNMENT_RAD;
                    sample.delta_angle_rad = [x + m * (y + z), y + m * (x + z), z + m * (x + y)];
                })
            },
        },
        FaultClass {
            name: "gyro g-sensitivity 1 °/h/g, estimated",
            injected: "row 34's g-sensitivity, with the systematic IMU error states on \
                       ([filter.imu_errors]; g-sensitivity prior 1 °/h/g 1σ)",
            reaction: "estimated from the burns' specific force: the innovations stay \
                       consistent (no consistency counter), no sensor declared faulty, the \
                       calibration within bound",
            counts: vec![
                (
                    counter!(star_inconsistent + gnss_inconsistent),
                    Expected::Exactly(0),
                ),
                (
                    counter!(star_declared_faulty + gnss_declared_faulty),
                    Expected::Exactly(0),
                ),
            ],
            injection_s: to_the_end_s,
            declared_faulty: none,
            criterion: Criterion::CalibrationWithinBound,
            scenario_change: Some(estimate_imu_errors),
            injector: |_| from_the_fault_start(g_sensitivity),
        },
    ]
}
