//! The truth's published gravity field (`[gravity]`, `docs/guide/model.md`): nav-sim's EGM2008
//! evaluation against an independent one (pyshtools, `nav-sim/data/gravity_oracle.py`), the
//! default flight unchanged without the table, the field's effect on the truth, and the
//! table's validation.

use nalgebra::Vector3;
use nav_sim::scenario::DEFAULT_SCENARIO_TOML;
use nav_sim::world::gravity::gfc::parse_gfc;
use nav_sim::world::gravity::harmonics::SphericalHarmonics;
use nav_sim::world::gravity::{RotatingRemainder, EGM2008_GFC};
use nav_sim::world::truth::TruthSimulator;
use nav_sim::Scenario;

/// pyshtools 4.14.1's accelerations of `nav-sim/data/EGM2008_60.gfc` (columns in its script).
const ORACLE_CSV: &str = include_str!("../../data/gravity_oracle.csv");

fn vector(values: &[f64]) -> Vector3<f64> {
    Vector3::new(values[0], values[1], values[2])
}

/// Every oracle row: degree 2 to 60, surface to 2,000 km, both poles. The complete field
/// agrees to 1e-13 of |g| and the remainder beyond point mass + `J2` to 1e-15 m/s²
/// (measured: 5.8e-15 relative, rounding in the two codes' sums of the 9.8 m/s² point mass,
/// and 1.4e-17 m/s²), far below the accelerometer noise.
#[test]
fn egm2008_evaluation_matches_pyshtools() {
    let frame = nav_core::frames::LaunchFrame::new(
        &Scenario::default_scenario().unwrap().launch_site.nav_site(),
    )
    .unwrap();
    let (mut worst_relative, mut worst_remainder): (f64, f64) = (0.0, 0.0);
    let mut rows = 0;
    for line in ORACLE_CSV.lines().skip(1) {
        let values: Vec<f64> = line.split(',').map(|cell| cell.parse().unwrap()).collect();
        let (degree, order) = (values[0] as usize, values[1] as usize);
        let position = vector(&values[2..5]);
        let complete = SphericalHarmonics::new(parse_gfc(EGM2008_GFC, degree, order).unwrap());
        let got = complete.acceleration_mps2(&position);
        let expected = vector(&values[5..8]);
        worst_relative = worst_relative.max((got - expected).norm() / expected.norm());
        let remainder = RotatingRemainder::new(EGM2008_GFC, degree, order, frame).unwrap();
        let got = remainder.field().acceleration_mps2(&position);
        worst_remainder = worst_remainder.max((got - vector(&values[8..11])).norm());
        rows += 1;
    }
    println!(
        "{rows} points: complete field {worst_relative:.2e} relative, remainder \
         {worst_remainder:.2e} m/s²"
    );
    assert_eq!(rows, 24);
    assert!(worst_relative < 1.0e-13, "{worst_relative:e}");
    assert!(worst_remainder < 1.0e-15, "{worst_remainder:e}");
}

fn with_gravity(table: &str) -> Result<Scenario, nav_sim::scenario::ScenarioError> {
    Scenario::from_toml_str(&format!("{DEFAULT_SCENARIO_TOML}\n[gravity]\n{table}\n"))
}

/// The truth's state after `frames` frames.
fn flown(scenario: &Scenario, frames: usize) -> nav_sim::setup::launch::TruthState {
    let mut truth = TruthSimulator::from_scenario(scenario).unwrap();
    let mut last = *truth.state();
    for frame in truth.by_ref().take(frames) {
        last = frame.unwrap().state();
    }
    last
}

/// `model = "j2"` flies the default's bits, and an absent table leaves the scenario's
/// rendering (the campaign's scenario hash) as it was.
#[test]
fn j2_model_and_no_table_fly_the_same_bits() {
    let default = Scenario::default_scenario().unwrap();
    assert!(!format!("{default:?}").contains("gravity"));
    let explicit = with_gravity("model = \"j2\"").unwrap();
    let (a, b) = (flown(&default, 500), flown(&explicit, 500));
    assert_eq!(a.position_m, b.position_m);
    assert_eq!(a.velocity_mps, b.velocity_mps);
}

/// Over 4 s of the default coast the field changes the truth's velocity by the integral of the
/// remainder along the path (trapezoidal rule on the full evaluation at both ends: its
/// error and the Taylor model's are far below the 1e-3 tolerance).
#[test]
fn egm2008_field_moves_the_truth_by_its_remainder() {
    let default = Scenario::default_scenario().unwrap();
    let field = with_gravity("model = \"egm2008\"\ndegree = 20\norder = 20").unwrap();
    let frames = 2000;
    let (start, plain, perturbed) = (
        *TruthSimulator::from_scenario(&default).unwrap().state(),
        flown(&default, frames),
        flown(&field, frames),
    );
    let launch = nav_sim::setup::launch::Launch::new(&field).unwrap();
    let remainder = RotatingRemainder::new(EGM2008_GFC, 20, 20, launch.frame).unwrap();
    let at = |state: &nav_sim::setup::launch::TruthState| {
        remainder
            .acceleration_mps2(state.time_s, &state.position_m)
            .unwrap()
    };
    let elapsed_s = plain.time_s - start.time_s;
    let expected = (at(&start) + at(&plain)) * (0.5 * elapsed_s);
    let got = perturbed.velocity_mps - plain.velocity_mps;
    println!("Δv after {elapsed_s} s: {got} (expected {expected})");
    assert!(expected.norm() > 1.0e-4);
    assert!((got - expected).norm() < 1.0e-3 * expected.norm());
}

#[test]
fn gravity_table_errors_name_the_key() {
    let cases = [
        (
            "model = \"egm2008\"\ndegree = 61\norder = 0",
            "gravity.degree = 61 must be in 2..=60",
        ),
        (
            "model = \"egm2008\"\ndegree = 1\norder = 0",
            "gravity.degree = 1 must be in 2..=60",
        ),
        (
            "model = \"egm2008\"\ndegree = 8\norder = 9",
            "gravity.order = 9 must be in 0..=gravity.degree (8)",
        ),
        (
            "model = \"egm2008\"\ndegree = 8",
            "gravity.order is required with a published model",
        ),
        (
            "model = \"j2\"\ndegree = 8",
            "gravity.degree must be absent with model = \"j2\"",
        ),
        ("model = \"egm96\"", "unknown variant `egm96`"),
        (
            "model = \"j2\"\nmax_degree = 3",
            "unknown field `max_degree`",
        ),
    ];
    for (table, expected) in cases {
        let message = with_gravity(table).unwrap_err().to_string();
        assert!(message.contains(expected), "{table:?}: {message}");
    }
}

/// The flight build's constants (`nav-core/src/gravity/egm2008.rs`, generated by
/// `scripts/generate_flight_gravity.py`) are the model file's, bit for bit: `GM`, `a`, every
/// `C̄_nm`, `S̄_nm` to degree 12, and the per-degree power of degrees 13–60 (summed over
/// m = 0..=n in the same order).
#[test]
fn flight_gravity_constants_are_the_model_file() {
    use nav_core::gravity::egm2008;
    let file = parse_gfc(EGM2008_GFC, 60, 60).unwrap();
    assert_eq!(egm2008::GM_M3_S2.to_bits(), file.gm_m3_s2.to_bits());
    assert_eq!(egm2008::RADIUS_M.to_bits(), file.radius_m.to_bits());
    let index = |n: usize, m: usize| n * (n + 1) / 2 + m;
    for n in 0..=egm2008::FLIGHT_MAX_DEGREE {
        for m in 0..=n {
            let at = index(n, m);
            assert_eq!(egm2008::C[at].to_bits(), file.c[at].to_bits(), "C {n} {m}");
            assert_eq!(egm2008::S[at].to_bits(), file.s[at].to_bits(), "S {n} {m}");
        }
    }
    for n in egm2008::FLIGHT_MAX_DEGREE + 1..=egm2008::TAIL_MAX_DEGREE {
        let power = (0..=n).fold(0.0, |sum, m| {
            let at = index(n, m);
            sum + (file.c[at] * file.c[at] + file.s[at] * file.s[at])
        });
        let stored = egm2008::TAIL_DEGREE_POWER[n - egm2008::FLIGHT_MAX_DEGREE - 1];
        assert_eq!(stored.to_bits(), power.to_bits(), "degree {n}");
    }
}

/// The flight's sliced evaluation (nav-core `gravity::harmonics`) against the truth's
/// (checked against pyshtools above) at the same degree and order, at points from 200 to
/// 2,000 km and times up to a day: the same field to 1e-12 of its size. And the flight's
/// omitted RMS against the truth's field: the RMS over 2,000 random directions at 500 km of
/// the 60 x 60 remainder minus the flight model is the flight's figure within 5 %.
#[test]
fn flight_field_is_the_truths_field() {
    use nav_core::gravity::harmonics::{FieldModel, FieldRemainder};
    use rand::{Rng, SeedableRng};
    let frame = nav_core::frames::LaunchFrame::new(
        &Scenario::default_scenario().unwrap().launch_site.nav_site(),
    )
    .unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(33);
    let mut unit = || {
        let v = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0f64),
        );
        v / v.norm()
    };
    let centre = *frame.earth_centre_launch_m();
    let mut worst: f64 = 0.0;
    for (degree, order) in [(2u8, 2u8), (4, 0), (6, 3), (8, 8), (12, 12)] {
        let model = FieldModel {
            degree,
            order,
            terms_per_frame: 7,
        };
        let truth =
            RotatingRemainder::new(EGM2008_GFC, degree.into(), order.into(), frame).unwrap();
        for (altitude_m, time_s) in [(200.0e3, 0.0), (500.0e3, 3_000.0), (2.0e6, 86_400.0)] {
            let position = centre + unit() * (6.4e6 + altitude_m);
            let mut flight = FieldRemainder::EMPTY;
            flight.configure(model).unwrap();
            for _ in 0..model.frames_per_evaluation() {
                flight.advance(&frame, time_s, &position).unwrap();
            }
            let expected = truth.acceleration_mps2(time_s, &position).unwrap();
            let error = (flight.acceleration_launch_mps2() - expected).norm() / expected.norm();
            worst = worst.max(error);
        }
    }
    println!("flight field against the truth's: worst {worst:.2e} relative");
    assert!(worst < 1e-12);

    let model = FieldModel {
        degree: 8,
        order: 8,
        terms_per_frame: 50,
    };
    let full = RotatingRemainder::new(EGM2008_GFC, 60, 60, frame).unwrap();
    let flown = RotatingRemainder::new(EGM2008_GFC, 8, 8, frame).unwrap();
    let radius_m = nav_core::gravity::egm2008::RADIUS_M + 500.0e3;
    let (mut sum_squares, mut reported) = (0.0, 0.0);
    let samples = 2_000;
    for _ in 0..samples {
        let position = centre + unit() * radius_m;
        let omitted = full.acceleration_mps2(0.0, &position).unwrap()
            - flown.acceleration_mps2(0.0, &position).unwrap();
        sum_squares += omitted.norm_squared();
        let mut flight = FieldRemainder::EMPTY;
        flight.configure(model).unwrap();
        for _ in 0..model.frames_per_evaluation() {
            flight.advance(&frame, 0.0, &position).unwrap();
        }
        reported = flight.omitted_rms_mps2();
    }
    let sampled = (sum_squares / f64::from(samples)).sqrt();
    println!("omitted beyond 8 x 8 at 500 km: sampled {sampled:.3e}, flight {reported:.3e} m/s²");
    assert!((sampled / reported - 1.0).abs() < 0.05);
}

/// A flight gravity model of higher degree or order than the simulated truth's is refused,
/// naming the flight key and the truth's: its filter would model terms the vehicle never
/// flies in. Equal to the truth's, or below it, is accepted.
#[test]
fn a_flight_model_beyond_the_truths_field_is_refused_naming_both_keys() {
    let refusal = |truth: Option<&str>, degree: u8, order: u8| {
        let mut scenario = match truth {
            Some(table) => with_gravity(table).unwrap(),
            None => Scenario::default_scenario().unwrap(),
        };
        scenario.filter.gravity.degree = degree;
        scenario.filter.gravity.order = order;
        scenario.validate().err().map(|error| error.to_string())
    };
    let egm_8_by_2 = Some("model = \"egm2008\"\ndegree = 8\norder = 2");
    for (truth, degree, order, expected) in [
        (
            egm_8_by_2,
            12,
            2,
            "filter.gravity.degree = 12 is above the simulated truth's gravity.degree = 8",
        ),
        (
            egm_8_by_2,
            8,
            4,
            "filter.gravity.order = 4 is above the simulated truth's gravity.order = 2",
        ),
        (
            None,
            4,
            4,
            "filter.gravity.degree = 4 is above the simulated truth's gravity.degree (point mass \
             + J2: no [gravity] table or model = \"j2\") = 2",
        ),
        (
            Some("model = \"j2\""),
            2,
            1,
            "filter.gravity.order = 1 is above the simulated truth's gravity.order (point mass \
             + J2",
        ),
    ] {
        let message = refusal(truth, degree, order).expect(expected);
        assert!(message.contains(expected), "{message}");
    }
    assert_eq!(refusal(egm_8_by_2, 8, 2), None);
    assert_eq!(refusal(egm_8_by_2, 4, 0), None);
    assert_eq!(refusal(None, 2, 0), None);
}
