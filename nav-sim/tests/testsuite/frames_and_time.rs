//! Frames and time scales at the ports against independent references, each cited where it
//! is used: the IAU SOFA test suite, Vallado's worked example, IERS Bulletin C and the GPS
//! week count; the flight code's constant-rotation model against the full IAU 2006/2000A
//! chain; and a replay whose GNSS tags cross a leap second.

use crate::common;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use nav_core::frames::{LaunchFrame, ECEF_Z_AXIS};
use nav_fsw::log_record::LogRecord;
use nav_sim::harness::log_replay;
use nav_sim::logs::sensor_log;
use nav_sim::scenario::epoch::{self, EarthOrientation, ItrfFromLaunchInertial, LaunchEpoch};
use nav_sim::setup::launch::{scenario_epoch, scenario_ground_constants};
use nav_sim::Scenario;

const ARCSEC: f64 = 1.0 / 206_264.806_247_096_36;

fn no_earth_orientation() -> EarthOrientation {
    EarthOrientation {
        ut1_minus_utc_s: 0.0,
        polar_motion_x_arcsec: 0.0,
        polar_motion_y_arcsec: 0.0,
    }
}

/// GCRF → ITRF through the crate's wiring of `c2t06a` (argument order, units, row-major
/// orientation) against the IAU SOFA C test suite, `t_sofa_c.c`, function `t_c2t06a`:
/// TT = UT1 = MJD 53736.0, x_p = 2.55060238e-7 rad, y_p = 1.860359247e-6 rad, all nine
/// elements to 1e-12 as SOFA checks them.
#[test]
#[allow(clippy::excessive_precision)] // SOFA's values as printed, digit for digit
fn celestial_to_terrestrial_matches_the_sofa_test_suite() {
    let expected = [
        [
            -0.181_033_212_830_589_728_2,
            0.983_476_980_693_859_229_6,
            0.655_555_096_299_843_650_5e-4,
        ],
        [
            -0.983_476_813_413_621_489_7,
            -0.181_033_220_364_913_083_2,
            0.574_980_084_490_559_411_0e-3,
        ],
        [
            0.577_347_402_474_854_587_8e-3,
            0.396_181_682_963_269_058_1e-4,
            0.999_999_832_550_174_778_5,
        ],
    ];
    let m = epoch::itrf_from_gcrf_mjd(53_736.0, 53_736.0, 2.550_602_38e-7, 1.860_359_247e-6);
    for (row, values) in expected.iter().enumerate() {
        for (column, value) in values.iter().enumerate() {
            assert!(
                (m[(row, column)] - value).abs() < 1e-12,
                "({row}, {column}): {} vs {value}",
                m[(row, column)]
            );
        }
    }
}

/// The whole ground path from a UTC string (hifitime's UTC → TT with TAI − UTC = 32 s, UT1
/// from UT1 − UTC) against Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed.,
/// Example 3-14 (IAU 2006/2000A, CIO based): 2004-04-06 07:51:28.386009 UTC,
/// UT1 − UTC = −0.4399619 s, x_p = −0.140682″, y_p = 0.333309″;
/// r_ITRF = (−1033.4793830, 7901.2952754, 6380.3565958) km and, without the dX, dY pole
/// offsets, r_GCRF = (5102.5089592, 6123.0114033, 6378.1369247) km. Also at the SOFA
/// test's date, 2006-01-01: the matrix is orthonormal and the Earth rotation angle advances
/// at its IERS rate.
#[test]
fn the_ground_rotation_matches_vallados_worked_example() {
    let epoch = LaunchEpoch::new(
        "2004-04-06T07:51:28.386009Z",
        EarthOrientation {
            ut1_minus_utc_s: -0.439_961_9,
            polar_motion_x_arcsec: -0.140_682,
            polar_motion_y_arcsec: 0.333_309,
        },
    )
    .unwrap();
    assert_eq!(epoch.tai_minus_utc_s().to_bits(), 32.0_f64.to_bits());
    let gcrf_m = Vector3::new(5_102.508_959_2, 6_123.011_403_3, 6_378.136_924_7) * 1e3;
    let itrf_m = Vector3::new(-1_033.479_383_0, 7_901.295_275_4, 6_380.356_595_8) * 1e3;
    let error_m = (epoch.itrf_from_gcrf() * gcrf_m - itrf_m).norm();
    println!("Vallado example 3-14: |ITRF error| = {error_m:.4} m");
    assert!(error_m < 0.05, "{error_m} m");
    // Leaving out UT1 − UTC (0.44 s of Earth rotation) moves the point by ~200 m: caught.
    let mut without_ut1 = no_earth_orientation();
    without_ut1.polar_motion_x_arcsec = -0.140_682;
    without_ut1.polar_motion_y_arcsec = 0.333_309;
    let wrong = LaunchEpoch::new("2004-04-06T07:51:28.386009Z", without_ut1).unwrap();
    let wrong_m = (wrong.itrf_from_gcrf() * gcrf_m - itrf_m).norm();
    println!("  with UT1 - UTC left out: {wrong_m:.1} m");
    assert!(wrong_m > 100.0);

    // 2006-01-01: one second later the frame turned by the ERA rate about the pole (IERS
    // Conventions 2010 eq. 5.15), to 3e-11 rad (precession–nutation moves ~2e-11 rad/s).
    let sofa_day = LaunchEpoch::new("2006-01-01T00:00:00Z", no_earth_orientation()).unwrap();
    let r0 = sofa_day.itrf_from_gcrf();
    let r1 = sofa_day.itrf_from_gcrf_after(1.0);
    assert!((r0 * r0.transpose() - nalgebra::Matrix3::identity()).norm() < 1e-15);
    let turn = r1 * r0.transpose();
    let angle = turn[(1, 0)].atan2(turn[(0, 0)]);
    assert!(
        (-angle - epoch::EARTH_ROTATION_ANGLE_RATE_RAD_S).abs() < 3e-11,
        "{angle}"
    );
}

/// Leap seconds: the end of 2016 (IERS Bulletin C 52, July 2016: TAI − UTC goes from 36 s
/// to 37 s at 2017-01-01 00:00:00 UTC; GPS − UTC from 17 s to 18 s, GPS time = TAI − 19 s).
/// GPS week 1930 begins at 2017-01-01 00:00:00 GPS time (1930 weeks after 1980-01-06), so
/// 2017-01-01 00:00:00 UTC is week 1930, 18 s and 2016-12-31 23:59:59 UTC is week 1930,
/// 16 s; 2016-12-31 23:55:00 UTC is week 1929, 604 517 s, 301 s (300 + the leap second)
/// before the first. A wrong leap-second count moves every one of these by a second.
#[test]
fn leap_seconds_and_gps_time_across_the_end_of_2016() {
    let at = |utc: &str| LaunchEpoch::new(utc, no_earth_orientation()).unwrap();
    let before = at("2016-12-31T23:59:59Z");
    let after = at("2017-01-01T00:00:00Z");
    assert_eq!(
        (before.tai_minus_utc_s(), before.gps_minus_utc_s()),
        (36.0, 17.0)
    );
    assert_eq!(
        (after.tai_minus_utc_s(), after.gps_minus_utc_s()),
        (37.0, 18.0)
    );
    assert_eq!(before.gps_week_and_seconds().unwrap(), (1930, 16.0));
    assert_eq!(after.gps_week_and_seconds().unwrap(), (1930, 18.0));
    let launch = at("2016-12-31T23:55:00Z");
    assert_eq!(launch.gps_week_and_seconds().unwrap(), (1929, 604_517.0));
    // The default scenario's epoch, 2024-02-26 04:00:00 UTC (GPS − UTC = 18 s): Monday
    // 04:00:18 GPS time of week 2303 (1980-01-06 + 2303 weeks = 2024-02-25).
    let default = at("2024-02-26T04:00:00Z");
    assert_eq!(default.gps_minus_utc_s().to_bits(), 18.0_f64.to_bits());
    assert_eq!(default.gps_week_and_seconds().unwrap(), (2303, 100_818.0));
}

/// The flight code's model of ITRF → launch-inertial (precession–nutation frozen at the
/// launch epoch, rotation about the day's pole at the WGS-84 rate) against the full chain at
/// every time, over an hour, for a point 1,000 km up: the error stays below 0.1 m (frozen
/// precession–nutation, ~0.02″ an hour, is most of it). Rotating about ECEF z instead (polar
/// motion left out) costs metres, measured and printed.
#[test]
fn the_flight_models_earth_rotation_error_is_bounded_over_an_hour() {
    let scenario = Scenario::default_scenario().unwrap();
    let launch = scenario_epoch(&scenario).unwrap();
    let frame = nav_sim::setup::launch::launch_frame(&scenario).unwrap();
    let full = ItrfFromLaunchInertial::new(&launch, &frame);
    let mut site_z = nav_sim::setup::launch::launch_site(&scenario);
    site_z.earth_axis_ecef = ECEF_Z_AXIS;
    let frame_z = LaunchFrame::new(&site_z).unwrap();
    let point = Vector3::new(3.0e5, 1.0e6, -2.0e5);
    let (mut worst, mut worst_z) = (0.0_f64, 0.0_f64);
    for minutes in [0.0, 1.0, 10.0, 30.0, 60.0] {
        let t = minutes * 60.0;
        let (ecef, _) = full.convert(&point, None, t);
        let back = frame.ecef_to_launch_inertial(&ecef, t).unwrap();
        let back_z = frame_z.ecef_to_launch_inertial(&ecef, t).unwrap();
        worst = worst.max((back - point).norm());
        worst_z = worst_z.max((back_z - point).norm());
    }
    println!(
        "flight Earth model over 1 h: {worst:.4} m (pole of the day), {worst_z:.2} m (ECEF z)"
    );
    assert!(worst < 0.1, "{worst}");
    assert!(worst_z > 10.0 * worst);
}

/// The ground constants: the star tracker's GCRF and the launch-inertial frame differ by a
/// large rotation (leaving `q_ig` out is not a small error: a test of the flight chain
/// catches it), and dropping UT1 − UTC or polar motion changes `q_ig` by what the docs say.
#[test]
fn ground_constants_and_what_each_parameter_costs() {
    let scenario = Scenario::default_scenario().unwrap();
    let ground = scenario_ground_constants(&scenario).unwrap();
    let [w, x, y, z] = ground.sensor_frames.gcrf_to_launch_inertial_wxyz;
    let q_ig = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
    println!("q_ig = {q_ig:?} ({:.2} deg)", q_ig.angle().to_degrees());
    assert!(q_ig.angle() > 10.0_f64.to_radians());
    let angle_without = |change: fn(&mut EarthOrientation)| {
        let mut changed = scenario.clone();
        change(&mut changed.launch_site.earth_orientation);
        let [w, x, y, z] = scenario_ground_constants(&changed)
            .unwrap()
            .sensor_frames
            .gcrf_to_launch_inertial_wxyz;
        q_ig.angle_to(&UnitQuaternion::from_quaternion(Quaternion::new(
            w, x, y, z,
        )))
    };
    let ut1 = angle_without(|e| e.ut1_minus_utc_s = 0.0);
    let pole = angle_without(|e| {
        e.polar_motion_x_arcsec = 0.0;
        e.polar_motion_y_arcsec = 0.0;
    });
    println!(
        "q_ig change: UT1 - UTC left out {:.4}\", polar motion left out {:.4}\"",
        ut1 / ARCSEC,
        pole / ARCSEC
    );
    // 0.002122 s of Earth rotation = 0.0318″; the pole of the day is 0.2619″ off z.
    assert!((ut1 / ARCSEC - 0.0318).abs() < 0.002, "{}", ut1 / ARCSEC);
    assert!((pole / ARCSEC - 0.2619).abs() < 0.01, "{}", pole / ARCSEC);
}

/// A replay whose GNSS tags cross the leap second at the end of 2016: the flight starts
/// 600 s after a launch at 2016-12-31 23:49:40 UTC, so UTC inserts 23:59:60 twenty seconds
/// in. GPS time runs on: every fix's GPS tag is the truth's time of validity, and the flight
/// fuses every fix (none stale, in the future or gated). The Earth orientation here is a
/// representative value, not the day's bulletin: the test is about time.
#[test]
fn a_replay_across_a_leap_second_fuses_every_fix() {
    let mut scenario = common::short_scenario();
    scenario.launch_site.epoch_utc = "2016-12-31T23:49:40Z".to_string();
    scenario.launch_site.earth_orientation = EarthOrientation {
        ut1_minus_utc_s: -0.41,
        polar_motion_x_arcsec: 0.1,
        polar_motion_y_arcsec: 0.3,
    };
    scenario.validate().unwrap();
    let frames = (42.0 / scenario.imu.frame_period_s()).round() as u64;
    let records = sensor_log::simulated_records(&scenario, frames).unwrap();
    let sensor_frames = scenario_ground_constants(&scenario).unwrap().sensor_frames;
    let mut tags = Vec::new();
    for record in &records {
        if let LogRecord::Gnss(gnss) = record {
            let t = sensor_frames
                .navigation_time_s(gnss.gps_week, gnss.gps_seconds_of_week)
                .unwrap();
            tags.push(t);
        }
    }
    assert!(tags.len() >= 40, "{}", tags.len());
    // 1 Hz from 601 s: whole seconds of navigation time, no jump at the leap second.
    for (k, t) in tags.iter().enumerate() {
        assert!((t - (601.0 + k as f64)).abs() < 1e-6, "fix {k}: {t}");
    }
    let mut csv = sensor_log::SensorLogWriter::new(Vec::new()).unwrap();
    for record in &records {
        csv.write(record).unwrap();
    }
    let csv = csv.finish().unwrap();
    let summary = log_replay::replay(csv.as_slice(), &scenario, &mut Vec::new()).unwrap();
    let health = &summary.health;
    println!("{}", summary.text());
    // Every star update is fused too: a flight code that left out the GCRF rotation would
    // see the attitude 100° off and gate them all.
    assert_eq!(
        (
            health.measurement_stale,
            health.measurement_future,
            health.gnss_gate_rejections,
            health.gnss_non_finite,
            health.star_gate_rejections
        ),
        (0, 0, 0, 0, 0)
    );
}

/// A leap second (IERS Bulletin C 52: 2016-12-31 23:59:60 UTC was inserted) is its own
/// second: 23:59:60 is GPS week 1930, 17 s, between 23:59:59 (16 s) and 2017-01-01 00:00:00
/// (18 s), and 23:59:60.5 is 17.5 s; TAI − UTC is still 36 s during it. The Earth rotation
/// there equals one SI second after 23:59:59's. Second 60 on a day without a leap second
/// (2015-12-31; the 2015 leap second was on 30 June) is refused.
#[test]
fn a_leap_second_epoch_is_the_second_between_its_neighbours() {
    let at = |utc: &str| LaunchEpoch::new(utc, no_earth_orientation()).unwrap();
    let leap = at("2016-12-31T23:59:60Z");
    assert_eq!(leap.gps_week_and_seconds().unwrap(), (1930, 17.0));
    assert_eq!(
        at("2016-12-31T23:59:60.5Z").gps_week_and_seconds().unwrap(),
        (1930, 17.5)
    );
    assert_eq!(leap.tai_minus_utc_s().to_bits(), 36.0_f64.to_bits());
    assert!(leap.utc_text().contains("23:59:60"), "{}", leap.utc_text());
    let before = at("2016-12-31T23:59:59Z");
    assert_eq!(
        before.after(1.0).gps_week_and_seconds().unwrap(),
        (1930, 17.0)
    );
    assert!(before.after(1.0).utc_text().contains("23:59:60"));
    assert_eq!(
        before.after(2.0).gps_week_and_seconds().unwrap(),
        (1930, 18.0)
    );
    let turned = leap.itrf_from_gcrf() - before.itrf_from_gcrf_after(1.0);
    assert!(turned.norm() < 1e-12, "{turned}");
    // 23:59:59's rotation is a second's turn away (7.3e-5 rad).
    assert!((before.itrf_from_gcrf() - leap.itrf_from_gcrf()).norm() > 5e-5);
    assert!(LaunchEpoch::new("2015-12-31T23:59:60Z", no_earth_orientation()).is_err());
}
