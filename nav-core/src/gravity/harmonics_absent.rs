//! [`FieldRemainder`] without the feature `gravity-field`: point mass + `J2` alone. It holds
//! no table and evaluates nothing, so a navigation computer built without the feature carries
//! none of the evaluation's memory; a model beyond `J2` is refused, never flown as `J2`.

use nalgebra::Vector3;

use super::FieldModel;
use crate::error::NavError;
use crate::frames::LaunchFrame;

/// The held value of a build without the field: zero.
static ZERO: Vector3<f64> = Vector3::new(0.0, 0.0, 0.0);

/// The field beyond `J2` compiled out (feature `gravity-field` off): the interface of the
/// sliced evaluation, for [`FieldModel::J2_ONLY`] alone (any work per frame). Nothing is
/// evaluated: the held value is zero and the omitted RMS is never measured.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldRemainder {
    model: FieldModel,
}

impl FieldRemainder {
    /// Point mass + `J2` only, a zero held value.
    pub const EMPTY: Self = Self {
        model: FieldModel::J2_ONLY,
    };

    /// Sets the model.
    ///
    /// # Errors
    /// As [`FieldModel::validate`], and [`NavError::InvalidConfiguration`] for a model beyond
    /// `J2` (degree above 2 or order above 0): its tables come with the feature
    /// `gravity-field`. `self` is unchanged on error.
    pub fn configure(&mut self, model: FieldModel) -> Result<(), NavError> {
        model.validate()?;
        if !model.is_j2_only() {
            return Err(NavError::InvalidConfiguration);
        }
        self.model = model;
        Ok(())
    }

    /// The model in use: point mass + `J2`.
    pub fn model(&self) -> &FieldModel {
        &self.model
    }

    /// Zero: no field beyond `J2` in this build.
    pub fn acceleration_launch_mps2(&self) -> &Vector3<f64> {
        &ZERO
    }

    /// Zero: the omitted field is not evaluated in this build.
    pub fn omitted_rms_mps2(&self) -> f64 {
        0.0
    }

    /// Zero: no evaluation in this build.
    pub fn evaluations(&self) -> u32 {
        0
    }

    /// Never: there is nothing to evaluate.
    #[inline]
    pub fn is_due(&self, _time_s: f64) -> bool {
        false
    }

    /// Does nothing: there is nothing to evaluate.
    ///
    /// # Errors
    /// None: always `Ok`, `self` unchanged.
    #[inline]
    pub fn advance(
        &mut self,
        _frame: &LaunchFrame,
        _time_s: f64,
        _position_launch_m: &Vector3<f64>,
    ) -> Result<(), NavError> {
        Ok(())
    }
}
