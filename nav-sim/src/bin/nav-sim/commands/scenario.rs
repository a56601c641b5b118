//! `nav-sim scenario`: prints the built-in default scenario, or a scenario file resolved
//! (`--resolved FILE`: its overlay chain applied, the canonical text its hash is taken of).

use std::path::PathBuf;

use nav_sim::scenario::overlay;
use nav_sim::Scenario;

use super::Failure;

/// The arguments of `nav-sim scenario`.
#[derive(clap::Args)]
pub struct Args {
    /// Print this scenario file resolved instead: its bases (`extends`) merged in, `remove`
    /// applied, keys sorted, no comments; `| sha256sum` gives the hash the outputs name it by.
    #[arg(long, value_name = "FILE")]
    resolved: Option<PathBuf>,
}

/// Prints the built-in default scenario (TOML) or the resolved file to standard output.
pub fn run(args: Args) -> Result<(), Failure> {
    let Some(path) = args.resolved.as_deref() else {
        print!("{}", nav_sim::scenario::DEFAULT_SCENARIO_TOML);
        return Ok(());
    };
    let resolved = overlay::resolve_file(path)?;
    print!("{}", resolved.to_toml(&path.display().to_string())?);
    // Printed first, so a scenario that resolves but is not valid can be read; then checked
    // as every command checks it, and a refusal is the command's failure.
    Scenario::load(path)?;
    Ok(())
}
