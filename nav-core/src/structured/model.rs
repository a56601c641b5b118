//! Rebuilding the structured model: the series of `Φ`, `E` and the noise blocks of `Qd`
//! (module docs of [`super`]).

use super::{
    DynamicBlocks, NoiseBlocks, Powers, StructuredModel, DYNAMIC_PAIRS, DYNAMIC_ROWS,
    INVERSE_FACTORIALS,
};

use crate::block::{
    self, add_scaled, mul, mul_transpose, mul_transpose_add, row_scale, scale, Block, FiniteCheck,
    IDENTITY, ZERO,
};
use crate::discretise::MAX_ORDER;
use crate::error_model::{LinearisationPoint, ProcessNoise};
use crate::state::{BlockMask, StateBlock, ACCEL_BIAS, GYRO_BIAS};
use crate::NavError;

/// `out = factor · Σ_n T_n / (n + shift)!` over the terms `(n, T_n)` with
/// `n + shift ≤ order` (an absent power is simply not listed). A diagonal first term
/// (`DIAGONAL_FIRST`: the identity, or `ΔI`) adds only its scaled diagonal (the same
/// products, without the zero off-diagonal ones). Inlined at each call, so the term
/// array, the shift and the diagonal flag fold into constants (a called function builds
/// the arrays of `(n, &T_n)` in memory at every call).
#[inline(always)]
fn series_into<const N: usize, const DIAGONAL_FIRST: bool>(
    out: &mut Block,
    terms: &[(usize, &Block); N],
    order: usize,
    shift: usize,
    factor: f64,
) {
    let mut sum = ZERO;
    for (index, (n, term)) in terms.iter().enumerate() {
        if n + shift <= order {
            if let Some(coefficient) = INVERSE_FACTORIALS.get(n + shift) {
                let scale = factor * coefficient;
                if DIAGONAL_FIRST && index == 0 {
                    for (i, (row, term_row)) in sum.iter_mut().zip(term.iter()).enumerate() {
                        if let (Some(value), Some(diagonal)) = (row.get_mut(i), term_row.get(i)) {
                            *value += diagonal * scale;
                        }
                    }
                } else {
                    sum = add_scaled(&sum, term, scale);
                }
            }
        }
    }
    *out = sum;
}

impl Powers {
    /// All blocks zero.
    const ZERO: Self = Powers {
        a: ZERO,
        b: ZERO,
        g: ZERO,
        d_identity: ZERO,
        a2: ZERO,
        a3: ZERO,
        a4: ZERO,
        d_b: ZERO,
        d_ba: ZERO,
        position_attitude_4: ZERO,
        dg: ZERO,
        d2_g2: ZERO,
        d2_g: ZERO,
        ba: ZERO,
        velocity_attitude_3: ZERO,
        velocity_attitude_4: ZERO,
        velocity_position_3: ZERO,
    };

    /// The powers at `point` over `d = Δ` (module docs: `a = WΔ`, `b = VΔ`, `g = NΔ`), in
    /// place: every block the order reaches is overwritten (a new struct is zero-filled and
    /// moved on the target).
    #[inline(never)]
    fn update(&mut self, point: &LinearisationPoint, c: &Block, d: f64, order: usize) {
        let rate = block::from_vector(&point.corrected_rate_rad_s);
        let force = block::from_vector(&point.corrected_specific_force_mps2);
        self.a = block::skew(row_scale(rate, -d));
        self.b = scale(&mul(c, &block::skew(force)), -2.0 * d);
        self.g = scale(&block::from_matrix(&point.gravity_gradient_per_s2), d);
        self.d_identity = scale(&IDENTITY, d);
        self.d_b = scale(&self.b, d);
        self.dg = scale(&self.g, d);
        // The blocks beyond the order are left as they are: the series never read them
        // (`series_into` takes a term only if its power is within the order).
        if order >= 2 {
            self.a2 = mul(&self.a, &self.a);
            self.ba = mul(&self.b, &self.a);
        }
        if order >= 3 {
            let gb = mul(&self.g, &self.b);
            let ba2 = mul(&self.ba, &self.a);
            self.a3 = mul(&self.a2, &self.a);
            self.d_ba = scale(&self.ba, d);
            self.d2_g = scale(&self.dg, d);
            self.velocity_attitude_3 = add_scaled(&ba2, &gb, d);
            let g2 = mul(&self.g, &self.g);
            self.velocity_position_3 = scale(&g2, d);
            if order >= 4 {
                self.a4 = mul(&self.a2, &self.a2);
                self.position_attitude_4 = add_scaled(&scale(&ba2, d), &gb, d * d);
                self.d2_g2 = scale(&g2, d * d);
                self.velocity_attitude_4 =
                    add_scaled(&mul(&ba2, &self.a), &mul(&self.g, &self.ba), d);
            }
        }
    }
}

impl Powers {
    /// `Φ = Σ (MΔ)^n/n!` block by block, and `E_g = −½Δ Ψ_{·ϑ}`, `E_a = −Δ Ψ_{·v} Ĉ` (`Ψ`:
    /// shift 1), from these powers over `d = Δ`. Not inlined, and given the blocks it fills
    /// apart from the powers: the powers lie deep into the model, beyond the reach of a
    /// load's offset from the model's address, and each read of one would need its
    /// own address computation.
    #[inline(never)]
    fn transition_into(
        &self,
        transition: &mut DynamicBlocks,
        gyro_bias_column: &mut [Block; 3],
        accel_bias_column: &mut [Block; 2],
        (order, d): (usize, f64),
        c: &Block,
    ) {
        let terms = SeriesTerms::of(self);
        transition_into(transition, &terms, order);
        terms.gyro_columns_into(gyro_bias_column, order, 1, -0.5 * d);
        terms.accel_columns_into(accel_bias_column, order, 1, -d, c);
    }
}

/// `dynamic = q Γ Γᵀ` (`ACCUMULATE` false: written, so the blocks need no zero fill first)
/// or `dynamic += q Γ Γᵀ` over the pairs of [`DYNAMIC_PAIRS`] for an input column
/// `Γ = [Γ_ϑ; Γ_p; Γ_v]`: `q Γ_R Γ_Sᵀ`, with `q` folded into the left factor.
fn noise_input<const ACCUMULATE: bool>(dynamic: &mut [Block; 6], q: f64, gamma: &[Block; 3]) {
    let [ga, gp, gv] = gamma;
    let scaled = [scale(ga, q), scale(gp, q), scale(gv, q)];
    let [qa, qp, qv] = &scaled;
    let products = [(qa, ga), (qa, gp), (qa, gv), (qp, gp), (qp, gv), (qv, gv)];
    for (slot, (left, right)) in dynamic.iter_mut().zip(products) {
        *slot = if ACCUMULATE {
            mul_transpose_add(slot, left, right)
        } else {
            mul_transpose(left, right)
        };
    }
}

/// `dynamic += q Γ Γᵀ` for an input with a zero attitude row, `Γ = [0; Γ_p; Γ_v]`: only
/// the pairs pp, pv, vv are reached.
fn add_accel_noise_input(dynamic: &mut [Block; 6], q: f64, gamma: &[Block; 2]) {
    let [gp, gv] = gamma;
    let qp = scale(gp, q);
    let [_, _, _, pp, pv, vv] = dynamic;
    *pp = mul_transpose_add(pp, &qp, gp);
    *pv = mul_transpose_add(pv, &qp, gv);
    *vv = mul_transpose_add(vv, &scale(gv, q), gv);
}

impl NoiseBlocks {
    /// Sets the dynamic and gyro-bias blocks to `q Γ Γᵀ` (module docs) of the gyro-bias
    /// walk, `q` = `q_k/Δ`, for its noise column `Γ = [Γ_ϑ; Γ_p; Γ_v; ΔI]` given by its
    /// dynamic rows `columns` (the first of the two walks: it writes, the other adds).
    fn set_gyro_walk(&mut self, q: f64, interval_s: f64, columns: &[Block; 3]) {
        noise_input::<false>(&mut self.dynamic, q, columns);
        // Γ_bias = ΔI: (X, bg) = q Γ_X Δ, (bg, bg) = q Δ² I.
        for (slot, gamma) in self.dynamic_gyro_bias.iter_mut().zip(columns) {
            *slot = scale(gamma, q * interval_s);
        }
        self.gyro_bias = scale(&IDENTITY, q * interval_s * interval_s);
    }

    /// No gyro-bias walk: the blocks [`NoiseBlocks::set_gyro_walk`] writes, zero.
    fn clear_gyro_walk(&mut self) {
        self.dynamic = [ZERO; 6];
        self.dynamic_gyro_bias = [ZERO; 3];
        self.gyro_bias = ZERO;
    }

    /// [`NoiseBlocks::set_gyro_walk`] for the accelerometer-bias walk, whose column has a
    /// zero attitude row: `columns` are its rows δp, δv. Adds to the dynamic blocks (after
    /// the gyro walk's), writes its own bias blocks.
    fn add_accel_walk(&mut self, q: f64, interval_s: f64, columns: &[Block; 2]) {
        add_accel_noise_input(&mut self.dynamic, q, columns);
        let [attitude, position, velocity] = &mut self.dynamic_accel_bias;
        let [walk_position, walk_velocity] = columns;
        *attitude = ZERO;
        *position = scale(walk_position, q * interval_s);
        *velocity = scale(walk_velocity, q * interval_s);
        self.accel_bias = scale(&IDENTITY, q * interval_s * interval_s);
    }

    /// No accelerometer-bias walk: its own bias blocks zero.
    fn clear_accel_walk(&mut self) {
        self.dynamic_accel_bias = [ZERO; 3];
        self.accel_bias = ZERO;
    }

    /// No noise.
    const ZERO: Self = NoiseBlocks {
        dynamic: [ZERO; 6],
        dynamic_gyro_bias: [ZERO; 3],
        dynamic_accel_bias: [ZERO; 3],
        gyro_bias: ZERO,
        accel_bias: ZERO,
    };

    /// Every block with its (row, column) state blocks.
    fn blocks_mut(&mut self) -> impl Iterator<Item = (StateBlock, StateBlock, &mut Block)> {
        let dynamic = self
            .dynamic
            .iter_mut()
            .zip(DYNAMIC_PAIRS)
            .map(|(block, (row, column))| (row, column, block));
        let gyro = self
            .dynamic_gyro_bias
            .iter_mut()
            .zip(DYNAMIC_ROWS)
            .map(|(block, row)| (row, GYRO_BIAS, block));
        let accel = self
            .dynamic_accel_bias
            .iter_mut()
            .zip(DYNAMIC_ROWS)
            .map(|(block, row)| (row, ACCEL_BIAS, block));
        dynamic.chain(gyro).chain(accel).chain([
            (GYRO_BIAS, GYRO_BIAS, &mut self.gyro_bias),
            (ACCEL_BIAS, ACCEL_BIAS, &mut self.accel_bias),
        ])
    }
}

impl StructuredModel {
    /// Discretises the error model at `point` over `interval_s` with a series of `order`
    /// terms (as `crate::discretise::discretise`, module docs for the block derivation).
    ///
    /// # Errors
    /// [`NavError::InvalidDiscretisationOrder`] for an order outside `1..=4`,
    /// [`NavError::InvalidTimeStep`] for a non-positive or non-finite interval,
    /// [`NavError::NonFiniteInput`] if the point or the noise densities hold NaN/Inf.
    pub fn new(
        point: &LinearisationPoint,
        noise: &ProcessNoise,
        interval_s: f64,
        order: u8,
    ) -> Result<Self, NavError> {
        let mut model = Self::EMPTY;
        model.rebuild(point, noise, interval_s, order)?;
        Ok(model)
    }

    /// A model with every block zero (no propagation), to be filled by
    /// [`StructuredModel::rebuild`].
    pub const EMPTY: Self = StructuredModel {
        transition: DynamicBlocks {
            attitude_attitude: ZERO,
            position_attitude: ZERO,
            position_position: ZERO,
            position_velocity: ZERO,
            velocity_attitude: ZERO,
            velocity_position: ZERO,
            velocity_velocity: ZERO,
        },
        gyro_bias_column: [ZERO; 3],
        accel_bias_column: [ZERO; 2],
        measured_rate_rad_s: [0.0; 3],
        measured_specific_force_mps2: [0.0; 3],
        input_noise: [0.0; 2],
        noise: NoiseBlocks::ZERO,
        bias_walk: false,
        noise_is_zero: true,
        powers: Powers::ZERO,
        interval_s: 0.0,
    };

    /// [`StructuredModel::new`] in place (the flight path keeps one model and refills it
    /// every propagation: the large model is never copied). On error the model is unchanged.
    ///
    /// # Errors
    /// As [`StructuredModel::new`].
    pub fn rebuild(
        &mut self,
        point: &LinearisationPoint,
        noise: &ProcessNoise,
        interval_s: f64,
        order: u8,
    ) -> Result<(), NavError> {
        let [gyro_noise, accel_noise, gyro_walk, accel_walk] =
            checked_intensities(point, noise, interval_s, order)?;
        let order = usize::from(order);
        let d = interval_s;
        self.interval_s = interval_s;
        let c = block::from_matrix(&point.body_to_inertial);
        self.powers.update(point, &c, d, order);
        self.powers.transition_into(
            &mut self.transition,
            &mut self.gyro_bias_column,
            &mut self.accel_bias_column,
            (order, d),
            &c,
        );
        let terms = SeriesTerms::of(&self.powers);
        self.measured_rate_rad_s = block::from_vector(&point.measured_rate_rad_s);
        self.measured_specific_force_mps2 = block::from_vector(&point.measured_specific_force_mps2);
        self.input_noise = [gyro_noise, accel_noise];
        // The walks' noise columns of Γ (module docs): [−½Δ² Χ_{·ϑ}; ΔI] and
        // [−Δ² Χ_{·v} Ĉ; ΔI] (Χ: shift 2).
        // Every noise block written once (no zero fill of them all first): the gyro walk
        // sets the dynamic blocks (or zeroes them), the accelerometer walk adds to them.
        // Without any walk the blocks are zeroed only if something made them non-zero.
        let noise = &mut self.noise;
        let squared = d * d;
        if gyro_walk > 0.0 || accel_walk > 0.0 {
            if gyro_walk > 0.0 {
                let mut columns = [ZERO; 3];
                terms.gyro_columns_into(&mut columns, order, 2, -0.5 * squared);
                noise.set_gyro_walk(gyro_walk, d, &columns);
            } else {
                noise.clear_gyro_walk();
            }
            if accel_walk > 0.0 {
                let mut columns = [ZERO; 2];
                terms.accel_columns_into(&mut columns, order, 2, -squared, &c);
                noise.add_accel_walk(accel_walk, d, &columns);
            } else {
                noise.clear_accel_walk();
            }
            self.noise_is_zero = false;
        } else if !self.noise_is_zero {
            *noise = NoiseBlocks::ZERO;
            self.noise_is_zero = true;
        }
        self.bias_walk = gyro_walk > 0.0 || accel_walk > 0.0;
        Ok(())
    }

    /// Adds the folded white-noise part of `Qd` (`q E_g E_gᵀ + q E_a E_aᵀ`, see
    /// [`StructuredModel::input_noise`]) to the explicit blocks, and clears the folded
    /// intensities: the model is unchanged, only its noise is held in the blocks.
    pub(super) fn unfold_input_noise(&mut self) {
        let [gyro_noise, accel_noise] = self.input_noise;
        if gyro_noise > 0.0 || accel_noise > 0.0 {
            self.noise_is_zero = false;
        }
        if gyro_noise > 0.0 {
            noise_input::<true>(&mut self.noise.dynamic, gyro_noise, &self.gyro_bias_column);
        }
        if accel_noise > 0.0 {
            add_accel_noise_input(
                &mut self.noise.dynamic,
                accel_noise,
                &self.accel_bias_column,
            );
        }
        self.input_noise = [0.0; 2];
    }

    /// Removes the process noise of the `blocks` (their rows and columns of `Qd` set to zero),
    /// as the flight scheduler does for frozen calibration blocks.
    pub fn remove_process_noise(&mut self, blocks: &BlockMask) {
        if blocks.is_empty() {
            return;
        }
        if DYNAMIC_ROWS.iter().any(|block| blocks.contains(*block)) {
            // The folded white noise reaches every dynamic row: hold it in the blocks.
            self.unfold_input_noise();
        }
        for (row, column, value) in self.noise.blocks_mut() {
            if blocks.contains(row) || blocks.contains(column) {
                *value = ZERO;
            }
        }
    }

    /// The interval `Δ` (s) the model discretises (0 for [`StructuredModel::EMPTY`]).
    pub fn interval_s(&self) -> f64 {
        self.interval_s
    }

    /// `ω_m` of the linearisation point (rad/s).
    pub(crate) fn measured_rate(&self) -> crate::block::Row {
        self.measured_rate_rad_s
    }

    /// `f_m` of the linearisation point (m/s²).
    pub(crate) fn measured_force(&self) -> crate::block::Row {
        self.measured_specific_force_mps2
    }

    /// The bias columns of `F`: `E_g` (rows ϑ, δp, δv) and `E_a` (rows δp, δv).
    pub(crate) fn bias_columns(&self) -> (&[Block; 3], &[Block; 2]) {
        (&self.gyro_bias_column, &self.accel_bias_column)
    }
}

/// The checks of [`StructuredModel::rebuild`]'s inputs, and the noise intensities `q/Δ` of
/// the gyro noise, accelerometer noise, gyro-bias walk and accelerometer-bias walk.
#[inline(always)]
fn checked_intensities(
    point: &LinearisationPoint,
    noise: &ProcessNoise,
    interval_s: f64,
    order: u8,
) -> Result<[f64; 4], NavError> {
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(NavError::InvalidDiscretisationOrder);
    }
    if !(interval_s.is_finite() && interval_s > 0.0) {
        return Err(NavError::InvalidTimeStep);
    }
    let mut check = FiniteCheck::new();
    for vector in [
        &point.corrected_rate_rad_s,
        &point.corrected_specific_force_mps2,
        &point.measured_rate_rad_s,
        &point.measured_specific_force_mps2,
    ] {
        for value in block::from_vector(vector) {
            check.value(value);
        }
    }
    check.block(&block::from_matrix(&point.body_to_inertial));
    check.block(&block::from_matrix(&point.gravity_gradient_per_s2));
    let density = |value: f64| value * value / interval_s;
    let intensities = [
        density(noise.gyro_noise_density_rad_s_per_sqrt_hz),
        density(noise.accel_noise_density_mps2_per_sqrt_hz),
        density(noise.gyro_bias_walk_rad_s2_per_sqrt_hz),
        density(noise.accel_bias_walk_mps3_per_sqrt_hz),
    ];
    for value in intensities {
        check.value(value);
    }
    if check.all_finite() {
        Ok(intensities)
    } else {
        Err(NavError::NonFiniteInput)
    }
}

/// The terms `(n, (MΔ)^n)` of each block's series (module docs table), by block of
/// [`DynamicBlocks`]; the velocity-velocity terms are the position-position ones.
struct SeriesTerms<'a> {
    attitude_attitude: [(usize, &'a Block); 5],
    position_attitude: [(usize, &'a Block); 3],
    position_position: [(usize, &'a Block); 3],
    position_velocity: [(usize, &'a Block); 2],
    velocity_attitude: [(usize, &'a Block); 4],
    velocity_position: [(usize, &'a Block); 2],
}

impl<'a> SeriesTerms<'a> {
    /// The terms over the powers `w`.
    #[inline(always)]
    fn of(w: &'a Powers) -> Self {
        SeriesTerms {
            attitude_attitude: [
                (0, &IDENTITY),
                (1, &w.a),
                (2, &w.a2),
                (3, &w.a3),
                (4, &w.a4),
            ],
            position_attitude: [(2, &w.d_b), (3, &w.d_ba), (4, &w.position_attitude_4)],
            position_position: [(0, &IDENTITY), (2, &w.dg), (4, &w.d2_g2)],
            position_velocity: [(1, &w.d_identity), (3, &w.d2_g)],
            velocity_attitude: [
                (1, &w.b),
                (2, &w.ba),
                (3, &w.velocity_attitude_3),
                (4, &w.velocity_attitude_4),
            ],
            velocity_position: [(1, &w.g), (3, &w.velocity_position_3)],
        }
    }

    /// `factor · Σ (MΔ)^n / (n + shift)!` over the attitude column (rows ϑ, δp, δv): the
    /// gyro-bias column of `F` (shift 1) or of the walk's `Γ` (shift 2).
    #[inline(always)]
    fn gyro_columns_into(&self, out: &mut [Block; 3], order: usize, shift: usize, factor: f64) {
        let [attitude, position, velocity] = out;
        series_into::<_, true>(attitude, &self.attitude_attitude, order, shift, factor);
        series_into::<_, false>(position, &self.position_attitude, order, shift, factor);
        series_into::<_, false>(velocity, &self.velocity_attitude, order, shift, factor);
    }

    /// `factor · Σ (MΔ)^n / (n + shift)! · Ĉ` over the velocity column (rows δp, δv): the
    /// accelerometer-bias column of `F` (shift 1) or of the walk's `Γ` (shift 2).
    #[inline(always)]
    fn accel_columns_into(
        &self,
        out: &mut [Block; 2],
        order: usize,
        shift: usize,
        factor: f64,
        c: &Block,
    ) {
        let mut psi = ZERO;
        let [position, velocity] = out;
        series_into::<_, true>(&mut psi, &self.position_velocity, order, shift, factor);
        *position = mul(&psi, c);
        series_into::<_, true>(&mut psi, &self.position_position, order, shift, factor);
        *velocity = mul(&psi, c);
    }
}

/// `Φ = Σ_{n=0..N} (MΔ)^n/n!` block by block.
#[inline(always)]
fn transition_into(t: &mut DynamicBlocks, terms: &SeriesTerms, order: usize) {
    series_into::<_, true>(
        &mut t.attitude_attitude,
        &terms.attitude_attitude,
        order,
        0,
        1.0,
    );
    series_into::<_, false>(
        &mut t.position_attitude,
        &terms.position_attitude,
        order,
        0,
        1.0,
    );
    series_into::<_, true>(
        &mut t.position_position,
        &terms.position_position,
        order,
        0,
        1.0,
    );
    series_into::<_, true>(
        &mut t.position_velocity,
        &terms.position_velocity,
        order,
        0,
        1.0,
    );
    series_into::<_, false>(
        &mut t.velocity_attitude,
        &terms.velocity_attitude,
        order,
        0,
        1.0,
    );
    series_into::<_, false>(
        &mut t.velocity_position,
        &terms.velocity_position,
        order,
        0,
        1.0,
    );
    series_into::<_, true>(
        &mut t.velocity_velocity,
        &terms.position_position,
        order,
        0,
        1.0,
    );
}
