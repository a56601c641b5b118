//! The orbit along the analysed truth: osculating perigee and apogee, the local orbital axes
//! at the start, and the figures `nav-sim design` checks a schedule against
//! ([`OrbitSummary`]).

use nalgebra::Vector3;
use nav_core::attitude::rotation_matrix;
use nav_core::frames::{LaunchFrame, WGS84_GM_M3_S2, WGS84_SEMI_MAJOR_AXIS_M};

use super::{DesignError, OrbitSummary};
use crate::scenario::Scenario;
use crate::setup::launch::Launch;
use crate::world::truth::TruthFrame;

/// Osculating perigee and apogee radii (m) of the Keplerian orbit through `position_m`,
/// `velocity_mps` (geocentric, inertial): `r_p,a = h² / (μ (1 ± e))` with `h = |r × v|` and
/// the eccentricity vector `e = (v × h)/μ − r̂` (Vallado, 4th ed., algorithm 9, RV2COE).
/// The apogee is infinite for an open orbit (`e ≥ 1`).
pub fn perigee_apogee_radii_m(
    position_m: &Vector3<f64>,
    velocity_mps: &Vector3<f64>,
) -> (f64, f64) {
    let angular_momentum = position_m.cross(velocity_mps);
    let eccentricity_vector =
        velocity_mps.cross(&angular_momentum) / WGS84_GM_M3_S2 - position_m / position_m.norm();
    let eccentricity = eccentricity_vector.norm();
    let semi_latus_rectum_m = angular_momentum.norm_squared() / WGS84_GM_M3_S2;
    let apogee_m = if eccentricity < 1.0 {
        semi_latus_rectum_m / (1.0 - eccentricity)
    } else {
        f64::INFINITY
    };
    (semi_latus_rectum_m / (1.0 + eccentricity), apogee_m)
}

/// The local orbital axes at the scenario start, in the launch-inertial frame: radial (up),
/// along-track (the in-plane unit vector perpendicular to radial, prograde) and orbit normal
/// (`r × v`). The default scenario's initial attitude is chosen against these.
///
/// # Errors
/// [`DesignError::Setup`] if the initial state cannot be built.
pub fn initial_orbital_axes(scenario: &Scenario) -> Result<[Vector3<f64>; 3], DesignError> {
    let launch = Launch::new(scenario)?;
    let state = launch.truth_start;
    let radial = launch
        .frame
        .geocentric_position_launch(&state.position_m)
        .normalize();
    let normal = radial.cross(&state.velocity_mps).normalize();
    Ok([radial, normal.cross(&radial), normal])
}

/// Tracks the orbit figures along the truth.
pub(super) struct OrbitTracker {
    pub(super) frame: LaunchFrame,
    pub(super) summary: OrbitSummary,
    pub(super) net_delta_v: Vector3<f64>,
}

impl OrbitTracker {
    pub(super) fn observe(&mut self, truth: &TruthFrame) {
        let geocentric = self.frame.geocentric_position_launch(&truth.position_m);
        let altitude_m = geocentric.norm() - WGS84_SEMI_MAJOR_AXIS_M;
        let (perigee_m, apogee_m) = perigee_apogee_radii_m(&geocentric, &truth.velocity_mps);
        let summary = &mut self.summary;
        summary.minimum_altitude_m = summary.minimum_altitude_m.min(altitude_m);
        summary.minimum_perigee_altitude_m = summary
            .minimum_perigee_altitude_m
            .min(perigee_m - WGS84_SEMI_MAJOR_AXIS_M);
        summary.final_perigee_altitude_m = perigee_m - WGS84_SEMI_MAJOR_AXIS_M;
        summary.final_apogee_altitude_m = apogee_m - WGS84_SEMI_MAJOR_AXIS_M;
        self.net_delta_v += rotation_matrix(&truth.attitude_q_ib) * truth.delta_velocity_mps;
        summary.net_delta_v_mps = self.net_delta_v.norm();
        summary.total_delta_v_mps += truth.delta_velocity_mps.norm();
    }
}
