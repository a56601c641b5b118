//! The error-state Kalman filter: covariance prediction, gated Joseph-form updates, and the
//! open-loop (paper) or closed-loop (reset) handling of the error state.
//!
//! * Predict: `x ← F x` (open loop only; closed loop keeps `x = 0`), `P ← F P Fᵀ + Qd`.
//! * Update: `ν = z − H x`, `S = H P Hᵀ + R` (Cholesky; not positive definite ⇒ error),
//!   NIS `= νᵀ S⁻¹ ν`, `K = P Hᵀ S⁻¹`, `x ← x + K ν`,
//!   Joseph form `P ← (I − K H) P (I − K H)ᵀ + K R Kᵀ` (Bucy & Joseph 1968), then
//!   symmetrised. A measurement whose NIS exceeds the gate leaves `x` and `P` untouched.
//! * Closed-loop reset: the caller applies `x` to the navigation solution and the sensor
//!   estimates ([`apply_error_state`]), and the filter zeroes `x` and maps `P` through the
//!   reset Jacobian: after `q̂⁺ = q̂ ⊗ δq(ϑ̂)`, the new error is `δq⁺ = δq(ϑ̂)* ⊗ δq`, so
//!   `∂ϑ⁺/∂ϑ = I − [ϑ̂×]` to first order (Solà 2017, §7.2, with `ϑ = δθ/2`); likewise for the
//!   installation error. All other blocks reset with the identity.
//!
//! Every failure is a typed [`NavError`] and leaves the filter exactly as it was.

use core::mem::MaybeUninit;

use nalgebra::{Cholesky, Matrix3, Quaternion, SVector, Vector3};

use crate::attitude::{self, skew};
use crate::block;
use crate::block_interface::{MeasuredBorder, UpdateInputs};
use crate::discretise::CovarianceMatrix;
use crate::measurement::LinearMeasurement;
use crate::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::structured::{self, StructuredModel};
use crate::NavError;
use blocks::OptionalBlocks;

pub use blocks::FilterConfig;
pub use config::InitialUncertainty;
pub use covariance::CALIBRATION_LOWER_TRIANGLE;
pub use optional::OptionalVarianceBounds;

/// The 24-element error-state vector.
pub type ErrorState = SVector<f64, STATE_DIMENSION>;

/// How the estimated errors are used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FilterMode {
    /// The paper's filter: the navigation solution is never corrected; `x` accumulates.
    OpenLoop,
    /// After each update the errors are fed back and `x` is zeroed (flight practice).
    ClosedLoop,
}

/// What an update computed, for gating and telemetry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InnovationReport {
    /// Innovation `ν = z − H x`.
    pub innovation: Vector3<f64>,
    /// Innovation covariance `S = H P Hᵀ + R`.
    pub covariance: Matrix3<f64>,
    /// Normalised innovation squared `νᵀ S⁻¹ ν` (χ² with 3 degrees of freedom if consistent).
    pub normalised_innovation_squared: f64,
    /// Whether the update was applied (false: rejected by the gate, filter untouched).
    pub accepted: bool,
}

/// The sensor-error estimates the closed-loop filter feeds back into.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationEstimate {
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: [f64; 3],
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: [f64; 3],
    /// Star-sensor installation error `q̂_ψ`, `[w, x, y, z]`.
    pub star_installation_wxyz: [f64; 4],
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: [f64; 3],
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: [f64; 3],
}

impl Default for CalibrationEstimate {
    fn default() -> Self {
        Self {
            gyro_bias_rad_s: [0.0; 3],
            accel_bias_mps2: [0.0; 3],
            star_installation_wxyz: [1.0, 0.0, 0.0, 0.0],
            gyro_scale_factor: [0.0; 3],
            accel_scale_factor: [0.0; 3],
        }
    }
}

/// Error state and covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStateFilter {
    state: ErrorState,
    covariance: CovarianceMatrix,
    mode: FilterMode,
    /// The optional blocks of the layout ([`crate::state::OptionalBlock`]), each inert when
    /// its model is off.
    blocks: OptionalBlocks,
}

/// The three states of `block`. Read with checked indices, so no panic path is compiled; the
/// closed state layout ([`StateBlock`]) keeps every index inside the state, so the NaN
/// fallback is never returned.
pub fn block_of(state: &ErrorState, block: StateBlock) -> Vector3<f64> {
    let component = |offset: usize| {
        block
            .index()
            .checked_add(offset)
            .and_then(|index| state.get(index))
            .copied()
            .unwrap_or(f64::NAN)
    };
    Vector3::new(component(0), component(1), component(2))
}

fn add3(target: &mut [f64; 3], delta: &Vector3<f64>) {
    let [x, y, z] = target;
    *x += delta.x;
    *y += delta.y;
    *z += delta.z;
}

/// Applies an error state to a navigation solution and calibration estimate (closed-loop
/// feedback): `q̂ ← q̂ ⊗ δq(ϑ)`, `p̂ += δp`, `v̂ += δv`, `b̂ += δb`, `λ̂ += δλ`,
/// `q̂_ψ ← q̂_ψ ⊗ δq(ψ)`. Nothing is changed on error.
///
/// # Errors
/// [`NavError::NonFiniteState`] if `x` is not finite, [`NavError::DegenerateQuaternion`] if
/// an attitude correction is not a valid quaternion vector part (|ϑ| ≥ 1).
pub fn apply_error_state(
    error: &ErrorState,
    attitude: &mut Quaternion<f64>,
    position_m: &mut Vector3<f64>,
    velocity_mps: &mut Vector3<f64>,
    calibration: &mut CalibrationEstimate,
) -> Result<(), NavError> {
    if !block::all_finite(error.as_slice()) {
        return Err(NavError::NonFiniteState);
    }
    let attitude_correction = attitude::from_vector_part(&block_of(error, ATTITUDE))?;
    let installation_correction = attitude::from_vector_part(&block_of(error, STAR_INSTALLATION))?;
    let [w, x, y, z] = calibration.star_installation_wxyz;
    let installation = attitude::normalise(&attitude::product(
        &Quaternion::new(w, x, y, z),
        &installation_correction,
    ))?;
    let new_attitude = attitude::normalise(&attitude::product(attitude, &attitude_correction))?;
    *attitude = new_attitude;
    calibration.star_installation_wxyz = [
        installation.w,
        installation.i,
        installation.j,
        installation.k,
    ];
    *position_m += block_of(error, POSITION);
    *velocity_mps += block_of(error, VELOCITY);
    add3(
        &mut calibration.gyro_bias_rad_s,
        &block_of(error, GYRO_BIAS),
    );
    add3(
        &mut calibration.accel_bias_mps2,
        &block_of(error, ACCEL_BIAS),
    );
    add3(
        &mut calibration.gyro_scale_factor,
        &block_of(error, GYRO_SCALE_FACTOR),
    );
    add3(
        &mut calibration.accel_scale_factor,
        &block_of(error, ACCEL_SCALE_FACTOR),
    );
    Ok(())
}

impl ErrorStateFilter {
    /// Everything zero, every optional block empty: what [`Self::init_in_place`] writes into
    /// its slot before the configuration's values.
    const EMPTY: Self = Self {
        state: ErrorState::from_array_storage(nalgebra::ArrayStorage([[0.0; STATE_DIMENSION]; 1])),
        covariance: CovarianceMatrix::from_array_storage(nalgebra::ArrayStorage(
            [[0.0; STATE_DIMENSION]; STATE_DIMENSION],
        )),
        // The zero discriminant: the constant is all zero bits, so it is written by a clear.
        mode: FilterMode::OpenLoop,
        blocks: OptionalBlocks::EMPTY,
    };

    /// A filter with `x = 0` and `P = diag(σ²)` from the configuration.
    ///
    /// # Errors
    /// As [`FilterConfig::validate`].
    pub fn new(config: &FilterConfig) -> Result<Self, NavError> {
        config.validate()?;
        let mut filter = Self {
            state: ErrorState::zeros(),
            covariance: CovarianceMatrix::zeros(),
            mode: config.mode,
            blocks: OptionalBlocks::EMPTY,
        };
        filter.blocks.start(config);
        filter.set_initial_covariance(config);
        Ok(filter)
    }

    /// [`ErrorStateFilter::new`] written into `slot` (a field of a larger structure, or a
    /// `static`), where it stays: the large filter is not built on the stack first and moved.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::new`]; `slot` is not written then.
    ///
    /// # Examples
    /// ```
    /// use core::mem::MaybeUninit;
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let mut slot = MaybeUninit::uninit();
    /// let filter = ErrorStateFilter::init_in_place(&mut slot, &config)?;
    /// assert_eq!(filter.covariance(), ErrorStateFilter::new(&config)?.covariance());
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn init_in_place<'slot>(
        slot: &'slot mut MaybeUninit<Self>,
        config: &FilterConfig,
    ) -> Result<&'slot mut Self, NavError> {
        config.validate()?;
        // Written from a constant: copied straight into the slot, never built on the stack.
        let filter = slot.write(Self::EMPTY);
        filter.mode = config.mode;
        filter.blocks.start(config);
        filter.set_initial_covariance(config);
        Ok(filter)
    }

    /// [`ErrorStateFilter::new`] again, in place (the filter is not built on the stack and
    /// moved): `x = 0`, `P = diag(σ²)`, every optional block at its prior.
    ///
    /// # Errors
    /// As [`ErrorStateFilter::new`]; the filter is unchanged then.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::state::VELOCITY;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let mut filter = ErrorStateFilter::new(&config)?;
    /// filter.add_block_variance(VELOCITY, 0.03)?;
    /// filter.restart(&config)?;
    /// assert_eq!(filter, ErrorStateFilter::new(&config)?);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn restart(&mut self, config: &FilterConfig) -> Result<(), NavError> {
        config.validate()?;
        self.state = ErrorState::zeros();
        self.covariance.fill(0.0);
        self.mode = config.mode;
        self.restart_optional_blocks(config);
        self.set_initial_covariance(config);
        Ok(())
    }

    /// Every optional block back at `config`'s prior (`config` checked by the caller, so
    /// nothing here can fail).
    fn restart_optional_blocks(&mut self, config: &FilterConfig) {
        self.blocks = OptionalBlocks::EMPTY;
        self.blocks.start(config);
    }

    /// The error-state estimate `x`.
    pub fn state(&self) -> &ErrorState {
        &self.state
    }

    /// The covariance `P`.
    pub fn covariance(&self) -> &CovarianceMatrix {
        &self.covariance
    }

    /// The mode.
    pub fn mode(&self) -> FilterMode {
        self.mode
    }

    /// 1σ of every state (square roots of the diagonal of `P`).
    pub fn standard_deviations(&self) -> ErrorState {
        self.covariance
            .diagonal()
            .map(|variance| crate::float::sqrt(variance.max(0.0)))
    }

    /// Innovation, its covariance and NIS for `measurement`, without changing the filter.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for NaN/Inf in the measurement,
    /// [`NavError::NonPositiveInnovationCovariance`] if `S` is not positive definite.
    pub fn innovation(
        &self,
        measurement: &LinearMeasurement,
    ) -> Result<InnovationReport, NavError> {
        check_measurement(measurement)?;
        let h = &measurement.jacobian;
        innovation_report(
            measurement.residual - h * self.state,
            &(h * self.covariance * h.transpose() + measurement.noise_covariance),
        )
    }

    /// Structured time update (the flight path): `P ← F P Fᵀ + Qd` and, in open loop,
    /// `x ← F x`, computed by blocks from a [`StructuredModel`] (derivation in
    /// [`crate::structured`]); equal to `ErrorStateFilter::predict` with the dense model
    /// of the same point within relative 1e-12.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the result is not finite (filter unchanged).
    pub fn predict_structured(&mut self, model: &StructuredModel) -> Result<(), NavError> {
        let state = match self.mode {
            FilterMode::OpenLoop => {
                let state = model.propagate_state(&self.state);
                if !block::all_finite(state.as_slice()) {
                    return Err(NavError::NonFiniteState);
                }
                Some(state)
            }
            // Closed loop: x = 0 stays 0.
            FilterMode::ClosedLoop => None,
        };
        // The optional blocks' new values first, then the core kernel (with their inputs),
        // then their commits: nothing changes on an error.
        let blocks = self.blocks.any_enabled();
        if blocks && !self.blocks.prepare_propagation(model, state.is_some()) {
            return Err(NavError::NonFiniteState);
        }
        if !model.propagate_covariance(&mut self.covariance, self.blocks.kernel_inputs()) {
            return Err(NavError::NonFiniteState);
        }
        if let Some(mut state) = state {
            self.blocks.add_state_increment(&mut state);
            self.state = state;
        }
        if blocks {
            self.blocks.commit_propagation(model);
        }
        Ok(())
    }

    /// Structured measurement update (the flight path): the same gated, frozen-block
    /// Joseph-form update as `ErrorStateFilter::update_with_frozen_blocks`, with `P Hᵀ`
    /// summed over the non-zero 3×3 blocks of `H` only, a 3×3 Cholesky of `S`, and the Joseph
    /// form expanded to O(n²) in place (derivation in [`crate::structured`]); equal to the
    /// dense update within relative 1e-12.
    ///
    /// # Errors
    /// As `ErrorStateFilter::update_with_frozen_blocks`; the filter is unchanged on any
    /// error.
    pub fn update_structured(
        &mut self,
        measurement: &LinearMeasurement,
        gate_nis: f64,
        frozen: &BlockMask,
    ) -> Result<InnovationReport, NavError> {
        check_update_inputs(measurement, gate_nis)?;
        let h = &measurement.jacobian;
        // H P = Mᵀ and H P Hᵀ, over the non-zero blocks of H.
        // The measured border (crate::block_interface), when one is in use.
        let coefficient = measurement.border_coefficient;
        let observed_blocks = structured::observed_blocks(h);
        let border = self
            .blocks
            .measured_border((h, &observed_blocks), coefficient);
        let mut products = [[0.0; 3]; STATE_DIMENSION];
        let observed = structured::ObservedCovariance::new(
            &mut products,
            (h, &observed_blocks),
            &self.covariance,
            self.blocks.measured_rows(border.as_ref()),
        );
        // `&self.state`: by reference, so the state is not copied first (a `memcpy` on the
        // target; clippy's `op_ref` assumes the copy is free).
        #[allow(clippy::op_ref)]
        let mut innovation = measurement.residual - h * &self.state;
        if let Some(border) = &border {
            innovation -= self.blocks.predicted_residual(border);
        }
        let covariance = symmetrised3(&(observed.projected() + measurement.noise_covariance));
        let cholesky = structured::Cholesky3::new(&covariance)
            .ok_or(NavError::NonPositiveInnovationCovariance)?;
        // NIS = νᵀ S⁻¹ ν = |L⁻¹ ν|².
        let whitened = Vector3::from(cholesky.whiten([innovation.x, innovation.y, innovation.z]));
        let nis = whitened.norm_squared();
        if !nis.is_finite() {
            return Err(NavError::NonPositiveInnovationCovariance);
        }
        if nis > gate_nis {
            return Ok(InnovationReport {
                innovation,
                covariance,
                normalised_innovation_squared: nis,
                accepted: false,
            });
        }
        // K = P Hᵀ S⁻¹ by state blocks, frozen blocks' gain zero.
        let gains = observed.gain(&cholesky, frozen);
        // x + K ν is checked first and added in place last (the same values twice: no
        // copy of the state to roll back).
        if !structured::corrected_state_is_finite(&self.state, &gains, &innovation) {
            return Err(NavError::NonFiniteState);
        }
        // The kernels read a copy of `S` (nine values): the report's own is then written
        // into the result directly, where one whose address the kernels take is copied
        // there with the innovation.
        let s = covariance;
        if self.blocks.any_enabled() {
            let solved = (&cholesky, &s, frozen);
            let jacobian = (h, &observed_blocks);
            self.update_borders_and_covariance(
                border.as_ref(),
                jacobian,
                &gains,
                &observed,
                solved,
                &innovation,
            )?;
        } else if !structured::joseph_update(&mut self.covariance, &gains, &observed, &s) {
            return Err(NavError::NonFiniteState);
        }
        structured::add_gain_times(&mut self.state, &gains, &innovation);
        Ok(InnovationReport {
            innovation,
            covariance,
            normalised_innovation_squared: nis,
            accepted: true,
        })
    }

    /// The covariance part of [`ErrorStateFilter::update_structured`] with optional blocks in
    /// use: the blocks' new values first (into their spare buffers), then the core Joseph
    /// kernel (with the measured border's `M` and `S`), then the blocks' commits; nothing
    /// changes on an error. Not inlined: its stack space is taken only when a block is in use.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if a result is not finite.
    #[inline(never)]
    fn update_borders_and_covariance(
        &mut self,
        border: Option<&MeasuredBorder>,
        jacobian: (
            &crate::measurement::MeasurementJacobian,
            &[bool; STATE_DIMENSION / 3],
        ),
        gains: &structured::StateRows,
        observed: &structured::ObservedCovariance,
        (cholesky, s, frozen): (&structured::Cholesky3, &Matrix3<f64>, &BlockMask),
        innovation: &Vector3<f64>,
    ) -> Result<(), NavError> {
        let inputs = UpdateInputs {
            jacobian,
            gains,
            products: observed.products(),
            frozen,
            cholesky,
            innovation: block::from_vector(innovation),
        };
        if !self.blocks.prepare_update(border, &inputs) {
            return Err(NavError::NonFiniteState);
        }
        if !structured::joseph_update(&mut self.covariance, gains, observed, s) {
            return Err(NavError::NonFiniteState);
        }
        self.blocks.commit_update();
        Ok(())
    }

    /// Closed-loop reset: returns the error state to feed back (see [`apply_error_state`]),
    /// zeroes `x` and applies the reset Jacobian to `P` (module docs), by blocks and in
    /// place: only the attitude and installation block rows and columns change
    /// ([`crate::structured`]).
    pub fn reset(&mut self) -> ErrorState {
        let error = self.state;
        self.reset_in_place();
        error
    }

    /// [`ErrorStateFilter::reset`] for a caller that has read the error state already
    /// ([`ErrorStateFilter::state`]): nothing is returned, so the state is not copied.
    pub fn reset_in_place(&mut self) {
        let [attitude, installation] =
            [ATTITUDE, STAR_INSTALLATION].map(|block| reset_jacobian_block(&self.state, block));
        structured::reset_covariance(&mut self.covariance, &attitude, &installation);
        if self.blocks.any_enabled() {
            self.blocks.transform_cross_rows(
                &block::from_matrix(&attitude),
                &block::from_matrix(&installation),
                true,
            );
        }
        self.state = ErrorState::zeros();
    }

    /// Moves the star-installation block from the head the filter fused until now (old) to
    /// another head (new): with `T = rotation_new_from_old` (`C_new,old`, from
    /// [`crate::star_heads::RelativeAlignment::hand_over`]) and
    /// `Q = added_covariance_half_angle` (the relative alignment's uncertainty as a
    /// half-angle covariance, rad²), `x_ψ ← T x_ψ`, `P_ψψ ← T P_ψψ Tᵀ + Q`, and
    /// `P_jψ ← P_jψ Tᵀ` for every other state `j`, every optional block's states
    /// included; nothing else changes. The derivation of
    /// `ψ_new = T ψ_old + δ/2` is in [`crate::star_heads`]. Done in place by blocks, as the
    /// reset ([`ErrorStateFilter::reset`]) is: the same map with `J_ϑϑ = I`, `J_ψψ = T`.
    /// `P` stays exactly symmetric.
    ///
    /// With a finite `P` and a rotation `T` every new value is a sum of three products with
    /// factors of magnitude at most 1 plus a finite `Q`, so after the input checks the map
    /// cannot fail.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite `T` or `Q` or a negative diagonal of
    /// `Q`, [`NavError::InvalidConfiguration`] for a `T` that is not a proper rotation
    /// (`|TᵀT − I| > 1e-9` in an element, or `det T < 0`); the filter is unchanged then.
    ///
    /// # Examples
    /// ```
    /// use nalgebra::{Matrix3, Vector3};
    /// use nav_core::attitude::{exp_rotation_vector, rotation_matrix};
    /// use nav_core::filter::{ErrorStateFilter, FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::state::STAR_INSTALLATION;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let mut filter = ErrorStateFilter::new(&config)?;
    /// // Heads 90° apart about sensor x; 10 µrad² of relative-alignment variance per axis.
    /// let alignment_old_from_new = exp_rotation_vector(&Vector3::new(1.5707963267948966, 0.0, 0.0));
    /// let rotation_new_from_old = rotation_matrix(&alignment_old_from_new).transpose();
    /// let added = Matrix3::identity() * (1e-10 / 4.0);
    /// filter.hand_over_installation(&rotation_new_from_old, &added)?;
    /// let i = STAR_INSTALLATION.index();
    /// assert!((filter.covariance()[(i, i)] - (0.25e-4 + 0.25e-10)).abs() < 1e-18);
    /// assert!(filter.hand_over_installation(&(rotation_new_from_old * 1.1), &added).is_err());
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn hand_over_installation(
        &mut self,
        rotation_new_from_old: &Matrix3<f64>,
        added_covariance_half_angle: &Matrix3<f64>,
    ) -> Result<(), NavError> {
        check_rotation(rotation_new_from_old)?;
        check_block_covariance(added_covariance_half_angle)?;
        let rotation = block::from_matrix(rotation_new_from_old);
        structured::reset_covariance(
            &mut self.covariance,
            &Matrix3::identity(),
            rotation_new_from_old,
        );
        if self.blocks.any_enabled() {
            self.blocks
                .transform_cross_rows(&block::IDENTITY, &rotation, false);
        }
        let installation = rotation_new_from_old * block_of(&self.state, STAR_INSTALLATION);
        let first = STAR_INSTALLATION.index();
        let states = first..first.saturating_add(STAR_INSTALLATION.dimension());
        if let Some(values) = self.state.as_mut_slice().get_mut(states) {
            for (value, new) in values.iter_mut().zip(installation.iter()) {
                *value = *new;
            }
        }
        self.add_symmetric_part(STAR_INSTALLATION, added_covariance_half_angle);
        Ok(())
    }

    /// In open loop, the current estimate of the error of one block (for reporting).
    pub fn block(&self, block: StateBlock) -> Vector3<f64> {
        block_of(&self.state, block)
    }

    /// Indices of the blocks, for reports (re-export of the state layout).
    pub fn blocks() -> &'static [StateBlock; 8] {
        &StateBlock::ALL
    }
}

/// [`NavError::NonFiniteInput`] for a non-finite entry or a negative diagonal entry of a
/// 3×3 covariance added to a block.
fn check_block_covariance(covariance: &Matrix3<f64>) -> Result<(), NavError> {
    let finite = covariance.iter().all(|value| value.is_finite());
    let diagonal_positive = covariance.diagonal().iter().all(|value| *value >= 0.0);
    if finite && diagonal_positive {
        Ok(())
    } else {
        Err(NavError::NonFiniteInput)
    }
}

/// Largest distance of an element of `TᵀT` from the identity's for a matrix taken as a
/// rotation (the round-off of a rotation built from a unit quaternion is ~1e-16).
const ROTATION_TOLERANCE: f64 = 1.0e-9;

/// [`NavError::NonFiniteInput`] for a non-finite `rotation`,
/// [`NavError::InvalidConfiguration`] if it is not a proper rotation (orthonormal within
/// [`ROTATION_TOLERANCE`], determinant positive).
fn check_rotation(rotation: &Matrix3<f64>) -> Result<(), NavError> {
    if !rotation.iter().all(|value| value.is_finite()) {
        return Err(NavError::NonFiniteInput);
    }
    let departure = (rotation.transpose() * rotation - Matrix3::identity()).amax();
    if departure <= ROTATION_TOLERANCE && rotation.determinant() > 0.0 {
        Ok(())
    } else {
        Err(NavError::InvalidConfiguration)
    }
}

/// [`NavError::NonFiniteInput`] for NaN/Inf in a measurement's residual, `H` or `R`.
fn check_measurement(measurement: &LinearMeasurement) -> Result<(), NavError> {
    // One multiply-add per value ([`block::all_finite`]): a fraction of the cost of
    // `is_finite` per value on the target.
    let finite = block::all_finite(measurement.residual.as_slice())
        && block::all_finite(measurement.jacobian.as_slice())
        && block::all_finite(measurement.noise_covariance.as_slice());
    if finite {
        Ok(())
    } else {
        Err(NavError::NonFiniteInput)
    }
}

/// The checks every update makes before touching the filter (the structured and the dense
/// update share them): [`NavError::NonFiniteInput`] for a NaN gate (it would silently accept
/// everything: `nis > NaN` is false) or NaN/Inf in the measurement.
fn check_update_inputs(measurement: &LinearMeasurement, gate_nis: f64) -> Result<(), NavError> {
    if gate_nis.is_nan() {
        return Err(NavError::NonFiniteInput);
    }
    check_measurement(measurement)
}

fn symmetrised(matrix: &CovarianceMatrix) -> CovarianceMatrix {
    (matrix + matrix.transpose()) * 0.5
}

/// The report for innovation `ν` and `S` (symmetrised here): NIS `νᵀ S⁻¹ ν` by Cholesky.
fn innovation_report(
    innovation: Vector3<f64>,
    covariance: &Matrix3<f64>,
) -> Result<InnovationReport, NavError> {
    let covariance = symmetrised3(covariance);
    let cholesky = Cholesky::new(covariance).ok_or(NavError::NonPositiveInnovationCovariance)?;
    let whitened = cholesky.solve(&innovation);
    let nis = innovation.dot(&whitened);
    if !(nis.is_finite() && nis >= 0.0) {
        return Err(NavError::NonPositiveInnovationCovariance);
    }
    Ok(InnovationReport {
        innovation,
        covariance,
        normalised_innovation_squared: nis,
        accepted: false,
    })
}

/// The reset Jacobian's diagonal block `I − [x̂×]` of an attitude-like `block` (module docs).
fn reset_jacobian_block(error: &ErrorState, block: StateBlock) -> Matrix3<f64> {
    Matrix3::identity() - skew(&block_of(error, block))
}

fn symmetrised3(matrix: &Matrix3<f64>) -> Matrix3<f64> {
    (matrix + matrix.transpose()) * 0.5
}

mod blocks;
mod config;
pub(crate) mod covariance;
#[cfg(any(test, feature = "dense-reference"))]
mod dense;
mod optional;
#[cfg(test)]
mod optional_tests;
#[cfg(test)]
mod restart_tests;
#[cfg(test)]
mod tests;
