//! Continuous error-state dynamics `dX/dt = A X + G W` of the 24-state model (paper Section
//! 1.2-1.3.1), derived in this crate's conventions (see the crate docs).
//!
//! ## Derivation
//! Sensor model (paper eqs. 1, 3): `ω_m = ω + Λg ω_m + bg + ηg`, `f_m = f + Λa f_m + ba + ηa`.
//! The navigation uses the corrected `ω̂ = ω_m − diag(ω_m) λ̂g − b̂g` (likewise `f̂`), so
//! with errors `δλ = λ − λ̂`, `δb = b − b̂` (truth − estimate):
//! `δω = ω − ω̂ = −(diag(ω_m) δλg + δbg + ηg)` (paper eq. 2) and
//! `δf = f − f̂ = −(diag(f_m) δλa + δba + ηa)`.
//!
//! * **Attitude** (paper eq. 7). `q = q̂ ⊗ δq`, `q̇ = ½ q ⊗ ω`, `q̂̇ = ½ q̂ ⊗ ω̂` give
//!   `δq̇ = ½(δq ⊗ ω − ω̂ ⊗ δq)`; with `ω = ω̂ + δω` and, for pure quaternions,
//!   `vec(a ⊗ b − b ⊗ a) = 2 a × b`: `ϑ̇ = −[ω̂×] ϑ + ½ δω`
//!   `= −[ω̂×] ϑ − ½ δbg − ½ diag(ω_m) δλg − ½ ηg`.
//! * **Velocity** (paper eq. 14, sign for this convention). `v̇ = C f + g(p)` with
//!   `C = Ĉ (I + 2[ϑ×])`: `δv̇ = Ĉ δf + 2 Ĉ [ϑ×] f̂ + (∂g/∂p) δp`
//!   `= −2 Ĉ [f̂×] ϑ − Ĉ δba − Ĉ diag(f_m) δλa + (∂g/∂p) δp − Ĉ ηa`.
//!   The paper prints `+2C[f×]δq` because its `φ× = 2[δq×]ᵀ` uses the opposite error
//!   direction. The gravity-gradient term is optional (the paper drops it).
//! * **Position**: `δṗ = δv` (the paper's printed `dδp/dt = dδv/dt` is a typo).
//! * **Calibration states** (biases, installation error, scale factors): random constants,
//!   with optional bias random walks (noise inputs 7-12 below).
//!
//! Noise vector `W` ([`NOISE_DIMENSION`] = 12): `[ηg (rad/s), ηa (m/s²), gyro-bias random walk
//! (rad/s²), accelerometer-bias random walk (m/s³)]`, all white, power spectral densities in
//! [`ProcessNoise`].
//!
//! Every block's sign is proven against the nonlinear equations by the tests below.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::attitude::skew;
use crate::state::{
    StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, GYRO_BIAS, GYRO_SCALE_FACTOR, POSITION,
    STATE_DIMENSION, VELOCITY,
};

/// Number of continuous white-noise inputs in `W`.
pub const NOISE_DIMENSION: usize = 12;
/// A 3-wide block of the noise vector `W` (three columns of `G`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoiseBlock {
    index: usize,
    name: &'static str,
}

impl NoiseBlock {
    /// Index of the block's first component in `W`.
    pub const fn index(self) -> usize {
        self.index
    }

    /// Short name (for tables).
    pub const fn name(self) -> &'static str {
        self.name
    }
}

/// Noise input block: gyro white rate noise `ηg`.
pub const NOISE_GYRO: NoiseBlock = NoiseBlock {
    index: 0,
    name: "gyro_noise",
};
/// Noise input block: accelerometer white noise `ηa`.
pub const NOISE_ACCEL: NoiseBlock = NoiseBlock {
    index: 3,
    name: "accel_noise",
};
/// Noise input block: gyro-bias random-walk driving noise.
pub const NOISE_GYRO_BIAS_WALK: NoiseBlock = NoiseBlock {
    index: 6,
    name: "gyro_bias_walk",
};
/// Noise input block: accelerometer-bias random-walk driving noise.
pub const NOISE_ACCEL_BIAS_WALK: NoiseBlock = NoiseBlock {
    index: 9,
    name: "accel_bias_walk",
};

/// The first row or column of a 3×3 block, for [`set_block`].
pub(crate) trait BlockOffset: Copy {
    /// The offset.
    fn offset(self) -> usize;
}

impl BlockOffset for StateBlock {
    fn offset(self) -> usize {
        self.index()
    }
}

impl BlockOffset for NoiseBlock {
    fn offset(self) -> usize {
        self.index
    }
}

/// Rows `offset..offset + 3` of a matrix with no state layout (a measurement's rows).
impl BlockOffset for usize {
    fn offset(self) -> usize {
        self
    }
}

/// 24×24 system matrix `A`.
pub type SystemMatrix = SMatrix<f64, STATE_DIMENSION, STATE_DIMENSION>;
/// 24×12 noise input matrix `G`.
pub type NoiseInputMatrix = SMatrix<f64, STATE_DIMENSION, NOISE_DIMENSION>;

/// What the error model is linearised about (one strapdown step's mean values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearisationPoint {
    /// Corrected body rate `ω̂` (rad/s).
    pub corrected_rate_rad_s: Vector3<f64>,
    /// Corrected specific force `f̂` (m/s²).
    pub corrected_specific_force_mps2: Vector3<f64>,
    /// Raw measured body rate `ω_m` (rad/s): the gyro scale-factor column is `diag(ω_m)`.
    pub measured_rate_rad_s: Vector3<f64>,
    /// Raw measured specific force `f_m` (m/s²).
    pub measured_specific_force_mps2: Vector3<f64>,
    /// Estimated attitude matrix `Ĉ = C_ib` (body to launch-inertial).
    pub body_to_inertial: Matrix3<f64>,
    /// Gravity gradient `∂g/∂p` in the launch-inertial frame (1/s²); zero reproduces the paper.
    pub gravity_gradient_per_s2: Matrix3<f64>,
}

/// Writes `value` into the 3×3 block (`row`, `column`) of a matrix.
pub(crate) fn set_block<const R: usize, const C: usize>(
    matrix: &mut SMatrix<f64, R, C>,
    row: impl BlockOffset,
    column: impl BlockOffset,
    value: &Matrix3<f64>,
) {
    matrix
        .fixed_view_mut::<3, 3>(row.offset(), column.offset())
        .copy_from(value);
}

/// The system matrix `A` at `point` (derivation in the module docs).
pub fn system_matrix(point: &LinearisationPoint) -> SystemMatrix {
    let mut a = SystemMatrix::zeros();
    let c = &point.body_to_inertial;
    let half = Matrix3::identity() * 0.5;
    set_block(
        &mut a,
        ATTITUDE,
        ATTITUDE,
        &(-skew(&point.corrected_rate_rad_s)),
    );
    set_block(&mut a, ATTITUDE, GYRO_BIAS, &(-half));
    set_block(
        &mut a,
        ATTITUDE,
        GYRO_SCALE_FACTOR,
        &(-half * Matrix3::from_diagonal(&point.measured_rate_rad_s)),
    );
    set_block(&mut a, POSITION, VELOCITY, &Matrix3::identity());
    set_block(
        &mut a,
        VELOCITY,
        ATTITUDE,
        &(-2.0 * c * skew(&point.corrected_specific_force_mps2)),
    );
    set_block(&mut a, VELOCITY, POSITION, &point.gravity_gradient_per_s2);
    set_block(&mut a, VELOCITY, ACCEL_BIAS, &(-c));
    set_block(
        &mut a,
        VELOCITY,
        ACCEL_SCALE_FACTOR,
        &(-c * Matrix3::from_diagonal(&point.measured_specific_force_mps2)),
    );
    a
}

/// The noise input matrix `G` at `point` (noise vector layout in the module docs).
pub fn noise_input_matrix(point: &LinearisationPoint) -> NoiseInputMatrix {
    let mut g = NoiseInputMatrix::zeros();
    set_block(&mut g, ATTITUDE, NOISE_GYRO, &(-Matrix3::identity() * 0.5));
    set_block(&mut g, VELOCITY, NOISE_ACCEL, &(-point.body_to_inertial));
    set_block(
        &mut g,
        GYRO_BIAS,
        NOISE_GYRO_BIAS_WALK,
        &Matrix3::identity(),
    );
    set_block(
        &mut g,
        ACCEL_BIAS,
        NOISE_ACCEL_BIAS_WALK,
        &Matrix3::identity(),
    );
    g
}

/// Sensor noise specification in physical units: the power spectral densities of `W`.
///
/// Interpretation of the paper's "gyro random noise 0.2 °/h": a white rate noise whose 1σ is
/// 0.2 °/h in a 1 Hz bandwidth, i.e. a density of 0.2 °/h/√Hz = 9.70e-7 rad/s/√Hz (an angle
/// random walk of 0.0033 °/√h). Over a sample of `T` seconds the integrated angle noise has
/// 1σ = density·√T. The accelerometer's "1e-4 m/s²" likewise: 1e-4 m/s²/√Hz.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ProcessNoise {
    /// Gyro white rate-noise density (rad/s/√Hz).
    pub gyro_noise_density_rad_s_per_sqrt_hz: f64,
    /// Accelerometer white-noise density (m/s²/√Hz).
    pub accel_noise_density_mps2_per_sqrt_hz: f64,
    /// Gyro-bias random-walk density (rad/s²/√Hz); 0 = constant bias (paper).
    pub gyro_bias_walk_rad_s2_per_sqrt_hz: f64,
    /// Accelerometer-bias random-walk density (m/s³/√Hz); 0 = constant bias (paper).
    pub accel_bias_walk_mps3_per_sqrt_hz: f64,
}

impl ProcessNoise {
    /// The paper's Section 3 values (biases constant).
    pub const PAPER: ProcessNoise = ProcessNoise {
        gyro_noise_density_rad_s_per_sqrt_hz: 0.2 * core::f64::consts::PI / 180.0 / 3600.0,
        accel_noise_density_mps2_per_sqrt_hz: 1.0e-4,
        gyro_bias_walk_rad_s2_per_sqrt_hz: 0.0,
        accel_bias_walk_mps3_per_sqrt_hz: 0.0,
    };

    /// True when every density is finite and non-negative.
    pub fn is_valid(&self) -> bool {
        [
            self.gyro_noise_density_rad_s_per_sqrt_hz,
            self.accel_noise_density_mps2_per_sqrt_hz,
            self.gyro_bias_walk_rad_s2_per_sqrt_hz,
            self.accel_bias_walk_mps3_per_sqrt_hz,
        ]
        .iter()
        .all(|density| density.is_finite() && *density >= 0.0)
    }

    /// Diagonal of the continuous noise PSD matrix `Q` (density², per [`NOISE_DIMENSION`]).
    pub fn spectral_density_diagonal(&self) -> SMatrix<f64, NOISE_DIMENSION, 1> {
        let mut diagonal = SMatrix::<f64, NOISE_DIMENSION, 1>::zeros();
        let entries = [
            (NOISE_GYRO, self.gyro_noise_density_rad_s_per_sqrt_hz),
            (NOISE_ACCEL, self.accel_noise_density_mps2_per_sqrt_hz),
            (NOISE_GYRO_BIAS_WALK, self.gyro_bias_walk_rad_s2_per_sqrt_hz),
            (NOISE_ACCEL_BIAS_WALK, self.accel_bias_walk_mps3_per_sqrt_hz),
        ];
        for (block, density) in entries {
            diagonal
                .fixed_view_mut::<3, 1>(block.index, 0)
                .fill(density * density);
        }
        diagonal
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::attitude::{conjugate, from_vector_part, product, rotation_matrix};
    use crate::state::{StateBlock, STAR_INSTALLATION};
    use nalgebra::{Quaternion, SVector};

    const GM: f64 = 3.986004418e14;

    /// Point-mass gravity (test-local, the sign proof needs only some smooth g(p)).
    pub fn point_mass_gravity(position: &Vector3<f64>) -> Vector3<f64> {
        let radius = position.norm();
        -GM / (radius * radius * radius) * position
    }

    /// Its gradient `(GM/r³)(3 r̂ r̂ᵀ − I)`.
    pub fn point_mass_gradient(position: &Vector3<f64>) -> Matrix3<f64> {
        let radius = position.norm();
        let unit = position / radius;
        GM / (radius * radius * radius) * (3.0 * unit * unit.transpose() - Matrix3::identity())
    }

    /// A full nonlinear "truth or estimate" with its sensor errors.
    #[derive(Clone, Copy)]
    pub struct Hypothesis {
        pub attitude: Quaternion<f64>,
        pub position: Vector3<f64>,
        pub velocity: Vector3<f64>,
        pub gyro_bias: Vector3<f64>,
        pub accel_bias: Vector3<f64>,
        pub gyro_scale: Vector3<f64>,
        pub accel_scale: Vector3<f64>,
    }

    pub fn estimate() -> Hypothesis {
        Hypothesis {
            attitude: crate::attitude::exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1)),
            position: Vector3::new(6.9e6, 1.2e5, -3.0e5),
            velocity: Vector3::new(120.0, 7500.0, -300.0),
            gyro_bias: Vector3::new(1e-4, -2e-4, 3e-4),
            accel_bias: Vector3::new(2e-3, 1e-3, -3e-3),
            gyro_scale: Vector3::new(3e-5, -2e-5, 1e-5),
            accel_scale: Vector3::new(5e-5, -4e-5, 2e-5),
        }
    }

    pub const MEASURED_RATE: Vector3<f64> = Vector3::new(0.3, -1.2, 1.7);
    pub const MEASURED_FORCE: Vector3<f64> = Vector3::new(4.0, 30.0, -12.0);

    /// Applies an error-state vector `δx` to the estimate, giving the truth.
    pub fn perturbed(estimate: &Hypothesis, error: &SVector<f64, 24>) -> Hypothesis {
        let block = |b: StateBlock| -> Vector3<f64> { error.fixed_rows::<3>(b.index()).into() };
        Hypothesis {
            attitude: product(
                &estimate.attitude,
                &from_vector_part(&block(ATTITUDE)).unwrap(),
            ),
            position: estimate.position + block(POSITION),
            velocity: estimate.velocity + block(VELOCITY),
            gyro_bias: estimate.gyro_bias + block(GYRO_BIAS),
            accel_bias: estimate.accel_bias + block(ACCEL_BIAS),
            gyro_scale: estimate.gyro_scale + block(GYRO_SCALE_FACTOR),
            accel_scale: estimate.accel_scale + block(ACCEL_SCALE_FACTOR),
        }
    }

    fn rate(h: &Hypothesis) -> Vector3<f64> {
        MEASURED_RATE - MEASURED_RATE.component_mul(&h.gyro_scale) - h.gyro_bias
    }
    fn force(h: &Hypothesis) -> Vector3<f64> {
        MEASURED_FORCE - MEASURED_FORCE.component_mul(&h.accel_scale) - h.accel_bias
    }

    /// Exact derivative of the nonlinear error (ϑ, δp, δv; calibration rows are zero).
    fn nonlinear_error_rate(truth: &Hypothesis, estimate: &Hypothesis) -> SVector<f64, 24> {
        let q_dot = 0.5 * truth.attitude * Quaternion::from_imag(rate(truth));
        let q_hat_dot = 0.5 * estimate.attitude * Quaternion::from_imag(rate(estimate));
        // δq = q̂* ⊗ q, so δq̇ = q̂̇* ⊗ q + q̂* ⊗ q̇.
        let delta_q_dot =
            conjugate(&q_hat_dot) * truth.attitude + conjugate(&estimate.attitude) * q_dot;
        let velocity_rate = |h: &Hypothesis| {
            rotation_matrix(&h.attitude) * force(h) + point_mass_gravity(&h.position)
        };
        let mut rate_of_error = SVector::<f64, 24>::zeros();
        rate_of_error
            .fixed_rows_mut::<3>(ATTITUDE.index())
            .copy_from(&delta_q_dot.imag());
        rate_of_error
            .fixed_rows_mut::<3>(POSITION.index())
            .copy_from(&(truth.velocity - estimate.velocity));
        rate_of_error
            .fixed_rows_mut::<3>(VELOCITY.index())
            .copy_from(&(velocity_rate(truth) - velocity_rate(estimate)));
        rate_of_error
    }

    pub fn linearisation(estimate: &Hypothesis) -> LinearisationPoint {
        LinearisationPoint {
            corrected_rate_rad_s: rate(estimate),
            corrected_specific_force_mps2: force(estimate),
            measured_rate_rad_s: MEASURED_RATE,
            measured_specific_force_mps2: MEASURED_FORCE,
            body_to_inertial: rotation_matrix(&estimate.attitude),
            gravity_gradient_per_s2: point_mass_gradient(&estimate.position),
        }
    }

    /// Typical error magnitude per block (so every block is perturbed at a physical scale).
    pub fn block_scale(block: StateBlock) -> f64 {
        match block.name() {
            "attitude" | "star_installation" => 1e-3,
            "position" => 100.0,
            "velocity" => 1.0,
            "gyro_bias" => 1e-3,
            "accel_bias" => 1e-2,
            _ => 1e-3,
        }
    }

    pub fn block_error(block: StateBlock, scale: f64) -> SVector<f64, 24> {
        let mut error = SVector::<f64, 24>::zeros();
        error
            .fixed_rows_mut::<3>(block.index())
            .copy_from(&(Vector3::new(1.0, -0.6, 0.8) * scale));
        error
    }

    /// Perturbs `block` by `scale` and by `scale/2`, and requires the mismatch between the
    /// nonlinear and the linear prediction (`predict` returns both for an error state) to be
    /// second order: halving the perturbation quarters it, or it is at round-off because the
    /// block enters exactly linearly. A sign error gives a mismatch as large as the linear
    /// term itself and fails.
    pub fn assert_second_order<const R: usize>(
        block: StateBlock,
        scale: f64,
        predict: impl Fn(&SVector<f64, 24>) -> (SVector<f64, R>, SVector<f64, R>),
    ) {
        let mut mismatch = [0.0; 2];
        let mut linear_size = 0.0;
        for (slot, halving) in [1.0, 0.5].into_iter().enumerate() {
            let (nonlinear, linear) = predict(&block_error(block, scale * halving));
            mismatch[slot] = (nonlinear - linear).amax();
            if slot == 0 {
                linear_size = linear.amax();
            }
        }
        let name = block.name();
        assert!(linear_size > 0.0, "{name}: block has no effect");
        let ratio = mismatch[0] / mismatch[1];
        println!(
            "{name}: |linear| = {linear_size:.3e}, mismatch = {:.3e} / {:.3e} (ratio {ratio:.3})",
            mismatch[0], mismatch[1]
        );
        let at_round_off = mismatch[0] <= 1e-9 * linear_size;
        assert!(
            at_round_off || (3.5..4.5).contains(&ratio),
            "{name}: mismatch {mismatch:?} (ratio {ratio}) vs linear {linear_size}"
        );
        assert!(
            mismatch[0] < 0.05 * linear_size,
            "{name}: {mismatch:?} vs {linear_size}"
        );
    }

    #[test]
    fn system_matrix_predicts_the_nonlinear_error_rate_to_second_order() {
        let estimate = estimate();
        let a = system_matrix(&linearisation(&estimate));
        for block in StateBlock::ALL {
            if block == STAR_INSTALLATION {
                // No dynamics: the installation error is a constant (zero column).
                assert_eq!(
                    a.fixed_columns::<3>(block.index()).amax().to_bits(),
                    0.0f64.to_bits()
                );
                continue;
            }
            assert_second_order(block, block_scale(block), |error| {
                let truth = perturbed(&estimate, error);
                (nonlinear_error_rate(&truth, &estimate), a * error)
            });
        }
    }

    #[test]
    fn a_sign_error_would_be_caught() {
        // The same check with the velocity-attitude block's sign flipped must fail.
        let estimate = estimate();
        let mut a = system_matrix(&linearisation(&estimate));
        let flipped = -a
            .fixed_view::<3, 3>(VELOCITY.index(), ATTITUDE.index())
            .into_owned();
        set_block(&mut a, VELOCITY, ATTITUDE, &flipped);
        let error = block_error(ATTITUDE, 1e-3);
        let truth = perturbed(&estimate, &error);
        let mismatch = (nonlinear_error_rate(&truth, &estimate) - a * error).amax();
        assert!(mismatch > 0.5 * (a * error).amax());
    }

    #[test]
    fn noise_matrix_matches_the_sensor_model() {
        let point = linearisation(&estimate());
        let g = noise_input_matrix(&point);
        // A gyro noise sample acts like a gyro bias, an accel noise sample like an accel bias.
        let a = system_matrix(&point);
        assert_eq!(
            g.fixed_columns::<3>(NOISE_GYRO.index),
            a.fixed_columns::<3>(GYRO_BIAS.index())
        );
        assert_eq!(
            g.fixed_columns::<3>(NOISE_ACCEL.index),
            a.fixed_columns::<3>(ACCEL_BIAS.index())
        );
        let psd = ProcessNoise::PAPER.spectral_density_diagonal();
        assert!((psd[0] - 9.696e-7_f64.powi(2)).abs() < 1e-3 * psd[0]);
    }

    /// Validity: every density finite and ≥ 0 (zero = the paper's constant biases); a
    /// negative, infinite or NaN density in any of the four fields is refused.
    #[test]
    fn process_noise_validity_per_field() {
        assert!(ProcessNoise::PAPER.is_valid());
        let all_zero = ProcessNoise {
            gyro_noise_density_rad_s_per_sqrt_hz: 0.0,
            accel_noise_density_mps2_per_sqrt_hz: 0.0,
            gyro_bias_walk_rad_s2_per_sqrt_hz: 0.0,
            accel_bias_walk_mps3_per_sqrt_hz: 0.0,
        };
        assert!(all_zero.is_valid());
        for field in 0..4 {
            for bad in [-1.0e-9, f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
                let mut noise = ProcessNoise::PAPER;
                let slot = match field {
                    0 => &mut noise.gyro_noise_density_rad_s_per_sqrt_hz,
                    1 => &mut noise.accel_noise_density_mps2_per_sqrt_hz,
                    2 => &mut noise.gyro_bias_walk_rad_s2_per_sqrt_hz,
                    _ => &mut noise.accel_bias_walk_mps3_per_sqrt_hz,
                };
                *slot = bad;
                assert!(!noise.is_valid(), "field {field} = {bad}");
            }
        }
    }
}
