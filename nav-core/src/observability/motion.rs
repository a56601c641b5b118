//! The paper's motion states of Table 1 ([`PaperMotionState`]) and the flight's question at a
//! phase change: which blocks and axes a constant motion makes observable after a reference
//! coast ([`motion_observability`]).

use nalgebra::{Matrix3, Quaternion, Vector3};

use super::{
    stack_measurements, MeasurementMatrix, ObservabilityAnalysis, RankTolerance, Scaling,
    StrippedObservability, SystemForm,
};
use crate::error_model::{system_matrix, LinearisationPoint};
use crate::measurement::{gnss_position, star_sensor};
use crate::state::StateBlock;
use crate::NavError;

/// Degrees to radians (for the paper's rates, given in °/s).
const RADIANS_PER_DEGREE: f64 = core::f64::consts::PI / 180.0;

/// The paper's three motion states of Table 1 (Section 2.3): the constant motions whose
/// observability the paper tabulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PaperMotionState {
    /// State I, unpowered coast: body rate 2.4e-4 °/s about every axis, no specific force.
    Coast,
    /// State II, attitude manoeuvre: body rate (0, 0, 10) °/s, no specific force.
    Rotation,
    /// State III, linear acceleration: specific force (0, 20, 0) m/s², no rotation.
    Acceleration,
}

impl PaperMotionState {
    /// The three states in the paper's order (Table 1 columns I, II, III).
    pub const ALL: [PaperMotionState; 3] = [Self::Coast, Self::Rotation, Self::Acceleration];
    /// State I's rate about each axis (°/s).
    pub const COAST_RATE_DEG_PER_S: f64 = 2.4e-4;
    /// State II's rate about body z (°/s).
    pub const ROTATION_RATE_DEG_PER_S: f64 = 10.0;
    /// State III's specific force along body y (m/s²).
    pub const ACCELERATION_MPS2: f64 = 20.0;

    /// The paper's label: "I", "II" or "III".
    pub fn label(self) -> &'static str {
        match self {
            Self::Coast => "I",
            Self::Rotation => "II",
            Self::Acceleration => "III",
        }
    }

    /// Body rate of the state (rad/s).
    pub fn body_rate_rad_s(self) -> Vector3<f64> {
        match self {
            Self::Coast => Vector3::repeat(Self::COAST_RATE_DEG_PER_S * RADIANS_PER_DEGREE),
            Self::Rotation => {
                Vector3::new(0.0, 0.0, Self::ROTATION_RATE_DEG_PER_S * RADIANS_PER_DEGREE)
            }
            Self::Acceleration => Vector3::zeros(),
        }
    }

    /// Specific force of the state (m/s²).
    pub fn specific_force_mps2(self) -> Vector3<f64> {
        match self {
            Self::Acceleration => Vector3::new(0.0, Self::ACCELERATION_MPS2, 0.0),
            Self::Coast | Self::Rotation => Vector3::zeros(),
        }
    }

    /// The linearisation point of this state at attitude `body_to_inertial` ([`constant_motion`]).
    pub fn linearisation_point(self, body_to_inertial: &Matrix3<f64>) -> LinearisationPoint {
        constant_motion(
            &self.body_rate_rad_s(),
            &self.specific_force_mps2(),
            body_to_inertial,
        )
    }
}

/// A constant-motion segment of the PWCS as the paper analyses it: measured = corrected rate
/// and specific force (the estimated sensor errors are zero at the start of an analysis),
/// attitude frozen at `body_to_inertial` (`Ĉ`, body to launch-inertial), gravity gradient zero
/// (paper eq. 14 ignores the gravity error).
pub fn constant_motion(
    body_rate_rad_s: &Vector3<f64>,
    specific_force_mps2: &Vector3<f64>,
    body_to_inertial: &Matrix3<f64>,
) -> LinearisationPoint {
    LinearisationPoint {
        corrected_rate_rad_s: *body_rate_rad_s,
        corrected_specific_force_mps2: *specific_force_mps2,
        measured_rate_rad_s: *body_rate_rad_s,
        measured_specific_force_mps2: *specific_force_mps2,
        body_to_inertial: *body_to_inertial,
        gravity_gradient_per_s2: Matrix3::zeros(),
    }
}

/// `H` of a full update (star rows 0-2, GNSS rows 3-5) at attitude `q̂_ib` with the nominal
/// star-sensor mounting `q_bs`, a zero installation estimate and a zero GNSS lever arm (the
/// paper has none): the blocks of [`star_sensor`] and [`gnss_position`], stacked.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in a quaternion.
pub fn full_update_measurement_matrix(
    attitude: &Quaternion<f64>,
    mounting: &Quaternion<f64>,
) -> Result<MeasurementMatrix, NavError> {
    let identity = Quaternion::identity();
    let star = star_sensor(attitude, mounting, &identity, &identity, &[0.0; 3])?;
    let zero = Vector3::zeros();
    let gnss = gnss_position(attitude, &zero, &zero, &zero, 0.0)?;
    Ok(stack_measurements(&star.jacobian, &gnss.jacobian))
}

/// Per block (the eight blocks of [`StateBlock::ALL`], in order) and per axis: whether the state passes
/// the null-space test. The flight calibration manager's view of an [`ObservabilityAnalysis`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisObservability {
    /// `axes[b][k]`: state `k` (x, y, z) of block `StateBlock::ALL[b]` is observable.
    pub axes: [[bool; 3]; 8],
}

impl AxisObservability {
    /// Regroups the per-state flags of `analysis` by block.
    pub fn from_analysis(analysis: &ObservabilityAnalysis) -> Self {
        let mut axes = [[false; 3]; 8];
        for (block, states) in axes.iter_mut().zip(analysis.observable.chunks_exact(3)) {
            for (flag, observable) in block.iter_mut().zip(states.iter()) {
                *flag = *observable;
            }
        }
        Self { axes }
    }

    /// The three flags of `block` (all `false` for a block not in [`StateBlock::ALL`]).
    pub fn block(&self, block: StateBlock) -> [bool; 3] {
        StateBlock::ALL
            .iter()
            .zip(self.axes.iter())
            .find(|(candidate, _)| **candidate == block)
            .map_or([false; 3], |(_, flags)| *flags)
    }

    /// Whether every axis of `block` is observable.
    pub fn fully_observable(&self, block: StateBlock) -> bool {
        self.block(block).iter().all(|flag| *flag)
    }

    /// Number of observable states (0..=24).
    pub fn observable_count(&self) -> usize {
        self.axes.iter().flatten().filter(|flag| **flag).count()
    }
}

/// Which states the constant motion `point` makes observable, for the flight calibration
/// manager at a phase change (estimate the blocks that are observable, freeze the others).
///
/// The question is asked in the paper's PWCS setting (Section 2; see the module docs and
/// `docs/guide/observability.md`): the stripped observability matrix of two continuous segments,
/// an ideal coast (ω = 0, f = 0) at the same attitude and then `point`, scaled with
/// [`Scaling::typical`]. A single constant segment on its own can never separate a scale
/// factor from the bias on the same axis (they enter as `b + diag(ω) λ` with constant `ω`), so
/// without the reference coast no manoeuvre would ever report a scale factor. Tolerance:
/// `tolerance` (use [`RankTolerance::DEFAULT`]: singular values ≤ 1e-12 σ_max are zero, a
/// state is observable when its unit vector's projection on that null space is ≤ 1e-6). This
/// is structural observability: a state that passes may still be weak (see
/// [`ObservabilityAnalysis::degree`]).
///
/// Cost: two segments of 144 Givens row updates on a 24×24 factor and one 24×24 SVD.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in `point` or `h`; [`NavError::SingularMatrix`] or
/// [`NavError::NonFiniteState`] if the SVD fails.
pub fn motion_observability(
    point: &LinearisationPoint,
    h: &MeasurementMatrix,
    tolerance: &RankTolerance,
) -> Result<AxisObservability, NavError> {
    let analysis = motion_observability_analysis(point, h, tolerance)?;
    Ok(AxisObservability::from_analysis(&analysis))
}

/// The analysis behind [`motion_observability`] (reference coast, then `point`; scaled
/// continuous segments), for callers that need more than the per-state flags, e.g.
/// [`ObservabilityAnalysis::observable_directions`].
///
/// # Errors
/// As [`motion_observability`].
pub fn motion_observability_analysis(
    point: &LinearisationPoint,
    h: &MeasurementMatrix,
    tolerance: &RankTolerance,
) -> Result<ObservabilityAnalysis, NavError> {
    let reference_coast = constant_motion(
        &Vector3::zeros(),
        &Vector3::zeros(),
        &point.body_to_inertial,
    );
    let mut stripped = StrippedObservability::new(Scaling::typical())?;
    stripped.add_segment(&system_matrix(&reference_coast), h, SystemForm::Continuous)?;
    stripped.add_segment(&system_matrix(point), h, SystemForm::Continuous)?;
    stripped.analyse(tolerance)
}
