//! Sensor frames and time scales at the ports: the star tracker's attitude relative to GCRF
//! and the GNSS receiver's GPS-time tags, turned into the launch-inertial frame and navigation
//! time with constants computed once on the ground (`docs/guide/frames-and-time.md`).
//!
//! * Star tracker: `q_gs`, sensor frame → GCRF. With the ground constant `q_ig` (GCRF →
//!   launch-inertial at the launch epoch; the precession–nutation of date, the Earth rotation
//!   angle and polar motion at `t₀`, then launch-from-ECEF at the site), the attitude the
//!   filter uses is `q_is = q_ig ⊗ q_gs` (Hamilton, scalar first). `q_ig` is constant over a
//!   flight: precession–nutation moves by less than 0.01″ in a few hours, below 1/1000 of the
//!   star sensor's 10″ noise.
//! * GNSS: fixes are tagged on the GPS time scale as week (full count since 1980-01-06, not
//!   modulo 1024) and seconds of week. GPS time has no leap seconds, so navigation time
//!   (seconds since the launch epoch `t₀`) is `t = 604800 (w − w₀) + (s − s₀)`, with the launch
//!   epoch's `(w₀, s₀)` computed on the ground from its UTC with the leap seconds of the day.
//!   The week and second differences are formed separately, so no ~1e9 s GPS time is ever
//!   formed and cancelled: the result is exact to the rounding of `s − s₀` (≤ 6e-11 s).

use nalgebra::Quaternion;

use crate::error::{ConfigField, FswError};

/// Seconds in a GPS week.
pub const SECONDS_PER_WEEK: f64 = 604_800.0;
/// Largest accepted GPS week (full count): week 9999 ends in the year 2171.
pub const MAX_GPS_WEEK: u32 = 9_999;

/// The ground-computed constants that relate the sensors' frames and time scales to the
/// launch-inertial frame and navigation time.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SensorFrames {
    /// `q_ig` `[w, x, y, z]`: GCRF → launch-inertial at the launch epoch (Hamilton, scalar
    /// first; `v_i = q_ig ⊗ v_g ⊗ q_ig*`). Unit ([`nav_core::attitude::is_unit_norm`]).
    pub gcrf_to_launch_inertial_wxyz: [f64; 4],
    /// GPS week of the launch epoch `w₀` (full count), at most [`MAX_GPS_WEEK`].
    pub launch_epoch_gps_week: u32,
    /// GPS seconds of week of the launch epoch `s₀` (s), in `[0, 604800)`.
    pub launch_epoch_gps_seconds_of_week: f64,
}

/// Why a GPS time tag was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GpsTimeFault {
    /// The seconds of week are NaN, infinite, negative or not below 604800.
    SecondsOfWeek,
    /// The week is beyond [`MAX_GPS_WEEK`].
    Week,
}

impl core::fmt::Display for GpsTimeFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::SecondsOfWeek => "GPS seconds of week must be finite and in [0, 604800)",
            Self::Week => "GPS week is beyond 9999",
        })
    }
}

impl core::error::Error for GpsTimeFault {}

/// Whether `(week, seconds)` is a valid GPS time tag.
fn check_gps_time(week: u32, seconds_of_week: f64) -> Result<(), GpsTimeFault> {
    if !(seconds_of_week.is_finite() && (0.0..SECONDS_PER_WEEK).contains(&seconds_of_week)) {
        return Err(GpsTimeFault::SecondsOfWeek);
    }
    if week > MAX_GPS_WEEK {
        return Err(GpsTimeFault::Week);
    }
    Ok(())
}

impl SensorFrames {
    /// GCRF axes equal to the launch-inertial axes and the launch epoch at GPS week 1000,
    /// 0 s: for tests and tools whose sensors already speak the launch-inertial frame and
    /// navigation time (a fix at navigation time `t` is [`Self::gps_time`]`(t)`).
    ///
    /// **A placeholder, never a launch's constants**: a real star tracker read through it is
    /// off by the launch frame's whole rotation and every GNSS fix by years. A flight image
    /// carries its launch's values, which `nav-sim ground-constants --format rust` prints.
    pub const ALIGNED: Self = Self {
        gcrf_to_launch_inertial_wxyz: [1.0, 0.0, 0.0, 0.0],
        launch_epoch_gps_week: 1000,
        launch_epoch_gps_seconds_of_week: 0.0,
    };

    /// Checks `q_ig` is finite and unit, the epoch a valid GPS time.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] ([`ConfigField::SensorFrames`]).
    pub fn validate(&self) -> Result<(), FswError> {
        let q = self.gcrf_to_launch_inertial_wxyz;
        let norm_squared: f64 = q.iter().map(|c| c * c).sum();
        let unit = q.iter().all(|c| c.is_finite())
            && nav_core::attitude::is_unit_norm(nav_core::float::sqrt(norm_squared));
        let epoch = check_gps_time(
            self.launch_epoch_gps_week,
            self.launch_epoch_gps_seconds_of_week,
        );
        if unit && epoch.is_ok() {
            Ok(())
        } else {
            Err(FswError::InvalidConfiguration(ConfigField::SensorFrames))
        }
    }

    /// The star tracker's attitude in the launch-inertial frame: `q_is = q_ig ⊗ q_gs`.
    pub fn star_in_launch_inertial(&self, sensor_to_gcrf: &Quaternion<f64>) -> Quaternion<f64> {
        let [w, x, y, z] = self.gcrf_to_launch_inertial_wxyz;
        Quaternion::new(w, x, y, z) * sensor_to_gcrf
    }

    /// Navigation time (s since the launch epoch) of the GPS time `(week, seconds_of_week)`:
    /// `604800 (w − w₀) + (s − s₀)` (module docs).
    ///
    /// # Errors
    /// [`GpsTimeFault`] for a tag outside the GPS time ranges.
    pub fn navigation_time_s(&self, week: u32, seconds_of_week: f64) -> Result<f64, GpsTimeFault> {
        check_gps_time(week, seconds_of_week)?;
        let weeks = if week >= self.launch_epoch_gps_week {
            f64::from(week.saturating_sub(self.launch_epoch_gps_week))
        } else {
            -f64::from(self.launch_epoch_gps_week.saturating_sub(week))
        };
        let seconds = seconds_of_week - self.launch_epoch_gps_seconds_of_week;
        Ok(weeks * SECONDS_PER_WEEK + seconds)
    }

    /// The GPS time `(week, seconds of week)` of navigation time `time_s` (the inverse of
    /// [`Self::navigation_time_s`], for simulators and tests; `None` before GPS week 0 or
    /// beyond [`MAX_GPS_WEEK`]). Bounded: at most one carry each way.
    pub fn gps_time(&self, time_s: f64) -> Option<(u32, f64)> {
        if !time_s.is_finite() {
            return None;
        }
        let whole_weeks = libm::floor(time_s / SECONDS_PER_WEEK);
        let mut seconds =
            (time_s - whole_weeks * SECONDS_PER_WEEK) + self.launch_epoch_gps_seconds_of_week;
        let mut weeks = whole_weeks;
        if seconds >= SECONDS_PER_WEEK {
            seconds -= SECONDS_PER_WEEK;
            weeks += 1.0;
        } else if seconds < 0.0 {
            seconds += SECONDS_PER_WEEK;
            weeks -= 1.0;
        }
        let week = f64::from(self.launch_epoch_gps_week) + weeks;
        let valid = (0.0..=f64::from(MAX_GPS_WEEK)).contains(&week);
        // `week` is an integer in [0, MAX_GPS_WEEK]: count it down to a u32 without a cast.
        let week = valid.then(|| integer_to_u32(week))??;
        check_gps_time(week, seconds).ok().map(|()| (week, seconds))
    }
}

/// The integer `value` in `[0, MAX_GPS_WEEK]` as a `u32` (binary digits, 14 steps; no cast).
fn integer_to_u32(value: f64) -> Option<u32> {
    let mut remaining = value;
    let mut result: u32 = 0;
    for bit in (0..14_u32).rev() {
        let weight = f64::from(1_u32 << bit);
        if remaining >= weight {
            remaining -= weight;
            result |= 1 << bit;
        }
    }
    (remaining == 0.0).then_some(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The launch epoch of the leap-second test: 2016-12-31T23:55:00 UTC is GPS week 1929,
    /// 604 517 s of week (23:55:17 GPS time on Saturday) (GPS − UTC = 17 s until 2017-01-01T00:00:00 UTC; IERS Bulletin C 52).
    fn before_the_leap_second() -> SensorFrames {
        SensorFrames {
            gcrf_to_launch_inertial_wxyz: [1.0, 0.0, 0.0, 0.0],
            launch_epoch_gps_week: 1929,
            launch_epoch_gps_seconds_of_week: 604_517.0,
        }
    }

    /// GPS time is continuous across the UTC leap second at the end of 2016: 2017-01-01
    /// 00:00:00 UTC is 00:00:18 GPS time (week 1930, 18 s), `5 · 60 + 1` (the leap second)
    /// `= 301 s` after the epoch, across a week roll, exactly.
    #[test]
    fn navigation_time_across_a_week_roll_and_the_leap_second() {
        let frames = before_the_leap_second();
        let t = frames.navigation_time_s(1930, 18.0).unwrap();
        assert_eq!(t.to_bits(), 301.0_f64.to_bits());
        assert_eq!(frames.navigation_time_s(1929, 604_517.0), Ok(0.0));
        assert_eq!(frames.gps_time(301.0), Some((1930, 18.0)));
        assert_eq!(frames.gps_time(0.0), Some((1929, 604_517.0)));
        assert_eq!(frames.gps_time(-604_800.0), Some((1928, 604_517.0)));
        for time_s in [-1.5, 0.002, 302.998, 3_600.0, 1.0e6] {
            let (week, seconds) = frames.gps_time(time_s).unwrap();
            let back = frames.navigation_time_s(week, seconds).unwrap();
            assert!((back - time_s).abs() < 1e-9, "{time_s}: {back}");
        }
    }

    #[test]
    fn bad_tags_and_constants_are_refused() {
        let frames = before_the_leap_second();
        assert_eq!(frames.validate(), Ok(()));
        for seconds in [f64::NAN, -1e-9, SECONDS_PER_WEEK, f64::INFINITY] {
            assert_eq!(
                frames.navigation_time_s(1930, seconds),
                Err(GpsTimeFault::SecondsOfWeek)
            );
        }
        assert_eq!(
            frames.navigation_time_s(10_000, 0.0),
            Err(GpsTimeFault::Week)
        );
        let mut bad = frames;
        bad.gcrf_to_launch_inertial_wxyz = [1.0, 1e-4, 0.0, 0.0];
        assert!(bad.validate().is_err());
        bad = frames;
        bad.launch_epoch_gps_seconds_of_week = SECONDS_PER_WEEK;
        assert!(bad.validate().is_err());
        bad = frames;
        bad.launch_epoch_gps_week = MAX_GPS_WEEK + 1;
        assert!(bad.validate().is_err());
    }

    /// `q_is = q_ig ⊗ q_gs`: a sensor aligned with GCRF reads `q_ig` itself, and a vector
    /// rotated through both equals the vector rotated by the product.
    #[test]
    fn star_attitude_is_composed_with_the_ground_rotation() {
        let half = core::f64::consts::FRAC_PI_8;
        let frames = SensorFrames {
            gcrf_to_launch_inertial_wxyz: [libm::cos(half), 0.0, 0.0, libm::sin(half)],
            ..before_the_leap_second()
        };
        let identity = Quaternion::new(1.0, 0.0, 0.0, 0.0);
        let q = frames.star_in_launch_inertial(&identity);
        assert!(
            (q.coords - Quaternion::new(libm::cos(half), 0.0, 0.0, libm::sin(half)).coords).norm()
                < 1e-16
        );
        let q_gs = nalgebra::UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3);
        let q_ig = nalgebra::UnitQuaternion::from_quaternion(q);
        let v = nalgebra::Vector3::new(0.3, -0.5, 0.8);
        let composed = nalgebra::UnitQuaternion::from_quaternion(
            frames.star_in_launch_inertial(q_gs.quaternion()),
        );
        assert!((composed * v - q_ig * (q_gs * v)).norm() < 1e-15);
    }
}
