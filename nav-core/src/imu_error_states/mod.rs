//! The systematic IMU error states ([`crate::imu_error`]: gyro non-orthogonality 3,
//! accelerometer misalignment 6, gyro g-sensitivity 3) as the border of a 36-state filter:
//! the 24-state kernels stay as they are, and only the border `ε̂`, `P_εε` (12×12) and
//! `C = P_xε` (24×12) is added (a bias border of `crate::block_interface`).
//!
//! ## Model
//! The twelve states are random constants (`ε̇ = 0`). Each acts on the navigation exactly as
//! an equivalent sensor bias ([`crate::imu_error::equivalent_bias_terms`]): with `u = M ε`
//! (`M`, 6×12, one non-zero per column: the measured rate or force component `m_k` on the
//! gyro or accelerometer axis the state disturbs), the continuous columns of `ε` are the
//! bias columns times `M`, `B_ε = B_b M`. The calibration rows of the 24-state system
//! matrix are zero, so the discrete transition of the same order is
//! `F₃₆ = [[F, Γ], [0, I]]` with `Γ = Σ_{n≥1} A^{n−1} B_b M Δⁿ/n! = E M`, `E = [E_g E_a]`
//! the bias columns of `F` ([`crate::structured`]: rows ϑ, δp, δv; zero elsewhere): no new
//! series. The noise enters `x` only, and `A₃₆ⁿ G = [Aⁿ G; 0]`, so `Qd₃₆ = diag(Qd, 0)`.
//!
//! ## Propagation
//! With `Y = F C` (its dynamic rows by `StructuredModel::propagate_rows`, the calibration
//! rows those of `C`):
//! * `C ← C⁺ = Y + Γ P_εε` (only the dynamic rows change: `Γ` has no others);
//! * `P_xx ← F P_xx Fᵀ + Γ Cᵀ Fᵀ + F C Γᵀ + Γ P_εε Γᵀ + Qd = U [Φ E]ᵀ + C⁺_d Γ_dᵀ + Qd` with
//!   `U = F P_xx + Γ Cᵀ`: since `Γ = E M`, the 24-state kernel computes it with
//!   `M C_jᵀ` added to column `j`'s folded bias inputs and `M C⁺_rᵀ` to row `r` of `U`'s
//!   folded bias columns (`structured::BorderBiasInputs`, derivation in
//!   [`crate::structured`]);
//! * `P_εε` unchanged; in open loop `x_d ← (F x)_d + E (M ε̂)`.
//!
//! ## Update
//! No measurement sees `ε` directly (`H_ε = 0`), so `S`, `M_x = P_xx H_xᵀ` and the 24-state
//! Joseph kernel are unchanged; the border adds `G = H_x C`, `M_ε = Gᵀ`, `K_ε = M_ε S⁻¹` and,
//! by the expanded Joseph form of the bordered update (`crate::structured`), `C⁺_ia = C_ia − K_i·M_εa` for a
//! row the update moves and `C_ia − M_i·K_εa` for a frozen one (`K_i = 0`),
//! `P⁺_εε = P_εε − K_ε M_εᵀ`, `ε̂ ← ε̂ + K_ε ν`.
//!
//! ## Reset
//! In closed loop the caller feeds `ε̂` into its sensor corrections with the 24 states
//! (`crate::imu_error::correct_increment`), the estimate is zeroed (the corrections are
//! additive: the reset Jacobian of `ε` is the identity) and `C ← J C` on the attitude and
//! installation rows.
//!
//! ## With the correlated GNSS error states (the measured border)
//! With both borders the covariance also holds `B = cov(ε_GNSS, ε)` (3×12). `x` gains `Γ ε`
//! and `ε_GNSS` decays by `φ`, so the GNSS border's cross-covariance propagates as
//! `C_GNSS ← φ (F C_GNSS + Γ Bᵀ)` (its dynamic rows gain `E M Bᵀ`,
//! `ImuErrorStates::gnss_coupling`) and `B ← φ B`. A GNSS position fix has `H_GNSS = h I`,
//! so `M_ε` gains `h Bᵀ`, and `B ← B − K_GNSS M_εᵀ` at every update (`K_GNSS` the GNSS
//! border's gains, any measurement); the rest is as above.

#[cfg(feature = "imu-error-states")]
use nalgebra::Vector3;
use nalgebra::{SMatrix, SVector};

#[cfg(feature = "imu-error-states")]
use crate::block::{self, Block, Row};
use crate::imu_error::{ImuErrorEstimate, IMU_ERROR_DIMENSION};
use crate::state::{OptionalBlock, STATE_DIMENSION};
#[cfg(feature = "imu-error-states")]
use crate::state::{ATTITUDE, STAR_INSTALLATION};
#[cfg(feature = "imu-error-states")]
use crate::structured::{BorderBiasInputs, StateRows};
use crate::NavError;

#[cfg(feature = "imu-error-states")]
mod interface;
mod prior;
#[cfg(feature = "imu-error-states")]
mod propagate;
#[cfg(feature = "imu-error-states")]
mod protect;
mod restart;
#[cfg(feature = "imu-error-states")]
mod update;

pub use prior::PriorCovariance;
pub use restart::{ImuErrorCovariance, IMU_ERROR_LOWER_TRIANGLE};

/// Number of 3-column groups of the border (`C` is kept as four 24×3 matrices, the shape
/// the structured propagation takes).
#[cfg(feature = "imu-error-states")]
const GROUPS: usize = IMU_ERROR_DIMENSION / 3;
#[cfg(feature = "imu-error-states")]
const _: () = assert!(GROUPS * 3 == IMU_ERROR_DIMENSION);

/// Number of dynamic states (ϑ, δp, δv).
#[cfg(feature = "imu-error-states")]
const DYNAMIC: usize = 9;

/// `C = P_xε` as four groups of three columns (`groups[g][j][c] = cov(x_j, ε_{3g+c})`).
#[cfg(feature = "imu-error-states")]
type CrossCovariance = [StateRows; GROUPS];
/// A 12×12 matrix by rows.
type BorderMatrix = [[f64; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION];

/// The triads' specification (configuration): the 1σ of every off-diagonal term of each
/// triad's error matrix in body axes, as a datasheet gives it, and of the gyro
/// g-sensitivity; all zero: the paper's 24 states only. The filter's prior in its own gauge,
/// with the correlations the gauge brings, follows from it ([`Self::prior_covariance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuErrorModel {
    /// Gyro triad misalignment and non-orthogonality, per off-diagonal term (rad).
    pub gyro_misalignment_sigma_rad: f64,
    /// Accelerometer triad misalignment and non-orthogonality, per off-diagonal term (rad).
    pub accel_misalignment_sigma_rad: f64,
    /// Gyro g-sensitivity, per axis (rad/s per m/s²).
    pub gyro_g_sensitivity_sigma_rad_s_per_mps2: f64,
}

impl ImuErrorModel {
    /// No systematic IMU error states (the paper's model).
    pub const DISABLED: Self = Self {
        gyro_misalignment_sigma_rad: 0.0,
        accel_misalignment_sigma_rad: 0.0,
        gyro_g_sensitivity_sigma_rad_s_per_mps2: 0.0,
    };

    fn sigmas(&self) -> [f64; 3] {
        [
            self.gyro_misalignment_sigma_rad,
            self.accel_misalignment_sigma_rad,
            self.gyro_g_sensitivity_sigma_rad_s_per_mps2,
        ]
    }

    /// Whether the states are in use (any 1σ above zero).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// assert!(!ImuErrorModel::DISABLED.is_enabled());
    /// let imu = ImuErrorModel { gyro_misalignment_sigma_rad: 2e-5,
    ///     accel_misalignment_sigma_rad: 2e-5, gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7 };
    /// assert!(imu.is_enabled());
    /// assert_eq!(imu.validate(), Ok(()));
    /// ```
    pub fn is_enabled(&self) -> bool {
        self.sigmas().iter().any(|sigma| *sigma > 0.0)
    }

    /// Checks the values: all zero, or all finite and above zero (a state with a zero prior
    /// would never move and only cost time) with the states compiled in (feature
    /// `imu-error-states`).
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] otherwise.
    pub fn validate(&self) -> Result<(), NavError> {
        if self.is_enabled() && !OptionalBlock::GyroNonOrthogonality.is_compiled() {
            return Err(NavError::InvalidConfiguration);
        }
        let sigmas = self.sigmas();
        let all_zero = sigmas.iter().all(|sigma| *sigma == 0.0);
        let all_positive = sigmas.iter().all(|sigma| sigma.is_finite() && *sigma > 0.0);
        if all_zero || all_positive {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// The prior variance of each of the twelve states in the filter's gauge, in
    /// [`crate::imu_error::ImuErrorBlock`] order: [`Self::prior_covariance`]'s diagonal.
    pub fn prior_variances(&self) -> [f64; IMU_ERROR_DIMENSION] {
        let mut prior = [[0.0; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION];
        self.write_prior(&mut prior);
        core::array::from_fn(|k| {
            prior
                .get(k)
                .and_then(|row| row.get(k))
                .copied()
                .unwrap_or(0.0)
        })
    }

    /// The prior 1σ of each of the twelve states in the filter's gauge, in
    /// [`crate::imu_error::ImuErrorBlock`] order: the square roots of
    /// [`Self::prior_covariance`]'s diagonal.
    pub fn state_sigmas(&self) -> [f64; IMU_ERROR_DIMENSION] {
        self.prior_variances().map(crate::float::sqrt)
    }
}

#[cfg(feature = "imu-error-states")]
/// `ε̂` ([`crate::imu_error::ImuErrorBlock`] order) and `P_εε`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Estimate {
    estimate: [f64; IMU_ERROR_DIMENSION],
    covariance: BorderMatrix,
    /// `B = cov(ε_GNSS, ε)` (3×12), with the correlated GNSS error states in use (zero
    /// otherwise; module docs, "With the correlated GNSS error states").
    gnss_cross: [[f64; IMU_ERROR_DIMENSION]; 3],
}

#[cfg(feature = "imu-error-states")]
/// The border of the 36-state filter (module docs): `ε̂`, `P_εε` and `C = P_xε`.
#[derive(Debug, Clone, Copy)]
pub struct ImuErrorStates {
    model: ImuErrorModel,
    /// `ε̂` and `P_εε`, twice: an update writes the new ones into the inactive half and its
    /// commit makes it active (with the new `C`).
    halves: [Estimate; 2],
    /// Whether `halves[1]` holds `ε̂` and `P_εε`.
    second_half: bool,
    /// Two buffers of `C`: an update writes the new `C` into the inactive one and a commit
    /// makes it active, so nothing changes if the update fails.
    buffers: [CrossCovariance; 2],
    /// Whether `buffers[1]` holds `C`.
    second_active: bool,
    /// What a propagation or an update keeps between its steps (kept here, so nothing large
    /// is returned or copied on the flight path; not part of the filter's state).
    scratch: Scratch,
    /// Whether each group of three states is frozen (its gain rows zero in every update, as a
    /// frozen core block's); a layout block freezes all of its groups.
    frozen: [bool; GROUPS],
    /// Whether `P_εε` may have changed since the variance protection last read it: only an
    /// update (or a new prior) changes it, its propagation keeps it (`ε̇ = 0`).
    variances_changed: bool,
    /// Whether the model is enabled ([`ImuErrorModel::is_enabled`], kept: the filter asks at
    /// every step).
    enabled: bool,
}

#[cfg(feature = "imu-error-states")]
impl PartialEq for ImuErrorStates {
    /// Equal model, `ε̂`, `P_εε` and `C` (whichever buffer holds it).
    fn eq(&self, other: &Self) -> bool {
        self.model == other.model
            && self.half() == other.half()
            && self.cross() == other.cross()
            && self.frozen == other.frozen
    }
}

#[cfg(feature = "imu-error-states")]
/// The border split for a kernel: `ε̂` and `P_εε` to read, the active `C` to read, the spare
/// buffer to write and the scratch.
struct Parts<'a> {
    estimate: &'a [f64; IMU_ERROR_DIMENSION],
    covariance: &'a BorderMatrix,
    gnss_cross: &'a [[f64; IMU_ERROR_DIMENSION]; 3],
    /// The inactive `ε̂` and `P_εε`, for an update to write.
    spare_half: &'a mut Estimate,
    old: &'a CrossCovariance,
    spare: &'a mut CrossCovariance,
    scratch: &'a mut Scratch,
}

#[cfg(feature = "imu-error-states")]
/// What a propagation or an update keeps between its steps.
#[derive(Debug, Clone, Copy)]
struct Scratch {
    /// The bias inputs the 24-state kernel folds in (module docs, "Propagation").
    kernel_inputs: BorderBiasInputs,
    /// `E M ε̂` on the dynamic rows (the open-loop state's increment).
    state_increment: [f64; DYNAMIC],
    /// An update's `M_ε` and `K_ε` by groups (row `c` of group `g`: state `3g + c`).
    border_products: [[Row; 3]; GROUPS],
    border_gains: [[Row; 3]; GROUPS],
}

#[cfg(feature = "imu-error-states")]
impl Scratch {
    const EMPTY: Self = Self {
        kernel_inputs: BorderBiasInputs::ZERO,
        state_increment: [0.0; DYNAMIC],
        border_products: [[[0.0; 3]; 3]; GROUPS],
        border_gains: [[[0.0; 3]; 3]; GROUPS],
    };
}

#[cfg(feature = "imu-error-states")]
impl ImuErrorStates {
    /// The prior: `ε̂ = 0`, `P_εε` = [`ImuErrorModel::prior_covariance`], `C = 0` (all zero
    /// when disabled).
    ///
    /// # Errors
    /// As [`ImuErrorModel::validate`].
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error_states::{ImuErrorModel, ImuErrorStates};
    /// let model = ImuErrorModel { gyro_misalignment_sigma_rad: 2e-5,
    ///     accel_misalignment_sigma_rad: 3e-5, gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7 };
    /// let states = ImuErrorStates::new(model)?;
    /// // m_xy = a^a_xy − a^g_xy: σ_a² + σ_g²
    /// assert!((states.covariance()[(3, 3)] - 1.3e-9).abs() < 1e-24);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn new(model: ImuErrorModel) -> Result<Self, NavError> {
        model.validate()?;
        let mut states = Self::EMPTY;
        states.start(model);
        Ok(states)
    }

    /// Everything zero, the model disabled: what the filter writes into its slot before
    /// [`Self::start`], so the large border is never built on the stack and moved
    /// (start-up's stack budget, `tests-host` `replay_bit_exact`).
    pub(crate) const EMPTY: Self = Self {
        model: ImuErrorModel::DISABLED,
        halves: [Estimate {
            estimate: [0.0; IMU_ERROR_DIMENSION],
            covariance: [[0.0; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION],
            gnss_cross: [[0.0; IMU_ERROR_DIMENSION]; 3],
        }; 2],
        second_half: false,
        buffers: [[[[0.0; 3]; STATE_DIMENSION]; GROUPS]; 2],
        second_active: false,
        scratch: Scratch::EMPTY,
        frozen: [false; GROUPS],
        variances_changed: false,
        enabled: false,
    };

    /// On an [`Self::EMPTY`] border, in place: the model and its prior
    /// ([`ImuErrorModel::prior_covariance`]) in both halves' `P_εε`. The caller has
    /// validated `model`.
    pub(crate) fn start(&mut self, model: ImuErrorModel) {
        self.model = model;
        self.enabled = model.is_enabled();
        self.variances_changed = true;
        for half in &mut self.halves {
            model.write_prior(&mut half.covariance);
        }
    }

    /// The model.
    pub fn model(&self) -> &ImuErrorModel {
        &self.model
    }

    /// Whether the states are in use.
    #[inline]
    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// `ε̂` ([`crate::imu_error::ImuErrorBlock`] order).
    pub fn estimate(&self) -> SVector<f64, IMU_ERROR_DIMENSION> {
        SVector::from(self.half().estimate)
    }

    /// `P_εε`.
    pub fn covariance(&self) -> SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION> {
        SMatrix::from_fn(|a, b| {
            self.half()
                .covariance
                .get(a)
                .and_then(|row| row.get(b))
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    /// `B = cov(ε_GNSS, ε)` (3×12; zero without the correlated GNSS error states).
    pub fn gnss_cross_covariance(&self) -> SMatrix<f64, 3, IMU_ERROR_DIMENSION> {
        SMatrix::from_fn(|m, a| {
            self.half()
                .gnss_cross
                .get(m)
                .and_then(|row| row.get(a))
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    /// `C = P_xε` (24×12).
    pub fn cross_covariance(&self) -> SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION> {
        SMatrix::from_fn(|j, a| self.cross_at(j, a))
    }

    fn cross_at(&self, j: usize, a: usize) -> f64 {
        self.cross()
            .get(a / 3)
            .and_then(|group| group.get(j))
            .and_then(|row| row.get(a % 3))
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// `C`, by groups.
    pub(super) fn cross(&self) -> &CrossCovariance {
        let [first, second] = &self.buffers;
        if self.second_active {
            second
        } else {
            first
        }
    }

    /// The active `ε̂` and `P_εε`.
    fn half(&self) -> &Estimate {
        let [first, second] = &self.halves;
        if self.second_half {
            second
        } else {
            first
        }
    }

    fn half_mut(&mut self) -> &mut Estimate {
        let [first, second] = &mut self.halves;
        if self.second_half {
            second
        } else {
            first
        }
    }

    /// The border split for a kernel ([`Parts`]).
    fn parts(&mut self) -> Parts<'_> {
        let [first, second] = &mut self.buffers;
        let (old, spare) = if self.second_active {
            (&*second, first)
        } else {
            (&*first, second)
        };
        let [first_half, second_half] = &mut self.halves;
        let (half, spare_half) = if self.second_half {
            (&*second_half, first_half)
        } else {
            (&*first_half, second_half)
        };
        Parts {
            estimate: &half.estimate,
            covariance: &half.covariance,
            gnss_cross: &half.gnss_cross,
            spare_half,
            old,
            spare,
            scratch: &mut self.scratch,
        }
    }

    fn cross_mut(&mut self) -> &mut CrossCovariance {
        let [first, second] = &mut self.buffers;
        if self.second_active {
            second
        } else {
            first
        }
    }

    /// The closed-loop reset: `C ← J C` on the attitude and installation rows, `ε̂ = 0` (the
    /// caller has fed it into its corrections).
    pub(crate) fn reset(&mut self, attitude: &Block, installation: &Block) {
        self.transform_cross_rows(attitude, installation);
        self.half_mut().estimate = [0.0; IMU_ERROR_DIMENSION];
    }

    /// `C ← J C` for `J` the identity except `J_ϑϑ = attitude` and `J_ψψ = installation`,
    /// `ε̂` unchanged: the reset's map, and the star-head hand-over's
    /// ([`crate::filter::ErrorStateFilter::hand_over_installation`]).
    pub(crate) fn transform_cross_rows(&mut self, attitude: &Block, installation: &Block) {
        for group in self.cross_mut().iter_mut() {
            for (offset, jacobian) in [
                (ATTITUDE.index(), attitude),
                (STAR_INSTALLATION.index(), installation),
            ] {
                if let Some(rows) = group.get_mut(offset..offset + 3) {
                    let old: Block = [0, 1, 2].map(|i| rows.get(i).copied().unwrap_or([0.0; 3]));
                    for (row, value) in rows.iter_mut().zip(block::mul(jacobian, &old)) {
                        *row = value;
                    }
                }
            }
        }
    }

    /// `corrections + ε̂`: the systematic corrections after the closed-loop feedback of the
    /// estimate (module docs, "Reset"); the caller resets the filter afterwards.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the sum is not finite (nothing is changed).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error::ImuErrorEstimate;
    /// use nav_core::imu_error_states::{ImuErrorModel, ImuErrorStates};
    /// let model = ImuErrorModel { gyro_misalignment_sigma_rad: 2e-5,
    ///     accel_misalignment_sigma_rad: 2e-5, gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7 };
    /// let states = ImuErrorStates::new(model)?;
    /// let corrections = ImuErrorEstimate::default();
    /// // A fresh filter's estimate is zero: nothing to feed back.
    /// assert_eq!(states.fed_back(&corrections)?, corrections);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn fed_back(&self, corrections: &ImuErrorEstimate) -> Result<ImuErrorEstimate, NavError> {
        let e = &self.half().estimate;
        let at = |k: usize| e.get(k).copied().unwrap_or(f64::NAN);
        let sum = ImuErrorEstimate {
            gyro_non_orthogonality_rad: corrections.gyro_non_orthogonality_rad
                + Vector3::from_fn(|k, _| at(k)),
            accel_misalignment_rad: corrections.accel_misalignment_rad
                + SVector::<f64, 6>::from_fn(|k, _| at(3 + k)),
            gyro_g_sensitivity_rad_s_per_mps2: corrections.gyro_g_sensitivity_rad_s_per_mps2
                + Vector3::from_fn(|k, _| at(9 + k)),
        };
        if sum.is_finite() {
            Ok(sum)
        } else {
            Err(NavError::NonFiniteState)
        }
    }

    /// Row `index` of `C` times `scale` (the state's uncertainty was scaled).
    pub(crate) fn scale_cross_row(&mut self, index: usize, scale: f64) {
        for group in self.cross_mut().iter_mut() {
            if let Some(row) = group.get_mut(index) {
                *row = block::row_scale(*row, scale);
            }
        }
    }

    /// Replaces `B` (tests: a random prior with both borders).
    #[cfg(test)]
    pub(crate) fn set_gnss_cross(&mut self, cross: &SMatrix<f64, 3, IMU_ERROR_DIMENSION>) {
        self.half_mut().gnss_cross =
            core::array::from_fn(|m| core::array::from_fn(|a| cross[(m, a)]));
    }

    /// Replaces `ε̂`, `P_εε` and `C`, and zeroes `B` (a random prior in tests; the
    /// calibration kept across a restart, `crate::filter::restart`).
    pub(crate) fn set(
        &mut self,
        estimate: &SVector<f64, IMU_ERROR_DIMENSION>,
        covariance: &SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>,
        cross: &SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION>,
    ) {
        self.variances_changed = true;
        let half = self.half_mut();
        half.gnss_cross = [[0.0; IMU_ERROR_DIMENSION]; 3];
        half.estimate = core::array::from_fn(|a| estimate[a]);
        half.covariance = core::array::from_fn(|a| core::array::from_fn(|b| covariance[(a, b)]));
        *self.cross_mut() = core::array::from_fn(|g| {
            core::array::from_fn(|j| core::array::from_fn(|c| cross[(j, 3 * g + c)]))
        });
    }
}

/// The states compiled out (feature `imu-error-states` off): no memory, the read accessors of
/// the real states, inert.
#[cfg(not(feature = "imu-error-states"))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuErrorStates;

#[cfg(not(feature = "imu-error-states"))]
impl ImuErrorStates {
    /// Nothing to replace (the states are never in use).
    pub(crate) fn set(
        &mut self,
        _estimate: &SVector<f64, IMU_ERROR_DIMENSION>,
        _covariance: &SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>,
        _cross: &SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION>,
    ) {
    }

    /// [`ImuErrorModel::DISABLED`] only (the model's validation refuses any other).
    ///
    /// # Errors
    /// As [`ImuErrorModel::validate`].
    pub fn new(model: ImuErrorModel) -> Result<Self, NavError> {
        model.validate().map(|()| Self)
    }

    /// The placeholder.
    pub(crate) const EMPTY: Self = Self;

    /// Nothing to start.
    pub(crate) fn start(&mut self, _model: ImuErrorModel) {}

    /// The model: [`ImuErrorModel::DISABLED`].
    pub fn model(&self) -> &ImuErrorModel {
        &ImuErrorModel::DISABLED
    }

    /// Never in use.
    pub fn is_enabled(&self) -> bool {
        false
    }

    /// Never frozen.
    pub fn is_frozen(&self, _block: OptionalBlock) -> bool {
        false
    }

    /// Zero.
    pub fn estimate(&self) -> SVector<f64, IMU_ERROR_DIMENSION> {
        SVector::zeros()
    }

    /// Zero.
    pub fn covariance(&self) -> SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION> {
        SMatrix::zeros()
    }

    /// Zero.
    pub fn gnss_cross_covariance(&self) -> SMatrix<f64, 3, IMU_ERROR_DIMENSION> {
        SMatrix::zeros()
    }

    /// Zero.
    pub fn cross_covariance(&self) -> SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION> {
        SMatrix::zeros()
    }

    /// `corrections`: no estimate to feed back.
    ///
    /// # Errors
    /// Never.
    pub fn fed_back(&self, corrections: &ImuErrorEstimate) -> Result<ImuErrorEstimate, NavError> {
        Ok(*corrections)
    }
}

impl crate::block_interface::OptionalModel for ImuErrorModel {
    const OFF: Self = Self::DISABLED;

    fn in_use(&self) -> bool {
        self.is_enabled()
    }

    fn check(&self) -> Result<(), NavError> {
        self.validate()
    }

    fn write_prior_variances(&self, variances: &mut [f64]) {
        for (slot, variance) in variances.iter_mut().zip(self.prior_variances()) {
            *slot = variance;
        }
    }
}

/// Compiled out: never in use.
#[cfg(not(feature = "imu-error-states"))]
impl crate::block_interface::OptionalStates for ImuErrorStates {
    type Model = ImuErrorModel;
    const FIRST_BLOCK: OptionalBlock = OptionalBlock::GyroNonOrthogonality;
    const DIMENSION: usize = IMU_ERROR_DIMENSION;
    const EMPTY: Self = Self;

    fn start(&mut self, _model: ImuErrorModel) {}

    fn in_use(&self) -> bool {
        false
    }
}

#[cfg(all(test, feature = "imu-error-states"))]
mod tests;
