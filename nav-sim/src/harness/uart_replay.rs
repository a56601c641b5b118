//! The host side of the replay over serial lines (`qemu/src/bin/uart_replay.rs`): a log split
//! into one byte stream per sensor, as each sensor sends it on its own UART; the QEMU run with
//! those streams on the MPS2's CMSDK UARTs; and the host's run of the very same bytes through
//! the same nav-fsw code ([`nav_fsw::stream_merge`]), so the two compare bit for bit,
//! corrupted lines included.
//!
//! Files in the run directory (QEMU `-serial pipe:` chardevs, `NAME.in` read by the UART,
//! `NAME.out` written by it): `ground` (UART0: setup and line lengths in; per-frame outputs
//! and the line counters out), `imu` (UART1), `star` (UART2), `gnss` (UART3), `telemetry`
//! (UART4: the frames' telemetry packets out, decoded by [`crate::logs::telemetry_packets`]
//! and compared with the host's output words).

use std::path::Path;

use nav_fsw::log_record::LogRecord;
use nav_fsw::replay::ReplaySetup;
use nav_fsw::stream_merge::{ArrivalMerge, LineSource, RecordedLine};
use nav_fsw::stream_ports::{RecordReader, StreamCounters};

use crate::harness::target_replay::{
    cost_statistics, first_difference, run_records_on_host, words_of, CostStatistics,
    FirstDifference, ReplayError, FRAME_WORDS,
};
use crate::logs::telemetry_packets::decode_stream;
use crate::scenario::Scenario;
use crate::setup::fsw::replay_setup_without_commands;
use nav_fsw::replay::{OUTPUT_FIELD_NAMES, OUTPUT_WORDS};
use nav_fsw::telemetry_packets::{PacketKind, PacketRates};

/// First word of the line counters after the last frame (`"NAVLINES"` little-endian).
pub const LINES_MAGIC: u64 = u64::from_le_bytes(*b"NAVLINES");
/// Counter words per line after [`LINES_MAGIC`]: records, resynchronisation bytes, wrong kind,
/// read errors.
pub const COUNTER_WORDS: usize = 4;
/// The chardev names of UART0..UART4.
pub const UART_FILES: [&str; 5] = ["ground", "imu", "star", "gnss", "telemetry"];

/// A log as its sensors send it: one byte stream per sensor line.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SensorLines {
    /// The IMU's bytes.
    pub imu: Vec<u8>,
    /// The star tracker's bytes.
    pub star: Vec<u8>,
    /// The GNSS receiver's bytes.
    pub gnss: Vec<u8>,
}

impl SensorLines {
    /// Each record of `records` on its sensor's line, in order.
    ///
    /// # Errors
    /// [`ReplayError::Log`] for a record that cannot be encoded.
    pub fn of_records(records: &[LogRecord]) -> Result<Self, ReplayError> {
        let mut lines = Self::default();
        for record in records {
            let bytes = record.encode().map_err(ReplayError::Log)?;
            let line = match record {
                LogRecord::Imu(_) => &mut lines.imu,
                LogRecord::Star(_) => &mut lines.star,
                LogRecord::Gnss(_) => &mut lines.gnss,
            };
            line.extend_from_slice(&bytes);
        }
        Ok(lines)
    }

    fn all(&self) -> [&[u8]; 3] {
        [&self.imu, &self.star, &self.gnss]
    }
}

/// What a replay over the lines produced: the frames' output words and what each line's
/// reader counted (IMU, star, GNSS).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinesOutput {
    /// Per frame the output record and its cost word.
    pub frame_words: Vec<u64>,
    /// The readers' counters, IMU, star, GNSS.
    pub counters: [StreamCounters; 3],
}

/// Runs `lines` through the flight software set up by `setup` on the host, exactly as the
/// UART firmware does (cost words 0).
///
/// # Errors
/// [`ReplayError::Input`] for a refused configuration or record.
pub fn run_lines_on_host(
    setup: &ReplaySetup,
    lines: &SensorLines,
) -> Result<LinesOutput, ReplayError> {
    let line = |bytes| LineSource(RecordReader::new(RecordedLine(bytes)));
    let mut merge = ArrivalMerge::new(line(&lines.imu), line(&lines.star), line(&lines.gnss));
    let records: Vec<LogRecord> = core::iter::from_fn(|| merge.next_record()).collect();
    let frame_words = run_records_on_host(setup, records)?;
    let (imu, star, gnss) = merge.sources();
    Ok(LinesOutput {
        frame_words,
        counters: [imu.counters(), star.counters(), gnss.counters()],
    })
}

/// Splits the UART firmware's ground-link output into frames and line counters.
///
/// # Errors
/// [`ReplayError::Input`] when the counters are missing or malformed.
pub fn parse_ground_output(bytes: &[u8]) -> Result<LinesOutput, ReplayError> {
    let words = words_of(bytes);
    let trailer = 1 + 3 * COUNTER_WORDS;
    let split = words
        .len()
        .checked_sub(trailer)
        .filter(|split| split % FRAME_WORDS == 0 && words.get(*split) == Some(&LINES_MAGIC))
        .ok_or_else(|| ReplayError::Input("ground output: no line counters at its end".into()))?;
    let counter = |line: usize, index: usize| {
        let word = words.get(split + 1 + line * COUNTER_WORDS + index).copied();
        u32::try_from(word.unwrap_or(0)).unwrap_or(u32::MAX)
    };
    let counters = [0, 1, 2].map(|line| StreamCounters {
        records: counter(line, 0),
        resync_bytes: counter(line, 1),
        wrong_kind: counter(line, 2),
        read_errors: counter(line, 3),
    });
    Ok(LinesOutput {
        frame_words: words.get(..split).unwrap_or(&[]).to_vec(),
        counters,
    })
}

/// What a replay over the UARTs measured against the host.
#[derive(Debug, Clone)]
pub struct UartReplayReport {
    /// Frames the target ran.
    pub frames: u64,
    /// Frame costs on the target by frame type.
    pub costs: [(&'static str, CostStatistics); 4],
    /// The target's output and line counters.
    pub target: LinesOutput,
    /// The host's output and line counters from the same bytes.
    pub host: LinesOutput,
    /// The first differing output word, if any.
    pub difference: Option<FirstDifference>,
    /// The target's telemetry packets decoded against the host's output: the first word
    /// that differs, is missing although its kind was due, or was sent although not due.
    pub packet_difference: Option<String>,
    /// Telemetry packets the target sent.
    pub packets: usize,
    /// QEMU's wall-clock time.
    pub qemu_wall_time: std::time::Duration,
}

impl UartReplayReport {
    /// Target and host agree on every output word and every line counter.
    pub fn bit_exact(&self) -> bool {
        self.difference.is_none()
            && self.packet_difference.is_none()
            && self.target.counters == self.host.counters
    }

    /// A short summary for the test log.
    pub fn text(&self) -> String {
        let [_, star, _] = self.target.counters;
        format!(
            "UART replay: {} frames, worst frame {} instructions, star line {} records / {} \
             resynchronisation bytes, {} telemetry packets, QEMU {:.1} s, host and target \
             (output words and decoded packets) {}\n",
            self.frames,
            self.costs[0].1.worst,
            star.records,
            star.resync_bytes,
            self.packets,
            self.qemu_wall_time.as_secs_f64(),
            if self.bit_exact() {
                "bit for bit equal"
            } else {
                "DIFFER"
            }
        )
    }
}

/// Writes `lines` and the setup of `scenario` into `directory`, runs the UART firmware `elf`
/// on QEMU there (`runner`: the project's `qemu/run.sh`, told the chardevs through
/// `QEMU_SERIAL`), runs the same bytes on the host and compares.
///
/// # Errors
/// [`ReplayError`] if a file cannot be written or read, the setup cannot be built, or QEMU
/// fails.
pub fn replay_lines_on_target(
    scenario: &Scenario,
    lines: &SensorLines,
    packet_rates: PacketRates,
    elf: &Path,
    runner: &Path,
    directory: &Path,
) -> Result<UartReplayReport, ReplayError> {
    std::fs::create_dir_all(directory)?;
    let directory = directory.canonicalize()?;
    let setup = replay_setup_without_commands(scenario)
        .map_err(crate::harness::flight::FlightError::from)?;
    let mut ground = Vec::new();
    for word in setup.to_words() {
        ground.extend_from_slice(&word.to_le_bytes());
    }
    for line in lines.all() {
        ground.extend_from_slice(&u64::try_from(line.len()).unwrap_or(u64::MAX).to_le_bytes());
    }
    for kind in PacketKind::ALL {
        ground.extend_from_slice(&u64::from(packet_rates.every_frames(kind)).to_le_bytes());
    }
    let contents = [ground.as_slice(), &lines.imu, &lines.star, &lines.gnss, &[]];
    let mut serial = Vec::new();
    for (name, bytes) in UART_FILES.iter().zip(contents) {
        std::fs::write(directory.join(format!("{name}.in")), bytes)?;
        std::fs::write(directory.join(format!("{name}.out")), [])?;
        serial.push(format!("-serial pipe:{}", directory.join(name).display()));
    }
    let started = std::time::Instant::now();
    let status = std::process::Command::new(runner.canonicalize()?)
        .arg(elf.canonicalize()?)
        .env("QEMU_SERIAL", serial.join(" "))
        .current_dir(&directory)
        .status()?;
    let qemu_wall_time = started.elapsed();
    if !status.success() {
        return Err(ReplayError::Input(format!(
            "UART replay firmware failed: {status}"
        )));
    }
    let target = parse_ground_output(&std::fs::read(directory.join("ground.out"))?)?;
    let host = run_lines_on_host(&setup, lines)?;
    let packet_stream = std::fs::read(directory.join("telemetry.out"))?;
    let (packets, packet_difference) =
        compare_packets(&packet_stream, packet_rates, &host.frame_words)?;
    Ok(UartReplayReport {
        frames: u64::try_from(target.frame_words.len() / FRAME_WORDS).unwrap_or(u64::MAX),
        costs: cost_statistics(&target.frame_words),
        difference: first_difference(&host.frame_words, &target.frame_words),
        packet_difference,
        packets,
        target,
        host,
        qemu_wall_time,
    })
}

/// The target's telemetry packet stream decoded and compared with the host's output words
/// (`host_words`: [`FRAME_WORDS`] per frame) at `rates`: every frame the packets name must be
/// the host's, each word present exactly when its kind was due, and equal to the host's.
/// Returns the number of packets and the first disagreement.
///
/// # Errors
/// [`ReplayError::Input`] for a stream the decoder refuses.
pub fn compare_packets(
    stream: &[u8],
    rates: PacketRates,
    host_words: &[u64],
) -> Result<(usize, Option<String>), ReplayError> {
    let frames = decode_stream(stream)
        .map_err(|error| ReplayError::Input(format!("telemetry packets: {error}")))?;
    let host: Vec<&[u64]> = host_words.chunks_exact(FRAME_WORDS).collect();
    let due_frames = host.iter().filter(|frame| {
        PacketKind::ALL
            .iter()
            .any(|kind| rates.due(*kind, frame[0]))
    });
    let mut packets = 0;
    let mut decoded = frames.iter();
    for host_frame in due_frames {
        let Some(frame) = decoded.next() else {
            return Ok((
                packets,
                Some(format!("no packets of frame {}", host_frame[0])),
            ));
        };
        for index in 0..OUTPUT_WORDS {
            let due = nav_fsw::telemetry_packets::PACKETS
                .iter()
                .find(|packet| {
                    packet
                        .words
                        .iter()
                        .any(|span| span.indices().contains(&index))
                })
                .is_none_or(|packet| rates.due(packet.kind, host_frame[0]));
            let expected = due.then_some(host_frame[index]);
            if frame[index] != expected {
                return Ok((
                    packets,
                    Some(format!(
                        "frame {}, word {}: packets {:?}, host {expected:?}",
                        host_frame[0], OUTPUT_FIELD_NAMES[index], frame[index]
                    )),
                ));
            }
        }
        packets += PacketKind::ALL
            .iter()
            .filter(|kind| rates.due(**kind, host_frame[0]))
            .count();
    }
    if decoded.next().is_some() {
        return Ok((
            packets,
            Some("packets of frames the host did not run".into()),
        ));
    }
    Ok((packets, None))
}
