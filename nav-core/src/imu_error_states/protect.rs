//! The core's protections for the border (`crate::filter::ErrorStateFilter`'s
//! `protect_optional_variances` and `set_optional_block_frozen`): the variance floor and
//! ceiling of `P_εε`'s diagonal, and the frozen groups.

use super::{ImuErrorStates, GROUPS};
use crate::block::{self, Row};
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::state::OptionalBlock;

impl ImuErrorStates {
    /// The groups of three states of `block` (one of the border's layout blocks), as a range
    /// of group indices; empty for a block that is not the border's.
    fn groups(block: OptionalBlock) -> core::ops::Range<usize> {
        let first = OptionalBlock::GyroNonOrthogonality.index();
        match block.index().checked_sub(first) {
            Some(offset) if block != OptionalBlock::GnssError => {
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

    /// The frozen flags by group.
    #[inline]
    pub(super) fn frozen_groups(&self) -> [bool; GROUPS] {
        self.frozen
    }

    /// The variance floor and ceiling on `P_εε`'s diagonal, as the core's
    /// (`ErrorStateFilter::protect_variances`): a variance below its `floor` is raised to
    /// it; one above its `ceiling` becomes the ceiling, with the rest of its row and column
    /// (`P_εε`, `C` and `B = cov(ε_GNSS, ε)`) multiplied by `s = √(ceiling/variance)`,
    /// `P' = S P S`, which keeps every correlation coefficient and positive definiteness.
    /// Returns whether anything changed. Only the diagonal is read unless a ceiling is
    /// crossed (the scaling is out of line: it never runs in a nominal flight).
    pub(crate) fn protect_variances(
        &mut self,
        floor: &[f64; IMU_ERROR_DIMENSION],
        ceiling: &[f64; IMU_ERROR_DIMENSION],
    ) -> bool {
        let mut clamped = false;
        let mut crossing = 0u16;
        let bounds = floor.iter().zip(ceiling);
        for (a, (row, (floor, ceiling))) in self
            .half_mut()
            .covariance
            .iter_mut()
            .zip(bounds)
            .enumerate()
        {
            let Some(variance) = row.get_mut(a) else {
                continue;
            };
            if *variance < *floor {
                *variance = *floor;
                clamped = true;
            } else if *variance > *ceiling {
                crossing |= 1 << a;
            }
        }
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
        let crossed = |a: usize| crossing & (1 << a) != 0;
        let half = self.half_mut();
        let scales: [f64; IMU_ERROR_DIMENSION] = core::array::from_fn(|a| {
            match (
                crossed(a),
                half.covariance.get(a).and_then(|row| row.get(a)),
            ) {
                (true, Some(variance)) => {
                    crate::float::sqrt(ceiling.get(a).copied().unwrap_or(f64::NAN) / variance)
                }
                _ => 1.0,
            }
        });
        for (a, (row, s_a)) in half.covariance.iter_mut().zip(scales).enumerate() {
            for (value, s_b) in row.iter_mut().zip(scales) {
                *value = *value * s_a * s_b;
            }
            if let (true, Some(variance), Some(ceiling)) =
                (crossed(a), row.get_mut(a), ceiling.get(a))
            {
                *variance = *ceiling;
            }
        }
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

/// Row `a` of the new `P_εε` (`new`, by rows) for each state `a` of a frozen group: its
/// gain `K_a` is zero and `N_a = K_a S − M_a = −M_a`, so the expanded Joseph form gives
/// `P⁺_ab = P_ab + N_a·K_b − K_a·M_b = P_ab − M_a·K_b` (`P_ab` itself when `b` is frozen
/// too, `K_b = 0`), where the update's moving rows take `P_ab − K_a·M_b`. Written on both
/// sides of the diagonal (exactly symmetric); returns the sum of the new values (for the
/// finite check). Out of line: it runs only while a group is frozen.
#[cold]
#[inline(never)]
pub(super) fn frozen_border_rows(
    new: &mut [[f64; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION],
    old: &[[f64; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION],
    (gains, products): (&[Row], &[Row]),
    frozen: [bool; GROUPS],
) -> f64 {
    let mut sum = 0.0;
    for a in 0..IMU_ERROR_DIMENSION {
        if !frozen.get(a / 3).copied().unwrap_or(false) {
            continue;
        }
        let m_a = products.get(a).copied().unwrap_or([f64::NAN; 3]);
        for (b, k_b) in gains.iter().enumerate().skip(a + 1) {
            let value = old
                .get(a)
                .and_then(|row| row.get(b))
                .copied()
                .unwrap_or(f64::NAN)
                - block::dot(m_a, *k_b);
            for (row, column) in [(a, b), (b, a)] {
                if let Some(slot) = new.get_mut(row).and_then(|r| r.get_mut(column)) {
                    *slot = value;
                }
            }
            sum += value;
        }
    }
    sum
}
