//! The flight configuration's ground constants for a launch: the launch site (with the day's
//! Earth axis) and the sensor frames (GCRF → launch-inertial rotation, the launch epoch in GPS
//! time), as an integrator pastes them into a flight image: TOML, JSON, a Rust literal or a C
//! initializer (`nav-sim ground-constants`). Every float is written in its shortest form that
//! reads back to the same bits. The Rust form also carries its provenance (the epoch, the
//! Earth orientation values and the tool that computed them), so a flight image says what
//! launch its constants are for.

use nav_core::frames::LaunchSite;
use nav_fsw::sensor_frames::SensorFrames;

use crate::scenario::epoch::LaunchEpoch;
use crate::scenario::Scenario;
use crate::setup::launch::{launch_site, scenario_epoch, scenario_ground_constants};
use crate::setup::SetupError;

/// The ground constants of one launch (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightGroundConstants {
    /// nav-core's launch site, with the day's Earth axis.
    pub site: LaunchSite,
    /// nav-fsw's sensor frames of the launch epoch.
    pub sensor_frames: SensorFrames,
    /// The launch epoch and Earth orientation they were computed for (the provenance).
    pub epoch: LaunchEpoch,
}

impl FlightGroundConstants {
    /// The ground constants of `scenario`'s launch site and epoch.
    ///
    /// # Errors
    /// [`SetupError::LaunchSite`] if the epoch or the site is refused.
    ///
    /// # Examples
    /// ```
    /// use nav_sim::setup::ground::FlightGroundConstants;
    /// let scenario = nav_sim::Scenario::default_scenario().unwrap();
    /// let constants = FlightGroundConstants::of(&scenario).unwrap();
    /// // 2024-02-26T04:00:00Z is GPS week 2303, Monday 04:00:18 (GPS − UTC = 18 s).
    /// assert_eq!(constants.sensor_frames.launch_epoch_gps_week, 2303);
    /// assert!(constants.to_rust().contains("launch_epoch_gps_seconds_of_week: 100818.0"));
    /// ```
    pub fn of(scenario: &Scenario) -> Result<Self, SetupError> {
        let refused =
            |error: crate::scenario::epoch::EpochError| SetupError::LaunchSite(error.to_string());
        let ground = scenario_ground_constants(scenario).map_err(refused)?;
        Ok(Self {
            site: launch_site(scenario),
            sensor_frames: ground.sensor_frames,
            epoch: scenario_epoch(scenario).map_err(refused)?,
        })
    }

    /// The fields as (section, name, value) in the order of the Rust types.
    fn fields(&self) -> [(&'static str, &'static str, String); 8] {
        let (site, frames) = (&self.site, &self.sensor_frames);
        let float = |value: f64| format!("{value:?}");
        let array = |values: &[f64]| {
            let items: Vec<String> = values.iter().map(|value| float(*value)).collect();
            format!("[{}]", items.join(", "))
        };
        [
            ("launch_site", "latitude_rad", float(site.latitude_rad)),
            ("launch_site", "longitude_rad", float(site.longitude_rad)),
            ("launch_site", "height_m", float(site.height_m)),
            ("launch_site", "azimuth_rad", float(site.azimuth_rad)),
            (
                "launch_site",
                "earth_axis_ecef",
                array(&site.earth_axis_ecef),
            ),
            (
                "sensor_frames",
                "gcrf_to_launch_inertial_wxyz",
                array(&frames.gcrf_to_launch_inertial_wxyz),
            ),
            (
                "sensor_frames",
                "launch_epoch_gps_week",
                frames.launch_epoch_gps_week.to_string(),
            ),
            (
                "sensor_frames",
                "launch_epoch_gps_seconds_of_week",
                float(frames.launch_epoch_gps_seconds_of_week),
            ),
        ]
    }

    /// TOML: tables `[launch_site]` and `[sensor_frames]`, keys as the Rust fields.
    pub fn to_toml(&self) -> String {
        let mut text = String::new();
        let mut section = "";
        for (table, name, value) in self.fields() {
            if table != section {
                if !section.is_empty() {
                    text.push('\n');
                }
                text += &format!("[{table}]\n");
                section = table;
            }
            text += &format!("{name} = {value}\n");
        }
        text
    }

    /// JSON: `{"launch_site": {...}, "sensor_frames": {...}}`, keys as the Rust fields.
    pub fn to_json(&self) -> String {
        let mut tables: Vec<String> = Vec::new();
        for table in ["launch_site", "sensor_frames"] {
            let members: Vec<String> = self
                .fields()
                .into_iter()
                .filter(|(section, _, _)| *section == table)
                .map(|(_, name, value)| format!("    \"{name}\": {value}"))
                .collect();
            tables.push(format!("  \"{table}\": {{\n{}\n  }}", members.join(",\n")));
        }
        format!("{{\n{}\n}}\n", tables.join(",\n"))
    }

    /// A C99 initializer of the C interface's `NavGroundConstants` (nav-c's `nav.h`), whose
    /// fields are named as the Rust ones, in the same order.
    pub fn to_c(&self) -> String {
        let mut text = String::from(
            "/* The launch's ground constants for nav.h (`nav-sim ground-constants --format c`). */\n\
             static const NavGroundConstants NAV_GROUND_CONSTANTS = {\n",
        );
        for (_, name, value) in self.fields() {
            let value = value.replace('[', "{").replace(']', "}");
            text += &format!("    .{name} = {value},\n");
        }
        text += "};\n";
        text
    }

    /// The provenance line: the epoch (UTC), the Earth orientation values used and the tool,
    /// e.g. `epoch_utc=2024-02-26T04:00:00Z ut1_minus_utc_s=… polar_motion_x_arcsec=…
    /// polar_motion_y_arcsec=… tool=nav-sim 0.1.0 ground-constants`.
    pub fn provenance(&self) -> String {
        let earth = self.epoch.earth_orientation();
        format!(
            "epoch_utc={}Z ut1_minus_utc_s={:?} polar_motion_x_arcsec={:?} \
             polar_motion_y_arcsec={:?} tool=nav-sim {} ground-constants",
            self.epoch.utc_text(),
            earth.ut1_minus_utc_s,
            earth.polar_motion_x_arcsec,
            earth.polar_motion_y_arcsec,
            env!("CARGO_PKG_VERSION"),
        )
    }

    /// The provenance as two doc-comment lines: the tool and the epoch, then the Earth
    /// orientation values.
    fn provenance_doc(&self) -> String {
        let earth = self.epoch.earth_orientation();
        format!(
            "/// Computed by nav-sim {} ground-constants for the launch epoch {}Z UTC,\n\
             /// with UT1 − UTC = {:?} s and polar motion x_p = {:?}″, y_p = {:?}″.\n",
            env!("CARGO_PKG_VERSION"),
            self.epoch.utc_text(),
            earth.ut1_minus_utc_s,
            earth.polar_motion_x_arcsec,
            earth.polar_motion_y_arcsec,
        )
    }

    /// A Rust literal: `LAUNCH_SITE: LaunchSite` and `SENSOR_FRAMES: SensorFrames` constants
    /// (`nav_fsw::nav_core::frames::LaunchSite`, `nav_fsw::sensor_frames::SensorFrames`),
    /// each documented with its provenance, and the provenance as `GROUND_CONSTANTS_PROVENANCE`
    /// (a string a flight image can carry into its telemetry or logs).
    pub fn to_rust(&self) -> String {
        let provenance = self.provenance();
        let mut text = String::from(
            "use nav_fsw::nav_core::frames::LaunchSite;\nuse nav_fsw::sensor_frames::SensorFrames;\n",
        );
        text += &format!(
            "\n/// Where the constants below come from: the launch epoch (UTC), the Earth orientation\n\
             /// values of the launch day (IERS Bulletin A) and the tool that computed them.\n\
             pub const GROUND_CONSTANTS_PROVENANCE: &str =\n    \"{provenance}\";\n"
        );
        for (table, constant, type_name, doc) in [
            (
                "launch_site",
                "LAUNCH_SITE",
                "LaunchSite",
                "The launch site, with the Earth axis of the launch day.",
            ),
            (
                "sensor_frames",
                "SENSOR_FRAMES",
                "SensorFrames",
                "GCRF → launch-inertial rotation and the launch epoch in GPS time.",
            ),
        ] {
            text += &format!(
                "\n/// {doc}\n///\n{}pub const {constant}: {type_name} = {type_name} {{\n",
                self.provenance_doc()
            );
            for (_, name, value) in self
                .fields()
                .into_iter()
                .filter(|(section, _, _)| *section == table)
            {
                text += &format!("    {name}: {value},\n");
            }
            text += "};\n";
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each format carries every field with the bits of the computed constants.
    #[test]
    fn every_format_reads_back_to_the_same_bits() {
        let scenario = Scenario::default_scenario().unwrap();
        let constants = FlightGroundConstants::of(&scenario).unwrap();
        let toml: toml::Table = constants.to_toml().parse().unwrap();
        let json: serde_json::Value = serde_json::from_str(&constants.to_json()).unwrap();
        let q = constants.sensor_frames.gcrf_to_launch_inertial_wxyz;
        for (index, value) in q.iter().enumerate() {
            let from_toml = toml["sensor_frames"]["gcrf_to_launch_inertial_wxyz"][index]
                .as_float()
                .unwrap();
            let from_json = json["sensor_frames"]["gcrf_to_launch_inertial_wxyz"][index]
                .as_f64()
                .unwrap();
            assert_eq!(from_toml.to_bits(), value.to_bits());
            assert_eq!(from_json.to_bits(), value.to_bits());
        }
        let latitude = toml["launch_site"]["latitude_rad"].as_float().unwrap();
        assert_eq!(latitude.to_bits(), constants.site.latitude_rad.to_bits());
        assert_eq!(
            json["sensor_frames"]["launch_epoch_gps_week"].as_u64(),
            Some(u64::from(constants.sensor_frames.launch_epoch_gps_week))
        );
        let rust = constants.to_rust();
        assert!(rust.contains("pub const SENSOR_FRAMES: SensorFrames = SensorFrames {"));
        assert!(rust.contains(&format!(
            "    latitude_rad: {:?},",
            constants.site.latitude_rad
        )));
    }
}
