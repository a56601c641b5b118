//! Strapdown inertial navigation in the launch-inertial frame.
//!
//! One step of length `T` from `t_{k−1}` to `t_k` (Savage, "Strapdown Inertial Navigation
//! Integration Algorithm Design", J. Guidance Control Dyn. 21(1)/(2), 1998; Titterton &
//! Weston, *Strapdown Inertial Navigation Technology*, 2nd ed., §11.2):
//!
//! 1. Sensor corrections (paper's sensor model `measured = true + Λ·measured + b`):
//!    `Δθ = Δθ_m − diag(λ̂_g) Δθ_m − b̂_g T`, `Δv = Δv_m − diag(λ̂_a) Δv_m − b̂_a T`.
//! 2. Two-sample coning (Savage 1998 Part 1, eq. 47 with the previous-interval sample):
//!    `φ = Δθ_k + (1/12) Δθ_{k−1} × Δθ_k`.
//! 3. Velocity increment with rotation compensation and two-sample sculling
//!    (Savage 1998 Part 1, eqs. 56–60 in their two-sample form):
//!    `Δv_comp = Δv_k + ½ Δθ_k × Δv_k + (1/12)(Δθ_{k−1} × Δv_k + Δv_{k−1} × Δθ_k)`.
//! 4. `v_k = v_{k−1} + C_{k−1} Δv_comp + g(p_{k−1} + v_{k−1} T/2) T`.
//! 5. `p_k = p_{k−1} + ½ (v_{k−1} + v_k) T`.
//! 6. `q_k = normalise(q_{k−1} ⊗ exp(φ))` (body rotation vector, `dq/dt = ½ q ⊗ ω`).

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::attitude::{all_finite3, exp_rotation_vector, normalise, product, rotation_matrix};
use crate::frames::LaunchFrame;
use crate::gravity::GravityModel;
use crate::NavError;

/// One IMU sample: integrated increments over one interval, body axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuIncrement {
    /// Integrated angular rate `Δθ = ∫ ω_ib^b dt` over the interval (rad).
    pub delta_angle_rad: Vector3<f64>,
    /// Integrated specific force `Δv = ∫ f^b dt` over the interval (m/s).
    pub delta_velocity_mps: Vector3<f64>,
    /// Interval length `T` (s), strictly positive.
    pub interval_s: f64,
}

impl ImuIncrement {
    /// Increments from constant rates: `Δθ = ω T` (ω in rad/s), `Δv = f T` (f in m/s²),
    /// interval `T` (s). Not validated here; [`Strapdown::step`] validates.
    pub fn from_rates(
        rate_rad_s: &Vector3<f64>,
        specific_force_mps2: &Vector3<f64>,
        interval_s: f64,
    ) -> Self {
        Self {
            delta_angle_rad: rate_rad_s * interval_s,
            delta_velocity_mps: specific_force_mps2 * interval_s,
            interval_s,
        }
    }
}

/// Whole-value navigation state in the launch-inertial frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavigationState {
    /// Attitude `q_ib` (body to launch-inertial), unit Hamilton quaternion, scalar first.
    pub attitude: Quaternion<f64>,
    /// Position in the launch-inertial frame (m).
    pub position_m: Vector3<f64>,
    /// Velocity in the launch-inertial frame (m/s).
    pub velocity_mps: Vector3<f64>,
    /// Time of validity on the GNSS time scale (s).
    pub time_s: f64,
}

impl NavigationState {
    fn is_finite(&self) -> bool {
        self.attitude.w.is_finite()
            && all_finite3(&self.attitude.imag())
            && all_finite3(&self.position_m)
            && all_finite3(&self.velocity_mps)
            && self.time_s.is_finite()
    }
}

/// Current sensor-error estimates applied to the raw increments (body axes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SensorCorrections {
    /// Gyro bias `b̂_g` (rad/s).
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Accelerometer bias `b̂_a` (m/s²).
    pub accel_bias_mps2: Vector3<f64>,
    /// Gyro scale-factor errors `λ̂_g` (dimensionless, diagonal of `Λ_g`).
    pub gyro_scale_factor: Vector3<f64>,
    /// Accelerometer scale-factor errors `λ̂_a` (dimensionless, diagonal of `Λ_a`).
    pub accel_scale_factor: Vector3<f64>,
}

impl SensorCorrections {
    fn is_finite(&self) -> bool {
        all_finite3(&self.gyro_bias_rad_s)
            && all_finite3(&self.accel_bias_mps2)
            && all_finite3(&self.gyro_scale_factor)
            && all_finite3(&self.accel_scale_factor)
    }
}

/// Strapdown algorithm options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StrapdownConfig {
    /// Apply the two-sample coning term `(1/12) Δθ_{k−1} × Δθ_k`.
    pub coning_compensation: bool,
    /// Apply the two-sample sculling term `(1/12)(Δθ_{k−1} × Δv_k + Δv_{k−1} × Δθ_k)`
    /// (the rotation compensation `½ Δθ_k × Δv_k` is always applied).
    pub sculling_compensation: bool,
    /// Gravitation model.
    pub gravity: GravityModel,
}

impl Default for StrapdownConfig {
    fn default() -> Self {
        Self {
            coning_compensation: true,
            sculling_compensation: true,
            gravity: GravityModel::default(),
        }
    }
}

/// By-products of one step, each the mean over the step (increment / `T`), body axes except
/// gravity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutput {
    /// Corrected angular rate `Δθ / T` (rad/s).
    pub corrected_rate_rad_s: Vector3<f64>,
    /// Corrected specific force `Δv / T` (m/s²).
    pub corrected_specific_force_mps2: Vector3<f64>,
    /// Raw angular rate `Δθ_m / T` (rad/s).
    pub measured_rate_rad_s: Vector3<f64>,
    /// Raw specific force `Δv_m / T` (m/s²).
    pub measured_specific_force_mps2: Vector3<f64>,
    /// Gravitation used, at the predicted mid-step position, launch-inertial axes (m/s²).
    pub gravity_mps2: Vector3<f64>,
}

/// Strapdown integrator; keeps the previous corrected increments for coning and sculling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strapdown {
    config: StrapdownConfig,
    /// Previous corrected `Δθ_{k−1}` (rad); zero before the first step.
    previous_delta_angle_rad: Vector3<f64>,
    /// Previous corrected `Δv_{k−1}` (m/s); zero before the first step.
    previous_delta_velocity_mps: Vector3<f64>,
    /// Gravitation beyond the model's point mass + `J2` (m/s², launch-inertial), held by the
    /// caller's field evaluation (`gravity::harmonics`); `None`: nothing added.
    field_beyond_j2_mps2: Option<Vector3<f64>>,
}

impl Strapdown {
    /// New integrator with empty increment history.
    pub fn new(config: StrapdownConfig) -> Self {
        Self {
            config,
            previous_delta_angle_rad: Vector3::zeros(),
            previous_delta_velocity_mps: Vector3::zeros(),
            field_beyond_j2_mps2: None,
        }
    }

    /// Sets the gravitation added to the model's at every later step (m/s², launch-inertial
    /// axes), e.g. the held value of [`crate::gravity::harmonics::FieldRemainder`]; `None`
    /// adds nothing (the model alone, bit for bit).
    pub fn set_field_beyond_j2(&mut self, acceleration_launch_mps2: Option<Vector3<f64>>) {
        self.field_beyond_j2_mps2 = acceleration_launch_mps2;
    }

    /// The configuration in use.
    pub fn config(&self) -> &StrapdownConfig {
        &self.config
    }

    /// Forgets the previous increments (e.g. after a data gap), so the next step uses no
    /// coning/sculling history.
    pub fn reset_history(&mut self) {
        self.previous_delta_angle_rad = Vector3::zeros();
        self.previous_delta_velocity_mps = Vector3::zeros();
    }

    /// Advances `nav` by one IMU increment (equations in the module docs); `nav.time_s`
    /// advances by `raw.interval_s`.
    ///
    /// # Errors
    /// [`NavError::InvalidTimeStep`] for a non-finite or non-positive interval,
    /// [`NavError::NonFiniteInput`] for non-finite increments or corrections,
    /// [`NavError::NonFiniteState`] for a non-finite `nav` or result,
    /// [`NavError::DegenerateQuaternion`] if the attitude cannot be normalised.
    /// On any error `nav` and the increment history are left unchanged.
    pub fn step(
        &mut self,
        nav: &mut NavigationState,
        raw: &ImuIncrement,
        corrections: &SensorCorrections,
        frame: &LaunchFrame,
    ) -> Result<StepOutput, NavError> {
        check_step_inputs(nav, raw, corrections)?;
        let interval = raw.interval_s;

        // 1. Sensor corrections.
        let delta_angle = raw.delta_angle_rad
            - corrections
                .gyro_scale_factor
                .component_mul(&raw.delta_angle_rad)
            - corrections.gyro_bias_rad_s * interval;
        let delta_velocity = raw.delta_velocity_mps
            - corrections
                .accel_scale_factor
                .component_mul(&raw.delta_velocity_mps)
            - corrections.accel_bias_mps2 * interval;

        // 2. Coning; 3. rotation compensation and sculling.
        let (rotation_vector, delta_velocity_body) =
            self.compensated(&delta_angle, &delta_velocity);

        // 4. Velocity with gravity at the predicted midpoint.
        let c_ib: Matrix3<f64> = rotation_matrix(&nav.attitude);
        let midpoint = nav.position_m + nav.velocity_mps * (0.5 * interval);
        let mut gravity = self.config.gravity.gravity_launch_mps2(frame, &midpoint);
        if let Some(beyond_j2) = &self.field_beyond_j2_mps2 {
            gravity += beyond_j2;
        }
        let velocity = nav.velocity_mps + c_ib * delta_velocity_body + gravity * interval;

        // 5. Trapezoidal position.
        let position = nav.position_m + (nav.velocity_mps + velocity) * (0.5 * interval);

        // 6. Attitude.
        let attitude = normalise(&product(
            &nav.attitude,
            &exp_rotation_vector(&rotation_vector),
        ))?;
        let time = nav.time_s + interval;

        if !all_finite3(&velocity)
            || !all_finite3(&position)
            || !all_finite3(&gravity)
            || !time.is_finite()
        {
            return Err(NavError::NonFiniteState);
        }

        let output = StepOutput {
            corrected_rate_rad_s: delta_angle / interval,
            corrected_specific_force_mps2: delta_velocity / interval,
            measured_rate_rad_s: raw.delta_angle_rad / interval,
            measured_specific_force_mps2: raw.delta_velocity_mps / interval,
            gravity_mps2: gravity,
        };
        if !all_finite3(&output.corrected_rate_rad_s)
            || !all_finite3(&output.corrected_specific_force_mps2)
            || !all_finite3(&output.measured_rate_rad_s)
            || !all_finite3(&output.measured_specific_force_mps2)
        {
            return Err(NavError::NonFiniteState);
        }

        // Commit.
        nav.attitude = attitude;
        nav.velocity_mps = velocity;
        nav.position_m = position;
        nav.time_s = time;
        self.previous_delta_angle_rad = delta_angle;
        self.previous_delta_velocity_mps = delta_velocity;
        Ok(output)
    }

    /// Steps 2 and 3 of [`Strapdown::step`] (module docs): the rotation vector with the
    /// coning term and the body velocity increment with the rotation and sculling terms,
    /// from the corrected increments and the previous ones.
    #[inline(always)]
    fn compensated(
        &self,
        delta_angle: &Vector3<f64>,
        delta_velocity: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let mut rotation_vector = *delta_angle;
        if self.config.coning_compensation {
            rotation_vector += self.previous_delta_angle_rad.cross(delta_angle) / 12.0;
        }
        let mut delta_velocity_body = delta_velocity + 0.5 * delta_angle.cross(delta_velocity);
        if self.config.sculling_compensation {
            delta_velocity_body += (self.previous_delta_angle_rad.cross(delta_velocity)
                + self.previous_delta_velocity_mps.cross(delta_angle))
                / 12.0;
        }
        (rotation_vector, delta_velocity_body)
    }
}

/// The input checks of [`Strapdown::step`], in its documented order of errors.
#[inline(always)]
fn check_step_inputs(
    nav: &NavigationState,
    raw: &ImuIncrement,
    corrections: &SensorCorrections,
) -> Result<(), NavError> {
    let interval = raw.interval_s;
    if !interval.is_finite() || interval <= 0.0 {
        return Err(NavError::InvalidTimeStep);
    }
    if !all_finite3(&raw.delta_angle_rad)
        || !all_finite3(&raw.delta_velocity_mps)
        || !corrections.is_finite()
    {
        return Err(NavError::NonFiniteInput);
    }
    if nav.is_finite() {
        Ok(())
    } else {
        Err(NavError::NonFiniteState)
    }
}

#[cfg(test)]
#[path = "strapdown_tests.rs"]
mod tests;
