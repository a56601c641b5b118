//! `nav-sim observability`: the paper's Table 1 (Section 2.3), recomputed with nav-core's
//! observability analysis, for the paper's three motion states and for every phase of a
//! scenario's manoeuvre schedule, as text, as JSON, and as a PNG heat map.
//!
//! Two analyses per case (method and scaling: `nav-core/src/observability.rs`,
//! `docs/guide/observability.md`):
//! * **ours**: continuous segments `[H; H Aτ; …]`, scaled ([`Scaling::typical`]); the degree
//!   `σ_k/σ_max` per state (singular-value assignment) and the exact null-space test
//!   ([`RankTolerance::DEFAULT`]: σ ≤ 1e-12 σ_max is zero, a state is observable when the
//!   projection of its unit vector on that null space is ≤ 1e-6);
//! * **paper-like**: the paper's own recipe, discrete segments `[H; H F; …]` at the IMU
//!   period and the scenario's discretisation order, unscaled, the singular value assigned to
//!   each state, "observable" when it is ≥ 5e-8 (the paper's threshold).
//!
//! Each phase of the schedule is one PWCS segment: its peak body rate and specific force, the
//! attitude frozen at the phase start (the scenario's initial attitude advanced by the peak
//! rate over `duration_s − ramp_s`, the integral of the raised-cosine command), zero GNSS lever
//! arm. It is analysed after all previous phases (the paper's PWCS setting) and alone.

use nalgebra::{Quaternion, Vector3};
use nav_core::attitude::{exp_rotation_vector, product, rotation_matrix};
use nav_core::discretise::discretise;
use nav_core::error_model::{noise_input_matrix, system_matrix, LinearisationPoint, ProcessNoise};
use nav_core::observability::{
    constant_motion, full_update_measurement_matrix, ObservabilityAnalysis, PaperMotionState,
    RankTolerance, Scaling, StrippedObservability, SystemForm,
};
use nav_core::state::{StateBlock, STATE_DIMENSION};
use nav_core::NavError;
use serde::Serialize;

use crate::scenario::{Scenario, ScenarioError};

mod heat_map;
pub mod imu_errors;
mod render;

pub use heat_map::write_heat_map;
pub use render::render_text;

/// The paper's Table 1, "singular values in different motion states", transcribed from the
/// PDF text extraction (Section 2.3 of the paper): one row per error state in the
/// order of eq. (15) (= nav-core's `StateBlock::ALL`), columns I, II, III.
///
/// The extraction is garbled in places:
/// * states 1 and 2 in state II read `8.7×10^{19}` and `9.3×10¹⁹`: the exponent's sign, or a
///   superscript digit, may have been lost. Transcribed as printed; either way they make every
///   other value of column II tiny relative to σ_max (docs/guide/observability.md);
/// * superscripts are mixed (`10 ⁻¹⁶`, `10^{-16}`, `10³`); read as powers of ten;
/// * state 23 in state I is printed `0` and state 21 in state I `1.1×10^{-37}`: as printed.
pub const PAPER_TABLE_1: [[f64; 3]; STATE_DIMENSION] = [
    [2.2, 8.7e19, 4.3e2],        // 1 attitude x
    [2.2, 9.3e19, 2.3],          // 2 attitude y
    [2.2, 4.0e2, 4.3e2],         // 3 attitude z
    [1.2, 1.2, 0.9],             // 4 position x
    [1.2, 2.2, 1.2],             // 5 position y
    [1.2, 1.1, 0.9],             // 6 position z
    [4.4, 4.4, 2.5],             // 7 velocity x
    [4.4, 0.8, 5.2],             // 8 velocity y
    [4.4, 4.0, 2.5],             // 9 velocity z
    [9.3, 8.3e2, 5.6e3],         // 10 gyro bias x
    [9.3, 5.4e2, 10.6],          // 11 gyro bias y
    [9.3, 2.3e-6, 5.6e3],        // 12 gyro bias z
    [64.2, 6.5e-15, 2.6e-14],    // 13 accelerometer bias x
    [64.2, 66.0, 8.4e-15],       // 14 accelerometer bias y
    [64.1, 51.0, 2.2e-14],       // 15 accelerometer bias z
    [1.0e-15, 2.9, 3.3],         // 16 installation x
    [6.3e-16, 2.8, 2.3],         // 17 installation y
    [3.7e-16, 3.2, 3.3],         // 18 installation z
    [1.6e-21, 2.9e-4, 4.2e-19],  // 19 gyro scale factor x
    [3.1e-21, 1.6e-5, 3.6e-21],  // 20 gyro scale factor y
    [1.1e-37, 3.3e4, 4.0e-21],   // 21 gyro scale factor z
    [7.3e-17, 6.6e-18, 2.5e-17], // 22 accelerometer scale factor x
    [0.0, 3.1e-7, 1.6e3],        // 23 accelerometer scale factor y
    [1.5e-16, 1.7e-16, 7.4e-17], // 24 accelerometer scale factor z
];

/// Heat-map file name inside `--out DIR`.
pub const HEAT_MAP_FILE: &str = "observability_degree.png";

/// Why the report could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ObservabilityReportError {
    /// The scenario could not be loaded.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// nav-core refused a case (bad numbers in the scenario, or an SVD failure).
    #[error("observability analysis of {case}: {error}")]
    Analysis {
        /// The case being analysed, e.g. `phase 3 "rotate about body y" after previous`.
        case: String,
        /// nav-core's error.
        error: NavError,
    },
    /// The report could not be written to standard output.
    #[error("cannot write the report to standard output: {0}")]
    Output(std::io::Error),
    /// JSON serialisation failed.
    #[error("cannot serialise the report as JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The output directory could not be created.
    #[error("cannot create output directory {path}: {source}")]
    Io {
        /// The directory.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// Drawing or encoding the heat map failed.
    #[error("cannot draw heat map {path}: {message}")]
    Plot {
        /// The PNG file.
        path: String,
        /// The plotting library's message.
        message: String,
    },
}

/// The whole report (what `--json` prints).
#[derive(Debug, Clone, Serialize)]
pub struct ObservabilityReport {
    /// Where the scenario came from.
    pub scenario: String,
    /// The scaling of "ours" (typical state magnitudes per block, row magnitudes, `τ`).
    pub scaling: ScalingReport,
    /// The decision thresholds.
    pub tolerance: ToleranceReport,
    /// Discrete step of the paper-like analysis (s): the scenario's IMU period.
    pub paper_like_step_s: f64,
    /// Truncation order of the paper-like `F` (the scenario's `filter.discretisation_order`).
    pub paper_like_order: u32,
    /// The paper's motion states I, II, III alone (Table 1), then I→II and I→III as PWCS.
    pub paper_states: Vec<CaseReport>,
    /// The scenario's schedule, phase by phase.
    pub phases: Vec<PhaseReport>,
}

/// The scaling used for "ours".
#[derive(Debug, Clone, Serialize)]
pub struct ScalingReport {
    /// Typical magnitude per block, in the block's units.
    pub state_magnitudes: Vec<BlockMagnitude>,
    /// Star-sensor rows are in units of this (rad, vector part).
    pub star_row_magnitude: f64,
    /// GNSS rows are in units of this (m).
    pub gnss_row_magnitude: f64,
    /// Time unit `τ` (s) of the paper's states; each case reports its own
    /// ([`CaseReport::time_unit_s`]).
    pub time_unit_s: f64,
}

/// One block's typical magnitude.
#[derive(Debug, Clone, Serialize)]
pub struct BlockMagnitude {
    /// Block name (`attitude`, `position`, …).
    pub block: String,
    /// Typical magnitude in the block's units.
    pub magnitude: f64,
}

/// The thresholds of the two verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct ToleranceReport {
    /// Ours: σ ≤ this × σ_max counts as zero.
    pub relative_zero: f64,
    /// Ours: a state is unobservable when its null-space projection exceeds this.
    pub null_space_projection: f64,
    /// The paper's: an assigned singular value below this is unobservable.
    pub paper_absolute: f64,
}

/// One analysed case: one or more PWCS segments.
#[derive(Debug, Clone, Serialize)]
pub struct CaseReport {
    /// Short name: "I", "II", "III", "I→II", "I→III", or the phase label.
    pub label: String,
    /// The segments, in order.
    pub segments: Vec<String>,
    /// Ours: the time unit `τ` of this case (s): 1 s, or 1 rad / (fastest rate) if shorter.
    pub time_unit_s: f64,
    /// Ours: numerical rank.
    pub rank: usize,
    /// Ours: states passing the null-space test.
    pub observable_count: usize,
    /// Paper-like: singular values ≥ 5e-8.
    pub paper_like_rank: usize,
    /// Paper-like: states whose assigned singular value is ≥ 5e-8.
    pub paper_like_observable_count: usize,
    /// Ours: the scaled singular values, descending.
    pub singular_values: Vec<f64>,
    /// Per state, in the order of eq. (15).
    pub states: Vec<StateReport>,
}

/// One state of one case.
#[derive(Debug, Clone, Serialize)]
pub struct StateReport {
    /// `block.axis`, e.g. `gyro_scale_factor.z`.
    pub state: String,
    /// Ours: `σ_k/σ_max` (0 if no singular value was assigned to the state).
    pub degree: f64,
    /// Ours: the (scaled) singular value assigned to the state.
    pub singular_value: f64,
    /// Ours: `‖Nᵀ e_k‖`.
    pub null_space_projection: f64,
    /// Ours: passes the null-space test.
    pub observable: bool,
    /// Paper-like: the (unscaled, discrete) singular value assigned to the state.
    pub paper_like_singular_value: f64,
    /// Paper-like: `paper_like_singular_value ≥ 5e-8`.
    pub observable_paper_threshold: bool,
    /// The paper's Table 1 value (paper states I, II, III only).
    pub paper_table_1: Option<f64>,
    /// The paper's verdict on its own value (≥ 5e-8).
    pub paper_table_1_observable: Option<bool>,
}

/// One phase of the schedule.
#[derive(Debug, Clone, Serialize)]
pub struct PhaseReport {
    /// 1-based position in the schedule.
    pub index: usize,
    /// The scenario's label.
    pub label: String,
    /// Peak body rate (deg/s).
    pub body_rate_deg_per_s: [f64; 3],
    /// Peak specific force (m/s²).
    pub specific_force_mps2: [f64; 3],
    /// Phase 1 to this one, as PWCS segments.
    pub after_previous: CaseReport,
    /// This phase alone.
    pub alone: CaseReport,
}

/// One PWCS segment: the constant motion and the attitude it is frozen at.
#[derive(Debug, Clone)]
struct Segment {
    label: String,
    point: LinearisationPoint,
    attitude: Quaternion<f64>,
}

/// The time unit `τ` of a case: 1 s, or less so that the fastest rotation of the case turns
/// by at most 1 rad per `τ` (`τ = min(1 s, 1 rad / max |ω|)`). The continuous powers
/// `(Aτ)^k`, k ≤ 23, then stay O(1): at the scenario's 100 °/s and τ = 1 s they would grow as
/// 1.75^23 ≈ 4e5 and push every state that is not coupled to the rotation towards the
/// 1e-12 relative zero threshold.
fn time_unit_s(segments: &[Segment]) -> f64 {
    let fastest_rad_s = segments
        .iter()
        .map(|s| s.point.corrected_rate_rad_s.norm())
        .fold(0.0_f64, f64::max);
    if fastest_rad_s > 1.0 {
        1.0 / fastest_rad_s
    } else {
        1.0
    }
}

/// What every case shares: mounting, tolerance, discretisation of the paper-like analysis.
struct Analyser {
    mounting: Quaternion<f64>,
    step_s: f64,
    order: u8,
}

/// Name of state `k`, `block.axis`.
fn state_name(k: usize) -> String {
    let block = StateBlock::ALL
        .get(k / 3)
        .map_or("state", |block| block.name());
    let axis = ["x", "y", "z"].get(k % 3).copied().unwrap_or("?");
    format!("{block}.{axis}")
}

fn rotation_vector_rad(degrees: &[f64; 3]) -> Vector3<f64> {
    Vector3::from_iterator(degrees.iter().map(|d| d.to_radians()))
}

impl Analyser {
    fn analyse(
        &self,
        label: &str,
        segments: &[Segment],
        paper_column: Option<usize>,
    ) -> Result<CaseReport, ObservabilityReportError> {
        let fail = |error: NavError| ObservabilityReportError::Analysis {
            case: label.to_string(),
            error,
        };
        let time_unit_s = time_unit_s(segments);
        let scaling = Scaling {
            time_unit_s,
            ..Scaling::typical()
        };
        let mut ours = StrippedObservability::new(scaling).map_err(fail)?;
        let mut paper_like = StrippedObservability::new(Scaling::unscaled()).map_err(fail)?;
        for segment in segments {
            let h =
                full_update_measurement_matrix(&segment.attitude, &self.mounting).map_err(fail)?;
            let system = system_matrix(&segment.point);
            ours.add_segment(&system, &h, SystemForm::Continuous)
                .map_err(fail)?;
            let transition = discretise(
                &system,
                &noise_input_matrix(&segment.point),
                &ProcessNoise::PAPER.spectral_density_diagonal(),
                self.step_s,
                self.order,
            )
            .map_err(fail)?
            .transition;
            paper_like
                .add_segment(&transition, &h, SystemForm::Discrete)
                .map_err(fail)?;
        }
        let ours = ours.analyse(&RankTolerance::DEFAULT).map_err(fail)?;
        let paper_like = paper_like.analyse(&RankTolerance::DEFAULT).map_err(fail)?;
        Ok(case_report(
            label,
            segments,
            time_unit_s,
            &ours,
            &paper_like,
            paper_column,
        ))
    }
}

fn case_report(
    label: &str,
    segments: &[Segment],
    time_unit_s: f64,
    ours: &ObservabilityAnalysis,
    paper_like: &ObservabilityAnalysis,
    paper_column: Option<usize>,
) -> CaseReport {
    let threshold = RankTolerance::DEFAULT.absolute;
    let states: Vec<StateReport> = (0..STATE_DIMENSION)
        .map(|k| {
            let paper_table_1 = paper_column
                .and_then(|column| PAPER_TABLE_1.get(k).and_then(|row| row.get(column)))
                .copied();
            let paper_like_singular_value = paper_like.assigned_singular_value[k];
            StateReport {
                state: state_name(k),
                degree: ours.degree[k],
                singular_value: ours.assigned_singular_value[k],
                null_space_projection: ours.null_space_projection[k],
                observable: ours.observable[k],
                paper_like_singular_value,
                observable_paper_threshold: paper_like_singular_value >= threshold,
                paper_table_1,
                paper_table_1_observable: paper_table_1.map(|value| value >= threshold),
            }
        })
        .collect();
    CaseReport {
        label: label.to_string(),
        segments: segments.iter().map(|s| s.label.clone()).collect(),
        time_unit_s,
        rank: ours.rank,
        observable_count: ours.observable_count(),
        paper_like_rank: paper_like.rank_absolute,
        paper_like_observable_count: states
            .iter()
            .filter(|s| s.observable_paper_threshold)
            .count(),
        singular_values: ours.singular_values.iter().copied().collect(),
        states,
    }
}

/// Builds the report for `scenario` (`origin` names it in the output).
///
/// # Errors
/// [`ObservabilityReportError::Analysis`] if nav-core refuses a case.
pub fn build_report(
    scenario: &Scenario,
    origin: &str,
) -> Result<ObservabilityReport, ObservabilityReportError> {
    let initial_attitude = exp_rotation_vector(&rotation_vector_rad(
        &scenario.initial_attitude.rotation_vector_deg,
    ));
    let analyser = Analyser {
        mounting: exp_rotation_vector(&rotation_vector_rad(
            &scenario.star_sensor.mounting_rotation_vector_deg,
        )),
        step_s: scenario.imu.frame_period_s(),
        // Validated to 1..=4 by the scenario.
        order: u8::try_from(scenario.filter.discretisation_order).unwrap_or(3),
    };
    let initial_matrix = rotation_matrix(&initial_attitude);
    let paper_segment = |state: PaperMotionState| Segment {
        label: state.label().to_string(),
        point: state.linearisation_point(&initial_matrix),
        attitude: initial_attitude,
    };
    let [coast, rotation, acceleration] = PaperMotionState::ALL.map(paper_segment);
    let mut paper_states = Vec::new();
    for (column, segment) in [&coast, &rotation, &acceleration].into_iter().enumerate() {
        paper_states.push(analyser.analyse(
            &segment.label,
            std::slice::from_ref(segment),
            Some(column),
        )?);
    }
    paper_states.push(analyser.analyse("I→II", &[coast.clone(), rotation], None)?);
    paper_states.push(analyser.analyse("I→III", &[coast, acceleration], None)?);

    let mut segments: Vec<Segment> = Vec::new();
    let mut phases = Vec::new();
    let mut attitude = initial_attitude;
    for (position, manoeuvre) in scenario.manoeuvres.iter().enumerate() {
        let index = position + 1;
        let rate = rotation_vector_rad(&manoeuvre.body_rate_deg_per_s);
        let force = Vector3::from(manoeuvre.specific_force_mps2);
        let segment = Segment {
            label: manoeuvre.label.clone(),
            point: constant_motion(&rate, &force, &rotation_matrix(&attitude)),
            attitude,
        };
        // Attitude at the next phase start: ∫ rate dt = peak (duration − ramp) (scenario docs).
        attitude = product(
            &attitude,
            &exp_rotation_vector(&(rate * (manoeuvre.duration_s - manoeuvre.ramp_s))),
        );
        segments.push(segment.clone());
        let name = format!("phase {index} \"{}\"", manoeuvre.label);
        let after_previous =
            analyser.analyse(&format!("{name} after previous"), &segments, None)?;
        let alone = analyser.analyse(&format!("{name} alone"), &[segment], None)?;
        phases.push(PhaseReport {
            index,
            label: manoeuvre.label.clone(),
            body_rate_deg_per_s: manoeuvre.body_rate_deg_per_s,
            specific_force_mps2: manoeuvre.specific_force_mps2,
            after_previous,
            alone,
        });
    }

    let scaling = Scaling::typical();
    Ok(ObservabilityReport {
        scenario: origin.to_string(),
        scaling: ScalingReport {
            state_magnitudes: Scaling::TYPICAL_STATE_MAGNITUDES
                .iter()
                .map(|(block, magnitude)| BlockMagnitude {
                    block: block.name().to_string(),
                    magnitude: *magnitude,
                })
                .collect(),
            star_row_magnitude: Scaling::STAR_ROW_MAGNITUDE,
            gnss_row_magnitude: Scaling::GNSS_ROW_MAGNITUDE,
            time_unit_s: scaling.time_unit_s,
        },
        tolerance: ToleranceReport {
            relative_zero: RankTolerance::DEFAULT.relative,
            null_space_projection: RankTolerance::DEFAULT.projection,
            paper_absolute: RankTolerance::DEFAULT.absolute,
        },
        paper_like_step_s: analyser.step_s,
        paper_like_order: u32::from(analyser.order),
        paper_states,
        phases,
    })
}

/// The report as pretty-printed JSON.
///
/// # Errors
/// [`ObservabilityReportError::Json`] (not expected for finite numbers).
pub fn render_json(report: &ObservabilityReport) -> Result<String, ObservabilityReportError> {
    Ok(serde_json::to_string_pretty(report)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_report() -> ObservabilityReport {
        build_report(&Scenario::default_scenario().unwrap(), "<built-in default>").unwrap()
    }

    /// Names of the states that pass our null-space test.
    fn observable(case: &CaseReport) -> Vec<String> {
        case.states
            .iter()
            .filter(|s| s.observable)
            .map(|s| s.state.clone())
            .collect()
    }

    fn blocks(names: &[&str]) -> Vec<String> {
        (0..STATE_DIMENSION)
            .map(state_name)
            .filter(|state| names.iter().any(|n| state.starts_with(&format!("{n}."))))
            .collect()
    }

    fn case<'a>(report: &'a ObservabilityReport, label: &str) -> &'a CaseReport {
        report
            .paper_states
            .iter()
            .find(|c| c.label == label)
            .unwrap()
    }

    #[test]
    fn paper_states_alone_have_rank_15_and_the_model_s_null_spaces() {
        let report = default_report();
        // I: attitude and installation enter the star sensor only as C_sb ϑ + ψ, the gyro
        // bias only as b_g + ω λ_g (equal coast rates), f = 0 hides λ_a.
        let coast = case(&report, "I");
        assert_eq!(
            observable(coast),
            blocks(&["position", "velocity", "accel_bias"])
        );
        // II alone: b_g,z and λ_g,z enter as b + ω_z λ (constant ω): not separable.
        let rotation = case(&report, "II");
        assert_eq!(
            observable(rotation),
            blocks(&["position", "velocity", "accel_bias"])
        );
        // III alone: b_a and λ_a,y f_y likewise; attitude ⊥ f couples through b_a.
        let acceleration = case(&report, "III");
        assert_eq!(
            observable(acceleration),
            blocks(&["position", "velocity", "gyro_bias"])
        );
        for state in [coast, rotation, acceleration] {
            assert_eq!(state.rank, 15, "{}", state.label);
            assert_eq!(state.paper_like_rank, 15, "{}", state.label);
            assert_eq!(state.singular_values.len(), STATE_DIMENSION);
        }
        // The paper's Table 1 column I has 15 values above its threshold (its text: "15
        // states observable in state I").
        let paper_count = coast
            .states
            .iter()
            .filter(|s| s.paper_table_1_observable == Some(true))
            .count();
        assert_eq!(paper_count, 15);
    }

    #[test]
    fn pwcs_after_the_coast_separates_the_scale_factor_of_the_manoeuvre_axis() {
        let report = default_report();
        let rotation = case(&report, "I→II");
        assert_eq!(rotation.rank, 18);
        let flag = |case: &CaseReport, name: &str| {
            case.states
                .iter()
                .find(|s| s.state == name)
                .unwrap()
                .observable
        };
        assert!(flag(rotation, "gyro_scale_factor.z"));
        assert!(!flag(rotation, "gyro_scale_factor.x"));
        let acceleration = case(&report, "I→III");
        assert_eq!(acceleration.rank, 21);
        assert!(flag(acceleration, "accel_scale_factor.y"));
        assert!(!flag(acceleration, "accel_scale_factor.x"));
        assert!(!flag(acceleration, "accel_scale_factor.z"));
    }

    #[test]
    fn the_full_schedule_makes_all_24_states_observable() {
        let report = default_report();
        let scenario = Scenario::default_scenario().unwrap();
        assert_eq!(report.phases.len(), scenario.manoeuvres.len());
        let last = report.phases.last().unwrap();
        assert_eq!(last.after_previous.rank, STATE_DIMENSION);
        assert_eq!(last.after_previous.observable_count, STATE_DIMENSION);
        assert_eq!(
            last.after_previous.segments.len(),
            scenario.manoeuvres.len()
        );
        // The first phase (the initial coast) alone is state I's pattern.
        assert_eq!(report.phases[0].after_previous.rank, 15);
        // The cumulative observable count never decreases along the schedule.
        let counts: Vec<usize> = report
            .phases
            .iter()
            .map(|p| p.after_previous.observable_count)
            .collect();
        assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
        // No single constant phase alone gets past rank 15.
        assert!(report.phases.iter().all(|p| p.alone.rank == 15));
        // With τ shortened for the 100 °/s rotations (0.57 s) the weakest direction (the
        // accelerometer scale factors) stays far above the 1e-12 zero threshold.
        assert!((last.after_previous.time_unit_s - 1.0 / 100.0_f64.to_radians()).abs() < 1e-12);
        let sigma = &last.after_previous.singular_values;
        let conditioning = sigma[STATE_DIMENSION - 1] / sigma[0];
        assert!(conditioning > 1e-8, "{conditioning:e}");
    }

    #[test]
    fn json_has_the_documented_shape() {
        let report = default_report();
        let value: serde_json::Value =
            serde_json::from_str(&render_json(&report).unwrap()).unwrap();
        let paper_states = value["paper_states"].as_array().unwrap();
        assert_eq!(paper_states.len(), 5);
        let labels: Vec<&str> = paper_states
            .iter()
            .map(|c| c["label"].as_str().unwrap())
            .collect();
        assert_eq!(labels, ["I", "II", "III", "I→II", "I→III"]);
        let first_state = &paper_states[0]["states"][0];
        assert_eq!(first_state["state"], "attitude.x");
        for key in [
            "degree",
            "singular_value",
            "null_space_projection",
            "paper_like_singular_value",
        ] {
            assert!(first_state[key].is_number(), "{key}");
        }
        assert!(first_state["observable"].is_boolean());
        assert!(first_state["observable_paper_threshold"].is_boolean());
        assert!((first_state["paper_table_1"].as_f64().unwrap() - 2.2).abs() < 1e-12);
        assert_eq!(first_state["paper_table_1_observable"], true);
        // PWCS cases carry no Table 1 value.
        assert!(paper_states[3]["states"][0]["paper_table_1"].is_null());
        let phases = value["phases"].as_array().unwrap();
        let scenario_phases = crate::scenario::Scenario::default_scenario()
            .unwrap()
            .manoeuvres
            .len();
        assert_eq!(phases.len(), scenario_phases);
        for phase in phases {
            for key in ["after_previous", "alone"] {
                assert_eq!(phase[key]["states"].as_array().unwrap().len(), 24);
                assert_eq!(phase[key]["singular_values"].as_array().unwrap().len(), 24);
            }
        }
        assert_eq!(phases[10]["after_previous"]["observable_count"], 24);
        assert!((value["tolerance"]["paper_absolute"].as_f64().unwrap() - 5e-8).abs() < 1e-20);
        assert_eq!(
            value["scaling"]["state_magnitudes"]
                .as_array()
                .unwrap()
                .len(),
            8
        );
    }

    #[test]
    fn text_report_lists_every_state_and_phase() {
        let report = default_report();
        let text = render_text(&report);
        for k in 0..STATE_DIMENSION {
            // Table 1, the PWCS table and two phase tables.
            assert_eq!(
                text.lines()
                    .filter(|line| line.starts_with(&format!("{:22}", state_name(k))))
                    .count(),
                4,
                "{}",
                state_name(k)
            );
        }
        assert!(text.contains("rotate about body z"));
        assert!(
            text.contains("  8.7e19 +"),
            "the garbled Table 1 value is shown as printed"
        );
    }

    #[test]
    fn heat_map_is_a_png() {
        let report = default_report();
        let directory =
            std::env::temp_dir().join(format!("nav-sim-observability-{}", std::process::id()));
        std::fs::create_dir_all(&directory).unwrap();
        let path = directory.join(HEAT_MAP_FILE);
        write_heat_map(&report, &path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        assert!(bytes.len() > 10_000, "{} bytes", bytes.len());
        std::fs::remove_dir_all(&directory).unwrap();
    }

    #[test]
    fn paper_table_1_transcription_spot_checks() {
        // Values the paper's text discusses: gyro scale factor z in state II and accelerometer
        // scale factor y in state III are large; installation in state I is zero.
        assert!((PAPER_TABLE_1[20][1] - 3.3e4).abs() < 1e-9);
        assert!((PAPER_TABLE_1[22][2] - 1.6e3).abs() < 1e-9);
        assert!(PAPER_TABLE_1[15..18].iter().all(|row| row[0] < 5e-8));
    }
}
