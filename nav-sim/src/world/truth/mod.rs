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
//! dv/dt    = C(q_ib) f(t) + g(r, t)       (g: point mass + J2, the flight code's model,
//!                                          plus a published model's remainder if chosen)
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
use crate::setup::launch::{Launch, TruthState};
use crate::setup::SetupError;
use crate::world::gravity::gfc::GfcError;
use crate::world::gravity::{RemainderTracker, RotatingRemainder};

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
    /// The scenario's gravity model file could not be read.
    #[error(transparent)]
    GravityModel(#[from] GfcError),
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
/// By default the truth uses the same model as the flight code (nav-core's point mass + J2),
/// so a navigation error cannot come from a truth/flight gravity mismatch; the scenario's
/// `[gravity]` table adds a published model's remainder ([`TruthGravity`]); tests substitute
/// simpler fields (any `Fn(&Vector3<f64>) -> Vector3<f64>`, time-independent).
pub trait GravityField {
    /// Gravitational acceleration `g(r, t)` (m/s²) at launch-inertial position `r` (m) and
    /// navigation time `t` (s): a field fixed to the rotating Earth depends on `t`.
    ///
    /// # Errors
    /// A human-readable reason when the position is refused.
    fn acceleration_mps2(
        &self,
        time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String>;

    /// Called by the truth at the start of every IMU frame with the state there, before the
    /// frame's first evaluation; a field evaluated at a lower rate refreshes here. Does
    /// nothing by default.
    ///
    /// # Errors
    /// A human-readable reason when the position is refused.
    fn start_frame(&mut self, _time_s: f64, _position_m: &Vector3<f64>) -> Result<(), String> {
        Ok(())
    }
}

impl<F> GravityField for F
where
    F: Fn(&Vector3<f64>) -> Vector3<f64>,
{
    fn acceleration_mps2(
        &self,
        _time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String> {
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
    #[inline]
    fn acceleration_mps2(
        &self,
        _time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String> {
        let gravity = self.model.gravity_launch_mps2(&self.frame, position_m);
        if nav_core::attitude::all_finite3(&gravity) {
            Ok(gravity)
        } else {
            Err("non-finite gravity (position at the Earth centre or non-finite)".to_string())
        }
    }
}

/// The truth's gravity: the flight code's ([`FlightGravity`]) and, when the scenario chooses a
/// published model, its remainder beyond point mass + `J2`, evaluated every
/// [`crate::world::gravity::REFRESH_INTERVAL_S`] and Taylor-expanded in between
/// ([`crate::world::gravity`]).
#[derive(Debug, Clone)]
pub struct TruthGravity {
    /// Point mass + `J2`, exactly at every evaluation.
    pub flight: FlightGravity,
    /// The published model's remainder, if any.
    pub remainder: Option<RemainderTracker>,
}

impl GravityField for TruthGravity {
    #[inline]
    fn acceleration_mps2(
        &self,
        time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String> {
        let gravity = self.flight.acceleration_mps2(time_s, position_m)?;
        match &self.remainder {
            None => Ok(gravity),
            Some(remainder) => Ok(gravity + remainder.acceleration_mps2(time_s, position_m)?),
        }
    }

    fn start_frame(&mut self, time_s: f64, position_m: &Vector3<f64>) -> Result<(), String> {
        match &mut self.remainder {
            None => Ok(()),
            Some(remainder) => remainder.start_frame(time_s, position_m),
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
        self.gravity
            .start_frame(start_time_s, &state.position_m)
            .map_err(|reason| gravity_error(start_time_s, &state.position_m, reason))?;
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
        let gravity = self
            .gravity
            .acceleration_mps2(time_s, position)
            .map_err(|reason| gravity_error(time_s, position, reason))?;
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

/// [`TruthError::Gravity`] at `time_s` and `position_m`.
fn gravity_error(time_s: f64, position_m: &Vector3<f64>, reason: String) -> TruthError {
    TruthError::Gravity {
        time_s,
        position_m: [position_m.x, position_m.y, position_m.z],
        reason,
    }
}

impl TruthSimulator<TruthGravity> {
    /// The scenario's truth: initial state from [`Launch::new`], its manoeuvre schedule, the
    /// flight code's gravity with J2 (plus the `[gravity]` table's published model, if any),
    /// at the IMU rate with the configured substeps.
    ///
    /// # Errors
    /// [`TruthError::Setup`], [`TruthError::GravityModel`] or [`TruthError::Setting`].
    pub fn from_scenario(scenario: &Scenario) -> Result<Self, TruthError> {
        Self::from_launch(scenario, &Launch::new(scenario)?)
    }

    /// [`TruthSimulator::from_scenario`] for the scenario's `launch`, already computed.
    ///
    /// # Errors
    /// [`TruthError::GravityModel`] or [`TruthError::Setting`].
    pub fn from_launch(scenario: &Scenario, launch: &Launch) -> Result<Self, TruthError> {
        let remainder = RotatingRemainder::from_settings(scenario.gravity.as_ref(), launch.frame)?;
        Self::new(
            launch.truth_start,
            CommandProfile::from_scenario(scenario),
            TruthGravity {
                flight: FlightGravity {
                    frame: launch.frame,
                    model: GravityModel { j2_enabled: true },
                },
                remainder: remainder.map(RemainderTracker::new),
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
mod tests;
