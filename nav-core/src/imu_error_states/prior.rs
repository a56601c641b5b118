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
//! prior that the burns never fully wash out (`docs/imu-errors.md`). The rotation `S` also
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

/// The state indices and signs of the three states an upper gyro term `a^g_ij` (`i < j`,
/// given as `(row, column)`) enters (module docs); `None` if a term is not in the layout.
fn shared_term_states(upper: (usize, usize)) -> Option<[(usize, f64); 3]> {
    let (row, column) = upper;
    let position = |terms: &[(usize, usize)], term: (usize, usize)| {
        terms.iter().position(|candidate| *candidate == term)
    };
    let gyro = position(&GYRO_NON_ORTHOGONALITY_TERMS, (column, row))?;
    let accel_upper = position(&ACCEL_MISALIGNMENT_TERMS, (row, column))?;
    let accel_lower = position(&ACCEL_MISALIGNMENT_TERMS, (column, row))?;
    let gyro_offset = ImuErrorBlock::GyroNonOrthogonality.offset();
    let accel_offset = ImuErrorBlock::AccelMisalignment.offset();
    Some([
        (gyro_offset + gyro, 1.0),
        (accel_offset + accel_upper, -1.0),
        (accel_offset + accel_lower, 1.0),
    ])
}

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
        let prior = self.prior_rows();
        PriorCovariance::from_fn(|a, b| {
            prior
                .get(a)
                .and_then(|row| row.get(b))
                .copied()
                .unwrap_or(0.0)
        })
    }

    /// [`Self::prior_covariance`] by rows, as the border keeps it.
    pub(super) fn prior_rows(&self) -> BorderMatrix {
        let gyro_variance = self.gyro_misalignment_sigma_rad * self.gyro_misalignment_sigma_rad;
        let accel_variance = self.accel_misalignment_sigma_rad * self.accel_misalignment_sigma_rad;
        let g_sensitivity_variance = self.gyro_g_sensitivity_sigma_rad_s_per_mps2
            * self.gyro_g_sensitivity_sigma_rad_s_per_mps2;
        let accel = ImuErrorBlock::AccelMisalignment.offset();
        let g_sensitivity = ImuErrorBlock::GyroGSensitivity.offset();
        let mut prior: BorderMatrix = core::array::from_fn(|a| {
            core::array::from_fn(|b| match (a == b, a) {
                (false, _) => 0.0,
                (true, k) if k < accel => gyro_variance,
                (true, k) if k < g_sensitivity => accel_variance,
                (true, _) => g_sensitivity_variance,
            })
        });
        for states in UPPER_GYRO_TERMS.into_iter().filter_map(shared_term_states) {
            for (a, sign_a) in states {
                for (b, sign_b) in states {
                    if let Some(entry) = prior.get_mut(a).and_then(|row| row.get_mut(b)) {
                        *entry += sign_a * sign_b * gyro_variance;
                    }
                }
            }
        }
        prior
    }
}
