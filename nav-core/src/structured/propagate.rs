//! Propagation of the state and the covariance through the structured model: the 3×3 block
//! kernel (the target's) and the tail shared with the row kernel (`super::rows`, the host's).

#[cfg(any(test, not(target_arch = "arm")))]
use super::rows;
use super::{StateRows, StructuredModel, ATT, BIAS_A, BIAS_G, POS, SCALE_A, SCALE_G, VEL};
use nalgebra::SMatrix;

#[cfg(any(test, target_arch = "arm"))]
use super::INSTALL;
use crate::block::{
    self, add, add_scaled, add_scaled_columns, mul, mul_add, mul_vector_add, read, row_add,
    write_diagonal_symmetric, write_symmetric, Block, FiniteCheck, Row,
};
#[cfg(any(test, target_arch = "arm"))]
use crate::block::{mul_transpose, mul_transpose_add};
use crate::discretise::CovarianceMatrix;
#[cfg(any(test, not(target_arch = "arm")))]
use crate::state::STATE_DIMENSION;

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

    /// Rows (ϑ, δp, δv) of `F C` for a 24×3 matrix `C` given by its rows (the calibration
    /// rows of `F C` are those of `C`): `Φ C_d + E_g (C_bg + diag(ω_m) C_λg) + E_a (C_ba +
    /// diag(f_m) C_λa)`, [`StructuredModel::propagate_state`] for three columns at once, by
    /// blocks (the correlated-error border's cross-covariance, [`crate::gnss_error`]).
    pub(crate) fn propagate_rows(&self, rows: &StateRows) -> [Block; 3] {
        let block = |offset: usize| -> Block {
            [0, 1, 2].map(|i| rows.get(offset + i).copied().unwrap_or([f64::NAN; 3]))
        };
        let gyro =
            block::add_scaled_rows(&block(BIAS_G), &block(SCALE_G), self.measured_rate_rad_s);
        let accel = block::add_scaled_rows(
            &block(BIAS_A),
            &block(SCALE_A),
            self.measured_specific_force_mps2,
        );
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

    /// Rows (ϑ, δp, δv) of `U = [Φ E] P` in one column block, given as its three columns of
    /// `P`; scale factors folded into the biases (module docs). Not inlined: one compact
    /// body called per column block keeps the working set in the registers and the
    /// addresses within load offsets on the target.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn propagate_column(&self, columns: [&[f64; 24]; 3]) -> [Block; 3] {
        use crate::block::add_scaled_rows;
        let rows = |offset: usize| -> Block {
            [0, 1, 2].map(|i| columns.map(|c| c.get(offset + i).copied().unwrap_or(f64::NAN)))
        };
        let attitude = rows(ATT);
        let position = rows(POS);
        let velocity = rows(VEL);
        let gyro = add_scaled_rows(&rows(BIAS_G), &rows(SCALE_G), self.measured_rate_rad_s);
        let accel = add_scaled_rows(
            &rows(BIAS_A),
            &rows(SCALE_A),
            self.measured_specific_force_mps2,
        );
        let t = &self.transition;
        let [gyro_attitude, gyro_position, gyro_velocity] = &self.gyro_bias_column;
        let [accel_position, accel_velocity] = &self.accel_bias_column;
        let sum = |terms: [(&Block, &Block); 5]| {
            let [(f0, x0), rest @ ..] = terms;
            rest.iter()
                .fold(mul(f0, x0), |acc, (f, x)| mul_add(&acc, f, x))
        };
        [
            mul_add(&mul(&t.attitude_attitude, &attitude), gyro_attitude, &gyro),
            sum([
                (&t.position_attitude, &attitude),
                (&t.position_position, &position),
                (&t.position_velocity, &velocity),
                (gyro_position, &gyro),
                (accel_position, &accel),
            ]),
            sum([
                (&t.velocity_attitude, &attitude),
                (&t.velocity_position, &position),
                (&t.velocity_velocity, &velocity),
                (gyro_velocity, &gyro),
                (accel_velocity, &accel),
            ]),
        ]
    }

    /// Block (`R`, `S`), `S` = δp or δv, of the new `P_dd = U_d [Φ E]_Sᵀ` (without the
    /// walks' `Qd`): `row` is `(U_Rϑ, U_Rp, U_Rv)`, `folded` row `R` of `U`'s folded
    /// calibration columns (with the white noise folded in), `transition` row `S` of `Φ` and
    /// `bias_columns` row `S` of `E_g`, `E_a` (multiplied transposed: `X Yᵀ`).
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn dynamic_pair(
        row: [&Block; 3],
        folded: [&Block; 2],
        transition: [&Block; 3],
        bias_columns: [&Block; 2],
    ) -> Block {
        let [u_attitude, u_position, u_velocity] = row;
        let [f_attitude, f_position, f_velocity] = transition;
        let [gyro, accel] = folded;
        let [e_gyro, e_accel] = bias_columns;
        let mut value = mul_transpose(u_attitude, f_attitude);
        value = mul_transpose_add(&value, u_position, f_position);
        value = mul_transpose_add(&value, u_velocity, f_velocity);
        value = mul_transpose_add(&value, gyro, e_gyro);
        mul_transpose_add(&value, accel, e_accel)
    }

    /// Block (`R`, ϑ) of the new `P_dd`: `Φ_ϑp = Φ_ϑv = 0` and `E_a` has no attitude row.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(never)]
    fn attitude_pair(&self, u_attitude: &Block, gyro: &Block) -> Block {
        let [gyro_attitude, _, _] = &self.gyro_bias_column;
        mul_transpose_add(
            &mul_transpose(u_attitude, &self.transition.attitude_attitude),
            gyro,
            gyro_attitude,
        )
    }

    /// `P ← F P Fᵀ + Qd` in place, by blocks (module docs); `false` (and `P` unchanged) if
    /// the result is not finite. Every new block is computed from the old `P` into locals
    /// first (`U` is 9×24, the new `P_dd` six blocks), checked, then written with its mirror.
    ///
    /// Two kernels compute `U` and the new `P_dd`, chosen by the target: 3×3 blocks with the
    /// accumulators in registers on a scalar double-precision FPU (32-bit ARM: the
    /// Cortex-M7 has no f64 SIMD), 24-wide rows that the compiler vectorises elsewhere
    /// (x86-64 SSE2, AArch64 NEON; [`rows`]). Both sum every element with the same
    /// operations in the same order, so they give the same bits (tested on the host, and by
    /// the host/target comparisons). The folding of the scale-factor columns, the noise of
    /// `P_dd`, the walk diagonal, the finite check of `P_dd` and its writes are shared; the
    /// new `P_dc` stays in blocks in one tail and in the rows of `U` in the other.
    pub(crate) fn propagate_covariance(&self, p: &mut CovarianceMatrix) -> bool {
        #[cfg(target_arch = "arm")]
        return self.propagate_covariance_by_blocks(p);
        #[cfg(not(target_arch = "arm"))]
        return self.propagate_covariance_by_rows(p);
    }

    /// [`StructuredModel::propagate_covariance`] with the 3×3 block kernel (the target's).
    #[cfg(any(test, target_arch = "arm"))]
    pub(super) fn propagate_covariance_by_blocks(&self, p: &mut CovarianceMatrix) -> bool {
        // `ck` is column `k` of `P` (state `k`, [`crate::state`] order): the three columns of
        // a block are `c{3b}..c{3b+2}` for the block at offset `3b`.
        let [c0, c1, c2, c3, c4, c5, c6, c7, c8, c9, c10, c11, c12, c13, c14, c15, c16, c17, c18, c19, c20, c21, c22, c23] =
            &p.data.0;
        // U = [Φ E] P by column blocks; U's calibration columns are the new P_dc.
        // Bound whole and split by reference: destructuring by value copies each block.
        let u_attitude_columns = self.propagate_column([c0, c1, c2]);
        let u_position_columns = self.propagate_column([c3, c4, c5]);
        let u_velocity_columns = self.propagate_column([c6, c7, c8]);
        let mut gyro_bias = self.propagate_column([c9, c10, c11]);
        let mut accel_bias = self.propagate_column([c12, c13, c14]);
        let installation = self.propagate_column([c15, c16, c17]);
        let gyro_scale = self.propagate_column([c18, c19, c20]);
        let accel_scale = self.propagate_column([c21, c22, c23]);
        let (folded_gyro, folded_accel) =
            self.fold_calibration_columns(&gyro_bias, &gyro_scale, &accel_bias, &accel_scale);
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
        // Rows of U_dd by reference (an array of blocks would be copied, 72 bytes each).
        let row_a = [u_aa, u_ap, u_av];
        let row_p = [u_pa, u_pp, u_pv];
        let row_v = [u_va, u_vp, u_vv];
        let mut dynamic = [
            self.attitude_pair(u_aa, fg_a),
            Self::dynamic_pair(row_a, [fg_a, fa_a], position_row, position_columns),
            Self::dynamic_pair(row_a, [fg_a, fa_a], velocity_row, velocity_columns),
            Self::dynamic_pair(row_p, [fg_p, fa_p], position_row, position_columns),
            Self::dynamic_pair(row_p, [fg_p, fa_p], velocity_row, velocity_columns),
            Self::dynamic_pair(row_v, [fg_v, fa_v], velocity_row, velocity_columns),
        ];
        self.write_propagated(
            p,
            [&mut gyro_bias, &mut accel_bias],
            [&installation, &gyro_scale, &accel_scale],
            &mut dynamic,
        )
    }

    /// [`StructuredModel::propagate_covariance`] with the row kernel ([`rows`]; the host's).
    #[cfg(any(test, not(target_arch = "arm")))]
    pub(super) fn propagate_covariance_by_rows(&self, p: &mut CovarianceMatrix) -> bool {
        // Every element is written by `projected_rows` (the zeros are never read).
        let mut u = [[0.0; STATE_DIMENSION]; rows::DYNAMIC_DIMENSION];
        rows::projected_rows(self, p, &mut u);
        let (folded_gyro, folded_accel) = self.fold_calibration_columns(
            &rows::column_block(&u, BIAS_G),
            &rows::column_block(&u, SCALE_G),
            &rows::column_block(&u, BIAS_A),
            &rows::column_block(&u, SCALE_A),
        );
        let mut dynamic = rows::dynamic_blocks(self, &u, &folded_gyro, &folded_accel);
        self.write_propagated_rows(p, &mut u, &mut dynamic)
    }

    /// `U`'s calibration columns folded (module docs), rows ϑ, δp, δv: the gyro's
    /// `U_bg + U_λg diag(ω_m) + q_g E_g` and the accelerometer's
    /// `U_ba + U_λa diag(f_m) + q_a E_a` (white noise folded in; `E_a` has no attitude row).
    #[inline(always)]
    fn fold_calibration_columns(
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
    /// (`dynamic`, pairs ϑϑ, ϑp, ϑv, pp, pv, vv without noise) and to the bias columns, the
    /// finite check of everything new, then the writes with their mirrors. `bias` are `U`'s
    /// gyro- and accelerometer-bias columns, `other` its installation and scale-factor
    /// columns (rows ϑ, δp, δv each). `false`, with `P` unchanged, if anything is not finite.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(always)]
    fn write_propagated(
        &self,
        p: &mut CovarianceMatrix,
        bias: [&mut [Block; 3]; 2],
        other: [&[Block; 3]; 3],
        dynamic: &mut [Block; 6],
    ) -> bool {
        self.add_dynamic_noise(dynamic);
        let [gyro_bias, accel_bias] = bias;
        // Bias walks: Qd in the bias columns of the dynamic rows and on the bias diagonal.
        if self.bias_walk {
            // In place (new arrays of blocks would be copies).
            let with = |column: &mut [Block; 3], noise: &[Block; 3]| {
                for (value, q) in column.iter_mut().zip(noise) {
                    *value = add(value, q);
                }
            };
            with(gyro_bias, &self.noise.dynamic_gyro_bias);
            with(accel_bias, &self.noise.dynamic_accel_bias);
        }
        let walk_diagonal = self.walk_diagonal(p);
        let [installation, gyro_scale, accel_scale] = other;
        let mut check = FiniteCheck::new();
        for blocks in [
            &*gyro_bias,
            &*accel_bias,
            installation,
            gyro_scale,
            accel_scale,
        ] {
            for value in blocks {
                check.block(value);
            }
        }
        Self::check_dynamic(&mut check, dynamic, &walk_diagonal);
        if !check.all_finite() {
            return false;
        }
        let [gyro_a, gyro_p, gyro_v] = &*gyro_bias;
        write_symmetric::<ATT, BIAS_G>(p, gyro_a);
        write_symmetric::<POS, BIAS_G>(p, gyro_p);
        write_symmetric::<VEL, BIAS_G>(p, gyro_v);
        let [accel_a, accel_p, accel_v] = &*accel_bias;
        write_symmetric::<ATT, BIAS_A>(p, accel_a);
        write_symmetric::<POS, BIAS_A>(p, accel_p);
        write_symmetric::<VEL, BIAS_A>(p, accel_v);
        let [installation_a, installation_p, installation_v] = installation;
        write_symmetric::<ATT, INSTALL>(p, installation_a);
        write_symmetric::<POS, INSTALL>(p, installation_p);
        write_symmetric::<VEL, INSTALL>(p, installation_v);
        let [scale_gyro_a, scale_gyro_p, scale_gyro_v] = gyro_scale;
        write_symmetric::<ATT, SCALE_G>(p, scale_gyro_a);
        write_symmetric::<POS, SCALE_G>(p, scale_gyro_p);
        write_symmetric::<VEL, SCALE_G>(p, scale_gyro_v);
        let [scale_accel_a, scale_accel_p, scale_accel_v] = accel_scale;
        write_symmetric::<ATT, SCALE_A>(p, scale_accel_a);
        write_symmetric::<POS, SCALE_A>(p, scale_accel_p);
        write_symmetric::<VEL, SCALE_A>(p, scale_accel_v);
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
        for value in dynamic.iter() {
            check.block(value);
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
