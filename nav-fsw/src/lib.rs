//! # nav-fsw
//!
//! The flight software around [`nav_core`]: a deterministic 500 Hz cyclic executive, sensor
//! ports, input checking, covariance health and the calibration manager. `no_std`, no
//! allocator, fixed-capacity queues only.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
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

pub mod calibration_manager;
pub mod config;
pub mod error;
pub mod health;
pub mod input_check;
pub mod log_record;
pub mod measurement_buffer;
pub mod ports;
pub mod replay;
pub mod scheduler;
pub mod stream_ports;
pub mod telemetry;

pub use error::{ConfigField, FswError};
