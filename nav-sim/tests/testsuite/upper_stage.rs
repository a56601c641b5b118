//! Flights a vehicle can fly: the upper-stage scenario keeps an upper stage's limits and
//! calibrates what its manoeuvres can reach; the paper's strategy as printed (a short flight)
//! leaves the accelerometer scale factors at their prior. Results: docs/guide/upper-stage.md.

use nav_sim::harness::flight::{fly, FlightOptions, FlightResult};
use nav_sim::output::report::{CalibrationResult, CalibrationRow, Parameter};
use nav_sim::Scenario;

const UPPER_STAGE_TOML: &str = include_str!("../../scenarios/upper_stage.toml");
/// χ²(15) 99.9 % point: the bound on one run's NEES of the 15 calibration states.
const CALIBRATION_NEES_BOUND: f64 = 37.70;

/// Final calibration rows of a whole flight, and its NEES.
fn fly_whole(scenario: &Scenario) -> (Vec<CalibrationRow>, f64) {
    let options = FlightOptions {
        record_interval_s: 60.0,
    };
    let result: FlightResult = fly(scenario, options, |_, _| {}).unwrap();
    let last = result.last().unwrap().time_history();
    let table = CalibrationResult::from_sample(&last, &Parameter::CALIBRATION);
    println!("{}", table.table());
    (table.rows, result.calibration_nees().unwrap())
}

/// Filter 1σ over the paper's accuracy.
fn sigma_ratio(row: &CalibrationRow) -> f64 {
    row.sigma / row.parameter.paper_accuracy().unwrap()
}

#[test]
fn the_upper_stage_scenario_keeps_the_vehicles_limits() {
    let scenario = Scenario::from_toml_str(UPPER_STAGE_TOML).unwrap();
    let (mut main_engine_mps, mut lateral_mps, mut duration_s) = (0.0, 0.0, 0.0);
    for segment in &scenario.manoeuvres {
        let hold_s = segment.duration_s - segment.ramp_s;
        let [x, y, z] = segment.specific_force_mps2;
        assert!(x >= 0.0, "{}: thrust only along body +x", segment.label);
        assert!(
            y.abs() <= 1.0 && z.abs() <= 1.0,
            "{}: RCS class",
            segment.label
        );
        let rate = segment.body_rate_deg_per_s;
        let rate_deg_per_s = rate.iter().map(|r| r * r).sum::<f64>().sqrt();
        assert!(
            rate_deg_per_s < 3.0,
            "{}: slews below 3 deg/s",
            segment.label
        );
        main_engine_mps += x * hold_s;
        lateral_mps += (y.abs() + z.abs()) * hold_s;
        duration_s += segment.duration_s;
    }
    assert!(
        (1000.0..=2500.0).contains(&main_engine_mps),
        "{main_engine_mps} m/s"
    );
    assert!(lateral_mps <= 50.0 + 1e-9, "{lateral_mps} m/s");
    assert!((3600.0..=7200.0).contains(&duration_s), "{duration_s} s");
    assert!(scenario.star_sensor.max_rate_deg_per_s <= 3.0);
    assert!(scenario.simulation.min_altitude_m >= 200e3);
    let gnss = &scenario.gnss;
    let total_m = (gnss.noise_m.powi(2) + gnss.correlated_noise_m.powi(2)).sqrt();
    assert!((total_m - 10.0).abs() < 1e-9 && gnss.velocity_noise_mps > 0.0);
}

/// The upper stage in the real gravity field reaches the paper's figure on every state its
/// manoeuvres excite and the field leaves to it (gyro scale factors from 24 slow turns, the
/// biases, the installation error), comes near it on the x accelerometer scale factor, which
/// 1.25 km/s of main-engine burns observe through a velocity the omitted field's allowance
/// blurs, and honestly not on the y and z accelerometer scale factors, which 50 m/s of RCS
/// translation cannot resolve (the measured ratios: docs/guide/upper-stage.md).
#[test]
fn the_upper_stage_flight_calibrates_what_its_manoeuvres_reach() {
    let scenario = Scenario::from_toml_str(UPPER_STAGE_TOML).unwrap();
    let (rows, nees) = fly_whole(&scenario);
    for row in &rows {
        let ratio = sigma_ratio(row);
        let accelerometer_scale = row.parameter == Parameter::AccelerometerScaleFactor;
        let bound = match row.axis {
            _ if !accelerometer_scale => 0.0..1.0,
            nav_sim::output::report::Axis::X => 1.0..1.5,
            _ => 30.0..100.0,
        };
        assert!(bound.contains(&ratio), "{row:?}: σ/accuracy {ratio:.2}");
    }
    assert!(nees < CALIBRATION_NEES_BOUND, "NEES {nees:.1}");
}

/// The paper's strategy as printed: 10 s of rotation and 15 s of thrust in a 400 s flight with
/// 1 Hz GNSS. The rotations calibrate the gyro scale factors; 250 m/s per axis watched for a
/// few minutes leaves the accelerometer scale factors near their 2e-4 prior (σ/accuracy
/// measured 69–74).
#[test]
fn the_papers_strategy_as_printed_leaves_the_accelerometer_scale_factors_near_their_prior() {
    let scenario = crate::realistic_campaign::scenario("paper_strategy_as_printed");
    let (rows, nees) = fly_whole(&scenario);
    for row in &rows {
        let ratio = sigma_ratio(row);
        if row.parameter == Parameter::AccelerometerScaleFactor {
            assert!(ratio > 50.0, "{row:?}: σ/accuracy {ratio:.2}");
        } else {
            assert!(ratio < 1.0, "{row:?}: σ/accuracy {ratio:.2}");
        }
    }
    assert!(nees < CALIBRATION_NEES_BOUND, "NEES {nees:.1}");
}

/// A tail draw of the prior that once lost both sensors: the Monte Carlo run with seed
/// 91,730,045 draws the star installation error 3.5σ from its prior about z, so the first
/// star measurements disagree with the filter beyond the steady gate (NIS 18.6 against
/// 16.27). Every measurement repeats that disagreement; with the steady gate from the start
/// they were all rejected, the healthy tracker was declared faulty after 20, the attitude
/// drifted by 2 rad on the gyro bias, the GNSS was then declared faulty in the first burn
/// and the flight ended 12,800 km off. Under the acquisition gate (nav-fsw
/// `ACQUISITION_GATE_NIS`) the first measurement is accepted and the flight is nominal.
#[test]
fn a_tail_draw_of_the_installation_error_does_not_lose_the_star_tracker() {
    let scenario = Scenario::from_toml_str(UPPER_STAGE_TOML).unwrap();
    let seed = 91_730_045;
    let seeded = nav_sim::setup::prior::with_truth_drawn_from_prior(&scenario, seed);
    let installation_z_rad = seeded.star_sensor.installation_error_rotation_vector_rad[2];
    let prior_rad = scenario.filter.initial_sigma.star_installation_rad;
    assert!(
        installation_z_rad.abs() > 3.4 * prior_rad,
        "{installation_z_rad}"
    );
    let truth = nav_sim::setup::dispersion::truth_scenario(&seeded, seed);
    let config = nav_sim::setup::fsw::run_config(&seeded, &truth).unwrap();
    let options = FlightOptions {
        record_interval_s: 60.0,
    };
    let result =
        nav_sim::harness::flight::fly_with(&truth, config, options, |_, _| {}, |_, _| {}).unwrap();
    let health = result.health;
    assert_eq!(
        (health.star_declared_faulty, health.gnss_declared_faulty),
        (0, 0)
    );
    let last = result.last().unwrap();
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let position_error_m = norm(last.position_error_m);
    assert!(
        position_error_m < 4.0 * norm(last.position_sigma_m),
        "{position_error_m} m"
    );
    let nees = result.calibration_nees().unwrap();
    assert!(nees < CALIBRATION_NEES_BOUND, "NEES {nees}");
}
