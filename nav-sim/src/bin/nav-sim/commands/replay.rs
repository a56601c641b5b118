//! `nav-sim replay`: a recorded sensor log flown through the flight software, its
//! per-second navigation and calibration output written as CSV, and on request every frame's
//! output record as telemetry packets and as the output-record CSV.

use std::io::Write;
use std::path::{Path, PathBuf};

use nav_fsw::telemetry_packets::{PacketEncoder, PacketKind, PacketRates, MAX_FRAME_PACKET_BYTES};
use nav_sim::logs::telemetry_packets::{full_frame, parse_rate, record_csv_header, record_csv_row};
use nav_sim::output::OutputFile;

use super::{inputs, load, Failure};

/// The arguments of `nav-sim replay`.
#[derive(clap::Args)]
pub struct Args {
    /// The sensor log (CSV, docs/guide/replay-format.md).
    log: PathBuf,
    /// Scenario TOML giving the flight software's setup (launch site, mounting, noise,
    /// initial solution); default: the built-in one.
    #[arg(long)]
    scenario: Option<PathBuf>,
    /// Output CSV (not the log or the scenario).
    #[arg(long, default_value = "replay-output.csv")]
    out: PathBuf,
    /// Also write every frame's telemetry packets (docs/reference/telemetry-packets.md) to
    /// this file, as the flight sends them.
    #[arg(long, value_name = "FILE")]
    packets: Option<PathBuf>,
    /// A packet kind's rate, KIND=FRAMES (e.g. `health=50`; repeatable); default: every kind
    /// every frame.
    #[arg(long = "packet-rate", value_name = "KIND=FRAMES", value_parser = parse_rate)]
    packet_rates: Vec<(PacketKind, u32)>,
    /// Also write every frame's output record as CSV (what `nav-sim telemetry decode` writes
    /// from the packets).
    #[arg(long, value_name = "FILE")]
    records: Option<PathBuf>,
}

/// Replays the log and writes the output CSV.
pub fn run(args: Args) -> Result<(), Failure> {
    let log = args.log.as_path();
    let scenario_path = args.scenario.as_deref();
    let mut input_paths = inputs(scenario_path);
    input_paths.push(log);
    let mut output = OutputFile::create_distinct(&args.out, &input_paths)?;
    let create = |path: &Option<PathBuf>| -> Result<Option<OutputFile>, Failure> {
        let file = path
            .as_deref()
            .map(|path: &Path| OutputFile::create_distinct(path, &input_paths));
        Ok(file.transpose()?)
    };
    let mut packets = create(&args.packets)?;
    let mut records = create(&args.records)?;
    let mut rates = PacketRates::EVERY_FRAME;
    for (kind, every_frames) in &args.packet_rates {
        rates.set(*kind, *every_frames)?;
    }
    let mut encoder = PacketEncoder::new(rates);
    let mut buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    if let Some(file) = records.as_mut() {
        writeln!(file, "{}", record_csv_header())?;
    }
    let mut sink = |words: &[u64; nav_fsw::replay::OUTPUT_WORDS]| -> Result<(), Failure> {
        if let Some(file) = packets.as_mut() {
            let length = encoder.encode_frame(words, &mut buffer)?;
            file.write_all(&buffer[..length])?;
        }
        if let Some(file) = records.as_mut() {
            writeln!(file, "{}", record_csv_row(&full_frame(words)))?;
        }
        Ok(())
    };
    let wanted = args.packets.is_some() || args.records.is_some();
    let scenario = load(scenario_path)?;
    let input = std::fs::File::open(log)
        .map_err(|error| format!("cannot open {}: {error}", log.display()))?;
    let summary = nav_sim::harness::log_replay::replay_with_records(
        input,
        &scenario,
        &mut output,
        wanted.then_some(&mut sink),
    )
    .map_err(|error| format!("replaying {}: {error}", log.display()))?;
    output.commit()?;
    println!("replayed {}: {}", log.display(), summary.text());
    println!("output {}", args.out.display());
    for (file, what) in [(packets, "telemetry packets"), (records, "output records")] {
        if let Some(file) = file {
            println!("{what} {}", file.commit()?.display());
        }
    }
    Ok(())
}
