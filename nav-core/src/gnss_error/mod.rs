//! Correlated GNSS position error: three first-order Gauss–Markov states `ε` (m, launch-
//! inertial axes) appended to the paper's 24, so that a receiver whose errors are correlated
//! over tens of seconds to hours (ephemeris, clock, ionosphere) does not make the filter
//! overconfident.
//!
//! ## Model
//! `ε̇ = −ε/τ + w`, stationary 1σ `σ` per axis: over an interval `Δ`,
//! `ε ← φ ε + w_d`, `φ = exp(−Δ/τ)`, `E[w_d w_dᵀ] = σ²(1 − φ²) I` (the exact discrete form).
//! The GNSS position residual gains `+ε`: `z = H_x x + h_ε ε + v` with `h_ε = 1`, or
//! `h_ε = exp(Δ_late/τ)` for a fix `Δ_late` old (`ε(t_m) = ε(t)/φ(Δ_late)`, the process noise
//! over the latency neglected as for `x`, `crate::measurement::refer_to_later_time`). Star
//! and velocity measurements have `h_ε = 0`. The receiver specifies `σ` and `τ` per ECEF
//! axis; an isotropic error keeps its covariance `σ² I` in any axes, and the Earth turns
//! 1.25° in 300 s, so the launch-inertial states carry the same model.
//!
//! ## The 27-state filter as a bordered 24-state filter
//! With `P = [[P_xx, C], [Cᵀ, P_εε]]` (`C = P_xε`, 24×3) the 24-state kernels stay as they
//! are and only the border is added:
//! * propagation: `P_xx ← F P_xx Fᵀ + Qd` (unchanged), `C ← φ F C`,
//!   `P_εε ← φ² P_εε + σ²(1 − φ²) I`, `ε̂ ← φ ε̂` (open and closed loop: `ε̂` is a receiver
//!   error, never fed back into the navigation solution);
//! * update (any gain, the Joseph form expanded as in [`crate::structured`]):
//!   `G = H_x C`, `M_x = P_xx H_xᵀ + h_ε C`, `M_ε = Gᵀ + h_ε P_εε`,
//!   `S = H_x P_xx H_xᵀ + h_ε (G + Gᵀ) + h_ε² P_εε + R`, `K = M S⁻¹` (frozen rows of `K_x`
//!   zero), `P⁺_ij = P_ij + N_i·K_j − K_i·M_j` with `N = K S − M` over all 27 rows, which
//!   for the `xx` block is the 24-state kernel fed with `M_x` and `S`;
//! * reset: `C ← J C` (the attitude and installation rows), `ε̂` kept.

use nalgebra::{Matrix3, SMatrix, Vector3};

#[cfg(feature = "gnss-error-states")]
use crate::block::{self, dot, row_add, row_scale, FiniteCheck, ZERO};
#[cfg(feature = "gnss-error-states")]
use crate::block::{Block, Row};
#[cfg(feature = "gnss-error-states")]
use crate::block_interface::MeasuredBorder;
#[cfg(feature = "gnss-error-states")]
use crate::measurement::MeasurementJacobian;
#[cfg(feature = "gnss-error-states")]
use crate::state::{BlockMask, DYNAMIC_DIMENSION as DYNAMIC_ROWS};
use crate::state::{OptionalBlock, BLOCK_DIMENSION, STATE_DIMENSION};
#[cfg(feature = "gnss-error-states")]
use crate::structured::{StateRows, StructuredModel};
use crate::NavError;

/// The layout's block: three states, one per axis, kept as 3-vectors and 3×3 blocks here.
const _: () = assert!(OptionalBlock::GnssError.dimension() == BLOCK_DIMENSION);

/// The receiver's correlated position-error specification (configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GnssErrorModel {
    /// Stationary 1σ per axis of the correlated position error (m); 0 = white errors only,
    /// the paper's 24-state model.
    pub sigma_m: f64,
    /// Correlation time `τ` (s); read only when `sigma_m > 0`.
    pub correlation_time_s: f64,
}

impl GnssErrorModel {
    /// White GNSS errors only (the paper's model): no correlated-error states.
    pub const WHITE: Self = Self {
        sigma_m: 0.0,
        correlation_time_s: 0.0,
    };

    /// Whether the correlated-error states are in use (`sigma_m > 0`).
    ///
    /// # Examples
    /// ```
    /// use nav_core::gnss_error::GnssErrorModel;
    /// assert!(!GnssErrorModel::WHITE.is_enabled());
    /// let receiver = GnssErrorModel { sigma_m: 8.0, correlation_time_s: 300.0 };
    /// assert!(receiver.is_enabled());
    /// ```
    pub fn is_enabled(&self) -> bool {
        self.sigma_m > 0.0
    }

    /// Checks the values: `sigma_m` finite and `≥ 0`; when it is `> 0`, `correlation_time_s`
    /// finite and `> 0` and the states compiled in (feature `gnss-error-states`).
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] otherwise.
    pub fn validate(&self) -> Result<(), NavError> {
        if self.is_enabled() && !OptionalBlock::GnssError.is_compiled() {
            return Err(NavError::InvalidConfiguration);
        }
        let sigma_ok = self.sigma_m.is_finite() && self.sigma_m >= 0.0;
        let tau_ok = self.correlation_time_s.is_finite() && self.correlation_time_s > 0.0;
        if sigma_ok && (!self.is_enabled() || tau_ok) {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// `φ = exp(−Δ/τ)` over `interval_s` (1 when the states are not in use).
    pub fn decay(&self, interval_s: f64) -> f64 {
        if self.is_enabled() {
            libm::exp(-interval_s / self.correlation_time_s)
        } else {
            1.0
        }
    }

    /// `h_ε` of a GNSS position fix `latency_s` old: `exp(latency/τ)` (module docs); 0 when
    /// the states are not in use.
    ///
    /// # Examples
    /// ```
    /// use nav_core::gnss_error::GnssErrorModel;
    /// let receiver = GnssErrorModel { sigma_m: 8.0, correlation_time_s: 300.0 };
    /// assert_eq!(receiver.position_coefficient(0.0).to_bits(), 1.0f64.to_bits());
    /// assert_eq!(GnssErrorModel::WHITE.position_coefficient(0.1).to_bits(), 0.0f64.to_bits());
    /// ```
    pub fn position_coefficient(&self, latency_s: f64) -> f64 {
        if self.is_enabled() {
            libm::exp(latency_s / self.correlation_time_s)
        } else {
            0.0
        }
    }
}

/// The border of the 27-state filter (module docs): `ε̂`, `P_εε` and `C = P_xε`.
#[cfg(feature = "gnss-error-states")]
#[derive(Debug, Clone, Copy)]
pub struct GnssErrorStates {
    model: GnssErrorModel,
    /// `ε̂` (m, launch-inertial axes).
    estimate: Row,
    /// `P_εε` (m²).
    covariance: Block,
    /// Two buffers of `C` (row `j`: `cov(x_j, ε)`): an update writes the new `C` into the
    /// inactive one and a commit makes it active, so nothing is copied and nothing changes
    /// if the update fails.
    buffers: [StateRows; 2],
    /// Whether `buffers[1]` holds `C`.
    second_active: bool,
    /// A prepared propagation's `P_εε` and `ε̂`, until it is committed (its `C` is in the
    /// inactive buffer).
    pending: (Block, Row),
    /// Whether the block is frozen: its gain rows are zero in every update, as a frozen core
    /// block's ([`GnssErrorStates::updated`]).
    frozen: bool,
}

#[cfg(feature = "gnss-error-states")]
impl PartialEq for GnssErrorStates {
    /// Equal model, `ε̂`, `P_εε` and `C` (whichever buffer holds it).
    fn eq(&self, other: &Self) -> bool {
        self.model == other.model
            && self.estimate == other.estimate
            && self.covariance == other.covariance
            && self.rows() == other.rows()
            && self.frozen == other.frozen
    }
}

#[cfg(feature = "gnss-error-states")]
impl GnssErrorStates {
    /// The prior: `ε̂ = 0`, `P_εε = σ² I`, `C = 0` (all zero when the model is white).
    ///
    /// # Errors
    /// As [`GnssErrorModel::validate`].
    pub fn new(model: GnssErrorModel) -> Result<Self, NavError> {
        model.validate()?;
        let mut states = Self::EMPTY;
        states.start(model);
        Ok(states)
    }

    /// Everything zero, the model white.
    const EMPTY: Self = Self {
        model: GnssErrorModel::WHITE,
        estimate: [0.0; 3],
        covariance: ZERO,
        buffers: [[[0.0; 3]; STATE_DIMENSION]; 2],
        second_active: false,
        pending: (ZERO, [0.0; 3]),
        frozen: false,
    };

    /// On [`Self::EMPTY`] states: the model and its prior `P_εε = σ² I`.
    fn start(&mut self, model: GnssErrorModel) {
        let variance = model.sigma_m * model.sigma_m;
        self.model = model;
        self.covariance = block::scale(&block::IDENTITY, variance);
    }

    /// The model.
    pub fn model(&self) -> &GnssErrorModel {
        &self.model
    }

    /// Whether the states are in use.
    pub fn is_enabled(&self) -> bool {
        self.model.is_enabled()
    }

    /// Whether the block is frozen (its gain rows zero in every update).
    pub fn is_frozen(&self) -> bool {
        self.frozen
    }

    /// `ε̂` (m, launch-inertial axes).
    pub fn estimate_m(&self) -> Vector3<f64> {
        Vector3::from(self.estimate)
    }

    /// `P_εε` (m²).
    pub fn covariance(&self) -> Matrix3<f64> {
        block::to_matrix(&self.covariance)
    }

    /// `C`, by rows.
    fn rows(&self) -> &StateRows {
        let [first, second] = &self.buffers;
        if self.second_active {
            second
        } else {
            first
        }
    }

    /// `C`, by rows, to change in place.
    fn rows_mut(&mut self) -> &mut StateRows {
        let [first, second] = &mut self.buffers;
        if self.second_active {
            second
        } else {
            first
        }
    }

    /// `C` = (the active buffer, the inactive one).
    fn rows_and_spare(&mut self) -> (&StateRows, &mut StateRows) {
        let [first, second] = &mut self.buffers;
        if self.second_active {
            (second, first)
        } else {
            (first, second)
        }
    }

    /// `C = P_xε` (24×3).
    pub fn cross_covariance(&self) -> SMatrix<f64, STATE_DIMENSION, 3> {
        SMatrix::from_fn(|row, column| {
            self.rows()
                .get(row)
                .and_then(|r| r.get(column))
                .copied()
                .unwrap_or(f64::NAN)
        })
    }

    /// `ε̂ ← φ ε̂`, `C ← φ F C`, `P_εε ← φ² P_εε + σ²(1 − φ²) I` (module docs), with
    /// `transition(c) = F c` for one 24-column. `false` (and nothing changed) if the result
    /// is not finite.
    #[cfg(any(test, feature = "dense-reference"))]
    pub(crate) fn propagate(
        &mut self,
        interval_s: f64,
        transition: impl Fn(&SMatrix<f64, STATE_DIMENSION, 1>) -> SMatrix<f64, STATE_DIMENSION, 1>,
    ) -> bool {
        if !self.is_enabled() {
            return true;
        }
        let phi = self.model.decay(interval_s);
        let columns: [SMatrix<f64, STATE_DIMENSION, 1>; 3] = core::array::from_fn(|a| {
            transition(&SMatrix::from_fn(|j, _| {
                self.rows()
                    .get(j)
                    .and_then(|r| r.get(a))
                    .copied()
                    .unwrap_or(f64::NAN)
            }))
        });
        let cross: StateRows = core::array::from_fn(|j| {
            let [c0, c1, c2] = columns
                .each_ref()
                .map(|c| c.get(j).copied().unwrap_or(f64::NAN));
            row_scale([c0, c1, c2], phi)
        });
        let variance = self.model.sigma_m * self.model.sigma_m;
        let walk = variance * (1.0 - phi * phi);
        let covariance = block::add(
            &block::scale(&self.covariance, phi * phi),
            &block::scale(&block::IDENTITY, walk),
        );
        let estimate = row_scale(self.estimate, phi);
        let mut check = FiniteCheck::new();
        check.block(&covariance);
        cross.iter().for_each(|row| check.row(row));
        check.row(&estimate);
        if !check.all_finite() {
            return false;
        }
        *self.rows_mut() = cross;
        self.covariance = covariance;
        self.estimate = estimate;
        true
    }

    /// The structured propagation (flight path), [`GnssErrorStates::propagate`] in two
    /// steps: the new `C = φ (F C + E X)` (`X` the optional `bias_inputs` of
    /// `StructuredModel::propagate_rows`: the IMU border's `M Bᵀ`), `P_εε` and `ε̂` into
    /// the inactive buffer and the pending values, written in place (nothing returned by
    /// value: every copy is a `memcpy` on the target, docs/guide/performance.md); `false` if not
    /// finite, nothing the filter reads changed. [`GnssErrorStates::commit_propagation`]
    /// makes them current.
    pub(crate) fn prepare_propagation(
        &mut self,
        model: &StructuredModel,
        bias_inputs: Option<&[Block; 2]>,
    ) -> bool {
        let phi = self.model.decay(model.interval_s());
        let variance = self.model.sigma_m * self.model.sigma_m;
        let covariance = block::add(
            &block::scale(&self.covariance, phi * phi),
            &block::scale(&block::IDENTITY, variance * (1.0 - phi * phi)),
        );
        let estimate = row_scale(self.estimate, phi);
        let mut check = FiniteCheck::new();
        check.block(&covariance);
        check.row(&estimate);
        check.value(phi);
        let (old, spare) = self.rows_and_spare();
        let dynamic = model.propagate_rows(old, bias_inputs);
        for (slot, row) in spare.iter_mut().zip(dynamic.iter().flatten()) {
            *slot = row_scale(*row, phi);
            check.row(slot);
        }
        for (slot, row) in spare.iter_mut().zip(old.iter()).skip(DYNAMIC_ROWS) {
            *slot = row_scale(*row, phi);
        }
        self.pending = (covariance, estimate);
        check.all_finite()
    }

    /// Makes the propagation prepared last current.
    pub(crate) fn commit_propagation(&mut self) {
        self.second_active = !self.second_active;
        (self.covariance, self.estimate) = self.pending;
    }

    /// The border's part of an update with Jacobian `H_x` and coefficient `h_ε` (module
    /// docs): `G = H_x C`, then `S`'s and `M_ε`'s terms; `observed` marks the 3×3 blocks of
    /// `H_x` that are not all zero (`crate::structured::observed_blocks`, found once per
    /// update). With `h_ε = 0` (a star or velocity measurement) the `S` term is not formed:
    /// it is zero, and the update does not read it then.
    pub(crate) fn border(
        &self,
        jacobian: &MeasurementJacobian,
        observed: &[bool; STATE_DIMENSION / 3],
        coefficient: f64,
    ) -> MeasuredBorder {
        // G = Σ_K H_K C_K over the 3×3 blocks K of H that are not all zero (a star or GNSS
        // measurement has two to five of the eight).
        let mut g = ZERO;
        let columns = jacobian
            .data
            .0
            .chunks_exact(3)
            .zip(self.rows().chunks_exact(3))
            .zip(observed);
        for ((h_columns, c_rows), _) in columns.filter(|(_, observed)| **observed) {
            for (h_column, c_row) in h_columns.iter().zip(c_rows) {
                for (g_row, h) in g.iter_mut().zip(h_column) {
                    *g_row = block::row_add_scaled(*g_row, *c_row, *h);
                }
            }
        }
        let g_transpose = block::transpose(&g);
        let projected = if coefficient == 0.0 {
            ZERO
        } else {
            block::add_scaled(
                &block::scale(&block::add(&g, &g_transpose), coefficient),
                &self.covariance,
                coefficient * coefficient,
            )
        };
        let products = block::add_scaled(&g_transpose, &self.covariance, coefficient);
        MeasuredBorder {
            coefficient,
            projected,
            products,
            frozen: self.frozen,
        }
    }

    /// `h_ε ε̂` (subtracted from the innovation).
    pub(crate) fn predicted_residual(&self, coefficient: f64) -> Vector3<f64> {
        Vector3::from(row_scale(self.estimate, coefficient))
    }

    /// The border after the update with gains `K_x` (`gains`, zero on the rows of the
    /// `frozen` blocks), `M_x` (`products`), `S⁻¹` (`solve`) and innovation `ν` (module
    /// docs): the new `C` (per element `C⁺_ia = C_ia + N_i·K_εa − K_i·M_εa`) into the spare
    /// buffer, which [`GnssErrorStates::commit`] makes active; the new `ε̂` and `P_εε`
    /// returned; `None` if anything is not finite (`C` unchanged).
    ///
    /// A frozen border has `K_ε = 0` and `N_ε = −M_ε`: `ε̂` and `P_εε` keep their values
    /// (`P⁺_ab = P_ab + N_a·K_b − K_a·M_b` with both gains zero), a moving core row takes
    /// `C_ia − K_i·M_εa` as before (`N_i = 0`) and a frozen one keeps `C_ia`, all of which
    /// the formulas below give with `K_ε = 0`.
    pub(crate) fn updated(
        &mut self,
        border: &MeasuredBorder,
        (gains, products, frozen): (&StateRows, &StateRows, &BlockMask),
        solve: impl Fn(Row) -> Row,
        innovation: Row,
    ) -> Option<(Row, Block)> {
        let [m0, m1, m2] = border.products;
        let k = if self.frozen {
            ZERO
        } else {
            [solve(m0), solve(m1), solve(m2)]
        };
        let cross_finite = self.update_cross(border, (gains, products, frozen), &k);
        let [k0, k1, k2] = k;
        let [[p00, p01, p02], [_, p11, p12], [_, _, p22]] = self.covariance;
        // Upper triangle, mirrored: exactly symmetric (frozen: `K_ε = 0`, nothing moves).
        let (q00, q01, q02) = (p00 - dot(k0, m0), p01 - dot(k0, m1), p02 - dot(k0, m2));
        let (q11, q12, q22) = (p11 - dot(k1, m1), p12 - dot(k1, m2), p22 - dot(k2, m2));
        let covariance = [[q00, q01, q02], [q01, q11, q12], [q02, q12, q22]];
        let estimate = row_add(
            self.estimate,
            [
                dot(k0, innovation),
                dot(k1, innovation),
                dot(k2, innovation),
            ],
        );
        let mut check = FiniteCheck::new();
        check.block(&covariance);
        check.row(&estimate);
        (cross_finite && check.all_finite()).then_some((estimate, covariance))
    }

    /// The new `C` of [`GnssErrorStates::updated`] into the spare buffer, with the border's
    /// gains `K_ε` (`border_gains`, rows `a`); whether every value is finite.
    ///
    /// The expanded Joseph form `P_ij + N_i·K_j − K_i·M_j` with `N_i = K_i S − M_i`:
    /// `K_i S = M_i` (to round-off) for every row the update moves, so `N_i = 0` there,
    /// and `N_i = −M_i` for a frozen row (`K_i = 0`); each element takes one product. The
    /// rows go by state blocks, so each block's three `M_ε` (or `K_ε`) rows stay in
    /// registers over its rows; the check is the sum of the new values, finite only if
    /// every one is (the exact check when it is not: a sum also overflows when large finite
    /// values add up).
    fn update_cross(
        &mut self,
        border: &MeasuredBorder,
        (gains, products, frozen): (&StateRows, &StateRows, &BlockMask),
        border_gains: &[Row; 3],
    ) -> bool {
        let (old_rows, cross) = self.rows_and_spare();
        let mut sum = 0.0;
        let blocks = cross
            .chunks_exact_mut(3)
            .zip(old_rows.chunks_exact(3))
            .zip(gains.chunks_exact(3).zip(products.chunks_exact(3)));
        for (block, ((new_rows, old), (k, m))) in blocks.enumerate() {
            let (left, [r0, r1, r2]) = if frozen.contains_state(3 * block) {
                (m, *border_gains)
            } else {
                (k, border.products)
            };
            for ((new, [c0, c1, c2]), left) in new_rows.iter_mut().zip(old).zip(left) {
                *new = [
                    c0 - dot(*left, r0),
                    c1 - dot(*left, r1),
                    c2 - dot(*left, r2),
                ];
                let [a, b, c] = *new;
                sum += a + b + c;
            }
        }
        sum.is_finite() || {
            let mut check = FiniteCheck::new();
            cross.iter().for_each(|row| check.row(row));
            check.all_finite()
        }
    }

    /// Replaces `ε̂`, `P_εε` and `C` (the dense reference update writes its result).
    #[cfg(any(test, feature = "dense-reference"))]
    pub(crate) fn set(
        &mut self,
        estimate: &Vector3<f64>,
        covariance: &Matrix3<f64>,
        cross: &SMatrix<f64, STATE_DIMENSION, 3>,
    ) {
        self.estimate = block::from_vector(estimate);
        self.covariance = block::from_matrix(covariance);
        *self.rows_mut() = core::array::from_fn(|j| {
            [0, 1, 2].map(|a| cross.get((j, a)).copied().unwrap_or(f64::NAN))
        });
    }

    /// Writes an update computed by [`GnssErrorStates::updated`]: its `ε̂` and `P_εε`, and
    /// its `C` made active.
    pub(crate) fn commit(&mut self, estimate: Row, covariance: &Block) {
        self.estimate = estimate;
        self.covariance = *covariance;
        self.second_active = !self.second_active;
    }

    /// [`GnssErrorStates::updated`] kept until [`GnssErrorStates::commit_update`]; `false`
    /// if a value is not finite (nothing changed but the spare buffer).
    pub(crate) fn prepare_update(
        &mut self,
        border: &MeasuredBorder,
        core: (&StateRows, &StateRows, &BlockMask),
        solve: impl Fn(Row) -> Row,
        innovation: Row,
    ) -> bool {
        match self.updated(border, core, solve, innovation) {
            Some((estimate, covariance)) => {
                self.pending = (covariance, estimate);
                true
            }
            None => false,
        }
    }

    /// Makes the update prepared last current.
    pub(crate) fn commit_update(&mut self) {
        let (covariance, estimate) = self.pending;
        self.commit(estimate, &covariance);
    }

    /// `C ← J C` for the reset Jacobian (attitude rows `J_ϑϑ`, installation rows `J_ψψ`,
    /// identity elsewhere).
    pub(crate) fn reset(&mut self, attitude: &Block, installation: &Block) {
        for (offset, jacobian) in [
            (crate::state::ATTITUDE.index(), attitude),
            (crate::state::STAR_INSTALLATION.index(), installation),
        ] {
            if let Some(rows) = self.rows_mut().get_mut(offset..offset + 3) {
                let old: Block = [0, 1, 2].map(|i| rows.get(i).copied().unwrap_or([0.0; 3]));
                let new = block::mul(jacobian, &old);
                for (row, value) in rows.iter_mut().zip(new) {
                    *row = value;
                }
            }
        }
    }

    /// Row `index` of `C` times `scale` (a variance ceiling scaled that state).
    pub(crate) fn scale_cross_row(&mut self, index: usize, scale: f64) {
        if let Some(row) = self.rows_mut().get_mut(index) {
            *row = row_scale(*row, scale);
        }
    }

    /// The variance floor and ceiling on `P_εε`'s diagonal, as the core's
    /// (`ErrorStateFilter::protect_variances`): a variance below its `floor` is raised to
    /// it; one above its `ceiling` becomes the ceiling, with the rest of its row and column
    /// (`P_εε` and `C`) multiplied by `s = √(ceiling/variance)`, `P' = S P S`, which keeps
    /// every correlation coefficient and positive definiteness. Returns whether anything
    /// changed and, when a ceiling was crossed, each state's `s` (1 within its ceiling), for
    /// the IMU border's `cov(ε_GNSS, ε)`. Only the diagonal is read unless a ceiling is
    /// crossed (the scaling is out of line: it never runs in a nominal flight).
    pub(crate) fn protect_variances(&mut self, floor: &Row, ceiling: &Row) -> (bool, Option<Row>) {
        let (clamped, crossing) =
            block::floor_and_mark_ceilings(&mut self.covariance, floor, ceiling);
        if crossing == 0 {
            return (clamped, None);
        }
        (true, Some(self.scale_to_ceilings(crossing, ceiling)))
    }

    /// `P' = S P S` for the states of `crossing` (bit `a`: state `a`), each with
    /// `s = √(ceiling/variance)`, on `P_εε` and `C`; each crossed diagonal then exactly its
    /// ceiling. Returns the scales.
    #[cold]
    #[inline(never)]
    fn scale_to_ceilings(&mut self, crossing: u16, ceiling: &Row) -> Row {
        let scales = block::scale_to_ceilings(&mut self.covariance, crossing, ceiling);
        let [s0, s1, s2] = scales;
        for row in self.rows_mut().iter_mut() {
            let [c0, c1, c2] = *row;
            *row = [c0 * s0, c1 * s1, c2 * s2];
        }
        scales
    }
}

/// The states compiled out (feature `gnss-error-states` off): no memory, the read accessors
/// of the real states, inert.
#[cfg(not(feature = "gnss-error-states"))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssErrorStates;

#[cfg(not(feature = "gnss-error-states"))]
impl GnssErrorStates {
    /// [`GnssErrorModel::WHITE`] only (the model's validation refuses any other).
    ///
    /// # Errors
    /// As [`GnssErrorModel::validate`].
    pub fn new(model: GnssErrorModel) -> Result<Self, NavError> {
        model.validate().map(|()| Self)
    }

    /// The model: [`GnssErrorModel::WHITE`].
    pub fn model(&self) -> &GnssErrorModel {
        &GnssErrorModel::WHITE
    }

    /// Never in use.
    pub fn is_enabled(&self) -> bool {
        false
    }

    /// Never frozen.
    pub fn is_frozen(&self) -> bool {
        false
    }

    /// Zero.
    pub fn estimate_m(&self) -> Vector3<f64> {
        Vector3::zeros()
    }

    /// Zero.
    pub fn covariance(&self) -> Matrix3<f64> {
        Matrix3::zeros()
    }

    /// Zero.
    pub fn cross_covariance(&self) -> SMatrix<f64, STATE_DIMENSION, 3> {
        SMatrix::zeros()
    }
}

mod interface;

#[cfg(all(test, feature = "gnss-error-states"))]
mod tests;
