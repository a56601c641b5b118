//! The covariance the analysis carries: nav-core's dense 24-state filter (27 with the
//! correlated GNSS error states), or, when the scenario turns on the twelve systematic IMU
//! error states (`[filter.imu_errors]`), a host-side dense covariance over 36 states (39 with
//! the GNSS states), which nav-core's dense reference refuses.
//!
//! The augmented model is the flight filter's (nav-core `imu_error_states`, module docs):
//! the twelve states are random constants, each acting on the navigation as an equivalent
//! sensor bias ([`equivalent_bias_terms`]): with `M` (6×12) holding the measured rate or
//! force component `m_k` on the gyro or accelerometer axis state `k` disturbs, the continuous
//! columns are the bias columns times `M`, and the discrete transition of the same order is
//! `Γ = E M` with `E` the bias columns of `F` minus their identity (the calibration rows of
//! `A` are zero). The order of the states is `x` (24), `ε_IMU` (12), then `ε_GNSS` (3):
//!
//! ```text
//! F₃₉ = [[F, E M, 0], [0, I, 0], [0, 0, φ I]],   Q₃₉ = diag(Qd, 0, σ²(1 − φ²) I)
//! P ← F₃₉ P F₃₉ᵀ + Q₃₉
//! ```
//!
//! and the update is the Joseph form with `H = [H_x, 0, h_ε I]` (no measurement sees the
//! IMU error states directly). Without the GNSS error states the last three rows and columns
//! stay zero. The second-order attitude growth reads and grows the 24-state
//! block only, as the flight software's does.

use nalgebra::{Matrix3, SMatrix};
use nav_core::discretise::{CovarianceMatrix, DiscreteModel};
use nav_core::error_model::LinearisationPoint;
use nav_core::filter::{ErrorState, ErrorStateFilter};
use nav_core::gnss_error::GnssErrorModel;
use nav_core::imu_error::{equivalent_bias_terms, BiasSensor, IMU_ERROR_DIMENSION};
use nav_core::measurement::LinearMeasurement;
use nav_core::state::{ACCEL_BIAS, ATTITUDE, GYRO_BIAS, STATE_DIMENSION};
use nav_core::NavError;

/// First of the twelve IMU error states in the augmented vector.
const IMU: usize = STATE_DIMENSION;
/// First of the three correlated GNSS error states (when carried).
const GNSS: usize = STATE_DIMENSION + IMU_ERROR_DIMENSION;
/// States of the augmented covariance: without the GNSS error states their rows and columns
/// stay zero (a zero prior, no noise, no measurement sees them), so the rest is the 36-state
/// covariance.
const DIMENSION: usize = GNSS + 3;
/// An augmented matrix.
type Square = SMatrix<f64, DIMENSION, DIMENSION>;

/// The covariance the analysis propagates and updates (module docs).
#[derive(Debug, Clone)]
pub(super) enum AnalysedFilter {
    /// nav-core's dense filter (24 or 27 states).
    Flight(Box<ErrorStateFilter>),
    /// The host-side 36- or 39-state covariance.
    Augmented(AugmentedCovariance),
}

impl AnalysedFilter {
    /// nav-core's filter, or the augmented covariance started from its prior when it carries
    /// the IMU error states.
    pub(super) fn new(filter: ErrorStateFilter) -> Self {
        if filter.imu_error().is_enabled() {
            Self::Augmented(AugmentedCovariance::from_prior(&filter))
        } else {
            Self::Flight(Box::new(filter))
        }
    }

    /// Time update with the 24-state discrete model of `point`.
    ///
    /// # Errors
    /// nav-core's error, or [`NavError::NonFiniteState`] for a non-finite result.
    pub(super) fn predict(
        &mut self,
        model: &DiscreteModel,
        point: &LinearisationPoint,
    ) -> Result<(), NavError> {
        match self {
            Self::Flight(filter) => filter.predict(model),
            Self::Augmented(augmented) => augmented.predict(model, point),
        }
    }

    /// Joseph-form update (no gate); whether it was applied.
    ///
    /// # Errors
    /// nav-core's error, [`NavError::NonPositiveInnovationCovariance`] or
    /// [`NavError::NonFiniteState`].
    pub(super) fn update(&mut self, linear: &LinearMeasurement) -> Result<bool, NavError> {
        match self {
            Self::Flight(filter) => filter
                .update(linear, f64::INFINITY)
                .map(|report| report.accepted),
            Self::Augmented(augmented) => augmented.update(linear).map(|()| true),
        }
    }

    /// The 24-state block of the covariance.
    pub(super) fn covariance(&self) -> CovarianceMatrix {
        match self {
            Self::Flight(filter) => *filter.covariance(),
            Self::Augmented(augmented) => augmented.navigation_covariance(),
        }
    }

    /// Adds `added` to the attitude block.
    ///
    /// # Errors
    /// nav-core's error for a non-finite or non-symmetric `added`.
    pub(super) fn add_attitude_covariance(&mut self, added: &Matrix3<f64>) -> Result<(), NavError> {
        match self {
            Self::Flight(filter) => filter.add_block_covariance(ATTITUDE, added),
            Self::Augmented(augmented) => augmented.add_attitude_covariance(added),
        }
    }

    /// 1σ of the 24 states.
    pub(super) fn standard_deviations(&self) -> ErrorState {
        match self {
            Self::Flight(filter) => filter.standard_deviations(),
            Self::Augmented(augmented) => {
                ErrorState::from_fn(|k, _| augmented.sigma(k).unwrap_or(0.0))
            }
        }
    }

    /// 1σ of the twelve IMU error states (nav-core `ImuErrorBlock` order), when carried.
    pub(super) fn imu_error_sigmas(&self) -> Option<[f64; IMU_ERROR_DIMENSION]> {
        match self {
            Self::Flight(_) => None,
            Self::Augmented(augmented) => Some(core::array::from_fn(|k| {
                augmented.sigma(IMU + k).unwrap_or(0.0)
            })),
        }
    }
}

/// The host-side augmented covariance (module docs).
#[derive(Debug, Clone)]
pub(super) struct AugmentedCovariance {
    covariance: Box<Square>,
    /// The correlated GNSS error states' model, when carried.
    gnss: Option<GnssErrorModel>,
}

/// `M` (6×12): state `k` enters the gyro (rows 0-2) or accelerometer (rows 3-5) error on one
/// axis, times the measured rate or force component (nav-core [`equivalent_bias_terms`]).
pub(super) fn equivalent_bias_map(
    point: &LinearisationPoint,
) -> SMatrix<f64, 6, IMU_ERROR_DIMENSION> {
    let mut map = SMatrix::<f64, 6, IMU_ERROR_DIMENSION>::zeros();
    let terms = equivalent_bias_terms(
        &point.measured_rate_rad_s,
        &point.measured_specific_force_mps2,
    );
    for (k, term) in terms.iter().enumerate() {
        let row = match term.sensor {
            BiasSensor::Gyro => term.axis,
            BiasSensor::Accel => 3 + term.axis,
        };
        map[(row, k)] = term.multiplier;
    }
    map
}

/// `E`: the gyro and accelerometer bias columns of `F` (24×6) without their identity.
pub(super) fn bias_columns(
    transition: &nav_core::error_model::SystemMatrix,
) -> SMatrix<f64, STATE_DIMENSION, 6> {
    let mut columns = SMatrix::<f64, STATE_DIMENSION, 6>::zeros();
    for (offset, block) in [(0, GYRO_BIAS), (3, ACCEL_BIAS)] {
        for axis in 0..3 {
            let state = block.index() + axis;
            for row in 0..STATE_DIMENSION {
                let identity = if row == state { 1.0 } else { 0.0 };
                columns[(row, offset + axis)] = transition[(row, state)] - identity;
            }
        }
    }
    columns
}

impl AugmentedCovariance {
    /// The flight filter's prior: its 24-state covariance, the IMU error states' and, when
    /// carried, the GNSS error states' (with their cross-covariances, zero at the start).
    fn from_prior(filter: &ErrorStateFilter) -> Self {
        let gnss = filter.gnss_error();
        let mut covariance = Box::new(Square::zeros());
        covariance
            .fixed_view_mut::<STATE_DIMENSION, STATE_DIMENSION>(0, 0)
            .copy_from(filter.covariance());
        covariance
            .fixed_view_mut::<IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>(IMU, IMU)
            .copy_from(&filter.imu_error().covariance());
        if gnss.is_enabled() {
            covariance
                .fixed_view_mut::<3, 3>(GNSS, GNSS)
                .copy_from(&gnss.covariance());
        }
        Self {
            covariance,
            gnss: gnss.is_enabled().then(|| *gnss.model()),
        }
    }

    fn sigma(&self, k: usize) -> Option<f64> {
        (k < DIMENSION).then(|| self.covariance[(k, k)].max(0.0).sqrt())
    }

    /// `P ← F₃₉ P F₃₉ᵀ + Q₃₉` (module docs).
    fn predict(
        &mut self,
        model: &DiscreteModel,
        point: &LinearisationPoint,
    ) -> Result<(), NavError> {
        let mut transition = Square::identity();
        transition
            .fixed_view_mut::<STATE_DIMENSION, STATE_DIMENSION>(0, 0)
            .copy_from(&model.transition);
        let coupling = bias_columns(&model.transition) * equivalent_bias_map(point);
        transition
            .fixed_view_mut::<STATE_DIMENSION, IMU_ERROR_DIMENSION>(0, IMU)
            .copy_from(&coupling);
        let mut noise = Square::zeros();
        noise
            .fixed_view_mut::<STATE_DIMENSION, STATE_DIMENSION>(0, 0)
            .copy_from(&model.process_noise);
        if let Some(gnss) = &self.gnss {
            let phi = gnss.decay(model.interval_s);
            let walk = gnss.sigma_m * gnss.sigma_m * (1.0 - phi * phi);
            for k in GNSS..DIMENSION {
                transition[(k, k)] = phi;
                noise[(k, k)] = walk;
            }
        }
        let propagated = transition * *self.covariance * transition.transpose() + noise;
        self.commit(&propagated)
    }

    /// Joseph-form update with `H = [H_x, 0, h_ε I]` (module docs).
    fn update(&mut self, linear: &LinearMeasurement) -> Result<(), NavError> {
        let mut h = SMatrix::<f64, 3, DIMENSION>::zeros();
        h.fixed_view_mut::<3, STATE_DIMENSION>(0, 0)
            .copy_from(&linear.jacobian);
        if self.gnss.is_some() {
            for axis in 0..3 {
                h[(axis, GNSS + axis)] = linear.border_coefficient;
            }
        }
        let noise = linear.noise_covariance;
        let p_ht = *self.covariance * h.transpose();
        let innovation = h * p_ht + noise;
        let cholesky = innovation
            .cholesky()
            .ok_or(NavError::NonPositiveInnovationCovariance)?;
        let gain = cholesky.solve(&p_ht.transpose()).transpose();
        let i_minus_kh = Square::identity() - gain * h;
        let updated = i_minus_kh * *self.covariance * i_minus_kh.transpose()
            + gain * noise * gain.transpose();
        self.commit(&updated)
    }

    fn navigation_covariance(&self) -> CovarianceMatrix {
        CovarianceMatrix::from_fn(|i, j| self.covariance[(i, j)])
    }

    fn add_attitude_covariance(&mut self, added: &Matrix3<f64>) -> Result<(), NavError> {
        if !added.iter().all(|v| v.is_finite()) {
            return Err(NavError::NonFiniteInput);
        }
        let first = ATTITUDE.index();
        let mut block = self.covariance.fixed_view_mut::<3, 3>(first, first);
        block += added;
        Ok(())
    }

    /// Keeps the symmetric part of `covariance` if it is finite.
    fn commit(&mut self, covariance: &Square) -> Result<(), NavError> {
        if covariance.iter().all(|v| v.is_finite()) {
            *self.covariance = (covariance + covariance.transpose()) * 0.5;
            Ok(())
        } else {
            Err(NavError::NonFiniteState)
        }
    }
}
