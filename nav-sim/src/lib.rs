//! # nav-sim (library)
//!
//! Host-side truth and sensor simulation, flight harness, campaigns and studies for the
//! INS/CNS/GNSS navigation flight software (Zong et al., J. Harbin Inst. Tech. 49(4), 2017;
//! `docs/guide/model.md`).
//!
//! ## Layers
//!
//! The crate is built in layers. A module imports only from its own layer and the layers
//! below it, never from a layer above, and no two modules import each other in a circle
//! (`tests/testsuite/layers.rs` derives the module graph from the sources and checks both).
//! From the bottom:
//!
//! 1. [`scenario`] and [`output`]: the scenario schema (TOML tables, validation, the
//!    `[dispersion]` and `[gravity]` tables, the launch epoch and Earth orientation) and the
//!    output toolkit (files written atomically, the calibration table, CSVs and plots).
//!    Neither imports anything from the crate.
//! 2. [`setup`]: what a run needs, computed once from a scenario (launch epoch and ground
//!    constants, launch site and frame, initial state, flight-software and filter
//!    configuration) and every random draw through one registry of streams.
//! 3. [`world`]: the simulated world, truth trajectory, gravity field and sensor models.
//! 4. [`logs`]: the sensor-log formats (CSV and binary).
//! 5. [`harness`]: a scenario or a log flown through the flight software, on the host, on
//!    QEMU and over serial lines.
//! 6. [`campaign`]: Monte Carlo runs, their statistics, shards and report.
//! 7. [`studies`]: the fault campaign, the benefit of the calibration, the covariance and
//!    manoeuvre design and the observability analysis.
//!
//! The command-line program (`src/bin/nav-sim/`) parses arguments and prints; the library
//! never does either.
//!
//! Conventions are nav-core's (see its crate docs): Hamilton scalar-first quaternions, `q_ib`
//! maps body vectors into the launch-inertial frame, `dq_ib/dt = ½ q_ib ⊗ ω_ib^b`, SI units.
//! Times are navigation time, seconds since the launch epoch.

pub mod campaign;
pub mod harness;
pub mod logs;
pub mod output;
pub mod scenario;
pub mod setup;
pub mod studies;
pub mod world;

pub use scenario::{Scenario, ScenarioError};
pub use world::sensors::SensorEvent;
pub use world::simulation::{Simulation, SimulationError};
