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

use nav_core::state::{
    BlockMask, StateBlock, ACCEL_BIAS, ACCEL_SCALE_FACTOR, CALIBRATION_BLOCKS, GYRO_BIAS,
    GYRO_SCALE_FACTOR, STAR_INSTALLATION,
};

use crate::error::{ConfigField, FswError};

/// Number of calibration blocks (biases, installation, scale factors).
pub const CALIBRATION_BLOCK_COUNT: usize = 5;

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

    /// The values in [`CALIBRATION_BLOCKS`] order.
    pub fn values(&self) -> [f64; CALIBRATION_BLOCK_COUNT] {
        [
            self.gyro_bias_rad_s,
            self.accel_bias_mps2,
            self.star_installation_rad,
            self.gyro_scale_factor,
            self.accel_scale_factor,
        ]
    }

    /// Every threshold finite and positive.
    fn is_valid(&self) -> bool {
        self.values().iter().all(|v| v.is_finite() && *v > 0.0)
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
}

impl Default for CalibrationManagerConfig {
    fn default() -> Self {
        let paper = CalibrationThresholds::PAPER_ACCURACY;
        Self {
            convergence_sigma: CalibrationThresholds {
                gyro_bias_rad_s: paper.gyro_bias_rad_s / 3.0,
                accel_bias_mps2: paper.accel_bias_mps2 / 3.0,
                star_installation_rad: paper.star_installation_rad / 3.0,
                gyro_scale_factor: paper.gyro_scale_factor / 3.0,
                accel_scale_factor: paper.accel_scale_factor / 3.0,
            },
            stability_window_s: 10.0,
            stability_fraction: 1.0,
            freeze_converged: false,
            policy: EstimationPolicy::AllBlocks,
        }
    }
}

impl CalibrationManagerConfig {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`FswError::InvalidConfiguration`] naming the field.
    pub fn validate(&self) -> Result<(), FswError> {
        if !self.convergence_sigma.is_valid() {
            return Err(FswError::InvalidConfiguration(
                ConfigField::CalibrationThreshold,
            ));
        }
        if !(self.stability_window_s.is_finite() && self.stability_window_s >= 0.0) {
            return Err(FswError::InvalidConfiguration(
                ConfigField::CalibrationWindow,
            ));
        }
        if !(self.stability_fraction.is_finite() && self.stability_fraction > 0.0) {
            return Err(FswError::InvalidConfiguration(
                ConfigField::CalibrationStability,
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
    /// Filter 1σ per axis (same units).
    pub sigma: [f64; 3],
    /// Navigation time at which the block was declared converged (s), if it has.
    pub converged_at_s: Option<f64>,
    /// The filter may not move this block now (converged and frozen, or outside its phase).
    pub frozen: bool,
}

/// The calibration table: one entry per block in [`CALIBRATION_BLOCKS`] order.
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
    /// The entries with their blocks, in [`CALIBRATION_BLOCKS`] order.
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
}

fn max_abs_difference(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a.iter()
        .zip(b.iter())
        .fold(0.0, |worst: f64, (x, y)| worst.max((x - y).abs()))
}

fn phase_estimates(policy: EstimationPolicy, phase: ManoeuvrePhase, block: StateBlock) -> bool {
    match (policy, phase) {
        (EstimationPolicy::AllBlocks, _) | (_, ManoeuvrePhase::Unknown) => true,
        (EstimationPolicy::PaperSchedule, ManoeuvrePhase::Coast) => {
            block == GYRO_BIAS || block == ACCEL_BIAS
        }
        (EstimationPolicy::PaperSchedule, ManoeuvrePhase::Rotation) => {
            block == GYRO_SCALE_FACTOR || block == STAR_INSTALLATION
        }
        (EstimationPolicy::PaperSchedule, ManoeuvrePhase::Acceleration) => {
            block == ACCEL_SCALE_FACTOR || block == STAR_INSTALLATION
        }
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
        })
    }

    /// The current phase.
    pub fn phase(&self) -> ManoeuvrePhase {
        self.phase
    }

    /// Sets the manoeuvre phase (from the flight plan or a ground command).
    pub fn set_phase(&mut self, phase: ManoeuvrePhase) {
        self.phase = phase;
    }

    /// Forgets convergence (all blocks estimated again), e.g. after a filter reset.
    pub fn restart(&mut self) {
        for entry in self.table.entries_mut() {
            entry.converged_at_s = None;
            entry.frozen = false;
        }
        self.windows = [Window::default(); CALIBRATION_BLOCK_COUNT];
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

    /// Updates the table with the filter's current estimates and 1σ (per block in
    /// [`CALIBRATION_BLOCKS`] order, units as in [`CalibrationEntry`]) at navigation time
    /// `now_s`, declares convergence and decides the frozen set.
    pub fn evaluate(
        &mut self,
        now_s: f64,
        values: &[[f64; 3]; CALIBRATION_BLOCK_COUNT],
        sigmas: &[[f64; 3]; CALIBRATION_BLOCK_COUNT],
    ) {
        let thresholds = self.config.convergence_sigma.values();
        let config = self.config;
        let phase = self.phase;
        let rows = self
            .table
            .entries_mut()
            .into_iter()
            .zip(self.windows.iter_mut())
            .zip(CALIBRATION_BLOCKS.iter())
            .zip(values.iter().zip(sigmas.iter()))
            .zip(thresholds.iter());
        for ((((entry, window), block), (value, sigma)), threshold) in rows {
            entry.value = *value;
            entry.sigma = *sigma;
            if entry.converged_at_s.is_none() {
                let small = sigma.iter().all(|s| *s < *threshold);
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
            entry.frozen = converged_frozen || !phase_estimates(config.policy, phase, *block);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut sigmas = uniform(1.0); // far above every threshold
        sigmas[3] = [1e-7; 3]; // gyro scale factor: below 1e-6 / 3
        let values = uniform(3e-5);
        manager.evaluate(0.0, &values, &sigmas);
        manager.evaluate(5.0, &values, &sigmas);
        assert_eq!(manager.table().converged_count(), 0);
        manager.evaluate(10.0, &values, &sigmas);
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
        let sigmas = uniform(1e-12);
        let mut values = uniform(0.0);
        manager.evaluate(0.0, &values, &sigmas);
        values[0] = [1e-6; 3]; // gyro bias moved by 2× its threshold (5e-7)
        manager.evaluate(10.0, &values, &sigmas);
        assert_eq!(manager.table().gyro_bias.converged_at_s, None);
        assert_eq!(manager.table().accel_bias.converged_at_s, Some(10.0));
        manager.evaluate(20.0, &values, &sigmas);
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
}
