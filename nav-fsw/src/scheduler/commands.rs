//! Ground and flight-plan commands: each is checked against the computer's state, refused
//! with its reason when it is unsafe or meaningless (the computer unchanged), and counted in
//! the frame telemetry ([`CommandCounters`]). Commands run between frames, never inside one,
//! so none adds to a frame's cost.

use super::*;

/// Ground or flight-plan commands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Command {
    /// The manoeuvre phase: drives the calibration manager under
    /// [`EstimationPolicy::PaperSchedule`]; refused under a policy that does not read it
    /// ([`EstimationPolicy::uses_phase`]).
    SetPhase(ManoeuvrePhase),
    /// Forget the fault declarations: both sensors are used again.
    ClearSensorFaults,
    /// Forget calibration convergence (unfreeze every block, the optional ones included, and
    /// every commanded freeze).
    RestartCalibration,
    /// Freeze an optional state block in use (`true`) or release it (`false`): its gain
    /// rows are zero in every update, as a frozen core block's (nav-core
    /// `ErrorStateFilter::set_optional_block_frozen`). A filter recovery or
    /// [`Command::RestartCalibration`] releases it.
    SetOptionalBlockFrozen(OptionalBlock, bool),
    /// Freeze a core calibration block (`true`: the filter no longer moves it, whatever the
    /// calibration policy says) or release a commanded freeze (`false`: the block is
    /// estimated again and its convergence is tested afresh). A commanded freeze survives
    /// a filter recovery; [`Command::RestartCalibration`] releases it. Refused for a
    /// navigation block ([`StateBlock::may_freeze`]).
    SetBlockFrozen(StateBlock, bool),
    /// Reset the filter. `keep_calibration: true` re-initialises the navigation states
    /// (and the optional blocks) to the configured prior and keeps the calibration, its
    /// estimates and their covariance (nav-core
    /// `ErrorStateFilter::restart_keeping_calibration`): after a navigation upset whose
    /// cause is not the sensors. `false` drops the calibration too: the sensor corrections
    /// return to zero and the whole filter to its prior, as at start-up.
    ResetFilter {
        /// Whether the calibration (estimates and covariance) is kept.
        keep_calibration: bool,
    },
    /// Use (`true`) or ignore (`false`) an aiding sensor's measurements. An ignored sensor's
    /// measurements are still read and checked (its outage monitor and, for the tracker, the
    /// heads' pairing go on), then discarded and counted; enabled again, it is acquired
    /// afresh (the acquisition gate). Refused for the last sensor in use: a filter with no
    /// aid drifts unobserved, with nothing to tell the operator.
    SetAidEnabled(AidingSensorId, bool),
    /// Make tracker head `0` or `1` the one the filter fuses, as an automatic hand-over
    /// does (`scheduler::heads`). Refused with one head configured, for a head declared
    /// faulty or not yet aligned, or one not heard within the outage timeout. Selecting the
    /// head already active changes nothing.
    SelectStarHead(u8),
}

/// An aiding sensor, as commands name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AidingSensorId {
    /// The star tracker (every head).
    StarTracker,
    /// The GNSS receiver (position and velocity).
    Gnss,
}

impl AidingSensorId {
    fn sensor(self) -> Sensor {
        match self {
            Self::StarTracker => Sensor::Star,
            Self::Gnss => Sensor::Gnss,
        }
    }
}

/// Why a [`Command`] was refused (the computer is unchanged).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CommandError {
    /// `SetPhase` under a policy that does not read the manoeuvre phase.
    PhaseNotUsed(EstimationPolicy),
    /// `SetOptionalBlockFrozen` for a block the configuration does not fly.
    BlockNotInUse(OptionalBlock),
    /// `SetBlockFrozen` for a block the layout does not let be frozen (a navigation block).
    BlockNotFreezable(StateBlock),
    /// `ResetFilter { keep_calibration: true }` in open loop with an optional block in use:
    /// the open-loop filter holds that block's estimate in its state, and the reset would
    /// drop it.
    OpenLoopOptionalEstimates,
    /// `SetAidEnabled(_, false)` for the only aiding sensor still in use.
    LastAidingSensor(AidingSensorId),
    /// `SelectStarHead` for a head the configuration does not have.
    StarHeadNotConfigured(u8),
    /// `SelectStarHead` for a head declared faulty or not yet aligned with the active one.
    StarHeadNotAligned(u8),
    /// `SelectStarHead` for a head not heard within the outage timeout.
    StarHeadSilent(u8),
    /// The filter refused the reset or the hand-over (nav-core's error; nothing changed).
    Filter(NavError),
}

impl core::fmt::Display for CommandError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::PhaseNotUsed(policy) => write!(
                f,
                "SetPhase refused: the calibration policy {policy:?} does not use the manoeuvre \
                 phase (only PaperSchedule does)"
            ),
            Self::BlockNotInUse(block) => write!(
                f,
                "SetOptionalBlockFrozen refused: the state block {} is not in use",
                block.name()
            ),
            Self::BlockNotFreezable(block) => write!(
                f,
                "SetBlockFrozen refused: {} is a navigation block, which may not be frozen",
                block.name()
            ),
            Self::OpenLoopOptionalEstimates => f.write_str(
                "ResetFilter keeping the calibration refused: in open loop the optional blocks' \
                 estimates are in the filter state and the reset would drop them",
            ),
            Self::LastAidingSensor(sensor) => write!(
                f,
                "SetAidEnabled refused: {sensor:?} is the last aiding sensor in use; without \
                 one the filter drifts unobserved"
            ),
            Self::StarHeadNotConfigured(head) => {
                write!(f, "SelectStarHead refused: head {head} is not configured")
            }
            Self::StarHeadNotAligned(head) => write!(
                f,
                "SelectStarHead refused: head {head} is declared faulty or not yet aligned"
            ),
            Self::StarHeadSilent(head) => write!(
                f,
                "SelectStarHead refused: head {head} was not heard within the outage timeout"
            ),
            Self::Filter(error) => write!(f, "command refused by the filter: {error}"),
        }
    }
}

impl core::error::Error for CommandError {}

/// The commands executed and refused, and the measurements of a sensor disabled by
/// [`Command::SetAidEnabled`] (discarded), in the frame telemetry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CommandCounters {
    /// Commands executed.
    pub accepted: u32,
    /// Commands refused ([`CommandError`]).
    pub refused: u32,
    /// Measurements discarded because their sensor is disabled by command.
    pub measurements_of_disabled_aid: u32,
    /// Calibration records loaded (`NavigationComputer::load_calibration`).
    pub calibration_records_loaded: u32,
    /// Calibration records refused (`crate::calibration_record::RecordError`).
    pub calibration_records_refused: u32,
}

impl NavigationComputer {
    /// Executes a command, counted in [`CommandCounters`].
    ///
    /// # Errors
    /// The [`CommandError`] that names why the command is refused; the computer is unchanged
    /// then (but for the refusal's count).
    pub fn command(&mut self, command: Command) -> Result<(), CommandError> {
        let executed = self.execute(command);
        let counter = match executed {
            Ok(()) => &mut self.operations.commands.accepted,
            Err(_) => &mut self.operations.commands.refused,
        };
        count(counter);
        executed
    }

    fn execute(&mut self, command: Command) -> Result<(), CommandError> {
        match command {
            Command::SetPhase(phase) => {
                let policy = self.config.calibration.policy;
                if !policy.uses_phase() {
                    return Err(CommandError::PhaseNotUsed(policy));
                }
                self.calibration.manager.set_phase(phase);
            }
            Command::ClearSensorFaults => self.aids.clear_faults(),
            Command::RestartCalibration => {
                self.calibration.manager.release_commanded_freezes();
                self.calibration.manager.restart();
                self.release_optional_blocks();
            }
            Command::SetOptionalBlockFrozen(block, frozen) => self
                .covariance
                .filter
                .set_optional_block_frozen(block, frozen)
                .map_err(|_| CommandError::BlockNotInUse(block))?,
            Command::SetBlockFrozen(block, frozen) => {
                if !block.may_freeze() {
                    return Err(CommandError::BlockNotFreezable(block));
                }
                self.calibration.manager.set_commanded_frozen(block, frozen);
            }
            Command::ResetFilter { keep_calibration } => self.reset_filter(keep_calibration)?,
            Command::SetAidEnabled(sensor, enabled) => self.set_aid_enabled(sensor, enabled)?,
            Command::SelectStarHead(head) => self.select_star_head(head)?,
        }
        Ok(())
    }

    /// Releases every optional block in use.
    fn release_optional_blocks(&mut self) {
        for block in OptionalBlock::ALL {
            // A block not in use has nothing to release.
            let _ = self
                .covariance
                .filter
                .set_optional_block_frozen(block, false);
        }
    }

    /// [`Command::ResetFilter`]: the filter restarted (keeping the calibration or not), then
    /// everything that follows the filter's state started again as after a recovery.
    fn reset_filter(&mut self, keep_calibration: bool) -> Result<(), CommandError> {
        let filter = &mut self.covariance.filter;
        let config = &self.config.filter;
        if keep_calibration {
            let optional_in_use = OptionalBlock::ALL
                .iter()
                .any(|block| filter.optional_block_in_use(*block));
            if filter.mode() == FilterMode::OpenLoop && optional_in_use {
                return Err(CommandError::OpenLoopOptionalEstimates);
            }
            filter
                .restart_keeping_calibration(config)
                .map_err(CommandError::Filter)?;
        } else {
            filter.restart(config).map_err(CommandError::Filter)?;
            self.calibration.estimate = CalibrationEstimate::default();
            self.calibration.imu_errors = ImuErrorEstimate::default();
            self.calibration.manager.restart();
        }
        self.restart_after_filter_reset();
        Ok(())
    }

    /// [`Command::SetAidEnabled`].
    fn set_aid_enabled(
        &mut self,
        sensor: AidingSensorId,
        enabled: bool,
    ) -> Result<(), CommandError> {
        let other_disabled = self.operations.disabled(sensor.sensor().other());
        if !enabled && other_disabled {
            return Err(CommandError::LastAidingSensor(sensor));
        }
        let was_disabled = self.operations.disabled(sensor.sensor());
        self.operations.set_disabled(sensor.sensor(), !enabled);
        if enabled && was_disabled {
            // Unseen while disabled, the state error has grown: acquire the aid afresh.
            self.reacquire(sensor.sensor());
        }
        Ok(())
    }
}
