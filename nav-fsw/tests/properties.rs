//! Property tests (proptest) on every input decoder and validator of the flight
//! software, and on the scheduler as a whole: whatever the bytes, numbers or time tags, nothing
//! panics, every refusal is a typed error, what is accepted satisfies the documented
//! invariants, and the filter's state and covariance stay finite, symmetric and positive
//! definite. (The binary log decoder's own properties live beside it in `log_record.rs`.)

use nalgebra::{Quaternion, Vector3};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;
use nav_fsw::config::FswConfig;
use nav_fsw::input_check::{check_gnss, check_star, ImuChecker, ImuLimits};
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::replay::{FramePorts, ReplaySetup, SETUP_WORDS};
use nav_fsw::scheduler::NavigationComputer;
use proptest::prelude::*;

/// Any f64 a sensor could deliver: plausible values, zeros, subnormals, huge values, ±Inf and
/// NaN, and arbitrary bit patterns.
fn any_sensor_value(typical: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => (-1.0..1.0_f64).prop_map(move |x| x * typical),
        1 => Just(0.0),
        1 => Just(f64::MIN_POSITIVE / 4.0), // subnormal
        1 => Just(-1e300),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::NAN),
        1 => any::<u64>().prop_map(f64::from_bits),
    ]
}

fn site() -> LaunchSite {
    LaunchSite {
        latitude_rad: 0.7,
        longitude_rad: 1.7,
        height_m: 1000.0,
        azimuth_rad: 1.6,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    }
}

fn initial_state() -> NavigationState {
    NavigationState {
        attitude: Quaternion::new(0.5, 0.5, -0.5, 0.5),
        position_m: Vector3::new(1.0e5, 6.7e6, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 0.0, 0.0),
        time_s: 0.0,
    }
}

fn is_finite_quaternion(q: &Quaternion<f64>) -> bool {
    q.coords.iter().all(|c| c.is_finite())
}

/// One frame's worth of (possibly garbage) sensor input.
#[derive(Debug, Clone)]
struct FrameInput {
    imu: Option<([f64; 3], [f64; 3], f64, u32)>,
    star: Option<(f64, [f64; 4])>,
    gnss: Option<(f64, [f64; 3])>,
}

fn frame_input() -> impl Strategy<Value = FrameInput> {
    let imu = proptest::option::weighted(
        0.9,
        (
            proptest::array::uniform3(any_sensor_value(0.02)),
            proptest::array::uniform3(any_sensor_value(0.2)),
            any_sensor_value(0.01),
            0_u32..4,
        ),
    );
    let star = proptest::option::weighted(
        0.3,
        (
            any_sensor_value(0.1),
            proptest::array::uniform4(any_sensor_value(1.0)),
        ),
    );
    let gnss = proptest::option::weighted(
        0.2,
        (
            any_sensor_value(0.1),
            proptest::array::uniform3(any_sensor_value(7e6)),
        ),
    );
    (imu, star, gnss).prop_map(|(imu, star, gnss)| FrameInput { imu, star, gnss })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The IMU checker never panics; an accepted sample is finite and within the limits.
    #[test]
    fn imu_checks_never_panic_and_accept_only_plausible_samples(
        samples in proptest::collection::vec(
            (proptest::array::uniform3(any_sensor_value(0.02)),
             proptest::array::uniform3(any_sensor_value(0.2)),
             any_sensor_value(1.0),
             any::<u32>()),
            1..20),
    ) {
        let limits = ImuLimits::default();
        let mut checker = ImuChecker::new(limits).unwrap();
        for (delta_angle_rad, delta_velocity_mps, time_s, sequence) in samples {
            let sample = ImuSample::new(sequence, time_s, delta_angle_rad, delta_velocity_mps);
            if checker.check(&sample).is_ok() {
                let rate_limit = limits.max_rate_rad_s * limits.period_s * (1.0 + limits.period_tolerance);
                prop_assert!(delta_angle_rad.iter().all(|v| v.is_finite() && v.abs() <= rate_limit));
                prop_assert!(delta_velocity_mps.iter().all(|v| v.is_finite()));
                prop_assert!(time_s.is_finite());
            }
        }
    }

    /// The star check never panics; what it accepts is a finite unit quaternion equal to the
    /// input up to sign, with the sign flagged against the previous sample.
    #[test]
    fn star_checks_return_unit_quaternions_or_typed_errors(
        attitude_wxyz in proptest::array::uniform4(any_sensor_value(1.0)),
        time_tag_s in any_sensor_value(100.0),
        previous in proptest::option::of(proptest::array::uniform4(-1.0..1.0_f64)),
    ) {
        let previous = previous.map(|[w, x, y, z]| Quaternion::new(w, x, y, z));
        let measurement = StarMeasurement::new(time_tag_s, attitude_wxyz, 0);
        if let Ok((q, flipped)) = check_star(&measurement, previous.as_ref(), 1e-3) {
            prop_assert!(is_finite_quaternion(&q));
            prop_assert!((q.norm() - 1.0).abs() < 1e-12);
            let [w, x, y, z] = attitude_wxyz;
            let input = Quaternion::new(w, x, y, z);
            let sign = if flipped { -1.0 } else { 1.0 };
            prop_assert!((q.coords * sign - input.coords / input.norm()).norm() < 1e-12);
            if let Some(p) = previous {
                prop_assert_eq!(flipped, p.coords.dot(&(input.coords)) < 0.0);
            }
        }
    }

    /// The GNSS check never panics and accepts only finite fixes within the jump limit.
    #[test]
    fn gnss_checks_accept_only_finite_fixes_within_the_jump_limit(
        position in proptest::array::uniform3(any_sensor_value(7e6)),
        time_tag_s in any_sensor_value(100.0),
        predicted in proptest::array::uniform3(-7e6..7e6_f64),
    ) {
        let fix = GnssFix::new(2_000, time_tag_s, position);
        let position = Vector3::from(position);
        let predicted = Vector3::from(predicted);
        if check_gnss(&fix, &position, &predicted, 1000.0).is_ok() {
            prop_assert!(position.iter().all(|v| v.is_finite()));
            prop_assert!((position - predicted).norm() <= 1000.0);
        }
    }

    /// The firmware's setup decoder: arbitrary words, or a real setup with one word replaced
    /// by arbitrary bits or an arbitrary sensor-like value, never panic; a decoded setup
    /// re-encodes to the same words, and the flight software either starts from it (its
    /// configuration validates) or refuses it with a typed configuration error (the decoder
    /// checks structure; values are checked at start, as documented on `from_words`).
    #[test]
    fn setup_words_decode_to_a_valid_configuration_or_a_typed_error(
        random in proptest::collection::vec(any::<u64>(), SETUP_WORDS),
        mode in 0_u8..3,
        index in 0_usize..SETUP_WORDS,
        bits in any::<u64>(),
        value in any_sensor_value(10.0),
    ) {
        let mut words = reference_setup().to_words();
        match mode {
            0 => words = random.try_into().unwrap(),
            1 => words[index] = bits,
            _ => words[index] = value.to_bits(),
        }
        if let Ok(setup) = ReplaySetup::from_words(&words) {
            prop_assert_eq!(setup.to_words(), words);
            // A refusal is a typed `FswError` by construction; a start implies a valid
            // configuration.
            if NavigationComputer::new(setup.config(), setup.initial).is_ok() {
                prop_assert!(setup.config().validate().is_ok());
            }
        }
    }

    /// Configuration validation: any single numeric field of the paper's defaults replaced by
    /// an arbitrary value either validates (and then the flight software starts) or is refused
    /// with a typed error naming a field; never a panic.
    #[test]
    fn a_configuration_either_validates_and_starts_or_names_its_bad_field(
        field in 0_usize..13,
        value in any_sensor_value(10.0),
    ) {
        let mut config = FswConfig::paper_defaults(site(), nav_fsw::sensor_frames::SensorFrames::ALIGNED);
        match field {
            0 => config.imu.period_s = value,
            1 => config.imu.max_rate_rad_s = value,
            2 => config.star.noise_rad = value,
            3 => config.star.gate_nis = value,
            4 => config.gnss.noise_m = value,
            5 => config.gnss.gate_nis = value,
            6 => config.gnss.max_jump_m = value,
            7 => config.timing.max_latency_s = value,
            8 => config.covariance.sigma_ceiling_factor = value,
            9 => config.calibration.stability_window_s = value,
            10 => config.launch_site.latitude_rad = value,
            11 => config.star.roll_noise_rad = value,
            _ => config.star.mounting_wxyz[1] = value,
        }
        match config.validate() {
            Ok(()) => prop_assert!(NavigationComputer::new(config, initial_state()).is_ok()),
            Err(error) => prop_assert!(matches!(
                error,
                nav_fsw::error::FswError::InvalidConfiguration(_)
            )),
        }
    }
}

/// Both filter modes survive the word encoding (the mode word 0 is open loop, 1 closed loop).
#[test]
fn both_filter_modes_round_trip_through_the_setup_words() {
    use nav_core::filter::FilterMode;
    for mode in [FilterMode::OpenLoop, FilterMode::ClosedLoop] {
        let mut config = reference_setup().config();
        config.filter.mode = mode;
        let setup = ReplaySetup::new(&config, initial_state());
        let decoded = ReplaySetup::from_words(&setup.to_words()).unwrap();
        assert_eq!(decoded, setup);
        assert_eq!(decoded.config().filter.mode, mode);
    }
}

fn reference_setup() -> ReplaySetup {
    let config = FswConfig::paper_defaults(site(), nav_fsw::sensor_frames::SensorFrames::ALIGNED);
    ReplaySetup::new(&config, initial_state())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The whole scheduler under garbage: 100 frames of arbitrary IMU samples, star quaternions,
    /// GNSS fixes and time tags. Never a panic; after every frame the navigation solution and
    /// the filter are finite and `P` is symmetric positive definite.
    #[test]
    fn the_scheduler_survives_arbitrary_inputs_with_a_healthy_covariance(
        frames in proptest::collection::vec(frame_input(), 100),
    ) {
        let mut computer =
            NavigationComputer::new(FswConfig::paper_defaults(site(), nav_fsw::sensor_frames::SensorFrames::ALIGNED), initial_state()).unwrap();
        let mut sequence = 0_u32;
        for (index, input) in frames.iter().enumerate() {
            let now_s = 0.002 * f64::from(u32::try_from(index + 1).unwrap());
            let mut ports = FramePorts::default();
            if let Some((delta_angle_rad, delta_velocity_mps, time_jitter_s, skip)) = input.imu {
                sequence = sequence.wrapping_add(1 + skip % 2);
                let time_s = if time_jitter_s.is_finite() { now_s + time_jitter_s } else { time_jitter_s };
                ports.imu.0 = Some(ImuSample::new(sequence, time_s, delta_angle_rad, delta_velocity_mps));
            }
            if let Some((offset_s, attitude_wxyz)) = input.star {
                let time_tag_s = now_s + offset_s;
                let _ = ports.star.0.push_back(StarMeasurement::new(time_tag_s, attitude_wxyz, 0));
            }
            if let Some((offset_s, position_ecef_m)) = input.gnss {
                // Navigation time is GPS seconds of week 1000 (the aligned frames' epoch).
                let gps_seconds_of_week = now_s + offset_s;
                let _ = ports.gnss.0.push_back(GnssFix::new(1_000, gps_seconds_of_week, position_ecef_m));
            }
            ports.run(&mut computer);
            let navigation = computer.navigation();
            prop_assert!(is_finite_quaternion(&navigation.attitude));
            prop_assert!(navigation.position_m.iter().chain(navigation.velocity_mps.iter()).all(|v| v.is_finite()));
            let p = computer.filter().covariance();
            prop_assert!(p.iter().all(|v| v.is_finite()));
            prop_assert!((p - p.transpose()).norm() <= 1e-12 * p.norm());
            prop_assert!(p.cholesky().is_some(), "P not positive definite after frame {}", index);
        }
    }
}
