//! An integrator's crate: what a flight image puts around nav-fsw, from the README's
//! dependency lines alone. `no_std`; it builds for `thumbv7em-none-eabihf` and for the host,
//! where its test runs one frame.
//!
//! The drivers here are stand-ins: each port hands the scheduler what a real driver would
//! have received since the last frame.
#![cfg_attr(not(test), no_std)]

use nav_fsw::nalgebra::{Quaternion, Vector3};
use nav_fsw::nav_core::frames::LaunchSite;
use nav_fsw::nav_core::strapdown::NavigationState;
use nav_fsw::sensor_frames::SensorFrames;
use nav_fsw::telemetry::FrameTelemetry;
use nav_fsw::{
    FswConfig, FswError, GnssFix, GnssPort, ImuPort, ImuSample, NavigationComputer,
    StarMeasurement, StarSensorPort,
};

/// Nominal frame period (s).
pub const FRAME_PERIOD_S: f64 = nav_fsw::MINOR_FRAME_PERIOD_S;

/// An IMU driver: one sample per frame, the increments a strapdown IMU integrates.
pub struct Imu {
    /// The sample the driver latched for the coming frame.
    pub latched: Option<ImuSample>,
}

impl ImuPort for Imu {
    fn read(&mut self) -> Option<ImuSample> {
        self.latched.take()
    }
}

/// A star-tracker driver with no measurement this frame.
pub struct StarTracker;

impl StarSensorPort for StarTracker {
    fn poll(&mut self) -> Option<StarMeasurement> {
        None
    }
}

/// A GNSS receiver driver with no fix this frame.
pub struct Receiver;

impl GnssPort for Receiver {
    fn poll(&mut self) -> Option<GnssFix> {
        None
    }
}

pub mod datasheets;
mod ground_constants;
/// The README's integration snippet, compiled here so that it cannot drift
/// (`scripts/integrator-check.sh` checks that README.md shows this file).
pub mod readme;

/// The launch site of the example (Jiuquan, azimuth 190°, the launch day's Earth axis), from
/// `nav-sim ground-constants` ([`ground_constants`]).
pub fn launch_site() -> LaunchSite {
    ground_constants::LAUNCH_SITE
}

/// The ground constants of the launch epoch (GCRF → launch-inertial, launch epoch in GPS
/// time), from `nav-sim ground-constants` for this launch. Not `SensorFrames::ALIGNED`: that
/// is a placeholder for tests, and a star tracker read through it is wrong by the launch
/// frame's whole rotation.
pub fn sensor_frames() -> SensorFrames {
    ground_constants::SENSOR_FRAMES
}

/// The computer configured from the vehicle's data sheets ([`datasheets::DATASHEETS`]) for
/// the launch ([`launch_site`], [`sensor_frames`]), starting from `initial`.
///
/// # Errors
/// The configuration's [`FswError`] when nav-fsw refuses it
/// (`nav_fsw::datasheet::Datasheets::field_of` names the data-sheet field).
pub fn start(initial: NavigationState) -> Result<NavigationComputer, FswError> {
    let config =
        FswConfig::from_datasheets(&datasheets::DATASHEETS, launch_site(), sensor_frames())?;
    NavigationComputer::new(config, initial)
}

/// One 2 ms frame with the IMU sample `sample` and no aiding measurement.
pub fn one_frame(computer: &mut NavigationComputer, sample: ImuSample) -> FrameTelemetry {
    let mut imu = Imu {
        latched: Some(sample),
    };
    computer.run_frame(&mut imu, &mut StarTracker, &mut Receiver)
}

/// A star tracker driver holding one measurement for the next poll.
pub struct HeldStarTracker {
    /// The measurement the driver received since the last poll.
    pub held: Option<StarMeasurement>,
}

impl StarSensorPort for HeldStarTracker {
    fn poll(&mut self) -> Option<StarMeasurement> {
        self.held.take()
    }
}

/// A state in a 500 km circular orbit (launch-inertial axes), for the example's frame.
pub fn orbit_state(time_s: f64) -> NavigationState {
    NavigationState {
        attitude: Quaternion::identity(),
        position_m: Vector3::new(0.0, 500e3, 0.0),
        velocity_mps: Vector3::new(7600.0, 0.0, 0.0),
        time_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_frame_advances_time_by_one_period_and_counts_no_fault() {
        let start_s = 600.0;
        let mut computer = start(orbit_state(start_s)).expect("the data sheets' configuration");
        let telemetry = one_frame(
            &mut computer,
            ImuSample::new(1, start_s + FRAME_PERIOD_S, [0.0; 3], [0.0; 3]),
        );
        assert!((telemetry.time_s - (start_s + FRAME_PERIOD_S)).abs() < 1e-9);
        assert_eq!(telemetry.health.imu_missing, 0);
        assert_eq!(telemetry.health.imu_non_finite, 0);
        // In free fall the position moves by v·T along x, within a metre of gravity's pull.
        let moved_m = computer.navigation().position_m.x;
        assert!((moved_m - 7600.0 * FRAME_PERIOD_S).abs() < 1.0, "{moved_m}");
    }

    /// Frames of `frames` with a star measurement of the true attitude (body = launch-inertial
    /// axes, one head mounted along the body) in GCRF, as the tracker reports it, at the
    /// first frame: the star gate rejections and whether a star update was accepted.
    fn star_frames(frames: SensorFrames) -> (u32, bool) {
        let start_s = 600.0;
        let mut sheets = datasheets::DATASHEETS;
        sheets.star_tracker.mounting_rotation_vector_deg = [0.0; 3];
        sheets.star_tracker.second_head_mounting_rotation_vector_deg = None;
        let config = FswConfig::from_datasheets(&sheets, launch_site(), frames).unwrap();
        let mut computer = NavigationComputer::new(config, orbit_state(start_s)).unwrap();
        // q_gs = q_gi ⊗ q_ib ⊗ q_bs with q_ib and q_bs the identity: the conjugate of the
        // launch's true GCRF → launch-inertial rotation.
        let [w, x, y, z] = SENSOR_FRAMES_OF_THE_LAUNCH.gcrf_to_launch_inertial_wxyz;
        let mut tracker = HeldStarTracker {
            held: Some(StarMeasurement::new(
                start_s + FRAME_PERIOD_S,
                [w, -x, -y, -z],
                0,
            )),
        };
        let mut accepted = false;
        let mut last = None;
        for frame in 1..=50_u32 {
            let mut imu = Imu {
                latched: Some(ImuSample::new(
                    frame,
                    start_s + f64::from(frame) * FRAME_PERIOD_S,
                    [0.0; 3],
                    [0.0; 3],
                )),
            };
            let telemetry = computer.run_frame(&mut imu, &mut tracker, &mut Receiver);
            accepted |= telemetry.fusion == nav_fsw::telemetry::FrameFusion::StarAccepted;
            last = Some(telemetry);
        }
        (
            last.map_or(u32::MAX, |t| t.health.star_gate_rejections),
            accepted,
        )
    }

    const SENSOR_FRAMES_OF_THE_LAUNCH: SensorFrames = ground_constants::SENSOR_FRAMES;

    /// With the ground constants of `nav-sim ground-constants` the tracker's GCRF attitude
    /// agrees with the navigation attitude and is fused; with the `ALIGNED` placeholder the
    /// same measurement is off by the launch frame's rotation and gated out.
    #[test]
    fn the_launchs_ground_constants_put_the_star_tracker_in_the_right_frame() {
        assert_eq!(star_frames(sensor_frames()), (0, true));
        assert_eq!(star_frames(SensorFrames::ALIGNED), (1, false));
    }

    /// The README's snippet starts the computer and runs a frame (no sample: held, counted).
    #[test]
    fn the_readmes_snippet_runs_a_frame() {
        let mut computer =
            readme::start(orbit_state(600.0)).expect("the data sheets' configuration");
        let mut drivers = (readme::Imu {}, readme::StarTracker {}, readme::Receiver {});
        let telemetry = readme::every_frame(&mut computer, &mut drivers);
        assert_eq!(telemetry.health.imu_missing, 1);
    }
}
