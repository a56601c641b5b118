//! `nav-sim log`: a scenario's sensor log written as CSV (the replay format).

use std::path::PathBuf;

use nav_sim::output::OutputFile;

use super::{inputs, load, Failure};

/// The arguments of `nav-sim log`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML (default: the built-in one).
    scenario: Option<PathBuf>,
    /// The CSV file to write (not the scenario).
    #[arg(long)]
    out: PathBuf,
}

/// Simulates the scenario and writes its sensor events to `--out`.
pub fn run(args: Args) -> Result<(), Failure> {
    let scenario_path = args.scenario.as_deref();
    let out = &args.out;
    let mut file = OutputFile::create_distinct(out, &inputs(scenario_path))?;
    let scenario = load(scenario_path)?;
    let recorded = nav_sim::logs::sensor_log::record_simulation(
        nav_sim::Simulation::new(&scenario)?,
        &mut file,
    )?;
    file.commit()?;
    println!("wrote {} sensor events to {}", recorded.rows, out.display());
    if recorded.withheld_star_measurements > 0 {
        println!(
            "not written: {} star measurements of star-tracker heads beyond the two a \
             tracker port carries",
            recorded.withheld_star_measurements
        );
    }
    Ok(())
}
