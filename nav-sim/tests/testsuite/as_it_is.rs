//! The vehicle-as-it-is flights (`as_it_is.toml`, `upper_stage_as_it_is.toml`: every effect
//! nav-sim models at once, the flight software configured from the data sheets) resolve,
//! validate and fly their first minutes as a campaign run (their dispersions drawn)
//! consistently: the NEES of the calibration states below its χ²(15) 99.9 % point, every
//! estimated state within 4σ, no sensor declared faulty and the gravity allowance not short.
//! Their 40-run campaigns are in docs/results (docs/guide/realistic-errors.md).

use crate::common::first_seconds;
use crate::realistic_campaign::scenario;
use nav_sim::campaign::monte_carlo::{fly_campaign, run_nees};

/// The χ²(15) 99.9 % point.
const NEES_BOUND: f64 = 37.7;

/// No state of a campaign run beyond this many σ.
const MAX_SIGMAS: f64 = 4.0;

/// The largest |e|/σ of a block's `error` and `covariance`.
fn worst<const N: usize>(
    error: &nalgebra::SVector<f64, N>,
    covariance: &nalgebra::SMatrix<f64, N, N>,
) -> f64 {
    (0..N)
        .map(|k| error[k].abs() / covariance[(k, k)].sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn the_vehicle_as_it_is_flies_its_first_minutes_consistently() {
    for name in ["as_it_is", "upper_stage_as_it_is"] {
        let scenario = first_seconds(scenario(name), 400.0);
        let seed = scenario.simulation.seed;
        let outcome = fly_campaign(&scenario, &[seed], &|| {}).unwrap().remove(0);
        let nees = run_nees(&outcome).unwrap();
        let imu = outcome.imu_error.as_ref().unwrap();
        let gnss = outcome.gnss_error.as_ref().unwrap();
        let sigmas = [
            worst(&outcome.error, &outcome.covariance),
            worst(&imu.error, &imu.covariance),
            worst(&gnss.error, &gnss.covariance),
        ];
        println!(
            "{name}: NEES {nees:.2}, worst σ {sigmas:?}, {:?}",
            outcome.health
        );
        assert!(nees < NEES_BOUND, "{name}: NEES {nees}");
        assert!(sigmas.iter().all(|&s| s < MAX_SIGMAS), "{name}: {sigmas:?}");
        for counter in [
            "star_declared_faulty",
            "gnss_declared_faulty",
            "gravity_allowance_short",
        ] {
            assert_eq!(outcome.health.get(counter), None, "{name}: {counter}");
        }
    }
}
