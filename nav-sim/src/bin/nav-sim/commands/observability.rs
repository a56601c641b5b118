//! `nav-sim observability`: the paper's Table 1 recomputed for its motion states and the
//! scenario's schedule, printed as text or JSON, with the heat map written on request.

use std::io::Write as _;
use std::path::PathBuf;

use nav_sim::studies::observability::{
    build_report, render_json, render_text, write_heat_map, ObservabilityReportError, HEAT_MAP_FILE,
};
use nav_sim::Scenario;

use super::Failure;

/// The arguments of `nav-sim observability`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario file (TOML); the built-in default (the paper's Section 3) when omitted.
    scenario: Option<PathBuf>,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Write the heat map of the observability degree (PNG) into this directory.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// Loads the scenario, builds the report, prints it and writes the heat map if asked.
pub fn run(args: Args) -> Result<(), Failure> {
    report(&args).map_err(Failure::from)
}

fn report(args: &Args) -> Result<(), ObservabilityReportError> {
    let (scenario, origin) = match &args.scenario {
        Some(path) => (Scenario::load(path)?, path.display().to_string()),
        None => (
            Scenario::default_scenario()?,
            "<built-in default>".to_string(),
        ),
    };
    let report = build_report(&scenario, &origin)?;
    let text = if args.json {
        render_json(&report)? + "\n"
    } else {
        render_text(&report)
    };
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        // A closed pipe (`| head`) is the reader's choice, not an error.
        Err(error) if error.kind() != std::io::ErrorKind::BrokenPipe => {
            return Err(ObservabilityReportError::Output(error));
        }
        _ => {}
    }
    if let Some(directory) = &args.out {
        std::fs::create_dir_all(directory).map_err(|source| ObservabilityReportError::Io {
            path: directory.display().to_string(),
            source,
        })?;
        let path = directory.join(HEAT_MAP_FILE);
        write_heat_map(&report, &path)?;
        eprintln!("heat map written to {}", path.display());
    }
    Ok(())
}
