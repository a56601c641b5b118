//! Consistency over time: every recorded sample of a flight carries the NEES of the 15
//! calibration states and the NIS of each aiding sensor since the previous sample; a Monte
//! Carlo campaign averages them per instant with their 95 % χ² intervals and plots them.

use nav_sim::campaign::monte_carlo::{fly_campaign, over_time, summarise};
use nav_sim::harness::flight::{fly, FlightOptions, FlightResult};
use nav_sim::setup::prior::with_truth_drawn_from_prior;

use crate::common;

fn flight(seed: u64) -> FlightResult {
    let scenario = with_truth_drawn_from_prior(&common::short_scenario(), seed);
    fly(&scenario, FlightOptions::default(), |_, _| {}).unwrap()
}

#[test]
fn samples_carry_the_nees_and_the_interval_nis_of_the_flight() {
    let result = flight(2000);
    let last = result.last().unwrap();
    let at_end = result.calibration_nees().unwrap();
    // Same error, same covariance, same arithmetic: the same bits.
    assert_eq!(last.calibration_nees.unwrap().to_bits(), at_end.to_bits());
    assert!(result
        .samples
        .iter()
        .all(|sample| sample.calibration_nees.is_some_and(f64::is_finite)));

    let star: u64 = result.samples.iter().map(|s| s.star_nis.updates).sum();
    let gnss: u64 = result.samples.iter().map(|s| s.gnss_nis.updates).sum();
    assert_eq!(star, result.star_nis.updates);
    assert_eq!(gnss, result.gnss_nis.updates);
    assert!(star > 0 && gnss > 0, "{star} {gnss}");
    let star_sum: f64 = result.samples.iter().map(|s| s.star_nis.sum).sum();
    assert!((star_sum / result.star_nis.sum - 1.0).abs() < 1e-12);

    // The campaign's thinned series keeps the totals, the first and the last instant.
    let series = over_time(&result.samples);
    assert!(series.len() <= nav_sim::campaign::monte_carlo::OVER_TIME_POINTS + 1);
    let thinned: u64 = series.iter().map(|point| point.star_nis.updates).sum();
    assert_eq!(thinned, result.star_nis.updates);
    let thinned: u64 = series.iter().map(|point| point.gnss_nis.updates).sum();
    assert_eq!(thinned, result.gnss_nis.updates);
    assert_eq!(
        series.last().unwrap().time_s.to_bits(),
        last.time_s.to_bits()
    );
    assert_eq!(
        series.last().unwrap().nees.unwrap().to_bits(),
        at_end.to_bits()
    );
}

#[test]
fn campaign_summary_has_the_consistency_over_time_and_plots_it() {
    let seeds: Vec<u64> = (0..3).map(|run| 3000 + run).collect();
    let outcomes = fly_campaign(&common::short_scenario(), &seeds, &|| {}).unwrap();
    let summary = summarise::<15, nav_sim::harness::flight::FlightError>(&outcomes).unwrap();
    let times: Vec<u64> = outcomes[0]
        .over_time
        .iter()
        .map(|point| point.time_s.to_bits())
        .collect();
    assert!(times.len() > 10, "{}", times.len());
    assert_eq!(
        summary
            .over_time
            .iter()
            .map(|point| point.time_s.to_bits())
            .collect::<Vec<_>>(),
        times
    );
    for point in &summary.over_time {
        assert!(point.nees_average.is_finite(), "{point:?}");
        assert!(
            point.nees_lower_bound < 15.0 && 15.0 < point.nees_upper_bound,
            "{point:?}"
        );
        for nis in [&point.star_nis, &point.gnss_nis].into_iter().flatten() {
            assert!(nis.average.is_finite(), "{point:?}");
            assert!(nis.lower_bound < 3.0 && 3.0 < nis.upper_bound, "{point:?}");
        }
    }
    assert!(summary
        .over_time
        .iter()
        .any(|point| point.star_nis.is_some()));
    assert!(summary
        .over_time
        .iter()
        .any(|point| point.gnss_nis.is_some()));
    // The last instant's average is the summary's end-of-flight NEES.
    let last = summary.over_time.last().unwrap();
    assert!((last.nees_average / summary.nees.average - 1.0).abs() < 1e-6);

    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("nees_over_time.png");
    summary.plot_over_time(&path).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 0);
    if let Ok(keep) = std::env::var("NAV_SIM_KEEP_PLOTS") {
        std::fs::copy(
            &path,
            std::path::Path::new(&keep).join("nees_over_time.png"),
        )
        .unwrap();
    }
}
