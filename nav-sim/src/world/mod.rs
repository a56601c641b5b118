//! The simulated world: the truth trajectory ([`truth`]), the sensor error models
//! ([`sensors`]) and both advanced together, frame by frame ([`simulation`]).

pub mod sensors;
pub mod simulation;
pub mod truth;
