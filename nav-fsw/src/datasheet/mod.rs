//! The flight configuration from the sensors' data sheets: typed tables an engineer copies
//! from each data sheet in its own units ([`Datasheets`]: the IMU's, the star tracker's, the
//! GNSS receiver's, the gravity model with its allowance, the hand-over's accuracy), and
//! [`FswConfig::from_datasheets`], which converts them to the flight software's SI 1σ and
//! densities, turns on the optional state blocks they call for and validates the result
//! through the parameter table ([`FswConfig::validate`]). Each conversion is one function
//! here whose doc gives its derivation; nav-sim's scenarios use the same functions, so a
//! scenario and a data sheet that state one value configure one flight
//! (docs/guide/flight-software.md, "Configuring it from the data sheets").

use crate::config::FswConfig;
use crate::error::{ConfigField, FswError};
use crate::sensor_frames::SensorFrames;
use nav_core::frames::LaunchSite;

mod gnss;
mod gravity;
mod imu;
mod star_tracker;
#[cfg(test)]
mod tests;

pub use gnss::{latency_window_s, GnssCorrelatedError, GnssDatasheet};
pub use gravity::GravityDatasheet;
pub use imu::{
    bias_prior_with_instability, bias_walk_with_instability, deg_per_h_to_rad_per_s,
    gauss_markov_from_allan_floor, AccelBiasInstability, AccelerometerDatasheet,
    GyroBiasInstability, GyroDatasheet, ImuDatasheet, ALLAN_PEAK_PER_SIGMA,
    ALLAN_PEAK_TAU_PER_CORRELATION_TIME, STANDARD_GRAVITY_MPS2,
};
pub use star_tracker::{
    arcsec_to_rad, mounting_wxyz_from_rotation_vector_deg, second_head_alignment_prior_rad,
    LowFrequencyError, StarTrackerDatasheet, PAIRS_BEFORE_HAND_OVER,
};

/// Seconds per hour: the data sheets' rates are per hour.
const SECONDS_PER_HOUR: f64 = 3600.0;

/// `√(s/h)` = 60: a random walk's coefficient per `√h` is 60 times its coefficient per `√s`
/// (`σ(t) = N √t`, with `t` in hours `√(t_s / 3600) = √t_s / 60`).
const SQRT_SECONDS_PER_SQRT_HOUR: f64 = 60.0;

/// Parts per million, and micro-units, per unit.
const PER_MILLION: f64 = 1.0e6;

/// Milli-units per unit.
const PER_THOUSAND: f64 = 1.0e3;

/// How well the flight starts: the 1σ per axis of the initial navigation solution the
/// ascent navigation (or the ground alignment) hands over, its own data sheet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandOverDatasheet {
    /// Attitude, 1σ per axis as a small rotation angle (mrad).
    pub attitude_mrad: f64,
    /// Position, 1σ per axis (m).
    pub position_m: f64,
    /// Velocity, 1σ per axis (m/s).
    pub velocity_mps: f64,
}

impl HandOverDatasheet {
    /// The filter's initial attitude, position and velocity 1σ: mrad / 1000 (exact for a
    /// whole number of mrad, as a division of two exact values is correctly rounded), m and
    /// m/s as given.
    fn apply(&self, config: &mut FswConfig) {
        let initial = &mut config.filter.initial;
        initial.attitude_rad = self.attitude_mrad / PER_THOUSAND;
        initial.position_m = self.position_m;
        initial.velocity_mps = self.velocity_mps;
    }
}

/// Every data sheet the flight configuration is made from, each in the units its data sheet
/// prints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Datasheets {
    /// The inertial measurement unit.
    pub imu: ImuDatasheet,
    /// The star tracker, its heads and their mountings.
    pub star_tracker: StarTrackerDatasheet,
    /// The GNSS receiver and its antenna.
    pub gnss: GnssDatasheet,
    /// The flight's gravity model and the allowance for the field it omits.
    pub gravity: GravityDatasheet,
    /// The initial navigation solution's accuracy.
    pub hand_over: HandOverDatasheet,
}

impl Datasheets {
    /// The data-sheet field behind a refused configuration field ([`FswError`] of
    /// [`FswConfig::from_datasheets`]), as `table.field`; `None` for a field the data sheets
    /// leave at the flight software's default (the launch site and ground constants are the
    /// caller's).
    pub fn field_of(field: ConfigField) -> Option<&'static str> {
        use crate::config::Param as P;
        let param = match field {
            ConfigField::Parameter(param) | ConfigField::Companion(_, param) => param,
            ConfigField::StarMounting => return Some("star_tracker.mounting_rotation_vector_deg"),
            ConfigField::StarSecondHead => {
                return Some("star_tracker.second_head_mounting_rotation_vector_deg")
            }
            ConfigField::MaxLatency => return Some("gnss.latency_s"),
            ConfigField::FutureTolerance => return Some("imu.output_rate_hz"),
            ConfigField::Gravity => return Some("gravity.order"),
            _ => return None,
        };
        imu::field_of(param)
            .or_else(|| star_tracker::field_of(param))
            .or_else(|| gnss::field_of(param))
            .or_else(|| gravity::field_of(param))
            .or(match param {
                P::InitialAttitude => Some("hand_over.attitude_mrad"),
                P::InitialPosition => Some("hand_over.position_m"),
                P::InitialVelocity => Some("hand_over.velocity_mps"),
                _ => None,
            })
    }
}

impl FswConfig {
    /// The flight configuration for `launch_site` and its ground constants `sensor_frames`
    /// from the sensors' data sheets: every value they give converted to the flight
    /// software's units (the conversions' docs give each derivation), the optional state
    /// blocks they call for turned on (the IMU error states when a misalignment or
    /// g-sensitivity is given, the receiver's correlated-error states when a correlated
    /// error is, the installation states' random walk for a star tracker's low-frequency
    /// error, the gravity field and its allowance), every other parameter at its default
    /// ([`FswConfig::paper_defaults`]), then validated ([`FswConfig::validate`]).
    /// [`Datasheets::field_of`] names the data-sheet field behind a refusal.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the first configuration field the data
    /// sheets put out of its range (or a companion they leave off, e.g. a gyro misalignment
    /// without the accelerometer's); nothing is returned on error.
    pub fn from_datasheets(
        sheets: &Datasheets,
        launch_site: LaunchSite,
        sensor_frames: SensorFrames,
    ) -> Result<Self, FswError> {
        let mut config = Self::paper_defaults(launch_site, sensor_frames);
        sheets.imu.apply(&mut config);
        sheets.hand_over.apply(&mut config);
        sheets.star_tracker.apply(&mut config);
        sheets.gnss.apply(&mut config);
        sheets.gravity.apply(&mut config);
        config.validate()?;
        Ok(config)
    }
}
