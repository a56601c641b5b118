//! The truth as the flight software's filter sees it when it estimates the systematic IMU
//! errors (`[filter.imu_errors]`): the filter's body frame is then the gyro-defined one, so
//! its biases, scale factors and star installation converge to the truth mapped into that
//! gauge (nav-core `imu_error::to_filter_gauge`), and its twelve systematic states to the
//! mapped misalignments and g-sensitivity. Without the states the truth is compared as it is.

use nalgebra::SVector;
use nav_core::imu_error::{to_filter_gauge, ImuErrorEstimate, ImuTruth, IMU_ERROR_DIMENSION};
use nav_core::NavError;

use crate::world::sensors::SensorErrorTruth;

/// The twelve states of an estimate as one vector (nav-core `ImuErrorBlock` order).
pub fn imu_error_vector(estimate: &ImuErrorEstimate) -> SVector<f64, IMU_ERROR_DIMENSION> {
    SVector::from_iterator(
        estimate
            .gyro_non_orthogonality_rad
            .iter()
            .chain(estimate.accel_misalignment_rad.iter())
            .chain(estimate.gyro_g_sensitivity_rad_s_per_mps2.iter())
            .copied(),
    )
}

/// `errors` in the filter's gauge, and the systematic states' truth in it.
///
/// # Errors
/// nav-core's error for a truth it cannot map (non-finite, singular or degenerate axes).
pub fn in_filter_gauge(
    errors: &SensorErrorTruth,
) -> Result<(SensorErrorTruth, ImuErrorEstimate), NavError> {
    let gauge = to_filter_gauge(&ImuTruth {
        gyro_misalignment_rad: errors.gyro_misalignment_rad,
        accel_misalignment_rad: errors.accel_misalignment_rad,
        gyro_g_sensitivity_rad_s_per_mps2: errors.gyro_g_sensitivity_rad_s_per_mps2,
        gyro_bias_rad_s: errors.gyro_bias_rad_per_s,
        accel_bias_mps2: errors.accel_bias_mps2,
        gyro_scale_factor: errors.gyro_scale_factor,
        accel_scale_factor: errors.accel_scale_factor,
        star_mounting: errors.star_mounting_q_bs,
        star_installation: errors.star_installation_q_psi,
    })?;
    let mapped = SensorErrorTruth {
        gyro_bias_rad_per_s: gauge.gyro_bias_rad_s,
        gyro_scale_factor: gauge.gyro_scale_factor,
        accel_bias_mps2: gauge.accel_bias_mps2,
        accel_scale_factor: gauge.accel_scale_factor,
        star_installation_q_psi: gauge.star_installation,
        ..*errors
    };
    Ok((mapped, gauge.imu))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Quaternion, Vector3};

    fn truth() -> SensorErrorTruth {
        SensorErrorTruth {
            gyro_bias_rad_per_s: Vector3::new(1e-6, -2e-6, 3e-6),
            gyro_scale_factor: Vector3::new(1e-4, -2e-4, 5e-5),
            accel_bias_mps2: Vector3::new(1e-4, 2e-4, -1e-4),
            accel_scale_factor: Vector3::new(-1e-4, 1e-4, 2e-4),
            star_installation_q_psi: Quaternion::new(1.0, 1e-4, -2e-4, 5e-5).normalize(),
            star_mounting_q_bs: Quaternion::new(0.9, 0.1, -0.4, 0.2).normalize(),
            gyro_misalignment_rad: Matrix3::zeros(),
            accel_misalignment_rad: Matrix3::zeros(),
            gyro_g_sensitivity_rad_s_per_mps2: Vector3::zeros(),
        }
    }

    /// Without misalignment the gauge is the body frame: every value is the truth's (to
    /// round-off) and the systematic states are zero.
    #[test]
    fn an_aligned_imu_maps_to_itself() {
        let errors = truth();
        let (mapped, imu) = in_filter_gauge(&errors).unwrap();
        assert!((mapped.gyro_bias_rad_per_s - errors.gyro_bias_rad_per_s).amax() < 1e-20);
        // The scale factors come back as 1 − (1 − λ): round-off of 1.
        assert!((mapped.accel_scale_factor - errors.accel_scale_factor).amax() < 1e-15);
        let q = (mapped.star_installation_q_psi.coords - errors.star_installation_q_psi.coords)
            .amax()
            .min(
                (mapped.star_installation_q_psi.coords + errors.star_installation_q_psi.coords)
                    .amax(),
            );
        assert!(q < 1e-15, "{q:e}");
        assert!(imu_error_vector(&imu).amax() < 1e-20);
    }

    /// A gyro x axis tilted towards y (`A_g,xy`) turns the filter's frame with it: the
    /// accelerometer shows the rotation as `a_xy = −a_yx`, and a g-sensitivity appears as
    /// itself.
    #[test]
    fn a_tilted_gyro_axis_turns_the_frame() {
        let mut errors = truth();
        errors.gyro_misalignment_rad[(0, 1)] = 2e-5;
        errors.gyro_g_sensitivity_rad_s_per_mps2 = Vector3::new(2.5e-7, 0.0, 0.0);
        let (_, imu) = in_filter_gauge(&errors).unwrap();
        let v = imu_error_vector(&imu);
        // accel_misalignment xy (index 3) and yx (index 5): a rotation about z (equal and
        // opposite to first order; the difference is second order in the tilt and the
        // scale factors).
        assert!((v[3] + v[5]).abs() < 1e-8, "{v}");
        assert!((v[0] - 2e-5).abs() < 1e-8, "{v}");
        assert!(v[3].abs() > 1.9e-5 && v[3].abs() < 2.1e-5, "{v}");
        assert!((v[9] - 2.5e-7).abs() < 1e-10, "{v}");
    }
}
