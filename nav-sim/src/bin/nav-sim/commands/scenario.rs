//! `nav-sim scenario`: prints the built-in default scenario.

use super::Failure;

/// The arguments of `nav-sim scenario` (none).
#[derive(clap::Args)]
pub struct Args {}

/// Prints the built-in default scenario (TOML) to standard output.
pub fn run(_args: Args) -> Result<(), Failure> {
    print!("{}", nav_sim::scenario::DEFAULT_SCENARIO_TOML);
    Ok(())
}
