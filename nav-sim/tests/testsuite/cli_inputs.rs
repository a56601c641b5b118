//! Command-line input that used to be accepted wrongly, now refused or handled: an error
//! about a value given by a flag names the flag, its value, the range and the unit; an Earth
//! orientation value out of range names its own key in readable words; a leap-second epoch
//! gives its own GPS second; the Rust ground constants carry their provenance; `--run K`
//! outside `--runs N` and a tracker with more heads than the flight software takes are
//! refused before any flight.

use std::path::Path;

use crate::cli::{assert_failed_saying, nav_sim, stderr, stdout};

/// `ground-constants` with `arguments`: the failure message (the command must fail).
fn ground_constants_refusal(arguments: &[&str]) -> String {
    let directory = tempfile::tempdir().unwrap();
    let mut all = vec!["ground-constants"];
    all.extend_from_slice(arguments);
    let output = nav_sim(directory.path(), &all);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    stderr(&output)
}

/// A value given by a flag is named by the flag, with its value, range and unit; the scenario
/// key it sets is not mentioned. An Earth orientation parameter out of range names itself
/// (not `epoch_utc`) in words, not as a Rust `Debug` struct.
#[test]
fn ground_constants_errors_name_the_flag_and_the_earth_orientation_key() {
    for (arguments, expected, key) in [
        (
            &["--latitude-deg", "95"][..],
            "nav-sim: --latitude-deg must be in [-90, 90] deg (got 95 deg)",
            "launch_site.latitude_deg",
        ),
        (
            &["--height-m", "-600"][..],
            "nav-sim: --height-m must be in [-500, 10000] m (got -600 m)",
            "launch_site.height_m",
        ),
        (
            &["--ut1-minus-utc-s", "1.5"][..],
            "nav-sim: --ut1-minus-utc-s = 1.5 s has a magnitude above the limit 0.9 s (leap \
             seconds keep |UT1 - UTC| <= 0.9 s)",
            "ut1_minus_utc_s",
        ),
        (
            &["--polar-motion-y-arcsec", "-3"][..],
            "nav-sim: --polar-motion-y-arcsec = -3 arcsec has a magnitude above the limit 2 \
             arcsec",
            "launch_site.earth_orientation",
        ),
        (
            &["--epoch-utc", "2015-12-31T23:59:60Z"][..],
            "nav-sim: --epoch-utc launch epoch \"2015-12-31T23:59:60Z\" is not an ISO 8601 UTC",
            "launch_site.epoch_utc",
        ),
    ] {
        let message = ground_constants_refusal(arguments);
        assert!(message.contains(expected), "{message}");
        assert!(!message.contains(key), "{message}");
        assert!(!message.contains("EarthOrientation"), "{message}");
    }
}

/// The same Earth orientation value in a scenario file names its scenario key, not
/// `launch_site.epoch_utc`.
#[test]
fn an_earth_orientation_value_in_a_scenario_names_its_key() {
    let directory = tempfile::tempdir().unwrap();
    let default = stdout(&nav_sim(directory.path(), &["scenario"]));
    let line = default
        .lines()
        .find(|line| line.starts_with("ut1_minus_utc_s = "))
        .unwrap();
    let path = directory.path().join("eop.toml");
    std::fs::write(&path, default.replacen(line, "ut1_minus_utc_s = -1.2", 1)).unwrap();
    let output = nav_sim(
        directory.path(),
        &["ground-constants", path.to_str().unwrap()],
    );
    assert_failed_saying(
        &output,
        "launch_site.earth_orientation.ut1_minus_utc_s = -1.2 s has a magnitude above the \
         limit 0.9 s",
    );
    assert!(
        !stderr(&output).contains("epoch_utc"),
        "{}",
        stderr(&output)
    );
}

/// `--epoch-utc` at the leap second 2016-12-31T23:59:60Z is GPS week 1930, 17 s (not 16 s,
/// the second before it).
#[test]
fn ground_constants_of_a_leap_second_are_its_own_gps_second() {
    let directory = tempfile::tempdir().unwrap();
    let json = stdout(&nav_sim(
        directory.path(),
        &[
            "ground-constants",
            "--format",
            "json",
            "--epoch-utc",
            "2016-12-31T23:59:60Z",
        ],
    ));
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let frames = &value["sensor_frames"];
    assert_eq!(
        frames["launch_epoch_gps_week"].as_u64(),
        Some(1930),
        "{json}"
    );
    assert_eq!(
        frames["launch_epoch_gps_seconds_of_week"].as_f64(),
        Some(17.0),
        "{json}"
    );
}

/// The Rust constants say what they were computed for: the epoch, the Earth orientation
/// values and the tool's version, as a constant a flight image carries and in each
/// constant's documentation.
#[test]
fn rust_ground_constants_carry_their_provenance() {
    let directory = tempfile::tempdir().unwrap();
    let rust = stdout(&nav_sim(
        directory.path(),
        &[
            "ground-constants",
            "--format",
            "rust",
            "--epoch-utc",
            "2024-03-01T12:30:00Z",
            "--ut1-minus-utc-s",
            "-0.0123",
            "--polar-motion-x-arcsec",
            "0.0456",
            "--polar-motion-y-arcsec",
            "0.3789",
        ],
    ));
    let provenance = format!(
        "epoch_utc=2024-03-01T12:30:00Z ut1_minus_utc_s=-0.0123 polar_motion_x_arcsec=0.0456 \
         polar_motion_y_arcsec=0.3789 tool=nav-sim {} ground-constants",
        env!("CARGO_PKG_VERSION")
    );
    assert!(
        rust.contains(&format!(
            "pub const GROUND_CONSTANTS_PROVENANCE: &str =\n    \"{provenance}\";"
        )),
        "{rust}"
    );
    let doc = format!(
        "/// Computed by nav-sim {} ground-constants for the launch epoch 2024-03-01T12:30:00Z \
         UTC,\n/// with UT1 − UTC = -0.0123 s and polar motion x_p = 0.0456″, y_p = 0.3789″.\n\
         pub const ",
        env!("CARGO_PKG_VERSION")
    );
    assert_eq!(rust.matches(&doc).count(), 2, "{rust}");
}

/// `--run K` flies run K of a campaign of `--runs N` runs, 0 to N − 1: a K outside is
/// refused naming both flags, before any flight.
#[test]
fn monte_carlo_refuses_a_run_outside_its_runs() {
    let directory = tempfile::tempdir().unwrap();
    for (run, runs) in [("7", "4"), ("4", "4")] {
        let output = nav_sim(
            directory.path(),
            &["monte-carlo", "--run", run, "--runs", runs],
        );
        assert_failed_saying(
            &output,
            &format!("--run {run} is not a run of --runs {runs}: the runs are numbered 0 to 3"),
        );
        assert!(stdout(&output).is_empty(), "{output:?}");
    }
}

/// A tracker with more heads than the flight software takes (two) is refused by the
/// commands that fly it, naming the key, the head count and the limit, before any flight.
#[test]
fn calibrate_and_monte_carlo_refuse_more_heads_than_the_flight_takes() {
    let directory = tempfile::tempdir().unwrap();
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/star_tracker_two_heads.toml");
    // The shipped file's second head (its last table), five times.
    let shipped = std::fs::read_to_string(&base).unwrap();
    let head = &shipped[shipped.find("\n[[star_sensor.additional_heads]]").unwrap()..];
    let text = format!("extends = '{}'\n{}", base.display(), head.repeat(5));
    let path = directory.path().join("six_heads.toml");
    std::fs::write(&path, text).unwrap();
    let path = path.to_str().unwrap();
    for arguments in [
        &["calibrate", path][..],
        &["monte-carlo", path, "--runs", "1"][..],
        &["monte-carlo", path, "--run", "0"][..],
    ] {
        let output = nav_sim(directory.path(), arguments);
        assert_failed_saying(
            &output,
            "star_sensor.additional_heads gives 6 star heads with [star_sensor], more than the \
             2 heads the flight software takes",
        );
    }
}
