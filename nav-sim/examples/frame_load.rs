//! The two frame loads of the flight software (`covariance.frame_load`) on one scenario:
//! `PropagateThenFuse` (a frame propagates the covariance, then fuses) and
//! `FuseOrPropagate` (a frame does one of the two, the default). Prints each run's
//! calibration NEES, the mean NIS of each sensor and the final errors in units of their
//! 1σ (docs/guide/flight-software.md).
//!
//! `cargo run --release -p nav-sim --example frame_load -- nav-sim/scenarios/default.toml`

use nav_fsw::config::FrameLoad;
use nav_sim::harness::flight::{fly_with, FlightOptions, FlightResult};
use nav_sim::scenario::Scenario;
use nav_sim::setup::fsw::fsw_config;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "nav-sim/scenarios/default.toml".into());
    let scenario = Scenario::load(std::path::Path::new(&path))?;
    println!("{path}");
    for load in [FrameLoad::PropagateThenFuse, FrameLoad::FuseOrPropagate] {
        let mut config = fsw_config(&scenario)?;
        config.covariance.frame_load = load;
        let options = FlightOptions {
            record_interval_s: 1.0,
        };
        let result = fly_with(&scenario, config, options, |_, _| {}, |_, _| {})?;
        report(&format!("{load:?}"), &result);
    }
    Ok(())
}

/// One run's consistency figures and final errors (error / 1σ, two decimals).
fn report(name: &str, result: &FlightResult) {
    let mean = |sum: f64, updates: u64| sum / updates.max(1) as f64;
    let Some(last) = result.last() else {
        println!("{name}: no samples");
        return;
    };
    let ratio = |error: f64, sigma: f64| format!("{:+.2}", error / sigma);
    let calibration: Vec<String> = (0..5)
        .flat_map(|block| {
            (0..3).map(move |axis| {
                ratio(
                    last.estimate[block][axis] - last.truth[block][axis],
                    last.sigma[block][axis],
                )
            })
        })
        .collect();
    let attitude: Vec<String> = (0..3)
        .map(|a| ratio(last.attitude_error_rad[a], last.attitude_sigma_rad[a]))
        .collect();
    let position: Vec<String> = (0..3)
        .map(|a| ratio(last.position_error_m[a], last.position_sigma_m[a]))
        .collect();
    println!(
        "{name}: calibration NEES {:.2} (15 states); mean NIS star {:.3} ({} updates), GNSS {:.3} ({}); filter resets {}",
        result.calibration_nees().unwrap_or(f64::NAN),
        mean(result.star_nis.sum, result.star_nis.updates),
        result.star_nis.updates,
        mean(result.gnss_nis.sum, result.gnss_nis.updates),
        result.gnss_nis.updates,
        result.health.filter_resets,
    );
    println!("  calibration error/1σ: {}", calibration.join(" "));
    println!(
        "  attitude error/1σ: {}; position error/1σ: {}",
        attitude.join(" "),
        position.join(" ")
    );
}
