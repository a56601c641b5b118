//! The `nav-sim` command line on bad input and bad output paths: an output that is an input is
//! refused and the input left byte for byte, a failed run leaves an existing output as it was,
//! a bad `--out` fails before the run naming its path, `--check` turns a missed calibration
//! figure or an inconsistent NEES into a failure, and `--runs` accepts 1 to 100,000.
//!
//! Every flight here is a 2 s scenario (the built-in one with its manoeuvres replaced by one
//! short coast), so the tests stay fast in a debug build.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use proptest::strategy::Strategy as _;

/// The one manoeuvre of the short scenario: 2 s of quiet coast, far too short for any
/// calibration figure to be met.
const SHORT_MANOEUVRE: &str = r#"[[manoeuvre]]
label = "short coast"
duration_s = 2.0
ramp_s = 0.0
body_rate_deg_per_s = [2.4e-4, 2.4e-4, 2.4e-4]
specific_force_mps2 = [0.0, 0.0, 0.0]

"#;

/// The seed line of the built-in scenario.
const SEED: &str = "seed = 20170415";

/// A seed of the short scenario whose single Monte Carlo run has a NEES of 31.9, above the
/// 95 % interval [6.26, 27.49] of one χ²(15) draw.
const INCONSISTENT_SEED: &str = "seed = 20170442";

/// The gyro scale factor of the built-in scenario, and a value 30σ of the filter's prior
/// (1e-4) from zero: the NEES of a flight with it is far above its bound.
const GYRO_SCALE_FACTOR: &str = "scale_factor = [3.0e-5, 3.0e-5, 3.0e-5]";
const GYRO_SCALE_FACTOR_BEYOND_THE_PRIOR: &str = "scale_factor = [3.0e-3, 3.0e-3, 3.0e-3]";

pub fn nav_sim(directory: &Path, arguments: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nav-sim"))
        .args(arguments)
        .current_dir(directory)
        .output()
        .unwrap()
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Writes the short scenario as `name` in `directory`, with each `(line, replacement)` of
/// `edits` applied to the settings before the manoeuvres.
pub fn short_scenario(directory: &Path, name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let default = stdout(&nav_sim(directory, &["scenario"]));
    let first = default.find("[[manoeuvre]]").unwrap();
    let filter = default.find("[filter]").unwrap();
    let mut text = default[..first].to_string();
    for (line, replacement) in edits {
        let line = format!("\n{line}\n");
        assert_eq!(text.matches(&line).count(), 1, "{line}");
        text = text.replace(&line, &format!("\n{replacement}\n"));
    }
    text += SHORT_MANOEUVRE;
    text += &default[filter..];
    let path = directory.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The names in `directory`, sorted (temporary files left behind would show here).
fn names(directory: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(directory)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The command failed and its message contains `text` (e.g. the path it names).
pub fn assert_failed_saying(output: &Output, text: &str) {
    assert!(!output.status.success(), "{output:?}");
    assert!(stderr(output).contains(text), "{}", stderr(output));
}

#[test]
fn replay_refuses_to_write_over_its_log() {
    let directory = tempfile::tempdir().unwrap();
    let log = directory.path().join("log.csv");
    let content = b"kind,arrival_time_s\nimu,600.002\n";
    std::fs::write(&log, content).unwrap();
    std::fs::hard_link(&log, directory.path().join("same.csv")).unwrap();
    for out in ["log.csv", "./log.csv", "same.csv"] {
        let output = nav_sim(directory.path(), &["replay", "log.csv", "--out", out]);
        assert_failed_saying(&output, out);
        assert!(stderr(&output).contains("refusing"), "{}", stderr(&output));
        assert_eq!(std::fs::read(&log).unwrap(), content);
    }
}

#[test]
fn log_refuses_to_write_over_its_scenario() {
    let directory = tempfile::tempdir().unwrap();
    let scenario = short_scenario(directory.path(), "short.toml", &[]);
    let before = std::fs::read(&scenario).unwrap();
    let output = nav_sim(
        directory.path(),
        &["log", "short.toml", "--out", "short.toml"],
    );
    assert_failed_saying(&output, "short.toml");
    assert!(stderr(&output).contains("refusing"), "{}", stderr(&output));
    assert_eq!(std::fs::read(&scenario).unwrap(), before);
    let output = nav_sim(
        directory.path(),
        &[
            "replay",
            "other.csv",
            "--scenario",
            "short.toml",
            "--out",
            "short.toml",
        ],
    );
    assert_failed_saying(&output, "short.toml");
    assert_eq!(std::fs::read(&scenario).unwrap(), before);
}

#[test]
fn a_failed_replay_leaves_the_previous_output_and_a_good_one_replaces_it() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "short.toml", &[]);
    let output = nav_sim(directory.path(), &["log", "short.toml", "--out", "log.csv"]);
    assert!(output.status.success(), "{}", stderr(&output));
    // The log's first 3000 bytes and a line with the wrong number of fields.
    let mut damaged = std::fs::read(directory.path().join("log.csv")).unwrap();
    damaged.truncate(3000);
    damaged.extend_from_slice(b"\nimu,1,2\n");
    std::fs::write(directory.path().join("damaged.csv"), damaged).unwrap();
    let previous = b"the previous output\n";
    let out = directory.path().join("out.csv");
    std::fs::write(&out, previous).unwrap();

    let arguments = ["--scenario", "short.toml", "--out", "out.csv"];
    let output = nav_sim(
        directory.path(),
        &[&["replay", "damaged.csv"], &arguments[..]].concat(),
    );
    assert_failed_saying(&output, "damaged.csv");
    assert_eq!(std::fs::read(&out).unwrap(), previous);
    assert_eq!(
        names(directory.path()),
        ["damaged.csv", "log.csv", "out.csv", "short.toml"]
    );

    let output = nav_sim(
        directory.path(),
        &[&["replay", "log.csv"], &arguments[..]].concat(),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.starts_with("time_s,"), "{written}");
    assert_eq!(written.lines().count(), 3, "{written}");
    assert_eq!(
        names(directory.path()),
        ["damaged.csv", "log.csv", "out.csv", "short.toml"]
    );
}

#[test]
fn a_bad_output_file_path_is_named() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "short.toml", &[]);
    std::fs::create_dir(directory.path().join("existing")).unwrap();
    for (out, reason) in [
        ("existing", "is a directory"),
        ("missing/log.csv", "No such file or directory"),
        ("short.toml/log.csv", "Not a directory"),
    ] {
        let output = nav_sim(directory.path(), &["log", "short.toml", "--out", out]);
        assert_failed_saying(&output, out);
        assert!(stderr(&output).contains(reason), "{}", stderr(&output));
        assert!(!stdout(&output).contains("wrote"), "{}", stdout(&output));
    }
    assert_eq!(names(directory.path()), ["existing", "short.toml"]);
    assert!(names(&directory.path().join("existing")).is_empty());
}

#[test]
fn a_bad_output_directory_fails_before_the_flight() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "short.toml", &[]);
    for out in ["short.toml", "short.toml/plots"] {
        let output = nav_sim(directory.path(), &["calibrate", "short.toml", "--out", out]);
        assert_failed_saying(&output, out);
        assert!(stdout(&output).is_empty(), "{}", stdout(&output));
        let output = nav_sim(
            directory.path(),
            &["monte-carlo", "short.toml", "--runs", "1", "--out", out],
        );
        assert_failed_saying(&output, out);
        assert!(stdout(&output).is_empty(), "{}", stdout(&output));
        let output = nav_sim(directory.path(), &["benefit", "short.toml", "--out", out]);
        assert_failed_saying(&output, out);
        assert!(stdout(&output).is_empty(), "{}", stdout(&output));
    }
    // The design search (tens of seconds) does not start when its output cannot be written.
    let out = "short.toml/designed.toml";
    let output = nav_sim(directory.path(), &["design", "short.toml", "--out", out]);
    assert_failed_saying(&output, out);
    assert!(stdout(&output).is_empty(), "{}", stdout(&output));
}

#[test]
fn calibrate_check_fails_when_the_nees_is_above_its_bound() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(
        directory.path(),
        "beyond.toml",
        &[(GYRO_SCALE_FACTOR, GYRO_SCALE_FACTOR_BEYOND_THE_PRIOR)],
    );
    let output = nav_sim(directory.path(), &["calibrate", "beyond.toml", "--check"]);
    assert_failed_saying(&output, "is above its χ²(15) 95 % bound 25.0");
}

#[test]
fn calibrate_check_fails_when_a_figure_is_not_met() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "short.toml", &[]);
    let output = nav_sim(directory.path(), &["calibrate", "short.toml"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("0 of 15 parameter axes meet"));
    // The health counters: a table of the non-zero ones (or one line), never a Debug struct.
    assert!(
        text.contains("health counters (the non-zero ones):")
            || text.contains("health counters: all zero"),
        "{text}"
    );
    assert!(!text.contains("HealthCounters {"), "{text}");
    let output = nav_sim(directory.path(), &["calibrate", "short.toml", "--check"]);
    assert_failed_saying(
        &output,
        "15 of 15 parameter axes do not meet the paper's accuracy",
    );
}

#[test]
fn monte_carlo_check_fails_when_the_nees_is_outside_its_interval() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "consistent.toml", &[]);
    short_scenario(
        directory.path(),
        "inconsistent.toml",
        &[(SEED, INCONSISTENT_SEED)],
    );
    let run = |scenario: &str, check: bool| {
        let mut arguments = vec!["monte-carlo", scenario, "--runs", "1", "--json"];
        if check {
            arguments.push("--check");
        }
        nav_sim(directory.path(), &arguments)
    };
    let output = run("inconsistent.toml", false);
    assert!(output.status.success(), "{}", stderr(&output));
    let output = run("inconsistent.toml", true);
    assert_failed_saying(&output, "outside its 95 % interval");
    let output = run("consistent.toml", true);
    assert!(output.status.success(), "{}", stderr(&output));
}

#[test]
fn runs_must_be_one_to_the_campaign_limit() {
    let directory = tempfile::tempdir().unwrap();
    for command in ["monte-carlo", "benefit"] {
        for runs in [
            "-1",
            "0",
            "many",
            "1e12",
            "100001",
            "18446744073709551615",
            "18446744073709551616",
        ] {
            let output = nav_sim(directory.path(), &[command, "--runs", runs]);
            assert_eq!(
                output.status.code(),
                Some(2),
                "{command} {runs}: {output:?}"
            );
            let message = stderr(&output);
            assert!(message.contains("--runs"), "{message}");
            assert!(message.contains("in 1..=100000"), "{message}");
            assert!(!message.contains("'-- -1'"), "{message}");
            assert!(!message.contains("panicked"), "{message}");
        }
    }
}

/// A `log` of the built-in flight (a 1.5 million-line CSV), a Monte Carlo shard and a `replay`,
/// each interrupted by SIGINT or SIGTERM while its output is staged: the command exits with 130
/// and leaves no temporary file, and an existing target as it was.
#[test]
fn an_interrupted_command_leaves_no_temporary_file() {
    for (arguments, signal) in [
        (&["log", "--out", "out/log.csv"][..], "-INT"),
        (
            &[
                "monte-carlo",
                "--runs",
                "4",
                "--shard",
                "0/2",
                "--out",
                "out",
            ][..],
            "-TERM",
        ),
        // The log is a FIFO no one writes: the replay has staged its output and waits.
        (
            &["replay", "sensors.fifo", "--out", "out/log.csv"][..],
            "-INT",
        ),
    ] {
        let directory = tempfile::tempdir().unwrap();
        let out = directory.path().join("out");
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("log.csv"), "kept\n").unwrap();
        let fifo = directory.path().join("sensors.fifo");
        assert!(Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        let mut child = Command::new(env!("CARGO_BIN_EXE_nav-sim"))
            .args(arguments)
            .current_dir(directory.path())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until the staged output exists (at most 60 s).
        let staged = |out: &Path| names(out).iter().any(|name| name.starts_with('.'));
        let start = std::time::Instant::now();
        while !staged(&out) {
            assert!(
                start.elapsed().as_secs() < 60,
                "{arguments:?}: nothing staged"
            );
            assert!(child.try_wait().unwrap().is_none(), "{arguments:?} ended");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let killed = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let output = child.wait_with_output().unwrap();
        let message = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(130), "{arguments:?}: {message}");
        assert!(message.contains("interrupted"), "{message}");
        assert_eq!(names(&out), ["log.csv"], "{arguments:?}");
        assert_eq!(
            std::fs::read_to_string(out.join("log.csv")).unwrap(),
            "kept\n"
        );
    }
}

/// A bad scenario value gets one message, naming the key, whichever subcommand reads the
/// scenario (a rotation vector of 1e300° once failed four ways in four subcommands).
#[test]
fn every_subcommand_refuses_a_bad_rotation_vector_with_the_same_message() {
    let directory = tempfile::tempdir().unwrap();
    let scenario = nav_sim::scenario::DEFAULT_SCENARIO_TOML.replacen(
        "rotation_vector_deg = [10.0, -20.0, 30.0]",
        "rotation_vector_deg = [1.0e300, -20.0, 30.0]",
        1,
    );
    std::fs::write(directory.path().join("bad.toml"), scenario).unwrap();
    std::fs::write(directory.path().join("log.csv"), "").unwrap();
    let expected = "nav-sim: scenario bad.toml: initial_attitude.rotation_vector_deg has a \
                    component of magnitude 1e300 deg, more than one turn (360 deg)";
    for arguments in [
        &["calibrate", "bad.toml"][..],
        &["monte-carlo", "bad.toml", "--runs", "1"],
        &["log", "bad.toml", "--out", "out.csv"],
        &["replay", "log.csv", "--scenario", "bad.toml"],
        &["observability", "bad.toml"],
        &["design", "bad.toml"],
        &["benefit", "bad.toml"],
        &["faults", "bad.toml"],
        &["gravity-omission", "bad.toml"],
    ] {
        let output = nav_sim(directory.path(), arguments);
        assert_eq!(output.status.code(), Some(1), "{arguments:?}: {output:?}");
        let message = stderr(&output);
        assert!(message.starts_with(expected), "{arguments:?}: {message}");
    }
}

/// `design --thrust-axes` names each axis once, none of them the main engine's.
#[test]
fn design_refuses_a_repeated_or_main_engine_thrust_axis() {
    let directory = tempfile::tempdir().unwrap();
    for axes in ["y,y", "x,z", "z,y,z"] {
        let output = nav_sim(directory.path(), &["design", "--thrust-axes", axes]);
        assert_eq!(output.status.code(), Some(1), "{axes}: {output:?}");
        let message = stderr(&output);
        assert!(
            message.contains("thrust axes must be distinct body axes other than the main"),
            "{axes}: {message}"
        );
    }
}

/// When no schedule fits, `design` says why the smallest one does not, naming the limit.
#[test]
fn design_names_the_limit_when_no_schedule_fits() {
    let directory = tempfile::tempdir().unwrap();
    let output = nav_sim(
        directory.path(),
        &["design", "--flight-time-s", "100", "--out", "designed.toml"],
    );
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    let message = stderr(&output);
    assert!(
        message.contains("the smallest one (1 round of 1-turn slews at 2.800 deg/s"),
        "{message}"
    );
    assert!(
        message.contains("does not fit the mission's coasts, the longest of which is 100.0 s"),
        "{message}"
    );
    assert!(!directory.path().join("designed.toml").exists());
}

/// `ground-constants` prints the built-in launch's constants in each format; the integrator
/// example's `ground_constants.rs` is its Rust output (up to formatting), so the example flies
/// the constants the command computes; a bad site value is refused naming its key.
#[test]
fn ground_constants_are_the_integrator_examples_and_bad_values_are_named() {
    let directory = tempfile::tempdir().unwrap();
    let rust = stdout(&nav_sim(
        directory.path(),
        &["ground-constants", "--format", "rust"],
    ));
    let example = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../examples/integrator/src/ground_constants.rs"),
    )
    .unwrap();
    let code = |text: &str| -> String {
        text.lines()
            .filter(|line| !line.starts_with("//!"))
            .flat_map(|line| line.chars().filter(|c| !c.is_whitespace()))
            .collect::<String>()
            // rustfmt adds a trailing comma after the last element of a broken array.
            .replace(",]", "]")
    };
    assert_eq!(
        code(&example),
        code(&rust),
        "regenerate: nav-sim ground-constants --format rust"
    );
    let toml = stdout(&nav_sim(directory.path(), &["ground-constants"]));
    assert!(
        toml.contains("[sensor_frames]\ngcrf_to_launch_inertial_wxyz = ["),
        "{toml}"
    );
    assert!(toml.contains("launch_epoch_gps_week = 2303\n"), "{toml}");
    let json = stdout(&nav_sim(
        directory.path(),
        &[
            "ground-constants",
            "--format",
            "json",
            "--epoch-utc",
            "2024-02-26T05:00:00Z",
        ],
    ));
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let seconds = value["sensor_frames"]["launch_epoch_gps_seconds_of_week"]
        .as_f64()
        .unwrap();
    assert!((seconds - 104_418.0).abs() < 1e-6, "{json}");
    let output = nav_sim(
        directory.path(),
        &["ground-constants", "--latitude-deg", "95"],
    );
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    assert!(
        stderr(&output).contains("--latitude-deg must be in [-90, 90] deg (got 95 deg)"),
        "{}",
        stderr(&output)
    );
}

/// The numeric flags of every subcommand, each as the arguments before its value.
const NUMERIC_FLAGS: &[&[&str]] = &[
    &["monte-carlo", "short.toml", "--runs"],
    &["monte-carlo", "short.toml", "--run"],
    &[
        "monte-carlo",
        "short.toml",
        "--runs",
        "2",
        "--out",
        "shards",
        "--shard",
    ],
    &["benefit", "short.toml", "--runs"],
    &["benefit", "short.toml", "--coast-s"],
    &["benefit", "short.toml", "--gnss-outage-s"],
    &["benefit", "short.toml", "--star-outage-s"],
    &["design", "short.toml", "--max-rate-deg-per-s"],
    &["design", "short.toml", "--max-lateral-accel-mps2"],
    &["design", "short.toml", "--lateral-delta-v-mps"],
    &["design", "short.toml", "--flight-time-s"],
    &["ground-constants", "--latitude-deg"],
    &["ground-constants", "--longitude-deg"],
    &["ground-constants", "--height-m"],
    &["ground-constants", "--azimuth-deg"],
    &["ground-constants", "--ut1-minus-utc-s"],
    &["ground-constants", "--polar-motion-x-arcsec"],
    &["ground-constants", "--polar-motion-y-arcsec"],
    &["gravity-omission", "short.toml", "--flight-degree"],
    &[
        "gravity-omission",
        "short.toml",
        "--flight-degree",
        "2",
        "--flight-order",
    ],
    &["gravity-omission", "short.toml", "--flight-refresh-s"],
    &[
        "gravity-omission",
        "short.toml",
        "--flight-latency-refreshes",
    ],
    &["gravity-omission", "short.toml", "--sample-s"],
    &["gravity-omission", "short.toml", "--max-lag-s"],
];

/// Runs `arguments` for at most `limit`: a run still going then is killed (it took the value
/// and is at work). Returns the exit code (`None` when killed or ended by a signal) and the
/// standard error.
fn run_for_at_most(
    directory: &Path,
    arguments: &[&str],
    limit: std::time::Duration,
) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nav-sim"))
        .args(arguments)
        .current_dir(directory)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() && start.elapsed() < limit {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let _ = child.kill();
    let output = child.wait_with_output().unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// No value of a numeric flag panics: each is taken (and the command at work or done),
    /// or refused with exit 1 or 2 and a message.
    #[test]
    fn no_numeric_flag_value_panics(
        flag in 0..NUMERIC_FLAGS.len(),
        value in proptest::prop_oneof![
            proptest::prelude::any::<f64>().prop_map(|v| format!("{v:e}")),
            proptest::prelude::any::<f64>().prop_map(|v| v.to_string()),
            proptest::prelude::any::<i64>().prop_map(|v| v.to_string()),
            proptest::prelude::any::<u64>().prop_map(|v| v.to_string()),
            proptest::sample::select(vec![
                "nan", "inf", "-inf", "1e400", "-0", "0", "", "1/0", "3/2", "0/1", "x",
                "18446744073709551616", "1e-400", "0x10",
            ])
            .prop_map(str::to_string),
        ],
    ) {
        let directory = tempfile::tempdir().unwrap();
        short_scenario(directory.path(), "short.toml", &[]);
        let mut arguments: Vec<&str> = NUMERIC_FLAGS[flag].to_vec();
        arguments.push(&value);
        let (code, message) =
            run_for_at_most(directory.path(), &arguments, std::time::Duration::from_secs(1));
        proptest::prop_assert!(!message.contains("panicked"), "{arguments:?}: {message}");
        proptest::prop_assert!(
            matches!(code, None | Some(0..=2)),
            "{arguments:?}: exit {code:?}: {message}"
        );
        if matches!(code, Some(1 | 2)) {
            proptest::prop_assert!(!message.trim().is_empty(), "{arguments:?}");
        }
    }
}

/// `--results DIR` writes the measured table, without the run time and the tables' borders,
/// as `DIR/<command>-<scenario>.md` under a header naming the command line, and a second run
/// writes the same bytes.
#[test]
fn results_are_written_under_the_command_that_measured_them() {
    let directory = tempfile::tempdir().unwrap();
    short_scenario(directory.path(), "short.toml", &[]);
    let arguments = ["calibrate", "short.toml", "--results", "out"];
    let output = nav_sim(directory.path(), &arguments);
    assert!(output.status.success(), "{}", stderr(&output));
    let file = directory.path().join("out/calibrate-short.md");
    let text = std::fs::read_to_string(&file).unwrap();
    let header = "<!-- generated by `nav-sim calibrate short.toml`; do not edit -->\n```text\n";
    assert!(text.starts_with(header), "{text}");
    assert!(text.ends_with("\n```\n"), "{text}");
    assert!(
        text.contains("parameter axes meet the paper's accuracy"),
        "{text}"
    );
    assert!(stdout(&output).contains(" frames ("), "{}", stdout(&output));
    assert!(
        !text.contains(" frames ("),
        "the run time is left out: {text}"
    );
    assert!(!text.contains('│') && !text.contains('┆'), "{text}");
    let again = nav_sim(directory.path(), &arguments);
    assert!(again.status.success(), "{}", stderr(&again));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), text);
}
