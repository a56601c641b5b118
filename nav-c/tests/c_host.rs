//! The C programs of examples/c-host, built with the system's C compiler (C99, `-Wall -Wextra
//! -Werror -pedantic`) against this crate's static library: `return_codes.c` provokes every
//! return code from C, and `main.c` replays nav-sim scenarios through the C interface, frame
//! for frame bit for bit with the Rust host replay (`nav_sim::harness::target_replay`).

use std::path::{Path, PathBuf};
use std::process::Command;

use nav_sim::harness::target_replay::{first_difference, output_file_words, run_on_host};
use nav_sim::Scenario;

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The static library cargo built for this test: `libnav_c-*.a` beside the test binary (the
/// lib target is built once, with all its crate types; the newest is this build's).
fn static_library() -> PathBuf {
    let deps = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    let mut libraries: Vec<(std::time::SystemTime, PathBuf)> = std::fs::read_dir(&deps)
        .unwrap()
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            let name = path.file_name()?.to_str()?;
            (name.starts_with("libnav_c-") && name.ends_with(".a"))
                .then(|| Some((path.metadata().ok()?.modified().ok()?, path)))?
        })
        .collect();
    libraries.sort();
    libraries
        .pop()
        .unwrap_or_else(|| panic!("no libnav_c-*.a in {}", deps.display()))
        .1
}

/// Builds `source` (examples/c-host) into `program` in the test's directory.
fn build(source: &str, directory: &Path) -> PathBuf {
    let program = directory.join(source.trim_end_matches(".c"));
    let output = Command::new("cc")
        .args([
            "-std=c99",
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
        ])
        .arg("-I")
        .arg(repository().join("nav-c/include"))
        .arg(repository().join("examples/c-host").join(source))
        .arg(static_library())
        // What std's runtime in a hosted static library needs (`rustc --print
        // native-static-libs`).
        .args([
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
        ])
        .arg("-o")
        .arg(&program)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "cc {source}:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    program
}

fn scratch(name: &str) -> PathBuf {
    let directory = repository().join("target/c-host").join(name);
    std::fs::create_dir_all(&directory).unwrap();
    directory
}

/// The lines `return_codes.c` must print: every return code, with the argument, the rule,
/// the parameters and the input it names.
const EXPECTED_CASES: &str = "\
sizes computer=fits replay=fits
frame_before_configure status=5 argument=1 field=0 param=- companion=- input=0 index=0
configure status=0 argument=0 field=0 param=- companion=- input=0 index=0
frame status=0 argument=0 field=0 param=- companion=- input=0 index=0
frame telemetry frame=1 imu_missing=0
frame_null_inputs status=1 argument=5 field=0 param=- companion=- input=0 index=0
frame_null_telemetry status=1 argument=6 field=0 param=- companion=- input=0 index=0
frame_null_memory status=1 argument=1 field=0 param=- companion=- input=0 index=0
frame_misaligned status=2 argument=1 field=0 param=- companion=- input=0 index=0
frame_imu_present_2 status=6 argument=5 field=0 param=- companion=- input=1 index=0
frame_too_many_stars status=6 argument=5 field=0 param=- companion=- input=2 index=0
frame_too_many_fixes status=6 argument=5 field=0 param=- companion=- input=3 index=0
frame_velocity_present_7 status=6 argument=5 field=0 param=- companion=- input=4 index=1
after refused frames frame=2 imu_missing=0
configure_null_memory status=1 argument=1 field=0 param=- companion=- input=0 index=0
configure_null_config status=1 argument=2 field=0 param=- companion=- input=0 index=0
configure_null_ground status=1 argument=3 field=0 param=- companion=- input=0 index=0
configure_null_initial status=1 argument=4 field=0 param=- companion=- input=0 index=0
configure_misaligned status=2 argument=1 field=0 param=- companion=- input=0 index=0
configure_too_small status=3 argument=1 field=0 param=- companion=- input=0 index=0
configure_gnss_noise_negative status=4 argument=2 field=1 param=gnss.noise_m companion=- input=0 index=0
frame_after_refused_configure status=5 argument=1 field=0 param=- companion=- input=0 index=0
configure_order_not_integer status=4 argument=2 field=1 param=filter.discretisation_order companion=- input=0 index=0
configure_companion_off status=4 argument=2 field=2 param=filter.gnss_error.correlation_time_s companion=filter.gnss_error.sigma_m input=0 index=0
configure_earth_axis status=4 argument=3 field=3 param=- companion=- input=0 index=0
configure_epoch status=4 argument=3 field=4 param=- companion=- input=0 index=0
configure_null_fault status=0
replay_push_before_start status=5 argument=1 field=0 param=- companion=- input=0 index=0
replay_start_zeros status=7 argument=7 field=0 param=- companion=- input=0 index=0
replay_start_short status=7 argument=7 field=0 param=- companion=- input=0 index=0
param_path none=null first=filter.mode last=strapdown.gravity.j2_enabled beyond=null
";

/// examples/c-host/ground_constants.h is `nav-sim ground-constants --format c` of the
/// built-in scenario, the launch `return_codes.c` configures.
#[test]
fn the_examples_ground_constants_are_the_commands_output() {
    let scenario = Scenario::default_scenario().unwrap();
    let constants = nav_sim::setup::ground::FlightGroundConstants::of(&scenario).unwrap();
    let path = repository().join("examples/c-host/ground_constants.h");
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert_eq!(
        committed,
        constants.to_c(),
        "run nav-sim ground-constants --format c > examples/c-host/ground_constants.h"
    );
}

#[test]
fn every_return_code_is_provoked_from_c() {
    let directory = scratch("return-codes");
    let program = build("return_codes.c", &directory);
    let output = Command::new(&program).output().unwrap();
    assert!(output.status.success());
    let printed = String::from_utf8(output.stdout).unwrap();
    for (line, (got, expected)) in printed.lines().zip(EXPECTED_CASES.lines()).enumerate() {
        assert_eq!(got, expected, "line {}", line + 1);
    }
    assert_eq!(printed.lines().count(), EXPECTED_CASES.lines().count());
    // Every status of the header is among them.
    for status in 0..=7 {
        assert!(
            printed.contains(&format!(" status={status} ")),
            "no case returns status {status}"
        );
    }
}

/// Replays `seconds` of `scenario` through the C example and the Rust host replay and
/// compares the outputs word for word.
fn replay_in_c_equals_rust(scenario: &Scenario, seconds: f64, name: &str) {
    let directory = scratch(name);
    let program = build("main.c", &directory);
    let input_path = directory.join("replay-in.bin");
    let output_path = directory.join("replay-out.bin");
    let frames = nav_sim::scenario::frames_in(seconds, scenario.imu.frame_period_s());
    let file = std::io::BufWriter::new(std::fs::File::create(&input_path).unwrap());
    nav_sim::harness::target_replay::write_input(scenario, frames, file).unwrap();
    let output = Command::new(&program)
        .arg(&input_path)
        .arg(&output_path)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let c_words = output_file_words(&std::fs::read(&output_path).unwrap());
    let rust_words = run_on_host(&std::fs::read(&input_path).unwrap()).unwrap();
    let record_words = nav_c::NAV_OUTPUT_WORDS + 1;
    assert_eq!(
        c_words.len(),
        usize::try_from(frames).unwrap() * record_words
    );
    assert_eq!(first_difference(&rust_words, &c_words), None);
    assert_eq!(c_words, rust_words);
    println!("{name}: {}", String::from_utf8_lossy(&output.stdout));
}

#[test]
fn the_c_example_replays_the_default_scenario_as_the_rust_replay() {
    let scenario = Scenario::default_scenario().unwrap();
    replay_in_c_equals_rust(&scenario, 30.0, "default");
}

#[test]
fn the_c_example_replays_the_realistic_sensor_scenario_as_the_rust_replay() {
    let path = repository().join("nav-sim/scenarios/realistic_sensors.toml");
    let scenario = Scenario::load(&path).unwrap();
    replay_in_c_equals_rust(&scenario, 30.0, "realistic");
}
