//! How many times faster than real time a simulated flight runs on one core: each scenario
//! flown whole (truth, sensors, the flight software and the recorded samples, as `calibrate`
//! and every Monte Carlo run fly it) on this thread, its CPU time measured (`cpu-time`, so a
//! loaded machine's other work does not count), and the ratio of flight time to CPU time,
//! also relative to the first scenario's (the built-in J2 default flight unless given).
//!
//! `cargo run --release -p nav-sim --example flight_speed -- [--results DIR] [SCENARIO ...]`
//! (no scenario: the built-in default and the two vehicle-as-it-is flights). `--results DIR`
//! also writes the table to `DIR/flight-speed.md`, naming the processor it was measured on:
//! CPU times depend on the machine, so the file is a benchmark's, not checked by a test.

use std::path::{Path, PathBuf};

use cpu_time::ThreadTime;
use nav_sim::harness::flight::{fly, FlightOptions};
use nav_sim::output::results;
use nav_sim::Scenario;

/// The scenarios flown when none is given: the J2 default flight first (the reference).
const DEFAULT_SCENARIOS: [&str; 3] = [
    "",
    "nav-sim/scenarios/as_it_is.toml",
    "nav-sim/scenarios/upper_stage_as_it_is.toml",
];

/// One scenario's measurement.
struct Speed {
    label: String,
    flight_s: f64,
    cpu_s: f64,
}

impl Speed {
    fn times_real_time(&self) -> f64 {
        self.flight_s / self.cpu_s
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut arguments: Vec<String> = std::env::args().skip(1).collect();
    let results_directory = match arguments.iter().position(|a| a == "--results") {
        Some(at) if at + 1 < arguments.len() => {
            let directory = PathBuf::from(arguments.remove(at + 1));
            arguments.remove(at);
            Some(directory)
        }
        Some(_) => return Err("--results needs a directory".into()),
        None => None,
    };
    let scenarios: Vec<String> = if arguments.is_empty() {
        DEFAULT_SCENARIOS.iter().map(|s| s.to_string()).collect()
    } else {
        arguments
    };
    let mut speeds = Vec::new();
    for path in &scenarios {
        let speed = measure(path)?;
        eprintln!(
            "{}: {:.0} s of flight in {:.2} s of CPU",
            speed.label, speed.flight_s, speed.cpu_s
        );
        speeds.push(speed);
    }
    let table = table(&speeds);
    print!("{table}");
    if let Some(directory) = results_directory {
        // The build (release or the test profile's) is named in the file's first line.
        let command = format!(
            "nav-sim example flight_speed --results {} {}",
            directory.display(),
            scenarios.join(" ")
        );
        let body = format!("{}\n{table}", machine());
        let written = results::write(&directory, "flight-speed.md", command.trim(), &body)?;
        eprintln!("written {}", written.display());
    }
    Ok(())
}

/// Flies the scenario at `path` (the built-in default for an empty path) on this thread.
fn measure(path: &str) -> Result<Speed, Box<dyn std::error::Error>> {
    let (scenario, label) = if path.is_empty() {
        (
            Scenario::default_scenario()?,
            "<built-in default>".to_string(),
        )
    } else {
        let label = Path::new(path)
            .file_name()
            .map_or(path.to_string(), |name| name.to_string_lossy().into_owned());
        (Scenario::load(Path::new(path))?, label)
    };
    let options = FlightOptions {
        record_interval_s: 1.0,
    };
    let start = ThreadTime::now();
    let result = fly(&scenario, options, |_, _| {})?;
    let cpu_s = start.elapsed().as_secs_f64();
    let flight_s = result.frames as f64 * scenario.imu.frame_period_s();
    Ok(Speed {
        label,
        flight_s,
        cpu_s,
    })
}

/// The table: flight time, CPU time, times real time, and that against the first row's.
fn table(speeds: &[Speed]) -> String {
    let reference = speeds.first().map_or(f64::NAN, Speed::times_real_time);
    let mut text = format!(
        "{:<34} {:>10} {:>9} {:>15} {:>14}\n",
        "scenario", "flight s", "CPU s", "x real time", "/ first row"
    );
    for speed in speeds {
        text += &format!(
            "{:<34} {:>10.0} {:>9.2} {:>15.0} {:>14.2}\n",
            speed.label,
            speed.flight_s,
            speed.cpu_s,
            speed.times_real_time(),
            speed.times_real_time() / reference
        );
    }
    text
}

/// The processor the figures were measured on (Linux's `/proc/cpuinfo`), and the build.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|line| line.starts_with("model name"))
                .and_then(|line| line.split_once(':'))
                .map(|(_, name)| name.trim().to_string())
        })
        .unwrap_or_else(|| "an unknown processor".to_string());
    let build = if cfg!(debug_assertions) {
        "a build with debug assertions (the test profile's, optimised)"
    } else {
        "the release build"
    };
    format!("One core of {cpu}, {build}; CPU time of the flying thread.")
}
