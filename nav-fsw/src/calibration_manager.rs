//! The calibration manager: the paper's Section 3 strategy as a state machine.
//!
//! The flight (or the ground, by command) tells the manager the manoeuvre phase; the manager
//! decides which calibration blocks the filter may move ([`EstimationPolicy`]), declares a
//! block converged when every axis's 1σ is below its threshold and the estimate has stayed
//! within `stability_fraction × threshold` of itself over `stability_window_s`, optionally
//! freezes converged blocks (their gain rows are zeroed: [`nav_core::filter`]'s
//! `update_with_frozen_blocks`; calibration blocks have no process noise unless a bias random
//! walk is configured, and the scheduler zeroes that too for a frozen block), and keeps the
//! calibration table (value, 1σ, time converged) that the ground reads.
//!
//! Which blocks may move is chosen by [`EstimationPolicy`]: all of them (default), the
//! paper's phase schedule, or the observability of the current motion
//! ([`EstimationPolicy::MotionObservability`]: the manager classifies the measured body rate
//! and specific force into a [`MotionSignature`] every frame and looks up which blocks that
//! motion makes observable in the configured [`MotionObservabilityTable`], the result of
//! nav-core's stripped-observability analysis for every signature).

use nalgebra::Vector3;
use nav_core::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, GYRO_BIAS, GYRO_SCALE_FACTOR,
    STAR_INSTALLATION,
};

use crate::error::{ConfigField, FswError};
pub use crate::motion_observability::{MotionObservabilityTable, MotionSignature};

/// Number of calibration blocks (biases, installation, scale factors).
pub const CALIBRATION_BLOCK_COUNT: usize = StateBlock::CALIBRATION.len();

/// The flight's manoeuvre phase, as commanded or as known from the flight plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ManoeuvrePhase {
    /// Not known (estimate everything the policy allows).
    #[default]
    Unknown,
    /// Quiet coast: no thrust, near-zero rates (paper: biases).
    Coast,
    /// Rotation about a body axis (paper: gyro scale factors).
    Rotation,
    /// Thrust along a body axis (paper: accelerometer scale factors, installation error).
    Acceleration,
}

/// Which blocks are estimated in which phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EstimationPolicy {
    /// Every calibration block is estimated in every phase (until converged and frozen).
    /// The default: the filter's own gains already weight each block by its observability.
    AllBlocks,
    /// The paper's schedule: coast → gyro and accelerometer biases; rotation → gyro scale
    /// factors and installation error; acceleration → accelerometer scale factors and
    /// installation error. The other calibration blocks are frozen in that phase.
    /// `Unknown` estimates all.
    PaperSchedule,
    /// Observability-driven: a calibration block is frozen while the current motion
    /// (its [`MotionSignature`], from the measured body rate and specific force) makes no
    /// direction of it observable **and** an earlier motion did; otherwise it is estimated.
    /// "Observable" is nav-core's structural test (`motion_observability_analysis`: the
    /// paper's PWCS setting, a reference coast then the motion, null space of the stripped
    /// observability matrix, per-block directions as
    /// `MotionObservabilityTable::ESTIMABLE`), tabulated for all 64 signatures at start-up
    /// ([`MotionObservabilityTable`]), so the per-frame cost is a table look-up. The
    /// manoeuvre phase is not used.
    ///
    /// Why "and an earlier motion did": freezing is a consider (Schmidt) update, which throws
    /// away what a measurement says about the frozen block. Freezing a block that no motion has
    /// revealed yet loses the correlations the filter builds before its manoeuvre (e.g. the
    /// installation error tied to the attitude prior during the first coast): measured on the
    /// short test scenario, the z gyro scale factor then ends at 1σ = 6.2e-5 instead of 1.1e-6.
    /// So the policy protects what a manoeuvre has taught the filter from being dragged by
    /// unmodelled effects in phases that cannot see it, and leaves the rest to the filter's
    /// own gains. Freezing is per block: a block with at least one observable direction moves
    /// as a whole (e.g. under a rotation about body z the gyro scale factor block moves, whose
    /// z axis alone is observable).
    MotionObservability,
}

impl EstimationPolicy {
    /// Whether the policy reads the manoeuvre phase (`Command::SetPhase`): only
    /// [`EstimationPolicy::PaperSchedule`] does.
    ///
    /// # Examples
    /// ```
    /// use nav_fsw::calibration_manager::EstimationPolicy;
    /// assert!(EstimationPolicy::PaperSchedule.uses_phase());
    /// assert!(!EstimationPolicy::AllBlocks.uses_phase());
    /// ```
    pub const fn uses_phase(self) -> bool {
        matches!(self, Self::PaperSchedule)
    }
}

/// Per calibration block thresholds (units of the block).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationThresholds {
    /// Gyro bias (rad/s).
    pub gyro_bias_rad_s: f64,
    /// Accelerometer bias (m/s²).
    pub accel_bias_mps2: f64,
    /// Star-sensor installation error, as a small rotation angle (rad).
    pub star_installation_rad: f64,
    /// Gyro scale factor (dimensionless).
    pub gyro_scale_factor: f64,
    /// Accelerometer scale factor (dimensionless).
    pub accel_scale_factor: f64,
}

impl CalibrationThresholds {
    /// The paper's reported accuracies (Section 3): the figures to meet.
    pub const PAPER_ACCURACY: CalibrationThresholds = CalibrationThresholds {
        gyro_bias_rad_s: 1.5e-6,
        accel_bias_mps2: 2.75e-4,
        star_installation_rad: 5e-6,
        gyro_scale_factor: 1e-6,
        accel_scale_factor: 2e-6,
    };

    /// The values in [`StateBlock::CALIBRATION`] order.
    pub const fn values(&self) -> [f64; CALIBRATION_BLOCK_COUNT] {
        [
            self.gyro_bias_rad_s,
            self.accel_bias_mps2,
            self.star_installation_rad,
            self.gyro_scale_factor,
            self.accel_scale_factor,
        ]
    }
}

/// Calibration manager settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationManagerConfig {
    /// A block converges when every axis's 1σ is below this (default: a third of the
    /// paper's reported accuracy, so the estimate is within it at 3σ).
    pub convergence_sigma: CalibrationThresholds,
    /// Window over which a converging estimate must stay put (s).
    pub stability_window_s: f64,
    /// Allowed drift of the estimate over the window, as a fraction of its threshold.
    pub stability_fraction: f64,
    /// Freeze converged blocks (gain and process noise off).
    pub freeze_converged: bool,
    /// Which blocks are estimated in which phase.
    pub policy: EstimationPolicy,
    /// [`EstimationPolicy::MotionObservability`]: a body axis counts as rotating above this
    /// rate (rad/s). Default 0.5 °/s: far above an orbital coast's rate (the paper's state I is
    /// 2.4e-4 °/s) and the gyro noise of one 2 ms sample, far below a calibration rotation.
    pub motion_rate_threshold_rad_s: f64,
    /// [`EstimationPolicy::MotionObservability`]: a body axis counts as thrusting above this
    /// specific force (m/s²). Default 0.5 m/s²: above the drag and accelerometer noise of a
    /// coast, far below a calibration burn.
    pub motion_force_threshold_mps2: f64,
    /// [`EstimationPolicy::MotionObservability`]: which blocks each motion signature makes
    /// observable. Default [`MotionObservabilityTable::structural`].
    pub motion_observability: MotionObservabilityTable,
}

/// The parameter table's defaults ([`crate::config::Param`]).
impl Default for CalibrationManagerConfig {
    fn default() -> Self {
        crate::config::FswConfig::table_defaults().calibration
    }
}

impl CalibrationManagerConfig {
    /// Checks the settings against their ranges in the parameter table.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the field.
    pub fn validate(&self) -> Result<(), FswError> {
        use crate::config::Param;
        let thresholds = &self.convergence_sigma;
        Param::ThresholdGyroBias.check(thresholds.gyro_bias_rad_s)?;
        Param::ThresholdAccelBias.check(thresholds.accel_bias_mps2)?;
        Param::ThresholdStarInstallation.check(thresholds.star_installation_rad)?;
        Param::ThresholdGyroScaleFactor.check(thresholds.gyro_scale_factor)?;
        Param::ThresholdAccelScaleFactor.check(thresholds.accel_scale_factor)?;
        Param::StabilityWindow.check(self.stability_window_s)?;
        Param::StabilityFraction.check(self.stability_fraction)?;
        Param::MotionRateThreshold.check(self.motion_rate_threshold_rad_s)?;
        Param::MotionForceThreshold.check(self.motion_force_threshold_mps2)?;
        if !self.motion_observability.is_valid() {
            return Err(FswError::InvalidConfiguration(
                ConfigField::CalibrationObservabilityTable,
            ));
        }
        Ok(())
    }
}

/// One row of the calibration table.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationEntry {
    /// Current estimate per axis (units of the block; the installation error as a small
    /// rotation vector in rad).
    pub value: [f64; 3],
    /// Filter variance per axis (units of the block, squared). Kept as the variance so the
    /// 500 Hz evaluation needs no square root (a software `sqrt` costs dozens of instructions
    /// on the Cortex-M7 target); [`CalibrationEntry::sigma`] gives the 1σ.
    pub variance: [f64; 3],
    /// Navigation time at which the block was declared converged (s), if it has.
    pub converged_at_s: Option<f64>,
    /// The filter may not move this block now (converged and frozen, or outside its phase).
    pub frozen: bool,
}

impl CalibrationEntry {
    /// Filter 1σ per axis (units of the block): the square roots of [`Self::variance`]
    /// (a negative variance, which the filter's floors prevent, reads as 0).
    pub fn sigma(&self) -> [f64; 3] {
        self.variance
            .map(|variance| nav_core::float::sqrt(variance.max(0.0)))
    }
}

/// The calibration table: one entry per block in [`StateBlock::CALIBRATION`] order.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationTable {
    /// Gyro bias (rad/s).
    pub gyro_bias: CalibrationEntry,
    /// Accelerometer bias (m/s²).
    pub accel_bias: CalibrationEntry,
    /// Star-sensor installation error (rad, rotation vector).
    pub star_installation: CalibrationEntry,
    /// Gyro scale factor.
    pub gyro_scale_factor: CalibrationEntry,
    /// Accelerometer scale factor.
    pub accel_scale_factor: CalibrationEntry,
}

impl CalibrationTable {
    /// The entries with their blocks, in [`StateBlock::CALIBRATION`] order.
    pub fn entries(&self) -> [(StateBlock, &CalibrationEntry); CALIBRATION_BLOCK_COUNT] {
        [
            (GYRO_BIAS, &self.gyro_bias),
            (ACCEL_BIAS, &self.accel_bias),
            (STAR_INSTALLATION, &self.star_installation),
            (GYRO_SCALE_FACTOR, &self.gyro_scale_factor),
            (ACCEL_SCALE_FACTOR, &self.accel_scale_factor),
        ]
    }

    fn entries_mut(&mut self) -> [&mut CalibrationEntry; CALIBRATION_BLOCK_COUNT] {
        [
            &mut self.gyro_bias,
            &mut self.accel_bias,
            &mut self.star_installation,
            &mut self.gyro_scale_factor,
            &mut self.accel_scale_factor,
        ]
    }

    /// Number of converged blocks.
    pub fn converged_count(&self) -> u32 {
        let mut count = 0;
        for (_, entry) in self.entries() {
            if entry.converged_at_s.is_some() {
                count += 1;
            }
        }
        count
    }
}

/// Convergence-window bookkeeping of one block.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Window {
    start_s: Option<f64>,
    start_value: [f64; 3],
}

/// The manager.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationManager {
    config: CalibrationManagerConfig,
    phase: ManoeuvrePhase,
    table: CalibrationTable,
    windows: [Window; CALIBRATION_BLOCK_COUNT],
    motion: MotionSignature,
    /// Blocks some motion since start (or the last restart) has made observable.
    revealed: BlockMask,
    /// Blocks frozen by command, whatever the policy says (kept by [`Self::restart`]).
    commanded_frozen: BlockMask,
}

fn max_abs_difference(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a.iter()
        .zip(b.iter())
        .fold(0.0, |worst: f64, (x, y)| worst.max((x - y).abs()))
}

/// The paper's schedule ([`EstimationPolicy::PaperSchedule`]): whether `phase` estimates
/// `block` (`Unknown` estimates all).
fn paper_schedule_estimates(phase: ManoeuvrePhase, block: StateBlock) -> bool {
    match phase {
        ManoeuvrePhase::Unknown => true,
        ManoeuvrePhase::Coast => block == GYRO_BIAS || block == ACCEL_BIAS,
        ManoeuvrePhase::Rotation => block == GYRO_SCALE_FACTOR || block == STAR_INSTALLATION,
        ManoeuvrePhase::Acceleration => block == ACCEL_SCALE_FACTOR || block == STAR_INSTALLATION,
    }
}

impl CalibrationManager {
    /// A manager with an empty table.
    ///
    /// # Errors
    /// As [`CalibrationManagerConfig::validate`].
    pub fn new(config: CalibrationManagerConfig) -> Result<Self, FswError> {
        config.validate()?;
        Ok(Self {
            config,
            phase: ManoeuvrePhase::Unknown,
            table: CalibrationTable::default(),
            windows: [Window::default(); CALIBRATION_BLOCK_COUNT],
            motion: MotionSignature::default(),
            revealed: BlockMask::NONE,
            commanded_frozen: BlockMask::NONE,
        })
    }

    /// Tells the manager the current motion (corrected body rate in rad/s and specific force
    /// in m/s², as used for the covariance propagation); it is classified into a
    /// [`MotionSignature`] for [`EstimationPolicy::MotionObservability`].
    pub fn observe_motion(
        &mut self,
        body_rate_rad_s: &Vector3<f64>,
        specific_force_mps2: &Vector3<f64>,
    ) {
        self.motion = MotionSignature::classify(
            body_rate_rad_s,
            specific_force_mps2,
            self.config.motion_rate_threshold_rad_s,
            self.config.motion_force_threshold_mps2,
        );
        let estimable = self.config.motion_observability.estimable(self.motion);
        for block in StateBlock::CALIBRATION {
            if estimable.contains(block) {
                self.revealed.insert(block);
            }
        }
    }

    /// The current motion's signature (last [`Self::observe_motion`]).
    pub fn motion(&self) -> MotionSignature {
        self.motion
    }

    /// Whether the policy lets the filter move `block` now (convergence freezing aside).
    fn estimates(&self, block: StateBlock) -> bool {
        match self.config.policy {
            EstimationPolicy::AllBlocks => true,
            EstimationPolicy::PaperSchedule => paper_schedule_estimates(self.phase, block),
            EstimationPolicy::MotionObservability => {
                let table = &self.config.motion_observability;
                table.estimable(self.motion).contains(block) || !self.revealed.contains(block)
            }
        }
    }

    /// The current phase.
    pub fn phase(&self) -> ManoeuvrePhase {
        self.phase
    }

    /// Sets the manoeuvre phase (from the flight plan or a ground command).
    pub fn set_phase(&mut self, phase: ManoeuvrePhase) {
        self.phase = phase;
    }

    /// Forgets convergence (every block estimated again but those frozen by command), e.g.
    /// after a filter reset.
    pub fn restart(&mut self) {
        let entries = self.table.entries_mut().into_iter();
        for (entry, block) in entries.zip(StateBlock::CALIBRATION.iter()) {
            entry.converged_at_s = None;
            entry.frozen = self.commanded_frozen.contains(*block);
        }
        self.windows = [Window::default(); CALIBRATION_BLOCK_COUNT];
        self.revealed = BlockMask::NONE;
    }

    /// Freezes `block` by command (`true`), whatever the policy says, at once and until
    /// released; or releases a commanded freeze (`false`): the block's convergence is tested
    /// afresh and the next evaluation decides its state as the policy says. A navigation
    /// block is not in the table and is ignored.
    pub fn set_commanded_frozen(&mut self, block: StateBlock, frozen: bool) {
        let Some(position) = StateBlock::CALIBRATION.iter().position(|b| *b == block) else {
            return;
        };
        if frozen {
            self.commanded_frozen.insert(block);
        } else {
            self.commanded_frozen.remove(block);
            if let Some(window) = self.windows.get_mut(position) {
                *window = Window::default();
            }
        }
        if let Some(entry) = self.table.entries_mut().into_iter().nth(position) {
            if !frozen {
                entry.converged_at_s = None;
            }
            entry.frozen = frozen;
        }
    }

    /// Releases every commanded freeze ([`Self::set_commanded_frozen`]).
    pub fn release_commanded_freezes(&mut self) {
        self.commanded_frozen = BlockMask::NONE;
    }

    /// The blocks frozen by command.
    pub fn commanded_frozen(&self) -> BlockMask {
        self.commanded_frozen
    }

    /// The calibration table.
    pub fn table(&self) -> &CalibrationTable {
        &self.table
    }

    /// The blocks the filter must not move now.
    pub fn frozen_blocks(&self) -> BlockMask {
        let mut mask = BlockMask::NONE;
        for (block, entry) in self.table.entries() {
            if entry.frozen {
                mask.insert(block);
            }
        }
        mask
    }

    /// Updates the table with the filter's current estimates and variances (per block in
    /// [`StateBlock::CALIBRATION`] order, units as in [`CalibrationEntry`]) at navigation time
    /// `now_s`, declares convergence and decides the frozen set. A block's 1σ is below its
    /// threshold `t` when every variance is below `t²`.
    pub fn evaluate(
        &mut self,
        now_s: f64,
        values: &[[f64; 3]; CALIBRATION_BLOCK_COUNT],
        variances: &[[f64; 3]; CALIBRATION_BLOCK_COUNT],
    ) {
        let thresholds = self.config.convergence_sigma.values();
        let config = self.config;
        let mut estimated = [true; CALIBRATION_BLOCK_COUNT];
        for (flag, block) in estimated.iter_mut().zip(StateBlock::CALIBRATION.iter()) {
            // A block frozen by command is not estimated, whatever the policy says.
            *flag = self.estimates(*block) && !self.commanded_frozen.contains(*block);
        }
        let rows = self
            .table
            .entries_mut()
            .into_iter()
            .zip(self.windows.iter_mut())
            .zip(estimated.iter())
            .zip(values.iter().zip(variances.iter()))
            .zip(thresholds.iter());
        for ((((entry, window), estimated), (value, variance)), threshold) in rows {
            entry.value = *value;
            entry.variance = *variance;
            if entry.converged_at_s.is_none() {
                let small = variance.iter().all(|v| *v < threshold * threshold);
                match (small, window.start_s) {
                    (false, _) => window.start_s = None,
                    (true, None) => {
                        window.start_s = Some(now_s);
                        window.start_value = *value;
                    }
                    (true, Some(start_s)) => {
                        if now_s - start_s >= config.stability_window_s {
                            let drift = max_abs_difference(value, &window.start_value);
                            if drift <= config.stability_fraction * threshold {
                                entry.converged_at_s = Some(now_s);
                            } else {
                                window.start_s = Some(now_s);
                                window.start_value = *value;
                            }
                        }
                    }
                }
            }
            let converged_frozen = config.freeze_converged && entry.converged_at_s.is_some();
            entry.frozen = converged_frozen || !*estimated;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion_observability::tests::mask;
    use nav_core::state::{ATTITUDE, POSITION, VELOCITY};

    fn uniform(value: f64) -> [[f64; 3]; CALIBRATION_BLOCK_COUNT] {
        [[value; 3]; CALIBRATION_BLOCK_COUNT]
    }

    #[test]
    fn a_block_converges_after_a_stable_window_and_is_frozen() {
        let config = CalibrationManagerConfig {
            freeze_converged: true,
            ..CalibrationManagerConfig::default()
        };
        let mut manager = CalibrationManager::new(config).unwrap();
        let mut variances = uniform(1.0); // far above every threshold
        variances[3] = [1e-14; 3]; // gyro scale factor: 1σ 1e-7, below 1e-6 / 3
        let values = uniform(3e-5);
        manager.evaluate(0.0, &values, &variances);
        manager.evaluate(5.0, &values, &variances);
        assert_eq!(manager.table().converged_count(), 0);
        manager.evaluate(10.0, &values, &variances);
        assert_eq!(manager.table().gyro_scale_factor.converged_at_s, Some(10.0));
        assert_eq!(manager.table().converged_count(), 1);
        let frozen = manager.frozen_blocks();
        assert!(frozen.contains(GYRO_SCALE_FACTOR));
        assert!(!frozen.contains(ACCEL_SCALE_FACTOR));
        manager.restart();
        assert!(manager.frozen_blocks().is_empty());
    }

    #[test]
    fn a_drifting_estimate_restarts_the_window() {
        let mut manager = CalibrationManager::new(CalibrationManagerConfig::default()).unwrap();
        let variances = uniform(1e-24);
        let mut values = uniform(0.0);
        manager.evaluate(0.0, &values, &variances);
        values[0] = [1e-6; 3]; // gyro bias moved by 2× its threshold (5e-7)
        manager.evaluate(10.0, &values, &variances);
        assert_eq!(manager.table().gyro_bias.converged_at_s, None);
        assert_eq!(manager.table().accel_bias.converged_at_s, Some(10.0));
        manager.evaluate(20.0, &values, &variances);
        assert_eq!(manager.table().gyro_bias.converged_at_s, Some(20.0));
        // Not frozen: freezing is off by default.
        assert!(manager.frozen_blocks().is_empty());
    }

    #[test]
    fn the_paper_schedule_freezes_blocks_outside_their_phase() {
        let config = CalibrationManagerConfig {
            policy: EstimationPolicy::PaperSchedule,
            ..CalibrationManagerConfig::default()
        };
        let mut manager = CalibrationManager::new(config).unwrap();
        let expected = [
            (ManoeuvrePhase::Unknown, 0b0000_0000),
            // bits: 3 gyro bias, 4 accel bias, 5 installation, 6 gyro SF, 7 accel SF
            (ManoeuvrePhase::Coast, 0b1110_0000),
            (ManoeuvrePhase::Rotation, 0b1001_1000),
            (ManoeuvrePhase::Acceleration, 0b0101_1000),
        ];
        for (phase, bits) in expected {
            manager.set_phase(phase);
            manager.evaluate(0.0, &uniform(0.0), &uniform(1.0));
            assert_eq!(manager.frozen_blocks().bits(), bits, "{phase:?}");
        }
    }

    /// Bits of [`BlockMask`] for the calibration blocks: 3 gyro bias, 4 accel bias,
    /// 5 installation, 6 gyro scale factor, 7 accel scale factor.

    #[test]
    fn the_motion_observability_policy_freezes_what_the_motion_cannot_see() {
        let config = CalibrationManagerConfig {
            policy: EstimationPolicy::MotionObservability,
            ..CalibrationManagerConfig::default()
        };
        let mut manager = CalibrationManager::new(config).unwrap();
        let degrees = core::f64::consts::PI / 180.0;
        let coast = (
            Vector3::new(1e-6, -2e-6, 1e-6),
            Vector3::new(1e-3, 0.0, -1e-3),
        );
        let cases = [
            // (rate rad/s, specific force m/s², expected signature, frozen blocks)
            // First coast: nothing revealed yet, so nothing to protect.
            (coast.0, coast.1, 0, 0),
            // Rotation about z reveals installation and gyro scale factor.
            (
                Vector3::new(0.0, 0.0, -100.0 * degrees),
                Vector3::zeros(),
                4,
                0,
            ),
            // Thrust along y (the 0.4 °/s rate is below the 0.5 °/s threshold) reveals the
            // accelerometer scale factor and cannot see the gyro scale factor: protected.
            (
                Vector3::new(0.4 * degrees, 0.0, 0.0),
                Vector3::new(0.0, 20.0, 0.0),
                16,
                mask(&[GYRO_SCALE_FACTOR]),
            ),
            // Coast again: every revealed block it cannot see is protected.
            (
                coast.0,
                coast.1,
                0,
                mask(&[STAR_INSTALLATION, GYRO_SCALE_FACTOR, ACCEL_SCALE_FACTOR]),
            ),
        ];
        for (rate, force, signature, frozen) in cases {
            manager.observe_motion(&rate, &force);
            assert_eq!(manager.motion().bits(), signature);
            // The manoeuvre phase is ignored by this policy.
            manager.set_phase(ManoeuvrePhase::Coast);
            manager.evaluate(0.0, &uniform(0.0), &uniform(1.0));
            assert_eq!(
                manager.frozen_blocks().bits(),
                frozen,
                "signature {signature}"
            );
        }
        // A restart forgets what was revealed.
        manager.restart();
        manager.evaluate(0.0, &uniform(0.0), &uniform(1.0));
        assert!(manager.frozen_blocks().is_empty());
        // NaN classifies as not moving (the filter refuses such samples anyway).
        manager.observe_motion(&Vector3::repeat(f64::NAN), &Vector3::repeat(f64::NAN));
        assert_eq!(manager.motion().bits(), 0);
    }

    #[test]
    fn an_observability_table_naming_navigation_blocks_is_refused() {
        let mut entries = [BlockMask::NONE; MotionSignature::COUNT];
        if let Some(entry) = entries.get_mut(5) {
            entry.insert(VELOCITY);
        }
        let config = CalibrationManagerConfig {
            motion_observability: MotionObservabilityTable::from_entries(entries),
            ..CalibrationManagerConfig::default()
        };
        assert_eq!(
            CalibrationManager::new(config),
            Err(FswError::InvalidConfiguration(
                ConfigField::CalibrationObservabilityTable
            ))
        );
    }

    #[test]
    fn motion_thresholds_are_validated() {
        use crate::config::Param;
        let (rate, force) = (Param::MotionRateThreshold, Param::MotionForceThreshold);
        for (rate_rad_s, force_mps2, param) in [
            (0.0, 0.5, rate),
            (f64::NAN, 0.5, rate),
            (0.01, -1.0, force),
            (0.01, f64::INFINITY, force),
        ] {
            let config = CalibrationManagerConfig {
                motion_rate_threshold_rad_s: rate_rad_s,
                motion_force_threshold_mps2: force_mps2,
                ..CalibrationManagerConfig::default()
            };
            assert_eq!(
                CalibrationManager::new(config),
                Err(FswError::InvalidConfiguration(ConfigField::Parameter(
                    param
                )))
            );
        }
    }

    /// Mutation-testing boundaries of the manager: strict thresholds, each validation edge,
    /// a table naming any one navigation block, the window measured from its start.
    #[test]
    fn thresholds_are_strict_and_every_invalid_setting_is_refused() {
        let degrees = core::f64::consts::PI / 180.0;
        let at_threshold = MotionSignature::classify(
            &Vector3::new(0.5 * degrees, 0.0, 0.0),
            &Vector3::new(0.0, 0.5, 0.0),
            0.5 * degrees,
            0.5,
        );
        assert_eq!(at_threshold.bits(), 0);

        let refused = |change: fn(&mut CalibrationManagerConfig)| {
            let mut config = CalibrationManagerConfig::default();
            change(&mut config);
            CalibrationManager::new(config).err()
        };
        use crate::config::Param;
        let named = |param| {
            Some(FswError::InvalidConfiguration(ConfigField::Parameter(
                param,
            )))
        };
        assert_eq!(
            refused(|c| c.convergence_sigma.gyro_bias_rad_s = 0.0),
            named(Param::ThresholdGyroBias)
        );
        assert_eq!(
            refused(|c| c.convergence_sigma.accel_scale_factor = f64::NAN),
            named(Param::ThresholdAccelScaleFactor)
        );
        assert_eq!(
            refused(|c| c.convergence_sigma.star_installation_rad = -1.0),
            named(Param::ThresholdStarInstallation)
        );
        let stability = named(Param::StabilityFraction);
        assert_eq!(refused(|c| c.stability_fraction = 0.0), stability);
        assert_eq!(refused(|c| c.stability_fraction = f64::INFINITY), stability);
        for block in [ATTITUDE, POSITION, VELOCITY] {
            let mut entries = [BlockMask::NONE; MotionSignature::COUNT];
            if let Some(entry) = entries.get_mut(9) {
                entry.insert(block);
            }
            let config = CalibrationManagerConfig {
                motion_observability: MotionObservabilityTable::from_entries(entries),
                ..CalibrationManagerConfig::default()
            };
            assert!(CalibrationManager::new(config).is_err(), "{}", block.name());
        }

        let mut manager = CalibrationManager::new(CalibrationManagerConfig::default()).unwrap();
        manager.set_phase(ManoeuvrePhase::Rotation);
        assert_eq!(manager.phase(), ManoeuvrePhase::Rotation);
        // A 1σ exactly at the threshold is not below it.
        let thresholds = CalibrationManagerConfig::default()
            .convergence_sigma
            .values();
        let at_variance = thresholds[0] * thresholds[0];
        let at = [[at_variance; 3], [1.0; 3], [1.0; 3], [1.0; 3], [1.0; 3]];
        manager.evaluate(0.0, &uniform(0.0), &at);
        manager.evaluate(20.0, &uniform(0.0), &at);
        assert_eq!(manager.table().gyro_bias.converged_at_s, None);
        // The window runs from its start: started at 5 s, not converged at 10 s (5 s < 10 s).
        let mut manager = CalibrationManager::new(CalibrationManagerConfig::default()).unwrap();
        manager.evaluate(5.0, &uniform(0.0), &uniform(1e-24));
        manager.evaluate(10.0, &uniform(0.0), &uniform(1e-24));
        assert_eq!(manager.table().converged_count(), 0);
        manager.evaluate(15.0, &uniform(0.0), &uniform(1e-24));
        assert_eq!(manager.table().converged_count(), 5);
    }
}
