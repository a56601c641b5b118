//! The fault-injection campaign (`nav_sim::studies::faults`, also
//! `nav-sim faults`) over the default scenario, its table printed, every row met.
//!
//! Ignored in the plain `cargo test --workspace` (it flies one 800 s flight per fault class):
//! `scripts/test.sh` runs it once, in its own step, with `--include-ignored --nocapture` so the
//! table is in the test command's output, and compares the table with the committed
//! `tests-host/change_indication/faults-default.md` (`NAV_RESULTS_BLESS=1` rewrites it).
//! `NAV_FAULT_ROWS=text` flies only the rows whose name contains `text` (nothing is then
//! compared).

use nav_sim::studies::faults::run_campaign_rows;
use nav_sim::Scenario;

#[test]
#[ignore = "the campaign (about a minute): scripts/test.sh runs it with --include-ignored"]
fn every_fault_class_is_survived_counted_and_leaves_the_calibration_consistent() {
    let scenario = Scenario::default_scenario().unwrap();
    let selected = std::env::var("NAV_FAULT_ROWS").ok();
    let select = |class: &nav_sim::studies::faults::FaultClass| {
        selected
            .as_deref()
            .is_none_or(|text| class.name.contains(text))
    };
    let result = run_campaign_rows(&scenario, select, |_, _| {}).unwrap();
    println!("{}", result.table());
    println!("{}", result.summary_line());
    let measured = format!("{}\n{}\n", result.table(), result.measured_summary_line());
    // The whole campaign is `nav-sim faults`: its table is committed beside the default
    // flight's change indication (too long for the docs, which link it).
    if selected.is_none() {
        tests_host::docs::check_committed(
            &tests_host::project_root().join("tests-host/change_indication/faults-default.md"),
            &nav_sim::output::results::render("nav-sim faults", &measured),
        );
    }
    let failed: Vec<&str> = result
        .outcomes
        .iter()
        .filter(|outcome| !outcome.met())
        .map(|outcome| outcome.name)
        .collect();
    assert!(failed.is_empty(), "rows not met: {failed:?}");
    assert_eq!(result.outcomes.len(), result.classes.len());
    assert!(!result.outcomes.is_empty(), "no row selected");
}
