//! The truth trajectory in the launch-inertial frame and the exact IMU increments.
//!
//! ## Model
//! State: attitude `q_ib`, position `r` and velocity `v` of the IMU in the launch-inertial
//! frame `i`. Commanded inputs, from the manoeuvre schedule ([`CommandProfile`]): the body
//! angular rate `ω(t) = ω_ib^b` and the body specific force `f(t) = f^b` (thrust acceleration).
//!
//! ```text
//! dq_ib/dt = ½ q_ib ⊗ [0, ω(t)]          (nav-core's kinematics)
//! dr/dt    = v
//! dv/dt    = C(q_ib) f(t) + g(r)          (g: point mass + J2, the flight code's model)
//! ```
//!
//! integrated with classical RK4 on `(q, r, v)` jointly, `truth_substeps_per_frame` steps per
//! IMU frame (default 16 × 125 µs at 500 Hz), the quaternion renormalised once per frame.
//!
//! ## IMU truth
//! What a navigation IMU outputs per frame `[t_k, t_k+1]`: the delta angle
//! `Δθ_k = ∫ ω(t) dt` and the delta velocity `Δv_k = ∫ f(t) dt`, both in body axes, computed
//! in closed form from the raised-cosine profile (exact, no quadrature). These are the
//! integrals of the body-frame signals, so they carry the coning/sculling content the flight
//! strapdown must compensate (its attitude and velocity updates are only exact to the order of
//! its compensation when the rate axis or the specific force rotates within a frame).
//!
//! Manoeuvre boundaries lie on IMU frame boundaries (the scenario validates it), so every frame
//! is integrated with a single, smooth segment command; a discontinuous command (ramp 0) never
//! falls inside an RK4 step.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use nav_core::frames::LaunchFrame;
use nav_core::gravity::GravityModel;

use crate::scenario::{frames_in, ManoeuvreSegment, Scenario};
use crate::setup::launch::{initial_state, launch_frame, TruthState};
use crate::setup::SetupError;

/// Why the truth simulation could not be set up or advanced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TruthError {
    /// The gravity model refused a position (e.g. inside the Earth, or non-finite).
    #[error("gravity model failed at t = {time_s} s, position {position_m:?} m: {reason}")]
    Gravity {
        /// Navigation time of the failed evaluation (s).
        time_s: f64,
        /// Launch-inertial position that was refused (m).
        position_m: [f64; 3],
        /// The gravity model's reason.
        reason: String,
    },
    /// The launch frame or the initial state could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A setting is unusable (e.g. zero substeps, non-positive frame period).
    #[error("truth setting {key} {requirement}")]
    Setting {
        /// The offending setting.
        key: &'static str,
        /// What it must satisfy.
        requirement: &'static str,
    },
}

/// A gravitational acceleration field in the launch-inertial frame.
///
/// The truth uses the same model as the flight code (nav-core's point mass + J2), so a
/// navigation error can never come from a truth/flight gravity mismatch; tests substitute
/// simpler fields.
pub trait GravityField {
    /// Gravitational acceleration `g(r)` (m/s²) at launch-inertial position `r` (m).
    ///
    /// # Errors
    /// A human-readable reason when the position is refused.
    fn acceleration_mps2(&self, position_m: &Vector3<f64>) -> Result<Vector3<f64>, String>;
}

impl<F> GravityField for F
where
    F: Fn(&Vector3<f64>) -> Vector3<f64>,
{
    fn acceleration_mps2(&self, position_m: &Vector3<f64>) -> Result<Vector3<f64>, String> {
        Ok(self(position_m))
    }
}

/// The flight code's gravity (nav-core point mass + J2) in the scenario's launch-inertial
/// frame, as a [`GravityField`] that refuses positions where it is not finite.
#[derive(Debug, Clone, Copy)]
pub struct FlightGravity {
    /// The launch-inertial frame geometry (Earth centre and axis).
    pub frame: LaunchFrame,
    /// The model (J2 on by default).
    pub model: GravityModel,
}

impl GravityField for FlightGravity {
    fn acceleration_mps2(&self, position_m: &Vector3<f64>) -> Result<Vector3<f64>, String> {
        let gravity = self.model.gravity_launch_mps2(&self.frame, position_m);
        if nav_core::attitude::all_finite3(&gravity) {
            Ok(gravity)
        } else {
            Err("non-finite gravity (position at the Earth centre or non-finite)".to_string())
        }
    }
}

/// Raised-cosine pulse shape `s(τ) ∈ [0, 1]` of a segment of length `duration_s` with rise and
/// fall time `ramp_s`: `½(1 − cos(π τ / ramp))` on `[0, ramp]`, 1 on the hold, mirrored on the
/// fall. `ramp_s = 0` gives 1 on the whole segment; outside `[0, duration_s]` it is 0.
pub fn raised_cosine_shape(elapsed_s: f64, duration_s: f64, ramp_s: f64) -> f64 {
    if !(0.0..=duration_s).contains(&elapsed_s) {
        return 0.0;
    }
    if ramp_s <= 0.0 {
        return 1.0;
    }
    let from_edge_s = elapsed_s.min(duration_s - elapsed_s);
    if from_edge_s >= ramp_s {
        1.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * from_edge_s / ramp_s).cos())
    }
}

/// `∫₀^τ s(u) du` (s) of [`raised_cosine_shape`], in closed form, for `τ` clamped to
/// `[0, duration_s]`. The rise contributes `½(τ − (ramp/π) sin(π τ / ramp))`; the whole pulse
/// integrates to `duration_s − ramp_s`.
pub fn raised_cosine_integral(elapsed_s: f64, duration_s: f64, ramp_s: f64) -> f64 {
    let tau = elapsed_s.clamp(0.0, duration_s);
    if ramp_s <= 0.0 {
        return tau;
    }
    // Integral of the rise from 0 to x (x ≤ ramp).
    let rise = |x: f64| {
        0.5 * (x - ramp_s / std::f64::consts::PI * (std::f64::consts::PI * x / ramp_s).sin())
    };
    let fall_start_s = duration_s - ramp_s;
    if tau <= ramp_s {
        rise(tau)
    } else if tau <= fall_start_s {
        0.5 * ramp_s + (tau - ramp_s)
    } else {
        // By symmetry: total minus the rise integral of the remaining time.
        (duration_s - ramp_s) - rise(duration_s - tau)
    }
}

/// One segment of the command profile, in SI units and absolute time.
#[derive(Debug, Clone, PartialEq)]
pub struct CommandSegment {
    /// Free-text name from the scenario.
    pub label: String,
    /// Navigation time at which the segment starts (s).
    pub start_time_s: f64,
    /// Segment length including both ramps (s).
    pub duration_s: f64,
    /// Rise and fall time (s).
    pub ramp_s: f64,
    /// Peak body angular rate (rad/s).
    pub peak_body_rate_rad_per_s: Vector3<f64>,
    /// Peak body specific force (m/s²).
    pub peak_specific_force_mps2: Vector3<f64>,
}

impl CommandSegment {
    /// Converts a scenario segment starting at `start_time_s`.
    pub fn from_manoeuvre(segment: &ManoeuvreSegment, start_time_s: f64) -> Self {
        let [rate_x, rate_y, rate_z] = segment.body_rate_deg_per_s;
        let [force_x, force_y, force_z] = segment.specific_force_mps2;
        Self {
            label: segment.label.clone(),
            start_time_s,
            duration_s: segment.duration_s,
            ramp_s: segment.ramp_s,
            peak_body_rate_rad_per_s: Vector3::new(
                rate_x.to_radians(),
                rate_y.to_radians(),
                rate_z.to_radians(),
            ),
            peak_specific_force_mps2: Vector3::new(force_x, force_y, force_z),
        }
    }

    /// Navigation time at which the segment ends (s).
    pub fn end_time_s(&self) -> f64 {
        self.start_time_s + self.duration_s
    }

    /// Pulse shape at navigation time `time_s` (extended by continuity to the closed segment).
    pub fn shape(&self, time_s: f64) -> f64 {
        raised_cosine_shape(time_s - self.start_time_s, self.duration_s, self.ramp_s)
    }

    /// `∫ shape` from `from_s` to `to_s` (s), closed form.
    pub fn shape_integral(&self, from_s: f64, to_s: f64) -> f64 {
        let integral = |time_s: f64| {
            raised_cosine_integral(time_s - self.start_time_s, self.duration_s, self.ramp_s)
        };
        integral(to_s) - integral(from_s)
    }

    /// Commanded body rate `ω_ib^b(t)` (rad/s).
    pub fn body_rate_rad_per_s(&self, time_s: f64) -> Vector3<f64> {
        self.peak_body_rate_rad_per_s * self.shape(time_s)
    }

    /// Commanded body specific force `f^b(t)` (m/s²).
    pub fn specific_force_mps2(&self, time_s: f64) -> Vector3<f64> {
        self.peak_specific_force_mps2 * self.shape(time_s)
    }
}

/// The manoeuvre schedule as absolute-time command segments, back to back.
#[derive(Debug, Clone, PartialEq)]
pub struct CommandProfile {
    /// The segments in time order; each starts where the previous one ends.
    pub segments: Vec<CommandSegment>,
}

impl CommandProfile {
    /// The scenario's manoeuvre schedule, starting at `simulation.start_time_s`.
    pub fn from_scenario(scenario: &Scenario) -> Self {
        let mut start_time_s = scenario.simulation.start_time_s;
        let segments = scenario
            .manoeuvres
            .iter()
            .map(|manoeuvre| {
                let segment = CommandSegment::from_manoeuvre(manoeuvre, start_time_s);
                start_time_s = segment.end_time_s();
                segment
            })
            .collect();
        Self { segments }
    }

    /// The segment in force at `time_s` (half-open `[start, end)`; the last segment is closed),
    /// or `None` outside the schedule.
    pub fn segment_at(&self, time_s: f64) -> Option<&CommandSegment> {
        self.segments
            .iter()
            .find(|segment| segment.start_time_s <= time_s && time_s < segment.end_time_s())
            .or_else(|| {
                self.segments
                    .last()
                    .filter(|last| last.start_time_s <= time_s && time_s <= last.end_time_s())
            })
    }
}

/// The truth over one IMU frame `[start_time_s, time_s]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthFrame {
    /// Frame counter, 0 for the first frame of the scenario.
    pub frame_index: u64,
    /// Start of the frame (s).
    pub start_time_s: f64,
    /// End of the frame: the time tag of the increments and of the state below (s).
    pub time_s: f64,
    /// Nominal frame length `T` = 1 / IMU rate (s); `time_s − start_time_s` up to rounding.
    pub interval_s: f64,
    /// Attitude `q_ib` at `time_s`.
    pub attitude_q_ib: Quaternion<f64>,
    /// Launch-inertial position at `time_s` (m).
    pub position_m: Vector3<f64>,
    /// Launch-inertial velocity at `time_s` (m/s).
    pub velocity_mps: Vector3<f64>,
    /// Exact delta angle `∫ ω_ib^b dt` over the frame (rad, body axes).
    pub delta_angle_rad: Vector3<f64>,
    /// Exact delta velocity `∫ f^b dt` over the frame (m/s, body axes).
    pub delta_velocity_mps: Vector3<f64>,
    /// Index of the manoeuvre segment flown during the frame.
    pub segment_index: usize,
}

impl TruthFrame {
    /// The state at the end of the frame.
    pub fn state(&self) -> TruthState {
        TruthState {
            time_s: self.time_s,
            attitude_q_ib: self.attitude_q_ib,
            position_m: self.position_m,
            velocity_mps: self.velocity_mps,
        }
    }
}

/// Time derivative of `(q, r, v)`.
struct Derivative {
    attitude: Quaternion<f64>,
    position: Vector3<f64>,
    velocity: Vector3<f64>,
}

/// Integrates the truth frame by frame; an iterator over [`TruthFrame`]s.
pub struct TruthSimulator<G: GravityField> {
    state: TruthState,
    profile: CommandProfile,
    gravity: G,
    frame_period_s: f64,
    substeps_per_frame: u32,
    /// Scenario start (s): frame `k` covers `[t0 + kT, t0 + (k+1)T]`, computed without
    /// accumulating rounding.
    start_time_s: f64,
    next_frame_index: u64,
    frame_count: u64,
}

impl<G: GravityField> TruthSimulator<G> {
    /// A simulator starting from `initial` (whose time is the scenario start), flying
    /// `profile` to its end in frames of `frame_period_s` with `substeps_per_frame` RK4 steps.
    ///
    /// # Errors
    /// [`TruthError::Setting`] for a non-positive period or zero substeps.
    pub fn new(
        initial: TruthState,
        profile: CommandProfile,
        gravity: G,
        frame_period_s: f64,
        substeps_per_frame: u32,
    ) -> Result<Self, TruthError> {
        if !(frame_period_s.is_finite() && frame_period_s > 0.0) {
            return Err(TruthError::Setting {
                key: "frame_period_s",
                requirement: "must be finite and > 0",
            });
        }
        if substeps_per_frame == 0 {
            return Err(TruthError::Setting {
                key: "substeps_per_frame",
                requirement: "must be >= 1",
            });
        }
        let duration_s = profile
            .segments
            .last()
            .map_or(0.0, |last| last.end_time_s() - initial.time_s);
        Ok(Self {
            start_time_s: initial.time_s,
            state: initial,
            profile,
            gravity,
            frame_period_s,
            substeps_per_frame,
            next_frame_index: 0,
            frame_count: frames_in(duration_s, frame_period_s),
        })
    }

    /// The current state (the end of the last frame produced, or the initial state).
    pub fn state(&self) -> &TruthState {
        &self.state
    }

    /// Number of frames the profile lasts.
    pub fn frame_count(&self) -> u64 {
        self.frame_count
    }

    /// The command profile being flown.
    pub fn profile(&self) -> &CommandProfile {
        &self.profile
    }

    /// Advances one frame, or returns `Ok(None)` at the end of the profile.
    ///
    /// # Errors
    /// [`TruthError::Gravity`] if the gravity model refuses a position.
    pub fn next_frame(&mut self) -> Result<Option<TruthFrame>, TruthError> {
        if self.next_frame_index >= self.frame_count {
            return Ok(None);
        }
        let frame_index = self.next_frame_index;
        // Whole-frame counts below 2^53 are exact in f64.
        let start_time_s = self.start_time_s + frame_index as f64 * self.frame_period_s;
        let end_time_s = self.start_time_s + (frame_index + 1) as f64 * self.frame_period_s;
        let middle_s = 0.5 * (start_time_s + end_time_s);
        let Some((segment_index, segment)) =
            self.profile
                .segments
                .iter()
                .enumerate()
                .find(|(_, segment)| {
                    segment.start_time_s <= middle_s && middle_s < segment.end_time_s()
                })
        else {
            return Ok(None);
        };

        let step_s = (end_time_s - start_time_s) / f64::from(self.substeps_per_frame);
        let mut state = self.state;
        state.time_s = start_time_s;
        for substep in 0..self.substeps_per_frame {
            let time_s = start_time_s + f64::from(substep) * step_s;
            state = self.rk4_step(segment, &state, time_s, step_s)?;
        }
        state.time_s = end_time_s;
        state.attitude_q_ib = UnitQuaternion::new_normalize(state.attitude_q_ib).into_inner();
        // Exact increments: the frame's command is `peak · s(t)`, so both integrals are the peak
        // times the closed-form integral of the shape.
        let shape_integral_s = segment.shape_integral(start_time_s, end_time_s);
        let delta_angle_rad = segment.peak_body_rate_rad_per_s * shape_integral_s;
        let delta_velocity_mps = segment.peak_specific_force_mps2 * shape_integral_s;
        self.state = state;
        self.next_frame_index += 1;

        Ok(Some(TruthFrame {
            frame_index,
            start_time_s,
            time_s: end_time_s,
            interval_s: self.frame_period_s,
            attitude_q_ib: state.attitude_q_ib,
            position_m: state.position_m,
            velocity_mps: state.velocity_mps,
            delta_angle_rad,
            delta_velocity_mps,
            segment_index,
        }))
    }

    fn derivative(
        &self,
        segment: &CommandSegment,
        time_s: f64,
        attitude: &Quaternion<f64>,
        position: &Vector3<f64>,
        velocity: &Vector3<f64>,
    ) -> Result<Derivative, TruthError> {
        let rate = segment.body_rate_rad_per_s(time_s);
        let force_body = segment.specific_force_mps2(time_s);
        let gravity =
            self.gravity
                .acceleration_mps2(position)
                .map_err(|reason| TruthError::Gravity {
                    time_s,
                    position_m: [position.x, position.y, position.z],
                    reason,
                })?;
        // Rotate with the (not yet renormalised) RK4 stage quaternion via the sandwich product,
        // which is exact for a unit quaternion; stage quaternions are unit to O(h^5).
        let force_inertial = (attitude * Quaternion::from_imag(force_body) * attitude.conjugate())
            .imag()
            / attitude.norm_squared();
        Ok(Derivative {
            attitude: attitude * Quaternion::from_imag(rate) * 0.5,
            position: *velocity,
            velocity: force_inertial + gravity,
        })
    }

    fn rk4_step(
        &self,
        segment: &CommandSegment,
        state: &TruthState,
        time_s: f64,
        step_s: f64,
    ) -> Result<TruthState, TruthError> {
        let (q0, r0, v0) = (state.attitude_q_ib, state.position_m, state.velocity_mps);
        let half_s = 0.5 * step_s;
        let k1 = self.derivative(segment, time_s, &q0, &r0, &v0)?;
        let k2 = self.derivative(
            segment,
            time_s + half_s,
            &(q0 + k1.attitude * half_s),
            &(r0 + k1.position * half_s),
            &(v0 + k1.velocity * half_s),
        )?;
        let k3 = self.derivative(
            segment,
            time_s + half_s,
            &(q0 + k2.attitude * half_s),
            &(r0 + k2.position * half_s),
            &(v0 + k2.velocity * half_s),
        )?;
        let k4 = self.derivative(
            segment,
            time_s + step_s,
            &(q0 + k3.attitude * step_s),
            &(r0 + k3.position * step_s),
            &(v0 + k3.velocity * step_s),
        )?;
        let sixth_s = step_s / 6.0;
        Ok(TruthState {
            time_s: time_s + step_s,
            attitude_q_ib: q0
                + (k1.attitude + k2.attitude * 2.0 + k3.attitude * 2.0 + k4.attitude) * sixth_s,
            position_m: r0
                + (k1.position + k2.position * 2.0 + k3.position * 2.0 + k4.position) * sixth_s,
            velocity_mps: v0
                + (k1.velocity + k2.velocity * 2.0 + k3.velocity * 2.0 + k4.velocity) * sixth_s,
        })
    }
}

impl TruthSimulator<FlightGravity> {
    /// The scenario's truth: initial state from [`initial_state`], its manoeuvre schedule, the
    /// flight code's gravity with J2, at the IMU rate with the configured substeps.
    ///
    /// # Errors
    /// [`TruthError::Setup`] or [`TruthError::Setting`].
    pub fn from_scenario(scenario: &Scenario) -> Result<Self, TruthError> {
        let frame = launch_frame(scenario)?;
        let initial = initial_state(scenario, &frame)?;
        Self::new(
            initial,
            CommandProfile::from_scenario(scenario),
            FlightGravity {
                frame,
                model: GravityModel { j2_enabled: true },
            },
            scenario.imu.frame_period_s(),
            scenario.simulation.truth_substeps_per_frame,
        )
    }
}

impl<G: GravityField> Iterator for TruthSimulator<G> {
    type Item = Result<TruthFrame, TruthError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_frame().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::scenario::Scenario;
    use crate::setup::launch::orbit_state_from_elements;
    use nav_core::attitude::exp_rotation_vector;
    use nav_core::frames::{WGS84_GM_M3_S2, WGS84_J2, WGS84_SEMI_MAJOR_AXIS_M};

    const MU_M3_PER_S2: f64 = WGS84_GM_M3_S2;

    /// The potential whose gradient is nav-core's point mass + J2 field:
    /// `U = −μ/r [1 − J2 (a/r)² P2(s/r)]`, `s = k·r` (k the Earth axis), `P2(x) = (3x² − 1)/2`.
    fn j2_potential(gravity: &FlightGravity, position_launch_m: &Vector3<f64>) -> f64 {
        let geocentric = gravity.frame.geocentric_position_launch(position_launch_m);
        let r = geocentric.norm();
        let sin_latitude = gravity.frame.earth_axis_launch().dot(&geocentric) / r;
        let p2 = 0.5 * (3.0 * sin_latitude * sin_latitude - 1.0);
        -MU_M3_PER_S2 / r * (1.0 - WGS84_J2 * (WGS84_SEMI_MAJOR_AXIS_M / r).powi(2) * p2)
    }

    fn segment(duration_s: f64, ramp_s: f64, rate: [f64; 3], force: [f64; 3]) -> ManoeuvreSegment {
        ManoeuvreSegment {
            label: "test".to_string(),
            duration_s,
            ramp_s,
            body_rate_deg_per_s: rate,
            specific_force_mps2: force,
        }
    }

    fn profile(segments: &[ManoeuvreSegment], start_time_s: f64) -> CommandProfile {
        let mut start = start_time_s;
        CommandProfile {
            segments: segments
                .iter()
                .map(|manoeuvre| {
                    let command = CommandSegment::from_manoeuvre(manoeuvre, start);
                    start = command.end_time_s();
                    command
                })
                .collect(),
        }
    }

    fn no_gravity(_: &Vector3<f64>) -> Vector3<f64> {
        Vector3::zeros()
    }

    #[test]
    fn raised_cosine_integral_matches_quadrature_and_closed_total() {
        let (duration_s, ramp_s) = (10.0, 1.5);
        // Midpoint quadrature with 1e5 cells: error ~ h² s''/24 ~ 1e-10.
        let cells = 100_000;
        let h = duration_s / f64::from(cells);
        let mut sum = 0.0;
        for cell in 0..cells {
            let tau = (f64::from(cell) + 0.5) * h;
            sum += raised_cosine_shape(tau, duration_s, ramp_s) * h;
            if cell % 9_973 == 0 {
                let partial = raised_cosine_integral(tau + 0.5 * h, duration_s, ramp_s);
                assert!((partial - sum).abs() < 1e-8, "{tau}: {partial} vs {sum}");
            }
        }
        assert!((sum - (duration_s - ramp_s)).abs() < 1e-8);
        let total = raised_cosine_integral(duration_s, duration_s, ramp_s);
        assert!((total - 8.5).abs() < 1e-14);
        assert!((raised_cosine_shape(0.75, duration_s, ramp_s) - 0.5).abs() < 1e-15);
        assert!(raised_cosine_shape(-0.1, duration_s, ramp_s).abs() < 1e-300);
    }

    #[test]
    fn pure_orbit_conserves_energy_over_one_orbit() {
        // The default scenario's 500 km orbit with nav-core's J2 gravity, no manoeuvre, for one
        // Keplerian period: ½v² + U(r) is an exact invariant (the field is static and
        // axisymmetric in the inertial frame).
        let mut scenario = Scenario::default_scenario().unwrap();
        let semi_major_axis_m = scenario.initial_orbit.semi_major_axis_m;
        let period_s =
            2.0 * std::f64::consts::PI * (semi_major_axis_m.powi(3) / MU_M3_PER_S2).sqrt();
        let frame_period_s = scenario.imu.frame_period_s();
        scenario.manoeuvres = vec![segment(
            (period_s / frame_period_s).ceil() * frame_period_s,
            0.0,
            [0.0; 3],
            [0.0; 3],
        )];
        let mut truth = TruthSimulator::from_scenario(&scenario).unwrap();
        let gravity = truth.gravity;
        let initial = *truth.state();
        let energy = |state: &TruthState| {
            0.5 * state.velocity_mps.norm_squared() + j2_potential(&gravity, &state.position_m)
        };
        let initial_energy = energy(&initial);
        let mut worst_relative = 0.0_f64;
        let mut last = initial;
        for frame in truth.by_ref() {
            let frame = frame.unwrap();
            if frame.frame_index % 1000 == 0 {
                let drift = ((energy(&frame.state()) - initial_energy) / initial_energy).abs();
                worst_relative = worst_relative.max(drift);
            }
            last = frame.state();
        }
        let final_relative = ((energy(&last) - initial_energy) / initial_energy).abs();
        println!("energy: worst relative drift {worst_relative:.3e}, final {final_relative:.3e}");
        // Measured: 1.0e-12 worst, 6.5e-13 final (RK4, 125 µs steps; round-off dominated).
        assert!(worst_relative.max(final_relative) < 1e-11);
        // After one Keplerian period the J2-perturbed orbit is back near its start: J2 shifts
        // the node and the period by some tens of km along a 43,000 km circumference.
        let closure_m = (last.position_m - initial.position_m).norm();
        println!("orbit closure after one Keplerian period: {closure_m:.0} m");
        assert!(closure_m < 100_000.0, "{closure_m}");
    }

    #[test]
    fn default_initial_state_is_the_stated_orbit_over_the_launch_site() {
        let scenario = Scenario::default_scenario().unwrap();
        let frame = launch_frame(&scenario).unwrap();
        let state = initial_state(&scenario, &frame).unwrap();
        let geocentric = frame.geocentric_position_launch(&state.position_m);
        // r = a (1 − e²) / (1 + e cos ν), ν = 160°.
        let expected_radius_m =
            6_878_137.0 * (1.0 - 0.001 * 0.001) / (1.0 + 0.001 * 160.0_f64.to_radians().cos());
        assert!((geocentric.norm() - expected_radius_m).abs() < 1e-6);
        // Inclination: the orbit normal makes 97.4° with the ECEF z axis at the epoch (the
        // elements' reference; the rotation axis of the day is 0.26″ from it).
        let normal = geocentric.cross(&state.velocity_mps).normalize();
        let z_launch = frame.launch_from_ecef() * Vector3::z();
        let inclination_deg = normal.dot(&z_launch).acos().to_degrees();
        assert!((inclination_deg - 97.4).abs() < 1e-9, "{inclination_deg}");
        // The orbit plane contains the launch site direction (within the 0.19° geodetic vs
        // geocentric latitude difference of the node placement).
        let site_direction = (-frame.earth_centre_launch_m()).normalize();
        let out_of_plane_deg = normal.dot(&site_direction).asin().to_degrees();
        assert!(out_of_plane_deg.abs() < 0.5, "{out_of_plane_deg}");
        // The vehicle is 21.4° of arc downrange of the site's pass.
        let arc_deg = geocentric
            .normalize()
            .dot(&site_direction)
            .acos()
            .to_degrees();
        assert!((arc_deg - 21.4).abs() < 0.5, "{arc_deg}");
        assert!((state.attitude_q_ib.norm() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn orbit_elements_give_the_right_radius_energy_and_plane() {
        let (a, e, i, raan, perigee, nu) = (7.0e6, 0.1, 0.9, 2.0, 0.4, 1.1);
        let (position, velocity) =
            orbit_state_from_elements(a, e, i, raan, perigee, nu, MU_M3_PER_S2);
        let expected_radius = a * (1.0 - e * e) / (1.0 + e * nu.cos());
        assert!((position.norm() - expected_radius).abs() < 1e-6);
        // Vis-viva: ½v² − μ/r = −μ/(2a).
        let energy = 0.5 * velocity.norm_squared() - MU_M3_PER_S2 / position.norm();
        assert!((energy + MU_M3_PER_S2 / (2.0 * a)).abs() < 1e-6 * MU_M3_PER_S2 / a);
        // Orbit normal = R3(Ω) R1(i) z = [sin i sin Ω, −sin i cos Ω, cos i].
        let normal = position.cross(&velocity).normalize();
        let expected_normal = Vector3::new(i.sin() * raan.sin(), -i.sin() * raan.cos(), i.cos());
        assert!((normal - expected_normal).norm() < 1e-12);
        // Argument of latitude u = ω + ν: z = r sin i sin u.
        assert!((position.z - expected_radius * i.sin() * (perigee + nu).sin()).abs() < 1e-6);
    }

    #[test]
    fn constant_rate_about_z_gives_the_analytic_attitude() {
        let rate_deg_per_s = 100.0;
        let duration_s = 3.0;
        let initial_attitude = exp_rotation_vector(&Vector3::new(0.3, -0.2, 0.1));
        let initial = TruthState {
            time_s: 10.0,
            attitude_q_ib: initial_attitude,
            position_m: Vector3::zeros(),
            velocity_mps: Vector3::zeros(),
        };
        let commands = profile(
            &[segment(
                duration_s,
                0.0,
                [0.0, 0.0, rate_deg_per_s],
                [0.0; 3],
            )],
            10.0,
        );
        let truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 16).unwrap();
        let mut worst_error = 0.0_f64;
        let mut frames = 0;
        for frame in truth {
            let frame = frame.unwrap();
            frames += 1;
            let elapsed_s = frame.time_s - 10.0;
            let expected = initial_attitude
                * exp_rotation_vector(&Vector3::new(
                    0.0,
                    0.0,
                    rate_deg_per_s.to_radians() * elapsed_s,
                ));
            let error = (frame.attitude_q_ib - expected).norm();
            worst_error = worst_error.max(error);
            let expected_increment = rate_deg_per_s.to_radians() * 0.002;
            // Frame times are t0 + kT with t0 = 10 s: their rounding (~2e-15 s) limits Δθ.
            let increment_error =
                (frame.delta_angle_rad - Vector3::new(0.0, 0.0, expected_increment)).norm();
            assert!(increment_error < 1e-14, "{increment_error}");
        }
        println!("attitude: worst quaternion error {worst_error:.3e} over {frames} frames");
        assert_eq!(frames, 1500);
        assert!(worst_error < 1e-12);
    }

    #[test]
    fn thrust_phase_changes_velocity_by_the_analytic_amount() {
        // 50 m/s² along body y with 1 s raised-cosine ramps over 5 s: Δv = 50 (5 − 1) = 200 m/s
        // along C(q) y, position change = ∫∫ f = 50 (∫₀^5 S(τ) dτ).
        let attitude = exp_rotation_vector(&Vector3::new(0.4, 0.2, -0.9));
        let initial = TruthState {
            time_s: 0.0,
            attitude_q_ib: attitude,
            position_m: Vector3::new(1.0, 2.0, 3.0),
            velocity_mps: Vector3::new(10.0, 0.0, 0.0),
        };
        let commands = profile(&[segment(5.0, 1.0, [0.0; 3], [0.0, 50.0, 0.0])], 0.0);
        let mut truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 8).unwrap();
        let mut body_delta_velocity = Vector3::zeros();
        let mut last = initial;
        while let Some(frame) = truth.next_frame().unwrap() {
            body_delta_velocity += frame.delta_velocity_mps;
            last = frame.state();
        }
        let direction = nav_core::attitude::rotate(&attitude, &Vector3::y());
        let velocity_change = last.velocity_mps - initial.velocity_mps;
        assert!(
            (velocity_change - direction * 200.0).norm() < 1e-10,
            "{velocity_change:?}"
        );
        assert!((body_delta_velocity - Vector3::new(0.0, 200.0, 0.0)).norm() < 1e-10);
        // ∫₀^5 S: the pulse is symmetric, so ∫₀^D S(τ)dτ = (D − ramp) · D / 2.
        let expected_displacement = initial.velocity_mps * 5.0 + direction * 50.0 * 4.0 * 2.5;
        let displacement = last.position_m - initial.position_m;
        assert!(
            (displacement - expected_displacement).norm() < 1e-9,
            "{displacement:?}"
        );
        // The attitude did not move.
        assert!((last.attitude_q_ib - attitude).norm() < 1e-15);
    }

    #[test]
    fn rotation_and_thrust_together_rotate_the_velocity_increment() {
        // Constant rate ω about z with constant body force f along x from t = 0: in inertial
        // axes the force direction rotates, v(T) = C0 (f/ω) [sin ωT, 1 − cos ωT, 0].
        // (The sculling/rotation-compensation content a strapdown must reproduce.)
        let rate_rad_per_s = 2.0_f64.to_radians() * 50.0;
        let force_mps2 = 20.0;
        let duration_s = 2.0;
        let attitude = exp_rotation_vector(&Vector3::new(-0.1, 0.7, 0.2));
        let initial = TruthState {
            time_s: 0.0,
            attitude_q_ib: attitude,
            position_m: Vector3::zeros(),
            velocity_mps: Vector3::zeros(),
        };
        let commands = profile(
            &[segment(
                duration_s,
                0.0,
                [0.0, 0.0, rate_rad_per_s.to_degrees()],
                [force_mps2, 0.0, 0.0],
            )],
            0.0,
        );
        let mut truth = TruthSimulator::new(initial, commands, no_gravity, 0.002, 16).unwrap();
        let mut last = initial;
        while let Some(frame) = truth.next_frame().unwrap() {
            last = frame.state();
        }
        let angle = rate_rad_per_s * duration_s;
        let expected = nav_core::attitude::rotate(
            &attitude,
            &(Vector3::new(angle.sin(), 1.0 - angle.cos(), 0.0) * (force_mps2 / rate_rad_per_s)),
        );
        assert!(
            (last.velocity_mps - expected).norm() < 1e-11,
            "{:?}",
            last.velocity_mps - expected
        );
    }

    #[test]
    fn segments_are_found_and_frames_never_straddle_them() {
        let commands = profile(
            &[
                segment(1.0, 0.0, [0.0; 3], [0.0; 3]),
                segment(2.0, 0.5, [10.0, 0.0, 0.0], [0.0; 3]),
            ],
            100.0,
        );
        assert!((commands.segment_at(100.999).unwrap().duration_s - 1.0).abs() < 1e-15);
        assert!((commands.segment_at(101.0).unwrap().duration_s - 2.0).abs() < 1e-15);
        assert!(commands.segment_at(103.0).is_some());
        assert!(commands.segment_at(103.001).is_none());
        let initial = TruthState {
            time_s: 100.0,
            attitude_q_ib: Quaternion::identity(),
            position_m: Vector3::zeros(),
            velocity_mps: Vector3::zeros(),
        };
        let truth = TruthSimulator::new(initial, commands, no_gravity, 0.01, 4).unwrap();
        assert_eq!(truth.frame_count(), 300);
        let frames: Vec<TruthFrame> = truth.map(Result::unwrap).collect();
        assert_eq!(frames.len(), 300);
        assert_eq!(frames[99].segment_index, 0);
        assert_eq!(frames[100].segment_index, 1);
        let total_angle: f64 = frames.iter().map(|frame| frame.delta_angle_rad.x).sum();
        assert!((total_angle - 10.0_f64.to_radians() * 1.5).abs() < 1e-14);
    }

    #[test]
    fn bad_settings_are_errors() {
        let initial = TruthState {
            time_s: 0.0,
            attitude_q_ib: Quaternion::identity(),
            position_m: Vector3::zeros(),
            velocity_mps: Vector3::zeros(),
        };
        let commands = profile(&[segment(1.0, 0.0, [0.0; 3], [0.0; 3])], 0.0);
        assert!(TruthSimulator::new(initial, commands.clone(), no_gravity, 0.0, 4).is_err());
        assert!(TruthSimulator::new(initial, commands, no_gravity, 0.002, 0).is_err());
    }
}
