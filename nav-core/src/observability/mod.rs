//! Observability analysis of the 24-state error model as a piece-wise constant system (PWCS),
//! paper Section 2 (see `docs/guide/model.md`, "Observability", and `docs/guide/observability.md`).
//!
//! ## Method
//! Each motion segment `j` is a constant system `(A_j, H)` (or `(F_j, H)` in discrete form).
//! Its observability matrix is `Q_j = [H; H A_j; …; H A_j^{n−1}]` (`n` = 24, 6 rows per power,
//! 144×24), and the stripped observability matrix of `r` segments (Goshen-Meskin &
//! Bar-Itzhack, IEEE TAES 28(4), 1992) is `Q_s(r) = [Q_1; …; Q_r]`. `Q_s` is never
//! materialised (144·r rows): [`StrippedObservability`] keeps only the 24×24 upper-triangular
//! factor `R` with `RᵀR = Q_sᵀQ_s`, updated one row at a time with Givens rotations (the
//! classic row-updating QR, numerically stable: orthogonal rotations never square the
//! condition number as forming `Q_sᵀQ_s` would). `Q_s` and `R` have the same singular values
//! and right singular vectors, so [`StrippedObservability::analyse`] takes the SVD of `R`.
//!
//! ## Scaling ([`Scaling`])
//! Raw `Q_s` mixes radians, metres and dimensionless scale factors over many decades, so the
//! SVD is taken of the scaled matrix `W Q_s S`, rows `W H (A τ)^k S`:
//! * `S = diag(s)`: states in units of a typical magnitude (`x = S x̃`); defaults
//!   [`Scaling::TYPICAL_STATE_MAGNITUDES`];
//! * `τ`: a time unit, the powers of `A` are taken of `A τ` (dimensionless); default 1 s;
//! * `W = diag(1/w)`: measurement rows in units of their noise (star vector-part noise
//!   10″/2, GNSS 10 m).
//!
//! Diagonal scaling never changes the rank nor *which* states are (un)observable (a state `k`
//! is unobservable iff some null vector has a non-zero `k`-th component, and the null space
//! of `W Q S` is `S⁻¹ null(Q)`), but it does change the singular values: the degrees reported
//! here are for the scaled problem, stated with the scaling. In discrete form `τ` is not used
//! (`F` is already per step) and the rows are `W H F^k S`.
//!
//! ## Observability degree ([`ObservabilityAnalysis`])
//! The singular-value method used in the paper (its ref. \[15\], the assignment popularised for
//! INS calibration analysis): for each singular value `σ_i` (descending), the state with the
//! largest absolute component of the right singular vector `v_i` is assigned `σ_i / σ_max`;
//! a state assigned several values keeps the largest, a state assigned none gets 0. This is a
//! heuristic (the null space can mix states); the per-state **null-space test** is exact:
//! with `N` the right singular vectors whose `σ ≤ tol`, a state is unobservable when the unit
//! vector `e_k` has `‖Nᵀ e_k‖ > 1e-6` (default, [`RankTolerance`]).
//!
//! ## Covariance measure ([`InformationAccumulator`])
//! A scale-free second opinion in the spirit of Ham & Brown ("Observability, eigenvalues,
//! and Kalman filtering", IEEE TAES 19(2), 1983): a Kalman filter without process noise over
//! the segments, in information form on the initial state, reporting per state
//! `prior variance / posterior variance` (≫ 1: learned from the measurements, ≈ 1: not).
//! Its square-root information matrix is accumulated with the same Givens update.
//!
//! ## Paper states and the flight helper
//! [`PaperMotionState`] holds the paper's motion states I, II, III (Table 1);
//! [`motion_observability`] answers, for the calibration manager at a phase change, which
//! blocks and axes a constant motion makes observable after a reference coast
//! ([`AxisObservability`]).

use nalgebra::{Matrix3, SMatrix, SVector, SymmetricEigen, Vector3, SVD};

use crate::error_model::SystemMatrix;
use crate::measurement::MeasurementJacobian;
use crate::state::{
    StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    MEASUREMENT_DIMENSION, POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::NavError;

mod motion;
pub use motion::{
    constant_motion, full_update_measurement_matrix, motion_observability,
    motion_observability_analysis, AxisObservability, PaperMotionState,
};

/// A 24-vector (one value per error state).
pub type StateVector = SVector<f64, STATE_DIMENSION>;
/// A 6-vector (one value per measurement row: star 3, GNSS 3).
pub type MeasurementVector = SVector<f64, MEASUREMENT_DIMENSION>;
/// The 6×24 measurement matrix of a full update: star-sensor rows 0-2, GNSS rows 3-5.
pub type MeasurementMatrix = SMatrix<f64, MEASUREMENT_DIMENSION, STATE_DIMENSION>;
/// Rows of one segment's observability matrix: 6 per power, powers 0..=23.
pub const SEGMENT_ROWS: usize = MEASUREMENT_DIMENSION * STATE_DIMENSION;
/// One segment's (scaled) observability matrix `Q_j`, 144×24 (too large for the flight stack: host/analysis use).
pub type SegmentObservabilityMatrix = SMatrix<f64, SEGMENT_ROWS, STATE_DIMENSION>;
/// Upper-triangular 24×24 factor `R` with `RᵀR = Q_sᵀQ_s`.
pub type TriangularFactor = SMatrix<f64, STATE_DIMENSION, STATE_DIMENSION>;

/// Largest number of measurement epochs one [`InformationAccumulator::add_segment`] accepts
/// (keeps every loop bounded by a constant).
pub const MAX_MEASUREMENTS_PER_SEGMENT: u32 = 1_000_000;

/// SVD convergence: relative epsilon and iteration cap for `nalgebra::SVD::try_new`.
const SVD_EPSILON: f64 = 1.0e-15;
/// SVD iteration cap.
const SVD_MAX_ITERATIONS: usize = 10_000;

/// Stacks the star-sensor block (rows 0-2) and the GNSS block (rows 3-5) into one `H`.
pub fn stack_measurements(
    star: &MeasurementJacobian,
    gnss: &MeasurementJacobian,
) -> MeasurementMatrix {
    let mut h = MeasurementMatrix::zeros();
    h.fixed_view_mut::<3, STATE_DIMENSION>(0, 0).copy_from(star);
    h.fixed_view_mut::<3, STATE_DIMENSION>(3, 0).copy_from(gnss);
    h
}

/// Scaling of states, measurements and time (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaling {
    /// Typical magnitude of each state (`S = diag`), in the state's units. All > 0.
    pub state_magnitudes: StateVector,
    /// Typical magnitude of each measurement row (`W = diag(1/w)`). All > 0.
    pub measurement_magnitudes: MeasurementVector,
    /// Time unit `τ` (s): continuous powers are of `A τ`. > 0.
    pub time_unit_s: f64,
}

impl Scaling {
    /// Default typical state magnitudes per block: attitude 1e-3, position 10 m, velocity
    /// 0.1 m/s, gyro bias 1e-5 rad/s, accelerometer bias 1e-3 m/s², installation 1e-3,
    /// gyro and accelerometer scale factors 1e-5.
    pub const TYPICAL_STATE_MAGNITUDES: [(StateBlock, f64); 8] = [
        (ATTITUDE, 1.0e-3),
        (POSITION, 10.0),
        (VELOCITY, 0.1),
        (GYRO_BIAS, 1.0e-5),
        (ACCEL_BIAS, 1.0e-3),
        (STAR_INSTALLATION, 1.0e-3),
        (GYRO_SCALE_FACTOR, 1.0e-5),
        (ACCEL_SCALE_FACTOR, 1.0e-5),
    ];
    /// Default star-sensor row magnitude: vector-part noise of a 10″ sensor, 10″/2 (rad).
    pub const STAR_ROW_MAGNITUDE: f64 = 0.5 * 10.0 / 3600.0 * core::f64::consts::PI / 180.0;
    /// Default GNSS row magnitude (m).
    pub const GNSS_ROW_MAGNITUDE: f64 = 10.0;

    /// Scaling from per-block state magnitudes, star/GNSS row magnitudes and `τ`.
    pub fn from_blocks(
        blocks: &[(StateBlock, f64); 8],
        star_row_magnitude: f64,
        gnss_row_magnitude: f64,
        time_unit_s: f64,
    ) -> Self {
        let mut state_magnitudes = StateVector::zeros();
        for (block, magnitude) in blocks {
            state_magnitudes
                .fixed_view_mut::<3, 1>(block.index(), 0)
                .fill(*magnitude);
        }
        let mut measurement_magnitudes = MeasurementVector::zeros();
        measurement_magnitudes
            .fixed_view_mut::<3, 1>(0, 0)
            .fill(star_row_magnitude);
        measurement_magnitudes
            .fixed_view_mut::<3, 1>(3, 0)
            .fill(gnss_row_magnitude);
        Self {
            state_magnitudes,
            measurement_magnitudes,
            time_unit_s,
        }
    }

    /// The default scaling (typical magnitudes, noise-scaled rows, `τ` = 1 s).
    pub fn typical() -> Self {
        Self::from_blocks(
            &Self::TYPICAL_STATE_MAGNITUDES,
            Self::STAR_ROW_MAGNITUDE,
            Self::GNSS_ROW_MAGNITUDE,
            1.0,
        )
    }

    /// No scaling at all (`S = I`, `W = I`, `τ` = 1 s): the paper's raw matrix.
    pub fn unscaled() -> Self {
        Self {
            state_magnitudes: StateVector::repeat(1.0),
            measurement_magnitudes: MeasurementVector::repeat(1.0),
            time_unit_s: 1.0,
        }
    }

    /// True when every magnitude and `τ` is finite and strictly positive.
    pub fn is_valid(&self) -> bool {
        let positive = |v: &f64| v.is_finite() && *v > 0.0;
        self.state_magnitudes.iter().all(positive)
            && self.measurement_magnitudes.iter().all(positive)
            && positive(&self.time_unit_s)
    }

    /// Scaled measurement matrix `W H S`.
    fn scale_measurement(&self, h: &MeasurementMatrix) -> MeasurementMatrix {
        let mut scaled = *h;
        for (mut row, magnitude) in scaled
            .row_iter_mut()
            .zip(self.measurement_magnitudes.iter())
        {
            row /= *magnitude;
        }
        for (mut column, magnitude) in scaled.column_iter_mut().zip(self.state_magnitudes.iter()) {
            column *= *magnitude;
        }
        scaled
    }

    /// Scaled transition `S⁻¹ M S · factor`.
    fn scale_system(&self, m: &SystemMatrix, factor: f64) -> SystemMatrix {
        let mut scaled = *m * factor;
        for (mut row, magnitude) in scaled.row_iter_mut().zip(self.state_magnitudes.iter()) {
            row /= *magnitude;
        }
        for (mut column, magnitude) in scaled.column_iter_mut().zip(self.state_magnitudes.iter()) {
            column *= *magnitude;
        }
        scaled
    }
}

impl Default for Scaling {
    fn default() -> Self {
        Self::typical()
    }
}

/// Whether a segment is given by its continuous `A` or its discrete `F`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SystemForm {
    /// `Q_j = [H; H Aτ; …; H (Aτ)^{23}]`.
    Continuous,
    /// `Q_j = [H; H F; …; H F^{23}]`.
    Discrete,
}

fn all_finite<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> bool {
    m.iter().all(|v| v.is_finite())
}

/// Rotates the row `row` into the upper-triangular `factor_transposed` (stored transposed, so
/// row `j` of `R` is column `j`), zeroing `row`. Non-finite input is the caller's check.
fn givens_add_row(factor_transposed: &mut TriangularFactor, row: &StateVector) {
    let mut x = *row;
    for (j, mut column) in factor_transposed.column_iter_mut().enumerate() {
        let (Some(&a), Some(&b)) = (column.get(j), x.get(j)) else {
            continue;
        };
        if b == 0.0 {
            continue;
        }
        let rho = libm::hypot(a, b);
        let (c, s) = (a / rho, b / rho);
        for (r_k, x_k) in column.iter_mut().zip(x.iter_mut()).skip(j) {
            let (r_old, x_old) = (*r_k, *x_k);
            *r_k = c * r_old + s * x_old;
            *x_k = c * x_old - s * r_old;
        }
    }
}

/// Builds the scaled per-power generator: `(W H S, S⁻¹ M S)` with `M = Aτ` or `F`.
fn scaled_pair(
    scaling: &Scaling,
    system: &SystemMatrix,
    h: &MeasurementMatrix,
    form: SystemForm,
) -> Result<(MeasurementMatrix, SystemMatrix), NavError> {
    if !scaling.is_valid() {
        return Err(NavError::InvalidConfiguration);
    }
    if !(all_finite(system) && all_finite(h)) {
        return Err(NavError::NonFiniteInput);
    }
    let factor = match form {
        SystemForm::Continuous => scaling.time_unit_s,
        SystemForm::Discrete => 1.0,
    };
    Ok((
        scaling.scale_measurement(h),
        scaling.scale_system(system, factor),
    ))
}

/// One segment's scaled observability matrix `W Q_j S` (144×24; module docs). For the
/// analysis of several segments use [`StrippedObservability`], which never forms it.
///
/// # Errors
/// [`NavError::InvalidConfiguration`] for an invalid scaling, [`NavError::NonFiniteInput`]
/// for NaN/Inf in `system` or `h`.
pub fn segment_observability_matrix(
    system: &SystemMatrix,
    h: &MeasurementMatrix,
    form: SystemForm,
    scaling: &Scaling,
) -> Result<SegmentObservabilityMatrix, NavError> {
    let (mut block, step) = scaled_pair(scaling, system, h, form)?;
    let mut q = SegmentObservabilityMatrix::zeros();
    for power in 0..STATE_DIMENSION {
        q.fixed_view_mut::<MEASUREMENT_DIMENSION, STATE_DIMENSION>(
            power * MEASUREMENT_DIMENSION,
            0,
        )
        .copy_from(&block);
        block *= step;
    }
    Ok(q)
}

/// Tolerances of the rank and null-space decisions.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RankTolerance {
    /// `σ_i ≤ relative · σ_max` counts as zero (rank, null space). Default 1e-12: about
    /// 1e4 × machine epsilon, above the round-off of the Givens accumulation and the SVD.
    pub relative: f64,
    /// The paper's absolute threshold: `σ_i < 5e-8` is "unobservable" (meaningful for the
    /// paper's unscaled discrete matrix only; reported as a second count).
    pub absolute: f64,
    /// Null-space projection `‖Nᵀ e_k‖` above which state `k` is unobservable. Default 1e-6.
    pub projection: f64,
}

impl RankTolerance {
    /// The defaults documented on the fields.
    pub const DEFAULT: RankTolerance = RankTolerance {
        relative: 1.0e-12,
        absolute: 5.0e-8,
        projection: 1.0e-6,
    };
}

impl Default for RankTolerance {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Result of the SVD of the stripped observability matrix (in scaled coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObservabilityAnalysis {
    /// Singular values, descending.
    pub singular_values: StateVector,
    /// Right singular vectors, column `i` belongs to `singular_values[i]`.
    pub right_singular_vectors: SystemMatrix,
    /// Number of singular values above `relative · σ_max`.
    pub rank: usize,
    /// Number of singular values above the paper's absolute threshold.
    pub rank_absolute: usize,
    /// The zero threshold actually used, `relative · σ_max`.
    pub zero_threshold: f64,
    /// Singular value assigned to each state (largest-component rule), raw.
    pub assigned_singular_value: StateVector,
    /// Observability degree per state: assigned singular value / `σ_max` (0 if none).
    pub degree: StateVector,
    /// `‖Nᵀ e_k‖`: norm of state `k`'s unit vector projected on the numerical null space.
    pub null_space_projection: StateVector,
    /// Per state: `null_space_projection ≤ projection tolerance`.
    pub observable: [bool; STATE_DIMENSION],
}

impl ObservabilityAnalysis {
    /// Number of states that pass the null-space test.
    pub fn observable_count(&self) -> usize {
        self.observable.iter().filter(|o| **o).count()
    }

    /// Whether every state of `block` passes the null-space test.
    pub fn block_observable(&self, block: StateBlock) -> [bool; 3] {
        let mut out = [false; 3];
        for (flag, observable) in out
            .iter_mut()
            .zip(self.observable.iter().skip(block.index()))
        {
            *flag = *observable;
        }
        out
    }

    /// Number of independent observable directions inside `block` (0..=3): linear
    /// combinations `uᵀ x_block` that are observable although the single states may not be.
    ///
    /// Derivation: a combination `u` (a 24-vector supported on the block) is observable iff it
    /// lies in the row space of the observability matrix, i.e. `Nᵀu = 0` for the null-space
    /// basis `N` (right singular vectors with `σ ≤` [`Self::zero_threshold`]). With `N_b` the
    /// block's three rows of `N`, the observable directions are the null space of
    /// `P_b = N_b N_bᵀ` (3×3, eigenvalues in [0, 1]); an eigenvalue counts as zero when it is
    /// ≤ `tolerance.projection²`, the per-state test's threshold squared. Example: a rotation
    /// about one body axis leaves the installation error about that axis (in sensor axes a
    /// mix of all three) inseparable from the attitude error, so no single installation state
    /// is observable, yet two installation directions are.
    ///
    /// # Errors
    /// [`NavError::SingularMatrix`] if the 3×3 eigen-decomposition does not converge.
    pub fn observable_directions(
        &self,
        block: StateBlock,
        tolerance: &RankTolerance,
    ) -> Result<usize, NavError> {
        let mut projection = Matrix3::<f64>::zeros();
        let null_columns = self
            .right_singular_vectors
            .column_iter()
            .zip(self.singular_values.iter())
            .filter(|(_, sigma)| **sigma <= self.zero_threshold);
        for (column, _) in null_columns {
            let mut part = Vector3::<f64>::zeros();
            for (value, component) in part.iter_mut().zip(column.iter().skip(block.index())) {
                *value = *component;
            }
            projection += part * part.transpose();
        }
        let eigen = SymmetricEigen::try_new(projection, SVD_EPSILON, SVD_MAX_ITERATIONS)
            .ok_or(NavError::SingularMatrix)?;
        let zero = tolerance.projection * tolerance.projection;
        Ok(eigen
            .eigenvalues
            .iter()
            .filter(|value| **value <= zero)
            .count())
    }
}

/// Accumulates the triangular factor of the stripped observability matrix of a PWCS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrippedObservability {
    /// `Rᵀ` (lower triangular; column `j` = row `j` of `R`).
    factor_transposed: TriangularFactor,
    scaling: Scaling,
    segments: u32,
}

impl StrippedObservability {
    /// An empty accumulator (`R = 0`) with the given scaling.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] when the scaling is not finite and positive.
    pub fn new(scaling: Scaling) -> Result<Self, NavError> {
        if !scaling.is_valid() {
            return Err(NavError::InvalidConfiguration);
        }
        Ok(Self {
            factor_transposed: TriangularFactor::zeros(),
            scaling,
            segments: 0,
        })
    }

    /// The scaling in use (report it with the results).
    pub fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    /// Number of segments added.
    pub fn segments(&self) -> u32 {
        self.segments
    }

    /// The upper-triangular factor `R` (`RᵀR = Q_sᵀ Q_s`, scaled).
    pub fn factor(&self) -> TriangularFactor {
        self.factor_transposed.transpose()
    }

    /// Appends segment `Q_j` (rows `W H M^k S`, k = 0..23, `M = Aτ` or `F`), row by row.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for NaN/Inf in the inputs or if the powers overflow
    /// (then the accumulator is left unchanged).
    pub fn add_segment(
        &mut self,
        system: &SystemMatrix,
        h: &MeasurementMatrix,
        form: SystemForm,
    ) -> Result<(), NavError> {
        let (mut block, step) = scaled_pair(&self.scaling, system, h, form)?;
        let mut updated = self.factor_transposed;
        for _ in 0..STATE_DIMENSION {
            if !all_finite(&block) {
                return Err(NavError::NonFiniteInput);
            }
            for row in block.row_iter() {
                givens_add_row(&mut updated, &row.transpose());
            }
            block *= step;
        }
        if !all_finite(&updated) {
            return Err(NavError::NonFiniteInput);
        }
        self.factor_transposed = updated;
        self.segments = self.segments.saturating_add(1);
        Ok(())
    }

    /// SVD of `R` and the per-state results (module docs).
    ///
    /// # Errors
    /// [`NavError::SingularMatrix`] if the SVD does not converge, [`NavError::NonFiniteState`]
    /// if it yields non-finite values.
    pub fn analyse(&self, tolerance: &RankTolerance) -> Result<ObservabilityAnalysis, NavError> {
        analyse_factor(&self.factor(), tolerance)
    }
}

/// SVD of a (triangular) factor and the per-state degree and null-space test.
///
/// # Errors
/// As [`StrippedObservability::analyse`].
pub fn analyse_factor(
    factor: &TriangularFactor,
    tolerance: &RankTolerance,
) -> Result<ObservabilityAnalysis, NavError> {
    let svd = SVD::try_new(*factor, false, true, SVD_EPSILON, SVD_MAX_ITERATIONS)
        .ok_or(NavError::SingularMatrix)?;
    let v_t = svd.v_t.ok_or(NavError::SingularMatrix)?;
    let singular_values = svd.singular_values;
    if !(all_finite(&v_t) && all_finite(&singular_values)) {
        return Err(NavError::NonFiniteState);
    }
    let right_singular_vectors = v_t.transpose();
    let sigma_max = singular_values.iter().copied().fold(0.0_f64, f64::max);
    let zero_threshold = tolerance.relative * sigma_max;
    let rank = singular_values
        .iter()
        .filter(|s| **s > zero_threshold)
        .count();
    let rank_absolute = singular_values
        .iter()
        .filter(|s| **s >= tolerance.absolute)
        .count();

    let mut assigned_singular_value = StateVector::zeros();
    let mut assigned = [false; STATE_DIMENSION];
    let mut null_square = StateVector::zeros();
    for (sigma, vector) in singular_values
        .iter()
        .zip(right_singular_vectors.column_iter())
    {
        // Largest absolute component (first one on ties).
        let mut best = (0usize, -1.0_f64);
        for (k, component) in vector.iter().enumerate() {
            if component.abs() > best.1 {
                best = (k, component.abs());
            }
        }
        if let (Some(flag), Some(value)) = (
            assigned.get_mut(best.0),
            assigned_singular_value.get_mut(best.0),
        ) {
            // Singular values come in descending order: the first assignment is the largest.
            if !*flag {
                *flag = true;
                *value = *sigma;
            }
        }
        if *sigma <= zero_threshold {
            for (square, component) in null_square.iter_mut().zip(vector.iter()) {
                *square += component * component;
            }
        }
    }
    let degree = if sigma_max > 0.0 {
        assigned_singular_value / sigma_max
    } else {
        StateVector::zeros()
    };
    let null_space_projection = null_square.map(crate::float::sqrt);
    let mut observable = [false; STATE_DIMENSION];
    for (flag, projection) in observable.iter_mut().zip(null_space_projection.iter()) {
        *flag = *projection <= tolerance.projection;
    }
    Ok(ObservabilityAnalysis {
        singular_values,
        right_singular_vectors,
        rank,
        rank_absolute,
        zero_threshold,
        assigned_singular_value,
        degree,
        null_space_projection,
        observable,
    })
}

/// Square-root information accumulation of a Kalman filter without process noise, on the
/// initial state, in prior-normalised coordinates `x = diag(σ₀) x̃` (so the prior information
/// is `I` and the factor starts as `I`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InformationAccumulator {
    /// `Rᵀ` of the normalised information `RᵀR = I + Σ (W H Φ_k S₀)ᵀ(W H Φ_k S₀)`.
    factor_transposed: TriangularFactor,
    prior_sigma: StateVector,
    /// Transition from the initial state to the current epoch, `Φ`.
    transition: SystemMatrix,
}

impl InformationAccumulator {
    /// Starts from a diagonal prior with standard deviations `prior_sigma` (all > 0).
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a non-finite or non-positive sigma.
    pub fn new(prior_sigma: &StateVector) -> Result<Self, NavError> {
        if !prior_sigma.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(NavError::InvalidConfiguration);
        }
        Ok(Self {
            factor_transposed: TriangularFactor::identity(),
            prior_sigma: *prior_sigma,
            transition: SystemMatrix::identity(),
        })
    }

    /// `measurements` epochs of a segment: before each, the state moves by `transition`
    /// (`F` over one measurement interval), then `h` is observed with 1σ `measurement_sigma`.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for non-positive sigmas or more than
    /// [`MAX_MEASUREMENTS_PER_SEGMENT`] epochs; [`NavError::NonFiniteInput`] for NaN/Inf
    /// (the accumulator is then left unchanged).
    pub fn add_segment(
        &mut self,
        transition: &SystemMatrix,
        h: &MeasurementMatrix,
        measurement_sigma: &MeasurementVector,
        measurements: u32,
    ) -> Result<(), NavError> {
        if measurements > MAX_MEASUREMENTS_PER_SEGMENT
            || !measurement_sigma.iter().all(|s| s.is_finite() && *s > 0.0)
        {
            return Err(NavError::InvalidConfiguration);
        }
        if !(all_finite(transition) && all_finite(h)) {
            return Err(NavError::NonFiniteInput);
        }
        let mut weighted = *h;
        for (mut row, sigma) in weighted.row_iter_mut().zip(measurement_sigma.iter()) {
            row /= *sigma;
        }
        let mut factor = self.factor_transposed;
        let mut phi = self.transition;
        for _ in 0..measurements {
            phi = transition * phi;
            let mut rows = weighted * phi;
            for (mut column, sigma) in rows.column_iter_mut().zip(self.prior_sigma.iter()) {
                column *= *sigma;
            }
            if !all_finite(&rows) {
                return Err(NavError::NonFiniteInput);
            }
            for row in rows.row_iter() {
                givens_add_row(&mut factor, &row.transpose());
            }
        }
        self.factor_transposed = factor;
        self.transition = phi;
        Ok(())
    }

    /// Per state `prior variance / posterior variance` of the initial state (≥ 1).
    ///
    /// # Errors
    /// [`NavError::SingularMatrix`] if the factor cannot be inverted (cannot happen with a
    /// finite prior unless round-off destroyed it).
    pub fn variance_ratios(&self) -> Result<StateVector, NavError> {
        let factor = self.factor_transposed.transpose();
        let inverse = factor
            .solve_upper_triangular(&TriangularFactor::identity())
            .ok_or(NavError::SingularMatrix)?;
        // Normalised posterior P̃ = R⁻¹R⁻ᵀ, P̃_kk = ‖row k of R⁻¹‖², prior variance 1.
        let mut ratios = StateVector::zeros();
        for (ratio, row) in ratios.iter_mut().zip(inverse.row_iter()) {
            let posterior = row.norm_squared();
            if !(posterior.is_finite() && posterior > 0.0) {
                return Err(NavError::SingularMatrix);
            }
            *ratio = 1.0 / posterior;
        }
        Ok(ratios)
    }
}

#[cfg(test)]
mod tests;
