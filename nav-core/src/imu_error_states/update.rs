//! The border's part of a measurement update, in two steps around the 24-state Joseph kernel
//! (module docs of [`crate::imu_error_states`]): `M_ε`, `K_ε` and the new `C` (into the spare
//! buffer) with the new `P_εε` and `ε̂` checked, then all of them committed in place.

use super::protect::apply_frozen;
use super::{BorderMatrix, CrossCovariance, Estimate, ImuErrorStates, Parts, GROUPS};
use crate::block::{self, dot, FiniteCheck, Row};
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::measurement::MeasurementJacobian;
use crate::state::{BlockMask, STATE_DIMENSION};
use crate::structured::StateRows;

impl ImuErrorStates {
    /// The first step of the border's update with `H_x` (`observed` its non-zero 3×3
    /// blocks), the 24 gains `K_x` (zero on the `frozen` rows), `M_x = P_xx H_xᵀ`, `S⁻¹`
    /// (`solve`) and the innovation `ν` (module docs): `M_ε = (H_x C)ᵀ`, `K_ε = M_ε S⁻¹`, the
    /// new `C` into the spare buffer (`C⁺_ia = C_ia − K_i·M_εa`, `− M_i·K_εa` on a frozen
    /// row); `false` if it, the new `P_εε` or the new `ε̂` is not finite (nothing the filter
    /// reads has changed). [`ImuErrorStates::commit_update`] writes them. `gnss`: the GNSS
    /// border's `h`, `M_GNSS` rows and whether it is frozen.
    ///
    /// With a frozen group, or the GNSS border frozen, the values of the moving border are
    /// corrected afterwards ([`apply_frozen`], out of line: a nominal flight never runs it),
    /// so the update's own loops are those of a border that moves.
    #[inline(always)]
    pub(crate) fn prepare_update(
        &mut self,
        jacobian: (&MeasurementJacobian, &[bool; STATE_DIMENSION / 3]),
        core: (&StateRows, &StateRows, &BlockMask),
        solve: impl Fn(Row) -> Row,
        innovation: Row,
        gnss: Option<(f64, &[Row; 3], bool)>,
    ) -> bool {
        let moving = gnss.map(|(coefficient, products, _)| (coefficient, products));
        let finite = self.prepare_moving_update(jacobian, core, solve, innovation, moving);
        let frozen_gnss = gnss.and_then(|(_, products, frozen)| frozen.then_some(products));
        if self.any_frozen() || frozen_gnss.is_some() {
            return apply_frozen(self, core.2, frozen_gnss);
        }
        finite
    }

    /// [`Self::prepare_update`] for a border that moves: every `K_ε` row as computed.
    #[inline(always)]
    fn prepare_moving_update(
        &mut self,
        (jacobian, observed): (&MeasurementJacobian, &[bool; STATE_DIMENSION / 3]),
        (gains, products, frozen): (&StateRows, &StateRows, &BlockMask),
        solve: impl Fn(Row) -> Row,
        innovation: Row,
        gnss: Option<(f64, &[Row; 3])>,
    ) -> bool {
        let Parts {
            estimate,
            covariance,
            gnss_cross,
            spare_half,
            old,
            spare,
            scratch,
        } = self.parts();
        border_products(&mut scratch.border_products, old, (jacobian, observed));
        // With the GNSS border: M_ε gains h Bᵀ (H_GNSS = h I).
        if let Some((coefficient, _)) = gnss.filter(|(h, _)| *h != 0.0) {
            add_gnss_products(&mut scratch.border_products, gnss_cross, coefficient);
        }
        for (gains_group, products_group) in scratch
            .border_gains
            .iter_mut()
            .zip(&scratch.border_products)
        {
            for (gain, product) in gains_group.iter_mut().zip(products_group) {
                *gain = solve(*product);
            }
        }
        let border = (&scratch.border_gains, &scratch.border_products);
        let mut sum = updated_cross(spare, old, (gains, products, frozen), border);
        let (gains_flat, products_flat) = (
            scratch.border_gains.as_flattened(),
            scratch.border_products.as_flattened(),
        );
        // Whole 12-row arrays: the loops' indices are then provably in bounds.
        let (Some(border_gains), Some(border_products)) = (
            gains_flat.first_chunk::<IMU_ERROR_DIMENSION>(),
            products_flat.first_chunk::<IMU_ERROR_DIMENSION>(),
        ) else {
            return false;
        };
        sum += updated_border(
            spare_half,
            (estimate, covariance),
            (border_gains, border_products),
            innovation,
        );
        // B ← B − K_GNSS M_εᵀ into the spare half.
        if let Some((_, gnss_products)) = gnss {
            let rows = spare_half
                .gnss_cross
                .iter_mut()
                .zip(gnss_cross)
                .zip(gnss_products);
            for ((new_row, old_row), gnss_product) in rows {
                let gain = solve(*gnss_product);
                for ((new, old), m_a) in new_row.iter_mut().zip(old_row).zip(products_flat) {
                    *new = old - dot(gain, *m_a);
                    sum += *new;
                }
            }
        } else {
            spare_half.gnss_cross = *gnss_cross;
        }
        let mut check = FiniteCheck::new();
        check.value(sum);
        check.all_finite()
    }

    /// The second step, after the 24-state kernel: the new `C`, `P_εε` and `ε̂` made active.
    pub(crate) fn commit_update(&mut self) {
        self.second_active = !self.second_active;
        self.second_half = !self.second_half;
        self.variances_changed = true;
    }
}

/// `M_ε` by groups, into `products`: row `c` of group `g` is `Σ_j H[:, j] C_g[j][c]` over the
/// observed blocks. A group's nine sums stay in registers across the observed blocks.
#[inline(always)]
fn border_products(
    products: &mut [[Row; 3]; GROUPS],
    cross: &CrossCovariance,
    (jacobian, observed): (&MeasurementJacobian, &[bool; STATE_DIMENSION / 3]),
) {
    for (group, products) in cross.iter().zip(products.iter_mut()) {
        let mut sums = [[0.0; 3]; 3];
        let blocks = jacobian.data.0.chunks_exact(3).zip(observed);
        let rows = group.chunks_exact(3);
        for ((h_columns, _), c_rows) in blocks.zip(rows).filter(|((_, seen), _)| **seen) {
            for (h_column, c_row) in h_columns.iter().zip(c_rows) {
                for (sum, c) in sums.iter_mut().zip(c_row) {
                    *sum = block::row_add_scaled(*sum, *h_column, *c);
                }
            }
        }
        *products = sums;
    }
}

/// `M_ε += h Bᵀ` (a GNSS position fix with the correlated GNSS error states).
#[inline(always)]
fn add_gnss_products(
    products: &mut [[Row; 3]; GROUPS],
    gnss_cross: &[[f64; IMU_ERROR_DIMENSION]; 3],
    coefficient: f64,
) {
    for (a, product) in products.as_flattened_mut().iter_mut().enumerate() {
        let column = [0, 1, 2].map(|m| {
            gnss_cross
                .get(m)
                .and_then(|row| row.get(a))
                .copied()
                .unwrap_or(f64::NAN)
        });
        *product = block::row_add_scaled(*product, column, coefficient);
    }
}

/// The new `C` into `new` (module docs, "Update"), from the 24 gains `K_x` (zero on the
/// frozen rows), `M_x` and the border's `K_ε`, `M_ε` by groups; returns the sum of the new
/// values (for the finite check).
#[inline(always)]
fn updated_cross(
    new: &mut CrossCovariance,
    old: &CrossCovariance,
    (gains, products, frozen): (&StateRows, &StateRows, &BlockMask),
    (border_gains, border_products): (&[[Row; 3]; GROUPS], &[[Row; 3]; GROUPS]),
) -> f64 {
    let mut sum = 0.0;
    let groups = new.iter_mut().zip(old.iter());
    for ((new_group, old_group), (k_g, m_g)) in groups.zip(border_gains.iter().zip(border_products))
    {
        // C⁺_ia = C_ia − K_i·M_εa on every row (K_i = 0 on a frozen row: C_ia − 0) ...
        let [m0, m1, m2] = *m_g;
        let rows = new_group.iter_mut().zip(old_group).zip(gains);
        for ((new, [c0, c1, c2]), k) in rows {
            let values = [c0 - dot(*k, m0), c1 - dot(*k, m1), c2 - dot(*k, m2)];
            let [a, b, c] = values;
            sum += (a + b) + c;
            *new = values;
        }
        // ... then − M_i·K_εa on the frozen rows.
        let [k0, k1, k2] = *k_g;
        let blocks = new_group.chunks_exact_mut(3).zip(products.chunks_exact(3));
        for (b, (new_rows, m_rows)) in blocks.enumerate() {
            if frozen.contains_state(3 * b) {
                for (new, m) in new_rows.iter_mut().zip(m_rows) {
                    *new = block::row_sub(*new, [dot(*m, k0), dot(*m, k1), dot(*m, k2)]);
                    let [a, b, c] = *new;
                    sum += (a + b) + c;
                }
            }
        }
    }
    sum
}

/// The new `P_εε = P_εε − K_ε M_εᵀ` (the upper triangle, then mirrored: exactly symmetric)
/// and `ε̂ + K_ε ν` into `new`; returns the sum of the new values (for the finite check).
#[inline(always)]
fn updated_border(
    new: &mut Estimate,
    (estimate, covariance): (&[f64; IMU_ERROR_DIMENSION], &BorderMatrix),
    (gains, products): (&[Row; IMU_ERROR_DIMENSION], &[Row; IMU_ERROR_DIMENSION]),
    innovation: Row,
) -> f64 {
    let mut sum = 0.0;
    let rows = new.covariance.iter_mut().zip(covariance.iter());
    for (a, ((new_row, old_row), k_a)) in rows.zip(gains).enumerate() {
        for b in a..IMU_ERROR_DIMENSION {
            let entry = (new_row.get_mut(b), old_row.get(b), products.get(b));
            if let (Some(new), Some(old), Some(m_b)) = entry {
                *new = old - dot(*k_a, *m_b);
                sum += *new;
            }
        }
        if let Some(value) = new.estimate.get_mut(a) {
            *value = estimate.get(a).copied().unwrap_or(f64::NAN) + dot(*k_a, innovation);
            sum += *value;
        }
    }
    for a in 0..IMU_ERROR_DIMENSION {
        let (upper, lower) = new.covariance.split_at_mut(a + 1);
        let Some(row) = upper.last() else { continue };
        for (lower_row, value) in lower.iter_mut().zip(row.iter().skip(a + 1)) {
            if let Some(slot) = lower_row.get_mut(a) {
                *slot = *value;
            }
        }
    }
    sum
}
