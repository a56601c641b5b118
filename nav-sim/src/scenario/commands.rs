//! Ground commands a scenario schedules (`[[command]]`): each is given to the flight software
//! through its own command interface (nav-fsw `NavigationComputer::command`) before the
//! frame at its time runs, so a campaign can fly filter resets, frozen blocks, disabled aids
//! and head selections, the calibration saved to and loaded from the vehicle's non-volatile
//! memory (nav-fsw `CalibrationStorePort`, one record kept for the whole flight), and
//! `reboot_keeping_calibration`, which the simulator flies itself: `save_calibration`, a
//! new computer started from the navigation solution of the moment (as a restart from the
//! last saved state) with its configured prior, then `load_calibration`. A command the flight software
//! refuses ends the flight with its reason: a schedule that does not fly as written is a
//! scenario error.

use nav_core::state::StateBlock;
use nav_fsw::scheduler::{AidingSensorId, Command};
use schemars::JsonSchema;
use serde::Deserialize;

/// One scheduled command.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScheduledCommand {
    /// Time after the scenario start at which the command is given, before that frame runs
    /// (s; within the flight).
    pub at_s: f64,
    /// The command.
    pub command: CommandKind,
    /// The calibration block of `freeze_block` and `release_block`, by its layout name
    /// (`gyro_bias`, `accel_bias`, `star_installation`, `gyro_scale_factor`,
    /// `accel_scale_factor`); absent for every other command.
    #[serde(default)]
    pub block: Option<String>,
    /// The sensor of `disable_aid` and `enable_aid`; absent for every other command.
    #[serde(default)]
    pub aid: Option<AidName>,
    /// The tracker head of `select_star_head` (0 or 1); absent for every other command.
    #[serde(default)]
    pub head: Option<u8>,
}

/// The commands a scenario may schedule (nav-fsw `Command`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CommandKind {
    /// Reset the filter, keeping the calibration (its estimates and covariance).
    ResetFilterKeepingCalibration,
    /// Reset the filter and the calibration to the start-up prior.
    ResetFilterDroppingCalibration,
    /// Freeze a calibration block (`block`).
    FreezeBlock,
    /// Release a commanded freeze of a calibration block (`block`).
    ReleaseBlock,
    /// Ignore an aiding sensor's measurements (`aid`).
    DisableAid,
    /// Use an aiding sensor's measurements again (`aid`).
    EnableAid,
    /// Make tracker head `head` the one the filter fuses.
    SelectStarHead,
    /// Forget the sensors' fault declarations.
    ClearSensorFaults,
    /// Forget calibration convergence and every freeze.
    RestartCalibration,
    /// Write the calibration record to the vehicle's non-volatile memory.
    SaveCalibration,
    /// Load the record in the vehicle's non-volatile memory as the prior.
    LoadCalibration,
    /// Restart the flight software, carrying the calibration over in a calibration record
    /// (saved, restarted, loaded).
    RebootKeepingCalibration,
}

/// What a scheduled command does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheduled {
    /// A flight-software command.
    Command(Command),
    /// A restart of the flight software that carries the calibration over in a record.
    RebootKeepingCalibration,
}

/// An aiding sensor, as a scheduled command names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AidName {
    /// The star tracker (every head).
    StarTracker,
    /// The GNSS receiver.
    Gnss,
}

impl ScheduledCommand {
    /// The flight software's command, or the key (relative to this command's table) that is
    /// missing, superfluous or wrong, with what it must be.
    ///
    /// # Errors
    /// `(key, requirement)` naming the argument at fault.
    pub fn to_command(&self) -> Result<Scheduled, (&'static str, String)> {
        use CommandKind::*;
        let needs = match self.command {
            FreezeBlock | ReleaseBlock => "block",
            DisableAid | EnableAid => "aid",
            SelectStarHead => "head",
            _ => "",
        };
        let given = [
            ("block", self.block.is_some()),
            ("aid", self.aid.is_some()),
            ("head", self.head.is_some()),
        ];
        for (key, present) in given {
            if present != (key == needs) {
                let requirement = if present {
                    format!("is not an argument of {:?}", self.command)
                } else {
                    format!("is required by {:?}", self.command)
                };
                return Err((key, requirement));
            }
        }
        if self.command == RebootKeepingCalibration {
            return Ok(Scheduled::RebootKeepingCalibration);
        }
        Ok(Scheduled::Command(match self.command {
            ResetFilterKeepingCalibration => Command::ResetFilter {
                keep_calibration: true,
            },
            ResetFilterDroppingCalibration => Command::ResetFilter {
                keep_calibration: false,
            },
            FreezeBlock => Command::SetBlockFrozen(self.calibration_block()?, true),
            ReleaseBlock => Command::SetBlockFrozen(self.calibration_block()?, false),
            DisableAid => Command::SetAidEnabled(self.sensor(), false),
            EnableAid => Command::SetAidEnabled(self.sensor(), true),
            SelectStarHead => Command::SelectStarHead(self.head.unwrap_or(0)),
            ClearSensorFaults => Command::ClearSensorFaults,
            SaveCalibration => Command::SaveCalibration,
            LoadCalibration => Command::LoadCalibration,
            RestartCalibration | RebootKeepingCalibration => Command::RestartCalibration,
        }))
    }

    fn calibration_block(&self) -> Result<StateBlock, (&'static str, String)> {
        let name = self.block.as_deref().unwrap_or("");
        StateBlock::CALIBRATION
            .into_iter()
            .find(|block| block.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = StateBlock::CALIBRATION.iter().map(|b| b.name()).collect();
                ("block", format!("must be one of {}", names.join(", ")))
            })
    }

    fn sensor(&self) -> AidingSensorId {
        match self.aid {
            Some(AidName::Gnss) => AidingSensorId::Gnss,
            _ => AidingSensorId::StarTracker,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scheduled(text: &str) -> ScheduledCommand {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn each_kind_becomes_the_flight_command_with_its_argument() {
        let cases = [
            (
                "at_s = 1.0\ncommand = \"reset_filter_keeping_calibration\"",
                Command::ResetFilter {
                    keep_calibration: true,
                },
            ),
            (
                "at_s = 1.0\ncommand = \"freeze_block\"\nblock = \"gyro_bias\"",
                Command::SetBlockFrozen(StateBlock::GyroBias, true),
            ),
            (
                "at_s = 1.0\ncommand = \"disable_aid\"\naid = \"gnss\"",
                Command::SetAidEnabled(AidingSensorId::Gnss, false),
            ),
            (
                "at_s = 1.0\ncommand = \"select_star_head\"\nhead = 1",
                Command::SelectStarHead(1),
            ),
        ];
        for (text, command) in cases {
            assert_eq!(
                scheduled(text).to_command(),
                Ok(Scheduled::Command(command)),
                "{text}"
            );
        }
    }

    #[test]
    fn a_missing_superfluous_or_unknown_argument_is_named() {
        let missing = scheduled("at_s = 1.0\ncommand = \"freeze_block\"");
        assert_eq!(missing.to_command().unwrap_err().0, "block");
        let extra = scheduled("at_s = 1.0\ncommand = \"clear_sensor_faults\"\nhead = 1");
        let (key, requirement) = extra.to_command().unwrap_err();
        assert_eq!(key, "head");
        assert!(requirement.contains("not an argument"), "{requirement}");
        let navigation = scheduled("at_s = 1.0\ncommand = \"freeze_block\"\nblock = \"attitude\"");
        let (key, requirement) = navigation.to_command().unwrap_err();
        assert_eq!(key, "block");
        assert!(requirement.contains("gyro_bias"), "{requirement}");
    }
}
