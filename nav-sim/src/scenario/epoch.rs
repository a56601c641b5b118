//! The launch epoch on the ground: time scales and Earth orientation, computed once into the
//! flight configuration (`docs/guide/frames-and-time.md`).
//!
//! * Time scales with leap seconds: [`hifitime`] (UTC → TAI, TT and GPS time; its leap-second
//!   table is IERS Bulletin C's). hifitime accepts second 60 only on a leap second's day but
//!   reads `23:59:60` as `23:59:59` (one UTC count for both); the epoch keeps that second
//!   as a flag and moves TAI, TT, GPS time and UT1 one SI second on.
//! * GCRF → ITRF: [`sofars`], a Rust port of IAU SOFA, `c2t06a` (IAU 2006/2000A
//!   precession–nutation, Earth rotation angle, polar motion; IERS Conventions 2010, ch. 5,
//!   eq. 5.1: `[ITRS] = W(t) R₃(ERA) Q(t) [GCRS]`). The celestial-pole offsets dX, dY (below
//!   1 mas) are not applied.
//! * The Earth orientation parameters of the launch day (UT1 − UTC, polar motion `x_p`, `y_p`)
//!   are configuration, from IERS Bulletin A for the day.
//!
//! The flight code receives three constants ([`GroundConstants`]): the rotation GCRF →
//! launch-inertial at `t₀` (`C_le · ITRF←GCRF(t₀)`), the launch epoch in GPS time, and the
//! Earth rotation axis (the CIP) in ITRF.

use hifitime::{Duration, Epoch, TimeScale};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use nav_core::frames::LaunchFrame;
use nav_fsw::sensor_frames::SensorFrames;

/// Arcseconds per radian.
const ARCSEC_PER_RAD: f64 = 206_264.806_247_096_36;
/// Modified Julian Date zero point as a Julian Date (days).
const MJD_ZERO_JD: f64 = 2_400_000.5;
/// Rate of the Earth rotation angle (rad/s): `2π · 1.00273781191135448 / 86400` (IERS
/// Conventions 2010, eq. 5.15).
pub const EARTH_ROTATION_ANGLE_RATE_RAD_S: f64 =
    2.0 * std::f64::consts::PI * 1.002_737_811_911_354_5 / 86_400.0;

/// The Earth orientation parameters of the launch day (IERS Bulletin A).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EarthOrientation {
    /// UT1 − UTC (s). Ignoring it (0) rotates ITRF by `ω_e · ΔUT1`: 0.1 s is 7.3e-6 rad,
    /// 46 m at the Earth's surface.
    pub ut1_minus_utc_s: f64,
    /// Polar motion `x_p` (arcsec). Ignoring it tilts ITRF by up to ~0.5″ (15 m at the surface).
    pub polar_motion_x_arcsec: f64,
    /// Polar motion `y_p` (arcsec).
    pub polar_motion_y_arcsec: f64,
}

/// Why an epoch could not be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EpochError {
    /// The UTC string does not parse.
    #[error("launch epoch {text:?} is not an ISO 8601 UTC date-time: {reason}")]
    Parse {
        /// The text.
        text: String,
        /// hifitime's reason.
        reason: String,
    },
    /// An Earth orientation parameter is out of range.
    #[error("{key} = {value} {unit} is outside [-{limit}, {limit}] {unit} ({reason})")]
    EarthOrientation {
        /// The parameter's key in `[launch_site.earth_orientation]`, e.g. `ut1_minus_utc_s`.
        key: &'static str,
        /// The value given.
        value: f64,
        /// The largest magnitude accepted.
        limit: f64,
        /// The unit of the value and the limit.
        unit: &'static str,
        /// Why the limit.
        reason: &'static str,
    },
    /// The epoch is outside GPS time's week range.
    #[error("launch epoch {0} is outside GPS weeks 0..=9999")]
    GpsWeek(String),
}

/// A launch epoch (UTC) with its Earth orientation parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaunchEpoch {
    /// hifitime's UTC count (`23:59:59` for `23:59:60`).
    utc: Epoch,
    /// The epoch lies in an inserted leap second (`23:59:60` UTC): one SI second after `utc`.
    in_leap_second: bool,
    earth: EarthOrientation,
}

/// What the flight software needs from the ground, computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundConstants {
    /// GCRF → launch-inertial rotation and launch epoch in GPS time.
    pub sensor_frames: SensorFrames,
    /// The Earth rotation axis (CIP) in ITRF, unit.
    pub earth_axis_ecef: [f64; 3],
}

impl LaunchEpoch {
    /// Parses an ISO 8601 UTC epoch (e.g. `2024-02-26T04:00:00Z`) and checks the parameters.
    ///
    /// # Errors
    /// [`EpochError::Parse`] or [`EpochError::EarthOrientation`].
    pub fn new(utc: &str, earth: EarthOrientation) -> Result<Self, EpochError> {
        let text = utc.trim_end_matches('Z').to_string() + " UTC";
        let epoch = Epoch::from_gregorian_str(&text).map_err(|error| EpochError::Parse {
            text: utc.to_string(),
            reason: error.to_string(),
        })?;
        earth.check()?;
        Ok(Self {
            utc: epoch.to_time_scale(TimeScale::UTC),
            in_leap_second: second_field_is_60(utc),
            earth,
        })
    }

    /// The epoch `elapsed_s` seconds (SI, continuous: GPS, TAI and TT seconds) after this one:
    /// formed in TAI, so a leap second on the way counts as the second it is.
    pub fn after(&self, elapsed_s: f64) -> Self {
        let tai = self.tai() + Duration::from_seconds(elapsed_s);
        let utc = tai.to_time_scale(TimeScale::UTC);
        // hifitime's UTC reads the leap second as the second before it: TAI and back differ.
        let in_leap_second = utc.to_time_scale(TimeScale::TAI) != tai;
        Self {
            utc,
            in_leap_second,
            earth: self.earth,
        }
    }

    /// The SI seconds hifitime's UTC count is behind the instant: 1 inside a leap second.
    fn leap_second_s(&self) -> f64 {
        if self.in_leap_second {
            1.0
        } else {
            0.0
        }
    }

    /// The epoch as a TAI instant.
    fn tai(&self) -> Epoch {
        self.utc.to_time_scale(TimeScale::TAI) + Duration::from_seconds(self.leap_second_s())
    }

    /// TAI − UTC at the epoch (s): the leap seconds (IERS Bulletin C). Formed from the
    /// epoch's TAI and UTC durations: hifitime's `leap_seconds` looks its table up by TAI, so
    /// in the 37 s before a leap second it already answers the new count.
    pub fn tai_minus_utc_s(&self) -> f64 {
        (self.utc.to_tai_duration() - self.utc.to_utc_duration()).to_seconds()
    }

    /// GPS − UTC at the epoch (s): TAI − UTC − 19 s (GPS time = TAI − 19 s, IS-GPS-200).
    pub fn gps_minus_utc_s(&self) -> f64 {
        self.tai_minus_utc_s() - 19.0
    }

    /// GPS week (full count) and seconds of week of the epoch.
    ///
    /// # Errors
    /// [`EpochError::GpsWeek`] outside weeks 0..=9999.
    pub fn gps_week_and_seconds(&self) -> Result<(u32, f64), EpochError> {
        let gps =
            self.utc.to_time_scale(TimeScale::GPST) + Duration::from_seconds(self.leap_second_s());
        let outside = || EpochError::GpsWeek(self.utc.to_string());
        if gps.to_gpst_seconds() < 0.0 {
            return Err(outside());
        }
        let (week, nanoseconds) = gps.to_time_of_week();
        if week > nav_fsw::sensor_frames::MAX_GPS_WEEK {
            return Err(outside());
        }
        // Below 6.1e14 ns: exact in f64, then one rounding to seconds.
        Ok((week, nanoseconds as f64 * 1e-9))
    }

    /// TT and UT1 as Modified Julian Dates (days): the SOFA 2-part dates are `2400000.5 + mjd`.
    /// Inside a leap second UT1 runs on from `23:59:59` by the second's elapsed part, with
    /// the UT1 − UTC of before the leap (Bulletin A's value of that day).
    fn tt_and_ut1_mjd(&self) -> (f64, f64) {
        let tt = self.tai().to_mjd_tt_days();
        let ut1_offset_s = self.earth.ut1_minus_utc_s + self.leap_second_s();
        let ut1 = self.utc.to_mjd_utc_days() + ut1_offset_s / 86_400.0;
        (tt, ut1)
    }

    /// Polar motion (rad).
    fn polar_motion_rad(&self) -> (f64, f64) {
        (
            self.earth.polar_motion_x_arcsec / ARCSEC_PER_RAD,
            self.earth.polar_motion_y_arcsec / ARCSEC_PER_RAD,
        )
    }

    /// ITRF ← GCRF at the epoch (SOFA `c2t06a`, IAU 2006/2000A, CIO based).
    pub fn itrf_from_gcrf(&self) -> Matrix3<f64> {
        self.itrf_from_gcrf_after(0.0)
    }

    /// ITRF ← GCRF `elapsed_s` SI seconds after the epoch. TT and UT1 advance continuously
    /// from their values at the epoch (UT1's rate differs from SI by ~1e-8, 4e-5 s a
    /// flight-hour): a leap second inserted in UTC during the flight moves neither.
    pub fn itrf_from_gcrf_after(&self, elapsed_s: f64) -> Matrix3<f64> {
        let (tt, ut1) = self.tt_and_ut1_mjd();
        let (xp, yp) = self.polar_motion_rad();
        let days = elapsed_s / 86_400.0;
        itrf_from_gcrf_mjd(tt + days, ut1 + days, xp, yp)
    }

    /// The Earth rotation axis (the CIP) in ITRF: the third column of the polar-motion matrix
    /// `W` (SOFA `pom00` with `sp00`), ≈ `[x_p, −y_p, 1]`.
    pub fn earth_axis_ecef(&self) -> [f64; 3] {
        let (tt, _) = self.tt_and_ut1_mjd();
        let (xp, yp) = self.polar_motion_rad();
        let w = sofars::pnp::pom00(xp, yp, sofars::pnp::sp00(MJD_ZERO_JD, tt));
        let axis = Vector3::new(w[0][2], w[1][2], w[2][2]).normalize();
        [axis.x, axis.y, axis.z]
    }

    /// The flight constants for the launch frame `frame` (built with any Earth axis: only its
    /// launch-from-ECEF rotation is used).
    ///
    /// # Errors
    /// [`EpochError::GpsWeek`] outside the GPS week range.
    pub fn ground_constants(&self, frame: &LaunchFrame) -> Result<GroundConstants, EpochError> {
        let launch_from_gcrf = frame.launch_from_ecef() * self.itrf_from_gcrf();
        let rotation = Rotation3::from_matrix(&launch_from_gcrf);
        let q = UnitQuaternion::from_rotation_matrix(&rotation).into_inner();
        // One sign, w ≥ 0, so equal inputs give equal configuration bits.
        let q = if q.w < 0.0 { -q } else { q };
        let (week, seconds) = self.gps_week_and_seconds()?;
        Ok(GroundConstants {
            sensor_frames: SensorFrames {
                gcrf_to_launch_inertial_wxyz: [q.w, q.i, q.j, q.k],
                launch_epoch_gps_week: week,
                launch_epoch_gps_seconds_of_week: seconds,
            },
            earth_axis_ecef: self.earth_axis_ecef(),
        })
    }

    /// The Earth orientation parameters of the launch day.
    pub fn earth_orientation(&self) -> EarthOrientation {
        self.earth
    }

    /// The UTC epoch as ISO 8601 text without a zone (hifitime's form, fractional seconds only
    /// when there are any; second 60 inside a leap second), e.g. `2024-02-26T04:00:00`.
    pub fn utc_text(&self) -> String {
        let shown = self.utc.to_string();
        let text = shown.strip_suffix(" UTC").unwrap_or(&shown).to_string();
        match text.get(17..19) {
            Some("59") if self.in_leap_second => format!("{}60{}", &text[..17], &text[19..]),
            _ => text,
        }
    }
}

impl EarthOrientation {
    /// Checks each parameter against its range (Bulletin A's values never leave it).
    ///
    /// # Errors
    /// [`EpochError::EarthOrientation`] naming the first parameter out of range.
    pub fn check(&self) -> Result<(), EpochError> {
        let pole = "the pole wanders within about 0.6 arcsec of its mean";
        for (key, value, limit, unit, reason) in [
            (
                "ut1_minus_utc_s",
                self.ut1_minus_utc_s,
                0.9,
                "s",
                "leap seconds keep |UT1 - UTC| <= 0.9 s",
            ),
            (
                "polar_motion_x_arcsec",
                self.polar_motion_x_arcsec,
                2.0,
                "arcsec",
                pole,
            ),
            (
                "polar_motion_y_arcsec",
                self.polar_motion_y_arcsec,
                2.0,
                "arcsec",
                pole,
            ),
        ] {
            if value.is_nan() || value.abs() > limit {
                return Err(EpochError::EarthOrientation {
                    key,
                    value,
                    limit,
                    unit,
                    reason,
                });
            }
        }
        Ok(())
    }
}

/// Whether an ISO 8601 date-time's seconds field is 60 (a leap second, which hifitime accepts
/// only on a leap second's day and folds into second 59).
fn second_field_is_60(utc: &str) -> bool {
    utc.split_once(['T', ' '])
        .and_then(|(_, time)| time.split(':').nth(2))
        .is_some_and(|second| second.starts_with("60"))
}

/// ITRF ← GCRF for TT and UT1 given as Modified Julian Dates (days) and the polar motion
/// (rad): SOFA `c2t06a(2400000.5, tt, 2400000.5, ut1, x_p, y_p)`, row-major.
pub fn itrf_from_gcrf_mjd(tt_mjd: f64, ut1_mjd: f64, xp_rad: f64, yp_rad: f64) -> Matrix3<f64> {
    let m = sofars::pnp::c2t06a(MJD_ZERO_JD, tt_mjd, MJD_ZERO_JD, ut1_mjd, xp_rad, yp_rad);
    Matrix3::from_fn(|row, column| m[row][column])
}

/// Launch-inertial truth to ITRF with the full IAU 2006/2000A chain at every time (the
/// simulator's GNSS receiver): `r_e = ITRF←GCRF(t) C_igᵀ (p_i − o_i)`, `o_i` the Earth centre
/// in launch-inertial axes; `v_e = ITRF←GCRF(t) C_igᵀ v_i − ERA-rate · k × r_e` (the rate of
/// `R₃(ERA)`; precession–nutation and polar-motion rates, below 1e-11 rad/s, are omitted).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ItrfFromLaunchInertial {
    epoch: LaunchEpoch,
    gcrf_from_launch: Matrix3<f64>,
    earth_centre_launch_m: Vector3<f64>,
    earth_axis_ecef: Vector3<f64>,
}

impl ItrfFromLaunchInertial {
    /// The conversion for `frame` launched at `epoch`.
    pub fn new(epoch: &LaunchEpoch, frame: &LaunchFrame) -> Self {
        let [x, y, z] = epoch.earth_axis_ecef();
        Self {
            epoch: *epoch,
            gcrf_from_launch: (frame.launch_from_ecef() * epoch.itrf_from_gcrf()).transpose(),
            earth_centre_launch_m: *frame.earth_centre_launch_m(),
            earth_axis_ecef: Vector3::new(x, y, z),
        }
    }

    /// ITRF position (m) and, with a velocity, ITRF velocity relative to the rotating Earth
    /// (m/s) of a launch-inertial position (m) and velocity (m/s) at navigation time `time_s`.
    pub fn convert(
        &self,
        position_m: &Vector3<f64>,
        velocity_mps: Option<&Vector3<f64>>,
        time_s: f64,
    ) -> (Vector3<f64>, Option<Vector3<f64>>) {
        let itrf_from_gcrf = self.epoch.itrf_from_gcrf_after(time_s);
        let geocentric = position_m - self.earth_centre_launch_m;
        let position_ecef = itrf_from_gcrf * (self.gcrf_from_launch * geocentric);
        let velocity_ecef = velocity_mps.map(|velocity| {
            itrf_from_gcrf * (self.gcrf_from_launch * velocity)
                - self.earth_axis_ecef.cross(&position_ecef) * EARTH_ROTATION_ANGLE_RATE_RAD_S
        });
        (position_ecef, velocity_ecef)
    }
}
