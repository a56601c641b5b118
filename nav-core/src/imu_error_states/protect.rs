//! The core's protections for the border (`crate::filter::ErrorStateFilter`'s
//! `protect_optional_variances` and `set_optional_block_frozen`): the variance floor and
//! ceiling of `P_εε`'s diagonal, and the frozen groups.

use super::{ImuErrorStates, Parts, GROUPS};
use crate::block::{self, FiniteCheck, Row};
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::state::{BlockMask, OptionalBlock};

impl ImuErrorStates {
    /// The groups of three states of `block` (one of the border's layout blocks), as a range
    /// of group indices; empty for a block that is not the border's.
    fn groups(block: OptionalBlock) -> core::ops::Range<usize> {
        let first = OptionalBlock::GyroNonOrthogonality.index();
        match block.index().checked_sub(first) {
            Some(offset) if offset < IMU_ERROR_DIMENSION => {
                offset / 3..(offset + block.dimension()) / 3
            }
            _ => 0..0,
        }
    }

    /// Whether `block` (one of the border's) is frozen; `false` for any other block.
    pub fn is_frozen(&self, block: OptionalBlock) -> bool {
        let groups = Self::groups(block);
        !groups.is_empty()
            && self
                .frozen
                .get(groups)
                .is_some_and(|flags| flags.iter().all(|frozen| *frozen))
    }

    /// Freezes `block` (one of the border's) or releases it; any other block changes nothing.
    pub(crate) fn set_frozen(&mut self, block: OptionalBlock, frozen: bool) {
        for flag in self
            .frozen
            .get_mut(Self::groups(block))
            .into_iter()
            .flatten()
        {
            *flag = frozen;
        }
    }

    /// Whether any group is frozen (one comparison on the update's path).
    #[inline]
    pub(super) fn any_frozen(&self) -> bool {
        self.frozen != [false; GROUPS]
    }

    /// The variance floor and ceiling on `P_εε`'s diagonal, as the core's
    /// (`ErrorStateFilter::protect_variances`): a variance below its `floor` is raised to
    /// it; one above its `ceiling` becomes the ceiling, with the rest of its row and column
    /// (`P_εε`, `C` and `B = cov(ε_GNSS, ε)`) multiplied by `s = √(ceiling/variance)`,
    /// `P' = S P S`, which keeps every correlation coefficient and positive definiteness.
    /// Returns whether anything changed. Only the diagonal is read unless a ceiling is
    /// crossed (the scaling is out of line: it never runs in a nominal flight), and only
    /// after `P_εε` may have changed: a new prior or an update, never a propagation
    /// (`ε̇ = 0` and no process noise keep it), nor the core's protections and resets (they
    /// scale or map `C` only).
    pub(crate) fn protect_variances(
        &mut self,
        floor: &[f64; IMU_ERROR_DIMENSION],
        ceiling: &[f64; IMU_ERROR_DIMENSION],
    ) -> bool {
        if !self.variances_changed {
            return false;
        }
        self.variances_changed = false;
        let (clamped, crossing) =
            block::floor_and_mark_ceilings(&mut self.half_mut().covariance, floor, ceiling);
        if crossing != 0 {
            self.scale_to_ceilings(crossing, ceiling);
        }
        clamped || crossing != 0
    }

    /// `P' = S P S` for the states of `crossing` (bit `a`: state `a`), each with
    /// `s = √(ceiling/variance)`, on `P_εε`, `B` and `C`; each crossed diagonal then exactly
    /// its ceiling.
    #[cold]
    #[inline(never)]
    fn scale_to_ceilings(&mut self, crossing: u16, ceiling: &[f64; IMU_ERROR_DIMENSION]) {
        let half = self.half_mut();
        let scales = block::scale_to_ceilings(&mut half.covariance, crossing, ceiling);
        for row in &mut half.gnss_cross {
            for (value, s) in row.iter_mut().zip(scales) {
                *value *= s;
            }
        }
        for (group, group_scales) in self.cross_mut().iter_mut().zip(scales.chunks_exact(3)) {
            let [s0, s1, s2] = [0, 1, 2].map(|c| group_scales.get(c).copied().unwrap_or(1.0));
            for row in group.iter_mut() {
                let [c0, c1, c2] = *row;
                *row = [c0 * s0, c1 * s1, c2 * s2];
            }
        }
    }

    /// Row `m` of `B = cov(ε_GNSS, ε)` times `scales[m]` (the GNSS border's ceiling scaled
    /// that state).
    pub(crate) fn scale_gnss_rows(&mut self, scales: &Row) {
        for (row, scale) in self.half_mut().gnss_cross.iter_mut().zip(scales) {
            for value in row.iter_mut() {
                *value *= scale;
            }
        }
    }
}

/// The update prepared for a border that moves, corrected for the frozen groups (their `K_ε`
/// rows zero, as a frozen core block's) and, with `frozen_gnss` (its `M_GNSS` rows), for a
/// frozen GNSS border (`K_GNSS = 0`); returns whether every new value is finite. With
/// `K_a = 0` and `N_a = K_a S − M_a = −M_a` for a frozen state `a`, the expanded Joseph form
/// `P⁺_ij = P_ij + N_i·K_j − K_i·M_j` gives:
/// * `ε̂_a` unchanged;
/// * `C_ia − K_i·M_εa` on a moving core row `i` (`N_i = 0`: as computed), `C_ia` on a frozen
///   one (`K_i = 0` too);
/// * `P⁺_ab = P_ab − M_a·K_b` for `b ≥ a` (`P_ab` itself when `b` is frozen too), mirrored;
///   the moving rows' `P_ab − K_a·M_b` (`b < a`) hold as computed;
/// * with the GNSS border frozen, `B⁺_ma = B_ma − M_GNSS,m·K_εa`; moving, `B_ma − K_m·M_εa`
///   as computed (it does not read `K_ε`).
#[cold]
#[inline(never)]
pub(super) fn apply_frozen(
    states: &mut ImuErrorStates,
    core_frozen: &BlockMask,
    frozen_gnss: Option<&[Row; 3]>,
) -> bool {
    let groups = states.frozen;
    let Parts {
        estimate,
        covariance,
        gnss_cross,
        spare_half,
        old,
        spare,
        scratch,
    } = states.parts();
    for (gains, frozen) in scratch.border_gains.iter_mut().zip(groups) {
        if frozen {
            *gains = [[0.0; 3]; 3];
        }
    }
    for ((new_group, old_group), frozen) in spare.iter_mut().zip(old.iter()).zip(groups) {
        let blocks = new_group.chunks_exact_mut(3).zip(old_group.chunks_exact(3));
        for (block, (new_rows, old_rows)) in blocks.enumerate() {
            if frozen && core_frozen.contains_state(3 * block) {
                for (new, old) in new_rows.iter_mut().zip(old_rows) {
                    *new = *old;
                }
            }
        }
    }
    let (gains, products) = (
        scratch.border_gains.as_flattened(),
        scratch.border_products.as_flattened(),
    );
    let frozen_state = |a: usize| groups.get(a / 3).copied().unwrap_or(false);
    for (a, (new, old)) in spare_half.estimate.iter_mut().zip(estimate).enumerate() {
        if frozen_state(a) {
            *new = *old;
        }
    }
    for a in (0..IMU_ERROR_DIMENSION).filter(|a| frozen_state(*a)) {
        let m_a = products.get(a).copied().unwrap_or([f64::NAN; 3]);
        for (b, k_b) in gains.iter().enumerate().skip(a) {
            let old = covariance.get(a).and_then(|row| row.get(b)).copied();
            let value = old.unwrap_or(f64::NAN) - block::dot(m_a, *k_b);
            for (row, column) in [(a, b), (b, a)] {
                if let Some(slot) = spare_half
                    .covariance
                    .get_mut(row)
                    .and_then(|r| r.get_mut(column))
                {
                    *slot = value;
                }
            }
        }
    }
    if let Some(gnss_products) = frozen_gnss {
        let rows = spare_half
            .gnss_cross
            .iter_mut()
            .zip(gnss_cross)
            .zip(gnss_products);
        for ((new_row, old_row), m_gnss) in rows {
            for ((new, old), k_a) in new_row.iter_mut().zip(old_row).zip(gains) {
                *new = old - block::dot(*m_gnss, *k_a);
            }
        }
    }
    let mut check = FiniteCheck::new();
    spare.iter().flatten().for_each(|row| check.row(row));
    let half = spare_half
        .covariance
        .iter()
        .chain(spare_half.gnss_cross.iter());
    half.flatten()
        .chain(spare_half.estimate.iter())
        .for_each(|value| check.value(*value));
    check.all_finite()
}
