//! The configuration struct for C, one field per parameter of nav-fsw's table but the
//! ground constants'. Generated from the table by `NAV_BLESS=1 cargo test -p nav-c --test params`; do not edit it by hand.

use nav_fsw::config::Param;

use super::NAV_CONFIG_PARAMS;

/// The flight software's configuration for C: every parameter of the table but the
/// ground constants' (`NavGroundConstants`), each a `double` holding the parameter's
/// number (a count its integer value, a flag 0 or 1, a choice its index), in the
/// table's order. `nav_config_defaults` fills it with the defaults.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavConfig {
    /// `filter.mode` must be one of open_loop, closed_loop (the two filter modes); as its index: 0 = open_loop, 1 = closed_loop; default 1
    pub filter_mode: f64,
    /// `filter.discretisation_order` must be in [1, 4] (nav-core's truncated transition series: 1 is Euler, 4 the longest it has); default 3
    pub filter_discretisation_order: f64,
    /// `gravity.field.degree` must be in [2, 12] (2 is point mass + J2 alone; the flight's EGM2008 tables end at degree 12); default 2
    pub gravity_field_degree: f64,
    /// `gravity.field.order` must be in [0, 12] (at most the degree (checked with it)); default 0
    pub gravity_field_order: f64,
    /// `gravity.field.terms_per_frame` must be in [1, 8] (the frame budget: each work item adds up to one coefficient's work to a frame that fuses nothing (docs/guide/gravity.md, its cost table); twice the default keeps that frame inside 30,000 instructions with every state block, 255 would not); default 4
    pub gravity_field_terms_per_frame: f64,
    /// `filter.initial.attitude_rad` must be in [1e-9, 3.141592653589793] rad (a rotation angle: below 1 nrad no sensor resolves it, beyond pi it wraps); default 0.001
    pub filter_initial_attitude_rad: f64,
    /// `filter.initial.position_m` must be in [0.001, 1e7] m (a millimetre is below any position fix; 1e7 m is the size of the Earth); default 10
    pub filter_initial_position_m: f64,
    /// `filter.initial.velocity_mps` must be in [1e-6, 10000] m/s (a micrometre per second is below any velocity fix; 1e4 m/s exceeds orbital speed); default 0.1
    pub filter_initial_velocity_mps: f64,
    /// `filter.initial.gyro_bias_rad_s` must be in [1e-12, 0.1] rad/s (1e-12 rad/s is far below the best gyro; 1e-1 rad/s (20,000 deg/h) far beyond any); default 0.001
    pub filter_initial_gyro_bias_rad_s: f64,
    /// `filter.initial.accel_bias_mps2` must be in [1e-9, 10] m/s^2 (1e-9 m/s^2 is far below the best accelerometer; 10 m/s^2 is 1 g); default 0.01
    pub filter_initial_accel_bias_mps2: f64,
    /// `filter.initial.star_installation_rad` must be in [1e-12, 3.141592653589793] rad (a rotation angle: down to 1e-12 rad, a prior so small that no update moves the state (the calibration switched off, as nav-sim's benefit study flies it); beyond pi it wraps); default 0.01
    pub filter_initial_star_installation_rad: f64,
    /// `filter.initial.gyro_scale_factor` must be in [1e-12, 0.1] (a relative error: down to 1e-12, a prior so small that no update moves the state (the calibration switched off, as nav-sim's benefit study flies it); 0.1 is nav-sim's largest truth scale factor and beyond the linear model); default 1e-4
    pub filter_initial_gyro_scale_factor: f64,
    /// `filter.initial.accel_scale_factor` must be in [1e-12, 0.1] (a relative error: down to 1e-12, a prior so small that no update moves the state (the calibration switched off, as nav-sim's benefit study flies it); 0.1 is nav-sim's largest truth scale factor and beyond the linear model); default 2e-4
    pub filter_initial_accel_scale_factor: f64,
    /// `process_noise.gyro_noise_density_rad_s_per_sqrt_hz` must be 0 (off) or in [1e-12, 0.1] rad/s/sqrt(Hz) (1e-12 rad/s/sqrt(Hz) is far below the best gyro, 1e-1 (20,000 deg/h/sqrt(Hz)) no gyro); default 9.69627362219072e-7
    pub process_noise_gyro_noise_density_rad_s_per_sqrt_hz: f64,
    /// `process_noise.accel_noise_density_mps2_per_sqrt_hz` must be 0 (off) or in [1e-12, 10] m/s^2/sqrt(Hz) (1e-12 m/s^2/sqrt(Hz) is far below the best accelerometer, 10 is no accelerometer); default 1e-4
    pub process_noise_accel_noise_density_mps2_per_sqrt_hz: f64,
    /// `process_noise.gyro_bias_walk_rad_s2_per_sqrt_hz` must be 0 (off) or in [1e-18, 1] rad/s^2/sqrt(Hz) (a bias random walk, with nav-sim's bias instability 2 sigma^2 / tau added: the largest instability 1-sigma over the shortest correlation time stays inside); default 0
    pub process_noise_gyro_bias_walk_rad_s2_per_sqrt_hz: f64,
    /// `process_noise.accel_bias_walk_mps3_per_sqrt_hz` must be 0 (off) or in [1e-15, 100] m/s^3/sqrt(Hz) (a bias random walk, with nav-sim's bias instability 2 sigma^2 / tau added: the largest instability 1-sigma over the shortest correlation time stays inside); default 0
    pub process_noise_accel_bias_walk_mps3_per_sqrt_hz: f64,
    /// `imu.period_s` must be in [1e-4, 0.1] s (10 kHz to 10 Hz: the two-sample coning and sculling terms need many samples per manoeuvre, and a faster frame leaves no room in the budget); default 0.002
    pub imu_period_s: f64,
    /// Element 0: `star.mounting_wxyz[0]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); default 1
    /// Element 1: `star.mounting_wxyz[1]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); default 0
    /// Element 2: `star.mounting_wxyz[2]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); default 0
    /// Element 3: `star.mounting_wxyz[3]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); default 0
    pub star_mounting_wxyz: [f64; 4],
    /// `star.noise_rad` must be in [1e-12, 0.1] rad (1e-12 rad is the floor nav-sim gives a noiseless test tracker; 1e-1 rad (6 deg) is no star tracker); default 4.84813681109536e-5
    pub star_noise_rad: f64,
    /// `star.gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 16.27
    pub star_gate_nis: f64,
    /// `gnss.noise_m` must be in [1e-6, 100000] m (1e-6 m is the floor nav-sim gives a noiseless test receiver; 1e5 m is no fix); default 10
    pub gnss_noise_m: f64,
    /// `gnss.gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 16.27
    pub gnss_gate_nis: f64,
    /// `timing.max_latency_s` must be in [0, 1] s (at most the navigation history's span, (HISTORY_CAPACITY - 1) IMU periods (checked with imu.period_s)); default 0.1
    pub timing_max_latency_s: f64,
    /// `filter.gnss_error.sigma_m` must be 0 (off) or in [0.001, 1000] m (a receiver's slowly varying error: ionosphere and orbit errors are metres, 1 km is no fix); default 0
    pub filter_gnss_error_sigma_m: f64,
    /// `filter.gnss_error.correlation_time_s` must be 0 (off) or in [1, 1e8] s (below 1 s (500 frames) the error is white noise to the filter, whose walk 2 sigma^2 / tau would swamp the covariance every frame; beyond 1e8 s (three years) it is a constant over any flight: 0 (off) leaves it to the constant states); default 0
    pub filter_gnss_error_correlation_time_s: f64,
    /// `gnss.velocity_noise_mps` must be 0 (off) or in [1e-6, 1000] m/s (0 turns velocity fusion off; a receiver's velocity is centimetres per second, 1 km/s is none); default 0.05
    pub gnss_velocity_noise_mps: f64,
    /// `imu.max_rate_rad_s` must be in [0.01, 1000] rad/s (a gyro's measurement span: 0.6 deg/s to 57,000 deg/s); default 7
    pub imu_max_rate_rad_s: f64,
    /// `imu.max_specific_force_mps2` must be in [1, 100000] m/s^2 (an accelerometer's measurement span: 0.1 g to 10,000 g); default 200
    pub imu_max_specific_force_mps2: f64,
    /// `filter.imu_error.gyro_misalignment_sigma_rad` must be 0 (off) or in [1e-9, 0.01] rad (the model is the small-angle I + A: navigation-grade triads are 5-20 urad, tactical ones 100 urad and more; 1 rad is no small angle); default 0
    pub filter_imu_error_gyro_misalignment_sigma_rad: f64,
    /// `filter.imu_error.accel_misalignment_sigma_rad` must be 0 (off) or in [1e-9, 0.01] rad (the model is the small-angle I + A: navigation-grade triads are 5-20 urad, tactical ones 100 urad and more; 1 rad is no small angle); default 0
    pub filter_imu_error_accel_misalignment_sigma_rad: f64,
    /// `filter.imu_error.gyro_g_sensitivity_sigma_rad_s_per_mps2` must be 0 (off) or in [1e-12, 0.001] rad/s per m/s^2 (navigation-grade gyros have 0.1-10 deg/h/g; 1e-3 is 2000 deg/h/g); default 0
    pub filter_imu_error_gyro_g_sensitivity_sigma_rad_s_per_mps2: f64,
    /// `gravity.omitted_field_sigma_mps2` must be 0 (off) or in [1e-12, 0.01] m/s^2 (the field beyond J2 is a few 1e-3 m/s^2 at most at the surface, less aloft); default 0
    pub gravity_omitted_field_sigma_mps2: f64,
    /// `gravity.omitted_field_psd_m2_per_s3` must be 0 (off) or in [1e-20, 1] m^2/s^3 (a velocity noise for that field: 1 m^2/s^3 swamps every accelerometer); default 0
    pub gravity_omitted_field_psd_m2_per_s3: f64,
    /// `star.roll_noise_rad` must be in [1e-12, 0.1] rad (1e-12 rad is the floor nav-sim gives a noiseless test tracker; 1e-1 rad (6 deg) is no star tracker); default 4.84813681109536e-5
    pub star_roll_noise_rad: f64,
    /// Element 0: `star.slow_error_sigma_rad[0]` must be 0 (off) or in [1e-9, 0.01] rad (a tracker's thermo-elastic error is arcseconds: 1e-2 rad (34 arcmin) is no tracker); default 0
    /// Element 1: `star.slow_error_sigma_rad[1]` must be 0 (off) or in [1e-9, 0.01] rad (a tracker's thermo-elastic error is arcseconds: 1e-2 rad (34 arcmin) is no tracker); default 0
    /// Element 2: `star.slow_error_sigma_rad[2]` must be 0 (off) or in [1e-9, 0.01] rad (a tracker's thermo-elastic error is arcseconds: 1e-2 rad (34 arcmin) is no tracker); default 0
    pub star_slow_error_sigma_rad: [f64; 3],
    /// `star.slow_error_correlation_time_s` must be 0 (off) or in [1, 1e8] s (below 1 s (500 frames) the error is white noise to the filter, whose walk 2 sigma^2 / tau would swamp the covariance every frame; beyond 1e8 s (three years) it is a constant over any flight: 0 (off) leaves it to the constant states); default 0
    pub star_slow_error_correlation_time_s: f64,
    /// `star.aberration_correction` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 0
    pub star_aberration_correction: f64,
    /// `star.noise_matching` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 1
    pub star_noise_matching: f64,
    /// `star.second_head` must be one of false, true (one tracker head or two; the head's values follow); as its index: 0 = false, 1 = true; default 0
    pub star_second_head: f64,
    /// `star.second_head.pairs_before_hand_over` must be in [1, 100000] pairs (at 0 the filter hands over to a head whose alignment no pair has measured; 1e5 pairs (hours at 10 Hz) is never); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_pairs_before_hand_over: f64,
    /// Element 0: `star.second_head.mounting_wxyz[0]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); no default: the mission gives it; read only while `star.second_head` is 1
    /// Element 1: `star.second_head.mounting_wxyz[1]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); no default: the mission gives it; read only while `star.second_head` is 1
    /// Element 2: `star.second_head.mounting_wxyz[2]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); no default: the mission gives it; read only while `star.second_head` is 1
    /// Element 3: `star.second_head.mounting_wxyz[3]` must be in [-1, 1] (a component of a unit quaternion (norm within 1e-9 of 1, checked with the whole quaternion)); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_mounting_wxyz: [f64; 4],
    /// `star.second_head.noise_rad` must be in [1e-12, 0.1] rad (1e-12 rad is the floor nav-sim gives a noiseless test tracker; 1e-1 rad (6 deg) is no star tracker); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_noise_rad: f64,
    /// `star.second_head.roll_noise_rad` must be in [1e-12, 0.1] rad (1e-12 rad is the floor nav-sim gives a noiseless test tracker; 1e-1 rad (6 deg) is no star tracker); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_roll_noise_rad: f64,
    /// `star.second_head.alignment_prior_sigma_rad` must be in [1e-9, 3.141592653589793] rad (a rotation angle: below 1 nrad no sensor resolves it, beyond pi it wraps); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_alignment_prior_sigma_rad: f64,
    /// `star.second_head.pair_gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); no default: the mission gives it; read only while `star.second_head` is 1
    pub star_second_head_pair_gate_nis: f64,
    /// `imu.period_tolerance` must be in [1e-6, 0.5] (a sample's relative step error: a clock within 1e-6 is a quartz; beyond a half two samples could share a frame); default 0.1
    pub imu_period_tolerance: f64,
    /// `star.acquisition_gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 30.67
    pub star_acquisition_gate_nis: f64,
    /// `star.unit_norm_tolerance` must be in [1e-12, 0.1] (a measured quaternion's norm error: 1e-12 is the rounding of its components; beyond 0.1 it is no attitude); default 0.001
    pub star_unit_norm_tolerance: f64,
    /// Element 0: `gnss.lever_arm_body_m[0]` must be in [-100, 100] m (within the vehicle); default 0
    /// Element 1: `gnss.lever_arm_body_m[1]` must be in [-100, 100] m (within the vehicle); default 0
    /// Element 2: `gnss.lever_arm_body_m[2]` must be in [-100, 100] m (within the vehicle); default 0
    pub gnss_lever_arm_body_m: [f64; 3],
    /// `gnss.acquisition_gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 30.67
    pub gnss_acquisition_gate_nis: f64,
    /// `gnss.max_jump_m` must be in [1, 1e7] m (a jump is beyond the receiver's noise (metres) and within the Earth's size); default 1000
    pub gnss_max_jump_m: f64,
    /// `gnss.velocity_gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 16.27
    pub gnss_velocity_gate_nis: f64,
    /// `gnss.velocity_acquisition_gate_nis` must be in [1, 1e6] or +inf (no gate) (a chi-square(3) point: below 1 it rejects four consistent measurements in five; above 1e6 it gates nothing a sensor can produce, say +inf); default 30.67
    pub gnss_velocity_acquisition_gate_nis: f64,
    /// `gnss.whiteness_window_fixes` must be in [1, 1e6] fixes (at least one fix; 1e6 fixes (days at 10 Hz) never forgets); default 64
    pub gnss_whiteness_window_fixes: f64,
    /// `gnss.whiteness_threshold` must be in (0, 1] (a correlation coefficient; the default: WhitenessMonitor docs); default 0.3
    pub gnss_whiteness_threshold: f64,
    /// `timing.future_tolerance_s` must be in [0, 0.1] s (below one IMU period (checked with imu.period_s): a later tag is a future frame's); default 0.001
    pub timing_future_tolerance_s: f64,
    /// `timing.outage_timeout_s` must be in [0.001, 3600] s (longer than a sensor's message interval; beyond an hour no outage is noticed); default 2
    pub timing_outage_timeout_s: f64,
    /// `timing.rejections_to_declare_faulty` must be in [1, 4.294967295e9] rejections (at least one; u32::MAX never declares a sensor faulty (a study of the flight without fault declaration)); default 20
    pub timing_rejections_to_declare_faulty: f64,
    /// `covariance.propagation_interval_frames` must be in [1, 500] frames (one second at 500 Hz at most: longer, the interval's mean rates no longer describe the motion); default 1
    pub covariance_propagation_interval_frames: f64,
    /// `covariance.frame_load` must be one of propagate_then_fuse, fuse_or_propagate (the two schedules); as its index: 0 = propagate_then_fuse, 1 = fuse_or_propagate; default 1
    pub covariance_frame_load: f64,
    /// `covariance.sigma_floor.attitude_rad` must be in [1e-15, 3.141592653589793] rad (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-9
    pub covariance_sigma_floor_attitude_rad: f64,
    /// `covariance.sigma_floor.position_m` must be in [1e-9, 1e7] m (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-4
    pub covariance_sigma_floor_position_m: f64,
    /// `covariance.sigma_floor.velocity_mps` must be in [1e-12, 10000] m/s (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-7
    pub covariance_sigma_floor_velocity_mps: f64,
    /// `covariance.sigma_floor.gyro_bias_rad_s` must be in [1e-18, 0.1] rad/s (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-10
    pub covariance_sigma_floor_gyro_bias_rad_s: f64,
    /// `covariance.sigma_floor.accel_bias_mps2` must be in [1e-15, 10] m/s^2 (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-8
    pub covariance_sigma_floor_accel_bias_mps2: f64,
    /// `covariance.sigma_floor.star_installation_rad` must be in [1e-15, 3.141592653589793] rad (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-9
    pub covariance_sigma_floor_star_installation_rad: f64,
    /// `covariance.sigma_floor.gyro_scale_factor` must be in [1e-15, 0.1] (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-10
    pub covariance_sigma_floor_gyro_scale_factor: f64,
    /// `covariance.sigma_floor.accel_scale_factor` must be in [1e-15, 0.1] (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-10
    pub covariance_sigma_floor_accel_scale_factor: f64,
    /// `covariance.optional_sigma_floor.gnss_error_m` must be in [1e-9, 1000] m (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-4
    pub covariance_optional_sigma_floor_gnss_error_m: f64,
    /// `covariance.optional_sigma_floor.gyro_non_orthogonality_rad` must be in [1e-15, 0.01] rad (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-12
    pub covariance_optional_sigma_floor_gyro_non_orthogonality_rad: f64,
    /// `covariance.optional_sigma_floor.accel_misalignment_rad` must be in [1e-15, 0.01] rad (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-12
    pub covariance_optional_sigma_floor_accel_misalignment_rad: f64,
    /// `covariance.optional_sigma_floor.gyro_g_sensitivity_rad_s_per_mps2` must be in [1e-18, 0.001] rad/s per m/s^2 (from a numerical guard far below every sensor's accuracy to the block's largest initial 1-sigma); default 1e-15
    pub covariance_optional_sigma_floor_gyro_g_sensitivity_rad_s_per_mps2: f64,
    /// `covariance.sigma_ceiling_factor` must be in [1, 1e6] (a multiple of the initial 1-sigma: below 1 the prior itself is clamped; beyond 1e6 the square of a large prior leaves the normal f64 range); default 1000
    pub covariance_sigma_ceiling_factor: f64,
    /// `covariance.held_sample.rate_rad_s` must be 0 (off) or in [1e-6, 1000] rad/s (within a gyro's measurement range); default 0.1
    pub covariance_held_sample_rate_rad_s: f64,
    /// `covariance.held_sample.specific_force_mps2` must be 0 (off) or in [1e-6, 100000] m/s^2 (within an accelerometer's measurement range); default 1
    pub covariance_held_sample_specific_force_mps2: f64,
    /// `covariance.second_order_attitude` must be one of neglected, bounded (the two models); as its index: 0 = neglected, 1 = bounded; default 1
    pub covariance_second_order_attitude: f64,
    /// `calibration.convergence_sigma.gyro_bias_rad_s` must be in [1e-12, 0.1] rad/s (a calibration accuracy, within the block's initial 1-sigma range); default 5e-7
    pub calibration_convergence_sigma_gyro_bias_rad_s: f64,
    /// `calibration.convergence_sigma.accel_bias_mps2` must be in [1e-9, 10] m/s^2 (a calibration accuracy, within the block's initial 1-sigma range); default 9.166666666666667e-5
    pub calibration_convergence_sigma_accel_bias_mps2: f64,
    /// `calibration.convergence_sigma.star_installation_rad` must be in [1e-9, 3.141592653589793] rad (a calibration accuracy, within the block's initial 1-sigma range); default 1.6666666666666669e-6
    pub calibration_convergence_sigma_star_installation_rad: f64,
    /// `calibration.convergence_sigma.gyro_scale_factor` must be in [1e-12, 0.1] (a calibration accuracy, within the block's initial 1-sigma range); default 3.333333333333333e-7
    pub calibration_convergence_sigma_gyro_scale_factor: f64,
    /// `calibration.convergence_sigma.accel_scale_factor` must be in [1e-12, 0.1] (a calibration accuracy, within the block's initial 1-sigma range); default 6.666666666666666e-7
    pub calibration_convergence_sigma_accel_scale_factor: f64,
    /// `calibration.stability_window_s` must be in [0, 86400] s (0 (converged at once) to one day of flight); default 10
    pub calibration_stability_window_s: f64,
    /// `calibration.stability_fraction` must be in [0.001, 1000] (a fraction of the block's threshold); default 1
    pub calibration_stability_fraction: f64,
    /// `calibration.freeze_converged` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 0
    pub calibration_freeze_converged: f64,
    /// `calibration.policy` must be one of all_blocks, paper_schedule, motion_observability (the three policies); as its index: 0 = all_blocks, 1 = paper_schedule, 2 = motion_observability; default 0
    pub calibration_policy: f64,
    /// `calibration.motion_rate_threshold_rad_s` must be in [1e-6, 1] rad/s (above an orbital coast's rate and the gyro noise, below a calibration rotation); default 0.008726646259971648
    pub calibration_motion_rate_threshold_rad_s: f64,
    /// `calibration.motion_force_threshold_mps2` must be in [1e-4, 100] m/s^2 (above a coast's drag and accelerometer noise, below a calibration burn); default 0.5
    pub calibration_motion_force_threshold_mps2: f64,
    /// `consistency.time_constant_measurements` must be in [1, 65536] measurements (the fading average's memory: one measurement to the monitor's largest); default 256
    pub consistency_time_constant_measurements: f64,
    /// `consistency.mean_nis_bound` must be in (3, 100] (above 3, a consistent filter's mean NIS; beyond 100 nothing is flagged); default 3.7
    pub consistency_mean_nis_bound: f64,
    /// `strapdown.coning_compensation` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 1
    pub strapdown_coning_compensation: f64,
    /// `strapdown.sculling_compensation` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 1
    pub strapdown_sculling_compensation: f64,
    /// `strapdown.gravity.j2_enabled` must be one of false, true (on or off); as its index: 0 = false, 1 = true; default 1
    pub strapdown_gravity_j2_enabled: f64,
}

/// The parameters of [`NavConfig`]'s fields, in their order.
pub(crate) const CONFIG_PARAMS: [Param; NAV_CONFIG_PARAMS] = [
    Param::FilterMode,
    Param::FilterDiscretisationOrder,
    Param::GravityDegree,
    Param::GravityOrder,
    Param::GravityTermsPerFrame,
    Param::InitialAttitude,
    Param::InitialPosition,
    Param::InitialVelocity,
    Param::InitialGyroBias,
    Param::InitialAccelBias,
    Param::InitialStarInstallation,
    Param::InitialGyroScaleFactor,
    Param::InitialAccelScaleFactor,
    Param::GyroNoiseDensity,
    Param::AccelNoiseDensity,
    Param::GyroBiasWalk,
    Param::AccelBiasWalk,
    Param::ImuPeriod,
    Param::StarMountingW,
    Param::StarMountingX,
    Param::StarMountingY,
    Param::StarMountingZ,
    Param::StarNoise,
    Param::StarGate,
    Param::GnssNoise,
    Param::GnssGate,
    Param::MaxLatency,
    Param::GnssCorrelatedSigma,
    Param::GnssCorrelationTime,
    Param::GnssVelocityNoise,
    Param::ImuMaxRate,
    Param::ImuMaxSpecificForce,
    Param::GyroMisalignmentSigma,
    Param::AccelMisalignmentSigma,
    Param::GyroGSensitivitySigma,
    Param::OmittedFieldSigma,
    Param::OmittedFieldPsd,
    Param::StarRollNoise,
    Param::StarSlowErrorX,
    Param::StarSlowErrorY,
    Param::StarSlowErrorZ,
    Param::StarSlowErrorCorrelationTime,
    Param::StarAberrationCorrection,
    Param::StarNoiseMatching,
    Param::StarSecondHead,
    Param::HeadPairsBeforeHandOver,
    Param::HeadMountingW,
    Param::HeadMountingX,
    Param::HeadMountingY,
    Param::HeadMountingZ,
    Param::HeadNoise,
    Param::HeadRollNoise,
    Param::HeadAlignmentPrior,
    Param::HeadPairGate,
    Param::ImuPeriodTolerance,
    Param::StarAcquisitionGate,
    Param::StarNormTolerance,
    Param::GnssLeverArmX,
    Param::GnssLeverArmY,
    Param::GnssLeverArmZ,
    Param::GnssAcquisitionGate,
    Param::GnssMaxJump,
    Param::GnssVelocityGate,
    Param::GnssVelocityAcquisitionGate,
    Param::GnssWhitenessWindow,
    Param::GnssWhitenessThreshold,
    Param::FutureTolerance,
    Param::OutageTimeout,
    Param::RejectionsToDeclareFaulty,
    Param::PropagationInterval,
    Param::FrameLoad,
    Param::FloorAttitude,
    Param::FloorPosition,
    Param::FloorVelocity,
    Param::FloorGyroBias,
    Param::FloorAccelBias,
    Param::FloorStarInstallation,
    Param::FloorGyroScaleFactor,
    Param::FloorAccelScaleFactor,
    Param::FloorGnssError,
    Param::FloorGyroNonOrthogonality,
    Param::FloorAccelMisalignment,
    Param::FloorGyroGSensitivity,
    Param::SigmaCeilingFactor,
    Param::HeldSampleRate,
    Param::HeldSampleSpecificForce,
    Param::SecondOrderAttitude,
    Param::ThresholdGyroBias,
    Param::ThresholdAccelBias,
    Param::ThresholdStarInstallation,
    Param::ThresholdGyroScaleFactor,
    Param::ThresholdAccelScaleFactor,
    Param::StabilityWindow,
    Param::StabilityFraction,
    Param::FreezeConverged,
    Param::EstimationPolicy,
    Param::MotionRateThreshold,
    Param::MotionForceThreshold,
    Param::ConsistencyTimeConstant,
    Param::ConsistencyMeanNisBound,
    Param::ConingCompensation,
    Param::ScullingCompensation,
    Param::StrapdownJ2,
];

impl NavConfig {
    /// The fields' values in [`CONFIG_PARAMS`] order.
    pub(crate) fn values(&self) -> [f64; NAV_CONFIG_PARAMS] {
        [
            self.filter_mode,
            self.filter_discretisation_order,
            self.gravity_field_degree,
            self.gravity_field_order,
            self.gravity_field_terms_per_frame,
            self.filter_initial_attitude_rad,
            self.filter_initial_position_m,
            self.filter_initial_velocity_mps,
            self.filter_initial_gyro_bias_rad_s,
            self.filter_initial_accel_bias_mps2,
            self.filter_initial_star_installation_rad,
            self.filter_initial_gyro_scale_factor,
            self.filter_initial_accel_scale_factor,
            self.process_noise_gyro_noise_density_rad_s_per_sqrt_hz,
            self.process_noise_accel_noise_density_mps2_per_sqrt_hz,
            self.process_noise_gyro_bias_walk_rad_s2_per_sqrt_hz,
            self.process_noise_accel_bias_walk_mps3_per_sqrt_hz,
            self.imu_period_s,
            self.star_mounting_wxyz[0],
            self.star_mounting_wxyz[1],
            self.star_mounting_wxyz[2],
            self.star_mounting_wxyz[3],
            self.star_noise_rad,
            self.star_gate_nis,
            self.gnss_noise_m,
            self.gnss_gate_nis,
            self.timing_max_latency_s,
            self.filter_gnss_error_sigma_m,
            self.filter_gnss_error_correlation_time_s,
            self.gnss_velocity_noise_mps,
            self.imu_max_rate_rad_s,
            self.imu_max_specific_force_mps2,
            self.filter_imu_error_gyro_misalignment_sigma_rad,
            self.filter_imu_error_accel_misalignment_sigma_rad,
            self.filter_imu_error_gyro_g_sensitivity_sigma_rad_s_per_mps2,
            self.gravity_omitted_field_sigma_mps2,
            self.gravity_omitted_field_psd_m2_per_s3,
            self.star_roll_noise_rad,
            self.star_slow_error_sigma_rad[0],
            self.star_slow_error_sigma_rad[1],
            self.star_slow_error_sigma_rad[2],
            self.star_slow_error_correlation_time_s,
            self.star_aberration_correction,
            self.star_noise_matching,
            self.star_second_head,
            self.star_second_head_pairs_before_hand_over,
            self.star_second_head_mounting_wxyz[0],
            self.star_second_head_mounting_wxyz[1],
            self.star_second_head_mounting_wxyz[2],
            self.star_second_head_mounting_wxyz[3],
            self.star_second_head_noise_rad,
            self.star_second_head_roll_noise_rad,
            self.star_second_head_alignment_prior_sigma_rad,
            self.star_second_head_pair_gate_nis,
            self.imu_period_tolerance,
            self.star_acquisition_gate_nis,
            self.star_unit_norm_tolerance,
            self.gnss_lever_arm_body_m[0],
            self.gnss_lever_arm_body_m[1],
            self.gnss_lever_arm_body_m[2],
            self.gnss_acquisition_gate_nis,
            self.gnss_max_jump_m,
            self.gnss_velocity_gate_nis,
            self.gnss_velocity_acquisition_gate_nis,
            self.gnss_whiteness_window_fixes,
            self.gnss_whiteness_threshold,
            self.timing_future_tolerance_s,
            self.timing_outage_timeout_s,
            self.timing_rejections_to_declare_faulty,
            self.covariance_propagation_interval_frames,
            self.covariance_frame_load,
            self.covariance_sigma_floor_attitude_rad,
            self.covariance_sigma_floor_position_m,
            self.covariance_sigma_floor_velocity_mps,
            self.covariance_sigma_floor_gyro_bias_rad_s,
            self.covariance_sigma_floor_accel_bias_mps2,
            self.covariance_sigma_floor_star_installation_rad,
            self.covariance_sigma_floor_gyro_scale_factor,
            self.covariance_sigma_floor_accel_scale_factor,
            self.covariance_optional_sigma_floor_gnss_error_m,
            self.covariance_optional_sigma_floor_gyro_non_orthogonality_rad,
            self.covariance_optional_sigma_floor_accel_misalignment_rad,
            self.covariance_optional_sigma_floor_gyro_g_sensitivity_rad_s_per_mps2,
            self.covariance_sigma_ceiling_factor,
            self.covariance_held_sample_rate_rad_s,
            self.covariance_held_sample_specific_force_mps2,
            self.covariance_second_order_attitude,
            self.calibration_convergence_sigma_gyro_bias_rad_s,
            self.calibration_convergence_sigma_accel_bias_mps2,
            self.calibration_convergence_sigma_star_installation_rad,
            self.calibration_convergence_sigma_gyro_scale_factor,
            self.calibration_convergence_sigma_accel_scale_factor,
            self.calibration_stability_window_s,
            self.calibration_stability_fraction,
            self.calibration_freeze_converged,
            self.calibration_policy,
            self.calibration_motion_rate_threshold_rad_s,
            self.calibration_motion_force_threshold_mps2,
            self.consistency_time_constant_measurements,
            self.consistency_mean_nis_bound,
            self.strapdown_coning_compensation,
            self.strapdown_sculling_compensation,
            self.strapdown_gravity_j2_enabled,
        ]
    }

    /// The configuration of values in [`CONFIG_PARAMS`] order.
    pub(crate) fn from_values(values: &[f64; NAV_CONFIG_PARAMS]) -> Self {
        Self {
            filter_mode: values[0],
            filter_discretisation_order: values[1],
            gravity_field_degree: values[2],
            gravity_field_order: values[3],
            gravity_field_terms_per_frame: values[4],
            filter_initial_attitude_rad: values[5],
            filter_initial_position_m: values[6],
            filter_initial_velocity_mps: values[7],
            filter_initial_gyro_bias_rad_s: values[8],
            filter_initial_accel_bias_mps2: values[9],
            filter_initial_star_installation_rad: values[10],
            filter_initial_gyro_scale_factor: values[11],
            filter_initial_accel_scale_factor: values[12],
            process_noise_gyro_noise_density_rad_s_per_sqrt_hz: values[13],
            process_noise_accel_noise_density_mps2_per_sqrt_hz: values[14],
            process_noise_gyro_bias_walk_rad_s2_per_sqrt_hz: values[15],
            process_noise_accel_bias_walk_mps3_per_sqrt_hz: values[16],
            imu_period_s: values[17],
            star_mounting_wxyz: [values[18], values[19], values[20], values[21]],
            star_noise_rad: values[22],
            star_gate_nis: values[23],
            gnss_noise_m: values[24],
            gnss_gate_nis: values[25],
            timing_max_latency_s: values[26],
            filter_gnss_error_sigma_m: values[27],
            filter_gnss_error_correlation_time_s: values[28],
            gnss_velocity_noise_mps: values[29],
            imu_max_rate_rad_s: values[30],
            imu_max_specific_force_mps2: values[31],
            filter_imu_error_gyro_misalignment_sigma_rad: values[32],
            filter_imu_error_accel_misalignment_sigma_rad: values[33],
            filter_imu_error_gyro_g_sensitivity_sigma_rad_s_per_mps2: values[34],
            gravity_omitted_field_sigma_mps2: values[35],
            gravity_omitted_field_psd_m2_per_s3: values[36],
            star_roll_noise_rad: values[37],
            star_slow_error_sigma_rad: [values[38], values[39], values[40]],
            star_slow_error_correlation_time_s: values[41],
            star_aberration_correction: values[42],
            star_noise_matching: values[43],
            star_second_head: values[44],
            star_second_head_pairs_before_hand_over: values[45],
            star_second_head_mounting_wxyz: [values[46], values[47], values[48], values[49]],
            star_second_head_noise_rad: values[50],
            star_second_head_roll_noise_rad: values[51],
            star_second_head_alignment_prior_sigma_rad: values[52],
            star_second_head_pair_gate_nis: values[53],
            imu_period_tolerance: values[54],
            star_acquisition_gate_nis: values[55],
            star_unit_norm_tolerance: values[56],
            gnss_lever_arm_body_m: [values[57], values[58], values[59]],
            gnss_acquisition_gate_nis: values[60],
            gnss_max_jump_m: values[61],
            gnss_velocity_gate_nis: values[62],
            gnss_velocity_acquisition_gate_nis: values[63],
            gnss_whiteness_window_fixes: values[64],
            gnss_whiteness_threshold: values[65],
            timing_future_tolerance_s: values[66],
            timing_outage_timeout_s: values[67],
            timing_rejections_to_declare_faulty: values[68],
            covariance_propagation_interval_frames: values[69],
            covariance_frame_load: values[70],
            covariance_sigma_floor_attitude_rad: values[71],
            covariance_sigma_floor_position_m: values[72],
            covariance_sigma_floor_velocity_mps: values[73],
            covariance_sigma_floor_gyro_bias_rad_s: values[74],
            covariance_sigma_floor_accel_bias_mps2: values[75],
            covariance_sigma_floor_star_installation_rad: values[76],
            covariance_sigma_floor_gyro_scale_factor: values[77],
            covariance_sigma_floor_accel_scale_factor: values[78],
            covariance_optional_sigma_floor_gnss_error_m: values[79],
            covariance_optional_sigma_floor_gyro_non_orthogonality_rad: values[80],
            covariance_optional_sigma_floor_accel_misalignment_rad: values[81],
            covariance_optional_sigma_floor_gyro_g_sensitivity_rad_s_per_mps2: values[82],
            covariance_sigma_ceiling_factor: values[83],
            covariance_held_sample_rate_rad_s: values[84],
            covariance_held_sample_specific_force_mps2: values[85],
            covariance_second_order_attitude: values[86],
            calibration_convergence_sigma_gyro_bias_rad_s: values[87],
            calibration_convergence_sigma_accel_bias_mps2: values[88],
            calibration_convergence_sigma_star_installation_rad: values[89],
            calibration_convergence_sigma_gyro_scale_factor: values[90],
            calibration_convergence_sigma_accel_scale_factor: values[91],
            calibration_stability_window_s: values[92],
            calibration_stability_fraction: values[93],
            calibration_freeze_converged: values[94],
            calibration_policy: values[95],
            calibration_motion_rate_threshold_rad_s: values[96],
            calibration_motion_force_threshold_mps2: values[97],
            consistency_time_constant_measurements: values[98],
            consistency_mean_nis_bound: values[99],
            strapdown_coning_compensation: values[100],
            strapdown_sculling_compensation: values[101],
            strapdown_gravity_j2_enabled: values[102],
        }
    }
}
