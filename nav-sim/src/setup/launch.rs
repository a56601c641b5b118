//! Where and when a run starts, computed from its scenario: the launch epoch and the ground
//! constants, the launch site and its launch-inertial frame, and the truth's initial state.
//! A run computes them once ([`Launch::new`]) and hands them to the truth, the sensors and the
//! flight software's configuration.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use nav_core::attitude::exp_rotation_vector;
use nav_core::frames::{LaunchFrame, LaunchSite, WGS84_GM_M3_S2};

use crate::scenario::epoch::{EpochError, GroundConstants, LaunchEpoch};
use crate::scenario::Scenario;
use crate::setup::SetupError;

/// The launch epoch on the simulator's time scale (s): the simulator's time is navigation
/// time, seconds since the launch epoch (small times keep 2 ms frame boundaries exact to
/// ~1e-13 s); the sensors' own time scales are formed at the ports ([`crate::scenario::epoch`]).
pub const LAUNCH_EPOCH_S: f64 = 0.0;

/// Where and when a run starts, computed once from its scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Launch {
    /// The launch epoch with the day's Earth orientation.
    pub epoch: LaunchEpoch,
    /// The launch site ([`launch_site`]).
    pub site: LaunchSite,
    /// The site's launch-inertial frame.
    pub frame: LaunchFrame,
    /// The ground constants of the flight software's configuration.
    pub ground: GroundConstants,
    /// The truth at the scenario start ([`initial_state`]).
    pub truth_start: TruthState,
}

impl Launch {
    /// Computes the scenario's launch once.
    ///
    /// # Errors
    /// [`SetupError::LaunchSite`] if the epoch or the ground constants are refused,
    /// [`SetupError::InitialState`] if nav-core refuses the site or a conversion of the initial
    /// state fails. A validated scenario is never refused.
    pub fn new(scenario: &Scenario) -> Result<Self, SetupError> {
        let epoch =
            scenario_epoch(scenario).map_err(|error| SetupError::LaunchSite(error.to_string()))?;
        let site = launch_site(scenario);
        let frame = launch_frame(scenario)?;
        let ground = epoch
            .ground_constants(&frame)
            .map_err(|error| SetupError::LaunchSite(error.to_string()))?;
        let truth_start = initial_state(scenario, &frame)?;
        Ok(Self {
            epoch,
            site,
            frame,
            ground,
            truth_start,
        })
    }
}

/// The scenario's launch epoch (`launch_site.epoch_utc`, `launch_site.earth_orientation`).
///
/// # Errors
/// As [`LaunchEpoch::new`].
pub fn scenario_epoch(scenario: &Scenario) -> Result<LaunchEpoch, EpochError> {
    scenario.launch_site.epoch()
}

/// The scenario's ground constants (its launch frame's rotation, its epoch).
///
/// # Errors
/// As [`LaunchEpoch::new`] and [`LaunchEpoch::ground_constants`]; a refused launch site as
/// [`EpochError::Parse`] naming the site.
pub fn scenario_ground_constants(scenario: &Scenario) -> Result<GroundConstants, EpochError> {
    let epoch = scenario_epoch(scenario)?;
    let frame = launch_frame(scenario).map_err(|error| EpochError::Parse {
        text: scenario.launch_site.epoch_utc.clone(),
        reason: error.to_string(),
    })?;
    epoch.ground_constants(&frame)
}

/// nav-core's [`LaunchSite`] for the scenario's launch site
/// ([`crate::scenario::LaunchSiteSettings::nav_site`]).
pub fn launch_site(scenario: &Scenario) -> LaunchSite {
    scenario.launch_site.nav_site()
}

/// The scenario's launch-inertial frame.
///
/// # Errors
/// [`SetupError::InitialState`] if nav-core refuses the site.
pub fn launch_frame(scenario: &Scenario) -> Result<LaunchFrame, SetupError> {
    LaunchFrame::new(&launch_site(scenario))
        .map_err(|error| SetupError::InitialState(format!("launch site refused: {error}")))
}

/// The truth state at the scenario start: the initial orbit's elements (referred to the
/// ECEF-at-epoch inertial axes `I`) converted with [`orbit_state_from_elements`] and then to
/// the launch-inertial frame, `p_i = C (r_I − r_site)`, `v_i = C v_I` (`C` = launch-from-ECEF;
/// no transport term since both frames are inertial); attitude `q_ib = exp(φ)` from
/// `initial_attitude.rotation_vector_deg`.
///
/// # Errors
/// [`SetupError::InitialState`] if a conversion yields a non-finite value.
pub fn initial_state(scenario: &Scenario, frame: &LaunchFrame) -> Result<TruthState, SetupError> {
    let orbit = &scenario.initial_orbit;
    let (position_earth_centred_m, velocity_earth_centred_mps) = orbit_state_from_elements(
        orbit.semi_major_axis_m,
        orbit.eccentricity,
        orbit.inclination_deg.to_radians(),
        orbit.right_ascension_of_node_deg.to_radians(),
        orbit.argument_of_perigee_deg.to_radians(),
        orbit.true_anomaly_deg.to_radians(),
        WGS84_GM_M3_S2,
    );
    // At the launch epoch ECEF and the inertial axes I coincide.
    let position_m = frame
        .ecef_to_launch_inertial(&position_earth_centred_m, LAUNCH_EPOCH_S)
        .map_err(|error| SetupError::InitialState(format!("initial position: {error}")))?;
    let velocity_mps = frame.launch_from_ecef() * velocity_earth_centred_mps;
    let [x, y, z] = scenario.initial_attitude.rotation_vector_deg;
    let attitude_q_ib = exp_rotation_vector(&Vector3::new(
        x.to_radians(),
        y.to_radians(),
        z.to_radians(),
    ));
    if !nav_core::attitude::all_finite3(&velocity_mps) {
        return Err(SetupError::InitialState(
            "non-finite initial velocity".to_string(),
        ));
    }
    Ok(TruthState {
        time_s: scenario.simulation.start_time_s,
        attitude_q_ib,
        position_m,
        velocity_mps,
    })
}

/// The truth state at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthState {
    /// Navigation time (s since the launch epoch).
    pub time_s: f64,
    /// Attitude `q_ib`, body to launch-inertial (unit).
    pub attitude_q_ib: Quaternion<f64>,
    /// Position in the launch-inertial frame (m).
    pub position_m: Vector3<f64>,
    /// Velocity in the launch-inertial frame (m/s).
    pub velocity_mps: Vector3<f64>,
}

/// Position and velocity (m, m/s) from Keplerian elements, in the inertial frame the elements
/// are referred to (Vallado, "Fundamentals of Astrodynamics", 4th ed., algorithm 10, COE2RV):
/// perifocal `r = p/(1 + e cos ν) [cos ν, sin ν, 0]`, `v = √(μ/p) [−sin ν, e + cos ν, 0]`,
/// rotated by `R3(−Ω) R1(−i) R3(−ω)`.
///
/// Angles in rad, `gravitational_parameter_m3_per_s2` = μ.
pub fn orbit_state_from_elements(
    semi_major_axis_m: f64,
    eccentricity: f64,
    inclination_rad: f64,
    right_ascension_of_node_rad: f64,
    argument_of_perigee_rad: f64,
    true_anomaly_rad: f64,
    gravitational_parameter_m3_per_s2: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let semi_latus_rectum_m = semi_major_axis_m * (1.0 - eccentricity * eccentricity);
    let (sin_nu, cos_nu) = true_anomaly_rad.sin_cos();
    let radius_m = semi_latus_rectum_m / (1.0 + eccentricity * cos_nu);
    let position_perifocal = Vector3::new(radius_m * cos_nu, radius_m * sin_nu, 0.0);
    let speed_scale = (gravitational_parameter_m3_per_s2 / semi_latus_rectum_m).sqrt();
    let velocity_perifocal = Vector3::new(
        -speed_scale * sin_nu,
        speed_scale * (eccentricity + cos_nu),
        0.0,
    );
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), right_ascension_of_node_rad)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), inclination_rad)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), argument_of_perigee_rad);
    (rotation * position_perifocal, rotation * velocity_perifocal)
}
