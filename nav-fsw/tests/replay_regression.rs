//! A change indicator for the whole flight software (PX4-style replay diff): 3,000 frames
//! (6 s at 500 Hz) of a deterministic synthetic flight through `NavigationComputer` — coast,
//! a rotation, thrust, star fixes at 10 Hz, GNSS fixes at 2 Hz arriving 10 ms late, an IMU
//! dropout, a duplicated IMU sample and a 5° star outlier — with every frame's 72-word output
//! record (navigation, fusion, NIS, calibration table, health counters) and the final
//! covariance folded into one FNV-1a digest.
//!
//! The digest pins the outputs bit for bit, so any change to the flight path's arithmetic or
//! logic shows here first (mutation testing relies on it for the scheduler). The test also
//! asserts what the flight must have done (updates accepted, the outlier rejected, the
//! dropout counted), which holds whatever the digest. When an output change is intended,
//! run `NAV_PRINT_DIGEST=1 cargo test -p nav-fsw --test replay_regression -- --nocapture`
//! and update `EXPECTED_DIGEST` in the same commit, saying why.

use nalgebra::{Quaternion, Vector3};
use nav_core::attitude;
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;
use nav_fsw::config::FswConfig;
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::{output_words, FramePorts};
use nav_fsw::scheduler::NavigationComputer;
use nav_fsw::telemetry::FrameFusion;

/// The digest of the run (see the module docs to update it).
const EXPECTED_DIGEST: u64 = 0xbf7a_1234_4897_59c2;

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

#[test]
fn the_flight_outputs_match_the_recorded_digest() {
    let site = LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        epoch_s: 0.0,
    };
    let initial = NavigationState {
        attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
        time_s: 600.0,
    };
    let mut computer = NavigationComputer::new(FswConfig::paper_defaults(site), initial).unwrap();
    // The star sensor sees the attitude turned by a fixed small offset (an installation error).
    let star_offset = attitude::exp_rotation_vector(&Vector3::new(2e-4, -1e-4, 3e-4));
    let outlier = attitude::exp_rotation_vector(&Vector3::new(5f64.to_radians(), 0.0, 0.0));
    let mut digest = 0xcbf2_9ce4_8422_2325_u64;
    let mut gnss_epoch = None;
    let (mut star_accepted, mut star_rejected, mut gnss_accepted) = (0, 0, 0);
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
            ports.imu.0 = Some(ImuSample {
                sequence,
                time_s,
                delta_angle_rad: rate.map(|w| w * PERIOD_S),
                delta_velocity_mps: force.map(|f| f * PERIOD_S),
            });
        }
        let navigation = computer.navigation();
        if frame % 50 == 0 {
            let seen = attitude::product(&true_attitude, &star_offset);
            let q = if frame == 1_500 {
                attitude::product(&seen, &outlier)
            } else {
                seen
            };
            ports
                .star
                .0
                .push_back(StarMeasurement {
                    time_tag_s: navigation.time_s,
                    attitude_wxyz: [q.w, q.i, q.j, q.k],
                })
                .unwrap();
        }
        // GNSS: the solution of 5 frames ago ± 1 m, delivered 10 ms late.
        if frame % 250 == 245 {
            gnss_epoch = Some((navigation.time_s, navigation.position_m));
        }
        if frame % 250 == 0 {
            if let Some((tag, position)) = gnss_epoch.take() {
                let sign = if frame % 500 == 0 { 1.0 } else { -1.0 };
                let fix = position + Vector3::new(1.0, -0.5, 0.5) * sign;
                let ecef = computer
                    .launch_frame()
                    .launch_inertial_to_ecef(&fix, tag)
                    .unwrap();
                ports
                    .gnss
                    .0
                    .push_back(GnssFix {
                        time_tag_s: tag,
                        position_ecef_m: [ecef.x, ecef.y, ecef.z],
                    })
                    .unwrap();
            }
        }
        let telemetry = ports.run(&mut computer);
        if !dropout {
            let turn = attitude::exp_rotation_vector(&(Vector3::from(rate) * PERIOD_S));
            true_attitude = attitude::product(&true_attitude, &turn);
        }
        match telemetry.fusion {
            FrameFusion::StarAccepted => star_accepted += 1,
            FrameFusion::StarRejected => star_rejected += 1,
            FrameFusion::GnssAccepted => gnss_accepted += 1,
            FrameFusion::GnssRejected | FrameFusion::None => {}
        }
        for word in output_words(&telemetry, &computer, 0) {
            digest = fold(digest, word);
        }
    }
    for value in computer.filter().covariance().iter() {
        digest = fold(digest, value.to_bits());
    }
    let health = computer.health();
    // What the flight must have done, whatever the digest.
    // 60 star fixes; the last frame's waits behind that frame's (older) GNSS fix: one fusion
    // per frame, by construction.
    assert_eq!(
        star_accepted + star_rejected,
        59,
        "every star fix fused or rejected"
    );
    assert_eq!(computer.health().measurement_overflow, 0);
    assert_eq!(star_rejected, 1, "only the 5° outlier is rejected");
    assert_eq!(health.star_gate_rejections, 1);
    assert_eq!(gnss_accepted, 12, "every late GNSS fix accepted");
    assert_eq!(health.imu_missing, 5, "the dropout counted frame by frame");
    assert_eq!(health.imu_duplicate, 1, "the repeated sample counted");
    assert_eq!(health.filter_resets, 0);
    if std::env::var_os("NAV_PRINT_DIGEST").is_some() {
        println!("digest {digest:#018x}");
    }
    assert_eq!(
        digest, EXPECTED_DIGEST,
        "the flight outputs changed (digest {digest:#018x}); if intended, update EXPECTED_DIGEST"
    );
}
