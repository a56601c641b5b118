//! `nav-sim ground-constants`: the flight configuration's ground constants (launch site with
//! the day's Earth axis, sensor frames of the launch epoch) for a scenario's launch, or for
//! the epoch, Earth orientation and site given on the command line, as TOML, JSON, Rust or C.

use std::path::PathBuf;

use nav_sim::scenario::ScenarioError;
use nav_sim::setup::ground::FlightGroundConstants;

use super::{load, Failure};

/// The output formats.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Format {
    /// `[launch_site]` and `[sensor_frames]` tables.
    Toml,
    /// `{"launch_site": {...}, "sensor_frames": {...}}`.
    Json,
    /// `LAUNCH_SITE` and `SENSOR_FRAMES` constants for a flight image.
    Rust,
    /// A `NavGroundConstants` initializer for a C flight image (nav-c's `nav.h`).
    C,
}

/// The arguments of `nav-sim ground-constants`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario TOML whose `[launch_site]` (and `[launch_site.earth_orientation]`) to use;
    /// default: the built-in one. The options below replace its values.
    scenario: Option<PathBuf>,
    /// Launch epoch, ISO 8601 UTC (e.g. 2024-02-26T04:00:00Z).
    #[arg(long)]
    epoch_utc: Option<String>,
    /// Geodetic latitude of the launch site (deg, WGS-84).
    #[arg(long, allow_negative_numbers = true)]
    latitude_deg: Option<f64>,
    /// Longitude of the launch site (deg, east positive).
    #[arg(long, allow_negative_numbers = true)]
    longitude_deg: Option<f64>,
    /// Height of the launch site above the WGS-84 ellipsoid (m).
    #[arg(long, allow_negative_numbers = true)]
    height_m: Option<f64>,
    /// Launch azimuth, clockwise from north (deg).
    #[arg(long, allow_negative_numbers = true)]
    azimuth_deg: Option<f64>,
    /// UT1 − UTC of the launch day (s, IERS Bulletin A).
    #[arg(long, allow_negative_numbers = true)]
    ut1_minus_utc_s: Option<f64>,
    /// Polar motion x of the launch day (arcsec).
    #[arg(long, allow_negative_numbers = true)]
    polar_motion_x_arcsec: Option<f64>,
    /// Polar motion y of the launch day (arcsec).
    #[arg(long, allow_negative_numbers = true)]
    polar_motion_y_arcsec: Option<f64>,
    /// Output format.
    #[arg(long, value_enum, default_value = "toml")]
    format: Format,
}

/// Prints the ground constants in the chosen format.
pub fn run(args: Args) -> Result<(), Failure> {
    let mut scenario = load(args.scenario.as_deref())?;
    let given = args.given_keys();
    let site = &mut scenario.launch_site;
    if let Some(epoch_utc) = args.epoch_utc {
        site.epoch_utc = epoch_utc;
    }
    let earth = &mut site.earth_orientation;
    for (value, field) in [
        (args.latitude_deg, &mut site.latitude_deg),
        (args.longitude_deg, &mut site.longitude_deg),
        (args.height_m, &mut site.height_m),
        (args.azimuth_deg, &mut site.azimuth_deg),
        (args.ut1_minus_utc_s, &mut earth.ut1_minus_utc_s),
        (args.polar_motion_x_arcsec, &mut earth.polar_motion_x_arcsec),
        (args.polar_motion_y_arcsec, &mut earth.polar_motion_y_arcsec),
    ] {
        if let Some(value) = value {
            *field = value;
        }
    }
    // The scenario's checks name the key of a bad value; a value given on the command line is
    // named by the flag the user typed.
    scenario
        .validate()
        .map_err(|error| named_by_flag(error, &given))?;
    let constants = FlightGroundConstants::of(&scenario)?;
    let text = match args.format {
        Format::Toml => constants.to_toml(),
        Format::Json => constants.to_json(),
        Format::Rust => constants.to_rust(),
        Format::C => constants.to_c(),
    };
    print!("{text}");
    Ok(())
}

/// The scenario key each flag sets.
const FLAG_KEYS: [(&str, &str); 8] = [
    ("--epoch-utc", "launch_site.epoch_utc"),
    ("--latitude-deg", "launch_site.latitude_deg"),
    ("--longitude-deg", "launch_site.longitude_deg"),
    ("--height-m", "launch_site.height_m"),
    ("--azimuth-deg", "launch_site.azimuth_deg"),
    (
        "--ut1-minus-utc-s",
        "launch_site.earth_orientation.ut1_minus_utc_s",
    ),
    (
        "--polar-motion-x-arcsec",
        "launch_site.earth_orientation.polar_motion_x_arcsec",
    ),
    (
        "--polar-motion-y-arcsec",
        "launch_site.earth_orientation.polar_motion_y_arcsec",
    ),
];

impl Args {
    /// The (flag, scenario key) pairs of the flags given.
    fn given_keys(&self) -> Vec<(&'static str, &'static str)> {
        let given = [
            self.epoch_utc.is_some(),
            self.latitude_deg.is_some(),
            self.longitude_deg.is_some(),
            self.height_m.is_some(),
            self.azimuth_deg.is_some(),
            self.ut1_minus_utc_s.is_some(),
            self.polar_motion_x_arcsec.is_some(),
            self.polar_motion_y_arcsec.is_some(),
        ];
        FLAG_KEYS
            .into_iter()
            .zip(given)
            .filter_map(|(pair, given)| given.then_some(pair))
            .collect()
    }
}

/// A scenario error about a key a flag set, reworded to name the flag (`--latitude-deg must be
/// in [-90, 90] deg (got 95 deg)`); any other error unchanged.
fn named_by_flag(error: ScenarioError, given: &[(&str, &str)]) -> Failure {
    if let ScenarioError::Invalid {
        key, requirement, ..
    } = &error
    {
        if let Some((flag, _)) = given.iter().find(|(_, flag_key)| flag_key == key) {
            return format!("{flag} {requirement}").into();
        }
    }
    error.into()
}
