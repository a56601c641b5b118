//! # nav-sim (library)
//!
//! Host-side truth and sensor simulation for the INS/CNS/GNSS navigation flight software
//! (Zong et al., J. Harbin Inst. Tech. 49(4), 2017; `shared/notes/model.md`).
//!
//! * [`scenario`]: scenarios as TOML, the built-in default being the paper's Section 3.
//! * [`truth`]: the truth trajectory in the launch-inertial frame (orbit with point-mass + J2
//!   gravity, commanded body rates and specific forces) and the exact IMU increments.
//! * [`sensors`]: the sensor error models (paper eqs. 1 and 3, star sensor, GNSS) producing a
//!   seeded, deterministic, time-ordered stream of sensor events.
//! * [`simulation`]: truth and sensors together, frame by frame.
//!
//! Conventions are nav-core's (see its crate docs): Hamilton scalar-first quaternions, `q_ib`
//! maps body vectors into the launch-inertial frame, `dq_ib/dt = ½ q_ib ⊗ ω_ib^b`, SI units.
//! Times are navigation time, seconds since the launch epoch.

pub mod covariance_design;
pub mod scenario;
pub mod sensors;
pub mod simulation;
pub mod truth;

pub use scenario::{Scenario, ScenarioError};
pub use sensors::SensorEvent;
pub use simulation::{Simulation, SimulationError};
