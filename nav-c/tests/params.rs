//! nav-c/src/params/ (the C configuration struct `NavConfig` and the parameter identifiers
//! `NavParam`) is written from nav-fsw's parameter table: cbindgen reads plain Rust items, not
//! the table's macro. This test renders the file and fails when the committed one differs;
//! `NAV_BLESS=1 cargo test -p nav-c --test params` writes it. It also holds the struct to the
//! table: every parameter is in `NavConfig` or `NavGroundConstants`, once.

use std::fmt::Write;
use std::path::PathBuf;

use nav_fsw::config::{FswConfig, Param};
use nav_fsw::error::ConfigField;

/// How the file is written again.
const BLESS: &str = "NAV_BLESS=1 cargo test -p nav-c --test params";

/// Whether the parameter is a ground constant's (in `NavGroundConstants`, not `NavConfig`).
fn is_ground_constant(param: Param) -> bool {
    let path = param.path();
    path.starts_with("launch_site.") || path.starts_with("sensor_frames.")
}

/// The C field of a path: `star.mounting_wxyz[2]` → (`star_mounting_wxyz`, Some(2)).
fn field_of(path: &str) -> (String, Option<usize>) {
    let (base, index) = match path.split_once('[') {
        Some((base, rest)) => (base, rest.trim_end_matches(']').parse().ok()),
        None => (path, None),
    };
    (base.replace('.', "_"), index)
}

/// The enum variant name of a parameter (the table's identifier).
fn variant_of(param: Param) -> String {
    format!("{param:?}")
}

/// The doc line of a parameter: its rule (range, unit, why), how a choice or flag is written
/// and its default.
fn doc_of(param: Param) -> String {
    let rule = format!("{}", ConfigField::Parameter(param));
    // The path in code quotes: its brackets are no links.
    let mut doc = format!(
        "`{}`{}",
        param.path(),
        rule.strip_prefix(param.path()).unwrap()
    );
    let choices = param.range().choices;
    if !choices.is_empty() {
        let named: Vec<String> = choices
            .iter()
            .enumerate()
            .map(|(index, name)| format!("{index} = {name}"))
            .collect();
        write!(doc, "; as its index: {}", named.join(", ")).unwrap();
    }
    match param.default_value() {
        Some(value) if value == 0.0 || (1e-3..1e6).contains(&value.abs()) => {
            write!(doc, "; default {value}").unwrap()
        }
        Some(value) => write!(doc, "; default {value:e}").unwrap(),
        None => doc.push_str("; no default: the mission gives it"),
    }
    if let Some(flag) = param.condition() {
        write!(doc, "; read only while `{}` is 1", flag.path()).unwrap();
    }
    doc
}

/// One C field: its name, the parameters in it (one, or an array's elements in order).
struct Field {
    name: String,
    params: Vec<Param>,
}

/// The fields of `NavConfig`, in table order; an array's elements are consecutive.
fn config_fields() -> Vec<Field> {
    let mut fields: Vec<Field> = Vec::new();
    for param in Param::ALL
        .iter()
        .copied()
        .filter(|p| !is_ground_constant(*p))
    {
        let (name, index) = field_of(param.path());
        match (index, fields.last_mut()) {
            (Some(index), Some(last)) if last.name == name => {
                assert_eq!(
                    last.params.len(),
                    index,
                    "{}: elements out of order",
                    param.path()
                );
                last.params.push(param);
            }
            (index, _) => {
                assert!(
                    index.is_none_or(|i| i == 0),
                    "{}: first element",
                    param.path()
                );
                assert!(
                    fields.iter().all(|field| field.name != name),
                    "{name}: two fields of one name"
                );
                fields.push(Field {
                    name,
                    params: vec![param],
                });
            }
        }
    }
    fields
}

/// The two generated files: the identifiers (`ids.rs`) and the configuration (`config.rs`).
fn render() -> (String, String) {
    let mut out = String::new();
    let fields = config_fields();
    let config_params: Vec<Param> = fields.iter().flat_map(|f| f.params.clone()).collect();
    let count = config_params.len();
    writeln!(
        out,
        "//! The flight parameters for C: [`NavConfig`] (one field per parameter of nav-fsw's\n\
         //! parameter table but the ground constants') and [`NavParam`] (every parameter's\n\
         //! identifier). Generated from the table (`nav-fsw/src/config/parameters.rs`) by\n\
         //! `{BLESS}`; the test fails when this file differs from the table. Do not edit it by\n\
         //! hand.\n\n\
         mod config;\n\n\
         pub use config::NavConfig;\n\
         pub(crate) use config::CONFIG_PARAMS;\n\n\
         /// Parameters in `NavConfig`, in the order of its fields.\n\
         pub const NAV_CONFIG_PARAMS: usize = {count};\n\n\
         /// Parameters in the table (`NavParam` counts them from 1).\n\
         pub const NAV_PARAMS: usize = {};\n",
        Param::ALL.len()
    )
    .unwrap();
    out.push_str(
        "/// Every flight parameter, numbered from 1 in the table's order (0 is none);\n\
         /// `nav_param_path` gives its path in the flight software's configuration.\n\
         #[repr(C)]\n#[derive(Debug, Clone, Copy, PartialEq, Eq)]\npub enum NavParam {\n    \
         /// No parameter.\n    None = 0,\n",
    );
    for (index, param) in Param::ALL.iter().enumerate() {
        writeln!(
            out,
            "    /// `{}`\n    {} = {},",
            param.path(),
            variant_of(*param),
            index + 1
        )
        .unwrap();
    }
    out.push_str("}\n\n");
    writeln!(
        out,
        "/// Every parameter's path, NUL-terminated, in the table's order.\n\
         pub(crate) const PARAM_PATHS: [&str; NAV_PARAMS] = ["
    )
    .unwrap();
    for param in Param::ALL {
        writeln!(out, "    \"{}\\0\",", param.path()).unwrap();
    }
    out.push_str("];\n\n");
    let ids = out;
    let mut out = String::new();
    writeln!(
        out,
        "//! The configuration struct for C, one field per parameter of nav-fsw's table but the\n\
         //! ground constants'. Generated from the table by `{BLESS}`; do not edit it by hand.\n\n\
         use nav_fsw::config::Param;\n\n\
         use super::NAV_CONFIG_PARAMS;\n"
    )
    .unwrap();
    out.push_str(
        "/// The flight software's configuration for C: every parameter of the table but the\n\
         /// ground constants' (`NavGroundConstants`), each a `double` holding the parameter's\n\
         /// number (a count its integer value, a flag 0 or 1, a choice its index), in the\n\
         /// table's order. `nav_config_defaults` fills it with the defaults.\n\
         #[repr(C)]\n#[derive(Debug, Clone, Copy, PartialEq)]\npub struct NavConfig {\n",
    );
    for field in &fields {
        if field.params.len() == 1 {
            writeln!(out, "    /// {}", doc_of(field.params[0])).unwrap();
            writeln!(out, "    pub {}: f64,", field.name).unwrap();
        } else {
            for (index, param) in field.params.iter().enumerate() {
                writeln!(out, "    /// Element {index}: {}", doc_of(*param)).unwrap();
            }
            writeln!(
                out,
                "    pub {}: [f64; {}],",
                field.name,
                field.params.len()
            )
            .unwrap();
        }
    }
    out.push_str("}\n\n");
    out.push_str(
        "/// The parameters of [`NavConfig`]'s fields, in their order.\n\
         pub(crate) const CONFIG_PARAMS: [Param; NAV_CONFIG_PARAMS] = [\n",
    );
    for param in &config_params {
        writeln!(out, "    Param::{},", variant_of(*param)).unwrap();
    }
    out.push_str("];\n\nimpl NavConfig {\n");
    out.push_str(
        "    /// The fields' values in [`CONFIG_PARAMS`] order.\n    \
         pub(crate) fn values(&self) -> [f64; NAV_CONFIG_PARAMS] {\n        [\n",
    );
    for field in &fields {
        if field.params.len() == 1 {
            writeln!(out, "            self.{},", field.name).unwrap();
        } else {
            for index in 0..field.params.len() {
                writeln!(out, "            self.{}[{index}],", field.name).unwrap();
            }
        }
    }
    out.push_str("        ]\n    }\n\n");
    out.push_str(
        "    /// The configuration of values in [`CONFIG_PARAMS`] order.\n    \
         pub(crate) fn from_values(values: &[f64; NAV_CONFIG_PARAMS]) -> Self {\n        \
         Self {\n",
    );
    let mut position = 0;
    for field in &fields {
        if field.params.len() == 1 {
            writeln!(out, "            {}: values[{position}],", field.name).unwrap();
            position += 1;
        } else {
            let elements: Vec<String> = (0..field.params.len())
                .map(|i| format!("values[{}]", position + i))
                .collect();
            position += field.params.len();
            writeln!(
                out,
                "            {}: [{}],",
                field.name,
                elements.join(", ")
            )
            .unwrap();
        }
    }
    out.push_str("        }\n    }\n}\n");
    (ids, out)
}

/// `text` as `cargo fmt` leaves it (the files are formatted like every other source).
fn rustfmt(text: &str) -> String {
    use std::io::Write as _;
    let mut child = std::process::Command::new("rustfmt")
        .args(["--edition", "2021", "--emit", "stdout"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert!(
        output.status.success(),
        "rustfmt refused the generated file"
    );
    String::from_utf8(output.stdout).unwrap()
}

#[test]
fn params_file_is_the_parameter_table() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/params");
    let (ids, config) = render();
    for (name, text) in [("mod.rs", ids), ("config.rs", config)] {
        let text = rustfmt(&text);
        let path = dir.join(name);
        if std::env::var_os("NAV_BLESS").is_some() {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &text).unwrap();
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "nav-c/src/params/{name} differs from the parameter table: run {BLESS}"
        );
    }
}

#[test]
fn every_parameter_is_in_the_config_or_the_ground_constants_once() {
    let fields = config_fields();
    let in_config: Vec<Param> = fields.iter().flat_map(|f| f.params.clone()).collect();
    let ground: Vec<Param> = Param::ALL
        .iter()
        .copied()
        .filter(|p| is_ground_constant(*p))
        .collect();
    // The ground constants: the launch site (4 numbers and the Earth axis) and the sensor
    // frames (the quaternion, the week and the seconds of week).
    assert_eq!(ground.len(), 13);
    assert_eq!(in_config.len() + ground.len(), Param::ALL.len());
    assert_eq!(nav_c::params::NAV_CONFIG_PARAMS, in_config.len());
    // The C struct is the table's numbers: as many doubles as parameters.
    assert_eq!(
        std::mem::size_of::<nav_c::params::NavConfig>(),
        8 * in_config.len()
    );
    // A value reaches its parameter through the structs: each parameter set alone to a value
    // off its own comes back from `FswConfig` through `NavConfig` and `NavGroundConstants`
    // (with a second head, so that its parameters apply).
    let site = nav_fsw::nav_core::frames::LaunchSite {
        latitude_rad: 0.5,
        longitude_rad: 1.0,
        height_m: 10.0,
        azimuth_rad: 2.0,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    };
    let mut defaults =
        FswConfig::paper_defaults(site, nav_fsw::sensor_frames::SensorFrames::ALIGNED);
    Param::StarSecondHead
        .set_number(&mut defaults, 1.0)
        .unwrap();
    for param in Param::ALL {
        let mut config = defaults;
        let changed = if param.value(&config).to_bits() == 1.0_f64.to_bits() {
            0.0
        } else {
            1.0
        };
        param.set_number(&mut config, changed).unwrap();
        let (c_config, ground) = nav_c::c_config_of(&config);
        let back = nav_c::fsw_config_of(&c_config, &ground).unwrap();
        for other in Param::ALL {
            assert_eq!(
                other.value(&back).to_bits(),
                other.value(&config).to_bits(),
                "{} set to {changed}: {} differs",
                param.path(),
                other.path()
            );
        }
    }
}
