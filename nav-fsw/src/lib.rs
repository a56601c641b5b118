//! # nav-fsw
//!
//! The flight software around [`nav_core`]: a deterministic 500 Hz cyclic executive, sensor
//! ports, input checking, covariance health and the calibration manager. `no_std`, no
//! allocator, fixed-capacity queues only.
//!
//! One dependency line is enough: nav-fsw re-exports [`nav_core`] and its [`nalgebra`]
//! (`no_std`, `libm`; a second `nalgebra = "0.35"` line would pull in `std`).
//!
//! # Examples
//! A computer configured with the paper's defaults for a launch site, run for one 2 ms frame
//! with the ready-made per-frame ports (a flight image keeps the computer in a `static`, built
//! there by [`NavigationComputer::init_in_place`]; see `qemu/src/bin/replay.rs`):
//! ```
//! use nav_fsw::nalgebra::{Quaternion, Vector3};
//! use nav_fsw::nav_core::frames::LaunchSite;
//! use nav_fsw::nav_core::strapdown::NavigationState;
//! use nav_fsw::{FrameGnss, FrameImu, FrameStar, FswConfig, ImuSample, NavigationComputer};
//!
//! let site = LaunchSite {
//!     latitude_rad: 40.958_f64.to_radians(),
//!     longitude_rad: 100.291_f64.to_radians(),
//!     height_m: 1000.0,
//!     azimuth_rad: 190.0_f64.to_radians(),
//!     earth_axis_ecef: [0.0, 0.0, 1.0],
//! };
//! let initial = NavigationState {
//!     attitude: Quaternion::identity(),
//!     position_m: Vector3::new(0.0, 500e3, 0.0),
//!     velocity_mps: Vector3::new(7600.0, 0.0, 0.0),
//!     time_s: 600.0,
//! };
//! // PLACEHOLDER ground constants: a flight image uses its launch's, from `nav-sim ground-constants`.
//! let mut computer = NavigationComputer::new(FswConfig::paper_defaults(site, nav_fsw::sensor_frames::SensorFrames::ALIGNED), initial)?;
//! let mut imu = FrameImu(Some(ImuSample::new(1, 600.002, [0.0; 3], [0.0; 3])));
//! let telemetry =
//!     computer.run_frame(&mut imu, &mut FrameStar::default(), &mut FrameGnss::default());
//! assert!((telemetry.time_s - 600.002).abs() < 1e-9);
//! assert_eq!(telemetry.health.imu_missing, 0);
//! # Ok::<(), nav_fsw::FswError>(())
//! ```
#![cfg_attr(not(test), no_std)]
#![deny(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::as_conversions,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

/// Nominal IMU / minor-frame period (s): 500 Hz, as in the paper's Section 3.
pub const MINOR_FRAME_PERIOD_S: f64 = 0.002;

pub mod aberration_monitor;
pub mod calibration_manager;
pub mod calibration_record;
pub mod config;
pub mod consistency;
pub mod datasheet;
pub mod error;
pub mod health;
pub mod input_check;
pub mod log_record;
pub mod measurement_buffer;
pub mod motion_observability;
pub mod noise_matching;
pub mod ports;
pub mod replay;
pub mod scheduler;
pub mod sensor_frames;
pub mod spi_imu;
pub mod stream_merge;
pub mod stream_ports;
pub mod telemetry;
pub mod telemetry_packets;
#[cfg(test)]
mod test_random;

pub use config::FswConfig;
pub use error::{ConfigField, FswError};
/// The navigation core, and through it nalgebra ([`nav_core::nalgebra`]): one dependency line
/// on nav-fsw is enough to use every type of its API.
pub use nav_core;
pub use nav_core::nalgebra;
pub use ports::{GnssFix, GnssPort, ImuPort, ImuSample, StarMeasurement, StarSensorPort};
/// The ready-made simple ports: one frame's IMU sample and measurements, for an integrator
/// whose drivers already collect them per frame.
pub use replay::{FrameGnss, FrameImu, FrameStar};
pub use scheduler::NavigationComputer;
