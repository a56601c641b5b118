//! `nav-sim target-bench`: the scenario's first seconds replayed on the Cortex-M7 firmware
//! under QEMU and on the host, compared bit for bit, with the per-frame cost report.

use std::io::Write as _;
use std::path::PathBuf;

use nav_sim::output::OutputFile;

use super::{load, Failure, ResultsArg};

/// The arguments of `nav-sim target-bench`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML (default: the built-in one).
    scenario: Option<PathBuf>,
    /// The replay firmware ELF (qemu/target/thumbv7em-none-eabihf/release/replay).
    #[arg(long)]
    elf: PathBuf,
    /// Scenario seconds to replay (500 frames each).
    #[arg(long, default_value_t = 60)]
    seconds: u64,
    /// QEMU runner script.
    #[arg(long, default_value = "qemu/run.sh")]
    runner: PathBuf,
    /// Working directory for the replay files; the report is written there too.
    #[arg(long, default_value = "target/qemu/bench")]
    out: PathBuf,
    #[command(flatten)]
    results: ResultsArg,
}

/// Replays on the target and the host, prints and writes the report, and fails if the two
/// differ.
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario = load(args.scenario.as_deref())?;
    let out = args.out.as_path();
    let report = nav_sim::harness::target_replay::replay_on_target(
        &scenario,
        args.seconds,
        &args.elf,
        &args.runner,
        out,
    )?;
    let text = report.text();
    print!("{text}");
    let path = out.join("target-bench-report.txt");
    let mut file = OutputFile::create(&path)?;
    file.write_all(text.as_bytes())?;
    file.commit()?;
    println!("report written to {}", path.display());
    args.results.write(
        "target-bench",
        args.scenario.as_deref(),
        &report.measured_text(),
    )?;
    if let Some(difference) = report.difference {
        return Err(format!("host and target differ first at {difference:?}").into());
    }
    Ok(())
}
