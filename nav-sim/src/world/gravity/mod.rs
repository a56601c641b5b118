//! The truth's gravity beyond point mass + `J2`: a published spherical-harmonic Earth model
//! (EGM2008, `nav-sim/data/`), rotating with the Earth, in the launch-inertial frame.
//!
//! ## What is added to the flight code's field
//! The truth keeps nav-core's point mass + `J2` (WGS-84 `GM`, `a`, `J2`) exactly at every RK4
//! substep and adds the model's **remainder** `δg`: every term of degree `n ≤ N` and order
//! `m ≤ M` except `C̄_00` and `C̄_20`, with the model's own `GM` and `a` ([`harmonics`]).
//! Leaving the model's own point mass and `C̄_20` out instead of subtracting them keeps the
//! flight's field exact; what that changes against the model's complete field (EGM2008
//! `GM` = 3.986004415e14 vs WGS-84's 3.986004418e14, `a` 6378136.3 m vs 6378137 m,
//! `−√5 C̄_20` = 1.0826262e-3 vs `J2` 1.08262668e-3) is at most 1.3e-8 m/s² in LEO.
//!
//! ## Earth rotation
//! The coefficients are Earth-fixed (ITRF). A launch-inertial position `p` at navigation time
//! `t` is at the Earth-fixed position `r_e = R_k(−ω_e t)(r_site + Cᵀ p)` (nav-core's
//! [`LaunchFrame::launch_inertial_to_ecef`], the truth's own relation), and the acceleration
//! returns as `δg_i = A(t) δg_e(r_e)`, `A(t) = C R_k(ω_e t)`, with `C` the launch-from-ECEF
//! rotation, `k` the Earth axis (CIP) and `ω_e` WGS-84's Earth rate.
//!
//! ## Evaluated at a lower rate
//! A degree-20 evaluation costs about as much as the rest of an RK4 substep several times
//! over, so `δg` is evaluated only every [`REFRESH_INTERVAL_S`] (at an IMU frame boundary, on
//! the truth state there: time `t_n`, position `p_n`) and used in between through its
//! first-order Taylor expansion in position and time:
//!
//! `δg(p, t) ≈ δg_n + G_n (p − p_n) + ġ_n (t − t_n)`,
//!
//! with `G_n = ∂δg/∂p` by central differences (step [`GRADIENT_STEP_M`]) and, from
//! `dA/dt = ω_e [k_i]× A` (`k_i = C k`, the axis in launch-inertial axes),
//! `ġ_n = ω_e k_i × δg_n − G_n (ω_e k_i × u_n)`, `u_n` the geocentric position. The error is
//! the second-order remainder, `½ |∂²δg/∂p²| d²` with `d` the distance flown relative to the
//! rotating Earth since `t_n` (below 1 km in 0.1 s): the unit tests bound it below 1e-9 m/s²
//! at 200 km altitude and 10 km/s, five orders of magnitude below the accelerometer's
//! 1e-4 m/s² per sample. The model is continuous within a block and jumps by that same
//! error at a refresh, which lies on a frame boundary, so no RK4 step straddles it.

pub mod gfc;
pub mod harmonics;
#[cfg(test)]
mod tests;

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use nav_core::frames::{LaunchFrame, WGS84_EARTH_RATE_RAD_S};

use crate::scenario::gravity::{GravityModelName, GravitySettings};
use gfc::{parse_gfc, triangle_index, GfcError};
use harmonics::SphericalHarmonics;

/// EGM2008 (Pavlis et al., *J. Geophys. Res.* 117, B04406, 2012), ICGEM file truncated at
/// degree 60 by `nav-sim/data/truncate_gfc.py`; provenance and checksums in
/// `nav-sim/data/README.md`.
pub const EGM2008_GFC: &str = include_str!("../../../data/EGM2008_60.gfc");

/// Time between two evaluations of the remainder (s), taken at the first IMU frame boundary
/// at or after it.
pub const REFRESH_INTERVAL_S: f64 = 0.1;

/// Step of the central differences for the remainder's gradient (m): the truncation error
/// `h² |∂³δg| / 6` and the rounding error `ε |δg| / h` are both below 1e-20 /s².
pub const GRADIENT_STEP_M: f64 = 50.0;

/// The remainder `δg` of a published model over point mass + `J2`, Earth-fixed, in the
/// launch-inertial frame (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RotatingRemainder {
    field: SphericalHarmonics,
    frame: LaunchFrame,
    earth_axis_ecef: Unit<Vector3<f64>>,
}

impl RotatingRemainder {
    /// The remainder of `model` to `degree` and `order` for the launch `frame`.
    ///
    /// # Errors
    /// [`GfcError`] if the model file is malformed or does not reach `degree`.
    pub fn new(
        model_text: &str,
        degree: usize,
        order: usize,
        frame: LaunchFrame,
    ) -> Result<Self, GfcError> {
        let mut coefficients = parse_gfc(model_text, degree, order)?;
        for zeroed in [triangle_index(0, 0), triangle_index(2, 0)] {
            coefficients.c[zeroed] = 0.0;
            coefficients.s[zeroed] = 0.0;
        }
        let [x, y, z] = frame.site().earth_axis_ecef;
        Ok(Self {
            field: SphericalHarmonics::new(coefficients),
            frame,
            earth_axis_ecef: Unit::new_normalize(Vector3::new(x, y, z)),
        })
    }

    /// The scenario's remainder: `None` for the flight code's field (`model = "j2"`, or no
    /// `[gravity]` table).
    ///
    /// # Errors
    /// [`GfcError`] as [`Self::new`].
    pub fn from_settings(
        settings: Option<&GravitySettings>,
        frame: LaunchFrame,
    ) -> Result<Option<Self>, GfcError> {
        let Some(settings) = settings else {
            return Ok(None);
        };
        match settings.model {
            GravityModelName::J2 => Ok(None),
            GravityModelName::Egm2008 => {
                let degree = settings.degree.unwrap_or(2) as usize;
                let order = settings.order.unwrap_or(0) as usize;
                Self::new(EGM2008_GFC, degree, order, frame).map(Some)
            }
        }
    }

    /// The evaluated spherical-harmonic field (Earth-fixed, without `C̄_00` and `C̄_20`).
    pub fn field(&self) -> &SphericalHarmonics {
        &self.field
    }

    /// `A(t) = C R_k(ω_e t)`: Earth-fixed axes at `time_s` to launch-inertial axes.
    fn launch_from_earth_fixed(&self, time_s: f64) -> Matrix3<f64> {
        let spin =
            Rotation3::from_axis_angle(&self.earth_axis_ecef, WGS84_EARTH_RATE_RAD_S * time_s);
        self.frame.launch_from_ecef() * spin.matrix()
    }

    /// `δg` (m/s², launch-inertial axes) at launch-inertial `position_m` (m) and navigation
    /// time `time_s` (s), evaluated in full.
    ///
    /// # Errors
    /// A reason when the position or time is not finite, or `δg` is not.
    pub fn acceleration_mps2(
        &self,
        time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String> {
        let earth_fixed = self
            .frame
            .launch_inertial_to_ecef(position_m, time_s)
            .map_err(|error| format!("gravity field: {error:?}"))?;
        let acceleration =
            self.launch_from_earth_fixed(time_s) * self.field.acceleration_mps2(&earth_fixed);
        if nav_core::attitude::all_finite3(&acceleration) {
            Ok(acceleration)
        } else {
            Err("non-finite gravity field (position at the Earth centre)".to_string())
        }
    }

    /// The first-order Taylor model of `δg` about (`time_s`, `position_m`).
    ///
    /// # Errors
    /// As [`Self::acceleration_mps2`].
    pub fn linearise(&self, time_s: f64, position_m: &Vector3<f64>) -> Result<TaylorNode, String> {
        let value = self.acceleration_mps2(time_s, position_m)?;
        let mut gradient = Matrix3::zeros();
        for axis in 0..3 {
            let mut step = Vector3::zeros();
            step[axis] = GRADIENT_STEP_M;
            let ahead = self.acceleration_mps2(time_s, &(position_m + step))?;
            let behind = self.acceleration_mps2(time_s, &(position_m - step))?;
            gradient.set_column(axis, &((ahead - behind) / (2.0 * GRADIENT_STEP_M)));
        }
        let spin = self.frame.earth_axis_launch() * WGS84_EARTH_RATE_RAD_S;
        let geocentric = self.frame.geocentric_position_launch(position_m);
        let rate = spin.cross(&value) - gradient * spin.cross(&geocentric);
        Ok(TaylorNode {
            time_s,
            position_m: *position_m,
            value_mps2: value,
            gradient_per_s2: gradient,
            rate_mps3: rate,
        })
    }
}

/// `δg` and its first derivatives at one node (module docs, "Evaluated at a lower rate").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaylorNode {
    /// Node time `t_n` (s).
    pub time_s: f64,
    /// Node position `p_n` (m, launch-inertial).
    pub position_m: Vector3<f64>,
    /// `δg_n` (m/s², launch-inertial).
    pub value_mps2: Vector3<f64>,
    /// `G_n = ∂δg/∂p` (1/s²).
    pub gradient_per_s2: Matrix3<f64>,
    /// `ġ_n = ∂δg/∂t` at fixed inertial position (m/s³).
    pub rate_mps3: Vector3<f64>,
}

impl TaylorNode {
    /// `δg_n + G_n (p − p_n) + ġ_n (t − t_n)` (m/s²).
    #[inline]
    pub fn acceleration_mps2(&self, time_s: f64, position_m: &Vector3<f64>) -> Vector3<f64> {
        self.value_mps2
            + self.gradient_per_s2 * (position_m - self.position_m)
            + self.rate_mps3 * (time_s - self.time_s)
    }
}

/// The remainder as the truth uses it: refreshed every [`REFRESH_INTERVAL_S`] at a frame
/// start, its Taylor model in between.
#[derive(Debug, Clone, PartialEq)]
pub struct RemainderTracker {
    remainder: RotatingRemainder,
    node: Option<TaylorNode>,
}

impl RemainderTracker {
    /// A tracker with no node yet (the first [`Self::start_frame`] makes one).
    pub fn new(remainder: RotatingRemainder) -> Self {
        Self {
            remainder,
            node: None,
        }
    }

    /// The field tracked.
    pub fn remainder(&self) -> &RotatingRemainder {
        &self.remainder
    }

    /// At a frame start (`time_s`, `position_m`): a new node if none is younger than
    /// [`REFRESH_INTERVAL_S`] (to a billionth of it, so frame times' rounding does not
    /// shift the refresh by a frame).
    ///
    /// # Errors
    /// As [`RotatingRemainder::acceleration_mps2`].
    pub fn start_frame(&mut self, time_s: f64, position_m: &Vector3<f64>) -> Result<(), String> {
        let stale = self
            .node
            .is_none_or(|node| time_s - node.time_s >= REFRESH_INTERVAL_S * (1.0 - 1.0e-9));
        if stale {
            self.node = Some(self.remainder.linearise(time_s, position_m)?);
        }
        Ok(())
    }

    /// `δg` (m/s²) from the current node's Taylor model.
    ///
    /// # Errors
    /// A reason when no frame has started yet.
    #[inline]
    pub fn acceleration_mps2(
        &self,
        time_s: f64,
        position_m: &Vector3<f64>,
    ) -> Result<Vector3<f64>, String> {
        self.node
            .as_ref()
            .map(|node| node.acceleration_mps2(time_s, position_m))
            .ok_or_else(|| "gravity field used before the first frame started".to_string())
    }
}
