//! The border's propagation in three steps around the 24-state kernel (module docs of
//! [`crate::imu_error_states`]): the new `C` and the kernel's bias inputs into the spare
//! buffer and the scratch, then the kernel with them, then the new `C` made active. By 3×3
//! blocks; `M` has one non-zero per column, so a product with it is three scaled rows or
//! columns.

use super::{CrossCovariance, ImuErrorStates, Parts, DYNAMIC};
use crate::block::{self, Block, FiniteCheck, Row};
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::structured::{BorderBiasInputs, StructuredModel};
#[cfg(test)]
use {
    super::GROUPS,
    crate::imu_error::{equivalent_bias_terms, BiasSensor},
    nalgebra::Vector3,
};

/// The four groups' equivalent-bias maps at a linearisation point: the sensor a group's
/// three states enter (one per group by the layout) and, per state, the axis and multiplier
/// `m_k` (module docs, `M`).
#[cfg(test)]
#[derive(Debug, Clone, Copy)]
pub(super) struct GroupMap {
    /// Index of the sensor: 0 gyro, 1 accelerometer.
    pub(super) sensor: usize,
    pub(super) axes: [usize; 3],
    pub(super) multipliers: Row,
}

/// The groups' maps at `model`'s linearisation point.
#[cfg(test)]
pub(super) fn group_maps(model: &StructuredModel) -> [GroupMap; GROUPS] {
    let terms = equivalent_bias_terms(
        &Vector3::from(model.measured_rate()),
        &Vector3::from(model.measured_force()),
    );
    core::array::from_fn(|g| {
        let term = |c: usize| terms.get(3 * g + c).copied();
        let sensor = match term(0).map(|t| t.sensor) {
            Some(BiasSensor::Accel) => 1,
            _ => 0,
        };
        GroupMap {
            sensor,
            axes: [0, 1, 2].map(|c| term(c).map_or(0, |t| t.axis)),
            multipliers: [0, 1, 2].map(|c| term(c).map_or(f64::NAN, |t| t.multiplier)),
        }
    })
}

/// `M v` for a 12-vector `v` of the states' values, by sensor (gyro, accelerometer), written
/// out for the layout: gyro `[f_x g_x, ω_x a_yx + f_y g_y, ω_x a_zx + ω_y a_zy + f_z g_z]`,
/// accelerometer `[f_y a_xy + f_z a_xz, f_x a_yx + f_z a_yz, f_x a_zx + f_y a_zy]`.
fn to_bias(v: &[f64; IMU_ERROR_DIMENSION], (rate, force): (Row, Row)) -> [Row; 2] {
    let [w_x, w_y, _] = rate;
    let [f_x, f_y, f_z] = force;
    let [yx, zx, zy, xy, xz, ayx, yz, azx, azy, gx, gy, gz] = *v;
    [
        [
            f_x * gx,
            w_x * yx + f_y * gy,
            w_x * zx + w_y * zy + f_z * gz,
        ],
        [
            f_y * xy + f_z * xz,
            f_x * ayx + f_z * yz,
            f_x * azx + f_y * azy,
        ],
    ]
}

/// `E_{s,b}`: block `b` (ϑ, δp, δv) of sensor `s`'s bias column of `F`; `None` where it is
/// zero (the accelerometer's ϑ block), so products with it are skipped.
#[inline(always)]
fn bias_block(model: &StructuredModel, s: usize, b: usize) -> Option<&Block> {
    let (gyro, accel) = model.bias_columns();
    match s {
        0 => gyro.get(b),
        _ => b.checked_sub(1).and_then(|k| accel.get(k)),
    }
}

/// `M C_jᵀ` for row `j` of a cross-covariance: the row's equivalent-bias 6-vector (gyro,
/// accelerometer), written out for the layout as [`to_bias`] is (the test
/// `explicit_projection_equals_the_maps` holds it to `imu_error::equivalent_bias_terms`).
#[inline(always)]
pub(super) fn equivalent_row(cross: &CrossCovariance, motion: (Row, Row), j: usize) -> [f64; 6] {
    let row = |g: usize| cross.get(g).and_then(|group| group.get(j)).copied();
    let (Some([yx, zx, zy]), Some([xy, xz, ayx]), Some([yz, azx, azy]), Some([gx, gy, gz])) =
        (row(0), row(1), row(2), row(3))
    else {
        return [f64::NAN; 6];
    };
    let [[g0, g1, g2], [a0, a1, a2]] =
        to_bias(&[yx, zx, zy, xy, xz, ayx, yz, azx, azy, gx, gy, gz], motion);
    [g0, g1, g2, a0, a1, a2]
}

/// Three columns' equivalent-bias vectors (`[gyro, accelerometer]` each) as the bias inputs
/// of `StructuredModel::propagate_rows`: per sensor a block whose rows are the sensor axes
/// and whose columns are the three columns.
fn bias_input_blocks(columns: &[[Row; 2]]) -> [Block; 2] {
    core::array::from_fn(|s| {
        core::array::from_fn(|u| {
            core::array::from_fn(|c| {
                columns
                    .get(c)
                    .and_then(|column| column.get(s))
                    .and_then(|axes| axes.get(u))
                    .copied()
                    .unwrap_or(f64::NAN)
            })
        })
    })
}

/// `C⁺ = F C + Γ P_εε` into `new`: the dynamic rows `F C + E Q` (`Q_{s,h}`: the columns of
/// group `h` of `M P_εε`, `m_p`, folded into the bias inputs), the calibration rows those
/// of `old`.
fn propagate_cross(
    model: &StructuredModel,
    old: &CrossCovariance,
    m_p: &[[Row; 2]; IMU_ERROR_DIMENSION],
    new: &mut CrossCovariance,
) {
    let groups = new.iter_mut().zip(old.iter()).zip(m_p.chunks_exact(3));
    for ((new_group, old_group), m_p_group) in groups {
        let q = bias_input_blocks(m_p_group);
        let dynamic = model.propagate_rows(old_group, Some(&q));
        for (value, new_rows) in dynamic.iter().zip(new_group.chunks_exact_mut(3)) {
            for (slot, row) in new_rows.iter_mut().zip(value) {
                *slot = *row;
            }
        }
        for (new, old) in new_group.iter_mut().zip(old_group).skip(DYNAMIC) {
            *new = *old;
        }
    }
}

impl ImuErrorStates {
    /// The first step of a propagation (module docs): the new `C` (`F C + Γ P_εε`) into the
    /// spare buffer and the bias inputs the 24-state kernel folds in
    /// ([`crate::structured::BorderBiasInputs`]: `M C_jᵀ` of the old `C`, `M C⁺_rᵀ` of the
    /// new one's dynamic rows), and in `open_loop` the state increment `E M ε̂`, computed
    /// from the border alone; `false` if the state increment is not finite (nothing the filter reads has changed; the rest the
    /// kernel checks, see the body). Then the kernel runs with
    /// [`ImuErrorStates::propagation_inputs`] and [`ImuErrorStates::commit_propagation`]
    /// makes the new `C` active.
    pub(crate) fn prepare_propagation(&mut self, model: &StructuredModel, open_loop: bool) -> bool {
        let Parts {
            estimate,
            covariance,
            old,
            spare,
            scratch,
            ..
        } = self.parts();
        let motion = (model.measured_rate(), model.measured_force());
        // M P_εε by columns (P_εε is symmetric: column c is row c).
        let mut m_p = [[[0.0; 3]; 2]; IMU_ERROR_DIMENSION];
        for (column, row) in m_p.iter_mut().zip(covariance.iter()) {
            *column = to_bias(row, motion);
        }
        // The state increment only in open loop (in closed loop the state is not propagated).
        let bias = open_loop.then(|| to_bias(estimate, motion));
        for (b, increment) in scratch.state_increment.chunks_exact_mut(3).enumerate() {
            let mut row = [0.0; 3];
            for (s, u) in bias.iter().flatten().enumerate() {
                if let Some(e) = bias_block(model, s, b) {
                    row = block::mul_vector_add(row, e, *u);
                }
            }
            increment.copy_from_slice(&row);
        }
        propagate_cross(model, old, &m_p, spare);
        let inputs = &mut scratch.kernel_inputs;
        for (j, input) in inputs.state_columns.iter_mut().enumerate() {
            *input = equivalent_row(old, motion, j);
        }
        for (r, input) in inputs.dynamic_rows.iter_mut().enumerate() {
            *input = equivalent_row(spare, motion, r);
        }
        // The new C and the bias inputs are checked by the kernel: every value of C⁺'s
        // dynamic rows (the only new ones) enters a bias input of `dynamic_rows` (`to_bias`
        // multiplies each by its m_k, and a non-finite value times zero is NaN), and every
        // bias input enters the kernel's checked output (U or the upper triangle of P_dd,
        // through E: NaN again even where E is zero), so a non-finite one makes the kernel
        // refuse. Only the state increment, which the kernel never sees, is checked here.
        let mut check = FiniteCheck::new();
        scratch.state_increment.iter().for_each(|v| check.value(*v));
        check.all_finite()
    }

    /// The bias inputs of the 24-state kernel prepared last
    /// ([`ImuErrorStates::prepare_propagation`]).
    pub(crate) fn propagation_inputs(&self) -> &BorderBiasInputs {
        &self.scratch.kernel_inputs
    }

    /// The third step: the new `C` made active, and `B ← φ B` with the correlated GNSS error
    /// states' decay `φ` over the interval (`None` without them).
    pub(crate) fn commit_propagation(&mut self, gnss_decay: Option<f64>) {
        self.second_active = !self.second_active;
        if let Some(phi) = gnss_decay {
            for value in self.half_mut().gnss_cross.iter_mut().flatten() {
                *value *= phi;
            }
        }
    }

    /// `M Bᵀ` (gyro, accelerometer; columns the three GNSS error states): the bias inputs
    /// through which the GNSS border's `F C_GNSS` gains `Γ Bᵀ = E M Bᵀ` (module docs;
    /// `StructuredModel::propagate_rows`).
    pub(crate) fn gnss_bias_inputs(&self, model: &StructuredModel) -> [Block; 2] {
        let motion = (model.measured_rate(), model.measured_force());
        bias_input_blocks(&self.half().gnss_cross.map(|row| to_bias(&row, motion)))
    }

    /// `E M ε̂` on the dynamic rows, the open-loop state's increment of the propagation
    /// prepared last.
    pub(crate) fn state_increment(&self) -> &[f64; DYNAMIC] {
        &self.scratch.state_increment
    }
}
