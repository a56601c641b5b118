//! Fault rows 30–31: a correlated GNSS drift, with and without its states in the filter.

use super::*;

/// The correlated-drift rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    let none = [0, 0];
    let calibration = Criterion::CalibrationWithinBound;
    vec![
        FaultClass {
            name: "GNSS correlated drift",
            injected: "a Gauss–Markov position error on every fix for 600 s: 8 m per ECEF axis, \
                       τ = 300 s (on top of the white noise); the filter is given the receiver's \
                       specification (filter.gnss_correlated_sigma_m = 8, \
                       gnss_correlation_time_s = 300)",
            reaction: "followed by the three correlated-error states; nothing refused, the \
                       innovations stay white",
            counts: vec![
                (counter!(filter_errors), Expected::Exactly(0)),
                (counter!(gnss_innovations_correlated), Expected::Exactly(0)),
            ],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: calibration,
            scenario_change: Some(|scenario| {
                scenario.filter.gnss_correlated_sigma_m = DRIFT_SIGMA_M;
                scenario.filter.gnss_correlation_time_s = DRIFT_CORRELATION_TIME_S;
            }),
            injector: |f| {
                let mut drift = GaussMarkovDrift::new(DRIFT_SIGMA_M, DRIFT_CORRELATION_TIME_S);
                let drifting = 0..f.frames(600.0);
                Box::new(move |relative, ports| {
                    if !drifting.contains(&relative) {
                        return;
                    }
                    for fix in ports.gnss.0.iter_mut() {
                        let error = drift.at(fix.gps_seconds_of_week);
                        for (value, e) in fix.position_ecef_m.iter_mut().zip(error) {
                            *value += e;
                        }
                    }
                })
            },
        },
        FaultClass {
            name: "GNSS correlated drift, not modelled",
            injected: "the drift of the row above with the filter left at white errors (the \
                       paper's model)",
            reaction: "the filter cannot stay consistent; the serially correlated innovations \
                       are counted, so the overconfidence is not silent",
            counts: vec![(counter!(gnss_innovations_correlated), Expected::AtLeast(1))],
            injection_s: 600.0,
            declared_faulty: none,
            criterion: Criterion::CountedOnly,
            scenario_change: None,
            injector: |f| {
                let mut drift = GaussMarkovDrift::new(DRIFT_SIGMA_M, DRIFT_CORRELATION_TIME_S);
                let drifting = 0..f.frames(600.0);
                Box::new(move |relative, ports| {
                    if !drifting.contains(&relative) {
                        return;
                    }
                    for fix in ports.gnss.0.iter_mut() {
                        let error = drift.at(fix.gps_seconds_of_week);
                        for (value, e) in fix.position_ecef_m.iter_mut().zip(error) {
                            *value += e;
                        }
                    }
                })
            },
        },
    ]
}
