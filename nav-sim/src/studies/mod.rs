//! Studies built on the flight harness and the campaigns: the fault-injection campaign
//! ([`faults`]), what the calibration buys ([`benefit`]), the covariance analysis
//! ([`covariance_design`]) and the manoeuvre search built on it ([`manoeuvre_design`]), the
//! paper's observability analysis ([`observability`]), and the process noise that covers the
//! gravity a flight field leaves out ([`gravity_omission`]).

pub mod benefit;
pub mod covariance_design;
pub mod faults;
pub mod gravity_omission;
pub mod manoeuvre_design;
pub mod observability;
