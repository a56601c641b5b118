use nav_fsw::nav_core::strapdown::NavigationState;
use nav_fsw::telemetry::FrameTelemetry;
use nav_fsw::{
    FswConfig, FswError, GnssFix, GnssPort, ImuPort, ImuSample, NavigationComputer,
    StarMeasurement, StarSensorPort,
};

// The ground constants of your launch (launch site with the day's Earth axis, GCRF →
// launch-inertial rotation, launch epoch in GPS time), written by
// `nav-sim ground-constants [SCENARIO] --format rust > src/ground_constants.rs`.
use crate::ground_constants::{LAUNCH_SITE, SENSOR_FRAMES};
// Your sensors' data sheets and gravity model, in nav-fsw's tables: src/datasheets.rs.
use crate::datasheets::DATASHEETS;

pub struct Imu {/* the driver */}
impl ImuPort for Imu {
    // This frame's ImuSample::new(sequence, time, Δθ (rad), Δv (m/s)); None if none came.
    fn read(&mut self) -> Option<ImuSample> {
        None // the sample the driver latched for this frame
    }
}
pub struct StarTracker {/* the driver */}
impl StarSensorPort for StarTracker {
    // Since the last poll: StarMeasurement::new(time tag, q sensor → GCRF [w, x, y, z], head).
    fn poll(&mut self) -> Option<StarMeasurement> {
        None // the attitude the tracker reported since the last poll
    }
}
pub struct Receiver {/* the driver */}
impl GnssPort for Receiver {
    // Since the last poll: GnssFix::new(GPS week, seconds of week, ITRF position) (+ velocity).
    fn poll(&mut self) -> Option<GnssFix> {
        None // the fix the receiver reported since the last poll
    }
}

/// Start-up: the configuration from your sensors' data sheets for your launch, from the
/// initial state (attitude q_ib, position and velocity in the launch-inertial frame, time).
pub fn start(initial: NavigationState) -> Result<NavigationComputer, FswError> {
    let config = FswConfig::from_datasheets(&DATASHEETS, LAUNCH_SITE, SENSOR_FRAMES)?;
    // In a flight image, in place in a static slot instead:
    // NavigationComputer::init_in_place(slot, config, initial)
    NavigationComputer::new(config, initial) // Err(FswError) naming the refused field
}

/// Every 2 ms: one frame; the telemetry holds the navigation solution, NIS, fusion, faulty
/// sensors and health counters.
pub fn every_frame(
    computer: &mut NavigationComputer,
    drivers: &mut (Imu, StarTracker, Receiver),
) -> FrameTelemetry {
    let (imu, star_tracker, receiver) = drivers;
    computer.run_frame(imu, star_tracker, receiver)
}
