//! The runs of a campaign: run `k` has the seed `scenario seed + k`, and its record is its
//! index with what it left for the statistics; [`fly_runs`] flies a list of them.

use crate::campaign::monte_carlo::{self, MonteCarloError, RunOutcome};
use crate::harness::flight::FlightError;
use crate::scenario::Scenario;

/// The most runs one campaign may have: each run's record (final covariance, consistency over
/// time) takes about 8 KB, so 100,000 runs hold under 1 GB in the process that reports them,
/// and take about two weeks of one core's time (shard them across a cluster,
/// docs/guide/monte-carlo.md).
pub const MAX_RUNS: u64 = 100_000;

/// The seed of run `run`: the scenario's seed plus the run index (wrapping).
pub fn run_seed(scenario: &Scenario, run: u64) -> u64 {
    scenario.simulation.seed.wrapping_add(run)
}

/// One run of a campaign: its index and what it left for the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    /// The run index `k` (seed = scenario seed + `k`).
    pub run: u64,
    /// The run's outcome.
    pub outcome: RunOutcome,
}

/// Flies the given runs of the campaign of `scenario` in parallel (rayon), in the order given,
/// calling `progress` once per finished run (from the rayon workers; `&|| {}` for none).
///
/// # Errors
/// [`MonteCarloError::Run`] with the seed of a failed flight.
pub fn fly_runs(
    scenario: &Scenario,
    runs: &[u64],
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<RunRecord>, MonteCarloError<FlightError>> {
    let seeds: Vec<u64> = runs.iter().map(|&run| run_seed(scenario, run)).collect();
    let outcomes = monte_carlo::fly_campaign(scenario, &seeds, progress)?;
    Ok(runs
        .iter()
        .zip(outcomes)
        .map(|(&run, outcome)| RunRecord { run, outcome })
        .collect())
}
