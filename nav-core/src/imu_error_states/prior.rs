//! The prior covariance of the twelve systematic IMU error states in the filter's gauge,
//! from the triads' specification.
//!
//! A datasheet (or a ground calibration's residual) gives the 1σ of every off-diagonal term
//! of each triad's error matrix in body axes: `σ_g` for the gyro's six, `σ_a` for the
//! accelerometer's six, drawn independently. The filter's frame follows the gyro triad
//! ([`crate::imu_error`], "Gauge freedom"), so to first order its terms are
//! ([`crate::imu_error::to_filter_gauge`] linearised at zero: `R ≈ I + S` with `S` the skew
//! matrix that removes the gyro's upper terms, `S_ij = a^g_ij` for `i < j`):
//!
//! * gyro non-orthogonality `l_ij = a^g_ij + a^g_ji` (`i > j`);
//! * accelerometer misalignment `m_ij = a^a_ij − a^g_ij` above the diagonal (`i < j`) and
//!   `m_ji = a^a_ji + a^g_ij` below it.
//!
//! Each upper gyro term `a^g_ij` (`i < j`) therefore enters three states, `l_ji` with `+1`,
//! `m_ij` with `−1` and `m_ji` with `+1`, and
//! `P₀ = diag(σ_g² ×3, σ_a² ×6, σ_s² ×3) + σ_g² Σ_{i<j} v_ij v_ijᵀ`,
//! with `v_ij` those three signs: each state's variance is the sum of its two terms'
//! (`2σ_g²`, `σ_a² + σ_g²`), and the three states that share a gyro term are correlated by
//! `±σ_g²`. A diagonal prior with the same variances would miss the shared term: along
//! `v_ij` it allows `2σ_g²` where the truth spreads `4σ_g²` (`σ_a = σ_g`), an optimistic
//! prior that the burns never fully wash out (`docs/guide/imu-errors.md`). The rotation `S` also
//! enters the star installation error, whose prior (milliradians) dwarfs it: that
//! correlation is left out. `σ_s` is the g-sensitivity's 1σ per axis, independent.

use nalgebra::SMatrix;

use super::{BorderMatrix, ImuErrorModel};
use crate::imu_error::{
    ImuErrorBlock, ACCEL_MISALIGNMENT_TERMS, GYRO_NON_ORTHOGONALITY_TERMS, IMU_ERROR_DIMENSION,
};

/// The twelve states' covariance.
pub type PriorCovariance = SMatrix<f64, IMU_ERROR_DIMENSION, IMU_ERROR_DIMENSION>;

/// The gyro's upper terms `a^g_ij` (`i < j`), as `(row, column)`.
const UPPER_GYRO_TERMS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// Index of `term` in `terms` (`usize::MAX` if absent: the `const` asserts below refuse it).
/// Evaluated only at compile time, where an index out of range is a build error.
#[allow(clippy::indexing_slicing)]
const fn index_of(terms: &[(usize, usize)], term: (usize, usize)) -> usize {
    let mut k = 0;
    while k < terms.len() {
        if terms[k].0 == term.0 && terms[k].1 == term.1 {
            return k;
        }
        k += 1;
    }
    usize::MAX
}

/// The state indices and signs of the three states an upper gyro term `a^g_ij` (`i < j`,
/// given as `(row, column)`) enters (module docs).
const fn shared_term_states(upper: (usize, usize)) -> [(usize, f64); 3] {
    let (row, column) = upper;
    let gyro = ImuErrorBlock::GyroNonOrthogonality.offset()
        + index_of(&GYRO_NON_ORTHOGONALITY_TERMS, (column, row));
    let accel = ImuErrorBlock::AccelMisalignment.offset();
    [
        (gyro, 1.0),
        (
            accel + index_of(&ACCEL_MISALIGNMENT_TERMS, (row, column)),
            -1.0,
        ),
        (
            accel + index_of(&ACCEL_MISALIGNMENT_TERMS, (column, row)),
            1.0,
        ),
    ]
}

/// For each upper gyro term, the three states it enters, with their signs.
const SHARED_TERM_STATES: [[(usize, f64); 3]; 3] = [
    shared_term_states(UPPER_GYRO_TERMS[0]),
    shared_term_states(UPPER_GYRO_TERMS[1]),
    shared_term_states(UPPER_GYRO_TERMS[2]),
];
// Compile-time check (an index out of range here is a build error, not a run-time panic).
#[allow(clippy::indexing_slicing)]
const _: () = {
    let mut g = 0;
    while g < SHARED_TERM_STATES.len() {
        let mut k = 0;
        while k < 3 {
            assert!(SHARED_TERM_STATES[g][k].0 < ImuErrorBlock::GyroGSensitivity.offset());
            k += 1;
        }
        g += 1;
    }
};

impl ImuErrorModel {
    /// The prior covariance of the twelve states in the filter's gauge, in
    /// [`ImuErrorBlock`] order (module docs: per-state variances `2σ_g²`, `σ_a² + σ_g²`,
    /// `σ_s²`, and `±σ_g²` between the three states that share an upper gyro term).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error_states::ImuErrorModel;
    /// let model = ImuErrorModel { gyro_misalignment_sigma_rad: 2e-5,
    ///     accel_misalignment_sigma_rad: 2e-5, gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7 };
    /// let prior = model.prior_covariance();
    /// assert!((prior[(0, 0)] - 8e-10).abs() < 1e-24); // l_yx = a_yx + a_xy: 2σ_g²
    /// assert!((prior[(0, 5)] - 4e-10).abs() < 1e-24); // l_yx and m_yx share a_xy
    /// assert!((prior[(0, 3)] + 4e-10).abs() < 1e-24); // m_xy = a^a_xy − a^g_xy
    /// assert!((prior[(9, 9)] - 6.25e-14).abs() < 1e-28);
    /// ```
    pub fn prior_covariance(&self) -> PriorCovariance {
        let mut prior = [[0.0; IMU_ERROR_DIMENSION]; IMU_ERROR_DIMENSION];
        self.write_prior(&mut prior);
        PriorCovariance::from_fn(|a, b| {
            prior
                .get(a)
                .and_then(|row| row.get(b))
                .copied()
                .unwrap_or(0.0)
        })
    }

    /// Adds [`Self::prior_covariance`] to `covariance` (by rows, as the border keeps it),
    /// in place: the border is built where it lives, not on the stack.
    #[inline]
    pub(super) fn write_prior(&self, covariance: &mut BorderMatrix) {
        let gyro_variance = self.gyro_misalignment_sigma_rad * self.gyro_misalignment_sigma_rad;
        let accel_variance = self.accel_misalignment_sigma_rad * self.accel_misalignment_sigma_rad;
        let g_sensitivity_variance = self.gyro_g_sensitivity_sigma_rad_s_per_mps2
            * self.gyro_g_sensitivity_sigma_rad_s_per_mps2;
        let accel = ImuErrorBlock::AccelMisalignment.offset();
        let g_sensitivity = ImuErrorBlock::GyroGSensitivity.offset();
        for (k, row) in covariance.iter_mut().enumerate() {
            let variance = if k < accel {
                gyro_variance
            } else if k < g_sensitivity {
                accel_variance
            } else {
                g_sensitivity_variance
            };
            if let Some(entry) = row.get_mut(k) {
                *entry += variance;
            }
        }
        for states in &SHARED_TERM_STATES {
            for (a, sign_a) in states {
                for (b, sign_b) in states {
                    if let Some(entry) = covariance.get_mut(*a).and_then(|row| row.get_mut(*b)) {
                        *entry += sign_a * sign_b * gyro_variance;
                    }
                }
            }
        }
    }
}
