//! Gravitation in the launch-inertial frame: point mass plus the `J2` zonal term, with the
//! Earth rotation axis fixed in inertial space (the `J2` field is axially symmetric, so the
//! Earth's rotation about that axis does not change it).
//!
//! With `r` the geocentric position, `r = |r|`, `k` the unit Earth axis and `s = k·r`
//! (Montenbruck & Gill, *Satellite Orbits*, 2000, eq. 3.13 for the point mass and the
//! `J2` term of the zonal expansion, eqs. 3.28–3.33; Vallado, *Fundamentals of
//! Astrodynamics and Applications*, 4th ed., eq. 8-30, written in vector form):
//!
//! `g = −GM r / r³ − (3/2) J2 GM a² / r⁵ · [ (1 − 5 s²/r²) r + 2 s k ]`.
//!
//! This is gravitation only (no centrifugal term): the navigation frame is inertial.
//! The field beyond `J2`, to a configured degree and order, is [`harmonics`]'s.

pub mod egm2008;
pub mod harmonics;

use nalgebra::{Matrix3, Vector3};

use crate::frames::{LaunchFrame, WGS84_GM_M3_S2, WGS84_J2, WGS84_SEMI_MAJOR_AXIS_M};

/// Gravitation model selection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GravityModel {
    /// Include the `J2` zonal term (otherwise point mass only).
    pub j2_enabled: bool,
}

impl Default for GravityModel {
    fn default() -> Self {
        Self { j2_enabled: true }
    }
}

/// `K = −(3/2) J2 GM a²` (m⁵/s²), the common factor of the `J2` acceleration.
const J2_FACTOR: f64 =
    -1.5 * WGS84_J2 * WGS84_GM_M3_S2 * WGS84_SEMI_MAJOR_AXIS_M * WGS84_SEMI_MAJOR_AXIS_M;

impl GravityModel {
    /// Gravitational acceleration (m/s²) in launch-inertial axes at launch-inertial position
    /// `position_launch_m` (m); equation in the module docs.
    ///
    /// Not fallible by design: a non-finite position, or one at the Earth centre, yields a
    /// non-finite result, which callers (e.g. the strapdown step) check and refuse.
    pub fn gravity_launch_mps2(
        &self,
        frame: &LaunchFrame,
        position_launch_m: &Vector3<f64>,
    ) -> Vector3<f64> {
        let r_vec = frame.geocentric_position_launch(position_launch_m);
        let r2 = r_vec.dot(&r_vec);
        let r = crate::float::sqrt(r2);
        let r3 = r2 * r;
        let mut g = r_vec * (-WGS84_GM_M3_S2 / r3);
        if self.j2_enabled {
            let k = frame.earth_axis_launch();
            let s = k.dot(&r_vec);
            let r5 = r3 * r2;
            g += (r_vec * (1.0 - 5.0 * s * s / r2) + k * (2.0 * s)) * (J2_FACTOR / r5);
        }
        g
    }

    /// Gravity gradient `∂g/∂p` (1/s²) in launch-inertial axes, analytic (symmetric).
    ///
    /// Point mass: `G₀ = (GM/r³)(3 r̂ r̂ᵀ − I)`.
    /// `J2`: differentiating `K [r⁻⁵ r − 5 s² r⁻⁷ r + 2 s r⁻⁵ k]` with `∂r/∂r = r̂ᵀ`,
    /// `∂s/∂r = kᵀ` gives
    /// `G₂ = K [ (r⁻⁵ − 5 s² r⁻⁷) I + (35 s² r⁻⁹ − 5 r⁻⁷) r rᵀ − 10 s r⁻⁷ (r kᵀ + k rᵀ)
    ///  + 2 r⁻⁵ k kᵀ ]`, `K = −(3/2) J2 GM a²`.
    /// Same non-finite behaviour as [`Self::gravity_launch_mps2`].
    pub fn gravity_gradient_launch(
        &self,
        frame: &LaunchFrame,
        position_launch_m: &Vector3<f64>,
    ) -> Matrix3<f64> {
        let r_vec = frame.geocentric_position_launch(position_launch_m);
        let r2 = r_vec.dot(&r_vec);
        let r = crate::float::sqrt(r2);
        let r3 = r2 * r;
        let rrt = r_vec * r_vec.transpose();
        let mut gradient = (rrt * (3.0 / r2) - Matrix3::identity()) * (WGS84_GM_M3_S2 / r3);
        if self.j2_enabled {
            let k = frame.earth_axis_launch();
            let s = k.dot(&r_vec);
            let inv_r5 = 1.0 / (r3 * r2);
            let inv_r7 = inv_r5 / r2;
            let inv_r9 = inv_r7 / r2;
            let rkt = r_vec * k.transpose();
            let j2_part = Matrix3::identity() * (inv_r5 - 5.0 * s * s * inv_r7)
                + rrt * (35.0 * s * s * inv_r9 - 5.0 * inv_r7)
                - (rkt + rkt.transpose()) * (10.0 * s * inv_r7)
                + k * k.transpose() * (2.0 * inv_r5);
            gradient += j2_part * J2_FACTOR;
        }
        gradient
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::WGS84_SEMI_MINOR_AXIS_M;

    use crate::frames::tests::wenchang_frame as frame;

    #[test]
    fn magnitude_at_site_is_about_9_8() {
        let f = frame();
        for j2 in [false, true] {
            let g = GravityModel { j2_enabled: j2 }.gravity_launch_mps2(&f, &Vector3::zeros());
            println!("|g| at site (J2 {j2}) = {} m/s^2, g = {g:?}", g.norm());
            assert!((g.norm() - 9.8).abs() < 0.05);
            // Points roughly down (−y), the geodetic normal differs from the geocentric one
            // by < 0.2°.
            assert!(-g.y / g.norm() > (0.2_f64.to_radians()).cos());
        }
    }

    #[test]
    fn gradient_matches_central_differences() {
        let f = frame();
        let mut worst: f64 = 0.0;
        for j2 in [false, true] {
            let model = GravityModel { j2_enabled: j2 };
            for p in [
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(1.2e5, 2.0e5, -3.0e4),
                Vector3::new(-2.0e6, 1.5e6, 3.0e6),
            ] {
                let analytic = model.gravity_gradient_launch(&f, &p);
                assert!((analytic - analytic.transpose()).abs().max() < 1e-20);
                let h = 10.0;
                for j in 0..3 {
                    let mut dp = Vector3::zeros();
                    dp[j] = h;
                    let column = (model.gravity_launch_mps2(&f, &(p + dp))
                        - model.gravity_launch_mps2(&f, &(p - dp)))
                        / (2.0 * h);
                    let err = (column - analytic.column(j)).norm() / analytic.norm();
                    worst = worst.max(err);
                }
            }
        }
        println!("worst relative gradient error vs central differences: {worst:e}");
        assert!(worst < 1e-6);
    }

    /// `J2` at equal radius: the pole is *weaker* than the equator (the oblate bulge pulls
    /// outward along the axis): `g_pole = GM/r² (1 − 3 J2 a²/r²)`,
    /// `g_eq = GM/r² (1 + 1.5 J2 a²/r²)`. At the WGS-84 surface (polar radius `b` < `a`) the
    /// pole is stronger, as observed.
    #[test]
    fn j2_pole_versus_equator() {
        let f = frame();
        let model = GravityModel { j2_enabled: true };
        let k = f.earth_axis_launch();
        let equatorial = {
            let e = Vector3::new(1.0, 0.0, 0.0) - k * k.x;
            e / e.norm()
        };
        let at = |unit: Vector3<f64>, radius: f64| {
            let p = unit * radius + *f.earth_centre_launch_m();
            model.gravity_launch_mps2(&f, &p).norm()
        };
        let r = WGS84_SEMI_MAJOR_AXIS_M;
        let (pole, eq) = (at(k, r), at(equatorial, r));
        let point = WGS84_GM_M3_S2 / (r * r);
        println!("equal radius a: pole {pole} eq {eq} m/s^2");
        assert!((pole - point * (1.0 - 3.0 * WGS84_J2)).abs() < 1e-9);
        assert!((eq - point * (1.0 + 1.5 * WGS84_J2)).abs() < 1e-9);
        assert!(eq > pole);
        let (pole_surface, eq_surface) = (at(k, WGS84_SEMI_MINOR_AXIS_M), at(equatorial, r));
        println!("surface: pole {pole_surface} eq {eq_surface} m/s^2");
        assert!(pole_surface > eq_surface);
        // Without J2 the two are equal at equal radius.
        let pm = GravityModel { j2_enabled: false };
        let p1 = pm.gravity_launch_mps2(&f, &(k * r + *f.earth_centre_launch_m()));
        let p2 = pm.gravity_launch_mps2(&f, &(equatorial * r + *f.earth_centre_launch_m()));
        assert!((p1.norm() - p2.norm()).abs() < 1e-12);
    }

    #[test]
    fn earth_centre_gives_non_finite_not_panic() {
        let f = frame();
        let g = GravityModel::default().gravity_launch_mps2(&f, f.earth_centre_launch_m());
        assert!(!g.x.is_finite() || !g.y.is_finite() || !g.z.is_finite());
    }
}
