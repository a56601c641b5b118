//! False alarms of the consistency flags on clean flights: over a campaign of a flight whose
//! truth is what the flight software is told, each flag of
//! `nav_fsw::health::HealthCounters::CONSISTENCY_FLAGS` raised in how many runs, and that
//! fraction (the false-alarm rate per flight) with its exact 95 % interval.
//!
//! **Interval** (Clopper and Pearson, "The use of confidence or fiducial limits illustrated in
//! the case of the binomial", Biometrika 26(4), 1934): for `k` runs raised of `n`, the lower
//! bound is the 2.5 % quantile of Beta(k, n − k + 1) (0 for `k` = 0), the upper the 97.5 %
//! quantile of Beta(k + 1, n − k) (1 for `k` = `n`); its coverage is at least 95 % whatever the
//! rate. With no run raised the upper bound is `1 − 0.025^(1/n)`, so 100 clean runs bound a
//! rate below 3.6 % and 300 below 1.2 %.

use std::fmt::Write as _;

use nav_fsw::health::HealthCounters;
use statrs::distribution::{Beta, ContinuousCDF};

use super::RunRecord;
use crate::output::scenario_label::ScenarioLabel;

/// The most a flag an operator acts on may raise on clean flights.
pub const MAX_FALSE_ALARM_RATE: f64 = 0.01;

/// One flag over a campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct FlagRate {
    /// The flag's counter name.
    pub flag: &'static str,
    /// Runs whose final counter is non-zero.
    pub runs_raised: u64,
    /// Runs flown.
    pub runs: u64,
    /// The exact (Clopper–Pearson) two-sided 95 % interval of the rate.
    pub interval_95: [f64; 2],
}

impl FlagRate {
    /// The measured rate, `runs_raised / runs`.
    pub fn rate(&self) -> f64 {
        self.runs_raised as f64 / self.runs.max(1) as f64
    }
}

/// The Clopper–Pearson two-sided 95 % interval of a binomial rate with `raised` of `runs`
/// (module docs); `[0, 1]` for no runs.
pub fn clopper_pearson_95(raised: u64, runs: u64) -> [f64; 2] {
    if runs == 0 || raised > runs {
        return [0.0, 1.0];
    }
    let (k, n) = (raised as f64, runs as f64);
    let quantile = |a: f64, b: f64, p: f64| Beta::new(a, b).map_or(f64::NAN, |d| d.inverse_cdf(p));
    // At the ends the Beta quantiles have closed forms: Beta(1, n) and Beta(n, 1).
    let lower = match raised {
        0 => 0.0,
        _ if raised == runs => 0.025_f64.powf(1.0 / n),
        _ => quantile(k, n - k + 1.0, 0.025),
    };
    let upper = match raised {
        0 => 1.0 - 0.025_f64.powf(1.0 / n),
        _ if raised == runs => 1.0,
        _ => quantile(k + 1.0, n - k, 0.975),
    };
    [lower, upper]
}

/// Every consistency flag over `records`: runs raised, runs, interval.
pub fn flag_rates(records: &[RunRecord]) -> Vec<FlagRate> {
    let runs = records.len() as u64;
    HealthCounters::CONSISTENCY_FLAGS
        .iter()
        .map(|&flag| {
            let runs_raised = records
                .iter()
                .filter(|record| record.outcome.health.get(flag).is_some_and(|v| *v > 0))
                .count() as u64;
            FlagRate {
                flag,
                runs_raised,
                runs,
                interval_95: clopper_pearson_95(runs_raised, runs),
            }
        })
        .collect()
}

/// The false-alarm table of a clean campaign of `scenario` as Markdown: one row per flag,
/// then the runs that raised any flag (their seeds, to fly them again).
pub fn false_alarm_text(scenario: &ScenarioLabel, records: &[RunRecord]) -> String {
    let rates = flag_rates(records);
    let mut text = String::new();
    let _ = writeln!(text, "{}", scenario.line());
    let _ = writeln!(
        text,
        "consistency flags on clean flights: runs raised of {} (95 % interval: Clopper–Pearson)\n",
        records.len()
    );
    let _ = writeln!(text, "| flag | runs raised | runs | rate | 95 % interval |");
    let _ = writeln!(text, "|---|---:|---:|---:|---|");
    for rate in &rates {
        let [lower, upper] = rate.interval_95;
        let _ = writeln!(
            text,
            "| `{}` | {} | {} | {:.2} % | [{:.2} %, {:.2} %] |",
            rate.flag,
            rate.runs_raised,
            rate.runs,
            100.0 * rate.rate(),
            100.0 * lower,
            100.0 * upper
        );
    }
    let raised: Vec<String> = records
        .iter()
        .filter(|record| {
            HealthCounters::CONSISTENCY_FLAGS
                .iter()
                .any(|flag| record.outcome.health.get(*flag).is_some_and(|v| *v > 0))
        })
        .map(|record| format!("run {} (seed {})", record.run, record.outcome.seed))
        .collect();
    let _ = writeln!(
        text,
        "\nruns with a flag raised: {}",
        if raised.is_empty() {
            "none".to_string()
        } else {
            raised.join(", ")
        }
    );
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interval against its closed forms: none raised, `[0, 1 − 0.025^(1/n)]`; all raised,
    /// `[0.025^(1/n), 1]`; and a textbook value (Clopper–Pearson 95 % for 3 of 40:
    /// [0.0157, 0.2039]).
    #[test]
    fn the_interval_has_its_closed_forms() {
        let [lower, upper] = clopper_pearson_95(0, 100);
        assert_eq!(lower.to_bits(), 0.0_f64.to_bits());
        assert!(
            (upper - (1.0 - 0.025_f64.powf(0.01))).abs() < 1e-9,
            "{upper}"
        );
        let [lower, upper] = clopper_pearson_95(100, 100);
        assert!((lower - 0.025_f64.powf(0.01)).abs() < 1e-9, "{lower}");
        assert_eq!(upper.to_bits(), 1.0_f64.to_bits());
        let [lower, upper] = clopper_pearson_95(3, 40);
        assert!((lower - 0.0157).abs() < 5e-4, "{lower}");
        assert!((upper - 0.2039).abs() < 5e-4, "{upper}");
    }
}
