//! `nav-sim replay`: a recorded sensor log (CSV, `docs/replay-format.md`) fed through the
//! flight software frame by frame (nav-fsw's `FrameAssembler`, the same one the QEMU replay
//! firmware uses), with the per-second navigation and calibration output written as CSV.

use std::io::{Read, Write};

use nav_fsw::replay::FrameAssembler;
use nav_fsw::scheduler::NavigationComputer;

use crate::flight;
use crate::sensor_log::SensorLogReader;
use crate::Scenario;

/// What a replay did.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplaySummary {
    /// Frames run.
    pub frames: u64,
    /// The flight software's health counters at the end.
    pub health: nav_fsw::health::HealthCounters,
}

/// A replay failure.
pub type ReplayFailure = Box<dyn std::error::Error>;

/// Replays `log` through the flight software set up by `scenario` and writes the output CSV
/// to `output`.
///
/// # Errors
/// A log or configuration error, or an I/O error of `output`.
pub fn replay<R: Read, W: Write>(
    log: R,
    scenario: &Scenario,
    output: W,
) -> Result<ReplaySummary, ReplayFailure> {
    let setup = flight::replay_setup(scenario)?;
    let mut computer = NavigationComputer::new(setup.config(), setup.initial)
        .map_err(|error| format!("flight software configuration refused: {error:?}"))?;
    let reader = SensorLogReader::new(log)?;
    let mut output = std::io::BufWriter::new(output);
    writeln!(
        output,
        "time_s,position_x_m,position_y_m,position_z_m,velocity_x_mps,velocity_y_mps,velocity_z_mps,\
         gyro_bias_x,gyro_bias_y,gyro_bias_z,accel_bias_x,accel_bias_y,accel_bias_z,\
         installation_x,installation_y,installation_z,gyro_sf_x,gyro_sf_y,gyro_sf_z,\
         accel_sf_x,accel_sf_y,accel_sf_z"
    )?;
    let mut assembler = FrameAssembler::default();
    let mut frames = 0_u64;
    let mut run = |ports: Option<nav_fsw::replay::FramePorts>,
                   output: &mut dyn Write|
     -> Result<(), ReplayFailure> {
        let Some(mut ports) = ports else {
            return Ok(());
        };
        let telemetry = ports.run(&mut computer);
        frames += 1;
        if frames % 500 == 0 {
            let mut line = format!("{}", telemetry.time_s);
            for value in telemetry.position_m.iter().chain(&telemetry.velocity_mps) {
                line += &format!(",{value}");
            }
            for (_, entry) in computer.calibration_table().entries() {
                for value in entry.value {
                    line += &format!(",{value}");
                }
            }
            writeln!(output, "{line}")?;
        }
        Ok(())
    };
    for record in reader {
        let ports = assembler.push(&record?);
        run(ports, &mut output)?;
    }
    run(assembler.finish(), &mut output)?;
    output.flush()?;
    Ok(ReplaySummary {
        frames,
        health: *computer.health(),
    })
}
