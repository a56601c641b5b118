//! Replay: a recorded sensor log fed to the flight software frame by frame, identically on
//! the host and on the target, with a fixed-layout output record per frame so the two can be
//! compared bit for bit.
//!
//! * [`FramePorts`]: the port contents of one frame (the IMU sample and the measurements
//!   delivered with it); the simulator fills them live, the replay from the log.
//! * [`FrameAssembler`]: groups the log's records (`crate::log_record`, delivery order) into
//!   frames: a frame is an IMU record and the star/GNSS records after it, up to the next IMU
//!   record (records before the first IMU record join the first frame).
//! * [`ReplaySetup`]: what a scenario decides about the flight software (launch site, initial
//!   navigation solution, filter, noise, gates), as 8-byte words, so the target builds the
//!   very configuration the host built ([`ReplaySetup::config`]).
//! * [`output_words`]: the frame's output record, [`OUTPUT_WORDS`] little-endian 8-byte
//!   words named by [`OUTPUT_FIELD_NAMES`] (floats as their bit patterns).

use heapless::Deque;
use nalgebra::{Quaternion, Vector3};
use nav_core::error_model::ProcessNoise;
use nav_core::filter::{FilterMode, InitialUncertainty};
use nav_core::frames::LaunchSite;
use nav_core::strapdown::NavigationState;

use crate::config::FswConfig;
use crate::error::{ConfigField, FswError};
use crate::log_record::LogRecord;
use crate::ports::{GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};
use crate::scheduler::NavigationComputer;
use crate::telemetry::{FrameFusion, FrameTelemetry};

/// Most star measurements one frame can carry (more are counted as dropped).
pub const FRAME_STAR_CAPACITY: usize = 8;
/// Most GNSS fixes one frame can carry.
pub const FRAME_GNSS_CAPACITY: usize = 4;

/// The IMU port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameImu(pub Option<ImuSample>);

impl ImuPort for FrameImu {
    fn read(&mut self) -> Option<ImuSample> {
        self.0.take()
    }
}

/// The star-sensor port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameStar(pub Deque<StarMeasurement, FRAME_STAR_CAPACITY>);

impl StarSensorPort for FrameStar {
    fn poll(&mut self) -> Option<StarMeasurement> {
        self.0.pop_front()
    }
}

/// The GNSS port of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameGnss(pub Deque<GnssFix, FRAME_GNSS_CAPACITY>);

impl GnssPort for FrameGnss {
    fn poll(&mut self) -> Option<GnssFix> {
        self.0.pop_front()
    }
}

/// What the ports hold for one frame.
#[derive(Debug, Clone, Default)]
pub struct FramePorts {
    /// The IMU sample.
    pub imu: FrameImu,
    /// Star measurements delivered in the frame.
    pub star: FrameStar,
    /// GNSS fixes delivered in the frame.
    pub gnss: FrameGnss,
    /// Measurements that did not fit the frame's capacity (lost, counted here).
    pub dropped: u32,
}

impl FramePorts {
    /// Adds a record's content to the frame (an IMU record replaces the sample).
    pub fn add(&mut self, record: &LogRecord) {
        let refused = match record {
            LogRecord::Imu(imu) => {
                self.imu.0 = Some(imu.to_imu_sample());
                false
            }
            LogRecord::Star(star) => self.star.0.push_back(star.to_star_measurement()).is_err(),
            LogRecord::Gnss(gnss) => self.gnss.0.push_back(gnss.to_gnss_fix()).is_err(),
        };
        if refused {
            self.dropped = self.dropped.saturating_add(1);
        }
    }

    /// Runs the frame on `computer`.
    pub fn run(&mut self, computer: &mut NavigationComputer) -> FrameTelemetry {
        computer.run_frame(&mut self.imu, &mut self.star, &mut self.gnss)
    }
}

/// Groups records into frames (module docs).
#[derive(Debug, Clone, Default)]
pub struct FrameAssembler {
    pending: FramePorts,
    has_imu: bool,
}

impl FrameAssembler {
    /// Takes the next record; returns the previous frame when `record` starts a new one.
    pub fn push(&mut self, record: &LogRecord) -> Option<FramePorts> {
        let starts_frame = matches!(record, LogRecord::Imu(_));
        let complete = if starts_frame && self.has_imu {
            Some(core::mem::take(&mut self.pending))
        } else {
            None
        };
        if starts_frame {
            self.has_imu = true;
        }
        self.pending.add(record);
        complete
    }

    /// The last frame, at the end of the log.
    pub fn finish(&mut self) -> Option<FramePorts> {
        if self.has_imu {
            self.has_imu = false;
            Some(core::mem::take(&mut self.pending))
        } else {
            None
        }
    }
}

/// Number of words of a [`ReplaySetup`].
pub const SETUP_WORDS: usize = 46;
/// First word of an encoded setup (`"NAVSETUP"` little-endian).
pub const SETUP_MAGIC: u64 = u64::from_le_bytes(*b"NAVSETUP");

/// The scenario-dependent part of the flight software's configuration and its initial
/// navigation solution; everything else is [`FswConfig::paper_defaults`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySetup {
    /// Launch site.
    pub launch_site: LaunchSite,
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
    /// Star noise 1σ (rad).
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
}

impl ReplaySetup {
    /// The flight software configuration.
    pub fn config(&self) -> FswConfig {
        let mut config = FswConfig::paper_defaults(self.launch_site);
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
        config
    }

    /// The setup as words.
    pub fn to_words(&self) -> [u64; SETUP_WORDS] {
        let site = &self.launch_site;
        let q = &self.initial.attitude;
        let p = &self.initial.position_m;
        let v = &self.initial.velocity_mps;
        let s = &self.initial_sigma;
        let n = &self.process_noise;
        let [mw, mx, my, mz] = self.star_mounting_wxyz;
        let mode = match self.mode {
            FilterMode::OpenLoop => 0,
            FilterMode::ClosedLoop => 1,
        };
        let floats = [
            site.latitude_rad,
            site.longitude_rad,
            site.height_m,
            site.azimuth_rad,
            site.epoch_s,
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
        ];
        let mut words = [0_u64; SETUP_WORDS];
        let mut slots = words.iter_mut();
        let header = [SETUP_MAGIC, mode, u64::from(self.discretisation_order)];
        // `header` first: zip polls its first iterator first, so no slot is skipped.
        for (value, slot) in header.into_iter().zip(&mut slots) {
            *slot = value;
        }
        for (slot, value) in slots.zip(floats) {
            *slot = value.to_bits();
        }
        words
    }

    /// The setup from words.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] (`InitialNavigation`) for a bad magic or mode; the
    /// values themselves are checked by [`NavigationComputer::new`].
    pub fn from_words(words: &[u64; SETUP_WORDS]) -> Result<Self, FswError> {
        let bad = FswError::InvalidConfiguration(ConfigField::InitialNavigation);
        let [magic, mode, order, floats @ ..] = words;
        if *magic != SETUP_MAGIC {
            return Err(bad);
        }
        let mode = match mode {
            0 => FilterMode::OpenLoop,
            1 => FilterMode::ClosedLoop,
            _ => return Err(bad),
        };
        let order = u8::try_from(*order).map_err(|_| bad)?;
        let f = floats.map(f64::from_bits);
        let [lat, lon, height, azimuth, epoch, qw, qx, qy, qz, px, py, pz, vx, vy, vz, time, s_att, s_pos, s_vel, s_gb, s_ab, s_inst, s_gsf, s_asf, n_g, n_a, n_gw, n_aw, period, mw, mx, my, mz, star_noise, star_gate, gnss_noise, gnss_gate, latency, correlated_sigma, correlation_time, velocity_noise, max_rate, max_force] =
            f;
        Ok(Self {
            launch_site: LaunchSite {
                latitude_rad: lat,
                longitude_rad: lon,
                height_m: height,
                azimuth_rad: azimuth,
                epoch_s: epoch,
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
        })
    }
}

/// Number of words of a frame's output record.
pub const OUTPUT_WORDS: usize = 76;

/// Names of the output words, in order.
pub const OUTPUT_FIELD_NAMES: [&str; OUTPUT_WORDS] = [
    "frame",
    "time_s",
    "attitude_w",
    "attitude_x",
    "attitude_y",
    "attitude_z",
    "position_x_m",
    "position_y_m",
    "position_z_m",
    "velocity_x_mps",
    "velocity_y_mps",
    "velocity_z_mps",
    "fusion",
    "last_star_nis",
    "last_gnss_nis",
    "star_faulty",
    "gnss_faulty",
    "converged_blocks",
    "frozen_blocks",
    "gyro_bias_x",
    "gyro_bias_y",
    "gyro_bias_z",
    "accel_bias_x",
    "accel_bias_y",
    "accel_bias_z",
    "star_installation_x",
    "star_installation_y",
    "star_installation_z",
    "gyro_scale_factor_x",
    "gyro_scale_factor_y",
    "gyro_scale_factor_z",
    "accel_scale_factor_x",
    "accel_scale_factor_y",
    "accel_scale_factor_z",
    "gyro_bias_sigma_x",
    "gyro_bias_sigma_y",
    "gyro_bias_sigma_z",
    "accel_bias_sigma_x",
    "accel_bias_sigma_y",
    "accel_bias_sigma_z",
    "star_installation_sigma_x",
    "star_installation_sigma_y",
    "star_installation_sigma_z",
    "gyro_scale_factor_sigma_x",
    "gyro_scale_factor_sigma_y",
    "gyro_scale_factor_sigma_z",
    "accel_scale_factor_sigma_x",
    "accel_scale_factor_sigma_y",
    "accel_scale_factor_sigma_z",
    "imu_non_finite",
    "imu_saturated",
    "imu_duplicate",
    "imu_missing",
    "imu_time_jump",
    "star_non_finite",
    "star_not_unit",
    "star_sign_flip",
    "gnss_non_finite",
    "gnss_jump",
    "measurement_stale",
    "measurement_future",
    "measurement_overflow",
    "star_gate_rejections",
    "gnss_gate_rejections",
    "covariance_clamps",
    "filter_resets",
    "star_declared_faulty",
    "gnss_declared_faulty",
    "ignored_from_faulty_sensor",
    "filter_errors",
    "strapdown_failures",
    "dropped_measurements",
    "last_gnss_velocity_nis",
    "gnss_velocity_gate_rejections",
    "imu_held_frames",
    "gnss_innovations_correlated",
];

/// The output record of a frame (module docs): telemetry (without the platform's frame cost,
/// which only the target measures) and the calibration table.
pub fn output_words(
    telemetry: &FrameTelemetry,
    computer: &NavigationComputer,
    dropped_measurements: u32,
) -> [u64; OUTPUT_WORDS] {
    let t = telemetry;
    let h = &t.health;
    let fusion = match t.fusion {
        FrameFusion::None => 0,
        FrameFusion::StarAccepted => 1,
        FrameFusion::StarRejected => 2,
        FrameFusion::GnssAccepted => 3,
        FrameFusion::GnssRejected => 4,
        FrameFusion::GnssVelocityAccepted => 5,
        FrameFusion::GnssVelocityRejected => 6,
    };
    let mut words = [0_u64; OUTPUT_WORDS];
    let mut slots = words.iter_mut();
    let mut put = |value: u64| {
        if let Some(slot) = slots.next() {
            *slot = value;
        }
    };
    put(u64::from(t.frame));
    put(t.time_s.to_bits());
    for value in t.attitude_wxyz {
        put(value.to_bits());
    }
    for value in t.position_m.iter().chain(t.velocity_mps.iter()) {
        put(value.to_bits());
    }
    put(fusion);
    put(t.last_star_nis.to_bits());
    put(t.last_gnss_nis.to_bits());
    put(u64::from(t.star_faulty));
    put(u64::from(t.gnss_faulty));
    put(u64::from(t.converged_blocks));
    put(u64::from(t.frozen_blocks));
    let table = computer.calibration_table().entries();
    for (_, entry) in table {
        for value in entry.value {
            put(value.to_bits());
        }
    }
    for (_, entry) in table {
        for value in entry.sigma() {
            put(value.to_bits());
        }
    }
    let counters = [
        h.imu_non_finite,
        h.imu_saturated,
        h.imu_duplicate,
        h.imu_missing,
        h.imu_time_jump,
        h.star_non_finite,
        h.star_not_unit,
        h.star_sign_flip,
        h.gnss_non_finite,
        h.gnss_jump,
        h.measurement_stale,
        h.measurement_future,
        h.measurement_overflow,
        h.star_gate_rejections,
        h.gnss_gate_rejections,
        h.covariance_clamps,
        h.filter_resets,
        h.star_declared_faulty,
        h.gnss_declared_faulty,
        h.ignored_from_faulty_sensor,
        h.filter_errors,
        h.strapdown_failures,
        dropped_measurements,
    ];
    for counter in counters {
        put(u64::from(counter));
    }
    put(t.last_gnss_velocity_nis.to_bits());
    put(u64::from(h.gnss_velocity_gate_rejections));
    put(u64::from(h.imu_held_frames));
    put(u64::from(h.gnss_innovations_correlated));
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log_record::{GnssRecord, ImuRecord, StarRecord};

    fn imu(sequence: u64) -> LogRecord {
        LogRecord::Imu(ImuRecord {
            sequence,
            time_s: 0.002 * f64::from(u32::try_from(sequence).unwrap()),
            interval_s: 0.002,
            delta_angle_rad: [0.0; 3],
            delta_velocity_mps: [0.0; 3],
        })
    }

    #[test]
    fn frames_are_an_imu_record_and_the_measurements_after_it() {
        let star = LogRecord::Star(StarRecord {
            arrival_time_s: 0.0,
            time_tag_s: 0.0,
            attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
        });
        let gnss = LogRecord::Gnss(GnssRecord {
            arrival_time_s: 0.0,
            time_tag_s: 0.0,
            position_ecef_m: [7e6, 0.0, 0.0],
            velocity_ecef_mps: None,
        });
        let mut assembler = FrameAssembler::default();
        assert!(assembler.push(&star).is_none()); // before the first IMU: joins frame 0
        assert!(assembler.push(&imu(0)).is_none());
        assert!(assembler.push(&gnss).is_none());
        let first = assembler.push(&imu(1)).unwrap();
        assert_eq!(first.imu.0.unwrap().sequence, 0);
        assert_eq!((first.star.0.len(), first.gnss.0.len()), (1, 1));
        let second = assembler.finish().unwrap();
        assert_eq!(second.imu.0.unwrap().sequence, 1);
        assert!(second.star.0.is_empty());
        assert!(assembler.finish().is_none());
    }

    #[test]
    fn the_setup_round_trips_bit_for_bit_and_rejects_a_bad_magic() {
        let config = FswConfig::paper_defaults(LaunchSite {
            latitude_rad: 0.7,
            longitude_rad: 1.7,
            height_m: 1000.0,
            azimuth_rad: 3.3,
            epoch_s: 0.0,
        });
        let setup = ReplaySetup {
            launch_site: config.launch_site,
            initial: NavigationState {
                attitude: Quaternion::new(0.5, 0.5, -0.5, 0.5),
                position_m: Vector3::new(1.0, -2.0, 3.0),
                velocity_mps: Vector3::new(7.5e3, 0.1, -0.2),
                time_s: 600.0,
            },
            mode: FilterMode::ClosedLoop,
            discretisation_order: 3,
            initial_sigma: config.filter.initial,
            process_noise: config.process_noise,
            imu_period_s: 0.002,
            star_mounting_wxyz: [0.9659, 0.0, -0.2588, 0.0],
            star_noise_rad: 4.8e-5,
            star_gate_nis: 16.27,
            gnss_noise_m: 10.0,
            gnss_gate_nis: 16.27,
            max_latency_s: 0.1,
            gnss_error: nav_core::gnss_error::GnssErrorModel {
                sigma_m: 8.0,
                correlation_time_s: 300.0,
            },
            gnss_velocity_noise_mps: 0.05,
            imu_max_rate_rad_s: 7.0,
            imu_max_specific_force_mps2: 200.0,
        };
        let words = setup.to_words();
        assert_eq!(ReplaySetup::from_words(&words), Ok(setup));
        let mut bad = words;
        bad[0] = 0;
        assert!(ReplaySetup::from_words(&bad).is_err());
        bad = words;
        bad[1] = 7;
        assert!(ReplaySetup::from_words(&bad).is_err());
    }
}
