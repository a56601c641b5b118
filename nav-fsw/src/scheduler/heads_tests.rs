//! Two tracker heads on a vehicle that does not turn: the pairs align the second head, an
//! outage of the first hands the installation over, the first head's return hands it back.

use super::tests;
use super::*;
use crate::config::StarHeadConfig;
use crate::sensor_frames::SensorFrames;

const ARCSEC_RAD: f64 = 4.848_136_811_095_36e-6;

/// Head 1 with its boresight 90° from head 0's (turned about body x), 5″ across and 35″
/// about the boresight on both heads, aligned after 20 pairs.
pub(super) fn two_head_computer() -> NavigationComputer {
    let mut config = FswConfig::paper_defaults(tests::site(), SensorFrames::ALIGNED);
    config.star.noise_rad = 5.0 * ARCSEC_RAD;
    config.star.roll_noise_rad = 35.0 * ARCSEC_RAD;
    let half = core::f64::consts::FRAC_PI_4;
    config.star.second_head = Some(StarHeadConfig {
        mounting_wxyz: [libm::cos(half), libm::sin(half), 0.0, 0.0],
        noise_rad: 5.0 * ARCSEC_RAD,
        roll_noise_rad: 35.0 * ARCSEC_RAD,
        alignment_prior_sigma_rad: 100.0 * ARCSEC_RAD,
        pair_gate_nis: crate::config::GATE_NIS,
        pairs_before_hand_over: 20,
    });
    NavigationComputer::new(config, tests::initial_state()).unwrap()
}

/// Head 1's true installation error: 40″ about its x and 20″ about its z.
fn head_one_misalignment() -> Quaternion<f64> {
    attitude::exp_rotation_vector(&Vector3::new(40.0 * ARCSEC_RAD, 0.0, 20.0 * ARCSEC_RAD))
}

/// Flies `frames` frames; every tenth frame each head in `heads` measures (noise-free) the
/// constant attitude through its mounting (head 1 with [`head_one_misalignment`]).
pub(super) fn fly(computer: &mut NavigationComputer, frames: u32, heads: &[u8]) {
    fly_with_steps(computer, frames, heads, &[]);
}

/// A step fault: 120″ about the sensor's x axis, far outside the gates.
fn step() -> Quaternion<f64> {
    attitude::exp_rotation_vector(&Vector3::new(120.0 * ARCSEC_RAD, 0.0, 0.0))
}

/// As [`fly`], the heads in `stepped` turned by [`step`].
fn fly_with_steps(computer: &mut NavigationComputer, frames: u32, heads: &[u8], stepped: &[u8]) {
    let first = computer.frame.wrapping_add(1);
    for sequence in first..first + frames {
        let mut ports = crate::replay::FramePorts::default();
        let time_s = computer.navigation().time_s + 0.002;
        ports.imu.0 = Some(crate::ports::ImuSample {
            sequence,
            time_s,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        });
        if sequence % 10 == 0 {
            for head in heads {
                let (mounting, _) = computer.head_mounting_and_noise(*head);
                let mut sensor = if *head == 1 {
                    attitude::product(&mounting, &head_one_misalignment())
                } else {
                    mounting
                };
                if stepped.contains(head) {
                    sensor = attitude::product(&sensor, &step());
                }
                let q = attitude::product(&computer.navigation().attitude, &sensor);
                let measurement = crate::ports::StarMeasurement {
                    time_tag_s: computer.navigation().time_s,
                    sensor_to_gcrf_wxyz: [q.w, q.i, q.j, q.k],
                    head: *head,
                };
                ports.star.0.push_back(measurement).unwrap();
            }
        }
        ports.run(computer);
    }
}

#[test]
fn the_pairs_align_the_second_head_and_an_outage_hands_the_installation_over_and_back() {
    let mut computer = two_head_computer();
    fly(&mut computer, 2_000, &[0, 1]);
    let health = *computer.health();
    assert!(computer.heads.pairs_accepted() >= 150, "{health:?}");
    assert_eq!(health.star_pair_rejections, 0);
    assert_eq!(health.star_head_handovers, 0);
    assert_eq!(computer.active_star_head(), 0);
    // The second head's alignment to the first: its mounting turned by its misalignment.
    let (mounting, _) = computer.head_mounting_and_noise(1);
    let truth = attitude::product(&mounting, &head_one_misalignment());
    let alignment = computer.heads.alignment.unwrap();
    let error = attitude::product(&attitude::conjugate(alignment.estimate()), &truth);
    assert!(error.imag().norm() < 2.0 * ARCSEC_RAD, "{error:?}");

    // Head 0 falls silent: after the outage timeout head 1 carries the installation, and its
    // measurements are accepted with the installation handed over.
    let rejections_before = health.star_gate_rejections;
    fly(&mut computer, 3_000, &[1]);
    let health = *computer.health();
    assert_eq!(health.star_head_handovers, 1, "{health:?}");
    assert_eq!(computer.active_star_head(), 1);
    assert_eq!(health.star_gate_rejections, rejections_before);
    let expected = attitude::product(&head_one_misalignment(), &Quaternion::identity());
    let installation = computer.installation_estimate();
    let off = attitude::product(&attitude::conjugate(&installation), &expected);
    // The filter's installation estimate is head 1's misalignment (both heads noise-free,
    // head 0 mounted without error).
    assert!(off.imag().norm() < 3.0 * ARCSEC_RAD, "{installation:?}");

    // Head 0 returns: the first pair hands the installation back to it.
    fly(&mut computer, 500, &[0, 1]);
    let health = *computer.health();
    assert_eq!(health.star_head_handovers, 2, "{health:?}");
    assert_eq!(computer.active_star_head(), 0);
    assert_eq!(health.star_gate_rejections, rejections_before);
    assert_eq!(health.star_declared_faulty, 0);
}

#[test]
fn a_head_the_configuration_lacks_is_counted_and_ignored() {
    let mut computer = tests::computer();
    let mut ports = crate::replay::FramePorts::default();
    let measurement = crate::ports::StarMeasurement {
        time_tag_s: computer.navigation().time_s,
        sensor_to_gcrf_wxyz: [1.0, 0.0, 0.0, 0.0],
        head: 1,
    };
    ports.star.0.push_back(measurement).unwrap();
    ports.imu.0 = Some(crate::ports::ImuSample {
        sequence: 1,
        time_s: computer.navigation().time_s + 0.002,
        delta_angle_rad: [0.0; 3],
        delta_velocity_mps: [0.0; 3],
    });
    ports.run(&mut computer);
    assert_eq!(computer.health().star_unknown_head, 1);
    assert_eq!(computer.queued_measurements(), 0);
}

/// A computer whose pairs have aligned the second head (2,000 frames, 200 pairs).
fn aligned_computer() -> NavigationComputer {
    let mut computer = two_head_computer();
    fly(&mut computer, 2_000, &[0, 1]);
    assert!(computer.heads.pairs_accepted() >= 150);
    computer
}

#[test]
fn an_outage_does_not_hand_the_installation_to_a_head_that_disagrees() {
    let mut computer = aligned_computer();
    // Head 1 steps: its pairs are rejected, head 0 (fused) is not blamed.
    fly_with_steps(&mut computer, 500, &[0, 1], &[1]);
    let health = *computer.health();
    assert!(health.star_pair_rejections >= 40, "{health:?}");
    assert_eq!(health.star_declared_faulty, 0);
    // Head 0 falls silent: the outage is counted, the block stays with head 0.
    fly_with_steps(&mut computer, 3_000, &[1], &[1]);
    let health = *computer.health();
    assert_eq!(health.star_outages, 1, "{health:?}");
    assert_eq!(health.star_head_handovers, 0);
    assert_eq!(computer.active_star_head(), 0);
    // Head 0 returns and is fused again.
    assert!(!computer.aids.star.acquired);
    fly_with_steps(&mut computer, 500, &[0, 1], &[1]);
    assert!(computer.aids.star.acquired && !computer.aids.star.faulty);
    assert_eq!(computer.active_star_head(), 0);
    assert_eq!(computer.health().star_declared_faulty, 0);
}

#[test]
fn a_faulty_head_hands_over_and_takes_the_block_back_only_once_it_agrees_again() {
    let mut computer = aligned_computer();
    // Head 0 steps: declared faulty, the block goes to head 1.
    fly_with_steps(&mut computer, 1_000, &[0, 1], &[0]);
    let health = *computer.health();
    assert_eq!(health.star_declared_faulty, 1, "{health:?}");
    assert_eq!(health.star_head_handovers, 1);
    assert_eq!(computer.active_star_head(), 1);
    // Still stepped: its pairs disagree and it does not take the block back.
    fly_with_steps(&mut computer, 1_000, &[0, 1], &[0]);
    assert_eq!(computer.health().star_head_handovers, 1);
    assert_eq!(computer.active_star_head(), 1);
    // The step ends: after 20 agreeing pairs (the configuration's) head 0 has the block back.
    fly(&mut computer, 150, &[0, 1]);
    assert_eq!(computer.active_star_head(), 1, "back after one pair");
    fly(&mut computer, 100, &[0, 1]);
    let health = *computer.health();
    assert_eq!(health.star_head_handovers, 2, "{health:?}");
    assert_eq!(computer.active_star_head(), 0);
    assert_eq!(health.star_declared_faulty, 1);
}

#[test]
fn a_carrying_head_declared_faulty_hands_the_block_back_when_the_first_returns() {
    let mut computer = aligned_computer();
    fly(&mut computer, 3_000, &[1]);
    assert_eq!(computer.active_star_head(), 1);
    // Head 1 steps while it carries the block and head 0 is silent: declared faulty.
    fly_with_steps(&mut computer, 1_000, &[1], &[1]);
    let health = *computer.health();
    assert_eq!(health.star_declared_faulty, 1, "{health:?}");
    assert_eq!(computer.active_star_head(), 1);
    // Head 0 returns: its first pair hands the block back although the pair disagrees,
    // and the filter fuses head 0 again.
    fly_with_steps(&mut computer, 500, &[0, 1], &[1]);
    let health = *computer.health();
    assert_eq!(health.star_head_handovers, 2, "{health:?}");
    assert_eq!(computer.active_star_head(), 0);
    assert!(computer.aids.star.acquired && !computer.aids.star.faulty);
}
