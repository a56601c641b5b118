//! Calibration glue: closed-loop feedback of the error state, the calibration blocks' estimates
//! and the calibration manager's evaluation.

use super::*;

impl NavigationComputer {
    /// Closed-loop feedback of the error state into the navigation solution, the history and
    /// the sensor corrections, then the filter reset (module docs).
    pub(super) fn feed_back(&mut self) {
        // nav-core's `apply_error_state` changes nothing on error, so the correction is
        // applied to the navigation solution and calibration in place (no copies of them to
        // roll back), and the large filter is reset in place only once it succeeded.
        // The systematic IMU errors' sum first: nothing is changed if it fails.
        let imu_error = self.covariance.filter.imu_error();
        let imu_errors = if imu_error.is_enabled() {
            match imu_error.fed_back(&self.calibration.imu_errors) {
                Ok(sum) => Some(sum),
                Err(_) => {
                    self.recover_filter();
                    return;
                }
            }
        } else {
            None
        };
        let error = self.covariance.filter.state();
        let applied = apply_error_state(
            error,
            &mut self.navigation.solution.attitude,
            &mut self.navigation.solution.position_m,
            &mut self.navigation.solution.velocity_mps,
            &mut self.calibration.estimate,
        );
        if applied.is_err() {
            // A correction nav-core cannot apply (|ϑ| ≥ 1 or non-finite): keep everything
            // as it was and re-initialise the filter (documented recovery).
            self.recover_filter();
            return;
        }
        if let Some(sum) = imu_errors {
            self.calibration.imu_errors = sum;
        }
        let attitude_correction = attitude::from_vector_part(&block_of(error, ATTITUDE));
        let position_correction = block_of(error, POSITION);
        let velocity_correction = block_of(error, VELOCITY);
        if let Ok(correction) = attitude_correction {
            // Snapshots are corrected when read ([`History::corrected`]).
            self.navigation.history.record_correction(Correction {
                frame: self.frame,
                attitude: correction,
                position_m: position_correction,
                velocity_mps: velocity_correction,
            });
        }
        self.arithmetic.reset_in_place(&mut self.covariance.filter);
    }

    /// Current estimate and variance of one calibration block in table units (the
    /// installation error as a rotation vector: twice the quaternion vector part, so four
    /// times its variance).
    pub(super) fn block_estimate(
        block: StateBlock,
        estimate: &CalibrationEstimate,
        variances: &ErrorState,
    ) -> ([f64; 3], [f64; 3]) {
        let variance = block_of(variances, block);
        let c = estimate;
        match block {
            StateBlock::StarInstallation => {
                let [w, x, y, z] = c.star_installation_wxyz;
                let vector = attitude::log_rotation_vector(&Quaternion::new(w, x, y, z));
                (
                    array3(&vector),
                    array3(&(variance * ANGLE_VARIANCE_PER_HALF_ANGLE_VARIANCE)),
                )
            }
            StateBlock::GyroBias => (c.gyro_bias_rad_s, array3(&variance)),
            StateBlock::AccelBias => (c.accel_bias_mps2, array3(&variance)),
            StateBlock::GyroScaleFactor => (c.gyro_scale_factor, array3(&variance)),
            StateBlock::AccelScaleFactor => (c.accel_scale_factor, array3(&variance)),
            // Navigation blocks have no calibration estimate (the table holds none).
            StateBlock::Attitude | StateBlock::Position | StateBlock::Velocity => {
                ([0.0; 3], array3(&variance))
            }
        }
    }

    pub(super) fn evaluate_calibration(&mut self) {
        let mut values = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
        let mut variances = [[0.0; 3]; CALIBRATION_BLOCK_COUNT];
        // Once per frame (not per block): the estimate and the variance of every state.
        let estimate = self.calibration_estimate();
        let state_variances = self.covariance.filter.covariance().diagonal();
        for ((value, variance), block) in values
            .iter_mut()
            .zip(variances.iter_mut())
            .zip(StateBlock::CALIBRATION.iter())
        {
            (*value, *variance) = Self::block_estimate(*block, &estimate, &state_variances);
        }
        self.calibration
            .manager
            .evaluate(self.navigation.solution.time_s, &values, &variances);
    }

    /// The systematic IMU errors' estimate (`filter.imu_error` in use; zero otherwise), in
    /// the filter's gauge (nav-core `imu_error`): in closed loop the fed-back corrections,
    /// in open loop the filter's estimate `ε̂`.
    ///
    /// # Errors
    /// [`NavError::NonFiniteState`] if the open-loop sum is not finite.
    pub fn imu_error_estimate(&self) -> Result<ImuErrorEstimate, NavError> {
        let filter = &self.covariance.filter;
        if filter.mode() == FilterMode::OpenLoop && filter.imu_error().is_enabled() {
            filter.imu_error().fed_back(&self.calibration.imu_errors)
        } else {
            Ok(self.calibration.imu_errors)
        }
    }

    /// The sensor-error estimate: in closed loop the fed-back corrections; in open loop the
    /// filter's current error state applied to them.
    pub fn calibration_estimate(&self) -> CalibrationEstimate {
        let mut calibration = self.calibration.estimate;
        if self.covariance.filter.mode() == FilterMode::OpenLoop {
            let mut scratch = self.navigation.solution;
            // Errors only for a non-finite or degenerate x; the fed-back value stands then.
            let _ = apply_error_state(
                self.covariance.filter.state(),
                &mut scratch.attitude,
                &mut scratch.position_m,
                &mut scratch.velocity_mps,
                &mut calibration,
            );
        }
        calibration
    }
}
