//! One optical head of the star tracker: its mounting, installation error, white noise, slow
//! errors, aberration, rate limit, re-acquisition and outages, and its own random streams
//! (head 0, `[star_sensor]`, draws from the streams the single tracker always had; head `h ≥ 1`
//! from [`Stream::star_noise`]`(h)` and [`Stream::star_slow_error`]`(h)`). A head measures
//! `q_is,m = q_ib ⊗ q_bs ⊗ q_ψ ⊗ [exp(a_s)] ⊗ [exp(ε_slow)] ⊗ exp(n)` (the module docs of
//! [`super`]); every head samples at the same frames, so their time tags coincide.

use nalgebra::{Quaternion, Vector3};
use nav_core::attitude::{canonical, exp_rotation_vector};
use rand_chacha::ChaCha8Rng;

use super::star_errors::StarSlowErrors;
use super::{normal3, vector, SensorEvent};
use crate::scenario::{StarAberration, StarSensorSettings};
use crate::setup::streams::{self, Stream};
use crate::world::truth::TruthFrame;

/// The true alignment of one head as its measurement sees it now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StarHeadAlignment {
    /// Nominal mounting `q_bs`, sensor → body (known to the flight code).
    pub mounting_q_bs: Quaternion<f64>,
    /// The installation error `q_ψ = exp(ψ)`, times `exp(ε_slow)` at the head's last sample
    /// when it has slowly varying errors (the measurement cannot tell them apart).
    pub installation_q_psi: Quaternion<f64>,
}

impl StarHeadAlignment {
    /// The head's true sensor → body rotation `q_bs ⊗ q_ψ`.
    pub fn installed_q_bs(&self) -> Quaternion<f64> {
        self.mounting_q_bs * self.installation_q_psi
    }

    /// The alignment of this head `h` relative to `head_0`: `q_ab = (q_bs,0 q_ψ,0)⁻¹ ⊗
    /// (q_bs,h q_ψ,h)`, head `h`'s sensor axes (b) → head 0's sensor axes (a), canonical
    /// (`w ≥ 0`). With both true sensor → body rotations `q_b s_k = q_bs,k q_ψ,k`, a vector
    /// `v_h` in head `h`'s axes is `q_b s_h v_h` in body axes and `q_b s_0⁻¹ q_b s_h v_h` in head
    /// 0's. The inverse of a unit quaternion is its conjugate.
    pub fn relative_to(&self, head_0: &Self) -> Quaternion<f64> {
        canonical(&(head_0.installed_q_bs().conjugate() * self.installed_q_bs()))
    }
}

/// One head's models and state.
#[derive(Debug, Clone)]
pub(super) struct StarHead {
    /// The head's number (0 = `[star_sensor]`), carried by its events.
    head: usize,
    mounting_q_bs: Quaternion<f64>,
    installation_q_psi: Quaternion<f64>,
    /// The white noise's 1σ about sensor x, y and z (rad).
    noise_rad: Vector3<f64>,
    rng: ChaCha8Rng,
    /// The slowly varying errors ([`super::star_errors`]); `None` when off, and then the
    /// measurement is the model without them, bit for bit.
    slow: Option<StarSlowErrors>,
    /// Whether the measured attitude carries the velocity aberration
    /// ([`aberration_rotation_rad`]).
    aberration: bool,
    max_rate_rad_s: f64,
    reacquisition_s: f64,
    /// `[[start_s, duration_s], ...]` after the scenario start.
    outages: Vec<[f64; 2]>,
    /// The head delivers nothing before this time (s): it lost track.
    blind_until_s: f64,
    /// Scenario start (s), the origin of the outage times.
    start_time_s: f64,
}

impl StarHead {
    /// Head `head` from its (validated) `settings`, its streams from `seed`.
    pub(super) fn new(
        head: usize,
        settings: &StarSensorSettings,
        seed: u64,
        start_time_s: f64,
    ) -> Self {
        let [mount_x, mount_y, mount_z] = settings.mounting_rotation_vector_deg;
        Self {
            head,
            mounting_q_bs: exp_rotation_vector(&Vector3::new(
                mount_x.to_radians(),
                mount_y.to_radians(),
                mount_z.to_radians(),
            )),
            installation_q_psi: exp_rotation_vector(&vector(
                settings.installation_error_rotation_vector_rad,
            )),
            noise_rad: Vector3::from(settings.noise_per_axis_rad()),
            rng: streams::rng(seed, Stream::star_noise(head)),
            slow: StarSlowErrors::new(settings, start_time_s, || {
                streams::rng(seed, Stream::star_slow_error(head))
            }),
            aberration: settings.aberration == StarAberration::Uncorrected,
            max_rate_rad_s: settings.max_rate_deg_per_s.to_radians(),
            reacquisition_s: settings.reacquisition_s,
            outages: settings.outages.clone(),
            blind_until_s: f64::NEG_INFINITY,
            start_time_s,
        }
    }

    /// The head's alignment now (the slow errors at its last sample).
    pub(super) fn alignment(&self) -> StarHeadAlignment {
        StarHeadAlignment {
            mounting_q_bs: self.mounting_q_bs,
            installation_q_psi: match &self.slow {
                None => self.installation_q_psi,
                Some(slow) => self.installation_q_psi * exp_rotation_vector(&slow.last()),
            },
        }
    }

    /// Whether the head tracks during `truth`'s frame: not while the body rate's magnitude
    /// (the frame's mean, `|Δθ| / T`) exceeds its `max_rate_deg_per_s`, nor for its
    /// `reacquisition_s` after it falls back below. Called on every frame.
    pub(super) fn tracking(&mut self, truth: &TruthFrame) -> bool {
        star_tracker_tracks(
            truth,
            self.max_rate_rad_s,
            self.reacquisition_s,
            &mut self.blind_until_s,
        )
    }

    /// The sample valid at the end of `truth`'s frame, pushed to `events` if the head is
    /// `tracking` and not in an outage; `gcrf_from_launch_q` is `q_ig*`. Drawn whether or not
    /// it is delivered: the noise of every other sample stays what it is without the outage.
    pub(super) fn sample(
        &mut self,
        truth: &TruthFrame,
        tracking: bool,
        gcrf_from_launch_q: &Quaternion<f64>,
        events: &mut Vec<SensorEvent>,
    ) {
        // Per axis; with the same σ on every axis the same bits as `normal3 · σ`.
        let noise = normal3(&mut self.rng).component_mul(&self.noise_rad);
        let mut installed = truth.attitude_q_ib * self.mounting_q_bs * self.installation_q_psi;
        if self.aberration {
            let rotation = aberration_rotation_rad(&installed, &truth.velocity_mps);
            installed *= exp_rotation_vector(&rotation);
        }
        let measured = match &mut self.slow {
            None => installed * exp_rotation_vector(&noise),
            Some(slow) => {
                installed
                    * exp_rotation_vector(&slow.at(truth.time_s))
                    * exp_rotation_vector(&noise)
            }
        };
        let elapsed_s = truth.time_s - self.start_time_s;
        if tracking && !crate::scenario::in_outage(&self.outages, elapsed_s) {
            events.push(SensorEvent::Star {
                head: self.head,
                time_tag_s: truth.time_s,
                attitude_q_gs: canonical(&(*gcrf_from_launch_q * measured.normalize())),
            });
        }
    }
}

/// The rotation (rad, sensor axes) by which velocity aberration turns the attitude a
/// tracker of true sensor-to-inertial attitude `q_is` reports at the inertial velocity
/// `velocity_mps`: `a_s = β_s × z`, `β_s = C_isᵀ v / c` (docs/guide/model.md, "Star sensor
/// truth", and nav-core `aberration` for the derivation; the sign is proven against star
/// directions displaced by the nonlinear formula in `aberration_tests.rs`). Written here
/// apart from the flight code's correction, which it checks.
pub fn aberration_rotation_rad(
    q_is: &Quaternion<f64>,
    velocity_mps: &Vector3<f64>,
) -> Vector3<f64> {
    let beta_sensor = nalgebra::UnitQuaternion::from_quaternion(*q_is)
        .inverse_transform_vector(velocity_mps)
        / nav_core::aberration::SPEED_OF_LIGHT_MPS;
    beta_sensor.cross(&Vector3::z())
}

/// Whether a star tracker that loses its stars above `max_rate_rad_s` (0 = no limit) and
/// needs `reacquisition_s` to find them again tracks during `truth`'s frame: not while the
/// frame's mean body rate `|Δθ| / T` exceeds the limit, nor until `blind_until_s`, which a
/// frame above the limit moves to its end plus the re-acquisition time.
pub fn star_tracker_tracks(
    truth: &TruthFrame,
    max_rate_rad_s: f64,
    reacquisition_s: f64,
    blind_until_s: &mut f64,
) -> bool {
    if max_rate_rad_s <= 0.0 {
        return true;
    }
    let rate_rad_s = truth.delta_angle_rad.norm() / truth.interval_s;
    if rate_rad_s > max_rate_rad_s {
        *blind_until_s = truth.time_s + reacquisition_s;
        return false;
    }
    truth.time_s >= *blind_until_s
}
