//! The ground constants of the launch this example flies: the built-in scenario's (Jiuquan,
//! 2024-02-26T04:00:00Z), written by `nav-sim ground-constants --format rust`. A flight image
//! carries the output of that command for its own launch; `nav-sim/tests/testsuite/cli.rs`
//! checks that this file is the command's output.

use nav_fsw::nav_core::frames::LaunchSite;
use nav_fsw::sensor_frames::SensorFrames;

/// Where the constants below come from: the launch epoch (UTC), the Earth orientation
/// values of the launch day (IERS Bulletin A) and the tool that computed them.
pub const GROUND_CONSTANTS_PROVENANCE: &str =
    "epoch_utc=2024-02-26T04:00:00Z ut1_minus_utc_s=-0.002122 polar_motion_x_arcsec=0.01618 polar_motion_y_arcsec=0.26147 tool=nav-sim 0.1.0 ground-constants";

/// The launch site, with the Earth axis of the launch day.
///
/// Computed by nav-sim 0.1.0 ground-constants for the launch epoch 2024-02-26T04:00:00Z UTC,
/// with UT1 − UTC = -0.002122 s and polar motion x_p = 0.01618″, y_p = 0.26147″.
pub const LAUNCH_SITE: LaunchSite = LaunchSite {
    latitude_rad: 0.7148519550318375,
    longitude_rad: 1.750408160117633,
    height_m: 1000.0,
    azimuth_rad: 3.3161255787892263,
    earth_axis_ecef: [
        7.844285360352285e-8,
        -1.2676423319967603e-6,
        0.9999999999991935,
    ],
};

/// GCRF → launch-inertial rotation and the launch epoch in GPS time.
///
/// Computed by nav-sim 0.1.0 ground-constants for the launch epoch 2024-02-26T04:00:00Z UTC,
/// with UT1 − UTC = -0.002122 s and polar motion x_p = 0.01618″, y_p = 0.26147″.
pub const SENSOR_FRAMES: SensorFrames = SensorFrames {
    gcrf_to_launch_inertial_wxyz: [
        0.48490989988191335,
        -0.6582762769406675,
        0.0137710902030395,
        0.5756258240283053,
    ],
    launch_epoch_gps_week: 2303,
    launch_epoch_gps_seconds_of_week: 100818.0,
};
