//! # nav-sim (library)
//!
//! Host-side truth and sensor simulation for the INS/CNS/GNSS navigation flight software
//! (Zong et al., J. Harbin Inst. Tech. 49(4), 2017; `docs/model.md`).
//!
//! * [`scenario`]: scenarios as TOML, the built-in default being the paper's Section 3.
//! * [`truth`]: the truth trajectory in the launch-inertial frame (orbit with point-mass + J2
//!   gravity, commanded body rates and specific forces) and the exact IMU increments.
//! * [`sensors`]: the sensor error models (paper eqs. 1 and 3, star sensor, GNSS) producing a
//!   seeded, deterministic, time-ordered stream of sensor events.
//! * [`simulation`]: truth and sensors together, frame by frame.
//! * [`flight`]: a scenario flown through the flight software (nav-fsw), recorded.
//! * [`log_replay`]: a recorded sensor log replayed through the flight software.
//! * [`faults`]: the fault-injection campaign (`nav-sim faults`).
//! * [`monte_carlo`]: parallel runs over seeds, RMS error, mean 1σ and the NEES test.
//! * [`dispersion`]: the scenario's `[dispersion]` table, truth-side quantities (initial
//!   navigation error, noise levels, star mounting, GNSS correlated error and latency) drawn
//!   afresh for every Monte Carlo run from its seed.
//! * [`campaign`]: Monte Carlo campaigns in shards (JSON Lines per run), merged into one
//!   report with percentiles and the runs outside 3σ (`nav-sim monte-carlo --shard`, `merge`).
//! * [`output`]: output files written atomically, refused when they are an input.
//! * [`report`]: calibration table (text, JSON), time-history CSVs and PNG plots.
//! * [`sensor_log`]: the replay log (CSV and binary) of the sensor-event stream.
//! * [`observability_report`]: the paper's Table 1 recomputed for its motion states and a
//!   scenario's schedule (`nav-sim observability`).
//! * [`benefit`]: what the calibration buys: navigation error through an aiding outage after
//!   the calibration flight, with and without the calibration states (`nav-sim benefit`).
//! * [`manoeuvre_design`]: a manoeuvre schedule searched with the covariance analysis under a
//!   vehicle's limits, written as a scenario (`nav-sim design`).
//!
//! Conventions are nav-core's (see its crate docs): Hamilton scalar-first quaternions, `q_ib`
//! maps body vectors into the launch-inertial frame, `dq_ib/dt = ½ q_ib ⊗ ω_ib^b`, SI units.
//! Times are navigation time, seconds since the launch epoch.

pub mod benefit;
pub mod campaign;
pub mod covariance_design;
pub mod dispersion;
pub mod epoch;
pub mod faults;
pub mod flight;
pub mod log_replay;
pub mod manoeuvre_design;
pub mod monte_carlo;
pub mod observability_report;
pub mod output;
pub mod report;
pub mod scenario;
pub mod sensor_log;
pub mod sensors;
pub mod simulation;
pub mod target_replay;
pub mod truth;
pub mod uart_replay;

pub use scenario::{Scenario, ScenarioError};
pub use sensors::SensorEvent;
pub use simulation::{Simulation, SimulationError};
