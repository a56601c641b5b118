//! docs/reference/flight-parameters.md is written from the parameter table: this test renders
//! it and fails when the committed file differs. `NAV_BLESS=1 cargo test -p nav-fsw --test
//! reference` writes it. The page is the default build's table: a build without the
//! feature `gravity-field` narrows the gravity parameters' ranges and has no page of its own.
#![cfg(feature = "gravity-field")]

use nav_fsw::config::{FswConfig, Number, Param, COMPANIONS};
use nav_fsw::ConfigField;

/// The page, from the table.
fn render() -> String {
    let mut page = String::from(
        "# Flight parameters\n\n\
         Generated from the parameter table (`nav-fsw/src/config/parameters.rs`) by \
         `NAV_BLESS=1 cargo test -p nav-fsw --test reference`; the test fails when this file \
         differs from the table. Do not edit it by hand.\n\n\
         Every parameter of the flight software's configuration (`FswConfig`): its path, unit, \
         default (`mission`: given by the mission or the scenario), the range \
         `FswConfig::validate` accepts (a value outside is refused naming the path, the range \
         and the unit) and why, and its word in the replay setup (`-`: not carried; the \
         replay takes the default). nav-sim's `[filter]` keys are checked by these same \
         rules.\n\n",
    );
    let initial = nav_fsw::replay::INITIAL_NAVIGATION_WORDS;
    page.push_str(&format!(
        "The replay setup has {} words: word 0 is the magic `NAVSETUP`, words {} to {} the \
         initial navigation solution (attitude `w x y z`, position, velocity, time), every \
         other word a parameter's.\n\n\
         | path | unit | default | range | word | why |\n|---|---|---|---|---|---|\n",
        nav_fsw::replay::SETUP_WORDS,
        initial.start,
        initial.end - 1
    ));
    for param in Param::ALL {
        let range = param.range();
        let default = match param.default_value() {
            None => "mission".to_string(),
            Some(value) if !range.choices.is_empty() => {
                let index = value as usize;
                range.choices.get(index).copied().unwrap_or("?").to_string()
            }
            Some(value) => Number(value).to_string(),
        };
        let word = param
            .word()
            .map_or("-".to_string(), |word| word.to_string());
        let unit = if param.unit().is_empty() {
            "-"
        } else {
            param.unit()
        };
        page.push_str(&format!(
            "| `{}` | {unit} | {default} | {range} | {word} | {} |\n",
            param.path(),
            param.why().replace('|', "/")
        ));
    }
    page.push_str("\n## Parameters that go together\n\nWhen the first is on (not 0), the second must be too:\n\n");
    for (on, off) in COMPANIONS {
        page.push_str(&format!("- `{}` needs `{}`\n", on.path(), off.path()));
    }
    page.push_str("\n## Rules between values\n\n");
    for field in [
        ConfigField::LaunchSite,
        ConfigField::SensorFrames,
        ConfigField::StarMounting,
        ConfigField::StarSecondHead,
        ConfigField::MaxLatency,
        ConfigField::FutureTolerance,
        ConfigField::Gravity,
        ConfigField::CalibrationObservabilityTable,
    ] {
        page.push_str(&format!("- `{}` {}\n", field.key(), field.rule()));
    }
    page
}

#[test]
fn the_flight_parameter_reference_is_the_table() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../docs/reference/flight-parameters.md");
    let page = render();
    if std::env::var_os("NAV_BLESS").is_some() {
        std::fs::write(&path, &page).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == page,
        "{} differs from the parameter table: run NAV_BLESS=1 cargo test -p nav-fsw --test \
         reference",
        path.display()
    );
    // Every parameter is on the page, and the page names what the defaults are.
    let defaults = FswConfig::paper_defaults(
        nav_fsw::nav_core::frames::LaunchSite {
            latitude_rad: 0.0,
            longitude_rad: 0.0,
            height_m: 0.0,
            azimuth_rad: 0.0,
            earth_axis_ecef: [0.0, 0.0, 1.0],
        },
        nav_fsw::sensor_frames::SensorFrames::ALIGNED,
    );
    for param in Param::ALL {
        assert!(page.contains(&format!("| `{}` |", param.path())));
        if let Some(value) = param.default_value() {
            assert_eq!(value.to_bits(), param.value(&defaults).to_bits());
        }
    }
}
