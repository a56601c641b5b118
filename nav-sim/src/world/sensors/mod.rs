//! Sensor error models: IMU (paper eqs. 1 and 3), star sensor and GNSS, producing a seeded,
//! deterministic, time-ordered stream of [`SensorEvent`]s from the truth.
//!
//! ## IMU (per frame of length `T`, body axes)
//! The paper's rate model `ω_m = ω + Λg ω_m + b_g + η_g` (eq. 1), integrated over the frame,
//! gives for the increments
//!
//! ```text
//! Δθ_m = (I − Λg)⁻¹ (Δθ + b_g T + n_g),   n_g ~ N(0, σ_g² T I),  σ_g = rate-noise density
//! Δv_m = (I − Λa)⁻¹ (Δv + b_a T + n_a),   n_a ~ N(0, (σ_a T)² I), σ_a = per-sample noise
//! ```
//!
//! (eq. 3 likewise; `Λ` diagonal, so the inverse is a per-axis division by `1 − λ`). The gyro
//! noise is white rate noise integrated over the frame (`σ_Δθ = σ_g √T`); the accelerometer's
//! 1e-4 m/s² is a per-sample specific-force σ held over the frame (`σ_Δv = σ_a T`); see the
//! default scenario for why. Optional: bias random walk `b_{k+1} = b_k + σ_rw √T w_k` (the
//! bias of frame `k` is `b_k`), and output quantisation with the residual carried to the next
//! frame (as pulse-output IMUs do), so no error accumulates. Optional too: misalignment,
//! gyro g-sensitivity and bias instability, entering before the bias (`imu_errors.rs`).
//!
//! ## Star sensor
//! `q_is,m = q_ib ⊗ q_bs ⊗ q_ψ ⊗ exp(n)`, `n ~ N(0, diag(σ_x², σ_y², σ_z²))` a small rotation
//! in sensor axes (`σ_x = σ_y` cross-boresight, `σ_z` roll about the boresight; all `σ_s`
//! unless the per-axis keys are given), optionally with the slow errors `exp(ε_slow)` between
//! `q_ψ` and `exp(n)` (`star_errors.rs`),
//! `q_bs` the nominal (known) mounting, `q_ψ = exp(ψ)` the installation error (unknown) with
//! `ψ` a rotation vector in rad. Model.md's `q_s,meas = q_s ⊗ q_ψ` with `q_s = q_ib ⊗ q_bs`.
//! The filter's installation state is the vector part of `q_ψ`, `sin(|ψ|/2) ψ/|ψ| ≈ ψ/2`
//! ([`SensorErrorTruth::star_installation_vector_part`]). Output canonicalised to `w ≥ 0`.
//! With `aberration = "uncorrected"` the velocity aberration `exp(a_s)`
//! ([`aberration_rotation_rad`], docs/guide/model.md) follows `q_ψ`, before the slow errors.
//! The tracker may have several heads (`star_head.rs`), each this model with its own
//! settings and random streams; head 0 is `[star_sensor]`, and its events and truth are
//! what they are without the other heads, bit for bit.
//!
//! ## GNSS
//! ECEF position of the truth (the IMU's position; no lever arm) at the fix's time of validity,
//! through nav-core's `LaunchFrame::launch_inertial_to_ecef`, plus `N(0, σ² I)` per ECEF axis.
//! Delivered `latency_s` later (a whole number of IMU frames).
//!
//! ## Stream order and timing
//! For every truth frame `k` (`[t_k, t_k+1]`): first `Imu` (time tag `t_k+1`), then the star
//! samples valid at `t_k+1` in head order, then any GNSS fix delivered at `t_k+1`. Measurements are sampled at
//! whole multiples of their period after the scenario start (the IMU rate is a whole multiple of
//! each measurement rate). Each error source draws from its own ChaCha8 stream of the scenario
//! seed, so changing one sensor's settings never changes another's noise, and a seed reproduces
//! the stream bit for bit on any platform (`rand_distr::StandardNormal` is pure IEEE arithmetic
//! plus `ln`/`exp` from the platform's libm; the host builds agree).

use nalgebra::{Matrix3, Quaternion, Vector3};
use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
use nav_fsw::sensor_frames::SensorFrames;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::scenario::{frames_in, Scenario};
use crate::setup::launch::Launch;
use crate::setup::streams::{self, Stream};
use crate::world::truth::TruthFrame;
use imu_errors::TriadExtras;
use star_head::StarHead;
pub use star_head::{aberration_rotation_rad, star_tracker_tracks, StarHeadAlignment};

/// One sensor output, in delivery order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SensorEvent {
    /// IMU increments over frame `frame_index`, ending at `time_s`.
    Imu {
        /// Frame counter (0 = the first frame of the scenario).
        frame_index: u64,
        /// End of the frame: the increments' time tag (s).
        time_s: f64,
        /// Frame length `T` (s).
        interval_s: f64,
        /// Measured delta angle (rad, body axes).
        delta_angle_rad: Vector3<f64>,
        /// Measured delta velocity (m/s, body axes).
        delta_velocity_mps: Vector3<f64>,
    },
    /// Star-sensor attitude from one head of the tracker.
    Star {
        /// The head (0 = `[star_sensor]`, `h` = the `h`-th
        /// `[[star_sensor.additional_heads]]`); the heads of one frame come in head order.
        head: usize,
        /// Time of validity (s, navigation time).
        time_tag_s: f64,
        /// Measured `q_gs`, sensor to GCRF, canonical (`w ≥ 0`).
        attitude_q_gs: Quaternion<f64>,
    },
    /// GNSS position fix.
    Gnss {
        /// Time of validity (s, navigation time: the simulator's own clock).
        time_tag_s: f64,
        /// Time of validity as the receiver tags it: GPS week.
        gps_week: u32,
        /// Time of validity as the receiver tags it: GPS seconds of week (s).
        gps_seconds_of_week: f64,
        /// Time the fix is delivered, `time_tag_s + latency` (s).
        delivery_time_s: f64,
        /// Measured ECEF position (m, WGS-84).
        position_ecef_m: Vector3<f64>,
        /// Measured ECEF velocity relative to the rotating Earth (m/s), from a receiver that
        /// outputs it (`gnss.velocity_noise_mps > 0`).
        velocity_ecef_mps: Option<Vector3<f64>>,
    },
}

impl SensorEvent {
    /// Time at which the event becomes available to the flight code (s): the IMU frame end,
    /// the star time tag, the GNSS delivery time.
    pub fn delivery_time_s(&self) -> f64 {
        match self {
            Self::Imu { time_s, .. } => *time_s,
            Self::Star { time_tag_s, .. } => *time_tag_s,
            Self::Gnss {
                delivery_time_s, ..
            } => *delivery_time_s,
        }
    }

    /// The IMU event as the flight software's port sample (sequence = frame index modulo 2³²,
    /// the counter of a real IMU wraps), or `None` for other events.
    pub fn to_imu_sample(&self) -> Option<ImuSample> {
        match self {
            Self::Imu {
                frame_index,
                time_s,
                delta_angle_rad,
                delta_velocity_mps,
                ..
            } => Some(ImuSample::new(
                // Truncation to the low 32 bits is the intended wrap-around.
                (*frame_index & u64::from(u32::MAX)) as u32,
                *time_s,
                [delta_angle_rad.x, delta_angle_rad.y, delta_angle_rad.z],
                [
                    delta_velocity_mps.x,
                    delta_velocity_mps.y,
                    delta_velocity_mps.z,
                ],
            )),
            _ => None,
        }
    }

    /// The star event as the flight software's port measurement, with its head (the caller
    /// chooses which heads to hand over), or `None` (also for a head beyond 255).
    pub fn to_star_measurement(&self) -> Option<StarMeasurement> {
        match self {
            Self::Star {
                time_tag_s,
                attitude_q_gs,
                head,
            } => Some(StarMeasurement::new(
                *time_tag_s,
                [
                    attitude_q_gs.w,
                    attitude_q_gs.i,
                    attitude_q_gs.j,
                    attitude_q_gs.k,
                ],
                u8::try_from(*head).ok()?,
            )),
            _ => None,
        }
    }

    /// The GNSS event as the flight software's port fix, or `None`.
    pub fn to_gnss_fix(&self) -> Option<GnssFix> {
        match self {
            Self::Gnss {
                gps_week,
                gps_seconds_of_week,
                position_ecef_m,
                velocity_ecef_mps,
                ..
            } => Some(
                GnssFix::new(
                    *gps_week,
                    *gps_seconds_of_week,
                    [position_ecef_m.x, position_ecef_m.y, position_ecef_m.z],
                )
                .with_velocity_ecef_mps(velocity_ecef_mps.map(|v| [v.x, v.y, v.z])),
            ),
            _ => None,
        }
    }
}

/// Why the sensor simulation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensorError {
    /// nav-core refused a frame conversion (non-finite truth).
    #[error("GNSS at t = {time_s} s: launch-inertial to ECEF conversion failed: {reason}")]
    FrameConversion {
        /// Time of validity of the fix (s).
        time_s: f64,
        /// nav-core's error.
        reason: String,
    },
    /// The scenario's launch site was refused.
    #[error("launch site refused by nav-core: {0}")]
    LaunchSite(String),
}

/// The true sensor errors (what the calibration should find), at the current time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorErrorTruth {
    /// Gyro bias `b_g` (rad/s); drifts only with a bias random walk.
    pub gyro_bias_rad_per_s: Vector3<f64>,
    /// Gyro scale factors, diagonal of `Λg`.
    pub gyro_scale_factor: Vector3<f64>,
    /// Accelerometer bias `b_a` (m/s²).
    pub accel_bias_mps2: Vector3<f64>,
    /// Accelerometer scale factors, diagonal of `Λa`.
    pub accel_scale_factor: Vector3<f64>,
    /// Head 0's alignment error as its measurement sees it now: the installation
    /// error `q_ψ = exp(ψ)`, times `exp(ε_slow)` at the last star sample when the tracker
    /// has slowly varying errors. The measurement model cannot tell the two apart (they
    /// stand side by side in `q_ib ⊗ q_bs ⊗ q_ψ ⊗ exp(ε_slow) ⊗ δq`), so this is what the
    /// filter's installation state estimates; without slow errors it is `q_ψ`.
    pub star_installation_q_psi: Quaternion<f64>,
    /// Head 0's nominal mounting `q_bs` (known to the flight code).
    pub star_mounting_q_bs: Quaternion<f64>,
    /// Gyro misalignment and non-orthogonality `A_g` (rad, zero diagonal; zero when off).
    pub gyro_misalignment_rad: Matrix3<f64>,
    /// Accelerometer misalignment and non-orthogonality `A_a` (rad; zero when off).
    pub accel_misalignment_rad: Matrix3<f64>,
    /// Gyro g-sensitivity, the diagonal of `G` (rad/s per m/s²; zero when off).
    pub gyro_g_sensitivity_rad_s_per_mps2: Vector3<f64>,
}

impl SensorErrorTruth {
    /// The vector part of `q_ψ`: the filter's installation-error state (≈ ψ/2).
    pub fn star_installation_vector_part(&self) -> Vector3<f64> {
        self.star_installation_q_psi.imag()
    }
}

fn normal3(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    let x: f64 = rng.sample(StandardNormal);
    let y: f64 = rng.sample(StandardNormal);
    let z: f64 = rng.sample(StandardNormal);
    Vector3::new(x, y, z)
}

fn vector(components: [f64; 3]) -> Vector3<f64> {
    Vector3::new(components[0], components[1], components[2])
}

/// One IMU triad (gyro or accelerometer): `Δ_m = (I − Λ)⁻¹ (Δ + b T + n)`.
#[derive(Debug, Clone)]
struct TriadModel {
    bias: Vector3<f64>,
    scale_factor: Vector3<f64>,
    /// `σ_n(T)`: noise 1σ per increment for the frame period (units of the increment).
    increment_noise_sigma: f64,
    bias_walk_per_sqrt_s: f64,
    quantum: f64,
    noise_rng: ChaCha8Rng,
    bias_walk_rng: ChaCha8Rng,
    /// Σ unquantised output so far, and Σ quantised output so far (quantisation residual
    /// carried forward).
    continuous_total: Vector3<f64>,
    quantised_total: Vector3<f64>,
    /// Misalignment, g-sensitivity and bias instability ([`imu_errors`]); `None` when all
    /// are off, and then the measurement is the paper's model alone, bit for bit.
    extras: Option<TriadExtras>,
}

impl TriadModel {
    /// The measured increment for the true `true_increment` (and, for the gyro's
    /// g-sensitivity, the true velocity increment `specific_force_increment`).
    fn measure(
        &mut self,
        true_increment: &Vector3<f64>,
        specific_force_increment: &Vector3<f64>,
        interval_s: f64,
    ) -> Vector3<f64> {
        let noise = if self.increment_noise_sigma > 0.0 {
            normal3(&mut self.noise_rng) * self.increment_noise_sigma
        } else {
            Vector3::zeros()
        };
        let perturbed = match &self.extras {
            None => true_increment + self.bias * interval_s + noise,
            Some(extras) => {
                extras.sensed(true_increment, specific_force_increment, interval_s)
                    + self.bias * interval_s
                    + noise
            }
        };
        let measured = perturbed.component_div(&(Vector3::repeat(1.0) - self.scale_factor));
        if self.bias_walk_per_sqrt_s > 0.0 {
            self.bias +=
                normal3(&mut self.bias_walk_rng) * (self.bias_walk_per_sqrt_s * interval_s.sqrt());
        }
        if let Some(extras) = &mut self.extras {
            extras.advance(interval_s);
        }
        if self.quantum > 0.0 {
            self.continuous_total += measured;
            let quantised_total =
                (self.continuous_total / self.quantum).map(f64::round) * self.quantum;
            let output = quantised_total - self.quantised_total;
            self.quantised_total = quantised_total;
            output
        } else {
            measured
        }
    }
}

impl TriadModel {
    /// The misalignment `A` (zero when off).
    fn misalignment(&self) -> Matrix3<f64> {
        self.extras
            .as_ref()
            .map_or_else(Matrix3::zeros, TriadExtras::misalignment)
    }

    /// The g-sensitivity `g` (zero when off).
    fn g_sensitivity(&self) -> Vector3<f64> {
        self.extras
            .as_ref()
            .map_or_else(Vector3::zeros, TriadExtras::g_sensitivity)
    }

    /// The bias of the next frame: the constant (and random-walk) part plus the bias
    /// instability's, when that is on.
    fn total_bias(&self) -> Vector3<f64> {
        match self.extras.as_ref().and_then(TriadExtras::instability_bias) {
            Some(instability) => self.bias + instability,
            None => self.bias,
        }
    }
}

/// Produces the sensor events for each truth frame.
#[derive(Debug, Clone)]
pub struct SensorSimulator {
    /// The receiver's ECEF: the full IAU 2006/2000A chain at each fix.
    itrf: crate::scenario::epoch::ItrfFromLaunchInertial,
    /// The ground constants: the star tracker's GCRF and the GPS time of the launch.
    sensor_frames: SensorFrames,
    /// `q_ig*`, launch-inertial → GCRF.
    gcrf_from_launch_q: Quaternion<f64>,
    gyro: TriadModel,
    accelerometer: TriadModel,
    /// The tracker's head 0 (`[star_sensor]`).
    star_head_0: StarHead,
    /// Its additional heads, 1, 2, … (`[[star_sensor.additional_heads]]`).
    star_additional_heads: Vec<StarHead>,
    /// Frames between star samples, the same for every head.
    star_frames_per_sample: u64,
    gnss_noise_m: f64,
    gnss_frames_per_sample: u64,
    gnss_latency_s: f64,
    gnss_rng: ChaCha8Rng,
    gnss_correlated: GaussMarkov,
    gnss_velocity_noise_mps: f64,
    gnss_velocity_rng: ChaCha8Rng,
    gnss_outages: Vec<[f64; 2]>,
    /// Scenario start (s), the origin of the outage times.
    start_time_s: f64,
    /// Fixes sampled but not yet delivered, oldest first.
    pending_gnss: std::collections::VecDeque<SensorEvent>,
}

impl SensorSimulator {
    /// Builds the error models from a (validated) scenario.
    ///
    /// # Errors
    /// [`SensorError::LaunchSite`] if the scenario's launch is refused ([`Launch::new`]).
    pub fn new(scenario: &Scenario) -> Result<Self, SensorError> {
        let launch =
            Launch::new(scenario).map_err(|error| SensorError::LaunchSite(error.to_string()))?;
        Ok(Self::with_launch(scenario, &launch))
    }

    /// [`SensorSimulator::new`] for the scenario's `launch`, already computed.
    pub fn with_launch(scenario: &Scenario, launch: &Launch) -> Self {
        let (frame, epoch, ground) = (&launch.frame, &launch.epoch, &launch.ground);
        let [w, x, y, z] = ground.sensor_frames.gcrf_to_launch_inertial_wxyz;
        let seed = scenario.simulation.seed;
        let period_s = scenario.imu.frame_period_s();
        let gyro = &scenario.gyro;
        let accelerometer = &scenario.accelerometer;
        let star = &scenario.star_sensor;
        Self {
            itrf: crate::scenario::epoch::ItrfFromLaunchInertial::new(epoch, frame),
            sensor_frames: ground.sensor_frames,
            gcrf_from_launch_q: Quaternion::new(w, x, y, z).conjugate(),
            gyro: TriadModel {
                bias: vector(gyro.bias_rad_per_s),
                scale_factor: vector(gyro.scale_factor),
                increment_noise_sigma: gyro.delta_angle_noise_sigma_rad(period_s),
                bias_walk_per_sqrt_s: gyro.bias_random_walk_rad_per_s_per_sqrt_s,
                quantum: gyro.quantum_rad,
                noise_rng: streams::rng(seed, Stream::GyroNoise),
                bias_walk_rng: streams::rng(seed, Stream::GyroBiasWalk),
                continuous_total: Vector3::zeros(),
                quantised_total: Vector3::zeros(),
                extras: TriadExtras::new(
                    &gyro.misalignment_rad,
                    &gyro.g_sensitivity_rad_s_per_mps2,
                    (
                        gyro.bias_instability_sigma_rad_per_s,
                        gyro.bias_instability_correlation_time_s,
                    ),
                    || streams::rng(seed, Stream::GyroBiasInstability),
                ),
            },
            accelerometer: TriadModel {
                bias: vector(accelerometer.bias_mps2),
                scale_factor: vector(accelerometer.scale_factor),
                increment_noise_sigma: accelerometer.delta_velocity_noise_sigma_mps(period_s),
                bias_walk_per_sqrt_s: accelerometer.bias_random_walk_mps2_per_sqrt_s,
                quantum: accelerometer.quantum_mps,
                noise_rng: streams::rng(seed, Stream::AccelNoise),
                bias_walk_rng: streams::rng(seed, Stream::AccelBiasWalk),
                continuous_total: Vector3::zeros(),
                quantised_total: Vector3::zeros(),
                extras: TriadExtras::new(
                    &accelerometer.misalignment_rad,
                    &[0.0; 3],
                    (
                        accelerometer.bias_instability_sigma_mps2,
                        accelerometer.bias_instability_correlation_time_s,
                    ),
                    || streams::rng(seed, Stream::AccelBiasInstability),
                ),
            },
            star_head_0: StarHead::new(0, star, seed, scenario.simulation.start_time_s),
            star_additional_heads: star
                .heads()
                .enumerate()
                .skip(1)
                .map(|(head, settings)| {
                    StarHead::new(head, settings, seed, scenario.simulation.start_time_s)
                })
                .collect(),
            star_frames_per_sample: frames_in(1.0 / star.rate_hz, period_s),
            gnss_noise_m: scenario.gnss.noise_m,
            gnss_frames_per_sample: frames_in(1.0 / scenario.gnss.rate_hz, period_s),
            gnss_latency_s: scenario.gnss.latency_s,
            gnss_rng: streams::rng(seed, Stream::Gnss),
            gnss_correlated: GaussMarkov {
                sigma: scenario.gnss.correlated_noise_m,
                correlation_time_s: scenario.gnss.correlation_time_s,
                state: None,
                rng: streams::rng(seed, Stream::GnssCorrelated),
            },
            gnss_velocity_noise_mps: scenario.gnss.velocity_noise_mps,
            gnss_velocity_rng: streams::rng(seed, Stream::GnssVelocity),
            gnss_outages: scenario.gnss.outages.clone(),
            start_time_s: scenario.simulation.start_time_s,
            pending_gnss: std::collections::VecDeque::new(),
        }
    }

    /// The true sensor errors now (biases change only with a bias random walk or a bias
    /// instability; the bias is the sum of both, the one of the next frame).
    pub fn error_truth(&self) -> SensorErrorTruth {
        let head_0 = self.star_head_0.alignment();
        SensorErrorTruth {
            gyro_bias_rad_per_s: self.gyro.total_bias(),
            gyro_scale_factor: self.gyro.scale_factor,
            accel_bias_mps2: self.accelerometer.total_bias(),
            accel_scale_factor: self.accelerometer.scale_factor,
            star_installation_q_psi: head_0.installation_q_psi,
            star_mounting_q_bs: head_0.mounting_q_bs,
            gyro_misalignment_rad: self.gyro.misalignment(),
            accel_misalignment_rad: self.accelerometer.misalignment(),
            gyro_g_sensitivity_rad_s_per_mps2: self.gyro.g_sensitivity(),
        }
    }

    /// The receiver's correlated position error (ECEF, m) at `time_s`: its last fix's value
    /// carried forward by the Gauss–Markov process, drawn from a copy of the process so the
    /// flight's random streams are unchanged (zero when the receiver has none). A time
    /// before the last fix gives the last fix's value.
    pub fn gnss_correlated_error_ecef_m(&self, time_s: f64) -> Vector3<f64> {
        self.gnss_correlated.clone().at(time_s)
    }

    /// Appends to `events` what the sensors deliver during truth frame `truth` (see the module
    /// docs for the order).
    ///
    /// # Errors
    /// [`SensorError::FrameConversion`] if the truth position cannot be converted to ECEF.
    pub fn process_frame(
        &mut self,
        truth: &TruthFrame,
        events: &mut Vec<SensorEvent>,
    ) -> Result<(), SensorError> {
        let interval_s = truth.interval_s;
        events.push(SensorEvent::Imu {
            frame_index: truth.frame_index,
            time_s: truth.time_s,
            interval_s,
            delta_angle_rad: self.gyro.measure(
                &truth.delta_angle_rad,
                &truth.delta_velocity_mps,
                interval_s,
            ),
            delta_velocity_mps: self.accelerometer.measure(
                &truth.delta_velocity_mps,
                &truth.delta_velocity_mps,
                interval_s,
            ),
        });

        let frames_elapsed = truth.frame_index + 1;
        let star_sampled = frames_elapsed % self.star_frames_per_sample == 0;
        let heads = std::iter::once(&mut self.star_head_0).chain(&mut self.star_additional_heads);
        for head in heads {
            let tracking = head.tracking(truth);
            if star_sampled {
                head.sample(truth, tracking, &self.gcrf_from_launch_q, events);
            }
        }

        if frames_elapsed % self.gnss_frames_per_sample == 0 {
            let with_velocity = self.gnss_velocity_noise_mps > 0.0;
            let (position_ecef_m, velocity_ecef_mps) = self.itrf.convert(
                &truth.position_m,
                with_velocity.then_some(&truth.velocity_mps),
                truth.time_s,
            );
            if !(position_ecef_m.iter().all(|v| v.is_finite())) {
                return Err(SensorError::FrameConversion {
                    time_s: truth.time_s,
                    reason: "non-finite ECEF position".to_string(),
                });
            }
            let noise = normal3(&mut self.gnss_rng) * self.gnss_noise_m
                + self.gnss_correlated.at(truth.time_s);
            let velocity_ecef_mps = velocity_ecef_mps.map(|velocity| {
                velocity + normal3(&mut self.gnss_velocity_rng) * self.gnss_velocity_noise_mps
            });
            let (gps_week, gps_seconds_of_week) = self
                .sensor_frames
                .gps_time(truth.time_s)
                .ok_or_else(|| SensorError::FrameConversion {
                    time_s: truth.time_s,
                    reason: "outside GPS weeks 0..=9999".to_string(),
                })?;
            let elapsed_s = truth.time_s - self.start_time_s;
            if !crate::scenario::in_outage(&self.gnss_outages, elapsed_s) {
                self.pending_gnss.push_back(SensorEvent::Gnss {
                    time_tag_s: truth.time_s,
                    gps_week,
                    gps_seconds_of_week,
                    delivery_time_s: truth.time_s + self.gnss_latency_s,
                    position_ecef_m: position_ecef_m + noise,
                    velocity_ecef_mps,
                });
            }
        }
        // Deliver every fix due by the end of this frame (half a frame of tolerance absorbs the
        // rounding of `time + latency`; latencies are whole frames).
        let due_by_s = truth.time_s + 0.5 * interval_s;
        while let Some(fix) = self.pending_gnss.front() {
            if fix.delivery_time_s() > due_by_s {
                break;
            }
            if let Some(fix) = self.pending_gnss.pop_front() {
                events.push(fix);
            }
        }
        Ok(())
    }
}

impl SensorSimulator {
    /// The number of star-tracker heads (1 + the additional heads).
    pub fn star_head_count(&self) -> usize {
        1 + self.star_additional_heads.len()
    }

    /// Head `head`'s true alignment now (its slow errors at its last sample), `None` past the
    /// last head. Head 0's is also in [`SensorSimulator::error_truth`].
    pub fn star_head_alignment(&self, head: usize) -> Option<StarHeadAlignment> {
        match head {
            0 => Some(self.star_head_0.alignment()),
            head => self
                .star_additional_heads
                .get(head - 1)
                .map(StarHead::alignment),
        }
    }

    /// Head `head`'s true alignment relative to head 0 now,
    /// `q_ab = (q_bs,0 q_ψ,0)⁻¹ ⊗ (q_bs,h q_ψ,h)` with each head's slow errors at its last
    /// sample ([`StarHeadAlignment::relative_to`]); `None` past the last head.
    pub fn star_relative_alignment_q(&self, head: usize) -> Option<Quaternion<f64>> {
        self.star_head_alignment(head)
            .map(|alignment| alignment.relative_to(&self.star_head_0.alignment()))
    }
}

/// A first-order Gauss–Markov error per axis, `ε̇ = −ε/τ + w`, stationary 1σ `sigma`: drawn
/// from `N(0, σ²)` at its first sample, then advanced exactly between samples,
/// `ε ← φ ε + σ √(1 − φ²) w`, `φ = exp(−Δt/τ)`. Zero (and no draw) when `sigma` is 0.
#[derive(Debug, Clone)]
struct GaussMarkov {
    sigma: f64,
    correlation_time_s: f64,
    state: Option<(f64, Vector3<f64>)>,
    rng: ChaCha8Rng,
}

impl GaussMarkov {
    /// The error at `time_s` (not before the previous sample).
    fn at(&mut self, time_s: f64) -> Vector3<f64> {
        if self.sigma <= 0.0 {
            return Vector3::zeros();
        }
        let value = match self.state {
            None => normal3(&mut self.rng) * self.sigma,
            Some((last_s, last)) => {
                let phi = (-(time_s - last_s).max(0.0) / self.correlation_time_s).exp();
                last * phi + normal3(&mut self.rng) * (self.sigma * (1.0 - phi * phi).sqrt())
            }
        };
        self.state = Some((time_s, value));
        value
    }
}

#[cfg(test)]
mod aberration_tests;
mod imu_errors;
#[cfg(test)]
mod imu_errors_tests;
mod star_errors;
#[cfg(test)]
mod star_errors_tests;
mod star_head;
#[cfg(test)]
mod star_head_tests;
#[cfg(test)]
mod tests;
