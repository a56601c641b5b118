//! Propagation of the state and the covariance through the structured model: the 3×3 block
//! kernel (the target's) and the tail shared with the row kernel (`super::rows`, the host's).

#[cfg(any(test, target_arch = "arm"))]
use super::columns;
#[cfg(any(test, not(target_arch = "arm")))]
use super::rows;
use super::{
    BorderBiasInputs, StateRows, StructuredModel, ATT, BIAS_A, BIAS_G, POS, SCALE_A, SCALE_G, VEL,
};
use nalgebra::SMatrix;

#[cfg(any(test, target_arch = "arm"))]
use super::INSTALL;
use crate::block::{
    self, add, add_scaled, add_scaled_columns, mul, mul_add, mul_vector_add, read, row_add,
    write_diagonal_symmetric, write_symmetric, Block, FiniteCheck, Row,
};
#[cfg(any(test, target_arch = "arm"))]
use crate::block::{dot, dot_add, entry, row_at};
use crate::discretise::CovarianceMatrix;
#[cfg(any(test, target_arch = "arm"))]
use crate::state::CALIBRATION_DIMENSION;
use crate::state::{DYNAMIC_DIMENSION, STATE_DIMENSION};

impl StructuredModel {
    /// `x_d ← Φ x_d + E_g (x_bg + diag(ω_m) x_λg) + E_a (x_ba + diag(f_m) x_λa)`; the
    /// calibration states are unchanged (open-loop state propagation `x ← F x`).
    pub(crate) fn propagate_state(&self, state: &SMatrix<f64, 24, 1>) -> SMatrix<f64, 24, 1> {
        let part =
            |index: usize| [0, 1, 2].map(|i| state.get(index + i).copied().unwrap_or(f64::NAN));
        let multiply = |x: Row, scale: Row| {
            let ([x0, x1, x2], [s0, s1, s2]) = (x, scale);
            [x0 * s0, x1 * s1, x2 * s2]
        };
        let gyro = row_add(
            part(BIAS_G),
            multiply(part(SCALE_G), self.measured_rate_rad_s),
        );
        let accel = row_add(
            part(BIAS_A),
            multiply(part(SCALE_A), self.measured_specific_force_mps2),
        );
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let (attitude, position, velocity) = (part(ATT), part(POS), part(VEL));
        let zero = [0.0; 3];
        let new_attitude = mul_vector_add(
            mul_vector_add(zero, &t.attitude_attitude, attitude),
            gyro_attitude,
            gyro,
        );
        let new_position = [
            (&t.position_attitude, attitude),
            (&t.position_position, position),
            (&t.position_velocity, velocity),
            (gyro_position, gyro),
            (accel_position, accel),
        ]
        .iter()
        .fold(zero, |sum, (m, x)| mul_vector_add(sum, m, *x));
        let new_velocity = [
            (&t.velocity_attitude, attitude),
            (&t.velocity_position, position),
            (&t.velocity_velocity, velocity),
            (gyro_velocity, gyro),
            (accel_velocity, accel),
        ]
        .iter()
        .fold(zero, |sum, (m, x)| mul_vector_add(sum, m, *x));
        let mut propagated = *state;
        for (offset, values) in [
            (ATT, new_attitude),
            (POS, new_position),
            (VEL, new_velocity),
        ] {
            for (i, value) in values.iter().enumerate() {
                if let Some(slot) = propagated.get_mut(offset + i) {
                    *slot = *value;
                }
            }
        }
        propagated
    }

    /// Rows (ϑ, δp, δv) of `F C + E X` for a 24×3 matrix `C` given by its rows (the
    /// calibration rows of `F C` are those of `C`): `Φ C_d + E_g (C_bg + diag(ω_m) C_λg +
    /// X_g) + E_a (C_ba + diag(f_m) C_λa + X_a)`, [`StructuredModel::propagate_state`] for
    /// three columns at once, by blocks (the optional blocks' cross-covariances,
    /// [`crate::state::OptionalBlock`]). `bias_inputs`, `X = (X_g, X_a)`
    /// (rows the sensor axes, columns those of `C`), is the part `E X` of columns driven
    /// through the bias columns (a border's `Γ = E M`); `None` is `X = 0` (nothing added).
    pub(crate) fn propagate_rows(
        &self,
        rows: &StateRows,
        bias_inputs: Option<&[Block; 2]>,
    ) -> [Block; 3] {
        let block = |offset: usize| -> Block {
            [0, 1, 2].map(|i| rows.get(offset + i).copied().unwrap_or([f64::NAN; 3]))
        };
        let mut gyro =
            block::add_scaled_rows(&block(BIAS_G), &block(SCALE_G), self.measured_rate_rad_s);
        let mut accel = block::add_scaled_rows(
            &block(BIAS_A),
            &block(SCALE_A),
            self.measured_specific_force_mps2,
        );
        if let Some([gyro_input, accel_input]) = bias_inputs {
            gyro = add(&gyro, gyro_input);
            accel = add(&accel, accel_input);
        }
        let (attitude, position, velocity) = (block(ATT), block(POS), block(VEL));
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let new_attitude = mul_add(&mul(&t.attitude_attitude, &attitude), gyro_attitude, &gyro);
        let new_position = [
            (&t.position_position, &position),
            (&t.position_velocity, &velocity),
            (gyro_position, &gyro),
            (accel_position, &accel),
        ]
        .iter()
        .fold(mul(&t.position_attitude, &attitude), |sum, (m, x)| {
            mul_add(&sum, m, x)
        });
        let new_velocity = [
            (&t.velocity_position, &position),
            (&t.velocity_velocity, &velocity),
            (gyro_velocity, &gyro),
            (accel_velocity, &accel),
        ]
        .iter()
        .fold(mul(&t.velocity_attitude, &attitude), |sum, (m, x)| {
            mul_add(&sum, m, x)
        });
        [new_attitude, new_position, new_velocity]
    }

    /// Block (`R`, `S`), `S` = δp or δv, of the new `P_dd = U_d [Φ E]_Sᵀ` (without the
    /// walks' `Qd`): `row` is `(U_Rϑ, U_Rp, U_Rv)`, `folded` row `R` of `U`'s folded
    /// calibration columns (with the white noise folded in), `transition` row `S` of `Φ` and
    /// `bias_columns` row `S` of `E_g`, `E_a` (multiplied transposed: `X Yᵀ`, as
    /// `block::mul_transpose` then `block::mul_transpose_add`). A diagonal block (`UPPER`)
    /// is computed on and above its diagonal only (the rest is never read: zero).
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn dynamic_pair<const UPPER: bool>(
        row: [&Block; 3],
        folded: [&Block; 2],
        transition: [&Block; 3],
        bias_columns: [&Block; 2],
    ) -> Block {
        let [u_attitude, u_position, u_velocity] = row;
        let [f_attitude, f_position, f_velocity] = transition;
        let [gyro, accel] = folded;
        let [e_gyro, e_accel] = bias_columns;
        let terms = [
            (u_position, f_position),
            (u_velocity, f_velocity),
            (gyro, e_gyro),
            (accel, e_accel),
        ];
        pair_elements::<UPPER>(|i, j| {
            terms.iter().fold(
                dot(row_at(u_attitude, i), row_at(f_attitude, j)),
                |sum, (x, y)| dot_add(sum, row_at(x, i), row_at(y, j)),
            )
        })
    }

    /// Block (ϑ, ϑ) of the new `P_dd`, on and above its diagonal (`Φ_ϑp = Φ_ϑv = 0` and
    /// `E_a` has no attitude row).
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn attitude_pair(&self, u_attitude: &Block, gyro: &Block) -> Block {
        let [gyro_attitude, _, _] = &self.gyro_bias_column;
        let f_attitude = &self.transition.attitude_attitude;
        pair_elements::<true>(|i, j| {
            dot_add(
                dot(row_at(u_attitude, i), row_at(f_attitude, j)),
                row_at(gyro, i),
                row_at(gyro_attitude, j),
            )
        })
    }

    /// `P ← F P Fᵀ + Qd` in place, by blocks (module docs); `false` (and `P` unchanged) if
    /// the result is not finite. With `border` (states whose transition columns are `E M`,
    /// [`BorderBiasInputs`]) the 24-state part of the bordered propagation, `P ← F P Fᵀ +
    /// E M Cᵀ Fᵀ + F C Mᵀ Eᵀ + E M P_εε Mᵀ Eᵀ + Qd`, by the same kernels (module docs).
    /// Every new block is computed from the old `P` into locals first (`U` is 9×24, the new
    /// `P_dd` six blocks), checked, then written with its mirror.
    ///
    /// Two kernels compute `U` and the new `P_dd`, chosen by the target: 3×3 blocks with the
    /// accumulators in registers on a scalar double-precision FPU (32-bit ARM: the
    /// Cortex-M7 has no f64 SIMD), 24-wide rows that the compiler vectorises elsewhere
    /// (x86-64 SSE2, AArch64 NEON; [`rows`]). Both sum every element with the same
    /// operations in the same order, so they give the same bits (tested on the host, and by
    /// the host/target comparisons). The folding of the scale-factor columns, the noise of
    /// `P_dd`, the walk diagonal, the finite check of `P_dd` and its writes are shared; the
    /// new `P_dc` stays in blocks in one tail and in the rows of `U` in the other.
    ///
    /// Not inlined: inlined into the filter's one propagation path, its registers and stack
    /// frame would be shared with the optional blocks' steps, which costs the frame loop
    /// stack and instructions on the target (QEMU replay).
    #[inline(never)]
    pub(crate) fn propagate_covariance(
        &self,
        p: &mut CovarianceMatrix,
        border: Option<&BorderBiasInputs>,
    ) -> bool {
        #[cfg(target_arch = "arm")]
        return self.propagate_covariance_by_blocks(p, border);
        #[cfg(not(target_arch = "arm"))]
        return self.propagate_covariance_by_rows(p, border);
    }

    /// [`StructuredModel::propagate_covariance`] with the 3×3 block kernel (the target's,
    /// [`columns`]): `U`'s dynamic column blocks into locals, its calibration column blocks
    /// (the new `P_dc`) into the lower triangle of `P`, then the new `P_dd` from them.
    #[cfg(any(test, target_arch = "arm"))]
    pub(super) fn propagate_covariance_by_blocks(
        &self,
        p: &mut CovarianceMatrix,
        border: Option<&BorderBiasInputs>,
    ) -> bool {
        let rows = self.kernel_rows();
        let u_attitude_columns = self.dynamic_column_block::<ATT>(&rows, &p.data.0, border);
        let u_position_columns = self.dynamic_column_block::<POS>(&rows, &p.data.0, border);
        let u_velocity_columns = self.dynamic_column_block::<VEL>(&rows, &p.data.0, border);
        let check = self.calibration_column_blocks(&rows, p, border);
        let (folded_gyro, folded_accel) = self.fold_calibration_columns(
            &written_column::<BIAS_G>(p),
            &written_column::<SCALE_G>(p),
            &written_column::<BIAS_A>(p),
            &written_column::<SCALE_A>(p),
            border,
        );
        let [u_aa, u_pa, u_va] = &u_attitude_columns;
        let [u_ap, u_pp, u_vp] = &u_position_columns;
        let [u_av, u_pv, u_vv] = &u_velocity_columns;
        let [fg_a, fg_p, fg_v] = &folded_gyro;
        let [fa_a, fa_p, fa_v] = &folded_accel;
        let t = &self.transition;
        let [_, e_gyro_p, e_gyro_v] = &self.gyro_bias_column;
        let [e_accel_p, e_accel_v] = &self.accel_bias_column;
        let position_row = [
            &t.position_attitude,
            &t.position_position,
            &t.position_velocity,
        ];
        let velocity_row = [
            &t.velocity_attitude,
            &t.velocity_position,
            &t.velocity_velocity,
        ];
        let position_columns = [e_gyro_p, e_accel_p];
        let velocity_columns = [e_gyro_v, e_accel_v];
        // Rows of U_dd by reference (an array of blocks would copy every block).
        let row_a = [u_aa, u_ap, u_av];
        let row_p = [u_pa, u_pp, u_pv];
        let row_v = [u_va, u_vp, u_vv];
        let mut dynamic = [
            self.attitude_pair(u_aa, fg_a),
            Self::dynamic_pair::<false>(row_a, [fg_a, fa_a], position_row, position_columns),
            Self::dynamic_pair::<false>(row_a, [fg_a, fa_a], velocity_row, velocity_columns),
            Self::dynamic_pair::<true>(row_p, [fg_p, fa_p], position_row, position_columns),
            Self::dynamic_pair::<false>(row_p, [fg_p, fa_p], velocity_row, velocity_columns),
            Self::dynamic_pair::<true>(row_v, [fg_v, fa_v], velocity_row, velocity_columns),
        ];
        self.write_propagated(p, check, &mut dynamic)
    }

    /// `U`'s five calibration column blocks written into the lower triangle of `P`
    /// ([`columns`]), with their finite check. Not inlined: one frame for the five.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn calibration_column_blocks(
        &self,
        rows: &columns::KernelRows,
        p: &mut CovarianceMatrix,
        border: Option<&BorderBiasInputs>,
    ) -> FiniteCheck {
        let (dynamic, calibration) = p.data.0.split_at_mut(DYNAMIC_DIMENSION);
        let (Ok(dynamic), Ok(calibration)) = (
            <&mut [[f64; STATE_DIMENSION]; DYNAMIC_DIMENSION]>::try_from(dynamic),
            <&[[f64; STATE_DIMENSION]; CALIBRATION_DIMENSION]>::try_from(&*calibration),
        ) else {
            let mut check = FiniteCheck::new();
            check.value(f64::NAN);
            return check;
        };
        let (d, c) = (dynamic, calibration);
        let mut check = self.calibration_column_block::<BIAS_G>(rows, d, c, border);
        check.merge(self.calibration_column_block::<BIAS_A>(rows, d, c, border));
        check.merge(self.calibration_column_block::<INSTALL>(rows, d, c, border));
        check.merge(self.calibration_column_block::<SCALE_G>(rows, d, c, border));
        check.merge(self.calibration_column_block::<SCALE_A>(rows, d, c, border));
        check
    }

    /// [`StructuredModel::propagate_covariance`] with the row kernel ([`rows`]; the host's).
    #[cfg(any(test, not(target_arch = "arm")))]
    pub(super) fn propagate_covariance_by_rows(
        &self,
        p: &mut CovarianceMatrix,
        border: Option<&BorderBiasInputs>,
    ) -> bool {
        // Every element is written by `projected_rows` (the zeros are never read).
        let mut u = [[0.0; STATE_DIMENSION]; DYNAMIC_DIMENSION];
        rows::projected_rows(self, p, &mut u, border);
        let (folded_gyro, folded_accel) = self.fold_calibration_columns(
            &rows::column_block(&u, BIAS_G),
            &rows::column_block(&u, SCALE_G),
            &rows::column_block(&u, BIAS_A),
            &rows::column_block(&u, SCALE_A),
            border,
        );
        let mut dynamic = rows::dynamic_blocks(self, &u, &folded_gyro, &folded_accel);
        self.write_propagated_rows(p, &mut u, &mut dynamic)
    }

    /// `U`'s calibration columns folded (module docs), rows ϑ, δp, δv: the gyro's
    /// `U_bg + U_λg diag(ω_m) + q_g E_g` and the accelerometer's
    /// `U_ba + U_λa diag(f_m) + q_a E_a` (white noise folded in; `E_a` has no attitude row),
    /// then the border's `M C⁺_rᵀ` added to row `r` when there is one.
    #[inline(always)]
    fn fold_calibration_columns(
        &self,
        gyro_bias: &[Block; 3],
        gyro_scale: &[Block; 3],
        accel_bias: &[Block; 3],
        accel_scale: &[Block; 3],
        border: Option<&BorderBiasInputs>,
    ) -> ([Block; 3], [Block; 3]) {
        let (mut gyro, mut accel) =
            self.fold_bias_columns(gyro_bias, gyro_scale, accel_bias, accel_scale);
        if let Some(border) = border {
            let rows = border.dynamic_rows.chunks_exact(3);
            for ((gyro_block, accel_block), inputs) in gyro.iter_mut().zip(&mut accel).zip(rows) {
                for ((gyro_row, accel_row), input) in gyro_block
                    .iter_mut()
                    .zip(accel_block.iter_mut())
                    .zip(inputs)
                {
                    let [g0, g1, g2, a0, a1, a2] = *input;
                    *gyro_row = block::row_add(*gyro_row, [g0, g1, g2]);
                    *accel_row = block::row_add(*accel_row, [a0, a1, a2]);
                }
            }
        }
        (gyro, accel)
    }

    /// [`StructuredModel::fold_calibration_columns`] without a border.
    #[inline(always)]
    fn fold_bias_columns(
        &self,
        gyro_bias: &[Block; 3],
        gyro_scale: &[Block; 3],
        accel_bias: &[Block; 3],
        accel_scale: &[Block; 3],
    ) -> ([Block; 3], [Block; 3]) {
        let rate = self.measured_rate_rad_s;
        let force = self.measured_specific_force_mps2;
        let [gyro_a, gyro_p, gyro_v] = gyro_bias;
        let [accel_a, accel_p, accel_v] = accel_bias;
        let [scale_gyro_a, scale_gyro_p, scale_gyro_v] = gyro_scale;
        let [scale_accel_a, scale_accel_p, scale_accel_v] = accel_scale;
        let [gyro_noise, accel_noise] = self.input_noise;
        let [e_gyro_a, e_gyro_p, e_gyro_v] = &self.gyro_bias_column;
        let [e_accel_p, e_accel_v] = &self.accel_bias_column;
        let fold = |bias, scale_factor, input, column, noise| {
            add_scaled(
                &add_scaled_columns(bias, scale_factor, input),
                column,
                noise,
            )
        };
        (
            [
                fold(gyro_a, scale_gyro_a, rate, e_gyro_a, gyro_noise),
                fold(gyro_p, scale_gyro_p, rate, e_gyro_p, gyro_noise),
                fold(gyro_v, scale_gyro_v, rate, e_gyro_v, gyro_noise),
            ],
            [
                add_scaled_columns(accel_a, scale_accel_a, force),
                fold(accel_p, scale_accel_p, force, e_accel_p, accel_noise),
                fold(accel_v, scale_accel_v, force, e_accel_v, accel_noise),
            ],
        )
    }

    /// The block kernel's tail of the propagation: the walks' `Qd` added to the new `P_dd`
    /// (`dynamic`, pairs ϑϑ, ϑp, ϑv, pp, pv, vv without noise) and to the bias columns of
    /// the new `P_dc` (in the lower triangle, [`columns`]), the finite check of everything
    /// new (`check` holds the new `P_dc`'s before the walks), then the writes: the new
    /// `P_dc` copied into the upper triangle, `P_dd` with its mirror. `false`, with `P`
    /// restored from its upper triangle, if anything is not finite.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(always)]
    fn write_propagated(
        &self,
        p: &mut CovarianceMatrix,
        mut check: FiniteCheck,
        dynamic: &mut [Block; 6],
    ) -> bool {
        self.add_dynamic_noise(dynamic);
        // Bias walks: Qd in the bias columns of the dynamic rows and on the bias diagonal.
        if self.bias_walk {
            add_walk_to_lower::<BIAS_G>(p, &self.noise.dynamic_gyro_bias, &mut check);
            add_walk_to_lower::<BIAS_A>(p, &self.noise.dynamic_accel_bias, &mut check);
        }
        let walk_diagonal = self.walk_diagonal(p);
        Self::check_dynamic(&mut check, dynamic, &walk_diagonal);
        if !check.all_finite() {
            block::mirror_upper_to_lower(p, DYNAMIC_DIMENSION);
            return false;
        }
        copy_lower_calibration_to_upper(p);
        Self::write_dynamic(p, dynamic, &walk_diagonal);
        true
    }

    /// The row kernel's tail: as [`StructuredModel::write_propagated`], with `U`'s
    /// calibration columns (the new `P_dc`) kept in the rows of `u`: the walks' `Qd` added
    /// there, checked there, and written from there (each row into its column of `P`, and
    /// mirrored).
    #[cfg(any(test, not(target_arch = "arm")))]
    #[inline(always)]
    fn write_propagated_rows(
        &self,
        p: &mut CovarianceMatrix,
        u: &mut rows::ProjectedRows,
        dynamic: &mut [Block; 6],
    ) -> bool {
        self.add_dynamic_noise(dynamic);
        if self.bias_walk {
            rows::add_to_column(u, BIAS_G, &self.noise.dynamic_gyro_bias);
            rows::add_to_column(u, BIAS_A, &self.noise.dynamic_accel_bias);
        }
        let walk_diagonal = self.walk_diagonal(p);
        let mut check = FiniteCheck::new();
        Self::check_dynamic(&mut check, dynamic, &walk_diagonal);
        if !(check.all_finite() && rows::calibration_finite(u)) {
            return false;
        }
        rows::write_calibration_columns(p, u);
        Self::write_dynamic(p, dynamic, &walk_diagonal);
        true
    }

    /// The walks' `Qd` added to the new `P_dd` (zero noise blocks, no walk, are not added).
    #[inline(always)]
    fn add_dynamic_noise(&self, dynamic: &mut [Block; 6]) {
        if !self.noise_is_zero {
            for (value, q) in dynamic.iter_mut().zip(&self.noise.dynamic) {
                *value = add(value, q);
            }
        }
    }

    /// The new bias diagonal blocks under bias walks, `P_bg,bg + Qd` and `P_ba,ba + Qd`
    /// (read from the old `P`); `None` without walks (the blocks keep their values).
    #[inline(always)]
    fn walk_diagonal(&self, p: &CovarianceMatrix) -> Option<[Block; 2]> {
        if self.bias_walk {
            Some([
                add(&read::<BIAS_G, BIAS_G, 24, 24>(p), &self.noise.gyro_bias),
                add(&read::<BIAS_A, BIAS_A, 24, 24>(p), &self.noise.accel_bias),
            ])
        } else {
            None
        }
    }

    /// Adds the new `P_dd` and bias diagonal blocks to a finite check.
    #[inline(always)]
    fn check_dynamic(
        check: &mut FiniteCheck,
        dynamic: &[Block; 6],
        walk_diagonal: &Option<[Block; 2]>,
    ) {
        // The diagonal blocks on and above their diagonal only (the rest is not written).
        let [aa, ap, av, pp, pv, vv] = dynamic;
        for value in [upper(aa), *ap, *av, upper(pp), *pv, upper(vv)] {
            check.block(&value);
        }
        if let Some(blocks) = walk_diagonal {
            for value in blocks {
                check.block(value);
            }
        }
    }

    /// Writes the new `P_dd` (upper block triangle, mirrored) and bias diagonal blocks.
    #[inline(always)]
    fn write_dynamic(
        p: &mut CovarianceMatrix,
        dynamic: &[Block; 6],
        walk_diagonal: &Option<[Block; 2]>,
    ) {
        let [new_aa, new_ap, new_av, new_pp, new_pv, new_vv] = dynamic;
        write_diagonal_symmetric::<ATT>(p, new_aa);
        write_symmetric::<ATT, POS>(p, new_ap);
        write_symmetric::<ATT, VEL>(p, new_av);
        write_diagonal_symmetric::<POS>(p, new_pp);
        write_symmetric::<POS, VEL>(p, new_pv);
        write_diagonal_symmetric::<VEL>(p, new_vv);
        if let Some([gyro, accel]) = walk_diagonal {
            write_diagonal_symmetric::<BIAS_G>(p, gyro);
            write_diagonal_symmetric::<BIAS_A>(p, accel);
        }
    }
}

/// The elements of a 3×3 block from `element(i, j)`; with `UPPER`, those on and above the
/// diagonal only (the others zero).
#[cfg(any(test, target_arch = "arm"))]
#[inline(always)]
fn pair_elements<const UPPER: bool>(element: impl Fn(usize, usize) -> f64) -> Block {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| if UPPER && j < i { 0.0 } else { element(i, j) }))
}

/// A diagonal block's elements on and above its diagonal (the others zero).
#[inline(always)]
fn upper(b: &Block) -> Block {
    let [[b00, b01, b02], [_, b11, b12], [_, _, b22]] = *b;
    [[b00, b01, b02], [0.0, b11, b12], [0.0, 0.0, b22]]
}

/// `U`'s column block at `C` (rows ϑ, δp, δv) as written by the block kernel into the
/// lower triangle of `P` ([`columns`]): element `(i, j)` of block `R` is `P(C + j, R + i)`.
#[cfg(any(test, target_arch = "arm"))]
#[inline(always)]
fn written_column<const C: usize>(p: &CovarianceMatrix) -> [Block; 3] {
    [ATT, POS, VEL].map(|r| [0, 1, 2].map(|i| [0, 1, 2].map(|j| entry(p, C + j, r + i))))
}

/// Adds a walk's `Qd` blocks (rows ϑ, δp, δv) to the new `P_dc`'s column block at `C` in the
/// lower triangle (as `block::add`), and checks the sums.
#[cfg(any(test, target_arch = "arm"))]
#[inline(always)]
fn add_walk_to_lower<const C: usize>(
    p: &mut CovarianceMatrix,
    noise: &[Block; 3],
    check: &mut FiniteCheck,
) {
    for (r, block) in [ATT, POS, VEL].iter().zip(noise) {
        for (i, q_row) in block.iter().enumerate() {
            let Some(row) = p.data.0.get_mut(r + i).and_then(|c| c.get_mut(C..C + 3)) else {
                continue;
            };
            for (value, q) in row.iter_mut().zip(q_row) {
                *value += q;
                check.value(*value);
            }
        }
    }
}

/// Copies the new `P_dc` from the lower triangle (rows 9..24 of columns 0..9, where the
/// block kernel writes it) into the upper (rows 0..9 of columns 9..24).
#[cfg(any(test, target_arch = "arm"))]
#[inline(always)]
fn copy_lower_calibration_to_upper(p: &mut CovarianceMatrix) {
    let (dynamic, calibration) = p.data.0.split_at_mut(DYNAMIC_DIMENSION);
    let Ok(dynamic) = <&[[f64; STATE_DIMENSION]; DYNAMIC_DIMENSION]>::try_from(&*dynamic) else {
        return;
    };
    for (row, column) in (DYNAMIC_DIMENSION..).zip(calibration.iter_mut()) {
        let Some(top) = column.first_chunk_mut::<{ DYNAMIC_DIMENSION }>() else {
            continue;
        };
        *top = dynamic
            .each_ref()
            .map(|source| source.get(row).copied().unwrap_or(f64::NAN));
    }
}
