//! `nav-sim telemetry decode`: a stream of the flight's telemetry packets
//! (docs/reference/telemetry-packets.md) decoded into the output-record CSV.

use std::path::PathBuf;

use nav_sim::logs::telemetry_packets::{decode_stream, write_record_csv};
use nav_sim::output::OutputFile;

use super::Failure;

/// The arguments of `nav-sim telemetry`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    action: Action,
}

#[derive(clap::Subcommand)]
enum Action {
    /// Decode a packet stream (every header, length, CRC and sequence count checked) into
    /// the output-record CSV, one row per frame, a word whose packet the frame did not carry
    /// left empty.
    Decode {
        /// The packet stream (the bytes as received, packets back to back).
        #[arg(long)]
        input: PathBuf,
        /// Output CSV (not the input).
        #[arg(long)]
        output: PathBuf,
    },
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<(), Failure> {
    let Action::Decode { input, output } = args.action;
    let mut file = OutputFile::create_distinct(&output, &[input.as_path()])?;
    let bytes = std::fs::read(&input)
        .map_err(|error| format!("cannot read {}: {error}", input.display()))?;
    let frames =
        decode_stream(&bytes).map_err(|error| format!("decoding {}: {error}", input.display()))?;
    let rows = write_record_csv(frames, &mut file)?;
    file.commit()?;
    println!("decoded {}: {rows} frames", input.display());
    println!("output {}", output.display());
    Ok(())
}
