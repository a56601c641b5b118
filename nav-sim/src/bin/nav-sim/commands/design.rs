//! `nav-sim design`: a manoeuvre schedule searched under a vehicle's limits, printed and
//! written as a scenario on request.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use nav_sim::output::OutputFile;
use nav_sim::studies::manoeuvre_design::{
    self, Constraints, ManoeuvreDesignError, UPPER_STAGE_TOML,
};
use nav_sim::Scenario;

use super::Failure;

/// A body axis on the command line (`x`, `y`, `z`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Axis {
    /// Body x.
    X,
    /// Body y.
    Y,
    /// Body z.
    Z,
}

impl Axis {
    /// The library's axis.
    fn axis(self) -> manoeuvre_design::Axis {
        match self {
            Self::X => manoeuvre_design::Axis::X,
            Self::Y => manoeuvre_design::Axis::Y,
            Self::Z => manoeuvre_design::Axis::Z,
        }
    }
}

/// The arguments of `nav-sim design`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario (TOML) whose orbit, sensors, filter and main-engine burns the design keeps;
    /// default: the built-in upper stage (nav-sim/scenarios/upper_stage.toml).
    scenario: Option<PathBuf>,
    /// Largest body rate (deg/s).
    #[arg(long, default_value_t = 3.0)]
    max_rate_deg_per_s: f64,
    /// Largest lateral (RCS) acceleration (m/s²).
    #[arg(long, default_value_t = 1.0)]
    max_lateral_accel_mps2: f64,
    /// Lateral Δv budget, Σ|Δv| over all translations (m/s).
    #[arg(long, default_value_t = 50.0)]
    lateral_delta_v_mps: f64,
    /// Flight time (s); default: the scenario's. Mission segments ending after it are left
    /// out.
    #[arg(long)]
    flight_time_s: Option<f64>,
    /// The main engine's body axis; its burns are taken from the scenario as they are.
    #[arg(long, value_enum, default_value = "x")]
    main_engine_axis: Axis,
    /// Body axes the RCS may translate along (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "y,z")]
    thrust_axes: Vec<Axis>,
    /// Analyses run at once during the search.
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// Write the scenario with the designed schedule here (TOML).
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

impl Args {
    /// The constraints the arguments give.
    fn constraints(&self) -> Constraints {
        Constraints {
            max_body_rate_deg_per_s: self.max_rate_deg_per_s,
            max_lateral_acceleration_mps2: self.max_lateral_accel_mps2,
            lateral_delta_v_mps: self.lateral_delta_v_mps,
            flight_time_s: self.flight_time_s,
            main_engine_axis: self.main_engine_axis.axis().index(),
            thrust_axes: self
                .thrust_axes
                .iter()
                .map(|axis| axis.axis().index())
                .collect(),
        }
    }
}

/// Loads the scenario, designs, prints the design and writes the scenario if asked.
pub fn run(args: Args) -> Result<(), Failure> {
    design(&args).map_err(Failure::from)
}

fn design(args: &Args) -> Result<(), ManoeuvreDesignError> {
    let (scenario, text) = match &args.scenario {
        Some(path) => {
            let (scenario, resolved) = Scenario::load_resolved(path)?;
            // The written scenario is the input with its schedule replaced: an overlay's own
            // text may hold no schedule and names its base relative to its own directory, so
            // its resolved text stands in for it.
            let text = if resolved.files().len() > 1 {
                resolved.to_toml(&path.display().to_string())?
            } else {
                std::fs::read_to_string(path).map_err(|source| ManoeuvreDesignError::Io {
                    path: path.display().to_string(),
                    source,
                })?
            };
            (scenario, text)
        }
        None => (
            Scenario::from_toml_str(UPPER_STAGE_TOML)?,
            UPPER_STAGE_TOML.to_string(),
        ),
    };
    let inputs: Vec<&Path> = args.scenario.iter().map(PathBuf::as_path).collect();
    // The output is refused or created before the search, so a bad --out fails at once.
    let output = match &args.out {
        Some(out) => Some((out, OutputFile::create_distinct(out, &inputs)?)),
        None => None,
    };
    let constraints = args.constraints();
    let design = manoeuvre_design::design(&scenario, &constraints, args.threads)?;
    print!("{}", design.text());
    if let Some((out, mut file)) = output {
        let header = design.header(&constraints);
        let written =
            manoeuvre_design::replace_manoeuvres(&text, &design.scenario.manoeuvres, &header);
        file.write_all(written.as_bytes())
            .map_err(|source| ManoeuvreDesignError::Io {
                path: out.display().to_string(),
                source,
            })?;
        file.commit()?;
        println!("wrote {}", out.display());
    }
    Ok(())
}
