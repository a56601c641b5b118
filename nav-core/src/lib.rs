//! # nav-core
//!
//! Allocation-free, panic-free `no_std` f64 navigation mathematics for an INS/CNS/GNSS
//! integrated navigation computer, after Zong et al., "On-line errors calibration method for
//! INS/CNS/GNSS integrated navigation", J. Harbin Inst. Tech. 49(4), 2017 (the "paper"; the
//! model as implemented is described in `docs/guide/model.md`).
//!
//! ## Conventions (stated once, used everywhere)
//!
//! * **Frames.** `i`: launch-inertial frame (origin at the launch site at the launch epoch,
//!   axes fixed in inertial space, see [`frames`]). `b`: IMU body frame (the paper's `g`).
//!   `s`: star-sensor frame. `e`: ECEF (WGS-84).
//! * **Quaternions** are Hamilton quaternions, scalar first, `q = w + x i + y j + z k`
//!   (`nalgebra::Quaternion`, whose product is the Hamilton product). `q_ab` maps a vector
//!   expressed in frame `b` into frame `a`: `v_a = q_ab ⊗ v_b ⊗ q_ab*`, and
//!   `C_ab = R(q_ab)` is the matching direction-cosine matrix. The attitude is `q_ib`
//!   (body to launch-inertial). Kinematics: `dq_ib/dt = ½ q_ib ⊗ ω_ib^b` (body rate). The
//!   paper's eq. (5) `dq/dt = ½ ω ⊗ q` is the same equation written for the inverse
//!   quaternion.
//! * **Attitude error** is a body-frame (right) error: `q_true = q̂ ⊗ δq`,
//!   `δq ≈ [1, ϑ]`, where the state `ϑ` is the vector part of `δq` (half the small rotation
//!   angle). Then `C_true = Ĉ (I + 2[ϑ×])`, and the paper's eq. (7)
//!   `dϑ/dt = -[ω̂×]ϑ + ½ δω` holds exactly as printed.
//! * **Errors** of additive quantities are `truth − estimate` (`δp = p − p̂`,
//!   `δb_g = b_g − b̂_g`, ...).
//! * **Units** are SI (m, s, rad, m/s, m/s²) unless a name says otherwise (`_deg`, `_arcsec`).
//!
//! ## Rules of this crate
//! No allocation, no recursion, every loop bounded by a constant, fixed-size types only, no
//! panicking operations on the flight path: fallible functions return [`NavError`]. All
//! transcendental functions go through `libm` so host and Cortex-M builds agree bit for bit;
//! the square root goes through [`float::sqrt`] (correctly rounded: libm, or the FPU's
//! instruction with the `hardware-sqrt` feature, the same bits).
#![cfg_attr(not(test), no_std)]
// A build without an optional state block leaves the shared kernels' inputs for it (border
// products, bias inputs, their finiteness checks) unused; the full build checks dead code.
#![cfg_attr(
    not(all(feature = "gnss-error-states", feature = "imu-error-states")),
    allow(dead_code)
)]
// No unsafe code but the one FPU instruction of `float::sqrt` (feature `hardware-sqrt`).
#![deny(unsafe_code)]
// Flight-path lint policy (the common policy is [workspace.lints] in the root Cargo.toml).
// Tests may unwrap and index; the flight code may not.
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

pub mod aberration;
pub mod arithmetic;
pub mod attitude;
mod block;
mod block_interface;
pub mod discretise;
pub mod error;
pub mod error_model;
pub mod filter;
pub mod float;
pub mod frames;
pub mod gnss_error;
pub mod gravity;
pub mod imu_error;
pub mod imu_error_states;
pub mod measurement;
#[cfg(any(test, feature = "ground-analysis"))]
pub mod observability;
#[cfg(any(test, feature = "selftest"))]
pub mod selftest;
pub mod star_heads;
pub mod state;
pub mod strapdown;
pub mod structured;
pub mod unmodelled;

pub use error::NavError;
/// nalgebra as nav-core builds it (`no_std`, `libm`, `libm-force`): the types of nav-core's
/// API come from here, so an integrator depends on nav-core (or nav-fsw) alone and never on a
/// second nalgebra whose default features pull in `std`.
pub use nalgebra;
