//! Referring a measurement to a later time without forming the system matrix.

use super::{ATT, BIAS_A, BIAS_G, POS, SCALE_A, SCALE_G, VEL};

use crate::block::{self, mul, mul_add, read, scale, scale_columns, Block, FiniteCheck};
use crate::error_model::LinearisationPoint;
use crate::measurement::LinearMeasurement;
use crate::NavError;

/// `crate::measurement::refer_to_later_time` without forming `A`: `H' = H − (H A) Δ`
/// computed from the blocks of `A` at `point` (only its attitude, position and velocity rows
/// are non-zero, [`crate::error_model`]):
/// `(H A)_ϑ = H_ϑ W + H_v V`, `(H A)_p = H_v N`, `(H A)_v = H_p`, `(H A)_bg = −½ H_ϑ`,
/// `(H A)_ba = −H_v Ĉ`, `(H A)_λg = −½ H_ϑ diag(ω_m)`, `(H A)_λa = −H_v Ĉ diag(f_m)`,
/// `(H A)_ψ = 0`, with `W = −[ω̂×]`, `V = −2Ĉ[f̂×]`, `N = ∂g/∂p`. Equal to the dense
/// version (proven by the tests).
///
/// # Errors
/// [`NavError::InvalidTimeStep`] for a negative or non-finite latency,
/// [`NavError::NonFiniteInput`] for a non-finite point.
pub fn refer_to_later_time_at(
    measurement: &LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<LinearMeasurement, NavError> {
    let mut referred = *measurement;
    refer_to_later_time_in_place(&mut referred, point, latency_s)?;
    Ok(referred)
}

/// [`refer_to_later_time_at`] in place (the flight path: a [`LinearMeasurement`] is large,
/// and every copy of it is a `memcpy` on the Cortex-M7 target). On an error the measurement
/// is unchanged.
///
/// # Errors
/// As [`refer_to_later_time_at`].
pub fn refer_to_later_time_in_place(
    measurement: &mut LinearMeasurement,
    point: &LinearisationPoint,
    latency_s: f64,
) -> Result<(), NavError> {
    if !(latency_s.is_finite() && latency_s >= 0.0) {
        return Err(NavError::InvalidTimeStep);
    }
    let rate = block::from_vector(&point.corrected_rate_rad_s);
    let force = block::from_vector(&point.corrected_specific_force_mps2);
    let measured_rate = block::from_vector(&point.measured_rate_rad_s);
    let measured_force = block::from_vector(&point.measured_specific_force_mps2);
    let c = block::from_matrix(&point.body_to_inertial);
    let gradient = block::from_matrix(&point.gravity_gradient_per_s2);
    let mut check = FiniteCheck::new();
    for value in rate
        .iter()
        .chain(&force)
        .chain(&measured_rate)
        .chain(&measured_force)
    {
        check.value(*value);
    }
    check.block(&c);
    check.block(&gradient);
    if !check.all_finite() {
        return Err(NavError::NonFiniteInput);
    }
    let h = &measurement.jacobian;
    // The blocks of H that (H A) reads, copied before H is changed.
    let (h_attitude, h_position, h_velocity) = (
        read::<0, ATT, 3, 24>(h),
        read::<0, POS, 3, 24>(h),
        read::<0, VEL, 3, 24>(h),
    );
    // A block of H that is all zero adds nothing to (H A): its products are skipped (a
    // star measurement has no position or velocity block, a GNSS velocity without lever
    // arm no attitude block; each product not formed is a block product saved on the
    // target). Subtracting a zero would change at most the sign of a zero entry of H,
    // which no later product sees.
    let attitude_observed = !is_zero(&h_attitude);
    let velocity_observed = !is_zero(&h_velocity);
    // H's columns (nalgebra stores columns: data.0[column][row]); element (i, offset + j)
    // is column offset + j, row i.
    let columns = &mut measurement.jacobian.data.0;
    let mut subtract = |offset: usize, product: &Block| {
        if let Some(block_columns) = columns.get_mut(offset..offset + 3) {
            for (j, column) in block_columns.iter_mut().enumerate() {
                for (entry, row) in column.iter_mut().zip(product) {
                    if let Some(value) = row.get(j) {
                        *entry -= value * latency_s;
                    }
                }
            }
        }
    };
    if attitude_observed {
        let w = scale(&block::skew(rate), -1.0);
        let h_w = mul(&h_attitude, &w);
        let v = mul(&scale(&c, -2.0), &block::skew(force));
        // (H A)_ϑ = H_ϑ W + H_v V (H_v V of a zero H_v is zero, and adding it is skipped).
        if velocity_observed {
            subtract(ATT, &mul_add(&h_w, &h_velocity, &v));
        } else {
            subtract(ATT, &h_w);
        }
        let half_attitude = scale(&h_attitude, -0.5);
        subtract(BIAS_G, &half_attitude);
        subtract(SCALE_G, &scale_columns(&half_attitude, measured_rate));
    } else if velocity_observed {
        let v = mul(&scale(&c, -2.0), &block::skew(force));
        subtract(ATT, &mul(&h_velocity, &v));
    }
    if velocity_observed {
        subtract(POS, &mul(&h_velocity, &gradient));
        let accel = mul(&h_velocity, &scale(&c, -1.0));
        subtract(BIAS_A, &accel);
        subtract(SCALE_A, &scale_columns(&accel, measured_force));
    }
    if !is_zero(&h_position) {
        subtract(VEL, &h_position);
    }
    Ok(())
}

/// Whether every value of `block` is zero (a NaN is not).
#[inline(always)]
fn is_zero(block: &Block) -> bool {
    block.iter().flatten().all(|value| *value == 0.0)
}
