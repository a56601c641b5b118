use super::aid::STAR_FITTED_BLOCKS;
use super::*;
use crate::sensor_frames::SensorFrames;
use nav_core::frames::LaunchSite;

pub(super) fn site() -> LaunchSite {
    LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    }
}

pub(super) fn initial_state() -> NavigationState {
    NavigationState {
        attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
        time_s: 600.0,
    }
}

pub(super) fn computer() -> NavigationComputer {
    NavigationComputer::new(
        FswConfig::paper_defaults(site(), SensorFrames::ALIGNED),
        initial_state(),
    )
    .unwrap()
}

/// A snapshot read back equals the eager correction of the history: every correction
/// fed back in its frame or later, in feedback order (rotations that do not commute),
/// none from before it, across the frame counter's wrap.
#[test]
fn a_snapshot_takes_the_corrections_since_its_frame_in_order() {
    let mut computer = computer();
    let recorded = u32::MAX - 1;
    let snapshot = Snapshot {
        frame: recorded,
        time_s: 1.0,
        attitude: attitude::exp_rotation_vector(&Vector3::new(0.0, 0.0, 0.3)),
        position_m: Vector3::new(10.0, 20.0, 30.0),
        velocity_mps: Vector3::new(1.0, 2.0, 3.0),
    };
    let rotation = |x: f64, y: f64| attitude::exp_rotation_vector(&Vector3::new(x, y, 0.0));
    let corrections = [
        // (frame, attitude, position): before the snapshot, in its frame, after the wrap.
        (
            recorded.wrapping_sub(1),
            rotation(0.5, 0.0),
            Vector3::new(100.0, 0.0, 0.0),
        ),
        (recorded, rotation(0.1, 0.0), Vector3::new(1.0, 0.0, 0.0)),
        (
            recorded.wrapping_add(3),
            rotation(0.0, 0.2),
            Vector3::new(0.0, 2.0, 0.0),
        ),
    ];
    for (frame, attitude, position_m) in corrections {
        computer.navigation.history.record_correction(Correction {
            frame,
            attitude,
            velocity_mps: position_m * 0.5,
            position_m,
        });
    }
    computer.frame = recorded.wrapping_add(4);
    let corrected = computer
        .navigation
        .history
        .corrected(computer.frame, &snapshot);
    let mut eager = snapshot;
    for (_, attitude, position_m) in &corrections[1..] {
        eager.attitude = attitude::product(&eager.attitude, attitude);
        eager.position_m += position_m;
        eager.velocity_mps += position_m * 0.5;
    }
    assert_eq!(
        corrected.attitude.coords.map(f64::to_bits),
        eager.attitude.coords.map(f64::to_bits)
    );
    assert_eq!(
        corrected.position_m.map(f64::to_bits),
        eager.position_m.map(f64::to_bits)
    );
    // The order matters: the opposite order gives a different attitude.
    let reversed = attitude::product(
        &attitude::product(&snapshot.attitude, &corrections[2].1),
        &corrections[1].1,
    );
    assert!((reversed.coords - corrected.attitude.coords).norm() > 1e-3);
}

/// The documented recovery: a covariance nav-core refuses to propagate (its products
/// overflow) re-initialises the filter from the configured 1σ, once, counted; the
/// navigation solution is kept.
#[test]
fn a_filter_that_cannot_be_propagated_is_reinitialised_once() {
    use crate::replay::FramePorts;
    let mut computer = computer();
    let fresh = *computer.covariance.filter.covariance();
    let huge = nav_core::discretise::CovarianceMatrix::from_element(f64::MAX);
    computer.covariance.filter.set_covariance(&huge).unwrap();
    let before = computer.navigation();
    let mut ports = FramePorts::default();
    ports.imu.0 = Some(crate::ports::ImuSample {
        sequence: 1,
        time_s: 600.002,
        delta_angle_rad: [0.0; 3],
        delta_velocity_mps: [0.0; 3],
    });
    ports.run(&mut computer);
    assert_eq!(computer.health().filter_resets, 1);
    assert_eq!(
        computer.covariance.filter.covariance().map(f64::to_bits),
        fresh.map(f64::to_bits)
    );
    assert!((computer.navigation().position_m - before.position_m).norm() < 100.0);
}

fn one_frame(computer: &mut NavigationComputer, sequence: u32) {
    let mut ports = crate::replay::FramePorts::default();
    ports.imu.0 = Some(crate::ports::ImuSample {
        sequence,
        time_s: 600.0 + 0.002 * f64::from(sequence),
        delta_angle_rad: [0.0; 3],
        delta_velocity_mps: [0.0; 3],
    });
    ports.run(computer);
}

/// A strapdown step nav-core refuses (the solution at the Earth's centre, where gravity
/// is not finite) is counted and leaves the solution as it was, except that navigation
/// time still advances by one frame.
#[test]
fn a_refused_strapdown_step_still_advances_time_by_one_frame() {
    let mut computer = computer();
    computer.navigation.solution.position_m = *computer.launch_frame.earth_centre_launch_m();
    computer.navigation.solution.velocity_mps = Vector3::zeros();
    let before = computer.navigation.solution;
    one_frame(&mut computer, 1);
    assert_eq!(computer.health().strapdown_failures, 1);
    let period = computer.config.imu.period_s;
    assert_eq!(
        computer.navigation.solution.time_s.to_bits(),
        (before.time_s + period).to_bits()
    );
    assert_eq!(
        computer.navigation.solution.position_m.map(f64::to_bits),
        before.position_m.map(f64::to_bits)
    );
}

/// Under the paper's schedule, a coast freezes every calibration block but the biases,
/// and the computer reports exactly the set its telemetry carries.
#[test]
fn the_frozen_set_is_the_policy_s_for_the_phase() {
    use crate::calibration_manager::{EstimationPolicy, ManoeuvrePhase};
    use nav_core::state::{ACCEL_BIAS, GYRO_BIAS, GYRO_SCALE_FACTOR, STAR_INSTALLATION};
    let mut config = computer().config;
    config.calibration.policy = EstimationPolicy::PaperSchedule;
    let initial = computer().navigation.solution;
    let mut computer = NavigationComputer::new(config, initial).unwrap();
    computer
        .command(Command::SetPhase(ManoeuvrePhase::Coast))
        .unwrap();
    one_frame(&mut computer, 1);
    let frozen = computer.frozen_blocks();
    assert!(!frozen.contains(GYRO_BIAS) && !frozen.contains(ACCEL_BIAS));
    assert!(frozen.contains(GYRO_SCALE_FACTOR) && frozen.contains(STAR_INSTALLATION));
    assert_eq!(
        frozen.bits(),
        computer.telemetry(FrameFusion::None).frozen_blocks
    );
}

/// A slot that held another computer (other site, other state, frames run) becomes exactly
/// the computer `new` builds: a field left out of the in-place writes would keep the old
/// value and show in the debug form.
#[test]
fn init_in_place_writes_every_field() {
    let mut config = FswConfig::paper_defaults(
        LaunchSite {
            latitude_rad: -0.3,
            height_m: 20.0,
            ..site()
        },
        SensorFrames {
            launch_epoch_gps_week: 2_000,
            ..SensorFrames::ALIGNED
        },
    );
    config.covariance.sigma_ceiling_factor *= 2.0;
    config.filter.initial.position_m *= 3.0;
    let mut other = NavigationComputer::new(config, initial_state()).unwrap();
    other.set_arithmetic(FilterArithmetic::DenseReference);
    other.set_frame_budget(7);
    for sequence in 1..=70 {
        one_frame(&mut other, sequence);
    }
    other.report_frame_cost(11);
    let mut slot = core::mem::MaybeUninit::new(other);
    let expected = computer();
    let built =
        NavigationComputer::init_in_place(&mut slot, *expected.config(), initial_state()).unwrap();
    assert_eq!(format!("{built:?}"), format!("{expected:?}"));
}

/// A refused configuration is refused in place as by value, with the same error.
#[test]
fn init_in_place_refuses_as_new_does() {
    let mut slot = core::mem::MaybeUninit::uninit();
    let mut config = *computer().config();
    config.imu.period_s = f64::NAN;
    let refused = NavigationComputer::init_in_place(&mut slot, config, initial_state());
    let expected = NavigationComputer::new(config, initial_state());
    let (refused, expected) = (refused.err(), expected.err());
    assert!(refused.is_some());
    assert_eq!(refused, expected);
}

/// An initial time where a frame no longer advances the clock (1e17 s: one ulp is 16 s) is
/// refused naming the initial state; the largest allowed time still advances by one frame.
#[test]
fn an_initial_time_beyond_the_limit_is_refused() {
    let config = FswConfig::paper_defaults(site(), SensorFrames::ALIGNED);
    for time_s in [1.0e17, -1.0e17, 1.000_000_1e9] {
        let initial = NavigationState {
            time_s,
            ..initial_state()
        };
        assert_eq!(
            NavigationComputer::new(config, initial).err(),
            Some(FswError::InvalidConfiguration(
                ConfigField::InitialNavigation
            )),
            "{time_s}"
        );
    }
    let initial = NavigationState {
        time_s: crate::config::MAX_INITIAL_TIME_S,
        ..initial_state()
    };
    let mut computer = NavigationComputer::new(config, initial).unwrap();
    let start_s = computer.navigation().time_s;
    one_frame(&mut computer, 1);
    let advanced_s = computer.navigation().time_s - start_s;
    assert!((advanced_s - 0.002).abs() < 1e-6, "{advanced_s}");
}

/// Runs 40 frames with a star measurement tagged at the navigation time in every fourth
/// frame and two in frame 22 (a burst), under `frame_load`; returns per frame whether it
/// fused, its navigation time and its covariance's time.
fn flight_with_frame_load(frame_load: crate::config::FrameLoad) -> Vec<(bool, f64, f64)> {
    let mut config = *computer().config();
    config.covariance.frame_load = frame_load;
    let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
    let mut frames = Vec::new();
    for sequence in 1..=40_u32 {
        let mut ports = crate::replay::FramePorts::default();
        ports.imu.0 = Some(crate::ports::ImuSample {
            sequence,
            time_s: 600.0 + 0.002 * f64::from(sequence),
            delta_angle_rad: [1e-4, -2e-4, 3e-3],
            delta_velocity_mps: [0.01, 0.04, -0.02],
        });
        let star_count = match sequence {
            22 => 2,
            s if s % 4 == 0 => 1,
            _ => 0,
        };
        let q = computer.navigation().attitude;
        for older in (0..star_count).rev() {
            // The burst's first is 1 ms older (a queue holds one measurement per time tag).
            let measurement = crate::ports::StarMeasurement {
                time_tag_s: computer.navigation().time_s - 0.001 * f64::from(older),
                sensor_to_gcrf_wxyz: [q.w, q.i, q.j, q.k],
                head: 0,
            };
            ports.star.0.push_back(measurement).unwrap();
        }
        let telemetry = ports.run(&mut computer);
        frames.push((
            telemetry.fusion != FrameFusion::None,
            computer.navigation().time_s,
            computer.covariance_time_s(),
        ));
    }
    frames
}

/// `FuseOrPropagate`: no frame both propagates and fuses. A fusion frame's covariance is
/// the previous frame's (its propagation waits), a propagation waits one frame at most (a
/// measurement due then waits instead), and every measurement is fused.
#[test]
fn a_frame_fuses_or_propagates_never_both() {
    let frames = flight_with_frame_load(crate::config::FrameLoad::FuseOrPropagate);
    let period = 0.002;
    let mut fused = 0;
    for (index, (fusion, time_s, covariance_time_s)) in frames.iter().enumerate() {
        let lag_frames = (time_s - covariance_time_s) / period;
        if *fusion {
            fused += 1;
            assert!(
                (lag_frames - 1.0).abs() < 1e-6,
                "frame {index}: {lag_frames}"
            );
        } else {
            assert!(lag_frames.abs() < 1e-6, "frame {index}: {lag_frames}");
        }
    }
    // Ten single measurements and the burst's two, each tagged at the navigation time before
    // its frame: the covariance's time when the frame before propagated.
    assert_eq!(fused, 10 + 2);
    // The burst: frame 22 fuses one, 23 propagates, 24 fuses the other, 25 propagates and
    // 26 fuses frame 24's.
    let fusion = |frame: usize| frames[frame - 1].0;
    let pattern: Vec<bool> = (22..=27).map(fusion).collect();
    assert_eq!(pattern, [true, false, true, false, true, false]);
}

/// `PropagateThenFuse`: every frame propagates, and the fusion follows in the same frame.
#[test]
fn propagate_then_fuse_propagates_every_frame() {
    let frames = flight_with_frame_load(crate::config::FrameLoad::PropagateThenFuse);
    assert!(frames
        .iter()
        .all(|(_, time_s, covariance_time_s)| time_s.to_bits() == covariance_time_s.to_bits()));
    assert_eq!(
        frames.iter().filter(|(fusion, _, _)| *fusion).count(),
        10 + 2
    );
}

/// Flies `frames` frames of a vehicle that does not turn (its true attitude stays the
/// initial one) with a star measurement in every second frame, rotated from the true attitude
/// by `offset_rad` about body x; returns the NIS of the last star measurement tested.
fn fly_star_offset(computer: &mut NavigationComputer, frames: u32, offset_rad: f64) -> f64 {
    let first = computer.frame.wrapping_add(1);
    for sequence in first..first + frames {
        let mut ports = crate::replay::FramePorts::default();
        ports.imu.0 = Some(crate::ports::ImuSample {
            sequence,
            time_s: computer.navigation().time_s + 0.002,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        });
        if sequence % 2 == 0 {
            let turn = attitude::exp_rotation_vector(&Vector3::new(offset_rad, 0.0, 0.0));
            let q = attitude::product(&initial_state().attitude, &turn);
            let measurement = crate::ports::StarMeasurement {
                time_tag_s: computer.navigation().time_s,
                sensor_to_gcrf_wxyz: [q.w, q.i, q.j, q.k],
                head: 0,
            };
            ports.star.0.push_back(measurement).unwrap();
        }
        ports.run(computer);
    }
    computer.aids.star.last_nis
}

/// The offset about body x, beyond `base_rad` (where the filter's estimate is), whose first
/// star measurement has an NIS of about `nis` for this computer (probed on a copy: the NIS
/// of a fixed error grows as its square).
fn offset_for_nis(computer: &NavigationComputer, base_rad: f64, nis: f64) -> f64 {
    let probe_rad = 1e-6;
    let probed = fly_star_offset(&mut computer.clone(), 2, base_rad + probe_rad);
    probe_rad * (nis / probed).sqrt()
}

/// The star gate, the acquisition gate, an NIS halfway between them and the offset about
/// body x whose first star measurement has that NIS for `computer`.
fn between_the_gates(computer: &NavigationComputer) -> (f64, f64, f64, f64) {
    let (gate, acquisition) = (
        computer.config.star.gate_nis,
        computer.config.star.acquisition_gate_nis,
    );
    let nis = 0.5 * (gate + acquisition);
    (gate, acquisition, nis, offset_for_nis(computer, 0.0, nis))
}

/// A healthy star sensor whose first measurements disagree with the prior beyond the steady
/// gate (a tail draw of the installation or attitude error, which every measurement repeats)
/// is acquired under the acquisition gate, not declared faulty. Once acquired, a
/// disagreement of the same NIS is rejected under the steady gate, and after
/// `timing.rejections_to_declare_faulty` in a row the sensor is declared faulty.
#[test]
fn a_sensor_is_acquired_under_the_wider_gate_and_faulted_under_the_steady_one() {
    let mut computer = computer();
    let (gate, acquisition, nis, offset_rad) = between_the_gates(&computer);
    let first_nis = fly_star_offset(&mut computer, 2, offset_rad);
    assert!(first_nis > gate && first_nis < acquisition, "{first_nis}");
    assert!(computer.aids.star.acquired);
    assert_eq!(computer.health().star_gate_rejections, 0);
    // The filter now agrees with the sensor; measurements at that attitude are accepted.
    fly_star_offset(&mut computer, 40, offset_rad);
    assert_eq!(computer.health().star_gate_rejections, 0);
    // The same NIS after acquisition: rejected, then declared faulty.
    let limit = computer.config.timing.rejections_to_declare_faulty;
    let steady_offset_rad = offset_rad + offset_for_nis(&computer, offset_rad, nis);
    let nis_after = fly_star_offset(&mut computer, 2 * limit, steady_offset_rad);
    assert!(nis_after > gate && nis_after < acquisition, "{nis_after}");
    assert_eq!(computer.health().star_gate_rejections, limit);
    assert_eq!(computer.health().star_declared_faulty, 1);
    assert!(computer.aids.star.faulty);
}

/// A run of rejections whose innovations grow (each star measurement farther off than the
/// last, as from an inertial solution drifting away) is blamed on the inertial solution
/// even though the monitors passed when it began: `inertial_suspect` counts, the tracker is
/// kept, and the attitude variance is widened by the run's last NIS (capped at the gate)
/// over 3. The same run at a constant offset is the tracker's
/// (`a_sensor_is_acquired_under_the_wider_gate_and_faulted_under_the_steady_one`).
#[test]
fn a_run_of_growing_innovations_is_blamed_on_the_inertial_solution() {
    let mut computer = computer();
    let (gate, _, nis, offset_rad) = between_the_gates(&computer);
    fly_star_offset(&mut computer, 42, offset_rad);
    assert!(!computer.inconsistent(Sensor::Star) && !computer.inconsistent(Sensor::Gnss));
    let limit = computer.config.timing.rejections_to_declare_faulty;
    let first_rad = offset_rad + offset_for_nis(&computer, offset_rad, nis);
    // Each measurement one first-offset's worth farther: NIS 4 to 400 times the first.
    let step_rad = first_rad - offset_rad;
    let attitude_variance = |computer: &NavigationComputer| computer.filter().covariance()[(0, 0)];
    let mut before = 0.0;
    let mut fitted_before = [0.0; 2];
    let mut last_nis = 0.0;
    for k in 0..limit {
        before = attitude_variance(&computer);
        fitted_before = STAR_FITTED_BLOCKS.map(|block| variance(&computer, block));
        last_nis = fly_star_offset(&mut computer, 2, first_rad + f64::from(k) * step_rad);
    }
    let health = computer.health();
    assert_eq!(health.star_gate_rejections, limit);
    assert_eq!(health.star_declared_faulty, 0);
    assert_eq!(health.inertial_suspect, 1);
    assert!(last_nis > 100.0 * gate, "{last_nis}");
    // Widened by the run's last NIS capped at the gate (16.27 / 3 = 5.4), not by the
    // monitor's average (about 4 / 3 after 20 gate-capped entries).
    let after = attitude_variance(&computer);
    assert!(after > 4.0 * before, "{before} {after}");
    // The installation and gyro scale factor, fitted by the same updates, widen with it.
    let fitted_after = STAR_FITTED_BLOCKS.map(|block| variance(&computer, block));
    for (before, after) in fitted_before.iter().zip(&fitted_after) {
        assert!(*after > 4.0 * before, "{fitted_before:?} {fitted_after:?}");
    }
    assert!(!computer.aids.star.faulty);
}

/// The variance of the first state of `block`.
fn variance(computer: &NavigationComputer, block: StateBlock) -> f64 {
    computer.filter().covariance()[(block.index(), block.index())]
}

/// A tracker noisier than configured (3.5 times about body x): once the noise matching has
/// found the larger noise, a run of rejections at a constant offset, which a tracker as
/// noisy as configured is declared faulty for
/// (`a_sensor_is_acquired_under_the_wider_gate_and_faulted_under_the_steady_one`), is
/// blamed on the filter's fit: the tracker is kept, and the installation and gyro scale
/// factor are widened with the attitude and gyro bias.
#[test]
fn a_run_after_the_tracker_proved_noisier_than_configured_is_blamed_on_the_fit() {
    let mut computer = computer();
    let noise_rad = computer.config.star.noise_rad;
    let mut normal = crate::test_random::normal_source(0x0dd_ba11_c0ff_ee00);
    for _ in 0..600 {
        fly_star_offset(&mut computer, 2, 3.5 * noise_rad * normal());
    }
    assert!(computer.aids.star_noise.engaged());
    assert!(computer.star_noise_exceeds_configured());
    assert_eq!(computer.health().star_declared_faulty, 0);
    let suspect_before = computer.health().inertial_suspect;
    // Eight times the matched noise: far beyond the gate, a step in the tracker's output.
    let offset_rad = 8.0
        * computer
            .star_noise_rad()
            .iter()
            .fold(0.0, |a: f64, b| a.max(*b));
    let fitted_before = STAR_FITTED_BLOCKS.map(|block| variance(&computer, block));
    let limit = computer.config.timing.rejections_to_declare_faulty;
    fly_star_offset(&mut computer, 2 * limit, offset_rad);
    let health = computer.health();
    assert_eq!(health.star_declared_faulty, 0);
    assert!(health.inertial_suspect > suspect_before);
    assert!(!computer.aids.star.faulty);
    let fitted_after = STAR_FITTED_BLOCKS.map(|block| variance(&computer, block));
    for (before, after) in fitted_before.iter().zip(&fitted_after) {
        assert!(*after > *before, "{fitted_before:?} {fitted_after:?}");
    }
}

/// Without the acquisition gate (set to the steady one) the same first disagreement is a
/// fault: the persistent prior error is rejected every time.
#[test]
fn without_the_acquisition_gate_a_tail_draw_of_the_prior_is_declared_a_fault() {
    let mut config = *computer().config();
    config.star.acquisition_gate_nis = config.star.gate_nis;
    let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
    let nis = 0.5 * (config.star.gate_nis + crate::config::ACQUISITION_GATE_NIS);
    let offset_rad = offset_for_nis(&computer, 0.0, nis);
    let limit = config.timing.rejections_to_declare_faulty;
    fly_star_offset(&mut computer, 2 * limit, offset_rad);
    assert_eq!(computer.health().star_gate_rejections, limit);
    assert_eq!(computer.health().star_declared_faulty, 1);
}

/// The run of rejections of the test above, begun while the star sensor's innovations
/// already fail the consistency test (a gradual onset: the inertial solution drifting away),
/// or while the receiver's fail it, is blamed on the inertial solution: the star sensor is
/// kept, the run counted in `inertial_suspect`, and the attitude and gyro-bias variances
/// widened by the average NIS over 3.
#[test]
fn a_run_of_rejections_with_inconsistent_innovations_is_blamed_on_the_inertial_solution() {
    for witness in [Sensor::Star, Sensor::Gnss] {
        let mut computer = computer();
        let (gate, _, nis, offset_rad) = between_the_gates(&computer);
        fly_star_offset(&mut computer, 42, offset_rad);
        let consistency = computer.config.consistency;
        let monitor = match witness {
            Sensor::Star => &mut computer.aids.star_consistency,
            Sensor::Gnss => &mut computer.aids.gnss_consistency,
        };
        for _ in 0..2 * consistency.time_constant_measurements {
            monitor.observe(12.0, true, gate, &consistency);
        }
        assert!(computer.inconsistent(witness));
        let limit = computer.config.timing.rejections_to_declare_faulty;
        let steady_offset_rad = offset_rad + offset_for_nis(&computer, offset_rad, nis);
        let variance = |computer: &NavigationComputer, block: StateBlock| {
            computer.filter().covariance()[(block.index(), block.index())]
        };
        let before = [ATTITUDE, GYRO_BIAS].map(|block| variance(&computer, block));
        fly_star_offset(&mut computer, 2 * limit, steady_offset_rad);
        let health = computer.health();
        assert_eq!(health.star_gate_rejections, limit, "{witness:?}");
        assert_eq!(health.star_declared_faulty, 0, "{witness:?}");
        assert_eq!(health.inertial_suspect, 1, "{witness:?}");
        assert!(!computer.aids.star.faulty);
        let after = [ATTITUDE, GYRO_BIAS].map(|block| variance(&computer, block));
        // m ≈ 12 (the star's own test) or ≈ 3.6 (its last rejections): widened by m / 3.
        let least = if witness == Sensor::Star { 3.0 } else { 1.1 };
        assert!(
            after[1] > least * before[1],
            "{witness:?} {before:?} {after:?}"
        );
        assert!(after[0] > before[0], "{witness:?} {before:?} {after:?}");
    }
}

/// With the systematic IMU error states on (closed loop), a flight that turns about z under
/// thrust along x, with star updates offset about z, feeds the border's estimate back into
/// the corrections at every reset (the filter's `ε̂` is zero after each), the fed-back
/// corrections move off zero through the estimate's correlation with the attitude, and the
/// border's variances shrink from the prior and stay positive.
/// One frame of a constant turn, with a star measurement every tenth frame that sees the
/// attitude turned by 200 µrad about z (an attitude error the filter must correct).
pub(super) fn run_frame_with_turned_star(computer: &mut NavigationComputer, sequence: u32) {
    let mut ports = crate::replay::FramePorts::default();
    ports.imu.0 = Some(crate::ports::ImuSample {
        sequence,
        time_s: 600.0 + 0.002 * f64::from(sequence),
        delta_angle_rad: [2e-4, 1e-4, 4e-3],
        delta_velocity_mps: [0.06, 0.002, -0.001],
    });
    if sequence % 10 == 0 {
        let q = attitude::product(
            &computer.navigation().attitude,
            &attitude::exp_rotation_vector(&Vector3::new(0.0, 0.0, 2e-4)),
        );
        let measurement = crate::ports::StarMeasurement {
            time_tag_s: computer.navigation().time_s,
            sensor_to_gcrf_wxyz: [q.w, q.i, q.j, q.k],
            head: 0,
        };
        ports.star.0.push_back(measurement).unwrap();
    }
    ports.run(computer);
}

#[test]
fn the_systematic_imu_error_states_are_fed_back_at_every_reset() {
    let mut config = *computer().config();
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 1e-3,
        accel_misalignment_sigma_rad: 1e-3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-5,
    };
    let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
    let prior = computer.filter().imu_error().covariance();
    for sequence in 1..=400_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
        assert_eq!(
            computer.filter().imu_error().estimate(),
            nalgebra::SVector::<f64, 12>::zeros(),
            "frame {sequence}"
        );
    }
    let estimate = computer.imu_error_estimate().unwrap();
    assert!(estimate.is_finite());
    let moved = estimate
        .gyro_non_orthogonality_rad
        .iter()
        .chain(estimate.gyro_g_sensitivity_rad_s_per_mps2.iter())
        .any(|v| v.abs() > 0.0);
    assert!(moved, "{estimate:?}");
    let posterior = computer.filter().imu_error().covariance();
    for k in 0..12 {
        assert!(posterior[(k, k)] > 0.0, "state {k}");
        assert!(posterior[(k, k)] <= prior[(k, k)], "state {k}");
    }
    assert!((0..12).any(|k| posterior[(k, k)] < 0.99 * prior[(k, k)]));
}

/// The tracker's slow error (`star.slow_error_sigma_rad`) walks the installation states and
/// nothing else: over 200 IMU-only frames the installation variances grow by exactly
/// `σ²/(2τ)` per second more than without it (per sensor axis; to 1e-4, the rounding of
/// 1e-16 increments on a 2.5e-5 prior variance), and every other entry of `P` keeps its
/// bits (the installation enters no dynamic state).
#[test]
fn the_star_slow_error_walks_the_installation_states_only() {
    let still = computer();
    let mut config = *still.config();
    config.star.slow_error_sigma_rad = [1.0e-5, 2.0e-5, 4.0e-5];
    config.star.slow_error_correlation_time_s = 1000.0;
    let mut walking = NavigationComputer::new(config, initial_state()).unwrap();
    let mut still = still;
    let frames = 200_u32;
    for sequence in 1..=frames {
        one_frame(&mut still, sequence);
        one_frame(&mut walking, sequence);
    }
    let (p_still, p_walking) = (
        still.covariance.filter.covariance(),
        walking.covariance.filter.covariance(),
    );
    let elapsed_s = f64::from(frames) * config.imu.period_s;
    let first = STAR_INSTALLATION.index();
    for row in 0..nav_core::state::STATE_DIMENSION {
        for column in 0..nav_core::state::STATE_DIMENSION {
            let (a, b) = (p_still[(row, column)], p_walking[(row, column)]);
            let axis = row.wrapping_sub(first);
            if row == column && axis < 3 {
                let sigma = config.star.slow_error_sigma_rad[axis];
                let expected = sigma * sigma / (2.0 * 1000.0) * elapsed_s;
                assert!(
                    ((b - a) / expected - 1.0).abs() < 1e-4,
                    "axis {axis}: grew {} against {expected}",
                    b - a
                );
            } else {
                assert_eq!(a.to_bits(), b.to_bits(), "P[{row}][{column}]");
            }
        }
    }
}

/// A slow error without a correlation time, or with a negative 1σ, is refused by name.
#[test]
fn a_star_slow_error_without_its_correlation_time_is_refused() {
    use crate::config::Param;
    let mut config = *computer().config();
    config.star.slow_error_sigma_rad = [1.0e-5, 0.0, 0.0];
    config.star.slow_error_correlation_time_s = 0.0;
    assert_eq!(
        config.validate(),
        Err(FswError::InvalidConfiguration(ConfigField::Companion(
            Param::StarSlowErrorX,
            Param::StarSlowErrorCorrelationTime
        )))
    );
    for tau_s in [-1.0, f64::NAN, 1e-320] {
        config.star.slow_error_correlation_time_s = tau_s;
        assert_eq!(
            config.validate(),
            Err(FswError::InvalidConfiguration(ConfigField::Parameter(
                Param::StarSlowErrorCorrelationTime
            )))
        );
    }
    config.star.slow_error_correlation_time_s = 1000.0;
    config.star.slow_error_sigma_rad = [-1.0e-5, 0.0, 0.0];
    assert_eq!(
        config.validate(),
        Err(FswError::InvalidConfiguration(ConfigField::Parameter(
            Param::StarSlowErrorX
        )))
    );
}

/// An optional block is frozen by command as a core block is: with the systematic IMU error
/// states frozen, the flight of [`the_systematic_imu_error_states_are_fed_back_at_every_reset`]
/// (star updates offset about z) moves none of them, so nothing is fed back; a block not
/// flown is refused, and `RestartCalibration` releases the frozen ones.
#[test]
fn a_frozen_optional_block_is_not_moved_and_a_block_not_flown_is_refused() {
    use nav_core::state::OptionalBlock;
    let mut config = *computer().config();
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 1e-3,
        accel_misalignment_sigma_rad: 1e-3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-5,
    };
    let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
    assert_eq!(
        computer.command(Command::SetOptionalBlockFrozen(
            OptionalBlock::GnssError,
            true
        )),
        Err(CommandError::BlockNotInUse(OptionalBlock::GnssError))
    );
    let imu_blocks = [
        OptionalBlock::GyroNonOrthogonality,
        OptionalBlock::AccelMisalignment,
        OptionalBlock::GyroGSensitivity,
    ];
    for block in imu_blocks {
        computer
            .command(Command::SetOptionalBlockFrozen(block, true))
            .unwrap();
        assert!(computer.filter().optional_block_frozen(block));
    }
    let prior = computer.filter().imu_error().covariance();
    let attitude_prior = variance(&computer, ATTITUDE);
    for sequence in 1..=200_u32 {
        run_frame_with_turned_star(&mut computer, sequence);
    }
    // The star updates were fused.
    assert!(variance(&computer, ATTITUDE) < attitude_prior);
    assert_eq!(
        computer.imu_error_estimate().unwrap(),
        nav_core::imu_error::ImuErrorEstimate::default()
    );
    // Frozen: the border's covariance is the prior's (no gain, no process noise).
    assert_eq!(computer.filter().imu_error().covariance(), prior);
    computer.command(Command::RestartCalibration).unwrap();
    for block in imu_blocks {
        assert!(!computer.filter().optional_block_frozen(block));
    }
}

/// An optional block's variance floor: a g-sensitivity floor above the prior 1σ raises the
/// block's variances to it at the first propagation, counted as a covariance clamp; the
/// default floors and ceilings leave the prior alone.
#[test]
fn an_optional_block_s_variance_is_raised_to_its_floor() {
    let mut config = *computer().config();
    config.filter.imu_error = nav_core::imu_error_states::ImuErrorModel {
        gyro_misalignment_sigma_rad: 1e-3,
        accel_misalignment_sigma_rad: 1e-3,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 1e-5,
    };
    let run = |config: FswConfig| {
        let mut computer = NavigationComputer::new(config, initial_state()).unwrap();
        one_frame(&mut computer, 1);
        (
            computer.filter().imu_error().covariance(),
            computer.health().covariance_clamps,
        )
    };
    let (nominal, nominal_clamps) = run(config);
    assert_eq!(nominal_clamps, 0);
    config
        .covariance
        .optional_sigma_floor
        .gyro_g_sensitivity_rad_s_per_mps2 = 2e-5;
    let (raised, clamps) = run(config);
    assert_eq!(clamps, 1);
    for k in 0..12 {
        let expected = if k >= 9 { 2e-5 * 2e-5 } else { nominal[(k, k)] };
        assert_eq!(raised[(k, k)].to_bits(), expected.to_bits(), "state {k}");
    }
}
