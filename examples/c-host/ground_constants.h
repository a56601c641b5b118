/* The launch's ground constants for nav.h (`nav-sim ground-constants --format c`). */
static const NavGroundConstants NAV_GROUND_CONSTANTS = {
    .latitude_rad = 0.7148519550318375,
    .longitude_rad = 1.750408160117633,
    .height_m = 1000.0,
    .azimuth_rad = 3.3161255787892263,
    .earth_axis_ecef = {7.844285360352285e-8, -1.2676423319967603e-6, 0.9999999999991935},
    .gcrf_to_launch_inertial_wxyz = {0.48490989988191335, -0.6582762769406675, 0.0137710902030395, 0.5756258240283053},
    .launch_epoch_gps_week = 2303,
    .launch_epoch_gps_seconds_of_week = 100818.0,
};
