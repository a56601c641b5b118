//! The filter's configuration ([`FilterConfig`]: its mode, discretisation order, initial
//! uncertainty per core block, and the optional blocks' models, whose fields the blocks'
//! registration declares) and its validation.

use nalgebra::Matrix3;

use super::{ErrorState, ErrorStateFilter, FilterConfig};
use crate::error_model::set_block;
use crate::state::{
    StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR, POSITION,
    STAR_INSTALLATION, VELOCITY,
};
use crate::NavError;

/// Initial 1σ per block (same value on each of the block's three axes).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InitialUncertainty {
    /// Attitude error, as a rotation angle (rad); the state's 1σ is half of it.
    pub attitude_rad: f64,
    /// Position (m).
    pub position_m: f64,
    /// Velocity (m/s).
    pub velocity_mps: f64,
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: f64,
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: f64,
    /// Star-sensor installation error, as a rotation angle (rad); the state's 1σ is half.
    pub star_installation_rad: f64,
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: f64,
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: f64,
}

impl FilterConfig {
    /// Checks every value is finite and in range.
    ///
    /// # Errors
    /// [`NavError::InvalidDiscretisationOrder`], or [`NavError::InvalidConfiguration`] for a
    /// non-finite or non-positive initial 1σ or an optional block's model it refuses.
    pub fn validate(&self) -> Result<(), NavError> {
        if !(1..=crate::discretise::MAX_ORDER).contains(&self.discretisation_order) {
            return Err(NavError::InvalidDiscretisationOrder);
        }
        self.check_optional_models()?;
        let sigmas = self.initial_sigmas();
        if sigmas
            .iter()
            .all(|(_, sigma)| sigma.is_finite() && *sigma > 0.0)
        {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// The diagonal of the initial `P` (every state's configured 1σ squared, the values
    /// [`ErrorStateFilter::new`] puts there), without building a filter.
    ///
    /// # Errors
    /// As [`FilterConfig::validate`].
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty};
    /// use nav_core::state::{ATTITUDE, POSITION};
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let variances = config.initial_variances()?;
    /// assert_eq!(variances[POSITION.index()], 100.0);
    /// // The attitude states are half-angles: (½ · 1 mrad)².
    /// assert!((variances[ATTITUDE.index()] - 0.25e-6).abs() < 1e-21);
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn initial_variances(&self) -> Result<ErrorState, NavError> {
        self.validate()?;
        let mut variances = ErrorState::zeros();
        for (block, sigma) in self.initial_sigmas() {
            let first = block.index();
            let states = first..first.saturating_add(block.dimension());
            for variance in variances
                .as_mut_slice()
                .get_mut(states)
                .into_iter()
                .flatten()
            {
                *variance = sigma * sigma;
            }
        }
        Ok(variances)
    }

    /// 1σ of each block's state (the attitude and installation states are half-angles).
    fn initial_sigmas(&self) -> [(StateBlock, f64); 8] {
        let i = &self.initial;
        [
            (ATTITUDE, 0.5 * i.attitude_rad),
            (POSITION, i.position_m),
            (VELOCITY, i.velocity_mps),
            (GYRO_BIAS, i.gyro_bias_rad_s),
            (ACCEL_BIAS, i.accel_bias_mps2),
            (STAR_INSTALLATION, 0.5 * i.star_installation_rad),
            (GYRO_SCALE_FACTOR, i.gyro_scale_factor),
            (ACCEL_SCALE_FACTOR, i.accel_scale_factor),
        ]
    }
}

impl ErrorStateFilter {
    /// `P = diag(σ²)` of a validated configuration, on a zero `P`.
    pub(super) fn set_initial_covariance(&mut self, config: &FilterConfig) {
        self.set_initial_blocks(config, |_| true);
    }

    /// The prior's diagonal blocks of the navigation states ([`StateBlock::NAVIGATION`]).
    pub(super) fn set_initial_navigation_covariance(&mut self, config: &FilterConfig) {
        self.set_initial_blocks(config, |block| !block.is_calibration());
    }

    /// The prior's diagonal blocks of the blocks `chosen` picks.
    fn set_initial_blocks(&mut self, config: &FilterConfig, chosen: impl Fn(StateBlock) -> bool) {
        for (block, sigma) in config.initial_sigmas() {
            if !chosen(block) {
                continue;
            }
            set_block(
                &mut self.covariance,
                block,
                block,
                &(Matrix3::identity() * (sigma * sigma)),
            );
        }
    }
}
