//! Unit tests of the spherical-harmonic field, its reader and its Taylor model.

use super::*;

use gfc::GravityCoefficients;
use nav_core::frames::{
    LaunchSite, ECEF_Z_AXIS, WGS84_GM_M3_S2, WGS84_J2, WGS84_SEMI_MAJOR_AXIS_M,
};
use nav_core::gravity::GravityModel;

fn site(earth_axis_ecef: [f64; 3]) -> LaunchFrame {
    LaunchFrame::new(&LaunchSite {
        latitude_rad: 40.958_f64.to_radians(),
        longitude_rad: 100.291_f64.to_radians(),
        height_m: 1000.0,
        azimuth_rad: 190.0_f64.to_radians(),
        earth_axis_ecef,
    })
    .unwrap()
}

/// Launch-inertial positions from the surface to 2,000 km, over both poles.
fn positions(frame: &LaunchFrame) -> Vec<Vector3<f64>> {
    let directions = [
        [1.0, 0.2, -0.3],
        [0.0, 0.0, 1.0],
        [0.01, -0.02, -1.0],
        [-0.6, 0.7, 0.1],
        [0.3, -0.9, 0.5],
    ];
    let mut points = Vec::new();
    for (index, direction) in directions.iter().enumerate() {
        let unit = Vector3::from(*direction).normalize();
        let radius_m = WGS84_SEMI_MAJOR_AXIS_M + 5.0e5 * index as f64;
        points.push(frame.launch_from_ecef() * (unit * radius_m) + frame.earth_centre_launch_m());
    }
    points
}

/// Degree 2, order 0 with WGS-84's `GM`, `a` and `C̄_20 = −J2/√5` is nav-core's point mass +
/// `J2`, to rounding.
#[test]
fn degree_two_zonal_is_nav_core_j2() {
    let size = gfc::triangle_index(2, 2) + 1;
    let mut c = vec![0.0; size];
    c[0] = 1.0;
    c[gfc::triangle_index(2, 0)] = -WGS84_J2 / 5.0_f64.sqrt();
    let field = SphericalHarmonics::new(GravityCoefficients {
        model: "WGS-84 J2".to_string(),
        gm_m3_s2: WGS84_GM_M3_S2,
        radius_m: WGS84_SEMI_MAJOR_AXIS_M,
        degree: 2,
        order: 0,
        c,
        s: vec![0.0; size],
    });
    let frame = site(ECEF_Z_AXIS);
    let mut worst: f64 = 0.0;
    for position in positions(&frame) {
        let earth_fixed = frame.launch_inertial_to_ecef(&position, 0.0).unwrap();
        let harmonic = frame.launch_from_ecef() * field.acceleration_mps2(&earth_fixed);
        let j2 = GravityModel { j2_enabled: true }.gravity_launch_mps2(&frame, &position);
        worst = worst.max((harmonic - j2).norm() / j2.norm());
    }
    println!("degree 2 order 0 vs nav-core J2: worst relative difference {worst:.2e}");
    assert!(worst < 1.0e-13, "{worst:e}");
}

/// The remainder in launch-inertial axes is the Earth-fixed field carried through nav-core's
/// own ECEF → launch-inertial relation (the truth's), at several times.
#[test]
fn remainder_rotates_with_the_earth_as_nav_core_relates_the_frames() {
    let frame = site([2.0e-6, -1.2e-6, (1.0_f64 - 5.2e-12).sqrt()]);
    let remainder = RotatingRemainder::new(EGM2008_GFC, 20, 20, frame).unwrap();
    for time_s in [0.0, 600.0, 3677.0, 43_200.0] {
        for position in positions(&frame) {
            let earth_fixed = frame.launch_inertial_to_ecef(&position, time_s).unwrap();
            let field_ecef = remainder.field().acceleration_mps2(&earth_fixed);
            // ECEF → launch-inertial of a vector: the difference of two mapped points.
            let tip = frame
                .ecef_to_launch_inertial(&(earth_fixed + field_ecef * 1.0e6), time_s)
                .unwrap();
            let tail = frame.ecef_to_launch_inertial(&earth_fixed, time_s).unwrap();
            let expected = (tip - tail) / 1.0e6;
            let got = remainder.acceleration_mps2(time_s, &position).unwrap();
            assert!(
                (got - expected).norm() < 1.0e-9 * expected.norm(),
                "{got} {expected}"
            );
        }
    }
}

/// The remainder's size (EGM2008 to 20 × 20) where the default flight flies: 1e-5 to 1e-4.
#[test]
fn remainder_is_the_size_of_the_terms_beyond_j2() {
    let frame = site(ECEF_Z_AXIS);
    let remainder = RotatingRemainder::new(EGM2008_GFC, 20, 20, frame).unwrap();
    let mut largest: f64 = 0.0;
    for position in positions(&frame).into_iter().skip(1).take(2) {
        largest = largest.max(remainder.acceleration_mps2(0.0, &position).unwrap().norm());
    }
    println!("largest |δg| at 500-1000 km: {largest:.3e} m/s²");
    assert!((1.0e-5..3.0e-4).contains(&largest), "{largest:e}");
}

/// The Taylor model stays within 1e-9 m/s² of the full evaluation over a refresh interval
/// and one frame more, flying at 10 km/s along three axes at 200 km, where `δg` varies
/// fastest (the bound of the module docs), at degree 20 and at the file's 60.
#[test]
fn taylor_model_error_is_bounded_over_a_refresh_interval() {
    for degree in [20, 60] {
        let worst = worst_taylor_error_mps2(degree);
        println!("degree {degree}: worst Taylor error {worst:.2e} m/s² over 0.102 s at 10 km/s");
        assert!(worst < 1.0e-9, "{worst:e}");
    }
}

/// Worst error of the Taylor model of the remainder to `degree` × `degree` over one refresh
/// interval and a frame, at 200 km and 10 km/s along three axes.
fn worst_taylor_error_mps2(degree: usize) -> f64 {
    let frame = site(ECEF_Z_AXIS);
    let remainder = RotatingRemainder::new(EGM2008_GFC, degree, degree, frame).unwrap();
    let horizon_s = REFRESH_INTERVAL_S + 0.002;
    let mut worst: f64 = 0.0;
    for (index, direction) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        .iter()
        .enumerate()
    {
        let radial = Vector3::new(0.3, -0.5 + index as f64 * 0.4, 0.8).normalize();
        let position = frame.launch_from_ecef() * (radial * (WGS84_SEMI_MAJOR_AXIS_M + 2.0e5))
            + frame.earth_centre_launch_m();
        let velocity = Vector3::from(*direction) * 1.0e4;
        let start_s = 100.0 * index as f64;
        let node = remainder.linearise(start_s, &position).unwrap();
        for step in 1..=10 {
            let elapsed_s = horizon_s * f64::from(step) / 10.0;
            let there = position + velocity * elapsed_s;
            let exact = remainder
                .acceleration_mps2(start_s + elapsed_s, &there)
                .unwrap();
            let model = node.acceleration_mps2(start_s + elapsed_s, &there);
            worst = worst.max((exact - model).norm());
        }
    }
    worst
}

#[test]
fn tracker_refreshes_at_the_interval_and_not_before() {
    let frame = site(ECEF_Z_AXIS);
    let remainder = RotatingRemainder::new(EGM2008_GFC, 4, 4, frame).unwrap();
    let mut tracker = RemainderTracker::new(remainder);
    let position = positions(&frame)[1];
    assert!(tracker.acceleration_mps2(0.0, &position).is_err());
    let period_s = 0.002;
    let mut node_times = Vec::new();
    for frame_index in 0..120_u32 {
        let time_s = 600.0 + f64::from(frame_index) * period_s;
        tracker.start_frame(time_s, &position).unwrap();
        let node_time_s = tracker.node.map(|node| node.time_s).unwrap();
        if node_times.last() != Some(&node_time_s) {
            node_times.push(node_time_s);
        }
    }
    // Frames 0, 50 and 100: every 0.1 s at 500 Hz.
    assert_eq!(node_times.len(), 3, "{node_times:?}");
    assert!((node_times[2] - node_times[0] - 0.2).abs() < 1.0e-9);
}

/// An ICGEM header and the first coefficient lines of a model, with `line` appended.
fn file_with(norm: &str, line: &str) -> String {
    format!(
        "modelname test\nearth_gravity_constant 0.3986004415E+15\nradius 0.63781363E+07\n\
         max_degree 3\nnorm {norm}\nend_of_head ====\ngfc 0 0 1.0d0 0.0d0\n\
         gfc 2 0 -0.484165143790815e-03 0.0\ngfc 2 1 0.0 0.0\ngfc 2 2 2.4e-6 -1.4e-6\n{line}\n"
    )
}

#[test]
fn reader_reports_malformed_files_clearly() {
    let good = file_with("fully_normalized", "");
    let coefficients = parse_gfc(&good, 2, 2).unwrap();
    assert_eq!(coefficients.model, "test");
    assert!((coefficients.c[gfc::triangle_index(2, 2)] - 2.4e-6).abs() < 1.0e-20);
    let cases = [
        (parse_gfc("radius 1\n", 2, 2), "header key end_of_head"),
        (
            parse_gfc(&file_with("unnormalized", ""), 2, 2),
            "norm is \"unnormalized\"",
        ),
        (
            parse_gfc(&good.replace("radius 0.63781363E+07\n", ""), 2, 2),
            "header key radius",
        ),
        (
            parse_gfc(&file_with("fully_normalized", "gfc 3 0 x 0.0"), 3, 3),
            "line 11: expected `gfc L M C S`",
        ),
        (parse_gfc(&good, 3, 3), "degree 3 order 0 is missing"),
        (
            parse_gfc(&good, 4, 4),
            "degree 4 requested, the file stops at 3",
        ),
    ];
    for (result, expected) in cases {
        let message = result.unwrap_err().to_string();
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
}

#[test]
fn shipped_model_reads_to_its_full_degree() {
    let coefficients = parse_gfc(EGM2008_GFC, 60, 60).unwrap();
    assert_eq!(coefficients.model, "EGM2008");
    assert!((coefficients.gm_m3_s2 - 3.986004415e14).abs() < 1.0);
    assert!((coefficients.radius_m - 6_378_136.3).abs() < 1.0e-6);
    // The published tide-free C̄_20.
    let c20 = coefficients.c[gfc::triangle_index(2, 0)];
    assert!((c20 + 0.484165143790815e-3).abs() < 1.0e-18);
    assert!(parse_gfc(EGM2008_GFC, 61, 61).is_err());
}
