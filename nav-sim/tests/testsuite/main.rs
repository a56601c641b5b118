//! nav-sim's integration tests, one binary with a module per topic (as cargo's own
//! `tests/testsuite`): one link, and one place to run them, `cargo test -p nav-sim --test
//! testsuite [filter]`.

mod as_it_is;
mod benefit;
mod campaign;
mod cli;
mod cli_inputs;
mod commands;
mod common;
mod conditioning;
mod consistency;
mod design;
mod design_imu_errors;
mod dispersion;
mod flight_software;
mod frames_and_time;
mod gravity_field;
mod gravity_flight_model;
mod gravity_omission;
mod imu_errors;
mod layers;
mod model_mismatch;
mod nees_over_time;
mod operator_flags;
mod optional_outputs;
mod paper_accuracy;
mod realistic_campaign;
mod realistic_errors;
mod replay_logs;
mod scenario_keys_reference;
mod scenario_overlays;
mod star_aberration;
mod star_flight_noise;
mod star_heads;
mod star_slow_error;
mod telemetry_packets;
mod upper_stage;
mod validation;
