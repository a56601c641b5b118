//! The simulated world: the truth trajectory ([`truth`]) in its gravity field ([`gravity`]),
//! the sensor error models ([`sensors`]) and both advanced together, frame by frame
//! ([`simulation`]).

pub mod gravity;
pub mod sensors;
pub mod simulation;
pub mod truth;
