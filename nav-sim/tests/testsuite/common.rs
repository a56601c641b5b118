//! Shared test scenarios.

use nav_sim::campaign::monte_carlo::{fly_campaign, RunOutcome};
use nav_sim::scenario::ManoeuvreSegment;
use nav_sim::Scenario;

/// A manoeuvre segment: body rate (deg/s) and specific force (m/s²) held for `duration_s`,
/// reached over `ramp_s`.
pub fn segment(
    label: &str,
    duration_s: f64,
    ramp_s: f64,
    rate: [f64; 3],
    force: [f64; 3],
) -> ManoeuvreSegment {
    ManoeuvreSegment {
        label: label.to_string(),
        duration_s,
        ramp_s,
        body_rate_deg_per_s: rate,
        specific_force_mps2: force,
    }
}

/// 42 s with a 4 Hz star sensor and 1 Hz GNSS: 10 s coast, 12 s rotation about z at 100 °/s, 20 s coast (21,000 frames).
pub fn short_scenario() -> Scenario {
    let mut scenario = Scenario::default_scenario().unwrap();
    let segment = |label: &str, duration_s: f64, ramp_s: f64, rate: [f64; 3]| {
        segment(label, duration_s, ramp_s, rate, [0.0; 3])
    };
    scenario.manoeuvres = vec![
        segment("coast", 10.0, 0.0, [2.4e-4; 3]),
        segment("rotate z", 12.0, 1.0, [0.0, 0.0, 100.0]),
        segment("coast", 20.0, 0.0, [2.4e-4; 3]),
    ];
    // Rates the tests' counts are written for (the default scenario may change them).
    scenario.star_sensor.rate_hz = 4.0;
    scenario.gnss.rate_hz = 1.0;
    scenario.validate().unwrap();
    scenario
}

/// The health counters a consistent flight with healthy sensors never raises: the aids' and
/// the tracker heads' consistency verdicts, the star noise matching they engage, a head the
/// flight software lacks, an aberration left in and the fault declarations.
pub const QUIET_COUNTERS: [&str; 9] = [
    "star_inconsistent",
    "star_aberration_suspected",
    "star_heads_inconsistent",
    "star_unknown_head",
    "star_noise_matched",
    "gnss_inconsistent",
    "gnss_velocity_inconsistent",
    "star_declared_faulty",
    "gnss_declared_faulty",
];

/// The runs of `name` flown: one (the scenario's seed plus `NAV_MC_FIRST_RUN`), or
/// `NAV_MC_RUNS` when set. For the tracker cases, each a whole flight per run.
pub fn one_run_unless_told(name: &str) -> Vec<RunOutcome> {
    let scenario = crate::realistic_campaign::scenario(name);
    let mut seeds = crate::realistic_campaign::seeds(&scenario);
    if std::env::var_os("NAV_MC_RUNS").is_none() {
        seeds.truncate(1);
    }
    fly_campaign(&scenario, &seeds, &|| {}).unwrap()
}

/// A health counter's final value in one run (0 when never raised).
pub fn counted(outcome: &RunOutcome, key: &str) -> u32 {
    outcome.health.get(key).copied().unwrap_or(0)
}

/// The NEES of one run's 15 calibration states.
pub fn nees(outcome: &RunOutcome) -> f64 {
    let inverse = outcome.covariance.try_inverse().unwrap();
    (outcome.error.transpose() * inverse * outcome.error)[(0, 0)]
}

/// Prints one run's worst calibration state, NEES and health counters, and holds the run
/// consistent: every calibration state within 4σ, the NEES below the χ²(15) 99.9 % point.
pub fn assert_run_within_bounds(outcome: &RunOutcome) {
    let (worst, nees) = (
        crate::realistic_campaign::worst_sigma(outcome),
        nees(outcome),
    );
    println!(
        "seed {}: worst {worst:.2} sigma, NEES {nees:.1}, {:?}",
        outcome.seed, outcome.health
    );
    assert!(worst <= 4.0, "seed {}: {worst:.2} sigma", outcome.seed);
    assert!(nees < 37.70, "seed {}: NEES {nees:.1}", outcome.seed);
}

/// The first `seconds` of a scenario's manoeuvre plan (whole segments).
pub fn first_seconds(mut scenario: Scenario, seconds: f64) -> Scenario {
    let mut elapsed = 0.0;
    scenario.manoeuvres.retain(|segment| {
        elapsed += segment.duration_s;
        elapsed <= seconds
    });
    scenario.validate().unwrap();
    scenario
}
