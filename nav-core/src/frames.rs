//! WGS-84 constants, the launch site, and the launch / launch-inertial frames.
//!
//! * **Launch frame** `l`: origin at the launch site, `y` up along the geodetic normal
//!   (ellipsoid normal), `x` horizontal along the launch azimuth (measured from north toward
//!   east), `z = x × y` (right-handed). It rotates with the Earth.
//! * **Launch-inertial frame** `i`: the launch frame frozen in inertial space at the launch
//!   epoch `t₀`. It is the navigation frame of this crate.
//! * **ECEF-at-epoch inertial axes** `I`: the ECEF axes frozen at `t₀` (origin at the Earth
//!   centre). A point fixed in ECEF moves in `I` by the Earth rotation `ω_e (t − t₀)` about `z`.
//!
//! So `p_i = C (R_k(ω_e (t − t₀)) r_e − r_site)`, where `C = C_le` is the launch-from-ECEF
//! rotation at the site and `R_k(θ)` the active rotation by `θ` about the Earth rotation axis
//! `k` (the celestial intermediate pole in ECEF, [`LaunchSite::earth_axis_ecef`]; `[0, 0, 1]`
//! when polar motion is neglected). Times are navigation times, seconds since the launch
//! epoch `t₀` (so `t₀ = 0`). With `W` the polar-motion matrix and `E(t)` the Earth rotation
//! angle, ITRF ← GCRF is `W R₃(E(t)) Q(t)` (IERS Conventions 2010, eq. 5.1); with the
//! precession–nutation `Q` constant over a flight, ITRF(t₀) ← ITRF(t) is
//! `W R₃(E(t₀) − E(t)) Wᵀ`, the active rotation by `E(t) − E(t₀) = ω_e (t − t₀)` about
//! `k = W ẑ` (`docs/guide/frames-and-time.md` bounds what these approximations cost).
//! Geodetic-to-ECEF follows NIMA TR8350.2 (WGS-84), eq. 4-14; the east/north/up basis is the
//! standard one (e.g. Groves, *Principles of GNSS, Inertial, and Multisensor Integrated
//! Navigation Systems*, 2nd ed., eq. 2.99).

use nalgebra::{Matrix3, Vector3};

use crate::attitude::all_finite3;
use crate::NavError;

/// WGS-84 semi-major axis `a` (m).
pub const WGS84_SEMI_MAJOR_AXIS_M: f64 = 6_378_137.0;
/// WGS-84 flattening `f` (dimensionless).
pub const WGS84_FLATTENING: f64 = 1.0 / 298.257_223_563;
/// WGS-84 first eccentricity squared `e² = f (2 − f)` (dimensionless).
pub const WGS84_ECCENTRICITY_SQUARED: f64 = WGS84_FLATTENING * (2.0 - WGS84_FLATTENING);
/// WGS-84 semi-minor axis `b = a (1 − f)` (m).
pub const WGS84_SEMI_MINOR_AXIS_M: f64 = WGS84_SEMI_MAJOR_AXIS_M * (1.0 - WGS84_FLATTENING);
/// WGS-84 Earth gravitational constant `GM` (m³/s²).
pub const WGS84_GM_M3_S2: f64 = 3.986_004_418e14;
/// Second zonal harmonic `J2` (unnormalised, dimensionless).
pub const WGS84_J2: f64 = 1.082_626_68e-3;
/// WGS-84 Earth rotation rate `ω_e` (rad/s).
pub const WGS84_EARTH_RATE_RAD_S: f64 = 7.292_115e-5;

/// Accepted launch-site height range (m above the ellipsoid).
pub const SITE_HEIGHT_RANGE_M: (f64, f64) = (-1.0e3, 1.0e4);

/// Largest accepted angle between the configured Earth rotation axis and the ECEF `z` axis
/// (rad): polar motion stays below 1″ ≈ 4.8e-6 rad; 1e-4 rad leaves room and refuses a
/// wrong axis.
pub const MAX_EARTH_AXIS_TILT_RAD: f64 = 1.0e-4;

/// Launch site and Earth rotation axis that define the launch and launch-inertial frames.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LaunchSite {
    /// Geodetic latitude φ (rad), in `[−π/2, π/2]`.
    pub latitude_rad: f64,
    /// Longitude λ (rad, east positive), in `[−2π, 2π]`.
    pub longitude_rad: f64,
    /// Height above the WGS-84 ellipsoid (m), in [`SITE_HEIGHT_RANGE_M`].
    pub height_m: f64,
    /// Launch azimuth `A` (rad), from north toward east, in `[−2π, 2π]`.
    pub azimuth_rad: f64,
    /// Unit Earth rotation axis (the celestial intermediate pole) in ECEF (ITRF) axes,
    /// computed on the ground from the day's polar motion `(x_p, y_p)`: `W [0, 0, 1]ᵀ ≈
    /// [x_p, −y_p, 1]` (IERS Conventions 2010, eq. 5.3); `[0, 0, 1]` neglects polar motion.
    /// Unit ([`crate::attitude::is_unit_norm`]), within [`MAX_EARTH_AXIS_TILT_RAD`] of `z`.
    pub earth_axis_ecef: [f64; 3],
}

/// The Earth rotation axis when polar motion is neglected: the ECEF `z` axis.
pub const ECEF_Z_AXIS: [f64; 3] = [0.0, 0.0, 1.0];

impl LaunchSite {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a non-finite or out-of-range field.
    pub fn validate(&self) -> Result<(), NavError> {
        let two_pi = 2.0 * core::f64::consts::PI;
        let ok = self.latitude_rad.is_finite()
            && self.longitude_rad.is_finite()
            && self.height_m.is_finite()
            && self.azimuth_rad.is_finite()
            && self.earth_axis_is_valid()
            && self.latitude_rad.abs() <= core::f64::consts::FRAC_PI_2
            && self.longitude_rad.abs() <= two_pi
            && self.azimuth_rad.abs() <= two_pi
            && self.height_m >= SITE_HEIGHT_RANGE_M.0
            && self.height_m <= SITE_HEIGHT_RANGE_M.1;
        if ok {
            Ok(())
        } else {
            Err(NavError::InvalidConfiguration)
        }
    }

    /// Whether [`Self::earth_axis_ecef`] is finite, unit and near `z` (its `x`, `y` are the
    /// sines of the tilt's components, so `√(x² + y²)` bounds the tilt).
    fn earth_axis_is_valid(&self) -> bool {
        let [x, y, z] = self.earth_axis_ecef;
        let norm = crate::float::sqrt(x * x + y * y + z * z);
        x.is_finite()
            && y.is_finite()
            && z > 0.0
            && crate::attitude::is_unit_norm(norm)
            && crate::float::sqrt(x * x + y * y) <= MAX_EARTH_AXIS_TILT_RAD
    }
}

/// ECEF position (m) of a geodetic point (WGS-84; NIMA TR8350.2 eq. 4-14):
/// `N = a / √(1 − e² sin²φ)`, `r = [(N+h) cosφ cosλ, (N+h) cosφ sinλ, (N(1−e²)+h) sinφ]`.
pub fn geodetic_to_ecef(latitude_rad: f64, longitude_rad: f64, height_m: f64) -> Vector3<f64> {
    let (sin_lat, cos_lat) = (libm::sin(latitude_rad), libm::cos(latitude_rad));
    let (sin_lon, cos_lon) = (libm::sin(longitude_rad), libm::cos(longitude_rad));
    let n = WGS84_SEMI_MAJOR_AXIS_M
        / crate::float::sqrt(1.0 - WGS84_ECCENTRICITY_SQUARED * sin_lat * sin_lat);
    Vector3::new(
        (n + height_m) * cos_lat * cos_lon,
        (n + height_m) * cos_lat * sin_lon,
        (n * (1.0 - WGS84_ECCENTRICITY_SQUARED) + height_m) * sin_lat,
    )
}

/// `ω_e k × r` (m/s): the velocity of a point fixed in ECEF at `r` (m), in ECEF axes.
fn earth_rotation_velocity(axis: &Vector3<f64>, position_ecef_m: &Vector3<f64>) -> Vector3<f64> {
    axis.cross(position_ecef_m) * WGS84_EARTH_RATE_RAD_S
}

/// Active rotation by `angle_rad` about the unit axis `k` (Rodrigues' formula):
/// `R_k(θ) = cosθ I + sinθ [k]× + (1 − cosθ) k kᵀ`.
fn rotation_about(axis: &Vector3<f64>, angle_rad: f64) -> Matrix3<f64> {
    let (s, c) = (libm::sin(angle_rad), libm::cos(angle_rad));
    Matrix3::identity() * c + axis.cross_matrix() * s + (axis * axis.transpose()) * (1.0 - c)
}

/// Precomputed launch-frame geometry for one [`LaunchSite`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaunchFrame {
    site: LaunchSite,
    /// `C = C_le`: rows are the launch `x`, `y`, `z` axes expressed in ECEF.
    launch_from_ecef: Matrix3<f64>,
    /// Site position in ECEF (m).
    site_ecef_m: Vector3<f64>,
    /// Earth centre in launch(-inertial) axes, `−C r_site` (m).
    earth_centre_launch_m: Vector3<f64>,
    /// Unit Earth rotation axis in ECEF axes, `k`.
    earth_axis_ecef: Vector3<f64>,
    /// Unit Earth rotation axis in launch(-inertial) axes, `C k`.
    earth_axis_launch: Vector3<f64>,
}

impl LaunchFrame {
    /// Builds the frame: with up `u = [cosφ cosλ, cosφ sinλ, sinφ]`,
    /// north `n = [−sinφ cosλ, −sinφ sinλ, cosφ]`, east `e = [−sinλ, cosλ, 0]`
    /// (Groves eq. 2.99), `x = cosA n + sinA e`, `y = u`, `z = x × y`, `C = [x y z]ᵀ`.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] if [`LaunchSite::validate`] fails.
    pub fn new(site: &LaunchSite) -> Result<Self, NavError> {
        site.validate()?;
        let (sin_lat, cos_lat) = (libm::sin(site.latitude_rad), libm::cos(site.latitude_rad));
        let (sin_lon, cos_lon) = (libm::sin(site.longitude_rad), libm::cos(site.longitude_rad));
        let (sin_az, cos_az) = (libm::sin(site.azimuth_rad), libm::cos(site.azimuth_rad));
        let up = Vector3::new(cos_lat * cos_lon, cos_lat * sin_lon, sin_lat);
        let north = Vector3::new(-sin_lat * cos_lon, -sin_lat * sin_lon, cos_lat);
        let east = Vector3::new(-sin_lon, cos_lon, 0.0);
        let x_axis = north * cos_az + east * sin_az;
        let y_axis = up;
        let z_axis = x_axis.cross(&y_axis);
        let launch_from_ecef =
            Matrix3::from_rows(&[x_axis.transpose(), y_axis.transpose(), z_axis.transpose()]);
        let site_ecef_m = geodetic_to_ecef(site.latitude_rad, site.longitude_rad, site.height_m);
        let [kx, ky, kz] = site.earth_axis_ecef;
        let earth_axis_ecef = Vector3::new(kx, ky, kz);
        Ok(Self {
            site: *site,
            launch_from_ecef,
            site_ecef_m,
            earth_centre_launch_m: -(launch_from_ecef * site_ecef_m),
            earth_axis_ecef,
            earth_axis_launch: launch_from_ecef * earth_axis_ecef,
        })
    }

    /// The site this frame was built from.
    pub fn site(&self) -> &LaunchSite {
        &self.site
    }

    /// `C = C_le`, the launch-from-ECEF rotation (dimensionless).
    pub fn launch_from_ecef(&self) -> &Matrix3<f64> {
        &self.launch_from_ecef
    }

    /// Site position in ECEF (m).
    pub fn site_ecef_m(&self) -> &Vector3<f64> {
        &self.site_ecef_m
    }

    /// Earth centre in launch-inertial axes, `−C r_site` (m).
    pub fn earth_centre_launch_m(&self) -> &Vector3<f64> {
        &self.earth_centre_launch_m
    }

    /// ECEF position (m) at navigation time `time_s` (s since the launch epoch) to launch-inertial position (m):
    /// `p_i = C (R_z(ω_e (t − t₀)) r_e − r_site)`.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite position or time.
    pub fn ecef_to_launch_inertial(
        &self,
        position_ecef_m: &Vector3<f64>,
        time_s: f64,
    ) -> Result<Vector3<f64>, NavError> {
        if !all_finite3(position_ecef_m) || !time_s.is_finite() {
            return Err(NavError::NonFiniteInput);
        }
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        let inertial = rotation_about(&self.earth_axis_ecef, angle) * position_ecef_m;
        Ok(self.launch_from_ecef * (inertial - self.site_ecef_m))
    }

    /// ECEF velocity (m/s, relative to the rotating Earth, at ECEF position `position_ecef_m`)
    /// at navigation time `time_s` (s since the launch epoch) to launch-inertial velocity (m/s): the time derivative
    /// of [`Self::ecef_to_launch_inertial`],
    /// `v_i = C R_k(θ) (v_e + ω_e k × r_e)`, `θ = ω_e t` (`d/dt R_k(θ) r = R_k(θ)
    /// (ω_e k × r)` since `R_k` commutes with its own generator).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite position, velocity or time.
    ///
    /// # Examples
    /// ```
    /// use nav_core::frames::{LaunchFrame, LaunchSite};
    /// use nalgebra::Vector3;
    /// let site = LaunchSite { latitude_rad: 0.0, longitude_rad: 0.0, height_m: 0.0,
    ///     azimuth_rad: 0.0, earth_axis_ecef: [0.0, 0.0, 1.0] };
    /// let frame = LaunchFrame::new(&site).unwrap();
    /// // The site at rest on the equator moves eastward at ω_e a ≈ 465 m/s inertially.
    /// let v = frame
    ///     .ecef_velocity_to_launch_inertial(frame.site_ecef_m(), &Vector3::zeros(), 0.0)
    ///     .unwrap();
    /// assert!((v.norm() - 465.1).abs() < 0.1);
    /// ```
    pub fn ecef_velocity_to_launch_inertial(
        &self,
        position_ecef_m: &Vector3<f64>,
        velocity_ecef_mps: &Vector3<f64>,
        time_s: f64,
    ) -> Result<Vector3<f64>, NavError> {
        if !(all_finite3(position_ecef_m) && all_finite3(velocity_ecef_mps) && time_s.is_finite()) {
            return Err(NavError::NonFiniteInput);
        }
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        let inertial =
            velocity_ecef_mps + earth_rotation_velocity(&self.earth_axis_ecef, position_ecef_m);
        Ok(self.launch_from_ecef * (rotation_about(&self.earth_axis_ecef, angle) * inertial))
    }

    /// ECEF velocity (m/s, relative to the rotating Earth) turned into launch-inertial axes at
    /// navigation time `time_s` (s since the launch epoch), `C R_k(θ) v_e`: the launch-inertial
    /// velocity without its Earth-rotation term, which needs the position
    /// ([`EarthRotation::velocity_at`]; the two add to
    /// [`Self::ecef_velocity_to_launch_inertial`]). A receiver's velocity is converted in these
    /// two parts so that the Earth-rotation term can take the navigation's position instead of
    /// the fix's own, whose error `ε` would add `Ω × ε` (7e-4 m/s for 10 m) to the velocity.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite velocity or time.
    pub fn ecef_velocity_to_launch_axes(
        &self,
        velocity_ecef_mps: &Vector3<f64>,
        time_s: f64,
    ) -> Result<Vector3<f64>, NavError> {
        if !(all_finite3(velocity_ecef_mps) && time_s.is_finite()) {
            return Err(NavError::NonFiniteInput);
        }
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        Ok(self.launch_from_ecef
            * (rotation_about(&self.earth_axis_ecef, angle) * velocity_ecef_mps))
    }

    /// The Earth's rotation in launch-inertial axes ([`EarthRotation`]).
    pub fn earth_rotation(&self) -> EarthRotation {
        EarthRotation {
            rate_launch_rad_s: self.earth_axis_launch * WGS84_EARTH_RATE_RAD_S,
            centre_launch_m: self.earth_centre_launch_m,
        }
    }

    /// Inverse of [`Self::ecef_velocity_to_launch_inertial`]: launch-inertial velocity (m/s)
    /// at launch-inertial position `position_launch_m` (m) to ECEF velocity (m/s),
    /// `v_e = R_k(−θ) Cᵀ v_i − ω_e k × r_e`.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite position, velocity or time.
    pub fn launch_inertial_velocity_to_ecef(
        &self,
        position_launch_m: &Vector3<f64>,
        velocity_launch_mps: &Vector3<f64>,
        time_s: f64,
    ) -> Result<Vector3<f64>, NavError> {
        if !all_finite3(velocity_launch_mps) {
            return Err(NavError::NonFiniteInput);
        }
        let position_ecef = self.launch_inertial_to_ecef(position_launch_m, time_s)?;
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        let inertial = rotation_about(&self.earth_axis_ecef, -angle)
            * (self.launch_from_ecef.transpose() * velocity_launch_mps);
        Ok(inertial - earth_rotation_velocity(&self.earth_axis_ecef, &position_ecef))
    }

    /// Inverse of [`Self::ecef_to_launch_inertial`]: launch-inertial position (m) to ECEF
    /// position (m) at navigation time `time_s` (s since the launch epoch),
    /// `r_e = R_k(−ω_e t) (r_site + Cᵀ p_i)`.
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite position or time.
    pub fn launch_inertial_to_ecef(
        &self,
        position_launch_m: &Vector3<f64>,
        time_s: f64,
    ) -> Result<Vector3<f64>, NavError> {
        if !all_finite3(position_launch_m) || !time_s.is_finite() {
            return Err(NavError::NonFiniteInput);
        }
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        Ok(rotation_about(&self.earth_axis_ecef, -angle)
            * self.earth_centred_inertial_position(position_launch_m))
    }

    /// The rotation from launch-inertial to Earth-fixed axes at navigation time `time_s` (s
    /// since the launch epoch), `R_k(−ω_e t) Cᵀ`: a geocentric vector `u` in launch-inertial
    /// axes is `R_k(−ω_e t) Cᵀ u` in ECEF (as in [`Self::launch_inertial_to_ecef`], with
    /// `u = p − p_centre`).
    ///
    /// # Errors
    /// [`NavError::NonFiniteInput`] for a non-finite time.
    pub fn ecef_from_launch_axes(&self, time_s: f64) -> Result<Matrix3<f64>, NavError> {
        if !time_s.is_finite() {
            return Err(NavError::NonFiniteInput);
        }
        let angle = WGS84_EARTH_RATE_RAD_S * time_s;
        Ok(rotation_about(&self.earth_axis_ecef, -angle) * self.launch_from_ecef.transpose())
    }

    /// Geocentric position (m) in the ECEF-at-epoch inertial axes of a launch-inertial
    /// position (m): `r_I = r_site + Cᵀ p_i`.
    pub fn earth_centred_inertial_position(
        &self,
        position_launch_m: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.site_ecef_m + self.launch_from_ecef.transpose() * position_launch_m
    }

    /// Geocentric position (m) expressed in launch-inertial axes: `p_i − (−C r_site)`
    /// `= C r_site + p_i` (the same vector as [`Self::earth_centred_inertial_position`], in
    /// other axes).
    pub fn geocentric_position_launch(&self, position_launch_m: &Vector3<f64>) -> Vector3<f64> {
        position_launch_m - self.earth_centre_launch_m
    }

    /// Unit Earth rotation axis in launch-inertial axes, `C k` (dimensionless).
    pub fn earth_axis_launch(&self) -> Vector3<f64> {
        self.earth_axis_launch
    }
}

/// The Earth's rotation in launch-inertial axes: its rate `Ω = ω_e C k` and its centre
/// `c = −C r_site`. A point fixed to the Earth at launch-inertial position `p` moves at
/// `Ω × (p − c)`: the launch-inertial form of the ECEF term `C R_k(θ) (ω_e k × r_e)`, since a
/// rotation carries a cross product (`R (a × b) = R a × R b`), `R_k(θ) k = k` and
/// `C R_k(θ) r_e = p − c` ([`LaunchFrame::ecef_to_launch_inertial`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarthRotation {
    /// `Ω = ω_e C k` (rad/s, launch-inertial axes).
    pub rate_launch_rad_s: Vector3<f64>,
    /// `c = −C r_site` (m, launch-inertial axes).
    pub centre_launch_m: Vector3<f64>,
}

impl EarthRotation {
    /// The velocity (m/s) of the Earth-fixed point at launch-inertial position
    /// `position_launch_m` (m): `Ω × (p − c)`.
    ///
    /// # Examples
    /// ```
    /// use nav_core::frames::{LaunchFrame, LaunchSite};
    /// use nalgebra::Vector3;
    /// let site = LaunchSite { latitude_rad: 0.0, longitude_rad: 0.0, height_m: 0.0,
    ///     azimuth_rad: 0.0, earth_axis_ecef: [0.0, 0.0, 1.0] };
    /// let earth = LaunchFrame::new(&site).unwrap().earth_rotation();
    /// // The launch site on the equator moves eastward at ω_e a ≈ 465 m/s.
    /// assert!((earth.velocity_at(&Vector3::zeros()).norm() - 465.1).abs() < 0.1);
    /// ```
    pub fn velocity_at(&self, position_launch_m: &Vector3<f64>) -> Vector3<f64> {
        self.rate_launch_rad_s
            .cross(&(position_launch_m - self.centre_launch_m))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The test launch site (Wenchang, azimuth 90°, polar motion neglected).
    pub(crate) fn wenchang() -> LaunchSite {
        LaunchSite {
            latitude_rad: 19.6_f64.to_radians(),
            longitude_rad: 110.9_f64.to_radians(),
            height_m: 0.0,
            azimuth_rad: 90.0_f64.to_radians(),
            earth_axis_ecef: ECEF_Z_AXIS,
        }
    }

    /// The launch frame of [`wenchang`].
    pub(crate) fn wenchang_frame() -> LaunchFrame {
        LaunchFrame::new(&wenchang()).unwrap()
    }

    /// The velocity conversion is the time derivative of the position conversion: a point
    /// moving in ECEF, converted at `t ± h`, differences to the converted velocity (central
    /// difference, `h` = 0.5 s: truncation ~h² ω_e² |v| ≈ 1e-6 m/s); and the inverse returns
    /// the input.
    #[test]
    fn velocity_conversion_is_the_derivative_of_the_position_conversion() {
        let frame = wenchang_frame();
        let r0 = Vector3::new(-1.6e6, 5.9e6, 2.2e6);
        let v_e = Vector3::new(3100.0, -1200.0, 6400.0);
        let (t, h) = (4321.0, 0.5);
        let position_at = |time: f64| {
            frame
                .ecef_to_launch_inertial(&(r0 + v_e * (time - t)), time)
                .unwrap()
        };
        let numerical = (position_at(t + h) - position_at(t - h)) / (2.0 * h);
        let analytic = frame
            .ecef_velocity_to_launch_inertial(&r0, &v_e, t)
            .unwrap();
        assert!(
            (numerical - analytic).norm() < 1e-5,
            "{}",
            (numerical - analytic).norm()
        );
        // Turned in two parts, the Earth-rotation term at the converted position.
        let earth = frame.earth_rotation();
        let parts = frame.ecef_velocity_to_launch_axes(&v_e, t).unwrap()
            + earth.velocity_at(&position_at(t));
        assert!(
            (parts - analytic).norm() < 1e-9,
            "{}",
            (parts - analytic).norm()
        );
        assert!(frame.ecef_velocity_to_launch_axes(&v_e, f64::NAN).is_err());
        // The Earth-rotation term matters: without it the answer is ~470 m/s off.
        let without = frame.launch_from_ecef() * v_e;
        assert!((without - analytic).norm() > 100.0);
        let back = frame
            .launch_inertial_velocity_to_ecef(&position_at(t), &analytic, t)
            .unwrap();
        assert!((back - v_e).norm() < 1e-9, "{}", (back - v_e).norm());
        let nan = Vector3::new(f64::NAN, 0.0, 0.0);
        assert!(frame
            .ecef_velocity_to_launch_inertial(&r0, &nan, t)
            .is_err());
        assert!(frame
            .ecef_velocity_to_launch_inertial(&nan, &v_e, t)
            .is_err());
        assert!(frame
            .ecef_velocity_to_launch_inertial(&r0, &v_e, f64::NAN)
            .is_err());
        assert!(frame
            .launch_inertial_velocity_to_ecef(&r0, &nan, t)
            .is_err());
    }

    #[test]
    fn site_maps_to_origin_at_epoch_and_axes_are_as_documented() {
        let frame = LaunchFrame::new(&wenchang()).unwrap();
        let site = *frame.site_ecef_m();
        let origin = frame.ecef_to_launch_inertial(&site, 0.0).unwrap();
        println!("site -> launch-inertial at epoch: {origin:?}");
        assert!(origin.norm() < 1e-9);
        // Orthonormal, right-handed.
        let c = frame.launch_from_ecef();
        assert!((c * c.transpose() - Matrix3::identity()).abs().max() < 1e-15);
        assert!((c.determinant() - 1.0).abs() < 1e-15);
        // 100 m along the geodetic normal is +y; azimuth 90° puts +x due east.
        let up = Vector3::new(
            19.6_f64.to_radians().cos() * 110.9_f64.to_radians().cos(),
            19.6_f64.to_radians().cos() * 110.9_f64.to_radians().sin(),
            19.6_f64.to_radians().sin(),
        );
        let above = frame
            .ecef_to_launch_inertial(&(site + 100.0 * up), 0.0)
            .unwrap();
        assert!(
            (above - Vector3::new(0.0, 100.0, 0.0)).norm() < 1e-8,
            "{above:?}"
        );
        let east = Vector3::new(
            -110.9_f64.to_radians().sin(),
            110.9_f64.to_radians().cos(),
            0.0,
        );
        assert!((c * east - Vector3::x()).norm() < 1e-15);
        // Earth axis: in the y-z plane tilt by latitude (x east has no axis component).
        let axis = frame.earth_axis_launch();
        assert!((axis.norm() - 1.0).abs() < 1e-15);
        assert!((axis.y - 19.6_f64.to_radians().sin()).abs() < 1e-15);
        assert!(axis.x.abs() < 1e-15);
    }

    #[test]
    fn ecef_launch_inertial_round_trip_and_earth_rotation() {
        let frame = LaunchFrame::new(&wenchang()).unwrap();
        let r = Vector3::new(-2.3e6, 5.9e6, 2.2e6);
        let mut worst: f64 = 0.0;
        for t in [0.0, 1.0, 600.0, 5_000.0, 86_164.0] {
            let p = frame.ecef_to_launch_inertial(&r, t).unwrap();
            let back = frame.launch_inertial_to_ecef(&p, t).unwrap();
            worst = worst.max((back - r).norm());
        }
        println!("worst ECEF round-trip error: {worst:e} m");
        assert!(worst < 1e-6);
        // The site itself drifts eastward in launch-inertial axes after t0: about
        // ω_e R cosφ t along +x (east) for small t.
        let p = frame
            .ecef_to_launch_inertial(frame.site_ecef_m(), 1.0)
            .unwrap();
        let expected = WGS84_EARTH_RATE_RAD_S * frame.site_ecef_m().xy().norm();
        assert!((p.x - expected).abs() < 1e-3, "{p:?} vs {expected}");
        // Earth centre: geocentric position of the origin is the site.
        let centre = frame.earth_centred_inertial_position(frame.earth_centre_launch_m());
        assert!(centre.norm() < 1e-8);
    }

    /// The launch site, fixed in ECEF, seen from the launch-inertial frame at `t − t₀` later.
    /// Independent analytic answer (no `R_z`, no ECEF): its geocentric vector `g₀ = C r_site`
    /// (launch axes) turns about the Earth axis `k` by `ω_e (t − t₀)` (Rodrigues' formula
    /// `g(t) = g₀ cosθ + (k × g₀) sinθ + k (k·g₀)(1 − cosθ)`), so `p(t) = g(t) − g₀`. The
    /// measured angle about `k` must equal `ω_e (t − t₀)` for up to almost half a day.
    #[test]
    fn site_rotates_about_the_earth_axis_at_earth_rate() {
        let mut site = wenchang();
        // A pole 0.3″ and 0.4″ off z (a typical polar motion): the rotation is about it.
        let (x_pole, y_pole) = (0.3 / 206_264.806, 0.4 / 206_264.806);
        site.earth_axis_ecef = [
            x_pole,
            -y_pole,
            crate::float::sqrt(1.0 - x_pole * x_pole - y_pole * y_pole),
        ];
        let frame = LaunchFrame::new(&site).unwrap();
        let k = frame.earth_axis_launch();
        let g0 = -*frame.earth_centre_launch_m();
        let g0_perp = g0 - k * k.dot(&g0);
        let (mut worst_position, mut worst_angle): (f64, f64) = (0.0, 0.0);
        for elapsed in [1.0, 60.0, 3_600.0, 21_541.0, 43_000.0] {
            let theta = WGS84_EARTH_RATE_RAD_S * elapsed;
            let rotated = g0 * theta.cos()
                + k.cross(&g0) * theta.sin()
                + k * (k.dot(&g0) * (1.0 - theta.cos()));
            let expected = rotated - g0;
            let p = frame
                .ecef_to_launch_inertial(frame.site_ecef_m(), elapsed)
                .unwrap();
            worst_position = worst_position.max((p - expected).norm());
            let g = p + g0;
            let g_perp = g - k * k.dot(&g);
            // Axial component and distance from the axis are preserved.
            assert!((k.dot(&g) - k.dot(&g0)).abs() < 1e-8);
            assert!((g_perp.norm() - g0_perp.norm()).abs() < 1e-8);
            let measured = libm::atan2(k.dot(&g0_perp.cross(&g_perp)), g0_perp.dot(&g_perp));
            worst_angle = worst_angle.max((measured - theta).abs());
        }
        println!(
            "site vs Rodrigues rotation about the Earth axis: worst {worst_position:e} m, \
             worst angle error {worst_angle:e} rad"
        );
        assert!(worst_position < 1e-6);
        assert!(worst_angle < 1e-13);
        // 21,541 s is ≈ 90°: the site is then ≈ √2 · (distance from the axis) from the origin.
        let quarter = frame
            .ecef_to_launch_inertial(frame.site_ecef_m(), 21_541.0)
            .unwrap();
        assert!((quarter.norm() / g0_perp.norm() - 2.0_f64.sqrt()).abs() < 1e-3);
    }

    /// Published WGS-84 values (NIMA TR8350.2 Table 3.3): `e² = 6.694 379 990 14e-3`,
    /// `b = 6 356 752.3142 m`; the poles are at `±b` and the equator at `a` on the axes.
    #[test]
    fn wgs84_derived_constants_and_geodetic_points_on_the_axes() {
        assert!((WGS84_ECCENTRICITY_SQUARED - 6.694_379_990_14e-3).abs() < 1e-14);
        assert!((WGS84_SEMI_MINOR_AXIS_M - 6_356_752.314_2).abs() < 1e-4);
        let equator = geodetic_to_ecef(0.0, core::f64::consts::FRAC_PI_2, 0.0);
        assert!((equator - Vector3::new(0.0, WGS84_SEMI_MAJOR_AXIS_M, 0.0)).norm() < 1e-9);
        let north_pole = geodetic_to_ecef(core::f64::consts::FRAC_PI_2, 0.3, 0.0);
        assert!((north_pole - Vector3::new(0.0, 0.0, WGS84_SEMI_MINOR_AXIS_M)).norm() < 1e-6);
        // A surface point lies on the ellipse ρ²/a² + z²/b² = 1.
        let surface = geodetic_to_ecef(0.7, -1.9, 0.0);
        let ellipse = surface.xy().norm_squared() / WGS84_SEMI_MAJOR_AXIS_M.powi(2)
            + surface.z * surface.z / WGS84_SEMI_MINOR_AXIS_M.powi(2);
        assert!((ellipse - 1.0).abs() < 1e-15, "{ellipse}");
    }

    /// Height moves a point along the ellipsoid normal `u = [cosφ cosλ, cosφ sinλ, sinφ]`:
    /// `r(φ, λ, h) − r(φ, λ, 0) = h u` in every component.
    #[test]
    fn height_moves_along_the_ellipsoid_normal() {
        let (latitude, longitude) = (0.7_f64, -1.9_f64);
        let up = Vector3::new(
            latitude.cos() * longitude.cos(),
            latitude.cos() * longitude.sin(),
            latitude.sin(),
        );
        for height in [-500.0, 1_000.0, 9_000.0] {
            let moved = geodetic_to_ecef(latitude, longitude, height)
                - geodetic_to_ecef(latitude, longitude, 0.0);
            assert!((moved - height * up).norm() < 1e-8, "{height}: {moved:?}");
        }
    }

    /// The angle bounds are ±2π exactly (longitude and azimuth); ±(2π + 1e-9) is refused.
    #[test]
    fn angle_ranges_are_plus_minus_two_pi() {
        let two_pi = 2.0 * core::f64::consts::PI;
        for angle in [two_pi, -two_pi, 6.0, -6.0] {
            let mut site = wenchang();
            site.longitude_rad = angle;
            assert_eq!(site.validate(), Ok(()), "longitude {angle}");
            site = wenchang();
            site.azimuth_rad = angle;
            assert_eq!(site.validate(), Ok(()), "azimuth {angle}");
        }
        for angle in [two_pi + 1e-9, -two_pi - 1e-9] {
            let mut site = wenchang();
            site.longitude_rad = angle;
            assert_eq!(site.validate(), Err(NavError::InvalidConfiguration));
            site = wenchang();
            site.azimuth_rad = angle;
            assert_eq!(site.validate(), Err(NavError::InvalidConfiguration));
        }
    }

    /// The launch-inertial origin (the site at `t₀`) seen in ECEF at `t₀ + Δ` is the site's
    /// geodetic point moved west by `ω_e Δ` in longitude (the Earth turned under it), and
    /// ECEF → launch-inertial → ECEF is the identity.
    #[test]
    fn launch_inertial_to_ecef_after_the_epoch() {
        let site = wenchang();
        let frame = LaunchFrame::new(&site).unwrap();
        for elapsed in [0.0, 1.0, 3_600.0, 40_000.0] {
            let origin = frame
                .launch_inertial_to_ecef(&Vector3::zeros(), elapsed)
                .unwrap();
            let expected = geodetic_to_ecef(
                site.latitude_rad,
                site.longitude_rad - WGS84_EARTH_RATE_RAD_S * elapsed,
                site.height_m,
            );
            assert!((origin - expected).norm() < 1e-6, "{elapsed}: {origin:?}");
            let r = Vector3::new(-2.3e6, 5.9e6, 2.2e6);
            let p = frame.ecef_to_launch_inertial(&r, elapsed).unwrap();
            let back = frame.launch_inertial_to_ecef(&p, elapsed).unwrap();
            assert!((back - r).norm() < 1e-6, "{elapsed}: {back:?}");
        }
    }

    #[test]
    fn bad_sites_and_inputs_are_refused() {
        let mut site = wenchang();
        site.latitude_rad = 2.0;
        assert_eq!(LaunchFrame::new(&site), Err(NavError::InvalidConfiguration));
        site = wenchang();
        site.height_m = f64::NAN;
        assert_eq!(site.validate(), Err(NavError::InvalidConfiguration));
        // The Earth axis: not unit, tilted beyond the bound, pointing south, not finite.
        for axis in [
            [0.0, 0.0, 1.0 + 1e-8],
            [2e-4, 0.0, crate::float::sqrt(1.0 - 4e-8)],
            [0.0, 0.0, -1.0],
            [f64::NAN, 0.0, 1.0],
        ] {
            site = wenchang();
            site.earth_axis_ecef = axis;
            assert_eq!(
                site.validate(),
                Err(NavError::InvalidConfiguration),
                "{axis:?}"
            );
        }
        let frame = LaunchFrame::new(&wenchang()).unwrap();
        assert_eq!(
            frame.ecef_to_launch_inertial(&Vector3::zeros(), f64::INFINITY),
            Err(NavError::NonFiniteInput)
        );
        assert_eq!(
            frame.launch_inertial_to_ecef(&Vector3::new(f64::NAN, 0.0, 0.0), 0.0),
            Err(NavError::NonFiniteInput)
        );
    }
}
