//! The border's propagation in three steps around the 24-state kernel (module docs of
//! [`crate::imu_error_states`]): the new `C` into the spare buffer, then `P_xx += ΔP`, then
//! the new `C` made active. By 3×3 blocks; `M` has one non-zero per column, so a product
//! with it is three scaled rows or columns.

use super::{
    BorderMatrix, CrossCovariance, GroupMap, ImuErrorStates, Parts, Scratch, DYNAMIC, GROUPS,
};
use crate::block::{self, Block, FiniteCheck};
use crate::discretise::CovarianceMatrix;
use crate::imu_error::{equivalent_bias_terms, BiasSensor};
use crate::state::STATE_DIMENSION;
use crate::structured::{StateRows, StructuredModel};
use nalgebra::Vector3;

/// The groups' maps at `model`'s linearisation point.
fn group_maps(model: &StructuredModel) -> [GroupMap; GROUPS] {
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

/// `acc += B Mᵀ` for a block `B` with the group's three states as columns: column `k` of
/// `B` times `m_k` lands in column `axis_k`.
#[inline(always)]
pub(super) fn add_times_map_transpose(acc: &mut Block, b: &Block, map: &GroupMap) {
    for (acc_row, b_row) in acc.iter_mut().zip(b) {
        for ((axis, multiplier), value) in map.axes.iter().zip(map.multipliers).zip(b_row) {
            if let Some(slot) = acc_row.get_mut(*axis) {
                *slot += multiplier * value;
            }
        }
    }
}

/// `acc += M B` for a block `B` with the group's three states as rows: row `k` times `m_k`
/// lands in row `axis_k`.
#[inline(always)]
fn add_map_times(acc: &mut Block, map: &GroupMap, b: &Block) {
    for ((axis, multiplier), row) in map.axes.iter().zip(map.multipliers).zip(b) {
        if let Some(slot) = acc.get_mut(*axis) {
            *slot = block::row_add_scaled(*slot, *row, multiplier);
        }
    }
}

/// Row block `b` (states `3b..3b+3`) of a 24×3 matrix by rows.
#[inline(always)]
pub(super) fn rows_block(rows: &StateRows, b: usize) -> Block {
    [0, 1, 2].map(|i| rows.get(3 * b + i).copied().unwrap_or([f64::NAN; 3]))
}

/// Block `(g, h)` of `P_εε`.
#[inline(always)]
fn border_block(covariance: &BorderMatrix, g: usize, h: usize) -> Block {
    [0, 1, 2].map(|i| {
        let row = covariance.get(3 * g + i);
        [0, 1, 2].map(|j| {
            row.and_then(|r| r.get(3 * h + j))
                .copied()
                .unwrap_or(f64::NAN)
        })
    })
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

/// `Z_{j,s} = Σ_{g∈s} C⁺_{j,g} M_gᵀ` of row block `j`, into `z`.
fn project_rows(new: &CrossCovariance, maps: &[GroupMap; GROUPS], j: usize, z: &mut [Block; 2]) {
    *z = [block::ZERO; 2];
    for (group, map) in new.iter().zip(maps) {
        if let Some(target) = z.get_mut(map.sensor) {
            add_times_map_transpose(target, &rows_block(group, j), map);
        }
    }
}

/// `E_{s,b}`: block `b` (ϑ, δp, δv) of sensor `s`'s bias column.
#[inline(always)]
fn bias_block(scratch: &Scratch, s: usize, b: usize) -> Block {
    scratch
        .bias_columns
        .get(s)
        .and_then(|column| column.get(b))
        .copied()
        .unwrap_or(block::ZERO)
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
        } = self.parts();
        scratch.maps = group_maps(model);
        let (gyro, [accel_position, accel_velocity]) = model.bias_columns();
        scratch.bias_columns = [*gyro, [block::ZERO, *accel_position, *accel_velocity]];
        // Q_{s,h} = Σ_{g∈s} M_g P_gh, Π_{s,s'} = Σ_{h∈s'} Q_{s,h} M_hᵀ, and M ε̂ by sensor.
        let mut q = [[block::ZERO; GROUPS]; 2];
        let mut bias = [[0.0; 3]; 2];
        for (g, (map, values)) in scratch
            .maps
            .iter()
            .zip(estimate.chunks_exact(3))
            .enumerate()
        {
            if let (Some(q_row), Some(u)) = (q.get_mut(map.sensor), bias.get_mut(map.sensor)) {
                for (h, q_block) in q_row.iter_mut().enumerate() {
                    add_map_times(q_block, map, &border_block(covariance, g, h));
                }
                for ((axis, multiplier), value) in map.axes.iter().zip(map.multipliers).zip(values)
                {
                    if let Some(slot) = u.get_mut(*axis) {
                        *slot += multiplier * value;
                    }
                }
            }
        }
        scratch.projected = [[block::ZERO; 2]; 2];
        for (q_row, projected_row) in q.iter().zip(scratch.projected.iter_mut()) {
            for (q_block, map) in q_row.iter().zip(&scratch.maps) {
                if let Some(target) = projected_row.get_mut(map.sensor) {
                    add_times_map_transpose(target, q_block, map);
                }
            }
        }
        let mut state_increment = [0.0; DYNAMIC];
        for (b, increment) in state_increment.chunks_exact_mut(3).enumerate() {
            let mut row = [0.0; 3];
            for (s, u) in bias.iter().enumerate() {
                row = block::mul_vector_add(row, &bias_block(scratch, s, b), *u);
            }
            increment.copy_from_slice(&row);
        }
        scratch.state_increment = state_increment;
        // C⁺: dynamic rows F C + E Q, calibration rows those of C.
        let mut sum = 0.0;
        for (h, (new_group, old_group)) in spare.iter_mut().zip(old.iter()).enumerate() {
            let dynamic = model.propagate_rows(old_group);
            for (b, (y, new_rows)) in dynamic
                .iter()
                .zip(new_group.chunks_exact_mut(3))
                .enumerate()
            {
                let mut value = *y;
                for (s, q_row) in q.iter().enumerate() {
                    if let Some(q_block) = q_row.get(h) {
                        value = block::mul_add(&value, &bias_block(scratch, s, b), q_block);
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
    /// rows (module docs, written with the new `C⁺ = Y + Γ P_εε`: `ΔP_ji = C⁺_j Γ_iᵀ` for a
    /// calibration row `j`, `C⁺_j Γ_iᵀ + Γ_j C⁺_iᵀ − Γ_j P_εε Γ_iᵀ` in the dynamic block),
    /// symmetric by construction. `false` if the result is not finite: the kernel has
    /// written `P` then (finite covariances that overflow), and the caller restarts the
    /// filter.
    pub(crate) fn add_propagation_increment(&mut self, covariance: &mut CovarianceMatrix) -> bool {
        let Self {
            buffers: [first, second],
            second_active,
            scratch,
            ..
        } = self;
        let new: &CrossCovariance = if *second_active { first } else { second };
        for (b, z) in scratch.dynamic_projected.iter_mut().enumerate() {
            project_rows(new, &scratch.maps, b, z);
        }
        let scratch: &Scratch = scratch;
        let mut z = [block::ZERO; 2];
        let mut sum = 0.0;
        for j in 0..STATE_DIMENSION / 3 {
            let dynamic_row = scratch.dynamic_projected.get(j);
            match dynamic_row {
                Some(projected) => z = *projected,
                None => project_rows(new, &scratch.maps, j, &mut z),
            }
            for i in 0..3 {
                if dynamic_row.is_some() && j > i {
                    continue;
                }
                let delta = increment_block(scratch, &z, j, i);
                sum += delta.iter().flatten().sum::<f64>();
                add_block(covariance, (3 * j, 3 * i), &delta, j != i);
            }
        }
        sum.is_finite()
    }

    /// The third step: the new `C` made active.
    pub(crate) fn commit_propagation(&mut self) {
        self.second_active = !self.second_active;
    }

    /// `E M ε̂` on the dynamic rows, the open-loop state's increment of the propagation
    /// prepared last.
    pub(crate) fn state_increment(&self) -> &[f64; DYNAMIC] {
        &self.scratch.state_increment
    }
}

/// `ΔP` block (`j`, `i`), `i` dynamic, from `z = Z_{j,·}` (module docs); a diagonal block
/// from its upper triangle, mirrored, so it is exactly symmetric.
fn increment_block(scratch: &Scratch, z: &[Block; 2], j: usize, i: usize) -> Block {
    // Σ_s Z_{j,s} E_{s,i}ᵀ.
    let mut delta = block::ZERO;
    for (s, z_s) in z.iter().enumerate() {
        delta = block::mul_transpose_add(&delta, z_s, &bias_block(scratch, s, i));
    }
    if let (Some(_), Some(z_i)) = (
        scratch.dynamic_projected.get(j),
        scratch.dynamic_projected.get(i),
    ) {
        // + Σ_s E_{s,j} Z_{i,s}ᵀ − Σ_{s,s'} E_{s,j} Π_{s,s'} E_{s',i}ᵀ.
        for (s, z_is) in z_i.iter().enumerate() {
            delta = block::mul_transpose_add(&delta, &bias_block(scratch, s, j), z_is);
        }
        for (s, projected_row) in scratch.projected.iter().enumerate() {
            let e_j = bias_block(scratch, s, j);
            for (s2, projected) in projected_row.iter().enumerate() {
                let left = block::mul(&e_j, projected);
                let term = block::mul_transpose(&left, &bias_block(scratch, s2, i));
                delta = block::add_scaled(&delta, &term, -1.0);
            }
        }
    }
    if j == i {
        let [[d00, d01, d02], [_, d11, d12], [_, _, d22]] = delta;
        delta = [[d00, d01, d02], [d01, d11, d12], [d02, d12, d22]];
    }
    delta
}
