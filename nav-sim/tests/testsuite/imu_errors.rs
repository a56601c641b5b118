//! Monte Carlo of the default flight with the IMU as it is (docs/imu-errors.md): a bias
//! instability the flight software is told of keeps it consistent (the average NEES of the 15
//! calibration states inside its two-sided 95 % χ² interval, no run's state beyond 4σ).
//!
//! `NAV_MC_RUNS` sets the runs (default 6, the test command's size; the docs' campaigns use
//! `nav-sim monte-carlo … --runs 20`); `NAV_MC_FIRST_RUN` offsets the seeds.

use crate::realistic_campaign::{fly, print, scenario};

/// Largest |error| / σ any run's calibration state may end at.
const WORST_SIGMA_BOUND: f64 = 4.0;

#[test]
fn a_bias_instability_the_filter_is_told_of_keeps_it_consistent() {
    let name = "imu_bias_instability";
    let campaign = fly(&scenario(name));
    print(name, &campaign);
    assert!(campaign.consistent, "{name}: {}", campaign.nees_line);
    assert!(
        campaign.worst_sigma <= WORST_SIGMA_BOUND,
        "{name}: a calibration state ended {:.2} sigma off (seed {})",
        campaign.worst_sigma,
        campaign.worst_seed
    );
}
