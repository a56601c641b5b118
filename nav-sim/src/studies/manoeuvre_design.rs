//! `nav-sim design`: a manoeuvre schedule searched with the covariance analysis
//! ([`crate::studies::covariance_design`]) under a vehicle's limits, for the sensors of a scenario.
//!
//! **The mission stays as it is.** The input scenario's main-engine burns (specific force
//! along the main-engine axis above the lateral acceleration limit) and its attitude slews
//! that are not whole turns (e.g. the upper stage's 180° turn to the apogee-burn attitude)
//! keep their start times, durations and labels. Everything else (coasts, calibration slews,
//! translations) is replaced.
//!
//! **The template.** The coasts between the mission's segments are windows; the design fills
//! them:
//! * the first window starts with a 60 s initial coast;
//! * slew rounds: a round is six slews, `turns` whole turns about +x, −x, +y, −y, +z, −z at
//!   the slew rate with 5 s ramps, each followed by 20 s of quiet coast; whole turns bring the
//!   vehicle back to the attitude it had, so every burn starts in its attitude; each round
//!   goes into the first window (from the start) with room for it, after what is there;
//! * the `+` translations (one per thrusting axis, at the lateral acceleration limit, each
//!   followed by a quiet coast, the translation gap) fly in the first window, at a fraction
//!   of its spare coast (0 = right after its slews, 1 = right before the next mission
//!   segment);
//! * the `−` translations (the same Δv back, so the translations' net Δv is zero) fly in one
//!   window before the first mission slew, while body axes point where they did for the `+`,
//!   at a fraction of that window's spare coast (after the `+` when in the same window);
//! * the rest of each window is quiet coast at the input's coast rate.
//!
//! **The search** minimises the worst `σ / target` over the 15 calibration states
//! ([`crate::studies::covariance_design::CALIBRATION_TARGETS`]), ties (within 2 %) broken by the
//! next-worst ratio and so on, by coordinate descent over six coordinates: the slew rate (14/15 of the
//! tighter of the body-rate limit and the star tracker's tracking limit; also 14/15 of the
//! body-rate limit when the tracker's is the tighter, so the search weighs a blind tracker
//! against a faster slew), (turns per slew, slew rounds) in {1, 2, 3}², the first thrusting
//! axis' share of the lateral Δv budget (0.3-0.7), the `+` placement (0, ½, 1), the `−`
//! window and placement, and the translation gap (20 or 300 s). It starts from one round of
//! one turn, an even split, and sweeps each coordinate in turn, at most three passes. The
//! candidates are analysed coarsely (covariance steps up to 2 s, every 20th measurement epoch
//! with 1/20 of the variance, one truth substep: within 0.05 % of the full analysis on the
//! upper stage); the chosen schedule is analysed again at every epoch. A candidate that does
//! not fit its windows, fails [`Scenario::validate`], or whose lowest altitude (geocentric
//! radius minus the equatorial radius, below the ellipsoid altitude) goes below
//! `simulation.min_altitude_m`, is discarded.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::output::{OutputError, OutputFile};
use crate::scenario::{frames_in, ManoeuvreSegment, Scenario, ScenarioError};
use crate::studies::covariance_design::{analyse, DesignError, DesignOptions, DesignReport};

/// The upper-stage scenario: the default input of `nav-sim design`.
pub const UPPER_STAGE_TOML: &str = include_str!("../../scenarios/upper_stage.toml");

/// Slews fly at this fraction of the rate limit: a margin for the attitude controller.
const RATE_MARGIN: f64 = 14.0 / 15.0;
/// Ramp of a calibration slew (s).
const SLEW_RAMP_S: f64 = 5.0;
/// Ramp of a translation (s).
const TRANSLATION_RAMP_S: f64 = 1.0;
/// Quiet coast after each slew and translation (s).
const SETTLE_S: f64 = 20.0;
/// Coast at the start of the flight, before any manoeuvre (s).
const INITIAL_COAST_S: f64 = 60.0;
/// A rotation segment turns a whole number of turns if within this many turns of one.
const WHOLE_TURN_TOLERANCE: f64 = 1e-3;
/// Body rate above which a segment is a slew (deg/s); below it, a coast.
const SLEW_RATE_DEG_PER_S: f64 = 0.1;
/// (turns per slew, slew rounds) the search tries.
const SLEWS: [(u32, u32); 9] = [
    (1, 1),
    (2, 1),
    (3, 1),
    (1, 2),
    (2, 2),
    (3, 2),
    (1, 3),
    (2, 3),
    (3, 3),
];
/// Shares of the lateral Δv budget for the first thrusting axis the search tries.
const SHARES: [f64; 5] = [0.3, 0.4, 0.5, 0.6, 0.7];
/// Where a group of translations flies in its window's spare coast (0 = right after the
/// window's slews, 1 = at its end).
const PLACEMENTS: [f64; 3] = [0.0, 0.5, 1.0];
/// Quiet coast after each translation (s) the search tries.
const TRANSLATION_GAPS_S: [f64; 2] = [SETTLE_S, 300.0];
/// Search coordinates: slew rate, slews, share, `+` placement, `−` slot, translation gap.
const COORDINATES: usize = 6;
/// A point of the search grid: one value index per coordinate.
type GridPoint = [usize; COORDINATES];
/// Coordinate-descent passes at most.
const MAX_PASSES: usize = 3;

/// Why a design could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ManoeuvreDesignError {
    /// The input scenario could not be read.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The covariance analysis of the final schedule failed.
    #[error(transparent)]
    Analysis(#[from] DesignError),
    /// A constraint is unusable.
    #[error("design constraint {key} {requirement}")]
    Constraint {
        /// The offending constraint.
        key: &'static str,
        /// What it must satisfy.
        requirement: String,
    },
    /// No schedule of the template fits the windows and passes the checks.
    #[error("no schedule of the template fits the mission's coasts and passes the checks")]
    NoFeasibleSchedule,
    /// The scenario file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Reading the input or writing the output failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}

/// A body axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Axis {
    /// Body x.
    X,
    /// Body y.
    Y,
    /// Body z.
    Z,
}

impl Axis {
    /// 0, 1, 2.
    pub fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }

    fn name(index: usize) -> &'static str {
        ["x", "y", "z"].get(index).copied().unwrap_or("?")
    }
}

/// The vehicle's limits the design respects.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    /// Largest body rate (deg/s).
    pub max_body_rate_deg_per_s: f64,
    /// Largest lateral (RCS) specific force (m/s²).
    pub max_lateral_acceleration_mps2: f64,
    /// Lateral Δv budget, `Σ |Δv|` over all translations (m/s).
    pub lateral_delta_v_mps: f64,
    /// Flight time (s); `None` = the input scenario's duration. Mission segments that do
    /// not end within it are left out.
    pub flight_time_s: Option<f64>,
    /// The main engine's body axis (0 = x).
    pub main_engine_axis: usize,
    /// The body axes the RCS may translate along.
    pub thrust_axes: Vec<usize>,
}

impl Constraints {
    /// The upper-stage brief (`docs/upper-stage.md`): 3 °/s, 1 m/s², 50 m/s of lateral Δv,
    /// main engine along +x, translations along y and z, the input's flight time.
    pub fn upper_stage() -> Self {
        Self {
            max_body_rate_deg_per_s: 3.0,
            max_lateral_acceleration_mps2: 1.0,
            lateral_delta_v_mps: 50.0,
            flight_time_s: None,
            main_engine_axis: 0,
            thrust_axes: vec![1, 2],
        }
    }

    fn validate(&self) -> Result<(), ManoeuvreDesignError> {
        let fail = |key, requirement: &str| {
            Err(ManoeuvreDesignError::Constraint {
                key,
                requirement: requirement.to_string(),
            })
        };
        let positive = |value: f64| value.is_finite() && value > 0.0;
        if !positive(self.max_body_rate_deg_per_s) {
            return fail("max body rate", "must be > 0");
        }
        if !positive(self.max_lateral_acceleration_mps2) {
            return fail("max lateral acceleration", "must be > 0");
        }
        if !(self.lateral_delta_v_mps.is_finite() && self.lateral_delta_v_mps >= 0.0) {
            return fail("lateral delta-v", "must be >= 0");
        }
        if self.flight_time_s.is_some_and(|time_s| !positive(time_s)) {
            return fail("flight time", "must be > 0");
        }
        if self.main_engine_axis > 2 {
            return fail("main engine axis", "must be x, y or z");
        }
        if self
            .thrust_axes
            .iter()
            .any(|axis| *axis > 2 || *axis == self.main_engine_axis)
        {
            return fail(
                "thrust axes",
                "must be body axes other than the main engine's",
            );
        }
        Ok(())
    }
}

/// One schedule of the template (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TemplateParameters {
    /// Peak rate of the calibration slews (deg/s).
    pub slew_rate_deg_per_s: f64,
    /// Whole turns per slew.
    pub turns_per_slew: u32,
    /// Rounds of six slews.
    pub slew_rounds: u32,
    /// Share of the lateral Δv budget for the first thrusting axis; the others share the rest
    /// equally.
    pub first_axis_share: f64,
    /// Where the `+` translations fly in the first window's spare coast (0-1).
    pub outbound_placement: f64,
    /// The window (index among all windows) of the `−` translations.
    pub return_window: usize,
    /// Where in that window's spare coast they fly (0-1; after the `+` in the same window).
    pub return_placement: f64,
    /// Quiet coast after each translation (s).
    pub translation_gap_s: f64,
}

/// A mission segment kept from the input, with its first frame.
#[derive(Debug, Clone)]
struct MissionSegment {
    first_frame: u64,
    frames: u64,
    segment: ManoeuvreSegment,
    /// A slew that changes the attitude (not whole turns).
    turns_vehicle: bool,
}

/// A coast between mission segments that the design fills.
#[derive(Debug, Clone, Copy)]
struct Window {
    frames: u64,
    /// Mission slews before it: windows of one epoch share body-axis directions.
    attitude_epoch: usize,
}

/// The mission skeleton of the input scenario under the constraints.
#[derive(Debug, Clone)]
pub struct Mission {
    period_s: f64,
    /// Mission segments in time order.
    segments: Vec<MissionSegment>,
    /// Windows: before the first mission segment, between them, after the last.
    windows: Vec<Window>,
    coast_rate_deg_per_s: [f64; 3],
    /// Labels of the input's mission segments that end after the flight time.
    left_out: Vec<String>,
}

fn norm(vector: &[f64; 3]) -> f64 {
    vector.iter().map(|value| value * value).sum::<f64>().sqrt()
}

/// Frames of at least `duration_s`.
fn frames_at_least(duration_s: f64, period_s: f64) -> u64 {
    let frames = (duration_s / period_s - 1e-9).ceil();
    if frames.is_finite() && frames > 0.0 {
        // A finite, positive whole number far below 2^53.
        frames as u64
    } else {
        0
    }
}

impl Mission {
    /// The mission of `scenario` (module docs) under `constraints`.
    ///
    /// # Errors
    /// [`ManoeuvreDesignError::Constraint`] if the constraints are unusable.
    pub fn of(
        scenario: &Scenario,
        constraints: &Constraints,
    ) -> Result<Self, ManoeuvreDesignError> {
        constraints.validate()?;
        let period_s = scenario.imu.frame_period_s();
        let end_frame = frames_in(
            constraints.flight_time_s.unwrap_or(scenario.duration_s()),
            period_s,
        );
        let mut segments = Vec::new();
        let mut left_out = Vec::new();
        let mut coast_rate_deg_per_s = None;
        let mut first_frame = 0;
        for segment in &scenario.manoeuvres {
            let frames = frames_in(segment.duration_s, period_s);
            let rate_deg_per_s = norm(&segment.body_rate_deg_per_s);
            let main_engine = segment
                .specific_force_mps2
                .get(constraints.main_engine_axis)
                .is_some_and(|force| force.abs() > constraints.max_lateral_acceleration_mps2);
            let turns = rate_deg_per_s * (segment.duration_s - segment.ramp_s) / 360.0;
            let whole_turns =
                turns.round() >= 1.0 && (turns - turns.round()).abs() < WHOLE_TURN_TOLERANCE;
            let turns_vehicle = rate_deg_per_s > SLEW_RATE_DEG_PER_S && !whole_turns;
            if main_engine || turns_vehicle {
                if first_frame + frames <= end_frame {
                    segments.push(MissionSegment {
                        first_frame,
                        frames,
                        segment: segment.clone(),
                        turns_vehicle,
                    });
                } else {
                    left_out.push(segment.label.clone());
                }
            } else if coast_rate_deg_per_s.is_none()
                && rate_deg_per_s <= SLEW_RATE_DEG_PER_S
                && norm(&segment.specific_force_mps2) <= 0.0
            {
                coast_rate_deg_per_s = Some(segment.body_rate_deg_per_s);
            }
            first_frame += frames;
        }
        let mut windows = Vec::new();
        let (mut cursor, mut attitude_epoch) = (0, 0);
        for mission in &segments {
            windows.push(Window {
                frames: mission.first_frame.saturating_sub(cursor),
                attitude_epoch,
            });
            cursor = mission.first_frame + mission.frames;
            attitude_epoch += usize::from(mission.turns_vehicle);
        }
        windows.push(Window {
            frames: end_frame.saturating_sub(cursor),
            attitude_epoch,
        });
        Ok(Self {
            period_s,
            segments,
            windows,
            coast_rate_deg_per_s: coast_rate_deg_per_s.unwrap_or([0.0; 3]),
            left_out,
        })
    }

    /// Labels of the input's mission segments left out because they end after the flight
    /// time.
    pub fn left_out(&self) -> &[String] {
        &self.left_out
    }

    /// Windows where the `−` translations may fly: those of the first attitude epoch.
    fn return_windows(&self) -> Vec<usize> {
        self.windows
            .iter()
            .enumerate()
            .filter(|(_, window)| window.attitude_epoch == 0)
            .map(|(index, _)| index)
            .collect()
    }

    fn coast(&self, label: &str, frames: u64) -> ManoeuvreSegment {
        ManoeuvreSegment {
            label: label.to_string(),
            duration_s: frames as f64 * self.period_s,
            ramp_s: 0.0,
            body_rate_deg_per_s: self.coast_rate_deg_per_s,
            specific_force_mps2: [0.0; 3],
        }
    }

    /// The calibration slews of one round at `parameters` (each with its settling coast).
    fn slew_round(&self, parameters: &TemplateParameters) -> Vec<ManoeuvreSegment> {
        let angle_deg = 360.0 * f64::from(parameters.turns_per_slew);
        let frames = frames_at_least(
            angle_deg / parameters.slew_rate_deg_per_s + SLEW_RAMP_S,
            self.period_s,
        );
        let duration_s = frames as f64 * self.period_s;
        // The whole number of frames is at least the nominal length, so the rate that turns
        // exactly the whole turns is at most the nominal rate.
        let rate_deg_per_s = angle_deg / (duration_s - SLEW_RAMP_S);
        let mut round = Vec::new();
        for axis in 0..3 {
            for sign in [1.0, -1.0] {
                let mut rate = [0.0; 3];
                if let Some(component) = rate.get_mut(axis) {
                    *component = sign * rate_deg_per_s;
                }
                round.push(ManoeuvreSegment {
                    label: format!(
                        "calibration slew: {} turn{} {}{} at {:.2} deg/s",
                        parameters.turns_per_slew,
                        if parameters.turns_per_slew == 1 {
                            ""
                        } else {
                            "s"
                        },
                        if sign > 0.0 { "+" } else { "-" },
                        Axis::name(axis),
                        rate_deg_per_s
                    ),
                    duration_s,
                    ramp_s: SLEW_RAMP_S,
                    body_rate_deg_per_s: rate,
                    specific_force_mps2: [0.0; 3],
                });
                round.push(self.coast("quiet coast", frames_in(SETTLE_S, self.period_s)));
            }
        }
        round
    }

    /// The translations of one sign (each with its settling coast).
    fn translations(
        &self,
        constraints: &Constraints,
        parameters: &TemplateParameters,
        sign: f64,
    ) -> Vec<ManoeuvreSegment> {
        let axes = &constraints.thrust_axes;
        let mut segments = Vec::new();
        for (position, axis) in axes.iter().enumerate() {
            let share = match (position, axes.len()) {
                (_, 1) => 1.0,
                (0, _) => parameters.first_axis_share,
                (_, count) => (1.0 - parameters.first_axis_share) / (count - 1) as f64,
            };
            // Half of the axis' share each way.
            let delta_v_mps = 0.5 * share * constraints.lateral_delta_v_mps;
            if delta_v_mps <= 0.0 {
                continue;
            }
            let frames = frames_at_least(
                delta_v_mps / constraints.max_lateral_acceleration_mps2 + TRANSLATION_RAMP_S,
                self.period_s,
            );
            let duration_s = frames as f64 * self.period_s;
            let acceleration_mps2 = delta_v_mps / (duration_s - TRANSLATION_RAMP_S);
            let mut force = [0.0; 3];
            if let Some(component) = force.get_mut(*axis) {
                *component = sign * acceleration_mps2;
            }
            segments.push(ManoeuvreSegment {
                label: format!(
                    "RCS translation {}{}: {:.2} m/s at {:.3} m/s^2",
                    if sign > 0.0 { "+" } else { "-" },
                    Axis::name(*axis),
                    delta_v_mps,
                    acceleration_mps2
                ),
                duration_s,
                ramp_s: TRANSLATION_RAMP_S,
                body_rate_deg_per_s: [0.0; 3],
                specific_force_mps2: force,
            });
            segments.push(self.coast(
                "quiet coast",
                frames_in(parameters.translation_gap_s, self.period_s),
            ));
        }
        segments
    }

    /// The schedule of `parameters`, or `None` if it does not fit the windows.
    pub fn schedule(
        &self,
        constraints: &Constraints,
        parameters: &TemplateParameters,
    ) -> Option<Vec<ManoeuvreSegment>> {
        let frames_of = |segments: &[ManoeuvreSegment]| -> u64 {
            segments
                .iter()
                .map(|segment| frames_in(segment.duration_s, self.period_s))
                .sum()
        };
        let mut leading: Vec<Vec<ManoeuvreSegment>> = vec![Vec::new(); self.windows.len()];
        leading
            .first_mut()?
            .push(self.coast("initial coast", frames_in(INITIAL_COAST_S, self.period_s)));
        // Translation groups per window: (placement in the spare coast, segments).
        let mut groups: Vec<Vec<(f64, Vec<ManoeuvreSegment>)>> =
            vec![Vec::new(); self.windows.len()];
        groups.first_mut()?.push((
            parameters.outbound_placement,
            self.translations(constraints, parameters, 1.0),
        ));
        let returns = groups.get_mut(parameters.return_window)?;
        if returns
            .first()
            .is_some_and(|(outbound, _)| *outbound > parameters.return_placement)
        {
            return None;
        }
        returns.push((
            parameters.return_placement,
            self.translations(constraints, parameters, -1.0),
        ));
        let round = self.slew_round(parameters);
        let round_frames = frames_of(&round);
        // Frames of window `index` not used by `segments` and its translation groups.
        let spare = |index: usize, segments: &[ManoeuvreSegment]| -> Option<u64> {
            let window = self.windows.get(index)?.frames;
            let translations: u64 = groups
                .get(index)?
                .iter()
                .map(|(_, group)| frames_of(group))
                .sum();
            window.checked_sub(frames_of(segments) + translations)
        };
        for _ in 0..parameters.slew_rounds {
            let index = (0..self.windows.len()).find(|index| {
                leading
                    .get(*index)
                    .and_then(|segments| spare(*index, segments))
                    .is_some_and(|frames| frames >= round_frames)
            })?;
            leading.get_mut(index)?.extend(round.iter().cloned());
        }
        let mut schedule = Vec::new();
        for (index, segments) in leading.iter().enumerate() {
            let spare = spare(index, segments)?;
            schedule.extend(segments.iter().cloned());
            let mut used = 0;
            for (placement, group) in groups.get(index)? {
                let before = ((spare as f64 * placement).round() as u64).clamp(used, spare);
                if before > used {
                    schedule.push(self.coast("quiet coast", before - used));
                }
                used = before;
                schedule.extend(group.iter().cloned());
            }
            if spare > used {
                schedule.push(self.coast("quiet coast", spare - used));
            }
            if let Some(mission) = self.segments.get(index) {
                schedule.push(mission.segment.clone());
            }
        }
        Some(schedule)
    }
}

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
    /// Wall time of the final analysis (s).
    pub final_wall_s: f64,
    /// `Σ |Δv|` of the translations (m/s).
    pub lateral_delta_v_mps: f64,
    /// Input mission segments left out (they end after the flight time).
    pub left_out: Vec<String>,
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
/// [`ManoeuvreDesignError::NoFeasibleSchedule`] if no candidate fits and passes the checks,
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
    let mut best_index = [0, 0, sizes[2] / 2, 0, sizes[4].saturating_sub(1), 0];
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
    let parameters = space
        .parameters(&best_index)
        .filter(|_| best.is_some())
        .ok_or(ManoeuvreDesignError::NoFeasibleSchedule)?;
    let final_started = Instant::now();
    let designed = with_schedule(
        scenario,
        mission
            .schedule(constraints, &parameters)
            .ok_or(ManoeuvreDesignError::NoFeasibleSchedule)?,
    )
    .ok_or(ManoeuvreDesignError::NoFeasibleSchedule)?;
    let report = analyse(&designed, &FINAL_OPTIONS)?;
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
    })
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

impl ManoeuvreDesign {
    /// The design as text: parameters, schedule, predicted accuracy and wall times.
    pub fn text(&self) -> String {
        let p = &self.parameters;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "design: slews at {:.2} deg/s, {} turn(s) each way per axis, {} round(s); lateral \
             share of the first thrust axis {:.2} ({:.1} m/s of translation in all), {:.0} s \
             apart; outbound translations at {:.0} % of the first window's spare coast, \
             returns in window {} at {:.0} % of its spare coast",
            p.slew_rate_deg_per_s,
            p.turns_per_slew,
            p.slew_rounds,
            p.first_axis_share,
            self.lateral_delta_v_mps,
            p.translation_gap_s,
            100.0 * p.outbound_placement,
            p.return_window,
            100.0 * p.return_placement
        );
        if !self.left_out.is_empty() {
            let _ = writeln!(
                text,
                "left out (they end after the flight time): {}",
                self.left_out.join("; ")
            );
        }
        let _ = writeln!(text, "\nschedule:\n    start (s)  duration (s)  label");
        let mut start_s = 0.0;
        for segment in &self.scenario.manoeuvres {
            let _ = writeln!(
                text,
                "{:>13.1}  {:>12.3}  {}",
                start_s, segment.duration_s, segment.label
            );
            start_s += segment.duration_s;
        }
        let orbit = &self.report.orbit;
        let _ = writeln!(
            text,
            "\npredicted final accuracy (covariance analysis, every measurement epoch):\n{}\
             worst sigma/target {:.3}\norbit: lowest altitude {:.1} km, lowest osculating \
             perigee {:.1} km, final perigee {:.1} km, final apogee {:.1} km",
            self.report.table(),
            self.report.worst_ratio(),
            orbit.minimum_altitude_m / 1e3,
            orbit.minimum_perigee_altitude_m / 1e3,
            orbit.final_perigee_altitude_m / 1e3,
            orbit.final_apogee_altitude_m / 1e3,
        );
        let _ = writeln!(
            text,
            "wall time: search {:.1} s ({} schedules analysed), final analysis {:.1} s",
            self.search_wall_s, self.evaluations, self.final_wall_s
        );
        text
    }
}

/// The TOML of one manoeuvre segment.
fn segment_toml(segment: &ManoeuvreSegment) -> String {
    let array = |values: &[f64; 3]| {
        let [x, y, z] = values;
        format!("[{x:?}, {y:?}, {z:?}]")
    };
    format!(
        "[[manoeuvre]]\nlabel = {:?}\nduration_s = {:?}\nramp_s = {:?}\nbody_rate_deg_per_s = {}\n\
         specific_force_mps2 = {}\n",
        segment.label,
        segment.duration_s,
        segment.ramp_s,
        array(&segment.body_rate_deg_per_s),
        array(&segment.specific_force_mps2)
    )
}

/// `text` (a scenario's TOML) with its `[[manoeuvre]]` tables replaced by `manoeuvres`,
/// preceded by `header` (comment lines): everything else is kept as written. The new list
/// takes the place of the first old table and of the comment block right above it.
pub fn replace_manoeuvres(text: &str, manoeuvres: &[ManoeuvreSegment], header: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let is_header = |line: &str| line.trim_start().starts_with('[');
    let is_manoeuvre = |line: &str| line.trim() == "[[manoeuvre]]";
    let is_comment = |line: &str| line.trim_start().starts_with('#');
    let mut kept: Vec<String> = Vec::new();
    let mut inserted = false;
    let mut index = 0;
    while let Some(line) = lines.get(index) {
        if !is_manoeuvre(line) {
            kept.push((*line).to_string());
            index += 1;
            continue;
        }
        let mut end = index + 1;
        while lines.get(end).is_some_and(|line| !is_header(line)) {
            end += 1;
        }
        // Comment lines right above the next table belong to it.
        while end > index + 1
            && lines
                .get(end - 1)
                .is_some_and(|line| is_comment(line) || line.trim().is_empty())
        {
            end -= 1;
        }
        if !inserted {
            while kept.last().is_some_and(|line| is_comment(line)) {
                kept.pop();
            }
            kept.extend(header.lines().map(|line| format!("# {line}")));
            for segment in manoeuvres {
                kept.extend(segment_toml(segment).lines().map(str::to_string));
                kept.push(String::new());
            }
            inserted = true;
        }
        index = end;
        while lines.get(index).is_some_and(|line| line.trim().is_empty()) {
            index += 1;
        }
    }
    let mut result = kept.join("\n");
    result.push('\n');
    result
}

/// Command-line arguments of `nav-sim design`.
#[derive(Debug, Clone, clap::Args)]
pub struct DesignArgs {
    /// Scenario (TOML) whose orbit, sensors, filter and main-engine burns the design keeps;
    /// default: the built-in upper stage (nav-sim/scenarios/upper_stage.toml).
    pub scenario: Option<PathBuf>,
    /// Largest body rate (deg/s).
    #[arg(long, default_value_t = 3.0)]
    pub max_rate_deg_per_s: f64,
    /// Largest lateral (RCS) acceleration (m/s²).
    #[arg(long, default_value_t = 1.0)]
    pub max_lateral_accel_mps2: f64,
    /// Lateral Δv budget, Σ|Δv| over all translations (m/s).
    #[arg(long, default_value_t = 50.0)]
    pub lateral_delta_v_mps: f64,
    /// Flight time (s); default: the scenario's. Mission segments ending after it are left
    /// out.
    #[arg(long)]
    pub flight_time_s: Option<f64>,
    /// The main engine's body axis; its burns are taken from the scenario as they are.
    #[arg(long, value_enum, default_value = "x")]
    pub main_engine_axis: Axis,
    /// Body axes the RCS may translate along (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "y,z")]
    pub thrust_axes: Vec<Axis>,
    /// Analyses run at once during the search.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Write the scenario with the designed schedule here (TOML).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

impl DesignArgs {
    /// The constraints the arguments give.
    pub fn constraints(&self) -> Constraints {
        Constraints {
            max_body_rate_deg_per_s: self.max_rate_deg_per_s,
            max_lateral_acceleration_mps2: self.max_lateral_accel_mps2,
            lateral_delta_v_mps: self.lateral_delta_v_mps,
            flight_time_s: self.flight_time_s,
            main_engine_axis: self.main_engine_axis.index(),
            thrust_axes: self.thrust_axes.iter().map(|axis| axis.index()).collect(),
        }
    }

    /// Loads the scenario, designs, prints the design and writes the scenario if asked.
    ///
    /// # Errors
    /// Any [`ManoeuvreDesignError`].
    pub fn run(&self) -> Result<(), ManoeuvreDesignError> {
        let text = match &self.scenario {
            Some(path) => {
                std::fs::read_to_string(path).map_err(|source| ManoeuvreDesignError::Io {
                    path: path.display().to_string(),
                    source,
                })?
            }
            None => UPPER_STAGE_TOML.to_string(),
        };
        let scenario = match &self.scenario {
            Some(path) => Scenario::load(path)?,
            None => Scenario::from_toml_str(UPPER_STAGE_TOML)?,
        };
        let inputs: Vec<&Path> = self.scenario.iter().map(PathBuf::as_path).collect();
        // The output is refused or created before the search, so a bad --out fails at once.
        let output = match &self.out {
            Some(out) => Some((out, OutputFile::create_distinct(out, &inputs)?)),
            None => None,
        };
        let design = design(&scenario, &self.constraints(), self.threads)?;
        print!("{}", design.text());
        if let Some((out, mut file)) = output {
            let header = self.header(&design);
            let written = replace_manoeuvres(&text, &design.scenario.manoeuvres, &header);
            file.write_all(written.as_bytes())
                .map_err(|source| ManoeuvreDesignError::Io {
                    path: out.display().to_string(),
                    source,
                })?;
            file.commit()?;
            println!("wrote {}", out.display());
        }
        Ok(())
    }

    /// The comment above the written schedule: how it was made.
    fn header(&self, design: &ManoeuvreDesign) -> String {
        let p = &design.parameters;
        format!(
            "The manoeuvre schedule, written by `nav-sim design` (docs/scenario-design.md) under\n\
             max body rate {} deg/s, max lateral acceleration {} m/s^2, lateral delta-v {} m/s,\n\
             main engine along body {}: slews at {:.2} deg/s, {} turns each way per axis, {} \
             round(s);\nfirst thrust axis' share of the lateral delta-v {:.2}. Predicted worst \
             sigma/target {:.3}.",
            self.max_rate_deg_per_s,
            self.max_lateral_accel_mps2,
            self.lateral_delta_v_mps,
            Axis::name(self.main_engine_axis.index()),
            p.slew_rate_deg_per_s,
            p.turns_per_slew,
            p.slew_rounds,
            p.first_axis_share,
            design.report.worst_ratio()
        )
    }
}
