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

/// The launch site of the example (Jiuquan, azimuth 190°).
pub fn launch_site() -> LaunchSite {
    LaunchSite {
        latitude_rad: 40.958_f64.to_radians(),
        longitude_rad: 100.291_f64.to_radians(),
        height_m: 1000.0,
        azimuth_rad: 190.0_f64.to_radians(),
        // The day's pole from the ground (docs/frames-and-time.md); here ECEF z.
        earth_axis_ecef: [0.0, 0.0, 1.0],
    }
}

/// The ground constants of the launch epoch (GCRF → launch-inertial, launch epoch in GPS
/// time); a flight image carries the values computed for its launch, this example the
/// aligned ones.
pub fn sensor_frames() -> SensorFrames {
    SensorFrames::ALIGNED
}

/// The computer with the paper's configuration at `launch_site`, starting from `initial`.
///
/// # Errors
/// The configuration's [`FswError`] when nav-fsw refuses it.
pub fn start(initial: NavigationState) -> Result<NavigationComputer, FswError> {
    NavigationComputer::new(
        FswConfig::paper_defaults(launch_site(), sensor_frames()),
        initial,
    )
}

/// One 2 ms frame with the IMU sample `sample` and no aiding measurement.
pub fn one_frame(computer: &mut NavigationComputer, sample: ImuSample) -> FrameTelemetry {
    let mut imu = Imu {
        latched: Some(sample),
    };
    computer.run_frame(&mut imu, &mut StarTracker, &mut Receiver)
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
        let mut computer = start(orbit_state(start_s)).expect("the paper's configuration");
        let telemetry = one_frame(
            &mut computer,
            ImuSample {
                sequence: 1,
                time_s: start_s + FRAME_PERIOD_S,
                delta_angle_rad: [0.0; 3],
                delta_velocity_mps: [0.0; 3],
            },
        );
        assert!((telemetry.time_s - (start_s + FRAME_PERIOD_S)).abs() < 1e-9);
        assert_eq!(telemetry.health.imu_missing, 0);
        assert_eq!(telemetry.health.imu_non_finite, 0);
        // In free fall the position moves by v·T along x, within a metre of gravity's pull.
        let moved_m = computer.navigation().position_m.x;
        assert!((moved_m - 7600.0 * FRAME_PERIOD_S).abs() < 1.0, "{moved_m}");
    }
}
