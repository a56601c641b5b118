//! Input checking: nothing a sensor sends is trusted. Each check returns a typed verdict; the
//! scheduler counts every fault in [`crate::health::HealthCounters`] and reacts as documented
//! on each fault variant.

use nalgebra::{Quaternion, Vector3};
use nav_core::attitude;

use crate::error::FswError;
use crate::ports::{self, GnssFix, ImuSample, StarMeasurement};

/// Limits for IMU sample checks.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuLimits {
    /// Nominal sampling period (s). Default 0.002 (500 Hz, paper Section 3).
    pub period_s: f64,
    /// Accepted relative deviation of a sample's time step from the period. Default 0.1.
    pub period_tolerance: f64,
    /// The gyro's measurement range per axis (rad/s): a sample at or beyond it is saturated
    /// (a saturated IMU outputs its full-scale value). Default 7.0 rad/s (≈ 400 °/s; the
    /// paper's manoeuvres reach 100 °/s).
    pub max_rate_rad_s: f64,
    /// The accelerometer's measurement range per axis (m/s²), as the gyro's. Default
    /// 200 m/s² (≈ 20 g; the paper's manoeuvres reach 50 m/s²).
    pub max_specific_force_mps2: f64,
}

/// The parameter table's defaults ([`crate::config::Param`]).
impl Default for ImuLimits {
    fn default() -> Self {
        crate::config::FswConfig::table_defaults().imu
    }
}

impl ImuLimits {
    /// Checks every field against its range in the parameter table.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the first bad field.
    pub fn validate(&self) -> Result<(), FswError> {
        use crate::config::Param;
        Param::ImuPeriod.check(self.period_s)?;
        Param::ImuPeriodTolerance.check(self.period_tolerance)?;
        Param::ImuMaxRate.check(self.max_rate_rad_s)?;
        Param::ImuMaxSpecificForce.check(self.max_specific_force_mps2)
    }
}

/// Why an IMU sample was not used as it came.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ImuFault {
    /// A field is NaN or infinite. Reaction: sample discarded; the frame is propagated with
    /// the last good sample (hold), counted as a dropout.
    NonFinite,
    /// A rate or specific force beyond the configured limits (saturation or spike). Reaction:
    /// as [`ImuFault::NonFinite`].
    Saturated,
    /// Same sequence number as the previous sample (repeated sample), or one at most
    /// [`OUT_OF_ORDER_WINDOW`] behind it (a late, out-of-order sample). Reaction: discarded,
    /// the frame is propagated with the last good sample (hold).
    Duplicate,
    /// The time step disagrees with the period (zero, negative or a jump). Reaction: the
    /// sample's increments are used over the nominal period, and the time base is re-anchored
    /// to the sample's time.
    TimeJump,
}

impl core::fmt::Display for ImuFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NonFinite => "an IMU field is not finite",
            Self::Saturated => "an IMU rate or specific force is at or beyond its range",
            Self::Duplicate => "the IMU sample repeats or precedes the last one",
            Self::TimeJump => "the IMU time step disagrees with the period",
        })
    }
}

impl core::error::Error for ImuFault {}

/// A sequence number at most this many samples behind the last accepted one is a late
/// (out-of-order) sample, discarded as [`ImuFault::Duplicate`]. Farther behind is taken as a
/// counter restart, accepted as a forward gap (2 s at 500 Hz; without this window a late
/// sample read as a forward gap of about 2³² missing samples).
pub const OUT_OF_ORDER_WINDOW: u32 = 1000;

/// What an accepted IMU sample implies about the frames before it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuContinuity {
    /// Samples missing between the previous accepted sample and this one (sequence gap).
    pub missing_samples: u32,
}

/// Stateful IMU checker (sequence and time continuity).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuChecker {
    limits: ImuLimits,
    last_sequence: Option<u32>,
    last_time_s: Option<f64>,
}

impl ImuChecker {
    /// A checker with validated limits.
    ///
    /// # Errors
    /// As [`ImuLimits::validate`].
    pub fn new(limits: ImuLimits) -> Result<Self, FswError> {
        limits.validate()?;
        Ok(Self {
            limits,
            last_sequence: None,
            last_time_s: None,
        })
    }

    /// Checks one sample. On `Ok` the sample may be used as it is; the continuity tells how
    /// many samples were lost before it. On `Err(TimeJump)` the increments are still valid
    /// (see [`ImuFault::TimeJump`]); the checker has re-anchored its time base.
    ///
    /// # Errors
    /// The [`ImuFault`] found, in the order: non-finite, saturated, duplicate, time jump.
    pub fn check(&mut self, sample: &ImuSample) -> Result<ImuContinuity, ImuFault> {
        let delta_angle = ports::vector(&sample.delta_angle_rad);
        let delta_velocity = ports::vector(&sample.delta_velocity_mps);
        if !(attitude::all_finite3(&delta_angle)
            && attitude::all_finite3(&delta_velocity)
            && sample.time_s.is_finite())
        {
            return Err(ImuFault::NonFinite);
        }
        let max_angle = self.limits.max_rate_rad_s * self.limits.period_s;
        let max_velocity = self.limits.max_specific_force_mps2 * self.limits.period_s;
        // A saturated IMU outputs its full-scale value: at or beyond the range is saturated.
        if delta_angle.amax() >= max_angle || delta_velocity.amax() >= max_velocity {
            return Err(ImuFault::Saturated);
        }
        let behind = self
            .last_sequence
            .map(|last| last.wrapping_sub(sample.sequence))
            .is_some_and(|behind| behind <= OUT_OF_ORDER_WINDOW);
        if behind {
            return Err(ImuFault::Duplicate);
        }
        let missing_samples = self
            .last_sequence
            .map(|last| sample.sequence.wrapping_sub(last).saturating_sub(1))
            .unwrap_or(0);
        self.last_sequence = Some(sample.sequence);
        let expected_step_s = self.limits.period_s * (1.0 + f64::from(missing_samples));
        let time_ok = self.last_time_s.is_none_or(|last| {
            let step = sample.time_s - last;
            (step - expected_step_s).abs() <= self.limits.period_tolerance * self.limits.period_s
        });
        self.last_time_s = Some(sample.time_s);
        if time_ok {
            Ok(ImuContinuity { missing_samples })
        } else {
            Err(ImuFault::TimeJump)
        }
    }
}

/// Why a star-sensor measurement was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StarFault {
    /// A component or the time tag is not finite. Reaction: measurement discarded.
    NonFinite,
    /// The quaternion norm differs from 1 by more than the tolerance (zero quaternion
    /// included). Reaction: discarded (a badly non-unit attitude is a corrupted message, not a
    /// rounding issue).
    NotUnit,
}

impl core::fmt::Display for StarFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NonFinite => "a star-sensor component or time tag is not finite",
            Self::NotUnit => "the star-sensor quaternion is not unit within the tolerance",
        })
    }
}

impl core::error::Error for StarFault {}

/// Checks a star-sensor quaternion and returns it normalised, with its sign made continuous
/// with `previous` (a `q → −q` flip is the same attitude and is not a fault; it is undone here
/// so the residual never sees it) and whether a flip was undone.
///
/// # Errors
/// [`StarFault`] as documented on each variant.
pub fn check_star(
    measurement: &StarMeasurement,
    previous: Option<&Quaternion<f64>>,
    unit_norm_tolerance: f64,
) -> Result<(Quaternion<f64>, bool), StarFault> {
    let raw = ports::quaternion(&measurement.sensor_to_gcrf_wxyz);
    if !(measurement.time_tag_s.is_finite() && raw.coords.iter().all(|c| c.is_finite())) {
        return Err(StarFault::NonFinite);
    }
    let norm = nav_core::float::sqrt(raw.coords.dot(&raw.coords));
    if (norm - 1.0).abs() > unit_norm_tolerance {
        return Err(StarFault::NotUnit);
    }
    let unit = attitude::normalise(&raw).map_err(|_| StarFault::NotUnit)?;
    let flipped = previous.is_some_and(|last| last.coords.dot(&unit.coords) < 0.0);
    Ok(if flipped {
        (-unit, true)
    } else {
        (unit, false)
    })
}

/// Why a GNSS fix was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GnssFault {
    /// A component or the time tag is not finite. Reaction: discarded.
    NonFinite,
    /// The fix is farther from the navigation solution than the configured jump limit (a
    /// gross error, well beyond what the innovation gate is for). Reaction: discarded.
    Jump,
}

impl core::fmt::Display for GnssFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NonFinite => "a GNSS component or time tag is not finite",
            Self::Jump => {
                "the GNSS fix is farther from the navigation solution than the jump limit"
            }
        })
    }
}

impl core::error::Error for GnssFault {}

/// Checks a GNSS fix against the predicted antenna position (both in the same frame).
///
/// # Errors
/// [`GnssFault`] as documented on each variant.
pub fn check_gnss(
    fix: &GnssFix,
    fix_position_m: &Vector3<f64>,
    predicted_position_m: &Vector3<f64>,
    max_jump_m: f64,
) -> Result<(), GnssFault> {
    if !(fix.gps_seconds_of_week.is_finite() && attitude::all_finite3(fix_position_m)) {
        return Err(GnssFault::NonFinite);
    }
    if (fix_position_m - predicted_position_m).norm() > max_jump_m {
        return Err(GnssFault::Jump);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(sequence: u32, time_s: f64) -> ImuSample {
        ImuSample {
            sequence,
            time_s,
            delta_angle_rad: [1e-4, 0.0, 0.0],
            delta_velocity_mps: [0.0, 0.01, 0.0],
        }
    }

    #[test]
    fn imu_checker_counts_gaps_and_rejects_bad_samples() {
        let mut checker = ImuChecker::new(ImuLimits::default()).unwrap();
        assert_eq!(
            checker.check(&sample(7, 0.014)),
            Ok(ImuContinuity { missing_samples: 0 })
        );
        assert_eq!(
            checker.check(&sample(8, 0.016)),
            Ok(ImuContinuity { missing_samples: 0 })
        );
        assert_eq!(checker.check(&sample(8, 0.016)), Err(ImuFault::Duplicate));
        // A late sample (behind the last) is out of order, not a gap of 2³² − 2 samples.
        assert_eq!(checker.check(&sample(7, 0.014)), Err(ImuFault::Duplicate));
        assert_eq!(
            checker.check(&sample(11, 0.022)),
            Ok(ImuContinuity { missing_samples: 2 })
        );
        assert_eq!(checker.check(&sample(12, 0.022)), Err(ImuFault::TimeJump));
        assert_eq!(
            checker.check(&sample(13, 0.024)),
            Ok(ImuContinuity { missing_samples: 0 })
        );
        let mut nan = sample(14, 0.026);
        nan.delta_angle_rad[1] = f64::NAN;
        assert_eq!(checker.check(&nan), Err(ImuFault::NonFinite));
        let mut spike = sample(14, 0.026);
        spike.delta_velocity_mps[2] = 1.0; // 500 m/s² over 2 ms
        assert_eq!(checker.check(&spike), Err(ImuFault::Saturated));
    }

    #[test]
    fn imu_sequence_counter_wrap_is_continuous() {
        let mut checker = ImuChecker::new(ImuLimits::default()).unwrap();
        checker.check(&sample(u32::MAX, 1.0)).unwrap();
        assert_eq!(
            checker.check(&sample(0, 1.002)),
            Ok(ImuContinuity { missing_samples: 0 })
        );
    }

    #[test]
    fn bad_limits_name_the_field() {
        let limits = ImuLimits {
            max_rate_rad_s: -1.0,
            ..ImuLimits::default()
        };
        assert_eq!(
            limits.validate(),
            Err(FswError::InvalidConfiguration(
                crate::ConfigField::Parameter(crate::config::Param::ImuMaxRate)
            ))
        );
    }

    #[test]
    fn star_check_undoes_sign_flips_and_rejects_corrupt_quaternions() {
        let previous = Quaternion::new(0.5, 0.5, 0.5, 0.5);
        let flipped = StarMeasurement {
            time_tag_s: 1.0,
            sensor_to_gcrf_wxyz: [-0.5, -0.5, -0.5, -0.5],
            head: 0,
        };
        let (q, was_flipped) = check_star(&flipped, Some(&previous), 1e-3).unwrap();
        assert!(was_flipped);
        assert!((q.coords - previous.coords).norm() < 1e-15);
        let zero = StarMeasurement {
            time_tag_s: 1.0,
            sensor_to_gcrf_wxyz: [0.0; 4],
            head: 0,
        };
        assert_eq!(check_star(&zero, None, 1e-3), Err(StarFault::NotUnit));
        let long = StarMeasurement {
            time_tag_s: 1.0,
            sensor_to_gcrf_wxyz: [1.01, 0.0, 0.0, 0.0],
            head: 0,
        };
        assert_eq!(check_star(&long, None, 1e-3), Err(StarFault::NotUnit));
        let nan = StarMeasurement {
            time_tag_s: f64::NAN,
            sensor_to_gcrf_wxyz: [1.0, 0.0, 0.0, 0.0],
            head: 0,
        };
        assert_eq!(check_star(&nan, None, 1e-3), Err(StarFault::NonFinite));
    }

    #[test]
    fn gnss_jump_is_rejected() {
        let fix = GnssFix {
            gps_week: 2_000,
            gps_seconds_of_week: 10.0,
            position_ecef_m: [0.0; 3],
            velocity_ecef_mps: None,
        };
        let predicted = Vector3::new(0.0, 0.0, 0.0);
        assert_eq!(
            check_gnss(&fix, &Vector3::new(50.0, 0.0, 0.0), &predicted, 100.0),
            Ok(())
        );
        assert_eq!(
            check_gnss(&fix, &Vector3::new(150.0, 0.0, 0.0), &predicted, 100.0),
            Err(GnssFault::Jump)
        );
        assert_eq!(
            check_gnss(
                &fix,
                &Vector3::new(f64::INFINITY, 0.0, 0.0),
                &predicted,
                100.0
            ),
            Err(GnssFault::NonFinite)
        );
    }

    /// Boundaries of every check: `>` against `>=` at the limits, `&&` against `||` in the
    /// tolerance check, and the sign of the GNSS difference (mutations the other tests
    /// would let through).
    #[test]
    fn limits_are_inclusive_and_validation_refuses_each_edge() {
        let limits = ImuLimits::default();
        let refused = |change: fn(&mut ImuLimits)| {
            let mut bad = limits;
            change(&mut bad);
            bad.validate().is_err()
        };
        assert!(refused(|l| l.period_s = 0.0));
        assert!(refused(|l| l.period_tolerance = 1.0));
        assert!(refused(|l| l.period_tolerance = 2.0));
        assert!(refused(|l| l.period_tolerance = 0.0));
        assert!(limits.validate().is_ok());

        // An increment at the range (a saturated IMU's full-scale output) is saturated, on
        // either channel; just below it is accepted.
        let max_angle = limits.max_rate_rad_s * limits.period_s;
        let max_velocity = limits.max_specific_force_mps2 * limits.period_s;
        let below = 1.0 - 1e-12;
        let sample = |angle: f64, velocity: f64| ImuSample {
            sequence: 1,
            time_s: 0.002,
            delta_angle_rad: [angle, -angle, 0.0],
            delta_velocity_mps: [0.0, velocity, -velocity],
        };
        let check = |s: &ImuSample| ImuChecker::new(limits).unwrap().check(s);
        assert!(check(&sample(max_angle * below, max_velocity * below)).is_ok());
        assert_eq!(check(&sample(max_angle, 0.0)), Err(ImuFault::Saturated));
        assert_eq!(check(&sample(0.0, max_velocity)), Err(ImuFault::Saturated));

        // Star: a norm exactly at the tolerance is accepted; a zero dot product with the
        // previous sample is not a sign change.
        let long = StarMeasurement {
            time_tag_s: 1.0,
            sensor_to_gcrf_wxyz: [1.5, 0.0, 0.0, 0.0],
            head: 0,
        };
        assert!(check_star(&long, None, 0.5).is_ok());
        let previous = Quaternion::new(1.0, 0.0, 0.0, 0.0);
        let orthogonal = StarMeasurement {
            time_tag_s: 1.0,
            sensor_to_gcrf_wxyz: [0.0, 1.0, 0.0, 0.0],
            head: 0,
        };
        assert_eq!(
            check_star(&orthogonal, Some(&previous), 1e-3).map(|(_, f)| f),
            Ok(false)
        );

        // GNSS: a jump of exactly the limit is accepted (3-4-5 triangle), and a fix equal to a
        // far-away prediction is no jump at all.
        let fix = GnssFix {
            gps_week: 2_000,
            gps_seconds_of_week: 1.0,
            position_ecef_m: [0.0; 3],
            velocity_ecef_mps: None,
        };
        let origin = Vector3::zeros();
        assert_eq!(
            check_gnss(&fix, &Vector3::new(3.0, 4.0, 0.0), &origin, 5.0),
            Ok(())
        );
        let far = Vector3::new(7.0e6, -1.0e6, 2.0e6);
        assert_eq!(check_gnss(&fix, &far, &far, 1.0), Ok(()));
    }
}
