//! Each command's accepted and refused cases: what an accepted one changes, that a refused
//! one changes nothing but its count, and the reason it names.

use super::heads_tests::{fly, two_head_computer};
use super::tests::{computer, initial_state, run_frame_with_turned_star};
use super::*;
use nav_core::state::{DYNAMIC_DIMENSION, STATE_DIMENSION};

/// A computer that has fused 400 frames of turned star measurements: calibration estimates
/// off zero and a calibration covariance below the prior, correlated with navigation.
fn calibrated(config: FswConfig) -> NavigationComputer {
    let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
    for sequence in 1..=400_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    computer
}

fn refused(computer: &mut NavigationComputer, command: Command, reason: CommandError) {
    let before = computer.clone();
    let refused_before = computer.operations.commands.refused;
    assert_eq!(computer.command(command), Err(reason));
    assert_eq!(computer.operations.commands.refused, refused_before + 1);
    assert_eq!(computer.filter(), before.filter(), "{command:?}");
    assert_eq!(
        computer.calibration_estimate(),
        before.calibration_estimate()
    );
    assert_eq!(computer.frozen_blocks(), before.frozen_blocks());
    assert_eq!(computer.active_star_head(), before.active_star_head());
}

#[test]
fn a_reset_keeping_the_calibration_keeps_estimates_and_bounds_their_covariance() {
    let mut computer = calibrated(*super::tests::computer().config());
    let estimate = computer.calibration_estimate();
    let p = *computer.filter().covariance();
    let config = computer.config().filter;
    let bound = computer
        .filter()
        .calibration_covariance_for_restart(&config)
        .unwrap();
    let prior = ErrorStateFilter::new(&config).unwrap();
    assert!(p[(9, 9)] < prior.covariance()[(9, 9)]);
    assert!((0..DYNAMIC_DIMENSION).any(|i| p[(i, 12)].abs() > 0.0));
    computer
        .command(Command::ResetFilter {
            keep_calibration: true,
        })
        .unwrap();
    assert_eq!(computer.calibration_estimate(), estimate);
    let kept = computer.filter().calibration_covariance();
    assert_eq!(kept.map(f64::to_bits), bound.map(f64::to_bits));
    let after = computer.filter().covariance();
    for i in 0..STATE_DIMENSION {
        for j in 0..DYNAMIC_DIMENSION {
            let expected = if i < DYNAMIC_DIMENSION {
                prior.covariance()[(i, j)]
            } else {
                0.0
            };
            assert_eq!(after[(i, j)].to_bits(), expected.to_bits(), "P[{i},{j}]");
        }
        // The calibration's variances only grow by the correlation forgotten.
        assert!(after[(i, i)] >= p[(i, i)] || i < DYNAMIC_DIMENSION);
    }
    let commands = computer.operations.commands;
    assert_eq!((commands.accepted, commands.refused), (1, 0));
    assert_eq!(
        computer.health().filter_resets,
        0,
        "a command is not a recovery"
    );
    // Each aid's next measurement is an acquisition (the acquisition gate), as after a
    // recovery.
    assert!(!computer.aids.star.acquired && !computer.aids.gnss.acquired);
}

#[test]
fn a_reset_dropping_the_calibration_is_the_start_up_filter() {
    let mut computer = calibrated(*super::tests::computer().config());
    assert_ne!(
        computer.calibration_estimate(),
        CalibrationEstimate::default()
    );
    computer
        .command(Command::ResetFilter {
            keep_calibration: false,
        })
        .unwrap();
    assert_eq!(
        computer.calibration_estimate(),
        CalibrationEstimate::default()
    );
    let prior = ErrorStateFilter::new(&computer.config().filter).unwrap();
    assert_eq!(computer.filter(), &prior);
    assert_eq!(computer.calibration_table().converged_count(), 0);
}

#[test]
fn a_reset_keeping_the_calibration_in_open_loop_with_optional_states_is_refused() {
    let mut config = *computer().config();
    config.filter.mode = FilterMode::OpenLoop;
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 1e-3,
        accel_misalignment_sigma_rad: 1e-3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-5,
    };
    let mut computer = calibrated(config);
    let keep = Command::ResetFilter {
        keep_calibration: true,
    };
    refused(&mut computer, keep, CommandError::OpenLoopOptionalEstimates);
    // Without optional states, open loop keeps its calibration in the state: accepted.
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel::DISABLED;
    let mut computer = calibrated(config);
    let estimate = computer.calibration_estimate();
    computer.command(keep).unwrap();
    assert_eq!(computer.calibration_estimate(), estimate);
}

#[test]
fn a_commanded_freeze_holds_a_block_until_released_and_a_navigation_block_is_refused() {
    let mut computer = computer();
    computer
        .command(Command::SetBlockFrozen(GYRO_BIAS, true))
        .unwrap();
    assert!(computer.frozen_blocks().contains(GYRO_BIAS));
    for sequence in 1..=400_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    // Frozen through every update and the manager's evaluations (policy: all blocks).
    assert!(computer.frozen_blocks().contains(GYRO_BIAS));
    let gyro_bias = computer.calibration_estimate().gyro_bias_rad_s;
    assert_eq!(gyro_bias.map(f64::to_bits), [0.0f64.to_bits(); 3]);
    assert!(computer.calibration_estimate().star_installation_wxyz[3].abs() > 0.0);
    // A recovery keeps a commanded freeze.
    computer.recover_filter();
    assert!(computer.frozen_blocks().contains(GYRO_BIAS));
    computer
        .command(Command::SetBlockFrozen(GYRO_BIAS, false))
        .unwrap();
    assert!(!computer.frozen_blocks().contains(GYRO_BIAS));
    for sequence in 401..=800_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    assert!(computer.calibration_estimate().gyro_bias_rad_s[2].abs() > 0.0);
    refused(
        &mut computer,
        Command::SetBlockFrozen(ATTITUDE, true),
        CommandError::BlockNotFreezable(ATTITUDE),
    );
    // RestartCalibration releases a commanded freeze too.
    computer
        .command(Command::SetBlockFrozen(ACCEL_BIAS, true))
        .unwrap();
    computer.command(Command::RestartCalibration).unwrap();
    assert!(!computer.frozen_blocks().contains(ACCEL_BIAS));
}

#[test]
fn a_disabled_aid_is_read_and_discarded_and_the_last_aid_cannot_be_disabled() {
    let mut computer = computer();
    let star = AidingSensorId::StarTracker;
    computer
        .command(Command::SetAidEnabled(star, false))
        .unwrap();
    for sequence in 1..=100_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    // Ten star measurements read, none fused: the attitude error stays uncorrected.
    assert_eq!(
        computer.operations.commands.measurements_of_disabled_aid,
        10
    );
    assert_eq!(
        computer.calibration_estimate(),
        CalibrationEstimate::default()
    );
    assert_eq!(
        computer.health().star_outages,
        0,
        "a disabled sensor is still heard"
    );
    refused(
        &mut computer,
        Command::SetAidEnabled(AidingSensorId::Gnss, false),
        CommandError::LastAidingSensor(AidingSensorId::Gnss),
    );
    computer
        .command(Command::SetAidEnabled(star, true))
        .unwrap();
    for sequence in 101..=200_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    assert_eq!(
        computer.operations.commands.measurements_of_disabled_aid,
        10
    );
    assert!(computer.calibration_estimate().star_installation_wxyz[3].abs() > 0.0);
}

#[test]
fn a_star_head_is_selected_only_when_configured_aligned_and_heard() {
    let mut one_head = computer();
    refused(
        &mut one_head,
        Command::SelectStarHead(1),
        CommandError::StarHeadNotConfigured(1),
    );
    let mut computer = two_head_computer();
    fly(&mut computer, 100, &[0, 1]);
    refused(
        &mut computer,
        Command::SelectStarHead(1),
        CommandError::StarHeadNotAligned(1),
    );
    refused(
        &mut computer,
        Command::SelectStarHead(2),
        CommandError::StarHeadNotConfigured(2),
    );
    fly(&mut computer, 1_900, &[0, 1]);
    computer.command(Command::SelectStarHead(0)).unwrap();
    assert_eq!(computer.health().star_head_handovers, 0, "already active");
    computer.command(Command::SelectStarHead(1)).unwrap();
    assert_eq!(computer.active_star_head(), 1);
    assert_eq!(computer.health().star_head_handovers, 1);
    // Head 1 carries the installation: its measurements are accepted.
    let rejections = computer.health().star_gate_rejections;
    fly(&mut computer, 500, &[0, 1]);
    assert_eq!(computer.health().star_gate_rejections, rejections);
    // Head 0 silent past the outage timeout: it may not be selected.
    let timeout_frames = computer.config().timing.outage_timeout_s / 0.002;
    fly(&mut computer, libm::ceil(timeout_frames) as u32 + 50, &[1]);
    refused(
        &mut computer,
        Command::SelectStarHead(0),
        CommandError::StarHeadSilent(0),
    );
}

#[test]
fn every_refusal_names_its_reason() {
    let reasons = [
        CommandError::BlockNotFreezable(ATTITUDE),
        CommandError::OpenLoopOptionalEstimates,
        CommandError::LastAidingSensor(AidingSensorId::Gnss),
        CommandError::StarHeadNotConfigured(2),
        CommandError::StarHeadNotAligned(1),
        CommandError::StarHeadSilent(0),
        CommandError::Filter(NavError::NonFiniteState),
    ];
    let words = [
        "attitude",
        "open loop",
        "Gnss",
        "head 2",
        "aligned",
        "outage",
        "filter",
    ];
    for (reason, word) in reasons.iter().zip(words) {
        let text = std::format!("{reason}");
        assert!(text.contains(word), "{text}");
    }
}
