//! A fixed numerical workload run identically by the firmware on the Cortex-M7 and by the host
//! tests, whose results must agree bit for bit (`f64::to_bits`). It exercises what the filter
//! uses: 24×24 f64 products, libm transcendentals and quaternion integration.

use nalgebra::{Quaternion, SMatrix, Vector3};

use crate::attitude;

/// Number of f64 results produced by [`reference_workload`].
pub const REFERENCE_RESULT_COUNT: usize = 8;

/// Runs the reference workload: builds a deterministic 24×24 matrix `M` from `sin`/`exp`,
/// forms `M Mᵀ` and `M M` and their traces, and integrates the attitude quaternion of a coning
/// motion for 500 steps of 2 ms with the exact rotation-vector exponential.
///
/// Returns `[trace(M Mᵀ), trace(M M), (M Mᵀ)[(3,17)], q.w, q.x, q.y, q.z, |q| − 1]`.
pub fn reference_workload() -> [f64; REFERENCE_RESULT_COUNT] {
    let matrix = SMatrix::<f64, 24, 24>::from_fn(|row, column| {
        let r = f64::from(u32::try_from(row).unwrap_or(0));
        let c = f64::from(u32::try_from(column).unwrap_or(0));
        libm::sin(0.37 * r + 1.13 * c) * libm::exp(-0.05 * (r - c) * (r - c)) + 0.01 * r
    });
    let gram = matrix * matrix.transpose();
    let square = matrix * matrix;

    let mut attitude = Quaternion::new(1.0, 0.0, 0.0, 0.0);
    let step_s = 0.002;
    let coning_rate_rad_s = 2.0 * core::f64::consts::PI * 5.0;
    let cone_half_angle_rad = 0.02;
    let mut time_s = 0.0;
    for _ in 0..500 {
        let rate = Vector3::new(
            -cone_half_angle_rad * coning_rate_rad_s * libm::sin(coning_rate_rad_s * time_s),
            cone_half_angle_rad * coning_rate_rad_s * libm::cos(coning_rate_rad_s * time_s),
            0.1,
        );
        attitude = attitude::product(&attitude, &attitude::exp_rotation_vector(&(rate * step_s)));
        time_s += step_s;
    }
    [
        gram.trace(),
        square.trace(),
        gram.get((3, 17)).copied().unwrap_or(f64::NAN),
        attitude.w,
        attitude.i,
        attitude.j,
        attitude.k,
        attitude.norm() - 1.0,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_workload_is_finite_and_keeps_the_quaternion_unit() {
        let results = reference_workload();
        assert!(results.iter().all(|value| value.is_finite()));
        assert!(results[0] > 0.0, "trace of a Gram matrix is positive");
        assert!(results[7].abs() < 1e-12);
    }
}
