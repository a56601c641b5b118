//! The replay setup: what a scenario decides about the flight software, as 8-byte words.

use nalgebra::{Quaternion, Vector3};
use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterMode, InitialUncertainty};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;

use super::{FrameGrid, DEFAULT_MAX_GAP_S};
use crate::config::FswConfig;
use crate::error::{ConfigField, FswError};
use crate::sensor_frames::SensorFrames;

/// Number of words of a [`ReplaySetup`].
pub const SETUP_WORDS: usize = 79;
/// First word of an encoded setup (`"NAVSETUP"` little-endian).
pub const SETUP_MAGIC: u64 = u64::from_le_bytes(*b"NAVSETUP");

/// The scenario-dependent part of the flight software's configuration and its initial
/// navigation solution; everything else is [`FswConfig::paper_defaults`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySetup {
    /// Launch site.
    pub launch_site: LaunchSite,
    /// The sensors' frames and time scales (ground constants).
    pub sensor_frames: SensorFrames,
    /// Initial navigation solution.
    pub initial: NavigationState,
    /// Filter mode.
    pub mode: FilterMode,
    /// Discretisation order.
    pub discretisation_order: u8,
    /// Initial 1σ.
    pub initial_sigma: InitialUncertainty,
    /// Noise densities.
    pub process_noise: ProcessNoise,
    /// IMU period (s).
    pub imu_period_s: f64,
    /// Star mounting `q_bs` `[w, x, y, z]`.
    pub star_mounting_wxyz: [f64; 4],
    /// Star noise across the boresight, 1σ about sensor `x` and `y` (rad).
    pub star_noise_rad: f64,
    /// Star NIS gate.
    pub star_gate_nis: f64,
    /// GNSS noise 1σ (m).
    pub gnss_noise_m: f64,
    /// GNSS NIS gate.
    pub gnss_gate_nis: f64,
    /// Largest measurement latency (s).
    pub max_latency_s: f64,
    /// The receiver's correlated position error (`filter.gnss_error`).
    pub gnss_error: nav_core::gnss_error::GnssErrorModel,
    /// GNSS velocity noise 1σ (m/s); 0 = velocities not fused.
    pub gnss_velocity_noise_mps: f64,
    /// The gyro's measurement range per axis (rad/s).
    pub imu_max_rate_rad_s: f64,
    /// The accelerometer's measurement range per axis (m/s²).
    pub imu_max_specific_force_mps2: f64,
    /// The systematic IMU error states' prior (`filter.imu_error`).
    pub imu_error: nav_core::imu_error_states::ImuErrorModel,
    /// The gravity field beyond `J2` and the allowance for what it omits (`gravity`).
    pub gravity: crate::config::GravityConfig,
    /// Star noise about the boresight, 1σ about sensor `z` (rad).
    pub star_roll_noise_rad: f64,
    /// The star tracker's slowly varying error, 1σ per sensor axis (rad), and its
    /// correlation time (s) (`star.slow_error_sigma_rad`, `star.slow_error_correlation_time_s`).
    pub star_slow_error_sigma_rad: [f64; 3],
    /// See `star_slow_error_sigma_rad`.
    pub star_slow_error_correlation_time_s: f64,
    /// Whether the flight software removes the star tracker's velocity aberration
    /// (`star.aberration_correction`); the last word but one, 0 or 1.
    pub star_aberration_correction: bool,
    /// Whether the star noise follows the innovations once they fail the consistency test
    /// (`star.noise_matching`); the last word, 0 or 1.
    pub star_noise_matching: bool,
    /// `star.second_head`: `None` = one tracker head.
    pub star_second_head: Option<crate::config::StarHeadConfig>,
}

impl ReplaySetup {
    /// The flight software configuration.
    pub fn config(&self) -> FswConfig {
        let mut config = FswConfig::paper_defaults(self.launch_site, self.sensor_frames);
        config.filter.mode = self.mode;
        config.filter.discretisation_order = self.discretisation_order;
        config.filter.initial = self.initial_sigma;
        config.process_noise = self.process_noise;
        config.imu.period_s = self.imu_period_s;
        config.star.mounting_wxyz = self.star_mounting_wxyz;
        config.star.noise_rad = self.star_noise_rad;
        config.star.gate_nis = self.star_gate_nis;
        config.gnss.noise_m = self.gnss_noise_m;
        config.gnss.gate_nis = self.gnss_gate_nis;
        config.timing.max_latency_s = self.max_latency_s;
        config.filter.gnss_error = self.gnss_error;
        config.gnss.velocity_noise_mps = self.gnss_velocity_noise_mps;
        config.imu.max_rate_rad_s = self.imu_max_rate_rad_s;
        config.imu.max_specific_force_mps2 = self.imu_max_specific_force_mps2;
        config.filter.imu_error = self.imu_error;
        config.gravity = self.gravity;
        config.star.roll_noise_rad = self.star_roll_noise_rad;
        config.star.slow_error_sigma_rad = self.star_slow_error_sigma_rad;
        config.star.slow_error_correlation_time_s = self.star_slow_error_correlation_time_s;
        config.star.aberration_correction = self.star_aberration_correction;
        config.star.noise_matching = self.star_noise_matching;
        config.star.second_head = self.star_second_head;
        config
    }

    /// The frames a replay with this setup runs: from the initial solution's time at the IMU
    /// period, with the flight software's IMU period tolerance and [`DEFAULT_MAX_GAP_S`].
    pub fn frame_grid(&self) -> FrameGrid {
        FrameGrid {
            start_time_s: self.initial.time_s,
            period_s: self.imu_period_s,
            tolerance: self.config().imu.period_tolerance,
            max_gap_s: DEFAULT_MAX_GAP_S,
        }
    }

    /// The setup as words. One line per word in layout order, so the layout reads top to
    /// bottom beside [`Self::from_words`]; longer than a function usually is for that reason.
    pub fn to_words(&self) -> [u64; SETUP_WORDS] {
        let site = &self.launch_site;
        let [kx, ky, kz] = site.earth_axis_ecef;
        let frames = &self.sensor_frames;
        let [gw, gx, gy, gz] = frames.gcrf_to_launch_inertial_wxyz;
        let q = &self.initial.attitude;
        let p = &self.initial.position_m;
        let v = &self.initial.velocity_mps;
        let s = &self.initial_sigma;
        let n = &self.process_noise;
        let [mw, mx, my, mz] = self.star_mounting_wxyz;
        let [slow_x, slow_y, slow_z] = self.star_slow_error_sigma_rad;
        let mode = match self.mode {
            FilterMode::OpenLoop => 0,
            FilterMode::ClosedLoop => 1,
        };
        let floats = [
            site.latitude_rad,
            site.longitude_rad,
            site.height_m,
            site.azimuth_rad,
            kx,
            ky,
            kz,
            gw,
            gx,
            gy,
            gz,
            frames.launch_epoch_gps_seconds_of_week,
            q.w,
            q.i,
            q.j,
            q.k,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            self.initial.time_s,
            s.attitude_rad,
            s.position_m,
            s.velocity_mps,
            s.gyro_bias_rad_s,
            s.accel_bias_mps2,
            s.star_installation_rad,
            s.gyro_scale_factor,
            s.accel_scale_factor,
            n.gyro_noise_density_rad_s_per_sqrt_hz,
            n.accel_noise_density_mps2_per_sqrt_hz,
            n.gyro_bias_walk_rad_s2_per_sqrt_hz,
            n.accel_bias_walk_mps3_per_sqrt_hz,
            self.imu_period_s,
            mw,
            mx,
            my,
            mz,
            self.star_noise_rad,
            self.star_gate_nis,
            self.gnss_noise_m,
            self.gnss_gate_nis,
            self.max_latency_s,
            self.gnss_error.sigma_m,
            self.gnss_error.correlation_time_s,
            self.gnss_velocity_noise_mps,
            self.imu_max_rate_rad_s,
            self.imu_max_specific_force_mps2,
            self.imu_error.gyro_misalignment_sigma_rad,
            self.imu_error.accel_misalignment_sigma_rad,
            self.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2,
            self.gravity.omitted_field_sigma_mps2,
            self.gravity.omitted_field_psd_m2_per_s3,
            self.star_roll_noise_rad,
            slow_x,
            slow_y,
            slow_z,
            self.star_slow_error_correlation_time_s,
        ];
        let mut words = [0_u64; SETUP_WORDS];
        let mut slots = words.iter_mut();
        let header = [
            SETUP_MAGIC,
            mode,
            u64::from(self.discretisation_order),
            u64::from(frames.launch_epoch_gps_week),
            u64::from(self.gravity.field.degree),
            u64::from(self.gravity.field.order),
            u64::from(self.gravity.field.terms_per_frame),
        ];
        // `header` first: zip polls its first iterator first, so no slot is skipped.
        for (value, slot) in header.into_iter().zip(&mut slots) {
            *slot = value;
        }
        // `floats` first, as `header` above: no slot is skipped before the flags.
        for (value, slot) in floats.into_iter().zip(&mut slots) {
            *slot = value.to_bits();
        }
        // The flags after the floats, each 0 or 1.
        let flags = [
            self.star_aberration_correction,
            self.star_noise_matching,
            self.star_second_head.is_some(),
        ];
        for (flag, slot) in flags.into_iter().zip(&mut slots) {
            *slot = u64::from(flag);
        }
        // The second head last (zeros without one): its pair count, then its floats.
        let head = self.star_second_head;
        let [hw, hx, hy, hz] = head.map_or([0.0; 4], |head| head.mounting_wxyz);
        let pairs = head.map_or(0, |head| head.pairs_before_hand_over);
        let head_floats = head.map_or([0.0; 4], |head| {
            [
                head.noise_rad,
                head.roll_noise_rad,
                head.alignment_prior_sigma_rad,
                head.pair_gate_nis,
            ]
        });
        let tail = core::iter::once(u64::from(pairs)).chain(
            [hw, hx, hy, hz]
                .into_iter()
                .chain(head_floats)
                .map(f64::to_bits),
        );
        for (value, slot) in tail.zip(slots) {
            *slot = value;
        }
        words
    }

    /// The setup from words.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] (`InitialNavigation`) for a bad magic, mode or
    /// flag (neither 0 nor 1), or a second head's word not zero without a second head; the
    /// values themselves are checked by
    /// [`crate::scheduler::NavigationComputer::new`].
    pub fn from_words(words: &[u64; SETUP_WORDS]) -> Result<Self, FswError> {
        let bad = FswError::InvalidConfiguration(ConfigField::InitialNavigation);
        let [magic, mode, order, week, field_degree, field_order, terms_per_frame, floats @ .., aberration_correction, noise_matching, second_head, pairs, hw, hx, hy, hz, head_noise, head_roll_noise, head_prior, head_gate] =
            words;
        if *magic != SETUP_MAGIC {
            return Err(bad);
        }
        let mode = match mode {
            0 => FilterMode::OpenLoop,
            1 => FilterMode::ClosedLoop,
            _ => return Err(bad),
        };
        let order = u8::try_from(*order).map_err(|_| bad)?;
        let week = u32::try_from(*week).map_err(|_| bad)?;
        let field = nav_core::gravity::harmonics::FieldModel {
            degree: u8::try_from(*field_degree).map_err(|_| bad)?,
            order: u8::try_from(*field_order).map_err(|_| bad)?,
            terms_per_frame: u8::try_from(*terms_per_frame).map_err(|_| bad)?,
        };
        let flag = |word: &u64| match word {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(bad),
        };
        let star_aberration_correction = flag(aberration_correction)?;
        let star_noise_matching = flag(noise_matching)?;
        let star_second_head = if flag(second_head)? {
            Some(crate::config::StarHeadConfig {
                mounting_wxyz: [*hw, *hx, *hy, *hz].map(f64::from_bits),
                noise_rad: f64::from_bits(*head_noise),
                roll_noise_rad: f64::from_bits(*head_roll_noise),
                alignment_prior_sigma_rad: f64::from_bits(*head_prior),
                pair_gate_nis: f64::from_bits(*head_gate),
                pairs_before_hand_over: u32::try_from(*pairs).map_err(|_| bad)?,
            })
        } else if [
            pairs,
            hw,
            hx,
            hy,
            hz,
            head_noise,
            head_roll_noise,
            head_prior,
            head_gate,
        ]
        .iter()
        .any(|word| **word != 0)
        {
            // Without a second head its words are zero: one setup, one encoding.
            return Err(bad);
        } else {
            None
        };
        let f = floats.map(f64::from_bits);
        let [lat, lon, height, azimuth, kx, ky, kz, gw, gx, gy, gz, seconds_of_week, qw, qx, qy, qz, px, py, pz, vx, vy, vz, time, s_att, s_pos, s_vel, s_gb, s_ab, s_inst, s_gsf, s_asf, n_g, n_a, n_gw, n_aw, period, mw, mx, my, mz, star_noise, star_gate, gnss_noise, gnss_gate, latency, correlated_sigma, correlation_time, velocity_noise, max_rate, max_force, imu_non_orthogonality, imu_misalignment, imu_g_sensitivity, omitted_sigma, omitted_psd, star_roll_noise, slow_x, slow_y, slow_z, slow_tau] =
            f;
        Ok(Self {
            launch_site: LaunchSite {
                latitude_rad: lat,
                longitude_rad: lon,
                height_m: height,
                azimuth_rad: azimuth,
                earth_axis_ecef: [kx, ky, kz],
            },
            sensor_frames: SensorFrames {
                gcrf_to_launch_inertial_wxyz: [gw, gx, gy, gz],
                launch_epoch_gps_week: week,
                launch_epoch_gps_seconds_of_week: seconds_of_week,
            },
            initial: NavigationState {
                attitude: Quaternion::new(qw, qx, qy, qz),
                position_m: Vector3::new(px, py, pz),
                velocity_mps: Vector3::new(vx, vy, vz),
                time_s: time,
            },
            mode,
            discretisation_order: order,
            initial_sigma: InitialUncertainty {
                attitude_rad: s_att,
                position_m: s_pos,
                velocity_mps: s_vel,
                gyro_bias_rad_s: s_gb,
                accel_bias_mps2: s_ab,
                star_installation_rad: s_inst,
                gyro_scale_factor: s_gsf,
                accel_scale_factor: s_asf,
            },
            process_noise: ProcessNoise {
                gyro_noise_density_rad_s_per_sqrt_hz: n_g,
                accel_noise_density_mps2_per_sqrt_hz: n_a,
                gyro_bias_walk_rad_s2_per_sqrt_hz: n_gw,
                accel_bias_walk_mps3_per_sqrt_hz: n_aw,
            },
            imu_period_s: period,
            star_mounting_wxyz: [mw, mx, my, mz],
            star_noise_rad: star_noise,
            star_gate_nis: star_gate,
            gnss_noise_m: gnss_noise,
            gnss_gate_nis: gnss_gate,
            max_latency_s: latency,
            gnss_error: nav_core::gnss_error::GnssErrorModel {
                sigma_m: correlated_sigma,
                correlation_time_s: correlation_time,
            },
            gnss_velocity_noise_mps: velocity_noise,
            imu_max_rate_rad_s: max_rate,
            imu_max_specific_force_mps2: max_force,
            imu_error: nav_core::imu_error_states::ImuErrorModel {
                gyro_misalignment_sigma_rad: imu_non_orthogonality,
                accel_misalignment_sigma_rad: imu_misalignment,
                gyro_g_sensitivity_sigma_rad_s_per_mps2: imu_g_sensitivity,
            },
            gravity: crate::config::GravityConfig {
                field,
                omitted_field_sigma_mps2: omitted_sigma,
                omitted_field_psd_m2_per_s3: omitted_psd,
            },
            star_roll_noise_rad: star_roll_noise,
            star_slow_error_sigma_rad: [slow_x, slow_y, slow_z],
            star_slow_error_correlation_time_s: slow_tau,
            star_aberration_correction,
            star_noise_matching,
            star_second_head,
        })
    }
}
