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

use crate::output::OutputError;
use crate::scenario::{frames_in, ManoeuvreSegment, Scenario, ScenarioError};
use crate::studies::covariance_design::DesignError;

mod report;
mod search;

pub use report::replace_manoeuvres;
pub use search::{design, ManoeuvreDesign, FINAL_OPTIONS, SEARCH_OPTIONS};

/// The upper-stage scenario: the default input of `nav-sim design`.
pub const UPPER_STAGE_TOML: &str = include_str!("../../../scenarios/upper_stage.toml");

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
    /// No schedule of the template fits the windows and passes the checks; `reason` says
    /// why the smallest one does not, naming the limit.
    #[error(
        "no schedule of the template fits the mission's coasts and passes the checks: the \
         smallest one {reason}"
    )]
    NoFeasibleSchedule {
        /// Why the smallest schedule fails (the limit it meets).
        reason: String,
    },
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
    /// The upper-stage brief (`docs/guide/upper-stage.md`): 3 °/s, 1 m/s², 50 m/s of lateral Δv,
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
        let repeated = self.thrust_axes.iter().enumerate().any(|(position, axis)| {
            self.thrust_axes
                .get(..position)
                .is_some_and(|before| before.contains(axis))
        });
        if repeated
            || self
                .thrust_axes
                .iter()
                .any(|axis| *axis > 2 || *axis == self.main_engine_axis)
        {
            return fail(
                "thrust axes",
                "must be distinct body axes other than the main engine's (each axis once: \
                 the lateral Δv budget is shared among the axes listed)",
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
    /// The longest coast window the design can fill (s).
    fn longest_window_s(&self) -> f64 {
        let frames = self.windows.iter().map(|window| window.frames).max();
        frames.unwrap_or(0) as f64 * self.period_s
    }

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
        // Saturating: a schedule at a vanishing rate or acceleration has segments of ~2^64
        // frames, which fit no window rather than overflow.
        let frames_of = |segments: &[ManoeuvreSegment]| -> u64 {
            segments
                .iter()
                .map(|segment| frames_in(segment.duration_s, self.period_s))
                .fold(0, u64::saturating_add)
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
                .fold(0, u64::saturating_add);
            window.checked_sub(frames_of(segments).saturating_add(translations))
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
