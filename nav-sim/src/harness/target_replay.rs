//! The replay files of the target firmware (`qemu/src/bin/replay.rs`) and the host's run of
//! the very same replay, so the two can be compared bit for bit.
//!
//! Input file (`replay-in.bin`): the scenario's [`ReplaySetup`] as [`SETUP_WORDS`]
//! little-endian u64 words, then the binary sensor log (`docs/guide/replay-format.md`).
//! Output file (`replay-out.bin`): per frame, nav-fsw's [`OUTPUT_WORDS`] output words and one
//! word of frame cost (instructions on the target; 0 on the host).

use std::io::Write;

use nav_fsw::log_record::{self, LogRecord};
use nav_fsw::replay::{
    output_words, FrameAssembler, ReplaySetup, OUTPUT_FIELD_NAMES, OUTPUT_WORDS, SETUP_WORDS,
};
use nav_fsw::scheduler::NavigationComputer;

use crate::harness::flight::FlightError;
use crate::logs::sensor_log;
use crate::logs::star_heads::FlightStarHeads;
use crate::scenario::Scenario;
use crate::setup::fsw::replay_setup_without_commands;
use crate::world::simulation::Simulation;

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

/// Writes the replay input of the first `max_frames` frames of `scenario`, with the events
/// the flight software takes ([`FlightStarHeads`]); returns the number of frames written and
/// the number of star measurements of the additional heads held back.
///
/// # Errors
/// [`ReplayError`].
pub fn write_input<W: Write>(
    scenario: &Scenario,
    max_frames: u64,
    mut writer: W,
) -> Result<(u64, u64), ReplayError> {
    write_input_header(scenario, &mut writer)?;
    let mut simulation = Simulation::new(scenario)?;
    let mut events = Vec::new();
    let mut star_heads = FlightStarHeads::for_scenario(scenario);
    let mut frames = 0;
    while frames < max_frames && simulation.step(&mut events)?.is_some() {
        for event in events
            .drain(..)
            .filter(|event| star_heads.hands_over(event))
        {
            let bytes = sensor_log::record_of(&event)
                .encode()
                .map_err(ReplayError::Log)?;
            writer.write_all(&bytes)?;
        }
        frames += 1;
    }
    writer.flush()?;
    Ok((frames, star_heads.withheld()))
}

/// The start of a replay input: the setup words of `scenario`, then the binary log header.
fn write_input_header<W: Write>(scenario: &Scenario, writer: &mut W) -> Result<(), ReplayError> {
    for word in replay_setup_without_commands(scenario)
        .map_err(FlightError::from)?
        .to_words()
    {
        writer.write_all(&word.to_le_bytes())?;
    }
    writer.write_all(&log_record::encode_header())?;
    Ok(())
}

/// The replay input of `records` (a recorded or edited log) with the flight software set up
/// by `scenario`: what [`run_on_host`] and the firmware read.
///
/// # Errors
/// [`ReplayError`] if the setup cannot be built or a record cannot be encoded.
pub fn records_input(scenario: &Scenario, records: &[LogRecord]) -> Result<Vec<u8>, ReplayError> {
    let mut input = Vec::new();
    write_input_header(scenario, &mut input)?;
    for record in records {
        input.extend_from_slice(&record.encode().map_err(ReplayError::Log)?);
    }
    Ok(input)
}

pub(crate) fn words_of(bytes: &[u8]) -> Vec<u64> {
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
        .map_err(|error| ReplayError::Input(format!("setup: {error}")))?;
    let log = input.get(SETUP_WORDS * 8..).unwrap_or(&[]);
    let records: Vec<LogRecord> =
        sensor_log::read_binary(log).map_err(|error| ReplayError::Input(error.to_string()))?;
    run_records_on_host(&setup, records)
}

/// Runs `records` (delivery order) through the flight software set up by `setup`, record by
/// record and frame by frame in the firmware's order, so the assembler's counts match too;
/// returns the output words (cost words 0).
///
/// # Errors
/// [`ReplayError::Input`] for a refused configuration or record.
pub fn run_records_on_host(
    setup: &ReplaySetup,
    records: impl IntoIterator<Item = LogRecord>,
) -> Result<Vec<u64>, ReplayError> {
    let mut computer = NavigationComputer::new(setup.config(), setup.initial)
        .map_err(|error| ReplayError::Input(format!("configuration: {error}")))?;
    let mut assembler = FrameAssembler::new(setup.frame_grid())
        .map_err(|error| ReplayError::Input(format!("frame grid: {error}")))?;
    let mut output = Vec::new();
    let mut run_ready = |assembler: &mut FrameAssembler, output: &mut Vec<u64>| {
        while let Some(mut ports) = assembler.next_frame() {
            let telemetry = ports.run(&mut computer);
            output.extend_from_slice(&output_words(&telemetry, &computer, &assembler.counts()));
            output.push(0);
        }
    };
    for (index, record) in records.into_iter().enumerate() {
        assembler
            .push(&record)
            .map_err(|error| ReplayError::Input(format!("record {index}: {error}")))?;
        run_ready(&mut assembler, &mut output);
    }
    assembler.finish();
    run_ready(&mut assembler, &mut output);
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
        ("with GNSS update", Vec::new()), // position or velocity
    ];
    for frame in target.chunks_exact(FRAME_WORDS) {
        let cost = frame.last().copied().unwrap_or(0);
        let group = match frame.get(fusion_index).copied().unwrap_or(0) {
            1 | 2 => 2,
            3..=6 => 3,
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

/// Static memory of a firmware image, from its ELF section headers (bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ImageMemory {
    /// Code and read-only data in flash: vector table, `.text`, `.rodata` and the initial
    /// values of `.data` (copied to RAM at reset).
    pub flash_bytes: u64,
    /// Static RAM: `.data`, `.bss` and `.uninit` (the stack lives above it).
    pub static_ram_bytes: u64,
}

/// Reads the static memory figures of an ELF image.
///
/// # Errors
/// [`ReplayError::Input`] if the file is not an ELF object.
pub fn image_memory(elf: &[u8]) -> Result<ImageMemory, ReplayError> {
    use object::{Object, ObjectSection, SectionKind};
    let file =
        object::File::parse(elf).map_err(|error| ReplayError::Input(format!("ELF: {error}")))?;
    let mut memory = ImageMemory::default();
    for section in file.sections() {
        match section.kind() {
            SectionKind::Text | SectionKind::ReadOnlyData | SectionKind::ReadOnlyString => {
                memory.flash_bytes += section.size();
            }
            SectionKind::Data => {
                memory.flash_bytes += section.size();
                memory.static_ram_bytes += section.size();
            }
            SectionKind::UninitializedData => memory.static_ram_bytes += section.size(),
            _ => {}
        }
    }
    Ok(memory)
}

/// Stack use measured by the firmware (`replay-stack.bin`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StackUsage {
    /// Deepest stack use of the frame loop, from the top of the stack (bytes): `main`'s frame
    /// plus the deepest call of the flight path over the whole replay.
    pub high_water_bytes: u64,
    /// Size of the stack region (bytes): RAM above the static data.
    pub region_bytes: u64,
    /// Deepest stack use during start-up (reading the setup, configuration checks, building
    /// the computer in its static slot).
    pub start_up_bytes: u64,
}

/// Stack budget of the flight software's frame loop (bytes): the replay fails if the painted
/// stack shows a deeper use. 16 KiB: about 1.6 times the measured 10,200 bytes of the replay
/// firmware on the realistic-sensor scenario (main's frame plus the deepest flight-path
/// call). Start-up runs once, before the frames, and has its own budget
/// ([`START_UP_STACK_BUDGET_BYTES`]).
pub const STACK_BUDGET_BYTES: u64 = 16 * 1024;

/// Stack budget of start-up (bytes): the computer is built in place in its static slot
/// (`NavigationComputer::init_in_place`, the filter by `ErrorStateFilter::init_in_place`), so
/// start-up needs only the construction's small parts (about 2.3 kB measured).
pub const START_UP_STACK_BUDGET_BYTES: u64 = 4 * 1024;

/// Everything one target replay measured.
#[derive(Debug, Clone, PartialEq)]
pub struct TargetReplayReport {
    /// Frames replayed.
    pub frames: u64,
    /// Replayed scenario time (s).
    pub seconds: f64,
    /// Cost statistics by frame type (instructions).
    pub costs: [(&'static str, CostStatistics); 4],
    /// Stack use.
    pub stack: StackUsage,
    /// Static memory of the image.
    pub memory: ImageMemory,
    /// Size of the firmware's `NavigationComputer` (bytes): the memory of the blocks its
    /// build carries; `None` from a firmware that does not report it (the C firmware).
    pub computer_bytes: Option<u64>,
    /// QEMU wall-clock time.
    pub qemu_wall_time: std::time::Duration,
    /// The first host/target difference, if any.
    pub difference: Option<FirstDifference>,
    /// The host's output words ([`FRAME_WORDS`] per frame, cost words 0).
    pub host_output: Vec<u64>,
    /// Star measurements of the additional star-tracker heads not in the replay input (the
    /// flight software takes head 0, and head 1 when the scenario has it: [`FlightStarHeads`]).
    pub withheld_star_measurements: u64,
}

impl TargetReplayReport {
    /// The report as text (what the test command and `nav-sim target-bench` print).
    pub fn text(&self) -> String {
        format!(
            "{}QEMU wall time {:.1?}\n",
            self.measured_text(),
            self.qemu_wall_time
        )
    }

    /// [`Self::text`] without the QEMU wall time: only what `-icount` makes deterministic,
    /// as a results file holds it.
    pub fn measured_text(&self) -> String {
        let mut text = match &self.difference {
            None => format!(
                "Replay of the scenario's first {} frames ({:.0} s): host and target \
                 outputs identical bit for bit ({} words per frame).\n",
                self.frames,
                self.seconds,
                FRAME_WORDS - 1
            ),
            Some(difference) => format!(
                "Replay of {} frames: host and target DIFFER, first at {difference:?}\n",
                self.frames
            ),
        };
        if self.withheld_star_measurements > 0 {
            text += &format!(
                "Star measurements of star-tracker heads the flight software is not told of, \
                 not replayed: {}\n",
                self.withheld_star_measurements
            );
        }
        text += "Target cost per frame (instructions, QEMU -icount shift=0; budget 2,000,000 = 2 ms):\n";
        for (name, statistics) in &self.costs {
            text += &format!(
                "  {name:<18} frames {:>7}  min {:>9}  median {:>9}  worst {:>9}\n",
                statistics.frames, statistics.minimum, statistics.median, statistics.worst
            );
        }
        text += &format!(
            "Stack high-water mark of the frame loop {} bytes (budget {} bytes; start-up {} bytes; stack region {} bytes)\n\
             Image: flash {} bytes, static RAM {} bytes\n",
            self.stack.high_water_bytes,
            STACK_BUDGET_BYTES,
            self.stack.start_up_bytes,
            self.stack.region_bytes,
            self.memory.flash_bytes,
            self.memory.static_ram_bytes,
        );
        if let Some(bytes) = self.computer_bytes {
            text += &format!("NavigationComputer {bytes} bytes (in static RAM)\n");
        }
        text
    }
}

/// Writes the replay input of the first `seconds` of `scenario` into `directory`, runs the
/// firmware `elf` on QEMU there (`runner`: the project's `qemu/run.sh`), runs the same input
/// on the host and compares every output word; returns what was measured (a difference is
/// reported in the result, not as an error).
///
/// # Errors
/// [`ReplayError`] if a file cannot be written or read, or QEMU fails.
pub fn replay_on_target(
    scenario: &Scenario,
    seconds: u64,
    elf: &std::path::Path,
    runner: &std::path::Path,
    directory: &std::path::Path,
) -> Result<TargetReplayReport, ReplayError> {
    std::fs::create_dir_all(directory)?;
    let period_s = scenario.imu.frame_period_s();
    // Seconds of flight are far below 2⁵³: exact in f64.
    let frames = crate::scenario::frames_in(seconds as f64, period_s);
    let input_path = directory.join("replay-in.bin");
    let (_, withheld_star_measurements) = write_input(
        scenario,
        frames,
        std::io::BufWriter::new(std::fs::File::create(&input_path)?),
    )?;
    let report = run_and_compare(&input_path, period_s, elf, runner, directory)?;
    Ok(TargetReplayReport {
        withheld_star_measurements,
        ..report
    })
}

/// As [`replay_on_target`], for a log given as records (a recorded or edited log) with the
/// flight software set up by `scenario`.
///
/// # Errors
/// As [`replay_on_target`].
pub fn replay_records_on_target(
    scenario: &Scenario,
    records: &[LogRecord],
    elf: &std::path::Path,
    runner: &std::path::Path,
    directory: &std::path::Path,
) -> Result<TargetReplayReport, ReplayError> {
    std::fs::create_dir_all(directory)?;
    let input_path = directory.join("replay-in.bin");
    std::fs::write(&input_path, records_input(scenario, records)?)?;
    let period_s = scenario.imu.frame_period_s();
    run_and_compare(&input_path, period_s, elf, runner, directory)
}

/// Runs the replay input at `input_path` on QEMU and on the host and compares the outputs.
fn run_and_compare(
    input_path: &std::path::Path,
    period_s: f64,
    elf: &std::path::Path,
    runner: &std::path::Path,
    directory: &std::path::Path,
) -> Result<TargetReplayReport, ReplayError> {
    let runner = runner.canonicalize()?;
    let started = std::time::Instant::now();
    let status = std::process::Command::new(runner)
        .arg(elf.canonicalize()?)
        .current_dir(directory)
        .status()?;
    let qemu_wall_time = started.elapsed();
    if !status.success() {
        return Err(ReplayError::Input(format!(
            "firmware replay failed: {status}"
        )));
    }
    let target = output_file_words(&std::fs::read(directory.join("replay-out.bin"))?);
    let host = run_on_host(&std::fs::read(input_path)?)?;
    let stack_words = words_of(&std::fs::read(directory.join("replay-stack.bin"))?);
    // Three words from the C firmware, a fourth (the computer's size) from the Rust one.
    let (stack, computer_bytes) = match stack_words.as_slice() {
        [high_water_bytes, region_bytes, start_up_bytes, computer @ ..] if computer.len() <= 1 => (
            StackUsage {
                high_water_bytes: *high_water_bytes,
                region_bytes: *region_bytes,
                start_up_bytes: *start_up_bytes,
            },
            computer.first().copied(),
        ),
        _ => {
            return Err(ReplayError::Input(
                "replay-stack.bin: expected three or four words".into(),
            ))
        }
    };
    let frames = u64::try_from(target.len() / FRAME_WORDS).unwrap_or(u64::MAX);
    Ok(TargetReplayReport {
        frames,
        // Frame counts are far below 2⁵³: exact in f64.
        seconds: frames as f64 * period_s,
        costs: cost_statistics(&target),
        stack,
        memory: image_memory(&std::fs::read(elf)?)?,
        computer_bytes,
        qemu_wall_time,
        difference: first_difference(&host, &target),
        host_output: host,
        withheld_star_measurements: 0,
    })
}
