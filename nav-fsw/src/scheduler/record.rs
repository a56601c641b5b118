//! The calibration kept across a reboot ([`crate::calibration_record`]): exported from the
//! computer, loaded as the prior of a new start.

use super::*;
use crate::calibration_record::{
    configuration_fingerprint, CalibrationRecord, RecordError, CALIBRATION_RECORD_BYTES,
};
use nav_core::imu_error_states::ImuErrorCovariance;

impl NavigationComputer {
    /// The calibration earned so far as a record (its bytes: [`CalibrationRecord::to_bytes`]):
    /// the core calibration estimate and the systematic IMU errors' as the outputs give them
    /// ([`Self::calibration_estimate`], [`Self::imu_error_estimate`]) and the calibration
    /// block of `P`.
    ///
    /// The covariance is the calibration block a restart to the navigation prior needs
    /// (nav-core `ErrorStateFilter::calibration_covariance_for_restart`): the record starts
    /// a new computer whose navigation error is no longer known to be correlated with it.
    ///
    /// # Errors
    /// As `calibration_covariance_for_restart` (the navigation less certain than its prior).
    pub fn export_calibration(&self) -> Result<CalibrationRecord, NavError> {
        let filter = &self.covariance.filter;
        Ok(CalibrationRecord {
            fingerprint: configuration_fingerprint(&self.config),
            time_s: self.navigation.solution.time_s,
            estimate: self.calibration_estimate(),
            imu_errors: self
                .imu_error_estimate()
                .unwrap_or(self.calibration.imu_errors),
            covariance: filter.calibration_covariance_for_restart(&self.config.filter)?,
            imu_error_covariance: filter
                .imu_error_covariance_for_restart(&self.config.filter)?
                .unwrap_or(ImuErrorCovariance::ZERO),
        })
    }

    /// Loads a calibration record as the prior (a ground command, or at start-up after
    /// [`Self::new`]): the sensor corrections become the record's estimates, the calibration
    /// block of `P` its covariance, and the navigation states and optional blocks restart at
    /// their configured prior, as after a filter reset that keeps the calibration. Counted in
    /// the frame telemetry (`commands.calibration_records_loaded` / `_refused`).
    ///
    /// # Errors
    /// [`RecordError`] for a record that is not one, was changed (CRC), has another version,
    /// was made under another configuration or holds values that are not finite or not a
    /// covariance, and in open loop; the computer keeps its calibration and prior then.
    pub fn load_calibration(
        &mut self,
        bytes: &[u8; CALIBRATION_RECORD_BYTES],
    ) -> Result<(), RecordError> {
        let loaded = self.load_record(bytes);
        let counter = match loaded {
            Ok(()) => &mut self.operations.commands.calibration_records_loaded,
            Err(_) => &mut self.operations.commands.calibration_records_refused,
        };
        count(counter);
        loaded
    }

    fn load_record(&mut self, bytes: &[u8; CALIBRATION_RECORD_BYTES]) -> Result<(), RecordError> {
        if self.covariance.filter.mode() == FilterMode::OpenLoop {
            return Err(RecordError::OpenLoop);
        }
        let record = CalibrationRecord::from_bytes(bytes, &self.config)?;
        let estimate = &record.estimate;
        let finite = [
            estimate.gyro_bias_rad_s.as_slice(),
            &estimate.accel_bias_mps2,
            &estimate.gyro_scale_factor,
            &estimate.accel_scale_factor,
        ]
        .into_iter()
        .flatten()
        .all(|value| value.is_finite())
            && record.imu_errors.is_finite();
        let [w, x, y, z] = estimate.star_installation_wxyz;
        let norm = Quaternion::new(w, x, y, z).norm();
        if !(finite && norm.is_finite() && attitude::is_unit_norm(norm)) {
            return Err(RecordError::Values);
        }
        // The covariance first: refused, it changes nothing; accepted, the restart below
        // keeps it (the configuration was validated at start-up, so the restart succeeds).
        let filter = &mut self.covariance.filter;
        let set = if filter.imu_error().is_enabled() {
            filter.set_calibration_and_imu_error_covariance(
                &record.covariance,
                &record.imu_error_covariance,
            )
        } else {
            filter.set_calibration_covariance(&record.covariance)
        };
        set.map_err(|_| RecordError::Values)?;
        filter
            .restart_keeping_calibration(&self.config.filter)
            .map_err(|_| RecordError::Values)?;
        self.calibration.estimate = record.estimate;
        self.calibration.imu_errors = record.imu_errors;
        self.calibration.manager.restart();
        self.restart_after_filter_reset();
        Ok(())
    }
}
