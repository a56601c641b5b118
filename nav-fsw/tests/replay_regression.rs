//! A change indicator for the whole flight software (PX4-style replay diff): 3,000 frames
//! (6 s at 500 Hz) of a deterministic synthetic flight through `NavigationComputer` — coast,
//! a rotation, thrust, star fixes at 10 Hz, GNSS fixes at 2 Hz arriving 10 ms late (one
//! between two frames), an IMU dropout, a duplicated IMU sample, a 5° star outlier, three
//! outliers in a row that get the star sensor declared faulty and the ground command that
//! clears it, and a frame-cost report — with every frame's output record (navigation,
//! fusion, NIS, calibration table, health counters, the optional state blocks' words) and the
//! final covariance folded into one FNV-1a digest.
//!
//! The digest pins the outputs bit for bit, so any change to the flight path's arithmetic or
//! logic shows here first (mutation testing relies on it for the scheduler). The test also
//! asserts what the flight must have done (updates accepted, the outlier rejected, the
//! dropout counted), which holds whatever the digest. When an output change is intended,
//! run `NAV_PRINT_DIGEST=1 cargo test -p nav-fsw --test replay_regression -- --nocapture`
//! and update `EXPECTED_DIGEST` in the same commit, saying why.

use nalgebra::{Quaternion, Vector3};
use nav_core::attitude;
use nav_core::discretise::CovarianceMatrix;
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;
use nav_fsw::config::{FrameLoad, FswConfig};
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::{output_words, AssemblyCounts, FramePorts};
use nav_fsw::scheduler::{Command, FilterArithmetic, NavigationComputer};
use nav_fsw::sensor_frames::SensorFrames;
use nav_fsw::telemetry::FrameFusion;

/// The digest of the run (see the module docs to update it); the same with and without the
/// feature `gravity-field`: this flight (point mass + `J2`, no allowance) has no allowance to
/// check, a configuration warning rather than an episode of `gravity_allowance_short`.
const EXPECTED_DIGEST: u64 = 0x61ba_08bd_70e3_702f;

const FRAMES: u32 = 3_000;
const PERIOD_S: f64 = 0.002;

/// FNV-1a over 64-bit words.
fn fold(digest: u64, word: u64) -> u64 {
    word.to_le_bytes().iter().fold(digest, |hash, byte| {
        (hash ^ u64::from(*byte)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Body rate (rad/s) and specific force (m/s²) of the synthetic flight at `frame`.
fn motion(frame: u32) -> ([f64; 3], [f64; 3]) {
    match frame {
        // Rotation about z then x at 3 °/s.
        1_000..=1_499 => ([0.0, 0.0, 3f64.to_radians()], [0.0; 3]),
        1_500..=1_999 => ([3f64.to_radians(), 0.0, 0.0], [0.0; 3]),
        // Thrust along x with a small lateral part.
        2_000..=2_599 => ([0.0; 3], [2.0, 0.1, -0.05]),
        _ => ([0.0; 3], [0.0; 3]),
    }
}

/// What one flight produced.
struct Flight {
    digest: u64,
    star_accepted: u32,
    star_rejected: u32,
    star_accepted_after_clearing: u32,
    gnss_accepted: u32,
    overruns_reported: u32,
    computer: NavigationComputer,
}

/// Star frames whose fix is 5° off: one alone, then three in a row (the sensor is declared
/// faulty after 3 consecutive rejections in this test's configuration).
const STAR_OUTLIER_FRAMES: [u32; 4] = [1_500, 2_500, 2_550, 2_600];
/// The frame of the `ClearSensorFaults` command.
const CLEAR_FRAME: u32 = 2_720;
/// The frame whose GNSS fix is tagged between two frames (1.1 ms before the frame's time).
const BETWEEN_FRAMES_FIX: u32 = 1_610;
/// From this frame on the star sensor reports `−q` (the same attitude).
const SIGN_CHANGE_FRAME: u32 = 2_800;
/// The star frame whose fix is tagged 0.5 ms after the frame's own solution.
const SLIGHTLY_FUTURE_FIX: u32 = 1_400;
/// The frame carrying a star fix 0.5 s old (beyond the 0.1 s largest latency).
const STALE_FIX: u32 = 1_210;
/// The frame carrying a GNSS fix 0.5 s in the future.
const FUTURE_FIX: u32 = 1_310;
/// The star frame whose fix is tagged 0.3 ms before the end of the frame: between two frames
/// (interpolated, and referred over its 0.3 ms latency).
const LATE_BY_A_FRACTION_FIX: u32 = 1_650;
/// The frame carrying a star fix tagged before the first frame (within the largest latency,
/// but older than anything in the history).
const BEFORE_HISTORY_FIX: u32 = 5;
/// The frame carrying a GNSS fix 1 m inside the jump limit (gated by its NIS, not a jump).
const NEAR_JUMP_FIX: u32 = 2_125;
/// GNSS antenna lever arm in body axes (m).
const LEVER_ARM_M: [f64; 3] = [0.5, 1.0, -0.2];
/// Frame-cost budget (arbitrary units) and the cost reported for frame `n`: `n mod 1,500`.
const COST_BUDGET: u32 = 1_400;

/// The sensors' frames: GCRF turned 120° from the launch-inertial frame about (1, 1, 1), and
/// a launch epoch 603 s before a GPS week roll, so the star and GNSS conversions are in the
/// digest and the GNSS tags cross a week.
const SENSOR_FRAMES: SensorFrames = SensorFrames {
    gcrf_to_launch_inertial_wxyz: [0.5, 0.5, 0.5, 0.5],
    launch_epoch_gps_week: 2_391,
    launch_epoch_gps_seconds_of_week: 604_197.0,
};

/// A star-tracker measurement of `q_is`: its attitude relative to GCRF, `q_ig* ⊗ q_is`.
fn star_in_gcrf(q_is: &Quaternion<f64>) -> [f64; 4] {
    let [w, x, y, z] = SENSOR_FRAMES.gcrf_to_launch_inertial_wxyz;
    let q = Quaternion::new(w, x, y, z).conjugate() * q_is;
    [q.w, q.i, q.j, q.k]
}

/// A GNSS fix at navigation time `time_s`, tagged in GPS time.
fn gnss_fix(time_s: f64, ecef: &Vector3<f64>) -> GnssFix {
    let (gps_week, gps_seconds_of_week) = SENSOR_FRAMES.gps_time(time_s).unwrap();
    GnssFix::new(gps_week, gps_seconds_of_week, [ecef.x, ecef.y, ecef.z])
}

fn fly(arithmetic: FilterArithmetic, propagation_interval_frames: u32) -> Flight {
    fly_with_load(
        arithmetic,
        propagation_interval_frames,
        FrameLoad::FuseOrPropagate,
    )
}

fn fly_with_load(
    arithmetic: FilterArithmetic,
    propagation_interval_frames: u32,
    frame_load: FrameLoad,
) -> Flight {
    let site = LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    };
    let initial = NavigationState {
        attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
        time_s: 600.0,
    };
    let mut config = FswConfig::paper_defaults(site, SENSOR_FRAMES);
    config.timing.rejections_to_declare_faulty = 3;
    config.covariance.propagation_interval_frames = propagation_interval_frames;
    config.covariance.frame_load = frame_load;
    // The antenna is off the body origin: the GNSS prediction adds the rotated lever arm.
    config.gnss.lever_arm_body_m = LEVER_ARM_M;
    // A floor the installation error's 1σ reaches during the flight: covariance protection at
    // work (clamps counted, the filter never reset).
    config.covariance.sigma_floor.star_installation_rad =
        0.5 * config.filter.initial.star_installation_rad;
    let mut computer = NavigationComputer::new(config, initial).unwrap();
    computer.set_arithmetic(arithmetic);
    computer.set_frame_budget(COST_BUDGET);
    // The star sensor sees the attitude turned by a fixed small offset (an installation error).
    let star_offset = attitude::exp_rotation_vector(&Vector3::new(2e-4, -1e-4, 3e-4));
    let outlier = attitude::exp_rotation_vector(&Vector3::new(5f64.to_radians(), 0.0, 0.0));
    let mut digest = 0xcbf2_9ce4_8422_2325_u64;
    let mut gnss_epoch = None;
    let (mut star_accepted, mut star_rejected, mut gnss_accepted) = (0, 0, 0);
    let (mut star_accepted_after_clearing, mut overruns_reported) = (0, 0);
    let mut sequence = 0_u32;
    // The true attitude, from the body rates alone (the star sensor sees it, not the filter's
    // estimate, so the closed-loop corrections do not move the measurements).
    let mut true_attitude = initial.attitude;
    for frame in 1..=FRAMES {
        let time_s = 600.0 + PERIOD_S * f64::from(frame);
        let (rate, force) = motion(frame);
        let mut ports = FramePorts::default();
        // A 5-frame dropout, then the last sample delivered twice.
        let dropout = (500..505).contains(&frame);
        if !dropout {
            if frame != 801 {
                sequence += 1;
            }
            ports.imu.0 = Some(ImuSample::new(
                sequence,
                time_s,
                rate.map(|w| w * PERIOD_S),
                force.map(|f| f * PERIOD_S),
            ));
        }
        let navigation = computer.navigation();
        if frame % 50 == 0 {
            let seen = attitude::product(&true_attitude, &star_offset);
            let q = if STAR_OUTLIER_FRAMES.contains(&frame) {
                attitude::product(&seen, &outlier)
            } else {
                seen
            };
            // From frame 2,800 on the sensor reports the other sign of the same attitude
            // (counted once, as one change of the sensor's sign convention).
            let q = if frame >= SIGN_CHANGE_FRAME { -q } else { q };
            // One fix a little after this frame's own time of validity: within the future
            // tolerance, fused with the newest solution.
            let tag = match frame {
                SLIGHTLY_FUTURE_FIX => navigation.time_s + PERIOD_S + 0.0005,
                LATE_BY_A_FRACTION_FIX => navigation.time_s + PERIOD_S - 0.0003,
                _ => navigation.time_s,
            };
            ports
                .star
                .0
                .push_back(StarMeasurement::new(tag, star_in_gcrf(&q), 0))
                .unwrap();
        }
        // A fix older than the largest latency (refused as stale) and one far in the future.
        if frame == BEFORE_HISTORY_FIX {
            ports
                .star
                .0
                .push_back(StarMeasurement::new(600.0 - 0.05, [1.0, 0.0, 0.0, 0.0], 0))
                .unwrap();
        }
        if frame == STALE_FIX {
            ports
                .star
                .0
                .push_back(StarMeasurement::new(
                    navigation.time_s - 0.5,
                    [1.0, 0.0, 0.0, 0.0],
                    0,
                ))
                .unwrap();
        }
        if frame == FUTURE_FIX {
            let ecef = computer
                .launch_frame()
                .launch_inertial_to_ecef(&navigation.position_m, navigation.time_s)
                .unwrap();
            ports
                .gnss
                .0
                .push_back(gnss_fix(navigation.time_s + 0.5, &ecef))
                .unwrap();
        }
        // GNSS: the solution of 5 frames ago ± 1 m, delivered 10 ms late; one fix tagged
        // between two frames (the solution there is interpolated).
        let lever_arm = Vector3::from(LEVER_ARM_M);
        let antenna =
            |position: Vector3<f64>| position + attitude::rotate(&navigation.attitude, &lever_arm);
        if frame % 250 == 245 {
            gnss_epoch = Some((navigation.time_s, antenna(navigation.position_m)));
        }
        if frame == BETWEEN_FRAMES_FIX {
            let tag = navigation.time_s - 0.0011;
            let velocity = navigation.velocity_mps;
            gnss_epoch = Some((tag, antenna(navigation.position_m - velocity * 0.0011)));
        }
        if frame % 250 == 0 || frame == BETWEEN_FRAMES_FIX + 2 {
            if let Some((tag, position)) = gnss_epoch.take() {
                let sign = if frame % 500 == 0 { 1.0 } else { -1.0 };
                let fix = position + Vector3::new(1.0, -0.5, 0.5) * sign;
                let ecef = computer
                    .launch_frame()
                    .launch_inertial_to_ecef(&fix, tag)
                    .unwrap();
                ports.gnss.0.push_back(gnss_fix(tag, &ecef)).unwrap();
            }
        }
        // A fix just inside the jump limit from the predicted antenna position, along the
        // lever arm: not a jump, but far outside the innovation gate.
        if frame == NEAR_JUMP_FIX {
            let offset = attitude::rotate(&navigation.attitude, &lever_arm);
            let limit = computer.config().gnss.max_jump_m;
            let fix = antenna(navigation.position_m) + offset * ((limit - 1.0) / offset.norm());
            let ecef = computer
                .launch_frame()
                .launch_inertial_to_ecef(&fix, navigation.time_s)
                .unwrap();
            ports
                .gnss
                .0
                .push_back(gnss_fix(navigation.time_s, &ecef))
                .unwrap();
        }
        if frame == CLEAR_FRAME {
            computer.command(Command::ClearSensorFaults).unwrap();
        }
        let telemetry = ports.run(&mut computer);
        let cost = frame % 1_500;
        computer.report_frame_cost(cost);
        overruns_reported += u32::from(cost > COST_BUDGET);
        if !dropout {
            let turn = attitude::exp_rotation_vector(&(Vector3::from(rate) * PERIOD_S));
            true_attitude = attitude::product(&true_attitude, &turn);
        }
        match telemetry.fusion {
            FrameFusion::StarAccepted => {
                star_accepted += 1;
                star_accepted_after_clearing += u32::from(frame > CLEAR_FRAME);
            }
            FrameFusion::StarRejected => star_rejected += 1,
            FrameFusion::GnssAccepted => gnss_accepted += 1,
            FrameFusion::GnssRejected
            | FrameFusion::GnssVelocityAccepted
            | FrameFusion::GnssVelocityRejected
            | FrameFusion::None => {}
        }
        for word in output_words(&telemetry, &computer, &AssemblyCounts::default()) {
            digest = fold(digest, word);
        }
    }
    for value in computer.filter().covariance().iter() {
        digest = fold(digest, value.to_bits());
    }
    Flight {
        digest,
        star_accepted,
        star_rejected,
        star_accepted_after_clearing,
        gnss_accepted,
        overruns_reported,
        computer,
    }
}

#[test]
fn the_flight_outputs_match_the_recorded_digest() {
    let flight = fly(FilterArithmetic::Structured, 1);
    let computer = &flight.computer;
    let health = computer.health();
    // What the flight must have done, whatever the digest. 60 star fixes: the last frame's
    // waits behind that frame's (older) GNSS fix (one fusion per frame, by construction); the
    // two while the sensor is declared faulty are ignored (reported as rejected).
    assert_eq!(health.ignored_from_faulty_sensor, 2);
    assert_eq!(flight.star_accepted + flight.star_rejected, 59);
    assert_eq!(
        flight.star_rejected,
        4 + 2,
        "the four outliers and the two ignored fixes"
    );
    assert_eq!(
        health.star_gate_rejections, 4,
        "only the outliers are gated"
    );
    assert_eq!(health.star_declared_faulty, 1, "three outliers in a row");
    assert_eq!(
        flight.star_accepted_after_clearing, 5,
        "the command cleared the fault"
    );
    assert_eq!(flight.gnss_accepted, 13, "every late GNSS fix accepted");
    assert_eq!(health.imu_missing, 5, "the dropout counted frame by frame");
    assert_eq!(health.imu_duplicate, 1, "the repeated sample counted");
    assert_eq!(
        health.imu_held_frames, 6,
        "each held sample grows the covariance"
    );
    assert_eq!(health.filter_resets, 0, "clamps never reset the filter");
    assert!(
        health.covariance_clamps > 0,
        "the installation floor was reached"
    );
    assert_eq!(
        health.star_sign_flip, 1,
        "one change of sign convention, counted once"
    );
    assert_eq!(
        health.measurement_stale, 2,
        "one too old, one older than the history"
    );
    assert_eq!(health.measurement_future, 1);
    assert_eq!(health.measurement_overflow, 0);
    assert_eq!(health.gnss_jump, 0, "the near-limit fix is not a jump");
    assert_eq!(health.gnss_gate_rejections, 1, "it is gated instead");
    assert!(
        computer.configuration_warnings().gravity_without_allowance,
        "no allowance: a start-up warning"
    );
    assert_eq!(health.gravity_allowance_short, 0, "not a flight event");
    assert_eq!(computer.worst_frame_cost(), 1_499);
    assert_eq!(health.frame_overruns, flight.overruns_reported);
    assert!(flight.overruns_reported > 0);
    let digest = flight.digest;
    if std::env::var_os("NAV_PRINT_DIGEST").is_some() {
        println!("digest {digest:#018x}");
    }
    assert_eq!(
        digest, EXPECTED_DIGEST,
        "the flight outputs changed (digest {digest:#018x}); if intended, update EXPECTED_DIGEST"
    );
}

/// The dense reference arithmetic flies the same flight to round-off: same decisions, the
/// same solution and covariance within relative 1e-9.
#[test]
fn the_dense_reference_flies_the_same_flight() {
    let structured = fly(FilterArithmetic::Structured, 1);
    let dense = fly(FilterArithmetic::DenseReference, 1);
    assert_eq!(structured.star_accepted, dense.star_accepted);
    assert_eq!(structured.gnss_accepted, dense.gnss_accepted);
    let (a, b) = (
        structured.computer.navigation(),
        dense.computer.navigation(),
    );
    assert!((a.position_m - b.position_m).norm() < 1e-6);
    assert!((a.attitude.coords - b.attitude.coords).norm() < 1e-12);
    let (p, q) = (
        structured.computer.filter().covariance(),
        dense.computer.filter().covariance(),
    );
    assert!(
        (p - q).norm() <= 1e-9 * p.norm(),
        "{}",
        (p - q).norm() / p.norm()
    );
    // ... and it is a different arithmetic: the round-off differs somewhere.
    assert_ne!(p.map(f64::to_bits), q.map(f64::to_bits));
    let (x, y) = (
        structured.computer.calibration_estimate(),
        dense.computer.calibration_estimate(),
    );
    for (u, v) in x.gyro_bias_rad_s.iter().zip(y.gyro_bias_rad_s) {
        assert!((u - v).abs() < 1e-12);
    }
}

/// Largest difference of an element of two covariances relative to its two standard
/// deviations in `p` (the correlation scale: every state counts, whatever its unit).
fn largest_scaled_difference(p: &CovarianceMatrix, q: &CovarianceMatrix) -> f64 {
    let mut largest = 0.0_f64;
    for i in 0..24 {
        for j in 0..24 {
            let scale = (p[(i, i)] * p[(j, j)]).sqrt();
            largest = largest.max((p[(i, j)] - q[(i, j)]).abs() / scale);
        }
    }
    largest
}

/// Propagating the covariance every 5 frames, about the interval's mean rates and forces,
/// gives nearly the covariance of propagating every frame (the motion is piecewise constant
/// here, so only the discretisation of the longer step differs): every element within 5 %
/// of its two standard deviations (measured 2.3 %; the sums instead of the means give 10 %
/// to 390 %).
#[test]
fn a_longer_propagation_interval_uses_the_mean_motion() {
    let every_frame = fly(FilterArithmetic::Structured, 1);
    let every_fifth = fly(FilterArithmetic::Structured, 5);
    let (p, q) = (
        every_frame.computer.filter().covariance(),
        every_fifth.computer.filter().covariance(),
    );
    let largest = largest_scaled_difference(p, q);
    assert!(largest < 0.05, "{largest:e}");
    // The gyro scale factors' variances, which the measured rates alone drive (they enter
    // only the scale-factor columns): within 1e-6 (measured ~2e-9; the sums instead of the
    // means of the measured rates give ~1e-4).
    for i in 18..21 {
        let relative = (p[(i, i)] - q[(i, i)]).abs() / p[(i, i)];
        assert!(relative < 1e-6, "gyro scale factor {i}: {relative:e}");
    }
}

/// The two frame loads fly the same flight: the same decisions, and the covariance and the
/// solution of fusing against the covariance of the frame before (`FuseOrPropagate`, the
/// propagation over two frames after) close to those of propagating first.
#[test]
fn the_two_frame_loads_fly_the_same_flight() {
    let split = fly(FilterArithmetic::Structured, 1);
    let both = fly_with_load(
        FilterArithmetic::Structured,
        1,
        FrameLoad::PropagateThenFuse,
    );
    assert_eq!(split.star_accepted, both.star_accepted);
    assert_eq!(split.star_rejected, both.star_rejected);
    assert_eq!(split.gnss_accepted, both.gnss_accepted);
    let (p, q) = (
        split.computer.filter().covariance(),
        both.computer.filter().covariance(),
    );
    // Measured 0.74 %: each update meets the covariance one frame less grown.
    let largest = largest_scaled_difference(p, q);
    assert!(largest < 0.02, "{largest:e}");
    let (a, b) = (split.computer.navigation(), both.computer.navigation());
    let position_m = (a.position_m - b.position_m).norm();
    let angle_rad = 2.0 * (a.attitude.conjugate() * b.attitude).imag().norm();
    // Measured 7.7e-8 m and 8.9e-9 rad against 1σ of 2.7 m and 4.3e-3 rad.
    assert!(position_m < 1e-3 * p[(3, 3)].sqrt(), "{position_m:e} m");
    assert!(
        angle_rad < 1e-3 * 2.0 * p[(0, 0)].sqrt(),
        "{angle_rad:e} rad"
    );
}
