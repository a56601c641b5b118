//! Observability analysis of the 24-state error model as a piece-wise constant system (PWCS),
//! paper Section 2 (see `docs/model.md`, "Observability", and `docs/observability.md`).
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

use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, SymmetricEigen, Vector3, SVD};

use crate::error_model::{system_matrix, LinearisationPoint, SystemMatrix};
use crate::measurement::{gnss_position, star_sensor, MeasurementJacobian};
use crate::state::{
    StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR,
    MEASUREMENT_DIMENSION, POSITION, STAR_INSTALLATION, STATE_DIMENSION, VELOCITY,
};
use crate::NavError;

/// A 24-vector (one value per error state).
pub type StateVector = SVector<f64, STATE_DIMENSION>;
/// A 6-vector (one value per measurement row: star 3, GNSS 3).
pub type MeasurementVector = SVector<f64, MEASUREMENT_DIMENSION>;
/// The 6×24 measurement matrix of a full update: star-sensor rows 0-2, GNSS rows 3-5.
pub type MeasurementMatrix = SMatrix<f64, MEASUREMENT_DIMENSION, STATE_DIMENSION>;
/// Rows of one segment's observability matrix: 6 per power, powers 0..=23.
pub const SEGMENT_ROWS: usize = MEASUREMENT_DIMENSION * STATE_DIMENSION;
/// One segment's (scaled) observability matrix `Q_j`, 144×24 (27.6 kB: host/analysis use).
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
    let null_space_projection = null_square.map(libm::sqrt);
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

/// Degrees to radians (for the paper's rates, given in °/s).
const RADIANS_PER_DEGREE: f64 = core::f64::consts::PI / 180.0;

/// The paper's three motion states of Table 1 (Section 2.3): the constant motions whose
/// observability the paper tabulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PaperMotionState {
    /// State I, unpowered coast: body rate 2.4e-4 °/s about every axis, no specific force.
    Coast,
    /// State II, attitude manoeuvre: body rate (0, 0, 10) °/s, no specific force.
    Rotation,
    /// State III, linear acceleration: specific force (0, 20, 0) m/s², no rotation.
    Acceleration,
}

impl PaperMotionState {
    /// The three states in the paper's order (Table 1 columns I, II, III).
    pub const ALL: [PaperMotionState; 3] = [Self::Coast, Self::Rotation, Self::Acceleration];
    /// State I's rate about each axis (°/s).
    pub const COAST_RATE_DEG_PER_S: f64 = 2.4e-4;
    /// State II's rate about body z (°/s).
    pub const ROTATION_RATE_DEG_PER_S: f64 = 10.0;
    /// State III's specific force along body y (m/s²).
    pub const ACCELERATION_MPS2: f64 = 20.0;

    /// The paper's label: "I", "II" or "III".
    pub fn label(self) -> &'static str {
        match self {
            Self::Coast => "I",
            Self::Rotation => "II",
            Self::Acceleration => "III",
        }
    }

    /// Body rate of the state (rad/s).
    pub fn body_rate_rad_s(self) -> Vector3<f64> {
        match self {
            Self::Coast => Vector3::repeat(Self::COAST_RATE_DEG_PER_S * RADIANS_PER_DEGREE),
            Self::Rotation => {
                Vector3::new(0.0, 0.0, Self::ROTATION_RATE_DEG_PER_S * RADIANS_PER_DEGREE)
            }
            Self::Acceleration => Vector3::zeros(),
        }
    }

    /// Specific force of the state (m/s²).
    pub fn specific_force_mps2(self) -> Vector3<f64> {
        match self {
            Self::Acceleration => Vector3::new(0.0, Self::ACCELERATION_MPS2, 0.0),
            Self::Coast | Self::Rotation => Vector3::zeros(),
        }
    }

    /// The linearisation point of this state at attitude `body_to_inertial` ([`constant_motion`]).
    pub fn linearisation_point(self, body_to_inertial: &Matrix3<f64>) -> LinearisationPoint {
        constant_motion(
            &self.body_rate_rad_s(),
            &self.specific_force_mps2(),
            body_to_inertial,
        )
    }
}

/// A constant-motion segment of the PWCS as the paper analyses it: measured = corrected rate
/// and specific force (the estimated sensor errors are zero at the start of an analysis),
/// attitude frozen at `body_to_inertial` (`Ĉ`, body to launch-inertial), gravity gradient zero
/// (paper eq. 14 ignores the gravity error).
pub fn constant_motion(
    body_rate_rad_s: &Vector3<f64>,
    specific_force_mps2: &Vector3<f64>,
    body_to_inertial: &Matrix3<f64>,
) -> LinearisationPoint {
    LinearisationPoint {
        corrected_rate_rad_s: *body_rate_rad_s,
        corrected_specific_force_mps2: *specific_force_mps2,
        measured_rate_rad_s: *body_rate_rad_s,
        measured_specific_force_mps2: *specific_force_mps2,
        body_to_inertial: *body_to_inertial,
        gravity_gradient_per_s2: Matrix3::zeros(),
    }
}

/// `H` of a full update (star rows 0-2, GNSS rows 3-5) at attitude `q̂_ib` with the nominal
/// star-sensor mounting `q_bs`, a zero installation estimate and a zero GNSS lever arm (the
/// paper has none): the blocks of [`star_sensor`] and [`gnss_position`], stacked.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in a quaternion.
pub fn full_update_measurement_matrix(
    attitude: &Quaternion<f64>,
    mounting: &Quaternion<f64>,
) -> Result<MeasurementMatrix, NavError> {
    let identity = Quaternion::identity();
    let star = star_sensor(attitude, mounting, &identity, &identity, 0.0)?;
    let zero = Vector3::zeros();
    let gnss = gnss_position(attitude, &zero, &zero, &zero, 0.0)?;
    Ok(stack_measurements(&star.jacobian, &gnss.jacobian))
}

/// Per block (the eight blocks of [`StateBlock::ALL`], in order) and per axis: whether the state passes
/// the null-space test. The flight calibration manager's view of an [`ObservabilityAnalysis`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisObservability {
    /// `axes[b][k]`: state `k` (x, y, z) of block `StateBlock::ALL[b]` is observable.
    pub axes: [[bool; 3]; 8],
}

impl AxisObservability {
    /// Regroups the per-state flags of `analysis` by block.
    pub fn from_analysis(analysis: &ObservabilityAnalysis) -> Self {
        let mut axes = [[false; 3]; 8];
        for (block, states) in axes.iter_mut().zip(analysis.observable.chunks_exact(3)) {
            for (flag, observable) in block.iter_mut().zip(states.iter()) {
                *flag = *observable;
            }
        }
        Self { axes }
    }

    /// The three flags of `block` (all `false` for a block not in [`StateBlock::ALL`]).
    pub fn block(&self, block: StateBlock) -> [bool; 3] {
        StateBlock::ALL
            .iter()
            .zip(self.axes.iter())
            .find(|(candidate, _)| **candidate == block)
            .map_or([false; 3], |(_, flags)| *flags)
    }

    /// Whether every axis of `block` is observable.
    pub fn fully_observable(&self, block: StateBlock) -> bool {
        self.block(block).iter().all(|flag| *flag)
    }

    /// Number of observable states (0..=24).
    pub fn observable_count(&self) -> usize {
        self.axes.iter().flatten().filter(|flag| **flag).count()
    }
}

/// Which states the constant motion `point` makes observable, for the flight calibration
/// manager at a phase change (estimate the blocks that are observable, freeze the others).
///
/// The question is asked in the paper's PWCS setting (Section 2; see the module docs and
/// `docs/observability.md`): the stripped observability matrix of two continuous segments,
/// an ideal coast (ω = 0, f = 0) at the same attitude and then `point`, scaled with
/// [`Scaling::typical`]. A single constant segment on its own can never separate a scale
/// factor from the bias on the same axis (they enter as `b + diag(ω) λ` with constant `ω`), so
/// without the reference coast no manoeuvre would ever report a scale factor. Tolerance:
/// `tolerance` (use [`RankTolerance::DEFAULT`]: singular values ≤ 1e-12 σ_max are zero, a
/// state is observable when its unit vector's projection on that null space is ≤ 1e-6). This
/// is structural observability: a state that passes may still be weak (see
/// [`ObservabilityAnalysis::degree`]).
///
/// Cost: two segments of 144 Givens row updates on a 24×24 factor and one 24×24 SVD.
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf in `point` or `h`; [`NavError::SingularMatrix`] or
/// [`NavError::NonFiniteState`] if the SVD fails.
pub fn motion_observability(
    point: &LinearisationPoint,
    h: &MeasurementMatrix,
    tolerance: &RankTolerance,
) -> Result<AxisObservability, NavError> {
    let analysis = motion_observability_analysis(point, h, tolerance)?;
    Ok(AxisObservability::from_analysis(&analysis))
}

/// The analysis behind [`motion_observability`] (reference coast, then `point`; scaled
/// continuous segments), for callers that need more than the per-state flags, e.g.
/// [`ObservabilityAnalysis::observable_directions`].
///
/// # Errors
/// As [`motion_observability`].
pub fn motion_observability_analysis(
    point: &LinearisationPoint,
    h: &MeasurementMatrix,
    tolerance: &RankTolerance,
) -> Result<ObservabilityAnalysis, NavError> {
    let reference_coast = constant_motion(
        &Vector3::zeros(),
        &Vector3::zeros(),
        &point.body_to_inertial,
    );
    let mut stripped = StrippedObservability::new(Scaling::typical())?;
    stripped.add_segment(&system_matrix(&reference_coast), h, SystemForm::Continuous)?;
    stripped.add_segment(&system_matrix(point), h, SystemForm::Continuous)?;
    stripped.analyse(tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{exp_rotation_vector, rotation_matrix};
    use crate::discretise::discretise;
    use crate::error_model::{noise_input_matrix, ProcessNoise};

    use nalgebra::{Quaternion, Vector3};

    const DEG: f64 = core::f64::consts::PI / 180.0;
    const STEP_S: f64 = 0.002;

    fn attitude() -> Quaternion<f64> {
        exp_rotation_vector(&Vector3::new(0.2, 0.4, -0.1))
    }

    fn motion(rate_deg_s: Vector3<f64>, force_mps2: Vector3<f64>) -> LinearisationPoint {
        constant_motion(
            &(rate_deg_s * DEG),
            &force_mps2,
            &rotation_matrix(&attitude()),
        )
    }

    fn coast() -> LinearisationPoint {
        PaperMotionState::Coast.linearisation_point(&rotation_matrix(&attitude()))
    }
    fn ideal_coast() -> LinearisationPoint {
        motion(Vector3::zeros(), Vector3::zeros())
    }
    fn rotation(axis: usize) -> LinearisationPoint {
        let mut rate = Vector3::zeros();
        rate[axis] = 10.0;
        motion(rate, Vector3::zeros())
    }
    fn acceleration(axis: usize) -> LinearisationPoint {
        let mut force = Vector3::zeros();
        force[axis] = 20.0;
        motion(Vector3::zeros(), force)
    }

    /// H from the measurement module: star (generic mounting) and GNSS with zero lever arm
    /// (the paper has none).
    fn h() -> MeasurementMatrix {
        let mounting = exp_rotation_vector(&Vector3::new(0.4, -1.1, 0.25));
        full_update_measurement_matrix(&attitude(), &mounting).unwrap()
    }

    fn transition(point: &LinearisationPoint) -> SystemMatrix {
        discretise(
            &system_matrix(point),
            &noise_input_matrix(point),
            &ProcessNoise::PAPER.spectral_density_diagonal(),
            STEP_S,
            3,
        )
        .unwrap()
        .transition
    }

    fn analyse(
        segments: &[LinearisationPoint],
        form: SystemForm,
        scaling: Scaling,
    ) -> ObservabilityAnalysis {
        let mut som = StrippedObservability::new(scaling).unwrap();
        for point in segments {
            let system = match form {
                SystemForm::Continuous => system_matrix(point),
                SystemForm::Discrete => transition(point),
            };
            som.add_segment(&system, &h(), form).unwrap();
        }
        som.analyse(&RankTolerance::DEFAULT).unwrap()
    }

    fn continuous(segments: &[LinearisationPoint]) -> ObservabilityAnalysis {
        analyse(segments, SystemForm::Continuous, Scaling::typical())
    }

    fn state_name(k: usize) -> String {
        let block = StateBlock::ALL[k / 3];
        format!("{}.{}", block.name(), ["x", "y", "z"][k % 3])
    }

    fn unobservable(analysis: &ObservabilityAnalysis) -> Vec<String> {
        (0..STATE_DIMENSION)
            .filter(|k| !analysis.observable[*k])
            .map(state_name)
            .collect()
    }

    fn full_schedule() -> Vec<LinearisationPoint> {
        vec![
            coast(),
            rotation(0),
            rotation(1),
            rotation(2),
            acceleration(0),
            acceleration(1),
            acceleration(2),
        ]
    }

    #[test]
    fn givens_factor_reproduces_the_gram_matrix_and_singular_values() {
        let scaling = Scaling::typical();
        let segments = [coast(), rotation(2), acceleration(1)];
        let mut som = StrippedObservability::new(scaling).unwrap();
        let mut gram = SystemMatrix::zeros();
        for point in &segments {
            let a = system_matrix(point);
            som.add_segment(&a, &h(), SystemForm::Continuous).unwrap();
            let q =
                segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
            gram += q.transpose() * q;
        }
        let r = som.factor();
        // Upper triangular.
        for i in 0..STATE_DIMENSION {
            for j in 0..i {
                assert_eq!(r[(i, j)].abs().to_bits(), 0.0_f64.to_bits());
            }
        }
        let difference = (r.transpose() * r - gram).norm() / gram.norm();
        assert!(difference < 1e-13, "{difference}");
        // Singular values of one segment's Q_j equal those of its R.
        let a = system_matrix(&rotation(2));
        let q = segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
        let mut single = StrippedObservability::new(scaling).unwrap();
        single
            .add_segment(&a, &h(), SystemForm::Continuous)
            .unwrap();
        let from_r = single
            .analyse(&RankTolerance::DEFAULT)
            .unwrap()
            .singular_values;
        let from_gram = (q.transpose() * q).symmetric_eigen().eigenvalues;
        let mut eig: Vec<f64> = from_gram.iter().map(|e| e.max(0.0).sqrt()).collect();
        eig.sort_by(|a, b| b.partial_cmp(a).unwrap());
        for (k, (s, e)) in from_r.iter().zip(eig.iter()).enumerate().take(12) {
            assert!((s - e).abs() <= 1e-9 * from_r[0], "{k}: {s} vs {e}");
        }
    }

    #[test]
    fn invalid_inputs_are_typed_errors() {
        let mut bad = Scaling::typical();
        bad.time_unit_s = 0.0;
        assert_eq!(
            StrippedObservability::new(bad),
            Err(NavError::InvalidConfiguration)
        );
        let mut som = StrippedObservability::new(Scaling::typical()).unwrap();
        let mut a = system_matrix(&coast());
        a[(0, 0)] = f64::NAN;
        assert_eq!(
            som.add_segment(&a, &h(), SystemForm::Continuous),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(som.segments(), 0);
        assert_eq!(
            InformationAccumulator::new(&StateVector::zeros()),
            Err(NavError::InvalidConfiguration)
        );
    }

    #[test]
    fn observability_coast_alone_rank_15() {
        let analysis = continuous(&[coast()]);
        println!("I alone: σ = {:.3e}", analysis.singular_values.transpose());
        assert_eq!(analysis.rank, 15, "{:?}", analysis.singular_values);
        // All six scale factors and the installation error (not separable from attitude)
        // have a null-space component; so do attitude and (through b_g + ω λ_g) gyro bias.
        for block in [
            GYRO_SCALE_FACTOR,
            ACCEL_SCALE_FACTOR,
            STAR_INSTALLATION,
            ATTITUDE,
        ] {
            assert_eq!(
                analysis.block_observable(block),
                [false; 3],
                "{}",
                block.name()
            );
        }
        for block in [POSITION, VELOCITY, ACCEL_BIAS] {
            assert_eq!(
                analysis.block_observable(block),
                [true; 3],
                "{}",
                block.name()
            );
        }
        // Accelerometer scale factors: zero columns (f = 0), the null vector is e_k itself.
        for k in ACCEL_SCALE_FACTOR.index()..ACCEL_SCALE_FACTOR.index() + 3 {
            assert!((analysis.null_space_projection[k] - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn observability_rotation_alone_cannot_separate_z_scale_factor_from_z_bias() {
        let analysis = continuous(&[rotation(2)]);
        assert_eq!(analysis.rank, 15, "{:?}", analysis.singular_values);
        // Constant ω: diag(ω) λ_g and b_g enter identically, the z pair is one direction.
        let z = GYRO_SCALE_FACTOR.index() + 2;
        let bz = GYRO_BIAS.index() + 2;
        assert!(!analysis.observable[z]);
        assert!(!analysis.observable[bz]);
        // The null vector pairs them with weights (b_gz, λ_gz) ∝ (−ω_z, 1) in physical units.
        let scaling = Scaling::typical();
        let null_pair: Vec<_> = analysis
            .right_singular_vectors
            .column_iter()
            .zip(analysis.singular_values.iter())
            .filter(|(_, s)| **s <= analysis.zero_threshold)
            .map(|(v, _)| {
                (
                    v[bz] * scaling.state_magnitudes[bz],
                    v[z] * scaling.state_magnitudes[z],
                )
            })
            .filter(|(b, l)| b.abs() + l.abs() > 1e-12)
            .collect();
        assert!(!null_pair.is_empty());
        for (b, l) in null_pair {
            assert!((b / l + 10.0 * DEG).abs() < 1e-9 * 10.0 * DEG, "{b} {l}");
        }
    }

    #[test]
    fn observability_coast_then_rotation_z_separates_z_gyro_scale_factor() {
        let analysis = continuous(&[coast(), rotation(2)]);
        assert_eq!(analysis.rank, 18);
        let degree = |block: StateBlock, axis: usize| analysis.degree[block.index() + axis];
        let z = GYRO_SCALE_FACTOR.index() + 2;
        assert!(analysis.observable[z]);
        assert!(
            degree(GYRO_SCALE_FACTOR, 2) > 1e-4,
            "{}",
            degree(GYRO_SCALE_FACTOR, 2)
        );
        // x, y: observable only through the coast's 4e-6 rad/s rates: practically not.
        for axis in 0..2 {
            let d = analysis.null_space_projection[GYRO_SCALE_FACTOR.index() + axis];
            let sigma = analysis.assigned_singular_value[GYRO_SCALE_FACTOR.index() + axis];
            println!("I+II: λg axis {axis}: null projection {d:.2e}, σ {sigma:.2e}");
        }
        // With an ideal coast (ω = 0) x, y are exactly unobservable.
        let ideal = continuous(&[ideal_coast(), rotation(2)]);
        assert_eq!(
            ideal.block_observable(GYRO_SCALE_FACTOR),
            [false, false, true]
        );
        // Rotation about z separates the installation error's components ⊥ z (body) from
        // attitude; the z component stays tied to attitude.
        println!("ideal I+II unobservable: {:?}", unobservable(&ideal));
    }

    #[test]
    fn observability_coast_then_acceleration_y_separates_y_accel_scale_factor() {
        let analysis = continuous(&[coast(), acceleration(1)]);
        assert_eq!(analysis.rank, 21);
        assert_eq!(
            analysis.block_observable(ACCEL_SCALE_FACTOR),
            [false, true, false]
        );
        println!("I+III unobservable: {:?}", unobservable(&analysis));
        let alone = continuous(&[acceleration(1)]);
        assert!(!alone.observable[ACCEL_SCALE_FACTOR.index() + 1]);
    }

    #[test]
    fn observability_full_schedule_rank_24() {
        let analysis = continuous(&full_schedule());
        println!("full: σ = {:.3e}", analysis.singular_values.transpose());
        assert_eq!(analysis.rank, STATE_DIMENSION);
        assert_eq!(analysis.observable_count(), STATE_DIMENSION);
        let discrete = analyse(&full_schedule(), SystemForm::Discrete, Scaling::typical());
        assert_eq!(discrete.rank, STATE_DIMENSION);
    }

    #[test]
    fn observable_directions_count_combinations_inside_a_block() {
        // Rotation about body x after a coast, generic star mounting: the installation error
        // about body x (a mix of all three sensor axes) stays glued to the attitude error, so
        // no single installation state passes the per-state test, yet two directions do; the
        // gyro scale factor has exactly one observable direction (x).
        let mounting = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.5));
        let h = full_update_measurement_matrix(&attitude(), &mounting).unwrap();
        let analysis =
            motion_observability_analysis(&rotation(0), &h, &RankTolerance::DEFAULT).unwrap();
        assert_eq!(analysis.block_observable(STAR_INSTALLATION), [false; 3]);
        let count = |block| {
            analysis
                .observable_directions(block, &RankTolerance::DEFAULT)
                .unwrap()
        };
        assert_eq!(count(STAR_INSTALLATION), 2);
        assert_eq!(count(GYRO_SCALE_FACTOR), 1);
        assert_eq!(count(ACCEL_SCALE_FACTOR), 0);
        assert_eq!(count(GYRO_BIAS), 3);
        assert_eq!(count(ATTITUDE), 2);
    }

    #[test]
    fn observability_covariance_ratios_agree_with_the_pattern() {
        let mut prior = StateVector::zeros();
        for (block, sigma) in [
            (ATTITUDE, 1e-3),
            (POSITION, 10.0),
            (VELOCITY, 1.0),
            (GYRO_BIAS, 1e-3),
            (ACCEL_BIAS, 1e-2),
            (STAR_INSTALLATION, 1e-2),
            (GYRO_SCALE_FACTOR, 1e-4),
            (ACCEL_SCALE_FACTOR, 1e-4),
        ] {
            prior.fixed_rows_mut::<3>(block.index()).fill(sigma);
        }
        let noise = Scaling::typical().measurement_magnitudes;
        let run = |segments: &[LinearisationPoint]| {
            let mut info = InformationAccumulator::new(&prior).unwrap();
            for point in segments {
                // Measurements every 0.1 s for 20 s per segment.
                let step = transition(point);
                let mut f = SystemMatrix::identity();
                for _ in 0..50 {
                    f = step * f;
                }
                info.add_segment(&f, &h(), &noise, 200).unwrap();
            }
            info.variance_ratios().unwrap()
        };
        let coast_only = run(&[coast()]);
        let full = run(&full_schedule());
        println!("ratio prior/posterior variance (coast | full schedule):");
        for k in 0..STATE_DIMENSION {
            println!(
                "  {:24} {:10.3e} {:10.3e}",
                state_name(k),
                coast_only[k],
                full[k]
            );
        }
        for k in 0..3 {
            assert!(coast_only[ACCEL_SCALE_FACTOR.index() + k] < 1.0 + 1e-9);
            // Weak: 20 s at 20 m/s² with λa = 1e-4 moves the position ≈ 0.4 m against a
            // 10 m GNSS: learned, but only a little (≈ 1.03-1.23 with this prior).
            assert!(full[ACCEL_SCALE_FACTOR.index() + k] > 1.02);
            assert!(full[GYRO_SCALE_FACTOR.index() + k] > 100.0);
            assert!(full[STAR_INSTALLATION.index() + k] > 100.0);
        }
    }

    #[test]
    fn observability_table_1() {
        let cases: Vec<(&str, Vec<LinearisationPoint>)> = vec![
            ("I", vec![coast()]),
            ("II", vec![rotation(2)]),
            ("III", vec![acceleration(1)]),
            ("I+II", vec![coast(), rotation(2)]),
            ("I+III", vec![coast(), acceleration(1)]),
            ("full", full_schedule()),
        ];
        let scaled: Vec<_> = cases.iter().map(|(_, s)| continuous(s)).collect();
        let raw: Vec<_> = cases
            .iter()
            .map(|(_, s)| analyse(s, SystemForm::Discrete, Scaling::unscaled()))
            .collect();
        println!(
            "Observability degree σ_k/σ_max (continuous, scaled; '*' = null-space test fails)"
        );
        print!("{:22}", "state");
        for (name, _) in &cases {
            print!("{name:>11}");
        }
        println!();
        for k in 0..STATE_DIMENSION {
            print!("{:22}", state_name(k));
            for a in &scaled {
                let mark = if a.observable[k] { ' ' } else { '*' };
                print!("{:>10.1e}{mark}", a.degree[k]);
            }
            println!();
        }
        print!("{:22}", "rank (rel 1e-12)");
        for a in &scaled {
            print!("{:>11}", a.rank);
        }
        println!();
        println!("Paper-like: discrete Δ = 2 ms, unscaled, assigned σ (paper threshold 5e-8)");
        for k in 0..STATE_DIMENSION {
            print!("{:22}", state_name(k));
            for a in &raw {
                print!("{:>11.1e}", a.assigned_singular_value[k]);
            }
            println!();
        }
        print!("{:22}", "count σ ≥ 5e-8");
        for a in &raw {
            print!("{:>11}", a.rank_absolute);
        }
        println!();
        print!("{:22}", "rank (rel 1e-12)");
        for a in &raw {
            print!("{:>11}", a.rank);
        }
        println!();
    }

    /// The flight helper on the paper's three states (after the reference ideal coast).
    #[test]
    fn motion_observability_of_the_paper_states() {
        let attitude_matrix = rotation_matrix(&attitude());
        let result = |state: PaperMotionState| {
            motion_observability(
                &state.linearisation_point(&attitude_matrix),
                &h(),
                &RankTolerance::DEFAULT,
            )
            .unwrap()
        };
        let all = [true; 3];
        let none = [false; 3];
        // I: position, velocity, both biases; attitude and installation only as their sum
        // (the star sees C_sb ϑ + ψ), no scale factor (ω ≈ 0, f = 0).
        let coast = result(PaperMotionState::Coast);
        for (block, expected) in [
            (ATTITUDE, none),
            (POSITION, all),
            (VELOCITY, all),
            (GYRO_BIAS, all),
            (ACCEL_BIAS, all),
            (STAR_INSTALLATION, none),
            (GYRO_SCALE_FACTOR, none),
            (ACCEL_SCALE_FACTOR, none),
        ] {
            assert_eq!(coast.block(block), expected, "I {}", block.name());
        }
        assert_eq!(coast.observable_count(), 12);
        // II: rotation about z separates attitude x, y from the installation and makes the
        // z gyro scale factor observable.
        let rotation = result(PaperMotionState::Rotation);
        assert_eq!(rotation.block(ATTITUDE), [true, true, false]);
        assert_eq!(rotation.block(GYRO_SCALE_FACTOR), [false, false, true]);
        assert_eq!(rotation.block(STAR_INSTALLATION), none);
        assert_eq!(rotation.block(ACCEL_SCALE_FACTOR), none);
        assert!(rotation.fully_observable(GYRO_BIAS));
        assert_eq!(rotation.observable_count(), 15);
        // III: acceleration along y makes attitude ⊥ y visible in the velocity and the y
        // accelerometer scale factor observable.
        let acceleration = result(PaperMotionState::Acceleration);
        assert_eq!(acceleration.block(ATTITUDE), [true, false, true]);
        assert_eq!(acceleration.block(ACCEL_SCALE_FACTOR), [false, true, false]);
        assert_eq!(acceleration.block(GYRO_SCALE_FACTOR), none);
        assert_eq!(acceleration.block(STAR_INSTALLATION), none);
        assert!(acceleration.fully_observable(ACCEL_BIAS));
        assert_eq!(acceleration.observable_count(), 15);
        // Bad input is a typed error.
        let mut bad = PaperMotionState::Coast.linearisation_point(&attitude_matrix);
        bad.corrected_rate_rad_s.x = f64::NAN;
        assert_eq!(
            motion_observability(&bad, &h(), &RankTolerance::DEFAULT),
            Err(NavError::NonFiniteInput)
        );
    }

    /// The documented scaling values: star rows 5″ (10″/2) in radians, `unscaled` all ones
    /// with `τ` = 1 s, `typical` the per-block magnitudes.
    #[test]
    fn scaling_constructors_hold_the_documented_values() {
        // 5″ = 5 / 3600 · π / 180 rad.
        assert!((Scaling::STAR_ROW_MAGNITUDE - 2.424_068_405_547_68e-5).abs() < 1e-19);
        let unscaled = Scaling::unscaled();
        assert_eq!(unscaled.state_magnitudes, StateVector::repeat(1.0));
        assert_eq!(
            unscaled.measurement_magnitudes,
            MeasurementVector::repeat(1.0)
        );
        assert_eq!(unscaled.time_unit_s.to_bits(), 1.0_f64.to_bits());
        let typical = Scaling::typical();
        assert_eq!(typical, Scaling::default());
        for (block, magnitude) in Scaling::TYPICAL_STATE_MAGNITUDES {
            for k in block.index()..block.index() + 3 {
                assert_eq!(typical.state_magnitudes[k].to_bits(), magnitude.to_bits());
            }
        }
        let custom = Scaling::from_blocks(&Scaling::TYPICAL_STATE_MAGNITUDES, 3.0, 7.0, 0.5);
        assert_eq!(
            custom.measurement_magnitudes,
            MeasurementVector::new(3.0, 3.0, 3.0, 7.0, 7.0, 7.0)
        );
        assert_eq!(custom.time_unit_s.to_bits(), 0.5_f64.to_bits());
    }

    /// Unscaled rows with `τ` = 2 s are `H (2A)^k` exactly as written in the module docs
    /// (checked for k = 0, 1, 2 against products formed here); NaN in `H` or `A` is refused.
    #[test]
    fn segment_matrix_rows_are_h_times_powers_of_a_tau() {
        let scaling = Scaling {
            time_unit_s: 2.0,
            ..Scaling::unscaled()
        };
        let a = system_matrix(&rotation(2));
        let q = segment_observability_matrix(&a, &h(), SystemForm::Continuous, &scaling).unwrap();
        let mut expected = h();
        for power in 0..3 {
            let rows = q.fixed_rows::<MEASUREMENT_DIMENSION>(power * MEASUREMENT_DIMENSION);
            let error = (rows - expected).amax();
            assert!(error <= 1e-14 * expected.amax(), "power {power}: {error:e}");
            expected *= a * 2.0;
        }
        // Discrete form ignores τ: rows H F^k.
        let discrete = segment_observability_matrix(&a, &h(), SystemForm::Discrete, &scaling)
            .unwrap()
            .fixed_rows::<MEASUREMENT_DIMENSION>(MEASUREMENT_DIMENSION)
            .into_owned();
        assert!((discrete - h() * a).amax() <= 1e-14 * (h() * a).amax());
        let mut bad_h = h();
        bad_h[(4, 2)] = f64::NAN;
        assert_eq!(
            segment_observability_matrix(&a, &bad_h, SystemForm::Continuous, &scaling),
            Err(NavError::NonFiniteInput)
        );
        let mut bad_a = a;
        bad_a[(1, 7)] = f64::INFINITY;
        assert_eq!(
            segment_observability_matrix(&bad_a, &h(), SystemForm::Continuous, &scaling),
            Err(NavError::NonFiniteInput)
        );
    }

    #[test]
    fn stripped_observability_counts_its_segments() {
        let mut som = StrippedObservability::new(Scaling::typical()).unwrap();
        assert_eq!(som.segments(), 0);
        for expected in 1..=3 {
            som.add_segment(&system_matrix(&coast()), &h(), SystemForm::Continuous)
                .unwrap();
            assert_eq!(som.segments(), expected);
        }
    }

    /// A diagonal factor has its diagonal as singular values (exactly) and the unit vectors as
    /// singular vectors, so every reported number is known: threshold `1e-12 · σ_max`, a
    /// value exactly at the threshold is zero (`σ ≤ threshold`), a value exactly at the
    /// paper's `5e-8` counts (`σ ≥ 5e-8`), degree `σ_k / σ_max`.
    #[test]
    fn analyse_factor_of_a_diagonal_factor() {
        let tolerance = RankTolerance::DEFAULT;
        let sigma_max = 1.0e6;
        let at_threshold = tolerance.relative * sigma_max;
        let mut diagonal = StateVector::zeros();
        for (k, value) in diagonal.iter_mut().enumerate() {
            *value = 0.5 * (k as f64 + 1.0);
        }
        diagonal[3] = sigma_max;
        diagonal[7] = at_threshold;
        diagonal[9] = tolerance.absolute;
        diagonal[11] = 0.0;
        let analysis =
            analyse_factor(&TriangularFactor::from_diagonal(&diagonal), &tolerance).unwrap();
        assert_eq!(analysis.zero_threshold.to_bits(), at_threshold.to_bits());
        assert!((analysis.zero_threshold - 1.0e-6).abs() < 1e-21);
        // 24 values minus the one at the threshold, 5e-8 and 0.
        assert_eq!(analysis.rank, 21);
        // Only the zero is below 5e-8.
        assert_eq!(analysis.rank_absolute, 23);
        for k in 0..STATE_DIMENSION {
            assert_eq!(
                analysis.assigned_singular_value[k].to_bits(),
                diagonal[k].to_bits()
            );
            assert!((analysis.degree[k] - diagonal[k] / sigma_max).abs() <= 1e-16 * diagonal[k]);
            let unobservable = [7, 9, 11].contains(&k);
            assert_eq!(analysis.observable[k], !unobservable, "state {k}");
            let projection = if unobservable { 1.0 } else { 0.0 };
            assert!((analysis.null_space_projection[k] - projection).abs() < 1e-15);
        }
        assert!((analysis.degree[3] - 1.0).abs() < 1e-16);
        assert!((analysis.degree[23] - 12.0e-6).abs() < 1e-21);
    }

    /// `R = [[2, 2], [0, 0]]` (plus `3 I` elsewhere): right singular vectors `(1, ±1)/√2`
    /// with `σ = 2√2` and 0, an exact tie between states 0 and 1. The first state wins the
    /// tie, so state 0 gets `2√2` (and keeps it over the 0) and state 1 gets nothing.
    #[test]
    fn analyse_factor_breaks_ties_towards_the_first_state() {
        let mut factor = TriangularFactor::identity() * 3.0;
        factor[(0, 0)] = 2.0;
        factor[(0, 1)] = 2.0;
        factor[(1, 1)] = 0.0;
        let analysis = analyse_factor(&factor, &RankTolerance::DEFAULT).unwrap();
        assert!((analysis.assigned_singular_value[0] - 2.0 * 2.0_f64.sqrt()).abs() < 1e-14);
        assert_eq!(
            analysis.assigned_singular_value[1].to_bits(),
            0.0_f64.to_bits()
        );
        assert_eq!(analysis.degree[1].to_bits(), 0.0_f64.to_bits());
        // The null vector (1, −1)/√2 makes both unobservable.
        assert!(!analysis.observable[0] && !analysis.observable[1]);
        assert!((analysis.null_space_projection[0] - 0.5_f64.sqrt()).abs() < 1e-14);
    }

    /// Degenerate factors: all zero gives rank 0 and degree 0 (not 0/0 = NaN); a factor whose
    /// singular value overflows is a typed error, not an analysis with an infinite σ.
    #[test]
    fn analyse_factor_of_zero_and_of_an_overflowing_factor() {
        let zero = analyse_factor(&TriangularFactor::zeros(), &RankTolerance::DEFAULT).unwrap();
        assert_eq!(zero.rank, 0);
        assert_eq!(zero.rank_absolute, 0);
        assert_eq!(zero.degree, StateVector::zeros());
        assert_eq!(zero.observable_count(), 0);
        let mut overflowing = TriangularFactor::identity();
        overflowing[(2, 2)] = f64::MAX;
        overflowing[(2, 5)] = f64::MAX;
        assert_eq!(
            analyse_factor(&overflowing, &RankTolerance::DEFAULT),
            Err(NavError::NonFiniteState)
        );
    }

    /// One null vector `v = 1e-4 e₀ + √(1 − 1e-8) e₂₃` (factor `I − v vᵀ`): the attitude
    /// block's projection `P_b = diag(1e-8, 0, 0)` has one eigenvalue 1e-8 > 1e-6² , so only
    /// two attitude directions are observable; the state test agrees (‖Nᵀe₀‖ = 1e-4 > 1e-6).
    #[test]
    fn observable_directions_uses_the_squared_projection_threshold() {
        let mut v = StateVector::zeros();
        v[0] = 1.0e-4;
        v[23] = libm::sqrt(1.0 - 1.0e-8);
        let factor = TriangularFactor::identity() - v * v.transpose();
        let analysis = analyse_factor(&factor, &RankTolerance::DEFAULT).unwrap();
        assert_eq!(analysis.rank, 23);
        assert!((analysis.null_space_projection[0] - 1.0e-4).abs() < 1e-12);
        assert!(!analysis.observable[0]);
        assert!(analysis.observable[1] && analysis.observable[2]);
        let directions = analysis
            .observable_directions(ATTITUDE, &RankTolerance::DEFAULT)
            .unwrap();
        assert_eq!(directions, 2);
        assert_eq!(
            analysis
                .observable_directions(POSITION, &RankTolerance::DEFAULT)
                .unwrap(),
            3
        );
    }

    /// One epoch-invariant scalar case in closed form: `H` observes position x (row 3) and
    /// velocity y (row 4) with noise `m`, transition `I`, `n` epochs: the information on a
    /// state with prior σ₀ is `1/σ₀² + n/m²`, so `prior/posterior = 1 + n σ₀²/m²`; unobserved
    /// states keep 1.
    #[test]
    fn information_ratios_in_closed_form() {
        let mut prior = StateVector::repeat(1.0);
        prior[POSITION.index()] = 10.0;
        prior[VELOCITY.index() + 1] = 2.0;
        let mut h = MeasurementMatrix::zeros();
        h[(3, POSITION.index())] = 1.0;
        h[(4, VELOCITY.index() + 1)] = 1.0;
        let noise = MeasurementVector::new(1.0, 1.0, 1.0, 5.0, 0.5, 1.0);
        let mut info = InformationAccumulator::new(&prior).unwrap();
        info.add_segment(&SystemMatrix::identity(), &h, &noise, 4)
            .unwrap();
        let ratios = info.variance_ratios().unwrap();
        let expected_position = 1.0 + 4.0 * 100.0 / 25.0;
        let expected_velocity = 1.0 + 4.0 * 4.0 / 0.25;
        assert!((ratios[POSITION.index()] - expected_position).abs() < 1e-12);
        assert!((ratios[VELOCITY.index() + 1] - expected_velocity).abs() < 1e-12);
        for k in 0..STATE_DIMENSION {
            if k != POSITION.index() && k != VELOCITY.index() + 1 {
                assert!((ratios[k] - 1.0).abs() < 1e-15, "{k}: {}", ratios[k]);
            }
        }
    }

    /// The input checks in their documented order: epoch count (≤ 1e6, exactly 1e6 allowed),
    /// then sigmas (finite and > 0), then finiteness of `transition` and `h` (even with zero
    /// epochs, when neither is used); a refused call leaves the accumulator unchanged.
    #[test]
    fn information_accumulator_input_checks() {
        let mut info = InformationAccumulator::new(&StateVector::repeat(1.0)).unwrap();
        let before = info;
        let sigma = MeasurementVector::repeat(1.0);
        let identity = SystemMatrix::identity();
        let mut nan_transition = identity;
        nan_transition[(0, 0)] = f64::NAN;
        // The count check comes first: just above the limit it is a configuration error
        // even with a NaN transition; exactly at the limit the NaN is what is refused.
        assert_eq!(
            info.add_segment(
                &nan_transition,
                &h(),
                &sigma,
                MAX_MEASUREMENTS_PER_SEGMENT + 1
            ),
            Err(NavError::InvalidConfiguration)
        );
        assert_eq!(
            info.add_segment(&nan_transition, &h(), &sigma, MAX_MEASUREMENTS_PER_SEGMENT),
            Err(NavError::NonFiniteInput)
        );
        for bad in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            let mut bad_sigma = sigma;
            bad_sigma[4] = bad;
            assert_eq!(
                info.add_segment(&identity, &h(), &bad_sigma, 1),
                Err(NavError::InvalidConfiguration),
                "{bad}"
            );
        }
        let mut nan_h = h();
        nan_h[(2, 2)] = f64::NAN;
        assert_eq!(
            info.add_segment(&identity, &nan_h, &sigma, 0),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            info.add_segment(&nan_transition, &h(), &sigma, 0),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(info, before);
        assert_eq!(info.add_segment(&identity, &h(), &sigma, 0), Ok(()));
    }

    /// A factor whose inverse overflows (a diagonal of 1e-200: posterior variance 1e400) or
    /// underflows is reported as singular instead of a ratio of 1/∞ = 0. Not reachable through
    /// `add_segment` (its diagonals only grow from 1) except by round-off, hence set directly.
    #[test]
    fn variance_ratios_refuse_an_overflowing_posterior() {
        let mut info = InformationAccumulator::new(&StateVector::repeat(1.0)).unwrap();
        info.factor_transposed[(5, 5)] = 1.0e-200;
        assert_eq!(info.variance_ratios(), Err(NavError::SingularMatrix));
        // An underflowing one (1e200 diagonal: posterior 1e-400 → 0) likewise, not ∞.
        info.factor_transposed[(5, 5)] = 1.0e200;
        assert_eq!(info.variance_ratios(), Err(NavError::SingularMatrix));
        info.factor_transposed[(5, 5)] = 0.5;
        let ratios = info.variance_ratios().unwrap();
        assert!((ratios[5] - 0.25).abs() < 1e-15);
    }

    /// Table 1's column labels, and `fully_observable` is false as soon as one axis fails
    /// (rotation about z: attitude x, y observable, z not) and for a block with no axis.
    #[test]
    fn paper_labels_and_fully_observable() {
        let labels: Vec<&str> = PaperMotionState::ALL.iter().map(|s| s.label()).collect();
        assert_eq!(labels, ["I", "II", "III"]);
        let rotation = motion_observability(
            &PaperMotionState::Rotation.linearisation_point(&rotation_matrix(&attitude())),
            &h(),
            &RankTolerance::DEFAULT,
        )
        .unwrap();
        assert_eq!(rotation.block(ATTITUDE), [true, true, false]);
        assert!(!rotation.fully_observable(ATTITUDE));
        assert!(!rotation.fully_observable(ACCEL_SCALE_FACTOR));
        assert!(rotation.fully_observable(POSITION));
    }
}
