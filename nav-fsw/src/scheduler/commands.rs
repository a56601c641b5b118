//! Ground and flight-plan commands: each is checked against the computer's state, refused
//! with its reason when it is unsafe or meaningless (the computer unchanged), and counted in
//! the frame telemetry ([`CommandCounters`]). Commands run between frames, never inside one,
//! so none adds to a frame's cost.

use super::*;
use crate::calibration_record::{RecordError, CALIBRATION_RECORD_BYTES};
use crate::ports::{CalibrationStoreFault, CalibrationStorePort, NoCalibrationStore};

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
    /// Write the calibration earned so far to the calibration store
    /// ([`NavigationComputer::export_calibration`], [`CalibrationStorePort::write_record`]):
    /// before a planned power cycle, or periodically. Refused without a store
    /// ([`NavigationComputer::command_with_store`]) or when the export fails.
    SaveCalibration,
    /// Load the record in the calibration store as the prior
    /// ([`NavigationComputer::load_calibration`]): the sensor corrections become its
    /// estimates and the navigation restarts at its configured prior. Refused, the computer
    /// unchanged, without a store, when the store cannot be read, or for a record
    /// [`NavigationComputer::load_calibration`] refuses.
    LoadCalibration,
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
    /// The filter refused the reset, the hand-over or the export (nav-core's error; nothing
    /// changed).
    Filter(NavError),
    /// `SaveCalibration` or `LoadCalibration`: the calibration store could not be used.
    CalibrationStore(CalibrationStoreFault),
    /// `LoadCalibration`: the stored record is refused.
    CalibrationRecord(RecordError),
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
            Self::CalibrationStore(fault) => write!(f, "calibration command refused: {fault}"),
            Self::CalibrationRecord(error) => write!(f, "LoadCalibration refused: {error}"),
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

/// Number of counters in [`CommandCounters`].
pub const COMMAND_COUNTER_COUNT: usize = 5;

impl CommandCounters {
    /// Every counter with its name in the replay output record and the telemetry packets
    /// (`commands_` before the two command counts, so a ground display reads them alone),
    /// in declaration order.
    pub const fn named(&self) -> [(&'static str, u32); COMMAND_COUNTER_COUNT] {
        [
            ("commands_accepted", self.accepted),
            ("commands_refused", self.refused),
            (
                "measurements_of_disabled_aid",
                self.measurements_of_disabled_aid,
            ),
            (
                "calibration_records_loaded",
                self.calibration_records_loaded,
            ),
            (
                "calibration_records_refused",
                self.calibration_records_refused,
            ),
        ]
    }
}

impl NavigationComputer {
    /// Executes a command, counted in [`CommandCounters`], for a computer given no
    /// calibration store (`SaveCalibration` and `LoadCalibration` are refused with
    /// [`CalibrationStoreFault::NoStore`]; [`Self::command_with_store`] takes one).
    ///
    /// # Errors
    /// The [`CommandError`] that names why the command is refused; the computer is unchanged
    /// then (but for the refusal's count).
    pub fn command(&mut self, command: Command) -> Result<(), CommandError> {
        self.command_with_store(command, &mut NoCalibrationStore)
    }

    /// Executes a command, counted in [`CommandCounters`], with the integrator's
    /// calibration store for `SaveCalibration` and `LoadCalibration`.
    ///
    /// ```
    /// use nav_fsw::calibration_record::CALIBRATION_RECORD_BYTES;
    /// use nav_fsw::nalgebra::{Quaternion, Vector3};
    /// use nav_fsw::nav_core::frames::LaunchSite;
    /// use nav_fsw::nav_core::strapdown::NavigationState;
    /// use nav_fsw::ports::{CalibrationStoreFault, CalibrationStorePort};
    /// use nav_fsw::scheduler::{Command, CommandError};
    /// use nav_fsw::sensor_frames::SensorFrames;
    /// use nav_fsw::{FrameGnss, FrameImu, FrameStar, FswConfig, ImuSample, NavigationComputer};
    ///
    /// /// The vehicle's non-volatile memory (here a copy in RAM).
    /// struct Store(Option<[u8; CALIBRATION_RECORD_BYTES]>);
    /// impl CalibrationStorePort for Store {
    ///     fn read_record(
    ///         &mut self,
    ///         record: &mut [u8; CALIBRATION_RECORD_BYTES],
    ///     ) -> Result<(), CalibrationStoreFault> {
    ///         *record = self.0.ok_or(CalibrationStoreFault::Empty)?;
    ///         Ok(())
    ///     }
    ///     fn write_record(
    ///         &mut self,
    ///         record: &[u8; CALIBRATION_RECORD_BYTES],
    ///     ) -> Result<(), CalibrationStoreFault> {
    ///         self.0 = Some(*record);
    ///         Ok(())
    ///     }
    /// }
    ///
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let site = LaunchSite {
    ///     latitude_rad: 40.958_f64.to_radians(),
    ///     longitude_rad: 100.291_f64.to_radians(),
    ///     height_m: 1000.0,
    ///     azimuth_rad: 190.0_f64.to_radians(),
    ///     earth_axis_ecef: [0.0, 0.0, 1.0],
    /// };
    /// let initial = NavigationState {
    ///     attitude: Quaternion::identity(),
    ///     position_m: Vector3::new(0.0, 500e3, 0.0),
    ///     velocity_mps: Vector3::new(7600.0, 0.0, 0.0),
    ///     time_s: 600.0,
    /// };
    /// // PLACEHOLDER ground constants: a flight image uses its launch's (`nav-sim ground-constants`).
    /// let config = FswConfig::paper_defaults(site, SensorFrames::ALIGNED);
    /// let mut computer = NavigationComputer::new(config, initial)?;
    /// let mut store = Store(None);
    /// assert_eq!(
    ///     computer.command_with_store(Command::LoadCalibration, &mut store),
    ///     Err(CommandError::CalibrationStore(CalibrationStoreFault::Empty))
    /// );
    /// computer.command_with_store(Command::SaveCalibration, &mut store)?;
    /// computer.command_with_store(Command::LoadCalibration, &mut store)?;
    /// let mut imu = FrameImu(Some(ImuSample::new(1, 600.002, [0.0; 3], [0.0; 3])));
    /// let telemetry =
    ///     computer.run_frame(&mut imu, &mut FrameStar::default(), &mut FrameGnss::default());
    /// assert_eq!(telemetry.commands.calibration_records_loaded, 1);
    /// assert_eq!((telemetry.commands.accepted, telemetry.commands.refused), (2, 1));
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// # Errors
    /// As [`Self::command`], and [`CommandError::CalibrationStore`] or
    /// [`CommandError::CalibrationRecord`] for a store or record that cannot be used.
    pub fn command_with_store<P: CalibrationStorePort>(
        &mut self,
        command: Command,
        store: &mut P,
    ) -> Result<(), CommandError> {
        let executed = self.execute(command, store);
        let counter = match executed {
            Ok(()) => &mut self.operations.commands.accepted,
            Err(_) => &mut self.operations.commands.refused,
        };
        count(counter);
        executed
    }

    fn execute<P: CalibrationStorePort>(
        &mut self,
        command: Command,
        store: &mut P,
    ) -> Result<(), CommandError> {
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
            Command::SaveCalibration => self.save_calibration(store)?,
            Command::LoadCalibration => self.load_stored_calibration(store)?,
        }
        Ok(())
    }

    /// [`Command::SaveCalibration`].
    fn save_calibration<P: CalibrationStorePort>(
        &mut self,
        store: &mut P,
    ) -> Result<(), CommandError> {
        let record = self.export_calibration().map_err(CommandError::Filter)?;
        store
            .write_record(&record.to_bytes())
            .map_err(CommandError::CalibrationStore)
    }

    /// [`Command::LoadCalibration`]: the record read, then loaded as at start-up (counted as
    /// a record loaded or refused, besides the command's count).
    fn load_stored_calibration<P: CalibrationStorePort>(
        &mut self,
        store: &mut P,
    ) -> Result<(), CommandError> {
        let mut bytes = [0; CALIBRATION_RECORD_BYTES];
        store
            .read_record(&mut bytes)
            .map_err(CommandError::CalibrationStore)?;
        self.load_calibration(&bytes)
            .map_err(CommandError::CalibrationRecord)
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
