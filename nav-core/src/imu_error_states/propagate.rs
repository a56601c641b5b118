//! The border's propagation in three steps around the 24-state kernel (module docs of
//! [`crate::imu_error_states`]): the new `C` into the spare buffer, then `P_xx += ΔP`, then
//! the new `C` made active. By 3×3 blocks; `M` has one non-zero per column, so a product
//! with it is three scaled rows or columns.

use super::{CrossCovariance, ImuErrorStates, Parts, DYNAMIC};
use crate::block::{self, Block, FiniteCheck, Row};
use crate::discretise::CovarianceMatrix;
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::state::STATE_DIMENSION;
use crate::structured::{StateRows, StructuredModel};
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

/// Row block `b` (states `3b..3b+3`) of a 24×3 matrix by rows.
#[inline(always)]
pub(super) fn rows_block(rows: &StateRows, b: usize) -> Block {
    [0, 1, 2].map(|i| rows.get(3 * b + i).copied().unwrap_or([f64::NAN; 3]))
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

/// `Z_{j,s} = Σ_{g∈s} C⁺_{j,g} M_gᵀ` of row block `j`, into `z`: [`equivalent_row`] of its
/// three rows.
fn project_rows(new: &CrossCovariance, motion: (Row, Row), j: usize, z: &mut [Block; 2]) {
    let [gyro, accel] = z;
    for (r, (gyro_row, accel_row)) in gyro.iter_mut().zip(accel.iter_mut()).enumerate() {
        let [g0, g1, g2, a0, a1, a2] = equivalent_row(new, motion, 3 * j + r);
        *gyro_row = [g0, g1, g2];
        *accel_row = [a0, a1, a2];
    }
}

/// `Σ_s Z_s E_{s,i}ᵀ`.
#[inline(always)]
fn times_bias_transpose(model: &StructuredModel, z: &[Block; 2], i: usize) -> Block {
    let mut product = block::ZERO;
    for (s, z_s) in z.iter().enumerate() {
        if let Some(e) = bias_block(model, s, i) {
            product = block::mul_transpose_add(&product, z_s, e);
        }
    }
    product
}

/// `P(r₀ + i, c₀ + j) += value[i][j]` and, when `mirror`, `P(c₀ + j, r₀ + i)` too (the
/// column-major storage: column by column).
fn add_block(
    covariance: &mut CovarianceMatrix,
    (r0, c0): (usize, usize),
    value: &Block,
    mirror: bool,
) {
    let columns = &mut covariance.data.0;
    for (j, column) in columns.iter_mut().skip(c0).take(3).enumerate() {
        for (slot, row) in column.iter_mut().skip(r0).zip(value) {
            if let Some(x) = row.get(j) {
                *slot += x;
            }
        }
    }
    if mirror {
        for (row, column) in value.iter().zip(columns.iter_mut().skip(r0)) {
            for (slot, x) in column.iter_mut().skip(c0).zip(row) {
                *slot += x;
            }
        }
    }
}

impl ImuErrorStates {
    /// The first step of a propagation (module docs): the new `C` (`F C + Γ P_εε`) into the
    /// spare buffer, computed from the border alone; `false` if it is not finite (nothing the
    /// filter reads has changed). Then the 24-state kernel runs,
    /// [`ImuErrorStates::add_propagation_increment`] adds `ΔP` and
    /// [`ImuErrorStates::commit_propagation`] makes the new `C` active.
    pub(crate) fn prepare_propagation(&mut self, model: &StructuredModel) -> bool {
        let Parts {
            estimate,
            covariance,
            old,
            spare,
            scratch,
            ..
        } = self.parts();
        let motion = (model.measured_rate(), model.measured_force());
        scratch.motion = motion;
        // M P_εε by columns (P_εε is symmetric: column c is row c), then
        // Π_{s,s'} = (M P_εε Mᵀ) by sensor pairs, row by row.
        let mut m_p = [[[0.0; 3]; 2]; IMU_ERROR_DIMENSION];
        for (column, row) in m_p.iter_mut().zip(covariance.iter()) {
            *column = to_bias(row, motion);
        }
        for (s, projected_row) in scratch.projected.iter_mut().enumerate() {
            for u in 0..3 {
                let row: [f64; IMU_ERROR_DIMENSION] = core::array::from_fn(|k| {
                    m_p.get(k)
                        .and_then(|c| c.get(s))
                        .and_then(|r| r.get(u))
                        .copied()
                        .unwrap_or(f64::NAN)
                });
                let [gyro, accel] = to_bias(&row, motion);
                for (projected, values) in projected_row.iter_mut().zip([gyro, accel]) {
                    if let Some(target) = projected.get_mut(u) {
                        *target = values;
                    }
                }
            }
        }
        let bias = to_bias(estimate, motion);
        let mut state_increment = [0.0; DYNAMIC];
        for (b, increment) in state_increment.chunks_exact_mut(3).enumerate() {
            let mut row = [0.0; 3];
            for (s, u) in bias.iter().enumerate() {
                if let Some(e) = bias_block(model, s, b) {
                    row = block::mul_vector_add(row, e, *u);
                }
            }
            increment.copy_from_slice(&row);
        }
        scratch.state_increment = state_increment;
        // C⁺: dynamic rows F C + E Q (Q_{s,h}: the columns of group h of M P_εε), calibration
        // rows those of C.
        let mut sum = 0.0;
        let groups = spare.iter_mut().zip(old.iter()).zip(m_p.chunks_exact(3));
        for ((new_group, old_group), m_p_group) in groups {
            let q: [Block; 2] = core::array::from_fn(|s| {
                core::array::from_fn(|u| {
                    core::array::from_fn(|c| {
                        m_p_group
                            .get(c)
                            .and_then(|column| column.get(s))
                            .and_then(|r| r.get(u))
                            .copied()
                            .unwrap_or(f64::NAN)
                    })
                })
            });
            let dynamic = model.propagate_rows(old_group);
            for (b, (y, new_rows)) in dynamic
                .iter()
                .zip(new_group.chunks_exact_mut(3))
                .enumerate()
            {
                let mut value = *y;
                for (s, q_block) in q.iter().enumerate() {
                    if let Some(e) = bias_block(model, s, b) {
                        value = block::mul_add(&value, e, q_block);
                    }
                }
                for (slot, row) in new_rows.iter_mut().zip(value) {
                    *slot = row;
                    sum += row.iter().sum::<f64>();
                }
            }
            for (new, old) in new_group.iter_mut().zip(old_group).skip(DYNAMIC) {
                *new = *old;
            }
        }
        let mut check = FiniteCheck::new();
        check.value(sum);
        scratch
            .projected
            .iter()
            .flatten()
            .for_each(|b| check.block(b));
        scratch.state_increment.iter().for_each(|v| check.value(*v));
        check.all_finite()
    }

    /// The second step, after the 24-state kernel: `P_xx += ΔP` on the dynamic columns and
    /// rows (module docs, written with the new `C⁺ = Y + Γ P_εε`), by 3×3 blocks: with
    /// `Z_{j,s} = C⁺_j M_sᵀ` (row block `j`'s equivalent-bias columns) and `E_{s,i}` block
    /// `i` of `E`, `ΔP_ji = Σ_s Z_{j,s} E_{s,i}ᵀ` for a calibration row block `j`, and in
    /// the dynamic block `ΔP_ji = A_ji + A_ijᵀ`, `A_ji = Σ_s Z'_{j,s} E_{s,i}ᵀ`,
    /// `Z'_{j,s} = Z_{j,s} − ½ Σ_{s'} E_{s',j} Π_{s',s}` (`Π = M P_εε Mᵀ`: the
    /// `−Γ P_εε Γᵀ` term split between the two halves). Symmetric by construction. `false`
    /// if the result is not finite: the kernel has written `P` then (finite covariances that
    /// overflow), and the caller restarts the filter.
    pub(crate) fn add_propagation_increment(
        &mut self,
        model: &StructuredModel,
        covariance: &mut CovarianceMatrix,
    ) -> bool {
        let Parts { spare, scratch, .. } = self.parts();
        // After prepare_propagation the spare buffer holds C⁺.
        let new: &CrossCovariance = spare;
        let mut dynamic = [[block::ZERO; 2]; 3];
        for (b, z) in dynamic.iter_mut().enumerate() {
            project_rows(new, scratch.motion, b, z);
            for (s, z_s) in z.iter_mut().enumerate() {
                for (s2, projected_row) in scratch.projected.iter().enumerate() {
                    if let (Some(e), Some(projected)) =
                        (bias_block(model, s2, b), projected_row.get(s))
                    {
                        *z_s = block::add_scaled(z_s, &block::mul(e, projected), -0.5);
                    }
                }
            }
        }
        let mut sum = 0.0;
        for (j, z_j) in dynamic.iter().enumerate() {
            for (i, z_i) in dynamic.iter().enumerate().skip(j) {
                let a_ji = times_bias_transpose(model, z_j, i);
                let a_ij = times_bias_transpose(model, z_i, j);
                let delta = block::add(&a_ji, &block::transpose(&a_ij));
                sum += delta.iter().flatten().sum::<f64>();
                add_block(covariance, (3 * j, 3 * i), &delta, j != i);
            }
        }
        let mut z = [block::ZERO; 2];
        for j in 3..STATE_DIMENSION / 3 {
            project_rows(new, scratch.motion, j, &mut z);
            for i in 0..3 {
                let delta = times_bias_transpose(model, &z, i);
                sum += delta.iter().flatten().sum::<f64>();
                add_block(covariance, (3 * j, 3 * i), &delta, true);
            }
        }
        sum.is_finite()
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

    /// `Γ Bᵀ = E M Bᵀ` on the dynamic rows (ϑ, δp, δv; columns: the three GNSS error
    /// states): what the GNSS border's `F C_GNSS` gains from the coupling (module docs).
    pub(crate) fn gnss_coupling(&self, model: &StructuredModel) -> [Block; 3] {
        let motion = (model.measured_rate(), model.measured_force());
        let bias = self.half().gnss_cross.map(|row| to_bias(&row, motion));
        core::array::from_fn(|b| {
            let mut rows = block::ZERO;
            for (m, [gyro, accel]) in bias.iter().enumerate() {
                let mut column = [0.0; 3];
                for (s, u) in [gyro, accel].into_iter().enumerate() {
                    if let Some(e) = bias_block(model, s, b) {
                        column = block::mul_vector_add(column, e, *u);
                    }
                }
                for (row, value) in rows.iter_mut().zip(column) {
                    if let Some(slot) = row.get_mut(m) {
                        *slot = value;
                    }
                }
            }
            rows
        })
    }

    /// `E M ε̂` on the dynamic rows, the open-loop state's increment of the propagation
    /// prepared last.
    pub(crate) fn state_increment(&self) -> &[f64; DYNAMIC] {
        &self.scratch.state_increment
    }
}
