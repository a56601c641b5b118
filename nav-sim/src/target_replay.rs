//! The replay files of the target firmware (`qemu/src/bin/replay.rs`) and the host's run of
//! the very same replay, so the two can be compared bit for bit.
//!
//! Input file (`replay-in.bin`): the scenario's [`ReplaySetup`] as [`SETUP_WORDS`]
//! little-endian u64 words, then the binary sensor log (`docs/replay-format.md`).
//! Output file (`replay-out.bin`): per frame, nav-fsw's [`OUTPUT_WORDS`] output words and one
//! word of frame cost (instructions on the target; 0 on the host).

use std::io::Write;

use nav_fsw::log_record::{self, LogRecord};
use nav_fsw::replay::{
    output_words, FrameAssembler, ReplaySetup, OUTPUT_FIELD_NAMES, OUTPUT_WORDS, SETUP_WORDS,
};
use nav_fsw::scheduler::NavigationComputer;

use crate::flight::{replay_setup, FlightError};
use crate::scenario::Scenario;
use crate::sensor_log;
use crate::simulation::Simulation;

/// Words per output frame: the record and the cost.
pub const FRAME_WORDS: usize = OUTPUT_WORDS + 1;

/// Why a replay could not be written, run or compared.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The scenario could not be flown.
    #[error(transparent)]
    Flight(#[from] FlightError),
    /// The simulation failed.
    #[error(transparent)]
    Simulation(#[from] crate::SimulationError),
    /// A record could not be encoded or decoded.
    #[error("replay log: {0}")]
    Log(log_record::LogRecordError),
    /// The input is malformed.
    #[error("replay input: {0}")]
    Input(String),
    /// I/O.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// Writes the replay input of the first `max_frames` frames of `scenario`; returns the number
/// of frames written.
///
/// # Errors
/// [`ReplayError`].
pub fn write_input<W: Write>(
    scenario: &Scenario,
    max_frames: u64,
    mut writer: W,
) -> Result<u64, ReplayError> {
    let setup = replay_setup(scenario)?;
    for word in setup.to_words() {
        writer.write_all(&word.to_le_bytes())?;
    }
    writer.write_all(&log_record::encode_header())?;
    let mut simulation = Simulation::new(scenario)?;
    let mut events = Vec::new();
    let mut frames = 0;
    while frames < max_frames && simulation.step(&mut events)?.is_some() {
        for event in events.drain(..) {
            let bytes = sensor_log::record_of(&event)
                .encode()
                .map_err(ReplayError::Log)?;
            writer.write_all(&bytes)?;
        }
        frames += 1;
    }
    writer.flush()?;
    Ok(frames)
}

fn words_of(bytes: &[u8]) -> Vec<u64> {
    bytes
        .chunks_exact(8)
        .map(|chunk| {
            let mut le = [0_u8; 8];
            le.copy_from_slice(chunk);
            u64::from_le_bytes(le)
        })
        .collect()
}

/// Runs a replay input on the host exactly as the firmware does; returns the output words
/// (cost words 0).
///
/// # Errors
/// [`ReplayError`] for a malformed input or a refused configuration.
pub fn run_on_host(input: &[u8]) -> Result<Vec<u64>, ReplayError> {
    let setup_bytes = input
        .get(..SETUP_WORDS * 8)
        .ok_or_else(|| ReplayError::Input("setup truncated".into()))?;
    let setup_words: [u64; SETUP_WORDS] = words_of(setup_bytes)
        .try_into()
        .map_err(|_| ReplayError::Input("setup size".into()))?;
    let setup = ReplaySetup::from_words(&setup_words)
        .map_err(|error| ReplayError::Input(format!("setup: {error:?}")))?;
    let log = input.get(SETUP_WORDS * 8..).unwrap_or(&[]);
    let records: Vec<LogRecord> =
        sensor_log::read_binary(log).map_err(|error| ReplayError::Input(error.to_string()))?;
    let mut computer = NavigationComputer::new(setup.config(), setup.initial)
        .map_err(|error| ReplayError::Input(format!("configuration: {error:?}")))?;
    let mut assembler = FrameAssembler::default();
    let mut output = Vec::new();
    let mut dropped = 0_u32;
    let mut run = |mut ports: nav_fsw::replay::FramePorts, output: &mut Vec<u64>| {
        let telemetry = ports.run(&mut computer);
        dropped = dropped.saturating_add(ports.dropped);
        output.extend_from_slice(&output_words(&telemetry, &computer, dropped));
        output.push(0);
    };
    for record in &records {
        if let Some(ports) = assembler.push(record) {
            run(ports, &mut output);
        }
    }
    if let Some(ports) = assembler.finish() {
        run(ports, &mut output);
    }
    Ok(output)
}

/// Decodes an output file's bytes into words.
pub fn output_file_words(bytes: &[u8]) -> Vec<u64> {
    words_of(bytes)
}

/// The first difference between two outputs, ignoring the cost words.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FirstDifference {
    /// Frame index (0-based).
    pub frame: usize,
    /// Name of the differing field ("frame count" if the lengths differ).
    pub field: &'static str,
    /// Host word.
    pub host: Option<u64>,
    /// Target word.
    pub target: Option<u64>,
}

/// Compares two outputs word by word (cost words excluded).
pub fn first_difference(host: &[u64], target: &[u64]) -> Option<FirstDifference> {
    for (frame, (h, t)) in host
        .chunks(FRAME_WORDS)
        .zip(target.chunks(FRAME_WORDS))
        .enumerate()
    {
        for (index, name) in OUTPUT_FIELD_NAMES.iter().enumerate() {
            let (hw, tw) = (h.get(index), t.get(index));
            if hw != tw {
                return Some(FirstDifference {
                    frame,
                    field: name,
                    host: hw.copied(),
                    target: tw.copied(),
                });
            }
        }
    }
    if host.len() != target.len() {
        return Some(FirstDifference {
            frame: host.len().min(target.len()) / FRAME_WORDS,
            field: "frame count",
            host: Some(u64::try_from(host.len() / FRAME_WORDS).unwrap_or(u64::MAX)),
            target: Some(u64::try_from(target.len() / FRAME_WORDS).unwrap_or(u64::MAX)),
        });
    }
    None
}

/// Frame cost statistics of one frame type (instructions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CostStatistics {
    /// Frames of this type.
    pub frames: usize,
    /// Cheapest frame.
    pub minimum: u64,
    /// Median frame.
    pub median: u64,
    /// Worst frame.
    pub worst: u64,
}

/// Costs of a target output by frame type: all, IMU only, star update, GNSS update. (The
/// scheduler fuses at most one measurement per frame, so no frame has both.)
pub fn cost_statistics(target: &[u64]) -> [(&'static str, CostStatistics); 4] {
    let fusion_index = OUTPUT_FIELD_NAMES
        .iter()
        .position(|name| *name == "fusion")
        .unwrap_or(0);
    let mut groups: [(&'static str, Vec<u64>); 4] = [
        ("all frames", Vec::new()),
        ("IMU only", Vec::new()),
        ("with star update", Vec::new()),
        ("with GNSS update", Vec::new()),
    ];
    for frame in target.chunks_exact(FRAME_WORDS) {
        let cost = frame.last().copied().unwrap_or(0);
        let group = match frame.get(fusion_index).copied().unwrap_or(0) {
            1 | 2 => 2,
            3 | 4 => 3,
            _ => 1,
        };
        groups[0].1.push(cost);
        groups[group].1.push(cost);
    }
    groups.map(|(name, mut costs)| {
        costs.sort_unstable();
        let statistics = CostStatistics {
            frames: costs.len(),
            minimum: costs.first().copied().unwrap_or(0),
            median: costs.get(costs.len() / 2).copied().unwrap_or(0),
            worst: costs.last().copied().unwrap_or(0),
        };
        (name, statistics)
    })
}
