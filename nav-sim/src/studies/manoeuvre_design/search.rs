//! The search of `nav-sim design`: coordinate descent over the template's parameters, each
//! candidate schedule analysed coarsely ([`SEARCH_OPTIONS`]), the chosen one again at every
//! epoch ([`FINAL_OPTIONS`]).

use std::time::Instant;

use super::{
    Constraints, GridPoint, ManoeuvreDesignError, Mission, TemplateParameters, COORDINATES,
    MAX_PASSES, PLACEMENTS, RATE_MARGIN, SHARES, SLEWS, TRANSLATION_GAPS_S,
};
use crate::scenario::{ManoeuvreSegment, Scenario};
use crate::studies::covariance_design::{analyse, DesignOptions, DesignReport};

/// Two ratios within this relative difference are a tie, decided by the next-worst ratio.
const TIE_TOLERANCE: f64 = 0.02;

/// One analysed candidate: its `σ / target` ratios, worst first.
#[derive(Debug, Clone)]
struct Evaluation {
    ratios: Vec<f64>,
}

impl Evaluation {
    fn of(report: &DesignReport) -> Self {
        let mut ratios: Vec<f64> = report.rows.iter().map(|row| row.ratio()).collect();
        ratios.sort_by(|a, b| b.total_cmp(a));
        Self { ratios }
    }

    /// A lower worst ratio; within [`TIE_TOLERANCE`] of each other, a lower next-worst, and
    /// so on: when the worst axis is out of reach, the others still improve.
    fn better_than(&self, other: &Self) -> bool {
        for (mine, theirs) in self.ratios.iter().zip(&other.ratios) {
            if (mine - theirs).abs() > TIE_TOLERANCE * theirs {
                return mine < theirs;
            }
        }
        false
    }
}

/// The coarse analysis of the search (module docs).
pub const SEARCH_OPTIONS: DesignOptions = DesignOptions {
    step_frames: 1000,
    truth_substeps_per_frame: Some(1),
    gravity_gradient: true,
    process_noise: None,
    measurement_stride: 20,
    second_order_attitude: true,
};

/// The analysis of the chosen schedule: every measurement epoch, steps of at most 0.1 s.
pub const FINAL_OPTIONS: DesignOptions = DesignOptions {
    step_frames: 50,
    truth_substeps_per_frame: Some(2),
    gravity_gradient: true,
    process_noise: None,
    measurement_stride: 1,
    second_order_attitude: true,
};

/// The result of a design.
#[derive(Debug, Clone)]
pub struct ManoeuvreDesign {
    /// The chosen template parameters.
    pub parameters: TemplateParameters,
    /// The input scenario with the designed schedule.
    pub scenario: Scenario,
    /// The full-rate covariance analysis of the designed schedule.
    pub report: DesignReport,
    /// Candidates analysed in the search.
    pub evaluations: usize,
    /// Wall time of the search (s).
    pub search_wall_s: f64,
    /// Wall time of the final analysis, and of the input schedule's when it is made (s).
    pub final_wall_s: f64,
    /// `Σ |Δv|` of the translations (m/s).
    pub lateral_delta_v_mps: f64,
    /// Input mission segments left out (they end after the flight time).
    pub left_out: Vec<String>,
    /// With the systematic IMU error states (`[filter.imu_errors]`): the full-rate analysis
    /// of the input schedule, to set the designed one's twelve states against.
    pub input_report: Option<DesignReport>,
}

/// The search space: values per coordinate.
struct SearchSpace {
    rates: Vec<f64>,
    returns: Vec<(usize, f64)>,
    lateral_axes: usize,
}

impl SearchSpace {
    fn sizes(&self) -> GridPoint {
        let shares = if self.lateral_axes > 1 {
            SHARES.len()
        } else {
            1
        };
        [
            self.rates.len(),
            SLEWS.len(),
            shares,
            PLACEMENTS.len(),
            self.returns.len(),
            TRANSLATION_GAPS_S.len(),
        ]
    }

    fn parameters(&self, point: &GridPoint) -> Option<TemplateParameters> {
        let [rate, slews, share, outbound, slot, gap] = *point;
        let (return_window, return_placement) = *self.returns.get(slot)?;
        let (turns_per_slew, slew_rounds) = *SLEWS.get(slews)?;
        Some(TemplateParameters {
            slew_rate_deg_per_s: *self.rates.get(rate)?,
            turns_per_slew,
            slew_rounds,
            first_axis_share: if self.lateral_axes > 1 {
                *SHARES.get(share)?
            } else {
                1.0
            },
            outbound_placement: *PLACEMENTS.get(outbound)?,
            return_window,
            return_placement,
            translation_gap_s: *TRANSLATION_GAPS_S.get(gap)?,
        })
    }
}

/// `scenario` with `manoeuvres`, if it passes [`Scenario::validate`].
fn with_schedule(scenario: &Scenario, manoeuvres: Vec<ManoeuvreSegment>) -> Option<Scenario> {
    let mut designed = scenario.clone();
    designed.manoeuvres = manoeuvres;
    designed.validate().ok().map(|()| designed)
}

/// The analysis of one candidate, `None` if it does not fit, fails validation or the
/// minimum altitude, or the analysis fails.
fn evaluate(
    scenario: &Scenario,
    mission: &Mission,
    constraints: &Constraints,
    parameters: &TemplateParameters,
    options: &DesignOptions,
) -> Option<(Scenario, DesignReport)> {
    let designed = with_schedule(scenario, mission.schedule(constraints, parameters)?)?;
    let report = analyse(&designed, options).ok()?;
    (report.orbit.minimum_altitude_m >= designed.simulation.min_altitude_m)
        .then_some((designed, report))
}

/// Searches the template's schedules for `scenario` under `constraints` (module docs) with
/// up to `threads` analyses at once, then analyses the best at the full rate.
///
/// # Errors
/// [`ManoeuvreDesignError::Constraint`] for unusable constraints,
/// [`ManoeuvreDesignError::NoFeasibleSchedule`] if no candidate fits and passes the checks
/// (naming the limit the smallest schedule meets),
/// [`ManoeuvreDesignError::Analysis`] if the final analysis fails.
pub fn design(
    scenario: &Scenario,
    constraints: &Constraints,
    threads: usize,
) -> Result<ManoeuvreDesign, ManoeuvreDesignError> {
    let started = Instant::now();
    let mission = Mission::of(scenario, constraints)?;
    let body_limit = RATE_MARGIN * constraints.max_body_rate_deg_per_s;
    let tracker = scenario.star_sensor.max_rate_deg_per_s;
    let mut rates = vec![if tracker > 0.0 {
        body_limit.min(RATE_MARGIN * tracker)
    } else {
        body_limit
    }];
    if rates.first().is_some_and(|rate| *rate < body_limit) {
        rates.push(body_limit);
    }
    let space = SearchSpace {
        rates,
        returns: mission
            .return_windows()
            .into_iter()
            .flat_map(|window| PLACEMENTS.map(|placement| (window, placement)))
            .collect(),
        lateral_axes: constraints.thrust_axes.len(),
    };
    let sizes = space.sizes();
    let mut cache: Vec<(GridPoint, Option<Evaluation>)> = Vec::new();
    // Start: one round of one turn (the smallest schedule), an even split, the `+` right
    // after the slews, the returns at the end of the last window that can take them.
    let start_index = [0, 0, sizes[2] / 2, 0, sizes[4].saturating_sub(1), 0];
    let mut best_index = start_index;
    let mut best: Option<Evaluation> = None;
    for _ in 0..MAX_PASSES {
        let mut improved = false;
        for coordinate in 0..COORDINATES {
            let size = sizes.get(coordinate).copied().unwrap_or(0);
            let candidates: Vec<GridPoint> = (0..size)
                .map(|value| {
                    let mut index = best_index;
                    if let Some(slot) = index.get_mut(coordinate) {
                        *slot = value;
                    }
                    index
                })
                .filter(|index| cache.iter().all(|(seen, _)| seen != index))
                .collect();
            let results = evaluate_all(
                scenario,
                &mission,
                constraints,
                &space,
                &candidates,
                threads,
            );
            cache.extend(results);
            for (index, evaluation) in &cache {
                let Some(evaluation) = evaluation else {
                    continue;
                };
                let on_line = index
                    .iter()
                    .zip(best_index)
                    .enumerate()
                    .all(|(c, (a, b))| c == coordinate || *a == b);
                if on_line && best.as_ref().is_none_or(|b| evaluation.better_than(b)) {
                    improved |= *index != best_index || best.is_none();
                    best = Some(evaluation.clone());
                    best_index = *index;
                }
            }
        }
        if !improved {
            break;
        }
    }
    let search_wall_s = started.elapsed().as_secs_f64();
    let infeasible =
        |parameters: Option<&TemplateParameters>| ManoeuvreDesignError::NoFeasibleSchedule {
            reason: parameters.map_or_else(
                || "has no parameters (the search space is empty)".to_string(),
                |parameters| why_infeasible(scenario, &mission, constraints, parameters),
            ),
        };
    let Some(parameters) = space.parameters(&best_index).filter(|_| best.is_some()) else {
        let smallest = space.parameters(&start_index);
        return Err(infeasible(smallest.as_ref()));
    };
    let final_started = Instant::now();
    let designed = mission
        .schedule(constraints, &parameters)
        .and_then(|schedule| with_schedule(scenario, schedule))
        .ok_or_else(|| infeasible(Some(&parameters)))?;
    let report = analyse(&designed, &FINAL_OPTIONS)?;
    let input_report = match report.imu_errors {
        Some(_) => Some(analyse(scenario, &FINAL_OPTIONS)?),
        None => None,
    };
    let lateral_delta_v_mps = designed
        .manoeuvres
        .iter()
        .map(|segment| {
            constraints
                .thrust_axes
                .iter()
                .filter_map(|axis| segment.specific_force_mps2.get(*axis))
                .map(|force| force.abs() * (segment.duration_s - segment.ramp_s))
                .sum::<f64>()
        })
        .sum();
    Ok(ManoeuvreDesign {
        parameters,
        scenario: designed,
        report,
        evaluations: cache.len(),
        search_wall_s,
        final_wall_s: final_started.elapsed().as_secs_f64(),
        lateral_delta_v_mps,
        left_out: mission.left_out,
        input_report,
    })
}

/// Why the schedule of `parameters` is not a candidate, naming the limit it meets: it does
/// not fit the mission's coasts, the scenario with it is refused, the covariance analysis
/// fails, or the orbit dips below the scenario's minimum altitude.
fn why_infeasible(
    scenario: &Scenario,
    mission: &Mission,
    constraints: &Constraints,
    parameters: &TemplateParameters,
) -> String {
    let Some(schedule) = mission.schedule(constraints, parameters) else {
        return format!(
            "({} round of {}-turn slews at {:.3} deg/s and the translations of {} m/s of \
             lateral delta-v at {} m/s^2) does not fit the mission's coasts, the longest of \
             which is {:.1} s: raise the max body rate or the lateral acceleration, lower the \
             lateral delta-v, or lengthen the coasts",
            parameters.slew_rounds,
            parameters.turns_per_slew,
            parameters.slew_rate_deg_per_s,
            constraints.lateral_delta_v_mps,
            constraints.max_lateral_acceleration_mps2,
            mission.longest_window_s()
        );
    };
    let mut designed = scenario.clone();
    designed.manoeuvres = schedule;
    if let Err(error) = designed.validate() {
        return format!("is refused as a scenario: {error}");
    }
    match analyse(&designed, &SEARCH_OPTIONS) {
        Err(error) => format!("fails its covariance analysis: {error}"),
        Ok(report) => format!(
            "flies down to {:.0} m, below simulation.min_altitude_m = {:.0} m",
            report.orbit.minimum_altitude_m, designed.simulation.min_altitude_m
        ),
    }
}

/// Analyses `candidates` on up to `threads` threads.
fn evaluate_all(
    scenario: &Scenario,
    mission: &Mission,
    constraints: &Constraints,
    space: &SearchSpace,
    candidates: &[GridPoint],
    threads: usize,
) -> Vec<(GridPoint, Option<Evaluation>)> {
    let one = |index: &GridPoint| {
        let evaluation = space.parameters(index).and_then(|parameters| {
            evaluate(scenario, mission, constraints, &parameters, &SEARCH_OPTIONS)
                .map(|(_, report)| Evaluation::of(&report))
        });
        (*index, evaluation)
    };
    let chunk = candidates.len().div_ceil(threads.max(1)).max(1);
    std::thread::scope(|scope| {
        let handles: Vec<_> = candidates
            .chunks(chunk)
            .map(|part| scope.spawn(move || part.iter().map(one).collect::<Vec<_>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|handle| handle.join().unwrap_or_default())
            .collect()
    })
}
