//! Studies built on the flight harness and the campaigns: the fault-injection campaign
//! ([`faults`]), what the calibration buys ([`benefit`]), the covariance analysis
//! ([`covariance_design`]) and the manoeuvre search built on it ([`manoeuvre_design`]), and
//! the paper's observability analysis ([`observability`]).

pub mod benefit;
pub mod covariance_design;
pub mod faults;
pub mod manoeuvre_design;
pub mod observability;
